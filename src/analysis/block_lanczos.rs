//! The lowest eigenpairs of `K φ = λ M φ` (K symmetric positive definite, M symmetric positive
//! semi-definite) by block shift-and-invert Lanczos with full reorthogonalization and thick
//! restart: the method of the structural codes' modal solvers (Grimes, Lewis & Simon, "A shifted
//! block Lanczos algorithm for solving sparse symmetric generalized eigenproblems", SIAM J.
//! Matrix Anal. Appl. 15 (1994) 228–272).
//!
//! # Why a block method, and why blocks of 2
//! Each step solves with the factor of K for a block of `b` vectors at once. A sparse
//! triangular solve reads the whole factor from memory for one vector; for a block it reads it
//! once for all. MUMPS on the 51k-DOF shell model of `scripts/bench/peer.sh` (9.0M factor
//! entries, 2-core AMD EPYC, OpenBLAS 0.3.21): 21.3 ms for one right-hand side, 23.4 ms for 2,
//! 29.3 ms for 4, 37.8 ms for 8. Larger blocks need more vectors in all to converge the same
//! Ritz pairs (a numpy prototype at the tolerance below: 18 single vectors, 13 blocks of 2, 10
//! of 4, 8 of 8), and every block is orthogonalized against the whole basis, whose size grows
//! with `b`. Measured side by side on that model (6 modes, eigensolve including the
//! factorization, 1 rank): SLEPc 3.18's Krylov–Schur, one vector at a time, 22 solves and
//! 0.83–0.89 s; blocks of 2: 14 solves, 0.75–0.79 s; of 3: 0.76–0.80 s; of 4: 0.79–0.82 s; of 8:
//! 0.90 s (the orthogonalization and first touch of a 72-column basis cost more than the solves
//! save). On 2 ranks, blocks of 2: 0.60–0.61 s against SLEPc's 0.62–0.64 s.
//!
//! # The iteration
//! `S = K⁻¹ M` is self-adjoint in the M-inner product `⟨x, y⟩ = xᵀ M y`, with eigenvalues
//! `θ = 1/λ`: the lowest λ are its largest θ. The basis `V` is M-orthonormal (`Vᵀ M V = I`); its
//! images `SV = S V` and `MV = M V` are kept beside it. From a frontier block `F`:
//!
//! ```text
//!   1. SF = K⁻¹ (M F)                        one solve for the block;  V ← [V F], SV ← [SV SF]
//!   2. T = Vᵀ M S V = MVᵀ SV                 its new column block MVᵀ SF (T is symmetric)
//!   3. F' ← SF, M-orthogonalized against V (classical Gram–Schmidt, the first pass with the
//!      column block of step 2) and M-orthonormalized by SVQB (Stathopoulos & Wu, SIAM J. Sci.
//!      Comput. 23 (2002)), twice: W⊥ = SF − V (MVᵀ SF) = F' R. Directions whose Gram
//!      eigenvalue is below DROP of the block's own scale are dropped (an invariant subspace
//!      was found); an emptied block is refilled with fresh start vectors.
//!   4. T s_i = θ_i s_i                       Rayleigh–Ritz; the nev largest θ_i
//!   5. S V = V T + W⊥ E_lastᵀ, so the residual S y_i − θ_i y_i of y_i = V s_i is F' R s_i,last
//!      and its M-norm ‖R s_i,last‖₂ (s_i,last: the rows of the last block); converged when
//!      ‖R s_i,last‖ ≤ tol θ_i for the nev pairs
//!   6. thick restart when the basis would pass `max_basis`: V ← V S_k, SV ← SV S_k, MV ← MV S_k,
//!      T ← S_kᵀ T S_k for the k = nev + b largest Ritz pairs. Every residual lies in the span of
//!      the frontier F', which is M-orthogonal to the old V and so to the new one.
//! ```
//! The eigenvectors are `φ_i = SV s_i / θ_i`: one more application of S, free since SV is kept.
//! It also removes any component along M's null space (fixed or massless DOFs), so the start
//! vectors need no purification. Each φ_i is returned with `φᵀ M φ = 1`, and its residual in
//! the original problem, `‖K φ − λ M φ‖₂ / ‖K φ‖₂`, is computed once (one product of K with the
//! block of modes) and reported.
//!
//! # Parallel
//! Rows are distributed like K's. Every small matrix (T, the Gram matrices, the Ritz
//! coefficients) is a sum of local products over the ranks (one all-reduce) and then computed
//! identically on every rank.

