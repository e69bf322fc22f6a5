//! The virtual tests (paper §2.1, "Virtual tests"): uniaxial compression and tension, shear under
//! constant vertical compression, their cyclic versions, and the derived numbers.
//!
//! ```toml
//! [test]
//! type = "compression"      # or "tension"
//! max_strain = 2e-3         # |ε_yy| at the end (platen displacement / height)
//! steps = 50
//! # type = "shear", vertical_stress = 1e6, max_displacement = 6e-3, steps = 60, rotation = "fixed"
//! # type = "cyclic_tension_compression", amplitudes = [5e-5, 1e-4, 2e-4], compression_ratio = 1.0,
//! #        steps_per_half_cycle = 20
//! # type = "cyclic_shear", vertical_stress = 1e6, amplitudes = [1e-3, 2e-3, 4e-3],
//! #        steps_per_half_cycle = 20, rotation = "fixed"
//! ```
//!
//! **Cyclic protocol** ([`cyclic_protocol`]). Cycle `k` drives the platen from where it is to
//! `+a_k` and then to `−c a_k` (`c` = `compression_ratio` for tension–compression, 1 for shear);
//! after the last cycle it returns to 0. Each branch is one load stage, with
//! `⌈n |Δ| / ((1 + c) a_k)⌉` steps, `n` = `steps_per_half_cycle` (a full half cycle `+a_k → −c a_k`
//! gets `n` steps). Loading and unloading go through the same event-driven solver: broken beams
//! stay broken, cracks close through contacts, closed cracks slide with Coulomb friction, so the
//! loops show stiffness degradation, crack closure and frictional hysteresis. Amplitudes are
//! strains `U_y/H` (tension–compression) or top-platen displacements in m (shear).
//!
//! **Stopping.** Monotonic tests: the target, or loss of load (the driven force below
//! `loss_fraction` × its peak after a break). Cyclic tests: the end of the protocol, or loss of
//! load in every direction visited: the largest |force| of the latest branch towards `+` (and
//! towards `−`) below `loss_fraction` × that direction's peak.
//!
//! Platens are bonded to the bottom and top rows ([`super::dofs`]). Sign convention: tension
//! positive; `strain = U_y/H` (compression, tension) or `U_x/H` (shear), `stress = F/(W t_z)` with
//! `F` the top platen's force along the driven DOF. Lateral strain `(ū_x,right − ū_x,left)/W`.

use std::time::Instant;

use serde::{Deserialize, Serialize};

use super::dofs::{DofControl, DofMap};
use super::error::{non_negative, positive, DemError};
use super::options::SolverOptions;
use super::records::{LoadPoint, Observer, StageEnd, StateRecord};
use super::snapshots::{ParticleStates, Recorder};
use super::solver::Solver;
use super::system::Model;
use super::test_result::{curve_of, derive, RunStats, TestEnd, TestResult};
use crate::dem::mechanics::MechParams;
use crate::dem::sample::Sample;

