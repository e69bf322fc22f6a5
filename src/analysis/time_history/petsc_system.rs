//! The distributed structural model as a [`DynamicSystem`]: PETSc matrices and KSP, the rank's
//! elements, ghosted displacements.
//!
//! Matrices: `M` (mass, free rows only), `K₀` (initial stiffness, assembled before gravity, for
//! Rayleigh damping and the `initial` Newton variant) and `J = K + c_m M + c_c C` with
//! `C = α M + β K₀`, i.e. `J = K + (c_m + c_c α) M + c_c β K₀`. `J` is factored (default: MUMPS
//! LU, or Cholesky when every element is linear; any `-ksp_type`/`-pc_type` from the command
//! line or `[solver.petsc]` wins) and the factorization is kept — `KSPSetOperators` is simply not
//! called again — as long as `J` cannot have changed: same coefficients and either a linear model
//! or the initial stiffness. Modified Newton calls [`DynamicSystem::prepare`] once per step, so
//! the factorization is reused across its iterations.
//!
//! For a linear model (no element has state) the internal force is the product `K₀ u`.
//!
//! Element errors (a material update that fails) happen on one rank: the loops below record the
//! first one, still take part in every collective call, and the ranks then agree on it, so a
//! failing element makes the step fail on every rank (and be substepped), never hang.
use super::damping::Rayleigh;
use super::system::DynamicSystem;
use crate::analysis::assembly::{self, Rows};
use crate::analysis::{Discretization, FeProblem};
use crate::element::{ElementOutput, EvalRequest, MassKind};
use crate::error::Error;
use crate::mesh::Mesh;
use crate::model::StructuralModel;
use crate::parallel::{agree, timed, Context, Phases};
use crate::petsc::{Ksp, Matrix, Vector};
use mpi::traits::CommunicatorCollectives;
use std::collections::HashMap;

/// The model as a dynamic system on the ranks of `ctx`.
pub struct PetscSystem<'a> {
    ctx: &'a Context,
    mesh: &'a Mesh,
    model: &'a StructuralModel,
    /// Partition, numbering and the owned elements.
    pub disc: Discretization,
    m: Matrix,
    k0: Matrix,
    j: Matrix,
    ksp: Ksp,
    rayleigh: Rayleigh,
    x: Vector,
    y: Vector,
    ug: Vector,
    idx: Vec<i32>,
    local: HashMap<usize, usize>,
    iota: [Vec<f64>; 3],
    m_iota: [Vec<f64>; 3],
    f_static: Vec<f64>,
    /// True when no element has state: the tangent is K₀ everywhere.
    pub linear: bool,
    /// `M`'s diagonal (owned rows) when `M` is diagonal (a lumped mass): `M x` is then a scaling.
    m_diagonal: Option<Vec<f64>>,
    key: Option<(u64, u64, bool)>,
    /// Factorizations (operator changes) so far.
    pub factorizations: usize,
    /// Linear solves so far.
    pub solves: usize,
    /// `[dynamics] damage_relaxation_time` (viscous damage in the time history).
    relaxation_time: Option<f64>,
    /// Wall time of the system's work: the Jacobian assemblies (`"assemble"`), the first solve
    /// after each (`"factorize"`: the numeric factorization and one solve), the other solves
    /// (`"solve"`), the internal-force evaluations (`"internal_force"`: the elements' state
    /// updates and the assembly of their forces), and the points' histories outside them
    /// (`"histories"`: commit, revert, and IMPL-EX's extrapolation, settling and holding).
    pub phases: Phases,
    /// The next solve is the first with a new operator (it factorizes).
    fresh_operator: bool,
}

