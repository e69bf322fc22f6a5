//! The consistent tangent of the equilibrium equations with contacts and friction, as an operator
//! on the unknowns (matrix-free), and how it relates to the factorized symmetric operator.
//!
//! ```text
//!   K_T = K_beams + Σ_contacts Gᵀ J_c G + diag(ε)
//! ```
//!
//! `J_c = ∂(F_n b + F_t c)/∂(q_i, q_j)` is each contact's 6×6 Jacobian, by central differences of
//! the contact law itself ([`contact_set::pair_jacobian`]) at the current state and the committed
//! friction state. It holds the three parts a frozen-geometry tangent misses or simplifies:
//! the exact area gradient (`dF_n = Ē t_z/ℓ_c dS_r`), Coulomb's slip coupling
//! (`dF_t = μ sign(F_t) dF_n`, not symmetric) and the turning of the normal and the moving point
//! of application (`F_n ∂b/∂q`, which for a corner contact with a short chord is as large as the
//! penalty term). `G` maps the pair to the generalized coordinates ([`super::DofMap::pair_map`]).
//!
//! The factorized operator (beams, penalty `k_n w_b w_bᵀ`, sticking `k_t w_c w_cᵀ`, `ε`) is the
//! symmetric positive definite approximation of `K_T` used as GMRES preconditioner
//! ([`super::gmres`]); for flat sticking contacts the two agree.
use nalgebra::{SMatrix, SVector};

use super::contact_set::{self, ActiveContact};
use super::error::DemError;
use super::system::Model;

type V6 = SVector<f64, 6>;

/// The full tangent `K_T` (see the module docs).
pub struct Tangent<'m, 'a> {
    model: &'m Model<'a>,
    intact: &'m [bool],
    reg: &'m [f64],
    contacts: Vec<([usize; 6], SMatrix<f64, 6, 6>)>,
}

impl<'m, 'a> Tangent<'m, 'a> {
    /// The tangent at `z` with the evaluated `contacts`, whose friction trial starts from
    /// `z_commit` and the committed tangential forces `committed`.
    pub fn new(
        model: &'m Model<'a>,
        intact: &'m [bool],
        reg: &'m [f64],
        contacts: &[ActiveContact],
        z: &[f64],
        z_commit: &[f64],
        committed: &contact_set::Histories,
    ) -> Result<Self, DemError> {
        let map = &model.map;
        let mut terms = Vec::with_capacity(contacts.len());
        for a in contacts {
            let q = [map.particle_dofs(a.i, z), map.particle_dofs(a.j, z)];
            let c = [map.particle_dofs(a.i, z_commit), map.particle_dofs(a.j, z_commit)];
            let old = committed.get(&(a.i, a.j)).copied().unwrap_or_default();
            let jac = contact_set::pair_jacobian(model.sample, &model.params, a, q, c, old)?;
            let (idx, g) = map.pair_map(a.i, a.j);
            terms.push((idx, g.transpose() * jac * g));
        }
        Ok(Tangent { model, intact, reg, contacts: terms })
    }

    /// `out = K_T v` (equations).
    pub fn apply(&self, v: &[f64], out: &mut [f64]) {
        let eq = &self.model.map.eq;
        for (o, (r, x)) in out.iter_mut().zip(self.reg.iter().zip(v)) {
            *o = r * x;
        }
        let beams = self.model.terms.iter().zip(self.intact).filter(|(_, &ok)| ok).map(|(t, _)| (&t.idx, &t.k));
        let contacts = self.contacts.iter().map(|(idx, k)| (idx, k));
        for (idx, k) in beams.chain(contacts) {
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
