//! The static step before the earthquake: the static loads (self-weight, nodal loads) applied by
//! a load factor λ from 0 to 1 in `steps` steps, full Newton with a secant line search in each
//! on `r(u) = λ f_static − f_int(u)` ([`line_search_step`]); the steps' sizes follow [`IncrementControl`]: a failing step
//! is halved, a converged one lets the next grow by 1.5 up to `1/steps`, and a load the structure
//! cannot carry (a limit point) ends at the floor `1/steps / 2^max_cuts`, after `max_cuts`
//! halvings in a row, or when the attempt budget is spent, with its last equilibrium. An attempt
//! whose residual falls too slowly to reach the tolerance within twice `max_iterations` is
//! abandoned as soon as that shows ([`convergence_rate::too_slow`]: on the church, the last load step's
//! three failing attempts stalled near 3e-3 from their 10th iteration and ran to 40). It uses the same
//! [`DynamicSystem`] as the time history (with `c_m = c_c = 0` the Jacobian is the tangent), so the
//! gravity state the earthquake starts from lives in the same elements.
use super::system::DynamicSystem;
use crate::analysis::convergence_rate;
use crate::analysis::increment::{IncrementControl, IncrementStop};
use crate::analysis::line_search::{self, LineSearchSettings};
use crate::parallel::Log;

/// Settings of the gravity phase.
#[derive(Clone, Copy, Debug)]
pub struct GravitySettings {
    /// Load steps.
    pub steps: usize,
    /// Newton iterations per step.
    pub max_iterations: usize,
    /// Relative tolerance on ‖r‖ / ‖λ f‖.
    pub tolerance: f64,
    /// Halvings of a failing step in a row; also sets the floor `1/steps / 2^max_cuts`.
    pub max_cuts: usize,
}

/// A gravity phase that stopped short of the full load: the structure cannot carry its static
/// load (a limit point under load control), or Newton cannot find the next equilibrium. The last
/// equilibrium stays committed in the elements.
#[derive(Clone, Debug)]
pub struct GravityFailure {
    /// Load factor of the last equilibrium.
    pub lambda: f64,
    /// Load factor of the last step tried.
    pub target: f64,
    /// Displacement at `lambda` (owned DOFs).
    pub u: Vec<f64>,
    /// Residual `target f − f_int` of the last iteration tried (owned DOFs).
    pub r: Vec<f64>,
    /// What happened, for the user.
    pub message: String,
}

