//! [`Matrix`]: a distributed, square, preallocated PETSc sparse matrix (AIJ or BAIJ).
//!
//! Rank `r` owns the rows `ownership_range()` and, for the parallel formats, splits each owned row
//! into a *diagonal* block (columns in the same range, counted by `d_nnz`) and an *off-diagonal*
//! block (all other columns, `o_nnz`). Preallocation must be exact or generous: a new nonzero
//! outside it is an error (`MAT_NEW_NONZERO_ALLOCATION_ERR`), never a silent slow reallocation.

use std::ffi::c_void;

use super::error::{petsc_call, PetscError};
use super::runtime::{ensure_running, is_running};
use super::vector::{check_indices, Vector};
use super::{sys, to_petsc_int, to_usize, type_name, PetscComm};

/// A PETSc matrix of `f64`; destroyed (`MatDestroy`) when dropped.
///
/// Indices are checked against the global size before PETSc sees them: the Debian PETSc is built
/// without debugging, and an out-of-range index would silently corrupt memory.
pub struct Matrix {
    raw: sys::Mat,
    /// Global number of rows (= columns), cached for the index checks.
    n_global: sys::PetscInt,
}

/// Checks the preallocation arrays against the number of local (block) rows.
fn check_nnz(call: &'static str, rows: usize, d_nnz: &[i32], o_nnz: &[i32]) -> Result<(), PetscError> {
    if d_nnz.len() != rows || o_nnz.len() != rows {
        return Err(PetscError::usage(
            sys::PETSC_ERR_ARG_SIZ,
            call,
            format!("{rows} local (block) rows but d_nnz has {} and o_nnz {} entries", d_nnz.len(), o_nnz.len()),
        ));
    }
    if let Some(bad) = d_nnz.iter().chain(o_nnz).find(|&&n| n < 0) {
        return Err(PetscError::usage(
            sys::PETSC_ERR_ARG_OUTOFRANGE,
            call,
            format!("negative nonzero count {bad} in the preallocation"),
        ));
    }
    Ok(())
}

impl Matrix {
    /// Square AIJ (CSR) matrix with `n_local_rows` rows (and columns) on this rank, preallocated
    /// with `d_nnz[i]` / `o_nnz[i]` nonzeros in local row `i` inside / outside the diagonal block.
    /// Type `MATAIJ`: SeqAIJ on one rank, MPIAIJ otherwise. Collective on `comm`.
    pub fn new_aij(
        comm: &impl PetscComm,
        n_local_rows: usize,
        d_nnz: &[i32],
        o_nnz: &[i32],
    ) -> Result<Matrix, PetscError> {
        const CALL: &str = "Matrix::new_aij";
        ensure_running(CALL)?;
        check_nnz(CALL, n_local_rows, d_nnz, o_nnz)?;
        let n = to_petsc_int(n_local_rows, CALL, "n_local_rows")?;
        let mut m = Matrix { raw: std::ptr::null_mut(), n_global: 0 };
        petsc_call!(MatCreate(comm.as_raw(), &mut m.raw))?;
        petsc_call!(MatSetSizes(m.raw, n, n, sys::PETSC_DETERMINE, sys::PETSC_DETERMINE))?;
        petsc_call!(MatSetType(m.raw, type_name(sys::MATAIJ)))?;
        // Each call is ignored by the other matrix type, so both are always made.
        petsc_call!(MatSeqAIJSetPreallocation(m.raw, 0, d_nnz.as_ptr()))?;
        petsc_call!(MatMPIAIJSetPreallocation(m.raw, 0, d_nnz.as_ptr(), 0, o_nnz.as_ptr()))?;
        m.finish_creation()?;
        Ok(m)
    }

