//! What the stepping loop of a time history reads besides the system and the state: the
//! settings, the job, the mesh, the model, the ground motion and the results' name.
use super::ground::GroundMotion;
use crate::config::{DynamicsConfig, Job};
use crate::mesh::Mesh;
use crate::model::StructuralModel;

/// The time history's results: `<stem>.h5` and `<stem>.xdmf` (a restart adds
/// `<stem>-restart-<step>.h5`, listed in the same index).
pub(super) const RESULTS_STEM: &str = "results";

/// Everything the stepping loop needs besides the system and the state (with the envelopes
/// saved in a checkpoint, if continuing one: node and cell values).
pub struct Integration<'a> {
    /// Settings.
    pub cfg: &'a DynamicsConfig,
    /// The job (output folder, parts).
    pub job: &'a Job,
    /// Mesh.
    pub mesh: &'a Mesh,
    /// Model.
    pub model: &'a StructuralModel,
    /// Ground motion.
    pub ground: &'a GroundMotion,
    /// Results file stem.
    pub stem: String,
    /// True when continuing from a checkpoint.
    pub restart: bool,
}

/// Envelopes read from a checkpoint: node values, cell values (see [`super::envelope::Envelopes`]).
pub type SavedEnvelopes = (Vec<f64>, Vec<f64>);
