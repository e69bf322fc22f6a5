//! The crate's layers (src/lib.rs): each top-level module of `src/` imports only from its own
//! layer or the layers below, and no two modules import each other, directly or through others.
//!
//! ```text
//!   6  run                                   jobs: dispatch, the non-FE job drivers
//!   5  analysis, error, fault                FE analyses and machinery; the run's error
//!   4  model, config                         the structural model, typed job files
//!   3  element, material, dem, identify, seismic
//!   2  petsc, mesh, io, parallel, plot       platform
//!   1  bounds                                input bounds
//! ```
//! An import is any `crate::<module>` path in code (comments and doc links excluded): a
//! `use crate::x::…`, a `crate::x::f(…)` call, or a name inside `use crate::{…}`.
use std::collections::{BTreeMap, BTreeSet};
use std::path::{Path, PathBuf};

const LAYERS: [(&str, u32); 18] = [
    ("run", 6),
    ("analysis", 5),
    ("error", 5),
    ("fault", 5),
    ("model", 4),
    ("config", 4),
    ("element", 3),
    ("material", 3),
    ("dem", 3),
    ("identify", 3),
    ("seismic", 3),
    ("petsc", 2),
    ("mesh", 2),
    ("io", 2),
    ("parallel", 2),
    ("plot", 2),
    ("bounds", 1),
    ("lib", 7),
];

fn rust_files(dir: &Path, out: &mut Vec<PathBuf>) {
    for e in std::fs::read_dir(dir).unwrap() {
        let p = e.unwrap().path();
        if p.is_dir() {
            rust_files(&p, out);
        } else if p.extension().is_some_and(|x| x == "rs") {
            out.push(p);
        }
    }
}

/// The top-level module a file belongs to (`src/analysis/x.rs` → analysis, `src/error.rs` → error).
fn module_of(src: &Path, file: &Path) -> String {
    let rel = file.strip_prefix(src).unwrap();
    let first = rel.components().next().unwrap().as_os_str().to_string_lossy().into_owned();
    first.trim_end_matches(".rs").to_string()
}

/// The modules a file's code names through `crate::`.
fn imports(text: &str, modules: &BTreeSet<String>) -> BTreeSet<String> {
    let code: String = text.lines().filter(|l| !l.trim_start().starts_with("//")).collect::<Vec<_>>().join("\n");
    let mut found = BTreeSet::new();
    let mut rest = code.as_str();
    while let Some(i) = rest.find("crate::") {
        rest = &rest[i + "crate::".len()..];
        if let Some(group) = rest.strip_prefix('{') {
            // use crate::{a::X, b, c::{…}}: every name at the group's top level.
            let end = group.find('}').unwrap_or(group.len());
            for part in group[..end].split(',') {
                let name: String = part.trim().chars().take_while(|c| c.is_alphanumeric() || *c == '_').collect();
                if modules.contains(&name) {
                    found.insert(name);
                }
            }
        } else {
            let name: String = rest.chars().take_while(|c| c.is_alphanumeric() || *c == '_').collect();
            if modules.contains(&name) {
                found.insert(name);
            }
        }
    }
    found
}

#[test]
fn modules_import_downwards_only_and_without_cycles() {
    let src = PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("src");
    let layer: BTreeMap<String, u32> = LAYERS.iter().map(|(m, l)| (m.to_string(), *l)).collect();
    let mut files = Vec::new();
    rust_files(&src, &mut files);
    let mut modules: BTreeSet<String> = files.iter().map(|f| module_of(&src, f)).collect();
    modules.remove("main");
    for m in &modules {
        assert!(
            layer.contains_key(m),
            "src/{m}: a new top-level module: give it a layer in tests/layers.rs and src/lib.rs"
        );
    }
    let mut edges: BTreeMap<String, BTreeSet<String>> = BTreeMap::new();
    let mut wrong = Vec::new();
    for f in &files {
        let from = module_of(&src, f);
        if from == "main" || from == "lib" {
            continue;
        }
        for to in imports(&std::fs::read_to_string(f).unwrap(), &modules) {
            if to == from {
                continue;
            }
            if layer[&to] > layer[&from] {
                wrong.push(format!(
                    "{} ({from}, layer {}) imports {to} (layer {})",
                    f.display(),
                    layer[&from],
                    layer[&to]
                ));
            }
            edges.entry(from.clone()).or_default().insert(to);
        }
    }
    assert!(wrong.is_empty(), "imports that point up:\n{}", wrong.join("\n"));
    // No cycle: a depth-first search finds no module on its own path.
    fn visit(
        m: &str,
        edges: &BTreeMap<String, BTreeSet<String>>,
        path: &mut Vec<String>,
        done: &mut BTreeSet<String>,
    ) -> Option<Vec<String>> {
        if let Some(i) = path.iter().position(|p| p == m) {
            let mut cycle = path[i..].to_vec();
            cycle.push(m.to_string());
            return Some(cycle);
        }
        if done.contains(m) {
            return None;
        }
        path.push(m.to_string());
        for n in edges.get(m).into_iter().flatten() {
            if let Some(c) = visit(n, edges, path, done) {
                return Some(c);
            }
        }
        path.pop();
        done.insert(m.to_string());
        None
    }
    let mut done = BTreeSet::new();
    for m in edges.keys() {
        if let Some(c) = visit(m, &edges, &mut Vec::new(), &mut done) {
            panic!("an import cycle between modules: {}", c.join(" → "));
        }
    }
    // The check can fail: a planted upward import is found.
    let planted =
        imports("use crate::run::Error;\nfn f() { crate::analysis::x(); }\n// crate::dem in a comment\n", &modules);
    assert_eq!(planted, ["analysis", "run"].iter().map(|s| s.to_string()).collect());
}

