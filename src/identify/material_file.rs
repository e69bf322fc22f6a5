//! The material file the identification writes and structural jobs read by path
//! (`[materials.NAME] type = "damage", law_file = "…"`): a TOML file whose `[law]` table is the
//! damage law's parameters (`material::DamageParams`, the same keys as an inline material) and
//! whose `[provenance]` table says where they come from (ignored by the reader).
//!
//! ```text
//!   # header: written by the identification job, how to regenerate it, the job's notes
//!   [law]                       the parameters, shortest round-trip digits (the reference)
//!   [provenance]                job (path from this file's folder), software version, seeds,
//!                               regularization and its element size h
//!   [provenance.dem]            the calibrated lattice parameters (round-trip digits: a DEM job
//!                               with them gives the virtual tests' curves again)
//!   [provenance.calibration]    Table 1: target, mean ± std over n samples, relative error
//!   [provenance.law_fit]        the fitted measure's errors, eq. 15 and relative RMS beside
//!   [provenance.peaks]          the law's peaks against the DEM mean curves' and samples'
//!   [provenance.variant]        a material variant's samples (identify::variants), when it is one
//! ```
//! The text depends only on the job and its results: no time stamp, host name or absolute path,
//! so a rerun from the same seeds writes the same bytes. Reported figures (statistics, errors,
//! peaks) carry [`FIGURE_DIGITS`] significant digits: they are read, not fed back.
use super::error::IdentifyError;
use crate::material::DamageParams;
use std::fmt::Write as _;
use std::path::{Component, Path, PathBuf};

/// Significant digits of the reported figures (means, deviations, errors, peaks).
pub const FIGURE_DIGITS: usize = 5;

/// A calibrated quantity against its target (Table 1).
#[derive(Clone, Debug, PartialEq)]
pub struct TargetFigure {
    /// Key (`young_modulus`, `poisson`, `first_crack_stress`, `peak_stress`).
    pub name: &'static str,
    /// The measured value.
    pub target: f64,
    /// The calibrated DEM's sample mean.
    pub mean: f64,
    /// Its sample standard deviation.
    pub std: f64,
    /// Samples counted.
    pub n: usize,
    /// (mean − target) / target.
    pub relative_error: f64,
}

/// One error measure at the identified law.
#[derive(Clone, Debug, PartialEq)]
pub struct MeasureFigure {
    /// The measure's job-file name.
    pub measure: &'static str,
    /// Tension (None: not computable).
    pub tension: Option<f64>,
    /// Compression.
    pub compression: Option<f64>,
}

/// A peak of the law against the DEM's.
#[derive(Clone, Debug, PartialEq)]
pub struct PeakFigure {
    /// The DEM mean curve's peak [Pa].
    pub dem: f64,
    /// The law's peak [Pa].
    pub law: f64,
    /// (law − dem) / dem.
    pub relative_error: f64,
    /// The DEM samples' own peaks: mean, std, n.
    pub samples: Option<(f64, f64, usize)>,
}

/// A material variant: which samples its law was fitted to (identify::variants).
#[derive(Clone, Debug, PartialEq)]
pub struct VariantFigure {
    /// Its number, 1..=count.
    pub number: usize,
    /// How many variants the job fits.
    pub count: usize,
    /// The scheme's job-file name.
    pub scheme: &'static str,
    /// The bootstrap's seed (None under `halves`).
    pub seed: Option<u64>,
    /// Tension samples (numbered from 1 in the order of the curves).
    pub tension: Vec<usize>,
    /// Compression samples.
    pub compression: Vec<usize>,
    /// Samples of each test (tension, compression) the numbers count.
    pub of: [usize; 2],
}

