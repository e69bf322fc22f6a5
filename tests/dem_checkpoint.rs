//! Checkpoints of DEM tests: a test stopped after a checkpoint and resumed from it ends as the
//! uninterrupted one, and a DEM job continues from its checkpoints with `--restart`.
//!
//! ```text
//!   small wall (0.5 m x 0.6 m, 5 courses x 3 stones, the paper's parameters), seed 2
//!   ├ compression to 2e-3 in 20 steps; cyclic shear under 1 MPa, amplitudes 0.5, 1 mm
//!   │   uninterrupted, a checkpoint after every load step:
//!   │     the same curve, bit for bit, as without checkpoints (a sink does not touch the path)
//!   │   stopped by its sink after 1/4, 1/2, 3/4 of its checkpoints, resumed from the last one:
//!   │     the checkpoint is the uninterrupted run's, bit for bit (the path is deterministic);
//!   │     the same broken beams in the same order, the same states and how the test ended;
//!   │     the curve within 1e-6 of the peak |stress| (a resumed test factorizes afresh: round-off
//!   │     and the equilibrium tolerance, 1e-8 of the largest force, in place of bit equality)
//!   │   the finished checkpoint: the uninterrupted result again (finished_result)
//!   └ the job (2 samples): killed after sample 0's third checkpoint, --restart continues it
//!       and runs sample 1: the summary's numbers of the uninterrupted job; --restart again, all
//!       finished: the same summary, no sample run, no checkpoint written; a damaged checkpoint
//!       and one of another test: exit code 2 naming the file (1 and 2 ranks)
//! ```
mod common;
use common::*;
use masonry_hpc::dem::mechanics::MechParams;
use masonry_hpc::dem::sample::{Sample, SampleConfig, SampleLayout};
use masonry_hpc::dem::solver::{
    finished_result, run_test_checkpointed, run_test_with, CheckpointSink, Checkpoints, CurvePoint, DemError,
    PlatenRotation, SolverOptions, SolverState, TestCheckpoint, TestResult, TestRun, VirtualTest,
};
use std::cell::RefCell;
use std::path::Path;
use std::rc::Rc;

fn small_wall(seed: u64) -> Sample {
    let mut cfg = SampleConfig::paper_wall(seed);
    if let SampleLayout::Coursed(c) = &mut cfg.layout {
        (c.width, c.height, c.n_courses, c.n_per_course) = (0.5, 0.6, 5, 3);
    }
    Sample::build(&cfg).unwrap()
}

/// Keeps the checkpoints it is given, one after every load step; with `stop_after`, fails its
/// write after that many have been kept, as a killed run would stop right after writing.
struct Keep {
    kept: Rc<RefCell<Vec<TestCheckpoint>>>,
    stop_after: Option<usize>,
}

impl CheckpointSink for Keep {
    fn due(&mut self, _: &SolverState) -> bool {
        true
    }
    fn write(&mut self, c: TestCheckpoint) -> Result<(), DemError> {
        let mut kept = self.kept.borrow_mut();
        kept.push(c);
        match self.stop_after {
            Some(n) if kept.len() == n => Err(DemError::Checkpoint("stopped here".into())),
            _ => Ok(()),
        }
    }
}

/// Runs `test` on `s` with a [`Keep`] sink, from `resume`: the result and the checkpoints.
fn run_kept(
    s: &Sample,
    test: &VirtualTest,
    stop_after: Option<usize>,
    resume: Option<TestCheckpoint>,
) -> (Result<TestResult, DemError>, Vec<TestCheckpoint>) {
    let kept = Rc::new(RefCell::new(Vec::new()));
    let sink = Keep { kept: kept.clone(), stop_after };
    let c = Checkpoints { sink: Some(Box::new(sink)), resume };
    let p = MechParams::default();
    let r = run_test_checkpointed(s, &p, test, TestRun { checkpoints: c, ..Default::default() });
    (r, kept.take())
}

fn bits(z: &[f64]) -> Vec<u64> {
    z.iter().map(|x| x.to_bits()).collect()
}

/// The largest differences of `b`'s curve from `a`'s: of the stress over the peak |stress| and
/// of the platen displacement over the largest |displacement| (the same states asserted first).
fn curve_difference(a: &TestResult, b: &TestResult) -> (f64, f64) {
    assert_eq!(a.curve.len(), b.curve.len(), "the same recorded states");
    let peak = |f: fn(&CurvePoint) -> f64| a.curve.iter().map(|c| f(c).abs()).fold(0.0, f64::max);
    let (s, u) = (peak(|c| c.stress), peak(|c| c.displacement));
    let mut worst = (0.0f64, 0.0f64);
    for (x, y) in a.curve.iter().zip(&b.curve) {
        assert_eq!((x.state, x.kind, x.broken), (y.state, y.kind, y.broken));
        worst.0 = worst.0.max((x.stress - y.stress).abs() / s);
        worst.1 = worst.1.max((x.displacement - y.displacement).abs() / u);
    }
    worst
}

