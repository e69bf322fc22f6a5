//! Tests of the fiber beam: elastic equivalence with the frame, rigid-body modes, consistent
//! tangent, tension softening with the Hillerborg energy, checkpoints, mass, bad input.

use super::*;
use crate::element::{ElasticFrame3d, FrameSection};
use crate::material::test_support::params;
use crate::material::{DamageParams, Regularization};

fn elastic_section(ny: usize, nz: usize) -> FiberSection {
    FiberSection {
        width: 0.3,
        height: 0.5,
        ny,
        nz,
        integration_points: 2,
        material: FiberMaterial::Elastic { e: 3e9, nu: 0.2 },
        density: 2000.0,
        nonstructural_mass: 0.0,
        torsion_constant: None,
    }
}

fn damage_section(reg: Regularization) -> FiberSection {
    FiberSection {
        material: FiberMaterial::Damage(DamageParams { regularization: reg, ..params() }),
        ..elastic_section(4, 6)
    }
}

/// Elements along a few axes, with seeded oblique ones (64-bit LCG, Knuth's MMIX constants).
fn geometries() -> Vec<([f64; 3], [f64; 3], [f64; 3])> {
    let mut out =
        vec![([0.0; 3], [1.5, 0.0, 0.0], [0.0, 0.0, 1.0]), ([1.0, 2.0, 0.0], [1.0, 2.0, 1.2], [1.0, 0.0, 0.0])];
    let mut s = 11u64;
    let mut next = || {
        s = s.wrapping_mul(6364136223846793005).wrapping_add(1442695040888963407);
        ((s >> 11) as f64 / (1u64 << 53) as f64) * 2.0 - 1.0
    };
    while out.len() < 6 {
        let x1 = [next(), next(), next()];
        let x2 = [next() + 1.5, next(), next()];
        let v = [next(), next(), next() + 2.0];
        out.push((x1, x2, v));
    }
    out
}

fn max_abs(m: &Mat12) -> f64 {
    m.amax()
}

/// With elastic fibers the local stiffness equals the elastic frame's with EA = E b h and the
/// grid's closed-form EIy, EIz (fiber_section docs) and the same GJ: two Gauss points integrate
/// the quadratic Bᵀ k_s B exactly. 1e-10 relative to max |K|. The mass matrices equal the
/// frame's with the continuum section (1e-12).
#[test]
fn elastic_fibers_equal_the_frame_with_closed_form_ea_ei() {
    for (ny, nz) in [(2, 3), (5, 9), (20, 20)] {
        let s = elastic_section(ny, nz);
        for n_gp in 2..=5 {
            let s = FiberSection { integration_points: n_gp, ..s };
            for (x1, x2, v) in geometries() {
                let fib = FiberBeam3d::new(x1, x2, v, s).unwrap();
                let frame = ElasticFrame3d::new(
                    x1,
                    x2,
                    v,
                    FrameSection {
                        e: 3e9,
                        g: s.material.shear_modulus(),
                        area: s.area(),
                        iy: s.iy_fibers(),
                        iz: s.iz_fibers(),
                        j: s.torsion_constant(),
                        density: 2000.0,
                        nonstructural_mass: 0.0,
                    },
                )
                .unwrap();
                let kf = fib.local_tangent(&[0.0; 12]).unwrap();
                let ke = frame.local_stiffness();
                assert!(
                    max_abs(&(kf - ke)) < 1e-10 * max_abs(&ke),
                    "ny={ny} nz={nz} gp={n_gp}: {:e}",
                    max_abs(&(kf - ke)) / max_abs(&ke)
                );
                // Mass: the frame's with the continuum section (Ip = b h (b² + h²)/12).
                let (b, h) = (s.width, s.height);
                let continuum = FrameSection { iy: b * h * h * h / 12.0, iz: h * b * b * b / 12.0, ..*frame.section() };
                let frame = ElasticFrame3d::new(x1, x2, v, continuum).unwrap();
                for kind in [MassKind::Consistent, MassKind::Lumped] {
                    let (mf, me) = (fib.local_mass(kind), frame.local_mass(kind));
                    assert!(max_abs(&(mf - me)) < 1e-12 * max_abs(&me), "{kind:?} mass");
                }
            }
        }
    }
}

