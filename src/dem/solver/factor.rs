//! The linear solver: a sparse Cholesky factorization of a base matrix `A` (faer, sequential)
//! plus a low-rank correction handled by the Woodbury identity, and the cost model that decides
//! when refactorizing is cheaper than carrying the correction.
//!
//! # Low-rank updates
//! Breaking a beam removes its stiffness `Gᵀ K_b G`, a symmetric positive semidefinite term of
//! rank ≤ 3; a contact adds or removes rank-1 terms. Each term is written `Σ_k s_k u_k u_kᵀ`
//! with `s_k = ±1` (from the eigen-decomposition of the 6×6 element matrix,
//! `u_k = √λ_k v_k`; each `u_k` has at most six non-zeros). With `U = [u_1 … u_m]`,
//! `Σ = diag(s)`, the Woodbury identity (`Σ⁻¹ = Σ`) gives
//!
//! ```text
//!   (A + U Σ Uᵀ)⁻¹ b = x₀ − Y M⁻¹ (Uᵀ x₀),   x₀ = A⁻¹ b,  Y = A⁻¹ U,  M = Σ + Uᵀ Y   (m × m)
//! ```
//!
//! `Y` is built as terms arrive (the new terms' columns solved together, [`BATCH`] right-hand
//! sides per pass over `L`), `M` is recomputed from the sparse `U` (`6m²` flops) and factorized densely
//! (LU, `m ≲ 100`). A term that leaves again before the next factorization ([`Self::remove`],
//! e.g. a contact that opens in the next Newton iteration) has its columns dropped: exact and
//! free, instead of a second, cancelling term. When `A + UΣUᵀ` is close to singular, `M` is
//! ill-conditioned and the Woodbury solve loses digits ([`Self::is_accurate`]).
//!
//! # When to refactorize (cost model)
//! Costs are counted in flops from the symbolic structure of `L` (deterministic: the same run
//! makes the same choices on any machine):
//!
//! ```text
//!   one base solve        W_s = 4 nnz(L)                     (forward + backward substitution)
//!   one factorization     W_f = Σ_j c_j² / R                 (c_j = entries of column j of L)
//!   a Woodbury column     W_s, or W_s (1 + (k−1) β)          (alone, or k in one pass)
//!   a corrected solve     W_s + 4 m n                        (Uᵀx₀ is sparse; Y c is dense)
//! ```
//!
//! `β` = [`BATCH_COLUMN_COST`]; `R` is how much faster per flop the factorization runs than the
//! substitutions (memory-bound): [`FACTOR_SPEEDUP`] for a supernodal factor (dense blocks,
//! BLAS-3), [`FACTOR_SPEEDUP_SIMPLICIAL`] for a simplicial one (small systems), measured on the
//! DEM operators of 1k and 10k stones (`examples/dem_factorization.rs`). The flops spent on the correction since the
//! last factorization (its columns and the extra `4mn` of every solve) are summed; once they
//! pass `W_f` the caller refactorizes ([`Self::wants_refactorization`]). This is the
//! rent-or-buy rule: whatever the future sequence of updates, it costs at most twice the best
//! schedule chosen in hindsight.
//!
//! # Updates in place
//! [`LowRankCholesky::with_updates`] keeps no correction: each term is an update (`+`) or a
//! downdate (`−`) of CHOLMOD's simplicial `LDLᵀ` in place ([`super::cholmod`]), so a solve
//! always costs one pair of substitutions with the current factor. A term leaving is a
//! downdate ([`LowRankCholesky::remove`] answers `false`). What accumulates is fill: a contact
//! between stones that no beam joined extends the pattern of `L`, and a downdate never shrinks
//! it, so the solves grow dearer (a 50k-stone tension test: 14.3M entries after the first
//! factorization, 19.1M after 350 breaks). The same rent-or-buy rule buys it back: each solve
//! books `4 (E − E₀)` flops (`E₀` the entries after the last factorization, `E` now), and once
//! they pass [`FILL_REFACTOR_FACTOR`] times the factorization's `Σ c_j²` the caller
//! refactorizes (a fresh analysis of the current pattern, without the pairs apart). Otherwise
//! only a downdate that loses a pivot to round-off ([`LowRankCholesky::needs_rebuild`]), a
//! floating stone or a continuation refactorizes. Chosen by
//! [`super::SolverOptions::updates_in_place`].
//!
//! # Sparse right-hand sides
//! Where no contact is active, Newton's step solves `M Δz = r` with `r` concentrated on few
//! unknowns: after a break, the released beam's force on its two stones (and the previous
//! equilibrium's round-off everywhere); at a load step, the platens' move on the stones bonded
//! to them. With updates in place the forward substitution `L y = P r` then visits only the
//! columns of `L` on the elimination tree's paths from those rows to the root (Gilbert and
//! Peierls' reach), and only the backward substitution is dense
//! ([`LowRankCholesky::solve_sparse`]). The caller (`equilibrium.rs`) drops the entries
//! of `r` below `SPARSE_RHS_DROP · tol · scale` (`10⁻⁵` of the residual tolerance): the step is
//! exact for the rest, so the state it reaches keeps at most that residual, against the
//! `tol · scale` of convergence. Chosen by [`super::SolverOptions::sparse_rhs`]; never with
//! crushing (its softening makes the path depend on differences below the tolerance).
//!
//! The symbolic analysis (fill-reducing ordering, elimination tree, supernodes) is kept and reused
//! as long as the sparsity structure of `A` does not change (broken beams keep their entries, as
//! zeros). The ordering is faer's AMD for small systems and METIS nested dissection
//! ([`super::ordering`]) from [`NESTED_DISSECTION_MIN`] unknowns on.
use faer::dyn_stack::{MemBuffer, MemStack};
use faer::perm::PermRef;
use faer::sparse::linalg::cholesky::{
    factorize_symbolic_cholesky, LltRef, SymbolicCholesky, SymbolicCholeskyRaw, SymmetricOrdering,
};
use faer::sparse::{Argsort, Pair, SparseColMat, SymbolicSparseColMat, Triplet};
use faer::{Conj, MatMut, Par, Side};
use nalgebra::DMatrix;

