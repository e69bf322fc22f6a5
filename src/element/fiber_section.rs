//! [`FiberSection`]: a rectangular section cut into a grid of fibers, for the fiber beam
//! ([`FiberBeam3d`](super::FiberBeam3d)).
//!
//! # Grid
//! Width b along the local y axis, height h along the local z axis (the axes of
//! [`LocalFrame`](super::LocalFrame)), centred on the member axis, cut into `ny × nz` equal
//! rectangles; each fiber sits at the centre of its rectangle and carries its area:
//!
//! ```text
//!   y_i = −b/2 + (i + ½) b/ny,   z_j = −h/2 + (j + ½) h/nz,   A_f = b h / (ny nz)
//! ```
//!
//! # Elastic stiffness of the grid (closed form, the reference of the section test)
//! With every fiber elastic (modulus E) the section stiffness is diagonal (the grid is symmetric):
//! ```text
//!   EA  = E b h                                      (exact)
//!   EIz = E Σ A_f y² = E h b³/12 · (1 − 1/ny²)        (bending in the x–y plane)
//!   EIy = E Σ A_f z² = E b h³/12 · (1 − 1/nz²)        (bending in the x–z plane)
//! ```
//! (the midpoint sum of y² over ny equal strips misses each strip's own inertia, b³/(12 ny²) per
//! unit h b); the relative error −1/n² is 1% at n = 10 and 0.25% at n = 20.
//!
//! # Torsion and mass
//! Torsion is elastic (the fibers carry axial stress only): G J with G = E/(2(1 + ν)) and J given
//! (`torsion_constant`) or the rectangle formula of Roark (*Formulas for Stress and Strain*,
//! table 10.7, case 4; within 4% of the exact series), with a ≥ c the long and short sides:
//! `J = a c³ [1/3 − 0.21 (c/a)(1 − c⁴/(12 a⁴))]`.
//! Mass from the continuum section: ρ b h per length plus the non-structural mass, and the polar
//! moment Ip = b h (b² + h²)/12 for the rotary inertia about the axis.
//!
//! # Job-file form (TOML)
//! ```toml
//! [sections.pilaster]
//! type = "fiber"
//! width = 0.6              # m, along local y
//! height = 0.8             # m, along local z
//! ny = 12                  # fibers along y
//! nz = 16                  # fibers along z
//! integration_points = 2   # Gauss points along the element (2..=5), default 2
//! nonstructural_mass = 0.0 # kg/m, default 0
//! # torsion_constant = 0.02  # m^4, default: Roark's rectangle formula
//! ```

use super::error::ElementError;
use super::shell::ShellMaterial;

/// Fibers along one side of the grid: at least 2 (a single fiber across a side has no second
/// moment about the axis along that side, I = A·0², and leaves a bending mechanism), at most this.
pub const MAX_FIBERS_PER_SIDE: usize = 200;
/// Default number of Gauss points along a fiber beam.
pub const DEFAULT_INTEGRATION_POINTS: usize = 2;

/// The material of the fibers: the same enum as the shell layers' (elastic, or the damage law,
/// here in its uniaxial form).
pub type FiberMaterial = ShellMaterial;

/// One fiber: position in the section (local y, z) and area.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Fiber {
    /// Local y coordinate (m).
    pub y: f64,
    /// Local z coordinate (m).
    pub z: f64,
    /// Area (m²).
    pub area: f64,
}

/// A rectangular fiber section (module docs). SI units.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct FiberSection {
    /// Width b along local y (m).
    pub width: f64,
    /// Height h along local z (m).
    pub height: f64,
    /// Fibers along y.
    pub ny: usize,
    /// Fibers along z.
    pub nz: usize,
    /// Gauss–Legendre points along the element (2..=5).
    pub integration_points: usize,
    /// The fibers' material.
    pub material: FiberMaterial,
    /// Mass density ρ (kg/m³), ≥ 0.
    pub density: f64,
    /// Non-structural mass per length (kg/m), ≥ 0.
    pub nonstructural_mass: f64,
    /// Saint-Venant torsion constant J (m⁴); `None`: Roark's rectangle formula.
    pub torsion_constant: Option<f64>,
}

