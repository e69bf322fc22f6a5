//! The rank's piece of the mesh, in output numbering, and its XDMF "Mixed" topology encoding.
//!
//! Output numbering: the global list of output nodes (and of output cells) is the concatenation of
//! the ranks' owned pieces in rank order, so rank `r` owns the contiguous range
//! `[node_offset, node_offset + coords.len())`. Each rank writes exactly that hyperslab.
//!
//! ## Mixed topology
//! XDMF's `TopologyType="Mixed"` stores all cells in one integer array; each cell is its XDMF
//! type id followed by its node indices (0-based into the geometry):
//!
//! | cell      | encoding              | XDMF name     |
//! |-----------|-----------------------|---------------|
//! | `Quad4`   | `5 a b c d`           | Quadrilateral |
//! | `Tri3`    | `4 a b c`             | Triangle      |
//! | `Line2`   | `2 2 a b`             | Polyline with its node count 2 |
//! | `Point1`  | `2 2 a a`             | a degenerate 2-node Polyline (see below) |
//!
//! Why points are degenerate lines: the XDMF library and ParaView 5.11 (both its "XDMF Reader" and
//! "Xdmf3ReaderS") expect a Polyvertex (id 1) in a Mixed topology to be followed by its node count
//! (`1 1 a`), while meshio 5.3 reads id 1 as always one node with no count (`1 a`); each misreads
//! the other's form (checked on both). A zero-length line `2 2 a a` is read identically by both.
//! The true kind stays available as the cell attribute `gmsh_type` (dataset `/mesh/cell_types`).

use crate::mesh::CellKind;

/// The rank's piece of the mesh in output numbering: nodes and cells in global output order are
/// contiguous per rank (rank r owns nodes `[node_offset, node_offset + coords.len())`).
#[derive(Clone, Copy, Debug)]
pub struct OutputMesh<'a> {
    /// Global output index of this rank's first node (the sum of the lower ranks' node counts).
    pub node_offset: usize,
    /// Number of output nodes over all ranks.
    pub n_nodes_global: usize,
    /// Owned nodes, in output order.
    pub coords: &'a [[f64; 3]],
    /// Their Gmsh tags (dataset `/mesh/node_ids`).
    pub node_ids: &'a [u64],
    /// Global output index of this rank's first cell (the sum of the lower ranks' cell counts).
    pub cell_offset: usize,
    /// Number of output cells over all ranks.
    pub n_cells_global: usize,
    /// Owned cells.
    pub cell_kinds: &'a [CellKind],
    /// Their nodes, concatenated, as GLOBAL output node indices.
    pub cell_nodes: &'a [usize],
    /// Their Gmsh tags (dataset `/mesh/cell_ids`).
    pub cell_ids: &'a [u64],
    /// Physical tag of each cell (dataset `/mesh/cell_group`, cell field "group" in ParaView).
    pub cell_groups: &'a [i32],
}

/// XDMF topology type id of a polyline in a Mixed topology (followed by the node count).
const XDMF_POLYLINE: i64 = 2;
/// XDMF topology type id of a triangle.
const XDMF_TRIANGLE: i64 = 4;
/// XDMF topology type id of a quadrilateral.
const XDMF_QUADRILATERAL: i64 = 5;

/// Number of integers cell `kind` takes in the Mixed topology array.
pub(crate) const fn mixed_len(kind: CellKind) -> usize {
    match kind {
        CellKind::Point1 | CellKind::Line2 => 4,
        CellKind::Tri3 => 4,
        CellKind::Quad4 => 5,
    }
}

