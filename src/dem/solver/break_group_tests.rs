//! Tests of several beam breaks per equilibrium ([`SolverOptions::breaks_per_equilibrium`]), the
//! opt-in approximation, against paper §2.1's one-break path.
use super::speed_tests::{compress, random};
use super::*;

/// The largest platen force of a run (N) and its dissipated energy at the end (J).
fn peak_and_dissipation(s: &Solver) -> (f64, f64) {
    let peak = s.states().iter().fold(0.0f64, |m, st| m.max(st.platen_force[1][1].abs()));
    let dissipated = s.states().last().map_or(0.0, |st| st.dissipated.iter().sum());
    (peak, dissipated)
}

#[test]
fn several_breaks_per_equilibrium_keep_the_peak_and_the_dissipated_energy() {
    // 120 random stones compressed to 2e-3, exactly and with up to 8 breaks per equilibrium.
    let s = random(120, 5);
    let exact = compress(&s, SolverOptions::default());
    let n = 8;
    let grouped = compress(&s, SolverOptions { breaks_per_equilibrium: n, ..Default::default() });
    assert!(exact.broken().len() > 10, "breaks {}", exact.broken().len());
    // A load step still stops where the first beam reaches P = 1: the first break is the same
    // beam at the same recorded state.
    let first = |v: &Solver| (v.broken()[0].beam, v.broken()[0].state);
    assert_eq!(first(&grouped), first(&exact));
    // Fewer equilibria: a cascade's overloaded beams break together, at most n per state.
    let relaxed = |v: &Solver| v.states().iter().filter(|st| st.kind == StateKind::Relaxed).count();
    assert!(relaxed(&grouped) < relaxed(&exact), "relaxed states {} against {}", relaxed(&grouped), relaxed(&exact));
    for w in grouped.states().windows(2) {
        assert!(w[1].broken[0] - w[0].broken[0] <= n, "{} breaks in one state", w[1].broken[0] - w[0].broken[0]);
    }
    // The approximation's acceptance (the DEM-scale issue): the peak within 2 %, the dissipated
    // energy within 5 % of the exact path's.
    let ((p0, d0), (p1, d1)) = (peak_and_dissipation(&exact), peak_and_dissipation(&grouped));
    assert!((p1 / p0 - 1.0).abs() <= 0.02, "peak {p1} N against {p0} N");
    assert!((d1 / d0 - 1.0).abs() <= 0.05, "dissipated {d1} J against {d0} J");
}