/// Where the law comes from.
#[derive(Clone, Debug)]
pub struct Provenance {
    /// The identification job file (as run; written relative to the material file's folder).
    pub job: PathBuf,
    /// What was fitted (a sentence).
    pub method: String,
    /// `[analysis] seed` (designs, surrogate).
    pub seed: u64,
    /// Seeds of the calibration's DEM samples.
    pub calibration_sample_seeds: Vec<u64>,
    /// Seeds of the virtual tests' DEM samples (empty when the curves came from files).
    pub law_sample_seeds: Vec<u64>,
    /// Where the DEM curves came from (a sentence).
    pub curves: String,
    /// Where E and ν come from (a sentence).
    pub elastic: String,
    /// Element size h [m] of the comparison (Hillerborg).
    pub element_size: f64,
    /// The softening energy f_t h / B_t at h [J/m²] (identify::law_fit): G_f under
    /// `hillerborg`, G_f − f_t² h/(2E) under `hillerborg_no_elastic`.
    pub softening_energy: f64,
    /// Final error (the fitted measure's value) in tension.
    pub error_tension: f64,
    /// Compression error.
    pub error_compression: f64,
    /// The fitted error measure.
    pub error_measure: String,
    /// Every measure at the law (eq. 15, relative RMS, peak_energy).
    pub measures: Vec<MeasureFigure>,
    /// Tension and compression peaks.
    pub peaks: Option<[PeakFigure; 2]>,
    /// The DEM parameters the virtual tests used (None when the curves came from files).
    pub dem: Option<super::dem_adapter::DemParameters>,
    /// Table 1 against the calibrated DEM (when the calibration ran).
    pub calibration: Vec<TargetFigure>,
    /// Failed virtual-test samples (left out of the means).
    pub virtual_test_failures: Vec<String>,
    /// Comment lines for the header (the job's `[law] material_notes`).
    pub notes: Option<String>,
    /// The variant this law is, when it is one.
    pub variant: Option<VariantFigure>,
}

/// Magnitudes written without an exponent: [1e-3, 1e6).
fn plain(x: f64) -> bool {
    (1e-3..1e6).contains(&x.abs())
}

/// A TOML float from Rust's text of it: a decimal point where it has none (`1` → `1.0`).
fn float_text(t: String) -> String {
    if t.contains(['.', 'e', 'E', 'n', 'i']) {
        t
    } else {
        t + ".0"
    }
}

/// A float as TOML, shortest round-trip digits (Rust's `{}` in [1e-3, 1e6), `{:e}` outside): the
/// value read back is the same f64.
fn exact(x: f64) -> String {
    if x.is_nan() {
        "nan".into()
    } else if x.is_infinite() {
        if x > 0.0 {
            "inf".into()
        } else {
            "-inf".into()
        }
    } else if x == 0.0 || plain(x) {
        float_text(format!("{}", x + 0.0))
    } else {
        format!("{x:e}")
    }
}

/// A float as TOML with [`FIGURE_DIGITS`] significant digits.
fn figure(x: f64) -> String {
    if !x.is_finite() {
        return exact(x);
    }
    if x != 0.0 && (1e-3..1e5).contains(&x.abs()) {
        let decimals = (FIGURE_DIGITS as i32 - 1 - x.abs().log10().floor() as i32).max(0) as usize;
        float_text(format!("{:.*}", decimals, x))
    } else {
        format!("{:.*e}", FIGURE_DIGITS - 1, x)
    }
}

/// A relative error as TOML, to 1e-6 (below that it is round-off: E is met exactly by the
/// calibration's stage 1).
fn relative(x: f64) -> String {
    if x.is_finite() {
        format!("{:.6}", (x * 1e6).round() / 1e6 + 0.0)
    } else {
        exact(x)
    }
}

/// A TOML basic string.
fn quoted(s: &str) -> String {
    toml::Value::String(s.to_string()).to_string()
}

/// `to` relative to the folder `from` (both made absolute against the current folder and
/// normalized lexically); `to` itself when they share no root.
pub fn relative_path(from: &Path, to: &Path) -> PathBuf {
    let abs = |p: &Path| {
        let p = if p.is_absolute() { p.to_path_buf() } else { std::env::current_dir().unwrap_or_default().join(p) };
        let p = std::fs::canonicalize(&p).unwrap_or(p);
        crate::io::normalize(&p)
    };
    let (f, t) = (abs(from), abs(to));
    let fc: Vec<Component> = f.components().collect();
    let tc: Vec<Component> = t.components().collect();
    let common = fc.iter().zip(&tc).take_while(|(a, b)| a == b).count();
    if common == 0 {
        return to.to_path_buf();
    }
    let mut r = PathBuf::new();
    for _ in common..fc.len() {
        r.push("..");
    }
    for c in &tc[common..] {
        r.push(c.as_os_str());
    }
    r
}

