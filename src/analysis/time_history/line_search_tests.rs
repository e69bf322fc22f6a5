//! The time history's line search (`stepper`, module docs "Line search") on one DOF whose
//! internal force is a cube root, the classical case where Newton's iterates run away:
//!
//! ```text
//!   f_int(u) = ∛(u − a) + ∛a,   f_int(0) = 0,   static load F = ∛a: the root at u = a
//!   Newton (statics):  u_{k+1} − a = −2 (u_k − a)
//! ```
//!
//! With a unit mass and a step of 10⁴ s the inertia term of the Jacobian, `4 m / h² = 4·10⁻⁸`,
//! is negligible beside the spring's tangent near the root, so the step is the static problem:
//! without the search every attempt runs away; with it the step converges.
use super::scheme::Scheme;
use super::stepper::{State, StepSettings, Stepper};
use super::system::DynamicSystem;
use crate::config::{IntegrationKind, NewtonKind};
use crate::error::Error;

/// The spring of the module docs with a unit mass and no damping.
struct CubeRootSpring {
    a: f64,
    load: Vec<f64>,
    zero: Vec<f64>,
    jacobian: f64,
}

impl CubeRootSpring {
    fn new(a: f64) -> Self {
        CubeRootSpring { a, load: vec![a.cbrt()], zero: vec![0.0], jacobian: 1.0 }
    }
    fn f_int(&self, u: f64) -> f64 {
        (u - self.a).cbrt() + self.a.cbrt()
    }
}

impl DynamicSystem for CubeRootSpring {
    fn len(&self) -> usize {
        1
    }
    fn dot(&self, a: &[f64], b: &[f64]) -> f64 {
        a[0] * b[0]
    }
    fn mass_mult(&mut self, x: &[f64], y: &mut [f64]) -> Result<(), Error> {
        y[0] = x[0];
        Ok(())
    }
    fn damping_mult(&mut self, _x: &[f64], y: &mut [f64]) -> Result<(), Error> {
        y[0] = 0.0;
        Ok(())
    }
    fn mass_influence(&self, _d: usize) -> &[f64] {
        &self.zero
    }
    fn influence(&self, _d: usize) -> &[f64] {
        &self.zero
    }
    fn static_load(&self) -> &[f64] {
        &self.load
    }
    fn internal_force(&mut self, u: &[f64], f: &mut [f64]) -> Result<(), Error> {
        f[0] = self.f_int(u[0]);
        Ok(())
    }
    fn prepare(&mut self, at: Option<&[f64]>, c_m: f64, _c_c: f64) -> Result<(), Error> {
        let u = at.map_or(0.0, |u| u[0]);
        let k = 1.0 / (3.0 * (u - self.a).abs().powf(2.0 / 3.0)).max(1e-300);
        self.jacobian = k + c_m;
        Ok(())
    }
    fn solve(&mut self, r: &[f64], x: &mut [f64]) -> Result<(), Error> {
        x[0] = r[0] / self.jacobian;
        Ok(())
    }
    fn commit(&mut self) {}
    fn revert(&mut self) {}
}

/// The relative force tolerance: the cube root's residual is steep at its root (one ulp of u
/// from a = 2 leaves (4.4·10⁻¹⁶)^(1/3) = 7.6·10⁻⁶ of force, 3·10⁻⁶ of the load), so the test asks
/// for 10⁻⁴, |u − a| ≤ (2.5·10⁻⁴)³ ≈ 1.6·10⁻¹¹.
const TOLERANCE: f64 = 1e-4;

fn settings(newton: NewtonKind, line_search: bool) -> StepSettings {
    StepSettings {
        scheme: Scheme::default(),
        newton,
        integration: IntegrationKind::Implicit,
        krylov_dimension: 3,
        refresh_cost: 0,
        max_iterations: 40,
        tolerance: TOLERANCE,
        max_substeps: 0,
        max_damage_increment: 1.0,
        line_search,
    }
}

/// One step of 10⁴ s from rest under the static load: the relative residual reached, or the
/// failure's.
fn one_step(newton: NewtonKind, line_search: bool) -> Result<f64, f64> {
    let (a, h) = (2.0, 1.0e4);
    let mut sys = CubeRootSpring::new(a);
    let mut state = State::at_rest(&mut sys, vec![0.0], [0.0; 3]).expect("the state at rest");
    let mut stepper = Stepper::new(settings(newton, line_search));
    let ground = |_t: f64| [0.0; 3];
    match stepper.advance(&mut sys, &ground, &mut state, h, h) {
        Ok(report) => {
            // The root of the static problem, within what the inertia of the step leaves.
            assert!((state.u[0] - a).abs() < 1e-9, "u = {} against the root {a}", state.u[0]);
            Ok(report.residual)
        }
        Err(failure) => Err(failure.residual),
    }
}

/// Full Newton. (The secant iterations of `krylov` on a single cube root fall into a 2-cycle
/// with or without the search, ±3.67 and ±0.87 from the root: one DOF gives the accelerator
/// nothing to work with; its scaled secant pairs are tested in `krylov.rs`.)
#[test]
fn full_newton_runs_away_on_the_cube_root_and_the_line_search_converges() {
    let without = one_step(NewtonKind::Tangent, false);
    assert!(without.is_err(), "full Newton without the search was expected to fail: {without:?}");
    let with = one_step(NewtonKind::Tangent, true);
    assert!(with.is_ok_and(|r| r <= TOLERANCE), "full Newton with the search: {with:?}");
}
