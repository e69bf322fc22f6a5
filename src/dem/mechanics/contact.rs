//! Normal contact between two particles not (or no longer) bonded by a beam (paper §2.1, eqs. 3–4
//! corrected).
//!
//! # Law
//! Overlap polygon `O = P_i ∩ P_j` (convex clipping, current configuration), area `S_r`, centroid
//! `x_c` (the point of application, so the force carries moments about both reference points):
//!
//! ```text
//!   F_n = Ē S_r t_z / ℓ_c ,   ℓ_c = 2 / (1/D_i + 1/D_j)   (harmonic mean of the diameters)
//! ```
//!
//! # Normal and chord
//! The boundary of `O` is made of a chain `A ⊂ ∂P_i` (the part of i's outline inside j) and a
//! chain `B ⊂ ∂P_j`, joined at the two points where the outlines cross; the chord joins those
//! points and `n_c ⊥ chord`. Computing the crossings directly is fragile (collinear edges, as for
//! two aligned squares, make the outline intersection a segment), so the chord is obtained from the
//! overlap's edges instead. Each edge `e` of `O` (counter-clockwise, outward length-weighted normal
//! `ν_e = (e_y, −e_x)`) is labelled by whether its midpoint lies on `∂P_i`, on `∂P_j`, or on both
//! (collinear edges), within `tol = 1e-11 ×` the coordinate scale. Since `∫ n ds` along a path is
//! its end-to-end vector turned by −90°,
//!
//! ```text
//!   s = Σ_{e ∈ A only} ν_e − Σ_{e ∈ B only} ν_e = 2 R₋₉₀ (m₂ − m₁)
//! ```
//!
//! where `m₁`, `m₂` are the midpoints of the two crossing sets (points, or segments when edges
//! are collinear). Hence `n_c = s/|s|`, oriented from i to j by construction (i's outline bulges
//! into j), chord length `L = |s|/2`, chord `m₁ m₂`. For two aligned unit squares overlapping by a
//! strip, the crossing sets are the strip's top and bottom sides and `n_c` is the axis.
//!
//! When `|s|` is below 1e-3 of the overlap's perimeter (one polygon inside the other, symmetric
//! multi-crossings, or a sliver thinner than `tol`), the chord is undefined; then `n_c` is the
//! direction from `ref_i` to `ref_j`, the chord is the overlap's extent across `n_c` through
//! `x_c`, and [`Contact::from_references`] is set. With more than two crossing sets (deep
//! overlaps) `n_c` and `L` still come from `s`, the chord drawn is centred on `x_c`.
//!
//! # Linearization (for an implicit solver)
//! * Exact area gradient `∂S_r/∂(q_i, q_j)` for rigid motions of the particles: a rigid motion of
//!   particle k moves its boundary with velocity `v_k(x) = u_k + θ_k e_z × (x − c_k)`, and
//!   `dS_r = Σ_{e ∈ A} ν_e · v_i(mid_e) + Σ_{e ∈ B} ν_e · v_j(mid_e)` (exact: `v` is linear along
//!   the edge). Collinear edges count ½ to each side (`S_r` has a kink there; ½ is the mean of the
//!   one-sided derivatives). Stored in [`Contact::ds_dq`].
//! * Penalty (secant) stiffness: for a normal approach `δ` at `x_c`, `dS_r/dδ = L`, so
//!   `k_n = Ē t_z L / ℓ_c`, along `n_c` at `x_c`: `K_n = k_n b bᵀ` with
//!   `b = (n_c, r_i × n_c, −n_c, −r_j × n_c)` (`r = x_c − c`), symmetric positive semidefinite.
//! * Consistent (frozen normal and application point): `K_n = (Ē t_z/ℓ_c) b ∂S_rᵀ` (not symmetric
//!   in general; equals the penalty form for a pure normal approach).
//!
//! # Stored energy
//! Read as a Winkler layer along the chord, the law is a distributed pressure
//! `p(s) = κ δ(s)`, `κ = Ē t_z/ℓ_c`, where `δ(s)` is the overlap's thickness along `n_c` at the
//! tangential coordinate `s` (its section by the line through `s` parallel to `n_c`): the
//! resultant `∫ p ds = κ S_r = F_n` acts at the pressure centroid, whose tangential coordinate is
//! the overlap centroid's, `x_c`. Its potential is
//!
//! ```text
//!   U_n = ½ κ ∫ δ(s)² ds        (dU_n = κ ∫ δ dδ(s) ds = F_n b·dq for a rigid relative motion)
//! ```
//!
//! For a strip (uniform `δ` over `L`) `U_n = ½ κ S_r²/L = F_n²/(2 k_n)`. A relative rotation `φ`
//! makes the strip a wedge, `δ(s) = δ̄ + φ s`: `U_n = ½ k_n (δ̄² + φ² L²/12)`, the moment of `F_n`
//! about the chord midpoint is `k_n L² φ/12` and does the work `k_n L² φ²/24` that `F_n²/(2 k_n)`
//! does not hold. For a corner overlap (triangle of depth `h`, chord `2h`) `U_n = κ h³/3` while
//! `F_n²/(2 k_n) = κ h³/4`. The non-uniform part, the *wedge energy*
//! `U_w = ½ κ (∫δ² ds − S_r²/L)` (0 for a strip), is [`Contact::wedge_energy`]; the contact's
//! normal energy is `F_n²/(2 k_n) + U_w`. With crushing `F_n` is the crushed force (the plastic
//! penetration is uniform across the chord) and, since that force acts at the overlap centroid,
//! the moment it carries about the chord midpoint and the wedge energy `U_w = M²/(2 k_φ)`
//! (`k_φ = k_n L²/12`) scale with it: `U_w (F_n/κS_r)²` (`solver::contact_set`). `δ(s)` is piecewise linear between
//! the vertices' tangential coordinates (convex overlap), so `∫δ² ds` is exact:
//! `Σ h_k (δ_k² + δ_k δ_{k+1} + δ_{k+1}²)/3`.
//!
//! # Sign convention
//! As for the beams, the forces returned are *internal* forces (what the particles exert on the
//! contact): `f = F_n b`, i.e. `+F_n n_c` at i and `−F_n n_c` at j; the contact pushes j along
//! `+n_c` and i along `−n_c`. Stiffnesses are `∂f/∂q`.

