//! The damage law in uniaxial stress, for the fibers of fiber-section beams.
//!
//! One strain ε = ε_11, σ = (1 − d) E ε, tr σ̃ = E ε (so the side is the sign of ε, tension at 0).
//!
//! # Lateral strains enter ε_eq
//! A fiber is in uniaxial stress, so its lateral strains are ε_22 = ε_33 = −ν ε and its principal
//! strains are (ε, −ν ε, −ν ε). The fiber is treated exactly as the uniaxial stress state of the
//! plane-stress law: ε_33 plays ε_zz and counts iff
//! [`EZZ_ENTERS_EQUIVALENT_STRAIN`] (true), so
//! fibers and shell layers agree. With ν > 0:
//!
//! ```text
//!   ε ≥ 0:  ε_eq^t = ε                          (tension as in a bar)
//!   ε < 0:  ε_eq^c = √2 ν |ε|                   (compression damage from lateral extension)
//! ```
//! In general ε_eq = r |ε| with r = sqrt(⟨1⟩² + n_lat ⟨−ν⟩²) for ε ≥ 0 and r = sqrt(n_lat) ⟨ν⟩₊ for
//! ε < 0, n_lat = 2 (1 if ε_zz were left out). With ν = 0 a fiber never damages in compression.
//! Y = ½ E ε², so the dissipation factor is c = Y/ε_eq² = E/(2 r²).

use nalgebra::{Matrix1, Vector1};

use super::law::PointLaw;
use super::plane_stress::EZZ_ENTERS_EQUIVALENT_STRAIN;
use super::response::{Response, StressState};
use super::spectral;
use super::split::Split;
use super::state::{evolve, DamageState, Side};

/// The result of one fiber update (scalar form of [`Response`]).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct UniaxialResponse {
    /// Stress σ (Pa).
    pub stress: f64,
    /// Secant modulus (1 − d) E (Pa).
    pub secant: f64,
    /// Consistent tangent dσ/dε (Pa): (1 − d) E − E ε d'(κ) dε_eq/dε while loading.
    pub tangent: f64,
    /// The trial history.
    pub state: DamageState,
    /// Energy per volume dissipated by this update (J/m³), ≥ 0.
    pub dissipation: f64,
    /// The active side (sign of ε).
    pub side: Side,
    /// Whether the active damage grew.
    pub loading: bool,
}

/// Number of lateral principal strains counted in ε_eq (module docs).
const N_LATERAL: f64 = if EZZ_ENTERS_EQUIVALENT_STRAIN { 2.0 } else { 1.0 };

/// The ratio r = ε_eq / |ε| on the side of `strain` (module docs).
#[inline]
pub fn equivalent_strain_ratio(law: &PointLaw, strain: f64) -> f64 {
    let nu = law.nu();
    if strain >= 0.0 {
        let lat = (-nu).max(0.0);
        (1.0 + N_LATERAL * lat * lat).sqrt()
    } else {
        N_LATERAL.sqrt() * nu.max(0.0)
    }
}

/// Update a fiber at total strain `strain` from the committed history. Pure, no allocation.
#[inline]
pub fn update(law: &PointLaw, strain: f64, committed: &DamageState) -> UniaxialResponse {
    let e = law.e();
    let sigma_tilde = e * strain;
    let side = Side::of_trace(sigma_tilde);
    let r = equivalent_strain_ratio(law, strain);
    let eq = r * strain.abs();
    if law.split() == Split::Spectral {
        let deq = if strain >= 0.0 { r } else { -r };
        return spectral::uniaxial(law, strain, side, eq, deq, committed);
    }
    let y = 0.5 * strain * sigma_tilde;
    let evo = evolve(law, side, eq, y, committed);
    let secant = evo.integrity * e;
    // dε_eq/dε = r sign(ε); sign(ε) = ±1 on the side (loading needs ε_eq > 0, so ε ≠ 0).
    let deq = if strain >= 0.0 { r } else { -r };
    let tangent = if evo.loading { secant - sigma_tilde * evo.dd_deq * deq } else { secant };
    UniaxialResponse {
        stress: evo.integrity * sigma_tilde,
        secant,
        tangent,
        state: evo.state,
        dissipation: evo.dissipation,
        side,
        loading: evo.loading,
    }
}

/// Marker of the uniaxial (fiber) kinematics for generic drivers.
#[derive(Clone, Copy, Debug, Default)]
pub struct Uniaxial;

