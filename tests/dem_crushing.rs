//! The optional crushing extension of the DEM (`[mechanics] crushing_stress`, `crushing_energy`)
//! through the program: a small wall in compression reaches a peak and loses its load, crushed
//! beams are counted in `curve.csv` and drawn in the crack pictures; a key without its partner
//! is a located error.
mod common;
use common::{expect_job_error, run, scratch, stderr};
use std::path::{Path, PathBuf};

const SMALL_WALL: &str = "layout = { type = \"coursed\", width = 0.5, height = 0.6, n_courses = 5, n_per_course = 3, jitter = 0.2, size_variability = 0.2 }";

fn job(dir: &Path, mechanics: &str) -> PathBuf {
    let text = format!(
        "[analysis]\ntype = \"dem\"\nsamples = 2\nparticle_states = \"none\"\n\
         [sample]\nseed = 3\n{SMALL_WALL}\n\
         [mechanics]\n{mechanics}\n\
         [test]\ntype = \"compression\"\nmax_strain = 6.0e-3\nsteps = 30\n\
         [output]\ndir = \"out\"\nexisting = \"overwrite\"\n"
    );
    let f = dir.join("crush.toml");
    std::fs::write(&f, text).unwrap();
    f
}

fn last_row(csv: &Path) -> std::collections::BTreeMap<String, String> {
    let text = std::fs::read_to_string(csv).unwrap();
    let mut lines = text.lines();
    let head: Vec<String> = lines.next().unwrap().split(',').map(String::from).collect();
    let last = lines.last().unwrap();
    head.into_iter().zip(last.split(',').map(String::from)).collect()
}

/// σ_c = 3 MPa, G_c = 1 kJ/m² on two samples of a 15-stone wall, 2 ranks: each sample ends
/// after a peak (loss of load or collapse, not at the target strain), with crushed beams in
/// `curve.csv` and orange crushing cracks in `cracks-end.svg`; the peak lies below the largest
/// possible mean stress of contacts at σ_c (σ_c itself) and above the first crack.
#[test]
fn small_wall_with_crushing_peaks_and_counts_crushed_beams() {
    let dir = scratch("dem-crushing");
    let f = job(&dir, "crushing_stress = 3.0e6\ncrushing_energy = 1.0e3");
    let out = run(2, &[f.to_str().unwrap()]);
    assert!(out.status.success(), "{}", stderr(&out));
    let summary: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(dir.join("out/summary.json")).unwrap()).unwrap();
    for k in 0..2 {
        let sdir = dir.join(format!("out/sample-{k:03}"));
        let row = last_row(&sdir.join("curve.csv"));
        let crushed: usize = row["broken_crushing"].parse().unwrap();
        assert!(crushed > 0, "sample {k}: no crushed beam");
        let diss: f64 = row["dissipated_crushing"].parse().unwrap();
        assert!(diss > 0.0, "sample {k}: no crushing dissipation");
        let svg = std::fs::read_to_string(sdir.join("cracks-end.svg")).unwrap();
        assert!(svg.contains("#ff7f0e") && svg.contains("crushing"), "sample {k}: no crushing crack drawn");
    }
    let text = summary.to_string();
    assert!(!text.contains("\"target\""), "every sample ends after a peak: {text}");
    // A 15-stone wall has fewer than 1,000 unknowns: the default ("auto") keeps the Woodbury
    // path, and each sample's report says so.
    let samples = summary["samples"].as_array().unwrap();
    assert!(samples.iter().all(|s| s["factor_updates"] == "woodbury"), "{text}");
    let peak = summary.pointer("/peak_stress/mean").and_then(|v| v.as_f64()).unwrap_or(f64::NAN);
    assert!(peak > 0.5e6 && peak < 3.0e6, "peak {peak}");
}

/// A crushing key without its partner, or a non-positive crushing stress, is an error at that
/// key, printed once, alone and under `mpirun -n 2`.
#[test]
fn crushing_keys_are_checked() {
    let dir = scratch("dem-crushing-bad");
    let f = job(&dir, "crushing_stress = 3.0e6");
    expect_job_error(&f, 2, &["crush.toml:9:", "crushing_stress", "crushing_energy"]);
    let f = job(&dir, "crushing_energy = 1.0e3");
    expect_job_error(&f, 2, &["crush.toml:9:", "crushing_energy", "crushing_stress"]);
    let f = job(&dir, "crushing_stress = -3.0e6\ncrushing_energy = 1.0e3");
    expect_job_error(&f, 2, &["crush.toml:9:", "crushing_stress", "> 0"]);
}
