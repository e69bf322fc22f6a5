//! Results of structural analyses to HDF5/XDMF: the rank's piece of the mesh in output numbering
//! (owned nodes in global order; owned cells after those of lower ranks) and its fields.
use super::Discretization;
use crate::config::Job;
use crate::element::AppliedLoads;
use crate::io::{OutputMesh, ResultsWriter};
use crate::mesh::Mesh;
use crate::model::StructuralModel;
use crate::parallel::Context;
use crate::run::Error;
use mpi::traits::{Communicator, CommunicatorCollectives};

/// Collective. The largest `value` over ranks and the tag that goes with it (ties: lowest rank).
pub fn global_max_with_tag(comm: &impl Communicator, value: f64, tag: u64) -> (f64, u64) {
    let n = comm.size() as usize;
    let mut values = vec![0.0f64; n];
    let mut tags = vec![0u64; n];
    comm.all_gather_into(&value, &mut values[..]);
    comm.all_gather_into(&tag, &mut tags[..]);
    let mut best = 0;
    for i in 1..n {
        if values[i] > values[best] {
            best = i;
        }
    }
    (values[best], tags[best])
}

/// Collective. Writes the mesh, displacements, rotations, reactions and element quantities of a
/// static solution (`u_local`: owned then ghost DOFs; `r_owned`: owned DOFs) as one time step.
pub fn write_static_results(
    ctx: &Context,
    job: &Job,
    mesh: &Mesh,
    model: &StructuralModel,
    disc: &Discretization,
    u_local: &[f64],
    r_owned: &[f64],
) -> Result<(), Error> {
    let dofs = &disc.dofs;
    let coords: Vec<[f64; 3]> = dofs.owned.iter().map(|&n| mesh.coords[n]).collect();
    let node_ids: Vec<u64> = dofs.owned.iter().map(|&n| mesh.node_tags[n]).collect();
    let mut cell_kinds = Vec::with_capacity(disc.local_cells.len());
    let mut cell_nodes = Vec::new();
    let mut cell_ids = Vec::with_capacity(disc.local_cells.len());
    let mut cell_groups = Vec::with_capacity(disc.local_cells.len());
    for &c in &disc.local_cells {
        let mc = model.cells[c];
        let cell = &mesh.cells[mc.cell];
        cell_kinds.push(cell.kind);
        cell_nodes.extend(cell.nodes.iter().map(|&n| dofs.global[n]));
        cell_ids.push(cell.tag);
        let group = mesh.group(&job.spec.parts[mc.part].group).map(|g| g.tag).unwrap_or(-1);
        cell_groups.push(group);
    }
    let n_local_cells = disc.local_cells.len() as u64;
    let mut cell_offset = 0u64;
    ctx.comm.exclusive_scan_into(&n_local_cells, &mut cell_offset, mpi::collective::SystemOperation::sum());
    if ctx.rank == 0 {
        cell_offset = 0;
    }
    let out_mesh = OutputMesh {
        node_offset: dofs.node_offset(),
        n_nodes_global: dofs.n_global_nodes,
        coords: &coords,
        node_ids: &node_ids,
        cell_offset: cell_offset as usize,
        n_cells_global: model.cells.len(),
        cell_kinds: &cell_kinds,
        cell_nodes: &cell_nodes,
        cell_ids: &cell_ids,
        cell_groups: &cell_groups,
    };
    let mut w = ResultsWriter::create(&ctx.comm, &job.output_dir, "results", &out_mesh)?;
    w.begin_step(0.0)?;
    let n_owned = dofs.owned.len();
    let pick = |src: &[f64], off: usize| -> Vec<f64> {
        (0..n_owned).flat_map(|i| src[6 * i + off..6 * i + off + 3].iter().copied()).collect()
    };
    w.write_node_field("displacement", 3, &pick(u_local, 0))?;
    w.write_node_field("rotation", 3, &pick(u_local, 3))?;
    // Reactions R = f_int(u) − f_ext on fixed DOFs (K u = f_ext + R): the forces the supports
    // apply to the structure. Zero on free DOFs.
    let mut react = vec![0.0; 6 * n_owned];
    for (i, &n) in dofs.owned.iter().enumerate() {
        for d in 0..6 {
            if dofs.is_fixed(n, d) {
                react[6 * i + d] = r_owned[6 * i + d];
            }
        }
    }
    w.write_node_field("reaction_force", 3, &pick(&react, 0))?;
    w.write_node_field("reaction_moment", 3, &pick(&react, 3))?;
    let loads = AppliedLoads { gravity: model.gravity.unwrap_or([0.0; 3]) };
    let (names, values) = super::assembly::cell_outputs(disc, mesh, model, u_local, &loads)?;
    // Every rank must write the same fields: take the names from the element kinds of the model.
    let k = names.len();
    for (j, name) in names.iter().enumerate() {
        let v: Vec<f64> = (0..disc.local_cells.len()).map(|i| values[i * k + j]).collect();
        w.write_cell_field(name, 1, &v)?;
    }
    w.end_step()?;
    Ok(())
}
