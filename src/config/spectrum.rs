//! The job file of a response-spectrum analysis: a ground motion's elastic response spectra,
//! drawn against Eurocode 8 elastic spectra (like the paper's Fig. 7).
//!
//! ```toml
//! [analysis]
//! type = "spectrum"
//! damping = 0.05                       # ratio of critical
//! periods = { min = 0.02, max = 4.0, count = 200 }
//! [record]                             # a file ...
//! file = "records/vallorcine-like-synthetic.txt"
//! format = "two_column"                # at2 | esm | two_column | one_column
//! units = "m/s2"                       # two_column, one_column: g | m/s2 | cm/s2
//! scale = 1.0
//! # ... or: synthetic = "vallorcine_like"
//! [ec8]                                # optional: code spectra to compare with
//! ground = "A"
//! ag = 1.6                             # m/s²
//! types = ["type1", "type2"]
//! ```
use crate::seismic::{Ec8Type, GroundType};
use serde::Deserialize;
use std::path::PathBuf;

/// `[analysis]` of a spectrum job.
#[derive(Clone, Debug, Deserialize, PartialEq, schemars::JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct SpectrumAnalysis {
    /// Always `"spectrum"`.
    #[serde(rename = "type")]
    pub kind: String,
    /// Damping ratio (default 0.05).
    #[serde(default = "five_percent")]
    pub damping: f64,
    /// Periods: log-spaced between `min` and `max` (plus T = 0).
    #[serde(default)]
    pub periods: PeriodRange,
}

fn five_percent() -> f64 {
    0.05
}

/// Log-spaced periods.
#[derive(Clone, Debug, Deserialize, PartialEq, schemars::JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct PeriodRange {
    /// Shortest period [s].
    pub min: f64,
    /// Longest period [s].
    pub max: f64,
    /// Number of periods.
    pub count: usize,
}

impl Default for PeriodRange {
    fn default() -> Self {
        PeriodRange { min: 0.02, max: 4.0, count: 200 }
    }
}

/// Record file formats.
#[derive(Clone, Copy, Debug, Deserialize, PartialEq, Eq, schemars::JsonSchema)]
#[serde(rename_all = "snake_case")]
pub enum RecordFormat {
    /// PEER NGA `.AT2` (in g).
    At2,
    /// ESM ASCII (units in its header).
    Esm,
    /// Two columns `t a`.
    TwoColumn,
    /// One column of accelerations at a given `dt`.
    OneColumn,
}

/// `[record]`: the ground motion.
#[derive(Clone, Debug, Deserialize, PartialEq, schemars::JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct RecordConfig {
    /// A record file, relative to the job file's folder.
    pub file: Option<PathBuf>,
    /// Its format.
    pub format: Option<RecordFormat>,
    /// Units of a column file: `g`, `m/s2`, `cm/s2`.
    pub units: Option<String>,
    /// Time step of a one-column file [s].
    pub dt: Option<f64>,
    /// A built-in synthetic record instead of a file: `"vallorcine_like"`.
    pub synthetic: Option<String>,
    /// Scale factor on the accelerations (default 1).
    #[serde(default = "unit")]
    pub scale: f64,
}

fn unit() -> f64 {
    1.0
}

/// `[ec8]`: Eurocode 8 elastic spectra to compare with.
#[derive(Clone, Debug, Deserialize, PartialEq, schemars::JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct Ec8Config {
    /// Ground type A–E.
    pub ground: GroundType,
    /// Design ground acceleration a_g [m/s²].
    pub ag: f64,
    /// Spectrum types (default both).
    #[serde(default = "both_types")]
    pub types: Vec<Ec8Type>,
}

fn both_types() -> Vec<Ec8Type> {
    vec![Ec8Type::Type1, Ec8Type::Type2]
}

/// A spectrum job file, as written.
#[derive(Clone, Debug, Deserialize, PartialEq, schemars::JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct SpectrumJobFile {
    /// A one-line description.
    pub title: Option<String>,
    /// `[analysis]`.
    pub analysis: SpectrumAnalysis,
    /// The ground motion.
    pub record: RecordConfig,
    /// Code spectra.
    pub ec8: Option<Ec8Config>,
    /// Where results go.
    #[serde(default)]
    pub output: super::OutputConfig,
}
