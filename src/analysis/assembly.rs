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
use crate::mesh::Mesh;
use crate::model::StructuralModel;
use crate::petsc::{Matrix, Vector};
use crate::run::Error;

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
        el.evaluate(&s.u_e, EvalRequest::ForceAndTangent, &mut out).map_err(|source| Error::Element {
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
    m.assemble()?;
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
        let idx: Vec<i32> = (0..6)
            .map(|d| if rows == Rows::Free { disc.dofs.equation(n, d) } else { disc.dofs.dof(n, d) })
            .collect();
        f.add_values(&idx, &load)?;
    }
    if let Some(g) = model.gravity {
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
    f.set_all(0.0)?;
    let mut s = Scratch::default();
    let mut out = ElementOutput::new(12);
    let local = disc.dofs.local_index();
    for (i, &c) in disc.local_cells.iter().enumerate() {
        let cell = &mesh.cells[model.cells[c].cell];
        disc.element_equations(&cell.nodes, &mut s.free, &mut s.all);
        gather(&cell.nodes, Some(u_local), Some(&local), &mut s.u_e);
        disc.elements[i].evaluate(&s.u_e, EvalRequest::Force, &mut out).map_err(|source| {
            Error::Element { tag: cell.tag, group: String::new(), source }
        })?;
        f.add_values(&s.all, out.f_int.as_slice())?;
    }
    f.assemble()?;
    Ok(())
}

/// Cell quantities of the owned elements (`names.len()` per cell, cell-major), at `u_local`.
pub fn cell_outputs(
    disc: &Discretization,
    mesh: &Mesh,
    model: &StructuralModel,
    u_local: &[f64],
    loads: &AppliedLoads,
) -> Result<(Vec<&'static str>, Vec<f64>), Error> {
    let local = disc.dofs.local_index();
    let names: Vec<&'static str> =
        disc.elements.first().map(|e| e.cell_output_names().to_vec()).unwrap_or_default();
    let mut values = vec![0.0; names.len() * disc.elements.len()];
    let mut u_e = Vec::new();
    for (i, &c) in disc.local_cells.iter().enumerate() {
        let cell = &mesh.cells[model.cells[c].cell];
        gather(&cell.nodes, Some(u_local), Some(&local), &mut u_e);
        let k = names.len();
        disc.elements[i]
            .cell_output(&u_e, loads, &mut values[i * k..(i + 1) * k])
            .map_err(|source| Error::Element { tag: cell.tag, group: String::new(), source })?;
    }
    Ok((names, values))
}

/// The element's DOF values from the local form of a ghosted vector.
fn gather(
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
