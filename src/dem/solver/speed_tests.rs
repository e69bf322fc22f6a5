//! Tests of the pieces that make the event loop cheaper without changing its equilibria: the
//! load-step predictor after a break, the tangent's difference from the factorized operator,
//! the Jacobian cache's count of contacts on the Coulomb cone, and the reused matrix assembly.
use nalgebra::{DVector, SMatrix};

use super::contact_set::{self, ContactHistory};
use super::dofs::{DofControl, DofMap};
use super::tangent::{JacobianCache, Tangent};
use super::*;
use crate::dem::mechanics::{MechParams, SlipState};
use crate::dem::sample::{RandomLayout, Sample, SampleConfig, SampleLayout, TinyFacetPolicy};

pub(super) fn random(n: usize, seed: u64) -> Sample {
    Sample::build(&SampleConfig {
        layout: SampleLayout::Random(RandomLayout {
            width: 1.0,
            height: 1.0,
            n_particles: n,
            min_distance_factor: 0.7,
        }),
        thickness: 1.0,
        seed,
        alpha: 0.8,
        facet_tolerance: 0.02,
        tiny_facets: TinyFacetPolicy::Merge,
    })
    .unwrap()
}

/// Compression of `s` to 2e-3 in 20 steps with `opts`: the solver after the stage.
pub(super) fn compress<'a>(s: &'a Sample, opts: SolverOptions) -> Solver<'a> {
    let map = DofMap::new(s, [[DofControl::Prescribed; 3]; 2]).unwrap();
    let model = Model::new(s, &MechParams::default(), map).unwrap();
    let zero = LoadPoint { prescribed: vec![0.0; 6], forces: vec![] };
    let target = LoadPoint { prescribed: vec![0.0, 0.0, 0.0, 0.0, -2e-3 * s.height, 0.0], forces: vec![] };
    let mut solver = Solver::new(model, opts, zero).unwrap();
    solver.start().unwrap();
    solver.run_stage(&target, 20, Some((1, 1))).unwrap();
    solver
}

/// Asserts that `a` and `b` followed the same path: the same beams broken in the same order at
/// the same states, the same recorded states (kind, broken counts), their load fractions within
/// `t_tol` (when given) and their driven platen forces within `force_tol` of `b`'s peak force.
fn assert_same_path(a: &Solver, b: &Solver, force_tol: f64, t_tol: Option<f64>, label: &str) {
    let seq = |v: &Solver| v.broken().iter().map(|b| (b.beam, b.mode, b.state)).collect::<Vec<_>>();
    assert_eq!(seq(a), seq(b), "{label}");
    assert_eq!(a.states().len(), b.states().len(), "{label}");
    let peak = b.states().iter().fold(0.0f64, |m, st| m.max(st.platen_force[1][1].abs()));
    for (x, y) in a.states().iter().zip(b.states()) {
        assert_eq!((x.kind, x.broken), (y.kind, y.broken), "{label}");
        if let Some(t_tol) = t_tol {
            assert!((x.t - y.t).abs() <= t_tol, "{label}: t {} vs {}", x.t, y.t);
        }
        let d = (x.platen_force[1][1] - y.platen_force[1][1]).abs();
        assert!(
            d <= force_tol * peak,
            "{label}: force {} vs {} (peak {peak})",
            x.platen_force[1][1],
            y.platen_force[1][1]
        );
    }
}

#[test]
fn predicted_load_steps_reach_the_same_equilibria() {
    // 120 random stones compressed far past the first cracks, with and without the load-step
    // predictor: the same beams break in the same order at the same states, and every recorded
    // platen force agrees within 1e-6 of the peak force (the equilibrium tolerance is 1e-8 of
    // the largest generalized force: two solutions within it differ by about that much, the
    // margin covers their difference carried over the later steps); the predictor was used and
    // Newton's method needed fewer iterations with it.
    let s = random(120, 5);
    let with = compress(&s, SolverOptions::default());
    let without = compress(&s, SolverOptions { predict_steps: false, ..Default::default() });
    assert!(with.broken().len() > 10, "breaks {}", with.broken().len());
    // A break's load fraction comes from the converged end of its step, known to the
    // tolerance: 1e-7 of the stage (measured: 2e-9).
    assert_same_path(&with, &without, 1e-6, Some(1e-7), "predictor");
    assert!(with.diag.profile.predicted_steps > 0 && without.diag.profile.predicted_steps == 0);
    assert!(
        with.diag.profile.newton_iterations < without.diag.profile.newton_iterations,
        "Newton iterations {} with the predictor, {} without",
        with.diag.profile.newton_iterations,
        without.diag.profile.newton_iterations
    );
}