impl StressState<1> for Uniaxial {
    const COMPONENTS: [&'static str; 1] = ["xx"];
    const SHEAR_XY: Option<usize> = None;
    fn evaluate(law: &PointLaw, strain: &Vector1<f64>, committed: &DamageState) -> Response<1> {
        let r = update(law, strain[0], committed);
        Response {
            stress: Vector1::new(r.stress),
            secant: Matrix1::new(r.secant),
            tangent: Matrix1::new(r.tangent),
            state: r.state,
            dissipation: r.dissipation,
            side: r.side,
            loading: r.loading,
        }
    }
}

#[cfg(test)]
mod tests {
    use nalgebra::Vector3;

    use super::*;
    use crate::material::test_support::{check_random_paths, check_tangent, law, params, Rng};
    use crate::material::{plane_stress, Regularization};

    #[test]
    fn uniaxial_tension_matches_the_closed_form() {
        // Closed form (paper §3.1 with κ = ε): σ = E ε for ε ≤ ε₀^t, σ = E ε₀ exp(−B_t (ε − ε₀)) after.
        // Tolerance 1e-12 relative (round-off of exp and of (ε₀/ε)·ε).
        let law = law();
        let (e, eps0, b) = (law.e(), law.eps0_t(), law.b_t());
        let mut state = DamageState::default();
        let mut peak: f64 = 0.0;
        for k in 1..=400 {
            let eps = k as f64 * 0.05 * eps0; // up to 20 ε₀
            let r = update(&law, eps, &state);
            let exact = if eps <= eps0 { e * eps } else { e * eps0 * (-b * (eps - eps0)).exp() };
            assert!((r.stress - exact).abs() <= 1e-12 * exact, "ε = {eps}: {} vs {exact}", r.stress);
            peak = peak.max(r.stress);
            state = r.state;
        }
        // Peak E ε₀^t reached at ε₀^t (k = 20).
        assert!((peak - e * eps0).abs() <= 1e-12 * e * eps0);
        assert_eq!(state.d_c, 0.0);
    }

    #[test]
    fn uniaxial_compression_matches_the_closed_form() {
        // Free lateral stress: principal strains (ε, −νε, −νε), so ε_eq^c = √2 ν |ε| (module docs),
        // κ_c = max(ε₀^c, √2 ν |ε|), σ = E ε [(1 − A_c) ε₀/κ + A_c exp(−B_c (κ − ε₀))].
        // Tolerance 1e-12 relative.
        let law = law();
        let p = params();
        let onset = p.eps0_c / (2f64.sqrt() * p.nu);
        let mut state = DamageState::default();
        for k in 1..=300 {
            let eps = -(k as f64) * 0.1 * onset; // up to 30× the onset strain
            let r = update(&law, eps, &state);
            let kappa = (2f64.sqrt() * p.nu * eps.abs()).max(p.eps0_c);
            let s = (1.0 - p.a_c) * p.eps0_c / kappa + p.a_c * (-p.b_c * (kappa - p.eps0_c)).exp();
            let exact = p.e * eps * s;
            assert!((r.stress - exact).abs() <= 1e-12 * exact.abs(), "ε = {eps}: {} vs {exact}", r.stress);
            assert_eq!(r.side, Side::Compression);
            state = r.state;
        }
        assert!(state.d_c > 0.5 && state.d_t == 0.0);
    }

    #[test]
    fn fiber_equals_the_plane_stress_uniaxial_state() {
        // The fiber is the plane-stress law at (ε, −νε, 0) (module docs): same stress, damage and
        // dissipation to round-off (1e-12 relative), in tension and in compression.
        let law = law();
        let nu = law.nu();
        for eps in [0.5e-4, 3e-4, 2e-3, -1e-4, -3e-3, -2e-2] {
            let f = update(&law, eps, &DamageState::default());
            let ps = plane_stress::update(&law, &Vector3::new(eps, -nu * eps, 0.0), &DamageState::default());
            assert!((f.stress - ps.stress[0]).abs() <= 1e-12 * f.stress.abs());
            assert!(ps.stress[1].abs() <= 1e-12 * f.stress.abs());
            assert!((f.state.d_t - ps.state.d_t).abs() <= 1e-12);
            assert!((f.state.d_c - ps.state.d_c).abs() <= 1e-12);
            assert!((f.dissipation - ps.dissipation).abs() <= 1e-12 * f.dissipation.max(1e-300));
        }
    }

