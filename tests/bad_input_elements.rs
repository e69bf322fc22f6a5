//! Bad input for shells, beams and ties: each broken variant of a small valid shell-and-beam
//! model (or of a tied portal, [`tie_case`]) fails with one clear message (element tag and group,
//! what is wrong, the limit) and a non-zero exit code, alone and under `mpirun -n 2` (no hang, no
//! panic, printed once).
//!
//! ```text
//!   4 (0,0,1) ---- 5 (1,0,1) ---- 6 (2,0,1)      shells in the x–z plane: quad 1-2-5-4,
//!     |    quad     |  tri /  |                   triangles 2-3-6 and 2-6-5; a beam 4-7 along y
//!   1 (0,0,0) ---- 2 (1,0,0) ---- 3 (2,0,0)      base 1-2-3 clamped; 7 = (0,1,1)
//! ```
mod common;
use common::*;
use std::path::{Path, PathBuf};

/// Writes the valid model in `dir`; returns the job path.
fn valid_case(dir: &Path) -> PathBuf {
    let nodes: [[f64; 3]; 7] = [
        [0.0, 0.0, 0.0],
        [1.0, 0.0, 0.0],
        [2.0, 0.0, 0.0],
        [0.0, 0.0, 1.0],
        [1.0, 0.0, 1.0],
        [2.0, 0.0, 1.0],
        [0.0, 1.0, 1.0],
    ];
    write_mesh(dir, &nodes);
    let job = "[analysis]\ntype = \"linear_static\"\n[mesh]\nfile = \"m.msh\"\n\
        [materials.m]\ntype = \"elastic\"\nE = 3.0e9\nnu = 0.2\n\
        [sections.wall]\ntype = \"shell\"\nthickness = 0.3\nlayers = 3\n\
        [sections.beam]\ntype = \"frame\"\narea = 0.04\niy = 1.3e-4\niz = 1.3e-4\nj = 2.2e-4\n\
        [[parts]]\ngroup = \"quad\"\nsection = \"wall\"\nmaterial = \"m\"\n\
        [[parts]]\ngroup = \"tris\"\nsection = \"wall\"\nmaterial = \"m\"\n\
        [[parts]]\ngroup = \"beam\"\nsection = \"beam\"\nmaterial = \"m\"\norientation = [0.0, 0.0, 1.0]\n\
        [[supports]]\ngroup = \"base\"\ndofs = [\"all\"]\n\
        [[supports]]\ngroup = \"end\"\ndofs = [\"all\"]\n\
        [[loads]]\ntype = \"nodal\"\ngroup = \"top\"\nforce = [1.0e3, 0.0, 0.0]\n\
        [output]\ndir = \"out\"\nexisting = \"overwrite\"\n";
    std::fs::write(dir.join("job.toml"), job).unwrap();
    dir.join("job.toml")
}

/// MSH 4.1: surface groups "quad" (tag 1) and "tris" (2), curve group "beam" (3), point groups
/// "base" (1 2 3), "top" (5), "end" (7). Element tags: points 1–5, beam 6, quad 7, triangles 8, 9.
fn write_mesh(dir: &Path, nodes: &[[f64; 3]; 7]) {
    let mut s = String::from("$MeshFormat\n4.1 0 8\n$EndMeshFormat\n$PhysicalNames\n6\n");
    s += "2 1 \"quad\"\n2 2 \"tris\"\n1 3 \"beam\"\n0 4 \"base\"\n0 5 \"top\"\n0 6 \"end\"\n$EndPhysicalNames\n";
    let pts = [(1usize, 4usize), (2, 4), (3, 4), (5, 5), (7, 6)];
    s += "$Entities\n5 1 2 0\n";
    for (k, (n, g)) in pts.iter().enumerate() {
        let x = nodes[n - 1];
        s += &format!("{} {} {} {} 1 {g}\n", k + 1, x[0], x[1], x[2]);
    }
    s += "1 -1e9 -1e9 -1e9 1e9 1e9 1e9 1 3 0\n";
    s += "1 -1e9 -1e9 -1e9 1e9 1e9 1e9 1 1 0\n2 -1e9 -1e9 -1e9 1e9 1e9 1e9 1 2 0\n$EndEntities\n";
    s += "$Nodes\n1 7 1 7\n2 1 0 7\n";
    for i in 1..=7 {
        s += &format!("{i}\n");
    }
    for x in nodes {
        s += &format!("{:.17e} {:.17e} {:.17e}\n", x[0], x[1], x[2]);
    }
    s += "$EndNodes\n$Elements\n8 9 1 9\n";
    for (k, (n, _)) in pts.iter().enumerate() {
        s += &format!("0 {} 15 1\n{} {n}\n", k + 1, k + 1);
    }
    s += "1 1 1 1\n6 4 7\n2 1 3 1\n7 1 2 5 4\n2 2 2 2\n8 2 3 6\n9 2 6 5\n$EndElements\n";
    std::fs::write(dir.join("m.msh"), s).unwrap();
}

