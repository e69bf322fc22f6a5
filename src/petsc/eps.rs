//! [`Eps`]: a SLEPc eigensolver for `K·φ = λ·M·φ` (modal analysis: K stiffness, M mass).
//!
//! With `M` given, the problem is generalized Hermitian (`EPS_GHEP`: K symmetric, M symmetric
//! positive (semi)definite) and the eigenvectors come back M-normalized, φᵀ·M·φ = 1; without `M`
//! it is the standard Hermitian problem and ‖φ‖₂ = 1. Shift-and-invert about σ solves
//! `(K − σM)⁻¹·M·φ = θ·φ`, θ = 1/(λ − σ), whose largest θ are the λ nearest σ: the way to get the
//! lowest modes fast (σ = 0 or just below the first frequency²). Its inner linear solver is
//! configured under the prefix with `st_` (e.g. `-modal_st_pc_factor_mat_solver_type mumps`, needed
//! in parallel where PETSc's own LU is sequential), or with [`Eps::set_st_factor`].

use std::ffi::c_void;

use super::error::{petsc_call, PetscError};
use super::matrix::Matrix;
use super::options::c_string;
use super::runtime::{ensure_running, is_running};
use super::vector::Vector;
use super::{sys, to_usize, type_name, PetscComm};

/// A SLEPc `EPS`; destroyed (`EPSDestroy`) when dropped.
pub struct Eps {
    raw: sys::EPS,
    /// `(K, M)` are set: `solve` needs them for the eigenvector layout.
    has_operators: bool,
}

impl Eps {
    /// An eigensolver on `comm` reading options under `prefix` (`""` for none). Collective.
    pub fn new(comm: &impl PetscComm, prefix: &str) -> Result<Eps, PetscError> {
        ensure_running("Eps::new")?;
        let c_prefix = c_string(prefix, "EPSSetOptionsPrefix")?;
        let mut e = Eps { raw: std::ptr::null_mut(), has_operators: false };
        petsc_call!(EPSCreate(comm.as_raw(), &mut e.raw))?;
        if !prefix.is_empty() {
            petsc_call!(EPSSetOptionsPrefix(e.raw, c_prefix.as_ptr()))?;
        }
        Ok(e)
    }

    /// The raw SLEPc handle (still owned by `self`).
    pub fn as_raw(&self) -> sys::EPS {
        self.raw
    }

    /// Sets `K` and, for the generalized problem, `M`; selects `EPS_GHEP` with `M`, `EPS_HEP`
    /// without. SLEPc keeps references, so the matrices may be dropped first. Collective.
    pub fn set_operators(&mut self, k: &Matrix, m: Option<&Matrix>) -> Result<(), PetscError> {
        let m_raw = m.map_or(std::ptr::null_mut(), Matrix::as_raw);
        petsc_call!(EPSSetOperators(self.raw, k.as_raw(), m_raw))?;
        let kind = if m.is_some() { sys::EPS_GHEP } else { sys::EPS_HEP };
        petsc_call!(EPSSetProblemType(self.raw, kind))?;
        self.has_operators = true;
        Ok(())
    }

    /// Shift-and-invert about `sigma` (`STSINVERT`, target σ, eigenvalues nearest σ in
    /// magnitude first). Collective.
    pub fn set_shift_invert(&mut self, sigma: f64) -> Result<(), PetscError> {
        let st = self.st()?;
        petsc_call!(STSetType(st, type_name(sys::STSINVERT)))?;
        petsc_call!(EPSSetTarget(self.raw, sigma))?;
        petsc_call!(EPSSetWhichEigenpairs(self.raw, sys::EPS_TARGET_MAGNITUDE))
    }

