//! DEM virtual tests on a batch of random samples, spread over the ranks with dynamic scheduling
//! (`parallel::run_batch`: samples differ in cost, one that cracks early ends early).
//!
//! Outputs (rank 0), in the results folder:
//! * `sample-KKK/curve.csv`: every recorded equilibrium state (strain, stress, lateral strain,
//!   broken beams by mode, external work, stored and dissipated energy);
//! * `sample-KKK/cracks-first.svg`, `cracks-peak.svg`, `cracks-end.svg`: the stones with the
//!   broken beams drawn along their facets, tension in red, shear/rotation in blue;
//! * `sample-KKK/particles.xdmf` + `particles.h5`: the particle states (`[analysis]
//!   particle_states`), written by the rank that ran the sample ([`crate::dem::output`]);
//! * `sample-KKK/curve.png` (cyclic tests): that sample's hysteresis loops;
//! * `stress_strain.png`: all samples' curves, with the experiment's modulus line and its
//!   first-crack and peak stresses overlaid when `[experiment]` gives them;
//! * `summary.json`: per sample E, ν, first-crack stress, peak stress, strain at peak, events,
//!   timing and how the factor followed the breaks (`factor_updates`); their mean and sample standard deviation (`null` when no sample has the quantity:
//!   ν in shear, first crack in a sample that never cracked); the experiment's values beside them.
//!
//! * `checkpoints/sample-KKK.ckpt`: each sample's test as it goes and once it ended
//!   (`[analysis] checkpoint_minutes`, [`super::dem_checkpoint`]); `--restart` continues from them.
//!
//! Signs: the curve files keep the solver's convention (tension positive); the chart plots
//! compression tests as shortening and compressive stress, both positive.
use super::dem_checkpoint::{checkpoint_file, read_checkpoint, FileSink};
use crate::config::DemJob;
use crate::dem::error::TestFailure;
use crate::dem::output::write_particle_states;
use crate::dem::sample::{draw_svg, Sample, SvgStyle};
use crate::dem::solver::{
    finished_result, run_test_checkpointed, CheckpointSink, Checkpoints, FailureModeTag, Fingerprint, ParticleStates,
    Report, SolverOptions, StateRecord, TestEnd, TestResult, TestRun, VirtualTest,
};
use crate::error::{Error, JobError};
use crate::identify::Stat;
use crate::io::summary::with_message;
use crate::parallel::{agree, global_sum, run_batch, Context, Log, Phases};
use crate::plot::{LineChart, SeriesStyle};
use std::fmt::Write as _;
use std::path::Path;
use std::time::{Duration, Instant};

/// One sample's numbers.
#[derive(Debug, Clone, serde::Serialize)]
pub struct SampleReport {
    /// Sample number.
    pub sample: usize,
    /// Its seed.
    pub seed: u64,
    /// Derived numbers (Pa, -), or the error that stopped it before anything was recorded
    /// (written as its message).
    #[serde(serialize_with = "with_message")]
    pub result: Result<crate::dem::solver::Derived, TestFailure>,
    /// How the test ended (target, loss of load, post-peak collapse, failure); `None` when it
    /// could not start.
    pub end: Option<TestEnd>,
    /// Whether its numbers count in the statistics.
    pub counted: bool,
    /// Beam-break events.
    pub events: usize,
    /// Wall time of the test [s].
    pub seconds: f64,
    /// How the factor followed the breaks: "in_place" or "woodbury" (`[analysis]
    /// factor_updates`); `None` when the test could not start.
    pub factor_updates: Option<crate::dem::solver::FactorUpdates>,
}

/// What a DEM batch reports.
#[derive(Debug, Clone, serde::Serialize)]
pub struct DemSummary {
    /// The test.
    pub test: VirtualTest,
    /// Ranks.
    pub ranks: usize,
    /// Beams broken together per equilibrium (1: the exact algorithm; more: an approximation).
    pub breaks_per_equilibrium: usize,
    /// Samples.
    pub samples: Vec<SampleReport>,
    /// Young modulus (or τ/γ for shear) [Pa].
    pub young_modulus: Option<Stat>,
    /// Poisson ratio (none for shear tests).
    pub poisson: Option<Stat>,
    /// First-crack stress [Pa] (samples that cracked).
    pub first_crack_stress: Option<Stat>,
    /// Peak stress [Pa].
    pub peak_stress: Option<Stat>,
    /// Strain at peak.
    pub strain_at_peak: Option<Stat>,
    /// The experiment, if given.
    pub experiment: Option<crate::config::ExperimentConfig>,
    /// Wall time of the whole batch [s].
    pub seconds: f64,
    /// Beam-break events per second of test time, over the batch.
    pub events_per_second: f64,
}

