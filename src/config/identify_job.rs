//! An identification job loaded and checked: the stages' settings against each other and the
//! sample, the calibration's targets from `[experiment]`, and the DEM curves read from files
//! when `[law]` fits curves instead of running the DEM (the file's schema: [`super::identify`]).
use super::identify::{CalibrationConfig, ElasticSource, IdentifyJobFile, LawIdentConfig};
use super::{ConfigError, Seg, Source};
use crate::dem::solver::VirtualTest;
use crate::identify::variants::VariantScheme;
use crate::identify::{Curve, DemParameters, Targets};
use crate::material::Regularization;
use std::path::{Path, PathBuf};

/// A loaded, validated identification job.
pub struct IdentifyJob {
    /// The file and its text.
    pub source: Source,
    /// What it says.
    pub spec: IdentifyJobFile,
    /// The DEM parameters before calibration (α from `[sample]`, the rest from `[mechanics]`).
    pub dem: DemParameters,
    /// The calibration targets (all four given), when `[calibration]` is present.
    pub targets: Option<Targets>,
    /// DEM curves read from `[law.dem_curves]` (tension, compression), test direction.
    pub dem_curves: Option<(Curve, Curve)>,
    /// Every sample's curves read from `[law.dem_samples]` (tension, compression).
    pub dem_samples: Option<(Vec<Curve>, Vec<Curve>)>,
    /// `[law] material_file`, resolved.
    pub material_copy: Option<PathBuf>,
    /// The material file the variants' copies are named after (`[law.variants] material_file`,
    /// else `[law] material_file`), resolved.
    pub variants_beside: Option<PathBuf>,
    /// The results folder.
    pub output_dir: PathBuf,
}

/// What `[law]` brings besides its settings: curves read from files, the material file's copy.
#[derive(Default)]
struct LawInputs {
    dem_curves: Option<(Curve, Curve)>,
    dem_samples: Option<(Vec<Curve>, Vec<Curve>)>,
    material_copy: Option<PathBuf>,
    variants_beside: Option<PathBuf>,
}

impl IdentifyJob {
    /// Parses and checks the job in `source` (read from `path`): the sample and the lattice,
    /// then stage (a), then stage (b); the first problem found is returned.
    pub(super) fn from_source(source: Source, path: &Path) -> Result<IdentifyJob, ConfigError> {
        let spec: IdentifyJobFile = source.deserialize().map_err(|e| super::tagged::refine(&source, e))?;
        let folder = path.parent().map(Path::to_path_buf).unwrap_or_default();
        spec.sample.validate().map_err(|e| source.error_at(&[Seg::key("sample")], e.to_string()))?;
        let dem = starting_dem(&spec);
        spec.mechanics.validated_params(spec.sample.thickness, &source)?;
        if spec.calibration.is_none() && spec.law.is_none() {
            return Err(source.error_at(&[Seg::key("analysis")], "nothing to identify: add [calibration] (the DEM against the experiment), [law] (the damage law from virtual tests), or both"));
        }
        let targets = match &spec.calibration {
            Some(c) => Some(check_calibration(&source, &spec, c)?),
            None => None,
        };
        let law = match &spec.law {
            Some(l) => {
                check_law(&source, &spec, l)?;
                let inputs = law_inputs(&source, &folder, l)?;
                check_variants(&source, l, &inputs)?;
                inputs
            }
            None => LawInputs::default(),
        };
        let output_dir = super::output_dir(path, &spec.output);
        let LawInputs { dem_curves, dem_samples, material_copy, variants_beside } = law;
        Ok(IdentifyJob {
            source,
            spec,
            dem,
            targets,
            dem_curves,
            dem_samples,
            material_copy,
            variants_beside,
            output_dir,
        })
    }
}

/// The DEM parameters before calibration: α from `[sample]`, the rest from `[mechanics]`.
fn starting_dem(spec: &IdentifyJobFile) -> DemParameters {
    let m = &spec.mechanics;
    DemParameters {
        alpha: spec.sample.alpha,
        e_bar: m.e_bar,
        eps_cr: m.eps_cr,
        theta_cr: m.theta_cr,
        mu: m.mu,
        kt_over_kn: m.kt_over_kn,
        crushing_stress: m.crushing_stress,
        crushing_energy: m.crushing_energy,
    }
}

/// An interval at `keys`: finite, lower < upper, and (if `positive`) lower > 0.
fn interval(src: &Source, keys: &[&str], b: [f64; 2], positive: bool, what: &str) -> Result<(), ConfigError> {
    let [lo, hi] = b;
    if !(lo.is_finite() && hi.is_finite()) || lo >= hi {
        return Err(src.error_at(
            &Seg::path(keys),
            format!("expected bounds [lower, upper] with lower < upper, got [{lo}, {hi}]"),
        ));
    }
    if positive {
        src.positive_finite(&Seg::path(keys), lo, &format!("the lower bound of {what}"), "")?;
    }
    Ok(())
}

