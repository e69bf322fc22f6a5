//! Equilibrium at a fixed load: Newton's method on the contact–friction problem (paper §2.1,
//! "Solution algorithm", step 2).
//!
//! ```text
//!   r(z) = f_ext + f_extra − f_int(z) − ε (z − z_commit)      (unknown rows)
//!   repeat:
//!     contacts and friction at z: overlap, F_n, return map from the committed F_t
//!     ‖r‖∞ ≤ tol · scale  → converged
//!     K_T Δz = r           (consistent tangent, GMRES preconditioned by the factorized
//!                           symmetric part M, its products v + D M⁻¹v with D = K_T − M the
//!                           contacts' part only; one direct solve when no contact is active;
//!                           a sparse LU of the assembled K_T when GMRES misses its tolerance)
//!     Δz capped: no stone moves more than `max_move` (translation, or rotation × D̄) per iteration
//!     no contact at z, at z + Δz nor at the committed state, Δz not capped: z + Δz is the
//!                  equilibrium (the linear phase, [`super::linear`]: no confirming residual)
//!     line search: z + α Δz, α = 1, ½, ¼ … (6 tries) until the merit ½‖r‖² decreases by
//!                  the Armijo factor (1 − 10⁻⁴ α); otherwise the trial with the smallest merit
//! ```
//!
//! `f_int` holds the intact beams (linear) and the contacts (overlap area, Coulomb return map
//! from the last committed state: path dependence enters only through `F_t,commit`, `z_commit`).
//! The residual is measured with the same contact evaluation the next iteration uses, so
//! "converged" means the state *is* in equilibrium with its own contact and stick/slip set.
//! Along a line search the beams' forces are `K_b z₀ + α K_b Δz` (one product per search; the
//! beam law is linear, so these are the forces at `z₀ + α Δz` to round-off).
//!
//! The merit function weighs the moment rows by `1/D̄` (D̄ = mean stone diameter), so forces and
//! moments count in the same unit. The scale of the convergence test is the largest internal or
//! external generalized force at the state, and at least
//!
//! - `10⁻⁹ Ē t_z W`;
//! - a tenth of the largest platen force of the test so far (the load level of the test: at a
//!   cyclic reversal the current forces pass through zero, where a scale taken from them alone
//!   would ask for an absolute equilibrium far below anything the test resolves, the role of
//!   the time-averaged force in Abaqus' criterion);
//! - `f_ε / tol`, with
//!
//! ```text
//!   f_ε = 64 ε_mach · X · Ē t_z        (X: the largest vertex coordinate of the sample)
//! ```
//!
//! the round-off of the contact law: overlaps are clipped from absolute vertex coordinates, so a
//! contact's force carries an error of a few `ε_mach X` times its stiffness `Ē t_z L/ℓ_c ≈ Ē t_z`
//! (about 10⁻⁶ N for a 1 m wall of Ē = 2.5 GPa; `f_ε` ≈ 6.6·10⁻⁵ N). Near a load reversal the
//! forces in a cracked wall fall to a few newtons, where `tol · scale` would ask the residual to
//! go below that noise and Newton's method stalls at it; the floor accepts a residual at the
//! level of round-off instead. Under load (`scale` above `f_ε / tol`, a few kN) it never binds.
//!
//! **When GMRES misses its tolerance.** Where stones have lost every beam and are held by many
//! sliding contacts, `K_T` is far from `M` (the slip coupling is non-symmetric and the sliding
//! directions have almost no stiffness) and GMRES(60) can stall after its 240 products. Newton's
//! method driven by such an unconverged direction stalls too: on a calibration point of
//! `identify-wall.toml` (seed 8, 45 loose stones, 24 sliding contacts) it stopped at a relative
//! residual of 2·10⁻⁸ against a tolerance of 10⁻⁸ at every increment, so every load step fell
//! back to the continuation at the smallest increment and the test crawled on for hours. The
//! step is then solved directly instead, by a sparse LU of the assembled tangent with row
//! pivoting ([`Tangent::solve_direct`]; a fresh analysis and factorization each time, so only
//! where GMRES failed, counted in `SolverProfile::direct_solves`): the same sample ends by loss
//! of load in 20 s.
//!
//! **Where the tolerance meets the stones' chatter.** The test is on the largest residual of
//! any stone against the sample's force scale, so a large sample asks the same absolute
//! equilibrium of its loosest stone as of its loaded ones. In the post-peak cascade of a
//! 50k-stone sample in tension (1 m², stones of 4.5 mm, scale 1.7·10⁴ N) the crack holds stones
//! that touch their neighbours with `F_n` of 10⁻⁴–10⁻³ N (10⁻⁷ of the load, 2–20 `f_ε`). Their
//! contacts flip between stick and slip from one Newton iteration to the next (about 15 of 300
//! per iteration, moves of 10⁻¹³ m), and the largest residual, 0.3–1.4 mN at such a stone, cycles
//! at 2–8·10⁻⁸ of the scale: neither Newton's method nor the continuation goes below it, with
//! converged GMRES steps. The trace ([`super::trace`]) names the stone of the largest residual
//! and the contacts that changed. `SolverOptions::tol` is the user's choice: at 10⁻⁷ the same
//! sample runs to loss of load (543 breaks, no continuation), and a 10k sample's tension test
//! gives the same breaks at the same states as at 10⁻⁸, its stresses within 4·10⁻⁹ of the peak.
//!
//! If the iterations do not converge in `max_iterations`, [`DemError::NoConvergence`] is returned
//! with the stones that have no intact beam left (the usual cause: a stone held only by contacts
//! that slide, or by nothing): the caller cuts the load increment back.
use super::contact_set;
use super::diagnostics::Diagnostics;
use super::error::DemError;
use super::evaluation::Evaluation;
use super::gmres::{gmres_split, ForcingSequence};
use super::linear::linear_step;
use super::operator::Refactor;
use super::problem::Problem;
use super::profile;
use super::records::LoadPoint;
use super::state::SolverState;
use super::tangent::Tangent;
use super::trace::{newton_step, NewtonStep};
use super::workspace::{upkeep, Workspace};
use std::time::Instant;

