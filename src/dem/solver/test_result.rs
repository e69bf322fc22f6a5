//! What a virtual test returns: its curve (one point per recorded state), the numbers derived
//! from it, the run's statistics and how it ended.
//!
//! Signs and strains as in [`super::virtual_test`] (tension positive, `stress = F/(W t_z)`).
//!
//! Derived numbers: `E = σ/ε` at the first recorded loading state (the response is linear
//! before the first break: secant = tangent), `ν = −ε_lat/ε_axial` there, first-crack stress =
//! the stress of the first pre-break state, peak = the largest `|σ|`, and the strain there.
use serde::Serialize;

use super::records::{BrokenBeam, StateKind, StateRecord};
use super::snapshots::ParticleState;

/// One point of the curve (one recorded equilibrium state).
#[derive(Clone, Debug, PartialEq, Serialize, serde::Deserialize)]
pub struct CurvePoint {
    /// Index of the recorded state.
    pub state: usize,
    /// Why it was recorded.
    pub kind: StateKind,
    /// Driven platen displacement (m).
    pub displacement: f64,
    /// Axial (or shear) strain.
    pub strain: f64,
    /// Stress (Pa, tension positive).
    pub stress: f64,
    /// Lateral strain.
    pub lateral_strain: f64,
    /// Broken beams: total, tension, shear, crushing.
    pub broken: [usize; 4],
    /// External work (J).
    pub external_work: f64,
    /// Stored energy (J).
    pub stored: f64,
    /// Dissipated energy: fracture, friction, relaxation, crushing (J).
    pub dissipated: [f64; 4],
}

/// Derived numbers of a test.
#[derive(Clone, Debug, PartialEq, Serialize, serde::Deserialize)]
pub struct Derived {
    /// Initial modulus `σ/ε` (Pa; shear test: the shear modulus-like ratio τ/γ).
    pub young_modulus: f64,
    /// `−ε_lat/ε_axial` in the elastic range.
    pub poisson: f64,
    /// |σ| at the first break (Pa), if any.
    pub first_crack_stress: Option<f64>,
    /// Largest |σ| (Pa).
    pub peak_stress: f64,
    /// Strain at the peak.
    pub strain_at_peak: f64,
}

/// Run statistics.
#[derive(Clone, Debug, PartialEq, Serialize, serde::Deserialize)]
pub struct RunStats {
    /// Beam breaks.
    pub events: usize,
    /// Linear solves.
    pub solves: usize,
    /// Numeric factorizations.
    pub factorizations: usize,
    /// Wall time (s).
    pub seconds: f64,
    /// Whether the run stopped on loss of load.
    pub loss_of_load: bool,
    /// Load steps ended at a contact event (stick → slip, closing, opening).
    #[serde(default)]
    pub contact_events: usize,
    /// Load-increment cut-backs (halved steps or beam releases).
    pub cutbacks: usize,
    /// Load steps whose equilibrium was found by continuation (past a snap-back, or where
    /// Newton's method alternated between two states).
    #[serde(default)]
    pub continued_steps: usize,
    /// Pseudo-transient continuations run (snap-backs and stalled releases), converged or not.
    #[serde(default)]
    pub continuations: usize,
    /// Load steps halved because their energy did not balance (crushing; `stage.rs`, "Snaps
    /// inside a step").
    #[serde(default)]
    pub imbalance_cutbacks: usize,
    /// Such steps left at the smallest increment and recorded as snaps.
    #[serde(default)]
    pub snaps_in_steps: usize,
    /// Whether the factor followed the breaks by updates in place (else by a Woodbury
    /// correction; [`super::FactorUpdates`]).
    #[serde(default)]
    pub updates_in_place: bool,
}