/// A count at `keys` of at least `min`.
fn count(src: &Source, keys: &[&str], v: usize, min: usize) -> Result<(), ConfigError> {
    if v < min {
        return Err(src.error_at(&Seg::path(keys), format!("expected at least {min}, got {v}")));
    }
    Ok(())
}

/// Stage (a): counts, the test (compression or tension), the bounds, the weights; returns
/// the targets, all four of which `[experiment]` must give.
fn check_calibration(src: &Source, spec: &IdentifyJobFile, c: &CalibrationConfig) -> Result<Targets, ConfigError> {
    count(src, &["calibration", "samples"], c.samples, 1)?;
    count(src, &["calibration", "design_points"], c.design_points, 2)?;
    count(src, &["calibration", "batch"], c.batch, 1)?;
    c.test.validate().map_err(|e| src.error_at(&Seg::path(&["calibration", "test"]), e.to_string()))?;
    if !matches!(c.test, VirtualTest::Compression { .. } | VirtualTest::Tension { .. }) {
        return Err(src.error_at(
            &Seg::path(&["calibration", "test"]),
            "the calibration fits a compression (or tension) test, not shear",
        ));
    }
    check_calibration_bounds(src, spec, c)?;
    let weights = Seg::path(&["calibration", "weights"]);
    for (i, w) in c.weights.iter().enumerate() {
        src.non_negative(&[weights.clone(), vec![Seg::Index(i)]].concat(), *w, "weight", "")?;
    }
    if c.weights.iter().all(|w| *w == 0.0) {
        return Err(src.error_at(&weights, "expected four finite weights >= 0, not all zero"));
    }
    if c.strategy == crate::identify::Strategy::Staged && c.weights[2] == 0.0 && c.weights[3] == 0.0 {
        return Err(src.error_at(
            &weights,
            "the staged strategy fits the first crack and the peak in its second stage, and both weights are 0: give one > 0, or strategy = \"joint\"",
        ));
    }
    calibration_targets(src, spec)
}

/// `[calibration.bounds]`: four positive intervals, and the crushing stress's only with a
/// fixed crushing energy.
fn check_calibration_bounds(src: &Source, spec: &IdentifyJobFile, c: &CalibrationConfig) -> Result<(), ConfigError> {
    let b = &c.bounds;
    interval(src, &["calibration", "bounds", "alpha"], b.alpha, true, "alpha")?;
    interval(src, &["calibration", "bounds", "e_bar"], b.e_bar, true, "e_bar")?;
    interval(src, &["calibration", "bounds", "eps_cr"], b.eps_cr, true, "eps_cr")?;
    interval(src, &["calibration", "bounds", "theta_cr"], b.theta_cr, true, "theta_cr")?;
    if let Some(sc) = b.crushing_stress {
        interval(src, &["calibration", "bounds", "crushing_stress"], sc, true, "crushing_stress")?;
        if spec.mechanics.crushing_energy.is_none() {
            return Err(src.error_at(
                &Seg::path(&["calibration", "bounds", "crushing_stress"]),
                "calibrating crushing_stress needs [mechanics] crushing_energy (J/m², fixed) and a crushing_stress (any value in the bounds)",
            ));
        }
    }
    Ok(())
}

/// The calibration's targets: `[experiment]`'s four values, each given and > 0.
fn calibration_targets(src: &Source, spec: &IdentifyJobFile) -> Result<Targets, ConfigError> {
    let ex = spec.experiment.clone().unwrap_or_default();
    let need = |v: Option<f64>, k: &str| -> Result<f64, ConfigError> {
        match v {
            Some(x) => src.positive_finite(&Seg::path(&["experiment", k]), x, k, ""),
            None => Err(src.error_at(
                &Seg::path(if spec.experiment.is_some() { &["experiment"] } else { &["calibration"] }),
                format!("the calibration needs [experiment] {k} (all of young_modulus, poisson, first_crack_stress, peak_stress)"),
            )),
        }
    };
    Ok(Targets {
        young_modulus: need(ex.young_modulus, "young_modulus")?,
        poisson: need(ex.poisson, "poisson")?,
        first_crack_stress: need(ex.first_crack_stress, "first_crack_stress")?,
        peak_stress: need(ex.peak_stress, "peak_stress")?,
    })
}

