//! The identification job through the whole program (SPEC §3): the damage law recovered from
//! curves the law itself produced; the DEM calibrated against numbers the DEM itself produced;
//! the chain on a tiny wall under `mpirun -n 2`; bad input.
mod common;
use common::*;
use masonry_hpc::material::{run_path, DamageParams, LoadPath, NewtonSettings, PlaneStress, Regularization};
use std::path::{Path, PathBuf};

/// The law that generates the synthetic "DEM" curves (rubble-masonry orders of magnitude).
fn known_law() -> DamageParams {
    DamageParams {
        e: 2.885e9,
        nu: 0.19,
        eps0_t: 1.0e-4,
        eps0_c: 4.0e-4,
        gf_t: 30.0,
        a_c: 0.8,
        b_c: 800.0,
        regularization: Regularization::Hillerborg,
    }
}

const H: f64 = 1.2;

/// Writes the law's uniaxial curve (ε_xx, σ_xx), tension positive, as `strain,stress` CSV.
fn write_law_curve(file: &Path, p: &DamageParams, max: f64, tension: bool) {
    let law = p.for_element(H).unwrap();
    let path = if tension { LoadPath::<3>::uniaxial_tension(max, 300) } else { LoadPath::<3>::uniaxial_compression(max, 300) }.unwrap();
    let rec = run_path(PlaneStress, &law, &path, &NewtonSettings::default()).unwrap();
    let mut s = String::from("strain,stress\n");
    for r in rec {
        s.push_str(&format!("{:e},{:e}\n", r.strain[0], r.stress[0]));
    }
    std::fs::write(file, s).unwrap();
}

const LAW_BOUNDS: &str =
    "bounds = { eps0_t = [5e-5, 2e-4], eps0_c = [2e-4, 8e-4], gf_t = [10.0, 90.0], a_c = [0.5, 1.0], b_c = [300.0, 2000.0] }";

fn law_job(dir: &Path, extra: &str, bounds: &str) -> PathBuf {
    let text = format!(
        "[analysis]\ntype = \"identification\"\nseed = 3\n\
         [sample]\nseed = 1\nlayout = {{ type = \"coursed\", width = 1.0, height = {H}, n_courses = 3, n_per_course = 3 }}\n\
         [law]\ndem_curves = {{ tension = \"t.csv\", compression = \"c.csv\" }}\nyoung_modulus = 2.885e9\npoisson = 0.19\n\
         iterations = 6\nbatch = 2\n{extra}{bounds}\n\
         [output]\ndir = \"out\"\nexisting = \"overwrite\"\n"
    );
    let f = dir.join("law.toml");
    std::fs::write(&f, text).unwrap();
    f
}

fn summary(dir: &Path) -> serde_json::Value {
    serde_json::from_str(&std::fs::read_to_string(dir.join("out/summary.json")).unwrap()).unwrap()
}

#[test]
fn law_identification_recovers_the_law_that_made_the_curves() {
    let dir = scratch("identify-law");
    let p = known_law();
    write_law_curve(&dir.join("t.csv"), &p, 6e-4, true);
    write_law_curve(&dir.join("c.csv"), &p, 1.5e-2, false);
    let f = law_job(&dir, "", LAW_BOUNDS);
    let out = run(0, &[f.to_str().unwrap()]);
    assert!(out.status.success(), "{}\n{}", stdout(&out), stderr(&out));
    let s = summary(&dir);
    let law = &s["law"];
    // Acceptance (issue): the law's peaks within 5% of the reference curves' peaks.
    let (tp, cp) = (law["tension_peak_error"].as_f64().unwrap(), law["compression_peak_error"].as_f64().unwrap());
    assert!(tp.abs() < 0.05 && cp.abs() < 0.05, "peak errors {tp}, {cp}");
    // The reference curves are the law's own: eq. 15 per point (mean sqrt of the relative
    // deviation) under 0.1 means a typical relative deviation under 1%.
    for side in ["tension", "compression"] {
        let v = law["fit"][side]["value"].as_f64().unwrap();
        let n = law["fit"][side]["points"].as_f64().unwrap();
        assert!(v / n < 0.1, "{side}: F = {v} over {n} points");
    }
    // The tensile threshold is what sets the tensile peak E ε₀ᵗ: recovered within 5%.
    let eps0_t = law["params"]["eps0_t"].as_f64().unwrap();
    assert!((eps0_t - p.eps0_t).abs() / p.eps0_t < 0.05, "eps0_t {eps0_t}");
    // Outputs a person looks at.
    for f in ["law.csv", "law_error.png", "law_tension.png", "law_compression.png", "material.toml"] {
        assert!(dir.join("out").join(f).is_file(), "{f} missing");
    }
    // The history has the 32 factorial points first, then the infill.
    let hist = std::fs::read_to_string(dir.join("out/law.csv")).unwrap();
    assert!(hist.lines().count() > 1 + 32, "{hist}");
    // A structural job reads the material file by path.
    let job = format!(
        "[analysis]\ntype = \"linear_static\"\n[mesh]\nfile = \"none.msh\"\n\
         [materials.masonry]\ntype = \"damage\"\nlaw_file = \"out/material.toml\"\n\
         [sections.s]\ntype = \"shell\"\nthickness = 0.5\n\
         [[parts]]\ngroup = \"wall\"\nsection = \"s\"\nmaterial = \"masonry\"\n"
    );
    std::fs::write(dir.join("structure.toml"), job).unwrap();
    let j = masonry_hpc::config::Job::load(&dir.join("structure.toml")).unwrap();
    let m = &j.spec.materials["masonry"];
    let masonry_hpc::config::MaterialConfig::Damage(d) = m else { panic!("not a damage material") };
    let read = d.law.unwrap();
    assert!((read.eps0_t - eps0_t).abs() <= 1e-12 * eps0_t);
    assert_eq!(read.e, 2.885e9);
}

