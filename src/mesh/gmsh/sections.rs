//! The sections of an MSH 4.1 file that the reader interprets, each parsed into a [`Builder`].
//!
//! Layouts (Gmsh reference manual, "MSH file format", version 4.1); `size_t`, `int` and `double`
//! are read by [`Cursor`] in the file's encoding:
//!
//! ```text
//! $MeshFormat      version(4.1) file-type(0 ASCII | 1 binary) data-size(8)
//!                  [binary only: int 1, written natively, to tell the byte order]
//! $PhysicalNames   numPhysicalNames(ASCII int), then per line: dim tag "name"   (text even in binary files)
//! $Entities        numPoints numCurves numSurfaces numVolumes(size_t)
//!                  point:   tag(int) X Y Z(double) numPhysicalTags(size_t) physicalTag(int)...
//!                  curve/surface/volume: tag(int) minX minY minZ maxX maxY maxZ(double)
//!                           numPhysicalTags(size_t) physicalTag(int)...
//!                           numBoundingEntities(size_t) boundingTag(int)...
//! $Nodes           numEntityBlocks numNodes minNodeTag maxNodeTag(size_t)
//!                  per block: entityDim entityTag parametric(int) numNodesInBlock(size_t)
//!                             nodeTag(size_t) x numNodesInBlock,
//!                             then x y z(double) [u if dim>=1, v if dim>=2, w if dim==3, when parametric] x numNodesInBlock
//! $Elements        numEntityBlocks numElements minElementTag maxElementTag(size_t)
//!                  per block: entityDim entityTag elementType(int) numElementsInBlock(size_t)
//!                             then per element: elementTag(size_t) nodeTag(size_t) x nodes-per-type
//! ```

use super::cursor::{parse_i32, trim, Cursor};
use super::error::{show, Location, MshError};
use super::tagmap::TagMap;
use crate::mesh::{Cell, CellKind, Mesh, PhysicalGroup};

/// A mesh under construction, with the lookups the sections need.
#[derive(Default)]
pub(super) struct Builder {
    /// The mesh so far.
    pub mesh: Mesh,
    /// Node tag -> node index.
    nodes: TagMap,
    /// Entities in file order (for a deterministic order of unnamed groups).
    entity_order: Vec<(u8, i32)>,
    /// Which of `$Nodes`, `$Elements` were read.
    pub seen_nodes: bool,
    /// Whether `$Elements` was read.
    pub seen_elements: bool,
}

/// Capacity to reserve for `n` items, each taking at least `min_bytes` of the remaining file.
fn reserve_for(c: &Cursor<'_>, n: usize, min_bytes: usize) -> usize {
    n.min(c.remaining() / min_bytes.max(1))
}

/// `$MeshFormat`: checks version 4.1 and data size 8, and switches `c` to binary if needed.
pub(super) fn mesh_format(c: &mut Cursor<'_>) -> Result<(), MshError> {
    let Some((line, at)) = c.next_line() else {
        return Err(c.truncated("version, file type and data size"));
    };
    let mut fields = line.split(|b| b.is_ascii_whitespace()).filter(|f| !f.is_empty());
    let version = fields.next().unwrap_or_default();
    if version != b"4.1" {
        return Err(MshError::Version { path: c.path.to_string(), at, found: show(version) });
    }
    let file_type = fields.next().and_then(parse_i32);
    let data_size = fields.next().and_then(parse_i32);
    if data_size != Some(8) {
        return Err(c.format(at, format!("expected data size 8 in \"{}\"", show(line))));
    }
    match file_type {
        Some(0) => {}
        Some(1) => {
            // The int 1 written in the writer's byte order tells which order the file uses.
            let at = Location::Byte(c.offset());
            let one = c.bytes::<4>("the binary byte-order check")?;
            let big_endian = match one {
                [1, 0, 0, 0] => false,
                [0, 0, 0, 1] => true,
                _ => {
                    return Err(
                        c.format(at, format!("binary byte-order check: expected the int 1, found bytes {one:?}"))
                    )
                }
            };
            c.set_binary(big_endian);
        }
        _ => return Err(c.format(at, format!("expected file type 0 (ASCII) or 1 (binary) in \"{}\"", show(line)))),
    }
    if fields.next().is_some() {
        return Err(c.format(at, format!("unexpected extra fields in \"{}\"", show(line))));
    }
    c.expect_end()
}

