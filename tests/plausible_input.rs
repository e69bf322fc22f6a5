//! Warnings for implausible input (`config::plausible`, `model::plausible`): each case is a
//! value typed in other units on the elastic wall of `common::write_wall_mesh` (2 × 3 quads of
//! 1 m), warned by `check` (exit 0) and by a run, with the file, line, key and value; `--strict`
//! makes each an error (exit 2). The plausible job warns of nothing.
mod common;
use common::*;
use std::path::{Path, PathBuf};

/// The wall's time-history job, with `edit` applied as (from, to) text replacements; the record
/// `rec.txt` is written as `record_set` writes its records (m/s², with its unit header), peak
/// 0.5 m/s².
fn job(dir: &Path, edits: &[(&str, &str)]) -> PathBuf {
    write_wall_mesh(dir);
    let mut rec = String::from("# origin: artificial\n# units: time s, acceleration m/s^2; dt = 0.01 s; 21 samples\n# columns: t [s]  a [m/s^2]\n");
    for i in 0..=20 {
        rec += &format!("{:.2} {:e}\n", 0.01 * i as f64, 0.5 * (0.3 * i as f64).sin());
    }
    std::fs::write(dir.join("rec.txt"), rec).unwrap();
    let mut text = "[analysis]\ntype = \"time_history\"\n[mesh]\nfile = \"m.msh\"\n\
         [materials.stone]\ntype = \"elastic\"\nE = 3.0e9\nnu = 0.2\ndensity = 2000.0\n\
         [sections.wall]\ntype = \"shell\"\nthickness = 0.3\n\
         [[parts]]\ngroup = \"wall\"\nsection = \"wall\"\nmaterial = \"stone\"\n\
         [[supports]]\ngroup = \"base\"\ndofs = [\"all\"]\n\
         [gravity]\nacceleration = [0.0, 0.0, -9.81]\n\
         [dynamics]\nduration = 0.05\ndt = 0.01\n\
         [[dynamics.ground_motion]]\ndirection = \"x\"\nfile = \"rec.txt\"\nformat = \"two_column\"\nunits = \"m/s2\"\nscale = 1.0\n\
         [output]\ndir = \"out\"\nexisting = \"overwrite\"\n"
        .to_string();
    for (from, to) in edits {
        assert!(text.contains(from), "test setup: {from}");
        text = text.replacen(from, to, 1);
    }
    let f = dir.join("job.toml");
    std::fs::write(&f, text).unwrap();
    f
}

/// `check` warns with every needle and exits 0; `check --strict` exits 2 with them.
fn expect_warning(name: &str, edits: &[(&str, &str)], needles: &[&str]) {
    let dir = scratch(name);
    let f = job(&dir, edits);
    let out = run(0, &["check", f.to_str().unwrap()]);
    let err = stderr(&out);
    assert_eq!(out.status.code(), Some(0), "{name}: check exits 0 on a warning:\n{err}");
    for n in needles {
        assert!(err.contains(n), "{name}: the warning lacks '{n}':\n{err}");
    }
    assert!(err.contains("warning:") && err.contains("job.toml:"), "{name}: a located warning:\n{err}");
    let strict = run(0, &["check", "--strict", f.to_str().unwrap()]);
    let serr = stderr(&strict);
    assert_eq!(strict.status.code(), Some(2), "{name}: --strict exits 2:\n{serr}");
    assert!(serr.contains("--strict") && needles.iter().all(|n| serr.contains(n)), "{name}:\n{serr}");
}

#[test]
fn the_plausible_job_warns_of_nothing() {
    let dir = scratch("plausible-none");
    let f = job(&dir, &[]);
    let out = run(0, &["check", "--strict", f.to_str().unwrap()]);
    assert_eq!(out.status.code(), Some(0), "{}", stderr(&out));
    assert!(!stderr(&out).contains("warning"), "{}", stderr(&out));
}

/// 55 typed for 0.55 m (centimetres): over 3 m, and over twice the 1 m elements.
#[test]
fn a_thickness_in_centimetres_is_warned() {
    expect_warning(
        "plausible-thickness-cm",
        &[("thickness = 0.3", "thickness = 55")],
        &[
            "key 'sections.wall.thickness'",
            "thickness = 55 m is over 3 m",
            "thickness = 55 m is over 2 times the elements",
        ],
    );
}

