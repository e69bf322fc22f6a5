//! The consistent tangent of the equilibrium equations with contacts and friction, as an operator
//! on the unknowns (matrix-free), and how it relates to the factorized symmetric operator.
//!
//! ```text
//!   K_T = K_beams + Σ_contacts Gᵀ J_c G + diag(ε)
//! ```
//!
//! `J_c = ∂(F_n b + F_t c)/∂(q_i, q_j)` is each contact's 6×6 Jacobian, exact, by forward-mode
//! dual numbers through the contact law itself ([`contact_set::pair_jacobian`],
//! [`crate::dem::mechanics::contact_jacobian`]) at the current state and the committed friction
//! state. It holds the three parts a frozen-geometry tangent misses or simplifies: the exact area
//! gradient (`dF_n = Ē t_z/ℓ_c dS_r`), Coulomb's slip coupling (`dF_t = μ sign(F_t) dF_n`, not
//! symmetric) and the turning of the normal and the moving point of application (`F_n ∂b/∂q`,
//! which for a corner contact with a short chord is as large as the penalty term). At a kink of
//! the law (a contact reaching the Coulomb cone, a vertex reaching an edge) it is the one-sided
//! derivative of the branch the state lies on, the generalized Jacobian of semismooth Newton
//! (Alart & Curnier 1991; Hüeber, Stadler & Wohlmuth 2008); a contact on the cone (it slid at
//! the committed state and has not moved since) takes the slip branch's. `G` maps the pair to
//! the generalized coordinates ([`super::DofMap::pair_map`]).
//!
//! The factorized operator (beams, penalty `k_n w_b w_bᵀ`, tangential `k_t w_c w_cᵀ`, `ε`) is the
//! symmetric positive definite approximation of `K_T` used as GMRES preconditioner
//! ([`super::gmres`]); for flat sticking contacts the two agree. A sliding contact's tangent
//! replaces `k_t w_c w_cᵀ` by the slip coupling `μ sign(F_t) w_c (∂F_n)ᵀ`; how much of
//! `k_t w_c w_cᵀ` such a contact keeps in the factorized operator, and when a stick/slip flip
//! reaches the factor, is `SolverOptions::slip_terms` ([`super::slip_terms`]). With only sticking
//! contacts in it and the Woodbury path, each of the ~55 stick↔slip flips per Newton iteration
//! of a 10k-stone sample was a Woodbury column pair, and the rank cap forced a refactorization
//! nearly every iteration (`examples/dem_profile.rs`, 100 events of 10k stones: 262
//! factorizations and 4520 columns, against 20 and 338 with every contact's `k_t w_c w_cᵀ` kept).
//!
//! **Reused Jacobians.** A contact's `J_c` is kept ([`JacobianCache`]) with the states `q`, `c`
//! it was computed at, and reused while
//!
//! ```text
//!   Σ_{p = i, j} (|Δu_p| + |Δθ_p| D_p)  over both q and c   ≤   η S_r / L
//! ```
//!
//! (the motion of the pair's outlines since, against its mean penetration `S_r/L`, the length
//! over which `J_c` changes) and the contact's regime is the same (stick or slip and the slip
//! direction, crushing elastic or plastic). `η = 0` (the default, [`REUSE_FRACTION`])
//! recomputes every Jacobian. Reuse paid with central differences (twelve evaluations of the law
//! per Jacobian); the exact one costs about 2.6 µs against their 15 µs, and on the 1k sample
//! (`examples/dem_profile.rs 1000 2e-3 40`) `η = 10⁻²` left the Newton iterations as they were
//! (3,559) and saved no time (tangent 0.85 s against 0.90 s, 2-core AMD EPYC), so it is opt-in.
//! With reuse, every Jacobian is recomputed after [`FRESH_AFTER`] iterations of one
//! equilibrium (a contact crossing a geometric kink changes `J_c` more than its motion says).
//!
//! **On the cone.** A contact that slid at the last committed state starts the next equilibrium
//! on the Coulomb cone: with no slip increment yet, `|F_t| = μ F_n` and the return map reports
//! "stick". Either branch's derivative is a one-sided derivative there; the exact Jacobian takes
//! the slip branch's (`contact_jacobian::ON_CONE`), the direction the contact was sliding in.
//! The stick branch's instead cost 15 more Newton iterations on the same sample (3,574).
use std::collections::HashMap;

use nalgebra::{SMatrix, SVector};

use super::contact_set::{self, ActiveContact};
use super::error::DemError;
use super::state::SolverState;
use super::system::Model;
use crate::dem::mechanics::SlipState;

