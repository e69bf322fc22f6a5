//! When Krylov–Newton forms and factors the tangent again: a cost model in solves.
//!
//! A factored Jacobian `J = K_t + c_m M + c_c C` stays a valid preconditioner for the
//! accelerated iterations of [`super::krylov`] long after `K_t` has drifted: a stale `J` costs
//! extra iterations, a fresh one costs an assembly and a factorization. Measured on the church
//! (19 308 DOF, 1 rank, `summary.json`'s `system_seconds`): an assembly 0.11 s and a factorization
//! with its first solve 0.115 s, an iteration (internal forces, a solve, the products) about
//! 0.03 s; a refresh is worth about 8 iterations, the default of `[dynamics] refresh_cost`.
//!
//! The rule, counted in iterations (not in wall time, so that every rank and every rank count
//! takes the same decisions from the same iteration counts):
//!
//! ```text
//!   a step that started on a fresh J and did not refresh within:  b ← its iterations  (baseline)
//!   a step that started on a kept J:                               E ← E + max(0, i − b)
//!   the next step starts on a fresh J when                          E ≥ refresh_cost
//! ```
//!
//! and always when `J` must change anyway or cannot be trusted: a new step size (the
//! coefficients `c_m`, `c_c` change), after a failed attempt (the retry starts on the tangent at
//! its start, as plain Krylov–Newton does), before any baseline exists, and after a step that
//! filled its subspace and formed J within. That last rule keeps J only where the response is
//! quiet: where damage grows, a J formed at an iterate of the last step serves the next one
//! badly. Measured on the church's record (2 ranks): with J kept through the refreshes within
//! steps, two steps needed substeps by t = 3.4 s (the whole record needs one with a fresh J at
//! every step); with the rule, the first 5 s took 1,235 iterations and 312 factorizations
//! against 1,236 and 430 with a fresh J at every step. `refresh_cost = 0` refreshes at every
//! step's start (Krylov–Newton as in OpenSees). The step after a periodic checkpoint starts
//! afresh ([`RefreshPolicy::forget`]), as a run restarted from it does, so that the restarted
//! run repeats the uninterrupted one exactly.

/// The refresh decisions of one stepper.
#[derive(Clone, Debug, Default)]
pub struct RefreshPolicy {
    /// Extra iterations worth one refresh (0: refresh at every step).
    cost: usize,
    /// Iterations of the last step on a fresh J without a refresh inside.
    baseline: Option<usize>,
    /// Extra iterations spent on kept tangents since the last refresh.
    excess: usize,
    /// The step size of the factored J (bits), none when no J is valid or the next step must
    /// start on a fresh one.
    h: Option<u64>,
    /// Refreshes of J at a step's start, and steps that kept it.
    pub refreshed: usize,
    /// Steps that started on a kept J.
    pub kept: usize,
}

impl RefreshPolicy {
    /// A policy with the given cost of a refresh in iterations.
    pub fn new(cost: usize) -> RefreshPolicy {
        RefreshPolicy { cost, ..Default::default() }
    }

    /// Whether the attempt of size `h` about to start must form J afresh. Counts the decision.
    pub fn refresh_at_start(&mut self, h: f64) -> bool {
        let fresh =
            self.cost == 0 || self.h != Some(h.to_bits()) || self.baseline.is_none() || self.excess >= self.cost;
        if fresh {
            self.refreshed += 1;
            self.excess = 0;
            self.h = Some(h.to_bits());
        } else {
            self.kept += 1;
        }
        fresh
    }

    /// J was formed within a step (its subspace full): the next step starts on a fresh one.
    pub fn refreshed_within(&mut self) {
        self.excess = 0;
        self.h = None;
    }

    /// An attempt converged in `iterations`, having started on a fresh J (`fresh`) and formed
    /// J again `within` times.
    pub fn converged(&mut self, iterations: usize, fresh: bool, within: usize) {
        match (fresh, within, self.baseline) {
            (true, 0, _) => self.baseline = Some(iterations),
            (false, 0, Some(b)) => self.excess += iterations.saturating_sub(b),
            _ => {}
        }
    }

    /// Forgets the history (baseline, excess, the kept J), as a new policy would, keeping the
    /// counts: the next attempt starts on a fresh J.
    pub fn forget(&mut self) {
        (self.baseline, self.excess, self.h) = (None, 0, None);
    }

    /// An attempt failed (or J could not be formed): the next attempt starts on a fresh J.
    pub fn failed(&mut self) {
        self.h = None;
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_stale_tangent_is_kept_until_its_extra_iterations_pay_for_a_refresh() {
        // Cost 8: a fresh step of 3 iterations sets the baseline; kept steps of 5 iterations cost
        // 2 extra each, so the 4th kept step's excess (8) triggers the refresh before the 5th.
        let mut p = RefreshPolicy::new(8);
        assert!(p.refresh_at_start(0.02));
        p.converged(3, true, 0);
        let mut kept = 0;
        while !p.refresh_at_start(0.02) {
            p.converged(5, false, 0);
            kept += 1;
        }
        assert_eq!(kept, 4);
        assert_eq!((p.refreshed, p.kept), (2, 4));
    }

    #[test]
    fn a_new_step_size_a_failure_or_cost_zero_refresh_at_once() {
        let mut p = RefreshPolicy::new(8);
        assert!(p.refresh_at_start(0.02));
        p.converged(2, true, 0);
        assert!(!p.refresh_at_start(0.02));
        p.converged(2, false, 0);
        assert!(p.refresh_at_start(0.01), "a new step size changes J");
        p.converged(2, true, 0);
        p.failed();
        assert!(p.refresh_at_start(0.01), "a retry starts on a fresh J");
        let mut every = RefreshPolicy::new(0);
        assert!((0..5).all(|_| {
            let f = every.refresh_at_start(0.02);
            every.converged(2, f, 0);
            f
        }));
    }

    #[test]
    fn a_refresh_within_a_step_makes_the_next_step_start_fresh() {
        let mut p = RefreshPolicy::new(4);
        assert!(p.refresh_at_start(0.02));
        p.converged(2, true, 0);
        assert!(!p.refresh_at_start(0.02));
        p.converged(3, false, 0); // excess 1
        assert!(!p.refresh_at_start(0.02));
        p.refreshed_within();
        p.converged(9, false, 1); // no baseline from it, and J is not kept
        assert!(p.refresh_at_start(0.02));
        p.converged(2, true, 0);
        assert!(!p.refresh_at_start(0.02));
        p.converged(4, false, 0); // excess 2
        assert!(!p.refresh_at_start(0.02));
        p.converged(4, false, 0); // excess 4: refresh next
        assert!(p.refresh_at_start(0.02));
    }
}
