//! Identification of the damage law from DEM virtual tests (SPEC §3b).
//!
//! Unknowns `x = (ε₀^t, ε₀^c, G_f, A_c, B_c)`; E and ν fixed (from the experiment, or the DEM's
//! means). For each x the law is driven, as a plane-stress material point, along the DEM tests'
//! paths: uniaxial stress, ε_xx imposed on the reference curves' uniform strain grids
//! (`material::run_path`, lateral stresses free); its stress is compared with the DEM's mean
//! curve at the same strains by the error measure ([`super::error_measure`], paper eq. 15):
//!
//! ```text
//!   F(x) = F_tension(x) + F_compression(x)
//! ```
//! B_t follows from G_f by the Hillerborg regularization with the element size `h` = the DEM
//! sample's height (the DEM's strain is the platen displacement over the height, so its softening
//! branch is that of one element of length h crossed by the crack), so G_f comes out per unit
//! crack area and the material file serves any mesh. Initial design: the 2⁵ two-level
//! factorial (the paper's 32 combinations); then EGO infill on ln(F + δ); then, since one
//! evaluation costs milliseconds, a Nelder–Mead polish from the EGO optimum ([`super::polish`];
//! its evaluations appear in the history as the iteration after the last infill).
use super::collective::{best_record, run_ego, PointRecord};
use super::curves::{uniform_grid, Curve};
use super::doe::two_level_factorial;
use super::ego::EgoSettings;
use super::error::IdentifyError;
use super::error_measure::{curve_error, CurveError, ErrorMeasure};
use super::space::Space;
use crate::material::{run_path, DamageParams, LoadPath, NewtonSettings, PlaneStress, Regularization};
use crate::parallel::{Context, TaskResult};
use serde::Serialize;

/// Starting points of the polish: the best EGO points.
pub const POLISH_STARTS: usize = 3;
/// Restarts of each polish from its own result with a fresh simplex (Nelder–Mead stalls on
/// non-smooth objectives such as eq. 15; a restart is the standard remedy).
pub const POLISH_RESTARTS: usize = 3;

/// The unknowns' names, in order (as in the job file and the material file).
pub const UNKNOWNS: [&str; 5] = ["eps0_t", "eps0_c", "gf_t", "a_c", "b_c"];

/// Everything the identification needs.
#[derive(Clone, Debug)]
pub struct LawFit {
    /// Young modulus [Pa].
    pub young_modulus: f64,
    /// Poisson ratio.
    pub poisson: f64,
    /// Hillerborg variant (not `none`).
    pub regularization: Regularization,
    /// Element size h of the comparison [m].
    pub element_size: f64,
    /// DEM tension curve on a uniform grid from 0 (test direction).
    pub tension: Curve,
    /// DEM compression curve on a uniform grid from 0 (shortening, compressive stress positive).
    pub compression: Curve,
    /// Error measure.
    pub measure: ErrorMeasure,
    /// The unknowns ([`UNKNOWNS`] order) and their intervals.
    pub space: Space,
    /// Factorial levels in the unit cube.
    pub levels: [f64; 2],
    /// The EGO loop.
    pub ego: EgoSettings,
    /// Nelder–Mead iterations polishing the EGO optimum ([`super::polish`]); 0: none.
    pub polish_iterations: u64,
}

/// The law's fit at one point.
#[derive(Clone, Debug, Serialize, serde::Deserialize)]
pub struct LawEvaluation {
    /// Tension error.
    pub tension: CurveError,
    /// Compression error.
    pub compression: CurveError,
    /// The sum (the objective).
    pub total: f64,
}

/// The identification's outcome (rank 0).
#[derive(Clone, Debug, Serialize)]
pub struct LawResult {
    /// The identified law.
    pub params: DamageParams,
    /// Its errors.
    pub fit: LawEvaluation,
    /// Relative error of the law's tensile peak against the DEM's.
    pub tension_peak_error: f64,
    /// Relative error of the law's compressive peak against the DEM's.
    pub compression_peak_error: f64,
    /// DEM peaks (tension, compression) [Pa].
    pub dem_peaks: [f64; 2],
    /// Law peaks (tension, compression) [Pa].
    pub law_peaks: [f64; 2],
    /// Every point: iteration, physical coordinates, objective.
    pub history: Vec<(usize, Vec<f64>, Result<f64, String>)>,
    /// Best objective after each evaluation.
    pub best_so_far: Vec<f64>,
    /// The law's curves at the optimum on the DEM grids (tension, compression).
    #[serde(skip)]
    pub law_curves: (Curve, Curve),
}

impl LawFit {
    /// Puts a reference curve on a uniform grid of `points` points from 0 to its last strain.
    pub fn on_grid(c: &Curve, points: usize, what: &str) -> Result<Curve, IdentifyError> {
        c.check(what)?;
        let max = c.x[c.x.len() - 1];
        let grid = uniform_grid(max, points);
        let y = c.resample(&grid);
        Ok(Curve { x: grid, y, loss_of_load: c.loss_of_load })
    }

    /// The law's parameters at the physical point `x`.
    pub fn params_at(&self, x: &[f64]) -> DamageParams {
        DamageParams {
            e: self.young_modulus,
            nu: self.poisson,
            eps0_t: x[0],
            eps0_c: x[1],
            gf_t: x[2],
            a_c: x[3],
            b_c: x[4],
            gf_c: None,
            regularization: self.regularization,
        }
    }

