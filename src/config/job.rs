//! The typed structural job file (its `[analysis]` settings: `analysis.rs`). Every table rejects
//! unknown keys; defaults live beside their keys.
//!
//! A structural job (`[analysis] type = "linear_static"`):
//!
//! ```toml
//! title = "Lattice tower under self-weight and top loads"
//! [analysis]
//! type = "linear_static"
//! [mesh]
//! file = "../meshes/tower.msh"          # relative to this job file's folder
//! [materials.steel]
//! type = "elastic"
//! E = 210e9                             # Young's modulus [Pa]
//! nu = 0.3                              # Poisson ratio (or G = shear modulus [Pa])
//! density = 7850.0                      # [kg/m^3]
//! [sections.leg]
//! type = "frame"
//! area = 2.0e-3                         # [m^2]
//! iy = 1.5e-6                           # second moment about local y [m^4]
//! iz = 1.5e-6                           # second moment about local z [m^4]
//! j = 3.0e-6                            # torsion constant [m^4]
//! nonstructural_mass = 0.0              # [kg/m], optional
//! [sections.pilaster]                   # a fiber beam (element::fiber_section)
//! type = "fiber"
//! width = 0.6                           # [m] along local y
//! height = 0.8                          # [m] along local z
//! ny = 12                               # fibers along y (>= 2)
//! nz = 16                               # fibers along z (>= 2)
//! [sections.nave_tie]                   # an iron tie rod (element::tie): axial force only
//! type = "tie"
//! area = 1.6e-3                         # [m^2]
//! pretension = 0.0                      # [N], optional: initial axial force, tension positive
//! tension_only = true                   # optional: slack in compression
//! [[parts]]
//! group = "legs"                        # a physical group of the mesh
//! section = "leg"
//! material = "steel"
//! orientation = [1.0, 0.0, 0.0]         # a vector in the local x-z plane (optional)
//! [[parts]]
//! group = "nave_ties"                   # 2-node lines whose ends lie on shells or beams
//! section = "nave_tie"                  # (or on supports holding ux uy uz)
//! material = "steel"                    # elastic
//! [[supports]]
//! group = "base"
//! dofs = ["all"]                        # or any of ux uy uz rx ry rz
//! [[loads]]
//! type = "nodal"
//! group = "top"
//! force = [1.0e3, 0.0, 0.0]             # [N] on every node of the group
//! [[masses]]                            # point masses (optional)
//! group = "top"                         # or node = <Gmsh tag>
//! mass = 500.0                          # [kg] per node
//! [gravity]
//! acceleration = [0.0, 0.0, -9.81]      # [m/s^2]
//! [solver.petsc]                        # PETSc options; the command line wins
//! ksp_type = "preonly"
//! [output]
//! dir = "results/tower"                 # default: results/<job file stem>
//! ```
use super::analysis::AnalysisConfig;
use serde::Deserialize;
use std::collections::BTreeMap;
use std::path::PathBuf;

/// `[mesh]`
#[derive(Clone, Debug, Deserialize, PartialEq, schemars::JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct MeshConfig {
    /// Gmsh MSH 4.1 file, relative to the job file's folder.
    pub file: PathBuf,
}

/// `[materials.NAME]`
#[derive(Clone, Debug, Deserialize, PartialEq, schemars::JsonSchema)]
#[serde(tag = "type", rename_all = "snake_case")]
pub enum MaterialConfig {
    /// Isotropic linear elasticity.
    Elastic(ElasticMaterial),
    /// The masonry damage law (paper §3.1), for shell layers and beam fibers.
    Damage(DamageMaterial),
}

impl MaterialConfig {
    /// Mass density [kg/m³].
    pub fn density(&self) -> f64 {
        match self {
            MaterialConfig::Elastic(m) => m.density,
            MaterialConfig::Damage(m) => m.density,
        }
    }

    /// Young's modulus [Pa] (of the law file's parameters, once loaded, for `damage`).
    pub fn young_modulus(&self) -> Option<f64> {
        match self {
            MaterialConfig::Elastic(m) => Some(m.e),
            MaterialConfig::Damage(m) => m.law.as_ref().map(|l| l.e),
        }
    }

