//! The step of a linear system: one solve, one product with the mass, no residual iteration.
//!
//! When `f_int(u) = K₀ u` (no element has state), the Jacobian `J = K₀ + c_m M + c_c C` of
//! [`super::stepper`] is the exact derivative of the residual, so one correction from the
//! predictor `u = u_n` ends the step in equilibrium, to the accuracy of the solve. Every quantity
//! at the end of the step is then linear in that correction `Δu`. Keeping the products of the
//! state with `M` and `C` from step to step, the predictor's terms need no product at all
//! (`kinematics` in [`super::scheme`]: `a_p = −c₂ v_n − c₃ a_n`, `v_p = d₂ v_n + d₃ a_n`):
//!
//! ```text
//!   M a_p = −c₂ M v_n − c₃ M a_n            C v_p = d₂ C v_n + d₃ C a_n
//!   M v_p =  d₂ M v_n + d₃ M a_n            C a_p = −c₂ C v_n − c₃ C a_n
//!   r₀ = (1+α) f_{n+1} − α f_n + α (C v_n + K u_n) − M a_p − (1+α)(C v_p + K u_n)
//!   J Δu = r₀ / (1+α)
//! ```
//!
//! and the end of the step follows from the three products `M Δu`, `K₀ Δu`, `C Δu`. With Rayleigh
//! damping only `M Δu` needs a product: `C Δu = α_R M Δu + β_R K₀ Δu`, and the solve itself gives
//! `K₀ Δu = (r₀/(1+α) − (c_m + c_c α_R) M Δu) / (1 + c_c β_R)` ([`DynamicSystem::products`]);
//! with a lumped mass that product is a diagonal scaling:
//!
//! ```text
//!   u = u_n + Δu    v = v_p + d₁ Δu    a = a_p + c₁ Δu
//!   K u = K u_n + K Δu    M v = M v_p + d₁ M Δu    M a = M a_p + c₁ M Δu
//!   C v = C v_p + d₁ C Δu    C a = C a_p + c₁ C Δu
//! ```
//!
//! so that `M a + (1+α)(C v + K u) − [M a_p + (1+α)(C v_p + K u_n)] = (1+α) J Δu = r₀`: the
//! residual at the end vanishes by construction. The energy terms of [`super::energy`] are dot
//! products of these vectors (one reduction).
//!
//! # The check
//! The updated products drift from the true ones by round-off, and a solve can be inaccurate.
//! At the first step after any change (a new factorization, a step size, a restart, a step of the
//! Newton path) and every [`CHECK_EVERY`] steps, the products of the end state are computed again
//! (`M a`, `M v`, `K₀ u`, `C v`, `C a`) and the residual evaluated with them against the force
//! tolerance of the Newton path; the fresh products then replace the updated ones. A step that
//! misses the tolerance is handed back to the Newton path, which iterates it to the tolerance.
use super::energy::StepVectors;
use super::scheme::Scheme;
use super::state::{external_force, State};
use super::system::DynamicSystem;
use crate::error::Error;

/// Steps between two checks of the residual with fresh products.
pub const CHECK_EVERY: usize = 64;

/// The products of the state with `M` and `C` kept from step to step, and the step's vectors.
#[derive(Default)]
pub struct LinearStep {
    /// The state (step, time bits) the products belong to.
    key: Option<(usize, u64)>,
    /// The relative residual of the last check.
    last_residual: f64,
    /// The step size and the steps since the last check.
    h: f64,
    since_check: usize,
    /// `M v_n`, `M a_n`, `C a_n` (`K u_n` and `C v_n` are the state's `f_int` and `cv`).
    mv: Vec<f64>,
    ma: Vec<f64>,
    ca: Vec<f64>,
    /// The step: loads at both ends, the residual, the correction and its products.
    f0: Vec<f64>,
    f1: Vec<f64>,
    r: Vec<f64>,
    du: Vec<f64>,
    mdu: Vec<f64>,
    kdu: Vec<f64>,
    cdu: Vec<f64>,
    /// The end of the step: u, v, a and their products.
    end: EndState,
}