/// Rotation of the top platen in the shear test.
#[derive(Clone, Copy, Debug, Default, Deserialize, Serialize, PartialEq, Eq, schemars::JsonSchema)]
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
#[derive(Clone, Debug, Deserialize, Serialize, PartialEq, schemars::JsonSchema)]
#[serde(tag = "type", rename_all = "snake_case", deny_unknown_fields)]
pub enum VirtualTest {
    /// Uniaxial compression along y.
    Compression {
        /// Final |ε_yy| [-].
        max_strain: f64,
        /// Load steps.
        steps: usize,
    },
    /// Uniaxial tension along y.
    Tension {
        /// Final ε_yy [-].
        max_strain: f64,
        /// Load steps.
        steps: usize,
    },
    /// Shear under a constant vertical compression.
    Shear {
        /// Vertical compressive stress held on the top platen [Pa].
        #[serde(default = "default_vertical_stress")]
        vertical_stress: f64,
        /// Final horizontal displacement of the top platen [m].
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
    /// Cycles of tension and compression along y, amplitudes increasing per cycle.
    CyclicTensionCompression {
        /// Tensile strain amplitude `ε_yy` [-] of each cycle, > 0, non-decreasing.
        amplitudes: Vec<f64>,
        /// Compressive amplitude over tensile amplitude (≥ 0; 0 = unload to zero strain only).
        #[serde(default = "one")]
        compression_ratio: f64,
        /// Load steps per half cycle (`+a → −c a`).
        steps_per_half_cycle: usize,
    },
    /// Cycles of horizontal top-platen displacement `±a_k` under a constant vertical compression.
    CyclicShear {
        /// Vertical compressive stress held on the top platen [Pa].
        #[serde(default = "default_vertical_stress")]
        vertical_stress: f64,
        /// Displacement amplitude of each cycle [m], > 0, non-decreasing.
        amplitudes: Vec<f64>,
        /// Load steps per half cycle (`+a → −a`).
        steps_per_half_cycle: usize,
        /// Steps of the vertical preload.
        #[serde(default = "default_preload_steps")]
        preload_steps: usize,
        /// Platen rotation.
        #[serde(default)]
        rotation: PlatenRotation,
    },
}

fn one() -> f64 {
    1.0
}

/// The branches of a cyclic protocol: `(target, steps)` with targets `+a_1, −c a_1, +a_2, …,
/// −c a_N, 0` (see the module documentation); zero-length branches are left out.
pub fn cyclic_protocol(amplitudes: &[f64], ratio: f64, steps_per_half_cycle: usize) -> Vec<(f64, usize)> {
    let n = steps_per_half_cycle.max(1) as f64;
    let mut out = Vec::with_capacity(2 * amplitudes.len() + 1);
    let mut at = 0.0f64;
    let mut push = |target: f64, span: f64, at: &mut f64| {
        let d = (target - *at).abs();
        if d > 0.0 {
            out.push((target, ((n * d / span) - 1e-9).ceil().max(1.0) as usize));
            *at = target;
        }
    };
    for &a in amplitudes {
        let span = (1.0 + ratio) * a;
        push(a, span, &mut at);
        push(-ratio * a, span, &mut at);
    }
    if let Some(&a) = amplitudes.last() {
        push(0.0, (1.0 + ratio) * a, &mut at);
    }
    out
}

fn check_amplitudes(amplitudes: &[f64]) -> Result<(), DemError> {
    if amplitudes.is_empty() {
        return Err(DemError::InvalidParameter {
            field: "amplitudes",
            value: "[]".into(),
            expected: "at least one amplitude",
        });
    }
    for (k, &a) in amplitudes.iter().enumerate() {
        positive("amplitudes", a)?;
        if k > 0 && a < amplitudes[k - 1] {
            return Err(DemError::InvalidParameter {
                field: "amplitudes",
                value: format!("{a} after {}", amplitudes[k - 1]),
                expected: "amplitudes that do not decrease from one cycle to the next",
            });
        }
    }
    Ok(())
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
        let half_cycle_steps = |s: usize| {
            if s == 0 {
                Err(DemError::InvalidParameter {
                    field: "steps_per_half_cycle",
                    value: "0".into(),
                    expected: "at least 1",
                })
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
                non_negative("vertical_stress", vertical_stress)?;
                positive("max_displacement", max_displacement)?;
                steps(s)?;
                steps(preload_steps)
            }
            VirtualTest::CyclicTensionCompression { ref amplitudes, compression_ratio, steps_per_half_cycle } => {
                check_amplitudes(amplitudes)?;
                non_negative("compression_ratio", compression_ratio)?;
                half_cycle_steps(steps_per_half_cycle)
            }
            VirtualTest::CyclicShear {
                vertical_stress, ref amplitudes, steps_per_half_cycle, preload_steps, ..
            } => {
                non_negative("vertical_stress", vertical_stress)?;
                check_amplitudes(amplitudes)?;
                half_cycle_steps(steps_per_half_cycle)?;
                steps(preload_steps)
            }
        }
    }

    /// Whether the test cycles (several loading and unloading branches).
    pub fn is_cyclic(&self) -> bool {
        matches!(self, VirtualTest::CyclicTensionCompression { .. } | VirtualTest::CyclicShear { .. })
    }

    /// Whether the driven DOF is the top platen's horizontal displacement (shear tests).
    pub fn is_shear(&self) -> bool {
        matches!(self, VirtualTest::Shear { .. } | VirtualTest::CyclicShear { .. })
    }
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
    run_test_recording(sample, params, test, opts, ParticleStates::None)
}

/// A report of a test's recorded states, called with each state's index and record as it is
/// committed ([`run_test_observed`]).
pub type Report<'a> = Box<dyn FnMut(usize, &StateRecord) + 'a>;

/// The particle-state recorder (if any) and a report of every recorded state, as one observer.
struct Reporting<'a> {
    recorder: Option<Box<dyn Observer + 'a>>,
    report: Report<'a>,
}

impl Observer for Reporting<'_> {
    fn recorded(&mut self, index: usize, record: &StateRecord, z: &[f64]) {
        if let Some(r) = self.recorder.as_mut() {
            r.recorded(index, record, z);
        }
        (self.report)(index, record);
    }
}

/// One load stage of a test's protocol.
struct Stage {
    target: LoadPoint,
    steps: usize,
    /// Monotonic tests: `run_stage` watches the driven force for loss of load.
    monitor: bool,
    /// Cyclic branches: the direction (±1) of the amplitude the branch ends at; `None` for a
    /// preload, a monotonic stage or the final return to zero.
    towards: Option<f64>,
}

