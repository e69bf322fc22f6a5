//! The linear phase: Newton's first step taken as the equilibrium, without the residual that
//! would confirm it, where no contact is active at the committed state, at the start of the
//! iteration and at the end of the step (paper §2.1's lattice alone).
//!
//! ```text
//!   r(z) = f_ext + f_extra − K_b z − ε (z − z_commit)        (unknown rows; K_b: intact beams)
//!   M = K_b + diag ε  (the factorized operator, contact terms synced out)
//!   z₁ = z₀ + M⁻¹ r(z₀)          exact: r(z₁) = 0 to the solve's round-off
//! ```
//!
//! Without contacts the residual is affine in `z` and `M` is its exact Jacobian, so Newton's
//! first step from `z₀` lands on the equilibrium. Newton's method ([`super::equilibrium`]) then
//! evaluates the residual at `z₁` in its line search (a contact search, the beams' forces
//! `K_b Δz`, the residual) only to find it within the tolerance. The linear phase keeps the
//! contact search and skips the rest: the step is taken where the search finds no overlap at
//! `z₁` (otherwise the line search runs as before, counted in
//! `SolverProfile::linear_fallbacks`). It applies only to Newton's first iteration, from a start
//! where the residual evaluation found no contact, with a step its cap left whole (`max_move`: a
//! stone held by little more than the regularization moves in capped steps, and a long step
//! could carry a stone through a neighbour between two contact searches). The equilibria are
//! Newton's bit for bit: the same residual, operator, solve and contact searches, minus a
//! confirmation (the skipped residuals, evaluated over the paper wall's cyclic
//! tension–compression test, were at most 3.3·10⁻¹⁵ of the scale against the tolerance 10⁻⁸).
//! With a sparse right-hand side (updates in place, [`super::factor`], "Sparse right-hand
//! sides") the step leaves the residual entries it dropped, at most `10⁻⁵ · tol` of the scale.
//!
//! The closed-form `λ` of the next break ([`super::breaks`]) is read along this exact linear
//! path `z₀ → z₁`, and the state at the break is `z₀ + λ (z₁ − z₀)` ([`super::stage`]): between
//! breaks and in a break's release, the linear phase costs one beam-force product, one solve and
//! two contact searches per equilibrium. Off with `SolverOptions::linear_phase`.
use std::time::Instant;

use super::contact_set::{self, ActiveContact};
use super::diagnostics::Diagnostics;
use super::error::DemError;
use super::problem::Problem;
use super::profile;
use super::state::SolverState;
use super::workspace::Workspace;

/// Newton's first step `Δz` (over the unknowns, from a start without contacts, not capped)
/// taken as the equilibrium when the problem is linear over it (module docs): `true`, `z`
/// moved to `z + Δz`; `false`, `z` unchanged and Newton's method goes on as before.
pub(super) fn linear_step(
    pb: &Problem<'_>,
    state: &mut SolverState,
    ws: &mut Workspace,
    diag: &mut Diagnostics<'_>,
    dz: &[f64],
) -> Result<bool, DemError> {
    if !pb.opts.linear_phase || !state.committed_contacts.is_empty() {
        return Ok(false);
    }
    let mut z1 = state.z.clone();
    for (e, &zi) in pb.model.map.unknowns.iter().enumerate() {
        z1[zi] += dz[e];
    }
    if !contacts_at(pb, state, ws, diag, &z1)?.is_empty() {
        diag.profile.linear_fallbacks += 1;
        return Ok(false);
    }
    state.z = z1;
    diag.profile.linear_solves += 1;
    Ok(true)
}

/// The active contacts at `z` (the contact search of a residual evaluation, without the
/// forces).
fn contacts_at(
    pb: &Problem<'_>,
    state: &SolverState,
    ws: &mut Workspace,
    diag: &mut Diagnostics<'_>,
    z: &[f64],
) -> Result<Vec<ActiveContact>, DemError> {
    if !pb.opts.contacts || state.broken.is_empty() {
        return Ok(Vec::new());
    }
    let clock = Instant::now();
    let pairs = ws.candidates.candidates(pb.model.sample, &pb.model.map, z, &state.intact);
    diag.profile.pair_evaluations += pairs.len();
    diag.profile.candidate_rebuilds = ws.candidates.rebuilds;
    let m = &pb.model;
    let contacts = contact_set::evaluate(m.sample, &m.map, &m.params, &pairs, z, &state.z_commit, &state.histories)?;
    if !pairs.is_empty() {
        let touching: Vec<(usize, usize)> = contacts.iter().map(|a| (a.i, a.j)).collect();
        ws.candidates.refresh_apart(m.sample, &m.map, z, &touching);
    }
    profile::add(&mut diag.profile.evaluate_seconds, clock.elapsed());
    Ok(contacts)
}
