//! The virtual tests (SPEC §1, "Virtual tests"): uniaxial compression and tension, shear under
//! constant vertical compression, and the derived numbers.
//!
//! ```toml
//! [test]
//! type = "compression"      # or "tension"
//! max_strain = 2e-3         # |ε_yy| at the end (platen displacement / height)
//! steps = 50
//! # type = "shear", vertical_stress = 1e6, max_displacement = 6e-3, steps = 60, rotation = "fixed"
//! ```
//!
//! Platens are bonded to the bottom and top rows ([`super::dofs`]). Sign convention: tension
//! positive; `strain = U_y/H` (compression, tension) or `U_x/H` (shear), `stress = F/(W t_z)` with
//! `F` the top platen's force along the driven DOF. Lateral strain `(ū_x,right − ū_x,left)/W`.
//!
//! Derived numbers: `E = σ/ε` at the first recorded loading state (the response is linear
//! before the first break: secant = tangent), `ν = −ε_lat/ε_axial` there, first-crack stress =
//! the stress of the first pre-break state, peak = the largest `|σ|`, and the strain there.
use std::time::Instant;

use serde::{Deserialize, Serialize};

use super::dofs::{DofControl, DofMap};
use super::error::{positive, DemError};
use super::events::{BrokenBeam, LoadPoint, Solver, SolverOptions, StageEnd, StateKind};
use super::system::Model;
use crate::dem::mechanics::MechParams;
use crate::dem::sample::Sample;

/// Rotation of the top platen in the shear test.
#[derive(Clone, Copy, Debug, Default, Deserialize, Serialize, PartialEq, Eq)]
#[serde(rename_all = "snake_case")]
pub enum PlatenRotation {
    /// Θ = 0.
    #[default]
    Fixed,
    /// Zero moment.
    Free,
}

fn default_vertical_stress() -> f64 {
    1e6
}
fn default_preload_steps() -> usize {
    5
}

/// A virtual test.
#[derive(Clone, Debug, Deserialize, Serialize, PartialEq)]
#[serde(tag = "type", rename_all = "snake_case", deny_unknown_fields)]
pub enum VirtualTest {
    /// Uniaxial compression along y.
    Compression {
        /// Final |ε_yy|.
        max_strain: f64,
        /// Load steps.
        steps: usize,
    },
    /// Uniaxial tension along y.
    Tension {
        /// Final ε_yy.
        max_strain: f64,
        /// Load steps.
        steps: usize,
    },
    /// Shear under a constant vertical compression.
    Shear {
        /// Vertical compressive stress held on the top platen (Pa).
        #[serde(default = "default_vertical_stress")]
        vertical_stress: f64,
        /// Final horizontal displacement of the top platen (m).
        max_displacement: f64,
        /// Load steps of the horizontal displacement.
        steps: usize,
        /// Steps of the vertical preload.
        #[serde(default = "default_preload_steps")]
        preload_steps: usize,
        /// Platen rotation.
        #[serde(default)]
        rotation: PlatenRotation,
    },
}

impl VirtualTest {
    /// Checks the parameters.
    pub fn validate(&self) -> Result<(), DemError> {
        let steps = |s: usize| {
            if s == 0 {
                Err(DemError::InvalidParameter { field: "steps", value: "0".into(), expected: "at least 1" })
            } else {
                Ok(())
            }
        };
        match *self {
            VirtualTest::Compression { max_strain, steps: s } | VirtualTest::Tension { max_strain, steps: s } => {
                positive("max_strain", max_strain)?;
                steps(s)
            }
            VirtualTest::Shear { vertical_stress, max_displacement, steps: s, preload_steps, .. } => {
                if !(vertical_stress.is_finite() && vertical_stress >= 0.0) {
                    return Err(DemError::InvalidParameter {
                        field: "vertical_stress",
                        value: vertical_stress.to_string(),
                        expected: "a finite number >= 0 (compression)",
                    });
                }
                positive("max_displacement", max_displacement)?;
                steps(s)?;
                steps(preload_steps)
            }
        }
    }
}

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
    /// Broken beams: total, tension, shear.
    pub broken: [usize; 3],
    /// External work (J).
    pub external_work: f64,
    /// Stored energy (J).
    pub stored: f64,
    /// Dissipated energy: fracture, friction, relaxation (J).
    pub dissipated: [f64; 3],
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
    /// Load-increment cut-backs (halved steps or beam releases).
    pub cutbacks: usize,
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
}

/// Runs `test` on `sample` with the default solver options.
pub fn run_test(sample: &Sample, params: &MechParams, test: &VirtualTest) -> Result<TestResult, DemError> {
    run_test_with(sample, params, test, SolverOptions::default())
}

