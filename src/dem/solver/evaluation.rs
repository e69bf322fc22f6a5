//! A residual evaluation at a state of the solver: the contacts found there, the residual and
//! its measures, the beams' forces ([`super::equilibrium`] makes it, the Newton trace and the
//! continuation read it).
use super::contact_set::ActiveContact;

/// A residual evaluation.
pub(super) struct Evaluation {
    /// Contacts at the state.
    pub contacts: Vec<ActiveContact>,
    /// Residual on the equations.
    pub r: Vec<f64>,
    /// `‖r‖∞ / scale`.
    pub relative: f64,
    /// `½ Σ (w_e r_e)²`, `w = 1` on force rows, `1/D̄` on moment rows.
    pub merit: f64,
    /// The intact beams' internal forces `K_b z` at the state (over `z`).
    pub beam_forces: Vec<f64>,
}
