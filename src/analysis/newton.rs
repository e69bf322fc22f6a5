//! The nonlinear static system of one rank and Newton's method for one increment.
//!
//! Unknowns: the free DOFs u_f and, under displacement control with a load pattern, the pattern
//! factor μ. External force `f_ext = λ f_c + μ f_p` (f_c: the job's loads and gravity; f_p: the
//! control pattern). Imposed DOFs (supports, and control nodes without a pattern) keep the values
//! set before the iterations, and the free equations see them through f_int(u).
//!
//! ```text
//!   r_k = f_ext − f_int(u_k)                        (free rows)
//!   K(u_k) δu_r = r_k                               (the elements' consistent tangent, or their
//!                                                    secant stiffness for secant iterations)
//!   pattern control: K_t δu_p = f_p,  δμ = (u_c* − u_c − δu_r,c) / δu_p,c,  δu = δu_r + δμ δu_p
//!   otherwise:       δu = δu_r
//!   line search:     η with δu · r(u_k + η δu) ≈ 0  (analysis::line_search), η = 1 under
//!                    pattern control (the constraint u_c = u_c* holds only for η = 1)
//!   u_{k+1} = u_k + η δu,  μ += δμ
//! ```
//! Converged when ‖r‖ ≤ tol_f · F or, after the first iteration, when the energy
//! |δu · r| ≤ tol_e · |δu₀ · r₀|. The force scale is F = max(‖f_ext‖, ‖f_int‖) (f_int on all
//! rows, so the reactions set the scale of a displacement-driven problem), at most G·F₀ with F₀
//! its value at the increment's start ([`bounded_reference`]): a runaway iterate, with huge
//! internal forces and control multiplier, must not loosen its own test.
//!
//! The system's operations (f_int, the residual, the solves) are in analysis::nonlinear_system;
//! this file is the method: one `NewtonSolve` per increment, an iteration being
//! `residual → convergence test → direction → energy test → update (line search)`.
use super::line_search::{self, LineSearchSettings};
use super::Discretization;
use crate::error::Error;
use crate::mesh::Mesh;
use crate::model::StructuralModel;
use crate::parallel::Context;

pub use super::nonlinear_system::{global_sum, Increment, NonlinearSystem};

/// Settings of one Newton solve.
#[derive(Clone, Copy, Debug)]
pub struct NewtonSettings {
    /// Largest number of iterations.
    pub max_iterations: usize,
    /// Relative force tolerance.
    pub force_tolerance: f64,
    /// Relative energy tolerance.
    pub energy_tolerance: f64,
    /// Line search, if any.
    pub line_search: Option<LineSearchSettings>,
    /// Iterate on the secant stiffness (damage: (1 − d) C₀, positive definite; linear but
    /// robust convergence through softening) instead of the consistent tangent.
    pub secant: bool,
}

/// How a Newton solve ended.
#[derive(Clone, Debug)]
pub struct NewtonOutcome {
    /// Whether it converged.
    pub converged: bool,
    /// Iterations made.
    pub iterations: usize,
    /// Final ‖r‖ / reference.
    pub residual: f64,
    /// Extra residual evaluations of the line search.
    pub line_search_evaluations: usize,
    /// Why it failed (empty when converged).
    pub reason: String,
}

impl NewtonOutcome {
    /// Not converged yet, no iteration made.
    fn start() -> Self {
        NewtonOutcome {
            converged: false,
            iterations: 0,
            residual: f64::INFINITY,
            line_search_evaluations: 0,
            reason: String::new(),
        }
    }

    /// Converged.
    fn converged(mut self) -> Self {
        self.converged = true;
        self
    }

    /// Failed, for `reason`.
    fn failed(mut self, reason: String) -> Self {
        self.reason = reason;
        self
    }
}

/// A Newton direction (δu, δμ), or why none could be computed (the increment fails, the run
/// goes on).
type Direction = Result<(Vec<f64>, f64), NoDirection>;

/// Why no Newton direction could be computed.
#[derive(Debug, thiserror::Error)]
enum NoDirection {
    /// The linear solve failed (the solver's reason).
    #[error("linear solve failed: {0}")]
    LinearSolve(String),
    /// With pattern control, the pattern's solution is zero at the control DOF.
    #[error("the load pattern does not move the control DOF (K⁻¹ f_p is zero there)")]
    ControlNotMoved,
}

/// The scales the convergence test keeps from the increment's first iteration: the force
/// scale F₀ and the energy |δu₀ · r₀|.
#[derive(Default)]
struct FirstIteration {
    /// F₀.
    force: f64,
    /// |δu₀ · r₀|, at least `f64::MIN_POSITIVE`.
    energy: f64,
}

impl FirstIteration {
    /// The force scale of iteration `it` from its `max(‖f_ext‖, ‖f_int‖)` ([`bounded_reference`]);
    /// the first iteration's is F₀.
    fn force_scale(&mut self, it: usize, current: f64) -> f64 {
        if it == 0 {
            self.force = current;
        }
        bounded_reference(current, self.force)
    }

