//! Warnings for input that is valid but implausible for a masonry building, most often a value
//! typed in other units (centimetres for metres, t/m³ or kN/m³ for kg/m³, MPa for Pa, a record in
//! m/s² read as g). They are not errors: the run goes on, the log and `masonry-hpc check` print
//! them, and `--strict` turns them into an error (exit code 2).
//!
//! | key | warned when | typical slip |
//! |---|---|---|
//! | `materials.NAME.density` | outside 100–10,000 kg/m³ (0, a massless material, is not warned) | 2.2 (t/m³), 22000 (N/m³) |
//! | `materials.NAME.E`, `…law.E` | outside 10 MPa–300 GPa | 2500 (MPa) |
//! | `sections.NAME.thickness` | over 3 m (or over twice its elements: `model::plausible`) | 55 (cm) |
//! | `dynamics.ground_motion[i].scale` | the record's PGA after scaling over 1.5 g | a factor for g on m/s² |
//! | `dynamics.ground_motion[i].units` | contradicts the unit the record's own header states | `"g"` on a file in m/s² |
//!
//! Each warning names the file, line, key and value, like an error ([`super::ConfigError`]).
use super::job::{MaterialConfig, SectionConfig, StructuralJobFile};
use super::source::{Seg, Source};
use crate::seismic::{AccelUnit, STANDARD_GRAVITY};
use std::path::Path;

/// Densities outside this range are warned [kg/m³].
pub const DENSITY_RANGE: (f64, f64) = (100.0, 10_000.0);
/// Young's moduli outside this range are warned [Pa].
pub const MODULUS_RANGE: (f64, f64) = (10e6, 300e9);
/// Shell thicknesses over this are warned [m].
pub const MAX_THICKNESS: f64 = 3.0;
/// Records whose PGA after scaling exceeds this many g are warned.
pub const MAX_PGA_G: f64 = 1.5;

/// The warnings of a structural job file that need no mesh; `folder` is the job file's folder
/// (record files are relative to it).
pub fn warnings(src: &Source, job: &StructuralJobFile, folder: &Path) -> Vec<String> {
    let mut out = Vec::new();
    let mut warn = |path: Vec<Seg>, message: String| out.push(src.error_at(&path, message).to_string());
    for (name, m) in &job.materials {
        let at = |k: &str| Seg::path(&["materials", name.as_str(), k]);
        let (density, e, e_key) = match m {
            MaterialConfig::Elastic(el) => (el.density, Some(el.e), at("E")),
            MaterialConfig::Damage(d) => {
                let key = if d.law_file.is_some() {
                    at("law_file")
                } else {
                    Seg::path(&["materials", name.as_str(), "law", "E"])
                };
                (d.density, d.law.as_ref().map(|l| l.e), key)
            }
        };
        if density != 0.0 && !(DENSITY_RANGE.0..=DENSITY_RANGE.1).contains(&density) {
            warn(
                at("density"),
                format!("density = {density} kg/m^3 is outside {}–{} kg/m^3 (masonry ≈ 1,800–2,400): a value in t/m^3 or N/m^3?", DENSITY_RANGE.0, DENSITY_RANGE.1),
            );
        }
        if let Some(e) = e.filter(|e| !(MODULUS_RANGE.0..=MODULUS_RANGE.1).contains(e)) {
            warn(e_key, format!("E = {e} Pa is outside 10 MPa–300 GPa (masonry ≈ 1–10 GPa): a value in MPa or GPa?"));
        }
    }
    for (name, s) in &job.sections {
        if let SectionConfig::Shell(sh) = s {
            if sh.thickness > MAX_THICKNESS {
                warn(
                    Seg::path(&["sections", name.as_str(), "thickness"]),
                    format!("thickness = {} m is over {MAX_THICKNESS} m: a value in cm?", sh.thickness),
                );
            }
        }
    }
    if let Some(d) = &job.dynamics {
        for (i, g) in d.ground_motion.iter().enumerate() {
            let at = |k: &str| vec![Seg::key("dynamics"), Seg::key("ground_motion"), Seg::Index(i), Seg::key(k)];
            if let Some(r) = &g.record {
                let pga = crate::seismic::pga(r);
                if pga > MAX_PGA_G * STANDARD_GRAVITY {
                    warn(
                        at("scale"),
                        format!(
                            "the record's PGA after scaling (scale = {}) is {pga:.4} m/s^2 = {:.3} g, over {MAX_PGA_G} g: check scale and units",
                            g.scale,
                            pga / STANDARD_GRAVITY
                        ),
                    );
                }
            }
            if let (Some(f), Some(u)) = (&g.file, &g.units) {
                let file = super::resolve(folder, f);
                if let (Some(given), Some((stated, line))) = (AccelUnit::parse(u), header_unit(&file)) {
                    if given != stated {
                        warn(
                            at("units"),
                            format!(
                                "units = \"{u}\", but {} states its acceleration in {} (line {line}): the record would be scaled by {:.4}",
                                file.display(),
                                stated.name(),
                                given.to_si() / stated.to_si()
                            ),
                        );
                    }
                }
            }
        }
    }
    out
}

/// The acceleration unit a record file's `#` header states, and its line: `acceleration <unit>`
/// (as `record_set` and the synthetic records write it) or `a [<unit>]` (their column line).
pub fn header_unit(file: &Path) -> Option<(AccelUnit, usize)> {
    let text = std::fs::read_to_string(file).ok()?;
    for (k, line) in text.lines().enumerate().take_while(|(_, l)| l.trim_start().starts_with('#')) {
        let found = line
            .split("acceleration ")
            .nth(1)
            .and_then(|rest| rest.split([';', ',', ' ']).next())
            .or_else(|| line.split("a [").nth(1).and_then(|rest| rest.split(']').next()));
        if let Some(u) = found.and_then(AccelUnit::parse) {
            return Some((u, k + 1));
        }
    }
    None
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The header lines of the tool's own records state m/s²; a file without a header states
    /// nothing.
    #[test]
    fn the_unit_of_a_record_header_is_found() {
        let dir = std::env::temp_dir().join(format!("mhpc-header-unit-{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        let f = dir.join("r.txt");
        std::fs::write(&f, "# origin: artificial\n# units: time s, acceleration m/s^2; dt = 0.01 s\n0 0\n").unwrap();
        assert_eq!(header_unit(&f), Some((AccelUnit::MetersPerSecond2, 2)));
        std::fs::write(&f, "# columns: t [s]  a [g]\n0 0\n").unwrap();
        assert_eq!(header_unit(&f), Some((AccelUnit::G, 1)));
        std::fs::write(&f, "0 0\n# acceleration g\n").unwrap();
        assert_eq!(header_unit(&f), None);
        std::fs::remove_dir_all(dir).unwrap();
    }
}
