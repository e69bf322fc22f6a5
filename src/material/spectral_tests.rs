//! Tests of the spectral split: elastic limits, the equal-damage limit, the potential (closed
//! cycles do no work), continuity at crack closure, consistent tangents, and the history.

use nalgebra::{SVector, Vector1, Vector3, Vector6};

use super::*;
use crate::material::test_support::{check_random_paths, check_tangent, fd_tangent, params, rel_diff};
use crate::material::{
    plane_stress, three_d, uniaxial, DamageParams, PlaneStress, Split, StressState, ThreeD, Uniaxial,
};

fn spectral_params() -> DamageParams {
    DamageParams { split: Split::Spectral, ..params() }
}

/// The law of the reference parameters with the spectral split (0.1 m element, B_t = 600).
fn spectral_law() -> PointLaw {
    match spectral_params().for_element(0.1) {
        Ok(l) => l,
        Err(e) => panic!("reference parameters rejected: {e}"),
    }
}

fn trace_law() -> PointLaw {
    crate::material::test_support::law()
}

/// A committed state whose damages are `d_t` and `d_c` (κ by bisection on d(κ), to 1e-14).
fn state_with(law: &PointLaw, d_t: f64, d_c: f64) -> DamageState {
    let kappa = |side: Side, d: f64| {
        let (mut lo, mut hi) = (law.threshold(side), 1.0);
        if d <= 0.0 {
            return lo;
        }
        for _ in 0..200 {
            let mid = 0.5 * (lo + hi);
            if law.damage(side, mid).d < d {
                lo = mid;
            } else {
                hi = mid;
            }
        }
        hi
    };
    let (kt, kc) = (kappa(Side::Tension, d_t), kappa(Side::Compression, d_c));
    DamageState {
        kappa_t: kt,
        kappa_c: kc,
        d_t: law.damage(Side::Tension, kt).d,
        d_c: law.damage(Side::Compression, kc).d,
    }
}

#[test]
fn the_condensed_strains_of_an_undamaged_point_are_the_elastic_ones() {
    // a = (1, 1): ε_zz = −ν/(1−ν) tr_in (plane stress), lateral = −ν ε (uniaxial). 1e-15 relative.
    let law = spectral_law();
    let (l, m, nu) = (law.lambda(), law.mu(), law.nu());
    for t0 in [3e-4, -2e-4, 0.0, 1e-12] {
        let z = condensed_strain(l, m, [1.0, 1.0], t0, 1.0);
        assert!((z + nu / (1.0 - nu) * t0).abs() <= 1e-15 * t0.abs().max(1e-30), "{t0}: {z}");
        let z = condensed_strain(l, m, [1.0, 1.0], t0, 2.0);
        assert!((z + nu * t0).abs() <= 1e-15 * t0.abs().max(1e-30), "{t0}: {z}");
    }
    // Damaged: the root makes σ_z vanish (to round-off of the stresses, 1e-12 of λ|t₀|).
    for (a, t0, k) in
        [([0.1, 0.9], 3e-4, 1.0), ([0.02, 1.0], -3e-4, 1.0), ([0.3, 0.6], 5e-4, 2.0), ([0.01, 0.5], -1e-3, 2.0)]
    {
        let z = condensed_strain(l, m, a, t0, k);
        let t = t0 + k * z;
        let s = l * weight(a, t) * t + 2.0 * m * weight(a, z) * z;
        assert!(s.abs() <= 1e-12 * l * t0.abs(), "{a:?} {t0} {k}: σ_z {s}");
    }
}