/// `$PhysicalNames`: one group per line, always text.
pub(super) fn physical_names(c: &mut Cursor<'_>, b: &mut Builder) -> Result<(), MshError> {
    let Some((line, at)) = c.next_line() else {
        return Err(c.truncated("the number of physical names"));
    };
    let n = super::cursor::parse_u64(line).ok_or_else(|| MshError::Garbled {
        path: c.path.to_string(),
        at,
        expected: "a non-negative integer",
        what: "number of physical names",
        found: show(line),
    })?;
    for _ in 0..n {
        let Some((line, at)) = c.next_line() else {
            return Err(c.truncated("a physical name line: dim tag \"name\""));
        };
        if line.first() == Some(&b'$') {
            return Err(MshError::EarlyEnd {
                path: c.path.to_string(),
                at,
                section: c.section.to_string(),
                what: "a physical name line",
                found: show(line),
            });
        }
        let group = physical_name_line(line).ok_or_else(|| {
            c.format(at, format!("expected a physical name line: dim tag \"name\", found \"{}\"", show(line)))
        })?;
        if b.mesh.groups.iter().any(|g| g.dim == group.dim && g.tag == group.tag) {
            return Err(c.format(at, format!("physical group (dim {}, tag {}) named twice", group.dim, group.tag)));
        }
        b.mesh.groups.push(group);
    }
    c.expect_end()
}

/// Parses `dim tag "name"`; the name may hold spaces.
fn physical_name_line(line: &[u8]) -> Option<PhysicalGroup> {
    let mut rest = line;
    let mut field = || {
        let s = trim(rest);
        let end = s.iter().position(|b| b.is_ascii_whitespace()).unwrap_or(s.len());
        rest = &s[end..];
        &s[..end]
    };
    let dim = u8::try_from(parse_i32(field())?).ok().filter(|d| *d <= 3)?;
    let tag = parse_i32(field())?;
    let quoted = trim(rest);
    let name = quoted.strip_prefix(b"\"")?.strip_suffix(b"\"")?;
    let name = std::str::from_utf8(name).ok()?;
    Some(PhysicalGroup { dim, tag, name: name.to_string() })
}

/// `$Entities`: the physical tags of each entity.
pub(super) fn entities(c: &mut Cursor<'_>, b: &mut Builder) -> Result<(), MshError> {
    let mut counts = [0usize; 4];
    for (k, what) in
        ["number of points", "number of curves", "number of surfaces", "number of volumes"].into_iter().enumerate()
    {
        counts[k] = c.count(what)?.0;
    }
    for (dim, &n) in counts.iter().enumerate() {
        let dim = dim as u8; // 0..=3
        for _ in 0..n {
            let (tag, at) = c.int("entity tag")?;
            let n_coords = if dim == 0 { 3 } else { 6 };
            for _ in 0..n_coords {
                c.double("entity coordinate or bounding box")?;
            }
            let (n_phys, _) = c.count("number of physical tags")?;
            let mut phys = Vec::with_capacity(reserve_for(c, n_phys, 1));
            for _ in 0..n_phys {
                phys.push(c.int("physical tag")?.0);
            }
            if dim > 0 {
                let (n_bound, _) = c.count("number of bounding entities")?;
                for _ in 0..n_bound {
                    c.int("bounding entity tag")?;
                }
            }
            if b.mesh.entity_groups.insert((dim, tag), phys).is_some() {
                return Err(c.format(at, format!("entity (dim {dim}, tag {tag}) listed twice")));
            }
            b.entity_order.push((dim, tag));
        }
    }
    c.expect_end()
}

/// Whether two positions are on the same line of an ASCII file.
fn same_line(a: Location, b: Location) -> bool {
    matches!((a, b), (Location::Line(x), Location::Line(y)) if x == y)
}

/// Reads an entity dimension and checks it is 0..=3.
fn entity_dim(c: &mut Cursor<'_>) -> Result<u8, MshError> {
    let (d, at) = c.int("entity dimension")?;
    u8::try_from(d)
        .ok()
        .filter(|d| *d <= 3)
        .ok_or_else(|| c.format(at, format!("entity dimension {d} is not 0, 1, 2 or 3")))
}

/// `$Nodes`: coordinates and tags; node indices follow the order of appearance.
pub(super) fn nodes(c: &mut Cursor<'_>, b: &mut Builder) -> Result<(), MshError> {
    if b.seen_nodes {
        return Err(c.format(c.loc(), "a second $Nodes section".to_string()));
    }
    b.seen_nodes = true;
    let header_at = c.loc();
    let (n_blocks, _) = c.count("number of entity blocks")?;
    let (n_nodes, _) = c.count("number of nodes")?;
    let (min_tag, _) = c.size("minimum node tag")?;
    let (max_tag, _) = c.size("maximum node tag")?;
    // Each node takes at least 8 bytes in either encoding (a tag and 3 coordinates).
    let cap = reserve_for(c, n_nodes, 8);
    b.nodes = TagMap::with_range(min_tag, max_tag, cap, c.remaining());
    b.mesh.coords.reserve(cap);
    b.mesh.node_tags.reserve(cap);
    for _ in 0..n_blocks {
        let dim = entity_dim(c)?;
        c.int("entity tag")?;
        let (parametric, at) = c.int("parametric flag")?;
        let extra = match parametric {
            0 => 0,
            1 => dim as usize, // u for curves, u v for surfaces, u v w for volumes
            p => return Err(c.format(at, format!("parametric flag must be 0 or 1, found {p}"))),
        };
        let (n, _) = c.count("number of nodes in block")?;
        for _ in 0..n {
            let (tag, at) = c.size("node tag")?;
            let index = b.mesh.node_tags.len();
            if !b.nodes.insert(tag, index) {
                return Err(MshError::DuplicateNode { path: c.path.to_string(), at, tag });
            }
            b.mesh.node_tags.push(tag);
        }
        for _ in 0..n {
            let x = c.double("x coordinate")?;
            let y = c.double("y coordinate")?;
            let z = c.double("z coordinate")?;
            for _ in 0..extra {
                c.double("parametric coordinate")?;
            }
            b.mesh.coords.push([x, y, z]);
        }
    }
    let found = b.mesh.coords.len() as u64;
    if found != n_nodes as u64 {
        return Err(MshError::CountMismatch {
            path: c.path.to_string(),
            at: header_at,
            section: c.section.to_string(),
            what: "nodes",
            declared: n_nodes as u64,
            found,
        });
    }
    c.expect_end()
}

