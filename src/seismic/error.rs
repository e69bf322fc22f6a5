//! Typed errors of the ground-motion module: every one names the file (or record) and, where it
//! applies, the line.
use std::path::PathBuf;

/// What can go wrong reading, checking or processing a ground-motion record.
#[derive(Debug, thiserror::Error)]
pub enum SeismicError {
    /// The file cannot be read.
    #[error("cannot read record {}: {source}", path.display())]
    Io {
        /// The file.
        path: PathBuf,
        /// The operating system's error.
        source: std::io::Error,
    },
    /// A line cannot be understood.
    #[error("{file}:{line}: {reason}")]
    Parse {
        /// The file (or record name).
        file: String,
        /// 1-based line number.
        line: usize,
        /// What is wrong.
        reason: String,
    },
    /// A value is NaN or infinite.
    #[error("{file}:{line}: value '{value}' is not finite")]
    NonFinite {
        /// The file (or record name).
        file: String,
        /// 1-based line number (0 for an in-memory record: then it is the sample index + 1).
        line: usize,
        /// The offending text.
        value: String,
    },
    /// Time does not increase.
    #[error("{file}:{line}: time {t} s does not increase (previous {t_prev} s)")]
    NonMonotonicTime {
        /// The file.
        file: String,
        /// 1-based line number.
        line: usize,
        /// Previous time.
        t_prev: f64,
        /// This time.
        t: f64,
    },
    /// The time step is not uniform within the tolerance.
    #[error(
        "{file}:{line}: time step {dt_found} s differs from the mean {dt_mean} s by more than {tolerance:e} (relative)"
    )]
    NonUniformDt {
        /// The file.
        file: String,
        /// 1-based line number.
        line: usize,
        /// Mean step.
        dt_mean: f64,
        /// This step.
        dt_found: f64,
        /// The relative tolerance.
        tolerance: f64,
    },
    /// The header's point count disagrees with the data.
    #[error("{file}: header declares {declared} points (line {line}) but the file holds {found}")]
    CountMismatch {
        /// The file.
        file: String,
        /// Line of the declaration.
        line: usize,
        /// Declared count.
        declared: usize,
        /// Count found.
        found: usize,
    },
    /// The record is shorter than a requested duration.
    #[error("record '{name}' lasts {duration} s, shorter than the requested {requested} s")]
    TooShort {
        /// Record name.
        name: String,
        /// Its duration.
        duration: f64,
        /// The duration asked for.
        requested: f64,
    },
    /// A parameter is out of its range.
    #[error("{what}: {reason}")]
    InvalidParameter {
        /// Which parameter (and of what).
        what: String,
        /// Why it is refused.
        reason: String,
    },
}

impl SeismicError {
    /// Shorthand for [`SeismicError::InvalidParameter`].
    pub fn invalid(what: impl Into<String>, reason: impl Into<String>) -> SeismicError {
        SeismicError::InvalidParameter { what: what.into(), reason: reason.into() }
    }

    /// The [`SeismicError::InvalidParameter`] of `what` out of its bound `b`
    /// ([`crate::bounds`]): "`what`: expected > 0, got `value`".
    pub fn out_of_bounds(what: impl Into<String>, b: crate::bounds::OutOfBounds) -> SeismicError {
        SeismicError::invalid(what, b.to_string())
    }
}
