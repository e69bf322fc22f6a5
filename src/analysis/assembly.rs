//! Assembly of the global stiffness, loads and internal forces into PETSc objects.
//!
//! Each rank loops over the elements it owns and adds their contributions with `ADD_VALUES`;
//! rows owned by other ranks travel at `assemble()` (the "compress" of deal.II).
//!
//! Fixed DOFs keep their equation (so 6-blocks stay whole) but are removed from the system:
//! their element rows and columns are added with index `-1`, which PETSc ignores, and only
//! the element's diagonal term `K_ii` is added on the diagonal. The fixed equation then reads
//! `(Σ_e K_ii) u_i = 0`, a well-scaled row that leaves the free equations untouched, and whose
//! solution is exactly zero. Mass matrices (modal analysis) will put 0 there instead, which sends
//! the fixed DOFs' eigenvalues to infinity, out of a shift-and-invert search.
use super::Discretization;
use crate::element::{AppliedLoads, ElementOutput, EvalRequest};
use crate::error::Error;
use crate::mesh::Mesh;
use crate::model::StructuralModel;
use crate::petsc::{Matrix, Vector};

/// Which equations an assembled vector fills.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Rows {
    /// Free equations only (the right-hand side of the solve).
    Free,
    /// All equations, fixed ones included (reactions).
    All,
}

/// Scratch reused across elements.
#[derive(Default)]
struct Scratch {
    free: Vec<i32>,
    all: Vec<i32>,
    row_major: Vec<f64>,
    u_e: Vec<f64>,
}

/// Collective. Adds the tangent stiffness at displacement `u_local` (local form: owned then
/// ghost DOFs; `None` = zero displacement) into `k`, then assembles it.
pub fn assemble_stiffness(
    disc: &mut Discretization,
    mesh: &Mesh,
    model: &StructuralModel,
    u_local: Option<&[f64]>,
    k: &mut Matrix,
) -> Result<(), Error> {
    assemble_stiffness_of(disc, mesh, model, u_local, &|_| true, k)
}

/// Collective. As [`assemble_stiffness`], over the elements of the parts (indices into the
/// job's `parts`) for which `part_filter` is true.
pub fn assemble_stiffness_of(
    disc: &mut Discretization,
    mesh: &Mesh,
    model: &StructuralModel,
    u_local: Option<&[f64]>,
    part_filter: &dyn Fn(usize) -> bool,
    k: &mut Matrix,
) -> Result<(), Error> {
    assemble_matrix_of(disc, mesh, model, u_local, part_filter, EvalRequest::ForceAndTangent, k)
}

/// Collective. As [`assemble_stiffness`], with the matrix the `request` asks for (the tangent,
/// or the secant stiffness for secant iterations).
pub fn assemble_secant_or_tangent(
    disc: &mut Discretization,
    mesh: &Mesh,
    model: &StructuralModel,
    u_local: Option<&[f64]>,
    request: EvalRequest,
    k: &mut Matrix,
) -> Result<(), Error> {
    assemble_matrix_of(disc, mesh, model, u_local, &|_| true, request, k)
}

fn assemble_matrix_of(
    disc: &mut Discretization,
    mesh: &Mesh,
    model: &StructuralModel,
    u_local: Option<&[f64]>,
    part_filter: &dyn Fn(usize) -> bool,
    request: EvalRequest,
    k: &mut Matrix,
) -> Result<(), Error> {
    let mut s = Scratch::default();
    let mut out = ElementOutput::new(12);
    let local = u_local.map(|_| disc.dofs.local_index());
    for (i, &c) in disc.local_cells.iter().enumerate() {
        if !part_filter(model.cells[c].part) {
            continue;
        }
        let cell = &mesh.cells[model.cells[c].cell];
        disc.element_equations(&cell.nodes, &mut s.free, &mut s.all);
        gather(&cell.nodes, u_local, local.as_ref(), &mut s.u_e);
        let el = &mut disc.elements[i];
        el.evaluate(&s.u_e, request, &mut out).map_err(|source| Error::Element {
            tag: cell.tag,
            group: String::new(),
            source,
        })?;
        let n = s.free.len();
        s.row_major.clear();
        for r in 0..n {
            for col in 0..n {
                s.row_major.push(out.k_t[(r, col)]);
            }
        }
        k.add_values(&s.free, &s.free, &s.row_major)?;
        for r in 0..n {
            if s.free[r] < 0 {
                k.add_values(&s.all[r..r + 1], &s.all[r..r + 1], &[out.k_t[(r, r)]])?;
            }
        }
    }
    k.assemble()?;
    Ok(())
}

