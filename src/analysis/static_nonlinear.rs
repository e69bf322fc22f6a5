//! Nonlinear static analysis in two stages, each a sequence of increments solved by Newton's
//! method ([`newton`](super::newton): consistent tangent, line search, force and energy norms):
//!
//! ```text
//!   stage "loads":   the job's nodal loads and gravity scaled by λ: 0 → 1 in `steps` increments
//!                    (skipped when the job has none)
//!   stage "control": (with [analysis.control]) loads held at λ = 1; the control DOF driven from
//!                    its value to value + target in control.steps increments: imposed on the
//!                    control nodes, or reached by scaling a load pattern (pushover)
//! ```
//!
//! # Substepping and the stop
//! An increment whose tangent iterations fail is retried with secant iterations (the damaged
//! elastic stiffness: positive definite, slower but robust through softening). An increment that
//! still does not converge is abandoned (elements revert to their committed state) and retried
//! with half the size, up to `max_cuts` halvings in a row and never below the nominal size /
//! 2^max_cuts; after a success the size grows back by 1.5× up to the nominal one
//! ([`IncrementControl`], which also bounds the attempts). When the last
//! halving fails too, the run stops with a diagnosis: where it stopped, the largest out-of-balance force (node tag and DOF), and the
//! elements whose damage grew in the failed increment (count, and the five largest increases with
//! their element tags). Every converged increment is written to `results.xdmf` before, so a run
//! that stops keeps what it computed.
//!
//! # Viscous damage (optional)
//! With `damage_relaxation_time = τ` the damage histories follow Duvaut–Lions' law in the
//! pseudo-time of the stages (each lasts 1): before every increment the elements get Δt = the
//! increment's fraction of its stage (`Element::set_damage_relaxation`, `material::state` docs).
//!
//! # Nonlocal damage (optional)
//! With `nonlocal_radius = R` the damage of shell layers is driven by strains averaged over the
//! points of the same layer within R (`analysis::nonlocal`, `material::nonlocal`), and the
//! softening is regularized by R instead of each element's size. Off by default.
//!
//! # Outputs
//! `results.xdmf` (one step per converged increment; time = λ in the loads stage, 1 + the
//! fraction of the control target in the control stage), `curve.csv` (one line per converged
//! increment: stage, λ, control displacement and force, dissipated energy, iterations),
//! `curve.png` under displacement control (force against displacement, with the optional overlay
//! curve of `[analysis.control.overlay]`), and the summary returned to `summary.json`.
use std::io::Write;

use super::assembly;
use super::increment::{IncrementControl, IncrementStop};
use super::line_search::LineSearchSettings;
use super::newton::{global_sum, Increment, NewtonSettings, NonlinearSystem};
use super::output::{global_max_with_tag, node_triplets, MeshPiece};
use super::Discretization;
use crate::config::{IterationMatrix, Job, LineSearchKind, StaticNonlinearConfig};
use crate::element::AppliedLoads;
use crate::error::Error;
use crate::io::ResultsWriter;
use crate::mesh::Mesh;
use crate::model::StructuralModel;
use crate::parallel::{agree, Context};

/// One converged increment.
#[derive(Debug, Clone, serde::Serialize)]
pub struct StepReport {
    /// `"loads"` or `"control"`.
    pub stage: &'static str,
    /// Load factor of the job's loads.
    pub lambda: f64,
    /// Value of the control DOF (0 without control).
    pub control_displacement: f64,
    /// Force at the control (reaction of the imposed DOFs, or μ × pattern resultant).
    pub control_force: f64,
    /// Energy dissipated by the damage so far (J).
    pub dissipated_energy: f64,
    /// Newton iterations.
    pub iterations: usize,
    /// Final relative residual.
    pub residual: f64,
    /// Largest translation [m].
    pub max_displacement: f64,
}

/// What a nonlinear static run reports.
#[derive(Debug, Clone, serde::Serialize)]
pub struct StaticNonlinearSummary {
    /// Converged increments.
    pub steps: Vec<StepReport>,
    /// Increment halvings made.
    pub cuts: usize,
    /// Extra residual evaluations made by line searches.
    pub line_search_evaluations: usize,
}

