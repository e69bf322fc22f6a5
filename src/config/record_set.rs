//! The job file of a record set: ground motions compatible with a Eurocode 8 elastic spectrum
//! (EN 1998-1 §3.2.3.1), artificial ones matched to it and recorded ones scaled to it, checked
//! and written for later time histories ([`crate::seismic::build_set`]).
//!
//! ```toml
//! [analysis]
//! type = "record_set"
//! [record_set]
//! spectrum_type = "type1"          # type1 (Ms > 5.5) | type2 (Ms ≤ 5.5)
//! ground = "A"                     # A–E (EN 1998-1 Table 3.1)
//! ag = 1.6                         # a_g = γ_I a_gR [m/s²]
//! t1 = 0.33                        # T₁ [s]: the check's range is [0.2 T₁, 2 T₁] ...
//! # period_range = { min = 0.066, max = 0.66 }   # ... or a range given directly
//! range_points = 100               # log-spaced periods over the range (default 100)
//! require_compatible = true        # a set that fails the check ends the job with an error (default)
//! [record_set.artificial]          # optional: artificial records matched to the spectrum
//! count = 3                        # default 3
//! seed = 20260301                  # record k (0-based) uses seed + k
//! duration = 20.0                  # s (default 20)
//! dt = 0.01                        # s (default 0.01)
//! rise = 2.0                       # s, envelope (t/rise)² (default 2)
//! stationary = 10.0                # s, constant envelope (default 10; EC8 §3.2.3.1.2(3): ≥ 10 s)
//! decay = 0.5                      # 1/s, exp decay after it (default 0.5)
//! high_pass = 0.1                  # Hz, zero-phase high-pass before matching (default 0.1; 0: none)
//! matching_iterations = 8          # default 8
//! matching_periods = { min = 0.02, max = 4.0, count = 100 }   # the default
//! [[record_set.recorded]]          # optional, any number: each scaled by one factor
//! file = "records/some.AT2"
//! format = "at2"                   # at2 | esm | two_column | one_column
//! units = "g"                      # two_column, one_column: g | m/s2 | cm/s2
//! dt = 0.01                        # one_column only
//! ```
use super::{ConfigError, OutputConfig, PeriodRange, RecordConfig, RecordFormat, Seg, Source};
use crate::seismic::{
    ArtificialSpec, CompatibilityRules, Ec8Spectrum, Ec8Type, GroundType, MatchSettings, Record, SET_DAMPING,
};
use serde::Deserialize;
use std::path::{Path, PathBuf};

/// `[analysis]` of a record-set job.
#[derive(Clone, Debug, Deserialize, PartialEq, schemars::JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct RecordSetAnalysis {
    /// Always `"record_set"`.
    #[serde(rename = "type")]
    pub kind: String,
}

/// A period interval [s].
#[derive(Clone, Copy, Debug, Deserialize, PartialEq, schemars::JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct PeriodInterval {
    /// Shortest period [s].
    pub min: f64,
    /// Longest period [s].
    pub max: f64,
}

/// `[record_set]`.
#[derive(Clone, Debug, Deserialize, PartialEq, schemars::JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct RecordSetConfig {
    /// EC8 spectrum type.
    pub spectrum_type: Ec8Type,
    /// Ground type.
    pub ground: GroundType,
    /// Design ground acceleration a_g [m/s²].
    pub ag: f64,
    /// The structure's fundamental period T₁ [s] (range [0.2 T₁, 2 T₁]).
    pub t1: Option<f64>,
    /// Or the range itself.
    pub period_range: Option<PeriodInterval>,
    /// Log-spaced periods over the range, for the check and the scale factors.
    #[serde(default = "default_range_points")]
    pub range_points: usize,
    /// Whether a failed check ends the job with an error.
    #[serde(default = "yes")]
    pub require_compatible: bool,
    /// Artificial records.
    pub artificial: Option<ArtificialConfig>,
    /// Recorded records.
    #[serde(default)]
    pub recorded: Vec<RecordedConfig>,
}

fn default_range_points() -> usize {
    100
}

fn yes() -> bool {
    true
}

