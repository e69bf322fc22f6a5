//! The errors of the FE analyses: each names the stage, the key, the file or the mode it concerns.
//!
//! They live beside the run's [`Error`](super::Error) rather than in `analysis/`, which returns
//! that error: the two modules would otherwise import each other.
use crate::element::ElementError;
use std::path::PathBuf;

/// Why an FE analysis could not produce its result.
#[derive(Debug, thiserror::Error)]
pub enum AnalysisError {
    /// The block Lanczos eigensolver ran out of block solves.
    #[error("modal: block Lanczos did not converge in {solves} block solves ({columns} columns) for {modes} modes")]
    LanczosNoConvergence {
        /// Block solves done (the cap).
        solves: usize,
        /// Columns of the basis.
        columns: usize,
        /// Modes asked for.
        modes: usize,
    },
    /// The model has fewer modes than asked for.
    #[error("modal: only {exist} of the {asked} modes exist: the problem has {with_mass} DOF with mass")]
    TooFewModes {
        /// Modes that exist.
        exist: usize,
        /// Modes asked for.
        asked: usize,
        /// DOFs with mass.
        with_mass: usize,
    },
    /// A target of the modal updating has no converged mode.
    #[error("modal updating: only {converged} mode(s) converged, but mode {mode} is a target")]
    TargetNotConverged {
        /// Converged modes.
        converged: usize,
        /// The target mode (1-based).
        mode: usize,
    },
    /// A target of the modal updating has no computed shape to pair with.
    #[error("modal updating: target mode {mode} has no computed shape to pair with ({computed} mode(s))")]
    TargetWithoutShape {
        /// The target mode (1-based).
        mode: usize,
        /// Modes computed.
        computed: usize,
    },
    /// The target shapes file cannot be read or does not fit the mesh.
    #[error("target shapes {}: {reason}", file.display())]
    TargetShapes {
        /// The HDF5 file.
        file: PathBuf,
        /// What is wrong (with the dataset's name).
        reason: String,
    },
    /// A monitor or a storey drift of `[dynamics]` cannot be placed on the model.
    #[error("{key}: {reason}")]
    Placement {
        /// The key and its name (`dynamics.monitor[0] ('top')`).
        key: String,
        /// What is wrong.
        reason: String,
    },
    /// A time history without `[dynamics]`.
    #[error("a time history needs [dynamics]")]
    NoDynamics,
    /// A step of a time history did not converge, even with substeps; the diagnosis says where
    /// the residual is largest, which elements changed state and where the state is saved.
    #[error("{diagnosis}")]
    StepFailed {
        /// The step that failed (1-based).
        step: usize,
        /// The whole diagnosis.
        diagnosis: String,
    },
    /// Gravity could not be applied in full.
    #[error("{diagnosis}")]
    GravityFailed {
        /// The load factor of the last equilibrium.
        lambda: f64,
        /// The whole diagnosis.
        diagnosis: String,
    },
    /// A stage of a nonlinear static analysis stopped before its end.
    #[error(
        "static_nonlinear: stage '{stage}' stopped at {at:.6} of the stage: {reason}; results up to the last converged increment are in {results}"
    )]
    StageStopped {
        /// The stage's name.
        stage: String,
        /// How far it got (fraction of the stage).
        at: f64,
        /// Why it stopped.
        reason: String,
        /// The results file.
        results: String,
    },
    /// A checkpoint file cannot be read or written.
    #[error("checkpoint {}: {reason}", file.display())]
    Checkpoint {
        /// The file or folder.
        file: PathBuf,
        /// What is wrong.
        reason: String,
    },
    /// An element's state cannot be saved into a checkpoint.
    #[error("checkpoint: {kind} state: {source}")]
    SaveState {
        /// The element kind.
        kind: &'static str,
        /// The element's error.
        source: ElementError,
    },
    /// A checkpoint's element state does not fit the element.
    #[error("the checkpoint's {kind} state ({values} values): {source}")]
    LoadState {
        /// The element kind.
        kind: &'static str,
        /// The values in the checkpoint.
        values: usize,
        /// The element's error.
        source: ElementError,
    },
    /// A checkpoint of another model.
    #[error(
        "the checkpoint holds {dofs} DOFs and {elements} elements on rank {rank}, the model {model_dofs} and {model_elements}: was the mesh or the job changed?"
    )]
    CheckpointMismatch {
        /// DOFs in the checkpoint.
        dofs: usize,
        /// Elements in the checkpoint.
        elements: usize,
        /// The rank.
        rank: usize,
        /// DOFs of the model.
        model_dofs: usize,
        /// Elements of the model.
        model_elements: usize,
    },
    /// A restarted assessment cannot read the stages of its first run.
    #[error("--restart needs {} from the first run of this job (the updated moduli): {source}", file.display())]
    StagesMissing {
        /// The stages file.
        file: PathBuf,
        /// The operating system's error.
        source: std::io::Error,
    },
    /// The stages file is not one, or belongs to another job.
    #[error("{}: {reason}", file.display())]
    StagesInvalid {
        /// The stages file.
        file: PathBuf,
        /// What is wrong.
        reason: String,
    },
    /// The stages file of another job.
    #[error(
        "{name} lists the moduli of other parts than the job's {parts} (was the job changed since the first run?)"
    )]
    StagesOfOtherParts {
        /// The stages file's name.
        name: &'static str,
        /// The job's parts.
        parts: usize,
    },
    /// The overlay curve of a nonlinear static chart cannot be read.
    #[error("overlay curve {}: {reason}", file.display())]
    OverlayCurve {
        /// The CSV file.
        file: PathBuf,
        /// What is wrong.
        reason: String,
    },
    /// The dense test system was solved before it was factorized.
    #[error("solve before prepare")]
    NotPrepared,
    /// The dense test system's Jacobian is singular.
    #[error("singular dense Jacobian")]
    SingularJacobian,
    /// An error that every rank had was lost while the ranks agreed on it.
    #[error("internal error: an error was lost in agreement")]
    LostInAgreement,
}
