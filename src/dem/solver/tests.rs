//! Solver tests: hand examples, Woodbury vs. refactorization, energy balance, friction through
//! the solver, and the paper's wall (report printed with `--nocapture`).
use super::*;
use crate::dem::mechanics::MechParams;
use crate::dem::sample::{GeometryOptions, RandomLayout, Sample, SampleConfig, SampleLayout};

pub(super) fn column(n: usize) -> Sample {
    // n unit squares stacked: width 1, height n, seeds at the centres (arms 0, ℓ = 1, A = 1).
    let seeds: Vec<[f64; 2]> = (0..n).map(|k| [0.5, k as f64 + 0.5]).collect();
    let opts = GeometryOptions { thickness: 1.0, alpha: 0.8, facet_tolerance: 0.0, tiny_facets: Default::default() };
    Sample::from_seeds(1.0, n as f64, &seeds, &opts).unwrap()
}

fn paper_wall() -> Sample {
    Sample::build(&SampleConfig::paper_wall(1)).unwrap()
}

/// External work minus stored and dissipated energy: zero when the energy balance closes.
pub(super) fn balance(c: &CurvePoint) -> f64 {
    c.external_work - c.stored - c.dissipated.iter().sum::<f64>()
}

#[test]
fn three_stone_column_breaks_at_the_hand_lambda() {
    // Column of 3 unit squares, bottom and top bonded to the platens, two beams in series
    // (ℓ = 1, A = 1, Ē = 2.5e9 → EA/ℓ = 2.5e9 N/m). Top platen lifted by δ: each beam stretches
    // δ/2, P = (δ/2)/ε_cr = 1 at δ* = 2e-4 m. One step to δ = 5e-4: λ* = 0.4 exactly.
    // σ at the break = EA ε_cr / (W t_z) = 2.5e5 Pa; E_sample = σ/(δ/H) = 2.5e5/(2e-4/3) = 3.75e9.
    // Energy at the break: W = ½ R δ* = 25 J = stored (2 × 12.5 J). Breaking one beam (12.5 J)
    // lets the other unload (12.5 J relaxation) and the load drops to 0: loss of load.
    // Tolerances 1e-9 relative (round-off of the solve).
    let s = column(3);
    let t = VirtualTest::Tension { max_strain: 5e-4 / 3.0, steps: 1 };
    let r = run_test(&s, &MechParams::default(), &t).unwrap();
    assert!(r.stats.loss_of_load);
    assert_eq!(r.broken.len(), 1);
    let pre = &r.curve[r.broken[0].state];
    assert_eq!(pre.kind, StateKind::PreBreak);
    assert!((pre.displacement - 2e-4).abs() < 1e-9 * 2e-4, "{}", pre.displacement);
    assert!((pre.stress - 2.5e5).abs() < 1e-9 * 2.5e5);
    assert!((r.derived.young_modulus - 3.75e9).abs() < 1e-9 * 3.75e9);
    assert_eq!(r.broken[0].mode, FailureModeTag::Tension);
    assert!((r.broken[0].energy - 12.5).abs() < 1e-8);
    let last = r.curve.last().unwrap();
    assert!(last.stress.abs() < 1e-6 * 2.5e5);
    assert!((last.external_work - 25.0).abs() < 1e-8);
    assert!((last.dissipated[0] - 12.5).abs() < 1e-8 && (last.dissipated[2] - 12.5).abs() < 1e-8);
    assert!(balance(last).abs() < 1e-8);
}

#[test]
fn a_report_sees_every_recorded_state_beside_the_particle_states() {
    // The small wall in compression with a report (`run_test_observed`): it is called once per
    // recorded state, in order, with the records of the result's curve; the particle states are
    // kept as without it, and the run is the same, state for state.
    let s = small_wall(2);
    let t = VirtualTest::Compression { max_strain: 1e-3, steps: 10 };
    let (p, o) = (MechParams::default(), SolverOptions::default());
    let mut seen: Vec<(usize, usize, usize)> = Vec::new();
    let report = Box::new(|index: usize, r: &StateRecord| seen.push((index, r.stage, r.broken[0])));
    let with = run_test_observed(&s, &p, &t, o, ParticleStates::Steps, Some(report)).unwrap();
    let without = run_test_recording(&s, &p, &t, o, ParticleStates::Steps).unwrap();
    assert!(with.stats.events > 3, "events {}", with.stats.events);
    assert_eq!(seen.len(), with.curve.len());
    assert!(seen.iter().enumerate().all(|(k, &(i, _, _))| i == k));
    assert!(seen.iter().zip(&with.curve).all(|(&(_, _, b), c)| b == c.broken[0]));
    assert!(!with.particle_states.is_empty());
    assert_eq!(with.particle_states, without.particle_states);
    assert_eq!(with.curve, without.curve);
}

