//! Adaptive intensities (hunt and fill, Vamvatsikos and Cornell 2004) and fragility functions
//! through the whole program, on the wall of `tests/sweep.rs` (2 m × 3 m × 0.3 m of damage shells
//! shaken out of its plane, two pulse records; `common/sweep.rs`):
//!
//! * the hunt steps up from its first level by its steps until the limit is passed, then bisects
//!   the passage to the stated precision: every passage lies between a member below the limit and
//!   one above it, at most 5 % apart; under two law variants, the records' and the materials'
//!   dispersions and the fragility over both are the method of moments on ln x of the passages,
//!   P at the code level Φ(ln(c/θ)/β);
//! * the same members and results on 1 rank, on 3 ranks in groups of 1 and in one group of 2;
//! * without `[sweep.hunt]` the hunt takes its levels from the code level;
//! * a member that stops converging ends its hunt (the flat end) and its passage is bisected;
//! * a limit never passed up to the cap: the summary says so, no fit, no error;
//! * a sweep killed during the hunt and restarted ends with the members and the fragility figures
//!   of an uninterrupted one;
//! * bad input: a hunt without a limit, a precision <= 0, both a grid and a hunt, neither
//!   without a code level: one message naming file, line and key, and no results.
mod common;
use common::sweep::*;
use common::*;
use std::path::Path;

const HUNT: &str = "first = 0.25\nstep = 0.25\nstep_increase = 0.125\ncap = 2.0\nprecision = 0.05";
const LIMIT: &str = "[[sweep.limit]]\ngroup = \"wall\"\nshare = 0.1";

/// Φ(z) by Abramowitz and Stegun 7.1.26 (|error| < 1.5e-7 in erf), written here apart from the
/// program's.
fn phi(z: f64) -> f64 {
    let x = z.abs() / 2f64.sqrt();
    let t = 1.0 / (1.0 + 0.3275911 * x);
    let poly = t * (0.254829592 + t * (-0.284496736 + t * (1.421413741 + t * (-1.453152027 + t * 1.061405429))));
    let erf = 1.0 - poly * (-x * x).exp();
    if z >= 0.0 {
        0.5 * (1.0 + erf)
    } else {
        0.5 * (1.0 - erf)
    }
}

/// The rows of sweep.csv: (record, intensity, status, wall share with d_t > 0.5, material).
fn rows(dir: &Path) -> Vec<(String, f64, String, f64, String)> {
    let text = std::fs::read_to_string(dir.join("sweep/sweep.csv")).unwrap();
    let mut lines = text.lines();
    let head: Vec<&str> = lines.next().unwrap().split(',').collect();
    let col = |name: &str| head.iter().position(|h| *h == name).unwrap();
    let (r, x, st, sh, v) =
        (col("record"), col("intensity"), col("status"), col("wall:share_dt_above_0.5"), col("variant"));
    lines
        .map(|l| {
            let c: Vec<&str> = l.split(',').collect();
            let share = c[sh].parse().unwrap_or(f64::NAN);
            (c[r].to_string(), c[x].parse().unwrap(), c[st].to_string(), share, c[v].to_string())
        })
        .collect()
}

/// The hunt's levels from 0.25 by 0.25 growing by 0.125: 0.25, 0.5, 0.875, 1.375, 2.0, ...
fn hunt_level(k: usize) -> f64 {
    (0..k).fold(0.25, |x, i| x + 0.25 + 0.125 * i as f64)
}

/// The wall's law in two law files, the second with half the tensile strain threshold (the
/// material variants of tests/sweep.rs), as the sweep's materials.
fn write_two_laws(dir: &Path) {
    let law = |eps0_t: f64| {
        format!("[law]\nE = 2.885e9\nnu = 0.19\neps0_t = {eps0_t:e}\neps0_c = 5.0e-5\ngf_t = 20.0\na_c = 0.9\nb_c = 2000.0\nregularization = \"hillerborg\"\n")
    };
    std::fs::write(dir.join("law-strong.toml"), law(5.0e-5)).unwrap();
    std::fs::write(dir.join("law-weak.toml"), law(2.5e-5)).unwrap();
    edit(dir, "wall.toml", "[materials.masonry.law]\nE = 2.885e9\nnu = 0.19\neps0_t = 5.0e-5\neps0_c = 5.0e-5\ngf_t = 20.0\na_c = 0.9\nb_c = 2000.0\nregularization = \"hillerborg\"\n", "law_file = \"law-strong.toml\"\n");
    edit(
        dir,
        "sweep.toml",
        "code_level = 1.0\n",
        "code_level = 1.0\nmaterials = [\"law-strong.toml\", \"law-weak.toml\"]\n",
    );
}