/// Collective. `M`'s diagonal (owned rows) when `M` is diagonal, else none: `d = M 1` (the row
/// sums), accepted when `M x = d ∘ x` holds bit for bit on every rank for an `x` with distinct
/// entries (a diagonal `M` stored with explicit zeros off the diagonal adds exact zeros).
fn diagonal_of(
    ctx: &Context,
    m: &Matrix,
    idx: &[i32],
    x: &mut Vector,
    y: &mut Vector,
) -> Result<Option<Vec<f64>>, Error> {
    let n = idx.len();
    x.set_values(idx, &vec![1.0; n])?;
    x.assemble()?;
    m.mult(x, y)?;
    let d = y.owned_values()?;
    let probe: Vec<f64> = idx.iter().map(|&i| 1.0 + (i as f64 * 0.618_033_988_749_895).fract()).collect();
    x.set_values(idx, &probe)?;
    x.assemble()?;
    m.mult(x, y)?;
    let mx = y.owned_values()?;
    let local = mx.iter().zip(&d).zip(&probe).all(|((m, d), p)| *m == d * p);
    Ok(crate::parallel::all_ranks(ctx, local).then_some(d))
}

/// The linear solver: MUMPS LU (Cholesky for a linear model), then the options.
fn new_solver(ctx: &Context, linear: bool) -> Result<Ksp, Error> {
    let mut ksp = Ksp::new(&ctx.comm, "")?;
    ksp.set_type("preonly")?;
    ksp.set_pc_type(if linear { "cholesky" } else { "lu" })?;
    ksp.set_factor_solver("mumps")?;
    ksp.set_from_options()?;
    Ok(ksp)
}

