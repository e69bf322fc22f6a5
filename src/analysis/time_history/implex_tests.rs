//! IMPL-EX steps (`stepper.rs`, "IMPL-EX") on the single-DOF bar of `bar_tests.rs` with the
//! masonry damage law, its point kept by the elements' own store ([`PointStates`]:
//! extrapolation, commits).
//!
//! The bar cracks in tension and closes in compression, and
//! under a₀ = 0.05 m/s² its d_t climbs the whole softening branch over the pulse.
use super::bar_tests::{largest_difference, linear_part, linear_part_methods, sampled, wall_law, AREA, LENGTH};
use super::scheme::Scheme;
use super::stepper::{State, StepReport, StepSettings, Stepper};
use super::system::{DenseSystem, DynamicSystem};
use crate::config::{IntegrationKind, NewtonKind};
use crate::element::PointStates;
use crate::material::implex::SplitAt;
use crate::material::{PointLaw, Response, StressState, Uniaxial};
use nalgebra::Vector1;
use std::f64::consts::PI;

/// The bar (module docs): mass, damping and influence from a [`DenseSystem`], the force from the
/// law through a [`PointStates`] of one point; the Jacobian with the point's tangent at the
/// trial (the implicit law's consistent tangent, or IMPL-EX's at the extrapolated damage).
struct Bar {
    lin: DenseSystem,
    law: PointLaw,
    states: PointStates,
    j: f64,
    factorizations: usize,
}

impl Bar {
    fn new(implex: Option<SplitAt>) -> Bar {
        let law = wall_law();
        let lin = linear_part(&law);
        let mut states = PointStates::new(1, 1);
        states.set_implex(implex);
        Bar { lin, law, states, j: 0.0, factorizations: 0 }
    }

    /// The point's response at `u` (its trial state written).
    fn respond(&mut self, u: f64) -> Response<1> {
        let strain = Vector1::new(u / LENGTH);
        let law = self.law;
        let r = self.states.for_update().respond(&law, 0, &strain, Uniaxial::evaluate);
        self.states.set_trial_dissipation(AREA * LENGTH * r.dissipation);
        r
    }
}

impl DynamicSystem for Bar {
    linear_part_methods!();
    fn internal_force(&mut self, u: &[f64], f: &mut [f64]) -> Result<(), crate::error::Error> {
        f[0] = AREA * self.respond(u[0]).stress[0];
        Ok(())
    }
    fn prepare(&mut self, tangent_at: Option<&[f64]>, c_m: f64, c_c: f64) -> Result<(), crate::error::Error> {
        let k = match tangent_at {
            Some(u) => self.respond(u[0]).tangent[(0, 0)],
            None => self.law.e(),
        };
        self.j = k * AREA / LENGTH + c_m * self.lin.m[(0, 0)] + c_c * self.lin.c[(0, 0)];
        self.factorizations += 1;
        Ok(())
    }
    fn solve(&mut self, r: &[f64], x: &mut [f64]) -> Result<(), crate::error::Error> {
        x[0] = r[0] / self.j;
        Ok(())
    }
    fn dissipated_energy(&self) -> f64 {
        self.states.dissipated()
    }
    fn max_damage_increment(&self) -> f64 {
        self.states.damage_increment()
    }
    fn set_implex_step(&mut self, h: f64) {
        let law = self.law;
        self.states.set_implex_step(&law, h);
    }
    fn update_histories(&mut self) {
        let law = self.law;
        self.states.settle(|_, e, c| {
            let r = Uniaxial::evaluate(&law, &Vector1::new(e[0]), c);
            (r.state, AREA * LENGTH * r.dissipation)
        });
    }
    fn hold_histories(&mut self) -> f64 {
        self.states.hold_trial()
    }
    fn commit(&mut self) {
        self.update_histories();
        self.states.commit();
    }
    fn revert(&mut self) {
        self.states.revert();
    }
}

/// What a run gives: u and d_t after each step, the reports, the final state.
struct Run {
    u: Vec<f64>,
    d_t: Vec<f64>,
    reports: Vec<StepReport>,
    last: State,
}

