//! Linear static analysis, `K u = f`: setup, assemble, solve, check, output.
//!
//! After the solve, equilibrium is checked independently of the linear solver, element by
//! element: `r = f_int(u) − f_ext` must vanish on the free equations (relative to `‖f_ext‖`), and
//! on the fixed ones it gives the support reactions, whose sum must balance the applied loads.
use super::assembly::{self, Rows};
use super::output;
use super::Discretization;
use crate::config::Job;
use crate::error::Error;
use crate::mesh::Mesh;
use crate::model::StructuralModel;
use crate::parallel::{agree, Context};
use crate::petsc::{Ksp, Petsc, Vector};
use mpi::collective::SystemOperation;
use mpi::traits::CommunicatorCollectives;
use std::time::Instant;

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
    /// Sum of applied loads (Fx Fy Fz; moments about the origin Mx My Mz).
    pub applied_sum: [f64; 6],
    /// Sum of support reactions (forces of the supports on the structure), same convention;
    /// equilibrium: `applied_sum + reaction_sum = 0`.
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

/// Collective. Runs the analysis and writes results into `job.output_dir`.
pub fn run(
    ctx: &Context,
    petsc: &Petsc,
    job: &Job,
    mesh: &Mesh,
    model: &StructuralModel,
) -> Result<LinearStaticSummary, Error> {
    let _ = petsc;
    let log = &ctx.log;
    let mut t = Timings::default();

    // Setup.
    let t0 = Instant::now();
    let mut disc = Discretization::setup(ctx, job, mesh, model)?;
    let dofs = &disc.dofs;
    let n_owned = dofs.n_owned_dofs();
    let format = job.spec.solver.matrix;
    let mut k = disc.new_matrix(ctx, mesh, model, format)?;
    k.set_near_null_space(&ctx.comm, super::rigid_body_modes(ctx, mesh, &disc.dofs)?)?;
    let ghost_dofs = dofs.ghost_dofs();
    let mut u = Vector::new_ghosted(&ctx.comm, n_owned, &ghost_dofs)?;
    let mut f = Vector::new_mpi(&ctx.comm, n_owned, None)?;
    t.setup = t0.elapsed().as_secs_f64();
    log.info(format!(
        "setup: {} nodes, {} elements, {} equations ({} fixed) on {} rank(s); {:?} matrix",
        dofs.n_global_nodes,
        model.cells.len(),
        6 * dofs.n_global_nodes,
        count_fixed(model, dofs),
        ctx.size,
        format
    ));

    // Assemble.
    crate::fault::inject("assembly", ctx.rank)?;
    let t0 = Instant::now();
    assembly::assemble_stiffness(&mut disc, mesh, model, None, &mut k)?;
    assembly::assemble_loads(&disc, mesh, model, Rows::Free, &mut f)?;
    t.assemble = t0.elapsed().as_secs_f64();
    log.info(format!("assembly: {:.3} s", t.assemble));

    // Solve.
    let t0 = Instant::now();
    let mut ksp = Ksp::new(&ctx.comm, "")?;
    ksp.set_operators(&k)?;
    ksp.set_type("preonly")?;
    ksp.set_pc_type("cholesky")?;
    ksp.set_factor_solver("mumps")?;
    ksp.set_from_options()?;
    // KSP failures are collective (every rank sees the same converged reason): agree on them so
    // the message is printed once and the ranks exit together.
    let stats = agree(&ctx.comm, ksp.solve(&f, &mut u).map_err(Error::from), Error::exit_code)?;
    t.solve = t0.elapsed().as_secs_f64();
    let ksp_desc = ksp.describe()?;
    log.info(format!("solve: {:.3} s, {} iteration(s), {ksp_desc}", t.solve, stats.iterations));
    u.ghost_update()?;

    // Check equilibrium element by element; reactions on the fixed DOFs.
    let t0 = Instant::now();
    let u_local = u.with_local_form(|s| s.to_vec())?;
    let mut r = Vector::new_mpi(&ctx.comm, n_owned, None)?;
    let mut f_all = Vector::new_mpi(&ctx.comm, n_owned, None)?;
    assembly::assemble_internal_forces(&mut disc, mesh, model, &u_local, &mut r)?;
    assembly::assemble_loads(&disc, mesh, model, Rows::All, &mut f_all)?;
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
    t.check = t0.elapsed().as_secs_f64();
    log.info(format!("equilibrium: relative residual {residual:.3e}"));
    log.info(format!("applied loads  F = ({:.6e}, {:.6e}, {:.6e}) N", applied_sum[0], applied_sum[1], applied_sum[2]));
    log.info(format!(
        "reactions      R = ({:.6e}, {:.6e}, {:.6e}) N",
        reaction_sum[0], reaction_sum[1], reaction_sum[2]
    ));

    // Largest translation.
    let (mut umax, mut umax_tag) = (0.0f64, 0u64);
    for (i, &n) in dofs.owned.iter().enumerate() {
        let v = &u_local[6 * i..6 * i + 3];
        let m = (v[0] * v[0] + v[1] * v[1] + v[2] * v[2]).sqrt();
        if m > umax {
            umax = m;
            umax_tag = mesh.node_tags[n];
        }
    }
    let (umax, umax_tag) = output::global_max_with_tag(&ctx.comm, umax, umax_tag);
    log.info(format!("largest displacement: {umax:.6e} m at node {umax_tag}"));

    // Output.
    let t0 = Instant::now();
    // The writer checks its arguments across ranks before each collective call, so its errors
    // are seen by every rank.
    agree(&ctx.comm, output::write_static_results(ctx, job, mesh, model, &disc, &u_local, &r_owned), Error::exit_code)?;
    t.output = t0.elapsed().as_secs_f64();
    log.info(format!("results: {}", job.output_dir.join("results.xdmf").display()));

    let mut tmax = [t.setup, t.assemble, t.solve, t.check, t.output];
    let local_t = tmax;
    ctx.comm.all_reduce_into(&local_t[..], &mut tmax[..], SystemOperation::max());
    let seconds = Timings { setup: tmax[0], assemble: tmax[1], solve: tmax[2], check: tmax[3], output: tmax[4] };
    Ok(LinearStaticSummary {
        ranks: ctx.size,
        nodes: disc.dofs.n_global_nodes,
        elements: model.cells.len(),
        equations: 6 * disc.dofs.n_global_nodes,
        fixed_dofs: count_fixed(model, &disc.dofs),
        matrix: format!("{format:?}").to_lowercase(),
        ksp: ksp_desc,
        iterations: stats.iterations,
        seconds,
        equilibrium_residual: residual,
        applied_sum,
        reaction_sum,
        max_displacement: umax,
        max_displacement_node: umax_tag,
    })
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
