//! The `time_history` job: setup, gravity (or a checkpoint), then the steps, with output every k
//! steps, CSV rows every step, checkpoints, progress and, when a step fails for good, a diagnosis,
//! a checkpoint of the last converged state and a clean stop.
//!
//! ```text
//!  setup       PetscSystem::on the problem: M, K₀, static load, ι_d, M ι_d, KSP
//!  initial     gravity::solve_gravity → State::at_rest          | checkpoint::read_latest (--restart)
//!              (a static load the model cannot carry: gravity-failure.xdmf, the last equilibrium)
//!  per step    Stepper::advance (Newton, substeps) → envelopes, monitors.csv, energy.csv, progress
//!              every `output_every` steps: results.xdmf (relative and absolute u, v, a; cell outputs)
//!              every N steps / M minutes: checkpoint
//!  end         final checkpoint, envelopes.xdmf, monitor PNGs, summary
//! ```
//!
//! [`integrate`] is the stepping loop on its own, callable by a driver that chains analyses
//! (modal → updating → gravity → earthquake) on the same [`PetscSystem`].
use super::checkpoint::{self, CheckpointClock};
use super::damage_shares;
use super::damping::Rayleigh;
use super::diagnosis::{self, agreed};
use super::gravity::{solve_gravity, GravitySettings};
use super::gravity_failure::gravity_failure;
use super::ground::GroundMotion;
use super::integration::{Integration, SavedEnvelopes, RESULTS_STEM};
use super::petsc_system::PetscSystem;
use super::progress::Progress;
use super::scheme::Scheme;
use super::step_output::StepOutputs;
use super::stepper::{State, StepReport, StepSettings, Stepper};
pub use super::summary::{DriftPeak, TimeHistorySummary};
use crate::analysis::output::global_max_with_tag;
use crate::analysis::FeProblem;
use crate::config::{scheme_parameters, DynamicsConfig, Job};
use crate::error::{AnalysisError, Error};
use crate::mesh::Mesh;
use crate::model::StructuralModel;
use crate::parallel::{agree, Context, Phases};
use std::path::Path;

/// The ground motion of the job's components.
pub fn ground_motion(cfg: &DynamicsConfig) -> GroundMotion {
    let mut c: [Option<crate::seismic::Record>; 3] = Default::default();
    for g in &cfg.ground_motion {
        c[g.direction.index()] = g.record.clone();
    }
    GroundMotion::new(c)
}

/// Where a time history starts.
#[derive(Clone, Copy, Debug)]
pub enum Start<'a> {
    /// Gravity solved in load steps, the model at rest under it.
    Gravity,
    /// The latest checkpoint in the job's results folder (`--restart`).
    Restart,
    /// The gravity state [`save_gravity`] wrote into a folder (a sweep's, shared by its members),
    /// the model at rest under it when this job's ground starts moving.
    SavedGravity(&'a Path),
}

/// Called on every rank after each converged step (its output and checkpoint done): a sweep's
/// scheduler answers the other groups there while its own group computes.
pub trait StepObserver {
    /// Step `step` is done.
    fn after_step(&mut self, step: usize);
}

impl StepObserver for () {
    fn after_step(&mut self, _step: usize) {}
}

