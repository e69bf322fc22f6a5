//! [`PointStates`]: the damage histories of an element's integration points (shell layer points,
//! beam fibers): committed and trial, the energy dissipated up to each, and with IMPL-EX the
//! committed history one step back.
//!
//! # Trial and committed (the [`Element`](super::Element) contract)
//! ```text
//!   evaluate(u)   reads the committed states (and, with IMPL-EX, the extrapolated ones),
//!                 writes the trial states and the trial dissipation ([`PointUpdate`])
//!   commit()      trial → committed                    revert()   committed → trial
//! ```
//!
//! # IMPL-EX (`material::implex`)
//! With IMPL-EX on, the store also keeps per point the committed state of the step before,
//! κ_{n−1}, the committed strain ε_n (m components) and the size Δt_n of the last committed
//! step. [`PointStates::set_implex_step`]`(law, h)` computes, before the evaluations of a step of
//! size h, every point's extrapolated history with the ratio h/Δt_n (0 while no step has been
//! committed since IMPL-EX was switched on, so the first step uses the committed damage); the
//! evaluations ([`PointUpdate::respond`]) take their stress from it with the split at their own
//! strain or frozen at ε_n (`material::implex::SplitAt`; not frozen on that first step: ε_n is
//! known once a step is behind), and record their strain.
//! A commit shifts committed → previous, records Δt_n = h and ε_n; the extrapolated states are
//! then reset to the committed ones until the next step sets them.
//!
//! An IMPL-EX evaluation is the law at fixed damage (one law evaluation per point), or with the
//! split frozen `S ε` with the point's secant S of the step (kept from its first evaluation).
//! Where the extrapolated damage is equal on both sides (d̃_t = d̃_c, every undamaged point among
//! them) the law at fixed damage is linear, σ = (1 − d̃) C₀ ε, whatever the split: the tangent of
//! the point's first evaluation of the step then gives the stress of the others, `C ε`, without
//! the law (equal to it to round-off; the material point's tests check it for both splits);
//! the trial state, the implicit update at the evaluated strain, is needed only for the step
//! that converged: [`PointStates::settle`] computes it then, once per step instead of once per
//! iteration, and the element calls it before it commits or measures its damage increment.
//!
//! # Checkpoint layout
//! ```text
//!   implicit:  [κ_t, κ_c, d_t, d_c] per point, then the dissipated energy (J)     4 n + 1
//!   IMPL-EX:   the same, then [κ_t, κ_c] of κ_{n−1} per point, Δt_n (s),
//!              then ε_n per point (m values)                                     (6 + m) n + 2
//! ```
//! [`PointStates::load`] reads either: the implicit layout under IMPL-EX (a state written by an
//! implicit run, such as a saved gravity state) has no step behind it (κ_{n−1} = κ_n, Δt_n = 0);
//! the IMPL-EX layout switches IMPL-EX on, with its history.

use nalgebra::{SMatrix, SVector};

use super::error::{check_len, ElementError};
use crate::material::implex::{self, SplitAt};
use crate::material::{DamageState, PointLaw, Response, Side};

/// The IMPL-EX part of the store (module docs).
#[derive(Clone, Debug, PartialEq)]
struct ImplexHistory {
    /// κ_t, κ_c of the committed states one step back.
    previous: Vec<[f64; 2]>,
    /// Δt_n: the size of the step from `previous` to the committed states (0: none).
    last_step: f64,
    /// The size of the step the next evaluations belong to.
    step: f64,
    /// The histories their stress uses.
    extrapolated: Vec<DamageState>,
    /// The committed strains (`strain_len` per point), where the split is frozen; known once a
    /// step is behind the committed states (`last_step > 0`).
    strains: Vec<f64>,
    /// The strains of the last evaluation.
    trial_strains: Vec<f64>,
    /// The step's secants S (m × m per point, column-major), computed at a point's first
    /// evaluation of the step (they depend on the extrapolated history and ε_n only).
    secants: Vec<f64>,
    /// Whether a point's secant is computed for this step.
    secant_known: Vec<bool>,
    /// Whether the trial states wait for [`PointStates::settle`] (module docs).
    pending: bool,
    /// Where the split of the step's stress is taken.
    split: SplitAt,
}