/// Mean and sample standard deviation of `y`.
fn mean_std(y: &[f64]) -> (f64, f64) {
    let n = y.len() as f64;
    let m = y.iter().sum::<f64>() / n;
    (m, (y.iter().map(|v| (v - m).powi(2)).sum::<f64>() / (n - 1.0)).sqrt())
}

#[test]
fn a_hunt_brackets_each_passage_to_its_precision_and_fits_the_fragility() {
    // Two records under two materials: four hunts.
    let dir = scratch("hunt");
    write_model(&dir, 0.3, "");
    write_hunt_sweep(&dir, HUNT, LIMIT, 1);
    write_two_laws(&dir);
    let out = run_ok(2, &[dir.join("sweep.toml").to_str().unwrap()]);
    let log = stdout(&out);
    // Progress: which record's hunt is at which intensity.
    assert!(log.contains("hunt rec-a / law-strong: PGA 0.2500 m/s² (level 1 of the hunt)"), "{log}");
    assert!(log.contains("hunt rec-b / law-weak: PGA 0.5000 m/s² (level 2 of the hunt)"), "{log}");
    let s = json(&dir.join("sweep/summary.json"));
    assert_eq!(s["intensities"], "hunt");
    let rows = rows(&dir);
    let l = &s["limits"][0];
    let mut passages = vec![];
    for (v, law) in ["law-strong", "law-weak"].iter().enumerate() {
        for (r, rec) in ["rec-a", "rec-b"].iter().enumerate() {
            let mut pts: Vec<(f64, f64)> =
                rows.iter().filter(|x| x.0 == *rec && x.4 == *law && x.2 == "completed").map(|x| (x.1, x.3)).collect();
            pts.sort_by(|a, b| a.0.total_cmp(&b.0));
            let c = &l["variants"][v]["crossings"][r];
            assert_eq!(c["how"], "reached", "{rec} {law}: {c}");
            let x = c["intensity"].as_f64().unwrap();
            // The bracket: the highest member below the limit under x, the lowest at or above it.
            let lo = pts.iter().filter(|p| p.1 < 0.1 && p.0 <= x).map(|p| p.0).fold(0.0f64, f64::max);
            let hi = pts.iter().filter(|p| p.1 >= 0.1 && p.0 >= x).map(|p| p.0).fold(f64::INFINITY, f64::min);
            assert!(lo > 0.0 && hi.is_finite() && lo <= x && x <= hi, "{rec} {law}: {x} not in [{lo}, {hi}]: {pts:?}");
            assert!(hi - lo <= 0.05 * hi + 1e-9, "{rec} {law}: bracket [{lo}, {hi}] wider than 5 %: {pts:?}");
            // Every level of the hunt up to its top ran (the fill's levels lie between them), and
            // the hunt stopped at the first level above the passage.
            let top = pts.iter().map(|p| p.0).fold(0.0f64, f64::max);
            let k_top = (0..5).find(|&k| (hunt_level(k) - top).abs() < 1e-9);
            let k_top = k_top.unwrap_or_else(|| panic!("{rec} {law}: the top {top} is no hunt level: {pts:?}"));
            for k in 0..=k_top {
                let h = hunt_level(k);
                assert!(pts.iter().any(|p| (p.0 - h).abs() < 1e-9), "{rec} {law}: hunt level {h} missing: {pts:?}");
            }
            assert!(k_top > 0 && hunt_level(k_top - 1) < x, "{rec} {law}: the hunt went past {x}: {pts:?}");
            assert_eq!(s["hunts"][2 * v + r]["end"], "all_passed", "{}", s["hunts"]);
            passages.push(x);
        }
    }
    // The weaker law passes lower under each record.
    assert!(passages[2] < passages[0] && passages[3] < passages[1], "{passages:?}");
    // The fits, none censored: the method of moments on ln x (Baker 2015). Per material the
    // geometric mean of its two records and their sample standard deviation; the dispersion from
    // the records the mean of the two; from the materials the standard deviation of the two
    // medians; the fragility over all four. To 1e-9 (the same arithmetic in another order).
    let ln: Vec<f64> = passages.iter().map(|x| x.ln()).collect();
    let close = |got: &serde_json::Value, want: f64| {
        let g = got.as_f64().unwrap_or(f64::NAN);
        assert!((g - want).abs() <= 1e-9 * want.abs().max(1.0), "{g} against {want}\n{l}");
    };
    let (m0, b0) = mean_std(&ln[0..2]);
    let (m1, b1) = mean_std(&ln[2..4]);
    close(&l["variants"][0]["median"], m0.exp());
    close(&l["variants"][1]["median"], m1.exp());
    close(&l["beta_records"], 0.5 * (b0 + b1));
    close(&l["beta_materials"], (m0 - m1).abs() / 2f64.sqrt());
    let f = &l["fragility"];
    let (m, beta) = mean_std(&ln);
    assert_eq!(f["fit"]["estimator"], "moments", "{f}");
    close(&f["fit"]["median"], m.exp());
    close(&f["fit"]["beta"], beta);
    assert!(beta > 0.1, "the two laws should spread the passages: {f}");
    // P at the code level (1.0 m/s²): Φ(ln(1/θ)/β), 1e-6 for two approximations of Φ (1.5e-7
    // and 1.2e-7).
    let p = phi(-m / beta);
    assert!((f["p_code_level"].as_f64().unwrap() - p).abs() < 1e-6, "{f} against {p}");
    assert_eq!((f["passed"].as_u64(), f["not_passed"].as_u64()), (Some(4), Some(0)), "{f}");
    assert!(dir.join("sweep/fragility-wall-10.png").is_file());
    let text = std::fs::read_to_string(dir.join("sweep/summary.txt")).unwrap();
    assert!(text.contains("P(passed | PGA = 1)") && text.contains("method of moments"), "{text}");
    // The code level moved to θ e^(β/2) and the sweep restarted (every member done: none runs
    // again, the summary is written anew): P there is Φ(0.5) = 0.6914624613 (Abramowitz and
    // Stegun Table 26.1), whatever the wall's θ and β; 1e-6 for the two approximations of Φ.
    let c = m.exp() * (0.5 * beta).exp();
    edit(&dir, "sweep.toml", "code_level = 1.0", &format!("code_level = {c:.17e}"));
    let out = run_ok(2, &["--restart", dir.join("sweep.toml").to_str().unwrap()]);
    let n = s["members"].as_u64().unwrap();
    assert!(stdout(&out).contains(&format!("restart: {n} member(s) of the hunts done before")), "{}", stdout(&out));
    let s2 = json(&dir.join("sweep/summary.json"));
    assert_eq!(s2["timing"]["members_run"].as_u64(), Some(0), "{s2}");
    let p = s2["limits"][0]["fragility"]["p_code_level"].as_f64().unwrap();
    assert!((p - 0.6914624613).abs() < 1e-6 && (phi(0.5) - 0.6914624613).abs() < 1e-6, "{p}");
}