/// The `[law]` table: every parameter with round-trip digits.
fn law_table(law: &DamageParams) -> String {
    let mut s = String::from("[law]\n");
    let _ = writeln!(s, "E = {}", exact(law.e));
    let _ = writeln!(s, "nu = {}", exact(law.nu));
    let _ = writeln!(s, "eps0_t = {}", exact(law.eps0_t));
    let _ = writeln!(s, "eps0_c = {}", exact(law.eps0_c));
    let _ = writeln!(s, "gf_t = {}", exact(law.gf_t));
    let _ = writeln!(s, "a_c = {}", exact(law.a_c));
    let _ = writeln!(s, "b_c = {}", exact(law.b_c));
    if let Some(g) = law.gf_c {
        let _ = writeln!(s, "gf_c = {}", exact(g));
    }
    let reg = match law.regularization {
        crate::material::Regularization::Unregularized { b_t } => format!("{{ none = {{ b_t = {} }} }}", exact(b_t)),
        r => quoted(r.name()),
    };
    let _ = writeln!(s, "regularization = {reg}");
    if !law.split.is_trace() {
        let _ = writeln!(s, "split = {}", quoted(law.split.name()));
    }
    s
}

/// The file's text; `file` is where it goes (the job's path is written relative to its folder).
pub fn material_toml(file: &Path, law: &DamageParams, p: &Provenance) -> String {
    let folder = file.parent().filter(|f| !f.as_os_str().is_empty()).unwrap_or(Path::new("."));
    let job = relative_path(folder, &p.job);
    let job = job.to_string_lossy().replace('\\', "/");
    let mut s = header(&job, p.variant.as_ref(), p.notes.as_deref());
    s.push('\n');
    s.push_str(&law_table(law));
    provenance_table(&mut s, &job, p);
    if let Some(v) = &p.variant {
        variant_table(&mut s, v);
    }
    if let Some(d) = &p.dem {
        dem_table(&mut s, d);
    }
    if !p.calibration.is_empty() {
        calibration_table(&mut s, &p.calibration);
    }
    if !p.measures.is_empty() {
        law_fit_table(&mut s, &p.measures);
    }
    if let Some(peaks) = &p.peaks {
        peaks_table(&mut s, peaks);
    }
    s
}

/// `NAME VERSION` of this software.
fn software() -> String {
    format!("{} {}", env!("CARGO_PKG_NAME"), env!("CARGO_PKG_VERSION"))
}

/// The header comment: what wrote the file (the job, at `job` from the file's folder), how to
/// regenerate it, how to read it, what a variant is (when it is one), then the job's notes, one
/// comment line each.
fn header(job: &str, variant: Option<&VariantFigure>, notes: Option<&str>) -> String {
    let mut s = String::new();
    let _ = write!(
        s,
        "# Masonry damage law identified from DEM virtual tests (paper §3.2), written by the identification job\n\
         # {job} (path from this file's folder) of {}: do not edit by hand.\n\
         # Regenerate it by running that job again: from the same seeds it writes this file again, byte\n\
         # for byte. Structural jobs read the [law] table: [materials.NAME] type = \"damage\",\n\
         # law_file = \"<path of this file>\"; [provenance] says where the numbers come from.\n",
        software()
    );
    if let Some(v) = variant {
        let _ = write!(
            s,
            "#\n\
             # Material variant {} of {} (scheme \"{}\"): the law fitted like the job's main law (the same\n\
             # design, optimizer settings and E, nu) to the mean curves of a subset of the DEM samples only,\n\
             # to carry the samples' scatter into structural analyses; [provenance.variant] names them.\n",
            v.number, v.count, v.scheme
        );
    }
    if let Some(notes) = notes {
        s.push_str("#\n");
        for line in notes.trim_end().lines() {
            let line = line.trim_end();
            if line.is_empty() {
                s.push_str("#\n");
            } else {
                let _ = writeln!(s, "# {line}");
            }
        }
    }
    s
}

