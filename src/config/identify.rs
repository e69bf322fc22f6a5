//! The job file of an identification (paper §3.2): (a) calibrate the DEM against experimental
//! numbers, (b) identify the damage law from the DEM's virtual tests, or both in a chain.
//! A stage runs when its table is present; with both, (b) uses the DEM calibrated by (a).
//!
//! ```toml
//! [analysis]
//! type = "identification"
//! seed = 1                     # seeds the designs and the surrogate (sample seeds: [sample] seed)
//! [sample]                     # the virtual wall (dem::sample::SampleConfig); its alpha is the
//! seed = 1                     # starting value when (a) does not run
//! layout = { type = "coursed", width = 1.0, height = 1.2, n_courses = 10, n_per_course = 6, jitter = 0.2, size_variability = 0.2 }
//! [mechanics]                  # fixed μ, k_t/k_n; Ē, ε_cr, θ_cr when (a) does not run
//! mu = 0.6
//! [experiment]                 # targets of (a): all four needed; E, ν also feed (b)
//! young_modulus = 2.885e9
//! poisson = 0.19
//! first_crack_stress = 0.4e6
//! peak_stress = 2.1e6
//!
//! [calibration]                # (a)
//! strategy = "staged"          # (alpha, e_bar) from (nu, E) on the elastic state, then the
//!                              # strengths by kriging + EI; or "joint" (all at once)
//! samples = 4                  # random samples per design point (mean ± std)
//! design_points = 16           # Latin hypercube
//! iterations = 4               # EGO infill iterations
//! batch = 2                    # points per iteration (q-EI, constant liar)
//! weights = [1.0, 1.0, 1.0, 1.0]   # E, ν, first crack, peak
//! test = { type = "compression", max_strain = 3.0e-3, steps = 60 }
//! bounds = { alpha = [0.4, 1.2], e_bar = [1.5e9, 4.0e9], eps_cr = [5e-5, 3e-4], theta_cr = [3e-4, 2e-3] }
//!
//! [law]                        # (b)
//! samples = 4                  # DEM samples per virtual test (mean curves)
//! tension = { type = "tension", max_strain = 1.0e-3, steps = 50 }
//! compression = { type = "compression", max_strain = 3.0e-3, steps = 60 }
//! # dem_curves = { tension = "t.csv", compression = "c.csv" }   # instead of running the DEM
//! # dem_samples = { tension = "dem_tension_samples.csv", compression = "dem_compression_samples.csv" }
//! #                            # or every sample's curve, as an earlier run wrote them (law fit only)
//! mean = "peak_aligned"        # how sample curves are averaged, or "pointwise" (identify::curves)
//! regularization = "hillerborg"    # or "hillerborg_no_elastic" (G_f = the whole dissipation per
//!                              # crack area; bounds.gf_t then bounds its softening part G_s =
//!                              # G_f − f_t² h/(2E), so the whole box is admissible: identify::law_fit)
//! # split = "spectral"          # the law's unilateral split: "trace" (the paper's, default) or
//! #                            # "spectral" (material::split)
//! # element_size = 1.2         # h of the comparison [m], default the sample height
//! elastic = "experiment"       # E, ν of the law: "experiment" (else the DEM's means) or "dem"
//! # young_modulus, poisson     # explicit values win over `elastic`
//! error = "eq15"               # or "relative_rms", or "peak_energy" (envelope to the peak, peak,
//!                              # post-peak energy: identify::error_measure)
//! points = 60                  # resampled points per curve
//! levels = [0.25, 0.75]        # the 2⁵ factorial's levels, fractions of each interval
//! iterations = 12
//! batch = 2
//! polish_iterations = 400    # Nelder-Mead from the best separated EGO points (law evaluations are cheap); 0: off
//! bounds = { eps0_t = [2e-5, 4e-4], eps0_c = [5e-5, 2e-3], gf_t = [5.0, 500.0], a_c = [0.0, 1.0], b_c = [100.0, 5000.0] }
//! #   optional sixth unknown in bounds: gf_c = [10.0, 2000.0] (compressive fracture energy, J/m²;
//! #   needs a_c > 0 throughout)
//! # material_file = "../materials/wall.toml"   # a copy beside the results' material.toml
//! # material_notes = """..."""  # comment lines for the material file's header
//! # variants = { count = 2, scheme = "halves" }   # material variants (identify::variants):
//! #                            # the law fitted again to subsets of the samples, each like the
//! #                            # main law (same design, optimizer and E, nu) on its samples' mean
//! #                            # curves; "halves": count disjoint groups dealt round-robin
//! #                            # ({1, 3} and {2, 4} of 4); "bootstrap": n samples drawn with
//! #                            # replacement (seed = 1: SplitMix64). Written as
//! #                            # material-variant-<k>.toml in the results and, beside the material
//! #                            # file, <its stem>-variant-<k>.toml; material_file = "..." in the
//! #                            # table names that file for the variants alone (the main law then
//! #                            # only in the results). Needs the samples' curves: the virtual
//! #                            # tests or dem_samples, not dem_curves.
//! ```
use super::{ExperimentConfig, MechanicsConfig, OutputConfig};
use crate::dem::sample::SampleConfig;
use crate::dem::solver::VirtualTest;
use crate::identify::variants::VariantScheme;
use crate::identify::ErrorMeasure;
use crate::material::Regularization;
use serde::Deserialize;
use std::path::PathBuf;

