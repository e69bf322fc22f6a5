//! Curves as the identification sees them: monotonic loading curves `(x, y)` in the test's own
//! direction (shortening and compressive stress positive for compression), resampled on a
//! common uniform grid and averaged over samples.
//!
//! Resampling is piecewise linear. Beyond a curve's last point the value is held at its last
//! value, or set to zero when the test ended by loss of load (the wall carries nothing more).
//!
//! # Averaging brittle curves: pointwise or peak-aligned
//! The pointwise mean `f̄(ε) = (1/n) Σ_k f_k(ε)` of curves that drop at different strains is no
//! sample's curve: where one sample has dropped and another has not, it is a staircase whose
//! top is below every sample's peak, and the drops are smeared over the spread of the peak
//! strains. The peak-aligned mean ([`peak_aligned_mean`], [`MeanKind::PeakAligned`]) averages
//! the samples at the same *stage* of their response instead: with sample k's peak (ε_k, f_k)
//! and the mean peak strain ε̄ = (1/n) Σ ε_k,
//!
//! ```text
//!   f̄(ε) = (1/n) Σ_k f_k(ε_k ε/ε̄)            ε ≤ ε̄   (the rising branches, scaled to the mean peak strain)
//!   f̄(ε) = (1/n) Σ_k f_k(ε_k + ε − ε̄)        ε > ε̄   (the post-peak branches, shifted to start there)
//! ```
//! so the mean peak is the mean of the samples' peaks, at the mean peak strain, and the drop
//! stays a drop; the post-peak energy over a strain range after the peak is the samples' mean.
//! Its grid is uniform and passes through ε̄ ([`grid_through`]).
use super::error::IdentifyError;
use serde::{Deserialize, Serialize};

/// A loading curve: abscissae increasing (ties allowed), in the test direction.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct Curve {
    /// Strain (test direction, ≥ 0).
    pub x: Vec<f64>,
    /// Stress (test direction) [Pa].
    pub y: Vec<f64>,
    /// Whether the test stopped on loss of load (the value beyond the end is zero).
    pub loss_of_load: bool,
}

impl Curve {
    /// Checks that the curve can be fitted: at least two points, finite values, a non-zero
    /// stress somewhere and a strain range; `what` names it in the error.
    pub fn check(&self, what: &str) -> Result<(), IdentifyError> {
        let bad = |reason: String| IdentifyError::BadCurve { what: what.to_string(), reason };
        if self.x.len() < 2 || self.x.len() != self.y.len() {
            return Err(bad(format!(
                "needs at least two (strain, stress) points, got {}",
                self.x.len().min(self.y.len())
            )));
        }
        if self.x.iter().chain(&self.y).any(|v| !v.is_finite()) {
            return Err(bad("has non-finite values".into()));
        }
        let ymax = self.y.iter().fold(0.0f64, |m, v| m.max(v.abs()));
        if ymax == 0.0 {
            return Err(bad("is flat: the stress is zero everywhere".into()));
        }
        let (x0, x1) = (self.x[0], self.x[self.x.len() - 1]);
        if !(x1 > x0) {
            return Err(bad(format!("is flat in strain: from {x0} to {x1}")));
        }
        Ok(())
    }

    /// Largest stress (test direction) and the strain there.
    pub fn peak(&self) -> (f64, f64) {
        self.x.iter().zip(&self.y).fold((0.0, 0.0), |(py, px), (&x, &y)| if y > py { (y, x) } else { (py, px) })
    }

    /// Linear interpolation at `t` (held / zero beyond the end, see the module docs; the first
    /// value before the start).
    pub fn at(&self, t: f64) -> f64 {
        let n = self.x.len();
        if n == 0 {
            return 0.0;
        }
        if t <= self.x[0] {
            return self.y[0];
        }
        if t > self.x[n - 1] {
            return if self.loss_of_load { 0.0 } else { self.y[n - 1] };
        }
        // First index with x ≥ t (x sorted).
        let k = self.x.partition_point(|&v| v < t).max(1);
        let (x0, x1, y0, y1) = (self.x[k - 1], self.x[k], self.y[k - 1], self.y[k]);
        if x1 > x0 {
            y0 + (y1 - y0) * (t - x0) / (x1 - x0)
        } else {
            y1
        }
    }

    /// Values on `grid`.
    pub fn resample(&self, grid: &[f64]) -> Vec<f64> {
        grid.iter().map(|&t| self.at(t)).collect()
    }

