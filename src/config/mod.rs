//! Job files: TOML through serde into typed structs, validated once at load.
//!
//! Every error names the file, the line and column, the key and what was expected
//! ([`ConfigError`]). Relative paths resolve against the job file's folder.
//!
//! **Cycles.** The files are one concept, the job file, split by table: `job.rs` holds the whole
//! file and `analysis.rs` its `[analysis]` table, which names the job's DOFs and loads; `validate.rs`
//! checks the structural tables and hands the assessment's stages to `assessment.rs`, whose
//! updating check is `validate.rs`'s.
mod analysis;
mod assessment;
mod convergence;
mod dem;
mod drift;
mod dynamics;
mod error;
mod identify;
mod identify_job;
mod job;
mod keys;
mod keys_render;
mod kind;
mod material_point;
pub mod plausible;
mod record;
mod record_set;
mod source;
mod spectrum;
mod sweep;
mod sweep_hunt;
mod sweep_member;
mod tagged;
mod validate;

pub use analysis::*;
pub use assessment::*;
pub use convergence::{BandReport, BandSettings, ConvergenceBand};
pub use dem::*;
pub use drift::{DriftConfig, DriftLevels, DEFAULT_LEVEL_TOLERANCE};
pub use dynamics::*;
pub use error::{ConfigError, FileError, Location};
pub use identify::*;
pub use identify_job::IdentifyJob;
pub use job::*;
pub use keys::{all_keys, keys_of, kind_named, KeyRow, KeyTable, KindKeys, KIND_NAMES};
pub use keys_render::{markdown as keys_markdown, text as keys_text, REGENERATE as KEYS_REGENERATE};
pub use kind::{job_kind, JobKind, ANALYSIS_TYPES};
pub use material_point::*;
pub use record_set::*;
pub use source::{format_path, Seg, Source};
pub use spectrum::*;
pub use sweep::*;
pub use sweep_hunt::{HuntConfig, HuntRules, Intensities, Plan, LEVEL_RESOLUTION};
pub use sweep_member::Member;

use crate::io::normalize;
use std::path::{Path, PathBuf};

/// A loaded, validated job.
pub struct Job {
    /// The file and its text (to locate keys in later, mesh-dependent checks).
    pub source: Source,
    /// The structural job it describes.
    pub spec: StructuralJobFile,
    /// The mesh file, resolved against the job file's folder.
    pub mesh_file: PathBuf,
    /// The results folder, resolved against the job file's folder.
    pub output_dir: PathBuf,
    /// PETSc options of `[solver.petsc]`, as (`-key`, value) pairs.
    pub petsc_options: Vec<(String, String)>,
}

impl Job {
    /// Reads, parses and validates a structural job file.
    pub fn load(path: &Path) -> Result<Job, ConfigError> {
        match load_job(path)? {
            AnyJob::Structural(job) => Ok(job),
            AnyJob::MaterialPoint(j) => {
                Err(j.source.error_at(&[Seg::key("analysis"), Seg::key("type")], "expected a structural analysis here"))
            }
            AnyJob::Spectrum(j) => {
                Err(j.source.error_at(&[Seg::key("analysis"), Seg::key("type")], "expected a structural analysis here"))
            }
            AnyJob::Dem(j) => {
                Err(j.source.error_at(&[Seg::key("analysis"), Seg::key("type")], "expected a structural analysis here"))
            }
            AnyJob::Identify(j) => {
                Err(j.source.error_at(&[Seg::key("analysis"), Seg::key("type")], "expected a structural analysis here"))
            }
            AnyJob::RecordSet(j) => {
                Err(j.source.error_at(&[Seg::key("analysis"), Seg::key("type")], "expected a structural analysis here"))
            }
            AnyJob::Sweep(j) => {
                Err(j.source.error_at(&[Seg::key("analysis"), Seg::key("type")], "expected a structural analysis here"))
            }
        }
    }