#[test]
fn linear_phase_reaches_the_same_equilibria_as_newton() {
    // 120 random stones compressed far past the first cracks, every equilibrium by Newton's
    // method against the linear phase (`linear.rs`): it takes Newton's first step and skips
    // only the residual that confirms it, so the recorded states agree to round-off (bit for
    // bit by construction; asserted: the same beams break in the same order at the same states,
    // every platen force within 1e-12 of the peak force). Without contacts every Newton
    // iteration is such a step and the residual evaluations are fewer; with contacts the linear
    // phase ends where the first contact appears (Newton iterations with contacts follow).
    let s = random(120, 5);
    for contacts in [false, true] {
        let base = SolverOptions { contacts, ..Default::default() };
        let linear = compress(&s, base);
        let newton = compress(&s, SolverOptions { linear_phase: false, ..base });
        assert!(newton.broken().len() > 10, "breaks {}", newton.broken().len());
        assert_same_path(&linear, &newton, 1e-12, Some(1e-12), &format!("contacts {contacts}"));
        assert!(linear.diag.profile.linear_solves > 0 && newton.diag.profile.linear_solves == 0);
        if contacts {
            let p = &linear.diag.profile;
            assert!(p.gmres_solves > 0 && p.linear_solves < p.newton_iterations, "{p:?}");
        } else {
            assert_eq!(linear.diag.profile.newton_iterations, linear.diag.profile.linear_solves);
            assert_eq!(linear.diag.profile.linear_fallbacks, 0);
            assert!(linear.diag.profile.evaluations < newton.diag.profile.evaluations);
        }
    }
}

#[test]
fn updates_in_place_reach_the_same_equilibria_as_woodbury() {
    // 120 random stones compressed far past the first cracks, with and without contacts, the
    // operator kept by Woodbury columns and refactorizations (default) and by CHOLMOD's updates
    // and downdates in place (`cholmod.rs`): another factorization, so another round-off, and
    // Newton's method stops anywhere within its tolerance (1e-8 of the largest force). The same
    // beams break in the same order at the same states and every recorded platen force agrees
    // within 1e-6 of the peak force (as for the predictor above: the tolerance carried over the
    // later steps). In place no Woodbury correction is kept, so no batch of columns meets the
    // rank cap, even a cap of 1 column (no rank-cap refactorization); without contacts (breaks are
    // downdates within the factor's pattern: no fill) the factorization is the first one only;
    // the update columns are counted.
    let s = random(120, 5);
    for contacts in [false, true] {
        let base = SolverOptions { contacts, factor_updates: FactorUpdates::Woodbury, ..Default::default() };
        let woodbury = compress(&s, base);
        let updown = compress(&s, SolverOptions { factor_updates: FactorUpdates::InPlace, max_rank: 1, ..base });
        if !contacts {
            // The default (`FactorUpdates::Auto`) keeps the Woodbury path below 1,000 unknowns:
            // the same run, bit for bit.
            assert!(woodbury.model().map.n_eq() < super::options::IN_PLACE_MIN_UNKNOWNS);
            let auto = compress(&s, SolverOptions { contacts, ..Default::default() });
            assert_same_path(&auto, &woodbury, 0.0, Some(0.0), "auto below 1,000 unknowns");
        }
        assert!(woodbury.broken().len() > 10, "breaks {}", woodbury.broken().len());
        assert_same_path(&updown, &woodbury, 1e-6, None, &format!("contacts {contacts}"));
        let r = updown.diag.profile.refactorizations;
        assert_eq!((r.initial, r.rank_cap), (1, 0), "{r:?}");
        if !contacts {
            assert_eq!(r.cost_model, 0, "{r:?}");
        }
        assert!(
            woodbury.diag.profile.refactorizations.cost_model + woodbury.diag.profile.refactorizations.rank_cap > 0
        );
        assert!(updown.diag.profile.columns_added >= 3 * updown.broken().len());
    }
}

