//! The substeps of one nominal step: sizes `H / 2^k` on the dyadic grid of the step.
//!
//! A nominal step of size `H` (the job's `dt`, or the shorter last step of a duration that is not
//! a multiple of it) is walked in substeps of `H / 2^level`, `level ≤ max` (`max` halvings
//! allowed). Positions are counted in integers, in units of the finest substep `H / 2^max`:
//!
//! ```text
//!   size of the substep     2^(max − level) units
//!   halve                   level + 1                         (while level < max)
//!   double                  level − 1, only where done ≡ 0 (mod 2 · size)
//! ```
//!
//! A substep doubles only at a multiple of its doubled size, so every substep starts on the
//! grid of its own size, none overshoots the step's end (the end, `2^max` units, is a multiple
//! of every size), and the last substep ends exactly on it. The sizes themselves are `H / 2^k`
//! exactly (a division by a power of two), not differences of times, so a size that comes back
//! meets the factorization made for it ([`super::stepper`]).

/// Where a nominal step stands (module docs).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(super) struct Substeps {
    /// Halvings allowed: the finest substep is `H / 2^max`.
    max: u32,
    /// The current substep is `H / 2^level`.
    level: u32,
    /// Time done, in units of the finest substep.
    done: u64,
}

impl Substeps {
    /// The start of a step with `max` halvings allowed, its first substep `H / 2^level` (at most
    /// the finest).
    pub fn new(max: u32, level: u32) -> Substeps {
        Substeps { max, level: level.min(max), done: 0 }
    }

    /// The halvings of a step of size `big` whose substeps may not be smaller than `h_min` (a
    /// relative tolerance of 1e-9 on the comparison, as the sizes are exact powers of two of
    /// `dt`), at most 63.
    pub fn halvings_allowed(big: f64, h_min: f64) -> u32 {
        let mut k = 0;
        while k < 63 && big / f64::powi(2.0, k as i32 + 1) >= h_min * (1.0 - 1e-9) {
            k += 1;
        }
        k
    }

    /// The current substep's level: its size is `H / 2^level`.
    pub fn level(&self) -> u32 {
        self.level
    }

    /// The current substep's size for a step of size `big`: `big / 2^level`, exact.
    pub fn size(&self, big: f64) -> f64 {
        big / f64::powi(2.0, self.level as i32)
    }

    fn units(&self) -> u64 {
        1u64 << (self.max - self.level)
    }

    /// Whether the current substep ends the step.
    pub fn is_last(&self) -> bool {
        self.done + self.units() == 1u64 << self.max
    }

    /// Whether the current substep may still be halved.
    pub fn can_halve(&self) -> bool {
        self.level < self.max
    }

    /// The current substep, taken again as two halves.
    pub fn halve(&mut self) {
        debug_assert!(self.can_halve());
        self.level += 1;
    }

    /// The current substep was accepted; the next one starts where it ended.
    pub fn accept(&mut self) {
        self.done += self.units();
        debug_assert!(self.done <= 1u64 << self.max);
    }

    /// Doubles the next substep where the grid allows it (module docs); whether it did.
    pub fn try_double(&mut self) -> bool {
        let ok = self.level > 0 && self.done % (2 * self.units()) == 0;
        if ok {
            self.level -= 1;
        }
        ok
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Random halvings, acceptances and doublings (seeded): every size is `H / 2^k` with
    /// `k ≤ max`, every substep starts on the grid of its own size, the sizes of the accepted
    /// substeps add up to `H` exactly (in units), and the last one is the one `is_last` names.
    #[test]
    fn the_substeps_stay_on_the_dyadic_grid_and_end_on_the_step() {
        let mut seed = 0x2545_f491_4f6c_dd1du64;
        let mut next = move || {
            seed ^= seed << 13;
            seed ^= seed >> 7;
            seed ^= seed << 17;
            seed
        };
        for round in 0..200 {
            let max = (round % 7) as u32;
            let mut s = Substeps::new(max, (next() % 9) as u32);
            assert!(s.level() <= max);
            let (mut sum, mut accepted) = (0u64, 0);
            loop {
                assert_eq!(s.done % s.units(), 0, "a substep off its grid");
                assert_eq!(s.size(0.02), 0.02 / f64::powi(2.0, s.level() as i32));
                if s.can_halve() && next() % 3 == 0 {
                    s.halve();
                    continue;
                }
                let last = s.is_last();
                sum += s.units();
                accepted += 1;
                s.accept();
                if next() % 2 == 0 {
                    s.try_double();
                }
                if last {
                    break;
                }
                assert!(sum < 1 << max);
            }
            assert_eq!(sum, 1 << max, "round {round}: {accepted} substeps");
        }
    }

    /// After a halving, a substep of `H/4` at 1/4 of the step cannot double (it would end at
    /// 3/4 on a grid of `H/2`); at 1/2 it can. At the end of a step the level may always go up.
    #[test]
    fn a_substep_doubles_only_at_a_multiple_of_its_doubled_size() {
        let mut s = Substeps::new(4, 2);
        s.accept();
        assert!(!s.try_double());
        s.accept();
        assert!(s.try_double());
        assert_eq!(s.level(), 1);
        assert!(s.is_last());
        s.accept();
        assert!(s.try_double());
        assert_eq!(s.level(), 0);
        assert_eq!(Substeps::halvings_allowed(0.02, 0.02 / 16.0), 4);
        assert_eq!(Substeps::halvings_allowed(0.02, 0.02), 0);
        // A short last step (a quarter of dt) has two fewer halvings above dt / 16.
        assert_eq!(Substeps::halvings_allowed(0.005, 0.02 / 16.0), 2);
    }
}
