//! One rigid stone: its convex cell and the quantities mechanics needs.
//!
//! The rigid-body reference point is the cell's centroid `c`; the stone rotates about it. Its
//! equivalent diameter is `D = 2 sqrt(A/π)` (the disk of the same area; paper §2.1), used by the
//! contact length `ℓ_c`. The polar moment `J = ∫ |x − c|² dA` (m⁴, per unit thickness) gives the
//! rotational inertia `ρ t_z J` with the mass `ρ t_z A`.
use crate::dem::polygon::{Polygon, P2};

/// A rigid stone.
#[derive(Clone, Debug, PartialEq)]
pub struct Particle {
    /// Its cell, vertices counter-clockwise.
    pub polygon: Polygon,
    /// The Voronoi seed (the beams' end point).
    pub seed: P2,
    /// The cell centroid: the reference point of the 3 DOF `(u_x, u_y, θ)` (m).
    pub centroid: P2,
    /// Cell area `A` (m²).
    pub area: f64,
    /// Equivalent diameter `D = 2 sqrt(A/π)` (m).
    pub diameter: f64,
    /// Polar second moment about the centroid `J = ∫ |x − c|² dA` (m⁴).
    pub polar_moment: f64,
}

impl Particle {
    /// The particle of a cell and its seed.
    pub fn new(polygon: Polygon, seed: P2) -> Particle {
        let area = polygon.area();
        Particle {
            centroid: polygon.centroid(),
            diameter: 2.0 * (area / std::f64::consts::PI).sqrt(),
            polar_moment: polygon.polar_moment(),
            area,
            seed,
            polygon,
        }
    }

    /// The seed's offset from the centroid, `s − c` (m): a beam end's lever arm.
    pub fn seed_arm(&self) -> P2 {
        [self.seed[0] - self.centroid[0], self.seed[1] - self.centroid[1]]
    }

    /// Where a point `p` of the stone goes under the rigid motion `(u_x, u_y, θ)` of the centroid,
    /// exact for finite rotations: `c + u + R(θ)(p − c)`.
    pub fn moved_point(&self, p: P2, u: [f64; 3]) -> P2 {
        let (s, co) = u[2].sin_cos();
        let r = [p[0] - self.centroid[0], p[1] - self.centroid[1]];
        [self.centroid[0] + u[0] + co * r[0] - s * r[1], self.centroid[1] + u[1] + s * r[0] + co * r[1]]
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn unit_square_particle() {
        // Unit square: A = 1, D = 2/√π = 1.1283791670955126, J = (1 + 1)/12, centroid (½, ½).
        let p = Particle::new(Polygon::rectangle(0.0, 0.0, 1.0, 1.0), [0.25, 0.5]);
        assert!((p.diameter - std::f64::consts::FRAC_2_SQRT_PI).abs() < 1e-15);
        assert!((p.polar_moment - 1.0 / 6.0).abs() < 1e-15);
        assert_eq!(p.seed_arm(), [-0.25, 0.0]);
        // Quarter turn about the centroid: the seed (¼, ½) goes to (½, ¼).
        let q = p.moved_point(p.seed, [0.0, 0.0, std::f64::consts::FRAC_PI_2]);
        assert!((q[0] - 0.5).abs() < 1e-15 && (q[1] - 0.25).abs() < 1e-15, "{q:?}");
    }
}
