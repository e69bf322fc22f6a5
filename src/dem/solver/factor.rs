//! The linear solver: a sparse Cholesky factorization of a base matrix `A` (faer) plus a
//! low-rank correction handled by the Woodbury identity.
//!
//! # Low-rank updates
//! Breaking a beam removes its stiffness `Gᵀ K_b G`, a symmetric positive semidefinite term of
//! rank ≤ 3; a contact adds or removes rank-1 terms. Each term is written `Σ_k s_k u_k u_kᵀ`
//! with `s_k = ±1` (from the eigen-decomposition of the 6×6 element matrix,
//! `u_k = √λ_k v_k`). With `U = [u_1 … u_m]`, `Σ = diag(s)`, the Woodbury identity
//! (`Σ⁻¹ = Σ`) gives
//!
//! ```text
//!   (A + U Σ Uᵀ)⁻¹ b = x₀ − Y M⁻¹ (Uᵀ x₀),   x₀ = A⁻¹ b,  Y = A⁻¹ U,  M = Σ + Uᵀ Y   (m × m)
//! ```
//!
//! `Y` is built column by column as terms arrive (one sparse solve per column), `M` grows by a
//! border and is re-factorized densely (LU, `m ≲ 100`). The caller refactorizes `A` when `m`
//! passes a threshold. When `A + UΣUᵀ` is close to singular, `M` is ill-conditioned and the
//! Woodbury solve loses digits: the caller's Newton loop measures the residual and refactorizes
//! if a solve was not accurate enough.
//!
//! The symbolic analysis (AMD ordering, elimination tree) is kept and reused as long as the
//! sparsity structure of `A` does not change (broken beams keep their entries, as zeros).
use faer::linalg::solvers::Solve;
use faer::sparse::linalg::solvers::{Llt, SymbolicLlt};
use faer::sparse::{SparseColMat, Triplet};
use faer::{MatMut, Side};
use nalgebra::DMatrix;

/// An SPD matrix's upper triangle as triplets `(row ≤ col)`, duplicates summed.
pub type UpperTriplets = Vec<Triplet<usize, usize, f64>>;

/// Why a factorization failed.
#[derive(Clone, Debug, PartialEq)]
pub struct FactorError(pub String);

/// `A = LLᵀ` and the Woodbury data of the terms added since.
pub struct LowRankCholesky {
    n: usize,
    symbolic: Option<(SymbolicLlt<usize>, Vec<usize>, Vec<usize>)>,
    llt: Option<Llt<usize, f64>>,
    u: Vec<Vec<f64>>,
    y: Vec<Vec<f64>>,
    sign: Vec<f64>,
    m: DMatrix<f64>,
    m_lu: Option<nalgebra::LU<f64, nalgebra::Dyn, nalgebra::Dyn>>,
    /// Number of numeric factorizations done.
    pub n_factorizations: usize,
    /// Number of symbolic analyses done.
    pub n_symbolic: usize,
}

impl LowRankCholesky {
    /// An empty solver for `n` unknowns (call [`Self::factorize`] first).
    pub fn new(n: usize) -> Self {
        LowRankCholesky {
            n,
            symbolic: None,
            llt: None,
            u: Vec::new(),
            y: Vec::new(),
            sign: Vec::new(),
            m: DMatrix::zeros(0, 0),
            m_lu: None,
            n_factorizations: 0,
            n_symbolic: 0,
        }
    }

    /// Number of unknowns.
    pub fn dim(&self) -> usize {
        self.n
    }

    /// Rank of the current correction (number of `u` columns).
    pub fn rank(&self) -> usize {
        self.u.len()
    }

    /// Factorizes `A` (upper triangle given) and drops the low-rank correction. The symbolic
    /// analysis is reused when the structure is unchanged.
    pub fn factorize(&mut self, upper: &UpperTriplets) -> Result<(), FactorError> {
        let a = SparseColMat::<usize, f64>::try_new_from_triplets(self.n, self.n, upper)
            .map_err(|e| FactorError(format!("matrix assembly: {e:?}")))?;
        let (cp, ri) = (a.symbolic().col_ptr().to_vec(), a.symbolic().row_idx().to_vec());
        let reuse = matches!(&self.symbolic, Some((_, c, r)) if *c == cp && *r == ri);
        if !reuse {
            let s = SymbolicLlt::try_new(a.symbolic(), Side::Upper)
                .map_err(|e| FactorError(format!("symbolic analysis: {e:?}")))?;
            self.symbolic = Some((s, cp, ri));
            self.n_symbolic += 1;
        }
        let sym = match &self.symbolic {
            Some((s, _, _)) => s.clone(),
            None => return Err(FactorError("no symbolic factorization".into())),
        };
        let llt = Llt::try_new_with_symbolic(sym, a.as_ref(), Side::Upper)
            .map_err(|e| FactorError(format!("numeric Cholesky: {e:?} (matrix not positive definite)")))?;
        self.llt = Some(llt);
        self.n_factorizations += 1;
        self.u.clear();
        self.y.clear();
        self.sign.clear();
        self.m = DMatrix::zeros(0, 0);
        self.m_lu = None;
        Ok(())
    }

    fn base_solve(&self, x: &mut [f64]) -> Result<(), FactorError> {
        let llt = self.llt.as_ref().ok_or_else(|| FactorError("solve before factorization".into()))?;
        llt.solve_in_place(MatMut::from_column_major_slice_mut(x, self.n, 1));
        Ok(())
    }

