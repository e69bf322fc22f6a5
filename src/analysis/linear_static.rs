//! Linear static analysis, `K u = f`: setup, assemble, solve, check, output.
//!
//! After the solve, equilibrium is checked independently of the linear solver, element by
//! element: `r = f_int(u) − f_ext` must vanish on the free equations (relative to `‖f_ext‖`), and
//! on the fixed ones it gives the support reactions, whose sum must balance the applied loads.
use super::assembly::{self, Rows};
use super::output;
use super::{Discretization, FeProblem};
use crate::error::Error;
use crate::mesh::Mesh;
use crate::model::StructuralModel;
use crate::parallel::{agree, Context, Phases};
use crate::petsc::{Ksp, Matrix, Vector};
use mpi::collective::SystemOperation;
use mpi::traits::CommunicatorCollectives;

/// What a linear static run reports (rank 0 writes it as `summary.json`).
#[derive(Debug, Clone, serde::Serialize)]
pub struct LinearStaticSummary {
    /// Ranks.
    pub ranks: usize,
    /// Active nodes.
    pub nodes: usize,
    /// Elements.
    pub elements: usize,
    /// Equations (6 per node, fixed ones included).
    pub equations: usize,
    /// Fixed DOFs.
    pub fixed_dofs: usize,
    /// Matrix format.
    pub matrix: String,
    /// Solver settings.
    pub ksp: String,
    /// Solver iterations.
    pub iterations: i32,
    /// Wall-clock seconds per phase.
    pub seconds: Timings,
    /// `‖f_int(u) − f_ext‖` on free equations over `‖f_ext‖`.
    pub equilibrium_residual: f64,
    /// Sum of applied loads (`fx` `fy` `fz` [N]; moments about the origin `mx` `my` `mz` [N m]).
    #[serde(with = "crate::io::summary::wrench")]
    pub applied_sum: [f64; 6],
    /// Sum of support reactions (forces of the supports on the structure), same convention;
    /// equilibrium: `applied_sum + reaction_sum = 0`.
    #[serde(with = "crate::io::summary::wrench")]
    pub reaction_sum: [f64; 6],
    /// Largest translation magnitude.
    pub max_displacement: f64,
    /// Gmsh tag of the node where it occurs.
    pub max_displacement_node: u64,
}

/// Seconds spent per phase (the maximum over ranks).
#[derive(Debug, Clone, Default, serde::Serialize)]
pub struct Timings {
    /// Partition, numbering, element construction, matrix creation.
    pub setup: f64,
    /// Stiffness and load assembly.
    pub assemble: f64,
    /// Linear solve (factorization included).
    pub solve: f64,
    /// Equilibrium check and reactions.
    pub check: f64,
    /// HDF5/XDMF output.
    pub output: f64,
}

