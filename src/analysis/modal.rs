//! Modal analysis: the lowest modes of `K φ = ω² M φ` by block shift-and-invert Lanczos
//! ([`block_lanczos`](super::block_lanczos); MUMPS's Cholesky factor of K).
//!
//! Modes are normalized to unit modal mass, `φᵀ M φ = 1`. For a ground motion along direction
//! `d` (influence vector `ι_d`: unit translation `d` at every free node), the participation factor
//! of mode `k` is `Γ_kd = φ_kᵀ M ι_d` and its effective modal mass `m_kd = Γ_kd²`. Over all modes
//! `Σ_k m_kd = ι_dᵀ M ι_d`, the mass that moves with the free DOFs (the "total mass" reported;
//! mass lumped on supported DOFs does not participate), so partial sums stay below it and
//! approach it as modes are added (Chopra, *Dynamics of Structures*, §13.2).
use super::assembly;
use super::block_lanczos;
use super::output::{node_triplets, MeshPiece};
use super::{Discretization, FeProblem};
use crate::config::{Job, ModalConfig};
use crate::element::MassKind;
use crate::error::Error;
use crate::io::ResultsWriter;
use crate::mesh::Mesh;
use crate::model::StructuralModel;
use crate::parallel::{agree, all_ranks, Context, Phases};
use crate::petsc::{Matrix, Vector};

crate::io::summary::named!(
    /// The phases of a modal run.
    seconds_names: ["setup", "assembly", "eigensolve", "output"]
);

/// One mode.
#[derive(Debug, Clone, serde::Serialize)]
pub struct Mode {
    /// 1-based mode number, by increasing frequency.
    pub mode: usize,
    /// Frequency [Hz].
    pub frequency: f64,
    /// Period [s].
    pub period: f64,
    /// Circular frequency ω [rad/s].
    pub omega: f64,
    /// Participation factors Γ in `x`, `y`, `z`.
    #[serde(with = "crate::io::summary::xyz")]
    pub participation: [f64; 3],
    /// Effective modal masses in `x`, `y`, `z` [kg].
    #[serde(with = "crate::io::summary::xyz")]
    pub effective_mass: [f64; 3],
    /// Cumulative effective mass over the total, in `x`, `y`, `z`.
    #[serde(with = "crate::io::summary::xyz")]
    pub cumulative_ratio: [f64; 3],
}

/// What a modal run reports.
#[derive(Debug, Clone, serde::Serialize)]
pub struct ModalSummary {
    /// Ranks.
    pub ranks: usize,
    /// Active nodes.
    pub nodes: usize,
    /// Elements.
    pub elements: usize,
    /// Equations.
    pub equations: usize,
    /// Mass matrix kind.
    pub mass: String,
    /// Mass that moves with the free DOFs, per direction `x` `y` `z` [kg].
    #[serde(with = "crate::io::summary::xyz")]
    pub total_mass: [f64; 3],
    /// The modes.
    pub modes: Vec<Mode>,
    /// Seconds: `setup`, `assembly`, `eigensolve`, `output`.
    #[serde(with = "seconds_names")]
    pub seconds: [f64; 4],
}

/// Collective. The `n` lowest eigenpairs `(λ = ω², φ)` of `K φ = λ M φ`, ascending, with
/// `φᵀ M φ = 1`, by block shift-and-invert Lanczos ([`block_lanczos`](super::block_lanczos)).
/// `diagonal_mass`: `M` is diagonal (a lumped mass stored as such). Logs the solves it took.
pub fn lowest_modes(
    ctx: &Context,
    k: &Matrix,
    m: &Matrix,
    n: usize,
    diagonal_mass: bool,
) -> Result<Vec<(f64, Vector)>, Error> {
    let (pairs, stats) = block_lanczos::lowest_eigenpairs(ctx, k, m, n, diagonal_mass)?;
    ctx.log.info(format!(
        "block Lanczos: {} solves of up to {} vectors ({} in all), {} restart(s); largest residual \
         ‖Kφ − λMφ‖/‖Kφ‖ = {:.1e}",
        stats.solves,
        block_lanczos::BLOCK,
        stats.columns,
        stats.restarts,
        stats.residual
    ));
    Ok(pairs)
}