type V6 = SVector<f64, 6>;

/// The default reuse threshold `η` of contact Jacobians: none (see the module docs).
pub const REUSE_FRACTION: f64 = 0.0;

/// Newton iterations of one equilibrium after which every contact Jacobian is recomputed.
pub const FRESH_AFTER: usize = 6;

/// A contact's regime: stick/slip, `∂F_t/∂F_n` (the slip direction), crushing plastic.
type Regime = (SlipState, f64, bool);

#[derive(Clone, Debug)]
struct Cached {
    q: [[f64; 3]; 2],
    c: [[f64; 3]; 2],
    regime: Regime,
    jac: SMatrix<f64, 6, 6>,
}

/// Contact Jacobians kept between Newton iterations, by pair (see the module docs).
#[derive(Clone, Debug)]
pub struct JacobianCache {
    entries: HashMap<(usize, usize), Cached>,
    /// The reuse threshold `η` (0: never reuse).
    pub reuse_fraction: f64,
    /// Recompute every Jacobian (set by the Newton iteration after [`FRESH_AFTER`] iterations
    /// of one equilibrium: a stale `J_c` must not be what keeps it from converging).
    pub fresh_only: bool,
    /// Jacobians computed.
    pub computed: usize,
    /// Jacobians reused.
    pub reused: usize,
    /// Jacobians taken on the slip branch for contacts on the cone.
    pub on_cone: usize,
}

impl Default for JacobianCache {
    fn default() -> Self {
        JacobianCache {
            entries: HashMap::new(),
            reuse_fraction: REUSE_FRACTION,
            fresh_only: false,
            computed: 0,
            reused: 0,
            on_cone: 0,
        }
    }
}

impl JacobianCache {
    /// `J_c` of contact `a` at `q` with the committed `c`, `old`: the kept one when it may be
    /// reused, else a new one (kept when reuse is on).
    pub(super) fn jacobian(
        &mut self,
        model: &Model,
        a: &ActiveContact,
        q: [[f64; 3]; 2],
        c: [[f64; 3]; 2],
        old: contact_set::ContactHistory,
    ) -> Result<SMatrix<f64, 6, 6>, DemError> {
        let plastic = a.crush.as_ref().is_some_and(|u| u.plastic);
        // On the cone the slip branch's derivative (module docs; `contact_jacobian::ON_CONE`).
        let on_cone = a.sticks() && !a.sticks_off_cone(model.params.mu);
        let regime: Regime = if on_cone {
            self.on_cone += 1;
            (SlipState::Slip, model.params.mu * a.friction.f_t.signum(), plastic)
        } else {
            (a.friction.state, a.friction.d_ft_d_fn, plastic)
        };
        let depth = if a.contact.chord_length > 0.0 { a.contact.overlap_area / a.contact.chord_length } else { 0.0 };
        if let Some(e) = self.entries.get(&(a.i, a.j)).filter(|_| !self.fresh_only) {
            let d = [model.sample.particles[a.i].diameter, model.sample.particles[a.j].diameter];
            let moved: f64 = (0..2)
                .map(|k| {
                    let m = |x: [f64; 3], y: [f64; 3]| {
                        let (dx, dy) = (x[0] - y[0], x[1] - y[1]);
                        (dx * dx + dy * dy).sqrt() + (x[2] - y[2]).abs() * d[k]
                    };
                    m(q[k], e.q[k]) + m(c[k], e.c[k])
                })
                .sum();
            if e.regime == regime && self.reuse_fraction > 0.0 && moved <= self.reuse_fraction * depth {
                self.reused += 1;
                return Ok(e.jac);
            }
        }
        let jac = contact_set::pair_jacobian(model.sample, &model.params, a, q, c, old);
        self.computed += 1;
        if self.reuse_fraction > 0.0 {
            self.entries.insert((a.i, a.j), Cached { q, c, regime, jac });
        }
        Ok(jac)
    }

    /// Forgets the pairs that are not in `contacts`.
    fn keep_only(&mut self, contacts: &[ActiveContact]) {
        if self.entries.len() > contacts.len() {
            let live: std::collections::HashSet<(usize, usize)> = contacts.iter().map(|a| (a.i, a.j)).collect();
            self.entries.retain(|k, _| live.contains(k));
        }
    }
}

/// The full tangent `K_T` (see the module docs).
pub struct Tangent<'m, 'a> {
    model: &'m Model<'a>,
    intact: &'m [bool],
    reg: &'m [f64],
    contacts: Vec<([usize; 6], SMatrix<f64, 6, 6>)>,
}

