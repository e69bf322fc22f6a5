//! Fiber beams through the whole program: a cantilever's tip deflections and frequencies against
//! Euler–Bernoulli, and the non-structural mass per length of beams.
//!
//! ```text
//!   z
//!   |  section b = 0.3 (local y = global Y) × h = 0.5 (local z = global Z), 20 × 20 fibers
//!   o===o===o===o=== ... ===o  → x      10 elements, L = 3 m, clamped at x = 0, loads at the tip
//! ```
//! The fiber grid's second moments are I (1 − 1/n²) (element::fiber_section docs): with n = 20
//! the stiffness is 0.25% below the continuum's, so the deflections are 0.25% above and the frequencies
//! 0.125% below Euler–Bernoulli with the continuum I, inside the issue's 0.5%.
mod common;
use common::*;
use std::f64::consts::PI;

const E: f64 = 3.0e9;
const RHO: f64 = 2000.0;
const B: f64 = 0.3;
const H: f64 = 0.5;
const L: f64 = 3.0;
const N_EL: usize = 10;

fn cantilever(dir: &std::path::Path, analysis: &str, extra: &str) -> std::path::PathBuf {
    let nodes: Vec<[f64; 3]> = (0..=N_EL).map(|i| [L * i as f64 / N_EL as f64, 0.0, 0.0]).collect();
    let lines: Vec<[usize; 2]> = (0..N_EL).map(|i| [i, i + 1]).collect();
    write_line_mesh(&dir.join("m.msh"), &nodes, &lines, &[("base", &[0]), ("tip", &[N_EL])]);
    let job = format!(
        "[analysis]\n{analysis}\n[mesh]\nfile = \"m.msh\"\n\
         [materials.m]\ntype = \"elastic\"\nE = {E:e}\nnu = 0.2\ndensity = {RHO}\n\
         [sections.s]\ntype = \"fiber\"\nwidth = {B}\nheight = {H}\nny = 20\nnz = 20\n\
         [[parts]]\ngroup = \"beams\"\nsection = \"s\"\nmaterial = \"m\"\norientation = [0.0, 0.0, 1.0]\n\
         [[supports]]\ngroup = \"base\"\ndofs = [\"all\"]\n\
         [output]\ndir = \"out\"\nexisting = \"overwrite\"\n{extra}"
    );
    std::fs::write(dir.join("job.toml"), job).unwrap();
    dir.join("job.toml")
}

/// Tip loads P along Y, Z and X: v = P L³/(3 E Iz), w = P L³/(3 E Iy) (Gere & Timoshenko,
/// cantilever table) with the continuum Iz = h b³/12, Iy = b h³/12, within 0.5% (expected
/// +0.25%, module docs; the cubic elements are exact for the grid's I); u = P L/(E b h) to 1e-9.
#[test]
fn cantilever_tip_deflections_match_euler_bernoulli() {
    let dir = scratch("fiber-cantilever-static");
    let p = 1.0e4;
    let job = cantilever(
        &dir,
        "type = \"linear_static\"",
        &format!("[[loads]]\ntype = \"nodal\"\ngroup = \"tip\"\nforce = [{p:e}, {p:e}, {p:e}]\n"),
    );
    let out = run(0, &[job.to_str().unwrap()]);
    assert!(out.status.success(), "{}\n{}", stdout(&out), stderr(&out));
    let u = node_field(&dir.join("out"), "displacement");
    let tip = &u[&(N_EL as u64 + 1)];
    let (iz, iy) = (H * B.powi(3) / 12.0, B * H.powi(3) / 12.0);
    let v = p * L.powi(3) / (3.0 * E * iz);
    let w = p * L.powi(3) / (3.0 * E * iy);
    let ua = p * L / (E * B * H);
    for (got, want, what) in [(tip[1], v, "v (Y)"), (tip[2], w, "w (Z)")] {
        let rel = (got - want) / want;
        println!("{what}: {got:.6e} m vs Euler–Bernoulli {want:.6e} m ({:+.3}%)", 100.0 * rel);
        assert!(rel.abs() < 5e-3, "{what}: {got} vs {want}");
        // The grid's closed form: exactly (1 − 1/400)⁻¹ of it, to 1e-8 (direct solver).
        assert!((got - want / (1.0 - 1.0 / 400.0)).abs() < 1e-8 * want, "{what}: grid closed form");
    }
    assert!((tip[0] - ua).abs() < 1e-9 * ua, "axial {} vs {ua}", tip[0]);
}

fn frequencies(dir: &std::path::Path) -> Vec<f64> {
    let s: serde_json::Value = common::summary(&dir.join("out"));
    s["modes"].as_array().unwrap().iter().map(|m| m["frequency"].as_f64().unwrap()).collect()
}