    /// The material with `E ← s E` (and `G ← s G` when given): the whole elastic stiffness
    /// scaled by `s`, the Poisson ratio held. A damage law keeps its strain thresholds, so its
    /// strengths (f_t = E ε₀ᵗ) scale with it (modal updating, paper §4.2).
    pub fn with_modulus_scaled(&self, s: f64) -> MaterialConfig {
        let mut m = self.clone();
        match &mut m {
            MaterialConfig::Elastic(e) => {
                e.e *= s;
                if let Some(g) = e.g.as_mut() {
                    *g *= s;
                }
            }
            MaterialConfig::Damage(d) => {
                if let Some(law) = d.law.as_mut() {
                    law.e *= s;
                }
            }
        }
        m
    }
}

/// `type = "damage"` (shell layers and beam fibers): the damage law's parameters, inline (`[materials.NAME.law]`) or from the
/// material file an identification job writes (`law_file`); exactly one of the two.
#[derive(Clone, Debug, Deserialize, PartialEq, schemars::JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct DamageMaterial {
    /// Mass density [kg/m³].
    #[serde(default)]
    pub density: f64,
    /// The law's parameters.
    pub law: Option<crate::material::DamageParams>,
    /// A TOML file holding the law's parameters (as `[law]`), relative to the job file's folder;
    /// read and checked at load, after which `law` holds them.
    pub law_file: Option<PathBuf>,
}

/// `type = "elastic"`: isotropic linear elasticity.
#[derive(Clone, Debug, Deserialize, PartialEq, schemars::JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct ElasticMaterial {
    /// Young's modulus [Pa].
    #[serde(rename = "E")]
    pub e: f64,
    /// Poisson ratio; give it or `G`.
    pub nu: Option<f64>,
    /// Shear modulus [Pa]; give it or `nu`.
    #[serde(rename = "G")]
    pub g: Option<f64>,
    /// Mass density [kg/m³].
    #[serde(default)]
    pub density: f64,
}

impl ElasticMaterial {
    /// The shear modulus: `G`, or `E / (2 (1 + nu))`.
    pub fn shear_modulus(&self) -> f64 {
        match (self.g, self.nu) {
            (Some(g), _) => g,
            (None, Some(nu)) => self.e / (2.0 * (1.0 + nu)),
            (None, None) => f64::NAN,
        }
    }
}

/// `[sections.NAME]`
#[derive(Clone, Debug, Deserialize, PartialEq, schemars::JsonSchema)]
#[serde(tag = "type", rename_all = "snake_case")]
pub enum SectionConfig {
    /// Elastic frame section of a 2-node beam.
    Frame(FrameSectionConfig),
    /// Layered shell section of 3- and 4-node shells.
    Shell(ShellSectionConfig),
    /// Rectangular fiber section of a 2-node beam (elastic or damage material per fiber).
    Fiber(FiberSectionConfig),
    /// Tie rod on 2-node lines: axial force only (elastic material).
    Tie(TieSectionConfig),
}

/// `type = "tie"`: an iron tie rod (`element::tie`) on 2-node lines, with an elastic material
/// (E, density). Both end nodes of every tie must belong to a shell or beam, or be held by
/// supports in ux uy uz.
#[derive(Clone, Debug, Deserialize, PartialEq, schemars::JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct TieSectionConfig {
    /// Area [m²].
    pub area: f64,
    /// Pretension [N] ≥ 0, default 0: the initial axial force (lack of fit), tension positive,
    /// applied as a static load with the self weight.
    #[serde(default)]
    pub pretension: f64,
    /// Tension only (default true): a slender rod buckles at a few kN, so it carries no
    /// compression; false: it carries both.
    #[serde(default = "yes")]
    pub tension_only: bool,
}

fn yes() -> bool {
    true
}

/// `type = "fiber"`: a rectangular section cut into `ny × nz` fibers (`element::fiber_section`),
/// each with the part's material (elastic, or the damage law in uniaxial form).
#[derive(Clone, Debug, Deserialize, PartialEq, schemars::JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct FiberSectionConfig {
    /// Width along the local y axis [m].
    pub width: f64,
    /// Height along the local z axis [m].
    pub height: f64,
    /// Fibers along y.
    pub ny: usize,
    /// Fibers along z.
    pub nz: usize,
    /// Gauss points along each element (2 to 5), default 2.
    #[serde(default = "default_integration_points")]
    pub integration_points: usize,
    /// Saint-Venant torsion constant [m⁴]; default: Roark's formula for the rectangle.
    pub torsion_constant: Option<f64>,
    /// Non-structural mass per length [kg/m], default 0.
    #[serde(default)]
    pub nonstructural_mass: f64,
}

