//! A sparse Cholesky factor that is updated in place: CHOLMOD's simplicial `LDLᵀ` and its
//! multiple-rank update/downdate (`cholmod_updown`; SuiteSparse 5, Debian's
//! `libsuitesparse-dev`). The anchor of lattice fracture codes: Nukala and Šimunović, IJNME 2005.
//!
//! ```text
//!   A = P L D Lᵀ Pᵀ               (simplicial LDLᵀ, fill-reducing P from CHOLMOD's analysis)
//!   A ± C Cᵀ  →  L̃ D̃ L̃ᵀ           (cholmod_updown: rank(C) ≤ 8 per pass, C's rows permuted by P;
//!                                   cost ∝ the entries of L on the etree paths of C's rows)
//! ```
//!
//! A broken beam is a downdate of rank ≤ 3 (its term `Σ u uᵀ`, [`super::system::Model::factors`]),
//! a contact term entering or leaving an update or downdate of rank 1. Unlike the Woodbury
//! correction of [`super::factor`], nothing accumulates: every solve costs one pair of
//! triangular substitutions with the current factor. The pattern of `L` grows where an update
//! brings entries outside it (CHOLMOD extends it); [`UpdatableCholesky::entries`] counts it, and
//! [`super::factor`] refactorizes once that fill has cost a factorization. A right-hand side
//! that is zero outside a few rows (a broken beam's force) is solved with the forward
//! substitution over their reach only ([`UpdatableCholesky::solve_sparse`]).
//!
//! **Binding.** The few CHOLMOD 3.0 functions used, declared by hand (`int` indices): the
//! `cholmod_common` block is opaque (its size checked against a sentinel tail,
//! [`COMMON_BYTES`]), its three fields used here (`supernodal`, `print`, `status`) at their C offsets; `cholmod_sparse`,
//! `cholmod_dense` and the head of `cholmod_factor` as `#[repr(C)]` structs (offsets of
//! SuiteSparse 5.12 on x86-64, checked by the tests through the library's own routines). Every
//! call's status is checked ([`CholmodError`]); `Drop` frees the factor and ends the workspace.
use std::os::raw::{c_int, c_void};

use faer::sparse::Triplet;

/// Why a CHOLMOD call failed (the call and CHOLMOD's status, or the input it refused).
#[derive(Clone, Debug, PartialEq)]
pub struct CholmodError(pub String);

/// A sparse column: `(row, value)` pairs.
type Column = Vec<(usize, f64)>;

/// Bytes reserved for `cholmod_common` (2664 in SuiteSparse 5.12 on x86-64; the rest is a
/// sentinel that `cholmod_start` must leave untouched).
const COMMON_BYTES: usize = 8192;
/// `sizeof(cholmod_common)` this binding was written against (SuiteSparse 5.12, x86-64).
const COMMON_SIZE: usize = 2664;
/// Offsets in `cholmod_common` (SuiteSparse 5.12, x86-64).
const OFFSET_SUPERNODAL: usize = 48;
const OFFSET_STATUS: usize = 1972;
const OFFSET_PRINT: usize = 144;
const CHOLMOD_SIMPLICIAL: c_int = 0;
const CHOLMOD_REAL: c_int = 1;
const CHOLMOD_A: c_int = 0;
const CHOLMOD_LT: c_int = 5;
/// `cholmod_updown` takes at most this many columns per call.
const MAX_RANK: usize = 8;
/// The smallest ratio of a pivot after a downdate to its value before: below it the downdate
/// cancelled more than 12 of the pivot's 16 digits (its relative error is then above about
/// 10⁻⁴) and the factor is rebuilt instead ([`UpdatableCholesky::update`]).
///
/// A stone whose last contact leaves keeps only its regularization spring, `10⁻¹⁰` of its
/// intact stiffness ([`super::scales`]): its pivot falls by 10⁻⁹–10⁻¹⁰ and keeps 6–7 digits,
/// plenty for a preconditioner (GMRES's split form then solves a tangent that differs from the
/// exact one in that stone's regularization by 10⁻⁶ of it; the residual, and so the equilibrium,
/// are exact). With a bound of 10⁻⁶ each such downdate rebuilt the factor: 801 of the 828
/// factorizations of a 10k-stone compression test to 6,500 breaks, 168 s of its 1,961 s, almost
/// all of them in its last 100 breaks; with 10⁻¹² none (40 factorizations, 3.5 s).
const MIN_PIVOT_RATIO: f64 = 1e-12;