#[test]
fn below_the_thresholds_it_is_the_elastic_law() {
    // d = 0: σ = C ε in every kinematics (the trace split's elastic branch), 1e-12 relative.
    let (s, t) = (spectral_law(), trace_law());
    let e3 = Vector3::new(0.3e-4, -0.5e-4, 0.4e-4);
    let (a, b) = (
        plane_stress::update(&s, &e3, &DamageState::default()),
        plane_stress::update(&t, &e3, &DamageState::default()),
    );
    assert!(rel_diff(a.stress.as_slice(), b.stress.as_slice()) <= 1e-12);
    assert!(rel_diff(a.tangent.as_slice(), b.tangent.as_slice()) <= 1e-12);
    let e6 = Vector6::new(0.3e-4, -0.5e-4, 0.1e-4, 0.2e-4, -0.1e-4, 0.4e-4);
    let (a, b) = (three_d::update(&s, &e6, &DamageState::default()), three_d::update(&t, &e6, &DamageState::default()));
    assert!(rel_diff(a.stress.as_slice(), b.stress.as_slice()) <= 1e-12);
    assert!(rel_diff(a.tangent.as_slice(), b.tangent.as_slice()) <= 1e-12);
    for eps in [0.5e-4, -3e-4] {
        let (a, b) =
            (uniaxial::update(&s, eps, &DamageState::default()), uniaxial::update(&t, eps, &DamageState::default()));
        assert!(
            (a.stress - b.stress).abs() <= 1e-12 * b.stress.abs() && (a.tangent - b.tangent).abs() <= 1e-12 * b.tangent
        );
    }
}

#[test]
fn with_equal_damages_both_splits_agree() {
    // d_t = d_c = d: ψ = (1 − d) ψ₀, σ = (1 − d) C ε, whatever the split (ψ₀⁺ + ψ₀⁻ = ψ₀). Unloading
    // strains (κ above ε_eq); 1e-12 relative.
    let (s, t) = (spectral_law(), trace_law());
    let st = state_with(&s, 0.4, 0.4);
    assert!((st.d_t - st.d_c).abs() < 1e-12);
    for e3 in [Vector3::new(1e-4, -0.7e-4, 0.5e-4), Vector3::new(-1e-4, -0.2e-4, 0.9e-4)] {
        let (a, b) = (plane_stress::update(&s, &e3, &st), plane_stress::update(&t, &e3, &st));
        assert!(!a.loading && !b.loading);
        assert!(rel_diff(a.stress.as_slice(), b.stress.as_slice()) <= 1e-11, "{} vs {}", a.stress, b.stress);
    }
    let e6 = Vector6::new(1e-4, -0.5e-4, 0.2e-4, 0.3e-4, -0.1e-4, 0.4e-4);
    let (a, b) = (three_d::update(&s, &e6, &st), three_d::update(&t, &e6, &st));
    assert!(rel_diff(a.stress.as_slice(), b.stress.as_slice()) <= 1e-11);
}

/// Σ σ·Δε over a closed polygon of strains: each edge is cut into `n` pieces; with `exact`, a piece
/// over which the directional derivative D Δε of the stress (D the secant, the derivative at fixed
/// damage) changes is split at the kink, found by bisection to machine precision, so that the
/// trapezoidal rule is exact on both parts of a piecewise-linear stress. Returns (net work,
/// Σ |σ·Δε|) and asserts that no damage grows.
fn cycle_work<const N: usize, M: StressState<N>>(
    law: &PointLaw,
    committed: &DamageState,
    corners: &[SVector<f64, N>],
    n: usize,
    exact: bool,
) -> (f64, f64) {
    let at = |e: &SVector<f64, N>| {
        let r = M::evaluate(law, e, committed);
        assert!(!r.loading, "damage grew at {e:?}");
        r
    };
    let (mut net, mut abs) = (0.0, 0.0);
    let mut piece = |e0: SVector<f64, N>, e1: SVector<f64, N>| {
        let w = 0.5 * (at(&e0).stress + at(&e1).stress).dot(&(e1 - e0));
        net += w;
        abs += w.abs();
    };
    for k in 0..corners.len() {
        let (a, b) = (corners[k], corners[(k + 1) % corners.len()]);
        for i in 0..n {
            let e0 = a + (b - a) * (i as f64 / n as f64);
            let e1 = a + (b - a) * ((i + 1) as f64 / n as f64);
            let de = e1 - e0;
            let slope = |e: &SVector<f64, N>| at(e).secant * de;
            let same = |x: &SVector<f64, N>, y: &SVector<f64, N>| (x - y).norm() <= 1e-10 * x.norm().max(y.norm());
            let (s0, s1) = (slope(&(e0 + de * 1e-6)), slope(&(e1 - de * 1e-6)));
            if !exact || same(&s0, &s1) {
                piece(e0, e1);
                continue;
            }
            let (mut lo, mut hi) = (e0, e1);
            for _ in 0..80 {
                let mid = (lo + hi) * 0.5;
                if same(&s0, &slope(&mid)) {
                    lo = mid;
                } else {
                    hi = mid;
                }
            }
            // One kink per piece at this resolution: beyond it the slope is the end's.
            assert!(same(&slope(&((hi + e1) * 0.5)), &s1), "two kinks in one piece of edge {k}: {e0:?} {lo:?}");
            piece(e0, lo);
            piece(lo, e1);
        }
    }
    (net, abs)
}

