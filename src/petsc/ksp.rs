//! [`Ksp`]: a PETSc linear solver (Krylov method + preconditioner) for `A·x = b`.
//!
//! Configure programmatically first (`set_type`, `set_pc_type`, `set_factor_solver`,
//! `set_tolerances`), then call [`Ksp::set_from_options`] LAST so that the options database (command
//! line, `PETSC_OPTIONS`, job defaults) under the solver's prefix wins. [`Ksp::solve`] reads
//! `KSPGetConvergedReason` after every solve: `KSPSolve` itself succeeds even when it diverged.

use std::ffi::{c_char, c_void, CStr};

use super::dense::DenseBlock;
use super::error::{ksp_reason_name, pc_failure_name, petsc_call, PetscError, SolverError};
use super::matrix::Matrix;
use super::options::c_string;
use super::runtime::{ensure_running, is_running};
use super::vector::Vector;
use super::{sys, type_name, PetscComm};

/// Outcome of a converged solve.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct KspStats {
    /// Iterations done (0 or 1 for a direct solve with `preonly`).
    pub iterations: i32,
    /// Last residual norm the method computed (the preconditioned one for left preconditioning;
    /// 0 for `preonly`, which computes none).
    pub residual_norm: f64,
    /// Why it stopped, e.g. `"CONVERGED_RTOL"` or `"CONVERGED_ITS"` (preonly).
    pub reason: &'static str,
}

/// A PETSc `KSP`; destroyed (`KSPDestroy`) when dropped.
pub struct Ksp {
    raw: sys::KSP,
}

/// A possibly-null C string from PETSc as text (`"default"` when null: PETSc picks at set-up).
fn c_text(p: *const c_char) -> String {
    if p.is_null() {
        "default".to_owned()
    } else {
        // SAFETY: PETSc type names are NUL-terminated strings owned by the object.
        unsafe { CStr::from_ptr(p) }.to_string_lossy().into_owned()
    }
}

impl Ksp {
    /// A solver on `comm` whose options are read under `prefix` (e.g. `"struct_"` reads
    /// `-struct_ksp_type`); `""` for none. Collective on `comm`.
    pub fn new(comm: &impl PetscComm, prefix: &str) -> Result<Ksp, PetscError> {
        ensure_running("Ksp::new")?;
        let c_prefix = c_string(prefix, "KSPSetOptionsPrefix")?;
        let mut k = Ksp { raw: std::ptr::null_mut() };
        petsc_call!(KSPCreate(comm.as_raw(), &mut k.raw))?;
        if !prefix.is_empty() {
            petsc_call!(KSPSetOptionsPrefix(k.raw, c_prefix.as_ptr()))?;
        }
        Ok(k)
    }

    /// The raw PETSc handle (still owned by `self`).
    pub fn as_raw(&self) -> sys::KSP {
        self.raw
    }

    /// The preconditioner (owned by the KSP).
    fn pc(&self) -> Result<sys::PC, PetscError> {
        let mut pc: sys::PC = std::ptr::null_mut();
        petsc_call!(KSPGetPC(self.raw, &mut pc))?;
        Ok(pc)
    }

    /// Uses `a` as both operator and preconditioning matrix (PETSc keeps a reference, so `a` may
    /// be dropped first). After `a` changes, set it again to refactor. Collective.
    pub fn set_operators(&mut self, a: &Matrix) -> Result<(), PetscError> {
        petsc_call!(KSPSetOperators(self.raw, a.as_raw(), a.as_raw()))
    }

    /// Krylov method by PETSc name: `"cg"`, `"gmres"`, `"preonly"`, ... Collective.
    pub fn set_type(&mut self, ksp_type: &str) -> Result<(), PetscError> {
        let c = c_string(ksp_type, "KSPSetType")?;
        petsc_call!(KSPSetType(self.raw, c.as_ptr()))
    }

    /// Preconditioner by PETSc name: `"jacobi"`, `"lu"`, `"cholesky"`, `"gamg"`, ... Collective.
    pub fn set_pc_type(&mut self, pc_type: &str) -> Result<(), PetscError> {
        let c = c_string(pc_type, "PCSetType")?;
        petsc_call!(PCSetType(self.pc()?, c.as_ptr()))
    }

