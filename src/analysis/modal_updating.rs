//! Modal updating: Young's moduli of chosen substructures (physical groups) fitted, within
//! bounds, to target natural frequencies.
//!
//! A factor `s_g` multiplies the elastic moduli of the group's elements — E, and G with it (the
//! Poisson ratio held) — so it multiplies their whole stiffness. The stiffness is linear in the
//! factors:
//! `K(s) = K_rest + Σ_g s_g K_g`, each `K_g` assembled once from its group's elements. With
//! mass-normalized modes, the eigenvalue sensitivities are exact (Fox & Kapoor 1968):
//! `∂λ_k/∂s_g = φ_kᵀ K_g φ_k`, and `f = √λ / 2π` gives `∂f_k/∂s_g = ∂λ_k/∂s_g / (8π² f_k)`.
//! The residuals are relative frequency errors `r_k = (f_k(s) − f̄_k)/f̄_k`, paired by mode number.
//! Levenberg–Marquardt steps `(JᵀJ + μ diag JᵀJ) δ = −Jᵀ r`, projected onto the bounds
//! `s_min ≤ s ≤ s_max`, are accepted when the cost ½‖r‖² decreases (μ ÷ 3), else retried with
//! μ × 4. Each evaluation is one eigensolve.
//!
//! Pairing: by mode number, or — when target shapes are given — each target takes the computed
//! mode with the largest modal assurance criterion over the DOFs the target file gives
//! (translations, and rotations when present — a beam-axis torsion mode has no translation): `MAC = (ψᵀφ)² / ((ψᵀψ)(φᵀφ))` (Allemang & Brown 1982). Mode order changes as the
//! moduli move (a torsion mode that does not depend on E overtakes a bending mode that does), so
//! pairing by number alone can lock onto the wrong mode.
use super::assembly;
use super::modal::lowest_modes;
use super::mode_pairing::{computed_target_shapes, load_target_shapes, pair_targets, TargetShape};
use super::{Discretization, FeProblem};
use crate::config::{Job, MaterialConfig, ModalUpdatingConfig};
use crate::error::{AnalysisError, Error};
use crate::mesh::Mesh;
use crate::model::StructuralModel;
use crate::parallel::Context;
use crate::petsc::{Matrix, Vector};
use nalgebra::{DMatrix, DVector};
use std::f64::consts::PI;

/// One updated group.
#[derive(Debug, Clone, serde::Serialize)]
pub struct UpdatedParameter {
    /// Physical group.
    pub group: String,
    /// Fitted factor on E.
    pub factor: f64,
    /// Young's modulus of its material before [Pa].
    pub modulus_before: f64,
    /// After [Pa].
    pub modulus_after: f64,
    /// Whether the factor ended on a bound.
    pub at_bound: bool,
}

/// One target, before and after.
#[derive(Debug, Clone, serde::Serialize)]
pub struct TargetReport {
    /// Mode number.
    pub mode: usize,
    /// Target [Hz].
    pub target: f64,
    /// Computed before updating [Hz].
    pub before: f64,
    /// Computed after [Hz].
    pub after: f64,
    /// The computed mode paired with it after updating (1-based).
    pub paired_mode: usize,
    /// Its MAC with the target shape (1 when paired by mode number).
    pub mac: f64,
}

/// What a modal updating run reports.
#[derive(Debug, Clone, serde::Serialize)]
pub struct UpdatingSummary {
    /// Iterations (accepted steps).
    pub iterations: usize,
    /// Eigensolves.
    pub evaluations: usize,
    /// RMS relative frequency error before.
    pub rms_error_before: f64,
    /// RMS relative frequency error after.
    pub rms_error_after: f64,
    /// Whether the tolerance was reached.
    pub converged: bool,
    /// The parameters.
    pub parameters: Vec<UpdatedParameter>,
    /// The targets.
    pub targets: Vec<TargetReport>,
    /// RMS relative error after each accepted step.
    pub history: Vec<f64>,
}

struct Evaluation {
    freqs: Vec<f64>,
    residual: DVector<f64>,
    jacobian: DMatrix<f64>,
    /// Computed mode (0-based) paired with each target, and its MAC (1 when paired by number).
    paired: Vec<(usize, f64)>,
}

