//! Rigid-body check of the supports: is each connected piece of the structure held?
//!
//! A piece (a connected component of the cells, through shared nodes) moves as a rigid body by
//! `u(x) = t + θ × (x − c)` (translation t, small rotation θ about its centroid c). A fixed DOF
//! at node p restrains the combination `r·(t, θ)` with
//!
//! * translation DOF d: `u_d(p) = t_d + (θ × (p − c))_d`, so `r = (e_d, (p − c) × e_d)`;
//! * rotation DOF d:    `θ_d`, so `r = (0, e_d)`.
//!
//! The piece is held when the r's span all six rigid motions, i.e. when `G = Σ r rᵀ` (6×6, made
//! dimensionless with the piece's size) has no (near-)zero eigenvalue; the eigenvectors of the
//! zero eigenvalues are the free motions, which the error names. Rigid-jointed frames and shells
//! have no internal mechanisms, so this check finds every singular model they can make; the
//! solver's zero-pivot report remains the fallback.
//!
//! # Ties
//! A tie (axial force only) does not make its two nodes one rigid piece: pieces are connected
//! through the other cells only, and a tie restrains the relative motion of its ends along its
//! axis e. Once the piece at one end is held, the tie holds the other end's translation along e
//! like a support would: `r = (e, (p − c) × e)` at that end p. Pieces are checked in rounds,
//! each round adding the ties that reach a piece held by then, until no more pieces are held.
//! Pieces that only hold each other (neither held first) are reported, which is conservative:
//! a support in the right places settles it.
use super::rigid_pieces::RigidPieces;
use crate::mesh::Mesh;
use nalgebra::{Matrix6, Vector3, Vector6};

/// A piece of the structure that can move as a rigid body.
#[derive(Clone, Debug, PartialEq)]
pub struct Mechanism {
    /// Number of cells in the piece.
    pub n_cells: usize,
    /// Gmsh tag of one of its nodes.
    pub node_tag: u64,
    /// Where that node is.
    pub node_coords: [f64; 3],
    /// The free rigid motions, in words ("translation along x", "rotation about z", ...).
    pub free_motions: Vec<String>,
}

impl std::fmt::Display for Mechanism {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        let [x, y, z] = self.node_coords;
        write!(
            f,
            "the model is a mechanism (its stiffness matrix is singular): the piece of {} element(s) \
             containing node {} at ({x}, {y}, {z}) is free to move as a rigid body ({}); add supports \
             ([[supports]]) that restrain it",
            self.n_cells,
            self.node_tag,
            self.free_motions.join("; ")
        )
    }
}

impl super::StructuralModel {
    /// The pieces of the model that its supports (and ties, module docs) do not hold.
    pub fn find_mechanisms(&self, mesh: &Mesh) -> Vec<Mechanism> {
        find_mechanisms_with_ties(mesh, &self.cell_nodes(mesh), &self.is_tie, &self.fixed)
    }
}

/// Pieces of the model (cells as node lists) that the fixed-DOF masks do not hold, every cell
/// joining its nodes rigidly.
pub fn find_mechanisms(mesh: &Mesh, cells: &[&[usize]], fixed: &[u8]) -> Vec<Mechanism> {
    find_mechanisms_with_ties(mesh, cells, &[], fixed)
}

/// Pieces of the model that the fixed-DOF masks and the ties do not hold; `is_tie[c]` marks the
/// 2-node cells that are ties (empty: none).
pub fn find_mechanisms_with_ties(mesh: &Mesh, cells: &[&[usize]], is_tie: &[bool], fixed: &[u8]) -> Vec<Mechanism> {
    let tie = |c: usize| is_tie.get(c).copied().unwrap_or(false);
    let pieces = RigidPieces::of(mesh, cells, |c| !tie(c));
    let mut gram = support_gram(&pieces, fixed);
    let mut held: Vec<bool> = gram.iter().map(is_held).collect();
    hold_through_ties(&pieces, tie_ends(cells, tie, &pieces), &mut gram, &mut held);
    let n_cells = cells_per_piece(cells, tie, &pieces);
    let mut out = Vec::new();
    for p in (0..pieces.len()).filter(|&p| !held[p]) {
        let free = free_motions(&gram[p]);
        if !free.is_empty() {
            let node = pieces.root(p);
            out.push(Mechanism {
                n_cells: n_cells[p],
                node_tag: mesh.node_tags[node],
                node_coords: mesh.coords[node],
                free_motions: free,
            });
        }
    }
    out
}

/// Smallest eigenvalue of the (dimensionless) Gram matrix below which a rigid motion is free.
const FREE_EIGENVALUE: f64 = 1e-10;

