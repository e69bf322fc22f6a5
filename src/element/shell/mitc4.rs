//! [`ShellQuad4`]: 4-node flat shell — bilinear membrane, MITC4 bending and transverse shear
//! (Dvorkin & Bathe 1984), Hughes–Brezzi drilling penalty; 2×2 Gauss in-plane.
//!
//! # Shape functions and Jacobian
//! Nodes at (ξ_a, η_a) = (−1,−1), (1,−1), (1,1), (−1,1); N_a = ¼ (1 + ξ ξ_a)(1 + η η_a) on the
//! flat projected element ([`geometry`](super::geometry)). J = [[x,ξ, y,ξ], [x,η, y,η]],
//! [∂/∂x; ∂/∂y] = J⁻¹ [∂/∂ξ; ∂/∂η].
//!
//! # MITC4 transverse shear
//! The covariant shear strains γ_ξ = w,ξ + βx x,ξ + βy y,ξ and γ_η (likewise with η) are not
//! taken at the Gauss points but interpolated from the mid-side tying points:
//! ```text
//!   γ̃_ξ = ½(1 − η) γ_ξ(0, −1) + ½(1 + η) γ_ξ(0, 1)
//!   γ̃_η = ½(1 − ξ) γ_η(−1, 0) + ½(1 + ξ) γ_η(1, 0)
//!   [γ_xz; γ_yz] = J⁻¹ [γ̃_ξ; γ̃_η]    (J at the Gauss point)
//! ```
//! Along each edge γ_ξ (or γ_η) at the mid-side is the exact Kirchhoff constraint of a cubic w, so
//! the element does not lock as t → 0 and passes the constant-curvature patch test (tested).

use nalgebra::{Matrix2, SMatrix, SVector, Vector2};

use super::element::{PlanePoint, ShellElement};
use super::geometry;
use super::section::ShellSection;
use super::ShellError;

/// 4-node flat shell (module docs).
pub type ShellQuad4 = ShellElement<4, 24>;

const XI: [f64; 4] = [-1.0, 1.0, 1.0, -1.0];
const ETA: [f64; 4] = [-1.0, -1.0, 1.0, 1.0];

/// Shape functions and their (ξ, η) derivatives.
fn shape(xi: f64, eta: f64) -> ([f64; 4], [f64; 4], [f64; 4]) {
    let mut n = [0.0; 4];
    let mut dxi = [0.0; 4];
    let mut deta = [0.0; 4];
    for a in 0..4 {
        n[a] = 0.25 * (1.0 + xi * XI[a]) * (1.0 + eta * ETA[a]);
        dxi[a] = 0.25 * XI[a] * (1.0 + eta * ETA[a]);
        deta[a] = 0.25 * ETA[a] * (1.0 + xi * XI[a]);
    }
    (n, dxi, deta)
}

/// J = [[x,ξ, y,ξ], [x,η, y,η]].
fn jacobian(xy: &[[f64; 2]; 4], dxi: &[f64; 4], deta: &[f64; 4]) -> Matrix2<f64> {
    let mut j = Matrix2::zeros();
    for a in 0..4 {
        j[(0, 0)] += dxi[a] * xy[a][0];
        j[(0, 1)] += dxi[a] * xy[a][1];
        j[(1, 0)] += deta[a] * xy[a][0];
        j[(1, 1)] += deta[a] * xy[a][1];
    }
    j
}

/// Row of the covariant shear strain along the natural direction with derivatives `dn` and base
/// vector `(xd, yd)` = (x,ξ, y,ξ) or (x,η, y,η): γ = w,d + βx x,d + βy y,d with βx = θy, βy = −θx.
fn covariant_shear_row(n: &[f64; 4], dn: &[f64; 4], xd: f64, yd: f64) -> SVector<f64, 24> {
    let mut r = SVector::<f64, 24>::zeros();
    for a in 0..4 {
        r[6 * a + 2] = dn[a];
        r[6 * a + 4] = n[a] * xd;
        r[6 * a + 3] = -n[a] * yd;
    }
    r
}