use faer::linalg::matmul::matmul;
use faer::{Accum, MatMut, MatRef, Par};
use mpi::collective::SystemOperation;
use mpi::traits::CommunicatorCollectives;
use nalgebra::DMatrix;

use crate::error::{AnalysisError, Error};
use crate::parallel::Context;
use crate::petsc::{DenseBlock, Ksp, Matrix, SolverError, Vector};

/// Vectors per block: 8 right-hand sides cost 1.8 times one (module docs).
pub const BLOCK: usize = 2;

/// Relative residual `‖S φ − θ φ‖_M / θ` at which a Ritz pair is accepted. The eigenvalue's
/// relative error is of the order of its square (Parlett, *The Symmetric Eigenvalue Problem*,
/// §11.7); the mode shape's is the residual over the relative gap to the next eigenvalue.
pub const TOLERANCE: f64 = 1e-8;

/// Gram eigenvalues below this fraction of the block's own scale are directions already in
/// the basis (1e-12 in norm, squared).
const DROP: f64 = 1e-24;

/// Block solves allowed before the iteration is declared not converged.
const MAX_SOLVES: usize = 200;

/// What one solve of the eigenproblem cost, and how well it solved it.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct LanczosStats {
    /// Block solves with the factor of K.
    pub solves: usize,
    /// Right-hand sides in those solves.
    pub columns: usize,
    /// Thick restarts.
    pub restarts: usize,
    /// The largest `‖K φ − λ M φ‖₂ / ‖K φ‖₂` over the modes returned.
    pub residual: f64,
}

/// The mass matrix as an operator on blocks of local rows.
enum Mass<'a> {
    /// A diagonal M (lumped): its owned diagonal.
    Diagonal(Vec<f64>),
    /// Any other M, through PETSc's sparse × dense product.
    Sparse(&'a Matrix),
}

impl Mass<'_> {
    /// `out ← M X` for `cols` columns of `n` local rows. Collective.
    fn apply(&self, ctx: &Context, x: &[f64], n: usize, cols: usize, out: &mut Vec<f64>) -> Result<(), Error> {
        out.clear();
        match self {
            Mass::Diagonal(d) => {
                for c in 0..cols {
                    out.extend(x[c * n..(c + 1) * n].iter().zip(d).map(|(v, m)| v * m));
                }
            }
            Mass::Sparse(m) => {
                let mut b = DenseBlock::new(&ctx.comm, n, cols)?;
                b.set_local_values(&x[..n * cols])?;
                out.extend_from_slice(&m.times_block(&b)?.local_values()?);
            }
        }
        Ok(())
    }

    /// Whether a DOF has no mass (diagonal M only; for a sparse M every DOF counts as massive).
    fn massless(&self, i: usize) -> bool {
        matches!(self, Mass::Diagonal(d) if d[i] == 0.0)
    }
}

/// `aᵀ b` summed over the ranks: `a` is `n × ca`, `b` is `n × cb`, both column-major local rows;
/// the result is `ca × cb`. Collective.
fn inner(ctx: &Context, a: &[f64], b: &[f64], n: usize, ca: usize, cb: usize) -> DMatrix<f64> {
    let mut local = vec![0.0; ca * cb];
    if n > 0 && ca > 0 && cb > 0 {
        matmul(
            MatMut::from_column_major_slice_mut(&mut local, ca, cb),
            Accum::Replace,
            MatRef::from_column_major_slice(a, n, ca).transpose(),
            MatRef::from_column_major_slice(b, n, cb),
            1.0,
            Par::Seq,
        );
    }
    let mut global = vec![0.0; ca * cb];
    ctx.comm.all_reduce_into(&local[..], &mut global[..], SystemOperation::sum());
    DMatrix::from_vec(ca, cb, global)
}

