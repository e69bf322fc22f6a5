//! Errors of the quasi-static DEM solver and the virtual tests, each naming what and where.

use crate::dem::mechanics::MechanicsError;
use crate::dem::sample::SampleError;

/// What can go wrong while setting up or running a virtual test.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum DemError {
    /// A test or solver parameter outside its admissible range.
    #[error("virtual test: `{field}`: expected {expected}, got {value}")]
    InvalidParameter {
        /// The parameter name.
        field: &'static str,
        /// The value given, as text.
        value: String,
        /// What is admissible.
        expected: &'static str,
    },
    /// The sample cannot carry platens (no bottom or top row, or a stone on both).
    #[error("sample cannot be tested: {reason}")]
    BadSample {
        /// Why.
        reason: String,
    },
    /// A stone lost every bond and every contact (it cannot be held in equilibrium) and the
    /// solver was told to stop in that case ([`super::FloatingPolicy::Error`]).
    #[error("free-floating stone {particle} after event {event}: no intact beam and no active contact holds it")]
    FreeFloating {
        /// The particle.
        particle: usize,
        /// The event (beam break) count when it was detected.
        event: usize,
    },
    /// The sparse Cholesky factorization failed (matrix not positive definite).
    #[error("stiffness factorization failed after event {event}: {reason}")]
    Factorization {
        /// The event count.
        event: usize,
        /// faer's message.
        reason: String,
    },
    /// The contact/friction iterations did not converge.
    #[error(
        "equilibrium not found after {iterations} iterations at load fraction {load} of stage {stage} (event {event}): relative residual {residual:e}{}",
        unbonded_note(unbonded)
    )]
    NoConvergence {
        /// Load stage index.
        stage: usize,
        /// Load parameter within the stage, in [0, 1].
        load: f64,
        /// Event count.
        event: usize,
        /// Iterations done.
        iterations: usize,
        /// Relative residual reached.
        residual: f64,
        /// Stones (not on a platen) without any intact beam at that point: held only by
        /// contacts, or free-floating; the usual reason no equilibrium exists.
        unbonded: Vec<usize>,
    },
    /// The number of events exceeded the configured cap.
    #[error("more than {max_events} beam-break events: raise `max_events` or coarsen the test")]
    TooManyEvents {
        /// The cap.
        max_events: usize,
    },
    /// A beam or contact of the sample is invalid for the mechanics.
    #[error("beam {beam} ({i}–{j}): {source}")]
    Beam {
        /// Beam index.
        beam: usize,
        /// First particle.
        i: usize,
        /// Second particle.
        j: usize,
        /// The mechanics error.
        source: MechanicsError,
    },
    /// A contact between two stones could not be evaluated.
    #[error("contact {i}–{j}: {source}")]
    Contact {
        /// First particle.
        i: usize,
        /// Second particle.
        j: usize,
        /// The mechanics error.
        source: MechanicsError,
    },
    /// Invalid mechanical parameters.
    #[error("mechanical parameters: {0}")]
    Params(MechanicsError),
    /// Sample construction failed.
    #[error(transparent)]
    Sample(#[from] SampleError),
    /// A checkpoint could not be written ([`super::checkpoint`]): the test stops with it,
    /// without a result.
    #[error("checkpoint: {0}")]
    Checkpoint(String),
}

/// `Err(InvalidParameter)` unless `v` is finite and > 0 ([`crate::bounds::positive`]).
pub(crate) fn positive(field: &'static str, v: f64) -> Result<f64, DemError> {
    crate::bounds::positive(v).map_err(|b| out_of_bounds(field, b))
}

/// `Err(InvalidParameter)` unless `v` is finite and >= 0 ([`crate::bounds::non_negative`]).
pub(crate) fn non_negative(field: &'static str, v: f64) -> Result<f64, DemError> {
    crate::bounds::non_negative(v).map_err(|b| out_of_bounds(field, b))
}

fn out_of_bounds(field: &'static str, b: crate::bounds::OutOfBounds) -> DemError {
    DemError::InvalidParameter { field, value: b.value.to_string(), expected: b.expected }
}

/// The tail of the no-convergence message naming the unbonded stones (at most 12).
fn unbonded_note(unbonded: &[usize]) -> String {
    if unbonded.is_empty() {
        return String::new();
    }
    let shown: Vec<String> = unbonded.iter().take(12).map(|p| p.to_string()).collect();
    let more = if unbonded.len() > 12 { format!(" and {} more", unbonded.len() - 12) } else { String::new() };
    format!("; stones without any intact beam (held only by contacts, or free-floating): {}{more}", shown.join(", "))
}
