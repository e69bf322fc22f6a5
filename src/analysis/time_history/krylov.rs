//! Krylov subspace acceleration of modified Newton (Carlson & Miller, "Design and application of
//! a 1D GWMFE code", SIAM J. Sci. Comput. 19(3), 1998; the `KrylovNewton` algorithm of OpenSees).
//!
//! Modified Newton iterates `y_{k+1} = y_k + f_k` with the preconditioned residual
//! `f_k = J⁻¹ R(y_k)` and one factored `J` (the tangent of the step's start). Its convergence is
//! linear, slow when the tangent has changed much within the step (a softening layer or fiber).
//! The accelerator keeps the previous corrections `v_j` and the changes they caused in the
//! preconditioned residual, `A v_j = f_j − f_{j+1}` (a secant estimate of `J⁻¹ R'(y) v_j`), and
//! corrects the new residual by the part of it that the subspace explains:
//!
//! ```text
//!   c = argmin ‖f_k − Σ_j c_j A v_j‖                (least squares, j < k)
//!   v_k = f_k + Σ_j c_j (v_j − A v_j)
//! ```
//!
//! that is: the step `Σ c_j v_j` inside the subspace, which by the secant model removes
//! `Σ c_j A v_j` of the residual, plus the plain modified-Newton step on what remains. With an
//! empty subspace `v_k = f_k` (modified Newton). On a linear problem with `J` exact, `A v_j = v_j`
//! and `v_k = f_k`; with `J` not exact it is GMRES on the preconditioned system.
//!
//! The least squares is solved by its normal equations `G c = b`, `G_ij = A v_i · A v_j`,
//! `b_i = A v_i · f_k` (one collective reduction for all the dot products, so every rank finds
//! the same `c`), Jacobi-scaled and factored by Cholesky. When `G` is numerically singular (a
//! correction that no longer changes the residual) the subspace is cleared and the step is the
//! plain one. The subspace holds at most `max_dim` vectors: when it is full, the caller refreshes
//! the tangent (and then [`KrylovAccelerator::clear`]s), as OpenSees does.
use super::system::DynamicSystem;
use nalgebra::{DMatrix, DVector};

/// The subspace of previous corrections and of the residual changes they caused.
#[derive(Debug, Default)]
pub struct KrylovAccelerator {
    max_dim: usize,
    dim: usize,
    /// Corrections `v_j` applied.
    v: Vec<Vec<f64>>,
    /// `A v_j = f_j − f_{j+1}` for j < dim − 1; the last holds `f_{dim−1}` until the next call.
    av: Vec<Vec<f64>>,
}

/// Smallest pivot of the Jacobi-scaled normal equations (1 on the diagonal) accepted as
/// independent directions: below it the subspace is cleared.
const MIN_PIVOT: f64 = 1e-10;

impl KrylovAccelerator {
    /// An empty subspace of at most `max_dim` (≥ 1) directions.
    pub fn new(max_dim: usize) -> KrylovAccelerator {
        KrylovAccelerator { max_dim: max_dim.max(1), ..Default::default() }
    }

    /// Forgets the subspace (after the Jacobian changed).
    pub fn clear(&mut self) {
        self.dim = 0;
    }

    /// Whether the subspace is full: the caller refreshes the tangent and clears it.
    pub fn is_full(&self) -> bool {
        self.dim > self.max_dim
    }

    /// Scales the last correction recorded by `eta`: the step taken along it was `eta` times
    /// it (a line search), and the next residual change is that step's.
    pub fn scale_last(&mut self, eta: f64) {
        if let Some(v) = self.dim.checked_sub(1).and_then(|k| self.v.get_mut(k)) {
            v.iter_mut().for_each(|x| *x *= eta);
        }
    }