#[test]
fn a_closed_strain_cycle_across_crack_closure_does_no_work_with_the_spectral_split() {
    // A crack (d_t = 0.9, d_c = 0.2) opens and closes under shear: the strain goes round a polygon
    // of α(1, 1, 0) + β(0, 0, 1) with α changing sign (tr σ̃ = 0 crossed twice) and β > 0 (fixed
    // principal directions, so the spectral stress is piecewise linear). The stress derives from a
    // potential, so the work is zero: 1e-10 of Σ|σ·Δε| (round-off of the exact trapezoids). The
    // paper's split creates energy on the same cycle (the module docs of split.rs): its net work is
    // reported, and must be far from zero (> 1e-3 of Σ|σ·Δε|).
    let amp = 0.1 * 2.0e-4;
    let corners: Vec<Vector3<f64>> =
        [(-1.0, 1.0), (1.0, 1.0), (1.0, 3.0), (-2.0, 2.5)].iter().map(|&(a, b)| Vector3::new(a, a, b) * amp).collect();
    let s = spectral_law();
    let st = state_with(&s, 0.9, 0.2);
    let (net, abs) = cycle_work::<3, PlaneStress>(&s, &st, &corners, 64, true);
    assert!(net.abs() <= 1e-10 * abs, "spectral: net work {net:e} of {abs:e}");
    let t = trace_law();
    let (net_t, abs_t) = cycle_work::<3, PlaneStress>(&t, &st, &corners, 20_000, false);
    eprintln!(
        "closed cycle, plane stress: spectral {:.2e}, trace {:.2e} of the path's |work|",
        net / abs,
        net_t / abs_t
    );
    assert!(net_t.abs() > 1e-3 * abs_t, "trace: net work {net_t:e} of {abs_t:e}");

    // 3D: the same polygon in α(1, 1, 1) + β γ_xy, and a second shear component.
    let corners: Vec<Vector6<f64>> = [(-1.0, 1.0), (1.0, 1.0), (1.0, 3.0), (-2.0, 2.5)]
        .iter()
        .map(|&(a, b)| Vector6::new(a, a, a, 0.0, 0.0, b) * amp)
        .collect();
    let (net, abs) = cycle_work::<6, ThreeD>(&s, &st, &corners, 64, true);
    assert!(net.abs() <= 1e-10 * abs, "spectral 3D: net work {net:e} of {abs:e}");
    let (net_t, abs_t) = cycle_work::<6, ThreeD>(&t, &st, &corners, 64, true);
    eprintln!("closed cycle, 3D: spectral {:.2e}, trace {:.2e}", net / abs, net_t / abs_t);
    assert!(net_t.abs() > 1e-3 * abs_t, "trace 3D: net work {net_t:e} of {abs_t:e}");

    // Fibers: tension and compression around zero strain (no shear, so no jump with either split;
    // the spectral one must still close).
    let corners: Vec<Vector1<f64>> = [-1.0, 1.5].iter().map(|&a| Vector1::new(a * amp)).collect();
    let (net, abs) = cycle_work::<1, Uniaxial>(&s, &st, &corners, 16, true);
    assert!(net.abs() <= 1e-10 * abs, "spectral fiber: net work {net:e} of {abs:e}");
}

