//! DEM calibration against experiments (paper §3.2a): find the lattice parameters
//! `x = (α, Ē, ε_cr, θ_cr)`, optionally with the crushing stress σ_c as a fifth unknown
//! (`dem::mechanics::crushing`; its energy G_c fixed), μ fixed, for which the mean over random
//! samples of the virtual test's E, ν, first-crack stress and peak stress match the measured
//! ones (Table 1).
//!
//! Objective (sum of squared relative errors of the sample means m_k(x) against targets t_k):
//!
//! ```text
//!   J(x) = Σ_k w_k ( (m_k(x) − t_k) / t_k )²,     k ∈ {E, ν, σ_first crack, σ_peak}
//! ```
//! **Strategies** (`[calibration] strategy`):
//!
//! * `staged` (default). The lattice is linear elastic until its first beam breaks, all its
//!   stiffnesses scale with Ē and α enters only the beams' inertia: ν̄ depends on α alone and
//!   Ē on Ē · ḡ(α), whatever the strengths. So (1) (α, Ē) come from (ν, E) on the elastic state
//!   alone, one loading state of strain [`ELASTIC_STRAIN`] per sample, by a 1-D root of the
//!   monotonic ν̄(α) and Ē = E_t / ḡ(α) ([`super::elastic_fit`]); (2) with α, Ē fixed, the
//!   strengths (ε_cr, θ_cr[, σ_c]) come from (first crack, peak) by kriging + EI on
//!   `J₂ = w₃ e²_first crack + w₄ e²_peak` (E and ν do not change in stage 2: same samples,
//!   same elastic parameters). Why: in the joint search the strengths' errors pull α: first
//!   crack and peak both grow with α (at fixed ε_cr, θ_cr, σ_c, α 0.37 → 0.55 raises them by
//!   27 % and 11 %, 8 samples of the paper's wall), so one move of α mends two errors at the
//!   cost of a ν error that J weighs lightly (5 % in ν adds 0.0025 to J); a surrogate fitted to
//!   40 points in 5 unknowns settled at α's upper bound with ν −5.4 %, in the shallow basin
//!   where α alone meets the first crack, and missed the narrow valley where ε_cr and σ_c do. Staging removes that
//!   trade: ν is met to 0.1 % by construction, and EGO works in 2 or 3 unknowns.
//! * `joint`: all unknowns at once by kriging + EI on J (paper §3.2a as written).
//!
//! A point whose samples all fail is a failed evaluation; if no sample cracks, the first-crack
//! term counts as a 100% error. A sample whose solver stopped at its peak without equilibrium
//! (end `failed`) has valid elastic and first-crack numbers (states before the peak are
//! equilibria) but no valid peak: it counts in E, ν and the first crack, not in the peak (`n`
//! of each quantity is recorded). Each design point runs `samples` random samples (seeds
//! `seed, seed + 1, …`, the same for every point: common random numbers, so differences between
//! points are the parameters', not the samples'). EGO ([`super::collective::run_ego`]) on
//! ln(J + δ), Latin-hypercube initial design.
use super::collective::TaskResult;
use super::collective::{best_record, broadcast_json, run_ego, run_rounds, PointRecord};
use super::dem_adapter::{run_virtual_test, DemParameters, DemRun};
use super::doe::latin_hypercube;
use super::ego::EgoSettings;
use super::elastic_fit::{ElasticFit, ElasticMeans, ElasticSearch, ElasticSettings, ELASTIC_STRAIN};
use super::error::EvalError;
use super::error::IdentifyError;
use super::space::Space;
use super::stat::Stat;
use crate::dem::sample::SampleConfig;
use crate::dem::solver::VirtualTest;
use crate::parallel::Context;
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

/// The sample statistics of the four quantities over the successful runs: E, ν over all, the
/// first crack over the samples that cracked, the peak over the valid ones (a sample stopped at
/// its peak without equilibrium has no valid peak; see the module docs).
pub fn sample_stats(runs: &[&DemRun]) -> [Stat; 4] {
    let col = |f: &dyn Fn(&DemRun) -> Option<f64>| {
        Stat::of(&runs.iter().filter_map(|r| f(r)).filter(|v| v.is_finite()).collect::<Vec<_>>())
    };
    [
        col(&|r| Some(r.young_modulus)),
        col(&|r| Some(r.poisson)),
        col(&|r| r.first_crack_stress),
        col(&|r| r.valid.then_some(r.peak_stress)),
    ]
}

