//! Pseudo-transient continuation: the static equilibrium at a fixed load that Newton's method
//! does not reach.
//!
//! **Why Newton stops** (measured on the paper's wall with crushing, `examples/dem_peak.rs`).
//! Two situations, both at the compressive peak and after it:
//! * *alternation across kinks*: the return maps (crushing elastic/plastic, stick/slip) make the
//!   residual piecewise smooth; with several crushing contacts on their softening branch
//!   `F_y(κ) = σ_c L t_z (1 − κ/δ_u)` (tangent terms `−H k_n/(k_n − H)`), Newton's direction
//!   from one side of a kink is not one of descent for `½‖r‖²` and the line search takes its
//!   best trial: the iteration alternates between two states at a relative residual of
//!   1e-6..1e-4, at every increment down to 2⁻¹⁰ of the step, although an equilibrium lies
//!   close by;
//! * *snap-back*: a band of crushing contacts softening together turns the path back in the
//!   platen displacement; past the limit point the next equilibrium is on the post-peak branch,
//!   far away (a drop of the force at fixed platen displacement); likewise a break that leaves
//!   stones held only by sliding contacts.
//!
//! **The damped path.** Between two static states the stones would move dynamically and come to
//! rest, the kinetic energy damped. Its heavily damped limit is followed in a pseudo-time `τ`
//! (pseudo-transient continuation, Kelley & Keyes, SIAM J. Numer. Anal. 35 (1998) 508–523; the
//! masses as in Underwood's dynamic relaxation):
//!
//! ```text
//!   (K_T + σ_k M) Δz_k = r(z_k) ,   σ_k = 1/Δτ_k (dimensionless) ,   M = diag K₀
//! ```
//!
//! `M = diag K₀` (every beam intact: Underwood's fictitious masses; they make `σ` dimensionless
//! and damp each stone by its own stiffness); `r`, `K_T` the static problem's
//! ([`super::equilibrium`], [`super::tangent`]). A step is taken only if it releases energy:
//!
//! ```text
//!   downhill:  Δzᵀ r(z_k) > 0                         (first-order decrease of the energy)
//!   released:  ½ (r(z_k) + r(z_k + Δz))ᵀ Δz > 0       (trapezoid of the work of the
//!                                                     out-of-balance forces along the step)
//! ```
//!
//! (no energy function is needed, only forces; the second test rejects a step that overshoots a
//! valley, which a residual-norm test cannot tell from a step through an unstable region, where
//! the residual must grow). A rejected step multiplies `σ` by 4 (more damping) and is solved
//! again. No stone moves more than the trust radius `TRUST_RADIUS · D̄` in one step (the step is
//! scaled down); a step inside it halves `σ` (down to `SIGMA_MIN`), so near the equilibrium the
//! iteration is Newton's method with its fast convergence. `σ₀ = 1`.
//! **Converged only when the static residual meets the equilibrium test,
//! `‖r‖∞ ≤ tol · scale`** (the tolerance unchanged): the end state is a static equilibrium with
//! its own contact and stick/slip set, committed like any other. The friction and crushing
//! return maps run from the committed state, as in every increment. Beams are judged at the end
//! state (the event loop breaks any with `P ≥ 1` there, one at a time).
//!
//! The linear solve is GMRES on `K_T + σM` preconditioned by the factorization of the symmetric
//! operator with the shift `σM` in place of the regularization, refactorized when `σ` has moved
//! by more than a factor 2 since the last factorization (contact terms entering or leaving in
//! between are Woodbury terms, as in Newton's method); afterwards the unshifted operator is
//! refactorized. With updates in place ([`super::SolverOptions::factor_updates`]) the shifted
//! operators are a Woodbury operator of their own (faer's supernodal factorization: at 50k
//! stones about 1 s, against 4.5 s for CHOLMOD's simplicial one), kept between continuations;
//! the updatable factor is refactorized once, on the way back.
//! It is a fallback: one continuation costs up to `MAX_ITERATIONS` factorizations
//! of a small wall, more than Newton's method, and runs only where Newton's method failed at the
//! smallest increment.
use super::diagnostics::Diagnostics;
use super::equilibrium::{apply_load, evaluate, unbonded_stones};
use super::error::DemError;
use super::evaluation::Evaluation;
use super::gmres::{gmres, GmresInfo};
use super::operator::{Operator, Refactor};
use super::problem::Problem;
use super::records::LoadPoint;
use super::state::SolverState;
use super::tangent::Tangent;
use super::trace::{newton_step, NewtonStep};
use super::workspace::{upkeep, Workspace};