/// Collective. The time history of `p`: the system (setup), gravity, a restart or a saved gravity
/// state (`start`), integration; `observer` is called after every step.
pub fn run(mut p: FeProblem, start: Start, observer: &mut dyn StepObserver) -> Result<TimeHistorySummary, Error> {
    let (ctx, job, mesh, model) = (p.ctx, p.job, p.mesh, p.model);
    let cfg = job.spec.dynamics.as_ref().ok_or(AnalysisError::NoDynamics)?;
    let (beta, gamma, alpha) = scheme_parameters(cfg);
    let rayleigh = Rayleigh::from_config(&cfg.damping);
    let ground = ground_motion(cfg);
    let mut phases = Phases::default();
    phases.add("setup", p.take_setup_seconds());
    let mut sys = phases.time("setup", || PetscSystem::on(p, cfg.mass, rayleigh))?;
    log_setup(ctx, cfg, model, &sys, (beta, gamma, alpha), rayleigh);
    let (state, envelopes) = phases.time("gravity", || -> Result<_, Error> {
        match start {
            Start::Restart => {
                let c = checkpoint::read_latest(ctx, &job.output_dir)?;
                ctx.log.info(format!("restart from the checkpoint of step {} (t = {} s)", c.step, c.t));
                checkpoint::restore(ctx, &mut sys, c)
            }
            Start::Gravity => Ok((at_rest_under_gravity(ctx, &mut sys, job, mesh, model, cfg, &ground)?, None)),
            Start::SavedGravity(dir) => {
                let c = checkpoint::read_latest(ctx, dir)?;
                ctx.log.info(format!("the gravity state of {}", dir.display()));
                let u0 = c.vectors[0].clone();
                checkpoint::restore(ctx, &mut sys, c)?;
                Ok((State::at_rest(&mut sys, u0, ground.acceleration(0.0))?, None))
            }
        }
    })?;
    // After gravity (implicit) or the restored state (either layout): the history starts here.
    let implex =
        (cfg.integration == crate::config::IntegrationKind::Implex).then(|| cfg.implex_split.unwrap_or_default());
    if sys.set_implex(implex)? {
        ctx.log.info("IMPL-EX: J is symmetric at each step's fixed damage, factored by Cholesky");
    }
    let restart = matches!(start, Start::Restart);
    let first_step = state.step;
    let stem = if restart { format!("{RESULTS_STEM}-restart-{first_step:06}") } else { RESULTS_STEM.to_string() };
    let it = Integration { cfg, job, mesh, model, ground: &ground, stem, restart };
    let settings = StepSettings {
        scheme: Scheme { beta, gamma, alpha },
        newton: cfg.newton,
        integration: cfg.integration,
        krylov_dimension: cfg.krylov_dimension,
        refresh_cost: cfg.refresh_cost,
        max_iterations: cfg.max_iterations,
        tolerance: cfg.force_tolerance,
        max_substeps: cfg.max_substeps,
        max_damage_increment: cfg.max_damage_increment,
        line_search: cfg.line_search,
        implex_corrections: cfg.implex_corrections,
        implex_tolerance: cfg.implex_correction_tolerance,
        implex_pass_tolerance: cfg.implex_pass_tolerance.unwrap_or(0.0),
    };
    let mut summary = integrate(ctx, &mut sys, &it, settings, state, envelopes, observer)?;
    [summary.seconds[0], summary.seconds[1]] = phases.seconds_of(["setup", "gravity"]);
    summary.rayleigh = [rayleigh.alpha, rayleigh.beta];
    summary.newton = format!("{:?}", cfg.newton).to_lowercase();
    summary.line_search = cfg.line_search;
    summary.integration = cfg.integration.name().to_string();
    summary.implex_split = implex.map(|s| s.name().to_string());
    summary.implex_corrections = cfg.implex_corrections;
    summary.implex_correction_tolerance = cfg.implex_correction_tolerance;
    summary.implex_pass_tolerance = cfg.implex_pass_tolerance;
    Ok(summary)
}

