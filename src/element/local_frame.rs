//! Local axes of a line element and the transformation between global and local components.
//!
//! # Convention (OpenSees `geomTransf Linear $vecxz`)
//!
//! Given the end nodes x₁, x₂ and an *orientation vector* `vecxz` (global components):
//!
//! ```text
//!   e_x = (x₂ − x₁) / L                 element axis, node 1 → node 2, L = |x₂ − x₁|
//!   e_y = (vecxz × e_x) / |vecxz × e_x| `vecxz` lies in the local x–z plane …
//!   e_z = e_x × e_y                     … on the +z side (vecxz · e_z > 0)
//! ```
//!
//! so `vecxz` plays the role of the local z axis (up to the component along the axis that is
//! removed). Example: a horizontal beam along global X with `vecxz = (0, 0, 1)` has local axes equal
//! to the global ones (e_y = +Y, e_z = +Z): bending under gravity is in the local x–z plane and is
//! resisted by `Iy`. This is the same choice as OpenSees (`vecxz`) and as the Abaqus n₁/n₂ pair with
//! n₂ ≈ `vecxz`.
//!
//! # Rotation matrix
//!
//! `R` has the local unit axes as its **rows** (global components): `R = [e_xᵀ; e_yᵀ; e_zᵀ]`. A vector
//! transforms as a_local = R a_global and a_global = Rᵀ a_local. For a 2-node element with 6 DOF per
//! node, T = diag(R, R, R, R) (ux uy uz, rx ry rz, at each node), u_l = T u_g, f_g = Tᵀ f_l and
//! K_g = Tᵀ K_l T.
//!
//! # Checks
//! - coordinates must be finite;
//! - zero length: L ≤ 1e-10 · (1 + max |coordinate|) is refused (relative to the size of the
//!   coordinates, so a 1 µm element far from the origin is still accepted when it is not round-off);
//! - orientation: `vecxz` must be finite and sin∠(e_x, vecxz) = |e_x × vecxz| / |vecxz| ≥ 1e-6.

use nalgebra::{Matrix3, SMatrix, SVector, Vector3};

use super::error::ElementError;

/// 12×12 matrix of a 2-node, 6-DOF-per-node element.
pub type Mat12 = SMatrix<f64, 12, 12>;
/// 12-vector of a 2-node, 6-DOF-per-node element.
pub type Vec12 = SVector<f64, 12>;

/// Relative tolerance below which an element is taken to have zero length.
const ZERO_LENGTH_RTOL: f64 = 1e-10;
/// Smallest accepted sine of the angle between the element axis and the orientation vector.
const MIN_SIN_ANGLE: f64 = 1e-6;

/// Length and local axes of a 2-node line element.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct LocalFrame {
    /// R: rows are the local axes e_x, e_y, e_z in global components.
    rotation: Matrix3<f64>,
    /// Element length L.
    length: f64,
}

impl LocalFrame {
    /// Local axes of the element x₁ → x₂ with orientation vector `vecxz` (see the module docs).
    pub fn from_vecxz(x1: [f64; 3], x2: [f64; 3], vecxz: [f64; 3]) -> Result<Self, ElementError> {
        for (node, c) in [x1, x2].into_iter().enumerate() {
            if c.iter().any(|x| !x.is_finite()) {
                return Err(ElementError::NonFiniteCoordinates { node, coords: c });
            }
        }
        let a = Vector3::from(x1);
        let b = Vector3::from(x2);
        let d = b - a;
        let length = d.norm();
        let scale = 1.0 + a.amax().max(b.amax());
        if length <= ZERO_LENGTH_RTOL * scale {
            return Err(ElementError::ZeroLength { node1: x1, node2: x2, length });
        }
        let ex = d / length;
        let v = Vector3::from(vecxz);
        let v_norm = v.norm();
        let y = v.cross(&ex);
        let sin_angle = if v_norm > 0.0 && v_norm.is_finite() { y.norm() / v_norm } else { 0.0 };
        if sin_angle.is_nan() || sin_angle < MIN_SIN_ANGLE {
            return Err(ElementError::BadOrientation { vecxz, axis: ex.into(), sin_angle });
        }
        let ey = y.normalize();
        let ez = ex.cross(&ey);
        let rotation = Matrix3::from_rows(&[ex.transpose(), ey.transpose(), ez.transpose()]);
        Ok(Self { rotation, length })
    }

    /// Element length L.
    pub fn length(&self) -> f64 {
        self.length
    }

    /// R = [e_xᵀ; e_yᵀ; e_zᵀ] (rows = local axes in global components).
    pub fn rotation(&self) -> &Matrix3<f64> {
        &self.rotation
    }

    /// Local axis `i` (0 = x, 1 = y, 2 = z) in global components.
    pub fn axis(&self, i: usize) -> Vector3<f64> {
        self.rotation.row(i).transpose()
    }

    /// a_local = R a_global.
    pub fn to_local(&self, a: &Vector3<f64>) -> Vector3<f64> {
        self.rotation * a
    }

