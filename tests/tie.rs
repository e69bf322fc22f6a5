//! Iron tie rods through the whole program: a tied portal — two masonry piers clamped at their
//! base, their tops joined by a tie — against closed forms.
//!
//! ```text
//!        node 4 o=========== tie (node 4 → 8) ===========o node 8      H = 6 m, S = 8 m
//!   P_left →    |                                        |   ← P_right
//!               |  pier: 3 elastic frame elements        |    E = 3 GPa, 1.0 × 1.2 m:
//!               |  (bending along x resisted by Iy)       |    Iy = 0.144 m⁴
//!              ===  base, clamped                        ===
//!             x = 0                                     x = S
//! ```
//!
//! Each pier is a cantilever with tip stiffness k_c = 3 E Iy / H³ = 6.0e6 N/m (Euler–Bernoulli;
//! cubic frame elements are nodally exact for tip loads), the tie a spring k_t = E_t A_t / S =
//! 190 GPa × 1.6e-3 m² / 8 m = 3.8e7 N/m between the tops (horizontal: the piers carry no axial
//! force). Tops move by u₁ (left) and u₂ (right) along x; the tie's elongation is δ = u₂ − u₁ and
//! its force N = N₀ + k_t δ. Equilibrium of the tops: k_c u₁ = P₁ + N, k_c u₂ = P₂ − N.
//! The element and the solve are exact, so every check is 1e-8 relative (round-off is ~1e-12).
//!
//! (a) a horizontal load, (b) a pretension (linear statics, a static nonlinear load stage, a time
//! history's gravity phase), (c) tension only; (d) a single pier tied to an anchored support:
//! statics, modes, and a time history through the slack and taut branches.
mod common;
use common::*;
use std::path::{Path, PathBuf};

const H: f64 = 6.0;
const S: f64 = 8.0;
const E_PIER: f64 = 3.0e9;
const IY: f64 = 0.144;
const E_TIE: f64 = 190.0e9;
const A_TIE: f64 = 1.6e-3;
const TOL: f64 = 1e-8;
/// Gmsh tags: points 1–4 (base ×2, the two tops), pier lines 5–10, the tie 11.
const TIE_TAG: u64 = 11;
const LEFT_TOP: u64 = 4;
const RIGHT_TOP: u64 = 8;

fn k_pier() -> f64 {
    3.0 * E_PIER * IY / H.powi(3)
}

fn k_tie() -> f64 {
    E_TIE * A_TIE / S
}

fn rel(a: f64, b: f64) -> f64 {
    (a - b).abs() / b.abs()
}

/// Writes the portal's mesh and a job with the given `[analysis]` body, tie section keys and
/// extra TOML (loads, dynamics); returns the job path.
fn portal(dir: &Path, analysis: &str, tie: &str, extra: &str) -> PathBuf {
    let mut nodes = Vec::new();
    for x in [0.0, S] {
        for i in 0..=3 {
            nodes.push([x, 0.0, H * i as f64 / 3.0]);
        }
    }
    let lines: Vec<[usize; 2]> = vec![[0, 1], [1, 2], [2, 3], [4, 5], [5, 6], [6, 7], [3, 7]];
    write_line_mesh_groups(
        &dir.join("portal.msh"),
        &nodes,
        &lines,
        &[("piers", (0..6).collect()), ("tie", vec![6])],
        &[("base", &[0, 4]), ("left_top", &[3]), ("right_top", &[7])],
    );
    let job = format!(
        "[analysis]\n{analysis}\n[mesh]\nfile = \"portal.msh\"\n\
         [materials.masonry]\ntype = \"elastic\"\nE = {E_PIER:e}\nnu = 0.2\ndensity = 1800.0\n\
         [materials.wrought_iron]\ntype = \"elastic\"\nE = {E_TIE:e}\nnu = 0.3\ndensity = 7700.0\n\
         [sections.pier]\ntype = \"frame\"\narea = 1.2\niy = {IY:e}\niz = 0.1\nj = 0.2\n\
         [sections.nave_tie]\ntype = \"tie\"\narea = {A_TIE:e}\n{tie}\n\
         [[parts]]\ngroup = \"piers\"\nsection = \"pier\"\nmaterial = \"masonry\"\norientation = [1.0, 0.0, 0.0]\n\
         [[parts]]\ngroup = \"tie\"\nsection = \"nave_tie\"\nmaterial = \"wrought_iron\"\n\
         [[supports]]\ngroup = \"base\"\ndofs = [\"all\"]\n\
         [output]\ndir = \"out\"\nexisting = \"overwrite\"\n{extra}"
    );
    std::fs::write(dir.join("job.toml"), job).unwrap();
    dir.join("job.toml")
}