use super::cholmod::UpdatableCholesky;

/// An SPD matrix's upper triangle as triplets `(row ≤ col)`, duplicates summed.
pub type UpperTriplets = Vec<Triplet<usize, usize, f64>>;

/// A sparse column: `(row, value)` pairs.
pub type SparseColumn = Vec<(usize, f64)>;

/// How much faster per flop a supernodal numeric factorization runs than a pair of triangular
/// solves (measured with `examples/dem_factorization.rs`, sequential faer: 10k stones, 2.9).
pub const FACTOR_SPEEDUP: f64 = 3.0;

/// The same for a simplicial factorization (small systems; faer picks it from the structure):
/// slower per flop than the substitutions (1k stones: 0.27).
pub const FACTOR_SPEEDUP_SIMPLICIAL: f64 = 0.3;

/// With updates in place: the refactorization is due once the fill that updates brought into
/// `L` has cost this many times the flops of its factorization (`Σ c_j²`) in extra solve work
/// (`4` flops per extra entry per solve): the rent-or-buy rule of the Woodbury correction, with
/// CHOLMOD's simplicial factorization and substitutions at about the same rate per flop.
pub const FILL_REFACTOR_FACTOR: f64 = 1.0;

/// Right-hand sides solved together when Woodbury columns are added ([`LowRankCholesky::add_batch`]).
pub const BATCH: usize = 16;

/// Cost of each further right-hand side of a batched solve, in base solves (measured with
/// `examples/dem_factorization.rs`).
pub const BATCH_COLUMN_COST: f64 = 0.3;

/// The fill-reducing ordering of the symbolic analysis.
#[derive(Clone, Copy, Debug, PartialEq, Eq, serde::Serialize)]
#[serde(rename_all = "snake_case")]
pub enum Ordering {
    /// Approximate minimum degree (faer's own).
    Amd,
    /// METIS nested dissection ([`super::ordering`]).
    NestedDissection,
}

/// Systems with at least this many unknowns are ordered by nested dissection, smaller ones by
/// AMD (measured with `examples/dem_factorization.rs`, which factorizes with both).
pub const NESTED_DISSECTION_MIN: usize = 20_000;

/// Why a factorization failed.
#[derive(Clone, Debug, PartialEq)]
pub struct FactorError(pub String);

/// Handle of a term in the Woodbury correction (see [`LowRankCholesky::remove`]).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub struct TermId(u64);

struct Symbolic {
    sym: SymbolicCholesky<usize>,
    col_ptr: Vec<usize>,
    row_idx: Vec<usize>,
    /// `4 nnz(L)`.
    solve_flops: f64,
    /// `Σ_j c_j² / R`.
    factor_flops: f64,
}

/// A term of the correction: its id, its columns' range in `u`/`y`/`sign`.
struct Term {
    id: TermId,
    start: usize,
    len: usize,
}