/// `[analysis]`.
#[derive(Clone, Debug, Deserialize, PartialEq, schemars::JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct IdentifyAnalysis {
    /// Always `"identification"`.
    #[serde(rename = "type")]
    pub kind: String,
    /// Seed of the designs and of the surrogate.
    #[serde(default = "one_u64")]
    pub seed: u64,
}

fn one_u64() -> u64 {
    1
}
fn four() -> usize {
    4
}
fn sixteen() -> usize {
    16
}
fn two() -> usize {
    2
}
fn twelve() -> usize {
    12
}
fn sixty() -> usize {
    60
}
fn four_hundred() -> u64 {
    400
}
fn unit_weights() -> [f64; 4] {
    [1.0; 4]
}
fn default_levels() -> [f64; 2] {
    [0.25, 0.75]
}
fn hillerborg() -> Regularization {
    Regularization::Hillerborg
}

/// `[calibration.bounds]`: intervals `[lower, upper]` of the four unknowns.
#[derive(Clone, Debug, Deserialize, PartialEq, schemars::JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct CalibrationBounds {
    /// Beam inertia coefficient α.
    pub alpha: [f64; 2],
    /// Lattice Young modulus Ē [Pa].
    pub e_bar: [f64; 2],
    /// Critical strain ε_cr.
    pub eps_cr: [f64; 2],
    /// Critical rotation θ_cr [rad].
    pub theta_cr: [f64; 2],
    /// Crushing stress σ_c [Pa] (optional fifth unknown; needs `[mechanics] crushing_energy`).
    pub crushing_stress: Option<[f64; 2]>,
}

/// `[calibration]`: (a) the DEM against the experiment.
#[derive(Clone, Debug, Deserialize, PartialEq, schemars::JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct CalibrationConfig {
    /// Staged (elastic parameters first) or joint (identify::calibration).
    #[serde(default)]
    pub strategy: crate::identify::Strategy,
    /// Random samples per design point.
    #[serde(default = "four")]
    pub samples: usize,
    /// Latin-hypercube points.
    #[serde(default = "sixteen")]
    pub design_points: usize,
    /// EGO infill iterations.
    #[serde(default = "four")]
    pub iterations: usize,
    /// Points per infill iteration.
    #[serde(default = "two")]
    pub batch: usize,
    /// Weights of E, ν, first crack, peak.
    #[serde(default = "unit_weights")]
    pub weights: [f64; 4],
    /// The virtual test (compression for Table 1).
    pub test: VirtualTest,
    /// Search intervals.
    pub bounds: CalibrationBounds,
}

/// Where the law's E and ν come from.
#[derive(Clone, Copy, Debug, Default, Deserialize, PartialEq, Eq, serde::Serialize, schemars::JsonSchema)]
#[serde(rename_all = "snake_case")]
pub enum ElasticSource {
    /// `[experiment]` young_modulus and poisson (paper §3.2b; else the DEM's means).
    #[default]
    Experiment,
    /// The virtual tests' mean initial modulus and Poisson ratio, so the law's elastic branch
    /// is the DEM's even when the calibration could not reach the measured E.
    Dem,
}

/// `[law.bounds]`: intervals of the five unknowns.
#[derive(Clone, Debug, Deserialize, PartialEq, schemars::JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct LawBounds {
    /// Tensile threshold ε₀^t.
    pub eps0_t: [f64; 2],
    /// Compressive threshold ε₀^c.
    pub eps0_c: [f64; 2],
    /// Softening energy G_s = f_t h / B_t [J/m²]: G_f under `hillerborg`, G_f − f_t² h/(2E)
    /// under `hillerborg_no_elastic` (identify::law_fit).
    pub gf_t: [f64; 2],
    /// A_c ∈ [0, 1].
    pub a_c: [f64; 2],
    /// B_c [1/strain].
    pub b_c: [f64; 2],
    /// Compressive fracture energy G_c [J/m²]: an optional sixth unknown.
    pub gf_c: Option<[f64; 2]>,
}