/// The sibling files a file's code names, through `super::<file>` or `crate::<folder>::<file>`
/// (comments, doc links and the tests after `#[cfg(test)]` excluded).
fn sibling_imports(text: &str, folder_path: &str, siblings: &BTreeSet<String>) -> BTreeSet<String> {
    let code: Vec<&str> = text
        .lines()
        .take_while(|l| !l.trim_start().starts_with("#[cfg(test)]"))
        .filter(|l| !l.trim_start().starts_with("//"))
        .collect();
    let code = code.join("\n");
    let mut found = BTreeSet::new();
    for prefix in ["super::".to_string(), format!("crate::{folder_path}::")] {
        let mut rest = code.as_str();
        while let Some(i) = rest.find(&prefix) {
            rest = &rest[i + prefix.len()..];
            let names: Vec<String> = match rest.strip_prefix('{') {
                Some(group) => group[..group.find('}').unwrap_or(group.len())]
                    .split(',')
                    .map(|p| p.trim().chars().take_while(|c| c.is_alphanumeric() || *c == '_').collect())
                    .collect(),
                None => vec![rest.chars().take_while(|c| c.is_alphanumeric() || *c == '_').collect()],
            };
            found.extend(names.into_iter().filter(|n| siblings.contains(n)));
        }
    }
    found
}

/// Inside a folder, files import each other in a cycle only where the folder is one concept and
/// its module doc says so: every cycle among a folder's files is named, each file as `name.rs`,
/// in a paragraph of its `mod.rs` that starts with `**Cycles.**`.
#[test]
fn cycles_inside_a_folder_are_named_in_its_module_doc() {
    let src = PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("src");
    let mut files = Vec::new();
    rust_files(&src, &mut files);
    let folders: BTreeSet<PathBuf> = files
        .iter()
        .filter(|f| f.file_name().is_some_and(|n| n == "mod.rs"))
        .map(|f| f.parent().unwrap().into())
        .collect();
    let mut unnamed = Vec::new();
    for folder in &folders {
        let own: Vec<&PathBuf> = files.iter().filter(|f| f.parent() == Some(folder.as_path())).collect();
        let stem = |f: &Path| f.file_stem().unwrap().to_string_lossy().into_owned();
        let siblings: BTreeSet<String> = own.iter().map(|f| stem(f)).filter(|s| s != "mod").collect();
        let folder_path = folder.strip_prefix(&src).unwrap().to_string_lossy().replace('/', "::");
        let edges: BTreeMap<String, BTreeSet<String>> = own
            .iter()
            .filter(|f| stem(f) != "mod")
            .map(|f| {
                let mut to = sibling_imports(&std::fs::read_to_string(f).unwrap(), &folder_path, &siblings);
                to.remove(&stem(f));
                (stem(f), to)
            })
            .collect();
        // A file is in a cycle with every file that reaches it and that it reaches.
        let reach = |from: &str| -> BTreeSet<String> {
            let (mut seen, mut todo) = (BTreeSet::new(), vec![from.to_string()]);
            while let Some(m) = todo.pop() {
                for n in edges.get(&m).into_iter().flatten() {
                    if seen.insert(n.clone()) {
                        todo.push(n.clone());
                    }
                }
            }
            seen
        };
        let reaches: BTreeMap<&String, BTreeSet<String>> = edges.keys().map(|m| (m, reach(m))).collect();
        let doc = std::fs::read_to_string(folder.join("mod.rs")).unwrap();
        let cycles_doc: String = doc
            .split("\n//!\n")
            .filter(|p| p.trim_start().trim_start_matches("//!").trim_start().starts_with("**Cycles.**"))
            .collect();
        for (m, r) in &reaches {
            if r.contains(*m) && !cycles_doc.contains(&format!("`{m}.rs`")) {
                let with: Vec<&String> = r.iter().filter(|n| reaches[n].contains(*m)).collect();
                unnamed.push(format!("{}/{m}.rs (in a cycle with {with:?})", folder.display()));
            }
        }
    }
    assert!(
        unnamed.is_empty(),
        "files in an import cycle that their folder's mod.rs does not name under **Cycles.**:\n{}",
        unnamed.join("\n")
    );
}

/// One FE problem object: `Discretization::setup` (partition, numbering, elements) is called in
/// code at exactly one place, `FeProblem::setup` in `src/analysis/problem.rs`, and is visible to
/// `analysis/` only (`pub(super)`), so an analysis cannot set up a discretization of its own: a
/// chain of analyses on one problem partitions once. No process-global counter stands in for
/// this.
#[test]
fn the_discretization_is_set_up_by_the_fe_problem_only() {
    let src = Path::new(env!("CARGO_MANIFEST_DIR")).join("src");
    let mut files = Vec::new();
    rust_files(&src, &mut files);
    let mut calls = Vec::new();
    for f in &files {
        let text = std::fs::read_to_string(f).unwrap();
        for (i, line) in text.lines().enumerate() {
            let t = line.trim_start();
            if !t.starts_with("//") && t.contains("Discretization::setup(") {
                calls.push(format!("{}:{}", f.strip_prefix(&src).unwrap().display(), i + 1));
            }
        }
    }
    assert_eq!(calls.len(), 1, "Discretization::setup is called at {calls:?}: an analysis takes an FeProblem");
    assert!(calls[0].starts_with("analysis/problem.rs:"), "{calls:?}");
    let disc = std::fs::read_to_string(src.join("analysis/discretization.rs")).unwrap();
    assert!(disc.contains("    pub(super) fn setup("), "Discretization::setup must stay private to analysis/");
    assert!(!disc.contains("static "), "analysis/discretization.rs keeps no process-global state");
}
