//! The integrator on dense SDOF and 2-DOF systems against closed forms.
use super::bar_tests::linear_part_methods;
use super::scheme::Scheme;
use super::stepper::{State, StepSettings, Stepper};
use super::system::{DenseSystem, DynamicSystem};
use crate::config::NewtonKind;
use nalgebra::DMatrix;
use std::f64::consts::PI;

fn settings(scheme: Scheme) -> StepSettings {
    StepSettings {
        scheme,
        newton: NewtonKind::Modified,
        integration: crate::config::IntegrationKind::Implicit,
        krylov_dimension: 3,
        refresh_cost: 0,
        max_iterations: 10,
        tolerance: 1e-12,
        max_substeps: 3,
        max_damage_increment: 1.0,
        line_search: false,
        implex_corrections: 0,
        implex_tolerance: 0.0,
        implex_pass_tolerance: 0.0,
    }
}

fn sdof(m: f64, c: f64, k: f64) -> DenseSystem {
    let one = |x: f64| DMatrix::from_element(1, 1, x);
    DenseSystem::new(one(m), one(c), one(k), vec![vec![1.0]])
}

/// Runs `steps` steps of `dt` from (u0, v0) with ground acceleration `ag` along x; returns the
/// states after each step (the initial one first).
fn run(
    sys: &mut DenseSystem,
    scheme: Scheme,
    u0: Vec<f64>,
    v0: Vec<f64>,
    ag: &dyn Fn(f64) -> f64,
    dt: f64,
    steps: usize,
) -> Vec<State> {
    let n = sys.len();
    // a₀ from the equation of motion: M a₀ = f(0) − C v₀ − K u₀.
    let f0: Vec<f64> = sys.mass_influence(0).iter().map(|m| -m * ag(0.0)).collect();
    let rhs = nalgebra::DVector::from_vec(f0)
        - &sys.c * nalgebra::DVector::from_vec(v0.clone())
        - &sys.k * nalgebra::DVector::from_vec(u0.clone());
    let a0 = sys.m.clone().lu().solve(&rhs).unwrap();
    let mut st = State::new(sys, u0, v0, a0.as_slice().to_vec()).unwrap();
    assert_eq!(st.u.len(), n);
    let mut out = vec![st.clone()];
    let mut stepper = Stepper::new(settings(scheme));
    let g = |t: f64| [ag(t), 0.0, 0.0];
    for k in 1..=steps {
        stepper.advance(sys, &g, &mut st, k as f64 * dt, dt).unwrap();
        out.push(st.clone());
    }
    out
}

#[test]
fn sdof_damped_free_vibration_matches_the_closed_form() {
    // u(t) = e^{−ζωt} [u₀ cos ω_d t + (v₀ + ζ ω u₀)/ω_d sin ω_d t] (Chopra, §2.2).
    // Average acceleration with Ω = ω h = 0.02: phase error ≈ Ω²/12 per radian (Chopra §5.5),
    // 3.3e-5 × ω t ≈ 4e-4 rad after two periods: tolerance 1e-3 of the initial amplitude.
    let (m, k, zeta) = (2.0f64, 800.0f64, 0.05);
    let w = (k / m).sqrt();
    let c = 2.0 * zeta * m * w;
    let mut sys = sdof(m, c, k);
    let dt = 0.02 / w;
    let steps = (2.0 * 2.0 * PI / w / dt) as usize;
    let (u0, v0) = (0.01, 0.3);
    let out = run(&mut sys, Scheme::default(), vec![u0], vec![v0], &|_| 0.0, dt, steps);
    let wd = w * (1.0 - zeta * zeta).sqrt();
    let amp = (u0 * u0 + ((v0 + zeta * w * u0) / wd).powi(2)).sqrt();
    for s in &out {
        let t = s.t;
        let exact = (-zeta * w * t).exp() * (u0 * (wd * t).cos() + (v0 + zeta * w * u0) / wd * (wd * t).sin());
        assert!((s.u[0] - exact).abs() < 1e-3 * amp, "t = {t}: {} vs {exact}", s.u[0]);
    }
}

