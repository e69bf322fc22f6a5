//! DEM calibration against experiments (SPEC §3a): find the lattice parameters
//! `x = (α, Ē, ε_cr, θ_cr)`, optionally with the crushing stress σ_c as a fifth unknown
//! (`dem::mechanics::crushing`; its energy G_c fixed), μ fixed, for which the mean over random samples of the virtual
//! test's E, ν, first-crack stress and peak stress match the measured ones (Table 1).
//!
//! Objective (sum of squared relative errors of the sample means m_k(x) against targets t_k):
//!
//! ```text
//!   J(x) = Σ_k w_k ( (m_k(x) − t_k) / t_k )²,     k ∈ {E, ν, σ_first crack, σ_peak}
//! ```
//! A point whose samples all fail is a failed evaluation; if no sample cracks, the first-crack
//! term counts as a 100% error. As in the DEM job, a sample whose solver stopped before its peak
//! (end `failed`) does not count in the statistics (its peak is only where the solver stopped). Each design point runs `samples` random samples (seeds
//! `seed, seed + 1, …`, the same for every point: common random numbers, so differences between
//! points are the parameters', not the samples'). EGO ([`super::collective::run_ego`]) on
//! ln(J + δ), Latin-hypercube initial design.
use super::collective::{best_record, run_ego, PointRecord};
use super::dem_adapter::{run_virtual_test, DemParameters, DemRun};
use super::doe::latin_hypercube;
use super::ego::EgoSettings;
use super::error::IdentifyError;
use super::space::Space;
use crate::dem::sample::SampleConfig;
use crate::dem::solver::VirtualTest;
use crate::parallel::{Context, TaskResult};
use serde::{Deserialize, Serialize};

/// The four measured numbers.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
pub struct Targets {
    /// Young modulus [Pa].
    pub young_modulus: f64,
    /// Poisson ratio.
    pub poisson: f64,
    /// First-crack stress [Pa].
    pub first_crack_stress: f64,
    /// Peak stress [Pa].
    pub peak_stress: f64,
}

impl Targets {
    /// In the order E, ν, first crack, peak.
    pub fn as_array(&self) -> [f64; 4] {
        [self.young_modulus, self.poisson, self.first_crack_stress, self.peak_stress]
    }
}

/// Names of the four quantities, in [`Targets::as_array`] order.
pub const QUANTITIES: [&str; 4] = ["young_modulus", "poisson", "first_crack_stress", "peak_stress"];

/// Mean and sample standard deviation.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
pub struct Stat {
    /// Mean.
    pub mean: f64,
    /// Sample standard deviation (0 for one value).
    pub std: f64,
    /// Number of values.
    pub n: usize,
}

impl Stat {
    /// Of `v` (NaN mean when empty).
    pub fn of(v: &[f64]) -> Stat {
        let n = v.len();
        let mean = if n == 0 { f64::NAN } else { v.iter().sum::<f64>() / n as f64 };
        let var = if n > 1 { v.iter().map(|x| (x - mean).powi(2)).sum::<f64>() / (n - 1) as f64 } else { 0.0 };
        Stat { mean, std: var.sqrt(), n }
    }
}

/// The sample statistics of the four quantities over the successful runs (first crack over the
/// samples that cracked).
pub fn sample_stats(runs: &[&DemRun]) -> [Stat; 4] {
    let col = |f: &dyn Fn(&DemRun) -> Option<f64>| Stat::of(&runs.iter().filter_map(|r| f(r)).collect::<Vec<_>>());
    [
        col(&|r| Some(r.young_modulus)),
        col(&|r| Some(r.poisson)),
        col(&|r| r.first_crack_stress),
        col(&|r| Some(r.peak_stress)),
    ]
}

/// Everything the calibration needs.
#[derive(Clone, Debug)]
pub struct Calibration {
    /// The virtual wall (its seed is the first sample's).
    pub sample: SampleConfig,
    /// The fixed parameters (μ, k_t/k_n) and the defaults of the others.
    pub fixed: DemParameters,
    /// The virtual test (compression for Table 1).
    pub test: VirtualTest,
    /// Random samples per design point.
    pub samples: usize,
    /// The unknowns α, Ē, ε_cr, θ_cr (and σ_c with crushing) and their intervals, in this order.
    pub space: Space,
    /// The measured numbers.
    pub targets: Targets,
    /// Weights w_k in [`QUANTITIES`] order.
    pub weights: [f64; 4],
    /// Initial Latin-hypercube points.
    pub design_points: usize,
    /// Seed of the design (the EGO seed follows from it).
    pub seed: u64,
    /// The EGO loop.
    pub ego: EgoSettings,
}

