//! Beam breaks: where along a load step the first intact beam reaches its failure index, which
//! beam is the most critical at a state, and the break itself with the quasi-static release of
//! the beam's force (paper §2.1, "Solution algorithm", steps 2–4).
//!
//! ```text
//!   λ* = min over intact beams of  failure_lambda(z_old → z)       (P piecewise linear in λ)
//!                                  crushing_lambda(z_old → z)      (P_c = −Ē ε/σ_c, with crushing)
//!   after a break: while some intact beam has max(P, P_c) ≥ 1, break the largest and relax
//! ```
//!
//! **Several breaks per equilibrium (opt-in, approximate).** With
//! [`super::SolverOptions::breaks_per_equilibrium`] `= n > 1`, a cascade breaks the `n` most
//! critical beams with `P ≥ 1` at once and re-equilibrates once, instead of breaking the most
//! critical one and re-equilibrating before the next. A load step still stops at the first beam
//! to reach `P = 1` (no beam breaks before it is overloaded at an equilibrium: a window of
//! several first crossings along the step, broken together at the load of the last, raised the
//! paper wall's tensile peak by 6.5 % on average at `n = 4`). What is lost is the order inside a
//! cascade: a beam that the release of a more critical one would have unloaded breaks anyway.
//! `n = 1` is paper §2.1's algorithm, bit for bit.

use std::time::Instant;

use super::continuation::continuation;
use super::diagnostics::Diagnostics;
use super::energy::commit;
use super::equilibrium::equilibrate;
use super::error::DemError;
use super::options::FloatingPolicy;
use super::phases::Phase;
use super::problem::Problem;
use super::profile;
use super::records::{BrokenBeam, FailureModeTag, LoadPoint, StateKind};
use super::state::SolverState;
use super::workspace::{upkeep, Workspace};
use crate::dem::mechanics::{failure_index, failure_lambda, failure_mode, FailureMode};

/// The crushing index `P_c = −Ē ε/σ_c` of beam `b` at `z` (−∞ without crushing).
fn crushing_index(pb: &Problem<'_>, b: usize, z: &[f64]) -> f64 {
    let Some(c) = &pb.model.params.crushing else { return f64::NEG_INFINITY };
    let (qi, qj) = pb.model.beam_dofs(b, z);
    let g = &pb.model.geoms[b];
    c.beam_index(pb.model.params.e_bar, g.delta_n(qi, qj) / g.ell)
}

/// The smallest crushing fraction of beam `b` along `z_a → z_b` (`None` without crushing).
fn crushing_lambda(pb: &Problem<'_>, b: usize, z_a: &[f64], z_b: &[f64]) -> Option<f64> {
    let c = pb.model.params.crushing.as_ref()?;
    let g = &pb.model.geoms[b];
    let (q0i, q0j) = pb.model.beam_dofs(b, z_a);
    let (q1i, q1j) = pb.model.beam_dofs(b, z_b);
    let (e0, e1) = (g.delta_n(q0i, q0j) / g.ell, g.delta_n(q1i, q1j) / g.ell);
    c.beam_lambda(pb.model.params.e_bar, e0, e1 - e0)
}

/// The beam that reaches its failure index first along `z_old → z`, inside the step
/// (`λ < 1`), with its `λ` (ties by beam index). One beam even with
/// [`super::SolverOptions::breaks_per_equilibrium`] `> 1`: no beam breaks before it reaches
/// `P = 1` (module docs).
pub(super) fn first_failure(
    pb: &Problem<'_>,
    state: &SolverState,
    diag: &mut Diagnostics<'_>,
    z_old: &[f64],
) -> Option<(f64, usize)> {
    let clock = Instant::now();
    let first = first_crossing_on_chord(pb, &state.intact, z_old, &state.z, 1.0);
    profile::add(&mut diag.profile.failure_seconds, clock.elapsed());
    diag.profile.failure_scans += 1;
    first
}

/// The intact beam that reaches its failure index (or crushing index) first along the chord
/// `z_a + μ (z_b − z_a)`, `μ ∈ [0, reach]`, with its `μ < reach` (ties by beam index). Both
/// indices are piecewise linear in `μ` (the beam law is linear in the end displacements), so
/// the crossing is closed-form: the chord stretched by `reach` is handed to
/// [`failure_lambda`], and its fraction scaled back.
pub(super) fn first_crossing_on_chord(
    pb: &Problem<'_>,
    intact: &[bool],
    z_a: &[f64],
    z_b: &[f64],
    reach: f64,
) -> Option<(f64, usize)> {
    let mut first: Option<(f64, usize)> = None;
    let z_far: Vec<f64>;
    let z_end = if reach == 1.0 {
        z_b
    } else {
        z_far = z_a.iter().zip(z_b).map(|(a, b)| a + reach * (b - a)).collect();
        &z_far
    };
    for b in (0..intact.len()).filter(|&b| intact[b]) {
        let (q0i, q0j) = pb.model.beam_dofs(b, z_a);
        let (q1i, q1j) = pb.model.beam_dofs(b, z_end);
        let d = |a: [f64; 3], c: [f64; 3]| [a[0] - c[0], a[1] - c[1], a[2] - c[2]];
        let lambdas = [
            failure_lambda(&pb.model.geoms[b], &pb.model.thresholds, q0i, q0j, d(q1i, q0i), d(q1j, q0j)),
            crushing_lambda(pb, b, z_a, z_end),
        ];
        let Some(l) = lambdas.into_iter().flatten().reduce(f64::min) else { continue };
        if l >= 1.0 || first.is_some_and(|(fl, _)| l >= fl) {
            continue;
        }
        first = Some((l, b));
    }
    first.map(|(l, b)| (l * reach, b))
}

