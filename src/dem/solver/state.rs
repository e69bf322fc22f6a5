//! What a virtual test is at a moment, apart from how the solver computes it.
//!
//! The solver ([`super::Solver`]) owns a [`SolverState`] and a workspace, and the step
//! pipeline takes both as arguments ([`super::solver`]). The state is the mechanics:
//! coordinates, intact beams, contacts and their committed histories, the load, the energy
//! account and the record of committed states. The workspace ([`super::workspace`]) holds what
//! the state determines and the solver keeps only for speed:
//! - the factorized operator with its Woodbury correction ([`super::operator`]);
//! - the contact candidate list ([`super::contact_candidates`]);
//! - the contact Jacobian cache ([`super::tangent`]).
//!
//! A clone of the state, taken between stages, continues the test in a new solver
//! ([`super::Solver::resume`]): the workspace is rebuilt from the state, and the path agrees
//! with the uninterrupted one to the round-off of a fresh factorization. Serialized with the
//! stage walk, it is a test's checkpoint ([`super::checkpoint`]).
//!
//! **Trial and committed.** During an equilibrium iteration `z` and `contacts` are the trial.
//! [`SolverState::accept`] makes the trial the committed state: the friction histories, the
//! regularization's anchor `z_commit` and the contact set of the contact events.
//! [`SolverState::restore`] goes back to it after a failed trial.
use super::contact_set::{self, ActiveContact, Histories};
use super::records::{BrokenBeam, LoadPoint, StateRecord};

/// The mechanical state of one virtual test (module docs).
#[derive(Clone, Debug, serde::Serialize, serde::Deserialize)]
pub struct SolverState {
    /// Generalized coordinates: the trial during an equilibrium iteration, the committed state
    /// after it.
    pub z: Vec<f64>,
    /// The last committed coordinates: the friction trial's start and the anchor of the
    /// regularization springs.
    pub z_commit: Vec<f64>,
    /// Beam intact flags.
    pub intact: Vec<bool>,
    /// The active contacts of the trial (after an equilibrium: of the equilibrium state).
    pub contacts: Vec<ActiveContact>,
    /// The active contacts of the last committed state (for the contact events).
    pub committed_contacts: Vec<ActiveContact>,
    /// Committed contact histories (tangential force, plastic penetration) by pair.
    #[serde(with = "pairs")]
    pub histories: Histories,
    /// The load of the last committed state.
    pub load: LoadPoint,
    /// The current load stage.
    pub stage: usize,
    /// The energy account so far ([`super::energy`]).
    pub energy: Energy,
    /// A tenth of the largest platen force component of the recorded states (N): a floor of the
    /// convergence scale ([`super::equilibrium`], module docs).
    pub reference_force: f64,
    /// The recorded states, in order.
    pub records: Vec<StateRecord>,
    /// The broken beams, in order.
    pub broken: Vec<BrokenBeam>,
    /// Stones found free-floating, with the number of breaks when they were found.
    pub floating: Vec<(usize, usize)>,
}

impl SolverState {
    /// The unloaded state: `n_z` coordinates at zero, `n_beams` intact beams, no contact, `load`
    /// as the current load.
    pub fn new(n_z: usize, n_beams: usize, load: LoadPoint) -> SolverState {
        SolverState {
            z: vec![0.0; n_z],
            z_commit: vec![0.0; n_z],
            intact: vec![true; n_beams],
            contacts: Vec::new(),
            committed_contacts: Vec::new(),
            histories: Histories::new(),
            load,
            stage: 0,
            energy: Energy::default(),
            reference_force: 0.0,
            records: Vec::new(),
            broken: Vec::new(),
            floating: Vec::new(),
        }
    }

    /// Makes the trial the committed state (friction dissipation booked, contact histories,
    /// regularization anchor) without recording it: e.g. an intermediate state of a cut-back
    /// release.
    pub fn accept(&mut self) {
        self.energy.friction += self.contacts.iter().map(|a| a.friction.dissipation).sum::<f64>();
        self.energy.crushing += self.contacts.iter().map(|a| a.crushing_dissipation()).sum::<f64>();
        // Pairs apart keep their plastic state (no tangential force without contact).
        let mut next: Histories = self
            .histories
            .iter()
            .filter(|(_, h)| h.plastic.kappa > 0.0)
            .map(|(&k, h)| (k, contact_set::ContactHistory { f_t: 0.0, plastic: h.plastic }))
            .collect();
        next.extend(self.contacts.iter().map(|a| ((a.i, a.j), a.history())));
        self.histories = next;
        self.committed_contacts.clone_from(&self.contacts);
        self.z_commit.clone_from(&self.z);
    }

    /// Back to the committed coordinates (a failed trial).
    pub fn restore(&mut self) {
        self.z.clone_from(&self.z_commit);
    }

    /// The number of beams broken so far (the "event" that errors name).
    pub fn events(&self) -> usize {
        self.broken.len()
    }
}

/// The energy account's running totals (J), [`super::energy`].
#[derive(Clone, Copy, Debug, Default, serde::Serialize, serde::Deserialize)]
pub struct Energy {
    /// External work.
    pub external: f64,
    /// Fracture: each broken beam's energy when it broke.
    pub fracture: f64,
    /// Friction: the contacts' return-map dissipation.
    pub friction: f64,
    /// Relaxation: what re-equilibrations at fixed load release beyond the broken beams' energy.
    pub relaxation: f64,
    /// Crushing: the plastic work of crushing contacts.
    pub crushing: f64,
}

/// `(i, j)`-keyed maps as a list of pairs (JSON keys are strings).
mod pairs {
    use serde::{Deserialize, Deserializer, Serialize, Serializer};
    use std::collections::BTreeMap;

    /// Serializes the map as `[[key, value], ...]`.
    pub fn serialize<K: Serialize, V: Serialize, S: Serializer>(m: &BTreeMap<K, V>, s: S) -> Result<S::Ok, S::Error> {
        s.collect_seq(m.iter())
    }

    /// Reads `[[key, value], ...]`.
    pub fn deserialize<'de, K, V, D>(d: D) -> Result<BTreeMap<K, V>, D::Error>
    where
        K: Deserialize<'de> + Ord,
        V: Deserialize<'de>,
        D: Deserializer<'de>,
    {
        Ok(Vec::<(K, V)>::deserialize(d)?.into_iter().collect())
    }
}