/// One stage: what an increment at fraction `t` ∈ (0, 1] of the stage asks for.
struct Stage {
    name: &'static str,
    steps: usize,
    at: Box<dyn Fn(f64) -> Increment>,
    /// Time written to the results for fraction t.
    time: Box<dyn Fn(f64) -> f64>,
}

/// Collective. Runs the analysis.
pub fn run(
    ctx: &Context,
    job: &Job,
    cfg: &StaticNonlinearConfig,
    mesh: &Mesh,
    model: &StructuralModel,
) -> Result<StaticNonlinearSummary, Error> {
    let log = &ctx.log;
    let mut disc = Discretization::setup(ctx, job, mesh, model)?;
    let mut sys = NonlinearSystem::new(ctx, mesh, model, &disc, job.spec.solver.matrix)?;
    if let Some(radius) = cfg.nonlocal_radius {
        sys.enable_nonlocal(ctx, &mut disc, mesh, model, radius)?;
    }
    let settings = NewtonSettings {
        max_iterations: cfg.max_iterations,
        force_tolerance: cfg.force_tolerance,
        energy_tolerance: cfg.energy_tolerance,
        line_search: match cfg.line_search {
            LineSearchKind::None => None,
            LineSearchKind::Secant => Some(LineSearchSettings::default()),
        },
        secant: cfg.stiffness == IterationMatrix::Secant,
    };
    // Secant iterations converge linearly: more of them.
    let secant_settings = NewtonSettings { secant: true, max_iterations: 4 * cfg.max_iterations, ..settings };
    let settings = if settings.secant { secant_settings } else { settings };
    let piece = MeshPiece::new(ctx, job, mesh, model, &disc);
    let mut writer = agree(
        &ctx.comm,
        ResultsWriter::create(&ctx.comm, &job.output_dir, "results", &piece.view()).map_err(Error::from),
        Error::exit_code,
    )?;
    let curve_path = job.output_dir.join("curve.csv");
    if ctx.rank == 0 {
        let header = "stage,lambda,control_displacement,control_force,dissipated_energy,iterations,residual\n";
        std::fs::write(&curve_path, header).map_err(|e| Error::Analysis(format!("{}: {e}", curve_path.display())))?;
    }

    let overlay = match cfg.control.as_ref().and_then(|c| c.overlay.as_ref()) {
        Some(o) => Some((o.label.clone(), agree(&ctx.comm, super::curve_plot::read_overlay(o), Error::exit_code)?)),
        None => None,
    };
    let has_loads = global_sum(ctx, sys.f_loads.iter().map(|x| x * x).sum()) > 0.0;
    let mut stages: Vec<Stage> = Vec::new();
    if has_loads || model.control.is_none() {
        stages.push(Stage {
            name: "loads",
            steps: cfg.steps,
            at: Box::new(|t| Increment { lambda: t, imposed: None, control_target: None }),
            time: Box::new(|t| t),
        });
    }
    let mut pattern_resultant = 0.0;
    if let Some(ctl) = &model.control {
        let (target, start) = (ctl.target, control_start(ctx, &sys, &disc, ctl));
        let lambda = if has_loads { 1.0 } else { 0.0 };
        let with_pattern = !ctl.pattern.is_empty();
        pattern_resultant = ctl.pattern.iter().map(|(_, f)| f[ctl.dof]).sum();
        stages.push(Stage {
            name: "control",
            steps: ctl.steps,
            at: Box::new(move |t| Increment {
                lambda,
                imposed: (!with_pattern).then_some(start + t * target),
                control_target: with_pattern.then_some(start + t * target),
            }),
            time: Box::new(move |t| lambda + t),
        });
        log.info(format!(
            "displacement control: DOF {} of {} node(s) from {start:.4e} by {target:.4e} in {} steps{}",
            ["ux", "uy", "uz", "rx", "ry", "rz"][ctl.dof],
            ctl.nodes.len(),
            ctl.steps,
            if with_pattern { ", load pattern scaled to follow" } else { ", imposed" }
        ));
    }

    let mut reports = Vec::new();
    let (mut cuts_total, mut ls_total) = (0, 0);
    for stage in &stages {
        let mut control = IncrementControl::new(stage.steps, cfg.max_cuts);
        let mut t = 0.0f64;
        while t < 1.0 - 1e-12 {
            let target = (t + control.size()).min(1.0);
            let inc = (stage.at)(target);
            if cfg.damage_relaxation_time.is_some() {
                for e in disc.elements.iter_mut() {
                    e.set_damage_relaxation(target - t, cfg.damage_relaxation_time);
                }
            }
            let mut out = sys.solve_increment(ctx, &mut disc, mesh, model, &inc, &settings)?;
            ls_total += out.line_search_evaluations;
            if !out.converged && !settings.secant {
                // The tangent failed (softening, a change of branch): secant iterations next.
                sys.revert(&mut disc);
                log.info(format!(
                    "{} towards {target:.4}: tangent iterations failed ({}); retrying with the secant stiffness",
                    stage.name, out.reason
                ));
                let tangent_iterations = out.iterations;
                out = sys.solve_increment(ctx, &mut disc, mesh, model, &inc, &secant_settings)?;
                out.iterations += tangent_iterations;
                ls_total += out.line_search_evaluations;
            }
            if out.converged {
                sys.commit(ctx, &mut disc, mesh, model)?;
                t = target;
                let report = write_step(
                    ctx,
                    &disc,
                    mesh,
                    model,
                    &mut sys,
                    &mut writer,
                    &curve_path,
                    stage,
                    &inc,
                    (stage.time)(t),
                    pattern_resultant,
                    out.iterations,
                    out.residual,
                )?;
                log.info(format!(
                    "{} {:.4}: {} iteration(s), residual {:.2e}, control {:.4e} / force {:.4e}, dissipated {:.4e} J",
                    stage.name,
                    t,
                    out.iterations,
                    out.residual,
                    report.control_displacement,
                    report.control_force,
                    report.dissipated_energy
                ));
                reports.push(report);
                control.converged();
                if t < 1.0 - 1e-12 && control.exhausted() {
                    draw_curve(ctx, job, model, &reports, overlay.as_ref())?;
                    return Err(Error::Analysis(format!(
                        "static_nonlinear: stage '{}' stopped at {t:.6} of the stage: {}; results up to the last converged increment are in {}",
                        stage.name,
                        IncrementStop::Budget.describe(&control),
                        job.output_dir.join("results.xdmf").display()
                    )));
                }
            } else {
                let diagnosis = diagnose(ctx, &disc, mesh, model, &sys, &inc)?;
                sys.revert(&mut disc);
                // Stop at the floor, after max_cuts halvings in a row, or when the attempts are
                // spent (successes in between do not make it shrink forever: `increment.rs`).
                if let Err(stop) = control.failed() {
                    draw_curve(ctx, job, model, &reports, overlay.as_ref())?;
                    return Err(Error::Analysis(format!(
                        "static_nonlinear: stage '{}' stopped at {:.6} of the stage: the increment towards {:.6} failed ({}, relative residual {:.3e}) \
                         and {}; {diagnosis}; results up to the last converged increment are in {}",
                        stage.name,
                        t,
                        target,
                        out.reason,
                        out.residual,
                        stop.describe(&control),
                        job.output_dir.join("results.xdmf").display()
                    )));
                }
                cuts_total += 1;
                let dt = control.size();
                log.info(format!(
                    "{} towards {target:.4} failed ({}); halving the increment to {dt:.4e}; {diagnosis}",
                    stage.name, out.reason
                ));
            }
        }
    }
    draw_curve(ctx, job, model, &reports, overlay.as_ref())?;
    Ok(StaticNonlinearSummary { steps: reports, cuts: cuts_total, line_search_evaluations: ls_total })
}