/// The `[provenance]` table: the job, the software, the method, the seeds, where the curves and
/// the elastic constants come from, the regularization's h, the final errors and the failures.
fn provenance_table(s: &mut String, job: &str, p: &Provenance) {
    s.push_str("\n[provenance]\n");
    let _ = writeln!(s, "job = {}", quoted(job));
    let _ = writeln!(s, "software = {}", quoted(&software()));
    let _ = writeln!(s, "method = {}", quoted(&p.method));
    let seeds = |v: &[u64]| format!("[{}]", v.iter().map(u64::to_string).collect::<Vec<_>>().join(", "));
    let _ = writeln!(s, "seed = {}                      # [analysis] seed: designs and surrogates", p.seed);
    if !p.calibration_sample_seeds.is_empty() {
        let _ = writeln!(s, "calibration_sample_seeds = {}", seeds(&p.calibration_sample_seeds));
    }
    if !p.law_sample_seeds.is_empty() {
        let _ = writeln!(s, "virtual_test_sample_seeds = {}", seeds(&p.law_sample_seeds));
    }
    let _ = writeln!(s, "curves = {}", quoted(&p.curves));
    let _ = writeln!(s, "elastic = {}", quoted(&p.elastic));
    let _ =
        writeln!(s, "element_size = {}           # h [m] of the comparison (regularization)", exact(p.element_size));
    let _ = writeln!(s, "softening_energy = {}    # f_t h / B_t at h [J/m2]", figure(p.softening_energy));
    let _ = writeln!(s, "error_measure = {}", quoted(&p.error_measure));
    let _ = writeln!(s, "error_tension = {}", figure(p.error_tension));
    let _ = writeln!(s, "error_compression = {}", figure(p.error_compression));
    if !p.virtual_test_failures.is_empty() {
        let items: Vec<String> = p.virtual_test_failures.iter().map(|f| quoted(f)).collect();
        let _ = writeln!(s, "virtual_test_failures = [{}]", items.join(", "));
    }
}

/// `[provenance.variant]`: the variant's number and scheme, and its samples in each test.
fn variant_table(s: &mut String, v: &VariantFigure) {
    s.push_str("\n[provenance.variant]                   # the samples, numbered 1..n in the order of the curves\n");
    let _ = writeln!(s, "variant = {}", v.number);
    let _ = writeln!(s, "count = {}", v.count);
    let _ = writeln!(s, "scheme = {}", quoted(v.scheme));
    if let Some(seed) = v.seed {
        let _ = writeln!(s, "seed = {seed}                      # SplitMix64 (identify::variants)");
    }
    let list = |k: &[usize]| k.iter().map(usize::to_string).collect::<Vec<_>>().join(", ");
    let _ = writeln!(s, "tension_samples = [{}]       # of {}", list(&v.tension), v.of[0]);
    let _ = writeln!(s, "compression_samples = [{}]   # of {}", list(&v.compression), v.of[1]);
}

/// `[provenance.dem]`: the calibrated lattice's parameters, round-trip digits.
fn dem_table(s: &mut String, d: &super::dem_adapter::DemParameters) {
    s.push_str("\n[provenance.dem]                       # the calibrated lattice (round-trip digits)\n");
    for (k, v) in [
        ("alpha", d.alpha),
        ("e_bar", d.e_bar),
        ("eps_cr", d.eps_cr),
        ("theta_cr", d.theta_cr),
        ("mu", d.mu),
        ("kt_over_kn", d.kt_over_kn),
    ] {
        let _ = writeln!(s, "{k} = {}", exact(v));
    }
    if let Some(v) = d.crushing_stress {
        let _ = writeln!(s, "crushing_stress = {}", exact(v));
    }
    if let Some(v) = d.crushing_energy {
        let _ = writeln!(s, "crushing_energy = {}", exact(v));
    }
}

/// `[provenance.calibration]`: Table 1, each quantity's target, sample mean ± std (n) and
/// relative error.
fn calibration_table(s: &mut String, calibration: &[TargetFigure]) {
    s.push_str(
        "\n[provenance.calibration]               # Table 1 against the calibrated DEM: sample mean ± std (n)\n",
    );
    for c in calibration {
        let _ = writeln!(
            s,
            "{} = {{ target = {}, mean = {}, std = {}, n = {}, relative_error = {} }}",
            c.name,
            exact(c.target),
            figure(c.mean),
            figure(c.std),
            c.n,
            relative(c.relative_error)
        );
    }
}

