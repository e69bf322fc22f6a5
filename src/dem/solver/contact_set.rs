//! Contacts and friction between stones not bonded by an intact beam (paper §2.1, eqs. 3–5).
//!
//! **Candidates.** Pairs whose beam is broken, plus pairs of stones whose current bounding
//! boxes overlap, found with a uniform grid of cell size = the largest box (each stone is
//! entered in every cell its box touches; a pair is tested once). Pairs with an intact beam are
//! skipped: the bond carries their interaction.
//!
//! **Evaluation.** For each candidate, [`mechanics::contact`] on the *current* polygons
//! (`Particle::polygon` moved rigidly by `q`) gives `F_n`, the normal `n_c`, the point `x_c` and
//! the penalty stiffness `k_n`. Friction: the trial force is the committed `F_t` plus
//! `k_t Δg_t`, `Δg_t` the tangential slip of the increment from the last committed equilibrium
//! state (rotations included), followed by the Coulomb return map ([`mechanics::friction_update`]).
//! Internal forces `F_n b + F_t c` ([`Contact::normal_forces`], [`Contact::tangential_forces`]).
//!
//! **Crushing (optional, [`mechanics::crushing`]).** With `MechParams::crushing`, the normal
//! force is bounded by the crushing return map from the committed plastic state of the pair
//! (uniform plastic depth `δ_p` of the Winkler layer, accumulated plastic penetration `κ_p`):
//! `F_n = κ ∫ (δ(s) − δ_p)₊ ds ≤ σ_c L t_z (1 − κ_p/δ_u)₊`, acting at the centroid of that
//! pressure (moved along the chord from the overlap centroid; its normal coordinate is kept),
//! with the potential `½ κ ∫ (δ − δ_p)₊² ds` stored as `F_n²/(2 k_n)` plus the wedge energy;
//! friction then uses this `F_n`. The committed
//! history of a pair ([`ContactHistory`]: `F_t` and the plastic state) survives while the stones
//! are apart, so a crushed joint that reopens and closes again starts from its plastic state.
//!
//! **Stored energy.** The normal energy is the potential of the normal law read as a Winkler
//! layer along the chord, `½ κ ∫δ(s)² ds` = `F_n²/(2 k_n)` (uniform part; for a flat strip
//! `S_r = L δ`, `F_n = k_n δ`) `+ U_w` (the wedge energy of an overlap whose thickness varies
//! along the chord, [`mechanics::Contact::wedge_energy`]); the elastic tangential energy is
//! `F_t²/(2 k_t)`. Counting only `F_n²/(2 k_n)` misses the work of the contact moment
//! `k_n L² φ/12` of a relative rotation `φ` (stones rocking on a joint in shear).
use std::collections::{BTreeMap, BTreeSet};

use super::dofs::DofMap;
use super::error::DemError;
use crate::dem::mechanics::contact_jacobian::{self, PairShape, PairTrial};
use crate::dem::mechanics::{self, Contact, FrictionUpdate, MechParams, SlipState};
use crate::dem::polygon::Polygon;
use crate::dem::sample::Sample;
use nalgebra::{SMatrix, SVector};

/// The committed history of a pair: its tangential force and its plastic (crushing) state.
#[derive(Clone, Copy, Debug, Default, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct ContactHistory {
    /// Committed tangential force `F_t` (N).
    pub f_t: f64,
    /// Committed plastic state ([`mechanics::crushing`]), zero without crushing.
    pub plastic: mechanics::PlasticState,
}

/// The committed histories, by pair `(i < j)`.
pub type Histories = BTreeMap<(usize, usize), ContactHistory>;

/// An active contact in a trial state.
#[derive(Clone, Debug, serde::Serialize, serde::Deserialize)]
pub struct ActiveContact {
    /// First stone (lower index).
    pub i: usize,
    /// Second stone.
    pub j: usize,
    /// Normal contact.
    pub contact: Contact,
    /// Friction return map result.
    pub friction: FrictionUpdate,
    /// Tangential stiffness used.
    pub k_t: f64,
    /// The crushing update of the normal force (`None` without crushing).
    pub crush: Option<mechanics::CrushUpdate>,
}

