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
//! Elements evaluate from their committed state at the total displacement and keep the result
//! as their trial state; [`NonlinearSystem::commit`] makes sure the trial state is that of the
//! converged u before committing.
use super::assembly::{self, Rows};
use super::line_search::{self, LineSearchSettings};
use super::Discretization;
use crate::element::EvalRequest;
use crate::error::Error;
use crate::mesh::Mesh;
use crate::model::StructuralModel;
use crate::parallel::{agree, Context};
use crate::petsc::{Ksp, Matrix, Vector};
use mpi::collective::SystemOperation;
use mpi::traits::CommunicatorCollectives;

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

/// What one increment asks for.
#[derive(Clone, Copy, Debug)]
pub struct Increment {
    /// Factor λ of the job's loads.
    pub lambda: f64,
    /// Value of the imposed control DOFs (control without a pattern), if any.
    pub imposed: Option<f64>,
    /// Target value of the control DOF (control with a pattern), if any.
    pub control_target: Option<f64>,
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

/// The system of one rank: owned values of u and of the load vectors, PETSc objects, the control.
pub struct NonlinearSystem {
    /// Owned DOF count.
    pub n_owned: usize,
    /// First owned global equation.
    pub first: usize,
    /// Owned DOF is free (not a support, not imposed).
    pub free: Vec<bool>,
    /// The job's loads and gravity, owned free rows.
    pub f_loads: Vec<f64>,
    /// The control pattern, owned free rows (zeros without a pattern).
    pub f_pattern: Vec<f64>,
    /// Owned local indices of the imposed control DOFs.
    pub imposed: Vec<usize>,
    /// Owned local index of the control DOF under a pattern (on its owner rank).
    pub control: Option<usize>,
    /// Current displacement (owned).
    pub u: Vec<f64>,
    /// Committed displacement (owned).
    pub u_committed: Vec<f64>,
    /// Current pattern factor μ, and its committed value.
    pub mu: f64,
    /// Committed μ.
    pub mu_committed: f64,
    /// Internal forces at `u` on all rows (owned), valid when `fresh`.
    pub f_int: Vec<f64>,
    fresh: bool,
    ug: Vector,
    fint_vec: Vector,
    rhs: Vector,
    sol: Vector,
    k: Matrix,
    ksp: Ksp,
    options_set: bool,
    /// Nonlocal averaging of the damage-driving strains, if the analysis asks for it
    /// ([`NonlinearSystem::enable_nonlocal`]); refreshed before every element evaluation.
    nonlocal: Option<super::nonlocal::NonlocalAveraging>,
}

/// Collective. Σ over ranks.
pub fn global_sum(ctx: &Context, x: f64) -> f64 {
    let mut out = 0.0;
    ctx.comm.all_reduce_into(&x, &mut out, SystemOperation::sum());
    out
}

/// Collective. The linear solver: MUMPS LU (the options database is applied at the first solve).
fn new_solver(ctx: &Context) -> Result<Ksp, Error> {
    let mut ksp = Ksp::new(&ctx.comm, "")?;
    ksp.set_type("preonly")?;
    ksp.set_pc_type("lu")?;
    ksp.set_factor_solver("mumps")?;
    Ok(ksp)
}

fn dot(a: &[f64], b: &[f64]) -> f64 {
    a.iter().zip(b).map(|(x, y)| x * y).sum()
}

impl NonlinearSystem {
    /// Collective. Vectors, matrix and solver for `disc`; loads assembled; u = 0.
    pub fn new(
        ctx: &Context,
        mesh: &Mesh,
        model: &StructuralModel,
        disc: &Discretization,
        matrix: crate::config::MatrixFormat,
    ) -> Result<Self, Error> {
        let n_owned = disc.dofs.n_owned_dofs();
        let first = 6 * disc.dofs.node_offset();
        let mut k = disc.new_matrix(ctx, mesh, model, matrix)?;
        // The damage law's consistent tangent is not symmetric: no solver may assume it.
        k.set_option_symmetric(false)?;
        k.set_near_null_space(&ctx.comm, super::rigid_body_modes(ctx, mesh, &disc.dofs)?)?;
        let mut f = Vector::new_mpi(&ctx.comm, n_owned, None)?;
        assembly::assemble_loads(disc, mesh, model, Rows::Free, &mut f)?;
        let f_loads = f.owned_values()?;
        let mut f_pattern = vec![0.0; n_owned];
        let (mut imposed, mut control) = (Vec::new(), None);
        if let Some(ctl) = &model.control {
            if !ctl.pattern.is_empty() {
                let pattern_model = StructuralModel {
                    nodal_loads: ctl.pattern.clone(),
                    gravity: None,
                    point_masses: Vec::new(),
                    ..model.clone()
                };
                assembly::assemble_loads(disc, mesh, &pattern_model, Rows::Free, &mut f)?;
                f_pattern = f.owned_values()?;
            }
            for &n in &ctl.nodes {
                if disc.dofs.owner[n] == disc.dofs.rank {
                    let i = disc.dofs.dof(n, ctl.dof) as usize - first;
                    if ctl.pattern.is_empty() {
                        imposed.push(i);
                    } else {
                        control = Some(i);
                    }
                }
            }
        }
        let free: Vec<bool> = disc
            .dofs
            .owned
            .iter()
            .flat_map(|&n| (0..6).map(move |d| (n, d)))
            .map(|(n, d)| disc.dofs.equation(n, d) >= 0)
            .collect();
        let ksp = new_solver(ctx)?;
        Ok(NonlinearSystem {
            n_owned,
            first,
            free,
            f_loads,
            f_pattern,
            imposed,
            control,
            u: vec![0.0; n_owned],
            u_committed: vec![0.0; n_owned],
            mu: 0.0,
            mu_committed: 0.0,
            f_int: vec![0.0; n_owned],
            fresh: false,
            ug: Vector::new_ghosted(&ctx.comm, n_owned, &disc.dofs.ghost_dofs())?,
            fint_vec: Vector::new_mpi(&ctx.comm, n_owned, None)?,
            rhs: Vector::new_mpi(&ctx.comm, n_owned, None)?,
            sol: Vector::new_mpi(&ctx.comm, n_owned, None)?,
            k,
            ksp,
            options_set: false,
            nonlocal: None,
        })
    }