/// `y ← beta y + v c`: `v` is `n × cv`, `c` is `cv × cy`, `y` is `n × cy`. Local.
fn combine(y: &mut [f64], beta: f64, v: &[f64], c: &DMatrix<f64>, n: usize) {
    let (cv, cy) = c.shape();
    if n == 0 || cy == 0 {
        return;
    }
    if cv == 0 {
        y.iter_mut().for_each(|x| *x *= beta);
        return;
    }
    let accum = if beta == 0.0 {
        Accum::Replace
    } else {
        if beta != 1.0 {
            y.iter_mut().for_each(|x| *x *= beta);
        }
        Accum::Add
    };
    matmul(
        MatMut::from_column_major_slice_mut(y, n, cy),
        accum,
        MatRef::from_column_major_slice(v, n, cv),
        MatRef::from_column_major_slice(c.as_slice(), cv, cy),
        1.0,
        Par::Seq,
    );
}

/// `out ← v c` (`out` resized to `n × c.ncols()`). Local.
fn times_into(out: &mut Vec<f64>, v: &[f64], c: &DMatrix<f64>, n: usize) {
    out.clear();
    out.resize(n * c.ncols(), 0.0);
    combine(out, 0.0, v, c, n);
}

/// `v c` as a new block. Local.
fn times(v: &[f64], c: &DMatrix<f64>, n: usize) -> Vec<f64> {
    let mut y = Vec::new();
    times_into(&mut y, v, c, n);
    y
}

/// The eigenvalues of a symmetric matrix in descending order, with their eigenvectors.
fn descending_eigen(a: &DMatrix<f64>) -> (Vec<f64>, DMatrix<f64>) {
    let sym = (a + a.transpose()) * 0.5;
    let eig = sym.symmetric_eigen();
    let mut order: Vec<usize> = (0..eig.eigenvalues.len()).collect();
    order.sort_by(|&i, &j| eig.eigenvalues[j].total_cmp(&eig.eigenvalues[i]));
    let values = order.iter().map(|&i| eig.eigenvalues[i]).collect();
    let vectors = DMatrix::from_fn(a.nrows(), order.len(), |r, c| eig.eigenvectors[(r, order[c])]);
    (values, vectors)
}

/// The Krylov basis and its images (module docs), `n` local rows.
struct Basis {
    n: usize,
    /// Columns in the basis.
    m: usize,
    v: Vec<f64>,
    mv: Vec<f64>,
    sv: Vec<f64>,
    /// `T = Vᵀ M S V`, `m × m`.
    t: DMatrix<f64>,
}

/// A frontier block: M-orthonormal columns, M-orthogonal to the basis, with their M images.
#[derive(Default)]
struct Frontier {
    f: Vec<f64>,
    mf: Vec<f64>,
    cols: usize,
}

/// Reused work space of `n × block` arrays.
#[derive(Default)]
struct Work {
    w: Vec<f64>,
    mw: Vec<f64>,
    tmp: Vec<f64>,
}

