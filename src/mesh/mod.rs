//! The in-memory mesh and its Gmsh MSH 4.1 reader.
//!
//! Every rank reads the same mesh file (meshes of a church are a few hundred thousand cells at
//! most, a few tens of MB); the partition then decides which cells each rank computes.
//!
//! Indices: `Mesh::coords[i]` is node *index* `i` (0-based, dense); `node_tags[i]` is the Gmsh
//! tag it had in the file. Cells refer to node indices, never to tags.

mod gmsh;

pub use gmsh::{element_type_name, read_msh, Location, MshError};

use std::fmt;

/// The cell types the structural model understands.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum CellKind {
    /// A 1-node point (Gmsh type 15): point masses, supports or loads on a node.
    Point1,
    /// A 2-node line (Gmsh type 1): beams.
    Line2,
    /// A 3-node triangle (Gmsh type 2): shells.
    Tri3,
    /// A 4-node quadrangle (Gmsh type 3): shells.
    Quad4,
}

impl CellKind {
    /// Number of nodes of the cell.
    pub const fn n_nodes(self) -> usize {
        match self {
            CellKind::Point1 => 1,
            CellKind::Line2 => 2,
            CellKind::Tri3 => 3,
            CellKind::Quad4 => 4,
        }
    }

    /// Topological dimension (0 point, 1 curve, 2 surface).
    pub const fn dim(self) -> u8 {
        match self {
            CellKind::Point1 => 0,
            CellKind::Line2 => 1,
            CellKind::Tri3 | CellKind::Quad4 => 2,
        }
    }

    /// The Gmsh element type number.
    pub const fn gmsh_type(self) -> i32 {
        match self {
            CellKind::Point1 => 15,
            CellKind::Line2 => 1,
            CellKind::Tri3 => 2,
            CellKind::Quad4 => 3,
        }
    }

    /// The cell kind of a Gmsh element type number, if supported.
    pub fn from_gmsh_type(t: i32) -> Option<CellKind> {
        match t {
            15 => Some(CellKind::Point1),
            1 => Some(CellKind::Line2),
            2 => Some(CellKind::Tri3),
            3 => Some(CellKind::Quad4),
            _ => None,
        }
    }
}

impl fmt::Display for CellKind {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        let s = match self {
            CellKind::Point1 => "1-node point",
            CellKind::Line2 => "2-node line",
            CellKind::Tri3 => "3-node triangle",
            CellKind::Quad4 => "4-node quadrangle",
        };
        f.write_str(s)
    }
}

/// One cell of the mesh.
#[derive(Clone, Debug, PartialEq)]
pub struct Cell {
    /// Its type.
    pub kind: CellKind,
    /// Its Gmsh element tag.
    pub tag: u64,
    /// Node indices (into [`Mesh::coords`]), `kind.n_nodes()` of them, in Gmsh order.
    pub nodes: Vec<usize>,
    /// The Gmsh entity `(dim, tag)` it belongs to.
    pub entity: (u8, i32),
}

/// A named physical group.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct PhysicalGroup {
    /// Dimension (0 points, 1 curves, 2 surfaces, 3 volumes).
    pub dim: u8,
    /// Gmsh physical tag.
    pub tag: i32,
    /// Its name (empty when the file names none).
    pub name: String,
}

/// A mesh: nodes, cells, physical groups and which entities belong to which groups.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Mesh {
    /// Node coordinates, by node index.
    pub coords: Vec<[f64; 3]>,
    /// Gmsh node tag of each node index.
    pub node_tags: Vec<u64>,
    /// All cells of supported kinds, in file order.
    pub cells: Vec<Cell>,
    /// Physical groups, in file order.
    pub groups: Vec<PhysicalGroup>,
    /// For each entity `(dim, tag)`: the physical tags it carries.
    pub entity_groups: std::collections::HashMap<(u8, i32), Vec<i32>>,
}

/// Errors about a group a job file names.
#[derive(Debug, thiserror::Error, PartialEq)]
pub enum GroupError {
    /// The mesh has no physical group of that name.
    #[error("the mesh has no physical group named '{name}'; it has: {}", available.join(", "))]
    Unknown {
        /// The requested name.
        name: String,
        /// The names present.
        available: Vec<String>,
    },
}

impl Mesh {
    /// The group called `name`.
    pub fn group(&self, name: &str) -> Result<&PhysicalGroup, GroupError> {
        self.groups
            .iter()
            .find(|g| g.name == name)
            .ok_or_else(|| GroupError::Unknown { name: name.to_string(), available: self.group_names() })
    }

    /// The names of all physical groups, in file order, quoted where unnamed (`#tag`).
    pub fn group_names(&self) -> Vec<String> {
        self.groups
            .iter()
            .map(|g| if g.name.is_empty() { format!("#{} (dim {})", g.tag, g.dim) } else { g.name.clone() })
            .collect()
    }

    /// Indices of the cells in group `g` (cells of the group's dimension whose entity carries it).
    pub fn cells_in_group<'a>(&'a self, g: &'a PhysicalGroup) -> impl Iterator<Item = usize> + 'a {
        self.cells.iter().enumerate().filter_map(move |(i, c)| {
            (c.entity.0 == g.dim && self.entity_groups.get(&c.entity).is_some_and(|tags| tags.contains(&g.tag)))
                .then_some(i)
        })
    }

    /// Sorted, deduplicated node indices of the cells in group `g`.
    pub fn nodes_in_group(&self, g: &PhysicalGroup) -> Vec<usize> {
        let mut n: Vec<usize> = self.cells_in_group(g).flat_map(|c| self.cells[c].nodes.iter().copied()).collect();
        n.sort_unstable();
        n.dedup();
        n
    }
}
