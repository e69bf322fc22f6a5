//! Stage 1 of the staged DEM calibration ([`super::calibration`]): the elastic parameters
//! `(α, Ē)` from the measured `(ν, E)`, on the elastic state alone.
//!
//! Why it can be done apart: before the first beam breaks the lattice is linear elastic. Every
//! stiffness of the lattice is proportional to Ē (beams `Ē A / L`, `Ē I / L`, contacts scaled
//! with them), and α enters only through the beams' inertia `I = α t L_f³ / 12`. So, over a fixed
//! set of samples (common random numbers),
//!
//! ```text
//!   ν̄(α, Ē, ε_cr, θ_cr, σ_c) = ν̄(α)             (a ratio of strains: Ē cancels)
//!   Ē(α, Ē, …)  = Ē · ḡ(α),    ḡ(α) = mean_k E_k / Ē
//! ```
//! independent of the strengths (they act only after the first break). ν̄ decreases with α (a
//! stiffer bending response restrains the lateral expansion: docs/dem-elastic-constants.md, 0.238 at α = 0.2 to
//! 0.082 at 1.2). Hence:
//!
//! 1. `ν̄(α) = ν_target` is a one-dimensional root: a grid of `GRID` values of α over its
//!    bounds brackets it; regula falsi in the bracket (linear interpolation between the two
//!    bracketing points, the bracket shrunk to the side of the new point) refines it until
//!    `|ν̄ − ν_t| ≤ tol · ν_t` or `max_rounds` rounds;
//! 2. `Ē = E_target / ḡ(α)`, exact because E is linear in Ē.
//!
//! Every value reported comes from an evaluated point (no extrapolation): α is the evaluated
//! point closest to the target. A target outside ν̄'s range over the α bounds ends at the nearer
//! bound (reported, not an error: the later stages still run and the result file shows the miss);
//! a ν̄ that does not decrease along the evaluated points is an error (no unique α).
//!
//! The search is ask-and-tell ([`ElasticSearch::first`], [`ElasticSearch::tell`],
//! [`ElasticSearch::ask`]), so the evaluations run as MPI batches between questions
//! ([`super::collective::run_rounds`]) and the logic is tested without the DEM.
use super::error::{EvalError, IdentifyError};
use super::stat::Stat;
use serde::Serialize;

/// α values of the initial grid (bounds included).
pub const GRID: usize = 5;
/// Strain of the elastic loading state: far below any first crack (ε_cr ≳ 3e-5), so the state
/// is the linear one; E and ν are those of the full test's first loading state to round-off.
pub const ELASTIC_STRAIN: f64 = 1e-6;

/// The sample means at one α (any Ē).
#[derive(Clone, Copy, Debug, PartialEq, Serialize)]
pub struct ElasticMeans {
    /// ν over the samples.
    pub poisson: Stat,
    /// E / Ē over the samples.
    pub e_ratio: Stat,
}

/// One evaluated α.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct ElasticPoint {
    /// Round (0 = the grid).
    pub round: usize,
    /// α.
    pub alpha: f64,
    /// The means, or why the point could not be evaluated.
    #[serde(serialize_with = "crate::io::summary::with_message")]
    pub value: Result<ElasticMeans, EvalError>,
}

/// Settings of the search.
#[derive(Clone, Copy, Debug, PartialEq, Serialize)]
pub struct ElasticSettings {
    /// α bounds.
    pub alpha: [f64; 2],
    /// Ē bounds [Pa].
    pub e_bar: [f64; 2],
    /// Target ν.
    pub poisson: f64,
    /// Target E [Pa].
    pub young_modulus: f64,
    /// Relative tolerance on ν̄.
    pub tolerance: f64,
    /// Refinement rounds after the grid.
    pub max_rounds: usize,
}

impl ElasticSettings {
    /// Defaults: ν within 0.1 % (well inside the sample scatter, std ≈ 4 % of ν), 10 rounds.
    pub fn new(alpha: [f64; 2], e_bar: [f64; 2], poisson: f64, young_modulus: f64) -> ElasticSettings {
        ElasticSettings { alpha, e_bar, poisson, young_modulus, tolerance: 1e-3, max_rounds: 10 }
    }
}

