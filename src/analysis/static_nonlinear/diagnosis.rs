//! Where a failed increment went wrong: the largest out-of-balance force and the elements
//! whose damage grew.
use crate::analysis::assembly;
use crate::analysis::newton::{global_sum, Increment, NonlinearSystem};
use crate::analysis::output::global_max_with_tag;
use crate::analysis::Discretization;
use crate::element::AppliedLoads;
use crate::error::Error;
use crate::mesh::Mesh;
use crate::model::StructuralModel;
use crate::parallel::Context;

/// Collective. Where a failed increment went wrong: the largest out-of-balance force (node tag,
/// DOF) at the last iterate, and the elements whose damage grew from the committed state.
pub(super) fn diagnose(
    ctx: &Context,
    disc: &Discretization,
    mesh: &Mesh,
    model: &StructuralModel,
    sys: &NonlinearSystem,
    inc: &Increment,
) -> Result<String, Error> {
    let r = sys.current_residual(inc.lambda);
    let (mut worst, mut at) = (0.0f64, 0u64);
    for (i, x) in r.iter().enumerate() {
        if x.abs() > worst || !x.is_finite() {
            worst = if x.is_finite() { x.abs() } else { f64::INFINITY };
            let node = disc.dofs.owned[i / 6];
            at = mesh.node_tags[node] * 8 + (i % 6) as u64;
        }
    }
    let (worst, at) = global_max_with_tag(&ctx.comm, worst, at);
    let dof = ["ux", "uy", "uz", "rx", "ry", "rz"][(at % 8) as usize];
    // Damage at the last iterate vs at the committed displacement (both from the committed state).
    let loads = AppliedLoads::default();
    let (names_now, now) = assembly::cell_outputs(ctx, disc, mesh, model, &local_of(ctx, disc, &sys.u)?, &loads)?;
    let (_, before) = assembly::cell_outputs(ctx, disc, mesh, model, &local_of(ctx, disc, &sys.u_committed)?, &loads)?;
    let mut growth: Vec<(f64, u64)> = Vec::new();
    for key in ["d_t_max", "d_c_max"] {
        if let Some(k) = names_now.iter().position(|n| n == key) {
            for (i, (a, b)) in now[k].iter().zip(&before[k]).enumerate() {
                if a.is_finite() && b.is_finite() && a - b > 1e-12 {
                    let tag = mesh.cells[model.cells[disc.local_cells[i]].cell].tag;
                    growth.push((a - b, tag));
                }
            }
        }
    }
    growth.sort_by(|a, b| b.0.total_cmp(&a.0));
    growth.dedup_by_key(|g| g.1);
    let count = global_sum(ctx, growth.len() as f64) as usize;
    let mut top = Vec::new();
    for _ in 0..5 {
        let (v, tag) =
            global_max_with_tag(&ctx.comm, growth.first().map_or(0.0, |g| g.0), growth.first().map_or(0, |g| g.1));
        if v <= 0.0 {
            break;
        }
        top.push(format!("{tag} (+{v:.3})"));
        if growth.first().is_some_and(|g| g.1 == tag && g.0 == v) {
            growth.remove(0);
        }
    }
    Ok(format!(
        "largest out-of-balance force {worst:.3e} at node {} DOF {dof}; damage grew in {count} element(s){}",
        at / 8,
        if top.is_empty() { String::new() } else { format!(", most in {}", top.join(", ")) }
    ))
}

/// Collective. The local form (owned, then ghosts) of the owned values `u`.
fn local_of(ctx: &Context, disc: &Discretization, u: &[f64]) -> Result<Vec<f64>, Error> {
    let n_owned = disc.dofs.n_owned_dofs();
    let mut v = crate::petsc::Vector::new_ghosted(&ctx.comm, n_owned, &disc.dofs.ghost_dofs())?;
    let first = 6 * disc.dofs.node_offset();
    let idx: Vec<i32> = (0..n_owned).map(|i| (first + i) as i32).collect();
    v.set_values(&idx, u)?;
    v.assemble()?;
    v.ghost_update()?;
    Ok(v.with_local_form(|s| s.to_vec())?)
}