#[test]
fn woodbury_updates_match_refactorization_in_a_test() {
    // The same compression run with the default low-rank updates and with a refactorization at
    // every event (max_rank = 0) gives the same curve to 1e-8 relative.
    let s = paper_wall();
    let t = VirtualTest::Compression { max_strain: 3e-4, steps: 6 };
    let p = MechParams::default();
    let a = run_test_with(&s, &p, &t, SolverOptions { contacts: false, ..Default::default() }).unwrap();
    let b = run_test_with(&s, &p, &t, SolverOptions { contacts: false, max_rank: 0, ..Default::default() }).unwrap();
    assert!(a.stats.events > 3, "events {}", a.stats.events);
    assert!(a.stats.factorizations < b.stats.factorizations);
    assert_eq!(a.curve.len(), b.curve.len());
    let smax = a.curve.iter().fold(0.0f64, |m, c| m.max(c.stress.abs()));
    for (x, y) in a.curve.iter().zip(&b.curve) {
        assert!((x.stress - y.stress).abs() <= 1e-8 * smax, "{} vs {}", x.stress, y.stress);
        assert_eq!(x.broken, y.broken);
    }
}

#[test]
fn block_on_a_block_slides_at_mu_n_through_the_solver() {
    // Two unit squares, bottom on the fixed platen, top bonded to the top platen; vertical force
    // N = 1e6 N held on the top platen (U_y force-controlled), then the beam is cut and the top
    // platen pushed along x by 1e-3 m. The contact sticks until |F_t| = μ N (elastic slip
    // μN/k_t ≈ 2.7e-4 m < 1e-3), then slides: the horizontal reaction is μ N = 6e5 N.
    // Tolerance 1e-6 relative (equilibrium tolerance 1e-9 on the forces).
    use super::dofs::{DofControl::*, DofMap};
    let s = column(2);
    let p = MechParams::default();
    let map = DofMap::new(&s, [[Prescribed; 3], [Prescribed, Force, Prescribed]]).unwrap();
    let model = Model::new(&s, &p, map).unwrap();
    let zero = LoadPoint { prescribed: vec![0.0; 5], forces: vec![0.0] };
    let mut solver = Solver::new(model, SolverOptions::default(), zero).unwrap();
    solver.start().unwrap();
    let n = 1e6;
    let pre = LoadPoint { prescribed: vec![0.0; 5], forces: vec![-n] };
    solver.run_stage(&pre, 2, None).unwrap();
    solver.break_and_relax(0).unwrap();
    let push = LoadPoint { prescribed: vec![0.0, 0.0, 0.0, 1e-3, 0.0], forces: vec![-n] };
    solver.run_stage(&push, 10, None).unwrap();
    let last = solver.states().last().unwrap();
    assert_eq!(last.contacts, 1);
    // On the contact itself |F_t| = μ F_n exactly (slip); the platen's horizontal force differs
    // from μN by O(δ/L) ≈ 1e-3 because the chord normal of the shifted overlap tilts by ~δ/L
    // (δ ≈ 4.5e-4 m the overlap depth, L ≈ 1 m): tolerance 2e-3 relative there.
    let c = &solver.contacts()[0];
    assert!((c.friction.f_t.abs() - 0.6 * c.contact.f_n).abs() < 1e-9 * n);
    assert!((last.platen_force[1][0].abs() - 0.6 * n).abs() < 2e-3 * n, "F_x = {}", last.platen_force[1][0]);
    assert!((last.platen_force[1][1] + n).abs() < 1e-8 * n);
    // Friction dissipated μN × sliding, sliding = 1e-3 − μN/k_t at least half the push.
    assert!(last.dissipated[1] > 0.6 * n * 0.5e-3);
}

