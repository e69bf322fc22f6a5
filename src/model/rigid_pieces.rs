//! The rigid pieces of a model: the connected components of its cells through shared nodes, each
//! moving as one rigid body `u(x) = t + θ × (x − c)` about its centroid c (see `stability`).
//!
//! A translation restrained along the unit vector e at node p of a piece restrains the rigid
//! motions by `r·(t, θ)` with `r = (e, (p − c)/size × e)`: the lever arm is made dimensionless
//! with the piece's size (its bounding box's diagonal) so that translations and rotations weigh
//! alike in the Gram matrix of the restraints.
use crate::mesh::Mesh;
use nalgebra::{Vector3, Vector6};

/// The nodes of a model grouped into rigid pieces, with the centroid and size of each piece.
pub(super) struct RigidPieces<'m> {
    /// The mesh's node coordinates.
    coords: &'m [[f64; 3]],
    /// Piece of each node; `usize::MAX` for a node in no cell.
    piece: Vec<usize>,
    /// One node of each piece (its union-find root), in the order the pieces were numbered.
    root: Vec<usize>,
    /// Centroid c of each piece's nodes.
    centroid: Vec<Vector3<f64>>,
    /// Size of each piece: its bounding box's diagonal, at least `f64::MIN_POSITIVE`.
    size: Vec<f64>,
}

/// The root of node `a`'s set, halving the path on the way.
fn find(parent: &mut [usize], mut a: usize) -> usize {
    while parent[a] != a {
        parent[a] = parent[parent[a]];
        a = parent[a];
    }
    a
}

/// Union-find parents after joining the consecutive nodes of every rigid cell (`rigid(c)`); a
/// merged set keeps the lower of the two roots.
fn join_rigid_cells(n: usize, cells: &[&[usize]], rigid: impl Fn(usize) -> bool) -> Vec<usize> {
    let mut parent: Vec<usize> = (0..n).collect();
    for (_, c) in cells.iter().enumerate().filter(|(i, _)| rigid(*i)) {
        for w in c.windows(2) {
            let (a, b) = (find(&mut parent, w[0]), find(&mut parent, w[1]));
            if a != b {
                parent[a.max(b)] = a.min(b);
            }
        }
    }
    parent
}

/// Whether each of the `n` nodes is in some cell (ties included).
fn in_some_cell(n: usize, cells: &[&[usize]]) -> Vec<bool> {
    let mut active = vec![false; n];
    for c in cells {
        for &a in c.iter() {
            active[a] = true;
        }
    }
    active
}

/// The piece of each active node, numbered in the order of their lowest node, and the root of
/// each piece.
fn number_pieces(parent: &mut [usize], active: &[bool]) -> (Vec<usize>, Vec<usize>) {
    let mut roots: Vec<usize> = Vec::new();
    let mut piece = vec![usize::MAX; active.len()];
    for a in 0..active.len() {
        if active[a] {
            let r = find(parent, a);
            let idx = match roots.iter().position(|&x| x == r) {
                Some(i) => i,
                None => {
                    roots.push(r);
                    roots.len() - 1
                }
            };
            piece[a] = idx;
        }
    }
    (piece, roots)
}

/// The centroid and the size (bounding-box diagonal) of each of the `np` pieces.
fn measure_pieces(coords: &[[f64; 3]], piece: &[usize], np: usize) -> (Vec<Vector3<f64>>, Vec<f64>) {
    let mut centroid = vec![Vector3::zeros(); np];
    let mut count = vec![0usize; np];
    let mut lo = vec![Vector3::repeat(f64::INFINITY); np];
    let mut hi = vec![Vector3::repeat(f64::NEG_INFINITY); np];
    for (a, &p) in piece.iter().enumerate() {
        if p != usize::MAX {
            let x = Vector3::from(coords[a]);
            centroid[p] += x;
            count[p] += 1;
            lo[p] = lo[p].inf(&x);
            hi[p] = hi[p].sup(&x);
        }
    }
    for p in 0..np {
        centroid[p] /= count[p] as f64;
    }
    let size = (0..np).map(|p| (hi[p] - lo[p]).norm().max(f64::MIN_POSITIVE)).collect();
    (centroid, size)
}

impl<'m> RigidPieces<'m> {
    /// The pieces of `cells` on `mesh`, the cells with `rigid(c)` false (ties) joining nothing.
    pub fn of(mesh: &'m Mesh, cells: &[&[usize]], rigid: impl Fn(usize) -> bool) -> Self {
        let n = mesh.coords.len();
        let mut parent = join_rigid_cells(n, cells, rigid);
        let (piece, root) = number_pieces(&mut parent, &in_some_cell(n, cells));
        let (centroid, size) = measure_pieces(&mesh.coords, &piece, root.len());
        Self { coords: &mesh.coords, piece, root, centroid, size }
    }

    /// Number of pieces.
    pub fn len(&self) -> usize {
        self.root.len()
    }

    /// Number of nodes (of the mesh).
    pub fn n_nodes(&self) -> usize {
        self.piece.len()
    }

    /// The piece of node `a` (`None`: in no cell).
    pub fn of_node(&self, a: usize) -> Option<usize> {
        Some(self.piece[a]).filter(|&p| p != usize::MAX)
    }

    /// The piece of node `a` of a cell.
    pub fn of_cell_node(&self, a: usize) -> usize {
        debug_assert!(self.piece[a] != usize::MAX, "node {a} is in no cell");
        self.piece[a]
    }

    /// Where node `a` is.
    pub fn position(&self, a: usize) -> Vector3<f64> {
        Vector3::from(self.coords[a])
    }

    /// One node of piece `p`.
    pub fn root(&self, p: usize) -> usize {
        self.root[p]
    }

    /// The restraint `r = (e, (x_a − c)/size × e)` of a translation along the unit vector e at
    /// node `a`, in the rigid motions `(t, θ)` of its piece.
    pub fn translation_restraint(&self, a: usize, e: Vector3<f64>) -> Vector6<f64> {
        let p = self.piece[a];
        let rel = (self.position(a) - self.centroid[p]) / self.size[p];
        let mut r = Vector6::zeros();
        r.fixed_rows_mut::<3>(0).copy_from(&e);
        r.fixed_rows_mut::<3>(3).copy_from(&rel.cross(&e));
        r
    }
}
