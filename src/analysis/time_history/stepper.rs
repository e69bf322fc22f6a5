//! One time step: Newton iterations on the scheme's residual, halved substeps when they fail.
//!
//! The residual of step `n → n+1` (size `h`) at the trial `u = u_{n+1}` (see [`super::scheme`]):
//!
//! ```text
//!   r(u) = (1+α) f_{n+1} − α f_n + α (C v_n + f_int,n) − M a_{n+1} − (1+α)(C v_{n+1} + f_int(u))
//! ```
//!
//! Newton: `(K + c_m M + c_c C) Δu = r / (1+α)`, `u ← u + Δu`, from the predictor `u = u_n`,
//! converged when `‖r‖ ≤ tol · (‖(1+α) f_{n+1} − α f_n + α(C v_n + f_int,n)‖ + ‖M a‖ + (1+α)(‖C v‖ + ‖f_int‖))`.
//! `K` is the tangent at every iteration (`tangent`), at the step's start (`modified`) or the
//! initial stiffness (`initial`); the system keeps a factorization while `K` and the coefficients
//! stay the same, so a linear model factors once per step size. `krylov` is `modified` with the
//! corrections accelerated in the subspace of the previous ones ([`super::krylov`]), the tangent
//! refreshed at the current iterate when that subspace is full.
//!
//! A linear system (no element with state) takes the step of [`super::linear_step`] instead: one
//! solve and two products, its residual checked with fresh products every few steps.
//!
//! # IMPL-EX
//! With `[dynamics] integration = "implex"` every attempt of a (sub)step of size h first gives
//! the elements h ([`DynamicSystem::set_implex_step`]): their damage histories are extrapolated
//! by the ratio of h to the last committed (sub)step's size and held for the attempt
//! (`material::implex`), the unilateral split taken at the step's strain or frozen at the
//! committed one (`[dynamics] implex_split`). The residual at the predictor is then evaluated by
//! the elements (their stress at u_n differs from the committed `f_int,n` by the new
//! extrapolation), and the iterations solve an equilibrium without softening: piecewise linear
//! where cracks open or close (the split at the step's strain), linear with the split frozen,
//! one iteration on the step's own matrix (`modified`, `tangent`) or a few accelerated ones on a
//! kept one (`krylov`). Everything else is the implicit stepper's: the
//! convergence test, the substeps on a failure or a damage increment (that of the histories'
//! implicit update) over the limit, the commit, the energies.
//!
//! # IMPL-EX corrections
//! With `[dynamics] implex_corrections = K > 0`, a converged IMPL-EX (sub)step is not accepted
//! at once: its implicit update (κ from κ_n at the converged strain, [`DynamicSystem::update_histories`])
//! becomes the damage held by the step ([`DynamicSystem::hold_histories`]), and the equilibrium
//! is solved again from the converged iterate, K times (a staggered, alternating iteration
//! between equilibrium at fixed damage and the damage of that equilibrium):
//!
//! ```text
//!   κ⁽⁰⁾ = κ̃ (extrapolated);   for k = 0 … K:  u⁽ᵏ⁾ = equilibrium at d(κ⁽ᵏ⁾),
//!                                               κ⁽ᵏ⁺¹⁾ = max(κ_n, ε_eq(ε(u⁽ᵏ⁾)))
//!   accepted: u⁽ᴷ⁾, the histories κ⁽ᴷ⁺¹⁾ committed (as IMPL-EX commits its implicit update)
//! ```
//!
//! A fixed point of the iteration is the implicit step's solution; the extrapolation is its
//! predictor, which selects the branch where the implicit step has more than one. Each pass is
//! an equilibrium at fixed damage, as IMPL-EX's, and K is fixed: no decision of the step
//! depends on how close an iterate comes to a threshold, so round-off moves the answer by
//! round-off (a Newton cap or a halving, which the implicit step needs, is such a decision).
//! The iterations of all passes count as the step's; `max_iterations` caps each pass. A pass
//! whose held damage differs from the damage its equilibrium had by at most
//! `implex_correction_tolerance` at every point (max |Δd_t|, |Δd_c|, one max-reduction; 0 at
//! every point of a quiet step) ends the corrections, at no further evaluation: the step's
//! equilibrium is then within the response to that damage change of the next pass's, and the
//! committed histories are the implicit update at it. The stop is a decision, but one whose
//! two outcomes differ by less than the tolerance in damage, unlike a halving, whose two
//! outcomes are two different paths.
//!
//! The passes before the last only decide the damage the next one holds, so they may stop at a
//! looser force tolerance, `implex_pass_tolerance`: a pass converged to it whose held damage
//! moves by more than `implex_correction_tolerance` goes on to the next pass as before; one
//! whose damage has settled (or the K-th) goes on iterating at its held damage to the step's
//! own `tolerance`, so the accepted equilibrium is as tight as without. Measured on the church's
//! member at 1.5 times the code level (4 s, 1 rank, force tolerance 1e-6): 1e-3 for the passes
//! took 3,416 iterations against 6,588 and 177 s against 299 s, with the same shares to the
//! printed digits but the tower's (47.54 against 47.70 %), the drift to 5 digits and the
//! energies within 5e-4 of the input; but its dt/2 against dt/4 is 2.08 points, outside the
//! study's 2-point band that every pass tight meets. With 1e-4 it is 1.04 points, the tight
//! passes' shares to the printed digits, with 14–15 % fewer iterations
//! (docs/convergence-implex.md).
//!
//! A step that does not converge (too many iterations, a non-finite residual, an element or solver
//! error) is retried as two half steps, recursively, down to `h / 2^max_substeps`; the elements
//! are reverted before each retry. When even that fails, the elements keep the failed trial state
//! (for the diagnosis) and the caller decides.
//!
//! # Damage control
//! The damage of an integration point is an implicit function of its strain history; a step that
//! crosses a large part of the softening branch in one go gives a damage that moves with `dt`.
//! With `[dynamics] max_damage_increment = Δd_max < 1` (and an element with state), the substeps
//! follow the damage, as load increments do in quasi-static damage analyses:
//!
//! ```text
//!   Δd = max over points of max(d_t,trial − d_t,committed, d_c,trial − d_c,committed)
//!   converged substep h, Δd > Δd_max, h/2 ≥ h_min    → revert, halve: a damage cut
//!   converged substep h, Δd > Δd_max, h = h_min       → accepted (counted: over the limit)
//!   accepted substep with Δd < Δd_max / 4             → the next substep may double
//!   h_min = dt / 2^max_substeps
//! ```
//!
//! Doubling keeps every size `dt / 2^k` and the substeps on the step's dyadic grid
//! ([`super::substeps`]), so the nominal step's end is hit exactly. The size reached at the end
//! of a step is where the next one starts ([`State::substep_level`]): a phase of strong damage
//! does not try `dt` again at every step, and quiet steps bring the size back up to `dt`, one
//! doubling per quiet substep. A quarter of the limit for growth leaves a margin: a substep
//! that doubles at Δd < Δd_max/4 takes roughly twice the increment (under Δd_max/2, where the
//! damage grows steadily) and is not cut at once. Newton failures halve as before, and the size
//! they leave is kept the same way. `Δd_max = 1` switches the control off: every step then
//! starts at `dt`, no increment is measured (no reduction over ranks) and the steps are those
//! of a stepper without the control. A linear system takes no substeps of its own.
//!
//! # Line search
//! With `[dynamics] line_search = true` each correction Δu (accelerated under `krylov`) is
//! followed by the secant line search of [`crate::analysis::line_search`]: the step length η
//! with `s(η) = Δu · r(u + η Δu) ≈ 0`, the full step kept when `|s(1)| ≤ 0.8 |s(0)|`, so that an
//! iteration that reduces the projection costs nothing more (the residual at η = 1 is the next
//! iteration's). Where a point crosses a switch of the law within a correction (its damage
//! threshold, a principal strain changing sign in the split) r(u) is kinked: the linearization
//! on either side points across the kink, the iterates cross it back and forth, and the search
//! lands on it instead (as the gravity phase's, `super::gravity`). Under `krylov` the
//! accelerator's last direction is scaled by η, so that its secant pair is the step taken.
use super::energy::StepVectors;
use super::krylov::KrylovAccelerator;
use super::linear_step::{LinearStep, Outcome};
use super::refresh::RefreshPolicy;
use super::scheme::Scheme;
pub use super::state::{external_force, State};
use super::substeps::Substeps;
use super::system::DynamicSystem;
use super::trial::Trial;
use crate::config::{IntegrationKind, NewtonKind};

