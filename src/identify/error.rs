//! Errors of the identification: the optimizer's set-up, the data it fits, the batches it runs.
use crate::dem::error::TestFailure;
use crate::parallel::Unfinished;
use std::path::PathBuf;

/// What went wrong in an identification.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum IdentifyError {
    /// A search interval is empty, inverted or not finite.
    #[error("bounds of `{name}`: expected finite lower < upper, got [{lower}, {upper}]")]
    InvalidBounds {
        /// The unknown.
        name: String,
        /// Lower bound.
        lower: f64,
        /// Upper bound.
        upper: f64,
    },
    /// A curve to fit has no usable point or no load at all.
    #[error("{what}: {reason}")]
    BadCurve {
        /// Which curve (e.g. "DEM tension curve").
        what: String,
        /// What is wrong with it.
        reason: String,
    },
    /// Too few design points could be evaluated to build the surrogate.
    #[error(
        "the surrogate needs at least {needed} evaluated points, only {got} succeeded; first failure: {first_failure}"
    )]
    TooFewPoints {
        /// Needed.
        needed: usize,
        /// Succeeded.
        got: usize,
        /// The first failure's message.
        first_failure: String,
    },
    /// The surrogate optimizer failed.
    #[error("surrogate optimizer: {0}")]
    Optimizer(String),
    /// A batch of evaluations could not be run or transferred.
    #[error("batch: {0}")]
    Batch(String),
    /// Invalid settings.
    #[error("{0}")]
    Settings(String),
    /// Material variants that need more samples than a test has (identify::variants).
    #[error("material variants ({scheme}): the {test} test has {samples} sample(s), {needed} needed (one per group)")]
    TooFewSamples {
        /// The scheme's job-file name.
        scheme: &'static str,
        /// "tension" or "compression".
        test: &'static str,
        /// The test's samples.
        samples: usize,
        /// Samples needed.
        needed: usize,
    },
    /// A file cannot be read.
    #[error("cannot read {}: {reason}", file.display())]
    Read {
        /// The file.
        file: PathBuf,
        /// The operating system's error, as text.
        reason: String,
    },
    /// A file cannot be written.
    #[error("cannot write {}: {reason}", file.display())]
    Write {
        /// The file.
        file: PathBuf,
        /// The operating system's error, as text.
        reason: String,
    },
    /// A curve file is malformed.
    #[error("{}{}: {reason}", file.display(), line.map_or(String::new(), |l| format!(":{l}")))]
    CurveFile {
        /// The CSV file.
        file: PathBuf,
        /// The 1-based line, when one is at fault.
        line: Option<usize>,
        /// What is wrong.
        reason: String,
    },
}

/// Why one evaluation of a search (a virtual test, the law's curves, the objective of a point)
/// gave no value. It crosses ranks as JSON; the searches' histories write it as its message.
#[derive(Debug, Clone, PartialEq, serde::Serialize, serde::Deserialize, thiserror::Error)]
pub enum EvalError {
    /// A virtual test of a sample.
    #[error(transparent)]
    Test(#[from] TestFailure),
    /// The law cannot be set up for the element size.
    #[error("{reason}")]
    Law {
        /// The law's message.
        reason: String,
    },
    /// The law's material-point driver failed along a test path.
    #[error("{reason}")]
    Path {
        /// The driver's message.
        reason: String,
    },
    /// The law's curve and the reference have no comparable point.
    #[error("{curve}: no comparable point")]
    NoComparablePoint {
        /// "tension" or "compression".
        curve: String,
    },
    /// The objective is not finite.
    #[error("non-finite objective {value}")]
    NonFinite {
        /// Its value.
        value: f64,
    },
    /// The elastic runs of an α give no finite ν and E.
    #[error("alpha {alpha}: no finite nu and E over the samples (nu {poisson}, E/Ebar {e_ratio})")]
    NoFiniteElastic {
        /// α.
        alpha: f64,
        /// The mean ν.
        poisson: f64,
        /// The mean E/Ē.
        e_ratio: f64,
    },
    /// Every sample stopped before its peak.
    #[error("every sample stopped before its peak (solver end 'failed')")]
    EveryRunStopped,
    /// No sample was run.
    #[error("no sample")]
    NoSample,
    /// A point without any task result.
    #[error("no result")]
    NoResult,
    /// The elastic stage's search ended without a fit.
    #[error("{reason}")]
    Search {
        /// The search's message.
        reason: String,
    },
    /// A task whose worker ended without a result.
    #[error(transparent)]
    Unfinished(#[from] Unfinished),
}
