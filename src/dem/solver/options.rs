//! The solver's options: tolerances, caps and the switches of its optional algorithms, a plain
//! `Copy + Default` parameter block (the defaults are the ones the virtual tests run with).
pub use super::slip_terms::SlipTerms;

/// What to do with a stone that lost every bond and contact.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, serde::Deserialize, serde::Serialize)]
#[serde(rename_all = "snake_case")]
pub enum FloatingPolicy {
    /// Hold it by the regularization spring and report it (default).
    #[default]
    Regularize,
    /// Stop with [`DemError::FreeFloating`].
    Error,
}

/// Solver options.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct SolverOptions {
    /// Relative residual tolerance.
    pub tol: f64,
    /// Maximum equilibrium iterations.
    pub max_iterations: usize,
    /// Refactorize when the Woodbury correction has more columns than this (90 = 30 beams; not
    /// with updates in place, which keep no correction).
    pub max_rank: usize,
    /// Stop when `|R| < loss_fraction × peak |R|` (after the peak).
    pub loss_fraction: f64,
    /// Cap on the number of beam breaks.
    pub max_events: usize,
    /// Contacts and friction between unbonded stones.
    pub contacts: bool,
    /// Free-floating stones.
    pub floating: FloatingPolicy,
    /// Halvings of a load step (or of a beam's release) tried before giving up.
    pub max_cutbacks: usize,
    /// End load steps at contact events (stick → slip, a contact closing or opening), see the
    /// module docs (default off).
    pub contact_events: bool,
    /// The contacts' tangential terms in the factorized preconditioner: the share of `k_t c cᵀ`
    /// a sliding contact keeps and how many Newton iterations a stick/slip flip waits before it
    /// reaches the factor ([`SlipTerms`], [`super::slip_terms`]; default [`SlipTerms::FULL`]:
    /// every contact keeps `k_t c cᵀ`, so flips never touch the factor and GMRES absorbs them).
    pub slip_terms: SlipTerms,
    /// Tolerance of the linear (GMRES) solve inside Newton ([`super::gmres::Forcing`]).
    pub forcing: super::gmres::Forcing,
    /// Where Newton's method finds no equilibrium at the smallest increment (a load step or a
    /// beam's release), look for it by pseudo-transient continuation ([`super::continuation`];
    /// default on).
    pub continuation: bool,
    /// Keep the Newton history of the last equilibrium attempts ([`super::trace`]; default
    /// off).
    pub trace: bool,
    /// Start a load step after a break from the cut step's response
    /// ([`super::step_predictor`]; default on: the same equilibria, fewer Newton iterations;
    /// never with crushing, whose softening contacts make the equilibrium depend on the start).
    pub predict_steps: bool,
    /// Find equilibria by one solve while no contact is active ([`super::linear`]; default on:
    /// the same equilibria as Newton's method to round-off, without its confirming residual).
    pub linear_phase: bool,
    /// With updates in place: solve a contact-free Newton step whose residual is concentrated
    /// on few unknowns (a broken beam's force, a platen's move) by a forward substitution over
    /// their reach only ([`super::factor`], "Sparse right-hand sides"; default on; never with
    /// crushing, whose softening contacts make the path depend on differences below the
    /// tolerance).
    pub sparse_rhs: bool,
    /// How the factorized operator follows breaks and contact changes: CHOLMOD's updates and
    /// downdates in place, or a Woodbury correction with refactorizations ([`FactorUpdates`];
    /// default [`FactorUpdates::Auto`]).
    pub factor_updates: FactorUpdates,
    /// With updates in place: refactorize once the fill that updates brought into the factor
    /// has cost this many factorizations in extra solve work ([`super::factor`], "Updates in
    /// place"; default [`super::factor::FILL_REFACTOR_FACTOR`]; `f64::INFINITY`: never).
    pub fill_refactor: f64,
    /// Replace a contact term held in the factorized operator once it has drifted from the
    /// contact's current one by more than this fraction (Frobenius norm of the 6×6 terms): the
    /// normal turns and the chord's stiffness changes as a contact deepens, and the difference
    /// is left to GMRES ([`super::operator`]). `f64::INFINITY`: a term is kept until its contact
    /// leaves.
    pub refresh_drift: f64,
    /// Beams broken together before one re-equilibration (default 1: paper §2.1's algorithm, one
    /// break per equilibrium). `n > 1` is an approximation, opt-in ([`super::breaks`], "Several
    /// breaks per equilibrium"): a cascade breaks up to `n` beams with `P ≥ 1` at once.
    pub breaks_per_equilibrium: usize,
    /// How a load step finds the load of its first beam break ([`BreakSearch`],
    /// [`super::break_search`]; default [`BreakSearch::Trial`]).
    pub break_search: BreakSearch,
    /// GMRES's preconditioner solves with an `f32` supernodal copy of the factor updated in
    /// place, made once the factor has stayed unchanged for a few solves, from this many entries
    /// of `L` on (default [`super::cholmod::COPY_MIN_ENTRIES`], about 5,000 stones; `usize::MAX`:
    /// never, CHOLMOD's factor throughout) ([`super::supernodes`],
    /// [`super::cholmod::UpdatableCholesky::precondition`]). It preconditions only: Newton's
    /// residual, and so every equilibrium, is computed as before, while GMRES's split form takes
    /// the copy for `M⁻¹` (its relative error, about 10⁻⁶, is left in Newton's step, which the
    /// next iteration's residual sees).
    pub preconditioner_copy_from: usize,
}

