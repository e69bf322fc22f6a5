//! [`ShellTri3`]: 3-node flat shell — Allman membrane with vertex drilling rotations (Allman 1984,
//! "A compatible triangular element including vertex rotations for plane elasticity analysis",
//! Comput. Struct. 19), DKT bending (Batoz, Bathe & Ho 1980, "A study of three-node triangular
//! plate bending elements", IJNME 15), Hughes–Brezzi drilling penalty.
//!
//! # Allman membrane
//! The in-plane displacements are those of the 6-node (LST) triangle whose mid-side values are
//! not free but follow from the corner displacements and the corner rotations θz: on the edge from
//! node i to node j (mid-side k),
//!
//! ```text
//!   u_k = ½ (u_i + u_j) + (y_j − y_i)(θ_j − θ_i)/8
//!   v_k = ½ (v_i + v_j) + (x_i − x_j)(θ_j − θ_i)/8
//! ```
//! i.e. the normal displacement of the edge is the quadratic u_n = c s (L − s) whose end slopes
//! ±cL best fit the corner rotations (cL = (θ_i − θ_j)/2), normal n = e_z × (x_j − x_i)/L. So
//! u = Σ_a N_a^u (u_a, v_a, θ_a) with the quadratic N₁…N₆ ([`quadratic`]); the strains
//! ε₀ = [u,x, v,y, u,y + v,x] are linear and the 3-point rule integrates the stiffness exactly.
//! Properties (tested): a linear field with θ_a = its rotation ω (the corrections vanish with
//! equal θ) is reproduced exactly, so the membrane patch test passes; a rigid rotation gives no
//! strain; the one extra zero-energy mode of Allman's element (equal θ at the three corners, no
//! displacement) is removed by the Hughes–Brezzi term ½ ∫ k_δ (θz − ω)² dA with θz interpolated
//! linearly and ω = ½ (v,x − u,y) from the Allman field, which vanishes on the linear fields above.
//! Mass and gravity use the linear functions for the translations (the element's lumping).
//!
//! # DKT (discrete Kirchhoff triangle)
//! The rotations βx = θy, βy = −θx are quadratic, βx = H_x(ξ, η)·U, βy = H_y(ξ, η)·U with
//! U = (w, θx, θy) at the three corners; the mid-side rotations are eliminated by the discrete
//! Kirchhoff constraints (zero shear at the corners and mid-sides, w cubic and β_n linear along
//! each edge). With the quadratic shape functions N₁…N₆ (corners, then mid-sides 4, 5, 6 on the
//! edges 2-3, 3-1, 1-2) and, for a node a whose edges are m (a first) and n (a second):
//!
//! ```text
//!   H_x[w_a]  = 3/2 (a_m N_m − a_n N_n)      H_y[w_a]  = 3/2 (d_m N_m − d_n N_n)
//!   H_x[θx_a] = b_m N_m + b_n N_n            H_y[θx_a] = −N_a + e_m N_m + e_n N_n
//!   H_x[θy_a] = N_a − c_m N_m − c_n N_n      H_y[θy_a] = −H_x[θx_a]
//!   edge k from node i to node j, x_ij = x_i − x_j, l² = x_ij² + y_ij²:
//!   a_k = −x_ij/l², b_k = ¾ x_ij y_ij/l², c_k = (¼ x_ij² − ½ y_ij²)/l²,
//!   d_k = −y_ij/l², e_k = (¼ y_ij² − ½ x_ij²)/l²
//! ```
//! (Batoz et al. 1980, eq. 36 and Table; each term was re-derived from the edge constraints.)
//! κ = [βx,x, βy,y, βx,y + βy,x] is linear; there is no transverse shear energy (thin shells).
//! The in-plane rule is the 3-point rule at (1/6, 1/6), (2/3, 1/6), (1/6, 2/3) (degree 2: exact
//! for the elastic DKT stiffness and the consistent mass), used for every term, so each point has
//! its own layer states.

use nalgebra::{Matrix2, SMatrix, SVector, Vector2};

use super::element::{PlanePoint, ShellElement};
use super::geometry;
use super::section::ShellSection;
use super::ShellError;

/// 3-node flat shell (module docs).
pub type ShellTri3 = ShellElement<3, 18>;

