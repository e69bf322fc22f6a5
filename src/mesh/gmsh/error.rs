//! Errors of the MSH reader: what went wrong, in which file, and where.
//!
//! Every message starts with the file path and, except for I/O errors and missing sections, the
//! position: `line N` in an ASCII file (1-based), `byte offset N` in a binary one (0-based), so a
//! user can open the file at the faulty spot.

use std::fmt;

/// Where in the file an error was found.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Location {
    /// A 1-based line number (ASCII files).
    Line(usize),
    /// A 0-based byte offset (binary files).
    Byte(usize),
}

impl fmt::Display for Location {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            Location::Line(n) => write!(f, "line {n}"),
            Location::Byte(n) => write!(f, "byte offset {n}"),
        }
    }
}

/// Errors reading a Gmsh MSH file.
#[derive(Debug, thiserror::Error)]
pub enum MshError {
    /// The file could not be read.
    #[error("{path}: {source}")]
    Io {
        /// The file.
        path: String,
        /// The cause.
        source: std::io::Error,
    },
    /// The file does not start with a `$MeshFormat` section.
    #[error("{path}: not a Gmsh MSH file: it must start with $MeshFormat, found \"{found}\"")]
    NotMsh {
        /// The file.
        path: String,
        /// The start of what the file holds instead.
        found: String,
    },
    /// The MSH version is not 4.1.
    #[error("{path}: {at}: unsupported MSH format version \"{found}\" (expected 4.1)")]
    Version {
        /// The file.
        path: String,
        /// Where.
        at: Location,
        /// The version the file declares.
        found: String,
    },
    /// A structural problem with no more specific variant (bad flag, bad dimension, ...).
    #[error("{path}: {at}: {message}")]
    Format {
        /// The file.
        path: String,
        /// Where.
        at: Location,
        /// What is wrong.
        message: String,
    },
    /// The file ends in the middle of a section.
    #[error("{path}: {at}: unexpected end of file while reading section ${section} ({what})")]
    Truncated {
        /// The file.
        path: String,
        /// Where (the end of the file).
        at: Location,
        /// The section being read.
        section: String,
        /// What was expected next.
        what: &'static str,
    },
    /// A token that is not the number the format requires there.
    #[error("{path}: {at}: expected {expected} ({what}), found \"{found}\"")]
    Garbled {
        /// The file.
        path: String,
        /// Where.
        at: Location,
        /// The kind of number expected ("an integer", "a float", ...).
        expected: &'static str,
        /// Which field was being read.
        what: &'static str,
        /// The token found.
        found: String,
    },
    /// A section end marker appears before the data its counts announce.
    #[error(
        "{path}: {at}: section ${section} ends early: found \"{found}\" where {what} was expected \
         (the counts in the section disagree with its data)"
    )]
    EarlyEnd {
        /// The file.
        path: String,
        /// Where.
        at: Location,
        /// The section.
        section: String,
        /// Which field was expected.
        what: &'static str,
        /// The token found.
        found: String,
    },
    /// Data follows where the section's counts say it should end.
    #[error(
        "{path}: {at}: expected $End{section} after the data of section ${section}, found \"{found}\" \
         (the counts in the section disagree with its data)"
    )]
    TrailingData {
        /// The file.
        path: String,
        /// Where.
        at: Location,
        /// The section.
        section: String,
        /// What was found instead of the end marker.
        found: String,
    },
    /// A total announced in a section header disagrees with the sum over its blocks.
    #[error("{path}: {at}: section ${section} declares {declared} {what} but its blocks hold {found}")]
    CountMismatch {
        /// The file.
        path: String,
        /// Where (the section header).
        at: Location,
        /// The section.
        section: String,
        /// What is counted ("nodes", "elements").
        what: &'static str,
        /// The announced total.
        declared: u64,
        /// The actual total.
        found: u64,
    },
    /// An element of a type the structural model does not handle.
    #[error(
        "{path}: {at}: unsupported element type: {} (type {type_number}), element tag {element}; \
         supported: {}",
        element_type_name(*type_number).unwrap_or("unknown type"),
        supported_types()
    )]
    UnsupportedElement {
        /// The file.
        path: String,
        /// Where.
        at: Location,
        /// The Gmsh element type number.
        type_number: i32,
        /// The tag of the first element of that type.
        element: u64,
    },
    /// An element refers to a node tag that the `$Nodes` section does not define.
    #[error("{path}: {at}: element {element} refers to node {node}, which $Nodes does not define")]
    DanglingNode {
        /// The file.
        path: String,
        /// Where.
        at: Location,
        /// The element tag.
        element: u64,
        /// The missing node tag.
        node: u64,
    },
    /// Two nodes share a tag.
    #[error("{path}: {at}: duplicate node tag {tag}")]
    DuplicateNode {
        /// The file.
        path: String,
        /// Where (the second occurrence).
        at: Location,
        /// The tag.
        tag: u64,
    },
    /// Two elements share a tag.
    #[error("{path}: {at}: duplicate element tag {tag}")]
    DuplicateElement {
        /// The file.
        path: String,
        /// Where (the second occurrence).
        at: Location,
        /// The tag.
        tag: u64,
    },
    /// A section the mesh needs is absent.
    #[error("{path}: the file has no ${section} section (a mesh needs $Nodes and $Elements)")]
    MissingSection {
        /// The file.
        path: String,
        /// The missing section.
        section: &'static str,
    },
}

