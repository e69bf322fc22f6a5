//! The damage elements under IMPL-EX (`material::implex`, [`PointStates`]): a layered shell and
//! a fiber beam, each cracked by an implicit step, then stepped with the extrapolated history.
//!
//! ```text
//!   shell: one MITC4 quad (1.1 × 0.9 m, skewed), 0.2 m, 7 layers, the reference law;
//!          membrane strain and curvature that crack the lower layers in tension
//!   beam:  a 1.5 m fiber beam (0.3 × 0.5 m, 4 × 6 fibers), axial strain with bending
//! ```
use nalgebra::{DMatrix, DVector};

use super::*;
use crate::material::implex::SplitAt;
use crate::material::test_support::params;
use crate::material::{DamageParams, Split};

fn shell(split: Split) -> ShellQuad4 {
    let section = ShellSection {
        material: ShellMaterial::Damage(DamageParams { split, ..params() }),
        ..ShellSection::elastic(0.2, 1.0, 0.2, 2000.0)
    };
    ShellQuad4::new([[0.0, 0.0, 0.0], [1.1, 0.1, 0.0], [1.0, 0.9, 0.0], [-0.1, 0.8, 0.0]], &section).unwrap()
}

fn beam(split: Split) -> FiberBeam3d {
    let section = FiberSection {
        width: 0.3,
        height: 0.5,
        ny: 4,
        nz: 6,
        integration_points: 2,
        material: FiberMaterial::Damage(DamageParams { split, ..params() }),
        density: 2000.0,
        nonstructural_mass: 0.0,
        torsion_constant: None,
    };
    FiberBeam3d::new([0.0; 3], [1.5, 0.0, 0.0], [0.0, 0.0, 1.0], section).unwrap()
}

/// Node displacements that crack the element: a smooth field of size `scale` on every DOF.
fn cracking(n: usize, scale: f64) -> DVector<f64> {
    DVector::from_fn(n, |i, _| scale * (1.0 + 0.6 * ((i as f64) * 1.3).sin()) * if i % 6 < 3 { 1.0 } else { 0.3 })
}

fn force(el: &mut dyn Element, u: &DVector<f64>) -> DVector<f64> {
    let mut out = ElementOutput::new(el.n_dofs());
    el.evaluate(u.as_slice(), EvalRequest::Force, &mut out).unwrap();
    out.f_int.clone()
}

/// The element of `make` cracked by an implicit step to `u1`, then IMPL-EX on and stepped to
/// `u2`: the trial state is the implicit element's bit for bit (and its damage grew); the force
/// is the committed damage's (the first IMPL-EX step has no step behind it), homogeneous of
/// degree 1 in u (1e-12: no damage grows inside the step); the tangent equals central
/// differences of that force (step 1e-7 max|u|, 1e-6 of max|K|). Returns the IMPL-EX element.
fn first_step_uses_the_committed_damage(make: impl Fn() -> Box<dyn Element>, u1: &DVector<f64>) -> Box<dyn Element> {
    let (mut implicit, mut ex) = (make(), make());
    let n = implicit.n_dofs();
    for el in [&mut implicit, &mut ex] {
        force(el.as_mut(), u1);
        el.commit();
    }
    let cracked = committed_after(implicit.as_mut());
    ex.set_implex(Some(SplitAt::Frozen));
    ex.set_implex_step(0.01);
    let u2 = u1 * 1.4;
    let f = force(ex.as_mut(), &u2);
    force(implicit.as_mut(), &u2);
    let (a, b) = (committed_after(implicit.as_mut()), committed_after(ex.as_mut()));
    // The states bit for bit; the dissipated energy (the last value) summed point by point
    // rather than section by section: equal to round-off (1e-14 relative, a few ulps).
    let last = a.len() - 1;
    assert_eq!(a[..last], b[..last], "the trial states differ");
    assert!((a[last] - b[last]).abs() <= 1e-14 * a[last].abs(), "dissipated {} against {}", a[last], b[last]);
    assert!(a.last() > cracked.last(), "no damage grew from u1 to u2");
    let f2 = force(ex.as_mut(), &(&u2 * 2.0));
    let off = (&f2 - &f * 2.0).amax() / f2.amax();
    assert!(off <= 1e-12, "not homogeneous: {off:e}");
    let mut out = ElementOutput::new(n);
    ex.evaluate(u2.as_slice(), EvalRequest::ForceAndTangent, &mut out).unwrap();
    let k = out.k_t.clone();
    let h = 1e-7 * u2.amax();
    let mut kfd = DMatrix::zeros(n, n);
    for j in 0..n {
        let mut up = u2.clone();
        up[j] += h;
        let fp = force(ex.as_mut(), &up);
        up[j] -= 2.0 * h;
        kfd.set_column(j, &((fp - force(ex.as_mut(), &up)) / (2.0 * h)));
    }
    let err = (&kfd - &k).amax() / k.amax();
    assert!(err <= 1e-6, "tangent vs differences {err:e}");
    force(ex.as_mut(), &u2);
    ex
}