    /// Whether the options database chooses this solver's preconditioner (`-<prefix>pc_type`):
    /// a choice the program must then not override. Not collective.
    pub fn pc_type_in_options(&self) -> Result<bool, PetscError> {
        let mut prefix: *const c_char = std::ptr::null();
        petsc_call!(KSPGetOptionsPrefix(self.raw, &mut prefix))?;
        let mut set = sys::PETSC_FALSE;
        let name = c_string("-pc_type", "PetscOptionsHasName")?;
        petsc_call!(PetscOptionsHasName(std::ptr::null_mut(), prefix, name.as_ptr(), &mut set))?;
        Ok(set == sys::PETSC_TRUE)
    }

    /// Factorization package of an `lu`/`cholesky` preconditioner: `"mumps"`, `"petsc"`,
    /// `"superlu_dist"`, ... (set the PC type first). Collective.
    pub fn set_factor_solver(&mut self, solver: &str) -> Result<(), PetscError> {
        let c = c_string(solver, "PCFactorSetMatSolverType")?;
        petsc_call!(PCFactorSetMatSolverType(self.pc()?, c.as_ptr()))
    }

    /// Stops when ‖r‖ ≤ max(rtol·‖b‖, atol) (PETSc's default test), or fails with
    /// `DIVERGED_ITS` after `max_it` iterations. Collective.
    pub fn set_tolerances(&mut self, rtol: f64, atol: f64, max_it: i32) -> Result<(), PetscError> {
        petsc_call!(KSPSetTolerances(self.raw, rtol, atol, f64::from(sys::PETSC_DEFAULT), max_it))
    }

    /// Keeps the preconditioner (e.g. a factorization) across solves even if the operator's
    /// values change (modified Newton). Collective.
    pub fn set_reuse_preconditioner(&mut self, reuse: bool) -> Result<(), PetscError> {
        let flag = if reuse { sys::PETSC_TRUE } else { sys::PETSC_FALSE };
        petsc_call!(KSPSetReusePreconditioner(self.raw, flag))
    }

    /// Reads the options database under the prefix; call it LAST so the command line wins.
    /// Collective.
    pub fn set_from_options(&mut self) -> Result<(), PetscError> {
        petsc_call!(KSPSetFromOptions(self.raw))
    }

    /// Solves `A·x = b` (`x` holds the initial guess only if a nonzero guess was requested).
    /// Checks `KSPGetConvergedReason`: a negative reason is [`SolverError::Diverged`] with the
    /// preconditioner's diagnosis (`PCGetFailedReason`, and the zero-pivot row from the factor,
    /// when the PC is a factorization that reports one). Collective.
    pub fn solve(&mut self, b: &Vector, x: &mut Vector) -> Result<KspStats, SolverError> {
        petsc_call!(KSPSolve(self.raw, b.as_raw(), x.as_raw()))?;
        let mut reason: sys::KSPConvergedReason = 0;
        let mut iterations: sys::PetscInt = 0;
        let mut residual_norm = 0.0;
        petsc_call!(KSPGetConvergedReason(self.raw, &mut reason))?;
        petsc_call!(KSPGetIterationNumber(self.raw, &mut iterations))?;
        petsc_call!(KSPGetResidualNorm(self.raw, &mut residual_norm))?;
        if reason >= 0 {
            return Ok(KspStats { iterations, residual_norm, reason: ksp_reason_name(reason) });
        }
        let (pc_failure, zero_pivot_row) = self.pc_diagnosis()?;
        Err(SolverError::Diverged {
            reason: ksp_reason_name(reason),
            iterations,
            residual_norm,
            pc_failure,
            zero_pivot_row,
        })
    }

    /// Solves `A·X = B` for all the columns of a dense block at once (`KSPMatSolve`; with
    /// `preonly` and a factorization, one `MatMatSolve`, which reads the factor once for all the
    /// columns). The set-up (the factorization) is checked first: a failed one is
    /// [`SolverError::Diverged`] with the preconditioner's diagnosis. Collective.
    pub fn mat_solve(&mut self, b: &DenseBlock, x: &mut DenseBlock) -> Result<(), SolverError> {
        petsc_call!(KSPSetUp(self.raw))?;
        let (pc_failure, zero_pivot_row) = self.pc_diagnosis()?;
        if pc_failure.is_some() {
            return Err(SolverError::Diverged {
                reason: "DIVERGED_PC_FAILED",
                iterations: 0,
                residual_norm: f64::NAN,
                pc_failure,
                zero_pivot_row,
            });
        }
        petsc_call!(KSPMatSolve(self.raw, b.as_raw(), x.as_raw()))?;
        Ok(())
    }

