//! The problem of one virtual test: what the step pipeline reads and never changes.
use super::options::SolverOptions;
use super::scales::Scales;
use super::system::Model;

/// The model, the solver's options and the sample's scales, fixed for a test (module docs).
pub(super) struct Problem<'a> {
    /// The assembled model ([`Model`]).
    pub model: Model<'a>,
    /// The solver's options.
    pub opts: SolverOptions,
    /// The sample's fixed scales ([`Scales`]).
    pub scales: Scales,
}

impl<'a> Problem<'a> {
    /// The problem of `model` solved with `opts`, its scales computed.
    pub fn new(model: Model<'a>, opts: SolverOptions) -> Problem<'a> {
        Problem { scales: Scales::of(&model), opts, model }
    }
}