#[repr(C)]
struct CholmodSparse {
    nrow: usize,
    ncol: usize,
    nzmax: usize,
    p: *mut c_void,
    i: *mut c_void,
    nz: *mut c_void,
    x: *mut c_void,
    z: *mut c_void,
    stype: c_int,
    itype: c_int,
    xtype: c_int,
    dtype: c_int,
    sorted: c_int,
    packed: c_int,
}

#[repr(C)]
struct CholmodDense {
    nrow: usize,
    ncol: usize,
    nzmax: usize,
    d: usize,
    x: *mut c_void,
    z: *mut c_void,
    xtype: c_int,
    dtype: c_int,
}

/// The head of `cholmod_factor` (the fields read here).
#[repr(C)]
struct CholmodFactorHead {
    n: usize,
    minor: usize,
    perm: *mut c_void,
    colcount: *mut c_void,
    iperm: *mut c_void,
    nzmax: usize,
    p: *mut c_void,
    i: *mut c_void,
    x: *mut c_void,
    z: *mut c_void,
    nz: *mut c_void,
}

#[link(name = "cholmod")]
extern "C" {
    fn cholmod_start(common: *mut u8) -> c_int;
    fn cholmod_finish(common: *mut u8) -> c_int;
    fn cholmod_allocate_sparse(
        nrow: usize,
        ncol: usize,
        nzmax: usize,
        sorted: c_int,
        packed: c_int,
        stype: c_int,
        xtype: c_int,
        common: *mut u8,
    ) -> *mut CholmodSparse;
    fn cholmod_free_sparse(a: *mut *mut CholmodSparse, common: *mut u8) -> c_int;
    fn cholmod_allocate_dense(nrow: usize, ncol: usize, d: usize, xtype: c_int, common: *mut u8) -> *mut CholmodDense;
    fn cholmod_free_dense(x: *mut *mut CholmodDense, common: *mut u8) -> c_int;
    fn cholmod_analyze(a: *mut CholmodSparse, common: *mut u8) -> *mut CholmodFactorHead;
    fn cholmod_factorize(a: *mut CholmodSparse, l: *mut CholmodFactorHead, common: *mut u8) -> c_int;
    fn cholmod_free_factor(l: *mut *mut CholmodFactorHead, common: *mut u8) -> c_int;
    fn cholmod_solve(sys: c_int, l: *mut CholmodFactorHead, b: *mut CholmodDense, common: *mut u8)
        -> *mut CholmodDense;
    fn cholmod_updown(update: c_int, c: *mut CholmodSparse, l: *mut CholmodFactorHead, common: *mut u8) -> c_int;
}

/// `A` factorized as CHOLMOD's simplicial `LDLᵀ`, updated and downdated in place (module docs).
pub struct UpdatableCholesky {
    n: usize,
    common: Box<[u8]>,
    factor: *mut CholmodFactorHead,
    /// `inverse[i]`: the position of unknown `i` in the factor's order (`P`'s inverse).
    inverse: Vec<usize>,
    /// Numeric factorizations done.
    pub n_factorizations: usize,
    /// Update/downdate passes (at most [`MAX_RANK`] columns each).
    pub n_updates: usize,
}

impl UpdatableCholesky {
    /// A workspace for `n` unknowns (call [`Self::factorize`] first).
    pub fn new(n: usize) -> Result<Self, CholmodError> {
        let mut common = vec![0xA5u8; COMMON_BYTES].into_boxed_slice();
        // SAFETY: `common` has room for a `cholmod_common` (checked just below).
        unsafe { cholmod_start(common.as_mut_ptr()) };
        if common[COMMON_SIZE..].iter().any(|&b| b != 0xA5) {
            return Err(CholmodError(format!(
                "cholmod_common larger than the {COMMON_SIZE} bytes this binding expects"
            )));
        }
        let mut s = UpdatableCholesky {
            n,
            common,
            factor: std::ptr::null_mut(),
            inverse: Vec::new(),
            n_factorizations: 0,
            n_updates: 0,
        };
        s.check("cholmod_start")?;
        s.set_int(OFFSET_SUPERNODAL, CHOLMOD_SIMPLICIAL);
        s.set_int(OFFSET_PRINT, 0); // every status is checked and returned here
        Ok(s)
    }