impl ActiveContact {
    /// Whether the contact sticks.
    pub fn sticks(&self) -> bool {
        self.friction.state == SlipState::Stick
    }

    /// Whether the contact sticks off the Coulomb cone: a sticking trial within
    /// [`contact_jacobian::ON_CONE`] of `μ F_n` (a contact that slid at the committed state and
    /// has not moved since) takes the slip branch's tangent ([`super::tangent`], "On the cone").
    pub fn sticks_off_cone(&self, mu: f64) -> bool {
        let limit = mu * self.contact.f_n;
        self.sticks() && !(limit > 0.0 && self.friction.f_t.abs() >= (1.0 - contact_jacobian::ON_CONE) * limit)
    }

    /// The history to commit for this pair.
    pub fn history(&self) -> ContactHistory {
        ContactHistory { f_t: self.friction.f_t, plastic: self.crush.map_or(Default::default(), |c| c.state) }
    }

    /// Energy dissipated by crushing in the increment (J).
    pub fn crushing_dissipation(&self) -> f64 {
        self.crush.map_or(0.0, |c| c.dissipation)
    }

    /// Stored elastic energy `F_n²/(2k_n) + U_w + F_t²/(2k_t)` (module docs).
    pub fn energy(&self) -> f64 {
        let c = &self.contact;
        let en = if c.k_n > 0.0 { 0.5 * c.f_n * c.f_n / c.k_n } else { 0.0 };
        en + c.wedge_energy + 0.5 * self.friction.f_t * self.friction.f_t / self.k_t
    }
}

/// The current polygon of stone `p` for its DOFs `q`.
fn current_polygon(sample: &Sample, p: usize, q: [f64; 3]) -> Polygon {
    let part = &sample.particles[p];
    part.polygon.moved(part.centroid, [q[0], q[1]], q[2])
}

/// The axis-aligned bounding box `[x_min, y_min, x_max, y_max]` of a polygon.
pub(super) fn bounding_box(poly: &Polygon) -> [f64; 4] {
    poly.vertices.iter().fold([f64::MAX, f64::MAX, f64::MIN, f64::MIN], |b, v| {
        [b[0].min(v[0]), b[1].min(v[1]), b[2].max(v[0]), b[3].max(v[1])]
    })
}

/// The pairs `(i < j)` whose boxes overlap within `tol`, in increasing order: a uniform grid
/// broad phase whose cell is the largest box side, so each box touches at most 2 × 2 cells and
/// every overlapping pair shares at least one cell.
pub(super) fn overlapping_boxes(boxes: &[[f64; 4]], tol: f64) -> BTreeSet<(usize, usize)> {
    let cell = boxes.iter().fold(0.0f64, |m, b| m.max(b[2] - b[0]).max(b[3] - b[1])).max(1e-12);
    let (x0, y0) = boxes.iter().fold((f64::MAX, f64::MAX), |m, b| (m.0.min(b[0]), m.1.min(b[1])));
    let mut grid: BTreeMap<(i64, i64), Vec<usize>> = BTreeMap::new();
    for (p, b) in boxes.iter().enumerate() {
        let (ia, ib) = (((b[0] - x0) / cell) as i64, ((b[2] - x0) / cell) as i64);
        let (ja, jb) = (((b[1] - y0) / cell) as i64, ((b[3] - y0) / cell) as i64);
        for gi in ia..=ib {
            for gj in ja..=jb {
                grid.entry((gi, gj)).or_default().push(p);
            }
        }
    }
    let mut pairs = BTreeSet::new();
    for list in grid.values() {
        for (a, &p) in list.iter().enumerate() {
            for &q in &list[a + 1..] {
                let (i, j) = if p < q { (p, q) } else { (q, p) };
                let (bi, bj) = (&boxes[i], &boxes[j]);
                if bi[0] <= bj[2] + tol && bj[0] <= bi[2] + tol && bi[1] <= bj[3] + tol && bj[1] <= bi[3] + tol {
                    pairs.insert((i, j));
                }
            }
        }
    }
    pairs
}

