//! The job file of a DEM virtual test: a batch of random samples of one virtual wall, one test.
//!
//! ```toml
//! [analysis]
//! type = "dem"
//! samples = 16                 # samples with seeds seed, seed+1, ...: mean ± std in the summary
//! particle_states = "steps"    # HDF5/XDMF particle states per sample: "none" | "steps" | "all"
//! breaks_per_equilibrium = 1   # > 1: several beams break per equilibrium (approximate, opt-in)
//! factor_updates = "auto"      # "auto" | "in_place" | "woodbury": how the factor follows breaks
//! checkpoint_minutes = 10      # a checkpoint of each running test this often (0: none)
//! [sample]                     # dem::sample::SampleConfig
//! seed = 1
//! layout = { type = "coursed", width = 1.0, height = 1.2, n_courses = 10, n_per_course = 6, jitter = 0.2, size_variability = 0.2 }
//! [mechanics]                  # lattice parameters; defaults: the paper's Table 1 set
//! e_bar = 2.5e9
//! [test]                       # dem::solver::VirtualTest
//! type = "compression"
//! max_strain = 2.0e-3
//! steps = 40
//! [experiment]                 # optional: values to overlay and compare (Table 1)
//! young_modulus = 2.885e9
//! ```
use crate::dem::sample::SampleConfig;
use crate::dem::solver::{FactorUpdates, VirtualTest};
use serde::Deserialize;

/// `[analysis]` of a DEM job.
#[derive(Clone, Debug, Deserialize, PartialEq, schemars::JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct DemAnalysis {
    /// Always `"dem"`.
    #[serde(rename = "type")]
    pub kind: String,
    /// Number of random samples (seeds `sample.seed + k`), default 1.
    #[serde(default = "one")]
    pub samples: usize,
    /// Which recorded states go to `sample-KKK/particles.xdmf` (default: the ends of the load
    /// steps, the first crack, the peak and the last state; see `dem::solver::snapshots`).
    #[serde(default)]
    pub particle_states: crate::dem::solver::ParticleStates,
    /// Beams broken together before one re-equilibration (default 1: paper §2.1's exact
    /// algorithm). More is an approximation for large samples
    /// (`dem::solver::SolverOptions::breaks_per_equilibrium`); the summary says so.
    #[serde(default = "one")]
    pub breaks_per_equilibrium: usize,
    /// How the factorized operator follows breaks and contact changes (default `"auto"`: CHOLMOD's
    /// updates in place from 1,000 unknowns, a Woodbury correction below;
    /// `dem::solver::FactorUpdates`). The same physics either way, to round-off; in place is
    /// faster and lighter on large samples.
    #[serde(default = "auto")]
    pub factor_updates: FactorUpdates,
    /// Wall time between two checkpoints of a sample's running test [min] (default 10; 0: no
    /// checkpoints). Each sample's test writes `checkpoints/sample-KKK.ckpt` in the results
    /// folder when this much time has passed since its last one, and once when it ends;
    /// `masonry-hpc --restart` then takes a finished sample's result from its checkpoint and
    /// continues a running one from it (docs/running.md).
    #[serde(default = "ten")]
    pub checkpoint_minutes: f64,
}

fn ten() -> f64 {
    10.0
}

fn auto() -> FactorUpdates {
    FactorUpdates::Auto
}

fn one() -> usize {
    1
}

