//! Running a job: load and check the input on every rank (errors agreed collectively), start
//! PETSc with the job's options under the command line's, run the analysis, write the summary.
//! The top layer of the crate, under `main`: it dispatches the structural jobs to
//! [`crate::analysis`], and holds the drivers of the jobs that use no FE machinery:
//!
//! | file                | job                                                              |
//! |---------------------|------------------------------------------------------------------|
//! | `dem.rs`            | `[analysis] type = "dem"`: virtual tests of the DEM lab, batched over ranks |
//! | `dem_checkpoint.rs` | the DEM job's checkpoints: one file per sample, written as its test goes; `--restart` |
//! | `identify/`         | `"identification"`: calibration, virtual tests, law fit, material file |
//! | `spectrum.rs`       | `"spectrum"`: a record's response spectra against Eurocode 8     |
//! | `material_point.rs` | `"material_point"`: one integration point along a strain path   |
//! | `record_set.rs`     | `"record_set"`: records compatible with a Eurocode 8 spectrum, checked |
//! | `sweep/`            | `"sweep"`: many time histories of one model (records × intensities × materials) in groups of ranks |
//! | `output_dir.rs`     | the results folder: backup, overwrite or refuse                  |
pub mod dem;
mod dem_checkpoint;
pub mod identify;
pub mod material_point;
mod output_dir;
pub mod record_set;
pub mod spectrum;
pub mod sweep;

pub use crate::error::Error;
pub use output_dir::{backup_path, prepare_output_dir};

use crate::analysis::time_history::Start;
use crate::analysis::{linear_static, FeProblem};
use crate::config::{load_job, AnalysisConfig, AnyJob, Job, MaterialPointJob};
use crate::error::JobError;
use crate::io::IoError;
use crate::mesh::{read_msh, Mesh};
use crate::model::StructuralModel;
use crate::parallel::{agree, Context};
use crate::petsc::Petsc;
use std::path::Path;

/// Everything a job needs before the analysis: the job, its mesh and its model, all checked.
pub struct Input {
    /// The job.
    pub job: Job,
    /// The mesh.
    pub mesh: Mesh,
    /// The model.
    pub model: StructuralModel,
}

/// Collective. Loads and checks any job file (and, for a structural job, its mesh and its
/// model) without running anything; `strict`: implausible input is an error ([`load_input`]).
pub fn check_job(ctx: &Context, path: &Path, strict: bool) -> Result<String, Error> {
    match agree(&ctx.comm, load_job(path).map_err(Error::from), Error::exit_code)? {
        AnyJob::Structural(job) => {
            let input = load_input(ctx, path, job, strict)?;
            let n_fixed: u32 = input.model.fixed.iter().map(|m| m.count_ones()).sum();
            Ok(format!(
                "{} structural elements in {} part(s), {} fixed DOFs, {} loaded node(s); results would go to {}",
                input.model.cells.len(),
                input.job.spec.parts.len(),
                n_fixed,
                input.model.nodal_loads.len(),
                input.job.output_dir.display()
            ))
        }
        AnyJob::Spectrum(job) => Ok(format!(
            "spectrum of {} ({} s, PGA {:.4} m/s²); results would go to {}",
            job.record.name,
            job.record.duration(),
            crate::seismic::pga(&job.record),
            job.output_dir.display()
        )),
        AnyJob::Dem(job) => Ok(format!(
            "DEM, {} sample(s), test {:?}; results would go to {}",
            job.spec.analysis.samples,
            job.spec.test,
            job.output_dir.display()
        )),
        AnyJob::Identify(job) => Ok(format!(
            "identification:{}{}; results would go to {}",
            if job.spec.calibration.is_some() { " DEM calibration" } else { "" },
            if job.spec.law.is_some() { " damage-law identification" } else { "" },
            job.output_dir.display()
        )),
        AnyJob::RecordSet(job) => Ok(format!(
            "record set: {} artificial + {} recorded record(s), check over [{:.4}, {:.4}] s; results would go to {}",
            job.artificial.as_ref().map_or(0, |a| a.1),
            job.recorded.len(),
            job.rules.range.0,
            job.rules.range.1,
            job.output_dir.display()
        )),
        AnyJob::Sweep(job) => Ok(format!(
            "sweep: {}, groups of {} rank(s), base job {}; results would go to {}",
            job.plan_line(),
            job.spec.analysis.group_size,
            job.base_file.display(),
            job.output_dir.display()
        )),
        AnyJob::MaterialPoint(job) => Ok(format!(
            "material point, h = {} m (B_t = {:.6e}); results would go to {}",
            job.spec.analysis.element_size,
            job.law.b_t(),
            job.output_dir.display()
        )),
    }
}

