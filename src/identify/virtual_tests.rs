//! The calibrated DEM's virtual tests for the law identification: tension and compression of
//! `samples` random samples each, as one dynamic batch (2 × samples tasks), reduced to the
//! mean curves on uniform strain grids ([`super::curves::mean_of`]: peak-aligned or pointwise).
//! A sample whose solver stopped before its peak (the DEM's `failed` end) has no valid post-peak
//! branch and is left out of the mean, as the DEM job leaves it out of its statistics; it is
//! reported with the failures. A post-peak collapse counts, with zero stress after its end.
use super::collective::evaluate_points;
use super::curves::{mean_of, Curve, MeanKind};
use super::dem_adapter::{run_virtual_test, DemParameters, DemRun};
use super::error::{EvalError, IdentifyError};
use super::stat::Stat;
use crate::dem::sample::SampleConfig;
use crate::dem::solver::VirtualTest;
use crate::parallel::Context;

/// The virtual tests' outcome (rank 0).
#[derive(Clone, Debug)]
pub struct VirtualCurves {
    /// Mean tension curve.
    pub tension: Curve,
    /// Mean compression curve.
    pub compression: Curve,
    /// Every sample's tension curve.
    pub tension_samples: Vec<Curve>,
    /// Every sample's compression curve.
    pub compression_samples: Vec<Curve>,
    /// Failed samples' messages.
    pub failures: Vec<String>,
    /// Mean E and ν of the compression samples.
    pub young_modulus: f64,
    /// Mean Poisson ratio of the compression samples.
    pub poisson: f64,
    /// The samples' peak stresses [Pa]: tension, compression (mean ± std).
    pub peaks: [Stat; 2],
}

fn max_strain(t: &VirtualTest) -> f64 {
    match *t {
        VirtualTest::Compression { max_strain, .. } | VirtualTest::Tension { max_strain, .. } => max_strain,
        _ => 0.0, // shear and cyclic tests have no monotonic strain range
    }
}

/// Collective. Runs both tests on `samples` samples with `p`; `points` grid points per curve.
#[allow(clippy::too_many_arguments)] // the sample, the law's parameters, two tests and the curves' grid
pub fn run_virtual_tests(
    ctx: &Context,
    sample: &SampleConfig,
    p: &DemParameters,
    tension: &VirtualTest,
    compression: &VirtualTest,
    samples: usize,
    points: usize,
    mean: MeanKind,
) -> Result<Option<VirtualCurves>, IdentifyError> {
    ctx.log.info(format!("virtual tests: tension and compression of {samples} sample(s) each"));
    let tests = [vec![0.0], vec![1.0]];
    let work = |which: &[f64], k: usize| -> Result<DemRun, EvalError> {
        let t = if which[0] == 0.0 { tension } else { compression };
        run_virtual_test(sample, p, t, k)
    };
    let Some(results) = evaluate_points(ctx, &tests, samples, &work)? else {
        return Ok(None);
    };
    let mut failures = Vec::new();
    // The valid runs; when none is valid, every run that produced a curve (said so in the
    // failures), so that a test whose samples all stop at their peak still gives a curve.
    let mut split = |rs: &[Result<DemRun, EvalError>], name: &str| -> Vec<DemRun> {
        let mut valid = Vec::new();
        let mut stopped = Vec::new();
        for (k, r) in rs.iter().enumerate() {
            match r {
                Ok(d) if d.valid => valid.push(d.clone()),
                Ok(d) => {
                    failures.push(format!(
                        "{name}: sample {k}: the solver stopped before the peak (end {}, peak {:.4e} Pa at strain {:.4e}): left out of the mean curve",
                        d.end, d.peak_stress, d.strain_at_peak
                    ));
                    stopped.push(d.clone());
                }
                Err(e) => failures.push(format!("{name}: {e}")),
            }
        }
        if valid.is_empty() && !stopped.is_empty() {
            failures.push(format!("{name}: no sample reached a valid end: the mean curve is that of the {} stopped sample(s), up to where they stopped", stopped.len()));
            return stopped;
        }
        valid
    };
    let t_runs = split(&results[0], "tension");
    let c_runs = split(&results[1], "compression");
    let tension_samples: Vec<Curve> = t_runs.iter().map(|r| r.curve.clone()).collect();
    let compression_samples: Vec<Curve> = c_runs.iter().map(|r| r.curve.clone()).collect();
    let t_mean = mean_of(mean, &tension_samples, max_strain(tension), points, "DEM tension curve")?;
    let c_mean = mean_of(mean, &compression_samples, max_strain(compression), points, "DEM compression curve")?;
    t_mean.check("DEM tension curve")?;
    c_mean.check("DEM compression curve")?;
    let n = c_runs.len() as f64;
    Ok(Some(VirtualCurves {
        young_modulus: c_runs.iter().map(|r| r.young_modulus).sum::<f64>() / n,
        poisson: c_runs.iter().map(|r| r.poisson).sum::<f64>() / n,
        peaks: [
            Stat::of(&tension_samples.iter().map(|c| c.peak().0).collect::<Vec<_>>()),
            Stat::of(&compression_samples.iter().map(|c| c.peak().0).collect::<Vec<_>>()),
        ],
        tension: t_mean,
        compression: c_mean,
        tension_samples,
        compression_samples,
        failures,
    }))
}