    /// Direct inner solve of the spectral transformation: `preonly` + `pc_type` (`"lu"` or
    /// `"cholesky"`) from the factorization package `solver` (e.g. `"mumps"`). Collective.
    pub fn set_st_factor(&mut self, pc_type: &str, solver: &str) -> Result<(), PetscError> {
        let c_pc = c_string(pc_type, "PCSetType")?;
        let c_solver = c_string(solver, "PCFactorSetMatSolverType")?;
        let mut ksp: sys::KSP = std::ptr::null_mut();
        petsc_call!(STGetKSP(self.st()?, &mut ksp))?;
        petsc_call!(KSPSetType(ksp, type_name(sys::KSPPREONLY)))?;
        let mut pc: sys::PC = std::ptr::null_mut();
        petsc_call!(KSPGetPC(ksp, &mut pc))?;
        petsc_call!(PCSetType(pc, c_pc.as_ptr()))?;
        petsc_call!(PCFactorSetMatSolverType(pc, c_solver.as_ptr()))
    }

    /// The spectral transformation (owned by the EPS).
    fn st(&self) -> Result<sys::ST, PetscError> {
        let mut st: sys::ST = std::ptr::null_mut();
        petsc_call!(EPSGetST(self.raw, &mut st))?;
        Ok(st)
    }

    /// Number of eigenpairs wanted (`nev`; SLEPc picks the subspace size). Collective.
    pub fn set_dimensions(&mut self, nev: usize) -> Result<(), PetscError> {
        let n = super::to_petsc_int(nev, "EPSSetDimensions", "nev")?;
        petsc_call!(EPSSetDimensions(self.raw, n, sys::PETSC_DEFAULT, sys::PETSC_DEFAULT))
    }

    /// Convergence tolerance (relative residual ‖Kφ − λMφ‖/|λ| by default) and iteration cap.
    pub fn set_tolerances(&mut self, tol: f64, max_it: i32) -> Result<(), PetscError> {
        petsc_call!(EPSSetTolerances(self.raw, tol, max_it))
    }

    /// The Krylov method's starting vector (`EPSSetInitialSpace` with one vector; by default
    /// SLEPc draws a random one). Collective.
    pub fn set_initial_vector(&mut self, v: &Vector) -> Result<(), PetscError> {
        let mut raw = [v.as_raw()];
        petsc_call!(EPSSetInitialSpace(self.raw, 1, raw.as_mut_ptr()))
    }

    /// Whether the eigenvectors of a generalized problem are purified (`EPSSetPurify`, on by
    /// default): one more application of the operator to each, which removes their components
    /// along the null space of `M` (the infinite eigenvalues). Collective.
    pub fn set_purify(&mut self, purify: bool) -> Result<(), PetscError> {
        petsc_call!(EPSSetPurify(self.raw, if purify { sys::PETSC_TRUE } else { sys::PETSC_FALSE }))
    }

    /// Reads the options database under the prefix; call it LAST so the command line wins.
    pub fn set_from_options(&mut self) -> Result<(), PetscError> {
        petsc_call!(EPSSetFromOptions(self.raw))
    }

    /// Solves and returns the `nev` wanted eigenpairs `(λ, φ)` sorted by ascending λ.
    ///
    /// Errors: a failed call, or fewer than `nev` converged pairs (`PETSC_ERR_NOT_CONVERGED`,
    /// saying how many did and SLEPc's reason). Collective.
    pub fn solve(&mut self) -> Result<std::vec::Vec<(f64, Vector)>, PetscError> {
        const CALL: &str = "Eps::solve";
        if !self.has_operators {
            return Err(PetscError::usage(sys::PETSC_ERR_ORDER, CALL, "set_operators was not called"));
        }
        petsc_call!(EPSSolve(self.raw))?;
        let (mut nev, mut ncv, mut mpd) = (0, 0, 0);
        petsc_call!(EPSGetDimensions(self.raw, &mut nev, &mut ncv, &mut mpd))?;
        let mut nconv = 0;
        petsc_call!(EPSGetConverged(self.raw, &mut nconv))?;
        if nconv < nev {
            let mut reason: sys::EPSConvergedReason = 0;
            petsc_call!(EPSGetConvergedReason(self.raw, &mut reason))?;
            let mut its = 0;
            petsc_call!(EPSGetIterationNumber(self.raw, &mut its))?;
            return Err(PetscError::usage(
                sys::PETSC_ERR_NOT_CONVERGED,
                CALL,
                format!(
                    "only {nconv} of {nev} eigenpairs converged after {its} iterations \
                     (EPSConvergedReason {reason})"
                ),
            ));
        }
        let mut k: sys::Mat = std::ptr::null_mut();
        let mut m: sys::Mat = std::ptr::null_mut();
        petsc_call!(EPSGetOperators(self.raw, &mut k, &mut m))?;
        let mut pairs = std::vec::Vec::with_capacity(to_usize(nev));
        for i in 0..nev {
            let mut raw_vec: sys::Vec = std::ptr::null_mut();
            petsc_call!(MatCreateVecs(k, &mut raw_vec, std::ptr::null_mut()))?;
            let phi = Vector::adopt(raw_vec)?;
            let (mut re, mut im) = (0.0, 0.0);
            petsc_call!(EPSGetEigenpair(self.raw, i, &mut re, &mut im, phi.as_raw(), std::ptr::null_mut()))?;
            pairs.push((re, phi));
        }
        pairs.sort_by(|a, b| a.0.total_cmp(&b.0));
        Ok(pairs)
    }
}

