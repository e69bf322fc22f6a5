//! Intensity sweeps through the whole program, on a masonry wall of damage shells shaken out of
//! its plane (2 m × 3 m × 0.3 m, 2 × 3 MITC4 quads of 3 layers, clamped at the base; the wall of
//! `time_history.rs`), two pulse records, each scaled to two PGAs:
//!
//! * every member of the sweep has the results of its own job file run alone as a time history
//!   (monitors, energies, peaks, damage shares within 1e-10 of their largest magnitude), on 1
//!   rank, on 2 ranks as one group of 2, and on 3 ranks in groups of 1 (oversubscribed);
//! * a member that cannot converge is an outcome with its diagnosis while the others finish;
//! * a sweep killed mid-way and restarted ends with the table of an uninterrupted one;
//! * `scale_by = "sa_t1"` scales each record by its own 5 %-damped Sa(T₁), checked by an
//!   integrator of the test's own;
//! * bad input: an empty record set, an intensity ≤ 0, a group size that does not divide the
//!   ranks, a record set that failed its check: one message naming file, key and line.
mod common;
use common::sweep::*;
use common::*;
use std::f64::consts::PI;
use std::path::Path;

/// The samples `(dt, a)` of a two-column record file (uniform steps).
fn samples(path: &Path) -> (f64, Vec<f64>) {
    let rows: Vec<(f64, f64)> = std::fs::read_to_string(path)
        .unwrap()
        .lines()
        .filter(|l| !l.starts_with('#'))
        .filter_map(|l| {
            let mut w = l.split_whitespace().map(|x| x.parse::<f64>().ok());
            Some((w.next()??, w.next()??))
        })
        .collect();
    (rows[1].0 - rows[0].0, rows.iter().map(|r| r.1).collect())
}

/// The 5 %-damped pseudo-spectral acceleration ω² max|u| of `ü + 2ζωu̇ + ω²u = −a_g(t)`, a_g
/// linear between samples, by classical Runge–Kutta with 200 substeps per sample from rest (an
/// integrator of its own, independent of the program's: its error is below 1e-8 here).
fn pseudo_sa(dt: f64, a: &[f64], period: f64) -> f64 {
    let (w, z) = (2.0 * PI / period, 0.05);
    let n_sub = 200;
    let h = dt / n_sub as f64;
    let f = |ag: f64, u: f64, v: f64| (v, -ag - 2.0 * z * w * v - w * w * u);
    let (mut u, mut v, mut peak) = (0.0f64, 0.0f64, 0.0f64);
    for k in 0..a.len() - 1 {
        for j in 0..n_sub {
            let ag = |s: f64| a[k] + (a[k + 1] - a[k]) * (j as f64 + s) / n_sub as f64;
            let (k1u, k1v) = f(ag(0.0), u, v);
            let (k2u, k2v) = f(ag(0.5), u + 0.5 * h * k1u, v + 0.5 * h * k1v);
            let (k3u, k3v) = f(ag(0.5), u + 0.5 * h * k2u, v + 0.5 * h * k2v);
            let (k4u, k4v) = f(ag(1.0), u + h * k3u, v + h * k3v);
            u += h / 6.0 * (k1u + 2.0 * k2u + 2.0 * k3u + k4u);
            v += h / 6.0 * (k1v + 2.0 * k2v + 2.0 * k3v + k4v);
            peak = peak.max(u.abs());
        }
    }
    w * w * peak
}

/// Every number of `a` and `b` (JSON values of the same shape) within `tol` of the largest
/// magnitude of its list (or of itself).
fn json_close(a: &serde_json::Value, b: &serde_json::Value, tol: f64, at: &str) {
    use serde_json::Value as V;
    match (a, b) {
        (V::Number(x), V::Number(y)) => {
            let (x, y) = (x.as_f64().unwrap(), y.as_f64().unwrap());
            assert!((x - y).abs() <= tol * x.abs().max(y.abs()).max(1e-300), "{at}: {x} vs {y}");
        }
        (V::Array(x), V::Array(y)) => {
            assert_eq!(x.len(), y.len(), "{at}");
            for (k, (p, q)) in x.iter().zip(y).enumerate() {
                json_close(p, q, tol, &format!("{at}[{k}]"));
            }
        }
        (V::Object(x), V::Object(y)) => {
            for (k, p) in x {
                json_close(p, &y[k], tol, &format!("{at}.{k}"));
            }
        }
        (p, q) => assert_eq!(p, q, "{at}"),
    }
}

