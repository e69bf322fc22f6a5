//! Through-thickness integration: the layer rule and the section update at one in-plane point.
//!
//! # Rule: composite Simpson, one Simpson rule per layer
//! The thickness t is cut into n equal layers; each layer is integrated by Simpson's rule
//! (= 3-point Gauss–Lobatto) on its bottom, middle and top; neighbouring layers share their
//! interface point, so there are 2n + 1 material points (15 for the default 7 layers):
//!
//! ```text
//!   z_j = −t/2 + j t/(2n),  j = 0 … 2n
//!   w_j = t/(6n) · [1, 4, 2, 4, 2, …, 2, 4, 1]
//! ```
//! Simpson is exact for cubics, so with an elastic material Σ w = t, Σ w z = 0 and Σ w z² = t³/12
//! hold to round-off: the layered section equals the closed form A = t C, B = 0, D = t³/12 C for any
//! n (tested). The outer fibres z = ±t/2 are material points, so cracking starts where the bending
//! stress is largest, not half a layer inside (as with a midpoint rule, which would also make D
//! wrong by the factor 1 − 1/n²).
//!
//! # Section update
//! At an in-plane point with membrane strain ε₀ = [ε_xx, ε_yy, γ_xy] and curvature
//! κ = [κ_xx, κ_yy, κ_xy] (element local axes), every layer point j has ε_j = ε₀ + z_j κ and
//! (σ_j, C_j) from the material, and
//!
//! ```text
//!   N = Σ w_j σ_j          A = Σ w_j C_j
//!   M = Σ w_j z_j σ_j      B = Σ w_j z_j C_j      (∂N/∂κ = ∂M/∂ε₀ = B)
//!                          D = Σ w_j z_j² C_j
//! ```
//! With the damage law C_j is the consistent tangent (not symmetric while loading), so the section
//! tangent S = [[A, B], [B, D]] is exact and the element tangent is consistent.

use nalgebra::{Matrix3, Matrix6, Vector3};

use crate::element::PointUpdate;
use crate::material::{nonlocal, plane_stress, PointLaw};

/// Points and weights of the through-thickness rule (module docs).
#[derive(Clone, Debug, PartialEq)]
pub struct ThicknessRule {
    z: Vec<f64>,
    w: Vec<f64>,
}

impl ThicknessRule {
    /// Composite Simpson over `layers` equal layers of a thickness `t` (`layers` ≥ 1).
    pub fn simpson(t: f64, layers: usize) -> Self {
        let n = layers.max(1);
        let np = 2 * n + 1;
        let h = t / (2 * n) as f64;
        let z = (0..np).map(|j| -0.5 * t + j as f64 * h).collect();
        let w = (0..np)
            .map(|j| {
                let c = if j == 0 || j == np - 1 {
                    1.0
                } else if j % 2 == 1 {
                    4.0
                } else {
                    2.0
                };
                c * h / 3.0
            })
            .collect();
        ThicknessRule { z, w }
    }

    /// Number of material points through the thickness (2 n + 1).
    pub fn len(&self) -> usize {
        self.z.len()
    }

    /// Always false (at least 3 points).
    pub fn is_empty(&self) -> bool {
        self.z.is_empty()
    }

    /// Position z_j from the mid-surface (m), bottom to top.
    pub fn z(&self) -> &[f64] {
        &self.z
    }

    /// Weight w_j (m).
    pub fn weights(&self) -> &[f64] {
        &self.w
    }

    /// Elastic section tangent S = [[A, B], [B, D]] of the in-plane elastic matrix `c` summed by
    /// the rule (module docs).
    pub fn elastic_section(&self, c: &Matrix3<f64>) -> Matrix6<f64> {
        let (mut a, mut b, mut d) = (0.0, 0.0, 0.0);
        for (&z, &w) in self.z.iter().zip(&self.w) {
            a += w;
            b += w * z;
            d += w * z * z;
        }
        block_section(&(c * a), &(c * b), &(c * d))
    }
}

/// [[A, B], [B, D]] from its blocks.
pub fn block_section(a: &Matrix3<f64>, b: &Matrix3<f64>, d: &Matrix3<f64>) -> Matrix6<f64> {
    let mut s = Matrix6::zeros();
    s.fixed_view_mut::<3, 3>(0, 0).copy_from(a);
    s.fixed_view_mut::<3, 3>(0, 3).copy_from(b);
    s.fixed_view_mut::<3, 3>(3, 0).copy_from(b);
    s.fixed_view_mut::<3, 3>(3, 3).copy_from(d);
    s
}