/// The outcome of stage 1.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct ElasticFit {
    /// Identified α.
    pub alpha: f64,
    /// Identified Ē [Pa].
    pub e_bar: f64,
    /// ν̄ at α (sample statistics).
    pub poisson: Stat,
    /// E at (α, Ē) [Pa]: Ē · (E/Ē)'s statistics.
    pub young_modulus: Stat,
    /// Whether ν̄ reached the tolerance.
    pub converged: bool,
    /// What limited the fit (a bound), if anything.
    pub note: Option<String>,
    /// Every evaluated α.
    pub points: Vec<ElasticPoint>,
}

/// The ask-and-tell search of stage 1 (see the module docs).
#[derive(Clone, Debug)]
pub struct ElasticSearch {
    s: ElasticSettings,
    points: Vec<ElasticPoint>,
    round: usize,
    done: bool,
}

impl ElasticSearch {
    /// A new search; the bounds must be finite with lower < upper and α > 0, Ē > 0.
    pub fn new(s: ElasticSettings) -> Result<ElasticSearch, IdentifyError> {
        for (name, [lo, hi]) in [("alpha", s.alpha), ("e_bar", s.e_bar)] {
            if !(lo.is_finite() && hi.is_finite() && lo > 0.0 && lo < hi) {
                return Err(IdentifyError::InvalidBounds { name: name.into(), lower: lo, upper: hi });
            }
        }
        if !s.poisson.is_finite() || crate::bounds::positive(s.young_modulus).is_err() {
            return Err(IdentifyError::Settings(format!(
                "elastic fit: invalid targets E = {}, nu = {}",
                s.young_modulus, s.poisson
            )));
        }
        Ok(ElasticSearch { s, points: Vec::new(), round: 0, done: false })
    }

    /// The initial grid: `GRID` values of α evenly over its bounds.
    pub fn first(&self) -> Vec<f64> {
        let [lo, hi] = self.s.alpha;
        (0..GRID).map(|i| lo + (hi - lo) * i as f64 / (GRID - 1) as f64).collect()
    }

    /// Records the means at `alphas` (the last batch asked for).
    pub fn tell(&mut self, alphas: &[f64], values: Vec<Result<ElasticMeans, EvalError>>) {
        for (&alpha, value) in alphas.iter().zip(values) {
            let value = match value {
                Ok(m) if !(m.poisson.mean.is_finite() && m.e_ratio.mean.is_finite() && m.e_ratio.mean > 0.0) => {
                    Err(EvalError::NoFiniteElastic { alpha, poisson: m.poisson.mean, e_ratio: m.e_ratio.mean })
                }
                v => v,
            };
            self.points.push(ElasticPoint { round: self.round, alpha, value });
        }
        self.round += 1;
    }

    /// The evaluated points with their means, sorted by α.
    fn ok_sorted(&self) -> Vec<(f64, ElasticMeans)> {
        let mut v: Vec<(f64, ElasticMeans)> =
            self.points.iter().filter_map(|p| p.value.as_ref().ok().map(|m| (p.alpha, *m))).collect();
        v.sort_by(|a, b| a.0.total_cmp(&b.0));
        v
    }

    /// The evaluated point whose ν̄ is closest to the target.
    fn closest(&self) -> Option<(f64, ElasticMeans)> {
        let t = self.s.poisson;
        self.ok_sorted()
            .into_iter()
            .min_by(|a, b| (a.1.poisson.mean - t).abs().total_cmp(&(b.1.poisson.mean - t).abs()))
    }

