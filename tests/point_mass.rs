//! Point masses (`[[masses]]`, per group or per node) through the whole program: their weight
//! under gravity, and the frequency of a cantilever carrying a tip mass.
//!
//! ```text
//!   clamped o===o===o=== ... ===o (M)     20 elastic frame elements along x, L = 2 m
//! ```
mod common;
use common::*;
use std::f64::consts::PI;

const E: f64 = 2.0e11;
const G: f64 = 8.0e10;
const RHO: f64 = 7850.0;
const L: f64 = 2.0;
const N: usize = 20;
// area, iy, iz, j
const SEC: [f64; 4] = [1.0e-3, 2.0e-6, 8.0e-6, 3.0e-6];

fn cantilever(dir: &std::path::Path, analysis: &str, density: f64, extra: &str) -> std::path::PathBuf {
    let nodes: Vec<[f64; 3]> = (0..=N).map(|i| [L * i as f64 / N as f64, 0.0, 0.0]).collect();
    let lines: Vec<[usize; 2]> = (0..N).map(|i| [i, i + 1]).collect();
    write_line_mesh(&dir.join("m.msh"), &nodes, &lines, &[("base", &[0]), ("tip", &[N]), ("middle", &[N / 2])]);
    let job =
        frame_job("m.msh", E, G, SEC, None, &format!("[[supports]]\ngroup = \"base\"\ndofs = [\"all\"]\n{extra}"))
            .replace("type = \"linear_static\"", analysis)
            .replace("density = 0.0", &format!("density = {density:e}"));
    std::fs::write(dir.join("job.toml"), job).unwrap();
    dir.join("job.toml")
}

/// Massless beam, a point mass M on the tip (by group) and M/2 in the middle (by node tag),
/// gravity −g z: the applied load sums to −1.5 M g (exact, 1e-12) and the tip deflection is the
/// superposition of the two point loads, M g L³/(3EI) + (M g/2)(L/2)²(3L − L/2)/(6EI)
/// (Gere & Timoshenko, cantilever table), exact for cubic elements: 1e-9.
#[test]
fn point_masses_weigh_under_gravity() {
    let dir = scratch("point-mass-weight");
    let (m, g) = (500.0, 9.81);
    let extra = format!(
        "[[masses]]\ngroup = \"tip\"\nmass = {m}\n[[masses]]\nnode = {}\nmass = {}\nrotary_inertia = [1.0, 2.0, 3.0]\n\
         [gravity]\nacceleration = [0.0, 0.0, -{g}]\n",
        N / 2 + 1,
        m / 2.0
    );
    let job = cantilever(&dir, "type = \"linear_static\"", 0.0, &extra);
    let out = run(0, &[job.to_str().unwrap()]);
    assert!(out.status.success(), "{}\n{}", stdout(&out), stderr(&out));
    let s: serde_json::Value = common::summary(&dir.join("out"));
    let fz = s["applied_sum"]["fz"].as_f64().unwrap();
    assert!((fz + 1.5 * m * g).abs() < 1e-12 * m * g, "applied {fz}");
    let u = node_field(&dir.join("out"), "displacement");
    let ei = E * SEC[1];
    let a = L / 2.0;
    let want = -(m * g * L.powi(3) / (3.0 * ei) + (m * g / 2.0) * a * a * (3.0 * L - a) / (6.0 * ei));
    let got = u[&(N as u64 + 1)][2];
    assert!((got - want).abs() < 1e-9 * want.abs(), "tip {got} vs {want}");
}

/// Cantilever of mass m = ρ A L with a tip mass M = m: the first bending frequency solves
/// 1 + cos β cosh β + (M/m) β (cos β sinh β − sin β cosh β) = 0 (β = β₁L; Blevins, *Formulas
/// for natural frequency and mode shape*, table 8-1 case 4; solved here by bisection), with
/// ω = β² sqrt(E I / (m L³)). 20 consistent-mass elements: within 0.5% (the issue's tolerance for
/// beams). The total mass reported counts M: (1 + 1) m, minus the clamped node's share (< 5%).
#[test]
fn tip_mass_lowers_the_cantilever_frequency_as_the_closed_form() {
    let dir = scratch("point-mass-modal");
    let mb = RHO * SEC[0] * L;
    let job =
        cantilever(&dir, "type = \"modal\"\nmodes = 2", RHO, &format!("[[masses]]\ngroup = \"tip\"\nmass = {mb}\n"));
    let out = run(0, &[job.to_str().unwrap()]);
    assert!(out.status.success(), "{}\n{}", stdout(&out), stderr(&out));
    let s: serde_json::Value = common::summary(&dir.join("out"));
    let f1 = s["modes"][0]["frequency"].as_f64().unwrap();
    let r = 1.0; // M / m
    let eq = |b: f64| 1.0 + b.cos() * b.cosh() + r * b * (b.cos() * b.sinh() - b.sin() * b.cosh());
    let (mut lo, mut hi) = (0.5, 1.875104);
    assert!(eq(lo) * eq(hi) < 0.0);
    for _ in 0..100 {
        let mid = 0.5 * (lo + hi);
        if eq(lo) * eq(mid) <= 0.0 {
            hi = mid;
        } else {
            lo = mid;
        }
    }
    let beta = 0.5 * (lo + hi);
    // Lowest mode: bending with the smaller I (iy, motion along z).
    let want = beta * beta * (E * SEC[1] / (mb / L * L.powi(4))).sqrt() / (2.0 * PI);
    println!("tip mass = beam mass: f1 = {f1:.5} Hz vs closed form {want:.5} Hz (β₁L = {beta:.6})");
    assert!((f1 - want).abs() < 5e-3 * want, "{f1} vs {want}");
    let total = s["total_mass"]["z"].as_f64().unwrap();
    assert!(total <= 2.0 * mb && total > 1.95 * mb, "total mass {total} vs {}", 2.0 * mb);
}

/// A point mass with both a group and a node, and a node tag the mesh lacks: clear errors naming
/// the key, exit code 2.
#[test]
fn bad_point_masses_are_clear_errors() {
    let dir = scratch("point-mass-bad");
    for (extra, expect) in [
        ("[[masses]]\ngroup = \"tip\"\nnode = 3\nmass = 1.0\n", "give either group or node"),
        ("[[masses]]\nnode = 999\nmass = 1.0\n", "no node with tag 999"),
        ("[[masses]]\ngroup = \"tip\"\nmass = -1.0\n", "masses[0].mass"),
    ] {
        let job = cantilever(&dir, "type = \"linear_static\"", 0.0, extra);
        let out = run(0, &[job.to_str().unwrap()]);
        let err = stderr(&out);
        assert_eq!(out.status.code(), Some(2), "{extra}: {err}");
        assert!(err.contains(expect) && !err.contains("panicked"), "{extra}: {err}");
    }
}
