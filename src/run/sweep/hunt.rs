//! Hunt and fill for one record and one material (Vamvatsikos and Cornell 2004, "Applied
//! incremental dynamic analysis", Earthquake Spectra 20(2)): which intensity runs next, decided
//! from the members run so far and nothing else, so that a restarted sweep replays the same
//! decisions from the outcomes on disk.
//!
//! ```text
//!  hunt   first, first + step, + step + step_increase, ...  (capped)   until the highest level
//!         passes every limit, or stopped converging, or is flat, or is the cap
//!  fill   per limit in order: lower = the level below its first passage, upper = that passage;
//!         while upper - lower > precision x upper: run the midpoint (on the 1e-4 lattice)
//! ```
//!
//! A member passes a limit where its share of the limit's substructure with d_t > 0.5 reaches the
//! limit's share, or where it stopped converging or is flat (the flat end of the IDA curve, where
//! the structure has no capacity left: every limit counts as passed there). Flat: its secant
//! slope, intensity over peak drift ratio, is below `flat_slope` times the first level's
//! (Vamvatsikos and Cornell 2002 take 20 % of the elastic slope, on the tangent; the secant lets
//! each member decide alone, so that the fill can bisect it). One member of a chain runs at a
//! time, which makes the levels a chain ends with independent of the order the groups finish in;
//! the chains of the other records and materials run beside it.
use crate::config::{HuntRules, LEVEL_RESOLUTION};
use serde::Serialize;

/// `x` on the levels' lattice: the double nearest to its 4-decimal form, as a member's name
/// reads.
pub fn on_lattice(x: f64) -> f64 {
    lattice_index(x) as f64 / (1.0 / LEVEL_RESOLUTION).round()
}

/// A level's position on the lattice.
pub fn lattice_index(x: f64) -> u64 {
    (x / LEVEL_RESOLUTION).round() as u64
}

/// One member's response as the hunt reads it.
#[derive(Clone, Debug, PartialEq)]
pub enum Response {
    /// The whole record ran: the shares with d_t > 0.5 of the limits' substructures, in the
    /// limits' order, and the peak drift ratio.
    Completed {
        /// Per limit.
        shares: Vec<f64>,
        /// Peak drift ratio.
        drift: f64,
    },
    /// No convergence: the flat end.
    Stopped,
    /// The material's gravity state could not be found: the chain ends.
    GravityFailed,
}

/// What one level says about one limit.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Reading {
    /// The share reached.
    Share(f64),
    /// Stopped converging: passed.
    Stopped,
    /// On the flat end of the curve, below the limit's share: passed.
    Flat,
}

/// Where a limit is first passed along increasing intensities.
#[derive(Clone, Debug, Serialize, PartialEq)]
pub struct Crossing {
    /// The record.
    pub record: String,
    /// The intensity [m/s²], or `None` when not reached.
    pub intensity: Option<f64>,
    /// "reached" (linear in the share between the levels around it), "at_or_below_lowest",
    /// "stopped" or "flat" (passed at that level), "above_highest" (a grid) or "above_cap" (a
    /// hunt that reached its cap): not passed up to `censored_at`.
    pub how: &'static str,
    /// The highest intensity run, when not reached [m/s²].
    pub censored_at: Option<f64>,
}

/// Where the readings `(level, reading)` along increasing levels first pass `share`; `above`
/// names a crossing not reached.
pub fn crossing(record: &str, points: &[(f64, Reading)], share: f64, above: &'static str) -> Crossing {
    let at = |x: f64, how| Crossing { record: record.into(), intensity: Some(x), how, censored_at: None };
    let mut prev: Option<(f64, f64)> = None;
    for &(x, r) in points {
        match r {
            Reading::Stopped | Reading::Flat if prev.is_none() => return at(x, "at_or_below_lowest"),
            Reading::Stopped => return at(x, "stopped"),
            Reading::Share(y) if y >= share => {
                return match prev {
                    None => at(x, "at_or_below_lowest"),
                    Some((x0, y0)) => {
                        let t = if y > y0 { (share - y0) / (y - y0) } else { 1.0 };
                        at(x0 + t * (x - x0), "reached")
                    }
                }
            }
            Reading::Flat => return at(x, "flat"),
            Reading::Share(y) => prev = Some((x, y)),
        }
    }
    let top = points.last().map(|p| p.0);
    Crossing { record: record.into(), intensity: None, how: above, censored_at: top }
}

