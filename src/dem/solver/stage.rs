//! The stage loop: the quasi-static, incremental, event-driven solution algorithm (paper §2.1,
//! steps 1–4).
//!
//! ```text
//! for each load step  t → t_target  (t = load parameter of the stage, in [0, 1]):
//!   1. z_new = equilibrium at t_target (modified Newton on the residual, contacts + friction)
//!   2. λ* = min over intact beams of failure_lambda(z_old → z_new)   (P piecewise linear in λ)
//!   3. λ* ≥ 1: commit z_new (state "loading").
//!      λ* < 1: t ← t + λ*(t_target − t); equilibrium there (z_old + λ*Δz when no contact is
//!              active: exact, the problem is then linear); commit (state "pre-break");
//!              break that beam; re-equilibrate at fixed load, commit ("relaxed");
//!              while some intact beam has P ≥ 1: break the most critical one, re-equilibrate,
//!              commit; then continue the step from t.
//! stop at t = 1 of the last stage, or on loss of load (|R| < loss_fraction × peak).
//! ```
//!
//! **In the pipeline** ([`super::solver`], "The step as a pipeline"). [`continue_stage`] runs
//! this loop over the solver's parts: each trial step (`solve_trial`: the equilibrium from the
//! step predictor or the plain start, continuation at the smallest increment, the energy check
//! with crushing), the first failure along it ([`super::breaks`]), a contact event inside it
//! ([`super::contact_events`]), the commit ([`super::energy`]) and the break cascade. With
//! [`super::SolverOptions::break_search`] a step first predicts its first break from one
//! tangent solve and solves the equilibrium there only ([`super::break_search`]: steps 1–2
//! without the equilibrium at `t_target`, the break landed on `P = 1`); a step without a
//! predicted break is the trial step above.
//!
//! **Contact events.** A contact that starts to slide (stick → slip), closes or opens inside a
//! load step puts a kink into the platen force–displacement path; the trapezoid rule of the
//! external work misses the area at the kink: for a spring–slider driven from `F_0` (sticking)
//! to the Coulomb limit `F_1` with the plastic slip `Δg_p` in one step, the trapezoid is short by
//! `½ (F_1 − F_0) Δg_p` (exact work `F_1 Δu − (F_1 − F_0)²/(2k)` against the trapezoid
//! `½ (F_0 + F_1) Δu`). With `SolverOptions::contact_events` (off by default) a step whose converged
//! end shows such an event is retried to end at the event, estimated along `z_old → z`:
//! stick → slip where `|F_t,0 + λ(F_trial − F_t,0)| = μ (F_n,0 + λ ΔF_n)`; closing where the
//! normal approach `b·Δz` has covered the step's approach minus the depth `S_r/L` reached,
//! `λ = 1 − (S_r/L)/(b·Δz)`; opening where the separation has covered the committed depth. The
//! first event over all contacts ends the step (a state of kind "loading"); a step already ending
//! at an event is not cut again, and no step shorter than `MIN_EVENT_STEP` of the stage's step is
//! made, so the kinks left sit in steps ≤ 1/16 of the nominal one.
//!
//! **Crushing (optional).** With `MechParams::crushing`, a beam also breaks when its compressive
//! stress reaches σ_c (`P_c = −Ē ε/σ_c ≥ 1`, mode "crushing"); `λ*` is the smallest crossing of
//! either index, both linear or piecewise linear in λ. Crushing contacts soften inside the
//! equilibrium iteration (their return map is part of the residual and of the tangent); under
//! displacement control the loss-of-load test or, when no equilibrium exists past the peak, the
//! caller's collapse classification ends the test. A crushed beam leaves its stones overlapping
//! by about its shortening: the contact that takes over holds elastic energy the intact beam's
//! pair did not, so re-equilibrations after crushing can show a negative relaxation term (energy
//! is still balanced: `W_ext = stored + dissipated` over the loading steps).
//!
//! **Continuation** ([`super::SolverOptions::continuation`], on by default). Where Newton's method
//! finds no equilibrium at the smallest increment (a load step cut back `max_cutbacks` times,
//! or a beam's release), the equilibrium at that load is sought by pseudo-transient
//! continuation ([`super::continuation`]), with the same residual tolerance. A load step found
//! so is recorded as a state of kind "relaxed" at its (tiny) platen increment: past a
//! snap-back the curve shows a vertical drop at the platen displacement, and the energy the
//! drop releases is booked as relaxation (what a dynamic model would damp); then, as after any
//! break, the beams with `P ≥ 1` at that state break one at a time. A release found so ends
//! the release. If the continuation fails too, Newton's error is returned (the caller's
//! collapse/failed classification).
//!
//! **Snaps inside a step (crushing).** Crushing contacts soften, so past the peak Newton's
//! method can converge to an equilibrium on a lower branch than the step's start: the path
//! between them is a snap, not the straight line the trapezoid rule of the external work
//! assumes, and the energy it releases shows as an imbalance of that loading step (on the
//! paper's wall, seed 5: 25 J and 36 J, 2.3 % of the work, in two steps out of 215; a local
//! snap need not move the platen force much). A trial step is therefore checked before it is
//! committed:
//!
//! ```text
//!   ΔW − ΔU − ΔD  ≤  MAX_STEP_IMBALANCE · max(W, U)      (10⁻³; W, U at the last state)
//! ```
//!
//! with `ΔW` the trapezoid of the platen forces, `ΔU` the change of stored energy, `ΔD` the
//! friction and crushing dissipation of the step. A step that fails it is halved like a failed
//! one: a kink of the path then resolves into smaller steps (its trapezoid error falls with the
//! step), while a snap keeps its imbalance down to the smallest increment (`max_cutbacks`
//! halvings), where it is recorded as the drop past a snap-back under "Continuation": a state of
//! kind "relaxed", the released energy booked as relaxation, the beams with `P ≥ 1` broken.
//!
//! **Equilibrium iteration.** Residual `r = f_ext − f_int(z) − ε (z − z_commit)` on the
//! unknowns; `Δz = K̃⁻¹ r` with `K̃` the factorized operator (intact beams, contact normal
//! penalties `k_n b bᵀ`, sticking tangential terms `k_t c cᵀ`, the regularization `ε`). Converged
//! when `‖r‖∞ ≤ tol · scale` and the contact and stick/slip sets did not change in the iteration.
//! Without contacts the beam problem is linear and one solve is exact.
//!
//! **Regularization (free-floating stones).** Every unknown has a tiny spring
//! `ε_k = 10⁻¹⁰ × (its diagonal with all beams intact)` to its position at the last committed
//! equilibrium state. It changes connected stones' response by O(10⁻¹⁰) relative and holds a stone
//! that lost every bond and contact where it was, so the matrix stays positive definite. Such
//! stones are detected after every break (no intact beam, no active contact) and either reported
//! ([`super::FloatingPolicy::Regularize`], default) or turned into [`super::DemError::FreeFloating`].
//!
//! **Low-rank updates.** A break subtracts its beam's term from the factorized operator and
//! contact terms enter and leave it as Woodbury corrections, until a refactorization pays
//! ([`super::operator`]).
//!
//! **Energy.** Each recorded state carries the energy account of [`super::energy`].
use super::break_search::{land, lands, search_break, searches, Landing};
use super::breaks::{break_cascade, first_failure};
use super::checkpoint::{CheckpointSink, TestCheckpoint};
use super::contact_events::first_contact_event;
use super::continuation::continuation;
use super::diagnostics::Diagnostics;
use super::energy::{commit, trial_step_imbalance};
use super::equilibrium::equilibrate;
use super::error::DemError;
use super::options::SolverOptions;
use super::phases::Phase;
use super::problem::Problem;
use super::records::{LoadPoint, StageEnd, StateKind, StateRecord};
use super::state::SolverState;
use super::step_predictor::{equilibrate_predicted, predicts_steps, StepPredictor};
use super::walk::StageWalk;
use super::workspace::Workspace;

