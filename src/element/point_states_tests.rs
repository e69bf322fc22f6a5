//! Tests of [`PointStates`]: the implicit store as before, the IMPL-EX history through steps,
//! commits and checkpoints.
use super::*;
use crate::material::implex::SplitAt;
use crate::material::{DamageParams, Regularization, Side, Split};

fn law() -> PointLaw {
    law_with(Split::Trace)
}

fn law_with(split: Split) -> PointLaw {
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
        split,
    }
    .for_element(0.1)
    .unwrap()
}

/// A state with κ_t = k ε₀ᵗ (d_t = d(κ_t)), κ_c at its threshold.
fn with_kappa_t(law: &PointLaw, k: f64) -> DamageState {
    let kappa_t = k * law.eps0_t();
    DamageState { kappa_t, kappa_c: law.eps0_c(), d_t: law.damage(Side::Tension, kappa_t).d, d_c: 0.0 }
}

/// Writes `trial` (and with IMPL-EX the strains `10⁻⁴ (k + 1)`, k the value's index) as the
/// evaluation of a step would, then commits.
fn step(s: &mut PointStates, trial: &[DamageState], dissipation: f64) {
    let u = s.for_update();
    u.trial.copy_from_slice(trial);
    if let Some(x) = u.implex {
        for (k, e) in x.trial_strains.iter_mut().enumerate() {
            *e = 1e-4 * (k + 1) as f64;
        }
    }
    s.set_trial_dissipation(dissipation);
    s.commit();
}

/// The extrapolated histories an evaluation reads (none: implicit).
fn extrapolated(s: &mut PointStates) -> Option<Vec<DamageState>> {
    s.for_update().implex.map(|x| x.extrapolated.to_vec())
}

/// The committed strains an evaluation freezes the split at (none: not known, or implicit).
fn frozen_at(s: &mut PointStates) -> Option<Vec<f64>> {
    s.for_update().implex.and_then(|x| x.strains.map(|e| e.to_vec()))
}

#[test]
fn the_implicit_store_keeps_its_layout() {
    // 4 values per point and the dissipated energy; a round trip restores it exactly; no
    // extrapolated history is handed to the evaluations.
    let law = law();
    let mut s = PointStates::new(3, 3);
    step(&mut s, &[with_kappa_t(&law, 2.0); 3], 0.5);
    assert_eq!(s.n_state(), 4 * 3 + 1);
    let mut out = vec![0.0; s.n_state()];
    s.save(&mut out).unwrap();
    assert_eq!(out[12], 0.5);
    let mut back = PointStates::new(3, 3);
    back.load(&out).unwrap();
    assert_eq!(back, s);
    assert!(extrapolated(&mut back).is_none());
    assert!(back.load(&out[..5]).is_err());
    assert_eq!(PointStates::new(0, 3).n_state(), 0);
}