/// A rigid motion u = c + θ × x (rotation θ at both nodes) strains no fiber: f_int = 0 to 1e-9
/// relative to |K||u|, also for a damaged committed state.
#[test]
fn rigid_body_motion_gives_no_force() {
    let mut out = ElementOutput::new(12);
    for (x1, x2, v) in geometries() {
        let mut el = FiberBeam3d::new(x1, x2, v, damage_section(Regularization::Hillerborg)).unwrap();
        // Damage some fibers first.
        let mut u = [0.0; 12];
        let ex = el.local_frame().axis(0);
        for k in 0..3 {
            u[6 + k] = 5e-4 * el.local_frame().length() * ex[k];
        }
        el.evaluate(&u, EvalRequest::Force, &mut out).unwrap();
        el.commit();
        assert!(el.committed_states().iter().any(|s| s.d_t > 0.0));
        let (c, th) = (Vector3::new(0.3, -0.2, 0.1), Vector3::new(0.01, -0.02, 0.015));
        let mut ur = u;
        for (n, x) in el.coords().iter().enumerate() {
            let t = c + th.cross(&Vector3::from(*x));
            for k in 0..3 {
                ur[6 * n + k] += t[k];
                ur[6 * n + 3 + k] += th[k];
            }
        }
        let mut base = ElementOutput::new(12);
        el.evaluate(&u, EvalRequest::ForceAndTangent, &mut base).unwrap();
        el.evaluate(&ur, EvalRequest::Force, &mut out).unwrap();
        let scale = base.k_t.amax() * 0.05;
        assert!((&out.f_int - &base.f_int).amax() < 1e-9 * scale, "rigid motion changed f_int");
    }
}

/// The tangent is the derivative of f_int: central differences (step 1e-9 of the displacement
/// scale) on a state that loads in tension and compression at once (bending with axial strain),
/// from a damaged committed state. Tolerance 1e-5 relative to max |K| (difference truncation).
#[test]
fn tangent_matches_finite_differences() {
    let (x1, x2, v) = geometries()[3];
    let mut el = FiberBeam3d::new(x1, x2, v, damage_section(Regularization::Hillerborg)).unwrap();
    let l = el.local_frame().length();
    let mut u: Vec<f64> = (0..12).map(|i| 2e-4 * l * ((i as f64) * 1.7).sin()).collect();
    let mut out = ElementOutput::new(12);
    el.evaluate(&u, EvalRequest::Force, &mut out).unwrap();
    el.commit();
    for x in u.iter_mut() {
        *x *= 1.3;
    }
    el.evaluate(&u, EvalRequest::ForceAndTangent, &mut out).unwrap();
    assert!(el.states.trial().iter().zip(el.states.committed()).any(|(t, c)| t.d_t > c.d_t), "no loading fiber");
    let k = out.k_t.clone();
    let h = 1e-9 * l;
    let mut fd = DMatrix::zeros(12, 12);
    for j in 0..12 {
        let (mut up, mut um) = (u.clone(), u.clone());
        up[j] += h;
        um[j] -= h;
        el.evaluate(&up, EvalRequest::Force, &mut out).unwrap();
        let fp = out.f_int.clone();
        el.evaluate(&um, EvalRequest::Force, &mut out).unwrap();
        fd.set_column(j, &((fp - &out.f_int) / (2.0 * h)));
    }
    let err = (&fd - &k).amax() / k.amax();
    assert!(err < 1e-5, "tangent vs finite differences: {err:e}");
}

