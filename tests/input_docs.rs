//! docs/input.md, the reference of every job-file key, is generated from the config types by
//! `masonry-hpc keys --markdown`; these tests keep the committed page and the code together:
//!
//! * the page is what the command writes, byte for byte (a failure prints the command that
//!   regenerates it);
//! * every key of every committed job file (`jobs/*.toml`, tables, inline tables and arrays of
//!   tables walked) has a row in the page, in its job kind's section, under the header of its
//!   table (`NAME` standing for a name the job chooses) and of its variant (`type = "..."`): a
//!   key the renderer missed, or a table it did not reach, fails here;
//! * `masonry-hpc keys KIND` answers for one kind, and refuses a kind that does not exist.
//!
//! No MPI: the command answers before MPI starts.
use std::collections::BTreeSet;
use std::path::{Path, PathBuf};
use std::process::Command;

const REGENERATE: &str = "cargo run --release -- keys --markdown > docs/input.md";

fn root() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR"))
}

fn keys(args: &[&str]) -> std::process::Output {
    Command::new(env!("CARGO_BIN_EXE_masonry-hpc")).arg("keys").args(args).output().expect("run masonry-hpc keys")
}

#[test]
fn committed_page_is_what_the_command_writes() {
    let out = keys(&["--markdown"]);
    assert!(out.status.success(), "{}", String::from_utf8_lossy(&out.stderr));
    let written = String::from_utf8(out.stdout).unwrap();
    let committed = std::fs::read_to_string(root().join("docs/input.md")).unwrap_or_default();
    if written != committed {
        let line = written.lines().zip(committed.lines()).position(|(a, b)| a != b);
        panic!(
            "docs/input.md differs from what `masonry-hpc keys --markdown` writes (first difference at line {}).\n\
             Regenerate it with:\n    {REGENERATE}",
            line.map_or_else(|| "the end".to_string(), |l| (l + 1).to_string())
        );
    }
}

/// One table of the page: its kind section, header segments, variant and keys.
struct Table {
    kind: String,
    path: Vec<String>,
    variant: Option<(String, String)>,
    keys: BTreeSet<String>,
    /// Keys of type `table` with free names inside (PETSc's options): documented as a whole.
    maps: BTreeSet<String>,
}

/// The tables of docs/input.md, each with the `[analysis] type` values of its kind's section.
fn page_tables() -> (Vec<Table>, Vec<(String, String)>) {
    let text = std::fs::read_to_string(root().join("docs/input.md")).expect("docs/input.md");
    let (mut tables, mut kinds) = (Vec::new(), Vec::new());
    let mut kind = String::new();
    for line in text.lines() {
        if let Some(h) = line.strip_prefix("## ") {
            kind = h.to_string();
        } else if line.contains("`[analysis] type` =") && !kind.is_empty() {
            for t in line.split('`').skip(3).step_by(2) {
                kinds.push((t.to_string(), kind.clone()));
            }
        } else if let Some(h) = line.strip_prefix("### ") {
            let path = if h == "top level" {
                Vec::new()
            } else {
                let header = h.split('`').nth(1).expect("a header in backticks");
                header.trim_matches(['[', ']']).split('.').map(String::from).collect()
            };
            let variant = h.split(" with `").nth(1).map(|v| {
                let (tag, value) = v.trim_end_matches('`').split_once(" = ").expect("tag = \"value\"");
                (tag.to_string(), value.trim_matches('"').to_string())
            });
            tables.push(Table { kind: kind.clone(), path, variant, keys: BTreeSet::new(), maps: BTreeSet::new() });
        } else if let (Some(t), Some(row)) = (tables.last_mut(), line.strip_prefix("| `")) {
            let key = row.split('`').next().unwrap().to_string();
            if row.split('|').nth(1).map(str::trim) == Some("table") {
                t.maps.insert(key.clone());
            }
            t.keys.insert(key);
        }
    }
    (tables, kinds)
}

fn matches(header: &[String], path: &[String]) -> bool {
    header.len() == path.len() && header.iter().zip(path).all(|(h, p)| h == "NAME" || h == p)
}

