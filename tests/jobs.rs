//! The committed example jobs (`jobs/*.toml`): each passes `masonry-hpc check` (its mesh, records
//! and every file it references are there, every key is known and valid), and its results go
//! under the repository's `results/` folder, where the README and the job's header say. The one
//! job that needs another's results first (`church-sweep.toml` reads the record set's summary)
//! passes or names that job.
mod common;
use common::{run, stderr, stdout};
use std::path::PathBuf;

fn root() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR"))
}

#[test]
fn every_example_job_checks_and_writes_under_results() {
    let mut jobs: Vec<PathBuf> = std::fs::read_dir(root().join("jobs"))
        .unwrap()
        .map(|e| e.unwrap().path())
        .filter(|p| p.extension().is_some_and(|x| x == "toml"))
        .collect();
    jobs.sort();
    assert!(jobs.len() >= 20, "{} jobs", jobs.len());
    let results = root().join("results");
    for job in &jobs {
        let name = job.file_name().unwrap().to_string_lossy().into_owned();
        let o = run(0, &["check", job.to_str().unwrap()]);
        let (out, err) = (stdout(&o), stderr(&o));
        if name == "church-sweep.toml" && !o.status.success() {
            assert!(err.contains("sweep.record_set") && err.contains("run the record_set job first"), "{name}: {err}");
            continue;
        }
        assert!(o.status.success(), "{name}: {out}\n{err}");
        let text = format!("{out}{err}");
        let dir = text.split("results would go to ").nth(1).and_then(|s| s.lines().next()).unwrap_or_default();
        let dir = if PathBuf::from(dir).is_absolute() { PathBuf::from(dir) } else { root().join(dir) };
        assert!(
            dir.starts_with(&results) && !dir.starts_with(root().join("jobs")),
            "{name}: results in {}",
            dir.display()
        );
    }
}
