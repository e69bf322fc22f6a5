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
mod diagnosis;
mod output;

use super::increment::{IncrementControl, IncrementStop};
use super::line_search::LineSearchSettings;
use super::newton::{global_sum, Increment, NewtonOutcome, NewtonSettings, NonlinearSystem};
use super::{Discretization, FeProblem};
use crate::config::{IterationMatrix, Job, LineSearchKind, StaticNonlinearConfig};
use crate::error::{AnalysisError, Error};
use crate::mesh::Mesh;
use crate::model::StructuralModel;
use crate::parallel::Context;
use diagnosis::diagnose;
use output::{draw_curve, write_step, Outputs};

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

/// Collective. Runs the analysis of `p`: the outputs opened, the stages (loads, then the
/// control), each a sequence of increments, then the curve's picture.
pub fn run(p: &mut FeProblem, cfg: &StaticNonlinearConfig) -> Result<StaticNonlinearSummary, Error> {
    let (ctx, job, mesh, model) = (p.ctx, p.job, p.mesh, p.model);
    let disc = &mut p.disc;
    let mut sys = NonlinearSystem::new(ctx, mesh, model, disc, job.spec.solver.matrix)?;
    if let Some(radius) = cfg.nonlocal_radius {
        sys.enable_nonlocal(ctx, disc, mesh, model, radius)?;
    }
    let (settings, secant_settings) = newton_settings(cfg);
    let outputs = Outputs::open(ctx, job, cfg, mesh, model, disc)?;
    let (stages, pattern_resultant) = stages(ctx, cfg, model, &sys, disc);
    let mut run = Increments {
        ctx,
        job,
        cfg,
        mesh,
        model,
        settings,
        secant_settings,
        pattern_resultant,
        disc,
        sys,
        outputs,
        reports: Vec::new(),
        cuts: 0,
        line_search_evaluations: 0,
    };
    for stage in &stages {
        run.stage(stage)?;
    }
    run.draw_curve()?;
    Ok(StaticNonlinearSummary {
        steps: run.reports,
        cuts: run.cuts,
        line_search_evaluations: run.line_search_evaluations,
    })
}

/// The Newton settings of the increments, and those of the secant retries (secant iterations
/// converge linearly: more of them). With `stiffness = "secant"` both are the secant ones.
fn newton_settings(cfg: &StaticNonlinearConfig) -> (NewtonSettings, NewtonSettings) {
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
    let secant_settings = NewtonSettings { secant: true, max_iterations: 4 * cfg.max_iterations, ..settings };
    let settings = if settings.secant { secant_settings } else { settings };
    (settings, secant_settings)
}

/// Collective. The stages to run: the loads (when the job has any, or no control), then the
/// control (when `[analysis.control]` is given); and the resultant of the control's load
/// pattern along its DOF (0 without one).
fn stages(
    ctx: &Context,
    cfg: &StaticNonlinearConfig,
    model: &StructuralModel,
    sys: &NonlinearSystem,
    disc: &Discretization,
) -> (Vec<Stage>, f64) {
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
        let (target, start) = (ctl.target, control_start(ctx, sys, disc, ctl));
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
        ctx.log.info(format!(
            "displacement control: DOF {} of {} node(s) from {start:.4e} by {target:.4e} in {} steps{}",
            ["ux", "uy", "uz", "rx", "ry", "rz"][ctl.dof],
            ctl.nodes.len(),
            ctl.steps,
            if with_pattern { ", load pattern scaled to follow" } else { ", imposed" }
        ));
    }
    (stages, pattern_resultant)
}

/// The increments of the stages on one system: its state, the outputs, and what was done.
struct Increments<'a> {
    ctx: &'a Context,
    job: &'a Job,
    cfg: &'a StaticNonlinearConfig,
    mesh: &'a Mesh,
    model: &'a StructuralModel,
    settings: NewtonSettings,
    secant_settings: NewtonSettings,
    pattern_resultant: f64,
    disc: &'a mut Discretization,
    sys: NonlinearSystem,
    outputs: Outputs,
    reports: Vec<StepReport>,
    cuts: usize,
    line_search_evaluations: usize,
}