/// Settings of the iterations.
#[derive(Clone, Copy, Debug)]
pub struct StepSettings {
    /// Scheme.
    pub scheme: Scheme,
    /// Newton variant.
    pub newton: NewtonKind,
    /// Implicit damage, or IMPL-EX (module docs).
    pub integration: IntegrationKind,
    /// Subspace size of [`NewtonKind::Krylov`].
    pub krylov_dimension: usize,
    /// [`NewtonKind::Krylov`]: extra iterations that pay for a tangent refresh
    /// ([`super::refresh`]; 0: a fresh tangent at every step).
    pub refresh_cost: usize,
    /// Iterations per (sub)step.
    pub max_iterations: usize,
    /// Relative force tolerance.
    pub tolerance: f64,
    /// Halvings allowed.
    pub max_substeps: usize,
    /// The largest damage increment of a substep (module docs, "Damage control"); 1 or more:
    /// no control.
    pub max_damage_increment: f64,
    /// A secant line search along each correction (module docs, "Line search").
    pub line_search: bool,
    /// IMPL-EX: equilibria solved again at the implicitly updated damage (module docs,
    /// "IMPL-EX corrections"); 0 without.
    pub implex_corrections: usize,
    /// IMPL-EX: a correction pass whose held damage changes by at most this ends the
    /// corrections (module docs, "IMPL-EX corrections").
    pub implex_tolerance: f64,
    /// IMPL-EX: the force tolerance of the passes before the last, at least `tolerance` (module
    /// docs, "IMPL-EX corrections"); 0 or `tolerance`: every pass to `tolerance`.
    pub implex_pass_tolerance: f64,
}