fn default_integration_points() -> usize {
    crate::element::DEFAULT_INTEGRATION_POINTS
}

/// `type = "shell"`: a layered shell section.
#[derive(Clone, Debug, Deserialize, PartialEq, schemars::JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct ShellSectionConfig {
    /// Thickness [m].
    pub thickness: f64,
    /// Layers through the thickness (default 7).
    #[serde(default = "default_layers")]
    pub layers: usize,
    /// Non-structural mass per area [kg/m²] (finishes, fill), default 0.
    #[serde(default)]
    pub nonstructural_mass: f64,
}

fn default_layers() -> usize {
    7
}

/// `type = "frame"`: elastic section of a 2-node beam.
#[derive(Clone, Debug, Deserialize, PartialEq, schemars::JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct FrameSectionConfig {
    /// Area [m²].
    pub area: f64,
    /// Second moment of area about the local y axis [m⁴].
    pub iy: f64,
    /// Second moment of area about the local z axis [m⁴].
    pub iz: f64,
    /// Torsion constant [m⁴].
    pub j: f64,
    /// Non-structural mass per length [kg/m] (finishes, loads carried as mass), default 0.
    #[serde(default)]
    pub nonstructural_mass: f64,
}

impl SectionConfig {
    /// The name used in the job file.
    pub fn type_name(&self) -> &'static str {
        match self {
            SectionConfig::Frame(_) => "frame",
            SectionConfig::Shell(_) => "shell",
            SectionConfig::Fiber(_) => "fiber",
            SectionConfig::Tie(_) => "tie",
        }
    }
}

/// `[[parts]]`: a physical group modelled with a section and a material.
#[derive(Clone, Debug, Deserialize, PartialEq, schemars::JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct PartConfig {
    /// Physical group name in the mesh.
    pub group: String,
    /// Section name (a key of `[sections]`).
    pub section: String,
    /// Material name (a key of `[materials]`).
    pub material: String,
    /// For beams: a vector lying in the local x–z plane (see `element::frame`); default: global Z,
    /// or global X for members parallel to Z.
    pub orientation: Option<[f64; 3]>,
}

/// A nodal degree of freedom, as named in job files.
#[derive(Clone, Copy, Debug, Deserialize, PartialEq, Eq, schemars::JsonSchema)]
#[serde(rename_all = "snake_case")]
pub enum DofName {
    /// Translation along x.
    Ux,
    /// Translation along y.
    Uy,
    /// Translation along z.
    Uz,
    /// Rotation about x.
    Rx,
    /// Rotation about y.
    Ry,
    /// Rotation about z.
    Rz,
    /// All six.
    All,
}

impl DofName {
    /// The DOF indices (0..6) this name stands for.
    pub fn indices(self) -> std::ops::Range<usize> {
        match self {
            DofName::All => 0..6,
            d => {
                let i = d as usize;
                i..i + 1
            }
        }
    }
}

/// `[[supports]]`: fixed DOFs of every node of a group.
#[derive(Clone, Debug, Deserialize, PartialEq, schemars::JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct SupportConfig {
    /// Physical group name.
    pub group: String,
    /// Fixed DOFs (`["all"]`, or a subset of ux uy uz rx ry rz).
    pub dofs: Vec<DofName>,
}

/// `[[loads]]`
#[derive(Clone, Debug, Deserialize, PartialEq, schemars::JsonSchema)]
#[serde(tag = "type", rename_all = "snake_case")]
pub enum LoadConfig {
    /// A force and a moment on every node of a group.
    Nodal(NodalLoadConfig),
}

/// `type = "nodal"`: a force and a moment on every node of a group.
#[derive(Clone, Debug, Deserialize, PartialEq, schemars::JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct NodalLoadConfig {
    /// Physical group name.
    pub group: String,
    /// Force [N].
    #[serde(default)]
    pub force: [f64; 3],
    /// Moment [N·m].
    #[serde(default)]
    pub moment: [f64; 3],
}