#[test]
fn the_stress_is_continuous_where_a_crack_closes_under_shear() {
    // Pure shear γ plus a volumetric strain ±δ: tr σ̃ changes sign with δ. With d_t = 0.9 and
    // d_c = 0 the paper's 3D split jumps by a factor (1 − d_c)/(1 − d_t) = 10 in τ_xy; the spectral
    // stress changes by O(δ/γ) = 1e-8 relative (tolerance 1e-6).
    let (s, t) = (spectral_law(), trace_law());
    let st = state_with(&s, 0.9, 0.0);
    let g = 1e-4;
    let shear = |law: &PointLaw, delta: f64| three_d::update(law, &Vector6::new(delta, delta, delta, 0.0, 0.0, g), &st);
    let (up, down) = (shear(&s, 1e-12), shear(&s, -1e-12));
    assert_eq!((up.side, down.side), (Side::Tension, Side::Compression));
    assert!((up.stress[5] / down.stress[5] - 1.0).abs() < 1e-6, "{} vs {}", up.stress[5], down.stress[5]);
    // The closed crack's shear stiffness is the strut's: τ = μ γ (1 − (d_t + d_c)/2) (principal
    // strains ±γ/2, half the shear energy on each side), 1e-10 relative.
    let expected = s.mu() * g * (1.0 - 0.5 * (st.d_t + st.d_c));
    let pure = shear(&s, 0.0).stress[5];
    assert!((pure - expected).abs() <= 1e-10 * expected, "{pure} vs {expected}");
    let (tu, td) = (shear(&t, 1e-12), shear(&t, -1e-12));
    assert!(td.stress[5] / tu.stress[5] > 9.0, "trace split: {} vs {}", tu.stress[5], td.stress[5]);
}

#[test]
fn the_stress_is_the_gradient_of_the_free_energy() {
    // 3D, fixed damage (unloading states): σ = ∂ψ/∂ε by central differences of free_energy_3d
    // (engineering shear: ∂ψ/∂γ_ij = σ_ij), step 1e-7 |ε|, tolerance 1e-6; and ψ = ½ σ·ε (degree-2
    // homogeneity), 1e-12.
    let s = spectral_law();
    let st = state_with(&s, 0.7, 0.3);
    for e in [
        Vector6::new(1e-4, -0.5e-4, 0.2e-4, 0.3e-4, -0.1e-4, 0.4e-4),
        Vector6::new(-1e-4, -0.2e-4, 0.1e-4, 0.0, 0.6e-4, -0.2e-4),
        Vector6::new(0.1e-4, 0.1e-4, -0.3e-4, 0.9e-4, 0.0, 0.0),
    ] {
        let r = three_d::update(&s, &e, &st);
        assert!(!r.loading);
        let psi = |x: &Vector6<f64>| free_energy_3d(&s, x, st.d_t, st.d_c);
        let h = 1e-7 * e.amax();
        let mut grad = Vector6::zeros();
        for j in 0..6 {
            let (mut p, mut m) = (e, e);
            p[j] += h;
            m[j] -= h;
            grad[j] = (psi(&p) - psi(&m)) / (2.0 * h);
        }
        assert!(rel_diff(r.stress.as_slice(), grad.as_slice()) <= 1e-6, "{} vs {}", r.stress, grad);
        assert!((psi(&e) - 0.5 * r.stress.dot(&e)).abs() <= 1e-12 * psi(&e));
        // The secant is symmetric and gives the stress (Euler).
        assert!(rel_diff(r.secant.as_slice(), r.secant.transpose().as_slice()) <= 1e-14);
        assert!(rel_diff((r.secant * e).as_slice(), r.stress.as_slice()) <= 1e-12);
    }
}

#[test]
fn consistent_tangents_match_finite_differences() {
    // Central differences, step 1e-7 ‖ε‖∞, tolerance 1e-6 norm-wise relative (as the trace split's
    // checks); plane-stress directions in the switch band are checked by the next test.
    let s = spectral_law();
    let c0 = plane_stress::elastic_matrix(&s);
    let in_band = |e: &Vector3<f64>| {
        let st = c0 * e;
        let x = (st[0] + st[1]) / (st[0] * st[0] + st[1] * st[1] + 2.0 * st[2] * st[2]).sqrt();
        x < 0.0 && x > -plane_stress::SWITCH_BAND
    };
    let n = check_tangent::<3, PlaneStress>(&s, 21, 400, 1e-6, |e| {
        if in_band(e) {
            0.0
        } else {
            plane_stress::equivalent_strain(&s, e).0
        }
    });
    assert_eq!(n, 200);
    let n = check_tangent::<6, ThreeD>(&s, 31, 400, 1e-6, |e| three_d::equivalent_strain(e).0);
    assert_eq!(n, 200);
    let n =
        check_tangent::<1, Uniaxial>(&s, 41, 200, 1e-6, |e| uniaxial::equivalent_strain_ratio(&s, e[0]) * e[0].abs());
    assert_eq!(n, 100);
}