impl ShellElement<4, 24> {
    /// A 4-node shell on the nodes `coords` (global, in order around the element) with `section`.
    ///
    /// Errors: non-finite coordinates, invalid section, degenerate or non-convex quadrilateral,
    /// warping ratio above [`WARPING_LIMIT`](super::WARPING_LIMIT), damage law not valid for the
    /// element size sqrt(area).
    pub fn new(coords: [[f64; 3]; 4], section: &ShellSection) -> Result<Self, ShellError> {
        section.validate()?;
        let geo = geometry::quad(&coords)?;
        let xy = geo.xy;
        // Tying points: γ_ξ at (0, ∓1), γ_η at (∓1, 0).
        let tie = |xi: f64, eta: f64, along_xi: bool| {
            let (n, dxi, deta) = shape(xi, eta);
            let j = jacobian(&xy, &dxi, &deta);
            if along_xi {
                covariant_shear_row(&n, &dxi, j[(0, 0)], j[(0, 1)])
            } else {
                covariant_shear_row(&n, &deta, j[(1, 0)], j[(1, 1)])
            }
        };
        let g_xi_bottom = tie(0.0, -1.0, true);
        let g_xi_top = tie(0.0, 1.0, true);
        let g_eta_left = tie(-1.0, 0.0, false);
        let g_eta_right = tie(1.0, 0.0, false);

        let gp = 1.0 / 3f64.sqrt();
        let mut points = Vec::with_capacity(4);
        for (xi, eta) in [(-gp, -gp), (gp, -gp), (gp, gp), (-gp, gp)] {
            let (n, dxi, deta) = shape(xi, eta);
            let j = jacobian(&xy, &dxi, &deta);
            let det = j.determinant();
            let jinv = j.try_inverse().ok_or(ShellError::Degenerate {
                coords: coords.to_vec(),
                corner: 0,
                ratio: 0.0,
                min_ratio: geometry::MIN_CORNER_JACOBIAN,
            })?;
            let mut b = SMatrix::<f64, 6, 24>::zeros();
            let mut b_d = SMatrix::<f64, 1, 24>::zeros();
            for a in 0..4 {
                let d = jinv * Vector2::new(dxi[a], deta[a]);
                let (nx, ny) = (d.x, d.y);
                let o = 6 * a;
                // membrane
                b[(0, o)] = nx;
                b[(1, o + 1)] = ny;
                b[(2, o)] = ny;
                b[(2, o + 1)] = nx;
                // bending: κxx = θy,x; κyy = −θx,y; κxy = θy,y − θx,x
                b[(3, o + 4)] = nx;
                b[(4, o + 3)] = -ny;
                b[(5, o + 4)] = ny;
                b[(5, o + 3)] = -nx;
                // drilling θz − ½(v,x − u,y)
                b_d[(0, o + 5)] = n[a];
                b_d[(0, o)] = 0.5 * ny;
                b_d[(0, o + 1)] = -0.5 * nx;
            }
            let g_xi = g_xi_bottom * (0.5 * (1.0 - eta)) + g_xi_top * (0.5 * (1.0 + eta));
            let g_eta = g_eta_left * (0.5 * (1.0 - xi)) + g_eta_right * (0.5 * (1.0 + xi));
            let mut b_s = SMatrix::<f64, 2, 24>::zeros();
            for c in 0..24 {
                let cart = jinv * Vector2::new(g_xi[c], g_eta[c]);
                b_s[(0, c)] = cart.x;
                b_s[(1, c)] = cart.y;
            }
            points.push(PlanePoint { weight: det, shape: SVector::<f64, 4>::from(n), b, b_s, b_d });
        }
        ShellElement::from_parts("shell_mitc4", coords, geo, points, section)
    }
}
