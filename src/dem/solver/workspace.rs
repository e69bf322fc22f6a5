//! The workspace of the step pipeline: what the solver keeps between equilibria only for
//! speed, and rebuilds from the state when it is lost ([`super::Solver::resume`]).
//!
//! | field | holds | read and kept up by |
//! |---|---|---|
//! | `operator` | the factorized operator with its Woodbury correction or updates in place | [`super::operator`] |
//! | `shifted` | with updates in place: the continuation's shifted operators | [`super::continuation`] |
//! | `candidates` | the contact search's candidate pairs | [`super::contact_candidates`] |
//! | `jacobians` | contact Jacobians kept between evaluations | [`super::tangent`] |
//!
//! The operator's upkeep reads the problem and the intact beams and counts into the profile
//! ([`upkeep`]): the operator is borrowed from the workspace beside it.
use super::contact_candidates::CandidateList;
use super::error::DemError;
use super::operator::{Operator, Upkeep};
use super::options::SolverOptions;
use super::problem::Problem;
use super::profile::SolverProfile;
use super::state::SolverState;
use super::tangent::JacobianCache;

/// The workspace of one test (module docs).
pub(super) struct Workspace {
    /// The factorized operator of Newton's method ([`super::operator`]).
    pub operator: Operator,
    /// With updates in place: the continuation's shifted operators, a Woodbury operator of their
    /// own, so that the updatable factor stays unshifted ([`super::continuation`]).
    pub shifted: Option<Operator>,
    /// The contact search's candidate list ([`super::contact_candidates`]).
    pub candidates: CandidateList,
    /// Contact Jacobians kept between evaluations ([`super::tangent`]).
    pub jacobians: JacobianCache,
}

impl Workspace {
    /// An empty workspace for `n_eq` equations: the operator to be factorized before its first
    /// use, no candidates, no Jacobians.
    pub fn new(n_eq: usize, opts: &SolverOptions) -> Result<Workspace, DemError> {
        Ok(Workspace {
            operator: Operator::new(n_eq, opts.factor_updates.in_place(n_eq), opts.fill_refactor)?,
            shifted: None,
            candidates: CandidateList::default(),
            jacobians: JacobianCache::default(),
        })
    }

    /// The factorization statistics `(numeric factorizations, symbolic analyses)`, the
    /// continuation's own shifted operator's included.
    pub fn factor_stats(&self) -> (usize, usize) {
        let shifted = self.shifted.as_ref().map_or((0, 0), |s| (s.factor.n_factorizations, s.factor.n_symbolic));
        (self.operator.factor.n_factorizations + shifted.0, self.operator.factor.n_symbolic + shifted.1)
    }
}

/// What the operator's upkeep reads at `state`: the model, the intact beams, the options, the
/// profile it counts into and the number of breaks.
pub(super) fn upkeep<'u, 'a>(
    pb: &'u Problem<'a>,
    state: &'u SolverState,
    profile: &'u mut SolverProfile,
) -> Upkeep<'u, 'a> {
    Upkeep { model: &pb.model, intact: &state.intact, opts: &pb.opts, profile, event: state.broken.len() }
}