/// One element of length L in tension, driven to full softening in uneven steps: with
/// `hillerborg_no_elastic` every fiber of both Gauss points dissipates G_f/L per volume, so the
/// element dissipates G_f b h (Hillerborg; exact for any step, material/mod.rs docs) to 1e-9;
/// with `hillerborg` G_f b h + f_t² b h L/(2E). The peak force is f_t b h (1e-12), the force at the
/// end is below 1e-6 of it, and the cell outputs report d_t → 1 with max = mean.
#[test]
fn tension_softening_dissipates_gf_times_area() {
    let p = params();
    let ft = p.e * p.eps0_t;
    for (reg, extra) in [(Regularization::HillerborgNoElastic, 0.0), (Regularization::Hillerborg, 1.0)] {
        let s = damage_section(reg);
        let l = 1.0;
        let mut el = FiberBeam3d::new([0.0; 3], [l, 0.0, 0.0], [0.0, 0.0, 1.0], s).unwrap();
        let mut out = ElementOutput::new(12);
        let mut peak: f64 = 0.0;
        let mut last = 0.0;
        for k in 1..=60 {
            let eps = p.eps0_t * (k as f64 / 10.0).powi(3);
            let mut u = [0.0; 12];
            u[6] = eps * l;
            el.evaluate(&u, EvalRequest::Force, &mut out).unwrap();
            el.commit();
            last = out.f_int[6];
            peak = peak.max(last);
        }
        let area = s.area();
        assert!((peak - ft * area).abs() < 1e-12 * ft * area, "peak {peak}");
        assert!(last.abs() < 1e-6 * ft * area, "residual force {last}");
        let want = p.gf_t * area + extra * ft * ft * area * l / (2.0 * p.e);
        let got = el.dissipated_energy();
        assert!((got - want).abs() < 1e-9 * want, "{reg:?}: {got} vs {want}");
        let mut vals = [0.0; 18];
        let mut u = [0.0; 12];
        u[6] = p.eps0_t * 216.0 * l;
        el.cell_output(&u, &AppliedLoads::default(), &mut vals).unwrap();
        assert!(vals[0] > 0.999 && (vals[0] - vals[1]).abs() < 1e-12, "{vals:?}");
        assert!((vals[17] - got).abs() < 1e-12 * got);
        assert!(vals[4] > 0.0 && vals[4] < 1e-6 * ft * area, "axial force {}", vals[4]);
    }
}

/// save_state → load_state into a fresh element restores the committed state: the same f_int
/// (exactly) and the same dissipated energy; wrong lengths are errors.
#[test]
fn checkpoint_round_trip() {
    let (x1, x2, v) = geometries()[4];
    let s = damage_section(Regularization::Hillerborg);
    let mut a = FiberBeam3d::new(x1, x2, v, s).unwrap();
    let l = a.local_frame().length();
    let u: Vec<f64> = (0..12).map(|i| 4e-4 * l * ((i as f64) * 0.9).cos()).collect();
    let mut out = ElementOutput::new(12);
    a.evaluate(&u, EvalRequest::Force, &mut out).unwrap();
    a.commit();
    assert!(a.dissipated_energy() > 0.0);
    let mut state = vec![0.0; a.n_state()];
    assert_eq!(state.len(), 4 * 2 * 24 + 1);
    a.save_state(&mut state).unwrap();
    let mut b = FiberBeam3d::new(x1, x2, v, s).unwrap();
    b.load_state(&state).unwrap();
    let u2: Vec<f64> = u.iter().map(|x| 0.7 * x).collect();
    let mut ob = ElementOutput::new(12);
    a.evaluate(&u2, EvalRequest::Force, &mut out).unwrap();
    b.evaluate(&u2, EvalRequest::Force, &mut ob).unwrap();
    assert_eq!(out.f_int, ob.f_int);
    assert_eq!(a.dissipated_energy(), b.dissipated_energy());
    assert!(b.load_state(&state[1..]).is_err());
    let el = FiberBeam3d::new(x1, x2, v, elastic_section(2, 2)).unwrap();
    assert_eq!(el.n_state(), 0);
}

/// Mass with a non-structural mass per length m_ns: a rigid translation gives
/// rᵀ M r = (ρ b h + m_ns) L for consistent and lumped mass, and the self weight sums to the
/// same mass times g (1e-12).
#[test]
fn mass_and_weight_include_nonstructural_mass() {
    let s = FiberSection { nonstructural_mass: 150.0, ..elastic_section(3, 3) };
    for (x1, x2, v) in geometries() {
        let el = FiberBeam3d::new(x1, x2, v, s).unwrap();
        let l = el.local_frame().length();
        let total = (2000.0 * s.area() + 150.0) * l;
        for kind in [MassKind::Consistent, MassKind::Lumped] {
            let mut m = DMatrix::zeros(0, 0);
            el.mass(kind, &mut m);
            let mut r = DVector::zeros(12);
            r[1] = 1.0;
            r[7] = 1.0;
            let got = (r.transpose() * &m * &r)[0];
            assert!((got - total).abs() < 1e-12 * total, "{kind:?}: {got} vs {total}");
        }
        let mut f = DVector::zeros(0);
        el.gravity_load([0.0, 0.0, -9.81], &mut f);
        let fz = f[2] + f[8];
        assert!((fz + 9.81 * total).abs() < 1e-12 * 9.81 * total);
    }
}

