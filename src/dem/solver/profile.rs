//! Where an event-driven DEM run spends its time: counters and phase timers of the equilibrium
//! iterations and the linear solver, filled as the solver runs (a few `Instant::now()` per
//! Newton iteration; negligible against the work they time).
//!
//! Read it after a run ([`super::Diagnostics::profile`]); `examples/dem_profile.rs` prints it as JSON
//! for a compression test of a random sample.
use std::time::Duration;

use super::phases::{PhaseCounts, Phases};

/// Counters and phase times of one solver.
#[derive(Clone, Debug, Default, PartialEq, serde::Serialize)]
pub struct SolverProfile {
    /// Newton iterations (linear solves of the tangent).
    pub newton_iterations: usize,
    /// Iterations of pseudo-transient continuations (`super::continuation`).
    pub continuation_iterations: usize,
    /// Equilibria found by one solve without contacts ([`super::linear`]).
    pub linear_solves: usize,
    /// Such solves that met a contact at their result and went back to Newton's method.
    pub linear_fallbacks: usize,
    /// Scans of the intact beams' failure indices (`failure_seconds`).
    pub failure_scans: usize,
    /// Contact-free Newton steps solved with a sparse right-hand side (`super::factor`,
    /// "Sparse right-hand sides").
    pub sparse_solves: usize,
    /// Supernodal copies of the factor made for GMRES's preconditioner
    /// ([`super::SolverOptions::preconditioner_copy_from`]).
    pub preconditioner_copies: usize,
    /// The columns of `L` their forward substitutions visited, summed.
    pub sparse_columns: usize,
    /// Newton iterations that needed GMRES (some contact active).
    pub gmres_solves: usize,
    /// GMRES products (each one preconditioner solve).
    pub gmres_iterations: usize,
    /// Newton steps solved directly (sparse LU of the assembled tangent) after GMRES missed
    /// its tolerance.
    pub direct_solves: usize,
    /// Residual evaluations (contact detection + forces), line search included.
    pub evaluations: usize,
    /// Pairs given to the contact law in residual evaluations ([`super::contact_candidates`]).
    pub pair_evaluations: usize,
    /// Candidate lists built ([`super::contact_candidates`]).
    pub candidate_rebuilds: usize,
    /// Contact Jacobians computed ([`super::tangent`]).
    pub jacobians_computed: usize,
    /// Contact Jacobians reused ([`super::tangent`]).
    pub jacobians_reused: usize,
    /// Contact Jacobians taken on the slip branch for contacts on the Coulomb cone
    /// ([`super::tangent`], "On the cone").
    pub jacobians_on_cone: usize,
    /// Load steps after a break started from the cut step's response
    /// ([`super::step_predictor`]) and converged from there.
    pub predicted_steps: usize,
    /// Load steps whose predicted start failed and that were solved again from the plain start.
    pub predictor_fallbacks: usize,
    /// Woodbury columns added (each one base solve).
    pub columns_added: usize,
    /// Woodbury columns dropped because their term left the operator before a refactorization
    /// (no solve).
    pub columns_dropped: usize,
    /// Contact terms that entered / left the operator: normal in, normal out, tangential in,
    /// tangential out (the contact-set churn the Woodbury columns pay for; with
    /// `SolverOptions::slip_terms` following the regimes, every stick↔slip flip that reaches
    /// the operator counts here, out and in).
    pub operator_changes: [usize; 4],
    /// Stick↔slip flips that reached the operator, and flips that turned back before their lag
    /// was over ([`super::slip_terms`]; zero with [`super::SlipTerms::FULL`]).
    pub slip_flips: [usize; 2],
    /// Largest Woodbury rank reached.
    pub max_rank: usize,
    /// Contact terms of the operator replaced because they drifted
    /// ([`super::SolverOptions::refresh_drift`]).
    pub refreshed_terms: usize,
    /// With updates in place: the entries of `L` after the last factorization and now (the fill
    /// that updates brought, [`super::factor::FILL_REFACTOR_FACTOR`]).
    pub factor_entries: [usize; 2],
    /// Numeric factorizations, by cause: the cost model, the rank cap, an inaccurate
    /// capacitance matrix or GMRES failure, a floating stone, the first one.
    pub refactorizations: Refactorizations,
    /// Seconds in numeric (and symbolic) factorizations.
    pub factor_seconds: f64,
    /// Seconds computing Woodbury columns (base solves of new terms, capacitance update).
    pub columns_seconds: f64,
    /// Seconds in preconditioner / direct solves.
    pub solve_seconds: f64,
    /// Seconds in GMRES outside the preconditioner (tangent products, orthogonalization).
    pub gmres_seconds: f64,
    /// Seconds building the contact tangent (the contacts' Jacobians).
    pub tangent_seconds: f64,
    /// Seconds in residual evaluations (contacts, forces).
    pub evaluate_seconds: f64,
    /// Seconds scanning the intact beams' failure indices (the crossing λ along a step, the
    /// most critical beam after a break).
    pub failure_seconds: f64,
    /// Seconds committing and recording states (platen forces, stored energy, the record).
    pub commit_seconds: f64,
    /// The sliding contacts at the Newton steps that needed GMRES, summed.
    pub sliding_at_gmres: usize,
    /// The active contacts at those steps, summed.
    pub contacts_at_gmres: usize,
    /// The work of the equilibria by phase ([`super::phases`]).
    pub phases: Phases,
    /// What the break search did ([`super::break_search`]; zero with
    /// [`super::BreakSearch::Trial`]).
    pub break_search: BreakSearchCounts,
}