/// Collective. The updating of `p`'s moduli, before and after. Targets are paired with computed
/// modes by MAC against the shapes of `[analysis.updating] target_shapes` when given, else
/// against `computed` (the owned values of the modes of the model as given, as
/// [`super::modal::run`] returns them), else by number. The elements are left as they are: the
/// caller moves the moduli ([`FeProblem::rebuild_elements`]).
pub fn run(
    p: &mut FeProblem,
    cfg: &ModalUpdatingConfig,
    computed: Option<&[Vec<f64>]>,
) -> Result<UpdatingSummary, Error> {
    let (ctx, job, mesh, model) = (p.ctx, p.job, p.mesh, p.model);
    let disc = &mut p.disc;
    let log = &ctx.log;
    let ops = Operators::assemble(ctx, job, cfg, mesh, model, disc)?;
    let shapes = match (&cfg.target_shapes, computed) {
        (Some(file), _) => {
            Some(crate::parallel::agree(&ctx.comm, load_target_shapes(file, cfg, mesh, disc), Error::exit_code)?)
        }
        (None, Some(modes)) => Some(computed_target_shapes(cfg, modes)?),
        (None, None) => None,
    };
    let mut problem = Problem { ctx, cfg, ops, shapes, evaluations: 0 };

    let mut s = DVector::from_element(cfg.parameters.len(), 1.0);
    problem.project(&mut s);
    let ev = problem.evaluate(&s)?;
    let before: Vec<f64> = ev.paired.iter().map(|&(j, _)| ev.freqs[j]).collect();
    let rms_before = rms(&ev.residual);
    log.info(format!(
        "modal updating: {} parameter(s), {} target(s); RMS relative error {:.4e}",
        s.len(),
        cfg.targets.len(),
        rms_before
    ));
    let fit = levenberg_marquardt(&mut problem, s, ev)?;
    let rms_after = rms(&fit.ev.residual);
    let converged = rms_after <= cfg.tolerance;
    if !converged {
        log.warn(format!(
            "modal updating stopped after {} iteration(s) with RMS relative error {rms_after:.3e} > tolerance {:.1e}: \
             the targets may not be reachable within the bounds, or the parameters may not be identifiable from them",
            fit.iterations, cfg.tolerance
        ));
    }
    let parameters = updated_parameters(job, cfg, &fit.s);
    let targets = target_reports(cfg, &before, &fit.ev);
    log_report(ctx, &targets, &parameters);
    Ok(UpdatingSummary {
        iterations: fit.iterations,
        evaluations: problem.evaluations,
        rms_error_before: rms_before,
        rms_error_after: rms_after,
        converged,
        parameters,
        targets,
        history: fit.history,
    })
}

/// RMS of the relative frequency errors.
fn rms(r: &DVector<f64>) -> f64 {
    (r.norm_squared() / r.len().max(1) as f64).sqrt()
}

/// The operators of `K(s) = K_rest + Σ_g s_g K_g` and `M`, with `k` the full pattern that each
/// evaluation fills.
struct Operators {
    k_rest: Matrix,
    k_groups: Vec<Matrix>,
    k: Matrix,
    m: Matrix,
}

impl Operators {
    /// Collective. `K_rest` from the parts not updated, `K_g` from each parameter's group, `M`.
    fn assemble(
        ctx: &Context,
        job: &Job,
        cfg: &ModalUpdatingConfig,
        mesh: &Mesh,
        model: &StructuralModel,
        disc: &mut Discretization,
    ) -> Result<Operators, Error> {
        let format = job.spec.solver.matrix;
        // Part index → parameter index (None: not updated).
        let param_of: Vec<Option<usize>> =
            job.spec.parts.iter().map(|p| cfg.parameters.iter().position(|q| q.group == p.group)).collect();
        let mut k_rest = disc.new_matrix(ctx, mesh, model, format)?;
        assembly::assemble_stiffness_of(disc, mesh, model, None, &|p| param_of[p].is_none(), &mut k_rest)?;
        let mut k_groups = Vec::with_capacity(cfg.parameters.len());
        for g in 0..cfg.parameters.len() {
            let mut kg = disc.new_matrix(ctx, mesh, model, format)?;
            assembly::assemble_stiffness_of(disc, mesh, model, None, &|p| param_of[p] == Some(g), &mut kg)?;
            k_groups.push(kg);
        }
        let mut k = disc.new_matrix(ctx, mesh, model, format)?;
        assembly::assemble_stiffness(disc, mesh, model, None, &mut k)?; // the full pattern
        let mut m = disc.new_matrix(ctx, mesh, model, format)?;
        assembly::assemble_mass(disc, mesh, model, cfg.mass, &mut m)?;
        Ok(Operators { k_rest, k_groups, k, m })
    }
}

