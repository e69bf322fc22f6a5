//! Pairing of target modes with computed ones by the modal assurance criterion over the DOFs a
//! target shape gives (translations, and rotations when present — a beam-axis torsion mode has
//! no translation): `MAC = (ψᵀφ)² / ((ψᵀψ)(φᵀφ))` (Allemang & Brown 1982). The target shapes come
//! from a file (a `modes.xdmf`'s HDF5, or measured shapes) or from the model's computed modes.
use super::Discretization;
use crate::config::ModalUpdatingConfig;
use crate::error::{AnalysisError, Error};
use crate::mesh::Mesh;
use crate::parallel::Context;
use crate::petsc::Vector;

/// A target shape on this rank's owned DOFs: values (translations, and rotations when the file
/// has them) and which DOFs it gives.
pub(super) struct TargetShape {
    values: Vec<f64>,
    given: Vec<bool>,
}

/// Reads the target shapes (every rank reads the same file) onto the owned DOFs.
pub(super) fn load_target_shapes(
    file: &std::path::Path,
    cfg: &ModalUpdatingConfig,
    mesh: &Mesh,
    disc: &Discretization,
) -> Result<Vec<TargetShape>, Error> {
    let err = |reason: String| Error::from(AnalysisError::TargetShapes { file: file.to_path_buf(), reason });
    let f = hdf5::File::open(file).map_err(|e| err(e.to_string()))?;
    let ids: Vec<u64> =
        f.dataset("mesh/node_ids").and_then(|d| d.read_raw()).map_err(|e| err(format!("mesh/node_ids: {e}")))?;
    let row: std::collections::HashMap<u64, usize> = ids.iter().enumerate().map(|(i, &t)| (t, i)).collect();
    let n_owned = disc.dofs.n_owned_dofs();
    let mut out = Vec::with_capacity(cfg.targets.len());
    for t in &cfg.targets {
        let name = format!("steps/{}/mode_translation", t.mode - 1);
        let v: Vec<f64> = f.dataset(&name).and_then(|d| d.read_raw()).map_err(|e| err(format!("{name}: {e}")))?;
        if v.len() != 3 * ids.len() {
            return Err(err(format!("{name} has {} values, expected 3 per node ({})", v.len(), ids.len())));
        }
        // Rotations too, when the file has them (a computed mode does; measured shapes rarely).
        let rot_name = format!("steps/{}/mode_rotation", t.mode - 1);
        let rot: Option<Vec<f64>> =
            f.dataset(&rot_name).and_then(|d| d.read_raw()).ok().filter(|r: &Vec<f64>| r.len() == v.len());
        let mut shape = TargetShape { values: vec![0.0; n_owned], given: vec![false; n_owned] };
        for (i, &n) in disc.dofs.owned.iter().enumerate() {
            if let Some(&r) = row.get(&mesh.node_tags[n]) {
                for d in 0..3 {
                    shape.values[6 * i + d] = v[3 * r + d];
                    shape.given[6 * i + d] = true;
                    if let Some(rot) = &rot {
                        shape.values[6 * i + 3 + d] = rot[3 * r + d];
                        shape.given[6 * i + 3 + d] = true;
                    }
                }
            }
        }
        out.push(shape);
    }
    Ok(out)
}

/// Collective. MAC of every (target, computed mode) pair, target-major.
fn mac_matrix(ctx: &Context, shapes: &[TargetShape], modes: &[Vec<f64>]) -> Vec<f64> {
    use mpi::collective::SystemOperation;
    use mpi::traits::CommunicatorCollectives;
    let mut local = Vec::with_capacity(3 * shapes.len() * modes.len());
    for s in shapes {
        for phi in modes {
            let (mut ab, mut aa, mut bb) = (0.0, 0.0, 0.0);
            for i in 0..s.values.len() {
                if s.given[i] {
                    ab += s.values[i] * phi[i];
                    aa += s.values[i] * s.values[i];
                    bb += phi[i] * phi[i];
                }
            }
            local.extend([ab, aa, bb]);
        }
    }
    let mut sum = vec![0.0; local.len()];
    ctx.comm.all_reduce_into(&local[..], &mut sum[..], SystemOperation::sum());
    sum.chunks(3).map(|c| if c[1] > 0.0 && c[2] > 0.0 { c[0] * c[0] / (c[1] * c[2]) } else { 0.0 }).collect()
}

/// The target shapes from computed modes (owned values in the discretization's numbering, mode
/// k at index k − 1): each target takes its mode's shape, every DOF given.
pub(super) fn computed_target_shapes(cfg: &ModalUpdatingConfig, modes: &[Vec<f64>]) -> Result<Vec<TargetShape>, Error> {
    cfg.targets
        .iter()
        .map(|t| {
            let values = modes.get(t.mode - 1).cloned().ok_or_else(|| {
                Error::from(AnalysisError::TargetWithoutShape { mode: t.mode, computed: modes.len() })
            })?;
            Ok(TargetShape { given: vec![true; values.len()], values })
        })
        .collect()
}

/// Collective. The computed mode (0-based) paired with each target and its MAC: by mode number
/// (MAC 1) without shapes, else the mode of the largest MAC with the target's shape.
pub(super) fn pair_targets(
    ctx: &Context,
    cfg: &ModalUpdatingConfig,
    shapes: Option<&[TargetShape]>,
    pairs: &[(f64, Vector)],
) -> Result<Vec<(usize, f64)>, Error> {
    let Some(shapes) = shapes else { return Ok(cfg.targets.iter().map(|t| (t.mode - 1, 1.0)).collect()) };
    let owned: Vec<Vec<f64>> = pairs.iter().map(|(_, phi)| phi.owned_values()).collect::<Result<_, _>>()?;
    let mac = mac_matrix(ctx, shapes, &owned);
    Ok((0..cfg.targets.len())
        .map(|i| {
            let row = &mac[i * owned.len()..(i + 1) * owned.len()];
            row.iter().enumerate().fold((0, -1.0), |b, (j, &m)| if m > b.1 { (j, m) } else { b })
        })
        .collect())
}
