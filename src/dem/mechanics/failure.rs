//! The beam failure criterion (paper §2.1, eq. 2) and the load fraction at which it is reached.
//!
//! ```text
//!   P = ε/ε_cr + |θ_i − θ_j|/θ_cr ,   ε = δn/ℓ  (signed: compression lowers P)
//! ```
//!
//! A beam breaks when `P ≥ 1`. Both `δn` (end-point elongation, [`BeamGeom::delta_n`]) and
//! `θ_i − θ_j` are linear in the particle DOFs and invariant under rigid motions.
//!
//! **Failure mode.** Tension-dominated if `ε/ε_cr ≥ |θ_i − θ_j|/θ_cr`, otherwise rotation/shear.
//!
//! **Crossing along an increment.** For `q(λ) = q₀ + λ Δq`: `ε(λ) = ε₀ + λ Δε`,
//! `φ(λ) = θ_i − θ_j = φ₀ + λ Δφ`, so
//!
//! ```text
//!   P(λ) = (ε₀ + λΔε)/ε_cr + |φ₀ + λΔφ|/θ_cr
//! ```
//!
//! is piecewise linear with at most one kink, at `λ_k = −φ₀/Δφ`. On each piece `[a, b]` (split at
//! `λ_k` when `0 < λ_k < 1`) the slope is `s = Δε/ε_cr + σ Δφ/θ_cr` with `σ` the sign of `φ` on the
//! piece; the first piece with `P(b) ≥ 1` holds the crossing `λ = a + (1 − P(a))/s`. The smallest
//! such λ is returned (the solver scales its increment by it).

use super::beam::BeamGeom;
use super::thresholds::Thresholds;

/// Which term of the criterion dominates at failure.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum FailureMode {
    /// `ε/ε_cr ≥ |θ_i − θ_j|/θ_cr`: an opening (tensile) crack.
    Tension,
    /// The rotation term dominates: a rotation/shear crack.
    Shear,
}

/// The two terms of the criterion, `(ε/ε_cr, |θ_i − θ_j|/θ_cr)`.
pub fn failure_terms(geom: &BeamGeom, thr: &Thresholds, q_i: [f64; 3], q_j: [f64; 3]) -> (f64, f64) {
    let eps = geom.delta_n(q_i, q_j) / geom.ell;
    (eps / thr.eps_cr, (q_i[2] - q_j[2]).abs() / thr.theta_cr)
}

/// The failure index `P = ε/ε_cr + |θ_i − θ_j|/θ_cr` (breaks at `P ≥ 1`).
pub fn failure_index(geom: &BeamGeom, thr: &Thresholds, q_i: [f64; 3], q_j: [f64; 3]) -> f64 {
    let (a, b) = failure_terms(geom, thr, q_i, q_j);
    a + b
}

/// Tension if the strain term is at least the rotation term, otherwise shear.
pub fn failure_mode(geom: &BeamGeom, thr: &Thresholds, q_i: [f64; 3], q_j: [f64; 3]) -> FailureMode {
    let (a, b) = failure_terms(geom, thr, q_i, q_j);
    if a >= b {
        FailureMode::Tension
    } else {
        FailureMode::Shear
    }
}

/// The smallest `λ ∈ [0, 1]` with `P(q₀ + λΔq) = 1`, or `None` if `P < 1` on all of `[0, 1]`.
/// `Some(0.0)` means the beam is already at or past failure at `q₀`.
pub fn failure_lambda(
    geom: &BeamGeom,
    thr: &Thresholds,
    q0_i: [f64; 3],
    q0_j: [f64; 3],
    dq_i: [f64; 3],
    dq_j: [f64; 3],
) -> Option<f64> {
    first_crossing(
        geom.delta_n(q0_i, q0_j) / geom.ell,
        geom.delta_n(dq_i, dq_j) / geom.ell,
        q0_i[2] - q0_j[2],
        dq_i[2] - dq_j[2],
        thr,
    )
}

/// The smallest `λ ∈ [0, 1]` with `(eps0 + λ deps)/ε_cr + |phi0 + λ dphi|/θ_cr = 1` (see the module
/// docs), or `None` if the index stays below 1 on `[0, 1]`.
pub fn first_crossing(eps0: f64, deps: f64, phi0: f64, dphi: f64, thr: &Thresholds) -> Option<f64> {
    let p = |l: f64| (eps0 + l * deps) / thr.eps_cr + (phi0 + l * dphi).abs() / thr.theta_cr;
    let kink = if dphi != 0.0 { -phi0 / dphi } else { f64::NAN };
    let (split, whole) = ([(0.0, kink), (kink, 1.0)], [(0.0, 1.0)]);
    let pieces: &[(f64, f64)] = if kink > 0.0 && kink < 1.0 { &split } else { &whole };
    for &(a, b) in pieces {
        let (pa, pb) = (p(a), p(b));
        if pa >= 1.0 {
            return Some(a);
        }
        if pb >= 1.0 {
            let sigma = (phi0 + 0.5 * (a + b) * dphi).signum();
            let slope = deps / thr.eps_cr + sigma * dphi / thr.theta_cr;
            // slope > 0 since P rises from below 1 to at least 1 on this piece.
            return Some((a + (1.0 - pa) / slope).clamp(a, b));
        }
    }
    None
}

