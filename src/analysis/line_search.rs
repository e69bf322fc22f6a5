//! Line search along a Newton correction: the step length η that makes the residual orthogonal
//! to the correction,
//!
//! ```text
//!   s(η) = Δu · r(u + η Δu) = 0,      s(0) = Δu · r(u) = Δuᵀ K Δu > 0 for a positive tangent
//! ```
//!
//! (the stationarity condition of the potential along Δu). The secant method (Crisfield,
//! *Non-linear Finite Element Analysis of Solids and Structures*, vol. 1, §9.3; OpenSees
//! `SecantLineSearch`) starts from η₀ = 0, η₁ = 1 and iterates
//! `η_{j+1} = η_j − s_j (η_j − η_{j−1}) / (s_j − s_{j−1})`, each η clamped to [η_min, η_max],
//! until |s(η)| ≤ tol |s(0)|. The full step is kept when it is already good enough
//! (|s(1)| ≤ tol |s(0)|), so a well-behaved Newton iteration costs no extra residual.
//! When the search does not settle, the η with the smallest |s| found is used: a line search
//! only has to make the step better, not optimal.

/// Line-search settings.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct LineSearchSettings {
    /// Accept η when |s(η)| ≤ tolerance · |s(0)| (Crisfield suggests 0.5–0.8).
    pub tolerance: f64,
    /// Largest number of extra residual evaluations.
    pub max_iterations: usize,
    /// Smallest η.
    pub eta_min: f64,
    /// Largest η.
    pub eta_max: f64,
}

impl Default for LineSearchSettings {
    fn default() -> Self {
        LineSearchSettings { tolerance: 0.8, max_iterations: 5, eta_min: 0.1, eta_max: 10.0 }
    }
}

/// The outcome of a search.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct LineSearchResult {
    /// The step length chosen.
    pub eta: f64,
    /// s at that η.
    pub s: f64,
    /// Residual evaluations made beyond s(1).
    pub evaluations: usize,
}

/// Secant line search (module docs). `s0` = s(0), `s1` = s(1) (already computed by the caller
/// with the full step), `eval(η)` computes s(η). Errors of `eval` are passed on.
pub fn secant<E>(
    s0: f64,
    s1: f64,
    settings: &LineSearchSettings,
    mut eval: impl FnMut(f64) -> Result<f64, E>,
) -> Result<LineSearchResult, E> {
    let tol = settings.tolerance * s0.abs();
    let mut best = LineSearchResult { eta: 1.0, s: s1, evaluations: 0 };
    if !s1.is_finite() || s1.abs() <= tol || s0 == 0.0 {
        return Ok(best);
    }
    let (mut eta_prev, mut s_prev) = (0.0, s0);
    let (mut eta, mut s) = (1.0, s1);
    for k in 1..=settings.max_iterations {
        let denom = s - s_prev;
        if denom == 0.0 || !denom.is_finite() {
            break;
        }
        let next = (eta - s * (eta - eta_prev) / denom).clamp(settings.eta_min, settings.eta_max);
        if next == eta {
            break;
        }
        let s_next = eval(next)?;
        (eta_prev, s_prev) = (eta, s);
        (eta, s) = (next, s_next);
        if s.is_finite() && s.abs() < best.s.abs() {
            best = LineSearchResult { eta, s, evaluations: k };
        }
        best.evaluations = k;
        if s.is_finite() && s.abs() <= tol {
            break;
        }
    }
    Ok(best)
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A quadratic potential along Δu: s(η) = a (η* − η) is linear, so (with a tight tolerance) the secant step
    /// lands on η* in one evaluation (exact to round-off, 1e-14).
    #[test]
    fn linear_s_is_solved_in_one_step() {
        for target in [0.3, 2.5, 7.0] {
            let s = |eta: f64| -> Result<f64, ()> { Ok(3.0 * (target - eta)) };
            let set = LineSearchSettings { tolerance: 1e-6, ..Default::default() };
            let r = secant(s(0.0).unwrap(), s(1.0).unwrap(), &set, s).unwrap();
            assert!((r.eta - target).abs() < 1e-14, "{r:?}");
            assert_eq!(r.evaluations, 1);
        }
    }

    /// A full step that is already good (|s(1)| ≤ 0.8 |s(0)|) is kept without evaluations.
    #[test]
    fn good_full_step_is_kept() {
        let r = secant(1.0, 0.5, &LineSearchSettings::default(), |_| -> Result<f64, ()> {
            panic!("no evaluation expected")
        })
        .unwrap();
        assert_eq!((r.eta, r.evaluations), (1.0, 0));
    }

    /// A nonlinear s(η) = 1 − (η/0.6)³ (root at 0.6): the search gets |s| within the tolerance
    /// (here 1e-3) in a few steps; the clamp keeps η in [0.1, 10] for an overshooting secant.
    #[test]
    fn nonlinear_s_converges_and_clamps() {
        let set = LineSearchSettings { tolerance: 1e-3, max_iterations: 20, ..Default::default() };
        let f = |eta: f64| -> Result<f64, ()> { Ok(1.0 - (eta / 0.6).powi(3)) };
        let r = secant(1.0, f(1.0).unwrap(), &set, f).unwrap();
        assert!((r.eta - 0.6).abs() < 1e-3, "{r:?}");
        // s decreasing very slowly: the secant overshoots and is clamped to η_max.
        let g = |eta: f64| -> Result<f64, ()> { Ok(1.0 - 0.01 * eta) };
        let r = secant(1.0, g(1.0).unwrap(), &LineSearchSettings::default(), g).unwrap();
        assert!(r.eta <= 10.0 && r.eta >= 1.0, "{r:?}");
    }
}
