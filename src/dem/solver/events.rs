//! The quasi-static, incremental, event-driven solution algorithm (SPEC §1, steps 1–4).
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
//! **Continuation** ([`SolverOptions::continuation`], on by default). Where Newton's method
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
//! ([`FloatingPolicy::Regularize`], default) or turned into [`DemError::FreeFloating`].
//!
//! **Low-rank updates.** A break adds `−Σ u uᵀ` (rank ≤ 3) to the Woodbury correction of the
//! factorization ([`LowRankCholesky`]); contact terms entering / leaving the operator likewise
//! (rank 1 each; a contact term that leaves before the next factorization is dropped from the
//! correction). The base matrix is refactorized when the correction has cost more than a
//! factorization (the cost model of [`super::factor`]), when its rank would exceed `max_rank`,
//! or when its capacitance matrix is ill-conditioned or GMRES fails with it (accuracy).
//!
//! **Energy.** Each recorded state carries the energy account of [`super::energy`].
use std::collections::BTreeMap;

use super::contact_set::{self, ActiveContact};
use super::equilibrium::Refactor;
use super::error::DemError;
use super::factor::{LowRankCholesky, TermId};
use super::profile::SolverProfile;
use super::step_predictor::StepPredictor;
use super::system::{Model, ZTerm};
use crate::dem::mechanics::{failure_index, failure_lambda, failure_mode, FailureMode};
use contact_set::Histories;

/// The shortest load step a contact event makes, as a fraction of the stage's step: the
/// trapezoid error of an unresolved kink scales with the square of the step containing it, so
/// events closer than this to either end of a step are left (≤ 1/256 of the error).
const MIN_EVENT_STEP: f64 = 1.0 / 16.0;

/// The regularization spring of every unknown, relative to its diagonal with all beams intact
/// (module docs, "Regularization").
const REGULARIZATION: f64 = 1e-10;
/// `f_ε = ROUNDOFF_FACTOR · ε_mach · X · Ē t_z`: the round-off of a contact force, below which a
/// residual counts as converged ([`super::equilibrium`], module docs).
const ROUNDOFF_FACTOR: f64 = 64.0;

/// The largest energy imbalance of one load step with crushing, as a fraction of the external
/// work so far (at least of the stored energy), module docs, "Snaps inside a step".
const MAX_STEP_IMBALANCE: f64 = 1e-3;

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
    /// Refactorize when the Woodbury correction has more columns than this (90 = 30 beams).
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
    /// Keep every contact's tangential stiffness `k_t c cᵀ` in the factorized preconditioner,
    /// sliding or not (default on): a stick/slip change then leaves the factorization alone and
    /// GMRES absorbs the difference ([`super::tangent`]). Off: only sticking contacts carry it.
    pub slip_in_preconditioner: bool,
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
            slip_in_preconditioner: true,
            forcing: super::gmres::Forcing::default(),
            continuation: true,
            trace: false,
            predict_steps: true,
        }
    }
}

/// The load of a stage: prescribed platen values (order of [`DofMap::prescribed`]) and forces
/// (order of [`DofMap::forced`]).
#[derive(Clone, Debug, PartialEq)]
pub struct LoadPoint {
    /// Imposed displacements/rotations.
    pub prescribed: Vec<f64>,
    /// External forces/moments.
    pub forces: Vec<f64>,
}

impl LoadPoint {
    fn lerp(a: &LoadPoint, b: &LoadPoint, t: f64) -> LoadPoint {
        let l = |x: &[f64], y: &[f64]| x.iter().zip(y).map(|(u, v)| u + t * (v - u)).collect();
        LoadPoint { prescribed: l(&a.prescribed, &b.prescribed), forces: l(&a.forces, &b.forces) }
    }
}

/// Why a committed state was recorded.
#[derive(Clone, Copy, Debug, PartialEq, Eq, serde::Serialize, serde::Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum StateKind {
    /// End of a load step.
    Loading,
    /// Load scaled to the first beam reaching P = 1.
    PreBreak,
    /// Re-equilibrated at fixed load after a break.
    Relaxed,
}

