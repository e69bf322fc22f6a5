//! Running a virtual test ([`super::virtual_test`]): the protocol's stages one after the other
//! on one solver, stopped at the target or at a loss of load (that module's "Stopping"), or by
//! an error that `classify_stop` names a post-peak collapse or a failure; then the curve, the
//! derived numbers and the statistics ([`TestResult`]).
//!
//! With checkpoints ([`run_test_checkpointed`], [`super::checkpoint`]) a sink is asked after
//! each load step whether one is due and gets one at the end; a running test's checkpoint
//! continues in a solver resumed from its state, in the stage walk it stood in, the cyclic
//! branches before it counted as the uninterrupted test counted them. A finished test's
//! checkpoint gives its result without a solver ([`finished_result`]).

use std::time::Instant;

use super::checkpoint::{CheckpointSink, Finished, TestCheckpoint};
use super::dofs::{DofControl, DofMap};
use super::error::DemError;
use super::options::SolverOptions;
use super::records::{LoadPoint, Observer, StageEnd, StateRecord};
use super::snapshots::{ParticleStates, Recorder};
use super::solver::Solver;
use super::state::SolverState;
use super::system::Model;
use super::test_result::{curve_of, derive, RunStats, TestEnd, TestResult};
use super::virtual_test::{protocol, Stage, VirtualTest};
use super::walk::StageWalk;
use crate::dem::mechanics::MechParams;
use crate::dem::sample::Sample;

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
    run_test_checkpointed(sample, params, test, TestRun { opts, states, report, ..Default::default() })
}

/// How a test is run besides its sample, law and protocol ([`run_test_checkpointed`]): the
/// solver's options, the particle states kept, a report of the recorded states and the
/// checkpoints. The default is [`run_test_with`]'s: default options, no particle states
/// ([`ParticleStates::None`]), no report, no checkpoints.
pub struct TestRun<'a> {
    /// The solver's options.
    pub opts: SolverOptions,
    /// The particle states kept in [`TestResult::particle_states`].
    pub states: ParticleStates,
    /// Called on every recorded state (its index and record) as the test goes.
    pub report: Option<Report<'a>>,
    /// Where the checkpoints go, and the one the test continues from.
    pub checkpoints: Checkpoints<'a>,
}

impl Default for TestRun<'_> {
    fn default() -> Self {
        TestRun {
            opts: SolverOptions::default(),
            states: ParticleStates::None,
            report: None,
            checkpoints: Checkpoints::default(),
        }
    }
}

/// A test's checkpoints ([`super::checkpoint`]): where they go, and the one it continues from.
#[derive(Default)]
pub struct Checkpoints<'a> {
    /// Receives a checkpoint after every load step it finds due, and one at the end (finished).
    pub sink: Option<Box<dyn CheckpointSink + 'a>>,
    /// A running test's checkpoint to continue from (a finished test's result is
    /// [`finished_result`]); its fingerprint is the caller's to check.
    pub resume: Option<TestCheckpoint>,
}

/// Stamps each checkpoint with the test's wall time so far.
struct Clocked<'a> {
    inner: Box<dyn CheckpointSink + 'a>,
    clock: Instant,
    before: f64,
}

impl CheckpointSink for Clocked<'_> {
    fn due(&mut self, state: &SolverState) -> bool {
        self.inner.due(state)
    }

    fn write(&mut self, mut c: TestCheckpoint) -> Result<(), DemError> {
        c.seconds = self.before + self.clock.elapsed().as_secs_f64();
        self.inner.write(c)
    }
}