/// The platen controls, the driven top DOF (0 = U_x, 1 = U_y), the stages and the first stage
/// whose force is the test's driven force.
fn protocol(test: &VirtualTest, w: f64, h: f64, tz: f64) -> ([DofControl; 3], usize, Vec<Stage>, usize) {
    use DofControl::{Force, Prescribed};
    let fixed = [Prescribed; 3];
    let axial = |value: f64| LoadPoint { prescribed: vec![0.0, 0.0, 0.0, 0.0, value * h, 0.0], forces: vec![] };
    // Shear: the top platen holds the vertical force; U_x (and Θ when fixed) prescribed.
    let shear_setup = |vertical_stress: f64, rotation: PlatenRotation| {
        let fy = -vertical_stress * w * tz;
        let (ctl, forces) = match rotation {
            PlatenRotation::Fixed => ([Prescribed, Force, Prescribed], vec![fy]),
            PlatenRotation::Free => ([Prescribed, Force, Force], vec![fy, 0.0]),
        };
        let n_p = if rotation == PlatenRotation::Fixed { 5 } else { 4 };
        let at = move |ux: f64| {
            let mut p = vec![0.0; n_p];
            p[3] = ux;
            LoadPoint { prescribed: p, forces: forces.clone() }
        };
        (ctl, at)
    };
    let cyclic = |amplitudes: &[f64], ratio: f64, n: usize, point: &dyn Fn(f64) -> LoadPoint| -> Vec<Stage> {
        cyclic_protocol(amplitudes, ratio, n)
            .into_iter()
            .map(|(target, steps)| Stage {
                target: point(target),
                steps,
                monitor: false,
                towards: (target != 0.0).then(|| target.signum()),
            })
            .collect()
    };
    match *test {
        VirtualTest::Compression { max_strain, steps } | VirtualTest::Tension { max_strain, steps } => {
            let sign = if matches!(test, VirtualTest::Compression { .. }) { -1.0 } else { 1.0 };
            (fixed, 1, vec![Stage { target: axial(sign * max_strain), steps, monitor: true, towards: None }], 0)
        }
        VirtualTest::Shear { vertical_stress, max_displacement, steps, preload_steps, rotation } => {
            let (ctl, at) = shear_setup(vertical_stress, rotation);
            let stages = vec![
                Stage { target: at(0.0), steps: preload_steps, monitor: false, towards: None },
                Stage { target: at(max_displacement), steps, monitor: true, towards: None },
            ];
            (ctl, 0, stages, 1)
        }
        VirtualTest::CyclicTensionCompression { ref amplitudes, compression_ratio, steps_per_half_cycle } => {
            (fixed, 1, cyclic(amplitudes, compression_ratio, steps_per_half_cycle, &axial), 0)
        }
        VirtualTest::CyclicShear { vertical_stress, ref amplitudes, steps_per_half_cycle, preload_steps, rotation } => {
            let (ctl, at) = shear_setup(vertical_stress, rotation);
            let mut stages = vec![Stage { target: at(0.0), steps: preload_steps, monitor: false, towards: None }];
            stages.extend(cyclic(amplitudes, 1.0, steps_per_half_cycle, &at));
            (ctl, 0, stages, 1)
        }
    }
}

/// Loss of load of a cyclic test: per direction, the peak |force| so far and the largest |force|
/// of the latest branch towards it.
#[derive(Default)]
struct CyclicEnvelope {
    peak: [f64; 2],
    latest: [Option<f64>; 2],
}

impl CyclicEnvelope {
    fn branch(&mut self, towards: f64, largest: f64) {
        let k = usize::from(towards < 0.0);
        self.peak[k] = self.peak[k].max(largest);
        self.latest[k] = Some(largest);
    }

    /// Every direction visited carries less than `fraction` of its peak.
    fn lost(&self, fraction: f64) -> bool {
        let visited: Vec<usize> = (0..2).filter(|&k| self.latest[k].is_some()).collect();
        !visited.is_empty()
            && visited
                .iter()
                .all(|&k| self.peak[k] > 0.0 && self.latest[k].is_some_and(|l| l < fraction * self.peak[k]))
    }
}

/// Runs `test` on `sample` with explicit solver options, keeping the particle states `states`
/// asks for in [`TestResult::particle_states`].
pub fn run_test_recording(
    sample: &Sample,
    params: &MechParams,
    test: &VirtualTest,
    opts: SolverOptions,
    states: ParticleStates,
) -> Result<TestResult, DemError> {
    run_test_observed(sample, params, test, opts, states, None)
}

