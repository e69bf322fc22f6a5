//! The solver of one virtual test: the model, its options, the mechanical state
//! ([`SolverState`]) and the workspace that computes it, with the counters, the profile and
//! the observer of recorded states.
//!
//! | part | fields | lives |
//! |---|---|---|
//! | problem | `model`, `opts`, `scales` | fixed for the test |
//! | state | `state` | the test's mechanics: cloned, it continues in a new solver ([`Solver::resume`]) |
//! | workspace | `operator`, `candidates`, `jacobians` | rebuilt from the state when lost |
//! | diagnostics | `counters`, `profile`, `trace`, `observer` | read after the run |
//!
//! The algorithm's steps live in their own files: the stage loop ([`super::stage`]), the
//! breaks ([`super::breaks`]), equilibrium ([`super::equilibrium`]), continuation
//! ([`super::continuation`]), the energy account and commits ([`super::energy`]).
use super::contact_candidates::CandidateList;
use super::contact_set::ActiveContact;
use super::error::DemError;
use super::operator::{Operator, Upkeep};
use super::options::SolverOptions;
use super::phases::Phase;
use super::profile::{Counters, SolverProfile};
use super::records::{BrokenBeam, LoadPoint, Observer, StateRecord};
use super::scales::Scales;
use super::state::SolverState;
use super::system::Model;
use super::tangent::JacobianCache;
use super::trace::Trace;

/// The solver of one test (module docs).
pub struct Solver<'a> {
    pub(super) model: Model<'a>,
    pub(super) opts: SolverOptions,
    pub(super) scales: Scales,
    pub(super) state: SolverState,
    pub(super) operator: Operator,
    /// With updates in place: the continuation's shifted operators, a Woodbury operator of their
    /// own, so that the updatable factor stays unshifted ([`super::continuation`]).
    pub(super) shifted: Option<Operator>,
    /// The contact search's candidate list ([`super::contact_candidates`]).
    pub(super) candidates: CandidateList,
    /// Contact Jacobians kept between evaluations ([`super::tangent`]).
    pub(super) jacobians: JacobianCache,
    /// How often the algorithm's branches were taken ([`Counters`]).
    pub counters: Counters,
    /// Counters and phase times of the numerics ([`SolverProfile`]).
    pub profile: SolverProfile,
    /// Sees every recorded state ([`Observer`]).
    pub observer: Option<Box<dyn Observer + 'a>>,
    /// The Newton history of the last equilibrium attempts (with [`SolverOptions::trace`]).
    pub trace: Option<Trace>,
    /// What the next equilibria are solved for ([`super::phases`]).
    pub(super) phase: Phase,
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
        Ok(Solver {
            scales: Scales::of(&model),
            operator: Operator::new(map.n_eq(), opts.factor_updates.in_place(map.n_eq()), opts.fill_refactor)?,
            shifted: None,
            opts,
            state,
            candidates: CandidateList::default(),
            jacobians: JacobianCache::default(),
            counters: Counters::default(),
            profile: SolverProfile::default(),
            observer: None,
            trace: opts.trace.then(Default::default),
            phase: Phase::Other,
            model,
        })
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
        &self.model
    }

    /// The factorization statistics `(numeric factorizations, symbolic analyses)`, the
    /// continuation's own shifted operator's included.
    pub fn factor_stats(&self) -> (usize, usize) {
        let shifted = self.shifted.as_ref().map_or((0, 0), |s| (s.factor.n_factorizations, s.factor.n_symbolic));
        (self.operator.factor.n_factorizations + shifted.0, self.operator.factor.n_symbolic + shifted.1)
    }

    /// Sets the reuse threshold `η` of contact Jacobians ([`super::tangent`]; 0, the default,
    /// recomputes every Jacobian at every Newton iteration). Errors: `η` negative or not finite.
    pub fn set_jacobian_reuse(&mut self, eta: f64) -> Result<(), DemError> {
        super::error::non_negative("jacobian reuse fraction", eta)?;
        self.jacobians.reuse_fraction = eta;
        Ok(())
    }

    /// Finds equilibrium at `load` starting from the current `z` (see [`super::equilibrium`]);
    /// leaves the contacts of the equilibrium state in [`Self::contacts`].
    pub fn equilibrate(&mut self, load: &LoadPoint, t: f64) -> Result<(), DemError> {
        self.equilibrate_with(load, None, t)
    }

    /// Finds equilibrium at `load` plus the extra external forces `extra` (over `z`, e.g. a
    /// broken beam's force being released), starting from the current `z` (Newton's method,
    /// [`super::equilibrium`]); leaves the contacts of the equilibrium state in the state's
    /// `contacts`. Its work is booked to the current phase, or to the cut-backs when it does
    /// not converge ([`super::phases`]).
    pub(super) fn equilibrate_with(&mut self, load: &LoadPoint, extra: Option<&[f64]>, t: f64) -> Result<(), DemError> {
        let (before, clock) = (self.profile.running(), std::time::Instant::now());
        let out = self.newton(load, extra, t);
        let mut w = self.profile.running().since(&before);
        w.equilibria = 1;
        w.seconds = clock.elapsed().as_secs_f64();
        let failed = matches!(out, Err(DemError::NoConvergence { .. }));
        self.profile.phases.book(self.phase, failed, &w);
        out
    }

    /// The operator with what its upkeep reads, and the scales (disjoint borrows of the
    /// solver's parts).
    pub(super) fn operator_upkeep(&mut self) -> (&mut Operator, Upkeep<'_, 'a>, &Scales) {
        let upkeep = Upkeep {
            model: &self.model,
            intact: &self.state.intact,
            opts: &self.opts,
            profile: &mut self.profile,
            event: self.state.broken.len(),
        };
        (&mut self.operator, upkeep, &self.scales)
    }

    /// Refactorizes the operator with the regularization when it is stale.
    pub(super) fn refresh_operator(&mut self) -> Result<(), DemError> {
        let (op, mut u, scales) = self.operator_upkeep();
        op.refresh(&mut u, &scales.reg)
    }
}
