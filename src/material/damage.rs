//! The scalar damage evolution laws d_t(κ), d_c(κ) (paper eqs. 13–14, paper §3.1), their slopes, and
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

/// The compressive branch with a regularized softening after the stress peak (the `gf_c` option,
/// [`params`](super::params) docs). Let κ_s = max(ε₀, 1/B_c) be the history value of the peak of
/// the uniaxial compressive stress (its decaying part ∝ κ g_c(κ) peaks at κ = 1/B_c) and
/// g_s = g_c(κ_s). Up to κ_s d_c is eq. 14 unchanged; beyond it the decaying part follows its own
/// exponential with the slope B_s set by G_c and h:
///
/// ```text
///   κ ≤ κ_s:  1 − d_c = (1 − A_c) ε₀/κ + A_c g_c(κ)
///   κ > κ_s:  1 − d_c = (1 − A_c) ε₀/κ + A_c g_s (κ_s/κ) e_s(κ),     e_s = exp[−B_s (κ − κ_s)]
///             d_c'    = (1 − A_c) ε₀/κ² + A_c g_s κ_s e_s (1/κ² + B_s/κ)
///             F_c(κ)  = (1 − A_c) ε₀ κ − A_c g_s κ_s e_s (κ + 2/B_s) + C,
///             C = A_c g_s (2κ_s/B_s − 2κ_s/B_c − 2/B_c²)   (F_c continuous at κ_s)
/// ```
/// (check: d/dκ[−e_s (κ + 2/B_s)] = e_s (1 + B_s κ), so F_c' = κ² d_c'). d_c and the stress are
/// continuous at κ_s; d_c keeps growing to 1.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct CompressionSoftening {
    /// κ_s = max(ε₀^c, 1/B_c), where the regularized softening starts.
    pub kappa_s: f64,
    /// g_s = exp[−B_c (κ_s − ε₀^c)].
    pub g_s: f64,
    /// B_s (1/strain), the slope of the regularized softening.
    pub b_s: f64,
}

impl CompressionSoftening {
    /// κ_s and g_s of the law (ε₀ = `eps0`, B_c = `b`) with the softening slope `b_s`.
    pub fn new(eps0: f64, b: f64, b_s: f64) -> Self {
        let kappa_s = eps0.max(1.0 / b);
        CompressionSoftening { kappa_s, g_s: (-b * (kappa_s - eps0)).exp(), b_s }
    }
}

/// Compressive damage d_c at `kappa` with the regularized softening `soft` beyond κ_s (see
/// [`CompressionSoftening`]); eq. 14 itself ([`compression`]) up to κ_s.
#[inline]
pub fn compression_softened(eps0: f64, a: f64, b: f64, soft: &CompressionSoftening, kappa: f64) -> DamageValue {
    if kappa <= soft.kappa_s {
        return compression(eps0, a, b, kappa);
    }
    let k = kappa;
    let e = (-soft.b_s * (k - soft.kappa_s)).exp();
    let r = eps0 / k;
    let tail = a * soft.g_s * soft.kappa_s / k * e;
    let integrity = (1.0 - a) * r + tail;
    DamageValue { d: 1.0 - integrity, integrity, slope: (1.0 - a) * r / k + tail * (1.0 / k + soft.b_s) }
}

/// F_c(κ) = ∫ κ² d_c'(κ) dκ of [`compression_softened`] (continuous at κ_s).
#[inline]
pub fn compression_softened_primitive(eps0: f64, a: f64, b: f64, soft: &CompressionSoftening, kappa: f64) -> f64 {
    if kappa <= soft.kappa_s {
        return compression_primitive(eps0, a, b, kappa);
    }
    let (ks, bs) = (soft.kappa_s, soft.b_s);
    let e = (-bs * (kappa - ks)).exp();
    let c = a * soft.g_s * (2.0 * ks / bs - 2.0 * ks / b - 2.0 / (b * b));
    (1.0 - a) * eps0 * kappa - a * soft.g_s * ks * e * (kappa + 2.0 / bs) + c
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
            let fd =
                (compression(EPS0, 0.6, 700.0, kappa + h).d - compression(EPS0, 0.6, 700.0, kappa - h).d) / (2.0 * h);
            assert!((c.slope - fd).abs() <= 1e-7 * c.slope, "{} vs {fd}", c.slope);
        }
    }

    #[test]
    fn primitives_differentiate_to_kappa_squared_times_slope() {
        // F'(κ) = κ² d'(κ) (module docs); central differences, tolerance 1e-7 relative.
        for kappa in [1.5 * EPS0, 4.0 * EPS0, 30.0 * EPS0] {
            let h = 1e-6 * kappa;
            let fd =
                (tension_primitive(EPS0, 800.0, kappa + h) - tension_primitive(EPS0, 800.0, kappa - h)) / (2.0 * h);
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
    fn softened_compression_is_continuous_and_its_slope_and_primitive_differentiate() {
        // κ_s = 1/B_c = 1/700 > ε₀: peak of the decaying part; B_s = 3000.
        let (a, b) = (0.6, 700.0);
        let soft = CompressionSoftening::new(EPS0, b, 3000.0);
        assert!((soft.kappa_s - 1.0 / b).abs() < 1e-18);
        // Continuity of d and of F at κ_s (1e-12 relative; the branches are evaluated apart).
        let ks = soft.kappa_s;
        let below = compression(EPS0, a, b, ks * (1.0 - 1e-13));
        let above = compression_softened(EPS0, a, b, &soft, ks * (1.0 + 1e-13));
        assert!((below.d - above.d).abs() <= 1e-12);
        let fb = compression_primitive(EPS0, a, b, ks);
        let fa = compression_softened_primitive(EPS0, a, b, &soft, ks * (1.0 + 1e-13));
        assert!((fb - fa).abs() <= 1e-9 * fb.abs(), "{fb} vs {fa}");
        // Beyond κ_s: slope and primitive against central differences (1e-7 relative, step 1e-6 κ).
        for kappa in [1.2 * ks, 3.0 * ks, 10.0 * ks] {
            let h = 1e-6 * kappa;
            let v = compression_softened(EPS0, a, b, &soft, kappa);
            let fd = (compression_softened(EPS0, a, b, &soft, kappa + h).d
                - compression_softened(EPS0, a, b, &soft, kappa - h).d)
                / (2.0 * h);
            assert!((v.slope - fd).abs() <= 1e-7 * v.slope, "{} vs {fd}", v.slope);
            let fd = (compression_softened_primitive(EPS0, a, b, &soft, kappa + h)
                - compression_softened_primitive(EPS0, a, b, &soft, kappa - h))
                / (2.0 * h);
            let exact = kappa * kappa * v.slope;
            assert!((fd - exact).abs() <= 1e-7 * exact, "{fd} vs {exact}");
        }
        // Below κ_s: eq. 14 exactly.
        assert_eq!(compression_softened(EPS0, a, b, &soft, 0.5 * ks), compression(EPS0, a, b, 0.5 * ks));
        // With B_c ≥ 1/ε₀ the softening starts at the threshold.
        let s2 = CompressionSoftening::new(EPS0, 1.0e5, 3000.0);
        assert_eq!((s2.kappa_s, s2.g_s), (EPS0, 1.0));
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
