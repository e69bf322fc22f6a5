//! Particle states kept during a virtual test, for the HDF5/XDMF output
//! ([`crate::dem::output`]).
//!
//! The solver calls an observer with every recorded equilibrium state and its generalized
//! coordinates `z`; the [`Recorder`] keeps the states the policy asks for:
//!
//! | policy  | states kept                                                                   |
//! |---------|-------------------------------------------------------------------------------|
//! | `none`  | none                                                                          |
//! | `steps` | the end of every load step, the first crack (the state just before the first break and the relaxed state after it), the peak of the driven force, the last state |
//! | `all`   | every recorded state (pre-break and relaxed states included)                  |
//!
//! `z` is stored as recorded (one `Vec<f64>` per kept state, `n_z` values, platen masters
//! included) and turned into per-particle `(u_x, u_y, θ)` at the end by the DOF map, so a boundary
//! stone moves with its platen.
use std::cell::RefCell;
use std::collections::BTreeMap;
use std::rc::Rc;

use serde::{Deserialize, Serialize};

use super::dofs::DofMap;
use super::records::{Observer, StateKind, StateRecord};

/// Which recorded states are written as particle states.
#[derive(Clone, Copy, Debug, Default, Deserialize, Serialize, PartialEq, Eq, schemars::JsonSchema)]
#[serde(rename_all = "snake_case")]
pub enum ParticleStates {
    /// No particle states.
    None,
    /// Ends of load steps, first crack, peak, last state (default).
    #[default]
    Steps,
    /// Every recorded state.
    All,
}

/// The rigid motion of every particle at one recorded state.
#[derive(Clone, Debug, PartialEq)]
pub struct ParticleState {
    /// Index of the recorded state (the curve's `state` column).
    pub state: usize,
    /// `(u_x, u_y, θ)` of each particle's centroid (m, m, rad).
    pub dofs: Vec<[f64; 3]>,
}

#[derive(Default)]
struct Kept {
    states: BTreeMap<usize, Vec<f64>>,
    /// The state with the largest |driven force| so far: (|F|, state, z).
    peak: Option<(f64, usize, Vec<f64>)>,
    /// The first pre-break state was seen; the next state is kept too.
    first_break: Option<usize>,
}

/// Collects the states a [`ParticleStates`] policy keeps (shared with the solver's observer).
#[derive(Clone)]
pub struct Recorder {
    policy: ParticleStates,
    /// First load stage whose force is the test's driven force (after a preload).
    first_driven_stage: usize,
    /// `(platen, dof)` of the driven force.
    driven: (usize, usize),
    kept: Rc<RefCell<Kept>>,
}

impl Recorder {
    /// A recorder for `policy`; the peak is that of `|platen_force[driven.0][driven.1]|` over the
    /// stages from `first_driven_stage` on.
    pub fn new(policy: ParticleStates, first_driven_stage: usize, driven: (usize, usize)) -> Recorder {
        Recorder { policy, first_driven_stage, driven, kept: Rc::default() }
    }

    /// The observer to install in the solver (`None` for the `none` policy).
    pub fn observer<'a>(&self) -> Option<Box<dyn Observer + 'a>> {
        (self.policy != ParticleStates::None).then(|| Box::new(self.clone()) as Box<dyn Observer + 'a>)
    }

    /// The kept states as particle motions, in state order; `last` is the final committed state
    /// `(index, z)` (kept by every policy but `none`).
    pub fn finish(&self, map: &DofMap, n_particles: usize, last: Option<(usize, &[f64])>) -> Vec<ParticleState> {
        if self.policy == ParticleStates::None {
            return Vec::new();
        }
        let mut k = self.kept.borrow_mut();
        if let Some((_, index, z)) = k.peak.take() {
            if !z.is_empty() {
                k.states.entry(index).or_insert(z);
            }
        }
        if let Some((index, z)) = last {
            k.states.entry(index).or_insert_with(|| z.to_vec());
        }
        std::mem::take(&mut k.states)
            .into_iter()
            .map(|(state, z)| ParticleState {
                state,
                dofs: (0..n_particles).map(|p| map.particle_dofs(p, &z)).collect(),
            })
            .collect()
    }
}

impl Observer for Recorder {
    fn recorded(&mut self, index: usize, record: &StateRecord, z: &[f64]) {
        let mut k = self.kept.borrow_mut();
        let keep = match self.policy {
            ParticleStates::None => false,
            ParticleStates::All => true,
            ParticleStates::Steps => {
                let first = record.kind == StateKind::PreBreak && k.first_break.is_none();
                if first {
                    k.first_break = Some(index);
                }
                first || record.kind == StateKind::Loading || k.first_break.is_some_and(|f| f + 1 == index)
            }
        };
        if keep {
            k.states.insert(index, z.to_vec());
        }
        if self.policy == ParticleStates::Steps && record.stage >= self.first_driven_stage {
            let f = record.platen_force[self.driven.0][self.driven.1].abs();
            if k.peak.as_ref().is_none_or(|(p, _, _)| f > *p) {
                let z = if keep { Vec::new() } else { z.to_vec() }; // kept states are not copied twice
                k.peak = Some((f, index, z));
            }
        }
    }
}