/// `A = LLᵀ` and the Woodbury data of the terms added since.
pub struct LowRankCholesky {
    n: usize,
    /// The ordering of the symbolic analysis.
    pub ordering: Ordering,
    symbolic: Option<Symbolic>,
    /// The last matrix's triplet indices, its structure and the triplets' order into it.
    #[allow(clippy::type_complexity)]
    assembly: Option<(Vec<(usize, usize)>, SymbolicSparseColMat<usize>, Argsort<usize>)>,
    values: Vec<f64>,
    factorized: bool,
    scratch: MemBuffer,
    terms: Vec<Term>,
    next_id: u64,
    u: Vec<SparseColumn>,
    y: Vec<Vec<f64>>,
    sign: Vec<f64>,
    m_lu: Option<nalgebra::LU<f64, nalgebra::Dyn, nalgebra::Dyn>>,
    /// Flops spent on the correction since the last factorization (see the module docs).
    spent: f64,
    /// Number of numeric factorizations done.
    pub n_factorizations: usize,
    /// Number of symbolic analyses done.
    pub n_symbolic: usize,
    /// Woodbury columns computed (one base solve each).
    pub n_columns: usize,
    /// Woodbury columns dropped by [`Self::remove`].
    pub n_dropped: usize,
    /// With [`Self::with_updates`]: CHOLMOD's factor, updated and downdated in place instead of
    /// the Woodbury correction ("Updates in place" in the module docs).
    updown: Option<UpdatableCholesky>,
    /// An update in place failed (a pivot lost to round-off): the factor is to be rebuilt.
    update_failed: bool,
    /// With [`Self::with_updates`]: the entries of `L` after the last factorization and now
    /// ("Updates in place" in the module docs: the fill that updates bring).
    pub entries: (usize, usize),
    /// With [`Self::with_updates`]: the flops of the last factorization, `Σ c_j²`.
    updown_factor_flops: f64,
    /// With [`Self::with_updates`]: the refactorization is due once the fill has cost this many
    /// factorizations ([`FILL_REFACTOR_FACTOR`]).
    fill_refactor: f64,
}

impl LowRankCholesky {
    /// An empty solver for `n` unknowns (call [`Self::factorize`] first), ordered by nested
    /// dissection from [`NESTED_DISSECTION_MIN`] unknowns on, else by AMD.
    pub fn new(n: usize) -> Self {
        Self::with_ordering(n, if n >= NESTED_DISSECTION_MIN { Ordering::NestedDissection } else { Ordering::Amd })
    }

    /// An empty solver for `n` unknowns with the given ordering.
    pub fn with_ordering(n: usize, ordering: Ordering) -> Self {
        LowRankCholesky {
            n,
            ordering,
            symbolic: None,
            assembly: None,
            values: Vec::new(),
            factorized: false,
            scratch: MemBuffer::new(faer::dyn_stack::StackReq::EMPTY),
            terms: Vec::new(),
            next_id: 0,
            u: Vec::new(),
            y: Vec::new(),
            sign: Vec::new(),
            m_lu: None,
            spent: 0.0,
            n_factorizations: 0,
            n_symbolic: 0,
            n_columns: 0,
            n_dropped: 0,
            updown: None,
            update_failed: false,
            entries: (0, 0),
            updown_factor_flops: 0.0,
            fill_refactor: FILL_REFACTOR_FACTOR,
        }
    }

    /// An empty solver for `n` unknowns whose terms are updates and downdates of CHOLMOD's
    /// factor in place ("Updates in place" in the module docs): no correction accumulates,
    /// [`Self::rank`] stays 0, and the cost model asks for a refactorization once the fill of
    /// the updates has cost `fill_refactor` factorizations.
    pub fn with_updates(n: usize, fill_refactor: f64) -> Result<Self, FactorError> {
        let mut s = Self::with_ordering(n, Ordering::Amd);
        s.fill_refactor = fill_refactor;
        s.updown = Some(UpdatableCholesky::new(n).map_err(|e| FactorError(e.0))?);
        Ok(s)
    }

    /// The preconditioner's supernodal copies made ([`Self::precondition`]).
    pub fn copies(&self) -> usize {
        self.updown.as_ref().map_or(0, |f| f.n_copies)
    }

    /// Whether the factor is updated in place ([`Self::with_updates`]).
    pub fn updates_in_place(&self) -> bool {
        self.updown.is_some()
    }