/// The keys of `table` at `path` missing from the page's tables of `kind`, as `path.key`.
fn missing(table: &toml::Table, path: &[String], kind: &str, tables: &[Table], out: &mut Vec<String>) {
    let candidates: Vec<&Table> = tables
        .iter()
        .filter(|t| t.kind == kind && matches(&t.path, path))
        .filter(|t| t.variant.as_ref().is_none_or(|(tag, v)| table.get(tag).and_then(|x| x.as_str()) == Some(v)))
        .collect();
    for (key, value) in table {
        let mut sub = path.to_vec();
        sub.push(key.clone());
        match value {
            // A free map (its row says `table`): its entries are the map's, not the page's keys.
            toml::Value::Table(_) if candidates.iter().any(|c| c.maps.contains(key)) => {}
            toml::Value::Table(t) => missing(t, &sub, kind, tables, out),
            toml::Value::Array(a) if a.iter().all(|v| v.is_table()) && !a.is_empty() => {
                for v in a {
                    missing(v.as_table().unwrap(), &sub, kind, tables, out);
                }
            }
            _ => {
                if !candidates.iter().any(|t| t.keys.contains(key) || t.keys.contains("NAME")) {
                    out.push(sub.join("."));
                }
            }
        }
    }
}

fn job_files() -> Vec<PathBuf> {
    let mut files: Vec<PathBuf> = std::fs::read_dir(root().join("jobs"))
        .unwrap()
        .map(|e| e.unwrap().path())
        .filter(|p| p.extension().is_some_and(|x| x == "toml"))
        .collect();
    files.sort();
    files
}

fn analysis_type(job: &toml::Table) -> String {
    job["analysis"]["type"].as_str().expect("[analysis] type").to_string()
}

#[test]
fn every_key_of_every_committed_job_is_in_the_page() {
    let (tables, kinds) = page_tables();
    assert!(tables.len() > 40, "too few tables in docs/input.md: {}", tables.len());
    let files = job_files();
    assert!(files.len() >= 20, "jobs/: {} files", files.len());
    let mut problems = Vec::new();
    let mut checked = 0;
    for file in &files {
        let text = std::fs::read_to_string(file).unwrap();
        let job: toml::Table = toml::from_str(&text).unwrap_or_else(|e| panic!("{}: {e}", file.display()));
        let ty = analysis_type(&job);
        let Some((_, kind)) = kinds.iter().find(|(t, _)| *t == ty) else {
            problems.push(format!("{}: no section for [analysis] type = \"{ty}\"", name(file)));
            continue;
        };
        let mut out = Vec::new();
        missing(&job, &[], kind, &tables, &mut out);
        checked += 1;
        problems.extend(out.into_iter().map(|k| format!("{}: {k}", name(file))));
    }
    assert_eq!(checked, files.len());
    assert!(
        problems.is_empty(),
        "keys of committed jobs missing from docs/input.md (regenerate with `{REGENERATE}`, or document the key's type):\n  {}",
        problems.join("\n  ")
    );
}

fn name(p: &Path) -> String {
    p.file_name().unwrap().to_string_lossy().into_owned()
}

/// The walk finds a key that is not in the page (the check can fail).
#[test]
fn a_key_outside_the_page_is_found() {
    let (tables, kinds) = page_tables();
    let kind = &kinds.iter().find(|(t, _)| t == "dem").expect("a dem section").1;
    let job: toml::Table =
        toml::from_str("[analysis]\ntype = \"dem\"\nsamples = 2\n[mechanics]\nmu = 0.6\nglue = 1.0\n").unwrap();
    let mut out = Vec::new();
    missing(&job, &[], kind, &tables, &mut out);
    assert_eq!(out, vec!["mechanics.glue".to_string()]);
}

#[test]
fn one_kind_by_name_and_an_unknown_kind() {
    let out = keys(&["dem"]);
    assert!(out.status.success());
    let text = String::from_utf8(out.stdout).unwrap();
    assert!(text.starts_with("dem jobs") && text.contains("[mechanics]") && text.contains("e_bar"), "{text}");
    assert!(!text.contains("[dynamics]"), "only the dem kind: {text}");
    // An [analysis] type names its kind.
    let modal = String::from_utf8(keys(&["modal"]).stdout).unwrap();
    assert!(modal.starts_with("structural jobs") && modal.contains("[dynamics]"), "{modal}");
    let bad = keys(&["church"]);
    assert_eq!(bad.status.code(), Some(2));
    let err = String::from_utf8_lossy(&bad.stderr);
    assert!(err.contains("unknown job kind 'church'") && err.contains("material_point"), "{err}");
}
