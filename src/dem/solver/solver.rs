//! The solver of one virtual test: the owner of the parts the step pipeline works on, with the
//! public entry points that call it.
//!
//! | part | type | fields | lives |
//! |---|---|---|---|
//! | problem | [`Problem`] | `model`, `opts`, `scales` | fixed for the test |
//! | state | [`SolverState`] | coordinates, beams, contacts, load, energy, records | the test's mechanics: cloned, it continues in a new solver ([`Solver::resume`]) |
//! | workspace | [`Workspace`] | `operator`, `shifted`, `candidates`, `jacobians` | rebuilt from the state when lost |
//! | diagnostics | [`Diagnostics`] | `counters`, `profile`, `trace`, `observer`, `phase` | read after the run |
//!
//! **The step as a pipeline.** The algorithm is free functions over these parts, in the manner
//! of rapier's pipelines and pmsim's solvers: each takes the parts it touches, always in the
//! order
//!
//! ```text
//!   fn step(pb: &Problem, state: &mut SolverState, ws: &mut Workspace, diag: &mut Diagnostics, <its own arguments>)
//! ```
//!
//! leaving out those it does not touch (a function that only reads the state takes
//! `&SolverState`). The problem is one struct passed by reference, not the model, the options
//! and the scales apart, because nearly every step reads the model and most read the options or
//! the scales; the diagnostics are one struct for the same reason. So every list stays within
//! seven arguments, the borrows are disjoint by construction (the workspace's operator beside
//! the state it is kept up from), and a signature says what a step may change: a `&mut` part.
//! The solver holds no algorithm: [`Solver::start`], [`Solver::run_stage`] and the others hand
//! its parts to the pipeline.
//!
//! | file | the pipeline's step |
//! |---|---|
//! | [`super::stage`] | the stage loop: trial load steps, cut-backs, snaps, breaks inside a step, contact events |
//! | [`super::breaks`] | where a beam breaks, the most critical beams, the release of a broken beam's force |
//! | [`super::equilibrium`] | an equilibrium at a fixed load: Newton's method, booked to its phase |
//! | [`super::linear`] | Newton's first step as the equilibrium where the problem is linear |
//! | [`super::continuation`] | pseudo-transient continuation where Newton's method fails |
//! | [`super::energy`] | the commit of a state and the energy account |
//! | [`super::step_predictor`], [`super::contact_events`] | the start of a step after a break; the first contact event of a step |
use super::breaks;
use super::checkpoint::CheckpointSink;
use super::contact_set::ActiveContact;
use super::diagnostics::Diagnostics;
use super::equilibrium;
use super::error::DemError;
use super::options::SolverOptions;
use super::problem::Problem;
use super::records::{BrokenBeam, LoadPoint, StageEnd, StateRecord};
use super::stage;
use super::state::SolverState;
use super::system::Model;
use super::walk::StageWalk;
use super::workspace::Workspace;

/// The solver of one test (module docs).
pub struct Solver<'a> {
    /// The model, the options and the scales.
    pub(super) problem: Problem<'a>,
    /// The mechanical state.
    pub(super) state: SolverState,
    /// The operator, the contact candidates and the Jacobians.
    pub(super) ws: Workspace,
    /// The counters, the profile and the trace, read after the run, and the observer, set
    /// before it ([`Diagnostics`]).
    pub diag: Diagnostics<'a>,
}

