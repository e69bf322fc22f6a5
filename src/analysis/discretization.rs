//! Setup of the discrete system (deal.II's `setup_system`): partition, DOF numbering, and the
//! element objects of the cells this rank owns.
use crate::config::{Job, MaterialConfig, SectionConfig};
use crate::element::{
    ElasticFrame3d, Element, FiberBeam3d, FiberSection, FrameSection, ShellError, ShellMaterial, ShellQuad4,
    ShellSection, ShellTri3, Tie, TieSection,
};
use crate::error::Error;
use crate::mesh::CellKind;
use crate::mesh::Mesh;
use crate::model::{ModelCell, StructuralModel};
use crate::parallel::{agree, partition_cells, Context, DofMap};

/// The discrete system of one rank.
pub struct Discretization {
    /// Ownership and numbering.
    pub dofs: DofMap,
    /// Part (rank) of every model cell.
    pub cell_rank: Vec<usize>,
    /// The model cells this rank owns (indices into `StructuralModel::cells`), in model order.
    pub local_cells: Vec<usize>,
    /// Their element objects, aligned with `local_cells`.
    pub elements: Vec<Box<dyn Element>>,
    /// The whole model's mass and weight (logged at setup).
    pub mass: super::model_mass::ModelMass,
}

/// Default orientation of a beam (a vector in its local x–z plane): global Z, or global X when
/// the member is within about 0.1° of vertical.
pub fn default_orientation(x1: [f64; 3], x2: [f64; 3]) -> [f64; 3] {
    let d = [x2[0] - x1[0], x2[1] - x1[1], x2[2] - x1[2]];
    let l = (d[0] * d[0] + d[1] * d[1] + d[2] * d[2]).sqrt();
    if l > 0.0 && d[2].abs() / l > 0.999_998 {
        [1.0, 0.0, 0.0]
    } else {
        [0.0, 0.0, 1.0]
    }
}

impl Discretization {
    /// Collective. Partitions the model's cells, numbers the DOFs, builds the owned elements.
    /// Called by [`super::FeProblem::setup`] only: an analysis takes the problem.
    pub(super) fn setup(ctx: &Context, job: &Job, mesh: &Mesh, model: &StructuralModel) -> Result<Self, Error> {
        let cells = model.cell_nodes(mesh);
        let cell_rank = agree(&ctx.comm, partition_cells(&ctx.comm, &cells), |_| 1)?;
        let dofs = DofMap::build(&cells, &cell_rank, model.fixed.clone(), ctx.rank, ctx.size);
        let local_cells: Vec<usize> = (0..cells.len()).filter(|&c| cell_rank[c] == ctx.rank).collect();
        let scale = vec![1.0; job.spec.parts.len()];
        let built = build_elements(job, mesh, model, &local_cells, &scale);
        let elements = agree(&ctx.comm, built, Error::exit_code)?;
        let mut disc = Discretization { dofs, cell_rank, local_cells, elements, mass: Default::default() };
        disc.mass = super::model_mass::ModelMass::of(ctx, &disc, model);
        ctx.log.info(disc.mass.line());
        Ok(disc)
    }

    /// Collective. The owned elements built again, fresh (no damage, no state), with the Young
    /// modulus of each part's material scaled by `scale[part]`
    /// ([`MaterialConfig::with_modulus_scaled`]); the partition and the numbering stay
    /// ([`super::FeProblem::rebuild_elements`]).
    pub(super) fn rebuild_elements(
        &mut self,
        ctx: &Context,
        job: &Job,
        mesh: &Mesh,
        model: &StructuralModel,
        scale: &[f64],
    ) -> Result<(), Error> {
        let built = build_elements(job, mesh, model, &self.local_cells, scale);
        self.elements = agree(&ctx.comm, built, Error::exit_code)?;
        Ok(())
    }

    /// Collective. An empty matrix over the equations, preallocated exactly for the model's
    /// couplings, in the requested storage (AIJ, or BAIJ with 6×6 node blocks), declared symmetric.
    pub fn new_matrix(
        &self,
        ctx: &Context,
        mesh: &Mesh,
        model: &StructuralModel,
        format: crate::config::MatrixFormat,
    ) -> Result<crate::petsc::Matrix, Error> {
        use crate::petsc::Matrix;
        let p = self.dofs.preallocation(&model.cell_nodes(mesh));
        let n = self.dofs.n_owned_dofs();
        let mut m = match format {
            crate::config::MatrixFormat::Aij => Matrix::new_aij(&ctx.comm, n, &p.d_nnz, &p.o_nnz)?,
            crate::config::MatrixFormat::Baij => Matrix::new_baij(&ctx.comm, 6, n, &p.d_nnz_blocks, &p.o_nnz_blocks)?,
        };
        m.set_option_symmetric(true)?;
        Ok(m)
    }

    /// The equations of an element's DOFs, free (`-1` for fixed) and all.
    pub fn element_equations(&self, nodes: &[usize], free: &mut Vec<i32>, all: &mut Vec<i32>) {
        free.clear();
        all.clear();
        for &n in nodes {
            for d in 0..crate::parallel::DOFS_PER_NODE {
                free.push(self.dofs.equation(n, d));
                all.push(self.dofs.dof(n, d));
            }
        }
    }
}