impl StepSettings {
    /// The line search's settings: those of `analysis::line_search`.
    fn line_search_settings(&self) -> crate::analysis::line_search::LineSearchSettings {
        crate::analysis::line_search::LineSearchSettings::default()
    }

    /// Whether the damage control is on for `sys`: a limit below 1 and an element with state.
    fn damage_control<S: DynamicSystem>(&self, sys: &S) -> bool {
        self.max_damage_increment < 1.0 && !sys.is_linear()
    }
}

/// What a converged step took.
#[derive(Clone, Copy, Debug, Default)]
pub struct StepReport {
    /// Newton iterations (solves), summed over substeps.
    pub iterations: usize,
    /// Substeps (1 when the step converged whole).
    pub substeps: usize,
    /// Relative residual at convergence (largest over substeps); for a linear step, the one of
    /// its last check.
    pub residual: f64,
    /// Newton iterations of the attempts that failed and were halved (not in `iterations`).
    pub failed_iterations: usize,
    /// Converged substeps taken again as two halves because their damage increment exceeded
    /// the limit (module docs, "Damage control").
    pub damage_cuts: usize,
    /// Newton iterations of those substeps (not in `iterations`).
    pub damage_cut_iterations: usize,
    /// Substeps accepted at the smallest size with a damage increment over the limit.
    pub over_limit: usize,
    /// The smallest substep accepted [s].
    pub smallest_substep: f64,
    /// The largest damage increment of the accepted substeps (0 without the control: not
    /// measured).
    pub damage_increment: f64,
    /// IMPL-EX correction passes of the accepted substeps (module docs, "IMPL-EX corrections").
    pub implex_passes: usize,
}