/// Horizontal loads on the tops (N along x).
fn top_loads(left: f64, right: f64) -> String {
    format!(
        "[[loads]]\ntype = \"nodal\"\ngroup = \"left_top\"\nforce = [{left:e}, 0.0, 0.0]\n\
         [[loads]]\ntype = \"nodal\"\ngroup = \"right_top\"\nforce = [{right:e}, 0.0, 0.0]\n"
    )
}

/// Runs `job` on `np` ranks (0: no mpirun); returns (u₁, u₂, N, strain) at the last step.
fn run_portal(np: usize, job: &Path) -> (f64, f64, f64, f64) {
    let out = run(np, &[job.to_str().unwrap()]);
    assert!(out.status.success(), "np={np}:\n{}\n{}", stdout(&out), stderr(&out));
    let dir = job.parent().unwrap().join("out");
    let u = node_field(&dir, "displacement");
    let n = cell_field(&dir, "axial_force");
    let eps = cell_field(&dir, "strain");
    for tag in [LEFT_TOP, RIGHT_TOP] {
        assert!(
            u[&tag][1].abs() < 1e-14 && u[&tag][2].abs() < 1e-12,
            "np={np}: top {tag} moves out of the x direction: {:?}",
            u[&tag]
        );
    }
    (u[&LEFT_TOP][0], u[&RIGHT_TOP][0], n[&TIE_TAG][0], eps[&TIE_TAG][0])
}

fn linear_static() -> &'static str {
    "type = \"linear_static\""
}

fn static_nonlinear(steps: usize) -> String {
    format!("type = \"static_nonlinear\"\nsteps = {steps}")
}

/// (a) The left top pulled outwards by P (−x), linear statics: solving the two top equations,
/// u₁ = −P (k_c + k_t) / (k_c (k_c + 2 k_t)), u₂ = −P k_t / (k_c (k_c + 2 k_t)),
/// N = P k_t / (k_c + 2 k_t) (tension), strain N / (E_t A_t). Base shears balance P. 1 and 2 ranks.
#[test]
fn tied_portal_under_a_horizontal_load() {
    let p = 1.0e5;
    let (kc, kt) = (k_pier(), k_tie());
    let want_u1 = -p * (kc + kt) / (kc * (kc + 2.0 * kt));
    let want_u2 = -p * kt / (kc * (kc + 2.0 * kt));
    let want_n = p * kt / (kc + 2.0 * kt);
    for np in [0, 2] {
        let dir = scratch(&format!("tie-portal-{np}"));
        let job = portal(&dir, linear_static(), "", &top_loads(-p, 0.0));
        let (u1, u2, n, eps) = run_portal(np, &job);
        assert!(rel(u1, want_u1) < TOL, "np={np}: u1 = {u1:e} vs {want_u1:e}");
        assert!(rel(u2, want_u2) < TOL, "np={np}: u2 = {u2:e} vs {want_u2:e}");
        assert!(rel(n, want_n) < TOL, "np={np}: N = {n:e} vs {want_n:e}");
        assert!(rel(eps, want_n / (E_TIE * A_TIE)) < TOL, "np={np}: strain {eps:e}");
        let s = summary(&dir.join("out"));
        let residual = s["equilibrium_residual"].as_f64().unwrap();
        assert!(residual < 1e-10, "np={np}: equilibrium residual {residual:e}");
        let rx = s["reaction_sum"]["fx"].as_f64().unwrap();
        assert!(rel(rx, p) < TOL, "np={np}: base shear {rx} vs {p}");
        eprintln!(
            "np={np}: u1 = {u1:.9e} m, u2 = {u2:.9e} m, N = {n:.9e} N; relative errors {:.1e} {:.1e} {:.1e}",
            rel(u1, want_u1),
            rel(u2, want_u2),
            rel(n, want_n)
        );
    }
}

