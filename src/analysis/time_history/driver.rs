//! The `time_history` job: setup, gravity (or a checkpoint), then the steps, with output every k
//! steps, CSV rows every step, checkpoints, progress and, when a step fails for good, a diagnosis,
//! a checkpoint of the last converged state and a clean stop.
//!
//! ```text
//!  setup       PetscSystem::new: partition, elements, M, K₀, static load, ι_d, M ι_d, KSP
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
use super::checkpoint::{self, Checkpoint};
use super::damping::Rayleigh;
use super::diagnosis;
use super::envelope::Envelopes;
use super::gravity::{solve_gravity, GravityFailure, GravitySettings};
use super::ground::GroundMotion;
use super::monitor::{self, CsvLog};
use super::petsc_system::PetscSystem;
use super::progress::Progress;
use super::scheme::Scheme;
use super::stepper::{State, StepSettings, Stepper};
use super::system::DynamicSystem;
use super::EnergyBalance;
use crate::analysis::output::{global_max_with_tag, node_triplets, MeshPiece};
use crate::analysis::Discretization;
use crate::config::{scheme_parameters, DynamicsConfig, Job};
use crate::element::AppliedLoads;
use crate::error::Error;
use crate::io::ResultsWriter;
use crate::mesh::Mesh;
use crate::model::StructuralModel;
use crate::parallel::{agree, Context};
use mpi::traits::{Communicator, Root};
use std::time::Instant;

/// What a time-history run reports (`summary.json`).
#[derive(Debug, Clone, Default, serde::Serialize)]
pub struct TimeHistorySummary {
    /// Ranks.
    pub ranks: usize,
    /// Equations (6 per node).
    pub equations: usize,
    /// Elements.
    pub elements: usize,
    /// Whether every element is linear.
    pub linear: bool,
    /// Scheme: β, γ, α.
    pub scheme: [f64; 3],
    /// Rayleigh α [1/s], β [s].
    pub rayleigh: [f64; 2],
    /// Newton variant.
    pub newton: String,
    /// Linear solver.
    pub solver: String,
    /// Time step [s].
    pub dt: f64,
    /// Steps of the whole history.
    pub steps: usize,
    /// Step the run started from (0, or the checkpoint's on a restart).
    pub first_step: usize,
    /// Time reached [s].
    pub time: f64,
    /// Newton iterations (solves) in this run.
    pub iterations: usize,
    /// Steps that needed substeps.
    pub substepped_steps: usize,
    /// Jacobian factorizations (operator changes).
    pub factorizations: usize,
    /// Output steps written.
    pub output_steps: usize,
    /// Checkpoints written.
    pub checkpoints: usize,
    /// Final energies [J]: input, kinetic, strain, damping, dissipated by damage (the law's),
    /// exchanged at unilateral switches (`energy.rs`).
    pub energy: [f64; 6],
    /// Largest relative energy-balance error over the steps.
    pub max_balance_error: f64,
    /// Peak relative displacement over nodes and time, x y z [m].
    pub peak_displacement: [f64; 3],
    /// Peak drift ratio.
    pub peak_drift_ratio: f64,
    /// Largest tensile and compressive damage.
    pub max_damage: [f64; 2],
    /// Seconds: setup, gravity, stepping, output, checkpoints.
    pub seconds: [f64; 5],
    /// Stepping seconds per step.
    pub seconds_per_step: f64,
    /// Results file of this run.
    pub results: String,
}

/// Everything the stepping loop needs besides the system and the state (with the envelopes
/// saved in a checkpoint, if continuing one: node and cell values).
pub struct Integration<'a> {
    /// Settings.
    pub cfg: &'a DynamicsConfig,
    /// The job (output folder, parts).
    pub job: &'a Job,
    /// Mesh.
    pub mesh: &'a Mesh,
    /// Model.
    pub model: &'a StructuralModel,
    /// Ground motion.
    pub ground: &'a GroundMotion,
    /// Results file stem.
    pub stem: String,
    /// True when continuing from a checkpoint.
    pub restart: bool,
}