/// The floor of the convergence scale relative to the largest platen force of the test so far
/// (module docs).
const REFERENCE_FRACTION: f64 = 0.1;

/// Residual entries below this fraction of the tolerance (`tol · scale`) are left out of a
/// sparse right-hand side ([`super::factor`], "Sparse right-hand sides"): the state the step
/// reaches keeps them as its residual, `10⁻⁵` of what convergence allows.
///
/// A release's residual is the broken beam's force on 6 unknowns (`10⁻⁸–10⁻² · scale`) over the
/// previous solves' round-off, which on a 10k-stone lattice lies between `10⁻¹⁶` and `10⁻¹²` of
/// the scale on thousands of unknowns (absolute displacements times stiffnesses). The lower
/// the threshold, the more of that tail is solved for; the higher, the more of it stays as
/// residual, which the lattice's conditioning turns into stresses off by more. Measured over
/// 1,500 contact-free breaks of the 10k sample (`examples/dem_profile.rs`), against dense solves
/// (with CHOLMOD's own sparse solve, `cholmod_solve2` with `Bset`, which visits the same columns
/// as [`super::cholmod::UpdatableCholesky::solve_sparse`] but spent 0.44 ms per solve finding
/// them):
///
/// | drop      | sparse solves | columns visited | stress difference / peak | same breaks |
/// |-----------|---------------|-----------------|--------------------------|-------------|
/// | `10⁻⁶`    | 1,113 of 2,098 | 31 %           | (not measured)           |             |
/// | `10⁻⁵`    | 1,672          | 16 %           | 8.5·10⁻¹⁰                | yes         |
/// | `3·10⁻⁵`  | 1,860          | 13 %           | 3.4·10⁻⁹                 | yes         |
/// | `10⁻⁴`    | 2,028          | 14 %           | 1.5·10⁻⁸                 | yes         |
///
/// `10⁻⁵` solves within 3 % of `10⁻⁴`'s time and keeps the curve ten times closer.
const SPARSE_RHS_DROP: f64 = 1e-5;

