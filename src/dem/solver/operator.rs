//! The factorized operator `M` of Newton's method and its upkeep: intact beams, the contacts'
//! normal penalties `k_n b bᵀ` and tangential terms `k_t c cᵀ`, and the regularization `ε`
//! (or the continuation's shift).
//!
//! ```text
//!   M = K_beams(intact) + Σ_contacts (k_n b bᵀ + k_t c cᵀ) + diag(ε)
//!     = L Lᵀ (factorized)  −  U C Uᵀ (Woodbury correction of the changes since)
//! ```
//!
//! A broken beam subtracts its term (rank ≤ 3); a contact term that enters or leaves adds or
//! subtracts a rank-one term, and one that leaves before the next factorization is dropped from
//! the correction instead ([`LowRankCholesky`]). The base is refactorized when the correction
//! has cost more than a factorization (the cost model of [`super::factor`]), when its rank would
//! pass `max_rank` (the Woodbury path only: updates in place keep no correction), when the
//! capacitance matrix is ill-conditioned or GMRES failed with it, after a stone lost every bond
//! and contact, and around a pseudo-transient continuation.
//!
//! **Drift refresh (opt-in, `refresh_drift`).** A held contact term is the rank-one penalty of
//! the contact's geometry when it entered. As the stones rotate, the current term
//! `k b bᵀ` drifts from it and GMRES pays for the difference. With a finite
//! `refresh_drift = δ`, a held term whose 6×6 block differs from the current one by more than
//! `δ · max(‖held‖_F, ‖current‖_F)` is removed (dropped from the correction, or downdated) and
//! added again. Off by default: with the Woodbury path it measured neutral at 10k stones, and it
//! only preconditions, so the equilibrium path does not depend on it.
//!
//! **Pattern.** Every pair whose contact terms were once factorized keeps its entries (zeros once
//! the contact is gone), in pair order: the same triplets in the same order, so the symbolic
//! analysis (a fill-reducing ordering, METIS at 10k stones) is reused.
use std::collections::{BTreeMap, BTreeSet};
use std::time::Instant;

use nalgebra::{SMatrix, SVector};

use super::contact_set::ActiveContact;
use super::error::DemError;
use super::factor::{LowRankCholesky, SparseColumn, TermId};
use super::options::SolverOptions;
use super::profile::{self, SolverProfile};
use super::slip_terms::{Held, HeldRegimes};
use super::system::{Model, ZTerm};

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

/// A contact term's key: the pair and 0 = normal, 1 = tangential.
type TermKey = (usize, usize, u8);

type V6 = SVector<f64, 6>;

/// A term the operator is to hold: key, direction, stiffness, and on a stick/slip flip the
/// regime it is to hold (`true`: stick).
type Want = (TermKey, V6, f64, Option<bool>);

/// The factorized operator and the contact terms it holds (module docs).
pub(super) struct Operator {
    /// The factorization with its Woodbury correction.
    pub factor: LowRankCholesky,
    /// The operator is to be refactorized before its next use.
    stale: bool,
    /// Why it was marked stale (for the profile; `None`: a floating stone).
    pending: Option<Refactor>,
    /// Contact terms currently in the operator, with their handle in the Woodbury correction
    /// while they are there.
    terms: BTreeMap<TermKey, (ZTerm, Option<TermId>)>,
    /// The `z` indices of every pair whose contact terms were ever factorized (module docs,
    /// "Pattern").
    pattern: BTreeMap<(usize, usize), [usize; 6]>,
    /// The regime each contact's tangential term holds, with the flips waiting
    /// ([`super::slip_terms`]; empty while every contact holds `k_t c cᵀ`).
    regimes: HeldRegimes,
}

/// What the operator's upkeep reads besides the contacts: the model, the intact beams, the
/// options, the profile it counts into, and the number of breaks (named in errors).
pub(super) struct Upkeep<'u, 'a> {
    pub model: &'u Model<'a>,
    pub intact: &'u [bool],
    pub opts: &'u SolverOptions,
    pub profile: &'u mut SolverProfile,
    pub event: usize,
}

