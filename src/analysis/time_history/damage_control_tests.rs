//! The damage control of the stepper (`stepper.rs`, "Damage control") on the single-DOF bar of
//! `bar_tests.rs` with the masonry damage law.
//!
//! The bar cracks in tension (ε₀ᵗ = 5e-5: u = 50 µm) and closes in compression (the compressive
//! threshold is out of reach), so d_t climbs the softening branch over the first cycles; under
//! a₀ = 1 m/s² a step of 0.02 s raises it by more than 0.3 at the first opening (asserted
//! below).
use super::bar_tests::{largest_difference, linear_part, linear_part_methods, sampled, wall_law, AREA, LENGTH};
use super::scheme::Scheme;
use super::stepper::{State, StepReport, StepSettings, Stepper};
use super::system::{DenseSystem, DynamicSystem};
use crate::config::NewtonKind;
use crate::material::{uniaxial, DamageState, PointLaw};
use std::cell::RefCell;
use std::f64::consts::PI;

/// The bar (module docs): the linear part (mass, damping, influence) from a [`DenseSystem`],
/// the force from the law; the Jacobian with the secant stiffness (positive on the softening
/// branch, so Newton converges at any step size, linearly). `commits` records the damage
/// increment of every committed substep.
struct DamageBar {
    lin: DenseSystem,
    law: PointLaw,
    committed: DamageState,
    trial: DamageState,
    j: f64,
    commits: Vec<f64>,
}

impl DamageBar {
    fn new() -> DamageBar {
        let law = wall_law();
        let lin = linear_part(&law);
        let virgin = DamageState::virgin(&law);
        DamageBar { lin, law, committed: virgin, trial: virgin, j: 0.0, commits: Vec::new() }
    }

    fn respond(&self, u: f64) -> uniaxial::UniaxialResponse {
        uniaxial::update(&self.law, u / LENGTH, &self.committed)
    }
}

impl DynamicSystem for DamageBar {
    linear_part_methods!();
    fn internal_force(&mut self, u: &[f64], f: &mut [f64]) -> Result<(), crate::error::Error> {
        let r = self.respond(u[0]);
        self.trial = r.state;
        f[0] = AREA * r.stress;
        Ok(())
    }
    fn prepare(&mut self, tangent_at: Option<&[f64]>, c_m: f64, c_c: f64) -> Result<(), crate::error::Error> {
        let secant = tangent_at.map_or(self.law.e(), |u| self.respond(u[0]).secant);
        self.j = secant * AREA / LENGTH + c_m * self.lin.m[(0, 0)] + c_c * self.lin.c[(0, 0)];
        Ok(())
    }
    fn solve(&mut self, r: &[f64], x: &mut [f64]) -> Result<(), crate::error::Error> {
        x[0] = r[0] / self.j;
        Ok(())
    }
    fn max_damage_increment(&self) -> f64 {
        crate::element::damage_increment(&[self.trial], &[self.committed])
    }
    fn commit(&mut self) {
        self.commits.push(self.max_damage_increment());
        self.committed = self.trial;
    }
    fn revert(&mut self) {
        self.trial = self.committed;
    }
}

/// The ground motion of the module docs, with amplitude `a0` [m/s²].
fn ground(a0: f64) -> impl Fn(f64) -> f64 {
    move |t: f64| if t < 0.6 { a0 * (2.0 * PI * 4.0 * t).sin() } else { 0.0 }
}

/// What a run gives: d_t after each step, the reports, the bar (its commits), every time
/// the stepper evaluated the ground at, and the final state.
struct Run {
    d_t: Vec<f64>,
    reports: Vec<StepReport>,
    bar: DamageBar,
    times: Vec<f64>,
    last: State,
}

/// `duration / dt` steps of `dt` under `a0`, with the damage limit `limit` (1: off) and
/// `max_substeps` halvings; Newton with the secant to 1e-9 (the round-off floor of the relative
/// residual of the reference's steps of 7.8e-5 s is about 1e-10).
fn run(dt: f64, duration: f64, a0: f64, limit: f64, max_substeps: usize) -> Run {
    let mut bar = DamageBar::new();
    let mut st = State::new(&mut bar, vec![0.0], vec![0.0], vec![0.0]).unwrap();
    let mut stepper = Stepper::new(StepSettings {
        scheme: Scheme::default(),
        newton: NewtonKind::Tangent,
        integration: crate::config::IntegrationKind::Implicit,
        krylov_dimension: 3,
        refresh_cost: 0,
        max_iterations: 200,
        tolerance: 1e-9,
        max_substeps,
        max_damage_increment: limit,
        line_search: false,
        implex_corrections: 0,
        implex_tolerance: 0.0,
        implex_pass_tolerance: 0.0,
    });
    let ag = ground(a0);
    let times = RefCell::new(Vec::new());
    let g = |t: f64| {
        times.borrow_mut().push(t);
        [ag(t), 0.0, 0.0]
    };
    let steps = (duration / dt).round() as usize;
    let (mut d_t, mut reports) = (Vec::new(), Vec::new());
    for k in 1..=steps {
        let target = k as f64 * dt;
        reports.push(stepper.advance(&mut bar, &g, &mut st, target, dt).unwrap());
        assert_eq!(st.t, target, "step {k} ends on the nominal grid exactly");
        d_t.push(bar.committed.d_t);
    }
    Run { d_t, reports, bar, times: times.into_inner(), last: st }
}