/// Runs `test` on `sample` as `run` asks ([`TestRun`]): [`run_test_observed`] with checkpoints,
/// written to `run.checkpoints.sink` as the test goes and at its end, and continued from
/// `run.checkpoints.resume` when given. A resumed test's particle states start at the
/// resumption; its counters and wall time add to the checkpoint's (its factorizations are this
/// run's: the workspace is not checkpointed). Errors: those of [`run_test`], a finished test's
/// checkpoint to resume from, and the sink's ([`DemError::Checkpoint`]), which end the test
/// without a result.
pub fn run_test_checkpointed<'a>(
    sample: &'a Sample,
    params: &MechParams,
    test: &VirtualTest,
    run: TestRun<'a>,
) -> Result<TestResult, DemError> {
    let TestRun { opts, states, report, checkpoints } = run;
    test.validate()?;
    let clock = Instant::now();
    let (w, h, tz) = (sample.width, sample.height, params.t_z);
    let (top, driven, stages, first_driven) = protocol(test, w, h, tz);
    let map = DofMap::new(sample, [[DofControl::Prescribed; 3], top])?;
    let model = Model::new(sample, params, map)?;
    let before = checkpoints.resume.as_ref().map_or(0.0, |c| c.seconds);
    let (mut solver, walk) = solver_from(model, opts, checkpoints.resume)?;
    let mut sink = checkpoints.sink.map(|inner| Clocked { inner, clock, before });
    let recorder = Recorder::new(states, first_driven, (1, driven));
    solver.diag.observer = match report {
        Some(report) => Some(Box::new(Reporting { recorder: recorder.observer(), report })),
        None => recorder.observer(),
    };
    let sink_ref = sink.as_mut().map(|s| s as &mut dyn CheckpointSink);
    let end = match run_stages(&mut solver, &stages, driven, walk, sink_ref) {
        Ok(end) => end,
        Err(e @ DemError::Checkpoint(_)) => return Err(e),
        Err(e) => classify_stop(e.to_string(), &solver, &stages, first_driven, driven),
    };
    solver.diag.observer = None;
    let result = result_of(&mut solver, sample, &recorder, end, (driven, first_driven), before + secs(clock));
    if let Some(mut sink) = sink {
        let finished = Finished { end: result.end.clone(), stats: result.stats.clone() };
        let (state, counters) = (solver.state().clone(), solver.diag.counters);
        sink.write(TestCheckpoint { state, walk: None, counters, seconds: 0.0, finished: Some(finished) })?;
    }
    Ok(result)
}

fn secs(clock: Instant) -> f64 {
    clock.elapsed().as_secs_f64()
}

/// A new solver at the unloaded state, or one that continues a running test's checkpoint (with
/// its counters and the walk of the stage it stood in).
fn solver_from(
    model: Model<'_>,
    opts: SolverOptions,
    resume: Option<TestCheckpoint>,
) -> Result<(Solver<'_>, Option<StageWalk>), DemError> {
    match resume {
        None => {
            let n = (model.map.prescribed.len(), model.map.forced.len());
            let initial = LoadPoint { prescribed: vec![0.0; n.0], forces: vec![0.0; n.1] };
            Ok((Solver::new(model, opts, initial)?, None))
        }
        Some(TestCheckpoint { state, walk: Some(walk), counters, finished: None, .. }) => {
            let mut solver = Solver::resume(model, opts, state)?;
            solver.diag.counters = counters;
            Ok((solver, Some(walk)))
        }
        Some(_) => Err(DemError::InvalidParameter {
            field: "checkpoint",
            value: "a finished test's".into(),
            expected: "a running test's checkpoint (a finished test's result: finished_result)",
        }),
    }
}

/// The largest |driven force| of the recorded states of stage `k`.
fn largest_of(states: &[StateRecord], k: usize, driven: usize) -> f64 {
    states.iter().filter(|s| s.stage == k).map(|s| s.platen_force[1][driven].abs()).fold(0.0, f64::max)
}