    fn set_int(&mut self, offset: usize, v: c_int) {
        self.common[offset..offset + 4].copy_from_slice(&v.to_ne_bytes());
    }

    fn status(&self) -> c_int {
        c_int::from_ne_bytes(self.common[OFFSET_STATUS..OFFSET_STATUS + 4].try_into().unwrap_or([0; 4]))
    }

    /// An error unless CHOLMOD's status is `CHOLMOD_OK` (0): 1 = not positive definite, other
    /// positive values warnings, negative values errors.
    fn check(&self, call: &str) -> Result<(), CholmodError> {
        match self.status() {
            0 => Ok(()),
            1 => Err(CholmodError(format!("{call}: matrix not positive definite (CHOLMOD_NOT_POSDEF)"))),
            s => Err(CholmodError(format!("{call}: CHOLMOD status {s}"))),
        }
    }

    /// The entries of `L` (its columns' counts, the diagonal included): what a solve reads,
    /// `2 ×` per substitution. Zero without a factor.
    pub fn entries(&self) -> usize {
        self.column_counts().iter().map(|&c| c as usize).sum()
    }

    /// The flops of a fresh numeric factorization with the current pattern, `Σ_j c_j²` over the
    /// column counts `c_j` of `L` (an up-looking `LDLᵀ` spends one multiply-add per pair of
    /// entries in a column). Zero without a factor.
    pub fn factorization_flops(&self) -> f64 {
        self.column_counts().iter().map(|&c| (c as f64) * (c as f64)).sum()
    }

    /// `L`'s column counts (`nz` of a simplicial factor).
    fn column_counts(&self) -> &[c_int] {
        if self.factor.is_null() {
            return &[];
        }
        // SAFETY: a simplicial factor's `nz` holds `n` ints, owned by CHOLMOD for the factor's
        // lifetime (borrowed from `self`).
        unsafe {
            let nz = (*self.factor).nz as *const c_int;
            if nz.is_null() {
                return &[];
            }
            std::slice::from_raw_parts(nz, self.n)
        }
    }

    /// Whether a factor is there to solve with.
    pub fn is_factorized(&self) -> bool {
        !self.factor.is_null()
    }

    /// Factorizes `A` (its upper triangle as triplets, duplicates summed): CHOLMOD's analysis
    /// (fill-reducing ordering) and numeric `LDLᵀ`.
    pub fn factorize(&mut self, upper: &[Triplet<usize, usize, f64>]) -> Result<(), CholmodError> {
        let n = self.n;
        // Compressed columns of the upper triangle, duplicates summed, rows sorted.
        let mut count = vec![0usize; n + 1];
        for t in upper {
            if t.row > t.col || t.col >= n {
                return Err(CholmodError(format!("triplet ({}, {}) outside the upper triangle of {n}", t.row, t.col)));
            }
            count[t.col + 1] += 1;
        }
        for j in 0..n {
            count[j + 1] += count[j];
        }
        let mut slot = count.clone();
        let mut entries = vec![(0usize, 0.0f64); upper.len()];
        for t in upper {
            entries[slot[t.col]] = (t.row, t.val);
            slot[t.col] += 1;
        }
        let mut p: Vec<c_int> = Vec::with_capacity(n + 1);
        let (mut rows, mut vals): (Vec<c_int>, Vec<f64>) = (Vec::new(), Vec::new());
        for j in 0..n {
            p.push(rows.len() as c_int);
            let col = &mut entries[count[j]..count[j + 1]];
            col.sort_by_key(|e| e.0);
            for &(r, v) in col.iter() {
                if rows.len() > p[j] as usize && *rows.last().unwrap_or(&-1) == r as c_int {
                    *vals.last_mut().unwrap_or(&mut 0.0) += v;
                } else {
                    rows.push(r as c_int);
                    vals.push(v);
                }
            }
        }
        p.push(rows.len() as c_int);
        let c = self.common.as_mut_ptr();
        // SAFETY: the sparse matrix is allocated by CHOLMOD with room for `rows.len()` entries,
        // filled within it and freed below; the factor pointer is CHOLMOD's own.
        unsafe {
            let mut a = cholmod_allocate_sparse(n, n, rows.len().max(1), 1, 1, 1, CHOLMOD_REAL, c);
            if a.is_null() {
                return Err(CholmodError("cholmod_allocate_sparse failed".into()));
            }
            std::ptr::copy_nonoverlapping(p.as_ptr(), (*a).p as *mut c_int, n + 1);
            std::ptr::copy_nonoverlapping(rows.as_ptr(), (*a).i as *mut c_int, rows.len());
            std::ptr::copy_nonoverlapping(vals.as_ptr(), (*a).x as *mut f64, vals.len());
            self.free_factor();
            self.factor = cholmod_analyze(a, c);
            if self.factor.is_null() {
                cholmod_free_sparse(&mut a, c);
                return Err(CholmodError(format!("cholmod_analyze: CHOLMOD status {}", self.status())));
            }
            cholmod_factorize(a, self.factor, c);
            cholmod_free_sparse(&mut a, c);
            if let Err(e) = self.check("cholmod_factorize") {
                self.free_factor();
                return Err(e);
            }
            let perm = std::slice::from_raw_parts((*self.factor).perm as *const c_int, n);
            self.inverse = vec![0; n];
            for (k, &i) in perm.iter().enumerate() {
                self.inverse[i as usize] = k;
            }
        }
        self.n_factorizations += 1;
        Ok(())
    }