/// `[[masses]]`: a point mass (and optional rotary inertia) on every node of a group, or on one
/// node given by its Gmsh tag (exactly one of the two). It adds to the mass matrix (modal and
/// dynamic analyses) and, under `[gravity]`, to the self weight.
///
/// ```toml
/// [[masses]]
/// group = "bells"                       # or: node = 1234 (Gmsh node tag)
/// mass = 1800.0                         # [kg] on each node
/// rotary_inertia = [0.0, 0.0, 350.0]    # [kg m^2] about global x, y, z (optional)
/// ```
#[derive(Clone, Debug, Deserialize, PartialEq, schemars::JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct PointMassConfig {
    /// Physical group whose every node carries the mass.
    pub group: Option<String>,
    /// One node, by its Gmsh tag.
    pub node: Option<u64>,
    /// Mass on each node [kg].
    pub mass: f64,
    /// Rotary inertia about the global axes [kg m²], default zero.
    #[serde(default)]
    pub rotary_inertia: [f64; 3],
}

/// `[gravity]`: self-weight of every element with a density.
#[derive(Clone, Debug, Deserialize, PartialEq, schemars::JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct GravityConfig {
    /// Gravitational acceleration vector [m/s²].
    pub acceleration: [f64; 3],
}

/// Storage of the assembled matrices.
#[derive(Clone, Copy, Debug, Default, Deserialize, PartialEq, Eq, schemars::JsonSchema)]
#[serde(rename_all = "snake_case")]
pub enum MatrixFormat {
    /// PETSc AIJ (compressed rows): works with every preconditioner and factorization.
    #[default]
    Aij,
    /// PETSc BAIJ with 6×6 blocks (one per node pair): less index storage, faster products.
    Baij,
}

/// `[solver]`
#[derive(Clone, Debug, Default, Deserialize, PartialEq, schemars::JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct SolverConfig {
    /// Matrix storage (`"aij"` default, or `"baij"`).
    #[serde(default)]
    pub matrix: MatrixFormat,
    /// PETSc options without the leading dash (`ksp_type = "cg"`); the command line and
    /// `PETSC_OPTIONS` win over these.
    #[serde(default)]
    #[schemars(with = "BTreeMap<String, PetscOptionValue>")]
    pub petsc: BTreeMap<String, toml::Value>,
}

/// The value of a PETSc option, as the key reference shows it (the job keeps the TOML value).
#[derive(schemars::JsonSchema)]
#[serde(untagged)]
#[allow(dead_code)]
enum PetscOptionValue {
    /// A string (`"cg"`).
    Text(String),
    /// A number (`1e-10`).
    Number(f64),
    /// A switch (`true`).
    Switch(bool),
}

/// What a run does when its output folder holds a previous run's results.
#[derive(Clone, Copy, Debug, Default, Deserialize, PartialEq, Eq, schemars::JsonSchema)]
#[serde(rename_all = "snake_case")]
pub enum ExistingOutput {
    /// Move the previous results to `<dir>.previous` (replacing an older copy) and say so.
    #[default]
    Backup,
    /// Replace them, and say so.
    Overwrite,
    /// Stop with an error.
    Error,
}

/// `[output]`
#[derive(Clone, Debug, Default, Deserialize, PartialEq, schemars::JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct OutputConfig {
    /// Results folder, relative to the job file's folder; default `results/<job file stem>`.
    pub dir: Option<PathBuf>,
    /// What to do with a previous run's results there.
    #[serde(default)]
    pub existing: ExistingOutput,
}

/// A structural job file, as written.
#[derive(Clone, Debug, Deserialize, PartialEq, schemars::JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct StructuralJobFile {
    /// A one-line description, echoed in logs and outputs.
    pub title: Option<String>,
    /// Which analysis.
    pub analysis: AnalysisConfig,
    /// The mesh.
    pub mesh: MeshConfig,
    /// Materials by name.
    #[serde(default)]
    pub materials: BTreeMap<String, MaterialConfig>,
    /// Sections by name.
    #[serde(default)]
    pub sections: BTreeMap<String, SectionConfig>,
    /// Groups modelled as elements.
    #[serde(default)]
    pub parts: Vec<PartConfig>,
    /// Fixed DOFs.
    #[serde(default)]
    pub supports: Vec<SupportConfig>,
    /// Applied loads.
    #[serde(default)]
    pub loads: Vec<LoadConfig>,
    /// Point masses.
    #[serde(default)]
    pub masses: Vec<PointMassConfig>,
    /// Self-weight.
    pub gravity: Option<GravityConfig>,
    /// Linear solver options.
    #[serde(default)]
    pub solver: SolverConfig,
    /// Where results go.
    #[serde(default)]
    pub output: OutputConfig,
    /// Time integration settings (`type = "time_history"`): see [`super::DynamicsConfig`].
    pub dynamics: Option<super::DynamicsConfig>,
}