/// One second of the pulse (module docs) with amplitude `a0` in steps of `dt`: IMPL-EX with the
/// split where `implex` says, or the implicit law (`None`), with `newton`; force tolerance 1e-10
/// (relative), 40 iterations, 10 halvings.
fn run(dt: f64, a0: f64, implex: Option<SplitAt>, newton: NewtonKind) -> Run {
    run_corrected(dt, a0, implex, newton, 0, 0.0)
}

/// [`run_passes`] with every pass solved to the force tolerance.
fn run_corrected(
    dt: f64,
    a0: f64,
    implex: Option<SplitAt>,
    newton: NewtonKind,
    corrections: usize,
    tolerance: f64,
) -> Run {
    run_passes(dt, a0, implex, newton, (corrections, tolerance), 0.0)
}

/// [`run`] with `corrections` IMPL-EX corrections ended by a change of held damage of at most
/// `tolerance`, the passes before the last solved to the force tolerance `pass_tolerance`
/// (`stepper.rs`, "IMPL-EX corrections").
fn run_passes(
    dt: f64,
    a0: f64,
    implex: Option<SplitAt>,
    newton: NewtonKind,
    (corrections, tolerance): (usize, f64),
    pass_tolerance: f64,
) -> Run {
    let integration = if implex.is_some() { IntegrationKind::Implex } else { IntegrationKind::Implicit };
    let mut bar = Bar::new(implex);
    let mut st = State::new(&mut bar, vec![0.0], vec![0.0], vec![0.0]).unwrap();
    let mut stepper = Stepper::new(StepSettings {
        scheme: Scheme::default(),
        newton,
        integration,
        krylov_dimension: 3,
        refresh_cost: 0,
        max_iterations: 40,
        tolerance: 1e-10,
        max_substeps: 10,
        max_damage_increment: 1.0,
        line_search: false,
        implex_corrections: corrections,
        implex_tolerance: tolerance,
        implex_pass_tolerance: pass_tolerance,
    });
    let g = |t: f64| [if t < 0.6 { a0 * (2.0 * PI * 4.0 * t).sin() } else { 0.0 }, 0.0, 0.0];
    let (mut u, mut d_t, mut reports) = (Vec::new(), Vec::new(), Vec::new());
    for k in 1..=(1.0 / dt).round() as usize {
        reports.push(stepper.advance(&mut bar, &g, &mut st, k as f64 * dt, dt).unwrap());
        u.push(st.u[0]);
        d_t.push(bar.states.committed()[0].d_t);
    }
    Run { u, d_t, reports, last: st }
}

fn peak(v: &[f64]) -> f64 {
    v.iter().fold(0.0f64, |m, x| m.max(x.abs()))
}

