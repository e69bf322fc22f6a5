//! From independently clipped cells to one conforming tessellation: shared vertices welded, zero
//! edges removed, facets (edges shared by two cells) paired, tiny facets merged or rejected.
//!
//! **Welding.** The same Voronoi vertex computed in two cells differs by rounding; vertices within
//! `weld_tol` (1e-9 × the mean seed spacing) become one. Points on a domain side are exactly on
//! it after clipping the rectangle (`x = 0 + t·0`), and a welded vertex keeps that exact coordinate,
//! so the cells keep tiling the rectangle.
//!
//! **Tiny facets.** A facet `a–b` shorter than the tolerance is removed by moving `a` and `b` to
//! one point: their midpoint, or the one on the domain boundary if one is (a corner wins over a
//! side point), so the outer boundary is unchanged. Every cell using `a` or `b` is updated, so the
//! tessellation stays conforming and the areas still sum to the domain's. The two particles then
//! touch at a point and get no beam; the facets around the moved vertex turn slightly, so their
//! beams are no longer exactly perpendicular to them (by an angle of order tolerance/facet length).
use super::config::TinyFacetPolicy;
use super::error::SampleError;
use super::voronoi::{EdgeOwner, RawCell, Side};
use crate::dem::polygon::P2;
use std::collections::HashMap;

const BOTTOM: u8 = 1;
const RIGHT: u8 = 2;
const TOP: u8 = 4;
const LEFT: u8 = 8;

/// Which domain sides a vertex lies on (bit mask).
fn side_bit(s: Side) -> u8 {
    match s {
        Side::Bottom => BOTTOM,
        Side::Right => RIGHT,
        Side::Top => TOP,
        Side::Left => LEFT,
    }
}

/// A conforming tessellation of the domain.
#[derive(Clone, Debug)]
pub struct Tessellation {
    /// Shared vertices.
    pub vertices: Vec<P2>,
    /// Per vertex, the domain sides it lies on (bits: bottom 1, right 2, top 4, left 8).
    pub sides: Vec<u8>,
    /// Per cell, vertex ids counter-clockwise.
    pub cells: Vec<Vec<usize>>,
    /// Per cell, the generator of the edge starting at each vertex.
    pub owners: Vec<Vec<EdgeOwner>>,
}

/// An edge shared by cells `i < j`, running `a → b` counter-clockwise around `i`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Facet {
    /// Lower particle index.
    pub i: usize,
    /// Higher particle index.
    pub j: usize,
    /// Start vertex id (counter-clockwise around `i`).
    pub a: usize,
    /// End vertex id.
    pub b: usize,
}

/// A facet removed because it was shorter than the tolerance.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct MergedFacet {
    /// Lower particle index.
    pub i: usize,
    /// Higher particle index.
    pub j: usize,
    /// Its length before the merge (m).
    pub length: f64,
    /// Where its two end points were moved to (m).
    pub point: P2,
}

