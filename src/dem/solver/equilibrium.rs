//! Equilibrium at a fixed load: Newton's method on the contact–friction problem (SPEC §1,
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
//! If the iterations do not converge in `max_iterations`, [`DemError::NoConvergence`] is returned
//! with the stones that have no intact beam left (the usual cause: a stone held only by contacts
//! that slide, or by nothing): the caller cuts the load increment back.
use std::collections::BTreeMap;

use super::contact_set::{self, ActiveContact};
use super::error::DemError;
use super::events::Solver;
use super::factor::{SparseColumn, TermId};
use super::gmres::{gmres_split, ForcingSequence};
use super::profile;
use super::system::ZTerm;
use super::tangent::Tangent;
use super::trace::NewtonStep;
use std::time::Instant;

/// The floor of the convergence scale relative to the largest platen force of the test so far
/// (module docs).
const REFERENCE_FRACTION: f64 = 0.1;

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

/// Why the operator is refactorized (counted in [`super::SolverProfile::refactorizations`]).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(super) enum Refactor {
    /// The Woodbury correction has cost more than a factorization (cost model).
    CostModel,
    /// The correction's rank would pass `max_rank`.
    RankCap,
    /// Ill-conditioned capacitance matrix, or GMRES failed with the correction.
    Accuracy,
    /// The pseudo-transient continuation's shifted operator, or the return from it.
    Continuation,
}

impl<'a> Solver<'a> {
    /// Sets the reuse threshold `η` of contact Jacobians ([`super::tangent`]; 0 recomputes every
    /// Jacobian at every Newton iteration). Errors: `η` negative or not finite.
    pub fn set_jacobian_reuse(&mut self, eta: f64) -> Result<(), DemError> {
        if !(eta.is_finite() && eta >= 0.0) {
            return Err(DemError::InvalidParameter {
                field: "jacobian reuse fraction",
                value: eta.to_string(),
                expected: "a finite number >= 0",
            });
        }
        self.jacobians.reuse_fraction = eta;
        Ok(())
    }

    /// Factorizes the current operator (intact beams, the contact terms, `ε`); `cause` is
    /// counted in the profile (`None`: the first factorization, or a floating stone).
    pub(super) fn refactorize(&mut self, cause: Option<Refactor>) -> Result<(), DemError> {
        let diagonal = self.reg.clone();
        self.refactorize_with(cause, &diagonal)
    }

    /// Factorizes the operator with `diagonal` in place of the regularization `ε` (the
    /// pseudo-transient continuation's shifted operator, [`super::continuation`]).
    pub(super) fn refactorize_with(&mut self, cause: Option<Refactor>, diagonal: &[f64]) -> Result<(), DemError> {
        let clock = Instant::now();
        for (&(i, j, _), (t, id)) in self.op_terms.iter_mut() {
            *id = None;
            self.pattern.insert((i, j), t.idx);
        }
        // Every pair in contact once keeps its entries (zeros once the contact is gone), one term
        // per pair in pair order: the same triplets in the same order, the same symbolic
        // analysis (a new pattern costs a fill-reducing ordering, METIS at 10k stones).
        let op = &self.op_terms;
        let extra: Vec<ZTerm> = self
            .pattern
            .iter()
            .map(|(&(i, j), &idx)| {
                let mut k = nalgebra::SMatrix::<f64, 6, 6>::zeros();
                for kind in [0u8, 1] {
                    if let Some((t, _)) = op.get(&(i, j, kind)) {
                        k += t.k;
                    }
                }
                ZTerm { idx, k }
            })
            .collect();
        let t = self.model.assemble(&self.intact, diagonal, &extra);
        self.factor.factorize(&t).map_err(|e| DemError::Factorization { event: self.broken.len(), reason: e.0 })?;
        self.needs_factor = false;
        let r = &mut self.profile.refactorizations;
        match cause {
            Some(Refactor::CostModel) => r.cost_model += 1,
            Some(Refactor::RankCap) => r.rank_cap += 1,
            Some(Refactor::Accuracy) => r.accuracy += 1,
            Some(Refactor::Continuation) => r.continuation += 1,
            None if self.factor.n_factorizations == 1 => r.initial += 1,
            None => r.floating += 1,
        }
        profile::add(&mut self.profile.factor_seconds, clock.elapsed());
        Ok(())
    }

