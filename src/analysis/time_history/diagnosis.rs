//! What to tell the user when a step cannot be completed: where the out-of-balance force is
//! largest (node and DOF), and which elements' state the failed iteration changed (trial against
//! committed state, compared through [`Element::save_state`]).
use crate::element::Element;
use crate::error::{AnalysisError, Error};
use crate::mesh::Mesh;
use crate::model::StructuralModel;
use crate::parallel::{agree, Context, DofMap};
use mpi::traits::CommunicatorCollectives;

const DOF_NAMES: [&str; 6] = ["ux", "uy", "uz", "rx", "ry", "rz"];
const LISTED: usize = 5;

/// Collective. The largest residual entry over ranks: (|r|, Gmsh node tag, DOF name).
pub fn largest_residual(ctx: &Context, r: &[f64], dofs: &DofMap, mesh: &Mesh) -> (f64, u64, &'static str) {
    let (mut best, mut key) = (0.0f64, 0u64);
    for (i, &n) in dofs.owned.iter().enumerate() {
        for d in 0..6 {
            let v = r.get(6 * i + d).copied().unwrap_or(0.0).abs();
            if v > best || (v.is_nan() && !best.is_nan()) {
                best = v;
                key = mesh.node_tags[n] * 8 + d as u64;
            }
        }
    }
    let (v, k) = crate::analysis::output::global_max_with_tag(&ctx.comm, best, key);
    (v, k / 8, DOF_NAMES[(k % 8) as usize % 6])
}

/// Collective. Elements whose trial state differs from their committed state: their number over
/// all ranks and the (Gmsh tag, largest change) of up to five with the largest changes. Leaves
/// every element with trial = committed.
pub fn changed_elements(
    ctx: &Context,
    elements: &mut [Box<dyn Element>],
    local_cells: &[usize],
    mesh: &Mesh,
    model: &StructuralModel,
) -> (u64, Vec<(u64, f64)>) {
    let mut changed: Vec<(u64, f64)> = Vec::new();
    for (i, e) in elements.iter_mut().enumerate() {
        let n = e.n_state();
        if n == 0 {
            continue;
        }
        let (mut committed, mut trial) = (vec![0.0; n], vec![0.0; n]);
        if e.save_state(&mut committed).is_err() {
            continue;
        }
        e.commit();
        let saved = e.save_state(&mut trial);
        // Restores the committed state (and the trial with it).
        let _ = e.load_state(&committed);
        if saved.is_err() {
            continue;
        }
        let diff = committed.iter().zip(&trial).map(|(a, b)| (a - b).abs()).fold(0.0, f64::max);
        if diff > 0.0 {
            changed.push((mesh.cells[model.cells[local_cells[i]].cell].tag, diff));
        }
    }
    let count_local = changed.len() as u64;
    let mut count = 0u64;
    ctx.comm.all_reduce_into(&count_local, &mut count, mpi::collective::SystemOperation::sum());
    changed.sort_by(|a, b| b.1.total_cmp(&a.1));
    changed.truncate(LISTED);
    let mut tags = [0u64; LISTED];
    let mut diffs = [-1.0f64; LISTED];
    for (k, (t, d)) in changed.iter().enumerate() {
        tags[k] = *t;
        diffs[k] = *d;
    }
    let mut all_tags = vec![0u64; LISTED * ctx.size];
    let mut all_diffs = vec![0.0f64; LISTED * ctx.size];
    ctx.comm.all_gather_into(&tags[..], &mut all_tags[..]);
    ctx.comm.all_gather_into(&diffs[..], &mut all_diffs[..]);
    let mut all: Vec<(u64, f64)> = all_tags.into_iter().zip(all_diffs).filter(|(_, d)| *d >= 0.0).collect();
    all.sort_by(|a, b| b.1.total_cmp(&a.1));
    all.truncate(LISTED);
    (count, all)
}

/// Collective. An error every rank has, as an agreed one (printed once, no abort).
pub(super) fn agreed(ctx: &Context, e: Error) -> Error {
    match agree(&ctx.comm, Err::<(), Error>(e), Error::exit_code) {
        Err(a) => Error::from(a),
        Ok(()) => AnalysisError::LostInAgreement.into(),
    }
}
