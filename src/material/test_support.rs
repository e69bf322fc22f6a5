//! Shared helpers of the material tests: a seeded random generator and reference parameters.

use super::{DamageParams, PointLaw, Regularization};

/// SplitMix64 (Steele, Lea, Flood 2014): tiny, seeded, reproducible.
pub struct Rng(u64);

impl Rng {
    pub fn new(seed: u64) -> Self {
        Rng(seed)
    }
    pub fn next_u64(&mut self) -> u64 {
        self.0 = self.0.wrapping_add(0x9E37_79B9_7F4A_7C15);
        let mut z = self.0;
        z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
        z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
        z ^ (z >> 31)
    }
    /// Uniform in [0, 1).
    pub fn unit(&mut self) -> f64 {
        (self.next_u64() >> 11) as f64 / (1u64 << 53) as f64
    }
    /// Uniform in [a, b).
    pub fn range(&mut self, a: f64, b: f64) -> f64 {
        a + (b - a) * self.unit()
    }
}

/// Masonry-like parameters (order of SPEC §1 Table 1): E = 3 GPa, ν = 0.2, f_t = 0.3 MPa.
pub fn params() -> DamageParams {
    DamageParams {
        e: 3.0e9,
        nu: 0.2,
        eps0_t: 1.0e-4,
        eps0_c: 2.0e-4,
        gf_t: 50.0,
        a_c: 0.8,
        b_c: 800.0,
        regularization: Regularization::Hillerborg,
    }
}

/// The law of [`params`] for a 0.1 m element: B_t = 0.3e6 · 0.1 / 50 = 600.
pub fn law() -> PointLaw {
    match params().for_element(0.1) {
        Ok(l) => l,
        Err(e) => panic!("reference parameters rejected: {e}"),
    }
}

/// max |a − b| / max |b| over the entries (norm-wise relative difference).
pub fn rel_diff(a: &[f64], b: &[f64]) -> f64 {
    let num = a.iter().zip(b).map(|(x, y)| (x - y).abs()).fold(0.0, f64::max);
    let den = b.iter().map(|y| y.abs()).fold(0.0, f64::max);
    num / den
}