#[test]
fn average_acceleration_period_elongation_matches_its_formula() {
    // Trapezoidal rule: the discrete free vibration is exactly a sampled sinusoid of angular step
    // θ = 2 arctan(Ω/2), so T̄/T = Ω/(2 arctan(Ω/2)) (Hughes, *The FEM*, §9.1.3; Chopra Table 5.3.1
    // gives the same curve). θ is measured from the three-term recurrence u_{n+1} + u_{n−1} =
    // 2 cos θ u_n by least squares over 400 steps: exact up to round-off, tolerance 1e-9.
    for omega_h in [0.1, 0.5, 1.0, 2.0] {
        let (m, k) = (1.0, 4.0 * PI * PI);
        let w = 2.0 * PI;
        let dt = omega_h / w;
        let mut sys = sdof(m, 0.0, k);
        let out = run(&mut sys, Scheme::default(), vec![1.0], vec![0.0], &|_| 0.0, dt, 400);
        let u: Vec<f64> = out.iter().map(|s| s.u[0]).collect();
        let (mut num, mut den) = (0.0, 0.0);
        for n in 1..u.len() - 1 {
            num += u[n] * (u[n + 1] + u[n - 1]);
            den += 2.0 * u[n] * u[n];
        }
        let theta = (num / den).acos();
        let measured = omega_h / theta;
        let formula = omega_h / (2.0 * (omega_h / 2.0).atan());
        assert!((measured - formula).abs() < 1e-9, "Ω = {omega_h}: T̄/T = {measured} vs {formula}");
        // Sanity: at Ω = 0.1 the elongation is about Ω²/12 = 0.083 %.
        if omega_h == 0.1 {
            assert!((measured - 1.0 - omega_h * omega_h / 12.0).abs() < 1e-5);
        }
    }
}

#[test]
fn sdof_steady_state_under_harmonic_base_excitation() {
    // a_g = a₀ sin(ϖ t): steady relative amplitude u₀ = (a₀/ω²) / sqrt((1 − r²)² + (2ζr)²),
    // r = ϖ/ω (Chopra, §3.2 with p₀ = −m a₀). After 12 s (e^{−ζωt} = 3e-7 of the transient) the
    // peak over the last two forcing periods matches within 0.3 % (h = T/400: phase error 2e-5,
    // peak sampling error ≤ 1 − cos(π/400·…) ≈ 3e-5).
    let (m, zeta, f) = (1.0, 0.2, 1.0);
    let w = 2.0 * PI * f;
    let k = m * w * w;
    let mut sys = sdof(m, 2.0 * zeta * m * w, k);
    let (a0, wf) = (2.0, 0.7 * w);
    let dt = 1.0 / (400.0 * f);
    let steps = (12.0 / dt) as usize;
    let out = run(&mut sys, Scheme::default(), vec![0.0], vec![0.0], &|t| a0 * (wf * t).sin(), dt, steps);
    let r = wf / w;
    let expect = a0 / (w * w) / ((1.0 - r * r).powi(2) + (2.0 * zeta * r).powi(2)).sqrt();
    let t_last = out.last().unwrap().t;
    let peak = out.iter().filter(|s| s.t > t_last - 2.0 * 2.0 * PI / wf).map(|s| s.u[0].abs()).fold(0.0, f64::max);
    assert!((peak - expect).abs() < 3e-3 * expect, "steady amplitude {peak} vs {expect}");
}

/// Two-storey shear building: masses m₁ = 2m, m₂ = m, stiffnesses k₁ = 2k (ground), k₂ = k.
fn two_dof(c_alpha: f64, c_beta: f64) -> DenseSystem {
    let (m, k) = (1.0, 100.0);
    let mm = DMatrix::from_row_slice(2, 2, &[2.0 * m, 0.0, 0.0, m]);
    let kk = DMatrix::from_row_slice(2, 2, &[3.0 * k, -k, -k, k]);
    let cc = &mm * c_alpha + &kk * c_beta;
    DenseSystem::new(mm, cc, kk, vec![vec![1.0, 1.0]])
}