/// (b) Pretension N₀ and no other load: the tie pulls the tops together. The piers in series,
/// k_f = k_c / 2, against the tie: N = N₀ k_f / (k_f + k_t) = N₀ k_c / (k_c + 2 k_t); the tops
/// move inwards by N / k_c each (u₁ = +N/k_c, u₂ = −N/k_c), the tie's strain is
/// (N − N₀)/(E_t A_t) < 0 and the left base's reaction −N along x. The same state from linear
/// statics (1 and 2 ranks), from a static nonlinear load stage in 4 steps (the pretension ramped
/// with λ like any static load) and from the gravity phase of a time history under a ground at
/// rest (held for the 5 steps that follow).
#[test]
fn pretension_pulls_the_tops_together() {
    let n0 = 5.0e4;
    let (kc, kt) = (k_pier(), k_tie());
    let want_n = n0 * kc / (kc + 2.0 * kt);
    let want_u = want_n / kc;
    let tie = format!("pretension = {n0:e}");
    let dynamics = "[dynamics]\nduration = 0.05\ndt = 0.01\ngravity_steps = 3\n\
                    [[dynamics.ground_motion]]\ndirection = \"x\"\nfile = \"rest.txt\"\nformat = \"two_column\"\nunits = \"m/s2\"\n";
    let cases: [(&str, usize, String, &str); 4] = [
        ("linear", 0, linear_static().to_string(), ""),
        ("linear", 2, linear_static().to_string(), ""),
        ("nonlinear", 0, static_nonlinear(4), ""),
        ("time-history", 0, "type = \"time_history\"".to_string(), dynamics),
    ];
    for (name, np, analysis, extra) in cases {
        let dir = scratch(&format!("tie-pretension-{name}-{np}"));
        std::fs::write(dir.join("rest.txt"), "0.0 0.0\n0.1 0.0\n").unwrap();
        let job = portal(&dir, &analysis, &tie, extra);
        let (u1, u2, n, eps) = run_portal(np, &job);
        assert!(rel(n, want_n) < TOL, "{name} np={np}: N = {n:e} vs {want_n:e}");
        assert!(
            rel(u1, want_u) < TOL && rel(u2, -want_u) < TOL,
            "{name} np={np}: u1 = {u1:e}, u2 = {u2:e} vs ±{want_u:e}"
        );
        assert!(rel(eps, (want_n - n0) / (E_TIE * A_TIE)) < TOL, "{name} np={np}: strain {eps:e}");
        if name == "linear" {
            let r = node_field(&dir.join("out"), "reaction_force");
            assert!(rel(r[&1][0], -want_n) < TOL, "{name} np={np}: left base reaction {:?}", r[&1]);
        }
        eprintln!(
            "{name} np={np}: N = {n:.9e} N, tops inwards by {u1:.9e} m; relative errors {:.1e} {:.1e}",
            rel(n, want_n),
            rel(u1, want_u)
        );
    }
}

/// (c) Tension only, static nonlinear (2 load steps). Tops pulled apart (P outwards on each):
/// u = P / (k_c + 2 k_t) outwards, N = 2 k_t P / (k_c + 2 k_t). Pushed together: the tie goes
/// slack, N = 0, each pier alone, u = P / k_c inwards, strain −2u/S; with `tension_only = false`
/// the tie is compressed instead, u = P/(k_c + 2 k_t), N = −2 k_t P/(k_c + 2 k_t). With a
/// pretension N₀ and the tops pushed together: taut while N₀ k_c > 2 k_t P, where
/// u = (P + N₀)/(k_c + 2 k_t) and N = (N₀ k_c − 2 k_t P)/(k_c + 2 k_t); beyond, slack as without
/// pretension (the pretension load and the slack tie's force cancel).
#[test]
fn tension_only_tie_carries_no_compression() {
    let (kc, kt) = (k_pier(), k_tie());
    let n0 = 5.0e4;
    // (name, tie keys, P (inwards on each top, negative = outwards), ranks, u₁ and N expected)
    let p = 1.0e5;
    let cases: Vec<(&str, String, f64, usize, f64, f64)> = vec![
        ("apart", String::new(), -p, 0, -p / (kc + 2.0 * kt), 2.0 * kt * p / (kc + 2.0 * kt)),
        ("together", String::new(), p, 0, p / kc, 0.0),
        ("together", String::new(), p, 2, p / kc, 0.0),
        (
            "together-both-ways",
            "tension_only = false".into(),
            p,
            0,
            p / (kc + 2.0 * kt),
            -2.0 * kt * p / (kc + 2.0 * kt),
        ),
        (
            "together-pretensioned-taut",
            format!("pretension = {n0:e}"),
            1.0e3,
            0,
            (1.0e3 + n0) / (kc + 2.0 * kt),
            (n0 * kc - 2.0 * kt * 1.0e3) / (kc + 2.0 * kt),
        ),
        ("together-pretensioned-slack", format!("pretension = {n0:e}"), p, 0, p / kc, 0.0),
    ];
    for (name, tie, load, np, want_u1, want_n) in cases {
        let dir = scratch(&format!("tie-tension-only-{name}-{np}"));
        let job = portal(&dir, &static_nonlinear(2), &tie, &top_loads(load, -load));
        let (u1, u2, n, eps) = run_portal(np, &job);
        assert!(
            rel(u1, want_u1) < TOL && rel(u2, -want_u1) < TOL,
            "{name} np={np}: u1 = {u1:e}, u2 = {u2:e} vs ±{want_u1:e}"
        );
        if want_n == 0.0 {
            assert_eq!(n, 0.0, "{name} np={np}: a slack tie carries nothing");
        } else {
            assert!(rel(n, want_n) < TOL, "{name} np={np}: N = {n:e} vs {want_n:e}");
        }
        assert!(rel(eps, -2.0 * want_u1 / S) < TOL, "{name} np={np}: strain {eps:e}");
        eprintln!(
            "{name} np={np}: u1 = {u1:.9e} m, N = {n:.9e} N; relative errors {:.1e} {:.1e}",
            rel(u1, want_u1),
            if want_n == 0.0 { n.abs() } else { rel(n, want_n) }
        );
    }
}