/// Collective. `curve.png` of the control stage (rank 0 draws; all agree on the outcome).
fn draw_curve(
    ctx: &Context,
    job: &Job,
    model: &StructuralModel,
    reports: &[StepReport],
    overlay: Option<&(String, Vec<(f64, f64)>)>,
) -> Result<(), Error> {
    let Some(ctl) = &model.control else { return Ok(()) };
    let drawn = if ctx.rank == 0 {
        let mut points = vec![(0.0, 0.0)];
        points
            .extend(reports.iter().filter(|r| r.stage == "control").map(|r| (r.control_displacement, r.control_force)));
        let dof = ["ux", "uy", "uz", "rx", "ry", "rz"][ctl.dof];
        super::curve_plot::plot_curve(
            &job.output_dir.join("curve.png"),
            dof,
            &points,
            overlay.map(|(l, p)| (l.as_str(), p.as_slice())),
        )
    } else {
        Ok(())
    };
    agree(&ctx.comm, drawn, Error::exit_code)?;
    Ok(())
}

/// Collective. The committed value of the control DOF (the first control node's).
fn control_start(ctx: &Context, sys: &NonlinearSystem, disc: &Discretization, ctl: &crate::model::ControlSpec) -> f64 {
    let n = ctl.nodes[0];
    let v = if disc.dofs.owner[n] == disc.dofs.rank {
        sys.u_committed[disc.dofs.dof(n, ctl.dof) as usize - sys.first]
    } else {
        0.0
    };
    global_sum(ctx, v)
}

