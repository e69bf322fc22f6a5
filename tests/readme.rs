//! The front door stays a front door: README.md is short, names only files that exist, gives the
//! two commands that CI and the main run really use, and the docs cite public references only.
//!
//! * README.md has at most 8,000 characters (Unicode scalar values, not bytes), ARCHITECTURE.md
//!   (a map read in ten minutes) at most 12,000, and every source file ARCHITECTURE.md names in
//!   backquotes (`name.rs`, `folder/`) exists under `src/` or `tests/`;
//! * every repository path it names (`jobs/…`, `scripts/…`, `docs/…`, `materials/…`, `meshes/…`,
//!   `src/…`, `tests/…`, `examples/…`) and every relative link target exists, except what runs
//!   write: paths under `results/` and `docs/img/`, and the generated pages of [`GENERATED`]
//!   while the script that writes them exists;
//! * its two commands are the script `.ci/run` calls and `scripts/run.sh` with that script's
//!   default job and rank count;
//! * it names every job kind of `src/config/kind.rs`;
//! * the relative links of README.md, CHANGELOG.md and `docs/*.md` resolve, anchors included
//!   (to a heading of the target, slugged as the forges do), with the same exemptions;
//! * README.md, CHANGELOG.md and every Markdown file under `docs/` cite no "SPEC §" (SPEC is an
//!   internal brief that does not ship: cite the paper or a public reference).
//!
//! No MPI, no build of the binary: the files are read as text.
use std::path::{Path, PathBuf};

/// The README's budget in characters.
const MAX_CHARS: usize = 8000;

/// ARCHITECTURE.md's budget in characters.
const MAX_ARCHITECTURE_CHARS: usize = 12000;

/// Path prefixes the README may name, all inside the repository.
const PREFIXES: [&str; 8] = ["jobs/", "scripts/", "docs/", "materials/", "meshes/", "src/", "tests/", "examples/"];

/// Prefixes of what runs write (results, pictures copied from them): not checked.
const WRITTEN_BY_RUNS: [&str; 2] = ["results/", "docs/img/"];

/// Pages a script writes, with the script: allowed to be missing while the script exists.
const GENERATED: [(&str, &str); 1] = [("docs/convergence.md", "scripts/convergence.py")];

fn root() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR"))
}

fn read(rel: &str) -> String {
    let p = root().join(rel);
    std::fs::read_to_string(&p).unwrap_or_else(|e| panic!("{}: {e}", p.display()))
}

fn path_char(c: char) -> bool {
    c.is_ascii_alphanumeric() || matches!(c, '_' | '-' | '.' | '/')
}

/// Every token of `text` that starts with one of `PREFIXES` at a word boundary (not inside a
/// longer path such as `results/x/docs/…`), up to the first character that cannot be part of a
/// path; a trailing `.` or `,` (end of a sentence) is dropped.
fn named_paths(text: &str) -> Vec<String> {
    let mut out = Vec::new();
    let chars: Vec<(usize, char)> = text.char_indices().collect();
    for (k, &(i, _)) in chars.iter().enumerate() {
        if k > 0 && path_char(chars[k - 1].1) {
            continue;
        }
        let rest = &text[i..];
        if !PREFIXES.iter().any(|p| rest.starts_with(p)) {
            continue;
        }
        let end = rest.find(|c: char| !path_char(c)).unwrap_or(rest.len());
        let token = rest[..end].trim_end_matches(['.', ',']);
        out.push(token.to_string());
    }
    out
}

/// The targets of the Markdown links `[text](target)` of `text` that stay in the repository
/// (not URLs), as `(path, anchor)`: the path empty for an anchor in the same file.
fn links(text: &str) -> Vec<(String, Option<String>)> {
    let mut out = Vec::new();
    for (i, _) in text.match_indices("](") {
        let rest = &text[i + 2..];
        let Some(end) = rest.find(')') else { continue };
        let target = rest[..end].trim();
        if target.is_empty() || target.contains("://") || target.starts_with("mailto:") {
            continue;
        }
        let (path, anchor) = match target.split_once('#') {
            Some((p, a)) => (p, Some(a.to_string())),
            None => (target, None),
        };
        out.push((path.to_string(), anchor));
    }
    out
}

