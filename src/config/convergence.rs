//! `[dynamics] convergence`: the band a convergence study measured for this job's settings, so
//! that the damage shares a run reports carry their numerical uncertainty.
//!
//! The file is `scripts/convergence.py`'s `band.json` (committed for the church as
//! `jobs/church-convergence.json`). For each loading it ran (the job's own record, and a stronger
//! one), it holds, per substructure, how far the share of area with d_t > 0.5 moved:
//!
//! ```text
//!   time_step = |share(dt) − share(dt/4)|          the job's step against a converged reference
//!   ranks     = |share(1 rank) − share(2 ranks)|   round-off and the partition
//! ```
//!
//! A run reports `time_step + ranks` as its band when the study's settings are its own (time
//! step, mesh, law files, damage-increment control) and one of the study's loadings is at least
//! as strong as its own ground motion (the largest PGA over the components): a band measured under
//! stronger shaking bounds a weaker one's, since damage, and the error of its integration, grows
//! with the shaking. Otherwise it says why no band applies. A material variant of a measured law
//! (`<stem>-variant-<k>.toml`, the same fit on half of the virtual samples) counts as that law,
//! so that a sweep's members carry the band measured on the main law.
use super::FileError;
use serde::{Deserialize, Serialize};
use std::collections::BTreeMap;
use std::path::{Path, PathBuf};

/// The law file a variant was fitted after: `<stem>-variant-<k>.toml` is `<stem>.toml` (the
/// identification's variants are the same fit on halves of the samples, named so).
fn main_law(name: &str) -> String {
    if let Some((stem, k)) = name.strip_suffix(".toml").and_then(|s| s.rsplit_once("-variant-")) {
        if !k.is_empty() && k.chars().all(|c| c.is_ascii_digit()) {
            return format!("{stem}.toml");
        }
    }
    name.to_string()
}

/// A convergence study's band file.
#[derive(Clone, Debug, Deserialize, PartialEq, schemars::JsonSchema)]
pub struct ConvergenceBand {
    /// The file (set when read).
    #[serde(skip)]
    pub file: PathBuf,
    /// When it was measured.
    #[serde(default)]
    pub date: String,
    /// The settings it holds for.
    pub settings: BandSettings,
    /// Per loading (`code`, `member`): its bands.
    pub loadings: BTreeMap<String, LoadingBand>,
}

/// The settings a band was measured with.
#[derive(Clone, Debug, Deserialize, PartialEq, schemars::JsonSchema)]
pub struct BandSettings {
    /// `[dynamics] dt` [s].
    pub dt: f64,
    /// The mesh file's name.
    pub mesh: String,
    /// The damage law files' names.
    pub law_files: Vec<String>,
    /// `[dynamics] max_damage_increment`.
    pub max_damage_increment: f64,
    /// `[dynamics] integration` (`implicit`, the default of files written before the key, or
    /// `implex`).
    #[serde(default = "implicit")]
    pub integration: String,
    /// `[dynamics] implex_corrections` (0, the default of files written before the key).
    #[serde(default)]
    pub implex_corrections: usize,
}

fn implicit() -> String {
    "implicit".to_string()
}

/// The band of one loading.
#[derive(Clone, Debug, Deserialize, PartialEq, schemars::JsonSchema)]
pub struct LoadingBand {
    /// The largest PGA over the ground-motion components [m/s²].
    pub pga: f64,
    /// The analysed duration [s].
    pub duration: f64,
    /// Per substructure (physical group).
    pub groups: BTreeMap<String, GroupBand>,
    /// |peak drift ratio at dt − at dt/4| / at dt/4.
    pub peak_drift_ratio: f64,
}

/// Share differences of one substructure, as fractions of its area.
#[derive(Clone, Copy, Debug, Deserialize, PartialEq, schemars::JsonSchema)]
pub struct GroupBand {
    /// |share(dt) − share(dt/4)|.
    pub time_step: f64,
    /// |share(1 rank) − share(2 ranks)| (none when not measured).
    pub ranks: Option<f64>,
}

impl GroupBand {
    /// The band a run reports: both parts.
    pub fn total(&self) -> f64 {
        self.time_step + self.ranks.unwrap_or(0.0)
    }
}

