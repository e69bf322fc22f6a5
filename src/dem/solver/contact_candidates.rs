//! The candidate pairs of the contact search, kept between residual evaluations: a Verlet list
//! with a separation bound per pair.
//!
//! The contact law is evaluated for the pairs without an intact beam whose polygons may overlap
//! ([`super::contact_set`]). Searching them from scratch at every residual evaluation (every stone
//! moved, a grid of bounding boxes, the polygon clipping of every pair of touching boxes, most of
//! them second neighbours that never touch) costs `O(n)` clippings per evaluation and dominated
//! the large samples. Instead:
//!
//! **List.** At an anchor state `z_a`, every pair `(i < j)` whose bounding boxes, each grown by
//! the margin `h` on every side, overlap is listed (except two stones of one platen without a
//! beam: they move together), with its beam (if any) and its separation `g_ij` at `z_a`: the
//! largest gap between the projections of the two polygons on an edge normal of either
//! (separating axis theorem: convex polygons are apart iff some edge normal separates them, and
//! `g > 0` is then a lower bound of their distance).
//!
//! **Motion bound.** A rigid motion `q_a → q` moves every point of stone `p` by at most
//!
//! ```text
//!   δ_p = |u − u_a| + |θ − θ_a| R_p        (R_p = largest centroid–vertex distance;
//!                                            |R(θ) − R(θ_a)| = 2 |sin(Δθ/2)| ≤ |Δθ|)
//! ```
//!
//! **Query at `z`.** If some `δ_p > h`, the list is rebuilt at `z`. Otherwise a pair whose boxes
//! overlap now had grown boxes that overlapped at the anchor (each box moved by at most `δ ≤ h`),
//! so it is listed; and a listed pair can overlap only if their outlines have closed the gap
//! `g_ij` on its (fixed) separating axis `n`. Points of stone `p` move by `Δu_p + (R(Δθ_p) − I)(x − c_p)`,
//! so the projection gap on `n` closes by at most the *relative* motion
//!
//! ```text
//!   δ_ij = |Δu_i − Δu_j| + |Δθ_i| R_i + |Δθ_j| R_j      (Δ: since the anchor)
//! ```
//!
//! (the uniform part of the motion, which grows across a loaded sample, cancels). The candidates
//! are the listed pairs without an intact beam and with `δ_ij + τ ≥ g_ij` (`τ = 10⁻⁹ D̄` against
//! round-off), in `(i, j)` order: the pairs skipped are pairs the contact law would find apart,
//! so the contacts are exactly those of a search from scratch
//! ([`super::contact_set::candidates`]; compared in the tests below).
//!
//! **Refresh.** The bound holds from any state where the pair's separation was measured, not only
//! from the list's anchor. A pair the contact law found apart is re-anchored there, with its
//! separation there (when positive): a crack that opened (its beam broken, the two stones
//! bonded at the list's anchor, `g_ij ≈ 0`) is then skipped until its two stones have moved,
//! relative to each other, by its opening.

use super::dofs::DofMap;
use crate::dem::polygon::{Polygon, P2};
use crate::dem::sample::Sample;

/// The margin `h` as a fraction of the mean stone diameter: larger lists, fewer rebuilds (a
/// uniaxial test to 2·10⁻³ strain moves the top row by 0.2 D̄ on a sample of 100 × 100 stones).
pub const MARGIN_FRACTION: f64 = 0.1;

/// A listed pair.
#[derive(Clone, Copy, Debug, PartialEq)]
struct Pair {
    i: usize,
    j: usize,
    beam: Option<usize>,
    /// The separation `g_ij` at the pair's anchor.
    gap: f64,
    /// The two stones' DOFs at the pair's anchor (the list's anchor, or where the pair was last
    /// found apart, [`CandidateList::refresh_apart`]).
    at: [[f64; 3]; 2],
}