/// The next member of a chain, and why.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Next {
    /// Level number `step` of the hunt (0 the first).
    Hunt {
        /// The intensity [m/s²].
        level: f64,
        /// Its number.
        step: usize,
    },
    /// A bisection of limit `limit`'s passage between `lower` and `upper`.
    Fill {
        /// The intensity [m/s²].
        level: f64,
        /// The limit's index.
        limit: usize,
        /// The highest level below the passage.
        lower: f64,
        /// The lowest level at or above it.
        upper: f64,
    },
}

impl Next {
    /// The intensity to run.
    pub fn level(&self) -> f64 {
        match *self {
            Next::Hunt { level, .. } | Next::Fill { level, .. } => level,
        }
    }
}

/// Why a chain's hunt ended (at its highest level).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize)]
#[serde(rename_all = "snake_case")]
pub enum HuntEnd {
    /// Every limit's share reached.
    AllPassed,
    /// The member stopped converging.
    Stopped,
    /// The IDA curve is flat there.
    Flat,
    /// The cap, with some limit not passed.
    Cap,
    /// No gravity state for the material.
    GravityFailed,
}

/// The members of one record and material run so far, by increasing level.
#[derive(Clone, Debug)]
pub struct Chain<'a> {
    rules: &'a HuntRules,
    shares: Vec<f64>,
    points: Vec<(f64, Response)>,
}

