//! The material file's provenance (identify::material_file): how the law was obtained, from the
//! job and its results.
use super::IdentifySummary;
use crate::config::{ElasticSource, IdentifyJob, LawIdentConfig};
use crate::dem::solver::VirtualTest;
use crate::identify::calibration::{CalibrationResult, QUANTITIES};
use crate::identify::curves::MeanKind;
use crate::identify::material_file::{MeasureFigure, PeakFigure, Provenance, TargetFigure, VariantFigure};
use crate::identify::{LawFit, LawResult};
use std::path::Path;

/// The material file's provenance (identify::material_file) from the job and its results.
pub(super) fn provenance(
    path: &Path,
    job: &IdentifyJob,
    fit: &LawFit,
    r: &LawResult,
    summary: &IdentifySummary,
) -> Provenance {
    let spec = &job.spec;
    let law = spec.law.as_ref();
    let from_files = job.dem_curves.is_some() || job.dem_samples.is_some();
    let seeds = |n: usize| sample_seeds(spec.sample.seed, n);
    let calibration_sample_seeds = match (&spec.calibration, &summary.calibration) {
        (Some(c), Some(_)) => seeds(c.samples),
        _ => Vec::new(),
    };
    let mean = mean_name(law);
    Provenance {
        job: path.to_path_buf(),
        method: method(fit, mean),
        seed: spec.analysis.seed,
        calibration_sample_seeds,
        law_sample_seeds: if from_files { Vec::new() } else { seeds(law.map_or(0, |l| l.samples)) },
        curves: curves(job, law, mean, summary.calibration.is_some()),
        elastic: elastic(law),
        element_size: fit.element_size,
        softening_energy: fit.softening_energy(&r.params),
        error_tension: r.fit.tension.value,
        error_compression: r.fit.compression.value,
        error_measure: fit.measure.name().to_string(),
        measures: measure_figures(r),
        peaks: Some(peak_figures(r)),
        dem: if from_files { None } else { Some(summary.calibration.as_ref().map_or(job.dem, |c| c.parameters)) },
        calibration: summary.calibration.as_ref().map_or(Vec::new(), target_figures),
        virtual_test_failures: summary.virtual_test_failures.clone(),
        notes: law.and_then(|l| l.material_notes.clone()),
        variant: None,
    }
}

/// A material variant's provenance: the main law's, with the variant's samples (`variant`) and
/// where its curves come from saying so.
pub(super) fn variant_provenance(
    path: &Path,
    job: &IdentifyJob,
    fit: &LawFit,
    r: &LawResult,
    summary: &IdentifySummary,
    variant: VariantFigure,
) -> Provenance {
    let mut p = provenance(path, job, fit, r, summary);
    p.curves = format!(
        "{}; of them only the samples of [provenance.variant] (material variant {} of {})",
        p.curves, variant.number, variant.count
    );
    p.variant = Some(variant);
    p
}

/// The seeds of `n` DEM samples from the job's `[sample] seed`: seed, seed + 1, ...
fn sample_seeds(seed: u64, n: usize) -> Vec<u64> {
    (0..n as u64).map(|k| seed.wrapping_add(k)).collect()
}

/// How the DEM samples' curves are averaged, in words.
fn mean_name(law: Option<&LawIdentConfig>) -> &'static str {
    match law.map(|l| l.mean) {
        Some(MeanKind::Pointwise) => "pointwise",
        _ => "peak-aligned",
    }
}

/// What was fitted (a sentence), with the design's dimension and the error measure.
fn method(fit: &LawFit, mean: &str) -> String {
    format!(
        "2^{} factorial + EGO (kriging, q-EI) + Nelder-Mead on the {} error between the law (plane-stress material point, uniaxial stress, element size h) and the DEM's mean tension and compression curves ({mean} mean of the samples)",
        fit.space.dim(),
        fit.measure.name(),
    )
}

/// A virtual test in words ("tension to 1e-3 in 100 steps"; "-" when none).
fn virtual_test(t: &Option<VirtualTest>) -> String {
    match t {
        Some(VirtualTest::Tension { max_strain, steps }) => format!("tension to {max_strain:e} in {steps} steps"),
        Some(VirtualTest::Compression { max_strain, steps }) => {
            format!("compression to {max_strain:e} in {steps} steps")
        }
        _ => "-".to_string(),
    }
}

/// Where the DEM curves came from (a sentence): the job's mean-curve files, its sample files, or
/// the virtual tests of the calibrated (`calibrated`) or given DEM.
fn curves(job: &IdentifyJob, law: Option<&LawIdentConfig>, mean: &str, calibrated: bool) -> String {
    match (law, &job.dem_curves, &job.dem_samples) {
        (Some(l), Some(_), _) => l.dem_curves.as_ref().map_or(String::new(), |f| {
            format!("mean curves from the files {} and {} (paths from the job's folder)", f.tension.display(), f.compression.display())
        }),
        (Some(l), None, Some(_)) => l.dem_samples.as_ref().map_or(String::new(), |f| {
            format!(
                "every sample's curve from the files {} and {} (paths from the job's folder), {mean} mean on about {} points",
                f.tension.display(),
                f.compression.display(),
                l.points
            )
        }),
        (Some(l), None, None) => format!(
            "virtual tests of the {} DEM on the job's [sample] wall: {} and {}, {} samples each, {mean} mean on about {} points",
            if calibrated { "calibrated" } else { "given" },
            virtual_test(&l.tension),
            virtual_test(&l.compression),
            l.samples,
            l.points
        ),
        _ => String::new(),
    }
}

/// Where E and ν come from (a sentence).
fn elastic(law: Option<&LawIdentConfig>) -> String {
    match law {
        Some(l) if l.young_modulus.is_some() || l.poisson.is_some() => {
            "E and nu given in the job's [law] table".to_string()
        }
        Some(l) if l.elastic == ElasticSource::Dem => {
            "E and nu: the virtual compression tests' means ([law] elastic = dem)".to_string()
        }
        _ => "E and nu: the job's [experiment] table".to_string(),
    }
}

/// Table 1: each calibrated quantity against its target.
fn target_figures(c: &CalibrationResult) -> Vec<TargetFigure> {
    let t = c.targets.as_array();
    (0..4)
        .map(|k| TargetFigure {
            name: QUANTITIES[k],
            target: t[k],
            mean: c.stats[k].mean,
            std: c.stats[k].std,
            n: c.stats[k].n,
            relative_error: c.relative_errors[k],
        })
        .collect()
}

/// Every error measure at the law.
fn measure_figures(r: &LawResult) -> Vec<MeasureFigure> {
    r.measures
        .iter()
        .map(|m| MeasureFigure {
            measure: m.measure,
            tension: m.tension.map(|e| e.value),
            compression: m.compression.map(|e| e.value),
        })
        .collect()
}

/// The law's tension and compression peaks against the DEM's.
fn peak_figures(r: &LawResult) -> [PeakFigure; 2] {
    let peak = |k: usize, e: f64| PeakFigure {
        dem: r.dem_peaks[k],
        law: r.law_peaks[k],
        relative_error: e,
        samples: r.dem_sample_peaks.map(|s| (s[k].mean, s[k].std, s[k].n)),
    };
    [peak(0, r.tension_peak_error), peak(1, r.compression_peak_error)]
}