/// The element's state once its trial is committed (the committed state is then restored).
fn committed_after(el: &mut dyn Element) -> Vec<f64> {
    let mut before = vec![0.0; el.n_state()];
    el.save_state(&mut before).unwrap();
    el.commit();
    let mut after = vec![0.0; el.n_state()];
    el.save_state(&mut after).unwrap();
    el.load_state(&before).unwrap();
    after
}

#[test]
fn a_shell_steps_with_the_extrapolated_damage_and_checkpoints_its_history() {
    // Then a committed IMPL-EX step of 0.01 s and a checkpoint (6 values per layer point + 2):
    // a fresh element read from it extrapolates the same history for a step of 0.02 s (ratio
    // 2) and gives the same force bit for bit, which differs from the committed damage's.
    let u1 = cracking(24, 4e-4);
    let mut ex = first_step_uses_the_committed_damage(|| Box::new(shell(Split::Trace)), &u1);
    ex.set_implex_step(0.01);
    force(ex.as_mut(), &(&u1 * 1.4));
    ex.commit();
    assert_eq!(ex.n_state(), (6 + 3) * 4 * 15 + 2);
    let mut saved = vec![0.0; ex.n_state()];
    ex.save_state(&mut saved).unwrap();
    let mut fresh: Box<dyn Element> = Box::new(shell(Split::Trace));
    fresh.load_state(&saved).unwrap();
    // The split is the job's, not the checkpoint's: set after the restore, as the time history does.
    fresh.set_implex(Some(SplitAt::Frozen));
    let u3 = &u1 * 1.6;
    let frozen = force(ex.as_mut(), &u3);
    for el in [&mut ex, &mut fresh] {
        el.set_implex_step(0.02);
    }
    let (a, b) = (force(ex.as_mut(), &u3), force(fresh.as_mut(), &u3));
    assert_eq!(a, b);
    assert!((&a - &frozen).amax() > 1e-3 * a.amax(), "the extrapolation changed nothing");
    // With a committed IMPL-EX step behind, the split is frozen at its strains: the force is
    // linear in u (1e-12 of its size) and the tangent is symmetric (1e-12).
    let u4 = cracking(24, -2e-4).map(|x| x * x.abs().sqrt() * 50.0);
    let combo = force(ex.as_mut(), &(&u3 * 0.6 + &u4 * 1.7));
    let sum = force(ex.as_mut(), &u3) * 0.6 + force(ex.as_mut(), &u4) * 1.7;
    assert!((&combo - &sum).amax() <= 1e-12 * combo.amax(), "{:e}", (&combo - &sum).amax() / combo.amax());
    let mut out = ElementOutput::new(24);
    ex.evaluate(u3.as_slice(), EvalRequest::ForceAndTangent, &mut out).unwrap();
    assert!((&out.k_t - out.k_t.transpose()).amax() <= 1e-12 * out.k_t.amax());
}

#[test]
fn a_spectral_shell_and_fiber_beams_step_with_the_extrapolated_damage() {
    first_step_uses_the_committed_damage(|| Box::new(shell(Split::Spectral)), &cracking(24, 4e-4));
    for split in [Split::Trace, Split::Spectral] {
        first_step_uses_the_committed_damage(|| Box::new(beam(split)), &cracking(12, 3e-4));
    }
}