/// [`run_test_recording`], with `report` called on every recorded state (its index and record) as
/// the test goes, e.g. to print the progress of a long test.
pub fn run_test_observed<'a>(
    sample: &'a Sample,
    params: &MechParams,
    test: &VirtualTest,
    opts: SolverOptions,
    states: ParticleStates,
    report: Option<Report<'a>>,
) -> Result<TestResult, DemError> {
    test.validate()?;
    let clock = Instant::now();
    let (w, h, tz) = (sample.width, sample.height, params.t_z);
    let (top, driven, stages, first_driven) = protocol(test, w, h, tz);
    let map = DofMap::new(sample, [[DofControl::Prescribed; 3], top])?;
    let model = Model::new(sample, params, map)?;
    let n_f = model.map.forced.len();
    let n_p = model.map.prescribed.len();
    let initial = LoadPoint { prescribed: vec![0.0; n_p], forces: vec![0.0; n_f] };
    let mut solver = Solver::new(model, opts, initial)?;
    let recorder = Recorder::new(states, first_driven, (1, driven));
    solver.observer = match report {
        Some(report) => Some(Box::new(Reporting { recorder: recorder.observer(), report })),
        None => recorder.observer(),
    };
    let mut end = TestEnd::Target;
    let mut envelope = CyclicEnvelope::default();
    let outcome = solver.start().and_then(|()| {
        for (k, stage) in stages.iter().enumerate() {
            let monitor = stage.monitor.then_some((1, driven));
            if solver.run_stage(&stage.target, stage.steps, monitor)? == StageEnd::LossOfLoad {
                end = TestEnd::LossOfLoad;
                break;
            }
            if let Some(towards) = stage.towards {
                let largest = solver
                    .states()
                    .iter()
                    .filter(|s| s.stage == k)
                    .map(|s| s.platen_force[1][driven].abs())
                    .fold(0.0, f64::max);
                envelope.branch(towards, largest);
                if !solver.broken().is_empty() && envelope.lost(opts.loss_fraction) {
                    end = TestEnd::LossOfLoad;
                    break;
                }
            }
        }
        Ok(())
    });
    if let Err(e) = outcome {
        end = classify_stop(e.to_string(), &solver, &stages, first_driven, driven);
    }
    let curve = curve_of(solver.states(), driven, (w, h, tz));
    let derived = derive(&curve, solver.broken(), first_driven, solver.states());
    let loss = end == TestEnd::LossOfLoad;
    let (factorizations, _) = solver.factor_stats();
    let updates_in_place = solver.operator.factor.updates_in_place();
    solver.observer = None;
    let last = solver.states().len().checked_sub(1).map(|i| (i, solver.state().z_commit.as_slice()));
    let c = solver.counters;
    let particle_states = recorder.finish(&solver.model().map, sample.particles.len(), last);
    Ok(TestResult {
        stats: RunStats {
            events: solver.broken().len(),
            solves: c.solves,
            factorizations,
            seconds: clock.elapsed().as_secs_f64(),
            loss_of_load: loss,
            cutbacks: c.cutbacks,
            contact_events: c.contact_events,
            continued_steps: c.continued_steps,
            continuations: c.continuations,
            imbalance_cutbacks: c.imbalance_cutbacks,
            snaps_in_steps: c.snaps_in_steps,
            updates_in_place,
        },
        end,
        curve,
        broken: solver.broken().to_vec(),
        floating: solver.state().floating.clone(),
        derived,
        particle_states,
        trace: solver.trace.take(),
    })
}

/// How a test the solver stopped ended: a post-peak `Collapse` when, after a break, the driven
/// force had fallen at least 10 % below its peak (monotonic: |F| over the driven stage; cyclic:
/// the force along the current branch's direction, which must still be on its loading side),
/// else `Failed`.
fn classify_stop(message: String, solver: &Solver, stages: &[Stage], first_driven: usize, driven: usize) -> TestEnd {
    let current = solver.states().last().map_or(0, |s| s.stage);
    let force = |s: &StateRecord| s.platen_force[1][driven];
    let along: Vec<f64> = match stages.get(current) {
        Some(Stage { towards: Some(dir), .. }) => {
            solver.states().iter().filter(|s| s.stage >= first_driven).map(|s| dir * force(s)).collect()
        }
        Some(Stage { monitor: true, .. }) => {
            solver.states().iter().filter(|s| s.stage == current).map(|s| force(s).abs()).collect()
        }
        _ => Vec::new(),
    };
    let peak = along.iter().cloned().fold(0.0, f64::max);
    let now = along.last().copied().unwrap_or(0.0);
    let loading_side = now >= 0.0;
    if peak > 0.0 && loading_side && now <= 0.9 * peak && !solver.broken().is_empty() {
        TestEnd::Collapse { message }
    } else {
        TestEnd::Failed { message }
    }
}