#[test]
fn implex_converges_to_the_implicit_history_as_dt_shrinks() {
    // Reference: the implicit law with steps of 0.02/256 s (full Newton, 1e-10). IMPL-EX with
    // dt = 0.02, 0.01, 0.005, 0.0025 s (modified Newton; the split frozen, then at the step's
    // strain), compared at the times of the coarsest step over the second of the record.
    // Measured (this test's printout), frozen:
    //   largest |Δu| / peak u   8.0e-1, 3.5e-1, 1.2e-1, 2.6e-2   (orders 1.2, 1.6, 2.2)
    //   largest |Δd_t|          2.1e-1, 4.9e-2, 1.2e-2, 3.2e-3   (order 2)
    //   the implicit law at the same dt: |Δu|/peak 2.4e-1, 2.4e-2, 2.2e-2, 1.2e-2
    //   iterations per step     1 (implicit, full Newton: 1.36 at 0.02 s to 1.19 at 0.0025 s)
    //   unilateral energy U     5.2e-2, 2.8e-2, 7.1e-3, 1.9e-3 J against D = 0.14 to 0.21 J
    // Asserted for both: each halving divides the u error by more than 2 and the d_t error by
    // more than 3; at 0.0025 s within 5 % of the peak and 5e-3; none failed; U falls by more
    // than 1.5 per halving; the balance closes to 1e-9. Frozen: one iteration per step (two at
    // most: the first step's split is not frozen).
    let a0 = 0.05;
    let fine = 0.02 / 256.0;
    let reference = run(fine, a0, None, NewtonKind::Tangent);
    let (u_ref, d_ref) = (sampled(&reference.u, fine, 0.02), sampled(&reference.d_t, fine, 0.02));
    let scale = peak(&u_ref);
    for split in [SplitAt::Frozen, SplitAt::Current] {
        let mut errors = Vec::new();
        for dt in [0.02, 0.01, 0.005, 0.0025] {
            let ex = run(dt, a0, Some(split), NewtonKind::Modified);
            let im = run(dt, a0, None, NewtonKind::Tangent);
            let eu = |r: &Run| largest_difference(&sampled(&r.u, dt, 0.02), &u_ref) / scale;
            let ed = |r: &Run| largest_difference(&sampled(&r.d_t, dt, 0.02), &d_ref);
            let its = |r: &Run| r.reports.iter().map(|x| x.iterations).sum::<usize>() as f64 / r.reports.len() as f64;
            let failed: usize = ex.reports.iter().map(|x| x.failed_iterations).sum();
            let e = &ex.last.energy;
            eprintln!(
                "{split:?} dt {dt}: IMPL-EX |Δu|/peak {:.3e}, |Δd_t| {:.3e}, {:.2} it/step, {failed} failed; implicit \
                 |Δu|/peak {:.3e}, |Δd_t| {:.3e}, {:.2} it/step; IMPL-EX energy: D {:.4e} J, U {:.3e} J, balance {:.1e}",
                eu(&ex),
                ed(&ex),
                its(&ex),
                eu(&im),
                ed(&im),
                its(&im),
                e.dissipated(),
                e.unilateral(),
                e.relative_error()
            );
            let most = ex.reports.iter().map(|x| x.iterations).max().unwrap();
            assert!(failed == 0, "{split:?} dt {dt}");
            if split == SplitAt::Frozen {
                assert!(its(&ex) <= 1.01 && most <= 2, "dt {dt}: {} iterations per step, at most {most}", its(&ex));
            }
            assert!(e.relative_error() < 1e-9, "{split:?} dt {dt}: {:?}", e);
            errors.push((eu(&ex), ed(&ex), e.unilateral().abs()));
        }
        let order: Vec<f64> = errors.windows(2).map(|w| (w[0].0 / w[1].0).log2()).collect();
        eprintln!("{split:?}: observed orders of the displacement error: {order:?}");
        for w in errors.windows(2) {
            assert!(w[0].0 > 2.0 * w[1].0 && w[0].1 > 3.0 * w[1].1 && w[0].2 > 1.5 * w[1].2, "{split:?} {errors:?}");
        }
        assert!(errors[3].0 < 5e-2 && errors[3].1 < 5e-3, "{split:?} {errors:?}");
    }
}

#[test]
fn an_implex_step_is_one_linear_solve_with_the_split_frozen() {
    // dt = 0.02 s under a₀ = 0.05 and 1 m/s² (the bar breaks in the first cycle): with the split
    // frozen at the committed strain an IMPL-EX step is linear, so one iteration ends every
    // step after the first (whose split is not frozen: two at most) with the step's first
    // tangent (modified) as with a fresh one at every iteration (tangent). With the split at the
    // step's strain, full Newton needs two where the crack opens or closes (the stiffness jumps
    // between (1 − d̃_t) E and E). The implicit law needs more in all than either (modified);
    // no IMPL-EX attempt fails and no step is substepped.
    for a0 in [0.05, 1.0] {
        let total = |r: &Run| r.reports.iter().map(|x| x.iterations).sum::<usize>();
        let implicit = run(0.02, a0, None, NewtonKind::Modified);
        let cases = [
            (SplitAt::Frozen, NewtonKind::Modified),
            (SplitAt::Frozen, NewtonKind::Tangent),
            (SplitAt::Current, NewtonKind::Tangent),
            (SplitAt::Current, NewtonKind::Modified),
        ];
        for (split, newton) in cases {
            let r = run(0.02, a0, Some(split), newton);
            let most = r.reports[1..].iter().map(|x| x.iterations).max().unwrap();
            eprintln!(
                "a0 {a0}: IMPL-EX {split:?} {newton:?} {} iterations (at most {most} a step); implicit modified {}",
                total(&r),
                total(&implicit)
            );
            assert!(r.reports[0].iterations <= 2, "a0 {a0} {split:?} {newton:?}");
            match (split, newton) {
                (SplitAt::Frozen, _) => assert_eq!(most, 1, "a0 {a0} {newton:?}"),
                (SplitAt::Current, NewtonKind::Tangent) => assert!(most <= 2, "a0 {a0}"),
                _ => {}
            }
            assert!(r.reports.iter().all(|x| x.failed_iterations == 0 && x.substeps == 1), "a0 {a0}");
            assert!(total(&r) < total(&implicit), "a0 {a0} {split:?} {newton:?}");
        }
    }
}

