//! The break search: one equilibrium per break ([`super::SolverOptions::break_search`] =
//! [`BreakSearch::Tangent`]; off by default).
//!
//! The trial path ([`BreakSearch::Trial`], [`super::stage`]) solves a load step `t₀ → t₁` to
//! its end, finds the first beam's crossing `λ*` on the chord from the step's start to that
//! equilibrium, and solves again at `λ*`: near the peak, where nearly every step ends at a
//! break, the equilibrium at `t₁` is solved only to be thrown away. The search predicts `λ*`
//! from the tangent at the step's start instead and solves the equilibrium there only.
//!
//! **Prediction.** At the committed equilibrium `z₀` (load `t₀`, every intact beam below its
//! threshold), the residual with the load of `t₁` is the load increment `Δf` (the platens'
//! move, their forces), and one solve with the consistent tangent gives the step's linear
//! response:
//!
//! ```text
//!   K_T δz = r(z₀; t₁) = Δf           (Newton's first direction of a step from z₀: GMRES
//!                                      preconditioned by the factorized operator, tolerance
//!                                      PREDICTOR_ETA; one direct solve without contacts)
//!   z_p = z₀ + (Δu_platen, δz)        (the tangent's end of the step)
//! ```
//!
//! Along `z₀ + s (z_p − z₀)` each beam's end displacements are linear in `s`, and so are its
//! axial strain `ε` and relative rotation `φ`. Its failure index
//!
//! ```text
//!   P_b(s) = (ε₀ + s Δε)/ε_cr + |φ₀ + s Δφ|/θ_cr        (crushing: P_c = −Ē ε/σ_c, linear)
//! ```
//!
//! is piecewise linear with one kink at `s = −φ₀/Δφ`; on the piece `[a, b]` where it reaches 1
//! the crossing is closed-form, `s_b = a + (1 − P_b(a)) / (Δε/ε_cr + σ Δφ/θ_cr)` with `σ` the
//! sign of `φ` on the piece ([`crate::dem::mechanics::failure_lambda`]). `s* = min_b s_b`
//! ([`first_crossing_on_chord`]). `s* ≥ 1`: no beam breaks inside the step, which is taken as
//! a trial step (whose chord is still checked for a break, as on the trial path).
//!
//! **Landing.** Newton's method is run at `λ₁ = t₀ + s* (t₁ − t₀)` from `z₀ + s* (z_p − z₀)`,
//! and the beams' indices are read at its equilibrium `z(λ₁)`:
//!
//! ```text
//!   P_max = max_b P_b(z(λ₁))
//!   |P_max − 1| ≤ LANDING_TOL   landed: the beam of P_max breaks at λ₁ (state "pre-break")
//!   P_max > 1                   past it: hi = λ₁; the next λ on the chord lo → z(λ₁)
//!   P_max < 1                   short of it: the next λ on the chord from the last state
//!                               below through z(λ₁), extended up to hi (or t₁); lo = λ₁
//! ```
//!
//! `lo` is the last equilibrium with every index below 1 (`z₀` at first), `hi` the last one
//! past it. On a chord between two equilibria every index is again piecewise linear, so the
//! next `λ` is the closed-form first crossing of the chord (the secant of the equilibrium path:
//! regula falsi when past, the secant extended when short), and Newton starts from the chord's
//! point. A guess outside `(lo, hi)` bisects. Without contacts the path is linear in `λ` and
//! the tangent exact, so the first guess lands with no Newton iteration (its residual is
//! already within the tolerance). With contacts the path bends (a contact's force grows with
//! its overlap area, and contacts open, close and slide along it); each pass shrinks the error
//! of the crossing by the chord's curvature, and a chord point that is already an equilibrium
//! to the tolerance lands on `P = 1` to round-off. No landing in `MAX_PASSES` equilibria, no
//! equilibrium at a guess, or no crossing inside the step on a second look: the search gives up
//! and the step is taken as a trial step from the committed state.
//!
//! **Breaks the tangent did not predict.** A step whose prediction shows no break is a trial
//! step; if its chord shows one (the path bent towards a threshold), that break is landed by
//! the same passes from the chord's crossing ([`land`]; [`BreakSearch::TrialLanded`] lands every
//! break of the trial path so). Only a landing given up falls back to the trial path's.
//!
//! **Against the trial path.** The trial path lands on the chord from `z₀` to the equilibrium
//! at `t₁`, then re-solves there: its pre-break state sits where that chord, not the
//! equilibrium path, has `P_b = 1`. On the 1k reference (`tests/data/dem-random-1k`) its
//! pre-break states have `|P_b − 1|` of 1.9·10⁻⁶ (median), 4.7·10⁻⁵ (90 %), 8.9·10⁻⁴ (largest)
//! with contacts, round-off without; the search's are within `LANDING_TOL`. The same beams break
//! in the same order and modes; the stresses at the regular load points (the ends of the load
//! steps) agree within 10⁻⁸ of the peak until a break the trial path took late leaves the next
//! beam over its threshold in a cascade that the search reaches by a further load increment,
//! and by 2·10⁻⁷ of the peak after it. Against the trial path with landed breaks the search
//! records the same states and its regular points agree within 10⁻⁸ of the peak
//! (`break_search_tests.rs`; the landing tolerance from 10⁻⁶ to 10⁻¹² changes neither).
//!
//! **Not with crushing.** Crushing contacts soften: the equilibrium at a load depends on where
//! Newton's method starts ([`super::step_predictor`]), and a load step also checks its energy
//! balance; with `MechParams::crushing` the search is off and every step is a trial step.
use super::breaks::{first_crossing_on_chord, largest_index};
use super::diagnostics::Diagnostics;
use super::equilibrium::{apply_load, equilibrate, evaluate, newton_direction};
use super::error::DemError;
use super::operator::Refactor;
use super::options::BreakSearch;
use super::phases::Phase;
use super::problem::Problem;
use super::state::SolverState;
use super::step_predictor::StepPredictor;
use super::walk::StageWalk;
use super::workspace::{upkeep, Workspace};