    /// The next α to evaluate, or `None` when the fit is done (converged, at a bound, or out of
    /// rounds). Errors: fewer than two points evaluated; ν̄ not decreasing in α.
    pub fn ask(&mut self) -> Result<Option<Vec<f64>>, IdentifyError> {
        if self.done {
            return Ok(None);
        }
        let pts = self.ok_sorted();
        if pts.len() < 2 {
            let first_failure =
                self.points.iter().find_map(|p| p.value.as_ref().err()).map_or("none".into(), |e| e.to_string());
            return Err(IdentifyError::TooFewPoints { needed: 2, got: pts.len(), first_failure });
        }
        if let Some(w) = pts.windows(2).find(|w| !(w[1].1.poisson.mean < w[0].1.poisson.mean)) {
            return Err(IdentifyError::Settings(format!(
                "elastic fit: the mean Poisson ratio does not decrease with alpha (nu = {:.5} at alpha = {}, {:.5} at alpha = {}): alpha is not identifiable from nu here",
                w[0].1.poisson.mean, w[0].0, w[1].1.poisson.mean, w[1].0
            )));
        }
        let t = self.s.poisson;
        let f = |m: &ElasticMeans| m.poisson.mean - t;
        let converged = self.closest().is_some_and(|(_, m)| f(&m).abs() <= self.s.tolerance * t.abs());
        let bracket = pts.windows(2).find(|w| f(&w[0].1) >= 0.0 && f(&w[1].1) <= 0.0);
        let Some(w) = bracket else {
            self.done = true; // the target lies outside ν̄'s range: result() reports the bound
            return Ok(None);
        };
        if converged || self.round > self.s.max_rounds {
            self.done = true;
            return Ok(None);
        }
        let ((a, fa), (b, fb)) = ((w[0].0, f(&w[0].1)), (w[1].0, f(&w[1].1)));
        // Regula falsi: the zero of the chord through the bracket's ends.
        let next = if fa == fb { 0.5 * (a + b) } else { a + fa * (b - a) / (fa - fb) };
        let width = self.s.alpha[1] - self.s.alpha[0];
        if self.points.iter().any(|p| (p.alpha - next).abs() <= 1e-9 * width) {
            self.done = true;
            return Ok(None);
        }
        Ok(Some(vec![next]))
    }

