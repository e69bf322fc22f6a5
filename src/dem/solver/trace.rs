//! The Newton history of the last equilibrium attempts: what a stopped test was doing when it
//! stopped (diagnostics, off by default: [`super::SolverOptions::trace`]).
//!
//! Every call of the equilibrium iteration ([`super::Solver::equilibrate`], a beam's release, a
//! load step, a cut-back) is one [`Attempt`]; each Newton iteration one [`NewtonStep`] with the
//! residual it started from, the step taken and the state of the contact set. Only the last
//! [`KEPT_ATTEMPTS`] attempts are kept, so a long run costs a bounded memory.
use std::collections::VecDeque;

/// Attempts kept.
pub const KEPT_ATTEMPTS: usize = 12;

/// One Newton iteration.
#[derive(Clone, Debug, PartialEq, serde::Serialize)]
pub struct NewtonStep {
    /// `‖r‖∞ / scale` at the start of the iteration.
    pub relative: f64,
    /// The merit `½ Σ (w r)²` at the start.
    pub merit: f64,
    /// Active contacts at the start.
    pub contacts: usize,
    /// Of which sliding.
    pub sliding: usize,
    /// Of which on the crushing branch (plastic in this increment).
    pub crushing: usize,
    /// Contacts entering or leaving, and stick/slip flips, against the previous iteration.
    pub set_changes: usize,
    /// GMRES products of the linear solve (0: a direct solve).
    pub gmres_iterations: usize,
    /// Whether the linear solve met its tolerance.
    pub linear_converged: bool,
    /// The scale the step cap applied (1: none).
    pub cap: f64,
    /// The line-search step length accepted (continuation: 1 accepted, 0 rejected).
    pub alpha: f64,
    /// The continuation's shift `σ` (0 in Newton's method).
    pub shift: f64,
    /// Where the residual is largest: the stone (`None`: a force-controlled platen), the
    /// component (0, 1: force x, y; 2: moment) and the residual there (N or N·m).
    pub worst: (Option<usize>, usize, f64),
    /// The contacts that entered, left or flipped between stick and slip against the previous
    /// iteration (the first [`KEPT_CHANGES`] of `set_changes`): the pair, what happened, `F_n`
    /// (N) and `|F_t| / F_n` at this iteration (both 0 for a contact that left).
    pub changed: Vec<Change>,
}

/// Changed contacts kept per iteration.
pub const KEPT_CHANGES: usize = 6;

/// A contact that entered, left or flipped between two Newton iterations.
#[derive(Clone, Debug, PartialEq, serde::Serialize)]
pub struct Change {
    /// The pair.
    pub pair: (usize, usize),
    /// "enter", "leave", "stick" (slip → stick) or "slip" (stick → slip).
    pub what: &'static str,
    /// Normal force (N) at this iteration.
    pub f_n: f64,
    /// `|F_t| / F_n` at this iteration.
    pub ratio: f64,
}

/// One equilibrium attempt.
#[derive(Clone, Debug, PartialEq, serde::Serialize)]
pub struct Attempt {
    /// Load stage.
    pub stage: usize,
    /// Load parameter within the stage.
    pub t: f64,
    /// Broken beams so far.
    pub event: usize,
    /// What the attempt was (the caller's label: "step", "release", "pre-break", ...).
    pub what: &'static str,
    /// The Newton iterations.
    pub steps: Vec<NewtonStep>,
    /// The final relative residual (NaN where the linear phase took Newton's first step as the
    /// equilibrium without evaluating it, `super::linear`).
    pub final_relative: f64,
    /// Whether it converged.
    pub converged: bool,
}

/// The last attempts.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Trace {
    /// Oldest first.
    pub attempts: VecDeque<Attempt>,
}

impl Trace {
    /// Starts a new attempt (dropping the oldest beyond [`KEPT_ATTEMPTS`]).
    pub fn begin(&mut self, stage: usize, t: f64, event: usize, what: &'static str) {
        if self.attempts.len() == KEPT_ATTEMPTS {
            self.attempts.pop_front();
        }
        self.attempts.push_back(Attempt {
            stage,
            t,
            event,
            what,
            steps: Vec::new(),
            final_relative: f64::NAN,
            converged: false,
        });
    }

    /// Adds an iteration to the current attempt.
    pub fn step(&mut self, s: NewtonStep) {
        if let Some(a) = self.attempts.back_mut() {
            a.steps.push(s);
        }
    }

    /// Closes the current attempt.
    pub fn end(&mut self, final_relative: f64, converged: bool) {
        if let Some(a) = self.attempts.back_mut() {
            a.final_relative = final_relative;
            a.converged = converged;
        }
    }

    /// A readable table of the kept attempts.
    pub fn report(&self) -> String {
        let mut s = String::new();
        for a in &self.attempts {
            s.push_str(&format!(
                "attempt {} stage {} t {:.6} event {}: {} iterations, final residual {:.3e}, {}\n",
                a.what,
                a.stage,
                a.t,
                a.event,
                a.steps.len(),
                a.final_relative,
                if a.converged { "converged" } else { "NOT converged" }
            ));
            s.push_str(
                "   it   residual      merit   contacts sliding crushing changes gmres lin    cap   alpha   shift\n",
            );
            for (k, st) in a.steps.iter().enumerate() {
                s.push_str(&format!(
                    "  {:3} {:10.3e} {:10.3e} {:8} {:7} {:8} {:7} {:5} {:3} {:6.3} {:7.4} {:7.1e}\n",
                    k,
                    st.relative,
                    st.merit,
                    st.contacts,
                    st.sliding,
                    st.crushing,
                    st.set_changes,
                    st.gmres_iterations,
                    if st.linear_converged { "y" } else { "n" },
                    st.cap,
                    st.alpha,
                    st.shift
                ));
                let at = st.worst.0.map_or_else(|| "a platen".to_string(), |p| format!("stone {p}"));
                s.push_str(&format!("        worst: {at} component {} residual {:.3e}", st.worst.1, st.worst.2));
                for c in &st.changed {
                    s.push_str(&format!(
                        "; ({}, {}) {} F_n {:.3e} |F_t|/F_n {:.4}",
                        c.pair.0, c.pair.1, c.what, c.f_n, c.ratio
                    ));
                }
                s.push('\n');
            }
        }
        s
    }
}
