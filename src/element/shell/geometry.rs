//! Local frame of a flat shell element and the projection of a warped quadrilateral.
//!
//! # Local axes
//! ```text
//!   quadrilateral 1-2-3-4:  e₃ = (x₃ − x₁) × (x₄ − x₂) / |…|     (normal of the mean plane)
//!                           e₁ = projection on the plane of ½(x₂ + x₃ − x₁ − x₄), normalized
//!                                (the mean direction of the sides 1→2 and 4→3)
//!   triangle 1-2-3:         e₃ = (x₂ − x₁) × (x₃ − x₁) / |…|,  e₁ = (x₂ − x₁) / |x₂ − x₁|
//!   both:                   e₂ = e₃ × e₁
//! ```
//! The origin is the centroid of the nodes. The normal follows the node order (right-hand rule):
//! nodes go counter-clockwise seen from +e₃. `R = [e₁ᵀ; e₂ᵀ; e₃ᵀ]` (rows = local axes), a_local =
//! R a_global, as in [`LocalFrame`](crate::element::LocalFrame).
//!
//! # Warped quadrilaterals
//! The plane through the centroid normal to e₃ is the "mean plane": the four nodes lie at heights
//! z_i = (x_i − x_c)·e₃ = ±h above it, alternating in sign (z₁ = z₃ = −z₂ = −z₄; an identity of
//! the diagonal normal). The element is computed on the projected flat quadrilateral, and each
//! node is joined to its projection by a rigid link (Taylor's warping correction, MacNeal
//! *Finite Elements* §9.5): the projected point p_i = x_i − z_i e₃ moves as
//!
//! ```text
//!   u_p = u_i + θ_i × (p_i − x_i) = u_i − z_i θ_i × e₃,   i.e. in local axes
//!   u_p = u − z θ_y,   v_p = v + z θ_x,   w_p = w,   rotations unchanged.
//! ```
//! A rigid motion of the warped element is then a rigid motion of the flat one, so the element
//! keeps exactly six zero-energy modes (tested). The flat element misses the membrane–bending
//! coupling of a truly twisted surface; that error grows with h: the warping ratio
//! h / sqrt(area) is refused above [`WARPING_LIMIT`] = 0.05 (a 1 m element may be 5 cm off plane),
//! where triangles or a finer mesh should be used. Triangles are always flat.
//!
//! # Transformation
//! u_flat = G u_global with, per node, G_i = [[R, Z_i R], [0, R]] and Z_i = [[0, −z_i, 0],
//! [z_i, 0, 0], [0, 0, 0]] (G_i = T_i for flat elements). f_global = Gᵀ f_flat, K = Gᵀ K_flat G.

use nalgebra::{Matrix3, SMatrix, Vector3};

use super::error::ShellError;
use crate::element::ElementError;

/// Largest accepted warping ratio h / sqrt(area) of a quadrilateral (module docs).
pub const WARPING_LIMIT: f64 = 0.05;

/// Smallest accepted Jacobian at a corner relative to the mean one (convexity, node order).
pub(crate) const MIN_CORNER_JACOBIAN: f64 = 1e-6;

/// The flat (projected) element in its local frame.
#[derive(Clone, Debug, PartialEq)]
pub struct FlatGeometry<const N: usize> {
    /// R: rows are e₁, e₂, e₃ in global components.
    pub rotation: Matrix3<f64>,
    /// Centroid of the nodes (global).
    pub origin: Vector3<f64>,
    /// Local in-plane coordinates of the projected nodes.
    pub xy: [[f64; 2]; N],
    /// Heights of the nodes above the mean plane, z_i (0 for flat elements).
    pub offsets: [f64; N],
    /// Area of the projected element.
    pub area: f64,
}

fn check_finite<const N: usize>(coords: &[[f64; 3]; N]) -> Result<(), ShellError> {
    for (node, c) in coords.iter().enumerate() {
        if c.iter().any(|x| !x.is_finite()) {
            return Err(ElementError::NonFiniteCoordinates { node, coords: *c }.into());
        }
    }
    Ok(())
}

fn degenerate<const N: usize>(coords: &[[f64; 3]; N], corner: usize, ratio: f64) -> ShellError {
    ShellError::Degenerate { coords: coords.to_vec(), corner, ratio, min_ratio: MIN_CORNER_JACOBIAN }
}

fn frame<const N: usize>(
    coords: &[[f64; 3]; N],
    normal: Vector3<f64>,
    e1_hint: Vector3<f64>,
) -> Option<FlatGeometry<N>> {
    let nn = normal.norm();
    if !(nn > 0.0 && nn.is_finite()) {
        return None;
    }
    let e3 = normal / nn;
    let v = e1_hint - e3 * e1_hint.dot(&e3);
    let vn = v.norm();
    if !(vn > 0.0 && vn.is_finite()) {
        return None;
    }
    let e1 = v / vn;
    let e2 = e3.cross(&e1);
    let rotation = Matrix3::from_rows(&[e1.transpose(), e2.transpose(), e3.transpose()]);
    let origin = coords.iter().map(|c| Vector3::from(*c)).sum::<Vector3<f64>>() / N as f64;
    let mut xy = [[0.0; 2]; N];
    let mut z = [0.0; N];
    for (i, c) in coords.iter().enumerate() {
        let l = rotation * (Vector3::from(*c) - origin);
        xy[i] = [l.x, l.y];
        z[i] = l.z;
    }
    Some(FlatGeometry { rotation, origin, xy, offsets: z, area: 0.0 })
}