/// `[law.dem_curves]`: DEM curves from files instead of running the DEM.
#[derive(Clone, Debug, Deserialize, PartialEq, schemars::JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct DemCurveFiles {
    /// Tension curve CSV (columns strain, stress).
    pub tension: PathBuf,
    /// Compression curve CSV.
    pub compression: PathBuf,
}

/// `[law] variants`: the law fitted again to subsets of the samples (identify::variants).
#[derive(Clone, Debug, Deserialize, PartialEq, schemars::JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct LawVariants {
    /// How many variants (at least 2).
    pub count: usize,
    /// How their samples are chosen.
    pub scheme: VariantScheme,
    /// Seed of the bootstrap's draws (SplitMix64); unused by `halves`.
    #[serde(default = "one_u64")]
    pub seed: u64,
    /// The material file the variants' copies are named after, `<stem>-variant-<k>.toml` beside
    /// it (relative to the job file's folder; not itself written); default `[law] material_file`.
    pub material_file: Option<PathBuf>,
}

/// `[law]`: (b) the damage law from virtual tests.
#[derive(Clone, Debug, Deserialize, PartialEq, schemars::JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct LawIdentConfig {
    /// DEM samples per virtual test.
    #[serde(default = "four")]
    pub samples: usize,
    /// The tension test (needed unless `dem_curves`).
    pub tension: Option<VirtualTest>,
    /// The compression test (needed unless `dem_curves`).
    pub compression: Option<VirtualTest>,
    /// Curves from files.
    pub dem_curves: Option<DemCurveFiles>,
    /// Every sample's curve from files (`sample,strain,stress,loss_of_load`, as the chain
    /// writes them in `dem_*_samples.csv`), averaged by `mean`.
    pub dem_samples: Option<DemCurveFiles>,
    /// How the samples' curves are averaged.
    #[serde(default)]
    pub mean: crate::identify::curves::MeanKind,
    /// Hillerborg variant.
    #[serde(default = "hillerborg")]
    pub regularization: Regularization,
    /// The unilateral split of the identified law (`material::Split`; the paper's by default).
    #[serde(default)]
    pub split: crate::material::Split,
    /// Element size of the comparison [m]; default the sample height.
    pub element_size: Option<f64>,
    /// Where E and ν come from when not given here (default: the experiment, paper §3.2b).
    #[serde(default)]
    pub elastic: ElasticSource,
    /// E [Pa]; default per `elastic`.
    pub young_modulus: Option<f64>,
    /// ν; default the experiment's, else the DEM's mean.
    pub poisson: Option<f64>,
    /// Error measure.
    #[serde(default)]
    pub error: ErrorMeasure,
    /// Resampled points per curve.
    #[serde(default = "sixty")]
    pub points: usize,
    /// Factorial levels.
    #[serde(default = "default_levels")]
    pub levels: [f64; 2],
    /// EGO infill iterations.
    #[serde(default = "twelve")]
    pub iterations: usize,
    /// Points per infill iteration.
    #[serde(default = "two")]
    pub batch: usize,
    /// Nelder–Mead iterations of each polish from the best separated EGO points (0: none).
    #[serde(default = "four_hundred")]
    pub polish_iterations: u64,
    /// Search intervals.
    pub bounds: LawBounds,
    /// A copy of the material file (relative to the job file's folder).
    pub material_file: Option<PathBuf>,
    /// Comment lines for the material file's header, after the generated ones: why the values
    /// are what they are (identify::material_file).
    pub material_notes: Option<String>,
    /// Material variants (none by default).
    pub variants: Option<LawVariants>,
}

/// An identification job file, as written.
#[derive(Clone, Debug, Deserialize, PartialEq, schemars::JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct IdentifyJobFile {
    /// A one-line description.
    pub title: Option<String>,
    /// `[analysis]`.
    pub analysis: IdentifyAnalysis,
    /// The virtual wall.
    pub sample: SampleConfig,
    /// Fixed lattice parameters (and starting values).
    #[serde(default)]
    pub mechanics: MechanicsConfig,
    /// The measured numbers.
    pub experiment: Option<ExperimentConfig>,
    /// Stage (a).
    pub calibration: Option<CalibrationConfig>,
    /// Stage (b).
    pub law: Option<LawIdentConfig>,
    /// Where results go.
    #[serde(default)]
    pub output: OutputConfig,
}
