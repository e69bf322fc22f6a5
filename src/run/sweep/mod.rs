//! The `sweep` job: incremental dynamic analysis of one structure, as one MPI batch. Every member
//! (material variant × record × intensity) is a full nonlinear time history of the base job;
//! the world is split into groups of `group_size` ranks, each running members one at a time
//! under dynamic scheduling (`parallel::groups`). The intensities are hunted and filled per
//! record and material (`hunt.rs`, `feed.rs`: the members decided as results come in, several
//! records' hunts side by side), or a fixed grid (the costliest, highest intensity, first).
//!
//! ```text
//!  <results>/
//!    jobs/<member>.toml                  a member's job: it runs alone as it stands (its results
//!                                        go to members/<member>, the sweep's moved aside)
//!    jobs/gravity-<variant>.toml         the job of a material's gravity state
//!    gravity/<variant>/stages.json, checkpoint/   the material's state under gravity, computed
//!                                        once (by one group) and shared by its members
//!    members/<member>/results.xdmf, monitors.csv, summary.json, outcome.json
//!    sweep.csv                           one row per member (table.rs)
//!    summary.json, summary.txt           the limits' intensities, their spread and fragility
//!                                        functions (table.rs, fragility.rs)
//!    ida-<group>.png                     damage share against intensity per substructure (ida.rs)
//!    fragility-<group>-<share>.png       P(limit passed) against intensity (fragility.rs)
//! ```
//!
//! Phases: (1) the gravity states, one task per variant; (2) the members. A member that stops
//! (no convergence after its substeps) is an outcome with its diagnosis, not a failure of the
//! sweep. `--restart` skips the variants and members that are done (their marker files), replays
//! the hunts' decisions from the outcomes, and continues a member from its own last checkpoint.
mod feed;
mod fragility;
mod hunt;
mod ida;
mod member;
mod outcome;
mod table;

pub use outcome::{Outcome, Status, OUTCOME_FILE};

use crate::analysis::time_history::StepObserver;
use crate::config::{AnalysisConfig, HuntRules, Intensities, Member, SweepJob};
use crate::error::{Error, JobError};
use crate::mesh::read_msh;
use crate::parallel::{agree, Context, Dispatcher, Groups, Log};
use crate::petsc::Petsc;
use mpi::traits::{Communicator, CommunicatorCollectives};
use std::path::Path;