use nalgebra::{SMatrix, SVector};

use super::error::{positive, MechanicsError};
use super::kinematics::{cross, dot, perp};
use super::thickness::ThicknessProfile;
use super::MechParams;
use crate::dem::polygon::{Polygon, P2};

/// A contact between particles i and j in the current configuration.
#[derive(Clone, Debug, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct Contact {
    /// Unit normal `n_c`, from i to j.
    pub normal: P2,
    /// Point of application: the overlap centroid `x_c`.
    pub point: P2,
    /// Overlap area `S_r` (m²).
    pub overlap_area: f64,
    /// Normal force magnitude `F_n = Ē S_r t_z / ℓ_c` (N, ≥ 0, compressive).
    pub f_n: f64,
    /// The chord's end points (the two outline crossings).
    pub chord: [P2; 2],
    /// The chord length `L = |s|/2` (m).
    pub chord_length: f64,
    /// `ℓ_c`, harmonic mean of the diameters (m).
    pub l_c: f64,
    /// Penalty normal stiffness `k_n = Ē t_z L / ℓ_c` (N/m).
    pub k_n: f64,
    /// `x_c − c_i`.
    pub arm_i: P2,
    /// `x_c − c_j`.
    pub arm_j: P2,
    /// `∂S_r/∂(u_x,i, u_y,i, θ_i, u_x,j, u_y,j, θ_j)` for rigid motions (m, m, m²).
    pub ds_dq: [f64; 6],
    /// Whether the chord was undefined and `n_c` comes from the reference points (see module docs).
    pub from_references: bool,
    /// The wedge energy `U_w = ½ κ (∫δ(s)² ds − S_r²/L)` (J): the normal elastic energy beyond
    /// `F_n²/(2 k_n)` of an overlap whose thickness varies along the chord (module docs).
    pub wedge_energy: f64,
    /// The overlap's thickness across `n_c`, `δ(s)` (module docs; [`ThicknessProfile`]).
    pub profile: ThicknessProfile,
}

#[derive(Clone, Copy, PartialEq, Eq)]
pub(super) enum Side {
    I,
    J,
    Both,
}

pub(super) fn counter_clockwise(p: &Polygon) -> Polygon {
    let v = &p.vertices;
    let n = v.len();
    let twice_area: f64 = (0..n).map(|k| cross(v[k], v[(k + 1) % n])).sum();
    if twice_area < 0.0 {
        Polygon { vertices: v.iter().rev().copied().collect() }
    } else {
        p.clone()
    }
}

/// The lengths of a polygon's edges, edge `k` from vertex `k` to vertex `k + 1`.
fn edge_lengths(p: &Polygon) -> Vec<f64> {
    let v = &p.vertices;
    let n = v.len();
    (0..n).map(|k| (v[(k + 1) % n][0] - v[k][0]).hypot(v[(k + 1) % n][1] - v[k][1])).collect()
}

/// Signed distance to the boundary of a convex CCW polygon (≤ 0 inside): max over the edges,
/// whose lengths are `lengths` ([`edge_lengths`], computed once per polygon and contact: the
/// same values for every point, and `hypot` was a sixth of a contact evaluation).
fn boundary_distance(p: &Polygon, lengths: &[f64], x: P2) -> f64 {
    let v = &p.vertices;
    let n = v.len();
    (0..n)
        .map(|k| {
            let (a, b) = (v[k], v[(k + 1) % n]);
            let e = [b[0] - a[0], b[1] - a[1]];
            let len = lengths[k];
            if len > 0.0 {
                (e[1] * (x[0] - a[0]) - e[0] * (x[1] - a[1])) / len
            } else {
                f64::NEG_INFINITY
            }
        })
        .fold(f64::NEG_INFINITY, f64::max)
}