impl Tessellation {
    /// Welds the vertices of independently clipped cells.
    pub fn weld(raw: &[RawCell], width: f64, height: f64, weld_tol: f64) -> Result<Tessellation, SampleError> {
        let mut vertices: Vec<P2> = Vec::new();
        let mut sides: Vec<u8> = Vec::new();
        let mut hash: HashMap<(i64, i64), Vec<usize>> = HashMap::new();
        let key = |p: P2| ((p[0] / weld_tol).floor() as i64, (p[1] / weld_tol).floor() as i64);
        let mut cells = Vec::with_capacity(raw.len());
        let mut owners = Vec::with_capacity(raw.len());
        for c in raw {
            let mut ids = Vec::with_capacity(c.vertices.len());
            for &p in &c.vertices {
                let mut bits = 0;
                bits |= if p[1] == 0.0 { BOTTOM } else { 0 };
                bits |= if p[0] == width { RIGHT } else { 0 };
                bits |= if p[1] == height { TOP } else { 0 };
                bits |= if p[0] == 0.0 { LEFT } else { 0 };
                let (kx, ky) = key(p);
                let mut found = None;
                'search: for dy in -1..=1 {
                    for dx in -1..=1 {
                        if let Some(list) = hash.get(&(kx + dx, ky + dy)) {
                            for &v in list {
                                let q = vertices[v];
                                if (q[0] - p[0]).hypot(q[1] - p[1]) <= weld_tol {
                                    found = Some(v);
                                    break 'search;
                                }
                            }
                        }
                    }
                }
                let v = match found {
                    Some(v) => v,
                    None => {
                        vertices.push(p);
                        sides.push(0);
                        hash.entry((kx, ky)).or_default().push(vertices.len() - 1);
                        vertices.len() - 1
                    }
                };
                sides[v] |= bits;
                ids.push(v);
            }
            cells.push(ids);
            owners.push(c.owners.clone());
        }
        for (v, &s) in sides.iter().enumerate() {
            snap_to_sides(&mut vertices[v], s, width, height);
        }
        let mut t = Tessellation { vertices, sides, cells, owners };
        for c in 0..t.cells.len() {
            t.dedupe(c)?;
        }
        Ok(t)
    }

    /// Removes zero-length edges (repeated consecutive vertex ids) of cell `c`.
    fn dedupe(&mut self, c: usize) -> Result<(), SampleError> {
        let (ids, owners) = (&mut self.cells[c], &mut self.owners[c]);
        let mut k = 0;
        while k < ids.len() && ids.len() > 1 {
            if ids[k] == ids[(k + 1) % ids.len()] {
                ids.remove(k);
                owners.remove(k);
            } else {
                k += 1;
            }
        }
        if ids.len() < 3 {
            return Err(SampleError::ZeroAreaCell { particle: c, area: 0.0 });
        }
        Ok(())
    }

    /// Length of the segment between two vertex ids.
    pub fn distance(&self, a: usize, b: usize) -> f64 {
        let (p, q) = (self.vertices[a], self.vertices[b]);
        (q[0] - p[0]).hypot(q[1] - p[1])
    }

    /// Every shared edge once (`i < j`), checking that both sides agree.
    pub fn facets(&self) -> Result<Vec<Facet>, SampleError> {
        let mut edges: HashMap<(usize, usize), usize> = HashMap::new();
        for (c, ids) in self.cells.iter().enumerate() {
            for k in 0..ids.len() {
                edges.insert((ids[k], ids[(k + 1) % ids.len()]), c);
            }
        }
        let mut out = Vec::new();
        for (i, ids) in self.cells.iter().enumerate() {
            for (k, owner) in self.owners[i].iter().enumerate() {
                let EdgeOwner::Seed(j) = *owner else { continue };
                let (a, b) = (ids[k], ids[(k + 1) % ids.len()]);
                let twin = edges.get(&(b, a)).copied();
                let twin_ok = twin == Some(j)
                    && self.cells[j]
                        .iter()
                        .enumerate()
                        .any(|(m, &v)| v == b && self.owners[j][m] == EdgeOwner::Seed(i));
                if !twin_ok {
                    return Err(SampleError::NonConforming { i, j });
                }
                if i < j {
                    out.push(Facet { i, j, a, b });
                }
            }
        }
        Ok(out)
    }

    /// Merges (or rejects) facets shorter than `tol` (m) until none is left.
    pub fn merge_tiny_facets(&mut self, tol: f64, policy: TinyFacetPolicy) -> Result<Vec<MergedFacet>, SampleError> {
        let mut merged = Vec::new();
        if tol <= 0.0 {
            return Ok(merged);
        }
        loop {
            let mut tiny: Vec<(f64, Facet)> =
                self.facets()?.into_iter().map(|f| (self.distance(f.a, f.b), f)).filter(|(l, _)| *l < tol).collect();
            if tiny.is_empty() {
                return Ok(merged);
            }
            tiny.sort_by(|x, y| x.0.total_cmp(&y.0).then((x.1.i, x.1.j).cmp(&(y.1.i, y.1.j))));
            if policy == TinyFacetPolicy::Reject {
                let (length, f) = tiny[0];
                return Err(SampleError::TinyFacet { i: f.i, j: f.j, length, tolerance: tol });
            }
            let mut users: HashMap<usize, Vec<usize>> = HashMap::new();
            for (c, ids) in self.cells.iter().enumerate() {
                for &v in ids {
                    users.entry(v).or_default().push(c);
                }
            }
            let mut touched = vec![false; self.vertices.len()];
            let mut dirty = Vec::new();
            for (length, f) in tiny {
                if touched[f.a] || touched[f.b] {
                    continue;
                }
                let (sa, sb) = (self.sides[f.a], self.sides[f.b]);
                let (pa, pb) = (self.vertices[f.a], self.vertices[f.b]);
                let target = match (sa, sb) {
                    (0, 0) => [0.5 * (pa[0] + pb[0]), 0.5 * (pa[1] + pb[1])],
                    (_, 0) => pa,
                    (0, _) => pb,
                    _ if sa & sb == 0 => {
                        return Err(SampleError::CannotMergeFacet { i: f.i, j: f.j, length });
                    }
                    _ if sa.count_ones() > 1 => pa,
                    _ if sb.count_ones() > 1 => pb,
                    _ => [0.5 * (pa[0] + pb[0]), 0.5 * (pa[1] + pb[1])],
                };
                self.vertices[f.a] = target;
                self.sides[f.a] |= sb;
                for &c in users.get(&f.b).map(Vec::as_slice).unwrap_or(&[]) {
                    for v in self.cells[c].iter_mut() {
                        if *v == f.b {
                            *v = f.a;
                        }
                    }
                    dirty.push(c);
                }
                touched[f.a] = true;
                touched[f.b] = true;
                merged.push(MergedFacet { i: f.i, j: f.j, length, point: target });
            }
            dirty.sort_unstable();
            dirty.dedup();
            for c in dirty {
                self.dedupe(c)?;
            }
        }
    }

    /// Particles with an edge on each domain side: `[bottom, right, top, left]`, ascending.
    pub fn boundary_cells(&self) -> [Vec<usize>; 4] {
        let mut out: [Vec<usize>; 4] = Default::default();
        for (c, owners) in self.owners.iter().enumerate() {
            for (s, list) in [Side::Bottom, Side::Right, Side::Top, Side::Left].into_iter().zip(out.iter_mut()) {
                if owners.contains(&EdgeOwner::Boundary(s)) {
                    list.push(c);
                }
            }
        }
        out
    }

    /// The domain sides of a vertex, as [`Side`]s.
    pub fn vertex_sides(&self, v: usize) -> Vec<Side> {
        [Side::Bottom, Side::Right, Side::Top, Side::Left]
            .into_iter()
            .filter(|&s| self.sides[v] & side_bit(s) != 0)
            .collect()
    }
}

