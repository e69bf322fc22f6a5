//! Tests of the IMPL-EX update (`implex.rs`) in the three kinematics and both splits: the
//! extrapolation, the committed state against the implicit law, the tangent against finite
//! differences of the extrapolated stress, and the stress when the extrapolation is exact.
use nalgebra::{SMatrix, SVector, Vector3};

use super::*;
use crate::material::test_support::{law, params, rel_diff, Rng};
use crate::material::{plane_stress, DamageParams, PlaneStress, Split, ThreeD, Uniaxial};

/// The reference law of `test_support` with the given split.
fn law_with(split: Split) -> PointLaw {
    match (params().split, split) {
        (Split::Trace, Split::Trace) => law(),
        _ => DamageParams { split, ..params() }.for_element(0.1).unwrap(),
    }
}

/// A random strain of `N` components of size `scale` (uniform in [−scale, scale) each).
fn random_strain<const N: usize>(rng: &mut Rng, scale: f64) -> SVector<f64, N> {
    SVector::<f64, N>::from_fn(|_, _| rng.range(-scale, scale))
}

#[test]
fn the_extrapolation_is_exact_for_a_linearly_growing_history() {
    // κ_t(t) = ε₀ᵗ (1 + 40 t), κ_c(t) = ε₀ᶜ (1 + 7 t): from t_{n−1} = 0.10, t_n = 0.11, the
    // extrapolation over Δt_{n+1} = 0.02, 0.005 and 0.01 (ratios 2, 0.5, 1) lands on κ(t_{n+1})
    // to round-off (1e-14 relative), with d = d(κ̃) exactly.
    let law = law();
    let at = |t: f64| {
        let (kt, kc) = (law.eps0_t() * (1.0 + 40.0 * t), law.eps0_c() * (1.0 + 7.0 * t));
        DamageState {
            kappa_t: kt,
            kappa_c: kc,
            d_t: law.damage(Side::Tension, kt).d,
            d_c: law.damage(Side::Compression, kc).d,
        }
    };
    let (previous, committed) = (at(0.10), at(0.11));
    for h in [0.02, 0.005, 0.01] {
        let x = extrapolate(&law, &committed, &previous, h / 0.01);
        let exact = at(0.11 + h);
        assert!((x.kappa_t - exact.kappa_t).abs() <= 1e-14 * exact.kappa_t, "{h}: {x:?} vs {exact:?}");
        assert!((x.kappa_c - exact.kappa_c).abs() <= 1e-14 * exact.kappa_c, "{h}: {x:?} vs {exact:?}");
        assert_eq!(x.d_t, law.damage(Side::Tension, x.kappa_t).d);
        assert_eq!(x.d_c, law.damage(Side::Compression, x.kappa_c).d);
        assert!(x.d_t > committed.d_t && x.d_c > committed.d_c);
    }
}

#[test]
fn the_extrapolation_never_goes_below_the_committed_history() {
    // Ratio 0 (no earlier step) gives κ_n; a virgin point whose previous state is the default
    // (κ = 0, below the thresholds) is not extrapolated (both κ clamp to ε₀); a previous κ above
    // the committed one (not a history the law makes) cannot lower it. Exact.
    let law = law();
    let virgin = DamageState::virgin(&law);
    assert_eq!(extrapolate(&law, &DamageState::default(), &DamageState::default(), 3.0), virgin);
    assert_eq!(extrapolate(&law, &virgin, &DamageState::default(), 2.0), virgin);
    let grown = plane_stress::update(&law, &Vector3::new(4e-4, 0.0, 0.0), &virgin).state;
    assert!(grown.d_t > 0.0);
    assert_eq!(extrapolate(&law, &grown, &virgin, 0.0), grown);
    let above = DamageState { kappa_t: 2.0 * grown.kappa_t, ..grown };
    assert_eq!(extrapolate(&law, &grown, &above, 1.0), grown);
}

/// Along random strain increments from a virgin point, stepping the committed and previous
/// states as an element does (ratio 1, the split frozen at the last strain): the IMPL-EX trial
/// state and dissipation equal
/// the implicit law's from the same committed state bit for bit. Returns the number of loading
/// updates (the check has teeth only where the history grows).
fn committed_state_follows_the_implicit_law<const N: usize, K: StressState<N>>(law: &PointLaw, seed: u64) -> usize {
    let mut rng = Rng::new(seed);
    let scale = 1.5 * law.eps0_t().max(law.eps0_c());
    let mut loading = 0;
    for _ in 0..20 {
        let (mut previous, mut committed) = (DamageState::default(), DamageState::default());
        let mut eps = SVector::<f64, N>::zeros();
        for _ in 0..40 {
            let before = eps;
            eps += random_strain::<N>(&mut rng, scale);
            let x = extrapolate(law, &committed, &previous, 1.0);
            let r = update::<N, K>(law, &eps, &committed, &x, Some(&before));
            let implicit = K::evaluate(law, &eps, &committed);
            assert_eq!(r.state, implicit.state);
            assert_eq!(r.dissipation.to_bits(), implicit.dissipation.to_bits());
            assert_eq!(r.loading, implicit.loading);
            loading += r.loading as usize;
            (previous, committed) = (committed, r.state);
        }
    }
    loading
}