#[test]
fn two_dof_free_vibration_in_its_first_mode() {
    // For M = m diag(2, 1), K = k [[3, −1], [−1, 1]]: ω² = k/m · {1/2, 2}, φ₁ = (1/2, 1),
    // φ₂ = (−1, 1) (Chopra, Example 10.4 pattern; check: K φ₁ = ω₁² M φ₁). Released from φ₁ at
    // rest the motion is φ₁ cos ω₁ t; the second mode stays unexcited to round-off. h = T₁/600:
    // phase error (ω₁ h)²/12 · ω₁ t ≈ 1.1e-4 · 2 periods... tolerance 2e-4 of the amplitude.
    let mut sys = two_dof(0.0, 0.0);
    let w1 = (100.0f64 / 2.0).sqrt();
    let dt = 2.0 * PI / w1 / 600.0;
    let out = run(&mut sys, Scheme::default(), vec![0.5, 1.0], vec![0.0, 0.0], &|_| 0.0, dt, 1200);
    for s in &out {
        let c = (w1 * s.t).cos();
        assert!((s.u[0] - 0.5 * c).abs() < 2e-4 && (s.u[1] - c).abs() < 2e-4, "t = {}: {:?}", s.t, s.u);
        // The second-mode coordinate φ₂ᵀ M u = −2 u₁ + u₂ stays zero.
        assert!((-2.0 * s.u[0] + s.u[1]).abs() < 1e-12);
    }
}

#[test]
fn two_dof_steady_state_under_harmonic_base_excitation() {
    // Steady state of M ü + C u̇ + K u = −M ι a₀ sin ϖt: u = Im(U e^{iϖt}) with
    // (K − ϖ² M + i ϖ C) U = −M ι a₀ (the complex frequency response; Chopra §12.?). Rayleigh
    // C = 0.5 M + 0.002 K. Transient decays as e^{−ζ₁ ω₁ t}, ζ₁ ≈ 0.042: after 60 s, 4e-6.
    // Peaks over the last two periods within 0.3 % (h = 2π/ϖ / 400).
    let (ca, cb) = (0.5, 0.002);
    let mut sys = two_dof(ca, cb);
    let (a0, wf) = (1.0, 5.0);
    let dt = 2.0 * PI / wf / 400.0;
    let steps = (60.0 / dt) as usize;
    let out = run(&mut sys, Scheme::default(), vec![0.0, 0.0], vec![0.0, 0.0], &|t| a0 * (wf * t).sin(), dt, steps);
    // Solve the 2×2 complex system by hand: A = K − ϖ² M (real), B = ϖ C (imag part).
    let (m, k) = (two_dof(0.0, 0.0).m, two_dof(0.0, 0.0).k);
    let c = &m * ca + &k * cb;
    let a = &k - &m * (wf * wf);
    let b = &c * wf;
    // [A −B; B A] [Re U; Im U] = [−M ι a₀; 0]
    let mut big = DMatrix::zeros(4, 4);
    big.view_mut((0, 0), (2, 2)).copy_from(&a);
    big.view_mut((0, 2), (2, 2)).copy_from(&(-&b));
    big.view_mut((2, 0), (2, 2)).copy_from(&b);
    big.view_mut((2, 2), (2, 2)).copy_from(&a);
    let rhs = nalgebra::DVector::from_vec(vec![-m[(0, 0)] * a0, -m[(1, 1)] * a0, 0.0, 0.0]);
    let x = big.lu().solve(&rhs).unwrap();
    let amp = [(x[0] * x[0] + x[2] * x[2]).sqrt(), (x[1] * x[1] + x[3] * x[3]).sqrt()];
    let t_last = out.last().unwrap().t;
    for d in 0..2 {
        let peak = out.iter().filter(|s| s.t > t_last - 2.0 * 2.0 * PI / wf).map(|s| s.u[d].abs()).fold(0.0, f64::max);
        assert!((peak - amp[d]).abs() < 3e-3 * amp[d], "DOF {d}: {peak} vs {}", amp[d]);
    }
}

