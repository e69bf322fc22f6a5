//! Restarted GMRES with right preconditioning, for the nonsymmetric consistent tangent of the
//! contact–friction problem, in its flexible form (Saad, *Iterative Methods for Sparse Linear
//! Systems*, 2nd ed., Alg. 9.6): the preconditioned vectors `z_j = M⁻¹ v_j` are kept, so the
//! update needs no extra preconditioner solve.
//!
//! ```text
//!   solve A x = b:   Arnoldi on A M⁻¹ from r₀ = b − A x₀,
//!   V = [v₁ … v_k] orthonormal (modified Gram–Schmidt), z_j = M⁻¹ v_j, H̄ (k+1)×k Hessenberg,
//!   y = argmin ‖β e₁ − H̄ y‖ (Givens rotations), x = x₀ + Z y.
//! ```
//!
//! The residual norm `‖b − A x‖₂` is non-increasing over the iterations (the defining property of
//! GMRES), which is why it is used here rather than BiCGSTAB (the one nonsymmetric Krylov method
//! faer 0.24 ships): with the symmetric part of the tangent as preconditioner, `A M⁻¹` is the
//! identity plus a low-rank term (one rank-one term per sliding contact), and GMRES converges in
//! at most that many iterations plus one, monotonically.
//!
//! Inside Newton the solve need not be exact: [`Forcing`] chooses its relative tolerance per
//! step (Eisenstat–Walker: loose while Newton is far from the solution, tight as it converges,
//! never below what the Newton test needs).

/// The outcome of a GMRES solve.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct GmresInfo {
    /// Matrix–vector products done.
    pub iterations: usize,
    /// `‖b − A x‖₂ / ‖b‖₂` at the end (as tracked by the Givens recurrence).
    pub relative_residual: f64,
    /// Whether `relative_residual ≤ tol`.
    pub converged: bool,
}

fn dot(a: &[f64], b: &[f64]) -> f64 {
    a.iter().zip(b).map(|(x, y)| x * y).sum()
}

fn norm(a: &[f64]) -> f64 {
    dot(a, a).sqrt()
}

/// Solves `A x = b` from the initial guess in `x`, with `apply(v, out)`: `out = A v`, and
/// `precond(v)`: `v ← M⁻¹ v` in place. Restarts every `restart` iterations, stops at
/// `max_iterations` products or when `‖b − A x‖ ≤ tol ‖b‖`. Errors of `precond` are passed on.
pub fn gmres<E>(
    x: &mut [f64],
    b: &[f64],
    mut apply: impl FnMut(&[f64], &mut [f64]),
    precond: impl FnMut(&mut [f64]) -> Result<(), E>,
    tol: f64,
    restart: usize,
    max_iterations: usize,
) -> Result<GmresInfo, E> {
    gmres_core(x, b, |_, z, out| apply(z, out), precond, tol, restart, max_iterations)
}

/// [`gmres`] for `A = M + D` where the preconditioner is `M` itself (up to its own round-off)
/// and `D` is cheap: the Arnoldi products are `A M⁻¹ v = v + D (M⁻¹ v)`, so `A` is never applied
/// inside a cycle. `apply_difference(z, out)`: `out = D z`; `apply(x, out)`: `out = A x`, used
/// only for the residual of a restart (`x ≠ 0`).
///
/// With `M` the factorized symmetric operator and `D = K_T − M` the contacts' part of the
/// tangent that the factorization does not hold ([`super::tangent::TangentDifference`]), a
/// product costs `O(contacts)` instead of `O(beams)`. The solve is that of `M + D` only as far
/// as `M⁻¹` is exact (a Woodbury correction is, to round-off): Newton's step, not its residual.
#[allow(clippy::too_many_arguments)] // gmres's arguments plus the difference operator
pub fn gmres_split<E>(
    x: &mut [f64],
    b: &[f64],
    mut apply: impl FnMut(&[f64], &mut [f64]),
    mut apply_difference: impl FnMut(&[f64], &mut [f64]),
    precond: impl FnMut(&mut [f64]) -> Result<(), E>,
    tol: f64,
    restart: usize,
    max_iterations: usize,
) -> Result<GmresInfo, E> {
    let product = |v: Option<&[f64]>, z: &[f64], out: &mut [f64]| match v {
        Some(v) => {
            apply_difference(z, out);
            for (o, vi) in out.iter_mut().zip(v) {
                *o += vi;
            }
        }
        None => apply(z, out),
    };
    gmres_core(x, b, product, precond, tol, restart, max_iterations)
}

