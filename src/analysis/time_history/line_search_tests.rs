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
use super::cube_root_spring::CubeRootSpring;
use super::scheme::Scheme;
use super::stepper::{State, StepSettings, Stepper};
use crate::config::{IntegrationKind, NewtonKind};

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
        implex_corrections: 0,
        implex_tolerance: 0.0,
        implex_pass_tolerance: 0.0,
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