/// `ℓ_c = 2/(1/D_i + 1/D_j)`.
pub fn contact_length(d_i: f64, d_j: f64) -> Result<f64, MechanicsError> {
    positive("d_i", d_i)?;
    positive("d_j", d_j)?;
    Ok(2.0 / (1.0 / d_i + 1.0 / d_j))
}

/// The contact between convex polygons `poly_i`, `poly_j` (current configuration) with reference
/// points `ref_i`, `ref_j` (current positions) and diameters `d_i`, `d_j`; `None` when they do not
/// overlap (zero area to round-off). Uses `params.e_bar` and `params.t_z`.
/// Errors: non-positive diameters, `e_bar` or `t_z`.
pub fn contact(
    poly_i: &Polygon,
    poly_j: &Polygon,
    ref_i: P2,
    ref_j: P2,
    d_i: f64,
    d_j: f64,
    params: &MechParams,
) -> Result<Option<Contact>, MechanicsError> {
    let l_c = contact_length(d_i, d_j)?;
    positive("e_bar", params.e_bar)?;
    positive("t_z", params.t_z)?;
    if poly_i.is_empty() || poly_j.is_empty() {
        return Ok(None);
    }
    let (pi, pj) = (counter_clockwise(poly_i), counter_clockwise(poly_j));
    let coord = pi.vertices.iter().chain(&pj.vertices).fold(0.0f64, |m, p| m.max(p[0].abs()).max(p[1].abs()));
    let size = pi.area().min(pj.area()).sqrt();
    let tol = 1e-11 * (coord + size);

    let overlap = overlap_polygon(&pi, &pj, tol);
    let area = overlap.area();
    // Zero area to round-off. The threshold must stay far below any area the solver resolves:
    // F_n = κ S_r is continuous at S_r = 0 only if contacts appear at (numerically) zero overlap;
    // a larger cut-off makes F_n jump by κ × cut-off when a contact appears, and Newton's method
    // cannot converge on such a jump (with Ē = 2.5 GPa, ℓ_c = 0.2 m and coordinates of order 1 m
    // the jump here is about 10⁻⁵ N).
    if overlap.is_empty() || area.is_nan() || area <= 1e-15 * (coord + size).powi(2) {
        return Ok(None);
    }
    let v = &overlap.vertices;
    let x_c = overlap.centroid();
    let edges = EdgeSums::of(v, (&pi, &pj), (ref_i, ref_j), tol);
    let arm_i = [x_c[0] - ref_i[0], x_c[1] - ref_i[1]];
    let arm_j = [x_c[0] - ref_j[0], x_c[1] - ref_j[1]];
    let s_norm = edges.s[0].hypot(edges.s[1]);
    let (normal, chord, chord_length, from_references, ds) = if s_norm >= 1e-3 * edges.perimeter {
        let n = [edges.s[0] / s_norm, edges.s[1] / s_norm];
        let chord = crossing_midpoints(v, &edges.sides).unwrap_or_else(|| {
            let t = perp(n);
            let h = 0.25 * s_norm;
            [[x_c[0] - h * t[0], x_c[1] - h * t[1]], [x_c[0] + h * t[0], x_c[1] + h * t[1]]]
        });
        (n, chord, 0.5 * s_norm, false, edges.ds)
    } else {
        // No chord from the edges (the overlap is cut symmetrically): the normal along the
        // references, the chord the overlap's extent across it.
        let d = [ref_j[0] - ref_i[0], ref_j[1] - ref_i[1]];
        let dn = d[0].hypot(d[1]);
        let n = if dn > 0.0 { [d[0] / dn, d[1] / dn] } else { [1.0, 0.0] };
        let t = perp(n);
        let proj = v.iter().map(|p| dot([p[0] - x_c[0], p[1] - x_c[1]], t));
        let (lo, hi) = proj.fold((f64::INFINITY, f64::NEG_INFINITY), |(lo, hi), x| (lo.min(x), hi.max(x)));
        let chord = [[x_c[0] + lo * t[0], x_c[1] + lo * t[1]], [x_c[0] + hi * t[0], x_c[1] + hi * t[1]]];
        // The exact gradient is meaningless here: use the penalty one, L b.
        let l = hi - lo;
        let b = [n[0], n[1], cross(arm_i, n), -n[0], -n[1], -cross(arm_j, n)];
        (n, chord, l, true, b.map(|x| l * x))
    };
    let e_t = params.e_bar * params.t_z / l_c;
    let profile = thickness_profile(v, normal, tol);
    let wedge_energy =
        if chord_length > 0.0 { 0.5 * e_t * (profile.clipped(0.0).second - area * area / chord_length) } else { 0.0 };
    Ok(Some(Contact {
        normal,
        point: x_c,
        overlap_area: area,
        f_n: e_t * area,
        chord,
        chord_length,
        l_c,
        k_n: e_t * chord_length,
        arm_i,
        arm_j,
        ds_dq: ds,
        from_references,
        wedge_energy,
        profile,
    }))
}