/// How a test ended.
#[derive(Clone, Debug, PartialEq, Serialize, serde::Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum TestEnd {
    /// The target displacement was reached.
    Target,
    /// The driven force fell below the loss fraction of its peak.
    LossOfLoad,
    /// No equilibrium state was found (after all cut-backs) once the driven force had fallen at
    /// least 10 % below its peak: the sample failed (a brittle collapse the quasi-static model
    /// cannot follow); the curve up to there is kept and its numbers count.
    Collapse {
        /// The solver's message.
        message: String,
    },
    /// The solver stopped before the peak (no equilibrium, factorization failure, ...): the
    /// curve up to there is kept, the sample does not count in the statistics.
    Failed {
        /// The solver's message.
        message: String,
    },
}

impl TestEnd {
    /// Whether the sample's numbers are valid (the test reached a target, a loss of load or a
    /// post-peak collapse).
    pub fn is_valid(&self) -> bool {
        !matches!(self, TestEnd::Failed { .. })
    }
}

/// The result of a virtual test.
#[derive(Clone, Debug, PartialEq, Serialize, serde::Deserialize)]
pub struct TestResult {
    /// The curve.
    pub curve: Vec<CurvePoint>,
    /// Broken beams, in order.
    pub broken: Vec<BrokenBeam>,
    /// Stones found free-floating `(particle, event)`.
    pub floating: Vec<(usize, usize)>,
    /// Derived numbers.
    pub derived: Derived,
    /// Statistics.
    pub stats: RunStats,
    /// How it ended.
    pub end: TestEnd,
    /// Particle states kept for the HDF5/XDMF output (not transferred between ranks).
    #[serde(skip)]
    pub particle_states: Vec<ParticleState>,
    /// The Newton history of the last equilibrium attempts (with `SolverOptions::trace`; not
    /// transferred between ranks).
    #[serde(skip)]
    pub trace: Option<super::trace::Trace>,
}

/// The curve of the recorded `states`: the driven top-platen DOF `driven` (0 = U_x, 1 = U_y) of a
/// sample of width, height and thickness `(w, h, t_z)`.
pub(super) fn curve_of(states: &[StateRecord], driven: usize, (w, h, tz): (f64, f64, f64)) -> Vec<CurvePoint> {
    states
        .iter()
        .enumerate()
        .map(|(s, st)| {
            let d = st.platen[1][driven];
            let strain = d / h;
            let lat = (st.lateral_ux[1] - st.lateral_ux[0]) / w;
            CurvePoint {
                state: s,
                kind: st.kind,
                displacement: d,
                strain,
                stress: st.platen_force[1][driven] / (w * tz),
                lateral_strain: lat,
                broken: st.broken,
                external_work: st.external_work,
                stored: st.stored,
                dissipated: st.dissipated,
            }
        })
        .collect()
}

/// The derived numbers: the driven stages are those from `first_driven` on.
pub(super) fn derive(
    curve: &[CurvePoint],
    broken: &[BrokenBeam],
    first_driven: usize,
    states: &[StateRecord],
) -> Derived {
    // First loading state of the first driven stage with a non-zero strain and nothing broken.
    let first = curve
        .iter()
        .zip(states)
        .find(|(c, s)| s.stage == first_driven && c.strain != 0.0 && c.kind != StateKind::Relaxed)
        .map(|(c, _)| c);
    let (young_modulus, poisson) = match first {
        Some(c) => (c.stress / c.strain, -c.lateral_strain / c.strain),
        None => (f64::NAN, f64::NAN),
    };
    // First break during the driven stages (a shear test's preload may crack a few beams).
    let first_crack_stress = broken
        .iter()
        .find(|b| states.get(b.state).is_some_and(|s| s.stage >= first_driven && s.t > 0.0))
        .and_then(|b| curve.get(b.state))
        .map(|c| c.stress.abs());
    let (mut peak_stress, mut strain_at_peak) = (0.0, 0.0);
    for (c, _) in curve.iter().zip(states).filter(|(_, s)| s.stage >= first_driven) {
        if c.stress.abs() > peak_stress {
            peak_stress = c.stress.abs();
            strain_at_peak = c.strain;
        }
    }
    Derived { young_modulus, poisson, first_crack_stress, peak_stress, strain_at_peak }
}