/// One committed equilibrium state.
#[derive(Clone, Debug, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct StateRecord {
    /// Load stage index.
    pub stage: usize,
    /// Load parameter within the stage.
    pub t: f64,
    /// Kind.
    pub kind: StateKind,
    /// Platen DOFs `(U_x, U_y, Θ)`, bottom then top.
    pub platen: [[f64; 3]; 2],
    /// Platen generalized forces (internal = reactions for prescribed DOFs).
    pub platen_force: [[f64; 3]; 2],
    /// Mean `u_x` of the left and of the right boundary stones.
    pub lateral_ux: [f64; 2],
    /// Broken beams so far: total, tension, shear, crushing.
    pub broken: [usize; 4],
    /// Active contacts.
    pub contacts: usize,
    /// External work (J).
    pub external_work: f64,
    /// Stored elastic energy (J).
    pub stored: f64,
    /// Dissipated: fracture, friction, relaxation, crushing (J).
    pub dissipated: [f64; 4],
}

/// A broken beam.
#[derive(Clone, Debug, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct BrokenBeam {
    /// Beam index.
    pub beam: usize,
    /// Failure mode at breaking.
    pub mode: FailureModeTag,
    /// Index of the recorded state at which it broke (the last state with it intact).
    pub state: usize,
    /// Its elastic energy when it broke (J).
    pub energy: f64,
}

/// Serializable failure mode.
#[derive(Clone, Copy, Debug, PartialEq, Eq, serde::Serialize, serde::Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum FailureModeTag {
    /// Tension-dominated.
    Tension,
    /// Rotation/shear-dominated.
    Shear,
    /// Compressive stress at the crushing stress (only with crushing).
    Crushing,
}

/// The solver state of one test.
pub struct Solver<'a> {
    pub(super) model: Model<'a>,
    pub(super) opts: SolverOptions,
    /// Generalized coordinates (trial during an iteration, committed after `commit`).
    pub z: Vec<f64>,
    pub(super) z_commit: Vec<f64>,
    /// Beam intact flags.
    pub intact: Vec<bool>,
    pub(super) reg: Vec<f64>,
    /// Each unknown's diagonal with every beam intact (a positive fallback where it has none):
    /// the scale of the regularization springs and the continuation's masses.
    pub(super) intact_diagonal: Vec<f64>,
    pub(super) factor: LowRankCholesky,
    pub(super) needs_factor: bool,
    /// Why `needs_factor` was set (for the profile; `None`: a floating stone).
    pub(super) pending_refactor: Option<Refactor>,
    // Contact terms currently in the operator, keyed by (i, j, 0 = normal / 1 = tangential),
    // with their handle in the Woodbury correction while they are there.
    pub(super) op_terms: BTreeMap<(usize, usize, u8), (ZTerm, Option<TermId>)>,
    /// The `z` indices of every pair whose contact terms were ever factorized: they stay in the
    /// sparsity pattern (as zeros once the contact is gone), so the symbolic analysis is reused.
    pub(super) pattern: BTreeMap<(usize, usize), [usize; 6]>,
    pub(super) contacts: Vec<ActiveContact>,
    /// The active contacts of the last committed state (for the contact events).
    pub(super) committed_contacts: Vec<ActiveContact>,
    /// The contact search's candidate list and the contact Jacobians kept between evaluations.
    pub(super) candidates: super::contact_candidates::CandidateList,
    pub(super) jacobians: super::tangent::JacobianCache,
    /// Committed contact histories (tangential force, plastic penetration) by pair.
    pub(super) committed_ft: Histories,
    load: LoadPoint,
    /// Recorded states.
    pub states: Vec<StateRecord>,
    /// Broken beams in order.
    pub broken: Vec<BrokenBeam>,
    /// Stones found free-floating, with the event count.
    pub floating: Vec<(usize, usize)>,
    pub(super) energy: super::energy::Energy,
    pub(super) stage: usize,
    /// Total equilibrium solves (linear solves, GMRES preconditioner applications included).
    pub n_solves: usize,
    /// Load-increment cut-backs done (halvings of a load step or of a beam's release).
    pub n_cutbacks: usize,
    /// Load steps ended at a contact event.
    pub n_contact_events: usize,
    /// Pseudo-transient continuations run ([`super::continuation`]).
    pub n_continuations: usize,
    /// Load steps whose equilibrium was found by continuation (module docs, "Continuation").
    pub n_continued_steps: usize,
    /// Load steps halved because their energy did not balance (module docs, "Snaps inside a
    /// step"; counted in `n_cutbacks` too).
    pub n_imbalance_cutbacks: usize,
    /// Such steps left at the smallest increment and recorded as snaps.
    pub n_snaps_in_steps: usize,
    /// Counters and phase times ([`SolverProfile`]).
    pub profile: SolverProfile,
    pub(super) lateral: [Vec<usize>; 2],
    /// Mean stone diameter D̄ (m): weighs moments in the merit function.
    pub(super) mean_diameter: f64,
    /// Largest move of a stone in one Newton iteration (m): 5 % of D̄.
    pub(super) max_move: f64,
    /// The round-off of a contact force, `f_ε` of [`super::equilibrium`]'s convergence scale (N).
    pub(super) roundoff_force: f64,
    /// A tenth of the largest platen force component of the recorded states (N): a floor of
    /// the convergence scale ([`super::equilibrium`], module docs).
    pub(super) reference_force: f64,
    /// Called with every recorded state (its index, the record, the coordinates `z`), e.g. to
    /// keep particle states ([`super::snapshots::Recorder`]).
    #[allow(clippy::type_complexity)]
    pub observer: Option<Box<dyn FnMut(usize, &StateRecord, &[f64]) + 'a>>,
    /// The Newton history of the last equilibrium attempts (with [`SolverOptions::trace`]).
    pub trace: Option<super::trace::Trace>,
}