#[test]
fn sparse_right_hand_sides_reach_the_same_equilibria_as_dense_solves() {
    // 400 random stones (1,092 unknowns) compressed far past the first cracks with updates in
    // place, the contact-free Newton steps solved with sparse right-hand sides (default,
    // `factor.rs`, "Sparse right-hand sides") and densely. The sparse step leaves the residual
    // entries below 1e-5 of the tolerance (1e-13 of the largest force), so without contacts
    // the recorded forces agree within 1e-9 of the peak (measured: 3.2e-11 here, 8.5e-10 for
    // 10k stones over 1,500 breaks: the lattice's conditioning grows with its size); with
    // contacts Newton's method then stops anywhere within its tolerance, 1e-6 of the peak as
    // above. The same beams break in the same order at the same states either way; sparse
    // solves were made (without contacts 100 of them, visiting 35 % of the columns on average)
    // and their forward substitutions visited fewer columns than dense ones would have.
    let s = random(400, 5);
    for contacts in [false, true] {
        let base = SolverOptions { contacts, factor_updates: FactorUpdates::InPlace, ..Default::default() };
        let sparse = compress(&s, base);
        if !contacts {
            // The default (`FactorUpdates::Auto`) updates a system of 1,092 unknowns in place:
            // the same run, bit for bit.
            assert!(sparse.model().map.n_eq() >= super::options::IN_PLACE_MIN_UNKNOWNS);
            let auto = compress(&s, SolverOptions { contacts, ..Default::default() });
            assert_same_path(&auto, &sparse, 0.0, Some(0.0), "auto from 1,000 unknowns");
        }
        let dense = compress(&s, SolverOptions { sparse_rhs: false, ..base });
        assert!(dense.broken().len() > 10, "breaks {}", dense.broken().len());
        let tol = if contacts { 1e-6 } else { 1e-9 };
        assert_same_path(&sparse, &dense, tol, None, &format!("contacts {contacts}"));
        let (p, n) = (&sparse.diag.profile, sparse.model().map.n_eq());
        assert!(p.sparse_solves > 0 && dense.diag.profile.sparse_solves == 0, "{} sparse solves", p.sparse_solves);
        assert!(
            p.sparse_columns < p.sparse_solves * n,
            "{} columns in {} solves of {n}",
            p.sparse_columns,
            p.sparse_solves
        );
    }
}

/// Two free stones of a random sample pushed together across their shared facet by `δ`, the
/// beam between them broken: the contact at `q = [0, −(δ + extra) n]` with the history `old`.
struct Pair<'a> {
    s: &'a Sample,
    model: Model<'a>,
    i: usize,
    j: usize,
    beam: usize,
    n: [f64; 2],
    delta: f64,
}

impl<'a> Pair<'a> {
    fn new(s: &'a Sample) -> Self {
        let map = DofMap::new(s, [[DofControl::Prescribed; 3]; 2]).unwrap();
        let model = Model::new(s, &MechParams::default(), map).unwrap();
        let beam = s.beams.iter().position(|b| !model.map.is_slave(b.i) && !model.map.is_slave(b.j)).unwrap();
        let (i, j, n) = (s.beams[beam].i, s.beams[beam].j, s.beams[beam].normal);
        Pair { s, model, i, j, beam, n, delta: 1e-4 * s.mean_diameter() }
    }

    fn q(&self, tangential: f64) -> [[f64; 3]; 2] {
        let (n, d) = (self.n, self.delta);
        [[0.0; 3], [-d * n[0] - tangential * n[1], -d * n[1] + tangential * n[0], 0.0]]
    }

    fn contact(&self, q: [[f64; 3]; 2], c: [[f64; 3]; 2], old: ContactHistory) -> contact_set::ActiveContact {
        contact_set::evaluate_pair(self.s, &self.model.params, self.i, self.j, q, c, old).unwrap().unwrap()
    }
}

#[test]
fn contacts_on_the_cone_are_counted_and_their_jacobian_is_the_exact_one() {
    // A pressed pair whose committed tangential force sits on the cone, F_t,c = μ F_n, with no
    // slip increment (q = c): the return map says "stick" (|trial| = μ F_n). The cache counts it
    // on the cone and hands out the exact Jacobian (the slip branch's, `jacobian_tests`) bit for
    // bit; a contact well inside the cone is not counted.
    let s = random(60, 3);
    let p = Pair::new(&s);
    let q = p.q(0.0);
    let f_n = p.contact(q, q, ContactHistory::default()).contact.f_n;
    let old = ContactHistory { f_t: p.model.params.mu * f_n, plastic: Default::default() };
    let a = p.contact(q, q, old);
    assert_eq!(a.friction.state, SlipState::Stick);
    let mut cache = JacobianCache::default();
    let jac = cache_jacobian(&mut cache, &p, &a, q, q, old);
    assert_eq!(cache.on_cone, 1);
    assert_eq!(jac, contact_set::pair_jacobian(&s, &p.model.params, &a, q, q, old));
    let inside = ContactHistory { f_t: 0.5 * old.f_t, ..old };
    let b = p.contact(q, q, inside);
    let mut fresh = JacobianCache::default();
    let jb = cache_jacobian(&mut fresh, &p, &b, q, q, inside);
    assert_eq!(fresh.on_cone, 0);
    assert_eq!(jb, contact_set::pair_jacobian(&s, &p.model.params, &b, q, q, inside));
}