/// Runs a broken variant on 1 rank (no mpirun) and on 2 ranks: both fail with `code`, print one
/// message containing every one of `needles`, and do not panic.
fn expect_error(name: &str, break_it: impl Fn(&Path), code: i32, needles: &[&str]) {
    let dir = scratch(name);
    let job = valid_case(&dir);
    break_it(&dir);
    expect_job_error(&job, code, needles);
}

/// Moves node `n` (1-based) of the valid mesh to `x`.
fn move_node(dir: &Path, n: usize, x: [f64; 3]) {
    let mut nodes: [[f64; 3]; 7] = [
        [0.0, 0.0, 0.0],
        [1.0, 0.0, 0.0],
        [2.0, 0.0, 0.0],
        [0.0, 0.0, 1.0],
        [1.0, 0.0, 1.0],
        [2.0, 0.0, 1.0],
        [0.0, 1.0, 1.0],
    ];
    nodes[n - 1] = x;
    write_mesh(dir, &nodes);
}

#[test]
fn the_valid_shell_and_beam_case_runs() {
    let dir = scratch("bad-el-valid");
    let job = valid_case(&dir);
    for np in [0, 2] {
        let out = run(np, &[job.to_str().unwrap()]);
        assert!(out.status.success(), "np={np}: {}", stderr(&out));
    }
}

#[test]
fn zero_length_beam() {
    // Node 7 onto node 4: the beam 4–7 has zero length.
    expect_error(
        "bad-el-zero-length",
        |d| move_node(d, 7, [0.0, 0.0, 1.0]),
        2,
        &["element 6 (group 'beam')", "zero-length"],
    );
}

#[test]
fn orientation_parallel_to_the_beam() {
    expect_error(
        "bad-el-orientation",
        |d| edit(d, "job.toml", "orientation = [0.0, 0.0, 1.0]", "orientation = [0.0, 2.0, 0.0]"),
        2,
        &["element 6", "orientation vector", "parallel to the element axis"],
    );
}

#[test]
fn warped_quadrilateral_beyond_the_limit() {
    // Node 5 pushed 0.4 m out of the plane: ±0.1 m off the mean plane of a 1 m quad, warping ratio
    // about 0.1 > WARPING_LIMIT = 0.05 (a 0.2 m push, ratio 0.05, is accepted: checked by hand).
    expect_error("bad-el-warped", |d| move_node(d, 5, [1.0, 0.4, 1.0]), 2, &["element 7", "warped", "limit 5e-2"]);
}

#[test]
fn degenerate_triangle() {
    // Node 6 onto the line 2–3 extended: the triangle 2-3-6 has zero area.
    expect_error(
        "bad-el-degenerate-tri",
        |d| move_node(d, 6, [3.0, 0.0, 0.0]),
        2,
        &["element 8 (group 'tris')", "degenerate"],
    );
}

#[test]
fn non_convex_quadrilateral() {
    // Node 5 inside the quad's other half: the corner at node 5 turns the wrong way.
    expect_error("bad-el-nonconvex", |d| move_node(d, 5, [0.3, 0.0, 0.3]), 2, &["element 7", "degenerate", "convex"]);
}

#[test]
fn non_positive_thickness() {
    expect_error(
        "bad-el-thickness",
        |d| edit(d, "job.toml", "thickness = 0.3", "thickness = -0.3"),
        2,
        &["job.toml:11:1", "sections.wall.thickness", "shell thickness [m]: expected > 0, got -0.3"],
    );
}

