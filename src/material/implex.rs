//! IMPL-EX: the damage of a step extrapolated explicitly from the last two committed steps, the
//! stress of the step computed with it, the history then updated implicitly (Oliver, Huespe and
//! Cante, *An implicit/explicit integration scheme to increase computability of non-linear
//! material and contact/friction problems*, CMAME 197 (2008) 1865–1889).
//!
//! # The update of a point over the step n → n+1 (size Δt_{n+1})
//! ```text
//!   κ̃_{n+1} = κ_n + (Δt_{n+1}/Δt_n) (κ_n − κ_{n−1})        per side (t, c); κ ≥ ε₀ on both
//!   σ_{n+1}  = σ(ε_{n+1}; d(κ̃_{n+1}))                      the law at fixed damage
//!   C_{n+1}  = ∂σ_{n+1}/∂ε_{n+1}  at fixed d(κ̃_{n+1})
//!   κ_{n+1}  = max(κ_n, ε_eq(ε_{n+1}))                      the implicit update: committed
//! ```
//! κ never decreases, so κ̃ ≥ κ_n, and Δt_{n+1}/Δt_n = 0 (no earlier step, or its size unknown)
//! gives κ̃ = κ_n. The stress of the step is the law's at the frozen history κ̃
//! ([`PointLaw::with_frozen_history`]): no damage grows inside the step, so the tangent has no
//! softening term. With the paper's split outside the plane-stress switch band and in every
//! uniaxial state the stress is then linear in ε (the secant (1 − d̃) C₀ of the side of tr σ̃),
//! so the step's equilibrium is a linear system on each side of the unilateral switch; with the
//! spectral split it is piecewise linear in the principal strains. The tangent is the exact
//! derivative of that stress (tested against finite differences below).
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
//! An element keeps, per point, the committed state and the one before it, and the size of the
//! step between them; before the evaluations of a step it computes [`extrapolate`] once per
//! point, then [`evaluate`] gives each evaluation's response: the stress, secant and tangent of
//! the extrapolated history, the trial state and dissipation of the implicit update.

use nalgebra::SVector;

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

/// The response of a point whose law is `eval` (any kinematics, local or nonlocal), from its
/// `committed` state: with `extrapolated` (IMPL-EX), [`combine`] of the frozen law at that
/// history and the implicit update; without, the implicit update alone.
#[inline]
pub fn evaluate<const N: usize>(
    law: &PointLaw,
    committed: &DamageState,
    extrapolated: Option<&DamageState>,
    eval: impl Fn(&PointLaw, &DamageState) -> Response<N>,
) -> Response<N> {
    let implicit = eval(law, committed);
    match extrapolated {
        None => implicit,
        Some(x) => combine(eval(&law.with_frozen_history(), x), implicit),
    }
}

/// [`evaluate`] for the kinematics `K` at `strain`.
#[inline]
pub fn update<const N: usize, K: StressState<N>>(
    law: &PointLaw,
    strain: &SVector<f64, N>,
    committed: &DamageState,
    extrapolated: &DamageState,
) -> Response<N> {
    evaluate(law, committed, Some(extrapolated), |l, s| K::evaluate(l, strain, s))
}

#[cfg(test)]
#[path = "implex_tests.rs"]
mod tests;