/// Local geometry of a quadrilateral (module docs). Refuses non-finite coordinates, degenerate or
/// non-convex elements and warping ratios above [`WARPING_LIMIT`].
pub fn quad(coords: &[[f64; 3]; 4]) -> Result<FlatGeometry<4>, ShellError> {
    check_finite(coords)?;
    let x: Vec<Vector3<f64>> = coords.iter().map(|c| Vector3::from(*c)).collect();
    let normal = (x[2] - x[0]).cross(&(x[3] - x[1]));
    let hint = (x[1] + x[2] - x[0] - x[3]) * 0.5;
    let Some(mut geo) = frame(coords, normal, hint) else {
        return Err(degenerate(coords, 0, 0.0));
    };
    let xy = geo.xy;
    // Jacobian of the bilinear map at corner a: ¼ (x_next − x_a) × (x_prev − x_a), and area / 4
    // on average; so corner_cross / area is 1 at every corner of a parallelogram and drops to 0
    // when the quad degenerates into a triangle or stops being convex.
    let mut corner_cross = [0.0; 4];
    for a in 0..4 {
        let p = xy[a];
        let n = xy[(a + 1) % 4];
        let q = xy[(a + 3) % 4];
        corner_cross[a] = (n[0] - p[0]) * (q[1] - p[1]) - (n[1] - p[1]) * (q[0] - p[0]);
    }
    // Area of the projected quad: half the cross product of its diagonals.
    let d1 = [xy[2][0] - xy[0][0], xy[2][1] - xy[0][1]];
    let d2 = [xy[3][0] - xy[1][0], xy[3][1] - xy[1][1]];
    let area = 0.5 * (d1[0] * d2[1] - d1[1] * d2[0]);
    for (a, &c) in corner_cross.iter().enumerate() {
        let ratio = c / area;
        let valid = area > 0.0 && ratio > MIN_CORNER_JACOBIAN;
        if !valid {
            return Err(degenerate(coords, a, if area > 0.0 { ratio } else { 0.0 }));
        }
    }
    let offset = geo.offsets.iter().fold(0.0f64, |m, z| m.max(z.abs()));
    let ratio = offset / area.sqrt();
    if ratio > WARPING_LIMIT {
        return Err(ShellError::Warped { coords: coords.to_vec(), offset, ratio, limit: WARPING_LIMIT });
    }
    geo.area = area;
    Ok(geo)
}

/// Local geometry of a triangle (module docs). Refuses non-finite coordinates and (nearly) zero
/// area: 2 area ≤ 1e-6 × (longest side)².
pub fn triangle(coords: &[[f64; 3]; 3]) -> Result<FlatGeometry<3>, ShellError> {
    check_finite(coords)?;
    let x: Vec<Vector3<f64>> = coords.iter().map(|c| Vector3::from(*c)).collect();
    let normal = (x[1] - x[0]).cross(&(x[2] - x[0]));
    let longest = (0..3).map(|i| (x[(i + 1) % 3] - x[i]).norm_squared()).fold(0.0, f64::max);
    let ratio = if longest > 0.0 { normal.norm() / longest } else { 0.0 };
    let valid = ratio > MIN_CORNER_JACOBIAN;
    if !valid {
        return Err(degenerate(coords, 0, ratio));
    }
    let Some(mut geo) = frame(coords, normal, x[1] - x[0]) else {
        return Err(degenerate(coords, 0, 0.0));
    };
    geo.offsets = [0.0; 3];
    geo.area = 0.5 * normal.norm();
    Ok(geo)
}

impl<const N: usize> FlatGeometry<N> {
    /// Characteristic length h = sqrt(area) (m), for the regularization of the damage law.
    pub fn characteristic_length(&self) -> f64 {
        self.area.sqrt()
    }

    /// G with u_flat = G u_global (module docs); `D` must be 6 N.
    pub fn transformation<const D: usize>(&self) -> SMatrix<f64, D, D> {
        debug_assert_eq!(D, 6 * N);
        let r = &self.rotation;
        let mut g = SMatrix::<f64, D, D>::zeros();
        for i in 0..N {
            let o = 6 * i;
            let z = self.offsets[i];
            let zm = Matrix3::new(0.0, -z, 0.0, z, 0.0, 0.0, 0.0, 0.0, 0.0);
            g.fixed_view_mut::<3, 3>(o, o).copy_from(r);
            g.fixed_view_mut::<3, 3>(o, o + 3).copy_from(&(zm * r));
            g.fixed_view_mut::<3, 3>(o + 3, o + 3).copy_from(r);
        }
        g
    }
}
