//! The static step before the earthquake: the static loads (self-weight, nodal loads) applied by
//! a load factor λ from 0 to 1 in `steps` steps, full Newton in each on
//! `r(u) = λ f_static − f_int(u)`; a failing step is halved, up to `max_cuts` times in a row, and
//! after each converged step Δλ doubles again up to its initial `1/steps`. It uses the same
//! [`DynamicSystem`] as the time history (with `c_m = c_c = 0` the Jacobian is the tangent), so the
//! gravity state the earthquake starts from lives in the same elements.
use super::system::DynamicSystem;
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
    /// Halvings of a failing step.
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
    let mut dl = 1.0 / s.steps as f64;
    let mut cuts = 0;
    while lambda < 1.0 - 1e-12 {
        let target = (lambda + dl).min(1.0);
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
            cuts = 0;
            dl = (2.0 * dl).min(1.0 / s.steps as f64);
            log.info(format!("gravity: λ = {lambda:.4}, {its} iteration(s), relative residual {rel:.2e}"));
        } else {
            sys.revert();
            cuts += 1;
            if cuts > s.max_cuts {
                let message = format!(
                    "gravity: no static equilibrium from λ = {lambda:.6} towards {target:.6} after {} halvings in a row (relative residual {rel:.3e}: {reason})",
                    s.max_cuts
                );
                return Err(GravityFailure { lambda, target, u, r, message });
            }
            dl /= 2.0;
            log.info(format!("gravity: step towards λ = {target:.4} failed after {its} iteration(s) (residual {rel:.2e}: {reason}); Δλ = {dl:.4e}"));
        }
    }
    Ok(u)
}