    /// `A ← A + sign Σ u uᵀ` over the columns `u` (sparse, in unknown numbering), by
    /// `cholmod_updown` passes of at most [`MAX_RANK`] columns (an update for `sign > 0`, a
    /// downdate otherwise). A downdate that leaves a pivot not positive, or cancels it below
    /// [`MIN_PIVOT_RATIO`] of its former value, is an error: the factor is then to be rebuilt
    /// from the matrix (every pivot is read before and after: `2n` reads against the
    /// downdate's work).
    pub fn update(&mut self, cols: &[Column], sign: f64) -> Result<(), CholmodError> {
        if !self.is_factorized() {
            return Err(CholmodError("update before factorization".into()));
        }
        for chunk in cols.chunks(MAX_RANK) {
            let before = if sign <= 0.0 { self.pivots() } else { Vec::new() };
            let nnz: usize = chunk.iter().map(|u| u.len()).sum();
            let c = self.common.as_mut_ptr();
            // SAFETY: C is allocated by CHOLMOD with `nnz` entries and `chunk.len()` columns and
            // filled within them; rows are in 0..n (checked).
            unsafe {
                let mut cm = cholmod_allocate_sparse(self.n, chunk.len(), nnz.max(1), 1, 1, 0, CHOLMOD_REAL, c);
                if cm.is_null() {
                    return Err(CholmodError("cholmod_allocate_sparse failed".into()));
                }
                let (cp, ci, cx) = ((*cm).p as *mut c_int, (*cm).i as *mut c_int, (*cm).x as *mut f64);
                let mut k = 0usize;
                for (j, u) in chunk.iter().enumerate() {
                    *cp.add(j) = k as c_int;
                    let mut col: Vec<(usize, f64)> = Vec::with_capacity(u.len());
                    for &(r, v) in u {
                        if r >= self.n {
                            cholmod_free_sparse(&mut cm, c);
                            return Err(CholmodError(format!("update row {r} outside {}", self.n)));
                        }
                        col.push((self.inverse[r], v));
                    }
                    col.sort_by_key(|e| e.0);
                    for (r, v) in col {
                        *ci.add(k) = r as c_int;
                        *cx.add(k) = v;
                        k += 1;
                    }
                }
                *cp.add(chunk.len()) = k as c_int;
                cholmod_updown(c_int::from(sign > 0.0), cm, self.factor, c);
                cholmod_free_sparse(&mut cm, c);
            }
            self.n_updates += 1;
            self.check("cholmod_updown")?;
            if sign <= 0.0 {
                self.check_pivots(&before)?;
            }
        }
        Ok(())
    }

