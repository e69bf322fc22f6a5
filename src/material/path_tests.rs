//! Tests of the material-point path driver: closed forms of the paths, mixed control, errors.
use super::*;
use crate::material::test_support::{law, params};
use crate::material::{PlaneStress, ThreeD, Uniaxial};

/// Closed-form uniaxial stress–strain curve (paper §3.1; lateral-extension ε_eq^c = √2 ν|ε|).
fn closed_form(law: &PointLaw, eps: f64, kappa_t: f64, kappa_c: f64) -> f64 {
    let p = params();
    if eps >= 0.0 {
        let k = kappa_t.max(p.eps0_t);
        law.e() * eps * p.eps0_t / k * (-law.b_t() * (k - p.eps0_t)).exp()
    } else {
        let k = kappa_c.max(p.eps0_c);
        law.e() * eps * ((1.0 - p.a_c) * p.eps0_c / k + p.a_c * (-p.b_c * (k - p.eps0_c)).exp())
    }
}

fn check_uniaxial<const N: usize>(records: &[PathRecord<N>], law: &PointLaw) {
    // The lateral components are solved by Newton to rtol = 1e-12 of E·ε, so σ_xx matches the
    // closed form to 1e-10 f_t + 1e-9 |σ_xx| (absolute part as σ_xx → 0 in the softening;
    // relative part: the lateral residual is amplified through d(ε_eq) at large strain).
    let ft = law.tensile_strength();
    let nu = law.nu();
    let (mut kt, mut kc) = (0.0f64, 0.0f64);
    for r in records {
        let eps = r.strain[0];
        kt = kt.max(eps);
        kc = kc.max(-2f64.sqrt() * nu * eps);
        let exact = closed_form(law, eps, kt, kc);
        assert!(
            (r.stress[0] - exact).abs() <= 1e-10 * ft + 1e-9 * exact.abs(),
            "step {}: {} vs {exact}",
            r.step,
            r.stress[0]
        );
        // The free components satisfy the Newton criterion ‖r‖∞ ≤ 1e-12 E max(‖ε‖∞, ε₀^t).
        let newton_tol = 1e-12 * law.e() * eps.abs().max(law.eps0_t());
        for i in 1..N {
            assert!(r.stress[i].abs() <= newton_tol, "step {} component {i}: {}", r.step, r.stress[i]);
        }
        if N >= 2 {
            assert!((r.strain[1] + nu * eps).abs() <= 1e-10 * eps.abs().max(1e-6));
        }
    }
}

#[test]
fn uniaxial_tension_in_every_kinematics() {
    let law = law();
    let path1 = LoadPath::<1>::uniaxial_tension(10.0 * law.eps0_t(), 50).unwrap();
    let path3 = LoadPath::<3>::uniaxial_tension(10.0 * law.eps0_t(), 50).unwrap();
    let path6 = LoadPath::<6>::uniaxial_tension(10.0 * law.eps0_t(), 50).unwrap();
    let s = NewtonSettings::default();
    let r1 = run_path(Uniaxial, &law, &path1, &s).unwrap();
    let r3 = run_path(PlaneStress, &law, &path3, &s).unwrap();
    let r6 = run_path(ThreeD, &law, &path6, &s).unwrap();
    assert_eq!((r1.len(), r3.len(), r6.len()), (51, 51, 51));
    check_uniaxial(&r1, &law);
    check_uniaxial(&r3, &law);
    check_uniaxial(&r6, &law);
    // Same dissipation in the three (1e-9 relative: the lateral strains are Newton solutions).
    let d = r1[50].dissipated;
    assert!(d > 0.0);
    assert!((r3[50].dissipated - d).abs() <= 1e-9 * d && (r6[50].dissipated - d).abs() <= 1e-9 * d);
}

#[test]
fn uniaxial_compression_in_every_kinematics() {
    let law = law();
    let s = NewtonSettings::default();
    let r1 = run_path(Uniaxial, &law, &LoadPath::uniaxial_compression(0.05, 50).unwrap(), &s).unwrap();
    let r3 = run_path(PlaneStress, &law, &LoadPath::uniaxial_compression(0.05, 50).unwrap(), &s).unwrap();
    let r6 = run_path(ThreeD, &law, &LoadPath::uniaxial_compression(0.05, 50).unwrap(), &s).unwrap();
    check_uniaxial(&r1, &law);
    check_uniaxial(&r3, &law);
    check_uniaxial(&r6, &law);
    assert!(r6[50].d_c > 0.5 && r6[50].d_t == 0.0);
}

#[test]
fn cyclic_path_shows_the_unilateral_effect() {
    // Tension to 6 ε₀^t, compression to −6 ε₀^t (below the compressive onset ε₀^c/(√2ν) ≈ 7 ε₀^t):
    // every compressive state has σ = E ε exactly (d_c = 0), the tensile damage is kept.
    let law = law();
    let path = LoadPath::<3>::cyclic_tension_compression(6.0 * law.eps0_t(), 6.0 * law.eps0_t(), 3, 20).unwrap();
    assert_eq!(path.len(), 7 * 20);
    let rec = run_path(PlaneStress, &law, &path, &NewtonSettings::default()).unwrap();
    check_uniaxial(&rec, &law);
    let mut prev = &rec[0];
    for r in &rec[1..] {
        assert!(r.d_t >= prev.d_t && r.dissipated >= prev.dissipated);
        if r.strain[0] < 0.0 {
            assert_eq!(r.d_c, 0.0);
            assert!((r.stress[0] - law.e() * r.strain[0]).abs() <= 1e-10 * law.tensile_strength());
        }
        prev = r;
    }
    assert!(rec.last().map(|r| r.d_t).unwrap_or(0.0) > 0.5);
}