/// The lowest bending frequencies f = (β L)²/(2π L²) sqrt(E I/(ρ A)), β₁L = 1.875104,
/// β₂L = 4.694091 (Blevins, *Formulas for natural frequency and mode shape*, table 8-1), in both
/// planes with the continuum I: within 0.5% (expected −0.125%, module docs; 10 consistent-mass
/// elements add < 1e-4); and the first torsion mode.
#[test]
fn cantilever_frequencies_match_euler_bernoulli() {
    let dir = scratch("fiber-cantilever-modal");
    let job = cantilever(&dir, "type = \"modal\"\nmodes = 5", "");
    let out = run(0, &[job.to_str().unwrap()]);
    assert!(out.status.success(), "{}\n{}", stdout(&out), stderr(&out));
    let f = frequencies(&dir);
    let eb = |beta_l: f64, i: f64| beta_l * beta_l / (2.0 * PI * L * L) * (E * i / (RHO * B * H)).sqrt();
    let (iz, iy) = (H * B.powi(3) / 12.0, B * H.powi(3) / 12.0);
    // Torsion (mode 4 here): f = sqrt(G J / (ρ Ip)) / (4 L) (Blevins table 8-19, fixed-free
    // shaft), with the model's J (Roark's rectangle formula) and Ip = b h (b² + h²)/12.
    let (a, c) = (H, B);
    let j = a * c.powi(3) * (1.0 / 3.0 - 0.21 * (c / a) * (1.0 - c.powi(4) / (12.0 * a.powi(4))));
    let g = E / 2.4;
    let torsion = (g * j / (RHO * B * H * (B * B + H * H) / 12.0)).sqrt() / (4.0 * L);
    let mut want = [eb(1.875104, iz), eb(1.875104, iy), eb(4.694091, iz), eb(4.694091, iy), torsion];
    want.sort_by(f64::total_cmp);
    for (k, w) in want.iter().enumerate() {
        let rel = (f[k] - w) / w;
        println!("mode {}: {:.5} Hz vs closed form {:.5} Hz ({:+.3}%)", k + 1, f[k], w, 100.0 * rel);
        assert!(rel.abs() < 5e-3, "mode {}: {} vs {w}", k + 1, f[k]);
    }
}

/// A non-structural mass per length equal to ρ A doubles the translational mass of every
/// element (and leaves the rotary inertia), so the bending frequencies of the elastic frame and of
/// the fiber beam drop by exactly √2 (bending modes carry no torsional inertia): 1e-7 relative
/// (eigensolver tolerance).
#[test]
fn nonstructural_mass_per_length_lowers_frequencies_by_root_two() {
    let ns = RHO * B * H;
    for (kind, section) in [
        ("fiber", format!("type = \"fiber\"\nwidth = {B}\nheight = {H}\nny = 4\nnz = 4\n")),
        ("frame", format!("type = \"frame\"\narea = {}\niy = 3.125e-3\niz = 1.125e-3\nj = 2.8e-3\n", B * H)),
    ] {
        let mut f = Vec::new();
        for extra in ["", &format!("nonstructural_mass = {ns}\n")] {
            let dir = scratch(&format!("nsm-{kind}-{}", extra.len()));
            let job = cantilever(&dir, "type = \"modal\"\nmodes = 2", "");
            let text = std::fs::read_to_string(&job).unwrap();
            let start = text.find("[sections.s]\n").unwrap() + "[sections.s]\n".len();
            let end = text.find("[[parts]]").unwrap();
            let text = format!("{}{section}{extra}{}", &text[..start], &text[end..]);
            std::fs::write(&job, text).unwrap();
            let out = run(0, &[job.to_str().unwrap()]);
            assert!(out.status.success(), "{kind}: {}\n{}", stdout(&out), stderr(&out));
            f.push(frequencies(&dir));
        }
        for k in 0..2 {
            let ratio = f[0][k] / f[1][k];
            assert!((ratio - 2f64.sqrt()).abs() < 1e-7 * 2f64.sqrt(), "{kind} mode {}: ratio {ratio}", k + 1);
        }
    }
}

/// Bad input names the key: one fiber across a side, a zero-length element (both nodes at the
/// same place), and an orientation vector along the member; exit code 2, no panic.
#[test]
fn bad_fiber_input_is_a_clear_error() {
    let dir = scratch("fiber-bad-input");
    let job = cantilever(&dir, "type = \"linear_static\"", "");
    let text = std::fs::read_to_string(&job).unwrap();
    for (from, to, expect) in [
        ("ny = 20", "ny = 1", "sections.s.ny"),
        ("orientation = [0.0, 0.0, 1.0]", "orientation = [2.0, 0.0, 0.0]", "parallel to the element axis"),
    ] {
        std::fs::write(&job, text.replace(from, to)).unwrap();
        let out = run(0, &[job.to_str().unwrap()]);
        let err = stderr(&out);
        assert_eq!(out.status.code(), Some(2), "{from}: {err}");
        assert!(err.contains(expect) && !err.contains("panicked"), "{from}: {err}");
    }
    // Zero length: the tip node moved onto its neighbour.
    let nodes: Vec<[f64; 3]> = (0..=N_EL).map(|i| [L * (i.min(N_EL - 1)) as f64 / N_EL as f64, 0.0, 0.0]).collect();
    let lines: Vec<[usize; 2]> = (0..N_EL).map(|i| [i, i + 1]).collect();
    write_line_mesh(&dir.join("m.msh"), &nodes, &lines, &[("base", &[0]), ("tip", &[N_EL])]);
    std::fs::write(&job, &text).unwrap();
    let out = run(0, &[job.to_str().unwrap()]);
    let err = stderr(&out);
    assert_eq!(out.status.code(), Some(2), "{err}");
    assert!(err.contains("zero-length") && err.contains("element 12"), "{err}");
}
