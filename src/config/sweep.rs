//! The job file of an intensity sweep (incremental dynamic analysis): one structural model, a set
//! of records, each scaled to a list of intensities, optionally with material variants; every
//! combination (a member) a full nonlinear time history of the base job.
//!
//! ```toml
//! [analysis]
//! type = "sweep"
//! job = "church.toml"              # the base job: time_history or seismic_assessment
//! group_size = 1                   # ranks per member (divides the rank count)
//! [sweep]
//! record_set = "../results/record-set-ec8"   # a record_set job's results (its summary.json) ...
//! # [[sweep.record]]               # ... and/or record files (any number)
//! # file = "records/some.AT2"
//! # format = "at2"                 # at2 | esm | two_column | one_column (units, dt as for a record)
//! require_compatible = true        # the record set must have passed its EN 1998-1 check (default)
//! scale_by = "pga"                 # pga | sa_t1 (5 % damped pseudo-acceleration at `period`)
//! period = 0.333                   # T₁ [s], for sa_t1
//! code_level = 1.6                 # the site's code intensity, marked on the curves [m/s²]
//! duration = 8.0                   # optional: the time histories stop here [s] (default: the base job's)
//! materials = ["../materials/a.toml", "../materials/b.toml"]   # optional law-file variants
//! [sweep.hunt]                     # adaptive intensities per record and material (sweep_hunt.rs;
//! first = 0.4                      # the default, each key defaulting to a share of code_level) ...
//! step = 0.4                       # m/s²
//! cap = 4.8
//! # intensities = [0.8, 1.6, 2.4]  # ... or a fixed grid [m/s²]
//! [[sweep.limit]]                  # the intensity at which a substructure's share of area with
//! group = "nave_vault"             # d_t > 0.5 passes `share`, per record (a hunt needs one)
//! share = 0.5
//! ```
//!
//! Each member replaces the record file of every `[[dynamics.ground_motion]]` of the base job by
//! its record, and multiplies each component's `scale` (relative: 0.3 for an EC8 combination) by
//! `s = I / IM(record)`, the record's intensity measure taken as written in its file. A material
//! variant replaces the `law_file` of every damage material of the base job.
use super::{ConfigError, FileError, Job, OutputConfig, RecordConfig, RecordFormat, Seg, Source};
use crate::seismic::Record;
use serde::Deserialize;
use std::path::{Path, PathBuf};

/// `[analysis]` of a sweep job.
#[derive(Clone, Debug, Deserialize, PartialEq, schemars::JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct SweepAnalysis {
    /// Always `"sweep"`.
    #[serde(rename = "type")]
    pub kind: String,
    /// The base job file, relative to the sweep job's folder.
    pub job: PathBuf,
    /// Ranks per group; each group runs one member at a time.
    #[serde(default = "one")]
    pub group_size: usize,
}

fn one() -> usize {
    1
}

fn yes() -> bool {
    true
}

fn default_threshold() -> f64 {
    0.5
}

/// The intensity measure a record is scaled by.
#[derive(Clone, Copy, Debug, Deserialize, PartialEq, Eq, serde::Serialize, schemars::JsonSchema)]
#[serde(rename_all = "snake_case")]
pub enum IntensityMeasure {
    /// Peak ground acceleration [m/s²].
    Pga,
    /// 5 %-damped spectral pseudo-acceleration at the period T₁ [m/s²].
    SaT1,
}

impl IntensityMeasure {
    /// The column name and axis label.
    pub fn label(self) -> &'static str {
        match self {
            IntensityMeasure::Pga => "PGA",
            IntensityMeasure::SaT1 => "Sa(T1)",
        }
    }

    /// Its tag in member names.
    pub fn file_tag(self) -> &'static str {
        match self {
            IntensityMeasure::Pga => "pga",
            IntensityMeasure::SaT1 => "sa",
        }
    }
}

