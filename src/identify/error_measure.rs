//! The distance between a reference curve (DEM) and a model curve (the damage law) sampled at
//! the same abscissae (paper eq. 15, SPEC §3b):
//!
//! ```text
//!   F(x) = Σ_i sqrt( |f_i^DEM − f_i^con(x)| / |f_i^DEM| )       over i with |f_i^DEM| > η max_j |f_j^DEM|
//! ```
//! Points where the reference nearly vanishes (the origin, the broken tail of a tension test)
//! are skipped: their relative error is undefined. η = [`SKIP_FRACTION`].
//!
//! The option `relative_rms` is `sqrt( Σ_i (f_i^DEM − f_i^con)² / Σ_i (f_i^DEM)² )` over the same
//! points. Both are reported with the number of points used; `F/n` (the mean of
//! sqrt(relative error)) reads as a typical relative deviation's square root.
use serde::{Deserialize, Serialize};

/// Reference values below this fraction of the largest one are skipped.
pub const SKIP_FRACTION: f64 = 1e-3;

/// Which measure.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum ErrorMeasure {
    /// Paper eq. 15: Σ sqrt(|Δf| / |f|).
    #[default]
    Eq15,
    /// sqrt(Σ Δf² / Σ f²).
    RelativeRms,
}

/// A measured distance.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
pub struct CurveError {
    /// The value of the chosen measure.
    pub value: f64,
    /// Points used (not skipped).
    pub points: usize,
}

/// The distance between `reference` and `model` (same length) by `measure`; `None` when no
/// reference point is usable or a model value is not finite.
pub fn curve_error(reference: &[f64], model: &[f64], measure: ErrorMeasure) -> Option<CurveError> {
    let fmax = reference.iter().fold(0.0f64, |m, v| m.max(v.abs()));
    if fmax == 0.0 || !fmax.is_finite() || reference.len() != model.len() {
        return None;
    }
    let used: Vec<(f64, f64)> =
        reference.iter().zip(model).filter(|(f, _)| f.abs() > SKIP_FRACTION * fmax).map(|(&f, &g)| (f, g)).collect();
    if used.is_empty() || used.iter().any(|(_, g)| !g.is_finite()) {
        return None;
    }
    let value = match measure {
        ErrorMeasure::Eq15 => used.iter().map(|(f, g)| ((f - g).abs() / f.abs()).sqrt()).sum(),
        ErrorMeasure::RelativeRms => {
            let num: f64 = used.iter().map(|(f, g)| (f - g).powi(2)).sum();
            let den: f64 = used.iter().map(|(f, _)| f * f).sum();
            (num / den).sqrt()
        }
    };
    Some(CurveError { value, points: used.len() })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn eq15_by_hand() {
        // Reference (0, 1, 2, 4), model (0, 1.01, 2, 3): the origin is skipped;
        // sqrt(0.01/1) + 0 + sqrt(1/4) = 0.1 + 0.5 = 0.6 over 3 points.
        let e = curve_error(&[0.0, 1.0, 2.0, 4.0], &[0.0, 1.01, 2.0, 3.0], ErrorMeasure::Eq15).unwrap();
        assert!((e.value - 0.6).abs() < 1e-12 && e.points == 3, "{e:?}");
        // Relative RMS: sqrt((1e-4 + 0 + 1) / (1 + 4 + 16)).
        let r = curve_error(&[0.0, 1.0, 2.0, 4.0], &[0.0, 1.01, 2.0, 3.0], ErrorMeasure::RelativeRms).unwrap();
        assert!((r.value - (1.0001f64 / 21.0).sqrt()).abs() < 1e-12);
        assert!(curve_error(&[0.0, 0.0], &[1.0, 1.0], ErrorMeasure::Eq15).is_none());
        assert!(curve_error(&[1.0], &[f64::NAN], ErrorMeasure::Eq15).is_none());
    }
}
