//! The finite-element analyses and their machinery. Each analysis reads as phases — setup,
//! assemble, solve, check, output — and takes what it needs (context, job, mesh, model) as
//! arguments. The job drivers that use no FE machinery (the DEM lab, the identification, the
//! spectrum and the material point) are in [`crate::run`], beside the dispatch.
pub mod assembly;
pub mod assessment;
pub mod block_lanczos;
pub mod convergence_rate;
pub mod curve_plot;
mod discretization;
pub mod increment;
pub mod line_search;
pub mod linear_static;
pub mod modal;
pub mod modal_updating;
mod mode_pairing;
mod model_mass;
pub mod newton;
mod nonlinear_system;
pub mod nonlocal;
pub mod output;
mod problem;
mod rigid_modes;
pub mod static_nonlinear;
pub mod time_history;

pub use discretization::{default_orientation, Discretization};
pub use model_mass::ModelMass;
pub use problem::FeProblem;
pub use rigid_modes::rigid_body_modes;
