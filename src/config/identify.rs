//! The job file of an identification (SPEC §3): (a) calibrate the DEM against experimental
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
//! ```
use super::{ExperimentConfig, MechanicsConfig, OutputConfig};
use crate::dem::sample::SampleConfig;
use crate::dem::solver::VirtualTest;
use crate::identify::ErrorMeasure;
use crate::material::Regularization;
use serde::Deserialize;
use std::path::PathBuf;

/// `[analysis]`.
#[derive(Clone, Debug, Deserialize, PartialEq)]
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
#[derive(Clone, Debug, Deserialize, PartialEq)]
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
#[derive(Clone, Debug, Deserialize, PartialEq)]
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
#[derive(Clone, Copy, Debug, Default, Deserialize, PartialEq, Eq, serde::Serialize)]
#[serde(rename_all = "snake_case")]
pub enum ElasticSource {
    /// `[experiment]` young_modulus and poisson (SPEC §3b; else the DEM's means).
    #[default]
    Experiment,
    /// The virtual tests' mean initial modulus and Poisson ratio, so the law's elastic branch
    /// is the DEM's even when the calibration could not reach the measured E.
    Dem,
}

/// `[law.bounds]`: intervals of the five unknowns.
#[derive(Clone, Debug, Deserialize, PartialEq)]
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
#[derive(Clone, Debug, Deserialize, PartialEq)]
#[serde(deny_unknown_fields)]
pub struct DemCurveFiles {
    /// Tension curve CSV (columns strain, stress).
    pub tension: PathBuf,
    /// Compression curve CSV.
    pub compression: PathBuf,
}

/// `[law]`: (b) the damage law from virtual tests.
#[derive(Clone, Debug, Deserialize, PartialEq)]
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
    /// Element size of the comparison [m]; default the sample height.
    pub element_size: Option<f64>,
    /// Where E and ν come from when not given here (default: the experiment, SPEC §3b).
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
}

/// An identification job file, as written.
#[derive(Clone, Debug, Deserialize, PartialEq)]
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

/// A loaded, validated identification job.
pub struct IdentifyJob {
    /// The file and its text.
    pub source: super::Source,
    /// What it says.
    pub spec: IdentifyJobFile,
    /// The DEM parameters before calibration (α from `[sample]`, the rest from `[mechanics]`).
    pub dem: crate::identify::DemParameters,
    /// The calibration targets (all four given), when `[calibration]` is present.
    pub targets: Option<crate::identify::Targets>,
    /// DEM curves read from `[law.dem_curves]` (tension, compression), test direction.
    pub dem_curves: Option<(crate::identify::Curve, crate::identify::Curve)>,
    /// Every sample's curves read from `[law.dem_samples]` (tension, compression).
    pub dem_samples: Option<(Vec<crate::identify::Curve>, Vec<crate::identify::Curve>)>,
    /// `[law] material_file`, resolved.
    pub material_copy: Option<PathBuf>,
    /// The results folder.
    pub output_dir: PathBuf,
}

