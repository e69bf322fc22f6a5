//! The Newton history of the last equilibrium attempts: what a stopped test was doing when it
//! stopped (diagnostics, off by default: [`super::SolverOptions::trace`]).
//!
//! Every call of the equilibrium iteration ([`super::Solver::equilibrate`], a beam's release, a
//! load step, a cut-back) is one [`Attempt`]; each Newton iteration one [`NewtonStep`] with the
//! residual it started from, the step taken and the state of the contact set (`newton_step`
//! reads it off the iteration's residual evaluation and the previous contact set). Only the last
//! [`KEPT_ATTEMPTS`] attempts are kept, so a long run costs a bounded memory.
use std::collections::{BTreeMap, BTreeSet, VecDeque};

use super::dofs::DofMap;
use super::evaluation::Evaluation;

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

/// The trace's record of a Newton iteration at the evaluation `ev` (the linear solve's and the
/// line search's figures filled in later); `previous` is the contact set of the last one, `map`
/// names the stone of each equation.
pub(super) fn newton_step(
    ev: &Evaluation,
    previous: &mut Option<Vec<(usize, usize, bool)>>,
    map: &DofMap,
) -> NewtonStep {
    let mut changed = previous.as_ref().map_or_else(Vec::new, |p| changed_contacts(p, ev));
    let changes = changed.len();
    changed.truncate(KEPT_CHANGES);
    *previous = Some(ev.contacts.iter().map(|a| (a.i, a.j, a.sticks())).collect());
    let (e, r) =
        ev.r.iter().enumerate().fold((0, 0.0f64), |(k, m), (e, x)| if x.abs() > m { (e, x.abs()) } else { (k, m) });
    let zi = map.unknowns.get(e).copied().unwrap_or(0);
    NewtonStep {
        relative: ev.relative,
        merit: ev.merit,
        contacts: ev.contacts.len(),
        sliding: ev.contacts.iter().filter(|a| !a.sticks()).count(),
        crushing: ev.contacts.iter().filter(|a| a.crush.is_some_and(|c| c.plastic)).count(),
        set_changes: changes,
        gmres_iterations: 0,
        linear_converged: true,
        cap: 1.0,
        alpha: 1.0,
        shift: 0.0,
        worst: (map.stone_of(zi), zi % 3, r),
        changed,
    }
}

/// The contacts of `ev` that entered or flipped between stick and slip, then those that left,
/// against the previous set `a` `(i, j, sticks)`.
fn changed_contacts(a: &[(usize, usize, bool)], ev: &Evaluation) -> Vec<Change> {
    let ma: BTreeMap<(usize, usize), bool> = a.iter().map(|&(i, j, s)| ((i, j), s)).collect();
    let mut out = Vec::new();
    for c in &ev.contacts {
        let what = match ma.get(&(c.i, c.j)) {
            None => "enter",
            Some(&s) if s != c.sticks() => {
                if c.sticks() {
                    "stick"
                } else {
                    "slip"
                }
            }
            _ => continue,
        };
        let f_n = c.contact.f_n;
        out.push(Change {
            pair: (c.i, c.j),
            what,
            f_n,
            ratio: if f_n > 0.0 { c.friction.f_t.abs() / f_n } else { 0.0 },
        });
    }
    let now: BTreeSet<(usize, usize)> = ev.contacts.iter().map(|c| (c.i, c.j)).collect();
    for k in ma.keys().filter(|k| !now.contains(k)) {
        out.push(Change { pair: *k, what: "leave", f_n: 0.0, ratio: 0.0 });
    }
    out
}
