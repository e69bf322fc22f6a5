//! Equilibrium at a fixed load: Newton's method on the contact–friction problem (paper §2.1,
//! "Solution algorithm", step 2).
//!
//! ```text
//!   r(z) = f_ext + f_extra − f_int(z) − ε (z − z_commit)      (unknown rows)
//!   repeat:
//!     contacts and friction at z: overlap, F_n, return map from the committed F_t
//!     ‖r‖∞ ≤ tol · scale  → converged
//!     K_T Δz = r           (consistent tangent, GMRES preconditioned by the factorized
//!                           symmetric part M, its products v + D M⁻¹v with D = K_T − M the
//!                           contacts' part only; one direct solve when no contact is active;
//!                           a sparse LU of the assembled K_T when GMRES misses its tolerance)
//!     Δz capped: no stone moves more than `max_move` (translation, or rotation × D̄) per iteration
//!     no contact at z, at z + Δz nor at the committed state, Δz not capped: z + Δz is the
//!                  equilibrium (the linear phase, [`super::linear`]: no confirming residual)
//!     line search: z + α Δz, α = 1, ½, ¼ … (6 tries) until the merit ½‖r‖² decreases by
//!                  the Armijo factor (1 − 10⁻⁴ α); otherwise the trial with the smallest merit
//! ```
//!
//! `f_int` holds the intact beams (linear) and the contacts (overlap area, Coulomb return map
//! from the last committed state: path dependence enters only through `F_t,commit`, `z_commit`).
//! The residual is measured with the same contact evaluation the next iteration uses, so
//! "converged" means the state *is* in equilibrium with its own contact and stick/slip set.
//! Along a line search the beams' forces are `K_b z₀ + α K_b Δz` (one product per search; the
//! beam law is linear, so these are the forces at `z₀ + α Δz` to round-off).
//!
//! The merit function weighs the moment rows by `1/D̄` (D̄ = mean stone diameter), so forces and
//! moments count in the same unit. The scale of the convergence test is the largest internal or
//! external generalized force at the state, and at least
//!
//! - `10⁻⁹ Ē t_z W`;
//! - a tenth of the largest platen force of the test so far (the load level of the test: at a
//!   cyclic reversal the current forces pass through zero, where a scale taken from them alone
//!   would ask for an absolute equilibrium far below anything the test resolves, the role of
//!   the time-averaged force in Abaqus' criterion);
//! - `f_ε / tol`, with
//!
//! ```text
//!   f_ε = 64 ε_mach · X · Ē t_z        (X: the largest vertex coordinate of the sample)
//! ```
//!
//! the round-off of the contact law: overlaps are clipped from absolute vertex coordinates, so a
//! contact's force carries an error of a few `ε_mach X` times its stiffness `Ē t_z L/ℓ_c ≈ Ē t_z`
//! (about 10⁻⁶ N for a 1 m wall of Ē = 2.5 GPa; `f_ε` ≈ 6.6·10⁻⁵ N). Near a load reversal the
//! forces in a cracked wall fall to a few newtons, where `tol · scale` would ask the residual to
//! go below that noise and Newton's method stalls at it; the floor accepts a residual at the
//! level of round-off instead. Under load (`scale` above `f_ε / tol`, a few kN) it never binds.
//!
//! **When GMRES misses its tolerance.** Where stones have lost every beam and are held by many
//! sliding contacts, `K_T` is far from `M` (the slip coupling is non-symmetric and the sliding
//! directions have almost no stiffness) and GMRES(60) can stall after its 240 products. Newton's
//! method driven by such an unconverged direction stalls too: on a calibration point of
//! `identify-wall.toml` (seed 8, 45 loose stones, 24 sliding contacts) it stopped at a relative
//! residual of 2·10⁻⁸ against a tolerance of 10⁻⁸ at every increment, so every load step fell
//! back to the continuation at the smallest increment and the test crawled on for hours. The
//! step is then solved directly instead, by a sparse LU of the assembled tangent with row
//! pivoting ([`Tangent::solve_direct`]; a fresh analysis and factorization each time, so only
//! where GMRES failed, counted in `SolverProfile::direct_solves`): the same sample ends by loss
//! of load in 20 s.
//!
//! **Where the tolerance meets the stones' chatter.** The test is on the largest residual of
//! any stone against the sample's force scale, so a large sample asks the same absolute
//! equilibrium of its loosest stone as of its loaded ones. In the post-peak cascade of a
//! 50k-stone sample in tension (1 m², stones of 4.5 mm, scale 1.7·10⁴ N) the crack holds stones
//! that touch their neighbours with `F_n` of 10⁻⁴–10⁻³ N (10⁻⁷ of the load, 2–20 `f_ε`). Their
//! contacts flip between stick and slip from one Newton iteration to the next (about 15 of 300
//! per iteration, moves of 10⁻¹³ m), and the largest residual, 0.3–1.4 mN at such a stone, cycles
//! at 2–8·10⁻⁸ of the scale: neither Newton's method nor the continuation goes below it, with
//! converged GMRES steps. The trace ([`super::trace`]) names the stone of the largest residual
//! and the contacts that changed. `SolverOptions::tol` is the user's choice: at 10⁻⁷ the same
//! sample runs to loss of load (543 breaks, no continuation), and a 10k sample's tension test
//! gives the same breaks at the same states as at 10⁻⁸, its stresses within 4·10⁻⁹ of the peak.
//!
//! If the iterations do not converge in `max_iterations`, [`DemError::NoConvergence`] is returned
//! with the stones that have no intact beam left (the usual cause: a stone held only by contacts
//! that slide, or by nothing): the caller cuts the load increment back.
use std::collections::BTreeMap;

