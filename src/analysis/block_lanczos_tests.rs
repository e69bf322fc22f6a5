//! Tests of [`super`]: closed forms of spring–mass chains (lumped and consistent mass,
//! repeated eigenvalues, thick restarts, a problem smaller than the basis) and SLEPc.
use super::*;
use crate::petsc::testing::with_petsc;
use mpi::topology::Communicator;

/// Chains of `n` unit masses between fixed ends, springs of stiffness 1, `copies` of them
/// side by side (uncoupled), then `fixed` decoupled DOFs as the assembly leaves supports
/// (K_ii = 1, M_ii = 0). Consistent mass: `M = (1/6) tridiag(1, 4, 1)` per chain; lumped:
/// `M = I`. Returns (K, M, DOF).
fn chains(ctx: &Context, n: usize, copies: usize, fixed: usize, consistent: bool) -> (Matrix, Matrix, usize) {
    let size = n * copies + fixed;
    let mut k = Matrix::new_aij(&ctx.comm, size, &vec![3; size], &vec![0; size]).unwrap();
    let mut m = Matrix::new_aij(&ctx.comm, size, &vec![3; size], &vec![0; size]).unwrap();
    for c in 0..copies {
        for i in 0..n {
            let r = (c * n + i) as i32;
            let (mi, mo) = if consistent { (4.0 / 6.0, 1.0 / 6.0) } else { (1.0, 0.0) };
            k.set_values(&[r], &[r], &[2.0]).unwrap();
            m.set_values(&[r], &[r], &[mi]).unwrap();
            if i + 1 < n {
                k.set_values(&[r], &[r + 1], &[-1.0]).unwrap();
                k.set_values(&[r + 1], &[r], &[-1.0]).unwrap();
                if consistent {
                    m.set_values(&[r], &[r + 1], &[mo]).unwrap();
                    m.set_values(&[r + 1], &[r], &[mo]).unwrap();
                }
            }
        }
    }
    for f in 0..fixed {
        let r = (n * copies + f) as i32;
        k.set_values(&[r], &[r], &[1.0]).unwrap();
    }
    k.assemble().unwrap();
    m.assemble().unwrap();
    k.set_option_symmetric(true).unwrap();
    m.set_option_symmetric(true).unwrap();
    (k, m, size)
}

/// The chain's eigenvalues in closed form: the sine vectors `sin(j i π / (n + 1))` diagonalize
/// both tridiagonal matrices, with `λ_j = (2 − 2 cos t_j) / m_j`, `t_j = j π / (n + 1)`,
/// `m_j = 1` (lumped) or `(4 + 2 cos t_j) / 6` (consistent).
fn chain_eigenvalue(n: usize, j: usize, consistent: bool) -> f64 {
    let t = j as f64 * std::f64::consts::PI / (n as f64 + 1.0);
    let mj = if consistent { (4.0 + 2.0 * t.cos()) / 6.0 } else { 1.0 };
    (2.0 - 2.0 * t.cos()) / mj
}

/// Each `(λ, φ)` of `pairs` against the closed form of mode `mode(i)` of a chain of `n`
/// masses, to 1e-12 relative.
fn assert_chain_eigenvalues(pairs: &[(f64, Vector)], n: usize, consistent: bool, mode: impl Fn(usize) -> usize) {
    for (i, (lambda, _)) in pairs.iter().enumerate() {
        let want = chain_eigenvalue(n, mode(i), consistent);
        assert!((lambda - want).abs() <= 1e-12 * want, "λ{} = {lambda}, closed form {want}", i + 1);
    }
}

/// The lowest eigenvalues of a chain of 300 masses, lumped (diagonal M) and consistent
/// (sparse M), equal the closed form to 1e-12 relative (the residual tolerance 1e-8 bounds
/// the eigenvalue's error by its square times the spread, Parlett §11.7); the modes are
/// M-normalized, zero on the fixed DOFs, and their residual in K φ = λ M φ is below 1e-7.
#[test]
fn chain_eigenvalues_match_the_closed_form() {
    with_petsc(|comm| {
        let ctx = Context::new(comm.duplicate(), true);
        for consistent in [false, true] {
            let (n, fixed) = (300, 4);
            let (k, m, size) = chains(&ctx, n, 1, fixed, consistent);
            let (pairs, stats) = lowest_eigenpairs(&ctx, &k, &m, 6, !consistent).unwrap();
            assert_eq!(pairs.len(), 6);
            assert!(stats.residual < 1e-7, "consistent {consistent}: residual {}", stats.residual);
            for (j, (lambda, phi)) in pairs.iter().enumerate() {
                let want = chain_eigenvalue(n, j + 1, consistent);
                assert!(
                    (lambda - want).abs() <= 1e-12 * want,
                    "consistent {consistent}: λ{} = {lambda}, closed form {want}",
                    j + 1
                );
                let v = phi.owned_values().unwrap();
                assert!(v[n..size].iter().all(|&x| x == 0.0), "a fixed DOF moves: {:?}", &v[n..size]);
                let (_, mut mphi) = m.create_vectors().unwrap();
                m.mult(phi, &mut mphi).unwrap();
                let modal_mass = phi.dot(&mphi).unwrap();
                assert!((modal_mass - 1.0).abs() < 1e-12, "φᵀMφ = {modal_mass}");
            }
        }
    });
}

