//! The damage law in 3D, for the material-point driver (identification, checks).
//!
//! Voigt order `[xx, yy, zz, yz, xz, xy]` with engineering shear strains γ = 2 ε_ij; stresses in the
//! same order. C₀ = λ 1⊗1 + 2μ 𝕀: normal block λ + 2μ on the diagonal, λ off it, μ on the shear
//! diagonal (engineering shear). tr σ̃ = (3λ + 2μ) tr ε. Principal strains by a symmetric 3×3
//! eigen solver ([`principal`](super::principal)).

use nalgebra::{Matrix6, Vector6};

use super::law::PointLaw;
use super::principal::positive_part_3d;
use super::response::{assemble, Response, StressState};
use super::spectral;
use super::split::Split;
use super::state::{evolve, DamageState, Side};

/// Isotropic elastic matrix C₀ (Pa) in Voigt order `[xx, yy, zz, yz, xz, xy]`, engineering shear.
#[inline]
pub fn elastic_matrix(law: &PointLaw) -> Matrix6<f64> {
    let (l, m) = (law.lambda(), law.mu());
    let mut c = Matrix6::zeros();
    for i in 0..3 {
        for j in 0..3 {
            c[(i, j)] = l;
        }
        c[(i, i)] = l + 2.0 * m;
        c[(i + 3, i + 3)] = m;
    }
    c
}

/// ε_eq = sqrt(Σ⟨ε_i⟩₊²) over the three principal strains and its gradient with respect to the
/// Voigt strain (zero where ε_eq = 0).
#[inline]
pub fn equivalent_strain(strain: &Vector6<f64>) -> (f64, Vector6<f64>) {
    let (half_sq, grad) = positive_part_3d(strain);
    let eq = (2.0 * half_sq).sqrt();
    if eq > 0.0 {
        (eq, grad / eq)
    } else {
        (eq, Vector6::zeros())
    }
}

/// Update a 3D material point at the total Voigt strain from the committed history. Pure, no
/// allocation.
#[inline]
pub fn update(law: &PointLaw, strain: &Vector6<f64>, committed: &DamageState) -> Response<6> {
    let c0 = elastic_matrix(law);
    let sigma_tilde = c0 * strain;
    let side = Side::of_trace(sigma_tilde[0] + sigma_tilde[1] + sigma_tilde[2]);
    let (eq, grad) = equivalent_strain(strain);
    if law.split() == Split::Spectral {
        return spectral::three_d(law, strain, side, eq, &grad, committed);
    }
    let y = 0.5 * strain.dot(&sigma_tilde);
    let evo = evolve(law, side, eq, y, committed);
    assemble(&c0, &sigma_tilde, side, evo, &grad)
}

/// Marker of the 3D kinematics for generic drivers.
#[derive(Clone, Copy, Debug, Default)]
pub struct ThreeD;

impl StressState<6> for ThreeD {
    const COMPONENTS: [&'static str; 6] = ["xx", "yy", "zz", "yz", "xz", "xy"];
    const SHEAR_XY: Option<usize> = Some(5);
    fn evaluate(law: &PointLaw, strain: &Vector6<f64>, committed: &DamageState) -> Response<6> {
        update(law, strain, committed)
    }
}

#[cfg(test)]
mod tests {
    use nalgebra::Vector3;

    use super::*;
    use crate::material::plane_stress;
    use crate::material::test_support::{check_random_paths, check_tangent, law, params};