    /// Adds `sign · u uᵀ` for each column `u` (length `n`) to the operator.
    pub fn add_terms(&mut self, cols: Vec<Vec<f64>>, sign: f64) -> Result<(), FactorError> {
        if cols.is_empty() {
            return Ok(());
        }
        let old = self.u.len();
        for u in cols {
            let mut y = u.clone();
            self.base_solve(&mut y)?;
            self.u.push(u);
            self.y.push(y);
            self.sign.push(sign);
        }
        let m = self.u.len();
        let mut big = DMatrix::zeros(m, m);
        big.view_mut((0, 0), (old, old)).copy_from(&self.m);
        for r in 0..m {
            for c in old.max(r)..m {
                // M_rc = s_r δ_rc + u_r · y_c  (symmetric: u_r·A⁻¹u_c)
                let v = dot(&self.u[r], &self.y[c]) + if r == c { self.sign[r] } else { 0.0 };
                big[(r, c)] = v;
                big[(c, r)] = v;
            }
        }
        self.m = big;
        self.m_lu = Some(self.m.clone().lu());
        Ok(())
    }

    /// Whether the Woodbury correction can be used: its capacitance matrix `M` is invertible and
    /// not close to singular (reciprocal condition estimate from the LU pivots above 10⁻¹²).
    /// When it is not, the caller refactorizes `A + UΣUᵀ` directly.
    pub fn is_accurate(&self) -> bool {
        let Some(lu) = &self.m_lu else { return true };
        let u = lu.u();
        let d: Vec<f64> = (0..u.nrows()).map(|k| u[(k, k)].abs()).collect();
        let (lo, hi) = d.iter().fold((f64::INFINITY, 0.0f64), |(lo, hi), &x| (lo.min(x), hi.max(x)));
        lo.is_finite() && lo > 1e-12 * hi
    }

    /// Solves `(A + UΣUᵀ) x = b` in place.
    pub fn solve(&self, x: &mut [f64]) -> Result<(), FactorError> {
        self.base_solve(x)?;
        if let Some(lu) = &self.m_lu {
            let w = nalgebra::DVector::from_iterator(self.u.len(), self.u.iter().map(|u| dot(u, x)));
            let c = lu.solve(&w).ok_or_else(|| FactorError("singular Woodbury capacitance matrix".into()))?;
            for (k, y) in self.y.iter().enumerate() {
                let ck = c[k];
                for (xi, yi) in x.iter_mut().zip(y) {
                    *xi -= ck * yi;
                }
            }
        }
        Ok(())
    }
}

fn dot(a: &[f64], b: &[f64]) -> f64 {
    a.iter().zip(b).map(|(x, y)| x * y).sum()
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A 1D chain of springs k_e between n+1 nodes, node 0 fixed (SPD tridiagonal), plus a
    /// diagonal 0.1 to keep it SPD after removing springs.
    fn chain(n: usize, k: &[f64]) -> UpperTriplets {
        let mut t = Vec::new();
        for e in 0..n {
            // spring between node e and e+1 (unknown index e-1, e); node 0 fixed.
            let (a, b) = (e as isize - 1, e as isize);
            t.push(Triplet::new(b as usize, b as usize, k[e]));
            if a >= 0 {
                t.push(Triplet::new(a as usize, a as usize, k[e]));
                t.push(Triplet::new(a as usize, b as usize, -k[e]));
            }
        }
        for i in 0..n {
            t.push(Triplet::new(i, i, 0.1));
        }
        t
    }

    #[test]
    fn woodbury_equals_fresh_factorization() {
        // Remove springs 3, 7 and 11 (each a rank-1 term −k (e_a − e_b)(e_a − e_b)ᵀ) and add a
        // diagonal spring: the Woodbury solve must match a fresh factorization of the updated
        // matrix to 1e-10 relative.
        let n = 20;
        let k: Vec<f64> = (0..n).map(|e| 1.0 + 0.37 * e as f64).collect();
        let mut f = LowRankCholesky::new(n);
        f.factorize(&chain(n, &k)).unwrap();
        let mut k2 = k.clone();
        for e in [3usize, 7, 11] {
            let mut u = vec![0.0; n];
            u[e] = k[e].sqrt();
            u[e - 1] = -k[e].sqrt();
            f.add_terms(vec![u], -1.0).unwrap();
            k2[e] = 0.0;
        }
        let mut u = vec![0.0; n];
        u[5] = 2.0;
        f.add_terms(vec![u], 1.0).unwrap();
        let mut t2 = chain(n, &k2);
        t2.push(Triplet::new(5, 5, 4.0));
        let mut g = LowRankCholesky::new(n);
        g.factorize(&t2).unwrap();
        let b: Vec<f64> = (0..n).map(|i| (i as f64 * 0.7).sin() + 0.3).collect();
        let (mut x1, mut x2) = (b.clone(), b.clone());
        f.solve(&mut x1).unwrap();
        g.solve(&mut x2).unwrap();
        let scale = x2.iter().fold(0.0f64, |m, v| m.max(v.abs()));
        for i in 0..n {
            assert!((x1[i] - x2[i]).abs() <= 1e-10 * scale, "{i}: {} vs {}", x1[i], x2[i]);
        }
        assert_eq!(f.rank(), 4);
        // Same structure: the symbolic analysis is reused.
        f.factorize(&chain(n, &k2)).unwrap();
        assert_eq!((f.n_symbolic, f.n_factorizations), (1, 2));
    }

    #[test]
    fn indefinite_matrix_is_an_error() {
        let mut f = LowRankCholesky::new(2);
        let t = vec![Triplet::new(0, 0, 1.0), Triplet::new(1, 1, -1.0)];
        assert!(f.factorize(&t).is_err());
        let mut x = vec![1.0, 1.0];
        assert!(LowRankCholesky::new(2).solve(&mut x).is_err());
    }
}
