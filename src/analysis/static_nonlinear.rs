//! Nonlinear static analysis: the loads `f` scaled by a load factor λ from 0 to 1 in steps, and
//! in each step Newton's method on `r(u) = λ f − f_int(u) = 0` (free equations):
//!
//! ```text
//!   K_t(u_k) Δu = r(u_k),   u_{k+1} = u_k + Δu,   K_t = ∂f_int/∂u (the elements' consistent tangent)
//!   converged when ‖r‖ ≤ tol_f ‖λ f‖ (or ‖r‖ tiny in absolute terms) and |Δu·r| ≤ tol_e |Δu₀·r₀|
//! ```
//!
//! Elements evaluate from their committed state and keep the result as a trial state; a converged
//! step commits every element, a failed one reverts them and is retried with half the load
//! increment, up to `max_cuts` times, after which the run stops with a diagnosis: the step, λ,
//! the residual, and the node and DOF where the out-of-balance force is largest. Every converged
//! step is written to `results.xdmf` (time = λ), so a run that stops keeps what it computed.
use super::assembly::{self, Rows};
use super::output::{node_triplets, MeshPiece};
use super::Discretization;
use crate::config::{Job, StaticNonlinearConfig};
use crate::element::AppliedLoads;
use crate::io::ResultsWriter;
use crate::mesh::Mesh;
use crate::model::StructuralModel;
use crate::parallel::{agree, Context};
use crate::petsc::{Ksp, Vector};
use crate::run::Error;

/// One converged step.
#[derive(Debug, Clone, serde::Serialize)]
pub struct StepReport {
    /// Load factor reached.
    pub lambda: f64,
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
    /// Converged steps.
    pub steps: Vec<StepReport>,
    /// Step cut-backs made.
    pub cuts: usize,
}