impl ImplexHistory {
    /// No step behind the committed states `committed` (`strain_len` strains per point).
    fn starting_at(committed: &[DamageState], strain_len: usize, split: SplitAt) -> ImplexHistory {
        let previous = committed.iter().map(|s| [s.kappa_t, s.kappa_c]).collect();
        let strains = vec![0.0; strain_len * committed.len()];
        ImplexHistory {
            previous,
            last_step: 0.0,
            step: 0.0,
            extrapolated: committed.to_vec(),
            trial_strains: strains.clone(),
            secants: vec![0.0; strain_len * strain_len * committed.len()],
            secant_known: vec![false; committed.len()],
            strains,
            pending: false,
            split,
        }
    }
}

/// The IMPL-EX part of a [`PointUpdate`].
#[derive(Debug)]
struct ImplexUpdate<'a> {
    extrapolated: &'a [DamageState],
    strains: Option<&'a [f64]>,
    trial_strains: &'a mut [f64],
    secants: &'a mut [f64],
    secant_known: &'a mut [bool],
    pending: &'a mut bool,
}

/// What an evaluation of a group of points reads (their committed states and, with IMPL-EX,
/// the extrapolated histories and committed strains) and writes (their trial states and, with
/// IMPL-EX, strains).
#[derive(Debug)]
pub struct PointUpdate<'a> {
    committed: &'a [DamageState],
    trial: &'a mut [DamageState],
    implex: Option<ImplexUpdate<'a>>,
}

impl<'a> PointUpdate<'a> {
    /// The implicit law from `committed`, into `trial` (an output's scratch states).
    pub fn implicit(committed: &'a [DamageState], trial: &'a mut [DamageState]) -> PointUpdate<'a> {
        PointUpdate { committed, trial, implex: None }
    }

    /// The points `range` of these (`strain_len` strains per point).
    pub fn slice(&mut self, range: std::ops::Range<usize>, strain_len: usize) -> PointUpdate<'_> {
        let r = range.start * strain_len..range.end * strain_len;
        PointUpdate {
            committed: &self.committed[range.clone()],
            trial: &mut self.trial[range.clone()],
            implex: self.implex.as_mut().map(|x| ImplexUpdate {
                extrapolated: &x.extrapolated[range.clone()],
                strains: x.strains.map(|s| &s[r.clone()]),
                trial_strains: &mut x.trial_strains[r],
                secants: &mut x.secants[range.start * strain_len * strain_len..range.end * strain_len * strain_len],
                secant_known: &mut x.secant_known[range],
                pending: &mut *x.pending,
            }),
        }
    }

    /// The response of point `j` at `strain` under the law `eval(law, strain, history)`
    /// (`material::implex::evaluate`); its trial state (and strain) written. With IMPL-EX the
    /// stress is the law's at fixed damage, at the step's strain or, frozen, `S ε` with the
    /// point's secant S of the step (kept from its first evaluation); the implicit update waits
    /// for [`PointStates::settle`]: the response's trial state is the committed one, its
    /// dissipation 0 and `loading` false (module docs).
    #[inline]
    pub fn respond<const N: usize>(
        &mut self,
        law: &PointLaw,
        j: usize,
        strain: &SVector<f64, N>,
        eval: impl Fn(&PointLaw, &SVector<f64, N>, &DamageState) -> Response<N>,
    ) -> Response<N> {
        let Some(x) = &mut self.implex else {
            let r = eval(law, strain, &self.committed[j]);
            self.trial[j] = r.state;
            return r;
        };
        x.trial_strains[N * j..N * (j + 1)].copy_from_slice(strain.as_slice());
        self.trial[j] = self.committed[j];
        *x.pending = true;
        let linear = x.extrapolated[j].d_t == x.extrapolated[j].d_c;
        let stress = match x.strains {
            None if linear => {
                // Equal damage on both sides: the law at fixed damage is linear, σ = (1 − d) C₀ ε
                // for either split, so its tangent at the first evaluation of the step gives the
                // stress of every other one (the undamaged points, most of a model, among them).
                let cell = &mut x.secants[N * N * j..N * N * (j + 1)];
                if !x.secant_known[j] {
                    let r = eval(&law.with_frozen_history(), strain, &x.extrapolated[j]);
                    cell.copy_from_slice(r.tangent.as_slice());
                    x.secant_known[j] = true;
                    r
                } else {
                    let s = SMatrix::<f64, N, N>::from_column_slice(cell);
                    let (state, side) = (self.committed[j], Side::Tension);
                    Response {
                        stress: s * strain,
                        secant: s,
                        tangent: s,
                        state,
                        dissipation: 0.0,
                        side,
                        loading: false,
                    }
                }
            }
            None => eval(&law.with_frozen_history(), strain, &x.extrapolated[j]),
            Some(strains) => {
                let cell = &mut x.secants[N * N * j..N * N * (j + 1)];
                if !x.secant_known[j] {
                    let at = SVector::<f64, N>::from_column_slice(&strains[N * j..N * (j + 1)]);
                    let s = eval(&law.with_frozen_history(), &at, &x.extrapolated[j]).secant;
                    cell.copy_from_slice(s.as_slice());
                    x.secant_known[j] = true;
                }
                let s = SMatrix::<f64, N, N>::from_column_slice(cell);
                let (state, side) = (self.committed[j], Side::Tension);
                Response { stress: s * strain, secant: s, tangent: s, state, dissipation: 0.0, side, loading: false }
            }
        };
        Response { state: self.committed[j], dissipation: 0.0, loading: false, ..stress }
    }
}