#[test]
fn undamped_linear_runs_conserve_energy() {
    // Average acceleration conserves E_k + E_s exactly in free vibration, and the trapezoidal
    // balance W_in = E_k + W_damp + W_int holds exactly under any loading (see `energy.rs`):
    // tolerance 1e-10 relative (round-off of 2000 steps).
    let mut sys = two_dof(0.0, 0.0);
    let out = run(&mut sys, Scheme::default(), vec![0.3, -0.2], vec![0.1, 0.0], &|_| 0.0, 0.05, 2000);
    let e0 = out[0].energy.kinetic + out[0].energy.strain;
    for s in &out {
        let e = s.energy.kinetic + s.energy.strain;
        assert!((e - e0).abs() <= 1e-10 * e0, "step {}: {e} vs {e0}", s.step);
    }
    let mut sys = two_dof(0.3, 0.001);
    let out = run(
        &mut sys,
        Scheme::default(),
        vec![0.0, 0.0],
        vec![0.0, 0.0],
        &|t| (3.0 * t).sin() + 0.5 * (11.0 * t).cos(),
        0.01,
        2000,
    );
    let last = out.last().unwrap().energy;
    assert!(last.input.abs() > 0.0 && last.damping > 0.0);
    assert!(last.relative_error() < 1e-10, "balance error {}", last.relative_error());
    // Linear elastic: nothing is dissipated by damage.
    assert!(last.dissipated().abs() < 1e-10 * last.input.abs());
}

#[test]
fn a_linear_system_factors_once_per_step_size() {
    // Modified and initial Newton on a linear system: J depends on h only.
    let mut sys = two_dof(0.3, 0.001);
    run(&mut sys, Scheme::default(), vec![0.1, 0.0], vec![0.0, 0.0], &|_| 0.0, 0.01, 50);
    assert_eq!(sys.factorizations, 1);
}

#[test]
fn the_linear_step_equals_newton_on_a_linear_system() {
    // The one-solve step of `linear_step.rs` (products kept from step to step, the residual
    // checked with fresh products every CHECK_EVERY steps) against the Newton path iterated to
    // 1e-12 on the same damped 2-DOF system (Rayleigh 0.3 M + 0.001 K) under a two-harmonic
    // ground motion, with HHT α = −0.1 and a short last step (1.0 s is 99 steps of 0.0101 s plus
    // one of 0.0001 s): both are the same linear recurrence, so they agree to round-off (1e-10 of
    // the largest value) in u, v, a and in every energy term. Both take one solve per step, and
    // factor twice (h = 0.0101 s, then the last step's h).
    let ag = |t: f64| (3.0 * t).sin() + 0.5 * (11.0 * t).cos();
    let go = |linear: bool| {
        let mut sys = two_dof(0.3, 0.001);
        sys.linear = linear;
        let mut st = State::new(&mut sys, vec![0.01, -0.02], vec![0.1, 0.0], vec![0.0, 0.0]).unwrap();
        let mut stepper = Stepper::new(settings(Scheme::hht(-0.1)));
        let (mut out, mut its) = (vec![], 0);
        for k in 1..=100 {
            let target = (k as f64 * 0.0101).min(1.0);
            its += stepper.advance(&mut sys, &|t| [ag(t), 0.0, 0.0], &mut st, target, 0.0101).unwrap().iterations;
            out.push(st.clone());
        }
        (out, its, sys.factorizations)
    };
    let ((lin, its_lin, fact_lin), (newton, its_newton, fact_newton)) = (go(true), go(false));
    assert_eq!((its_lin, its_newton, fact_lin, fact_newton), (100, 100, 2, 2));
    /// One group of compared values of a state.
    type Field = fn(&State) -> Vec<f64>;
    let big = |f: Field| newton.iter().flat_map(f).fold(0.0, |m: f64, x| m.max(x.abs()));
    let fields: [Field; 4] = [
        |s| s.u.clone(),
        |s| s.v.clone(),
        |s| s.a.clone(),
        |s| {
            let e = s.energy;
            vec![e.input, e.kinetic, e.strain, e.damping, e.internal_work]
        },
    ];
    for f in fields {
        let scale = big(f);
        for (a, b) in lin.iter().zip(&newton) {
            assert_eq!((a.step, a.t), (b.step, b.t));
            for (x, y) in f(a).iter().zip(f(b)) {
                assert!((x - y).abs() <= 1e-10 * scale, "step {}: {x} vs {y} (scale {scale})", a.step);
            }
        }
    }
    assert!((lin.last().unwrap().t - 1.0).abs() < 1e-15);
}