    /// The fit: α the evaluated point closest to the target, Ē = E_t / ḡ(α) within its bounds.
    pub fn result(&self) -> Result<ElasticFit, IdentifyError> {
        let (alpha, m) = self.closest().ok_or_else(|| IdentifyError::TooFewPoints {
            needed: 1,
            got: 0,
            first_failure: self
                .points
                .iter()
                .find_map(|p| p.value.as_ref().err())
                .map(|e| e.to_string())
                .unwrap_or_default(),
        })?;
        let t = self.s.poisson;
        let converged = (m.poisson.mean - t).abs() <= self.s.tolerance * t.abs();
        let mut notes = Vec::new();
        if !converged {
            let pts = self.ok_sorted();
            let (lo, hi) = (pts[0].1.poisson.mean, pts[pts.len() - 1].1.poisson.mean);
            if t > lo || t < hi {
                notes.push(format!(
                    "the target nu = {t} is outside the mean nu over the alpha bounds [{}, {}] ({hi:.4} to {lo:.4}): alpha stays at the bound {alpha}",
                    self.s.alpha[0], self.s.alpha[1]
                ));
            } else {
                notes.push(format!("nu not within {} of its target after {} round(s)", self.s.tolerance, self.round));
            }
        }
        let wanted = self.s.young_modulus / m.e_ratio.mean;
        let e_bar = wanted.clamp(self.s.e_bar[0], self.s.e_bar[1]);
        if e_bar != wanted {
            notes.push(format!(
                "E = {} Pa needs e_bar = {wanted:.4e} Pa, outside its bounds [{:e}, {:e}]: e_bar = {e_bar:.4e} Pa",
                self.s.young_modulus, self.s.e_bar[0], self.s.e_bar[1]
            ));
        }
        let young_modulus = Stat { mean: e_bar * m.e_ratio.mean, std: e_bar * m.e_ratio.std, n: m.e_ratio.n };
        Ok(ElasticFit {
            alpha,
            e_bar,
            poisson: m.poisson,
            young_modulus,
            converged,
            note: if notes.is_empty() { None } else { Some(notes.join("; ")) },
            points: self.points.clone(),
        })
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A synthetic lattice: ν̄(α) decreasing and curved (docs/dem-elastic-constants.md's wall values, 0.238 at
    /// α 0.2 to 0.082 at 1.2, follow ν ≈ 0.3 − 0.35 α + 0.12 α²), E = Ē (0.7 + 0.25 α).
    fn means(alpha: f64) -> ElasticMeans {
        let nu = 0.3 - 0.35 * alpha + 0.12 * alpha * alpha;
        let st = |mean: f64| Stat { mean, std: 0.04 * mean, n: 8 };
        ElasticMeans { poisson: st(nu), e_ratio: st(0.7 + 0.25 * alpha) }
    }

    fn run(s: ElasticSettings) -> (ElasticFit, usize) {
        let mut search = ElasticSearch::new(s).unwrap();
        let mut batch = search.first();
        let mut evaluations = 0;
        loop {
            evaluations += batch.len();
            let values = batch.iter().map(|&a| Ok(means(a))).collect();
            search.tell(&batch, values);
            match search.ask().unwrap() {
                Some(b) => batch = b,
                None => break,
            }
        }
        (search.result().unwrap(), evaluations)
    }

    #[test]
    fn recovers_alpha_and_e_bar_of_a_synthetic_lattice() {
        // Truth: α* solves 0.3 − 0.35 α + 0.12 α² = 0.19 (the smaller root of the quadratic),
        // Ē* = 2.885e9 / (0.7 + 0.25 α*).
        let (a, b, c): (f64, f64, f64) = (0.12, -0.35, 0.3 - 0.19);
        let alpha_true = (-b - (b * b - 4.0 * a * c).sqrt()) / (2.0 * a);
        let e_bar_true = 2.885e9 / (0.7 + 0.25 * alpha_true);
        let s = ElasticSettings::new([0.2, 0.8], [2.0e9, 5.0e9], 0.19, 2.885e9);
        let (fit, evaluations) = run(s);
        assert!(fit.converged && fit.note.is_none(), "{fit:?}");
        // ν within the tolerance 1e-3 relative; dν/dα ≈ −0.25 here, so α within
        // 1e-3 · 0.19 / 0.25 ≈ 8e-4, and Ē (through ḡ, dḡ/dα / ḡ ≈ 0.3) within 3e-4 relative.
        assert!((fit.poisson.mean - 0.19).abs() <= 1e-3 * 0.19, "{fit:?}");
        assert!((fit.alpha - alpha_true).abs() < 8e-4, "alpha {} vs {alpha_true}", fit.alpha);
        assert!((fit.e_bar - e_bar_true).abs() < 3e-4 * e_bar_true, "e_bar {} vs {e_bar_true}", fit.e_bar);
        // E at the identified point is the target exactly (E linear in Ē).
        assert!((fit.young_modulus.mean - 2.885e9).abs() < 1e-9 * 2.885e9);
        // The grid of 5, then a few regula falsi rounds: a cheap stage.
        assert!(evaluations <= GRID + 4, "{evaluations} evaluations");
    }

    #[test]
    fn a_target_outside_the_range_stops_at_the_bound_and_says_so() {
        // ν̄(0.5) = 0.155 is the lowest the bounds reach: ν = 0.12 is out of range.
        let (fit, _) = run(ElasticSettings::new([0.2, 0.5], [2.0e9, 5.0e9], 0.12, 2.885e9));
        assert_eq!(fit.alpha, 0.5);
        assert!(!fit.converged && fit.note.as_ref().is_some_and(|n| n.contains("outside")), "{fit:?}");
        // Ē at its upper bound when E needs more.
        let (fit, _) = run(ElasticSettings::new([0.2, 0.8], [2.0e9, 3.0e9], 0.19, 2.885e9));
        assert_eq!(fit.e_bar, 3.0e9);
        assert!(fit.note.as_ref().is_some_and(|n| n.contains("e_bar")), "{fit:?}");
    }

    #[test]
    fn a_non_decreasing_nu_is_an_error() {
        let mut search = ElasticSearch::new(ElasticSettings::new([0.2, 0.8], [2.0e9, 5.0e9], 0.19, 2.885e9)).unwrap();
        let batch = search.first();
        let values = batch.iter().map(|&a| Ok(means(1.0 - a))).collect(); // increasing in α
        search.tell(&batch, values);
        let e = search.ask().unwrap_err();
        assert!(e.to_string().contains("does not decrease"), "{e}");
    }
}
