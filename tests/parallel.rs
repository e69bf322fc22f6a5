//! The demo job on 1 and 2 MPI ranks gives the same displacements (1e-10 relative to the
//! largest), and its HDF5/XDMF output reads back with independent readers (h5py, meshio).
mod common;
use common::*;
use std::path::Path;

fn demo_job(dir: &Path, extra: &str) -> std::path::PathBuf {
    let root = Path::new(env!("CARGO_MANIFEST_DIR"));
    let text = std::fs::read_to_string(root.join("jobs/tower.toml")).unwrap();
    let mesh = root.join("meshes/tower.msh");
    let text = text
        .replace("\"../meshes/tower.msh\"", &format!("{:?}", mesh.to_str().unwrap()))
        .replace("\"../results/tower\"", "\"out\"")
        .replace("existing = \"backup\"", "existing = \"overwrite\"")
        + extra;
    let job = dir.join("tower.toml");
    std::fs::write(&job, text).unwrap();
    job
}

fn max_rel_diff(a: &std::collections::BTreeMap<u64, Vec<f64>>, b: &std::collections::BTreeMap<u64, Vec<f64>>) -> f64 {
    assert_eq!(a.len(), b.len(), "node counts differ");
    let scale = a.values().flatten().fold(0.0f64, |m, x| m.max(x.abs()));
    let mut worst = 0.0f64;
    for (id, va) in a {
        let vb = &b[id];
        for (x, y) in va.iter().zip(vb) {
            worst = worst.max((x - y).abs() / scale);
        }
    }
    worst
}

#[test]
fn demo_on_one_and_two_ranks_agrees() {
    let d1 = scratch("demo-np1");
    let d2 = scratch("demo-np2");
    let j1 = demo_job(&d1, "");
    let j2 = demo_job(&d2, "");
    let o1 = run(1, &[j1.to_str().unwrap()]);
    assert!(o1.status.success(), "np=1: {}\n{}", stdout(&o1), stderr(&o1));
    let o2 = run(2, &[j2.to_str().unwrap()]);
    assert!(o2.status.success(), "np=2: {}\n{}", stdout(&o2), stderr(&o2));
    for field in ["displacement", "rotation"] {
        let a = node_field(&d1.join("out"), field);
        let b = node_field(&d2.join("out"), field);
        let diff = max_rel_diff(&a, &b);
        assert!(diff < 1e-10, "{field}: np=1 vs np=2 differ by {diff:e} (relative to the largest)");
    }
    // Equilibrium, checked element by element by the run itself.
    let s: serde_json::Value = common::summary(&d2.join("out"));
    assert!(s["equilibrium_residual"].as_f64().unwrap() < 1e-9, "{s}");
    const WRENCH: [&str; 6] = ["fx", "fy", "fz", "mx", "my", "mz"];
    let applied: Vec<&serde_json::Value> = WRENCH.iter().map(|k| &s["applied_sum"][k]).collect();
    let react: Vec<&serde_json::Value> = WRENCH.iter().map(|k| &s["reaction_sum"][k]).collect();
    // Tolerance: 1e-10 of the largest resultant component (round-off of sums over ~2000 nodes).
    let scale = (0..6).map(|k| applied[k].as_f64().unwrap().abs()).fold(0.0, f64::max);
    for k in 0..6 {
        let (a, r) = (applied[k].as_f64().unwrap(), react[k].as_f64().unwrap());
        assert!((a + r).abs() <= 1e-10 * scale, "resultant {k}: applied {a} + reactions {r} != 0");
    }
}

#[test]
fn iterative_solver_and_baij_give_the_direct_solution() {
    // CG + block Jacobi/ICC from the command line over the job's direct solver, on BAIJ storage.
    let d1 = scratch("demo-direct");
    let d2 = scratch("demo-cg");
    let j1 = demo_job(&d1, "");
    let j2 = demo_job(&d2, "[solver]\nmatrix = \"baij\"\n");
    let o1 = run(2, &[j1.to_str().unwrap()]);
    assert!(o1.status.success(), "{}", stderr(&o1));
    let o2 = run(
        2,
        &[
            j2.to_str().unwrap(),
            "-ksp_type",
            "cg",
            "-pc_type",
            "bjacobi",
            "-sub_pc_type",
            "icc",
            "-ksp_rtol",
            "1e-13",
            "-ksp_max_it",
            "20000",
        ],
    );
    assert!(o2.status.success(), "{}", stderr(&o2));
    assert!(stdout(&o2).contains("ksp=cg"), "the command line must win over the job: {}", stdout(&o2));
    let diff = max_rel_diff(&node_field(&d1.join("out"), "displacement"), &node_field(&d2.join("out"), "displacement"));
    assert!(diff < 1e-7, "CG (rtol 1e-13) vs direct: {diff:e}");
}

