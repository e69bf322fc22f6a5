//! The work of the equilibria counted by what they were solved for: the phases of the stage loop
//! ([`super::stage`], [`super::breaks`]) and the cut-backs.
//!
//! | phase | the equilibrium of |
//! |---|---|
//! | `trial` | a load step `t → t_try` (thrown away when a beam reaches `P = 1` inside it: `discarded`) |
//! | `predictor` | no equilibrium: the tangent solve that predicts a step's first break (`SolverOptions::break_search`) |
//! | `lambda` | the state at a break's crossing `λ*` inside a converged trial, or at the load the break search landed on ("pre-break") |
//! | `release` | the first beam's release after that state (or a beam broken on request) |
//! | `cascade` | each further release of a cascade (beams with `P ≥ 1` at a relaxed state) |
//! | `cut_back` | any attempt above that did not converge and was retried with a smaller increment |
//! | `other` | the unloaded start |
//!
//! Counts are machine-independent (Newton and GMRES iterations, Jacobians, evaluations), the
//! seconds are not. GMRES's iterations are also kept against the number of sliding contacts at
//! each Newton step ([`SlidingBucket`]): the preconditioner holds a sliding contact's `k_t c cᵀ`
//! that its tangent does not have ([`super::gmres`]), so that is where its quality shows.
/// What an equilibrium is solved for (module docs).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum Phase {
    /// A load step.
    Trial,
    /// The tangent solve of the break search (not an equilibrium).
    Predictor,
    /// The state at a break's `λ*`.
    Lambda,
    /// The first release after a break.
    Release,
    /// A further release of a cascade.
    Cascade,
    /// Anything else (the start).
    #[default]
    Other,
}

/// The counters of one phase (module docs).
#[derive(Clone, Copy, Debug, Default, PartialEq, serde::Serialize)]
pub struct PhaseCounts {
    /// Equilibria solved (attempts; for `cut_back` the attempts that failed).
    pub equilibria: usize,
    /// Newton iterations.
    pub newton_iterations: usize,
    /// Newton iterations whose step needed GMRES (some contact active).
    pub gmres_solves: usize,
    /// GMRES iterations.
    pub gmres_iterations: usize,
    /// The sliding contacts at those Newton steps, summed (over `gmres_solves`: the mean).
    pub sliding: usize,
    /// The active contacts at those Newton steps, summed.
    pub contacts: usize,
    /// Contact Jacobians computed.
    pub jacobians: usize,
    /// Residual evaluations.
    pub evaluations: usize,
    /// Seconds building contact tangents.
    pub jacobian_seconds: f64,
    /// Seconds in residual evaluations.
    pub evaluate_seconds: f64,
    /// Seconds in the equilibria, all of it.
    pub seconds: f64,
}

impl PhaseCounts {
    /// `self += other`.
    pub fn add(&mut self, o: &PhaseCounts) {
        self.equilibria += o.equilibria;
        self.newton_iterations += o.newton_iterations;
        self.gmres_solves += o.gmres_solves;
        self.gmres_iterations += o.gmres_iterations;
        self.sliding += o.sliding;
        self.contacts += o.contacts;
        self.jacobians += o.jacobians;
        self.evaluations += o.evaluations;
        self.jacobian_seconds += o.jacobian_seconds;
        self.evaluate_seconds += o.evaluate_seconds;
        self.seconds += o.seconds;
    }

    /// `self − earlier` (counters only grow).
    pub fn since(&self, earlier: &PhaseCounts) -> PhaseCounts {
        PhaseCounts {
            equilibria: self.equilibria - earlier.equilibria,
            newton_iterations: self.newton_iterations - earlier.newton_iterations,
            gmres_solves: self.gmres_solves - earlier.gmres_solves,
            gmres_iterations: self.gmres_iterations - earlier.gmres_iterations,
            sliding: self.sliding - earlier.sliding,
            contacts: self.contacts - earlier.contacts,
            jacobians: self.jacobians - earlier.jacobians,
            evaluations: self.evaluations - earlier.evaluations,
            jacobian_seconds: self.jacobian_seconds - earlier.jacobian_seconds,
            evaluate_seconds: self.evaluate_seconds - earlier.evaluate_seconds,
            seconds: self.seconds - earlier.seconds,
        }
    }
}

/// Newton steps with GMRES whose sliding contacts number in `[lo, hi)`.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, serde::Serialize)]
pub struct SlidingBucket {
    /// Fewest sliding contacts of the bucket.
    pub lo: usize,
    /// One past the most.
    pub hi: usize,
    /// Newton steps.
    pub steps: usize,
    /// Their GMRES iterations.
    pub gmres_iterations: usize,
}

