//! Cyclic DEM tests and particle states through the whole program.
//!
//! ```text
//!   cyclic shear job, small wall (0.5 m x 0.6 m, 5 courses x 3 stones), 2 samples on 2 ranks
//!   ├ each sample folder: curve.csv, curve.png (the loops), cracks-*.svg, particles.xdmf/.h5
//!   │ (written by the rank that ran the sample)
//!   ├ summary.json: ν is null for a shear test (no -0.0 with n = 0)
//!   ├ particles.h5 read back with h5py: the last state is the curve's last state; every stone
//!   │ vertex moves by the exact rigid motion u + (R(θ) − 1)(x − c) of its stone (recomputed in
//!   │ Python, 1e-12 m); the top row follows the platen (curve.csv displacement, 1e-12 m); the
//!   │ crack cells present at the end = the broken beams of curve.csv's last row
//!   └ pv_dem.py (ParaView's XDMF reader) sees the same stones, cracks and arrays and renders a
//!     non-blank PNG (skipped, with the reason printed, without pvpython or Xvfb)
//! ```
mod common;
use common::*;
use std::path::{Path, PathBuf};
use std::process::Command;

const SMALL_WALL: &str = "layout = { type = \"coursed\", width = 0.5, height = 0.6, n_courses = 5, n_per_course = 3, jitter = 0.2, size_variability = 0.2 }";

fn root() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR"))
}

fn on_path(cmd: &str) -> bool {
    Command::new("sh").arg("-c").arg(format!("command -v {cmd}")).output().is_ok_and(|o| o.status.success())
}

fn cyclic_job(dir: &Path) -> PathBuf {
    let text = format!(
        "[analysis]\ntype = \"dem\"\nsamples = 2\nparticle_states = \"steps\"\n\
         [sample]\nseed = 3\n{SMALL_WALL}\n\
         [test]\ntype = \"cyclic_shear\"\nvertical_stress = 1.0e6\namplitudes = [0.5e-3, 1.0e-3]\nsteps_per_half_cycle = 8\npreload_steps = 3\n\
         [output]\ndir = \"out\"\nexisting = \"overwrite\"\n"
    );
    let f = dir.join("cyclic.toml");
    std::fs::write(&f, text).unwrap();
    f
}

const H5_CHECK: &str = r#"
import csv, json, math, sys
import h5py, numpy as np
sdir = sys.argv[1]
rows = list(csv.DictReader(open(sdir + "/curve.csv")))
with h5py.File(sdir + "/particles.h5", "r") as f:
    xyz = f["/mesh/coordinates"][...]
    topo = f["/mesh/topology"][...]
    particle = f["/mesh/particle"][...]
    steps = sorted(f["/steps"].keys(), key=int)
    last = f["/steps"][steps[-1]]
    state = int(last.attrs["state"])
    disp = last["displacement"][...]
    pdisp = last["particle_displacement"][...]
    rot = last["rotation"][...]
    crack = last["crack"][...]
    strain = float(last.attrs["strain"])
# Walk the Mixed topology: polygons (3, n, ids...), lines (2, 2, a, b).
cells, r = [], 0
while r < len(topo):
    t, n = int(topo[r]), int(topo[r + 1])
    cells.append((t, [int(v) for v in topo[r + 2:r + 2 + n]]))
    r += 2 + n
assert len(cells) == len(particle), (len(cells), len(particle))
err = 0.0
for c, (t, ids) in enumerate(cells):
    if t != 3:
        continue
    pts = xyz[ids, :2]
    # The centroid of the polygon (shoelace), independent of the program's own code.
    x, y = pts[:, 0], pts[:, 1]
    xs, ys = np.roll(x, -1), np.roll(y, -1)
    cr = x * ys - xs * y
    a = cr.sum() / 2
    cx, cy = ((x + xs) * cr).sum() / (6 * a), ((y + ys) * cr).sum() / (6 * a)
    th, u = rot[c], pdisp[c]
    for i, v in enumerate(ids):
        rx, ry = xyz[v, 0] - cx, xyz[v, 1] - cy
        ex = u[0] + math.cos(th) * rx - math.sin(th) * ry - rx
        ey = u[1] + math.sin(th) * rx + math.cos(th) * ry - ry
        err = max(err, abs(disp[v, 0] - ex), abs(disp[v, 1] - ey))
row = rows[state]
print(json.dumps({"steps": len(steps), "state": state, "curve_last_state": int(rows[-1]["state"]),
                  "strain": strain, "curve_strain": float(row["strain"]), "curve_displacement": float(row["displacement"]),
                  "rigid_motion_error": err, "stones": int((particle >= 0).sum()), "lines": int((particle < 0).sum()),
                  "cracks_present": int((crack >= 0).sum()), "curve_broken": int(row["broken"]),
                  "top_ux": [float(pdisp[c][0]) for c in range(len(cells)) if cells[c][0] == 3 and max(xyz[cells[c][1], 1]) > 0.6 - 1e-9]}))
"#;

