//! The quasi-static, incremental, event-driven DEM solver (SPEC §1, "Solution algorithm") and
//! the virtual tests built on it.
//!
//! | file | concept |
//! |---|---|
//! | `dofs.rs`, `system.rs` | the unknowns (stones, platens as master DOFs) and the assembled model |
//! | `factor.rs` | faer sparse Cholesky (symbolic analysis reused) with sparse Woodbury columns solved in batches; a flop cost model refactorizes once the correction has cost more than a factorization; a contact term that leaves before it is dropped from the correction |
//! | `ordering.rs` | METIS nested dissection from 20k unknowns, AMD below |
//! | `events.rs` | the event loop: load steps, one beam break per equilibrium (its closed-form crossing λ), cut-backs of load steps and beam releases |
//! | `equilibrium.rs` | Newton on the consistent contact–friction tangent, converged at `tol` times the state's largest force (floored by a tenth of the test's largest platen force so far and the contact law's round-off), with line search and a step cap |
//! | `tangent.rs` | per-contact central-difference Jacobians, reused while a contact moved less than 1 % of its penetration in the same stick/slip regime; GMRES products through `TangentDifference` (contacts only: the beams cancel); a direct sparse LU where GMRES misses its tolerance |
//! | `gmres.rs` | GMRES preconditioned by the factorized symmetric operator (every contact keeps `k_t c cᵀ` in it, stick or slip, so stick/slip changes never touch the factorization); Eisenstat–Walker forcing |
//! | `contact_set.rs`, `contact_candidates.rs` | contact pairs and their histories (committed chord, plastic depth of crushing); candidates kept between residual evaluations with a margin, exactly the contacts of a search from scratch |
//! | `energy.rs` | the energy account: recorded states, the trial step's balance (with crushing, a step whose energy does not balance within 1e-3 of the work is halved) |
//! | `continuation.rs` | the fallback where Newton fails at the smallest increment: pseudo-transient continuation (K_T + σ diag K₀) Δz = r, kept only downhill; the state is recorded as `Relaxed` |
//! | `step_predictor.rs` | the load step after a break starts from the response of the step that was cut (never with crushing) |
//! | `contact_events.rs` | optional (`SolverOptions::contact_events`): a load step ends where a contact starts to slide, closes or opens |
//! | `virtual_test.rs` | tension, compression, shear and cyclic tests; ends as target, loss of load, collapse or failed |
//! | `snapshots.rs`, `trace.rs`, `profile.rs` | states kept for output (an observer on commit), the Newton history of the last attempts, counters and phase times |
pub mod dofs;
pub mod error;
pub mod factor;

pub use dofs::{DofControl, DofMap, PlatenControl};
pub use error::DemError;
pub use factor::LowRankCholesky;
pub mod contact_candidates;
mod contact_events;
pub mod contact_set;
mod continuation;
mod energy;
mod equilibrium;
pub mod events;
pub mod gmres;
pub mod ordering;
pub mod profile;
pub mod system;
pub mod tangent;
pub mod trace;

pub use events::{
    BrokenBeam, FailureModeTag, FloatingPolicy, LoadPoint, Solver, SolverOptions, StageEnd, StateKind, StateRecord,
};
pub use profile::SolverProfile;
pub use system::Model;
#[cfg(test)]
mod crushing_tests;
#[cfg(test)]
mod cyclic_tests;
pub mod snapshots;
#[cfg(test)]
mod speed_tests;
mod step_predictor;
#[cfg(test)]
mod tests;
pub mod virtual_test;

pub use snapshots::{ParticleState, ParticleStates};
pub use virtual_test::{
    cyclic_protocol, run_test, run_test_recording, run_test_with, CurvePoint, Derived, PlatenRotation, RunStats,
    TestEnd, TestResult, VirtualTest,
};
