//! Where a load step meets its first contact event (the module docs of [`super::stage`],
//! "Contact events"): a contact that starts to slide, closes or opens inside the step.
use std::collections::{BTreeMap, BTreeSet};

use super::contact_set::ActiveContact;
use super::problem::Problem;
use super::state::SolverState;
use crate::dem::mechanics::beam::stack;

/// The first contact event along the step `z_old → z` (`z` the converged end of a trial
/// step), as the fraction `λ ∈ (0, 1)` of the step, estimated along the straight line
/// (module docs, "Contact events"); `None` without an event inside the step.
pub(super) fn first_contact_event(pb: &Problem<'_>, state: &SolverState, z_old: &[f64]) -> Option<f64> {
    let map = &pb.model.map;
    let mu = pb.model.params.mu;
    let dq = |i: usize, j: usize| {
        let (qi, qj) = (map.particle_dofs(i, &state.z), map.particle_dofs(j, &state.z));
        let (oi, oj) = (map.particle_dofs(i, z_old), map.particle_dofs(j, z_old));
        stack([qi[0] - oi[0], qi[1] - oi[1], qi[2] - oi[2]], [qj[0] - oj[0], qj[1] - oj[1], qj[2] - oj[2]])
    };
    let depth = |a: &ActiveContact| {
        if a.contact.chord_length > 0.0 {
            a.contact.overlap_area / a.contact.chord_length
        } else {
            0.0
        }
    };
    let old: BTreeMap<(usize, usize), &ActiveContact> =
        state.committed_contacts.iter().map(|a| ((a.i, a.j), a)).collect();
    let now: BTreeSet<(usize, usize)> = state.contacts.iter().map(|a| (a.i, a.j)).collect();
    let mut best: Option<f64> = None;
    let mut consider = |l: f64| {
        if l > 0.0 && l < 1.0 && best.is_none_or(|b| l < b) {
            best = Some(l);
        }
    };
    for a in &state.contacts {
        match old.get(&(a.i, a.j)) {
            Some(o) if o.sticks() && !a.sticks() => {
                // |F_t,0 + λ (F_trial − F_t,0)| = μ (F_n,0 + λ (F_n − F_n,0))
                let (f0, n0) = (o.friction.f_t, o.contact.f_n);
                let trial = a.friction.f_t + a.k_t * a.friction.slip;
                let sign = trial.signum();
                let (num, den) = (mu * n0 - sign * f0, sign * (trial - f0) - mu * (a.contact.f_n - n0));
                if num > 0.0 && den > num {
                    consider(num / den);
                }
            }
            Some(_) => {}
            None => {
                // Closing: the approach b·Δq of the step against the depth S_r/L reached.
                let approach = a.contact.normal_direction().dot(&dq(a.i, a.j));
                if approach > depth(a) {
                    consider(1.0 - depth(a) / approach);
                }
            }
        }
    }
    for o in state.committed_contacts.iter().filter(|o| !now.contains(&(o.i, o.j))) {
        // Opening: the separation −b·Δq against the committed depth.
        let separation = -o.contact.normal_direction().dot(&dq(o.i, o.j));
        if separation > depth(o) {
            consider(depth(o) / separation);
        }
    }
    best
}