#[test]
fn a_step_with_a_large_damage_jump_is_cut() {
    // Without the control, a step of 0.02 s commits a damage increment above 0.3 (the first
    // opening of the crack). With the limit 0.1 and 12 halvings allowed, no committed substep
    // takes more than 0.1 (none had to be accepted at the smallest size), steps were cut, and the
    // cuts are counted apart from Newton's failures (none here: the secant Newton converges at
    // any size).
    let off = run(0.02, 1.0, 1.0, 1.0, 12);
    let jump = off.bar.commits.iter().fold(0.0f64, |m, &x| m.max(x));
    assert!(jump > 0.3, "the uncontrolled run's largest increment {jump}");
    assert!(off.reports.iter().all(|r| r.damage_cuts == 0 && r.substeps == 1));
    let on = run(0.02, 1.0, 1.0, 0.1, 12);
    let cuts: usize = on.reports.iter().map(|r| r.damage_cuts).sum();
    let over: usize = on.reports.iter().map(|r| r.over_limit).sum();
    let largest = on.bar.commits.iter().fold(0.0f64, |m, &x| m.max(x));
    assert!(cuts > 0 && over == 0, "cuts {cuts}, over the limit {over}");
    assert!(largest <= 0.1, "a committed increment of {largest}");
    assert!(on.reports.iter().all(|r| r.failed_iterations == 0));
    let reported = on.reports.iter().fold(0.0f64, |m, r| m.max(r.damage_increment));
    assert_eq!(reported, largest, "the reports carry the largest committed increment");
}

#[test]
fn at_the_smallest_substep_an_increment_over_the_limit_is_accepted_and_counted() {
    // One halving allowed and a limit of 0.02: the first opening (more than 0.3 in 0.02 s, so
    // more than 0.02 in 0.01 s) cannot be brought under the limit; its substeps are accepted at
    // 0.01 s and counted, one for each committed increment over the limit.
    let r = run(0.02, 1.0, 1.0, 0.02, 1);
    let over: usize = r.reports.iter().map(|r| r.over_limit).sum();
    let committed_over = r.bar.commits.iter().filter(|&&x| x > 0.02).count();
    assert!(over > 0);
    assert_eq!(over, committed_over);
    assert!(r.reports.iter().all(|r| r.smallest_substep == 0.02 || r.smallest_substep == 0.01));
}

#[test]
fn substeps_are_dt_over_powers_of_two_on_the_steps_grid_and_grow_back() {
    // Every time the stepper evaluates the ground at lies on the grid of the finest substep
    // dt/2^12 (to 1e-6 of it: the times are sums of exact sizes); every smallest substep is
    // dt/2^k exactly; and once the shaking stops (t ≥ 0.6 s) and the damage with it, the
    // substeps double back to dt: the last steps are whole and the next step would start at dt.
    let dt = 0.02;
    let r = run(dt, 1.0, 1.0, 0.1, 12);
    let h_min = dt / 4096.0;
    for t in &r.times {
        let k = t / h_min;
        assert!((k - k.round()).abs() < 1e-6, "t = {t} is off the grid of dt/2^12");
    }
    for rep in &r.reports {
        let k = (dt / rep.smallest_substep).log2().round() as i32;
        assert_eq!(rep.smallest_substep, dt / f64::powi(2.0, k));
    }
    assert!(r.reports.iter().any(|rep| rep.substeps > 1));
    // The last 0.2 s: no damage, whole steps.
    assert!(r.reports[40..].iter().all(|rep| rep.substeps == 1 && rep.damage_increment == 0.0));
    assert_eq!(r.last.substep_level, 0);
}

#[test]
fn with_the_control_the_damage_history_converges_as_dt_shrinks() {
    // Reference: a fixed step of 0.02/256 = 7.8e-5 s without the control, under a₀ = 0.05 m/s²
    // (d_t climbs to 0.994 over the pulse: the whole softening branch). Runs with dt = 0.02,
    // 0.01, 0.005 s and the limit 0.1, compared with it at the times of the coarsest step over
    // the record (1 s). Measured (this test's printout): the largest |Δd_t| is 2.1e-1, 4.5e-2,
    // 1.1e-2, second order (×4 per halving); the final d_t is off by 6.1e-3, 1.2e-3, 2.6e-4.
    // Asserted: at least ×2 per halving, below 2e-2 at 0.005 s, the final d_t within 1e-3.
    //
    // Not asserted, and worth knowing: on this single point the control does not reduce the
    // error at the nominal times (2.10e-1 with it and without at 0.02 s, 4.5e-2 and 4.4e-2 at
    // 0.01 s). A point's damage is a function of its largest strain, which the implicit update
    // takes exactly; what is left is the error of the displacement (the phase of the response),
    // which substeps in the damaging phase alone do not remove. The control's target is the
    // path within a step where points share a load (one softens while another unloads), which a
    // single point does not have.
    let (a0, fine) = (0.05, 0.02 / 256.0);
    let reference = run(fine, 1.0, a0, 1.0, 0);
    let d_ref = sampled(&reference.d_t, fine, 0.02);
    let mut errors = Vec::new();
    for dt in [0.02, 0.01, 0.005] {
        let on = run(dt, 1.0, a0, 0.1, 12);
        let off = run(dt, 1.0, a0, 1.0, 12);
        let e = |r: &Run| largest_difference(&sampled(&r.d_t, dt, 0.02), &d_ref);
        let cuts: usize = on.reports.iter().map(|r| r.damage_cuts).sum();
        let end = (on.d_t.last().unwrap() - d_ref.last().unwrap()).abs();
        eprintln!(
            "dt {dt}: largest |Δd_t| {:.3e} with the control ({cuts} cuts), {:.3e} without; final |Δd_t| {end:.3e}",
            e(&on),
            e(&off)
        );
        errors.push((e(&on), end));
    }
    assert!(errors[0].0 > 2.0 * errors[1].0 && errors[1].0 > 2.0 * errors[2].0, "{errors:?}");
    assert!(errors[2].0 < 2e-2 && errors[2].1 < 1e-3, "{errors:?}");
}