    /// Square block-AIJ matrix with blocks of `bs`×`bs` (6 for the 3D frame DOFs):
    /// `n_local_rows` scalar rows on this rank (a multiple of `bs`), preallocated per local *block*
    /// row with `d_nnz_blocks` / `o_nnz_blocks` nonzero blocks. Type `MATBAIJ`. Collective.
    pub fn new_baij(
        comm: &impl PetscComm,
        bs: usize,
        n_local_rows: usize,
        d_nnz_blocks: &[i32],
        o_nnz_blocks: &[i32],
    ) -> Result<Matrix, PetscError> {
        const CALL: &str = "Matrix::new_baij";
        ensure_running(CALL)?;
        if bs == 0 || n_local_rows % bs != 0 {
            return Err(PetscError::usage(
                sys::PETSC_ERR_ARG_WRONG,
                CALL,
                format!("{n_local_rows} local rows is not a multiple of the block size {bs}"),
            ));
        }
        check_nnz(CALL, n_local_rows / bs, d_nnz_blocks, o_nnz_blocks)?;
        let n = to_petsc_int(n_local_rows, CALL, "n_local_rows")?;
        let b = to_petsc_int(bs, CALL, "bs")?;
        let mut m = Matrix { raw: std::ptr::null_mut(), n_global: 0 };
        petsc_call!(MatCreate(comm.as_raw(), &mut m.raw))?;
        petsc_call!(MatSetSizes(m.raw, n, n, sys::PETSC_DETERMINE, sys::PETSC_DETERMINE))?;
        petsc_call!(MatSetBlockSize(m.raw, b))?;
        petsc_call!(MatSetType(m.raw, type_name(sys::MATBAIJ)))?;
        petsc_call!(MatSeqBAIJSetPreallocation(m.raw, b, 0, d_nnz_blocks.as_ptr()))?;
        petsc_call!(MatMPIBAIJSetPreallocation(m.raw, b, 0, d_nnz_blocks.as_ptr(), 0, o_nnz_blocks.as_ptr()))?;
        m.finish_creation()?;
        Ok(m)
    }

    /// Common end of the constructors: preallocation overflow is an error; cache the size.
    fn finish_creation(&mut self) -> Result<(), PetscError> {
        petsc_call!(MatSetOption(self.raw, sys::MAT_NEW_NONZERO_ALLOCATION_ERR, sys::PETSC_TRUE))?;
        let mut n_cols = 0;
        petsc_call!(MatGetSize(self.raw, &mut self.n_global, &mut n_cols))
    }

    /// The raw PETSc handle (still owned by `self`).
    pub fn as_raw(&self) -> sys::Mat {
        self.raw
    }

    /// Adds the dense block `vals_row_major[i·cols.len() + j]` at `(rows[i], cols[j])`
    /// (`ADD_VALUES`); entries with a negative row or column index are ignored — the assembly
    /// relies on this for fixed DOFs. Rows of other ranks are allowed. Not collective.
    pub fn add_values(&mut self, rows: &[i32], cols: &[i32], vals_row_major: &[f64]) -> Result<(), PetscError> {
        self.set_block(rows, cols, vals_row_major, sys::ADD_VALUES)
    }

    /// Like [`add_values`](Self::add_values) with `INSERT_VALUES` (do not mix the two modes
    /// between assemblies).
    pub fn set_values(&mut self, rows: &[i32], cols: &[i32], vals_row_major: &[f64]) -> Result<(), PetscError> {
        self.set_block(rows, cols, vals_row_major, sys::INSERT_VALUES)
    }

    /// `MatSetValues` with a size check on the dense block.
    fn set_block(&mut self, rows: &[i32], cols: &[i32], vals: &[f64], mode: sys::InsertMode) -> Result<(), PetscError> {
        const CALL: &str = "MatSetValues";
        if rows.len().checked_mul(cols.len()) != Some(vals.len()) {
            return Err(PetscError::usage(
                sys::PETSC_ERR_ARG_SIZ,
                CALL,
                format!("{} rows × {} columns but {} values", rows.len(), cols.len(), vals.len()),
            ));
        }
        check_indices(CALL, "row", rows, self.n_global)?;
        check_indices(CALL, "column", cols, self.n_global)?;
        let m = to_petsc_int(rows.len(), CALL, "rows")?;
        let n = to_petsc_int(cols.len(), CALL, "columns")?;
        petsc_call!(MatSetValues(self.raw, m, rows.as_ptr(), n, cols.as_ptr(), vals.as_ptr(), mode))
    }