/// The candidate list of one solver (built at the first query).
#[derive(Clone, Debug, Default)]
pub struct CandidateList {
    /// Each stone's DOFs `q_p` at the anchor.
    anchor: Vec<[f64; 3]>,
    /// Each stone's `R_p` (m).
    radius: Vec<f64>,
    /// `h` (m).
    margin: f64,
    /// Round-off guard `τ` (m).
    guard: f64,
    pairs: Vec<Pair>,
    /// Each stone's `δ_p` at the last query (scratch).
    moved: Vec<f64>,
    /// The listed pairs returned by the last query, by index in `pairs`.
    last: Vec<usize>,
    /// Lists built (the first one included).
    pub rebuilds: usize,
    /// Refreshes of the pairs found apart ([`Self::refresh_apart`]).
    pub refreshes: usize,
}

/// The current polygon of stone `p` for its DOFs `q`.
fn current_polygon(sample: &Sample, p: usize, q: [f64; 3]) -> Polygon {
    let part = &sample.particles[p];
    part.polygon.moved(part.centroid, [q[0], q[1]], q[2])
}

/// The separation of two convex polygons (either orientation): the largest gap between their
/// projections on the unit edge normals of either; positive iff they are apart.
pub fn separation(a: &Polygon, b: &Polygon) -> f64 {
    let mut best = f64::NEG_INFINITY;
    for (p, q) in [(a, b), (b, a)] {
        let v = &p.vertices;
        let n = v.len();
        let twice_area: f64 = (0..n).map(|k| v[k][0] * v[(k + 1) % n][1] - v[(k + 1) % n][0] * v[k][1]).sum();
        let orient = if twice_area < 0.0 { -1.0 } else { 1.0 };
        for k in 0..n {
            let (s, e) = (v[k], v[(k + 1) % n]);
            let d: P2 = [e[0] - s[0], e[1] - s[1]];
            let len = d[0].hypot(d[1]);
            if len == 0.0 {
                continue;
            }
            // Outward unit normal of a counter-clockwise edge: (d_y, −d_x)/|d|.
            let nu = [orient * d[1] / len, -orient * d[0] / len];
            // The edge's own line bounds a convex polygon; the maximum over all vertices keeps
            // the bound valid for outlines convex only to round-off.
            let top = v.iter().map(|w| nu[0] * w[0] + nu[1] * w[1]).fold(nu[0] * s[0] + nu[1] * s[1], f64::max);
            let low = q.vertices.iter().map(|w| nu[0] * w[0] + nu[1] * w[1]).fold(f64::INFINITY, f64::min);
            best = best.max(low - top);
        }
    }
    best
}

fn same_platen(sample: &Sample, i: usize, j: usize) -> bool {
    let b = &sample.boundary;
    (b.bottom.contains(&i) && b.bottom.contains(&j)) || (b.top.contains(&i) && b.top.contains(&j))
}

impl CandidateList {
    /// Rebuilds the list at `z` (see the module docs).
    fn rebuild(&mut self, sample: &Sample, map: &DofMap, z: &[f64]) {
        let n = sample.particles.len();
        if self.radius.len() != n {
            self.radius = sample
                .particles
                .iter()
                .map(|p| {
                    p.polygon
                        .vertices
                        .iter()
                        .map(|v| (v[0] - p.centroid[0]).hypot(v[1] - p.centroid[1]))
                        .fold(0.0, f64::max)
                })
                .collect();
            let d = sample.mean_diameter();
            self.margin = MARGIN_FRACTION * d;
            self.guard = 1e-9 * d;
        }
        self.anchor = (0..n).map(|p| map.particle_dofs(p, z)).collect();
        let polys: Vec<Polygon> = (0..n).map(|p| current_polygon(sample, p, self.anchor[p])).collect();
        let h = self.margin;
        let boxes: Vec<[f64; 4]> = polys
            .iter()
            .map(|poly| {
                let b = super::contact_set::bounding_box(poly);
                [b[0] - h, b[1] - h, b[2] + h, b[3] + h]
            })
            .collect();
        let found = super::contact_set::overlapping_boxes(&boxes, 0.0);
        self.pairs.clear();
        for (i, j) in found {
            let beam = sample.beam_between(i, j);
            if beam.is_none() && map.is_slave(i) && map.is_slave(j) && same_platen(sample, i, j) {
                continue;
            }
            let at = [self.anchor[i], self.anchor[j]];
            self.pairs.push(Pair { i, j, beam, gap: separation(&polys[i], &polys[j]), at });
        }
        self.rebuilds += 1;
    }