#[test]
fn the_committed_state_is_the_implicit_laws() {
    for split in [Split::Trace, Split::Spectral] {
        let law = law_with(split);
        let n = [
            committed_state_follows_the_implicit_law::<1, Uniaxial>(&law, 1),
            committed_state_follows_the_implicit_law::<3, PlaneStress>(&law, 2),
            committed_state_follows_the_implicit_law::<6, ThreeD>(&law, 3),
        ];
        assert!(n.iter().all(|&k| k > 50), "{split:?}: loading updates {n:?}");
    }
}

/// At `n` random strains with a damaged extrapolated history (d_t, d_c drawn up to 0.9), the
/// IMPL-EX tangent against central differences of the IMPL-EX stress: step 1e-7 ‖ε‖∞,
/// tolerance 1e-6 norm-wise relative (the implicit law's checks). Strains whose active side
/// changes within ±2 steps (the paper's split jumps there where d_t ≠ d_c) are skipped.
fn tangent_matches_differences<const N: usize, K: StressState<N>>(law: &PointLaw, seed: u64, n: usize) {
    let mut rng = Rng::new(seed);
    let kappa = |side: Side, d: f64| {
        // κ with d(κ) = d by bisection (d is increasing), to 1e-15 relative.
        let (mut lo, mut hi) = (law.threshold(side), 1.0);
        for _ in 0..200 {
            let mid = 0.5 * (lo + hi);
            if law.damage(side, mid).d < d {
                lo = mid
            } else {
                hi = mid
            }
        }
        lo
    };
    let mut checked = 0;
    while checked < n {
        let (dt, dc) = (rng.range(0.0, 0.9), rng.range(0.0, 0.9));
        let (kt, kc) = (kappa(Side::Tension, dt), kappa(Side::Compression, dc));
        let committed = DamageState {
            kappa_t: law.eps0_t().max(0.5 * kt),
            kappa_c: law.eps0_c().max(0.5 * kc),
            ..DamageState::default()
        };
        let x = DamageState { kappa_t: kt, kappa_c: kc, d_t: dt, d_c: dc };
        let eps = random_strain::<N>(&mut rng, 4.0 * law.eps0_c());
        let delta = 1e-7 * eps.amax();
        let side = |e: &SVector<f64, N>| update::<N, K>(law, e, &committed, &x, None).side;
        let s0 = side(&eps);
        if side(&(eps + SVector::repeat(2.0 * delta))) != s0 || side(&(eps - SVector::repeat(2.0 * delta))) != s0 {
            continue;
        }
        let r = update::<N, K>(law, &eps, &committed, &x, None);
        let mut fd = SMatrix::<f64, N, N>::zeros();
        for j in 0..N {
            let (mut p, mut m) = (eps, eps);
            p[j] += delta;
            m[j] -= delta;
            let ds = update::<N, K>(law, &p, &committed, &x, None).stress
                - update::<N, K>(law, &m, &committed, &x, None).stress;
            fd.set_column(j, &(ds / (2.0 * delta)));
        }
        let err = rel_diff(r.tangent.as_slice(), fd.as_slice());
        assert!(err <= 1e-6, "{:?} state {checked}: {err:e}\n{}\n{}", law.split(), r.tangent, fd);
        checked += 1;
    }
}

#[test]
fn the_tangent_is_the_derivative_of_the_extrapolated_stress() {
    for split in [Split::Trace, Split::Spectral] {
        let law = law_with(split);
        tangent_matches_differences::<1, Uniaxial>(&law, 11, 100);
        tangent_matches_differences::<3, PlaneStress>(&law, 12, 300);
        tangent_matches_differences::<6, ThreeD>(&law, 13, 300);
    }
}

#[test]
fn with_the_history_guessed_exactly_the_stress_is_the_implicit_one() {
    // A loading update from κ_n: choose κ_{n−1} = 2 κ_n − κ_{n+1} (the implicit κ_{n+1} at this
    // strain), so that the extrapolation with ratio 1 is exact; the IMPL-EX stress is then the
    // implicit one (1e-12 relative: κ̃ and κ_{n+1} differ by round-off).
    for split in [Split::Trace, Split::Spectral] {
        let law = law_with(split);
        let committed = DamageState { kappa_t: 1.5 * law.eps0_t(), kappa_c: 1.2 * law.eps0_c(), d_t: 0.0, d_c: 0.0 };
        let eps = SVector::<f64, 6>::new(1.8e-4, -0.4e-4, -0.3e-4, 0.2e-4, 0.1e-4, 0.5e-4);
        let implicit = ThreeD::evaluate(&law, &eps, &committed);
        assert!(implicit.loading);
        let k = |s: Side| 2.0 * committed.kappa(s) - implicit.state.kappa(s);
        let previous = DamageState { kappa_t: k(Side::Tension), kappa_c: k(Side::Compression), d_t: 0.0, d_c: 0.0 };
        assert!(previous.kappa_t >= law.eps0_t(), "{previous:?}");
        let x = extrapolate(&law, &committed, &previous, 1.0);
        let r = update::<6, ThreeD>(&law, &eps, &committed, &x, None);
        assert!(rel_diff(r.stress.as_slice(), implicit.stress.as_slice()) <= 1e-12, "{split:?}");
    }
}