    /// The pivots `D_jj` of the simplicial `LDLᵀ`.
    fn pivots(&self) -> Vec<f64> {
        // SAFETY: a simplicial LDLᵀ factor of order n: column j's first entry, at p[j], is D_jj.
        unsafe {
            let f = &*self.factor;
            let (p, x) = (f.p as *const c_int, f.x as *const f64);
            (0..self.n).map(|j| *x.add(*p.add(j) as usize)).collect()
        }
    }

    /// After a downdate: an error if some pivot is not positive and finite (`cholmod_updown`
    /// does not report a downdate that leaves `A` indefinite), or fell below
    /// [`MIN_PIVOT_RATIO`] of its value `before` (cancellation: it kept fewer than 4 of its
    /// 16 digits).
    fn check_pivots(&self, before: &[f64]) -> Result<(), CholmodError> {
        for (j, (&d, &d0)) in self.pivots().iter().zip(before).enumerate() {
            if !(d.is_finite() && d > 0.0) {
                return Err(CholmodError(format!(
                    "cholmod_updown: pivot {j} not positive (matrix not positive definite)"
                )));
            }
            if d < MIN_PIVOT_RATIO * d0 {
                return Err(CholmodError(format!("cholmod_updown: pivot {j} cancelled from {d0:e} to {d:e}")));
            }
        }
        Ok(())
    }

    /// Solves `A x = b` in place.
    pub fn solve(&mut self, x: &mut [f64]) -> Result<(), CholmodError> {
        if !self.is_factorized() {
            return Err(CholmodError("solve before factorization".into()));
        }
        if x.len() != self.n {
            return Err(CholmodError(format!("right-hand side of {} entries for {} unknowns", x.len(), self.n)));
        }
        let c = self.common.as_mut_ptr();
        // SAFETY: B and X are CHOLMOD's n × 1 dense matrices, read and written within n entries,
        // and freed here.
        unsafe {
            let mut b = cholmod_allocate_dense(self.n, 1, self.n, CHOLMOD_REAL, c);
            if b.is_null() {
                return Err(CholmodError("cholmod_allocate_dense failed".into()));
            }
            std::ptr::copy_nonoverlapping(x.as_ptr(), (*b).x as *mut f64, self.n);
            let mut sol = cholmod_solve(CHOLMOD_A, self.factor, b, c);
            cholmod_free_dense(&mut b, c);
            if sol.is_null() {
                return Err(CholmodError(format!("cholmod_solve: CHOLMOD status {}", self.status())));
            }
            std::ptr::copy_nonoverlapping((*sol).x as *const f64, x.as_mut_ptr(), self.n);
            cholmod_free_dense(&mut sol, c);
        }
        Ok(())
    }

