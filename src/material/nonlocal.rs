//! The plane-stress law of shell layers with nonlocal damage-driving strains (the integral
//! regularization of Pijaudier-Cabot & Bažant 1987; Bažant & Jirásek 2002, J. Eng. Mech. 128).
//!
//! # Why
//! With the local law a softening band is as narrow as the mesh allows, its direction follows
//! mesh lines, and the mechanism a wall takes after its peak can change with round-off (the
//! order in which the cells are numbered, a viscosity a factor 2 smaller): in the paper's wall in
//! shear under 1 MPa the diagonal band of compression damage competes with a vertical splitting
//! crack, a one-cell column of points whose tr σ̃ has crossed to the tensile side. Crossing the
//! unilateral switch is a jump in strength, because both sides are driven by the same ε_eq:
//! a point loaded in compression with an equivalent strain of 3e-4 has d_c ≈ 0.27
//! (ε₀^c = 2e-4), the same strain on the tensile side gives d_t ≈ 0.85 (ε₀^t = 5e-5, B_t = 360 at h = 0.05 m). A single
//! point that crosses loses most of its stiffness at once, its neighbours follow, and the column
//! of cells on one mesh line becomes a crack.
//!
//! # The averaging
//! Each side's damage is driven by the weighted average of that side's local driving strain over
//! the material points of the same layer within the interaction radius R:
//!
//! ```text
//!   ε_t,loc = w ε_eq,  ε_c,loc = (1 − w) ε_eq         (w: the tensile weight of plane_stress.rs)
//!   ε̄_k(x_i) = Σ_j α(|x_i − x_j|) V_j ε_k,loc(x_j) / Σ_j α(|x_i − x_j|) V_j
//!   α(r) = ⟨1 − r²/R²⟩₊²                               (the truncated quartic "bell")
//!   κ_k = max(κ_k,old, ε̄_k)  (Duvaut–Lions relaxation as in state.rs when τ is given)
//!   σ = [w (1 − d_t(κ_t)) + (1 − w)(1 − d_c(κ_c))] C₀ ε
//! ```
//! V_j are the points' volume weights (in-plane weight × thickness weight). The side's weight w
//! and the stress are local; only what drives the damage is averaged. Averaging each side's share
//! separately makes a crossing gradual: a point that crosses raises ε̄_t of its neighbourhood by
//! its share of the weights only, so a crack on the tensile side needs a band about R wide to
//! cross, not one point.
//!
//! # Tangent
//! The exact tangent couples every pair of points within R (a nonlocal stiffness). This update
//! returns the local part of it: ∂ε̄_k/∂ε_i = s_i ∂ε_k,loc/∂ε_i with the point's own share
//! s_i = α(0) V_i / Σ_j α_ij V_j, the diagonal block of the exact tangent. Newton then converges
//! linearly where damage grows (the driver falls back on secant iterations when needed); the
//! stress and the dissipation are exact for the given averages.
//!
//! # Dissipation
//! Y_t ḋ_t + Y_c ḋ_c with Y_t = w y, Y_c = (1 − w) y (y = ½ ε·C₀ε) at the point, integrated over
//! the increment as in state.rs (c = Y_k / κ_k²): exact for a radial path along which the point's
//! Y_k stays proportional to κ_k², as with the local law. A point whose damage grows through its
//! neighbours' strains while its own Y_k = 0 dissipates nothing (Y ḋ = 0).

use nalgebra::Vector3;

use super::law::PointLaw;
use super::plane_stress::{blended, direction, elastic_matrix, equivalent_strain, tensile_weight, Blend};
use super::response::Response;
use super::spectral;
use super::split::Split;
use super::state::{DamageState, Side};

/// The bell weight α(r) = ⟨1 − r²/R²⟩₊² (module docs).
#[inline]
pub fn bell(r: f64, radius: f64) -> f64 {
    let q = 1.0 - (r * r) / (radius * radius);
    if q > 0.0 {
        q * q
    } else {
        0.0
    }
}

/// The local driving strains `[ε_t,loc, ε_c,loc] = [w ε_eq, (1 − w) ε_eq]` of an in-plane
/// strain `[ε_xx, ε_yy, γ_xy]` (module docs).
#[inline]
pub fn driving_strains(law: &PointLaw, strain: &Vector3<f64>) -> [f64; 2] {
    let c0 = elastic_matrix(law);
    let sigma_tilde = c0 * strain;
    let (eq, _) = equivalent_strain(law, strain);
    let (x, _) = direction(&c0, &sigma_tilde);
    let (w, _) = tensile_weight(x);
    [w * eq, (1.0 - w) * eq]
}