/// The file targets of the links of `text` (anchors dropped).
fn link_targets(text: &str) -> Vec<String> {
    links(text).into_iter().map(|(p, _)| p).filter(|p| !p.is_empty()).collect()
}

/// `rel` (a link in the file `from`, both relative to the root) as a path from the root, with
/// `.` and `..` resolved.
fn resolve(from: &str, rel: &str) -> String {
    let mut parts: Vec<&str> = from.split('/').collect();
    parts.pop();
    for p in rel.split('/') {
        match p {
            "" | "." => {}
            ".." => {
                parts.pop();
            }
            _ => parts.push(p),
        }
    }
    parts.join("/")
}

/// The anchors of the headings of a Markdown text, as the forges slug them: lower case, letters,
/// digits, `-` and `_` kept, spaces to `-`, the rest dropped (code blocks skipped).
fn heading_anchors(text: &str) -> Vec<String> {
    let mut fenced = false;
    let mut out = Vec::new();
    for line in text.lines() {
        if line.starts_with("```") {
            fenced = !fenced;
        }
        if fenced || !line.starts_with('#') {
            continue;
        }
        let title = line.trim_start_matches('#').trim();
        let slug: String = title
            .to_lowercase()
            .chars()
            .filter_map(|c| match c {
                ' ' => Some('-'),
                c if c.is_alphanumeric() || c == '-' || c == '_' => Some(c),
                _ => None,
            })
            .collect();
        out.push(slug);
    }
    out
}

/// Whether `rel` must exist in the repository, and if not, why not.
fn exemption(rel: &str) -> Option<String> {
    if let Some(p) = WRITTEN_BY_RUNS.iter().find(|p| rel.starts_with(*p)) {
        return Some(format!("under {p}, written by runs"));
    }
    let (_, writer) = GENERATED.iter().find(|(page, _)| *page == rel)?;
    root().join(writer).is_file().then(|| format!("written by {writer}"))
}

fn missing(paths: &[String]) -> Vec<String> {
    let mut out: Vec<String> = paths
        .iter()
        .filter(|p| exemption(p).is_none() && !root().join(Path::new(p.as_str())).exists())
        .cloned()
        .collect();
    out.sort();
    out.dedup();
    out
}

#[test]
fn readme_is_at_most_8000_characters() {
    let n = read("README.md").chars().count();
    assert!(
        n <= MAX_CHARS,
        "README.md has {n} characters, more than {MAX_CHARS}: move the detail to docs/ and link to it"
    );
}

#[test]
fn architecture_is_at_most_12000_characters() {
    let n = read("ARCHITECTURE.md").chars().count();
    assert!(
        n <= MAX_ARCHITECTURE_CHARS,
        "ARCHITECTURE.md has {n} characters, more than {MAX_ARCHITECTURE_CHARS}: it is a map, the detail lives in the modules' docs"
    );
}

/// Every file and folder name under `dir`, relative paths with `/` included (`a/b.rs`, `a/`).
fn tree_names(dir: &Path, base: &str, out: &mut Vec<String>) {
    for e in std::fs::read_dir(dir).unwrap_or_else(|e| panic!("{}: {e}", dir.display())) {
        let p = e.unwrap().path();
        let name = p.file_name().unwrap().to_string_lossy().into_owned();
        let rel = format!("{base}{name}");
        if p.is_dir() {
            out.push(format!("{rel}/"));
            tree_names(&p, &format!("{rel}/"), out);
        } else {
            out.push(rel);
        }
    }
}

/// The backquoted names of `text` that look like a Rust source file or a folder: `x.rs`,
/// `a/b.rs`, `dir/` (no spaces, no wildcard).
fn backquoted_sources(text: &str) -> Vec<String> {
    text.split('`')
        .skip(1)
        .step_by(2)
        .filter(|t| !t.contains([' ', '*', ':']) && (t.ends_with(".rs") || t.ends_with('/')))
        .map(str::to_string)
        .collect()
}

