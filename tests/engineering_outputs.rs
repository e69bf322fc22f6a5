//! The engineering outputs of a time history through the whole program: the base reactions
//! (base shear) of `monitors.csv` and their peak in `summary.json`, the storey drifts of
//! `[[dynamics.drift]]`, and the model's mass and weight.
//!
//! ```text
//!   z ^  9----10---11   top row (group "top": node 10)     2 m wide, 3 m high, 0.3 m thick,
//!     |  |    |    |                                      2 × 3 elastic MITC4 quads,
//!     |  6----7----8                                      ρ = 2000 kg/m³: 600 kg per quad,
//!     |  |    |    |                                      lumped at its corners (A/4 each)
//!     |  3----4----5
//!     |  |    |    |
//!     +--0====1====2--> x   base: all DOFs fixed (the bottom quads' 2 × 2 quarter masses)
//! ```
//!
//! Mass that moves with the free DOFs: 6 quads less the base nodes' quarters (2 quads × 2 × 1/4
//! = 1 quad) = 5 × 600 = 3000 kg; the model's whole mass 3600 kg.
mod common;
use common::*;
use std::path::Path;

const QUAD_MASS: f64 = 2000.0 * 0.3 * 1.0 * 1.0;
const G: f64 = 9.81;

/// The elastic wall's job: `dynamics` is the `[dynamics]` body and what follows it.
fn wall_job(dir: &Path, e: f64, gravity: bool, extra: &str, dynamics: &str) {
    write_wall_mesh(dir);
    let gravity = if gravity { format!("[gravity]\nacceleration = [0.0, 0.0, -{G}]\n") } else { String::new() };
    let job = format!(
        "[analysis]\ntype = \"time_history\"\n[mesh]\nfile = \"m.msh\"\n\
         [materials.stone]\ntype = \"elastic\"\nE = {e:e}\nnu = 0.2\ndensity = 2000.0\n\
         [sections.wall]\ntype = \"shell\"\nthickness = 0.3\n\
         [[parts]]\ngroup = \"wall\"\nsection = \"wall\"\nmaterial = \"stone\"\n\
         [[supports]]\ngroup = \"base\"\ndofs = [\"all\"]\n{gravity}{extra}\
         [dynamics]\n{dynamics}\n[output]\ndir = \"out\"\nexisting = \"overwrite\"\n"
    );
    std::fs::write(dir.join("th.toml"), job).unwrap();
}

/// `monitors.csv` as its header and rows of numbers.
fn monitors(dir: &Path) -> (Vec<String>, Vec<Vec<f64>>) {
    let text = std::fs::read_to_string(dir.join("out/monitors.csv")).unwrap();
    let mut lines = text.lines();
    let header = lines.next().unwrap().split(',').map(str::to_string).collect();
    (header, lines.map(|l| l.split(',').map(|x| x.parse().unwrap()).collect()).collect())
}

fn column(header: &[String], name: &str) -> usize {
    header.iter().position(|h| h == name).unwrap_or_else(|| panic!("no column {name} in {header:?}"))
}

fn run_ok(np: usize, job: &Path) -> String {
    let out = run(np, &[job.to_str().unwrap()]);
    assert!(out.status.success(), "{}\n{}", stdout(&out), stderr(&out));
    stdout(&out)
}

