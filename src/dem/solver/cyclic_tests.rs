//! Cyclic virtual tests: the protocol, elastic retracing, the envelope against the monotonic
//! curve, energy balance over loops, and the particle states kept for the XDMF output.
use super::tests::{balance, column, small_wall};
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
    let t: VirtualTest =
        toml::from_str("type = \"cyclic_shear\"\namplitudes = [1e-3, 2e-3]\nsteps_per_half_cycle = 10").unwrap();
    assert!(
        matches!(t, VirtualTest::CyclicShear { vertical_stress, preload_steps: 5, rotation: PlatenRotation::Fixed, .. } if vertical_stress == 1e6)
    );
    assert!(toml::from_str::<VirtualTest>(
        "type = \"cyclic_shear\"\namplitudes = [1e-3]\nsteps_per_half_cycle = 2\nbogus = 1"
    )
    .is_err());
}

/// Below the first crack the lattice is linear (no broken beam, hence no contact): every state of
/// two tension–compression cycles lies on the line σ = E ε of the first loading step, to 1e-8 of
/// the largest stress (round-off and the 1e-10 regularization), the lateral strain retraces too,
/// and the external work is the elastic energy ½ F δ of the current state (the trapezoid rule is
/// exact on a linear path), so it returns to 0 with the platen.
#[test]
fn undamaged_sample_retraces_its_loading_line() {
    let s = small_wall(2);
    let t = VirtualTest::CyclicTensionCompression {
        amplitudes: vec![1e-5, 2e-5],
        compression_ratio: 1.0,
        steps_per_half_cycle: 8,
    };
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
        assert!(
            (c.stress - e * c.strain).abs() <= 1e-8 * smax,
            "state {}: σ {} vs E ε {}",
            c.state,
            c.stress,
            e * c.strain
        );
        assert!((c.lateral_strain + nu * c.strain).abs() <= 1e-8 * lmax, "state {}", c.state);
        let elastic = 0.5 * c.stress * (s.width * p.t_z) * c.displacement;
        assert!(
            (c.external_work - elastic).abs() <= 1e-8 * wmax,
            "state {}: W {} vs ½Fδ {}",
            c.state,
            c.external_work,
            elastic
        );
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
/// exceed the monotonic peak. Energy balance over the loops within 1 % (the issue's tolerance).
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
    let r =
        run_test_recording(&s, &MechParams::default(), &t, SolverOptions::default(), ParticleStates::Steps).unwrap();
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
    assert!(
        last.stress.abs() > 0.01e6 && preload_end.stress.abs() < last.stress.abs(),
        "{} vs {}",
        last.stress,
        preload_end.stress
    );
    let loading = r.curve.iter().filter(|c| c.kind == StateKind::Loading).count();
    assert!(r.particle_states.len() >= loading);
    assert!(r.particle_states.windows(2).all(|w| w[0].state < w[1].state));
    let end = r.particle_states.last().unwrap();
    assert_eq!(end.state, last.state);
    for &p in &s.boundary.top {
        assert!((end.dofs[p][0] - last.displacement).abs() < 1e-12, "top stone {p}");
    }
}

/// The energy balance over shear cycles (cycles of ±0.5 mm and ±1 mm on a small wall):
/// W_ext = stored + dissipated within 1 % of W_ext (issue 3's acceptance tolerance). The stored
/// contact energy includes the wedge energy of rocking joints ([`crate::dem::mechanics::contact`],
/// "Stored energy"): counted as `F_n²/(2k_n)` alone the imbalance was 3.3 %; with it 0.83 %
/// (0.72 % with contact events, which resolve the stick–slip kinks of the trapezoid rule).
#[test]
fn cyclic_shear_energy_balance() {
    let s = small_wall(3);
    let r = run_test(&s, &MechParams::default(), &cyclic_shear(vec![0.5e-3, 1e-3])).unwrap();
    let last = r.curve.last().unwrap();
    assert!(balance(last).abs() <= 0.01 * last.external_work, "imbalance {} of {}", balance(last), last.external_work);
}