/// Runs the protocol's stages to the end or to a loss of load: from the unloaded state, or
/// (`walk` given) from the stage a checkpoint stood in, the branches before it counted as the
/// uninterrupted test counted them. After each load step `sink` is asked for a checkpoint.
fn run_stages(
    solver: &mut Solver,
    stages: &[Stage],
    driven: usize,
    mut walk: Option<StageWalk>,
    mut sink: Option<&mut dyn CheckpointSink>,
) -> Result<TestEnd, DemError> {
    let first = if walk.is_some() { solver.state().stage } else { 0 };
    if walk.is_none() {
        solver.start()?;
    }
    let mut envelope = CyclicEnvelope::default();
    for (k, stage) in stages.iter().enumerate() {
        if k >= first {
            let monitor = stage.monitor.then_some((1, driven));
            let w = walk.take().unwrap_or_else(|| solver.stage_walk(&stage.target, stage.steps));
            if solver.continue_stage(w, monitor, sink.as_mut().map(|s| &mut **s as _))? == StageEnd::LossOfLoad {
                return Ok(TestEnd::LossOfLoad);
            }
        }
        if let Some(towards) = stage.towards {
            envelope.branch(towards, largest_of(solver.states(), k, driven));
            if k >= first && !solver.broken().is_empty() && envelope.lost(solver.problem.opts.loss_fraction) {
                return Ok(TestEnd::LossOfLoad);
            }
        }
    }
    Ok(TestEnd::Target)
}

/// The test's result once its stages ended as `end`: its curve, derived numbers, statistics
/// (`seconds` of wall time) and the particle states `recorder` kept. `(driven, first_driven)`:
/// the driven top DOF and the first stage whose force is the test's.
fn result_of(
    solver: &mut Solver,
    sample: &Sample,
    recorder: &Recorder,
    end: TestEnd,
    (driven, first_driven): (usize, usize),
    seconds: f64,
) -> TestResult {
    let dims = (sample.width, sample.height, solver.model().params.t_z);
    let curve = curve_of(solver.states(), driven, dims);
    let derived = derive(&curve, solver.broken(), first_driven, solver.states());
    let (factorizations, _) = solver.factor_stats();
    let last = solver.states().len().checked_sub(1).map(|i| (i, solver.state().z_commit.as_slice()));
    let particle_states = recorder.finish(&solver.model().map, sample.particles.len(), last);
    let c = solver.diag.counters;
    TestResult {
        stats: RunStats {
            events: solver.broken().len(),
            solves: c.solves,
            factorizations,
            seconds,
            loss_of_load: end == TestEnd::LossOfLoad,
            cutbacks: c.cutbacks,
            contact_events: c.contact_events,
            continued_steps: c.continued_steps,
            continuations: c.continuations,
            imbalance_cutbacks: c.imbalance_cutbacks,
            snaps_in_steps: c.snaps_in_steps,
            updates_in_place: solver.ws.operator.factor.updates_in_place(),
        },
        end,
        curve,
        broken: solver.broken().to_vec(),
        floating: solver.state().floating.clone(),
        derived,
        particle_states,
        trace: solver.diag.trace.take(),
    }
}

/// The result of a finished test from its last checkpoint, as the test returned it (without
/// particle states or trace). Errors: a checkpoint of a test still running.
pub fn finished_result(
    sample: &Sample,
    params: &MechParams,
    test: &VirtualTest,
    c: &TestCheckpoint,
) -> Result<TestResult, DemError> {
    let f = c.finished.as_ref().ok_or_else(|| DemError::InvalidParameter {
        field: "checkpoint",
        value: "a running test's".into(),
        expected: "a finished test's checkpoint",
    })?;
    let (w, h, tz) = (sample.width, sample.height, params.t_z);
    let (_, driven, _, first_driven) = protocol(test, w, h, tz);
    let records = &c.state.records;
    let curve = curve_of(records, driven, (w, h, tz));
    let derived = derive(&curve, &c.state.broken, first_driven, records);
    Ok(TestResult {
        curve,
        broken: c.state.broken.clone(),
        floating: c.state.floating.clone(),
        derived,
        stats: f.stats.clone(),
        end: f.end.clone(),
        particle_states: Vec::new(),
        trace: None,
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