/// The left pier alone, its top tied to an anchor: node 5 at (S, 0, H), which only the tie
/// reaches, held by a support in every DOF (`StructuralModel::anchors`). Massless pier and tie, a
/// point mass `mass` on the top; returns the job path.
fn anchored(dir: &Path, analysis: &str, extra: &str) -> PathBuf {
    let nodes: Vec<[f64; 3]> = (0..=3).map(|i| [0.0, 0.0, H * i as f64 / 3.0]).chain([[S, 0.0, H]]).collect();
    let lines: Vec<[usize; 2]> = vec![[0, 1], [1, 2], [2, 3], [3, 4]];
    write_line_mesh_groups(
        &dir.join("anchored.msh"),
        &nodes,
        &lines,
        &[("pier", (0..3).collect()), ("tie", vec![3])],
        &[("base", &[0]), ("top", &[3]), ("anchor", &[4])],
    );
    let job = format!(
        "[analysis]\n{analysis}\n[mesh]\nfile = \"anchored.msh\"\n\
         [materials.masonry]\ntype = \"elastic\"\nE = {E_PIER:e}\nnu = 0.2\n\
         [materials.wrought_iron]\ntype = \"elastic\"\nE = {E_TIE:e}\nnu = 0.3\n\
         [sections.pier]\ntype = \"frame\"\narea = 1.2\niy = {IY:e}\niz = 0.1\nj = 0.2\n\
         [sections.nave_tie]\ntype = \"tie\"\narea = {A_TIE:e}\n\
         [[parts]]\ngroup = \"pier\"\nsection = \"pier\"\nmaterial = \"masonry\"\norientation = [1.0, 0.0, 0.0]\n\
         [[parts]]\ngroup = \"tie\"\nsection = \"nave_tie\"\nmaterial = \"wrought_iron\"\n\
         [[supports]]\ngroup = \"base\"\ndofs = [\"all\"]\n\
         [[supports]]\ngroup = \"anchor\"\ndofs = [\"ux\", \"uy\", \"uz\"]\n\
         [output]\ndir = \"out\"\nexisting = \"overwrite\"\n{extra}"
    );
    std::fs::write(dir.join("job.toml"), job).unwrap();
    dir.join("job.toml")
}