fn sample_config(job: &DemJob, k: usize) -> crate::dem::sample::SampleConfig {
    let mut c = job.spec.sample.clone();
    c.seed = job.spec.sample.seed.wrapping_add(k as u64);
    c
}

/// Collective. Runs the batch and writes the outputs; `restart` continues a killed run from the
/// samples' checkpoints ([`super::dem_checkpoint`]).
pub fn run(ctx: &Context, job: &DemJob, restart: bool) -> Result<DemSummary, Error> {
    let n = job.spec.analysis.samples;
    let mut phases = Phases::default();
    ctx.log.info(format!("DEM: {n} sample(s) of {:?}, over {} rank(s)", job.spec.test, ctx.size));
    let analysis = &job.spec.analysis;
    let opts = SolverOptions {
        breaks_per_equilibrium: analysis.breaks_per_equilibrium,
        factor_updates: analysis.factor_updates,
        ..Default::default()
    };
    if opts.breaks_per_equilibrium > 1 {
        ctx.log.info(format!(
            "DEM: up to {} beams break per equilibrium: an approximation of the one-break path",
            opts.breaks_per_equilibrium
        ));
    }
    if restart {
        check_checkpoints(ctx, job)?;
    }
    let log = &ctx.log;
    let work = |k: usize| run_sample(job, k, opts, restart, log);
    let results = phases.time("batch", || {
        let batch = run_batch(&ctx.comm, n, work, |done, total| log.info(format!("  {done}/{total} samples done")));
        agree(&ctx.comm, batch.map_err(Error::from), Error::exit_code)
    })?;
    let seconds = phases.seconds("batch");
    let written = match results {
        Some(results) => write_outputs(ctx, job, &results, seconds).map(Some),
        None => Ok(None),
    };
    let summary = agree(&ctx.comm, written, Error::exit_code)?;
    Ok(summary.unwrap_or_else(|| DemSummary {
        test: job.spec.test.clone(),
        ranks: ctx.size,
        breaks_per_equilibrium: job.spec.analysis.breaks_per_equilibrium,
        samples: Vec::new(),
        young_modulus: None,
        poisson: None,
        first_crack_stress: None,
        peak_stress: None,
        strain_at_peak: None,
        experiment: None,
        seconds,
        events_per_second: 0.0,
    }))
}

/// Sample `k`'s test, on the rank that got it; that rank writes its checkpoints and particle
/// states. Restarted: a finished test's result from its checkpoint (unless its particle states
/// are missing), a running one continued from it. Rank 0 reports the progress of the samples
/// it runs itself.
fn run_sample(
    job: &DemJob,
    k: usize,
    opts: SolverOptions,
    restart: bool,
    log: &Log,
) -> Result<TestResult, TestFailure> {
    let config = sample_config(job, k);
    let sample =
        Sample::build(&config).map_err(|e| TestFailure::Sample { sample: k, seed: None, message: e.to_string() })?;
    let (test, params) = (&job.spec.test, &job.params);
    let fingerprint = Fingerprint::new(&sample, config.seed, params, test);
    let file = checkpoint_file(&job.output_dir, k);
    let sdir = job.output_dir.join(format!("sample-{k:03}"));
    let states = job.spec.analysis.particle_states;
    let output =
        |what: String, e: &dyn std::fmt::Display| TestFailure::Output { sample: k, what, message: e.to_string() };
    let resume =
        if restart { read_checkpoint(&file, &fingerprint).map_err(|e| output("checkpoint".into(), &e))? } else { None };
    let resume = match resume {
        Some(c) if c.finished.is_some() && particles_kept(job, k) => {
            return finished_result(&sample, params, test, &c).map_err(|e| TestFailure::solver(k, None, &e));
        }
        running => running.filter(|c| c.finished.is_none()),
    };
    let minutes = job.spec.analysis.checkpoint_minutes;
    let out = &job.output_dir;
    let sink =
        (minutes > 0.0).then(|| Box::new(FileSink::new(out, k, fingerprint, minutes)) as Box<dyn CheckpointSink>);
    let report = log.is_root().then(|| sample_progress(log.clone(), k, PROGRESS_EVERY));
    let checkpoints = Checkpoints { sink, resume };
    let run = TestRun { opts, states, report, checkpoints };
    let mut result = run_test_checkpointed(&sample, params, test, run).map_err(|e| TestFailure::solver(k, None, &e))?;
    if !result.particle_states.is_empty() {
        std::fs::create_dir_all(&sdir).map_err(|e| output(format!("cannot create {}", sdir.display()), &e))?;
        write_particle_states(&sdir, "particles", &sample, &result)
            .map_err(|e| output("particle states".into(), &e))?;
        result.particle_states = Vec::new();
    }
    Ok(result)
}

