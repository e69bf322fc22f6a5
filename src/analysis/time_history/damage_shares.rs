//! Damage per substructure: for every part's group of shells, the share of its area whose peak
//! tensile (compressive) damage over the layers passed a threshold, from the cell envelopes.
//! The same measure as `scripts/pv_post.py`'s `damage-by-group.csv` (area shares
//! with d_t > 0.05 and > 0.5), so that a sweep's table and the pictures of one run agree.
//!
//! A cell's area is that of its flat polygon (a quad as two triangles over its diagonal 1–3).
//!
//! Beside the shares, each group's energy dissipated by damage (J): the shares count the area of
//! cracked cells, so a crack one element wide weighs as much as the element is large, while the
//! crack-band regularization (Bažant and Oh 1983) scales each element's softening so that it
//! dissipates the fracture energy per crack area whatever its size. The dissipated energy is
//! therefore the nearer to mesh-objective of the two (docs/convergence.md measures both on two
//! meshes).
use super::envelope::{Envelopes, CELL_VALUES};
use crate::analysis::Discretization;
use crate::config::Job;
use crate::mesh::{CellKind, Mesh};
use crate::model::StructuralModel;
use crate::parallel::Context;
use mpi::collective::SystemOperation;
use mpi::traits::CommunicatorCollectives;

/// Whether every `[[dynamics.stop_when]]` share is reached in `groups` ([`by_group`]'s measure;
/// false without rules). The damage is irreversible, so a share never falls once reached: the
/// run may end there with every later share at least as large.
pub fn stop_reached(groups: &[GroupDamage], rules: &[crate::config::StopWhenConfig]) -> bool {
    !rules.is_empty() && rules.iter().all(|r| groups.iter().any(|g| g.group == r.group && g.share_dt >= r.share))
}

/// The damage that counts as cracked (d_t, d_c above it).
pub const CRACKED: f64 = 0.5;
/// The damage that counts as begun.
pub const ONSET: f64 = 0.05;

/// Damage of one substructure.
#[derive(Clone, Debug, Default, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct GroupDamage {
    /// The physical group.
    pub group: String,
    /// Its shell area [m²].
    pub area: f64,
    /// Share of the area with peak d_t > [`ONSET`] = 0.05: cracking has begun.
    pub share_dt_onset: f64,
    /// Share of the area with peak d_t > [`CRACKED`] = 0.5: more than half the tensile stiffness
    /// lost (the sweep's limits and the convergence band use this share).
    pub share_dt: f64,
    /// Share of the area with peak d_c > [`CRACKED`] = 0.5.
    pub share_dc: f64,
    /// Largest d_t.
    pub max_dt: f64,
    /// Energy dissipated by damage in its shells up to the committed state [J] (the module docs).
    #[serde(default)]
    pub dissipated: f64,
    /// The convergence band of `share_dt` (`[dynamics] convergence`), where one applies.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub share_dt_band: Option<f64>,
}

/// Area of a flat triangle or quad with corners `p`.
fn polygon_area(p: &[[f64; 3]]) -> f64 {
    let tri = |a: [f64; 3], b: [f64; 3], c: [f64; 3]| {
        let u = [b[0] - a[0], b[1] - a[1], b[2] - a[2]];
        let v = [c[0] - a[0], c[1] - a[1], c[2] - a[2]];
        let n = [u[1] * v[2] - u[2] * v[1], u[2] * v[0] - u[0] * v[2], u[0] * v[1] - u[1] * v[0]];
        0.5 * (n[0] * n[0] + n[1] * n[1] + n[2] * n[2]).sqrt()
    };
    match p.len() {
        3 => tri(p[0], p[1], p[2]),
        4 => tri(p[0], p[1], p[2]) + tri(p[0], p[2], p[3]),
        _ => 0.0,
    }
}

