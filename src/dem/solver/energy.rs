//! The energy account of the stage loop ([`super::stage`]): what each recorded state carries,
//! and the check of a trial load step's balance.
//!
//! **Per committed state:** external work (trapezoid of the platen forces times the platen
//! displacement increments, prescribed and force-controlled DOFs), stored energy (intact beams
//! `½ zᵀK z`, contacts [`super::contact_set::ActiveContact::energy`]), dissipation = fracture (each beam's energy at
//! the moment it breaks) + friction (return-map dissipation) + relaxation (what the
//! re-equilibration at fixed load releases beyond the broken beam's own energy: the kinetic
//! energy a dynamic model would damp) + crushing (the plastic work of crushing contacts, with
//! [`crate::dem::mechanics::crushing`]). The relaxation term closes the balance over
//! re-equilibration steps by definition; the balance check is meaningful over the loading steps,
//! where `W_ext` and `E_stored` are computed independently (reactions vs. beam energies).
//!
//! **A trial step** ([`trial_step_imbalance`]): `ΔW − ΔU − ΔD` against the last recorded
//! state, with the same trapezoid, stored energy and dissipation as a commit would book (the
//! stage module's "Snaps inside a step").
use std::time::Instant;

use super::contact_set;
use super::diagnostics::Diagnostics;
use super::equilibrium::raise_reference_force;
use super::problem::Problem;
use super::profile;
use super::records::{FailureModeTag, StateKind, StateRecord};
use super::state::SolverState;

/// Platen generalized values `(U_x, U_y, Θ)` or forces, bottom then top.
type PlatenValues = [[f64; 3]; 2];

/// The external work from the recorded state `prev` to a state with platen values `platen` and
/// forces `force`: the trapezoid over the six platen DOFs.
fn step_work(prev: &StateRecord, platen: &PlatenValues, force: &PlatenValues) -> f64 {
    let mut w = 0.0;
    for k in 0..2 {
        for a in 0..3 {
            w += 0.5 * (prev.platen_force[k][a] + force[k][a]) * (platen[k][a] - prev.platen[k][a]);
        }
    }
    w
}

/// Intact beams' and active contacts' elastic energy at the trial state.
fn stored_energy(pb: &Problem<'_>, state: &SolverState) -> f64 {
    let beams: f64 =
        (0..state.intact.len()).filter(|&b| state.intact[b]).map(|b| pb.model.beam_energy(b, &state.z)).sum();
    beams + state.contacts.iter().map(|a| a.energy()).sum::<f64>()
}

/// The platen DOFs at the trial state and their generalized forces (the reactions of
/// prescribed DOFs): the platens' rows of the internal force, from the beams and contacts
/// that reach a platen only (the same sums as the whole internal force's rows, bit for bit).
fn platen_state(pb: &Problem<'_>, state: &SolverState) -> (PlatenValues, PlatenValues) {
    let mut f = vec![0.0; pb.model.map.n_z];
    pb.model.add_platen_beam_forces(&state.intact, &state.z, &mut f);
    let map = &pb.model.map;
    let touching = state.contacts.iter().filter(|a| map.is_slave(a.i) || map.is_slave(a.j));
    contact_set::add_contact_forces(map, touching, &mut f);
    let b = pb.model.map.platen_base;
    let at = |v: &[f64], k: usize| [v[b[k]], v[b[k] + 1], v[b[k] + 2]];
    ([at(&state.z, 0), at(&state.z, 1)], [at(&f, 0), at(&f, 1)])
}

/// Commits the trial state and records it.
pub(super) fn commit(pb: &Problem<'_>, state: &mut SolverState, diag: &mut Diagnostics<'_>, t: f64, kind: StateKind) {
    let clock = Instant::now();
    let (platen, pf) = platen_state(pb, state);
    if let Some(prev) = state.records.last() {
        state.energy.external += step_work(prev, &platen, &pf);
    }
    state.accept();
    raise_reference_force(state, &pf);
    let mut lateral_ux = [0.0; 2];
    let boundary = &pb.model.sample.boundary;
    for (s, set) in [&boundary.left, &boundary.right].into_iter().enumerate() {
        let sum: f64 = set.iter().map(|&p| pb.model.map.particle_dofs(p, &state.z)[0]).sum();
        lateral_ux[s] = sum / set.len().max(1) as f64;
    }
    let n_t = state.broken.iter().filter(|b| b.mode == FailureModeTag::Tension).count();
    let n_c = state.broken.iter().filter(|b| b.mode == FailureModeTag::Crushing).count();
    let stored = stored_energy(pb, state);
    if kind == StateKind::Relaxed {
        // Energy released by the re-equilibration beyond the broken beam's own energy.
        if let Some(prev) = state.records.last() {
            let before = prev.external_work - prev.stored - prev.dissipated.iter().sum::<f64>();
            let e = &state.energy;
            let now = e.external - stored - e.fracture - e.friction - e.relaxation - e.crushing;
            state.energy.relaxation += now - before;
        }
    }
    let e = state.energy;
    state.records.push(StateRecord {
        stage: state.stage,
        t,
        kind,
        platen,
        platen_force: pf,
        lateral_ux,
        broken: [state.broken.len(), n_t, state.broken.len() - n_t - n_c, n_c],
        contacts: state.contacts.len(),
        external_work: e.external,
        stored,
        dissipated: [e.fracture, e.friction, e.relaxation, e.crushing],
    });
    profile::add(&mut diag.profile.commit_seconds, clock.elapsed());
    if let (Some(observer), Some(record)) = (diag.observer.as_mut(), state.records.last()) {
        observer.recorded(state.records.len() - 1, record, &state.z);
        observer.profiled(state.records.len() - 1, &diag.profile);
    }
}

/// The energy imbalance `ΔW − ΔU − ΔD` of the trial state against the last recorded one, and
/// the scale it is measured against, `max(W, U)` there.
pub(super) fn trial_step_imbalance(pb: &Problem<'_>, state: &SolverState) -> (f64, f64) {
    let Some(prev) = state.records.last() else { return (0.0, 0.0) };
    let (platen, pf) = platen_state(pb, state);
    let dissipated: f64 = state.contacts.iter().map(|a| a.friction.dissipation + a.crushing_dissipation()).sum();
    let imbalance = step_work(prev, &platen, &pf) - (stored_energy(pb, state) - prev.stored) - dissipated;
    (imbalance, prev.external_work.max(prev.stored))
}