/// How a stage ended.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum StageEnd {
    /// The target was reached.
    Completed,
    /// The monitored force dropped below the loss fraction of its peak.
    LossOfLoad,
}

impl<'a> Solver<'a> {
    /// A solver at the unloaded state (nothing broken, no contact), with the first load point.
    pub fn new(model: Model<'a>, opts: SolverOptions, initial: LoadPoint) -> Result<Solver<'a>, DemError> {
        let map = &model.map;
        if initial.prescribed.len() != map.prescribed.len() || initial.forces.len() != map.forced.len() {
            return Err(DemError::InvalidParameter {
                field: "load point",
                value: format!("{} prescribed / {} forces", initial.prescribed.len(), initial.forces.len()),
                expected: "one value per prescribed and per force-controlled platen DOF",
            });
        }
        let diag = model.diagonal();
        let positive: Vec<f64> = diag.iter().copied().filter(|d| *d > 0.0).collect();
        let mean = positive.iter().sum::<f64>() / positive.len().max(1) as f64;
        let intact_diagonal: Vec<f64> = diag.iter().map(|&d| if d > 0.0 { d } else { mean.max(1.0) }).collect();
        let reg = intact_diagonal.iter().map(|d| REGULARIZATION * d).collect();
        let n_z = map.n_z;
        let n_eq = map.n_eq();
        let lateral = [model.sample.boundary.left.clone(), model.sample.boundary.right.clone()];
        let intact = vec![true; model.sample.beams.len()];
        let mean_diameter = model.sample.mean_diameter();
        let extent = model
            .sample
            .particles
            .iter()
            .flat_map(|p| p.polygon.vertices.iter())
            .fold(0.0f64, |m, v| m.max(v[0].abs()).max(v[1].abs()));
        let roundoff_force = ROUNDOFF_FACTOR * f64::EPSILON * extent * model.params.e_bar * model.params.t_z;
        Ok(Solver {
            opts,
            z: vec![0.0; n_z],
            z_commit: vec![0.0; n_z],
            intact,
            reg,
            intact_diagonal,
            factor: LowRankCholesky::new(n_eq),
            needs_factor: true,
            pending_refactor: None,
            op_terms: BTreeMap::new(),
            pattern: BTreeMap::new(),
            contacts: Vec::new(),
            committed_contacts: Vec::new(),
            candidates: Default::default(),
            jacobians: Default::default(),
            committed_ft: BTreeMap::new(),
            load: initial,
            states: Vec::new(),
            broken: Vec::new(),
            floating: Vec::new(),
            energy: Default::default(),
            stage: 0,
            n_solves: 0,
            n_cutbacks: 0,
            n_contact_events: 0,
            n_continuations: 0,
            n_continued_steps: 0,
            n_imbalance_cutbacks: 0,
            n_snaps_in_steps: 0,
            profile: SolverProfile::default(),
            lateral,
            mean_diameter,
            max_move: 0.05 * mean_diameter,
            roundoff_force,
            reference_force: 0.0,
            observer: None,
            trace: opts.trace.then(Default::default),
            model,
        })
    }

    /// The active contacts of the last equilibrium state.
    pub fn contacts(&self) -> &[ActiveContact] {
        &self.contacts
    }

    /// The model.
    pub fn model(&self) -> &Model<'a> {
        &self.model
    }

