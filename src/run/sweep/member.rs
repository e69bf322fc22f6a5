//! The two kinds of task a group runs, on its own communicator: the gravity state of one
//! material (with the modal updating of a seismic assessment), and one member's time history
//! from it. Both read their job file from the sweep's folder (`jobs/gravity-<variant>.toml`,
//! `jobs/<member>.toml`), the file a user runs to repeat the task alone.
use super::outcome::Outcome;
use crate::analysis::time_history::{self, Start, StepObserver, TimeHistorySummary};
use crate::analysis::{assessment, FeProblem};
use crate::config::{AnalysisConfig, Job, Member, SweepJob};
use crate::error::Error;
use crate::mesh::Mesh;
use crate::model::StructuralModel;
use crate::parallel::{agree, Context};
use std::path::{Path, PathBuf};
use std::time::Instant;

/// The file that marks a material's gravity state as whole.
pub const GRAVITY_DONE: &str = "gravity.json";
/// The file that holds why a material's gravity state could not be found.
pub const GRAVITY_FAILED: &str = "gravity-failure.txt";

/// The job file of a material's gravity state.
pub fn variant_job(out: &Path, job: &SweepJob, v: usize) -> PathBuf {
    out.join("jobs").join(format!("gravity-{}.toml", job.variants[v].name))
}

/// The job file of a member.
pub fn member_job(out: &Path, m: &Member) -> PathBuf {
    out.join("jobs").join(format!("{}.toml", m.name))
}

/// The folder of a material's gravity state.
pub fn variant_dir(out: &Path, job: &SweepJob, v: usize) -> PathBuf {
    out.join("gravity").join(&job.variants[v].name)
}

/// The folder of a member.
pub fn member_dir(out: &Path, m: &Member) -> PathBuf {
    out.join("members").join(&m.name)
}

/// Collective over the group. The job in `file` and its model.
fn load(ctx: &Context, file: &Path, mesh: &Mesh) -> Result<(Job, StructuralModel), Error> {
    let job = agree(&ctx.comm, Job::load(file).map_err(Error::from), Error::exit_code)?;
    let model = agree(&ctx.comm, StructuralModel::build(&job, mesh).map_err(Error::from), Error::exit_code)?;
    Ok((job, model))
}

/// Collective over the group. The FE problem of `job`, with the updated moduli of `stages` (a
/// seismic assessment's `stages.json` folder) when given.
fn problem<'a>(
    ctx: &'a Context,
    job: &'a Job,
    mesh: &'a Mesh,
    model: &'a StructuralModel,
    stages: Option<&Path>,
) -> Result<FeProblem<'a>, Error> {
    let mut p = FeProblem::setup(ctx, job, mesh, model)?;
    if let (Some(stages), AnalysisConfig::SeismicAssessment(_)) = (stages, &job.spec.analysis) {
        let factors = agree(&ctx.comm, assessment::part_factors_in(job, stages), Error::exit_code)?;
        p.rebuild_elements(&factors)?;
    }
    Ok(p)
}

/// Collective over the group. The gravity state of the job `file` in its results folder `dir`:
/// for a seismic assessment, stages 1–3 first (modal, updating: `stages.json`); then gravity,
/// saved as a checkpoint; then the marker file. An error (the model cannot carry its weight) is
/// returned, after the leader wrote it to `gravity-failure.txt` for the members' outcomes.
pub fn prepare_variant(ctx: &Context, file: &Path, dir: &Path, mesh: &Mesh) -> Result<f64, Error> {
    let start = Instant::now();
    let done = (|| -> Result<(), Error> {
        let (job, model) = load(ctx, file, mesh)?;
        let mut p = problem(ctx, &job, mesh, &model, None)?;
        if let AnalysisConfig::SeismicAssessment(cfg) = &job.spec.analysis {
            assessment::pre_stages(&mut p, cfg)?;
        }
        time_history::save_gravity(p, dir)
    })();
    if let Err(e) = done {
        if ctx.rank == 0 {
            let _ = std::fs::write(dir.join(GRAVITY_FAILED), format!("{e}\n"));
        }
        return Err(e);
    }
    let seconds = start.elapsed().as_secs_f64();
    let written = if ctx.rank == 0 {
        std::fs::write(dir.join(GRAVITY_DONE), serde_json::json!({ "seconds": seconds }).to_string() + "\n")
            .map_err(|source| Error::OutputDir { path: dir.join(GRAVITY_DONE), source })
    } else {
        Ok(())
    };
    agree(&ctx.comm, written, Error::exit_code)?;
    Ok(seconds)
}

/// Whether the gravity state in `dir` is whole.
pub fn variant_done(dir: &Path) -> bool {
    dir.join(GRAVITY_DONE).is_file()
}

/// Why the gravity state in `dir` could not be found (as its task wrote it).
pub fn variant_failure(dir: &Path) -> String {
    std::fs::read_to_string(dir.join(GRAVITY_FAILED))
        .map(|s| s.trim().to_string())
        .unwrap_or_else(|_| format!("the gravity state in {} could not be found", dir.display()))
}

/// Collective over the group. Member `m`'s time history (its job file and results folder in the
/// sweep's results `out`), from its material's gravity state (or from its own last checkpoint,
/// when a killed sweep left one); `observer` after every step. The group's leader writes
/// `summary.json`; the outcome is returned.
pub fn run_member(
    ctx: &Context,
    job: &SweepJob,
    m: &Member,
    out: &Path,
    mesh: &Mesh,
    observer: &mut dyn StepObserver,
) -> Outcome {
    let start = Instant::now();
    let (file, dir, gravity) = (member_job(out, m), member_dir(out, m), variant_dir(out, job, m.variant));
    let (dir, gravity) = (dir.as_path(), gravity.as_path());
    let resume = dir.join("checkpoint").join("latest.json").is_file();
    let run = (|| -> Result<TimeHistorySummary, Error> {
        let (mjob, model) = load(ctx, &file, mesh)?;
        let p = problem(ctx, &mjob, mesh, &model, Some(gravity))?;
        let from = if resume { Start::Restart } else { Start::SavedGravity(gravity) };
        let summary = time_history::run(p, from, observer)?;
        if ctx.rank == 0 {
            let text = crate::io::summary::summary_json(&summary).unwrap_or_default();
            let _ = std::fs::write(dir.join("summary.json"), text + "\n");
        }
        Ok(summary)
    })();
    Outcome::new(job, m, &run, dir, start.elapsed().as_secs_f64())
}
