//! The size of the next load increment of a load-controlled static analysis (the gravity phase of
//! a time history, the stages of `static_nonlinear`), and when to give up.
//!
//! ```text
//!   start      Δ = Δ₀ = 1 / steps
//!   converged  Δ ← min(1.5 Δ, Δ₀)
//!   failed     Δ ← Δ / 2, unless one of the stops below
//! ```
//!
//! Under load control a structure that cannot carry the whole load has a limit point λ*: every
//! increment that ends beyond it fails. Halving alone then never ends, because each increment
//! short enough to stay below λ* converges and the next one, grown again, fails; the increments
//! shrink towards 0 and λ creeps towards λ* for ever (measured on the church with a weak law:
//! Δλ = 4.4e-17 after 12 minutes). Three stops make every such run end:
//! * **the floor**: a failed increment is not halved below Δ_min = Δ₀ / 2^max_cuts;
//! * **halvings in a row**: `max_cuts` failures without a success in between;
//! * **the budget**: at most `10 (steps + max_cuts)` attempts in all, successes included, so a
//!   run that alternates successes and failures near λ* ends as well (a run that needs no
//!   halving takes `steps` attempts, one that halves at every step about `2 steps`).
/// Why the increments stop.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum IncrementStop {
    /// The failed increment was already at the floor Δ₀ / 2^max_cuts.
    Floor,
    /// `max_cuts` halvings in a row.
    HalvingsInRow,
    /// The attempt budget is spent.
    Budget,
}

impl IncrementStop {
    /// A phrase for messages ("the load increment reached its floor 1.2e-5").
    pub fn describe(self, control: &IncrementControl) -> String {
        match self {
            IncrementStop::Floor => {
                format!("the increment reached its floor {:.3e} (1/steps / 2^{})", control.floor(), control.max_cuts)
            }
            IncrementStop::HalvingsInRow => format!("{} halvings in a row", control.max_cuts),
            IncrementStop::Budget => format!("the budget of {} attempts is spent", control.max_attempts),
        }
    }
}

/// The increment controller: one per load stage.
#[derive(Clone, Debug)]
pub struct IncrementControl {
    nominal: f64,
    size: f64,
    max_cuts: usize,
    cuts_in_row: usize,
    attempts: usize,
    max_attempts: usize,
}

impl IncrementControl {
    /// A stage of `steps` nominal increments (≥ 1) with at most `max_cuts` halvings in a row.
    pub fn new(steps: usize, max_cuts: usize) -> IncrementControl {
        let steps = steps.max(1);
        let nominal = 1.0 / steps as f64;
        IncrementControl {
            nominal,
            size: nominal,
            max_cuts,
            cuts_in_row: 0,
            attempts: 0,
            max_attempts: 10 * (steps + max_cuts),
        }
    }

    /// The size of the next increment (a fraction of the stage).
    pub fn size(&self) -> f64 {
        self.size
    }

    /// The smallest increment tried: Δ₀ / 2^max_cuts.
    pub fn floor(&self) -> f64 {
        self.nominal / f64::powi(2.0, self.max_cuts as i32)
    }

    /// Attempts so far (converged and failed).
    pub fn attempts(&self) -> usize {
        self.attempts
    }

    /// The increment converged: the next one grows by 1.5 up to the nominal size. A success
    /// that spends the budget is kept; the next call to [`IncrementControl::failed`] or
    /// [`IncrementControl::exhausted`] says so.
    pub fn converged(&mut self) {
        self.attempts += 1;
        self.cuts_in_row = 0;
        self.size = (1.5 * self.size).min(self.nominal);
    }

    /// True when no attempt is left although the stage is not done.
    pub fn exhausted(&self) -> bool {
        self.attempts >= self.max_attempts
    }

    /// The increment failed: halves it, or says why the stage stops.
    pub fn failed(&mut self) -> Result<(), IncrementStop> {
        self.attempts += 1;
        if 0.5 * self.size < self.floor() * (1.0 - 1e-9) {
            return Err(IncrementStop::Floor);
        }
        if self.cuts_in_row >= self.max_cuts {
            return Err(IncrementStop::HalvingsInRow);
        }
        if self.exhausted() {
            return Err(IncrementStop::Budget);
        }
        self.cuts_in_row += 1;
        self.size *= 0.5;
        Ok(())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Drives the controller on a load stage whose increments converge only below a limit point
    /// λ* (any increment ending beyond it fails), as a structure under load control does.
    fn drive(steps: usize, max_cuts: usize, limit: f64) -> (f64, IncrementStop, usize) {
        let mut c = IncrementControl::new(steps, max_cuts);
        let mut lambda = 0.0;
        loop {
            let target = (lambda + c.size()).min(1.0);
            if target <= limit {
                c.converged();
                lambda = target;
                assert!(lambda < 1.0, "a stage with λ* < 1 cannot finish");
            } else if let Err(stop) = c.failed() {
                return (lambda, stop, c.attempts());
            }
        }
    }

    #[test]
    fn a_limit_point_ends_the_stage_within_the_floor_and_the_budget() {
        // λ* = 0.8773 (the church's gravity with the identified law): the stage ends below it,
        // closer to it than the last increment tried, which is under twice the floor
        // Δ₀/2^12 = 2.44e-5 (it could not be halved), and within the budget 10 (10 + 12) = 220.
        let (lambda, stop, attempts) = drive(10, 12, 0.8773);
        assert!(lambda <= 0.8773 && 0.8773 - lambda < 2.0 * 0.1 / 4096.0, "λ = {lambda}");
        assert!(attempts <= 220, "{attempts} attempts");
        assert_eq!(stop, IncrementStop::Floor);
    }

    #[test]
    fn a_stage_without_failures_takes_its_nominal_steps() {
        let mut c = IncrementControl::new(10, 12);
        let mut lambda: f64 = 0.0;
        while lambda < 1.0 - 1e-12 {
            lambda = (lambda + c.size()).min(1.0);
            c.converged();
        }
        assert_eq!(c.attempts(), 10);
    }

    #[test]
    fn halvings_in_row_and_budget_stop_too() {
        let mut c = IncrementControl::new(4, 3);
        assert!(c.failed().is_ok() && c.failed().is_ok() && c.failed().is_ok());
        // Three halvings reach the floor 0.25/8: the fourth failure stops there.
        assert_eq!(c.failed(), Err(IncrementStop::Floor));
        // Two successes and a failure, again and again, never approach the floor (each success
        // grows the size back by 1.5): the budget 10 (4 + 30) = 340 attempts ends it.
        let mut c = IncrementControl::new(4, 30);
        let mut stop = None;
        for _ in 0..1000 {
            c.converged();
            c.converged();
            if let Err(s) = c.failed() {
                stop = Some(s);
                break;
            }
        }
        assert_eq!(stop, Some(IncrementStop::Budget));
        assert!(c.attempts() <= 342, "{}", c.attempts());
    }
}
