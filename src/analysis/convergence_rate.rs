//! Whether a Newton iteration can still reach its tolerance within its budget, judged from how
//! fast its residual has fallen: an attempt that cannot is abandoned early and its step cut,
//! instead of being run to the iteration limit.
//!
//! This is the logarithmic rate-of-convergence check of Abaqus' automatic increment control
//! (Abaqus Analysis User's Guide, "Commonly used control parameters": an increment whose residuals
//! project more iterations than allowed is abandoned). With r_k the relative residual of
//! iteration k and a window of w iterations, the mean contraction per iteration over the window
//! and the iterations it projects to reach the tolerance τ are
//!
//! ```text
//!   ρ = (r_k / r_{k−w})^{1/w},      n = ln(τ / r_k) / ln ρ   (n = ∞ when ρ ≥ 1)
//! ```
//!
//! and the attempt is abandoned when k + n exceeds twice the budget: the projection is rough (a
//! linearly converging attempt may still speed up: the cube-root spring of the gravity tests
//! projects 46 at its 10th iteration and converges within 40). It is judged only from k = 2w on,
//! so that the first, often erratic, iterations of a step (a crack opening, a line search's
//! first landings) cannot end it. Quadratic or linear convergence at any useful rate passes: the
//! test only ends attempts whose residual has stalled or crawls.

/// Iterations over which the contraction is averaged; the check starts at twice this.
pub const RATE_WINDOW: usize = 5;

/// Why an attempt with relative residuals `history` (iteration 0 first) will not reach
/// `tolerance` within `max_iterations`, judged over [`RATE_WINDOW`]; `None` while it may.
pub fn too_slow(history: &[f64], tolerance: f64, max_iterations: usize) -> Option<String> {
    let k = history.len().checked_sub(1)?;
    if k < 2 * RATE_WINDOW || k >= max_iterations {
        return None;
    }
    let (now, before) = (history[k], history[k - RATE_WINDOW]);
    if !(now > tolerance) || !(before > 0.0) {
        return None;
    }
    let rate = (now / before).powf(1.0 / RATE_WINDOW as f64);
    let needed = if rate < 1.0 { (tolerance / now).ln() / rate.ln() } else { f64::INFINITY };
    (k as f64 + needed > (2 * max_iterations) as f64).then(|| {
        format!(
            "the residual falls by {rate:.3} per iteration over the last {RATE_WINDOW}: {} to the tolerance, far beyond the {max_iterations} allowed",
            if needed.is_finite() { format!("{:.0} more iterations", needed.ceil()) } else { "never".into() }
        )
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    fn geometric(r0: f64, rate: f64, n: usize) -> Vec<f64> {
        (0..n).map(|k| r0 * rate.powi(k as i32)).collect()
    }

    /// A residual that halves each iteration reaches 1e-10 from 1e-1 in 30 iterations: within a
    /// budget of 40 (or 15, twice which is 30) it is never judged too slow, within a budget of 14
    /// it is from iteration 10 on (10 + 20 projected > 28).
    #[test]
    fn a_steady_rate_is_judged_against_the_budget() {
        let r = geometric(0.1, 0.5, 31);
        for k in 0..r.len() {
            assert!(too_slow(&r[..=k], 1e-10, 40).is_none(), "iteration {k}");
            assert!(too_slow(&r[..=k], 1e-10, 15).is_none(), "iteration {k}");
        }
        assert!(too_slow(&r[..10], 1e-10, 14).is_none(), "judged before 2 windows");
        let why = too_slow(&r[..11], 1e-10, 14).expect("10 + 20 iterations > 28");
        assert!(why.contains("0.500") && why.contains("20 more"), "{why}");
    }

    /// The plateau of the church's last gravity step (relative residuals 8e-3 to 3e-3 from
    /// iteration 3 on, measured; projected 137 to 441 more iterations at the 10th): abandoned at
    /// iteration 10, where it used to run to 40.
    #[test]
    fn a_stalled_residual_is_abandoned_after_two_windows() {
        let r = [1.0e-1, 3.1e-2, 1.9e-2, 8.3e-3, 7.0e-3, 6.7e-3, 5.9e-3, 5.3e-3, 5.0e-3, 5.1e-3, 5.0e-3];
        assert!(too_slow(&r[..10], 1e-10, 40).is_none());
        let why = too_slow(&r, 1e-10, 40).expect("stalled");
        assert!(why.contains("far beyond the 40 allowed"), "{why}");
        let rising = [1.0e-1, 3.1e-2, 1.9e-2, 8.3e-3, 7.0e-3, 6.7e-3, 5.9e-3, 5.3e-3, 5.0e-3, 5.1e-3, 7.5e-3];
        assert!(too_slow(&rising, 1e-10, 40).expect("rising").contains("never"));
    }

    /// Quadratic convergence after a jump (the church's gravity step at λ = 0.9688: 1.1e-3, then
    /// 0.89 at iteration 5, converged at 11) is not judged: over the window the residual fell.
    #[test]
    fn convergence_after_a_jump_passes() {
        let r = [6.7e-3, 6.7e-3, 4.3e-3, 1.1e-3, 9.0e-1, 8.9e-1, 7.4e-1, 1.3e-1, 2.0e-2, 5.0e-4, 3.0e-7];
        assert!(too_slow(&r, 1e-10, 40).is_none());
        assert!(too_slow(&r[..3], 1e-10, 40).is_none() && too_slow(&[], 1e-10, 40).is_none());
    }
}
