//! Why a virtual test of a batch gave no result, as it travels between ranks.
//!
//! The solver's [`DemError`] is classified here by its variant into a [`StopKind`], once, where
//! a test's error leaves the solver; callers match on the kind, never on the message. A
//! [`TestFailure`] crosses ranks as JSON, so it keeps its cause's message beside the kind.
use crate::dem::solver::DemError;
use crate::parallel::Unfinished;
use serde::{Deserialize, Serialize};

/// What stopped a virtual test with an error.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum StopKind {
    /// The test, the sample or the mechanical parameters are invalid.
    InvalidInput,
    /// No equilibrium was found, even after cut-backs.
    NoEquilibrium,
    /// A stone lost every bond and every contact.
    FreeFloating,
    /// The stiffness could not be factorized.
    Factorization,
    /// More beam-break events than the cap.
    TooManyEvents,
    /// A checkpoint could not be written.
    Checkpoint,
}

impl From<&DemError> for StopKind {
    fn from(e: &DemError) -> StopKind {
        match e {
            DemError::InvalidParameter { .. }
            | DemError::BadSample { .. }
            | DemError::Beam { .. }
            | DemError::Contact { .. }
            | DemError::Params(_)
            | DemError::Sample(_) => StopKind::InvalidInput,
            DemError::NoConvergence { .. } => StopKind::NoEquilibrium,
            DemError::FreeFloating { .. } => StopKind::FreeFloating,
            DemError::Factorization { .. } => StopKind::Factorization,
            DemError::TooManyEvents { .. } => StopKind::TooManyEvents,
            DemError::Checkpoint(_) => StopKind::Checkpoint,
        }
    }
}

/// Why one virtual test of a batch (sample `sample`) gave no result.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize, thiserror::Error)]
pub enum TestFailure {
    /// The sample could not be built.
    #[error("sample {sample}{}: {message}", seed_note(*seed))]
    Sample {
        /// The sample.
        sample: usize,
        /// Its seed, when the message names it.
        seed: Option<u64>,
        /// The sample generator's message.
        message: String,
    },
    /// The mechanical parameters are invalid.
    #[error("sample {sample}: {message}")]
    Params {
        /// The sample.
        sample: usize,
        /// The mechanics' message.
        message: String,
    },
    /// The solver stopped with an error before the test could give a result.
    #[error("sample {sample}{}: {message}", seed_note(*seed))]
    Solver {
        /// The sample.
        sample: usize,
        /// Its seed, when the message names it.
        seed: Option<u64>,
        /// What stopped it.
        kind: StopKind,
        /// The solver's message.
        message: String,
    },
    /// The test ran, but its files could not be written.
    #[error("sample {sample}: {what}: {message}")]
    Output {
        /// The sample.
        sample: usize,
        /// Which output.
        what: String,
        /// The cause's message.
        message: String,
    },
    /// The rank running it ended without a result.
    #[error(transparent)]
    Unfinished(#[from] Unfinished),
}

impl TestFailure {
    /// The failure of sample `sample` (seed `seed`, when the message is to name it) that the
    /// solver reported as `e`, classified by its variant.
    pub fn solver(sample: usize, seed: Option<u64>, e: &DemError) -> TestFailure {
        TestFailure::Solver { sample, seed, kind: StopKind::from(e), message: e.to_string() }
    }
}

fn seed_note(seed: Option<u64>) -> String {
    seed.map_or(String::new(), |s| format!(" (seed {s})"))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn classified_by_variant_with_the_message_kept() {
        let e = DemError::TooManyEvents { max_events: 3 };
        let f = TestFailure::solver(2, Some(9), &e);
        assert!(matches!(f, TestFailure::Solver { kind: StopKind::TooManyEvents, .. }));
        assert_eq!(f.to_string(), format!("sample 2 (seed 9): {e}"));
        let back: TestFailure = serde_json::from_str(&serde_json::to_string(&f).unwrap()).unwrap();
        assert_eq!(back, f);
        let free = DemError::FreeFloating { particle: 4, event: 7 };
        assert_eq!(StopKind::from(&free), StopKind::FreeFloating);
    }
}
