//! The keys of every job kind, read from the config types themselves: each job file's type
//! derives a JSON Schema (`schemars`, which follows the serde attributes: renames, defaults,
//! tags, unknown fields denied) whose doc comments are the keys' meanings. This module walks that
//! schema into tables of keys; `keys_render.rs` writes them as text or as `docs/input.md`
//! (`masonry-hpc keys --markdown`), so the reference cannot drift from the code.
//!
//! A key's unit is the first bracketed unit of its doc comment, written as `[m/s²]`, `[Pa]`,
//! `[kg/m³]`, `[-]` (dimensionless); see [`unit_of`].
use super::kind::{JobKind, ANALYSIS_TYPES};
use schemars::generate::SchemaSettings;
use schemars::JsonSchema;
use serde_json::{Map, Value};

/// One key of a table.
#[derive(Clone, Debug, PartialEq)]
pub struct KeyRow {
    /// The key as written in the job file (`NAME` for a key the user names).
    pub key: String,
    /// Its TOML type (`float`, `integer`, `string`, `bool`, an array, or the strings allowed).
    pub ty: String,
    /// Its default as TOML, `required`, or empty when it is optional without a default value.
    pub default: String,
    /// Its unit (from the doc comment), empty when none is written.
    pub unit: String,
    /// What it means: its doc comment on one line.
    pub meaning: String,
}

/// One table of a job file: `[analysis]`, `[[parts]]`, `[materials.NAME]`, ...
#[derive(Clone, Debug, PartialEq)]
pub struct KeyTable {
    /// The table's header as written, e.g. `[dynamics.damping]`, `[[dynamics.ground_motion]]`.
    pub header: String,
    /// The variant of a tagged table, e.g. `type = "modal"`; empty for plain tables.
    pub variant: String,
    /// What the table is (the first paragraph of its doc comment).
    pub about: String,
    /// Its keys, sorted by name.
    pub rows: Vec<KeyRow>,
}

/// The keys of one kind of job file.
#[derive(Clone, Debug, PartialEq)]
pub struct KindKeys {
    /// The kind's name (`structural`, `dem`, ...).
    pub name: &'static str,
    /// The `[analysis] type` values that select it.
    pub analysis_types: Vec<&'static str>,
    /// Its tables, in the order of the walk (top-level keys first).
    pub tables: Vec<KeyTable>,
}

/// The job kinds, by name, in the order of the reference page.
pub const KIND_NAMES: [(&str, JobKind); 7] = [
    ("structural", JobKind::Structural),
    ("sweep", JobKind::Sweep),
    ("record_set", JobKind::RecordSet),
    ("spectrum", JobKind::Spectrum),
    ("dem", JobKind::Dem),
    ("identification", JobKind::Identify),
    ("material_point", JobKind::MaterialPoint),
];

/// The kind named `name`: a kind of [`KIND_NAMES`] or any `[analysis] type` of [`ANALYSIS_TYPES`].
pub fn kind_named(name: &str) -> Option<JobKind> {
    KIND_NAMES.iter().chain(ANALYSIS_TYPES.iter()).find(|(n, _)| *n == name).map(|(_, k)| *k)
}

/// The keys of every kind, in the order of [`KIND_NAMES`].
pub fn all_keys() -> Vec<KindKeys> {
    KIND_NAMES.iter().map(|(_, k)| keys_of(*k)).collect()
}

/// The keys of the job files of `kind`.
pub fn keys_of(kind: JobKind) -> KindKeys {
    use super::*;
    let schema = match kind {
        JobKind::Structural => schema_of::<StructuralJobFile>(),
        JobKind::MaterialPoint => schema_of::<MaterialPointJobFile>(),
        JobKind::Dem => schema_of::<DemJobFile>(),
        JobKind::Spectrum => schema_of::<SpectrumJobFile>(),
        JobKind::Identify => schema_of::<IdentifyJobFile>(),
        JobKind::RecordSet => schema_of::<RecordSetJobFile>(),
        JobKind::Sweep => schema_of::<SweepJobFile>(),
    };
    let name = KIND_NAMES.iter().find(|(_, k)| *k == kind).map(|(n, _)| *n).unwrap_or("?");
    let analysis_types = ANALYSIS_TYPES.iter().filter(|(_, k)| *k == kind).map(|(n, _)| *n).collect();
    let mut tables = Vec::new();
    walk_table(&schema, &[], false, "", &mut tables);
    KindKeys { name, analysis_types, tables }
}