/// `[mechanics]`: the lattice's parameters (paper §2.1). Defaults are the paper's set
/// (Ē = 2.5 GPa, ε_cr = 1e-4, θ_cr = 7e-4, μ = 0.6); α is in `[sample]`.
#[derive(Clone, Debug, Deserialize, PartialEq, schemars::JsonSchema)]
#[serde(deny_unknown_fields, default)]
pub struct MechanicsConfig {
    /// Lattice Young modulus Ē [Pa].
    pub e_bar: f64,
    /// Critical beam strain ε_cr [-].
    pub eps_cr: f64,
    /// Critical relative rotation θ_cr [rad].
    pub theta_cr: f64,
    /// Friction coefficient μ [-].
    pub mu: f64,
    /// Tangential over normal contact stiffness [-].
    pub kt_over_kn: f64,
    /// Crushing stress σ_c [Pa] (an extension of paper §2.1, `dem::mechanics::crushing`): beams
    /// crush when their compressive stress reaches it, contact pressures are bounded by it and
    /// soften. Absent (default): paper §2.1's model, no compressive failure.
    pub crushing_stress: Option<f64>,
    /// Crushing fracture energy G_c [J/m²] (per contact area), the area under the contact's linear
    /// softening (plastic penetration at full crushing 2 G_c/σ_c); required with
    /// `crushing_stress`, and G_c > σ_c² ℓ_c/(2 Ē) at every contact.
    pub crushing_energy: Option<f64>,
}

impl Default for MechanicsConfig {
    fn default() -> Self {
        let d = crate::dem::mechanics::MechParams::default();
        MechanicsConfig {
            e_bar: d.e_bar,
            eps_cr: d.eps_cr,
            theta_cr: d.theta_cr,
            mu: d.mu,
            kt_over_kn: d.kt_over_kn,
            crushing_stress: None,
            crushing_energy: None,
        }
    }
}

impl MechanicsConfig {
    /// The solver's parameters for a sample of out-of-plane thickness `t_z`, checked; an invalid
    /// value is reported at its `[mechanics]` key in `source`.
    pub fn validated_params(
        &self,
        t_z: f64,
        source: &super::Source,
    ) -> Result<crate::dem::mechanics::MechParams, super::ConfigError> {
        let at =
            |key: &str, msg: String| source.error_at(&[super::Seg::key("mechanics"), super::Seg::Key(key.into())], msg);
        let crushing = match (self.crushing_stress, self.crushing_energy) {
            (None, None) => None,
            (Some(stress), Some(energy)) => Some(crate::dem::mechanics::Crushing { stress, energy }),
            (Some(_), None) => {
                return Err(at(
                    "crushing_stress",
                    "`crushing_stress` needs `crushing_energy` (J/m², the crushing fracture energy) beside it".into(),
                ))
            }
            (None, Some(_)) => {
                return Err(at("crushing_energy", "`crushing_energy` is used only with `crushing_stress` (Pa)".into()))
            }
        };
        let params = crate::dem::mechanics::MechParams {
            e_bar: self.e_bar,
            t_z,
            eps_cr: self.eps_cr,
            theta_cr: self.theta_cr,
            mu: self.mu,
            kt_over_kn: self.kt_over_kn,
            crushing,
        };
        params.validate().map_err(|e| {
            let mut at = vec![super::Seg::key("mechanics")];
            at.extend(e.quantity().map(super::Seg::key));
            source.error_at(&at, e.to_string())
        })?;
        Ok(params)
    }
}

/// `[experiment]`: measured values to compare with (all optional).
#[derive(Clone, Debug, Default, Deserialize, PartialEq, serde::Serialize, schemars::JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct ExperimentConfig {
    /// Young's modulus [Pa].
    pub young_modulus: Option<f64>,
    /// Poisson ratio [-].
    pub poisson: Option<f64>,
    /// First-crack stress [Pa].
    pub first_crack_stress: Option<f64>,
    /// Peak stress [Pa].
    pub peak_stress: Option<f64>,
    /// Where the numbers come from.
    pub source: Option<String>,
}

/// A DEM job file, as written.
#[derive(Clone, Debug, Deserialize, PartialEq, schemars::JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct DemJobFile {
    /// A one-line description.
    pub title: Option<String>,
    /// `[analysis]`.
    pub analysis: DemAnalysis,
    /// The virtual wall.
    pub sample: SampleConfig,
    /// Lattice parameters.
    #[serde(default)]
    pub mechanics: MechanicsConfig,
    /// The virtual test.
    pub test: VirtualTest,
    /// Values to compare with.
    pub experiment: Option<ExperimentConfig>,
    /// Where results go.
    #[serde(default)]
    pub output: super::OutputConfig,
}
