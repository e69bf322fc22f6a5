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
use super::Discretization;
use crate::config::{Job, MaterialConfig, ModalUpdatingConfig};
use crate::error::Error;
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

/// A target shape on this rank's owned DOFs: values (translations, and rotations when the file
/// has them) and which DOFs it gives.
struct TargetShape {
    values: Vec<f64>,
    given: Vec<bool>,
}

/// Reads the target shapes (every rank reads the same file) onto the owned DOFs.
fn load_target_shapes(
    file: &std::path::Path,
    cfg: &ModalUpdatingConfig,
    mesh: &Mesh,
    disc: &Discretization,
) -> Result<Vec<TargetShape>, Error> {
    let err = |what: String| Error::Analysis(format!("target shapes {}: {what}", file.display()));
    let f = hdf5::File::open(file).map_err(|e| err(e.to_string()))?;
    let ids: Vec<u64> =
        f.dataset("mesh/node_ids").and_then(|d| d.read_raw()).map_err(|e| err(format!("mesh/node_ids: {e}")))?;
    let row: std::collections::HashMap<u64, usize> = ids.iter().enumerate().map(|(i, &t)| (t, i)).collect();
    let n_owned = disc.dofs.n_owned_dofs();
    let mut out = Vec::with_capacity(cfg.targets.len());
    for t in &cfg.targets {
        let name = format!("steps/{}/mode_translation", t.mode - 1);
        let v: Vec<f64> = f.dataset(&name).and_then(|d| d.read_raw()).map_err(|e| err(format!("{name}: {e}")))?;
        if v.len() != 3 * ids.len() {
            return Err(err(format!("{name} has {} values, expected 3 per node ({})", v.len(), ids.len())));
        }
        // Rotations too, when the file has them (a computed mode does; measured shapes rarely).
        let rot_name = format!("steps/{}/mode_rotation", t.mode - 1);
        let rot: Option<Vec<f64>> =
            f.dataset(&rot_name).and_then(|d| d.read_raw()).ok().filter(|r: &Vec<f64>| r.len() == v.len());
        let mut shape = TargetShape { values: vec![0.0; n_owned], given: vec![false; n_owned] };
        for (i, &n) in disc.dofs.owned.iter().enumerate() {
            if let Some(&r) = row.get(&mesh.node_tags[n]) {
                for d in 0..3 {
                    shape.values[6 * i + d] = v[3 * r + d];
                    shape.given[6 * i + d] = true;
                    if let Some(rot) = &rot {
                        shape.values[6 * i + 3 + d] = rot[3 * r + d];
                        shape.given[6 * i + 3 + d] = true;
                    }
                }
            }
        }
        out.push(shape);
    }
    Ok(out)
}

/// Collective. MAC of every (target, computed mode) pair, target-major.
fn mac_matrix(ctx: &Context, shapes: &[TargetShape], modes: &[Vec<f64>]) -> Vec<f64> {
    use mpi::collective::SystemOperation;
    use mpi::traits::CommunicatorCollectives;
    let mut local = Vec::with_capacity(3 * shapes.len() * modes.len());
    for s in shapes {
        for phi in modes {
            let (mut ab, mut aa, mut bb) = (0.0, 0.0, 0.0);
            for i in 0..s.values.len() {
                if s.given[i] {
                    ab += s.values[i] * phi[i];
                    aa += s.values[i] * s.values[i];
                    bb += phi[i] * phi[i];
                }
            }
            local.extend([ab, aa, bb]);
        }
    }
    let mut sum = vec![0.0; local.len()];
    ctx.comm.all_reduce_into(&local[..], &mut sum[..], SystemOperation::sum());
    sum.chunks(3).map(|c| if c[1] > 0.0 && c[2] > 0.0 { c[0] * c[0] / (c[1] * c[2]) } else { 0.0 }).collect()
}