/// The overlap of `pi` and `pj` without the near-duplicate vertices (within `tol`) that
/// clipping leaves at corners.
fn overlap_polygon(pi: &Polygon, pj: &Polygon, tol: f64) -> Polygon {
    let raw = pi.intersection(pj).vertices;
    let mut v: Vec<P2> = Vec::with_capacity(raw.len());
    for p in raw {
        if v.last().is_none_or(|q: &P2| (p[0] - q[0]).hypot(p[1] - q[1]) > tol) {
            v.push(p);
        }
    }
    while v.len() > 1 && (v[0][0] - v[v.len() - 1][0]).hypot(v[0][1] - v[v.len() - 1][1]) <= tol {
        v.pop();
    }
    Polygon { vertices: v }
}

/// Sums over the overlap's edges: each edge's side (on `i`'s boundary, `j`'s, or both), the
/// chord vector `s = Σ ±ν_k` (outer edge normals of length |edge|, `+` on `i`'s side, `−` on
/// `j`'s), the perimeter, and the area's gradient `∂S/∂q` over `(q_i, q_j)`.
pub(super) struct EdgeSums {
    pub(super) sides: Vec<Side>,
    pub(super) s: [f64; 2],
    pub(super) perimeter: f64,
    ds: [f64; 6],
}

impl EdgeSums {
    pub(super) fn of(v: &[P2], (pi, pj): (&Polygon, &Polygon), (ref_i, ref_j): (P2, P2), tol: f64) -> EdgeSums {
        let m = v.len();
        let mut sides = Vec::with_capacity(m);
        let (mut s, mut perimeter, mut ds) = ([0.0; 2], 0.0, [0.0; 6]);
        let (len_i, len_j) = (edge_lengths(pi), edge_lengths(pj));
        for k in 0..m {
            let (a, b) = (v[k], v[(k + 1) % m]);
            let mid = [0.5 * (a[0] + b[0]), 0.5 * (a[1] + b[1])];
            let nu = [b[1] - a[1], a[0] - b[0]];
            perimeter += nu[0].hypot(nu[1]);
            let on_i = boundary_distance(pi, &len_i, mid) >= -tol;
            let on_j = boundary_distance(pj, &len_j, mid) >= -tol;
            let (side, w_i) = match (on_i, on_j) {
                (true, false) => (Side::I, 1.0),
                (false, true) => (Side::J, 0.0),
                _ => (Side::Both, 0.5),
            };
            let sign = match side {
                Side::I => 1.0,
                Side::J => -1.0,
                Side::Both => 0.0,
            };
            s = [s[0] + sign * nu[0], s[1] + sign * nu[1]];
            sides.push(side);
            for (off, w, c) in [(0, w_i, ref_i), (3, 1.0 - w_i, ref_j)] {
                ds[off] += w * nu[0];
                ds[off + 1] += w * nu[1];
                ds[off + 2] += w * cross([mid[0] - c[0], mid[1] - c[1]], nu);
            }
        }
        EdgeSums { sides, s, perimeter, ds }
    }
}

/// The thickness function of the convex polygon `v` across the direction `n` (unit),
/// [`ThicknessProfile`]: its section at each vertex coordinate `s_k = t·v_k` (coordinates closer
/// than `tol` count as one; at an end where an edge is parallel to `n`, the section is that edge,
/// the limit from inside).
fn thickness_profile(v: &[P2], n: P2, tol: f64) -> ThicknessProfile {
    let t = perp(n);
    let m = v.len();
    if m < 3 {
        return ThicknessProfile::default();
    }
    let s: Vec<f64> = v.iter().map(|p| dot(*p, t)).collect();
    let h: Vec<f64> = v.iter().map(|p| dot(*p, n)).collect();
    let mut cuts = s.clone();
    cuts.sort_by(f64::total_cmp);
    cuts.dedup_by(|a, b| (*a - *b).abs() <= tol);
    let section = |s0: f64| -> f64 {
        let (mut lo, mut hi) = (f64::INFINITY, f64::NEG_INFINITY);
        for k in 0..m {
            let l = (k + 1) % m;
            let mut add = |x: f64| {
                lo = lo.min(x);
                hi = hi.max(x);
            };
            if (s[k] - s0).abs() <= tol {
                add(h[k]);
            }
            let (a, b) = (s[k].min(s[l]), s[k].max(s[l]));
            if b - a > tol && s0 > a + tol && s0 < b - tol {
                add(h[k] + (s0 - s[k]) / (s[l] - s[k]) * (h[l] - h[k]));
            }
        }
        if hi >= lo {
            hi - lo
        } else {
            0.0
        }
    };
    let delta = cuts.iter().map(|&c| section(c)).collect();
    ThicknessProfile { s: cuts, delta }
}