/// What a run says about its band (in `summary.json`).
#[derive(Clone, Debug, Default, PartialEq, Serialize, Deserialize, schemars::JsonSchema)]
pub struct BandReport {
    /// The band file.
    pub file: String,
    /// The study's loading whose band applies, when one does.
    pub loading: Option<String>,
    /// The PGA of the study's loading that covers the run [m/s²] (none: none does).
    pub measured_pga: Option<f64>,
    /// The run's PGA [m/s²].
    pub run_pga: f64,
    /// Relative band of the peak drift ratio (when a loading applies).
    pub peak_drift_ratio: Option<f64>,
    /// Why no band applies (settings that differ, or shaking stronger than measured).
    pub not_applicable: Vec<String>,
}

impl ConvergenceBand {
    /// Reads and checks `file`; the error says what is wrong.
    pub fn read(file: &Path) -> Result<ConvergenceBand, FileError> {
        let text = std::fs::read_to_string(file).map_err(|e| FileError::Read {
            what: "convergence band file",
            file: file.to_path_buf(),
            reason: e.to_string(),
        })?;
        let invalid = |reason: String| FileError::Invalid { file: file.to_path_buf(), reason };
        let mut b: ConvergenceBand = serde_json::from_str(&text)
            .map_err(|e| invalid(format!("{e} (expected the band.json that scripts/convergence.py writes)")))?;
        for (name, l) in &b.loadings {
            let bad = |what: &str| invalid(format!("loading {name}: {what}"));
            crate::bounds::positive(l.pga).map_err(|b| bad(&format!("pga [m/s²]: {b}")))?;
            for (g, v) in &l.groups {
                for (k, x) in [("time_step", Some(v.time_step)), ("ranks", v.ranks)] {
                    let share_difference = |b| bad(&format!("group {g}: {k} share difference: {b}"));
                    x.map(crate::bounds::non_negative).transpose().map_err(share_difference)?;
                }
            }
        }
        b.file = file.to_path_buf();
        Ok(b)
    }

    /// The report of a run with the settings `run` (file names as the study's: the mesh's and
    /// the law files' names) under ground motion of largest PGA `pga`.
    pub fn report(&self, run: &BandSettings, pga: f64) -> BandReport {
        let s = &self.settings;
        let mut why = Vec::new();
        let (dt, max_damage_increment) = (run.dt, run.max_damage_increment);
        if (dt - s.dt).abs() > 1e-12 * s.dt {
            why.push(format!("dt {dt} s, measured at {} s", s.dt));
        }
        if run.mesh != s.mesh {
            why.push(format!("mesh {}, measured on {}", run.mesh, s.mesh));
        }
        if run.integration != s.integration {
            why.push(format!("integration {}, measured with {}", run.integration, s.integration));
        }
        if run.implex_corrections != s.implex_corrections {
            why.push(format!("implex_corrections {}, measured with {}", run.implex_corrections, s.implex_corrections));
        }
        let mut laws: Vec<String> = run.law_files.iter().map(|p| main_law(p)).collect();
        laws.sort();
        laws.dedup();
        let mut measured = s.law_files.clone();
        measured.sort();
        if laws != measured {
            why.push(format!("law files {laws:?}, measured with {measured:?}"));
        }
        if (max_damage_increment - s.max_damage_increment).abs() > 1e-12 {
            why.push(format!("max_damage_increment {max_damage_increment}, measured with {}", s.max_damage_increment));
        }
        // The weakest measured loading at least as strong as the run's (1e-6 relative: the
        // same record scaled the same way).
        let loading = self
            .loadings
            .iter()
            .filter(|(_, l)| l.pga >= pga * (1.0 - 1e-6))
            .min_by(|a, b| a.1.pga.total_cmp(&b.1.pga));
        if loading.is_none() {
            let top = self.loadings.values().map(|l| l.pga).fold(0.0, f64::max);
            why.push(format!("PGA {pga:.4} m/s², stronger than the strongest measured ({top:.4} m/s²)"));
        }
        let applies = why.is_empty();
        BandReport {
            file: self.file.display().to_string(),
            loading: loading.filter(|_| applies).map(|(n, _)| n.clone()),
            measured_pga: loading.map(|(_, l)| l.pga),
            run_pga: pga,
            peak_drift_ratio: loading.filter(|_| applies).map(|(_, l)| l.peak_drift_ratio),
            not_applicable: why,
        }
    }