/// Candidate pairs `(i < j)` without an intact beam (see the module docs).
pub fn candidates(sample: &Sample, map: &DofMap, z: &[f64], intact: &[bool]) -> Vec<(usize, usize)> {
    let mut set: BTreeSet<(usize, usize)> = BTreeSet::new();
    for (b, beam) in sample.beams.iter().enumerate() {
        if !intact[b] {
            set.insert((beam.i, beam.j));
        }
    }
    // Bounding boxes of the current polygons.
    let n = sample.particles.len();
    let boxes: Vec<[f64; 4]> =
        (0..n).map(|p| bounding_box(&current_polygon(sample, p, map.particle_dofs(p, z)))).collect();
    // A small tolerance so stones that touch along an edge (zero overlap) are candidates.
    let cell = boxes.iter().fold(0.0f64, |m, b| m.max(b[2] - b[0]).max(b[3] - b[1])).max(1e-12);
    for (i, j) in overlapping_boxes(&boxes, 1e-9 * cell) {
        if map.is_slave(i) && map.is_slave(j) && same_platen(sample, i, j) {
            continue;
        }
        match sample.beam_between(i, j) {
            Some(b) if intact[b] => {}
            _ => {
                set.insert((i, j));
            }
        }
    }
    let mut v: Vec<_> = set.into_iter().collect();
    v.sort_unstable();
    v
}

fn same_platen(sample: &Sample, i: usize, j: usize) -> bool {
    let b = &sample.boundary;
    (b.bottom.contains(&i) && b.bottom.contains(&j)) || (b.top.contains(&i) && b.top.contains(&j))
}

/// Evaluates the candidate pairs at `z`, with friction trial states from the committed tangential
/// forces and plastic penetrations `committed` and the committed coordinates `z_commit`.
pub fn evaluate(
    sample: &Sample,
    map: &DofMap,
    params: &MechParams,
    pairs: &[(usize, usize)],
    z: &[f64],
    z_commit: &[f64],
    committed: &Histories,
) -> Result<Vec<ActiveContact>, DemError> {
    let mut out = Vec::new();
    for &(i, j) in pairs {
        let q = [map.particle_dofs(i, z), map.particle_dofs(j, z)];
        let c = [map.particle_dofs(i, z_commit), map.particle_dofs(j, z_commit)];
        let old = committed.get(&(i, j)).copied().unwrap_or_default();
        if let Some(a) = evaluate_pair(sample, params, i, j, q, c, old)? {
            out.push(a);
        }
    }
    Ok(out)
}

