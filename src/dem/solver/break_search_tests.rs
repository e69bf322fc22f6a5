//! Tests of the break search ([`super::break_search`], `SolverOptions::break_search`) against
//! the trial path, on random samples in compression between bonded platens (contacts and
//! friction; `speed_tests::random`, the benchmark's sample of `examples/common/random_sample.rs`):
//!
//! ```text
//!   ┌──────────────┐  platen: u_y = −2·10⁻³ H in 20 (120 stones) or 40 (1k) load steps
//!   │ N Voronoi    │
//!   │ stones, 1 m² │  the same beams break in the same order on both paths; the search
//!   └──────────────┘  lands every break on P = 1, the trial path on its step's chord
//! ```
//!
//! The 1k sample is the benchmark's reference run (`tests/data/dem-random-1k`, the trial path).
use std::cell::RefCell;
use std::rc::Rc;

use super::break_search::LANDING_TOL;
use super::speed_tests::random;
use super::*;
use crate::dem::mechanics::{failure_index, MechParams};
use crate::dem::sample::Sample;

/// A compression run of `s` to 2·10⁻³ in `steps` load steps with `opts`: the solver after the
/// stage and the coordinates of its pre-break states, by state index.
fn compress_keeping_breaks(s: &Sample, opts: SolverOptions, steps: usize) -> (Solver<'_>, Vec<(usize, Vec<f64>)>) {
    let kept = Rc::new(RefCell::new(Vec::new()));
    let keep = Rc::clone(&kept);
    let map = DofMap::new(s, [[DofControl::Prescribed; 3]; 2]).unwrap();
    let model = Model::new(s, &MechParams::default(), map).unwrap();
    let zero = LoadPoint { prescribed: vec![0.0; 6], forces: vec![] };
    let target = LoadPoint { prescribed: vec![0.0, 0.0, 0.0, 0.0, -2e-3 * s.height, 0.0], forces: vec![] };
    let mut solver = Solver::new(model, opts, zero).unwrap();
    solver.diag.observer = Some(Box::new(move |k: usize, st: &StateRecord, z: &[f64]| {
        if st.kind == StateKind::PreBreak {
            keep.borrow_mut().push((k, z.to_vec()));
        }
    }));
    solver.start().unwrap();
    solver.run_stage(&target, steps, Some((1, 1))).unwrap();
    solver.diag.observer = None;
    let kept = kept.borrow().clone();
    (solver, kept)
}

/// `|P − 1|` of the first beam broken after each pre-break state.
fn landing_errors(solver: &Solver, pre_break: &[(usize, Vec<f64>)]) -> Vec<f64> {
    let m = solver.model();
    pre_break
        .iter()
        .map(|(k, z)| {
            let b = solver.broken().iter().find(|b| b.state == *k).expect("a break after a pre-break state").beam;
            let (qi, qj) = m.beam_dofs(b, z);
            (failure_index(&m.geoms[b], &m.thresholds, qi, qj) - 1.0).abs()
        })
        .collect()
}

#[test]
fn search_breaks_the_same_beams_in_order_each_on_its_threshold() {
    let s = random(120, 5);
    let (trial, trial_z) = compress_keeping_breaks(&s, SolverOptions::default(), 20);
    let tangent_opts = SolverOptions { break_search: BreakSearch::Tangent, ..Default::default() };
    let (tangent, tangent_z) = compress_keeping_breaks(&s, tangent_opts, 20);
    let seq = |v: &Solver| v.broken().iter().map(|b| (b.beam, b.mode)).collect::<Vec<_>>();
    assert!(trial.broken().len() > 10, "a test with breaks: {}", trial.broken().len());
    assert_eq!(seq(&tangent), seq(&trial));
    // One equilibrium per break: the breaks inside load steps are the search's landings, but
    // for the searches given up (their steps taken as trial steps, whose chord found the break).
    let bs = tangent.diag.profile.break_search;
    assert!(bs.landed <= tangent_z.len() && tangent_z.len() <= bs.landed + bs.given_up, "{bs:?}");
    assert!(bs.given_up * 10 <= bs.landed, "{bs:?}");
    // The search's landing (module docs of break_search): |P − 1| ≤ LANDING_TOL at every
    // pre-break state it landed on; the trial path's own landing, on the chord of its step, is
    // printed.
    let (e_tangent, e_trial) = (landing_errors(&tangent, &tangent_z), landing_errors(&trial, &trial_z));
    let max = |e: &[f64]| e.iter().fold(0.0f64, |m, &x| m.max(x));
    println!("|P − 1| at the pre-break states: search {:.1e}, trial path {:.1e}", max(&e_tangent), max(&e_trial));
    let off = e_tangent.iter().filter(|&&e| e > LANDING_TOL).count();
    assert!(off <= bs.given_up, "{off} pre-break states off P = 1: {e_tangent:?}");
    let d = regular_point_differences(&tangent, &trial, 20);
    println!("regular points: {:.1e} of the peak", d.iter().fold(0.0f64, |m, &x| m.max(x)));
}