fn expect_error(dir: &Path, job: &Path, needles: &[&str], nps: &[usize]) {
    let _ = dir;
    for &np in nps {
        let out = run(np, &["check", job.to_str().unwrap()]);
        let err = stderr(&out);
        assert_eq!(out.status.code(), Some(2), "np={np}: {err}");
        for n in needles {
            assert!(err.contains(n), "np={np}: message lacks '{n}':\n{err}");
        }
        assert_eq!(err.matches("error:").count(), 1, "np={np}: one message:\n{err}");
    }
}

#[test]
fn bad_bounds_are_located() {
    let dir = scratch("identify-bad-bounds");
    let p = known_law();
    write_law_curve(&dir.join("t.csv"), &p, 6e-4, true);
    write_law_curve(&dir.join("c.csv"), &p, 1.5e-2, false);
    // ε₀ ≤ 0 (line 13 holds the bounds).
    let f = law_job(&dir, "", &LAW_BOUNDS.replace("eps0_t = [5e-5", "eps0_t = [0.0"));
    expect_error(&dir, &f, &["law.toml:13:", "key 'law.bounds.eps0_t'", "must be > 0"], &[0, 2]);
    // A_c outside [0, 1].
    let f = law_job(&dir, "", &LAW_BOUNDS.replace("a_c = [0.5, 1.0]", "a_c = [0.5, 1.2]"));
    expect_error(&dir, &f, &["law.toml:13:", "key 'law.bounds.a_c'", "[0, 1]"], &[0]);
    // Inverted bounds.
    let f = law_job(&dir, "", &LAW_BOUNDS.replace("gf_t = [10.0, 90.0]", "gf_t = [90.0, 10.0]"));
    expect_error(&dir, &f, &["key 'law.bounds.gf_t'", "lower < upper", "[90, 10]"], &[0]);
}

#[test]
fn element_above_the_regularization_limit_gives_the_limit() {
    // hillerborg_no_elastic needs h < 2 E G_f / f_t² everywhere in the box; the smallest limit
    // is at gf_t = 10, eps0_t = 2e-4: 2 · 2.885e9 · 10 / (2.885e9 · 2e-4)² = 0.17331 m < h = 1.2 m.
    let dir = scratch("identify-limit");
    let p = known_law();
    write_law_curve(&dir.join("t.csv"), &p, 6e-4, true);
    write_law_curve(&dir.join("c.csv"), &p, 1.5e-2, false);
    let f = law_job(&dir, "regularization = \"hillerborg_no_elastic\"\nelement_size = 1.2\n", LAW_BOUNDS);
    let limit = 2.0 * 2.885e9 * 10.0 / (2.885e9f64 * 2e-4).powi(2);
    assert!((limit - 0.17331).abs() < 1e-4);
    expect_error(&dir, &f, &["key 'law.element_size'", "exceeds the limit 2 E G_f / f_t² = 0.1733"], &[0, 2]);
}

#[test]
fn empty_and_flat_dem_curves_are_rejected() {
    let dir = scratch("identify-flat");
    write_law_curve(&dir.join("t.csv"), &known_law(), 6e-4, true);
    std::fs::write(dir.join("c.csv"), "strain,stress\n0.0,0.0\n-1e-3,0.0\n-2e-3,0.0\n").unwrap();
    let f = law_job(&dir, "", LAW_BOUNDS);
    expect_error(&dir, &f, &["key 'law.dem_curves.compression'", "c.csv", "flat"], &[0]);
    std::fs::write(dir.join("c.csv"), "strain,stress\n").unwrap();
    expect_error(&dir, &f, &["key 'law.dem_curves.compression'", "at least two"], &[0]);
    std::fs::write(dir.join("c.csv"), "").unwrap();
    expect_error(&dir, &f, &["key 'law.dem_curves.compression'", "empty file"], &[0]);
}