    /// Collective. `u` into the ghosted vector; returns its local form (owned, then ghosts).
    pub fn local_form(&mut self, u: &[f64]) -> Result<Vec<f64>, Error> {
        let idx: Vec<i32> = (0..self.n_owned).map(|i| (self.first + i) as i32).collect();
        self.ug.set_values(&idx, u)?;
        self.ug.assemble()?;
        self.ug.ghost_update()?;
        Ok(self.ug.with_local_form(|s| s.to_vec())?)
    }

    /// Collective. Switch the damage shells to nonlocal driving strains averaged within
    /// `radius` (analysis::nonlocal); every later evaluation refreshes the averages first.
    pub fn enable_nonlocal(
        &mut self,
        ctx: &Context,
        disc: &mut Discretization,
        mesh: &Mesh,
        model: &StructuralModel,
        radius: f64,
    ) -> Result<(), Error> {
        self.nonlocal = Some(super::nonlocal::NonlocalAveraging::setup(ctx, disc, mesh, model, radius)?);
        Ok(())
    }

    /// Collective. The averaged driving strains at the displacement of `local` (no-op for the
    /// local law).
    fn refresh_nonlocal(
        &self,
        ctx: &Context,
        disc: &mut Discretization,
        mesh: &Mesh,
        model: &StructuralModel,
        local: &[f64],
    ) -> Result<(), Error> {
        match &self.nonlocal {
            Some(nl) => nl.update(ctx, disc, mesh, model, local),
            None => Ok(()),
        }
    }

    /// Collective. f_int at `u` (all rows, owned) into `self.f_int`; elements' trial state at `u`.
    fn internal_force_at(
        &mut self,
        ctx: &Context,
        disc: &mut Discretization,
        mesh: &Mesh,
        model: &StructuralModel,
        u: &[f64],
    ) -> Result<(), Error> {
        let local = self.local_form(u)?;
        self.refresh_nonlocal(ctx, disc, mesh, model, &local)?;
        assembly::assemble_internal_forces_on(disc, mesh, model, &local, Rows::All, &mut self.fint_vec)?;
        self.f_int = self.fint_vec.owned_values()?;
        Ok(())
    }

    /// The residual on free rows, f_ext − f_int, for load factor λ and pattern factor μ.
    fn residual(&self, lambda: f64, mu: f64) -> Vec<f64> {
        (0..self.n_owned)
            .map(|i| if self.free[i] { lambda * self.f_loads[i] + mu * self.f_pattern[i] - self.f_int[i] } else { 0.0 })
            .collect()
    }