/// The counts of every phase, and GMRES against sliding contacts (module docs).
#[derive(Clone, Debug, Default, PartialEq, serde::Serialize)]
pub struct Phases {
    /// Load steps.
    pub trial: PhaseCounts,
    /// Converged trials thrown away: a beam reached `P = 1` inside the step (it is then solved
    /// again at `λ*`), the energy did not balance, or a contact event ends the step earlier.
    pub trial_discarded: usize,
    /// Tangent solves of the break search (`equilibria`: the solves; no Newton iteration).
    pub predictor: PhaseCounts,
    /// States at `λ*`.
    pub lambda: PhaseCounts,
    /// First releases.
    pub release: PhaseCounts,
    /// Further releases of cascades.
    pub cascade: PhaseCounts,
    /// Attempts that failed and were cut back.
    pub cut_back: PhaseCounts,
    /// The start.
    pub other: PhaseCounts,
    /// GMRES iterations by the number of sliding contacts: buckets `[0, 1)`, `[1, 2)`, `[2, 4)`,
    /// `[4, 8)` … (only those reached).
    pub gmres_by_sliding: Vec<SlidingBucket>,
}

impl Phases {
    /// Books the work `w` of one equilibrium solved for `phase`; `failed`: it did not converge
    /// (booked as a cut-back).
    pub fn book(&mut self, phase: Phase, failed: bool, w: &PhaseCounts) {
        let to = match (failed, phase) {
            (true, _) => &mut self.cut_back,
            (false, Phase::Trial) => &mut self.trial,
            (false, Phase::Predictor) => &mut self.predictor,
            (false, Phase::Lambda) => &mut self.lambda,
            (false, Phase::Release) => &mut self.release,
            (false, Phase::Cascade) => &mut self.cascade,
            (false, Phase::Other) => &mut self.other,
        };
        to.add(w);
    }

    /// One Newton step with `sliding` sliding contacts took `iterations` GMRES iterations.
    pub fn gmres_step(&mut self, sliding: usize, iterations: usize) {
        let k = if sliding == 0 { 0 } else { (usize::BITS - sliding.leading_zeros()) as usize };
        while self.gmres_by_sliding.len() <= k {
            let j = self.gmres_by_sliding.len();
            let (lo, hi) = if j == 0 { (0, 1) } else { (1 << (j - 1), 1 << j) };
            self.gmres_by_sliding.push(SlidingBucket { lo, hi, ..Default::default() });
        }
        self.gmres_by_sliding[k].steps += 1;
        self.gmres_by_sliding[k].gmres_iterations += iterations;
    }

    /// All phases together (the cut-backs included).
    pub fn total(&self) -> PhaseCounts {
        let mut t = PhaseCounts::default();
        for p in [&self.trial, &self.predictor, &self.lambda, &self.release, &self.cascade, &self.cut_back, &self.other]
        {
            t.add(p);
        }
        t
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn sliding_buckets_are_powers_of_two_and_failures_are_cut_backs() {
        // 0 → [0,1), 1 → [1,2), 3 → [2,4), 4 → [4,8), 1000 → [512,1024) (by hand).
        let mut p = Phases::default();
        for (s, it) in [(0, 1), (1, 2), (3, 3), (4, 4), (1000, 5)] {
            p.gmres_step(s, it);
        }
        let b = &p.gmres_by_sliding;
        assert_eq!(b.len(), 11);
        assert_eq!((b[0].lo, b[0].hi, b[0].steps, b[0].gmres_iterations), (0, 1, 1, 1));
        assert_eq!((b[2].lo, b[2].hi, b[2].gmres_iterations), (2, 4, 3));
        assert_eq!((b[3].lo, b[3].hi, b[3].gmres_iterations), (4, 8, 4));
        assert_eq!((b[10].lo, b[10].hi, b[10].gmres_iterations), (512, 1024, 5));
        assert_eq!(b[5].steps, 0);
        let w = PhaseCounts { equilibria: 1, newton_iterations: 3, ..Default::default() };
        p.book(Phase::Trial, false, &w);
        p.book(Phase::Trial, true, &w);
        p.book(Phase::Cascade, false, &w);
        assert_eq!((p.trial.newton_iterations, p.cut_back.newton_iterations, p.cascade.equilibria), (3, 3, 1));
        assert_eq!(p.total().newton_iterations, 9);
    }
}