/// Collective. Gravity solved on `p` (as [`Start::Gravity`] does) and its state saved as a
/// checkpoint of step 0 under `dir`, for [`Start::SavedGravity`]. A static load the model cannot
/// carry is an error with its diagnosis in the job's results folder.
pub fn save_gravity(p: FeProblem, dir: &Path) -> Result<(), Error> {
    let (ctx, job, mesh, model) = (p.ctx, p.job, p.mesh, p.model);
    let cfg = job.spec.dynamics.as_ref().ok_or(AnalysisError::NoDynamics)?;
    let rayleigh = Rayleigh::from_config(&cfg.damping);
    let ground = ground_motion(cfg);
    let mut sys = PetscSystem::on(p, cfg.mass, rayleigh)?;
    let state = at_rest_under_gravity(ctx, &mut sys, job, mesh, model, cfg, &ground)?;
    let states = agree(&ctx.comm, checkpoint::element_states(&sys.disc.elements), Error::exit_code)?;
    let c = checkpoint::Checkpoint {
        step: 0,
        t: 0.0,
        energy: state.energy.to_array(),
        vectors: [state.u, state.v, state.a, state.f_int, state.cv],
        states,
        node_envelope: Vec::new(),
        cell_envelope: Vec::new(),
        substep_level: 0,
    };
    checkpoint::write(ctx, dir, &c)?;
    Ok(())
}

/// The system and the scheme, and each ground-motion component, in the log.
fn log_setup(
    ctx: &Context,
    cfg: &DynamicsConfig,
    model: &StructuralModel,
    sys: &PetscSystem,
    (beta, gamma, alpha): (f64, f64, f64),
    rayleigh: Rayleigh,
) {
    let log = &ctx.log;
    log.info(format!(
        "setup: {} equations, {} element(s) ({}), {:?} mass; Newmark β = {beta}, γ = {gamma}, HHT α = {alpha}; Rayleigh α = {:.4e} 1/s, β = {:.4e} s; {:?} Newton, {} damage; {}",
        6 * sys.disc.dofs.n_global_nodes,
        model.cells.len(),
        if sys.linear { "all linear" } else { "with damage" },
        cfg.mass,
        rayleigh.alpha,
        rayleigh.beta,
        cfg.newton,
        cfg.integration.name(),
        sys.describe_solver()
    ));
    for g in &cfg.ground_motion {
        if let Some(r) = &g.record {
            log.info(format!(
                "ground motion {:?}: {} ({} s, dt {} s, PGA {:.4} m/s²)",
                g.direction,
                r.name,
                r.duration(),
                r.dt,
                crate::seismic::pga(r)
            ));
        }
    }
}

/// Collective. The state the earthquake starts from: gravity solved (in load steps), the model at
/// rest there. A static load the model cannot carry is an error with its diagnosis
/// (`gravity-failure.xdmf`, the last equilibrium).
fn at_rest_under_gravity(
    ctx: &Context,
    sys: &mut PetscSystem,
    job: &Job,
    mesh: &Mesh,
    model: &StructuralModel,
    cfg: &DynamicsConfig,
    ground: &GroundMotion,
) -> Result<State, Error> {
    let g = GravitySettings {
        steps: cfg.gravity_steps,
        max_iterations: cfg.max_iterations.max(10),
        tolerance: cfg.force_tolerance.min(1e-8),
        max_cuts: cfg.max_substeps,
    };
    let u0 = match solve_gravity(sys, g, &ctx.log) {
        Ok(u) => u,
        Err(f) => return Err(gravity_failure(ctx, sys, job, mesh, model, f)),
    };
    State::at_rest(sys, u0, ground.acceleration(0.0))
}

