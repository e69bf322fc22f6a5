//! The structural model: which mesh cells are which elements, with which section and material,
//! what is fixed and what is loaded. Built identically on every rank from the job and the mesh;
//! the element objects themselves (with their integration-point state) are created only by the
//! rank that owns each cell (see [`crate::analysis`]).
mod build;
pub mod plausible;
mod rigid_pieces;
mod stability;
mod ties;

pub use build::{ControlSpec, ModelCell, ModelError, StructuralModel};
pub use stability::{find_mechanisms, find_mechanisms_with_ties, Mechanism};