#[test]
fn at_fixed_damage_the_papers_split_is_linear_on_each_side() {
    // The trace split at the extrapolated history: σ(a ε₁ + b ε₂) = a σ(ε₁) + b σ(ε₂) for strains
    // on one side outside the switch band, and the tangent is the secant: one Newton iteration
    // solves such a step. 1e-12 relative.
    let law = law();
    let committed = DamageState::virgin(&law);
    let x = extrapolate(&law, &committed, &DamageState::default(), 0.0);
    let x = DamageState { kappa_t: 3.0 * x.kappa_t, d_t: law.damage(Side::Tension, 3.0 * x.kappa_t).d, ..x };
    let (e1, e2) = (Vector3::new(3e-4, 0.5e-4, 1e-4), Vector3::new(1e-4, 2e-4, -0.5e-4));
    let s = |e: &Vector3<f64>| update::<3, PlaneStress>(&law, e, &committed, &x, None);
    let combo = s(&(e1 * 0.7 + e2 * 1.9)).stress;
    let sum = s(&e1).stress * 0.7 + s(&e2).stress * 1.9;
    assert!(rel_diff(combo.as_slice(), sum.as_slice()) <= 1e-12);
    assert_eq!(s(&e1).tangent, s(&e1).secant);
    assert!(s(&e1).stress.norm() < (plane_stress::elastic_matrix(&law) * e1).norm());
    let fiber = |e: f64| update::<1, Uniaxial>(&law, &SVector::<f64, 1>::new(e), &committed, &x, None).stress[0];
    assert!((fiber(5e-4) - 5.0 * fiber(1e-4)).abs() <= 1e-12 * fiber(5e-4).abs());
}

/// At `n` random committed strains ε_n and damaged extrapolated histories, the split frozen at
/// ε_n: the stress at ε_n is the law's at the extrapolated history (1e-10 relative: the
/// homogeneity σ = S ε of the law at fixed damage, to the round-off of the spectral
/// decomposition); the stress is linear in ε (1e-12); the tangent is the secant, symmetric
/// (1e-10 relative), and positive definite.
fn frozen_split_is_linear_and_exact_at_the_committed_strain<const N: usize, K: StressState<N>>(
    law: &PointLaw,
    seed: u64,
    n: usize,
) {
    let mut rng = Rng::new(seed);
    for k in 0..n {
        let scale = 4.0 * law.eps0_c();
        let kt = law.eps0_t() * rng.range(1.0, 30.0);
        let kc = law.eps0_c() * rng.range(1.0, 3.0);
        let x = DamageState {
            kappa_t: kt,
            kappa_c: kc,
            d_t: law.damage(Side::Tension, kt).d,
            d_c: law.damage(Side::Compression, kc).d,
        };
        let committed = DamageState::virgin(law);
        let at = random_strain::<N>(&mut rng, scale);
        let (e1, e2) = (random_strain::<N>(&mut rng, scale), random_strain::<N>(&mut rng, scale));
        let frozen = |e: &SVector<f64, N>| update::<N, K>(law, e, &committed, &x, Some(&at));
        let free = update::<N, K>(law, &at, &committed, &x, None);
        let r = frozen(&at);
        let what = format!("{:?} point {k}", law.split());
        assert!(
            rel_diff(r.stress.as_slice(), free.stress.as_slice()) <= 1e-10,
            "{what}: {} vs {}",
            r.stress,
            free.stress
        );
        let combo = frozen(&(e1 * 0.7 - e2 * 1.3)).stress;
        let sum = frozen(&e1).stress * 0.7 - frozen(&e2).stress * 1.3;
        assert!(rel_diff(combo.as_slice(), sum.as_slice()) <= 1e-12, "{what}");
        assert_eq!(r.tangent, r.secant);
        assert!(rel_diff(r.tangent.as_slice(), r.tangent.transpose().as_slice()) <= 1e-10, "{what}: {}", r.tangent);
        let sym = (r.tangent + r.tangent.transpose()) * 0.5;
        let dense = nalgebra::DMatrix::from_column_slice(N, N, sym.as_slice());
        assert!(dense.cholesky().is_some(), "{what}: not positive definite {}", r.tangent);
    }
}

#[test]
fn with_the_split_frozen_the_step_is_linear_and_exact_at_the_committed_strain() {
    for split in [Split::Trace, Split::Spectral] {
        let law = law_with(split);
        frozen_split_is_linear_and_exact_at_the_committed_strain::<1, Uniaxial>(&law, 21, 100);
        frozen_split_is_linear_and_exact_at_the_committed_strain::<3, PlaneStress>(&law, 22, 300);
        frozen_split_is_linear_and_exact_at_the_committed_strain::<6, ThreeD>(&law, 23, 300);
    }
}