#[cfg(test)]
mod tests {
    use super::*;

    const THR: Thresholds = Thresholds { eps_cr: 1e-4, theta_cr: 1e-3 };

    fn close(a: Option<f64>, b: f64, tol: f64) -> bool {
        a.is_some_and(|a| (a - b).abs() <= tol)
    }

    #[test]
    fn index_and_mode_by_hand() {
        // Beam along x, ℓ = 0.5, no offsets. Stretch 2.5e-5 → ε = 5e-5 → 0.5; θ_i − θ_j = −3e-4 →
        // 0.3; P = 0.8 (tolerance 1e-14), tension-dominated.
        let g = BeamGeom { ell: 0.5, n: [1.0, 0.0], r_i: [0.0; 2], r_j: [0.0; 2], area: 1.0, inertia: 1.0 };
        let (qi, qj) = ([0.0, 0.0, 1e-4], [2.5e-5, 0.0, 4e-4]);
        assert!((failure_index(&g, &THR, qi, qj) - 0.8).abs() < 1e-14);
        assert_eq!(failure_mode(&g, &THR, qi, qj), FailureMode::Tension);
        // Compression lowers P: −2.5e-5 → −0.5 + 0.3 = −0.2; the rotation term dominates.
        let qj = [-2.5e-5, 0.0, 4e-4];
        assert!((failure_index(&g, &THR, qi, qj) + 0.2).abs() < 1e-14);
        assert_eq!(failure_mode(&g, &THR, qi, qj), FailureMode::Shear);
    }

    #[test]
    fn crossing_without_kink() {
        // P(λ) = 2λ (ε = 2e-4 λ): λ = 0.5 exactly (tolerance 1e-15).
        assert!(close(first_crossing(0.0, 2e-4, 0.0, 0.0, &THR), 0.5, 1e-15));
        // P(λ) = 0.2 + 0.3λ + |0.1 + 0.5λ| (φ keeps its sign): 0.3 + 0.8λ = 1 → λ = 0.875.
        assert!(close(first_crossing(0.2e-4, 0.3e-4, 1e-4, 5e-4, &THR), 0.875, 1e-15));
        // Never reaches 1: P(1) = 0.9.
        assert_eq!(first_crossing(0.0, 0.9e-4, 0.0, 0.0, &THR), None);
        // Already failed.
        assert_eq!(first_crossing(1.1e-4, -1e-4, 0.0, 0.0, &THR), Some(0.0));
        // Exactly at λ = 1.
        assert!(close(first_crossing(0.0, 1e-4, 0.0, 0.0, &THR), 1.0, 0.0));
    }

    #[test]
    fn crossing_after_the_kink() {
        // P(λ) = 0.5λ + |0.3 − λ|: 0.3 at 0, 0.15 at the kink λ = 0.3, then 1.5λ − 0.3 = 1
        // → λ = 13/15 (tolerance 1e-15).
        let l = first_crossing(0.0, 0.5e-4, 3e-4, -1e-3, &THR);
        assert!(close(l, 13.0 / 15.0, 1e-15), "{l:?}");
    }

    #[test]
    fn crossing_before_the_kink() {
        // P(λ) = 2λ + |0.8 − λ| = 0.8 + λ on [0, 0.8]: λ = 0.2 (tolerance 1e-15).
        let l = first_crossing(0.0, 2e-4, 8e-4, -1e-3, &THR);
        assert!(close(l, 0.2, 1e-15), "{l:?}");
        // Kink where P dips but never reaches 1: P = 0.1λ + |0.5 − λ|, P(1) = 0.6.
        assert_eq!(first_crossing(0.0, 0.1e-4, 5e-4, -1e-3, &THR), None);
    }

    #[test]
    fn crossing_along_a_particle_increment() {
        // Beam along x, ℓ = 1, offsets 0. Increment: j moves +x by 5e-5 and i rotates by −1e-3
        // from θ_i = 2e-4: P(λ) = 0.5λ + |0.2 − λ| → kink at 0.2, then 1.5λ − 0.2 = 1 → λ = 0.8.
        let g = BeamGeom { ell: 1.0, n: [1.0, 0.0], r_i: [0.0; 2], r_j: [0.0; 2], area: 1.0, inertia: 1.0 };
        let l = failure_lambda(&g, &THR, [0.0, 0.0, 2e-4], [0.0; 3], [0.0, 0.0, -1e-3], [5e-5, 0.0, 0.0]);
        assert!(close(l, 0.8, 1e-15), "{l:?}");
        let lam = l.unwrap_or(f64::NAN);
        let p = failure_index(&g, &THR, [0.0, 0.0, 2e-4 - lam * 1e-3], [lam * 5e-5, 0.0, 0.0]);
        assert!((p - 1.0).abs() < 1e-14);
    }
}