#[test]
fn implex_corrections_converge_to_the_implicit_step() {
    // A fixed point of the corrections is the implicit step's solution (`stepper.rs`, "IMPL-EX
    // corrections"): at dt = 0.02 and 0.01 s, under a₀ = 0.05 (d_t climbs the whole softening
    // branch), IMPL-EX (split at the step's strain, full Newton, 1e-10) with K = 0, 1, 2, 4, 8
    // corrections against the implicit law at the same dt (full Newton, 1e-10), over the
    // second of the record. Measured (this test's printout), largest |Δu| / peak u and |Δd_t|:
    //   dt 0.02:  K 0  7.7e-1, 5.1e-2   K 1  8.0e-2, 2.3e-3   K 2  4.4e-3, 1.2e-4
    //             K 4  1.6e-5, 6.0e-7   K 8  2.6e-9, 1.1e-10  (54 → 93 iterations in all)
    //   dt 0.01:  K 0  3.7e-1, 1.7e-2   K 1  1.0e-2, 3.6e-4   K 2  2.2e-4, 8.4e-6
    //             K 4  1.3e-7, 5.2e-9   K 8  4.7e-9, 7.7e-11  (102 → 165)
    // each correction dividing the difference by 10 to 40: the staggered iteration contracts.
    // Asserted: the u and d_t differences from the implicit run fall with K and are at K = 8
    // under a tenth of K = 0's; none failed; the balance closes to 1e-9.
    let a0 = 0.05;
    for dt in [0.02, 0.01] {
        let implicit = run(dt, a0, None, NewtonKind::Tangent);
        let scale = peak(&implicit.u);
        let mut differences = Vec::new();
        for k in [0, 1, 2, 4, 8] {
            let r = run_corrected(dt, a0, Some(SplitAt::Current), NewtonKind::Tangent, k, 0.0);
            let du = largest_difference(&r.u, &implicit.u) / scale;
            let dd = largest_difference(&r.d_t, &implicit.d_t);
            let its = r.reports.iter().map(|x| x.iterations).sum::<usize>();
            let failed: usize = r.reports.iter().map(|x| x.failed_iterations).sum();
            let e = &r.last.energy;
            eprintln!(
                "dt {dt}, K {k}: |Δu|/peak {du:.3e}, |Δd_t| {dd:.3e}, {its} iterations, {failed} failed; \
                 U {:.3e} J, D {:.4e} J, balance {:.1e}",
                e.unilateral(),
                e.dissipated(),
                e.relative_error()
            );
            assert!(failed == 0, "dt {dt} K {k}");
            assert!(e.relative_error() < 1e-9, "dt {dt} K {k}: {e:?}");
            differences.push((du, dd));
        }
        for w in differences.windows(2) {
            assert!(w[1].0 <= w[0].0 && w[1].1 <= w[0].1, "dt {dt}: {differences:?}");
        }
        let (first, last) = (differences[0], differences[differences.len() - 1]);
        assert!(last.0 < 0.1 * first.0 && last.1 < 0.1 * first.1, "dt {dt}: {differences:?}");
    }
}