use super::contact_set::{self, ActiveContact};
use super::error::DemError;
use super::gmres::{gmres_split, ForcingSequence};
use super::operator::Refactor;
use super::profile;
use super::records::LoadPoint;
use super::solver::Solver;
use super::tangent::Tangent;
use super::trace::NewtonStep;
use std::time::Instant;

/// The floor of the convergence scale relative to the largest platen force of the test so far
/// (module docs).
const REFERENCE_FRACTION: f64 = 0.1;

/// Residual entries below this fraction of the tolerance (`tol · scale`) are left out of a
/// sparse right-hand side ([`super::factor`], "Sparse right-hand sides"): the state the step
/// reaches keeps them as its residual, `10⁻⁵` of what convergence allows.
///
/// A release's residual is the broken beam's force on 6 unknowns (`10⁻⁸–10⁻² · scale`) over the
/// previous solves' round-off, which on a 10k-stone lattice lies between `10⁻¹⁶` and `10⁻¹²` of
/// the scale on thousands of unknowns (absolute displacements times stiffnesses). The lower
/// the threshold, the more of that tail is solved for; the higher, the more of it stays as
/// residual, which the lattice's conditioning turns into stresses off by more. Measured over
/// 1,500 contact-free breaks of the 10k sample (`examples/dem_profile.rs`), against dense solves
/// (with CHOLMOD's own sparse solve, `cholmod_solve2` with `Bset`, which visits the same columns
/// as [`super::cholmod::UpdatableCholesky::solve_sparse`] but spent 0.44 ms per solve finding
/// them):
///
/// | drop      | sparse solves | columns visited | stress difference / peak | same breaks |
/// |-----------|---------------|-----------------|--------------------------|-------------|
/// | `10⁻⁶`    | 1,113 of 2,098 | 31 %           | (not measured)           |             |
/// | `10⁻⁵`    | 1,672          | 16 %           | 8.5·10⁻¹⁰                | yes         |
/// | `3·10⁻⁵`  | 1,860          | 13 %           | 3.4·10⁻⁹                 | yes         |
/// | `10⁻⁴`    | 2,028          | 14 %           | 1.5·10⁻⁸                 | yes         |
///
/// `10⁻⁵` solves within 3 % of `10⁻⁴`'s time and keeps the curve ten times closer.
const SPARSE_RHS_DROP: f64 = 1e-5;