    /// Adds `sign ·` `term` to the operator as a Woodbury term; `None` when the operator is to
    /// be refactorized anyway (then the factorization includes the term).
    pub(super) fn add_low_rank(&mut self, term: &ZTerm, sign: f64) -> Result<Option<TermId>, DemError> {
        if self.needs_factor {
            return Ok(None); // the next factorization will include the current terms
        }
        let cols = self.model.factors(term);
        if self.factor.rank() + cols.len() > self.opts.max_rank {
            self.needs_factor = true;
            self.pending_refactor = Some(Refactor::RankCap);
            return Ok(None);
        }
        let clock = Instant::now();
        let id = self
            .factor
            .add_terms(cols, sign)
            .map_err(|e| DemError::Factorization { event: self.broken.len(), reason: e.0 })?;
        profile::add(&mut self.profile.columns_seconds, clock.elapsed());
        Ok(Some(id))
    }

    /// Brings the operator's contact terms (normal penalty, sticking tangential) in line with
    /// `contacts`: a term that leaves is dropped from the Woodbury correction when it entered
    /// since the last factorization, else subtracted; the new and subtracted terms are added
    /// in one batch. A refactorization is requested instead when the correction would pass
    /// `max_rank`, or when it has cost more than a factorization (the cost model of
    /// [`super::factor`]).
    pub(super) fn sync_operator(&mut self, contacts: &[ActiveContact]) -> Result<(), DemError> {
        let mut want: BTreeMap<(usize, usize, u8), ()> = BTreeMap::new();
        for a in contacts {
            want.insert((a.i, a.j, 0), ());
            if a.sticks() || self.opts.slip_in_preconditioner {
                want.insert((a.i, a.j, 1), ());
            }
        }
        // (key of a new term, or None for a subtraction; columns; sign)
        type TermKey = (usize, usize, u8);
        let mut batch: Vec<(Option<TermKey>, Vec<SparseColumn>, f64)> = Vec::new();
        let gone: Vec<_> = self.op_terms.keys().filter(|k| !want.contains_key(k)).copied().collect();
        for k in gone {
            self.profile.operator_changes[if k.2 == 0 { 1 } else { 3 }] += 1;
            if let Some((t, id)) = self.op_terms.remove(&k) {
                if id.is_some_and(|id| self.factor.remove(id)) || self.needs_factor {
                    continue;
                }
                batch.push((None, self.model.factors(&t), -1.0));
            }
        }
        for a in contacts {
            for (kind, dir, k) in
                [(0u8, a.contact.normal_direction(), a.contact.k_n), (1u8, a.contact.tangential_direction(), a.k_t)]
            {
                let key = (a.i, a.j, kind);
                if want.contains_key(&key) && !self.op_terms.contains_key(&key) {
                    self.profile.operator_changes[if kind == 0 { 0 } else { 2 }] += 1;
                    let t = self.model.rank_one(a.i, a.j, &dir, k);
                    if !self.needs_factor {
                        batch.push((Some(key), self.model.factors(&t), 1.0));
                    }
                    self.op_terms.insert(key, (t, None));
                }
            }
        }
        if self.needs_factor {
            return Ok(()); // the next factorization includes the current terms
        }
        let cols: usize = batch.iter().map(|b| b.1.len()).sum();
        if self.factor.rank() + cols > self.opts.max_rank {
            self.needs_factor = true;
            self.pending_refactor = Some(Refactor::RankCap);
            return Ok(());
        }
        if !batch.is_empty() {
            let clock = Instant::now();
            let keys: Vec<_> = batch.iter().map(|b| b.0).collect();
            let ids = self
                .factor
                .add_batch(batch.into_iter().map(|(_, c, s)| (c, s)).collect())
                .map_err(|e| DemError::Factorization { event: self.broken.len(), reason: e.0 })?;
            for (key, id) in keys.into_iter().zip(ids) {
                if let Some(entry) = key.and_then(|k| self.op_terms.get_mut(&k)) {
                    entry.1 = Some(id);
                }
            }
            profile::add(&mut self.profile.columns_seconds, clock.elapsed());
        }
        if self.factor.wants_refactorization() {
            self.needs_factor = true;
            self.pending_refactor = Some(Refactor::CostModel);
        }
        Ok(())
    }