/// Collective. The static equilibrium under the full static load, committed in the elements.
/// Returns the displacement (zero when there is no static load).
pub fn solve_gravity<S: DynamicSystem>(sys: &mut S, s: GravitySettings, log: &Log) -> Result<Vec<f64>, GravityFailure> {
    let n = sys.len();
    let f = sys.static_load().to_vec();
    let f_norm = sys.dot(&f, &f).sqrt();
    let mut u = vec![0.0; n];
    if f_norm == 0.0 {
        log.info("gravity: no static load; the time history starts from rest at u = 0");
        return Ok(u);
    }
    let (mut fi, mut r, mut du) = (vec![0.0; n], vec![0.0; n], vec![0.0; n]);
    let mut lambda = 0.0f64;
    let mut control = IncrementControl::new(s.steps, s.max_cuts);
    while lambda < 1.0 - 1e-12 {
        let target = (lambda + control.size()).min(1.0);
        let mut trial = u.clone();
        let mut converged = false;
        let mut rel = f64::INFINITY;
        let mut its = 0;
        let mut reason = String::from("no convergence");
        // fi holds f_int(trial) (the line search's last evaluation landed on the accepted η).
        let mut fresh = false;
        let mut history = Vec::with_capacity(s.max_iterations + 1);
        for it in 0..=s.max_iterations {
            its = it;
            if !fresh {
                if let Err(e) = sys.internal_force(&trial, &mut fi) {
                    reason = e.to_string();
                    break;
                }
            }
            for i in 0..n {
                r[i] = target * f[i] - fi[i];
            }
            rel = sys.dot(&r, &r).sqrt() / (target * f_norm);
            if !rel.is_finite() {
                reason = "the residual is not finite".into();
                break;
            }
            if rel > crate::analysis::newton::DIVERGED {
                reason = format!("iteration {it}: the iterate diverged");
                break;
            }
            if rel <= s.tolerance {
                converged = true;
                break;
            }
            if it == s.max_iterations {
                break;
            }
            history.push(rel);
            if let Some(why) = convergence_rate::too_slow(&history, s.tolerance, s.max_iterations) {
                reason = why;
                break;
            }
            if let Err(e) = sys.prepare(Some(&trial), 0.0, 0.0).and_then(|_| sys.solve(&r, &mut du)) {
                reason = format!("iteration {it}: {e}");
                break;
            }
            match line_search_step(sys, &f, target, &mut trial, &du, &r, &mut fi) {
                Ok(landed) => fresh = landed,
                Err(e) => {
                    reason = format!("iteration {it}: {e}");
                    break;
                }
            }
        }
        if converged {
            sys.commit();
            u = trial;
            lambda = target;
            control.converged();
            log.info(format!("gravity: λ = {lambda:.4}, {its} iteration(s), relative residual {rel:.2e}"));
            if lambda < 1.0 - 1e-12 && control.exhausted() {
                let message =
                    format!("gravity: stopped at λ = {lambda:.6}: {}", IncrementStop::Budget.describe(&control));
                return Err(GravityFailure { lambda, target: lambda, u, r: r.clone(), message });
            }
        } else {
            sys.revert();
            if let Err(stop) = control.failed() {
                let message = format!(
                    "gravity: no static equilibrium from λ = {lambda:.6} towards {target:.6}: {} after {} attempts (last relative residual {rel:.3e}: {reason})",
                    stop.describe(&control),
                    control.attempts()
                );
                return Err(GravityFailure { lambda, target, u, r, message });
            }
            log.info(format!(
                "gravity: step towards λ = {target:.4} failed after {its} iteration(s) (residual {rel:.2e}: {reason}); Δλ = {:.4e}",
                control.size()
            ));
        }
    }
    Ok(u)
}

/// Collective. Moves `trial` along the Newton correction `du` by the step length of a secant
/// line search (`analysis::line_search`: η with du · r(trial + η du) ≈ 0, the full step kept when
/// |s(1)| ≤ 0.8 |s(0)|, which costs nothing: its f_int is the next iteration's). A damage point
/// that ends a load step exactly on its threshold makes r(u) kinked there: the linearization of
/// each side points across the kink, and full Newton steps jump from one side to the other with a
/// residual of the size of the load increment, however small (measured: the fiber-beam church's
/// gravity stalled at λ = 0.983 with 1.7e-5 against a tolerance of 1e-5, halving to the floor).
/// The search lands on the kink instead. Returns whether `fi` holds f_int(trial) on return.
fn line_search_step<S: DynamicSystem>(
    sys: &mut S,
    f: &[f64],
    target: f64,
    trial: &mut [f64],
    du: &[f64],
    r: &[f64],
    fi: &mut [f64],
) -> Result<bool, crate::error::Error> {
    let n = trial.len();
    let s0 = sys.dot(du, r);
    let base = trial.to_vec();
    for i in 0..n {
        trial[i] = base[i] + du[i];
    }
    let residual_along = |sys: &mut S, x: &[f64], fi: &mut [f64]| -> Result<f64, crate::error::Error> {
        sys.internal_force(x, fi)?;
        let r1: Vec<f64> = (0..n).map(|i| target * f[i] - fi[i]).collect();
        Ok(sys.dot(du, &r1))
    };
    let s1 = residual_along(sys, trial, fi)?;
    let mut last = 1.0;
    let found = line_search::secant(s0, s1, &LineSearchSettings::default(), |eta| {
        let x: Vec<f64> = (0..n).map(|i| base[i] + eta * du[i]).collect();
        last = eta;
        residual_along(sys, &x, fi)
    })?;
    for i in 0..n {
        trial[i] = base[i] + found.eta * du[i];
    }
    Ok(last == found.eta)
}