#[derive(Default)]
struct EndState {
    u: Vec<f64>,
    v: Vec<f64>,
    a: Vec<f64>,
    ku: Vec<f64>,
    cv: Vec<f64>,
    mv: Vec<f64>,
    ma: Vec<f64>,
    ca: Vec<f64>,
}

/// What a linear step did.
pub enum Outcome {
    /// The state is at the end of the step; the relative residual of the last check.
    Done { residual: f64 },
    /// The check found the residual above the tolerance: the state is unchanged.
    Missed,
}

impl LinearStep {
    /// Forgets the kept products (the next step computes them afresh and checks).
    pub fn invalidate(&mut self) {
        self.key = None;
    }

    /// Collective. One step of size `h` from `state` to `t1` (module docs); `tolerance` is the
    /// relative force tolerance of the check.
    pub fn step<S: DynamicSystem>(
        &mut self,
        sys: &mut S,
        ground: &dyn Fn(f64) -> [f64; 3],
        state: &mut State,
        (t1, h): (f64, f64),
        sc: Scheme,
        tolerance: f64,
    ) -> Result<Outcome, Error> {
        let n = sys.len();
        let key = (state.step, state.t.to_bits());
        let fresh = self.key != Some(key) || self.h.to_bits() != h.to_bits() || self.since_check + 1 >= CHECK_EVERY;
        if self.key != Some(key) {
            self.resync(sys, state)?;
        }
        let (c_m, c_c) = sc.jacobian_coefficients(h);
        sys.prepare(Some(&state.u), c_m, c_c)?;
        let (c1, c2, c3) = (1.0 / (sc.beta * h * h), 1.0 / (sc.beta * h), 1.0 / (2.0 * sc.beta) - 1.0);
        let (d1, d2, d3) = (sc.gamma / (sc.beta * h), 1.0 - sc.gamma / sc.beta, h * (1.0 - sc.gamma / (2.0 * sc.beta)));
        let al = sc.alpha;
        external_force(sys, ground(state.t), &mut self.f0);
        external_force(sys, ground(t1), &mut self.f1);
        let e = &mut self.end;
        for v in [&mut self.r, &mut self.du, &mut self.mdu, &mut self.kdu, &mut self.cdu] {
            v.resize(n, 0.0);
        }
        for v in [&mut e.u, &mut e.v, &mut e.a, &mut e.ku, &mut e.cv, &mut e.mv, &mut e.ma, &mut e.ca] {
            v.resize(n, 0.0);
        }
        // The predictor's products (kept in `end` until the correction is added).
        for i in 0..n {
            e.ma[i] = -c2 * self.mv[i] - c3 * self.ma[i];
            e.mv[i] = d2 * self.mv[i] + d3 * self.ma[i];
            e.cv[i] = d2 * state.cv[i] + d3 * self.ca[i];
            e.ca[i] = -c2 * state.cv[i] - c3 * self.ca[i];
            let rhs = (1.0 + al) * self.f1[i] - al * self.f0[i] + al * (state.cv[i] + state.f_int[i]);
            self.r[i] = (rhs - e.ma[i] - (1.0 + al) * (e.cv[i] + state.f_int[i])) / (1.0 + al);
        }
        sys.solve(&self.r, &mut self.du)?;
        sys.products(&self.du, Some(&self.r), &mut self.mdu, &mut self.kdu, &mut self.cdu)?;
        for i in 0..n {
            let (du, vn, an) = (self.du[i], state.v[i], state.a[i]);
            e.u[i] = state.u[i] + du;
            e.v[i] = d2 * vn + d3 * an + d1 * du;
            e.a[i] = -c2 * vn - c3 * an + c1 * du;
            e.ku[i] = state.f_int[i] + self.kdu[i];
            e.mv[i] += d1 * self.mdu[i];
            e.ma[i] += c1 * self.mdu[i];
            e.cv[i] += d1 * self.cdu[i];
            e.ca[i] += c1 * self.cdu[i];
        }
        let residual = if fresh { Some(self.check(sys, state, al)?) } else { None };
        if residual.is_some_and(|r| !(r <= tolerance)) {
            self.key = None;
            return Ok(Outcome::Missed);
        }
        self.accept(sys, state, t1);
        self.h = h;
        self.since_check = if fresh { 0 } else { self.since_check + 1 };
        self.key = Some((state.step, state.t.to_bits()));
        if let Some(r) = residual {
            self.last_residual = r;
        }
        Ok(Outcome::Done { residual: self.last_residual })
    }