/// The calibration's outcome (rank 0).
#[derive(Clone, Debug, Serialize)]
pub struct CalibrationResult {
    /// The identified parameters.
    pub parameters: DemParameters,
    /// The objective J there.
    pub objective: f64,
    /// Sample statistics at the optimum, [`QUANTITIES`] order.
    pub stats: [Stat; 4],
    /// Relative error of each sample mean against its target.
    pub relative_errors: [f64; 4],
    /// The targets.
    pub targets: Targets,
    /// Evaluations of the objective (design + infill).
    pub evaluations: usize,
    /// Every point: iteration, physical coordinates, objective.
    pub history: Vec<(usize, Vec<f64>, Result<f64, String>)>,
    /// The runs at the optimum (curves for the picture).
    #[serde(skip)]
    pub best_runs: Vec<DemRun>,
    /// The failures at the optimum.
    pub best_failures: Vec<String>,
}

/// The parameters at the physical point `x = (α, Ē, ε_cr, θ_cr[, σ_c])`.
pub fn parameters_at(fixed: &DemParameters, x: &[f64]) -> DemParameters {
    let crushing_stress = x.get(4).copied().or(fixed.crushing_stress);
    DemParameters { alpha: x[0], e_bar: x[1], eps_cr: x[2], theta_cr: x[3], crushing_stress, ..*fixed }
}

/// J of a set of runs (see the module docs).
pub fn objective(targets: &Targets, weights: &[f64; 4], runs: &[TaskResult<DemRun>]) -> Result<f64, String> {
    let ok: Vec<&DemRun> = runs.iter().filter_map(|r| r.as_ref().ok()).filter(|r| r.valid).collect();
    if ok.is_empty() {
        return Err(runs
            .iter()
            .find_map(|r| r.as_ref().err().cloned())
            .unwrap_or_else(|| "every sample stopped before its peak (solver end 'failed')".into()));
    }
    let stats = sample_stats(&ok);
    Ok(relative_errors(&stats, targets).iter().zip(weights).map(|(e, w)| w * e * e).sum())
}

/// (m_k − t_k)/t_k; a quantity no sample produced counts as −1 (100%).
pub fn relative_errors(stats: &[Stat; 4], targets: &Targets) -> [f64; 4] {
    let t = targets.as_array();
    std::array::from_fn(|k| if stats[k].n == 0 { -1.0 } else { (stats[k].mean - t[k]) / t[k] })
}

/// Collective. Runs the calibration; rank 0 gets the result.
pub fn calibrate(ctx: &Context, c: &Calibration) -> Result<Option<CalibrationResult>, IdentifyError> {
    let design = latin_hypercube(c.design_points, c.space.dim(), c.seed)?;
    ctx.log.info(format!(
        "calibration: {} design points × {} samples, then {} infill iteration(s) of {} point(s)",
        c.design_points, c.samples, c.ego.iterations, c.ego.batch
    ));
    let work = |u: &[f64], k: usize| -> TaskResult<DemRun> {
        let p = parameters_at(&c.fixed, &c.space.from_unit(u));
        run_virtual_test(&c.sample, &p, &c.test, k)
    };
    let reduce = |_: &[f64], runs: &[TaskResult<DemRun>]| objective(&c.targets, &c.weights, runs);
    let Some(records) = run_ego(ctx, c.space.dim(), design, c.ego.clone(), c.samples, work, reduce, "calibration")? else {
        return Ok(None);
    };
    Ok(Some(summarize(c, records)?))
}

fn summarize(c: &Calibration, records: Vec<PointRecord<DemRun>>) -> Result<CalibrationResult, IdentifyError> {
    let history: Vec<_> = records.iter().map(|r| (r.iteration, c.space.from_unit(&r.unit), r.value.clone())).collect();
    let best = best_record(&records)?;
    let runs: Vec<DemRun> = best.tasks.iter().filter_map(|r| r.as_ref().ok().cloned()).collect();
    let refs: Vec<&DemRun> = runs.iter().filter(|r| r.valid).collect();
    let stats = sample_stats(&refs);
    Ok(CalibrationResult {
        parameters: parameters_at(&c.fixed, &c.space.from_unit(&best.unit)),
        objective: best.value.clone().unwrap_or(f64::NAN),
        relative_errors: relative_errors(&stats, &c.targets),
        stats,
        targets: c.targets,
        evaluations: records.len(),
        history,
        best_failures: best
            .tasks
            .iter()
            .enumerate()
            .filter_map(|(k, r)| match r {
                Err(e) => Some(e.clone()),
                Ok(d) if !d.valid => Some(format!("sample {k}: the solver stopped before the peak (end {}): left out of the statistics", d.end)),
                Ok(_) => None,
            })
            .collect(),
        best_runs: runs,
    })
}