/// A joint rocked one way, back, the other way and back (two stones, one reversal in each
/// direction), against its closed form. Column of two unit squares on the fixed bottom platen;
/// the top platen presses with the force `N = k_n δ̄` (vertical DOF force-controlled), the beam
/// between the stones is cut, and the contact takes the load: a strip overlap of depth `δ̄`,
/// `k_n = Ē t_z L/ℓ_c`, L = 1, ℓ_c the common diameter. Then the top platen turns the upper stone
/// by `Θ` about the middle of the joint (`U_x = −Θ`: the platen turns about `(W/2, H)`, one unit
/// above the joint). The overlap becomes a wedge `δ(s) = δ̄ − Θ s`; the normal force, applied at
/// the overlap centroid, has the moment `k_n L² Θ/12` about the joint's middle, so (Winkler
/// layer, by hand)
///
/// ```text
///   E_stored(Θ) = ½ k_n δ̄² + k_n L² Θ²/24,   W_ext(Θ) − W_ext(0) = k_n L² Θ²/24,   no dissipation
/// ```
///
/// (the joint does not open, `Θ L/2 < δ̄`, and the slip at the contact point is `O(Θ δ̄)`, so it
/// sticks with a negligible tangential energy). The wedge term is 7.7 % of the energy at
/// `Θ = δ̄ = 1e-4`: counting only `F_n²/(2k_n)` unbalances the rocked states by as much and
/// balances again when the joint is back flat. The moment is linear in `Θ`, so the trapezoid
/// external work is exact. Tolerance 1e-3 relative: the geometric corrections are `O(δ̄/L)`,
/// `O(Θ)` and `O(Θ²/δ̄)` (finite rotation of the outline), each ≤ 1e-4.
#[test]
fn rocking_joint_stores_the_wedge_energy() {
    use super::dofs::{DofControl::*, DofMap};
    let s = column(2);
    let p = MechParams::default();
    let map = DofMap::new(&s, [[Prescribed; 3], [Prescribed, Force, Prescribed]]).unwrap();
    let model = Model::new(&s, &p, map).unwrap();
    let (d_i, d_j) = (s.particles[0].diameter, s.particles[1].diameter);
    let k_n = p.e_bar * p.t_z * 1.0 / (2.0 / (1.0 / d_i + 1.0 / d_j));
    let (db, th) = (1e-4, 1e-4);
    let load = |ux: f64, n: f64, th: f64| LoadPoint { prescribed: vec![0.0, 0.0, 0.0, ux, th], forces: vec![-n] };
    let mut solver = Solver::new(model, SolverOptions::default(), load(0.0, 0.0, 0.0)).unwrap();
    solver.start().unwrap();
    solver.run_stage(&load(0.0, k_n * db, 0.0), 2, None).unwrap();
    solver.break_and_relax(0).unwrap();
    let flat = solver.states().len() - 1;
    for target in [th, 0.0, -th, 0.0] {
        solver.run_stage(&load(-target, k_n * db, target), 4, None).unwrap();
    }
    let st0 = solver.states()[flat].clone();
    let mut rocked = 0;
    for st in &solver.states()[flat..] {
        let theta = st.platen[1][2];
        let wedge = k_n * theta * theta / 24.0;
        let want = 0.5 * k_n * db * db + wedge;
        let work = st.external_work - st0.external_work;
        let dissipated: f64 = st.dissipated.iter().zip(&st0.dissipated).map(|(a, b)| a - b).sum();
        println!("Θ {theta:+.2e}: ΔW {work:.6e}, stored {:.6e}, closed form {want:.6e}", st.stored);
        assert_eq!(st.contacts, 1);
        assert!((st.platen[1][1] + db).abs() <= 1e-3 * db, "δ̄ {}", -st.platen[1][1]);
        assert!((st.stored - want).abs() <= 1e-3 * want, "Θ = {theta}: stored {} vs {want}", st.stored);
        assert!((work - wedge).abs() <= 1e-3 * want, "Θ = {theta}: ΔW_ext {work} vs {wedge}");
        assert!(dissipated.abs() <= 1e-6 * want, "dissipated {dissipated}");
        if theta.abs() > 0.5 * th {
            rocked += 1;
        }
    }
    assert!(rocked >= 4, "rocked states {rocked}");
    assert!((solver.states().last().unwrap().platen[1][2]).abs() < 1e-20);
}