/// The iteration of [`gmres`]: `product(Some(v), z, out)` is `out = A z` for `z = M⁻¹ v` (an
/// Arnoldi step), `product(None, x, out)` a plain `out = A x`.
fn gmres_core<E>(
    x: &mut [f64],
    b: &[f64],
    mut product: impl FnMut(Option<&[f64]>, &[f64], &mut [f64]),
    mut precond: impl FnMut(&mut [f64]) -> Result<(), E>,
    tol: f64,
    restart: usize,
    max_iterations: usize,
) -> Result<GmresInfo, E> {
    let n = b.len();
    let b_norm = norm(b);
    if b_norm == 0.0 {
        x.iter_mut().for_each(|v| *v = 0.0);
        return Ok(GmresInfo { iterations: 0, relative_residual: 0.0, converged: true });
    }
    let restart = restart.max(1);
    let mut total = 0;
    let mut w = vec![0.0; n];
    loop {
        // r0 = b − A x (no product for a zero initial guess)
        let r: Vec<f64> = if x.iter().all(|v| *v == 0.0) {
            b.to_vec()
        } else {
            product(None, x, &mut w);
            total += 1;
            b.iter().zip(&w).map(|(bi, wi)| bi - wi).collect()
        };
        let beta = norm(&r);
        let mut rel = beta / b_norm;
        if rel <= tol || total >= max_iterations {
            return Ok(GmresInfo { iterations: total, relative_residual: rel, converged: rel <= tol });
        }
        let mut v: Vec<Vec<f64>> = vec![r.iter().map(|ri| ri / beta).collect()];
        let mut zs: Vec<Vec<f64>> = Vec::new();
        let mut h: Vec<Vec<f64>> = Vec::new(); // column j: H[0..=j+1, j]
        let (mut cs, mut sn) = (Vec::<f64>::new(), Vec::<f64>::new());
        let mut g = vec![beta];
        let mut k = 0;
        while k < restart && total < max_iterations {
            // w = A M⁻¹ v_k
            let mut z = v[k].clone();
            precond(&mut z)?;
            product(Some(&v[k]), &z, &mut w);
            zs.push(z);
            total += 1;
            let mut col = vec![0.0; k + 2];
            for (i, vi) in v.iter().enumerate() {
                let hij = dot(&w, vi);
                col[i] = hij;
                for (wl, vl) in w.iter_mut().zip(vi) {
                    *wl -= hij * vl;
                }
            }
            let hn = norm(&w);
            col[k + 1] = hn;
            // Apply the previous rotations, then a new one zeroing col[k+1].
            for i in 0..k {
                let t = cs[i] * col[i] + sn[i] * col[i + 1];
                col[i + 1] = -sn[i] * col[i] + cs[i] * col[i + 1];
                col[i] = t;
            }
            let d = col[k].hypot(col[k + 1]);
            let (c, s) = if d > 0.0 { (col[k] / d, col[k + 1] / d) } else { (1.0, 0.0) };
            col[k] = d;
            col[k + 1] = 0.0;
            cs.push(c);
            sn.push(s);
            g.push(-s * g[k]);
            g[k] *= c;
            h.push(col);
            k += 1;
            rel = g[k].abs() / b_norm;
            if rel <= tol || hn <= 1e-300 {
                break;
            }
            v.push(w.iter().map(|wi| wi / hn).collect());
        }
        // Back substitution H y = g (upper triangular k×k), x += Z y.
        let mut y = vec![0.0; k];
        for i in (0..k).rev() {
            let s: f64 = (i + 1..k).map(|j| h[j][i] * y[j]).sum();
            y[i] = if h[i][i] != 0.0 { (g[i] - s) / h[i][i] } else { 0.0 };
        }
        for (j, yj) in y.iter().enumerate() {
            for (xi, zj) in x.iter_mut().zip(&zs[j]) {
                *xi += yj * zj;
            }
        }
        if rel <= tol || total >= max_iterations {
            return Ok(GmresInfo { iterations: total, relative_residual: rel, converged: rel <= tol });
        }
    }
}