/// Collective. Runs the analysis.
pub fn run(ctx: &Context, job: &Job, cfg: &StaticNonlinearConfig, mesh: &Mesh, model: &StructuralModel) -> Result<StaticNonlinearSummary, Error> {
    let log = &ctx.log;
    let mut disc = Discretization::setup(ctx, job, mesh, model)?;
    let n_owned = disc.dofs.n_owned_dofs();
    let mut k = disc.new_matrix(ctx, mesh, model, job.spec.solver.matrix)?;
    k.set_near_null_space(&ctx.comm, super::rigid_body_modes(ctx, mesh, &disc.dofs)?)?;
    let mut f_ref = Vector::new_mpi(&ctx.comm, n_owned, None)?;
    assembly::assemble_loads(&disc, mesh, model, Rows::Free, &mut f_ref)?;
    let f_norm = f_ref.norm2()?;
    let mut u = Vector::new_ghosted(&ctx.comm, n_owned, &disc.dofs.ghost_dofs())?;
    let mut u_committed = Vector::new_mpi(&ctx.comm, n_owned, None)?;
    let mut du = Vector::new_mpi(&ctx.comm, n_owned, None)?;
    let mut r = Vector::new_mpi(&ctx.comm, n_owned, None)?;
    let mut fint = Vector::new_mpi(&ctx.comm, n_owned, None)?;
    let mut ksp = Ksp::new(&ctx.comm, "")?;
    ksp.set_type("preonly")?;
    ksp.set_pc_type("lu")?;
    ksp.set_factor_solver("mumps")?;

    let piece = MeshPiece::new(ctx, job, mesh, model, &disc);
    let mut writer = agree(&ctx.comm, ResultsWriter::create(&ctx.comm, &job.output_dir, "results", &piece.view()).map_err(Error::from), Error::exit_code)?;

    let mut lambda = 0.0f64;
    let mut dlambda = 1.0 / cfg.steps as f64;
    let mut reports = Vec::new();
    let mut cuts_total = 0;
    let mut cuts_in_row = 0;
    while lambda < 1.0 - 1e-12 {
        let target = (lambda + dlambda).min(1.0);
        // Newton from the committed state.
        u_committed.with_owned_values(|c| c.to_vec()).and_then(|c| {
            let first = (6 * disc.dofs.node_offset()) as i32;
            let idx: Vec<i32> = (0..n_owned as i32).map(|i| first + i).collect();
            u.set_values(&idx, &c)
        })?;
        u.assemble()?;
        u.ghost_update()?;
        let mut converged = false;
        let mut last = f64::INFINITY;
        let mut energy0 = 0.0f64;
        let mut iterations = 0;
        for it in 0..cfg.max_iterations {
            iterations = it + 1;
            let u_local = u.with_local_form(|s| s.to_vec())?;
            // r = λ f − f_int(u) on the free rows.
            assembly::assemble_internal_forces_on(&mut disc, mesh, model, &u_local, Rows::Free, &mut fint)?;
            r.copy_from(&f_ref)?;
            r.scale(target)?;
            r.axpy(-1.0, &fint)?;
            let rn = r.norm2()?;
            last = rn / (target * f_norm).max(f64::MIN_POSITIVE);
            k.zero_entries()?;
            assembly::assemble_stiffness(&mut disc, mesh, model, Some(&u_local), &mut k)?;
            ksp.set_operators(&k)?;
            if it == 0 {
                ksp.set_from_options()?;
            }
            let solved = agree(&ctx.comm, ksp.solve(&r, &mut du).map_err(Error::from), Error::exit_code);
            if solved.is_err() {
                break;
            }
            let energy = du.dot(&r)?.abs();
            if it == 0 {
                energy0 = energy.max(f64::MIN_POSITIVE);
            }
            if last <= cfg.force_tolerance || (it > 0 && energy <= cfg.energy_tolerance * energy0) || rn == 0.0 {
                converged = true;
                break;
            }
            // u += Δu (owned part; ghosts refreshed).
            let d = du.owned_values()?;
            let first = (6 * disc.dofs.node_offset()) as i32;
            let idx: Vec<i32> = (0..n_owned as i32).map(|i| first + i).collect();
            let mut cur = u.with_local_form(|s| s[..n_owned].to_vec())?;
            for (c, x) in cur.iter_mut().zip(&d) {
                *c += x;
            }
            u.set_values(&idx, &cur)?;
            u.assemble()?;
            u.ghost_update()?;
            if !last.is_finite() {
                break;
            }
        }
        if converged {
            for e in disc.elements.iter_mut() {
                e.commit();
            }
            lambda = target;
            let owned = u.with_local_form(|s| s[..n_owned].to_vec())?;
            let first = (6 * disc.dofs.node_offset()) as i32;
            let idx: Vec<i32> = (0..n_owned as i32).map(|i| first + i).collect();
            u_committed.set_values(&idx, &owned)?;
            u_committed.assemble()?;
            let mut umax = 0.0f64;
            for i in 0..disc.dofs.owned.len() {
                let v = &owned[6 * i..6 * i + 3];
                umax = umax.max((v[0] * v[0] + v[1] * v[1] + v[2] * v[2]).sqrt());
            }
            let (umax, _) = super::output::global_max_with_tag(&ctx.comm, umax, 0);
            log.info(format!("step λ = {lambda:.4}: {iterations} iteration(s), residual {last:.2e}, max |u| = {umax:.4e} m"));
            let u_local = u.with_local_form(|s| s.to_vec())?;
            let wrote: Result<(), Error> = (|| {
                writer.begin_step(lambda)?;
                let n = disc.dofs.owned.len();
                writer.write_node_field("displacement", 3, &node_triplets(&u_local, n, 0))?;
                writer.write_node_field("rotation", 3, &node_triplets(&u_local, n, 3))?;
                let loads = AppliedLoads { gravity: model.gravity.map(|g| [g[0] * lambda, g[1] * lambda, g[2] * lambda]).unwrap_or([0.0; 3]) };
                let (names, values) = assembly::cell_outputs(ctx, &disc, mesh, model, &u_local, &loads)?;
                for (name, v) in names.iter().zip(&values) {
                    writer.write_cell_field(name, 1, v)?;
                }
                writer.end_step()?;
                Ok(())
            })();
            agree(&ctx.comm, wrote, Error::exit_code)?;
            reports.push(StepReport { lambda, iterations, residual: last, max_displacement: umax });
            cuts_in_row = 0;
            dlambda = (dlambda * 1.5).min(1.0 / cfg.steps as f64);
        } else {
            for e in disc.elements.iter_mut() {
                e.revert();
            }
            if cuts_in_row >= cfg.max_cuts {
                return Err(Error::Analysis(format!(
                    "static_nonlinear: no equilibrium from λ = {lambda:.6} towards {target:.6} after {} halvings of the step \
                     (last relative residual {last:.3e}); results up to λ = {lambda:.6} are in {}",
                    cfg.max_cuts,
                    job.output_dir.join("results.xdmf").display()
                )));
            }
            cuts_in_row += 1;
            cuts_total += 1;
            dlambda *= 0.5;
            log.info(format!("step towards λ = {target:.4} did not converge (residual {last:.2e}); cutting the step to Δλ = {dlambda:.4e}"));
        }
    }
    Ok(StaticNonlinearSummary { steps: reports, cuts: cuts_total })
}