fn resumes_as_uninterrupted(test: VirtualTest) {
    let s = small_wall(2);
    let plain = run_test_with(&s, &MechParams::default(), &test, SolverOptions::default()).unwrap();
    let (whole, all) = run_kept(&s, &test, None, None);
    let whole = whole.unwrap();
    assert_eq!(plain.curve, whole.curve, "a sink does not change the path");
    assert!(whole.stats.events >= 3, "{} breaks: too few to test the order", whole.stats.events);
    let running = all.len() - 1;
    assert!(all[running].finished.is_some() && all[..running].iter().all(|c| c.finished.is_none()));
    for stop in [running / 4, running / 2, 3 * running / 4] {
        let (stopped, kept) = run_kept(&s, &test, Some(stop), None);
        assert!(matches!(stopped, Err(DemError::Checkpoint(_))), "{stopped:?}");
        let at = kept.last().unwrap().clone();
        assert_eq!(bits(&at.state.z), bits(&all[stop - 1].state.z), "the stopped run's checkpoint {stop}");
        let (breaks, stage) = (at.state.broken.len(), at.state.stage);
        let (resumed, _) = run_kept(&s, &test, None, Some(at));
        let resumed = resumed.unwrap();
        let beams = |r: &TestResult| r.broken.iter().map(|b| (b.beam, b.mode, b.state)).collect::<Vec<_>>();
        assert_eq!(beams(&resumed), beams(&whole), "stopped at checkpoint {stop}");
        assert_eq!(resumed.end, whole.end);
        let (ds, du) = curve_difference(&whole, &resumed);
        println!(
            "{test:?}: resumed at checkpoint {stop} of {running} (stage {stage}, {breaks} of {} breaks): \
             stress within {ds:.1e} of the peak, displacement within {du:.1e} of the largest",
            whole.stats.events
        );
        // Round-off of a fresh factorization and the equilibrium tolerance (1e-8), with room
        // for their growth along the path (module docs of `dem::solver::checkpoint`); the
        // displacements differ only at the breaks, whose load fraction λ is computed from z.
        assert!(ds <= 1e-6 && du <= 1e-6, "stopped at checkpoint {stop}: {ds:e}, {du:e}");
    }
    let done = finished_result(&s, &MechParams::default(), &test, &all[running]).unwrap();
    assert_eq!((&done.curve, &done.broken, &done.derived), (&whole.curve, &whole.broken, &whole.derived));
    assert_eq!((&done.end, &done.stats), (&whole.end, &whole.stats));
}

#[test]
fn a_compression_resumed_from_a_checkpoint_ends_as_the_uninterrupted_one() {
    resumes_as_uninterrupted(VirtualTest::Compression { max_strain: 2e-3, steps: 20 });
}

#[test]
fn a_cyclic_shear_resumed_from_a_checkpoint_ends_as_the_uninterrupted_one() {
    resumes_as_uninterrupted(VirtualTest::CyclicShear {
        vertical_stress: 1e6,
        amplitudes: vec![0.5e-3, 1e-3],
        steps_per_half_cycle: 8,
        preload_steps: 3,
        rotation: PlatenRotation::Fixed,
    });
}

const SMALL_WALL: &str = "layout = { type = \"coursed\", width = 0.5, height = 0.6, n_courses = 5, n_per_course = 3, jitter = 0.2, size_variability = 0.2 }";

/// A compression job of 2 small walls, a checkpoint after every load step (1e-6 min = 60 µs).
fn job(dir: &Path) -> std::path::PathBuf {
    let text = format!(
        "[analysis]\ntype = \"dem\"\nsamples = 2\nparticle_states = \"none\"\ncheckpoint_minutes = 1.0e-6\n\
         [sample]\nseed = 2\n{SMALL_WALL}\n\
         [test]\ntype = \"compression\"\nmax_strain = 2.0e-3\nsteps = 20\n\
         [output]\ndir = \"out\"\nexisting = \"error\"\n"
    );
    let f = dir.join("lab.toml");
    std::fs::write(&f, text).unwrap();
    f
}

/// The per-sample numbers of a summary (without the wall times, which differ between runs).
fn samples(dir: &Path) -> Vec<serde_json::Value> {
    let s = summary(&dir.join("out"));
    let mut v = s["samples"].as_array().unwrap().clone();
    v.iter_mut().for_each(|x| x.as_object_mut().unwrap().retain(|k, _| k != "seconds"));
    v
}

fn run_ok(args: &[&str]) -> std::process::Output {
    let o = run(0, args);
    assert!(o.status.success(), "{}\n{}", stdout(&o), stderr(&o));
    o
}