impl Operator {
    /// An operator of `n_eq` equations, to be factorized before its first use.
    pub fn new(n_eq: usize, updates_in_place: bool, fill_refactor: f64) -> Result<Operator, DemError> {
        let factor = if updates_in_place {
            LowRankCholesky::with_updates(n_eq, fill_refactor)
                .map_err(|e| DemError::Factorization { event: 0, reason: e.0 })?
        } else {
            LowRankCholesky::new(n_eq)
        };
        Ok(Operator {
            factor,
            stale: true,
            pending: None,
            terms: BTreeMap::new(),
            pattern: BTreeMap::new(),
            regimes: HeldRegimes::default(),
        })
    }

    /// Marks the operator for refactorization; `cause` replaces the recorded one when given.
    pub fn invalidate(&mut self, cause: Option<Refactor>) {
        self.stale = true;
        if cause.is_some() {
            self.pending = cause;
        }
    }

    /// Whether the operator is to be refactorized before its next use.
    pub fn is_stale(&self) -> bool {
        self.stale
    }

    /// Refactorizes with the regularization `reg` when the operator is stale (with the recorded
    /// cause).
    pub fn refresh(&mut self, u: &mut Upkeep<'_, '_>, reg: &[f64]) -> Result<(), DemError> {
        if self.stale {
            let cause = self.pending.take();
            self.refactorize(u, cause, reg)?;
        }
        Ok(())
    }

    /// Factorizes the operator with `diagonal` as its diagonal term (the regularization `ε`, or
    /// the continuation's shifted one); `cause` is counted in the profile (`None`: the first
    /// factorization, or a floating stone). It answers any pending request.
    pub fn refactorize(
        &mut self,
        u: &mut Upkeep<'_, '_>,
        cause: Option<Refactor>,
        diagonal: &[f64],
    ) -> Result<(), DemError> {
        let clock = Instant::now();
        for (&(i, j, _), (t, id)) in self.terms.iter_mut() {
            *id = None;
            self.pattern.insert((i, j), t.idx);
        }
        // One term per pair ever in contact, in pair order (module docs, "Pattern"); a factor
        // updated in place is analysed afresh each time, so it leaves out the pairs apart.
        let fresh = self.factor.updates_in_place();
        let extra: Vec<ZTerm> = self
            .pattern
            .iter()
            .map(|(&(i, j), &idx)| ZTerm { idx, k: self.held(i, j) })
            .filter(|t| !fresh || t.k.iter().any(|&v| v != 0.0))
            .collect();
        let t = u.model.assemble(u.intact, diagonal, &extra);
        self.factor.factorize(&t).map_err(|e| DemError::Factorization { event: u.event, reason: e.0 })?;
        (self.stale, self.pending) = (false, None);
        let r = &mut u.profile.refactorizations;
        match cause {
            Some(Refactor::CostModel) => r.cost_model += 1,
            Some(Refactor::RankCap) => r.rank_cap += 1,
            Some(Refactor::Accuracy) => r.accuracy += 1,
            Some(Refactor::Continuation) => r.continuation += 1,
            None if self.factor.n_factorizations == 1 => r.initial += 1,
            None => r.floating += 1,
        }
        profile::add(&mut u.profile.factor_seconds, clock.elapsed());
        u.profile.factor_entries = [self.factor.entries.0, self.factor.entries.1];
        Ok(())
    }

    /// The contact terms the operator holds for the pair `(i, j)` (normal and tangential, in the
    /// pair's `z` indices; zero when it holds none).
    pub fn held(&self, i: usize, j: usize) -> SMatrix<f64, 6, 6> {
        let mut k = SMatrix::<f64, 6, 6>::zeros();
        for kind in [0u8, 1] {
            if let Some((t, _)) = self.terms.get(&(i, j, kind)) {
                k += t.k;
            }
        }
        k
    }

    /// Whether `cols` more columns would pass the Woodbury correction's rank cap. With updates in
    /// place the correction stays empty (every column goes into the factor, whose fill the cost
    /// model of [`super::factor`] buys back), so no batch passes it: counting a batch's columns
    /// there refactorized the operator after any Newton iteration with more than `max_rank`
    /// contact terms entering or leaving.
    fn over_rank_cap(&self, cols: usize, max_rank: usize) -> bool {
        !self.factor.updates_in_place() && self.factor.rank() + cols > max_rank
    }