#[test]
fn paper_wall_compression_report_and_energy_balance() {
    // The paper's wall (Table 1 set): report E, ν, first crack, peak next to the experiment and
    // check the energy balance W_ext = stored + dissipated within 1 % over the whole test.
    let s = paper_wall();
    let t = VirtualTest::Compression { max_strain: 2e-3, steps: 40 };
    let r = run_test(&s, &MechParams::default(), &t).unwrap();
    let d = &r.derived;
    println!(
        "paper wall ({} stones, {} beams): E = {:.3} GPa (exp. 2.885), ν = {:.3} (0.19), first crack = {:.3} MPa (0.4), peak = {:.3} MPa (2.1) at ε = {:.2e}",
        s.particles.len(),
        s.beams.len(),
        d.young_modulus / 1e9,
        d.poisson,
        d.first_crack_stress.unwrap_or(f64::NAN) / 1e6,
        d.peak_stress / 1e6,
        d.strain_at_peak
    );
    println!(
        "  events {} ({} states), solves {}, factorizations {}, {:.3} s, loss of load: {}, floating {}",
        r.stats.events,
        r.curve.len(),
        r.stats.solves,
        r.stats.factorizations,
        r.stats.seconds,
        r.stats.loss_of_load,
        r.floating.len()
    );
    let last = r.curve.last().unwrap();
    println!(
        "  energy: W_ext {:.4e}, stored {:.4e}, fracture {:.4e}, friction {:.4e}, relaxation {:.4e}, imbalance {:.3e}",
        last.external_work,
        last.stored,
        last.dissipated[0],
        last.dissipated[1],
        last.dissipated[2],
        balance(last)
    );
    assert!(d.young_modulus > 0.0 && d.poisson.is_finite() && d.peak_stress > 0.0);
    assert!(r.stats.events > 0);
    assert!(balance(last).abs() <= 0.01 * last.external_work, "imbalance {}", balance(last));
}

#[test]
fn bad_test_parameters_are_errors() {
    let s = column(3);
    let p = MechParams::default();
    assert!(run_test(&s, &p, &VirtualTest::Compression { max_strain: -1.0, steps: 3 }).is_err());
    assert!(run_test(&s, &p, &VirtualTest::Tension { max_strain: 1e-3, steps: 0 }).is_err());
    let toml = "type = \"shear\"\nmax_displacement = 5e-3\nsteps = 10\nrotation = \"free\"";
    let t: VirtualTest = toml::from_str(toml).unwrap();
    assert!(
        matches!(t, VirtualTest::Shear { vertical_stress, rotation: PlatenRotation::Free, .. } if vertical_stress == 1e6)
    );
    assert!(toml::from_str::<VirtualTest>("type = \"tension\"\nmax_strain = 1\nsteps = 1\nbogus = 2").is_err());
}

#[test]
fn random_sample_is_isotropic() {
    // 2000 random stones in a unit square: E along y (compression) and along x (the same seeds
    // mirrored x ↔ y, compressed along y again) within 5 % of each other. Elastic step only
    // (ε = 1e-6, far below the first crack); one linear solve each.
    let s = random_sample(2000);
    let opts = GeometryOptions { thickness: 1.0, alpha: 0.8, facet_tolerance: 0.02, tiny_facets: Default::default() };
    let seeds: Vec<[f64; 2]> = s.particles.iter().map(|p| [p.seed[1], p.seed[0]]).collect();
    let s2 = Sample::from_seeds(s.height, s.width, &seeds, &opts).unwrap();
    let t = VirtualTest::Compression { max_strain: 1e-6, steps: 1 };
    let p = MechParams::default();
    let ey = run_test(&s, &p, &t).unwrap();
    let ex = run_test(&s2, &p, &t).unwrap();
    let (a, b) = (ey.derived.young_modulus, ex.derived.young_modulus);
    println!(
        "random 2000: E_y = {:.4} GPa, E_x = {:.4} GPa, ν_y = {:.3}, ν_x = {:.3}, {:.3} s + {:.3} s",
        a / 1e9,
        b / 1e9,
        ey.derived.poisson,
        ex.derived.poisson,
        ey.stats.seconds,
        ex.stats.seconds
    );
    assert_eq!(ey.stats.events, 0);
    assert!((a - b).abs() <= 0.05 * a.max(b), "E_y {a} vs E_x {b}");
}

fn random_sample(n: usize) -> Sample {
    Sample::build(&SampleConfig {
        layout: SampleLayout::Random(RandomLayout {
            width: 1.0,
            height: 1.0,
            n_particles: n,
            min_distance_factor: 0.7,
        }),
        thickness: 1.0,
        seed: 11,
        alpha: 0.8,
        facet_tolerance: 0.02,
        tiny_facets: Default::default(),
    })
    .unwrap()
}