    fn from_source(source: Source, path: &Path) -> Result<Job, ConfigError> {
        let spec: StructuralJobFile = source.deserialize().map_err(|e| tagged::refine(&source, e))?;
        validate::validate_structural(&source, &spec)?;
        let folder = path.parent().map(Path::to_path_buf).unwrap_or_default();
        let mesh_file = resolve(&folder, &spec.mesh.file);
        let mut spec = spec;
        for (name, m) in spec.materials.iter_mut() {
            if let MaterialConfig::Damage(d) = m {
                if let Some(p) = &d.law_file {
                    let at = [Seg::key("materials"), Seg::Key(name.clone()), Seg::key("law_file")];
                    let file = resolve(&folder, p);
                    d.law = Some(read_law_file(&file).map_err(|e| source.error_at(&at, e.to_string()))?);
                    d.law_file = Some(file);
                }
            }
        }
        if let AnalysisConfig::StaticNonlinear(c) = &mut spec.analysis {
            if let Some(o) = c.control.as_mut().and_then(|c| c.overlay.as_mut()) {
                let file = resolve(&folder, &o.file);
                if !file.is_file() {
                    return Err(source.error_at(
                        &[Seg::key("analysis"), Seg::key("control"), Seg::key("overlay"), Seg::key("file")],
                        format!("overlay curve file {} does not exist", file.display()),
                    ));
                }
                o.file = file;
            }
        }
        let updating = match &mut spec.analysis {
            AnalysisConfig::ModalUpdating(u) => Some((u, vec![Seg::key("analysis")])),
            AnalysisConfig::SeismicAssessment(a) => {
                a.updating.as_mut().map(|u| (u, vec![Seg::key("analysis"), Seg::key("updating")]))
            }
            _ => None,
        };
        if let Some((u, base)) = updating {
            if let Some(p) = &u.target_shapes {
                let file = resolve(&folder, p);
                if !file.is_file() {
                    return Err(source.error_at(
                        &[base, vec![Seg::key("target_shapes")]].concat(),
                        format!("target shapes file {} does not exist", file.display()),
                    ));
                }
                u.target_shapes = Some(file);
            }
        }
        match (&spec.analysis, &mut spec.dynamics) {
            (AnalysisConfig::TimeHistory | AnalysisConfig::SeismicAssessment(_), Some(d)) => {
                dynamics::load_dynamics(&source, &folder, d)?;
                dynamics::check_stop_when(&source, &d.stop_when, &spec.parts)?;
            }
            (AnalysisConfig::TimeHistory, None) => {
                return Err(source
                    .error_at(&[Seg::key("analysis"), Seg::key("type")], "a time history needs a [dynamics] table"))
            }
            (_, Some(_)) => {
                return Err(source.error_at(
                    &[Seg::key("dynamics")],
                    "[dynamics] is read only by [analysis] type = \"time_history\" or \"seismic_assessment\"",
                ))
            }
            _ => {}
        }
        let output_dir = output_dir(path, &spec.output);
        let petsc_options = spec
            .solver
            .petsc
            .iter()
            .map(|(k, v)| {
                let value = match v {
                    toml::Value::String(s) => s.clone(),
                    other => other.to_string(),
                };
                (format!("-{}", k.trim_start_matches('-')), value)
            })
            .collect();
        Ok(Job { source, spec, mesh_file, output_dir, petsc_options })
    }

    /// The `Invalid` error for the key at `path` of this job file.
    pub fn error_at(&self, path: &[Seg], message: impl Into<String>) -> ConfigError {
        self.source.error_at(path, message)
    }
}

