//! The quasi-static, incremental, event-driven DEM solver (paper §2.1, "Solution algorithm") and
//! the virtual tests built on it.
//!
//! | file | concept |
//! |---|---|
//! | `solver.rs` | the solver of one test: the owner of the problem, the state, the workspace and the diagnostics, whose entry points hand them to the step pipeline; the pipeline's shape: free functions `(pb: &Problem, state: &mut SolverState, ws: &mut Workspace, diag: &mut Diagnostics, …)` in the files below |
//! | `problem.rs`, `workspace.rs`, `diagnostics.rs` | the parts the pipeline works on: the model, options and scales (fixed); the operator, candidates and Jacobians (rebuilt from the state); counters, profile, trace, observer and phase (read after the run) |
//! | `state.rs` | the mechanical state (coordinates, intact beams, contacts and histories, load, energy, records): cloned, it continues in a new solver |
//! | `options.rs`, `records.rs`, `scales.rs` | the options (among them how the factor follows breaks: in place from 1,000 unknowns, `FactorUpdates`); what is recorded (load points, states, breaks, the observer); the sample's fixed scales |
//! | `stage.rs`, `walk.rs` | the stage loop, the top of the pipeline: load steps, cut-backs, snaps, contact events (the algorithm's module docs); where a stage's walk over its load stands |
//! | `breaks.rs` | one beam break per equilibrium: its closed-form crossing λ, the most critical beam, the release of a broken beam's force; the opt-in approximation of several breaks per equilibrium |
//! | `break_search.rs`, `break_search_tests.rs` | optional (`SolverOptions::break_search`): a load step's first break predicted by one tangent solve and landed on `P = 1` by secant passes on the equilibrium path, one equilibrium per break instead of the step's end and the break's load; tested against the trial path and the 1k reference |
//! | `linear.rs` | the linear phase: where no contact is active, Newton's first step is the equilibrium, taken without the residual that would confirm it |
//! | `equilibrium.rs` | an equilibrium, booked to its phase: Newton on the consistent contact–friction tangent, converged at `tol` times the state's largest force (floored by a tenth of the test's largest platen force so far and the contact law's round-off), with line search and a step cap |
//! | `evaluation.rs` | a residual evaluation at a state: its contacts, the residual and its measures, the beams' forces |
//! | `operator.rs` | the factorized operator: beams, contact terms, regularization; Woodbury updates and when to refactorize |
//! | `dofs.rs`, `system.rs` | the unknowns (stones, platens as master DOFs) and the assembled model |
//! | `factor.rs` | faer sparse Cholesky (symbolic analysis reused) with sparse Woodbury columns solved in batches; a flop cost model refactorizes once the correction has cost more than a factorization |
//! | `cholmod.rs` | CHOLMOD's simplicial `LDLᵀ` with multiple-rank update/downdate in place (`cholmod_updown`) and solves of sparse right-hand sides (forward substitution over their reach), bound through bindgen (`cholmod_sys.rs`, `build.rs`) |
//! | `supernodes.rs` | a supernodal copy of CHOLMOD's simplicial factor (relaxed chains of the elimination tree as dense blocks, values in `f32`): GMRES's preconditioner solves with it while the factor stays unchanged, from about 5,000 stones |
//! | `ordering.rs` | METIS nested dissection from 20k unknowns, AMD below |
//! | `tangent.rs` | per-contact exact Jacobians (dual numbers through the contact law, `mechanics::contact_jacobian`; `jacobian_tests.rs` checks them against central differences); GMRES products through `TangentDifference` (contacts only: the beams cancel); a direct sparse LU where GMRES misses its tolerance |
//! | `gmres.rs` | GMRES preconditioned by the factorized symmetric operator; Eisenstat–Walker forcing |
//! | `slip_terms.rs` | how much of a contact's `k_t c cᵀ` the factorized operator holds, stick or slip, and when a stick/slip flip reaches it (a lagged update or downdate of the factor) |
//! | `contact_set.rs`, `contact_candidates.rs` | contact pairs and their histories (committed chord, plastic depth of crushing); candidates kept between residual evaluations with a margin, exactly the contacts of a search from scratch |
//! | `energy.rs` | the energy account: commits, the trial step's balance (with crushing, a step whose energy does not balance within 1e-3 of the work is halved) |
//! | `continuation.rs` | the fallback where Newton fails at the smallest increment: pseudo-transient continuation (K_T + σ diag K₀) Δz = r, kept only downhill; the state is recorded as `Relaxed` |
//! | `step_predictor.rs` | the load step after a break starts from the response of the step that was cut (never with crushing) |
//! | `contact_events.rs` | optional (`SolverOptions::contact_events`): a load step ends where a contact starts to slide, closes or opens |
//! | `checkpoint.rs` | a test's checkpoint: the state, the stage walk and the counters (and how a finished test ended), asked for by a sink after each load step; the file: versioned, fingerprinted (sample, mechanics, test), checksummed, written atomically; a resumed test continues from it |
//! | `virtual_test.rs`, `test_run.rs` | tension, compression, shear and cyclic tests (their protocols); running one: ends as target, loss of load, collapse or failed, with checkpoints or from one |
//! | `snapshots.rs`, `trace.rs`, `profile.rs`, `phases.rs` | states kept for output (an observer), the Newton history of the last attempts (each iteration's record read off its residual evaluation), counters and phase times, the equilibria's work by what they were solved for (trial, λ*, release, cascade, cut-back) |
#[cfg(test)]
mod break_group_tests;
mod break_search;
#[cfg(test)]
mod break_search_tests;
mod breaks;
pub mod checkpoint;
pub mod cholmod;
mod cholmod_sys;
pub mod contact_candidates;
mod contact_events;
pub mod contact_set;
mod continuation;
#[cfg(test)]
mod crushing_tests;
#[cfg(test)]
mod cyclic_tests;
pub mod diagnostics;
pub mod dofs;
pub mod energy;
mod equilibrium;
pub mod error;
mod evaluation;
pub mod factor;
pub mod gmres;
#[cfg(test)]
mod jacobian_tests;
mod linear;
mod operator;
pub mod options;
pub mod ordering;
pub mod phases;
mod problem;
pub mod profile;
pub mod records;
pub mod scales;
pub mod slip_terms;
pub mod snapshots;
#[allow(clippy::module_inception)]
pub mod solver;
#[cfg(test)]
mod speed_tests;
mod stage;
pub mod state;
mod step_predictor;
pub mod supernodes;
pub mod system;
pub mod tangent;
pub mod test_result;
pub mod test_run;
#[cfg(test)]
mod tests;
pub mod trace;
pub mod virtual_test;
mod walk;
mod workspace;

pub use checkpoint::{CheckpointSink, Fingerprint, TestCheckpoint};
pub use diagnostics::Diagnostics;
pub use dofs::{DofControl, DofMap, PlatenControl};
pub use error::DemError;
pub use factor::LowRankCholesky;
pub use options::{BreakSearch, FactorUpdates, FloatingPolicy, SlipTerms, SolverOptions};
pub use profile::{BreakSearchCounts, Counters, SolverProfile};
pub use records::{BrokenBeam, FailureModeTag, LoadPoint, Observer, StageEnd, StateKind, StateRecord};
pub use snapshots::{ParticleState, ParticleStates};
pub use solver::Solver;
pub use state::SolverState;
pub use system::Model;
pub use test_result::{CurvePoint, Derived, RunStats, TestEnd, TestResult};
pub use test_run::{
    finished_result, run_test, run_test_checkpointed, run_test_observed, run_test_recording, run_test_with,
    Checkpoints, Report, TestRun,
};
pub use virtual_test::{cyclic_protocol, PlatenRotation, VirtualTest};