/// Collective. Adds the mass matrix of the owned elements into `m`, then assembles it. Fixed
/// DOFs get no entry at all (zero row and column): their eigenvalues of `K φ = λ M φ` are then
/// infinite, out of reach of a shift-and-invert search near zero.
pub fn assemble_mass(
    disc: &Discretization,
    mesh: &Mesh,
    model: &StructuralModel,
    kind: crate::element::MassKind,
    m: &mut Matrix,
) -> Result<(), Error> {
    let mut s = Scratch::default();
    let mut me = nalgebra::DMatrix::zeros(12, 12);
    for (i, &c) in disc.local_cells.iter().enumerate() {
        let cell = &mesh.cells[model.cells[c].cell];
        disc.element_equations(&cell.nodes, &mut s.free, &mut s.all);
        disc.elements[i].mass(kind, &mut me);
        let n = s.free.len();
        s.row_major.clear();
        for r in 0..n {
            for col in 0..n {
                s.row_major.push(me[(r, col)]);
            }
        }
        m.add_values(&s.free, &s.free, &s.row_major)?;
    }
    add_point_masses(disc, model, m)?;
    m.assemble()?;
    Ok(())
}

/// Collective. Adds the diagonal of the owned elements' mass matrices (and the point masses)
/// into `m`, preallocated with one entry per row (the diagonal), then assembles it. Returns
/// whether every off-diagonal entry of this rank's element matrices is exactly zero, i.e.
/// whether `m` is this rank's share of the whole mass matrix: a lumped mass is diagonal, a
/// consistent one is not. The caller reduces the answer over the ranks before trusting `m`.
pub fn assemble_mass_diagonal(
    disc: &Discretization,
    mesh: &Mesh,
    model: &StructuralModel,
    kind: crate::element::MassKind,
    m: &mut Matrix,
) -> Result<bool, Error> {
    let mut s = Scratch::default();
    let mut me = nalgebra::DMatrix::zeros(12, 12);
    let mut diagonal = true;
    for (i, &c) in disc.local_cells.iter().enumerate() {
        let cell = &mesh.cells[model.cells[c].cell];
        disc.element_equations(&cell.nodes, &mut s.free, &mut s.all);
        disc.elements[i].mass(kind, &mut me);
        let n = s.free.len();
        for r in 0..n {
            diagonal &= (0..n).all(|col| col == r || me[(r, col)] == 0.0);
            if s.free[r] >= 0 && me[(r, r)] != 0.0 {
                m.add_values(&s.free[r..r + 1], &s.free[r..r + 1], &[me[(r, r)]])?;
            }
        }
    }
    add_point_masses(disc, model, m)?;
    m.assemble()?;
    Ok(diagonal)
}

/// Adds the point masses on the diagonal of their node's block, free DOFs only (on the rank
/// that owns the node). Not collective.
fn add_point_masses(disc: &Discretization, model: &StructuralModel, m: &mut Matrix) -> Result<(), Error> {
    for &(n, diag) in &model.point_masses {
        if disc.dofs.owner[n] != disc.dofs.rank {
            continue;
        }
        for (d, &v) in diag.iter().enumerate() {
            let eq = disc.dofs.equation(n, d);
            if eq >= 0 && v != 0.0 {
                m.add_values(&[eq], &[eq], &[v])?;
            }
        }
    }
    Ok(())
}

/// Collective. External loads (nodal loads on owned nodes, self-weight of owned elements) into
/// `f` (zeroed first), on the chosen rows, then assembled.
pub fn assemble_loads(
    disc: &Discretization,
    mesh: &Mesh,
    model: &StructuralModel,
    rows: Rows,
    f: &mut Vector,
) -> Result<(), Error> {
    f.set_all(0.0)?;
    let mut s = Scratch::default();
    for &(n, load) in &model.nodal_loads {
        if disc.dofs.owner[n] != disc.dofs.rank {
            continue;
        }
        let idx: Vec<i32> =
            (0..6).map(|d| if rows == Rows::Free { disc.dofs.equation(n, d) } else { disc.dofs.dof(n, d) }).collect();
        f.add_values(&idx, &load)?;
    }
    if let Some(g) = model.gravity {
        // Weight of the point masses on the nodes this rank owns.
        for &(n, diag) in &model.point_masses {
            if disc.dofs.owner[n] != disc.dofs.rank {
                continue;
            }
            let idx: Vec<i32> = (0..3)
                .map(|d| if rows == Rows::Free { disc.dofs.equation(n, d) } else { disc.dofs.dof(n, d) })
                .collect();
            f.add_values(&idx, &[diag[0] * g[0], diag[1] * g[1], diag[2] * g[2]])?;
        }
        let mut fe = nalgebra::DVector::zeros(12);
        for (i, &c) in disc.local_cells.iter().enumerate() {
            let cell = &mesh.cells[model.cells[c].cell];
            disc.element_equations(&cell.nodes, &mut s.free, &mut s.all);
            disc.elements[i].gravity_load(g, &mut fe);
            let idx = if rows == Rows::Free { &s.free } else { &s.all };
            f.add_values(idx, fe.as_slice())?;
        }
    }
    f.assemble()?;
    Ok(())
}

/// Collective. Internal forces `f_int(u)` of the owned elements on all rows into `f` (zeroed first).
pub fn assemble_internal_forces(
    disc: &mut Discretization,
    mesh: &Mesh,
    model: &StructuralModel,
    u_local: &[f64],
    f: &mut Vector,
) -> Result<(), Error> {
    assemble_internal_forces_on(disc, mesh, model, u_local, Rows::All, f)
}