    /// The factorization statistics `(numeric factorizations, symbolic analyses)`.
    pub fn factor_stats(&self) -> (usize, usize) {
        (self.factor.n_factorizations, self.factor.n_symbolic)
    }

    /// Internal forces in `z` (beams, contacts).
    pub(super) fn internal(&self, z: &[f64], contacts: &[ActiveContact]) -> Vec<f64> {
        let mut f = vec![0.0; self.model.map.n_z];
        self.model.add_beam_forces(&self.intact, z, &mut f);
        contact_set::add_contact_forces(&self.model.map, contacts, &mut f);
        f
    }

    /// Makes the trial state the committed one (friction history, regularization anchor)
    /// without recording it: an intermediate state of a cut-back release.
    pub(super) fn accept(&mut self) {
        self.energy.friction += self.contacts.iter().map(|a| a.friction.dissipation).sum::<f64>();
        self.energy.crushing += self.contacts.iter().map(|a| a.crushing_dissipation()).sum::<f64>();
        // Pairs apart keep their plastic state (no tangential force without contact).
        let mut next: Histories = self
            .committed_ft
            .iter()
            .filter(|(_, h)| h.plastic.kappa > 0.0)
            .map(|(&k, h)| (k, contact_set::ContactHistory { f_t: 0.0, plastic: h.plastic }))
            .collect();
        next.extend(self.contacts.iter().map(|a| ((a.i, a.j), a.history())));
        self.committed_ft = next;
        self.committed_contacts.clone_from(&self.contacts);
        self.z_commit.clone_from(&self.z);
    }

    /// Back to the committed state (a failed trial).
    pub(super) fn restore(&mut self) {
        self.z.clone_from(&self.z_commit);
    }

    /// Breaks beam `b` at the committed state.
    fn break_beam(&mut self, b: usize) -> Result<(), DemError> {
        let (qi, qj) = self.model.beam_dofs(b, &self.z);
        let crushing = self.crushing_index(b, &self.z);
        let mode = match failure_mode(&self.model.geoms[b], &self.model.thresholds, qi, qj) {
            _ if crushing >= 1.0 - 1e-9
                && crushing >= failure_index(&self.model.geoms[b], &self.model.thresholds, qi, qj) =>
            {
                FailureModeTag::Crushing
            }
            FailureMode::Tension => FailureModeTag::Tension,
            FailureMode::Shear => FailureModeTag::Shear,
        };
        let energy = self.model.beam_energy(b, &self.z);
        self.energy.fracture += energy;
        // The previous state's stored energy included this beam: move it to the fracture account
        // so the relaxation term measures only what the re-equilibration releases.
        if let Some(last) = self.states.last_mut() {
            last.stored -= energy;
            last.dissipated[0] += energy;
        }
        self.intact[b] = false;
        self.broken.push(BrokenBeam { beam: b, mode, state: self.states.len().saturating_sub(1), energy });
        if self.broken.len() > self.opts.max_events {
            return Err(DemError::TooManyEvents { max_events: self.opts.max_events });
        }
        let term = self.model.terms[b].clone();
        self.add_low_rank(&term, -1.0)?;
        let beam = &self.model.sample.beams[b];
        for p in [beam.i, beam.j] {
            if self.model.map.is_slave(p) {
                continue;
            }
            let bonded = self.model.sample.neighbours[p].iter().any(|&(_, k)| self.intact[k]);
            let touching = self.contacts.iter().any(|a| a.i == p || a.j == p);
            if !bonded && !touching {
                if self.opts.floating == FloatingPolicy::Error {
                    return Err(DemError::FreeFloating { particle: p, event: self.broken.len() });
                }
                self.floating.push((p, self.broken.len()));
                self.needs_factor = true; // avoid an ill-conditioned Woodbury correction
            }
        }
        Ok(())
    }