/// A right-hand side is solved as sparse when at most `1/SPARSE_RHS_FEW` of its entries are
/// kept. Beyond that the reach is most of `L`: on the 10k sample without this limit every
/// solve was sparse and visited 39 % of the columns on average, no faster within the noise
/// (10.5–11.3 against 10.8–11.3 ms per break), and the curve moved by `1.3·10⁻⁹` of the peak
/// instead of `8.5·10⁻¹⁰`.
const SPARSE_RHS_FEW: usize = 8;

/// Finds equilibrium at `load` plus the extra external forces `extra` (over `z`, e.g. a
/// broken beam's force being released), starting from the current `z` (Newton's method, module
/// docs); leaves the contacts of the equilibrium state in the state's `contacts`. Its work is
/// booked to the current phase, or to the cut-backs when it does not converge
/// ([`super::phases`]).
pub(super) fn equilibrate(
    pb: &Problem<'_>,
    state: &mut SolverState,
    ws: &mut Workspace,
    diag: &mut Diagnostics<'_>,
    load: &LoadPoint,
    extra: Option<&[f64]>,
    t: f64,
) -> Result<(), DemError> {
    let (before, clock) = (diag.profile.running(), Instant::now());
    let out = newton(pb, state, ws, diag, load, extra, t);
    let mut w = diag.profile.running().since(&before);
    w.equilibria = 1;
    w.seconds = clock.elapsed().as_secs_f64();
    let failed = matches!(out, Err(DemError::NoConvergence { .. }));
    diag.profile.phases.book(diag.phase, failed, &w);
    out
}

/// The residual at `z` for the external forces `f_ext` (over `z`).
pub(super) fn evaluate(
    pb: &Problem<'_>,
    state: &SolverState,
    ws: &mut Workspace,
    diag: &mut Diagnostics<'_>,
    z: &[f64],
    f_ext: &[f64],
) -> Result<Evaluation, DemError> {
    let clock = Instant::now();
    let mut beam_forces = vec![0.0; pb.model.map.n_z];
    pb.model.add_beam_forces(&state.intact, z, &mut beam_forces);
    profile::add(&mut diag.profile.evaluate_seconds, clock.elapsed());
    evaluate_with_beams(pb, state, ws, diag, z, f_ext, beam_forces)
}

/// [`evaluate`] with the beams' forces at `z` given (e.g. `K_b (z₀ + α Δz)` as
/// `K_b z₀ + α K_b Δz` along a line search: the beam law is linear).
fn evaluate_with_beams(
    pb: &Problem<'_>,
    state: &SolverState,
    ws: &mut Workspace,
    diag: &mut Diagnostics<'_>,
    z: &[f64],
    f_ext: &[f64],
    beam_forces: Vec<f64>,
) -> Result<Evaluation, DemError> {
    let clock = Instant::now();
    let pairs = if pb.opts.contacts && !state.broken.is_empty() {
        ws.candidates.candidates(pb.model.sample, &pb.model.map, z, &state.intact)
    } else {
        Vec::new()
    };
    diag.profile.pair_evaluations += pairs.len();
    diag.profile.candidate_rebuilds = ws.candidates.rebuilds;
    let ev = evaluate_at(pb, state, z, f_ext, &pairs, beam_forces);
    if let Ok(e) = &ev {
        if !pairs.is_empty() {
            let touching: Vec<(usize, usize)> = e.contacts.iter().map(|a| (a.i, a.j)).collect();
            ws.candidates.refresh_apart(pb.model.sample, &pb.model.map, z, &touching);
        }
    }
    diag.profile.evaluations += 1;
    profile::add(&mut diag.profile.evaluate_seconds, clock.elapsed());
    ev
}