/// A static load alone (gravity and a nodal force at the top, a ground at rest): at every step
/// the reactions balance the applied loads (equilibrium), within 1e-8 relative — the wall is
/// elastic, so gravity is one exact solve (MUMPS, round-off ~1e-14). The vertical reaction is
/// the weight carried by the free DOFs, 5 quads' weight (consistent gravity load: A/4 of a
/// rectangle's weight per corner). The storey drift between z = 0 and z = 3 m is the top row's
/// mean u_x over 3 m (the base nodes are fixed), and that of the groups `base`–`top` the top
/// node's u_x over 3 m: both as `results.h5` has them, to round-off.
#[test]
fn static_loads_are_balanced_by_the_base_reactions_and_drifts_follow_their_definition() {
    let dir = scratch("engineering-static");
    let (fx, fy) = (10.0e3, -4.0e3);
    std::fs::write(dir.join("rest.txt"), "# the ground at rest\n# columns: t [s]  a [m/s^2]\n0.0 0.0\n0.1 0.0\n")
        .unwrap();
    wall_job(
        &dir,
        1.0e10,
        true,
        &format!("[[loads]]\ntype = \"nodal\"\ngroup = \"top\"\nforce = [{fx:e}, {fy:e}, 0.0]\n"),
        "duration = 0.03\ndt = 0.01\n\
         [[dynamics.ground_motion]]\ndirection = \"x\"\nfile = \"rest.txt\"\nformat = \"two_column\"\nunits = \"m/s2\"\n\
         [[dynamics.drift]]\nname = \"levels\"\nlevels = [0.0, 3.0]\n\
         [[dynamics.drift]]\nname = \"groups\"\ngroups = [\"base\", \"top\"]\n",
    );
    for np in [0, 2] {
        let log = run_ok(np, &dir.join("th.toml"));
        let (h, rows) = monitors(&dir);
        assert_eq!(rows.len(), 4, "step 0 (gravity) and three steps");
        let weight_free = 5.0 * QUAD_MASS * G;
        for r in &rows {
            let (rx, ry, rz) = (r[column(&h, "reaction_x")], r[column(&h, "reaction_y")], r[column(&h, "reaction_z")]);
            assert!((rx + fx).abs() <= 1e-8 * fx.abs(), "np = {np}: reaction_x {rx} against the load {fx}");
            assert!((ry + fy).abs() <= 1e-8 * fy.abs(), "np = {np}: reaction_y {ry} against the load {fy}");
            assert!((rz - weight_free).abs() <= 1e-8 * weight_free, "np = {np}: reaction_z {rz}, {weight_free}");
        }
        // Drifts, from the displacements written at the last step (node tag = index + 1).
        let u = node_field(&dir.join("out"), "displacement");
        let top_row = (u[&10][0] + u[&11][0] + u[&12][0]) / 3.0;
        let last = rows.last().unwrap();
        for (name, expected) in [("levels", top_row / 3.0), ("groups", u[&11][0] / 3.0)] {
            let d = last[column(&h, &format!("drift:{name}:x"))];
            assert!(
                expected > 0.0 && (d - expected).abs() <= 1e-12 * expected,
                "np = {np}: drift {name} {d}, {expected}"
            );
        }
        let s = summary(&dir.join("out"));
        assert_eq!(s["format"], 2);
        let peak = s["peak_base_shear"]["x"].as_f64().unwrap();
        assert!((peak - fx).abs() <= 1e-8 * fx, "np = {np}: peak base shear {peak}");
        assert_eq!(s["drifts"][0]["nodes"]["upper"], 3, "np = {np}: the top row's nodes");
        assert_eq!(s["drifts"][1]["levels"]["upper"], 3.0);
        // The model's mass and weight: 6 quads, support nodes included.
        let m = s["model_mass"]["x"].as_f64().unwrap();
        assert!((m - 6.0 * QUAD_MASS).abs() <= 1e-9 * m, "np = {np}: model mass {m}");
        let w = s["weight"]["z"].as_f64().unwrap();
        assert!((w + 6.0 * QUAD_MASS * G).abs() <= 1e-9 * w.abs(), "np = {np}: weight {w}");
        assert!(log.contains("model: mass 3.600000e3 kg"), "np = {np}: the mass line:\n{log}");
        assert!(log.contains("peak base shear: x 1.0000e4 N"), "np = {np}:\n{log}");
    }
}

/// A stiff block under a constant base acceleration a = 1 m/s² along x: once the transient of
/// its (very high) elastic modes has died out, it moves with the ground and the base shear is
/// m·a, m the mass that moves with the free DOFs (3000 kg, lumped mass), within 1e-6 relative.
/// E = 1e13 Pa puts the wall's modes far above 1/dt, where HHT with α = −1/3 damps each step by
/// its spectral radius (1 + α)/(1 − α) = 1/2 (Hilber, Hughes & Taylor 1977): 60 steps leave
/// 2⁻⁶⁰ ≈ 1e-18 of the start. No gravity, so no vertical reaction.
#[test]
fn a_rigid_block_under_a_base_acceleration_has_a_base_shear_of_mass_times_acceleration() {
    let dir = scratch("engineering-rigid-block");
    let (a, duration, dt) = (1.0, 0.6, 0.01);
    let mut rec = String::from("# constant ground acceleration\n# columns: t [s]  a [m/s^2]\n");
    for i in 0..=70 {
        rec += &format!("{:.4} {a}\n", i as f64 * dt);
    }
    std::fs::write(dir.join("const.txt"), rec).unwrap();
    wall_job(
        &dir,
        1.0e13,
        false,
        "",
        &format!(
            "duration = {duration}\ndt = {dt}\nscheme = \"hht\"\nalpha = -0.333333333333333\nmass = \"lumped\"\n\
             [[dynamics.ground_motion]]\ndirection = \"x\"\nfile = \"const.txt\"\nformat = \"two_column\"\nunits = \"m/s2\"\n"
        ),
    );
    for np in [0, 2] {
        run_ok(np, &dir.join("th.toml"));
        let (h, rows) = monitors(&dir);
        let last = rows.last().unwrap();
        let m = 5.0 * QUAD_MASS;
        let rx = last[column(&h, "reaction_x")];
        assert!((rx - m * a).abs() <= 1e-6 * m * a, "np = {np}: base shear {rx} against m a = {}", m * a);
        for c in ["reaction_y", "reaction_z"] {
            assert!(last[column(&h, c)].abs() <= 1e-9 * m * a, "np = {np}: {c} = {}", last[column(&h, c)]);
        }
    }
}
