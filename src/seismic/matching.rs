//! Spectral matching in the frequency domain: the record's Fourier amplitudes are scaled by
//! `target(T)/Sa(T)` at `T = 1/f`, over a few iterations.
//!
//! Each iteration: (1) the 5%-damped (or any ζ) response spectrum `Sa(T_k)` over the matching
//! periods; (2) the record, zero-padded to a power of two `N ≥ 2n`, is transformed
//! ([`super::fft`]); (3) every bin of frequency `f` with `1/f` inside `[t_min, t_max]` is multiplied
//! (with its mirror bin, keeping the signal real) by `r(1/f)`, the ratio `target/Sa` interpolated
//! linearly between the matching periods; bins outside are left alone; (4) the inverse
//! transform, truncated to the record's length, is the new record. Phases are kept, so the
//! time envelope survives approximately. Matching is approximate (an oscillator's peak depends on
//! all frequencies and on the phases): the misfit `max_k |Sa_k/target_k − 1|` is reported
//! before and after each iteration and the best record seen is returned.
use super::error::SeismicError;
use super::fft::{fft_in_place, Complex};
use super::record::Record;
use super::spectrum::{interpolate, response_spectrum};

/// Settings of spectral matching.
#[derive(Clone, Debug, PartialEq)]
pub struct MatchSettings {
    /// Damping ratio of the spectra (0.05).
    pub damping: f64,
    /// Matching periods [s], increasing, all > 0.
    pub periods: Vec<f64>,
    /// Number of iterations.
    pub iterations: usize,
}

/// The misfit history of a matching.
#[derive(Clone, Debug, PartialEq)]
pub struct MatchReport {
    /// `max_k |Sa_k/target_k − 1|` of the input (index 0) and after each iteration.
    pub max_misfit: Vec<f64>,
    /// Mean of `|Sa_k/target_k − 1|`, same indexing.
    pub mean_misfit: Vec<f64>,
    /// Index of the returned record in these lists.
    pub best: usize,
}

fn misfit(sa: &[f64], target: &[f64]) -> (f64, f64) {
    let e: Vec<f64> = sa.iter().zip(target).map(|(s, t)| (s / t - 1.0).abs()).collect();
    (e.iter().fold(0.0, |m: f64, x| m.max(*x)), e.iter().sum::<f64>() / e.len() as f64)
}

/// Matches `r` to the spectrum `target(T)` [m/s²] over `settings.periods`.
pub fn match_spectrum(
    r: &Record,
    target: &dyn Fn(f64) -> f64,
    settings: &MatchSettings,
) -> Result<(Record, MatchReport), SeismicError> {
    let p = &settings.periods;
    let what = || format!("spectral matching of '{}'", r.name);
    if p.is_empty() || p.iter().any(|&t| t.is_nan() || t <= 0.0) || p.windows(2).any(|w| w[1] <= w[0]) {
        return Err(SeismicError::invalid(what(), "matching periods must be > 0 and increasing"));
    }
    let tgt: Vec<f64> = p.iter().map(|&t| target(t)).collect();
    for (t, &x) in p.iter().zip(&tgt) {
        crate::bounds::positive(x)
            .map_err(|b| SeismicError::out_of_bounds(format!("{}: the target spectrum at T = {t} s", what()), b))?;
    }
    let n = r.len();
    let nfft = (2 * n).next_power_of_two();
    let df = 1.0 / (nfft as f64 * r.dt);
    let (t_min, t_max) = (p[0], p[p.len() - 1]);
    let mut current = r.clone();
    let mut best = (r.clone(), f64::INFINITY);
    let mut report = MatchReport { max_misfit: Vec::new(), mean_misfit: Vec::new(), best: 0 };
    for it in 0..=settings.iterations {
        let sa = response_spectrum(&current, p, settings.damping)?.sa;
        let (mx, mean) = misfit(&sa, &tgt);
        report.max_misfit.push(mx);
        report.mean_misfit.push(mean);
        if mean < best.1 {
            best = (current.clone(), mean);
            report.best = it;
        }
        if it == settings.iterations {
            break;
        }
        let ratio: Vec<f64> = tgt.iter().zip(&sa).map(|(t, s)| if *s > 0.0 { t / s } else { 1.0 }).collect();
        let mut x = vec![Complex::default(); nfft];
        for (c, a) in x.iter_mut().zip(&current.accel) {
            c.re = *a;
        }
        fft_in_place(&mut x, false)?;
        for k in 1..=nfft / 2 {
            let t = 1.0 / (k as f64 * df);
            if t < t_min || t > t_max {
                continue;
            }
            let g = interpolate(p, &ratio, t);
            x[k].re *= g;
            x[k].im *= g;
            if k != nfft / 2 {
                x[nfft - k].re *= g;
                x[nfft - k].im *= g;
            }
        }
        fft_in_place(&mut x, true)?;
        current.accel = x[..n].iter().map(|c| c.re).collect();
    }
    let mut out = best.0;
    out.units_note =
        format!("{}; spectrally matched ({} iterations, best {})", r.units_note, settings.iterations, report.best);
    Ok((out, report))
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::seismic::baseline::Baseline;
    use crate::seismic::ec8::{Ec8Spectrum, Ec8Type, GroundType};
    use crate::seismic::synthetic::{generate, Envelope, GroundFilter, SyntheticSpec};
    use std::f64::consts::PI;

    #[test]
    fn matching_brings_a_record_close_to_ec8() {
        let spec = SyntheticSpec {
            name: "m".into(),
            duration: 20.0,
            dt: 0.01,
            filter: GroundFilter::CloughPenzien {
                omega_g: 2.0 * PI * 3.0,
                zeta_g: 0.5,
                omega_f: 2.0 * PI * 0.3,
                zeta_f: 0.7,
            },
            envelope: Envelope::Jennings { t1: 2.0, t2: 10.0, decay: 0.5 },
            high_pass_hz: None,
            baseline: Baseline::None,
            target_pga: 1.0,
            seed: 11,
        };
        let r = generate(&spec).unwrap();
        let ec8 = Ec8Spectrum::new(Ec8Type::Type1, GroundType::B, 1.6, 5.0).unwrap();
        let periods: Vec<f64> = (0..30).map(|k| 0.05 * (2.0f64 / 0.05).powf(k as f64 / 29.0)).collect();
        let settings = MatchSettings { damping: 0.05, periods, iterations: 6 };
        let (_m, rep) = match_spectrum(&r, &|t| ec8.se(t), &settings).unwrap();
        // This seeded case: mean misfit 53% → 2.3%, worst period 72% → 8% after 6 iterations.
        // Tolerances (mean < 10% and a third of the start, worst < 30%) leave room for other
        // platforms' round-off; frequency-domain matching is approximate.
        let (m0, mb) = (rep.mean_misfit[0], rep.mean_misfit[rep.best]);
        assert!(mb < 0.10 && mb < m0 / 3.0, "{:?}", rep);
        assert!(rep.max_misfit[rep.best] < 0.30, "{:?}", rep);
    }
}
