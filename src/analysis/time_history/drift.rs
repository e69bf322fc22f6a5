//! Storey drifts (`[[dynamics.drift]]`, `config::drift`): per step, along x and y,
//!
//! ```text
//!   drift = (ū_upper − ū_lower) / (z̄_upper − z̄_lower)
//! ```
//!
//! ū the mean relative displacement of a level's nodes, z̄ their mean height. A level is the
//! model's nodes within a tolerance of a height, or the nodes of a mesh group. Every rank knows
//! the levels' nodes (the whole mesh); each sums the displacements of the ones it owns, and the
//! sums are reduced with the monitors' values (`step_output.rs`).
use super::monitor::placement;
use crate::config::{DriftConfig, DriftLevels};
use crate::error::Error;
use crate::mesh::Mesh;
use crate::parallel::DofMap;

/// Values per drift in the reduced sums: Σ u_x and Σ u_y over the lower level's owned nodes,
/// then over the upper level's.
pub const SUMS: usize = 4;

/// One level of a drift.
#[derive(Clone, Debug)]
struct Level {
    /// Its nodes' indices among this rank's owned nodes.
    owned: Vec<usize>,
    /// Its nodes on all ranks.
    count: usize,
    /// Their mean z [m].
    z: f64,
}

/// One resolved drift.
#[derive(Clone, Debug)]
pub struct Drift {
    /// Its name.
    pub name: String,
    lower: Level,
    upper: Level,
}

impl Drift {
    /// The height between the two levels' mean z [m].
    pub fn height(&self) -> f64 {
        self.upper.z - self.lower.z
    }

    /// The mean z of the lower and the upper level [m].
    pub fn levels(&self) -> [f64; 2] {
        [self.lower.z, self.upper.z]
    }

    /// Nodes of the lower and the upper level.
    pub fn counts(&self) -> [usize; 2] {
        [self.lower.count, self.upper.count]
    }
}

/// Resolves the job's drifts against the mesh (errors name the drift and its key).
pub fn resolve(cfg: &[DriftConfig], mesh: &Mesh, dofs: &DofMap) -> Result<Vec<Drift>, Error> {
    let mut owned_index = vec![usize::MAX; mesh.coords.len()];
    for (i, &n) in dofs.owned.iter().enumerate() {
        owned_index[n] = i;
    }
    let in_model = |n: &usize| dofs.global[*n] != usize::MAX;
    let level = |nodes: Vec<usize>| Level {
        owned: nodes.iter().map(|&n| owned_index[n]).filter(|&i| i != usize::MAX).collect(),
        count: nodes.len(),
        z: nodes.iter().map(|&n| mesh.coords[n][2]).sum::<f64>() / nodes.len().max(1) as f64,
    };
    let mut out = Vec::new();
    for (i, d) in cfg.iter().enumerate() {
        let what = format!("dynamics.drift[{i}] ('{}')", d.name);
        let [lower, upper] = match d.how() {
            DriftLevels::Heights(z, tol) => z.map(|z| {
                let nodes: Vec<usize> =
                    (0..mesh.coords.len()).filter(in_model).filter(|&n| (mesh.coords[n][2] - z).abs() <= tol).collect();
                if nodes.is_empty() {
                    let nearest = (0..mesh.coords.len())
                        .filter(in_model)
                        .map(|n| mesh.coords[n][2])
                        .min_by(|a, b| (a - z).abs().total_cmp(&(b - z).abs()));
                    return Err(placement(
                        &what,
                        format!(
                            "levels: no node of the model within {tol} m of z = {z} m (the nearest is at z = {} m)",
                            nearest.map_or("-".to_string(), |v| v.to_string())
                        ),
                    ));
                }
                Ok(level(nodes))
            }),
            DriftLevels::Groups(groups) => groups.clone().map(|g| {
                let group = mesh.group(&g).map_err(|e| placement(&what, format!("groups: {e}")))?;
                let nodes: Vec<usize> = mesh.nodes_in_group(group).into_iter().filter(in_model).collect();
                if nodes.is_empty() {
                    return Err(placement(&what, format!("groups: group '{g}' has no node of the model")));
                }
                Ok(level(nodes))
            }),
        };
        let (lower, upper) = (lower?, upper?);
        if upper.z - lower.z <= 0.0 {
            return Err(placement(
                &what,
                format!("the upper level's mean z ({} m) is not above the lower level's ({} m)", upper.z, lower.z),
            ));
        }
        out.push(Drift { name: d.name.clone(), lower, upper });
    }
    Ok(out)
}

/// This rank's sums ([`SUMS`] per drift) of the owned level nodes' relative displacement `u`
/// (owned DOFs, 6 per node).
pub fn local_sums(drifts: &[Drift], u: &[f64]) -> Vec<f64> {
    let mut out = Vec::with_capacity(SUMS * drifts.len());
    for d in drifts {
        for l in [&d.lower, &d.upper] {
            for c in 0..2 {
                out.push(l.owned.iter().map(|&i| u[6 * i + c]).sum());
            }
        }
    }
    out
}

/// The drifts along x and y (2 per drift) from the sums of all ranks.
pub fn ratios(drifts: &[Drift], sums: &[f64]) -> Vec<f64> {
    let mut out = Vec::with_capacity(2 * drifts.len());
    for (d, s) in drifts.iter().zip(sums.chunks(SUMS)) {
        let (nl, nu) = (d.lower.count as f64, d.upper.count as f64);
        for c in 0..2 {
            out.push((s[2 + c] / nu - s[c] / nl) / d.height());
        }
    }
    out
}

/// The CSV header's columns: `drift:<name>:x`, `drift:<name>:y`.
pub fn header(drifts: &[Drift]) -> String {
    drifts.iter().map(|d| format!(",drift:{0}:x,drift:{0}:y", d.name)).collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Two levels of two nodes: the drift is the difference of the means over the height.
    #[test]
    fn a_drift_is_the_difference_of_the_mean_displacements_over_the_height() {
        let level = |owned: Vec<usize>, z: f64| Level { count: owned.len(), owned, z };
        let d = Drift { name: "s".into(), lower: level(vec![0, 1], 0.0), upper: level(vec![2, 3], 4.0) };
        let mut u = vec![0.0; 24];
        for (node, ux, uy) in [(0, 0.0, 0.0), (1, 0.002, 0.0), (2, 0.010, -0.004), (3, 0.014, -0.008)] {
            u[6 * node] = ux;
            u[6 * node + 1] = uy;
        }
        let sums = local_sums(std::slice::from_ref(&d), &u);
        let r = ratios(std::slice::from_ref(&d), &sums);
        // x: (0.012 − 0.001) / 4; y: (−0.006 − 0) / 4.
        assert!((r[0] - 0.011 / 4.0).abs() < 1e-15 && (r[1] + 0.006 / 4.0).abs() < 1e-15, "{r:?}");
        assert_eq!(header(&[d]), ",drift:s:x,drift:s:y");
    }
}