    /// Finishes insertion (`MatAssemblyBegin/End`, `MAT_FINAL_ASSEMBLY`). Collective.
    pub fn assemble(&mut self) -> Result<(), PetscError> {
        petsc_call!(MatAssemblyBegin(self.raw, sys::MAT_FINAL_ASSEMBLY))?;
        petsc_call!(MatAssemblyEnd(self.raw, sys::MAT_FINAL_ASSEMBLY))
    }

    /// Sets all stored entries to zero, keeping the nonzero structure. Collective.
    pub fn zero_entries(&mut self) -> Result<(), PetscError> {
        petsc_call!(MatZeroEntries(self.raw))
    }

    /// `self ← self + alpha · x`, where the nonzero pattern of `x` is contained in that of
    /// `self` (PETSc's `SUBSET_NONZERO_PATTERN`; e.g. `x` assembled from a subset of the
    /// elements that assembled `self`). Collective.
    pub fn axpy(&mut self, alpha: f64, x: &Matrix) -> Result<(), PetscError> {
        petsc_call!(MatAXPY(self.raw, alpha, x.raw, sys::SUBSET_NONZERO_PATTERN))
    }

    /// `y ← A·x`. Collective; `x`, `y` laid out as [`create_vectors`](Self::create_vectors).
    pub fn mult(&self, x: &Vector, y: &mut Vector) -> Result<(), PetscError> {
        petsc_call!(MatMult(self.raw, x.as_raw(), y.as_raw()))
    }

    /// The diagonal `dᵢ = Aᵢᵢ` as a vector. Collective.
    pub fn get_diagonal(&self) -> Result<Vector, PetscError> {
        let (_, d) = self.create_vectors()?;
        petsc_call!(MatGetDiagonal(self.raw, d.as_raw()))?;
        Ok(d)
    }

    /// Frobenius norm ‖A‖_F = (Σᵢⱼ Aᵢⱼ²)^½. Collective.
    pub fn norm_frobenius(&self) -> Result<f64, PetscError> {
        let mut norm = 0.0;
        petsc_call!(MatNorm(self.raw, sys::NORM_FROBENIUS, &mut norm))?;
        Ok(norm)
    }

    /// Declares the matrix symmetric (or not), and that this holds for the rest of its life
    /// (`MAT_SYMMETRIC` + `MAT_SYMMETRY_ETERNAL`), so Cholesky/CG and SLEPc may rely on it.
    pub fn set_option_symmetric(&mut self, symmetric: bool) -> Result<(), PetscError> {
        let flag = if symmetric { sys::PETSC_TRUE } else { sys::PETSC_FALSE };
        petsc_call!(MatSetOption(self.raw, sys::MAT_SYMMETRIC, flag))?;
        petsc_call!(MatSetOption(self.raw, sys::MAT_SYMMETRY_ETERNAL, flag))
    }

    /// Attaches a near-null space — for a structure, its rigid-body modes — which algebraic
    /// multigrid (GAMG, ML) uses to build coarse spaces; other solvers ignore it. The vectors are
    /// orthonormalized here by modified Gram–Schmidt (`MatNullSpaceCreate` requires it), and a
    /// vector left with less than 1e-10 of its norm (dependent on the others) is dropped.
    /// Returns how many were kept. Collective.
    pub fn set_near_null_space(
        &mut self,
        comm: &impl PetscComm,
        mut vecs: std::vec::Vec<Vector>,
    ) -> Result<usize, PetscError> {
        let mut kept: std::vec::Vec<Vector> = std::vec::Vec::with_capacity(vecs.len());
        for mut v in vecs.drain(..) {
            let n0 = v.norm2()?;
            if n0 == 0.0 {
                continue;
            }
            for q in &kept {
                let c = v.dot(q)?;
                v.axpy(-c, q)?;
            }
            let n = v.norm2()?;
            if n > 1e-10 * n0 {
                v.scale(1.0 / n)?;
                kept.push(v);
            }
        }
        let raws: std::vec::Vec<sys::Vec> = kept.iter().map(Vector::as_raw).collect();
        let mut ns: sys::MatNullSpace = std::ptr::null_mut();
        petsc_call!(MatNullSpaceCreate(
            comm.as_raw(),
            sys::PETSC_FALSE,
            to_petsc_int(raws.len(), "MatNullSpaceCreate", "number of vectors")?,
            raws.as_ptr(),
            &mut ns
        ))?;
        let set = petsc_call!(MatSetNearNullSpace(self.raw, ns));
        // The matrix holds its own reference; release ours whatever happened.
        let destroyed = petsc_call!(MatNullSpaceDestroy(&mut ns));
        set?;
        destroyed?;
        Ok(kept.len())
    }

