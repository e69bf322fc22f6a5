//! What a gravity phase that stopped short of the full load tells the user: where the last
//! attempt is out of balance, which groups are cracked through at the last equilibrium, and that
//! equilibrium written to `gravity-failure.xdmf` for ParaView.
use super::diagnosis::{self, agreed};
use super::gravity::GravityFailure;
use super::petsc_system::PetscSystem;
use crate::analysis::output::{node_triplets, MeshPiece};
use crate::config::Job;
use crate::element::AppliedLoads;
use crate::error::{AnalysisError, Error};
use crate::io::ResultsWriter;
use crate::mesh::Mesh;
use crate::model::StructuralModel;
use crate::parallel::{agree, Context};

/// `d_t_max` above which the gravity failure counts a cell as cracked through.
const CRACKED: f64 = 0.5;

/// Collective. The error of a gravity phase that stopped short of the full load, printed once:
/// where the out-of-balance force of the last attempt is largest, the groups with cells cracked
/// through (`d_t_max` > 0.5) at the last equilibrium, and `gravity-failure.xdmf`, that
/// equilibrium's displacements and cell outputs for ParaView.
pub(super) fn gravity_failure(
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
    agreed(ctx, AnalysisError::GravityFailed { lambda: f.lambda, diagnosis: msg }.into())
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
