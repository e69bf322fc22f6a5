//! The lattice: one Euler–Bernoulli beam per pair of cells sharing a Voronoi edge (paper §2.1).
//!
//! The beam joins the two seeds `s_i → s_j`: length `ℓ = |s_j − s_i|`, unit vector
//! `n = (s_j − s_i)/ℓ`, `t = e_z × n = (−n_y, n_x)`. Because the shared edge lies on the
//! perpendicular bisector of the seeds, `n` is normal to it. Section `A = L_f t_z` with `L_f` the
//! facet (shared edge) length; inertia from [`beam_inertia`].
//!
//! The particles' DOF live at the centroids, the beam ends at the seeds: the arms `r_i = s_i − c_i`,
//! `r_j = s_j − c_j` are stored, so an end moves as `u_c + θ e_z × r` (small rotations) or
//! `u_c + (R(θ) − 1) r` (exact), and a beam end force `F` on stone `i` gives the moment
//! `r_i × F` about the centroid in addition to the beam end moment.
use crate::dem::polygon::P2;

/// A cohesive beam between particles `i < j`.
#[derive(Clone, Debug, PartialEq)]
pub struct Beam {
    /// First particle (the lower index).
    pub i: usize,
    /// Second particle.
    pub j: usize,
    /// Seed distance `ℓ` (m).
    pub length: f64,
    /// Unit vector `n` from seed `i` to seed `j`.
    pub normal: P2,
    /// Unit vector `t = e_z × n = (−n_y, n_x)`.
    pub tangent: P2,
    /// The shared edge's end points, counter-clockwise around particle `i` (m).
    pub facet: [P2; 2],
    /// Facet length `L_f` (m).
    pub facet_length: f64,
    /// Facet midpoint (m).
    pub facet_midpoint: P2,
    /// Section area `A = L_f t_z` (m²).
    pub area: f64,
    /// Section inertia `I` from [`beam_inertia`] (m⁴).
    pub inertia: f64,
    /// Seed `i` minus centroid `i` (m).
    pub arm_i: P2,
    /// Seed `j` minus centroid `j` (m).
    pub arm_j: P2,
}

/// The beam's second moment of area, `I = α · t_z · L_f³ / 12` (m⁴).
///
/// **The definition of α is uncertain in the literature.** Here α scales the inertia of the
/// rectangular section `L_f × t_z` bent in the plane (`t_z L_f³/12`); some lattice papers instead
/// write `I = α A ℓ²/12` or put α on the shear/rotation stiffness. α is calibrated against the
/// measured Poisson ratio (paper §2.1; paper's Table 1: α = 0.80), so whatever its exact meaning, this
/// is the only place that turns it into an inertia.
pub fn beam_inertia(alpha: f64, thickness: f64, facet_length: f64) -> f64 {
    alpha * thickness * facet_length.powi(3) / 12.0
}

impl Beam {
    /// The beam between seeds `si`, `sj` (particles `i < j`, centroids `ci`, `cj`) across the facet
    /// `[fa, fb]`.
    #[allow(clippy::too_many_arguments)]
    pub fn new(i: usize, j: usize, si: P2, sj: P2, ci: P2, cj: P2, facet: [P2; 2], thickness: f64, alpha: f64) -> Beam {
        let d = [sj[0] - si[0], sj[1] - si[1]];
        let length = d[0].hypot(d[1]);
        let normal = [d[0] / length, d[1] / length];
        let [fa, fb] = facet;
        let facet_length = (fb[0] - fa[0]).hypot(fb[1] - fa[1]);
        Beam {
            i,
            j,
            length,
            normal,
            tangent: [-normal[1], normal[0]],
            facet,
            facet_length,
            facet_midpoint: [0.5 * (fa[0] + fb[0]), 0.5 * (fa[1] + fb[1])],
            area: facet_length * thickness,
            inertia: beam_inertia(alpha, thickness, facet_length),
            arm_i: [si[0] - ci[0], si[1] - ci[1]],
            arm_j: [sj[0] - cj[0], sj[1] - cj[1]],
        }
    }

    /// `|n · e_f|` with `e_f` the unit facet direction: 0 when the beam is normal to its facet.
    pub fn facet_skew(&self) -> f64 {
        let [fa, fb] = self.facet;
        let e = [(fb[0] - fa[0]) / self.facet_length, (fb[1] - fa[1]) / self.facet_length];
        (self.normal[0] * e[0] + self.normal[1] * e[1]).abs()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn beam_across_a_vertical_facet() {
        // Seeds (0.25, 0.5), (0.75, 0.5), facet x = ½ from (½, 0) to (½, 1), t_z = 0.5, α = 0.8:
        // ℓ = ½, n = (1, 0), t = (0, 1), A = 0.5, I = 0.8 · 0.5 · 1/12 = 1/30.
        let b = Beam::new(0, 1, [0.25, 0.5], [0.75, 0.5], [0.25, 0.5], [0.7, 0.5], [[0.5, 0.0], [0.5, 1.0]], 0.5, 0.8);
        assert_eq!((b.length, b.normal, b.tangent), (0.5, [1.0, 0.0], [0.0, 1.0]));
        assert_eq!((b.area, b.facet_midpoint), (0.5, [0.5, 0.5]));
        assert!((b.inertia - 1.0 / 30.0).abs() < 1e-16);
        assert_eq!(b.arm_i, [0.0, 0.0]);
        assert!((b.arm_j[0] - 0.05).abs() < 1e-15);
        assert_eq!(b.facet_skew(), 0.0);
    }
}
