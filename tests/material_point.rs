//! The material-point job through the whole program: the curve against the closed form of the
//! law (paper §3.1), the pictures, and bad input — alone and under `mpirun -n 2`.
mod common;
use common::*;
use std::path::{Path, PathBuf};

const E: f64 = 2.885e9;
const EPS0_T: f64 = 5.0e-5;
const GF: f64 = 20.0;
const H: f64 = 0.10;

fn job(dir: &Path, material_extra: &str, path: &str, regularization: &str, h: f64) -> PathBuf {
    let text = format!(
        "[analysis]\ntype = \"material_point\"\nkinematics = \"plane_stress\"\nelement_size = {h:e}\n\
         [material]\nE = {E:e}\nnu = 0.19\neps0_t = {EPS0_T:e}\neps0_c = 5.0e-5\ngf_t = {GF:e}\na_c = 0.9\n\
         b_c = 2000.0\nregularization = \"{regularization}\"\n{material_extra}\
         [path]\n{path}\n[output]\ndir = \"out\"\nexisting = \"overwrite\"\n"
    );
    let f = dir.join("mp.toml");
    std::fs::write(&f, text).unwrap();
    f
}

const TENSION: &str = "type = \"uniaxial_tension\"\nmax_strain = 2.0e-3\nsteps = 200";

fn read_csv(file: &Path) -> (Vec<String>, Vec<Vec<f64>>) {
    let text = std::fs::read_to_string(file).unwrap();
    let mut lines = text.lines();
    let head: Vec<String> = lines.next().unwrap().split(',').map(String::from).collect();
    let rows = lines.map(|l| l.split(',').map(|v| v.parse().unwrap()).collect()).collect();
    (head, rows)
}

#[test]
fn uniaxial_tension_follows_the_closed_form() {
    // Closed form (paper §3.1, uniaxial stress, Hillerborg B_t = f_t h / G_f):
    //   σ = E ε up to ε₀;  σ = E ε₀ exp(−B_t (ε − ε₀)) after.  Tolerance 1e-9 relative
    //   (the driver's Newton tolerance on the free stress components is 1e-12).
    for np in [0, 2] {
        let dir = scratch(&format!("mp-tension-{np}"));
        let f = job(&dir, "", TENSION, "hillerborg", H);
        let out = run(np, &[f.to_str().unwrap()]);
        assert!(out.status.success(), "np={np}: {}", stderr(&out));
        let (head, rows) = read_csv(&dir.join("out/curve.csv"));
        let (ie, is) =
            (head.iter().position(|h| h == "strain_xx").unwrap(), head.iter().position(|h| h == "stress_xx").unwrap());
        let ft = E * EPS0_T;
        let bt = ft * H / GF;
        for r in &rows {
            let (eps, sig) = (r[ie], r[is]);
            let want = if eps <= EPS0_T { E * eps } else { ft * (-bt * (eps - EPS0_T)).exp() };
            assert!((sig - want).abs() <= 1e-9 * ft, "np={np}: ε = {eps}: σ = {sig}, closed form {want}");
        }
        let s: serde_json::Value = common::summary(&dir.join("out"));
        assert!((s["peak_stress"].as_f64().unwrap() - ft).abs() < 1e-9 * ft, "{s}");
        for png in ["stress_strain.png", "damage.png"] {
            let b = std::fs::read(dir.join("out").join(png)).unwrap();
            assert_eq!(&b[1..4], b"PNG", "{png}");
        }
    }
}

fn expect_error(
    name: &str,
    material_extra: &str,
    path: &str,
    regularization: &str,
    h: f64,
    code: i32,
    needles: &[&str],
) {
    let dir = scratch(name);
    let f = job(&dir, material_extra, path, regularization, h);
    for np in [0, 2] {
        let out = run(np, &[f.to_str().unwrap()]);
        let err = stderr(&out);
        assert_eq!(out.status.code(), Some(code), "np={np}: {err}");
        for n in needles {
            assert!(err.contains(n), "np={np}: message lacks '{n}':\n{err}");
        }
        assert_eq!(err.matches("error:").count(), 1, "np={np}: one message:\n{err}");
    }
}

