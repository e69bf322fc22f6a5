//! Bad input to a record-set job (`[analysis] type = "record_set"`): one message naming the
//! file, line and key and what was expected, exit code 2, alone and under `mpirun -n 2` (neither
//! a hang nor one message per rank). The valid case is the committed job, results redirected.
mod common;
use common::*;
use std::path::{Path, PathBuf};

/// The committed job in `dir` (results in `dir/out`); returns its path.
fn valid_case(dir: &Path) -> PathBuf {
    let root = Path::new(env!("CARGO_MANIFEST_DIR"));
    let text = std::fs::read_to_string(root.join("jobs/record-set-ec8.toml")).unwrap();
    let text = text.replace("dir = \"../results/record-set-ec8\"", "dir = \"out\"\nexisting = \"overwrite\"");
    std::fs::write(dir.join("set.toml"), text).unwrap();
    dir.join("set.toml")
}

/// The line of the committed job that starts with `prefix` (1-based), for the expected location.
fn line_of(prefix: &str) -> usize {
    let root = Path::new(env!("CARGO_MANIFEST_DIR"));
    let text = std::fs::read_to_string(root.join("jobs/record-set-ec8.toml")).unwrap();
    text.lines().position(|l| l.starts_with(prefix)).expect("test setup: a line of the committed job") + 1
}

/// Replaces `from` by `to` in the valid case and expects exit code 2 with every one of `needles`.
fn expect_error(name: &str, from: &str, to: &str, needles: &[&str]) {
    let dir = scratch(name);
    let job = valid_case(&dir);
    edit(&dir, "set.toml", from, to);
    expect_job_error(&job, 2, needles);
    assert!(!dir.join("out").exists(), "bad input must not leave results");
}

#[test]
fn unknown_key_in_the_artificial_table() {
    let at = format!("set.toml:{}:1", line_of("seed = "));
    expect_error(
        "rs-unknown-key",
        "seed = 20260301",
        "sead = 20260301",
        &[&at, "record_set.artificial.sead", "unknown field `sead`", "expected one of `count`, `seed`"],
    );
}

#[test]
fn unknown_spectrum_type_and_ground() {
    expect_error(
        "rs-type",
        "spectrum_type = \"type1\"",
        "spectrum_type = \"type3\"",
        &["record_set.spectrum_type", "unknown variant `type3`, expected `type1` or `type2`"],
    );
    expect_error(
        "rs-ground",
        "ground = \"A\"",
        "ground = \"F\"",
        &["record_set.ground", "expected one of `A`, `B`, `C`, `D`, `E`"],
    );
}

#[test]
fn non_positive_ag() {
    let at = format!("set.toml:{}:1", line_of("ag = "));
    expect_error("rs-ag", "ag = 1.6 ", "ag = -1.0 ", &[&at, "record_set.ag", "a_g [m/s^2]: expected > 0, got -1"]);
}

#[test]
fn the_period_range_is_given_once() {
    expect_error("rs-t1-zero", "t1 = 0.333 ", "t1 = 0.0 ", &["record_set.t1", "T1 [s]: expected > 0, got 0"]);
    expect_error(
        "rs-both",
        "t1 = 0.333 ",
        "period_range = { min = 0.1, max = 0.5 }\nt1 = 0.333 ",
        &["record_set.period_range", "give either t1 or period_range, not both"],
    );
    expect_error("rs-neither", "t1 = 0.333 ", "# t1 = ", &["key 'record_set'", "give t1", "or period_range"]);
    expect_error(
        "rs-range",
        "t1 = 0.333 ",
        "period_range = { min = 0.5, max = 0.1 }\n# ",
        &["record_set.period_range", "expected 0 < min < max [s], got [0.5, 0.1]"],
    );
}

#[test]
fn the_envelope_must_fit_the_duration() {
    let at = format!("set.toml:{}:1", line_of("duration = "));
    expect_error(
        "rs-envelope",
        "stationary = 10.0",
        "stationary = 19.0",
        &[&at, "record_set.artificial.duration", "expected at least rise + stationary = 21 s, got 20 s"],
    );
    expect_error("rs-dt", "dt = 0.01", "dt = -0.01", &["record_set.artificial.dt", "dt [s]: expected > 0, got -0.01"]);
}

#[test]
fn bad_counts_seeds_and_filters() {
    expect_error(
        "rs-count",
        "count = 7",
        "count = 0",
        &["record_set.artificial.count", "expected 1 to 1000 records, got 0"],
    );
    expect_error("rs-seed", "seed = 20260301", "seed = -5", &["record_set.artificial.seed", "expected u64"]);
    expect_error(
        "rs-high-pass",
        "high_pass = 0.1",
        "high_pass = 60.0",
        &["record_set.artificial.high_pass", "expected 0 (none) or a corner in (0, 50) Hz, got 60"],
    );
    expect_error(
        "rs-matching",
        "min = 0.02, max = 4.0",
        "min = 4.0, max = 0.02",
        &["record_set.artificial.matching_periods", "expected 0 < min < max [s]"],
    );
    expect_error("rs-points", "range_points = 100", "range_points = 1", &["record_set.range_points", "got 1"]);
}

#[test]
fn a_recorded_record_is_read_at_load() {
    expect_error(
        "rs-missing-file",
        "[output]",
        "[[record_set.recorded]]\nfile = \"nope.AT2\"\nformat = \"at2\"\n\n[output]",
        &["record_set.recorded[0].file", "nope.AT2 does not exist"],
    );
    expect_error(
        "rs-no-units",
        "[output]",
        "[[record_set.recorded]]\nfile = \"set.toml\"\nformat = \"two_column\"\n\n[output]",
        &["record_set.recorded[0]", "a column file needs units = \"g\", \"m/s2\" or \"cm/s2\""],
    );
    // `scale` is the set's to choose: refused on a recorded record.
    expect_error(
        "rs-scale",
        "[output]",
        "[[record_set.recorded]]\nfile = \"x.AT2\"\nformat = \"at2\"\nscale = 2.0\n\n[output]",
        &["record_set.recorded[0].scale", "unknown field `scale`"],
    );
}

#[test]
fn a_set_without_records() {
    let dir = scratch("rs-empty");
    let job = valid_case(&dir);
    let text = std::fs::read_to_string(&job).unwrap();
    let start = text.find("[record_set.artificial]").unwrap();
    let end = text.find("[output]").unwrap();
    std::fs::write(&job, format!("{}{}", &text[..start], &text[end..])).unwrap();
    expect_job_error(&job, 2, &["key 'record_set'", "the set has no record"]);
}