impl Default for SolverOptions {
    fn default() -> Self {
        SolverOptions {
            tol: 1e-8,
            max_iterations: 40,
            max_rank: 90,
            loss_fraction: 0.05,
            max_events: 1_000_000,
            contacts: true,
            floating: FloatingPolicy::Regularize,
            max_cutbacks: 10,
            contact_events: false,
            slip_terms: SlipTerms::FULL,
            forcing: super::gmres::Forcing::default(),
            continuation: true,
            trace: false,
            predict_steps: true,
            linear_phase: true,
            sparse_rhs: true,
            factor_updates: FactorUpdates::Auto,
            fill_refactor: super::factor::FILL_REFACTOR_FACTOR,
            refresh_drift: f64::INFINITY,
            breaks_per_equilibrium: 1,
            break_search: BreakSearch::Trial,
            preconditioner_copy_from: super::cholmod::COPY_MIN_ENTRIES,
        }
    }
}

/// How a load step `t → t_try` finds the load `λ*` at which its first beam reaches `P = 1`
/// ([`super::break_search`]).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, serde::Deserialize, serde::Serialize)]
#[serde(rename_all = "snake_case")]
pub enum BreakSearch {
    /// The equilibrium at `t_try` first, `λ*` on the chord from the step's start to it, then
    /// the equilibrium at `λ*` ([`super::stage`]; default).
    #[default]
    Trial,
    /// The trial path, its breaks landed on `P = 1` by the search's secant passes
    /// ([`super::break_search`], "Landing"): the path [`BreakSearch::Tangent`] follows, at the
    /// trial path's cost and more; the reference of its tests.
    TrialLanded,
    /// One tangent solve at the step's start predicts `λ*`; the equilibrium is solved there
    /// only, its indices checked and `λ*` corrected by secant steps until the first beam lands
    /// on `P = 1` ([`super::break_search`]). Without a break inside the step, or with crushing,
    /// the step is the trial's.
    Tangent,
}

/// How the factorized operator follows beam breaks and contact changes ([`super::factor`]).
///
/// Updates in place are the faster path at every size measured (`examples/dem_profile.rs`,
/// random samples in compression to 2e-3 or in tension to loss of load, one core, the same
/// breaks and peaks to 1e-9 either way):
///
/// | stones | unknowns | test | Woodbury, s | in place, s | peak memory, MB |
/// |---|---|---|---|---|---|
/// | 60 | 141 | compression | 0.026 | 0.024 | |
/// | 200 | 522 | compression | 0.178 | 0.145 | |
/// | 1,000 | 2,823 | compression | 7.27 | 5.25 | 26 → 18 |
/// | 3,000 | 8,703 | compression, 600 breaks | 8.76 | 6.04 | 56 → 41 |
/// | 3,000 | 8,703 | tension | 2.21 | 1.05 | 58 → 40 |
/// | 10,000 | 29,448 | tension | 19.3 | 8.3 | 190 → 137 |
///
/// [`Self::Auto`] still keeps the Woodbury path below [`IN_PLACE_MIN_UNKNOWNS`]: there the
/// difference is a fraction of a second, and the paper's wall (about 180 unknowns) keeps the
/// round-off behind its published figures and behind the identified law
/// (`materials/rubble-identified.toml`, the same bytes from the same seeds).
#[derive(Clone, Copy, Debug, PartialEq, Eq, serde::Deserialize, serde::Serialize, schemars::JsonSchema)]
#[serde(rename_all = "snake_case")]
pub enum FactorUpdates {
    /// In place from [`IN_PLACE_MIN_UNKNOWNS`] unknowns on, Woodbury below.
    Auto,
    /// A Woodbury correction over the last factorization, refactorized by the cost model.
    Woodbury,
    /// CHOLMOD's updates and downdates of the factor in place.
    InPlace,
}

/// [`FactorUpdates::Auto`] updates the factor in place from this many unknowns on (a random
/// sample of about 350 stones).
pub const IN_PLACE_MIN_UNKNOWNS: usize = 1_000;

impl FactorUpdates {
    /// Whether a system of `n_eq` unknowns is updated in place.
    pub fn in_place(self, n_eq: usize) -> bool {
        match self {
            FactorUpdates::Auto => n_eq >= IN_PLACE_MIN_UNKNOWNS,
            FactorUpdates::Woodbury => false,
            FactorUpdates::InPlace => true,
        }
    }
}