const MEMBERS: [&str; 4] =
    ["base-rec-a-pga0.5000", "base-rec-a-pga1.5000", "base-rec-b-pga0.5000", "base-rec-b-pga1.5000"];

#[test]
fn every_member_of_a_sweep_equals_its_job_run_alone_on_1_2_and_3_ranks() {
    // The same numbers by two paths: the sweep (gravity once, from its saved state, in a group)
    // and the member's job file alone (its own gravity, on the group's rank count). Tolerance
    // 1e-10 of each quantity's largest magnitude (the figure; both repeat the same
    // operations on the same partition).
    for (np, group) in [(1usize, 1usize), (2, 2), (3, 1)] {
        let dir = scratch(&format!("sweep-{np}-{group}"));
        write_model(&dir, 0.3, "");
        write_sweep(&dir, "[0.5, 1.5]", group, "");
        let out = run_ok(np, &[dir.join("sweep.toml").to_str().unwrap()]);
        let log = stdout(&out);
        assert!(log.contains("4 member(s)"), "{log}");
        let csv = csv_columns(&dir.join("sweep/sweep.csv"));
        assert_eq!(csv[0].1.len(), 4);
        // The factor is the intensity over the record's PGA (the largest |a| of its file, read
        // here), to the CSV's 7 digits.
        let factor = &csv.iter().find(|c| c.0 == "factor").unwrap().1;
        for (k, (rec, x)) in [("rec-a", 0.5), ("rec-a", 1.5), ("rec-b", 0.5), ("rec-b", 1.5)].iter().enumerate() {
            let want = x / pga(&dir.join(format!("{rec}.txt")));
            assert!((factor[k] - want).abs() < 1e-6 * want, "{factor:?}");
        }
        // The stronger members crack the wall more.
        let share = &csv.iter().find(|c| c.0 == "wall:share_dt_above_0.5").unwrap().1;
        assert!(share[1] >= share[0] && share[1] > 0.0, "{share:?}");
        for m in MEMBERS {
            let mdir = dir.join("sweep/members").join(m);
            let swept_csv = csv_columns(&mdir.join("monitors.csv"));
            let swept = summary(&mdir);
            let alone_np = if group == 1 { 0 } else { group };
            run_ok(alone_np, &[dir.join("sweep/jobs").join(format!("{m}.toml")).to_str().unwrap()]);
            // The sweep's results of the member are kept aside.
            assert!(dir.join("sweep/members").join(format!("{m}.previous/outcome.json")).is_file());
            let alone_csv = csv_columns(&mdir.join("monitors.csv"));
            let alone = summary(&mdir);
            for ((name, a), (_, b)) in swept_csv.iter().zip(&alone_csv) {
                let scale = a.iter().fold(0.0f64, |s, x| s.max(x.abs()));
                assert_eq!(a.len(), b.len(), "{m} {name}");
                for (x, y) in a.iter().zip(b) {
                    assert!((x - y).abs() <= 1e-10 * scale, "np {np}: {m} {name}: {x} vs {y}");
                }
            }
            for key in
                ["peak_displacement", "peak_drift_ratio", "max_damage", "energy", "damage_by_group", "iterations"]
            {
                json_close(&swept[key], &alone[key], 1e-10, &format!("np {np}: {m} {key}"));
            }
        }
    }
}

#[test]
fn a_member_that_cannot_converge_is_an_outcome_and_the_others_finish() {
    // Newton on the initial stiffness with 4 iterations and 2 halvings per step follows the
    // elastic members (0.5 m/s², no cracking) but not the cracking of the 60 m/s² ones: those stop
    // with the time history's diagnosis, the others complete.
    let dir = scratch("sweep-stopped");
    write_model(&dir, 0.3, "max_substeps = 2\nmax_iterations = 4");
    edit(
        &dir,
        "wall.toml",
        "newton = \"krylov\"\nforce_tolerance = 1e-9",
        "newton = \"initial\"\nforce_tolerance = 1e-6",
    );
    write_sweep(&dir, "[0.5, 60.0]", 1, "");
    let out = run_ok(2, &[dir.join("sweep.toml").to_str().unwrap()]);
    let log = stdout(&out);
    let text = std::fs::read_to_string(dir.join("sweep/sweep.csv")).unwrap();
    let rows: Vec<&str> = text.lines().skip(1).collect();
    assert_eq!(rows.len(), 4, "{text}");
    for r in &rows {
        let status = r.split(',').nth(6).unwrap();
        if r.contains("pga0.5000") {
            assert_eq!(status, "completed", "{r}");
        } else {
            assert_eq!(status, "stopped", "{r}\n{log}");
            assert!(r.contains("did not converge"), "{r}");
        }
    }
    let s = summary(&dir.join("sweep"));
    assert_eq!((s["completed"].as_u64(), s["stopped"].as_u64()), (Some(2), Some(2)), "{s}");
    // A stopped member keeps its last converged state for a restart with other settings.
    let m = dir.join("sweep/members/base-rec-a-pga60.0000");
    assert!(m.join("checkpoint/latest.json").is_file());
    let o = json(&m.join("outcome.json"));
    assert!(o["time_reached"].as_f64().unwrap() < 0.3, "{o}");
}