#[test]
fn the_implex_history_follows_the_steps_and_survives_a_checkpoint() {
    // Steps of 0.01 s then 0.02 s: κ_t = 2, 3 ε₀ after them; the third step of 0.01 s
    // extrapolates with the ratio 0.01/0.02 to κ̃_t = 3.5 ε₀ (exact in binary to 1e-15). The
    // first step extrapolates nothing (no step behind) and freezes the split nowhere (no
    // committed strain); the next ones at the strains of the last commit. A checkpoint read into
    // a fresh (implicit) store switches IMPL-EX on with the same history and gives the same
    // extrapolation.
    let law = law();
    let mut s = PointStates::new(2, 3);
    s.set_implex(Some(SplitAt::Frozen));
    assert_eq!(s.n_state(), (6 + 3) * 2 + 2);
    s.set_implex_step(&law, 0.01);
    assert_eq!(extrapolated(&mut s).unwrap(), &[DamageState::virgin(&law); 2]);
    assert_eq!(frozen_at(&mut s), None);
    step(&mut s, &[with_kappa_t(&law, 2.0); 2], 0.1);
    s.set_implex_step(&law, 0.02);
    // κ_{n−1} = ε₀ (the virgin state clamped), κ_n = 2 ε₀, ratio 2: κ̃ = 4 ε₀.
    let x = extrapolated(&mut s).unwrap()[0];
    assert!((x.kappa_t - 4.0 * law.eps0_t()).abs() <= 1e-15 * x.kappa_t, "{x:?}");
    assert_eq!(frozen_at(&mut s).unwrap(), (1..=6).map(|k| 1e-4 * k as f64).collect::<Vec<_>>());
    step(&mut s, &[with_kappa_t(&law, 3.0); 2], 0.2);
    let mut out = vec![0.0; s.n_state()];
    s.save(&mut out).unwrap();
    assert_eq!(&out[9..14], &[2e-4, 2e-4, 2e-4, 2e-4, 0.02]);
    assert_eq!(&out[14..], &(1..=6).map(|k| 1e-4 * k as f64).collect::<Vec<_>>()[..]);
    let mut back = PointStates::new(2, 3);
    back.load(&out).unwrap();
    assert!(back.is_implex());
    // The split is the job's, not the checkpoint's: set after the restore, as the time history does.
    back.set_implex(Some(SplitAt::Frozen));
    for st in [&mut s, &mut back] {
        st.set_implex_step(&law, 0.01);
    }
    assert_eq!(back, s);
    assert_eq!(frozen_at(&mut back), frozen_at(&mut s));
    let x = extrapolated(&mut s).unwrap()[1];
    assert!((x.kappa_t - 3.5 * law.eps0_t()).abs() <= 1e-15 * x.kappa_t, "{x:?}");
    assert_eq!(x.d_t, law.damage(Side::Tension, x.kappa_t).d);
    // The split taken at the step's strain: no strain frozen. A revert keeps the history;
    // IMPL-EX off drops it and the layout shrinks.
    s.set_implex(Some(SplitAt::Current));
    assert_eq!(frozen_at(&mut s), None);
    s.revert();
    assert_eq!(s.committed(), &[with_kappa_t(&law, 3.0); 2]);
    s.set_implex(None);
    assert_eq!(s.n_state(), 4 * 2 + 1);
    assert!(extrapolated(&mut s).is_none());
}

#[test]
fn an_implicit_state_read_under_implex_has_no_step_behind_it() {
    // A gravity state (implicit layout) read by an IMPL-EX store: κ_{n−1} = κ_n, so the first
    // step's history is the committed one whatever its size.
    let law = law();
    let mut implicit = PointStates::new(1, 3);
    step(&mut implicit, &[with_kappa_t(&law, 5.0)], 1.0);
    let mut out = vec![0.0; implicit.n_state()];
    implicit.save(&mut out).unwrap();
    let mut s = PointStates::new(1, 3);
    s.set_implex(Some(SplitAt::Frozen));
    s.load(&out).unwrap();
    assert!(s.is_implex());
    s.set_implex_step(&law, 0.01);
    assert_eq!(extrapolated(&mut s).unwrap(), &[with_kappa_t(&law, 5.0)]);
    assert_eq!(frozen_at(&mut s), None);
    assert_eq!(s.dissipated(), 1.0);
}

