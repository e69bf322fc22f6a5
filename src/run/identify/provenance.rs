//! The material file's provenance (identify::material_file): how the law was obtained, from the
//! job and its results.
use super::IdentifySummary;
use crate::config::IdentifyJob;
use crate::identify::calibration::QUANTITIES;
use crate::identify::material_file::Provenance;
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
    use crate::identify::material_file::{MeasureFigure, PeakFigure, TargetFigure};
    let spec = &job.spec;
    let law = spec.law.as_ref();
    let from_files = job.dem_curves.is_some() || job.dem_samples.is_some();
    let seeds = |n: usize| (0..n as u64).map(|k| spec.sample.seed.wrapping_add(k)).collect::<Vec<_>>();
    let calibration_sample_seeds = match (&spec.calibration, &summary.calibration) {
        (Some(c), Some(_)) => seeds(c.samples),
        _ => Vec::new(),
    };
    let mean = match law.map(|l| l.mean) {
        Some(crate::identify::curves::MeanKind::Pointwise) => "pointwise",
        _ => "peak-aligned",
    };
    let test = |t: &Option<crate::dem::solver::VirtualTest>| match t {
        Some(crate::dem::solver::VirtualTest::Tension { max_strain, steps }) => {
            format!("tension to {max_strain:e} in {steps} steps")
        }
        Some(crate::dem::solver::VirtualTest::Compression { max_strain, steps }) => {
            format!("compression to {max_strain:e} in {steps} steps")
        }
        _ => "-".to_string(),
    };
    let curves = match (law, &job.dem_curves, &job.dem_samples) {
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
            if summary.calibration.is_some() { "calibrated" } else { "given" },
            test(&l.tension),
            test(&l.compression),
            l.samples,
            l.points
        ),
        _ => String::new(),
    };
    let elastic = match law {
        Some(l) if l.young_modulus.is_some() || l.poisson.is_some() => {
            "E and nu given in the job's [law] table".to_string()
        }
        Some(l) if l.elastic == crate::config::ElasticSource::Dem => {
            "E and nu: the virtual compression tests' means ([law] elastic = dem)".to_string()
        }
        _ => "E and nu: the job's [experiment] table".to_string(),
    };
    let calibration = summary.calibration.as_ref().map_or(Vec::new(), |c| {
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
    });
    let peak = |k: usize, e: f64| PeakFigure {
        dem: r.dem_peaks[k],
        law: r.law_peaks[k],
        relative_error: e,
        samples: r.dem_sample_peaks.map(|s| (s[k].mean, s[k].std, s[k].n)),
    };
    Provenance {
        job: path.to_path_buf(),
        method: format!(
            "2^{} factorial + EGO (kriging, q-EI) + Nelder-Mead on the {} error between the law (plane-stress material point, uniaxial stress, element size h) and the DEM's mean tension and compression curves ({mean} mean of the samples)",
            fit.space.dim(),
            fit.measure.name(),
        ),
        seed: spec.analysis.seed,
        calibration_sample_seeds,
        law_sample_seeds: if from_files { Vec::new() } else { seeds(law.map_or(0, |l| l.samples)) },
        curves,
        elastic,
        element_size: fit.element_size,
        softening_energy: fit.softening_energy(&r.params),
        error_tension: r.fit.tension.value,
        error_compression: r.fit.compression.value,
        error_measure: fit.measure.name().to_string(),
        measures: r
            .measures
            .iter()
            .map(|m| MeasureFigure { measure: m.measure, tension: m.tension.map(|e| e.value), compression: m.compression.map(|e| e.value) })
            .collect(),
        peaks: Some([peak(0, r.tension_peak_error), peak(1, r.compression_peak_error)]),
        dem: if from_files { None } else { Some(summary.calibration.as_ref().map_or(job.dem, |c| c.parameters)) },
        calibration,
        virtual_test_failures: summary.virtual_test_failures.clone(),
        notes: law.and_then(|l| l.material_notes.clone()),
    }
}
