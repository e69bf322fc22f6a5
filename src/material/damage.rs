//! The scalar damage evolution laws d_t(κ), d_c(κ) (paper eqs. 13–14, SPEC §2), their slopes, and
//! the primitives used to integrate the dissipation exactly.
//!
//! ```text
//!   d_t(κ) = 1 − (ε₀/κ) g_t(κ),                      g_t = exp[−B_t (κ − ε₀^t)]
//!   d_c(κ) = 1 − (1 − A_c) ε₀/κ − A_c g_c(κ),        g_c = exp[−B_c (κ − ε₀^c)]
//!   d_t'(κ) = (ε₀/κ) g_t (1/κ + B_t)                 > 0
//!   d_c'(κ) = (1 − A_c) ε₀/κ² + A_c B_c g_c          > 0   (A_c ∈ [0,1], B_c > 0)
//! ```
//! Both start at d(ε₀) = 0 and increase strictly to 1 as κ → ∞; the integrity 1 − d is computed
//! directly from the right-hand terms (no cancellation when d → 1).
//!
//! # Dissipation primitives
//! The dissipation rate is Y ḋ with Y = ½ ε:C₀:ε (the derivative of −ρψ with respect to d on the
//! active side, paper eq. 10). Along a radial strain path ε(s) = s ε̂ both Y and ε_eq scale with s,
//! so Y = c κ² with the constant c = Y / ε_eq² while loading (κ = ε_eq), and the energy dissipated
//! while κ grows from κ₁ to κ₂ is exactly c [F(κ₂) − F(κ₁)] with F(κ) = ∫ κ² d'(κ) dκ:
//!
//! ```text
//!   F_t(κ) = −ε₀ g_t(κ) (κ + 2/B_t)
//!   F_c(κ) = (1 − A_c) ε₀ κ − A_c g_c(κ) (κ² + 2κ/B_c + 2/B_c²)
//! ```
//! (check: d/dκ F_t = ε₀ g_t (1 + B_t κ) = κ² d_t'; d/dκ F_c = (1−A_c) ε₀ + A_c B_c κ² g_c = κ² d_c').
//! F is increasing, so the increment is never negative.

/// Damage, integrity and slope of a damage function at one value of the history variable κ.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct DamageValue {
    /// The damage d ∈ [0, 1).
    pub d: f64,
    /// The integrity 1 − d, computed without cancellation.
    pub integrity: f64,
    /// The slope ∂d/∂κ (> 0).
    pub slope: f64,
}

/// Tensile damage d_t at `kappa` (clamped below at `eps0`): threshold `eps0` = ε₀^t, slope
/// parameter `b` = B_t (1/strain).
#[inline]
pub fn tension(eps0: f64, b: f64, kappa: f64) -> DamageValue {
    let k = kappa.max(eps0);
    let g = (-b * (k - eps0)).exp();
    let integrity = eps0 / k * g;
    DamageValue { d: 1.0 - integrity, integrity, slope: integrity * (1.0 / k + b) }
}

/// Compressive damage d_c at `kappa` (clamped below at `eps0`): threshold `eps0` = ε₀^c, shape
/// parameters `a` = A_c and `b` = B_c (1/strain).
#[inline]
pub fn compression(eps0: f64, a: f64, b: f64, kappa: f64) -> DamageValue {
    let k = kappa.max(eps0);
    let g = (-b * (k - eps0)).exp();
    let r = eps0 / k;
    let integrity = (1.0 - a) * r + a * g;
    DamageValue { d: 1.0 - integrity, integrity, slope: (1.0 - a) * r / k + a * b * g }
}

/// F_t(κ) = ∫ κ² d_t'(κ) dκ (module docs), κ clamped below at `eps0`.
#[inline]
pub fn tension_primitive(eps0: f64, b: f64, kappa: f64) -> f64 {
    let k = kappa.max(eps0);
    -eps0 * (-b * (k - eps0)).exp() * (k + 2.0 / b)
}