/// A landing: `|P_max − 1|` at the equilibrium (module docs). A chord point in equilibrium to
/// the residual tolerance lands to round-off, so the passes past the first mostly cost no Newton
/// iteration: on the 1k reference, tolerances from 10⁻⁶ to 10⁻¹² gave the same Newton and GMRES
/// counts within 2 (docs/benchmarks.md, DEM).
pub(super) const LANDING_TOL: f64 = 1e-9;

/// Equilibria solved for one landing before the search gives up (module docs).
const MAX_PASSES: usize = 8;

/// The relative tolerance of the predictor's GMRES solve (module docs, "Prediction"). On the 1k
/// reference: 0.1 (Newton's first step) 3,252 Newton / 16,504 GMRES iterations, 10⁻³ 3,076 /
/// 16,336, 10⁻⁶ 2,995 / 17,842 (docs/benchmarks.md, DEM).
const PREDICTOR_ETA: f64 = 1e-3;

/// Where a load step's first beam reaches `P = 1`: the state is the equilibrium there.
pub(super) struct Landing {
    /// The load parameter of the break.
    pub t: f64,
    /// The beam that breaks.
    pub beam: usize,
    /// The start of the load step after the break: the response along the step's chord (the
    /// tangent's, or the trial's) over the step's span ([`super::step_predictor`]).
    pub predictor: StepPredictor,
}

/// An equilibrium of the search: its load parameter and coordinates.
#[derive(Clone)]
struct Point {
    t: f64,
    z: Vec<f64>,
}

impl Point {
    /// The point `μ` of the way from `self` to `other` (`μ > 1`: beyond `other`).
    fn toward(&self, other: &Point, mu: f64) -> Point {
        let z = self.z.iter().zip(&other.z).map(|(a, b)| a + mu * (b - a)).collect();
        Point { t: self.t + mu * (other.t - self.t), z }
    }
}

/// Whether load steps search for their first break ([`BreakSearch::Tangent`], never with
/// crushing; module docs).
pub(super) fn searches(pb: &Problem<'_>) -> bool {
    pb.opts.break_search == BreakSearch::Tangent && pb.model.params.crushing.is_none()
}

/// Whether a break found on a trial step's chord is landed on `P = 1` ([`land`]):
/// [`BreakSearch::Tangent`] and [`BreakSearch::TrialLanded`], never with crushing.
pub(super) fn lands(pb: &Problem<'_>) -> bool {
    pb.opts.break_search != BreakSearch::Trial && pb.model.params.crushing.is_none()
}

/// The first break of the load step from the committed state at `walk.t` to `t_try` (module
/// docs): `Some`, the state is the equilibrium at the landing (not committed); `None`, no
/// break inside the step or the search gave up, the state is the committed one.
pub(super) fn search_break(
    pb: &Problem<'_>,
    state: &mut SolverState,
    ws: &mut Workspace,
    diag: &mut Diagnostics<'_>,
    walk: &StageWalk,
    t_try: f64,
) -> Result<Option<Landing>, DemError> {
    let start = Point { t: walk.t, z: state.z.clone() };
    let tip = Point { t: t_try, z: tangent_end(pb, state, ws, diag, walk, t_try)? };
    let counts = &mut diag.profile.break_search;
    counts.predictor_solves += 1;
    let Some((s, _)) = first_crossing_on_chord(pb, &state.intact, &start.z, &tip.z, 1.0) else {
        counts.no_break += 1;
        return Ok(None);
    };
    land(pb, state, ws, diag, walk, (&start.z, &tip.z, t_try), s)
}