    /// Turns the preconditioned residual `f = J⁻¹ R(y_k)` (in place) into the correction `v_k`
    /// and records it. Collective (one reduction when the subspace is not empty).
    pub fn correct<S: DynamicSystem + ?Sized>(&mut self, sys: &S, f: &mut [f64]) {
        let n = f.len();
        let k = self.dim;
        while self.v.len() <= k {
            self.v.push(Vec::new());
            self.av.push(Vec::new());
        }
        let c = if k > 0 {
            // A v_{k−1} = f_{k−1} − f_k.
            for (a, fi) in self.av[k - 1].iter_mut().zip(f.iter()) {
                *a -= fi;
            }
            self.coefficients(sys, f)
        } else {
            Some(Vec::new())
        };
        // Dependent directions: the subspace starts again from this residual.
        let (k, c) = match c {
            Some(c) => (k, c),
            None => (0, Vec::new()),
        };
        // f_k is kept (raw) for the next A v_k.
        self.av[k].clear();
        self.av[k].extend_from_slice(f);
        for (j, cj) in c.iter().enumerate() {
            let (vj, avj) = (&self.v[j], &self.av[j]);
            for i in 0..n {
                f[i] += cj * (vj[i] - avj[i]);
            }
        }
        self.v[k].clear();
        self.v[k].extend_from_slice(f);
        self.dim = k + 1;
    }