/// Raises the reference force of the convergence scale (module docs) to a tenth of the
/// platen forces `pf` of a recorded state.
pub(super) fn raise_reference_force(state: &mut SolverState, pf: &[[f64; 3]; 2]) {
    for f in pf {
        state.reference_force = state.reference_force.max(REFERENCE_FRACTION * f[0].abs().max(f[1].abs()));
    }
}

/// The residual at `z` with the contact law evaluated on the candidate `pairs`
/// ([`super::contact_candidates`]).
fn evaluate_at(
    pb: &Problem<'_>,
    state: &SolverState,
    z: &[f64],
    f_ext: &[f64],
    pairs: &[(usize, usize)],
    beam_forces: Vec<f64>,
) -> Result<Evaluation, DemError> {
    let contacts = contact_set::evaluate(
        pb.model.sample,
        &pb.model.map,
        &pb.model.params,
        pairs,
        z,
        &state.z_commit,
        &state.histories,
    )?;
    let mut f = beam_forces.clone();
    contact_set::add_contact_forces(&pb.model.map, &contacts, &mut f);
    let map = &pb.model.map;
    let mut r = vec![0.0; map.n_eq()];
    let mut scale = (1e-9 * pb.model.params.e_bar * pb.model.params.t_z * pb.model.sample.width)
        .max(pb.scales.roundoff_force / pb.opts.tol)
        .max(state.reference_force);
    for v in f.iter().chain(f_ext.iter()) {
        scale = scale.max(v.abs());
    }
    let (mut inf, mut merit) = (0.0f64, 0.0);
    for (e, &zi) in map.unknowns.iter().enumerate() {
        r[e] = f_ext[zi] - f[zi] - pb.scales.reg[e] * (z[zi] - state.z_commit[zi]);
        inf = inf.max(r[e].abs());
        let w = if zi % 3 == 2 { 1.0 / pb.scales.mean_diameter } else { 1.0 };
        merit += 0.5 * (w * r[e]).powi(2);
    }
    Ok(Evaluation { contacts, r, relative: inf / scale, merit, beam_forces })
}

/// Newton's method for [`equilibrate`] (module docs).
fn newton(
    pb: &Problem<'_>,
    state: &mut SolverState,
    ws: &mut Workspace,
    diag: &mut Diagnostics<'_>,
    load: &LoadPoint,
    extra: Option<&[f64]>,
    t: f64,
) -> Result<(), DemError> {
    let f_ext = apply_load(pb, state, load, extra);
    let (stage, events) = (state.stage, state.broken.len());
    let z0 = state.z.clone();
    let mut ev = evaluate(pb, state, ws, diag, &z0, &f_ext)?;
    let mut forcing = ForcingSequence::new(pb.opts.forcing);
    if let Some(tr) = diag.trace.as_mut() {
        tr.begin(stage, t, events, if extra.is_some() { "release" } else { "load" });
    }
    let mut previous: Option<Vec<(usize, usize, bool)>> = None;
    for iteration in 0..pb.opts.max_iterations {
        ws.jacobians.fresh_only = iteration >= super::tangent::FRESH_AFTER;
        if ev.relative <= pb.opts.tol {
            break;
        }
        let mut step = diag.trace.as_ref().map(|_| newton_step(&ev, &mut previous, &pb.model.map));
        diag.profile.newton_iterations += 1;
        ws.operator.sync(&mut upkeep(pb, state, &mut diag.profile), &ev.contacts)?;
        ws.operator.refresh(&mut upkeep(pb, state, &mut diag.profile), &pb.scales.reg)?;
        let factor = &ws.operator.factor;
        diag.profile.max_rank = diag.profile.max_rank.max(factor.rank());
        diag.profile.columns_added = factor.n_columns;
        diag.profile.columns_dropped = factor.n_dropped;
        // The linear solve's tolerance (Eisenstat–Walker by default; the goal: ‖r‖∞ at
        // convergence, tol · scale = tol ‖r‖∞ / relative).
        let r2 = ev.r.iter().map(|x| x * x).sum::<f64>().sqrt();
        let r_inf = ev.r.iter().fold(0.0f64, |m, x| m.max(x.abs()));
        let eta = forcing.next(r2, if ev.relative > 0.0 { pb.opts.tol * r_inf / ev.relative } else { 0.0 });
        if factor.rank() > 0 && !factor.is_accurate() {
            // A near-singular Woodbury capacitance matrix: drop the correction.
            let mut u = upkeep(pb, state, &mut diag.profile);
            ws.operator.refactorize(&mut u, Some(Refactor::Accuracy), &pb.scales.reg)?;
        }
        let mut dz = newton_direction(pb, state, ws, diag, &ev, eta, step.as_mut())?;
        let cap = cap_step(pb, &mut dz);
        if iteration == 0 && cap == 1.0 && ev.contacts.is_empty() && linear_step(pb, state, ws, diag, &dz)? {
            // The linear phase: the step is the equilibrium ([`super::linear`]); its
            // residual is not evaluated (NaN in the trace).
            if let (Some(tr), Some(st)) = (diag.trace.as_mut(), step) {
                tr.step(st);
                tr.end(f64::NAN, true);
            }
            state.contacts = Vec::new();
            return Ok(());
        }
        let alpha;
        (ev, alpha) = line_search(pb, state, ws, diag, &dz, &f_ext, ev)?;
        if let (Some(tr), Some(mut st)) = (diag.trace.as_mut(), step) {
            st.cap = cap;
            st.alpha = alpha;
            tr.step(st);
        }
    }
    let converged = ev.relative <= pb.opts.tol;
    if let Some(tr) = diag.trace.as_mut() {
        tr.end(ev.relative, converged);
    }
    if converged {
        state.contacts = ev.contacts;
        return Ok(());
    }
    Err(DemError::NoConvergence {
        stage,
        load: t,
        event: events,
        iterations: pb.opts.max_iterations,
        residual: ev.relative,
        unbonded: unbonded_stones(pb, state),
    })
}