    /// Whether the energy |δu · r| of iteration `it` is within `tolerance` of the first one's
    /// (which the first iteration records; never converged there).
    fn energy_converged(&mut self, it: usize, energy: f64, tolerance: f64) -> bool {
        if it == 0 {
            self.energy = energy.max(f64::MIN_POSITIVE);
            false
        } else {
            energy <= tolerance * self.energy
        }
    }
}

/// `a · b` over the owned rows.
fn dot(a: &[f64], b: &[f64]) -> f64 {
    a.iter().zip(b).map(|(x, y)| x * y).sum()
}

impl NonlinearSystem {
    /// Collective. Newton's method for one increment (module docs), from the committed state.
    pub fn solve_increment(
        &mut self,
        ctx: &Context,
        disc: &mut Discretization,
        mesh: &Mesh,
        model: &StructuralModel,
        inc: &Increment,
        set: &NewtonSettings,
    ) -> Result<NewtonOutcome, Error> {
        self.start(inc);
        NewtonSolve { sys: self, ctx, disc, mesh, model, inc, set }.run()
    }
}

/// One increment's Newton solve: the system, and what every evaluation of it takes.
struct NewtonSolve<'a> {
    sys: &'a mut NonlinearSystem,
    ctx: &'a Context,
    disc: &'a mut Discretization,
    mesh: &'a Mesh,
    model: &'a StructuralModel,
    inc: &'a Increment,
    set: &'a NewtonSettings,
}

impl NewtonSolve<'_> {
    /// Collective. The iterations, from the started increment: converged, failed with a reason,
    /// or out of iterations.
    fn run(mut self) -> Result<NewtonOutcome, Error> {
        let mut outcome = NewtonOutcome::start();
        let mut first = FirstIteration::default();
        for it in 0..self.set.max_iterations {
            outcome.iterations = it + 1;
            if !self.sys.fresh {
                let u = self.sys.u.clone();
                self.internal_force_at(&u)?;
            }
            let r = self.sys.residual(self.inc.lambda, self.sys.mu);
            let rn = global_sum(self.ctx, dot(&r, &r)).sqrt();
            let reference = first.force_scale(it, self.force_scale());
            outcome.residual = if reference > 0.0 { rn / reference } else { rn };
            if !outcome.residual.is_finite() {
                return Ok(outcome.failed("the residual is not finite".into()));
            }
            let gap_ok = self.control_gap_closed();
            if gap_ok && (rn == 0.0 || outcome.residual <= self.set.force_tolerance) {
                return Ok(outcome.converged());
            }
            let (du, dmu) = match self.direction(&r)? {
                Ok(step) => step,
                Err(reason) => return Ok(outcome.failed(reason.to_string())),
            };
            let energy = global_sum(self.ctx, dot(&du, &r)).abs();
            if first.energy_converged(it, energy, self.set.energy_tolerance) && gap_ok {
                return Ok(outcome.converged());
            }
            outcome.line_search_evaluations += self.update(&du, dmu, &r)?;
        }
        Ok(outcome.failed(format!("no convergence in {} iterations", self.set.max_iterations)))
    }

    /// Collective. f_int at `u` into the system; the elements' trial state at `u`.
    fn internal_force_at(&mut self, u: &[f64]) -> Result<(), Error> {
        self.sys.internal_force_at(self.ctx, self.disc, self.mesh, self.model, u)
    }

    /// Collective. The current force scale `max(‖f_ext‖, ‖f_int‖)`, f_ext = λ f_c + μ f_p.
    fn force_scale(&self) -> f64 {
        let (sys, lambda) = (&*self.sys, self.inc.lambda);
        let ext: Vec<f64> = (0..sys.n_owned).map(|i| lambda * sys.f_loads[i] + sys.mu * sys.f_pattern[i]).collect();
        global_sum(self.ctx, dot(&ext, &ext)).sqrt().max(global_sum(self.ctx, dot(&sys.f_int, &sys.f_int)).sqrt())
    }

    /// Collective. Whether the control constraint u_c = u_c* holds (to round-off; it does after
    /// the first iteration); true without pattern control.
    fn control_gap_closed(&self) -> bool {
        self.inc
            .control_target
            .is_none_or(|t| (t - self.sys.control_value(self.ctx, &self.sys.u)).abs() <= 1e-12 * t.abs())
    }

    /// Collective. The Newton direction for the residual `r`: `K δu_r = r`, and under pattern
    /// control also `K δu_p = f_p` with the correction [`Self::control_correction`]. A failed
    /// linear solve fails the increment.
    fn direction(&mut self, r: &[f64]) -> Result<Direction, Error> {
        let u = self.sys.u.clone();
        let pattern = self.sys.f_pattern.clone();
        let rhs: &[&[f64]] = match self.inc.control_target {
            Some(_) => &[r, &pattern],
            None => &[r],
        };
        let sols = match self.sys.solve(self.ctx, self.disc, self.mesh, self.model, &u, rhs, self.set.secant) {
            Ok(s) => s,
            // The only agreed error of `solve` is the linear solve's (a singular or
            // indefinite matrix in a softening state): the increment fails, the run goes on.
            Err(Error::Solver(e)) => return Ok(Err(NoDirection::LinearSolve(e.to_string()))),
            Err(Error::Agreed(e)) => return Ok(Err(NoDirection::LinearSolve(e.message))),
            Err(e) => return Err(e),
        };
        Ok(match self.inc.control_target {
            Some(target) => self.control_correction(target, &sols[0], &sols[1]),
            None => Ok((sols[0].clone(), 0.0)),
        })
    }

    /// Collective. Pattern control: `δμ = (u_c* − u_c − δu_r,c) / δu_p,c` and
    /// `δu = δu_r + δμ δu_p`, so that the step lands on the target `u_c*`.
    fn control_correction(&self, target: f64, du_r: &[f64], du_p: &[f64]) -> Direction {
        let (dr_c, dp_c) = (self.sys.control_value(self.ctx, du_r), self.sys.control_value(self.ctx, du_p));
        if dp_c == 0.0 || !dp_c.is_finite() {
            return Err(NoDirection::ControlNotMoved);
        }
        let dmu = (target - self.sys.control_value(self.ctx, &self.sys.u) - dr_c) / dp_c;
        let mut du = du_r.to_vec();
        for (d, p) in du.iter_mut().zip(du_p) {
            *d += dmu * p;
        }
        Ok((du, dmu))
    }

    /// Collective. The full step `u += δu, μ += δμ` (f_int evaluated there), then, without pattern
    /// control, the line search if the full step is not good enough. Returns the line search's
    /// extra residual evaluations.
    fn update(&mut self, du: &[f64], dmu: f64, r: &[f64]) -> Result<usize, Error> {
        let s0 = global_sum(self.ctx, dot(du, r));
        let trial: Vec<f64> = self.sys.u.iter().zip(du).map(|(a, b)| a + b).collect();
        self.sys.mu += dmu;
        self.internal_force_at(&trial)?;
        self.sys.u = trial;
        self.sys.fresh = true;
        match (self.set.line_search, self.inc.control_target) {
            (Some(ls), None) => self.line_search(&ls, du, s0),
            _ => Ok(0),
        }
    }

    /// Collective. From the full step's u (= base + δu), the η with `δu · r(base + η δu) ≈ 0`
    /// (analysis::line_search; `s0` = δu · r at the base); u ← base + η δu. Returns the extra
    /// residual evaluations.
    fn line_search(&mut self, ls: &LineSearchSettings, du: &[f64], s0: f64) -> Result<usize, Error> {
        let lambda = self.inc.lambda;
        let r1 = self.sys.residual(lambda, self.sys.mu);
        let s1 = global_sum(self.ctx, dot(du, &r1));
        let base: Vec<f64> = self.sys.u.iter().zip(du).map(|(a, b)| a - b).collect();
        let mut last_eta = 1.0;
        let found = line_search::secant(s0, s1, ls, |eta| -> Result<f64, Error> {
            let x: Vec<f64> = base.iter().zip(du).map(|(a, b)| a + eta * b).collect();
            self.internal_force_at(&x)?;
            last_eta = eta;
            let r = self.sys.residual(lambda, self.sys.mu);
            Ok(global_sum(self.ctx, dot(du, &r)))
        })?;
        self.sys.u = base.iter().zip(du).map(|(a, b)| a + found.eta * b).collect();
        // The elements' trial state (and f_int) are those of the last evaluation.
        self.sys.fresh = last_eta == found.eta;
        Ok(found.evaluations)
    }
}