#[test]
fn hht_dissipates_high_frequencies_and_keeps_the_low() {
    // HHT-α with α = −0.1: spectral radius at Ω → ∞ is (1 + α)/(1 − α) = 0.818 per step (Hilber et
    // al. 1977); at Ω = 0.05 the damping ratio is below 0.2 %. An undamped SDOF at Ω = 10 loses
    // most of its energy in 20 steps; one at Ω = 0.05 keeps 99 % over one period.
    let sc = Scheme::hht(-0.1);
    let w = 2.0 * PI;
    let mut sys = sdof(1.0, 0.0, w * w);
    let out = run(&mut sys, sc, vec![1.0], vec![0.0], &|_| 0.0, 10.0 / w, 20);
    let e = |s: &State| s.energy.kinetic + s.energy.strain;
    assert!(e(out.last().unwrap()) < 0.05 * e(&out[0]));
    let mut sys = sdof(1.0, 0.0, w * w);
    let out = run(&mut sys, sc, vec![1.0], vec![0.0], &|_| 0.0, 0.05 / w, (2.0 * PI / 0.05) as usize);
    assert!(e(out.last().unwrap()) > 0.99 * e(&out[0]));
}

/// An SDOF with a hardening spring f_int = k u + k₃ u³ (Duffing), to exercise Newton and the
/// substepping on a nonlinear system.
struct Duffing {
    lin: DenseSystem,
    k3: f64,
    lu: f64,
}

impl DynamicSystem for Duffing {
    linear_part_methods!();
    fn internal_force(&mut self, u: &[f64], f: &mut [f64]) -> Result<(), crate::error::Error> {
        f[0] = self.lin.k[(0, 0)] * u[0] + self.k3 * u[0].powi(3);
        Ok(())
    }
    fn prepare(&mut self, tangent_at: Option<&[f64]>, c_m: f64, c_c: f64) -> Result<(), crate::error::Error> {
        let u = tangent_at.map_or(0.0, |u| u[0]);
        self.lu = self.lin.k[(0, 0)] + 3.0 * self.k3 * u * u + c_m * self.lin.m[(0, 0)] + c_c * self.lin.c[(0, 0)];
        Ok(())
    }
    fn solve(&mut self, r: &[f64], x: &mut [f64]) -> Result<(), crate::error::Error> {
        x[0] = r[0] / self.lu;
        Ok(())
    }
    fn commit(&mut self) {}
    fn revert(&mut self) {}
}

#[test]
fn a_step_that_fails_is_substepped_and_a_hopeless_one_reported() {
    // A stiffly hardening spring released from u₀ = 1 with modified Newton limited to 6
    // iterations: the whole step (ω₀h = 0.5, k₃ u² = 50 k) cannot converge, halves can.
    // Every substep ends in equilibrium, so the trapezoidal energy identity (`energy.rs`) holds
    // across them: E_k + W_int stays 0 (no input, no damping) to round-off, 1e-10 relative.
    let mk = || Duffing { lin: sdof(1.0, 0.0, 1.0), k3: 50.0, lu: 1.0 };
    let run_with = |max_iterations: usize, max_substeps: usize, dt: f64, steps: usize| {
        let mut sys = mk();
        let mut st = State::new(&mut sys, vec![1.0], vec![0.0], vec![-51.0]).unwrap();
        let mut stepper = Stepper::new(StepSettings {
            scheme: Scheme::default(),
            newton: NewtonKind::Modified,
            integration: crate::config::IntegrationKind::Implicit,
            krylov_dimension: 3,
            refresh_cost: 0,
            max_iterations,
            tolerance: 1e-12,
            max_substeps,
            max_damage_increment: 1.0,
            line_search: false,
            implex_corrections: 0,
            implex_tolerance: 0.0,
            implex_pass_tolerance: 0.0,
        });
        let mut reports = Vec::new();
        for k in 1..=steps {
            match stepper.advance(&mut sys, &|_| [0.0; 3], &mut st, k as f64 * dt, dt) {
                Ok(r) => reports.push(r),
                Err(f) => return Err(f),
            }
        }
        Ok((st, reports))
    };
    let (st, reports) = run_with(6, 6, 0.5, 1).unwrap();
    assert!(reports[0].substeps > 1, "{reports:?}");
    assert!(st.energy.relative_error() < 1e-10, "{:?}", st.energy);
    assert!(st.energy.kinetic > 0.0 && st.u[0].abs() < 1.0 + 1e-9);
    // With no halving allowed the step fails, and says why.
    let f = run_with(6, 0, 0.5, 1).unwrap_err();
    assert!(f.reason.contains("no convergence in 6 iterations"), "{}", f.reason);
    assert_eq!(f.r.len(), 1);
}