/// Collective. Checks a structural job's mesh and model, and warns of implausible input
/// (`config::plausible`, `model::plausible`); with `strict` the warnings are an error (exit 2).
pub fn load_input(ctx: &Context, path: &Path, job: Job, strict: bool) -> Result<Input, Error> {
    ctx.log.info(format!(
        "job {}{}",
        path.display(),
        job.spec.title.as_deref().map(|t| format!(": {t}")).unwrap_or_default()
    ));
    let mesh = agree(&ctx.comm, read_msh(&job.mesh_file).map_err(Error::from), Error::exit_code)?;
    ctx.log.info(format!(
        "mesh {}: {} nodes, {} cells, groups: {}",
        job.mesh_file.display(),
        mesh.coords.len(),
        mesh.cells.len(),
        mesh.group_names().join(", ")
    ));
    let model = agree(&ctx.comm, StructuralModel::build(&job, &mesh).map_err(Error::from), Error::exit_code)?;
    for (group, n) in model.unmodelled_groups(&job, &mesh) {
        ctx.log.warn(format!(
            "{}: mesh group '{group}' ({n} cells) is in no [[parts]] and no support, load or mass names it: its cells are not in the model",
            path.display()
        ));
    }
    warn_implausible(ctx, path, &job, &mesh, &model, strict)?;
    let mech = model.find_mechanisms(&mesh);
    if let Some(piece) = mech.first() {
        return Err(Error::Mechanism { piece: piece.clone(), pieces: mech.len() });
    }
    Ok(Input { job, mesh, model })
}

/// Every rank. The warnings of implausible input in the log (rank 0); with `strict`, an error
/// that lists them (every rank has the same).
fn warn_implausible(
    ctx: &Context,
    path: &Path,
    job: &Job,
    mesh: &Mesh,
    model: &StructuralModel,
    strict: bool,
) -> Result<(), Error> {
    let folder = path.parent().unwrap_or(Path::new(""));
    let mut warnings = crate::config::plausible::warnings(&job.source, &job.spec, folder);
    warnings.extend(crate::model::plausible::thickness_warnings(job, mesh, model));
    for w in &warnings {
        ctx.log.warn(w);
    }
    if strict && !warnings.is_empty() {
        let message = format!(
            "{} implausible value(s) with --strict (each warned above):\n  {}",
            warnings.len(),
            warnings.join("\n  ")
        );
        return Err(Error::Agreed(crate::parallel::Agreed { message, exit_code: 2, rank: 0 }));
    }
    Ok(())
}

/// Collective. Runs the job at `path`; `petsc_args` are the command-line PETSc options.
pub fn run_job(ctx: &Context, path: &Path, petsc_args: &[String]) -> Result<(), Error> {
    run_job_with(ctx, path, petsc_args, false, false)
}