    /// The crushing index `P_c = −Ē ε/σ_c` of beam `b` at `z` (−∞ without crushing).
    fn crushing_index(&self, b: usize, z: &[f64]) -> f64 {
        let Some(c) = &self.model.params.crushing else { return f64::NEG_INFINITY };
        let (qi, qj) = self.model.beam_dofs(b, z);
        let g = &self.model.geoms[b];
        c.beam_index(self.model.params.e_bar, g.delta_n(qi, qj) / g.ell)
    }

    /// The smallest crushing fraction of beam `b` along `z_old → z` (`None` without crushing).
    fn crushing_lambda(&self, b: usize, z_old: &[f64]) -> Option<f64> {
        let c = self.model.params.crushing.as_ref()?;
        let g = &self.model.geoms[b];
        let (q0i, q0j) = self.model.beam_dofs(b, z_old);
        let (q1i, q1j) = self.model.beam_dofs(b, &self.z);
        let (e0, e1) = (g.delta_n(q0i, q0j) / g.ell, g.delta_n(q1i, q1j) / g.ell);
        c.beam_lambda(self.model.params.e_bar, e0, e1 - e0)
    }

    /// The smallest failure fraction along `z_old → z` and its beam.
    fn first_failure(&self, z_old: &[f64]) -> Option<(f64, usize)> {
        let mut best: Option<(f64, usize)> = None;
        for b in 0..self.intact.len() {
            if !self.intact[b] {
                continue;
            }
            let (q0i, q0j) = self.model.beam_dofs(b, z_old);
            let (q1i, q1j) = self.model.beam_dofs(b, &self.z);
            let d = |a: [f64; 3], c: [f64; 3]| [a[0] - c[0], a[1] - c[1], a[2] - c[2]];
            if let Some(l) =
                failure_lambda(&self.model.geoms[b], &self.model.thresholds, q0i, q0j, d(q1i, q0i), d(q1j, q0j))
            {
                if best.is_none_or(|(bl, _)| l < bl) {
                    best = Some((l, b));
                }
            }
            if let Some(l) = self.crushing_lambda(b, z_old) {
                if best.is_none_or(|(bl, _)| l < bl) {
                    best = Some((l, b));
                }
            }
        }
        best
    }

    /// The intact beam with the largest `P ≥ 1` at the current state.
    fn most_critical(&self) -> Option<usize> {
        let mut best: Option<(f64, usize)> = None;
        for b in (0..self.intact.len()).filter(|&b| self.intact[b]) {
            let (qi, qj) = self.model.beam_dofs(b, &self.z);
            let p = failure_index(&self.model.geoms[b], &self.model.thresholds, qi, qj)
                .max(self.crushing_index(b, &self.z));
            if p >= 1.0 && best.is_none_or(|(bp, _)| p > bp) {
                best = Some((p, b));
            }
        }
        best.map(|(_, b)| b)
    }

    /// Finds equilibrium at `load` starting from the current `z` (see [`super::equilibrium`]);
    /// leaves the contacts of the equilibrium state in [`Self::contacts`].
    pub fn equilibrate(&mut self, load: &LoadPoint, t: f64) -> Result<(), DemError> {
        self.equilibrate_with(load, None, t)
    }

    /// Breaks beam `b` now (e.g. a pre-cracked sample), re-equilibrates at the current load and
    /// records the state.
    pub fn break_and_relax(&mut self, b: usize) -> Result<(), DemError> {
        if b >= self.intact.len() || !self.intact[b] {
            return Err(DemError::InvalidParameter {
                field: "beam",
                value: b.to_string(),
                expected: "the index of an intact beam",
            });
        }
        let l = self.load.clone();
        self.release(b, &l, 1.0)
    }