/// A right-hand side is solved as sparse when at most `1/SPARSE_RHS_FEW` of its entries are
/// kept. Beyond that the reach is most of `L`: on the 10k sample without this limit every
/// solve was sparse and visited 39 % of the columns on average, no faster within the noise
/// (10.5–11.3 against 10.8–11.3 ms per break), and the curve moved by `1.3·10⁻⁹` of the peak
/// instead of `8.5·10⁻¹⁰`.
const SPARSE_RHS_FEW: usize = 8;

/// A residual evaluation.
pub(super) struct Evaluation {
    /// Contacts at the state.
    pub contacts: Vec<ActiveContact>,
    /// Residual on the equations.
    pub r: Vec<f64>,
    /// `‖r‖∞ / scale`.
    pub relative: f64,
    /// `½ Σ (w_e r_e)²`, `w = 1` on force rows, `1/D̄` on moment rows.
    pub merit: f64,
    /// The intact beams' internal forces `K_b z` at the state (over `z`).
    pub beam_forces: Vec<f64>,
}

impl<'a> Solver<'a> {
    /// The residual at `z` for the external forces `f_ext` (over `z`).
    pub(super) fn evaluate(&mut self, z: &[f64], f_ext: &[f64]) -> Result<Evaluation, DemError> {
        let clock = Instant::now();
        let mut beam_forces = vec![0.0; self.model.map.n_z];
        self.model.add_beam_forces(&self.state.intact, z, &mut beam_forces);
        profile::add(&mut self.profile.evaluate_seconds, clock.elapsed());
        self.evaluate_with_beams(z, f_ext, beam_forces)
    }

    /// [`Self::evaluate`] with the beams' forces at `z` given (e.g. `K_b (z₀ + α Δz)` as
    /// `K_b z₀ + α K_b Δz` along a line search: the beam law is linear).
    fn evaluate_with_beams(&mut self, z: &[f64], f_ext: &[f64], beam_forces: Vec<f64>) -> Result<Evaluation, DemError> {
        let clock = Instant::now();
        let pairs = if self.opts.contacts && !self.state.broken.is_empty() {
            self.candidates.candidates(self.model.sample, &self.model.map, z, &self.state.intact)
        } else {
            Vec::new()
        };
        self.profile.pair_evaluations += pairs.len();
        self.profile.candidate_rebuilds = self.candidates.rebuilds;
        let ev = self.evaluate_at(z, f_ext, &pairs, beam_forces);
        if let Ok(e) = &ev {
            if !pairs.is_empty() {
                let touching: Vec<(usize, usize)> = e.contacts.iter().map(|a| (a.i, a.j)).collect();
                self.candidates.refresh_apart(self.model.sample, &self.model.map, z, &touching);
            }
        }
        self.profile.evaluations += 1;
        profile::add(&mut self.profile.evaluate_seconds, clock.elapsed());
        ev
    }

    /// Raises the reference force of the convergence scale (module docs) to a tenth of the
    /// platen forces `pf` of a recorded state.
    pub(super) fn raise_reference_force(&mut self, pf: &[[f64; 3]; 2]) {
        for f in pf {
            self.state.reference_force =
                self.state.reference_force.max(REFERENCE_FRACTION * f[0].abs().max(f[1].abs()));
        }
    }