    /// Global row range `[start, end)` owned by this rank.
    pub fn ownership_range(&self) -> Result<(usize, usize), PetscError> {
        let (mut lo, mut hi) = (0, 0);
        petsc_call!(MatGetOwnershipRange(self.raw, &mut lo, &mut hi))?;
        Ok((to_usize(lo), to_usize(hi)))
    }

    /// Global number of rows (= columns).
    pub fn size_global(&self) -> usize {
        to_usize(self.n_global)
    }

    /// Two zero vectors laid out for this matrix, `(x, b)`: `x` like a solution (columns, the
    /// right side of `A·x`) and `b` like a right-hand side (rows). Collective.
    pub fn create_vectors(&self) -> Result<(Vector, Vector), PetscError> {
        let mut right: sys::Vec = std::ptr::null_mut();
        let mut left: sys::Vec = std::ptr::null_mut();
        petsc_call!(MatCreateVecs(self.raw, &mut right, &mut left))?;
        // Adopt `left` first: if adopting `right` fails, `left` is still destroyed.
        let left = Vector::adopt(left);
        let (mut x, mut b) = (Vector::adopt(right)?, left?);
        x.set_all(0.0)?;
        b.set_all(0.0)?;
        Ok((x, b))
    }
}

impl Drop for Matrix {
    /// `MatDestroy` (collective). A matrix outliving PETSc is leaked instead.
    fn drop(&mut self) {
        if !self.raw.is_null() && is_running() {
            // SAFETY: `raw` is a live Mat owned by this value.
            let _ = unsafe { sys::MatDestroy(&mut self.raw) };
        }
    }
}

impl std::fmt::Debug for Matrix {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("Matrix").field("raw", &self.raw.cast::<c_void>()).finish()
    }
}

/// Test matrices shared by the solver tests of this module tree.
#[cfg(test)]
pub(crate) mod test_matrices {
    use super::*;