/// The schema of `T` with every subschema inlined.
fn schema_of<T: JsonSchema>() -> Value {
    let mut settings = SchemaSettings::draft2020_12();
    settings.inline_subschemas = true;
    settings.into_generator().into_root_schema_for::<T>().to_value()
}

/// What a property's schema is, for the walk.
enum Shape<'a> {
    /// A table with named keys.
    Table(&'a Value),
    /// Tables told apart by a tag key (`type = "..."`): (tag, value, variant schema).
    Tagged(Vec<(String, String, &'a Value)>),
    /// Tables under names the user chooses (`[materials.NAME]`), of this schema.
    Named(&'a Value),
    /// An array of tables (`[[parts]]`) of this schema.
    Array(&'a Value),
    /// A value.
    Leaf,
}

/// `s` without the `null` that an `Option` adds (`anyOf: [T, {type: null}]`).
fn non_null(s: &Value) -> &Value {
    let is_null = |m: &Value| m.get("type").and_then(Value::as_str) == Some("null");
    match s.get("anyOf").and_then(Value::as_array) {
        Some(ms) if ms.len() == 2 && ms.iter().any(is_null) => ms.iter().find(|m| !is_null(m)).unwrap_or(s),
        _ => s,
    }
}

fn shape(s: &Value) -> Shape<'_> {
    let s = non_null(s);
    if s.get("properties").is_some() {
        return Shape::Table(s);
    }
    if let Some(variants) = tagged_variants(s) {
        return Shape::Tagged(variants);
    }
    if let Some(items) = s.get("items") {
        if matches!(shape(items), Shape::Table(_) | Shape::Tagged(_)) {
            return Shape::Array(items);
        }
    }
    if let Some(v) = s.get("additionalProperties").filter(|v| v.is_object()) {
        if matches!(shape(v), Shape::Table(_) | Shape::Tagged(_)) {
            return Shape::Named(v);
        }
    }
    Shape::Leaf
}

/// The variants of an internally tagged enum: every `oneOf` member a table with one key whose
/// value is a constant string.
fn tagged_variants(s: &Value) -> Option<Vec<(String, String, &Value)>> {
    let members = s.get("oneOf").or_else(|| s.get("anyOf"))?.as_array()?;
    let mut out = Vec::new();
    for m in members {
        let props = m.get("properties")?.as_object()?;
        let (tag, value) = props.iter().find_map(|(k, v)| Some((k.clone(), v.get("const")?.as_str()?.to_string())))?;
        out.push((tag, value, m));
    }
    (!out.is_empty()).then_some(out)
}

/// A table found by the walk, to be walked next.
struct Pending<'a> {
    path: Vec<String>,
    array: bool,
    variant: String,
    schema: &'a Value,
}

/// Walks the table `s` at `path` (its header's segments), pushing it and its subtables.
fn walk_table(s: &Value, path: &[String], array: bool, variant: &str, out: &mut Vec<KeyTable>) {
    let empty = Map::new();
    let props = s.get("properties").and_then(Value::as_object).unwrap_or(&empty);
    let required: Vec<&str> = s
        .get("required")
        .and_then(Value::as_array)
        .map(|r| r.iter().filter_map(Value::as_str).collect())
        .unwrap_or_default();
    let mut rows = Vec::new();
    let mut subtables = Vec::new();
    for (key, p) in props {
        let mut sub = path.to_vec();
        sub.push(key.clone());
        match shape(p) {
            Shape::Table(t) => subtables.push(Pending { path: sub, array: false, variant: String::new(), schema: t }),
            Shape::Array(t) => push_shaped(t, sub, true, &mut subtables),
            Shape::Named(t) => {
                sub.push("NAME".into());
                push_shaped(t, sub, false, &mut subtables)
            }
            Shape::Tagged(vs) => {
                for (tag, value, v) in vs {
                    let variant = format!("{tag} = \"{value}\"");
                    subtables.push(Pending { path: sub.clone(), array: false, variant, schema: v });
                }
            }
            Shape::Leaf => rows.push(leaf_row(key, p, required.contains(&key.as_str()))),
        }
    }
    if let Some(v) = s.get("additionalProperties").filter(|v| v.is_object() && props.is_empty()) {
        // A table of free keys, e.g. `[solver.petsc]`.
        rows.push(KeyRow { key: "NAME".into(), ..leaf_row("NAME", v, false) });
    }
    if !path.is_empty() || !rows.is_empty() {
        let header = if array { format!("[[{}]]", path.join(".")) } else { format!("[{}]", path.join(".")) };
        let about = first_paragraph(s.get("description").and_then(Value::as_str).unwrap_or(""));
        out.push(KeyTable {
            header: if path.is_empty() { "top level".into() } else { header },
            variant: variant.into(),
            about,
            rows,
        });
    }
    for t in subtables {
        walk_table(t.schema, &t.path, t.array, &t.variant, out);
    }
}

/// Queues the table (or the tagged tables) of `t` at `path`.
fn push_shaped<'a>(t: &'a Value, path: Vec<String>, array: bool, q: &mut Vec<Pending<'a>>) {
    match shape(t) {
        Shape::Tagged(vs) => {
            for (tag, value, v) in vs {
                q.push(Pending { path: path.clone(), array, variant: format!("{tag} = \"{value}\""), schema: v });
            }
        }
        _ => q.push(Pending { path, array, variant: String::new(), schema: non_null(t) }),
    }
}

fn leaf_row(key: &str, p: &Value, required: bool) -> KeyRow {
    let meaning = one_line(p.get("description").and_then(Value::as_str).unwrap_or(""));
    let default = match (p.get("default"), p.get("const")) {
        (Some(d), _) => toml_literal(d),
        (None, Some(c)) => toml_literal(c),
        (None, None) if required => "required".into(),
        _ => String::new(),
    };
    KeyRow { key: key.into(), ty: type_name(p), default, unit: unit_of(&meaning), meaning }
}

/// The TOML type of a value's schema.
pub fn type_name(p: &Value) -> String {
    let p = non_null(p);
    if let Some(c) = p.get("const") {
        return format!("string {}", toml_literal(c));
    }
    if let Some(values) = string_choices(p) {
        return values.iter().map(|v| format!("\"{v}\"")).collect::<Vec<_>>().join(" or ");
    }
    if let Some(ms) = p.get("anyOf").or_else(|| p.get("oneOf")).and_then(Value::as_array) {
        let mut names: Vec<String> = ms.iter().map(type_name).collect();
        names.dedup();
        return names.join(" or ");
    }
    let ty = match p.get("type") {
        Some(Value::String(t)) => t.as_str(),
        Some(Value::Array(ts)) => ts.iter().filter_map(Value::as_str).find(|t| *t != "null").unwrap_or("any"),
        _ => "any",
    };
    match ty {
        "number" => "float".into(),
        "integer" => "integer".into(),
        "boolean" => "bool".into(),
        "string" => "string".into(),
        "array" => {
            let item = p.get("items").map(type_name).unwrap_or_else(|| "any".into());
            let plural = if item.chars().all(|c| c.is_ascii_alphabetic()) { format!("{item}s") } else { item };
            match (p.get("minItems"), p.get("maxItems")) {
                (Some(a), Some(b)) if a == b => format!("array of {a} {plural}"),
                _ => format!("array of {plural}"),
            }
        }
        "object" => "table".into(),
        _ => "any".into(),
    }
}

/// The strings a value may take (a unit enum), if it is one.
fn string_choices(p: &Value) -> Option<Vec<String>> {
    if let Some(e) = p.get("enum").and_then(Value::as_array) {
        return e.iter().map(|v| v.as_str().map(String::from)).collect();
    }
    let members = p.get("oneOf").or_else(|| p.get("anyOf"))?.as_array()?;
    let mut out = Vec::new();
    for m in members {
        match (m.get("const"), m.get("enum")) {
            (Some(Value::String(s)), _) => out.push(s.clone()),
            (None, Some(Value::Array(e))) => out.extend(e.iter().filter_map(Value::as_str).map(String::from)),
            _ => return None,
        }
    }
    Some(out)
}

/// A JSON value written as TOML.
pub fn toml_literal(v: &Value) -> String {
    match v {
        Value::Null => String::new(),
        Value::String(s) => format!("\"{s}\""),
        Value::Array(a) => format!("[{}]", a.iter().map(toml_literal).collect::<Vec<_>>().join(", ")),
        Value::Object(m) if m.is_empty() => "{}".into(),
        Value::Object(_) => "see the table".into(),
        Value::Number(n) => match n.as_f64().filter(|_| n.is_f64()) {
            Some(0.0) => "0.0".into(),
            Some(x) if !(1e-3..1e5).contains(&x.abs()) => format!("{x:e}"),
            Some(x) if x.fract() == 0.0 => format!("{x:.1}"),
            Some(x) => x.to_string(),
            None => n.to_string(),
        },
        Value::Bool(b) => b.to_string(),
    }
}

/// The unit of a key: the first `[...]` of its meaning whose content is made of units (m, N, Pa,
/// kg, s, Hz, J, rad, g, %, their prefixes, powers, products and quotients), or `[-]` for a
/// dimensionless number. Code spans and Markdown links are skipped.
pub fn unit_of(meaning: &str) -> String {
    let mut rest = meaning;
    let mut in_code = false;
    while let Some(i) = rest.find(['[', '`']) {
        let c = rest.as_bytes()[i];
        rest = &rest[i + 1..];
        if c == b'`' {
            in_code = !in_code;
            continue;
        }
        if in_code {
            continue;
        }
        let Some(end) = rest.find(']') else { break };
        let inner = &rest[..end];
        let link = rest[end + 1..].starts_with('(');
        if !link && is_unit(inner) {
            return inner.to_string();
        }
    }
    String::new()
}

const UNITS: [&str; 24] = [
    "m", "mm", "cm", "km", "N", "kN", "MN", "Pa", "kPa", "MPa", "GPa", "kg", "t", "s", "min", "h", "Hz", "J", "W",
    "rad", "g", "%", "1", "-",
];

fn is_unit(s: &str) -> bool {
    if s == "-" {
        return true;
    }
    let words: Vec<&str> = s
        .split(['/', '·', ' ', '*', '^', '(', ')', '²', '³', '⁴', '⁻', '¹'])
        .map(|t| t.trim_matches(|c: char| c.is_ascii_digit()))
        .filter(|t| !t.is_empty())
        .collect();
    !words.is_empty() && words.iter().all(|w| UNITS.contains(w))
}

/// A doc comment on one line: fenced code blocks dropped, lines joined.
pub fn one_line(doc: &str) -> String {
    let mut out = Vec::new();
    let mut fenced = false;
    for line in doc.lines() {
        if line.trim_start().starts_with("```") {
            fenced = !fenced;
            continue;
        }
        if !fenced && !line.trim().is_empty() {
            out.push(line.trim());
        }
    }
    out.join(" ")
}

fn first_paragraph(doc: &str) -> String {
    one_line(doc.split("\n\n").next().unwrap_or(""))
}