/// The driven platen force of `a` against `b` at the `steps + 1` regular load points (the
/// first state recorded at `t = k/steps`), in units of `b`'s peak force.
fn regular_point_differences(a: &Solver, b: &Solver, steps: usize) -> Vec<f64> {
    let peak = b.states().iter().fold(0.0f64, |m, st| m.max(st.platen_force[1][1].abs()));
    let at = |v: &Solver, k: usize| {
        let t = k as f64 / steps as f64;
        v.states().iter().find(|st| (st.t - t).abs() < 1e-12).expect("a regular point").platen_force[1][1]
    };
    (0..=steps).map(|k| (at(a, k) - at(b, k)).abs() / peak).collect()
}

/// `(beam, mode)` of the broken beams in order.
fn beams_in_order(v: &Solver) -> Vec<(usize, String)> {
    v.broken().iter().map(|b| (b.beam, format!("{:?}", b.mode))).collect()
}

/// The 1k reference (`tests/data/dem-random-1k`, `examples/dem_profile.rs 1000 2e-3 40`, the
/// trial path): the search breaks the same 689 beams in the same order and modes.
///
/// Its stresses at the regular load points agree with the reference within 10⁻⁸ of the peak
/// (the reference's own tolerance, `tests/data/dem-random-1k/README.md`) up to the first break
/// the two record at a different state; past it they do not, and cannot: the trial path lands
/// each break on the chord from its step's start to the step's end, where `|P − 1|` at its
/// pre-break states reaches 8.9·10⁻⁴ (median 1.9·10⁻⁶), and at event 505 its late break
/// (`P − 1 = 4.7·10⁻⁵`) leaves the next beam over its threshold in the cascade, which the search
/// breaks after a further load increment. From there the regular points differ by up to
/// 2.1·10⁻⁷ of the peak (measured). The second half of the comparison is against the trial
/// path with landed breaks ([`BreakSearch::TrialLanded`]): the same breaks at the same states,
/// the regular points within 10⁻⁸ of the peak. Both at the residual tolerance 10⁻¹⁰: at the
/// default 10⁻⁸, equilibria found from different starts differ by Newton's stopping point, up
/// to 9.8·10⁻⁹ of the peak at the regular points (at 10⁻¹⁰: 1.5·10⁻¹¹, measured).
#[test]
fn search_breaks_the_reference_beams_in_order_on_the_landed_path() {
    let s = random(1000, 7);
    let dir = concat!(env!("CARGO_MANIFEST_DIR"), "/tests/data/dem-random-1k");
    let read = |f: &str| std::fs::read_to_string(format!("{dir}/{f}")).unwrap();
    let reference: Vec<(usize, String, usize)> = read("broken.csv")
        .lines()
        .skip(1)
        .map(|l| {
            let c: Vec<&str> = l.split(',').collect();
            (c[1].parse().unwrap(), c[2].to_string(), c[3].parse().unwrap())
        })
        .collect();
    let curve: Vec<(f64, f64)> = read("curve.csv")
        .lines()
        .skip(1)
        .map(|l| {
            let c: Vec<&str> = l.split(',').collect();
            (c[1].parse().unwrap(), c[2].parse().unwrap())
        })
        .collect();
    let search = SolverOptions { break_search: BreakSearch::Tangent, ..Default::default() };
    let (tangent, _) = compress_keeping_breaks(&s, search, 40);
    let ref_beams: Vec<(usize, String)> = reference.iter().map(|(b, m, _)| (*b, m.clone())).collect();
    assert_eq!(beams_in_order(&tangent), ref_beams);
    assert_eq!(ref_beams.len(), 689);
    // Regular points up to the first break recorded at another state than the reference's.
    let first_other = tangent.broken().iter().zip(&reference).position(|(b, r)| b.state != r.2);
    let until = first_other.map_or(usize::MAX, |k| reference[k].2.min(tangent.broken()[k].state));
    let peak = curve.iter().fold(0.0f64, |m, c| m.max(c.1.abs()));
    let (area, h) = (s.width * MechParams::default().t_z, s.height);
    let mut checked = 0;
    for k in 0..=40 {
        let strain = -2e-3 * k as f64 / 40.0;
        let i = curve.iter().position(|c| (c.0 - strain).abs() <= 1e-9 * 5e-5).unwrap();
        if i >= until {
            break;
        }
        let st = tangent.states().iter().find(|st| (st.platen[1][1] / h - strain).abs() <= 1e-9 * 5e-5).unwrap();
        let d = (st.platen_force[1][1] / area - curve[i].1).abs() / peak;
        assert!(d <= 1e-8, "regular point {k}: {} vs {} Pa", st.platen_force[1][1] / area, curve[i].1);
        checked += 1;
    }
    assert!(checked >= 15, "regular points before the first break at another state: {checked}");
    // The landed trial path, both at the residual tolerance 1e-10 (doc above).
    let tight = |break_search| SolverOptions { break_search, tol: 1e-10, ..Default::default() };
    let (tangent, _) = compress_keeping_breaks(&s, tight(BreakSearch::Tangent), 40);
    let (landed, _) = compress_keeping_breaks(&s, tight(BreakSearch::TrialLanded), 40);
    let seq = |v: &Solver| v.broken().iter().map(|b| (b.beam, b.mode, b.state)).collect::<Vec<_>>();
    assert_eq!(seq(&tangent), seq(&landed));
    assert_eq!(tangent.states().len(), landed.states().len());
    let d = regular_point_differences(&tangent, &landed, 40);
    assert!(d.iter().all(|&x| x <= 1e-8), "{d:?}");
}
