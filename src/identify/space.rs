//! The search space: named unknowns, each in an interval `[lower, upper]`, mapped affinely to
//! the unit cube on which the surrogate works:
//!
//! ```text
//!   u_i = (x_i − lower_i) / (upper_i − lower_i) ∈ [0, 1],    x_i = lower_i + u_i (upper_i − lower_i)
//! ```
//! Working in the unit cube keeps the kriging correlation lengths comparable across unknowns
//! whose physical scales differ by orders of magnitude (Ē ≈ 1e9 Pa, ε_cr ≈ 1e-4).
use super::error::IdentifyError;
use serde::Serialize;

/// One unknown and its interval.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct Unknown {
    /// Name (as in the job file).
    pub name: String,
    /// Lower bound.
    pub lower: f64,
    /// Upper bound.
    pub upper: f64,
}

/// The unknowns of an identification, in order.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct Space {
    /// The unknowns.
    pub unknowns: Vec<Unknown>,
}

impl Space {
    /// A space from `(name, [lower, upper])`; every interval must be finite with lower < upper.
    pub fn new(unknowns: &[(&str, [f64; 2])]) -> Result<Space, IdentifyError> {
        let mut v = Vec::with_capacity(unknowns.len());
        for &(name, [lower, upper]) in unknowns {
            if !(lower.is_finite() && upper.is_finite() && lower < upper) {
                return Err(IdentifyError::InvalidBounds { name: name.to_string(), lower, upper });
            }
            v.push(Unknown { name: name.to_string(), lower, upper });
        }
        if v.is_empty() {
            return Err(IdentifyError::Settings("the search space has no unknown".into()));
        }
        Ok(Space { unknowns: v })
    }

    /// Number of unknowns.
    pub fn dim(&self) -> usize {
        self.unknowns.len()
    }

    /// Physical point of a unit-cube point (clamped to the cube).
    pub fn from_unit(&self, u: &[f64]) -> Vec<f64> {
        self.unknowns.iter().zip(u).map(|(k, &t)| k.lower + t.clamp(0.0, 1.0) * (k.upper - k.lower)).collect()
    }

    /// Unit-cube point of a physical point.
    pub fn to_unit(&self, x: &[f64]) -> Vec<f64> {
        self.unknowns.iter().zip(x).map(|(k, &v)| (v - k.lower) / (k.upper - k.lower)).collect()
    }

    /// The names, in order.
    pub fn names(&self) -> Vec<String> {
        self.unknowns.iter().map(|k| k.name.clone()).collect()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn unit_map_round_trips_and_bounds_are_checked() {
        let s = Space::new(&[("a", [1.0, 3.0]), ("b", [-1e-4, 1e-4])]).unwrap();
        let x = s.from_unit(&[0.25, 1.0]);
        assert_eq!(x, vec![1.5, 1e-4]);
        let u = s.to_unit(&x);
        assert!((u[0] - 0.25).abs() < 1e-15 && (u[1] - 1.0).abs() < 1e-12);
        for b in [[2.0, 1.0], [1.0, 1.0], [f64::NAN, 1.0]] {
            let e = Space::new(&[("g", b)]).unwrap_err();
            assert!(e.to_string().contains("`g`") && e.to_string().contains("lower < upper"), "{e}");
        }
    }
}
