//! IMPL-EX: the damage of a step extrapolated explicitly from the last two committed steps, the
//! stress of the step computed with it, the history then updated implicitly (Oliver, Huespe and
//! Cante, *An implicit/explicit integration scheme to increase computability of non-linear
//! material and contact/friction problems*, CMAME 197 (2008) 1865–1889).
//!
//! # The update of a point over the step n → n+1 (size Δt_{n+1})
//! ```text
//!   κ̃_{n+1} = κ_n + (Δt_{n+1}/Δt_n) (κ_n − κ_{n−1})        per side (t, c); κ ≥ ε₀ on both
//!   current:  σ_{n+1} = σ(ε_{n+1}; d(κ̃_{n+1})),  C_{n+1} = ∂σ/∂ε there   (law at fixed damage)
//!   frozen:   σ_{n+1} = S_{n+1} ε_{n+1},  C_{n+1} = S_{n+1},  S_{n+1} = ∂σ/∂ε (ε_n; d(κ̃_{n+1}))
//!   κ_{n+1}  = max(κ_n, ε_eq(ε_{n+1}))                      the implicit update: committed
//! ```
//! κ never decreases, so κ̃ ≥ κ_n, and Δt_{n+1}/Δt_n = 0 (no earlier step, or its size unknown)
//! gives κ̃ = κ_n. The law is evaluated at the frozen history κ̃
//! ([`PointLaw::with_frozen_history`]): no damage grows inside the step, so there is no
//! softening term.
//!
//! # Where the unilateral split is taken: [`SplitAt`]
//! At fixed damage the law is still not linear: the paper's split switches between 1 − d_t and
//! 1 − d_c with the sign of tr σ̃ (smoothed over a band of stress directions in plane stress,
//! where the stress falls as the direction turns when d_t > d_c), the spectral split with the
//! signs and directions of the principal strains.
//! * `current`: the law's own split at the step's strain. With the spectral split the stress
//!   at fixed damage derives from the potential ψ(ε; d̃), piecewise linear in the principal
//!   strains: Newton needs a few iterations where cracks open or close, and a closed strain
//!   cycle within a step does no work. With the paper's split a step in which points cross the
//!   plane-stress band can need many (on the church, 10 to 40, some steps halved).
//! * `frozen` (as OpenSees' ASDConcrete3D freezes its stress decomposition, `-implex`): the
//!   point's secant S at fixed damage is taken at its committed strain ε_n. The law is
//!   homogeneous of degree 1 at fixed damage, σ(ε) = S(ε) ε for both splits, so S(ε_n) ε_n is
//!   its stress at ε_n exactly. The step's stress S_{n+1} ε is linear in ε and its equilibrium
//!   one linear system with a symmetric positive definite Jacobian: one Newton iteration. A
//!   crack that closes within the step is seen one step late: it carries the cracked stiffness
//!   while it closes and the full one while it reopens, a cycle that returns more work than it
//!   took (energy from nothing, in the `unilateral` column of the time history's balance),
//!   which grows with the step and with the shaking.
//!
//! Without a committed strain (the first step after IMPL-EX is switched on) `frozen` takes the
//! split at the step's strain as `current` does.
//!
//! The committed history is the implicit law's, from κ_n at the converged strain ε_{n+1}: the
//! same state, damage and dissipation as the implicit update of [`super::state`] would give from
//! κ_n (tested bit for bit). The stress used for equilibrium lags it by the extrapolation, an
//! error of first order in Δt that the step size controls.
//!
//! # Energy
//! The dissipation a point reports is the implicit update's, c [F(κ_{n+1}) − F(κ_n)]: the
//! dissipated energy (`Element::dissipated_energy`) is that of the committed histories, so it is
//! never negative, never decreases, and is what the implicit law dissipates along the computed
//! strain path. The work of the internal forces is that of the stresses in equilibrium, the
//! extrapolated ones. The time history's balance (`analysis::time_history::energy`) closes with
//! those forces as before; the difference between the work of the extrapolated stresses and the
//! recoverable plus dissipated energy of the committed states, which vanishes with Δt, lands in
//! its `unilateral` column with the crack-closure exchange of the paper's split.
//!
//! # Use
//! An element keeps, per point, the committed state and strain and the state before, and the
//! size of the step between them; before the evaluations of a step it computes [`extrapolate`]
//! once per point, then [`evaluate`] gives each evaluation's response: the stress, secant and
//! tangent of the extrapolated history with the split where [`SplitAt`] says, the trial state
//! and dissipation of the implicit update (`element::PointStates` keeps the frozen secant of a
//! step and computes the implicit update once, for the converged step).

