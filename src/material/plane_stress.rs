//! The damage law in plane stress, for the layers of multilayer shells.
//!
//! Strain `[ε_xx, ε_yy, γ_xy]` (engineering shear), stress `[σ_xx, σ_yy, τ_xy]`.
//!
//! # Plane stress with scalar damage
//! σ_zz = (1 − d)(C₀:ε)_zz = 0 for d < 1 gives (C₀:ε)_zz = 0, i.e. ε_zz = −ν/(1−ν)(ε_xx + ε_yy)
//! whatever the damage: the condensation is exact and the same as in elasticity, so
//! σ = (1 − d) C_ps ε with C_ps = E/(1−ν²) [[1, ν, 0], [ν, 1, 0], [0, 0, (1−ν)/2]], and
//! tr σ̃ = σ̃_xx + σ̃_yy = E/(1−ν) (ε_xx + ε_yy) selects the side. Y = ½ ε:C₀:ε = ½ ε·C_ps ε
//! (σ̃_zz = 0). The transverse shears are elastic (element business), not part of this law.
//!
//! # ε_zz enters ε_eq: [`EZZ_ENTERS_EQUIVALENT_STRAIN`]
//! ε_zz is a principal strain of the 3D strain tensor (no out-of-plane shear in a plane-stress
//! layer), so it takes part in ε_eq = sqrt(⟨ε₁⟩₊² + ⟨ε₂⟩₊² + ⟨ε_zz⟩₊²). Consequences:
//! - uniaxial compression σ_xx < 0, σ_yy = 0: ε_yy = ε_zz = −ν ε_xx and ε_eq^c = √2 ν |ε_xx|, the same
//!   as in 3D and in the fiber law, so parameters identified on any of them carry over unchanged;
//! - biaxial compression (ε_xx, ε_yy < 0) damages through the out-of-plane extension ε_zz > 0,
//!   as in Mazars' model; it would not damage at all if ε_zz were left out.
//!
//! The gradient adds ⟨ε_zz⟩₊/ε_eq · ∂ε_zz/∂(ε_xx, ε_yy, γ_xy) = ⟨ε_zz⟩₊/ε_eq · (−ν/(1−ν)) (1, 1, 0).

use nalgebra::{Matrix3, Vector3};

use super::law::PointLaw;
use super::principal::positive_part_2d;
use super::response::{assemble, Response, StressState};
use super::state::{evolve, DamageState, Side};

/// Whether the out-of-plane strain ε_zz of the plane-stress condition takes part in the equivalent
/// strains of shell layers, and hence of beam fibers ([`uniaxial`](super::uniaxial)). The ONE
/// place this choice is made; `true` (module docs).
pub const EZZ_ENTERS_EQUIVALENT_STRAIN: bool = true;

/// Plane-stress elastic matrix C_ps (Pa) for `[ε_xx, ε_yy, γ_xy]`.
#[inline]
pub fn elastic_matrix(law: &PointLaw) -> Matrix3<f64> {
    let nu = law.nu();
    let f = law.e() / (1.0 - nu * nu);
    Matrix3::new(f, f * nu, 0.0, f * nu, f, 0.0, 0.0, 0.0, f * 0.5 * (1.0 - nu))
}

/// The out-of-plane strain ε_zz = −ν/(1−ν) (ε_xx + ε_yy) of the plane-stress condition.
#[inline]
pub fn eps_zz(law: &PointLaw, strain: &Vector3<f64>) -> f64 {
    let nu = law.nu();
    -nu / (1.0 - nu) * (strain[0] + strain[1])
}