#[test]
fn every_source_the_architecture_names_exists() {
    let named = backquoted_sources(&read("ARCHITECTURE.md"));
    assert!(named.iter().any(|t| t == "analysis/"), "the scanner found no `analysis/`: {named:?}");
    let mut tree = Vec::new();
    tree_names(&root().join("src"), "", &mut tree);
    tree_names(&root().join("tests"), "tests/", &mut tree);
    // A name matches a path that ends with it at a folder boundary.
    let found = |n: &str| tree.iter().any(|p| p == n || p.ends_with(&format!("/{n}")));
    let gone: Vec<&String> = named.iter().filter(|n| !found(n)).collect();
    assert!(gone.is_empty(), "ARCHITECTURE.md names sources that do not exist: {gone:?}");
}

#[test]
fn every_path_the_readme_names_exists() {
    let text = read("README.md");
    let named = named_paths(&text);
    assert!(named.iter().any(|p| p == "jobs/church.toml"), "the path scanner found no jobs/church.toml: {named:?}");
    let gone = missing(&named);
    assert!(gone.is_empty(), "README.md names paths that do not exist: {gone:?}");
    let links = link_targets(&text);
    assert!(links.iter().any(|p| p == "CITATION.cff"), "the link scanner found no CITATION.cff: {links:?}");
    let gone = missing(&links);
    assert!(gone.is_empty(), "README.md links to files that do not exist: {gone:?}");
}

/// The command lines of the README's "Two commands" section: its indented code lines.
fn readme_commands(text: &str) -> Vec<String> {
    let start = text.find("## Two commands").expect("README.md has a section '## Two commands'");
    let section = &text[start + 2..];
    let section = &section[..section.find("\n## ").unwrap_or(section.len())];
    section.lines().filter(|l| l.starts_with("    ") && !l.trim().is_empty()).map(|l| l.trim().to_string()).collect()
}

/// The script `.ci/run` runs: the first `scripts/…` word of a line that is not a comment.
fn ci_script() -> String {
    let ci = read(".ci/run");
    ci.lines()
        .filter(|l| !l.trim_start().starts_with('#'))
        .flat_map(|l| l.split_whitespace())
        .find(|w| w.starts_with("scripts/"))
        .expect(".ci/run calls a script under scripts/")
        .to_string()
}

/// `scripts/run.sh`'s default job (`job="${1:-…}"`) and rank count (`${NP:-…}`).
fn run_defaults() -> (String, String) {
    let run = read("scripts/run.sh");
    let after = |key: &str| -> String {
        let i = run.find(key).unwrap_or_else(|| panic!("scripts/run.sh has no '{key}'"));
        let rest = &run[i + key.len()..];
        rest[..rest.find('}').expect("a closing brace")].to_string()
    };
    (after("job=\"${1:-"), after("${NP:-"))
}

#[test]
fn the_readme_commands_are_those_ci_and_the_main_run_use() {
    let text = read("README.md");
    let commands = readme_commands(&text);
    assert_eq!(
        commands.len(),
        2,
        "README.md's 'Two commands' section has {} command lines: {commands:?}",
        commands.len()
    );
    let first_word = |c: &str| c.split_whitespace().next().unwrap_or("").to_string();

    let ci = ci_script();
    let test = commands.iter().find(|c| first_word(c) == ci).unwrap_or_else(|| {
        panic!("no README command runs {ci}, the script .ci/run calls: {commands:?}");
    });
    assert!(root().join(&ci).is_file(), "{ci} (called by .ci/run) does not exist");
    assert!(!test.contains("jobs/"), "the test command takes no job: {test}");

    let run = commands.iter().find(|c| first_word(c) == "scripts/run.sh").unwrap_or_else(|| {
        panic!("no README command runs scripts/run.sh: {commands:?}");
    });
    let (job, ranks) = run_defaults();
    assert!(run.contains(&job), "the README's run command should name scripts/run.sh's default job {job}: {run}");
    assert!(
        run.contains(&format!("{ranks} MPI ranks")),
        "the README's run command should say scripts/run.sh's default of {ranks} MPI ranks: {run}"
    );
    let script = read("scripts/run.sh");
    assert!(script.contains("post_church.sh") && run.contains("pictures"), "scripts/run.sh draws pictures: say so");
}

