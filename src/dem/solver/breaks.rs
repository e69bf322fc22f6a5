//! Beam breaks: where along a load step the first intact beam reaches its failure index, which
//! beam is the most critical at a state, and the break itself with the quasi-static release of
//! the beam's force (paper §2.1, "Solution algorithm", steps 2–4).
//!
//! ```text
//!   λ* = min over intact beams of  failure_lambda(z_old → z)       (P piecewise linear in λ)
//!                                  crushing_lambda(z_old → z)      (P_c = −Ē ε/σ_c, with crushing)
//!   after a break: while some intact beam has max(P, P_c) ≥ 1, break the largest and relax
//! ```
//!
//! **Several breaks per equilibrium (opt-in, approximate).** With
//! [`super::SolverOptions::breaks_per_equilibrium`] `= n > 1`, a cascade breaks the `n` most
//! critical beams with `P ≥ 1` at once and re-equilibrates once, instead of breaking the most
//! critical one and re-equilibrating before the next. A load step still stops at the first beam
//! to reach `P = 1` (no beam breaks before it is overloaded at an equilibrium: a window of
//! several first crossings along the step, broken together at the load of the last, raised the
//! paper wall's tensile peak by 6.5 % on average at `n = 4`). What is lost is the order inside a
//! cascade: a beam that the release of a more critical one would have unloaded breaks anyway.
//! `n = 1` is paper §2.1's algorithm, bit for bit.

use std::time::Instant;

use super::error::DemError;
use super::options::FloatingPolicy;
use super::phases::Phase;
use super::profile;
use super::records::{BrokenBeam, FailureModeTag, LoadPoint, StateKind};
use super::solver::Solver;
use crate::dem::mechanics::{failure_index, failure_lambda, failure_mode, FailureMode};

impl<'a> Solver<'a> {
    /// The crushing index `P_c = −Ē ε/σ_c` of beam `b` at `z` (−∞ without crushing).
    fn crushing_index(&self, b: usize, z: &[f64]) -> f64 {
        let Some(c) = &self.model.params.crushing else { return f64::NEG_INFINITY };
        let (qi, qj) = self.model.beam_dofs(b, z);
        let g = &self.model.geoms[b];
        c.beam_index(self.model.params.e_bar, g.delta_n(qi, qj) / g.ell)
    }

    /// The smallest crushing fraction of beam `b` along `z_old → z` (`None` without crushing).
    fn crushing_lambda(&self, b: usize, z_old: &[f64]) -> Option<f64> {
        let c = self.model.params.crushing.as_ref()?;
        let g = &self.model.geoms[b];
        let (q0i, q0j) = self.model.beam_dofs(b, z_old);
        let (q1i, q1j) = self.model.beam_dofs(b, &self.state.z);
        let (e0, e1) = (g.delta_n(q0i, q0j) / g.ell, g.delta_n(q1i, q1j) / g.ell);
        c.beam_lambda(self.model.params.e_bar, e0, e1 - e0)
    }

    /// The beam that reaches its failure index first along `z_old → z`, inside the step
    /// (`λ < 1`), with its `λ` (ties by beam index). One beam even with
    /// [`super::SolverOptions::breaks_per_equilibrium`] `> 1`: no beam breaks before it reaches
    /// `P = 1` (module docs).
    pub(super) fn first_failure(&mut self, z_old: &[f64]) -> Option<(f64, usize)> {
        let clock = Instant::now();
        let first = self.scan_first_failures(z_old, 1);
        profile::add(&mut self.profile.failure_seconds, clock.elapsed());
        self.profile.failure_scans += 1;
        first.first().copied()
    }