/// The counters of the break search ([`super::break_search`]).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, serde::Serialize)]
pub struct BreakSearchCounts {
    /// Tangent solves predicting a load step's first break.
    pub predictor_solves: usize,
    /// Steps whose prediction found no break inside the step (taken as trial steps).
    pub no_break: usize,
    /// Steps that landed on a break: the equilibrium where the first beam reaches `P = 1`.
    pub landed: usize,
    /// Equilibria solved at a predicted or corrected `λ*` (at least one per landing).
    pub equilibria: usize,
    /// Of those, the ones past the threshold: cut back.
    pub cut_backs: usize,
    /// Of those, the ones short of it: carried further.
    pub short: usize,
    /// Searches given up (no equilibrium at a `λ*`, no crossing inside the step on a second
    /// look, or no landing in the passes allowed): the step is taken as a trial step.
    pub given_up: usize,
}

impl SolverProfile {
    /// The running totals that [`super::phases`] books per equilibrium (`equilibria` and
    /// `seconds` left at zero).
    pub fn running(&self) -> PhaseCounts {
        PhaseCounts {
            equilibria: 0,
            newton_iterations: self.newton_iterations,
            gmres_solves: self.gmres_solves,
            gmres_iterations: self.gmres_iterations,
            sliding: self.sliding_at_gmres,
            contacts: self.contacts_at_gmres,
            jacobians: self.jacobians_computed,
            evaluations: self.evaluations,
            jacobian_seconds: self.tangent_seconds,
            evaluate_seconds: self.evaluate_seconds,
            seconds: 0.0,
        }
    }
}

/// How often the stage loop took each of its branches ([`super::stage`]).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, serde::Serialize, serde::Deserialize)]
pub struct Counters {
    /// Linear solves with the factorized operator (GMRES preconditioner applications included).
    pub solves: usize,
    /// Load-increment cut-backs (halvings of a load step or of a beam's release).
    pub cutbacks: usize,
    /// Load steps ended at a contact event.
    pub contact_events: usize,
    /// Pseudo-transient continuations run ([`super::continuation`]).
    pub continuations: usize,
    /// Load steps whose equilibrium was found by continuation, or left as a snap (the stage
    /// module's "Continuation" and "Snaps inside a step").
    pub continued_steps: usize,
    /// Load steps halved because their energy did not balance (counted in `cutbacks` too).
    pub imbalance_cutbacks: usize,
    /// Such steps left at the smallest increment and recorded as snaps.
    pub snaps_in_steps: usize,
}

/// Numeric factorizations by cause.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, serde::Serialize)]
pub struct Refactorizations {
    /// The first factorization of the run.
    pub initial: usize,
    /// The accumulated Woodbury columns, or the fill of updates in place, cost more than a
    /// factorization ([`super::factor`]).
    pub cost_model: usize,
    /// The Woodbury rank would pass `max_rank`.
    pub rank_cap: usize,
    /// Ill-conditioned capacitance matrix, or GMRES did not converge with the correction.
    pub accuracy: usize,
    /// A stone lost every bond and contact.
    pub floating: usize,
    /// The shifted operator of a pseudo-transient continuation, or the return from it
    /// (`super::continuation`).
    pub continuation: usize,
}

impl Refactorizations {
    /// All of them.
    pub fn total(&self) -> usize {
        self.initial + self.cost_model + self.rank_cap + self.accuracy + self.floating + self.continuation
    }
}

/// Adds the seconds of `d` to `acc`.
pub(super) fn add(acc: &mut f64, d: Duration) {
    *acc += d.as_secs_f64();
}
