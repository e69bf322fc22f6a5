//! Textbook verification of the linear static frame analysis, through the whole program (job
//! file → mesh → partition → PETSc solve → HDF5). Every expected value is a closed form of
//! Euler–Bernoulli beam theory (e.g. Gere & Timoshenko, *Mechanics of Materials*, App. G), for
//! which the 2-node frame element with consistent loads is nodally exact: tolerance 1e-10 relative.
//!
//! ```text
//!  cantilever                       propped cantilever               fixed-fixed, self-weight
//!  |=====o=====o=====o=====o -> P   |=========o=========o           |=========o=========|
//!  x=0                     x=L      A       P (mid)     B (uy=0)    A     q = ρAg       B
//! ```
mod common;
use common::*;

const E: f64 = 2.0e11;
const G: f64 = 8.0e10;
// area, iy, iz, j — iy ≠ iz so that a swapped bending plane fails the test.
const SEC: [f64; 4] = [1.0e-3, 2.0e-6, 5.0e-6, 3.0e-6];
const TOL: f64 = 1e-10;

fn rel(a: f64, b: f64) -> f64 {
    (a - b).abs() / b.abs()
}

/// A cantilever along x (default orientation: local y = global Y, local z = global Z), clamped
/// at x = 0, with `load` = [Fx Fy Fz Mx My Mz] at the tip; returns the tip's 6 displacements.
fn cantilever(name: &str, load: [f64; 6]) -> Vec<f64> {
    let dir = scratch(name);
    let l = 3.0;
    let n = 4;
    let nodes: Vec<[f64; 3]> = (0..=n).map(|i| [l * i as f64 / n as f64, 0.0, 0.0]).collect();
    let lines: Vec<[usize; 2]> = (0..n).map(|i| [i, i + 1]).collect();
    write_line_mesh(&dir.join("m.msh"), &nodes, &lines, &[("base", &[0]), ("tip", &[n])]);
    let extra = format!(
        "[[supports]]\ngroup = \"base\"\ndofs = [\"all\"]\n[[loads]]\ntype = \"nodal\"\ngroup = \"tip\"\n\
         force = [{:e}, {:e}, {:e}]\nmoment = [{:e}, {:e}, {:e}]\n",
        load[0], load[1], load[2], load[3], load[4], load[5]
    );
    std::fs::write(dir.join("job.toml"), frame_job("m.msh", E, G, SEC, None, &extra)).unwrap();
    let out = run(0, &[dir.join("job.toml").to_str().unwrap()]);
    assert!(out.status.success(), "run failed:\n{}\n{}", stdout(&out), stderr(&out));
    let u = node_field(&dir.join("out"), "displacement");
    let r = node_field(&dir.join("out"), "rotation");
    let tip = (n + 1) as u64;
    let mut v = u[&tip].clone();
    v.extend_from_slice(&r[&tip]);
    v
}

#[test]
fn cantilever_bending_in_the_xy_plane() {
    // P along y bends about local z: δ = PL³/(3 E Iz), θz = PL²/(2 E Iz).
    let (p, l): (f64, f64) = (1.0e3, 3.0);
    let v = cantilever("cant-y", [0.0, p, 0.0, 0.0, 0.0, 0.0]);
    let iz = SEC[2];
    assert!(rel(v[1], p * l.powi(3) / (3.0 * E * iz)) < TOL, "uy = {}", v[1]);
    assert!(rel(v[5], p * l * l / (2.0 * E * iz)) < TOL, "rz = {}", v[5]);
    assert!(v[0].abs() < 1e-15 && v[2].abs() < 1e-15, "{v:?}");
}

#[test]
fn cantilever_bending_in_the_xz_plane() {
    // P along z bends about local y: δ = PL³/(3 E Iy), θy = −PL²/(2 E Iy) (right-hand rule).
    let (p, l): (f64, f64) = (1.0e3, 3.0);
    let v = cantilever("cant-z", [0.0, 0.0, p, 0.0, 0.0, 0.0]);
    let iy = SEC[1];
    assert!(rel(v[2], p * l.powi(3) / (3.0 * E * iy)) < TOL, "uz = {}", v[2]);
    assert!(rel(v[4], -p * l * l / (2.0 * E * iy)) < TOL, "ry = {}", v[4]);
}