/// Collective. The mass matrix `M` of the eigenproblem, and whether it is diagonal. A lumped
/// mass is diagonal, and is then stored as such (one entry per row): the eigensolver applies it
/// as a vector. A mass with off-diagonal terms (consistent, or an element whose lumped mass
/// couples its DOFs) takes the stiffness's pattern.
fn mass_matrix(
    ctx: &Context,
    mesh: &Mesh,
    model: &StructuralModel,
    disc: &Discretization,
    kind: MassKind,
    format: crate::config::MatrixFormat,
) -> Result<(Matrix, bool), Error> {
    if kind == MassKind::Lumped {
        let n = disc.dofs.n_owned_dofs();
        let mut m = Matrix::new_aij(&ctx.comm, n, &vec![1; n], &vec![0; n])?;
        m.set_option_symmetric(true)?;
        let local = assembly::assemble_mass_diagonal(disc, mesh, model, kind, &mut m)?;
        if all_ranks(ctx, local) {
            return Ok((m, true));
        }
    }
    let mut m = disc.new_matrix(ctx, mesh, model, format)?;
    assembly::assemble_mass(disc, mesh, model, kind, &mut m)?;
    Ok((m, false))
}

/// Collective. The modal analysis of `p`: the mode shapes in `<stem>.xdmf` + `<stem>.h5` of the
/// job's results folder, and returned too: the owned values of each mass-normalized mode, in the
/// discretization's numbering (a seismic assessment pairs its updating targets with them).
pub fn run(p: &mut FeProblem, cfg: &ModalConfig, stem: &str) -> Result<(ModalSummary, Vec<Vec<f64>>), Error> {
    let setup = p.take_setup_seconds();
    let (ctx, job, mesh, model) = (p.ctx, p.job, p.mesh, p.model);
    let disc = &mut p.disc;
    let log = &ctx.log;
    let mut phases = Phases::default();
    phases.add("setup", setup);
    let format = job.spec.solver.matrix;
    let mut k = phases.time("setup", || disc.new_matrix(ctx, mesh, model, format))?;
    let (m, diagonal_mass) = phases.time("assemble", || -> Result<(Matrix, bool), Error> {
        assembly::assemble_stiffness(disc, mesh, model, None, &mut k)?;
        mass_matrix(ctx, mesh, model, disc, cfg.mass, format)
    })?;
    let t_assemble = phases.seconds("assemble");
    log.info(format!(
        "modal: {} equations, {:?} mass, {} mode(s) wanted; assembly {t_assemble:.3} s",
        6 * disc.dofs.n_global_nodes,
        cfg.mass,
        cfg.modes
    ));

    let pairs = phases.time("eigensolve", || lowest_modes(ctx, &k, &m, cfg.modes, diagonal_mass))?;
    let t_solve = phases.seconds("eigensolve");
    let Participation { modes, shapes, total_mass } = participation(ctx, disc, &m, pairs)?;
    log.info(format!(
        "eigensolve: {t_solve:.3} s; total mass (x, y, z) = ({:.4e}, {:.4e}, {:.4e}) kg",
        total_mass[0], total_mass[1], total_mass[2]
    ));
    log_modes(ctx, &modes, total_mass);
    phases.time("output", || write_shapes(ctx, job, mesh, model, disc, stem, &modes, &shapes))?;
    log.info(format!("mode shapes: {}", job.output_dir.join(format!("{stem}.xdmf")).display()));

    let summary = ModalSummary {
        ranks: ctx.size,
        nodes: disc.dofs.n_global_nodes,
        elements: model.cells.len(),
        equations: 6 * disc.dofs.n_global_nodes,
        mass: format!("{:?}", cfg.mass).to_lowercase(),
        total_mass,
        modes,
        seconds: phases.seconds_of(["setup", "assemble", "eigensolve", "output"]),
    };
    Ok((summary, shapes))
}

/// The modes with their participation, their shapes and the total masses.
struct Participation {
    modes: Vec<Mode>,
    /// Owned values of each mass-normalized mode, in the discretization's numbering.
    shapes: Vec<Vec<f64>>,
    /// `ι_dᵀ M ι_d` per direction [kg].
    total_mass: [f64; 3],
}