/// Collective. Writes one converged increment (fields, curve line) and returns its report.
#[allow(clippy::too_many_arguments)]
fn write_step(
    ctx: &Context,
    disc: &Discretization,
    mesh: &Mesh,
    model: &StructuralModel,
    sys: &mut NonlinearSystem,
    writer: &mut ResultsWriter,
    curve: &std::path::Path,
    stage: &Stage,
    inc: &Increment,
    time: f64,
    pattern_resultant: f64,
    iterations: usize,
    residual: f64,
) -> Result<StepReport, Error> {
    let u = sys.u_committed.clone();
    let u_local = sys.local_form(&u)?;
    let mut umax = 0.0f64;
    for v in u.chunks_exact(6) {
        umax = umax.max((v[0] * v[0] + v[1] * v[1] + v[2] * v[2]).sqrt());
    }
    let (umax, _) = global_max_with_tag(&ctx.comm, umax, 0);
    let lambda = inc.lambda;
    let loads = AppliedLoads {
        gravity: model.gravity.map(|g| [g[0] * lambda, g[1] * lambda, g[2] * lambda]).unwrap_or([0.0; 3]),
    };
    let (names, values) = assembly::cell_outputs(ctx, disc, mesh, model, &u_local, &loads)?;
    let dissipated = names
        .iter()
        .position(|n| n == "dissipated_energy")
        .map(|k| global_sum(ctx, values[k].iter().filter(|x| x.is_finite()).sum()))
        .unwrap_or(0.0);
    let control_displacement = match &model.control {
        Some(c) => control_start(ctx, sys, disc, c),
        None => 0.0,
    };
    let control_force = sys.control_force(ctx, pattern_resultant);
    let wrote: Result<(), Error> = (|| {
        writer.begin_step(time)?;
        let n = disc.dofs.owned.len();
        writer.write_node_field("displacement", 3, &node_triplets(&u_local, n, 0))?;
        writer.write_node_field("rotation", 3, &node_triplets(&u_local, n, 3))?;
        for (name, v) in names.iter().zip(&values) {
            writer.write_cell_field(name, 1, v)?;
        }
        writer.end_step()?;
        if ctx.rank == 0 {
            let mut f = std::fs::OpenOptions::new()
                .append(true)
                .open(curve)
                .map_err(|e| Error::Analysis(format!("{}: {e}", curve.display())))?;
            writeln!(
                f,
                "{},{:.12e},{:.12e},{:.12e},{:.12e},{},{:.3e}",
                stage.name, lambda, control_displacement, control_force, dissipated, iterations, residual
            )
            .map_err(|e| Error::Analysis(format!("{}: {e}", curve.display())))?;
        }
        Ok(())
    })();
    agree(&ctx.comm, wrote, Error::exit_code)?;
    Ok(StepReport {
        stage: stage.name,
        lambda,
        control_displacement,
        control_force,
        dissipated_energy: dissipated,
        iterations,
        residual,
        max_displacement: umax,
    })
}