    /// Solves `A x = b` in place for a `b` that is zero outside `support` (its entries there are
    /// read, the others ignored), and returns how many columns of `L` the forward substitution
    /// visited.
    ///
    /// ```text
    ///   y = D⁻¹ L⁻¹ P b     column j of L applied only where y_j ≠ 0: the reach of P·support
    ///   x = Pᵀ L⁻ᵀ y        dense (cholmod_solve, CHOLMOD_Lt)
    /// ```
    ///
    /// The forward substitution of a sparse `b` touches only the columns of `L` on the elimination
    /// tree's paths from the support to the root (Gilbert and Peierls): a column whose `y_j` is
    /// zero when its turn comes adds nothing and is skipped (a test per column, no pass over its
    /// entries). The backward substitution is dense. For a broken beam's force (6 entries) in a
    /// 10k-stone lattice the reach is a few thousand of 29k columns, and the solve costs little
    /// more than one substitution instead of two.
    pub fn solve_sparse(&mut self, x: &mut [f64], support: &[usize]) -> Result<usize, CholmodError> {
        if !self.is_factorized() {
            return Err(CholmodError("solve before factorization".into()));
        }
        let n = self.n;
        if x.len() != n {
            return Err(CholmodError(format!("right-hand side of {} entries for {} unknowns", x.len(), n)));
        }
        if let Some(&i) = support.iter().find(|&&i| i >= n) {
            return Err(CholmodError(format!("support entry {i} for {n} unknowns")));
        }
        let c = self.common.as_mut_ptr();
        let mut reach = 0;
        // SAFETY: a simplicial factor holds `p` (n + 1 ints), `nz` (n ints), `i` and `x`
        // (`nzmax` entries); column j's entries are `p[j] .. p[j] + nz[j]`, the diagonal (D_jj
        // of an LDLᵀ factor) first, all within `nzmax`. Y is allocated here as n × 1 and X by
        // CHOLMOD as n × 1; both are freed before returning.
        unsafe {
            let l = &*self.factor;
            let lp = std::slice::from_raw_parts(l.p as *const c_int, n + 1);
            let lnz = std::slice::from_raw_parts(l.nz as *const c_int, n);
            let li = std::slice::from_raw_parts(l.i as *const c_int, l.nzmax);
            let lx = std::slice::from_raw_parts(l.x as *const f64, l.nzmax);
            let mut y = cholmod_allocate_dense(n, 1, n, CHOLMOD_REAL, c);
            if y.is_null() {
                return Err(CholmodError("cholmod_allocate_dense failed".into()));
            }
            let yx = std::slice::from_raw_parts_mut((*y).x as *mut f64, n);
            yx.iter_mut().for_each(|v| *v = 0.0);
            let mut first = n;
            for &i in support {
                let k = self.inverse[i];
                yx[k] = x[i];
                first = first.min(k);
            }
            for j in first..n {
                let yj = yx[j];
                if yj == 0.0 {
                    continue;
                }
                reach += 1;
                let p0 = lp[j] as usize;
                for p in p0 + 1..p0 + lnz[j] as usize {
                    yx[li[p] as usize] -= lx[p] * yj;
                }
                yx[j] = yj / lx[p0];
            }
            let mut xd = cholmod_solve(CHOLMOD_LT, self.factor, y, c);
            cholmod_free_dense(&mut y, c);
            if xd.is_null() {
                return Err(CholmodError(format!("cholmod_solve (Lᵀ): CHOLMOD status {}", self.status())));
            }
            let xx = std::slice::from_raw_parts((*xd).x as *const f64, n);
            for (i, v) in x.iter_mut().enumerate() {
                *v = xx[self.inverse[i]];
            }
            cholmod_free_dense(&mut xd, c);
        }
        Ok(reach)
    }

    fn free_factor(&mut self) {
        if !self.factor.is_null() {
            // SAFETY: the factor was made by cholmod_analyze with this workspace.
            unsafe { cholmod_free_factor(&mut self.factor, self.common.as_mut_ptr()) };
            self.factor = std::ptr::null_mut();
        }
    }
}