/// Why a step failed.
#[derive(Debug)]
pub struct StepFailure {
    /// Time reached (the last converged substep).
    pub t: f64,
    /// Smallest substep tried.
    pub h: f64,
    /// Its last relative residual.
    pub residual: f64,
    /// Its last residual vector (owned entries).
    pub r: Vec<f64>,
    /// What stopped it.
    pub reason: String,
}

/// The step driver, with its scratch vectors. It holds no state of the analysis.
pub struct Stepper {
    /// Settings.
    pub settings: StepSettings,
    s: Trial,
    krylov: KrylovAccelerator,
    linear: LinearStep,
    /// When Krylov–Newton forms the tangent again.
    pub refresh: RefreshPolicy,
}

/// The Jacobian for iteration `it` of the Newton variant (module docs): refactored at the trial
/// `u` every iteration (`tangent`), at the first (`modified`), the initial stiffness (`initial`);
/// `krylov` starts a new subspace at the first iteration, on the tangent kept from earlier steps
/// or on a fresh one as the [`RefreshPolicy`] decides, and refreshes it whenever the subspace is
/// full. Returns whether the tangent was formed at the trial.
#[allow(clippy::too_many_arguments)]
fn prepare_jacobian<S: DynamicSystem>(
    sys: &mut S,
    kind: NewtonKind,
    (it, h): (usize, f64),
    krylov: &mut KrylovAccelerator,
    refresh: &mut RefreshPolicy,
    u: &[f64],
    c_m: f64,
    c_c: f64,
) -> Result<bool, crate::error::Error> {
    let fresh = match kind {
        NewtonKind::Tangent => true,
        NewtonKind::Modified => it == 0,
        NewtonKind::Initial => return sys.prepare(None, c_m, c_c).map(|_| false),
        NewtonKind::Krylov if it == 0 => {
            krylov.clear();
            refresh.refresh_at_start(h)
        }
        NewtonKind::Krylov if krylov.is_full() => {
            krylov.clear();
            refresh.refreshed_within();
            true
        }
        NewtonKind::Krylov => false,
    };
    if fresh {
        sys.prepare(Some(u), c_m, c_c)?;
    }
    Ok(fresh)
}

enum Attempt {
    Converged { iterations: usize, residual: f64, passes: usize },
    Failed { iterations: usize, residual: f64, reason: String },
}

impl Stepper {
    /// A stepper.
    pub fn new(settings: StepSettings) -> Stepper {
        Stepper {
            settings,
            s: Trial::default(),
            krylov: KrylovAccelerator::new(settings.krylov_dimension),
            linear: LinearStep::default(),
            refresh: RefreshPolicy::new(settings.refresh_cost),
        }
    }

    /// Forgets what the stepper keeps from earlier steps (the refresh policy's history, the
    /// factored tangent's validity, the linear step's products): the next step starts as the
    /// first step of a new stepper would.
    pub fn start_afresh(&mut self) {
        self.refresh.forget();
        self.linear.invalidate();
    }