/// The midpoints of the two crossing sets of the outlines, walking the overlap's edge labels; `None`
/// unless there are exactly two.
fn crossing_midpoints(v: &[P2], sides: &[Side]) -> Option<[P2; 2]> {
    let m = v.len();
    let k0 = sides.iter().position(|&s| s != Side::Both)?;
    let (mut last, mut run_start) = (sides[k0], v[(k0 + 1) % m]);
    let mut mids = Vec::with_capacity(2);
    for step in 1..=m {
        let k = (k0 + step) % m;
        if sides[k] == Side::Both {
            continue;
        }
        if sides[k] != last {
            mids.push([0.5 * (run_start[0] + v[k][0]), 0.5 * (run_start[1] + v[k][1])]);
            last = sides[k];
        }
        run_start = v[(k + 1) % m];
    }
    match mids[..] {
        [a, b] => Some([a, b]),
        _ => None,
    }
}

impl Contact {
    /// The tangent `t_c = e_z × n_c`.
    pub fn tangent(&self) -> P2 {
        perp(self.normal)
    }

    /// `b = (n_c, r_i × n_c, −n_c, −r_j × n_c)`: internal normal forces are `F_n b`, and `b·Δq` is
    /// the normal approach (closing) of the two particles at the contact point.
    pub fn normal_direction(&self) -> SVector<f64, 6> {
        let n = self.normal;
        SVector::<f64, 6>::from_column_slice(&[n[0], n[1], cross(self.arm_i, n), -n[0], -n[1], -cross(self.arm_j, n)])
    }

    /// `c = (−t_c, −r_i × t_c, t_c, r_j × t_c)`: `c·Δq` is the tangential slip increment `Δg_t` of
    /// j relative to i at the contact point; internal friction forces are `F_t c`.
    pub fn tangential_direction(&self) -> SVector<f64, 6> {
        let t = self.tangent();
        SVector::<f64, 6>::from_column_slice(&[-t[0], -t[1], -cross(self.arm_i, t), t[0], t[1], cross(self.arm_j, t)])
    }

    /// The tangential slip increment `Δg_t = (Δu_j(x_c) − Δu_i(x_c))·t_c` (rotations included) for
    /// particle DOF increments `dq_i`, `dq_j`.
    pub fn tangential_increment(&self, dq_i: [f64; 3], dq_j: [f64; 3]) -> f64 {
        self.tangential_direction().dot(&super::beam::stack(dq_i, dq_j))
    }

    /// Internal generalized normal forces `(f_i, f_j) = F_n b` (moments about the reference points).
    pub fn normal_forces(&self) -> ([f64; 3], [f64; 3]) {
        split(self.normal_direction() * self.f_n)
    }

    /// Internal generalized forces `(f_i, f_j) = F_t c` of a tangential force `f_t` (see
    /// [`super::friction`]).
    pub fn tangential_forces(&self, f_t: f64) -> ([f64; 3], [f64; 3]) {
        split(self.tangential_direction() * f_t)
    }

    /// Penalty normal stiffness `k_n b bᵀ` (symmetric).
    pub fn normal_stiffness(&self) -> SMatrix<f64, 6, 6> {
        let b = self.normal_direction();
        b * b.transpose() * self.k_n
    }

    /// Consistent normal stiffness with frozen normal and point, `(Ē t_z/ℓ_c) b (∂S_r/∂q)ᵀ`.
    pub fn normal_stiffness_consistent(&self, params: &MechParams) -> SMatrix<f64, 6, 6> {
        let g = SVector::<f64, 6>::from_column_slice(&self.ds_dq);
        self.normal_direction() * g.transpose() * (params.e_bar * params.t_z / self.l_c)
    }
}

fn split(f: SVector<f64, 6>) -> ([f64; 3], [f64; 3]) {
    ([f[0], f[1], f[2]], [f[3], f[4], f[5]])
}

#[cfg(test)]
mod tests {
    use super::*;

    fn params() -> MechParams {
        MechParams { e_bar: 2.5e9, t_z: 1.0, ..MechParams::default() }
    }

    fn unit_square_at(x: f64, y: f64) -> Polygon {
        Polygon::rectangle(x, y, x + 1.0, y + 1.0)
    }