    #[test]
    fn uniaxial_stress_closed_forms() {
        // (ε, −νε, −νε, 0, 0, 0) is uniaxial stress σ_xx = E ε in elasticity. Tension: ε_eq = ε;
        // compression: ε_eq = √2 ν |ε| (paper §3.1 with Mazars-type lateral extension). Tol. 1e-12 rel.
        let law = law();
        let p = params();
        let nu = p.nu;
        let mut st = DamageState::default();
        for k in 1..=100 {
            let eps = k as f64 * 0.2 * p.eps0_t;
            let r = update(&law, &Vector6::new(eps, -nu * eps, -nu * eps, 0.0, 0.0, 0.0), &st);
            let exact =
                if eps <= p.eps0_t { p.e * eps } else { p.e * p.eps0_t * (-law.b_t() * (eps - p.eps0_t)).exp() };
            assert!((r.stress[0] - exact).abs() <= 1e-12 * exact, "{eps}: {} vs {exact}", r.stress[0]);
            assert!(r.stress.rows(1, 5).amax() <= 1e-12 * p.e * eps);
            st = r.state;
        }
        let mut st = DamageState::default();
        for k in 1..=100 {
            let eps = -(k as f64) * 0.02;
            let r = update(&law, &Vector6::new(eps, -nu * eps, -nu * eps, 0.0, 0.0, 0.0), &st);
            let kappa = (2f64.sqrt() * nu * eps.abs()).max(p.eps0_c);
            let s = (1.0 - p.a_c) * p.eps0_c / kappa + p.a_c * (-p.b_c * (kappa - p.eps0_c)).exp();
            assert!((r.stress[0] - p.e * eps * s).abs() <= 1e-12 * (p.e * eps * s).abs());
            st = r.state;
        }
    }

    #[test]
    fn agrees_with_plane_stress_at_sigma_zz_zero() {
        // 3D at ε_zz = −ν/(1−ν)(ε_xx + ε_yy) = plane stress (σ_zz = 0): same in-plane stress and
        // damage, tolerance 1e-12 relative (eigen solver vs closed form).
        let law = law();
        for (exx, eyy, gxy) in [(3e-4, -1e-4, 2e-4), (-2e-3, 1e-4, 5e-4), (0.0, 0.0, 8e-4), (-1e-2, -1e-2, 0.0)] {
            let ps_eps = Vector3::new(exx, eyy, gxy);
            let ps = plane_stress::update(&law, &ps_eps, &DamageState::default());
            let ezz = plane_stress::eps_zz(&law, &ps_eps);
            let r = update(&law, &Vector6::new(exx, eyy, ezz, 0.0, 0.0, gxy), &DamageState::default());
            let scale = ps.stress.amax();
            assert!((r.stress[0] - ps.stress[0]).abs() <= 1e-12 * scale);
            assert!((r.stress[1] - ps.stress[1]).abs() <= 1e-12 * scale);
            assert!((r.stress[5] - ps.stress[2]).abs() <= 1e-12 * scale);
            assert!(r.stress[2].abs() <= 1e-12 * scale);
            assert!((r.state.d_t - ps.state.d_t).abs() <= 1e-12 && (r.state.d_c - ps.state.d_c).abs() <= 1e-12);
            assert_eq!(r.side, ps.side);
        }
    }

    #[test]
    fn hydrostatic_compression_does_not_damage() {
        // All principal strains negative: ε_eq = 0, no damage however large the pressure.
        let law = law();
        let r = update(&law, &Vector6::new(-0.05, -0.05, -0.05, 0.0, 0.0, 0.0), &DamageState::default());
        assert_eq!((r.side, r.state.d_c, r.loading), (Side::Compression, 0.0, false));
    }

    #[test]
    fn unilateral_effect() {
        let law = law();
        let t = update(&law, &Vector6::new(5e-4, 0.0, 0.0, 1e-4, 0.0, 0.0), &DamageState::default());
        assert!(t.state.d_t > 0.5);
        let c = update(&law, &Vector6::new(-1e-4, -1e-4, -1e-4, 0.0, 0.0, 0.0), &t.state);
        assert_eq!((c.side, c.state.d_c), (Side::Compression, 0.0));
        assert_eq!(c.secant, elastic_matrix(&law));
    }

    #[test]
    fn consistent_tangent_matches_finite_differences() {
        // Central differences, step 1e-7 ‖ε‖∞; tolerance 1e-6 norm-wise relative.
        let law = law();
        let loading = check_tangent::<6, ThreeD>(&law, 31, 400, 1e-6, |e| equivalent_strain(e).0);
        assert_eq!(loading, 200);
    }

    #[test]
    fn damage_never_decreases_on_random_paths() {
        let total = check_random_paths::<6, ThreeD>(&law(), 9, 200, 60, 3.0);
        assert!(total > 0.0);
    }
}