    /// The residual at `z` with the contact law evaluated on the candidate `pairs`
    /// ([`super::contact_candidates`]).
    pub(super) fn evaluate_at(
        &self,
        z: &[f64],
        f_ext: &[f64],
        pairs: &[(usize, usize)],
        beam_forces: Vec<f64>,
    ) -> Result<Evaluation, DemError> {
        let contacts = contact_set::evaluate(
            self.model.sample,
            &self.model.map,
            &self.model.params,
            pairs,
            z,
            &self.state.z_commit,
            &self.state.histories,
        )?;
        let mut f = beam_forces.clone();
        contact_set::add_contact_forces(&self.model.map, &contacts, &mut f);
        let map = &self.model.map;
        let mut r = vec![0.0; map.n_eq()];
        let mut scale = (1e-9 * self.model.params.e_bar * self.model.params.t_z * self.model.sample.width)
            .max(self.scales.roundoff_force / self.opts.tol)
            .max(self.state.reference_force);
        for v in f.iter().chain(f_ext.iter()) {
            scale = scale.max(v.abs());
        }
        let (mut inf, mut merit) = (0.0f64, 0.0);
        for (e, &zi) in map.unknowns.iter().enumerate() {
            r[e] = f_ext[zi] - f[zi] - self.scales.reg[e] * (z[zi] - self.state.z_commit[zi]);
            inf = inf.max(r[e].abs());
            let w = if zi % 3 == 2 { 1.0 / self.scales.mean_diameter } else { 1.0 };
            merit += 0.5 * (w * r[e]).powi(2);
        }
        Ok(Evaluation { contacts, r, relative: inf / scale, merit, beam_forces })
    }

    /// Newton's method for [`Self::equilibrate_with`] (module docs).
    pub(super) fn newton(&mut self, load: &LoadPoint, extra: Option<&[f64]>, t: f64) -> Result<(), DemError> {
        let f_ext = self.apply_load(load, extra);
        let (stage, events) = (self.state.stage, self.state.broken.len());
        let z0 = self.state.z.clone();
        let mut ev = self.evaluate(&z0, &f_ext)?;
        let mut forcing = ForcingSequence::new(self.opts.forcing);
        if let Some(tr) = self.trace.as_mut() {
            tr.begin(stage, t, events, if extra.is_some() { "release" } else { "load" });
        }
        let mut previous: Option<Vec<(usize, usize, bool)>> = None;
        for iteration in 0..self.opts.max_iterations {
            self.jacobians.fresh_only = iteration >= super::tangent::FRESH_AFTER;
            if ev.relative <= self.opts.tol {
                break;
            }
            let mut step = self.trace.as_ref().map(|_| newton_step(&ev, &mut previous, &self.model.map));
            self.profile.newton_iterations += 1;
            {
                let (op, mut u, _) = self.operator_upkeep();
                op.sync(&mut u, &ev.contacts)?;
            }
            self.refresh_operator()?;
            let factor = &self.operator.factor;
            self.profile.max_rank = self.profile.max_rank.max(factor.rank());
            self.profile.columns_added = factor.n_columns;
            self.profile.columns_dropped = factor.n_dropped;
            // The linear solve's tolerance (Eisenstat–Walker by default; the goal: ‖r‖∞ at
            // convergence, tol · scale = tol ‖r‖∞ / relative).
            let r2 = ev.r.iter().map(|x| x * x).sum::<f64>().sqrt();
            let r_inf = ev.r.iter().fold(0.0f64, |m, x| m.max(x.abs()));
            let eta = forcing.next(r2, if ev.relative > 0.0 { self.opts.tol * r_inf / ev.relative } else { 0.0 });
            if factor.rank() > 0 && !factor.is_accurate() {
                // A near-singular Woodbury capacitance matrix: drop the correction.
                let (op, mut u, scales) = self.operator_upkeep();
                op.refactorize(&mut u, Some(Refactor::Accuracy), &scales.reg)?;
            }
            let mut dz = self.newton_direction(&ev, eta, step.as_mut())?;
            let cap = self.cap_step(&mut dz);
            if iteration == 0 && cap == 1.0 && ev.contacts.is_empty() && self.linear_step(&dz)? {
                // The linear phase: the step is the equilibrium ([`super::linear`]); its
                // residual is not evaluated (NaN in the trace).
                if let (Some(tr), Some(st)) = (self.trace.as_mut(), step) {
                    tr.step(st);
                    tr.end(f64::NAN, true);
                }
                self.state.contacts = Vec::new();
                return Ok(());
            }
            let alpha;
            (ev, alpha) = self.line_search(&dz, &f_ext, ev)?;
            if let (Some(tr), Some(mut st)) = (self.trace.as_mut(), step) {
                st.cap = cap;
                st.alpha = alpha;
                tr.step(st);
            }
        }
        let converged = ev.relative <= self.opts.tol;
        if let Some(tr) = self.trace.as_mut() {
            tr.end(ev.relative, converged);
        }
        if converged {
            self.state.contacts = ev.contacts;
            return Ok(());
        }
        Err(DemError::NoConvergence {
            stage,
            load: t,
            event: events,
            iterations: self.opts.max_iterations,
            residual: ev.relative,
            unbonded: self.unbonded_stones(),
        })
    }