/// Runs `test` on `sample` with explicit solver options.
pub fn run_test_with(
    sample: &Sample,
    params: &MechParams,
    test: &VirtualTest,
    opts: SolverOptions,
) -> Result<TestResult, DemError> {
    test.validate()?;
    let clock = Instant::now();
    use DofControl::{Force, Prescribed};
    let (w, h, tz) = (sample.width, sample.height, params.t_z);
    let fixed = [Prescribed; 3];
    // (top control, driven top dof, stages: (target load, steps))
    let (top, driven, stages): ([DofControl; 3], usize, Vec<(LoadPoint, usize)>) = match *test {
        VirtualTest::Compression { max_strain, steps } | VirtualTest::Tension { max_strain, steps } => {
            let sign = if matches!(test, VirtualTest::Compression { .. }) { -1.0 } else { 1.0 };
            let target = LoadPoint { prescribed: vec![0.0, 0.0, 0.0, 0.0, sign * max_strain * h, 0.0], forces: vec![] };
            (fixed, 1, vec![(target, steps)])
        }
        VirtualTest::Shear { vertical_stress, max_displacement, steps, preload_steps, rotation } => {
            let fy = -vertical_stress * w * tz;
            let (ctl, forces) = match rotation {
                PlatenRotation::Fixed => ([Prescribed, Force, Prescribed], vec![fy]),
                PlatenRotation::Free => ([Prescribed, Force, Force], vec![fy, 0.0]),
            };
            let n_p = if rotation == PlatenRotation::Fixed { 5 } else { 4 };
            let mut pre = vec![0.0; n_p];
            let zero_f = vec![0.0; forces.len()];
            let _ = &zero_f;
            let preload = LoadPoint { prescribed: pre.clone(), forces: forces.clone() };
            pre[3] = max_displacement;
            let shear = LoadPoint { prescribed: pre, forces };
            (ctl, 0, vec![(preload, preload_steps), (shear, steps)])
        }
    };
    let map = DofMap::new(sample, [fixed, top])?;
    let model = Model::new(sample, params, map)?;
    let n_f = model.map.forced.len();
    let n_p = model.map.prescribed.len();
    let initial = LoadPoint { prescribed: vec![0.0; n_p], forces: vec![0.0; n_f] };
    let mut solver = Solver::new(model, opts, initial)?;
    let mut end = TestEnd::Target;
    let n_stages = stages.len();
    let outcome = solver.start().and_then(|()| {
        for (k, (target, steps)) in stages.iter().enumerate() {
            let monitor = if k + 1 == n_stages { Some((1, driven)) } else { None };
            if solver.run_stage(target, *steps, monitor)? == StageEnd::LossOfLoad {
                end = TestEnd::LossOfLoad;
                break;
            }
        }
        Ok(())
    });
    if let Err(e) = outcome {
        // Keep what was recorded; classify by the driven force's history in the last stage.
        let last_stage = solver.states.last().map_or(0, |s| s.stage);
        let forces: Vec<f64> = solver
            .states
            .iter()
            .filter(|s| s.stage == last_stage && last_stage + 1 == n_stages)
            .map(|s| s.platen_force[1][driven].abs())
            .collect();
        let peak = forces.iter().cloned().fold(0.0, f64::max);
        let now = forces.last().copied().unwrap_or(0.0);
        let message = e.to_string();
        end = if peak > 0.0 && now <= 0.9 * peak && !solver.broken.is_empty() {
            TestEnd::Collapse { message }
        } else {
            TestEnd::Failed { message }
        };
    }
    let curve: Vec<CurvePoint> = solver
        .states
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
        .collect();
    let derived = derive(&curve, &solver.broken, n_stages - 1, &solver.states);
    let loss = end == TestEnd::LossOfLoad;
    let (factorizations, _) = solver.factor_stats();
    Ok(TestResult {
        stats: RunStats {
            events: solver.broken.len(),
            solves: solver.n_solves,
            factorizations,
            seconds: clock.elapsed().as_secs_f64(),
            loss_of_load: loss,
            cutbacks: solver.n_cutbacks,
        },
        end,
        curve,
        broken: solver.broken.clone(),
        floating: solver.floating.clone(),
        derived,
    })
}

fn derive(
    curve: &[CurvePoint],
    broken: &[BrokenBeam],
    last_stage: usize,
    states: &[super::events::StateRecord],
) -> Derived {
    // First loading state of the driven stage with a non-zero strain and nothing broken.
    let first = curve
        .iter()
        .zip(states)
        .find(|(c, s)| s.stage == last_stage && c.strain != 0.0 && c.kind != StateKind::Relaxed)
        .map(|(c, _)| c);
    let (young_modulus, poisson) = match first {
        Some(c) => (c.stress / c.strain, -c.lateral_strain / c.strain),
        None => (f64::NAN, f64::NAN),
    };
    // First break during the driven stage (a shear test's preload may crack a few beams).
    let first_crack_stress = broken
        .iter()
        .find(|b| states.get(b.state).is_some_and(|s| s.stage == last_stage && s.t > 0.0))
        .and_then(|b| curve.get(b.state))
        .map(|c| c.stress.abs());
    let (mut peak_stress, mut strain_at_peak) = (0.0, 0.0);
    for (c, _) in curve.iter().zip(states).filter(|(_, s)| s.stage == last_stage) {
        if c.stress.abs() > peak_stress {
            peak_stress = c.stress.abs();
            strain_at_peak = c.strain;
        }
    }
    Derived { young_modulus, poisson, first_crack_stress, peak_stress, strain_at_peak }
}
