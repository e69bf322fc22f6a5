//! Which kind of job a file describes, read from `[analysis] type` before the whole file is
//! parsed into that kind's typed structure.
use super::source::{Seg, Source};
use super::ConfigError;
use toml::de::{DeTable, DeValue};

/// The kinds of job, each with its own typed job file.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum JobKind {
    /// A finite-element model of a structure (`linear_static`, ...): see [`super::StructuralJobFile`].
    Structural,
    /// One point of the damage law along a strain path: see [`super::MaterialPointJobFile`].
    MaterialPoint,
    /// A DEM virtual test on a batch of samples: see [`super::DemJobFile`].
    Dem,
    /// Response spectra of a ground motion: see [`super::SpectrumJobFile`].
    Spectrum,
    /// DEM calibration and damage-law identification: see [`super::IdentifyJobFile`].
    Identify,
    /// A record set compatible with a Eurocode 8 spectrum: see [`super::RecordSetJobFile`].
    RecordSet,
    /// An intensity sweep over records and materials: see [`super::SweepJobFile`].
    Sweep,
}

/// Every `[analysis] type` a job file may give, with its kind.
pub const ANALYSIS_TYPES: &[(&str, JobKind)] = &[
    ("linear_static", JobKind::Structural),
    ("modal", JobKind::Structural),
    ("modal_updating", JobKind::Structural),
    ("static_nonlinear", JobKind::Structural),
    ("time_history", JobKind::Structural),
    ("seismic_assessment", JobKind::Structural),
    ("material_point", JobKind::MaterialPoint),
    ("dem", JobKind::Dem),
    ("spectrum", JobKind::Spectrum),
    ("identification", JobKind::Identify),
    ("record_set", JobKind::RecordSet),
    ("sweep", JobKind::Sweep),
];

/// The kind of the job in `src`.
pub fn job_kind(src: &Source) -> Result<JobKind, ConfigError> {
    let names = || ANALYSIS_TYPES.iter().map(|(n, _)| *n).collect::<Vec<_>>().join(", ");
    let root =
        DeTable::parse(&src.text).map_err(|e| src.error_at_span(e.span(), &[], e.message().trim().to_string()))?;
    let analysis = root.get_ref().iter().find(|(k, _)| k.get_ref().as_ref() == "analysis");
    let Some((_, analysis)) = analysis else {
        return Err(
            src.error_at(&[], format!("the job has no [analysis] table; add one with type = one of: {}", names()))
        );
    };
    let DeValue::Table(t) = analysis.get_ref() else {
        return Err(src.error_at(&[Seg::key("analysis")], "expected a table [analysis]"));
    };
    let ty = t.iter().find(|(k, _)| k.get_ref().as_ref() == "type").map(|(_, v)| v.get_ref());
    let path = [Seg::key("analysis"), Seg::key("type")];
    match ty {
        Some(DeValue::String(s)) => {
            ANALYSIS_TYPES.iter().find(|(n, _)| *n == s.as_ref()).map(|(_, k)| *k).ok_or_else(|| {
                src.error_at(&path, format!("unknown analysis type '{s}', expected one of: {}", names()))
            })
        }
        Some(_) => Err(src.error_at(&path, format!("expected a string, one of: {}", names()))),
        None => Err(src.error_at(&[Seg::key("analysis")], format!("[analysis] needs type = one of: {}", names()))),
    }
}