    /// Puts the prescribed platen values of `load` into `z` and returns the external forces
    /// (over `z`): `load`'s forces plus `extra`.
    pub(super) fn apply_load(&mut self, load: &LoadPoint, extra: Option<&[f64]>) -> Vec<f64> {
        let map = &self.model.map;
        for (k, &zi) in map.prescribed.iter().enumerate() {
            self.state.z[zi] = load.prescribed[k];
        }
        let mut f_ext = extra.map_or_else(|| vec![0.0; map.n_z], |x| x.to_vec());
        for (k, &zi) in map.forced.iter().enumerate() {
            f_ext[zi] += load.forces[k];
        }
        f_ext
    }

    /// Newton's direction `K_T Δz = r` at the evaluation `ev`: one solve with the factorized
    /// operator when no contact is active (then `K_T = M`); else GMRES to the relative tolerance
    /// `eta`, preconditioned by `M`, with a direct sparse LU of `K_T` where GMRES misses it
    /// (module docs). The trace's `step` gets the GMRES figures.
    fn newton_direction(
        &mut self,
        ev: &Evaluation,
        eta: f64,
        step: Option<&mut NewtonStep>,
    ) -> Result<Vec<f64>, DemError> {
        let events = self.state.broken.len();
        let fail = |e: super::factor::FactorError| DemError::Factorization { event: events, reason: e.0 };
        let mut dz = ev.r.clone();
        if ev.contacts.is_empty() {
            let clock = Instant::now();
            let support = self.sparse_support(ev);
            let sparse = match &support {
                Some(s) => self.operator.factor.solve_sparse(&mut dz, s).map_err(fail)?,
                None => None,
            };
            match sparse {
                Some(columns) => {
                    self.profile.sparse_solves += 1;
                    self.profile.sparse_columns += columns;
                }
                None => self.operator.factor.solve(&mut dz).map_err(fail)?,
            }
            self.counters.solves += 1;
            profile::add(&mut self.profile.solve_seconds, clock.elapsed());
            return Ok(dz);
        }
        let clock = Instant::now();
        let tangent = Tangent::new(&self.model, &self.state, &self.scales.reg, &ev.contacts, &mut self.jacobians)?;
        let jc = &self.jacobians;
        let p = &mut self.profile;
        (p.jacobians_computed, p.jacobians_reused) = (jc.computed, jc.reused);
        p.jacobians_on_cone = jc.on_cone;
        // Inexact Newton: the linear solve to η ‖r‖ (`SolverOptions::forcing`; a fixed 1e-6 lost
        // two of the paper wall's 16 shear samples, a fixed 1e-8 was the former default).
        // D = K_T − M: GMRES's products cost O(contacts) (`gmres_split`).
        let op = &mut self.operator;
        let difference = tangent.difference(&ev.contacts, |i, j| op.held(i, j));
        profile::add(&mut p.tangent_seconds, clock.elapsed());
        let clock = Instant::now();
        let factor = &mut op.factor;
        let mut in_precond = std::time::Duration::ZERO;
        dz.iter_mut().for_each(|x| *x = 0.0);
        let info = gmres_split(
            &mut dz,
            &ev.r,
            |v, o| tangent.apply(v, o),
            |v, o| difference.apply(v, o),
            |v| {
                let c = Instant::now();
                let r = factor.solve(v);
                in_precond += c.elapsed();
                r
            },
            eta,
            60,
            240,
        )
        .map_err(fail)?;
        self.counters.solves += info.iterations;
        p.gmres_solves += 1;
        p.gmres_iterations += info.iterations;
        let sliding = ev.contacts.iter().filter(|a| !a.sticks()).count();
        p.sliding_at_gmres += sliding;
        p.contacts_at_gmres += ev.contacts.len();
        p.phases.gmres_step(sliding, info.iterations);
        profile::add(&mut p.solve_seconds, in_precond);
        profile::add(&mut p.gmres_seconds, clock.elapsed().saturating_sub(in_precond));
        let mut linear_converged = info.converged;
        if !info.converged {
            if op.factor.rank() > 0 {
                // An inaccurate Woodbury correction: start the next iteration afresh.
                op.invalidate(Some(Refactor::Accuracy));
            }
            // GMRES missed its tolerance (a tangent far from the preconditioner's: many sliding
            // contacts around stones with no intact beam): Newton's step by a direct solve of
            // the assembled tangent, so that the iteration is not driven by an unconverged
            // direction.
            let clock = Instant::now();
            if let Some(x) = tangent.solve_direct(&ev.r) {
                dz = x;
                p.direct_solves += 1;
                linear_converged = true;
            }
            profile::add(&mut p.solve_seconds, clock.elapsed());
        }
        if let Some(st) = step {
            st.gmres_iterations = info.iterations;
            st.linear_converged = linear_converged;
        }
        Ok(dz)
    }

