//! Resolving a job's parts, supports and loads against the mesh.
use crate::config::{AnalysisConfig, Job, LoadConfig, NodalLoadConfig, SectionConfig, Seg};
use crate::element::{pretension_load, tie_axis, ElementError};
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
    /// Fixed-DOF bit mask per mesh node (bit d: DOF d of ux uy uz rx ry rz): the supports, the
    /// rotations of the anchors, and the imposed DOFs of a displacement control without a pattern.
    pub fixed: Vec<u8>,
    /// Nodal loads `(mesh node, [Fx Fy Fz Mx My Mz])`, summed per node, in node order: the
    /// job's `[[loads]]` and the equivalent loads of tie pretensions, N₀ along each tie at both
    /// ends, pulling them together (`element::tie`: the static load every driver scales).
    pub nodal_loads: Vec<(usize, [f64; 6])>,
    /// Gravitational acceleration, if self-weight is on.
    pub gravity: Option<[f64; 3]>,
    /// Point masses `(mesh node, [m, m, m, Ix, Iy, Iz])` (kg, kg m² about the global axes),
    /// summed per node, in node order: the diagonal of the node's 6×6 mass block.
    pub point_masses: Vec<(usize, [f64; 6])>,
    /// Displacement control of a nonlinear static analysis, if any.
    pub control: Option<ControlSpec>,
    /// Per model cell: whether it is a tie (axial force only: it does not make its two nodes
    /// one rigid piece, see [`StructuralModel::find_mechanisms`]).
    pub is_tie: Vec<bool>,
    /// Anchors: the nodes (mesh indices, ascending) that only ties touch. Their supports hold
    /// ux uy uz (checked) and their rotations, which no element stiffens, are fixed here.
    pub anchors: Vec<usize>,
}