/// F_c(κ) = ∫ κ² d_c'(κ) dκ (module docs), κ clamped below at `eps0`.
#[inline]
pub fn compression_primitive(eps0: f64, a: f64, b: f64, kappa: f64) -> f64 {
    let k = kappa.max(eps0);
    let g = (-b * (k - eps0)).exp();
    (1.0 - a) * eps0 * k - a * g * (k * k + 2.0 * k / b + 2.0 / (b * b))
}

#[cfg(test)]
mod tests {
    use super::*;

    const EPS0: f64 = 1.2e-4;

    #[test]
    fn damage_starts_at_zero_at_the_threshold() {
        // d(ε₀) = 0 from eqs. 13–14; exact in floating point here (g = 1, ε₀/κ = 1).
        assert_eq!(tension(EPS0, 500.0, EPS0).d, 0.0);
        assert_eq!(compression(EPS0, 0.7, 900.0, EPS0).d, 0.0);
        // Below the threshold κ is clamped: still zero.
        assert_eq!(tension(EPS0, 500.0, 0.0).d, 0.0);
    }

    #[test]
    fn slopes_match_central_differences() {
        // Tolerance 1e-7 relative: central differences with step 1e-6 κ (error O(step²)).
        for kappa in [1.5 * EPS0, 4.0 * EPS0, 30.0 * EPS0] {
            let h = 1e-6 * kappa;
            let t = tension(EPS0, 800.0, kappa);
            let fd = (tension(EPS0, 800.0, kappa + h).d - tension(EPS0, 800.0, kappa - h).d) / (2.0 * h);
            assert!((t.slope - fd).abs() <= 1e-7 * t.slope, "{} vs {fd}", t.slope);
            let c = compression(EPS0, 0.6, 700.0, kappa);
            let fd = (compression(EPS0, 0.6, 700.0, kappa + h).d
                - compression(EPS0, 0.6, 700.0, kappa - h).d)
                / (2.0 * h);
            assert!((c.slope - fd).abs() <= 1e-7 * c.slope, "{} vs {fd}", c.slope);
        }
    }

    #[test]
    fn primitives_differentiate_to_kappa_squared_times_slope() {
        // F'(κ) = κ² d'(κ) (module docs); central differences, tolerance 1e-7 relative.
        for kappa in [1.5 * EPS0, 4.0 * EPS0, 30.0 * EPS0] {
            let h = 1e-6 * kappa;
            let fd = (tension_primitive(EPS0, 800.0, kappa + h) - tension_primitive(EPS0, 800.0, kappa - h))
                / (2.0 * h);
            let exact = kappa * kappa * tension(EPS0, 800.0, kappa).slope;
            assert!((fd - exact).abs() <= 1e-7 * exact, "{fd} vs {exact}");
            let fd = (compression_primitive(EPS0, 0.6, 700.0, kappa + h)
                - compression_primitive(EPS0, 0.6, 700.0, kappa - h))
                / (2.0 * h);
            let exact = kappa * kappa * compression(EPS0, 0.6, 700.0, kappa).slope;
            assert!((fd - exact).abs() <= 1e-7 * exact, "{fd} vs {exact}");
        }
    }

    #[test]
    fn integrity_stays_accurate_far_in_the_softening() {
        // At κ = ε₀ + 40/B: 1 − d = e^{-40} ε₀/κ ≈ 4.2e-18·ε₀/κ, far below the spacing of doubles
        // near 1, yet computed to round-off from the closed form.
        let b = 1000.0;
        let kappa = EPS0 + 40.0 / b;
        let v = tension(EPS0, b, kappa);
        let exact = EPS0 / kappa * (-40.0f64).exp();
        assert!((v.integrity - exact).abs() <= 1e-12 * exact);
        assert_eq!(v.d, 1.0);
    }
}