    /// The unknowns where the residual of `ev` passes `SPARSE_RHS_DROP · tol · scale`, when
    /// they are few enough (at most `n / SPARSE_RHS_FEW`) for a solve over their reach to pay
    /// ([`super::factor`], "Sparse right-hand sides"); `None`: solve densely.
    ///
    /// **Not with crushing**, like the step predictor ([`super::step_predictor`]): past the
    /// peak, crushing contacts soften and which equilibrium Newton's method finds depends on
    /// differences far below its tolerance. On the paper's wall with crushing
    /// (`crushing_tests.rs`, seed 4, updates in place) the residual the sparse step leaves
    /// (`10⁻¹³` of the scale) turned the loss of load into a collapse at event 78.
    fn sparse_support(&self, ev: &Evaluation) -> Option<Vec<usize>> {
        let crushing = self.model.params.crushing.is_some();
        if !self.opts.sparse_rhs || crushing || !self.operator.factor.updates_in_place() || ev.relative <= 0.0 {
            return None;
        }
        let r_inf = ev.r.iter().fold(0.0f64, |m, x| m.max(x.abs()));
        let drop = SPARSE_RHS_DROP * self.opts.tol * r_inf / ev.relative;
        let few = ev.r.len() / SPARSE_RHS_FEW;
        let mut support = Vec::new();
        for (e, x) in ev.r.iter().enumerate() {
            if x.abs() > drop {
                if support.len() == few {
                    return None;
                }
                support.push(e);
            }
        }
        Some(support)
    }