/// The relative tolerance `η_k` of the linear solve of each Newton step,
/// `‖r_k + K_T Δz‖₂ ≤ η_k ‖r_k‖₂` (inexact Newton).
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Forcing {
    /// The same `η` at every step.
    Fixed(f64),
    /// Eisenstat and Walker's choice 2 (SIAM J. Sci. Comput. 17(1), 1996, eq. 2.6 with the
    /// safeguard of §2.3), with a floor from the Newton goal:
    ///
    /// ```text
    ///   η_0 = η_max
    ///   η_k = γ (‖r_k‖ / ‖r_{k−1}‖)^α                       (how fast Newton converges now)
    ///   η_k ← max(η_k, γ η_{k−1}^α)    when γ η_{k−1}^α > 0.1   (no sudden drop)
    ///   η_k ← min(η_k, η_max)
    ///   η_k ← max(η_k, η_min, ½ g / ‖r_k‖)                   (no solve beyond the goal g)
    /// ```
    ///
    /// `g` is the 2-norm the linear residual need not go below: Newton stops once
    /// `‖r‖∞ ≤ g`, and `‖·‖∞ ≤ ‖·‖₂`.
    EisenstatWalker {
        /// `γ`.
        gamma: f64,
        /// `α`.
        alpha: f64,
        /// `η_max`: the first and loosest tolerance.
        eta_max: f64,
        /// `η_min`: the tightest tolerance.
        eta_min: f64,
    },
}

impl Default for Forcing {
    /// Eisenstat–Walker with `γ = 0.9`, `α = 2` (the paper's choice), `η_max = 0.1` (the first
    /// steps of an equilibrium after a break move many contacts: a looser first step costs more
    /// Newton iterations, each with a residual evaluation and a tangent, than it saves in GMRES),
    /// `η_min = 10⁻¹⁰`.
    fn default() -> Self {
        Forcing::EisenstatWalker { gamma: 0.9, alpha: 2.0, eta_max: 0.1, eta_min: 1e-10 }
    }
}

/// The forcing terms of one Newton solve (one equilibrium), step by step.
#[derive(Clone, Debug)]
pub struct ForcingSequence {
    forcing: Forcing,
    previous: Option<(f64, f64)>,
}

impl ForcingSequence {
    /// A new sequence (the next step is the first).
    pub fn new(forcing: Forcing) -> Self {
        ForcingSequence { forcing, previous: None }
    }

