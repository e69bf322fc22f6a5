//! The static step before the earthquake: the static loads (self-weight, nodal loads) applied by
//! a load factor λ from 0 to 1 in `steps` steps, full Newton in each on
//! `r(u) = λ f_static − f_int(u)`; the steps' sizes follow [`IncrementControl`]: a failing step
//! is halved, a converged one lets the next grow by 1.5 up to `1/steps`, and a load the structure
//! cannot carry (a limit point) ends at the floor `1/steps / 2^max_cuts`, after `max_cuts`
//! halvings in a row, or when the attempt budget is spent, with its last equilibrium. It uses the same
//! [`DynamicSystem`] as the time history (with `c_m = c_c = 0` the Jacobian is the tangent), so the
//! gravity state the earthquake starts from lives in the same elements.
use super::system::DynamicSystem;
use crate::analysis::increment::{IncrementControl, IncrementStop};
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
        for it in 0..=s.max_iterations {
            its = it;
            if let Err(e) = sys.internal_force(&trial, &mut fi) {
                reason = e.to_string();
                break;
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
            if let Err(e) = sys.prepare(Some(&trial), 0.0, 0.0).and_then(|_| sys.solve(&r, &mut du)) {
                reason = format!("iteration {it}: {e}");
                break;
            }
            for i in 0..n {
                trial[i] += du[i];
            }
        }
        if converged {
            sys.commit();
            u = trial;
            lambda = target;
            control.converged();
            log.info(format!("gravity: λ = {lambda:.4}, {its} iteration(s), relative residual {rel:.2e}"));
            if lambda < 1.0 - 1e-12 && control.exhausted() {
                let message = format!("gravity: stopped at λ = {lambda:.6}: {}", IncrementStop::Budget.describe(&control));
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