    /// Whether an update in place failed since the last factorization (a downdate that left a
    /// pivot not positive by round-off): the caller refactorizes before the next solve.
    pub fn needs_rebuild(&self) -> bool {
        self.update_failed
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
    ///
    /// The triplets' order into the compressed columns (a sort of all of them) is kept and reused
    /// while the triplets come with the same indices in the same order: the matrix is then the
    /// same as built from scratch, bit for bit (duplicates summed in the same order).
    pub fn factorize(&mut self, upper: &UpperTriplets) -> Result<(), FactorError> {
        self.factorized = false;
        if let Some(f) = &mut self.updown {
            f.factorize(upper).map_err(|e| FactorError(e.0))?;
            self.entries = (f.entries(), f.entries());
            self.updown_factor_flops = f.factorization_flops();
            self.spent = 0.0;
            self.factorized = true;
            self.update_failed = false;
            self.n_factorizations += 1;
            self.n_symbolic += 1;
            return Ok(());
        }
        let same = self.assembly.as_ref().is_some_and(|(idx, _, _)| {
            idx.len() == upper.len() && idx.iter().zip(upper).all(|(&(r, c), t)| r == t.row && c == t.col)
        });
        if !same {
            let idx: Vec<(usize, usize)> = upper.iter().map(|t| (t.row, t.col)).collect();
            let pairs: Vec<Pair<usize, usize>> = idx.iter().map(|&(row, col)| Pair { row, col }).collect();
            let (sym, argsort) = SymbolicSparseColMat::try_new_from_indices(self.n, self.n, &pairs)
                .map_err(|e| FactorError(format!("matrix assembly: {e:?}")))?;
            self.assembly = Some((idx, sym, argsort));
        }
        let Some((_, sym, argsort)) = &self.assembly else { return Err(FactorError("no matrix structure".into())) };
        let values: Vec<f64> = upper.iter().map(|t| t.val).collect();
        let a = SparseColMat::<usize, f64>::new_from_argsort(sym.clone(), argsort, &values)
            .map_err(|e| FactorError(format!("matrix assembly: {e:?}")))?;
        let (cp, ri) = (a.symbolic().col_ptr(), a.symbolic().row_idx());
        let reuse = matches!(&self.symbolic, Some(s) if s.col_ptr == cp && s.row_idx == ri);
        if !reuse {
            let symbolic = |ord: SymmetricOrdering<'_, usize>| {
                factorize_symbolic_cholesky(a.symbolic(), Side::Upper, ord, Default::default())
                    .map_err(|e| FactorError(format!("symbolic analysis: {e:?}")))
            };
            let sym = match self.ordering {
                Ordering::Amd => symbolic(SymmetricOrdering::Amd)?,
                Ordering::NestedDissection => {
                    let (perm, inv) = super::ordering::nested_dissection(self.n, cp, ri)
                        .map_err(|e| FactorError(format!("nested dissection: {}", e.0)))?;
                    symbolic(SymmetricOrdering::Custom(PermRef::new_checked(&perm, &inv, self.n)))?
                }
            };
            let (solve_flops, factor_flops) = flop_counts(&sym);
            let req = sym
                .factorize_numeric_llt_scratch::<f64>(Par::Seq, Default::default())
                .or(sym.solve_in_place_scratch::<f64>(BATCH, Par::Seq));
            self.scratch = MemBuffer::try_new(req).map_err(|e| FactorError(format!("workspace: {e:?}")))?;
            self.values = vec![0.0; sym.len_val()];
            self.symbolic =
                Some(Symbolic { sym, col_ptr: cp.to_vec(), row_idx: ri.to_vec(), solve_flops, factor_flops });
            self.n_symbolic += 1;
        }
        let Some(s) = &self.symbolic else { return Err(FactorError("no symbolic factorization".into())) };
        s.sym
            .factorize_numeric_llt::<f64>(
                &mut self.values,
                a.as_ref(),
                Side::Upper,
                Default::default(),
                Par::Seq,
                MemStack::new(&mut self.scratch),
                Default::default(),
            )
            .map_err(|e| FactorError(format!("numeric Cholesky: {e:?} (matrix not positive definite)")))?;
        self.factorized = true;
        self.n_factorizations += 1;
        self.terms.clear();
        self.u.clear();
        self.y.clear();
        self.sign.clear();
        self.m_lu = None;
        self.spent = 0.0;
        Ok(())
    }