/// Puts the prescribed platen values of `load` into `z` and returns the external forces
/// (over `z`): `load`'s forces plus `extra`.
pub(super) fn apply_load(
    pb: &Problem<'_>,
    state: &mut SolverState,
    load: &LoadPoint,
    extra: Option<&[f64]>,
) -> Vec<f64> {
    let map = &pb.model.map;
    for (k, &zi) in map.prescribed.iter().enumerate() {
        state.z[zi] = load.prescribed[k];
    }
    let mut f_ext = extra.map_or_else(|| vec![0.0; map.n_z], |x| x.to_vec());
    for (k, &zi) in map.forced.iter().enumerate() {
        f_ext[zi] += load.forces[k];
    }
    f_ext
}

/// Newton's direction `K_T Δz = r` at the evaluation `ev`: one solve with the factorized
/// operator when no contact is active (then `K_T = M`); else GMRES to the relative tolerance
/// `eta`, preconditioned by `M`, with a direct sparse LU of `K_T` where GMRES misses it
/// (module docs). The trace's `step` gets the GMRES figures.
pub(super) fn newton_direction(
    pb: &Problem<'_>,
    state: &SolverState,
    ws: &mut Workspace,
    diag: &mut Diagnostics<'_>,
    ev: &Evaluation,
    eta: f64,
    step: Option<&mut NewtonStep>,
) -> Result<Vec<f64>, DemError> {
    let events = state.broken.len();
    let fail = |e: super::factor::FactorError| DemError::Factorization { event: events, reason: e.0 };
    let mut dz = ev.r.clone();
    if ev.contacts.is_empty() {
        let clock = Instant::now();
        let support = sparse_support(pb, ws, ev);
        let sparse = match &support {
            Some(s) => ws.operator.factor.solve_sparse(&mut dz, s).map_err(fail)?,
            None => None,
        };
        match sparse {
            Some(columns) => {
                diag.profile.sparse_solves += 1;
                diag.profile.sparse_columns += columns;
            }
            None => ws.operator.factor.solve(&mut dz).map_err(fail)?,
        }
        diag.counters.solves += 1;
        profile::add(&mut diag.profile.solve_seconds, clock.elapsed());
        return Ok(dz);
    }
    let clock = Instant::now();
    let tangent = Tangent::new(&pb.model, state, &pb.scales.reg, &ev.contacts, &mut ws.jacobians)?;
    let jc = &ws.jacobians;
    let p = &mut diag.profile;
    (p.jacobians_computed, p.jacobians_reused) = (jc.computed, jc.reused);
    p.jacobians_on_cone = jc.on_cone;
    // Inexact Newton: the linear solve to η ‖r‖ (`SolverOptions::forcing`; a fixed 1e-6 lost
    // two of the paper wall's 16 shear samples, a fixed 1e-8 was the former default).
    // D = K_T − M: GMRES's products cost O(contacts) (`gmres_split`).
    let op = &mut ws.operator;
    let difference = tangent.difference(&ev.contacts, |i, j| op.held(i, j));
    profile::add(&mut p.tangent_seconds, clock.elapsed());
    let clock = Instant::now();
    let factor = &mut op.factor;
    let copy_from = pb.opts.preconditioner_copy_from;
    let mut in_precond = std::time::Duration::ZERO;
    dz.iter_mut().for_each(|x| *x = 0.0);
    let info = gmres_split(
        &mut dz,
        &ev.r,
        |v, o| tangent.apply(v, o),
        |v, o| difference.apply(v, o),
        |v| {
            let c = Instant::now();
            let r = factor.precondition(v, copy_from);
            in_precond += c.elapsed();
            r
        },
        eta,
        60,
        240,
    )
    .map_err(fail)?;
    diag.counters.solves += info.iterations;
    p.gmres_solves += 1;
    p.gmres_iterations += info.iterations;
    p.preconditioner_copies = op.factor.copies();
    let sliding = ev.contacts.iter().filter(|a| !a.sticks()).count();
    p.sliding_at_gmres += sliding;
    p.contacts_at_gmres += ev.contacts.len();
    p.phases.gmres_step(sliding, info.iterations);
    profile::add(&mut p.solve_seconds, in_precond);
    profile::add(&mut p.gmres_seconds, clock.elapsed().saturating_sub(in_precond));
    let mut linear_converged = info.converged;
    if !info.converged {
        if op.factor.rank() > 0 {
            // An inaccurate Woodbury correction: start the next iteration afresh.
            op.invalidate(Some(Refactor::Accuracy));
        }
        // GMRES missed its tolerance (a tangent far from the preconditioner's: many sliding
        // contacts around stones with no intact beam): Newton's step by a direct solve of
        // the assembled tangent, so that the iteration is not driven by an unconverged
        // direction.
        let clock = Instant::now();
        if let Some(x) = tangent.solve_direct(&ev.r) {
            dz = x;
            p.direct_solves += 1;
            linear_converged = true;
        }
        profile::add(&mut p.solve_seconds, clock.elapsed());
    }
    if let Some(st) = step {
        st.gmres_iterations = info.iterations;
        st.linear_converged = linear_converged;
    }
    Ok(dz)
}

