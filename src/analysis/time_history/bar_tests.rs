//! The single-DOF bar that the damage-control and IMPL-EX tests share (`damage_control_tests.rs`,
//! `implex_tests.rs`), and the comparisons of their histories:
//!
//! ```text
//!        m  ■ ──> u (relative to the base)      bar: L = 1 m, A = 0.01 m², the uniaxial law of
//!           │                                   the wall of Table 1 (E 2.885 GPa, ν 0.19,
//!           │  bar, σ = (1 − d) E ε,             f_t = E ε₀ᵗ = 0.144 MPa, G_f 20 J/m², B_t for
//!           │  ε = u / L                        h = L); m such that f = 5 Hz uncracked
//!   ════════╧════ base, a_g(t) = a₀ sin(2π 4 t) for t < 0.6 s, then at rest; 5 % damping
//! ```
//! Each test file keeps its own force and Jacobian (the law called directly, or through the
//! elements' point store); the linear part and the law are here.
use super::system::DenseSystem;
use crate::material::{DamageParams, PointLaw, Regularization};
use nalgebra::DMatrix;
use std::f64::consts::PI;

/// Bar length [m].
pub const LENGTH: f64 = 1.0;
/// Bar cross-section [m²].
pub const AREA: f64 = 0.01;

/// The wall's uniaxial law (Table 1), regularized for h = L; the compressive threshold out of
/// reach, so the bar cracks in tension and closes in compression.
pub fn wall_law() -> PointLaw {
    DamageParams {
        e: 2.885e9,
        nu: 0.19,
        eps0_t: 5.0e-5,
        eps0_c: 1.0e-2,
        gf_t: 20.0,
        a_c: 0.9,
        b_c: 2000.0,
        gf_c: None,
        regularization: Regularization::Hillerborg,
        split: crate::material::Split::Trace,
    }
    .for_element(LENGTH)
    .unwrap()
}

/// The bar's linear part for `law`: mass for 5 Hz uncracked, 5 % damping at that frequency, the
/// initial stiffness, unit influence.
pub fn linear_part(law: &PointLaw) -> DenseSystem {
    let k = law.e() * AREA / LENGTH;
    let w = 2.0 * PI * 5.0;
    let m = k / (w * w);
    let one = |x: f64| DMatrix::from_element(1, 1, x);
    DenseSystem::new(one(m), one(2.0 * 0.05 * m * w), one(k), vec![vec![1.0]])
}

/// The methods of [`super::system::DynamicSystem`] that a single-DOF test system takes from its
/// linear part `lin` (the bar here, the Duffing oscillator of `tests.rs`).
macro_rules! linear_part_methods {
    () => {
        fn len(&self) -> usize {
            1
        }
        fn dot(&self, a: &[f64], b: &[f64]) -> f64 {
            a[0] * b[0]
        }
        fn mass_mult(&mut self, x: &[f64], y: &mut [f64]) -> Result<(), crate::error::Error> {
            self.lin.mass_mult(x, y)
        }
        fn damping_mult(&mut self, x: &[f64], y: &mut [f64]) -> Result<(), crate::error::Error> {
            self.lin.damping_mult(x, y)
        }
        fn mass_influence(&self, d: usize) -> &[f64] {
            self.lin.mass_influence(d)
        }
        fn influence(&self, d: usize) -> &[f64] {
            self.lin.influence(d)
        }
        fn static_load(&self) -> &[f64] {
            self.lin.static_load()
        }
    };
}
pub(super) use linear_part_methods;

/// Every `coarse / dt`-th value (the times of a run with step `coarse`).
pub fn sampled(values: &[f64], dt: f64, coarse: f64) -> Vec<f64> {
    let every = (coarse / dt).round() as usize;
    values.iter().skip(every - 1).step_by(every).copied().collect()
}

/// The largest absolute difference of two histories of equal length.
pub fn largest_difference(a: &[f64], b: &[f64]) -> f64 {
    assert_eq!(a.len(), b.len());
    a.iter().zip(b).map(|(x, y)| (x - y).abs()).fold(0.0, f64::max)
}