    /// Breaks beam `b` at the committed state and re-equilibrates at the fixed `load`, then
    /// records the relaxed state.
    ///
    /// **Release path.** The beam's force at the committed state, `f_b`, is released along
    /// `f_extra(s) = (1 − s) f_b`, `s: 0 → 1`: at `s = 0` the committed state is in equilibrium,
    /// at `s = 1` the beam is gone. One step `s = 1` first; if Newton fails, the release is cut
    /// back (halved, at most `max_cutbacks` times), each intermediate equilibrium committed
    /// (friction history) but not recorded. This is the quasi-static path a dynamic release
    /// would follow with heavy damping, and it lets the contact and stick/slip sets change
    /// gradually when a break redistributes much load.
    fn release(&mut self, b: usize, load: &LoadPoint, t: f64) -> Result<(), DemError> {
        let term = &self.model.terms[b];
        let fb = term.k * Model::gather(&term.idx, &self.z);
        let mut f_b = vec![0.0; self.model.map.n_z];
        for a in 0..6 {
            f_b[term.idx[a]] += fb[a];
        }
        self.break_beam(b)?;
        let (mut s, mut h) = (0.0f64, 1.0f64);
        let h_min = 0.5f64.powi(self.opts.max_cutbacks as i32);
        while s < 1.0 {
            let s_try = (s + h).min(1.0);
            let extra: Vec<f64> = f_b.iter().map(|f| (1.0 - s_try) * f).collect();
            match self.equilibrate_with(load, Some(&extra), t) {
                Ok(()) => {
                    s = s_try;
                    if s < 1.0 {
                        self.accept();
                    }
                    h = (2.0 * h).min(1.0);
                }
                Err(e @ DemError::NoConvergence { .. }) => {
                    self.restore();
                    h *= 0.5;
                    self.n_cutbacks += 1;
                    if h < h_min {
                        // No equilibrium near the path: the full release by pseudo-transient
                        // continuation from the last intermediate state.
                        if !self.opts.continuation {
                            return Err(e);
                        }
                        if self.continuation(load, None, t).is_err() {
                            self.restore();
                            return Err(e);
                        }
                        s = 1.0;
                    }
                }
                Err(e) => return Err(e),
            }
        }
        self.commit(t, StateKind::Relaxed);
        Ok(())
    }

    /// Records the unloaded initial state (call once before the first stage).
    pub fn start(&mut self) -> Result<(), DemError> {
        let l = self.load.clone();
        self.equilibrate(&l, 0.0)?;
        self.commit(0.0, StateKind::Loading);
        Ok(())
    }