/// The initial shift `σ₀` (a step as stiff again as the intact lattice's diagonal).
const SIGMA_0: f64 = 1.0;
/// Bounds of the shift.
const SIGMA_MIN: f64 = 1e-12;
const SIGMA_MAX: f64 = 1e8;
/// The trust radius: the largest move of a stone in one iteration, as a fraction of the mean
/// stone diameter D̄.
const TRUST_RADIUS: f64 = 2e-4;
/// Iterations of one continuation.
pub(super) const MAX_ITERATIONS: usize = 600;

/// Finds the static equilibrium at `load` (plus `extra`, over `z`) from the current `z` by
/// pseudo-transient continuation (module docs); leaves the contacts of the equilibrium in
/// the state's `contacts`. Errors: [`DemError::NoConvergence`] after `MAX_ITERATIONS`.
pub(super) fn continuation(
    pb: &Problem<'_>,
    state: &mut SolverState,
    ws: &mut Workspace,
    diag: &mut Diagnostics<'_>,
    load: &LoadPoint,
    extra: Option<&[f64]>,
    t: f64,
) -> Result<(), DemError> {
    if !ws.operator.factor.updates_in_place() {
        let result = continue_to_equilibrium(pb, state, ws, diag, load, extra, t);
        // Back to the unshifted operator for the next Newton iteration.
        ws.operator.invalidate(Some(Refactor::Continuation));
        return result;
    }
    // Updates in place (module docs): the shifted operators in a Woodbury operator of their
    // own, kept between continuations; the updatable factor waits, and is refactorized once
    // for the next Newton iteration (its contact terms, held from before, would precondition
    // the contacts that moved, crushed or softened in between too poorly: measured, a
    // collapse of the paper wall's sample 3 that the refactorized one passes).
    let shifted = match ws.shifted.take() {
        Some(op) => op,
        None => Operator::new(pb.model.map.n_eq(), false, f64::INFINITY)?,
    };
    let updatable = std::mem::replace(&mut ws.operator, shifted);
    let result = continue_to_equilibrium(pb, state, ws, diag, load, extra, t);
    ws.shifted = Some(std::mem::replace(&mut ws.operator, updatable));
    ws.operator.invalidate(Some(Refactor::Continuation));
    result
}