    /// `c` of the least squares, or `None` when the scaled normal equations are singular.
    fn coefficients<S: DynamicSystem + ?Sized>(&self, sys: &S, f: &[f64]) -> Option<Vec<f64>> {
        let k = self.dim;
        let mut pairs: Vec<(&[f64], &[f64])> = Vec::with_capacity(k * (k + 1) / 2 + k);
        for i in 0..k {
            for j in 0..=i {
                pairs.push((&self.av[i], &self.av[j]));
            }
        }
        for i in 0..k {
            pairs.push((&self.av[i], f));
        }
        let d = sys.dots(&pairs);
        let mut g = DMatrix::zeros(k, k);
        let mut p = 0;
        for i in 0..k {
            for j in 0..=i {
                g[(i, j)] = d[p];
                g[(j, i)] = d[p];
                p += 1;
            }
        }
        let b = DVector::from_iterator(k, d[p..].iter().copied());
        let s: Vec<f64> = (0..k).map(|i| g[(i, i)].sqrt()).collect();
        if s.iter().any(|x| !(x.is_finite() && *x > 0.0)) {
            return None;
        }
        let gs = DMatrix::from_fn(k, k, |i, j| g[(i, j)] / (s[i] * s[j]));
        let bs = DVector::from_fn(k, |i, _| b[i] / s[i]);
        let chol = gs.cholesky()?;
        if (0..k).any(|i| chol.l_dirty()[(i, i)].powi(2) < MIN_PIVOT) {
            return None;
        }
        let y = chol.solve(&bs);
        let c: Vec<f64> = (0..k).map(|i| y[i] / s[i]).collect();
        c.iter().all(|x| x.is_finite()).then_some(c)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::analysis::time_history::system::DenseSystem;

    /// A 6 × 6 SPD matrix (a 1D Laplacian plus a random-ish coupling) and its diagonal.
    fn problem() -> (DMatrix<f64>, DVector<f64>) {
        let n = 6;
        let a = DMatrix::from_fn(n, n, |i, j| match (i as i64 - j as i64).abs() {
            0 => 4.0 + 0.3 * i as f64,
            1 => -1.0,
            2 => 0.4,
            _ => 0.0,
        });
        let b = DVector::from_fn(n, |i, _| 1.0 + (i as f64).sin());
        (a, b)
    }

    /// `x ← x + v` with `v` from `J⁻¹ (b − A x)`, `J` the diagonal of `A`; returns the
    /// iterations to ‖b − A x‖ ≤ 1e-12 ‖b‖ (or `limit`).
    fn iterate(accelerate: bool, limit: usize) -> (usize, DVector<f64>) {
        let (a, b) = problem();
        let n = b.len();
        let sys = DenseSystem::new(DMatrix::identity(n, n), DMatrix::zeros(n, n), a.clone(), vec![]);
        let mut acc = KrylovAccelerator::new(n + 1);
        let mut x = DVector::zeros(n);
        for it in 0..limit {
            let r = &b - &a * &x;
            if r.norm() <= 1e-12 * b.norm() {
                return (it, x);
            }
            let mut f: Vec<f64> = (0..n).map(|i| r[i] / a[(i, i)]).collect();
            if accelerate {
                acc.correct(&sys, &mut f);
            }
            x += DVector::from_vec(f);
        }
        (limit, x)
    }

    #[test]
    fn on_a_linear_system_it_terminates_like_gmres() {
        // Anderson-type acceleration with an untruncated subspace is equivalent to GMRES on a
        // linear problem (Walker & Ni, SIAM J. Numer. Anal. 49(4), 2011): the exact solution
        // after at most n + 1 corrections in exact arithmetic; n = 6, round-off allows 2 more.
        let (its, x) = iterate(true, 50);
        assert!(its <= 8, "{its} iterations");
        let (a, b) = problem();
        assert!((&a * &x - &b).norm() <= 1e-12 * b.norm());
        // The plain (Jacobi) iteration needs many more for the same tolerance.
        let (plain, _) = iterate(false, 500);
        assert!(plain > 3 * its, "plain {plain}, accelerated {its}");
    }

    #[test]
    fn steps_shortened_by_a_line_search_keep_their_secant_pairs() {
        // Every other correction taken at η = 0.4 (as a line search may) and recorded as taken
        // (`scale_last`): the pairs (η v_j, f_j − f_{j+1}) stay exact secants of the linear
        // problem, and each full step after a short one is the subspace's least-squares step
        // again, so the iteration ends within twice GMRES's n + 1 = 7 corrections, plus the 2
        // that round-off allows above. Recorded unscaled, the pairs are off by 1/η and the
        // iteration is more than twice as slow (measured: 14 against no convergence in 60).
        let (a, b) = problem();
        let n = b.len();
        let sys = DenseSystem::new(DMatrix::identity(n, n), DMatrix::zeros(n, n), a.clone(), vec![]);
        let run = |scaled: bool| {
            let mut acc = KrylovAccelerator::new(n + 1);
            let mut x = DVector::zeros(n);
            for it in 0..60 {
                let r = &b - &a * &x;
                if r.norm() <= 1e-12 * b.norm() {
                    return it;
                }
                let mut f: Vec<f64> = (0..n).map(|i| r[i] / a[(i, i)]).collect();
                acc.correct(&sys, &mut f);
                let eta = if it % 2 == 0 { 0.4 } else { 1.0 };
                x += eta * DVector::from_vec(f);
                if scaled {
                    acc.scale_last(eta);
                }
            }
            60
        };
        let scaled = run(true);
        assert!(scaled <= 2 * (n + 1) + 2, "{scaled} iterations with the steps recorded as taken");
        let unscaled = run(false);
        assert!(unscaled > 2 * scaled, "unscaled pairs: {unscaled} iterations against {scaled}");
    }

    #[test]
    fn dependent_directions_clear_the_subspace() {
        // The same residual twice: A v₀ = f₀ − f₁ = 0, so G is singular; the correction is the
        // plain step and the subspace restarts with one vector.
        let sys = DenseSystem::new(DMatrix::identity(2, 2), DMatrix::zeros(2, 2), DMatrix::identity(2, 2), vec![]);
        let mut acc = KrylovAccelerator::new(3);
        let mut f = vec![1.0, 2.0];
        acc.correct(&sys, &mut f);
        let mut g = vec![1.0, 2.0];
        acc.correct(&sys, &mut g);
        assert_eq!(g, vec![1.0, 2.0]);
        assert_eq!(acc.dim, 1);
        assert!(!acc.is_full());
    }
}
