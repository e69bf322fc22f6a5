//! `[analysis]`: which analysis a structural job runs, and its settings (static nonlinear with
//! load and displacement control, modal, modal updating, seismic assessment). Every table
//! rejects unknown keys; defaults live here.
use super::job::{DofName, NodalLoadConfig};
use serde::Deserialize;
use std::path::PathBuf;

/// The analyses a job can ask for.
#[derive(Clone, Debug, Deserialize, PartialEq, schemars::JsonSchema)]
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
    /// Modal analysis, modal updating, then gravity and the earthquake of `[dynamics]` on the
    /// updated model: see [`super::AssessmentConfig`].
    SeismicAssessment(super::AssessmentConfig),
}

/// `[analysis] type = "static_nonlinear"`: the job's loads (nodal loads and gravity) scaled by a
/// load factor λ going from 0 to 1 in `steps` equal steps; in each, Newton iterations on the
/// tangent stiffness until the out-of-balance force and energy are small; a step that fails is
/// cut in half (up to `max_cuts` times) before the run stops with a diagnosis.
#[derive(Clone, Debug, Deserialize, PartialEq, schemars::JsonSchema)]
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
    /// Line search along each Newton correction: `"secant"` (default) or `"none"`.
    #[serde(default)]
    pub line_search: LineSearchKind,
    /// Iteration matrix: `"tangent"` (default: the consistent tangent; an increment that fails
    /// is retried with secant iterations before it is halved) or `"secant"` (always).
    #[serde(default)]
    pub stiffness: IterationMatrix,
    /// Displacement control after the loads (pushover); absent: load control only.
    pub control: Option<DisplacementControlConfig>,
    /// Relaxation time τ of an optional viscous (Duvaut–Lions) regularization of the damage
    /// histories of shell layers, in the analysis' pseudo-time: each stage (the loads, then the
    /// control) lasts 1, so τ = 0.01 is 1% of a stage (`material::state` docs). Absent (the
    /// default): the rate-independent law. A viscous run's dissipated energy depends on τ.
    pub damage_relaxation_time: Option<f64>,
    /// Radius R [m] of the nonlocal averaging of the damage-driving strains of damage shells
    /// (`material::nonlocal`, `analysis::nonlocal`): each layer point's damage follows the
    /// strains of the same layer within R, weighted by ⟨1 − r²/R²⟩², and B_t (and B_s of
    /// `gf_c`) are regularized by R instead of the element size. R should span at least two
    /// elements. Absent (the default): the local law.
    pub nonlocal_radius: Option<f64>,
}

/// `[analysis] stiffness`: the matrix of the Newton-type iterations.
#[derive(Clone, Copy, Debug, Default, Deserialize, PartialEq, Eq, schemars::JsonSchema)]
#[serde(rename_all = "snake_case")]
pub enum IterationMatrix {
    /// The consistent tangent (quadratic convergence), with the secant as fallback.
    #[default]
    Tangent,
    /// The secant stiffness (damage: (1 − d) C₀), 4× the iterations allowed.
    Secant,
}

/// `[analysis] line_search`.
#[derive(Clone, Copy, Debug, Default, Deserialize, PartialEq, Eq, schemars::JsonSchema)]
#[serde(rename_all = "snake_case")]
pub enum LineSearchKind {
    /// Full Newton steps.
    None,
    /// Secant search for Δu · r(u + η Δu) = 0 (`analysis::line_search`).
    #[default]
    Secant,
}

/// `[analysis.control]`: once the job's loads and gravity are applied (load control, `steps`),
/// they are held and the DOF `dof` of the control node(s) is driven from its value to `target`
/// (added to it) in `steps` equal increments.
///
/// Without `pattern`, the DOF of every node of `group` (or of `node`) is imposed: the nodes are
/// pushed like a stiff platen, and the force is the reaction they need. With `pattern`, one
/// control node (a one-node group, or `node`) is free, the pattern's nodal loads are scaled by an
/// unknown factor μ, and each increment finds μ so that the control DOF reaches its value
/// (displacement control, Batoz & Dhatt 1979): the force is μ times the pattern's resultant along
/// `dof`.
///
/// ```toml
/// [analysis.control]
/// group = "top"            # or: node = 57 (Gmsh tag)
/// dof = "ux"
/// target = 0.004           # [m] (or [rad] for a rotation)
/// steps = 40
/// # [[analysis.control.pattern]]   # optional
/// # group = "floors"
/// # force = [1.0e3, 0.0, 0.0]
/// ```
#[derive(Clone, Debug, Deserialize, PartialEq, schemars::JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct DisplacementControlConfig {
    /// Physical group of the control node(s).
    pub group: Option<String>,
    /// One control node, by its Gmsh tag.
    pub node: Option<u64>,
    /// The controlled DOF (one of ux uy uz rx ry rz).
    pub dof: DofName,
    /// Displacement (or rotation) added to the DOF over the control stage.
    pub target: f64,
    /// Increments (default 20).
    #[serde(default = "default_control_steps")]
    pub steps: usize,
    /// Load pattern scaled by the unknown factor (optional; see the type's docs).
    #[serde(default)]
    pub pattern: Vec<NodalLoadConfig>,
    /// A second curve drawn on `curve.png` (e.g. the DEM virtual test's), optional.
    pub overlay: Option<CurveOverlayConfig>,
}

/// `[analysis.control.overlay]`: a curve read from a CSV file with a header line, drawn on the
/// force–displacement chart beside the computed one; x and y are columns picked by name and
/// multiplied by the scales (e.g. a DEM stress times the wall's cross-section to get a force).
///
/// ```toml
/// [analysis.control.overlay]
/// file = "../results/wall-shear/sample-000/curve.csv"   # relative to the job file's folder
/// x = "displacement"
/// y = "stress"
/// y_scale = 0.5            # [m^2] stress -> force on the 1.0 m x 0.5 m section
/// label = "DEM"
/// ```
#[derive(Clone, Debug, Deserialize, PartialEq, schemars::JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct CurveOverlayConfig {
    /// The CSV file (resolved against the job file's folder at load).
    pub file: PathBuf,
    /// Column of the abscissa.
    pub x: String,
    /// Column of the ordinate.
    pub y: String,
    /// Factor on x (default 1).
    #[serde(default = "one")]
    pub x_scale: f64,
    /// Factor on y (default 1).
    #[serde(default = "one")]
    pub y_scale: f64,
    /// Legend entry (default "reference").
    #[serde(default = "default_overlay_label")]
    pub label: String,
}

fn one() -> f64 {
    1.0
}

fn default_overlay_label() -> String {
    "reference".into()
}

fn default_control_steps() -> usize {
    20
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
            AnalysisConfig::SeismicAssessment(_) => "seismic_assessment",
        }
    }
}

/// `[analysis] type = "modal"`
#[derive(Clone, Debug, Deserialize, PartialEq, schemars::JsonSchema)]
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
#[derive(Clone, Debug, Deserialize, PartialEq, schemars::JsonSchema)]
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
#[derive(Clone, Debug, Deserialize, PartialEq, schemars::JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct TargetFrequency {
    /// Mode number (1 = lowest); with `target_shapes`, the shape `mode` of that file.
    pub mode: usize,
    /// Frequency [Hz].
    pub frequency: f64,
}

/// One updating parameter: the factor on E of the parts of a group.
#[derive(Clone, Debug, Deserialize, PartialEq, schemars::JsonSchema)]
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
