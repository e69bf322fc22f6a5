//! Results of structural analyses to HDF5/XDMF: the rank's piece of the mesh in output numbering
//! (owned nodes in global order; owned cells after those of lower ranks) and its fields.
use super::Discretization;
use crate::config::Job;
use crate::element::AppliedLoads;
use crate::error::Error;
use crate::io::{OutputMesh, ResultsWriter};
use crate::mesh::Mesh;
use crate::model::StructuralModel;
use crate::parallel::Context;
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

/// The rank's piece of the mesh in output numbering, owning its arrays.
pub struct MeshPiece {
    node_offset: usize,
    n_nodes_global: usize,
    coords: Vec<[f64; 3]>,
    node_ids: Vec<u64>,
    cell_offset: usize,
    n_cells_global: usize,
    cell_kinds: Vec<crate::mesh::CellKind>,
    cell_nodes: Vec<usize>,
    cell_ids: Vec<u64>,
    cell_groups: Vec<i32>,
}

impl MeshPiece {
    /// Collective. Owned nodes in global order; owned cells after those of lower ranks.
    pub fn new(ctx: &Context, job: &Job, mesh: &Mesh, model: &StructuralModel, disc: &Discretization) -> MeshPiece {
        let dofs = &disc.dofs;
        let mut p = MeshPiece {
            node_offset: dofs.node_offset(),
            n_nodes_global: dofs.n_global_nodes,
            coords: dofs.owned.iter().map(|&n| mesh.coords[n]).collect(),
            node_ids: dofs.owned.iter().map(|&n| mesh.node_tags[n]).collect(),
            cell_offset: 0,
            n_cells_global: model.cells.len(),
            cell_kinds: Vec::with_capacity(disc.local_cells.len()),
            cell_nodes: Vec::new(),
            cell_ids: Vec::with_capacity(disc.local_cells.len()),
            cell_groups: Vec::with_capacity(disc.local_cells.len()),
        };
        for &c in &disc.local_cells {
            let mc = model.cells[c];
            let cell = &mesh.cells[mc.cell];
            p.cell_kinds.push(cell.kind);
            p.cell_nodes.extend(cell.nodes.iter().map(|&n| dofs.global[n]));
            p.cell_ids.push(cell.tag);
            p.cell_groups.push(mesh.group(&job.spec.parts[mc.part].group).map(|g| g.tag).unwrap_or(-1));
        }
        let n_local = disc.local_cells.len() as u64;
        let mut offset = 0u64;
        ctx.comm.exclusive_scan_into(&n_local, &mut offset, mpi::collective::SystemOperation::sum());
        p.cell_offset = if ctx.rank == 0 { 0 } else { offset as usize };
        p
    }

    /// The writer's view of it.
    pub fn view(&self) -> OutputMesh<'_> {
        OutputMesh {
            node_offset: self.node_offset,
            n_nodes_global: self.n_nodes_global,
            coords: &self.coords,
            node_ids: &self.node_ids,
            cell_offset: self.cell_offset,
            n_cells_global: self.n_cells_global,
            cell_kinds: &self.cell_kinds,
            cell_nodes: &self.cell_nodes,
            cell_ids: &self.cell_ids,
            cell_groups: &self.cell_groups,
        }
    }
}

/// Owned-node values of 6-DOF data: components `off..off+3` of every node.
pub fn node_triplets(src: &[f64], n_owned: usize, off: usize) -> Vec<f64> {
    (0..n_owned).flat_map(|i| src[6 * i + off..6 * i + off + 3].iter().copied()).collect()
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
    let piece = MeshPiece::new(ctx, job, mesh, model, disc);
    let out_mesh = piece.view();
    let mut w = ResultsWriter::create(&ctx.comm, &job.output_dir, "results", &out_mesh)?;
    w.begin_step(0.0)?;
    let n_owned = dofs.owned.len();
    let pick = |src: &[f64], off: usize| node_triplets(src, n_owned, off);
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
    // The same field names on every rank, whatever element kinds each one holds.
    let (names, values) = super::assembly::cell_outputs(ctx, disc, mesh, model, u_local, &loads)?;
    for (name, v) in names.iter().zip(&values) {
        w.write_cell_field(name, 1, v)?;
    }
    w.end_step()?;
    Ok(())
}