    /// Runs one load stage from the current load to `target` in `steps` equal steps; `monitor`
    /// is the platen force `(platen, dof)` watched for loss of load.
    ///
    /// **Cut-back.** A step whose equilibrium is not found is retried from the committed state
    /// with half the increment (at most `max_cutbacks` halvings of one step); after a success the
    /// increment doubles again up to the step. If the smallest increment fails too, the error is
    /// returned: the recorded states so far stay in [`Self::states`].
    pub fn run_stage(
        &mut self,
        target: &LoadPoint,
        steps: usize,
        monitor: Option<(usize, usize)>,
    ) -> Result<StageEnd, DemError> {
        let from = self.load.clone();
        let n = steps.max(1) as f64;
        let step = 1.0 / n;
        let h_min = step * 0.5f64.powi(self.opts.max_cutbacks as i32);
        let (mut t, mut h) = (0.0f64, step);
        let mut peak = 0.0f64;
        let mut seen = self.states.len();
        // The trial step already ends at a contact event: it is not cut again (no Zeno steps).
        let mut at_event = false;
        // The response of the last step cut by a break ([`super::step_predictor`]).
        let mut predictor: Option<StepPredictor> = None;
        while t < 1.0 - 1e-12 {
            // Never step over a step boundary: the recorded curve keeps its regular points.
            let boundary = (((t * n) + 1e-9).floor() + 1.0) / n;
            let mut t_try = (t + h).min(boundary).min(1.0);
            if boundary - t_try < 1e-9 * step {
                t_try = boundary; // no sliver steps from round-off
            }
            let z_old = self.z.clone();
            let load = LoadPoint::lerp(&from, target, t_try);
            // No equilibrium at the smallest increment: past a limit point of the path, the
            // state after the snap-back (module docs, "Snap-back").
            let mut snapped = false;
            let mut ok =
                match self.equilibrate_predicted(predictor.as_ref().filter(|_| self.predicts_steps()), &load, t, t_try)
                {
                    Ok(()) => true,
                    Err(DemError::NoConvergence { .. }) if h * 0.5 >= h_min => false,
                    Err(e @ DemError::NoConvergence { .. }) if self.opts.continuation => {
                        self.restore();
                        if self.continuation(&load, None, t_try).is_err() {
                            self.restore();
                            self.load = LoadPoint::lerp(&from, target, t);
                            return Err(e);
                        }
                        snapped = true;
                        true
                    }
                    Err(e) => {
                        self.restore();
                        self.load = LoadPoint::lerp(&from, target, t);
                        return Err(e);
                    }
                };
            // Energy released inside a converged step (crushing only): halve the step; at the
            // smallest one the release is a snap (module docs, "Snaps inside a step").
            if ok && !snapped && self.model.params.crushing.is_some() {
                let (imbalance, scale) = self.trial_step_imbalance();
                if imbalance.abs() > MAX_STEP_IMBALANCE * scale {
                    if h * 0.5 >= h_min {
                        self.restore();
                        self.n_cutbacks += 1;
                        self.n_imbalance_cutbacks += 1;
                        h = 0.5 * (t_try - t);
                        continue;
                    }
                    self.n_snaps_in_steps += 1;
                    snapped = true;
                }
            }
            let failure = if ok && !snapped { self.first_failure(&z_old) } else { None };
            if ok && !snapped && self.opts.contact_events && !at_event && failure.is_none_or(|(lam, _)| lam >= 1.0) {
                if let Some(lam) = self.first_contact_event(&z_old) {
                    let t_c = t + lam * (t_try - t);
                    let min = MIN_EVENT_STEP * step;
                    if t_c - t >= min && t_try - t_c >= min {
                        self.restore();
                        self.n_contact_events += 1;
                        h = t_c - t;
                        at_event = true;
                        continue;
                    }
                }
            }
            at_event = false;
            if snapped {
                self.n_continued_steps += 1;
                self.commit(t_try, StateKind::Relaxed);
                t = t_try;
                self.load = load.clone();
                while let Some(bb) = self.most_critical() {
                    self.release(bb, &load, t_try)?;
                }
            } else if ok {
                match failure {
                    None => {
                        self.commit(t_try, StateKind::Loading);
                        t = t_try;
                    }
                    Some((lam, _)) if lam >= 1.0 => {
                        self.commit(t_try, StateKind::Loading);
                        t = t_try;
                    }
                    Some((lam, b)) => {
                        let t_l = t + lam * (t_try - t);
                        let load_l = LoadPoint::lerp(&from, target, t_l);
                        let z_end = self.z.clone();
                        if self.contacts.is_empty() {
                            for (zo, zn) in z_old.iter().zip(self.z.iter_mut()) {
                                *zn = zo + lam * (*zn - zo);
                            }
                        } else {
                            // Newton starts from the interpolated state: exact while the contact
                            // forces are linear along the step, so usually one iteration away.
                            for (zo, zn) in z_old.iter().zip(self.z.iter_mut()) {
                                *zn = zo + lam * (*zn - zo);
                            }
                            match self.equilibrate(&load_l, t_l) {
                                Ok(()) => {}
                                Err(DemError::NoConvergence { .. }) if h * 0.5 >= h_min => ok = false,
                                Err(e) => {
                                    self.restore();
                                    self.load = LoadPoint::lerp(&from, target, t);
                                    return Err(e);
                                }
                            }
                        }
                        if ok {
                            self.commit(t_l, StateKind::PreBreak);
                            predictor = Some(StepPredictor::new(t_l, t_try, &self.z, &z_end));
                            t = t_l;
                            self.load = load_l.clone();
                            let mut next = Some(b);
                            while let Some(bb) = next {
                                self.release(bb, &load_l, t_l)?;
                                next = self.most_critical();
                            }
                        }
                    }
                }
            }
            if !ok {
                self.restore();
                self.n_cutbacks += 1;
                h = 0.5 * (t_try - t);
                continue;
            }
            self.load = LoadPoint::lerp(&from, target, t);
            h = (2.0 * h).min(step);
            if let Some((k, a)) = monitor {
                for st in &self.states[seen..] {
                    peak = peak.max(st.platen_force[k][a].abs());
                }
                seen = self.states.len();
                let r = self.states.last().map_or(0.0, |s| s.platen_force[k][a].abs());
                if !self.broken.is_empty() && peak > 0.0 && r < self.opts.loss_fraction * peak {
                    return Ok(StageEnd::LossOfLoad);
                }
            }
        }
        self.load = target.clone();
        self.stage += 1;
        Ok(StageEnd::Completed)
    }
}
