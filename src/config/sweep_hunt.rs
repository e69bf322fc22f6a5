//! `[sweep.hunt]`: adaptive intensities by hunt and fill (Vamvatsikos and Cornell 2004, "Applied
//! incremental dynamic analysis", Earthquake Spectra 20(2)), the sweep's default; `[sweep]
//! intensities = [...]` gives a fixed grid instead.
//!
//! ```toml
//! [sweep.hunt]           # every key optional where [sweep] code_level is given (defaults below)
//! first = 0.4            # m/s²: the first intensity of every record and material (code_level / 4)
//! step = 0.4             # m/s²: the first step up (code_level / 4)
//! step_increase = 0.2    # m/s²: added to the step after each level (code_level / 8)
//! cap = 4.8              # m/s²: the hunt never goes above it (3 code_level)
//! precision = 0.05       # each limit's passage bisected until (upper - lower) <= precision x upper
//! flat_slope = 0.2       # the IDA curve is flat where its secant falls below this share of the first's
//! stop_at_passage = true # a member ends once it has passed every limit
//! ```
//!
//! Without `intensities` and without `[sweep.hunt]` the sweep hunts with these defaults. They
//! follow the proportions of Vamvatsikos and Cornell's example (a first step of 0.1 g growing by
//! 0.05 g) on the site's code level, and the cap at 3 times it.
//!
//! Per record and material, the hunt steps up from `first` (`first`, `first + step`,
//! `first + 2 step + step_increase`, ...) until the last level passes every `[[sweep.limit]]`,
//! stops converging, or is flat, or the level reached is `cap`; the fill then bisects each limit's
//! passage between the highest level below it and the lowest above it to `precision`. Levels lie
//! on a 1e-4 m/s² lattice (the members' names carry 4 decimals).
//!
//! With `stop_at_passage` (the default) each member's job ends its time history once every
//! limit's share is reached (`[[dynamics.stop_when]]`, checked at its output steps): damage never
//! heals, so the rest of the record cannot undo a passage, and the hunt reads passed or not,
//! which the shortened run already tells. Such a member's shares and drift are those at its end,
//! lower bounds of the whole record's (`sweep.csv` says where it ended); a passage interpolated
//! against one lies towards its level, within the bracket that `precision` bounds.
use super::{ConfigError, Seg, Source, SweepConfig};
use serde::{Deserialize, Serialize};

/// The lattice of the hunt's levels [m/s²]: the members' names carry 4 decimals.
pub const LEVEL_RESOLUTION: f64 = 1e-4;

fn default_precision() -> f64 {
    0.05
}

fn default_flat_slope() -> f64 {
    0.2
}

/// `[sweep.hunt]` as written.
#[derive(Clone, Debug, Deserialize, Serialize, PartialEq, schemars::JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct HuntConfig {
    /// The first level [m/s²].
    pub first: Option<f64>,
    /// The first step up [m/s²].
    pub step: Option<f64>,
    /// Added to the step after each level [m/s²].
    pub step_increase: Option<f64>,
    /// The highest level the hunt runs [m/s²].
    pub cap: Option<f64>,
    /// The fill's stopping rule, relative to the passage's upper level.
    #[serde(default = "default_precision")]
    pub precision: f64,
    /// The flat end's secant ratio.
    #[serde(default = "default_flat_slope")]
    pub flat_slope: f64,
    /// A member ends once it has passed every limit (default true).
    #[serde(default = "default_stop_at_passage")]
    pub stop_at_passage: bool,
}

fn default_stop_at_passage() -> bool {
    true
}

impl Default for HuntConfig {
    /// The table left out: every level from `code_level`, the precision and the flat slope at
    /// their defaults.
    fn default() -> HuntConfig {
        HuntConfig {
            first: None,
            step: None,
            step_increase: None,
            cap: None,
            precision: default_precision(),
            flat_slope: default_flat_slope(),
            stop_at_passage: default_stop_at_passage(),
        }
    }
}

/// The hunt's rules, resolved (every level in m/s²).
#[derive(Clone, Debug, Serialize, PartialEq)]
pub struct HuntRules {
    /// The first level.
    pub first: f64,
    /// The first step up.
    pub step: f64,
    /// Added to the step after each level (Vamvatsikos and Cornell 2004 step up by a constant
    /// plus an increment); 0 keeps the step constant.
    pub step_increase: f64,
    /// The highest level the hunt runs.
    pub cap: f64,
    /// The fill's stopping rule: (upper − lower) ≤ `precision` × upper for each passage.
    pub precision: f64,
    /// A member is on the flat end of the IDA curve where its secant slope, intensity over peak
    /// drift ratio, falls below `flat_slope` times the first level's (after the 20 % tangent rule
    /// of Vamvatsikos and Cornell 2002, on the secant so that each member decides alone).
    pub flat_slope: f64,
    /// A member ends once it has passed every limit (`[[dynamics.stop_when]]` in its job).
    pub stop_at_passage: bool,
}

/// A sweep's intensities, resolved at load.
#[derive(Clone, Debug, PartialEq)]
pub enum Plan {
    /// A fixed list [m/s²].
    Grid(Vec<f64>),
    /// Hunt and fill.
    Hunt(HuntRules),
}

/// How a sweep's intensities are chosen.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Intensities<'a> {
    /// A fixed list, every record and material at each.
    Grid(&'a [f64]),
    /// Hunt and fill per record and material.
    Hunt(&'a HuntRules),
}

impl super::SweepJob {
    /// The intensities: a grid or the hunt.
    pub fn intensities(&self) -> Intensities<'_> {
        match &self.plan {
            Plan::Grid(x) => Intensities::Grid(x),
            Plan::Hunt(h) => Intensities::Hunt(h),
        }
    }
}

