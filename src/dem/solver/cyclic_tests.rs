//! Cyclic virtual tests: the protocol, elastic retracing, the envelope against the monotonic
//! curve, energy balance over loops, and the particle states kept for the XDMF output.
use super::tests::{balance, small_wall};
use super::*;
use crate::dem::mechanics::MechParams;

#[test]
fn protocol_branches_and_steps() {
    // Amplitudes [1, 2], c = 1, n = 4: 0 → 1 (span 2: ⌈4·1/2⌉ = 2 steps), 1 → −1 (4), −1 → 2
    // (⌈4·3/4⌉ = 3), 2 → −2 (4), −2 → 0 (⌈4·2/4⌉ = 2).
    assert_eq!(cyclic_protocol(&[1.0, 2.0], 1.0, 4), vec![(1.0, 2), (-1.0, 4), (2.0, 3), (-2.0, 4), (0.0, 2)]);
    // c = 0: unloading to zero only, n steps each way; no zero-length branch at the end.
    let p = cyclic_protocol(&[1.0, 2.0], 0.0, 4);
    assert_eq!(p.iter().map(|b| b.1).collect::<Vec<_>>(), vec![4, 4, 4, 4]);
    assert_eq!(p.iter().map(|b| b.0.abs()).collect::<Vec<_>>(), vec![1.0, 0.0, 2.0, 0.0]);
    // Bad protocols are errors naming the key.
    let bad = |t: VirtualTest| t.validate().unwrap_err().to_string();
    let axial = |amplitudes: Vec<f64>, ratio: f64, n: usize| VirtualTest::CyclicTensionCompression {
        amplitudes,
        compression_ratio: ratio,
        steps_per_half_cycle: n,
    };
    assert!(bad(axial(vec![], 1.0, 4)).contains("amplitudes"));
    assert!(bad(axial(vec![2.0, 1.0], 1.0, 4)).contains("do not decrease"));
    assert!(bad(axial(vec![1.0, -1.0], 1.0, 4)).contains("amplitudes"));
    assert!(bad(axial(vec![1.0], -0.5, 4)).contains("compression_ratio"));
    assert!(bad(axial(vec![1.0], 1.0, 0)).contains("steps"));
    let t: VirtualTest = toml::from_str("type = \"cyclic_shear\"\namplitudes = [1e-3, 2e-3]\nsteps_per_half_cycle = 10").unwrap();
    assert!(matches!(t, VirtualTest::CyclicShear { vertical_stress, preload_steps: 5, rotation: PlatenRotation::Fixed, .. } if vertical_stress == 1e6));
    assert!(toml::from_str::<VirtualTest>("type = \"cyclic_shear\"\namplitudes = [1e-3]\nsteps_per_half_cycle = 2\nbogus = 1").is_err());
}

/// Below the first crack the lattice is linear (no broken beam, hence no contact): every state of
/// two tension–compression cycles lies on the line σ = E ε of the first loading step, to 1e-8 of
/// the largest stress (round-off and the 1e-10 regularization), the lateral strain retraces too,
/// and the external work is the elastic energy ½ F δ of the current state (the trapezoid rule is
/// exact on a linear path), so it returns to 0 with the platen.
#[test]
fn undamaged_sample_retraces_its_loading_line() {
    let s = small_wall(2);
    let t = VirtualTest::CyclicTensionCompression { amplitudes: vec![1e-5, 2e-5], compression_ratio: 1.0, steps_per_half_cycle: 8 };
    let p = MechParams::default();
    let r = run_test(&s, &p, &t).unwrap();
    assert_eq!(r.end, TestEnd::Target);
    assert_eq!(r.stats.events, 0, "the amplitudes stay below the first crack");
    let e = r.derived.young_modulus;
    let nu = r.derived.poisson;
    let smax = r.curve.iter().fold(0.0f64, |m, c| m.max(c.stress.abs()));
    let wmax = r.curve.iter().fold(0.0f64, |m, c| m.max(c.external_work.abs()));
    let lmax = r.curve.iter().fold(0.0f64, |m, c| m.max(c.lateral_strain.abs()));
    assert!((smax - e * 2e-5).abs() <= 1e-8 * smax, "peak stress {smax} vs E a {}", e * 2e-5);
    for c in &r.curve {
        assert!((c.stress - e * c.strain).abs() <= 1e-8 * smax, "state {}: σ {} vs E ε {}", c.state, c.stress, e * c.strain);
        assert!((c.lateral_strain + nu * c.strain).abs() <= 1e-8 * lmax, "state {}", c.state);
        let elastic = 0.5 * c.stress * (s.width * p.t_z) * c.displacement;
        assert!((c.external_work - elastic).abs() <= 1e-8 * wmax, "state {}: W {} vs ½Fδ {}", c.state, c.external_work, elastic);
    }
    // The branch ends sit exactly on the protocol: +a1, −a1, +a2, −a2, 0.
    let ends: Vec<f64> = [1e-5, -1e-5, 2e-5, -2e-5, 0.0].into();
    for target in ends {
        assert!(r.curve.iter().any(|c| (c.strain - target).abs() < 1e-12 * 2e-5 + 1e-300), "no state at ε = {target}");
    }
    assert!(r.curve.last().unwrap().strain.abs() < 1e-20);
}