/// The paper's wall compressed far past first cracking (8e-3): the energy balance of the whole
/// test holds within 1% (the tolerance: external work = stored + dissipated), with
/// cracking events on the way. Also prints the figures reported in the issue notes.
#[test]
fn paper_wall_compression_to_failure_report() {
    let s = paper_wall();
    let t = VirtualTest::Compression { max_strain: 8e-3, steps: 160 };
    let r = run_test(&s, &MechParams::default(), &t).unwrap();
    let d = &r.derived;
    let last = r.curve.last().unwrap();
    println!(
        "paper wall to 8e-3: peak = {:.3} MPa at ε = {:.2e}, first crack {:.3} MPa, events {} ({} T / {} S), {:.2} s, {:.0} events/s, factorizations {}, solves {}, loss of load {}, imbalance {:.2e} of W_ext {:.3e}",
        d.peak_stress / 1e6,
        d.strain_at_peak,
        d.first_crack_stress.unwrap_or(f64::NAN) / 1e6,
        r.stats.events,
        last.broken[1],
        last.broken[2],
        r.stats.seconds,
        r.stats.events as f64 / r.stats.seconds,
        r.stats.factorizations,
        r.stats.solves,
        r.stats.loss_of_load,
        balance(last),
        last.external_work
    );
    assert!(r.stats.events > 0, "cracks form");
    assert!(
        balance(last).abs() <= 0.01 * last.external_work,
        "energy balance {} of {}",
        balance(last),
        last.external_work
    );
}

/// A small coursed wall (5 courses × 3 stones, 0.5 m × 0.6 m) with the paper's parameters.
pub(super) fn small_wall(seed: u64) -> Sample {
    let mut cfg = SampleConfig::paper_wall(seed);
    if let SampleLayout::Coursed(c) = &mut cfg.layout {
        c.width = 0.5;
        c.height = 0.6;
        c.n_courses = 5;
        c.n_per_course = 3;
    }
    Sample::build(&cfg).unwrap()
}

/// Shear under 1 MPa on a small wall (5 courses × 3 stones, the paper's parameters): after the
/// preload cracks it, the stones slide on broken joints. The contact–friction Newton must reach
/// the target displacement, friction must dissipate energy, and the energy balance
/// (W_ext = stored + dissipated) must hold within 1 % over the whole test.
#[test]
fn shear_with_sliding_reaches_the_target() {
    let s = small_wall(3);
    let t = VirtualTest::Shear {
        vertical_stress: 1e6,
        max_displacement: 4e-3,
        steps: 20,
        preload_steps: 3,
        rotation: PlatenRotation::Fixed,
    };
    let r = run_test(&s, &MechParams::default(), &t).unwrap();
    let last = r.curve.last().unwrap();
    println!(
        "small wall shear: end {:?}, events {}, cutbacks {}, τ_end {:.3} MPa, peak {:.3} MPa, friction {:.3e} J, imbalance {:.2e} of {:.3e}",
        r.end,
        r.stats.events,
        r.stats.cutbacks,
        last.stress / 1e6,
        r.derived.peak_stress / 1e6,
        last.dissipated[1],
        balance(last),
        last.external_work
    );
    assert_eq!(r.end, TestEnd::Target);
    assert!((last.displacement - 4e-3).abs() < 1e-12);
    assert!(r.stats.events > 0 && last.dissipated[1] > 0.0, "stones slid with friction");
    assert!(balance(last).abs() <= 0.01 * last.external_work, "imbalance {}", balance(last));
}

/// A test stopped by the solver keeps the states recorded so far: with at most 3 breaks allowed
/// the compression test ends as `Failed` (before the peak) with its curve up to the stop.
#[test]
fn a_stopped_test_keeps_its_curve() {
    let s = small_wall(1);
    let t = VirtualTest::Compression { max_strain: 2e-3, steps: 20 };
    let opts = SolverOptions { max_events: 3, ..Default::default() };
    let r = run_test_with(&s, &MechParams::default(), &t, opts).unwrap();
    match &r.end {
        TestEnd::Failed { message } => assert!(message.contains("more than 3"), "{message}"),
        e => panic!("expected a failure, got {e:?}"),
    }
    assert_eq!(r.stats.events, 4);
    assert!(r.curve.len() > 4 && r.curve.iter().any(|c| c.kind == StateKind::PreBreak));
    assert!(!r.end.is_valid());
}

