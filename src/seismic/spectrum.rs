//! Response spectra: peak relative displacement `Sd(T, ζ)` of linear oscillators over a list of
//! periods, and the pseudo-spectra `Sv = ω Sd`, `Sa = ω² Sd` (ω = 2π/T).
//!
//! Each oscillator is integrated exactly ([`super::sdof`]) from rest over the record and then
//! over one more period of free vibration. The response is sampled at least 40 times per period
//! (steps split into equal sub-steps, which is exact for the piecewise-linear excitation), so the
//! peak between samples is missed by at most `1 − cos(π/40) ≈ 0.3%`. By convention
//! `Sa(T = 0) = PGA`, `Sd(0) = Sv(0) = 0`.
use super::error::SeismicError;
use super::intensity::pga;
use super::record::Record;
use super::sdof::peak_displacement;
use std::f64::consts::PI;

/// Sd, Sv, Sa of one record at one damping ratio.
#[derive(Clone, Debug, PartialEq)]
pub struct ResponseSpectrum {
    /// Damping ratio ζ (0.05 for 5%).
    pub damping: f64,
    /// Periods [s], as given (0 allowed).
    pub periods: Vec<f64>,
    /// Spectral displacement [m].
    pub sd: Vec<f64>,
    /// Pseudo-velocity [m/s].
    pub sv: Vec<f64>,
    /// Pseudo-acceleration [m/s²].
    pub sa: Vec<f64>,
}

impl ResponseSpectrum {
    /// The (T, Sa) points, for charts.
    pub fn sa_curve(&self) -> Vec<(f64, f64)> {
        self.periods.iter().copied().zip(self.sa.iter().copied()).collect()
    }

    /// Sa at period `t` by linear interpolation between the computed periods (clamped at the ends).
    pub fn sa_at(&self, t: f64) -> f64 {
        interpolate(&self.periods, &self.sa, t)
    }
}

/// Linear interpolation in a table with increasing `x`, clamped outside.
pub(crate) fn interpolate(x: &[f64], y: &[f64], t: f64) -> f64 {
    match x.iter().position(|&xi| xi >= t) {
        None => y.last().copied().unwrap_or(0.0),
        Some(0) => y.first().copied().unwrap_or(0.0),
        Some(i) => y[i - 1] + (y[i] - y[i - 1]) * (t - x[i - 1]) / (x[i] - x[i - 1]),
    }
}

/// `n` periods spaced evenly in log between `t_min` and `t_max` (both > 0), preceded by 0.
pub fn log_periods(t_min: f64, t_max: f64, n: usize) -> Vec<f64> {
    let mut p = vec![0.0];
    let n = n.max(2);
    for k in 0..n {
        p.push(t_min * (t_max / t_min).powf(k as f64 / (n - 1) as f64));
    }
    p
}

/// The response spectrum of `r` at damping ratio `damping` (≥ 0, e.g. 0.05) over `periods` [s] (≥ 0).
pub fn response_spectrum(r: &Record, periods: &[f64], damping: f64) -> Result<ResponseSpectrum, SeismicError> {
    let mut out =
        ResponseSpectrum { damping, periods: periods.to_vec(), sd: Vec::new(), sv: Vec::new(), sa: Vec::new() };
    for &t in periods {
        crate::bounds::non_negative(t).map_err(|b| {
            SeismicError::out_of_bounds(format!("period [s] of the response spectrum of '{}'", r.name), b)
        })?;
        if t == 0.0 {
            out.sd.push(0.0);
            out.sv.push(0.0);
            out.sa.push(pga(r));
            continue;
        }
        let w = 2.0 * PI / t;
        let sub = (40.0 * r.dt / t).ceil().max(1.0) as usize;
        let sd = peak_displacement(&r.accel, r.dt, w, damping, sub, 1.0)?;
        out.sd.push(sd);
        out.sv.push(w * sd);
        out.sa.push(w * w * sd);
    }
    Ok(out)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn short_period_sa_tends_to_pga() {
        // A smooth 1 Hz pulse: a stiff oscillator (T = 0.01 s) follows the ground, Sa → PGA
        // (ω² u ≈ −a_g, error ~ (T/T_pulse)² ~ 1e-4: tolerance 1%); T = 0 gives PGA exactly.
        let dt = 0.005;
        let acc: Vec<f64> = (0..=400)
            .map(|i| {
                let t = i as f64 * dt;
                if t <= 1.0 {
                    (PI * t).sin().powi(2) * (2.0 * PI * t).sin()
                } else {
                    0.0
                }
            })
            .collect();
        let r = Record::new("p", dt, acc, "", "").unwrap();
        let s = response_spectrum(&r, &[0.0, 0.01], 0.05).unwrap();
        assert_eq!(s.sa[0], pga(&r));
        assert!((s.sa[1] - s.sa[0]).abs() < 0.01 * s.sa[0], "{:?}", s.sa);
        assert!(response_spectrum(&r, &[-1.0], 0.05).is_err());
        let lp = log_periods(0.02, 4.0, 5);
        assert_eq!(lp.len(), 6);
        assert!((lp[5] - 4.0).abs() < 1e-12 && (lp[1] - 0.02).abs() < 1e-15);
    }
}
