//! The error of a whole run: one enum over the modules' typed errors, with the exit code each
//! calls for (2: bad input; 1: the computation failed; 70: an internal error).
//!
//! Each layer has its own error enum (`ConfigError`, `MshError`, `MaterialError`,
//! `ElementError`, `DemError`, `IdentifyError`, `SeismicError`, `IoError`, ...); they compose here
//! with `#[from]`. The FE analyses' [`AnalysisError`] and the job drivers' [`JobError`] live in
//! this module, as `analysis/` and `run/` return [`Error`] and sit at or above its layer.
mod analysis;
mod job;

pub use analysis::AnalysisError;
pub use job::JobError;

use crate::config::{ConfigError, FileError};
use crate::element::ElementError;
use crate::identify::IdentifyError;
use crate::io::IoError;
use crate::mesh::MshError;
use crate::model::ModelError;
use crate::parallel::Agreed;
use crate::parallel::{BatchError, PartitionError};
use crate::petsc::{PetscError, SolverError};
use crate::plot::PlotError;
use crate::seismic::SeismicError;

/// Anything that stops a run.
#[derive(Debug, thiserror::Error)]
pub enum Error {
    /// The job file.
    #[error(transparent)]
    Config(#[from] ConfigError),
    /// A file the job refers to, found unusable after the job was read.
    #[error(transparent)]
    File(#[from] FileError),
    /// The mesh file.
    #[error(transparent)]
    Mesh(#[from] MshError),
    /// The job against the mesh.
    #[error(transparent)]
    Model(#[from] ModelError),
    /// The model cannot carry load: `piece` can move as a rigid body, one of `pieces` such
    /// pieces (found alike by every rank).
    #[error("{piece}{}", if *.pieces > 1 { format!(" ({} such pieces in all)", .pieces) } else { String::new() })]
    Mechanism {
        /// The first piece found.
        piece: crate::model::Mechanism,
        /// How many pieces are free.
        pieces: usize,
    },
    /// The stiffness could not be factored by Cholesky: K is singular or not positive definite
    /// (a mechanism the supports leave, or a negative stiffness).
    #[error(
        "modal: the Cholesky factorization of the stiffness failed ({0}): K is singular or not positive \
         definite; check the supports"
    )]
    SingularStiffness(SolverError),
    /// METIS.
    #[error(transparent)]
    Partition(#[from] PartitionError),
    /// An element could not be built or evaluated.
    #[error("element {tag} (group '{group}'): {source}")]
    Element {
        /// Gmsh element tag.
        tag: u64,
        /// Its physical group.
        group: String,
        /// The cause.
        source: ElementError,
    },
    /// An element cannot be built from its input (a warped quadrangle, a damage law that does
    /// not fit the element size, ...).
    #[error("element {tag} (group '{group}'): {message}")]
    ElementInput {
        /// Gmsh element tag.
        tag: u64,
        /// Its physical group.
        group: String,
        /// What is wrong.
        message: String,
    },
    /// A PETSc call failed.
    #[error(transparent)]
    Petsc(#[from] PetscError),
    /// A linear solve did not converge.
    #[error(transparent)]
    Solver(#[from] SolverError),
    /// Results output.
    #[error(transparent)]
    Io(#[from] IoError),
    /// The results folder.
    #[error("results folder {}: {source}", path.display())]
    OutputDir {
        /// The folder.
        path: std::path::PathBuf,
        /// The cause.
        source: std::io::Error,
    },
    /// A previous run's results are in the way and the job says not to touch them.
    #[error("results folder {} already holds results of a previous run, and [output] existing = \"error\"; \
             move them away or set existing = \"backup\" or \"overwrite\"", .0.display())]
    OutputExists(std::path::PathBuf),
    /// A material-point path could not be built, or the law could not follow it; `reached` steps
    /// of it are kept in `curve` when it stopped on the way.
    #[error("material point: {source}{}", .reached.as_ref().map_or(String::new(), |(n, f)| format!("; the {n} step(s) reached are in {}", f.display())))]
    MaterialPoint {
        /// What stopped it.
        source: crate::material::PathError,
        /// The steps reached and the file that keeps them.
        reached: Option<(usize, std::path::PathBuf)>,
    },
    /// A material point's chart could not be drawn.
    #[error("material point: {0}")]
    MaterialPointChart(PlotError),
    /// An FE analysis could not produce its result (too few converged modes, a step that did
    /// not converge, ...).
    #[error(transparent)]
    Analysis(#[from] AnalysisError),
    /// A job's driver (DEM batch, identification, sweep, record set).
    #[error(transparent)]
    Job(#[from] JobError),
    /// An identification.
    #[error(transparent)]
    Identify(#[from] IdentifyError),
    /// Ground motions and response spectra.
    #[error(transparent)]
    Seismic(#[from] SeismicError),
    /// A chart.
    #[error(transparent)]
    Plot(#[from] PlotError),
    /// The batch machinery (a result that could not cross ranks).
    #[error(transparent)]
    Batch(#[from] BatchError),
    /// A failure injected for testing (see [`crate::fault`]).
    #[error("fault injected at phase '{phase}' on rank {rank} ({variable}={phase}@{rank})")]
    Injected {
        /// The phase that failed.
        phase: String,
        /// The rank that failed.
        rank: usize,
        /// The environment variable that asked for it.
        variable: &'static str,
    },
    /// An error some rank had, that every rank now knows.
    #[error(transparent)]
    Agreed(#[from] Agreed),
}

impl Error {
    /// The process exit code for this error.
    pub fn exit_code(&self) -> i32 {
        match self {
            Error::Config(_) | Error::Mesh(_) | Error::Model(_) | Error::OutputExists(_) => 2,
            Error::Mechanism { .. } | Error::SingularStiffness(_) | Error::ElementInput { .. } => 2,
            Error::Agreed(a) => a.exit_code,
            Error::Job(j) if j.is_bad_input() => 2,
            _ => 1,
        }
    }
}
