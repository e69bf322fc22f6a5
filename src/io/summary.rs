//! `summary.json`: the format version every summary starts with, and fixed-size arrays written
//! as objects with named fields (`"energy": {"input": …, "kinetic": …}` rather than a bare list
//! whose order a reader must know).
//!
//! A struct keeps its array (`[f64; 3]`, indexed in the code as before) and names it for the
//! file with `#[serde(with = "crate::io::summary::xyz")]`; each named layout below is a module
//! with `serialize` and `deserialize` (and `option` for an `Option` of the array), so files that
//! are read back (`stages.json`, a sweep member's `outcome.json`) read the names too.
//!
//! Series (a value per step, evaluation or mode) stay arrays: their index is their meaning.
use serde::Serialize;

/// The version of the layout of every `summary.json` (its `"format"` key). 2: arrays of values
/// with distinct meanings became objects with named fields (docs/outputs.md).
pub const SUMMARY_FORMAT: u32 = 2;

/// `summary` as pretty JSON with `"format"` first.
pub fn summary_json(summary: &impl Serialize) -> serde_json::Result<String> {
    #[derive(Serialize)]
    struct Versioned<'a, T: Serialize> {
        format: u32,
        #[serde(flatten)]
        summary: &'a T,
    }
    serde_json::to_string_pretty(&Versioned { format: SUMMARY_FORMAT, summary })
}

/// Defines a named layout: a module whose `serialize` / `deserialize` write and read `[T; N]` as
/// an object with the given field names, in order. Other modules define their own with
/// `crate::io::summary::named!(name: ["a", "b"]);`.
macro_rules! named {
    ($(#[$doc:meta])* $name:ident: [$($field:literal),+ $(,)?]) => {
        $(#[$doc])*
        #[allow(dead_code)]
        pub mod $name {
            /// The field names, in the array's order.
            pub const NAMES: &[&str] = &[$($field),+];
            const N: usize = NAMES.len();

            /// The array as an object.
            pub fn serialize<T: serde::Serialize, S: serde::Serializer>(v: &[T; N], s: S) -> Result<S::Ok, S::Error> {
                $crate::io::summary::write_named(NAMES, v, s)
            }

            /// The object as the array (every name required).
            pub fn deserialize<'de, T: serde::Deserialize<'de>, D: serde::Deserializer<'de>>(
                d: D,
            ) -> Result<[T; N], D::Error> {
                $crate::io::summary::read_named(NAMES, d)
            }

            /// The same for an `Option` of the array (`null` for `None`).
            pub mod option {
                use super::{NAMES, N};

                /// `None` as `null`, else as the object.
                pub fn serialize<T: serde::Serialize, S: serde::Serializer>(
                    v: &Option<[T; N]>,
                    s: S,
                ) -> Result<S::Ok, S::Error> {
                    match v {
                        Some(v) => $crate::io::summary::write_named(NAMES, v, s),
                        None => s.serialize_none(),
                    }
                }

                /// `null` as `None`, else the object as the array.
                pub fn deserialize<'de, T: serde::Deserialize<'de>, D: serde::Deserializer<'de>>(
                    d: D,
                ) -> Result<Option<[T; N]>, D::Error> {
                    let m: Option<std::collections::BTreeMap<String, T>> = serde::Deserialize::deserialize(d)?;
                    m.map(|m| $crate::io::summary::from_map(NAMES, m)).transpose()
                }
            }
        }
    };
}

pub(crate) use named;

/// A result as `{"Ok": value}` or `{"Err": message}`: a typed error as the summaries write it.
pub fn with_message<T: Serialize, E: std::fmt::Display, S: serde::Serializer>(
    r: &Result<T, E>,
    s: S,
) -> Result<S::Ok, S::Error> {
    match r {
        Ok(v) => s.serialize_newtype_variant("Result", 0, "Ok", v),
        Err(e) => s.serialize_newtype_variant("Result", 1, "Err", &e.to_string()),
    }
}