/// Stage (b)'s settings: counts, bounds, levels, a Hillerborg regularization, the element
/// size, explicit elastic constants, and where the DEM curves come from.
fn check_law(src: &Source, spec: &IdentifyJobFile, l: &LawIdentConfig) -> Result<(), ConfigError> {
    count(src, &["law", "samples"], l.samples, 1)?;
    count(src, &["law", "points"], l.points, 3)?;
    count(src, &["law", "batch"], l.batch, 1)?;
    check_law_bounds(src, l)?;
    let [lv0, lv1] = l.levels;
    if !(0.0..=1.0).contains(&lv0) || !(0.0..=1.0).contains(&lv1) || lv0 >= lv1 {
        return Err(
            src.error_at(&Seg::path(&["law", "levels"]), format!("expected 0 <= a < b <= 1, got [{lv0}, {lv1}]"))
        );
    }
    if let Regularization::Unregularized { .. } = l.regularization {
        return Err(src.error_at(
            &Seg::path(&["law", "regularization"]),
            "the identification fits G_f: use \"hillerborg\" or \"hillerborg_no_elastic\", not none",
        ));
    }
    let h = l.element_size.unwrap_or(spec.sample.layout.domain().1);
    src.positive_finite(&Seg::path(&["law", "element_size"]), h, "h", "m")?;
    if let Some(e) = l.young_modulus {
        src.positive_finite(&Seg::path(&["law", "young_modulus"]), e, "young_modulus", "Pa")?;
    }
    if let Some(nu) = l.poisson {
        if !(nu.is_finite() && nu > -1.0 && nu < 0.5) {
            return Err(src.error_at(&Seg::path(&["law", "poisson"]), format!("invalid poisson {nu}")));
        }
    }
    let from_files = l.dem_curves.is_some() || l.dem_samples.is_some();
    if from_files && l.elastic == ElasticSource::Dem && (l.young_modulus.is_none() || l.poisson.is_none()) {
        return Err(src.error_at(
            &Seg::path(&["law", "elastic"]),
            "elastic = \"dem\" needs the DEM to run; with dem_curves or dem_samples give young_modulus and poisson",
        ));
    }
    if l.dem_curves.is_some() && l.dem_samples.is_some() {
        return Err(src.error_at(
            &Seg::path(&["law", "dem_samples"]),
            "give dem_curves (mean curves) or dem_samples (every sample's curve), not both",
        ));
    }
    Ok(())
}

/// `[law.bounds]`: positive intervals, A_c within [0, 1] and, with a compressive fracture
/// energy to fit, above 0 throughout.
///
/// Every point of the box is admissible under either Hillerborg variant: the tensile energy
/// unknown is the softening energy G_s > 0 (identify::law_fit), and the no-elastic variant's
/// G_f = G_s + f_t² h/(2E) stays above its limit f_t² h/(2E).
fn check_law_bounds(src: &Source, l: &LawIdentConfig) -> Result<(), ConfigError> {
    let b = &l.bounds;
    interval(src, &["law", "bounds", "eps0_t"], b.eps0_t, true, "the tensile threshold eps0_t")?;
    interval(src, &["law", "bounds", "eps0_c"], b.eps0_c, true, "the compressive threshold eps0_c")?;
    interval(src, &["law", "bounds", "gf_t"], b.gf_t, true, "the fracture energy gf_t")?;
    interval(src, &["law", "bounds", "b_c"], b.b_c, true, "b_c")?;
    interval(src, &["law", "bounds", "a_c"], b.a_c, false, "a_c")?;
    let a_c = Seg::path(&["law", "bounds", "a_c"]);
    if let Some(g) = b.gf_c {
        interval(src, &["law", "bounds", "gf_c"], g, true, "the compressive fracture energy gf_c")?;
        let what = "with bounds.gf_c (it regularizes the decaying part A_c), the lower bound of a_c";
        src.positive_finite(&a_c, b.a_c[0], what, "")?;
    }
    if b.a_c[0] < 0.0 || b.a_c[1] > 1.0 {
        return Err(src.error_at(&a_c, format!("a_c must lie in [0, 1], got bounds [{}, {}]", b.a_c[0], b.a_c[1])));
    }
    Ok(())
}

