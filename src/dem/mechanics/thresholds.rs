//! Beam failure thresholds `(ε_cr, θ_cr)`: deterministic, or Weibull-distributed per beam.
//!
//! Masonry uses deterministic thresholds (its heterogeneity is geometric, paper §2.1); concrete-like
//! samples may draw each beam's thresholds from a two-parameter Weibull law
//!
//! ```text
//!   F(x) = 1 − exp(−(x/s)^m),      x = s (−ln U)^{1/m},  U ~ uniform(0, 1)
//! ```
//!
//! with shape `m` and scale `s` = the deterministic value. Note that `s` is the 63.2 % quantile,
//! not the mean: the mean is `s Γ(1 + 1/m)` (e.g. 0.886 s for m = 2, 0.952 s for m = 10), the
//! median `s (ln 2)^{1/m}`. The draw is a pure function of `(seed, beam id, which threshold)`:
//! `U` comes from a SplitMix64 hash of those three numbers (top 53 bits, centred in its bin so
//! `U ∈ (0, 1)` strictly). So it does not depend on the order beams are visited, nor on the
//! number of MPI ranks, and the two thresholds of a beam are independent.

use super::error::{positive, MechanicsError};

/// The failure thresholds of one beam.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Thresholds {
    /// Critical axial strain `ε_cr` (> 0).
    pub eps_cr: f64,
    /// Critical relative rotation `θ_cr` (rad, > 0).
    pub theta_cr: f64,
}

impl Thresholds {
    /// Checks that both thresholds are finite and > 0.
    pub fn validate(&self) -> Result<(), MechanicsError> {
        positive("eps_cr", self.eps_cr)?;
        positive("theta_cr", self.theta_cr)?;
        Ok(())
    }

    /// This beam's Weibull draw, with `self` as the scales and shape `m` (both thresholds drawn
    /// independently). Errors: `m` or a scale not finite and > 0.
    pub fn weibull(&self, m: f64, seed: u64, beam: u64) -> Result<Thresholds, MechanicsError> {
        Ok(Thresholds {
            eps_cr: weibull_sample(self.eps_cr, m, seed, beam.wrapping_mul(2))?,
            theta_cr: weibull_sample(self.theta_cr, m, seed, beam.wrapping_mul(2).wrapping_add(1))?,
        })
    }
}

/// SplitMix64 (Steele, Lea, Flood 2014): a bijective 64-bit mixer.
fn splitmix64(x: u64) -> u64 {
    let mut z = x.wrapping_add(0x9E37_79B9_7F4A_7C15);
    z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
    z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
    z ^ (z >> 31)
}

/// A uniform number in (0, 1), a pure function of `(seed, stream)`.
pub fn uniform(seed: u64, stream: u64) -> f64 {
    let h = splitmix64(splitmix64(seed) ^ stream);
    ((h >> 11) as f64 + 0.5) / (1u64 << 53) as f64
}

/// One Weibull draw `s (−ln U)^{1/m}` with `U = uniform(seed, stream)`.
pub fn weibull_sample(scale: f64, m: f64, seed: u64, stream: u64) -> Result<f64, MechanicsError> {
    positive("weibull scale", scale)?;
    positive("weibull shape m", m)?;
    Ok(scale * (-uniform(seed, stream).ln()).powf(1.0 / m))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn weibull_draws_follow_the_law() {
        // 40 000 draws, m = 2, s = 1e-4. Expected: mean s Γ(1.5) = s √π/2 = 0.886 227 s;
        // P(x ≤ s) = 1 − e^{−1} = 0.632 121. Standard errors: mean ≈ 0.463 s/√40000 = 0.0023 s,
        // fraction ≈ 0.0024; tolerances are 4 standard errors (0.01 s and 0.01).
        let base = Thresholds { eps_cr: 1e-4, theta_cr: 7e-4 };
        let n = 40_000u64;
        let (mut sum, mut below, mut sum_t) = (0.0, 0usize, 0.0);
        for b in 0..n {
            let t = base.weibull(2.0, 12345, b).unwrap();
            sum += t.eps_cr;
            sum_t += t.theta_cr;
            below += usize::from(t.eps_cr <= 1e-4);
        }
        let mean = sum / n as f64 / 1e-4;
        assert!((mean - 0.886_227).abs() < 0.01, "mean {mean}");
        assert!((sum_t / n as f64 / 7e-4 - 0.886_227).abs() < 0.01);
        let frac = below as f64 / n as f64;
        assert!((frac - 0.632_121).abs() < 0.01, "fraction {frac}");
    }

    #[test]
    fn draws_are_reproducible_and_independent_of_order() {
        let base = Thresholds { eps_cr: 1e-4, theta_cr: 7e-4 };
        let a = base.weibull(5.0, 7, 42).unwrap();
        let _ = base.weibull(5.0, 7, 3).unwrap();
        assert_eq!(a, base.weibull(5.0, 7, 42).unwrap());
        assert_ne!(a, base.weibull(5.0, 8, 42).unwrap());
        assert!(base.weibull(0.0, 7, 42).is_err());
        assert!(Thresholds { eps_cr: -1.0, theta_cr: 1.0 }.validate().is_err());
    }
}