/// The scheduler answers other groups after every step of its own group's member (named, for
/// the kill points of the resume tests: `sweep_<member>_step_<n>`).
struct Serve<'a, 'g>(&'a mut Dispatcher<'g>, &'a str);

impl StepObserver for Serve<'_, '_> {
    fn after_step(&mut self, step: usize) {
        crate::fault::kill_point(&format!("sweep_{}_step_{step}", self.1));
        self.0.serve();
    }
}

/// Collective. Runs the sweep (see the module docs); `restart` continues a killed one.
pub fn run(ctx: &Context, path: &Path, job: &SweepJob, petsc_args: &[String], restart: bool) -> Result<(), Error> {
    let log = &ctx.log;
    let out = &job.output_dir;
    let size = job.spec.analysis.group_size;
    let groups = Groups::split(&ctx.comm, size).map_err(|e| {
        Error::Config(
            job.source
                .error_at(&[crate::config::Seg::key("analysis"), crate::config::Seg::key("group_size")], e.to_string()),
        )
    });
    // Every rank computes the same answer: agree only to print it once.
    let groups = agree(&ctx.comm, groups, Error::exit_code)?;
    if !restart {
        super::prepare(ctx, out, job.spec.output.existing)?;
    }
    let members = job.members();
    log.info(format!(
        "sweep {}: {}, {} group(s) of {} rank(s){}",
        path.display(),
        job.plan_line(),
        groups.count,
        size,
        if restart { ", restart" } else { "" }
    ));
    let mesh = agree(&ctx.comm, read_msh(&job.base.mesh_file).map_err(Error::from), Error::exit_code)?;

    // The folders and the job files (rank 0; the same text again on a restart).
    let written = if ctx.rank == 0 { write_tasks(job, &members, restart, log) } else { Ok(()) };
    agree(&ctx.comm, written, Error::exit_code)?;

    let mut argv = vec!["masonry-hpc".to_string()];
    argv.extend(petsc_args.iter().cloned());
    let petsc = Petsc::initialize(&argv)?;
    petsc.set_default_options("", &job.base.petsc_options)?;

    let gctx = Context::new(groups.group.duplicate(), true);
    let tag = format!("[group {}/{}]", groups.index + 1, groups.count);

    let seconds_gravity = gravity_states(ctx, &groups, &gctx, job, &mesh, &tag);
    let s = Shared { ctx, groups: &groups, gctx: &gctx, job, mesh: &mesh, tag: &tag };
    let (members, members_run, seconds_members) = match job.intensities() {
        Intensities::Grid(_) => grid_members(&s, members)?,
        Intensities::Hunt(rules) => hunt_members(&s, rules, restart)?,
    };
    drop(petsc);

    // The table, the summary and the curves.
    let timing = table::Timing {
        groups: groups.count,
        group_size: size,
        seconds_gravity,
        seconds_members,
        members_run,
        members_per_hour: if seconds_members > 0.0 { 3600.0 * members_run as f64 / seconds_members } else { 0.0 },
    };
    let done = if ctx.rank == 0 { table::write_results(job, &members, timing, log) } else { Ok(()) };
    agree(&ctx.comm, done, Error::exit_code)?;
    Ok(())
}

/// Collective. Phase (1): the gravity state of every material not done yet, one task per
/// variant; its seconds.
fn gravity_states(
    ctx: &Context,
    groups: &Groups,
    gctx: &Context,
    job: &SweepJob,
    mesh: &crate::mesh::Mesh,
    tag: &str,
) -> f64 {
    let log = &ctx.log;
    let out = &job.output_dir;
    let leader = log.speaking(gctx.rank == 0);
    let todo: Vec<usize> =
        (0..job.variants.len()).filter(|&v| !member::variant_done(&member::variant_dir(out, job, v))).collect();
    if !todo.is_empty() {
        log.info(format!("gravity states of {} material(s)", todo.len()));
    }
    let clock = std::time::Instant::now();
    let mut d = Dispatcher::new(groups, &todo);
    while let Some(v) = d.next_task() {
        let dir = member::variant_dir(out, job, v);
        let name = &job.variants[v].name;
        leader.info(format!("{tag} gravity of material {name} ..."));
        match member::prepare_variant(gctx, &member::variant_job(out, job, v), &dir, mesh) {
            Ok(s) => leader.info(format!("{tag} gravity of material {name}: done in {s:.1} s")),
            Err(e) => leader.info(format!("{tag} gravity of material {name} FAILED: {e}")),
        }
    }
    d.finish();
    ctx.comm.barrier();
    clock.elapsed().as_secs_f64()
}

/// What the members' phase runs with.
struct Shared<'a> {
    ctx: &'a Context,
    groups: &'a Groups,
    gctx: &'a Context,
    job: &'a SweepJob,
    mesh: &'a crate::mesh::Mesh,
    tag: &'a str,
}

/// Collective. Phase (2) on a grid: the members not done yet, the highest intensity first (the
/// costliest); the members, how many ran, and their seconds.
fn grid_members(s: &Shared, members: Vec<Member>) -> Result<(Vec<Member>, usize, f64), Error> {
    let out = &s.job.output_dir;
    let mut order: Vec<&Member> =
        members.iter().filter(|m| Outcome::read(&member::member_dir(out, m)).is_none()).collect();
    order.sort_by(|a, b| b.level.total_cmp(&a.level).then(a.index.cmp(&b.index)));
    let order: Vec<usize> = order.iter().map(|m| m.index).collect();
    s.ctx.log.info(format!(
        "{} member(s) to run{}",
        order.len(),
        if order.len() < members.len() {
            format!(" ({} done before)", members.len() - order.len())
        } else {
            String::new()
        }
    ));
    let clock = std::time::Instant::now();
    let mut d = Dispatcher::new(s.groups, &order);
    while let Some(k) = d.next_task() {
        let pos = format!("{}/{}", order.iter().position(|&x| x == k).map_or(0, |p| p + 1), order.len());
        run_one(s, &members[k], &pos, &mut d)?;
    }
    d.finish();
    s.ctx.comm.barrier();
    Ok((members, order.len(), clock.elapsed().as_secs_f64()))
}

/// Collective. Phase (2) by hunt and fill: the chains of every record and material decided on
/// world rank 0 as the members' outcomes come in (`feed.rs`), each member's job file written by
/// its group's leader; the members (on rank 0), how many ran, and their seconds.
fn hunt_members(s: &Shared, rules: &HuntRules, restart: bool) -> Result<(Vec<Member>, usize, f64), Error> {
    let (job, log) = (s.job, &s.ctx.log);
    let mut feed = feed::HuntFeed::new(job, rules, log.clone());
    if restart && s.ctx.rank == 0 {
        let done = feed.restore(&job.output_dir);
        log.info(format!("restart: {done} member(s) of the hunts done before, their decisions replayed"));
    }
    let clock = std::time::Instant::now();
    let mut d = Dispatcher::with_source(s.groups, &mut feed);
    while let Some(k) = d.next_task() {
        let m = feed::member_of_task(job, k);
        let (dir, file) = (member::member_dir(&job.output_dir, &m), member::member_job(&job.output_dir, &m));
        let written = if s.gctx.rank == 0 {
            std::fs::create_dir_all(&dir)
                .and_then(|()| std::fs::write(&file, job.member_job_text(&m, &dir).map_err(std::io::Error::other)?))
                .map_err(|source| Error::OutputDir { path: file.clone(), source })
        } else {
            Ok(())
        };
        agree(&s.gctx.comm, written, Error::exit_code)?;
        run_one(s, &m, &format!("{} {:.4}", job.spec.sweep.scale_by.label(), m.level), &mut d)?;
    }
    d.finish();
    drop(d);
    s.ctx.comm.barrier();
    Ok((feed.members(), feed.handed_out, clock.elapsed().as_secs_f64()))
}