/// Any job, by kind. (One value per run: the variants' sizes do not matter.)
#[allow(clippy::large_enum_variant)]
pub enum AnyJob {
    /// A structural finite-element job.
    Structural(Job),
    /// A material-point job.
    MaterialPoint(MaterialPointJob),
    /// A DEM virtual test (a batch of samples).
    Dem(DemJob),
    /// Response spectra of a ground motion.
    Spectrum(SpectrumJob),
    /// An identification (DEM calibration, damage-law identification, or the chain).
    Identify(IdentifyJob),
    /// A record set compatible with a Eurocode 8 spectrum.
    RecordSet(RecordSetJob),
    /// An intensity sweep: many time histories of one model.
    Sweep(SweepJob),
}

/// A loaded, validated spectrum job: the record is read (and checked) at load.
pub struct SpectrumJob {
    /// The file and its text.
    pub source: Source,
    /// What it says.
    pub spec: SpectrumJobFile,
    /// The ground motion, scaled, in m/s².
    pub record: crate::seismic::Record,
    /// The results folder.
    pub output_dir: PathBuf,
}

impl SpectrumJob {
    fn from_source(source: Source, path: &Path) -> Result<SpectrumJob, ConfigError> {
        let spec: SpectrumJobFile = source.deserialize().map_err(|e| tagged::refine(&source, e))?;
        let a = &spec.analysis;
        if !(a.damping.is_finite() && a.damping >= 0.0 && a.damping < 1.0) {
            return Err(source.error_at(
                &[Seg::key("analysis"), Seg::key("damping")],
                format!("expected a damping ratio in [0, 1), got {}", a.damping),
            ));
        }
        let p = &a.periods;
        if !(p.min > 0.0 && p.max > p.min && p.count >= 2) {
            return Err(
                source.error_at(&[Seg::key("analysis"), Seg::key("periods")], "expected 0 < min < max and count >= 2")
            );
        }
        let r = &spec.record;
        let at = |k: &str| vec![Seg::key("record"), Seg::key(k)];
        let folder = path.parent().map(Path::to_path_buf).unwrap_or_default();
        let record = record::read_record(&source, &folder, r, &at)?;
        if let Some(e) = &spec.ec8 {
            source.positive_finite(&[Seg::key("ec8"), Seg::key("ag")], e.ag, "a_g", "m/s^2")?;
        }
        let output_dir = output_dir(path, &spec.output);
        Ok(SpectrumJob { source, spec, record, output_dir })
    }
}

/// A loaded, validated DEM job.
pub struct DemJob {
    /// The file and its text.
    pub source: Source,
    /// What it says.
    pub spec: DemJobFile,
    /// The lattice parameters (thickness from the sample).
    pub params: crate::dem::mechanics::MechParams,
    /// The results folder.
    pub output_dir: PathBuf,
}

impl DemJob {
    fn from_source(source: Source, path: &Path) -> Result<DemJob, ConfigError> {
        let spec: DemJobFile = source.deserialize().map_err(|e| tagged::refine(&source, e))?;
        if spec.analysis.samples == 0 {
            return Err(source.error_at(&[Seg::key("analysis"), Seg::key("samples")], "expected at least 1 sample"));
        }
        if spec.analysis.breaks_per_equilibrium == 0 {
            return Err(source.error_at(
                &[Seg::key("analysis"), Seg::key("breaks_per_equilibrium")],
                "expected at least 1 (1: one break per equilibrium, the exact algorithm)",
            ));
        }
        let minutes = spec.analysis.checkpoint_minutes;
        if !(minutes.is_finite() && minutes >= 0.0) {
            return Err(source.error_at(
                &[Seg::key("analysis"), Seg::key("checkpoint_minutes")],
                "expected minutes >= 0 (0: no checkpoints)",
            ));
        }
        spec.sample.validate().map_err(|e| source.error_at(&[Seg::key("sample")], e.to_string()))?;
        spec.test.validate().map_err(|e| {
            // At the offending key when the file has it, else at [test].
            let mut at = vec![Seg::key("test")];
            if let crate::dem::solver::DemError::InvalidParameter { field, .. } = &e {
                let mut k = at.clone();
                k.push(Seg::key(field));
                if source.span_of(&k).is_some() {
                    at = k;
                }
            }
            source.error_at(&at, e.to_string())
        })?;
        let params = spec.mechanics.validated_params(spec.sample.thickness, &source)?;
        let output_dir = output_dir(path, &spec.output);
        Ok(DemJob { source, spec, params, output_dir })
    }
}