impl StructuralModel {
    /// Resolves the job against the mesh.
    pub fn build(job: &Job, mesh: &Mesh) -> Result<StructuralModel, ModelError> {
        let spec = &job.spec;
        let mut part_of = vec![usize::MAX; mesh.cells.len()];
        let tie_part: Vec<bool> =
            spec.parts.iter().map(|p| matches!(spec.sections[&p.section], SectionConfig::Tie(_))).collect();
        for (ip, p) in spec.parts.iter().enumerate() {
            let at = [Seg::key("parts"), Seg::Index(ip), Seg::key("group")];
            let g = mesh.group(&p.group).map_err(|e| job.error_at(&at, e.to_string()))?;
            let want: &[CellKind] = match &spec.sections[&p.section] {
                SectionConfig::Frame(_) | SectionConfig::Fiber(_) | SectionConfig::Tie(_) => &[CellKind::Line2],
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
        let is_tie: Vec<bool> = cells.iter().map(|c| tie_part[c.part]).collect();
        let mut active = vec![false; mesh.coords.len()];
        // Nodes of a shell or beam: those whose rotations and transverse translations have stiffness.
        let mut structural = vec![false; mesh.coords.len()];
        for (c, &tie) in cells.iter().zip(&is_tie) {
            for &n in &mesh.cells[c.cell].nodes {
                active[n] = true;
                structural[n] |= !tie;
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
            let at = [Seg::key("supports"), Seg::Index(i), Seg::key("group")];
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

        let anchors = check_ties(job, mesh, &cells, &is_tie, &structural, &fixed)?;
        for &n in &anchors {
            fixed[n] |= 0b111000;
        }

        let sum_loads = |prefix: &[Seg],
                         loads: &mut dyn Iterator<Item = &NodalLoadConfig>|
         -> Result<Vec<(usize, [f64; 6])>, ModelError> {
            let mut load = vec![[0.0f64; 6]; mesh.coords.len()];
            let mut loaded = vec![false; mesh.coords.len()];
            for (i, NodalLoadConfig { group, force, moment }) in loads.enumerate() {
                let mut at = prefix.to_vec();
                at.extend([Seg::Index(i), Seg::key("group")]);
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
        let nodal_loads = sum_loads(
            &[Seg::key("loads")],
            &mut spec.loads.iter().map(|l| match l {
                LoadConfig::Nodal(n) => n,
            }),
        )?;
        let nodal_loads = add_pretension_loads(job, mesh, &cells, nodal_loads)?;

        let mut masses = vec![[0.0f64; 6]; mesh.coords.len()];
        let mut massive = vec![false; mesh.coords.len()];
        for (i, m) in spec.masses.iter().enumerate() {
            let nodes = match (&m.group, m.node) {
                (Some(group), _) => group_nodes(&[Seg::key("masses"), Seg::Index(i), Seg::key("group")], group)?,
                (None, Some(tag)) => {
                    let at = [Seg::key("masses"), Seg::Index(i), Seg::key("node")];
                    let n = mesh
                        .node_tags
                        .iter()
                        .position(|&t| t == tag)
                        .ok_or_else(|| job.error_at(&at, format!("the mesh has no node with tag {tag}")))?;
                    if !active[n] {
                        return Err(job
                            .error_at(&at, format!("node {tag} belongs to no element of the model's parts"))
                            .into());
                    }
                    vec![n]
                }
                // Rejected by validation; kept as an error, not a panic.
                (None, None) => {
                    return Err(job
                        .error_at(&[Seg::key("masses"), Seg::Index(i)], "a point mass needs a group or a node")
                        .into())
                }
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
                    let base = [Seg::key("analysis"), Seg::key("control")];
                    let nodes = match (&ctl.group, ctl.node) {
                        (Some(group), _) => {
                            group_nodes(&[Seg::key("analysis"), Seg::key("control"), Seg::key("group")], group)?
                        }
                        (None, Some(tag)) => {
                            let at = [Seg::key("analysis"), Seg::key("control"), Seg::key("node")];
                            let n = mesh
                                .node_tags
                                .iter()
                                .position(|&t| t == tag)
                                .ok_or_else(|| job.error_at(&at, format!("the mesh has no node with tag {tag}")))?;
                            if !active[n] {
                                return Err(job
                                    .error_at(&at, format!("node {tag} belongs to no element of the model's parts"))
                                    .into());
                            }
                            vec![n]
                        }
                        (None, None) => return Err(job.error_at(&base, "the control needs a group or a node").into()),
                    };
                    let dof = ctl.dof.indices().start;
                    let pattern = sum_loads(
                        &[Seg::key("analysis"), Seg::key("control"), Seg::key("pattern")],
                        &mut ctl.pattern.iter(),
                    )?;
                    if !pattern.is_empty() && nodes.len() != 1 {
                        return Err(job
                            .error_at(&base, format!("with a load pattern the control is one node; the group has {} nodes (use node = <tag>)", nodes.len()))
                            .into());
                    }
                    if let Some(&n) = nodes.iter().find(|&&n| fixed[n] & (1 << dof) != 0) {
                        return Err(job
                            .error_at(
                                &[Seg::key("analysis"), Seg::key("control"), Seg::key("dof")],
                                format!(
                                    "DOF {:?} of control node {} is fixed by a support",
                                    ctl.dof, mesh.node_tags[n]
                                ),
                            )
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
            is_tie,
            anchors,
        })
    }

    /// The node lists of the structural cells, in model order.
    pub fn cell_nodes<'m>(&self, mesh: &'m Mesh) -> Vec<&'m [usize]> {
        self.cells.iter().map(|c| mesh.cells[c.cell].nodes.as_slice()).collect()
    }

    /// The mesh's curve and surface groups whose cells the model leaves out: no part models any
    /// of them and no support, load or point mass names the group. (name, cells), in file order.
    /// A group added to a mesh and forgotten in its jobs is such a hole in the structure.
    pub fn unmodelled_groups(&self, job: &Job, mesh: &Mesh) -> Vec<(String, usize)> {
        let spec = &job.spec;
        let mut named: Vec<&str> = spec.supports.iter().map(|s| s.group.as_str()).collect();
        named.extend(spec.loads.iter().map(|l| match l {
            LoadConfig::Nodal(NodalLoadConfig { group, .. }) => group.as_str(),
        }));
        named.extend(spec.masses.iter().filter_map(|m| m.group.as_deref()));
        let mut modelled = vec![false; mesh.cells.len()];
        for c in &self.cells {
            modelled[c.cell] = true;
        }
        mesh.groups
            .iter()
            .filter(|g| (g.dim == 1 || g.dim == 2) && !named.contains(&g.name.as_str()))
            .filter_map(|g| {
                let cells: Vec<usize> = mesh.cells_in_group(g).collect();
                let name = if g.name.is_empty() { format!("#{}", g.tag) } else { g.name.clone() };
                (!cells.is_empty() && cells.iter().all(|&c| !modelled[c])).then_some((name, cells.len()))
            })
            .collect()
    }
}

/// The message of a tie element that cannot be used: "tie element 1234 of group nave_ties: …".
fn tie_error(job: &Job, mesh: &Mesh, c: &ModelCell, what: String) -> ModelError {
    let part = &job.spec.parts[c.part];
    let at = [Seg::key("parts"), Seg::Index(c.part), Seg::key("group")];
    job.error_at(&at, format!("tie element {} of group {}: {what}", mesh.cells[c.cell].tag, part.group)).into()
}

/// Checks of the ties against the mesh and the supports: a non-zero length, and both ends
/// attached to a shell or beam (`structural`) or held by supports in ux uy uz (`fixed`). Returns
/// the anchors: the end nodes that only ties touch, ascending.
fn check_ties(
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
fn add_pretension_loads(
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