/// The equivalent strain ε_eq of an in-plane strain (ε_zz included per
/// [`EZZ_ENTERS_EQUIVALENT_STRAIN`]) and its gradient with respect to `[ε_xx, ε_yy, γ_xy]`
/// (zero where ε_eq = 0).
#[inline]
pub fn equivalent_strain(law: &PointLaw, strain: &Vector3<f64>) -> (f64, Vector3<f64>) {
    let (half_sq, mut grad) = positive_part_2d(strain[0], strain[1], strain[2]);
    let mut sq = 2.0 * half_sq;
    if EZZ_ENTERS_EQUIVALENT_STRAIN {
        let ezz = eps_zz(law, strain).max(0.0);
        sq += ezz * ezz;
        let dz = -law.nu() / (1.0 - law.nu());
        grad[0] += ezz * dz;
        grad[1] += ezz * dz;
    }
    let eq = sq.sqrt();
    if eq > 0.0 {
        (eq, grad / eq)
    } else {
        (0.0, Vector3::zeros())
    }
}

/// Update a plane-stress material point at total strain `[ε_xx, ε_yy, γ_xy]` from the committed
/// history. Pure, no allocation.
#[inline]
pub fn update(law: &PointLaw, strain: &Vector3<f64>, committed: &DamageState) -> Response<3> {
    let c0 = elastic_matrix(law);
    let sigma_tilde = c0 * strain;
    let side = Side::of_trace(sigma_tilde[0] + sigma_tilde[1]);
    let (eq, grad) = equivalent_strain(law, strain);
    let y = 0.5 * strain.dot(&sigma_tilde);
    let evo = evolve(law, side, eq, y, committed);
    assemble(&c0, &sigma_tilde, side, evo, &grad)
}

/// Marker of the plane-stress kinematics for generic drivers.
#[derive(Clone, Copy, Debug, Default)]
pub struct PlaneStress;