/// `[sweep.hunt] stop_at_passage` (the default) against members run whole: the same members
/// (damage never heals, so passed or not is decided the same), the rows of the members that did
/// not pass unchanged, every member that passed ended at its passage or at the record's end with
/// a share at least the limit's and at most the whole run's, and each passage within its
/// bracket, the two estimates at most the 5 % precision apart.
#[test]
fn members_that_pass_every_limit_end_there_and_the_hunt_runs_the_same_members() {
    let table = |stop: bool| {
        // 0.6 s: the pulses' shaking (0.4 and 0.5 s) and some of what follows.
        let dir = scratch(&format!("hunt-stop-{stop}"));
        write_model(&dir, 0.6, "");
        write_hunt_sweep(&dir, &format!("{HUNT}\nstop_at_passage = {stop}"), LIMIT, 1);
        run_ok(2, &[dir.join("sweep.toml").to_str().unwrap()]);
        let text = std::fs::read_to_string(dir.join("sweep/sweep.csv")).unwrap();
        (dir, text)
    };
    let (whole_dir, whole) = table(false);
    let (ended_dir, ended) = table(true);
    let parse =
        |text: &str| -> Vec<Vec<String>> { text.lines().map(|l| l.split(',').map(str::to_string).collect()).collect() };
    let (w, e) = (parse(&whole), parse(&ended));
    let head = &w[0];
    let col = |n: &str| head.iter().position(|h| h == n).unwrap();
    let (share, until, reached) = (col("wall:share_dt_above_0.5"), col("ended_at_limits"), col("time_reached"));
    assert_eq!(w.len(), e.len(), "the same number of members");
    let mut early = 0;
    for (a, b) in w[1..].iter().zip(&e[1..]) {
        assert_eq!(a[0], b[0], "the same member in the same row");
        let (sa, sb): (f64, f64) = (a[share].parse().unwrap(), b[share].parse().unwrap());
        assert!(a[until].is_empty(), "run whole: {a:?}");
        if sa < 0.1 {
            assert_eq!(a, b, "a member below the limit runs whole either way");
        } else {
            assert!(sb >= 0.1 && sb <= sa + 1e-12, "{}: share {sb} against the whole run's {sa}", b[0]);
            if !b[until].is_empty() {
                let t: f64 = b[until].parse().unwrap();
                assert!((t - b[reached].parse::<f64>().unwrap()).abs() < 1e-9, "{b:?}");
                early += 1;
            }
        }
    }
    assert!(early > 0, "no member ended at its passage:\n{ended}");
    let (sw, se) = (json(&whole_dir.join("sweep/summary.json")), json(&ended_dir.join("sweep/summary.json")));
    assert_eq!(sw["hunts"], se["hunts"]);
    for v in 0..1 {
        for r in 0..2 {
            let x =
                |s: &serde_json::Value| s["limits"][0]["variants"][v]["crossings"][r]["intensity"].as_f64().unwrap();
            let (xw, xe) = (x(&sw), x(&se));
            assert!((xw - xe).abs() <= 0.05 * xw.max(xe), "record {r}: passage {xe} against {xw} run whole");
        }
    }
}