    #[test]
    fn aligned_squares_overlapping_by_a_strip() {
        // Squares [0,1]² and [0.9,1.9]×[0,1] (by hand): S = 0.1, centroid (0.95, 0.5), normal +x,
        // chord (0.95, 0)–(0.95, 1), L = 1. D = 2√(1/π) for both → ℓ_c = D = 1.128 379;
        // F_n = 2.5e9 · 0.1 · 1 / 1.128 379 (= 2/√π). Tolerances 1e-12 relative.
        let p = params();
        let d = 2.0 * (1.0 / std::f64::consts::PI).sqrt();
        let c = contact(&unit_square_at(0.0, 0.0), &unit_square_at(0.9, 0.0), [0.5, 0.5], [1.4, 0.5], d, d, &p)
            .unwrap()
            .unwrap();
        assert!((c.overlap_area - 0.1).abs() < 1e-12);
        assert!((c.point[0] - 0.95).abs() < 1e-12 && (c.point[1] - 0.5).abs() < 1e-12);
        assert!((c.normal[0] - 1.0).abs() < 1e-12 && c.normal[1].abs() < 1e-12, "{:?}", c.normal);
        assert!((c.l_c - std::f64::consts::FRAC_2_SQRT_PI).abs() < 1e-12);
        assert!((c.f_n / (2.5e9 * 0.1 / std::f64::consts::FRAC_2_SQRT_PI) - 1.0).abs() < 1e-12);
        assert!((c.chord_length - 1.0).abs() < 1e-12 && !c.from_references);
        let ys = [c.chord[0][1].min(c.chord[1][1]), c.chord[0][1].max(c.chord[1][1])];
        assert!((c.chord[0][0] - 0.95).abs() < 1e-12 && (c.chord[1][0] - 0.95).abs() < 1e-12);
        assert!(ys[0].abs() < 1e-12 && (ys[1] - 1.0).abs() < 1e-12);
        // Moments: internal force at i is +F_n e_x at (0.95, 0.5): arm (0.45, 0) ∥ force → 0.
        let (fi, fj) = c.normal_forces();
        assert!((fi[0] - c.f_n).abs() < 1e-12 * c.f_n && (fj[0] + c.f_n).abs() < 1e-12 * c.f_n);
        assert!(fi[2].abs() < 1e-12 * c.f_n && fj[2].abs() < 1e-12 * c.f_n);
        // Swapping the roles flips the normal.
        let r = contact(&unit_square_at(0.9, 0.0), &unit_square_at(0.0, 0.0), [1.4, 0.5], [0.5, 0.5], d, d, &p)
            .unwrap()
            .unwrap();
        assert!((r.normal[0] + 1.0).abs() < 1e-12);
    }

    #[test]
    fn squares_crossing_at_a_corner() {
        // [0,1]² and [0.75,1.75]×[0.5,1.5] (by hand): outlines cross at (1, 0.5) and (0.75, 1);
        // chord vector (−0.25, 0.5), L = √0.3125, normal (2, 1)/√5 (points from i to j).
        // Overlap 0.25 × 0.5 = 0.125 at (0.875, 0.75). D_i = 1, D_j = 0.5 → ℓ_c = 2/(1 + 2) = 2/3.
        // F_n = Ē · 0.125 · t_z / (2/3) with t_z = 0.5. Moment about c_i = (0.5, 0.5) of the
        // internal force F_n n at arm (0.375, 0.25): F_n (0.375·1 − 0.25·2)/√5. Tolerance 1e-12.
        let p = MechParams { t_z: 0.5, ..params() };
        let c = contact(&unit_square_at(0.0, 0.0), &unit_square_at(0.75, 0.5), [0.5, 0.5], [1.25, 1.0], 1.0, 0.5, &p)
            .unwrap()
            .unwrap();
        let s5 = 5f64.sqrt();
        assert!((c.normal[0] - 2.0 / s5).abs() < 1e-12 && (c.normal[1] - 1.0 / s5).abs() < 1e-12);
        assert!((c.chord_length - 0.3125f64.sqrt()).abs() < 1e-12);
        assert!((c.l_c - 2.0 / 3.0).abs() < 1e-15);
        assert!((c.f_n / (2.5e9 * 0.125 * 0.5 * 1.5) - 1.0).abs() < 1e-12);
        let mut ends = c.chord;
        ends.sort_by(|a, b| a[0].total_cmp(&b[0]));
        assert!((ends[0][0] - 0.75).abs() < 1e-12 && (ends[0][1] - 1.0).abs() < 1e-12);
        assert!((ends[1][0] - 1.0).abs() < 1e-12 && (ends[1][1] - 0.5).abs() < 1e-12);
        let (fi, _) = c.normal_forces();
        assert!((fi[2] - c.f_n * (0.375 - 0.5) / s5).abs() < 1e-12 * c.f_n);
        // Apart: no contact.
        let none = contact(&unit_square_at(0.0, 0.0), &unit_square_at(1.0, 0.0), [0.5, 0.5], [1.5, 0.5], 1.0, 1.0, &p);
        assert_eq!(none, Ok(None));
        assert!(
            contact(&unit_square_at(0.0, 0.0), &unit_square_at(0.5, 0.0), [0.5; 2], [1.0, 0.5], 0.0, 1.0, &p).is_err()
        );
    }