#[test]
fn implex_corrections_end_where_the_held_damage_settles() {
    // `implex_correction_tolerance` (`stepper.rs`, "IMPL-EX corrections"): K = 8 passes at most,
    // each ending the corrections once no point's held damage changes by more than τ, on the
    // bar and pulse of `implex_corrections_converge_to_the_implicit_step` (dt 0.02 s, a₀ = 0.05).
    // Since each pass divides the difference from the implicit step by 10 or more there, the
    // damage left after the last pass is below τ. Measured (this test's printout), largest
    // |Δu| / peak u, |Δd_t|, passes, iterations:
    //   τ 0     2.6e-9, 1.1e-10, 48, 93     τ 1e-4  1.8e-4, 8.0e-6, 13, 65
    //   τ 1e-3  1.1e-3, 4.3e-5,  10, 62     τ 1e-2  2.1e-2, 3.7e-4,  3, 55   (K = 0: 7.7e-1, 5.1e-2, 54)
    // Asserted: |Δd_t| from the implicit run ≤ τ;
    // fewer passes as τ grows (τ = 0: every pass that changes anything); the balance closes.
    let (dt, a0) = (0.02, 0.05);
    let implicit = run(dt, a0, None, NewtonKind::Tangent);
    let scale = peak(&implicit.u);
    let mut passes = Vec::new();
    for tol in [0.0, 1e-4, 1e-3, 1e-2] {
        let r = run_corrected(dt, a0, Some(SplitAt::Current), NewtonKind::Tangent, 8, tol);
        let du = largest_difference(&r.u, &implicit.u) / scale;
        let dd = largest_difference(&r.d_t, &implicit.d_t);
        let n: usize = r.reports.iter().map(|x| x.implex_passes).sum();
        let its: usize = r.reports.iter().map(|x| x.iterations).sum();
        eprintln!("τ {tol:.0e}: |Δu|/peak {du:.3e}, |Δd_t| {dd:.3e}, {n} passes, {its} iterations");
        assert!(dd <= tol.max(1e-9), "τ {tol}: |Δd_t| {dd:.3e}");
        assert!(r.last.energy.relative_error() < 1e-9, "τ {tol}");
        passes.push(n);
    }
    assert!(passes.windows(2).all(|w| w[1] <= w[0]) && passes[3] < passes[0], "{passes:?}");
}

#[test]
fn loose_passes_end_on_an_equilibrium_as_tight_as_the_step_asks() {
    // `implex_pass_tolerance` (`stepper.rs`, "IMPL-EX corrections"): the passes before the last
    // stop at a looser force tolerance, the last is solved to the step's (1e-10 here). On the bar
    // and pulse of `implex_corrections_end_where_the_held_damage_settles`, modified Newton (its
    // linear convergence is what a loose pass saves), K = 8, τ = 1e-3:
    // * a pass tolerance equal to the force tolerance is the tight run, bit for bit;
    // * with 1e-4 every accepted step's residual is within 1e-10, the damage within τ of the
    //   implicit run's (as the tight run's: the passes still end where the damage settles), in
    //   fewer iterations. Measured (this test's printout): tight |Δd_t| 4.3e-5, |Δu|/peak
    //   1.1e-3, 105 iterations; loose 1.4e-5, 1.5e-3, 98.
    let (dt, a0, k, tau) = (0.02, 0.05, 8, 1e-3);
    let implicit = run(dt, a0, None, NewtonKind::Tangent);
    let tight = run_passes(dt, a0, Some(SplitAt::Current), NewtonKind::Modified, (k, tau), 0.0);
    let same = run_passes(dt, a0, Some(SplitAt::Current), NewtonKind::Modified, (k, tau), 1e-10);
    assert_eq!((&tight.u, &tight.d_t), (&same.u, &same.d_t));
    let loose = run_passes(dt, a0, Some(SplitAt::Current), NewtonKind::Modified, (k, tau), 1e-4);
    let its = |r: &Run| r.reports.iter().map(|x| x.iterations).sum::<usize>();
    let scale = peak(&implicit.u);
    for (name, r) in [("tight", &tight), ("loose", &loose)] {
        let dd = largest_difference(&r.d_t, &implicit.d_t);
        let du = largest_difference(&r.u, &implicit.u) / scale;
        eprintln!("{name}: |Δd_t| {dd:.3e}, |Δu|/peak {du:.3e}, {} iterations", its(r));
        assert!(dd <= tau, "{name}: |Δd_t| {dd:.3e}");
        assert!(r.reports.iter().all(|x| x.residual <= 1e-10), "{name}: a step accepted above the tolerance");
        assert!(r.last.energy.relative_error() < 1e-9, "{name}");
    }
    assert!(its(&loose) < its(&tight), "{} against {}", its(&loose), its(&tight));
}
