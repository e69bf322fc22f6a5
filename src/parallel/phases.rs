//! Where a driver's time goes: named phases timed in one place, instead of `Instant` pairs
//! written out at every phase (deal.II's `TimerOutput` scopes, in their simplest form).
//!
//! ```text
//! let mut phases = Phases::default();
//! let k = phases.time("assemble", || assemble(&mut disc))?;
//! let pairs = phases.time("solve", || solve(&k))?;
//! let [t_assemble, t_solve] = phases.seconds_of(["assemble", "solve"]);
//! ```
//! A phase timed several times adds up. The times are this rank's wall times. Where the timed
//! code borrows the value that holds the `Phases` (a solver timing its own calls), [`timed`]
//! returns the time for [`Phases::add`].
use std::time::Instant;

/// Runs `f`; its value and its wall time [s].
pub fn timed<T>(f: impl FnOnce() -> T) -> (T, f64) {
    let start = Instant::now();
    let out = f();
    (out, start.elapsed().as_secs_f64())
}

/// Wall times of named phases [s], in the order first timed.
#[derive(Clone, Debug, Default)]
pub struct Phases {
    done: Vec<(&'static str, f64)>,
}

impl Phases {
    /// Runs `f` as the phase `name` and adds its wall time to the phase's.
    pub fn time<T>(&mut self, name: &'static str, f: impl FnOnce() -> T) -> T {
        let (out, seconds) = timed(f);
        self.add(name, seconds);
        out
    }

    /// Adds `seconds` to the phase `name`.
    pub fn add(&mut self, name: &'static str, seconds: f64) {
        match self.done.iter_mut().find(|(n, _)| *n == name) {
            Some((_, s)) => *s += seconds,
            None => self.done.push((name, seconds)),
        }
    }

    /// The time of the phase `name` (0 when it never ran).
    pub fn seconds(&self, name: &str) -> f64 {
        self.done.iter().find(|(n, _)| *n == name).map_or(0.0, |(_, s)| *s)
    }

    /// The times of the named phases, in the order asked.
    pub fn seconds_of<const N: usize>(&self, names: [&str; N]) -> [f64; N] {
        names.map(|n| self.seconds(n))
    }

    /// Every phase with its time, in the order first timed.
    pub fn all(&self) -> &[(&'static str, f64)] {
        &self.done
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Phases add up per name, keep their first order, and an unknown phase took no time.
    #[test]
    fn phases_add_up_by_name() {
        let mut p = Phases::default();
        let x = p.time("solve", || 2 + 2);
        assert_eq!(x, 4);
        p.add("assemble", 1.5);
        p.add("solve", 2.0);
        p.add("assemble", 0.25);
        assert_eq!(p.seconds("assemble"), 1.75);
        assert!(p.seconds("solve") >= 2.0 && p.seconds("solve") < 2.5);
        assert_eq!(p.seconds("output"), 0.0);
        assert_eq!(p.all().iter().map(|(n, _)| *n).collect::<Vec<_>>(), ["solve", "assemble"]);
        let [a, o] = p.seconds_of(["assemble", "output"]);
        assert_eq!((a, o), (1.75, 0.0));
    }
}