/// Collective. As [`run_job`]; `restart` continues a time history from its last checkpoint;
/// `strict` makes implausible input an error ([`load_input`]).
pub fn run_job_with(
    ctx: &Context,
    path: &Path,
    petsc_args: &[String],
    restart: bool,
    strict: bool,
) -> Result<(), Error> {
    let job = agree(&ctx.comm, load_job(path).map_err(Error::from), Error::exit_code)?;
    let restartable =
        |a: &AnalysisConfig| matches!(a, AnalysisConfig::TimeHistory | AnalysisConfig::SeismicAssessment(_));
    if restart
        && !matches!(&job, AnyJob::Structural(j) if restartable(&j.spec.analysis))
        && !matches!(job, AnyJob::Sweep(_) | AnyJob::Dem(_))
    {
        // Every rank knows it: print it once.
        let message = format!(
            "{}: --restart applies to [analysis] type = \"time_history\", \"seismic_assessment\", \"sweep\" or \"dem\" jobs only",
            path.display()
        );
        return Err(Error::Agreed(crate::parallel::Agreed { message, exit_code: 2, rank: 0 }));
    }
    match job {
        AnyJob::Structural(job) => run_structural(ctx, path, job, petsc_args, restart, strict),
        AnyJob::MaterialPoint(job) => run_material_point(ctx, path, &job),
        AnyJob::Dem(job) => run_dem(ctx, path, &job, restart),
        AnyJob::Identify(job) => {
            ctx.log.info(format!(
                "job {}{}",
                path.display(),
                job.spec.title.as_deref().map(|t| format!(": {t}")).unwrap_or_default()
            ));
            prepare(ctx, &job.output_dir, job.spec.output.existing)?;
            let summary = identify::run(ctx, path, &job)?;
            ctx.log.info(format!("results: {}", job.output_dir.display()));
            write_summary(ctx, &job.output_dir, &summary)
        }
        AnyJob::RecordSet(job) => {
            ctx.log.info(format!(
                "job {}{}",
                path.display(),
                job.spec.title.as_deref().map(|t| format!(": {t}")).unwrap_or_default()
            ));
            prepare(ctx, &job.output_dir, job.spec.output.existing)?;
            record_set::run(ctx, &job)
        }
        AnyJob::Sweep(job) => {
            ctx.log.info(format!(
                "job {}{}",
                path.display(),
                job.spec.title.as_deref().map(|t| format!(": {t}")).unwrap_or_default()
            ));
            sweep::run(ctx, path, &job, petsc_args, restart)
        }
        AnyJob::Spectrum(job) => {
            ctx.log.info(format!("job {}", path.display()));
            prepare(ctx, &job.output_dir, job.spec.output.existing)?;
            let summary = spectrum::run(ctx, &job)?;
            ctx.log.info(format!("results: {}", job.output_dir.display()));
            write_summary(ctx, &job.output_dir, &summary)
        }
    }
}

/// Collective. Rank 0 prepares the results folder; all ranks agree on the outcome.
pub(crate) fn prepare(ctx: &Context, dir: &Path, policy: crate::config::ExistingOutput) -> Result<(), Error> {
    let prepared = if ctx.rank == 0 { prepare_output_dir(dir, policy, &ctx.log) } else { Ok(()) };
    agree(&ctx.comm, prepared, Error::exit_code)?;
    Ok(())
}

/// Rank 0 writes `summary.json` into `dir`.
fn write_summary(ctx: &Context, dir: &Path, summary: &impl serde::Serialize) -> Result<(), Error> {
    if ctx.rank == 0 {
        let file = dir.join("summary.json");
        let text = crate::io::summary::summary_json(summary).map_err(|source| IoError::Json {
            file: file.clone(),
            what: "the summary",
            source,
        })?;
        std::fs::write(&file, text + "\n").map_err(|source| Error::OutputDir { path: file.clone(), source })?;
        ctx.log.info(format!("summary: {}", file.display()));
    }
    Ok(())
}

fn run_material_point(ctx: &Context, path: &Path, job: &MaterialPointJob) -> Result<(), Error> {
    ctx.log.info(format!(
        "job {}{}",
        path.display(),
        job.spec.title.as_deref().map(|t| format!(": {t}")).unwrap_or_default()
    ));
    prepare(ctx, &job.output_dir, job.spec.output.existing)?;
    let summary = material_point::run(ctx, job)?;
    ctx.log.info(format!("results: {}", job.output_dir.display()));
    write_summary(ctx, &job.output_dir, &summary)
}