/// How the unknowns are searched (see the module docs).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Serialize, Deserialize, schemars::JsonSchema)]
#[serde(rename_all = "snake_case")]
pub enum Strategy {
    /// (α, Ē) from (ν, E) on the elastic state, then the strengths by kriging + EI.
    #[default]
    Staged,
    /// All unknowns at once by kriging + EI.
    Joint,
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
    /// The EGO loop (of stage 2 when staged).
    pub ego: EgoSettings,
    /// Staged or joint.
    pub strategy: Strategy,
}

/// The calibration's outcome (rank 0).
#[derive(Clone, Debug, Serialize)]
pub struct CalibrationResult {
    /// Staged or joint.
    pub strategy: Strategy,
    /// The identified parameters.
    pub parameters: DemParameters,
    /// The objective J there (all four terms, whatever the strategy searched).
    pub objective: f64,
    /// Stage 1 of the staged strategy: (α, Ē) from the elastic state.
    pub elastic: Option<ElasticFit>,
    /// Sample statistics at the optimum, [`QUANTITIES`] order (named so in the summary).
    #[serde(with = "quantity_names")]
    pub stats: [Stat; 4],
    /// Relative error of each sample mean against its target (named by quantity).
    #[serde(with = "quantity_names")]
    pub relative_errors: [f64; 4],
    /// The targets.
    pub targets: Targets,
    /// Evaluations of the objective (design + infill).
    pub evaluations: usize,
    /// Every point: iteration, physical coordinates (all unknowns), objective (the searched
    /// one: J joint, J₂ in stage 2); in the summary each as `iteration`, `point` (named by
    /// [`CALIBRATION_UNKNOWNS`]) and `objective`.
    #[serde(serialize_with = "calibration_history")]
    pub history: Vec<(usize, Vec<f64>, Result<f64, EvalError>)>,
    /// The runs at the optimum (curves for the picture).
    #[serde(skip)]
    pub best_runs: Vec<DemRun>,
    /// The failures at the optimum.
    pub best_failures: Vec<String>,
}

crate::io::summary::named!(
    /// The measured quantities, [`QUANTITIES`].
    quantity_names: ["young_modulus", "poisson", "first_crack_stress", "peak_stress"]
);

/// The calibration's unknowns in the order of a point's coordinates (σ_c only with crushing).
pub const CALIBRATION_UNKNOWNS: [&str; 5] = ["alpha", "e_bar", "eps_cr", "theta_cr", "crushing_stress"];

fn calibration_history<S: serde::Serializer>(
    h: &[(usize, Vec<f64>, Result<f64, EvalError>)],
    s: S,
) -> Result<S::Ok, S::Error> {
    super::named_history(&CALIBRATION_UNKNOWNS, h, s)
}

/// The parameters at the physical point `x = (α, Ē, ε_cr, θ_cr[, σ_c])`.
pub fn parameters_at(fixed: &DemParameters, x: &[f64]) -> DemParameters {
    let crushing_stress = x.get(4).copied().or(fixed.crushing_stress);
    DemParameters { alpha: x[0], e_bar: x[1], eps_cr: x[2], theta_cr: x[3], crushing_stress, ..*fixed }
}

