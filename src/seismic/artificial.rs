//! Artificial accelerograms matched to a Eurocode 8 elastic spectrum (EN 1998-1 §3.2.3.1.2),
//! each reproducible from its own seed.
//!
//! Record `k` (0-based) of a set with base seed `s` is built from seed `s + k` (wrapping) alone,
//! so any record can be regenerated without the others, bit for bit:
//!
//! 1. **Stationary noise** ([`super::synthetic`]): Clough–Penzien filtered white noise. The site
//!    filter sits at the middle of the spectrum's plateau in log T, `T_g = √(T_B T_C)`
//!    (`ω_g = 2π/T_g`), with `ζ_g = 0.6`; the high-pass stage at `ω_f = 0.1 ω_g`, `ζ_f = ζ_g`
//!    (the proportions of Der Kiureghian & Neuenhofer 1992). Matching reshapes the spectrum
//!    anyway: the filter only gives it a plausible start.
//! 2. **Envelope**: Jennings, Housner & Tsai (1968), `(t/t_r)²` over the rise `t_r`, 1 over the
//!    stationary part `t_s`, then `exp(−c (t − t_r − t_s))`. EC8 §3.2.3.1.2(3): without
//!    site-specific data the stationary part is at least 10 s.
//! 3. A zero-phase high-pass ([`super::filter`]) and a displacement-fit baseline correction of
//!    order 1 ([`super::baseline`]); the record is scaled to PGA = a_g S.
//! 4. **Spectral matching** ([`super::matching`]) to `Se(T)` over the matching periods.
//! 5. A second displacement-fit baseline correction (order 1): matching amplifies some long
//!    periods and leaves a drift in the displacement; the correction's change to the spectrum
//!    is reported by the set's check, which runs on the records as written.
//!
//! The record's PGA is whatever matching gives: rule (4)b of the check (mean PGA ≥ a_g S) is
//! then verified, not imposed.
use super::baseline::{correct, Baseline};
use super::ec8::Ec8Spectrum;
use super::error::SeismicError;
use super::matching::{match_spectrum, MatchReport, MatchSettings};
use super::record::Record;
use super::synthetic::{generate, Envelope, GroundFilter, SyntheticSpec};
use std::f64::consts::PI;

/// Site filter damping ζ_g (and ζ_f).
pub const FILTER_DAMPING: f64 = 0.6;
/// High-pass stage frequency over the site frequency, ω_f/ω_g.
pub const HIGH_PASS_RATIO: f64 = 0.1;

/// Everything that defines a set of artificial records but the target.
#[derive(Clone, Debug, PartialEq)]
pub struct ArtificialSpec {
    /// Name prefix: record `k` is called `"{prefix} {k + 1}"`.
    pub prefix: String,
    /// Base seed: record `k` uses `seed + k`.
    pub seed: u64,
    /// Duration [s].
    pub duration: f64,
    /// Time step [s].
    pub dt: f64,
    /// Rise of the envelope [s].
    pub rise: f64,
    /// Stationary part of the envelope [s].
    pub stationary: f64,
    /// Decay rate after the stationary part [1/s].
    pub decay: f64,
    /// Zero-phase high-pass corner [Hz] applied before matching (`None`: none).
    pub high_pass_hz: Option<f64>,
    /// Matching periods, damping (0.05) and iterations.
    pub matching: MatchSettings,
}

impl ArtificialSpec {
    /// The seed of record `index`.
    pub fn seed_of(&self, index: usize) -> u64 {
        self.seed.wrapping_add(index as u64)
    }

    /// Checks the parameters: times and the decay rate > 0, the envelope's rise and stationary part
    /// inside the duration.
    pub fn validate(&self) -> Result<(), SeismicError> {
        let what = || format!("artificial records '{}'", self.prefix);
        let positive = [
            ("duration [s]", self.duration),
            ("dt [s]", self.dt),
            ("rise [s]", self.rise),
            ("stationary [s]", self.stationary),
            ("decay [1/s]", self.decay),
        ];
        for (k, v) in positive {
            crate::bounds::positive(v).map_err(|b| SeismicError::out_of_bounds(format!("{}: {k}", what()), b))?;
        }
        if self.rise + self.stationary > self.duration {
            return Err(SeismicError::invalid(
                what(),
                format!(
                    "rise {} s + stationary part {} s exceed the duration {} s",
                    self.rise, self.stationary, self.duration
                ),
            ));
        }
        Ok(())
    }