#[test]
fn tangent_with_both_sides_damaged_and_in_the_switch_band_matches_finite_differences() {
    // Committed d_t = 0.8, d_c = 0.3 (the spectral split differs most from the trace split when the
    // two differ), strains in all directions including the band, loading or not. Same tolerance.
    let s = spectral_law();
    let st = state_with(&s, 0.8, 0.3);
    let mut rng = crate::material::test_support::Rng::new(7);
    let (mut loading, mut checked) = (0, 0);
    while checked < 200 {
        let e = Vector3::new(rng.range(-1.0, 1.0), rng.range(-1.0, 1.0), rng.range(-1.0, 1.0))
            * (rng.range(0.5, 6.0) * 2e-4);
        let r = plane_stress::update(&s, &e, &st);
        let fd = fd_tangent::<3, PlaneStress>(&s, &e, &st, 1e-7 * e.amax());
        let err = rel_diff(r.tangent.as_slice(), fd.as_slice());
        // Skip the rare states within a step of a kink (a principal strain, ε_zz or tr ε at 0, or
        // the onset of loading), where the difference quotient straddles it: there the quotients
        // with steps δ and δ/4 disagree (elsewhere they agree to O(δ²)).
        let fd4 = fd_tangent::<3, PlaneStress>(&s, &e, &st, 0.25e-7 * e.amax());
        if rel_diff(fd4.as_slice(), fd.as_slice()) > 1e-7 {
            continue;
        }
        assert!(err <= 1e-6, "{e:?}: {err:e}\n{}\n{}", r.tangent, fd);
        loading += r.loading as usize;
        checked += 1;
    }
    assert!(loading > 20, "loading states {loading}");
}

#[test]
fn damage_never_decreases_on_random_paths() {
    let s = spectral_law();
    assert!(check_random_paths::<3, PlaneStress>(&s, 5, 300, 60, 3.0) > 0.0);
    assert!(check_random_paths::<6, ThreeD>(&s, 9, 200, 60, 3.0) > 0.0);
    assert!(check_random_paths::<1, Uniaxial>(&s, 11, 200, 60, 3.0) > 0.0);
}

#[test]
fn uniaxial_tension_to_failure_dissipates_what_it_works() {
    // A fiber pulled to ε = 200 ε₀ (1 − d_t ≈ 3e-8) with 8,000 steps: the work ∫σ dε (trapezoids) equals the
    // dissipation summed over the steps plus the energy left, ½ σ ε, to 1e-3 (the dissipation is
    // integrated with Y at the end of each step; halving the steps halves the gap). The spectral
    // split keeps the lateral compression undamaged, so its stress at a given d_t lies between
    // (1 − d_t) E ε and (1 − d_t)(λ + 2μ) ε, and so does the energy to failure relative to the
    // trace split's f_t²/(2E) + f_t/B_t ([`PointLaw::tensile_failure_energy_density`]).
    for law in [spectral_law(), trace_law()] {
        let n = 8000;
        let top = 200.0 * law.eps0_t();
        let (mut st, mut work, mut diss, mut prev) = (DamageState::default(), 0.0, 0.0, (0.0, 0.0));
        for k in 1..=n {
            let eps = top * k as f64 / n as f64;
            let r = uniaxial::update(&law, eps, &st);
            work += 0.5 * (r.stress + prev.1) * (eps - prev.0);
            diss += r.dissipation;
            prev = (eps, r.stress);
            st = r.state;
        }
        let left = 0.5 * prev.1 * prev.0;
        assert!((work - diss - left).abs() <= 1e-3 * work, "{:?}: work {work} vs {diss} + {left}", law.split());
        let ratio = work / law.tensile_failure_energy_density();
        let bound = (law.lambda() + 2.0 * law.mu()) / law.e();
        eprintln!("{:?}: energy to ε = 200 ε₀ / (f_t²/2E + f_t/B_t) = {ratio:.4}", law.split());
        match law.split() {
            Split::Trace => assert!((ratio - 1.0).abs() < 1e-3, "{ratio}"),
            Split::Spectral => assert!(ratio > 1.0 - 1e-3 && ratio < bound, "{ratio} vs (1, {bound})"),
        }
    }
}

