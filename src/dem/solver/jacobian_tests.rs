//! The exact contact Jacobians ([`super::contact_set::pair_jacobian`]) against central
//! differences of the contact law, away from its kinks: sticking, sliding, on the Coulomb cone,
//! and crushing (plastic and elastic above a plastic depth).
//!
//! The pair: two free stones of a 60-stone random sample (seed 3) sharing a facet, their beam
//! broken, stone j pressed into i by `δ = 10⁻⁴ D̄` along the facet normal, moved along the facet
//! by a tangential offset and turned by a small rotation (a wedge-shaped overlap, so the normal,
//! chord and point of application all move with `q`). Central differences with the outline
//! moved by `h = 10⁻³ δ` (translation `h`, rotation `2h/D_p`):
//!
//! - truncation `O(h²)`: the Jacobian changes over the penetration `δ`, so about `(h/δ)² = 10⁻⁶`
//!   of its largest entry;
//! - round-off: the law clips absolute coordinates (`X ≈ 1 m`), `ε_mach X/h ≈ 2·10⁻⁸` of it.
//!
//! Tolerance `10⁻⁵` of the largest entry: ten times the truncation bound. A Jacobian that misses
//! a term (the frozen normal, the slip coupling, the moving point, the implicit plastic
//! increment) is off by far more: each of those is at least `10⁻³` of the largest entry here,
//! checked against the frozen-geometry penalty tangent in the first test.
use nalgebra::SMatrix;

use super::contact_set::{self, ActiveContact, ContactHistory};
use super::dofs::{DofControl, DofMap};
use super::speed_tests::random;
use super::system::Model;
use crate::dem::mechanics::{Crushing, MechParams, PlasticState, SlipState};
use crate::dem::sample::Sample;

type M6 = SMatrix<f64, 6, 6>;

/// The pair (module docs).
struct Pair<'a> {
    s: &'a Sample,
    params: MechParams,
    /// The committed DOFs (zero unless a test sets them).
    c: [[f64; 3]; 2],
    i: usize,
    j: usize,
    n: [f64; 2],
    delta: f64,
}

impl<'a> Pair<'a> {
    fn new(s: &'a Sample, params: MechParams) -> Self {
        let map = DofMap::new(s, [[DofControl::Prescribed; 3]; 2]).unwrap();
        let model = Model::new(s, &params, map).unwrap();
        let b = s.beams.iter().position(|b| !model.map.is_slave(b.i) && !model.map.is_slave(b.j)).unwrap();
        let (i, j, n) = (s.beams[b].i, s.beams[b].j, s.beams[b].normal);
        Pair { s, params, c: [[0.0; 3]; 2], i, j, n, delta: 1e-4 * s.mean_diameter() }
    }

    /// j pressed by `δ`, moved along the facet by `tangential`, turned by `theta`.
    fn q(&self, tangential: f64, theta: f64) -> [[f64; 3]; 2] {
        let (n, d) = (self.n, self.delta);
        [[0.0; 3], [-d * n[0] - tangential * n[1], -d * n[1] + tangential * n[0], theta]]
    }

    fn contact(&self, q: [[f64; 3]; 2], old: ContactHistory) -> Option<ActiveContact> {
        contact_set::evaluate_pair(self.s, &self.params, self.i, self.j, q, self.c, old).unwrap()
    }

    fn exact(&self, q: [[f64; 3]; 2], old: ContactHistory) -> M6 {
        let a = self.contact(q, old).unwrap();
        contact_set::pair_jacobian(self.s, &self.params, &a, q, self.c, old)
    }

    /// Central differences of `F_n b + F_t c` (module docs).
    fn differences(&self, q: [[f64; 3]; 2], old: ContactHistory) -> M6 {
        let h = 1e-3 * self.delta;
        let d = [self.s.particles[self.i].diameter, self.s.particles[self.j].diameter];
        let mut jac = M6::zeros();
        for k in 0..6 {
            let step = if k % 3 == 2 { 2.0 * h / d[k / 3] } else { h };
            let f = [1.0, -1.0].map(|sign| {
                let mut qq = q;
                qq[k / 3][k % 3] += sign * step;
                self.contact(qq, old).unwrap().pair_forces()
            });
            jac.set_column(k, &((f[0] - f[1]) / (2.0 * step)));
        }
        jac
    }

    /// The exact Jacobian against the differences (module docs: tolerance 1e-5 of the largest
    /// entry); returns it.
    fn check(&self, q: [[f64; 3]; 2], old: ContactHistory, what: &str) -> M6 {
        let exact = self.exact(q, old);
        let fd = self.differences(q, old);
        let err = (exact - fd).amax() / exact.amax();
        assert!(err <= 1e-5, "{what}: |exact − differences| = {err:e} of the largest entry\n{exact}\n{fd}");
        // The value the dual numbers carry is the law's own force.
        let a = self.contact(q, old).unwrap();
        let pair = crate::dem::mechanics::contact_jacobian::PairShape {
            polygons: [&self.s.particles[self.i].polygon, &self.s.particles[self.j].polygon],
            centroids: [self.s.particles[self.i].centroid, self.s.particles[self.j].centroid],
            diameters: [self.s.particles[self.i].diameter, self.s.particles[self.j].diameter],
        };
        let trial = crate::dem::mechanics::contact_jacobian::PairTrial {
            committed: self.c,
            f_t: old.f_t,
            plastic: old.plastic,
            crush: a.crush,
        };
        let (value, _) =
            crate::dem::mechanics::contact_jacobian::pair_jacobian(&pair, &self.params, q, &trial).unwrap();
        let f = a.pair_forces();
        assert!((value - f).amax() <= 1e-12 * f.amax(), "{what}: value {value} vs the law's {f}");
        exact
    }
}