/// The least-squares problem: residuals and exact Jacobian of the factors `s`, one eigensolve
/// per evaluation.
struct Problem<'a> {
    ctx: &'a Context,
    cfg: &'a ModalUpdatingConfig,
    ops: Operators,
    /// Target shapes to pair by MAC; `None`: pairing by mode number.
    shapes: Option<Vec<TargetShape>>,
    /// Eigensolves so far.
    evaluations: usize,
}

impl Problem<'_> {
    /// `s` clamped to the bounds `[min, max]` of each parameter.
    fn project(&self, s: &mut DVector<f64>) {
        for (i, p) in self.cfg.parameters.iter().enumerate() {
            s[i] = s[i].clamp(p.min, p.max);
        }
    }

    /// Collective. Frequencies, residuals `r_k = (f_k − f̄_k)/f̄_k` and Jacobian
    /// `∂r_k/∂s_g = φ_kᵀ K_g φ_k / (8π² f_k f̄_k)` at `s`, the targets paired with modes.
    fn evaluate(&mut self, s: &DVector<f64>) -> Result<Evaluation, Error> {
        self.evaluations += 1;
        let (ctx, cfg) = (self.ctx, self.cfg);
        let Operators { k_rest, k_groups, k, m } = &mut self.ops;
        k.zero_entries()?;
        k.axpy(1.0, k_rest)?;
        for (g, kg) in k_groups.iter().enumerate() {
            k.axpy(s[g], kg)?;
        }
        let pairs = lowest_modes(ctx, k, m, cfg.modes, false)?;
        let freqs: Vec<f64> = pairs.iter().map(|(l, _)| l.max(0.0).sqrt() / (2.0 * PI)).collect();
        let nt = cfg.targets.len();
        let mut residual = DVector::zeros(nt);
        let mut jacobian = DMatrix::zeros(nt, k_groups.len());
        let mut kphi: Option<Vector> = None;
        let paired = pair_targets(ctx, cfg, self.shapes.as_deref(), &pairs)?;
        for (i, t) in cfg.targets.iter().enumerate() {
            let Some((_, phi)) = pairs.get(paired[i].0) else {
                return Err(AnalysisError::TargetNotConverged { converged: pairs.len(), mode: t.mode }.into());
            };
            let f = freqs[paired[i].0];
            residual[i] = (f - t.frequency) / t.frequency;
            for (g, kg) in k_groups.iter().enumerate() {
                let kp = match &mut kphi {
                    Some(v) => v,
                    None => kphi.insert(phi.duplicate()?),
                };
                kg.mult(phi, kp)?;
                let dlambda = phi.dot(kp)?;
                jacobian[(i, g)] = dlambda / (8.0 * PI * PI * f.max(f64::MIN_POSITIVE)) / t.frequency;
            }
        }
        Ok(Evaluation { freqs, residual, jacobian, paired })
    }
}

/// Where the Levenberg–Marquardt iteration ended.
struct Fit {
    /// The factors.
    s: DVector<f64>,
    /// Their evaluation.
    ev: Evaluation,
    /// Accepted steps.
    iterations: usize,
    /// RMS relative error before and after each accepted step.
    history: Vec<f64>,
}

/// Collective. Levenberg–Marquardt from `s` (evaluated as `ev`) until the RMS error is within
/// the tolerance, the iterations are spent, or no step decreases the cost.
fn levenberg_marquardt(problem: &mut Problem, mut s: DVector<f64>, mut ev: Evaluation) -> Result<Fit, Error> {
    let cfg = problem.cfg;
    let mut mu = 1e-3;
    let mut history = vec![rms(&ev.residual)];
    let mut iterations = 0;
    while iterations < cfg.max_iterations && rms(&ev.residual) > cfg.tolerance {
        let Some((trial, ev_trial)) = lm_step(problem, &s, &ev, &mut mu)? else { break };
        s = trial;
        ev = ev_trial;
        iterations += 1;
        history.push(rms(&ev.residual));
        problem.ctx.log.info(format!(
            "  iteration {iterations}: RMS relative error {:.4e}; factors {:?}",
            rms(&ev.residual),
            s.iter().map(|x| format!("{x:.6}")).collect::<Vec<_>>()
        ));
    }
    Ok(Fit { s, ev, iterations, history })
}