    /// Adds `sign ·` `term` to the operator as a Woodbury term; `None` when the operator is to
    /// be refactorized anyway (then the factorization includes the term).
    pub fn add_low_rank(
        &mut self,
        u: &mut Upkeep<'_, '_>,
        term: &ZTerm,
        sign: f64,
    ) -> Result<Option<TermId>, DemError> {
        if self.stale {
            return Ok(None); // the next factorization will include the current terms
        }
        let cols = u.model.factors(term);
        if self.over_rank_cap(cols.len(), u.opts.max_rank) {
            self.invalidate(Some(Refactor::RankCap));
            return Ok(None);
        }
        let clock = Instant::now();
        let id =
            self.factor.add_terms(cols, sign).map_err(|e| DemError::Factorization { event: u.event, reason: e.0 })?;
        profile::add(&mut u.profile.columns_seconds, clock.elapsed());
        if self.factor.needs_rebuild() {
            self.invalidate(Some(Refactor::Accuracy));
        }
        Ok(Some(id))
    }

    /// The terms the operator is to hold for `contacts`, in their order (normal, then
    /// tangential): key, direction, stiffness, and on a stick/slip flip that reaches the
    /// operator the regime its term is to hold (`true`: stick; [`super::slip_terms`]).
    /// A contact on the Coulomb cone counts as sliding, as in its tangent ([`super::tangent`]).
    fn wanted(&mut self, opts: &SolverOptions, mu: f64, contacts: &[ActiveContact]) -> Vec<Want> {
        let slip = opts.slip_terms;
        let mut want = Vec::with_capacity(2 * contacts.len());
        for a in contacts {
            want.push(((a.i, a.j, 0), a.contact.normal_direction(), a.contact.k_n, None));
            let (sticks, flip) = if slip.follows_regime() {
                match self.regimes.observe((a.i, a.j), a.sticks_off_cone(mu), slip.lag) {
                    Held::Keep(s) => (s, None),
                    Held::Enter(s) => (s, Some(s)),
                }
            } else {
                (true, None)
            };
            let k = slip.held_stiffness(a.k_t, sticks);
            if k > 0.0 {
                want.push(((a.i, a.j, 1), a.contact.tangential_direction(), k, flip));
            }
        }
        if slip.follows_regime() {
            let live: BTreeSet<(usize, usize)> = contacts.iter().map(|a| (a.i, a.j)).collect();
            self.regimes.retain(|p| live.contains(p));
        }
        want
    }

    /// Takes the term `key` out of the operator: dropped from the Woodbury correction when it
    /// entered since the last factorization, else its subtraction joins `batch`.
    fn take_out(&mut self, model: &Model, key: TermKey, batch: &mut Vec<(Option<TermKey>, Vec<SparseColumn>, f64)>) {
        if let Some((t, id)) = self.terms.remove(&key) {
            let dropped = id.is_some_and(|id| self.factor.remove(id));
            if !dropped && !self.stale {
                batch.push((None, model.factors(&t), -1.0));
            }
        }
    }

    /// With updates in place and a share `s > 0`: scales the held tangential terms `t` of the
    /// flips in `want` (stick → slip by `s`, slip → stick by `1/s`), and returns their keys and
    /// the columns of the differences, `(1/s − 1) t` to add and `(1 − s) t` to subtract: one
    /// column per flip, each sign one multiple-rank update of the factor
    /// ([`super::slip_terms`]). A flip of the Woodbury path, or with `s = 0`, replaces the term
    /// instead.
    fn scale_flips(&mut self, model: &Model, share: f64, want: &[Want]) -> (BTreeSet<TermKey>, [Vec<SparseColumn>; 2]) {
        let (mut scaled, mut cols) = (BTreeSet::new(), [Vec::new(), Vec::new()]);
        if !self.factor.updates_in_place() || share <= 0.0 {
            return (scaled, cols);
        }
        for &(key, _, _, flip) in want {
            let (Some(sticks), Some((t, _))) = (flip, self.terms.get_mut(&key)) else { continue };
            let ratio = if sticks { 1.0 / share } else { share };
            if !self.stale {
                let difference = ZTerm { idx: t.idx, k: t.k * (ratio - 1.0).abs() };
                cols[usize::from(!sticks)].extend(model.factors(&difference));
            }
            t.k *= ratio;
            scaled.insert(key);
        }
        (scaled, cols)
    }