    /// Solves `A X = B` in place for the `k` columns of `x` (column-major, `n × k`, `k ≤ BATCH`).
    fn base_solve(&mut self, x: &mut [f64], k: usize) -> Result<(), FactorError> {
        let s = match (&self.symbolic, self.factorized) {
            (Some(s), true) => s,
            _ => return Err(FactorError("solve before factorization".into())),
        };
        LltRef::new(&s.sym, &self.values).solve_in_place_with_conj(
            Conj::No,
            MatMut::from_column_major_slice_mut(x, self.n, k),
            Par::Seq,
            MemStack::new(&mut self.scratch),
        );
        Ok(())
    }

    /// `(W_s, W_f)`: flops of one base solve and (scaled by [`FACTOR_SPEEDUP`]) of one
    /// factorization; zero before the first factorization.
    pub fn costs(&self) -> (f64, f64) {
        self.symbolic.as_ref().map_or((0.0, 0.0), |s| (s.solve_flops, s.factor_flops))
    }

    /// Whether the correction has cost more than a factorization since the last one (see the
    /// module docs): the caller should refactorize `A + UΣUᵀ`.
    pub fn wants_refactorization(&self) -> bool {
        if self.updown.is_some() {
            return self.factorized && self.spent >= self.fill_refactor * self.updown_factor_flops;
        }
        let (_, w_f) = self.costs();
        !self.u.is_empty() && self.spent >= w_f
    }

    /// Adds `sign · u uᵀ` for each column `u` (sparse, length `n`) to the operator; returns the
    /// term's handle.
    pub fn add_terms(&mut self, cols: Vec<SparseColumn>, sign: f64) -> Result<TermId, FactorError> {
        let ids = self.add_batch(vec![(cols, sign)])?;
        ids.first().copied().ok_or_else(|| FactorError("no term added".into()))
    }

    /// Adds several terms `(columns, sign)` at once: their columns are solved together, up to
    /// [`BATCH`] right-hand sides per pass over `L` (the substitutions are memory-bound, so a
    /// pass with many right-hand sides costs little more than one). Returns the handles in order.
    pub fn add_batch(&mut self, terms: Vec<(Vec<SparseColumn>, f64)>) -> Result<Vec<TermId>, FactorError> {
        if let Some(f) = &mut self.updown {
            let mut ids = Vec::with_capacity(terms.len());
            for (cols, sign) in terms {
                if !self.update_failed && f.update(&cols, sign).is_err() {
                    self.update_failed = true;
                }
                self.entries.1 = f.entries();
                self.n_columns += cols.len();
                ids.push(TermId(self.next_id));
                self.next_id += 1;
            }
            return Ok(ids);
        }
        let n = self.n;
        let k: usize = terms.iter().map(|t| t.0.len()).sum();
        let mut rhs = vec![0.0; n * k];
        let mut c = 0;
        for (cols, _) in &terms {
            for col in cols {
                for &(r, v) in col {
                    rhs[c * n + r] += v;
                }
                c += 1;
            }
        }
        for chunk in rhs.chunks_mut(BATCH * n) {
            let kk = chunk.len() / n;
            self.base_solve(chunk, kk)?;
            self.spent += self.costs().0 * (1.0 + (kk as f64 - 1.0) * BATCH_COLUMN_COST);
        }
        let mut ids = Vec::with_capacity(terms.len());
        let mut c = 0;
        for (cols, sign) in terms {
            let id = TermId(self.next_id);
            self.next_id += 1;
            ids.push(id);
            let start = self.u.len();
            let len = cols.len();
            for col in cols {
                self.u.push(col);
                self.y.push(rhs[c * n..(c + 1) * n].to_vec());
                self.sign.push(sign);
                c += 1;
            }
            if len > 0 {
                self.terms.push(Term { id, start, len });
            }
        }
        self.n_columns += k;
        if k > 0 {
            self.update_capacitance();
        }
        Ok(ids)
    }

    /// Removes a term added since the last factorization (drops its columns: exact, no solve)
    /// and returns `true`; `false` when the term is not in the correction (it was folded into `A`
    /// by a factorization since: the caller subtracts it as a new term).
    pub fn remove(&mut self, id: TermId) -> bool {
        if self.updown.is_some() {
            return false; // in the factor already: subtracted as a new term
        }
        let Some(pos) = self.terms.iter().position(|t| t.id == id) else { return false };
        let t = self.terms.remove(pos);
        self.u.drain(t.start..t.start + t.len);
        self.y.drain(t.start..t.start + t.len);
        self.sign.drain(t.start..t.start + t.len);
        for later in &mut self.terms[pos..] {
            later.start -= t.len;
        }
        self.n_dropped += t.len;
        self.update_capacitance();
        true
    }

