//! The size rules of the code, checked rather than claimed:
//!
//! ```text
//!   a product file of src/            at most 600 lines before its #[cfg(test)] module
//!   a function of a product file      at most 100 lines
//!   test files (tests.rs, *_tests.rs under src/, tests/)   exempt
//! ```
//!
//! An exception is named in [`ALLOWED`], with the reason beside it.
//!
//! A function's length runs from its `fn` line to its closing brace, counted by brace depth with
//! string and character literals and `//` comments blanked first (a brace inside a raw string
//! would count: none of the sources has one). A failure names every offender with its length.
use std::path::{Path, PathBuf};

const FILE_LINES: usize = 600;
const FN_LINES: usize = 100;

/// Files (`src/...`) or functions (`src/...::name`) allowed over the limits, each with its reason.
/// None today.
const ALLOWED: &[(&str, &str)] = &[];

fn rust_files(dir: &Path, out: &mut Vec<PathBuf>) {
    for e in std::fs::read_dir(dir).unwrap_or_else(|e| panic!("{}: {e}", dir.display())) {
        let p = e.unwrap().path();
        if p.is_dir() {
            rust_files(&p, out);
        } else if p.extension().is_some_and(|x| x == "rs") {
            out.push(p);
        }
    }
}

fn is_test_file(p: &Path) -> bool {
    let name = p.file_stem().map(|s| s.to_string_lossy().into_owned()).unwrap_or_default();
    name == "tests" || name.ends_with("_tests")
}

/// `line` with the contents of string and character literals and a trailing `//` comment removed.
fn code_of(line: &str) -> String {
    let mut out = String::new();
    let mut chars = line.chars().peekable();
    let mut in_str = false;
    while let Some(c) = chars.next() {
        if in_str {
            match c {
                '\\' => {
                    chars.next();
                }
                '"' => {
                    in_str = false;
                    out.push('"');
                }
                _ => {}
            }
            continue;
        }
        match c {
            '"' => {
                in_str = true;
                out.push('"');
            }
            '/' if chars.peek() == Some(&'/') => break,
            // A char literal ('{', '\'', '\n'); a lifetime ('a) is left alone.
            '\'' => {
                let rest: String = chars.clone().take(3).collect();
                let len = if rest.starts_with('\\') {
                    rest.find('\'').map(|i| i + 1)
                } else if rest.chars().nth(1) == Some('\'') {
                    Some(2)
                } else {
                    None
                };
                match len {
                    Some(n) => {
                        for _ in 0..n {
                            chars.next();
                        }
                        out.push_str("' '");
                    }
                    None => out.push('\''),
                }
            }
            _ => out.push(c),
        }
    }
    out
}

/// The name of the function a line declares, if it does.
fn fn_name(code: &str) -> Option<String> {
    let t = code.trim_start();
    let mut words = t.split_whitespace().peekable();
    while let Some(w) = words.next() {
        match w {
            "pub" | "pub(crate)" | "pub(super)" | "const" | "async" | "unsafe" | "extern" | "\"C\"" | "\"\"" => {}
            w if w.starts_with("pub(") => {}
            "fn" => return words.next().map(|n| n.split(['(', '<']).next().unwrap_or(n).to_string()),
            _ => return None,
        }
    }
    None
}

/// Every function of `lines` longer than `FN_LINES`: (name, first line, length).
fn long_functions(lines: &[&str]) -> Vec<(String, usize, usize)> {
    let code: Vec<String> = lines.iter().map(|l| code_of(l)).collect();
    let mut out = Vec::new();
    for (i, c) in code.iter().enumerate() {
        let Some(name) = fn_name(c) else { continue };
        let mut depth = 0i64;
        let mut opened = false;
        for (j, c) in code.iter().enumerate().skip(i) {
            depth += c.matches('{').count() as i64 - c.matches('}').count() as i64;
            opened |= c.contains('{');
            if !opened && c.trim_end().ends_with(';') {
                break; // a declaration without a body
            }
            if opened && depth <= 0 {
                let len = j - i + 1;
                if len > FN_LINES {
                    out.push((name.clone(), i + 1, len));
                }
                break;
            }
        }
    }
    out
}

#[test]
fn sources_and_functions_stay_within_their_sizes() {
    let root = Path::new(env!("CARGO_MANIFEST_DIR"));
    let mut files = Vec::new();
    rust_files(&root.join("src"), &mut files);
    files.sort();
    let allowed = |what: &str| ALLOWED.iter().any(|(a, _)| *a == what);
    let mut faults = Vec::new();
    for f in files.iter().filter(|f| !is_test_file(f)) {
        let text = std::fs::read_to_string(f).unwrap();
        let lines: Vec<&str> = text.lines().collect();
        let rel = f.strip_prefix(root).unwrap().display().to_string();
        let body = lines.iter().position(|l| l.trim_start().starts_with("#[cfg(test)]")).unwrap_or(lines.len());
        if body > FILE_LINES && !allowed(&rel) {
            faults.push(format!("{rel}: {body} lines before its tests (at most {FILE_LINES})"));
        }
        for (name, at, len) in long_functions(&lines[..body]) {
            if !allowed(&format!("{rel}::{name}")) {
                faults.push(format!("{rel}:{at}: fn {name} has {len} lines (at most {FN_LINES})"));
            }
        }
    }
    assert!(files.len() > 100, "found only {} source files under src/", files.len());
    assert!(faults.is_empty(), "over the size limits:\n  {}", faults.join("\n  "));
}

/// The measure itself, on a known text: a 3-line function, braces inside strings and chars and
/// comments ignored, a declaration without a body skipped.
#[test]
fn the_function_measure_counts_braces_of_code_only() {
    let text = "fn a() {\n    let s = \"{{\"; let c = '{'; // {\n}\nfn b();\npub(crate) fn c<T>(x: T) {\n}\n";
    let lines: Vec<&str> = text.lines().collect();
    let code: Vec<String> = lines.iter().map(|l| code_of(l)).collect();
    assert_eq!(code[1].matches('{').count(), 0, "{}", code[1]);
    assert_eq!(fn_name(&code[0]).as_deref(), Some("a"));
    assert_eq!(fn_name(&code[4]).as_deref(), Some("c"));
    let many = format!("fn long() {{\n{}}}\n", "    x();\n".repeat(FN_LINES));
    let lines: Vec<&str> = many.lines().collect();
    assert_eq!(long_functions(&lines), vec![("long".to_string(), 1, FN_LINES + 2)]);
    assert!(long_functions(&text.lines().collect::<Vec<_>>()).is_empty());
}