    /// Brings the operator's contact terms (normal penalty, tangential) in line with `contacts`:
    /// a term that leaves (or flips between the stick and slip stiffness, [`super::slip_terms`])
    /// is dropped from the Woodbury correction when it entered since the last factorization,
    /// else subtracted; the new and subtracted terms are added in one batch. A refactorization
    /// is requested instead when the correction would pass `max_rank`, or when it has cost more
    /// than a factorization (the cost model of [`super::factor`]).
    pub fn sync(&mut self, u: &mut Upkeep<'_, '_>, contacts: &[ActiveContact]) -> Result<(), DemError> {
        let want = self.wanted(u.opts, u.model.params.mu, contacts);
        let (scaled, flip_columns) = self.scale_flips(u.model, u.opts.slip_terms.share, &want);
        let keep: BTreeSet<TermKey> =
            want.iter().filter(|w| w.3.is_none() || scaled.contains(&w.0)).map(|w| w.0).collect();
        // (key of a new term, or None for a subtraction; columns; sign)
        let mut batch: Vec<(Option<TermKey>, Vec<SparseColumn>, f64)> = Vec::new();
        let gone: Vec<_> = self.terms.keys().filter(|k| !keep.contains(k)).copied().collect();
        for k in gone {
            u.profile.operator_changes[if k.2 == 0 { 1 } else { 3 }] += 1;
            self.take_out(u.model, k, &mut batch);
        }
        for (key, dir, k, _) in want.into_iter().filter(|w| !scaled.contains(&w.0)) {
            let (i, j, kind) = key;
            let mut current = None;
            if u.opts.refresh_drift.is_finite() {
                // A held term that drifted from the contact's current one is replaced.
                let current = current.insert(u.model.rank_one(i, j, &dir, k));
                let drifted = self.terms.get(&key).is_some_and(|(t, _)| {
                    (current.k - t.k).norm() > u.opts.refresh_drift * t.k.norm().max(current.k.norm())
                });
                if drifted {
                    u.profile.refreshed_terms += 1;
                    self.take_out(u.model, key, &mut batch);
                }
            }
            if !self.terms.contains_key(&key) {
                u.profile.operator_changes[if kind == 0 { 0 } else { 2 }] += 1;
                let t = current.unwrap_or_else(|| u.model.rank_one(i, j, &dir, k));
                if !self.stale {
                    batch.push((Some(key), u.model.factors(&t), 1.0));
                }
                self.terms.insert(key, (t, None));
            }
        }
        u.profile.slip_flips = self.regimes.flips;
        if self.stale {
            return Ok(()); // the next factorization includes the current terms
        }
        let cols: usize = batch.iter().map(|b| b.1.len()).sum();
        if self.over_rank_cap(cols, u.opts.max_rank) {
            self.invalidate(Some(Refactor::RankCap));
            return Ok(());
        }
        let [up, down] = flip_columns;
        let flips: Vec<_> = [(up, 1.0), (down, -1.0)].into_iter().filter(|f| !f.0.is_empty()).collect();
        if !flips.is_empty() {
            let clock = Instant::now();
            self.factor.add_batch(flips).map_err(|e| DemError::Factorization { event: u.event, reason: e.0 })?;
            profile::add(&mut u.profile.columns_seconds, clock.elapsed());
        }
        if !batch.is_empty() {
            let clock = Instant::now();
            let keys: Vec<_> = batch.iter().map(|b| b.0).collect();
            let ids = self
                .factor
                .add_batch(batch.into_iter().map(|(_, c, s)| (c, s)).collect())
                .map_err(|e| DemError::Factorization { event: u.event, reason: e.0 })?;
            for (key, id) in keys.into_iter().zip(ids) {
                if let Some(entry) = key.and_then(|k| self.terms.get_mut(&k)) {
                    entry.1 = Some(id);
                }
            }
            profile::add(&mut u.profile.columns_seconds, clock.elapsed());
        }
        u.profile.factor_entries = [self.factor.entries.0, self.factor.entries.1];
        if self.factor.wants_refactorization() {
            self.invalidate(Some(Refactor::CostModel));
        }
        if self.factor.needs_rebuild() {
            self.invalidate(Some(Refactor::Accuracy));
        }
        Ok(())
    }
}