/// The unknowns where the residual of `ev` passes `SPARSE_RHS_DROP · tol · scale`, when
/// they are few enough (at most `n / SPARSE_RHS_FEW`) for a solve over their reach to pay
/// ([`super::factor`], "Sparse right-hand sides"); `None`: solve densely.
///
/// **Not with crushing**, like the step predictor ([`super::step_predictor`]): past the
/// peak, crushing contacts soften and which equilibrium Newton's method finds depends on
/// differences far below its tolerance. On the paper's wall with crushing
/// (`crushing_tests.rs`, seed 4, updates in place) the residual the sparse step leaves
/// (`10⁻¹³` of the scale) turned the loss of load into a collapse at event 78.
fn sparse_support(pb: &Problem<'_>, ws: &Workspace, ev: &Evaluation) -> Option<Vec<usize>> {
    let crushing = pb.model.params.crushing.is_some();
    if !pb.opts.sparse_rhs || crushing || !ws.operator.factor.updates_in_place() || ev.relative <= 0.0 {
        return None;
    }
    let r_inf = ev.r.iter().fold(0.0f64, |m, x| m.max(x.abs()));
    let drop = SPARSE_RHS_DROP * pb.opts.tol * r_inf / ev.relative;
    let few = ev.r.len() / SPARSE_RHS_FEW;
    let mut support = Vec::new();
    for (e, x) in ev.r.iter().enumerate() {
        if x.abs() > drop {
            if support.len() == few {
                return None;
            }
            support.push(e);
        }
    }
    Some(support)
}