    /// The synthetic-noise spec of record `index` for `target` (steps 1–3 of the module docs).
    pub fn synthetic(&self, target: &Ec8Spectrum, index: usize) -> SyntheticSpec {
        let omega_g = 2.0 * PI / (target.tb * target.tc).sqrt();
        SyntheticSpec {
            name: format!("{} {}", self.prefix, index + 1),
            duration: self.duration,
            dt: self.dt,
            filter: GroundFilter::CloughPenzien {
                omega_g,
                zeta_g: FILTER_DAMPING,
                omega_f: HIGH_PASS_RATIO * omega_g,
                zeta_f: FILTER_DAMPING,
            },
            envelope: Envelope::Jennings { t1: self.rise, t2: self.rise + self.stationary, decay: self.decay },
            high_pass_hz: self.high_pass_hz,
            baseline: Baseline::Displacement { order: 1 },
            target_pga: target.ag * target.s,
            seed: self.seed_of(index),
        }
    }
}

/// Record `index` of the set `spec` matched to `target`, with its matching history.
pub fn artificial_record(
    spec: &ArtificialSpec,
    target: &Ec8Spectrum,
    index: usize,
) -> Result<(Record, MatchReport), SeismicError> {
    spec.validate()?;
    target.validate()?;
    crate::bounds::positive(target.ag)
        .map_err(|b| SeismicError::out_of_bounds("artificial records: the target's a_g [m/s²]", b))?;
    let noise = generate(&spec.synthetic(target, index))?;
    let (matched, report) = match_spectrum(&noise, &|t| target.se(t), &spec.matching)?;
    let mut r = correct(&matched, Baseline::Displacement { order: 1 })?;
    r.units_note = format!("{}; baseline-corrected (displacement fit, order 1)", matched.units_note);
    r.source = format!(
        "ARTIFICIAL, matched to EC8 (a_g = {} m/s², S = {}, T_B = {} s, T_C = {} s, T_D = {} s, η = {}): {}",
        target.ag, target.s, target.tb, target.tc, target.td, target.eta, noise.source
    );
    Ok((r, report))
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::seismic::ec8::{Ec8Type, GroundType};
    use crate::seismic::spectrum::log_periods;

    fn spec() -> ArtificialSpec {
        ArtificialSpec {
            prefix: "a".into(),
            seed: 7,
            duration: 12.0,
            dt: 0.01,
            rise: 1.0,
            stationary: 8.0,
            decay: 1.0,
            high_pass_hz: Some(0.1),
            matching: MatchSettings { damping: 0.05, periods: log_periods(0.05, 2.0, 30)[1..].to_vec(), iterations: 3 },
        }
    }

    #[test]
    fn a_record_comes_from_its_own_seed() {
        let ec8 = Ec8Spectrum::new(Ec8Type::Type1, GroundType::A, 1.6, 5.0).unwrap();
        let s = spec();
        // Record 2 of base seed 7 is record 0 of base seed 9: bit-identical (the same arithmetic).
        let (a, _) = artificial_record(&s, &ec8, 2).unwrap();
        let (b, _) = artificial_record(&ArtificialSpec { seed: 9, ..s.clone() }, &ec8, 0).unwrap();
        assert_eq!(a.accel, b.accel);
        assert!(a.source.contains("seed 9"), "{}", a.source);
        assert_eq!(a.len(), 1201);
        // The site filter at √(T_B T_C) = √(0.15 · 0.4) s (Table 3.2, type 1, ground A).
        let GroundFilter::CloughPenzien { omega_g, .. } = s.synthetic(&ec8, 0).filter else { panic!() };
        assert!((omega_g - 2.0 * PI / 0.06f64.sqrt()).abs() < 1e-12);
    }

    #[test]
    fn bad_parameters_are_refused() {
        let ec8 = Ec8Spectrum::new(Ec8Type::Type1, GroundType::A, 1.6, 5.0).unwrap();
        let e = artificial_record(&ArtificialSpec { stationary: 12.0, ..spec() }, &ec8, 0).unwrap_err();
        assert!(e.to_string().contains("exceed the duration"), "{e}");
        assert!(artificial_record(&ArtificialSpec { dt: 0.0, ..spec() }, &ec8, 0).is_err());
        let zero = Ec8Spectrum { ag: 0.0, ..ec8 };
        assert!(artificial_record(&spec(), &zero, 0).is_err());
    }
}
