//! Bad input gives one clear message naming the file, line/key or element, and a non-zero exit
//! code — alone and under `mpirun -n 2` (where it must neither hang nor print once per rank).
mod common;
use common::*;
use std::path::{Path, PathBuf};

/// A valid two-element cantilever job in `dir`; returns the job path.
fn valid_case(dir: &Path) -> PathBuf {
    let nodes = [[0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [2.0, 0.0, 0.0]];
    write_line_mesh(&dir.join("m.msh"), &nodes, &[[0, 1], [1, 2]], &[("base", &[0]), ("tip", &[2])]);
    let extra = "[[supports]]\ngroup = \"base\"\ndofs = [\"all\"]\n[[loads]]\ntype = \"nodal\"\ngroup = \"tip\"\nforce = [0.0, -1.0e3, 0.0]\n";
    let job = frame_job("m.msh", 2.0e11, 8.0e10, [1e-3, 2e-6, 5e-6, 3e-6], None, extra);
    std::fs::write(dir.join("job.toml"), job).unwrap();
    dir.join("job.toml")
}

/// Runs a broken variant of the valid case on 1 rank (no mpirun) and on 2 ranks, and checks
/// that both fail with `code` and a message containing every one of `needles`, printed once.
fn expect_error(name: &str, break_it: impl Fn(&Path), code: i32, needles: &[&str]) {
    let dir = scratch(name);
    let job = valid_case(&dir);
    break_it(&dir);
    expect_job_error(&job, code, needles);
}

#[test]
fn the_valid_case_runs() {
    let dir = scratch("valid");
    let job = valid_case(&dir);
    for np in [0, 2] {
        let out = run(np, &[job.to_str().unwrap()]);
        assert!(out.status.success(), "np={np}: {}", stderr(&out));
    }
}

#[test]
fn malformed_toml() {
    expect_error(
        "malformed",
        |d| edit(d, "job.toml", "[mesh]", "[mesh"),
        2,
        &["job.toml:3:6", "unclosed table, expected `]`"],
    );
}

#[test]
fn unknown_key() {
    expect_error(
        "unknown-key",
        |d| edit(d, "job.toml", "density = 0.0", "density = 0.0\ndensty = 1.0"),
        2,
        &["job.toml:10:1", "materials.m.densty", "unknown field `densty`", "expected one of"],
    );
}

#[test]
fn wrong_type() {
    expect_error(
        "wrong-type",
        |d| edit(d, "job.toml", "area = 1e-3", "area = \"large\""),
        2,
        &["job.toml:12:8", "sections.s.area", "expected f64"],
    );
}

#[test]
fn missing_mesh_file() {
    expect_error("no-mesh", |d| std::fs::remove_file(d.join("m.msh")).unwrap(), 2, &["m.msh", "No such file"]);
}

#[test]
fn truncated_mesh() {
    expect_error(
        "truncated",
        |d| {
            let s = std::fs::read_to_string(d.join("m.msh")).unwrap();
            std::fs::write(d.join("m.msh"), &s[..s.find("$Elements").unwrap() + 20]).unwrap();
        },
        2,
        &["m.msh", "end of file"],
    );
}

#[test]
fn garbled_mesh() {
    expect_error("garbled", |d| edit(d, "m.msh", "$Nodes\n1 3 1 3", "$Nodes\n1 3 x 3"), 2, &["m.msh", "line"]);
}

#[test]
fn group_absent_from_mesh() {
    expect_error(
        "no-group",
        |d| edit(d, "job.toml", "group = \"base\"", "group = \"bse\""),
        2,
        &["supports[0].group", "no physical group named 'bse'", "beams, base, tip"],
    );
}

#[test]
fn zero_young_modulus() {
    expect_error("zero-e", |d| edit(d, "job.toml", "E = 2e11", "E = 0e0"), 2, &["materials.m.E", "> 0"]);
}

#[test]
fn negative_area() {
    expect_error("neg-area", |d| edit(d, "job.toml", "area = 1e-3", "area = -1e-3"), 2, &["sections.s.area", "> 0"]);
}

#[test]
fn unsupported_structure_is_a_named_mechanism() {
    expect_error(
        "mechanism",
        |d| edit(d, "job.toml", "[[supports]]\ngroup = \"base\"\ndofs = [\"all\"]\n", ""),
        2,
        &["mechanism", "node 1", "translation along x"],
    );
}

#[test]
fn partly_supported_structure_names_the_free_motion() {
    expect_error(
        "pinned",
        |d| edit(d, "job.toml", "dofs = [\"all\"]", "dofs = [\"ux\", \"uy\", \"uz\"]"),
        2,
        &["mechanism", "rotation about x"],
    );
}

#[test]
fn check_validates_without_running() {
    let dir = scratch("check");
    let job = valid_case(&dir);
    let out = run(0, &["check", job.to_str().unwrap()]);
    assert!(out.status.success(), "{}", stderr(&out));
    assert!(stdout(&out).contains("check: OK"), "{}", stdout(&out));
    assert!(!dir.join("out").exists(), "check must not write results");
    edit(&dir, "job.toml", "group = \"tip\"", "group = \"tp\"");
    let out = run(0, &["check", job.to_str().unwrap()]);
    assert_eq!(out.status.code(), Some(2));
    assert!(stderr(&out).contains("no physical group named 'tp'"), "{}", stderr(&out));
}

#[test]
fn help_and_version() {
    let out = run(0, &["--help"]);
    assert!(out.status.success());
    assert!(stdout(&out).contains("masonry-hpc check"), "{}", stdout(&out));
    let out = run(0, &["--version"]);
    assert!(out.status.success());
    assert!(stdout(&out).contains(env!("CARGO_PKG_VERSION")));
}

#[test]
fn an_error_on_one_rank_ends_every_rank() {
    // Rank 1 fails on entering assembly while rank 0 goes on into the collective assembly: the
    // failing rank must print its message and abort the job, not leave rank 0 waiting forever
    // (run() fails the test after its time limit).
    let dir = scratch("one-rank-fails");
    let job = valid_case(&dir);
    let mut cmd = std::process::Command::new("mpirun");
    cmd.args(["-n", "2", "--oversubscribe", "--bind-to", "none"])
        .arg(exe())
        .arg(&job)
        .env("OMPI_ALLOW_RUN_AS_ROOT", "1")
        .env("OMPI_ALLOW_RUN_AS_ROOT_CONFIRM", "1")
        .env("MASONRY_HPC_INJECT_FAULT", "assembly@1");
    let out = run_with_timeout(cmd, std::time::Duration::from_secs(60));
    let err = stderr(&out);
    assert!(!out.status.success(), "{err}");
    assert!(err.contains("error (rank 1): fault injected at phase 'assembly' on rank 1"), "{err}");
    assert!(!err.contains("panicked"), "{err}");
}