impl FiberSection {
    /// Check every quantity; the error names the first offending one. The damage parameters are
    /// checked when the law is set up for an element (they need the element length).
    pub fn validate(&self) -> Result<(), ElementError> {
        let positive = ElementError::positive;
        let non_negative = ElementError::non_negative;
        positive("width", self.width)?;
        positive("height", self.height)?;
        for (quantity, value, min, max) in [
            ("ny", self.ny, 2, MAX_FIBERS_PER_SIDE),
            ("nz", self.nz, 2, MAX_FIBERS_PER_SIDE),
            ("integration_points", self.integration_points, 2, 5),
        ] {
            if !(min..=max).contains(&value) {
                return Err(ElementError::InvalidCount { quantity, value, min, max });
            }
        }
        non_negative("density", self.density)?;
        non_negative("nonstructural_mass", self.nonstructural_mass)?;
        if let Some(j) = self.torsion_constant {
            positive("torsion_constant", j)?;
        }
        positive("E", self.material.e())?;
        let nu = self.material.nu();
        if !(nu.is_finite() && nu > -1.0 && nu < 0.5) {
            return Err(ElementError::InvalidSection { quantity: "nu", value: nu, expected: "in (-1, 0.5)" });
        }
        Ok(())
    }

    /// The fibers, y-major (fiber `i nz + j` at y_i, z_j; module docs).
    pub fn fibers(&self) -> Vec<Fiber> {
        let (b, h) = (self.width, self.height);
        let area = b * h / (self.ny * self.nz) as f64;
        let mut out = Vec::with_capacity(self.ny * self.nz);
        for i in 0..self.ny {
            for j in 0..self.nz {
                out.push(Fiber {
                    y: -0.5 * b + (i as f64 + 0.5) * b / self.ny as f64,
                    z: -0.5 * h + (j as f64 + 0.5) * h / self.nz as f64,
                    area,
                });
            }
        }
        out
    }

    /// Area b h (m²).
    pub fn area(&self) -> f64 {
        self.width * self.height
    }

    /// Second moment of the fiber grid about local z, h b³/12 (1 − 1/ny²) (m⁴; module docs).
    pub fn iz_fibers(&self) -> f64 {
        let n = self.ny as f64;
        self.height * self.width.powi(3) / 12.0 * (1.0 - 1.0 / (n * n))
    }

    /// Second moment of the fiber grid about local y, b h³/12 (1 − 1/nz²) (m⁴; module docs).
    pub fn iy_fibers(&self) -> f64 {
        let n = self.nz as f64;
        self.width * self.height.powi(3) / 12.0 * (1.0 - 1.0 / (n * n))
    }

    /// Polar moment of the continuum rectangle b h (b² + h²)/12 (m⁴), for the rotary inertia.
    pub fn polar_moment(&self) -> f64 {
        self.area() * (self.width * self.width + self.height * self.height) / 12.0
    }

    /// Torsion constant J: the given one, or Roark's rectangle formula (module docs).
    pub fn torsion_constant(&self) -> f64 {
        self.torsion_constant.unwrap_or_else(|| {
            let (a, c) = if self.width >= self.height { (self.width, self.height) } else { (self.height, self.width) };
            a * c.powi(3) * (1.0 / 3.0 - 0.21 * (c / a) * (1.0 - c.powi(4) / (12.0 * a.powi(4))))
        })
    }

    /// Line mass ρ b h + non-structural mass (kg/m).
    pub fn line_mass(&self) -> f64 {
        self.density * self.area() + self.nonstructural_mass
    }
}

