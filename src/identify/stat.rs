//! Mean and sample standard deviation of a set of values (the scatter of virtual samples).
use serde::{Deserialize, Serialize};

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

    /// Of `v`; `None` when `v` is empty (serialized as `null`).
    pub fn of_nonempty(v: &[f64]) -> Option<Stat> {
        (!v.is_empty()).then(|| Stat::of(v))
    }
}