/// Update a plane-stress point whose damage is driven by the averaged strains `averaged` =
/// `[ε̄_t, ε̄_c]`, with `self_share` = s_i its own share of the average (module docs). With
/// `averaged` = [`driving_strains`] and `self_share` = 1 it is [`plane_stress::update`]
/// (super::plane_stress::update) (to round-off).
///
/// ```text
///   g = w (1 − d_t) + (1 − w)(1 − d_c);  σ = g σ̃;  secant g C₀
///   tangent = g C₀ + σ̃ ⊗ [ w' (d_c − d_t) ∂x/∂ε − s w d_t' ∂ε_t,loc/∂ε − s (1 − w) d_c' ∂ε_c,loc/∂ε ]
///   ∂ε_t,loc/∂ε = w ∇ε_eq + ε_eq w' ∂x/∂ε,   ∂ε_c,loc/∂ε = (1 − w) ∇ε_eq − ε_eq w' ∂x/∂ε
/// ```
/// (d_k' only while κ_k grows.)
#[inline]
pub fn update(
    law: &PointLaw,
    strain: &Vector3<f64>,
    committed: &DamageState,
    averaged: [f64; 2],
    self_share: f64,
) -> Response<3> {
    let c0 = elastic_matrix(law);
    let sigma_tilde = c0 * strain;
    let side = Side::of_trace(sigma_tilde[0] + sigma_tilde[1]);
    let (eq, grad) = equivalent_strain(law, strain);
    let y = 0.5 * strain.dot(&sigma_tilde);
    let (x, dx) = direction(&c0, &sigma_tilde);
    let (w, dw) = tensile_weight(x);
    let kin = Blend { c0, sigma_tilde, side, eq, grad, y, dx, w, dw };
    match law.split() {
        Split::Trace => blended(law, &kin, averaged, self_share, committed),
        Split::Spectral => spectral::plane_stress(law, strain, &kin, averaged, self_share, committed),
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::material::plane_stress;
    use crate::material::test_support::law;

    #[test]
    fn with_its_own_strains_and_full_share_it_is_the_local_law() {
        // ε̄ = the point's own driving strains and s = 1: the local update of plane_stress.rs.
        // Stress, tangent and dissipation to 1e-12 relative (the same formulas, other order of
        // operations; the sharp-split branch of plane_stress::update equals the weighted one
        // for w ∈ {0, 1}); the states bitwise equal.
        let law = law();
        let strains = [
            Vector3::new(6.0e-4, -1.0e-4, 2.0e-4),
            Vector3::new(-3.0e-3, 0.4e-3, 0.5e-3),
            Vector3::new(-2.0e-3, -1.5e-3, 0.1e-3),
            Vector3::new(1.0e-3, -1.05e-3, 0.3e-3),
            Vector3::new(0.2e-4, -0.1e-4, 0.1e-4),
        ];
        for eps in strains {
            let a = plane_stress::update(&law, &eps, &DamageState::default());
            let b = update(&law, &eps, &DamageState::default(), driving_strains(&law, &eps), 1.0);
            let rel = |x: f64, y: f64, s: f64| (x - y).abs() <= 1e-12 * s.max(f64::MIN_POSITIVE);
            let s_norm = a.stress.norm();
            for k in 0..3 {
                assert!(rel(a.stress[k], b.stress[k], s_norm), "{eps:?}: {} vs {}", a.stress[k], b.stress[k]);
            }
            let t_norm = a.tangent.norm();
            for (x, y) in a.tangent.iter().zip(b.tangent.iter()) {
                assert!(rel(*x, *y, t_norm), "{eps:?}: tangent {x} vs {y}");
            }
            assert!(rel(a.dissipation, b.dissipation, a.dissipation), "{eps:?}");
            assert_eq!(a.state, b.state);
        }
    }

    #[test]
    fn damage_follows_the_average_not_the_point() {
        // An unstrained point whose neighbourhood averages ε̄_t = 4 ε₀^t: d_t = d_t(4 ε₀^t) from
        // eq. 13 (closed form, 1e-14), no stress and no dissipation at the point (Y = 0); the
        // same strain with a smaller average damages less.
        let law = law();
        let e0 = law.eps0_t();
        let r = update(&law, &Vector3::zeros(), &DamageState::default(), [4.0 * e0, 0.0], 0.1);
        let exact = 1.0 - 0.25 * (-law.b_t() * 3.0 * e0).exp();
        assert!((r.state.d_t - exact).abs() <= 1e-14, "{} vs {exact}", r.state.d_t);
        assert_eq!((r.dissipation, r.stress.norm()), (0.0, 0.0));
        let eps = Vector3::new(5.0 * e0, 0.0, 0.0);
        let local = update(&law, &eps, &DamageState::default(), driving_strains(&law, &eps), 1.0);
        let smeared = update(&law, &eps, &DamageState::default(), [2.0 * e0, 0.0], 0.3);
        assert!(smeared.state.d_t < local.state.d_t && smeared.stress[0] > local.stress[0]);
    }

    #[test]
    fn bell_weight() {
        // α(0) = 1, α(R/2) = (3/4)² = 0.5625, α(R) = 0 and zero beyond (exact).
        assert_eq!(bell(0.0, 0.2), 1.0);
        assert!((bell(0.1, 0.2) - 0.5625).abs() < 1e-15);
        assert_eq!(bell(0.2, 0.2), 0.0);
        assert_eq!(bell(0.3, 0.2), 0.0);
    }
}
