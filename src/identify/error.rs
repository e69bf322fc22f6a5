//! Errors of the identification: the optimizer's set-up, the data it fits, the batches it runs.

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
}