#[test]
fn output_reads_back_with_meshio_and_h5py() {
    let d = scratch("demo-readers");
    let j = demo_job(&d, "");
    let o = run(2, &[j.to_str().unwrap()]);
    assert!(o.status.success(), "{}", stderr(&o));
    let script = Path::new(env!("CARGO_MANIFEST_DIR")).join("scripts/check_xdmf.py");
    let py = std::process::Command::new("python3").arg(&script).arg(d.join("out/results.xdmf")).output().unwrap();
    assert!(py.status.success(), "check_xdmf.py failed: {}", String::from_utf8_lossy(&py.stderr));
    let info: serde_json::Value = serde_json::from_slice(&py.stdout).unwrap();
    let s: serde_json::Value = common::summary(&d.join("out"));
    assert_eq!(info["n_nodes"], s["nodes"], "{info}");
    assert_eq!(info["n_cells"], s["elements"], "{info}");
    // The largest displacement magnitude seen by meshio equals the one the run reported.
    assert_eq!(info["cells_gmsh"]["line"], s["elements"], "{info}");
    assert_eq!(info["h5_matches_meshio"], true, "{info}");
    let umax = info["steps"][0]["point_data"]["displacement"]["max_norm"].as_f64().unwrap();
    let want = s["max_displacement"].as_f64().unwrap();
    assert!((umax - want).abs() <= 1e-12 * want, "meshio {umax} vs run {want}");
}

#[test]
fn petsc_options_environment_wins_over_the_job() {
    // PETSC_OPTIONS is read by PETSc at start-up, like the command line: it overrides the job's
    // [solver.petsc] defaults (direct Cholesky) and the run reports the solver it used.
    let d = scratch("petsc-options-env");
    let j = demo_job(&d, "");
    let mut cmd = std::process::Command::new("mpirun");
    cmd.args(["-n", "2", "--oversubscribe", "--bind-to", "none"])
        .arg(exe())
        .arg(&j)
        .env("OMPI_ALLOW_RUN_AS_ROOT", "1")
        .env("OMPI_ALLOW_RUN_AS_ROOT_CONFIRM", "1")
        .env("PETSC_OPTIONS", "-ksp_type cg -pc_type gamg -ksp_rtol 1e-12 -ksp_max_it 2000");
    let out = run_with_timeout(cmd, std::time::Duration::from_secs(300));
    assert!(out.status.success(), "{}", stderr(&out));
    assert!(stdout(&out).contains("ksp=cg pc=gamg"), "{}", stdout(&out));
}

#[test]
fn nonlinear_static_of_an_elastic_model_equals_linear_static() {
    // With elastic elements, Newton load stepping must land on K u = f: equal displacements to
    // 1e-9 of the largest (the force tolerance is 1e-8 on the residual), on 2 ranks; and every
    // converged step is in the XDMF time series (λ = 1/3, 2/3, 1).
    let d1 = scratch("nl-linear");
    let d2 = scratch("nl-nonlinear");
    let j1 = demo_job(&d1, "");
    let j2 = demo_job(&d2, "");
    let t = std::fs::read_to_string(&j2)
        .unwrap()
        .replace("type = \"linear_static\"", "type = \"static_nonlinear\"\nsteps = 3");
    std::fs::write(&j2, t).unwrap();
    let o1 = run(2, &[j1.to_str().unwrap()]);
    assert!(o1.status.success(), "{}", stderr(&o1));
    let o2 = run(2, &[j2.to_str().unwrap()]);
    assert!(o2.status.success(), "{}", stderr(&o2));
    let diff = max_rel_diff(&node_field(&d1.join("out"), "displacement"), &node_field(&d2.join("out"), "displacement"));
    assert!(diff < 1e-9, "nonlinear static vs linear static: {diff:e}");
    let f = hdf5::File::open(d2.join("out/results.h5")).unwrap();
    let times: Vec<f64> = f.dataset("steps/times").unwrap().read_raw().unwrap();
    assert_eq!(times.len(), 3, "{times:?}");
    assert!((times[0] - 1.0 / 3.0).abs() < 1e-12 && (times[2] - 1.0).abs() < 1e-12, "{times:?}");
}