/// The rigid motions in the order of `(t, θ)`, in words.
const MOTION_NAMES: [&str; 6] = [
    "translation along x",
    "translation along y",
    "translation along z",
    "rotation about x",
    "rotation about y",
    "rotation about z",
];

/// Whether the restraints of Gram matrix `g` hold all six rigid motions (no eigenvalue below
/// [`FREE_EIGENVALUE`]).
fn is_held(g: &Matrix6<f64>) -> bool {
    g.symmetric_eigen().eigenvalues.iter().all(|&l| l >= FREE_EIGENVALUE)
}

/// The restraint `r = (0, e_d)` of the rotation DOF `d` (3, 4, 5: about x, y, z).
fn rotation_restraint(d: usize) -> Vector6<f64> {
    let mut r = Vector6::zeros();
    r[d] = 1.0;
    r
}

/// `G = Σ r rᵀ` of each piece over the fixed DOFs of its nodes (`fixed[a]` bit d: DOF d fixed).
fn support_gram(pieces: &RigidPieces, fixed: &[u8]) -> Vec<Matrix6<f64>> {
    let mut gram = vec![Matrix6::<f64>::zeros(); pieces.len()];
    for a in 0..pieces.n_nodes() {
        let Some(p) = pieces.of_node(a).filter(|_| fixed[a] != 0) else {
            continue;
        };
        for d in (0..6).filter(|d| fixed[a] & (1 << d) != 0) {
            let r = if d < 3 { pieces.translation_restraint(a, Vector3::ith(d, 1.0)) } else { rotation_restraint(d) };
            gram[p] += r * r.transpose();
        }
    }
    gram
}

/// The end nodes of the ties that join two different pieces.
fn tie_ends(cells: &[&[usize]], tie: impl Fn(usize) -> bool, pieces: &RigidPieces) -> Vec<(usize, usize)> {
    cells
        .iter()
        .enumerate()
        .filter(|(i, c)| tie(*i) && c.len() == 2 && pieces.of_cell_node(c[0]) != pieces.of_cell_node(c[1]))
        .map(|(_, c)| (c[0], c[1]))
        .collect()
}

/// Ties between pieces, in rounds (module docs): a tie reaching a held piece restrains the
/// translation of its other end along its axis; pieces held by then join `held`, until a round
/// neither uses a tie nor holds a piece.
fn hold_through_ties(
    pieces: &RigidPieces,
    mut pending: Vec<(usize, usize)>,
    gram: &mut [Matrix6<f64>],
    held: &mut [bool],
) {
    loop {
        let mut progress = false;
        pending.retain(|&(a, b)| {
            let (pa, pb) = (pieces.of_cell_node(a), pieces.of_cell_node(b));
            let (end, p) = match (held[pa], held[pb]) {
                (true, true) => return false,
                (true, false) => (b, pb),
                (false, true) => (a, pa),
                (false, false) => return true,
            };
            let d = pieces.position(b) - pieces.position(a);
            if d.norm() > 0.0 {
                let r = pieces.translation_restraint(end, d.normalize());
                gram[p] += r * r.transpose();
            }
            progress = true;
            false
        });
        let mut newly = false;
        for p in 0..gram.len() {
            if !held[p] && is_held(&gram[p]) {
                held[p] = true;
                newly = true;
            }
        }
        if !progress && !newly {
            break;
        }
    }
}

/// Number of cells (ties excepted) in each piece.
fn cells_per_piece(cells: &[&[usize]], tie: impl Fn(usize) -> bool, pieces: &RigidPieces) -> Vec<usize> {
    let mut n_cells = vec![0usize; pieces.len()];
    for (_, c) in cells.iter().enumerate().filter(|(i, _)| !tie(*i)) {
        n_cells[pieces.of_cell_node(c[0])] += 1;
    }
    n_cells
}

/// The free rigid motions of a piece with Gram matrix `g`, in words: each eigenvector of a zero
/// eigenvalue named by its components above 0.1 ("rotation about x combined with ...").
fn free_motions(g: &Matrix6<f64>) -> Vec<String> {
    let eig = g.symmetric_eigen();
    let mut free = Vec::new();
    for k in 0..6 {
        if eig.eigenvalues[k] < FREE_EIGENVALUE {
            let v = eig.eigenvectors.column(k);
            let parts: Vec<String> =
                (0..6).filter(|&i| v[i].abs() > 0.1).map(|i| MOTION_NAMES[i].to_string()).collect();
            free.push(parts.join(" combined with "));
        }
    }
    free
}

#[cfg(test)]
mod tests {
    use super::*;