#[test]
fn non_positive_threshold_is_located() {
    let dir = scratch("mp-eps0");
    let f = job(&dir, "", TENSION, "hillerborg", H);
    let text = std::fs::read_to_string(&f).unwrap().replace("eps0_t = 5e-5", "eps0_t = 0e0");
    std::fs::write(&f, &text).unwrap();
    for np in [0, 2] {
        let out = run(np, &[f.to_str().unwrap()]);
        let err = stderr(&out);
        assert_eq!(out.status.code(), Some(2), "{err}");
        assert!(
            err.contains("mp.toml:8:1: key 'material.eps0_t'") && err.contains("`eps0_t`: expected > 0, got 0"),
            "np={np}: {err}"
        );
    }
}

#[test]
fn a_c_outside_its_range() {
    let dir = scratch("mp-ac2");
    let f = job(&dir, "", TENSION, "hillerborg", H);
    let text = std::fs::read_to_string(&f).unwrap().replace("a_c = 0.9", "a_c = 1.5");
    std::fs::write(&f, &text).unwrap();
    let out = run(0, &[f.to_str().unwrap()]);
    let err = stderr(&out);
    assert_eq!(out.status.code(), Some(2), "{err}");
    assert!(err.contains("key 'material.a_c'") && err.contains("[0, 1]"), "{err}");
}

#[test]
fn element_above_the_regularization_limit_gives_the_limit() {
    // 2 E G_f / f_t² = 2 · 2.885e9 · 20 / (1.4425e5)² = 5.5459 m: an element of 6 m is too large.
    let limit = 2.0 * E * GF / (E * EPS0_T).powi(2);
    assert!((limit - 5.5459).abs() < 1e-3);
    expect_error(
        "mp-limit",
        "",
        TENSION,
        "hillerborg_no_elastic",
        6.0,
        2,
        &["key 'analysis.element_size'", "exceeds the limit 2 E G_f / f_t² = 5.545"],
    );
}

#[test]
fn unknown_path_key_is_located() {
    expect_error(
        "mp-path-key",
        "",
        "type = \"uniaxial_tension\"\nmax_strain = 2.0e-3\nstep = 200",
        "hillerborg",
        H,
        2,
        &["key 'path.step'", "unknown field `step`", "expected `max_strain` or `steps`"],
    );
}

#[test]
fn unknown_split_is_located() {
    // The [material] table's split names one of the two splits (material::split).
    expect_error(
        "mp-split",
        "split = \"spectrl\"\n",
        TENSION,
        "hillerborg",
        H,
        2,
        &["mp.toml:14:9: key 'material.split'", "unknown variant `spectrl`, expected `trace` or `spectral`"],
    );
}

#[test]
fn the_spectral_split_runs_through_the_job() {
    // A cyclic path with the spectral split: the job runs on 1 and 2 ranks and its curve starts on
    // the elastic line (σ = E ε in uniaxial stress below the threshold, 1e-9 relative).
    let dir = scratch("mp-spectral");
    let path = "type = \"uniaxial\"\ntargets = [2.0e-4, -4.0e-4, 3.0e-4]\nsteps_per_segment = 40";
    let f = job(&dir, "split = \"spectral\"\n", path, "hillerborg", H);
    for np in [0, 2] {
        let out = run(np, &[f.to_str().unwrap()]);
        assert!(out.status.success(), "np={np}: {}", stderr(&out));
    }
    let (head, rows) = read_csv(&dir.join("out/curve.csv"));
    let (ie, is) =
        (head.iter().position(|h| h == "strain_xx").unwrap(), head.iter().position(|h| h == "stress_xx").unwrap());
    let first = &rows[1];
    assert!(first[ie] > 0.0 && first[ie] < EPS0_T);
    assert!((first[is] - E * first[ie]).abs() <= 1e-9 * E * first[ie], "{:?}", first);
}