    /// Keeps the running maximum of x only (drops points where the strain went back), so the
    /// abscissae are sorted, as [`Curve::at`] needs.
    pub fn monotonic(mut self) -> Curve {
        let mut keep_x = Vec::with_capacity(self.x.len());
        let mut keep_y = Vec::with_capacity(self.y.len());
        for (&x, &y) in self.x.iter().zip(&self.y) {
            if keep_x.last().is_none_or(|&l| x >= l) {
                keep_x.push(x);
                keep_y.push(y);
            }
        }
        self.x = keep_x;
        self.y = keep_y;
        self
    }
}

/// How the virtual tests' sample curves are averaged (module docs).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Serialize, Deserialize, schemars::JsonSchema)]
#[serde(rename_all = "snake_case")]
pub enum MeanKind {
    /// Rising branches scaled to the mean peak strain, post-peak branches shifted to it.
    #[default]
    PeakAligned,
    /// The pointwise mean at each strain.
    Pointwise,
}

/// About `points` uniform points from 0 with `at` (0 < at) one of them: spacing Δ = at/m,
/// m = round(at (points − 1)/max) ≥ 1, up to the last multiple of Δ not beyond `max` (at least
/// up to `at`).
pub fn grid_through(max: f64, points: usize, at: f64) -> Vec<f64> {
    let points = points.max(2);
    let m = ((at / max) * (points - 1) as f64).round().max(1.0);
    let step = at / m;
    let n = ((max / step) * (1.0 + 1e-12)).floor().max(m) as usize + 1;
    (0..n).map(|k| if k as f64 == m { at } else { step * k as f64 }).collect()
}

/// The peak-aligned mean of `curves` (module docs) on [`grid_through`]`(max, points, ε̄)`; the
/// pointwise mean on a uniform grid when the mean peak strain is not positive (no sample rises).
pub fn peak_aligned_mean(curves: &[Curve], max: f64, points: usize, what: &str) -> Result<Curve, IdentifyError> {
    if curves.is_empty() {
        return Err(IdentifyError::BadCurve { what: what.into(), reason: "no sample produced a curve".into() });
    }
    let n = curves.len() as f64;
    let peaks: Vec<f64> = curves.iter().map(|c| c.peak().1).collect();
    let mean_peak = peaks.iter().sum::<f64>() / n;
    let Ok(mean_peak) = crate::bounds::positive(mean_peak) else {
        return mean_curve(curves, &uniform_grid(max, points), what);
    };
    let grid = grid_through(max.max(mean_peak), points, mean_peak);
    let y = grid
        .iter()
        .map(|&t| {
            curves
                .iter()
                .zip(&peaks)
                .map(|(c, &ek)| if t <= mean_peak { c.at(ek * t / mean_peak) } else { c.at(ek + t - mean_peak) })
                .sum::<f64>()
                / n
        })
        .collect();
    Ok(Curve { x: grid, y, loss_of_load: curves.iter().all(|c| c.loss_of_load) })
}

/// The mean of `curves` by `kind`: on about `points` points from 0 to `max`.
pub fn mean_of(kind: MeanKind, curves: &[Curve], max: f64, points: usize, what: &str) -> Result<Curve, IdentifyError> {
    match kind {
        MeanKind::Pointwise => mean_curve(curves, &uniform_grid(max, points), what),
        MeanKind::PeakAligned => peak_aligned_mean(curves, max, points, what),
    }
}

/// Sample curves as CSV, one row per point: `sample,strain,stress,loss_of_load` (test direction;
/// loss_of_load 1 when the sample's test ended by loss of load or collapse). Read back by
/// [`read_sample_curves_csv`].
pub fn sample_curves_csv(curves: &[Curve]) -> String {
    let mut s = String::from("sample,strain,stress,loss_of_load\n");
    for (k, c) in curves.iter().enumerate() {
        for (x, y) in c.x.iter().zip(&c.y) {
            s.push_str(&format!("{k},{x:e},{y:e},{}\n", u8::from(c.loss_of_load)));
        }
    }
    s
}

