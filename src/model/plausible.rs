//! The warning of implausible input that needs the mesh (`config::plausible` has the others): a
//! shell thickness larger than the elements it is given to. A flat shell's thickness is at most
//! about its elements' size (thick masonry walls are meshed with elements of about their
//! thickness: the church's 0.9 m nave walls with a median longest edge of 0.8 m); one over twice
//! the part's typical element, the median of its elements' longest edges, is most often a
//! thickness typed in centimetres. Not always: a wall loaded only in its plane, meshed finely for
//! its cracks (jobs/wall-shear-fe.toml, 0.5 m on 5 cm elements), is a sound model that warns.
use super::StructuralModel;
use crate::config::{Job, SectionConfig, Seg};
use crate::mesh::Mesh;

/// The thickness over the part's median longest edge above which a shell part is warned.
pub const THICKNESS_OVER_ELEMENT: f64 = 2.0;

/// One warning per shell part whose section's thickness is over [`THICKNESS_OVER_ELEMENT`] times
/// the median longest edge of the part's elements, located at the section's `thickness`.
pub fn thickness_warnings(job: &Job, mesh: &Mesh, model: &StructuralModel) -> Vec<String> {
    let mut out = Vec::new();
    for (p, part) in job.spec.parts.iter().enumerate() {
        let Some(SectionConfig::Shell(sh)) = job.spec.sections.get(&part.section) else { continue };
        let mut edges: Vec<f64> =
            model.cells.iter().filter(|c| c.part == p).map(|c| longest_edge(mesh, &mesh.cells[c.cell].nodes)).collect();
        if edges.is_empty() {
            continue;
        }
        edges.sort_by(f64::total_cmp);
        let median = edges[edges.len() / 2];
        if sh.thickness <= THICKNESS_OVER_ELEMENT * median {
            continue;
        }
        let at = Seg::path(&["sections", part.section.as_str(), "thickness"]);
        out.push(
            job.error_at(
                &at,
                format!(
                    "thickness = {} m is over {THICKNESS_OVER_ELEMENT} times the elements of group '{}' (their longest edges: median {median:.3} m, {:.3}–{:.3} m over {} elements): a value in cm? (a wall loaded only in its plane may be meshed finer than its thickness)",
                    sh.thickness,
                    part.group,
                    edges[0],
                    edges[edges.len() - 1],
                    edges.len()
                ),
            )
            .to_string(),
        );
    }
    out
}

/// The longest edge of a cell given by its corner nodes in order [m].
fn longest_edge(mesh: &Mesh, nodes: &[usize]) -> f64 {
    let n = nodes.len();
    (0..n)
        .map(|k| {
            let (a, b) = (mesh.coords[nodes[k]], mesh.coords[nodes[(k + 1) % n]]);
            ((a[0] - b[0]).powi(2) + (a[1] - b[1]).powi(2) + (a[2] - b[2]).powi(2)).sqrt()
        })
        .fold(0.0, f64::max)
}
