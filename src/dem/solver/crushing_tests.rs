//! Crushing through the solver (the optional extension of [`crate::dem::mechanics::crushing`]):
//! closed forms on one and two bonded pairs, and the energy balance of the paper's wall.
use super::dofs::{DofControl::*, DofMap};
use super::*;
use crate::dem::mechanics::{Crushing, MechParams};
use crate::dem::sample::{GeometryOptions, Sample, SampleConfig};

fn column(n: usize) -> Sample {
    // n unit squares stacked: width 1, height n, seeds at the centres (arms 0, ℓ = 1, A = 1).
    let seeds: Vec<[f64; 2]> = (0..n).map(|k| [0.5, k as f64 + 0.5]).collect();
    let opts = GeometryOptions { thickness: 1.0, alpha: 0.8, facet_tolerance: 0.0, tiny_facets: Default::default() };
    Sample::from_seeds(1.0, n as f64, &seeds, &opts).unwrap()
}

fn crushing(stress: f64, energy: f64) -> MechParams {
    MechParams { crushing: Some(Crushing { stress, energy }), ..MechParams::default() }
}

fn balance(c: &CurvePoint) -> f64 {
    c.external_work - c.stored - c.dissipated.iter().sum::<f64>()
}

#[test]
fn bonded_pair_crushes_exactly_at_the_crushing_stress() {
    // Two unit squares, one beam (ℓ = 1, A = 1 m², Ē = 2.5e9), bottom and top bonded to the
    // platens. Compression by δ: ε = −δ, compressive stress Ē δ = σ_c = 5e6 Pa at δ* = 2e-3 m.
    // One step to δ = 5e-3 m: λ* = 0.4 exactly. Tension never fails (ε < 0). Tolerance 1e-9
    // relative (round-off of the solve).
    let s = column(2);
    let t = VirtualTest::Compression { max_strain: 2.5e-3, steps: 1 };
    let r = run_test(&s, &crushing(5e6, 2e4), &t).unwrap();
    assert_eq!(r.broken.len(), 1);
    assert_eq!(r.broken[0].mode, FailureModeTag::Crushing);
    let pre = &r.curve[r.broken[0].state];
    assert_eq!(pre.kind, StateKind::PreBreak);
    assert!((pre.displacement + 2e-3).abs() < 1e-9 * 2e-3, "{}", pre.displacement);
    assert!((pre.stress + 5e6).abs() < 1e-9 * 5e6, "{}", pre.stress);
    assert_eq!(pre.broken, [0, 0, 0, 0]);
    assert_eq!(r.curve.last().unwrap().broken, [1, 0, 0, 1]);
    // Without crushing (paper §2.1's model) the same test never breaks.
    let plain = run_test(&s, &MechParams::default(), &t).unwrap();
    assert!(plain.broken.is_empty());
}

#[test]
fn contact_plateaus_at_the_crushing_force_then_softens_with_its_energy() {
    // Two unit squares, beam cut at zero load, both stones bonded to their platens (every DOF
    // prescribed), the top one pushed down by δ. The overlap is a strip: S_r = δ, chord L = 1,
    // ℓ_c = D = 2/√π (unit squares), k_n = Ē L t_z/ℓ_c. Closed form (crushing module docs):
    //   F = k_n δ                                  up to δ_y = σ_c ℓ_c/Ē  (σ_c L t_z = 5e6 N)
    //   F = σ_c L t_z (1 − δ_p/δ_u),  δ_p = (k_n δ − σ_c L t_z)/(k_n − H),  H = σ_c L t_z/δ_u
    //   F = 0 from δ = δ_u = 2 G_c/σ_c = 8e-3 m on;
    // dissipated by crushing ∫F_y dδ_p = G_c L t_z = 2e4 J at the end. The reaction is the contact
    // force (up to the regularization, 1e-10 relative): tolerance 1e-6 of σ_c L t_z; energy
    // 1e-6 relative. The balance W_ext = stored + dissipated (trapezoid of the reaction over
    // 50 steps across two kinks) within 1 % of W_ext.
    let (sc, gc) = (5e6, 2e4);
    let s = column(2);
    let p = crushing(sc, gc);
    let map = DofMap::new(&s, [[Prescribed; 3], [Prescribed; 3]]).unwrap();
    let model = Model::new(&s, &p, map).unwrap();
    let zero = LoadPoint { prescribed: vec![0.0; 6], forces: vec![] };
    let mut solver = Solver::new(model, SolverOptions::default(), zero).unwrap();
    solver.start().unwrap();
    solver.break_and_relax(0).unwrap();
    let push = LoadPoint { prescribed: vec![0.0, 0.0, 0.0, 0.0, -1e-2, 0.0], forces: vec![] };
    solver.run_stage(&push, 50, None).unwrap();
    let l_c = 2.0 / std::f64::consts::PI.sqrt();
    let k_n = 2.5e9 / l_c;
    let (f_y, d_u) = (sc, 2.0 * gc / sc);
    let h = f_y / d_u;
    let want = |d: f64| {
        let dp = ((k_n * d - f_y) / (k_n - h)).max(0.0);
        if d <= f_y / k_n {
            k_n * d
        } else if dp < d_u {
            f_y * (1.0 - dp / d_u)
        } else {
            0.0
        }
    };
    let mut peak: f64 = 0.0;
    for st in solver.states() {
        let d = -st.platen[1][1];
        let f = -st.platen_force[1][1];
        peak = peak.max(f);
        assert!((f - want(d)).abs() < 1e-6 * f_y, "δ = {d:e}: F = {f:e}, closed form {:e}", want(d));
    }
    // The plateau: never above σ_c L t_z; the states on the 2e-4 m grid straddle the kink at
    // δ_y = 2.257e-3 m, where the closed form gives 0.975 σ_c L t_z on either side.
    assert!(peak <= f_y * (1.0 + 1e-9) && peak > 0.97 * f_y, "largest recorded force {peak:e}");
    let last = solver.states().last().unwrap();
    assert!((last.dissipated[3] - gc).abs() < 1e-6 * gc, "crushing energy {:e}", last.dissipated[3]);
    let w = last.external_work;
    let imbalance = w - last.stored - last.dissipated.iter().sum::<f64>();
    assert!(imbalance.abs() < 1e-2 * w, "W_ext {w:e}, imbalance {imbalance:e}");
}

