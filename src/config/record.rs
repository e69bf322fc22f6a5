//! A ground-motion record named in a job file (`[record]` of a spectrum job, each
//! `[[dynamics.ground_motion]]` of a time history): read, checked and scaled at load, with errors
//! located at the job file's keys.
use super::{ConfigError, RecordConfig, RecordFormat, Seg, Source};
use crate::seismic::{self as sm, Record};
use std::path::Path;

/// Reads the record `r` describes (a file relative to `folder`, or a built-in synthetic one)
/// and scales it; `at(key)` is the key path of one of the record's keys, for error locations.
pub(super) fn read_record(
    src: &Source,
    folder: &Path,
    r: &RecordConfig,
    at: &dyn Fn(&str) -> Vec<Seg>,
) -> Result<Record, ConfigError> {
    let record = match (&r.file, &r.synthetic) {
        (Some(_), Some(_)) | (None, None) => {
            let mut p = at("file");
            p.pop();
            return Err(src.error_at(&p, "give either file (with format) or synthetic = \"vallorcine_like\""));
        }
        (None, Some(name)) => match name.as_str() {
            "vallorcine_like" => sm::vallorcine_like_synthetic(),
            other => {
                return Err(src.error_at(
                    &at("synthetic"),
                    format!("unknown synthetic record '{other}', expected vallorcine_like"),
                ))
            }
        },
        (Some(f), None) => {
            let file = super::resolve(folder, f);
            if !file.is_file() {
                return Err(src.error_at(&at("file"), format!("record file {} does not exist", file.display())));
            }
            let units = || -> Result<sm::AccelUnit, ConfigError> {
                let u = r.units.as_deref().ok_or_else(|| {
                    src.error_at(&at("units"), "a column file needs units = \"g\", \"m/s2\" or \"cm/s2\"")
                })?;
                sm::AccelUnit::parse(u).ok_or_else(|| {
                    src.error_at(&at("units"), format!("unknown units '{u}', expected g, m/s2 or cm/s2"))
                })
            };
            let read = match r.format {
                None => return Err(src.error_at(&at("file"), "give the format: at2, esm, two_column or one_column")),
                Some(RecordFormat::At2) => sm::read_at2(&file),
                Some(RecordFormat::Esm) => sm::read_esm(&file),
                Some(RecordFormat::TwoColumn) => sm::read_two_column(&file, units()?, sm::DEFAULT_DT_TOLERANCE),
                Some(RecordFormat::OneColumn) => {
                    let dt = r.dt.ok_or_else(|| src.error_at(&at("dt"), "a one-column file needs dt [s]"))?;
                    sm::read_one_column(&file, dt, units()?)
                }
            };
            read.map_err(|e| src.error_at(&at("file"), e.to_string()))?
        }
    };
    record.scaled(r.scale).map_err(|e| src.error_at(&at("scale"), e.to_string()))
}
