//! Tests of the break search ([`super::break_search`], `SolverOptions::break_search`) against
//! the trial path, on a random sample of 120 stones in compression (seed 5, 2·10⁻³ in 20 load
//! steps, contacts and friction; `speed_tests::random`).
//!
//! ```text
//!   ┌──────────────┐  platen: u_y = −2·10⁻³ H in 20 steps
//!   │ 120 Voronoi  │
//!   │ stones, 1 m² │  the same beams break in the same order on both paths; the search
//!   └──────────────┘  lands every break on P = 1, the trial path on its step's chord
//! ```
use std::cell::RefCell;
use std::rc::Rc;

use super::break_search::LANDING_TOL;
use super::speed_tests::random;
use super::*;
use crate::dem::mechanics::{failure_index, MechParams};
use crate::dem::sample::Sample;

/// A compression run of `s` (as `speed_tests::compress`) with `opts`: the solver after the
/// stage and the coordinates of its pre-break states, by state index.
fn compress_keeping_breaks(s: &Sample, opts: SolverOptions) -> (Solver<'_>, Vec<(usize, Vec<f64>)>) {
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
    solver.run_stage(&target, 20, Some((1, 1))).unwrap();
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
    let (trial, trial_z) = compress_keeping_breaks(&s, SolverOptions::default());
    let tangent_opts = SolverOptions { break_search: BreakSearch::Tangent, ..Default::default() };
    let (tangent, tangent_z) = compress_keeping_breaks(&s, tangent_opts);
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
    let peak = trial.states().iter().fold(0.0f64, |m, st| m.max(st.platen_force[1][1].abs()));
    let at = |v: &Solver, t: f64| v.states().iter().find(|st| (st.t - t).abs() < 1e-12).unwrap().platen_force[1][1];
    let d = (0..=20).map(|k| (at(&tangent, k as f64 / 20.0) - at(&trial, k as f64 / 20.0)).abs() / peak);
    println!("regular points: {:.1e} of the peak", d.fold(0.0f64, f64::max));
}
