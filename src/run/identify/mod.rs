//! The identification job (paper §3.2): (a) DEM calibration against the experiment, (b) damage-law
//! identification from the (calibrated) DEM's virtual tests, (c) both as one chain ending in a
//! material file. Phases, each collective and followed by an agreement on errors:
//!
//! ```text
//!  calibrate      staged: elastic α, Ē (1-D root) → calibration_elastic.csv
//!                 then strengths: LHS × samples → EGO (q-EI); or joint: all unknowns by EGO
//!                                                 → calibration.json/.csv, calibration.png
//!  virtual tests  tension + compression × samples → dem_tension.csv, dem_compression.csv
//!  identify law   2⁵ factorial → EGO (q-EI)       → law.csv, law_error.png, law_tension.png,
//!                                                   law_compression.png, material.toml
//!  variants       ([law] variants) the same fit on each subset of the samples
//!                                                 → material-variant-<k>.toml
//! ```
//! Rank 0 writes every file (`files.rs`, the material file's provenance in `provenance.rs`);
//! `summary.json` gathers the numbers and the phase timings. The variants' driver is
//! `variants.rs`.
mod files;
mod provenance;
mod variants;

use crate::config::{CalibrationConfig, ElasticSource, ExperimentConfig, IdentifyJob, LawIdentConfig};
use crate::dem::solver::VirtualTest;
use crate::error::{Error, JobError};
use crate::identify::calibration::CalibrationResult;
use crate::identify::collective::broadcast_json;
use crate::identify::curves::{mean_of, sample_curves_csv, Curve};
use crate::identify::virtual_tests::run_virtual_tests;
use crate::identify::Stat;
use crate::identify::{
    calibrate, identify, Calibration, DemParameters, EgoSettings, IdentifyError, LawFit, LawResult, Space, Targets,
};
use crate::parallel::{agree, timed, Context, Phases};
use files::{write_calibration, write_dem_curves, write_law, write_text};
use serde::Serialize;
use std::path::Path;

/// What an identification reports (`summary.json`).
#[derive(Clone, Debug, Default, Serialize)]
pub struct IdentifySummary {
    /// Ranks.
    pub ranks: usize,
    /// Stage (a), if it ran.
    pub calibration: Option<CalibrationResult>,
    /// Whether each sample mean is within 5% of its target (named by quantity: E, ν, first
    /// crack, peak).
    #[serde(with = "crate::identify::calibration::quantity_names::option")]
    pub calibration_within_5_percent: Option<[bool; 4]>,
    /// Stage (b), if it ran.
    pub law: Option<LawResult>,
    /// The material file written.
    pub material_file: Option<String>,
    /// The material variants fitted (`[law] variants`), in order.
    pub variants: Vec<variants::VariantSummary>,
    /// Failed DEM samples of the virtual tests.
    pub virtual_test_failures: Vec<String>,
    /// Wall time per phase [s]: calibration, virtual tests, law identification.
    pub seconds: PhaseSeconds,
}

/// Wall time per phase [s].
#[derive(Clone, Debug, Default, Serialize)]
pub struct PhaseSeconds {
    /// DEM calibration.
    pub calibration: f64,
    /// Virtual tests of the calibrated DEM.
    pub virtual_tests: f64,
    /// Damage-law identification.
    pub law: f64,
    /// The material variants' fits.
    pub variants: f64,
    /// The whole job.
    pub total: f64,
}

fn analysis_err(e: IdentifyError) -> Error {
    Error::from(e)
}

/// Collective. Runs the job's stages and writes the outputs; the phases' wall times go to the
/// summary.
pub fn run(ctx: &Context, path: &Path, job: &IdentifyJob) -> Result<IdentifySummary, Error> {
    let mut phases = Phases::default();
    let (summary, total) = timed(|| run_stages(ctx, path, job, &mut phases));
    let mut summary = summary?;
    let [calibration, virtual_tests, law, variants] =
        phases.seconds_of(["calibration", "virtual tests", "law", "variants"]);
    summary.seconds = PhaseSeconds { calibration, virtual_tests, law, variants, total };
    ctx.log.info(format!(
        "identification wall time {:.2} s (calibration {:.2} s, virtual tests {:.2} s, law {:.2} s, variants {:.2} s) on {} rank(s)",
        summary.seconds.total,
        summary.seconds.calibration,
        summary.seconds.virtual_tests,
        summary.seconds.law,
        summary.seconds.variants,
        ctx.size
    ));
    Ok(summary)
}