/// Collective. The stepping loop from `state` to the end of `[dynamics] duration`: per step the
/// step itself (Newton, substeps) with its records ("stepping"), every `output_every` steps the
/// results ("output"), when due a checkpoint ("checkpoint"); then the summary and the envelopes.
pub fn integrate(
    ctx: &Context,
    sys: &mut PetscSystem,
    it: &Integration,
    settings: StepSettings,
    mut state: State,
    envelopes: Option<SavedEnvelopes>,
    observer: &mut dyn StepObserver,
) -> Result<TimeHistorySummary, Error> {
    let log = &ctx.log;
    let cfg = it.cfg;
    let dt = cfg.dt;
    let n_steps = ((cfg.duration / dt) - 1e-9).ceil().max(1.0) as usize;
    let mut out = StepOutputs::open(ctx, sys, it, &state, envelopes)?;
    let mut summary = TimeHistorySummary {
        ranks: ctx.size,
        equations: 6 * sys.disc.dofs.n_global_nodes,
        elements: it.model.cells.len(),
        linear: sys.linear,
        scheme: [settings.scheme.beta, settings.scheme.gamma, settings.scheme.alpha],
        solver: sys.describe_solver(),
        dt,
        max_damage_increment: settings.max_damage_increment,
        smallest_substep: dt,
        steps: n_steps,
        first_step: state.step,
        results: out.writer.xdmf_path().display().to_string(),
        ..Default::default()
    };
    let mut phases = Phases::default();
    if !it.restart {
        out.record(ctx, it, &state);
        phases.time("output", || out.write_step(ctx, sys, it, &state))?;
        summary.output_steps += 1;
    }
    let mut stepper = Stepper::new(settings);
    let mut progress = Progress::new(log, state.step, n_steps, 5.0);
    let mut clock = CheckpointClock::default();
    let factorizations0 = sys.factorizations;
    let system0 = sys.phases.clone();
    log.info(format!("time history: {n_steps} step(s) of {dt} s from step {} (t = {} s)", state.step, state.t));
    while state.step < n_steps {
        phases.time("stepping", || -> Result<(), Error> {
            let report = step(ctx, sys, it, &mut stepper, &mut state, &out)?;
            summary.iterations += report.iterations;
            summary.failed_iterations += report.failed_iterations;
            summary.implex_passes += report.implex_passes;
            if report.substeps > 1 {
                summary.substepped_steps += 1;
            }
            summary.add_damage_control(&report);
            summary.max_balance_error = summary.max_balance_error.max(state.energy.relative_error());
            out.record(ctx, it, &state);
            progress.step(log, state.step, state.t, report.iterations, report.substeps, report.residual);
            Ok(())
        })?;
        let mut stop = false;
        if state.step % cfg.output_every == 0 || state.step == n_steps {
            phases.time("output", || out.write_step(ctx, sys, it, &state))?;
            summary.output_steps += 1;
            // `[[dynamics.stop_when]]`, on the cell damage the output step just read.
            stop = state.step < n_steps && !cfg.stop_when.is_empty() && {
                let groups = damage_shares::by_group(ctx, &sys.disc, &out.env, it.mesh, it.model, it.job);
                damage_shares::stop_reached(&groups, &cfg.stop_when)
            };
        }
        if cfg.checkpoint.every_steps > 0 && state.step % cfg.checkpoint.every_steps == 0 {
            // The step after a periodic checkpoint starts as a restart from it would: a fresh
            // tangent, the linear step's products computed afresh. So a run restarted from such
            // a checkpoint repeats the uninterrupted run's operations (and results) exactly.
            stepper.start_afresh();
        }
        if clock.due(ctx, cfg, state.step) || state.step == n_steps || stop {
            phases.time("checkpoint", || checkpoint::save(ctx, sys, &state, &out.env, &it.job.output_dir))?;
            clock.restart();
            summary.checkpoints += 1;
        }
        observer.after_step(state.step);
        if stop {
            log.info(format!("every [[dynamics.stop_when]] share is reached at t = {} s: the run ends here", state.t));
            summary.stopped_by_shares = Some(state.t);
            break;
        }
    }
    summary.factorizations = sys.factorizations - factorizations0;
    (summary.tangents_kept, summary.tangents_fresh) = (stepper.refresh.kept, stepper.refresh.refreshed);
    for &(name, seconds) in sys.phases.all() {
        summary.system_seconds.insert(name.to_string(), seconds - system0.seconds(name));
    }
    let [t_stepping, t_output, t_checkpoint] = phases.seconds_of(["stepping", "output", "checkpoint"]);
    summary.seconds[2..5].copy_from_slice(&[t_stepping, t_output, t_checkpoint]);
    finish(ctx, sys, it, &state, out, summary)
}