    fn scan_first_failures(&self, z_old: &[f64], n: usize) -> Vec<(f64, usize)> {
        // The n smallest (λ, b) with λ < 1, sorted; kept small by insertion.
        let mut first: Vec<(f64, usize)> = Vec::with_capacity(n + 1);
        let intact = &self.state.intact;
        for b in (0..intact.len()).filter(|&b| intact[b]) {
            let (q0i, q0j) = self.model.beam_dofs(b, z_old);
            let (q1i, q1j) = self.model.beam_dofs(b, &self.state.z);
            let d = |a: [f64; 3], c: [f64; 3]| [a[0] - c[0], a[1] - c[1], a[2] - c[2]];
            let lambdas = [
                failure_lambda(&self.model.geoms[b], &self.model.thresholds, q0i, q0j, d(q1i, q0i), d(q1j, q0j)),
                self.crushing_lambda(b, z_old),
            ];
            let Some(l) = lambdas.into_iter().flatten().reduce(f64::min) else { continue };
            if l >= 1.0 || (first.len() == n && l >= first[n - 1].0) {
                continue;
            }
            let at = first.partition_point(|&(fl, _)| fl <= l);
            first.insert(at, (l, b));
            first.truncate(n);
        }
        first
    }

    /// The intact beams with `P ≥ 1` at the current state, the most critical first (ties by
    /// beam index): at most [`super::SolverOptions::breaks_per_equilibrium`] of them.
    pub(super) fn most_critical(&mut self) -> Vec<usize> {
        let clock = Instant::now();
        let b = self.scan_most_critical(self.opts.breaks_per_equilibrium.max(1));
        profile::add(&mut self.profile.failure_seconds, clock.elapsed());
        self.profile.failure_scans += 1;
        b
    }

    fn scan_most_critical(&self, n: usize) -> Vec<usize> {
        // The n largest (P, b) with P ≥ 1, by decreasing P.
        let mut worst: Vec<(f64, usize)> = Vec::with_capacity(n + 1);
        let (z, intact) = (&self.state.z, &self.state.intact);
        for b in (0..intact.len()).filter(|&b| intact[b]) {
            let (qi, qj) = self.model.beam_dofs(b, z);
            let p = failure_index(&self.model.geoms[b], &self.model.thresholds, qi, qj).max(self.crushing_index(b, z));
            if p < 1.0 || (worst.len() == n && p <= worst[n - 1].0) {
                continue;
            }
            let at = worst.partition_point(|&(wp, _)| wp >= p);
            worst.insert(at, (p, b));
            worst.truncate(n);
        }
        worst.into_iter().map(|(_, b)| b).collect()
    }

    /// Breaks beam `b` now (e.g. a pre-cracked sample), re-equilibrates at the current load and
    /// records the state.
    pub fn break_and_relax(&mut self, b: usize) -> Result<(), DemError> {
        if b >= self.state.intact.len() || !self.state.intact[b] {
            return Err(DemError::InvalidParameter {
                field: "beam",
                value: b.to_string(),
                expected: "the index of an intact beam",
            });
        }
        let l = self.state.load.clone();
        self.phase = Phase::Release;
        self.release(&[b], &l, 1.0)
    }

    /// Breaks the beams `first` (none: the most critical ones), then the beams with `P ≥ 1`,
    /// each group released and relaxed at the fixed `load` ([`Self::release`]): one beam at a
    /// time, or up to [`super::SolverOptions::breaks_per_equilibrium`] together.
    pub(super) fn break_cascade(&mut self, first: Vec<usize>, load: &LoadPoint, t: f64) -> Result<(), DemError> {
        self.phase = if first.is_empty() { Phase::Cascade } else { Phase::Release };
        let mut next = if first.is_empty() { self.most_critical() } else { first };
        while !next.is_empty() {
            self.release(&next, load, t)?;
            self.phase = Phase::Cascade;
            next = self.most_critical();
        }
        Ok(())
    }

