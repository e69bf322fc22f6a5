//! The template building (docs/own-building.md): its jobs pass `check --strict` (no error, no
//! warning of implausible input), its mesh regenerates byte for byte from
//! scripts/make_house_mesh.py, and its committed record is record 1 of its record set job.
mod common;
use common::*;
use std::path::PathBuf;
use std::process::Command;

fn root() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR"))
}

/// The three template jobs check clean, strictly: the model (526 shells in 5 parts, the `base`
/// curves as supports: 41 nodes × 6 DOFs), its mesh and its record.
#[test]
fn the_template_jobs_check_without_warnings() {
    for job in ["template-building.toml", "template-building-modal.toml", "template-building-records.toml"] {
        let f = root().join("jobs").join(job);
        let o = run(0, &["check", "--strict", f.to_str().unwrap()]);
        let (out, err) = (stdout(&o), stderr(&o));
        assert_eq!(o.status.code(), Some(0), "{job}: {out}\n{err}");
        assert!(!err.contains("warning"), "{job}: {err}");
        if job != "template-building-records.toml" {
            assert!(out.contains("526 structural elements in 5 part(s), 246 fixed DOFs"), "{job}: {out}");
        }
    }
}

/// `jobs/records/template-building-01.txt` is `record-01.txt` of the record set job, byte for
/// byte (each record comes from its own seed alone).
#[test]
fn the_template_record_is_record_one_of_its_set() {
    let dir = scratch("template-records");
    let text = std::fs::read_to_string(root().join("jobs/template-building-records.toml")).unwrap();
    let text =
        text.replace("dir = \"../results/template-building-records\"", "dir = \"out\"\nexisting = \"overwrite\"");
    std::fs::write(dir.join("records.toml"), text).unwrap();
    let o = run(0, &[dir.join("records.toml").to_str().unwrap()]);
    assert!(o.status.success(), "{}", stderr(&o));
    assert!(stdout(&o).contains("compatible"), "{}", stdout(&o));
    let made = std::fs::read(dir.join("out/record-01.txt")).unwrap();
    let committed = std::fs::read(root().join("jobs/records/template-building-01.txt")).unwrap();
    assert!(made == committed, "the committed record differs from the record set's record-01.txt");
}

/// scripts/make_house_mesh.py writes meshes/house.msh again, byte for byte (gmsh 4.15.2, the
/// version scripts/setup.sh installs).
#[test]
fn the_house_mesh_regenerates_identically() {
    let ok = Command::new("python3").args(["-c", "import gmsh"]).output().map(|o| o.status.success()).unwrap_or(false);
    assert!(ok, "python3 cannot import gmsh: run scripts/setup.sh (it installs gmsh from PyPI)");
    let out = scratch("house-mesh").join("house.msh");
    let mut c = Command::new("python3");
    c.current_dir(root()).args(["scripts/make_house_mesh.py", "-o", out.to_str().unwrap()]);
    let o = run_with_timeout(c, std::time::Duration::from_secs(120));
    assert!(o.status.success(), "{}\n{}", stdout(&o), stderr(&o));
    assert!(stdout(&o).contains("593 nodes, 2 Triangle 3, 524 Quadrilateral 4"), "{}", stdout(&o));
    let committed = std::fs::read(root().join("meshes/house.msh")).unwrap();
    assert!(std::fs::read(&out).unwrap() == committed, "meshes/house.msh differs from the script's output");
}