/// Collective. Runs the analysis of `p` and writes results into the job's results folder:
/// setup, assemble, solve, check, output, each timed.
pub fn run(p: &mut FeProblem) -> Result<LinearStaticSummary, Error> {
    let (ctx, job, mesh, model) = (p.ctx, p.job, p.mesh, p.model);
    let log = &ctx.log;
    let mut phases = Phases::default();
    phases.add("setup", p.take_setup_seconds());
    let format = job.spec.solver.matrix;
    let mut sys = phases.time("setup", || LinearSystem::setup(p))?;
    let disc = &mut p.disc;
    let dofs = &disc.dofs;
    log.info(format!(
        "setup: {} nodes, {} elements, {} equations ({} fixed) on {} rank(s); {:?} matrix",
        dofs.n_global_nodes,
        model.cells.len(),
        6 * dofs.n_global_nodes,
        count_fixed(model, dofs),
        ctx.size,
        format
    ));

    crate::fault::inject("assembly", ctx.rank)?;
    phases.time("assemble", || sys.assemble(disc, mesh, model))?;
    log.info(format!("assembly: {:.3} s", phases.seconds("assemble")));

    let (stats, ksp_desc) = phases.time("solve", || sys.solve(ctx))?;
    log.info(format!("solve: {:.3} s, {} iteration(s), {ksp_desc}", phases.seconds("solve"), stats.iterations));
    sys.u.ghost_update()?;

    let (u_local, eq) = phases.time("check", || -> Result<_, Error> {
        let u_local = sys.u.with_local_form(|s| s.to_vec())?;
        let eq = check_equilibrium(ctx, disc, mesh, model, &u_local)?;
        Ok((u_local, eq))
    })?;
    log.info(format!("equilibrium: relative residual {:.3e}", eq.residual));
    let applied_sum = eq.applied_sum;
    log.info(format!("applied loads  F = ({:.6e}, {:.6e}, {:.6e}) N", applied_sum[0], applied_sum[1], applied_sum[2]));
    log.info(format!(
        "reactions      R = ({:.6e}, {:.6e}, {:.6e}) N",
        eq.reaction_sum[0], eq.reaction_sum[1], eq.reaction_sum[2]
    ));

    let (umax, umax_tag) = largest_translation(ctx, mesh, disc, &u_local);
    log.info(format!("largest displacement: {umax:.6e} m at node {umax_tag}"));

    // The writer checks its arguments across ranks before each collective call, so its errors
    // are seen by every rank.
    phases.time("output", || {
        let written = output::write_static_results(ctx, job, mesh, model, disc, &u_local, &eq.r_owned);
        agree(&ctx.comm, written, Error::exit_code)
    })?;
    log.info(format!("results: {}", job.output_dir.join("results.xdmf").display()));

    Ok(LinearStaticSummary {
        ranks: ctx.size,
        nodes: disc.dofs.n_global_nodes,
        elements: model.cells.len(),
        equations: 6 * disc.dofs.n_global_nodes,
        fixed_dofs: count_fixed(model, &disc.dofs),
        matrix: format!("{format:?}").to_lowercase(),
        ksp: ksp_desc,
        iterations: stats.iterations,
        seconds: Timings::max_over_ranks(ctx, &phases),
        equilibrium_residual: eq.residual,
        applied_sum,
        reaction_sum: eq.reaction_sum,
        max_displacement: umax,
        max_displacement_node: umax_tag,
    })
}

impl Timings {
    /// Collective. The phases' times, each the maximum over ranks.
    fn max_over_ranks(ctx: &Context, phases: &Phases) -> Timings {
        let local = phases.seconds_of(["setup", "assemble", "solve", "check", "output"]);
        let mut t = [0.0; 5];
        ctx.comm.all_reduce_into(&local[..], &mut t[..], SystemOperation::max());
        Timings { setup: t[0], assemble: t[1], solve: t[2], check: t[3], output: t[4] }
    }
}

/// `K u = f`'s matrix and vectors (`u` ghosted) on a problem's discretization.
struct LinearSystem {
    k: Matrix,
    u: Vector,
    f: Vector,
}

impl LinearSystem {
    /// Collective. The matrix (with the rigid-body modes as its near null space) and the vectors.
    fn setup(p: &FeProblem) -> Result<LinearSystem, Error> {
        let (ctx, job, mesh, model, disc) = (p.ctx, p.job, p.mesh, p.model, &p.disc);
        let n_owned = disc.dofs.n_owned_dofs();
        let mut k = disc.new_matrix(ctx, mesh, model, job.spec.solver.matrix)?;
        k.set_near_null_space(&ctx.comm, super::rigid_body_modes(ctx, mesh, &disc.dofs)?)?;
        let u = Vector::new_ghosted(&ctx.comm, n_owned, &disc.dofs.ghost_dofs())?;
        let f = Vector::new_mpi(&ctx.comm, n_owned, None)?;
        Ok(LinearSystem { k, u, f })
    }

    /// Collective. `K` and `f` on the free equations.
    fn assemble(&mut self, disc: &mut Discretization, mesh: &Mesh, model: &StructuralModel) -> Result<(), Error> {
        assembly::assemble_stiffness(disc, mesh, model, None, &mut self.k)?;
        assembly::assemble_loads(disc, mesh, model, Rows::Free, &mut self.f)
    }

    /// Collective. `u` by a Cholesky factorization (MUMPS) unless the options say otherwise;
    /// the solver's statistics and description.
    fn solve(&mut self, ctx: &Context) -> Result<(crate::petsc::KspStats, String), Error> {
        let mut ksp = Ksp::new(&ctx.comm, "")?;
        ksp.set_operators(&self.k)?;
        ksp.set_type("preonly")?;
        ksp.set_pc_type("cholesky")?;
        ksp.set_factor_solver("mumps")?;
        ksp.set_from_options()?;
        // KSP failures are collective (every rank sees the same converged reason): agree on them
        // so the message is printed once and the ranks exit together.
        let stats = agree(&ctx.comm, ksp.solve(&self.f, &mut self.u).map_err(Error::from), Error::exit_code)?;
        Ok((stats, ksp.describe()?))
    }
}