impl Drop for Eps {
    /// `EPSDestroy` (collective). A solver outliving SLEPc is leaked instead.
    fn drop(&mut self) {
        if !self.raw.is_null() && is_running() {
            // SAFETY: `raw` is a live EPS owned by this value.
            let _ = unsafe { sys::EPSDestroy(&mut self.raw) };
        }
    }
}

impl std::fmt::Debug for Eps {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("Eps").field("raw", &self.raw.cast::<c_void>()).finish()
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::petsc::matrix::test_matrices::laplacian_1d;
    use crate::petsc::testing::with_petsc;

    #[test]
    fn lowest_modes_of_1d_laplacian_by_shift_invert() {
        with_petsc(|comm| {
            const N: usize = 50;
            const NEV: usize = 4;
            let mut k = laplacian_1d(comm, N);
            k.set_option_symmetric(true).unwrap();
            // M = I, as a sparse diagonal matrix.
            let mut m = Matrix::new_aij(comm, N, &[1; N], &[0; N]).unwrap();
            for i in 0..N as i32 {
                m.add_values(&[i], &[i], &[1.0]).unwrap();
            }
            m.assemble().unwrap();
            m.set_option_symmetric(true).unwrap();

            let mut eps = Eps::new(comm, "modaltest_").unwrap();
            eps.set_operators(&k, Some(&m)).unwrap();
            eps.set_shift_invert(0.0).unwrap();
            eps.set_st_factor("cholesky", "petsc").unwrap();
            eps.set_dimensions(NEV).unwrap();
            eps.set_tolerances(1e-12, 1000).unwrap();
            eps.set_from_options().unwrap();
            let pairs = eps.solve().unwrap();
            assert_eq!(pairs.len(), NEV);
            for (idx, (lambda, phi)) in pairs.iter().enumerate() {
                // Eigenvalues of tridiag(−1, 2, −1) of order n: λ_k = 2 − 2cos(kπ/(n+1)), k = 1..n
                // (e.g. Strang, Computational Science and Engineering, §1.5).
                let kk = (idx + 1) as f64;
                let exact = 2.0 - 2.0 * (kk * std::f64::consts::PI / (N as f64 + 1.0)).cos();
                assert!(((lambda - exact) / exact).abs() < 1e-10, "λ_{kk} = {lambda}, exact {exact}");
                // M = I: M-normalized means unit 2-norm.
                assert!((phi.norm2().unwrap() - 1.0).abs() < 1e-10);
                // Residual ‖Kφ − λφ‖ small.
                let (_, mut r) = k.create_vectors().unwrap();
                k.mult(phi, &mut r).unwrap();
                r.axpy(-lambda, phi).unwrap();
                assert!(r.norm2().unwrap() < 1e-9);
            }
        });
    }

    #[test]
    fn solve_without_operators_is_an_error() {
        with_petsc(|comm| {
            let mut eps = Eps::new(comm, "").unwrap();
            let e = eps.solve().unwrap_err();
            assert_eq!(e.code, sys::PETSC_ERR_ORDER as i32);
        });
    }
}