    /// Advances `state` to time `target` (one nominal step), substepping if needed (module docs).
    /// On success every element is committed; on failure the elements hold the last failed trial
    /// state. Collective.
    pub fn advance<S: DynamicSystem>(
        &mut self,
        sys: &mut S,
        ground: &dyn Fn(f64) -> [f64; 3],
        state: &mut State,
        target: f64,
        dt: f64,
    ) -> Result<StepReport, StepFailure> {
        // Substeps are dt / 2^k exactly (not differences of times, whose round-off would change
        // the Jacobian's coefficients and defeat the reuse of its factorization); the last one
        // ends exactly at `target`.
        let h_min = dt / f64::powi(2.0, self.settings.max_substeps as i32);
        let mut big = dt.min(target - state.t).max(f64::MIN_POSITIVE);
        if (big - dt).abs() <= 1e-9 * dt {
            big = dt;
        }
        if sys.is_linear() && target - state.t <= big * (1.0 + 1e-9) {
            let sc = self.settings.scheme;
            match self.linear.step(sys, ground, state, (target, big), sc, self.settings.tolerance) {
                Ok(Outcome::Done { residual }) => {
                    return Ok(StepReport {
                        iterations: 1,
                        substeps: 1,
                        residual,
                        smallest_substep: big,
                        ..Default::default()
                    })
                }
                // The Newton path iterates the step to the tolerance, or substeps and reports.
                Ok(Outcome::Missed) | Err(_) => self.linear.invalidate(),
            }
        }
        let control = self.settings.damage_control(sys);
        let first = if control { state.substep_level } else { 0 };
        let mut sub = Substeps::new(Substeps::halvings_allowed(big, h_min), first);
        let mut report = StepReport { smallest_substep: f64::INFINITY, ..Default::default() };
        loop {
            let h = sub.size(big);
            let last = sub.is_last();
            let t1 = if last { target } else { state.t + h };
            match self.attempt(sys, ground, state, t1, h) {
                Attempt::Converged { iterations, residual, passes } => {
                    report.implex_passes += passes;
                    if !self.settle(sys, ground, state, (t1, h), &mut sub, &mut report, iterations, residual) {
                        continue;
                    }
                    if last {
                        state.step += 1;
                        // Only a step of the job's dt sets the size of the next one.
                        if control && big == dt {
                            state.substep_level = sub.level();
                        }
                        return Ok(report);
                    }
                }
                Attempt::Failed { iterations, residual, reason } => {
                    report.failed_iterations += iterations;
                    self.refresh.failed();
                    if !sub.can_halve() {
                        return Err(StepFailure { t: state.t, h, residual, r: self.s.r.clone(), reason });
                    }
                    sys.revert();
                    sub.halve();
                }
            }
        }
    }

    /// A converged substep `(t1, h)`: with the damage control on, taken again as two halves when
    /// its damage increment exceeds the limit and it can still be halved (returns false: the
    /// elements reverted); else committed and accepted into `state`, the next substep doubled
    /// where the increment stayed below a quarter of the limit (returns true). Collective.
    #[allow(clippy::too_many_arguments)]
    fn settle<S: DynamicSystem>(
        &mut self,
        sys: &mut S,
        ground: &dyn Fn(f64) -> [f64; 3],
        state: &mut State,
        (t1, h): (f64, f64),
        sub: &mut Substeps,
        report: &mut StepReport,
        iterations: usize,
        residual: f64,
    ) -> bool {
        let limit = self.settings.max_damage_increment;
        let control = self.settings.damage_control(sys);
        if control && self.settings.integration == IntegrationKind::Implex {
            sys.update_histories();
        }
        let increment = if control { sys.max_damage_increment() } else { 0.0 };
        if increment > limit {
            if sub.can_halve() {
                report.damage_cuts += 1;
                report.damage_cut_iterations += iterations;
                sys.revert();
                sub.halve();
                return false;
            }
            report.over_limit += 1;
        }
        sys.commit();
        self.accept(sys, ground, state, t1);
        report.iterations += iterations;
        report.substeps += 1;
        report.residual = report.residual.max(residual);
        report.smallest_substep = report.smallest_substep.min(h);
        report.damage_increment = report.damage_increment.max(increment);
        sub.accept();
        if control && increment < 0.25 * limit {
            sub.try_double();
        }
        true
    }