/// Three identical uncoupled chains: every eigenvalue is triple. A block of 2 still finds
/// the multiplicity (the 6 lowest are λ₁ three times and λ₂ three times, to 1e-12), with
/// mutually M-orthogonal modes.
#[test]
fn repeated_eigenvalues_are_found_with_their_multiplicity() {
    with_petsc(|comm| {
        let ctx = Context::new(comm.duplicate(), true);
        let n = 120;
        let (k, m, _) = chains(&ctx, n, 3, 0, false);
        let (pairs, _) = lowest_eigenpairs(&ctx, &k, &m, 6, true).unwrap();
        assert_chain_eigenvalues(&pairs, n, false, |i| 1 + i / 3);
        for a in 0..6 {
            for b in 0..a {
                let (_, mut mb) = m.create_vectors().unwrap();
                m.mult(&pairs[b].1, &mut mb).unwrap();
                let d = pairs[a].1.dot(&mb).unwrap();
                assert!(d.abs() < 1e-10, "φ{}ᵀ M φ{} = {d}", a + 1, b + 1);
            }
        }
    });
}

/// The same 8 lowest modes of a chain with two supported ends and a consistent mass as
/// SLEPc's Krylov–Schur (shift-and-invert, MUMPS), the project's previous eigensolver:
/// eigenvalues to 1e-10, mode shapes to 1e-6 (up to sign).
#[test]
fn modes_agree_with_slepc() {
    with_petsc(|comm| {
        let ctx = Context::new(comm.duplicate(), true);
        let (k, m, _) = chains(&ctx, 400, 1, 2, true);
        let (mine, _) = lowest_eigenpairs(&ctx, &k, &m, 8, false).unwrap();
        let mut eps = crate::petsc::Eps::new(&ctx.comm, "").unwrap();
        eps.set_operators(&k, Some(&m)).unwrap();
        eps.set_shift_invert(0.0).unwrap();
        eps.set_st_factor("cholesky", "mumps").unwrap();
        eps.set_dimensions(8).unwrap();
        eps.set_tolerances(1e-12, 1000).unwrap();
        let theirs = eps.solve().unwrap();
        for (j, ((a, pa), (b, pb))) in mine.iter().zip(&theirs).enumerate() {
            assert!((a - b).abs() <= 1e-10 * b, "λ{}: {a} against SLEPc's {b}", j + 1);
            let (x, y) = (pa.owned_values().unwrap(), pb.owned_values().unwrap());
            let (nx, ny) = (x.iter().map(|v| v * v).sum::<f64>().sqrt(), y.iter().map(|v| v * v).sum::<f64>().sqrt());
            let cos = x.iter().zip(&y).map(|(p, q)| p * q).sum::<f64>() / (nx * ny);
            assert!(1.0 - cos.abs() < 1e-6, "mode {}: |cos| = {}", j + 1, cos.abs());
        }
    });
}

/// A basis capped at 16 vectors for 6 modes forces thick restarts; the eigenvalues still
/// match the closed form to 1e-12.
#[test]
fn thick_restarts_keep_the_converging_ritz_pairs() {
    with_petsc(|comm| {
        let ctx = Context::new(comm.duplicate(), true);
        let n = 300;
        let (k, m, _) = chains(&ctx, n, 1, 0, false);
        let (pairs, stats) = lanczos(&ctx, &k, &m, 6, true, 2, 16).unwrap();
        assert!(stats.restarts >= 2, "{stats:?}");
        assert_chain_eigenvalues(&pairs, n, false, |j| j + 1);
    });
}

/// A problem with fewer DOF than the basis would hold: all 5 eigenpairs of a 5-mass chain are
/// exact once the Krylov space is the whole space; asking for more than exist is an error
/// that says how many there are.
#[test]
fn a_small_problem_gives_all_its_modes_and_no_more() {
    with_petsc(|comm| {
        let ctx = Context::new(comm.duplicate(), true);
        let (k, m, _) = chains(&ctx, 5, 1, 1, false);
        let (pairs, _) = lowest_eigenpairs(&ctx, &k, &m, 5, true).unwrap();
        assert_chain_eigenvalues(&pairs, 5, false, |j| j + 1);
        let err = lowest_eigenpairs(&ctx, &k, &m, 6, true).unwrap_err().to_string();
        assert!(err.contains("only 5 of the 6 modes"), "{err}");
    });
}