impl IdentifyJob {
    pub(super) fn from_source(
        source: super::Source,
        path: &std::path::Path,
    ) -> Result<IdentifyJob, super::ConfigError> {
        use super::Seg;
        let spec: IdentifyJobFile = source.deserialize().map_err(|e| super::tagged::refine(&source, e))?;
        let at = |keys: &[&str]| keys.iter().map(|k| Seg::key(k)).collect::<Vec<_>>();
        let folder = path.parent().map(std::path::Path::to_path_buf).unwrap_or_default();
        spec.sample.validate().map_err(|e| source.error_at(&[Seg::key("sample")], e.to_string()))?;
        let m = &spec.mechanics;
        let dem = crate::identify::DemParameters {
            alpha: spec.sample.alpha,
            e_bar: m.e_bar,
            eps_cr: m.eps_cr,
            theta_cr: m.theta_cr,
            mu: m.mu,
            kt_over_kn: m.kt_over_kn,
            crushing_stress: m.crushing_stress,
            crushing_energy: m.crushing_energy,
        };
        m.validated_params(spec.sample.thickness, &source)?;
        // An interval: finite, lower < upper, and (if `positive`) lower > 0.
        let interval = |keys: &[&str], b: [f64; 2], positive: bool, what: &str| -> Result<(), super::ConfigError> {
            let [lo, hi] = b;
            if !(lo.is_finite() && hi.is_finite()) || lo >= hi {
                return Err(source.error_at(
                    &at(keys),
                    format!("expected bounds [lower, upper] with lower < upper, got [{lo}, {hi}]"),
                ));
            }
            if positive && lo <= 0.0 {
                return Err(source.error_at(&at(keys), format!("{what} must be > 0: the lower bound is {lo}")));
            }
            Ok(())
        };
        if spec.calibration.is_none() && spec.law.is_none() {
            return Err(source.error_at(&[Seg::key("analysis")], "nothing to identify: add [calibration] (the DEM against the experiment), [law] (the damage law from virtual tests), or both"));
        }
        let count = |keys: &[&str], v: usize, min: usize| -> Result<(), super::ConfigError> {
            if v < min {
                return Err(source.error_at(&at(keys), format!("expected at least {min}, got {v}")));
            }
            Ok(())
        };
        let mut targets = None;
        if let Some(c) = &spec.calibration {
            count(&["calibration", "samples"], c.samples, 1)?;
            count(&["calibration", "design_points"], c.design_points, 2)?;
            count(&["calibration", "batch"], c.batch, 1)?;
            c.test.validate().map_err(|e| source.error_at(&at(&["calibration", "test"]), e.to_string()))?;
            if !matches!(c.test, VirtualTest::Compression { .. } | VirtualTest::Tension { .. }) {
                return Err(source.error_at(
                    &at(&["calibration", "test"]),
                    "the calibration fits a compression (or tension) test, not shear",
                ));
            }
            let b = &c.bounds;
            interval(&["calibration", "bounds", "alpha"], b.alpha, true, "alpha")?;
            interval(&["calibration", "bounds", "e_bar"], b.e_bar, true, "e_bar")?;
            interval(&["calibration", "bounds", "eps_cr"], b.eps_cr, true, "eps_cr")?;
            interval(&["calibration", "bounds", "theta_cr"], b.theta_cr, true, "theta_cr")?;
            if let Some(sc) = b.crushing_stress {
                interval(&["calibration", "bounds", "crushing_stress"], sc, true, "crushing_stress")?;
                if m.crushing_energy.is_none() {
                    return Err(source.error_at(
                        &at(&["calibration", "bounds", "crushing_stress"]),
                        "calibrating crushing_stress needs [mechanics] crushing_energy (J/m², fixed) and a crushing_stress (any value in the bounds)",
                    ));
                }
            }
            if c.weights.iter().any(|w| !(w.is_finite() && *w >= 0.0)) || c.weights.iter().all(|w| *w == 0.0) {
                return Err(source
                    .error_at(&at(&["calibration", "weights"]), "expected four finite weights >= 0, not all zero"));
            }
            if c.strategy == crate::identify::Strategy::Staged && c.weights[2] == 0.0 && c.weights[3] == 0.0 {
                return Err(source.error_at(
                    &at(&["calibration", "weights"]),
                    "the staged strategy fits the first crack and the peak in its second stage, and both weights are 0: give one > 0, or strategy = \"joint\"",
                ));
            }
            let ex = spec.experiment.clone().unwrap_or_default();
            let need = |v: Option<f64>, k: &str| -> Result<f64, super::ConfigError> {
                match v {
                    Some(x) if x.is_finite() && x > 0.0 => Ok(x),
                    Some(x) => Err(source.error_at(&at(&["experiment", k]), format!("expected a value > 0, got {x}"))),
                    None => Err(source.error_at(
                        &at(if spec.experiment.is_some() { &["experiment"] } else { &["calibration"] }),
                        format!("the calibration needs [experiment] {k} (all of young_modulus, poisson, first_crack_stress, peak_stress)"),
                    )),
                }
            };
            targets = Some(crate::identify::Targets {
                young_modulus: need(ex.young_modulus, "young_modulus")?,
                poisson: need(ex.poisson, "poisson")?,
                first_crack_stress: need(ex.first_crack_stress, "first_crack_stress")?,
                peak_stress: need(ex.peak_stress, "peak_stress")?,
            });
        }
        let mut dem_curves = None;
        let mut dem_samples = None;
        let mut material_copy = None;
        if let Some(l) = &spec.law {
            count(&["law", "samples"], l.samples, 1)?;
            count(&["law", "points"], l.points, 3)?;
            count(&["law", "batch"], l.batch, 1)?;
            let b = &l.bounds;
            interval(&["law", "bounds", "eps0_t"], b.eps0_t, true, "the tensile threshold eps0_t")?;
            interval(&["law", "bounds", "eps0_c"], b.eps0_c, true, "the compressive threshold eps0_c")?;
            interval(&["law", "bounds", "gf_t"], b.gf_t, true, "the fracture energy gf_t")?;
            interval(&["law", "bounds", "b_c"], b.b_c, true, "b_c")?;
            interval(&["law", "bounds", "a_c"], b.a_c, false, "a_c")?;
            if let Some(g) = b.gf_c {
                interval(&["law", "bounds", "gf_c"], g, true, "the compressive fracture energy gf_c")?;
                if b.a_c[0] <= 0.0 {
                    return Err(source.error_at(
                        &at(&["law", "bounds", "a_c"]),
                        format!("with bounds.gf_c, a_c must be > 0 throughout (gf_c regularizes the decaying part A_c), got the lower bound {}", b.a_c[0]),
                    ));
                }
            }
            if b.a_c[0] < 0.0 || b.a_c[1] > 1.0 {
                return Err(source.error_at(
                    &at(&["law", "bounds", "a_c"]),
                    format!("a_c must lie in [0, 1], got bounds [{}, {}]", b.a_c[0], b.a_c[1]),
                ));
            }
            let [lv0, lv1] = l.levels;
            if !(0.0..=1.0).contains(&lv0) || !(0.0..=1.0).contains(&lv1) || lv0 >= lv1 {
                return Err(
                    source.error_at(&at(&["law", "levels"]), format!("expected 0 <= a < b <= 1, got [{lv0}, {lv1}]"))
                );
            }
            if let Regularization::Unregularized { .. } = l.regularization {
                return Err(source.error_at(
                    &at(&["law", "regularization"]),
                    "the identification fits G_f: use \"hillerborg\" or \"hillerborg_no_elastic\", not none",
                ));
            }
            let h = l.element_size.unwrap_or(spec.sample.layout.domain().1);
            if !(h.is_finite() && h > 0.0) {
                return Err(source.error_at(&at(&["law", "element_size"]), format!("expected h > 0 [m], got {h}")));
            }
            for (k, v) in [("young_modulus", l.young_modulus), ("poisson", l.poisson)] {
                if let Some(x) = v {
                    let ok =
                        if k == "poisson" { x.is_finite() && x > -1.0 && x < 0.5 } else { x.is_finite() && x > 0.0 };
                    if !ok {
                        return Err(source.error_at(&at(&["law", k]), format!("invalid {k} {x}")));
                    }
                }
            }
            // Every point of the box is admissible under either Hillerborg variant: the tensile
            // energy unknown is the softening energy G_s > 0 (identify::law_fit), and the
            // no-elastic variant's G_f = G_s + f_t² h/(2E) stays above its limit f_t² h/(2E).
            let from_files = l.dem_curves.is_some() || l.dem_samples.is_some();
            if from_files && l.elastic == ElasticSource::Dem && (l.young_modulus.is_none() || l.poisson.is_none()) {
                return Err(source.error_at(
                    &at(&["law", "elastic"]),
                    "elastic = \"dem\" needs the DEM to run; with dem_curves or dem_samples give young_modulus and poisson",
                ));
            }
            if l.dem_curves.is_some() && l.dem_samples.is_some() {
                return Err(source.error_at(
                    &at(&["law", "dem_samples"]),
                    "give dem_curves (mean curves) or dem_samples (every sample's curve), not both",
                ));
            }
            if let Some(files) = &l.dem_samples {
                let read =
                    |name: &str, p: &std::path::Path| -> Result<Vec<crate::identify::Curve>, super::ConfigError> {
                        let file = super::resolve(&folder, p);
                        let curves = crate::identify::curves::read_sample_curves_csv(&file)
                            .map_err(|m| source.error_at(&at(&["law", "dem_samples", name]), m))?;
                        for (k, c) in curves.iter().enumerate() {
                            c.check(&format!("DEM {name} curve of sample {k} in {}", file.display()))
                                .map_err(|e| source.error_at(&at(&["law", "dem_samples", name]), e.to_string()))?;
                        }
                        Ok(curves)
                    };
                dem_samples = Some((read("tension", &files.tension)?, read("compression", &files.compression)?));
            }
            match &l.dem_curves {
                _ if l.dem_samples.is_some() => {}
                Some(files) => {
                    let read =
                        |name: &str, p: &std::path::Path| -> Result<crate::identify::Curve, super::ConfigError> {
                            let file = super::resolve(&folder, p);
                            let what = format!("DEM {name} curve {}", file.display());
                            let c = crate::identify::curves::read_curve_csv(&file)
                                .map_err(|m| source.error_at(&at(&["law", "dem_curves", name]), m))?;
                            c.check(&what)
                                .map_err(|e| source.error_at(&at(&["law", "dem_curves", name]), e.to_string()))?;
                            Ok(c)
                        };
                    dem_curves = Some((read("tension", &files.tension)?, read("compression", &files.compression)?));
                }
                None => {
                    for (k, t, tension) in [("tension", &l.tension, true), ("compression", &l.compression, false)] {
                        let Some(t) = t else {
                            return Err(source.error_at(&at(&["law"]), format!("[law] needs {k} = {{ type = \"{k}\", max_strain = ..., steps = ... }}, or dem_curves, or dem_samples")));
                        };
                        t.validate().map_err(|e| source.error_at(&at(&["law", k]), e.to_string()))?;
                        let right = if tension {
                            matches!(t, VirtualTest::Tension { .. })
                        } else {
                            matches!(t, VirtualTest::Compression { .. })
                        };
                        if !right {
                            return Err(source.error_at(&at(&["law", k]), format!("expected type = \"{k}\"")));
                        }
                    }
                }
            }
            material_copy = l.material_file.as_ref().map(|p| super::resolve(&folder, p));
        }
        let output_dir = super::output_dir(path, &spec.output);
        Ok(IdentifyJob { source, spec, dem, targets, dem_curves, dem_samples, material_copy, output_dir })
    }
}
