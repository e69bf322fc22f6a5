//! Analysis drivers. Each reads as phases — setup, assemble, solve, check, output — each timed,
//! and takes what it needs (context, job, mesh, model) as arguments.
pub mod assembly;
pub mod assessment;
pub mod curve_plot;
pub mod dem;
pub mod identify;
pub mod increment;
mod discretization;
pub mod line_search;
pub mod linear_static;
pub mod material_point;
pub mod modal;
pub mod modal_updating;
pub mod newton;
pub mod nonlocal;
pub mod output;
pub mod spectrum;
pub mod static_nonlinear;
pub mod time_history;
mod rigid_modes;

pub use discretization::{default_orientation, Discretization};
pub use rigid_modes::rigid_body_modes;