/// Tension cycles with unloading to zero strain (c = 0) on a small wall, against the monotonic
/// tension test of the same sample: damage only accumulates, so the cyclic envelope does not
/// exceed the monotonic peak. Energy balance over the loops within 1 % (the tolerance).
#[test]
fn cyclic_tension_envelope_and_energy_balance() {
    let s = small_wall(1);
    let p = MechParams::default();
    let mono = run_test(&s, &p, &VirtualTest::Tension { max_strain: 6e-4, steps: 30 }).unwrap();
    let cyc = VirtualTest::CyclicTensionCompression {
        amplitudes: vec![1e-4, 2e-4, 3e-4, 4e-4, 6e-4],
        compression_ratio: 0.0,
        steps_per_half_cycle: 10,
    };
    let r = run_test(&s, &p, &cyc).unwrap();
    let env = r.curve.iter().fold(0.0f64, |m, c| m.max(c.stress));
    let peak = mono.derived.peak_stress;
    let last = r.curve.last().unwrap();
    println!(
        "cyclic tension: end {:?}, envelope {:.4} MPa vs monotonic peak {:.4} MPa, events {} (monotonic {}), W_ext {:.3e}, imbalance {:.2e}",
        r.end,
        env / 1e6,
        peak / 1e6,
        r.stats.events,
        mono.stats.events,
        last.external_work,
        balance(last)
    );
    assert!(r.end.is_valid(), "{:?}", r.end);
    assert!(r.stats.events > 0, "the wall cracks");
    assert!(env <= peak * (1.0 + 1e-6), "cyclic envelope {env} above the monotonic peak {peak}");
    assert!(balance(last).abs() <= 0.01 * last.external_work, "imbalance {} of {}", balance(last), last.external_work);
}

fn cyclic_shear(amplitudes: Vec<f64>) -> VirtualTest {
    VirtualTest::CyclicShear {
        vertical_stress: 1e6,
        amplitudes,
        steps_per_half_cycle: 8,
        preload_steps: 3,
        rotation: PlatenRotation::Fixed,
    }
}

/// Cyclic shear under 1 MPa on a small wall, cycles of ±0.5 mm and ±1 mm: after cracking the
/// stones slide back and forth on the broken joints, so friction dissipates, both directions
/// carry load, the loop does not close on itself, and the particle states are kept for the
/// output (the top row moves with the platen).
#[test]
fn cyclic_shear_loops_dissipate() {
    let s = small_wall(3);
    let t = cyclic_shear(vec![0.5e-3, 1e-3]);
    let r = run_test_recording(&s, &MechParams::default(), &t, SolverOptions::default(), ParticleStates::Steps).unwrap();
    let last = r.curve.last().unwrap();
    println!(
        "cyclic shear: end {:?}, events {}, cutbacks {}, peak {:.3} MPa, friction {:.3e} J, W_ext {:.3e}, imbalance {:.2e}, {} particle states",
        r.end,
        r.stats.events,
        r.stats.cutbacks,
        r.derived.peak_stress / 1e6,
        last.dissipated[1],
        last.external_work,
        balance(last),
        r.particle_states.len()
    );
    assert_eq!(r.end, TestEnd::Target);
    assert!(last.displacement.abs() < 1e-15, "back to zero displacement");
    assert!(r.stats.events > 0 && last.dissipated[1] > 0.0, "cracks, then friction");
    assert!(r.curve.iter().any(|c| c.stress > 0.1e6) && r.curve.iter().any(|c| c.stress < -0.1e6));
    // Open loop: at zero displacement after the cycles the platen still carries a shear force
    // (residual stresses of slid joints), which it did not after the preload.
    let preload_end = r.curve.iter().take_while(|c| c.displacement == 0.0).last().unwrap();
    assert!(last.stress.abs() > 0.01e6 && preload_end.stress.abs() < last.stress.abs(), "{} vs {}", last.stress, preload_end.stress);
    let loading = r.curve.iter().filter(|c| c.kind == StateKind::Loading).count();
    assert!(r.particle_states.len() >= loading);
    assert!(r.particle_states.windows(2).all(|w| w[0].state < w[1].state));
    let end = r.particle_states.last().unwrap();
    assert_eq!(end.state, last.state);
    for &p in &s.boundary.top {
        assert!((end.dofs[p][0] - last.displacement).abs() < 1e-12, "top stone {p}");
    }
}

/// The energy balance over shear cycles (W_ext = stored + dissipated within 1 %) does NOT hold
/// yet: after cycles of ±0.5 mm and ±1 mm on this wall the imbalance is 3.3 % of W_ext (6.8 J of
/// 207 J; during the preload and the first loading it is below 0.1 %), growing on
/// every unloading–reloading of sliding contacts. Two likely causes, both in the contact law's
/// bookkeeping: the stored contact energy ½F_n²/k_n is exact only for a flat (strip) overlap
/// (for a corner overlap, S ∝ δ², it is ¾ of ∫F_n dδ), and the normal force along the chord
/// normal is not the gradient of the overlap area, so it does work around a closed path.
#[test]
#[ignore = "open: contact energy bookkeeping over load reversals (imbalance 3.3 % after two cycles)"]
fn cyclic_shear_energy_balance() {
    let s = small_wall(3);
    let r = run_test(&s, &MechParams::default(), &cyclic_shear(vec![0.5e-3, 1e-3])).unwrap();
    let last = r.curve.last().unwrap();
    assert!(balance(last).abs() <= 0.01 * last.external_work, "imbalance {} of {}", balance(last), last.external_work);
}