#[test]
fn a_point_with_no_tensile_integrity_left_stays_finite() {
    // κ_t = 1 gives d_t = 1 to round-off (exp(−600) underflows against 1): the tensile pieces of
    // σ_z are flat, the condensed strain takes the kink, and every response is finite; in
    // uniaxial tension the fiber carries nothing, in compression it closes with 2μ = E/(1 + ν):
    // with a_t = 0 the lateral extensions are free and ψ = μ ε² (the split's docs), 1e-9.
    let s = spectral_law();
    let st = DamageState { kappa_t: 1.0, ..DamageState::default() };
    assert_eq!(s.damage(Side::Tension, 1.0).d, 1.0);
    let finite = |v: &[f64]| v.iter().all(|x| x.is_finite());
    for e in [Vector3::new(3e-4, -1e-4, 2e-4), Vector3::new(1e-4, 1e-4, 0.0), Vector3::new(-2e-4, 1e-4, 3e-4)] {
        let r = plane_stress::update(&s, &e, &st);
        assert!(finite(r.stress.as_slice()) && finite(r.tangent.as_slice()), "{e:?}: {r:?}");
    }
    let r = three_d::update(&s, &Vector6::new(3e-4, -1e-4, 0.5e-4, 0.0, 1e-4, 2e-4), &st);
    assert!(finite(r.stress.as_slice()) && finite(r.tangent.as_slice()));
    let t = uniaxial::update(&s, 3e-4, &st);
    assert!(t.stress.is_finite() && t.tangent.is_finite() && t.stress.abs() <= 1e-9 * s.e() * 3e-4, "{t:?}");
    let c = uniaxial::update(&s, -1e-5, &st);
    assert!((c.stress + 2.0 * s.mu() * 1e-5).abs() <= 1e-9 * s.e() * 1e-5, "{c:?}");
}

#[test]
fn the_state_only_update_is_the_full_updates_state_to_the_bit() {
    // `plane_stress::update_state` (what IMPL-EX settles at every point) skips the stress and
    // tangent where no history grows. Along strain paths that load, unload, reverse and reload
    // in tension, compression and shear (a deterministic pseudo-random walk of 2,000 steps
    // from 0 to a few times ε₀, each step's state committed), with both splits, it must give
    // `update`'s state and dissipation exactly (bitwise), and both branches must be taken.
    let eps0 = params().eps0_t;
    for law in [spectral_law(), trace_law()] {
        let mut seed = 0x2545_f491_4f6c_dd1du64;
        let mut next = || {
            seed ^= seed << 13;
            seed ^= seed >> 7;
            seed ^= seed << 17;
            (seed >> 11) as f64 / (1u64 << 53) as f64 - 0.5
        };
        let (mut strain, mut committed) = (Vector3::zeros(), DamageState::default());
        let (mut loading, mut quiet) = (0, 0);
        for _ in 0..2000 {
            strain += Vector3::new(next(), next(), next()) * (0.8 * eps0);
            strain *= 0.995;
            let full = plane_stress::update(&law, &strain, &committed);
            let (state, dissipation) = plane_stress::update_state(&law, &strain, &committed);
            assert_eq!((state, dissipation.to_bits()), (full.state, full.dissipation.to_bits()), "{strain:?}");
            if full.loading {
                loading += 1;
            } else {
                quiet += 1;
            }
            committed = full.state;
        }
        assert!(loading > 20 && quiet > 20, "loading {loading}, quiet {quiet}");
    }
}