#[test]
fn a_hunt_ends_with_the_same_members_on_1_and_3_ranks_and_in_a_group_of_2() {
    // The four hunts of two records under two laws on 1 rank (one group: no other to wait for),
    // on 3 ranks in groups of 1 (oversubscribed: two groups wait while the third's member decides
    // its chain's next) and on 2 ranks as one group of 2: the same members with the same results,
    // sweep.csv to its 7 printed digits (each member the same time history on its group's ranks,
    // 1 and 2 ranks agreeing as the sweep's other tests show).
    let mut tables = Vec::new();
    for (np, group) in [(1usize, 1usize), (3, 1), (2, 2)] {
        let dir = scratch(&format!("hunt-ranks-{np}-{group}"));
        write_model(&dir, 0.3, "");
        write_hunt_sweep(&dir, HUNT, LIMIT, group);
        write_two_laws(&dir);
        run_ok(np, &[dir.join("sweep.toml").to_str().unwrap()]);
        tables.push(std::fs::read_to_string(dir.join("sweep/sweep.csv")).unwrap());
    }
    assert!(tables[0].lines().count() > 20, "{}", tables[0]);
    assert_eq!(tables[0], tables[1], "1 rank against 3 groups of 1");
    assert_eq!(tables[0], tables[2], "1 rank against a group of 2");
}

#[test]
fn a_limit_never_passed_up_to_the_cap_is_an_outcome_not_an_error() {
    // The whole wall with d_t > 0.5 (share 1.0) is not reached by 0.75 m/s² (the hunt: 0.25, 0.5,
    // 0.75 = the cap): both records end at the cap, censored there, and no fragility is fitted.
    let dir = scratch("hunt-cap");
    write_model(&dir, 0.3, "");
    write_hunt_sweep(
        &dir,
        "first = 0.25\nstep = 0.25\ncap = 0.75",
        "[[sweep.limit]]\ngroup = \"wall\"\nshare = 1.0",
        1,
    );
    run_ok(2, &[dir.join("sweep.toml").to_str().unwrap()]);
    let s = json(&dir.join("sweep/summary.json"));
    assert_eq!(s["members"].as_u64(), Some(6), "{s}");
    for r in 0..2 {
        let c = &s["limits"][0]["variants"][0]["crossings"][r];
        assert_eq!((c["how"].as_str(), c["censored_at"].as_f64()), (Some("above_cap"), Some(0.75)), "{c}");
        assert_eq!((s["hunts"][r]["end"].as_str(), s["hunts"][r]["at"].as_f64()), (Some("cap"), Some(0.75)));
    }
    let f = &s["limits"][0]["fragility"];
    assert!(f["fit"].is_null() && f["p_code_level"].is_null(), "{f}");
    assert_eq!((f["not_passed"].as_u64(), f["passed_by_code_level"].as_u64()), (Some(2), Some(0)), "{f}");
    let text = std::fs::read_to_string(dir.join("sweep/summary.txt")).unwrap();
    assert!(text.contains("rec-a not passed up to the cap 0.750"), "{text}");
    assert!(text.contains("not fitted") && text.contains("0 of 2 record-material pair(s) passed"), "{text}");
}

