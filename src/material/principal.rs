//! Principal strains and the equivalent strain ε_eq = sqrt(Σ_i ⟨ε_i⟩₊²) with its gradient.
//!
//! # Gradient
//! With the positive part ε₊ = Σ_i ⟨ε_i⟩₊ n_i ⊗ n_i, the scalar ½ ε_eq² = ½ Σ⟨ε_i⟩₊² has the
//! gradient ε₊ (a C¹ tensor function, also at repeated eigenvalues), so ∂ε_eq/∂ε = ε₊ / ε_eq.
//! In Voigt notation with **engineering** shear strains γ_ij = 2 ε_ij, the component of the gradient
//! with respect to γ_ij is the tensor component (ε₊)_ij (not doubled): d(½ε_eq²) = Σ_kl (ε₊)_kl dε_kl
//! and dε_ij = dε_ji = dγ_ij / 2.

use nalgebra::{Matrix3, SymmetricEigen, Vector3, Vector6};

/// Principal values (ε₁ ≥ ε₂) of the in-plane strain (ε_xx, ε_yy, γ_xy), closed form:
/// ε₁,₂ = (ε_xx + ε_yy)/2 ± sqrt(((ε_xx − ε_yy)/2)² + (γ_xy/2)²).
#[inline]
pub fn principal_2d(exx: f64, eyy: f64, gxy: f64) -> (f64, f64) {
    let c = 0.5 * (exx + eyy);
    let r = (0.5 * (exx - eyy)).hypot(0.5 * gxy);
    (c + r, c - r)
}

/// ½ Σ⟨ε_i⟩₊² of the in-plane strain and its gradient ε₊ = [(ε₊)_xx, (ε₊)_yy, (ε₊)_xy] (tensor
/// components; with respect to (ε_xx, ε_yy, γ_xy), module docs).
///
/// Closed form of ε₊: both principal values ≥ 0 → ε; both ≤ 0 → 0; otherwise (ε₁ > 0 > ε₂)
/// ε₊ = ε₁ n₁⊗n₁ with n₁⊗n₁ = (ε − ε₂ I)/(ε₁ − ε₂).
#[inline]
pub fn positive_part_2d(exx: f64, eyy: f64, gxy: f64) -> (f64, Vector3<f64>) {
    let (e1, e2) = principal_2d(exx, eyy, gxy);
    if e2 >= 0.0 {
        (0.5 * (e1 * e1 + e2 * e2), Vector3::new(exx, eyy, 0.5 * gxy))
    } else if e1 <= 0.0 {
        (0.0, Vector3::zeros())
    } else {
        // Here e1 > 0 > e2, so e1 − e2 > 0.
        let s = e1 / (e1 - e2);
        (0.5 * e1 * e1, Vector3::new(s * (exx - e2), s * (eyy - e2), s * 0.5 * gxy))
    }
}

/// The symmetric strain tensor of a Voigt vector `[ε_xx, ε_yy, ε_zz, γ_yz, γ_xz, γ_xy]`.
#[inline]
pub fn tensor_of_voigt(e: &Vector6<f64>) -> Matrix3<f64> {
    Matrix3::new(e[0], 0.5 * e[5], 0.5 * e[4], 0.5 * e[5], e[1], 0.5 * e[3], 0.5 * e[4], 0.5 * e[3], e[2])
}

/// Maximum number of Jacobi/QR sweeps of the 3×3 symmetric eigen solver; a finite strain converges
/// in a handful, a NaN never does and then gives NaN principal strains instead of looping.
const MAX_EIGEN_ITERATIONS: usize = 64;

/// Principal strains (unordered) and unit principal directions (columns) of a Voigt strain
/// `[ε_xx, ε_yy, ε_zz, γ_yz, γ_xz, γ_xy]`, by nalgebra's symmetric eigen solver (implicit QR,
/// no allocation). Non-finite input gives NaN values.
#[inline]
pub fn principal_3d(e: &Vector6<f64>) -> (Vector3<f64>, Matrix3<f64>) {
    let m = tensor_of_voigt(e);
    match SymmetricEigen::try_new(m, f64::EPSILON, MAX_EIGEN_ITERATIONS) {
        Some(eig) => (eig.eigenvalues, eig.eigenvectors),
        None => (Vector3::repeat(f64::NAN), Matrix3::identity()),
    }
}

/// ½ Σ⟨ε_i⟩₊² of a Voigt strain and its gradient ε₊ in Voigt order with tensor shear components
/// `[(ε₊)_xx, (ε₊)_yy, (ε₊)_zz, (ε₊)_yz, (ε₊)_xz, (ε₊)_xy]` (module docs).
#[inline]
pub fn positive_part_3d(e: &Vector6<f64>) -> (f64, Vector6<f64>) {
    let (values, vectors) = principal_3d(e);
    let mut half_sq = 0.0;
    let mut p = Matrix3::zeros();
    for i in 0..3 {
        let v = values[i];
        if v > 0.0 {
            half_sq += 0.5 * v * v;
            let n = vectors.column(i);
            p += v * n * n.transpose();
        } else if v.is_nan() {
            return (f64::NAN, Vector6::repeat(f64::NAN));
        }
    }
    (half_sq, Vector6::new(p[(0, 0)], p[(1, 1)], p[(2, 2)], p[(1, 2)], p[(0, 2)], p[(0, 1)]))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn plane_principal_values_of_pure_shear() {
        // γ_xy = 2e-4 alone: ε₁,₂ = ±1e-4 (Mohr's circle), round-off tolerance.
        let (e1, e2) = principal_2d(0.0, 0.0, 2e-4);
        assert!((e1 - 1e-4).abs() < 1e-18 && (e2 + 1e-4).abs() < 1e-18);
        let (h, p) = positive_part_2d(0.0, 0.0, 2e-4);
        assert!((h - 0.5e-8).abs() < 1e-22);
        // ε₊ = 1e-4 n₁⊗n₁ with n₁ = (1,1)/√2: components 0.5e-4 each.
        assert!((p - Vector3::new(0.5e-4, 0.5e-4, 0.5e-4)).norm() < 1e-18);
    }

    #[test]
    fn three_d_agrees_with_plane_closed_form() {
        // A strain with no out-of-plane shear: the 3D solver gives the 2D principal values plus ε_zz.
        let e = Vector6::new(3e-4, -1e-4, -0.5e-4, 0.0, 0.0, 2.4e-4);
        let (h3, p3) = positive_part_3d(&e);
        let (h2, p2) = positive_part_2d(3e-4, -1e-4, 2.4e-4);
        // Tolerance 1e-12 relative: QR eigen solver vs closed form.
        assert!((h3 - h2).abs() <= 1e-12 * h2);
        for (a, b) in [(p3[0], p2[0]), (p3[1], p2[1]), (p3[5], p2[2])] {
            assert!((a - b).abs() <= 1e-12 * p2.norm(), "{a} vs {b}");
        }
        assert!(p3[2].abs() <= 1e-12 * p2.norm());
    }

    #[test]
    fn non_finite_strain_gives_nan_not_a_hang() {
        let (h, _) = positive_part_3d(&Vector6::new(f64::NAN, 0.0, 0.0, 0.0, 0.0, 0.0));
        assert!(h.is_nan());
    }
}
