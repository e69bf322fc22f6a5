//! The nonlinear static system of one rank: the owned values of u and of the load vectors
//! (the job's loads f_c, the control pattern f_p), the imposed and control DOFs, the PETSc
//! objects, and the operations Newton's method (analysis::newton) is made of: f_int(u), the
//! residual `r = λ f_c + μ f_p − f_int(u)` on free rows, the tangent (or secant) solves.
//!
//! Elements evaluate from their committed state at the total displacement and keep the result
//! as their trial state; `fresh` says whether that trial state (and f_int) is the one of `u`,
//! and [`NonlinearSystem::commit`] makes sure it is before committing.
use super::assembly::{self, Rows};
use super::Discretization;
use crate::element::EvalRequest;
use crate::error::Error;
use crate::mesh::Mesh;
use crate::model::StructuralModel;
use crate::parallel::{agree, Context};
use crate::petsc::{Ksp, Matrix, Vector};

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
    /// The elements' trial state and `f_int` are those of `u`.
    pub(super) fresh: bool,
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

pub use crate::parallel::global_sum;

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

/// Collective. The linear solver: MUMPS LU (the options database is applied at the first solve).
fn new_solver(ctx: &Context) -> Result<Ksp, Error> {
    let mut ksp = Ksp::new(&ctx.comm, "")?;
    ksp.set_type("preonly")?;
    ksp.set_pc_type("lu")?;
    ksp.set_factor_solver("mumps")?;
    Ok(ksp)
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
    pub(super) fn internal_force_at(
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
    pub(super) fn residual(&self, lambda: f64, mu: f64) -> Vec<f64> {
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
    pub(super) fn solve(
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
    pub(super) fn start(&mut self, inc: &Increment) {
        self.u.copy_from_slice(&self.u_committed);
        self.mu = self.mu_committed;
        if let Some(v) = inc.imposed {
            for &i in &self.imposed {
                self.u[i] = v;
            }
        }
        self.fresh = false;
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
