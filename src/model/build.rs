//! Resolving a job's parts, supports and loads against the mesh.
use crate::config::{AnalysisConfig, Job, LoadConfig, NodalLoadConfig, Seg, SectionConfig};
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

/// Displacement control of a nonlinear static analysis, resolved against the mesh
/// (`[analysis.control]`).
#[derive(Clone, Debug, PartialEq)]
pub struct ControlSpec {
    /// The control nodes (mesh indices): imposed without a pattern; exactly one with a pattern.
    pub nodes: Vec<usize>,
    /// The controlled DOF (0..6: ux uy uz rx ry rz).
    pub dof: usize,
    /// Value added to the DOF over the control stage.
    pub target: f64,
    /// Increments.
    pub steps: usize,
    /// Pattern loads `(mesh node, [Fx Fy Fz Mx My Mz])` summed per node; empty: imposed DOFs.
    pub pattern: Vec<(usize, [f64; 6])>,
}

/// The model: structural cells, fixed DOFs and nodal loads, over the whole mesh.
#[derive(Clone, Debug)]
pub struct StructuralModel {
    /// The structural cells, in mesh order.
    pub cells: Vec<ModelCell>,
    /// Fixed-DOF bit mask per mesh node (bit d: DOF d of ux uy uz rx ry rz): the supports, and
    /// the imposed DOFs of a displacement control without a pattern.
    pub fixed: Vec<u8>,
    /// Nodal loads `(mesh node, [Fx Fy Fz Mx My Mz])`, summed per node, in node order.
    pub nodal_loads: Vec<(usize, [f64; 6])>,
    /// Gravitational acceleration, if self-weight is on.
    pub gravity: Option<[f64; 3]>,
    /// Point masses `(mesh node, [m, m, m, Ix, Iy, Iz])` (kg, kg m² about the global axes),
    /// summed per node, in node order: the diagonal of the node's 6×6 mass block.
    pub point_masses: Vec<(usize, [f64; 6])>,
    /// Displacement control of a nonlinear static analysis, if any.
    pub control: Option<ControlSpec>,
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
                SectionConfig::Frame(_) | SectionConfig::Fiber(_) => &[CellKind::Line2],
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

        let sum_loads = |prefix: &[Seg], loads: &mut dyn Iterator<Item = &NodalLoadConfig>| -> Result<Vec<(usize, [f64; 6])>, ModelError> {
            let mut load = vec![[0.0f64; 6]; mesh.coords.len()];
            let mut loaded = vec![false; mesh.coords.len()];
            for (i, NodalLoadConfig { group, force, moment }) in loads.enumerate() {
                let mut at = prefix.to_vec();
                at.extend([Seg::Index(i), key("group")]);
                for n in group_nodes(&at, group)? {
                    for k in 0..3 {
                        load[n][k] += force[k];
                        load[n][3 + k] += moment[k];
                    }
                    loaded[n] = true;
                }
            }
            Ok((0..mesh.coords.len()).filter(|&n| loaded[n]).map(|n| (n, load[n])).collect())
        };
        let nodal_loads = sum_loads(&[key("loads")], &mut spec.loads.iter().map(|l| match l {
            LoadConfig::Nodal(n) => n,
        }))?;

        let mut masses = vec![[0.0f64; 6]; mesh.coords.len()];
        let mut massive = vec![false; mesh.coords.len()];
        for (i, m) in spec.masses.iter().enumerate() {
            let nodes = match (&m.group, m.node) {
                (Some(group), _) => group_nodes(&[key("masses"), Seg::Index(i), key("group")], group)?,
                (None, Some(tag)) => {
                    let at = [key("masses"), Seg::Index(i), key("node")];
                    let n = mesh.node_tags.iter().position(|&t| t == tag).ok_or_else(|| {
                        job.error_at(&at, format!("the mesh has no node with tag {tag}"))
                    })?;
                    if !active[n] {
                        return Err(job.error_at(&at, format!("node {tag} belongs to no element of the model's parts")).into());
                    }
                    vec![n]
                }
                // Rejected by validation; kept as an error, not a panic.
                (None, None) => return Err(job.error_at(&[key("masses"), Seg::Index(i)], "a point mass needs a group or a node").into()),
            };
            for n in nodes {
                for k in 0..3 {
                    masses[n][k] += m.mass;
                    masses[n][3 + k] += m.rotary_inertia[k];
                }
                massive[n] = true;
            }
        }
        let point_masses = (0..mesh.coords.len()).filter(|&n| massive[n]).map(|n| (n, masses[n])).collect();

        let control = match &spec.analysis {
            AnalysisConfig::StaticNonlinear(c) => match &c.control {
                Some(ctl) => {
                    let base = [key("analysis"), key("control")];
                    let nodes = match (&ctl.group, ctl.node) {
                        (Some(group), _) => group_nodes(&[key("analysis"), key("control"), key("group")], group)?,
                        (None, Some(tag)) => {
                            let at = [key("analysis"), key("control"), key("node")];
                            let n = mesh.node_tags.iter().position(|&t| t == tag).ok_or_else(|| job.error_at(&at, format!("the mesh has no node with tag {tag}")))?;
                            if !active[n] {
                                return Err(job.error_at(&at, format!("node {tag} belongs to no element of the model's parts")).into());
                            }
                            vec![n]
                        }
                        (None, None) => return Err(job.error_at(&base, "the control needs a group or a node").into()),
                    };
                    let dof = ctl.dof.indices().start;
                    let pattern = sum_loads(&[key("analysis"), key("control"), key("pattern")], &mut ctl.pattern.iter())?;
                    if !pattern.is_empty() && nodes.len() != 1 {
                        return Err(job
                            .error_at(&base, format!("with a load pattern the control is one node; the group has {} nodes (use node = <tag>)", nodes.len()))
                            .into());
                    }
                    if let Some(&n) = nodes.iter().find(|&&n| fixed[n] & (1 << dof) != 0) {
                        return Err(job
                            .error_at(&[key("analysis"), key("control"), key("dof")], format!("DOF {:?} of control node {} is fixed by a support", ctl.dof, mesh.node_tags[n]))
                            .into());
                    }
                    Some(ControlSpec { nodes, dof, target: ctl.target, steps: ctl.steps, pattern })
                }
                None => None,
            },
            _ => None,
        };
        // Imposed control DOFs are supports that move: fixed in the DOF numbering.
        if let Some(c) = control.as_ref().filter(|c| c.pattern.is_empty()) {
            for &n in &c.nodes {
                fixed[n] |= 1 << c.dof;
            }
        }
        Ok(StructuralModel {
            cells,
            fixed,
            nodal_loads,
            gravity: spec.gravity.as_ref().map(|g| g.acceleration),
            point_masses,
            control,
        })
    }

    /// The node lists of the structural cells, in model order.
    pub fn cell_nodes<'m>(&self, mesh: &'m Mesh) -> Vec<&'m [usize]> {
        self.cells.iter().map(|c| mesh.cells[c.cell].nodes.as_slice()).collect()
    }
}