    /// Newton iterations from `state` to `t1`; the trial solution is left in the scratch vectors.
    fn attempt<S: DynamicSystem>(
        &mut self,
        sys: &mut S,
        ground: &dyn Fn(f64) -> [f64; 3],
        state: &State,
        t1: f64,
        h: f64,
    ) -> Attempt {
        let st = self.settings;
        sys.set_step_size(h);
        let implex = st.integration == IntegrationKind::Implex;
        if implex {
            sys.set_implex_step(h);
        }
        let rhs_norm = match self.s.start_step(sys, ground, state, t1, h, st.scheme) {
            Ok(norm) => norm,
            Err(e) => return Attempt::Failed { iterations: 0, residual: f64::INFINITY, reason: e.to_string() },
        };
        let jacobian = st.scheme.jacobian_coefficients(h);
        let mut residual = f64::INFINITY;
        let mut scale0 = 0.0f64;
        // Whether the first correction formed the tangent, and how often the others did.
        let (mut fresh, mut within) = (false, 0);
        // s(0) = Δu · r of the last correction, with the line search.
        let mut s0: Option<f64> = None;
        // Corrections made (the iterations), and those of the IMPL-EX corrections before.
        let (mut it, mut earlier, mut corrections) = (0, 0, 0);
        // IMPL-EX: the damage has settled and the last equilibrium is being solved to `tolerance`.
        let mut settling = false;
        loop {
            // IMPL-EX: the stress at u_n is that of the step's extrapolated damage.
            let known = (it == 0 && !implex).then_some(state.f_int.as_slice());
            let failed = |residual, reason| Attempt::Failed { iterations: it, residual, reason };
            let searched = self.s.residual_at_trial(sys, st.scheme.alpha, rhs_norm, known).and_then(|norms| match s0 {
                Some(s0) => self.search(sys, state, (h, rhs_norm), s0, norms),
                None => Ok(norms),
            });
            let (rn, current) = match searched {
                Ok(norms) => norms,
                Err(e) => return failed(residual, e.to_string()),
            };
            if it == 0 && corrections == 0 {
                scale0 = current;
            }
            // At most G·scale₀: a diverging iterate cannot loosen its own test.
            let scale = crate::analysis::newton::bounded_reference(current, scale0);
            residual = if scale > 0.0 { rn / scale } else { rn };
            if !residual.is_finite() {
                return failed(residual, "the residual is not finite".into());
            }
            if residual > crate::analysis::newton::DIVERGED {
                return failed(residual, format!("iteration {it}: the iterate diverged"));
            }
            let loose = implex && !settling && corrections < st.implex_corrections;
            let tol_now = if loose { st.tolerance.max(st.implex_pass_tolerance) } else { st.tolerance };
            if rn == 0.0 || residual <= tol_now {
                if loose {
                    // Module docs, "IMPL-EX corrections": the damage of this equilibrium held;
                    // where it is the damage the equilibrium had, so is the residual.
                    sys.update_histories();
                    if sys.hold_histories() > st.implex_tolerance {
                        (corrections, earlier, s0) = (corrections + 1, it, None);
                        continue;
                    }
                    if tol_now > st.tolerance && residual > st.tolerance {
                        settling = true;
                        (earlier, s0) = (it, None);
                        continue;
                    }
                }
                if it > 0 {
                    self.refresh.converged(it, fresh, within);
                }
                return Attempt::Converged { iterations: it, residual, passes: corrections };
            }
            if it - earlier == st.max_iterations {
                break;
            }
            match self.correct(sys, state, h, it, jacobian) {
                Ok(formed) if it == 0 => fresh = formed,
                Ok(formed) => within += formed as usize,
                Err(e) => return failed(residual, e.to_string()),
            }
            s0 = st.line_search.then(|| sys.dot(&self.s.du, &self.s.r));
            it += 1;
        }
        Attempt::Failed {
            iterations: it,
            residual,
            reason: format!("no convergence in {} iterations", st.max_iterations),
        }
    }