    /// The band of `group`'s share under the loading `report` names (none when none applies or
    /// the group was not measured).
    pub fn group_band(&self, report: &BandReport, group: &str) -> Option<f64> {
        let l = self.loadings.get(report.loading.as_deref()?)?;
        l.groups.get(group).map(GroupBand::total)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn band() -> ConvergenceBand {
        let text = r#"{"settings": {"dt": 0.02, "mesh": "church.msh", "law_files": ["law.toml"], "max_damage_increment": 1.0},
            "loadings": {"code": {"pga": 0.45, "duration": 22.0, "peak_drift_ratio": 0.01,
                                  "groups": {"vault": {"time_step": 0.004, "ranks": 0.001}}},
                         "member": {"pga": 2.4, "duration": 4.0, "peak_drift_ratio": 0.05,
                                    "groups": {"vault": {"time_step": 0.015, "ranks": null}}}}}"#;
        serde_json::from_str(text).unwrap()
    }

    /// A run's settings (the file names as the study writes them).
    fn run(dt: f64, mesh: &str, laws: &[&str], max_damage_increment: f64, integration: &str) -> BandSettings {
        let law_files = laws.iter().map(|s| s.to_string()).collect();
        let integration = integration.into();
        BandSettings { dt, mesh: mesh.into(), law_files, max_damage_increment, integration, implex_corrections: 0 }
    }

    #[test]
    fn the_weakest_loading_at_least_as_strong_applies() {
        let b = band();
        let laws = ["law.toml", "law.toml"];
        let r = b.report(&run(0.02, "church.msh", &laws, 1.0, "implicit"), 0.45);
        assert_eq!(r.loading.as_deref(), Some("code"), "{r:?}");
        // time_step + ranks of the code loading (the figures above)
        assert!((b.group_band(&r, "vault").unwrap() - 0.005).abs() < 1e-15);
        assert_eq!(b.group_band(&r, "tower"), None);
        let r = b.report(&run(0.02, "church.msh", &laws, 1.0, "implicit"), 1.6);
        assert_eq!(r.loading.as_deref(), Some("member"));
        assert!((b.group_band(&r, "vault").unwrap() - 0.015).abs() < 1e-15);
    }

    #[test]
    fn other_settings_or_stronger_shaking_get_no_band_and_say_why() {
        let b = band();
        let r = b.report(&run(0.01, "fine.msh", &["law.toml"], 0.1, "implex"), 3.0);
        assert_eq!(r.loading, None);
        assert_eq!(r.not_applicable.len(), 5, "{:?}", r.not_applicable);
        assert!(r.not_applicable[0].contains("dt 0.01"));
        assert!(r.not_applicable[2].contains("integration implex, measured with implicit"));
        assert!(r.not_applicable[4].contains("stronger than the strongest measured (2.4000"));
        let corrected =
            BandSettings { implex_corrections: 4, ..run(0.02, "church.msh", &["law.toml"], 1.0, "implicit") };
        let r = b.report(&corrected, 0.45);
        assert_eq!(r.loading, None);
        assert!(r.not_applicable[0].contains("implex_corrections 4, measured with 0"), "{:?}", r.not_applicable);
        let variant = ["law-variant-2.toml"];
        assert_eq!(
            b.report(&run(0.02, "church.msh", &variant, 1.0, "implicit"), 2.0).loading.as_deref(),
            Some("member")
        );
        let r = b.report(&run(0.02, "church.msh", &["other.toml"], 1.0, "implicit"), 0.45);
        assert_eq!(r.loading, None);
        assert!(r.not_applicable[0].contains("law files"), "{:?}", r.not_applicable);
    }

    #[test]
    fn a_malformed_file_is_an_error_that_names_it() {
        let dir = std::env::temp_dir().join(format!("band-{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        let f = dir.join("band.json");
        std::fs::write(&f, "{\"settings\": {}}").unwrap();
        let e = ConvergenceBand::read(&f).unwrap_err().to_string();
        assert!(e.contains("band.json") && e.contains("scripts/convergence.py"), "{e}");
        std::fs::write(&f, band_text_with_pga(-1.0)).unwrap();
        let e = ConvergenceBand::read(&f).unwrap_err().to_string();
        assert!(e.contains("loading code: pga [m/s²]: expected > 0, got -1"), "{e}");
        let e = ConvergenceBand::read(&dir.join("missing.json")).unwrap_err().to_string();
        assert!(e.contains("cannot read convergence band file"), "{e}");
        std::fs::remove_dir_all(&dir).ok();
    }

    fn band_text_with_pga(pga: f64) -> String {
        format!(
            r#"{{"settings": {{"dt": 0.02, "mesh": "m.msh", "law_files": [], "max_damage_increment": 1.0}},
                "loadings": {{"code": {{"pga": {pga}, "duration": 1.0, "peak_drift_ratio": 0.0, "groups": {{}}}}}}}}"#
        )
    }
}
