//! Seismic time history: gravity as a static step, then the base acceleration integrated
//! implicitly (Newmark or HHT-α) in the relative formulation
//!
//! ```text
//!   M ü + C u̇ + f_int(u) = f_static − M Σ_d ι_d a_g,d(t)
//! ```
//!
//! (u relative to the moving base, ι_d the unit translation along d at every free DOF).
//!
//! | file               | concept                                                          |
//! |--------------------|------------------------------------------------------------------|
//! | `scheme.rs`        | Newmark β, γ and HHT α: the kinematic updates and the Jacobian    |
//! | `damping.rs`       | Rayleigh damping from two frequencies and a ratio, or α and β    |
//! | `ground.rs`        | `a_g(t)` of up to three records; ground velocity and displacement |
//! | `system.rs`        | the [`DynamicSystem`] trait and a dense implementation            |
//! | `state.rs`         | the state after a converged step; the external force `f(t)`      |
//! | `stepper.rs`       | one step: Newton (tangent, modified, initial, krylov), substepping |
//! |                    | on Newton failures and on damage increments over the limit; with  |
//! |                    | IMPL-EX, each attempt at the extrapolated damage; a line search   |
//! | `trial.rs`         | a step's trial vectors and residual; a point along a correction   |
//! | `substeps.rs`      | the substeps of a step: sizes dt/2^k on the step's dyadic grid    |
//! | `krylov.rs`        | Krylov subspace acceleration of modified Newton (Carlson–Miller)  |
//! | `linear_step.rs`   | the step of a linear system: one solve, two products              |
//! | `refresh.rs`       | when Krylov–Newton forms the tangent again: a cost in iterations |
//! | `energy.rs`        | the energy balance                                                |
//! | `petsc_system.rs`  | [`PetscSystem`]: the distributed model (PETSc matrices, KSP reuse) |
//! | `gravity.rs`       | the static gravity step the earthquake starts from               |
//! | `gravity_failure.rs` | the diagnosis of a gravity step the model cannot carry         |
//! | `checkpoint.rs`    | atomic checkpoints and `--restart`                               |
//! | `diagnosis.rs`     | where a failed step is out of balance, which elements changed     |
//! | `monitor.rs`       | monitored nodes to CSV and PNG                                   |
//! | `base_shear.rs`    | the base reactions (base shear) per step                         |
//! | `drift.rs`         | storey drifts between two levels per step                        |
//! | `step_output.rs`   | results every k steps, CSV rows every step, envelopes at the end  |
//! | `envelope.rs`      | peak displacement, drift and damage                              |
//! | `damage_shares.rs` | per substructure, the area shares with damage above 0.05 and 0.5 |
//! | `progress.rs`      | progress lines with ETA on rank 0                                |
//! | `summary.rs`       | what a run reports in `summary.json`                             |
//! | `integration.rs`   | what the stepping loop reads: settings, job, mesh, model, ground  |
//! | `driver.rs`        | the `time_history` job, its starts (gravity, restart, a saved gravity state) and the reusable stepping loop |
#[cfg(test)]
mod bar_tests;
mod base_shear;
mod checkpoint;
#[cfg(test)]
mod cube_root_spring;
#[cfg(test)]
mod damage_control_tests;
mod damage_shares;
mod damping;
mod diagnosis;
mod drift;
mod driver;
mod energy;
mod envelope;
mod gravity;
mod gravity_failure;
mod ground;
#[cfg(test)]
mod implex_tests;
mod integration;
mod krylov;
#[cfg(test)]
mod line_search_tests;
mod linear_step;
mod monitor;
mod petsc_system;
mod progress;
mod refresh;
mod scheme;
mod state;
mod step_output;
mod stepper;
mod substeps;
mod summary;
mod system;
#[cfg(test)]
mod tests;
mod trial;

pub use checkpoint::Checkpoint;
pub use damage_shares::GroupDamage;
pub use damping::Rayleigh;
pub use driver::{ground_motion, integrate, run, save_gravity, Start, StepObserver, TimeHistorySummary};
pub use energy::EnergyBalance;
pub use envelope::Envelopes;
pub use gravity::{solve_gravity, GravityFailure, GravitySettings};
pub use ground::GroundMotion;
pub use integration::Integration;
pub use petsc_system::PetscSystem;
pub use scheme::Scheme;
pub use stepper::{external_force, State, StepFailure, StepReport, StepSettings, Stepper};
pub use system::{DenseSystem, DynamicSystem};