/// `$Elements`: cells of the supported types; any other type is an error.
pub(super) fn elements(c: &mut Cursor<'_>, b: &mut Builder) -> Result<(), MshError> {
    if b.seen_elements {
        return Err(c.format(c.loc(), "a second $Elements section".to_string()));
    }
    b.seen_elements = true;
    let header_at = c.loc();
    let (n_blocks, _) = c.count("number of entity blocks")?;
    let (n_elems, _) = c.count("number of elements")?;
    let (min_tag, _) = c.size("minimum element tag")?;
    let (max_tag, _) = c.size("maximum element tag")?;
    let cap = reserve_for(c, n_elems, 4);
    let mut seen = TagMap::with_range(min_tag, max_tag, cap, c.remaining());
    b.mesh.cells.reserve(cap);
    let first = b.mesh.cells.len();
    for _ in 0..n_blocks {
        let dim = entity_dim(c)?;
        let (entity, _) = c.int("entity tag")?;
        let (ty, ty_at) = c.int("element type")?;
        let (n, _) = c.count("number of elements in block")?;
        let kind = match CellKind::from_gmsh_type(ty) {
            Some(k) => k,
            None if n == 0 => continue,
            None => {
                let (element, at) = c.size("element tag")?;
                return Err(MshError::UnsupportedElement { path: c.path.to_string(), at, type_number: ty, element });
            }
        };
        if kind.dim() != dim {
            return Err(c.format(
                ty_at,
                format!(
                    "element type {ty} ({kind}) has dimension {}, but its block is of entity dimension {dim}",
                    kind.dim()
                ),
            ));
        }
        // In ASCII, one element per line: a tag on the line where the previous element ended,
        // or a node tag on a later line than its element's tag, means a wrong node count.
        let mut prev: Option<(u64, Location)> = None;
        for _ in 0..n {
            let (tag, at) = c.size("element tag")?;
            if let Some((p, end)) = prev.filter(|(_, end)| same_line(*end, at)) {
                let msg = format!("element {p} ({kind}) has more than {} node tags on its line", kind.n_nodes());
                return Err(c.format(end, msg));
            }
            if !seen.insert(tag, 0) {
                return Err(MshError::DuplicateElement { path: c.path.to_string(), at, tag });
            }
            let mut nodes = Vec::with_capacity(kind.n_nodes());
            let mut last = at;
            for k in 0..kind.n_nodes() {
                if matches!((at, c.next_loc()), (Location::Line(a), Location::Line(b)) if a != b) {
                    let msg =
                        format!("element {tag} ({kind}) lists {k} of its {} node tags on its line", kind.n_nodes());
                    return Err(c.format(at, msg));
                }
                let (node, node_at) = c.size("node tag of an element")?;
                let Some(i) = b.nodes.get(node) else {
                    return Err(MshError::DanglingNode { path: c.path.to_string(), at: node_at, element: tag, node });
                };
                nodes.push(i);
                last = node_at;
            }
            prev = Some((tag, last));
            b.mesh.cells.push(Cell { kind, tag, nodes, entity: (dim, entity) });
        }
    }
    // Unsupported-type blocks are errors, so every declared element is a cell here.
    let found = (b.mesh.cells.len() - first) as u64;
    if found != n_elems as u64 {
        return Err(MshError::CountMismatch {
            path: c.path.to_string(),
            at: header_at,
            section: c.section.to_string(),
            what: "elements",
            declared: n_elems as u64,
            found,
        });
    }
    c.expect_end()
}

impl Builder {
    /// The finished mesh: physical tags carried by entities but absent from `$PhysicalNames`
    /// become unnamed groups, in the order their entities appear.
    pub fn finish(mut self) -> Mesh {
        for key in &self.entity_order {
            let Some(tags) = self.mesh.entity_groups.get(key) else { continue };
            for &tag in tags {
                let dim = key.0;
                if !self.mesh.groups.iter().any(|g| g.dim == dim && g.tag == tag) {
                    self.mesh.groups.push(PhysicalGroup { dim, tag, name: String::new() });
                }
            }
        }
        self.mesh
    }
}