    /// a_global = Rᵀ a_local.
    pub fn to_global(&self, a: &Vector3<f64>) -> Vector3<f64> {
        self.rotation.tr_mul(a)
    }

    /// u_l = T u_g for a 12-vector (T = diag(R, R, R, R)).
    pub fn vec12_to_local(&self, u: &Vec12) -> Vec12 {
        let mut out = Vec12::zeros();
        for b in 0..4 {
            let blk = self.rotation * u.fixed_rows::<3>(3 * b);
            out.fixed_rows_mut::<3>(3 * b).copy_from(&blk);
        }
        out
    }

    /// f_g = Tᵀ f_l for a 12-vector.
    pub fn vec12_to_global(&self, f: &Vec12) -> Vec12 {
        let mut out = Vec12::zeros();
        for b in 0..4 {
            let blk = self.rotation.tr_mul(&f.fixed_rows::<3>(3 * b));
            out.fixed_rows_mut::<3>(3 * b).copy_from(&blk);
        }
        out
    }

    /// K_g = Tᵀ K_l T, computed by 3×3 blocks: K_g(I,J) = Rᵀ K_l(I,J) R.
    pub fn mat12_to_global(&self, k: &Mat12) -> Mat12 {
        let r = &self.rotation;
        let mut out = Mat12::zeros();
        for bi in 0..4 {
            for bj in 0..4 {
                let blk = k.fixed_view::<3, 3>(3 * bi, 3 * bj);
                let g = r.tr_mul(&(blk * r));
                out.fixed_view_mut::<3, 3>(3 * bi, 3 * bj).copy_from(&g);
            }
        }
        out
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Orthonormality and right-handedness: RᵀR = I, det R = +1 (to 1e-14, round-off of unit vectors).
    #[test]
    fn rotation_is_proper_orthogonal() {
        let f = LocalFrame::from_vecxz([1.0, 2.0, 3.0], [4.0, -1.0, 5.5], [0.3, 0.2, 1.0]).unwrap();
        let r = f.rotation();
        assert!((r.transpose() * r - Matrix3::identity()).amax() < 1e-14);
        assert!((r.determinant() - 1.0).abs() < 1e-14);
        // vecxz lies in the local x-z plane on the +z side: its e_y component vanishes, e_z one > 0.
        let v = Vector3::new(0.3, 0.2, 1.0);
        assert!(f.axis(1).dot(&v).abs() < 1e-14);
        assert!(f.axis(2).dot(&v) > 0.0);
        assert!((f.length() - (9.0f64 + 9.0 + 6.25).sqrt()).abs() < 1e-14);
    }

    /// The documented example: beam along X with vecxz = Z has local axes = global axes (exact).
    #[test]
    fn horizontal_beam_has_global_axes() {
        let f = LocalFrame::from_vecxz([0.0; 3], [2.0, 0.0, 0.0], [0.0, 0.0, 1.0]).unwrap();
        assert_eq!(*f.rotation(), Matrix3::identity());
    }

    #[test]
    fn zero_length_is_refused_with_coordinates() {
        let e = LocalFrame::from_vecxz([1.0, 1.0, 1.0], [1.0, 1.0, 1.0], [0.0, 0.0, 1.0]).unwrap_err();
        assert!(matches!(e, ElementError::ZeroLength { node1: [1.0, 1.0, 1.0], .. }), "{e}");
        assert!(e.to_string().contains("[1.0, 1.0, 1.0]"), "{e}");
    }

    #[test]
    fn parallel_or_zero_orientation_is_refused() {
        let e = LocalFrame::from_vecxz([0.0; 3], [0.0, 0.0, 3.0], [0.0, 0.0, -2.0]).unwrap_err();
        assert!(matches!(e, ElementError::BadOrientation { .. }), "{e}");
        let e = LocalFrame::from_vecxz([0.0; 3], [0.0, 0.0, 3.0], [0.0; 3]).unwrap_err();
        assert!(matches!(e, ElementError::BadOrientation { .. }), "{e}");
        let e = LocalFrame::from_vecxz([0.0; 3], [0.0, 0.0, 3.0], [f64::NAN, 0.0, 0.0]).unwrap_err();
        assert!(matches!(e, ElementError::BadOrientation { .. }), "{e}");
        let e = LocalFrame::from_vecxz([0.0, f64::INFINITY, 0.0], [1.0; 3], [0.0, 0.0, 1.0]).unwrap_err();
        assert!(matches!(e, ElementError::NonFiniteCoordinates { node: 0, .. }), "{e}");
    }

    /// T is orthogonal, so transforming to local and back is the identity (to 1e-14).
    #[test]
    fn vec12_round_trip() {
        let f = LocalFrame::from_vecxz([0.0; 3], [1.0, 1.0, 1.0], [1.0, 0.0, 0.0]).unwrap();
        let u = Vec12::from_fn(|i, _| (i as f64).sin());
        assert!((f.vec12_to_global(&f.vec12_to_local(&u)) - u).amax() < 1e-14);
    }
}