#[test]
fn paper_wall_with_crushing_peaks_and_balances_energy() {
    // The paper's wall (seed 1, Table 1 set) with σ_c = 3 MPa, G_c = 2 kJ/m²: a compressive peak
    // below σ_c·(1 + ...) is reached and the load then falls (loss of load or a post-peak
    // collapse); crushing beams are counted; W_ext = stored + dissipated within 1 %.
    let s = Sample::build(&SampleConfig::paper_wall(1)).unwrap();
    let t = VirtualTest::Compression { max_strain: 4e-3, steps: 40 };
    let r = run_test(&s, &crushing(3e6, 2e3), &t).unwrap();
    let last = r.curve.last().unwrap();
    println!(
        "peak {:.3} MPa at ε {:.2e}; end {:?}; broken {:?}; energy W {:.4e} stored {:.4e} diss {:?} imbalance {:.3e}",
        r.derived.peak_stress / 1e6,
        r.derived.strain_at_peak,
        r.end,
        last.broken,
        last.external_work,
        last.stored,
        last.dissipated,
        balance(last)
    );
    assert!(r.end.is_valid() && !matches!(r.end, TestEnd::Target), "the test ends after a peak: {:?}", r.end);
    assert!(last.stress.abs() < 0.9 * r.derived.peak_stress, "the load fell after the peak");
    assert!(last.broken[3] > 0, "beams crushed");
    assert!(balance(last).abs() <= 0.01 * last.external_work, "imbalance {}", balance(last));
}

#[test]
fn paper_wall_sample_continues_past_its_old_stop() {
    // jobs/wall-compression.toml's sample 3 (seed 4; σ_c = 2.2 MPa, G_c = 1 kJ/m²), in the job's
    // steps of Δε = 5e-5, to ε = 3e-3. Without continuation Newton's iterations find no
    // equilibrium down to 2⁻¹⁰ of a step near the peak (crushing contacts alternating on their
    // softening branch): the test ends `Failed` (measured: at ε = 1.10e-3), the curve short of
    // a post-peak. With continuation the equilibria past that point are found and the test
    // goes on to a loss of load (measured: at ε = 1.78e-3, 4 continuations), with
    // W_ext = stored + dissipated within 1 % of W_ext (measured: 0.11 %).
    let s = Sample::build(&SampleConfig::paper_wall(4)).unwrap();
    let p = crushing(2.2e6, 1e3);
    let t = VirtualTest::Compression { max_strain: 3e-3, steps: 60 };
    let off = SolverOptions { continuation: false, ..Default::default() };
    let before = run_test_with(&s, &p, &t, off).unwrap();
    assert!(
        matches!(before.end, TestEnd::Failed { .. } | TestEnd::Collapse { .. }),
        "the stop near the peak: {:?}",
        before.end
    );
    let stop = before.curve.last().unwrap().strain;
    let r = run_test(&s, &p, &t).unwrap();
    let last = r.curve.last().unwrap();
    println!(
        "without continuation: {:?} at ε = {stop:e}; with: {:?} at ε = {:e}, {:?}",
        before.end, r.end, last.strain, r.stats
    );
    assert!(matches!(r.end, TestEnd::LossOfLoad | TestEnd::Target), "{:?}", r.end);
    assert!(r.stats.continuations >= 1, "{:?}", r.stats);
    assert!(last.strain < stop - 2e-4, "continued from ε = {stop:e} to {:e}", last.strain);
    assert!(balance(last).abs() <= 0.01 * last.external_work, "imbalance {} of {}", balance(last), last.external_work);
}

