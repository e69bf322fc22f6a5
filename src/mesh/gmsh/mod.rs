//! Gmsh MSH 4.1 reader (ASCII and binary).
//!
//! [`read_msh`] reads the whole file into memory and makes a single pass over it. It interprets
//! `$MeshFormat`, `$PhysicalNames`, `$Entities`, `$Nodes` and `$Elements` (see `sections.rs`
//! for their layouts) and skips every other section (`$PartitionedEntities`, `$Periodic`,
//! `$NodeData`, `$Comments`, ...) by scanning to its `$End...` line. Node tags become dense
//! indices in order of appearance; cells refer to those indices.
//!
//! Bad input is always an [`MshError`] naming the file and the line (ASCII) or byte offset
//! (binary) — never a panic: counts read from the file bound nothing but loops that consume
//! the file, and allocations are capped by the file's size.

mod cursor;
mod error;
mod sections;
mod tagmap;
#[cfg(test)]
mod tests;

pub use error::{element_type_name, Location, MshError};

use super::Mesh;
use cursor::Cursor;
use error::show;
use sections::Builder;
use std::path::Path;

/// Reads a Gmsh MSH 4.1 file, ASCII or binary.
///
/// Supported element types: 1-node points (15), 2-node lines (1), 3-node triangles (2) and
/// 4-node quadrangles (3); any other type is an [`MshError::UnsupportedElement`].
pub fn read_msh(path: &Path) -> Result<Mesh, MshError> {
    let shown = path.display().to_string();
    let data = std::fs::read(path).map_err(|source| MshError::Io { path: shown.clone(), source })?;
    parse_msh(&data, &shown)
}

/// Parses the bytes of an MSH 4.1 file; `path` names it in error messages.
pub(crate) fn parse_msh(data: &[u8], path: &str) -> Result<Mesh, MshError> {
    let mut c = Cursor::new(data, path);
    match c.next_line() {
        Some((line, _)) if line == b"$MeshFormat" => {}
        Some((line, _)) => return Err(MshError::NotMsh { path: path.to_string(), found: show(line) }),
        None => return Err(MshError::NotMsh { path: path.to_string(), found: String::new() }),
    }
    sections::mesh_format(&mut c)?;

    let mut b = Builder::default();
    while let Some((line, at)) = c.next_line() {
        let name = line
            .strip_prefix(b"$")
            .and_then(|n| std::str::from_utf8(n).ok())
            .filter(|n| !n.is_empty() && !n.starts_with("End") && !n.contains(char::is_whitespace))
            .ok_or_else(|| {
                c.format(at, format!("expected a section header such as $Nodes, found \"{}\"", show(line)))
            })?;
        c.section = name;
        match name {
            "PhysicalNames" => sections::physical_names(&mut c, &mut b)?,
            "Entities" => sections::entities(&mut c, &mut b)?,
            "Nodes" => sections::nodes(&mut c, &mut b)?,
            "Elements" => sections::elements(&mut c, &mut b)?,
            "MeshFormat" => return Err(c.format(at, "a second $MeshFormat section".to_string())),
            _ => {
                let marker = format!("$End{name}");
                if !c.skip_to_line(marker.as_bytes()) {
                    return Err(c.truncated("skipping to its end marker"));
                }
            }
        }
    }
    for (seen, section) in [(b.seen_nodes, "Nodes"), (b.seen_elements, "Elements")] {
        if !seen {
            return Err(MshError::MissingSection { path: path.to_string(), section });
        }
    }
    Ok(b.finish())
}