    /// Breaks the beams `beams` at the committed state and re-equilibrates at the fixed `load`,
    /// then records the relaxed state.
    ///
    /// **Release path.** The beams' forces at the committed state, `f_b`, are released along
    /// `f_extra(s) = (1 − s) f_b`, `s: 0 → 1`: at `s = 0` the committed state is in equilibrium,
    /// at `s = 1` the beams are gone. One step `s = 1` first; if Newton fails, the release is cut
    /// back (halved, at most `max_cutbacks` times), each intermediate equilibrium committed
    /// (friction history) but not recorded. This is the quasi-static path a dynamic release
    /// would follow with heavy damping, and it lets the contact and stick/slip sets change
    /// gradually when a break redistributes much load.
    fn release(&mut self, beams: &[usize], load: &LoadPoint, t: f64) -> Result<(), DemError> {
        let mut f_b = vec![0.0; self.model.map.n_z];
        for &b in beams {
            self.model.add_beam_force(b, &self.state.z, &mut f_b);
        }
        for &b in beams {
            self.break_beam(b)?;
        }
        let (mut s, mut h) = (0.0f64, 1.0f64);
        let h_min = 0.5f64.powi(self.opts.max_cutbacks as i32);
        while s < 1.0 {
            let s_try = (s + h).min(1.0);
            let extra: Vec<f64> = f_b.iter().map(|f| (1.0 - s_try) * f).collect();
            match self.equilibrate_with(load, Some(&extra), t) {
                Ok(()) => {
                    s = s_try;
                    if s < 1.0 {
                        self.state.accept();
                    }
                    h = (2.0 * h).min(1.0);
                }
                Err(e @ DemError::NoConvergence { .. }) => {
                    self.state.restore();
                    h *= 0.5;
                    self.counters.cutbacks += 1;
                    if h < h_min {
                        // No equilibrium near the path: the full release by pseudo-transient
                        // continuation from the last intermediate state.
                        if !self.opts.continuation {
                            return Err(e);
                        }
                        if self.continuation(load, None, t).is_err() {
                            self.state.restore();
                            return Err(e);
                        }
                        s = 1.0;
                    }
                }
                Err(e) => return Err(e),
            }
        }
        self.commit(t, StateKind::Relaxed);
        Ok(())
    }

    /// Breaks beam `b` at the committed state: its mode, its energy moved from the stored to the
    /// fracture account, its term subtracted from the operator; a stone left with no bond and no
    /// contact is reported (or an error, [`FloatingPolicy::Error`]).
    fn break_beam(&mut self, b: usize) -> Result<(), DemError> {
        let z = &self.state.z;
        let (qi, qj) = self.model.beam_dofs(b, z);
        let crushing = self.crushing_index(b, z);
        let (geom, thresholds) = (&self.model.geoms[b], &self.model.thresholds);
        let mode = match failure_mode(geom, thresholds, qi, qj) {
            _ if crushing >= 1.0 - 1e-9 && crushing >= failure_index(geom, thresholds, qi, qj) => {
                FailureModeTag::Crushing
            }
            FailureMode::Tension => FailureModeTag::Tension,
            FailureMode::Shear => FailureModeTag::Shear,
        };
        let energy = self.model.beam_energy(b, z);
        let st = &mut self.state;
        st.energy.fracture += energy;
        // The previous state's stored energy included this beam: move it to the fracture account
        // so the relaxation term measures only what the re-equilibration releases.
        if let Some(last) = st.records.last_mut() {
            last.stored -= energy;
            last.dissipated[0] += energy;
        }
        st.intact[b] = false;
        st.broken.push(BrokenBeam { beam: b, mode, state: st.records.len().saturating_sub(1), energy });
        if st.broken.len() > self.opts.max_events {
            return Err(DemError::TooManyEvents { max_events: self.opts.max_events });
        }
        let term = self.model.terms[b].clone();
        let (op, mut u, _) = self.operator_upkeep();
        op.add_low_rank(&mut u, &term, -1.0)?;
        self.flag_floating(b)
    }

    /// Reports the stones of beam `b` that kept no bond and no contact (module docs of
    /// [`super::stage`], "Regularization").
    fn flag_floating(&mut self, b: usize) -> Result<(), DemError> {
        let beam = &self.model.sample.beams[b];
        for p in [beam.i, beam.j] {
            if self.model.map.is_slave(p) {
                continue;
            }
            let st = &mut self.state;
            let bonded = self.model.sample.neighbours[p].iter().any(|&(_, k)| st.intact[k]);
            let touching = st.contacts.iter().any(|a| a.i == p || a.j == p);
            if !bonded && !touching {
                if self.opts.floating == FloatingPolicy::Error {
                    return Err(DemError::FreeFloating { particle: p, event: st.broken.len() });
                }
                st.floating.push((p, st.broken.len()));
                self.operator.invalidate(None); // avoid an ill-conditioned Woodbury correction
            }
        }
        Ok(())
    }
}