impl Increments<'_> {
    /// Collective. One stage, from 0 to 1 in increments sized by [`IncrementControl`]: a
    /// converged increment is committed and written, a failed one reverted and halved; the run
    /// stops with a diagnosis when the control gives up.
    fn stage(&mut self, stage: &Stage) -> Result<(), Error> {
        let mut control = IncrementControl::new(stage.steps, self.cfg.max_cuts);
        let mut t = 0.0f64;
        while t < 1.0 - 1e-12 {
            let target = (t + control.size()).min(1.0);
            let inc = (stage.at)(target);
            let out = self.attempt(stage, &inc, t, target)?;
            if out.converged {
                t = target;
                self.accept(stage, &inc, t, &out)?;
                control.converged();
                if t < 1.0 - 1e-12 && control.exhausted() {
                    self.draw_curve()?;
                    return Err(AnalysisError::StageStopped {
                        stage: stage.name.to_string(),
                        at: t,
                        reason: IncrementStop::Budget.describe(&control),
                        results: self.results_path(),
                    }
                    .into());
                }
            } else {
                let (ctx, mesh, model) = (self.ctx, self.mesh, self.model);
                let diagnosis = diagnose(ctx, self.disc, mesh, model, &self.sys, &inc)?;
                self.sys.revert(self.disc);
                // Stop at the floor, after max_cuts halvings in a row, or when the attempts are
                // spent (successes in between do not make it shrink forever: `increment.rs`).
                if let Err(stop) = control.failed() {
                    self.draw_curve()?;
                    let reason = format!(
                        "the increment towards {target:.6} failed ({}, relative residual {:.3e}) and {}; {diagnosis}",
                        out.reason,
                        out.residual,
                        stop.describe(&control),
                    );
                    return Err(AnalysisError::StageStopped {
                        stage: stage.name.to_string(),
                        at: t,
                        reason,
                        results: self.results_path(),
                    }
                    .into());
                }
                self.cuts += 1;
                let dt = control.size();
                ctx.log.info(format!(
                    "{} towards {target:.4} failed ({}); halving the increment to {dt:.4e}; {diagnosis}",
                    stage.name, out.reason
                ));
            }
        }
        Ok(())
    }

    /// Collective. Solves the increment `inc` from `t` to `target` of the stage: with the
    /// iteration matrix of the settings, then, if tangent iterations failed, again from the
    /// committed state with secant iterations (softening, a change of branch).
    fn attempt(&mut self, stage: &Stage, inc: &Increment, t: f64, target: f64) -> Result<NewtonOutcome, Error> {
        let (ctx, mesh, model) = (self.ctx, self.mesh, self.model);
        if self.cfg.damage_relaxation_time.is_some() {
            for e in self.disc.elements.iter_mut() {
                e.set_damage_relaxation(target - t, self.cfg.damage_relaxation_time);
            }
        }
        let mut out = self.sys.solve_increment(ctx, self.disc, mesh, model, inc, &self.settings)?;
        self.line_search_evaluations += out.line_search_evaluations;
        if !out.converged && !self.settings.secant {
            self.sys.revert(self.disc);
            ctx.log.info(format!(
                "{} towards {target:.4}: tangent iterations failed ({}); retrying with the secant stiffness",
                stage.name, out.reason
            ));
            let tangent_iterations = out.iterations;
            out = self.sys.solve_increment(ctx, self.disc, mesh, model, inc, &self.secant_settings)?;
            out.iterations += tangent_iterations;
            self.line_search_evaluations += out.line_search_evaluations;
        }
        Ok(out)
    }

    /// Collective. Commits a converged increment that reached `t` of the stage, writes it and
    /// keeps its report.
    fn accept(&mut self, stage: &Stage, inc: &Increment, t: f64, out: &NewtonOutcome) -> Result<(), Error> {
        let (ctx, mesh, model) = (self.ctx, self.mesh, self.model);
        self.sys.commit(ctx, self.disc, mesh, model)?;
        let report = write_step(
            ctx,
            self.disc,
            mesh,
            model,
            &mut self.sys,
            &mut self.outputs.writer,
            &self.outputs.curve_path,
            stage,
            inc,
            (stage.time)(t),
            self.pattern_resultant,
            out.iterations,
            out.residual,
        )?;
        ctx.log.info(format!(
            "{} {:.4}: {} iteration(s), residual {:.2e}, control {:.4e} / force {:.4e}, dissipated {:.4e} J",
            stage.name,
            t,
            out.iterations,
            out.residual,
            report.control_displacement,
            report.control_force,
            report.dissipated_energy
        ));
        self.reports.push(report);
        Ok(())
    }

    /// Collective. `curve.png` of the reports so far.
    fn draw_curve(&self) -> Result<(), Error> {
        draw_curve(self.ctx, self.job, self.model, &self.reports, self.outputs.overlay.as_ref())
    }

    /// The results file, for messages.
    fn results_path(&self) -> String {
        self.job.output_dir.join("results.xdmf").display().to_string()
    }
}

/// Collective. The committed value of the control DOF (the first control node's).
pub(super) fn control_start(
    ctx: &Context,
    sys: &NonlinearSystem,
    disc: &Discretization,
    ctl: &crate::model::ControlSpec,
) -> f64 {
    let n = ctl.nodes[0];
    let v = if disc.dofs.owner[n] == disc.dofs.rank {
        sys.u_committed[disc.dofs.dof(n, ctl.dof) as usize - sys.first]
    } else {
        0.0
    };
    global_sum(ctx, v)
}