    /// `M = Σ + Uᵀ Y` and its LU (`M_rc = s_r δ_rc + u_r · y_c`, symmetric: `u_r·A⁻¹u_c`).
    fn update_capacitance(&mut self) {
        let m = self.u.len();
        if m == 0 {
            self.m_lu = None;
            return;
        }
        let mut big = DMatrix::zeros(m, m);
        for r in 0..m {
            for c in r..m {
                let v = self.u[r].iter().map(|&(i, x)| x * self.y[c][i]).sum::<f64>()
                    + if r == c { self.sign[r] } else { 0.0 };
                big[(r, c)] = v;
                big[(c, r)] = v;
            }
        }
        self.m_lu = Some(big.lu());
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

    /// Solves `A x = b` in place for a `b` that is zero outside `support`, by a forward
    /// substitution over the support's reach only (module docs, "Sparse right-hand sides");
    /// `Some(columns visited)`, or `None` without updates in place (nothing solved: the caller
    /// solves densely).
    pub fn solve_sparse(&mut self, x: &mut [f64], support: &[usize]) -> Result<Option<usize>, FactorError> {
        let Some(f) = self.in_place_solve()? else { return Ok(None) };
        f.solve_sparse(x, support).map(Some).map_err(|e| FactorError(e.0))
    }

    /// With updates in place, the factor to solve with, the fill since the factorization booked
    /// for one solve (4 flops per extra entry of L: two substitutions); an error when an update
    /// failed since. `None` on the Woodbury path.
    fn in_place_solve(&mut self) -> Result<Option<&mut UpdatableCholesky>, FactorError> {
        let Some(f) = &mut self.updown else { return Ok(None) };
        if self.update_failed {
            return Err(FactorError("solve with a factor whose update failed (refactorize first)".into()));
        }
        self.spent += 4.0 * self.entries.1.saturating_sub(self.entries.0) as f64;
        Ok(Some(f))
    }

    /// GMRES's preconditioner solve: with updates in place, by the factor's `f32` supernodal
    /// copy once the factor has stayed unchanged for a few solves, from `min_entries` entries
    /// of `L` ([`UpdatableCholesky::precondition`]); otherwise [`Self::solve`].
    pub fn precondition(&mut self, x: &mut [f64], min_entries: usize) -> Result<(), FactorError> {
        match self.in_place_solve()? {
            Some(f) => f.precondition(x, min_entries).map_err(|e| FactorError(e.0)),
            None => self.solve(x),
        }
    }

    /// Solves `(A + UΣUᵀ) x = b` in place.
    pub fn solve(&mut self, x: &mut [f64]) -> Result<(), FactorError> {
        if let Some(f) = self.in_place_solve()? {
            return f.solve(x).map_err(|e| FactorError(e.0));
        }
        self.base_solve(x, 1)?;
        if let Some(lu) = &self.m_lu {
            let w = nalgebra::DVector::from_iterator(
                self.u.len(),
                self.u.iter().map(|u| u.iter().map(|&(i, v)| v * x[i]).sum::<f64>()),
            );
            let c = lu.solve(&w).ok_or_else(|| FactorError("singular Woodbury capacitance matrix".into()))?;
            for (k, y) in self.y.iter().enumerate() {
                let ck = c[k];
                for (xi, yi) in x.iter_mut().zip(y) {
                    *xi -= ck * yi;
                }
            }
            self.spent += 4.0 * (self.u.len() * self.n) as f64;
        }
        Ok(())
    }
}

/// `(4 nnz(L), Σ_j c_j² / R)` from the symbolic factor (`c_j` = entries of column `j`, diagonal
/// included). A supernode of `w` columns and `r` rows below its diagonal block holds, in its
/// `k`-th column, `w − k + r` entries.
fn flop_counts(sym: &SymbolicCholesky<usize>) -> (f64, f64) {
    let (mut nnz, mut work) = (0.0f64, 0.0f64);
    match sym.raw() {
        SymbolicCholeskyRaw::Simplicial(s) => {
            for w in s.col_ptr().windows(2) {
                let c = (w[1] - w[0]) as f64;
                nnz += c;
                work += c * c;
            }
            work /= FACTOR_SPEEDUP_SIMPLICIAL;
        }
        SymbolicCholeskyRaw::Supernodal(s) => {
            let rp = s.col_ptr_for_row_idx();
            for (k, (&b, &e)) in s.supernode_begin().iter().zip(s.supernode_end()).enumerate() {
                let (w, r) = (e - b, rp[k + 1] - rp[k]);
                for j in 0..w {
                    let c = (w - j + r) as f64;
                    nnz += c;
                    work += c * c;
                }
            }
            work /= FACTOR_SPEEDUP;
        }
    }
    (4.0 * nnz, work)
}

/// A dense column as a [`SparseColumn`] (its non-zeros).
pub fn sparse_column(u: &[f64]) -> SparseColumn {
    u.iter().enumerate().filter(|(_, v)| **v != 0.0).map(|(i, v)| (i, *v)).collect()
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

    fn spring(n: usize, e: usize, k: f64) -> SparseColumn {
        let mut u = vec![0.0; n];
        u[e] = k.sqrt();
        u[e - 1] = -k.sqrt();
        sparse_column(&u)
    }

    fn assert_close(x1: &[f64], x2: &[f64], tol: f64) {
        let scale = x2.iter().fold(0.0f64, |m, v| m.max(v.abs()));
        for i in 0..x1.len() {
            assert!((x1[i] - x2[i]).abs() <= tol * scale, "{i}: {} vs {}", x1[i], x2[i]);
        }
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
            f.add_terms(vec![spring(n, e, k[e])], -1.0).unwrap();
            k2[e] = 0.0;
        }
        f.add_terms(vec![vec![(5, 2.0)]], 1.0).unwrap();
        let mut t2 = chain(n, &k2);
        t2.push(Triplet::new(5, 5, 4.0));
        let mut g = LowRankCholesky::new(n);
        g.factorize(&t2).unwrap();
        let b: Vec<f64> = (0..n).map(|i| (i as f64 * 0.7).sin() + 0.3).collect();
        let (mut x1, mut x2) = (b.clone(), b.clone());
        f.solve(&mut x1).unwrap();
        g.solve(&mut x2).unwrap();
        assert_close(&x1, &x2, 1e-10);
        assert_eq!(f.rank(), 4);
        // Same structure: the symbolic analysis is reused.
        f.factorize(&chain(n, &k2)).unwrap();
        assert_eq!((f.n_symbolic, f.n_factorizations), (1, 2));
    }