/// Collective. Stage (a) when `[calibration]` is given, then stage (b) when `[law]` is: the
/// DEM's curves ("virtual tests"), the law fitted to them ("law"), then its variants
/// ("variants") when `[law] variants` is given.
fn run_stages(ctx: &Context, path: &Path, job: &IdentifyJob, phases: &mut Phases) -> Result<IdentifySummary, Error> {
    let spec = &job.spec;
    let mut summary = IdentifySummary { ranks: ctx.size, ..Default::default() };
    let mut dem = job.dem;
    if let (Some(c), Some(targets)) = (&spec.calibration, job.targets) {
        dem = phases.time("calibration", || calibrate_dem(ctx, job, c, targets, &mut summary))?;
    }
    if let Some(l) = &spec.law {
        let DemCurves { reference, samples } =
            phases.time("virtual tests", || dem_reference(ctx, job, l, &dem, &mut summary))?;
        let fit = phases.time("law", || identify_law(ctx, path, job, l, reference, samples.as_ref(), &mut summary))?;
        if let Some(v) = &l.variants {
            let fitted = phases
                .time("variants", || variants::fit_variants(ctx, path, job, l, v, &fit, samples.as_ref(), &summary))?;
            summary.variants = fitted;
        }
    }
    Ok(summary)
}

/// Collective. Stage (a): the DEM calibrated against the experiment's `targets`, its files
/// written; the calibrated parameters on every rank (the job's when the search found none).
fn calibrate_dem(
    ctx: &Context,
    job: &IdentifyJob,
    c: &CalibrationConfig,
    targets: Targets,
    summary: &mut IdentifySummary,
) -> Result<DemParameters, Error> {
    let spec = &job.spec;
    let seed = spec.analysis.seed;
    let b = &c.bounds;
    let mut unknowns = vec![("alpha", b.alpha), ("e_bar", b.e_bar), ("eps_cr", b.eps_cr), ("theta_cr", b.theta_cr)];
    if let Some(sc) = b.crushing_stress {
        unknowns.push(("crushing_stress", sc));
    }
    let space = Space::new(&unknowns).map_err(analysis_err)?;
    let cal = Calibration {
        sample: spec.sample.clone(),
        fixed: job.dem,
        test: c.test.clone(),
        samples: c.samples,
        space,
        targets,
        weights: c.weights,
        design_points: c.design_points,
        seed,
        ego: EgoSettings { iterations: c.iterations, batch: c.batch, seed, log_transform: true, target: None },
        strategy: c.strategy,
    };
    let result = agree(&ctx.comm, calibrate(ctx, &cal).map_err(analysis_err), Error::exit_code)?;
    let written = match &result {
        Some(r) => write_calibration(ctx, job, r).map(|_| r.parameters),
        None => Ok(job.dem),
    };
    let calibrated = agree(&ctx.comm, written, Error::exit_code)?;
    let dem = broadcast_json(ctx, Some(&calibrated)).map_err(analysis_err)?;
    summary.calibration_within_5_percent = result.as_ref().map(|r| r.relative_errors.map(|e| e.abs() < 0.05));
    summary.calibration = result;
    Ok(dem)
}

/// The DEM's mean curves that the law is fitted to, on rank 0.
struct Reference {
    tension: Curve,
    compression: Curve,
    /// Whether they are already on a uniform grid from 0 (means of samples are).
    gridded: bool,
    /// The virtual tests' mean E [Pa] and ν (NaN when the curves come from files).
    young_modulus: f64,
    poisson: f64,
    /// The samples' peaks (tension, compression), when the samples are known.
    sample_peaks: Option<[Stat; 2]>,
}

/// The DEM's side of stage (b): rank 0's [`Reference`] (`None` on the others) and the samples'
/// curves for the pictures.
struct DemCurves {
    reference: Option<Reference>,
    samples: Option<(Vec<Curve>, Vec<Curve>)>,
}

/// Collective. The DEM's curves for stage (b): the mean curves of `[law.dem_curves]`, the means
/// of the sample curves of `[law.dem_samples]`, or the virtual tests of `dem` run now (their
/// curves written).
fn dem_reference(
    ctx: &Context,
    job: &IdentifyJob,
    l: &LawIdentConfig,
    dem: &DemParameters,
    summary: &mut IdentifySummary,
) -> Result<DemCurves, Error> {
    let samples = job.dem_samples.clone();
    let reference: Result<Option<Reference>, Error> = match (&job.dem_curves, &job.dem_samples) {
        (Some((t, c)), _) => Ok(Some(Reference {
            tension: t.clone(),
            compression: c.clone(),
            gridded: false,
            young_modulus: f64::NAN,
            poisson: f64::NAN,
            sample_peaks: None,
        })),
        (None, Some((ts, cs))) if ctx.rank == 0 => mean_of_samples(l, ts, cs).map(Some),
        (None, Some(_)) => Ok(None),
        (None, None) => return run_virtual_dem(ctx, job, l, dem, summary),
    };
    let reference = agree(&ctx.comm, reference, Error::exit_code)?;
    Ok(DemCurves { reference, samples })
}