    /// The candidate pairs `(i < j)` at `z` for the beams `intact` (see the module docs).
    pub fn candidates(&mut self, sample: &Sample, map: &DofMap, z: &[f64], intact: &[bool]) -> Vec<(usize, usize)> {
        let n = sample.particles.len();
        let mut fresh = self.anchor.len() != n;
        if !fresh {
            self.moved.resize(n, 0.0);
            for p in 0..n {
                let (q, a) = (map.particle_dofs(p, z), self.anchor[p]);
                // |Δu| by sqrt(Δx² + Δy²): within an ulp of `hypot` (no overflow at these sizes), and
                // the bound carries the guard τ.
                let (dx, dy) = (q[0] - a[0], q[1] - a[1]);
                self.moved[p] = (dx * dx + dy * dy).sqrt() + (q[2] - a[2]).abs() * self.radius[p];
            }
            fresh = self.moved.iter().any(|&d| d > self.margin);
        }
        if fresh {
            self.rebuild(sample, map, z);
            self.moved.clear();
            self.moved.resize(n, 0.0);
        }
        let (radius, guard) = (&self.radius, self.guard);
        let closing = |c: &Pair| {
            // The relative motion bound of the module docs since the pair's anchor,
            // |Δu_i − Δu_j| + |Δθ_i| R_i + |Δθ_j| R_j.
            let (qi, qj) = (map.particle_dofs(c.i, z), map.particle_dofs(c.j, z));
            let [ai, aj] = c.at;
            let (dx, dy) = ((qi[0] - ai[0]) - (qj[0] - aj[0]), (qi[1] - ai[1]) - (qj[1] - aj[1]));
            (dx * dx + dy * dy).sqrt() + (qi[2] - ai[2]).abs() * radius[c.i] + (qj[2] - aj[2]).abs() * radius[c.j]
        };
        self.last.clear();
        for (k, c) in self.pairs.iter().enumerate() {
            if c.beam.is_none_or(|b| !intact[b]) && closing(c) + guard >= c.gap {
                self.last.push(k);
            }
        }
        self.last.iter().map(|&k| (self.pairs[k].i, self.pairs[k].j)).collect()
    }