/// The iterations of [`continuation`] with the operator in place.
fn continue_to_equilibrium(
    pb: &Problem<'_>,
    state: &mut SolverState,
    ws: &mut Workspace,
    diag: &mut Diagnostics<'_>,
    load: &LoadPoint,
    extra: Option<&[f64]>,
    t: f64,
) -> Result<(), DemError> {
    let f_ext = apply_load(pb, state, load, extra);
    let unknowns = pb.model.map.unknowns.clone();
    let events = state.broken.len();
    if let Some(tr) = diag.trace.as_mut() {
        tr.begin(state.stage, t, events, "continuation");
    }
    diag.counters.continuations += 1;
    let z0 = state.z.clone();
    let mut ev = evaluate(pb, state, ws, diag, &z0, &f_ext)?;
    let mut sigma = SIGMA_0;
    let mut factored: Option<f64> = None;
    let mut converged = false;
    let mut previous = None;
    for _ in 0..MAX_ITERATIONS {
        if ev.relative <= pb.opts.tol {
            converged = true;
            break;
        }
        diag.profile.continuation_iterations += 1;
        if factored.is_none_or(|s| sigma > 2.0 * s || sigma < 0.5 * s) {
            ws.operator.invalidate(None);
        }
        let (op, mut u, scales) = (&mut ws.operator, upkeep(pb, state, &mut diag.profile), &pb.scales);
        op.sync(&mut u, &ev.contacts)?;
        if op.is_stale() || (op.factor.rank() > 0 && !op.factor.is_accurate()) {
            let diagonal: Vec<f64> =
                scales.reg.iter().zip(&scales.intact_diagonal).map(|(r, m)| r + sigma * m).collect();
            op.refactorize(&mut u, Some(Refactor::Continuation), &diagonal)?;
            factored = Some(sigma);
        }
        let (mut dz, info) = shifted_solve(pb, state, ws, diag, &ev, sigma)?;
        let work: f64 = dz.iter().zip(&ev.r).map(|(d, r)| d * r).sum();
        let downhill = work > 0.0;
        let cap = if downhill { cap_continuation(pb, &mut dz) } else { 0.0 };
        if let Some(tr) = diag.trace.as_mut() {
            tr.step(NewtonStep {
                gmres_iterations: info.iterations,
                linear_converged: info.converged,
                cap,
                alpha: if downhill { 1.0 } else { 0.0 },
                shift: sigma,
                ..newton_step(&ev, &mut previous, &pb.model.map)
            });
        }
        if !downhill {
            sigma = (4.0 * sigma).clamp(SIGMA_MIN, SIGMA_MAX);
            continue;
        }
        let mut z = state.z.clone();
        for (e, &zi) in unknowns.iter().enumerate() {
            z[zi] += dz[e];
        }
        let trial = evaluate(pb, state, ws, diag, &z, &f_ext)?;
        // The energy the step releases, by the trapezoid of the residual along it.
        let released = 0.5 * (work * cap + dz.iter().zip(&trial.r).map(|(d, r)| d * r).sum::<f64>());
        if released <= 0.0 {
            if let Some(st) = diag.trace.as_mut().and_then(|tr| tr.attempts.back_mut()).and_then(|a| a.steps.last_mut())
            {
                st.alpha = 0.0;
            }
            sigma = (4.0 * sigma).clamp(SIGMA_MIN, SIGMA_MAX);
            continue;
        }
        ev = trial;
        state.z = z;
        if cap >= 1.0 {
            sigma = (0.5 * sigma).max(SIGMA_MIN);
        }
    }
    if let Some(tr) = diag.trace.as_mut() {
        tr.end(ev.relative, converged);
    }
    if converged {
        state.contacts = ev.contacts;
        return Ok(());
    }
    Err(DemError::NoConvergence {
        stage: state.stage,
        load: t,
        event: events,
        iterations: MAX_ITERATIONS,
        residual: ev.relative,
        unbonded: unbonded_stones(pb, state),
    })
}

/// `(K_T + σ diag K₀) Δz = r` by GMRES to 1e-8, preconditioned by the factorized shifted
/// operator; an unconverged solve with a Woodbury correction marks the operator stale.
fn shifted_solve(
    pb: &Problem<'_>,
    state: &SolverState,
    ws: &mut Workspace,
    diag: &mut Diagnostics<'_>,
    ev: &Evaluation,
    sigma: f64,
) -> Result<(Vec<f64>, GmresInfo), DemError> {
    let events = state.broken.len();
    let tangent = Tangent::new(&pb.model, state, &pb.scales.reg, &ev.contacts, &mut ws.jacobians)?;
    let mass = &pb.scales.intact_diagonal;
    let mut dz = vec![0.0; pb.model.map.n_eq()];
    let factor = &mut ws.operator.factor;
    let info = gmres(
        &mut dz,
        &ev.r,
        |v, o| {
            tangent.apply(v, o);
            for ((o, v), m) in o.iter_mut().zip(v).zip(mass) {
                *o += sigma * m * v;
            }
        },
        |v| factor.solve(v),
        1e-8,
        60,
        240,
    )
    .map_err(|e| DemError::Factorization { event: events, reason: e.0 })?;
    diag.counters.solves += info.iterations;
    if !info.converged && ws.operator.factor.rank() > 0 {
        ws.operator.invalidate(None);
    }
    Ok((dz, info))
}

/// Scales `dz` so that no stone moves by more than the trust radius; returns the scale
/// applied (1: none).
fn cap_continuation(pb: &Problem<'_>, dz: &mut [f64]) -> f64 {
    let map = &pb.model.map;
    let d_mean = pb.scales.mean_diameter;
    let big = map
        .unknowns
        .iter()
        .zip(dz.iter())
        .map(|(&zi, d)| if zi % 3 == 2 { d.abs() * d_mean } else { d.abs() })
        .fold(0.0f64, f64::max);
    let radius = TRUST_RADIUS * d_mean;
    if big > radius {
        let s = radius / big;
        dz.iter_mut().for_each(|d| *d *= s);
        return s;
    }
    1.0
}
