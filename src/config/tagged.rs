//! Precise locations inside internally tagged tables (`[materials.X] type = "elastic"`).
//!
//! serde buffers an internally tagged table before choosing its variant, which drops the spans of
//! the keys inside it: an error there is first reported at the table. This second pass takes that
//! table out of the document with its spans, drops `type`, and deserializes the variant's own
//! struct from it, so the error names the inner key with its line and column.
use super::job::*;
use super::material_point::*;
use super::source::{Seg, Source};
use super::ConfigError;
use serde::de::DeserializeOwned;
use toml::de::{DeTable, DeValue};

/// Re-reports `err` at the key inside a tagged table when it can; otherwise returns it as is.
pub fn refine(src: &Source, err: ConfigError) -> ConfigError {
    let ConfigError::Invalid { at, .. } = &err else { return err };
    let Some(key) = &at.key else { return err };
    let path = parse_path(key);
    let kind = match path.first() {
        Some(Seg::Key(k)) => k.as_str(),
        _ => return err,
    };
    let table_path: Vec<Seg> = match (kind, path.len()) {
        ("materials" | "sections", 2) => path.clone(),
        ("loads", 2) => path.clone(),
        ("path", 1) => path.clone(),
        ("test", 1) => path.clone(),
        _ => return err,
    };
    let refined = match kind {
        "materials" => variant(src, &table_path, |t, tag| match tag {
            "elastic" => sub::<ElasticMaterial>(src, t, &table_path),
            "damage" => sub::<DamageMaterial>(src, t, &table_path),
            _ => None,
        }),
        "sections" => variant(src, &table_path, |t, tag| match tag {
            "frame" => sub::<FrameSectionConfig>(src, t, &table_path),
            "shell" => sub::<ShellSectionConfig>(src, t, &table_path),
            "tie" => sub::<TieSectionConfig>(src, t, &table_path),
            _ => None,
        }),
        "loads" => variant(src, &table_path, |t, tag| match tag {
            "nodal" => sub::<NodalLoadConfig>(src, t, &table_path),
            _ => None,
        }),
        "path" => variant(src, &table_path, |t, tag| match tag {
            "uniaxial_tension" => sub::<UniaxialTensionPath>(src, t, &table_path),
            "uniaxial_compression" => sub::<UniaxialCompressionPath>(src, t, &table_path),
            "uniaxial" => sub::<UniaxialPath>(src, t, &table_path),
            "cyclic" => sub::<CyclicPath>(src, t, &table_path),
            "biaxial" => sub::<BiaxialPath>(src, t, &table_path),
            "pure_shear" => sub::<PureShearPath>(src, t, &table_path),
            "shear_under_compression" => sub::<ShearUnderCompressionPath>(src, t, &table_path),
            _ => None,
        }),
        _ => None,
    };
    refined.unwrap_or(err)
}

fn parse_path(key: &str) -> Vec<Seg> {
    let mut out = Vec::new();
    for part in key.split('.') {
        let (name, rest) = part.split_once('[').map_or((part, None), |(n, r)| (n, Some(r)));
        out.push(Seg::Key(name.to_string()));
        if let Some(r) = rest {
            for idx in r.split('[') {
                if let Ok(i) = idx.trim_end_matches(']').parse() {
                    out.push(Seg::Index(i));
                }
            }
        }
    }
    out
}

fn variant(
    src: &Source,
    path: &[Seg],
    f: impl FnOnce(toml::Spanned<DeTable<'_>>, &str) -> Option<ConfigError>,
) -> Option<ConfigError> {
    let root = DeTable::parse(&src.text).ok()?;
    let mut value: Option<toml::Spanned<DeValue>> = None;
    let mut table = root.into_inner();
    for seg in path {
        let next = match (seg, value.take()) {
            (Seg::Key(k), None) => table.remove(k.as_str())?,
            (Seg::Key(k), Some(v)) => match v.into_inner() {
                DeValue::Table(mut t) => t.remove(k.as_str())?,
                _ => return None,
            },
            (Seg::Index(i), Some(v)) => match v.into_inner() {
                DeValue::Array(a) if *i < a.len() => a.into_iter().nth(*i)?,
                _ => return None,
            },
            (Seg::Index(_), None) => return None,
        };
        value = Some(next);
        table = DeTable::default();
    }
    let v = value?;
    let span = v.span();
    let DeValue::Table(mut t) = v.into_inner() else { return None };
    let tag = match t.remove("type").map(|v| v.into_inner()) {
        Some(DeValue::String(s)) => s.to_string(),
        _ => return None,
    };
    f(toml::Spanned::new(span, t), &tag)
}

fn sub<T: DeserializeOwned>(src: &Source, t: toml::Spanned<DeTable<'_>>, base: &[Seg]) -> Option<ConfigError> {
    let de = toml::de::Deserializer::from(t);
    match serde_path_to_error::deserialize::<_, T>(de) {
        Ok(_) => None,
        Err(e) => {
            let mut path = base.to_vec();
            path.extend(e.path().iter().filter_map(|s| match s {
                serde_path_to_error::Segment::Map { key } => Some(Seg::Key(key.clone())),
                serde_path_to_error::Segment::Seq { index } => Some(Seg::Index(*index)),
                _ => None,
            }));
            let inner = e.inner();
            Some(src.error_at_span(inner.span(), &path, inner.message().trim().to_string()))
        }
    }
}
