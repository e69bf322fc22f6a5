//! The base reactions of a time history, per step: the force the ground exerts on the structure,
//! summed per global direction (`reaction_x`, `reaction_y`: the base shear; `reaction_z`: the
//! vertical reaction) [N],
//!
//! ```text
//!   R_d = Σ_supports (f_int)_d = − Σ_free (f_int + C v)_d
//! ```
//!
//! The equality holds because a rigid translation strains no element: every element's internal
//! forces sum to zero along each axis, so the forces the elements put on the supports are minus
//! those on the free DOFs (`f_int` is zero on fixed DOFs in the system's vectors). The Rayleigh
//! damping forces `C v` are included: their stiffness part passes through the supports in the
//! same way, and their mass part acts on every node as a dashpot to the ground. By equilibrium
//! of the free DOFs, `R = Σ M a_abs − f_static` summed per direction: the inertia forces less the
//! static loads (gravity, nodal loads). The mass of the support nodes themselves, which the
//! ground moves directly, is not counted.
//!
//! Under a static load alone (gravity, at step 0, or no ground motion) `R = −Σ f_static`: the
//! reactions balance the applied loads, as `linear_static`'s `reaction_sum` does.

/// The CSV columns, after the monitors'.
pub const HEADER: &str = ",reaction_x,reaction_y,reaction_z";

/// The columns of the base shear, whose peaks the summary reports.
pub const SHEAR_COLUMNS: [&str; 2] = ["reaction_x", "reaction_y"];

/// This rank's share of `R` from its owned entries of `f_int` and `C v` (6 per owned node).
pub fn local_reaction(f_int: &[f64], cv: &[f64]) -> [f64; 3] {
    let mut r = [0.0; 3];
    for (f, c) in f_int.chunks_exact(6).zip(cv.chunks_exact(6)) {
        for d in 0..3 {
            r[d] -= f[d] + c[d];
        }
    }
    r
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Two nodes' forces: the sum per direction, negated, rotations left out.
    #[test]
    fn the_reaction_is_minus_the_free_forces_summed() {
        let f = [1.0, 2.0, 3.0, 9.0, 9.0, 9.0, 0.5, -1.0, 0.0, 9.0, 9.0, 9.0];
        let c = [0.25, 0.0, 0.0, 7.0, 7.0, 7.0, 0.0, 0.0, -1.0, 7.0, 7.0, 7.0];
        assert_eq!(local_reaction(&f, &c), [-1.75, -1.0, -2.0]);
    }
}