#[test]
fn krylov_newton_converges_to_the_same_steps_in_fewer_iterations() {
    // The hardening spring of the test above, mildly (k₃ u² = 5 k) so that modified Newton
    // converges without substeps: both variants stop at the same tolerance (1e-12), so the
    // trajectories agree to that tolerance (1e-9 of the amplitude), and the accelerated one needs
    // fewer iterations in total (Carlson–Miller; src/analysis/time_history/krylov.rs).
    let go = |newton: NewtonKind| {
        let mut sys = Duffing { lin: sdof(1.0, 0.0, 1.0), k3: 5.0, lu: 1.0 };
        let mut st = State::new(&mut sys, vec![1.0], vec![0.0], vec![-6.0]).unwrap();
        let mut stepper = Stepper::new(StepSettings {
            scheme: Scheme::default(),
            newton,
            integration: crate::config::IntegrationKind::Implicit,
            krylov_dimension: 3,
            refresh_cost: 0,
            max_iterations: 40,
            tolerance: 1e-12,
            max_substeps: 0,
            max_damage_increment: 1.0,
            line_search: false,
            implex_corrections: 0,
            implex_tolerance: 0.0,
            implex_pass_tolerance: 0.0,
        });
        let (mut us, mut its) = (Vec::new(), 0);
        for k in 1..=40 {
            let r = stepper.advance(&mut sys, &|_| [0.0; 3], &mut st, k as f64 * 0.1, 0.1).unwrap();
            its += r.iterations;
            us.push(st.u[0]);
        }
        (us, its)
    };
    let (um, im) = go(NewtonKind::Modified);
    let (uk, ik) = go(NewtonKind::Krylov);
    for (a, b) in um.iter().zip(&uk) {
        assert!((a - b).abs() < 1e-9, "{a} vs {b}");
    }
    assert!(ik < im, "krylov {ik} iterations, modified {im}");
    println!("iterations over 40 steps: modified {im}, krylov {ik}");
}

#[test]
fn a_kept_tangent_reaches_the_same_steps_with_fewer_refreshes() {
    // The hardening spring of the test above under Krylov–Newton, the tangent formed at every
    // step's start (refresh_cost 0) or kept while its extra iterations stay below 8 (the
    // default, `refresh.rs`): both converge every step to 1e-12, so the trajectories agree to
    // 1e-9 of the amplitude, and the kept tangent starts fewer steps on a fresh one.
    let go = |refresh_cost: usize| {
        let mut sys = Duffing { lin: sdof(1.0, 0.0, 1.0), k3: 5.0, lu: 1.0 };
        let mut st = State::new(&mut sys, vec![1.0], vec![0.0], vec![-6.0]).unwrap();
        let mut stepper =
            Stepper::new(StepSettings { refresh_cost, newton: NewtonKind::Krylov, ..settings(Scheme::default()) });
        stepper.settings.max_iterations = 40;
        let mut us = Vec::new();
        for k in 1..=40 {
            stepper.advance(&mut sys, &|_| [0.0; 3], &mut st, k as f64 * 0.1, 0.1).unwrap();
            us.push(st.u[0]);
        }
        (us, stepper.refresh.refreshed, stepper.refresh.kept)
    };
    let (u_every, fresh_every, kept_every) = go(0);
    let (u_kept, fresh_kept, kept_kept) = go(8);
    assert_eq!((fresh_every, kept_every), (40, 0));
    assert!(kept_kept > 0 && fresh_kept < 40, "fresh {fresh_kept}, kept {kept_kept}");
    for (a, b) in u_every.iter().zip(&u_kept) {
        assert!((a - b).abs() < 1e-9, "{a} vs {b}");
    }
}