/// The target shapes from computed modes (owned values in the discretization's numbering, mode
/// k at index k − 1): each target takes its mode's shape, every DOF given.
fn computed_target_shapes(cfg: &ModalUpdatingConfig, modes: &[Vec<f64>]) -> Result<Vec<TargetShape>, Error> {
    cfg.targets
        .iter()
        .map(|t| {
            let values = modes.get(t.mode - 1).cloned().ok_or_else(|| {
                Error::Analysis(format!(
                    "modal updating: target mode {} has no computed shape to pair with ({} mode(s))",
                    t.mode,
                    modes.len()
                ))
            })?;
            Ok(TargetShape { given: vec![true; values.len()], values })
        })
        .collect()
}

/// Collective. Runs the updating and reports before/after.
pub fn run(
    ctx: &Context,
    job: &Job,
    cfg: &ModalUpdatingConfig,
    mesh: &Mesh,
    model: &StructuralModel,
) -> Result<UpdatingSummary, Error> {
    let mut disc = Discretization::setup(ctx, job, mesh, model)?;
    run_on(ctx, job, cfg, mesh, model, &mut disc, None)
}

/// Collective. The updating on a discretization already set up (a stage of a seismic
/// assessment). Targets are paired with computed modes by MAC against the shapes of
/// `[analysis.updating] target_shapes` when given, else against `computed` (the owned values of
/// the modes of the model as given, as [`super::modal::run_on`] returns them), else by number.
/// The elements are left as they are: the caller moves the moduli (`Discretization::rebuild_elements`).
pub fn run_on(
    ctx: &Context,
    job: &Job,
    cfg: &ModalUpdatingConfig,
    mesh: &Mesh,
    model: &StructuralModel,
    disc: &mut Discretization,
    computed: Option<&[Vec<f64>]>,
) -> Result<UpdatingSummary, Error> {
    let log = &ctx.log;
    let format = job.spec.solver.matrix;
    let parts = &job.spec.parts;
    // Part index → parameter index (None: not updated).
    let param_of: Vec<Option<usize>> =
        parts.iter().map(|p| cfg.parameters.iter().position(|q| q.group == p.group)).collect();
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

    let shapes = match (&cfg.target_shapes, computed) {
        (Some(file), _) => {
            Some(crate::parallel::agree(&ctx.comm, load_target_shapes(file, cfg, mesh, disc), Error::exit_code)?)
        }
        (None, Some(modes)) => Some(computed_target_shapes(cfg, modes)?),
        (None, None) => None,
    };
    let lo: Vec<f64> = cfg.parameters.iter().map(|p| p.min).collect();
    let hi: Vec<f64> = cfg.parameters.iter().map(|p| p.max).collect();
    let project = |s: &mut DVector<f64>| {
        for i in 0..s.len() {
            s[i] = s[i].clamp(lo[i], hi[i]);
        }
    };
    let n_modes = cfg.modes;
    let mut evaluations = 0;
    let mut evaluate = |s: &DVector<f64>, k: &mut Matrix| -> Result<Evaluation, Error> {
        evaluations += 1;
        k.zero_entries()?;
        k.axpy(1.0, &k_rest)?;
        for (g, kg) in k_groups.iter().enumerate() {
            k.axpy(s[g], kg)?;
        }
        let pairs = lowest_modes(ctx, k, &m, n_modes)?;
        let freqs: Vec<f64> = pairs.iter().map(|(l, _)| l.max(0.0).sqrt() / (2.0 * PI)).collect();
        let nt = cfg.targets.len();
        let mut residual = DVector::zeros(nt);
        let mut jacobian = DMatrix::zeros(nt, k_groups.len());
        let mut kphi: Option<Vector> = None;
        let paired: Vec<(usize, f64)> = match &shapes {
            None => cfg.targets.iter().map(|t| (t.mode - 1, 1.0)).collect(),
            Some(shapes) => {
                let owned: Vec<Vec<f64>> = pairs.iter().map(|(_, phi)| phi.owned_values()).collect::<Result<_, _>>()?;
                let mac = mac_matrix(ctx, shapes, &owned);
                (0..nt)
                    .map(|i| {
                        let row = &mac[i * owned.len()..(i + 1) * owned.len()];
                        row.iter().enumerate().fold((0, -1.0), |b, (j, &m)| if m > b.1 { (j, m) } else { b })
                    })
                    .collect()
            }
        };
        for (i, t) in cfg.targets.iter().enumerate() {
            let Some((_, phi)) = pairs.get(paired[i].0) else {
                return Err(Error::Analysis(format!(
                    "modal updating: only {} mode(s) converged, but mode {} is a target",
                    pairs.len(),
                    t.mode
                )));
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
    };
    let rms = |r: &DVector<f64>| (r.norm_squared() / r.len().max(1) as f64).sqrt();

    let mut s = DVector::from_element(cfg.parameters.len(), 1.0);
    project(&mut s);
    let mut ev = evaluate(&s, &mut k)?;
    let before: Vec<f64> = ev.paired.iter().map(|&(j, _)| ev.freqs[j]).collect();
    let rms_before = rms(&ev.residual);
    log.info(format!(
        "modal updating: {} parameter(s), {} target(s); RMS relative error {:.4e}",
        s.len(),
        cfg.targets.len(),
        rms_before
    ));
    let mut mu = 1e-3;
    let mut history = vec![rms_before];
    let mut iterations = 0;
    while iterations < cfg.max_iterations && rms(&ev.residual) > cfg.tolerance {
        let jtj = ev.jacobian.transpose() * &ev.jacobian;
        let jtr = ev.jacobian.transpose() * &ev.residual;
        let mut accepted = false;
        for _ in 0..12 {
            let mut a = jtj.clone();
            for i in 0..a.nrows() {
                a[(i, i)] += mu * jtj[(i, i)].max(1e-12);
            }
            let Some(delta) = a.cholesky().map(|c| c.solve(&(-&jtr))) else {
                mu *= 4.0;
                continue;
            };
            let mut trial = &s + delta;
            project(&mut trial);
            if (&trial - &s).norm() < 1e-14 {
                break;
            }
            let ev_trial = evaluate(&trial, &mut k)?;
            if ev_trial.residual.norm_squared() < ev.residual.norm_squared() {
                s = trial;
                ev = ev_trial;
                mu = (mu / 3.0).max(1e-12);
                accepted = true;
                break;
            }
            mu *= 4.0;
        }
        if !accepted {
            break;
        }
        iterations += 1;
        history.push(rms(&ev.residual));
        log.info(format!(
            "  iteration {iterations}: RMS relative error {:.4e}; factors {:?}",
            rms(&ev.residual),
            s.iter().map(|x| format!("{x:.6}")).collect::<Vec<_>>()
        ));
    }
    let rms_after = rms(&ev.residual);
    let converged = rms_after <= cfg.tolerance;
    if !converged {
        log.warn(format!(
            "modal updating stopped after {iterations} iteration(s) with RMS relative error {rms_after:.3e} > tolerance {:.1e}: \
             the targets may not be reachable within the bounds, or the parameters may not be identifiable from them",
            cfg.tolerance
        ));
    }
    let parameters = cfg
        .parameters
        .iter()
        .enumerate()
        .map(|(g, p)| {
            let part = parts.iter().find(|q| q.group == p.group);
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
        .collect::<Vec<_>>();
    let targets = cfg
        .targets
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
        .collect::<Vec<_>>();
    log.info("target  [Hz]          before [Hz]   after [Hz]   error after   paired mode   MAC");
    for t in &targets {
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
    for p in &parameters {
        log.info(format!(
            "{:20} {:8.5}   {:13.5e}   {:12.5e}{}",
            p.group,
            p.factor,
            p.modulus_before,
            p.modulus_after,
            if p.at_bound { "   (at a bound)" } else { "" }
        ));
    }
    Ok(UpdatingSummary {
        iterations,
        evaluations,
        rms_error_before: rms_before,
        rms_error_after: rms_after,
        converged,
        parameters,
        targets,
        history,
    })
}
