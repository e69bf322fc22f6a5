//! The wall, its two pulse records and sweep jobs on them, for the sweep's tests
//! (`tests/sweep.rs`, `tests/sweep_hunt.rs`).
use super::*;
use std::f64::consts::PI;
use std::path::Path;

/// A pulse of `cycles`-ish sine at `f` Hz under a half-sine window over `t_on` s, amplitude
/// `amp`, as a two-column file of `t_end` s at `dt`.
pub fn write_pulse(path: &Path, dt: f64, t_end: f64, f: f64, t_on: f64, amp: f64) {
    let n = (t_end / dt).round() as usize + 1;
    let mut s = String::from("# test pulse\n# t [s]  a [m/s^2]\n");
    for i in 0..n {
        let t = i as f64 * dt;
        let a = if t < t_on { amp * (PI * t / t_on).sin() * (2.0 * PI * f * t).sin() } else { 0.0 };
        s += &format!("{t:.6} {a:.17e}\n");
    }
    std::fs::write(path, s).unwrap();
}

/// The wall's mesh, two records and the base job (`wall.toml`, a time history of `duration` s at
/// 0.01 s, checkpoints every 10 steps; `extra` goes into `[dynamics]`).
pub fn write_model(dir: &Path, duration: f64, extra: &str) {
    write_wall_mesh(dir);
    write_pulse(&dir.join("rec-a.txt"), 0.01, 2.0, 5.0, 0.4, 1.0);
    write_pulse(&dir.join("rec-b.txt"), 0.005, 2.0, 7.0, 0.5, 2.0);
    let job = format!(
        "[analysis]\ntype = \"time_history\"\n[mesh]\nfile = \"m.msh\"\n\
         [materials.masonry]\ntype = \"damage\"\ndensity = 2000.0\n\
         [materials.masonry.law]\nE = 2.885e9\nnu = 0.19\neps0_t = 5.0e-5\neps0_c = 5.0e-5\ngf_t = 20.0\na_c = 0.9\nb_c = 2000.0\nregularization = \"hillerborg\"\n\
         [sections.wall]\ntype = \"shell\"\nthickness = 0.3\nlayers = 3\n\
         [[parts]]\ngroup = \"wall\"\nsection = \"wall\"\nmaterial = \"masonry\"\n\
         [[supports]]\ngroup = \"base\"\ndofs = [\"all\"]\n\
         [gravity]\nacceleration = [0.0, 0.0, -9.81]\n\
         [dynamics]\nduration = {duration}\ndt = 0.01\nnewton = \"krylov\"\nforce_tolerance = 1e-9\noutput_every = 10\n{extra}\n\
         [dynamics.checkpoint]\nevery_steps = 10\n\
         [dynamics.damping]\nfrequencies = [5.0, 30.0]\nratio = 0.03\n\
         [[dynamics.ground_motion]]\ndirection = \"y\"\nfile = \"rec-a.txt\"\nformat = \"two_column\"\nunits = \"m/s2\"\n\
         [[dynamics.ground_motion]]\ndirection = \"x\"\nfile = \"rec-a.txt\"\nformat = \"two_column\"\nunits = \"m/s2\"\nscale = 0.3\n\
         [[dynamics.monitor]]\nname = \"top\"\ngroup = \"top\"\nnear = [1.0, 0.0, 3.0]\n\
         [output]\ndir = \"out-base\"\nexisting = \"overwrite\"\n"
    );
    std::fs::write(dir.join("wall.toml"), job).unwrap();
}

/// The sweep job over both records at `intensities` (PGA), groups of `group` rank(s).
pub fn write_sweep(dir: &Path, intensities: &str, group: usize, extra: &str) {
    let job = format!(
        "title = \"test sweep\"\n[analysis]\ntype = \"sweep\"\njob = \"wall.toml\"\ngroup_size = {group}\n\
         [sweep]\nscale_by = \"pga\"\nintensities = {intensities}\ncode_level = 1.0\n{extra}\n\
         [[sweep.record]]\nfile = \"rec-a.txt\"\nformat = \"two_column\"\nunits = \"m/s2\"\n\
         [[sweep.record]]\nfile = \"rec-b.txt\"\nformat = \"two_column\"\nunits = \"m/s2\"\n\
         [[sweep.limit]]\ngroup = \"wall\"\nshare = 0.1\n\
         [output]\ndir = \"sweep\"\nexisting = \"overwrite\"\n"
    );
    std::fs::write(dir.join("sweep.toml"), job).unwrap();
}

/// The sweep job over both records with adaptive intensities: `hunt` is the body of
/// `[sweep.hunt]`, `limits` the `[[sweep.limit]]` tables; groups of `group` rank(s).
pub fn write_hunt_sweep(dir: &Path, hunt: &str, limits: &str, group: usize) {
    let job = format!(
        "title = \"test hunt\"\n[analysis]\ntype = \"sweep\"\njob = \"wall.toml\"\ngroup_size = {group}\n\
         [sweep]\nscale_by = \"pga\"\ncode_level = 1.0\n\
         [sweep.hunt]\n{hunt}\n\
         [[sweep.record]]\nfile = \"rec-a.txt\"\nformat = \"two_column\"\nunits = \"m/s2\"\n\
         [[sweep.record]]\nfile = \"rec-b.txt\"\nformat = \"two_column\"\nunits = \"m/s2\"\n\
         {limits}\n\
         [output]\ndir = \"sweep\"\nexisting = \"overwrite\"\n"
    );
    std::fs::write(dir.join("sweep.toml"), job).unwrap();
}

/// The largest |a| of a two-column record file.
pub fn pga(path: &Path) -> f64 {
    std::fs::read_to_string(path)
        .unwrap()
        .lines()
        .filter(|l| !l.starts_with('#'))
        .filter_map(|l| l.split_whitespace().nth(1)?.parse::<f64>().ok())
        .fold(0.0, |m, a| m.max(a.abs()))
}

pub fn run_ok(np: usize, args: &[&str]) -> std::process::Output {
    let out = run(np, args);
    assert!(out.status.success(), "{}\n{}", stdout(&out), stderr(&out));
    out
}

/// The numeric columns of a CSV file, by header name.
pub fn csv_columns(path: &Path) -> Vec<(String, Vec<f64>)> {
    let text = std::fs::read_to_string(path).unwrap_or_else(|e| panic!("{}: {e}", path.display()));
    let mut lines = text.lines();
    let head: Vec<String> = lines.next().unwrap().split(',').map(String::from).collect();
    let rows: Vec<Vec<f64>> =
        lines.map(|l| l.split(',').map(|x| x.trim().parse().unwrap_or(f64::NAN)).collect()).collect();
    head.iter().enumerate().map(|(c, h)| (h.clone(), rows.iter().map(|r| r[c]).collect())).collect()
}

/// A JSON file.
pub fn json(path: &Path) -> serde_json::Value {
    serde_json::from_str(&std::fs::read_to_string(path).unwrap_or_else(|e| panic!("{}: {e}", path.display()))).unwrap()
}
