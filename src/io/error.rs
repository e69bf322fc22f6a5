//! The error type of the results output.
//!
//! Every variant names the file it concerns; the ones about a dataset name the dataset too, as its
//! HDF5 path (`/steps/3/displacement`).

use std::path::PathBuf;

/// What went wrong while writing results.
#[derive(Debug, thiserror::Error)]
pub enum IoError {
    /// This rank's piece of the output mesh is inconsistent (lengths, offsets, node indices).
    #[error("{}: invalid output mesh on rank {rank}: {reason}", file.display())]
    InvalidMesh {
        /// The HDF5 file being written.
        file: PathBuf,
        /// The rank whose piece is wrong.
        rank: i32,
        /// What is wrong.
        reason: String,
    },
    /// A call that does not fit the writer's state or a field whose name or length is wrong.
    #[error("{}: dataset {dataset}: {reason}", file.display())]
    InvalidField {
        /// The HDF5 file being written.
        file: PathBuf,
        /// The dataset concerned (HDF5 path).
        dataset: String,
        /// What is wrong.
        reason: String,
    },
    /// Another rank found an error in a collective call, or the ranks passed different arguments
    /// to it; every rank returns an error so that none is left waiting in a collective.
    #[error("{}: {what}: rejected on rank(s) {ranks:?}", file.display())]
    Collective {
        /// The HDF5 or XDMF file being written.
        file: PathBuf,
        /// The call and what was compared.
        what: String,
        /// The ranks that failed or disagree with rank 0.
        ranks: Vec<i32>,
    },
    /// The HDF5 library reported an error.
    #[error("{}: dataset {dataset}: HDF5 error: {source}", file.display())]
    Hdf5 {
        /// The HDF5 file being written.
        file: PathBuf,
        /// The dataset or group concerned (HDF5 path).
        dataset: String,
        /// The HDF5 error stack.
        #[source]
        source: hdf5::Error,
    },
    /// Writing the XDMF index failed (reported on every rank).
    #[error("{}: cannot write the XDMF index: {reason}", file.display())]
    Xdmf {
        /// The XDMF file.
        file: PathBuf,
        /// The operating-system error, as text (it crosses ranks).
        reason: String,
    },
    /// A results file (CSV, text) cannot be read back.
    #[error("{}: {source}", file.display())]
    Read {
        /// The file.
        file: PathBuf,
        /// The operating system's error.
        source: std::io::Error,
    },
    /// A results file (CSV, text) cannot be written.
    #[error("cannot write {}: {source}", file.display())]
    Write {
        /// The file.
        file: PathBuf,
        /// The operating system's error.
        source: std::io::Error,
    },
    /// A value cannot be written as JSON.
    #[error("{}: {what} cannot be written as JSON: {source}", file.display())]
    Json {
        /// The file it was for.
        file: PathBuf,
        /// What it is (`the summary`, `the calibration`).
        what: &'static str,
        /// serde's error.
        source: serde_json::Error,
    },
}