/// The largest failure index (or crushing index) of the intact beams at `z`, with its beam
/// (ties by beam index; `(−∞, usize::MAX)` with no intact beam).
pub(super) fn largest_index(pb: &Problem<'_>, intact: &[bool], z: &[f64]) -> (f64, usize) {
    let mut worst = (f64::NEG_INFINITY, usize::MAX);
    for b in (0..intact.len()).filter(|&b| intact[b]) {
        let (qi, qj) = pb.model.beam_dofs(b, z);
        let p = failure_index(&pb.model.geoms[b], &pb.model.thresholds, qi, qj).max(crushing_index(pb, b, z));
        if p > worst.0 {
            worst = (p, b);
        }
    }
    worst
}

/// The intact beams with `P ≥ 1` at the current state, the most critical first (ties by
/// beam index): at most [`super::SolverOptions::breaks_per_equilibrium`] of them.
fn most_critical(pb: &Problem<'_>, state: &SolverState, diag: &mut Diagnostics<'_>) -> Vec<usize> {
    let clock = Instant::now();
    let b = scan_most_critical(pb, state, pb.opts.breaks_per_equilibrium.max(1));
    profile::add(&mut diag.profile.failure_seconds, clock.elapsed());
    diag.profile.failure_scans += 1;
    b
}

fn scan_most_critical(pb: &Problem<'_>, state: &SolverState, n: usize) -> Vec<usize> {
    // The n largest (P, b) with P ≥ 1, by decreasing P.
    let mut worst: Vec<(f64, usize)> = Vec::with_capacity(n + 1);
    let (z, intact) = (&state.z, &state.intact);
    for b in (0..intact.len()).filter(|&b| intact[b]) {
        let (qi, qj) = pb.model.beam_dofs(b, z);
        let p = failure_index(&pb.model.geoms[b], &pb.model.thresholds, qi, qj).max(crushing_index(pb, b, z));
        if p < 1.0 || (worst.len() == n && p <= worst[n - 1].0) {
            continue;
        }
        let at = worst.partition_point(|&(wp, _)| wp >= p);
        worst.insert(at, (p, b));
        worst.truncate(n);
    }
    worst.into_iter().map(|(_, b)| b).collect()
}

/// Breaks beam `b` now (e.g. a pre-cracked sample), re-equilibrates at the current load and
/// records the state ([`super::Solver::break_and_relax`]).
pub(super) fn break_and_relax(
    pb: &Problem<'_>,
    state: &mut SolverState,
    ws: &mut Workspace,
    diag: &mut Diagnostics<'_>,
    b: usize,
) -> Result<(), DemError> {
    if b >= state.intact.len() || !state.intact[b] {
        return Err(DemError::InvalidParameter {
            field: "beam",
            value: b.to_string(),
            expected: "the index of an intact beam",
        });
    }
    let l = state.load.clone();
    diag.phase = Phase::Release;
    release(pb, state, ws, diag, &[b], &l, 1.0)
}

/// Breaks the beams `first` (none: the most critical ones), then the beams with `P ≥ 1`,
/// each group released and relaxed at the fixed `load` ([`release`]): one beam at a time, or
/// up to [`super::SolverOptions::breaks_per_equilibrium`] together.
pub(super) fn break_cascade(
    pb: &Problem<'_>,
    state: &mut SolverState,
    ws: &mut Workspace,
    diag: &mut Diagnostics<'_>,
    first: Vec<usize>,
    load: &LoadPoint,
    t: f64,
) -> Result<(), DemError> {
    diag.phase = if first.is_empty() { Phase::Cascade } else { Phase::Release };
    let mut next = if first.is_empty() { most_critical(pb, state, diag) } else { first };
    while !next.is_empty() {
        release(pb, state, ws, diag, &next, load, t)?;
        diag.phase = Phase::Cascade;
        next = most_critical(pb, state, diag);
    }
    Ok(())
}