fn snap_to_sides(p: &mut P2, bits: u8, width: f64, height: f64) {
    if bits & BOTTOM != 0 {
        p[1] = 0.0;
    }
    if bits & TOP != 0 {
        p[1] = height;
    }
    if bits & LEFT != 0 {
        p[0] = 0.0;
    }
    if bits & RIGHT != 0 {
        p[0] = width;
    }
}

#[cfg(test)]
mod tests {
    use super::super::voronoi::clipped_cells;
    use super::*;

    #[test]
    fn square_grid_has_no_diagonal_facets() {
        // 3 × 3 seeds at the centres of a 3 × 3 grid of unit squares: 4 seeds are cocircular at
        // every interior grid point, the diagonal pairs share only that point. Expected facets:
        // 2 · 3 · 2 = 12 (horizontal + vertical neighbours), 16 distinct vertices (4 × 4 grid).
        let seeds: Vec<P2> = (0..9).map(|k| [(k % 3) as f64 + 0.5, (k / 3) as f64 + 0.5]).collect();
        let raw = clipped_cells(3.0, 3.0, &seeds);
        let t = Tessellation::weld(&raw, 3.0, 3.0, 1e-9).expect("conforming");
        let f = t.facets().expect("conforming");
        assert_eq!(f.len(), 12);
        let used: std::collections::BTreeSet<usize> = t.cells.iter().flatten().copied().collect();
        assert_eq!(used.len(), 16);
        assert!(t.cells.iter().all(|c| c.len() == 4));
        assert_eq!(t.boundary_cells()[0], vec![0, 1, 2]);
        assert_eq!(t.boundary_cells()[3], vec![0, 3, 6]);
        assert_eq!(t.vertex_sides(0), vec![Side::Bottom, Side::Left]);
    }

    #[test]
    fn a_short_facet_is_merged_or_rejected() {
        // Four seeds around the centre of the unit square, nearly cocircular: (0.5 ± 0.25, 0.5)
        // and (0.5, 0.5 ± 0.25 + δ). The left/right cells share a facet of length ≈ 2δ.
        let d = 1e-4;
        let seeds = [[0.25, 0.5], [0.75, 0.5], [0.5, 0.25 - d], [0.5, 0.75 + d]];
        let raw = clipped_cells(1.0, 1.0, &seeds);
        let mut t = Tessellation::weld(&raw, 1.0, 1.0, 1e-12).expect("conforming");
        let f = t.facets().expect("conforming");
        let short = f.iter().find(|f| (f.i, f.j) == (0, 1)).expect("0–1 facet");
        let len = t.distance(short.a, short.b);
        assert!(len > 1e-4 && len < 1e-3, "{len}");
        let e = t.clone().merge_tiny_facets(1e-2, TinyFacetPolicy::Reject).unwrap_err();
        assert!(matches!(e, SampleError::TinyFacet { i: 0, j: 1, .. }), "{e}");
        let m = t.merge_tiny_facets(1e-2, TinyFacetPolicy::Merge).expect("mergeable");
        assert_eq!(m.len(), 1);
        let f = t.facets().expect("conforming");
        assert!(f.iter().all(|f| (f.i, f.j) != (0, 1)));
        // Tiling preserved: the four cells still fill the unit square.
        let area: f64 = t
            .cells
            .iter()
            .map(|ids| crate::dem::polygon::Polygon::new(ids.iter().map(|&v| t.vertices[v]).collect()).area())
            .sum();
        assert!((area - 1.0).abs() < 1e-14, "{area}");
    }
}