/// A DEM job; `restart` continues it from the checkpoints in its results folder.
fn run_dem(ctx: &Context, path: &Path, job: &crate::config::DemJob, restart: bool) -> Result<(), Error> {
    ctx.log.info(format!(
        "job {}{}{}",
        path.display(),
        job.spec.title.as_deref().map(|t| format!(": {t}")).unwrap_or_default(),
        if restart { " (restart)" } else { "" }
    ));
    if !restart {
        prepare(ctx, &job.output_dir, job.spec.output.existing)?;
    } else {
        let dir = &job.output_dir;
        let missing = ctx.rank == 0 && !dir.is_dir();
        let found = if missing { Err(Error::from(JobError::NothingToRestart { dir: dir.clone() })) } else { Ok(()) };
        agree(&ctx.comm, found, Error::exit_code)?;
    }
    let summary = dem::run(ctx, job, restart)?;
    ctx.log.info(format!("results: {}", job.output_dir.display()));
    write_summary(ctx, &job.output_dir, &summary)
}

/// The log's line naming the analysis.
fn analysis_line(analysis: &AnalysisConfig, restart: bool) -> String {
    let restart = if restart { " (restart)" } else { "" };
    match analysis {
        AnalysisConfig::LinearStatic => "analysis: linear static".to_string(),
        AnalysisConfig::StaticNonlinear(cfg) => format!("analysis: nonlinear static, {} load step(s)", cfg.steps),
        AnalysisConfig::ModalUpdating(_) => "analysis: modal updating".to_string(),
        AnalysisConfig::TimeHistory => format!("analysis: time history{restart}"),
        AnalysisConfig::SeismicAssessment(_) => {
            format!("analysis: seismic assessment (modal, updating, gravity, earthquake){restart}")
        }
        AnalysisConfig::Modal(cfg) => format!("analysis: modal, {} mode(s)", cfg.modes),
    }
}

fn run_structural(
    ctx: &Context,
    path: &Path,
    job: Job,
    petsc_args: &[String],
    restart: bool,
    strict: bool,
) -> Result<(), Error> {
    let input = load_input(ctx, path, job, strict)?;
    let job = &input.job;
    if !restart {
        prepare(ctx, &job.output_dir, job.spec.output.existing)?;
    }

    let mut argv = vec!["masonry-hpc".to_string()];
    argv.extend(petsc_args.iter().cloned());
    let petsc = Petsc::initialize(&argv)?;
    petsc.set_default_options("", &job.petsc_options)?;

    ctx.log.info(analysis_line(&job.spec.analysis, restart));
    let mut problem = FeProblem::setup(ctx, job, &input.mesh, &input.model)?;
    match &job.spec.analysis {
        AnalysisConfig::LinearStatic => {
            let summary = linear_static::run(&mut problem)?;
            write_summary(ctx, &job.output_dir, &summary)?;
        }
        AnalysisConfig::StaticNonlinear(cfg) => {
            let summary = crate::analysis::static_nonlinear::run(&mut problem, cfg)?;
            write_summary(ctx, &job.output_dir, &summary)?;
        }
        AnalysisConfig::ModalUpdating(cfg) => {
            let summary = crate::analysis::modal_updating::run(&mut problem, cfg, None)?;
            write_summary(ctx, &job.output_dir, &summary)?;
        }
        AnalysisConfig::TimeHistory => {
            let start = if restart { Start::Restart } else { Start::Gravity };
            let summary = crate::analysis::time_history::run(problem, start, &mut ())?;
            write_summary(ctx, &job.output_dir, &summary)?;
        }
        AnalysisConfig::SeismicAssessment(cfg) => {
            let summary = crate::analysis::assessment::run(problem, cfg, restart)?;
            write_summary(ctx, &job.output_dir, &summary)?;
        }
        AnalysisConfig::Modal(cfg) => {
            let (summary, _) = crate::analysis::modal::run(&mut problem, cfg, "modes")?;
            write_summary(ctx, &job.output_dir, &summary)?;
        }
    }
    drop(petsc);
    Ok(())
}