    #[test]
    fn normal_stiffness_matches_finite_differences_of_an_approach() {
        // Squares [0,1]² and [0.9,1.9]×[0,1]; j approaches by δ along −x (n_c = +x):
        // S(δ) = 0.1 + δ, so dF_n/dδ = Ē t_z L/ℓ_c with L = 1 (exact; FD tolerance 1e-7 relative).
        let p = params();
        let d = 1.0;
        let f_n = |delta: f64| {
            let pj = unit_square_at(0.9 - delta, 0.0);
            contact(&unit_square_at(0.0, 0.0), &pj, [0.5, 0.5], [1.4 - delta, 0.5], d, d, &p).unwrap().unwrap()
        };
        let c0 = f_n(0.0);
        let h = 1e-5;
        let fd = (f_n(h).f_n - f_n(-h).f_n) / (2.0 * h);
        assert!((fd / c0.k_n - 1.0).abs() < 1e-7, "{fd} vs {}", c0.k_n);
        assert!((c0.k_n - 2.5e9 * 1.0 / 1.0).abs() < 1e-3);
        // The stiffness matrix gives the same force change: Δq_j = (−h, 0, 0).
        let dq = SVector::<f64, 6>::from_column_slice(&[0.0, 0.0, 0.0, -h, 0.0, 0.0]);
        let df = c0.normal_stiffness() * dq;
        let (fi1, _) = f_n(h).normal_forces();
        let (fi0, _) = c0.normal_forces();
        assert!(((fi1[0] - fi0[0]) / df[0] - 1.0).abs() < 1e-7);
        let dfc = c0.normal_stiffness_consistent(&p) * dq;
        assert!(((fi1[0] - fi0[0]) / dfc[0] - 1.0).abs() < 1e-7);
    }

    #[test]
    fn area_gradient_matches_finite_differences_including_rotations() {
        // Generic crossing: a square and a tilted rectangle. Central differences of S_r over rigid
        // moves of each particle about its reference point (Polygon::moved, finite rotations:
        // O(h²) error); tolerance 1e-6 of the largest gradient component.
        let p = params();
        let pi = Polygon::rectangle(0.0, 0.0, 1.0, 1.0);
        let (ci, cj) = ([0.5, 0.5], [1.5, 0.9]);
        let pj = Polygon::rectangle(1.0, 0.6, 2.0, 1.2).moved(cj, [-0.1, 0.0], 0.3);
        let cj = [cj[0] - 0.1, cj[1]];
        let c = contact(&pi, &pj, ci, cj, 1.0, 1.0, &p).unwrap().unwrap();
        let area = |q: [f64; 6]| {
            let a = pi.moved(ci, [q[0], q[1]], q[2]);
            let b = pj.moved(cj, [q[3], q[4]], q[5]);
            a.intersection(&b).area()
        };
        let h = 1e-6;
        let scale = c.ds_dq.iter().fold(0.0f64, |m, x| m.max(x.abs()));
        for k in 0..6 {
            let (mut qp, mut qm) = ([0.0; 6], [0.0; 6]);
            qp[k] = h;
            qm[k] = -h;
            let fd = (area(qp) - area(qm)) / (2.0 * h);
            assert!((fd - c.ds_dq[k]).abs() < 1e-6 * scale, "dS/dq[{k}]: {fd} vs {}", c.ds_dq[k]);
        }
        // Generic case: the translation parts are ±L n_c (dS = L × normal approach).
        assert!((c.ds_dq[0] - c.chord_length * c.normal[0]).abs() < 1e-12);
        assert!((c.ds_dq[4] + c.chord_length * c.normal[1]).abs() < 1e-12);
    }

    #[test]
    fn rotated_aligned_squares_keep_the_rotated_axis() {
        // The strip case rotated by 0.4 rad about the origin: the collinear sides are collinear
        // only to round-off, the tolerance must still see them. Expected: normal (cos 0.4, sin 0.4),
        // S = 0.1, L = 1 (tolerance 1e-9).
        let p = params();
        let th: f64 = 0.4;
        let rot = |x: [f64; 2]| [th.cos() * x[0] - th.sin() * x[1], th.sin() * x[0] + th.cos() * x[1]];
        let a = unit_square_at(0.0, 0.0).moved([0.0, 0.0], [0.0, 0.0], th);
        let b = unit_square_at(0.9, 0.0).moved([0.0, 0.0], [0.0, 0.0], th);
        let c = contact(&a, &b, rot([0.5, 0.5]), rot([1.4, 0.5]), 1.0, 1.0, &p).unwrap().unwrap();
        assert!(!c.from_references);
        assert!((c.normal[0] - th.cos()).abs() < 1e-9 && (c.normal[1] - th.sin()).abs() < 1e-9, "{:?}", c.normal);
        assert!((c.overlap_area - 0.1).abs() < 1e-9 && (c.chord_length - 1.0).abs() < 1e-9);
    }