/// A block sliding on a block, pushed and pulled back (two stones, one reversal): the energy
/// balance with and without contact events, against a spring–slider. Column of two unit
/// squares, the beam cut, the upper stone pressed by `N = 1e5 N` (vertical force control) and
/// pushed by the top platen (rotation fixed) to `2e-4 m` in 10 steps and back to 0 in 10: the
/// contact slip is the platen displacement, the tangential stiffness `k_t = k_n = Ē t_z L/ℓ_c`,
/// the Coulomb limit `μN = 6e4 N`, reached after `μN/k_t = 2.7e-5 m` (inside the second step)
/// and, after the reversal, `2μN/k_t` later (inside the third step back). The same steps on
/// a spring–slider (by hand: `F ← clamp(F + k_t Δu, ±μN)`) give the trapezoid external work
/// short of `ΔE + D` by `½ ΔF Δg_p` at each kink: the solver's imbalance without contact events
/// must be that defect (here 1 % of the work; tolerance 10 %: `k_t ∝ L` shortens with the slide
/// by ≤ 2e-4, the chord normal of the shifted strip tilts by `δ/L ≈ 5e-5`). With contact events
/// the steps end at the kinks and the balance closes to 1e-3 of the work (the kink
/// estimate is exact for one linear contact; left: the `O(δ/L)` geometry).
#[test]
fn sliding_block_balance_at_stick_slip_kinks() {
    use super::dofs::{DofControl::*, DofMap};
    let s = column(2);
    let p = MechParams::default();
    let (d_i, d_j) = (s.particles[0].diameter, s.particles[1].diameter);
    let k_t = p.kt_over_kn * p.e_bar * p.t_z / (2.0 / (1.0 / d_i + 1.0 / d_j));
    let (n, a, steps) = (1e5, 2e-4, 10usize);
    let run = |events: bool| {
        let map = DofMap::new(&s, [[Prescribed; 3], [Prescribed, Force, Prescribed]]).unwrap();
        let model = Model::new(&s, &p, map).unwrap();
        let load = |ux: f64, n: f64| LoadPoint { prescribed: vec![0.0, 0.0, 0.0, ux, 0.0], forces: vec![-n] };
        let opts = SolverOptions { contact_events: events, ..Default::default() };
        let mut solver = Solver::new(model, opts, load(0.0, 0.0)).unwrap();
        solver.start().unwrap();
        solver.run_stage(&load(0.0, n), 2, None).unwrap();
        solver.break_and_relax(0).unwrap();
        let st0 = solver.states().last().unwrap().clone();
        solver.run_stage(&load(a, n), steps, None).unwrap();
        solver.run_stage(&load(0.0, n), steps, None).unwrap();
        let last = solver.states().last().unwrap().clone();
        let bal = |st: &StateRecord| st.external_work - st.stored - st.dissipated.iter().sum::<f64>();
        (last.external_work - st0.external_work, bal(&last) - bal(&st0), solver.diag.counters.contact_events)
    };
    // The spring–slider on the same steps: trapezoid work minus (ΔE + D).
    let limit = p.mu * n;
    let (mut f, mut trap, mut diss, mut u) = (0.0f64, 0.0, 0.0, 0.0);
    let targets =
        (1..=steps).map(|k| a * k as f64 / steps as f64).chain((0..steps).rev().map(|k| a * k as f64 / steps as f64));
    for target in targets {
        let du = target - u;
        let trial = f + k_t * du;
        let next = trial.clamp(-limit, limit);
        diss += limit * ((trial - next) / k_t).abs();
        trap += 0.5 * (f + next) * du;
        f = next;
        u = target;
    }
    let defect = trap - (0.5 * f * f / k_t + diss);
    let (w_plain, imb_plain, _) = run(false);
    let (w_events, imb_events, n_events) = run(true);
    println!("spring–slider defect {defect:.4e} J; no events: W {w_plain:.4e}, imbalance {imb_plain:.4e}; events ({n_events}): W {w_events:.4e}, imbalance {imb_events:.4e}");
    assert!(defect < -0.005 * w_plain, "the kinks fall inside steps: defect {defect}");
    assert!((imb_plain - defect).abs() <= 0.1 * defect.abs(), "imbalance {imb_plain} vs spring–slider {defect}");
    assert!(n_events >= 2, "events {n_events}");
    assert!(imb_events.abs() <= 1e-3 * w_events, "imbalance with events {imb_events} of {w_events}");
}