    /// Why the preconditioner failed, and the zero-pivot row if its factor knows it.
    fn pc_diagnosis(&self) -> Result<(Option<&'static str>, Option<i64>), PetscError> {
        let pc = self.pc()?;
        let mut failed: sys::PCFailedReason = sys::PC_NOERROR;
        petsc_call!(PCGetFailedReason(pc, &mut failed))?;
        let pc_failure = (failed != sys::PC_NOERROR).then(|| pc_failure_name(failed));
        if !self.pc_is_factorization(pc)? {
            return Ok((pc_failure, None));
        }
        // Only PETSc's own factorizations record the row (MatPivotCheck); external packages
        // (MUMPS, ...) flag the zero pivot but leave the row at its default 0, which would lie.
        let mut solver: sys::MatSolverType = std::ptr::null();
        petsc_call!(PCFactorGetMatSolverType(pc, &mut solver))?;
        if solver.is_null() || c_text(solver) != "petsc" {
            return Ok((pc_failure, None));
        }
        let mut factor: sys::Mat = std::ptr::null_mut();
        petsc_call!(PCFactorGetMatrix(pc, &mut factor))?;
        if factor.is_null() {
            return Ok((pc_failure, None));
        }
        let mut err: sys::MatFactorError = sys::MAT_FACTOR_NOERROR;
        petsc_call!(MatFactorGetError(factor, &mut err))?;
        if err != sys::MAT_FACTOR_NUMERIC_ZEROPIVOT && err != sys::MAT_FACTOR_STRUCT_ZEROPIVOT {
            return Ok((pc_failure, None));
        }
        let (mut pivot, mut row) = (0.0, -1);
        petsc_call!(MatFactorGetErrorZeroPivot(factor, &mut pivot, &mut row))?;
        Ok((pc_failure, (row >= 0).then_some(i64::from(row))))
    }

    /// True if the PC is one of PETSc's factorization preconditioners (LU, Cholesky, ILU, ICC).
    fn pc_is_factorization(&self, pc: sys::PC) -> Result<bool, PetscError> {
        for name in [sys::PCLU.as_slice(), sys::PCCHOLESKY, sys::PCILU, sys::PCICC] {
            let mut same = sys::PETSC_FALSE;
            petsc_call!(PetscObjectTypeCompare(pc.cast(), type_name(name), &mut same))?;
            if same == sys::PETSC_TRUE {
                return Ok(true);
            }
        }
        Ok(false)
    }

    /// One line for logs and benchmarks, e.g. `"ksp=preonly pc=cholesky solver=mumps rtol=1e-8"`
    /// (`solver` only for factorization PCs; `default` where PETSc decides at set-up).
    pub fn describe(&self) -> Result<String, PetscError> {
        let mut ksp_type: sys::KSPType = std::ptr::null();
        petsc_call!(KSPGetType(self.raw, &mut ksp_type))?;
        let pc = self.pc()?;
        let mut pc_type: sys::PCType = std::ptr::null();
        petsc_call!(PCGetType(pc, &mut pc_type))?;
        let mut s = format!("ksp={} pc={}", c_text(ksp_type), c_text(pc_type));
        if self.pc_is_factorization(pc)? {
            let mut solver: sys::MatSolverType = std::ptr::null();
            petsc_call!(PCFactorGetMatSolverType(pc, &mut solver))?;
            s.push_str(&format!(" solver={}", c_text(solver)));
        }
        let (mut rtol, mut atol, mut dtol, mut max_it) = (0.0, 0.0, 0.0, 0);
        petsc_call!(KSPGetTolerances(self.raw, &mut rtol, &mut atol, &mut dtol, &mut max_it))?;
        s.push_str(&format!(" rtol={rtol:e} atol={atol:e} max_it={max_it}"));
        Ok(s)
    }
}

impl Drop for Ksp {
    /// `KSPDestroy` (collective). A solver outliving PETSc is leaked instead.
    fn drop(&mut self) {
        if !self.raw.is_null() && is_running() {
            // SAFETY: `raw` is a live KSP owned by this value.
            let _ = unsafe { sys::KSPDestroy(&mut self.raw) };
        }
    }
}

impl std::fmt::Debug for Ksp {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("Ksp").field("raw", &self.raw.cast::<c_void>()).finish()
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::petsc::matrix::test_matrices::laplacian_1d;
    use crate::petsc::testing::{with_petsc, with_petsc_env};