/// `[[sweep.record]]`: a record file (scaled by the sweep, so no `scale` key).
#[derive(Clone, Debug, Deserialize, PartialEq, schemars::JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct SweepRecordConfig {
    /// The file, relative to the sweep job's folder.
    pub file: PathBuf,
    /// Its format.
    pub format: RecordFormat,
    /// Units of a column file.
    pub units: Option<String>,
    /// Time step of a one-column file [s].
    pub dt: Option<f64>,
}

/// `[[sweep.limit]]`: a damage level of one substructure.
#[derive(Clone, Debug, Deserialize, PartialEq, serde::Serialize, schemars::JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct LimitConfig {
    /// The substructure (a part's physical group of shells).
    pub group: String,
    /// The share of its area with d_t above `threshold`, in (0, 1].
    pub share: f64,
}

/// `[sweep]`.
#[derive(Clone, Debug, Deserialize, PartialEq, schemars::JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct SweepConfig {
    /// A record_set job's results folder.
    pub record_set: Option<PathBuf>,
    /// Record files.
    #[serde(default)]
    pub record: Vec<SweepRecordConfig>,
    /// Whether the record set must have passed its check.
    #[serde(default = "yes")]
    pub require_compatible: bool,
    /// The intensity measure.
    pub scale_by: IntensityMeasure,
    /// T₁ [s] for `sa_t1`.
    pub period: Option<f64>,
    /// A fixed grid of intensities [m/s²] (instead of the hunt).
    pub intensities: Option<Vec<f64>>,
    /// Adaptive intensities (the default, also without this table): hunt and fill.
    pub hunt: Option<super::HuntConfig>,
    /// The site's code level [m/s²], marked on the curves.
    pub code_level: Option<f64>,
    /// The time histories' duration [s] (default: the base job's).
    pub duration: Option<f64>,
    /// Law-file variants.
    #[serde(default)]
    pub materials: Vec<PathBuf>,
    /// The damage that counts as cracked (d_t and d_c above it), default 0.5.
    #[serde(default = "default_threshold")]
    pub threshold: f64,
    /// Damage levels whose intensity the summary gives.
    #[serde(default)]
    pub limit: Vec<LimitConfig>,
}

/// A sweep job file, as written.
#[derive(Clone, Debug, Deserialize, PartialEq, schemars::JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct SweepJobFile {
    /// A one-line description.
    pub title: Option<String>,
    /// `[analysis]`.
    pub analysis: SweepAnalysis,
    /// `[sweep]`.
    pub sweep: SweepConfig,
    /// Where results go.
    #[serde(default)]
    pub output: OutputConfig,
}

/// One record of the sweep: where it is, how to read it, and its intensity measure.
#[derive(Clone, Debug)]
pub struct SweepRecord {
    /// A short name (the file's stem), unique in the sweep.
    pub name: String,
    /// The file (absolute).
    pub file: PathBuf,
    /// Its format.
    pub format: RecordFormat,
    /// Units of a column file.
    pub units: Option<String>,
    /// Time step of a one-column file [s].
    pub dt: Option<f64>,
    /// The record as read (m/s²).
    pub record: Record,
    /// Its intensity measure as written in the file [m/s²].
    pub intensity: f64,
}

/// A material variant: a law file for every damage material, or the base job's own laws.
#[derive(Clone, Debug, PartialEq)]
pub struct Variant {
    /// A short name: `base`, or the law file's stem.
    pub name: String,
    /// The law file (absolute), `None` for the base job's.
    pub law_file: Option<PathBuf>,
}

/// A loaded, validated sweep job.
pub struct SweepJob {
    /// The file and its text.
    pub source: Source,
    /// What it says.
    pub spec: SweepJobFile,
    /// The base job file (absolute).
    pub base_file: PathBuf,
    /// The base job, loaded and checked.
    pub base: Job,
    /// The base job's text (members are derived from it).
    pub base_text: String,
    /// The records.
    pub records: Vec<SweepRecord>,
    /// The material variants (at least one).
    pub variants: Vec<Variant>,
    /// The results folder.
    pub output_dir: PathBuf,
    /// The intensities: a grid or the hunt's rules.
    pub plan: super::Plan,
}

