//! `[[dynamics.drift]]`: a storey drift between two levels of the model, written per step to
//! `monitors.csv` and as a peak to `summary.json` (`analysis::time_history::drift`).
//!
//! ```toml
//! [[dynamics.drift]]
//! name = "ground-floor"
//! levels = [0.0, 3.5]             # [m] z of the lower and the upper level: the model's nodes
//! tolerance = 0.01                # within this distance of each [m] (default 0.01)
//! # groups = ["base", "floor-1"]  # or two mesh groups: their nodes (any z)
//! ```
//!
//! The drift of a storey along x (or y) is the difference between the mean relative
//! displacement of the upper level's nodes and that of the lower level's, over the height
//! between the two levels' mean z: `(ū_upper − ū_lower) / (z̄_upper − z̄_lower)`.
use super::source::{Seg, Source};
use super::ConfigError;
use serde::Deserialize;

/// Default `tolerance` [m] of `levels`.
pub const DEFAULT_LEVEL_TOLERANCE: f64 = 0.01;

/// One `[[dynamics.drift]]`.
#[derive(Clone, Debug, Deserialize, PartialEq, schemars::JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct DriftConfig {
    /// Name in the CSV header (`drift:<name>:x`) and the summary.
    pub name: String,
    /// z of the lower and the upper level [m].
    pub levels: Option<[f64; 2]>,
    /// The mesh groups of the lower and the upper level.
    pub groups: Option<[String; 2]>,
    /// With `levels`: the largest distance in z of a level's nodes [m].
    #[serde(default = "default_tolerance")]
    pub tolerance: f64,
}

fn default_tolerance() -> f64 {
    DEFAULT_LEVEL_TOLERANCE
}

/// How a drift's two levels are chosen.
#[derive(Clone, Debug, PartialEq)]
pub enum DriftLevels<'a> {
    /// The nodes within `tolerance` of each z.
    Heights([f64; 2], f64),
    /// The nodes of each group.
    Groups(&'a [String; 2]),
}

impl DriftConfig {
    /// The levels, once checked ([`check_drifts`]).
    pub fn how(&self) -> DriftLevels<'_> {
        match (&self.levels, &self.groups) {
            (Some(z), _) => DriftLevels::Heights(*z, self.tolerance),
            (None, Some(g)) => DriftLevels::Groups(g),
            (None, None) => DriftLevels::Heights([0.0, 0.0], self.tolerance),
        }
    }
}

/// `[[dynamics.drift]]`: distinct names fit for a CSV header; either two distinct finite levels
/// (lower first) with a tolerance > 0, or two distinct groups.
pub fn check_drifts(src: &Source, drifts: &[DriftConfig]) -> Result<(), ConfigError> {
    for (i, d) in drifts.iter().enumerate() {
        let at = |k: &str| vec![Seg::key("dynamics"), Seg::key("drift"), Seg::Index(i), Seg::key(k)];
        if d.name.is_empty() || d.name.contains([',', '/', '\\', '"', ':']) {
            return Err(src.error_at(&at("name"), "expected a non-empty name without , : / \\ or quotes"));
        }
        if drifts[..i].iter().any(|o| o.name == d.name) {
            return Err(src.error_at(&at("name"), format!("drift '{}' is given twice", d.name)));
        }
        match (&d.levels, &d.groups) {
            (Some([lo, hi]), None) => {
                if !(lo.is_finite() && hi.is_finite() && lo < hi) {
                    return Err(src.error_at(
                        &at("levels"),
                        format!("expected [lower z, upper z] in m with lower < upper, got [{lo}, {hi}]"),
                    ));
                }
                if !(d.tolerance.is_finite() && d.tolerance > 0.0 && d.tolerance < 0.5 * (hi - lo)) {
                    return Err(src.error_at(
                        &at("tolerance"),
                        format!("expected a tolerance > 0 and below half the storey height [m], got {}", d.tolerance),
                    ));
                }
            }
            (None, Some([a, b])) if a != b => {}
            (None, Some(_)) => return Err(src.error_at(&at("groups"), "expected two different groups")),
            _ => {
                return Err(src.error_at(
                    &[Seg::key("dynamics"), Seg::key("drift"), Seg::Index(i)],
                    "give levels = [lower z, upper z] (m), or groups = [\"lower group\", \"upper group\"]",
                ))
            }
        }
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    fn check(toml_text: &str) -> Result<(), String> {
        #[derive(Deserialize, schemars::JsonSchema)]
        struct D {
            drift: Vec<DriftConfig>,
        }
        #[derive(Deserialize, schemars::JsonSchema)]
        struct F {
            dynamics: D,
        }
        let src = Source { file: "job.toml".into(), text: toml_text.to_string() };
        let f: F = src.deserialize().map_err(|e| e.to_string())?;
        check_drifts(&src, &f.dynamics.drift).map_err(|e| e.to_string())
    }

    /// Levels or groups, each checked at its key.
    #[test]
    fn drifts_are_checked_at_their_keys() {
        assert!(check("[[dynamics.drift]]\nname = \"a\"\nlevels = [0.0, 3.5]\n").is_ok());
        assert!(check("[[dynamics.drift]]\nname = \"a\"\ngroups = [\"base\", \"floor\"]\n").is_ok());
        let e = check("[[dynamics.drift]]\nname = \"a\"\nlevels = [3.5, 0.0]\n").unwrap_err();
        assert!(e.contains("dynamics.drift[0].levels") && e.contains("lower < upper"), "{e}");
        let e = check("[[dynamics.drift]]\nname = \"a\"\nlevels = [0, 3]\ntolerance = 2\n").unwrap_err();
        assert!(e.contains("dynamics.drift[0].tolerance"), "{e}");
        let e = check("[[dynamics.drift]]\nname = \"a\"\n").unwrap_err();
        assert!(e.contains("give levels"), "{e}");
        let e = check(
            "[[dynamics.drift]]\nname = \"a\"\nlevels = [0, 3]\n[[dynamics.drift]]\nname = \"a\"\nlevels = [3, 6]\n",
        )
        .unwrap_err();
        assert!(e.contains("dynamics.drift[1].name") && e.contains("twice"), "{e}");
        let e = check("[[dynamics.drift]]\nname = \"a\"\ngroups = [\"g\", \"g\"]\n").unwrap_err();
        assert!(e.contains("two different groups"), "{e}");
    }
}
