//! The quasi-static, incremental, event-driven DEM solver (SPEC §1, "Solution algorithm") and
//! the virtual tests built on it.
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
pub mod gmres;
pub mod ordering;
pub mod profile;
pub mod tangent;
pub mod trace;
pub mod events;
pub mod system;

pub use events::{
    BrokenBeam, FailureModeTag, FloatingPolicy, LoadPoint, Solver, SolverOptions, StageEnd, StateKind, StateRecord,
};
pub use profile::SolverProfile;
pub use system::Model;
pub mod snapshots;
mod step_predictor;
pub mod virtual_test;
#[cfg(test)]
mod crushing_tests;
#[cfg(test)]
mod cyclic_tests;
#[cfg(test)]
mod speed_tests;
#[cfg(test)]
mod tests;

pub use snapshots::{ParticleState, ParticleStates};
pub use virtual_test::{
    cyclic_protocol, run_test, run_test_recording, run_test_with, CurvePoint, Derived, PlatenRotation, RunStats, TestEnd,
    TestResult, VirtualTest,
};
