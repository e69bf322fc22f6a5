//! Helpers of the integration tests: run the binary (alone or under `mpirun`), write small
//! meshes and jobs into a scratch folder, read results back with the `hdf5` crate.
#![allow(dead_code)]
use std::path::{Path, PathBuf};
use std::process::{Command, Output};

pub mod sweep;

/// The binary under test.
pub fn exe() -> PathBuf {
    PathBuf::from(env!("CARGO_BIN_EXE_masonry-hpc"))
}

/// A fresh scratch folder for one test.
pub fn scratch(name: &str) -> PathBuf {
    let d = std::env::temp_dir().join(format!("masonry-hpc-tests-{}", std::process::id())).join(name);
    let _ = std::fs::remove_dir_all(&d);
    std::fs::create_dir_all(&d).expect("scratch folder");
    d
}

/// Runs `masonry-hpc args` on `np` ranks (`np = 0`: without mpirun, as a singleton), failing
/// the test after 300 s (a hang).
pub fn run(np: usize, args: &[&str]) -> Output {
    run_for(np, args, std::time::Duration::from_secs(300))
}

/// [`run`] for a run whose work is known to take minutes in a debug build, with its own limit.
pub fn run_for(np: usize, args: &[&str], limit: std::time::Duration) -> Output {
    let mut cmd = if np == 0 {
        Command::new(exe())
    } else {
        let mut c = Command::new("mpirun");
        c.args(["-n", &np.to_string(), "--oversubscribe", "--bind-to", "none"]).arg(exe());
        c
    };
    cmd.args(args)
        .env("OMPI_ALLOW_RUN_AS_ROOT", "1")
        .env("OMPI_ALLOW_RUN_AS_ROOT_CONFIRM", "1")
        .env("OMPI_MCA_rmaps_base_oversubscribe", "1")
        .env_remove("PETSC_OPTIONS");
    run_with_timeout(cmd, limit)
}

/// Runs `cmd` to completion, killing it (and failing the test) if it takes longer than `limit`:
/// a run that hangs under mpirun is a bug this suite must report, not wait for.
pub fn run_with_timeout(mut cmd: Command, limit: std::time::Duration) -> Output {
    use std::process::Stdio;
    let dir = std::env::temp_dir();
    let tag = format!("{}-{:?}", std::process::id(), std::thread::current().id()).replace(['(', ')'], "");
    let (po, pe) = (dir.join(format!("mhpc-{tag}.out")), dir.join(format!("mhpc-{tag}.err")));
    let fo = std::fs::File::create(&po).expect("stdout file");
    let fe = std::fs::File::create(&pe).expect("stderr file");
    let mut child = cmd
        .stdin(Stdio::null())
        .stdout(Stdio::from(fo))
        .stderr(Stdio::from(fe))
        .spawn()
        .expect("could not start the binary (is mpirun installed? run scripts/setup.sh)");
    let start = std::time::Instant::now();
    let status = loop {
        if let Some(s) = child.try_wait().expect("wait") {
            break s;
        }
        if start.elapsed() > limit {
            let _ = child.kill();
            let _ = child.wait();
            panic!("the run did not finish within {limit:?} (hang?): {cmd:?}");
        }
        std::thread::sleep(std::time::Duration::from_millis(20));
    };
    let out = Output {
        status,
        stdout: std::fs::read(&po).unwrap_or_default(),
        stderr: std::fs::read(&pe).unwrap_or_default(),
    };
    let _ = std::fs::remove_file(po);
    let _ = std::fs::remove_file(pe);
    out
}

/// stderr as text.
pub fn stderr(o: &Output) -> String {
    String::from_utf8_lossy(&o.stderr).into_owned()
}

/// Runs `job` on 1 rank (no mpirun) and on 2 ranks, and checks that both fail with `code` and
/// one message (printed once, not once per rank) containing every one of `needles`, without a
/// panic.
pub fn expect_job_error(job: &Path, code: i32, needles: &[&str]) {
    for np in [0, 2] {
        let out = run(np, &[job.to_str().unwrap()]);
        let err = stderr(&out);
        assert_eq!(out.status.code(), Some(code), "np={np}: exit code; stderr:\n{err}");
        for n in needles {
            assert!(err.contains(n), "np={np}: message lacks '{n}':\n{err}");
        }
        assert_eq!(err.matches("error:").count(), 1, "np={np}: one message, not one per rank:\n{err}");
        assert!(!err.contains("panicked") && !err.contains("RUST_BACKTRACE"), "np={np}: a panic:\n{err}");
    }
}