/// 2.5 m is under 3 m but over twice the wall's 1 m elements (median longest edge 1 m): warned
/// for the elements alone; 2 m, twice them, is not.
#[test]
fn a_thickness_larger_than_the_elements_is_warned() {
    expect_warning(
        "plausible-thickness-element",
        &[("thickness = 0.3", "thickness = 2.5")],
        &[
            "key 'sections.wall.thickness'",
            "thickness = 2.5 m is over 2 times the elements of group 'wall' (their longest edges: median 1.000 m",
        ],
    );
    let dir = scratch("plausible-thickness-twice");
    let f = job(&dir, &[("thickness = 0.3", "thickness = 2.0")]);
    let out = run(0, &["check", "--strict", f.to_str().unwrap()]);
    assert_eq!(out.status.code(), Some(0), "{}", stderr(&out));
}

/// 22,000: a unit weight in N/m³ typed for a density.
#[test]
fn a_density_outside_the_range_is_warned() {
    expect_warning(
        "plausible-density",
        &[("density = 2000.0", "density = 22000.0")],
        &["key 'materials.stone.density'", "density = 22000 kg/m^3 is outside 100–10000 kg/m^3"],
    );
}

/// 3000: the modulus in MPa typed for Pa.
#[test]
fn a_modulus_outside_the_range_is_warned() {
    expect_warning(
        "plausible-modulus",
        &[("E = 3.0e9", "E = 3000.0")],
        &["key 'materials.stone.E'", "E = 3000 Pa is outside 10 MPa–300 GPa"],
    );
}

/// scale = 40 on a record of peak 0.5 m/s²: 20 m/s² = 2.04 g.
#[test]
fn a_record_over_one_and_a_half_g_is_warned() {
    let pga = 40.0 * 0.5 * (0.3f64 * 5.0).sin();
    expect_warning(
        "plausible-pga",
        &[("scale = 1.0", "scale = 40.0")],
        &["key 'dynamics.ground_motion[0].scale'", &format!("is {pga:.4} m/s^2"), "over 1.5 g"],
    );
}

/// units = "g" on a file whose header says m/s²: 9.81 times the shaking.
#[test]
fn units_that_contradict_the_record_header_are_warned() {
    expect_warning(
        "plausible-units",
        &[("units = \"m/s2\"", "units = \"g\"")],
        &["key 'dynamics.ground_motion[0].units'", "states its acceleration in m/s^2 (line 2)", "scaled by 9.8066"],
    );
}

/// A run prints the warning once (not once per rank) and goes on.
#[test]
fn a_run_warns_once_and_goes_on() {
    let dir = scratch("plausible-run");
    let f = job(&dir, &[("density = 2000.0", "density = 2.0")]);
    let out = run(2, &[f.to_str().unwrap()]);
    let err = stderr(&out);
    assert!(out.status.success(), "{err}");
    assert_eq!(err.matches("materials.stone.density").count(), 1, "{err}");
    let strict = run(2, &["--strict", f.to_str().unwrap()]);
    assert_eq!(strict.status.code(), Some(2), "{}", stderr(&strict));
}

/// A law file that does not exist is named as a material file at its key, not as the job file.
#[test]
fn a_missing_law_file_is_named_as_a_material_file() {
    let dir = scratch("plausible-law-file");
    let f = job(
        &dir,
        &[(
            "[materials.stone]\ntype = \"elastic\"\nE = 3.0e9\nnu = 0.2\ndensity = 2000.0\n",
            "[materials.stone]\ntype = \"damage\"\ndensity = 2000.0\nlaw_file = \"no-such-law.toml\"\n",
        )],
    );
    let out = run(0, &["check", f.to_str().unwrap()]);
    let err = stderr(&out);
    assert_eq!(out.status.code(), Some(2), "{err}");
    assert!(
        err.contains("materials.stone.law_file")
            && err.contains("material file")
            && err.contains("no-such-law.toml does not exist"),
        "{err}"
    );
    assert!(!err.contains("cannot read job file"), "{err}");
}