/// Quadratic shape functions of the 6-node triangle and their (ξ, η) derivatives, with area
/// coordinates L = (1 − ξ − η, ξ, η); mid-side k lies on the edge opposite corner k.
fn quadratic(xi: f64, eta: f64) -> ([f64; 6], [f64; 6], [f64; 6]) {
    let l = [1.0 - xi - eta, xi, eta];
    let dl_xi = [-1.0, 1.0, 0.0];
    let dl_eta = [-1.0, 0.0, 1.0];
    let mut n = [0.0; 6];
    let mut nx = [0.0; 6];
    let mut ne = [0.0; 6];
    for a in 0..3 {
        n[a] = l[a] * (2.0 * l[a] - 1.0);
        nx[a] = (4.0 * l[a] - 1.0) * dl_xi[a];
        ne[a] = (4.0 * l[a] - 1.0) * dl_eta[a];
        let (i, j) = ((a + 1) % 3, (a + 2) % 3);
        n[3 + a] = 4.0 * l[i] * l[j];
        nx[3 + a] = 4.0 * (dl_xi[i] * l[j] + l[i] * dl_xi[j]);
        ne[3 + a] = 4.0 * (dl_eta[i] * l[j] + l[i] * dl_eta[j]);
    }
    (n, nx, ne)
}

/// Edge coefficients a, b, c, d, e of the DKT for the edge k (opposite corner k) of the triangle
/// with local coordinates `xy`; the edge runs from node (k+1)%3 to node (k+2)%3.
fn edge_coefficients(xy: &[[f64; 2]; 3]) -> [[f64; 5]; 3] {
    let mut out = [[0.0; 5]; 3];
    for (k, o) in out.iter_mut().enumerate() {
        let (i, j) = ((k + 1) % 3, (k + 2) % 3);
        let x = xy[i][0] - xy[j][0];
        let y = xy[i][1] - xy[j][1];
        let l2 = x * x + y * y;
        *o =
            [-x / l2, 0.75 * x * y / l2, (0.25 * x * x - 0.5 * y * y) / l2, -y / l2, (0.25 * y * y - 0.5 * x * x) / l2];
    }
    out
}

/// H_x and H_y (9 values each, per node w, θx, θy) evaluated with the quadratic functions `n`
/// (values or derivatives: H is linear in them).
fn dkt_h(coef: &[[f64; 5]; 3], n: &[f64; 6]) -> ([f64; 9], [f64; 9]) {
    let mut hx = [0.0; 9];
    let mut hy = [0.0; 9];
    for a in 0..3 {
        // Edge where a is the first node: the edge (a, a+1), opposite corner (a+2)%3; where a is
        // the second node: the edge (a−1, a), opposite corner (a+1)%3.
        let m = (a + 2) % 3;
        let q = (a + 1) % 3;
        let (cm, cq) = (coef[m], coef[q]);
        let (nm, nq) = (n[3 + m], n[3 + q]);
        hx[3 * a] = 1.5 * (cm[0] * nm - cq[0] * nq);
        hx[3 * a + 1] = cm[1] * nm + cq[1] * nq;
        hx[3 * a + 2] = n[a] - cm[2] * nm - cq[2] * nq;
        hy[3 * a] = 1.5 * (cm[3] * nm - cq[3] * nq);
        hy[3 * a + 1] = -n[a] + cm[4] * nm + cq[4] * nq;
        hy[3 * a + 2] = -hx[3 * a + 1];
    }
    (hx, hy)
}

impl ShellElement<3, 18> {
    /// A 3-node shell on the nodes `coords` (global; the order sets the normal) with `section`.
    ///
    /// Errors: non-finite coordinates, invalid section, (nearly) zero area, damage law not valid
    /// for the element size sqrt(area).
    pub fn new(coords: [[f64; 3]; 3], section: &ShellSection) -> Result<Self, ShellError> {
        Self::with_membrane(coords, section, Membrane::Allman)
    }