#[test]
fn sticking_and_sliding_contacts_match_central_differences() {
    let s = random(60, 3);
    let p = Pair::new(&s, MechParams::default());
    // Sticking: tangential offset 0.3 δ (trial k_t · 0.3 δ L-ish, inside μ F_n ≈ 0.6 κ L δ).
    let q = p.q(0.3 * p.delta, 5e-5);
    let a = p.contact(q, ContactHistory::default()).unwrap();
    assert_eq!(a.friction.state, SlipState::Stick);
    let stick = p.check(q, ContactHistory::default(), "stick");
    // The frozen-geometry tangent (penalty k_n b bᵀ + k_t c cᵀ) misses the moving normal and
    // point: it differs from the exact one by more than 10⁻³ of the largest entry.
    let c = &a.contact;
    let (b, t) = (c.normal_direction(), c.tangential_direction());
    let frozen = b * b.transpose() * c.k_n + t * t.transpose() * a.k_t;
    assert!((frozen - stick).amax() > 1e-3 * stick.amax(), "{}", (frozen - stick).amax() / stick.amax());
    // Sliding: offset 3 δ, beyond the cone.
    let q = p.q(3.0 * p.delta, 5e-5);
    assert_eq!(p.contact(q, ContactHistory::default()).unwrap().friction.state, SlipState::Slip);
    let slip = p.check(q, ContactHistory::default(), "slip");
    assert!((slip - stick).amax() > 1e-2 * stick.amax());
}

#[test]
fn a_contact_on_the_cone_takes_the_slip_branch() {
    // Committed on the cone (F_t,c = μ F_n) with no increment (q = c): the return map says
    // "stick" (|trial| = μ F_n), the Jacobian is the slip branch's: the differences with the committed
    // force 1 % outside the cone (F_t = μ F_n does not depend on the trial there), to the
    // module's tolerance; the stick branch's (the committed force at half the cone) differs
    // from it by more than 1 % of its largest entry.
    let s = random(60, 3);
    let mut p = Pair::new(&s, MechParams::default());
    let q = p.q(0.0, 5e-5);
    p.c = q;
    let f_n = p.contact(q, ContactHistory::default()).unwrap().contact.f_n;
    let old = ContactHistory { f_t: p.params.mu * f_n, plastic: Default::default() };
    assert_eq!(p.contact(q, old).unwrap().friction.state, SlipState::Stick);
    let on_cone = p.exact(q, old);
    let out = p.differences(q, ContactHistory { f_t: 1.01 * old.f_t, ..old });
    assert!((on_cone - out).amax() <= 1e-5 * on_cone.amax(), "{}", (on_cone - out).amax() / on_cone.amax());
    let stick = p.check(q, ContactHistory { f_t: 0.5 * old.f_t, ..old }, "inside the cone");
    assert!((stick - on_cone).amax() > 1e-2 * on_cone.amax());
}

#[test]
fn crushing_contacts_match_central_differences() {
    // σ_c = 10⁵ Pa against a contact pressure Ē δ/ℓ_c ≈ 2.5·10⁵ Pa: the first step is plastic
    // (the plastic increment from g(Δ) = 0, implicit in q). G_c = 10 J/m²: δ_u = 2·10⁻⁴ m, above
    // σ_c ℓ_c/Ē ≈ 5·10⁻⁶ m (no snap-back). Then elastic above a plastic depth 0.5 δ with
    // σ_c = 3·10⁵ Pa (pressure about 1.25·10⁵ Pa below the cap): the force at the pressure
    // centroid, which moves with q.
    let s = random(60, 3);
    let soft = MechParams { crushing: Some(Crushing { stress: 1e5, energy: 10.0 }), ..MechParams::default() };
    let p = Pair::new(&s, soft);
    let q = p.q(0.3 * p.delta, 5e-5);
    let a = p.contact(q, ContactHistory::default()).unwrap();
    assert!(a.crush.is_some_and(|u| u.plastic && u.f_n > 0.0), "{:?}", a.crush);
    p.check(q, ContactHistory::default(), "plastic");
    let hard = MechParams { crushing: Some(Crushing { stress: 3e5, energy: 10.0 }), ..MechParams::default() };
    let p = Pair::new(&s, hard);
    let old =
        ContactHistory { f_t: 0.0, plastic: PlasticState { depth: 0.5 * p.delta, kappa: 0.5 * p.delta, width: 0.0 } };
    let a = p.contact(q, old).unwrap();
    assert!(a.crush.is_some_and(|u| !u.plastic && u.f_n > 0.0), "{:?}", a.crush);
    p.check(q, old, "elastic above a plastic depth");
}
