//! [`DenseBlock`]: a distributed dense matrix of a few columns (PETSc `MATDENSE`), a block of
//! vectors that one call solves or multiplies at once: a solve with several right-hand sides
//! ([`Ksp::mat_solve`](super::Ksp::mat_solve)) reads the factor once for all of them.
//!
//! Rank `r` stores its rows of every column, column-major with leading dimension = its number
//! of rows (checked against `MatDenseGetLDA`).

use std::ffi::c_void;

use super::error::{petsc_call, PetscError};
use super::matrix::Matrix;
use super::runtime::{ensure_running, is_running};
use super::{sys, to_petsc_int, to_usize, PetscComm};

/// A distributed dense `n × cols` matrix; destroyed (`MatDestroy`) when dropped.
pub struct DenseBlock {
    raw: sys::Mat,
    rows: usize,
    cols: usize,
}

impl DenseBlock {
    /// Zero block with `n_local` rows on this rank and `cols` columns. Collective on `comm`.
    pub fn new(comm: &impl PetscComm, n_local: usize, cols: usize) -> Result<DenseBlock, PetscError> {
        const CALL: &str = "DenseBlock::new";
        ensure_running(CALL)?;
        let m = to_petsc_int(n_local, CALL, "n_local")?;
        let n = to_petsc_int(cols, CALL, "cols")?;
        let mut b = DenseBlock { raw: std::ptr::null_mut(), rows: n_local, cols };
        petsc_call!(MatCreateDense(
            comm.as_raw(),
            m,
            sys::PETSC_DECIDE,
            sys::PETSC_DETERMINE,
            n,
            std::ptr::null_mut(),
            &mut b.raw
        ))?;
        petsc_call!(MatZeroEntries(b.raw))?;
        petsc_call!(MatAssemblyBegin(b.raw, sys::MAT_FINAL_ASSEMBLY))?;
        petsc_call!(MatAssemblyEnd(b.raw, sys::MAT_FINAL_ASSEMBLY))?;
        b.check_lda(CALL)?;
        Ok(b)
    }

    /// Adopts a dense matrix PETSc created (the product of `MatMatMult`).
    fn adopt(raw: sys::Mat, call: &'static str) -> Result<DenseBlock, PetscError> {
        let mut b = DenseBlock { raw, rows: 0, cols: 0 };
        let (mut m, mut n) = (0, 0);
        petsc_call!(MatGetLocalSize(b.raw, &mut m, std::ptr::null_mut()))?;
        petsc_call!(MatGetSize(b.raw, std::ptr::null_mut(), &mut n))?;
        b.rows = to_usize(m);
        b.cols = to_usize(n);
        b.check_lda(call)?;
        Ok(b)
    }

    /// The local array must be packed (leading dimension = local rows) for the slices below.
    fn check_lda(&self, call: &'static str) -> Result<(), PetscError> {
        let mut lda = 0;
        petsc_call!(MatDenseGetLDA(self.raw, &mut lda))?;
        if to_usize(lda) != self.rows && self.rows > 0 {
            return Err(PetscError::usage(
                sys::PETSC_ERR_ARG_SIZ,
                call,
                format!("dense block with {} local rows has leading dimension {lda}", self.rows),
            ));
        }
        Ok(())
    }

    /// Rows on this rank.
    pub fn local_rows(&self) -> usize {
        self.rows
    }

    /// Columns.
    pub fn cols(&self) -> usize {
        self.cols
    }

    /// The raw handle (still owned by `self`).
    pub(crate) fn as_raw(&self) -> sys::Mat {
        self.raw
    }

    /// Copies this rank's rows out, column-major (`local_rows × cols`). Not collective.
    pub fn local_values(&self) -> Result<Vec<f64>, PetscError> {
        let mut out = Vec::with_capacity(self.rows * self.cols);
        self.local_values_into(&mut out)?;
        Ok(out)
    }

    /// Copies this rank's rows into `out` (resized), column-major. Not collective.
    pub fn local_values_into(&self, out: &mut Vec<f64>) -> Result<(), PetscError> {
        let mut p: *const f64 = std::ptr::null();
        petsc_call!(MatDenseGetArrayRead(self.raw, &mut p))?;
        let len = self.rows * self.cols;
        out.clear();
        if len > 0 {
            // SAFETY: PETSc hands out the packed local array (`check_lda`) of rows × cols
            // entries, valid until the matching restore below.
            out.extend_from_slice(unsafe { std::slice::from_raw_parts(p, len) });
        }
        petsc_call!(MatDenseRestoreArrayRead(self.raw, &mut p))
    }

    /// Overwrites this rank's rows with `values`, column-major (`local_rows × cols`). Not
    /// collective.
    pub fn set_local_values(&mut self, values: &[f64]) -> Result<(), PetscError> {
        const CALL: &str = "DenseBlock::set_local_values";
        if values.len() != self.rows * self.cols {
            return Err(PetscError::usage(
                sys::PETSC_ERR_ARG_SIZ,
                CALL,
                format!("{} values for a block of {} local rows × {} columns", values.len(), self.rows, self.cols),
            ));
        }
        let mut p: *mut f64 = std::ptr::null_mut();
        petsc_call!(MatDenseGetArrayWrite(self.raw, &mut p))?;
        if !values.is_empty() {
            // SAFETY: the packed local array holds rows × cols = values.len() entries until the
            // restore below.
            unsafe { std::slice::from_raw_parts_mut(p, values.len()) }.copy_from_slice(values);
        }
        petsc_call!(MatDenseRestoreArrayWrite(self.raw, &mut p))
    }
}

impl Matrix {
    /// `A · X` for a dense block `X` laid out like this matrix's columns: a new block.
    /// Collective.
    pub fn times_block(&self, x: &DenseBlock) -> Result<DenseBlock, PetscError> {
        let mut c: sys::Mat = std::ptr::null_mut();
        petsc_call!(MatMatMult(self.as_raw(), x.as_raw(), sys::MAT_INITIAL_MATRIX, sys::PETSC_DEFAULT as f64, &mut c))?;
        DenseBlock::adopt(c, "Matrix::times_block")
    }
}

impl Drop for DenseBlock {
    /// `MatDestroy` (collective). A block outliving PETSc is leaked instead.
    fn drop(&mut self) {
        if !self.raw.is_null() && is_running() {
            // SAFETY: `raw` is a live Mat owned by this value.
            let _ = unsafe { sys::MatDestroy(&mut self.raw) };
        }
    }
}

impl std::fmt::Debug for DenseBlock {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("DenseBlock")
            .field("raw", &self.raw.cast::<c_void>())
            .field("local_rows", &self.rows)
            .field("cols", &self.cols)
            .finish()
    }
}