impl<'m, 'a> Tangent<'m, 'a> {
    /// The tangent at the trial state of `state` with its evaluated `contacts`, whose friction
    /// trial starts from the committed state; `reg` the regularization; contact Jacobians from
    /// and into `cache`.
    pub fn new(
        model: &'m Model<'a>,
        state: &'m SolverState,
        reg: &'m [f64],
        contacts: &[ActiveContact],
        cache: &mut JacobianCache,
    ) -> Result<Self, DemError> {
        let (intact, z, z_commit, committed) = (&state.intact, &state.z, &state.z_commit, &state.histories);
        cache.keep_only(contacts);
        let map = &model.map;
        let mut terms = Vec::with_capacity(contacts.len());
        for a in contacts {
            let q = [map.particle_dofs(a.i, z), map.particle_dofs(a.j, z)];
            let c = [map.particle_dofs(a.i, z_commit), map.particle_dofs(a.j, z_commit)];
            let old = committed.get(&(a.i, a.j)).copied().unwrap_or_default();
            let jac = cache.jacobian(model, a, q, c, old)?;
            let (idx, g) = map.pair_map(a.i, a.j);
            terms.push((idx, g.transpose() * jac * g));
        }
        Ok(Tangent { model, intact, reg, contacts: terms })
    }

    /// `D = K_T − M` for the factorized operator `M` (see [`TangentDifference`]): per contact,
    /// its `Gᵀ J_c G` minus `held(i, j)`, the contact terms `M` holds for the pair (normal penalty
    /// and tangential stiffness, in the same `z` indices, [`super::DofMap::pair_map`]).
    pub fn difference(
        &self,
        contacts: &[ActiveContact],
        held: impl Fn(usize, usize) -> SMatrix<f64, 6, 6>,
    ) -> TangentDifference {
        let eq = &self.model.map.eq;
        let terms =
            contacts.iter().zip(&self.contacts).map(|(a, (idx, k))| (idx.map(|z| eq[z]), k - held(a.i, a.j))).collect();
        TangentDifference { terms }
    }

    /// The 6×6 terms of `K_T` with their `z` indices: the intact beams, then the contacts
    /// (`ε` apart).
    fn terms(&self) -> impl Iterator<Item = (&[usize; 6], &SMatrix<f64, 6, 6>)> {
        let beams = self.model.terms.iter().zip(self.intact).filter(|(_, &ok)| ok).map(|(t, _)| (&t.idx, &t.k));
        beams.chain(self.contacts.iter().map(|(idx, k)| (idx, k)))
    }

    /// `out = K_T v` (equations).
    pub fn apply(&self, v: &[f64], out: &mut [f64]) {
        let eq = &self.model.map.eq;
        for (o, (r, x)) in out.iter_mut().zip(self.reg.iter().zip(v)) {
            *o = r * x;
        }
        for (idx, k) in self.terms() {
            let x = V6::from_fn(|a, _| eq[idx[a]].map_or(0.0, |e| v[e]));
            let y = k * x;
            for a in 0..6 {
                if let Some(e) = eq[idx[a]] {
                    out[e] += y[a];
                }
            }
        }
    }
}

impl Tangent<'_, '_> {
    /// Solves `K_T x = b` (equations) by a sparse LU factorization of the assembled tangent
    /// (row pivoting; faer's supernodal LU): the direct solve that Newton's method falls back on
    /// when GMRES does not meet its tolerance ([`super::equilibrium`]). `None` when the tangent
    /// is numerically singular.
    pub fn solve_direct(&self, b: &[f64]) -> Option<Vec<f64>> {
        use faer::sparse::{SparseColMat, Triplet};
        let eq = &self.model.map.eq;
        let n = b.len();
        let mut entries: Vec<Triplet<usize, usize, f64>> = (0..n).map(|e| Triplet::new(e, e, self.reg[e])).collect();
        for (idx, k) in self.terms() {
            for a in 0..6 {
                let Some(r) = eq[idx[a]] else { continue };
                for c in 0..6 {
                    if let Some(col) = eq[idx[c]] {
                        entries.push(Triplet::new(r, col, k[(a, c)]));
                    }
                }
            }
        }
        let matrix = SparseColMat::<usize, f64>::try_new_from_triplets(n, n, &entries).ok()?;
        let lu = matrix.sp_lu().ok()?;
        let mut x = faer::Mat::<f64>::from_fn(n, 1, |i, _| b[i]);
        faer::linalg::solvers::SolveCore::solve_in_place_with_conj(&lu, faer::Conj::No, x.as_mut());
        let x: Vec<f64> = (0..n).map(|i| x[(i, 0)]).collect();
        x.iter().all(|v| v.is_finite()).then_some(x)
    }
}