fn cache_jacobian(
    cache: &mut JacobianCache,
    p: &Pair,
    a: &contact_set::ActiveContact,
    q: [[f64; 3]; 2],
    c: [[f64; 3]; 2],
    old: ContactHistory,
) -> SMatrix<f64, 6, 6> {
    cache.jacobian(&p.model, a, q, c, old).unwrap()
}

/// The pair of [`Pair`] pressed into contact by 0.3 of its overlap scale with its beam broken,
/// as the tangent tests need it: the solver state (its beam broken, committed state zero, no
/// histories, the one active contact) and the regularization ε = 1e-10 of the diagonal.
struct ContactState {
    state: SolverState,
    reg: Vec<f64>,
}

impl ContactState {
    fn new(s: &Sample, p: &Pair) -> Self {
        let map = &p.model.map;
        let load = LoadPoint { prescribed: vec![0.0; map.prescribed.len()], forces: vec![0.0; map.forced.len()] };
        let mut state = SolverState::new(map.n_z, s.beams.len(), load);
        let (idx, _) = map.particle_map(p.j);
        let qj = p.q(0.3 * p.delta)[1];
        for a in 0..3 {
            state.z[idx[a]] = qj[a];
        }
        state.intact[p.beam] = false;
        let reg: Vec<f64> = p.model.diagonal().iter().map(|d| 1e-10 * d.max(1.0)).collect();
        state.contacts =
            contact_set::evaluate(s, map, &p.model.params, &[(p.i, p.j)], &state.z, &state.z_commit, &state.histories)
                .unwrap();
        assert_eq!(state.contacts.len(), 1);
        ContactState { state, reg }
    }

    /// The tangent at this state (fresh Jacobians).
    fn tangent<'m, 'a>(&'m self, model: &'m Model<'a>) -> Tangent<'m, 'a> {
        let mut cache = JacobianCache::default();
        Tangent::new(model, &self.state, &self.reg, &self.state.contacts, &mut cache).unwrap()
    }
}

#[test]
fn tangent_difference_is_the_tangent_minus_the_factorized_operator() {
    // D = K_T − M for a pair in contact (its beam broken) with M = intact beams + ε + the
    // contact's normal and tangential terms as they entered the operator, k_n b₀b₀ᵀ and
    // k_t c₀c₀ᵀ taken at a slightly different state (as after Newton iterations): D v equals
    // K_T v − M v, M v from the assembled matrix, within 1e-9 of |K_T v| (round-off of the
    // large beam terms cancelling).
    let s = random(60, 3);
    let p = Pair::new(&s);
    let c = ContactState::new(&s, &p);
    let tangent = c.tangent(&p.model);
    let n = p.model.map.n_eq();
    // The terms as they entered the operator, one iteration earlier (no tangential offset).
    let earlier = p.contact(p.q(0.0), [[0.0; 3]; 2], ContactHistory::default());
    let held = [
        p.model.rank_one(p.i, p.j, &earlier.contact.normal_direction(), earlier.contact.k_n),
        p.model.rank_one(p.i, p.j, &earlier.contact.tangential_direction(), earlier.k_t),
    ];
    let diff = tangent.difference(&c.state.contacts, |_, _| held[0].k + held[1].k);
    let upper = p.model.assemble(&c.state.intact, &c.reg, &held);
    let mut m = nalgebra::DMatrix::<f64>::zeros(n, n);
    for t in &upper {
        m[(t.row, t.col)] += t.val;
        if t.row != t.col {
            m[(t.col, t.row)] += t.val;
        }
    }
    let v: Vec<f64> = (0..n).map(|k| ((k as f64) * 0.37).sin()).collect();
    let (mut kt_v, mut d_v) = (vec![0.0; n], vec![0.0; n]);
    tangent.apply(&v, &mut kt_v);
    diff.apply(&v, &mut d_v);
    let m_v = &m * DVector::from_column_slice(&v);
    let scale = kt_v.iter().fold(0.0f64, |x, y| x.max(y.abs()));
    let worst = (0..n).map(|e| (d_v[e] - (kt_v[e] - m_v[e])).abs()).fold(0.0f64, f64::max);
    assert!(worst <= 1e-9 * scale, "worst {worst} of {scale}");
    // The difference is not zero: the contact's Jacobian is not the held terms.
    assert!(d_v.iter().any(|x| x.abs() > 1e-6 * scale));
}