#[test]
fn the_kept_secants_give_the_material_updates_response() {
    // A plane-stress point cracked by an implicit step, then IMPL-EX steps: every evaluation's
    // stress and tangent equal `material::implex::update`'s at the same extrapolated history
    // and committed strain bit for bit, the secant kept from the step's first evaluation and
    // recomputed when the step (hence the extrapolation) or the committed strain changes; once
    // settled, the trial state is its state (the implicit update), and until then the
    // committed one.
    use crate::material::{implex, plane_stress, PlaneStress};
    use nalgebra::Vector3;
    let law = law();
    let eval = |l: &PointLaw, e: &Vector3<f64>, s: &DamageState| plane_stress::update(l, e, s);
    let mut s = PointStates::new(1, 3);
    let e0 = Vector3::new(3e-4, -0.5e-4, 1e-4);
    s.for_update().respond(&law, 0, &e0, eval);
    s.commit();
    s.set_implex(Some(SplitAt::Frozen));
    let mut at = e0;
    for (k, h) in [0.01, 0.01, 0.02, 0.005].into_iter().enumerate() {
        s.set_implex_step(&law, h);
        let strains = [e0 * (1.1 + 0.2 * k as f64), Vector3::new(-2e-4, 1e-4, 3e-4), e0 * 0.5];
        for e in &strains {
            let got = s.for_update().respond(&law, 0, e, eval);
            let x = extrapolated(&mut s).unwrap()[0];
            let frozen = frozen_at(&mut s).map(|v| Vector3::from_column_slice(&v));
            assert_eq!(frozen.is_some(), k > 0, "step {k}");
            let want = implex::update::<3, PlaneStress>(&law, e, &s.committed()[0], &x, frozen.as_ref());
            assert_eq!((got.stress, got.tangent), (want.stress, want.tangent), "step {k}");
            assert_eq!(s.trial()[0], s.committed()[0], "step {k}: settled before its time");
            s.settle(|_, e, c| {
                let r = plane_stress::update(&law, &Vector3::from_column_slice(e), c);
                (r.state, r.dissipation)
            });
            assert_eq!(s.trial()[0], want.state, "step {k}");
        }
        s.for_update().respond(&law, 0, &strains[0], eval);
        s.settle(|_, e, c| (plane_stress::update(&law, &Vector3::from_column_slice(e), c).state, 0.0));
        s.commit();
        assert_ne!(at, strains[0]);
        at = strains[0];
        assert_eq!(frozen_at(&mut s).unwrap(), at.as_slice());
    }
}

#[test]
fn an_undamaged_point_under_the_current_split_is_linear_and_matches_the_law() {
    // d̃_t = d̃_c = 0 under IMPL-EX with the split at the step's strain: the first evaluation of
    // a step is the law's (bit for bit); the others are C ε with its tangent, equal to the law's
    // stress in exact arithmetic (σ = C₀ ε at equal damage for both splits) and here within
    // 1e-13 of its norm (round-off of the principal decomposition, a few ulps of each term),
    // across tension, compression and shear, above the damage threshold too (the history is
    // frozen within the step). A cracked point (d̃_t > d̃_c) keeps the law's response bit for bit.
    use crate::material::{implex, plane_stress, PlaneStress};
    use nalgebra::Vector3;
    let strains = [
        Vector3::new(3e-5, -1e-5, 2e-5),
        Vector3::new(-4e-5, 1e-5, -3e-5),
        Vector3::new(1e-5, 2e-5, -6e-5),
        Vector3::new(3e-4, -2e-4, 1e-4),
        Vector3::new(-5e-4, -1e-4, 0.0),
    ];
    for split in [Split::Trace, Split::Spectral] {
        let law = law_with(split);
        let eval = |l: &PointLaw, e: &Vector3<f64>, s: &DamageState| plane_stress::update(l, e, s);
        let mut s = PointStates::new(2, 3);
        step(&mut s, &[DamageState::default(), with_kappa_t(&law, 3.0)], 0.0);
        s.set_implex(Some(SplitAt::Current));
        s.set_implex_step(&law, 0.01);
        let x = extrapolated(&mut s).unwrap();
        assert_eq!((x[0].d_t, x[0].d_c), (0.0, 0.0), "{split:?}: the virgin point");
        assert!(x[1].d_t > x[1].d_c, "{split:?}: the cracked point");
        for (k, e) in strains.iter().enumerate() {
            for j in 0..2 {
                let got = s.for_update().respond(&law, j, e, eval);
                let want = implex::update::<3, PlaneStress>(&law, e, &s.committed()[j], &x[j], None);
                if j == 1 || k == 0 {
                    assert_eq!(
                        (got.stress, got.tangent),
                        (want.stress, want.tangent),
                        "{split:?} point {j} strain {k}"
                    );
                } else {
                    let err = (got.stress - want.stress).norm() / want.stress.norm();
                    assert!(err < 1e-13, "{split:?} strain {k}: relative difference {err:e}");
                    assert!((got.tangent - want.tangent).norm() < 1e-13 * want.tangent.norm(), "{split:?} strain {k}");
                }
            }
        }
    }
}