impl<'a> Solver<'a> {
    /// A solver at the unloaded state (nothing broken, no contact), with the first load point.
    pub fn new(model: Model<'a>, opts: SolverOptions, initial: LoadPoint) -> Result<Solver<'a>, DemError> {
        let state = SolverState::new(model.map.n_z, model.sample.beams.len(), initial);
        Solver::resume(model, opts, state)
    }

    /// A solver that continues `state` (a clone of another solver's state for the same model,
    /// or a new one): the workspace is built afresh, the counters and the profile start at zero.
    /// Errors: a state or load of another size than the model's, a share of `slip_terms` outside
    /// `[0, 1]`.
    pub fn resume(model: Model<'a>, opts: SolverOptions, state: SolverState) -> Result<Solver<'a>, DemError> {
        let map = &model.map;
        let load = &state.load;
        if load.prescribed.len() != map.prescribed.len() || load.forces.len() != map.forced.len() {
            return Err(DemError::InvalidParameter {
                field: "load point",
                value: format!("{} prescribed / {} forces", load.prescribed.len(), load.forces.len()),
                expected: "one value per prescribed and per force-controlled platen DOF",
            });
        }
        if state.z.len() != map.n_z || state.z_commit.len() != map.n_z || state.intact.len() != model.terms.len() {
            return Err(DemError::InvalidParameter {
                field: "solver state",
                value: format!("{} coordinates / {} beams", state.z.len(), state.intact.len()),
                expected: "the model's coordinates and beams",
            });
        }
        if !opts.slip_terms.is_valid() {
            return Err(DemError::InvalidParameter {
                field: "slip_terms.share",
                value: opts.slip_terms.share.to_string(),
                expected: "a share of k_t in [0, 1]",
            });
        }
        let problem = Problem::new(model, opts);
        let ws = Workspace::new(problem.model.map.n_eq(), &problem.opts)?;
        Ok(Solver { diag: Diagnostics::new(&problem.opts), problem, state, ws })
    }

    /// The mechanical state ([`SolverState`]).
    pub fn state(&self) -> &SolverState {
        &self.state
    }

    /// The recorded states.
    pub fn states(&self) -> &[StateRecord] {
        &self.state.records
    }

    /// The broken beams, in order.
    pub fn broken(&self) -> &[BrokenBeam] {
        &self.state.broken
    }

    /// The active contacts of the last equilibrium state.
    pub fn contacts(&self) -> &[ActiveContact] {
        &self.state.contacts
    }

    /// The model.
    pub fn model(&self) -> &Model<'a> {
        &self.problem.model
    }

    /// The factorization statistics `(numeric factorizations, symbolic analyses)`, the
    /// continuation's own shifted operator's included.
    pub fn factor_stats(&self) -> (usize, usize) {
        self.ws.factor_stats()
    }

    /// Sets the reuse threshold `η` of contact Jacobians ([`super::tangent`]; 0, the default,
    /// recomputes every Jacobian at every Newton iteration). Errors: `η` negative or not finite.
    pub fn set_jacobian_reuse(&mut self, eta: f64) -> Result<(), DemError> {
        super::error::non_negative("jacobian reuse fraction", eta)?;
        self.ws.jacobians.reuse_fraction = eta;
        Ok(())
    }

    /// Records the unloaded initial state (call once before the first stage).
    pub fn start(&mut self) -> Result<(), DemError> {
        stage::start(&self.problem, &mut self.state, &mut self.ws, &mut self.diag)
    }

    /// Runs one load stage from the current load to `target` in `steps` equal steps; `monitor`
    /// is the platen force `(platen, dof)` watched for loss of load ([`super::stage`]).
    ///
    /// **Cut-back.** A step whose equilibrium is not found is retried from the committed state
    /// with half the increment (at most `max_cutbacks` halvings of one step); after a success the
    /// increment doubles again up to the step. If the smallest increment fails too, the error is
    /// returned: the recorded states so far stay in [`Self::states`].
    pub fn run_stage(
        &mut self,
        target: &LoadPoint,
        steps: usize,
        monitor: Option<(usize, usize)>,
    ) -> Result<StageEnd, DemError> {
        let walk = self.stage_walk(target, steps);
        self.continue_stage(walk, monitor, None)
    }

    /// The walk of a stage from the current load to `target` in `steps` steps, not yet begun.
    pub(super) fn stage_walk(&self, target: &LoadPoint, steps: usize) -> StageWalk {
        stage::stage_walk(&self.problem.opts, &self.state, target, steps)
    }

    /// Runs the stage `walk` stands in to its end ([`stage::continue_stage`]), asking `sink`
    /// after each load step whether a checkpoint is due.
    pub(super) fn continue_stage(
        &mut self,
        walk: StageWalk,
        monitor: Option<(usize, usize)>,
        sink: Option<&mut dyn CheckpointSink>,
    ) -> Result<StageEnd, DemError> {
        stage::continue_stage(&self.problem, &mut self.state, &mut self.ws, &mut self.diag, walk, monitor, sink)
    }

    /// Breaks beam `b` now (e.g. a pre-cracked sample), re-equilibrates at the current load and
    /// records the state ([`super::breaks`]). Errors: `b` not an intact beam, and those of the
    /// release.
    pub fn break_and_relax(&mut self, b: usize) -> Result<(), DemError> {
        breaks::break_and_relax(&self.problem, &mut self.state, &mut self.ws, &mut self.diag, b)
    }

    /// Finds equilibrium at `load` starting from the current `z` (see [`super::equilibrium`]);
    /// leaves the contacts of the equilibrium state in [`Self::contacts`].
    pub fn equilibrate(&mut self, load: &LoadPoint, t: f64) -> Result<(), DemError> {
        equilibrium::equilibrate(&self.problem, &mut self.state, &mut self.ws, &mut self.diag, load, None, t)
    }
}