/// Collective over the group. Runs member `m` (`pos` says where it stands, for the log) and
/// writes its outcome; `d` serves the other groups after each step.
fn run_one(s: &Shared, m: &Member, pos: &str, d: &mut Dispatcher) -> Result<(), Error> {
    let (job, out) = (s.job, &s.job.output_dir);
    let leader = s.ctx.log.speaking(s.gctx.rank == 0);
    let dir = member::member_dir(out, m);
    let gravity = member::variant_dir(out, job, m.variant);
    let tag = s.tag;
    let outcome = if member::variant_done(&gravity) {
        leader.info(format!("{tag} member {pos} {} ({} x {:.4}) ...", m.name, job.records[m.record].name, m.factor));
        member::run_member(s.gctx, job, m, out, s.mesh, &mut Serve(d, &m.name))
    } else {
        Outcome::gravity_failed(job, m, &member::variant_failure(&gravity))
    };
    leader.info(format!(
        "{tag} member {pos} {}: {} at t = {:.3} s{} in {:.1} s{}",
        m.name,
        outcome.status.name(),
        outcome.time_reached,
        if outcome.ended_at_limits.is_some() { " (every limit passed: ended there)" } else { "" },
        outcome.seconds,
        outcome.diagnosis.as_deref().map(|d| format!(": {}", first_sentence(d))).unwrap_or_default()
    ));
    let written = if s.gctx.rank == 0 {
        outcome.write(&dir).map_err(|source| Error::OutputDir { path: dir.join(OUTCOME_FILE), source })
    } else {
        Ok(())
    };
    agree(&s.gctx.comm, written, Error::exit_code)?;
    Ok(())
}

/// The first sentence of a diagnosis, for a progress line.
fn first_sentence(s: &str) -> &str {
    s.split(". ").next().unwrap_or(s)
}

/// Rank 0: the folders of the gravity states and members with their job files. A restart keeps
/// what is there (the files are written again with the same text).
fn write_tasks(job: &SweepJob, members: &[Member], restart: bool, log: &Log) -> Result<(), Error> {
    let out = &job.output_dir;
    let io = |p: &Path| {
        let p = p.to_path_buf();
        move |source| Error::OutputDir { path: p, source }
    };
    if restart && !out.is_dir() {
        return Err(JobError::NothingToRestart { dir: out.clone() }.into());
    }
    let jobs = out.join("jobs");
    std::fs::create_dir_all(&jobs).map_err(io(&jobs))?;
    let write = |file: &Path, text: String| std::fs::write(file, text).map_err(io(file));
    for v in 0..job.variants.len() {
        let dir = member::variant_dir(out, job, v);
        std::fs::create_dir_all(&dir).map_err(io(&dir))?;
        // The gravity state's job: the variant's first member's, its results in this folder.
        let first = match job.intensities() {
            Intensities::Grid(x) => job.member(0, v, 0, x[0], Some(0)),
            Intensities::Hunt(h) => job.member(0, v, 0, hunt::on_lattice(h.first), None),
        };
        write(&member::variant_job(out, job, v), job.member_job_text(&first, &dir)?)?;
    }
    for m in members {
        let dir = member::member_dir(out, m);
        std::fs::create_dir_all(&dir).map_err(io(&dir))?;
        write(&member::member_job(out, m), job.member_job_text(m, &dir)?)?;
    }
    let kind = match job.base.spec.analysis {
        AnalysisConfig::SeismicAssessment(_) => "seismic assessment (modal updating once per material)",
        _ => "time history",
    };
    let count = match job.intensities() {
        Intensities::Grid(_) => format!("{} of them", members.len()),
        Intensities::Hunt(_) => "written as the hunts decide them".into(),
    };
    log.info(format!(
        "job files: {}/jobs/<member>.toml ({count}, each runs alone), base job {} ({kind})",
        out.display(),
        job.base_file.display()
    ));
    Ok(())
}