/// Whether sample `k`'s particle states are on disk, or none are asked for: a finished test's
/// checkpoint stands for the test only then (it is written before the particle states).
fn particles_kept(job: &DemJob, k: usize) -> bool {
    let sdir = job.output_dir.join(format!("sample-{k:03}"));
    job.spec.analysis.particle_states == ParticleStates::None || sdir.join("particles.xdmf").is_file()
}

/// Collective. A restart's checkpoints, each checked against its sample, mechanics and test
/// before any sample runs (rank r checks samples r, r + size, ...): one that cannot be
/// continued stops the job on every rank with its file named (exit code 2). Logs what the
/// restart finds.
fn check_checkpoints(ctx: &Context, job: &DemJob) -> Result<(), Error> {
    let n = job.spec.analysis.samples;
    let mut found = [0.0f64; 2];
    let checked = (ctx.rank..n).step_by(ctx.size).try_for_each(|k| -> Result<(), Error> {
        let file = checkpoint_file(&job.output_dir, k);
        let config = sample_config(job, k);
        if !file.exists() {
            return Ok(());
        }
        // A sample that cannot be built fails in the batch, with its message.
        let Ok(sample) = Sample::build(&config) else { return Ok(()) };
        let fingerprint = Fingerprint::new(&sample, config.seed, &job.params, &job.spec.test);
        match read_checkpoint(&file, &fingerprint)? {
            Some(c) if c.finished.is_none() => found[1] += 1.0,
            Some(_) if particles_kept(job, k) => found[0] += 1.0,
            _ => {}
        }
        Ok(())
    });
    agree(&ctx.comm, checked, Error::exit_code)?;
    let (finished, running) = (global_sum(ctx, found[0]), global_sum(ctx, found[1]));
    ctx.log.info(format!(
        "restart: {finished} sample(s) finished before (results read from their checkpoints), \
         {running} continued from a checkpoint, {} started afresh",
        n as f64 - finished - running
    ));
    Ok(())
}

fn io_err(path: &Path) -> impl Fn(std::io::Error) -> Error + '_ {
    move |source| Error::OutputDir { path: path.to_path_buf(), source }
}

/// How often the progress of a long sample is printed (a 10k-stone sample in compression runs
/// for half an hour; the paper's wall, under a second, prints nothing).
const PROGRESS_EVERY: Duration = Duration::from_secs(30);

/// A report of sample `k`'s recorded states that logs a line at most once per `every`
/// ([`progress_line`]).
fn sample_progress<'a>(log: Log, k: usize, every: Duration) -> Report<'a> {
    let start = Instant::now();
    let mut last = start;
    Box::new(move |index: usize, r: &StateRecord| {
        if last.elapsed() >= every {
            last = Instant::now();
            log.info(progress_line(k, index, r, start.elapsed()));
        }
    })
}

/// The progress line of sample `k` at its recorded state number `index`, `r`: how far the load
/// stage is, beams broken, states recorded, active contacts, and the time since the sample
/// started.
fn progress_line(k: usize, index: usize, r: &StateRecord, elapsed: Duration) -> String {
    format!(
        "  sample {k}: stage {}, {:.1} % of its load; {} beams broken, {} states, {} contacts ({:.0} s)",
        r.stage + 1,
        100.0 * r.t,
        r.broken[0],
        index + 1,
        r.contacts,
        elapsed.as_secs_f64()
    )
}