/// Rank 0. The reference of sample curves read from files: their means (`[law] mean`) on about
/// `points` points up to each test's largest strain, and their peaks.
fn mean_of_samples(l: &LawIdentConfig, ts: &[Curve], cs: &[Curve]) -> Result<Reference, Error> {
    let peaks = |s: &[Curve]| Stat::of(&s.iter().map(|c| c.peak().0).collect::<Vec<_>>());
    let tension = mean_of(l.mean, ts, test_max_strain(&l.tension, ts), l.points, "DEM tension curve");
    let compression = mean_of(l.mean, cs, test_max_strain(&l.compression, cs), l.points, "DEM compression curve");
    Ok(Reference {
        tension: tension.map_err(analysis_err)?,
        compression: compression.map_err(analysis_err)?,
        gridded: true,
        young_modulus: f64::NAN,
        poisson: f64::NAN,
        sample_peaks: Some([peaks(ts), peaks(cs)]),
    })
}

/// The largest strain of a test: its `max_strain`, or the samples' last strain.
fn test_max_strain(t: &Option<VirtualTest>, samples: &[Curve]) -> f64 {
    match t {
        Some(VirtualTest::Tension { max_strain, .. } | VirtualTest::Compression { max_strain, .. }) => *max_strain,
        _ => samples.iter().map(|c| c.x[c.x.len() - 1]).fold(0.0, f64::max),
    }
}

/// Collective. The virtual tension and compression tests of `dem`, `[law] samples` each; rank 0
/// logs them and writes their curves (`dem_*.csv`, `dem_*_samples.csv`).
fn run_virtual_dem(
    ctx: &Context,
    job: &IdentifyJob,
    l: &LawIdentConfig,
    dem: &DemParameters,
    summary: &mut IdentifySummary,
) -> Result<DemCurves, Error> {
    let (Some(tt), Some(ct)) = (&l.tension, &l.compression) else {
        return Err(JobError::LawWithoutTests.into());
    };
    let v = run_virtual_tests(ctx, &job.spec.sample, dem, tt, ct, l.samples, l.points, l.mean).map_err(analysis_err);
    let Some(v) = agree(&ctx.comm, v, Error::exit_code)? else {
        return Ok(DemCurves { reference: agree(&ctx.comm, Ok(None), Error::exit_code)?, samples: None });
    };
    for f in &v.failures {
        ctx.log.warn(f);
    }
    summary.virtual_test_failures = v.failures.clone();
    ctx.log.info(format!(
        "virtual tests: E = {:.4e} Pa, nu = {:.4} (compression means); sample peaks: tension {:.4e} ± {:.2e} Pa (n = {}), compression {:.4e} ± {:.2e} Pa (n = {})",
        v.young_modulus, v.poisson, v.peaks[0].mean, v.peaks[0].std, v.peaks[0].n, v.peaks[1].mean, v.peaks[1].std, v.peaks[1].n
    ));
    let dir = &job.output_dir;
    let written = write_dem_curves(job, &v.tension_samples, &v.tension, "dem_tension.csv")
        .and_then(|_| write_dem_curves(job, &v.compression_samples, &v.compression, "dem_compression.csv"))
        .and_then(|_| write_text(&dir.join("dem_tension_samples.csv"), &sample_curves_csv(&v.tension_samples)))
        .and_then(|_| write_text(&dir.join("dem_compression_samples.csv"), &sample_curves_csv(&v.compression_samples)));
    let reference = written.map(|_| {
        Some(Reference {
            tension: v.tension,
            compression: v.compression,
            gridded: true,
            young_modulus: v.young_modulus,
            poisson: v.poisson,
            sample_peaks: Some(v.peaks),
        })
    });
    let reference = agree(&ctx.comm, reference, Error::exit_code)?;
    Ok(DemCurves { reference, samples: Some((v.tension_samples, v.compression_samples)) })
}

