//! Rigid-body modes of a 6-DOF-per-node structure, the near-null space of its stiffness.
//!
//! For a node at `x` (relative to a reference point `c`, scaled by the model size `s` so the six
//! vectors have comparable norms), the rigid motions are
//!
//! * translation along axis `k`: `u = e_k`, `θ = 0`;
//! * rotation about axis `k`:    `u = e_k × (x − c)/s`, `θ = e_k / s`
//!   (a rotation of `1/s` radians, which moves the farthest nodes by about one unit).
//!
//! Smoothed-aggregation multigrid (PETSc GAMG, ML) needs them to build coarse spaces that
//! represent bending; with translations alone, a slender frame needs hundreds of CG iterations
//! or does not converge.
use crate::mesh::Mesh;
use crate::parallel::{Context, DofMap};
use crate::petsc::{PetscError, Vector};
use mpi::collective::SystemOperation;
use mpi::traits::CommunicatorCollectives;

/// Collective. The six rigid-body modes as PETSc vectors over the owned equations.
pub fn rigid_body_modes(ctx: &Context, mesh: &Mesh, dofs: &DofMap) -> Result<Vec<Vector>, PetscError> {
    // Reference point and size: the bounding box of the active nodes.
    let mut lo: [f64; 3] = [f64::INFINITY; 3];
    let mut hi = [f64::NEG_INFINITY; 3];
    for &n in &dofs.owned {
        for k in 0..3 {
            lo[k] = lo[k].min(mesh.coords[n][k]);
            hi[k] = hi[k].max(mesh.coords[n][k]);
        }
    }
    let (mut glo, mut ghi) = ([0.0f64; 3], [0.0f64; 3]);
    ctx.comm.all_reduce_into(&lo[..], &mut glo[..], SystemOperation::min());
    ctx.comm.all_reduce_into(&hi[..], &mut ghi[..], SystemOperation::max());
    let c = [0.5 * (glo[0] + ghi[0]), 0.5 * (glo[1] + ghi[1]), 0.5 * (glo[2] + ghi[2])];
    let size = ((ghi[0] - glo[0]).powi(2) + (ghi[1] - glo[1]).powi(2) + (ghi[2] - glo[2]).powi(2))
        .sqrt()
        .max(f64::MIN_POSITIVE);

    let n_owned = dofs.n_owned_dofs();
    let first = (6 * dofs.node_offset()) as i32;
    let idx: Vec<i32> = (0..n_owned as i32).map(|i| first + i).collect();
    let mut modes = Vec::with_capacity(6);
    for m in 0..6 {
        let mut vals = vec![0.0; n_owned];
        for (i, &n) in dofs.owned.iter().enumerate() {
            let v = &mut vals[6 * i..6 * i + 6];
            if m < 3 {
                v[m] = 1.0;
            } else {
                let k = m - 3;
                let r = [
                    (mesh.coords[n][0] - c[0]) / size,
                    (mesh.coords[n][1] - c[1]) / size,
                    (mesh.coords[n][2] - c[2]) / size,
                ];
                // e_k × r
                let (a, b) = ((k + 1) % 3, (k + 2) % 3);
                v[b] = r[a];
                v[a] = -r[b];
                v[3 + k] = 1.0 / size;
            }
        }
        let mut vec = Vector::new_mpi(&ctx.comm, n_owned, None)?;
        vec.set_values(&idx, &vals)?;
        vec.assemble()?;
        modes.push(vec);
    }
    Ok(modes)
}