/// Collective. The damage of every group of shell parts (in the job's part order, each group
/// once), from the envelopes of the owned cells.
pub fn by_group(
    ctx: &Context,
    disc: &Discretization,
    env: &Envelopes,
    mesh: &Mesh,
    model: &StructuralModel,
    job: &Job,
) -> Vec<GroupDamage> {
    let mut groups: Vec<String> = Vec::new();
    for p in &job.spec.parts {
        if !groups.contains(&p.group) {
            groups.push(p.group.clone());
        }
    }
    let n = groups.len();
    // Per group: area, area with d_t > onset, d_t > cracked, d_c > cracked, dissipated energy
    // (sums); max d_t.
    let mut sums = vec![0.0; 5 * n];
    let mut max = vec![0.0f64; n];
    for (i, &c) in disc.local_cells.iter().enumerate() {
        let mc = &model.cells[c];
        let cell = &mesh.cells[mc.cell];
        if !matches!(cell.kind, CellKind::Tri3 | CellKind::Quad4) {
            continue;
        }
        let Some(g) = groups.iter().position(|g| *g == job.spec.parts[mc.part].group) else { continue };
        let corners: Vec<[f64; 3]> = cell.nodes.iter().map(|&k| mesh.coords[k]).collect();
        let a = polygon_area(&corners);
        let (dt, dc) = (env.cell[CELL_VALUES * i], env.cell[CELL_VALUES * i + 1]);
        sums[5 * g] += a;
        if dt > ONSET {
            sums[5 * g + 1] += a;
        }
        if dt > CRACKED {
            sums[5 * g + 2] += a;
        }
        if dc > CRACKED {
            sums[5 * g + 3] += a;
        }
        sums[5 * g + 4] += disc.elements[i].dissipated_energy();
        if dt.is_finite() {
            max[g] = max[g].max(dt);
        }
    }
    let mut total = vec![0.0; 5 * n];
    ctx.comm.all_reduce_into(&sums[..], &mut total[..], SystemOperation::sum());
    let mut peak = vec![0.0; n];
    ctx.comm.all_reduce_into(&max[..], &mut peak[..], SystemOperation::max());
    groups
        .into_iter()
        .enumerate()
        .filter(|&(g, _)| total[5 * g] > 0.0)
        .map(|(g, group)| {
            let area = total[5 * g];
            GroupDamage {
                group,
                area,
                share_dt_onset: total[5 * g + 1] / area,
                share_dt: total[5 * g + 2] / area,
                share_dc: total[5 * g + 3] / area,
                max_dt: peak[g],
                dissipated: total[5 * g + 4],
                share_dt_band: None,
            }
        })
        .collect()
}

/// The report of `[dynamics] convergence` for this job, and each group's band of `share_dt`
/// where it applies (`config::convergence`).
pub fn with_band(job: &Job, groups: &mut [GroupDamage]) -> Option<crate::config::BandReport> {
    let d = job.spec.dynamics.as_ref()?;
    let band = d.convergence_band.as_ref()?;
    let name = |p: &std::path::Path| p.file_name().map(|n| n.to_string_lossy().into_owned()).unwrap_or_default();
    let law_files = job
        .spec
        .materials
        .values()
        .filter_map(|m| match m {
            crate::config::MaterialConfig::Damage(c) => c.law_file.as_deref().map(name),
            _ => None,
        })
        .collect();
    let run = crate::config::BandSettings {
        dt: d.dt,
        mesh: name(&job.mesh_file),
        law_files,
        max_damage_increment: d.max_damage_increment,
        integration: d.integration.name().to_string(),
        implex_corrections: d.implex_corrections,
    };
    let pga = d.ground_motion.iter().filter_map(|g| g.record.as_ref()).map(crate::seismic::pga).fold(0.0, f64::max);
    let report = band.report(&run, pga);
    for g in groups.iter_mut() {
        g.share_dt_band = band.group_band(&report, &g.group);
    }
    Some(report)
}

/// The log line of a band report.
pub fn band_line(r: &crate::config::BandReport) -> String {
    match &r.loading {
        Some(l) => format!(
            "convergence band: {} (loading {l}, measured at PGA {:.3} m/s^2 >= this run's {:.3}): shares of d_t > 0.5 \
             in summary.json (damage_by_group, share_dt_band)",
            r.file,
            r.measured_pga.unwrap_or(f64::NAN),
            r.run_pga
        ),
        None => format!("convergence band of {}: does not apply ({})", r.file, r.not_applicable.join("; ")),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Areas by hand: the unit right triangle 1/2, a 2 × 3 rectangle 6 (tilted out of plane,
    /// still 6).
    #[test]
    fn areas_of_flat_cells() {
        assert!((polygon_area(&[[0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0]]) - 0.5).abs() < 1e-15);
        let s = 1.0 / 2f64.sqrt();
        let q = [[0.0, 0.0, 0.0], [2.0, 0.0, 0.0], [2.0, 3.0 * s, 3.0 * s], [0.0, 3.0 * s, 3.0 * s]];
        assert!((polygon_area(&q) - 6.0).abs() < 1e-12);
    }
}
