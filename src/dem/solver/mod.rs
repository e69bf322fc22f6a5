//! The quasi-static, incremental, event-driven DEM solver (SPEC §1, "Solution algorithm") and
//! the virtual tests built on it.
pub mod dofs;
pub mod error;
pub mod factor;

pub use dofs::{DofControl, DofMap, PlatenControl};
pub use error::DemError;
pub use factor::LowRankCholesky;