#[test]
fn zero_layers() {
    expect_error(
        "bad-el-layers",
        |d| edit(d, "job.toml", "layers = 3", "layers = 0"),
        2,
        &["job.toml:12:1", "sections.wall.layers", "expected 1 to 99 layers, got 0"],
    );
}

/// A tied portal: two piers (frames 1–2 and 3–4, clamped at nodes 1 and 3) whose tops are
/// joined by the tie 2–4, and node 5 at (5, 5.4, 7.5) that only the broken variants use.
///
/// ```text
///   2 (0,0,6) o====== tie ======o 4 (8,0,6)        o 5 (5,5.4,7.5)
///             |                 |
///   1 (0,0,0) o                 o 3 (8,0,0)
/// ```
/// Element tags: points 1–2 (base), piers 3–4, ties from 5 in the order of `ties` (node indices).
fn tie_case(name: &str, ties: &[[usize; 2]], node5: [f64; 3]) -> PathBuf {
    let dir = scratch(name);
    let nodes = [[0.0, 0.0, 0.0], [0.0, 0.0, 6.0], [8.0, 0.0, 0.0], [8.0, 0.0, 6.0], node5];
    let mut lines = vec![[0, 1], [2, 3]];
    lines.extend_from_slice(ties);
    write_line_mesh_groups(
        &dir.join("m.msh"),
        &nodes,
        &lines,
        &[("piers", vec![0, 1]), ("nave_ties", (2..lines.len()).collect())],
        &[("base", &[0, 2])],
    );
    let job = "[analysis]\ntype = \"linear_static\"\n[mesh]\nfile = \"m.msh\"\n\
        [materials.masonry]\ntype = \"elastic\"\nE = 3.0e9\nnu = 0.2\n\
        [materials.wrought_iron]\ntype = \"elastic\"\nE = 190.0e9\nnu = 0.3\ndensity = 7700.0\n\
        [sections.pier]\ntype = \"frame\"\narea = 1.2\niy = 0.144\niz = 0.1\nj = 0.2\n\
        [sections.nave_tie]\ntype = \"tie\"\narea = 1.6e-3\npretension = 2.0e4\n\
        [[parts]]\ngroup = \"piers\"\nsection = \"pier\"\nmaterial = \"masonry\"\n\
        [[parts]]\ngroup = \"nave_ties\"\nsection = \"nave_tie\"\nmaterial = \"wrought_iron\"\n\
        [[supports]]\ngroup = \"base\"\ndofs = [\"all\"]\n\
        [output]\ndir = \"out\"\nexisting = \"overwrite\"\n";
    std::fs::write(dir.join("job.toml"), job).unwrap();
    dir.join("job.toml")
}

const NODE5: [f64; 3] = [5.0, 5.4, 7.5];

#[test]
fn the_valid_tie_case_runs() {
    let job = tie_case("bad-tie-valid", &[[1, 3]], NODE5);
    for np in [0, 2] {
        let out = run(np, &[job.to_str().unwrap()]);
        assert!(out.status.success(), "np={np}: {}", stderr(&out));
    }
}

#[test]
fn tie_with_zero_area() {
    let job = tie_case("bad-tie-zero-area", &[[1, 3]], NODE5);
    edit(job.parent().unwrap(), "job.toml", "area = 1.6e-3", "area = 0.0");
    expect_job_error(
        &job,
        2,
        &["job.toml:22:1", "sections.nave_tie.area", "area of tie section 'nave_tie' [m^2]: expected > 0, got 0"],
    );
}

#[test]
fn tie_with_negative_area() {
    let job = tie_case("bad-tie-negative-area", &[[1, 3]], NODE5);
    edit(job.parent().unwrap(), "job.toml", "area = 1.6e-3", "area = -1.6e-3");
    expect_job_error(&job, 2, &["job.toml:22:1", "sections.nave_tie.area", "[m^2]: expected > 0, got -0.0016"]);
}

#[test]
fn tie_with_negative_pretension() {
    let job = tie_case("bad-tie-pretension", &[[1, 3]], NODE5);
    edit(job.parent().unwrap(), "job.toml", "pretension = 2.0e4", "pretension = -2.0e4");
    expect_job_error(
        &job,
        2,
        &[
            "job.toml:23:1",
            "sections.nave_tie.pretension",
            "pretension of tie section 'nave_tie' (tension positive) [N]: expected >= 0, got -20000",
        ],
    );
}