impl Basis {
    /// The block `w` (`cols` columns) M-orthogonalized against the basis and M-orthonormalized
    /// into `next` (module docs, step 5). Returns `R = Fᵀ M W⊥`, with `W⊥` the block after the
    /// first orthogonalization: `W⊥ = F R`, so that a Ritz pair's residual is `F R s_last`.
    /// Collective.
    #[allow(clippy::too_many_arguments)] // the block, its first coefficients, the output, the work space
    fn orthonormalize(
        &self,
        ctx: &Context,
        mass: &Mass,
        w: &[f64],
        cols: usize,
        first: Option<DMatrix<f64>>,
        next: &mut Frontier,
        work: &mut Work,
    ) -> Result<DMatrix<f64>, Error> {
        let n = self.n;
        let Work { w: wb, mw, tmp } = work;
        wb.clear();
        wb.extend_from_slice(&w[..n * cols]);
        mass.apply(ctx, wb, n, cols, mw)?;
        let scale = inner(ctx, wb, mw, n, cols, cols).diagonal().max();
        next.cols = 0;
        if !(scale > 0.0) {
            return Ok(DMatrix::zeros(0, cols));
        }
        let c = match first {
            Some(c) => c,
            None => inner(ctx, &self.mv, wb, n, self.m, cols),
        };
        combine(wb, 1.0, &self.v, &(-c), n);
        // W⊥, kept for R.
        tmp.clear();
        tmp.extend_from_slice(wb);
        let mut cols_now = cols;
        for pass in 0..2 {
            if pass == 1 {
                let c = inner(ctx, &self.mv, wb, n, self.m, cols_now);
                combine(wb, 1.0, &self.v, &(-c), n);
            }
            mass.apply(ctx, wb, n, cols_now, mw)?;
            let g = inner(ctx, wb, mw, n, cols_now, cols_now);
            let (values, vectors) = descending_eigen(&g);
            let floor = if pass == 0 { DROP * scale } else { DROP };
            let kept = values.iter().take_while(|&&l| l > floor).count();
            let q = DMatrix::from_fn(cols_now, kept, |r, c| vectors[(r, c)] / values[c].sqrt());
            times_into(&mut next.f, wb, &q, n);
            times_into(&mut next.mf, mw, &q, n);
            std::mem::swap(wb, &mut next.f);
            cols_now = kept;
            if kept == 0 {
                break;
            }
        }
        std::mem::swap(wb, &mut next.f);
        next.cols = cols_now;
        Ok(inner(ctx, &next.mf, tmp, n, cols_now, cols))
    }

    /// Appends the frontier with its images `sf = S f`; extends T by its column block.
    /// Collective.
    fn push(&mut self, ctx: &Context, front: &Frontier, sf: &[f64]) -> DMatrix<f64> {
        let (n, cols) = (self.n, front.cols);
        self.v.extend_from_slice(&front.f);
        self.mv.extend_from_slice(&front.mf);
        self.sv.extend_from_slice(sf);
        let m = self.m + cols;
        let col = inner(ctx, &self.mv, sf, n, m, cols);
        let mut t = std::mem::replace(&mut self.t, DMatrix::zeros(0, 0)).resize(m, m, 0.0);
        for c in 0..cols {
            for r in 0..m {
                t[(r, self.m + c)] = col[(r, c)];
                t[(self.m + c, r)] = col[(r, c)];
            }
        }
        self.t = t;
        self.m = m;
        col
    }

    /// Keeps the span of the Ritz vectors `s` (columns, `m × k`) (module docs, step 6).
    fn restart(&mut self, s: &DMatrix<f64>, work: &mut Work) {
        let n = self.n;
        for x in [&mut self.v, &mut self.mv, &mut self.sv] {
            times_into(&mut work.tmp, x, s, n);
            x.clear();
            x.extend_from_slice(&work.tmp);
        }
        self.t = s.transpose() * &self.t * s;
        self.m = s.ncols();
    }
}

/// Deterministic start vectors: column `c`, global row `g`: `frac((g + 1) α_c) − ½` with
/// `α_c = frac(√p_c)` for the c-th prime (Weyl sequences: distinct columns, the same on every
/// rank count), zero on massless DOFs.
fn start_block(mass: &Mass, n: usize, first_row: usize, cols: usize, seed: usize) -> Vec<f64> {
    const PRIMES: [f64; 16] = [2., 3., 5., 7., 11., 13., 17., 19., 23., 29., 31., 37., 41., 43., 47., 53.];
    let mut x = vec![0.0; n * cols];
    for c in 0..cols {
        let p = PRIMES[(c + seed) % PRIMES.len()] + (((c + seed) / PRIMES.len()) as f64) * 0.5;
        let alpha = p.sqrt().fract();
        for i in 0..n {
            if !mass.massless(i) {
                x[c * n + i] = (((first_row + i + 1) as f64) * alpha).fract() - 0.5;
            }
        }
    }
    x
}