/// Collective. One step to `(step + 1) dt` (the last one to the duration). A step that fails for
/// good is an error with its diagnosis, after a checkpoint of the last converged state.
fn step(
    ctx: &Context,
    sys: &mut PetscSystem,
    it: &Integration,
    stepper: &mut Stepper,
    state: &mut State,
    out: &StepOutputs,
) -> Result<StepReport, Error> {
    let cfg = it.cfg;
    crate::fault::inject(&format!("time_step_{}", state.step + 1), ctx.rank)?;
    let target = ((state.step + 1) as f64 * cfg.dt).min(cfg.duration);
    let ground = |t: f64| it.ground.acceleration(t);
    let f = match stepper.advance(sys, &ground, state, target, cfg.dt) {
        Ok(report) => return Ok(report),
        Err(f) => f,
    };
    let dir = &it.job.output_dir;
    let (rmax, tag, dof) = diagnosis::largest_residual(ctx, &f.r, &sys.disc.dofs, it.mesh);
    let (count, worst) =
        diagnosis::changed_elements(ctx, &mut sys.disc.elements, &sys.disc.local_cells, it.mesh, it.model);
    let ck = checkpoint::save(ctx, sys, state, &out.env, dir)?;
    let listed: Vec<String> = worst.iter().map(|(t, d)| format!("{t} (Δstate {d:.3e})")).collect();
    let diagnosis = format!(
        "time history: step {} (t = {:.6} → {target:.6} s) did not converge even with substeps of {:.3e} s ({}; relative residual {:.3e}). \
         Largest out-of-balance force {rmax:.4e} at node {tag}, DOF {dof}. {count} element(s) changed state in the failed iteration{}. \
         The state at t = {:.6} s is checkpointed in {} (restart with --restart after changing the settings); results up to the last output step are in {}",
        state.step + 1,
        state.t,
        f.h,
        f.reason,
        f.residual,
        if listed.is_empty() { String::new() } else { format!(", most: element {}", listed.join(", ")) },
        state.t,
        ck.display(),
        out.writer.xdmf_path().display()
    );
    // Every rank has the same failure: agree on it so it is printed once.
    Err(agreed(ctx, AnalysisError::StepFailed { step: state.step + 1, diagnosis }.into()))
}

/// The substeps and the damage control in the run's last lines: how many steps were substepped
/// and cut by damage, the smallest substep.
fn substep_line(s: &TimeHistorySummary) -> String {
    let control = if s.max_damage_increment >= 1.0 {
        "damage control off".to_string()
    } else {
        format!(
            "damage control (Δd ≤ {}): {} step(s) cut by damage ({} cut(s), {} iteration(s)), {} substep(s) over the limit at the smallest size, largest Δd {:.3}",
            s.max_damage_increment,
            s.damage_cut_steps,
            s.damage_cuts,
            s.damage_cut_iterations,
            s.over_limit_substeps,
            s.max_step_damage_increment
        )
    };
    format!("{} step(s) substepped, smallest substep {:.4e} s; {control}", s.substepped_steps, s.smallest_substep)
}

/// The peak base shear and storey drifts in the run's last lines.
fn engineering_line(s: &TimeHistorySummary) -> String {
    let [vx, vy] = s.peak_base_shear;
    let [tx, ty] = s.peak_base_shear_time;
    let w = s.weight.iter().map(|v| v * v).sum::<f64>().sqrt();
    let of_weight = |v: f64| if w > 0.0 { format!(" ({:.3} W)", v / w) } else { String::new() };
    let mut line = format!(
        "peak base shear: x {vx:.4e} N{} at t = {tx:.4} s, y {vy:.4e} N{} at t = {ty:.4} s",
        of_weight(vx),
        of_weight(vy)
    );
    for d in &s.drifts {
        line += &format!(
            "; drift '{}' ({:.3} → {:.3} m): peak x {:.3e} at t = {:.4} s, y {:.3e} at t = {:.4} s",
            d.name, d.levels[0], d.levels[1], d.peak[0], d.peak_time[0], d.peak[1], d.peak_time[1]
        );
    }
    line
}