    #[test]
    fn dissipation_to_failure_is_exact_for_each_regularization() {
        // Monotonic tension to B_t (κ − ε₀) = 60 in only 7 uneven steps: the closed-form
        // integration is exact for any step (mod.rs docs). Expected (params.rs table):
        //   hillerborg:            G_f/h + f_t²/(2E)
        //   hillerborg_no_elastic: G_f/h
        //   none:                  f_t²/(2E) + f_t/b_t
        // minus the tail left at the end, e^{-60}·(…) ≈ 1e-26 relative. Tolerance 1e-12 relative.
        let h = 0.1;
        let p = params();
        let ft = p.e * p.eps0_t;
        let elastic = ft * ft / (2.0 * p.e);
        for (reg, expected) in [
            (Regularization::Hillerborg, p.gf_t / h + elastic),
            (Regularization::HillerborgNoElastic, p.gf_t / h),
            (Regularization::Unregularized { b_t: 250.0 }, elastic + ft / 250.0),
        ] {
            let law = crate::material::DamageParams { regularization: reg, ..p }.for_element(h).unwrap();
            assert!((law.tensile_failure_energy_density() - expected).abs() <= 1e-12 * expected);
            let end = law.eps0_t() + 60.0 / law.b_t();
            let mut state = DamageState::default();
            let mut total = 0.0;
            for f in [0.3, 1.0, 1.0001, 1.3, 4.0, 17.0, 40.0] {
                let eps = (f * law.eps0_t()).min(end);
                let r = update(&law, eps, &state);
                total += r.dissipation;
                state = r.state;
            }
            let r = update(&law, end, &state);
            total += r.dissipation;
            assert!((total - expected).abs() <= 1e-12 * expected, "{reg:?}: {total} vs {expected}");
        }
    }

    #[test]
    fn dissipation_equals_the_work_done_to_failure() {
        // Energy balance: the work ∫σ dε (trapezoid, 200 000 steps) of a tension to failure equals
        // the dissipated energy (σ → 0, nothing stored). Tolerance 1e-6 relative (trapezoid error).
        let law = law();
        let end = law.eps0_t() + 40.0 / law.b_t();
        let n = 200_000;
        let mut state = DamageState::default();
        let (mut work, mut diss, mut prev) = (0.0, 0.0, (0.0, 0.0));
        for k in 1..=n {
            let eps = end * k as f64 / n as f64;
            let r = update(&law, eps, &state);
            work += 0.5 * (r.stress + prev.1) * (eps - prev.0);
            diss += r.dissipation;
            prev = (eps, r.stress);
            state = r.state;
        }
        assert!((work - diss).abs() <= 1e-6 * diss, "{work} vs {diss}");
    }

    #[test]
    fn unilateral_effect_both_ways() {
        let law = law();
        let e = law.e();
        // Tension damage first (ε = 5 ε₀^t), then compression below the compressive threshold:
        // the undamaged modulus E is recovered, d_c = 0 (paper §3.1 unilateral split). Exact.
        let r = update(&law, 5.0 * law.eps0_t(), &DamageState::default());
        assert!(r.state.d_t > 0.5);
        let c = update(&law, -2.0 * law.eps0_t(), &r.state);
        assert_eq!(c.side, Side::Compression);
        assert_eq!(c.state.d_c, 0.0);
        assert_eq!(c.secant, e);
        assert_eq!(c.tangent, e);
        assert_eq!(c.stress, -2.0 * law.eps0_t() * e);
        assert_eq!(c.state.d_t, r.state.d_t); // tensile damage remembered
                                              // Back in tension: the tensile damage is still there.
        let t = update(&law, 1.0 * law.eps0_t(), &c.state);
        assert!((t.secant - (1.0 - r.state.d_t) * e).abs() <= 1e-12 * e);
        // The reverse: compression damage, then tension sees E.
        let big = -20.0 * law.eps0_c() / (2f64.sqrt() * law.nu());
        let r = update(&law, big, &DamageState::default());
        assert!(r.state.d_c > 0.3);
        let t = update(&law, 0.5 * law.eps0_t(), &r.state);
        assert_eq!(t.side, Side::Tension);
        assert_eq!((t.state.d_t, t.secant), (0.0, e));
    }

    #[test]
    fn consistent_tangent_matches_finite_differences() {
        // Central differences, step 1e-7 |ε|; tolerance 1e-6 relative (a consistent tangent).
        let law = law();
        let loading =
            check_tangent::<1, Uniaxial>(&law, 11, 200, 1e-6, |e| equivalent_strain_ratio(&law, e[0]) * e[0].abs());
        assert_eq!(loading, 100);
    }

    #[test]
    fn damage_never_decreases_on_random_paths() {
        let total = check_random_paths::<1, Uniaxial>(&law(), 7, 300, 60, 3.0);
        assert!(total > 0.0);
    }

    #[test]
    fn zero_poisson_ratio_never_damages_in_compression() {
        let law = crate::material::DamageParams { nu: 0.0, ..params() }.for_element(0.1).unwrap();
        let mut rng = Rng::new(3);
        let mut state = DamageState::default();
        for _ in 0..50 {
            let r = update(&law, -rng.range(0.0, 0.1), &state);
            state = r.state;
        }
        assert_eq!(state.d_c, 0.0);
    }
}
