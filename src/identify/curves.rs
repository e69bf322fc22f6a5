//! Curves as the identification sees them: monotonic loading curves `(x, y)` in the test's own
//! direction (shortening and compressive stress positive for compression), resampled on a
//! common uniform grid and averaged over samples.
//!
//! Resampling is piecewise linear. Beyond a curve's last point the value is held at its last
//! value, or set to zero when the test ended by loss of load (the wall carries nothing more).
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
            return Err(bad(format!("needs at least two (strain, stress) points, got {}", self.x.len().min(self.y.len()))));
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
    fn empty_and_flat_curves_are_rejected() {
        let flat = Curve { x: vec![0.0, 1.0], y: vec![0.0, 0.0], loss_of_load: false };
        assert!(flat.check("DEM tension").unwrap_err().to_string().contains("flat"));
        let empty = Curve { x: vec![], y: vec![], loss_of_load: false };
        assert!(empty.check("DEM tension").unwrap_err().to_string().contains("at least two"));
    }
}

/// Reads a curve from a CSV file with a header naming the columns `strain` and `stress` (other
/// columns ignored; the DEM job's `sample-KKK/curve.csv` qualifies). Signs: the curve is turned
/// into the test direction by the sign of its largest-magnitude stress, so tension-positive
/// compression curves and positive-magnitude ones both work. Errors name the file and line.
pub fn read_curve_csv(file: &std::path::Path) -> Result<Curve, String> {
    let text = std::fs::read_to_string(file).map_err(|e| format!("cannot read {}: {e}", file.display()))?;
    let mut lines = text.lines().enumerate().filter(|(_, l)| !l.trim().is_empty() && !l.trim_start().starts_with('#'));
    let Some((_, header)) = lines.next() else {
        return Err(format!("{}: empty file (expected a header with columns strain and stress)", file.display()));
    };
    let cols: Vec<&str> = header.split(',').map(str::trim).collect();
    let find = |name: &str| {
        cols.iter().position(|c| *c == name).ok_or_else(|| format!("{}:1: no column '{name}' in the header ({header})", file.display()))
    };
    let (ix, iy) = (find("strain")?, find("stress")?);
    let (mut x, mut y) = (Vec::new(), Vec::new());
    for (n, line) in lines {
        let f: Vec<&str> = line.split(',').map(str::trim).collect();
        let get = |i: usize, name: &str| -> Result<f64, String> {
            f.get(i)
                .ok_or_else(|| format!("{}:{}: missing column '{name}'", file.display(), n + 1))?
                .parse::<f64>()
                .map_err(|e| format!("{}:{}: column '{name}': {e}", file.display(), n + 1))
        };
        x.push(get(ix, "strain")?);
        y.push(get(iy, "stress")?);
    }
    let s = y.iter().fold(0.0f64, |m, &v| if v.abs() > m.abs() { v } else { m });
    let sign = if s < 0.0 { -1.0 } else { 1.0 };
    let c = Curve { x: x.iter().map(|v| sign * v).collect(), y: y.iter().map(|v| sign * v).collect(), loss_of_load: false };
    Ok(c.monotonic())
}