/// Collective. One Levenberg–Marquardt step from `s`: `(JᵀJ + μ diag JᵀJ) δ = −Jᵀ r`, projected
/// onto the bounds, accepted when the cost decreases (μ ÷ 3), else retried with μ × 4, up to 12
/// tries. `None` when no try decreased the cost or the projected step vanished.
fn lm_step(
    problem: &mut Problem,
    s: &DVector<f64>,
    ev: &Evaluation,
    mu: &mut f64,
) -> Result<Option<(DVector<f64>, Evaluation)>, Error> {
    let jtj = ev.jacobian.transpose() * &ev.jacobian;
    let jtr = ev.jacobian.transpose() * &ev.residual;
    for _ in 0..12 {
        let mut a = jtj.clone();
        for i in 0..a.nrows() {
            a[(i, i)] += *mu * jtj[(i, i)].max(1e-12);
        }
        let Some(delta) = a.cholesky().map(|c| c.solve(&(-&jtr))) else {
            *mu *= 4.0;
            continue;
        };
        let mut trial = s + delta;
        problem.project(&mut trial);
        if (&trial - s).norm() < 1e-14 {
            return Ok(None);
        }
        let ev_trial = problem.evaluate(&trial)?;
        if ev_trial.residual.norm_squared() < ev.residual.norm_squared() {
            *mu = (*mu / 3.0).max(1e-12);
            return Ok(Some((trial, ev_trial)));
        }
        *mu *= 4.0;
    }
    Ok(None)
}

/// The fitted factors with their groups' moduli before and after, and whether each ended on a
/// bound.
fn updated_parameters(job: &Job, cfg: &ModalUpdatingConfig, s: &DVector<f64>) -> Vec<UpdatedParameter> {
    cfg.parameters
        .iter()
        .enumerate()
        .map(|(g, p)| {
            let part = job.spec.parts.iter().find(|q| q.group == p.group);
            let e = part
                .and_then(|q| job.spec.materials.get(&q.material))
                .and_then(MaterialConfig::young_modulus)
                .unwrap_or(f64::NAN);
            UpdatedParameter {
                group: p.group.clone(),
                factor: s[g],
                modulus_before: e,
                modulus_after: e * s[g],
                at_bound: s[g] <= p.min * (1.0 + 1e-12) || s[g] >= p.max * (1.0 - 1e-12),
            }
        })
        .collect()
}

/// Each target's frequency before (`before`, paired at the start) and after (`ev`), with its
/// final pairing.
fn target_reports(cfg: &ModalUpdatingConfig, before: &[f64], ev: &Evaluation) -> Vec<TargetReport> {
    cfg.targets
        .iter()
        .enumerate()
        .map(|(i, t)| TargetReport {
            mode: t.mode,
            target: t.frequency,
            before: before[i],
            after: ev.freqs[ev.paired[i].0],
            paired_mode: ev.paired[i].0 + 1,
            mac: ev.paired[i].1,
        })
        .collect()
}

/// The tables of targets and of parameters, before and after.
fn log_report(ctx: &Context, targets: &[TargetReport], parameters: &[UpdatedParameter]) {
    let log = &ctx.log;
    log.info("target  [Hz]          before [Hz]   after [Hz]   error after   paired mode   MAC");
    for t in targets {
        log.info(format!(
            "{:4}  {:12.6}  {:12.6}  {:11.6}   {:+.3e}   {:6}      {:.4}",
            t.mode,
            t.target,
            t.before,
            t.after,
            (t.after - t.target) / t.target,
            t.paired_mode,
            t.mac
        ));
    }
    log.info("group                factor     E before [Pa]   E after [Pa]");
    for p in parameters {
        log.info(format!(
            "{:20} {:8.5}   {:13.5e}   {:12.5e}{}",
            p.group,
            p.factor,
            p.modulus_before,
            p.modulus_after,
            if p.at_bound { "   (at a bound)" } else { "" }
        ));
    }
}