/// Breaks the beams `beams` at the committed state and re-equilibrates at the fixed `load`,
/// then records the relaxed state.
///
/// **Release path.** The beams' forces at the committed state, `f_b`, are released along
/// `f_extra(s) = (1 − s) f_b`, `s: 0 → 1`: at `s = 0` the committed state is in equilibrium,
/// at `s = 1` the beams are gone. One step `s = 1` first; if Newton fails, the release is cut
/// back (halved, at most `max_cutbacks` times), each intermediate equilibrium committed
/// (friction history) but not recorded. This is the quasi-static path a dynamic release
/// would follow with heavy damping, and it lets the contact and stick/slip sets change
/// gradually when a break redistributes much load.
fn release(
    pb: &Problem<'_>,
    state: &mut SolverState,
    ws: &mut Workspace,
    diag: &mut Diagnostics<'_>,
    beams: &[usize],
    load: &LoadPoint,
    t: f64,
) -> Result<(), DemError> {
    let mut f_b = vec![0.0; pb.model.map.n_z];
    for &b in beams {
        pb.model.add_beam_force(b, &state.z, &mut f_b);
    }
    for &b in beams {
        break_beam(pb, state, ws, diag, b)?;
    }
    let (mut s, mut h) = (0.0f64, 1.0f64);
    let h_min = 0.5f64.powi(pb.opts.max_cutbacks as i32);
    while s < 1.0 {
        let s_try = (s + h).min(1.0);
        let extra: Vec<f64> = f_b.iter().map(|f| (1.0 - s_try) * f).collect();
        match equilibrate(pb, state, ws, diag, load, Some(&extra), t) {
            Ok(()) => {
                s = s_try;
                if s < 1.0 {
                    state.accept();
                }
                h = (2.0 * h).min(1.0);
            }
            Err(e @ DemError::NoConvergence { .. }) => {
                state.restore();
                h *= 0.5;
                diag.counters.cutbacks += 1;
                if h < h_min {
                    // No equilibrium near the path: the full release by pseudo-transient
                    // continuation from the last intermediate state.
                    if !pb.opts.continuation {
                        return Err(e);
                    }
                    if continuation(pb, state, ws, diag, load, None, t).is_err() {
                        state.restore();
                        return Err(e);
                    }
                    s = 1.0;
                }
            }
            Err(e) => return Err(e),
        }
    }
    commit(pb, state, diag, t, StateKind::Relaxed);
    Ok(())
}

/// Breaks beam `b` at the committed state: its mode, its energy moved from the stored to the
/// fracture account, its term subtracted from the operator; a stone left with no bond and no
/// contact is reported (or an error, [`FloatingPolicy::Error`]).
fn break_beam(
    pb: &Problem<'_>,
    state: &mut SolverState,
    ws: &mut Workspace,
    diag: &mut Diagnostics<'_>,
    b: usize,
) -> Result<(), DemError> {
    let z = &state.z;
    let (qi, qj) = pb.model.beam_dofs(b, z);
    let crushing = crushing_index(pb, b, z);
    let (geom, thresholds) = (&pb.model.geoms[b], &pb.model.thresholds);
    let mode = match failure_mode(geom, thresholds, qi, qj) {
        _ if crushing >= 1.0 - 1e-9 && crushing >= failure_index(geom, thresholds, qi, qj) => FailureModeTag::Crushing,
        FailureMode::Tension => FailureModeTag::Tension,
        FailureMode::Shear => FailureModeTag::Shear,
    };
    let energy = pb.model.beam_energy(b, z);
    state.energy.fracture += energy;
    // The previous state's stored energy included this beam: move it to the fracture account
    // so the relaxation term measures only what the re-equilibration releases.
    if let Some(last) = state.records.last_mut() {
        last.stored -= energy;
        last.dissipated[0] += energy;
    }
    state.intact[b] = false;
    state.broken.push(BrokenBeam { beam: b, mode, state: state.records.len().saturating_sub(1), energy });
    if state.broken.len() > pb.opts.max_events {
        return Err(DemError::TooManyEvents { max_events: pb.opts.max_events });
    }
    ws.operator.add_low_rank(&mut upkeep(pb, state, &mut diag.profile), &pb.model.terms[b], -1.0)?;
    flag_floating(pb, state, ws, b)
}

/// Reports the stones of beam `b` that kept no bond and no contact (module docs of
/// [`super::stage`], "Regularization").
fn flag_floating(pb: &Problem<'_>, state: &mut SolverState, ws: &mut Workspace, b: usize) -> Result<(), DemError> {
    let beam = &pb.model.sample.beams[b];
    for p in [beam.i, beam.j] {
        if pb.model.map.is_slave(p) {
            continue;
        }
        let bonded = pb.model.sample.neighbours[p].iter().any(|&(_, k)| state.intact[k]);
        let touching = state.contacts.iter().any(|a| a.i == p || a.j == p);
        if !bonded && !touching {
            if pb.opts.floating == FloatingPolicy::Error {
                return Err(DemError::FreeFloating { particle: p, event: state.broken.len() });
            }
            state.floating.push((p, state.broken.len()));
            ws.operator.invalidate(None); // avoid an ill-conditioned Woodbury correction
        }
    }
    Ok(())
}
