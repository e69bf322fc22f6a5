//! The typed job file. Every table rejects unknown keys; defaults live here, in one place.
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
//! [[parts]]
//! group = "legs"                        # a physical group of the mesh
//! section = "leg"
//! material = "steel"
//! orientation = [1.0, 0.0, 0.0]         # a vector in the local x-z plane (optional)
//! [[supports]]
//! group = "base"
//! dofs = ["all"]                        # or any of ux uy uz rx ry rz
//! [[loads]]
//! type = "nodal"
//! group = "top"
//! force = [1.0e3, 0.0, 0.0]             # [N] on every node of the group
//! [gravity]
//! acceleration = [0.0, 0.0, -9.81]      # [m/s^2]
//! [solver.petsc]                        # PETSc options; the command line wins
//! ksp_type = "preonly"
//! [output]
//! dir = "results/tower"                 # default: results/<job file stem>
//! ```
use serde::Deserialize;
use std::collections::BTreeMap;
use std::path::PathBuf;

/// The analyses a job can ask for.
#[derive(Clone, Debug, Deserialize, PartialEq)]
#[serde(tag = "type", rename_all = "snake_case", deny_unknown_fields)]
pub enum AnalysisConfig {
    /// Linear static analysis: K u = f.
    LinearStatic,
    /// Modal analysis: the lowest modes of K φ = ω² M φ.
    Modal(ModalConfig),
    /// Modal updating: Young's moduli of chosen groups fitted to target frequencies.
    ModalUpdating(ModalUpdatingConfig),
    /// Nonlinear static analysis: the loads applied in steps, Newton iterations in each.
    StaticNonlinear(StaticNonlinearConfig),
    /// Seismic time history: gravity, then the base acceleration of `[dynamics]`.
    TimeHistory,
}

/// `[analysis] type = "static_nonlinear"`: the job's loads (nodal loads and gravity) scaled by a
/// load factor λ going from 0 to 1 in `steps` equal steps; in each, Newton iterations on the
/// tangent stiffness until the out-of-balance force and energy are small; a step that fails is
/// cut in half (up to `max_cuts` times) before the run stops with a diagnosis.
#[derive(Clone, Debug, Deserialize, PartialEq)]
#[serde(deny_unknown_fields)]
pub struct StaticNonlinearConfig {
    /// Load steps (default 10).
    #[serde(default = "default_load_steps")]
    pub steps: usize,
    /// Newton iterations per step (default 25).
    #[serde(default = "default_newton_iterations")]
    pub max_iterations: usize,
    /// Relative tolerance on the out-of-balance force, ‖r‖ ≤ tol ‖λ f‖ (default 1e-8).
    #[serde(default = "default_force_tolerance")]
    pub force_tolerance: f64,
    /// Relative tolerance on the energy norm |Δu·r| ≤ tol |Δu₀·r₀| (default 1e-14).
    #[serde(default = "default_energy_tolerance")]
    pub energy_tolerance: f64,
    /// Halvings of a failing step before the run stops (default 6).
    #[serde(default = "default_max_cuts")]
    pub max_cuts: usize,
}

fn default_load_steps() -> usize {
    10
}
fn default_newton_iterations() -> usize {
    25
}
fn default_force_tolerance() -> f64 {
    1e-8
}
fn default_energy_tolerance() -> f64 {
    1e-14
}
fn default_max_cuts() -> usize {
    6
}

impl AnalysisConfig {
    /// The name used in the job file.
    pub fn name(&self) -> &'static str {
        match self {
            AnalysisConfig::LinearStatic => "linear_static",
            AnalysisConfig::Modal(_) => "modal",
            AnalysisConfig::ModalUpdating(_) => "modal_updating",
            AnalysisConfig::StaticNonlinear(_) => "static_nonlinear",
            AnalysisConfig::TimeHistory => "time_history",
        }
    }
}

/// `[analysis] type = "modal"`
#[derive(Clone, Debug, Deserialize, PartialEq)]
#[serde(deny_unknown_fields)]
pub struct ModalConfig {
    /// Number of modes (lowest frequencies), default 6.
    #[serde(default = "default_modes")]
    pub modes: usize,
    /// Mass matrix: `"consistent"` (default) or `"lumped"`.
    #[serde(default = "default_mass")]
    pub mass: crate::element::MassKind,
}

/// `[analysis] type = "modal_updating"`: the factors `s_g` multiplying the elastic moduli (E,
/// and G with it) of the parts of chosen groups are fitted so that computed frequencies match
/// targets.
#[derive(Clone, Debug, Deserialize, PartialEq)]
#[serde(deny_unknown_fields)]
pub struct ModalUpdatingConfig {
    /// Modes computed at each iteration (at least the highest target mode).
    #[serde(default = "default_modes")]
    pub modes: usize,
    /// Mass matrix.
    #[serde(default = "default_mass")]
    pub mass: crate::element::MassKind,
    /// Target frequencies, paired with computed modes by mode number, or by MAC when
    /// `target_shapes` is given.
    pub targets: Vec<TargetFrequency>,
    /// Target mode shapes: an HDF5 file laid out as a modal run's `modes.h5`
    /// (`mesh/node_ids`, `steps/<k>/mode_translation`, k = mode − 1), possibly for a few nodes
    /// only (sensor locations). Relative to the job file's folder.
    pub target_shapes: Option<PathBuf>,
    /// The groups whose modulus is updated, with bounds on the factor.
    pub parameters: Vec<UpdateParameter>,
    /// Largest number of iterations (each one eigensolve), default 50.
    #[serde(default = "default_update_iterations")]
    pub max_iterations: usize,
    /// Stop when the RMS relative frequency error is below this, default 1e-9.
    #[serde(default = "default_update_tolerance")]
    pub tolerance: f64,
}