#[test]
fn bad_input_is_an_error() {
    let s = elastic_section(2, 2);
    let e = FiberBeam3d::new([1.0; 3], [1.0; 3], [0.0, 0.0, 1.0], s).unwrap_err();
    assert!(matches!(e, ElementError::ZeroLength { .. }));
    let e = FiberBeam3d::new([0.0; 3], [0.0, 0.0, 2.0], [0.0, 0.0, 1.0], s).unwrap_err();
    assert!(matches!(e, ElementError::BadOrientation { .. }));
    // hillerborg_no_elastic rejects elements longer than 2 E G_f / f_t² = 3.33 m.
    let e = FiberBeam3d::new(
        [0.0; 3],
        [4.0, 0.0, 0.0],
        [0.0, 0.0, 1.0],
        damage_section(Regularization::HillerborgNoElastic),
    )
    .unwrap_err();
    assert!(matches!(e, ElementError::Material { .. }), "{e}");
    assert!(e.to_string().contains("h = 4"), "{e}");
    let mut el = FiberBeam3d::new([0.0; 3], [1.0, 0.0, 0.0], [0.0, 0.0, 1.0], s).unwrap();
    let mut out = ElementOutput::new(12);
    assert!(el.evaluate(&[0.0; 11], EvalRequest::Force, &mut out).is_err());
    let mut u = [0.0; 12];
    u[2] = f64::INFINITY;
    assert!(el.evaluate(&u, EvalRequest::Force, &mut out).is_err());
    assert!(el.cell_output(&[0.0; 12], &AppliedLoads::default(), &mut [0.0; 13]).is_err());
}

/// Secant matrix: after uniform tensile damage d in every fiber, the axial secant stiffness is
/// (1 − d) E A / L (σ = (1 − d) E ε), while the consistent tangent is negative on the softening
/// branch. 1e-12 relative.
#[test]
fn secant_request_gives_the_damaged_elastic_stiffness() {
    let s = damage_section(Regularization::Hillerborg);
    let mut el = FiberBeam3d::new([0.0; 3], [1.0, 0.0, 0.0], [0.0, 0.0, 1.0], s).unwrap();
    let mut u = [0.0; 12];
    u[6] = 3.0 * params().eps0_t;
    let mut out = ElementOutput::new(12);
    el.evaluate(&u, EvalRequest::ForceAndSecant, &mut out).unwrap();
    let d = el.states.trial()[0].d_t;
    assert!(d > 0.1 && el.states.trial().iter().all(|t| (t.d_t - d).abs() < 1e-15));
    let want = (1.0 - d) * params().e * s.area();
    assert!((out.k_t[(6, 6)] - want).abs() < 1e-12 * want, "{} vs {want}", out.k_t[(6, 6)]);
    el.evaluate(&u, EvalRequest::ForceAndTangent, &mut out).unwrap();
    assert!(out.k_t[(6, 6)] < 0.0, "softening tangent {}", out.k_t[(6, 6)]);
}