    /// The same element with the membrane chosen: [`Membrane::Allman`] (what [`Self::new`]
    /// builds) or the constant-strain [`Membrane::Cst`] (kept for comparison in the tests of the
    /// Allman membrane; not reachable from job files).
    pub fn with_membrane(
        coords: [[f64; 3]; 3],
        section: &ShellSection,
        membrane: Membrane,
    ) -> Result<Self, ShellError> {
        section.validate()?;
        let geo = geometry::triangle(&coords)?;
        let xy = geo.xy;
        let coef = edge_coefficients(&xy);
        // Linear map x = x₁ + ξ x₂₁ + η x₃₁: J = [[x₂₁, y₂₁], [x₃₁, y₃₁]], det J = 2 area.
        let j = Matrix2::new(xy[1][0] - xy[0][0], xy[1][1] - xy[0][1], xy[2][0] - xy[0][0], xy[2][1] - xy[0][1]);
        let det = j.determinant();
        let jinv = j.try_inverse().ok_or(ShellError::Degenerate {
            coords: coords.to_vec(),
            corner: 0,
            ratio: 0.0,
            min_ratio: geometry::MIN_CORNER_JACOBIAN,
        })?;
        // Linear shape functions: constant Cartesian derivatives.
        let dlin: [Vector2<f64>; 3] =
            [jinv * Vector2::new(-1.0, -1.0), jinv * Vector2::new(1.0, 0.0), jinv * Vector2::new(0.0, 1.0)];
        let mut points = Vec::with_capacity(3);
        let allman = allman_edges(&xy);
        for (xi, eta) in [(1.0 / 6.0, 1.0 / 6.0), (2.0 / 3.0, 1.0 / 6.0), (1.0 / 6.0, 2.0 / 3.0)] {
            let lin = [1.0 - xi - eta, xi, eta];
            let (_, nxi, neta) = quadratic(xi, eta);
            // Cartesian derivatives of the quadratic functions.
            let dq: Vec<Vector2<f64>> = (0..6).map(|k| jinv * Vector2::new(nxi[k], neta[k])).collect();
            let (hx_xi, hy_xi) = dkt_h(&coef, &nxi);
            let (hx_eta, hy_eta) = dkt_h(&coef, &neta);
            let mut b = SMatrix::<f64, 6, 18>::zeros();
            let mut b_d = SMatrix::<f64, 1, 18>::zeros();
            for a in 0..3 {
                let o = 6 * a;
                // Membrane: (u, v) = Σ_a [N_uu u_a + N_uθ θ_a, N_vv v_a + N_vθ θ_a] (module docs);
                // CST: N_uu = N_vv = L_a, no θ terms.
                let (gu, gtu, gtv) = match membrane {
                    Membrane::Cst => (dlin[a], Vector2::zeros(), Vector2::zeros()),
                    Membrane::Allman => {
                        let mut gu = dq[a];
                        let mut gtu = Vector2::zeros();
                        let mut gtv = Vector2::zeros();
                        for (k, e) in allman.iter().enumerate() {
                            let sign = if a == e.j {
                                1.0
                            } else if a == e.i {
                                -1.0
                            } else {
                                continue;
                            };
                            gu += 0.5 * dq[3 + k];
                            gtu += sign * e.du * dq[3 + k];
                            gtv += sign * e.dv * dq[3 + k];
                        }
                        (gu, gtu, gtv)
                    }
                };
                b[(0, o)] = gu.x;
                b[(0, o + 5)] = gtu.x;
                b[(1, o + 1)] = gu.y;
                b[(1, o + 5)] = gtv.y;
                b[(2, o)] = gu.y;
                b[(2, o + 1)] = gu.x;
                b[(2, o + 5)] = gtu.y + gtv.x;
                // δ = θz − ω, ω = ½ (v,x − u,y).
                b_d[(0, o + 5)] = lin[a] - 0.5 * (gtv.x - gtu.y);
                b_d[(0, o)] = 0.5 * gu.y;
                b_d[(0, o + 1)] = -0.5 * gu.x;
                // DKT: local DOF (w, θx, θy) = (o+2, o+3, o+4).
                for c in 0..3 {
                    let hxd = jinv * Vector2::new(hx_xi[3 * a + c], hx_eta[3 * a + c]);
                    let hyd = jinv * Vector2::new(hy_xi[3 * a + c], hy_eta[3 * a + c]);
                    b[(3, o + 2 + c)] = hxd.x;
                    b[(4, o + 2 + c)] = hyd.y;
                    b[(5, o + 2 + c)] = hxd.y + hyd.x;
                }
            }
            points.push(PlanePoint {
                weight: det / 6.0,
                shape: SVector::<f64, 3>::from(lin),
                b,
                b_s: SMatrix::<f64, 2, 18>::zeros(),
                b_d,
            });
        }
        ShellElement::from_parts("shell_dkt3", coords, geo, points, section)
    }
}

/// The membrane of the 3-node shell.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Membrane {
    /// Allman's triangle with vertex rotations (module docs): the default.
    Allman,
    /// The constant-strain triangle; θz enters only through the drilling penalty.
    Cst,
}

/// One edge of the Allman interpolation: from corner `i` to corner `j` (mid-side k = the corner
/// opposite), with the mid-side coefficients of (θ_j − θ_i): u_k gets du (θ_j − θ_i), v_k gets
/// dv (θ_j − θ_i).
#[derive(Clone, Copy, Debug)]
struct AllmanEdge {
    i: usize,
    j: usize,
    du: f64,
    dv: f64,
}

/// The three edges, mid-side k on the edge from (k+1)%3 to (k+2)%3 (the order of [`quadratic`]):
/// du = (y_j − y_i)/8, dv = (x_i − x_j)/8 (module docs).
fn allman_edges(xy: &[[f64; 2]; 3]) -> [AllmanEdge; 3] {
    std::array::from_fn(|k| {
        let (i, j) = ((k + 1) % 3, (k + 2) % 3);
        AllmanEdge { i, j, du: (xy[j][1] - xy[i][1]) / 8.0, dv: (xy[i][0] - xy[j][0]) / 8.0 }
    })
}
