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

fn find(parent: &mut [usize], mut a: usize) -> usize {
    while parent[a] != a {
        parent[a] = parent[parent[a]];
        a = parent[a];
    }
    a
}

/// Pieces of the model (cells as node lists) that the fixed-DOF masks do not hold.
pub fn find_mechanisms(mesh: &Mesh, cells: &[&[usize]], fixed: &[u8]) -> Vec<Mechanism> {
    let n = mesh.coords.len();
    let mut parent: Vec<usize> = (0..n).collect();
    for c in cells {
        for w in c.windows(2) {
            let (a, b) = (find(&mut parent, w[0]), find(&mut parent, w[1]));
            if a != b {
                parent[a.max(b)] = a.min(b);
            }
        }
    }
    let mut roots: Vec<usize> = Vec::new();
    let mut piece = vec![usize::MAX; n];
    let mut active = vec![false; n];
    for c in cells {
        for &a in c.iter() {
            active[a] = true;
        }
    }
    for a in 0..n {
        if active[a] {
            let r = find(&mut parent, a);
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
    let np = roots.len();
    let mut centroid = vec![Vector3::zeros(); np];
    let mut count = vec![0usize; np];
    let mut lo = vec![Vector3::repeat(f64::INFINITY); np];
    let mut hi = vec![Vector3::repeat(f64::NEG_INFINITY); np];
    for a in 0..n {
        if active[a] {
            let x = Vector3::from(mesh.coords[a]);
            let p = piece[a];
            centroid[p] += x;
            count[p] += 1;
            lo[p] = lo[p].inf(&x);
            hi[p] = hi[p].sup(&x);
        }
    }
    for p in 0..np {
        centroid[p] /= count[p] as f64;
    }
    let mut gram = vec![Matrix6::<f64>::zeros(); np];
    for a in 0..n {
        if !active[a] || fixed[a] == 0 {
            continue;
        }
        let p = piece[a];
        let size = (hi[p] - lo[p]).norm().max(f64::MIN_POSITIVE);
        let rel = (Vector3::from(mesh.coords[a]) - centroid[p]) / size;
        for d in 0..6 {
            if fixed[a] & (1 << d) == 0 {
                continue;
            }
            let mut r = Vector6::zeros();
            if d < 3 {
                let e = Vector3::ith(d, 1.0);
                let m = rel.cross(&e);
                r[d] = 1.0;
                r.fixed_rows_mut::<3>(3).copy_from(&m);
            } else {
                r[d] = 1.0;
            }
            gram[p] += r * r.transpose();
        }
    }
    let mut n_cells = vec![0usize; np];
    for c in cells {
        n_cells[piece[c[0]]] += 1;
    }
    let names = ["translation along x", "translation along y", "translation along z", "rotation about x", "rotation about y", "rotation about z"];
    let mut out = Vec::new();
    for p in 0..np {
        let eig = gram[p].symmetric_eigen();
        let mut free = Vec::new();
        for k in 0..6 {
            if eig.eigenvalues[k] < 1e-10 {
                let v = eig.eigenvectors.column(k);
                let parts: Vec<String> = (0..6)
                    .filter(|&i| v[i].abs() > 0.1)
                    .map(|i| names[i].to_string())
                    .collect();
                free.push(parts.join(" combined with "));
            }
        }
        if !free.is_empty() {
            let node = roots[p];
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