#[test]
fn a_sweep_killed_mid_way_and_restarted_ends_with_the_table_of_an_uninterrupted_one() {
    // Two groups of 1 rank; 4 members of 200 steps with checkpoints every 10. The first run is
    // killed in the middle of a member (an injected exit without cleanup, as SIGKILL); `--restart`
    // skips the members done, resumes the killed one from its checkpoint and ends with the same
    // sweep.csv as an uninterrupted sweep, to its 7 printed digits.
    let whole = scratch("sweep-resume-whole");
    write_model(&whole, 2.0, "");
    write_sweep(&whole, "[0.5, 1.5]", 1, "");
    run_ok(2, &[whole.join("sweep.toml").to_str().unwrap()]);

    let dir = scratch("sweep-resume-killed");
    write_model(&dir, 2.0, "");
    write_sweep(&dir, "[0.5, 1.5]", 1, "");
    // The 1.5 m/s² members run first (the costliest first); the kill comes at step 55 of
    // rec-b at 0.5 m/s², one of the two members started after them, 5 steps after its checkpoint.
    let killed = "base-rec-b-pga0.5000";
    let mut cmd = std::process::Command::new("mpirun");
    cmd.args(["-n", "2", "--oversubscribe", "--bind-to", "none"])
        .arg(exe())
        .arg(dir.join("sweep.toml"))
        .env("OMPI_ALLOW_RUN_AS_ROOT", "1")
        .env("OMPI_ALLOW_RUN_AS_ROOT_CONFIRM", "1")
        .env("MASONRY_HPC_INJECT_KILL", format!("sweep_{killed}_step_55"));
    let out = run_with_timeout(cmd, std::time::Duration::from_secs(300));
    assert!(!out.status.success(), "the kill should end the sweep");
    let done =
        |d: &Path| MEMBERS.iter().filter(|m| d.join("sweep/members").join(m).join("outcome.json").is_file()).count();
    let finished = done(&dir);
    assert!((1..4).contains(&finished), "{finished} member(s) done before the kill");
    assert!(!dir.join("sweep/members").join(killed).join("outcome.json").is_file());
    assert!(dir.join("sweep/members").join(killed).join("checkpoint/step-000000050").is_dir());
    let out = run_ok(2, &["--restart", dir.join("sweep.toml").to_str().unwrap()]);
    assert!(stdout(&out).contains(&format!("({finished} done before)")), "{}", stdout(&out));
    let a = std::fs::read_to_string(whole.join("sweep/sweep.csv")).unwrap();
    let b = std::fs::read_to_string(dir.join("sweep/sweep.csv")).unwrap();
    assert_eq!(a, b);
    // The killed member went on from its checkpoint of step 50, in the same series.
    assert!(dir.join("sweep/members").join(killed).join("results-restart-000050.h5").is_file());
}

/// The model and a valid sweep in `dir`, then `from` replaced by `to` in sweep.toml: exit code 2
/// with every one of `needles` on 1 and 2 ranks, and no results written.
fn expect_sweep_error(name: &str, from: &str, to: &str, needles: &[&str]) {
    let dir = scratch(name);
    write_model(&dir, 0.3, "");
    write_sweep(&dir, "[0.5, 1.5]", 1, "");
    edit(&dir, "sweep.toml", from, to);
    expect_job_error(&dir.join("sweep.toml"), 2, needles);
    assert!(!dir.join("sweep").exists(), "bad input must not leave results");
}

