//! What the solver records: the load of a stage, the committed equilibrium states (one curve
//! point each, with the energy account), the broken beams, how a stage ended, and the
//! [`Observer`] that sees every recorded state with its coordinates.

/// The load of a stage: prescribed platen values (order of [`super::DofMap::prescribed`]) and forces
/// (order of [`super::DofMap::forced`]).
#[derive(Clone, Debug, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct LoadPoint {
    /// Imposed displacements/rotations.
    pub prescribed: Vec<f64>,
    /// External forces/moments.
    pub forces: Vec<f64>,
}

impl LoadPoint {
    /// `a + t (b − a)`.
    pub(super) fn lerp(a: &LoadPoint, b: &LoadPoint, t: f64) -> LoadPoint {
        let l = |x: &[f64], y: &[f64]| x.iter().zip(y).map(|(u, v)| u + t * (v - u)).collect();
        LoadPoint { prescribed: l(&a.prescribed, &b.prescribed), forces: l(&a.forces, &b.forces) }
    }
}

/// Why a committed state was recorded.
#[derive(Clone, Copy, Debug, PartialEq, Eq, serde::Serialize, serde::Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum StateKind {
    /// End of a load step.
    Loading,
    /// Load scaled to the first beam reaching P = 1.
    PreBreak,
    /// Re-equilibrated at fixed load after a break.
    Relaxed,
}

/// One committed equilibrium state.
#[derive(Clone, Debug, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct StateRecord {
    /// Load stage index.
    pub stage: usize,
    /// Load parameter within the stage.
    pub t: f64,
    /// Kind.
    pub kind: StateKind,
    /// Platen DOFs `(U_x, U_y, Θ)`, bottom then top.
    pub platen: [[f64; 3]; 2],
    /// Platen generalized forces (internal = reactions for prescribed DOFs).
    pub platen_force: [[f64; 3]; 2],
    /// Mean `u_x` of the left and of the right boundary stones.
    pub lateral_ux: [f64; 2],
    /// Broken beams so far: total, tension, shear, crushing.
    pub broken: [usize; 4],
    /// Active contacts.
    pub contacts: usize,
    /// External work (J).
    pub external_work: f64,
    /// Stored elastic energy (J).
    pub stored: f64,
    /// Dissipated: fracture, friction, relaxation, crushing (J).
    pub dissipated: [f64; 4],
}

/// A broken beam.
#[derive(Clone, Debug, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct BrokenBeam {
    /// Beam index.
    pub beam: usize,
    /// Failure mode at breaking.
    pub mode: FailureModeTag,
    /// Index of the recorded state at which it broke (the last state with it intact).
    pub state: usize,
    /// Its elastic energy when it broke (J).
    pub energy: f64,
}

/// Serializable failure mode.
#[derive(Clone, Copy, Debug, PartialEq, Eq, serde::Serialize, serde::Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum FailureModeTag {
    /// Tension-dominated.
    Tension,
    /// Rotation/shear-dominated.
    Shear,
    /// Compressive stress at the crushing stress (only with crushing).
    Crushing,
}

/// How a stage ended.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum StageEnd {
    /// The target was reached.
    Completed,
    /// The monitored force dropped below the loss fraction of its peak.
    LossOfLoad,
}

/// Sees every recorded state as it is committed: its index in the record, the record and the
/// generalized coordinates `z` (e.g. to keep particle states, [`super::snapshots::Recorder`]).
pub trait Observer {
    /// Called once per recorded state, in order.
    fn recorded(&mut self, index: usize, record: &StateRecord, z: &[f64]);

    /// Called after [`Self::recorded`] with the solver's profile so far (e.g. to print where a
    /// long run spends its time as it goes, `examples/dem_profile.rs`). Does nothing by default.
    fn profiled(&mut self, _index: usize, _profile: &super::SolverProfile) {}
}

/// A closure `|index, record, z|` is an observer.
impl<F: FnMut(usize, &StateRecord, &[f64])> Observer for F {
    fn recorded(&mut self, index: usize, record: &StateRecord, z: &[f64]) {
        self(index, record, z)
    }
}