#[test]
fn tie_end_attached_to_nothing() {
    // A second tie from the right pier's top (node 4) to node 5, which nothing else reaches.
    let job = tie_case("bad-tie-dangling", &[[1, 3], [3, 4]], NODE5);
    expect_job_error(
        &job,
        2,
        &["key 'parts[1].group'", "tie element 6 of group nave_ties: its end node 5 at (5.00, 5.40, 7.50) is attached to no shell or beam and to no support"],
    );
}

#[test]
fn tie_end_held_in_one_direction_only() {
    // Node 5 held by a support in uz only: the tie holds it along its axis, nothing across.
    let job = tie_case("bad-tie-partial-support", &[[1, 3], [3, 4]], NODE5);
    let dir = job.parent().unwrap();
    let nodes = [[0.0, 0.0, 0.0], [0.0, 0.0, 6.0], [8.0, 0.0, 0.0], [8.0, 0.0, 6.0], NODE5];
    let lines = [[0, 1], [2, 3], [1, 3], [3, 4]];
    write_line_mesh_groups(
        &dir.join("m.msh"),
        &nodes,
        &lines,
        &[("piers", vec![0, 1]), ("nave_ties", vec![2, 3])],
        &[("base", &[0, 2]), ("anchor", &[4])],
    );
    edit(dir, "job.toml", "[output]", "[[supports]]\ngroup = \"anchor\"\ndofs = [\"uz\"]\n[output]");
    expect_job_error(
        &job,
        2,
        &["tie element 7 of group nave_ties", "end node 5 at (5.00, 5.40, 7.50)", "leave ux, uy free"],
    );
}

#[test]
fn tie_of_zero_length() {
    // Node 5 onto node 4: the tie 4–5 has zero length.
    let job = tie_case("bad-tie-zero-length", &[[1, 3], [3, 4]], [8.0, 0.0, 6.0]);
    expect_job_error(
        &job,
        2,
        &["tie element 6 of group nave_ties", "its end nodes 4 and 5 coincide at (8.00, 0.00, 6.00)"],
    );
}

#[test]
fn tie_with_a_damage_material() {
    let job = tie_case("bad-tie-damage", &[[1, 3]], NODE5);
    let dir = job.parent().unwrap();
    edit(dir, "job.toml", "material = \"wrought_iron\"", "material = \"rubble\"");
    edit(
        dir,
        "job.toml",
        "[output]",
        "[materials.rubble]\ntype = \"damage\"\n[materials.rubble.law]\nE = 3.0e9\nnu = 0.2\neps0_t = 1.0e-4\neps0_c = 2.0e-4\n\
         gf_t = 50.0\na_c = 0.8\nb_c = 800.0\nregularization = \"hillerborg_no_elastic\"\n[output]",
    );
    expect_job_error(
        &job,
        2,
        &[
            "key 'parts[1].material'",
            "tie section 'nave_tie' needs an elastic material",
            "'rubble' is a damage material",
        ],
    );
}

#[test]
fn tie_section_on_a_surface_group() {
    expect_error(
        "bad-tie-on-shells",
        |d| {
            edit(d, "job.toml", "group = \"quad\"\nsection = \"wall\"", "group = \"quad\"\nsection = \"tie\"");
            edit(d, "job.toml", "[[parts]]", "[sections.tie]\ntype = \"tie\"\narea = 1.6e-3\n[[parts]]");
        },
        2,
        &[
            "key 'parts[0].group'",
            "group 'quad' holds a 4-node quadrangle (element 7)",
            "section 'tie' of type 'tie' needs 2-node line cells",
        ],
    );
}

#[test]
fn tie_with_a_misspelt_key() {
    let job = tie_case("bad-tie-misspelt", &[[1, 3]], NODE5);
    edit(job.parent().unwrap(), "job.toml", "pretension = 2.0e4", "pretention = 2.0e4");
    expect_job_error(
        &job,
        2,
        &[
            "job.toml:23:1",
            "sections.nave_tie.pretention",
            "unknown field `pretention`, expected one of `area`, `pretension`, `tension_only`",
        ],
    );
}