    /// The residual at `z` for the external forces `f_ext` (over `z`).
    pub(super) fn evaluate(&mut self, z: &[f64], f_ext: &[f64]) -> Result<Evaluation, DemError> {
        let clock = Instant::now();
        let mut beam_forces = vec![0.0; self.model.map.n_z];
        self.model.add_beam_forces(&self.intact, z, &mut beam_forces);
        profile::add(&mut self.profile.evaluate_seconds, clock.elapsed());
        self.evaluate_with_beams(z, f_ext, beam_forces)
    }

    /// [`Self::evaluate`] with the beams' forces at `z` given (e.g. `K_b (z₀ + α Δz)` as
    /// `K_b z₀ + α K_b Δz` along a line search: the beam law is linear).
    fn evaluate_with_beams(&mut self, z: &[f64], f_ext: &[f64], beam_forces: Vec<f64>) -> Result<Evaluation, DemError> {
        let clock = Instant::now();
        let pairs = if self.opts.contacts && !self.broken.is_empty() {
            self.candidates.candidates(self.model.sample, &self.model.map, z, &self.intact)
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
            self.reference_force = self.reference_force.max(REFERENCE_FRACTION * f[0].abs().max(f[1].abs()));
        }
    }

    /// The residual at `z` with the contact law evaluated on the candidate `pairs`
    /// ([`super::contact_candidates`]).
    fn evaluate_at(
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
            &self.z_commit,
            &self.committed_ft,
        )?;
        let mut f = beam_forces.clone();
        contact_set::add_contact_forces(&self.model.map, &contacts, &mut f);
        let map = &self.model.map;
        let mut r = vec![0.0; map.n_eq()];
        let mut scale = (1e-9 * self.model.params.e_bar * self.model.params.t_z * self.model.sample.width)
            .max(self.roundoff_force / self.opts.tol)
            .max(self.reference_force);
        for v in f.iter().chain(f_ext.iter()) {
            scale = scale.max(v.abs());
        }
        let (mut inf, mut merit) = (0.0f64, 0.0);
        for (e, &zi) in map.unknowns.iter().enumerate() {
            r[e] = f_ext[zi] - f[zi] - self.reg[e] * (z[zi] - self.z_commit[zi]);
            inf = inf.max(r[e].abs());
            let w = if zi % 3 == 2 { 1.0 / self.mean_diameter } else { 1.0 };
            merit += 0.5 * (w * r[e]).powi(2);
        }
        Ok(Evaluation { contacts, r, relative: inf / scale, merit, beam_forces })
    }

    /// Finds equilibrium at `load` plus the extra external forces `extra` (over `z`, e.g. a
    /// broken beam's force being released), starting from the current `z`; leaves the
    /// contacts of the equilibrium state in `self.contacts`.
    pub(super) fn equilibrate_with(
        &mut self,
        load: &super::events::LoadPoint,
        extra: Option<&[f64]>,
        t: f64,
    ) -> Result<(), DemError> {
        let map = &self.model.map;
        for (k, &zi) in map.prescribed.iter().enumerate() {
            self.z[zi] = load.prescribed[k];
        }
        let mut f_ext = extra.map_or_else(|| vec![0.0; map.n_z], |x| x.to_vec());
        for (k, &zi) in map.forced.iter().enumerate() {
            f_ext[zi] += load.forces[k];
        }
        let n_eq = map.n_eq();
        let z0 = self.z.clone();
        let mut ev = self.evaluate(&z0, &f_ext)?;
        let mut forcing = ForcingSequence::new(self.opts.forcing);
        let events = self.broken.len();
        let (stage, what) = (self.stage, if extra.is_some() { "release" } else { "load" });
        if let Some(tr) = self.trace.as_mut() {
            tr.begin(stage, t, events, what);
        }
        let mut previous: Option<Vec<(usize, usize, bool)>> = None;
        for iteration in 0..self.opts.max_iterations {
            self.jacobians.fresh_only = iteration >= super::tangent::FRESH_AFTER;
            if ev.relative <= self.opts.tol {
                if let Some(tr) = self.trace.as_mut() {
                    tr.end(ev.relative, true);
                }
                self.contacts = ev.contacts;
                return Ok(());
            }
            let mut step = self.trace.as_ref().map(|_| {
                let set: Vec<(usize, usize, bool)> = ev.contacts.iter().map(|a| (a.i, a.j, a.sticks())).collect();
                let changes = previous.as_ref().map_or(0, |p| set_changes(p, &set));
                previous = Some(set);
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
                }
            });
            self.profile.newton_iterations += 1;
            self.sync_operator(&ev.contacts)?;
            if self.needs_factor {
                let cause = self.pending_refactor.take();
                self.refactorize(cause)?;
            }
            self.profile.max_rank = self.profile.max_rank.max(self.factor.rank());
            self.profile.columns_added = self.factor.n_columns;
            self.profile.columns_dropped = self.factor.n_dropped;
            let fail = |e: super::factor::FactorError, ev: usize| DemError::Factorization { event: ev, reason: e.0 };
            let mut dz = vec![0.0; n_eq];
            // The linear solve's tolerance (Eisenstat–Walker by default; the goal: ‖r‖∞ at
            // convergence, tol · scale = tol ‖r‖∞ / relative).
            let r2 = ev.r.iter().map(|x| x * x).sum::<f64>().sqrt();
            let r_inf = ev.r.iter().fold(0.0f64, |m, x| m.max(x.abs()));
            let eta = forcing.next(r2, if ev.relative > 0.0 { self.opts.tol * r_inf / ev.relative } else { 0.0 });
            if self.factor.rank() > 0 && !self.factor.is_accurate() {
                // A near-singular Woodbury capacitance matrix: drop the correction.
                self.refactorize(Some(Refactor::Accuracy))?;
            }
            if ev.contacts.is_empty() {
                let clock = Instant::now();
                dz.clone_from(&ev.r);
                self.factor.solve(&mut dz).map_err(|e| fail(e, events))?;
                self.n_solves += 1;
                profile::add(&mut self.profile.solve_seconds, clock.elapsed());
            } else {
                let clock = Instant::now();
                let tangent = Tangent::new(
                    &self.model,
                    &self.intact,
                    &self.reg,
                    &ev.contacts,
                    &self.z,
                    &self.z_commit,
                    &self.committed_ft,
                    &mut self.jacobians,
                )?;
                self.profile.jacobians_computed = self.jacobians.computed;
                self.profile.jacobians_reused = self.jacobians.reused;
                self.profile.jacobians_on_cone = self.jacobians.on_cone;
                self.profile.jacobians_near_cone = self.jacobians.near_cone;
                // Inexact Newton: the linear solve to η ‖r‖ (`SolverOptions::forcing`; a fixed
                // 1e-6 lost two of the paper wall's 16 shear samples, a fixed 1e-8 was the
                // former default).
                // D = K_T − M: GMRES's products cost O(contacts) (`gmres_split`).
                let op = &self.op_terms;
                let held = |i: usize, j: usize| {
                    let mut k = nalgebra::SMatrix::<f64, 6, 6>::zeros();
                    for kind in [0u8, 1] {
                        if let Some((t, _)) = op.get(&(i, j, kind)) {
                            k += t.k;
                        }
                    }
                    k
                };
                let difference = tangent.difference(&ev.contacts, held);
                profile::add(&mut self.profile.tangent_seconds, clock.elapsed());
                let clock = Instant::now();
                let factor = &mut self.factor;
                let mut in_precond = std::time::Duration::ZERO;
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
                .map_err(|e| fail(e, events))?;
                self.n_solves += info.iterations;
                if let Some(st) = step.as_mut() {
                    st.gmres_iterations = info.iterations;
                    st.linear_converged = info.converged;
                }
                let p = &mut self.profile;
                p.gmres_solves += 1;
                p.gmres_iterations += info.iterations;
                profile::add(&mut p.solve_seconds, in_precond);
                profile::add(&mut p.gmres_seconds, clock.elapsed().saturating_sub(in_precond));
                if !info.converged && self.factor.rank() > 0 {
                    // An inaccurate Woodbury correction: start the next iteration afresh.
                    self.needs_factor = true;
                    self.pending_refactor = Some(Refactor::Accuracy);
                }
                if !info.converged {
                    // GMRES missed its tolerance (a tangent far from the preconditioner's:
                    // many sliding contacts around stones with no intact beam): Newton's step
                    // by a direct solve of the assembled tangent, so that the iteration is not
                    // driven by an unconverged direction.
                    let clock = Instant::now();
                    if let Some(x) = tangent.solve_direct(&ev.r) {
                        dz = x;
                        self.profile.direct_solves += 1;
                        if let Some(st) = step.as_mut() {
                            st.linear_converged = true;
                        }
                    }
                    profile::add(&mut self.profile.solve_seconds, clock.elapsed());
                }
            }
            let cap = self.cap_step(&mut dz);
            let alpha;
            (ev, alpha) = self.line_search(&dz, &f_ext, ev)?;

            if let (Some(tr), Some(mut st)) = (self.trace.as_mut(), step) {
                st.cap = cap;
                st.alpha = alpha;
                tr.step(st);
            }
        }
        if let Some(tr) = self.trace.as_mut() {
            tr.end(ev.relative, ev.relative <= self.opts.tol);
        }
        if ev.relative <= self.opts.tol {
            self.contacts = ev.contacts;
            return Ok(());
        }
        Err(DemError::NoConvergence {
            stage: self.stage,
            load: t,
            event: self.broken.len(),
            iterations: self.opts.max_iterations,
            residual: ev.relative,
            unbonded: self.unbonded_stones(),
        })
    }

    /// Scales `dz` so that no stone moves by more than `max_move` in one iteration; returns the
    /// scale applied (1: none).
    pub(super) fn cap_step(&self, dz: &mut [f64]) -> f64 {
        let map = &self.model.map;
        let big = map
            .unknowns
            .iter()
            .zip(dz.iter())
            .map(|(&zi, d)| if zi % 3 == 2 { d.abs() * self.mean_diameter } else { d.abs() })
            .fold(0.0f64, f64::max);
        if big > self.max_move {
            let s = self.max_move / big;
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
        let base = self.z.clone();
        let unknowns = self.model.map.unknowns.clone();
        let clock = Instant::now();
        let mut dz_z = vec![0.0; self.model.map.n_z];
        for (e, &zi) in unknowns.iter().enumerate() {
            dz_z[zi] = dz[e];
        }
        let mut k_dz = vec![0.0; self.model.map.n_z];
        self.model.add_beam_forces(&self.intact, &dz_z, &mut k_dz);
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
                    self.z[zi] = base[zi] + a * dz[e];
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
            .filter(|&p| !self.model.map.is_slave(p) && !s.neighbours[p].iter().any(|&(_, b)| self.intact[b]))
            .collect()
    }
}

/// Contacts entering or leaving and stick/slip flips between two sets `(i, j, sticks)`, both
/// sorted by pair.
fn set_changes(a: &[(usize, usize, bool)], b: &[(usize, usize, bool)]) -> usize {
    let ma: BTreeMap<(usize, usize), bool> = a.iter().map(|&(i, j, s)| ((i, j), s)).collect();
    let mb: BTreeMap<(usize, usize), bool> = b.iter().map(|&(i, j, s)| ((i, j), s)).collect();
    let gone = ma.keys().filter(|k| !mb.contains_key(k)).count();
    let changed = mb.iter().filter(|(k, s)| ma.get(k).is_none_or(|t| t != *s)).count();
    gone + changed
}