impl<'a> PetscSystem<'a> {
    /// Collective. The system of problem `p` (its elements' committed state is the system's
    /// starting state): assembles `M`, `K₀`, the static load and the influence vectors, and
    /// creates the solver (options read now, under no prefix).
    pub fn on(p: FeProblem<'a>, mass: MassKind, rayleigh: Rayleigh) -> Result<PetscSystem<'a>, Error> {
        let FeProblem { ctx, job, mesh, model, mut disc, .. } = p;
        let n = disc.dofs.n_owned_dofs();
        let format = job.spec.solver.matrix;
        let mut m = disc.new_matrix(ctx, mesh, model, format)?;
        let mut k0 = disc.new_matrix(ctx, mesh, model, format)?;
        let mut j = disc.new_matrix(ctx, mesh, model, format)?;
        assembly::assemble_mass(&disc, mesh, model, mass, &mut m)?;
        assembly::assemble_stiffness(&mut disc, mesh, model, None, &mut k0)?;
        assembly::assemble_stiffness(&mut disc, mesh, model, None, &mut j)?;
        j.set_near_null_space(&ctx.comm, crate::analysis::rigid_body_modes(ctx, mesh, &disc.dofs)?)?;
        for e in disc.elements.iter_mut() {
            e.revert();
        }
        let nonlinear_local = disc.elements.iter().filter(|e| e.n_state() > 0).count() as u64;
        let mut nonlinear = 0u64;
        ctx.comm.all_reduce_into(&nonlinear_local, &mut nonlinear, mpi::collective::SystemOperation::sum());
        let linear = nonlinear == 0;
        let ksp = new_solver(ctx, linear)?;
        let first = (6 * disc.dofs.node_offset()) as i32;
        let idx: Vec<i32> = (0..n as i32).map(|i| first + i).collect();
        let mut x = Vector::new_mpi(&ctx.comm, n, None)?;
        let mut y = Vector::new_mpi(&ctx.comm, n, None)?;
        let ug = Vector::new_ghosted(&ctx.comm, n, &disc.dofs.ghost_dofs())?;
        let mut iota: [Vec<f64>; 3] = Default::default();
        let mut m_iota: [Vec<f64>; 3] = Default::default();
        for d in 0..3 {
            let mut v = vec![0.0; n];
            for (i, &node) in disc.dofs.owned.iter().enumerate() {
                if !disc.dofs.is_fixed(node, d) {
                    v[6 * i + d] = 1.0;
                }
            }
            x.set_values(&idx, &v)?;
            x.assemble()?;
            m.mult(&x, &mut y)?;
            m_iota[d] = y.owned_values()?;
            iota[d] = v;
        }
        let m_diagonal = diagonal_of(ctx, &m, &idx, &mut x, &mut y)?;
        assembly::assemble_loads(&disc, mesh, model, Rows::Free, &mut y)?;
        let f_static = y.owned_values()?;
        let local = disc.dofs.local_index();
        Ok(PetscSystem {
            ctx,
            mesh,
            model,
            disc,
            m,
            k0,
            j,
            ksp,
            rayleigh,
            x,
            y,
            ug,
            idx,
            local,
            iota,
            m_iota,
            f_static,
            linear,
            m_diagonal,
            key: None,
            factorizations: 0,
            solves: 0,
            relaxation_time: job.spec.dynamics.as_ref().and_then(|d| d.damage_relaxation_time),
            fresh_operator: false,
            phases: Phases::default(),
        })
    }

    /// Collective. IMPL-EX on (with the split where `split` says) or off (`None`) in every
    /// element (`Element::set_implex`): on, each keeps its histories one step back from its
    /// committed state on. With IMPL-EX on and every element's tangent symmetric at fixed damage
    /// (`Element::implex_tangent_symmetric`), `J` is symmetric positive definite and MUMPS
    /// factors it by Cholesky (LDLᵀ: about half the flops and the memory of LU), unless the
    /// options chose the preconditioner; the next `prepare` forms `J` afresh. Returns whether
    /// it switched to Cholesky.
    pub fn set_implex(&mut self, split: Option<crate::material::implex::SplitAt>) -> Result<bool, Error> {
        for e in self.disc.elements.iter_mut() {
            e.set_implex(split);
        }
        let symmetric = split.is_some()
            && crate::parallel::all_ranks(self.ctx, self.disc.elements.iter().all(|e| e.implex_tangent_symmetric()));
        if !symmetric || self.linear || self.ksp.pc_type_in_options()? {
            return Ok(false);
        }
        self.ksp.set_pc_type("cholesky")?;
        self.ksp.set_factor_solver("mumps")?;
        self.ksp.set_from_options()?;
        self.key = None;
        Ok(true)
    }

    /// The solver in one line.
    pub fn describe_solver(&self) -> String {
        self.ksp.describe().unwrap_or_else(|e| e.to_string())
    }

    /// Collective. The local form (owned, then ghosts) of the owned vector `u`.
    pub fn local_form(&mut self, u: &[f64]) -> Result<Vec<f64>, Error> {
        self.ug.copy_owned_from(u)?;
        self.ug.ghost_update()?;
        Ok(self.ug.with_local_form(|s| s.to_vec())?)
    }

    /// The element DOF values of local cell `i` from a local-form vector.
    fn gather(&self, i: usize, u_local: &[f64], u_e: &mut Vec<f64>) {
        let cell = &self.mesh.cells[self.model.cells[self.disc.local_cells[i]].cell];
        u_e.clear();
        for n in &cell.nodes {
            let l = self.local[n];
            u_e.extend_from_slice(&u_local[6 * l..6 * l + 6]);
        }
    }

    /// Collective. Adds the tangent at `u_local` into `self.j` (zeroed first) and assembles it;
    /// element errors are agreed across ranks after the collective assembly.
    fn assemble_tangent(&mut self, u_local: &[f64]) -> Result<(), Error> {
        self.j.zero_entries()?;
        let mut out = ElementOutput::new(12);
        let (mut free, mut all, mut u_e, mut rows) = (Vec::new(), Vec::new(), Vec::new(), Vec::new());
        let mut first_err: Option<Error> = None;
        for i in 0..self.disc.local_cells.len() {
            let cell = &self.mesh.cells[self.model.cells[self.disc.local_cells[i]].cell];
            self.disc.element_equations(&cell.nodes, &mut free, &mut all);
            self.gather(i, u_local, &mut u_e);
            if let Err(source) = self.disc.elements[i].evaluate(&u_e, EvalRequest::ForceAndTangent, &mut out) {
                first_err.get_or_insert(Error::Element { tag: cell.tag, group: String::new(), source });
                continue;
            }
            let n = free.len();
            rows.clear();
            for r in 0..n {
                for c in 0..n {
                    rows.push(out.k_t[(r, c)]);
                }
            }
            self.j.add_values(&free, &free, &rows)?;
            for r in 0..n {
                if free[r] < 0 {
                    self.j.add_values(&all[r..r + 1], &all[r..r + 1], &[out.k_t[(r, r)]])?;
                }
            }
        }
        self.j.assemble()?;
        agree(&self.ctx.comm, first_err.map_or(Ok(()), Err), Error::exit_code)?;
        Ok(())
    }

    /// Collective. `J = K + c_m M + c_c (α M + β K₀)` with `K` the tangent at `tangent_at` (`K₀`
    /// without one, or for a linear model), set as the solver's operator.
    fn assemble_jacobian(&mut self, tangent_at: Option<&[f64]>, c_m: f64, c_c: f64) -> Result<(), Error> {
        let Rayleigh { alpha, beta } = self.rayleigh;
        match tangent_at {
            Some(u) if !self.linear => {
                let u_local = self.local_form(u)?;
                self.assemble_tangent(&u_local)?;
                self.j.axpy(c_c * beta, &self.k0)?;
            }
            _ => {
                self.j.zero_entries()?;
                self.j.axpy(1.0 + c_c * beta, &self.k0)?;
            }
        }
        self.j.axpy(c_m + c_c * alpha, &self.m)?;
        self.ksp.set_operators(&self.j)?;
        Ok(())
    }

    /// Collective. `M x`, `K₀ x` (fixed rows zeroed, as `f_int`) and `C x = α M x + β K₀ x`
    /// ([`DynamicSystem::products`]). From a solve of a linear model, `J x = r` with
    /// `J = (1 + c_c β) K₀ + (c_m + c_c α) M` gives `K₀ x = (r − (c_m + c_c α) M x) / (1 + c_c β)`:
    /// `M x` is the only product. Otherwise two.
    fn products_owned(
        &mut self,
        x: &[f64],
        solved: Option<&[f64]>,
        mx: &mut [f64],
        kx: &mut [f64],
        cx: &mut [f64],
    ) -> Result<(), Error> {
        self.x.copy_owned_from(x)?;
        match &self.m_diagonal {
            Some(d) => {
                for i in 0..mx.len() {
                    mx[i] = d[i] * x[i];
                }
            }
            None => {
                self.m.mult(&self.x, &mut self.y)?;
                self.y.with_owned_values(|s| mx.copy_from_slice(s))?;
            }
        }
        let Rayleigh { alpha, beta } = self.rayleigh;
        match (solved, self.key) {
            (Some(r), Some((c_m, c_c, true))) if self.linear => {
                let (c_m, c_c) = (f64::from_bits(c_m), f64::from_bits(c_c));
                let (a, b) = (c_m + c_c * alpha, 1.0 + c_c * beta);
                for i in 0..kx.len() {
                    kx[i] = (r[i] - a * mx[i]) / b;
                }
            }
            _ => {
                self.k0.mult(&self.x, &mut self.y)?;
                self.y.with_owned_values(|s| kx.copy_from_slice(s))?;
            }
        }
        for i in 0..cx.len() {
            cx[i] = alpha * mx[i] + beta * kx[i];
        }
        self.zero_fixed(kx);
        Ok(())
    }

    /// Zeroes the fixed DOFs' entries of an owned vector.
    fn zero_fixed(&self, f: &mut [f64]) {
        for (i, &node) in self.disc.dofs.owned.iter().enumerate() {
            for d in 0..6 {
                if self.disc.dofs.is_fixed(node, d) {
                    f[6 * i + d] = 0.0;
                }
            }
        }
    }

    /// Collective. `f_int(u)` on the owned equations ([`DynamicSystem::internal_force`]).
    fn internal_force_owned(&mut self, u: &[f64], f: &mut [f64]) -> Result<(), Error> {
        if self.linear {
            // No element has state: f_int(u) = K₀ u on the free rows (K₀'s fixed rows hold only
            // their diagonal and u vanishes there), one sparse product instead of an element loop.
            self.x.copy_owned_from(u)?;
            self.k0.mult(&self.x, &mut self.y)?;
            self.y.with_owned_values(|s| f.copy_from_slice(s))?;
            self.zero_fixed(f);
            return Ok(());
        }
        let u_local = self.local_form(u)?;
        self.y.set_all(0.0)?;
        let mut out = ElementOutput::new(12);
        let (mut free, mut all, mut u_e) = (Vec::new(), Vec::new(), Vec::new());
        let mut first_err: Option<Error> = None;
        for i in 0..self.disc.local_cells.len() {
            let cell = &self.mesh.cells[self.model.cells[self.disc.local_cells[i]].cell];
            self.disc.element_equations(&cell.nodes, &mut free, &mut all);
            self.gather(i, &u_local, &mut u_e);
            match self.disc.elements[i].evaluate(&u_e, EvalRequest::Force, &mut out) {
                Ok(()) => self.y.add_values(&free, out.f_int.as_slice())?,
                Err(source) => {
                    first_err.get_or_insert(Error::Element { tag: cell.tag, group: String::new(), source });
                }
            }
        }
        self.y.assemble()?;
        agree(&self.ctx.comm, first_err.map_or(Ok(()), Err), Error::exit_code)?;
        self.y.with_owned_values(|s| f.copy_from_slice(s))?;
        Ok(())
    }

    /// Collective. Solves `J x = r` (owned values). A failed solve replaces the solver.
    fn solve_owned(&mut self, r: &[f64], x: &mut [f64]) -> Result<(), Error> {
        self.x.copy_owned_from(r)?;
        let solved = self.ksp.solve(&self.x, &mut self.y).map_err(Error::from);
        if let Err(e) = agree(&self.ctx.comm, solved, Error::exit_code) {
            // A failed factorization poisons the solver: PETSc's MUMPS interface skips every
            // later numeric factorization of the same factor once one has failed (INFOG(1) < 0
            // stays set), so every retry of a cut step would fail at its first solve. A fresh
            // solver (and the next `prepare` assembling J again) starts clean.
            self.ksp = new_solver(self.ctx, self.linear)?;
            self.key = None;
            return Err(e.into());
        }
        self.y.with_owned_values(|s| x.copy_from_slice(s))?;
        self.solves += 1;
        Ok(())
    }
}

impl DynamicSystem for PetscSystem<'_> {
    fn len(&self) -> usize {
        self.idx.len()
    }