/// The equilibrium check: `r = f_int(u) − f_ext` on every owned equation (the reactions on the
/// fixed ones), its relative size on the free ones, and the resultants of loads and reactions.
struct Equilibrium {
    r_owned: Vec<f64>,
    residual: f64,
    reaction_sum: [f64; 6],
    applied_sum: [f64; 6],
}

/// Collective. Checks equilibrium element by element at `u_local`; reactions on the fixed DOFs.
fn check_equilibrium(
    ctx: &Context,
    disc: &mut Discretization,
    mesh: &Mesh,
    model: &StructuralModel,
    u_local: &[f64],
) -> Result<Equilibrium, Error> {
    let n_owned = disc.dofs.n_owned_dofs();
    let mut r = Vector::new_mpi(&ctx.comm, n_owned, None)?;
    let mut f_all = Vector::new_mpi(&ctx.comm, n_owned, None)?;
    assembly::assemble_internal_forces(disc, mesh, model, u_local, &mut r)?;
    assembly::assemble_loads(disc, mesh, model, Rows::All, &mut f_all)?;
    r.axpy(-1.0, &f_all)?;
    let r_owned = r.owned_values()?;
    let f_owned = f_all.owned_values()?;
    let dofs = &disc.dofs;
    let mut sums = [0.0f64; 14]; // free residual², |f|², reactions 6, applied 6
    for (i, &n) in dofs.owned.iter().enumerate() {
        let x = mesh.coords[n];
        for d in 0..6 {
            let (ri, fi) = (r_owned[6 * i + d], f_owned[6 * i + d]);
            sums[1] += fi * fi;
            if dofs.is_fixed(n, d) {
                add_resultant(&mut sums[2..8], x, d, ri);
            } else {
                sums[0] += ri * ri;
            }
            add_resultant(&mut sums[8..14], x, d, fi);
        }
    }
    let mut total = [0.0f64; 14];
    ctx.comm.all_reduce_into(&sums[..], &mut total[..], SystemOperation::sum());
    let residual = if total[1] > 0.0 { (total[0] / total[1]).sqrt() } else { total[0].sqrt() };
    let reaction_sum: [f64; 6] = total[2..8].try_into().unwrap_or_default();
    let applied_sum: [f64; 6] = total[8..14].try_into().unwrap_or_default();
    Ok(Equilibrium { r_owned, residual, reaction_sum, applied_sum })
}

/// Collective. The largest translation magnitude over the nodes and the Gmsh tag of its node.
fn largest_translation(ctx: &Context, mesh: &Mesh, disc: &Discretization, u_local: &[f64]) -> (f64, u64) {
    let (mut umax, mut umax_tag) = (0.0f64, 0u64);
    for (i, &n) in disc.dofs.owned.iter().enumerate() {
        let v = &u_local[6 * i..6 * i + 3];
        let m = (v[0] * v[0] + v[1] * v[1] + v[2] * v[2]).sqrt();
        if m > umax {
            umax = m;
            umax_tag = mesh.node_tags[n];
        }
    }
    output::global_max_with_tag(&ctx.comm, umax, umax_tag)
}

fn count_fixed(model: &StructuralModel, dofs: &crate::parallel::DofMap) -> usize {
    model
        .fixed
        .iter()
        .enumerate()
        .filter(|(n, _)| dofs.global[*n] != usize::MAX)
        .map(|(_, m)| m.count_ones() as usize)
        .sum()
}

/// Adds a nodal DOF value to a force/moment resultant about the origin: a force component
/// contributes to F and to x × F; a moment component to M.
fn add_resultant(acc: &mut [f64], x: [f64; 3], d: usize, v: f64) {
    if d < 3 {
        let mut fv = [0.0; 3];
        fv[d] = v;
        acc[d] += v;
        acc[3] += x[1] * fv[2] - x[2] * fv[1];
        acc[4] += x[2] * fv[0] - x[0] * fv[2];
        acc[5] += x[0] * fv[1] - x[1] * fv[0];
    } else {
        acc[d] += v;
    }
}