#[test]
fn a_killed_dem_job_continues_with_restart_and_a_finished_one_is_not_run_again() {
    let whole = scratch("dem-checkpoint-whole");
    run_ok(&[job(&whole).to_str().unwrap()]);
    assert!(whole.join("out/checkpoints/sample-001.ckpt").is_file());

    let dir = scratch("dem-checkpoint-killed");
    let lab = job(&dir);
    let mut cmd = std::process::Command::new(exe());
    cmd.arg(&lab)
        .env("OMPI_ALLOW_RUN_AS_ROOT", "1")
        .env("OMPI_ALLOW_RUN_AS_ROOT_CONFIRM", "1")
        .env("MASONRY_HPC_INJECT_KILL", "dem_sample_0_checkpoint_3");
    let o = run_with_timeout(cmd, std::time::Duration::from_secs(300));
    assert_eq!(o.status.code(), Some(137), "the kill ends the job: {}", stderr(&o));
    assert!(!dir.join("out/summary.json").exists());
    let lab = lab.to_str().unwrap();
    let o = run_ok(&["--restart", lab]);
    let log = stdout(&o);
    assert!(log.contains("restart: 0 sample(s) finished before"), "{log}");
    assert!(log.contains("1 continued from a checkpoint, 1 started afresh"), "{log}");
    // The continued sample agrees with the uninterrupted one as in the tests above: the same
    // breaks and end, its numbers within 1e-6 (relative; a fresh factorization's round-off and
    // the equilibrium tolerance); the sample started afresh is the same run.
    let (a, b) = (samples(&whole), samples(&dir));
    let mut worst = 0.0f64;
    for (x, y) in a.iter().zip(&b) {
        assert_eq!((&x["events"], &x["end"]), (&y["events"], &y["end"]));
        for q in ["young_modulus", "poisson", "first_crack_stress", "peak_stress", "strain_at_peak"] {
            let (u, v) = (x["result"]["Ok"][q].as_f64().unwrap(), y["result"]["Ok"][q].as_f64().unwrap());
            worst = worst.max((u - v).abs() / u.abs());
        }
    }
    println!("restarted job: the samples' numbers within {worst:.1e} (relative) of the uninterrupted job's");
    assert!(worst <= 1e-6, "{a:?}\n{b:?}");

    // Everything finished: the summary again, read from the checkpoints, none rewritten.
    let file = dir.join("out/checkpoints/sample-000.ckpt");
    let (bytes, mtime) = (std::fs::read(&file).unwrap(), std::fs::metadata(&file).unwrap().modified().unwrap());
    let o = run_ok(&["--restart", lab]);
    assert!(stdout(&o).contains("restart: 2 sample(s) finished before"), "{}", stdout(&o));
    assert_eq!(samples(&dir), b, "the same per-sample numbers");
    assert_eq!(std::fs::read(&file).unwrap(), bytes);
    assert_eq!(std::fs::metadata(&file).unwrap().modified().unwrap(), mtime, "not written again");

    // Without --restart the results folder's policy holds ("error": nothing touched).
    let o = run(0, &[lab]);
    assert_eq!(o.status.code(), Some(2), "{}", stderr(&o));
    assert_eq!(std::fs::read(&file).unwrap(), bytes);
}

/// `--restart` with each rank count: exit code 2, one message, every needle in it, no panic.
fn expect_restart_error(job: &Path, needles: &[&str]) {
    for np in [0, 2] {
        let out = run(np, &["--restart", job.to_str().unwrap()]);
        let err = stderr(&out);
        assert_eq!(out.status.code(), Some(2), "np={np}: exit code; stderr:\n{err}");
        for n in needles {
            assert!(err.contains(n), "np={np}: message lacks '{n}':\n{err}");
        }
        assert_eq!(err.matches("error:").count(), 1, "np={np}: one message:\n{err}");
        assert!(!err.contains("panicked"), "np={np}: a panic:\n{err}");
    }
}

#[test]
fn a_damaged_checkpoint_or_one_of_another_test_is_refused_by_name() {
    let dir = scratch("dem-checkpoint-bad");
    let lab = job(&dir);
    run_ok(&[lab.to_str().unwrap()]);
    let file = dir.join("out/checkpoints/sample-001.ckpt");
    let good = std::fs::read(&file).unwrap();
    let mut bad = good.clone();
    let n = bad.len();
    bad[n / 2] ^= 0x01;
    std::fs::write(&file, &bad).unwrap();
    expect_restart_error(&lab, &["checkpoints/sample-001.ckpt", "checksum mismatch"]);
    std::fs::write(&file, b"not a checkpoint").unwrap();
    expect_restart_error(&lab, &["checkpoints/sample-001.ckpt", "not a DEM checkpoint"]);
    std::fs::write(&file, &good).unwrap();
    edit(&dir, "lab.toml", "steps = 20", "steps = 25");
    expect_restart_error(
        &lab,
        &["checkpoints/sample-000.ckpt", "written for another sample or test", r#""steps":20"#, r#""steps":25"#],
    );
    edit(&dir, "lab.toml", "steps = 25", "steps = 20");
    std::fs::remove_dir_all(dir.join("out")).unwrap();
    expect_restart_error(&lab, &["does not exist (no earlier run to continue)"]);
}