#[cfg(test)]
mod tests {
    use super::super::cube_root_spring::CubeRootSpring;
    use super::*;
    use crate::error::Error;

    fn settings(steps: usize) -> GravitySettings {
        GravitySettings { steps, max_iterations: 40, tolerance: 1e-10, max_cuts: 6 }
    }

    /// Plain Newton on the spring runs away (|u − a| doubles each iteration); the gravity phase's
    /// line search lands on the root (the secant on s(η) = du · r(u + η du) finds η ≈ 1/3) and
    /// converges to the tolerance in one load step.
    #[test]
    fn the_line_search_converges_where_full_newton_runs_away() {
        let a = 2.0;
        let mut sys = CubeRootSpring::new(a);
        let (mut u, f) = (0.5, sys.load[0]);
        for _ in 0..5 {
            sys.prepare(Some(&[u]), 0.0, 0.0).unwrap();
            u += (f - sys.f_int(u)) / sys.jacobian;
        }
        assert!((u - a).abs() > 10.0, "full Newton was expected to run away, u = {u}");
        let mut sys = CubeRootSpring::new(a);
        let u = solve_gravity(&mut sys, settings(1), &Log::new(1, true)).expect("the gravity phase converges");
        assert!((sys.f_int(u[0]) - f).abs() <= 1e-10 * f, "f_int(u) = {} against F = {f}", sys.f_int(u[0]));
    }

    /// A dense linear system that counts its internal-force evaluations.
    struct Counted(super::super::system::DenseSystem, usize);

    impl DynamicSystem for Counted {
        fn len(&self) -> usize {
            self.0.len()
        }
        fn dot(&self, a: &[f64], b: &[f64]) -> f64 {
            self.0.dot(a, b)
        }
        fn mass_mult(&mut self, x: &[f64], y: &mut [f64]) -> Result<(), Error> {
            self.0.mass_mult(x, y)
        }
        fn damping_mult(&mut self, x: &[f64], y: &mut [f64]) -> Result<(), Error> {
            self.0.damping_mult(x, y)
        }
        fn mass_influence(&self, d: usize) -> &[f64] {
            self.0.mass_influence(d)
        }
        fn influence(&self, d: usize) -> &[f64] {
            self.0.influence(d)
        }
        fn static_load(&self) -> &[f64] {
            self.0.static_load()
        }
        fn internal_force(&mut self, u: &[f64], f: &mut [f64]) -> Result<(), Error> {
            self.1 += 1;
            self.0.internal_force(u, f)
        }
        fn prepare(&mut self, at: Option<&[f64]>, c_m: f64, c_c: f64) -> Result<(), Error> {
            self.0.prepare(at, c_m, c_c)
        }
        fn solve(&mut self, r: &[f64], x: &mut [f64]) -> Result<(), Error> {
            self.0.solve(r, x)
        }
        fn commit(&mut self) {}
        fn revert(&mut self) {}
    }

    /// A linear system: each load step converges in one iteration, and the line search keeps the
    /// full step without extra evaluations: its f_int at η = 1 is the next iteration's, so a step
    /// costs two evaluations (its start and its converged state), as full Newton's.
    #[test]
    fn a_linear_system_costs_no_extra_evaluation() {
        let k = nalgebra::DMatrix::from_row_slice(2, 2, &[4.0, -1.0, -1.0, 3.0]);
        let mut dense = super::super::system::DenseSystem::new(
            nalgebra::DMatrix::identity(2, 2),
            nalgebra::DMatrix::zeros(2, 2),
            k,
            vec![],
        );
        dense.f_static = vec![1.0, 2.0];
        let mut sys = Counted(dense, 0);
        let u = solve_gravity(&mut sys, settings(4), &Log::new(1, true)).unwrap();
        // K u = f: u = (5/11, 9/11).
        assert!((u[0] - 5.0 / 11.0).abs() < 1e-12 && (u[1] - 9.0 / 11.0).abs() < 1e-12, "{u:?}");
        assert_eq!(sys.1, 4 * 2, "two evaluations per load step");
    }
}