    /// The Newton correction of iteration `it`: the Jacobian `K + c_m M + c_c C` of the variant
    /// ([`prepare_jacobian`]), `Δu = J⁻¹ r / (1+α)` (accelerated under `krylov`), `u ← u + Δu`
    /// with the scheme's v and a. `r` is left divided by 1+α, also when the solve fails. Returns
    /// whether the tangent was formed.
    fn correct<S: DynamicSystem>(
        &mut self,
        sys: &mut S,
        state: &State,
        h: f64,
        it: usize,
        (c_m, c_c): (f64, f64),
    ) -> Result<bool, crate::error::Error> {
        let (st, s) = (self.settings, &mut self.s);
        let sc = st.scheme;
        let prepared = prepare_jacobian(sys, st.newton, (it, h), &mut self.krylov, &mut self.refresh, &s.u, c_m, c_c);
        for x in s.r.iter_mut() {
            *x /= 1.0 + sc.alpha;
        }
        let formed = prepared?;
        sys.solve(&s.r, &mut s.du)?;
        if st.newton == NewtonKind::Krylov {
            self.krylov.correct(sys, &mut s.du);
        }
        if st.line_search {
            s.u0.copy_from_slice(&s.u);
        }
        for i in 0..s.u.len() {
            s.u[i] += s.du[i];
        }
        sc.kinematics(h, &state.u, &state.v, &state.a, &s.u, &mut s.v, &mut s.a);
        Ok(formed)
    }

    /// The line search along the last correction `Δu` from `u0` (module docs, "Line search"),
    /// given `s(0)` (with `r / (1+α)`) and the residual's norms at the full step: the trial is
    /// left at the chosen `η` with its residual, whose norms are returned. A step length other
    /// than 1 scales the accelerator's last direction, so that its secant pair is the step
    /// taken. Collective.
    fn search<S: DynamicSystem>(
        &mut self,
        sys: &mut S,
        state: &State,
        (h, rhs_norm): (f64, f64),
        s0: f64,
        full: (f64, f64),
    ) -> Result<(f64, f64), crate::error::Error> {
        let sc = self.settings.scheme;
        let settings = self.settings.line_search_settings();
        let scale = 1.0 / (1.0 + sc.alpha);
        let s1 = scale * sys.dot(&self.s.du, &self.s.r);
        let (mut norms, mut at) = (full, 1.0);
        let s = &mut self.s;
        let found =
            crate::analysis::line_search::secant(s0, s1, &settings, |eta| -> Result<f64, crate::error::Error> {
                at = eta;
                norms = s.move_along(sys, state, (h, rhs_norm), sc, eta)?;
                Ok(scale * sys.dot(&s.du, &s.r))
            })?;
        if at != found.eta {
            norms = s.move_along(sys, state, (h, rhs_norm), sc, found.eta)?;
        }
        if found.eta != 1.0 && self.settings.newton == NewtonKind::Krylov {
            self.krylov.scale_last(found.eta);
        }
        Ok(norms)
    }

    /// Moves the converged trial solution into `state` and updates the energies (the
    /// trapezoidal sums of [`super::energy`], no allocation: the correction and the trial's
    /// inertia vectors are free once the step has converged).
    fn accept<S: DynamicSystem>(&mut self, sys: &mut S, ground: &dyn Fn(f64) -> [f64; 3], state: &mut State, t1: f64) {
        let s = &mut self.s;
        // f_0, f_1 were evaluated at the attempt's times: recompute for exactness of t1.
        external_force(sys, ground(t1), &mut s.f1);
        for i in 0..s.u.len() {
            s.du[i] = s.u[i] - state.u[i];
        }
        // A failure here would have shown in the iterations (same operator).
        let mv_ok = sys.mass_mult(&s.v, &mut s.ma).is_ok();
        let step = StepVectors {
            du: &s.du,
            f: [&s.f0, &s.f1],
            cv: [&state.cv, &s.cv],
            fi: [&state.f_int, &s.fi],
            u: &s.u,
            v: &s.v,
            mv: mv_ok.then_some(s.ma.as_slice()),
        };
        state.energy.add_step(sys, step);
        // The elements were committed before `accept`: their dissipation is the step's end's.
        state.energy.damage = sys.dissipated_energy();
        state.u.copy_from_slice(&s.u);
        state.v.copy_from_slice(&s.v);
        state.a.copy_from_slice(&s.a);
        state.f_int.copy_from_slice(&s.fi);
        state.cv.copy_from_slice(&s.cv);
        state.t = t1;
    }
}
