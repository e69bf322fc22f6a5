//! Identification of the damage law from DEM virtual tests (paper §3.2b).
//!
//! Unknowns `x = (ε₀^t, ε₀^c, G_f, A_c, B_c)`, optionally a sixth, the compressive fracture
//! energy G_c (`material::params`: it regularizes the compressive softening after the peak, so
//! the post-peak energy of a brittle compression curve is fitted apart from the shape before the
//! peak, which B_c sets); E and ν fixed (from the experiment, or the DEM's means). For each x
//! the law is driven, as a plane-stress material point, along the DEM tests' paths: uniaxial stress, ε_xx imposed on the reference curves' uniform strain grids
//! (`material::run_path`, lateral stresses free); its stress is compared with the DEM's mean
//! curve at the same strains by the error measure ([`super::error_measure`]: paper eq. 15, the
//! relative RMS, or `peak_energy`, the envelope up to the peak, the peak and the post-peak
//! energy). The law's path passes through the reference grid's strains and through its own peak
//! strains ([`LawFit::peak_strains`]), so its peak is exact whatever the grid:
//!
//! ```text
//!   F(x) = F_tension(x) + F_compression(x)
//! ```
//! B_t follows from G_f by the Hillerborg regularization with the element size `h` = the DEM
//! sample's height (the DEM's strain is the platen displacement over the height, so its softening
//! branch is that of one element of length h crossed by the crack), so G_f comes out per unit
//! crack area and the material file serves any mesh.
//!
//! # The tensile energy unknown: the softening energy G_s
//! The third unknown is G_s = f_t h / B_t, h times the area under the post-peak branch. Under
//! `hillerborg` it is G_f. Under `hillerborg_no_elastic` the law's G_f is the whole dissipation
//! per crack area (the crack band's fracture energy, h times the area under the complete curve),
//!
//! ```text
//!   G_f = G_s + f_t² h / (2E)          (B_t = f_t h / (G_f − f_t² h / 2E) = f_t h / G_s)
//! ```
//! so every point of the box is admissible (the variant's limit h < 2 E G_f / f_t² is G_s > 0)
//! and both variants draw the same curve at the identification's h; they differ in the elements
//! of another size: `hillerborg` dissipates G_f + f_t² h_e/(2E) per crack area in an element of
//! size h_e, `hillerborg_no_elastic` G_f in every element. With the paper's wall (h = 1.2 m, f_t
//! 0.19 MPa, E 2.9 GPa) the elastic part f_t² h/(2E) is 7.4 J/m², 70 % of G_s = 10.6 J/m², so the
//! variant that transfers the DEM wall's dissipation to a church element is the second.
//!
//! Initial design: the 2⁵ two-level
//! factorial (the paper's 32 combinations; 2⁶ with G_c); then EGO infill on ln(F + δ); then, since one
//! evaluation costs a fraction of a millisecond, a Nelder–Mead polish from up to
//! [`POLISH_STARTS`] of the best EGO points that lie apart from each other ([`polish_starts`],
//! [`super::polish`]), then one per curve over that curve's own unknowns ([`blocks`]: F is the
//! sum of a tension error in (ε₀ᵗ, G_s) and a compression error in the others); the polishes'
//! evaluations appear in the history as the iteration after the last infill.
use super::collective::TaskResult;
use super::collective::{best_record, run_ego, PointRecord};
use super::curves::{uniform_grid, Curve};
use super::doe::two_level_factorial;
use super::ego::EgoSettings;
use super::error::EvalError;
use super::error::IdentifyError;
use super::error_measure::{curve_distance, CurveError, ErrorMeasure};
use super::space::Space;
use crate::material::{run_path, Control, DamageParams, LoadPath, NewtonSettings, PlaneStress, Regularization, Split};
use crate::parallel::Context;
use serde::Serialize;

/// Starting points of the polish: the best EGO points, each at least [`POLISH_SEPARATION`] from
/// the ones taken before it (the best points of a design crowd into one basin: on the paper's
/// wall the three best lay around A_c = 1, B_c ≈ 2·10⁴ and the polish ended there at F = 0.307;
/// from the 8 best separated points it ends at F = 0.108, B_c ≈ 2.8·10³; see [`polish_starts`]).
pub const POLISH_STARTS: usize = 8;
/// Smallest distance between two starts of the polish, in the unit cube, over `√dim` (the
/// cube's diagonal).
pub const POLISH_SEPARATION: f64 = 0.15;
/// Restarts of each polish from its own result with a fresh simplex (Nelder–Mead stalls on
/// non-smooth objectives such as eq. 15; a restart is the standard remedy).
pub const POLISH_RESTARTS: usize = 3;