/// Collective. The `nev` lowest eigenpairs `(λ, φ)` of `K φ = λ M φ`, ascending, `φᵀ M φ = 1`
/// (module docs). `diagonal_mass`: `M` is diagonal (then applied as a vector). The factor of K is
/// MUMPS's Cholesky under the options prefix `modal_` (`-modal_pc_factor_mat_solver_type`, ...).
pub fn lowest_eigenpairs(
    ctx: &Context,
    k: &Matrix,
    m: &Matrix,
    nev: usize,
    diagonal_mass: bool,
) -> Result<(Vec<(f64, Vector)>, LanczosStats), Error> {
    let b = BLOCK.min(k.size_global().max(1));
    lanczos(ctx, k, m, nev, diagonal_mass, b, (2 * nev + 4 * b).max(12 * b).max(48))
}

/// The shift-invert solver: K factored once by MUMPS Cholesky (options prefix `modal_`).
fn cholesky_solver(ctx: &Context, k: &Matrix) -> Result<Ksp, Error> {
    let mut ksp = Ksp::new(&ctx.comm, "modal_")?;
    ksp.set_operators(k)?;
    ksp.set_type("preonly")?;
    ksp.set_pc_type("cholesky")?;
    ksp.set_factor_solver("mumps")?;
    ksp.set_from_options()?;
    Ok(ksp)
}

/// [`lowest_eigenpairs`] with blocks of `b` vectors and at most `max_basis` basis vectors.
fn lanczos(
    ctx: &Context,
    k: &Matrix,
    m: &Matrix,
    nev: usize,
    diagonal_mass: bool,
    b: usize,
    max_basis: usize,
) -> Result<(Vec<(f64, Vector)>, LanczosStats), Error> {
    let (lo, hi) = k.ownership_range()?;
    let n = hi - lo;
    let n_global = k.size_global();
    let mass = if diagonal_mass { Mass::Diagonal(m.get_diagonal()?.owned_values()?) } else { Mass::Sparse(m) };
    let mut ksp = cholesky_solver(ctx, k)?;

    let cap = n * (max_basis + b);
    let mut basis = Basis {
        n,
        m: 0,
        v: Vec::with_capacity(cap),
        mv: Vec::with_capacity(cap),
        sv: Vec::with_capacity(cap),
        t: DMatrix::zeros(0, 0),
    };
    let mut stats = LanczosStats { solves: 0, columns: 0, restarts: 0, residual: 0.0 };
    let mut work = Work::default();
    let (mut front, mut next) = (Frontier::default(), Frontier::default());
    let mut seed = 0;
    basis.orthonormalize(ctx, &mass, &start_block(&mass, n, lo, b, seed), b, None, &mut front, &mut work)?;
    let mut blocks: Option<(DenseBlock, DenseBlock)> = None;
    let mut sf = Vec::with_capacity(n * b);
    loop {
        if front.cols == 0 {
            // The basis spans an invariant subspace: refill the frontier.
            seed += b;
            if basis.m < n_global {
                basis.orthonormalize(
                    ctx,
                    &mass,
                    &start_block(&mass, n, lo, b, seed),
                    b,
                    None,
                    &mut front,
                    &mut work,
                )?;
            }
            if front.cols == 0 {
                let (theta, s) = descending_eigen(&basis.t);
                return finish(ctx, k, &mass, &basis, &theta, &s, nev, lo, stats);
            }
        }
        if stats.solves == MAX_SOLVES {
            return Err(
                AnalysisError::LanczosNoConvergence { solves: MAX_SOLVES, columns: stats.columns, modes: nev }.into()
            );
        }
        let cols = front.cols;
        if blocks.as_ref().is_none_or(|(r, _)| r.cols() != cols) {
            blocks = Some((DenseBlock::new(&ctx.comm, n, cols)?, DenseBlock::new(&ctx.comm, n, cols)?));
        }
        let (rhs, x) = blocks.as_mut().expect("created above");
        rhs.set_local_values(&front.mf)?;
        ksp.mat_solve(rhs, x).map_err(|e| match e {
            SolverError::Diverged { .. } => Error::SingularStiffness(e),
            other => Error::Solver(other),
        })?;
        x.local_values_into(&mut sf)?;
        stats.solves += 1;
        stats.columns += cols;
        let c = basis.push(ctx, &front, &sf);
        let r = basis.orthonormalize(ctx, &mass, &sf, cols, Some(c), &mut next, &mut work)?;

        // Rayleigh–Ritz; the residual of Ritz pair i is F R s_i,last (its M-norm ‖R s_i,last‖).
        let (theta, s) = descending_eigen(&basis.t);
        let k_ritz = nev.min(basis.m);
        let last = basis.m - cols;
        let converged = k_ritz == nev
            && (0..k_ritz).all(|i| {
                let s_last = s.view((last, i), (cols, 1));
                (&r * s_last).norm() <= TOLERANCE * theta[i].abs()
            });
        if converged || basis.m >= n_global {
            return finish(ctx, k, &mass, &basis, &theta, &s, nev, lo, stats);
        }
        std::mem::swap(&mut front, &mut next);
        if basis.m + front.cols.max(b) > max_basis {
            let keep = (nev + b).min(basis.m);
            basis.restart(&s.columns(0, keep).into_owned(), &mut work);
            stats.restarts += 1;
        }
    }
}