    /// `η_k` for a step from a residual of 2-norm `r_norm`, `goal` the 2-norm below which the
    /// linear residual is useless (see [`Forcing::EisenstatWalker`]).
    pub fn next(&mut self, r_norm: f64, goal: f64) -> f64 {
        let eta = match self.forcing {
            Forcing::Fixed(eta) => eta,
            Forcing::EisenstatWalker { gamma, alpha, eta_max, eta_min } => {
                let mut eta = match self.previous {
                    None => eta_max,
                    Some((r_prev, eta_prev)) => {
                        let mut e = if r_prev > 0.0 { gamma * (r_norm / r_prev).powf(alpha) } else { eta_max };
                        let keep = gamma * eta_prev.powf(alpha);
                        if keep > 0.1 {
                            e = e.max(keep);
                        }
                        e
                    }
                };
                eta = eta.min(eta_max);
                if r_norm > 0.0 {
                    eta = eta.max(0.5 * goal / r_norm);
                }
                eta.max(eta_min).min(eta_max.max(eta_min))
            }
        };
        self.previous = Some((r_norm, eta));
        eta
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn solves_a_nonsymmetric_system_with_and_without_preconditioner() {
        // A = tridiag(−1, 4, −2) + e₀ e₅ᵀ (nonsymmetric, diagonally dominant), n = 12, b = 1…12;
        // the solution is checked through the residual ‖b − A x‖ ≤ 1e-12 ‖b‖ computed directly.
        let n = 12;
        let apply = |v: &[f64], out: &mut [f64]| {
            for i in 0..n {
                let mut s = 4.0 * v[i];
                if i > 0 {
                    s -= v[i - 1];
                }
                if i + 1 < n {
                    s -= 2.0 * v[i + 1];
                }
                if i == 0 {
                    s += v[5];
                }
                out[i] = s;
            }
        };
        let b: Vec<f64> = (1..=n).map(|i| i as f64).collect();
        for (restart, jacobi) in [(50, false), (4, false), (50, true)] {
            let mut x = vec![0.0; n];
            let info = gmres::<()>(
                &mut x,
                &b,
                apply,
                |v| {
                    if jacobi {
                        v.iter_mut().for_each(|x| *x /= 4.0);
                    }
                    Ok(())
                },
                1e-13,
                restart,
                500,
            )
            .unwrap();
            let mut ax = vec![0.0; n];
            apply(&x, &mut ax);
            let r: f64 = b.iter().zip(&ax).map(|(a, c)| (a - c) * (a - c)).sum::<f64>().sqrt();
            assert!(info.converged && r <= 1e-12 * norm(&b), "restart {restart}: {info:?}, r = {r}");
            // Without restarts GMRES is exact after at most n products (+1 for the first residual).
            if restart == 50 {
                assert!(info.iterations <= n + 1, "{info:?}");
            }
        }
    }

    #[test]
    fn exact_preconditioner_converges_in_one_product() {
        // A = 3 I, M⁻¹ = A⁻¹: the first Krylov vector solves the system.
        let b = vec![1.0, -2.0, 0.5];
        let mut x = vec![0.0; 3];
        let info = gmres::<()>(
            &mut x,
            &b,
            |v, o| o.iter_mut().zip(v).for_each(|(o, v)| *o = 3.0 * v),
            |v| {
                v.iter_mut().for_each(|x| *x /= 3.0);
                Ok(())
            },
            1e-14,
            10,
            10,
        )
        .unwrap();
        assert!(info.converged && info.iterations == 1, "{info:?}");
        assert!(x.iter().zip(&b).all(|(x, b)| (3.0 * x - b).abs() < 1e-15));
    }

    #[test]
    fn split_form_solves_m_plus_d_with_products_of_d_only() {
        // M = diag(2 … 13) (its inverse exact), D = e₀ e₅ᵀ − 0.5 e₇ e₂ᵀ (rank 2, nonsymmetric):
        // GMRES on M + D with M⁻¹ as preconditioner converges within rank(D) + 1 = 3 products of D
        // and never applies M + D (no restart); the residual, computed directly, is below 1e-12.
        let n = 12;
        let m = |i: usize| 2.0 + i as f64;
        let d = |v: &[f64], out: &mut [f64]| {
            out.iter_mut().for_each(|o| *o = 0.0);
            out[0] += v[5];
            out[7] -= 0.5 * v[2];
        };
        let full = |v: &[f64], out: &mut [f64]| {
            d(v, out);
            for i in 0..n {
                out[i] += m(i) * v[i];
            }
        };
        let b: Vec<f64> = (1..=n).map(|i| (i as f64).cos()).collect();
        let mut x = vec![0.0; n];
        let mut full_products = 0;
        let info = gmres_split::<()>(
            &mut x,
            &b,
            |v, o| {
                full_products += 1;
                full(v, o)
            },
            d,
            |v| {
                v.iter_mut().enumerate().for_each(|(i, x)| *x /= m(i));
                Ok(())
            },
            1e-14,
            50,
            50,
        )
        .unwrap();
        let mut ax = vec![0.0; n];
        full(&x, &mut ax);
        let r = b.iter().zip(&ax).map(|(a, c)| (a - c) * (a - c)).sum::<f64>().sqrt();
        assert!(info.converged && info.iterations <= 3, "{info:?}");
        assert_eq!(full_products, 0);
        assert!(r <= 1e-12 * norm(&b), "r = {r}");
    }

    #[test]
    fn eisenstat_walker_follows_the_convergence_rate_within_its_bounds() {
        // γ = 0.9, α = 2, η_max = 0.1, η_min = 1e-10, goal 1e-12.
        // Step 0: η_max = 0.1. Step 1: ‖r‖ falls 1 → 0.1: 0.9 · 0.1² = 9e-3 (safeguard
        // 0.9 · 0.1² = 9e-3 ≤ 0.1 not applied). Step 2: 0.1 → 1e-4: 0.9 · 1e-6 = 9e-7.
        // Step 3: ‖r‖ = 1e-11, ratio 1e-7: 0.9e-14, below both ½ goal/‖r‖ = 0.05 → 0.05.
        let f = Forcing::EisenstatWalker { gamma: 0.9, alpha: 2.0, eta_max: 0.1, eta_min: 1e-10 };
        let mut s = ForcingSequence::new(f);
        let close = |a: f64, b: f64| (a - b).abs() <= 1e-12 * b;
        assert!(close(s.next(1.0, 1e-12), 0.1));
        assert!(close(s.next(0.1, 1e-12), 9e-3));
        assert!(close(s.next(1e-4, 1e-12), 9e-7));
        assert!(close(s.next(1e-11, 1e-12), 0.05));
        // Slow convergence (ratio 0.9) is capped at η_max; the fixed forcing never changes.
        let mut s = ForcingSequence::new(f);
        s.next(1.0, 0.0);
        assert!(close(s.next(0.9, 0.0), 0.1));
        // With a goal of 0 the floor is η_min.
        let mut s = ForcingSequence::new(f);
        s.next(1.0, 0.0);
        assert!(close(s.next(1e-9, 0.0), 1e-10));
        let mut s = ForcingSequence::new(Forcing::Fixed(1e-8));
        assert_eq!((s.next(1.0, 0.5), s.next(1e-6, 0.5)), (1e-8, 1e-8));
    }
}
