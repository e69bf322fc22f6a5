//! The damage law in uniaxial stress, for the fibers of fiber-section beams.
//!
//! One strain ε = ε_11, σ = (1 − d) E ε, tr σ̃ = E ε (so the side is the sign of ε, tension at 0).
//!
//! # Lateral strains enter ε_eq
//! A fiber is in uniaxial stress, so its lateral strains are ε_22 = ε_33 = −ν ε and its principal
//! strains are (ε, −ν ε, −ν ε). The fiber is treated exactly as the uniaxial stress state of the
//! plane-stress law: ε_33 plays ε_zz and counts iff
//! [`EZZ_ENTERS_EQUIVALENT_STRAIN`](super::plane_stress::EZZ_ENTERS_EQUIVALENT_STRAIN) (true), so
//! fibers and shell layers agree. With ν > 0:
//!
//! ```text
//!   ε ≥ 0:  ε_eq^t = ε                          (tension as in a bar)
//!   ε < 0:  ε_eq^c = √2 ν |ε|                   (compression damage from lateral extension)
//! ```
//! In general ε_eq = r |ε| with r = sqrt(⟨1⟩² + n_lat ⟨−ν⟩²) for ε ≥ 0 and r = sqrt(n_lat) ⟨ν⟩₊ for
//! ε < 0, n_lat = 2 (1 if ε_zz were left out). With ν = 0 a fiber never damages in compression.
//! Y = ½ E ε², so the dissipation factor is c = Y/ε_eq² = E/(2 r²).

use nalgebra::{Matrix1, Vector1};

use super::law::PointLaw;
use super::plane_stress::EZZ_ENTERS_EQUIVALENT_STRAIN;
use super::response::{Response, StressState};
use super::state::{evolve, DamageState, Side};

/// The result of one fiber update (scalar form of [`Response`]).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct UniaxialResponse {
    /// Stress σ (Pa).
    pub stress: f64,
    /// Secant modulus (1 − d) E (Pa).
    pub secant: f64,
    /// Consistent tangent dσ/dε (Pa): (1 − d) E − E ε d'(κ) dε_eq/dε while loading.
    pub tangent: f64,
    /// The trial history.
    pub state: DamageState,
    /// Energy per volume dissipated by this update (J/m³), ≥ 0.
    pub dissipation: f64,
    /// The active side (sign of ε).
    pub side: Side,
    /// Whether the active damage grew.
    pub loading: bool,
}

/// Number of lateral principal strains counted in ε_eq (module docs).
const N_LATERAL: f64 = if EZZ_ENTERS_EQUIVALENT_STRAIN { 2.0 } else { 1.0 };

/// The ratio r = ε_eq / |ε| on the side of `strain` (module docs).
#[inline]
pub fn equivalent_strain_ratio(law: &PointLaw, strain: f64) -> f64 {
    let nu = law.nu();
    if strain >= 0.0 {
        let lat = (-nu).max(0.0);
        (1.0 + N_LATERAL * lat * lat).sqrt()
    } else {
        N_LATERAL.sqrt() * nu.max(0.0)
    }
}

/// Update a fiber at total strain `strain` from the committed history. Pure, no allocation.
#[inline]
pub fn update(law: &PointLaw, strain: f64, committed: &DamageState) -> UniaxialResponse {
    let e = law.e();
    let sigma_tilde = e * strain;
    let side = Side::of_trace(sigma_tilde);
    let r = equivalent_strain_ratio(law, strain);
    let eq = r * strain.abs();
    let y = 0.5 * strain * sigma_tilde;
    let evo = evolve(law, side, eq, y, committed);
    let secant = evo.integrity * e;
    // dε_eq/dε = r sign(ε); sign(ε) = ±1 on the side (loading needs ε_eq > 0, so ε ≠ 0).
    let deq = if strain >= 0.0 { r } else { -r };
    let tangent = if evo.loading { secant - sigma_tilde * evo.dd_deq * deq } else { secant };
    UniaxialResponse {
        stress: evo.integrity * sigma_tilde,
        secant,
        tangent,
        state: evo.state,
        dissipation: evo.dissipation,
        side,
        loading: evo.loading,
    }
}

/// Marker of the uniaxial (fiber) kinematics for generic drivers.
#[derive(Clone, Copy, Debug, Default)]
pub struct Uniaxial;

impl StressState<1> for Uniaxial {
    const COMPONENTS: [&'static str; 1] = ["xx"];
    const SHEAR_XY: Option<usize> = None;
    fn evaluate(law: &PointLaw, strain: &Vector1<f64>, committed: &DamageState) -> Response<1> {
        let r = update(law, strain[0], committed);
        Response {
            stress: Vector1::new(r.stress),
            secant: Matrix1::new(r.secant),
            tangent: Matrix1::new(r.tangent),
            state: r.state,
            dissipation: r.dissipation,
            side: r.side,
            loading: r.loading,
        }
    }
}