/// Collective. Stage (b): the law fitted to the DEM's curves (`reference`, rank 0; the samples'
/// curves for the pictures), its files written (rank 0) and the material file's path in the
/// summary. Returns the fit's settings (every rank), which the variants reuse.
fn identify_law(
    ctx: &Context,
    path: &Path,
    job: &IdentifyJob,
    l: &LawIdentConfig,
    reference: Option<Reference>,
    samples: Option<&(Vec<Curve>, Vec<Curve>)>,
    summary: &mut IdentifySummary,
) -> Result<LawFit, Error> {
    let spec = &job.spec;
    let sample_peaks = reference.as_ref().and_then(|r| r.sample_peaks);
    let sample_peaks: Option<[Stat; 2]> = broadcast_json(ctx, Some(&sample_peaks)).map_err(analysis_err)?;
    let experiment = spec.experiment.clone().unwrap_or_default();
    let prepared = reference.map(|r| fit_inputs(ctx, path, l, &experiment, r)).transpose();
    let prepared = agree(&ctx.comm, prepared, Error::exit_code)?;
    let (tension, compression, e, nu) = broadcast_json(ctx, prepared.as_ref()).map_err(analysis_err)?;
    let b = &l.bounds;
    let mut unknowns =
        vec![("eps0_t", b.eps0_t), ("eps0_c", b.eps0_c), ("gf_t", b.gf_t), ("a_c", b.a_c), ("b_c", b.b_c)];
    if let Some(g) = b.gf_c {
        unknowns.push((crate::identify::law_fit::GF_C, g));
    }
    let space = Space::new(&unknowns).map_err(analysis_err)?;
    let h = l.element_size.unwrap_or(spec.sample.layout.domain().1);
    let fit = LawFit {
        young_modulus: e,
        poisson: nu,
        regularization: l.regularization,
        split: l.split,
        element_size: h,
        tension,
        compression,
        measure: l.error,
        space,
        sample_peaks,
        levels: l.levels,
        ego: EgoSettings {
            iterations: l.iterations,
            batch: l.batch,
            seed: spec.analysis.seed.wrapping_add(1000),
            log_transform: true,
            target: None,
        },
        polish_iterations: l.polish_iterations,
    };
    let result = agree(&ctx.comm, identify(ctx, &fit).map_err(analysis_err), Error::exit_code)?;
    let written = match &result {
        Some(r) => write_law(ctx, path, job, &fit, r, summary, samples).map(Some),
        None => Ok(None),
    };
    summary.material_file = agree(&ctx.comm, written, Error::exit_code)?;
    summary.law = result;
    Ok(fit)
}

/// Rank 0. What the law is fitted to: the DEM's curves on a uniform grid (mean curves of samples
/// are on their own, through the mean peak when peak-aligned; curves from `dem_curves` files are
/// put on one), and the law's E and ν: `[law]`'s, else per `[law] elastic` the experiment's or
/// the DEM's. A law E more than 5% off the DEM's is a warning.
fn fit_inputs(
    ctx: &Context,
    path: &Path,
    l: &LawIdentConfig,
    experiment: &ExperimentConfig,
    r: Reference,
) -> Result<(Curve, Curve, f64, f64), Error> {
    let (e_dem, nu_dem) = (r.young_modulus, r.poisson);
    let (e_x, nu_x) = match l.elastic {
        ElasticSource::Experiment => (experiment.young_modulus, experiment.poisson),
        ElasticSource::Dem => (None, None),
    };
    let e = l.young_modulus.or(e_x).unwrap_or(e_dem);
    let nu = l.poisson.or(nu_x).unwrap_or(nu_dem);
    if e_dem.is_finite() && (e - e_dem).abs() > 0.05 * e_dem {
        ctx.log.warn(format!(
            "the law's E = {e:.4e} Pa differs from the virtual tests' mean E = {e_dem:.4e} Pa by more than 5%: the law cannot follow the DEM's elastic branch (set [law] elastic = \"dem\" to use the DEM's)"
        ));
    }
    if crate::bounds::positive(e).is_err() || !(nu.is_finite() && nu > -1.0 && nu < 0.5) {
        return Err(JobError::LawWithoutElastic { file: path.to_path_buf() }.into());
    }
    let (t, c) = if r.gridded {
        r.tension
            .check("DEM tension curve")
            .and_then(|_| r.compression.check("DEM compression curve"))
            .map_err(analysis_err)?;
        (r.tension, r.compression)
    } else {
        (
            LawFit::on_grid(&r.tension, l.points, "DEM tension curve").map_err(analysis_err)?,
            LawFit::on_grid(&r.compression, l.points, "DEM compression curve").map_err(analysis_err)?,
        )
    };
    Ok((t, c, e, nu))
}
