//! The job file of a material-point analysis: one point of the damage law driven along a strain
//! path (mixed strain/stress control), to look at the law or to check identified parameters.
//!
//! ```toml
//! [analysis]
//! type = "material_point"
//! kinematics = "plane_stress"      # plane_stress (shell layers) | uniaxial (beam fibers) | three_d
//! element_size = 0.10              # m: the h of the Hillerborg regularization
//! [material]                       # the damage law (material::DamageParams)
//! E = 2.885e9
//! nu = 0.19
//! eps0_t = 5.0e-5
//! eps0_c = 5.0e-5
//! gf_t = 20.0
//! a_c = 0.9
//! b_c = 2000.0
//! regularization = "hillerborg"
//! [path]
//! type = "uniaxial_tension"        # see PathConfig
//! max_strain = 1.0e-3
//! steps = 200
//! ```
use crate::material::DamageParams;
use serde::Deserialize;

/// `[analysis]` of a material-point job.
#[derive(Clone, Debug, Deserialize, PartialEq, schemars::JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct MaterialPointAnalysis {
    /// Always `"material_point"`.
    #[serde(rename = "type")]
    pub kind: String,
    /// Which stress state the point is in.
    #[serde(default)]
    pub kinematics: Kinematics,
    /// Element characteristic length h [m] for the regularization.
    pub element_size: f64,
}

/// The stress state of the material point.
#[derive(Clone, Copy, Debug, Default, Deserialize, PartialEq, Eq, schemars::JsonSchema)]
#[serde(rename_all = "snake_case")]
pub enum Kinematics {
    /// Plane stress (a shell layer): components xx, yy, xy.
    #[default]
    PlaneStress,
    /// Uniaxial stress (a beam fiber): component xx.
    Uniaxial,
    /// General 3D: xx, yy, zz, yz, xz, xy.
    ThreeD,
}

/// `[path]`: the loading history (strains; stress components not driven are free).
#[derive(Clone, Debug, Deserialize, PartialEq, schemars::JsonSchema)]
#[serde(tag = "type", rename_all = "snake_case")]
pub enum PathConfig {
    /// ε_xx: 0 → max_strain.
    UniaxialTension(UniaxialTensionPath),
    /// ε_xx: 0 → −max_shortening.
    UniaxialCompression(UniaxialCompressionPath),
    /// ε_xx piecewise linear through `targets` (any sign).
    Uniaxial(UniaxialPath),
    /// Tension–compression cycles of growing amplitude.
    Cyclic(CyclicPath),
    /// Proportional biaxial strain ε_yy = ratio · ε_xx.
    Biaxial(BiaxialPath),
    /// γ_xy: 0 → max_gamma, normal stresses free.
    PureShear(PureShearPath),
    /// σ_yy held at −vertical_stress, γ_xy through `targets` (the lab's cyclic shear test).
    ShearUnderCompression(ShearUnderCompressionPath),
}

/// `type = "uniaxial_tension"`
#[derive(Clone, Debug, Deserialize, PartialEq, schemars::JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct UniaxialTensionPath {
    /// Final ε_xx (> 0).
    pub max_strain: f64,
    /// Number of steps.
    pub steps: usize,
}

/// `type = "uniaxial_compression"`
#[derive(Clone, Debug, Deserialize, PartialEq, schemars::JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct UniaxialCompressionPath {
    /// Final shortening |ε_xx| (> 0).
    pub max_shortening: f64,
    /// Number of steps.
    pub steps: usize,
}

/// `type = "uniaxial"`
#[derive(Clone, Debug, Deserialize, PartialEq, schemars::JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct UniaxialPath {
    /// ε_xx targets, reached in turn from 0.
    pub targets: Vec<f64>,
    /// Steps per segment.
    pub steps_per_segment: usize,
}

/// `type = "cyclic"`
#[derive(Clone, Debug, Deserialize, PartialEq, schemars::JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct CyclicPath {
    /// Largest tensile ε_xx (> 0).
    pub tension_amplitude: f64,
    /// Largest shortening |ε_xx| (> 0).
    pub compression_amplitude: f64,
    /// Number of cycles (amplitudes grow linearly to the largest).
    pub cycles: usize,
    /// Steps per branch.
    pub steps_per_segment: usize,
}

/// `type = "biaxial"`
#[derive(Clone, Debug, Deserialize, PartialEq, schemars::JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct BiaxialPath {
    /// Final ε_xx.
    pub max_strain_xx: f64,
    /// ε_yy / ε_xx.
    pub ratio: f64,
    /// Number of steps.
    pub steps: usize,
}

/// `type = "pure_shear"`
#[derive(Clone, Debug, Deserialize, PartialEq, schemars::JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct PureShearPath {
    /// Final engineering shear γ_xy.
    pub max_gamma: f64,
    /// Number of steps.
    pub steps: usize,
}

/// `type = "shear_under_compression"`
#[derive(Clone, Debug, Deserialize, PartialEq, schemars::JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct ShearUnderCompressionPath {
    /// The compressive stress held on yy [Pa] (> 0).
    pub vertical_stress: f64,
    /// Engineering shear γ_xy targets, reached in turn from 0.
    pub targets: Vec<f64>,
    /// Steps per segment.
    pub steps_per_segment: usize,
    /// Steps of the compressive preload (default 5).
    #[serde(default = "five")]
    pub preload_steps: usize,
}

fn five() -> usize {
    5
}

/// A material-point job file, as written.
#[derive(Clone, Debug, Deserialize, PartialEq, schemars::JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct MaterialPointJobFile {
    /// A one-line description.
    pub title: Option<String>,
    /// `[analysis]`.
    pub analysis: MaterialPointAnalysis,
    /// The damage law's parameters.
    pub material: DamageParams,
    /// The loading path.
    pub path: PathConfig,
    /// Where results go.
    #[serde(default)]
    pub output: super::OutputConfig,
}
