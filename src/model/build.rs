//! Resolving a job's parts, supports and loads against the mesh.
use super::ties::{add_pretension_loads, check_ties};
use crate::config::{AnalysisConfig, Job, LoadConfig, NodalLoadConfig, SectionConfig, Seg};
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
    /// Resolves the job against the mesh, in steps: the parts' cells, the nodes they reach, the
    /// supports and the ties' anchors, the nodal loads, the point masses, the displacement control.
    pub fn build(job: &Job, mesh: &Mesh) -> Result<StructuralModel, ModelError> {
        let spec = &job.spec;
        let cells = part_cells(job, mesh)?;
        let tie_part: Vec<bool> =
            spec.parts.iter().map(|p| matches!(spec.sections[&p.section], SectionConfig::Tie(_))).collect();
        let is_tie: Vec<bool> = cells.iter().map(|c| tie_part[c.part]).collect();
        let (active, structural) = node_roles(mesh, &cells, &is_tie);
        let nodes = NodeLookup { job, mesh, active: &active };

        let mut fixed = nodes.supported_dofs()?;
        let anchors = check_ties(job, mesh, &cells, &is_tie, &structural, &fixed)?;
        for &n in &anchors {
            fixed[n] |= 0b111000;
        }
        let job_loads = spec.loads.iter().map(|l| match l {
            LoadConfig::Nodal(n) => n,
        });
        let nodal_loads = nodes.sum_loads(&[Seg::key("loads")], job_loads)?;
        let nodal_loads = add_pretension_loads(job, mesh, &cells, nodal_loads)?;
        let point_masses = nodes.point_masses()?;
        let control = nodes.control(&fixed)?;
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

/// The structural cells, in mesh order: each part's group holds cells of the kind its section
/// needs (lines for beams and ties, triangles and quadrangles for shells), at least one, and a
/// cell belongs to one part only.
fn part_cells(job: &Job, mesh: &Mesh) -> Result<Vec<ModelCell>, ModelError> {
    let spec = &job.spec;
    let mut part_of = vec![usize::MAX; mesh.cells.len()];
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
    Ok(part_of
        .iter()
        .enumerate()
        .filter(|(_, &p)| p != usize::MAX)
        .map(|(cell, &part)| ModelCell { cell, part })
        .collect())
}

/// Per mesh node: whether a model cell reaches it (`active`), and whether a shell or beam does
/// (`structural`: its rotations and transverse translations have stiffness).
fn node_roles(mesh: &Mesh, cells: &[ModelCell], is_tie: &[bool]) -> (Vec<bool>, Vec<bool>) {
    let mut active = vec![false; mesh.coords.len()];
    let mut structural = vec![false; mesh.coords.len()];
    for (c, &tie) in cells.iter().zip(is_tie) {
        for &n in &mesh.cells[c.cell].nodes {
            active[n] = true;
            structural[n] |= !tie;
        }
    }
    (active, structural)
}

/// The job's groups and node tags resolved to mesh nodes that the model's cells reach; every
/// error names the job-file key at hand.
struct NodeLookup<'a> {
    job: &'a Job,
    mesh: &'a Mesh,
    /// Per mesh node: whether a model cell reaches it.
    active: &'a [bool],
}

