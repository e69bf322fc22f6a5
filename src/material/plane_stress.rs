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