/// Replaces the first `from` by `to` in `dir/file` (a test's way of breaking a valid input).
pub fn edit(dir: &Path, file: &str, from: &str, to: &str) {
    let p = dir.join(file);
    let s = std::fs::read_to_string(&p).unwrap();
    assert!(s.contains(from), "test setup: '{from}' not in {file}");
    std::fs::write(&p, s.replacen(from, to, 1)).unwrap();
}

/// stdout as text.
pub fn stdout(o: &Output) -> String {
    String::from_utf8_lossy(&o.stdout).into_owned()
}

/// Writes an ASCII MSH 4.1 file of 2-node lines: `nodes` (tag = index + 1), `lines` as pairs of
/// node indices in physical curve group 1 `"beams"`, and point groups (name, node indices) as
/// physical point groups 2, 3, ...
pub fn write_line_mesh(path: &Path, nodes: &[[f64; 3]], lines: &[[usize; 2]], point_groups: &[(&str, &[usize])]) {
    write_line_mesh_groups(path, nodes, lines, &[("beams", (0..lines.len()).collect())], point_groups);
}

/// Writes an ASCII MSH 4.1 file of 2-node lines in several physical curve groups (`line_groups`:
/// name and the indices of its lines), plus point groups, as [`write_line_mesh`] does for one.
pub fn write_line_mesh_groups(
    path: &Path,
    nodes: &[[f64; 3]],
    lines: &[[usize; 2]],
    line_groups: &[(&str, Vec<usize>)],
    point_groups: &[(&str, &[usize])],
) {
    let ng = line_groups.len();
    let mut s = String::from("$MeshFormat\n4.1 0 8\n$EndMeshFormat\n$PhysicalNames\n");
    s += &format!("{}\n", ng + point_groups.len());
    for (g, (name, _)) in line_groups.iter().enumerate() {
        s += &format!("1 {} \"{}\"\n", g + 1, name);
    }
    for (i, (name, _)) in point_groups.iter().enumerate() {
        s += &format!("0 {} \"{}\"\n", ng + i + 1, name);
    }
    s += "$EndPhysicalNames\n$Entities\n";
    let pts: Vec<(usize, usize)> =
        point_groups.iter().enumerate().flat_map(|(g, (_, ns))| ns.iter().map(move |&n| (g, n))).collect();
    s += &format!("{} {} 0 0\n", pts.len(), ng);
    for (k, (g, n)) in pts.iter().enumerate() {
        let x = nodes[*n];
        s += &format!("{} {} {} {} 1 {}\n", k + 1, x[0], x[1], x[2], ng + g + 1);
    }
    for g in 0..ng {
        s += &format!("{} -1e9 -1e9 -1e9 1e9 1e9 1e9 1 {} 0\n", g + 1, g + 1);
    }
    s += "$EndEntities\n";
    s += &format!("$Nodes\n1 {} 1 {}\n1 1 0 {}\n", nodes.len(), nodes.len(), nodes.len());
    for i in 0..nodes.len() {
        s += &format!("{}\n", i + 1);
    }
    for x in nodes {
        s += &format!("{:.17e} {:.17e} {:.17e}\n", x[0], x[1], x[2]);
    }
    s += "$EndNodes\n$Elements\n";
    let n_el = lines.len() + pts.len();
    s += &format!("{} {} 1 {}\n", ng + pts.len(), n_el, n_el);
    let mut tag = 1;
    for (k, (_, n)) in pts.iter().enumerate() {
        s += &format!("0 {} 15 1\n{} {}\n", k + 1, tag, n + 1);
        tag += 1;
    }
    for (g, (_, ls)) in line_groups.iter().enumerate() {
        s += &format!("1 {} 1 {}\n", g + 1, ls.len());
        for &l in ls {
            s += &format!("{} {} {}\n", tag, lines[l][0] + 1, lines[l][1] + 1);
            tag += 1;
        }
    }
    s += "$EndElements\n";
    std::fs::write(path, s).expect("write mesh");
}