    /// The normal energy `F_n²/(2k_n) + U_w` is the potential of the normal force: its
    /// derivative along an approach is `F_n`. Strip: `U_w = 0` (δ uniform). A square turned by
    /// 45° pressing its corner into a flat top by `h`: the overlap is a triangle of depth `h` on a
    /// chord `2h`, `S = h²`, `F_n = κ h²`, `∫δ² ds = 2h³/3` → `U_n = κ h³/3` (by hand), whose
    /// derivative is `κ h² = F_n`; `F_n²/(2k_n) = κ h³/4` alone would give `¾ F_n`. Tolerances:
    /// 1e-9 relative on the closed forms (clipping round-off), 1e-6 on the central difference
    /// (step 1e-4 h: truncation O(1e-8)).
    #[test]
    fn normal_energy_is_the_potential_of_the_normal_force() {
        let p = params();
        let d = 1.0;
        let kappa = p.e_bar * p.t_z / d;
        let strip = contact(&unit_square_at(0.0, 0.0), &unit_square_at(0.9, 0.0), [0.5, 0.5], [1.4, 0.5], d, d, &p)
            .unwrap()
            .unwrap();
        assert!(strip.wedge_energy.abs() < 1e-9 * 0.5 * strip.f_n * strip.f_n / strip.k_n, "{}", strip.wedge_energy);
        let r = std::f64::consts::FRAC_1_SQRT_2;
        let corner = |h: f64| {
            // Diamond of half-diagonal r (a unit square turned by 45°), lowest corner at y = 1 − h.
            let cy = 1.0 - h + r;
            let diamond = Polygon { vertices: vec![[0.5, cy - r], [0.5 + r, cy], [0.5, cy + r], [0.5 - r, cy]] };
            contact(&unit_square_at(0.0, 0.0), &diamond, [0.5, 0.5], [0.5, cy], d, d, &p).unwrap().unwrap()
        };
        let energy = |c: &Contact| 0.5 * c.f_n * c.f_n / c.k_n + c.wedge_energy;
        let h = 0.01;
        let c = corner(h);
        assert!((c.overlap_area - h * h).abs() < 1e-9 * h * h && (c.chord_length - 2.0 * h).abs() < 1e-9 * h);
        assert!((c.normal[1] - 1.0).abs() < 1e-12, "{:?}", c.normal);
        assert!((energy(&c) - kappa * h.powi(3) / 3.0).abs() < 1e-9 * kappa * h.powi(3));
        assert!((c.wedge_energy - kappa * h.powi(3) / 12.0).abs() < 1e-9 * kappa * h.powi(3));
        let e = 1e-4 * h;
        let fd = (energy(&corner(h + e)) - energy(&corner(h - e))) / (2.0 * e);
        assert!((fd / c.f_n - 1.0).abs() < 1e-6, "dU/dh {fd} vs F_n {}", c.f_n);
        // A wedge: the upper square turned by φ about the middle of its bottom edge, pressed by
        // δ̄ (δ(s) = δ̄ + φ s across L = 1): U_w = ½ κ φ² L³/12 to O(δ̄ + φ) relative.
        let (db, phi) = (1e-4, 1e-4);
        let upper = unit_square_at(0.0, 1.0 - db).moved([0.5, 1.0 - db], [0.0, 0.0], phi);
        let w = contact(&unit_square_at(0.0, 0.0), &upper, [0.5, 0.5], [0.5, 1.5 - db], d, d, &p).unwrap().unwrap();
        let want = 0.5 * kappa * phi * phi / 12.0;
        assert!((w.wedge_energy / want - 1.0).abs() < 1e-3, "wedge {} vs {want}", w.wedge_energy);
    }

    #[test]
    fn contained_polygon_falls_back_to_the_reference_direction() {
        // A 0.2 square inside a unit square: s = 0, the normal is c_j − c_i = +y, the chord is the
        // overlap's width 0.2 across it.
        let p = params();
        let big = Polygon::rectangle(0.0, 0.0, 1.0, 1.0);
        let small = Polygon::rectangle(0.4, 0.6, 0.6, 0.8);
        let c = contact(&big, &small, [0.5, 0.5], [0.5, 0.7], 1.0, 0.2, &p).unwrap().unwrap();
        assert!(c.from_references);
        assert!(c.normal[0].abs() < 1e-15 && (c.normal[1] - 1.0).abs() < 1e-15);
        assert!((c.chord_length - 0.2).abs() < 1e-12 && (c.overlap_area - 0.04).abs() < 1e-12);
    }
}