/// A measured (or assumed) natural frequency.
#[derive(Clone, Debug, Deserialize, PartialEq)]
#[serde(deny_unknown_fields)]
pub struct TargetFrequency {
    /// Mode number (1 = lowest); with `target_shapes`, the shape `mode` of that file.
    pub mode: usize,
    /// Frequency [Hz].
    pub frequency: f64,
}

/// One updating parameter: the factor on E of the parts of a group.
#[derive(Clone, Debug, Deserialize, PartialEq)]
#[serde(deny_unknown_fields)]
pub struct UpdateParameter {
    /// Physical group (one of the job's parts).
    pub group: String,
    /// Smallest factor (> 0).
    pub min: f64,
    /// Largest factor.
    pub max: f64,
}

fn default_update_iterations() -> usize {
    50
}

fn default_update_tolerance() -> f64 {
    1e-9
}

fn default_modes() -> usize {
    6
}

fn default_mass() -> crate::element::MassKind {
    crate::element::MassKind::Consistent
}

/// `[mesh]`
#[derive(Clone, Debug, Deserialize, PartialEq)]
#[serde(deny_unknown_fields)]
pub struct MeshConfig {
    /// Gmsh MSH 4.1 file, relative to the job file's folder.
    pub file: PathBuf,
}

/// `[materials.NAME]`
#[derive(Clone, Debug, Deserialize, PartialEq)]
#[serde(tag = "type", rename_all = "snake_case")]
pub enum MaterialConfig {
    /// Isotropic linear elasticity.
    Elastic(ElasticMaterial),
    /// The masonry damage law (SPEC §2), for shell layers.
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
}

/// `type = "damage"`: the damage law's parameters, inline (`[materials.NAME.law]`) or from the
/// material file an identification job writes (`law_file`); exactly one of the two.
#[derive(Clone, Debug, Deserialize, PartialEq)]
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
#[derive(Clone, Debug, Deserialize, PartialEq)]
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
#[derive(Clone, Debug, Deserialize, PartialEq)]
#[serde(tag = "type", rename_all = "snake_case")]
pub enum SectionConfig {
    /// Elastic frame section of a 2-node beam.
    Frame(FrameSectionConfig),
    /// Layered shell section of 3- and 4-node shells.
    Shell(ShellSectionConfig),
}

/// `type = "shell"`: a layered shell section.
#[derive(Clone, Debug, Deserialize, PartialEq)]
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
#[derive(Clone, Debug, Deserialize, PartialEq)]
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
}

impl SectionConfig {
    /// The name used in the job file.
    pub fn type_name(&self) -> &'static str {
        match self {
            SectionConfig::Frame(_) => "frame",
            SectionConfig::Shell(_) => "shell",
        }
    }
}

/// `[[parts]]`: a physical group modelled with a section and a material.
#[derive(Clone, Debug, Deserialize, PartialEq)]
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
#[derive(Clone, Copy, Debug, Deserialize, PartialEq, Eq)]
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
#[derive(Clone, Debug, Deserialize, PartialEq)]
#[serde(deny_unknown_fields)]
pub struct SupportConfig {
    /// Physical group name.
    pub group: String,
    /// Fixed DOFs (`["all"]`, or a subset of ux uy uz rx ry rz).
    pub dofs: Vec<DofName>,
}

/// `[[loads]]`
#[derive(Clone, Debug, Deserialize, PartialEq)]
#[serde(tag = "type", rename_all = "snake_case")]
pub enum LoadConfig {
    /// A force and a moment on every node of a group.
    Nodal(NodalLoadConfig),
}

/// `type = "nodal"`: a force and a moment on every node of a group.
#[derive(Clone, Debug, Deserialize, PartialEq)]
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

/// `[gravity]`: self-weight of every element with a density.
#[derive(Clone, Debug, Deserialize, PartialEq)]
#[serde(deny_unknown_fields)]
pub struct GravityConfig {
    /// Gravitational acceleration vector [m/s²].
    pub acceleration: [f64; 3],
}

/// Storage of the assembled matrices.
#[derive(Clone, Copy, Debug, Default, Deserialize, PartialEq, Eq)]
#[serde(rename_all = "snake_case")]
pub enum MatrixFormat {
    /// PETSc AIJ (compressed rows): works with every preconditioner and factorization.
    #[default]
    Aij,
    /// PETSc BAIJ with 6×6 blocks (one per node pair): less index storage, faster products.
    Baij,
}

/// `[solver]`
#[derive(Clone, Debug, Default, Deserialize, PartialEq)]
#[serde(deny_unknown_fields)]
pub struct SolverConfig {
    /// Matrix storage (`"aij"` default, or `"baij"`).
    #[serde(default)]
    pub matrix: MatrixFormat,
    /// PETSc options without the leading dash (`ksp_type = "cg"`); the command line and
    /// `PETSC_OPTIONS` win over these.
    #[serde(default)]
    pub petsc: BTreeMap<String, toml::Value>,
}

/// What a run does when its output folder holds a previous run's results.
#[derive(Clone, Copy, Debug, Default, Deserialize, PartialEq, Eq)]
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
#[derive(Clone, Debug, Default, Deserialize, PartialEq)]
#[serde(deny_unknown_fields)]
pub struct OutputConfig {
    /// Results folder, relative to the job file's folder; default `results/<job file stem>`.
    pub dir: Option<PathBuf>,
    /// What to do with a previous run's results there.
    #[serde(default)]
    pub existing: ExistingOutput,
}

/// A structural job file, as written.
#[derive(Clone, Debug, Deserialize, PartialEq)]
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