    fn line_mesh() -> Mesh {
        // Two separate beams: 0-1-2 along x, and 3-4 along y.
        Mesh {
            coords: vec![[0., 0., 0.], [1., 0., 0.], [2., 0., 0.], [5., 0., 0.], [5., 1., 0.]],
            node_tags: vec![1, 2, 3, 4, 5],
            ..Default::default()
        }
    }

    #[test]
    fn a_clamped_piece_is_held_and_a_free_one_is_named() {
        let m = line_mesh();
        let cells: Vec<&[usize]> = vec![&[0, 1], &[1, 2], &[3, 4]];
        let mut fixed = vec![0u8; 5];
        fixed[0] = 0b111111;
        let mech = find_mechanisms(&m, &cells, &fixed);
        assert_eq!(mech.len(), 1);
        assert_eq!(mech[0].node_tag, 4);
        assert_eq!(mech[0].n_cells, 1);
        assert_eq!(mech[0].free_motions.len(), 6);
        fixed[3] = 0b111111;
        assert!(find_mechanisms(&m, &cells, &fixed).is_empty());
    }

    /// A clamped column 0–1, a column 2–3 pinned at its foot 2, a tie 1–3 along x between their
    /// tops, and node 4 at (2, −1, 1), which only the tie 4–3 (along y) reaches.
    fn tied_mesh() -> Mesh {
        Mesh {
            coords: vec![[0., 0., 0.], [0., 0., 1.], [2., 0., 0.], [2., 0., 1.], [2., -1., 1.]],
            node_tags: vec![1, 2, 3, 4, 5],
            ..Default::default()
        }
    }

    #[test]
    fn a_tie_holds_its_far_end_along_its_axis_only() {
        let m = tied_mesh();
        let cells: Vec<&[usize]> = vec![&[0, 1], &[2, 3], &[1, 3]];
        let mut fixed = vec![0u8; 5];
        fixed[0] = 0b111111;
        fixed[2] = 0b000111; // pinned: rotations about the foot free
                             // Taken as a rigid link, the tie would make one held piece.
        assert!(find_mechanisms(&m, &cells, &fixed).is_empty());
        // As a tie it holds the top of column 2–3 along x: the rotation about y is held, those
        // about x (the top moves along y) and about z (the column's own axis) are free.
        let mech = find_mechanisms_with_ties(&m, &cells, &[false, false, true], &fixed);
        assert_eq!(mech.len(), 1, "{mech:?}");
        assert_eq!(mech[0].node_tag, 3);
        assert_eq!(mech[0].n_cells, 1);
        assert_eq!(mech[0].free_motions.len(), 2, "{mech:?}");
        assert!(mech[0].free_motions.iter().all(|f| !f.contains("rotation about y")), "{mech:?}");
        // Clamped at its foot, the column is held by itself.
        fixed[2] = 0b111111;
        assert!(find_mechanisms_with_ties(&m, &cells, &[false, false, true], &fixed).is_empty());
    }

    #[test]
    fn ties_to_held_pieces_hold_a_piece_in_rounds() {
        let m = tied_mesh();
        // Column 2–3 held at its foot in translation and torsion only; the tie 1–3 (along x, to
        // the clamped column) holds the rotation about y, the tie 4–3 (along y, to the fully
        // supported node 4) the rotation about x.
        let cells: Vec<&[usize]> = vec![&[0, 1], &[2, 3], &[1, 3], &[4, 3]];
        let ties = [false, false, true, true];
        let mut fixed = vec![0u8; 5];
        fixed[0] = 0b111111;
        fixed[2] = 0b100111;
        fixed[4] = 0b111111;
        assert!(find_mechanisms_with_ties(&m, &cells, &ties, &fixed).is_empty());
        // Without the anchor's support, node 4 and the column hold each other through a tie only:
        // node 4 is free, and the column keeps its rotation about x.
        fixed[4] = 0;
        let mech = find_mechanisms_with_ties(&m, &cells, &ties, &fixed);
        assert_eq!(mech.len(), 2, "{mech:?}");
        assert_eq!(mech[0].free_motions.len(), 1, "{mech:?}");
        assert_eq!(mech[1].node_tag, 5);
    }

    #[test]
    fn pins_on_one_line_leave_the_rotation_about_it_free() {
        let m = line_mesh();
        let cells: Vec<&[usize]> = vec![&[0, 1], &[1, 2]];
        let mut fixed = vec![0u8; 5];
        fixed[0] = 0b000111; // pinned
        fixed[2] = 0b000111; // pinned: rotation about the x axis through both stays free
        let mech = find_mechanisms(&m, &cells, &fixed);
        assert_eq!(mech.len(), 1);
        assert_eq!(mech[0].free_motions, vec!["rotation about x".to_string()]);
    }
}