/// A job file for a frame made of the `"beams"` group of `mesh`, with the given extra TOML.
pub fn frame_job(mesh: &str, e: f64, g: f64, sec: [f64; 4], orientation: Option<[f64; 3]>, extra: &str) -> String {
    let ori = orientation.map(|v| format!("orientation = [{}, {}, {}]\n", v[0], v[1], v[2])).unwrap_or_default();
    format!(
        "[analysis]\ntype = \"linear_static\"\n[mesh]\nfile = \"{mesh}\"\n\
         [materials.m]\ntype = \"elastic\"\nE = {e:e}\nG = {g:e}\ndensity = 0.0\n\
         [sections.s]\ntype = \"frame\"\narea = {:e}\niy = {:e}\niz = {:e}\nj = {:e}\n\
         [[parts]]\ngroup = \"beams\"\nsection = \"s\"\nmaterial = \"m\"\n{ori}\
         [output]\ndir = \"out\"\nexisting = \"overwrite\"\n{extra}",
        sec[0], sec[1], sec[2], sec[3]
    )
}

/// Node field `name` of the last step of `<dir>/results.h5`, keyed by Gmsh node tag.
pub fn node_field(dir: &Path, name: &str) -> std::collections::BTreeMap<u64, Vec<f64>> {
    let f = hdf5::File::open(dir.join("results.h5")).expect("open results.h5");
    let ids: Vec<u64> = f.dataset("mesh/node_ids").expect("node_ids").read_raw().expect("read node_ids");
    let steps = f.group("steps").expect("steps group");
    let steps: Vec<usize> = steps.member_names().expect("step names").iter().filter_map(|s| s.parse().ok()).collect();
    let last = steps.iter().max().expect("a step");
    let ds = f.dataset(&format!("steps/{last}/{name}")).expect("field dataset");
    let v: Vec<f64> = ds.read_raw().expect("read field");
    let nc = v.len() / ids.len();
    ids.iter().enumerate().map(|(i, &id)| (id, v[i * nc..(i + 1) * nc].to_vec())).collect()
}

/// Writes an ASCII MSH 4.1 file of 4-node quadrangles in one physical surface group `surface`,
/// plus point groups (name, node indices), as [`write_line_mesh`] does for lines.
pub fn write_quad_mesh(
    path: &Path,
    nodes: &[[f64; 3]],
    quads: &[[usize; 4]],
    surface: &str,
    point_groups: &[(&str, Vec<usize>)],
) {
    let mut s = String::from("$MeshFormat\n4.1 0 8\n$EndMeshFormat\n$PhysicalNames\n");
    s += &format!("{}\n2 1 \"{surface}\"\n", 1 + point_groups.len());
    for (i, (name, _)) in point_groups.iter().enumerate() {
        s += &format!("0 {} \"{}\"\n", i + 2, name);
    }
    s += "$EndPhysicalNames\n$Entities\n";
    let pts: Vec<(usize, usize)> =
        point_groups.iter().enumerate().flat_map(|(g, (_, ns))| ns.iter().map(move |&n| (g, n))).collect();
    s += &format!("{} 0 1 0\n", pts.len());
    for (k, (g, n)) in pts.iter().enumerate() {
        let x = nodes[*n];
        s += &format!("{} {} {} {} 1 {}\n", k + 1, x[0], x[1], x[2], g + 2);
    }
    s += "1 -1e9 -1e9 -1e9 1e9 1e9 1e9 1 1 0\n$EndEntities\n";
    s += &format!("$Nodes\n1 {} 1 {}\n2 1 0 {}\n", nodes.len(), nodes.len(), nodes.len());
    for i in 0..nodes.len() {
        s += &format!("{}\n", i + 1);
    }
    for x in nodes {
        s += &format!("{:.17e} {:.17e} {:.17e}\n", x[0], x[1], x[2]);
    }
    s += "$EndNodes\n$Elements\n";
    let n_el = quads.len() + pts.len();
    s += &format!("{} {} 1 {}\n", 1 + pts.len(), n_el, n_el);
    let mut tag = 1;
    for (k, (_, n)) in pts.iter().enumerate() {
        s += &format!("0 {} 15 1\n{} {}\n", k + 1, tag, n + 1);
        tag += 1;
    }
    s += &format!("2 1 3 {}\n", quads.len());
    for q in quads {
        s += &format!("{} {} {} {} {}\n", tag, q[0] + 1, q[1] + 1, q[2] + 1, q[3] + 1);
        tag += 1;
    }
    s += "$EndElements\n";
    std::fs::write(path, s).expect("write mesh");
}