/// (d) A tie anchored to a support (its rotations fixed by the model, its other DOFs by the
/// support): the top pulled away from the anchor by P moves by u = −P/(k_c + k_t), the tie
/// carries N = k_t P/(k_c + k_t) and the anchor's support pulls back with R_x = +N, no moment
/// (1 and 2 ranks, 1e-8). Modal, with a point mass m on the top: the mode along x has
/// ω² = (k_c + k_t)/m, the one along y ω² = 3 E Iz / (H³ m) (massless pier: exact, 1e-8). A time
/// history with the top shaken along x runs through the tie's slack and taut branches (its
/// anchored end keeps the fixed rows regular with no damping at all).
#[test]
fn tie_anchored_to_a_support() {
    let p = 1.0e5;
    let (kc, kt) = (k_pier(), k_tie());
    let loads = format!("[[loads]]\ntype = \"nodal\"\ngroup = \"top\"\nforce = [{:e}, 0.0, 0.0]\n", -p);
    for np in [0, 2] {
        let dir = scratch(&format!("tie-anchored-{np}"));
        let job = anchored(&dir, linear_static(), &loads);
        let out = run(np, &[job.to_str().unwrap()]);
        assert!(out.status.success(), "np={np}:\n{}\n{}", stdout(&out), stderr(&out));
        let out_dir = dir.join("out");
        let u = node_field(&out_dir, "displacement");
        let r = node_field(&out_dir, "reaction_force");
        let rm = node_field(&out_dir, "reaction_moment");
        let n = cell_field(&out_dir, "axial_force");
        let want_n = kt * p / (kc + kt);
        assert!(rel(u[&4][0], -p / (kc + kt)) < TOL, "np={np}: top {:?}", u[&4]);
        assert!(rel(n[&7][0], want_n) < TOL, "np={np}: N = {:e} vs {want_n:e}", n[&7][0]);
        assert!(rel(r[&5][0], want_n) < TOL && r[&5][1].abs() < 1e-9 * p, "np={np}: anchor reaction {:?}", r[&5]);
        assert!(rm[&5].iter().all(|m| *m == 0.0), "np={np}: anchor moment {:?}", rm[&5]);
        assert!(summary(&out_dir)["equilibrium_residual"].as_f64().unwrap() < 1e-10);
    }

    let m = 2.0e4;
    let dir = scratch("tie-anchored-modal");
    let job = anchored(&dir, "type = \"modal\"\nmodes = 2", &format!("[[masses]]\ngroup = \"top\"\nmass = {m:e}\n"));
    let out = run(0, &[job.to_str().unwrap()]);
    assert!(out.status.success(), "{}\n{}", stdout(&out), stderr(&out));
    let s = summary(&dir.join("out"));
    let f = |k: usize| s["modes"][k]["frequency"].as_f64().unwrap();
    let two_pi = 2.0 * std::f64::consts::PI;
    let (want_y, want_x) = ((3.0 * E_PIER * 0.1 / H.powi(3) / m).sqrt() / two_pi, ((kc + kt) / m).sqrt() / two_pi);
    assert!(rel(f(0), want_y) < TOL && rel(f(1), want_x) < TOL, "modes {} {} Hz vs {want_y} {want_x} Hz", f(0), f(1));

    let dir = scratch("tie-anchored-shaken");
    let record: String = (0..=200)
        .map(|i| {
            format!(
                "{:.4} {:.10e}\n",
                i as f64 * 0.005,
                5.0 * (2.0 * std::f64::consts::PI * 4.0 * i as f64 * 0.005).sin()
            )
        })
        .collect();
    std::fs::write(dir.join("shake.txt"), record).unwrap();
    let dynamics = format!(
        "[[masses]]\ngroup = \"top\"\nmass = {m:e}\n\
         [dynamics]\nduration = 1.0\ndt = 0.005\noutput_every = 1\n\
         [[dynamics.ground_motion]]\ndirection = \"x\"\nfile = \"shake.txt\"\nformat = \"two_column\"\nunits = \"m/s2\"\n"
    );
    let job = anchored(&dir, "type = \"time_history\"", &dynamics);
    let out = run(0, &[job.to_str().unwrap()]);
    assert!(out.status.success(), "{}\n{}", stdout(&out), stderr(&out));
    let h5 = hdf5::File::open(dir.join("out/results.h5")).unwrap();
    let ids: Vec<u64> = h5.dataset("mesh/cell_ids").unwrap().read_raw().unwrap();
    let at = ids.iter().position(|&t| t == 7).unwrap();
    let forces: Vec<f64> = h5
        .group("steps")
        .unwrap()
        .member_names()
        .unwrap()
        .iter()
        .filter(|k| k.parse::<usize>().is_ok())
        .map(|k| h5.dataset(&format!("steps/{k}/axial_force")).unwrap().read_raw::<f64>().unwrap()[at])
        .collect();
    let slack = forces.iter().filter(|&&n| n == 0.0).count();
    let max = forces.iter().fold(0.0f64, |a, &n| a.max(n));
    eprintln!("shaken: {} steps, slack in {slack}, largest tie force {max:.4e} N", forces.len());
    assert!(forces.iter().all(|&n| n >= 0.0), "a tension-only tie in compression");
    assert!(slack > 0 && max > 0.0, "both branches: slack in {slack} steps, largest force {max}");
}