/// `[record_set.artificial]`; the defaults are in [`Default`].
#[derive(Clone, Debug, Deserialize, PartialEq, schemars::JsonSchema)]
#[serde(deny_unknown_fields, default)]
pub struct ArtificialConfig {
    /// Number of records.
    pub count: usize,
    /// Base seed (record k uses seed + k).
    pub seed: u64,
    /// Duration [s].
    pub duration: f64,
    /// Time step [s].
    pub dt: f64,
    /// Envelope rise [s].
    pub rise: f64,
    /// Stationary part [s].
    pub stationary: f64,
    /// Decay rate [1/s].
    pub decay: f64,
    /// High-pass corner [Hz], 0 for none.
    pub high_pass: f64,
    /// Matching iterations.
    pub matching_iterations: usize,
    /// Matching periods, log-spaced.
    pub matching_periods: PeriodRange,
}

impl Default for ArtificialConfig {
    fn default() -> Self {
        ArtificialConfig {
            count: 3,
            seed: 20_260_301,
            duration: 20.0,
            dt: 0.01,
            rise: 2.0,
            stationary: 10.0,
            decay: 0.5,
            high_pass: 0.1,
            matching_iterations: 8,
            matching_periods: PeriodRange { min: 0.02, max: 4.0, count: 100 },
        }
    }
}

/// `[[record_set.recorded]]`: a record file (scaled by the set, so no `scale` key).
#[derive(Clone, Debug, Deserialize, PartialEq, schemars::JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct RecordedConfig {
    /// The file, relative to the job file's folder.
    pub file: PathBuf,
    /// Its format.
    pub format: RecordFormat,
    /// Units of a column file.
    pub units: Option<String>,
    /// Time step of a one-column file [s].
    pub dt: Option<f64>,
}

/// A record-set job file, as written.
#[derive(Clone, Debug, Deserialize, PartialEq, schemars::JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct RecordSetJobFile {
    /// A one-line description.
    pub title: Option<String>,
    /// `[analysis]`.
    pub analysis: RecordSetAnalysis,
    /// `[record_set]`.
    pub record_set: RecordSetConfig,
    /// Where results go.
    #[serde(default)]
    pub output: OutputConfig,
}

/// A loaded, validated record-set job: the target, the rules, the generator's settings and the
/// recorded records read (unscaled, m/s²).
pub struct RecordSetJob {
    /// The file and its text.
    pub source: Source,
    /// What it says.
    pub spec: RecordSetJobFile,
    /// The target spectrum (5 % damping).
    pub target: Ec8Spectrum,
    /// The rules with the period range.
    pub rules: CompatibilityRules,
    /// The artificial records' settings and count.
    pub artificial: Option<(ArtificialSpec, usize)>,
    /// The recorded records, as read.
    pub recorded: Vec<Record>,
    /// The results folder.
    pub output_dir: PathBuf,
}

fn at(keys: &[&str]) -> Vec<Seg> {
    std::iter::once("record_set").chain(keys.iter().copied()).map(Seg::key).collect()
}