    fn dot(&self, a: &[f64], b: &[f64]) -> f64 {
        let local: f64 = a.iter().zip(b).map(|(x, y)| x * y).sum();
        let mut global = 0.0;
        self.ctx.comm.all_reduce_into(&local, &mut global, mpi::collective::SystemOperation::sum());
        global
    }

    fn dots(&self, pairs: &[(&[f64], &[f64])]) -> Vec<f64> {
        let local: Vec<f64> = pairs.iter().map(|(a, b)| a.iter().zip(b.iter()).map(|(x, y)| x * y).sum()).collect();
        let mut global = vec![0.0; local.len()];
        self.ctx.comm.all_reduce_into(&local[..], &mut global[..], mpi::collective::SystemOperation::sum());
        global
    }

    fn mass_mult(&mut self, x: &[f64], y: &mut [f64]) -> Result<(), Error> {
        if let Some(d) = &self.m_diagonal {
            for i in 0..y.len() {
                y[i] = d[i] * x[i];
            }
            return Ok(());
        }
        self.x.copy_owned_from(x)?;
        self.m.mult(&self.x, &mut self.y)?;
        self.y.with_owned_values(|s| y.copy_from_slice(s))?;
        Ok(())
    }

    fn damping_mult(&mut self, x: &[f64], y: &mut [f64]) -> Result<(), Error> {
        let Rayleigh { alpha, beta } = self.rayleigh;
        if alpha == 0.0 && beta == 0.0 {
            y.iter_mut().for_each(|v| *v = 0.0);
            return Ok(());
        }
        self.x.copy_owned_from(x)?;
        self.m.mult(&self.x, &mut self.y)?;
        let my = self.y.owned_values()?;
        self.k0.mult(&self.x, &mut self.y)?;
        self.y.with_owned_values(|ky| {
            for i in 0..y.len() {
                y[i] = alpha * my[i] + beta * ky[i];
            }
        })?;
        Ok(())
    }