#[test]
fn cantilever_torsion_and_axial() {
    // θx = TL/(GJ); ux = NL/(EA).
    let (t, nf, l) = (500.0, 2.0e4, 3.0);
    let v = cantilever("cant-t", [nf, 0.0, 0.0, t, 0.0, 0.0]);
    assert!(rel(v[3], t * l / (G * SEC[3])) < TOL, "rx = {}", v[3]);
    assert!(rel(v[0], nf * l / (E * SEC[0])) < TOL, "ux = {}", v[0]);
}

#[test]
fn propped_cantilever_with_a_midspan_load() {
    // Clamped at A (x=0), vertical support at B (x=L), P downwards (−y) at midspan.
    // Closed forms: R_B = 5P/16; deflection under the load 7PL³/(768 E Iz).
    let dir = scratch("propped");
    let (l, p) = (4.0, 2.0e3);
    let nodes = [[0.0, 0.0, 0.0], [l / 2.0, 0.0, 0.0], [l, 0.0, 0.0]];
    write_line_mesh(&dir.join("m.msh"), &nodes, &[[0, 1], [1, 2]], &[("a", &[0]), ("mid", &[1]), ("b", &[2])]);
    let extra = format!(
        "[[supports]]\ngroup = \"a\"\ndofs = [\"all\"]\n[[supports]]\ngroup = \"b\"\ndofs = [\"uy\"]\n\
         [[loads]]\ntype = \"nodal\"\ngroup = \"mid\"\nforce = [0.0, {:e}, 0.0]\n",
        -p
    );
    std::fs::write(dir.join("job.toml"), frame_job("m.msh", E, G, SEC, None, &extra)).unwrap();
    let out = run(0, &[dir.join("job.toml").to_str().unwrap()]);
    assert!(out.status.success(), "{}", stderr(&out));
    let u = node_field(&dir.join("out"), "displacement");
    let r = node_field(&dir.join("out"), "reaction_force");
    assert!(rel(u[&2][1], -7.0 * p * l.powi(3) / (768.0 * E * SEC[2])) < TOL, "{:?}", u[&2]);
    assert!(rel(r[&3][1], 5.0 * p / 16.0) < TOL, "R_B = {:?}", r[&3]);
    assert!(rel(r[&1][1], 11.0 * p / 16.0) < TOL, "R_A = {:?}", r[&1]);
}

#[test]
fn fixed_fixed_beam_under_self_weight() {
    // q = ρ A g along −z; midspan deflection qL⁴/(384 E Iy); end reactions qL/2.
    let dir = scratch("selfweight");
    let (l, rho, g) = (6.0, 7850.0, 9.81);
    let nodes = [[0.0, 0.0, 0.0], [l / 2.0, 0.0, 0.0], [l, 0.0, 0.0]];
    write_line_mesh(&dir.join("m.msh"), &nodes, &[[0, 1], [1, 2]], &[("ends", &[0, 2])]);
    let extra =
        format!("[[supports]]\ngroup = \"ends\"\ndofs = [\"all\"]\n[gravity]\nacceleration = [0.0, 0.0, {:e}]\n", -g);
    let job = frame_job("m.msh", E, G, SEC, None, &extra).replace("density = 0.0", &format!("density = {rho:e}"));
    std::fs::write(dir.join("job.toml"), job).unwrap();
    let out = run(0, &[dir.join("job.toml").to_str().unwrap()]);
    assert!(out.status.success(), "{}", stderr(&out));
    let q = rho * SEC[0] * g;
    let u = node_field(&dir.join("out"), "displacement");
    let r = node_field(&dir.join("out"), "reaction_force");
    assert!(rel(u[&2][2], -q * l.powi(4) / (384.0 * E * SEC[1])) < TOL, "{:?}", u[&2]);
    assert!(rel(r[&1][2], q * l / 2.0) < TOL, "{:?}", r[&1]);
}