/// Collective. The summary's totals (time, energies, peaks over ranks), the envelopes written,
/// the outputs closed, and the run's last log lines.
fn finish(
    ctx: &Context,
    sys: &PetscSystem,
    it: &Integration,
    state: &State,
    out: StepOutputs,
    mut summary: TimeHistorySummary,
) -> Result<TimeHistorySummary, Error> {
    let log = &ctx.log;
    let dir = &it.job.output_dir;
    summary.time = state.t;
    let steps_done = (state.step - summary.first_step).max(1);
    summary.seconds_per_step = summary.seconds[2] / steps_done as f64;
    let e = state.energy;
    summary.energy = [e.input, e.kinetic, e.strain - e.strain0, e.damping, e.dissipated(), e.unilateral()];
    // Envelopes over ranks.
    let env = &out.env;
    let mut peak = [0.0; 4];
    for (k, p) in peak.iter_mut().enumerate() {
        *p = global_max_with_tag(&ctx.comm, env.node_max(k), 0).0;
    }
    summary.peak_displacement = [peak[0], peak[1], peak[2]];
    summary.peak_drift_ratio = peak[3];
    summary.max_damage =
        [global_max_with_tag(&ctx.comm, env.cell_max(0), 0).0, global_max_with_tag(&ctx.comm, env.cell_max(1), 0).0];
    summary.model_mass = sys.disc.mass.mass;
    summary.weight = sys.disc.mass.weight;
    let peaks = out.peaks(ctx);
    summary.peak_base_shear = [peaks[0].0, peaks[1].0];
    summary.peak_base_shear_time = [peaks[0].1, peaks[1].1];
    summary.drifts = out
        .drifts
        .iter()
        .zip(peaks[2..].chunks(2))
        .map(|(d, p)| DriftPeak {
            name: d.name.clone(),
            levels: d.levels(),
            nodes: d.counts(),
            peak: [p[0].0, p[1].0],
            peak_time: [p[0].1, p[1].1],
        })
        .collect();
    summary.damage_by_group = damage_shares::by_group(ctx, &sys.disc, env, it.mesh, it.model, it.job);
    summary.convergence = damage_shares::with_band(it.job, &mut summary.damage_by_group);
    if let Some(r) = &summary.convergence {
        log.info(damage_shares::band_line(r));
    }
    out.close(ctx, sys, dir, state.t)?;
    log.info(format!(
        "time history done: t = {:.4} s, {} iteration(s), {} factorization(s) ({} step(s) on a kept tangent), {:.4} s per step; {}; peak |u| = ({:.4e}, {:.4e}, {:.4e}) m, peak drift ratio {:.3e}, max damage d_t {:.4}, d_c {:.4}; energy: input {:.4e} J, kinetic {:.4e}, strain {:.4e}, damping {:.4e}, damage {:.4e}, unilateral {:.4e}, balance error {:.2e} (max {:.2e})",
        state.t,
        summary.iterations,
        summary.factorizations,
        summary.tangents_kept,
        summary.seconds_per_step,
        substep_line(&summary),
        peak[0],
        peak[1],
        peak[2],
        peak[3],
        summary.max_damage[0],
        summary.max_damage[1],
        e.input,
        e.kinetic,
        e.strain - e.strain0,
        e.damping,
        e.dissipated(),
        e.unilateral(),
        e.relative_error(),
        summary.max_balance_error
    ));
    log.info(engineering_line(&summary));
    log.info(format!(
        "results: {} (every {} step(s)), {}, {}, {}",
        summary.results,
        it.cfg.output_every,
        dir.join("envelopes.xdmf").display(),
        dir.join("energy.csv").display(),
        dir.join("monitors.csv").display()
    ));
    Ok(summary)
}
