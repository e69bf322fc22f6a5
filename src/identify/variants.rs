//! Material variants: which DEM samples each variant of the identified law is fitted to, so
//! that a structural analysis can carry the virtual lab's sample-to-sample scatter into its
//! damage. A variant is fitted like the main law (same design, optimizer settings and E, ν) on
//! the mean curves of its own samples (`run::identify`); this file only chooses the samples.
//!
//! Samples are numbered 1..n in the order of the curves (the virtual tests' seeds, or the rows
//! of the `dem_samples` files). With `count` = m variants:
//!
//! ```text
//!   halves      disjoint groups, the samples dealt round-robin: group g (1..m) holds
//!               g, g + m, g + 2m, ...   (n = 4, m = 2: {1, 3} and {2, 4})
//!   bootstrap   each variant draws n samples with replacement (Efron's bootstrap):
//!               sample = 1 + ⌊u · n / 2⁶⁴⌋ for the next 64-bit output u of SplitMix64(seed)
//! ```
//! When both tests have the same number of samples (the DEM tests each seed in tension and in
//! compression) one list serves both, so a variant keeps a sample's tension and compression
//! together; otherwise (a failed sample, files of different lengths) each test gets its own list,
//! and a bootstrap variant draws the tension list, then the compression list. Variant k's draws
//! follow variant k − 1's in the one stream.
//!
//! SplitMix64 (Steele, Lea and Flood, OOPSLA 2014; the seeding generator of Vigna's xoshiro):
//! a 64-bit counter advanced by the golden-ratio increment 0x9E3779B97F4A7C15, each value mixed
//! by two xor-shift-multiply rounds. It is written out here so the variants depend on no
//! crate's version. The multiply-shift ⌊u · n / 2⁶⁴⌋ (Lemire 2019) is biased by less than
//! n / 2⁶⁴.
use super::error::IdentifyError;
use serde::{Deserialize, Serialize};

/// How the variants' samples are chosen (module docs).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize, schemars::JsonSchema)]
#[serde(rename_all = "snake_case")]
pub enum VariantScheme {
    /// Disjoint groups, samples dealt round-robin.
    Halves,
    /// n samples drawn with replacement.
    Bootstrap,
}

impl VariantScheme {
    /// The job-file name.
    pub fn name(self) -> &'static str {
        match self {
            VariantScheme::Halves => "halves",
            VariantScheme::Bootstrap => "bootstrap",
        }
    }
}

/// One variant's samples, numbered from 1 in the order of each test's curves (a number may
/// repeat under `bootstrap`).
#[derive(Clone, Debug, PartialEq, Eq, Serialize, Deserialize)]
pub struct VariantSamples {
    /// Tension samples.
    pub tension: Vec<usize>,
    /// Compression samples.
    pub compression: Vec<usize>,
}

impl VariantSamples {
    /// The items of `all` (one per sample) with the numbers `numbers`, in that order.
    pub fn pick<T: Clone>(all: &[T], numbers: &[usize]) -> Vec<T> {
        numbers.iter().map(|&k| all[k - 1].clone()).collect()
    }
}

/// SplitMix64 (module docs).
#[derive(Clone, Debug)]
pub struct SplitMix64 {
    state: u64,
}

impl SplitMix64 {
    /// The generator seeded with `seed`.
    pub fn new(seed: u64) -> SplitMix64 {
        SplitMix64 { state: seed }
    }

    /// The next 64-bit output.
    pub fn next_u64(&mut self) -> u64 {
        self.state = self.state.wrapping_add(0x9E37_79B9_7F4A_7C15);
        let mut z = self.state;
        z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
        z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
        z ^ (z >> 31)
    }

    /// A number in 1..=n (n ≥ 1) by the multiply-shift ⌊u · n / 2⁶⁴⌋ + 1.
    pub fn sample_number(&mut self, n: usize) -> usize {
        debug_assert!(n >= 1);
        ((u128::from(self.next_u64()) * n as u128) >> 64) as usize + 1
    }
}

/// Group `g` (1..=count) of `halves` over n samples: g, g + count, ... up to n.
pub fn halves_group(n: usize, count: usize, g: usize) -> Vec<usize> {
    (g..=n).step_by(count).collect()
}