/// The contact of stones `i`, `j` at DOFs `q = [q_i, q_j]`, with the friction trial from the
/// committed DOFs `c` and the committed history `old`; `None` without overlap.
pub fn evaluate_pair(
    sample: &Sample,
    params: &MechParams,
    i: usize,
    j: usize,
    q: [[f64; 3]; 2],
    c: [[f64; 3]; 2],
    old: ContactHistory,
) -> Result<Option<ActiveContact>, DemError> {
    let [qi, qj] = q;
    let (pi, pj) = (&sample.particles[i], &sample.particles[j]);
    let err = |source| DemError::Contact { i, j, source };
    let ri = [pi.centroid[0] + qi[0], pi.centroid[1] + qi[1]];
    let rj = [pj.centroid[0] + qj[0], pj.centroid[1] + qj[1]];
    let contact = mechanics::contact(
        &current_polygon(sample, i, qi),
        &current_polygon(sample, j, qj),
        ri,
        rj,
        pi.diameter,
        pj.diameter,
        params,
    )
    .map_err(err)?;
    let Some(mut contact) = contact else { return Ok(None) };
    let crush = match &params.crushing {
        Some(cr) => {
            let u = cr
                .update(&contact.profile, contact.chord_length, params.e_bar, contact.l_c, params.t_z, old.plastic)
                .map_err(err)?;
            if u.plastic || u.state.depth > 0.0 {
                // The layer above the plastic depth (module docs, "Crushing"): the force at its
                // pressure centroid, its potential ½κ∫(δ − δ_p)₊² as F_n²/(2k_n) + U_w.
                let k = params.e_bar * params.t_z / contact.l_c;
                let c = contact.profile.clipped(u.state.depth);
                if c.area > 0.0 {
                    let t = contact.tangent();
                    let shift = c.first / c.area - (contact.point[0] * t[0] + contact.point[1] * t[1]);
                    contact.point = [contact.point[0] + shift * t[0], contact.point[1] + shift * t[1]];
                    contact.arm_i = [contact.arm_i[0] + shift * t[0], contact.arm_i[1] + shift * t[1]];
                    contact.arm_j = [contact.arm_j[0] + shift * t[0], contact.arm_j[1] + shift * t[1]];
                }
                let uniform = if contact.k_n > 0.0 { 0.5 * u.f_n * u.f_n / contact.k_n } else { 0.0 };
                contact.wedge_energy = 0.5 * k * c.second - uniform;
            }
            contact.f_n = u.f_n;
            Some(u)
        }
        None => None,
    };
    let [ci, cj] = c;
    let dqi = [qi[0] - ci[0], qi[1] - ci[1], qi[2] - ci[2]];
    let dqj = [qj[0] - cj[0], qj[1] - cj[1], qj[2] - cj[2]];
    let dg = contact.tangential_increment(dqi, dqj);
    let k_t = (params.kt_over_kn * contact.k_n).max(f64::MIN_POSITIVE);
    let friction = mechanics::friction_update(old.f_t, dg, k_t, params.mu, contact.f_n).map_err(err)?;
    Ok(Some(ActiveContact { i, j, contact, friction, k_t, crush }))
}

impl ActiveContact {
    /// The internal generalized forces `F_n b + F_t c` on `(q_i, q_j)`.
    pub fn pair_forces(&self) -> SVector<f64, 6> {
        self.contact.normal_direction() * self.contact.f_n + self.contact.tangential_direction() * self.friction.f_t
    }
}

/// The 6×6 Jacobian `J_c = ∂(F_n b + F_t c)/∂(q_i, q_j)` of contact `a` at DOFs `q`, with the
/// same committed state `c`, `old`: exact, by forward-mode dual numbers through the contact law
/// ([`mechanics::contact_jacobian`]): the area gradient, the friction return map, the turning
/// normal and the moving point of application, crushing; at a kink the one-sided derivative of
/// the branch the state lies on, and on the Coulomb cone the slip branch's.
pub fn pair_jacobian(
    sample: &Sample,
    params: &MechParams,
    a: &ActiveContact,
    q: [[f64; 3]; 2],
    c: [[f64; 3]; 2],
    old: ContactHistory,
) -> SMatrix<f64, 6, 6> {
    let (pi, pj) = (&sample.particles[a.i], &sample.particles[a.j]);
    let shape = PairShape {
        polygons: [&pi.polygon, &pj.polygon],
        centroids: [pi.centroid, pj.centroid],
        diameters: [pi.diameter, pj.diameter],
    };
    let trial = PairTrial { committed: c, f_t: old.f_t, plastic: old.plastic, crush: a.crush };
    contact_jacobian::pair_jacobian(&shape, params, q, &trial).map_or_else(SMatrix::zeros, |(_, j)| j)
}

/// Adds the internal contact and friction forces to `out` (length `n_z`).
pub fn add_contact_forces<'c>(map: &DofMap, contacts: impl IntoIterator<Item = &'c ActiveContact>, out: &mut [f64]) {
    for a in contacts {
        let (ni, nj) = a.contact.normal_forces();
        let (ti, tj) = a.contact.tangential_forces(a.friction.f_t);
        map.scatter_force(a.i, [ni[0] + ti[0], ni[1] + ti[1], ni[2] + ti[2]], out);
        map.scatter_force(a.j, [nj[0] + tj[0], nj[1] + tj[1], nj[2] + tj[2]], out);
    }
}