/// Collective. Internal forces `f_int(u)` on the chosen rows (free rows only for a residual).
pub fn assemble_internal_forces_on(
    disc: &mut Discretization,
    mesh: &Mesh,
    model: &StructuralModel,
    u_local: &[f64],
    rows: Rows,
    f: &mut Vector,
) -> Result<(), Error> {
    f.set_all(0.0)?;
    let mut s = Scratch::default();
    let mut out = ElementOutput::new(12);
    let local = disc.dofs.local_index();
    for (i, &c) in disc.local_cells.iter().enumerate() {
        let cell = &mesh.cells[model.cells[c].cell];
        disc.element_equations(&cell.nodes, &mut s.free, &mut s.all);
        gather(&cell.nodes, Some(u_local), Some(&local), &mut s.u_e);
        disc.elements[i].evaluate(&s.u_e, EvalRequest::Force, &mut out).map_err(|source| Error::Element {
            tag: cell.tag,
            group: String::new(),
            source,
        })?;
        let idx = if rows == Rows::Free { &s.free } else { &s.all };
        f.add_values(idx, out.f_int.as_slice())?;
    }
    f.assemble()?;
    Ok(())
}

/// Collective. Cell quantities of the owned elements, as named fields that are the same on every
/// rank: the union of the names of all element kinds in the model, in order of first appearance
/// (rank by rank). An element that does not define a field gets NaN there ("not applicable").
/// Returns the names and the values, field-major (`values[f][i]` for owned element `i`).
pub fn cell_outputs(
    ctx: &crate::parallel::Context,
    disc: &Discretization,
    mesh: &Mesh,
    model: &StructuralModel,
    u_local: &[f64],
    loads: &AppliedLoads,
) -> Result<(Vec<String>, Vec<Vec<f64>>), Error> {
    let mut local_names: Vec<&'static str> = Vec::new();
    for e in &disc.elements {
        for n in e.cell_output_names() {
            if !local_names.contains(n) {
                local_names.push(n);
            }
        }
    }
    let names = union_across_ranks(ctx, &local_names);
    let index: std::collections::HashMap<&str, usize> =
        names.iter().enumerate().map(|(i, n)| (n.as_str(), i)).collect();
    let local = disc.dofs.local_index();
    let mut values = vec![vec![f64::NAN; disc.elements.len()]; names.len()];
    let mut u_e = Vec::new();
    let mut buf = Vec::new();
    for (i, &c) in disc.local_cells.iter().enumerate() {
        let cell = &mesh.cells[model.cells[c].cell];
        gather(&cell.nodes, Some(u_local), Some(&local), &mut u_e);
        let e = &disc.elements[i];
        let own = e.cell_output_names();
        buf.clear();
        buf.resize(own.len(), 0.0);
        e.cell_output(&u_e, loads, &mut buf).map_err(|source| Error::Element {
            tag: cell.tag,
            group: String::new(),
            source,
        })?;
        for (n, v) in own.iter().zip(&buf) {
            values[index[n]][i] = *v;
        }
    }
    Ok((names, values))
}

/// Collective. The union of every rank's names, in order of first appearance, rank by rank.
fn union_across_ranks(ctx: &crate::parallel::Context, local: &[&str]) -> Vec<String> {
    use mpi::traits::CommunicatorCollectives;
    let joined = local.join("\n");
    let bytes = joined.as_bytes();
    let n = ctx.size;
    let mut lens = vec![0u64; n];
    ctx.comm.all_gather_into(&(bytes.len() as u64), &mut lens[..]);
    let total: u64 = lens.iter().sum();
    let mut all = vec![0u8; total as usize];
    let counts: Vec<i32> = lens.iter().map(|&l| l as i32).collect();
    let displs: Vec<i32> = counts
        .iter()
        .scan(0, |acc, &c| {
            let d = *acc;
            *acc += c;
            Some(d)
        })
        .collect();
    {
        let mut partition = mpi::datatype::PartitionMut::new(&mut all[..], &counts[..], &displs[..]);
        mpi::traits::CommunicatorCollectives::all_gather_varcount_into(&ctx.comm, bytes, &mut partition);
    }
    let mut out: Vec<String> = Vec::new();
    for r in 0..n {
        let piece = &all[displs[r] as usize..(displs[r] + counts[r]) as usize];
        for name in String::from_utf8_lossy(piece).split('\n') {
            if !name.is_empty() && !out.iter().any(|o| o == name) {
                out.push(name.to_string());
            }
        }
    }
    out
}

/// The element's DOF values from the local form of a ghosted vector.
pub(super) fn gather(
    nodes: &[usize],
    u_local: Option<&[f64]>,
    local: Option<&std::collections::HashMap<usize, usize>>,
    u_e: &mut Vec<f64>,
) {
    u_e.clear();
    match (u_local, local) {
        (Some(u), Some(map)) => {
            for n in nodes {
                let l = map[n];
                u_e.extend_from_slice(&u[6 * l..6 * l + 6]);
            }
        }
        _ => u_e.resize(6 * nodes.len(), 0.0),
    }
}