#[test]
fn cyclic_shear_job_writes_loops_and_particle_states() {
    let dir = scratch("dem-cyclic");
    let job = cyclic_job(&dir);
    let o = run(2, &[job.to_str().unwrap()]);
    assert!(o.status.success(), "{}\n{}", stdout(&o), stderr(&o));
    let out = dir.join("out");
    let summary: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(out.join("summary.json")).unwrap()).unwrap();
    assert!(summary["poisson"].is_null(), "ν of a shear test: {}", summary["poisson"]);
    assert!(summary["peak_stress"]["n"].as_u64().unwrap() >= 1);
    for k in 0..2 {
        let sdir = out.join(format!("sample-{k:03}"));
        for f in ["curve.csv", "curve.png", "cracks-end.svg", "particles.xdmf", "particles.h5"] {
            assert!(sdir.join(f).exists(), "{} missing", sdir.join(f).display());
        }
        let o = Command::new("python3").arg("-c").arg(H5_CHECK).arg(&sdir).output().unwrap();
        assert!(o.status.success(), "h5py check: {}", String::from_utf8_lossy(&o.stderr));
        let v: serde_json::Value = serde_json::from_slice(&o.stdout).unwrap();
        println!("sample {k}: {v}");
        assert_eq!(v["state"], v["curve_last_state"], "the last particle state is the curve's last state");
        assert_eq!(v["strain"], v["curve_strain"]);
        assert!(v["rigid_motion_error"].as_f64().unwrap() < 1e-12, "{}", v["rigid_motion_error"]);
        assert_eq!(v["stones"].as_u64().unwrap(), 15);
        assert_eq!(v["cracks_present"], v["curve_broken"], "every beam broken at the end is a crack cell");
        let d = v["curve_displacement"].as_f64().unwrap();
        let top = v["top_ux"].as_array().unwrap();
        assert!(!top.is_empty());
        for u in top {
            assert!((u.as_f64().unwrap() - d).abs() < 1e-12, "top stone u_x {u} vs platen {d}");
        }
    }

    if !(on_path("pvpython") && on_path("Xvfb")) {
        println!("skipped the ParaView check: pvpython or Xvfb is not installed (scripts/setup.sh --paraview)");
        return;
    }
    let sdir = out.join("sample-000");
    let png = dir.join("states.png");
    let mut c = Command::new("bash");
    c.current_dir(root())
        .args(["scripts/with_display.sh", "pvpython", "scripts/pv_dem.py"])
        .arg(sdir.join("particles.xdmf"))
        .args(["--size", "600x700", "--out", png.to_str().unwrap()]);
    let o = run_with_timeout(c, std::time::Duration::from_secs(120));
    assert!(o.status.success(), "pv_dem.py failed:\n{}\n{}", stdout(&o), stderr(&o));
    let line = stdout(&o).lines().rev().find(|l| l.starts_with('{')).unwrap_or_default().to_string();
    let v: serde_json::Value = serde_json::from_str(&line).unwrap_or_else(|e| panic!("{e}: {}", stdout(&o)));
    let rows = std::fs::read_to_string(sdir.join("curve.csv")).unwrap();
    let broken: u64 = rows.lines().last().unwrap().split(',').nth(6).unwrap().parse().unwrap();
    assert_eq!(v["stones"], 15);
    assert_eq!(v["polygon_cells"], 15);
    assert_eq!(v["cracks"].as_u64().unwrap(), broken);
    {
        let a = "displacement";
        assert!(v["point_arrays"].as_array().unwrap().iter().any(|x| x == a), "{v}");
    }
    for a in ["particle_displacement", "rotation", "crack", "particle", "beam"] {
        assert!(v["cell_arrays"].as_array().unwrap().iter().any(|x| x == a), "{v}");
    }
    let img = image::open(&png).expect("a PNG").to_rgb8();
    let drawn = img.pixels().filter(|p| p.0.iter().any(|&c| c < 235)).count() as f64;
    assert!(drawn / (img.width() * img.height()) as f64 > 0.05, "the picture is almost blank");
    // The legible picture (pv_dem.py, the crack SVGs' palette): a white background (the
    // corner), stones in #ebe3d3 with #4a4a4a outlines, cracks in tension red #d62728 and
    // shear blue #1f77b4. Each colour is looked for within 12 of each channel (anti-aliasing
    // and blending shift edges, not the bulk of a 4-pixel line or of a stone).
    assert_eq!(img.get_pixel(2, 2).0, [255, 255, 255], "background");
    let near = |want: [u8; 3]| {
        img.pixels().filter(|p| p.0.iter().zip(want).all(|(&c, w)| (c as i32 - w as i32).abs() <= 12)).count()
    };
    assert!(near([0xeb, 0xe3, 0xd3]) as f64 > 0.05 * (img.width() * img.height()) as f64, "stone fill");
    assert!(near([0x4a, 0x4a, 0x4a]) > 100, "stone outlines");
    if v["cracks_tension"].as_u64().unwrap() > 0 {
        assert!(near([0xd6, 0x27, 0x28]) > 20, "tension cracks in red");
    }
    if v["cracks_shear"].as_u64().unwrap() > 0 {
        assert!(near([0x1f, 0x77, 0xb4]) > 20, "shear cracks in blue");
    }
}

/// A cyclic protocol with decreasing amplitudes, or no amplitude, is a located error, printed
/// once, alone and under `mpirun -n 2`.
#[test]
fn bad_cyclic_protocol_is_located() {
    let dir = scratch("dem-cyclic-bad");
    let job = cyclic_job(&dir);
    let text = std::fs::read_to_string(&job).unwrap();
    for (bad, needles) in [
        ("amplitudes = [2.0e-3, 1.0e-3]", ["cyclic.toml:11:", "key 'test.amplitudes'", "do not decrease"]),
        ("amplitudes = []", ["cyclic.toml:11:", "key 'test.amplitudes'", "at least one amplitude"]),
    ] {
        std::fs::write(&job, text.replace("amplitudes = [0.5e-3, 1.0e-3]", bad)).unwrap();
        for np in [0, 2] {
            let out = run(np, &["check", job.to_str().unwrap()]);
            let err = stderr(&out);
            assert_eq!(out.status.code(), Some(2), "np={np}: {err}");
            for n in needles {
                assert!(err.contains(n), "np={np}: message lacks '{n}':\n{err}");
            }
            assert_eq!(err.matches("error:").count(), 1, "np={np}: one message:\n{err}");
        }
    }
}
