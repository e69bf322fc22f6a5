//! Where Newton's method starts a load step that follows a beam break.
//!
//! A load step `t → t_try` whose equilibrium `z_end` shows a failure at the fraction `λ` is cut
//! at `t_l = t + λ (t_try − t)`: the state `z_l` there is committed, the beam released (the
//! relaxed state `z_r`, same load), and the step from `t_l` is tried again. Its Newton iterations
//! used to start from `z_r` with only the platen moved: the first iteration then solves for the
//! whole load increment again. The increment's response is already known from the step that was
//! cut, `z_end − z_l` (the same load increment from a state that differs from `z_r` only by a
//! local release), so the step starts from
//!
//! ```text
//!   z₀ = z_r + s (z_end − z_l),   s = (t_try' − t_l)/(t_try − t_l)
//! ```
//!
//! (`t_try'` the new step's target). Only the starting point changes: the residual, its
//! tolerance, the committed friction state and the regularization anchor are those of a plain
//! start, so a converged step is the same equilibrium to the solver's tolerance. If Newton's
//! method fails from `z₀`, the step is tried again from the plain start before any cut-back, so
//! the load steps taken are those of a plain start too.
//!
//! **Not with crushing.** Contacts on the crushing return map's softening branch make the
//! equilibrium at a given load non-unique, and which one Newton's method finds depends on where
//! it starts: on the paper's wall with crushing (`crushing_tests.rs`, seed 5) a predicted start
//! took the post-peak path to a loss of load at 345 states instead of the target at 325. With
//! `MechParams::crushing` the steps start from the plain start, as before.

use super::diagnostics::Diagnostics;
use super::equilibrium::equilibrate;
use super::error::DemError;
use super::problem::Problem;
use super::records::LoadPoint;
use super::state::SolverState;
use super::workspace::Workspace;

/// The response of a cut load step, kept for the step that follows the break.
#[derive(Clone, Debug, serde::Serialize, serde::Deserialize)]
pub(super) struct StepPredictor {
    t_from: f64,
    t_to: f64,
    dz: Vec<f64>,
}

impl StepPredictor {
    /// The cut step's response: from `z_from` at `t_from` (the state committed before the break)
    /// to its converged end `z_end` at `t_to`.
    pub(super) fn new(t_from: f64, t_to: f64, z_from: &[f64], z_end: &[f64]) -> Self {
        StepPredictor { t_from, t_to, dz: z_end.iter().zip(z_from).map(|(e, f)| e - f).collect() }
    }

    /// The starting point of a step `t → t_try` from the state `z` (module docs); `None` when the
    /// step does not start where the cut one was cut (`t ≠ t_from`) or the cut step was empty.
    pub(super) fn guess(&self, z: &[f64], t: f64, t_try: f64) -> Option<Vec<f64>> {
        let span = self.t_to - self.t_from;
        if t != self.t_from || span <= 0.0 || t_try <= t || z.len() != self.dz.len() {
            return None;
        }
        let s = (t_try - t) / span;
        Some(z.iter().zip(&self.dz).map(|(z, d)| z + s * d).collect())
    }
}

/// Whether load steps after a break start from the predictor (module docs).
pub(super) fn predicts_steps(pb: &Problem<'_>) -> bool {
    pb.opts.predict_steps && pb.model.params.crushing.is_none()
}

/// Equilibrium at `load` (the load parameter `t_try`) for a step from the committed state:
/// first from `start`, the predictor's starting point ([`StepPredictor::guess`]) when it has one
/// for this step, then, if Newton's method fails from there, from the plain start (module docs).
pub(super) fn equilibrate_predicted(
    pb: &Problem<'_>,
    state: &mut SolverState,
    ws: &mut Workspace,
    diag: &mut Diagnostics<'_>,
    start: Option<Vec<f64>>,
    load: &LoadPoint,
    t_try: f64,
) -> Result<(), DemError> {
    if let Some(z0) = start {
        state.z = z0;
        match equilibrate(pb, state, ws, diag, load, None, t_try) {
            Ok(()) => {
                diag.profile.predicted_steps += 1;
                return Ok(());
            }
            Err(DemError::NoConvergence { .. }) => {
                diag.profile.predictor_fallbacks += 1;
                state.restore();
            }
            Err(e) => return Err(e),
        }
    }
    equilibrate(pb, state, ws, diag, load, None, t_try)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn guess_scales_the_cut_steps_response() {
        // A cut step from 0.25 (z_from = (1, 1)) to 0.75 (z_end = (2, −1)) moved z by (1, −2); a
        // step from 0.25 to 0.5 starts from z + ½ (1, −2), one to 0.75 from z + (1, −2) (exact
        // arithmetic on these binary fractions).
        let p = StepPredictor::new(0.25, 0.75, &[1.0, 1.0], &[2.0, -1.0]);
        assert_eq!(p.guess(&[0.5, 0.5], 0.25, 0.5), Some(vec![1.0, -0.5]));
        assert_eq!(p.guess(&[0.5, 0.5], 0.25, 0.75), Some(vec![1.5, -1.5]));
        // Another start, or a backward step: no guess.
        assert_eq!(p.guess(&[0.5, 0.5], 0.3, 0.75), None);
        assert_eq!(p.guess(&[0.5, 0.5], 0.25, 0.25), None);
    }
}