#[test]
fn the_readme_names_every_job_kind() {
    let kinds = read("src/config/kind.rs");
    let names: Vec<&str> = kinds
        .lines()
        .filter_map(|l| l.trim().strip_prefix("(\""))
        .filter_map(|l| l.split_once("\", JobKind::").map(|(name, _)| name))
        .collect();
    assert!(names.len() >= 12, "src/config/kind.rs: found only the kinds {names:?}");
    let text = read("README.md");
    let absent: Vec<&&str> = names.iter().filter(|n| !text.contains(&format!("`{n}`"))).collect();
    assert!(absent.is_empty(), "README.md's job kinds lack {absent:?}");
}

/// The Markdown files of the front door and the docs, relative to the root.
fn doc_files() -> Vec<String> {
    let mut files = vec![root().join("README.md"), root().join("CHANGELOG.md")];
    markdown_files(&root().join("docs"), &mut files);
    files.iter().map(|f| f.strip_prefix(root()).unwrap().to_string_lossy().replace('\\', "/")).collect()
}

#[test]
fn the_links_of_the_docs_resolve() {
    let files = doc_files();
    assert!(files.len() > 2, "no Markdown files under docs/: {files:?}");
    let mut broken = Vec::new();
    for f in &files {
        let text = read(f);
        for (path, anchor) in links(&text) {
            let target = if path.is_empty() { f.clone() } else { resolve(f, &path) };
            if exemption(&target).is_some() {
                continue;
            }
            let full = root().join(&target);
            if !full.exists() {
                broken.push(format!("{f}: ({path}): {target} does not exist"));
                continue;
            }
            let Some(anchor) = anchor else { continue };
            if !target.ends_with(".md") {
                continue;
            }
            if !heading_anchors(&read(&target)).contains(&anchor) {
                broken.push(format!("{f}: ({path}#{anchor}): no such heading in {target}"));
            }
        }
    }
    assert!(broken.is_empty(), "broken links:\n{}", broken.join("\n"));
}

fn markdown_files(dir: &Path, out: &mut Vec<PathBuf>) {
    let Ok(entries) = std::fs::read_dir(dir) else { return };
    for e in entries {
        let p = e.unwrap().path();
        if p.is_dir() {
            markdown_files(&p, out);
        } else if p.extension().is_some_and(|x| x == "md") {
            out.push(p);
        }
    }
}

#[test]
fn the_docs_cite_no_spec_sections() {
    let files = doc_files();
    assert!(files.len() > 2, "no Markdown files under docs/: {files:?}");
    let mut found = Vec::new();
    for f in &files {
        for (n, line) in read(f).lines().enumerate() {
            if line.contains("SPEC §") {
                found.push(format!("{f}:{}: {}", n + 1, line.trim()));
            }
        }
    }
    assert!(found.is_empty(), "cite the paper or a public reference, not SPEC:\n{}", found.join("\n"));
}

#[test]
fn the_scanners_find_what_they_should() {
    let text = "see jobs/church.toml, results/x/docs/a.md and (scripts/run.sh). [a](docs/b.md#x) [u](https://x.org/y)";
    assert_eq!(named_paths(text), ["jobs/church.toml", "scripts/run.sh", "docs/b.md"]);
    assert_eq!(link_targets(text), ["docs/b.md"]);
    assert!(exemption("results/church/pictures/damage-tension.png").is_some());
    assert!(exemption("docs/img/church-damage.png").is_some());
    assert!(exemption("docs/outputs.md").is_none());
    assert_eq!(resolve("docs/running.md", "../jobs/church.toml"), "jobs/church.toml");
    assert_eq!(resolve("docs/running.md", "outputs.md"), "docs/outputs.md");
    assert_eq!(
        heading_anchors("# A\n```\n# not\n```\n## summary.json (every job kind)\n### linear_static"),
        ["a", "summaryjson-every-job-kind", "linear_static"]
    );
}