impl StressState<3> for PlaneStress {
    const COMPONENTS: [&'static str; 3] = ["xx", "yy", "xy"];
    const SHEAR_XY: Option<usize> = Some(2);
    fn evaluate(law: &PointLaw, strain: &Vector3<f64>, committed: &DamageState) -> Response<3> {
        update(law, strain, committed)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::material::test_support::{check_random_paths, check_tangent, law, params};

    #[test]
    fn elastic_below_the_threshold() {
        // ε_eq < ε₀: σ = C_ps ε, tangent = secant = C_ps, no dissipation. Exact.
        let law = law();
        let eps = Vector3::new(0.3e-4, -0.2e-4, 0.4e-4);
        let r = update(&law, &eps, &DamageState::default());
        assert_eq!(r.stress, elastic_matrix(&law) * eps);
        assert_eq!(r.tangent, elastic_matrix(&law));
        assert_eq!((r.dissipation, r.loading), (0.0, false));
    }

    #[test]
    fn uniaxial_tension_and_compression_closed_forms() {
        // Uniaxial stress (ε, −νε, 0): ε_zz = −ν/(1−ν)(1−ν)ε = −νε, principal strains (ε, −νε, −νε).
        // Tension: ε_eq = ε, σ_xx = E ε₀ exp(−B_t(ε − ε₀)) after the peak.
        // Compression (ε_zz counted): ε_eq = √2 ν|ε|, σ_xx = E ε s_c(κ). σ_yy = 0. Tol. 1e-12 rel.
        let law = law();
        let p = params();
        let nu = p.nu;
        let mut st = DamageState::default();
        for k in 1..=200 {
            let eps = k as f64 * 0.1 * p.eps0_t;
            let r = update(&law, &Vector3::new(eps, -nu * eps, 0.0), &st);
            let exact = if eps <= p.eps0_t {
                p.e * eps
            } else {
                p.e * p.eps0_t * (-law.b_t() * (eps - p.eps0_t)).exp()
            };
            assert!((r.stress[0] - exact).abs() <= 1e-12 * exact, "{eps}: {} vs {exact}", r.stress[0]);
            assert!(r.stress[1].abs() <= 1e-12 * p.e * eps);
            st = r.state;
        }
        const { assert!(EZZ_ENTERS_EQUIVALENT_STRAIN, "the closed form below assumes ε_zz in ε_eq") };
        let mut st = DamageState::default();
        for k in 1..=200 {
            let eps = -(k as f64) * 0.01;
            let r = update(&law, &Vector3::new(eps, -nu * eps, 0.0), &st);
            let kappa = (2f64.sqrt() * nu * eps.abs()).max(p.eps0_c);
            let s = (1.0 - p.a_c) * p.eps0_c / kappa + p.a_c * (-p.b_c * (kappa - p.eps0_c)).exp();
            let exact = p.e * eps * s;
            assert!((r.stress[0] - exact).abs() <= 1e-12 * exact.abs(), "{eps}: {} vs {exact}", r.stress[0]);
            st = r.state;
        }
    }

    #[test]
    fn biaxial_compression_damages_through_the_out_of_plane_extension() {
        // ε_xx = ε_yy = −ε: no in-plane extension, ε_zz = 2ν/(1−ν) ε > 0 is the only positive
        // principal strain, so ε_eq^c = 2ν ε/(1−ν) (exact up to round-off, 1e-14).
        let law = law();
        let nu = law.nu();
        let eps = 0.01;
        let (eq, _) = equivalent_strain(&law, &Vector3::new(-eps, -eps, 0.0));
        assert!((eq - 2.0 * nu * eps / (1.0 - nu)).abs() <= 1e-14 * eq);
        let r = update(&law, &Vector3::new(-eps, -eps, 0.0), &DamageState::default());
        assert_eq!(r.side, Side::Compression);
        assert!(r.state.d_c > 0.0);
    }

    #[test]
    fn pure_shear_is_on_the_tension_side() {
        // tr σ̃ = 0 exactly: tension side by convention (state.rs), ε_eq = γ/2 (ε_zz = 0).
        let law = law();
        let g = 10.0 * law.eps0_t();
        let r = update(&law, &Vector3::new(0.0, 0.0, g), &DamageState::default());
        assert_eq!(r.side, Side::Tension);
        assert!((r.state.kappa_t - g / 2.0).abs() <= 1e-15);
        assert!(r.state.d_t > 0.0 && r.state.d_c == 0.0);
        assert!((r.stress[2] - (1.0 - r.state.d_t) * law.mu() * g).abs() <= 1e-12 * law.mu() * g);
    }

    #[test]
    fn unilateral_effect() {
        // Tensile damage, then biaxial compression below the compressive threshold: secant = C_ps.
        let law = law();
        let t = update(&law, &Vector3::new(6.0 * law.eps0_t(), 0.0, 0.0), &DamageState::default());
        assert!(t.state.d_t > 0.5);
        let c = update(&law, &Vector3::new(-2e-4, -1e-4, 0.5e-4), &t.state);
        assert_eq!(c.side, Side::Compression);
        assert_eq!(c.state.d_c, 0.0);
        assert_eq!(c.secant, elastic_matrix(&law));
        // The stress jump at tr σ̃ = 0 with d_t ≠ d_c (response.rs docs): a deviatoric strain just
        // above and below tr = 0 gives stresses in the ratio (1 − d_t) : 1.
        let dev = Vector3::new(1e-4, -1e-4, 0.0);
        let up = update(&law, &(dev + Vector3::new(1e-12, 0.0, 0.0)), &t.state);
        let down = update(&law, &(dev - Vector3::new(1e-12, 0.0, 0.0)), &t.state);
        assert_eq!((up.side, down.side), (Side::Tension, Side::Compression));
        assert!((up.stress[0] / down.stress[0] - (1.0 - t.state.d_t)).abs() < 1e-6);
    }

    #[test]
    fn consistent_tangent_matches_finite_differences() {
        // Central differences, step 1e-7 ‖ε‖∞; tolerance 1e-6 norm-wise relative.
        let law = law();
        let loading = check_tangent::<3, PlaneStress>(&law, 21, 400, 1e-6, |e| equivalent_strain(&law, e).0);
        assert_eq!(loading, 200);
    }

    #[test]
    fn damage_never_decreases_on_random_paths() {
        let total = check_random_paths::<3, PlaneStress>(&law(), 5, 300, 60, 3.0);
        assert!(total > 0.0);
    }
}
