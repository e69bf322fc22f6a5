//! Natural frequencies of square plates through the whole program (MITC4 shells, block Lanczos), against
//! Leissa's values, on 1 and 2 ranks; effective masses of the simply supported plate.
//!
//! ```text
//!   a = 1 m square, t = 0.01 m (t/a = 0.01: Kirchhoff theory applies), E = 2.1e11 Pa, ν = 0.3,
//!   ρ = 7800 kg/m³, 24 × 24 MITC4, in-plane motion fixed (ux = uy = rz = 0 at every node, as in
//!   NAFEMS FV12) so only bending modes appear.
//!   f = λ / (2π a²) · sqrt(D / (ρ t)),  D = E t³ / (12 (1 − ν²))
//! ```
//! References (frequency parameter λ = ω a² sqrt(ρ t / D)):
//! * simply supported (SSSS): λ_mn = π² (m² + n²), exact (Leissa, *Vibration of Plates*, NASA
//!   SP-160, 1969, eq. 4.4): 19.739, 49.348 (twice), 78.957;
//! * cantilever (one edge clamped, CFFF), ν = 0.3: 3.4917, 8.5246, 21.429, 27.331, 31.111
//!   (Leissa, "The free vibration of rectangular plates", J. Sound Vib. 31(3), 1973, Table for
//!   C-F-F-F, a/b = 1; the same values, to four digits, in Barton, J. Appl. Mech. 18, 1951, as
//!   quoted by code_aster's validation case SDLS01).
//!
//! Tolerance 1% (the issue's).
mod common;
use common::*;
use std::f64::consts::PI;

const A: f64 = 1.0;
const T: f64 = 0.01;
const E: f64 = 2.1e11;
const NU: f64 = 0.3;
const RHO: f64 = 7800.0;
const N: usize = 24;

/// Frequency (Hz) of parameter λ.
fn freq(lambda: f64) -> f64 {
    let d = E * T.powi(3) / (12.0 * (1.0 - NU * NU));
    lambda / (2.0 * PI * A * A) * (d / (RHO * T)).sqrt()
}

/// Writes the plate and a modal job with the given supports; returns the job path.
fn plate(dir: &std::path::Path, modes: usize, supports: &str) -> std::path::PathBuf {
    plate_with_mass(dir, modes, supports, "consistent")
}

/// As [`plate`], with the mass `"consistent"` or `"lumped"`.
fn plate_with_mass(dir: &std::path::Path, modes: usize, supports: &str, mass: &str) -> std::path::PathBuf {
    let idx = |i: usize, j: usize| i * (N + 1) + j;
    let mut nodes = Vec::new();
    for i in 0..=N {
        for j in 0..=N {
            nodes.push([A * i as f64 / N as f64, A * j as f64 / N as f64, 0.0]);
        }
    }
    let mut quads = Vec::new();
    for i in 0..N {
        for j in 0..N {
            quads.push([idx(i, j), idx(i + 1, j), idx(i + 1, j + 1), idx(i, j + 1)]);
        }
    }
    let all: Vec<usize> = (0..nodes.len()).collect();
    let x_edges: Vec<usize> = (0..=N).flat_map(|j| [idx(0, j), idx(N, j)]).collect();
    let y_edges: Vec<usize> = (0..=N).flat_map(|i| [idx(i, 0), idx(i, N)]).collect();
    let clamped: Vec<usize> = (0..=N).map(|j| idx(0, j)).collect();
    write_quad_mesh(
        &dir.join("plate.msh"),
        &nodes,
        &quads,
        "plate",
        &[("all", all), ("x_edges", x_edges), ("y_edges", y_edges), ("clamped", clamped)],
    );
    let job = format!(
        "[analysis]\ntype = \"modal\"\nmodes = {modes}\nmass = \"{mass}\"\n[mesh]\nfile = \"plate.msh\"\n\
         [materials.steel]\ntype = \"elastic\"\nE = {E:e}\nnu = {NU}\ndensity = {RHO}\n\
         [sections.s]\ntype = \"shell\"\nthickness = {T}\n\
         [[parts]]\ngroup = \"plate\"\nsection = \"s\"\nmaterial = \"steel\"\n\
         [[supports]]\ngroup = \"all\"\ndofs = [\"ux\", \"uy\", \"rz\"]\n{supports}\
         [output]\ndir = \"out\"\nexisting = \"overwrite\"\n"
    );
    std::fs::write(dir.join("job.toml"), job).unwrap();
    dir.join("job.toml")
}

fn summary(dir: &std::path::Path) -> serde_json::Value {
    common::summary(&dir.join("out"))
}

fn frequencies(s: &serde_json::Value) -> Vec<f64> {
    s["modes"].as_array().unwrap().iter().map(|m| m["frequency"].as_f64().unwrap()).collect()
}

fn check(f: &[f64], lambdas: &[f64], what: &str) {
    for (k, &l) in lambdas.iter().enumerate() {
        let want = freq(l);
        let rel = (f[k] - want) / want;
        println!("{what} mode {}: {:.4} Hz vs Leissa {:.4} Hz (λ = {l}): {:+.3}%", k + 1, f[k], want, 100.0 * rel);
        assert!(rel.abs() < 0.01, "{what} mode {}: {} vs {want}", k + 1, f[k]);
    }
}