#[test]
fn a_member_that_stops_converging_ends_the_hunt_and_is_bisected() {
    // Newton on the initial stiffness with 4 iterations and 2 halvings per step (the model of
    // tests/sweep.rs' stopped members): it follows the uncracked wall, not a cracking one. The
    // hunt from 0.5 by 20 m/s² stops at 20.5 (or earlier) and the fill bisects down to the lowest
    // stopped level, within 5 % above the highest completed one.
    let dir = scratch("hunt-stopped");
    write_model(&dir, 0.3, "max_substeps = 2\nmax_iterations = 4");
    edit(
        &dir,
        "wall.toml",
        "newton = \"krylov\"\nforce_tolerance = 1e-9",
        "newton = \"initial\"\nforce_tolerance = 1e-6",
    );
    write_hunt_sweep(&dir, "first = 0.5\nstep = 20.0\ncap = 60.0", "[[sweep.limit]]\ngroup = \"wall\"\nshare = 1.0", 1);
    run_ok(2, &[dir.join("sweep.toml").to_str().unwrap()]);
    let s = json(&dir.join("sweep/summary.json"));
    let rows = rows(&dir);
    for (r, rec) in ["rec-a", "rec-b"].iter().enumerate() {
        assert_eq!(s["hunts"][r]["end"], "stopped", "{}", s["hunts"]);
        let c = &s["limits"][0]["variants"][0]["crossings"][r];
        assert_eq!(c["how"], "stopped", "{c}");
        let x = c["intensity"].as_f64().unwrap();
        let below = rows.iter().filter(|p| p.0 == *rec && p.2 == "completed").map(|p| p.1).fold(0.0f64, f64::max);
        assert!(rows.iter().any(|p| p.0 == *rec && p.2 == "stopped" && (p.1 - x).abs() < 1e-9), "{rows:?}");
        assert!(below < x && x - below <= 0.05 * x + 1e-9, "{rec}: stopped at {x}, completed up to {below}: {rows:?}");
        assert!(rows.iter().all(|p| p.0 != *rec || p.2 != "stopped" || p.1 >= x), "{rows:?}");
    }
    // Every pair passed at or below the code level (1 m/s²): P there is 1, from the fit or, where
    // both passages fall at one intensity (beta 0), from its step.
    let f = &s["limits"][0]["fragility"];
    assert!((f["p_code_level"].as_f64().unwrap() - 1.0).abs() < 1e-9, "{f}");
    assert_eq!(f["passed_by_code_level"].as_u64(), Some(2), "{f}");
}

#[test]
fn a_hunt_killed_and_restarted_ends_with_the_members_and_fragility_of_an_uninterrupted_one() {
    // 1 s of the records (100 steps, checkpoints every 10). The first run is killed at step 45 of
    // rec-b's second hunt level (PGA 0.5), an injected exit without cleanup as SIGKILL, before
    // that member passes the limit and ends there (at 0.5 s, `stop_at_passage`); `--restart`
    // replays both hunts from the outcomes, resumes the killed member from its checkpoint of step
    // 40 and ends with the same sweep.csv (to its 7 printed digits) and the same fragility
    // figures.
    let whole = scratch("hunt-resume-whole");
    write_model(&whole, 1.0, "");
    write_hunt_sweep(&whole, HUNT, LIMIT, 1);
    run_ok(2, &[whole.join("sweep.toml").to_str().unwrap()]);

    let dir = scratch("hunt-resume-killed");
    write_model(&dir, 1.0, "");
    write_hunt_sweep(&dir, HUNT, LIMIT, 1);
    let killed = "base-rec-b-pga0.5000";
    let mut cmd = std::process::Command::new("mpirun");
    cmd.args(["-n", "2", "--oversubscribe", "--bind-to", "none"])
        .arg(exe())
        .arg(dir.join("sweep.toml"))
        .env("OMPI_ALLOW_RUN_AS_ROOT", "1")
        .env("OMPI_ALLOW_RUN_AS_ROOT_CONFIRM", "1")
        .env("MASONRY_HPC_INJECT_KILL", format!("sweep_{killed}_step_45"));
    let out = run_with_timeout(cmd, std::time::Duration::from_secs(300));
    assert!(!out.status.success(), "the kill should end the sweep");
    let members = dir.join("sweep/members");
    assert!(!members.join(killed).join("outcome.json").is_file());
    assert!(members.join(killed).join("checkpoint/step-000000040").is_dir());
    let before = std::fs::read_dir(&members)
        .unwrap()
        .filter(|e| e.as_ref().unwrap().path().join("outcome.json").is_file())
        .count();
    assert!(before >= 1, "no member done before the kill");
    let out = run_ok(2, &["--restart", dir.join("sweep.toml").to_str().unwrap()]);
    let log = stdout(&out);
    assert!(log.contains(&format!("restart: {before} member(s) of the hunts done before")), "{log}");
    let a = std::fs::read_to_string(whole.join("sweep/sweep.csv")).unwrap();
    let b = std::fs::read_to_string(dir.join("sweep/sweep.csv")).unwrap();
    assert_eq!(a, b);
    let head: Vec<&str> = b.lines().next().unwrap().split(',').collect();
    let k = head.iter().position(|h| *h == "ended_at_limits").unwrap();
    let row = b.lines().find(|l| l.starts_with(killed)).unwrap();
    assert!(!row.split(',').nth(k).unwrap().is_empty(), "the resumed member ends at its passage: {row}");
    let (sa, sb) = (json(&whole.join("sweep/summary.json")), json(&dir.join("sweep/summary.json")));
    assert_eq!(sa["limits"], sb["limits"]);
    assert_eq!(sa["hunts"], sb["hunts"]);
    assert!(sa["limits"][0]["fragility"]["fit"]["median"].as_f64().is_some(), "{}", sa["limits"]);
    assert!(members.join(killed).join("results-restart-000040.h5").is_file());
}