    const N: usize = 20;

    /// Solves tridiag(−1, 2, −1)·x = 1 (order N) with the given solver set-up, returning x.
    ///
    /// Closed form: xᵢ = i(N+1−i)/2 for i = 1..N (the discrete Poisson problem −x'' = 1 with
    /// x₀ = x_{N+1} = 0, whose second differences are exactly −1 for a quadratic).
    fn solve_laplacian(comm: &mpi::topology::SimpleCommunicator, setup: impl FnOnce(&mut Ksp)) -> (Vec<f64>, KspStats) {
        let a = laplacian_1d(comm, N);
        let (mut x, mut b) = a.create_vectors().unwrap();
        b.set_all(1.0).unwrap();
        let mut ksp = Ksp::new(comm, "").unwrap();
        ksp.set_operators(&a).unwrap();
        setup(&mut ksp);
        let stats = ksp.solve(&b, &mut x).unwrap();
        (x.owned_values().unwrap(), stats)
    }

    fn closed_form(i: usize) -> f64 {
        let k = (i + 1) as f64; // 1-based index
        k * ((N + 1) as f64 - k) / 2.0
    }

    #[test]
    fn laplacian_by_cg_jacobi_matches_closed_form() {
        with_petsc(|comm| {
            let (x, stats) = solve_laplacian(comm, |k| {
                k.set_type("cg").unwrap();
                k.set_pc_type("jacobi").unwrap();
                k.set_tolerances(1e-14, 1e-50, 1000).unwrap();
            });
            for (i, xi) in x.iter().enumerate() {
                // x is O(50); rtol 1e-14 on the residual, cond(A) ≈ 180 → error ≪ 1e-10.
                assert!((xi - closed_form(i)).abs() < 1e-10, "x[{i}] = {xi}");
            }
            assert!(stats.reason.starts_with("CONVERGED"), "{stats:?}");
            // CG in exact arithmetic converges in at most N steps (N distinct eigenvalues).
            assert!(stats.iterations <= N as i32 + 2, "{stats:?}");
        });
    }

    #[test]
    fn laplacian_by_direct_lu_matches_closed_form() {
        with_petsc(|comm| {
            let mut description = String::new();
            let (x, stats) = solve_laplacian(comm, |k| {
                k.set_type("preonly").unwrap();
                k.set_pc_type("lu").unwrap();
                k.set_factor_solver("petsc").unwrap();
                k.set_tolerances(1e-8, 1e-50, 100).unwrap();
                description = k.describe().unwrap();
            });
            for (i, xi) in x.iter().enumerate() {
                assert!((xi - closed_form(i)).abs() < 1e-10, "x[{i}] = {xi}");
            }
            assert_eq!(stats.reason, "CONVERGED_ITS");
            assert!(description.starts_with("ksp=preonly pc=lu solver=petsc rtol=1e-8"), "{description}");
        });
    }

    #[test]
    fn too_few_iterations_is_diverged_its() {
        with_petsc(|comm| {
            let a = laplacian_1d(comm, N);
            let (mut x, mut b) = a.create_vectors().unwrap();
            b.set_all(1.0).unwrap();
            let mut ksp = Ksp::new(comm, "").unwrap();
            ksp.set_operators(&a).unwrap();
            ksp.set_type("cg").unwrap();
            ksp.set_pc_type("none").unwrap();
            ksp.set_tolerances(1e-12, 1e-50, 3).unwrap();
            match ksp.solve(&b, &mut x) {
                Err(SolverError::Diverged { reason, iterations, residual_norm, pc_failure, zero_pivot_row }) => {
                    assert_eq!(reason, "DIVERGED_ITS");
                    assert_eq!(iterations, 3);
                    assert!(residual_norm > 0.0);
                    assert_eq!((pc_failure, zero_pivot_row), (None, None));
                }
                other => panic!("expected DIVERGED_ITS, got {other:?}"),
            }
        });
    }

    /// Laplacian of order N with row `zero_row` zeroed but its entries kept in the structure
    /// (explicit zeros), so the factorization meets a numerically zero pivot.
    fn singular_laplacian(comm: &mpi::topology::SimpleCommunicator, zero_row: i32) -> Matrix {
        let mut a = Matrix::new_aij(comm, N, &[3; N], &[0; N]).unwrap();
        for i in 0..N as i32 {
            let right = if i + 1 < N as i32 { i + 1 } else { -1 };
            let vals = if i == zero_row { [0.0, 0.0, 0.0] } else { [-1.0, 2.0, -1.0] };
            a.add_values(&[i], &[i - 1, i, right], &vals).unwrap();
        }
        a.assemble().unwrap();
        a
    }