/// Reads [`sample_curves_csv`]'s format (rows of one sample together, strains not decreasing);
/// errors name the file and line.
pub fn read_sample_curves_csv(file: &std::path::Path) -> Result<Vec<Curve>, IdentifyError> {
    let text = std::fs::read_to_string(file)
        .map_err(|e| IdentifyError::Read { file: file.to_path_buf(), reason: e.to_string() })?;
    let mut lines = text.lines().enumerate().filter(|(_, l)| !l.trim().is_empty() && !l.trim_start().starts_with('#'));
    let Some((_, header)) = lines.next() else {
        return Err(bad(file, None, "empty file (expected the header sample,strain,stress,loss_of_load)".into()));
    };
    let cols: Vec<&str> = header.split(',').map(str::trim).collect();
    if cols != ["sample", "strain", "stress", "loss_of_load"] {
        return Err(bad(file, Some(1), format!("expected the header sample,strain,stress,loss_of_load, got {header}")));
    }
    let mut curves: Vec<(String, Curve)> = Vec::new();
    for (n, line) in lines {
        let f: Vec<&str> = line.split(',').map(str::trim).collect();
        let at = |what: String| bad(file, Some(n + 1), what);
        if f.len() != 4 {
            return Err(at(format!("expected 4 columns, got {}", f.len())));
        }
        let num = |i: usize, name: &str| f[i].parse::<f64>().map_err(|e| at(format!("column '{name}': {e}")));
        let (x, y) = (num(1, "strain")?, num(2, "stress")?);
        let loss = match f[3] {
            "0" => false,
            "1" => true,
            other => return Err(at(format!("column 'loss_of_load': expected 0 or 1, got '{other}'"))),
        };
        if curves.last().is_none_or(|(k, _)| k != f[0]) {
            if curves.iter().any(|(k, _)| k == f[0]) {
                return Err(at(format!("the rows of sample {} are not together", f[0])));
            }
            curves.push((f[0].to_string(), Curve { x: Vec::new(), y: Vec::new(), loss_of_load: loss }));
        }
        let Some((_, c)) = curves.last_mut() else { continue };
        if c.x.last().is_some_and(|&l| x < l) {
            return Err(at(format!("strain {x} decreases (sample {})", f[0])));
        }
        c.x.push(x);
        c.y.push(y);
        c.loss_of_load |= loss;
    }
    if curves.is_empty() {
        return Err(bad(file, None, "no sample rows after the header".into()));
    }
    Ok(curves.into_iter().map(|(_, c)| c).collect())
}

/// `n` uniform points on `[0, max]` (0 included), `n ≥ 2`.
pub fn uniform_grid(max: f64, n: usize) -> Vec<f64> {
    let n = n.max(2);
    (0..n).map(|k| max * k as f64 / (n - 1) as f64).collect()
}

/// The pointwise mean of `curves` on `grid`; an error if there is none.
pub fn mean_curve(curves: &[Curve], grid: &[f64], what: &str) -> Result<Curve, IdentifyError> {
    if curves.is_empty() {
        return Err(IdentifyError::BadCurve { what: what.into(), reason: "no sample produced a curve".into() });
    }
    let mut y = vec![0.0; grid.len()];
    for c in curves {
        for (v, r) in y.iter_mut().zip(c.resample(grid)) {
            *v += r / curves.len() as f64;
        }
    }
    Ok(Curve { x: grid.to_vec(), y, loss_of_load: curves.iter().all(|c| c.loss_of_load) })
}

/// Reads a curve from a CSV file with a header naming the columns `strain` and `stress` (other
/// columns ignored; the DEM job's `sample-KKK/curve.csv` qualifies). Signs: the curve is turned
/// into the test direction by the sign of its largest-magnitude stress, so tension-positive
/// compression curves and positive-magnitude ones both work. Errors name the file and line.
pub fn read_curve_csv(file: &std::path::Path) -> Result<Curve, IdentifyError> {
    let text = std::fs::read_to_string(file)
        .map_err(|e| IdentifyError::Read { file: file.to_path_buf(), reason: e.to_string() })?;
    let mut lines = text.lines().enumerate().filter(|(_, l)| !l.trim().is_empty() && !l.trim_start().starts_with('#'));
    let Some((_, header)) = lines.next() else {
        return Err(bad(file, None, "empty file (expected a header with columns strain and stress)".into()));
    };
    let cols: Vec<&str> = header.split(',').map(str::trim).collect();
    let find = |name: &str| {
        cols.iter()
            .position(|c| *c == name)
            .ok_or_else(|| bad(file, Some(1), format!("no column '{name}' in the header ({header})")))
    };
    let (ix, iy) = (find("strain")?, find("stress")?);
    let (mut x, mut y) = (Vec::new(), Vec::new());
    for (n, line) in lines {
        let f: Vec<&str> = line.split(',').map(str::trim).collect();
        let get = |i: usize, name: &str| -> Result<f64, IdentifyError> {
            f.get(i)
                .ok_or_else(|| bad(file, Some(n + 1), format!("missing column '{name}'")))?
                .parse::<f64>()
                .map_err(|e| bad(file, Some(n + 1), format!("column '{name}': {e}")))
        };
        x.push(get(ix, "strain")?);
        y.push(get(iy, "stress")?);
    }
    let s = y.iter().fold(0.0f64, |m, &v| if v.abs() > m.abs() { v } else { m });
    let sign = if s < 0.0 { -1.0 } else { 1.0 };
    let c =
        Curve { x: x.iter().map(|v| sign * v).collect(), y: y.iter().map(|v| sign * v).collect(), loss_of_load: false };
    Ok(c.monotonic())
}