    #[test]
    fn removing_a_term_restores_the_operator_exactly() {
        // Add three terms (one of two columns), remove the middle ones: the solve must match a
        // fresh factorization of the chain with only the remaining term (1e-10 relative), with
        // no further base solve (columns counted).
        let n = 16;
        let k: Vec<f64> = (0..n).map(|e| 2.0 + 0.1 * e as f64).collect();
        let mut f = LowRankCholesky::new(n);
        f.factorize(&chain(n, &k)).unwrap();
        let a = f.add_terms(vec![spring(n, 4, k[4])], -1.0).unwrap();
        let b = f.add_terms(vec![vec![(2, 1.5)], vec![(9, 0.5), (10, -0.5)]], 1.0).unwrap();
        let c = f.add_terms(vec![spring(n, 12, k[12])], -1.0).unwrap();
        assert_eq!((f.rank(), f.n_columns), (4, 4));
        assert!(f.remove(b));
        assert!(!f.remove(b), "a term is removed once");
        assert_eq!((f.rank(), f.n_columns, f.n_dropped), (2, 4, 2));
        let mut k2 = k.clone();
        k2[4] = 0.0;
        k2[12] = 0.0;
        let mut g = LowRankCholesky::new(n);
        g.factorize(&chain(n, &k2)).unwrap();
        let rhs: Vec<f64> = (0..n).map(|i| 1.0 + (i as f64).cos()).collect();
        let (mut x1, mut x2) = (rhs.clone(), rhs.clone());
        f.solve(&mut x1).unwrap();
        g.solve(&mut x2).unwrap();
        assert_close(&x1, &x2, 1e-10);
        // After a factorization the handles no longer refer to the correction.
        f.factorize(&chain(n, &k2)).unwrap();
        assert!(!f.remove(a) && !f.remove(c));
    }