/// Lands the first break of the load step from the committed state at `walk.t` to `t_try`,
/// predicted at the fraction `s` of the chord `z₀ → z₁` (`z₁` at `t_try`: the tangent's end
/// of the step, or the equilibrium of a trial step): secant passes on the
/// equilibrium path until the largest index is within `LANDING_TOL` of 1 (module docs,
/// "Landing"). `None`: given up, the state is the committed one.
pub(super) fn land(
    pb: &Problem<'_>,
    state: &mut SolverState,
    ws: &mut Workspace,
    diag: &mut Diagnostics<'_>,
    walk: &StageWalk,
    (z0, z1, t_try): (&[f64], &[f64], f64),
    s: f64,
) -> Result<Option<Landing>, DemError> {
    let (start, tip) = (Point { t: walk.t, z: z0.to_vec() }, Point { t: t_try, z: z1.to_vec() });
    let (mut lo, mut hi): (Point, Option<Point>) = (start.clone(), None);
    let mut guess = lo.toward(&tip, s);
    for _ in 0..MAX_PASSES {
        let Some(p) = equilibrium_at(pb, state, ws, diag, walk, &guess)? else { break };
        let (p_max, beam) = largest_index(pb, &state.intact, &p.z);
        if (p_max - 1.0).abs() <= LANDING_TOL {
            diag.profile.break_search.landed += 1;
            // The next step starts from the response along the chord, over the same span.
            let predictor = StepPredictor::new(p.t, p.t + (t_try - start.t), &start.z, &tip.z);
            return Ok(Some(Landing { t: p.t, beam, predictor }));
        }
        let next = if p_max > 1.0 {
            diag.profile.break_search.cut_backs += 1;
            let mu = first_crossing_on_chord(pb, &state.intact, &lo.z, &p.z, 1.0).map(|(mu, _)| mu);
            let next = mu.map(|mu| lo.toward(&p, mu));
            hi = Some(p);
            next
        } else {
            diag.profile.break_search.short += 1;
            let limit = hi.as_ref().map_or(t_try, |h| h.t);
            let reach = (limit - lo.t) / (p.t - lo.t);
            let mu = first_crossing_on_chord(pb, &state.intact, &lo.z, &p.z, reach).map(|(mu, _)| mu);
            let next = mu.map(|mu| lo.toward(&p, mu));
            lo = p;
            if next.is_none() && hi.is_none() {
                break; // no crossing inside the step after all
            }
            next
        };
        guess = match (next, &hi) {
            (Some(g), Some(h)) if g.t > lo.t && g.t < h.t => g,
            (Some(g), None) if g.t > lo.t && g.t <= t_try => g,
            (_, Some(h)) => lo.toward(h, 0.5),
            (_, None) => break,
        };
    }
    state.restore();
    diag.profile.break_search.given_up += 1;
    Ok(None)
}

/// Newton's method at `guess.t` from `guess.z` (booked as a break's `λ*`): the equilibrium, or
/// `None` (the state restored) when it does not converge.
fn equilibrium_at(
    pb: &Problem<'_>,
    state: &mut SolverState,
    ws: &mut Workspace,
    diag: &mut Diagnostics<'_>,
    walk: &StageWalk,
    guess: &Point,
) -> Result<Option<Point>, DemError> {
    state.z.clone_from(&guess.z);
    diag.phase = Phase::Lambda;
    diag.profile.break_search.equilibria += 1;
    match equilibrate(pb, state, ws, diag, &walk.load_at(guess.t), None, guess.t) {
        Ok(()) => Ok(Some(Point { t: guess.t, z: state.z.clone() })),
        Err(e) => {
            state.restore();
            match e {
                DemError::NoConvergence { .. } => Ok(None),
                e => Err(e),
            }
        }
    }
}

/// The tangent's end of the load step from the committed state to `t_try` (module docs,
/// "Prediction"): Newton's first direction from the committed `z` with the load of `t_try`,
/// the prescribed coordinates at that load. The state is left at the committed `z`.
fn tangent_end(
    pb: &Problem<'_>,
    state: &mut SolverState,
    ws: &mut Workspace,
    diag: &mut Diagnostics<'_>,
    walk: &StageWalk,
    t_try: f64,
) -> Result<Vec<f64>, DemError> {
    let before = diag.profile.running();
    let clock = std::time::Instant::now();
    let f_ext = apply_load(pb, state, &walk.load_at(t_try), None);
    let z = state.z.clone();
    let ev = evaluate(pb, state, ws, diag, &z, &f_ext)?;
    ws.jacobians.fresh_only = false;
    ws.operator.sync(&mut upkeep(pb, state, &mut diag.profile), &ev.contacts)?;
    ws.operator.refresh(&mut upkeep(pb, state, &mut diag.profile), &pb.scales.reg)?;
    if ws.operator.factor.rank() > 0 && !ws.operator.factor.is_accurate() {
        let mut u = upkeep(pb, state, &mut diag.profile);
        ws.operator.refactorize(&mut u, Some(Refactor::Accuracy), &pb.scales.reg)?;
    }
    let dz = newton_direction(pb, state, ws, diag, &ev, PREDICTOR_ETA, None)?;
    let mut tip = z;
    for (e, &zi) in pb.model.map.unknowns.iter().enumerate() {
        tip[zi] += dz[e];
    }
    state.restore();
    let mut w = diag.profile.running().since(&before);
    (w.equilibria, w.seconds) = (1, clock.elapsed().as_secs_f64());
    diag.profile.phases.book(Phase::Predictor, false, &w);
    Ok(tip)
}
