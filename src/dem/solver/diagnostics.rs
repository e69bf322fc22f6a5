//! What the step pipeline reports besides the state: how often the algorithm's branches were
//! taken, the numerics' counters and phase times, the Newton history of the last attempts and
//! the observer of recorded states. Read after the run; nothing in the mechanics depends on it.
use super::options::SolverOptions;
use super::phases::Phase;
use super::profile::{Counters, SolverProfile};
use super::records::Observer;
use super::trace::Trace;

/// The diagnostics of one test (module docs).
pub struct Diagnostics<'a> {
    /// How often the algorithm's branches were taken ([`Counters`]).
    pub counters: Counters,
    /// Counters and phase times of the numerics ([`SolverProfile`]).
    pub profile: SolverProfile,
    /// Sees every recorded state ([`Observer`]).
    pub observer: Option<Box<dyn Observer + 'a>>,
    /// The Newton history of the last equilibrium attempts (with [`SolverOptions::trace`]).
    pub trace: Option<Trace>,
    /// What the next equilibria are solved for ([`super::phases`]).
    pub(super) phase: Phase,
}

impl Diagnostics<'_> {
    /// Counters and profile at zero, no observer, a trace when `opts` asks for one.
    pub(super) fn new(opts: &SolverOptions) -> Self {
        Diagnostics {
            counters: Counters::default(),
            profile: SolverProfile::default(),
            observer: None,
            trace: opts.trace.then(Default::default),
            phase: Phase::Other,
        }
    }
}