impl RecordSetJob {
    /// Parses and checks the job in `source` (read from `path`).
    pub(super) fn from_source(source: Source, path: &Path) -> Result<RecordSetJob, ConfigError> {
        let spec: RecordSetJobFile = source.deserialize()?;
        let c = &spec.record_set;
        let err = |keys: &[&str], msg: String| source.error_at(&at(keys), msg);
        source.positive_finite(&at(&["ag"]), c.ag, "a_g", "m/s^2")?;
        let target = Ec8Spectrum::new(c.spectrum_type, c.ground, c.ag, 100.0 * SET_DAMPING)
            .map_err(|e| err(&["ag"], e.to_string()))?;
        let rules = match (c.t1, c.period_range) {
            (Some(t1), None) => CompatibilityRules::ec8(source.positive_finite(&at(&["t1"]), t1, "T1", "s")?),
            (None, Some(r)) if r.min > 0.0 && r.max > r.min && r.max.is_finite() => {
                CompatibilityRules::ec8_range(r.min, r.max)
            }
            (None, Some(r)) => {
                return Err(err(&["period_range"], format!("expected 0 < min < max [s], got [{}, {}]", r.min, r.max)))
            }
            (Some(_), Some(_)) => {
                return Err(err(&["period_range"], "give either t1 or period_range, not both".into()))
            }
            (None, None) => {
                return Err(err(
                    &[],
                    "give t1 (the check's range is [0.2 t1, 2 t1]) or period_range = { min, max }".into(),
                ))
            }
        };
        if !(2..=10_000).contains(&c.range_points) {
            return Err(err(&["range_points"], format!("expected 2 to 10000 periods, got {}", c.range_points)));
        }
        let artificial = match &c.artificial {
            Some(a) => Some((artificial_spec(&source, a)?, a.count)),
            None => None,
        };
        let folder = path.parent().map(Path::to_path_buf).unwrap_or_default();
        let mut recorded = Vec::new();
        for (i, r) in c.recorded.iter().enumerate() {
            let keys = |k: &str| vec![Seg::key("record_set"), Seg::key("recorded"), Seg::Index(i), Seg::key(k)];
            let rc = RecordConfig {
                file: Some(r.file.clone()),
                format: Some(r.format),
                units: r.units.clone(),
                dt: r.dt,
                synthetic: None,
                scale: 1.0,
            };
            recorded.push(super::record::read_record(&source, &folder, &rc, &keys)?);
        }
        let n = artificial.as_ref().map_or(0, |a| a.1) + recorded.len();
        if n == 0 {
            return Err(err(
                &[],
                "the set has no record: add [record_set.artificial] (count ≥ 1) or [[record_set.recorded]]".into(),
            ));
        }
        let output_dir = super::output_dir(path, &spec.output);
        Ok(RecordSetJob { source, spec, target, rules, artificial, recorded, output_dir })
    }
}

/// The generator's settings of `[record_set.artificial]`, each checked at its key.
fn artificial_spec(source: &Source, a: &ArtificialConfig) -> Result<ArtificialSpec, ConfigError> {
    let err = |k: &str, msg: String| source.error_at(&at(&["artificial", k]), msg);
    let positive = [
        ("duration", a.duration, "s"),
        ("dt", a.dt, "s"),
        ("rise", a.rise, "s"),
        ("stationary", a.stationary, "s"),
        ("decay", a.decay, "1/s"),
    ];
    for (k, v, unit) in positive {
        source.positive_finite(&at(&["artificial", k]), v, k, unit)?;
    }
    if a.duration / a.dt > 1.0e6 {
        return Err(err("dt", format!("{} s over {} s is more than 10^6 samples", a.dt, a.duration)));
    }
    if a.rise + a.stationary > a.duration {
        return Err(err(
            "duration",
            format!("expected at least rise + stationary = {} s, got {} s", a.rise + a.stationary, a.duration),
        ));
    }
    if !(a.high_pass.is_finite() && a.high_pass >= 0.0 && a.high_pass < 0.5 / a.dt) {
        return Err(err(
            "high_pass",
            format!("expected 0 (none) or a corner in (0, {}) Hz, got {}", 0.5 / a.dt, a.high_pass),
        ));
    }
    if !(1..=1000).contains(&a.count) {
        return Err(err("count", format!("expected 1 to 1000 records, got {}", a.count)));
    }
    let p = &a.matching_periods;
    if !(p.min > 0.0 && p.max > p.min && p.max.is_finite() && (2..=10_000).contains(&p.count)) {
        return Err(err("matching_periods", "expected 0 < min < max [s] and 2 ≤ count ≤ 10000".into()));
    }
    if a.matching_iterations > 100 {
        return Err(err("matching_iterations", format!("expected at most 100, got {}", a.matching_iterations)));
    }
    let periods = crate::seismic::log_periods(p.min, p.max, p.count)[1..].to_vec();
    Ok(ArtificialSpec {
        prefix: "EC8 artificial".into(),
        seed: a.seed,
        duration: a.duration,
        dt: a.dt,
        rise: a.rise,
        stationary: a.stationary,
        decay: a.decay,
        high_pass_hz: (a.high_pass > 0.0).then_some(a.high_pass),
        matching: MatchSettings { damping: SET_DAMPING, periods, iterations: a.matching_iterations },
    })
}