impl NodeLookup<'_> {
    /// The nodes of group `name` (named at `at`): at least one, each reached by the model.
    fn group_nodes(&self, at: &[Seg], name: &str) -> Result<Vec<usize>, ModelError> {
        let (job, mesh) = (self.job, self.mesh);
        let g = mesh.group(name).map_err(|e| job.error_at(at, e.to_string()))?;
        let nodes = mesh.nodes_in_group(g);
        if let Some(&n) = nodes.iter().find(|&&n| !self.active[n]) {
            return Err(job
                .error_at(
                    at,
                    format!("node {} of group '{name}' belongs to no element of the model's parts", mesh.node_tags[n]),
                )
                .into());
        }
        if nodes.is_empty() {
            return Err(job.error_at(at, format!("group '{name}' has no nodes")).into());
        }
        Ok(nodes)
    }

    /// The node of Gmsh tag `tag` (named at `at`), reached by the model.
    fn tagged_node(&self, at: &[Seg], tag: u64) -> Result<usize, ModelError> {
        let job = self.job;
        let n = self
            .mesh
            .node_tags
            .iter()
            .position(|&t| t == tag)
            .ok_or_else(|| job.error_at(at, format!("the mesh has no node with tag {tag}")))?;
        if !self.active[n] {
            return Err(job.error_at(at, format!("node {tag} belongs to no element of the model's parts")).into());
        }
        Ok(n)
    }

    /// The nodes of the table at `base` that names a `group` (which wins) or a `node`; `what`
    /// names the table in the error when it names neither.
    fn group_or_node(
        &self,
        base: &[Seg],
        group: Option<&str>,
        node: Option<u64>,
        what: &str,
    ) -> Result<Vec<usize>, ModelError> {
        let at = |k: &str| [base, &[Seg::key(k)]].concat();
        match (group, node) {
            (Some(group), _) => self.group_nodes(&at("group"), group),
            (None, Some(tag)) => Ok(vec![self.tagged_node(&at("node"), tag)?]),
            // Rejected by validation; kept as an error, not a panic.
            (None, None) => Err(self.job.error_at(base, format!("{what} needs a group or a node")).into()),
        }
    }

    /// Fixed-DOF bit mask per mesh node from the `[[supports]]`.
    fn supported_dofs(&self) -> Result<Vec<u8>, ModelError> {
        let mut fixed = vec![0u8; self.mesh.coords.len()];
        for (i, s) in self.job.spec.supports.iter().enumerate() {
            let at = [Seg::key("supports"), Seg::Index(i), Seg::key("group")];
            let mask = s.dofs.iter().flat_map(|d| d.indices()).fold(0u8, |m, k| m | (1 << k));
            for n in self.group_nodes(&at, &s.group)? {
                fixed[n] |= mask;
            }
        }
        Ok(fixed)
    }

    /// Nodal loads `(mesh node, [Fx Fy Fz Mx My Mz])` of the load tables listed under `prefix`,
    /// summed per node, in node order.
    fn sum_loads<'l>(
        &self,
        prefix: &[Seg],
        loads: impl Iterator<Item = &'l NodalLoadConfig>,
    ) -> Result<Vec<(usize, [f64; 6])>, ModelError> {
        let nn = self.mesh.coords.len();
        let mut load = vec![[0.0f64; 6]; nn];
        let mut loaded = vec![false; nn];
        for (i, NodalLoadConfig { group, force, moment }) in loads.enumerate() {
            let at = [prefix, &[Seg::Index(i), Seg::key("group")]].concat();
            for n in self.group_nodes(&at, group)? {
                for k in 0..3 {
                    load[n][k] += force[k];
                    load[n][3 + k] += moment[k];
                }
                loaded[n] = true;
            }
        }
        Ok((0..nn).filter(|&n| loaded[n]).map(|n| (n, load[n])).collect())
    }

    /// Point masses `(mesh node, [m, m, m, Ix, Iy, Iz])` of the `[[masses]]`, summed per node, in
    /// node order.
    fn point_masses(&self) -> Result<Vec<(usize, [f64; 6])>, ModelError> {
        let nn = self.mesh.coords.len();
        let mut masses = vec![[0.0f64; 6]; nn];
        let mut massive = vec![false; nn];
        for (i, m) in self.job.spec.masses.iter().enumerate() {
            let base = [Seg::key("masses"), Seg::Index(i)];
            for n in self.group_or_node(&base, m.group.as_deref(), m.node, "a point mass")? {
                for k in 0..3 {
                    masses[n][k] += m.mass;
                    masses[n][3 + k] += m.rotary_inertia[k];
                }
                massive[n] = true;
            }
        }
        Ok((0..nn).filter(|&n| massive[n]).map(|n| (n, masses[n])).collect())
    }

    /// The displacement control of a nonlinear static analysis, if any: its nodes (one with a
    /// load pattern), its DOF free of supports (`fixed`), and the pattern's loads.
    fn control(&self, fixed: &[u8]) -> Result<Option<ControlSpec>, ModelError> {
        let AnalysisConfig::StaticNonlinear(c) = &self.job.spec.analysis else { return Ok(None) };
        let Some(ctl) = &c.control else { return Ok(None) };
        let base = [Seg::key("analysis"), Seg::key("control")];
        let nodes = self.group_or_node(&base, ctl.group.as_deref(), ctl.node, "the control")?;
        let dof = ctl.dof.indices().start;
        let pattern =
            self.sum_loads(&[Seg::key("analysis"), Seg::key("control"), Seg::key("pattern")], ctl.pattern.iter())?;
        if !pattern.is_empty() && nodes.len() != 1 {
            return Err(self
                .job
                .error_at(
                    &base,
                    format!(
                        "with a load pattern the control is one node; the group has {} nodes (use node = <tag>)",
                        nodes.len()
                    ),
                )
                .into());
        }
        if let Some(&n) = nodes.iter().find(|&&n| fixed[n] & (1 << dof) != 0) {
            return Err(self
                .job
                .error_at(
                    &[Seg::key("analysis"), Seg::key("control"), Seg::key("dof")],
                    format!("DOF {:?} of control node {} is fixed by a support", ctl.dof, self.mesh.node_tags[n]),
                )
                .into());
        }
        Ok(Some(ControlSpec { nodes, dof, target: ctl.target, steps: ctl.steps, pattern }))
    }
}