/// Gmsh's name of element type `t`, for the types Gmsh defines up to order 5 (Gmsh reference
/// manual, "MSH file format", list of `elementType`).
pub fn element_type_name(t: i32) -> Option<&'static str> {
    Some(match t {
        1 => "2-node line",
        2 => "3-node triangle",
        3 => "4-node quadrangle",
        4 => "4-node tetrahedron",
        5 => "8-node hexahedron",
        6 => "6-node prism",
        7 => "5-node pyramid",
        8 => "3-node second order line",
        9 => "6-node second order triangle",
        10 => "9-node second order quadrangle",
        11 => "10-node second order tetrahedron",
        12 => "27-node second order hexahedron",
        13 => "18-node second order prism",
        14 => "14-node second order pyramid",
        15 => "1-node point",
        16 => "8-node second order quadrangle",
        17 => "20-node second order hexahedron",
        18 => "15-node second order prism",
        19 => "13-node second order pyramid",
        20 => "9-node third order incomplete triangle",
        21 => "10-node third order triangle",
        22 => "12-node fourth order incomplete triangle",
        23 => "15-node fourth order triangle",
        24 => "15-node fifth order incomplete triangle",
        25 => "21-node fifth order complete triangle",
        26 => "4-node third order edge",
        27 => "5-node fourth order edge",
        28 => "6-node fifth order edge",
        29 => "20-node third order tetrahedron",
        30 => "35-node fourth order tetrahedron",
        31 => "56-node fifth order tetrahedron",
        92 => "64-node third order hexahedron",
        93 => "125-node fourth order hexahedron",
        _ => return None,
    })
}

/// The supported types, listed for error messages.
fn supported_types() -> String {
    use super::super::CellKind;
    [CellKind::Point1, CellKind::Line2, CellKind::Tri3, CellKind::Quad4]
        .iter()
        .map(|k| format!("{k} (type {})", k.gmsh_type()))
        .collect::<Vec<_>>()
        .join(", ")
}

/// A token as shown in an error message: lossy UTF-8, at most 40 characters.
pub(super) fn show(bytes: &[u8]) -> String {
    let s = String::from_utf8_lossy(bytes);
    let mut out: String = s.chars().take(40).flat_map(char::escape_debug).collect();
    if s.chars().count() > 40 {
        out.push_str("...");
    }
    out
}