/// Reads a job file, finds its kind from `[analysis] type`, parses and validates it.
pub fn load_job(path: &Path) -> Result<AnyJob, ConfigError> {
    let source = Source::read(path)?;
    Ok(match job_kind(&source)? {
        JobKind::Structural => AnyJob::Structural(Job::from_source(source, path)?),
        JobKind::MaterialPoint => AnyJob::MaterialPoint(MaterialPointJob::from_source(source, path)?),
        JobKind::Dem => AnyJob::Dem(DemJob::from_source(source, path)?),
        JobKind::Spectrum => AnyJob::Spectrum(SpectrumJob::from_source(source, path)?),
        JobKind::Identify => AnyJob::Identify(IdentifyJob::from_source(source, path)?),
        JobKind::RecordSet => AnyJob::RecordSet(RecordSetJob::from_source(source, path)?),
        JobKind::Sweep => AnyJob::Sweep(SweepJob::from_source(source, path)?),
    })
}

/// A loaded, validated material-point job.
pub struct MaterialPointJob {
    /// The file and its text.
    pub source: Source,
    /// What it says.
    pub spec: MaterialPointJobFile,
    /// The law at the job's element size (regularization applied).
    pub law: crate::material::PointLaw,
    /// The results folder.
    pub output_dir: PathBuf,
}

impl MaterialPointJob {
    fn from_source(source: Source, path: &Path) -> Result<MaterialPointJob, ConfigError> {
        let spec: MaterialPointJobFile = source.deserialize().map_err(|e| tagged::refine(&source, e))?;
        let law = spec.material.for_element(spec.analysis.element_size).map_err(|e| {
            use crate::material::MaterialError as M;
            let at = match &e {
                M::NonFinite { quantity, .. } | M::NonPositive { quantity, .. } | M::OutOfRange { quantity, .. } => {
                    vec![Seg::key("material"), Seg::key(quantity)]
                }
                M::InvalidElementSize { .. } | M::ElementTooLarge { .. } => {
                    vec![Seg::key("analysis"), Seg::key("element_size")]
                }
            };
            source.error_at(&at, e.to_string())
        })?;
        let output_dir = output_dir(path, &spec.output);
        Ok(MaterialPointJob { source, spec, law, output_dir })
    }
}

/// Reads the damage law's parameters from a material file (its `[law]` table, as the
/// identification writes it; other tables, e.g. provenance, are ignored).
fn read_law_file(file: &Path) -> Result<crate::material::DamageParams, FileError> {
    const WHAT: &str = "material file";
    if !file.is_file() {
        return Err(FileError::Missing { what: WHAT, file: file.to_path_buf() });
    }
    let src = Source::read(file).map_err(|e| match e {
        ConfigError::Read { path, source } => FileError::Read { what: WHAT, file: path, reason: source.to_string() },
        other => FileError::Table { what: WHAT, source: Box::new(other) },
    })?;
    #[derive(serde::Deserialize, schemars::JsonSchema)]
    struct LawFile {
        law: crate::material::DamageParams,
    }
    let f: LawFile = src.deserialize().map_err(|e| FileError::Table { what: WHAT, source: Box::new(e) })?;
    f.law.validate().map_err(|e| FileError::Invalid { file: file.to_path_buf(), reason: e.to_string() })?;
    Ok(f.law)
}

fn resolve(folder: &Path, p: &Path) -> PathBuf {
    normalize(&if p.is_absolute() { p.to_path_buf() } else { folder.join(p) })
}