/// Envelopes read from a checkpoint: node values, cell values (see [`Envelopes`]).
pub type SavedEnvelopes = (Vec<f64>, Vec<f64>);

/// The ground motion of the job's components.
pub fn ground_motion(cfg: &DynamicsConfig) -> GroundMotion {
    let mut c: [Option<crate::seismic::Record>; 3] = Default::default();
    for g in &cfg.ground_motion {
        c[g.direction.index()] = g.record.clone();
    }
    GroundMotion::new(c)
}

/// Collective. Runs the job: setup, gravity or restart, integration.
pub fn run(
    ctx: &Context,
    job: &Job,
    mesh: &Mesh,
    model: &StructuralModel,
    restart: bool,
) -> Result<TimeHistorySummary, Error> {
    let t0 = Instant::now();
    let disc = Discretization::setup(ctx, job, mesh, model)?;
    let t_setup = t0.elapsed().as_secs_f64();
    let mut summary = run_on(ctx, job, mesh, model, disc, restart)?;
    summary.seconds[0] += t_setup;
    Ok(summary)
}

/// Collective. As [`run`], on a discretization already set up (the last stage of a seismic
/// assessment): gravity or restart, integration.
pub fn run_on(
    ctx: &Context,
    job: &Job,
    mesh: &Mesh,
    model: &StructuralModel,
    disc: Discretization,
    restart: bool,
) -> Result<TimeHistorySummary, Error> {
    let log = &ctx.log;
    let cfg = job.spec.dynamics.as_ref().ok_or_else(|| Error::Analysis("a time history needs [dynamics]".into()))?;
    let (beta, gamma, alpha) = scheme_parameters(cfg);
    let rayleigh = Rayleigh::from_config(&cfg.damping);
    let ground = ground_motion(cfg);
    let t0 = Instant::now();
    let mut sys = PetscSystem::on(ctx, job, mesh, model, disc, cfg.mass, rayleigh)?;
    let t_setup = t0.elapsed().as_secs_f64();
    log.info(format!(
        "setup: {} equations, {} element(s) ({}), {:?} mass; Newmark β = {beta}, γ = {gamma}, HHT α = {alpha}; Rayleigh α = {:.4e} 1/s, β = {:.4e} s; {:?} Newton; {}",
        6 * sys.disc.dofs.n_global_nodes,
        model.cells.len(),
        if sys.linear { "all linear" } else { "with damage" },
        cfg.mass,
        rayleigh.alpha,
        rayleigh.beta,
        cfg.newton,
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
    let t0 = Instant::now();
    let state = if restart {
        let c = checkpoint::read_latest(ctx, &job.output_dir)?;
        log.info(format!("restart from the checkpoint of step {} (t = {} s)", c.step, c.t));
        restore(ctx, &mut sys, c)?
    } else {
        let g = GravitySettings {
            steps: cfg.gravity_steps,
            max_iterations: cfg.max_iterations.max(10),
            tolerance: cfg.force_tolerance.min(1e-8),
            max_cuts: cfg.max_substeps,
        };
        let u0 = match solve_gravity(&mut sys, g, log) {
            Ok(u) => u,
            Err(f) => return Err(gravity_failure(ctx, &mut sys, job, mesh, model, f)),
        };
        (State::at_rest(&mut sys, u0, ground.acceleration(0.0))?, None)
    };
    let t_gravity = t0.elapsed().as_secs_f64();
    let (state, envelopes) = state;
    let first_step = state.step;
    let stem = if restart { format!("results-restart-{first_step:06}") } else { "results".to_string() };
    let it = Integration { cfg, job, mesh, model, ground: &ground, stem, restart };
    let settings = StepSettings {
        scheme: Scheme { beta, gamma, alpha },
        newton: cfg.newton,
        krylov_dimension: cfg.krylov_dimension,
        max_iterations: cfg.max_iterations,
        tolerance: cfg.force_tolerance,
        max_substeps: cfg.max_substeps,
    };
    let mut summary = integrate(ctx, &mut sys, &it, settings, state, envelopes)?;
    summary.seconds[0] = t_setup;
    summary.seconds[1] = t_gravity;
    summary.rayleigh = [rayleigh.alpha, rayleigh.beta];
    summary.newton = format!("{:?}", cfg.newton).to_lowercase();
    Ok(summary)
}

/// Collective. Restores a checkpoint into the system's elements; the state and envelopes.
fn restore(ctx: &Context, sys: &mut PetscSystem, c: Checkpoint) -> Result<(State, Option<SavedEnvelopes>), Error> {
    let n = sys.len();
    let loaded = (|| -> Result<(), Error> {
        if c.vectors[0].len() != n || c.states.len() != sys.disc.elements.len() {
            return Err(Error::Analysis(format!(
                "the checkpoint holds {} DOFs and {} elements on rank {}, the model {} and {}: was the mesh or the job changed?",
                c.vectors[0].len(),
                c.states.len(),
                ctx.rank,
                n,
                sys.disc.elements.len()
            )));
        }
        for (e, s) in sys.disc.elements.iter_mut().zip(&c.states) {
            if s.len() != e.n_state() {
                return Err(Error::Analysis(format!(
                    "the checkpoint's {} state has {} values, the element {}",
                    e.kind_name(),
                    s.len(),
                    e.n_state()
                )));
            }
            e.load_state(s).map_err(|source| Error::Analysis(format!("checkpoint: {source}")))?;
        }
        Ok(())
    })();
    agree(&ctx.comm, loaded, Error::exit_code)?;
    let [u, v, a, f_int, cv] = c.vectors;
    let state = State { step: c.step, t: c.t, u, v, a, f_int, cv, energy: EnergyBalance::from_array(c.energy) };
    Ok((state, Some((c.node_envelope, c.cell_envelope))))
}

/// Heights of the owned nodes above the model's lowest node.
fn heights(sys: &PetscSystem, mesh: &Mesh) -> Vec<f64> {
    let dofs = &sys.disc.dofs;
    let z0 = (0..mesh.coords.len())
        .filter(|&n| dofs.global[n] != usize::MAX)
        .map(|n| mesh.coords[n][2])
        .fold(f64::INFINITY, f64::min);
    dofs.owned.iter().map(|&n| mesh.coords[n][2] - z0).collect()
}

/// Translations plus the ground's (per direction) at every owned node.
fn absolute(rel: &[f64], g: [f64; 3]) -> Vec<f64> {
    let mut out = rel.to_vec();
    for node in out.chunks_mut(6) {
        for d in 0..3 {
            node[d] += g[d];
        }
    }
    out
}

/// Collective. The stepping loop from `state` to the end of `[dynamics] duration`.
pub fn integrate(
    ctx: &Context,
    sys: &mut PetscSystem,
    it: &Integration,
    settings: StepSettings,
    mut state: State,
    envelopes: Option<SavedEnvelopes>,
) -> Result<TimeHistorySummary, Error> {
    let log = &ctx.log;
    let cfg = it.cfg;
    let dir = &it.job.output_dir;
    let dt = cfg.dt;
    let n_steps = ((cfg.duration / dt) - 1e-9).ceil().max(1.0) as usize;
    let mut env = {
        let mut fresh = Envelopes::new(heights(sys, it.mesh), sys.disc.elements.len());
        if let Some((node, cell)) = envelopes {
            if node.len() == fresh.node.len() && cell.len() == fresh.cell.len() {
                fresh.node = node;
                fresh.cell = cell;
            }
        }
        fresh
    };
    let monitors = monitor::resolve(&cfg.monitor, it.mesh, &sys.disc.dofs)?;
    for m in &monitors {
        log.info(format!("monitor '{}': node {} at {:?}", m.name, m.tag, it.mesh.coords[m.node]));
    }
    let restart_step = it.restart.then_some(state.step);
    let mut energy_csv = CsvLog::open(ctx, &dir.join("energy.csv"), EnergyBalance::CSV_HEADER, restart_step)?;
    let mut monitor_csv = CsvLog::open(ctx, &dir.join("monitors.csv"), &monitor::header(&monitors), restart_step)?;
    let piece = MeshPiece::new(ctx, it.job, it.mesh, it.model, &sys.disc);
    let mut writer = agree(
        &ctx.comm,
        ResultsWriter::create(&ctx.comm, dir, &it.stem, &piece.view()).map_err(Error::from),
        Error::exit_code,
    )?;
    let mut summary = TimeHistorySummary {
        ranks: ctx.size,
        equations: 6 * sys.disc.dofs.n_global_nodes,
        elements: it.model.cells.len(),
        linear: sys.linear,
        scheme: [settings.scheme.beta, settings.scheme.gamma, settings.scheme.alpha],
        solver: sys.describe_solver(),
        dt,
        steps: n_steps,
        first_step: state.step,
        results: writer.xdmf_path().display().to_string(),
        ..Default::default()
    };
    let (mut t_output, mut t_checkpoint) = (0.0, 0.0);
    let record_rows = |state: &State, energy_csv: &mut CsvLog, monitor_csv: &mut CsvLog| {
        let a_abs = absolute(&state.a, it.ground.acceleration(state.t));
        let vals = monitor::values(ctx, &monitors, &state.u, &a_abs);
        let mut row = format!("{},{:.10e}", state.step, state.t);
        for v in vals {
            row += &format!(",{v:.17e}");
        }
        monitor_csv.row(&row, log);
        energy_csv.row(&state.energy.csv_row(state.step, state.t), log);
    };
    if !it.restart {
        env.update_nodes(&state.u);
        record_rows(&state, &mut energy_csv, &mut monitor_csv);
        let t0 = Instant::now();
        write_step(ctx, &mut writer, sys, it, &state, &mut env)?;
        t_output += t0.elapsed().as_secs_f64();
        summary.output_steps += 1;
    }
    let mut stepper = Stepper::new(settings);
    let mut progress = Progress::new(log, state.step, n_steps, 5.0);
    let mut last_checkpoint = Instant::now();
    let ground = |t: f64| it.ground.acceleration(t);
    let t_loop = Instant::now();
    let factorizations0 = sys.factorizations;
    log.info(format!("time history: {n_steps} step(s) of {dt} s from step {} (t = {} s)", state.step, state.t));
    while state.step < n_steps {
        crate::fault::inject(&format!("time_step_{}", state.step + 1), ctx.rank)?;
        let target = ((state.step + 1) as f64 * dt).min(cfg.duration);
        let report = match stepper.advance(sys, &ground, &mut state, target, dt) {
            Ok(r) => r,
            Err(f) => {
                let (rmax, tag, dof) = diagnosis::largest_residual(ctx, &f.r, &sys.disc.dofs, it.mesh);
                let (count, worst) =
                    diagnosis::changed_elements(ctx, &mut sys.disc.elements, &sys.disc.local_cells, it.mesh, it.model);
                let ck = save_checkpoint(ctx, sys, &state, &env, dir)?;
                let listed: Vec<String> = worst.iter().map(|(t, d)| format!("{t} (Δstate {d:.3e})")).collect();
                let msg = format!(
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
                    writer.xdmf_path().display()
                );
                // Every rank has the same failure: agree on it so it is printed once.
                return Err(agreed(ctx, Error::Analysis(msg)));
            }
        };
        summary.iterations += report.iterations;
        if report.substeps > 1 {
            summary.substepped_steps += 1;
        }
        summary.max_balance_error = summary.max_balance_error.max(state.energy.relative_error());
        env.update_nodes(&state.u);
        record_rows(&state, &mut energy_csv, &mut monitor_csv);
        progress.step(log, state.step, state.t, report.iterations, report.substeps, report.residual);
        if state.step % cfg.output_every == 0 || state.step == n_steps {
            let t0 = Instant::now();
            write_step(ctx, &mut writer, sys, it, &state, &mut env)?;
            t_output += t0.elapsed().as_secs_f64();
            summary.output_steps += 1;
        }
        let c = &cfg.checkpoint;
        let mut due = c.every_steps > 0 && state.step % c.every_steps == 0;
        if c.every_minutes > 0.0 {
            let mut by_time = last_checkpoint.elapsed().as_secs_f64() >= 60.0 * c.every_minutes;
            ctx.comm.process_at_rank(0).broadcast_into(&mut by_time);
            due |= by_time;
        }
        if due || state.step == n_steps {
            let t0 = Instant::now();
            save_checkpoint(ctx, sys, &state, &env, dir)?;
            t_checkpoint += t0.elapsed().as_secs_f64();
            last_checkpoint = Instant::now();
            summary.checkpoints += 1;
        }
    }
    let t_stepping = t_loop.elapsed().as_secs_f64() - t_output - t_checkpoint;
    summary.factorizations = sys.factorizations - factorizations0;
    summary.time = state.t;
    let steps_done = (state.step - summary.first_step).max(1);
    summary.seconds[2] = t_stepping;
    summary.seconds[3] = t_output;
    summary.seconds[4] = t_checkpoint;
    summary.seconds_per_step = t_stepping / steps_done as f64;
    let e = state.energy;
    summary.energy = [e.input, e.kinetic, e.strain - e.strain0, e.damping, e.dissipated(), e.unilateral()];
    // Envelopes over ranks.
    let mut peak = [0.0; 4];
    for (k, p) in peak.iter_mut().enumerate() {
        *p = global_max_with_tag(&ctx.comm, env.node_max(k), 0).0;
    }
    summary.peak_displacement = [peak[0], peak[1], peak[2]];
    summary.peak_drift_ratio = peak[3];
    summary.max_damage =
        [global_max_with_tag(&ctx.comm, env.cell_max(0), 0).0, global_max_with_tag(&ctx.comm, env.cell_max(1), 0).0];
    let written: Result<(), Error> = (|| {
        let mut w = ResultsWriter::create(&ctx.comm, dir, "envelopes", &piece.view())?;
        w.begin_step(state.t)?;
        let n = sys.disc.dofs.owned.len();
        let node3: Vec<f64> = (0..n).flat_map(|i| env.node[4 * i..4 * i + 3].to_vec()).collect();
        w.write_node_field("peak_displacement", 3, &node3)?;
        w.write_node_field("peak_drift_ratio", 1, &env.node_column(3))?;
        w.write_cell_field("max_d_t", 1, &env.cell_column(0))?;
        w.write_cell_field("max_d_c", 1, &env.cell_column(1))?;
        w.end_step()?;
        w.close()?;
        Ok(())
    })();
    agree(&ctx.comm, written, Error::exit_code)?;
    agree(&ctx.comm, writer.close().map_err(Error::from), Error::exit_code)?;
    if ctx.rank == 0 && !monitors.is_empty() {
        match monitor::draw(&monitor_csv.path, &monitors, dir) {
            Ok(files) => log.info(format!("monitors: {} and {} picture(s)", monitor_csv.path.display(), files.len())),
            Err(e) => log.warn(format!("monitor pictures not drawn: {e}")),
        }
    }
    log.info(format!(
        "time history done: t = {:.4} s, {} iteration(s), {} factorization(s), {:.4} s per step; peak |u| = ({:.4e}, {:.4e}, {:.4e}) m, peak drift ratio {:.3e}, max damage d_t {:.4}, d_c {:.4}; energy: input {:.4e} J, kinetic {:.4e}, strain {:.4e}, damping {:.4e}, damage {:.4e}, unilateral {:.4e}, balance error {:.2e} (max {:.2e})",
        state.t,
        summary.iterations,
        summary.factorizations,
        summary.seconds_per_step,
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
    log.info(format!(
        "results: {} (every {} step(s)), {}, {}, {}",
        summary.results,
        cfg.output_every,
        dir.join("envelopes.xdmf").display(),
        dir.join("energy.csv").display(),
        dir.join("monitors.csv").display()
    ));
    Ok(summary)
}

/// Collective. Checkpoints the committed state.
fn save_checkpoint(
    ctx: &Context,
    sys: &PetscSystem,
    state: &State,
    env: &Envelopes,
    dir: &std::path::Path,
) -> Result<std::path::PathBuf, Error> {
    let states = checkpoint::element_states(&sys.disc.elements);
    let states = agree(&ctx.comm, states, Error::exit_code)?;
    let c = Checkpoint {
        step: state.step,
        t: state.t,
        energy: state.energy.to_array(),
        vectors: [state.u.clone(), state.v.clone(), state.a.clone(), state.f_int.clone(), state.cv.clone()],
        states,
        node_envelope: env.node.clone(),
        cell_envelope: env.cell.clone(),
    };
    checkpoint::write(ctx, dir, &c)
}

/// `d_t_max` above which the gravity failure counts a cell as cracked through.
const CRACKED: f64 = 0.5;

/// Collective. The error of a gravity phase that stopped short of the full load, printed once:
/// where the out-of-balance force of the last attempt is largest, the groups with cells cracked
/// through (`d_t_max` > 0.5) at the last equilibrium, and `gravity-failure.xdmf`, that
/// equilibrium's displacements and cell outputs for ParaView.
fn gravity_failure(
    ctx: &Context,
    sys: &mut PetscSystem,
    job: &Job,
    mesh: &Mesh,
    model: &StructuralModel,
    f: GravityFailure,
) -> Error {
    let (rmax, tag, dof) = diagnosis::largest_residual(ctx, &f.r, &sys.disc.dofs, mesh);
    let mut msg = format!("{}. Largest out-of-balance force {rmax:.4e} at node {tag}, DOF {dof}", f.message);
    let state = (|| -> Result<(std::path::PathBuf, String), Error> {
        let u_local = sys.local_form(&f.u)?;
        let loads = AppliedLoads { gravity: model.gravity.map(|g| g.map(|x| f.lambda * x)).unwrap_or([0.0; 3]) };
        let (names, values) = crate::analysis::assembly::cell_outputs(ctx, &sys.disc, mesh, model, &u_local, &loads)?;
        let cracked = cracked_groups(ctx, sys, job, model, &names, &values);
        let piece = MeshPiece::new(ctx, job, mesh, model, &sys.disc);
        let mut w = agree(
            &ctx.comm,
            ResultsWriter::create(&ctx.comm, &job.output_dir, "gravity-failure", &piece.view()).map_err(Error::from),
            Error::exit_code,
        )?;
        let n = sys.disc.dofs.owned.len();
        let written: Result<(), Error> = (|| {
            w.begin_step(f.lambda)?;
            w.write_node_field("displacement", 3, &node_triplets(&f.u, n, 0))?;
            w.write_node_field("rotation", 3, &node_triplets(&f.u, n, 3))?;
            for (name, v) in names.iter().zip(&values) {
                w.write_cell_field(name, 1, v)?;
            }
            w.end_step()?;
            Ok(())
        })();
        agree(&ctx.comm, written, Error::exit_code)?;
        let path = w.xdmf_path().to_path_buf();
        agree(&ctx.comm, w.close().map_err(Error::from), Error::exit_code)?;
        Ok((path, cracked))
    })();
    match state {
        Ok((path, cracked)) => msg.push_str(&format!(
            ". At the last equilibrium, λ = {:.6} of the static load, {cracked}; its displacements and cell outputs (time value = λ) are in {}",
            f.lambda,
            path.display()
        )),
        Err(e) => msg.push_str(&format!(". The last equilibrium (λ = {:.6}) could not be written: {e}", f.lambda)),
    }
    agreed(ctx, Error::Analysis(msg))
}

/// Collective. "cells with d_t_max > 0.5: group n of m, …" over all ranks, groups in job order.
fn cracked_groups(
    ctx: &Context,
    sys: &PetscSystem,
    job: &Job,
    model: &StructuralModel,
    names: &[String],
    values: &[Vec<f64>],
) -> String {
    use mpi::collective::SystemOperation;
    use mpi::traits::CommunicatorCollectives;
    let parts = &job.spec.parts;
    let mut counts = vec![0u64; 2 * parts.len()];
    let d_t = names.iter().position(|n| n == "d_t_max").map(|k| &values[k]);
    for (i, &c) in sys.disc.local_cells.iter().enumerate() {
        let part = model.cells[c].part;
        if let Some(d) = d_t.and_then(|d| d.get(i)).filter(|d| !d.is_nan()) {
            counts[2 * part + 1] += 1;
            if *d > CRACKED {
                counts[2 * part] += 1;
            }
        }
    }
    let mut all = vec![0u64; counts.len()];
    ctx.comm.all_reduce_into(&counts[..], &mut all[..], SystemOperation::sum());
    let listed: Vec<String> = parts
        .iter()
        .enumerate()
        .filter(|(p, _)| all[2 * p] > 0)
        .map(|(p, part)| format!("{} {} of {}", part.group, all[2 * p], all[2 * p + 1]))
        .collect();
    if listed.is_empty() {
        format!("no cell has d_t_max > {CRACKED}")
    } else {
        format!("cells with d_t_max > {CRACKED}: {}", listed.join(", "))
    }
}

/// Collective. An error every rank has, as an agreed one (printed once, no abort).
fn agreed(ctx: &Context, e: Error) -> Error {
    match agree(&ctx.comm, Err::<(), Error>(e), Error::exit_code) {
        Err(a) => Error::from(a),
        Ok(()) => Error::Analysis("internal error: an error was lost in agreement".into()),
    }
}

/// Collective. One output step: relative and absolute motion, cell outputs.
fn write_step(
    ctx: &Context,
    w: &mut ResultsWriter,
    sys: &mut PetscSystem,
    it: &Integration,
    state: &State,
    env: &mut Envelopes,
) -> Result<(), Error> {
    let n = sys.disc.dofs.owned.len();
    let ag = it.ground.acceleration(state.t);
    let (vg, ug) = it.ground.velocity_displacement(state.t);
    let u_local = sys.local_form(&state.u)?;
    let loads = AppliedLoads { gravity: it.model.gravity.unwrap_or([0.0; 3]) };
    let (names, values) = crate::analysis::assembly::cell_outputs(ctx, &sys.disc, it.mesh, it.model, &u_local, &loads)?;
    env.update_cells(&names, &values);
    let written: Result<(), Error> = (|| {
        w.begin_step(state.t)?;
        w.write_node_field("displacement", 3, &node_triplets(&state.u, n, 0))?;
        w.write_node_field("rotation", 3, &node_triplets(&state.u, n, 3))?;
        w.write_node_field("velocity", 3, &node_triplets(&state.v, n, 0))?;
        w.write_node_field("acceleration", 3, &node_triplets(&state.a, n, 0))?;
        w.write_node_field("absolute_displacement", 3, &node_triplets(&absolute(&state.u, ug), n, 0))?;
        w.write_node_field("absolute_velocity", 3, &node_triplets(&absolute(&state.v, vg), n, 0))?;
        w.write_node_field("absolute_acceleration", 3, &node_triplets(&absolute(&state.a, ag), n, 0))?;
        for (name, v) in names.iter().zip(&values) {
            w.write_cell_field(name, 1, v)?;
        }
        w.end_step()?;
        Ok(())
    })();
    agree(&ctx.comm, written, Error::exit_code)?;
    Ok(())
}
