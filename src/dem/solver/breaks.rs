//! Beam breaks: where along a load step the first intact beam reaches its failure index, which
//! beam is the most critical at a state, and the break itself with the quasi-static release of
//! the beam's force (SPEC §1, "Solution algorithm", steps 2–4).
//!
//! ```text
//!   λ* = min over intact beams of  failure_lambda(z_old → z)       (P piecewise linear in λ)
//!                                  crushing_lambda(z_old → z)      (P_c = −Ē ε/σ_c, with crushing)
//!   after a break: while some intact beam has max(P, P_c) ≥ 1, break the largest and relax
//! ```
use std::time::Instant;

use super::error::DemError;
use super::options::FloatingPolicy;
use super::profile;
use super::records::{BrokenBeam, FailureModeTag, LoadPoint, StateKind};
use super::solver::Solver;
use super::system::Model;
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

    /// The smallest failure fraction along `z_old → z` and its beam.
    pub(super) fn first_failure(&mut self, z_old: &[f64]) -> Option<(f64, usize)> {
        let clock = Instant::now();
        let best = self.scan_first_failure(z_old);
        profile::add(&mut self.profile.failure_seconds, clock.elapsed());
        best
    }

    fn scan_first_failure(&self, z_old: &[f64]) -> Option<(f64, usize)> {
        let mut best: Option<(f64, usize)> = None;
        let intact = &self.state.intact;
        for b in (0..intact.len()).filter(|&b| intact[b]) {
            let (q0i, q0j) = self.model.beam_dofs(b, z_old);
            let (q1i, q1j) = self.model.beam_dofs(b, &self.state.z);
            let d = |a: [f64; 3], c: [f64; 3]| [a[0] - c[0], a[1] - c[1], a[2] - c[2]];
            let lambdas = [
                failure_lambda(&self.model.geoms[b], &self.model.thresholds, q0i, q0j, d(q1i, q0i), d(q1j, q0j)),
                self.crushing_lambda(b, z_old),
            ];
            for l in lambdas.into_iter().flatten() {
                if best.is_none_or(|(bl, _)| l < bl) {
                    best = Some((l, b));
                }
            }
        }
        best
    }

    /// The intact beam with the largest `P ≥ 1` at the current state.
    pub(super) fn most_critical(&mut self) -> Option<usize> {
        let clock = Instant::now();
        let b = self.scan_most_critical();
        profile::add(&mut self.profile.failure_seconds, clock.elapsed());
        b
    }

    fn scan_most_critical(&self) -> Option<usize> {
        let mut best: Option<(f64, usize)> = None;
        let (z, intact) = (&self.state.z, &self.state.intact);
        for b in (0..intact.len()).filter(|&b| intact[b]) {
            let (qi, qj) = self.model.beam_dofs(b, z);
            let p = failure_index(&self.model.geoms[b], &self.model.thresholds, qi, qj).max(self.crushing_index(b, z));
            if p >= 1.0 && best.is_none_or(|(bp, _)| p > bp) {
                best = Some((p, b));
            }
        }
        best.map(|(_, b)| b)
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
        self.release(b, &l, 1.0)
    }

    /// Breaks beam `b`, then every beam with `P ≥ 1` one at a time, each released and relaxed at
    /// the fixed `load` ([`Self::release`]).
    pub(super) fn break_cascade(&mut self, b: Option<usize>, load: &LoadPoint, t: f64) -> Result<(), DemError> {
        let mut next = b.or_else(|| self.most_critical());
        while let Some(bb) = next {
            self.release(bb, load, t)?;
            next = self.most_critical();
        }
        Ok(())
    }

    /// Breaks beam `b` at the committed state and re-equilibrates at the fixed `load`, then
    /// records the relaxed state.
    ///
    /// **Release path.** The beam's force at the committed state, `f_b`, is released along
    /// `f_extra(s) = (1 − s) f_b`, `s: 0 → 1`: at `s = 0` the committed state is in equilibrium,
    /// at `s = 1` the beam is gone. One step `s = 1` first; if Newton fails, the release is cut
    /// back (halved, at most `max_cutbacks` times), each intermediate equilibrium committed
    /// (friction history) but not recorded. This is the quasi-static path a dynamic release
    /// would follow with heavy damping, and it lets the contact and stick/slip sets change
    /// gradually when a break redistributes much load.
    fn release(&mut self, b: usize, load: &LoadPoint, t: f64) -> Result<(), DemError> {
        let term = &self.model.terms[b];
        let fb = term.k * Model::gather(&term.idx, &self.state.z);
        let mut f_b = vec![0.0; self.model.map.n_z];
        for a in 0..6 {
            f_b[term.idx[a]] += fb[a];
        }
        self.break_beam(b)?;
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