/// `[provenance.law_fit]`: every error measure at the law, in tension and compression (`"-"`:
/// not computable).
fn law_fit_table(s: &mut String, measures: &[MeasureFigure]) {
    s.push_str("\n[provenance.law_fit]                   # every measure at the law (the fitted one: error_measure)\n");
    let opt = |v: Option<f64>| v.map_or_else(|| quoted("-"), figure);
    for m in measures {
        let _ = writeln!(s, "{} = {{ tension = {}, compression = {} }}", m.measure, opt(m.tension), opt(m.compression));
    }
}

/// `[provenance.peaks]`: the law's tension and compression peaks against the DEM mean curves'
/// (and the samples' own peaks when known).
fn peaks_table(s: &mut String, peaks: &[PeakFigure; 2]) {
    s.push_str("\n[provenance.peaks]                     # [Pa]: the law's against the DEM mean curves' (relative)\n");
    for (name, pk) in ["tension", "compression"].iter().zip(peaks) {
        let samples = pk.samples.map_or(String::new(), |(m, sd, n)| {
            format!(", dem_samples = {{ mean = {}, std = {}, n = {n} }}", figure(m), figure(sd))
        });
        let _ = writeln!(
            s,
            "{name} = {{ dem = {}, law = {}, relative_error = {}{samples} }}",
            figure(pk.dem),
            figure(pk.law),
            relative(pk.relative_error)
        );
    }
}