    fn mass_influence(&self, d: usize) -> &[f64] {
        &self.m_iota[d]
    }

    fn influence(&self, d: usize) -> &[f64] {
        &self.iota[d]
    }

    fn static_load(&self) -> &[f64] {
        &self.f_static
    }

    fn is_linear(&self) -> bool {
        self.linear
    }

    fn products(
        &mut self,
        x: &[f64],
        solved: Option<&[f64]>,
        mx: &mut [f64],
        kx: &mut [f64],
        cx: &mut [f64],
    ) -> Result<(), Error> {
        let (done, seconds) = timed(|| self.products_owned(x, solved, mx, kx, cx));
        self.phases.add("products", seconds);
        done
    }

    fn internal_force(&mut self, u: &[f64], f: &mut [f64]) -> Result<(), Error> {
        let (done, seconds) = timed(|| self.internal_force_owned(u, f));
        self.phases.add("internal_force", seconds);
        done
    }

    fn prepare(&mut self, tangent_at: Option<&[f64]>, c_m: f64, c_c: f64) -> Result<(), Error> {
        let initial = tangent_at.is_none() || self.linear;
        let key = (c_m.to_bits(), c_c.to_bits(), initial);
        if initial && self.key == Some(key) {
            return Ok(());
        }
        let (assembled, seconds) = timed(|| self.assemble_jacobian(tangent_at, c_m, c_c));
        self.phases.add("assemble", seconds);
        assembled?;
        self.factorizations += 1;
        self.fresh_operator = true;
        self.key = Some(key);
        Ok(())
    }