/// A record_set job's results folder `set` whose summary lists `records` and whose check
/// passed or not.
fn write_set_summary(set: &Path, records: &[&str], passed: bool) {
    std::fs::create_dir_all(set).unwrap();
    let list: Vec<String> = records.iter().map(|r| format!("{{\"file\": \"{r}\"}}")).collect();
    std::fs::write(
        set.join("summary.json"),
        format!("{{\"records\": [{}], \"check\": {{\"passed\": {passed}}}}}", list.join(", ")),
    )
    .unwrap();
}

#[test]
fn an_intensity_of_zero_is_an_error_at_its_key() {
    // Line 8 of sweep.toml (write_sweep): intensities.
    expect_sweep_error(
        "sweep-bad-intensity",
        "intensities = [0.5, 1.5]",
        "intensities = [0.0, 1.5]",
        &["sweep.toml:8:", "sweep.intensities[0]", "intensity [m/s^2]: expected > 0, got 0"],
    );
}

#[test]
fn a_group_size_that_does_not_divide_the_ranks_is_an_error() {
    expect_sweep_error(
        "sweep-bad-group",
        "group_size = 1",
        "group_size = 3",
        &["sweep.toml:5:", "analysis.group_size", "a group size of 3 rank(s) does not divide the"],
    );
}

#[test]
fn an_empty_record_set_is_an_error() {
    let dir = scratch("sweep-empty-set");
    write_model(&dir, 0.3, "");
    write_sweep(&dir, "[0.5, 1.5]", 1, "record_set = \"set\"");
    write_set_summary(&dir.join("set"), &[], true);
    // Only the set: no [[sweep.record]].
    let text = std::fs::read_to_string(dir.join("sweep.toml")).unwrap();
    let text = text.split("[[sweep.record]]").next().unwrap().to_string() + "[output]\ndir = \"sweep\"\n";
    std::fs::write(dir.join("sweep.toml"), text).unwrap();
    expect_job_error(&dir.join("sweep.toml"), 2, &["sweep.record_set", "the record set is empty"]);
    assert!(!dir.join("sweep").exists());
}

#[test]
fn a_record_set_that_failed_its_check_is_an_error_when_compatibility_is_required() {
    let dir = scratch("sweep-incompatible-set");
    write_model(&dir, 0.3, "");
    write_sweep(&dir, "[0.5, 1.5]", 1, "record_set = \"set\"");
    write_set_summary(&dir.join("set"), &["../rec-a.txt"], false);
    expect_job_error(
        &dir.join("sweep.toml"),
        2,
        &["sweep.record_set", "failed its EN 1998-1 compatibility check", "require_compatible = false"],
    );
    assert!(!dir.join("sweep").exists());
    // Allowed when the job says so: the set's record joins the two files (6 members).
    edit(&dir, "sweep.toml", "record_set = \"set\"", "record_set = \"set\"\nrequire_compatible = false");
    let out = run_ok(0, &["check", dir.join("sweep.toml").to_str().unwrap()]);
    assert!(stdout(&out).contains("6 member(s)"), "{}", stdout(&out));
}

#[test]
fn a_sweep_by_sa_t1_scales_each_record_to_its_spectral_acceleration() {
    // scale_by = "sa_t1": each member's factor is the intensity over the record's 5 %-damped
    // pseudo-acceleration at T₁ = 0.2 s, computed here by an integrator of the test's own. The
    // program's spectrum (Newmark, 40 substeps per period, the peak at the substeps) differs from
    // it by its discretization error: period elongation (ωh)²/12 = 0.2 % and the peak's sampling,
    // at most 1 − cos(π/40) = 0.3 %: tolerance 1 %. Scaling by PGA would give other factors:
    // Sa(0.2 s) is 2.98 and 3.28 m/s² for PGAs of about 1 and 2 m/s².
    let dir = scratch("sweep-sa");
    write_model(&dir, 0.1, "");
    write_sweep(&dir, "[0.5, 1.0]", 1, "period = 0.2");
    edit(&dir, "sweep.toml", "scale_by = \"pga\"", "scale_by = \"sa_t1\"");
    let out = run_ok(2, &[dir.join("sweep.toml").to_str().unwrap()]);
    assert!(stdout(&out).contains("4 member(s)"), "{}", stdout(&out));
    let csv = csv_columns(&dir.join("sweep/sweep.csv"));
    let col = |name: &str| csv.iter().find(|c| c.0 == name).unwrap().1.clone();
    let (factor, intensity) = (col("factor"), col("intensity"));
    for (k, rec) in ["rec-a", "rec-a", "rec-b", "rec-b"].iter().enumerate() {
        let (dt, a) = samples(&dir.join(format!("{rec}.txt")));
        let s = pseudo_sa(dt, &a, 0.2);
        let want = intensity[k] / s;
        assert!((factor[k] - want).abs() < 1e-2 * want, "{rec}: factor {} against {want} (Sa {s})", factor[k]);
        let by_pga = intensity[k] / pga(&dir.join(format!("{rec}.txt")));
        assert!((factor[k] - by_pga).abs() > 0.1 * by_pga, "{rec}: Sa and PGA give the same factor");
    }
    // The members are named and labelled by the measure.
    assert!(dir.join("sweep/members/base-rec-a-sa0.5000/outcome.json").is_file());
    let text = std::fs::read_to_string(dir.join("sweep/summary.txt")).unwrap();
    assert!(text.contains("Sa(T1)"), "{text}");
    let rows = std::fs::read_to_string(dir.join("sweep/sweep.csv")).unwrap();
    assert!(rows.lines().skip(1).all(|l| l.split(',').nth(3) == Some("Sa(T1)")), "{rows}");
}

