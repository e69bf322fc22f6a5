//! Rayleigh damping `C = α M + β K₀`, K₀ the initial (undamaged) stiffness.
//!
//! The damping ratio of a mode of circular frequency ω is `ζ(ω) = α/(2ω) + β ω/2`. Given two
//! frequencies with the same ratio ζ (Chopra, *Dynamics of Structures*, §11.4):
//!
//! ```text
//!   α = 2 ζ ω₁ ω₂ / (ω₁ + ω₂),   β = 2 ζ / (ω₁ + ω₂)
//! ```
//!
//! Using K₀ rather than the tangent keeps C constant: damping forces do not jump when elements
//! soften, and the damped energy stays a positive quadratic form.
use crate::config::DampingConfig;
use std::f64::consts::PI;

/// Rayleigh coefficients.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct Rayleigh {
    /// Mass-proportional coefficient α [1/s].
    pub alpha: f64,
    /// Stiffness-proportional coefficient β [s].
    pub beta: f64,
}

impl Rayleigh {
    /// From two frequencies [Hz] and a ratio.
    pub fn from_frequencies(f1: f64, f2: f64, zeta: f64) -> Rayleigh {
        let (w1, w2) = (2.0 * PI * f1, 2.0 * PI * f2);
        Rayleigh { alpha: 2.0 * zeta * w1 * w2 / (w1 + w2), beta: 2.0 * zeta / (w1 + w2) }
    }

    /// From the (validated) job settings.
    pub fn from_config(c: &DampingConfig) -> Rayleigh {
        match (c.frequencies, c.ratio) {
            (Some([f1, f2]), Some(z)) => Rayleigh::from_frequencies(f1, f2, z),
            _ => Rayleigh { alpha: c.alpha.unwrap_or(0.0), beta: c.beta.unwrap_or(0.0) },
        }
    }

    /// Damping ratio at circular frequency ω.
    pub fn ratio_at(&self, omega: f64) -> f64 {
        self.alpha / (2.0 * omega) + self.beta * omega / 2.0
    }

    /// Whether there is no damping at all.
    pub fn is_zero(&self) -> bool {
        self.alpha == 0.0 && self.beta == 0.0
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn two_frequencies_get_the_ratio() {
        // ζ(ω₁) = ζ(ω₂) = ζ by construction (Chopra eq. 11.4.9); between them ζ is smaller.
        let r = Rayleigh::from_frequencies(1.0, 10.0, 0.05);
        for f in [1.0, 10.0] {
            assert!((r.ratio_at(2.0 * PI * f) - 0.05).abs() < 1e-14);
        }
        assert!(r.ratio_at(2.0 * PI * 3.0) < 0.05);
    }
}