/// Writes an ASCII MSH 4.1 file with quadrangles and 2-node lines in named physical groups
/// (surfaces, then curves), plus point groups (name, node indices), all numbered in that order.
pub fn write_mixed_mesh(
    path: &Path,
    nodes: &[[f64; 3]],
    surfaces: &[(&str, Vec<[usize; 4]>)],
    curves: &[(&str, Vec<[usize; 2]>)],
    point_groups: &[(&str, Vec<usize>)],
) {
    let (ns, nc) = (surfaces.len(), curves.len());
    let mut s = String::from("$MeshFormat\n4.1 0 8\n$EndMeshFormat\n$PhysicalNames\n");
    s += &format!("{}\n", ns + nc + point_groups.len());
    for (g, (name, _)) in surfaces.iter().enumerate() {
        s += &format!("2 {} \"{name}\"\n", g + 1);
    }
    for (g, (name, _)) in curves.iter().enumerate() {
        s += &format!("1 {} \"{name}\"\n", ns + g + 1);
    }
    for (g, (name, _)) in point_groups.iter().enumerate() {
        s += &format!("0 {} \"{name}\"\n", ns + nc + g + 1);
    }
    s += "$EndPhysicalNames\n$Entities\n";
    let pts: Vec<(usize, usize)> =
        point_groups.iter().enumerate().flat_map(|(g, (_, v))| v.iter().map(move |&n| (g, n))).collect();
    s += &format!("{} {} {} 0\n", pts.len(), nc, ns);
    for (k, (g, n)) in pts.iter().enumerate() {
        let x = nodes[*n];
        s += &format!("{} {} {} {} 1 {}\n", k + 1, x[0], x[1], x[2], ns + nc + g + 1);
    }
    for g in 0..nc {
        s += &format!("{} -1e9 -1e9 -1e9 1e9 1e9 1e9 1 {} 0\n", g + 1, ns + g + 1);
    }
    for g in 0..ns {
        s += &format!("{} -1e9 -1e9 -1e9 1e9 1e9 1e9 1 {} 0\n", g + 1, g + 1);
    }
    s += "$EndEntities\n";
    s += &format!("$Nodes\n1 {} 1 {}\n2 1 0 {}\n", nodes.len(), nodes.len(), nodes.len());
    for i in 0..nodes.len() {
        s += &format!("{}\n", i + 1);
    }
    for x in nodes {
        s += &format!("{:.17e} {:.17e} {:.17e}\n", x[0], x[1], x[2]);
    }
    s += "$EndNodes\n$Elements\n";
    let n_el: usize =
        surfaces.iter().map(|g| g.1.len()).sum::<usize>() + curves.iter().map(|g| g.1.len()).sum::<usize>() + pts.len();
    s += &format!("{} {} 1 {}\n", ns + nc + pts.len(), n_el, n_el);
    let mut tag = 1;
    for (k, (_, n)) in pts.iter().enumerate() {
        s += &format!("0 {} 15 1\n{} {}\n", k + 1, tag, n + 1);
        tag += 1;
    }
    for (g, (_, ls)) in curves.iter().enumerate() {
        s += &format!("1 {} 1 {}\n", g + 1, ls.len());
        for l in ls {
            s += &format!("{} {} {}\n", tag, l[0] + 1, l[1] + 1);
            tag += 1;
        }
    }
    for (g, (_, qs)) in surfaces.iter().enumerate() {
        s += &format!("2 {} 3 {}\n", g + 1, qs.len());
        for q in qs {
            s += &format!("{} {} {} {} {}\n", tag, q[0] + 1, q[1] + 1, q[2] + 1, q[3] + 1);
            tag += 1;
        }
    }
    s += "$EndElements\n";
    std::fs::write(path, s).expect("write mesh");
}