/// The shortest load step a contact event makes, as a fraction of the stage's step: the
/// trapezoid error of an unresolved kink scales with the square of the step containing it, so
/// events closer than this to either end of a step are left (≤ 1/256 of the error).
const MIN_EVENT_STEP: f64 = 1.0 / 16.0;

/// The largest energy imbalance of one load step with crushing, as a fraction of the external
/// work so far (at least of the stored energy), module docs, "Snaps inside a step".
const MAX_STEP_IMBALANCE: f64 = 1e-3;

/// What a trial load step `t → t_try` came to, before the beams are checked.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum Trial {
    /// Equilibrium found by Newton's method, its energy balanced.
    Converged,
    /// The state past a snap: found by continuation at the smallest increment, or a step whose
    /// energy does not balance at the smallest increment (module docs).
    Snapped,
    /// No equilibrium found: retried with half the increment.
    Failed,
    /// Converged with an energy imbalance (crushing): retried with half the increment.
    Unbalanced,
}

/// A trial load step from the committed state at the walk's `t` to `t_try`.
struct TrialStep {
    /// The end of the step.
    t_try: f64,
    /// The committed coordinates the step starts from.
    z_old: Vec<f64>,
    /// The load at `t_try`.
    load: LoadPoint,
}

/// Watches the monitored platen force for loss of load: `|R| < loss_fraction × peak |R|`.
struct LossWatch {
    /// `(platen, dof)` of the force.
    force: (usize, usize),
    peak: f64,
    /// Records already seen.
    seen: usize,
}