/// Stage (b)'s inputs: every sample's curves (`dem_samples`), else the mean curves
/// (`dem_curves`), read and checked, else the two virtual tests checked; and the material
/// file's copy, resolved against `folder`.
fn law_inputs(src: &Source, folder: &Path, l: &LawIdentConfig) -> Result<LawInputs, ConfigError> {
    let mut inputs = LawInputs::default();
    if let Some(files) = &l.dem_samples {
        let read = |name: &str, p: &Path| read_sample_curves(src, folder, name, p);
        inputs.dem_samples = Some((read("tension", &files.tension)?, read("compression", &files.compression)?));
    }
    match &l.dem_curves {
        _ if l.dem_samples.is_some() => {}
        Some(files) => {
            let read = |name: &str, p: &Path| read_mean_curve(src, folder, name, p);
            inputs.dem_curves = Some((read("tension", &files.tension)?, read("compression", &files.compression)?));
        }
        None => check_law_tests(src, l)?,
    }
    inputs.material_copy = l.material_file.as_ref().map(|p| super::resolve(folder, p));
    inputs.variants_beside = l
        .variants
        .as_ref()
        .and_then(|v| v.material_file.as_ref())
        .map(|p| super::resolve(folder, p))
        .or_else(|| inputs.material_copy.clone());
    Ok(inputs)
}

/// `[law] variants`: at least 2; the samples' curves at hand (the virtual tests or
/// `dem_samples`, not the mean curves of `dem_curves`); `halves` with a sample for each group in
/// each test (the job's `samples`, or the curves in the files).
fn check_variants(src: &Source, l: &LawIdentConfig, inputs: &LawInputs) -> Result<(), ConfigError> {
    let Some(v) = &l.variants else { return Ok(()) };
    let at_count = Seg::path(&["law", "variants", "count"]);
    if v.count < 2 {
        return Err(src.error_at(
            &at_count,
            format!(
                "material variants: expected a count of at least 2, got {} (the main law is the fit to all samples)",
                v.count
            ),
        ));
    }
    if inputs.dem_curves.is_some() {
        return Err(src.error_at(
            &Seg::path(&["law", "variants"]),
            "material variants are fitted to subsets of the samples: they need every sample's curve (the virtual tests, or dem_samples), not the mean curves of dem_curves",
        ));
    }
    if v.scheme != VariantScheme::Halves {
        return Ok(());
    }
    let (n_t, n_c, from) = match &inputs.dem_samples {
        Some((t, c)) => (t.len(), c.len(), "in its dem_samples file"),
        None => (l.samples, l.samples, "([law] samples)"),
    };
    for (test, n) in [("tension", n_t), ("compression", n_c)] {
        if n < v.count {
            return Err(src.error_at(
                &at_count,
                format!("scheme \"halves\" deals each test's samples into {} groups, and the {test} test has {n} sample(s) {from}: give at most {n} variants", v.count),
            ));
        }
    }
    Ok(())
}

/// `[law.dem_samples] <name>`: every sample's curve of one test, each checked.
fn read_sample_curves(src: &Source, folder: &Path, name: &str, p: &Path) -> Result<Vec<Curve>, ConfigError> {
    let at = Seg::path(&["law", "dem_samples", name]);
    let file = super::resolve(folder, p);
    let curves =
        crate::identify::curves::read_sample_curves_csv(&file).map_err(|m| src.error_at(&at, m.to_string()))?;
    for (k, c) in curves.iter().enumerate() {
        c.check(&format!("DEM {name} curve of sample {k} in {}", file.display()))
            .map_err(|e| src.error_at(&at, e.to_string()))?;
    }
    Ok(curves)
}

/// `[law.dem_curves] <name>`: the mean curve of one test, checked.
fn read_mean_curve(src: &Source, folder: &Path, name: &str, p: &Path) -> Result<Curve, ConfigError> {
    let at = Seg::path(&["law", "dem_curves", name]);
    let file = super::resolve(folder, p);
    let what = format!("DEM {name} curve {}", file.display());
    let c = crate::identify::curves::read_curve_csv(&file).map_err(|m| src.error_at(&at, m.to_string()))?;
    c.check(&what).map_err(|e| src.error_at(&at, e.to_string()))?;
    Ok(c)
}

/// `[law] tension` and `compression` when the DEM runs: both given, valid, of their type.
fn check_law_tests(src: &Source, l: &LawIdentConfig) -> Result<(), ConfigError> {
    for (k, t, tension) in [("tension", &l.tension, true), ("compression", &l.compression, false)] {
        let Some(t) = t else {
            return Err(src.error_at(&[Seg::key("law")], format!("[law] needs {k} = {{ type = \"{k}\", max_strain = ..., steps = ... }}, or dem_curves, or dem_samples")));
        };
        t.validate().map_err(|e| src.error_at(&Seg::path(&["law", k]), e.to_string()))?;
        let right = if tension {
            matches!(t, VirtualTest::Tension { .. })
        } else {
            matches!(t, VirtualTest::Compression { .. })
        };
        if !right {
            return Err(src.error_at(&Seg::path(&["law", k]), format!("expected type = \"{k}\"")));
        }
    }
    Ok(())
}