#[test]
fn crushed_contacts_keep_the_energy_balance_far_past_the_peak() {
    // jobs/wall-compression.toml's sample 4 (seed 5; σ_c = 2.2 MPa, G_c = 1 kJ/m², Δε = 5e-5)
    // to ε = 3e-3, far past its peak, with deeply crushed corner overlaps. When the wedge energy
    // of an overlap was counted at its full elastic value on a crushed contact (whose force, and
    // so whose moment, crushing had reduced), this sample ended with stored + dissipated 356 J
    // (13 %) above the work done. Before loading steps were checked for snaps inside them
    // (`stage.rs`, "Snaps inside a step") it ended 1.3 % short, two steps carrying 25 J and
    // 36 J of released energy; with the crushed force at the overlap centroid and the wedge
    // energy scaled by (F/F_el)² it ended 0.56 % short (seeds 1–8: 0.46–0.91 %, a remainder that
    // did not fall with the step: the crushed contacts' moment). Asserted: stored ≤ W_ext + 1 %
    // at every state (dissipation is never negative), and the balance at the end within 1 % of
    // W_ext (measured with the layer law of `mechanics::crushing`: −0.07 %; seeds 1–16 of the
    // job: −0.07 to +0.24 %).
    let s = Sample::build(&SampleConfig::paper_wall(5)).unwrap();
    let t = VirtualTest::Compression { max_strain: 3e-3, steps: 60 };
    let r = run_test(&s, &crushing(2.2e6, 1e3), &t).unwrap();
    let last = r.curve.last().unwrap();
    let w_end = last.external_work;
    assert!(w_end > 0.0);
    for c in &r.curve {
        assert!(
            c.stored <= c.external_work + 0.01 * w_end,
            "state at ε {:e}: stored {:e} J, W_ext {:e} J",
            c.strain,
            c.stored,
            c.external_work
        );
    }
    println!(
        "seed 5: {} states, end {:?}, W_ext {w_end:.4e} J, imbalance {:.3e} J, {:?}",
        r.curve.len(),
        r.end,
        balance(last),
        r.stats
    );
    assert!(balance(last).abs() <= 0.01 * w_end, "imbalance {:e} J of W_ext {w_end:e} J", balance(last));
}

#[test]
fn continuation_with_updates_in_place_matches_the_woodbury_path() {
    // The sample above with CHOLMOD's factor updated in place: the continuation's shifted
    // operators are then a Woodbury operator of their own, and the updatable factor is
    // refactorized on the way back (continuation.rs). Another factorization, so another round-off under Newton's
    // tolerance (1e-8 of the largest force): the same end, at least one continuation, the energy
    // balance within 1 % of W_ext, and the peak within 1e-4 of the default path's (measured
    // below).
    let s = Sample::build(&SampleConfig::paper_wall(4)).unwrap();
    let p = crushing(2.2e6, 1e3);
    let t = VirtualTest::Compression { max_strain: 3e-3, steps: 60 };
    let with = |factor_updates| run_test_with(&s, &p, &t, SolverOptions { factor_updates, ..Default::default() });
    let (woodbury, updown) = (with(FactorUpdates::Woodbury).unwrap(), with(FactorUpdates::InPlace).unwrap());
    let last = updown.curve.last().unwrap();
    let (a, b) = (woodbury.derived.peak_stress, updown.derived.peak_stress);
    println!("peaks {a} and {b} ({:e}); ends {:?} and {:?}; {:?}", (b - a) / a, woodbury.end, updown.end, updown.stats);
    assert_eq!(std::mem::discriminant(&updown.end), std::mem::discriminant(&woodbury.end), "{:?}", updown.end);
    assert!(updown.stats.continuations >= 1, "{:?}", updown.stats);
    assert!(((b - a) / a).abs() <= 1e-4, "peaks {a} and {b}");
    assert!(balance(last).abs() <= 0.01 * last.external_work, "imbalance {} of {}", balance(last), last.external_work);
}
