//! Element-level mechanics of the 2D beam-particle DEM (paper §2.1): what one beam, one contact and
//! one friction law compute for the quasi-static event-driven solver.
//!
//! Particles are rigid, with 3 DOF `q = (u_x, u_y, θ)` at their reference point (the centroid);
//! kinematics are linear (small displacements). Every function takes plain inputs (points,
//! offsets, polygons, parameters) and returns forces as generalized forces `(F_x, F_y, M_z)` about
//! the reference points, ordered `(i, j)`; 6×6 matrices act on `(q_i, q_j)`.
//!
//! **Sign convention.** Returned forces are *internal* (resisting) forces, what the particles
//! exert on the beam/contact: equilibrium is `Σ f_internal = f_external`, and every stiffness is
//! `∂f_internal/∂q`. The beam or contact acts on the particles with `−f`.
//!
//! | file | concept |
//! |------|---------|
//! | [`kinematics`] | the 2×3 map of an attached point; forces at a point as particle forces |
//! | [`beam`]       | the cohesive Euler–Bernoulli beam between two seeds: forces, 6×6 stiffness |
//! | [`thresholds`] | failure thresholds, deterministic or Weibull per beam |
//! | [`failure`]    | the failure index P, the failure mode, the λ at which P reaches 1 |
//! | [`contact`]    | overlap, chord, normal, normal force and its linearizations |
//! | [`contact_jacobian`] | the exact Jacobian of a contact's forces (friction, crushing) by dual numbers through the law |
//! | [`dual`]       | forward-mode dual numbers over a pair's six DOFs |
//! | [`friction`]   | Coulomb return map, dissipation, tangent |
//! | [`thickness`]  | the overlap's thickness function and its integrals above a level (the Winkler layer) |
//! | [`crushing`]   | optional compressive failure: beam crushing, bounded and softening contact pressure |

pub mod beam;
pub mod contact;
pub mod contact_jacobian;
pub mod crushing;
pub mod dual;
pub mod error;
pub mod failure;
pub mod friction;
pub mod kinematics;
pub mod thickness;
pub mod thresholds;

pub use beam::{beam_actions, beam_forces, beam_stiffness, BeamActions, BeamGeom};
pub use contact::{contact, contact_length, Contact};
pub use crushing::{CrushUpdate, Crushing, PlasticState};
pub use error::MechanicsError;
pub use failure::{failure_index, failure_lambda, failure_mode, first_crossing, FailureMode};
pub use friction::{friction_stiffness, friction_update, FrictionUpdate, SlipState};
pub use thickness::{Clipped, ThicknessProfile};
pub use thresholds::Thresholds;

use error::{non_negative, positive};

/// The lattice parameters shared by all beams and contacts of a sample. Defaults: the paper's
/// Table 1 (`Ē = 2.5 GPa, ε_cr = 1e-4, θ_cr = 7e-4, μ = 0.6`), `t_z = 1 m`, `k_t = k_n`.
/// (The inertia coefficient α enters through each beam's `inertia`, computed by the sample
/// generator.)
#[derive(Clone, Copy, Debug, PartialEq, serde::Serialize)]
pub struct MechParams {
    /// Lattice Young modulus `Ē` (Pa), beams and contacts.
    pub e_bar: f64,
    /// Out-of-plane thickness `t_z` (m), used by the contact law.
    pub t_z: f64,
    /// Critical strain `ε_cr` (deterministic value, or Weibull scale).
    pub eps_cr: f64,
    /// Critical rotation `θ_cr` (rad; deterministic value, or Weibull scale).
    pub theta_cr: f64,
    /// Friction coefficient μ.
    pub mu: f64,
    /// Tangential contact stiffness as a multiple of the normal one, `k_t = kt_over_kn · k_n`.
    pub kt_over_kn: f64,
    /// Optional crushing (an extension of paper §2.1, [`crushing`]); `None`: paper §2.1's model.
    pub crushing: Option<Crushing>,
}

impl Default for MechParams {
    fn default() -> Self {
        MechParams { e_bar: 2.5e9, t_z: 1.0, eps_cr: 1e-4, theta_cr: 7e-4, mu: 0.6, kt_over_kn: 1.0, crushing: None }
    }
}

impl MechParams {
    /// The deterministic thresholds `(ε_cr, θ_cr)`.
    pub fn thresholds(&self) -> Thresholds {
        Thresholds { eps_cr: self.eps_cr, theta_cr: self.theta_cr }
    }

    /// Checks every field (finite; > 0, except μ ≥ 0).
    pub fn validate(&self) -> Result<(), MechanicsError> {
        positive("e_bar", self.e_bar)?;
        positive("t_z", self.t_z)?;
        positive("eps_cr", self.eps_cr)?;
        positive("theta_cr", self.theta_cr)?;
        non_negative("mu", self.mu)?;
        positive("kt_over_kn", self.kt_over_kn)?;
        if let Some(c) = &self.crushing {
            c.validate()?;
        }
        Ok(())
    }
}
