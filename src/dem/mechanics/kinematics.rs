//! Rigid-particle kinematics: how a point attached to a particle moves, and how a force at that
//! point acts on the particle.
//!
//! A particle has 3 DOF `q = (u_x, u_y, θ)` at its reference point `c` (the centroid). A point
//! `p = c + r` attached rigidly to it moves, for small rotations (linear kinematics: the solver is
//! quasi-static and small-displacement), by
//!
//! ```text
//!   u_p = u_c + θ e_z × r = [ 1  0  −r_y ] q  =  T(r) q          (2×3 map)
//!                           [ 0  1   r_x ]
//! ```
//!
//! By virtual work (`f·δu_p = (Tᵀ f)·δq`), a force `f` applied at `p` is the generalized force
//! `Tᵀ f = (f_x, f_y, r × f)` on the particle, with `r × f = r_x f_y − r_y f_x` its moment about
//! `c`. A pair quantity (beam end, contact point) of stiffness `K_p` in the point DOFs becomes
//! `Tᵀ K_p T` in the particle DOFs.

use nalgebra::SMatrix;

/// 2D cross product (z component) `a × b = a_x b_y − a_y b_x`.
pub fn cross(a: [f64; 2], b: [f64; 2]) -> f64 {
    a[0] * b[1] - a[1] * b[0]
}

/// Dot product.
pub fn dot(a: [f64; 2], b: [f64; 2]) -> f64 {
    a[0] * b[0] + a[1] * b[1]
}

/// `e_z × a = (−a_y, a_x)`: `a` turned by +90°.
pub fn perp(a: [f64; 2]) -> [f64; 2] {
    [-a[1], a[0]]
}

/// The 2×3 map `T(r)` from particle DOFs `(u_x, u_y, θ)` to the displacement of the point at
/// offset `r` from the reference point.
pub fn point_map(r: [f64; 2]) -> SMatrix<f64, 2, 3> {
    SMatrix::<f64, 2, 3>::new(1.0, 0.0, -r[1], 0.0, 1.0, r[0])
}

/// Displacement `u_c + θ e_z × r` of the point at offset `r` of a particle with DOFs `q`.
pub fn point_displacement(q: [f64; 3], r: [f64; 2]) -> [f64; 2] {
    [q[0] - q[2] * r[1], q[1] + q[2] * r[0]]
}

/// Generalized force `T(r)ᵀ f = (f_x, f_y, r × f)` of a force `f` applied at offset `r`.
pub fn generalized_force(f: [f64; 2], r: [f64; 2]) -> [f64; 3] {
    [f[0], f[1], cross(r, f)]
}

/// Particle DOFs of the rigid motion "rotate by `theta` about `about`, then translate by `u`"
/// (linearized), for a particle with reference point `reference`:
/// `(u + θ e_z × (reference − about), θ)`.
pub fn rigid_motion_dofs(about: [f64; 2], u: [f64; 2], theta: f64, reference: [f64; 2]) -> [f64; 3] {
    let d = [reference[0] - about[0], reference[1] - about[1]];
    [u[0] - theta * d[1], u[1] + theta * d[0], theta]
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn point_map_matches_point_displacement_and_virtual_work() {
        // Arbitrary values; identities are exact up to round-off (tolerance 1e-15 relative).
        let (q, r, f) = ([0.3, -0.2, 0.05], [1.5, -0.7], [2.0, 3.0]);
        let t = point_map(r);
        let up = t * nalgebra::Vector3::from(q);
        let u = point_displacement(q, r);
        assert!((up[0] - u[0]).abs() < 1e-15 && (up[1] - u[1]).abs() < 1e-15);
        // Virtual work: f·u_p = (Tᵀ f)·q.
        let g = generalized_force(f, r);
        let lhs = dot(f, u);
        let rhs = g[0] * q[0] + g[1] * q[1] + g[2] * q[2];
        assert!((lhs - rhs).abs() < 1e-15 * lhs.abs().max(1.0));
        // Moment of a force (0, 1) at (1, 0): +1 (counter-clockwise).
        assert_eq!(generalized_force([0.0, 1.0], [1.0, 0.0])[2], 1.0);
    }

    #[test]
    fn rigid_motion_moves_every_point_consistently() {
        // A point p = c + r of a particle moved rigidly about O must move by u + θ e_z × (p − O).
        let (o, u, th) = ([0.4, -1.0], [0.01, 0.02], 0.003);
        let (c, r) = ([2.0, 1.0], [0.5, 0.25]);
        let q = rigid_motion_dofs(o, u, th, c);
        let got = point_displacement(q, r);
        let p = [c[0] + r[0], c[1] + r[1]];
        let want = [u[0] - th * (p[1] - o[1]), u[1] + th * (p[0] - o[0])];
        assert!((got[0] - want[0]).abs() < 1e-17 && (got[1] - want[1]).abs() < 1e-17);
    }
}