    /// The 1D Laplacian `tridiag(-1, 2, -1)` of order `n` on one rank (AIJ), assembled.
    pub(crate) fn laplacian_1d(comm: &impl PetscComm, n: usize) -> Matrix {
        let d_nnz: Vec<i32> = (0..n).map(|i| if i == 0 || i + 1 == n { 2 } else { 3 }).collect();
        let o_nnz = vec![0; n];
        let mut a = Matrix::new_aij(comm, n, &d_nnz, &o_nnz).expect("create");
        let n_i = i32::try_from(n).expect("small n");
        for i in 0..n_i {
            // Neighbours outside 0..n are dropped by the negative-index rule.
            let right = if i + 1 < n_i { i + 1 } else { -1 };
            a.add_values(&[i], &[i - 1, i, right], &[-1.0, 2.0, -1.0]).expect("add");
        }
        a.assemble().expect("assemble");
        a
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::petsc::testing::with_petsc;

    /// Dense 12×12 symmetric test matrix with 6×6 block structure: entry (i, j) is
    /// 1/(1+|i−j|) + 10·δᵢⱼ where blocks (0,0), (0,1), (1,1), (1,0) are all present.
    fn entry(i: usize, j: usize) -> f64 {
        1.0 / (1.0 + i.abs_diff(j) as f64) + if i == j { 10.0 } else { 0.0 }
    }

    /// Dependent vectors are dropped from a near-null space: {1, 2·1, e_0} spans 2 dimensions.
    #[test]
    fn near_null_space_keeps_independent_vectors() {
        with_petsc(|comm| {
            let n = 8;
            let mut a = test_matrices::laplacian_1d(comm, n);
            let mk = |f: &dyn Fn(usize) -> f64| {
                let mut v = Vector::new_mpi(comm, n, None).unwrap();
                let idx: Vec<i32> = (0..n as i32).collect();
                let vals: Vec<f64> = (0..n).map(f).collect();
                v.set_values(&idx, &vals).unwrap();
                v.assemble().unwrap();
                v
            };
            let vecs = vec![mk(&|_| 1.0), mk(&|_| 2.0), mk(&|i| if i == 0 { 1.0 } else { 0.0 })];
            assert_eq!(a.set_near_null_space(comm, vecs).unwrap(), 2);
        });
    }

    #[test]
    fn baij_block6_product_equals_aij() {
        with_petsc(|comm| {
            const N: usize = 12;
            let all: Vec<i32> = (0..N as i32).collect();
            let dense: Vec<f64> = (0..N * N).map(|k| entry(k / N, k % N)).collect();
            let mut aij = Matrix::new_aij(comm, N, &[N as i32; N], &[0; N]).unwrap();
            let mut baij = Matrix::new_baij(comm, 6, N, &[2, 2], &[0, 0]).unwrap();
            // Element-like assembly: two overlapping 6-DOF contributions that sum to `dense`.
            for m in [&mut aij, &mut baij] {
                m.add_values(&all, &all, &dense.iter().map(|v| 0.25 * v).collect::<Vec<_>>()).unwrap();
                m.add_values(&all, &all, &dense.iter().map(|v| 0.75 * v).collect::<Vec<_>>()).unwrap();
                m.assemble().unwrap();
            }
            let (mut x, _) = aij.create_vectors().unwrap();
            let xs: Vec<f64> = (0..N).map(|i| (i as f64 * 0.7).sin()).collect();
            x.set_values(&all, &xs).unwrap();
            x.assemble().unwrap();
            let (_, mut y_aij) = aij.create_vectors().unwrap();
            let (_, mut y_baij) = baij.create_vectors().unwrap();
            aij.mult(&x, &mut y_aij).unwrap();
            baij.mult(&x, &mut y_baij).unwrap();
            let (ya, yb) = (y_aij.owned_values().unwrap(), y_baij.owned_values().unwrap());
            for i in 0..N {
                // Reference: the dense product in f64; same sums in a different order, so the
                // tolerance is a few ulps of |y| ≈ 15.
                let exact: f64 = (0..N).map(|j| entry(i, j) * xs[j]).sum();
                assert!((ya[i] - exact).abs() < 1e-13, "aij row {i}");
                assert!((yb[i] - ya[i]).abs() < 1e-13, "baij row {i}");
            }
            assert!((aij.norm_frobenius().unwrap() - baij.norm_frobenius().unwrap()).abs() < 1e-12);
        });
    }

    #[test]
    fn laplacian_diagonal_norm_and_symmetry() {
        with_petsc(|comm| {
            let mut a = test_matrices::laplacian_1d(comm, 5);
            a.set_option_symmetric(true).unwrap();
            assert_eq!(a.get_diagonal().unwrap().owned_values().unwrap(), vec![2.0; 5]);
            // ‖A‖_F² = 5·2² + 8·(−1)² = 28 for n = 5.
            assert!((a.norm_frobenius().unwrap() - 28f64.sqrt()).abs() < 1e-14);
            assert_eq!(a.ownership_range().unwrap(), (0, 5));
            a.zero_entries().unwrap();
            assert_eq!(a.norm_frobenius().unwrap(), 0.0);
        });
    }

    #[test]
    fn preallocation_overflow_is_an_error() {
        with_petsc(|comm| {
            let mut a = Matrix::new_aij(comm, 3, &[1, 1, 1], &[0, 0, 0]).unwrap();
            a.add_values(&[0], &[0], &[1.0]).unwrap();
            let e = a.add_values(&[0], &[2], &[1.0]).unwrap_err();
            assert_eq!(e.call, "MatSetValues");
            // PETSC_ERR_ARG_OUTOFRANGE (63): "new nonzero caused a malloc".
            assert_eq!(e.code, 63, "{e}");
            assert!(Matrix::new_aij(comm, 3, &[1, 1], &[0, 0, 0]).is_err());
            assert!(Matrix::new_baij(comm, 6, 7, &[1], &[0]).is_err());
            assert!(a.add_values(&[0, 1], &[0], &[1.0]).is_err());
            let e = a.add_values(&[3], &[0], &[1.0]).unwrap_err();
            assert_eq!(e.code, 63, "row 3 of a 3×3 matrix: {e}");
        });
    }
}