/// The part of the tangent that the factorized operator `M` does not hold,
/// `D = K_T − M = Σ_contacts Gᵀ (J_c − k_n b₀ b₀ᵀ − k_t c₀ c₀ᵀ) G`, with `b₀`, `c₀` the directions the
/// contact's terms entered `M` with: the beams and `ε` are in both and cancel exactly, so a
/// product `D z` costs `O(contacts)`, against `O(beams)` for `K_T z`
/// ([`super::gmres::gmres_split`]).
pub struct TangentDifference {
    terms: Vec<([Option<usize>; 6], SMatrix<f64, 6, 6>)>,
}

impl TangentDifference {
    /// `out = D z` (equations).
    pub fn apply(&self, z: &[f64], out: &mut [f64]) {
        out.iter_mut().for_each(|o| *o = 0.0);
        for (eqs, k) in &self.terms {
            let x = V6::from_fn(|a, _| eqs[a].map_or(0.0, |e| z[e]));
            let y = k * x;
            for a in 0..6 {
                if let Some(e) = eqs[a] {
                    out[e] += y[a];
                }
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::dem::mechanics::MechParams;
    use crate::dem::sample::{RandomLayout, Sample, SampleConfig, SampleLayout, TinyFacetPolicy};
    use crate::dem::solver::dofs::{DofControl, DofMap};

    #[test]
    fn jacobians_are_reused_only_for_small_motions_in_the_same_regime() {
        // Two free stones of a random sample pushed together by δ = 10⁻⁴ D̄ across their shared
        // facet. With η = 10⁻²: a further motion of 10⁻⁴ δ reuses the kept J_c (and a fresh one
        // differs from it by less than 10⁻³ of its largest entry: the motion is 10⁻⁴ of the
        // penetration); a motion of 0.5 δ recomputes it; η = 0 always recomputes.
        let s = Sample::build(&SampleConfig {
            layout: SampleLayout::Random(RandomLayout {
                width: 1.0,
                height: 1.0,
                n_particles: 60,
                min_distance_factor: 0.7,
            }),
            thickness: 1.0,
            seed: 3,
            alpha: 0.8,
            facet_tolerance: 0.02,
            tiny_facets: TinyFacetPolicy::Merge,
        })
        .unwrap();
        let map = DofMap::new(&s, [[DofControl::Prescribed; 3]; 2]).unwrap();
        let model = Model::new(&s, &MechParams::default(), map).unwrap();
        let b = s.beams.iter().position(|b| !model.map.is_slave(b.i) && !model.map.is_slave(b.j)).unwrap();
        let (i, j, n) = (s.beams[b].i, s.beams[b].j, s.beams[b].normal);
        let delta = 1e-4 * s.mean_diameter();
        let at = |extra: f64| [[0.0; 3], [-(delta + extra * delta) * n[0], -(delta + extra * delta) * n[1], 0.0]];
        let contact = |q: [[f64; 3]; 2]| {
            contact_set::evaluate_pair(&s, &model.params, i, j, q, [[0.0; 3]; 2], Default::default()).unwrap().unwrap()
        };
        let c = [[0.0; 3]; 2];
        let mut cache = JacobianCache { reuse_fraction: 1e-2, ..Default::default() };
        let j0 = cache.jacobian(&model, &contact(at(0.0)), at(0.0), c, Default::default()).unwrap();
        assert_eq!((cache.computed, cache.reused), (1, 0));
        let j1 = cache.jacobian(&model, &contact(at(1e-4)), at(1e-4), c, Default::default()).unwrap();
        assert_eq!((cache.computed, cache.reused), (1, 1));
        assert_eq!(j0, j1);
        let fresh = contact_set::pair_jacobian(&s, &model.params, &contact(at(1e-4)), at(1e-4), c, Default::default());
        assert!((fresh - j1).amax() <= 1e-3 * fresh.amax(), "{}", (fresh - j1).amax() / fresh.amax());
        cache.jacobian(&model, &contact(at(0.5)), at(0.5), c, Default::default()).unwrap();
        assert_eq!((cache.computed, cache.reused), (2, 1));
        cache.reuse_fraction = 0.0;
        cache.jacobian(&model, &contact(at(0.5)), at(0.5), c, Default::default()).unwrap();
        assert_eq!((cache.computed, cache.reused), (3, 1));
    }
}
