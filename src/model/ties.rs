//! Ties against the mesh and the supports: their lengths, their ends held by a shell, a beam or
//! supports, the anchors that only ties reach, and the nodal loads of their pretensions.
use super::{ModelCell, ModelError};
use crate::config::{Job, SectionConfig, Seg};
use crate::element::{pretension_load, tie_axis, ElementError};
use crate::mesh::Mesh;

/// The message of a tie element that cannot be used: "tie element 1234 of group nave_ties: …".
fn tie_error(job: &Job, mesh: &Mesh, c: &ModelCell, what: String) -> ModelError {
    let part = &job.spec.parts[c.part];
    let at = [Seg::key("parts"), Seg::Index(c.part), Seg::key("group")];
    job.error_at(&at, format!("tie element {} of group {}: {what}", mesh.cells[c.cell].tag, part.group)).into()
}

/// Checks of the ties against the mesh and the supports: a non-zero length, and both ends
/// attached to a shell or beam (`structural`) or held by supports in ux uy uz (`fixed`). Returns
/// the anchors: the end nodes that only ties touch, ascending.
pub(super) fn check_ties(
    job: &Job,
    mesh: &Mesh,
    cells: &[ModelCell],
    is_tie: &[bool],
    structural: &[bool],
    fixed: &[u8],
) -> Result<Vec<usize>, ModelError> {
    const DOF: [&str; 3] = ["ux", "uy", "uz"];
    let mut anchors = Vec::new();
    for (c, _) in cells.iter().zip(is_tie).filter(|(_, &t)| t) {
        let nodes = &mesh.cells[c.cell].nodes;
        let (a, b) = (nodes[0], nodes[1]);
        match tie_axis(mesh.coords[a], mesh.coords[b]) {
            Ok(_) => {}
            Err(ElementError::ZeroLength { node1: [x, y, z], length, .. }) => {
                return Err(tie_error(
                    job,
                    mesh,
                    c,
                    format!(
                        "its end nodes {} and {} coincide at ({x:.2}, {y:.2}, {z:.2}) (length {length:e} m): a tie joins two distinct points",
                        mesh.node_tags[a], mesh.node_tags[b]
                    ),
                ))
            }
            Err(e) => return Err(tie_error(job, mesh, c, e.to_string())),
        }
        for n in [a, b] {
            if structural[n] {
                continue;
            }
            let [x, y, z] = mesh.coords[n];
            let node = format!("its end node {} at ({x:.2}, {y:.2}, {z:.2})", mesh.node_tags[n]);
            let free: Vec<&str> = (0..3).filter(|&d| fixed[n] & (1 << d) == 0).map(|d| DOF[d]).collect();
            if free.len() == 3 {
                return Err(tie_error(
                    job,
                    mesh,
                    c,
                    format!("{node} is attached to no shell or beam and to no support"),
                ));
            }
            if !free.is_empty() {
                return Err(tie_error(
                    job,
                    mesh,
                    c,
                    format!(
                        "{node} is attached to no shell or beam, and its supports leave {} free: a tie holds its end along its axis only, \
                         so a node that only ties reach must be supported in ux, uy and uz",
                        free.join(", ")
                    ),
                ));
            }
            anchors.push(n);
        }
    }
    anchors.sort_unstable();
    anchors.dedup();
    Ok(anchors)
}

/// `loads` (summed per node, node order) with the pretension loads of the ties added
/// (`element::pretension_load`: N₀ along the tie at both ends, pulling them together).
pub(super) fn add_pretension_loads(
    job: &Job,
    mesh: &Mesh,
    cells: &[ModelCell],
    loads: Vec<(usize, [f64; 6])>,
) -> Result<Vec<(usize, [f64; 6])>, ModelError> {
    let spec = &job.spec;
    let mut by_node: std::collections::BTreeMap<usize, [f64; 6]> = loads.into_iter().collect();
    for c in cells {
        let SectionConfig::Tie(t) = &spec.sections[&spec.parts[c.part].section] else { continue };
        if t.pretension == 0.0 {
            continue;
        }
        let nodes = &mesh.cells[c.cell].nodes;
        let f = pretension_load(mesh.coords[nodes[0]], mesh.coords[nodes[1]], t.pretension)
            .map_err(|e| tie_error(job, mesh, c, e.to_string()))?;
        for (k, &n) in nodes.iter().enumerate() {
            let load = by_node.entry(n).or_insert([0.0; 6]);
            for d in 0..3 {
                load[d] += f[k][d];
            }
        }
    }
    Ok(by_node.into_iter().collect())
}