    #[test]
    fn laplacian_by_mumps_cholesky_matches_closed_form() {
        with_petsc(|comm| {
            let (x, _) = solve_laplacian(comm, |k| {
                k.set_type("preonly").unwrap();
                k.set_pc_type("cholesky").unwrap();
                k.set_factor_solver("mumps").unwrap();
            });
            for (i, xi) in x.iter().enumerate() {
                assert!((xi - closed_form(i)).abs() < 1e-10, "x[{i}] = {xi}");
            }
        });
    }

    #[test]
    fn singular_matrix_with_mumps_reports_pc_failure_without_row() {
        with_petsc(|comm| {
            let a = singular_laplacian(comm, 7);
            let (mut x, mut b) = a.create_vectors().unwrap();
            b.set_all(1.0).unwrap();
            let mut ksp = Ksp::new(comm, "").unwrap();
            ksp.set_operators(&a).unwrap();
            ksp.set_type("preonly").unwrap();
            ksp.set_pc_type("lu").unwrap();
            ksp.set_factor_solver("mumps").unwrap();
            match ksp.solve(&b, &mut x) {
                Err(SolverError::Diverged { reason, pc_failure, zero_pivot_row, .. }) => {
                    assert_eq!(reason, "DIVERGED_PC_FAILED");
                    // MUMPS INFOG(1) = -10 (singular) is mapped by PETSc to a numeric zero pivot.
                    assert_eq!(pc_failure, Some("FACTOR_NUMERIC_ZEROPIVOT"));
                    assert_eq!(zero_pivot_row, None, "MUMPS does not report the row");
                }
                other => panic!("expected DIVERGED_PC_FAILED, got {other:?}"),
            }
        });
    }

    #[test]
    fn singular_matrix_reports_zero_pivot_row() {
        with_petsc_env(|env| {
            const ZERO_ROW: i32 = 7;
            let comm = &env.comm;
            // With the natural ordering, PETSc's LU meets the zero pivot exactly at row 7.
            let a = singular_laplacian(comm, ZERO_ROW);
            let (mut x, mut b) = a.create_vectors().unwrap();
            b.set_all(1.0).unwrap();
            let opts = env.petsc.options();
            opts.set("-zp_pc_factor_mat_ordering_type", Some("natural")).unwrap();
            let mut ksp = Ksp::new(comm, "zp_").unwrap();
            ksp.set_operators(&a).unwrap();
            ksp.set_type("preonly").unwrap();
            ksp.set_pc_type("lu").unwrap();
            ksp.set_from_options().unwrap();
            let result = ksp.solve(&b, &mut x);
            opts.clear("-zp_pc_factor_mat_ordering_type").unwrap();
            match result {
                Err(SolverError::Diverged { reason, pc_failure, zero_pivot_row, .. }) => {
                    assert_eq!(reason, "DIVERGED_PC_FAILED");
                    assert_eq!(pc_failure, Some("FACTOR_NUMERIC_ZEROPIVOT"));
                    assert_eq!(zero_pivot_row, Some(i64::from(ZERO_ROW)));
                }
                other => panic!("expected DIVERGED_PC_FAILED, got {other:?}"),
            }
        });
    }

    #[test]
    fn command_line_overrides_programmatic_settings() {
        with_petsc_env(|env| {
            let opts = env.petsc.options();
            opts.insert_command_line("-cltest_ksp_type gmres -cltest_ksp_rtol 1e-9").unwrap();
            let mut ksp = Ksp::new(&env.comm, "cltest_").unwrap();
            ksp.set_type("cg").unwrap();
            ksp.set_pc_type("jacobi").unwrap();
            ksp.set_tolerances(1e-6, 1e-50, 50).unwrap();
            ksp.set_from_options().unwrap();
            let d = ksp.describe().unwrap();
            opts.clear("-cltest_ksp_type").unwrap();
            opts.clear("-cltest_ksp_rtol").unwrap();
            assert!(d.starts_with("ksp=gmres pc=jacobi rtol=1e-9 "), "{d}");
        });
    }
}