/// Resultants and tangent of a section at one in-plane point.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct SectionResponse {
    /// Membrane forces N = [N_xx, N_yy, N_xy] (N/m).
    pub n: Vector3<f64>,
    /// Moments M = [M_xx, M_yy, M_xy] = Σ w z σ (N m/m), work-conjugate to κ.
    pub m: Vector3<f64>,
    /// Tangent [[A, B], [B, D]] = ∂(N, M)/∂(ε₀, κ).
    pub tangent: Matrix6<f64>,
    /// Energy dissipated per area by this update (J/m²), Σ w_j Δφ_j.
    pub dissipation: f64,
}

/// The averaged damage-driving strains `[ε̄_t, ε̄_c]` of the layer points of one in-plane point
/// and their own shares of the averages (`material::nonlocal`), both of length `rule.len()`.
#[derive(Clone, Copy, Debug)]
pub struct NonlocalInput<'a> {
    /// `[ε̄_t, ε̄_c]` per layer point.
    pub averaged: &'a [[f64; 2]],
    /// The point's own share s of its average, per layer point.
    pub self_share: &'a [f64],
}

/// Damage-law update of all layer points of one in-plane point (`rule.len()` points in
/// `points`), their trial states written. Pure in the histories `points` reads. With `nonlocal` the
/// damage is driven by the given averages (`material::nonlocal`), else by the points' own
/// strains (`material::plane_stress`); with extrapolated histories the stress is IMPL-EX's
/// (`material::implex`).
#[allow(clippy::too_many_arguments)]
pub fn damage_section(
    law: &PointLaw,
    rule: &ThicknessRule,
    eps0: &Vector3<f64>,
    kappa: &Vector3<f64>,
    points: &mut PointUpdate,
    secant: bool,
    nonlocal: Option<NonlocalInput>,
) -> SectionResponse {
    let mut n = Vector3::zeros();
    let mut m = Vector3::zeros();
    let mut a = Matrix3::zeros();
    let mut b = Matrix3::zeros();
    let mut d = Matrix3::zeros();
    let mut dissipation = 0.0;
    for j in 0..rule.len() {
        let (z, w) = (rule.z[j], rule.w[j]);
        let strain = eps0 + kappa * z;
        let r = points.respond(law, j, &strain, |l, e, s| match nonlocal {
            None => plane_stress::update(l, e, s),
            Some(nl) => nonlocal::update(l, e, s, nl.averaged[j], nl.self_share[j]),
        });
        n += r.stress * w;
        m += r.stress * (w * z);
        let c = if secant { r.secant } else { r.tangent };
        a += c * w;
        b += c * (w * z);
        d += c * (w * z * z);
        dissipation += w * r.dissipation;
    }
    SectionResponse { n, m, tangent: block_section(&a, &b, &d), dissipation }
}

/// In-plane plane-stress elastic matrix E/(1−ν²) [[1, ν, 0], [ν, 1, 0], [0, 0, (1−ν)/2]].
pub fn plane_stress_matrix(e: f64, nu: f64) -> Matrix3<f64> {
    let f = e / (1.0 - nu * nu);
    Matrix3::new(f, f * nu, 0.0, f * nu, f, 0.0, 0.0, 0.0, f * 0.5 * (1.0 - nu))
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Simpson weights sum to t and integrate z² exactly: Σ w z² = t³/12 (1e-15 relative).
    #[test]
    fn simpson_moments() {
        for n in [1, 2, 7, 10] {
            let t = 0.37;
            let r = ThicknessRule::simpson(t, n);
            assert_eq!(r.len(), 2 * n + 1);
            let s0: f64 = r.weights().iter().sum();
            let s1: f64 = r.z().iter().zip(r.weights()).map(|(z, w)| z * w).sum();
            let s2: f64 = r.z().iter().zip(r.weights()).map(|(z, w)| z * z * w).sum();
            assert!((s0 - t).abs() < 1e-15 * t);
            assert!(s1.abs() < 1e-16);
            assert!((s2 - t.powi(3) / 12.0).abs() < 1e-15 * t.powi(3));
            assert_eq!((r.z()[0], r.z()[2 * n]), (-t / 2.0, t / 2.0));
        }
    }
}