/// Collective. The modes of the eigenpairs `(λ, φ)` (mass-normalized φ) with their
/// participation: with the influence vectors ι_d (unit translation d at every node), the factor
/// `Γ_d = φᵀ M ι_d`, the effective mass `Γ_d²` and its cumulative ratio to the total mass
/// `ι_dᵀ M ι_d`. Also the owned values of each φ, and the total masses.
fn participation(
    ctx: &Context,
    disc: &Discretization,
    m: &Matrix,
    pairs: Vec<(f64, Vector)>,
) -> Result<Participation, Error> {
    let n_owned = disc.dofs.n_owned_dofs();
    let first = (6 * disc.dofs.node_offset()) as i32;
    let idx: Vec<i32> = (0..n_owned as i32).map(|i| first + i).collect();
    let mut m_iota = Vec::with_capacity(3);
    let mut total_mass = [0.0; 3];
    for d in 0..3 {
        let vals: Vec<f64> = (0..n_owned).map(|i| if i % 6 == d { 1.0 } else { 0.0 }).collect();
        let mut iota = Vector::new_mpi(&ctx.comm, n_owned, None)?;
        iota.set_values(&idx, &vals)?;
        iota.assemble()?;
        let mut mi = Vector::new_mpi(&ctx.comm, n_owned, None)?;
        m.mult(&iota, &mut mi)?;
        total_mass[d] = iota.dot(&mi)?;
        m_iota.push(mi);
    }

    let mut modes = Vec::with_capacity(pairs.len());
    let mut shapes = Vec::with_capacity(pairs.len());
    let mut cumulative = [0.0; 3];
    for (i, (lambda, phi)) in pairs.into_iter().enumerate() {
        let omega = lambda.max(0.0).sqrt();
        let mut gamma = [0.0; 3];
        let mut meff = [0.0; 3];
        for d in 0..3 {
            gamma[d] = phi.dot(&m_iota[d])?;
            meff[d] = gamma[d] * gamma[d];
            cumulative[d] += meff[d];
        }
        let ratio = [0, 1, 2].map(|d| if total_mass[d] > 0.0 { cumulative[d] / total_mass[d] } else { 0.0 });
        modes.push(Mode {
            mode: i + 1,
            frequency: omega / (2.0 * std::f64::consts::PI),
            period: if omega > 0.0 { 2.0 * std::f64::consts::PI / omega } else { f64::INFINITY },
            omega,
            participation: gamma,
            effective_mass: meff,
            cumulative_ratio: ratio,
        });
        shapes.push(phi.owned_values()?);
    }
    Ok(Participation { modes, shapes, total_mass })
}

/// The table of modes: frequency, period, effective mass ratios and their running sums.
fn log_modes(ctx: &Context, modes: &[Mode], total_mass: [f64; 3]) {
    let log = &ctx.log;
    log.info("mode  frequency [Hz]   period [s]   eff. mass ratio x     y      z   (cumulative)");
    for md in modes {
        log.info(format!(
            "{:4}  {:14.6}  {:11.6}   {:6.3} {:6.3} {:6.3}   ({:.3} {:.3} {:.3})",
            md.mode,
            md.frequency,
            md.period,
            md.effective_mass[0] / total_mass[0].max(f64::MIN_POSITIVE),
            md.effective_mass[1] / total_mass[1].max(f64::MIN_POSITIVE),
            md.effective_mass[2] / total_mass[2].max(f64::MIN_POSITIVE),
            md.cumulative_ratio[0],
            md.cumulative_ratio[1],
            md.cumulative_ratio[2]
        ));
    }
}

/// Collective. The mode shapes in `<stem>.xdmf` + `<stem>.h5`: one output step per mode, the
/// step's "time" is the mode number.
#[allow(clippy::too_many_arguments)]
fn write_shapes(
    ctx: &Context,
    job: &Job,
    mesh: &Mesh,
    model: &StructuralModel,
    disc: &Discretization,
    stem: &str,
    modes: &[Mode],
    shapes: &[Vec<f64>],
) -> Result<(), Error> {
    let piece = MeshPiece::new(ctx, job, mesh, model, disc);
    let written: Result<(), Error> = (|| {
        let mut w = ResultsWriter::create(&ctx.comm, &job.output_dir, stem, &piece.view())?;
        let n_nodes = disc.dofs.owned.len();
        for (md, shape) in modes.iter().zip(shapes) {
            w.begin_step(md.mode as f64)?;
            w.write_node_field("mode_translation", 3, &node_triplets(shape, n_nodes, 0))?;
            w.write_node_field("mode_rotation", 3, &node_triplets(shape, n_nodes, 3))?;
            w.end_step()?;
        }
        w.close()?;
        Ok(())
    })();
    agree(&ctx.comm, written, Error::exit_code)?;
    Ok(())
}