/// A relative residual beyond which Newton's iterate has diverged: the attempt ends there, before
/// a tangent at runaway displacements is assembled and factorized (a step that cannot converge
/// otherwise runs to residuals of 1e75 and more, with non-finite entries in the matrix next).
pub const DIVERGED: f64 = 1e6;

/// How far the force scale of the convergence test may grow within one increment: G.
pub const REFERENCE_GROWTH: f64 = 10.0;

/// The force scale of the convergence test: the current `max(‖f_ext‖, ‖f_int‖)`, at most
/// `G·F₀`, F₀ its value at the start of the increment (or the step), G = [`REFERENCE_GROWTH`].
/// Forces may grow within an increment, but a diverging iterate, whose internal forces run
/// away, cannot make its own residual look small; forces that fall keep the test as strict as
/// they are. With F₀ = 0 (nothing loaded at the start) the current value is used.
pub fn bounded_reference(current: f64, start: f64) -> f64 {
    if start > 0.0 {
        current.min(REFERENCE_GROWTH * start)
    } else {
        current
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_force_scale_cannot_run_away_with_the_iterate() {
        // Within [F₀, G F₀] the current scale is used as it is.
        assert_eq!(bounded_reference(3.0, 1.0), 3.0);
        // An iterate whose forces blew up by 1e7 is judged against G F₀, not against itself.
        assert_eq!(bounded_reference(1.2e7, 1.0), REFERENCE_GROWTH);
        // Forces that fall keep their own (stricter) scale.
        assert_eq!(bounded_reference(0.1, 1.0), 0.1);
        // Nothing loaded at the start: the current scale.
        assert_eq!(bounded_reference(5.0, 0.0), 5.0);
    }
}