fn at(keys: &[&str]) -> Vec<Seg> {
    std::iter::once("sweep").chain(keys.iter().copied()).map(Seg::key).collect()
}

/// The intensities of `[sweep]`: a grid where `intensities` is given, else the hunt (its keys
/// or their defaults from `code_level`); each checked.
pub(super) fn check_plan(source: &Source, c: &SweepConfig) -> Result<Plan, ConfigError> {
    match (&c.intensities, &c.hunt) {
        (Some(_), Some(_)) => Err(source.error_at(
            &at(&["intensities"]),
            "give either intensities = [...] (a fixed grid) or [sweep.hunt] (adaptive intensities), not both",
        )),
        (Some(x), None) => check_grid(source, x).map(|()| Plan::Grid(x.clone())),
        (None, None) if c.code_level.is_none() => Err(source.error_at(
            &at(&[]),
            "no intensities: give intensities = [...] (a fixed grid), or [sweep.hunt] with first, step and cap [m/s^2], or code_level (the hunt's levels default to shares of it)",
        )),
        (None, h) => check_hunt(source, c, &h.clone().unwrap_or_default()).map(Plan::Hunt),
    }
}

fn check_grid(source: &Source, xs: &[f64]) -> Result<(), ConfigError> {
    if xs.is_empty() {
        return Err(source.error_at(&at(&["intensities"]), "give at least one intensity [m/s^2]"));
    }
    for (i, &x) in xs.iter().enumerate() {
        source.positive_finite(
            &[Seg::key("sweep"), Seg::key("intensities"), Seg::Index(i)],
            x,
            "intensity",
            "m/s^2",
        )?;
    }
    if xs.windows(2).any(|w| w[1] <= w[0]) {
        return Err(source.error_at(&at(&["intensities"]), "expected intensities in increasing order, each once"));
    }
    Ok(())
}

fn check_hunt(source: &Source, c: &SweepConfig, h: &HuntConfig) -> Result<HuntRules, ConfigError> {
    let table = if c.hunt.is_some() { at(&["hunt"]) } else { at(&[]) };
    if c.limit.is_empty() {
        return Err(source.error_at(
            &table,
            "a hunt needs at least one [[sweep.limit]]: it steps up until every limit is passed (or the response is flat, or the cap is reached); give a limit, or intensities = [...] for a fixed grid",
        ));
    }
    // A key as written, or its default: `share` of the code level.
    let key = |key: &str, given: Option<f64>, share: f64, what: &str| {
        given.or(c.code_level.map(|x| share * x)).ok_or_else(|| {
            source.error_at(
                &table,
                format!("the hunt needs {key} [m/s^2] ({what}): give it in [sweep.hunt], or give code_level, whose {share} times it is the default"),
            )
        })
    };
    let rules = HuntRules {
        first: key("first", h.first, 0.25, "the first intensity")?,
        step: key("step", h.step, 0.25, "the first step up")?,
        step_increase: key("step_increase", h.step_increase, 0.125, "added to the step after each level")?,
        cap: key("cap", h.cap, 3.0, "the highest intensity")?,
        precision: h.precision,
        flat_slope: h.flat_slope,
        stop_at_passage: h.stop_at_passage,
    };
    check_rules(source, &rules)?;
    Ok(rules)
}

fn check_rules(source: &Source, h: &HuntRules) -> Result<(), ConfigError> {
    let err = |key: &str, msg: String| source.error_at(&at(&["hunt", key]), msg);
    let res = LEVEL_RESOLUTION;
    if !(h.first.is_finite() && h.first >= res) {
        return Err(err("first", format!("expected a first intensity >= {res} [m/s^2], got {}", h.first)));
    }
    if !(h.step.is_finite() && h.step >= res) {
        return Err(err("step", format!("expected a step >= {res} [m/s^2], got {}", h.step)));
    }
    source.non_negative(&at(&["hunt", "step_increase"]), h.step_increase, "step increase", "m/s^2")?;
    if !(h.cap.is_finite() && h.cap >= h.first) {
        return Err(err("cap", format!("expected a cap >= first = {} [m/s^2], got {}", h.first, h.cap)));
    }
    if !(h.precision.is_finite() && h.precision > 0.0 && h.precision < 1.0) {
        return Err(err(
            "precision",
            format!(
                "expected a precision in (0, 1) (the bracket of a passage relative to its upper end, e.g. 0.05), got {}",
                h.precision
            ),
        ));
    }
    if !(h.flat_slope.is_finite() && h.flat_slope > 0.0 && h.flat_slope < 1.0) {
        return Err(err("flat_slope", format!("expected a slope ratio in (0, 1), e.g. 0.2, got {}", h.flat_slope)));
    }
    Ok(())
}

impl super::SweepJob {
    /// The members for people: "4 member(s) (1 material(s) x 2 record(s) x 2 intensit(ies) of
    /// PGA)", or the hunt's settings.
    pub fn plan_line(&self) -> String {
        let (v, r, im) = (self.variants.len(), self.records.len(), self.spec.sweep.scale_by.label());
        match self.intensities() {
            Intensities::Grid(x) => format!(
                "{} member(s) ({v} material(s) x {r} record(s) x {} intensit(ies) of {im})",
                v * r * x.len(),
                x.len()
            ),
            Intensities::Hunt(h) => format!(
                "adaptive intensities for {} record-material pair(s) ({v} material(s) x {r} record(s)): {im} hunted from {} by {} (+{} per level) up to {} m/s^2, each limit's passage bisected to {} %",
                v * r,
                h.first,
                h.step,
                h.step_increase,
                h.cap,
                100.0 * h.precision
            ),
        }
    }
}
