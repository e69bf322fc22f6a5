//! The text of a job file, kept to turn key paths and byte offsets into line and column numbers.
use super::error::{ConfigError, Location};
use std::ops::Range;
use std::path::{Path, PathBuf};
use toml::de::{DeTable, DeValue};

/// One step of a key path: a table key or an array index.
#[derive(Clone, Debug, PartialEq, Eq)]
pub enum Seg {
    /// A table key.
    Key(String),
    /// An array index.
    Index(usize),
}

impl Seg {
    /// The table key `k`.
    pub fn key(k: &str) -> Seg {
        Seg::Key(k.to_string())
    }

    /// The path of nested table keys: `Seg::path(&["analysis", "control"])` is `analysis.control`.
    pub fn path(keys: &[&str]) -> Vec<Seg> {
        keys.iter().map(|k| Seg::key(k)).collect()
    }
}

/// Formats a key path the way a user writes it: `parts[2].group`.
pub fn format_path(path: &[Seg]) -> String {
    let mut s = String::new();
    for seg in path {
        match seg {
            Seg::Key(k) => {
                if !s.is_empty() {
                    s.push('.');
                }
                s.push_str(k);
            }
            Seg::Index(i) => s.push_str(&format!("[{i}]")),
        }
    }
    s
}

/// A job file's path and text.
pub struct Source {
    /// The file.
    pub file: PathBuf,
    /// Its content.
    pub text: String,
}

impl Source {
    /// Reads `file`.
    pub fn read(file: &Path) -> Result<Source, ConfigError> {
        let text =
            std::fs::read_to_string(file).map_err(|e| ConfigError::Read { path: file.to_path_buf(), source: e })?;
        Ok(Source { file: file.to_path_buf(), text })
    }

    /// 1-based (line, column) of a byte offset (the column counts characters).
    pub fn line_col(&self, offset: usize) -> (usize, usize) {
        let mut offset = offset.min(self.text.len());
        while !self.text.is_char_boundary(offset) {
            offset -= 1;
        }
        let before = &self.text[..offset];
        let line = before.matches('\n').count() + 1;
        let col = before.rsplit('\n').next().map_or(0, |l| l.chars().count()) + 1;
        (line, col)
    }

    /// The byte span of the deepest part of `path` found in the document (the key of the last
    /// table entry reached, or the array element).
    pub fn span_of(&self, path: &[Seg]) -> Option<Range<usize>> {
        let root = DeTable::parse(&self.text).ok()?;
        let mut table: &DeTable = root.get_ref();
        let mut value: Option<&DeValue> = None;
        let mut best = None;
        for seg in path {
            match (seg, value) {
                (Seg::Key(k), None) => {
                    let (key, v) = table.iter().find(|(key, _)| key.get_ref().as_ref() == k.as_str())?;
                    best = Some(key.span());
                    value = Some(v.get_ref());
                    let _ = v;
                }
                (Seg::Key(k), Some(DeValue::Table(t))) => {
                    table = t;
                    let (key, v) = match t.iter().find(|(key, _)| key.get_ref().as_ref() == k.as_str()) {
                        Some(kv) => kv,
                        None => break,
                    };
                    best = Some(key.span());
                    value = Some(v.get_ref());
                }
                (Seg::Index(i), Some(DeValue::Array(a))) => match a.get(*i) {
                    Some(v) => {
                        best = Some(v.span());
                        value = Some(v.get_ref());
                    }
                    None => break,
                },
                _ => break,
            }
        }
        best
    }

    /// `v` when it is finite and > 0 ([`crate::bounds::positive`]), else the error at `path`:
    /// "`what` [`unit`]: expected > 0, got `v`" (no brackets when `unit` is empty).
    pub fn positive_finite(&self, path: &[Seg], v: f64, what: &str, unit: &str) -> Result<f64, ConfigError> {
        crate::bounds::positive(v).map_err(|b| self.out_of_bounds(path, b, what, unit))
    }

    /// `v` when it is finite and >= 0 ([`crate::bounds::non_negative`]), else the error at
    /// `path`: "`what` [`unit`]: expected >= 0, got `v`".
    pub fn non_negative(&self, path: &[Seg], v: f64, what: &str, unit: &str) -> Result<f64, ConfigError> {
        crate::bounds::non_negative(v).map_err(|b| self.out_of_bounds(path, b, what, unit))
    }

    /// The error at `path` for a value out of its bound: "`what` [`unit`]: `b`".
    pub fn out_of_bounds(&self, path: &[Seg], b: crate::bounds::OutOfBounds, what: &str, unit: &str) -> ConfigError {
        let unit = if unit.is_empty() { String::new() } else { format!(" [{unit}]") };
        self.error_at(path, format!("{what}{unit}: {b}"))
    }

    /// An `Invalid` error at `path` (located in the text when found there).
    pub fn error_at(&self, path: &[Seg], message: impl Into<String>) -> ConfigError {
        let (line, column) = match self.span_of(path) {
            Some(r) => {
                let (l, c) = self.line_col(r.start);
                (Some(l), Some(c))
            }
            None => (None, None),
        };
        let key = (!path.is_empty()).then(|| format_path(path));
        ConfigError::Invalid { at: Location { file: self.file.clone(), line, column, key }, message: message.into() }
    }

    /// An `Invalid` error at a byte span, with an optional key path.
    pub fn error_at_span(&self, span: Option<Range<usize>>, path: &[Seg], message: impl Into<String>) -> ConfigError {
        match span {
            Some(r) => {
                let (l, c) = self.line_col(r.start);
                ConfigError::Invalid {
                    at: Location {
                        file: self.file.clone(),
                        line: Some(l),
                        column: Some(c),
                        key: (!path.is_empty()).then(|| format_path(path)),
                    },
                    message: message.into(),
                }
            }
            None => self.error_at(path, message),
        }
    }

    /// Deserializes the whole document into `T`, turning any error into one that names the line,
    /// the column, the key and what was expected.
    pub fn deserialize<T: serde::de::DeserializeOwned>(&self) -> Result<T, ConfigError> {
        let de = toml::de::Deserializer::parse(&self.text)
            .map_err(|e| self.error_at_span(e.span(), &[], e.message().trim().to_string()))?;
        serde_path_to_error::deserialize(de).map_err(|e| {
            let path: Vec<Seg> = e
                .path()
                .iter()
                .filter_map(|s| match s {
                    serde_path_to_error::Segment::Map { key } => Some(Seg::Key(key.clone())),
                    serde_path_to_error::Segment::Seq { index } => Some(Seg::Index(*index)),
                    _ => None,
                })
                .collect();
            let inner = e.inner();
            let msg = inner.message().trim().to_string();
            // The toml span points at the offending key or value itself: prefer it.
            self.error_at_span(inner.span(), &path, msg)
        })
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn src(text: &str) -> Source {
        Source { file: "job.toml".into(), text: text.to_string() }
    }

    #[test]
    fn line_and_column_of_nested_keys() {
        let s = src("[a]\nx = 1\n[[b]]\ny = 2\n[[b]]\n  z = 3\n");
        let r = s.span_of(&[Seg::Key("b".into()), Seg::Index(1), Seg::Key("z".into())]).unwrap();
        assert_eq!(s.line_col(r.start), (6, 3));
        let r = s.span_of(&[Seg::Key("a".into()), Seg::Key("x".into())]).unwrap();
        assert_eq!(s.line_col(r.start), (2, 1));
        assert_eq!(format_path(&[Seg::Key("b".into()), Seg::Index(1), Seg::Key("z".into())]), "b[1].z");
    }
}