    #[test]
    fn reused_assembly_gives_the_matrix_built_from_scratch() {
        // The same triplet indices with new values (the kept order into the columns), then other
        // indices (a new structure): each solve equals, bit for bit, that of a fresh solver
        // factorizing the same triplets.
        let n = 16;
        let k: Vec<f64> = (0..n).map(|e| 2.0 + 0.1 * e as f64).collect();
        let k2: Vec<f64> = k.iter().map(|x| 1.5 * x).collect();
        let mut other = chain(n, &k);
        other.push(Triplet::new(3, 9, 0.05));
        let rhs: Vec<f64> = (0..n).map(|i| 1.0 + (i as f64).sin()).collect();
        let mut f = LowRankCholesky::new(n);
        for t in [chain(n, &k), chain(n, &k2), other] {
            f.factorize(&t).unwrap();
            let mut g = LowRankCholesky::new(n);
            g.factorize(&t).unwrap();
            let (mut x1, mut x2) = (rhs.clone(), rhs.clone());
            f.solve(&mut x1).unwrap();
            g.solve(&mut x2).unwrap();
            assert_eq!(x1, x2);
        }
        assert_eq!(f.n_symbolic, 2);
    }

    #[test]
    fn flop_counts_match_a_dense_factor() {
        // A dense SPD 6×6 matrix has a full factor: nnz(L) = 21 entries, Σ c_j² = Σ_{c=1..6} c²
        // = 91 (exact counts of the formula in the module docs, any supernode partition).
        let n = 6;
        let mut t = Vec::new();
        for c in 0..n {
            for r in 0..=c {
                t.push(Triplet::new(r, c, if r == c { 10.0 } else { 1.0 }));
            }
        }
        let mut f = LowRankCholesky::new(n);
        f.factorize(&t).unwrap();
        let (w_s, w_f) = f.costs();
        assert_eq!(w_s, 4.0 * 21.0);
        let r = (91.0 / w_f - FACTOR_SPEEDUP).abs().min((91.0 / w_f - FACTOR_SPEEDUP_SIMPLICIAL).abs());
        assert!(r < 1e-12, "W_f = {w_f}");
        assert!(!f.wants_refactorization());
    }

    #[test]
    fn fill_of_updates_in_place_is_bought_back_by_a_refactorization() {
        // A chain of 16 springs: a tridiagonal factor without fill, 2n − 1 = 31 entries and
        // W_f = Σ c_j² = 4(n − 1) + 1 = 61 flops. A rank-one update coupling unknowns 2 and 13
        // brings ΔE entries of fill; each solve then spends 4 ΔE extra flops, so the rule asks for
        // a refactorization after exactly ⌈W_f / (4 ΔE)⌉ solves, not one before. A refactorization
        // takes the fill into its new analysis and resets the account.
        let n = 16;
        let k: Vec<f64> = (0..n).map(|e| 2.0 + 0.1 * e as f64).collect();
        let mut t = chain(n, &k);
        let mut f = LowRankCholesky::with_updates(n, FILL_REFACTOR_FACTOR).unwrap();
        f.factorize(&t).unwrap();
        assert_eq!(f.entries, (2 * n - 1, 2 * n - 1));
        f.add_terms(vec![vec![(2, 0.7), (13, -0.7)]], 1.0).unwrap();
        let fill = f.entries.1 - f.entries.0;
        assert!(fill > 0, "the coupling brought no fill");
        let due = (61.0 / (4.0 * fill as f64)).ceil() as usize;
        let mut x = vec![1.0; n];
        for s in 1..=due {
            assert!(!f.wants_refactorization(), "due after {s} − 1 solves, expected {due}");
            f.solve(&mut x).unwrap();
        }
        assert!(f.wants_refactorization());
        for (r, c, v) in [(2, 2, 0.49), (13, 13, 0.49), (2, 13, -0.49)] {
            t.push(Triplet::new(r, c, v));
        }
        f.factorize(&t).unwrap();
        assert!(!f.wants_refactorization());
        assert_eq!(f.entries.0, f.entries.1);
        // Never, with an infinite factor.
        let mut g = LowRankCholesky::with_updates(n, f64::INFINITY).unwrap();
        g.factorize(&chain(n, &k)).unwrap();
        g.add_terms(vec![vec![(2, 0.7), (13, -0.7)]], 1.0).unwrap();
        for _ in 0..100 {
            g.solve(&mut x).unwrap();
        }
        assert!(!g.wants_refactorization());
    }

    #[test]
    fn indefinite_matrix_is_an_error() {
        let mut f = LowRankCholesky::new(2);
        let t = vec![Triplet::new(0, 0, 1.0), Triplet::new(1, 1, -1.0)];
        assert!(f.factorize(&t).is_err());
        let mut x = vec![1.0, 1.0];
        assert!(f.solve(&mut x).is_err());
        assert!(LowRankCholesky::new(2).solve(&mut x).is_err());
    }
}
