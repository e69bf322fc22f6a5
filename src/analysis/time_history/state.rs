//! The state of the time history at the end of a converged step, and the external force.
use super::energy::EnergyBalance;
use super::system::DynamicSystem;

/// The state at the end of the last converged step (relative motion).
#[derive(Clone, Debug, PartialEq)]
pub struct State {
    /// Steps done.
    pub step: usize,
    /// Time [s] (0 at the start of the time history).
    pub t: f64,
    /// Displacement.
    pub u: Vec<f64>,
    /// Velocity.
    pub v: Vec<f64>,
    /// Acceleration.
    pub a: Vec<f64>,
    /// `f_int(u)` (committed).
    pub f_int: Vec<f64>,
    /// `C v`.
    pub cv: Vec<f64>,
    /// Energies so far.
    pub energy: EnergyBalance,
    /// The next step starts with substeps of `dt / 2^substep_level`: the size the damage control
    /// of [`super::stepper`] left the last step at (0 without the control). Part of the state, so
    /// that a checkpoint carries it and a restart continues as the uninterrupted run.
    pub substep_level: u32,
}

impl State {
    /// At rest at `u0` (a static equilibrium under `f_static`) when the ground starts moving with
    /// `a_g(0)`: `v = 0` and `M a = −Σ M ι_d a_g,d(0)`, so `a = −Σ ι_d a_g,d(0)`.
    pub fn at_rest<S: DynamicSystem>(sys: &mut S, u0: Vec<f64>, ag0: [f64; 3]) -> Result<State, crate::error::Error> {
        let n = sys.len();
        let mut a = vec![0.0; n];
        for d in 0..3 {
            for (ai, ii) in a.iter_mut().zip(sys.influence(d)) {
                *ai -= ii * ag0[d];
            }
        }
        State::new(sys, u0, vec![0.0; n], a)
    }

    /// From given `u`, `v`, `a` (the caller ensures that `a` satisfies the equation of motion).
    pub fn new<S: DynamicSystem>(
        sys: &mut S,
        u: Vec<f64>,
        v: Vec<f64>,
        a: Vec<f64>,
    ) -> Result<State, crate::error::Error> {
        let n = sys.len();
        let mut f_int = vec![0.0; n];
        sys.internal_force(&u, &mut f_int)?;
        let mut cv = vec![0.0; n];
        sys.damping_mult(&v, &mut cv)?;
        let mut mv = vec![0.0; n];
        sys.mass_mult(&v, &mut mv)?;
        let strain = 0.5 * sys.dot(&u, &f_int);
        let damage = sys.dissipated_energy();
        let energy = EnergyBalance {
            kinetic: 0.5 * sys.dot(&v, &mv),
            strain,
            strain0: strain,
            damage,
            damage0: damage,
            ..Default::default()
        };
        Ok(State { step: 0, t: 0.0, u, v, a, f_int, cv, energy, substep_level: 0 })
    }
}

/// `f(t) = f_static − Σ_d M ι_d a_g,d(t)`.
pub fn external_force<S: DynamicSystem>(sys: &S, ag: [f64; 3], f: &mut Vec<f64>) {
    f.clear();
    f.extend_from_slice(sys.static_load());
    for d in 0..3 {
        if ag[d] != 0.0 {
            for (fi, mi) in f.iter_mut().zip(sys.mass_influence(d)) {
                *fi -= mi * ag[d];
            }
        }
    }
}