/// The damage states of an element's points (module docs). Empty for an elastic element.
#[derive(Clone, Debug, PartialEq)]
pub struct PointStates {
    committed: Vec<DamageState>,
    trial: Vec<DamageState>,
    dissipated: f64,
    trial_dissipated: f64,
    /// Strain components per point (1 for a fiber, 3 for a shell layer point).
    strain_len: usize,
    implex: Option<ImplexHistory>,
}

impl PointStates {
    /// `n` virgin points with `strain_len` strain components each, implicit.
    pub fn new(n: usize, strain_len: usize) -> PointStates {
        let v = vec![DamageState::default(); n];
        PointStates { committed: v.clone(), trial: v, dissipated: 0.0, trial_dissipated: 0.0, strain_len, implex: None }
    }

    /// Whether there is no point (an elastic element).
    pub fn is_empty(&self) -> bool {
        self.committed.is_empty()
    }

    /// The committed states.
    pub fn committed(&self) -> &[DamageState] {
        &self.committed
    }

    /// The trial states.
    pub fn trial(&self) -> &[DamageState] {
        &self.trial
    }

    /// The energy dissipated up to the committed states (J).
    pub fn dissipated(&self) -> f64 {
        self.dissipated
    }

    /// What an evaluation reads and writes (its trial states).
    pub fn for_update(&mut self) -> PointUpdate<'_> {
        let implex = self.implex.as_mut().map(|x| ImplexUpdate {
            extrapolated: &x.extrapolated,
            strains: (x.split == SplitAt::Frozen && x.last_step > 0.0).then_some(x.strains.as_slice()),
            trial_strains: &mut x.trial_strains,
            secants: &mut x.secants,
            secant_known: &mut x.secant_known,
            pending: &mut x.pending,
        });
        PointUpdate { committed: &self.committed, trial: &mut self.trial, implex }
    }

    /// Strain components per point.
    pub fn strain_len(&self) -> usize {
        self.strain_len
    }

    /// The energy the trial states dissipated from the committed ones (J).
    pub fn set_trial_dissipation(&mut self, dissipation: f64) {
        self.trial_dissipated = self.dissipated + dissipation;
    }

    /// With IMPL-EX and the split frozen, the trial states of the last evaluations: the implicit
    /// update of every point at the strain it was last evaluated at, `update(j, strain,
    /// committed)` giving its state and the energy it dissipates (J, weighted by the point's
    /// volume). Nothing when no evaluation waits for it (module docs). An element calls it
    /// before it commits and before it measures its damage increment.
    pub fn settle(&mut self, mut update: impl FnMut(usize, &[f64], &DamageState) -> (DamageState, f64)) {
        let Some(x) = &mut self.implex else { return };
        if !x.pending {
            return;
        }
        let m = self.strain_len;
        let mut dissipation = 0.0;
        for (j, (t, c)) in self.trial.iter_mut().zip(&self.committed).enumerate() {
            let (s, d) = update(j, &x.trial_strains[m * j..m * (j + 1)], c);
            *t = s;
            dissipation += d;
        }
        self.trial_dissipated = self.dissipated + dissipation;
        x.pending = false;
    }

    /// With IMPL-EX, the settled trial states ([`Self::settle`]) become the histories the stress
    /// of the step's next evaluations uses, in place of the extrapolated ones: a staggered
    /// correction of the step (`analysis::time_history::stepper`, "IMPL-EX corrections"). The
    /// committed states and the step are unchanged; a point whose held history changes computes
    /// its secant again. Returns the largest change of a point's held damage, max |Δd_t|, |Δd_c|
    /// (0 without IMPL-EX, and where only histories below their thresholds moved).
    pub fn hold_trial(&mut self) -> f64 {
        let Some(x) = &mut self.implex else { return 0.0 };
        debug_assert!(!x.pending, "an IMPL-EX correction of trial states not settled");
        let mut change = 0.0f64;
        for ((held, t), known) in x.extrapolated.iter_mut().zip(&self.trial).zip(x.secant_known.iter_mut()) {
            if held != t {
                change = change.max((t.d_t - held.d_t).abs()).max((t.d_c - held.d_c).abs());
                (*held, *known) = (*t, false);
            }
        }
        change
    }

    /// Trial → committed (with IMPL-EX, committed → previous first). The trial states must be
    /// settled ([`Self::settle`]).
    pub fn commit(&mut self) {
        if let Some(x) = &mut self.implex {
            debug_assert!(!x.pending, "an IMPL-EX commit of trial states not settled");
            for (p, c) in x.previous.iter_mut().zip(&self.committed) {
                *p = [c.kappa_t, c.kappa_c];
            }
            x.last_step = x.step;
            x.extrapolated.copy_from_slice(&self.trial);
            x.strains.copy_from_slice(&x.trial_strains);
            x.secant_known.fill(false);
        }
        self.committed.copy_from_slice(&self.trial);
        self.dissipated = self.trial_dissipated;
    }

    /// Committed → trial.
    pub fn revert(&mut self) {
        self.trial.copy_from_slice(&self.committed);
        self.trial_dissipated = self.dissipated;
        if let Some(x) = &mut self.implex {
            x.trial_strains.copy_from_slice(&x.strains);
            x.pending = false;
        }
    }

    /// The largest damage increment of the trial states over the committed ones.
    pub fn damage_increment(&self) -> f64 {
        super::damage_increment(&self.trial, &self.committed)
    }

    /// IMPL-EX on with the split taken where `split` says (the history starts at the committed
    /// states, no step behind them, unless it is on already), or off (`None`: the history
    /// dropped).
    pub fn set_implex(&mut self, split: Option<SplitAt>) {
        let empty = self.is_empty();
        match (split, &mut self.implex) {
            (Some(split), None) if !empty => {
                self.implex = Some(ImplexHistory::starting_at(&self.committed, self.strain_len, split))
            }
            (Some(split), Some(x)) => x.split = split,
            (None, _) => self.implex = None,
            _ => {}
        }
    }

    /// Whether IMPL-EX is on.
    pub fn is_implex(&self) -> bool {
        self.implex.is_some()
    }

    /// With IMPL-EX on, the size `h` of the step the next evaluations belong to: every point's
    /// history extrapolated by the ratio h/Δt_n (0 without a step behind). Else nothing.
    pub fn set_implex_step(&mut self, law: &PointLaw, h: f64) {
        let Some(x) = &mut self.implex else { return };
        let ratio = if x.last_step > 0.0 { h / x.last_step } else { 0.0 };
        x.step = h;
        x.secant_known.fill(false);
        for ((e, c), p) in x.extrapolated.iter_mut().zip(&self.committed).zip(&x.previous) {
            let previous = DamageState { kappa_t: p[0], kappa_c: p[1], ..DamageState::default() };
            *e = implex::extrapolate(law, c, &previous, ratio);
        }
    }

    /// Values of the checkpoint layout (module docs); 0 for an elastic element.
    pub fn n_state(&self) -> usize {
        match (self.is_empty(), &self.implex) {
            (true, _) => 0,
            (false, None) => Self::implicit_len(self.committed.len()),
            (false, Some(_)) => self.implex_len(),
        }
    }

    fn implicit_len(n: usize) -> usize {
        DamageState::N_VALUES * n + 1
    }

    fn implex_len(&self) -> usize {
        let n = self.committed.len();
        Self::implicit_len(n) + (2 + self.strain_len) * n + 1
    }

    /// The committed states into `out` (length [`Self::n_state`]).
    pub fn save(&self, out: &mut [f64]) -> Result<(), ElementError> {
        check_len("state", self.n_state(), out.len())?;
        if self.is_empty() {
            return Ok(());
        }
        let n = self.committed.len();
        for (chunk, s) in out.chunks_exact_mut(DamageState::N_VALUES).zip(&self.committed) {
            chunk.copy_from_slice(&s.to_array());
        }
        out[DamageState::N_VALUES * n] = self.dissipated;
        if let Some(x) = &self.implex {
            let tail = &mut out[Self::implicit_len(n)..];
            for (chunk, p) in tail.chunks_exact_mut(2).zip(&x.previous) {
                chunk.copy_from_slice(p);
            }
            tail[2 * n] = x.last_step;
            tail[2 * n + 1..].copy_from_slice(&x.strains);
        }
        Ok(())
    }

    /// The committed (and trial) states from `state`, in either layout (module docs).
    pub fn load(&mut self, state: &[f64]) -> Result<(), ElementError> {
        if self.is_empty() {
            return check_len("state", 0, state.len());
        }
        let n = self.committed.len();
        let with_history = state.len() == self.implex_len();
        if !with_history {
            check_len("state", Self::implicit_len(n), state.len())?;
        }
        for (chunk, s) in state.chunks_exact(DamageState::N_VALUES).zip(self.committed.iter_mut()) {
            *s = DamageState::from_array([chunk[0], chunk[1], chunk[2], chunk[3]]);
        }
        self.dissipated = state[DamageState::N_VALUES * n];
        if with_history || self.implex.is_some() {
            let split = self.implex.as_ref().map_or(SplitAt::default(), |x| x.split);
            let mut x = ImplexHistory::starting_at(&self.committed, self.strain_len, split);
            if with_history {
                let tail = &state[Self::implicit_len(n)..];
                for (chunk, p) in tail.chunks_exact(2).zip(x.previous.iter_mut()) {
                    *p = [chunk[0], chunk[1]];
                }
                x.last_step = tail[2 * n];
                x.strains.copy_from_slice(&tail[2 * n + 1..]);
            }
            self.implex = Some(x);
        }
        self.revert();
        Ok(())
    }
}

#[cfg(test)]
#[path = "point_states_tests.rs"]
mod tests;
