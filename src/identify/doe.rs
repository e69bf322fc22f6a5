//! Designs of experiments on the unit cube `[0, 1]^n` (see [`super::space`] for the map to the
//! physical unknowns).
//!
//! * [`latin_hypercube`]: `m` points, each coordinate's `m` strata `[k/m, (k+1)/m)` hit exactly
//!   once, optimized for the maximin distance (egobox-doe's `Optimized` LHS, enhanced stochastic
//!   evolution); seeded, so a seed gives the same design bit for bit.
//! * [`two_level_factorial`]: the `2^n` corners of the box `[a, b]^n` (`0 ≤ a < b ≤ 1`): the
//!   paper's "32 combinations" for the five damage-law unknowns. With `a = 1/4, b = 3/4` the
//!   points sit inside the box, where a kriging surrogate interpolates rather than extrapolates.
use super::error::IdentifyError;
use egobox_doe::{Lhs, LhsKind, SamplingMethod};
use rand_xoshiro::rand_core::SeedableRng;
use rand_xoshiro::Xoshiro256Plus;

/// `m` points of an optimized Latin hypercube in `[0, 1]^dim`, from `seed`.
pub fn latin_hypercube(m: usize, dim: usize, seed: u64) -> Result<Vec<Vec<f64>>, IdentifyError> {
    if m == 0 || dim == 0 {
        return Err(IdentifyError::Settings(format!(
            "a Latin hypercube needs m ≥ 1 points in ≥ 1 dimension, got m = {m}, dim = {dim}"
        )));
    }
    let mut limits = ndarray16::Array2::<f64>::zeros((dim, 2));
    for i in 0..dim {
        limits[[i, 1]] = 1.0;
    }
    let lhs = Lhs::new(&limits).kind(LhsKind::Optimized).with_rng(Xoshiro256Plus::seed_from_u64(seed));
    let x = lhs.sample(m);
    Ok(x.outer_iter().map(|r| r.to_vec()).collect())
}

/// The `2^dim` points of the two-level full factorial with levels `a < b` in `[0, 1]`, in
/// binary order (point `k` takes level `b` in coordinate `i` iff bit `i` of `k` is set).
pub fn two_level_factorial(dim: usize, levels: [f64; 2]) -> Result<Vec<Vec<f64>>, IdentifyError> {
    let [a, b] = levels;
    if !(0.0..=1.0).contains(&a) || !(0.0..=1.0).contains(&b) || a >= b {
        return Err(IdentifyError::Settings(format!("factorial levels must satisfy 0 ≤ a < b ≤ 1, got [{a}, {b}]")));
    }
    if dim == 0 || dim > 16 {
        return Err(IdentifyError::Settings(format!("a two-level factorial needs 1 to 16 factors, got {dim}")));
    }
    Ok((0..1usize << dim).map(|k| (0..dim).map(|i| if k >> i & 1 == 1 { b } else { a }).collect()).collect())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn latin_hypercube_fills_every_stratum_once_and_is_reproducible() {
        let (m, d) = (8, 4);
        let x = latin_hypercube(m, d, 3).unwrap();
        assert_eq!(x.len(), m);
        for i in 0..d {
            let mut strata: Vec<usize> = x.iter().map(|p| (p[i] * m as f64).floor() as usize).collect();
            strata.sort();
            assert_eq!(strata, (0..m).collect::<Vec<_>>(), "coordinate {i}");
        }
        assert_eq!(x, latin_hypercube(m, d, 3).unwrap());
        assert_ne!(x, latin_hypercube(m, d, 4).unwrap());
    }

    #[test]
    fn factorial_has_all_corners() {
        let x = two_level_factorial(5, [0.25, 0.75]).unwrap();
        assert_eq!(x.len(), 32);
        let mut keys: Vec<u32> =
            x.iter().map(|p| p.iter().enumerate().map(|(i, &v)| ((v > 0.5) as u32) << i).sum()).collect();
        keys.sort();
        assert_eq!(keys, (0..32).collect::<Vec<_>>());
        assert!(two_level_factorial(2, [0.7, 0.3]).is_err());
    }
}
