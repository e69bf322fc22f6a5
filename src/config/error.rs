//! Job-file errors: every one names the file, the line and column, the key, and what was expected.
use std::fmt;
use std::path::PathBuf;

/// Where in a job file something is.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Location {
    /// The job file.
    pub file: PathBuf,
    /// 1-based line, when known.
    pub line: Option<usize>,
    /// 1-based column, when known.
    pub column: Option<usize>,
    /// Dotted key path (`materials.steel.E`, `parts[2].group`), when known.
    pub key: Option<String>,
}

impl fmt::Display for Location {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "{}", self.file.display())?;
        if let Some(l) = self.line {
            write!(f, ":{l}")?;
            if let Some(c) = self.column {
                write!(f, ":{c}")?;
            }
        }
        if let Some(k) = &self.key {
            write!(f, ": key '{k}'")?;
        }
        Ok(())
    }
}

/// An error in a job file or in a file it references.
#[derive(Debug, thiserror::Error)]
pub enum ConfigError {
    /// The job file could not be read.
    #[error("cannot read job file {}: {source}", path.display())]
    Read {
        /// The file.
        path: PathBuf,
        /// The cause.
        source: std::io::Error,
    },
    /// The TOML is malformed, a key is unknown, a value has the wrong type, or a value is invalid.
    #[error("{at}: {message}")]
    Invalid {
        /// Where.
        at: Location,
        /// What is wrong and what was expected.
        message: String,
    },
}

/// A file that a job refers to (a material's law file, a record set's summary, a convergence
/// band, a sweep's base job) that cannot be used. It names the file; where a key of the job
/// names the file, the job's error reports it at that key.
#[derive(Debug, thiserror::Error)]
pub enum FileError {
    /// The file does not exist.
    #[error("{what} {} does not exist", file.display())]
    Missing {
        /// What the file is (`material file`).
        what: &'static str,
        /// The file.
        file: PathBuf,
    },
    /// The file cannot be read.
    #[error("cannot read {what} {}: {reason}", file.display())]
    Read {
        /// What the file is (`material file`, `convergence band file`).
        what: &'static str,
        /// The file.
        file: PathBuf,
        /// The operating system's error.
        reason: String,
    },
    /// A table of the file is malformed (the error names its key, line and column).
    #[error("in the {what}: {source}")]
    Table {
        /// What the file is.
        what: &'static str,
        /// The error at the key.
        source: Box<ConfigError>,
    },
    /// The file's content is not what it should be.
    #[error("{}: {reason}", file.display())]
    Invalid {
        /// The file.
        file: PathBuf,
        /// What is wrong.
        reason: String,
    },
    /// A record set whose EN 1998-1 check failed, where the job requires a compatible one.
    #[error(
        "the record set {} failed its EN 1998-1 compatibility check (see {}); set require_compatible = false to use it anyway",
        dir.display(),
        dir.join("check.txt").display()
    )]
    IncompatibleRecordSet {
        /// The record set's results folder.
        dir: PathBuf,
    },
}