/// J of a set of runs (see the module docs).
pub fn objective(targets: &Targets, weights: &[f64; 4], runs: &[TaskResult<DemRun>]) -> Result<f64, EvalError> {
    let ok: Vec<&DemRun> = runs.iter().filter_map(|r| r.as_ref().ok()).collect();
    if ok.is_empty() || (weights[3] > 0.0 && !ok.iter().any(|r| r.valid)) {
        return Err(runs.iter().find_map(|r| r.as_ref().err().cloned()).unwrap_or(EvalError::EveryRunStopped));
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
    match c.strategy {
        Strategy::Joint => calibrate_joint(ctx, c),
        Strategy::Staged => calibrate_staged(ctx, c),
    }
}

fn calibrate_joint(ctx: &Context, c: &Calibration) -> Result<Option<CalibrationResult>, IdentifyError> {
    let design = latin_hypercube(c.design_points, c.space.dim(), c.seed)?;
    ctx.log.info(format!(
        "calibration (joint): {} design points × {} samples, then {} infill iteration(s) of {} point(s)",
        c.design_points, c.samples, c.ego.iterations, c.ego.batch
    ));
    let work = |u: &[f64], k: usize| -> TaskResult<DemRun> {
        let p = parameters_at(&c.fixed, &c.space.from_unit(u));
        run_virtual_test(&c.sample, &p, &c.test, k)
    };
    let reduce = |_: &[f64], runs: &[TaskResult<DemRun>]| objective(&c.targets, &c.weights, runs);
    let Some(records) = run_ego(ctx, c.space.dim(), design, c.ego.clone(), c.samples, work, reduce, "calibration")?
    else {
        return Ok(None);
    };
    Ok(Some(summarize(c, records, |u| c.space.from_unit(u), None)?))
}

/// The elastic test of stage 1: `test`'s direction, one step to [`ELASTIC_STRAIN`].
pub fn elastic_test(test: &VirtualTest) -> VirtualTest {
    match test {
        VirtualTest::Tension { .. } => VirtualTest::Tension { max_strain: ELASTIC_STRAIN, steps: 1 },
        _ => VirtualTest::Compression { max_strain: ELASTIC_STRAIN, steps: 1 },
    }
}

/// The sample means of ν and E/Ē of one α's elastic runs.
pub fn elastic_means(runs: &[TaskResult<DemRun>], e_bar: f64) -> Result<ElasticMeans, EvalError> {
    let ok: Vec<&DemRun> = runs.iter().filter_map(|r| r.as_ref().ok()).collect();
    if ok.is_empty() {
        return Err(runs.iter().find_map(|r| r.as_ref().err().cloned()).unwrap_or(EvalError::NoSample));
    }
    let stats = sample_stats(&ok);
    let ratio: Vec<f64> = ok.iter().map(|r| r.young_modulus / e_bar).filter(|v| v.is_finite()).collect();
    Ok(ElasticMeans { poisson: stats[1], e_ratio: Stat::of(&ratio) })
}

fn calibrate_staged(ctx: &Context, c: &Calibration) -> Result<Option<CalibrationResult>, IdentifyError> {
    let u = &c.space.unknowns;
    if u.len() < 3 || u[0].name != "alpha" || u[1].name != "e_bar" {
        return Err(IdentifyError::Settings(
            "the staged calibration needs the unknowns alpha, e_bar, then the strengths".into(),
        ));
    }
    let weights = [0.0, 0.0, c.weights[2], c.weights[3]];
    if weights.iter().all(|w| *w == 0.0) {
        return Err(IdentifyError::Settings(
            "the staged calibration's second stage fits the first crack and the peak, whose weights are both 0: use strategy = \"joint\"".into(),
        ));
    }
    // Stage 1: (α, Ē) from (ν, E); the strengths at their intervals' middles (they do not act).
    let middle: Vec<f64> = c.space.from_unit(&vec![0.5; c.space.dim()]);
    let reference = parameters_at(&c.fixed, &middle);
    let test = elastic_test(&c.test);
    let settings = ElasticSettings::new(
        [u[0].lower, u[0].upper],
        [u[1].lower, u[1].upper],
        c.targets.poisson,
        c.targets.young_modulus,
    );
    let mut search = ElasticSearch::new(settings)?;
    ctx.log.info(format!(
        "calibration, stage 1 (elastic): alpha from nu = {} over alpha in [{}, {}] ({} samples per alpha, one loading state to a strain of {ELASTIC_STRAIN:e}), then e_bar from E = {:e} Pa",
        c.targets.poisson, u[0].lower, u[0].upper, c.samples, c.targets.young_modulus
    ));
    let first: Vec<Vec<f64>> = search.first().into_iter().map(|a| vec![a]).collect();
    let work = |x: &[f64], k: usize| -> TaskResult<DemRun> {
        run_virtual_test(&c.sample, &DemParameters { alpha: x[0], ..reference }, &test, k)
    };
    run_rounds(ctx, first, c.samples, work, |points, results| {
        let alphas: Vec<f64> = points.iter().map(|p| p[0]).collect();
        let values: Vec<Result<ElasticMeans, EvalError>> =
            results.iter().map(|r| elastic_means(r, reference.e_bar)).collect();
        for (a, v) in alphas.iter().zip(&values) {
            ctx.log.info(match v {
                Ok(m) => format!(
                    "  alpha = {a:.5}: nu = {:.5} ± {:.5}, E/e_bar = {:.5} ± {:.5} (n = {})",
                    m.poisson.mean, m.poisson.std, m.e_ratio.mean, m.e_ratio.std, m.poisson.n
                ),
                Err(e) => format!("  alpha = {a:.5}: failed: {e}"),
            });
        }
        search.tell(&alphas, values);
        Ok(search.ask()?.map(|next| next.into_iter().map(|a| vec![a]).collect()))
    })?;
    let fit = search.result().map_err(|e| EvalError::Search { reason: e.to_string() });
    let agreed: Result<(f64, f64), EvalError> =
        broadcast_json(ctx, Some(&fit.as_ref().map(|f| (f.alpha, f.e_bar)).map_err(Clone::clone)))?;
    let (alpha, e_bar) = agreed.map_err(|e| IdentifyError::Settings(e.to_string()))?;
    if let Ok(f) = &fit {
        ctx.log.info(format!(
            "calibration, stage 1: alpha = {alpha:.5}, e_bar = {e_bar:.5e} Pa: nu = {:.5} ± {:.5}, E = {:.5e} ± {:.3e} Pa (n = {}){}",
            f.poisson.mean,
            f.poisson.std,
            f.young_modulus.mean,
            f.young_modulus.std,
            f.poisson.n,
            f.note.as_ref().map_or(String::new(), |n| format!("; {n}"))
        ));
    }
    // Stage 2: the strengths, α and Ē fixed.
    let strengths = Space { unknowns: u[2..].to_vec() };
    let full = |v: &[f64]| -> Vec<f64> { [alpha, e_bar].into_iter().chain(strengths.from_unit(v)).collect() };
    let design = latin_hypercube(c.design_points, strengths.dim(), c.seed)?;
    ctx.log.info(format!(
        "calibration, stage 2 (strengths {}): {} design points × {} samples, then {} infill iteration(s) of {} point(s)",
        strengths.names().join(", "),
        c.design_points,
        c.samples,
        c.ego.iterations,
        c.ego.batch
    ));
    let work = |v: &[f64], k: usize| -> TaskResult<DemRun> {
        run_virtual_test(&c.sample, &parameters_at(&c.fixed, &full(v)), &c.test, k)
    };
    let reduce = |_: &[f64], runs: &[TaskResult<DemRun>]| objective(&c.targets, &weights, runs);
    let Some(records) =
        run_ego(ctx, strengths.dim(), design, c.ego.clone(), c.samples, work, reduce, "calibration, stage 2")?
    else {
        return Ok(None);
    };
    Ok(Some(summarize(c, records, full, fit.ok())?))
}

fn summarize(
    c: &Calibration,
    records: Vec<PointRecord<DemRun>>,
    to_x: impl Fn(&[f64]) -> Vec<f64>,
    elastic: Option<ElasticFit>,
) -> Result<CalibrationResult, IdentifyError> {
    let history: Vec<_> = records.iter().map(|r| (r.iteration, to_x(&r.unit), r.value.clone())).collect();
    let best = best_record(&records)?;
    let runs: Vec<DemRun> = best.tasks.iter().filter_map(|r| r.as_ref().ok().cloned()).collect();
    let refs: Vec<&DemRun> = runs.iter().collect();
    let stats = sample_stats(&refs);
    let relative_errors = relative_errors(&stats, &c.targets);
    Ok(CalibrationResult {
        strategy: c.strategy,
        parameters: parameters_at(&c.fixed, &to_x(&best.unit)),
        objective: relative_errors.iter().zip(&c.weights).map(|(e, w)| w * e * e).sum(),
        elastic,
        relative_errors,
        stats,
        targets: c.targets,
        evaluations: records.len(),
        history,
        best_failures: best
            .tasks
            .iter()
            .enumerate()
            .filter_map(|(k, r)| match r {
                Err(e) => Some(e.to_string()),
                Ok(d) if !d.valid => Some(format!(
                    "sample {k}: the solver stopped at its peak (end {}): left out of the peak statistics",
                    d.end
                )),
                Ok(_) => None,
            })
            .collect(),
        best_runs: runs,
    })
}
