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