    /// Collective. The products of the state computed afresh.
    fn resync<S: DynamicSystem>(&mut self, sys: &mut S, state: &mut State) -> Result<(), Error> {
        let n = sys.len();
        for v in [&mut self.mv, &mut self.ma, &mut self.ca, &mut self.kdu] {
            v.resize(n, 0.0);
        }
        sys.products(&state.v, None, &mut self.mv, &mut self.kdu, &mut state.cv)?;
        sys.products(&state.a, None, &mut self.ma, &mut self.kdu, &mut self.ca)?;
        sys.internal_force(&state.u, &mut state.f_int)?;
        self.since_check = 0;
        Ok(())
    }

    /// Collective. The residual at the end of the step with the products computed afresh, which
    /// then replace the updated ones; relative to the size of its terms, as in the Newton path.
    fn check<S: DynamicSystem>(&mut self, sys: &mut S, state: &State, al: f64) -> Result<f64, Error> {
        let e = &mut self.end;
        sys.products(&e.a, None, &mut e.ma, &mut self.kdu, &mut e.ca)?;
        sys.products(&e.v, None, &mut e.mv, &mut self.kdu, &mut e.cv)?;
        sys.internal_force(&e.u, &mut e.ku)?;
        let n = e.u.len();
        for i in 0..n {
            let rhs = (1.0 + al) * self.f1[i] - al * self.f0[i] + al * (state.cv[i] + state.f_int[i]);
            self.r[i] = rhs - e.ma[i] - (1.0 + al) * (e.cv[i] + e.ku[i]);
            self.mdu[i] = rhs;
        }
        let d = sys.dots(&[(&self.r, &self.r), (&self.mdu, &self.mdu), (&e.ma, &e.ma), (&e.cv, &e.cv), (&e.ku, &e.ku)]);
        let scale = d[1].sqrt() + d[2].sqrt() + (1.0 + al) * (d[3].sqrt() + d[4].sqrt());
        Ok(if scale > 0.0 { d[0].sqrt() / scale } else { d[0].sqrt() })
    }

    /// Collective. The end of the step into `state`, with the step's energies (the trapezoidal
    /// sums of [`super::energy`]); the kept products move to the new state.
    fn accept<S: DynamicSystem>(&mut self, sys: &mut S, state: &mut State, t1: f64) {
        let e = &self.end;
        for i in 0..e.u.len() {
            self.du[i] = e.u[i] - state.u[i];
        }
        let step = StepVectors {
            du: &self.du,
            f: [&self.f0, &self.f1],
            cv: [&state.cv, &e.cv],
            fi: [&state.f_int, &e.ku],
            u: &e.u,
            v: &e.v,
            mv: Some(&e.mv),
        };
        state.energy.add_step(sys, step);
        state.u.copy_from_slice(&e.u);
        state.v.copy_from_slice(&e.v);
        state.a.copy_from_slice(&e.a);
        state.f_int.copy_from_slice(&e.ku);
        state.cv.copy_from_slice(&e.cv);
        self.mv.copy_from_slice(&e.mv);
        self.ma.copy_from_slice(&e.ma);
        self.ca.copy_from_slice(&e.ca);
        state.t = t1;
        state.step += 1;
        sys.commit();
    }
}