/// Scales `dz` so that no stone moves by more than `max_move` in one iteration; returns the
/// scale applied (1: none).
fn cap_step(pb: &Problem<'_>, dz: &mut [f64]) -> f64 {
    let map = &pb.model.map;
    let big = map
        .unknowns
        .iter()
        .zip(dz.iter())
        .map(|(&zi, d)| if zi % 3 == 2 { d.abs() * pb.scales.mean_diameter } else { d.abs() })
        .fold(0.0f64, f64::max);
    if big > pb.scales.max_move {
        let s = pb.scales.max_move / big;
        dz.iter_mut().for_each(|d| *d *= s);
        return s;
    }
    1.0
}

/// Backtracking on the merit function along `dz`; moves the state's `z` and returns the
/// evaluation at the accepted point and the step length taken.
///
/// The beams' forces along the line are `K_b z₀ + α K_b Δz` (one product `K_b Δz` per
/// search, the beam law being linear; the same forces as `K_b z` to round-off).
fn line_search(
    pb: &Problem<'_>,
    state: &mut SolverState,
    ws: &mut Workspace,
    diag: &mut Diagnostics<'_>,
    dz: &[f64],
    f_ext: &[f64],
    ev0: Evaluation,
) -> Result<(Evaluation, f64), DemError> {
    let base = state.z.clone();
    let unknowns = pb.model.map.unknowns.clone();
    let clock = Instant::now();
    let mut dz_z = vec![0.0; pb.model.map.n_z];
    for (e, &zi) in unknowns.iter().enumerate() {
        dz_z[zi] = dz[e];
    }
    let mut k_dz = vec![0.0; pb.model.map.n_z];
    pb.model.add_beam_forces(&state.intact, &dz_z, &mut k_dz);
    profile::add(&mut diag.profile.evaluate_seconds, clock.elapsed());
    let mut best: Option<(f64, Evaluation)> = None;
    let mut alpha = 1.0;
    for _ in 0..6 {
        let mut z = base.clone();
        for (e, &zi) in unknowns.iter().enumerate() {
            z[zi] += alpha * dz[e];
        }
        let beams = ev0.beam_forces.iter().zip(&k_dz).map(|(f, k)| f + alpha * k).collect();
        let ev = evaluate_with_beams(pb, state, ws, diag, &z, f_ext, beams)?;
        let accept = ev.merit <= (1.0 - 1e-4 * alpha) * ev0.merit;
        if best.as_ref().is_none_or(|(_, b)| ev.merit < b.merit) {
            best = Some((alpha, ev));
        }
        if accept {
            break;
        }
        alpha *= 0.5;
    }
    match best {
        Some((a, ev)) => {
            for (e, &zi) in unknowns.iter().enumerate() {
                state.z[zi] = base[zi] + a * dz[e];
            }
            Ok((ev, a))
        }
        None => Ok((ev0, 0.0)),
    }
}

/// Stones (not bonded to a platen) without any intact beam.
pub(super) fn unbonded_stones(pb: &Problem<'_>, state: &SolverState) -> Vec<usize> {
    let s = pb.model.sample;
    (0..s.particles.len())
        .filter(|&p| !pb.model.map.is_slave(p) && !s.neighbours[p].iter().any(|&(_, b)| state.intact[b]))
        .collect()
}