/// Collective. Where a failed increment went wrong: the largest out-of-balance force (node tag,
/// DOF) at the last iterate, and the elements whose damage grew from the committed state.
fn diagnose(
    ctx: &Context,
    disc: &Discretization,
    mesh: &Mesh,
    model: &StructuralModel,
    sys: &NonlinearSystem,
    inc: &Increment,
) -> Result<String, Error> {
    let r = sys.current_residual(inc.lambda);
    let (mut worst, mut at) = (0.0f64, 0u64);
    for (i, x) in r.iter().enumerate() {
        if x.abs() > worst || !x.is_finite() {
            worst = if x.is_finite() { x.abs() } else { f64::INFINITY };
            let node = disc.dofs.owned[i / 6];
            at = mesh.node_tags[node] * 8 + (i % 6) as u64;
        }
    }
    let (worst, at) = global_max_with_tag(&ctx.comm, worst, at);
    let dof = ["ux", "uy", "uz", "rx", "ry", "rz"][(at % 8) as usize];
    // Damage at the last iterate vs at the committed displacement (both from the committed state).
    let loads = AppliedLoads::default();
    let (names_now, now) = assembly::cell_outputs(ctx, disc, mesh, model, &local_of(ctx, disc, &sys.u)?, &loads)?;
    let (_, before) = assembly::cell_outputs(ctx, disc, mesh, model, &local_of(ctx, disc, &sys.u_committed)?, &loads)?;
    let mut growth: Vec<(f64, u64)> = Vec::new();
    for key in ["d_t_max", "d_c_max"] {
        if let Some(k) = names_now.iter().position(|n| n == key) {
            for (i, (a, b)) in now[k].iter().zip(&before[k]).enumerate() {
                if a.is_finite() && b.is_finite() && a - b > 1e-12 {
                    let tag = mesh.cells[model.cells[disc.local_cells[i]].cell].tag;
                    growth.push((a - b, tag));
                }
            }
        }
    }
    growth.sort_by(|a, b| b.0.total_cmp(&a.0));
    growth.dedup_by_key(|g| g.1);
    let count = global_sum(ctx, growth.len() as f64) as usize;
    let mut top = Vec::new();
    for _ in 0..5 {
        let (v, tag) =
            global_max_with_tag(&ctx.comm, growth.first().map_or(0.0, |g| g.0), growth.first().map_or(0, |g| g.1));
        if v <= 0.0 {
            break;
        }
        top.push(format!("{tag} (+{v:.3})"));
        if growth.first().is_some_and(|g| g.1 == tag && g.0 == v) {
            growth.remove(0);
        }
    }
    Ok(format!(
        "largest out-of-balance force {worst:.3e} at node {} DOF {dof}; damage grew in {count} element(s){}",
        at / 8,
        if top.is_empty() { String::new() } else { format!(", most in {}", top.join(", ")) }
    ))
}

/// Collective. The local form (owned, then ghosts) of the owned values `u`.
fn local_of(ctx: &Context, disc: &Discretization, u: &[f64]) -> Result<Vec<f64>, Error> {
    let n_owned = disc.dofs.n_owned_dofs();
    let mut v = crate::petsc::Vector::new_ghosted(&ctx.comm, n_owned, &disc.dofs.ghost_dofs())?;
    let first = 6 * disc.dofs.node_offset();
    let idx: Vec<i32> = (0..n_owned).map(|i| (first + i) as i32).collect();
    v.set_values(&idx, u)?;
    v.assemble()?;
    v.ghost_update()?;
    Ok(v.with_local_form(|s| s.to_vec())?)
}