/// An increment cut and retried gives the same result as the smaller increment taken directly:
/// element A evaluates a large increment that damages every fiber of the tensile face (and with
/// the tangent, as Newton does), is reverted, then takes the half increment and commits; element
/// B takes the half increment directly. Both then continue to the full increment. f_int, the
/// tangent, the committed states and the dissipated energy agree exactly (the evaluation is a
/// pure function of the committed state and u_e, module docs of `element`).
#[test]
fn a_cut_and_retried_increment_equals_the_direct_smaller_one() {
    let (x1, x2, v) = geometries()[3];
    let s = damage_section(Regularization::Hillerborg);
    let mut a = FiberBeam3d::new(x1, x2, v, s).unwrap();
    let mut b = FiberBeam3d::new(x1, x2, v, s).unwrap();
    let l = a.local_frame().length();
    let p = params();
    // Bending plus stretching, in global axes: 30 times the cracking strain at the full step.
    let u_full: Vec<f64> = (0..12).map(|i| 30.0 * p.eps0_t * l * ((i as f64) * 1.3 + 0.4).sin()).collect();
    let u_half: Vec<f64> = u_full.iter().map(|x| 0.5 * x).collect();
    let (mut oa, mut ob) = (ElementOutput::new(12), ElementOutput::new(12));
    a.evaluate(&u_full, EvalRequest::ForceAndTangent, &mut oa).unwrap();
    let trial_damage = a.states.trial().iter().fold(0.0f64, |m, st| m.max(st.d_t));
    assert!(trial_damage > 0.5, "the abandoned trial should damage: {trial_damage}");
    a.revert();
    for (el, o) in [(&mut a, &mut oa), (&mut b, &mut ob)] {
        el.evaluate(&u_half, EvalRequest::ForceAndTangent, o).unwrap();
        el.commit();
    }
    assert_eq!(oa.f_int, ob.f_int);
    assert_eq!(oa.k_t, ob.k_t);
    assert_eq!(a.committed_states(), b.committed_states());
    assert_eq!(a.dissipated_energy(), b.dissipated_energy());
    for (el, o) in [(&mut a, &mut oa), (&mut b, &mut ob)] {
        el.evaluate(&u_full, EvalRequest::ForceAndTangent, o).unwrap();
        el.commit();
    }
    assert_eq!(oa.f_int, ob.f_int);
    assert_eq!(oa.k_t, ob.k_t);
    assert_eq!(a.committed_states(), b.committed_states());
    assert_eq!(a.dissipated_energy(), b.dissipated_energy());
    assert!(a.dissipated_energy() > 0.0);
}

/// `damage_increment` of a fiber beam in uniform tension (every fiber of both Gauss points at
/// the axial strain ε = u/L, κ_t = ε for ν > 0: `material/uniaxial.rs`): 0 before any
/// evaluation; d_t(ε₁) of the law at h = L after a stretch to ε₁ (1e-15 absolute: the same
/// function); 0 after the commit and after a revert; d_t(ε₂) − d_t(ε₁) for a further stretch
/// to ε₂; 0 for unloading to ε₁/2 (the damage does not heal).
#[test]
fn damage_increment_is_the_rise_of_the_fibers_damage() {
    let p = params();
    let l = 1.0;
    let s = damage_section(Regularization::Hillerborg);
    let law = DamageParams { regularization: Regularization::Hillerborg, ..p }.for_element(l).unwrap();
    let d = |eps: f64| law.damage(crate::material::Side::Tension, eps).d;
    let mut el = FiberBeam3d::new([0.0; 3], [l, 0.0, 0.0], [0.0, 0.0, 1.0], s).unwrap();
    let mut out = ElementOutput::new(12);
    let mut stretch = |el: &mut FiberBeam3d, eps: f64| {
        let mut u = [0.0; 12];
        u[6] = eps * l;
        el.evaluate(&u, EvalRequest::Force, &mut out).unwrap();
    };
    assert_eq!(el.damage_increment(), 0.0);
    let (e1, e2) = (2.0 * p.eps0_t, 5.0 * p.eps0_t);
    stretch(&mut el, e1);
    assert!((el.damage_increment() - d(e1)).abs() < 1e-15 && d(e1) > 0.1, "{} vs {}", el.damage_increment(), d(e1));
    el.commit();
    assert_eq!(el.damage_increment(), 0.0);
    stretch(&mut el, e2);
    let want = d(e2) - d(e1);
    assert!((el.damage_increment() - want).abs() < 1e-15 && want > 0.1, "{} vs {want}", el.damage_increment());
    el.revert();
    assert_eq!(el.damage_increment(), 0.0);
    stretch(&mut el, 0.5 * e1);
    assert_eq!(el.damage_increment(), 0.0);
}
