//! Shared helpers of the material tests: a seeded random generator and reference parameters.

use super::{DamageParams, PointLaw, Regularization};

/// SplitMix64 (Steele, Lea, Flood 2014): tiny, seeded, reproducible.
pub struct Rng(u64);

impl Rng {
    pub fn new(seed: u64) -> Self {
        Rng(seed)
    }
    pub fn next_u64(&mut self) -> u64 {
        self.0 = self.0.wrapping_add(0x9E37_79B9_7F4A_7C15);
        let mut z = self.0;
        z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
        z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
        z ^ (z >> 31)
    }
    /// Uniform in [0, 1).
    pub fn unit(&mut self) -> f64 {
        (self.next_u64() >> 11) as f64 / (1u64 << 53) as f64
    }
    /// Uniform in [a, b).
    pub fn range(&mut self, a: f64, b: f64) -> f64 {
        a + (b - a) * self.unit()
    }
}

/// Masonry-like parameters (order of paper §2.1 Table 1): E = 3 GPa, ν = 0.2, f_t = 0.3 MPa.
pub fn params() -> DamageParams {
    DamageParams {
        e: 3.0e9,
        nu: 0.2,
        eps0_t: 1.0e-4,
        eps0_c: 2.0e-4,
        gf_t: 50.0,
        a_c: 0.8,
        b_c: 800.0,
        gf_c: None,
        regularization: Regularization::Hillerborg,
        split: super::Split::Trace,
    }
}

/// The law of [`params`] for a 0.1 m element: B_t = 0.3e6 · 0.1 / 50 = 600.
pub fn law() -> PointLaw {
    match params().for_element(0.1) {
        Ok(l) => l,
        Err(e) => panic!("reference parameters rejected: {e}"),
    }
}

/// max |a − b| / max |b| over the entries (norm-wise relative difference).
pub fn rel_diff(a: &[f64], b: &[f64]) -> f64 {
    let num = a.iter().zip(b).map(|(x, y)| (x - y).abs()).fold(0.0, f64::max);
    let den = b.iter().map(|y| y.abs()).fold(0.0, f64::max);
    num / den
}

use nalgebra::{SMatrix, SVector};

use super::{DamageState, Side, StressState};

/// Central finite-difference tangent of `M` at `eps` from `committed`, step `delta` per component.
pub fn fd_tangent<const N: usize, M: StressState<N>>(
    law: &PointLaw,
    eps: &SVector<f64, N>,
    committed: &DamageState,
    delta: f64,
) -> SMatrix<f64, N, N> {
    let mut t = SMatrix::<f64, N, N>::zeros();
    for j in 0..N {
        let mut p = *eps;
        let mut m = *eps;
        p[j] += delta;
        m[j] -= delta;
        let sp = M::evaluate(law, &p, committed).stress;
        let sm = M::evaluate(law, &m, committed).stress;
        t.set_column(j, &((sp - sm) / (2.0 * delta)));
    }
    t
}