/// The paper's wall under the protocol of `jobs/wall-cyclic-tension-compression.toml`
/// (amplitudes 0.5, 1, 2, 4 × 10⁻⁴, 20 steps per half cycle), sample 1 of the job (seed 2). The
/// first tensile branch cracks it across a bed joint and leaves two stones without a beam; the
/// compressive reversals close the crack on contacts that pass from stick to slip while the
/// platen force goes through zero. This sample used to stop at 0.437 of stage 7: the Jacobian of
/// a contact within the difference step of the Coulomb cone was the mean of stick and slip
/// (`tangent`, "Near the cone"), and the convergence scale followed the forces down to the
/// reversal (`equilibrium`, the reference force). Now:
/// - the protocol completes;
/// - the energy balance holds within 1 % (the issue's tolerance);
/// - the unilateral effect: at the last tensile end, ε = 4·10⁻⁴, the cracked wall carries less
///   than 30 % of E ε (E from the first loading step), while at the compressive end,
///   ε = −4·10⁻⁴, the closed crack carries more than 80 % of it (flat joints in contact have
///   the penalty Ē S_r/ℓ_c, close to the beams' axial stiffness; the crack must first close
///   from its residual opening, so not all of E ε). Measured: 0.81 MPa against E ε = 0.89 MPa.
#[test]
fn paper_wall_tension_compression_reversals_complete() {
    let s = crate::dem::sample::Sample::build(&crate::dem::sample::SampleConfig::paper_wall(2)).unwrap();
    let p = MechParams::default();
    let t = VirtualTest::CyclicTensionCompression {
        amplitudes: vec![0.5e-4, 1e-4, 2e-4, 4e-4],
        compression_ratio: 1.0,
        steps_per_half_cycle: 20,
    };
    let r = run_test(&s, &p, &t).unwrap();
    let last = r.curve.last().unwrap();
    println!(
        "end {:?}, events {}, W_ext {:.4e} J, imbalance {:.3e} J",
        r.end,
        r.stats.events,
        last.external_work,
        balance(last)
    );
    assert_eq!(r.end, TestEnd::Target);
    assert!(r.stats.events > 0, "the wall cracks");
    assert!(balance(last).abs() <= 0.01 * last.external_work, "imbalance {} of {}", balance(last), last.external_work);
    let e = r.derived.young_modulus;
    let at = |strain: f64| r.curve.iter().find(|c| (c.strain - strain).abs() < 1e-12).map(|c| c.stress);
    let (pull, push) = (at(4e-4).expect("a state at ε = 4e-4"), at(-4e-4).expect("a state at ε = −4e-4"));
    let elastic = e * 4e-4;
    println!("σ at ε = ±4e-4: {:.4} / {:.4} MPa, E ε = {:.4} MPa", pull / 1e6, push / 1e6, elastic / 1e6);
    assert!(pull < 0.3 * elastic, "the cracked wall still carries {pull} Pa in tension (E ε = {elastic})");
    assert!(-push > 0.8 * elastic, "the closed crack carries only {push} Pa in compression (E ε = {elastic})");
}