fn at(keys: &[&str]) -> Vec<Seg> {
    std::iter::once("sweep").chain(keys.iter().copied()).map(Seg::key).collect()
}

impl SweepJob {
    /// Parses and checks the job in `source` (read from `path`): the base job is loaded, every
    /// record read and measured, every variant's law file read.
    pub(super) fn from_source(source: Source, path: &Path) -> Result<SweepJob, ConfigError> {
        let spec: SweepJobFile = source.deserialize()?;
        // Absolute: the members' job files live in another folder.
        let folder = path.parent().map(Path::to_path_buf).unwrap_or_default();
        let folder = absolute(&folder);
        let (period, plan) = check_keys(&source, &spec)?;
        let (base_file, base_text, base) = load_base(&source, &spec, &folder)?;
        let records = read_records(&source, &spec.sweep, &folder, &base, period)?;
        let variants = read_variants(&source, &spec.sweep, &folder, &base)?;
        let output_dir = absolute(&super::output_dir(path, &spec.output));
        Ok(SweepJob { source, spec, base_file, base, base_text, records, variants, output_dir, plan })
    }

    /// The scale factor on the record (as written) for intensity `x`.
    pub fn factor(&self, record: &SweepRecord, x: f64) -> f64 {
        x / record.intensity
    }
}

/// The `[analysis]` and `[sweep]` keys checked; the period of `sa_t1` scaling and the intensities.
fn check_keys(source: &Source, spec: &SweepJobFile) -> Result<(Option<f64>, super::Plan), ConfigError> {
    let c = &spec.sweep;
    let err = |keys: &[&str], msg: String| source.error_at(&at(keys), msg);
    if spec.analysis.group_size == 0 {
        return Err(source.error_at(
            &[Seg::key("analysis"), Seg::key("group_size")],
            "expected at least 1 rank per group".to_string(),
        ));
    }
    let plan = super::sweep_hunt::check_plan(source, c)?;
    let period = match (c.scale_by, c.period) {
        (IntensityMeasure::SaT1, None) => {
            return Err(err(&["period"], "scale_by = \"sa_t1\" needs period = T1 [s]".into()))
        }
        (_, Some(t)) => Some(source.positive_finite(&at(&["period"]), t, "T1", "s")?),
        (_, None) => None,
    };
    if let Some(x) = c.code_level {
        source.positive_finite(&at(&["code_level"]), x, "code level", "m/s^2")?;
    }
    if let Some(d) = c.duration {
        source.positive_finite(&at(&["duration"]), d, "duration", "s")?;
    }
    if !(c.threshold > 0.0 && c.threshold < 1.0) {
        return Err(err(&["threshold"], format!("expected a damage threshold in (0, 1), got {}", c.threshold)));
    }
    for (i, l) in c.limit.iter().enumerate() {
        if !(l.share > 0.0 && l.share <= 1.0) {
            return Err(source.error_at(
                &[Seg::key("sweep"), Seg::key("limit"), Seg::Index(i), Seg::key("share")],
                format!("expected a share in (0, 1], got {}", l.share),
            ));
        }
    }
    Ok((period, plan))
}