/// The material of shell layers and beam fibers (elastic, or the damage law) and its density.
/// `None` when a damage material's law was not loaded.
fn point_material(mat: &MaterialConfig) -> Option<(ShellMaterial, f64)> {
    match mat {
        MaterialConfig::Elastic(m) => {
            let nu = m.nu.unwrap_or_else(|| m.e / (2.0 * m.shear_modulus()) - 1.0);
            Some((ShellMaterial::Elastic { e: m.e, nu }, m.density))
        }
        MaterialConfig::Damage(d) => d.law.map(|law| (ShellMaterial::Damage(law), d.density)),
    }
}

/// The error of a damage material whose law was not loaded.
const NO_LAW: &str = "the damage material's law was not loaded";

/// The element objects of `local_cells`, the moduli of part `p` scaled by `scale[p]`.
fn build_elements(
    job: &Job,
    mesh: &Mesh,
    model: &StructuralModel,
    local_cells: &[usize],
    scale: &[f64],
) -> Result<Vec<Box<dyn Element>>, Error> {
    local_cells.iter().map(|&c| build_element(job, mesh, model, model.cells[c], scale[model.cells[c].part])).collect()
}

/// The element of model cell `mc`: its part's section with its part's material, the moduli
/// scaled by `scale`. A cell that cannot be built is bad input (exit code 2), as is a bad
/// geometry or orientation.
fn build_element(
    job: &Job,
    mesh: &Mesh,
    model: &StructuralModel,
    mc: ModelCell,
    scale: f64,
) -> Result<Box<dyn Element>, Error> {
    let spec = &job.spec;
    let cell = &mesh.cells[mc.cell];
    let part = &spec.parts[mc.part];
    let input_error = |message: String| Error::ElementInput { tag: cell.tag, group: part.group.clone(), message };
    let scaled;
    let material = if scale == 1.0 {
        &spec.materials[&part.material]
    } else {
        scaled = spec.materials[&part.material].with_modulus_scaled(scale);
        &scaled
    };
    let x = |k: usize| mesh.coords[cell.nodes[k]];
    let orientation = || part.orientation.unwrap_or_else(|| default_orientation(x(0), x(1)));
    let element: Box<dyn Element> = match (&spec.sections[&part.section], material) {
        (SectionConfig::Frame(s), MaterialConfig::Elastic(mat)) => {
            let section = FrameSection {
                e: mat.e,
                g: mat.shear_modulus(),
                area: s.area,
                iy: s.iy,
                iz: s.iz,
                j: s.j,
                density: mat.density,
                nonstructural_mass: s.nonstructural_mass,
            };
            Box::new(ElasticFrame3d::new(x(0), x(1), orientation(), section).map_err(|e| input_error(e.to_string()))?)
        }
        (SectionConfig::Tie(t), MaterialConfig::Elastic(mat)) => {
            let section = TieSection {
                e: mat.e,
                area: t.area,
                density: mat.density,
                pretension: t.pretension,
                tension_only: t.tension_only,
            };
            // An end that only ties touch is an anchor (`StructuralModel::anchors`).
            let anchored = [cell.nodes[0], cell.nodes[1]].map(|n| model.anchors.binary_search(&n).is_ok());
            let tie = Tie::new(x(0), x(1), section).map_err(|e| input_error(e.to_string()))?;
            Box::new(tie.with_anchored_ends(anchored))
        }
        (SectionConfig::Frame(_) | SectionConfig::Tie(_), MaterialConfig::Damage(_)) => {
            // Rejected when the job is validated; kept as an error, not a panic.
            return Err(input_error(format!(
                "a {} section needs an elastic material",
                spec.sections[&part.section].type_name()
            )));
        }
        (SectionConfig::Fiber(fs), mat) => {
            let (material, density) = point_material(mat).ok_or_else(|| input_error(NO_LAW.into()))?;
            let section = FiberSection {
                width: fs.width,
                height: fs.height,
                ny: fs.ny,
                nz: fs.nz,
                integration_points: fs.integration_points,
                material,
                density,
                nonstructural_mass: fs.nonstructural_mass,
                torsion_constant: fs.torsion_constant,
            };
            Box::new(FiberBeam3d::new(x(0), x(1), orientation(), section).map_err(|e| input_error(e.to_string()))?)
        }
        (SectionConfig::Shell(sh), mat) => {
            let (material, density) = point_material(mat).ok_or_else(|| input_error(NO_LAW.into()))?;
            let section = ShellSection {
                thickness: sh.thickness,
                layers: sh.layers,
                material,
                density,
                nonstructural_mass_per_area: sh.nonstructural_mass,
            };
            let err = |e: ShellError| input_error(e.to_string());
            match cell.kind {
                CellKind::Quad4 => Box::new(ShellQuad4::new([x(0), x(1), x(2), x(3)], &section).map_err(err)?),
                CellKind::Tri3 => Box::new(ShellTri3::new([x(0), x(1), x(2)], &section).map_err(err)?),
                other => {
                    return Err(input_error(format!("a shell section needs triangles or quadrangles, not a {other}")))
                }
            }
        }
    };
    Ok(element)
}
