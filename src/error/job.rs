//! The errors of the jobs' drivers (`run/`): a DEM batch, an identification, a sweep, a record
//! set. Each names the file, the member or the section of the job it concerns.
//!
//! They live beside the run's [`Error`](super::Error): `run/` sits above it.
use std::path::PathBuf;

/// Why a job's driver stopped.
#[derive(Debug, thiserror::Error)]
pub enum JobError {
    /// No sample of a DEM batch gave numbers.
    #[error("DEM: every sample failed (see the warnings above; the curves recorded so far are in the sample folders)")]
    EverySampleFailed,
    /// A DEM sample could not be built again for its pictures.
    #[error("sample {sample}: {source}")]
    Sample {
        /// The sample.
        sample: usize,
        /// The cause.
        source: crate::dem::sample::SampleError,
    },
    /// The law of an identification has no tension or no compression test.
    #[error("[law] needs tension and compression tests")]
    LawWithoutTests,
    /// The law of an identification from curve files has no elastic constants.
    #[error(
        "{}: [law] needs young_modulus and poisson (or [experiment] ones) when the DEM curves come from files",
        file.display()
    )]
    LawWithoutElastic {
        /// The job file.
        file: PathBuf,
    },
    /// Material variants without the samples' curves.
    #[error("material variants need every sample's curve (the virtual tests, or [law] dem_samples)")]
    VariantsWithoutSamples,
    /// A record set that the job requires compatible is not.
    #[error(
        "{}: the record set is not compatible with EN 1998-1 (see {}): {}",
        file.display(),
        check.display(),
        failures.join("; ")
    )]
    RecordSetNotCompatible {
        /// The job file.
        file: PathBuf,
        /// The check's report.
        check: PathBuf,
        /// The failed rules.
        failures: Vec<String>,
    },
    /// A sweep or a DEM job restarted in a folder that holds none.
    #[error("--restart: {} does not exist (no earlier run to continue); run without --restart", dir.display())]
    NothingToRestart {
        /// The results folder.
        dir: PathBuf,
    },
    /// A member of a finished sweep without its outcome.
    #[error("member {member} has no outcome in {}", dir.display())]
    NoOutcome {
        /// The member's name.
        member: String,
        /// Its folder.
        dir: PathBuf,
    },
    /// A DEM checkpoint that `--restart` cannot continue from.
    #[error(
        "--restart: checkpoint {}: {source}; remove it to run that sample afresh, or run the job without --restart",
        file.display()
    )]
    DemCheckpoint {
        /// The file.
        file: PathBuf,
        /// Why it cannot be used.
        source: crate::dem::solver::checkpoint::Unreadable,
    },
    /// A DEM checkpoint that cannot be read.
    #[error("--restart: cannot read checkpoint {}: {source}", file.display())]
    DemCheckpointRead {
        /// The file.
        file: PathBuf,
        /// The cause.
        source: std::io::Error,
    },
}

impl JobError {
    /// Whether the job's input is at fault (exit code 2): nothing to restart, or a checkpoint
    /// that cannot be continued.
    pub fn is_bad_input(&self) -> bool {
        matches!(
            self,
            JobError::NothingToRestart { .. } | JobError::DemCheckpoint { .. } | JobError::DemCheckpointRead { .. }
        )
    }
}
