//! A local polish of the EGO optimum for cheap objectives: Nelder–Mead (crate `argmin`) from
//! the best point, in the unit cube, with an initial simplex of edge `step`. The cube is kept by
//! a penalty: outside it the objective is evaluated at the nearest point of the cube and
//! `PENALTY · dist²` is added, so the simplex is pushed back without changing the minimizer.
//!
//! EGO locates the basin of the global minimum with few evaluations; when an evaluation costs
//! milliseconds (the damage law along a path), a few hundred more evaluations pin the minimum
//! down to the objective's resolution.
use super::error::{EvalError, IdentifyError};
use argmin::core::{CostFunction, Error, Executor, State};
use argmin::solver::neldermead::NelderMead;
use std::cell::RefCell;

/// Penalty factor on the squared distance outside the unit cube.
pub const PENALTY: f64 = 1e3;
/// Cost of a failed evaluation.
pub const FAILED: f64 = 1e30;

/// The polish's outcome.
#[derive(Clone, Debug)]
pub struct Polished {
    /// Best point (unit cube).
    pub unit: Vec<f64>,
    /// Its value.
    pub value: f64,
    /// Every evaluation: point (in the cube) and value.
    pub evaluations: Vec<(Vec<f64>, Result<f64, EvalError>)>,
}

/// Every point evaluated, with its value or why it has none.
type EvaluationLog = RefCell<Vec<(Vec<f64>, Result<f64, EvalError>)>>;

struct Cost<'a, F: Fn(&[f64]) -> Result<f64, EvalError>> {
    f: &'a F,
    log: &'a EvaluationLog,
}

impl<F: Fn(&[f64]) -> Result<f64, EvalError>> CostFunction for Cost<'_, F> {
    type Param = Vec<f64>;
    type Output = f64;
    fn cost(&self, p: &Vec<f64>) -> Result<f64, Error> {
        let inside: Vec<f64> = p.iter().map(|v| v.clamp(0.0, 1.0)).collect();
        let d2: f64 = p.iter().zip(&inside).map(|(a, b)| (a - b).powi(2)).sum();
        let v = (self.f)(&inside);
        let c = match &v {
            Ok(x) if x.is_finite() => *x,
            _ => FAILED,
        };
        self.log.borrow_mut().push((inside, v));
        Ok(c + PENALTY * d2)
    }
}

/// An error of the polish, as the optimizer's.
fn optimizer(e: impl std::fmt::Display) -> IdentifyError {
    IdentifyError::Optimizer(e.to_string())
}

/// Nelder–Mead from `start` (unit cube) on `f`, at most `max_iters` iterations.
pub fn polish<F: Fn(&[f64]) -> Result<f64, EvalError>>(
    f: &F,
    start: &[f64],
    step: f64,
    max_iters: u64,
) -> Result<Polished, IdentifyError> {
    let n = start.len();
    let mut simplex = vec![start.to_vec()];
    for i in 0..n {
        let mut v = start.to_vec();
        // Step inward, so every vertex starts in the cube.
        v[i] = if v[i] + step <= 1.0 { v[i] + step } else { v[i] - step };
        simplex.push(v);
    }
    let log = RefCell::new(Vec::new());
    let solver = NelderMead::new(simplex).with_sd_tolerance(1e-10).map_err(optimizer)?;
    let res =
        Executor::new(Cost { f, log: &log }, solver).configure(|s| s.max_iters(max_iters)).run().map_err(optimizer)?;
    let state = res.state();
    let best = state.get_best_param().cloned().unwrap_or_else(|| start.to_vec());
    let unit: Vec<f64> = best.iter().map(|v| v.clamp(0.0, 1.0)).collect();
    let value = f(&unit).map_err(optimizer)?;
    Ok(Polished { unit, value, evaluations: log.into_inner() })
}

/// [`polish`] from each of `starts`, each restarted from its result `restarts` times (a fresh
/// simplex around the last best point) while that improves; the best of all.
pub fn polish_multistart<F: Fn(&[f64]) -> Result<f64, EvalError>>(
    f: &F,
    starts: &[Vec<f64>],
    step: f64,
    max_iters: u64,
    restarts: usize,
) -> Result<Polished, IdentifyError> {
    let mut all = Vec::new();
    let mut best: Option<(Vec<f64>, f64)> = None;
    for s in starts {
        let mut at = s.clone();
        let mut value = f64::INFINITY;
        for _ in 0..=restarts {
            let p = polish(f, &at, step, max_iters)?;
            all.extend(p.evaluations);
            if !(p.value < value * (1.0 - 1e-9)) {
                if p.value < value {
                    (at, value) = (p.unit, p.value);
                }
                break;
            }
            (at, value) = (p.unit, p.value);
        }
        if best.as_ref().is_none_or(|b| value < b.1) {
            best = Some((at, value));
        }
    }
    let (unit, value) = best.ok_or_else(|| IdentifyError::Optimizer("no starting point".into()))?;
    Ok(Polished { unit, value, evaluations: all })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn reaches_a_minimum_on_the_cube_boundary_and_inside() {
        // f = Σ (u_i − c_i)², minimum 0 at c (inside), and at the clamped c on the boundary.
        let c = [0.3, 0.7, 1.4];
        let f = |u: &[f64]| Ok(u.iter().zip(&c).map(|(a, b)| (a - b).powi(2)).sum::<f64>());
        let p = polish(&f, &[0.5, 0.5, 0.5], 0.1, 500).unwrap();
        assert!(
            (p.unit[0] - 0.3).abs() < 1e-4 && (p.unit[1] - 0.7).abs() < 1e-4 && (p.unit[2] - 1.0).abs() < 1e-4,
            "{:?}",
            p.unit
        );
        // At the boundary the value is (1.4 − 1)² = 0.16.
        assert!((p.value - 0.16).abs() < 1e-6);
    }
}