impl LossWatch {
    /// Whether the force fell below `fraction` of its peak over `records` (only once a beam broke).
    fn lost(&mut self, records: &[StateRecord], any_broken: bool, fraction: f64) -> bool {
        let (k, a) = self.force;
        for st in &records[self.seen..] {
            self.peak = self.peak.max(st.platen_force[k][a].abs());
        }
        self.seen = records.len();
        let r = records.last().map_or(0.0, |s| s.platen_force[k][a].abs());
        any_broken && self.peak > 0.0 && r < fraction * self.peak
    }
}

/// Records the unloaded initial state (call once before the first stage).
pub(super) fn start(
    pb: &Problem<'_>,
    state: &mut SolverState,
    ws: &mut Workspace,
    diag: &mut Diagnostics<'_>,
) -> Result<(), DemError> {
    let l = state.load.clone();
    diag.phase = Phase::Other;
    equilibrate(pb, state, ws, diag, &l, None, 0.0)?;
    commit(pb, state, diag, 0.0, StateKind::Loading);
    Ok(())
}

/// The walk of a stage from the current load to `target` in `steps` steps, not yet begun.
pub(super) fn stage_walk(opts: &SolverOptions, state: &SolverState, target: &LoadPoint, steps: usize) -> StageWalk {
    let (load, records) = (state.load.clone(), state.records.len());
    StageWalk::new(load, target.clone(), steps, opts.max_cutbacks, records)
}

/// Runs the stage `walk` stands in to its end ([`super::Solver::run_stage`]): a new walk, or one
/// read from a checkpoint. After each committed load step `sink` is asked whether a checkpoint
/// is due ([`super::checkpoint`]); its errors end the stage.
pub(super) fn continue_stage(
    pb: &Problem<'_>,
    state: &mut SolverState,
    ws: &mut Workspace,
    diag: &mut Diagnostics<'_>,
    mut walk: StageWalk,
    monitor: Option<(usize, usize)>,
    mut sink: Option<&mut dyn CheckpointSink>,
) -> Result<StageEnd, DemError> {
    let mut watch = monitor.map(|force| LossWatch { force, peak: 0.0, seen: walk.records_at_start });
    while !walk.done() {
        let t_try = walk.trial_end();
        let step = TrialStep { t_try, z_old: state.z.clone(), load: walk.load_at(t_try) };
        if !take_step(pb, state, ws, diag, &mut walk, &step)? {
            continue;
        }
        state.load = walk.load_at(walk.t);
        walk.h = (2.0 * walk.h).min(walk.step);
        let (any_broken, fraction) = (!state.broken.is_empty(), pb.opts.loss_fraction);
        if watch.as_mut().is_some_and(|w| w.lost(&state.records, any_broken, fraction)) {
            return Ok(StageEnd::LossOfLoad);
        }
        if let Some(sink) = sink.as_deref_mut() {
            checkpoint_if_due(state, diag, sink, &walk)?;
        }
    }
    state.load = walk.target.clone();
    state.stage += 1;
    Ok(StageEnd::Completed)
}