    /// The law's stress (test direction) on the tension and compression grids.
    pub fn law_curves(&self, p: &DamageParams) -> Result<(Curve, Curve), String> {
        let law = p.for_element(self.element_size).map_err(|e| e.to_string())?;
        let run = |c: &Curve, sign: f64| -> Result<Curve, String> {
            let n = c.x.len() - 1;
            let max = c.x[n];
            let path = if sign > 0.0 { LoadPath::<3>::uniaxial_tension(max, n) } else { LoadPath::<3>::uniaxial_compression(max, n) }
                .map_err(|e| e.to_string())?;
            let rec = run_path(PlaneStress, &law, &path, &NewtonSettings::default()).map_err(|e| e.to_string())?;
            Ok(Curve {
                x: rec.iter().map(|r| sign * r.strain[0]).collect(),
                y: rec.iter().map(|r| sign * r.stress[0]).collect(),
                loss_of_load: false,
            })
        };
        Ok((run(&self.tension, 1.0)?, run(&self.compression, -1.0)?))
    }

    /// The errors at the physical point `x`.
    pub fn evaluate(&self, x: &[f64]) -> Result<LawEvaluation, String> {
        let (t, c) = self.law_curves(&self.params_at(x))?;
        let err = |reference: &Curve, model: &Curve, what: &str| {
            curve_error(&reference.y, &model.y, self.measure).ok_or_else(|| format!("{what}: no comparable point"))
        };
        let tension = err(&self.tension, &t, "tension")?;
        let compression = err(&self.compression, &c, "compression")?;
        Ok(LawEvaluation { tension, compression, total: tension.value + compression.value })
    }
}

/// Collective. Runs the identification; rank 0 gets the result.
pub fn identify(ctx: &Context, fit: &LawFit) -> Result<Option<LawResult>, IdentifyError> {
    let design = two_level_factorial(fit.space.dim(), fit.levels)?;
    ctx.log.info(format!(
        "law identification: {} factorial points, then {} infill iteration(s) of {} point(s)",
        design.len(),
        fit.ego.iterations,
        fit.ego.batch
    ));
    let work = |u: &[f64], _: usize| -> TaskResult<LawEvaluation> { fit.evaluate(&fit.space.from_unit(u)) };
    let reduce = |_: &[f64], r: &[TaskResult<LawEvaluation>]| match r.first() {
        Some(Ok(e)) => Ok(e.total),
        Some(Err(m)) => Err(m.clone()),
        None => Err("no result".into()),
    };
    let Some(records) = run_ego(ctx, fit.space.dim(), design, fit.ego.clone(), 1, work, reduce, "law identification")? else {
        return Ok(None);
    };
    let mut history: Vec<_> = records.iter().map(|r| (r.iteration, fit.space.from_unit(&r.unit), r.value.clone())).collect();
    let best = best_record(&records)?;
    let mut x = fit.space.from_unit(&best.unit);
    if fit.polish_iterations > 0 {
        let f = |u: &[f64]| fit.evaluate(&fit.space.from_unit(u)).map(|e| e.total);
        let last = records.iter().map(|r| r.iteration).max().unwrap_or(0) + 1;
        let mut ranked: Vec<&PointRecord<LawEvaluation>> = records.iter().filter(|r| r.value.is_ok()).collect();
        ranked.sort_by(|a, b| a.value.clone().unwrap_or(f64::INFINITY).total_cmp(&b.value.clone().unwrap_or(f64::INFINITY)));
        let starts: Vec<Vec<f64>> = ranked.iter().take(POLISH_STARTS).map(|r| r.unit.clone()).collect();
        let p = super::polish::polish_multistart(&f, &starts, 0.05, fit.polish_iterations, POLISH_RESTARTS).map_err(IdentifyError::Optimizer)?;
        ctx.log.info(format!(
            "law identification: Nelder-Mead polish from the {} best points, {} evaluations: objective {:.6e} -> {:.6e}",
            starts.len(),
            p.evaluations.len(),
            best.value.clone().unwrap_or(f64::NAN),
            p.value
        ));
        history.extend(p.evaluations.iter().map(|(u, v)| (last, fit.space.from_unit(u), v.clone())));
        if best.value.as_ref().is_ok_and(|&b| p.value < b) {
            x = fit.space.from_unit(&p.unit);
        }
    }
    let mut best_so_far = Vec::with_capacity(history.len());
    let mut b = f64::NAN;
    for (_, _, v) in &history {
        if let Ok(v) = v {
            if !(b <= *v) {
                b = *v;
            }
        }
        best_so_far.push(b);
    }
    let params = fit.params_at(&x);
    let fit_eval = fit.evaluate(&x).map_err(IdentifyError::Optimizer)?;
    let law_curves = fit.law_curves(&params).map_err(IdentifyError::Optimizer)?;
    let dem_peaks = [fit.tension.peak().0, fit.compression.peak().0];
    let law_peaks = [law_curves.0.peak().0, law_curves.1.peak().0];
    Ok(Some(LawResult {
        params,
        fit: fit_eval,
        tension_peak_error: (law_peaks[0] - dem_peaks[0]) / dem_peaks[0],
        compression_peak_error: (law_peaks[1] - dem_peaks[1]) / dem_peaks[1],
        dem_peaks,
        law_peaks,
        history,
        best_so_far,
        law_curves,
    }))
}