    /// Collective. The value of the pattern-control DOF (from its owner rank).
    pub fn control_value(&self, ctx: &Context, u: &[f64]) -> f64 {
        global_sum(ctx, self.control.map_or(0.0, |i| u[i]))
    }

    /// Collective. Tangent at `u`, factored; solves K x = b for each b.
    #[allow(clippy::too_many_arguments)]
    fn solve(
        &mut self,
        ctx: &Context,
        disc: &mut Discretization,
        mesh: &Mesh,
        model: &StructuralModel,
        u: &[f64],
        rhs: &[&[f64]],
        secant: bool,
    ) -> Result<Vec<Vec<f64>>, Error> {
        let local = self.local_form(u)?;
        self.refresh_nonlocal(ctx, disc, mesh, model, &local)?;
        self.k.zero_entries()?;
        let request = if secant { EvalRequest::ForceAndSecant } else { EvalRequest::ForceAndTangent };
        assembly::assemble_secant_or_tangent(disc, mesh, model, Some(&local), request, &mut self.k)?;
        self.fresh = true; // the stiffness evaluation left the trial state at u
        self.ksp.set_operators(&self.k)?;
        if !self.options_set {
            self.ksp.set_from_options()?;
            self.options_set = true;
        }
        let idx: Vec<i32> = (0..self.n_owned).map(|i| (self.first + i) as i32).collect();
        let mut out = Vec::with_capacity(rhs.len());
        for b in rhs {
            self.rhs.set_values(&idx, b)?;
            self.rhs.assemble()?;
            if let Err(e) =
                agree(&ctx.comm, self.ksp.solve(&self.rhs, &mut self.sol).map_err(Error::from), Error::exit_code)
            {
                // A failed factorization poisons the solver: PETSc's MUMPS interface skips every
                // later numeric factorization once one has failed, so every retry of a cut
                // increment would fail at its first solve. A fresh solver starts clean.
                self.ksp = new_solver(ctx)?;
                self.options_set = false;
                return Err(e.into());
            }
            out.push(self.sol.owned_values()?);
        }
        Ok(out)
    }