#[test]
fn a_cloned_state_continues_the_test_in_a_new_solver() {
    // The solver's state apart from its workspace: the paper's wall under 0.5 MPa of vertical
    // stress is pushed sideways to 2 mm, its state cloned, and the push to 3 mm continued both
    // in the same solver and in a new one resumed from the clone. The new solver starts with an
    // empty workspace (a fresh factorization in place of the Woodbury-corrected one, no cached
    // contact Jacobians or candidates), so both must break the same beams in the same order, and
    // their platen forces agree within 1e-6 of the largest: the equilibrium tolerance is 1e-8 of
    // the forces, and only round-off tells the two workspaces apart.
    use super::dofs::{DofControl::*, DofMap};
    let s = paper_wall();
    let p = MechParams::default();
    let fy = -0.5e6 * s.width * p.t_z;
    let controls = [[Prescribed; 3], [Prescribed, Force, Prescribed]];
    let model = || Model::new(&s, &p, DofMap::new(&s, controls).unwrap()).unwrap();
    let at = |ux: f64| LoadPoint { prescribed: vec![0.0, 0.0, 0.0, ux, 0.0], forces: vec![fy] };
    let mut solver = Solver::new(model(), SolverOptions::default(), at(0.0)).unwrap();
    solver.start().unwrap();
    solver.run_stage(&at(0.0), 2, None).unwrap();
    solver.run_stage(&at(2.0e-3), 20, None).unwrap();
    let (n0, b0) = (solver.states().len(), solver.broken().len());
    assert!(
        b0 > 0 && !solver.contacts().is_empty(),
        "the first push breaks beams and closes contacts: {b0} breaks, {} contacts",
        solver.contacts().len()
    );
    let mut resumed = Solver::resume(model(), SolverOptions::default(), solver.state().clone()).unwrap();
    for sv in [&mut solver, &mut resumed] {
        sv.run_stage(&at(3.0e-3), 10, None).unwrap();
    }
    let key = |sv: &Solver| sv.broken().iter().map(|b| (b.beam, b.mode)).collect::<Vec<_>>();
    assert!(solver.broken().len() > b0, "the second push breaks more beams");
    assert_eq!(key(&solver), key(&resumed), "the same breaks in the same order");
    assert_eq!(solver.states().len(), resumed.states().len());
    let peak = solver.states().iter().flat_map(|st| st.platen_force[1]).fold(0.0f64, |m, f| m.max(f.abs()));
    for (a, b) in solver.states()[n0..].iter().zip(&resumed.states()[n0..]) {
        for (fa, fb) in a.platen_force.iter().flatten().zip(b.platen_force.iter().flatten()) {
            assert!((fa - fb).abs() <= 1e-6 * peak, "{fa} vs {fb} (peak {peak})");
        }
    }
    // The workspace was rebuilt: the resumed solver factorized at least once of its own.
    assert!(resumed.factor_stats().0 >= 1);
    println!(
        "resumed at state {n0} ({b0} breaks): {} breaks after 3 mm, factorizations {} (continued) / {} (resumed)",
        solver.broken().len(),
        solver.factor_stats().0,
        resumed.factor_stats().0
    );
}

#[test]
fn trace_names_the_largest_residual_and_the_changed_contacts() {
    // 120 random stones compressed past the first cracks with the trace on: the kept Newton
    // iterations with contacts. Each names a free stone of the sample and one of its components
    // with a residual ≥ 0, positive wherever the relative residual is; the changed contacts are
    // the first min(set changes, KEPT_CHANGES) of the counted ones, so their number follows the
    // count; a contact that slides carries |F_t| = μ F_n (the return map onto the cone, to
    // round-off 1e-12), one that entered or sticks F_n > 0 and |F_t| ≤ μ F_n.
    let s = super::speed_tests::random(120, 5);
    let solver = super::speed_tests::compress(&s, SolverOptions { trace: true, ..Default::default() });
    let mu = MechParams::default().mu;
    let trace = solver.diag.trace.as_ref().expect("the trace is kept");
    let steps: Vec<&trace::NewtonStep> =
        trace.attempts.iter().flat_map(|a| a.steps.iter().skip(1)).filter(|st| st.contacts > 0).collect();
    assert!(!steps.is_empty(), "no Newton iteration with contacts kept");
    let mut seen = 0;
    for st in steps {
        // Both platens prescribed: every equation is a free stone's.
        let stone = st.worst.0.expect("a stone's equation");
        assert!(stone < s.particles.len() && st.worst.1 < 3, "{:?}", st.worst);
        assert!(!solver.model().map.is_slave(stone), "{:?}", st.worst);
        assert!(st.worst.2 >= 0.0 && (st.relative == 0.0 || st.worst.2 > 0.0), "{st:?}");
        assert_eq!(st.changed.len(), st.set_changes.min(trace::KEPT_CHANGES), "{st:?}");
        for c in &st.changed {
            seen += 1;
            match c.what {
                "slip" => assert!((c.ratio - mu).abs() <= 1e-12, "{c:?}"),
                "enter" | "stick" => assert!(c.f_n > 0.0 && c.ratio <= mu + 1e-12, "{c:?}"),
                "leave" => assert_eq!((c.f_n, c.ratio), (0.0, 0.0)),
                w => panic!("unknown change {w}"),
            }
        }
    }
    println!("{seen} changed contacts checked");
}