#[test]
fn material_variants_give_their_own_curves_and_the_spread_between_them() {
    // The wall's law in two law files, the second with half the tensile strain threshold (f_t
    // 0.072 against 0.144 MPa, the same G_f): a variant each. The weaker law passes 10 % of the
    // wall's area with d_t > 0.5 at a lower PGA than the stronger one, under each record (its
    // bottom row cracks at 0.5 m/s², the stronger one's at 0.75); the summary gives each
    // material's median and the dispersion between the two.
    let dir = scratch("sweep-variants");
    write_model(&dir, 0.3, "");
    let law = |eps0_t: f64| {
        format!("[law]\nE = 2.885e9\nnu = 0.19\neps0_t = {eps0_t:e}\neps0_c = 5.0e-5\ngf_t = 20.0\na_c = 0.9\nb_c = 2000.0\nregularization = \"hillerborg\"\n")
    };
    std::fs::write(dir.join("law-strong.toml"), law(5.0e-5)).unwrap();
    std::fs::write(dir.join("law-weak.toml"), law(2.5e-5)).unwrap();
    edit(&dir, "wall.toml", "[materials.masonry.law]\nE = 2.885e9\nnu = 0.19\neps0_t = 5.0e-5\neps0_c = 5.0e-5\ngf_t = 20.0\na_c = 0.9\nb_c = 2000.0\nregularization = \"hillerborg\"\n", "law_file = \"law-strong.toml\"\n");
    write_sweep(&dir, "[0.25, 0.5, 0.75, 1.0]", 1, "materials = [\"law-strong.toml\", \"law-weak.toml\"]");
    run_ok(2, &[dir.join("sweep.toml").to_str().unwrap()]);
    let s = summary(&dir.join("sweep"));
    assert_eq!(s["completed"].as_u64(), Some(16), "{s}");
    let l = &s["limits"][0];
    let v = l["variants"].as_array().unwrap();
    assert_eq!(v.len(), 2);
    assert_eq!((v[0]["variant"].as_str(), v[1]["variant"].as_str()), (Some("law-strong"), Some("law-weak")));
    for r in 0..2 {
        let strong = v[0]["crossings"][r]["intensity"].as_f64().unwrap_or(f64::INFINITY);
        let weak = v[1]["crossings"][r]["intensity"].as_f64().unwrap_or(f64::INFINITY);
        assert!(weak < strong, "record {r}: weak {weak} vs strong {strong}\n{l}");
        assert!(weak.is_finite(), "{l}");
    }
    let (a, b) = (v[0]["median"].as_f64().unwrap(), v[1]["median"].as_f64().unwrap());
    // β of two medians: |ln a − ln b| / √2 (the sample standard deviation of two values).
    let want = (a.ln() - b.ln()).abs() / 2f64.sqrt();
    assert!((l["beta_materials"].as_f64().unwrap() - want).abs() < 1e-12, "{l}");
    let text = std::fs::read_to_string(dir.join("sweep/summary.txt")).unwrap();
    assert!(text.contains("from the records beta") && text.contains("from the materials beta"), "{text}");
    // The member job files carry their variant's law file.
    let job = std::fs::read_to_string(dir.join("sweep/jobs/law-weak-rec-a-pga0.5000.toml")).unwrap();
    assert!(job.contains("law-weak.toml"), "{job}");
}