    /// Scales `dz` so that no stone moves by more than `max_move` in one iteration; returns the
    /// scale applied (1: none).
    pub(super) fn cap_step(&self, dz: &mut [f64]) -> f64 {
        let map = &self.model.map;
        let big = map
            .unknowns
            .iter()
            .zip(dz.iter())
            .map(|(&zi, d)| if zi % 3 == 2 { d.abs() * self.scales.mean_diameter } else { d.abs() })
            .fold(0.0f64, f64::max);
        if big > self.scales.max_move {
            let s = self.scales.max_move / big;
            dz.iter_mut().for_each(|d| *d *= s);
            return s;
        }
        1.0
    }

    /// Backtracking on the merit function along `dz`; moves `self.z` and returns the evaluation
    /// at the accepted point and the step length taken.
    ///
    /// The beams' forces along the line are `K_b z₀ + α K_b Δz` (one product `K_b Δz` per
    /// search, the beam law being linear; the same forces as `K_b z` to round-off).
    fn line_search(&mut self, dz: &[f64], f_ext: &[f64], ev0: Evaluation) -> Result<(Evaluation, f64), DemError> {
        let base = self.state.z.clone();
        let unknowns = self.model.map.unknowns.clone();
        let clock = Instant::now();
        let mut dz_z = vec![0.0; self.model.map.n_z];
        for (e, &zi) in unknowns.iter().enumerate() {
            dz_z[zi] = dz[e];
        }
        let mut k_dz = vec![0.0; self.model.map.n_z];
        self.model.add_beam_forces(&self.state.intact, &dz_z, &mut k_dz);
        profile::add(&mut self.profile.evaluate_seconds, clock.elapsed());
        let mut best: Option<(f64, Evaluation)> = None;
        let mut alpha = 1.0;
        for _ in 0..6 {
            let mut z = base.clone();
            for (e, &zi) in unknowns.iter().enumerate() {
                z[zi] += alpha * dz[e];
            }
            let beams = ev0.beam_forces.iter().zip(&k_dz).map(|(f, k)| f + alpha * k).collect();
            let ev = self.evaluate_with_beams(&z, f_ext, beams)?;
            let accept = ev.merit <= (1.0 - 1e-4 * alpha) * ev0.merit;
            if best.as_ref().is_none_or(|(_, b)| ev.merit < b.merit) {
                best = Some((alpha, ev));
            }
            if accept {
                break;
            }
            alpha *= 0.5;
        }
        match best {
            Some((a, ev)) => {
                for (e, &zi) in unknowns.iter().enumerate() {
                    self.state.z[zi] = base[zi] + a * dz[e];
                }
                Ok((ev, a))
            }
            None => Ok((ev0, 0.0)),
        }
    }

    /// Stones (not bonded to a platen) without any intact beam.
    pub(super) fn unbonded_stones(&self) -> Vec<usize> {
        let s = self.model.sample;
        (0..s.particles.len())
            .filter(|&p| !self.model.map.is_slave(p) && !s.neighbours[p].iter().any(|&(_, b)| self.state.intact[b]))
            .collect()
    }
}

/// The trace's record of a Newton iteration at the evaluation `ev` (the linear solve's and the
/// line search's figures filled in later); `previous` is the contact set of the last one, `map`
/// names the stone of each equation.
pub(super) fn newton_step(
    ev: &Evaluation,
    previous: &mut Option<Vec<(usize, usize, bool)>>,
    map: &super::DofMap,
) -> NewtonStep {
    let mut changed = previous.as_ref().map_or_else(Vec::new, |p| changed_contacts(p, ev));
    let changes = changed.len();
    changed.truncate(super::trace::KEPT_CHANGES);
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
fn changed_contacts(a: &[(usize, usize, bool)], ev: &Evaluation) -> Vec<super::trace::Change> {
    use super::trace::Change;
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
    let now: std::collections::BTreeSet<(usize, usize)> = ev.contacts.iter().map(|c| (c.i, c.j)).collect();
    for k in ma.keys().filter(|k| !now.contains(k)) {
        out.push(Change { pair: *k, what: "leave", f_n: 0.0, ratio: 0.0 });
    }
    out
}