/// Gauss–Legendre points and weights on [0, 1] (Abramowitz & Stegun, table 25.4, mapped), for
/// `n` in 2..=5; weights sum to 1.
pub fn gauss_points(n: usize) -> Vec<(f64, f64)> {
    let table: &[(f64, f64)] = match n {
        2 => &[(-0.577_350_269_189_625_8, 1.0), (0.577_350_269_189_625_8, 1.0)],
        3 => &[(-0.774_596_669_241_483_4, 5.0 / 9.0), (0.0, 8.0 / 9.0), (0.774_596_669_241_483_4, 5.0 / 9.0)],
        4 => &[
            (-0.861_136_311_594_052_6, 0.347_854_845_137_453_9),
            (-0.339_981_043_584_856_3, 0.652_145_154_862_546_1),
            (0.339_981_043_584_856_3, 0.652_145_154_862_546_1),
            (0.861_136_311_594_052_6, 0.347_854_845_137_453_9),
        ],
        _ => &[
            (-0.906_179_845_938_664, 0.236_926_885_056_189_1),
            (-0.538_469_310_105_683_1, 0.478_628_670_499_366_5),
            (0.0, 0.568_888_888_888_888_9),
            (0.538_469_310_105_683_1, 0.478_628_670_499_366_5),
            (0.906_179_845_938_664, 0.236_926_885_056_189_1),
        ],
    };
    table.iter().map(|&(x, w)| (0.5 * (x + 1.0), 0.5 * w)).collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    fn section(ny: usize, nz: usize) -> FiberSection {
        FiberSection {
            width: 0.3,
            height: 0.5,
            ny,
            nz,
            integration_points: 2,
            material: FiberMaterial::Elastic { e: 3e9, nu: 0.2 },
            density: 2000.0,
            nonstructural_mass: 0.0,
            torsion_constant: None,
        }
    }

    /// Σ A_f = b h, Σ A_f y = Σ A_f z = 0 and the second moments equal the closed forms of the
    /// module docs (1e-12 relative: round-off of the sums).
    #[test]
    fn grid_moments_match_the_closed_form() {
        for (ny, nz) in [(2, 2), (3, 7), (10, 20)] {
            let s = section(ny, nz);
            let f = s.fibers();
            assert_eq!(f.len(), ny * nz);
            let a: f64 = f.iter().map(|f| f.area).sum();
            let sy: f64 = f.iter().map(|f| f.area * f.y).sum();
            let sz: f64 = f.iter().map(|f| f.area * f.z).sum();
            let iz: f64 = f.iter().map(|f| f.area * f.y * f.y).sum();
            let iy: f64 = f.iter().map(|f| f.area * f.z * f.z).sum();
            assert!((a - s.area()).abs() < 1e-12 * s.area());
            assert!(sy.abs() < 1e-12 * s.area() && sz.abs() < 1e-12 * s.area());
            assert!((iz - s.iz_fibers()).abs() <= 1e-12 * s.iz_fibers().max(1e-30) + 1e-20);
            assert!((iy - s.iy_fibers()).abs() <= 1e-12 * s.iy_fibers().max(1e-30) + 1e-20);
        }
    }

    /// Gauss–Legendre with n points integrates ξ^k exactly for k ≤ 2n − 1: ∫₀¹ ξ^k = 1/(k+1)
    /// (1e-14).
    #[test]
    fn gauss_points_are_exact_to_their_degree() {
        for n in 2..=5 {
            let g = gauss_points(n);
            for k in 0..2 * n {
                let q: f64 = g.iter().map(|&(x, w)| w * x.powi(k as i32)).sum();
                assert!((q - 1.0 / (k as f64 + 1.0)).abs() < 1e-14, "n={n} k={k}: {q}");
            }
        }
    }

    /// Roark's formula for a square (a = c) gives 0.14083 a⁴ against the exact series value
    /// 0.1406 a⁴ (Timoshenko & Goodier, *Theory of Elasticity*, §109): within 0.5%; a thin strip tends to a c³/3 (5% at a = 20 c, where the
    /// correction −0.21 c/a is 6.3% of 1/3).
    #[test]
    fn torsion_constant_of_rectangles() {
        let sq = FiberSection { width: 0.4, height: 0.4, ..section(2, 2) };
        let j = sq.torsion_constant();
        assert!((j / 0.4f64.powi(4) - 0.1406).abs() < 0.005 * 0.1406, "{}", j / 0.4f64.powi(4));
        let strip = FiberSection { width: 2.0, height: 0.1, ..section(2, 2) };
        let thin = 2.0 * 0.1f64.powi(3) / 3.0;
        assert!((strip.torsion_constant() - thin).abs() < 0.07 * thin);
        let given = FiberSection { torsion_constant: Some(1.5e-3), ..section(2, 2) };
        assert_eq!(given.torsion_constant(), 1.5e-3);
    }

    #[test]
    fn bad_values_are_named() {
        let cases: [(&str, FiberSection); 6] = [
            ("width", FiberSection { width: 0.0, ..section(2, 2) }),
            ("height", FiberSection { height: f64::NAN, ..section(2, 2) }),
            ("ny", section(0, 2)),
            ("integration_points", FiberSection { integration_points: 1, ..section(2, 2) }),
            ("torsion_constant", FiberSection { torsion_constant: Some(-1.0), ..section(2, 2) }),
            ("nonstructural_mass", FiberSection { nonstructural_mass: -1.0, ..section(2, 2) }),
        ];
        for (name, s) in cases {
            let msg = s.validate().unwrap_err().to_string();
            assert!(msg.contains(&format!("`{name}`")), "{name}: {msg}");
        }
        assert!(section(2, 2).validate().is_ok());
    }
}