/// The base job: its file, its text and the job, checked to be a time history with records and
/// the limits' groups.
fn load_base(source: &Source, spec: &SweepJobFile, folder: &Path) -> Result<(PathBuf, String, Job), ConfigError> {
    let c = &spec.sweep;
    let base_at = [Seg::key("analysis"), Seg::key("job")];
    let base_file = super::resolve(folder, &spec.analysis.job);
    let base_text = std::fs::read_to_string(&base_file)
        .map_err(|e| source.error_at(&base_at, format!("cannot read the base job {}: {e}", base_file.display())))?;
    let base = Job::load(&base_file).map_err(|e| source.error_at(&base_at, format!("the base job: {e}")))?;
    use super::AnalysisConfig as A;
    if !matches!(base.spec.analysis, A::TimeHistory | A::SeismicAssessment(_)) {
        return Err(source.error_at(
            &base_at,
            format!("the base job {} must be a time_history or seismic_assessment job", base_file.display()),
        ));
    }
    let dynamics =
        base.spec.dynamics.as_ref().ok_or_else(|| source.error_at(&base_at, "the base job has no [dynamics]"))?;
    if dynamics.ground_motion.iter().any(|g| g.record.is_none()) {
        return Err(source.error_at(&base_at, "every [[dynamics.ground_motion]] of the base job must name a record"));
    }
    if limit_group_missing(&base, c) {
        let names: Vec<&str> = base.spec.parts.iter().map(|p| p.group.as_str()).collect();
        let i = c.limit.iter().position(|l| !names.contains(&l.group.as_str())).unwrap_or(0);
        return Err(source.error_at(
            &[Seg::key("sweep"), Seg::key("limit"), Seg::Index(i), Seg::key("group")],
            format!("no part of the base job is group '{}'; its parts: {}", c.limit[i].group, names.join(", ")),
        ));
    }
    Ok((base_file, base_text, base))
}

/// The records of `[sweep] record_set` and `[[sweep.record]]`, read, long enough and with their
/// intensity; each named after its file, unique.
fn read_records(
    source: &Source,
    c: &SweepConfig,
    folder: &Path,
    base: &Job,
    period: Option<f64>,
) -> Result<Vec<SweepRecord>, ConfigError> {
    let err = |keys: &[&str], msg: String| source.error_at(&at(keys), msg);
    let dynamics = base.spec.dynamics.as_ref().expect("load_base checked [dynamics]");
    let mut listed: Vec<(PathBuf, RecordConfig, Vec<Seg>)> = Vec::new();
    if let Some(dir) = &c.record_set {
        let dir = super::resolve(folder, dir);
        for (file, rc) in
            read_record_set(&dir, c.require_compatible).map_err(|e| err(&["record_set"], e.to_string()))?
        {
            listed.push((file, rc, at(&["record_set"])));
        }
    }
    for (i, r) in c.record.iter().enumerate() {
        let file = super::resolve(folder, &r.file);
        let rc = RecordConfig {
            file: Some(file.clone()),
            format: Some(r.format),
            units: r.units.clone(),
            dt: r.dt,
            synthetic: None,
            scale: 1.0,
        };
        listed.push((file, rc, vec![Seg::key("sweep"), Seg::key("record"), Seg::Index(i), Seg::key("file")]));
    }
    if listed.is_empty() {
        return Err(err(
            &[],
            "the sweep has no record: give record_set = <a record_set job's results> or [[sweep.record]]".into(),
        ));
    }
    let duration = c.duration.unwrap_or(dynamics.duration);
    let mut out: Vec<SweepRecord> = Vec::new();
    for (file, rc, key) in listed {
        // A [[sweep.record]]'s own keys (units, dt) where the reader names one; the
        // record_set key for a record of a set.
        let keys = |k: &str| {
            let mut p = key.clone();
            if matches!(p.get(1), Some(Seg::Key(s)) if s == "record") {
                p.pop();
                p.push(Seg::key(k));
            }
            p
        };
        let record = super::record::read_record(source, folder, &rc, &keys)?;
        record.require_duration(duration).map_err(|e| {
            source.error_at(&key, format!("{}: {e} (the sweep's duration is {duration} s)", file.display()))
        })?;
        let intensity = match c.scale_by {
            IntensityMeasure::Pga => crate::seismic::pga(&record),
            IntensityMeasure::SaT1 => sa_at(&record, period.unwrap_or(1.0)),
        };
        crate::bounds::positive(intensity).map_err(|b| {
            source.error_at(&key, format!("{}: its {} cannot be scaled: {b}", file.display(), c.scale_by.label()))
        })?;
        let stem = file.file_stem().map_or_else(|| "record".into(), |s| s.to_string_lossy().into_owned());
        let mut name = stem.clone();
        let mut k = 2;
        while out.iter().any(|r| r.name == name) {
            name = format!("{stem}-{k}");
            k += 1;
        }
        out.push(SweepRecord {
            name,
            file,
            format: rc.format.unwrap_or(RecordFormat::TwoColumn),
            units: rc.units,
            dt: rc.dt,
            record,
            intensity,
        });
    }
    Ok(out)
}