/// The wall and a valid hunt in `dir`, then `from` replaced by `to` in sweep.toml: exit code 2
/// with every one of `needles` on 1 and 2 ranks, and no results written.
fn expect_hunt_error(name: &str, from: &str, to: &str, needles: &[&str]) {
    let dir = scratch(name);
    write_model(&dir, 0.3, "");
    write_hunt_sweep(&dir, HUNT, LIMIT, 1);
    edit(&dir, "sweep.toml", from, to);
    expect_job_error(&dir.join("sweep.toml"), 2, needles);
    assert!(!dir.join("sweep").exists(), "bad input must not leave results");
}

#[test]
fn a_hunt_without_a_limit_is_an_error_at_its_table() {
    // Line 9 of sweep.toml (write_hunt_sweep): [sweep.hunt].
    expect_hunt_error(
        "hunt-no-limit",
        LIMIT,
        "",
        &["sweep.toml:9:", "sweep.hunt", "a hunt needs at least one [[sweep.limit]]"],
    );
}

#[test]
fn a_precision_of_zero_or_below_is_an_error_at_its_key() {
    // Line 14: precision.
    for p in ["0.0", "-0.05"] {
        expect_hunt_error(
            &format!("hunt-precision{p}"),
            "precision = 0.05",
            &format!("precision = {p}"),
            &[
                "sweep.toml:14:",
                "sweep.hunt.precision",
                "expected a precision in (0, 1)",
                &format!("got {}", p.parse::<f64>().unwrap()),
            ],
        );
    }
}

#[test]
fn a_grid_and_a_hunt_together_or_neither_without_a_code_level_are_errors() {
    expect_hunt_error(
        "hunt-and-grid",
        "code_level = 1.0",
        "code_level = 1.0\nintensities = [0.5, 1.0]",
        &["sweep.toml:9:", "sweep.intensities", "not both"],
    );
    // Line 6: [sweep].
    expect_hunt_error(
        "hunt-nor-grid",
        &format!("code_level = 1.0\n[sweep.hunt]\n{HUNT}\n"),
        "",
        &["sweep.toml:6:", "no intensities: give intensities = [...]", "or code_level"],
    );
}

#[test]
fn without_a_hunt_table_the_sweep_hunts_from_the_code_level() {
    // Neither intensities nor [sweep.hunt]: the hunt with its defaults on code_level = 1.0, first
    // and step a quarter of it, the step growing by an eighth, the cap at 3 times it.
    let dir = scratch("hunt-defaults");
    write_model(&dir, 0.3, "");
    write_hunt_sweep(&dir, HUNT, LIMIT, 1);
    edit(&dir, "sweep.toml", &format!("[sweep.hunt]\n{HUNT}\n"), "");
    let out = run_ok(0, &["check", dir.join("sweep.toml").to_str().unwrap()]);
    let text = stdout(&out);
    assert!(text.contains("PGA hunted from 0.25 by 0.25 (+0.125 per level) up to 3 m/s^2"), "{text}");
    assert!(text.contains("bisected to 5 %"), "{text}");
}