/// Writes the file.
pub fn write_material_file(file: &Path, law: &DamageParams, provenance: &Provenance) -> Result<(), IdentifyError> {
    let text = material_toml(file, law, provenance);
    std::fs::write(file, text).map_err(|e| IdentifyError::Write { file: file.to_path_buf(), reason: e.to_string() })
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::material::Regularization;

    fn provenance() -> Provenance {
        Provenance {
            job: PathBuf::from("jobs/j.toml"),
            method: "m \"quoted\"".into(),
            seed: 1,
            calibration_sample_seeds: vec![1, 2],
            law_sample_seeds: vec![1],
            curves: "c".into(),
            elastic: "e".into(),
            element_size: 1.2,
            softening_energy: 10.0,
            error_tension: 0.1,
            error_compression: 0.2,
            error_measure: "eq15".into(),
            measures: vec![MeasureFigure { measure: "eq15", tension: Some(91.6), compression: None }],
            peaks: Some([
                PeakFigure { dem: 1.9e5, law: 1.92e5, relative_error: 0.0105, samples: Some((1.9e5, 1e4, 4)) },
                PeakFigure { dem: 2.1e6, law: 2.1e6, relative_error: 0.0, samples: None },
            ]),
            dem: Some(crate::identify::DemParameters {
                alpha: 0.41771234567,
                e_bar: 3.5968e9,
                eps_cr: 7.07e-5,
                theta_cr: 3.32e-3,
                mu: 0.6,
                kt_over_kn: 0.4,
                crushing_stress: Some(2.587e6),
                crushing_energy: Some(1e3),
            }),
            calibration: vec![TargetFigure {
                name: "poisson",
                target: 0.19,
                mean: 0.18984,
                std: 0.00715,
                n: 8,
                relative_error: -8.4e-4,
            }],
            virtual_test_failures: vec!["tension: sample 2: stopped".into()],
            notes: Some("line one\n\nline three".into()),
            variant: None,
        }
    }

    #[test]
    fn law_table_reads_back_exactly_and_provenance_is_toml() {
        #[derive(serde::Deserialize)]
        struct F {
            law: DamageParams,
            provenance: toml::Table,
        }
        let law = DamageParams {
            e: 2.885123456789e9,
            nu: 0.19,
            eps0_t: 1.1e-4 / 3.0,
            eps0_c: 3e-4,
            gf_t: 40.0,
            a_c: 1.0,
            b_c: 900.0,
            gf_c: Some(104.3),
            regularization: Regularization::HillerborgNoElastic,
            split: crate::material::Split::Trace,
        };
        let p = provenance();
        for reg in [
            Regularization::Hillerborg,
            Regularization::HillerborgNoElastic,
            Regularization::Unregularized { b_t: 4000.0 },
        ] {
            for gf_c in [None, Some(104.3)] {
                let law = DamageParams { regularization: reg, gf_c, ..law };
                let text = material_toml(Path::new("materials/m.toml"), &law, &p);
                let back: F = toml::from_str(&text).unwrap_or_else(|e| panic!("{e}\n{text}"));
                assert_eq!(back.law, law, "{text}");
                assert_eq!(back.provenance["job"].as_str(), Some("../jobs/j.toml"));
                assert_eq!(back.provenance["dem"]["alpha"].as_float(), Some(0.41771234567));
                assert_eq!(back.provenance["calibration"]["poisson"]["n"].as_integer(), Some(8));
            }
        }
        // The header comments the notes, blank lines included, and names the version.
        let text = material_toml(Path::new("materials/m.toml"), &law, &p);
        assert!(text.contains("# line one\n#\n# line three\n"), "{text}");
        assert!(text.contains(env!("CARGO_PKG_VERSION")));
        // Figures carry FIGURE_DIGITS significant digits.
        assert!(text.contains("mean = 0.18984, std = 0.0071500, n = 8, relative_error = -0.000840"), "{text}");
        // Round-trip digits, a decimal point where Rust's text has none.
        assert!(
            text.contains("E = 2.885123456789e9\n") && text.contains("gf_t = 40.0\n") && text.contains("a_c = 1.0\n"),
            "{text}"
        );
        assert!(text.contains("eps0_t = 3.6666666666666666e-5\n"), "{text}");
    }

    #[test]
    fn a_variant_names_its_samples_in_the_header_and_its_table() {
        let law = DamageParams {
            e: 2.885e9,
            nu: 0.19,
            eps0_t: 6.5e-5,
            eps0_c: 1.7e-4,
            gf_t: 18.0,
            a_c: 0.99,
            b_c: 3400.0,
            gf_c: Some(687.0),
            regularization: Regularization::HillerborgNoElastic,
            split: crate::material::Split::Trace,
        };
        let variant = |seed| VariantFigure {
            number: 2,
            count: 2,
            scheme: "halves",
            seed,
            tension: vec![2, 4],
            compression: vec![2, 4],
            of: [4, 4],
        };
        let p = Provenance { variant: Some(variant(None)), ..provenance() };
        let text = material_toml(Path::new("materials/m-variant-2.toml"), &law, &p);
        assert!(text.contains("# Material variant 2 of 2 (scheme \"halves\")"), "{text}");
        let back: toml::Table = toml::from_str(&text).unwrap_or_else(|e| panic!("{e}\n{text}"));
        let v = &back["provenance"]["variant"];
        assert_eq!(v["variant"].as_integer(), Some(2));
        assert_eq!(v["scheme"].as_str(), Some("halves"));
        assert_eq!(v["tension_samples"].as_array().unwrap().len(), 2);
        assert_eq!(v["compression_samples"][1].as_integer(), Some(4));
        assert!(v.get("seed").is_none());
        // The notes follow the variant's lines; a bootstrap's seed is recorded.
        assert!(text.find("Material variant").unwrap() < text.find("# line one").unwrap());
        let p = Provenance { variant: Some(variant(Some(7))), ..provenance() };
        let back: toml::Table = toml::from_str(&material_toml(Path::new("m.toml"), &law, &p)).unwrap();
        assert_eq!(back["provenance"]["variant"]["seed"].as_integer(), Some(7));
    }

    #[test]
    fn relative_paths() {
        assert_eq!(
            relative_path(Path::new("/a/b/materials"), Path::new("/a/b/jobs/j.toml")),
            PathBuf::from("../jobs/j.toml")
        );
        assert_eq!(relative_path(Path::new("/a/b"), Path::new("/a/b/j.toml")), PathBuf::from("j.toml"));
        assert_eq!(relative_path(Path::new("/a/b/c/d"), Path::new("/a/x.toml")), PathBuf::from("../../../x.toml"));
    }
}