    /// Start an increment from the committed state: u ← u_committed with the imposed values set.
    fn start(&mut self, inc: &Increment) {
        self.u.copy_from_slice(&self.u_committed);
        self.mu = self.mu_committed;
        if let Some(v) = inc.imposed {
            for &i in &self.imposed {
                self.u[i] = v;
            }
        }
        self.fresh = false;
    }

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
        let mut outcome = NewtonOutcome {
            converged: false,
            iterations: 0,
            residual: f64::INFINITY,
            line_search_evaluations: 0,
            reason: String::new(),
        };
        let mut energy0 = 0.0f64;
        let mut reference0 = 0.0f64;
        for it in 0..set.max_iterations {
            outcome.iterations = it + 1;
            if !self.fresh {
                let u = self.u.clone();
                self.internal_force_at(ctx, disc, mesh, model, &u)?;
            }
            let r = self.residual(inc.lambda, self.mu);
            let rn = global_sum(ctx, dot(&r, &r)).sqrt();
            let ext: Vec<f64> =
                (0..self.n_owned).map(|i| inc.lambda * self.f_loads[i] + self.mu * self.f_pattern[i]).collect();
            let current =
                global_sum(ctx, dot(&ext, &ext)).sqrt().max(global_sum(ctx, dot(&self.f_int, &self.f_int)).sqrt());
            if it == 0 {
                reference0 = current;
            }
            let reference = bounded_reference(current, reference0);
            outcome.residual = if reference > 0.0 { rn / reference } else { rn };
            if !outcome.residual.is_finite() {
                outcome.reason = "the residual is not finite".into();
                return Ok(outcome);
            }
            // The control constraint holds after the first iteration (to round-off).
            let gap_ok =
                inc.control_target.is_none_or(|t| (t - self.control_value(ctx, &self.u)).abs() <= 1e-12 * t.abs());
            if gap_ok && (rn == 0.0 || outcome.residual <= set.force_tolerance) {
                outcome.converged = true;
                return Ok(outcome);
            }
            let u = self.u.clone();
            let pattern = self.f_pattern.clone();
            let sols = match inc.control_target {
                Some(_) => self.solve(ctx, disc, mesh, model, &u, &[&r, &pattern], set.secant),
                None => self.solve(ctx, disc, mesh, model, &u, &[&r], set.secant),
            };
            let sols = match sols {
                Ok(s) => s,
                // The only agreed error of `solve` is the linear solve's (a singular or
                // indefinite matrix in a softening state): the increment fails, the run goes on.
                Err(Error::Solver(e)) => {
                    outcome.reason = format!("linear solve failed: {e}");
                    return Ok(outcome);
                }
                Err(Error::Agreed(e)) => {
                    outcome.reason = format!("linear solve failed: {}", e.message);
                    return Ok(outcome);
                }
                Err(e) => return Err(e),
            };
            let mut du = sols[0].clone();
            let mut dmu = 0.0;
            if let Some(target) = inc.control_target {
                let (dr_c, dp_c) = (self.control_value(ctx, &sols[0]), self.control_value(ctx, &sols[1]));
                if dp_c == 0.0 || !dp_c.is_finite() {
                    outcome.reason = "the load pattern does not move the control DOF (K⁻¹ f_p is zero there)".into();
                    return Ok(outcome);
                }
                dmu = (target - self.control_value(ctx, &self.u) - dr_c) / dp_c;
                for (d, p) in du.iter_mut().zip(&sols[1]) {
                    *d += dmu * p;
                }
            }
            let energy = global_sum(ctx, dot(&du, &r)).abs();
            if it == 0 {
                energy0 = energy.max(f64::MIN_POSITIVE);
            } else if energy <= set.energy_tolerance * energy0 && gap_ok {
                outcome.converged = true;
                return Ok(outcome);
            }
            // Full step, then the line search if the full step is not good enough.
            let s0 = global_sum(ctx, dot(&du, &r));
            let trial: Vec<f64> = self.u.iter().zip(&du).map(|(a, b)| a + b).collect();
            self.mu += dmu;
            self.internal_force_at(ctx, disc, mesh, model, &trial)?;
            self.u = trial;
            self.fresh = true;
            if let (Some(ls), None) = (set.line_search, inc.control_target) {
                let r1 = self.residual(inc.lambda, self.mu);
                let s1 = global_sum(ctx, dot(&du, &r1));
                let base: Vec<f64> = self.u.iter().zip(&du).map(|(a, b)| a - b).collect();
                let mut last_eta = 1.0;
                let found = line_search::secant(s0, s1, &ls, |eta| -> Result<f64, Error> {
                    let x: Vec<f64> = base.iter().zip(&du).map(|(a, b)| a + eta * b).collect();
                    self.internal_force_at(ctx, disc, mesh, model, &x)?;
                    last_eta = eta;
                    let r = self.residual(inc.lambda, self.mu);
                    Ok(global_sum(ctx, dot(&du, &r)))
                })?;
                outcome.line_search_evaluations += found.evaluations;
                self.u = base.iter().zip(&du).map(|(a, b)| a + found.eta * b).collect();
                // The elements' trial state (and f_int) are those of the last evaluation.
                self.fresh = last_eta == found.eta;
            }
        }
        outcome.reason = format!("no convergence in {} iterations", set.max_iterations);
        Ok(outcome)
    }

    /// Collective. Accept the current state: trial state brought to u, then committed.
    pub fn commit(
        &mut self,
        ctx: &Context,
        disc: &mut Discretization,
        mesh: &Mesh,
        model: &StructuralModel,
    ) -> Result<(), Error> {
        if !self.fresh {
            let u = self.u.clone();
            self.internal_force_at(ctx, disc, mesh, model, &u)?;
        }
        for e in disc.elements.iter_mut() {
            e.commit();
        }
        self.u_committed.copy_from_slice(&self.u);
        self.mu_committed = self.mu;
        Ok(())
    }

    /// Discard the increment: elements back to their committed state.
    pub fn revert(&mut self, disc: &mut Discretization) {
        for e in disc.elements.iter_mut() {
            e.revert();
        }
        self.fresh = false;
    }

    /// Collective. The force at the control: the sum of f_int over the imposed DOFs (the reaction
    /// the imposed displacement needs), or μ times the pattern's resultant along the DOF.
    pub fn control_force(&self, ctx: &Context, pattern_resultant: f64) -> f64 {
        if self.control.is_some() || pattern_resultant != 0.0 {
            self.mu * pattern_resultant
        } else {
            global_sum(ctx, self.imposed.iter().map(|&i| self.f_int[i]).sum())
        }
    }

    /// The residual at the current state (owned, free rows).
    pub fn current_residual(&self, lambda: f64) -> Vec<f64> {
        self.residual(lambda, self.mu)
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