/// A malformed curve file, at `line` when one is at fault.
fn bad(file: &std::path::Path, line: Option<usize>, reason: String) -> IdentifyError {
    IdentifyError::CurveFile { file: file.to_path_buf(), line, reason }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn interpolates_holds_and_drops_to_zero() {
        let c = Curve { x: vec![0.0, 1.0, 2.0], y: vec![0.0, 2.0, 1.0], loss_of_load: false };
        assert_eq!(c.resample(&[0.5, 1.5, 3.0]), vec![1.0, 1.5, 1.0]);
        let d = Curve { loss_of_load: true, ..c.clone() };
        assert_eq!(d.at(3.0), 0.0);
        assert_eq!(c.peak(), (2.0, 1.0));
        let m = mean_curve(&[c, d], &[1.5, 3.0], "t").unwrap();
        assert_eq!(m.y, vec![1.5, 0.5]);
    }

    #[test]
    fn peak_aligned_mean_keeps_the_mean_peak_and_the_drop() {
        // Sample 1: peak 2 at ε = 1, drop to 0.5, held to 3. Sample 2: peak 4 at ε = 3, drop
        // to 1, held to 5. Mean peak strain 2: the aligned mean there is (2 + 4)/2 = 3, the mean
        // of the peaks; the pointwise mean at ε = 2 would be (0.5 + 8/3)/2 (sample 1 dropped).
        let c1 = Curve { x: vec![0.0, 1.0, 1.0, 3.0], y: vec![0.0, 2.0, 0.5, 0.5], loss_of_load: false };
        let c2 = Curve { x: vec![0.0, 3.0, 3.0, 5.0], y: vec![0.0, 4.0, 1.0, 1.0], loss_of_load: false };
        let m = peak_aligned_mean(&[c1, c2], 4.0, 5, "t").unwrap();
        // Grid through ε̄ = 2 with about 5 points on [0, 4]: step 1.
        assert_eq!(m.x, vec![0.0, 1.0, 2.0, 3.0, 4.0]);
        // ε = 1: sample 1 at 0.5 → 1, sample 2 at 1.5 → 2: 1.5. ε = 3, 4 (1 and 2 after the
        // peak): sample 1 at 2, 3 → 0.5, sample 2 at 4, 5 → 1: 0.75.
        let want = [0.0, 1.5, 3.0, 0.75, 0.75];
        for (a, b) in m.y.iter().zip(want) {
            assert!((a - b).abs() < 1e-12, "{:?}", m.y);
        }
        assert_eq!(m.peak(), (3.0, 2.0));
    }

    #[test]
    fn grid_passes_through_the_point() {
        let g = grid_through(1.0e-3, 60, 1.9e-4);
        // m = round(0.19 · 59) = 11 steps to 1.9e-4.
        assert_eq!(g[11], 1.9e-4);
        assert!((g[1] - 1.9e-4 / 11.0).abs() < 1e-18);
        assert!(*g.last().unwrap() <= 1.0e-3 * (1.0 + 1e-12) && 1.0e-3 - g.last().unwrap() < 1.9e-4 / 11.0);
    }

    #[test]
    fn sample_curves_round_trip() {
        let dir = std::env::temp_dir().join(format!("masonry-hpc-curves-{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        let f = dir.join("s.csv");
        let a = Curve { x: vec![0.0, 1e-4, 1e-4], y: vec![0.0, 2e5, 1e4], loss_of_load: true };
        let b = Curve { x: vec![0.0, 2e-4], y: vec![0.0, 3e5], loss_of_load: false };
        std::fs::write(&f, sample_curves_csv(&[a.clone(), b.clone()])).unwrap();
        assert_eq!(read_sample_curves_csv(&f).unwrap(), vec![a, b]);
        std::fs::write(&f, "sample,strain,stress,loss_of_load\n0,1e-4,1,0\n0,0.5e-4,1,0\n").unwrap();
        let e = read_sample_curves_csv(&f).unwrap_err().to_string();
        assert!(e.contains("s.csv:3:") && e.contains("decreases"), "{e}");
        std::fs::remove_dir_all(&dir).ok();
    }

    #[test]
    fn empty_and_flat_curves_are_rejected() {
        let flat = Curve { x: vec![0.0, 1.0], y: vec![0.0, 0.0], loss_of_load: false };
        assert!(flat.check("DEM tension").unwrap_err().to_string().contains("flat"));
        let empty = Curve { x: vec![], y: vec![], loss_of_load: false };
        assert!(empty.check("DEM tension").unwrap_err().to_string().contains("at least two"));
    }
}