    /// After the contact law ran on the last query's pairs at `z` and found the contacts
    /// `touching` (pairs `(i < j)` in increasing order): the pairs it found apart are anchored at
    /// `z` with their separation there, when positive (module docs, "Refresh").
    pub fn refresh_apart(&mut self, sample: &Sample, map: &DofMap, z: &[f64], touching: &[(usize, usize)]) {
        let mut t = touching.iter().peekable();
        for &k in &self.last {
            let c = &mut self.pairs[k];
            while t.next_if(|&&p| p < (c.i, c.j)).is_some() {}
            if t.peek().is_some_and(|&&p| p == (c.i, c.j)) {
                continue;
            }
            let at = [map.particle_dofs(c.i, z), map.particle_dofs(c.j, z)];
            let gap = separation(&current_polygon(sample, c.i, at[0]), &current_polygon(sample, c.j, at[1]));
            if gap > 0.0 {
                c.gap = gap;
                c.at = at;
            }
        }
        self.refreshes += 1;
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::dem::mechanics::MechParams;
    use crate::dem::sample::{RandomLayout, SampleConfig, SampleLayout, TinyFacetPolicy};
    use crate::dem::solver::contact_set;
    use crate::dem::solver::dofs::DofControl;
    use rand::{Rng, SeedableRng};

    #[test]
    fn separation_of_squares() {
        // Unit squares 0.25 apart along x: the gap is 0.25 (exact); overlapping by 0.1: −0.1.
        let a = Polygon::rectangle(0.0, 0.0, 1.0, 1.0);
        let b = Polygon::rectangle(1.25, 0.3, 2.25, 1.3);
        assert!((separation(&a, &b) - 0.25).abs() < 1e-15);
        let c = Polygon::rectangle(0.9, 0.0, 1.9, 1.0);
        assert!((separation(&a, &c) + 0.1).abs() < 1e-15);
        // A clockwise copy gives the same value.
        let cw = Polygon { vertices: b.vertices.iter().rev().copied().collect() };
        assert!((separation(&a, &cw) - 0.25).abs() < 1e-15);
    }

    #[test]
    fn same_contacts_as_a_search_from_scratch() {
        // 150 random stones, 40 % of the beams broken, a sequence of random rigid motions growing
        // to several margins (so the list is rebuilt), the pairs found apart re-anchored after
        // every evaluation: at every state the contacts found from the list are exactly those of
        // the search from scratch (same pairs, same forces bit for bit), and the list evaluates
        // fewer pairs.
        let s = Sample::build(&SampleConfig {
            layout: SampleLayout::Random(RandomLayout {
                width: 1.0,
                height: 1.0,
                n_particles: 150,
                min_distance_factor: 0.7,
            }),
            thickness: 1.0,
            seed: 11,
            alpha: 0.8,
            facet_tolerance: 0.02,
            tiny_facets: TinyFacetPolicy::Merge,
        })
        .unwrap();
        let map = DofMap::new(&s, [[DofControl::Prescribed; 3]; 2]).unwrap();
        let params = MechParams::default();
        let mut rng = rand_chacha::ChaCha8Rng::seed_from_u64(5);
        let intact: Vec<bool> = (0..s.beams.len()).map(|_| rng.random::<f64>() > 0.4).collect();
        let d = s.mean_diameter();
        let mut list = CandidateList::default();
        let mut z = vec![0.0; map.n_z];
        let (mut listed, mut scratch, mut contacts) = (0, 0, 0);
        for step in 0..30 {
            // A drift (uniform compression and a shear, growing) plus a random jiggle of 10⁻³ D̄.
            let e = 1e-3 * step as f64;
            for p in 0..s.particles.len() {
                if map.is_slave(p) {
                    continue;
                }
                let (idx, _) = map.particle_map(p);
                let c = s.particles[p].centroid;
                z[idx[0]] = 0.3 * e * c[1] * d / 0.1 + 1e-3 * d * (rng.random::<f64>() - 0.5);
                z[idx[1]] = -e * c[1] * d / 0.1 + 1e-3 * d * (rng.random::<f64>() - 0.5);
                z[idx[2]] = 1e-3 * (rng.random::<f64>() - 0.5);
            }
            let a = list.candidates(&s, &map, &z, &intact);
            let b = contact_set::candidates(&s, &map, &z, &intact);
            let none = Default::default();
            let ca = contact_set::evaluate(&s, &map, &params, &a, &z, &z, &none).unwrap();
            let cb = contact_set::evaluate(&s, &map, &params, &b, &z, &z, &none).unwrap();
            // The pairs found apart are re-anchored here, as the solver does.
            list.refresh_apart(&s, &map, &z, &ca.iter().map(|x| (x.i, x.j)).collect::<Vec<_>>());
            assert_eq!(ca.len(), cb.len(), "step {step}");
            for (x, y) in ca.iter().zip(&cb) {
                assert_eq!((x.i, x.j), (y.i, y.j), "step {step}");
                assert_eq!(x.pair_forces(), y.pair_forces(), "step {step}");
            }
            listed += a.len();
            scratch += b.len();
            contacts += ca.len();
        }
        assert!(contacts > 0 && list.rebuilds > 1, "contacts {contacts}, rebuilds {}", list.rebuilds);
        assert!(listed < scratch, "listed {listed} vs scratch {scratch}");
    }
}