impl<'a> Chain<'a> {
    /// An empty chain under `rules`, with the limits' `shares`.
    pub fn new(rules: &'a HuntRules, shares: Vec<f64>) -> Chain<'a> {
        Chain { rules, shares, points: Vec::new() }
    }

    /// Adds the member at `level` (a level run again replaces the earlier).
    pub fn add(&mut self, level: f64, response: Response) {
        self.points.retain(|p| lattice_index(p.0) != lattice_index(level));
        self.points.push((level, response));
        self.points.sort_by(|a, b| a.0.total_cmp(&b.0));
    }

    /// The levels run, increasing.
    pub fn levels(&self) -> Vec<f64> {
        self.points.iter().map(|p| p.0).collect()
    }

    /// Whether the member at point `i` is on the flat end (see the module docs).
    pub fn flat(&self, i: usize) -> bool {
        let (Some((x0, Response::Completed { drift: d0, .. })), Some((x, Response::Completed { drift, .. }))) =
            (self.points.first(), self.points.get(i))
        else {
            return false;
        };
        i > 0 && *d0 > 0.0 && *drift > 0.0 && x / drift < self.rules.flat_slope * (x0 / d0)
    }

    /// What point `i` says about limit `k` (`None`: no gravity state).
    pub fn reading(&self, i: usize, k: usize) -> Option<Reading> {
        match &self.points[i].1 {
            Response::Completed { shares, .. } if shares[k] < self.shares[k] && self.flat(i) => Some(Reading::Flat),
            Response::Completed { shares, .. } => Some(Reading::Share(shares[k])),
            Response::Stopped => Some(Reading::Stopped),
            Response::GravityFailed => None,
        }
    }

    /// The readings of limit `k` along the levels.
    pub fn readings(&self, k: usize) -> Vec<(f64, Reading)> {
        (0..self.points.len()).filter_map(|i| self.reading(i, k).map(|r| (self.points[i].0, r))).collect()
    }

    fn passes(&self, i: usize, k: usize) -> bool {
        match self.reading(i, k) {
            Some(Reading::Share(s)) => s >= self.shares[k],
            Some(_) => true,
            None => false,
        }
    }

    /// Why the hunt ended, at which level; `None` while it goes on.
    pub fn hunt_end(&self) -> Option<(HuntEnd, f64)> {
        let i = self.points.len().checked_sub(1)?;
        let x = self.points[i].0;
        if self.points[0].1 == Response::GravityFailed {
            return Some((HuntEnd::GravityFailed, self.points[0].0));
        }
        if self.points[i].1 == Response::Stopped {
            return Some((HuntEnd::Stopped, x));
        }
        if (0..self.shares.len()).all(|k| self.passes(i, k)) {
            let by_share = (0..self.shares.len()).all(|k| matches!(self.reading(i, k), Some(Reading::Share(_))));
            return Some((if by_share { HuntEnd::AllPassed } else { HuntEnd::Flat }, x));
        }
        (x >= self.rules.cap - 0.5 * LEVEL_RESOLUTION).then_some((HuntEnd::Cap, x))
    }

    /// The next member to run, or `None` when the chain is done.
    pub fn next(&self) -> Option<Next> {
        let h = self.rules;
        let Some(top) = self.points.last().map(|p| p.0) else {
            return Some(Next::Hunt { level: on_lattice(h.first), step: 0 });
        };
        if self.hunt_end().is_none() {
            let (mut x, mut s, mut step) = (h.first, h.step, 0);
            while on_lattice(x) <= top + 0.5 * LEVEL_RESOLUTION {
                x += s;
                s += h.step_increase;
                step += 1;
            }
            return Some(Next::Hunt { level: on_lattice(x.min(h.cap)), step });
        }
        if matches!(self.hunt_end(), Some((HuntEnd::GravityFailed, _))) {
            return None;
        }
        (0..self.shares.len()).find_map(|k| self.fill(k))
    }

    /// The bisection of limit `k`'s passage still to run, if any.
    fn fill(&self, k: usize) -> Option<Next> {
        let j = (0..self.points.len()).find(|&i| self.passes(i, k))?;
        let (lower, upper) = (self.points.get(j.checked_sub(1)?)?.0, self.points[j].0);
        if upper - lower <= self.rules.precision * upper {
            return None;
        }
        let level = on_lattice(0.5 * (lower + upper));
        let inside = level > lower + 0.5 * LEVEL_RESOLUTION && level < upper - 0.5 * LEVEL_RESOLUTION;
        inside.then_some(Next::Fill { level, limit: k, lower, upper })
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn rules() -> HuntRules {
        HuntRules {
            first: 0.5,
            step: 0.5,
            step_increase: 0.25,
            cap: 6.0,
            precision: 0.05,
            flat_slope: 0.2,
            stop_at_passage: true,
        }
    }

    /// Runs a chain to its end on a response given in closed form; the levels in the order run.
    fn run<'a>(rules: &'a HuntRules, shares: &[f64], f: impl Fn(f64) -> Response) -> (Chain<'a>, Vec<Next>) {
        let mut c = Chain::new(rules, shares.to_vec());
        let mut order = Vec::new();
        while let Some(n) = c.next() {
            assert!(order.len() < 100, "no end: {order:?}");
            order.push(n);
            c.add(n.level(), f(n.level()));
        }
        (c, order)
    }

    /// share = 0.1 x (the level in m/s^2), drift 1e-3 x level (linear, never flat): the limit of
    /// 0.26 is passed at 2.6 m/s² exactly. Hunt levels 0.5, 1.0 (step 0.5), 1.75 (0.5 + 0.25),
    /// 2.75 (0.75 + 0.25): passed there; the fill bisects [1.75, 2.75] to 5 % of the upper end:
    /// 2.25, 2.5, 2.625 (passed; 2.625 - 2.5 = 0.125 <= 0.05 x 2.625). The crossing, linear in
    /// the share between 2.5 and 2.625, is 2.6 to round-off (the share is linear).
    #[test]
    fn a_linear_response_is_hunted_then_bisected_to_the_precision() {
        let r = rules();
        let (c, order) = run(&r, &[0.26], |x| Response::Completed { shares: vec![0.1 * x], drift: 1e-3 * x });
        let levels: Vec<f64> = order.iter().map(Next::level).collect();
        let want = [0.5, 1.0, 1.75, 2.75, 2.25, 2.5, 2.625];
        assert_eq!(levels.len(), want.len(), "{levels:?}");
        for (a, b) in levels.iter().zip(want) {
            assert!((a - b).abs() < 1e-9, "{levels:?}");
        }
        assert!(matches!(order[3], Next::Hunt { step: 3, .. }) && matches!(order[4], Next::Fill { limit: 0, .. }));
        assert_eq!(c.hunt_end().map(|e| e.0), Some(HuntEnd::AllPassed));
        let x = crossing("r", &c.readings(0), 0.26, "above_cap");
        assert_eq!(x.how, "reached");
        assert!((x.intensity.unwrap() - 2.6).abs() < 1e-9, "{x:?}");
    }

    /// A limit never passed below the cap: the hunt runs up to the cap (capped last step) and
    /// stops; the crossing is censored at the cap.
    #[test]
    fn a_limit_not_passed_up_to_the_cap_is_censored_there() {
        let r = HuntRules { cap: 2.0, ..rules() };
        let (c, order) = run(&r, &[0.9], |x| Response::Completed { shares: vec![0.1 * x], drift: 1e-3 * x });
        let levels: Vec<f64> = order.iter().map(Next::level).collect();
        assert_eq!(levels, vec![0.5, 1.0, 1.75, 2.0]);
        assert_eq!(c.hunt_end(), Some((HuntEnd::Cap, 2.0)));
        let x = crossing("r", &c.readings(0), 0.9, "above_cap");
        assert_eq!((x.how, x.intensity, x.censored_at), ("above_cap", None, Some(2.0)));
    }

    /// Stops converging above 2.2 m/s², the share never reaching 0.9: the hunt ends at its first
    /// stopped level (2.75) and the fill bisects the collapse down to 5 %: the limit counts as
    /// passed at the lowest stopped level, within 5 % above 2.2.
    #[test]
    fn a_member_that_stops_is_the_flat_end_and_is_bisected() {
        let r = rules();
        let (c, _) = run(&r, &[0.9], |x| {
            if x > 2.2 {
                Response::Stopped
            } else {
                Response::Completed { shares: vec![0.1 * x], drift: 1e-3 * x }
            }
        });
        assert_eq!(c.hunt_end(), Some((HuntEnd::Stopped, 2.75)));
        let x = crossing("r", &c.readings(0), 0.9, "above_cap");
        assert_eq!(x.how, "stopped");
        let at = x.intensity.unwrap();
        assert!(at > 2.2 && at <= 2.2 / 0.95, "{at}");
    }

    /// Drift d = 1e-3 x for x <= 1, then 1e-3 + 0.05 (x - 1): the secant x / d falls below 0.2 of
    /// the first's (1000) where x < 200 d = 10 x - 9.8, i.e. x > 9.8 / 9 = 1.0889. The share stays
    /// below the limit: the hunt ends flat at 1.75 (secant 45) and the fill bisects the flat end
    /// to within 5 % above 1.0889.
    #[test]
    fn a_flat_response_ends_the_hunt_and_is_bisected() {
        let drift = |x: f64| if x <= 1.0 { 1e-3 * x } else { 1e-3 + 0.05 * (x - 1.0) };
        let r = rules();
        let (c, _) = run(&r, &[0.9], |x| Response::Completed { shares: vec![0.01 * x], drift: drift(x) });
        assert_eq!(c.hunt_end(), Some((HuntEnd::Flat, 1.75)));
        let x = crossing("r", &c.readings(0), 0.9, "above_cap");
        assert_eq!(x.how, "flat");
        let at = x.intensity.unwrap();
        let exact = 9.8 / 9.0;
        assert!(at > exact && at <= exact / 0.95, "{at} against {exact}");
    }

    /// Two limits: the second's passage is bisected after the first's; a limit passed at the
    /// first level is not bisected (at or below the lowest).
    #[test]
    fn each_limit_is_bisected_in_turn() {
        let r = rules();
        let (c, order) = run(&r, &[0.04, 0.26], |x| Response::Completed { shares: vec![0.1 * x; 2], drift: 1e-3 * x });
        let limits: Vec<usize> =
            order.iter().filter_map(|n| if let Next::Fill { limit, .. } = n { Some(*limit) } else { None }).collect();
        assert!(limits.iter().all(|&k| k == 1) && !limits.is_empty(), "{order:?}");
        assert_eq!(crossing("r", &c.readings(0), 0.04, "above_cap").how, "at_or_below_lowest");
    }

    /// Crossings of a grid by hand: between 1 (0.2) and 2 (0.6) the share reaches 0.5 at 1.75;
    /// above the highest; at the lowest; at a stopped member.
    #[test]
    fn crossings_of_a_limit() {
        let s = Reading::Share;
        let c = crossing("r", &[(1.0, s(0.2)), (2.0, s(0.6)), (3.0, s(0.9))], 0.5, "above_highest");
        assert_eq!(c.how, "reached");
        assert!((c.intensity.unwrap() - 1.75).abs() < 1e-12);
        let c = crossing("r", &[(1.0, s(0.1)), (2.0, s(0.2))], 0.5, "above_highest");
        assert_eq!((c.intensity, c.censored_at), (None, Some(2.0)));
        assert_eq!(crossing("r", &[(1.0, s(0.7))], 0.5, "above_highest").how, "at_or_below_lowest");
        let c = crossing("r", &[(1.0, s(0.1)), (2.0, Reading::Stopped)], 0.5, "above_highest");
        assert_eq!((c.how, c.intensity), ("stopped", Some(2.0)));
    }
}