/// The material variants of `[sweep] materials` (one, "base", without).
fn read_variants(source: &Source, c: &SweepConfig, folder: &Path, base: &Job) -> Result<Vec<Variant>, ConfigError> {
    let err = |keys: &[&str], msg: String| source.error_at(&at(keys), msg);
    let mut variants = Vec::new();
    if c.materials.is_empty() {
        variants.push(Variant { name: "base".into(), law_file: None });
    } else {
        let has_law_file =
            base.spec.materials.values().any(|m| matches!(m, super::MaterialConfig::Damage(d) if d.law_file.is_some()));
        if !has_law_file {
            return Err(err(
                &["materials"],
                "the base job has no damage material with a law_file for the variants to replace".into(),
            ));
        }
        for (i, p) in c.materials.iter().enumerate() {
            let file = super::resolve(folder, p);
            super::read_law_file(&file).map_err(|e| {
                source.error_at(
                    &[Seg::key("sweep"), Seg::key("materials"), Seg::Index(i)],
                    format!("{}: {e}", file.display()),
                )
            })?;
            let stem = file.file_stem().map_or_else(|| format!("variant-{i}"), |s| s.to_string_lossy().into_owned());
            let name = if variants.iter().any(|v: &Variant| v.name == stem) { format!("{stem}-{i}") } else { stem };
            variants.push(Variant { name, law_file: Some(file) });
        }
    }
    Ok(variants)
}

/// `p` as an absolute path (the empty path: the working folder).
fn absolute(p: &Path) -> PathBuf {
    let p = if p.as_os_str().is_empty() { Path::new(".") } else { p };
    crate::io::normalize(&std::path::absolute(p).unwrap_or_else(|_| p.to_path_buf()))
}

fn limit_group_missing(base: &Job, c: &SweepConfig) -> bool {
    c.limit.iter().any(|l| !base.spec.parts.iter().any(|p| p.group == l.group))
}

/// The 5 %-damped pseudo-acceleration of `record` at period `t` [m/s²].
pub fn sa_at(record: &Record, t: f64) -> f64 {
    crate::seismic::response_spectrum(record, &[t], 0.05).map_or(f64::NAN, |s| s.sa[0])
}

/// The records of a record_set job's results folder (its `summary.json`): each file with the
/// reading of a two-column file in m/s². With `require_compatible`, a set whose check failed is
/// an error.
fn read_record_set(dir: &Path, require_compatible: bool) -> Result<Vec<(PathBuf, RecordConfig)>, FileError> {
    let summary = dir.join("summary.json");
    let invalid = |reason: String| FileError::Invalid { file: summary.clone(), reason };
    let text = std::fs::read_to_string(&summary).map_err(|e| invalid(format!("{e} (run the record_set job first)")))?;
    let v: serde_json::Value =
        serde_json::from_str(&text).map_err(|e| invalid(format!("not a record set's summary: {e}")))?;
    let records = v["records"].as_array().ok_or_else(|| invalid("no \"records\" list".into()))?;
    if records.is_empty() {
        return Err(invalid("the record set is empty".into()));
    }
    if require_compatible && v["check"]["passed"].as_bool() != Some(true) {
        return Err(FileError::IncompatibleRecordSet { dir: dir.to_path_buf() });
    }
    records
        .iter()
        .map(|r| {
            let f = r["file"].as_str().ok_or_else(|| invalid("a record without \"file\"".into()))?;
            let file = dir.join(f);
            let rc = RecordConfig {
                file: Some(file.clone()),
                format: Some(RecordFormat::TwoColumn),
                units: Some("m/s2".into()),
                dt: None,
                synthetic: None,
                scale: 1.0,
            };
            Ok((file, rc))
        })
        .collect()
}