/// The results folder of the job at `path`: `[output] dir`, or `results/<job file stem>`, beside
/// the job file.
fn output_dir(path: &Path, out: &OutputConfig) -> PathBuf {
    let folder = path.parent().map(Path::to_path_buf).unwrap_or_default();
    match &out.dir {
        Some(d) => resolve(&folder, d),
        None => {
            let stem = path.file_stem().map_or_else(|| "job".into(), |s| s.to_string_lossy().into_owned());
            normalize(&folder.join("results").join(stem))
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A DEM mechanics parameter out of range is located at its own key (taken from the
    /// error's structure, `MechanicsError::quantity`), with its line in the file.
    #[test]
    fn a_bad_dem_mechanics_value_is_located_at_its_key() {
        let root = std::path::Path::new(env!("CARGO_MANIFEST_DIR"));
        let text = std::fs::read_to_string(root.join("jobs/wall-tension.toml")).unwrap();
        let line = text.lines().position(|l| l.starts_with("mu = ")).unwrap() + 1;
        let dir = std::env::temp_dir().join(format!("masonry-hpc-config-{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        let job = dir.join("bad-mu.toml");
        std::fs::write(&job, text.replacen("\nmu = 0.6", "\nmu = -0.5", 1)).unwrap();
        let e = load_job(&job).err().expect("mu < 0 is refused").to_string();
        let _ = std::fs::remove_dir_all(&dir);
        assert!(e.contains(&format!(":{line}:")) && e.contains("mechanics.mu") && e.contains("-0.5"), "{e}");
    }

    /// `breaks_per_equilibrium = 0` is refused at its key; 4 is read and kept.
    #[test]
    fn breaks_per_equilibrium_is_read_and_checked() {
        let root = std::path::Path::new(env!("CARGO_MANIFEST_DIR"));
        let text = std::fs::read_to_string(root.join("jobs/wall-tension.toml")).unwrap();
        let dir = std::env::temp_dir().join(format!("masonry-hpc-config-breaks-{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        let with = |n: usize| {
            let job = dir.join(format!("breaks-{n}.toml"));
            let t = text.replacen("type = \"dem\"", &format!("type = \"dem\"\nbreaks_per_equilibrium = {n}"), 1);
            std::fs::write(&job, t).unwrap();
            load_job(&job)
        };
        let e = with(0).err().expect("0 is refused").to_string();
        let Ok(AnyJob::Dem(four)) = with(4) else { panic!("4 is accepted") };
        let _ = std::fs::remove_dir_all(&dir);
        assert!(e.contains("analysis.breaks_per_equilibrium") && e.contains("at least 1"), "{e}");
        assert_eq!(four.spec.analysis.breaks_per_equilibrium, 4);
    }

    /// `factor_updates` defaults to "auto", reads "in_place" and "woodbury", and refuses anything
    /// else at its key, naming the accepted values.
    #[test]
    fn factor_updates_is_read_and_checked() {
        use crate::dem::solver::FactorUpdates;
        let root = std::path::Path::new(env!("CARGO_MANIFEST_DIR"));
        let text = std::fs::read_to_string(root.join("jobs/wall-tension.toml")).unwrap();
        let dir = std::env::temp_dir().join(format!("masonry-hpc-config-updates-{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        let with = |v: Option<&str>| {
            let job = dir.join(format!("updates-{}.toml", v.unwrap_or("none")));
            let t = match v {
                Some(v) => text.replacen("type = \"dem\"", &format!("type = \"dem\"\nfactor_updates = \"{v}\""), 1),
                None => text.clone(),
            };
            std::fs::write(&job, t).unwrap();
            match load_job(&job) {
                Ok(AnyJob::Dem(j)) => Ok(j.spec.analysis.factor_updates),
                Ok(_) => panic!("a DEM job"),
                Err(e) => Err(e.to_string()),
            }
        };
        let read = [with(None), with(Some("in_place")), with(Some("woodbury"))];
        let e = with(Some("cholmod")).expect_err("an unknown value is refused");
        let _ = std::fs::remove_dir_all(&dir);
        assert_eq!(read, [Ok(FactorUpdates::Auto), Ok(FactorUpdates::InPlace), Ok(FactorUpdates::Woodbury)]);
        assert!(e.contains("analysis.factor_updates") && e.contains("in_place") && e.contains("woodbury"), "{e}");
    }

    /// `E ← s E`, `G ← s G`: the Poisson ratio ν = E/2G − 1 is unchanged (0.25 here).
    #[test]
    fn scaling_the_modulus_keeps_the_poisson_ratio() {
        let m = MaterialConfig::Elastic(ElasticMaterial { e: 2.0e9, nu: None, g: Some(0.8e9), density: 1.0 });
        let MaterialConfig::Elastic(e) = m.with_modulus_scaled(1.5) else { panic!() };
        assert_eq!(e.e, 3.0e9);
        assert_eq!(e.g, Some(1.2e9));
    }

    fn load_str(text: &str) -> Result<Job, ConfigError> {
        let dir = std::env::temp_dir().join(format!("mhpc-config-{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        // A unique name per call: tests run in parallel threads of one process.
        static NEXT: std::sync::atomic::AtomicUsize = std::sync::atomic::AtomicUsize::new(0);
        let k = NEXT.fetch_add(1, std::sync::atomic::Ordering::SeqCst);
        let f = dir.join(format!("t{}-{k}.toml", text.len()));
        std::fs::write(&f, text).unwrap();
        Job::load(&f)
    }

    const GOOD: &str = r#"
[analysis]
type = "linear_static"
[mesh]
file = "m.msh"
[materials.steel]
type = "elastic"
E = 210e9
nu = 0.3
[sections.s]
type = "frame"
area = 1e-3
iy = 1e-6
iz = 1e-6
j = 2e-6
[[parts]]
group = "beams"
section = "s"
material = "steel"
[solver.petsc]
ksp_type = "cg"
ksp_rtol = 1e-10
"#;

    #[test]
    fn good_job_loads_and_resolves_paths() {
        let job = load_str(GOOD).unwrap();
        assert!(job.mesh_file.ends_with("m.msh"));
        assert!(job.mesh_file.parent().unwrap().ends_with(format!("mhpc-config-{}", std::process::id())));
        // Default results folder: results/<job file stem> beside the job file.
        let stem = job.source.file.file_stem().unwrap().to_owned();
        assert!(job.output_dir.ends_with(std::path::Path::new("results").join(stem)), "{}", job.output_dir.display());
        assert!(job.petsc_options.contains(&("-ksp_type".to_string(), "cg".to_string())));
        let rtol = job.petsc_options.iter().find(|(k, _)| k == "-ksp_rtol").unwrap();
        assert_eq!(rtol.1.parse::<f64>().unwrap(), 1e-10);
    }

    fn err(text: &str) -> String {
        match load_str(text) {
            Ok(_) => panic!("expected an error"),
            Err(e) => e.to_string(),
        }
    }

    #[test]
    fn unknown_key_is_located() {
        let e = err(&GOOD.replace("nu = 0.3", "nu = 0.3\nnuu = 0.2"));
        assert!(e.contains(":10:1: key 'materials.steel.nuu'"), "{e}");
        assert!(e.contains("unknown field `nuu`"), "{e}");
    }

    #[test]
    fn wrong_type_is_located() {
        let e = err(&GOOD.replace("area = 1e-3", "area = \"big\""));
        assert!(e.contains(":12:8"), "{e}");
        assert!(e.contains("sections.s.area") && e.contains("expected f64"), "{e}");
    }

    #[test]
    fn malformed_toml_is_located() {
        let e = err(&GOOD.replace("[mesh]", "[mesh"));
        assert!(e.contains(":4:"), "{e}");
    }

    #[test]
    fn non_positive_values_are_rejected_with_their_key() {
        let e = err(&GOOD.replace("E = 210e9", "E = -1.0"));
        assert!(e.contains(":8:1: key 'materials.steel.E'") && e.contains("> 0"), "{e}");
        let e = err(&GOOD.replace("area = 1e-3", "area = 0.0"));
        assert!(e.contains("key 'sections.s.area'") && e.contains("got 0"), "{e}");
    }

    /// `[dynamics] max_damage_increment`: the default when absent, 1.0 (the control off) read as
    /// given, and 0, a negative value, more than 1 and nan refused at the key, with its line and
    /// column and what was expected.
    #[test]
    fn max_damage_increment_is_read_and_checked() {
        let with = |value: Option<&str>| {
            let line = value.map_or(String::new(), |v| format!("max_damage_increment = {v}\n"));
            let text = GOOD.replace("type = \"linear_static\"", "type = \"time_history\"")
                + "[dynamics]\nduration = 1.0\ndt = 0.01\n"
                + &line
                + "[[dynamics.ground_motion]]\ndirection = \"x\"\nsynthetic = \"vallorcine_like\"\n";
            let row = text.lines().position(|l| l.starts_with("max_damage_increment")).map_or(0, |i| i + 1);
            (load_str(&text).map(|j| j.spec.dynamics.unwrap().max_damage_increment), row)
        };
        assert_eq!(with(None).0.unwrap(), DEFAULT_MAX_DAMAGE_INCREMENT);
        assert_eq!(with(Some("1.0")).0.unwrap(), 1.0);
        assert_eq!(with(Some("0.05")).0.unwrap(), 0.05);
        for bad in ["0.0", "-0.1", "1.5", "nan"] {
            let (r, row) = with(Some(bad));
            let e = r.err().unwrap_or_else(|| panic!("{bad} is refused")).to_string();
            assert!(
                e.contains(&format!(":{row}:1: key 'dynamics.max_damage_increment'")) && e.contains("(0, 1]"),
                "{bad}: {e}"
            );
        }
    }

    /// `[dynamics] convergence`: a band file that cannot be read is refused at the key, with the
    /// file named; a `damage_relaxation_time` <= 0 at its key.
    #[test]
    fn a_missing_convergence_band_file_and_a_bad_relaxation_time_are_refused_at_their_keys() {
        let text = GOOD.replace("type = \"linear_static\"", "type = \"time_history\"")
            + "[dynamics]\nduration = 1.0\ndt = 0.01\nconvergence = \"/nonexistent/band.json\"\n"
            + "[[dynamics.ground_motion]]\ndirection = \"x\"\nsynthetic = \"vallorcine_like\"\n";
        let row = text.lines().position(|l| l.starts_with("convergence")).unwrap() + 1;
        let e = load_str(&text).err().expect("a missing band file is refused").to_string();
        let bad = text.replace("convergence = \"/nonexistent/band.json\"", "damage_relaxation_time = -1.0");
        let e2 = load_str(&bad).err().expect("a negative relaxation time is refused").to_string();
        assert!(
            e2.contains(&format!(":{row}:1: key 'dynamics.damage_relaxation_time'"))
                && e2.contains("damage relaxation time [s]: expected > 0, got -1"),
            "{e2}"
        );
        assert!(
            e.contains(&format!(":{row}:1: key 'dynamics.convergence'"))
                && e.contains("cannot read convergence band file /nonexistent/band.json"),
            "{e}"
        );
    }

    #[test]
    fn unknown_names_list_what_exists() {
        let e = err(&GOOD.replace("section = \"s\"", "section = \"t\""));
        assert!(e.contains("parts[0].section") && e.contains("defined: s"), "{e}");
    }

    #[test]
    fn unknown_analysis_lists_the_variants() {
        let e = err(&GOOD.replace("linear_static", "dynamic"));
        assert!(e.contains(":3:1: key 'analysis.type'"), "{e}");
        assert!(e.contains("unknown analysis type 'dynamic'") && e.contains("one of: linear_static"), "{e}");
    }
}
