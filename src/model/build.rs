//! Resolving a job's parts, supports and loads against the mesh.
use crate::config::{Job, LoadConfig, NodalLoadConfig, Seg, SectionConfig};
use crate::mesh::{CellKind, Mesh};

/// A mesh cell that is a structural element.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct ModelCell {
    /// Index into `Mesh::cells`.
    pub cell: usize,
    /// Index into the job's `parts`.
    pub part: usize,
}

/// Errors relating the job to its mesh; each names the job-file key.
#[derive(Debug, thiserror::Error)]
pub enum ModelError {
    /// A problem with a key of the job file, found against the mesh.
    #[error(transparent)]
    Config(#[from] crate::config::ConfigError),
}

/// The model: structural cells, fixed DOFs and nodal loads, over the whole mesh.
#[derive(Clone, Debug)]
pub struct StructuralModel {
    /// The structural cells, in mesh order.
    pub cells: Vec<ModelCell>,
    /// Fixed-DOF bit mask per mesh node (bit d: DOF d of ux uy uz rx ry rz).
    pub fixed: Vec<u8>,
    /// Nodal loads `(mesh node, [Fx Fy Fz Mx My Mz])`, summed per node, in node order.
    pub nodal_loads: Vec<(usize, [f64; 6])>,
    /// Gravitational acceleration, if self-weight is on.
    pub gravity: Option<[f64; 3]>,
}

fn key(k: &str) -> Seg {
    Seg::Key(k.to_string())
}

impl StructuralModel {
    /// Resolves the job against the mesh.
    pub fn build(job: &Job, mesh: &Mesh) -> Result<StructuralModel, ModelError> {
        let spec = &job.spec;
        let mut part_of = vec![usize::MAX; mesh.cells.len()];
        for (ip, p) in spec.parts.iter().enumerate() {
            let at = [key("parts"), Seg::Index(ip), key("group")];
            let g = mesh.group(&p.group).map_err(|e| job.error_at(&at, e.to_string()))?;
            let want: &[CellKind] = match &spec.sections[&p.section] {
                SectionConfig::Frame(_) => &[CellKind::Line2],
                SectionConfig::Shell(_) => &[CellKind::Tri3, CellKind::Quad4],
            };
            let want_text = want.iter().map(|k| k.to_string()).collect::<Vec<_>>().join(" or ");
            let mut n = 0;
            for c in mesh.cells_in_group(g) {
                let kind = mesh.cells[c].kind;
                if !want.contains(&kind) {
                    return Err(job
                        .error_at(
                            &at,
                            format!(
                                "group '{}' holds a {kind} (element {}), but section '{}' of type '{}' \
                                 needs {want_text} cells",
                                p.group,
                                mesh.cells[c].tag,
                                p.section,
                                spec.sections[&p.section].type_name()
                            ),
                        )
                        .into());
                }
                if part_of[c] != usize::MAX {
                    let other = &spec.parts[part_of[c]].group;
                    return Err(job
                        .error_at(
                            &at,
                            format!(
                                "element {} of group '{}' is already modelled by part {} (group '{other}'): \
                                 a cell belongs to one part only",
                                mesh.cells[c].tag, p.group, part_of[c]
                            ),
                        )
                        .into());
                }
                part_of[c] = ip;
                n += 1;
            }
            if n == 0 {
                return Err(job
                    .error_at(&at, format!("group '{}' has no cells of dimension {}", p.group, want[0].dim()))
                    .into());
            }
        }
        let cells: Vec<ModelCell> = part_of
            .iter()
            .enumerate()
            .filter(|(_, &p)| p != usize::MAX)
            .map(|(cell, &part)| ModelCell { cell, part })
            .collect();
        let mut active = vec![false; mesh.coords.len()];
        for c in &cells {
            for &n in &mesh.cells[c.cell].nodes {
                active[n] = true;
            }
        }

        let group_nodes = |at: &[Seg], name: &str| -> Result<Vec<usize>, ModelError> {
            let g = mesh.group(name).map_err(|e| job.error_at(at, e.to_string()))?;
            let nodes = mesh.nodes_in_group(g);
            if let Some(&n) = nodes.iter().find(|&&n| !active[n]) {
                return Err(job
                    .error_at(
                        at,
                        format!(
                            "node {} of group '{name}' belongs to no element of the model's parts",
                            mesh.node_tags[n]
                        ),
                    )
                    .into());
            }
            if nodes.is_empty() {
                return Err(job.error_at(at, format!("group '{name}' has no nodes")).into());
            }
            Ok(nodes)
        };

        let mut fixed = vec![0u8; mesh.coords.len()];
        for (i, s) in spec.supports.iter().enumerate() {
            let at = [key("supports"), Seg::Index(i), key("group")];
            let mut mask = 0u8;
            for d in &s.dofs {
                for k in d.indices() {
                    mask |= 1 << k;
                }
            }
            for n in group_nodes(&at, &s.group)? {
                fixed[n] |= mask;
            }
        }

        let mut load = vec![[0.0f64; 6]; mesh.coords.len()];
        let mut loaded = vec![false; mesh.coords.len()];
        for (i, l) in spec.loads.iter().enumerate() {
            let LoadConfig::Nodal(NodalLoadConfig { group, force, moment }) = l;
            let at = [key("loads"), Seg::Index(i), key("group")];
            for n in group_nodes(&at, group)? {
                for k in 0..3 {
                    load[n][k] += force[k];
                    load[n][3 + k] += moment[k];
                }
                loaded[n] = true;
            }
        }
        let nodal_loads = (0..mesh.coords.len()).filter(|&n| loaded[n]).map(|n| (n, load[n])).collect();
        Ok(StructuralModel { cells, fixed, nodal_loads, gravity: spec.gravity.as_ref().map(|g| g.acceleration) })
    }

    /// The node lists of the structural cells, in model order.
    pub fn cell_nodes<'m>(&self, mesh: &'m Mesh) -> Vec<&'m [usize]> {
        self.cells.iter().map(|c| mesh.cells[c.cell].nodes.as_slice()).collect()
    }
}