/// SSSS (hard simple support: w = 0 and the rotation about the edge fixed, as NAFEMS FV12),
/// on 1 and 2 ranks: the four lowest frequencies within 1% of Leissa; the two runs equal to
/// 1e-8 relative (same direct solver and eigensolver tolerance; the issue's figure). Effective
/// masses in z: mode (1,1) carries 64/π⁴ = 0.6570 of the plate mass ρ t a² (Kirchhoff modal
/// participation of sin·sin modes, Σ over odd m, n of 64/(π⁴ m² n²) = 1), within 3%: the
/// influence vector covers the free DOFs only, so the mass coupled to the supported edge nodes
/// (an O(h) band) is missed (−1.6% on 20 × 20); the cumulative ratios never decrease and stay
/// ≤ 1, and with six modes (adding (1,3) and (3,1), 64/(9π⁴) each) reach 0.803 of ρ t a²
/// within 3%.
#[test]
fn simply_supported_plate_on_one_and_two_ranks() {
    let supports = "[[supports]]\ngroup = \"x_edges\"\ndofs = [\"uz\", \"rx\"]\n\
                    [[supports]]\ngroup = \"y_edges\"\ndofs = [\"uz\", \"ry\"]\n";
    let mut runs = Vec::new();
    for np in [1, 2] {
        let dir = scratch(&format!("plate-ssss-{np}"));
        let job = plate(&dir, 6, supports);
        let out = run(np, &[job.to_str().unwrap()]);
        assert!(out.status.success(), "np={np}: {}\n{}", stdout(&out), stderr(&out));
        runs.push(summary(&dir));
    }
    let f = frequencies(&runs[0]);
    let pi2 = PI * PI;
    check(&f, &[2.0 * pi2, 5.0 * pi2, 5.0 * pi2, 8.0 * pi2], "SSSS");
    let f2 = frequencies(&runs[1]);
    for (a, b) in f.iter().zip(&f2) {
        assert!((a - b).abs() <= 1e-8 * a, "1 vs 2 ranks: {a} vs {b}");
    }
    let plate_mass = RHO * T * A * A;
    let modes = runs[0]["modes"].as_array().unwrap();
    let m1 = modes[0]["effective_mass"]["z"].as_f64().unwrap() / plate_mass;
    assert!((m1 - 64.0 / PI.powi(4)).abs() < 0.03 * 64.0 / PI.powi(4), "mode 1 effective mass ratio {m1}");
    let mut prev = 0.0;
    let mut sum = 0.0;
    for m in modes {
        let c = m["cumulative_ratio"]["z"].as_f64().unwrap();
        assert!(c <= 1.0 + 1e-9 && c + 1e-12 >= prev, "cumulative {c} after {prev}");
        prev = c;
        sum += m["effective_mass"]["z"].as_f64().unwrap();
    }
    let want6 = 64.0 / PI.powi(4) * (1.0 + 2.0 / 9.0);
    println!("SSSS effective mass in z: mode 1 {m1:.4} (64/π⁴ = 0.6570), six modes {:.4} (0.8030)", sum / plate_mass);
    assert!((sum / plate_mass - want6).abs() < 0.03 * want6, "six-mode effective mass {}", sum / plate_mass);
}

/// SSSS with a lumped mass, on 1 and 2 ranks: the path of a diagonal `M` (stored with one entry
/// per row, the eigensolver started on the free DOFs without purification). The four lowest
/// frequencies within 1% of Leissa, the two runs within 1e-8 of each other, and mode (1,1)'s
/// effective mass within 3% of 64/π⁴ of the plate mass (the figures of the consistent mass).
#[test]
fn simply_supported_plate_with_lumped_mass_on_one_and_two_ranks() {
    let supports = "[[supports]]\ngroup = \"x_edges\"\ndofs = [\"uz\", \"rx\"]\n\
                    [[supports]]\ngroup = \"y_edges\"\ndofs = [\"uz\", \"ry\"]\n";
    let mut runs = Vec::new();
    for np in [1, 2] {
        let dir = scratch(&format!("plate-ssss-lumped-{np}"));
        let job = plate_with_mass(&dir, 4, supports, "lumped");
        let out = run(np, &[job.to_str().unwrap()]);
        assert!(out.status.success(), "np={np}: {}\n{}", stdout(&out), stderr(&out));
        runs.push(summary(&dir));
    }
    let f = frequencies(&runs[0]);
    let pi2 = PI * PI;
    check(&f, &[2.0 * pi2, 5.0 * pi2, 5.0 * pi2, 8.0 * pi2], "SSSS lumped");
    for (a, b) in f.iter().zip(&frequencies(&runs[1])) {
        assert!((a - b).abs() <= 1e-8 * a, "1 vs 2 ranks: {a} vs {b}");
    }
    let m1 = runs[0]["modes"][0]["effective_mass"]["z"].as_f64().unwrap() / (RHO * T * A * A);
    let want = 64.0 / PI.powi(4);
    assert!((m1 - want).abs() < 0.03 * want, "mode 1 effective mass ratio {m1}");
}

/// CFFF (edge x = 0 clamped): the five lowest frequencies within 1% of Leissa (1973).
#[test]
fn cantilever_plate_matches_leissa() {
    let dir = scratch("plate-cfff");
    let job = plate(&dir, 5, "[[supports]]\ngroup = \"clamped\"\ndofs = [\"all\"]\n");
    let out = run(0, &[job.to_str().unwrap()]);
    assert!(out.status.success(), "{}\n{}", stdout(&out), stderr(&out));
    check(&frequencies(&summary(&dir)), &[3.4917, 8.5246, 21.429, 27.331, 31.111], "CFFF");
}