/// Writes `v` as an object with `names` as keys (for [`named!`]).
pub fn write_named<T: Serialize, S: serde::Serializer>(names: &[&str], v: &[T], s: S) -> Result<S::Ok, S::Error> {
    use serde::ser::SerializeMap;
    let mut m = s.serialize_map(Some(names.len().min(v.len())))?;
    for (k, x) in names.iter().zip(v) {
        m.serialize_entry(k, x)?;
    }
    m.end()
}

/// Reads an object with `names` as keys into an array in that order (for [`named!`]).
pub fn read_named<'de, T: serde::Deserialize<'de>, D: serde::Deserializer<'de>, const N: usize>(
    names: &[&str],
    d: D,
) -> Result<[T; N], D::Error> {
    let m: std::collections::BTreeMap<String, T> = serde::Deserialize::deserialize(d)?;
    from_map(names, m)
}

/// The values of `m` under `names`, in that order (for [`named!`]).
pub fn from_map<T, E: serde::de::Error, const N: usize>(
    names: &[&str],
    mut m: std::collections::BTreeMap<String, T>,
) -> Result<[T; N], E> {
    let mut out = Vec::with_capacity(N);
    for k in names {
        out.push(m.remove(*k).ok_or_else(|| E::custom(format!("missing field `{k}`")))?);
    }
    out.try_into().map_err(|_| E::custom(format!("expected {N} named fields")))
}

named!(
    /// Components along the global axes: `x`, `y`, `z`.
    xyz: ["x", "y", "z"]
);
named!(
    /// A force and a moment resultant: `fx`, `fy`, `fz` [N], `mx`, `my`, `mz` [N m].
    wrench: ["fx", "fy", "fz", "mx", "my", "mz"]
);
named!(
    /// Tensile and compressive damage: `d_t`, `d_c`.
    damage: ["d_t", "d_c"]
);
named!(
    /// A value before and after a change: `before`, `after`.
    before_after: ["before", "after"]
);
named!(
    /// The two sides of a material test: `tension`, `compression`.
    tension_compression: ["tension", "compression"]
);
named!(
    /// The bounds of an interval: `low`, `high`.
    bounds: ["low", "high"]
);

/// An interval `(low, high)` as `{"low": …, "high": …}` (for `serialize_with`).
pub fn low_high<S: serde::Serializer>(r: &(f64, f64), s: S) -> Result<S::Ok, S::Error> {
    write_named(&["low", "high"], &[r.0, r.1], s)
}

#[cfg(test)]
mod tests {
    use serde::{Deserialize, Serialize};

    #[derive(Serialize, Deserialize, PartialEq, Debug)]
    struct S {
        #[serde(with = "super::xyz")]
        p: [f64; 3],
        #[serde(with = "super::damage::option")]
        d: Option<[f64; 2]>,
    }

    /// Named on the way out, the same array on the way back; `"format"` first.
    #[test]
    fn arrays_are_written_and_read_by_name() {
        let s = S { p: [1.0, 2.0, 3.0], d: Some([0.5, 0.25]) };
        let text = super::summary_json(&s).unwrap();
        assert!(text.starts_with("{\n  \"format\": 2,"), "{text}");
        let v: serde_json::Value = serde_json::from_str(&text).unwrap();
        assert_eq!(v["p"]["y"], 2.0);
        assert_eq!(v["d"]["d_c"], 0.25);
        let back: S = serde_json::from_value(v).unwrap();
        assert_eq!(back, s);
        let none: S = serde_json::from_str(r#"{"p": {"x": 0, "y": 0, "z": 0}, "d": null}"#).unwrap();
        assert_eq!(none.d, None);
        let missing = serde_json::from_str::<S>(r#"{"p": {"x": 0, "y": 0}, "d": null}"#);
        assert!(missing.unwrap_err().to_string().contains("missing field `z`"));
    }
}