/// The unknowns' names, in order (as in the job file and the material file); the optional
/// sixth is [`GF_C`].
pub const UNKNOWNS: [&str; 5] = ["eps0_t", "eps0_c", "gf_t", "a_c", "b_c"];

/// The optional sixth unknown, the compressive fracture energy G_c [J/m²].
pub const GF_C: &str = "gf_c";

/// Law steps per reference grid step on the identified law's curves (the pictures). The
/// objective needs none: under monotonic loading the law's state is a function of the current
/// strain (κ = the current equivalent strain), so its stress at a grid strain does not depend on
/// the steps taken to get there, and the peak strain is a step of its own.
pub const REFINE: usize = 8;

/// Everything the identification needs.
#[derive(Clone, Debug)]
pub struct LawFit {
    /// Young modulus [Pa].
    pub young_modulus: f64,
    /// Poisson ratio.
    pub poisson: f64,
    /// Hillerborg variant (not `none`).
    pub regularization: Regularization,
    /// The law's unilateral split (the paths are uniaxial, but the splits draw different curves).
    pub split: Split,
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
    /// The DEM samples' peak stresses (tension, compression), when known: reported beside the
    /// mean curves' peaks.
    pub sample_peaks: Option<[super::stat::Stat; 2]>,
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

/// One measure's values at the identified law (every measure is reported, whichever was fitted).
#[derive(Clone, Debug, Serialize)]
pub struct MeasureReport {
    /// The measure's job-file name.
    pub measure: &'static str,
    /// Tension.
    pub tension: Option<CurveError>,
    /// Compression.
    pub compression: Option<CurveError>,
}

/// The identification's outcome (rank 0).
#[derive(Clone, Debug, Serialize)]
pub struct LawResult {
    /// The identified law.
    pub params: DamageParams,
    /// The softening energy f_t h / B_t at the identification's h [J/m²] (module docs): G_f
    /// under `hillerborg`, G_f − f_t² h/(2E) under `hillerborg_no_elastic`.
    pub softening_energy: f64,
    /// Its errors.
    pub fit: LawEvaluation,
    /// Relative error of the law's tensile peak against the DEM's.
    pub tension_peak_error: f64,
    /// Relative error of the law's compressive peak against the DEM's.
    pub compression_peak_error: f64,
    /// DEM peaks (`tension`, `compression`) [Pa].
    #[serde(with = "crate::io::summary::tension_compression")]
    pub dem_peaks: [f64; 2],
    /// Law peaks (`tension`, `compression`) [Pa], on the law's refined path.
    #[serde(with = "crate::io::summary::tension_compression")]
    pub law_peaks: [f64; 2],
    /// The DEM samples' peaks (`tension`, `compression`), mean ± std, when known.
    #[serde(with = "crate::io::summary::tension_compression::option")]
    pub dem_sample_peaks: Option<[super::stat::Stat; 2]>,
    /// Every measure (eq. 15, relative RMS, peak_energy) at the identified law.
    pub measures: Vec<MeasureReport>,
    /// Every point: iteration, physical coordinates, objective; in the summary each as
    /// `iteration`, `point` (named by [`UNKNOWNS`]) and `objective`.
    #[serde(serialize_with = "law_history")]
    pub history: Vec<(usize, Vec<f64>, Result<f64, EvalError>)>,
    /// Best objective after each evaluation.
    pub best_so_far: Vec<f64>,
    /// The law's curves at the optimum on the DEM grids (tension, compression).
    #[serde(skip)]
    pub law_curves: (Curve, Curve),
}

fn law_history<S: serde::Serializer>(h: &[(usize, Vec<f64>, Result<f64, EvalError>)], s: S) -> Result<S::Ok, S::Error> {
    super::named_history(&UNKNOWNS, h, s)
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

    /// The law's parameters at the physical point `x` ([`UNKNOWNS`] order; the third is the
    /// softening energy G_s, see the module docs).
    pub fn params_at(&self, x: &[f64]) -> DamageParams {
        let gf_t = match self.regularization {
            Regularization::HillerborgNoElastic => x[2] + self.elastic_energy(x[0]),
            Regularization::Hillerborg | Regularization::Unregularized { .. } => x[2],
        };
        DamageParams {
            e: self.young_modulus,
            nu: self.poisson,
            eps0_t: x[0],
            eps0_c: x[1],
            gf_t,
            a_c: x[3],
            b_c: x[4],
            gf_c: x.get(5).copied(),
            regularization: self.regularization,
            split: self.split,
        }
    }

    /// The law at `x` as the fit evaluates it: at the identification's h, `hillerborg` with
    /// G_f = G_s draws the same curve as [`LawFit::params_at`] under either variant (module docs),
    /// and without the round trip G_s → G_f → B_t the objective, hence the search, is the same
    /// bit for bit whichever variant the material file is written with.
    pub fn curve_params_at(&self, x: &[f64]) -> DamageParams {
        let regularization = match self.regularization {
            Regularization::HillerborgNoElastic => Regularization::Hillerborg,
            r => r,
        };
        DamageParams { gf_t: x[2], regularization, ..self.params_at(x) }
    }

    /// The elastic energy per crack area at the tensile peak, f_t² h / (2E) with f_t = E ε₀ᵗ
    /// [J/m²]: what `hillerborg_no_elastic`'s G_f holds beyond the softening energy G_s.
    pub fn elastic_energy(&self, eps0_t: f64) -> f64 {
        0.5 * self.young_modulus * eps0_t * eps0_t * self.element_size
    }

    /// The softening energy G_s = f_t h / B_t of the law `p` at the identification's h [J/m²]
    /// (module docs): G_f under `hillerborg`, G_f − f_t² h/(2E) under `hillerborg_no_elastic`.
    pub fn softening_energy(&self, p: &DamageParams) -> f64 {
        match p.regularization {
            Regularization::HillerborgNoElastic => p.gf_t - self.elastic_energy(p.eps0_t),
            Regularization::Hillerborg | Regularization::Unregularized { .. } => p.gf_t,
        }
    }

    /// The law's stress (test direction) over the tension and compression grids' ranges, on
    /// paths `refine` times finer than the grids, through the law's peak strains (see
    /// [`LawFit::peak_strains`]), so the peaks are exact whatever the grid.
    pub fn law_curves(&self, p: &DamageParams, refine: usize) -> Result<(Curve, Curve), EvalError> {
        let law = p.for_element(self.element_size).map_err(|e| EvalError::Law { reason: e.to_string() })?;
        let [peak_t, peak_c] = Self::peak_strains(p);
        let run = |c: &Curve, sign: f64, critical: f64| -> Result<Curve, EvalError> {
            let n = (c.x.len() - 1) * refine.max(1);
            let max = c.x[c.x.len() - 1];
            let mut strains: Vec<f64> = (1..=n).map(|k| max * k as f64 / n as f64).collect();
            if critical > 0.0 && critical < max {
                let i = strains.partition_point(|&e| e < critical);
                if strains[i] != critical {
                    strains.insert(i, critical);
                }
            }
            let steps = strains
                .iter()
                .map(|&e| [Control::Strain(sign * e), Control::Stress(0.0), Control::Stress(0.0)])
                .collect();
            let rec = run_path(PlaneStress, &law, &LoadPath::<3>::new(steps), &NewtonSettings::default())
                .map_err(|e| EvalError::Path { reason: e.to_string() })?;
            Ok(Curve {
                x: rec.iter().map(|r| sign * r.strain[0]).collect(),
                y: rec.iter().map(|r| sign * r.stress[0]).collect(),
                loss_of_load: false,
            })
        };
        Ok((run(&self.tension, 1.0, peak_t)?, run(&self.compression, -1.0, peak_c)?))
    }

    /// The axial strains (magnitudes) at the law's uniaxial peaks, paper §3.1: in tension the
    /// threshold ε₀ᵗ (ε_eq = ε_xx: the lateral strains are contractions); in compression the
    /// equivalent strain is κ = r |ε_xx| (r = `DamageParams::uniaxial_compression_ratio`, the
    /// lateral extensions) and eq. 14's stress (1 − A_c) f_c + A_c f_c (κ/ε₀ᶜ) e^{−B_c(κ−ε₀ᶜ)}
    /// peaks at κ_s = max(ε₀ᶜ, 1/B_c), unchanged by the optional G_c, which acts after it;
    /// 0 when r = 0 (no compression damage).
    pub fn peak_strains(p: &DamageParams) -> [f64; 2] {
        let r = p.uniaxial_compression_ratio();
        let kappa_s = p.eps0_c.max(1.0 / p.b_c);
        [p.eps0_t, if r > 0.0 { kappa_s / r } else { 0.0 }]
    }

    /// The errors at the physical point `x`.
    pub fn evaluate(&self, x: &[f64]) -> Result<LawEvaluation, EvalError> {
        let (t, c) = self.law_curves(&self.curve_params_at(x), 1)?;
        let err = |reference: &Curve, model: &Curve, what: &str| {
            curve_distance(reference, model, self.measure)
                .ok_or_else(|| EvalError::NoComparablePoint { curve: what.to_string() })
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
        None => Err(EvalError::NoResult),
    };
    let Some(records) = run_ego(ctx, fit.space.dim(), design, fit.ego.clone(), 1, work, reduce, "law identification")?
    else {
        return Ok(None);
    };
    let mut history: Vec<_> =
        records.iter().map(|r| (r.iteration, fit.space.from_unit(&r.unit), r.value.clone())).collect();
    let best = best_record(&records)?;
    let mut x = fit.space.from_unit(&best.unit);
    if fit.polish_iterations > 0 {
        let f = |u: &[f64]| fit.evaluate(&fit.space.from_unit(u)).map(|e| e.total);
        let last = records.iter().map(|r| r.iteration).max().unwrap_or(0) + 1;
        let mut ranked: Vec<&PointRecord<LawEvaluation>> = records.iter().filter(|r| r.value.is_ok()).collect();
        ranked.sort_by(|a, b| {
            a.value.clone().unwrap_or(f64::INFINITY).total_cmp(&b.value.clone().unwrap_or(f64::INFINITY))
        });
        let starts = polish_starts(ranked.iter().map(|r| r.unit.as_slice()), POLISH_STARTS, POLISH_SEPARATION);
        let p = super::polish::polish_multistart(&f, &starts, 0.05, fit.polish_iterations, POLISH_RESTARTS)?;
        ctx.log.info(format!(
            "law identification: Nelder-Mead polish from the {} best separated points, {} evaluations: objective {:.6e} -> {:.6e}",
            starts.len(),
            p.evaluations.len(),
            best.value.clone().unwrap_or(f64::NAN),
            p.value
        ));
        history.extend(p.evaluations.iter().map(|(u, v)| (last, fit.space.from_unit(u), v.clone())));
        let mut u = best.unit.clone();
        if best.value.as_ref().is_ok_and(|&b| p.value < b) {
            u = p.unit;
        }
        u = polish_blocks(ctx, fit, &records, u, last, &mut history)?;
        x = fit.space.from_unit(&u);
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
    let fit_eval = fit.evaluate(&x).map_err(|e| IdentifyError::Optimizer(e.to_string()))?;
    let law_curves =
        fit.law_curves(&fit.curve_params_at(&x), REFINE).map_err(|e| IdentifyError::Optimizer(e.to_string()))?;
    let dem_peaks = [fit.tension.peak().0, fit.compression.peak().0];
    let law_peaks = [law_curves.0.peak().0, law_curves.1.peak().0];
    let measures = ErrorMeasure::ALL
        .iter()
        .map(|&m| MeasureReport {
            measure: m.name(),
            tension: curve_distance(&fit.tension, &law_curves.0, m),
            compression: curve_distance(&fit.compression, &law_curves.1, m),
        })
        .collect();
    Ok(Some(LawResult {
        softening_energy: fit.softening_energy(&params),
        params,
        fit: fit_eval,
        tension_peak_error: (law_peaks[0] - dem_peaks[0]) / dem_peaks[0],
        compression_peak_error: (law_peaks[1] - dem_peaks[1]) / dem_peaks[1],
        dem_peaks,
        law_peaks,
        dem_sample_peaks: fit.sample_peaks,
        measures,
        history,
        best_so_far,
        law_curves,
    }))
}

/// The unknowns each curve depends on ([`UNKNOWNS`] order): tension (ε₀ᵗ, G_s) and compression
/// (ε₀ᶜ, A_c, B_c[, G_c]). Under uniaxial tension tr σ̃ > 0 and only d_t grows, under uniaxial
/// compression only d_c (paper §3.1's split; the plane-stress switch band lies inside
/// −0.1‖σ̃‖ < tr σ̃ < 0, which neither path enters), so F = F_t(tension block) + F_c(compression block).
pub fn blocks(dim: usize) -> [Vec<usize>; 2] {
    [vec![0, 2], (0..dim).filter(|&i| i != 0 && i != 2).collect()]
}

/// Rank 0 (where the EGO loop returns its records): after the joint polish, a Nelder–Mead polish
/// of each curve's own error over its own unknowns ([`blocks`]), from the current point and the
/// EGO points best for that curve that lie apart. The joint polish works on the sum in 5 or 6
/// unknowns, where a good compression basin can hide behind a tension error; per block the
/// simplex has 2 or 4 vertices less and the starts are ranked by the error it reduces. On the
/// paper's wall the joint polish alone ended with A_c 0.87 (a residual plateau of 0.24 MPa) and
/// compression 0.0974; per block it reaches A_c 0.994 and 0.0947. Each block's evaluations go to the history with
/// the total objective (the other curve's error is constant). The result is kept only where the
/// total falls. Returns the unit-cube point.
fn polish_blocks(
    ctx: &Context,
    fit: &LawFit,
    records: &[PointRecord<LawEvaluation>],
    u0: Vec<f64>,
    iteration: usize,
    history: &mut Vec<(usize, Vec<f64>, Result<f64, EvalError>)>,
) -> Result<Vec<f64>, IdentifyError> {
    let start = fit.evaluate(&fit.space.from_unit(&u0)).map_err(|e| IdentifyError::Optimizer(e.to_string()))?;
    let mut u = u0.clone();
    for (side, block) in blocks(fit.space.dim()).into_iter().enumerate() {
        let part = |e: &LawEvaluation| if side == 0 { e.tension.value } else { e.compression.value };
        let here = fit.evaluate(&fit.space.from_unit(&u)).map_err(|e| IdentifyError::Optimizer(e.to_string()))?;
        let other = here.total - part(&here);
        let with = |v: &[f64]| {
            let mut w = u.clone();
            for (k, &i) in block.iter().enumerate() {
                w[i] = v[k];
            }
            w
        };
        let f = |v: &[f64]| fit.evaluate(&fit.space.from_unit(&with(v))).map(|e| part(&e));
        let own = |w: &[f64]| block.iter().map(|&i| w[i]).collect::<Vec<f64>>();
        let mut ranked: Vec<(Vec<f64>, f64)> = records
            .iter()
            .filter_map(|r| match r.tasks.first() {
                Some(Ok(e)) => Some((own(&r.unit), part(e))),
                _ => None,
            })
            .collect();
        ranked.sort_by(|a, b| a.1.total_cmp(&b.1));
        let points: Vec<Vec<f64>> = std::iter::once(own(&u)).chain(ranked.into_iter().map(|r| r.0)).collect();
        let starts = polish_starts(points.iter().map(Vec::as_slice), POLISH_STARTS, POLISH_SEPARATION);
        let p = super::polish::polish_multistart(&f, &starts, 0.05, fit.polish_iterations, POLISH_RESTARTS)?;
        ctx.log.info(format!(
            "law identification: {} polish over its own {} unknown(s) from {} start(s), {} evaluations: error {:.6e} -> {:.6e}",
            if side == 0 { "tension" } else { "compression" },
            block.len(),
            starts.len(),
            p.evaluations.len(),
            part(&here),
            p.value
        ));
        history.extend(p.evaluations.iter().map(|(v, r)| {
            (iteration, fit.space.from_unit(&with(v)), r.as_ref().map(|e| e + other).map_err(Clone::clone))
        }));
        if p.value < part(&here) {
            u = with(&p.unit);
        }
    }
    let end = fit.evaluate(&fit.space.from_unit(&u)).map_err(|e| IdentifyError::Optimizer(e.to_string()))?;
    Ok(if end.total < start.total { u } else { u0 })
}

/// Up to `n` starting points from `ranked` (best first): a point is taken when its distance to
/// every point taken before is at least `separation · √dim` (unit cube), so that the polish
/// starts in several basins rather than `n` times in the best one.
pub fn polish_starts<'a>(ranked: impl Iterator<Item = &'a [f64]>, n: usize, separation: f64) -> Vec<Vec<f64>> {
    let mut starts: Vec<Vec<f64>> = Vec::with_capacity(n);
    for u in ranked {
        if starts.len() == n {
            break;
        }
        let min = separation * (u.len() as f64).sqrt();
        if starts.iter().all(|s| s.iter().zip(u).map(|(a, b)| (a - b).powi(2)).sum::<f64>().sqrt() >= min) {
            starts.push(u.to_vec());
        }
    }
    starts
}

#[cfg(test)]
mod tests {
    use super::polish_starts;

    #[test]
    fn both_hillerborg_variants_draw_the_same_curve_at_h() {
        // G_s = 10 J/m², ε₀ᵗ = 6.5e-5, E = 2.885 GPa, h = 1.2 m: f_t = 0.1875 MPa, the elastic
        // part f_t² h/(2E) = 0.5 · 2.885e9 · (6.5e-5)² · 1.2 = 7.3134 J/m².
        use super::*;
        let curve = |n: usize, max: f64| Curve {
            x: (0..=n).map(|k| max * k as f64 / n as f64).collect(),
            y: vec![1.0; n + 1],
            loss_of_load: false,
        };
        let fit = |regularization| LawFit {
            young_modulus: 2.885e9,
            poisson: 0.19,
            regularization,
            split: Split::Trace,
            element_size: 1.2,
            tension: curve(40, 1e-3),
            compression: curve(40, 3e-3),
            measure: ErrorMeasure::PeakEnergy,
            space: Space::new(&[("eps0_t", [2e-5, 4e-4])]).unwrap(),
            sample_peaks: None,
            levels: [0.25, 0.75],
            ego: EgoSettings { iterations: 0, batch: 1, seed: 1, log_transform: true, target: None },
            polish_iterations: 0,
        };
        let x = [6.5e-5, 1.4e-4, 10.0, 1.0, 2800.0, 100.0];
        let (a, b) = (fit(Regularization::Hillerborg), fit(Regularization::HillerborgNoElastic));
        let (pa, pb) = (a.params_at(&x), b.params_at(&x));
        assert_eq!(pa.gf_t, 10.0);
        assert!((pb.gf_t - (10.0 + 0.5 * 2.885e9 * 6.5e-5f64.powi(2) * 1.2)).abs() < 1e-12, "{}", pb.gf_t);
        assert!((pb.gf_t - 17.3134).abs() < 1e-4);
        assert!((b.softening_energy(&pb) - 10.0).abs() < 1e-12);
        assert!((pa.b_t(1.2).unwrap() / pb.b_t(1.2).unwrap() - 1.0).abs() < 1e-12);
        let (ca, cb) = (a.law_curves(&pa, 1).unwrap(), b.law_curves(&pb, 1).unwrap());
        for (ya, yb) in ca.0.y.iter().zip(&cb.0.y).chain(ca.1.y.iter().zip(&cb.1.y)) {
            assert!((ya - yb).abs() <= 1e-9 * ya.abs().max(1.0), "{ya} vs {yb}");
        }
        // The fit evaluates both through the same hillerborg law, bit for bit.
        assert_eq!(a.curve_params_at(&x), b.curve_params_at(&x));
        assert_eq!(a.evaluate(&x[..6]).unwrap().total, b.evaluate(&x[..6]).unwrap().total);
        // A point with a small G_s and a high ε₀ᵗ is still admissible under the no-elastic variant.
        assert!(b.params_at(&[4e-4, 1.4e-4, 2.0, 1.0, 2800.0, 100.0]).for_element(1.2).is_ok());
    }

    #[test]
    fn polish_starts_skip_points_crowding_a_taken_one() {
        // Ranked points in 2D (√2 · 0.15 = 0.212 apart at least): the 2nd lies 0.05 from the
        // 1st and the 4th 0.1 from the 3rd, so they are skipped; the cap of 3 stops at the 5th.
        let ranked: Vec<Vec<f64>> =
            vec![vec![0.9, 0.9], vec![0.9, 0.85], vec![0.2, 0.2], vec![0.3, 0.2], vec![0.5, 0.9], vec![0.1, 0.9]];
        let starts = polish_starts(ranked.iter().map(|u| u.as_slice()), 3, 0.15);
        assert_eq!(starts, vec![vec![0.9, 0.9], vec![0.2, 0.2], vec![0.5, 0.9]]);
        // Separation 0: the n best, in order.
        let best = polish_starts(ranked.iter().map(|u| u.as_slice()), 2, 0.0);
        assert_eq!(best, vec![vec![0.9, 0.9], vec![0.9, 0.85]]);
    }
}