/// The axes of the stress–strain pictures: labels and the sign that plots compression positive.
struct Axes<'j> {
    title: &'j str,
    x: &'static str,
    y: &'static str,
    sign: f64,
}

impl<'j> Axes<'j> {
    fn of(job: &'j DemJob) -> Axes<'j> {
        let compression = matches!(job.spec.test, VirtualTest::Compression { .. });
        let (x, y) = match (compression, job.spec.test.is_shear()) {
            (true, _) => ("shortening ε [-]", "compressive stress σ [MPa]"),
            (_, true) => ("shear strain γ = U_x/H [-]", "shear stress τ [MPa]"),
            _ => ("strain ε [-]", "stress σ [MPa] (tension positive)"),
        };
        let title = job.spec.title.as_deref().unwrap_or("DEM virtual test");
        Axes { title, x, y, sign: if compression { -1.0 } else { 1.0 } }
    }
}

/// The derived numbers of the counted samples, by quantity, with the batch's break count and
/// test time.
#[derive(Default)]
struct Tally {
    young_modulus: Vec<f64>,
    poisson: Vec<f64>,
    first_crack_stress: Vec<f64>,
    peak_stress: Vec<f64>,
    strain_at_peak: Vec<f64>,
    events: usize,
    test_seconds: f64,
}

impl Tally {
    /// Adds the test `t` (its numbers only when they count; no Poisson ratio for shear).
    fn add(&mut self, t: &TestResult, shear: bool) {
        self.events += t.stats.events;
        self.test_seconds += t.stats.seconds;
        if !t.end.is_valid() {
            return;
        }
        let d = &t.derived;
        self.young_modulus.push(d.young_modulus);
        if !shear {
            self.poisson.push(d.poisson);
        }
        self.first_crack_stress.extend(d.first_crack_stress);
        self.peak_stress.push(d.peak_stress);
        self.strain_at_peak.push(d.strain_at_peak.abs());
    }
}

/// Rank 0. Writes each sample's files, the batch's picture and summary numbers, and logs them.
fn write_outputs(
    ctx: &Context,
    job: &DemJob,
    results: &[Result<TestResult, TestFailure>],
    seconds: f64,
) -> Result<DemSummary, Error> {
    let axes = Axes::of(job);
    let shear = job.spec.test.is_shear();
    let mut chart = LineChart::new(axes.title, axes.x, axes.y);
    let mut tally = Tally::default();
    let mut reports = Vec::with_capacity(results.len());
    for (k, r) in results.iter().enumerate() {
        let seed = sample_config(job, k).seed;
        let report = match r {
            Err(failure) => {
                ctx.log.warn(failure.to_string());
                let result = Err(failure.clone());
                SampleReport {
                    sample: k,
                    seed,
                    result,
                    end: None,
                    counted: false,
                    events: 0,
                    seconds: 0.0,
                    factor_updates: None,
                }
            }
            Ok(t) => {
                let pts = write_sample(ctx, job, k, t, &axes)?;
                chart = chart.series(if k == 0 { "DEM samples" } else { "" }, pts, SeriesStyle::Line);
                tally.add(t, shear);
                SampleReport {
                    sample: k,
                    seed,
                    result: Ok(t.derived.clone()),
                    end: Some(t.end.clone()),
                    counted: t.end.is_valid(),
                    events: t.stats.events,
                    seconds: t.stats.seconds,
                    factor_updates: Some(if t.stats.updates_in_place {
                        crate::dem::solver::FactorUpdates::InPlace
                    } else {
                        crate::dem::solver::FactorUpdates::Woodbury
                    }),
                }
            }
        };
        reports.push(report);
    }
    if tally.young_modulus.is_empty() {
        return Err(JobError::EverySampleFailed.into());
    }
    chart = with_experiment(chart, job, &tally.peak_stress);
    chart.save_png(&job.output_dir.join("stress_strain.png"))?;
    let t = &tally;
    let s = DemSummary {
        test: job.spec.test.clone(),
        ranks: ctx.size,
        breaks_per_equilibrium: job.spec.analysis.breaks_per_equilibrium,
        samples: reports,
        young_modulus: Stat::of_nonempty(&t.young_modulus),
        poisson: Stat::of_nonempty(&t.poisson),
        first_crack_stress: Stat::of_nonempty(&t.first_crack_stress),
        peak_stress: Stat::of_nonempty(&t.peak_stress),
        strain_at_peak: Stat::of_nonempty(&t.strain_at_peak),
        experiment: job.spec.experiment.clone(),
        seconds,
        events_per_second: if t.test_seconds > 0.0 { t.events as f64 / t.test_seconds } else { 0.0 },
    };
    log_summary(ctx, job, &s, &tally);
    Ok(s)
}

/// Sample `k`'s folder: its curve (CSV, and PNG for a cyclic test) and its cracks; says how it
/// ended when it stopped early. Returns its curve for the batch's picture.
fn write_sample(ctx: &Context, job: &DemJob, k: usize, t: &TestResult, axes: &Axes) -> Result<Vec<(f64, f64)>, Error> {
    let sdir = job.output_dir.join(format!("sample-{k:03}"));
    std::fs::create_dir_all(&sdir).map_err(io_err(&sdir))?;
    write_curve(&sdir.join("curve.csv"), t)?;
    write_cracks(job, k, &sdir, t)?;
    let pts: Vec<(f64, f64)> = t.curve.iter().map(|c| (axes.sign * c.strain, axes.sign * c.stress / 1e6)).collect();
    if job.spec.test.is_cyclic() {
        let f = sdir.join("curve.png");
        LineChart::new(&format!("{}: sample {k}", axes.title), axes.x, axes.y)
            .series("DEM (hysteresis loops)", pts.clone(), SeriesStyle::Line)
            .save_png(&f)?;
    }
    match &t.end {
        TestEnd::Failed { message } => ctx.log.warn(format!(
            "sample {k}: stopped before the peak after {} events ({message}); its curve is kept in {}, its numbers are not counted",
            t.stats.events,
            sdir.display()
        )),
        TestEnd::Collapse { message } => ctx.log.info(format!(
            "sample {k}: no equilibrium after the peak (collapse) after {} events: {message}",
            t.stats.events
        )),
        _ => {}
    }
    Ok(pts)
}

/// The experiment's modulus line and its first-crack and peak points (not for shear tests); the
/// line reaches the experiment's peak (or first crack, or the samples' largest peak `peaks`).
fn with_experiment(chart: LineChart, job: &DemJob, peaks: &[f64]) -> LineChart {
    let Some(x) = job.spec.experiment.as_ref().filter(|_| !job.spec.test.is_shear()) else { return chart };
    let Some(ex) = x.young_modulus else { return chart };
    let top = x.peak_stress.or(x.first_crack_stress).unwrap_or(peaks.iter().cloned().fold(0.0, f64::max));
    let mut chart = chart.series("experiment: E", vec![(0.0, 0.0), (top / ex, top / 1e6)], SeriesStyle::Dashed);
    let pts: Vec<(f64, f64)> =
        [x.first_crack_stress, x.peak_stress].into_iter().flatten().map(|f| (f / ex, f / 1e6)).collect();
    if !pts.is_empty() {
        chart = chart.series("experiment: first crack, peak", pts, SeriesStyle::Markers);
    }
    chart
}

/// The batch's numbers in the log, beside the experiment's.
fn log_summary(ctx: &Context, job: &DemJob, s: &DemSummary, tally: &Tally) {
    let line = |name: &str, st: &Option<Stat>, scale: f64, unit: &str, exp: Option<f64>| {
        let x = exp.map(|v| format!("   experiment {:.4} {unit}", v / scale)).unwrap_or_default();
        match st {
            Some(st) => ctx.log.info(format!(
                "{name:20} {:10.4} ± {:.4} {unit} (n = {}){x}",
                st.mean / scale,
                st.std / scale,
                st.n
            )),
            None => ctx.log.info(format!("{name:20} {:>10} (no sample has it){x}", "-")),
        }
    };
    let ex = job.spec.experiment.clone().unwrap_or_default();
    if job.spec.test.is_shear() {
        line("initial τ/γ", &s.young_modulus, 1e9, "GPa", None);
        let (w, h) = job.spec.sample.layout.domain();
        if let (Some(pk), Some(sp)) = (&s.peak_stress, &s.strain_at_peak) {
            ctx.log.info(format!(
                "peak shear stress {:.3} ± {:.3} MPa: force on the 0.5 m thick wall {:.1} ± {:.1} kN (τ × W × 0.5 m)",
                pk.mean / 1e6,
                pk.std / 1e6,
                pk.mean * w * 0.5 / 1e3,
                pk.std * w * 0.5 / 1e3
            ));
            ctx.log.info(format!(
                "displacement at peak {:.2} ± {:.2} mm (n = {})",
                sp.mean * h * 1e3,
                sp.std * h * 1e3,
                sp.n
            ));
        }
    } else {
        line("Young modulus", &s.young_modulus, 1e9, "GPa", ex.young_modulus);
        line("Poisson ratio", &s.poisson, 1.0, "", ex.poisson);
    }
    line("first-crack stress", &s.first_crack_stress, 1e6, "MPa", ex.first_crack_stress);
    line("peak stress", &s.peak_stress, 1e6, "MPa", ex.peak_stress);
    line("strain at peak", &s.strain_at_peak, 1e-3, "‰", None);
    ctx.log.info(format!(
        "{} events in {:.2} s of test time ({:.0} events/s); batch wall time {:.2} s",
        tally.events, tally.test_seconds, s.events_per_second, s.seconds
    ));
}

fn write_curve(file: &Path, t: &TestResult) -> Result<(), Error> {
    let mut s = String::from(
        "state,kind,displacement,strain,stress,lateral_strain,broken,broken_tension,broken_shear,broken_crushing,external_work,stored,dissipated_fracture,dissipated_friction,dissipated_relaxation,dissipated_crushing\n",
    );
    for c in &t.curve {
        let kind = serde_json::to_string(&c.kind).unwrap_or_default().replace('"', "");
        let _ = writeln!(
            s,
            "{},{kind},{:e},{:e},{:e},{:e},{},{},{},{},{:e},{:e},{:e},{:e},{:e},{:e}",
            c.state,
            c.displacement,
            c.strain,
            c.stress,
            c.lateral_strain,
            c.broken[0],
            c.broken[1],
            c.broken[2],
            c.broken[3],
            c.external_work,
            c.stored,
            c.dissipated[0],
            c.dissipated[1],
            c.dissipated[2],
            c.dissipated[3]
        );
    }
    std::fs::write(file, s).map_err(io_err(file))
}

/// Crack pictures at the first crack, at the peak and at the end (undeformed stones).
fn write_cracks(job: &DemJob, k: usize, dir: &Path, t: &TestResult) -> Result<(), Error> {
    let sample = Sample::build(&sample_config(job, k)).map_err(|source| JobError::Sample { sample: k, source })?;
    let peak_state =
        t.curve.iter().max_by(|a, b| a.stress.abs().total_cmp(&b.stress.abs())).map(|c| c.state).unwrap_or(0);
    let first_state = t.broken.first().map(|b| b.state).unwrap_or(0);
    let cat = |m: FailureModeTag| match m {
        FailureModeTag::Tension => 0u8,
        FailureModeTag::Shear => 1u8,
        FailureModeTag::Crushing => 2u8,
    };
    for (name, upto) in [("first", Some(first_state)), ("peak", Some(peak_state)), ("end", None)] {
        let broken: Vec<(usize, u8)> =
            t.broken.iter().filter(|b| upto.is_none_or(|s| b.state <= s)).map(|b| (b.beam, cat(b.mode))).collect();
        let style = SvgStyle { title: Some(format!("sample {k}: cracks at {name}")), ..SvgStyle::default() };
        let svg = draw_svg(&sample, None, &broken, &style).map_err(|source| JobError::Sample { sample: k, source })?;
        let f = dir.join(format!("cracks-{name}.svg"));
        std::fs::write(&f, svg).map_err(io_err(&f))?;
    }
    Ok(())
}