    fn solve(&mut self, r: &[f64], x: &mut [f64]) -> Result<(), Error> {
        let (solved, seconds) = timed(|| self.solve_owned(r, x));
        self.phases.add(if self.fresh_operator { "factorize" } else { "solve" }, seconds);
        self.fresh_operator = false;
        solved
    }

    fn dissipated_energy(&self) -> f64 {
        let local: f64 = self.disc.elements.iter().map(|e| e.dissipated_energy()).sum();
        let mut global = 0.0;
        self.ctx.comm.all_reduce_into(&local, &mut global, mpi::collective::SystemOperation::sum());
        global
    }

    /// Collective: one max-reduction over the ranks.
    fn max_damage_increment(&self) -> f64 {
        let local = self.disc.elements.iter().fold(0.0f64, |m, e| m.max(e.damage_increment()));
        let mut global = 0.0;
        self.ctx.comm.all_reduce_into(&local, &mut global, mpi::collective::SystemOperation::max());
        global
    }

    fn set_implex_step(&mut self, h: f64) {
        let ((), seconds) = timed(|| self.disc.elements.iter_mut().for_each(|e| e.set_implex_step(h)));
        self.phases.add("histories", seconds);
    }

    fn update_histories(&mut self) {
        let ((), seconds) = timed(|| self.disc.elements.iter_mut().for_each(|e| e.settle_implex()));
        self.phases.add("histories", seconds);
    }

    /// Collective: one max-reduction over the ranks.
    fn hold_histories(&mut self) -> f64 {
        let (local, seconds) =
            timed(|| self.disc.elements.iter_mut().map(|e| e.hold_implex_histories()).fold(0.0, f64::max));
        self.phases.add("histories", seconds);
        let mut global = 0.0f64;
        self.ctx.comm.all_reduce_into(&local, &mut global, mpi::collective::SystemOperation::max());
        global
    }

    fn set_step_size(&mut self, h: f64) {
        if self.relaxation_time.is_some() {
            for e in self.disc.elements.iter_mut() {
                e.set_damage_relaxation(h, self.relaxation_time);
            }
        }
    }

    fn commit(&mut self) {
        let ((), seconds) = timed(|| self.disc.elements.iter_mut().for_each(|e| e.commit()));
        self.phases.add("histories", seconds);
    }

    fn revert(&mut self) {
        let ((), seconds) = timed(|| self.disc.elements.iter_mut().for_each(|e| e.revert()));
        self.phases.add("histories", seconds);
    }
}