/// Cell field `name` of the last step of `<dir>/results.h5`, keyed by Gmsh element tag (the
/// components of each cell; one for a scalar field).
pub fn cell_field(dir: &Path, name: &str) -> std::collections::BTreeMap<u64, Vec<f64>> {
    let f = hdf5::File::open(dir.join("results.h5")).expect("open results.h5");
    let ids: Vec<u64> = f.dataset("mesh/cell_ids").expect("cell_ids").read_raw().expect("read cell_ids");
    let steps = f.group("steps").expect("steps group");
    let steps: Vec<usize> = steps.member_names().expect("step names").iter().filter_map(|s| s.parse().ok()).collect();
    let last = steps.iter().max().expect("a step");
    let v: Vec<f64> =
        f.dataset(&format!("steps/{last}/{name}")).expect("cell field dataset").read_raw().expect("read field");
    let nc = v.len() / ids.len();
    ids.iter().enumerate().map(|(i, &id)| (id, v[i * nc..(i + 1) * nc].to_vec())).collect()
}

/// `<dir>/summary.json`, checked to be in format 2 ([`assert_named_fields`]).
pub fn summary(dir: &Path) -> serde_json::Value {
    let p = dir.join("summary.json");
    let v: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(&p).unwrap_or_else(|e| panic!("{}: {e}", p.display())))
            .expect("summary.json");
    assert_named_fields(&v, &p.display().to_string());
    v
}

/// The lists of numbers a summary may hold: series, whose index is their meaning (a value per
/// accepted step or evaluation; the sample numbers of a variant). The key path's end.
pub const SERIES: [&str; 4] = ["history", "best_so_far", "samples.tension", "samples.compression"];

/// A summary in format 2 (docs/outputs.md, "summary.json"): `"format": 2` at the top, and no
/// list of numbers (at any depth) but the [`SERIES`]: a group of values with distinct meanings
/// is an object with named fields. `what` names the file in the failure.
pub fn assert_named_fields(v: &serde_json::Value, what: &str) {
    assert_eq!(v["format"], 2, "{what}: no \"format\": 2");
    fn walk(v: &serde_json::Value, path: &str, what: &str) {
        match v {
            serde_json::Value::Array(items) => {
                let numeric = !items.is_empty() && items.iter().all(|x| x.is_number() || x.is_null());
                assert!(
                    !numeric || SERIES.iter().any(|s| path.ends_with(s)),
                    "{what}: {path} is a bare list of numbers: {v}"
                );
                for (i, x) in items.iter().enumerate() {
                    walk(x, &format!("{path}[{i}]"), what);
                }
            }
            serde_json::Value::Object(m) => {
                for (k, x) in m {
                    walk(x, &if path.is_empty() { k.clone() } else { format!("{path}.{k}") }, what);
                }
            }
            _ => {}
        }
    }
    walk(v, "", what);
}

/// The mesh `m.msh` of a wall of 2 × 3 quads in the x–z plane (2 m wide, 3 m high), with the
/// point groups `base` (its bottom nodes) and `top` (the middle node of its top edge); the
/// surface group is `wall`. The damage-shell wall of `time_history.rs` and `sweep.rs`.
pub fn write_wall_mesh(dir: &Path) {
    let (nx, nz, w, h) = (2usize, 3usize, 2.0, 3.0);
    let nodes: Vec<[f64; 3]> = (0..=nz)
        .flat_map(|j| (0..=nx).map(move |i| [w * i as f64 / nx as f64, 0.0, h * j as f64 / nz as f64]))
        .collect();
    let quads: Vec<[usize; 4]> = (0..nz)
        .flat_map(|j| {
            (0..nx).map(move |i| {
                let a = j * (nx + 1) + i;
                [a, a + 1, a + nx + 2, a + nx + 1]
            })
        })
        .collect();
    write_quad_mesh(
        &dir.join("m.msh"),
        &nodes,
        &quads,
        "wall",
        &[("base", (0..=nx).collect()), ("top", vec![nz * (nx + 1) + nx / 2])],
    );
}