/// The eigenpairs from the Ritz pairs `(θ_i, s_i)`: `λ = 1/θ`, `φ = SV s / θ` scaled to
/// `φᵀ M φ = 1`, and their residual in `K φ = λ M φ` (module docs). Collective.
#[allow(clippy::too_many_arguments)]
fn finish(
    ctx: &Context,
    k_matrix: &Matrix,
    mass: &Mass,
    basis: &Basis,
    theta: &[f64],
    s: &DMatrix<f64>,
    nev: usize,
    first_row: usize,
    mut stats: LanczosStats,
) -> Result<(Vec<(f64, Vector)>, LanczosStats), Error> {
    let n = basis.n;
    let k = nev.min(basis.m);
    if k < nev || theta.iter().take(k).any(|&t| !(t > 0.0)) {
        return Err(AnalysisError::TooFewModes { exist: k, asked: nev, with_mass: basis.m }.into());
    }
    let mut phi = times(&basis.sv, &DMatrix::from_fn(basis.m, k, |r, c| s[(r, c)] / theta[c]), n);
    let mut mphi = Vec::new();
    mass.apply(ctx, &phi, n, k, &mut mphi)?;
    let norms = inner(ctx, &phi, &mphi, n, k, k).diagonal();
    for c in 0..k {
        let inv = 1.0 / norms[c].sqrt();
        phi[c * n..(c + 1) * n].iter_mut().chain(mphi[c * n..(c + 1) * n].iter_mut()).for_each(|v| *v *= inv);
    }
    // ‖K φ − λ M φ‖ / ‖K φ‖ per mode.
    let mut block = DenseBlock::new(&ctx.comm, n, k)?;
    block.set_local_values(&phi)?;
    let kphi = k_matrix.times_block(&block)?.local_values()?;
    let mut sums = vec![0.0_f64; 2 * k];
    for c in 0..k {
        let lambda = 1.0 / theta[c];
        for (kp, mp) in kphi[c * n..(c + 1) * n].iter().zip(&mphi[c * n..(c + 1) * n]) {
            sums[2 * c] += (kp - lambda * mp).powi(2);
            sums[2 * c + 1] += kp * kp;
        }
    }
    let mut total = vec![0.0_f64; 2 * k];
    ctx.comm.all_reduce_into(&sums[..], &mut total[..], SystemOperation::sum());
    stats.residual = (0..k).map(|c| (total[2 * c] / total[2 * c + 1]).sqrt()).fold(0.0, f64::max);
    let idx: Vec<i32> = (0..n).map(|i| (first_row + i) as i32).collect();
    let mut out = Vec::with_capacity(k);
    for c in 0..k {
        let mut v = Vector::new_mpi(&ctx.comm, n, None)?;
        v.set_values(&idx, &phi[c * n..(c + 1) * n])?;
        v.assemble()?;
        out.push((1.0 / theta[c], v));
    }
    Ok((out, stats))
}

#[cfg(test)]
#[path = "block_lanczos_tests.rs"]
mod tests;