#[test]
fn biaxial_tension_keeps_sigma_zz_free() {
    let law = law();
    let rec =
        run_path(ThreeD, &law, &LoadPath::biaxial(5.0 * law.eps0_t(), 1.0, 20).unwrap(), &NewtonSettings::default())
            .unwrap();
    let last = rec[20];
    // σ_zz = 0 and the shears are free (Newton tolerance, 1e-10 f_t); ε_zz = −2ν/(1−ν) ε_xx.
    for i in 2..6 {
        assert!(last.stress[i].abs() <= 1e-10 * law.tensile_strength());
    }
    let nu = law.nu();
    assert!((last.strain[2] + 2.0 * nu / (1.0 - nu) * last.strain[0]).abs() <= 1e-10 * last.strain[0]);
    assert!(last.d_t > 0.0 && last.stress[0] == last.stress[1]);
}

#[test]
fn pure_shear_in_plane_stress_and_3d() {
    // γ imposed, normal stresses free: ε_xx = ε_yy = 0, κ_t = γ/2, τ = (1 − d_t) μ γ.
    let law = law();
    let g = 8.0 * law.eps0_t();
    let s = NewtonSettings::default();
    let r3 = run_path(PlaneStress, &law, &LoadPath::pure_shear::<PlaneStress>(g, 16).unwrap(), &s).unwrap();
    let r6 = run_path(ThreeD, &law, &LoadPath::pure_shear::<ThreeD>(g, 16).unwrap(), &s).unwrap();
    let (a, b) = (r3[16], r6[16]);
    assert!((a.kappa_t - g / 2.0).abs() <= 1e-15 && (b.kappa_t - g / 2.0).abs() <= 1e-15);
    let tau = (1.0 - a.d_t) * law.mu() * g;
    assert!((a.stress[2] - tau).abs() <= 1e-12 * tau && (b.stress[5] - tau).abs() <= 1e-12 * tau);
    assert_eq!(a.d_c, 0.0);
}

#[test]
fn shear_under_a_held_compression_stays_elastic_below_the_thresholds() {
    // Plane stress, σ_yy = −p held, σ_xx free, γ up to 0.3 ε₀ᵗ: Hooke's law gives ε_yy = −p/E,
    // ε_xx = ν p/E, τ = μ γ (1e-10 relative: Newton's tolerance on the free components).
    let law = law();
    let p = 0.2 * law.e() * law.eps0_c();
    let g = 0.3 * law.eps0_t();
    let path = LoadPath::shear_under_compression::<PlaneStress>(p, &[g, -g], 10, 4).unwrap();
    assert_eq!(path.len(), 24);
    let r = run_path(PlaneStress, &law, &path, &NewtonSettings::default()).unwrap();
    let top = r[14];
    assert!((top.strain[2] - g).abs() <= 1e-15 * g && (top.stress[1] + p).abs() <= 1e-10 * p);
    assert!((top.strain[1] + p / law.e()).abs() <= 1e-10 * p / law.e(), "{:?}", top.strain);
    assert!((top.strain[0] - law.nu() * p / law.e()).abs() <= 1e-10 * p / law.e(), "{:?}", top.strain);
    assert!((top.stress[2] - law.mu() * g).abs() <= 1e-10 * law.mu() * g);
    assert_eq!((top.d_t, top.d_c), (0.0, 0.0));
    assert!(matches!(
        LoadPath::<1>::shear_under_compression::<Uniaxial>(p, &[g], 10, 4),
        Err(PathError::InvalidPath { .. })
    ));
}

#[test]
fn newton_failure_names_the_step() {
    // No iteration allowed: the first step with a stress-controlled component fails, typed.
    let law = law();
    let s = NewtonSettings { max_iterations: 0, rtol: 1e-12 };
    let err = run_path(PlaneStress, &law, &LoadPath::uniaxial_tension(1e-3, 5).unwrap(), &s).unwrap_err();
    assert!(matches!(err, PathError::NoConvergence { step: 1, iterations: 0, .. }), "{err:?}");
    assert!(err.to_string().contains("step 1"), "{err}");
    // Fully strain-controlled paths need no iteration.
    let path = LoadPath::<1>::uniaxial_tension(1e-3, 5).unwrap();
    assert_eq!(run_path(Uniaxial, &law, &path, &s).map(|r| r.len()), Ok(6));
}

#[test]
fn invalid_paths_are_rejected() {
    assert!(matches!(LoadPath::<1>::pure_shear::<Uniaxial>(1e-3, 5), Err(PathError::InvalidPath { .. })));
    assert!(matches!(LoadPath::<1>::biaxial(1e-3, 1.0, 5), Err(PathError::InvalidPath { .. })));
    assert!(matches!(LoadPath::<3>::uniaxial_tension(1e-3, 0), Err(PathError::InvalidPath { .. })));
    assert!(matches!(LoadPath::<3>::uniaxial_tension(-1e-3, 4), Err(PathError::InvalidPath { .. })));
    assert!(matches!(LoadPath::<3>::uniaxial(&[f64::NAN], 4), Err(PathError::InvalidPath { .. })));
}
