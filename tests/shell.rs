//! Shells through the whole program: the Scordelis–Lo roof (MacNeal & Harder, "A proposed
//! standard set of problems to test finite element accuracy", 1985), on 1 and 2 ranks.
//!
//! ```text
//!   cylindrical roof, R = 25, L = 50, t = 0.25, half-angle 40°, E = 4.32e8, ν = 0,
//!   self weight 90 per unit area, rigid diaphragms at the ends (u_y = u_z = 0);
//!   quarter model 0 ≤ x ≤ 25, 0 ≤ φ ≤ 40° (φ from the crown), symmetric at x = 25 and φ = 0.
//!   Reference: vertical displacement at the middle of the free edge 0.3024 (tolerance 2% on
//!   16×16 MITC4, the issue's figure).
//! ```
mod common;
use common::*;

fn roof(dir: &std::path::Path, n: usize) -> std::path::PathBuf {
    let (r, half_l, phi_max) = (25.0f64, 25.0f64, 40f64.to_radians());
    let idx = |i: usize, j: usize| i * (n + 1) + j; // i along x, j along φ
    let mut nodes = Vec::new();
    for i in 0..=n {
        for j in 0..=n {
            let (x, phi) = (half_l * i as f64 / n as f64, phi_max * j as f64 / n as f64);
            nodes.push([x, r * phi.sin(), r * phi.cos()]);
        }
    }
    let mut quads = Vec::new();
    for i in 0..n {
        for j in 0..n {
            quads.push([idx(i, j), idx(i + 1, j), idx(i + 1, j + 1), idx(i, j + 1)]);
        }
    }
    let diaphragm: Vec<usize> = (0..=n).map(|j| idx(0, j)).collect();
    let midspan: Vec<usize> = (0..=n).map(|j| idx(n, j)).collect();
    let crown: Vec<usize> = (0..=n).map(|i| idx(i, 0)).collect();
    let point: Vec<usize> = vec![idx(n, n)];
    write_quad_mesh(
        &dir.join("roof.msh"),
        &nodes,
        &quads,
        "roof",
        &[("diaphragm", diaphragm), ("midspan", midspan), ("crown", crown), ("edge_mid", point)],
    );
    // Self weight 90 per unit area: density · t · g = 90 with g = 1 and t = 0.25 → density 360.
    let job = "[analysis]\ntype = \"linear_static\"\n[mesh]\nfile = \"roof.msh\"\n\
        [materials.m]\ntype = \"elastic\"\nE = 4.32e8\nnu = 0.0\ndensity = 360.0\n\
        [sections.s]\ntype = \"shell\"\nthickness = 0.25\n\
        [[parts]]\ngroup = \"roof\"\nsection = \"s\"\nmaterial = \"m\"\n\
        [[supports]]\ngroup = \"diaphragm\"\ndofs = [\"uy\", \"uz\"]\n\
        [[supports]]\ngroup = \"midspan\"\ndofs = [\"ux\", \"ry\", \"rz\"]\n\
        [[supports]]\ngroup = \"crown\"\ndofs = [\"uy\", \"rx\", \"rz\"]\n\
        [gravity]\nacceleration = [0.0, 0.0, -1.0]\n\
        [output]\ndir = \"out\"\nexisting = \"overwrite\"\n";
    std::fs::write(dir.join("roof.toml"), job).unwrap();
    dir.join("roof.toml")
}

#[test]
fn scordelis_lo_roof_on_one_and_two_ranks() {
    let n = 16;
    let mut results = Vec::new();
    for np in [1, 2] {
        let dir = scratch(&format!("scordelis-{np}"));
        let job = roof(&dir, n);
        let out = run(np, &[job.to_str().unwrap()]);
        assert!(out.status.success(), "np={np}: {}\n{}", stdout(&out), stderr(&out));
        let u = node_field(&dir.join("out"), "displacement");
        let tag = ((n + 1) * (n + 1)) as u64; // idx(n, n) + 1
        let uz = u[&tag][2];
        assert!((uz.abs() - 0.3024).abs() < 0.02 * 0.3024, "np={np}: u_z at the free edge midspan = {uz}, reference −0.3024");
        assert!(uz < 0.0, "the roof sags");
        results.push(u);
    }
    // 1 and 2 ranks agree (direct solver): 1e-10 of the largest displacement.
    let scale = results[0].values().flatten().fold(0.0f64, |m, x| m.max(x.abs()));
    for (id, a) in &results[0] {
        for (x, y) in a.iter().zip(&results[1][id]) {
            assert!((x - y).abs() <= 1e-10 * scale, "node {id}: {x} vs {y}");
        }
    }
}