/// One load step from the committed state at `walk.t` to `step.t_try` (module docs): the
/// break search's landing ([`super::break_search`]) or the trial step, the first break inside
/// it, a contact event, the commit and the break cascade. `false`: the walk was cut back
/// (halved, or ended at a contact event) and the step is to be tried again.
fn take_step(
    pb: &Problem<'_>,
    state: &mut SolverState,
    ws: &mut Workspace,
    diag: &mut Diagnostics<'_>,
    walk: &mut StageWalk,
    step: &TrialStep,
) -> Result<bool, DemError> {
    if searches(pb) {
        let found = search_break(pb, state, ws, diag, walk, step.t_try).map_err(|e| abandon(state, walk, e))?;
        if let Some(landing) = found {
            walk.at_event = false;
            break_at(pb, state, ws, diag, walk, landing)?;
            return Ok(true);
        }
    }
    let t_try = step.t_try;
    let trial = solve_trial(pb, state, ws, diag, walk, step)?;
    if trial == Trial::Unbalanced {
        diag.profile.phases.trial_discarded += 1;
        state.restore();
        diag.counters.cutbacks += 1;
        diag.counters.imbalance_cutbacks += 1;
        walk.halve(t_try);
        return Ok(false);
    }
    let failure = if trial == Trial::Converged { first_failure(pb, state, diag, &step.z_old) } else { None };
    let breaks = failure.filter(|&(lam, _)| lam < 1.0);
    if breaks.is_some() {
        diag.profile.phases.trial_discarded += 1;
    }
    if trial == Trial::Converged && breaks.is_none() {
        if let Some(t_c) = contact_event_within(pb, state, walk, step) {
            diag.profile.phases.trial_discarded += 1;
            state.restore();
            diag.counters.contact_events += 1;
            walk.h = t_c - walk.t;
            walk.at_event = true;
            return Ok(false);
        }
    }
    walk.at_event = false;
    let advanced = match (trial, breaks) {
        (Trial::Snapped, _) => {
            diag.counters.continued_steps += 1;
            commit(pb, state, diag, t_try, StateKind::Relaxed);
            walk.t = t_try;
            state.load = step.load.clone();
            break_cascade(pb, state, ws, diag, Vec::new(), &step.load, t_try)?;
            true
        }
        (Trial::Converged, Some(crossing)) if lands(pb) => land_within_step(pb, state, ws, diag, walk, step, crossing)?,
        (Trial::Converged, Some(crossing)) => break_within_step(pb, state, ws, diag, walk, step, crossing)?,
        (Trial::Converged, None) => {
            commit(pb, state, diag, t_try, StateKind::Loading);
            walk.t = t_try;
            true
        }
        (Trial::Failed | Trial::Unbalanced, _) => false,
    };
    if !advanced {
        state.restore();
        diag.counters.cutbacks += 1;
        walk.halve(t_try);
        return Ok(false);
    }
    Ok(true)
}

/// The trial load `step`: Newton's method (from the cut step's response after a break,
/// [`super::step_predictor`]); at the smallest increment, continuation; with crushing, the
/// energy balance. Errors that no halving can mend end the stage, the committed state and its
/// load restored.
fn solve_trial(
    pb: &Problem<'_>,
    state: &mut SolverState,
    ws: &mut Workspace,
    diag: &mut Diagnostics<'_>,
    walk: &StageWalk,
    step: &TrialStep,
) -> Result<Trial, DemError> {
    let predictor = walk.predictor.as_ref().filter(|_| predicts_steps(pb));
    let start = predictor.and_then(|p| p.guess(&state.z, walk.t, step.t_try));
    diag.phase = Phase::Trial;
    match equilibrate_predicted(pb, state, ws, diag, start, &step.load, step.t_try) {
        Ok(()) => {}
        Err(DemError::NoConvergence { .. }) if walk.can_halve() => return Ok(Trial::Failed),
        Err(e @ DemError::NoConvergence { .. }) if pb.opts.continuation => {
            // No equilibrium at the smallest increment: past a limit point of the path, the
            // state after the snap-back (module docs, "Continuation").
            state.restore();
            if continuation(pb, state, ws, diag, &step.load, None, step.t_try).is_err() {
                return Err(abandon(state, walk, e));
            }
            return Ok(Trial::Snapped);
        }
        Err(e) => return Err(abandon(state, walk, e)),
    }
    // Energy released inside a converged step (crushing only): halve the step; at the
    // smallest one the release is a snap (module docs, "Snaps inside a step").
    if pb.model.params.crushing.is_some() {
        let (imbalance, scale) = trial_step_imbalance(pb, state);
        if imbalance.abs() > MAX_STEP_IMBALANCE * scale {
            if walk.can_halve() {
                return Ok(Trial::Unbalanced);
            }
            diag.counters.snaps_in_steps += 1;
            return Ok(Trial::Snapped);
        }
    }
    Ok(Trial::Converged)
}

/// The load parameter of the first contact event inside the converged trial `step` (with
/// [`super::SolverOptions::contact_events`]), when the step is to end there: not a trial already
/// ending at an event, and not closer than `MIN_EVENT_STEP` to either end.
fn contact_event_within(pb: &Problem<'_>, state: &SolverState, walk: &StageWalk, step: &TrialStep) -> Option<f64> {
    if !pb.opts.contact_events || walk.at_event {
        return None;
    }
    let lam = first_contact_event(pb, state, &step.z_old)?;
    let t_c = walk.t + lam * (step.t_try - walk.t);
    let min = MIN_EVENT_STEP * walk.step;
    (t_c - walk.t >= min && step.t_try - t_c >= min).then_some(t_c)
}