#[test]
fn direct_solve_inverts_the_tangent() {
    // Tangent::solve_direct (Newton's fallback when GMRES misses its tolerance) on a pair in
    // contact, its beam broken, so that the assembled tangent holds the contact's non-symmetric
    // Jacobian: K_T x = b to round-off, ‖K_T x − b‖∞ ≤ 1e-8 ‖b‖∞ (the regularization ε = 1e-10
    // of the diagonal bounds the conditioning at about 1e10; a sign or index slip in the
    // assembly leaves a residual of order ‖b‖).
    let s = random(60, 3);
    let p = Pair::new(&s);
    let c = ContactState::new(&s, &p);
    let tangent = c.tangent(&p.model);
    let n = p.model.map.n_eq();
    let b: Vec<f64> = (0..n).map(|k| ((k as f64) * 0.61).cos() * 1e6).collect();
    let x = tangent.solve_direct(&b).expect("a regular tangent");
    let mut kx = vec![0.0; n];
    tangent.apply(&x, &mut kx);
    let scale = b.iter().fold(0.0f64, |m, v| m.max(v.abs()));
    let worst = kx.iter().zip(&b).map(|(a, c)| (a - c).abs()).fold(0.0f64, f64::max);
    assert!(worst <= 1e-8 * scale, "‖K_T x − b‖∞ = {worst} of ‖b‖∞ = {scale}");
}

#[test]
fn slip_terms_that_follow_the_regimes_reach_the_same_equilibria() {
    // 120 random stones compressed to 2e-3 with the preconditioner holding every contact's
    // `k_t c cᵀ` (`SlipTerms::FULL`, the reference) and following the stick/slip regimes
    // (`slip_terms.rs`): the share 1e-2 with lags 0 and 2, in place (flips scale the held
    // terms) and on the Woodbury path (flips replace them), and the share 0 (sliding contacts
    // hold none). Only GMRES's path changes: the same beams break in the same order at the same
    // states and the recorded platen forces agree within 1e-6 of the peak (Newton's tolerance
    // carried over the later steps, as for the update paths above); flips reach the operator.
    let s = random(120, 5);
    let base = SolverOptions { factor_updates: FactorUpdates::InPlace, ..Default::default() };
    let full = compress(&s, base);
    for (slip_terms, factor_updates) in [
        (SlipTerms { share: 1e-2, lag: 0 }, FactorUpdates::InPlace),
        (SlipTerms { share: 1e-2, lag: 2 }, FactorUpdates::InPlace),
        (SlipTerms { share: 1e-2, lag: 0 }, FactorUpdates::Woodbury),
        (SlipTerms::STICK_ONLY, FactorUpdates::InPlace),
    ] {
        let following = compress(&s, SolverOptions { slip_terms, factor_updates, ..base });
        let label = format!("{slip_terms:?} {factor_updates:?}");
        assert_same_path(&following, &full, 1e-6, None, &label);
        assert!(following.diag.profile.slip_flips[0] > 0, "{label}: {:?}", following.diag.profile.slip_flips);
    }
    assert_eq!(full.diag.profile.slip_flips, [0, 0]);
}

#[test]
fn the_preconditioners_copy_reaches_the_same_equilibria() {
    // 120 random stones compressed to 2e-3 with GMRES preconditioned by CHOLMOD's factor
    // (`preconditioner_copy_from = usize::MAX`, the reference) and by its f32 supernodal copy
    // from the first entry (`0`; the default starts at 800k entries, about 5,000 stones). Only
    // GMRES's path changes: the same beams break in the same order at the same states, and the
    // platen forces agree within 1e-6 of the peak (Newton's tolerance carried over the later
    // steps, as for the slip terms above). The copy is made and used.
    let s = random(120, 5);
    let base = SolverOptions { factor_updates: FactorUpdates::InPlace, ..Default::default() };
    let exact = compress(&s, SolverOptions { preconditioner_copy_from: usize::MAX, ..base });
    let copied = compress(&s, SolverOptions { preconditioner_copy_from: 0, ..base });
    assert_same_path(&copied, &exact, 1e-6, None, "f32 supernodal copy");
    assert_eq!(exact.diag.profile.preconditioner_copies, 0);
    assert!(copied.diag.profile.preconditioner_copies > 0, "no copy made");
    // the default does not copy a factor this small: CHOLMOD's solves, bit for bit
    let default = compress(&s, base);
    assert_eq!(default.diag.profile.preconditioner_copies, 0);
    let forces = |v: &Solver| v.states().iter().map(|st| st.platen_force[1][1]).collect::<Vec<_>>();
    assert_eq!(forces(&default), forces(&exact));
}