/// The samples of `count` variants over `n_tension` and `n_compression` samples (module docs).
/// `halves` needs at least `count` samples in each test; both schemes at least one.
pub fn variant_samples(
    scheme: VariantScheme,
    count: usize,
    seed: u64,
    n_tension: usize,
    n_compression: usize,
) -> Result<Vec<VariantSamples>, IdentifyError> {
    if count < 2 {
        return Err(IdentifyError::Settings(format!("material variants: expected a count of at least 2, got {count}")));
    }
    for (test, n) in [("tension", n_tension), ("compression", n_compression)] {
        let need = if scheme == VariantScheme::Halves { count } else { 1 };
        if n < need {
            return Err(IdentifyError::TooFewSamples { scheme: scheme.name(), test, samples: n, needed: need });
        }
    }
    let mut rng = SplitMix64::new(seed);
    let mut draw = |n: usize| (0..n).map(|_| rng.sample_number(n)).collect::<Vec<_>>();
    let shared = n_tension == n_compression;
    Ok((1..=count)
        .map(|g| match scheme {
            VariantScheme::Halves => VariantSamples {
                tension: halves_group(n_tension, count, g),
                compression: halves_group(n_compression, count, g),
            },
            VariantScheme::Bootstrap if shared => {
                let both = draw(n_tension);
                VariantSamples { tension: both.clone(), compression: both }
            }
            VariantScheme::Bootstrap => {
                let tension = draw(n_tension);
                VariantSamples { tension, compression: draw(n_compression) }
            }
        })
        .collect())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn splitmix64_gives_the_reference_outputs() {
        // Seed 1234567: the reference values of Rosetta Code's "Pseudo-random numbers/Splitmix64".
        let mut r = SplitMix64::new(1234567);
        assert_eq!(
            [r.next_u64(), r.next_u64(), r.next_u64()],
            [6457827717110365317, 3203168211198807973, 9817491932198370423]
        );
        // Numbers stay in 1..=n.
        let mut r = SplitMix64::new(1);
        assert!((0..1000).map(|_| r.sample_number(4)).all(|k| (1..=4).contains(&k)));
    }

    #[test]
    fn halves_deal_the_samples_round_robin() {
        let v = variant_samples(VariantScheme::Halves, 2, 1, 4, 4).unwrap();
        assert_eq!(v[0], VariantSamples { tension: vec![1, 3], compression: vec![1, 3] });
        assert_eq!(v[1], VariantSamples { tension: vec![2, 4], compression: vec![2, 4] });
        // Unequal counts: each test dealt on its own; 5 samples in 3 groups: {1, 4}, {2, 5}, {3}.
        let v = variant_samples(VariantScheme::Halves, 3, 1, 5, 3).unwrap();
        let t: Vec<_> = v.iter().map(|s| s.tension.clone()).collect();
        assert_eq!(t, [vec![1, 4], vec![2, 5], vec![3]]);
        assert_eq!(v[2].compression, [3]);
        // A group without a sample is an error naming the test.
        let e = variant_samples(VariantScheme::Halves, 3, 1, 4, 2).unwrap_err();
        assert!(e.to_string().contains("compression") && e.to_string().contains("2 sample"), "{e}");
        assert!(variant_samples(VariantScheme::Halves, 1, 1, 4, 4).is_err());
    }

    #[test]
    fn bootstrap_is_seeded_and_shares_the_list_between_tests() {
        let a = variant_samples(VariantScheme::Bootstrap, 3, 7, 4, 4).unwrap();
        assert_eq!(a, variant_samples(VariantScheme::Bootstrap, 3, 7, 4, 4).unwrap());
        assert_ne!(a, variant_samples(VariantScheme::Bootstrap, 3, 8, 4, 4).unwrap());
        for v in &a {
            assert_eq!(v.tension.len(), 4);
            assert_eq!(v.tension, v.compression);
        }
        // The first variant's draws are the stream's first four numbers.
        let mut r = SplitMix64::new(7);
        let first: Vec<usize> = (0..4).map(|_| r.sample_number(4)).collect();
        assert_eq!(a[0].tension, first);
        // Unequal counts: own lists, tension drawn first.
        let b = variant_samples(VariantScheme::Bootstrap, 2, 7, 4, 3).unwrap();
        assert_eq!(b[0].tension, first);
        assert_eq!(b[0].compression.len(), 3);
        assert!(b[0].compression.iter().all(|&k| (1..=3).contains(&k)));
    }
}