/// The converged trial `step` has beam `b` reaching `P = 1` at the fraction `lam`: the state
/// there (`z_old + λ Δz`, exact without contacts; Newton's method from it with contacts) is
/// committed as "pre-break", the beam breaks and the beams it overloads follow. `false`: no
/// equilibrium at the break's load, the trial is to be halved.
fn break_within_step(
    pb: &Problem<'_>,
    state: &mut SolverState,
    ws: &mut Workspace,
    diag: &mut Diagnostics<'_>,
    walk: &mut StageWalk,
    step: &TrialStep,
    (lam, b): (f64, usize),
) -> Result<bool, DemError> {
    let t_l = walk.t + lam * (step.t_try - walk.t);
    let load_l = walk.load_at(t_l);
    let z_end = state.z.clone();
    for (zo, zn) in step.z_old.iter().zip(state.z.iter_mut()) {
        *zn = zo + lam * (*zn - zo);
    }
    if !state.contacts.is_empty() {
        // Newton starts from the interpolated state: exact while the contact forces are
        // linear along the step, so usually one iteration away.
        diag.phase = Phase::Lambda;
        match equilibrate(pb, state, ws, diag, &load_l, None, t_l) {
            Ok(()) => {}
            Err(DemError::NoConvergence { .. }) if walk.can_halve() => return Ok(false),
            Err(e) => return Err(abandon(state, walk, e)),
        }
    }
    let predictor = StepPredictor::new(t_l, step.t_try, &state.z, &z_end);
    break_at(pb, state, ws, diag, walk, Landing { t: t_l, beam: b, predictor })?;
    Ok(true)
}

/// With landed breaks ([`super::break_search`]): the converged trial `step` has beam `b`
/// reaching `P = 1` at the fraction `lam` of its chord (with the search: a break the tangent
/// did not predict); the break is landed on `P = 1` as the search's are. Given up: as on the
/// trial path.
fn land_within_step(
    pb: &Problem<'_>,
    state: &mut SolverState,
    ws: &mut Workspace,
    diag: &mut Diagnostics<'_>,
    walk: &mut StageWalk,
    step: &TrialStep,
    (lam, b): (f64, usize),
) -> Result<bool, DemError> {
    let (z_end, contacts_end) = (state.z.clone(), state.contacts.clone());
    let chord = (step.z_old.as_slice(), z_end.as_slice(), step.t_try);
    match land(pb, state, ws, diag, walk, chord, lam).map_err(|e| abandon(state, walk, e))? {
        Some(landing) => {
            break_at(pb, state, ws, diag, walk, landing)?;
            Ok(true)
        }
        None => {
            (state.z, state.contacts) = (z_end, contacts_end);
            break_within_step(pb, state, ws, diag, walk, step, (lam, b))
        }
    }
}

/// The state, in equilibrium at the break's load parameter where its beam reaches `P = 1`,
/// is committed as "pre-break"; the walk moves there, the beam breaks and the beams it
/// overloads follow ([`break_cascade`]); the next load step starts from the break's predictor.
fn break_at(
    pb: &Problem<'_>,
    state: &mut SolverState,
    ws: &mut Workspace,
    diag: &mut Diagnostics<'_>,
    walk: &mut StageWalk,
    Landing { t: t_l, beam, predictor }: Landing,
) -> Result<(), DemError> {
    let load_l = walk.load_at(t_l);
    commit(pb, state, diag, t_l, StateKind::PreBreak);
    walk.predictor = Some(predictor);
    walk.t = t_l;
    state.load = load_l.clone();
    break_cascade(pb, state, ws, diag, vec![beam], &load_l, t_l)
}

/// Hands a checkpoint of the committed state and `walk` to the sink when it finds one due.
fn checkpoint_if_due(
    state: &SolverState,
    diag: &Diagnostics<'_>,
    sink: &mut dyn CheckpointSink,
    walk: &StageWalk,
) -> Result<(), DemError> {
    if !sink.due(state) {
        return Ok(());
    }
    sink.write(TestCheckpoint {
        state: state.clone(),
        walk: Some(walk.clone()),
        counters: diag.counters,
        seconds: 0.0,
        finished: None,
    })
}

/// Ends the stage on `e`: back to the committed state and its load.
fn abandon(state: &mut SolverState, walk: &StageWalk, e: DemError) -> DemError {
    state.restore();
    state.load = walk.load_at(walk.t);
    e
}