/// Check the consistent tangent of `M` against central differences at `n` random states, half of
/// them loading (committed κ just below the current ε_eq), half unloading; `eq` gives ε_eq of a
/// strain. Norm-wise relative tolerance `tol`. Returns the number of loading states checked.
pub fn check_tangent<const N: usize, M: StressState<N>>(
    law: &PointLaw,
    seed: u64,
    n: usize,
    tol: f64,
    eq: impl Fn(&SVector<f64, N>) -> f64,
) -> usize {
    let mut rng = Rng::new(seed);
    let mut loading_checked = 0;
    let mut checked = 0;
    let mut loading_sides = [0usize; 2];
    while checked < n {
        let mut dir = SVector::<f64, N>::zeros();
        for v in dir.iter_mut() {
            *v = rng.range(-1.0, 1.0);
        }
        let e_dir = eq(&dir);
        if e_dir < 1e-3 {
            continue;
        }
        let side = M::evaluate(law, &dir, &DamageState::default()).side;
        let eps0 = law.threshold(side);
        let t = rng.range(1.2, 8.0);
        let eps = dir * (t * eps0 / e_dir);
        // Stay clear of the stress jump at tr σ̃ = 0: the trace must not change sign under ±δ.
        let delta = 1e-7 * eps.amax();
        let plus = M::evaluate(law, &(eps + SVector::repeat(2.0 * delta)), &DamageState::default()).side;
        let minus = M::evaluate(law, &(eps - SVector::repeat(2.0 * delta)), &DamageState::default()).side;
        if plus != side || minus != side {
            continue;
        }
        let loading = checked % 2 == 0;
        let kappa = if loading { (t - 0.05) * eps0 } else { (t + 0.5) * eps0 };
        let mut committed = DamageState::default();
        match side {
            Side::Tension => committed.kappa_t = kappa,
            Side::Compression => committed.kappa_c = kappa,
        }
        // Make the committed d consistent with κ (not needed by the update, but realistic).
        let r0 = M::evaluate(law, &(dir * 1e-30), &committed);
        committed = r0.state;
        let r = M::evaluate(law, &eps, &committed);
        assert_eq!(r.loading, loading, "state {checked}: eps {eps:?}");
        let fd = fd_tangent::<N, M>(law, &eps, &committed, delta);
        let err = rel_diff(r.tangent.as_slice(), fd.as_slice());
        assert!(
            err <= tol,
            "state {checked} ({side:?}, loading {loading}): tangent vs FD rel. diff {err:e}\n{}\n{}",
            r.tangent,
            fd
        );
        if loading {
            loading_checked += 1;
            loading_sides[side as usize] += 1;
            // The loading tangent differs from the secant: the check has teeth.
            assert!(rel_diff(r.secant.as_slice(), fd.as_slice()) > 1e3 * tol);
        }
        checked += 1;
    }
    // Both damage variables were exercised while loading.
    assert!(loading_sides[0] > 0 && loading_sides[1] > 0, "loading states per side: {loading_sides:?}");
    loading_checked
}

/// Property: over `n_paths` random strain paths of `n_steps` steps (increments up to `amp` times
/// the larger threshold per component, occasional returns towards zero), κ and d never decrease,
/// d = d(κ), the dissipation increment is never negative and is zero unless loading.
pub fn check_random_paths<const N: usize, M: StressState<N>>(
    law: &PointLaw,
    seed: u64,
    n_paths: usize,
    n_steps: usize,
    amp: f64,
) -> f64 {
    let mut rng = Rng::new(seed);
    let scale = amp * law.eps0_t().max(law.eps0_c());
    let mut total = 0.0;
    for _ in 0..n_paths {
        let mut eps = SVector::<f64, N>::zeros();
        let mut state = DamageState::default();
        for _ in 0..n_steps {
            if rng.unit() < 0.1 {
                eps *= rng.unit();
            } else {
                for v in eps.iter_mut() {
                    *v += scale * rng.range(-1.0, 1.0);
                }
            }
            let r = M::evaluate(law, &eps, &state);
            let s = r.state;
            assert!(s.kappa_t >= state.kappa_t && s.kappa_c >= state.kappa_c, "κ decreased");
            assert!(s.d_t >= state.d_t && s.d_c >= state.d_c, "d decreased: {state:?} -> {s:?}");
            assert!((0.0..=1.0).contains(&s.d_t) && (0.0..=1.0).contains(&s.d_c));
            assert_eq!(s.d_t, law.damage(Side::Tension, s.kappa_t).d);
            assert_eq!(s.d_c, law.damage(Side::Compression, s.kappa_c).d);
            assert!(r.dissipation >= 0.0, "negative dissipation {}", r.dissipation);
            if !r.loading {
                assert_eq!(r.dissipation, 0.0);
                assert_eq!(
                    s.to_array(),
                    DamageState {
                        kappa_t: state.kappa_t.max(law.eps0_t()),
                        kappa_c: state.kappa_c.max(law.eps0_c()),
                        ..state
                    }
                    .to_array()
                );
            }
            total += r.dissipation;
            state = s;
        }
    }
    total
}