use nalgebra::SVector;
use serde::{Deserialize, Serialize};

use super::law::PointLaw;
use super::response::{Response, StressState};
use super::state::{DamageState, Side};

/// The history the stress of the next step uses (module docs): per side
/// κ̃ = κ_n + ratio (κ_n − κ_{n−1}) with both κ clamped below at the side's threshold, and
/// never below κ_n; d = d(κ̃). `ratio` = Δt_{n+1}/Δt_n ≥ 0 (0: no extrapolation).
pub fn extrapolate(law: &PointLaw, committed: &DamageState, previous: &DamageState, ratio: f64) -> DamageState {
    let side = |s: Side| {
        let eps0 = law.threshold(s);
        let now = committed.kappa(s).max(eps0);
        let before = previous.kappa(s).max(eps0);
        let kappa = (now + ratio * (now - before)).max(now);
        (kappa, law.damage(s, kappa).d)
    };
    let (kappa_t, d_t) = side(Side::Tension);
    let (kappa_c, d_c) = side(Side::Compression);
    DamageState { kappa_t, kappa_c, d_t, d_c }
}

/// The response of a step's evaluation: stress, secant, tangent and side from `stress` (the law
/// at the extrapolated history), the trial state, dissipation and loading flag from `history`
/// (the implicit update from the committed state).
#[inline]
pub fn combine<const N: usize>(stress: Response<N>, history: Response<N>) -> Response<N> {
    Response { stress: stress.stress, secant: stress.secant, tangent: stress.tangent, side: stress.side, ..history }
}

/// Where the unilateral split of an IMPL-EX step's stress is taken (module docs): at the
/// step's own strain (`current`: the law at the extrapolated damage, Newton iterates across
/// crack closure) or at the committed strain (`frozen`: the step is linear, a crack is seen
/// closing one step late).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash, Serialize, Deserialize, schemars::JsonSchema)]
#[serde(rename_all = "snake_case")]
pub enum SplitAt {
    /// At the step's strain.
    #[default]
    Current,
    /// At the committed strain.
    Frozen,
}

impl SplitAt {
    /// The job-file name of the variant.
    pub fn name(&self) -> &'static str {
        match self {
            SplitAt::Current => "current",
            SplitAt::Frozen => "frozen",
        }
    }
}

/// What the stress of an IMPL-EX step is computed from (module docs): the extrapolated
/// history, and the point's committed strain where the split is frozen (none: not frozen).
#[derive(Clone, Copy, Debug)]
pub struct Extrapolated<'a, const N: usize> {
    /// κ̃ and d(κ̃).
    pub history: &'a DamageState,
    /// ε_n.
    pub strain: Option<&'a SVector<f64, N>>,
}

/// The response at `strain` of a point whose law is `eval(law, strain, history)` (any
/// kinematics, local or nonlocal), from its `committed` state: with `implex`, [`combine`] of the
/// step's stress (module docs) and the implicit update; without, the implicit update alone.
#[inline]
pub fn evaluate<const N: usize>(
    law: &PointLaw,
    committed: &DamageState,
    strain: &SVector<f64, N>,
    implex: Option<Extrapolated<N>>,
    eval: impl Fn(&PointLaw, &SVector<f64, N>, &DamageState) -> Response<N>,
) -> Response<N> {
    let implicit = eval(law, strain, committed);
    let Some(x) = implex else { return implicit };
    let frozen = law.with_frozen_history();
    let stress = match x.strain {
        None => eval(&frozen, strain, x.history),
        Some(at) => {
            let s = eval(&frozen, at, x.history);
            Response { stress: s.secant * strain, tangent: s.secant, ..s }
        }
    };
    combine(stress, implicit)
}

/// [`evaluate`] for the kinematics `K` at `strain`, the split frozen at `frozen_at` if given.
#[inline]
pub fn update<const N: usize, K: StressState<N>>(
    law: &PointLaw,
    strain: &SVector<f64, N>,
    committed: &DamageState,
    extrapolated: &DamageState,
    frozen_at: Option<&SVector<f64, N>>,
) -> Response<N> {
    let x = Extrapolated { history: extrapolated, strain: frozen_at };
    evaluate(law, committed, strain, Some(x), |l, e, s| K::evaluate(l, e, s))
}

#[cfg(test)]
#[path = "implex_tests.rs"]
mod tests;
