//! The trial state of one (sub)step and its residual: the stepper's working vectors
//! ([`super::stepper`]).
//!
//! ```text
//!   predictor   u = u_n, (v, a) from the scheme's kinematics
//!   residual    r(u) = (1+α) f_{n+1} − α f_n + α (C v_n + f_int,n) − M a − (1+α)(C v + f_int(u))
//!   scale       ‖rhs‖ + ‖M a_pred‖ + ‖f_int,n‖ + ‖C v_n‖ + ‖M a‖ + (1+α)(‖C v‖ + ‖f_int‖)
//!   line search u = u0 + η Δu along the last correction Δu from u0
//! ```
use super::scheme::Scheme;
use super::state::{external_force, State};
use super::system::DynamicSystem;

/// The vectors of a step's trial: displacement, velocity, acceleration, the forces at it, the
/// residual, the last correction and the iterate it started from, the loads.
#[derive(Default)]
pub(super) struct Trial {
    pub(super) u: Vec<f64>,
    pub(super) v: Vec<f64>,
    pub(super) a: Vec<f64>,
    pub(super) fi: Vec<f64>,
    pub(super) cv: Vec<f64>,
    pub(super) ma: Vec<f64>,
    pub(super) r: Vec<f64>,
    pub(super) du: Vec<f64>,
    /// The iterate before the last correction (line search).
    pub(super) u0: Vec<f64>,
    pub(super) rhs: Vec<f64>,
    pub(super) f0: Vec<f64>,
    pub(super) f1: Vec<f64>,
}

impl Trial {
    /// The step `state → t1` (size `h`) set up: the vectors sized, the loads `f_n`, `f_{n+1}`,
    /// the constant part of the residual `rhs = (1+α) f_{n+1} − α f_n + α (C v_n + f_int,n)`, and
    /// the predictor `u = u_n` with the scheme's v and a. Returns the size of the terms that
    /// cancel in r: the loads, the start's forces and the inertia of the predictor,
    /// `M (v_n/(βh) + (1/(2β) − 1) a_n)`; the tolerance is relative to it, so that a step whose
    /// forces all pass through zero is not asked for more than round-off.
    pub(super) fn start_step<S: DynamicSystem>(
        &mut self,
        sys: &mut S,
        ground: &dyn Fn(f64) -> [f64; 3],
        state: &State,
        t1: f64,
        h: f64,
        sc: Scheme,
    ) -> Result<f64, crate::error::Error> {
        let n = sys.len();
        let s = self;
        for v in
            [&mut s.u, &mut s.v, &mut s.a, &mut s.fi, &mut s.cv, &mut s.ma, &mut s.r, &mut s.du, &mut s.u0, &mut s.rhs]
        {
            v.resize(n, 0.0);
        }
        external_force(sys, ground(state.t), &mut s.f0);
        external_force(sys, ground(t1), &mut s.f1);
        let al = sc.alpha;
        for i in 0..n {
            s.rhs[i] = (1.0 + al) * s.f1[i] - al * s.f0[i] + al * (state.cv[i] + state.f_int[i]);
        }
        for i in 0..n {
            s.du[i] = state.v[i] / (sc.beta * h) + (0.5 / sc.beta - 1.0) * state.a[i];
        }
        sys.mass_mult(&s.du, &mut s.ma)?;
        let rhs_norm: f64 = sys
            .dots(&[(&s.rhs, &s.rhs), (&s.ma, &s.ma), (&state.f_int, &state.f_int), (&state.cv, &state.cv)])
            .iter()
            .map(|x| x.sqrt())
            .sum();
        s.u.copy_from_slice(&state.u);
        sc.kinematics(h, &state.u, &state.v, &state.a, &s.u, &mut s.v, &mut s.a);
        Ok(rhs_norm)
    }

    /// The trial `u = u0 + η Δu` with the scheme's v and a, and its residual's norms
    /// ([`Self::residual_at_trial`]).
    pub(super) fn move_along<S: DynamicSystem>(
        &mut self,
        sys: &mut S,
        state: &State,
        (h, rhs_norm): (f64, f64),
        sc: Scheme,
        eta: f64,
    ) -> Result<(f64, f64), crate::error::Error> {
        for i in 0..self.u.len() {
            self.u[i] = self.u0[i] + eta * self.du[i];
        }
        sc.kinematics(h, &state.u, &state.v, &state.a, &self.u, &mut self.v, &mut self.a);
        self.residual_at_trial(sys, sc.alpha, rhs_norm, None)
    }

    /// The forces at the trial (u, v, a) and the residual
    /// `r = rhs − M a − (1+α)(C v + f_int(u))` (module docs). Returns `‖r‖` and the force scale of
    /// the convergence test, `rhs_norm + ‖M a‖ + (1+α)(‖C v‖ + ‖f_int‖)`. `known` is `f_int(u)`
    /// when the caller has it: at the predictor `u = u_n` it is the state's (the elements' stress
    /// at their committed strain, from their committed state), so no element is evaluated.
    pub(super) fn residual_at_trial<S: DynamicSystem>(
        &mut self,
        sys: &mut S,
        al: f64,
        rhs_norm: f64,
        known: Option<&[f64]>,
    ) -> Result<(f64, f64), crate::error::Error> {
        let s = self;
        match known {
            Some(fi) => s.fi.copy_from_slice(fi),
            None => sys.internal_force(&s.u, &mut s.fi)?,
        }
        sys.damping_mult(&s.v, &mut s.cv).and_then(|_| sys.mass_mult(&s.a, &mut s.ma))?;
        for i in 0..s.r.len() {
            s.r[i] = s.rhs[i] - s.ma[i] - (1.0 + al) * (s.cv[i] + s.fi[i]);
        }
        let d = sys.dots(&[(&s.r, &s.r), (&s.ma, &s.ma), (&s.cv, &s.cv), (&s.fi, &s.fi)]);
        Ok((d[0].sqrt(), rhs_norm + d[1].sqrt() + (1.0 + al) * (d[2].sqrt() + d[3].sqrt())))
    }
}