impl Drop for UpdatableCholesky {
    fn drop(&mut self) {
        self.free_factor();
        // SAFETY: the workspace was started in `new`.
        unsafe { cholmod_finish(self.common.as_mut_ptr()) };
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use nalgebra::{DMatrix, DVector};

    /// A tridiagonal SPD matrix `tridiag(−1, 4, −1)` of size `n`, upper triplets and dense.
    fn tridiagonal(n: usize) -> (Vec<Triplet<usize, usize, f64>>, DMatrix<f64>) {
        let mut t = Vec::new();
        let mut a = DMatrix::zeros(n, n);
        for i in 0..n {
            t.push(Triplet::new(i, i, 4.0));
            a[(i, i)] = 4.0;
            if i + 1 < n {
                t.push(Triplet::new(i, i + 1, -1.0));
                a[(i, i + 1)] = -1.0;
                a[(i + 1, i)] = -1.0;
            }
        }
        (t, a)
    }

    #[test]
    fn solves_and_updates_match_dense_algebra() {
        // tridiag(−1, 4, −1) of size 40 (SPD: eigenvalues in (2, 6)); b = (1, 2, …). The solve
        // matches nalgebra's dense Cholesky to 1e-12 relative; then a rank-3 downdate (a "beam"
        // coupling unknowns 3 and 17, u = (1, −1)·0.8 and two more columns), a rank-1 update
        // (a "contact" between 5 and 30 with new fill) and the downdate of that update: each
        // solve matches the dense solve of the modified matrix to 1e-12 relative (the condition
        // number stays below 10, so round-off is far below that).
        let n = 40;
        let (t, mut a) = tridiagonal(n);
        let mut f = UpdatableCholesky::new(n).unwrap();
        f.factorize(&t).unwrap();
        let b = DVector::from_iterator(n, (0..n).map(|i| 1.0 + i as f64));
        let check = |f: &mut UpdatableCholesky, a: &DMatrix<f64>| {
            let mut x = b.as_slice().to_vec();
            f.solve(&mut x).unwrap();
            let want = a.clone().cholesky().unwrap().solve(&b);
            let err = (DVector::from_vec(x) - &want).amax() / want.amax();
            assert!(err < 1e-12, "relative error {err}");
        };
        check(&mut f, &a);
        let beam: Vec<Column> =
            vec![vec![(3, 0.8), (17, -0.8)], vec![(3, 0.5), (4, 0.3)], vec![(16, 0.4), (17, 0.2), (18, -0.1)]];
        f.update(&beam, -1.0).unwrap();
        for u in &beam {
            for &(i, vi) in u {
                for &(j, vj) in u {
                    a[(i, j)] -= vi * vj;
                }
            }
        }
        check(&mut f, &a);
        let contact: Vec<Column> = vec![vec![(5, 1.1), (30, -1.1)]];
        f.update(&contact, 1.0).unwrap();
        let mut a2 = a.clone();
        for &(i, vi) in &contact[0] {
            for &(j, vj) in &contact[0] {
                a2[(i, j)] += vi * vj;
            }
        }
        check(&mut f, &a2);
        f.update(&contact, -1.0).unwrap();
        check(&mut f, &a);
        assert_eq!((f.n_factorizations, f.n_updates), (1, 3));
    }

    #[test]
    fn sparse_right_hand_sides_solve_as_dense_ones_over_a_fraction_of_the_factor() {
        // The 5-point Laplacian of a 30 × 30 grid plus 0.1 I (SPD), b non-zero on the three
        // unknowns of one grid node's neighbourhood (a "beam force"). solve_sparse agrees with
        // the dense solve to 1e-13 relative (the same substitutions; only the order in which the
        // forward solve visits its columns may differ, a round-off of the condition number
        // ~ 8/0.1 times 1e-16), before and after a rank-one update that extends L's pattern.
        // Its forward substitution visits the reach of those rows in the elimination tree,
        // which for a 2D grid under a fill-reducing ordering is a path of separators, far
        // fewer than the 900 columns (found: 59 both times; asserted below a quarter, n/4).
        let m = 30;
        let n = m * m;
        let mut t = Vec::new();
        let mut a = DMatrix::zeros(n, n);
        for r in 0..m {
            for col in 0..m {
                let i = r * m + col;
                t.push(Triplet::new(i, i, 4.1));
                a[(i, i)] = 4.1;
                for j in [(col + 1 < m).then(|| i + 1), (r + 1 < m).then(|| i + m)].into_iter().flatten() {
                    t.push(Triplet::new(i, j, -1.0));
                    (a[(i, j)], a[(j, i)]) = (-1.0, -1.0);
                }
            }
        }
        let mut f = UpdatableCholesky::new(n).unwrap();
        f.factorize(&t).unwrap();
        let support = [434, 435, 464];
        let mut b = vec![0.0; n];
        for (k, &i) in support.iter().enumerate() {
            b[i] = 1.0 + k as f64;
        }
        let check = |f: &mut UpdatableCholesky| {
            let mut dense = b.clone();
            f.solve(&mut dense).unwrap();
            // Entries off the support are ignored, whatever they hold.
            let mut sparse: Vec<f64> = (0..n).map(|i| if support.contains(&i) { b[i] } else { 7.0 }).collect();
            let reach = f.solve_sparse(&mut sparse, &support).unwrap();
            let scale = dense.iter().fold(0.0f64, |m, v| m.max(v.abs()));
            let err = dense.iter().zip(&sparse).fold(0.0f64, |m, (d, s)| m.max((d - s).abs())) / scale;
            assert!(err < 1e-13, "relative difference {err}");
            assert!(reach >= support.len() && reach < n / 4, "reach {reach} of {n}");
        };
        check(&mut f);
        f.update(&[vec![(2, 0.9), (897, -0.9)]], 1.0).unwrap();
        check(&mut f);
        assert!(f.solve_sparse(&mut b, &[n]).is_err(), "a support entry out of range is an error");
    }

    #[test]
    fn entries_count_the_factor_and_its_fill() {
        // A tridiagonal matrix of size n has a Cholesky factor without fill under any ordering
        // that CHOLMOD picks for it (AMD keeps a path graph's elimination fill-free): 2n − 1
        // entries, Σ c_j² = 4(n − 1) + 1 over the column counts (2, …, 2, 1). A rank-one update
        // coupling unknowns 5 and 30 extends the pattern: more entries, never fewer.
        let n = 40;
        let (t, _) = tridiagonal(n);
        let mut f = UpdatableCholesky::new(n).unwrap();
        assert_eq!((f.entries(), f.factorization_flops()), (0, 0.0));
        f.factorize(&t).unwrap();
        assert_eq!(f.entries(), 2 * n - 1);
        assert_eq!(f.factorization_flops(), (4 * (n - 1) + 1) as f64);
        f.update(&[vec![(5, 1.1), (30, -1.1)]], 1.0).unwrap();
        assert!(f.entries() > 2 * n - 1, "no fill from the coupling: {} entries", f.entries());
    }

    #[test]
    fn downdate_to_indefinite_and_bad_input_are_errors() {
        // tridiag(−1, 4, −1) minus 5 e₀e₀ᵀ has A₀₀ = −1: not positive definite (the pivot of
        // unknown 0 comes out negative, whichever position the ordering gives it).
        let (t, _) = tridiagonal(6);
        let mut f = UpdatableCholesky::new(6).unwrap();
        let mut x = vec![1.0; 6];
        assert!(f.solve(&mut x).is_err(), "solve before factorization");
        f.factorize(&t).unwrap();
        let e = f.update(&[vec![(0, 5f64.sqrt())]], -1.0).unwrap_err();
        assert!(e.0.contains("not positive definite"), "{}", e.0);
        // A stone losing its last contact: unknown 0 held to unknown 1 by 4 (e₀ − e₁)(e₀ − e₁)ᵀ
        // and to the ground by ε only, unknowns 1…5 tridiag(−1, 4, −1). Downdating the contact
        // leaves A SPD with unknown 0's pivot exactly ε, a fall by ε/(4 + ε) or more. With
        // ε = 1e-13 (below MIN_PIVOT_RATIO): cancellation, an error. With ε = 1e-9 (a ratio
        // near 2.5e-10) it is accepted, the smallest pivot within 1e-5 of 1e-9 (the cancellation
        // costs a few units in the last place of 4, 8.9e-16 each).
        let loose = |eps: f64| {
            let mut t = vec![Triplet::new(0, 0, 4.0 + eps), Triplet::new(0, 1, -4.0), Triplet::new(1, 1, 8.0)];
            for i in 1..6 {
                if i > 1 {
                    t.push(Triplet::new(i, i, 4.0));
                }
                if i + 1 < 6 {
                    t.push(Triplet::new(i, i + 1, -1.0));
                }
            }
            t
        };
        let contact = vec![(0, 2.0), (1, -2.0)];
        f.factorize(&loose(1e-13)).unwrap();
        let e = f.update(std::slice::from_ref(&contact), -1.0).unwrap_err();
        assert!(e.0.contains("cancelled"), "{}", e.0);
        f.factorize(&loose(1e-9)).unwrap();
        f.update(std::slice::from_ref(&contact), -1.0).unwrap();
        let p1 = f.pivots().into_iter().fold(f64::INFINITY, f64::min);
        assert!((p1 - 1e-9).abs() <= 1e-5 * 1e-9, "smallest pivot {p1}");
        f.factorize(&t).unwrap();
        assert!(f.update(&[vec![(6, 1.0)]], 1.0).is_err(), "row outside");
        assert!(f.solve(&mut [1.0; 5]).is_err(), "wrong length");
        let lower = vec![Triplet::new(1, 0, 1.0)];
        assert!(f.factorize(&lower).is_err(), "lower triplet");
    }
}
