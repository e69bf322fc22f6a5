//! The keys of [`keys`](super::keys) written out: as aligned text for a terminal, or as the
//! Markdown page `docs/input.md` (`masonry-hpc keys --markdown > docs/input.md`).
use super::keys::{KeyTable, KindKeys};

/// The command that writes `docs/input.md`.
pub const REGENERATE: &str = "cargo run --release -- keys --markdown > docs/input.md";

/// What each kind of job file is, for the page's headings.
fn kind_about(name: &str) -> &'static str {
    match name {
        "structural" => "A finite-element model of a structure: its mesh, parts, supports, loads, and the analysis.",
        "sweep" => "An incremental dynamic analysis: many time histories of one base job.",
        "record_set" => "Accelerograms compatible with a Eurocode 8 spectrum.",
        "spectrum" => "A ground motion's response spectra, against Eurocode 8.",
        "dem" => "Virtual tests of a stone wall (the DEM lab) over a batch of samples.",
        "identification" => "DEM calibration against laboratory numbers, virtual tests, the damage law fitted to them.",
        "material_point" => "The damage law at one material point along a strain path.",
        _ => "",
    }
}

/// The reference page of every key of every kind, in Markdown.
pub fn markdown(kinds: &[KindKeys]) -> String {
    let mut s = String::new();
    s.push_str("# Job file keys\n\n");
    s.push_str("<!-- Written by `masonry-hpc keys --markdown` from the config types (src/config/); do not edit.\n");
    s.push_str(&format!("     Regenerate: {REGENERATE}\n     tests/input_docs.rs fails when this page and the command disagree. -->\n\n"));
    s.push_str(
        "Every key of every kind of job file, with its type, default, unit and meaning, generated from \
         the typed config structs: their doc comments, serde defaults and renames. A job file is TOML; \
         `[analysis] type` picks its kind. Unknown keys are errors, named with their line and column. \
         Units are SI (README, \"Units\"). `NAME` stands for a name the job chooses (a material, a \
         section, a PETSc option). A default of `required` means the key must be given; an empty \
         default means the key is optional and its absence has the meaning described. \
         `masonry-hpc keys KIND` prints one kind's keys in a terminal.\n\n",
    );
    for k in kinds {
        s.push_str(&format!("* [{}](#{}): {}\n", k.name, anchor(&kind_heading(k)), kind_about(k.name)));
    }
    for k in kinds {
        s.push_str(&format!("\n## {}\n\n{} {}.\n", kind_heading(k), kind_about(k.name), kind_types(k)));
        for t in &k.tables {
            table_markdown(t, &mut s);
        }
    }
    s
}

fn kind_heading(k: &KindKeys) -> String {
    format!("{} jobs", k.name)
}

fn kind_types(k: &KindKeys) -> String {
    let types: Vec<String> = k.analysis_types.iter().map(|t| format!("`{t}`")).collect();
    format!("`[analysis] type` = {}", types.join(", "))
}

/// A heading's anchor as the forges slug it: lower case, punctuation dropped, spaces as dashes.
fn anchor(heading: &str) -> String {
    heading
        .to_lowercase()
        .chars()
        .filter_map(|c| match c {
            ' ' => Some('-'),
            c if c.is_alphanumeric() || c == '-' || c == '_' => Some(c),
            _ => None,
        })
        .collect()
}

fn table_markdown(t: &KeyTable, s: &mut String) {
    let variant = if t.variant.is_empty() { String::new() } else { format!(" with `{}`", t.variant) };
    let header = if t.header == "top level" { "top level".to_string() } else { format!("`{}`", t.header) };
    s.push_str(&format!("\n### {header}{variant}\n\n"));
    if !t.about.is_empty() {
        s.push_str(&format!("{}\n\n", cell(&t.about)));
    }
    if t.rows.is_empty() {
        s.push_str("No keys of its own: its tables follow.\n");
        return;
    }
    s.push_str("| key | type | default | unit | meaning |\n|---|---|---|---|---|\n");
    for r in &t.rows {
        let default = if r.default.is_empty() || r.default == "required" {
            r.default.clone()
        } else {
            format!("`{}`", r.default)
        };
        let unit = if r.unit.is_empty() { String::new() } else { r.unit.clone() };
        s.push_str(&format!(
            "| `{}` | {} | {} | {} | {} |\n",
            r.key,
            cell(&r.ty),
            cell(&default),
            cell(&unit),
            cell(&r.meaning)
        ));
    }
}

/// Text made safe for a table cell: `|` escaped, links to Rust items left as code.
fn cell(text: &str) -> String {
    text.replace('|', "\\|").replace("[`", "`").replace("`]", "`")
}

/// The keys of the kinds as text, one line per key, under each table's header.
pub fn text(kinds: &[KindKeys]) -> String {
    let mut s = String::new();
    for k in kinds {
        s.push_str(&format!("{}: {}\n", kind_heading(k), kind_types(k).replace('`', "")));
        for t in &k.tables {
            let variant = if t.variant.is_empty() { String::new() } else { format!("  ({})", t.variant) };
            s.push_str(&format!("\n  {}{variant}\n", t.header));
            let width = t.rows.iter().map(|r| r.key.chars().count()).max().unwrap_or(0);
            for r in &t.rows {
                let unit = if r.unit.is_empty() { String::new() } else { format!(" [{}]", r.unit) };
                let default = if r.default.is_empty() { String::new() } else { format!(" = {}", r.default) };
                s.push_str(&format!("    {:width$}  {}{default}{unit}: {}\n", r.key, r.ty, r.meaning));
            }
        }
        s.push('\n');
    }
    s
}