impl OutputMesh<'_> {
    /// Number of owned nodes.
    pub fn n_owned_nodes(&self) -> usize {
        self.coords.len()
    }

    /// Number of owned cells.
    pub fn n_owned_cells(&self) -> usize {
        self.cell_kinds.len()
    }

    /// What is wrong with this rank's piece on its own (lengths and node indices), if anything.
    /// Offsets against the other ranks are checked collectively by the writer.
    pub fn local_problem(&self) -> Option<String> {
        let n = self.coords.len();
        if self.node_ids.len() != n {
            return Some(format!("{} node ids for {n} owned nodes", self.node_ids.len()));
        }
        let c = self.cell_kinds.len();
        if self.cell_ids.len() != c {
            return Some(format!("{} cell ids for {c} owned cells", self.cell_ids.len()));
        }
        if self.cell_groups.len() != c {
            return Some(format!("{} cell groups for {c} owned cells", self.cell_groups.len()));
        }
        let expected: usize = self.cell_kinds.iter().map(|k| k.n_nodes()).sum();
        if self.cell_nodes.len() != expected {
            return Some(format!(
                "{} cell node indices, but the {c} owned cells have {expected} nodes",
                self.cell_nodes.len()
            ));
        }
        if self.node_offset + n > self.n_nodes_global {
            return Some(format!(
                "owned nodes [{}, {}) exceed the {} global nodes",
                self.node_offset,
                self.node_offset + n,
                self.n_nodes_global
            ));
        }
        if self.cell_offset + c > self.n_cells_global {
            return Some(format!(
                "owned cells [{}, {}) exceed the {} global cells",
                self.cell_offset,
                self.cell_offset + c,
                self.n_cells_global
            ));
        }
        if let Some(pos) = self.cell_nodes.iter().position(|&v| v >= self.n_nodes_global) {
            return Some(format!(
                "cell node index {} (position {pos}) is not below the {} global nodes",
                self.cell_nodes[pos], self.n_nodes_global
            ));
        }
        if let Some(i) = self.coords.iter().position(|x| x.iter().any(|v| !v.is_finite())) {
            return Some(format!("node {} has non-finite coordinates", self.node_offset + i));
        }
        None
    }

    /// The owned cells' part of the Mixed topology array (see the module docs).
    /// Requires `local_problem()` to be `None`.
    pub(crate) fn mixed_topology(&self) -> Vec<i64> {
        let len = self.cell_kinds.iter().map(|&k| mixed_len(k)).sum();
        let mut out = Vec::with_capacity(len);
        let mut at = 0;
        for &kind in self.cell_kinds {
            let nodes = &self.cell_nodes[at..at + kind.n_nodes()];
            at += kind.n_nodes();
            // Node indices are below n_nodes_global (checked), which fits in i64 on 64-bit targets.
            let v = |i: usize| nodes[i] as i64;
            match kind {
                CellKind::Point1 => out.extend([XDMF_POLYLINE, 2, v(0), v(0)]),
                CellKind::Line2 => out.extend([XDMF_POLYLINE, 2, v(0), v(1)]),
                CellKind::Tri3 => out.extend([XDMF_TRIANGLE, v(0), v(1), v(2)]),
                CellKind::Quad4 => out.extend([XDMF_QUADRILATERAL, v(0), v(1), v(2), v(3)]),
            }
        }
        debug_assert_eq!(out.len(), len);
        out
    }

    /// Gmsh element type of each owned cell (dataset `/mesh/cell_types`).
    pub(crate) fn gmsh_types(&self) -> Vec<i32> {
        self.cell_kinds.iter().map(|k| k.gmsh_type()).collect()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    const COORDS: [[f64; 3]; 5] = [[0., 0., 0.], [1., 0., 0.], [1., 1., 0.], [0., 1., 0.], [2., 0., 0.]];
    const KINDS: [CellKind; 4] = [CellKind::Quad4, CellKind::Tri3, CellKind::Line2, CellKind::Point1];
    const NODES: [usize; 10] = [0, 1, 2, 3, 1, 4, 2, 0, 1, 4];

    fn mesh<'a>(cell_nodes: &'a [usize], node_ids: &'a [u64]) -> OutputMesh<'a> {
        OutputMesh {
            node_offset: 0,
            n_nodes_global: 5,
            coords: &COORDS,
            node_ids,
            cell_offset: 0,
            n_cells_global: 4,
            cell_kinds: &KINDS,
            cell_nodes,
            cell_ids: &[11, 12, 13, 14],
            cell_groups: &[1, 1, 2, 3],
        }
    }

    #[test]
    fn mixed_encoding_follows_the_table() {
        // Expected array written out by hand from the module table (exact integers).
        let m = mesh(&NODES, &[1, 2, 3, 4, 5]);
        assert_eq!(m.local_problem(), None);
        assert_eq!(m.mixed_topology(), vec![5, 0, 1, 2, 3, 4, 1, 4, 2, 2, 2, 0, 1, 2, 2, 4, 4]);
        let len: usize = KINDS.iter().map(|&k| mixed_len(k)).sum();
        assert_eq!(len, 17);
        assert_eq!(m.gmsh_types(), vec![3, 2, 1, 15]);
    }

    #[test]
    fn bad_pieces_are_reported() {
        assert!(mesh(&NODES, &[1, 2, 3]).local_problem().unwrap().contains("3 node ids"));
        assert!(mesh(&NODES[..9], &[1, 2, 3, 4, 5]).local_problem().unwrap().contains("9 cell node"));
        let mut bad = NODES;
        bad[3] = 5;
        assert!(mesh(&bad, &[1, 2, 3, 4, 5]).local_problem().unwrap().contains("index 5"));
        let mut m = mesh(&NODES, &[1, 2, 3, 4, 5]);
        m.node_offset = 1;
        assert!(m.local_problem().unwrap().contains("exceed"));
    }
}
