//! The exact Jacobian of a contact's internal forces, `J = ∂(F_n b + F_t c)/∂(q_i, q_j)`, by
//! forward-mode dual numbers ([`super::dual`]) through the contact law.
//!
//! The law of [`super::contact`], [`super::crushing`] and [`super::friction`] is evaluated once
//! more on [`Dual6`] numbers seeded with the pair's DOFs: the stones' outlines moved rigidly
//! (finite rotation, as `Polygon::moved`), the overlap clipped (Sutherland–Hodgman), its area,
//! centroid and chord vector `s = Σ_A ν_e − Σ_B ν_e`, the normal `n_c = s/|s|`, the arms, `F_n`,
//! the friction trial `F_old + k_t c·(q − q_commit)` with `k_t ∝ k_n = κ L`, the return map. Every
//! branch is taken on the values, as the `f64` law takes it (the values are its operations, in
//! its order): the clipping's inside tests, the merged near-duplicate vertices, each overlap
//! edge's side (on `∂P_i`, `∂P_j` or both, labelled by the `f64` law's own [`EdgeSums`]), the
//! fallback normal along the references, stick or slip. So the result is the derivative of the
//! branch the state lies on; at a kink (a vertex reaching an edge, a contact reaching the cone)
//! that is a one-sided derivative, an element of the generalized Jacobian that semismooth Newton
//! uses for frictional contact (Alart & Curnier 1991; Hüeber, Stadler & Wohlmuth 2008).
//!
//! **On the cone.** A contact that slid at the last committed state and has not moved since has
//! its trial exactly on the cone, `|F_trial| = μ F_n`: the return map calls it "stick" (its
//! value is the same either way) and the stick branch's derivative `k_t` would treat it as stuck
//! at the first Newton step of the next equilibrium. A trial within `ON_CONE` of the cone takes
//! the slip branch's derivative `∂F_t = μ sign(F_t) ∂F_n`: the branch its history says is active.
//!
//! **Crushing.** The normal force is `κ S(δ_p)` of the thickness profile ([`super::thickness`],
//! carried on duals: its cuts `s_k = t·v_k`, its sections, the integrals of `(δ − c)₊`). On the
//! plastic branch the plastic increment `Δ` solves `g(Δ, q) = κ S(δ_p,old + Δ) − F_y(κ_p,old + Δ,
//! L) = 0`, so `∂Δ/∂q = −(∂g/∂q)/(∂g/∂Δ)` (implicit function theorem), carried by one Newton
//! update on duals from the converged `Δ`: `Δ − g(Δ)/g'(Δ)` with `g'` a value. The crushed force
//! acts at the pressure centroid `S₁/S` along the chord, as in the `f64` law.
use nalgebra::{SMatrix, SVector};

use super::contact::{counter_clockwise, EdgeSums, Side};
use super::crushing::{CrushUpdate, PlasticState};
use super::dual::Dual6 as D;
use super::MechParams;
use crate::dem::polygon::{Polygon, P2};

/// A trial with `|F_trial| ≥ (1 − ON_CONE) μ F_n` lies on the Coulomb cone (module docs).
pub const ON_CONE: f64 = 1e-9;

type DP = [D; 2];

/// The two stones of a pair: outlines in the reference configuration, reference points
/// (centroids) and diameters.
#[derive(Clone, Copy, Debug)]
pub struct PairShape<'a> {
    /// The outlines.
    pub polygons: [&'a Polygon; 2],
    /// The reference points.
    pub centroids: [P2; 2],
    /// The diameters `D_i`, `D_j`.
    pub diameters: [f64; 2],
}

/// The committed state the trial starts from, and how the `f64` law crushed (`None` without
/// crushing).
#[derive(Clone, Copy, Debug)]
pub struct PairTrial {
    /// The committed DOFs `(q_i, q_j)`.
    pub committed: [[f64; 3]; 2],
    /// The committed tangential force.
    pub f_t: f64,
    /// The committed plastic state.
    pub plastic: PlasticState,
    /// The `f64` law's crushing update at the state.
    pub crush: Option<CrushUpdate>,
}

/// The internal forces `F_n b + F_t c` of the pair at DOFs `q` and their exact Jacobian (module
/// docs); `None` when the stones do not overlap. `params` must be valid (the `f64` law checked
/// them).
pub fn pair_jacobian(
    shape: &PairShape,
    params: &MechParams,
    q: [[f64; 3]; 2],
    trial: &PairTrial,
) -> Option<(SVector<f64, 6>, SMatrix<f64, 6, 6>)> {
    let qd: [[D; 3]; 2] = std::array::from_fn(|p| std::array::from_fn(|k| D::variable(q[p][k], 3 * p + k)));
    let c = contact_dual(shape, params, qd)?;
    let (f_n, c) = crushed(c, params, trial);
    // Friction (super::friction): trial from the committed state, return map on the values.
    let dq: Vec<D> = (0..6).map(|k| qd[k / 3][k % 3] - D::from(trial.committed[k / 3][k % 3])).collect();
    let (b_dir, c_dir) = directions(&c);
    let dg = (0..6).fold(D::constant(0.0), |acc, k| acc + c_dir[k] * dq[k]);
    let k_t = params.kt_over_kn * c.k_n;
    let k_t = if k_t.re >= f64::MIN_POSITIVE { k_t } else { D::constant(f64::MIN_POSITIVE) };
    let f_trial = D::from(trial.f_t) + k_t * dg;
    let limit = params.mu * f_n;
    let on_cone = limit.re > 0.0 && f_trial.re.abs() >= (1.0 - ON_CONE) * limit.re;
    let f_t = if f_trial.re.abs() <= limit.re && !on_cone { f_trial } else { f_trial.re.signum() * limit };
    let f: [D; 6] = std::array::from_fn(|k| b_dir[k] * f_n + c_dir[k] * f_t);
    let value = SVector::<f64, 6>::from_fn(|r, _| f[r].re);
    Some((value, SMatrix::<f64, 6, 6>::from_fn(|r, k| f[r].eps[k])))
}

/// The normal contact on duals (the `f64` law's [`super::contact::contact`], its branches
/// taken on the values).
struct DualContact {
    normal: DP,
    point: DP,
    arm_i: DP,
    arm_j: DP,
    area: D,
    chord_length: D,
    k_n: D,
    /// κ = Ē t_z/ℓ_c.
    kappa: f64,
    vertices: Vec<DP>,
    tol: f64,
}

fn re(p: &[DP]) -> Vec<P2> {
    p.iter().map(|v| [v[0].re, v[1].re]).collect()
}

fn moved(poly: &Polygon, about: P2, q: [D; 3]) -> Vec<DP> {
    let (s, c) = q[2].sin_cos();
    poly.vertices
        .iter()
        .map(|&p| {
            let r = [p[0] - about[0], p[1] - about[1]];
            [D::from(about[0]) + c * r[0] - s * r[1] + q[0], D::from(about[1]) + s * r[0] + c * r[1] + q[1]]
        })
        .collect()
}

fn cross(a: DP, b: DP) -> D {
    a[0] * b[1] - a[1] * b[0]
}

fn signed_area(v: &[DP]) -> D {
    let n = v.len();
    0.5 * (0..n).fold(D::constant(0.0), |acc, k| acc + cross(v[k], v[(k + 1) % n]))
}

/// The part of `v` with `n·x ≤ d` (`Polygon::clip_half_plane`).
fn clip(v: &[DP], n: DP, d: D) -> Vec<DP> {
    let mut out = Vec::with_capacity(v.len() + 1);
    let side = |p: DP| n[0] * p[0] + n[1] * p[1] - d;
    for i in 0..v.len() {
        let (p, q) = (v[i], v[(i + 1) % v.len()]);
        let (sp, sq) = (side(p), side(q));
        if sp.re <= 0.0 {
            out.push(p);
        }
        if (sp.re < 0.0 && sq.re > 0.0) || (sp.re > 0.0 && sq.re < 0.0) {
            let t = sp / (sp - sq);
            out.push([p[0] + t * (q[0] - p[0]), p[1] + t * (q[1] - p[1])]);
        }
    }
    out
}

/// The overlap of `a` and `b` without near-duplicate vertices (`overlap_polygon`).
fn overlap(a: &[DP], b: &[DP], tol: f64) -> Vec<DP> {
    let mut r = a.to_vec();
    for i in 0..b.len() {
        if r.len() < 3 {
            break;
        }
        let (p, q) = (b[i], b[(i + 1) % b.len()]);
        let n = [q[1] - p[1], -(q[0] - p[0])];
        r = clip(&r, n, n[0] * p[0] + n[1] * p[1]);
    }
    let far = |p: &DP, q: &DP| (p[0].re - q[0].re).hypot(p[1].re - q[1].re) > tol;
    let mut v: Vec<DP> = Vec::with_capacity(r.len());
    for p in r {
        if v.last().is_none_or(|q| far(&p, q)) {
            v.push(p);
        }
    }
    while v.len() > 1 && !far(&v[0], &v[v.len() - 1]) {
        v.pop();
    }
    v
}

fn contact_dual(shape: &PairShape, params: &MechParams, q: [[D; 3]; 2]) -> Option<DualContact> {
    let mut outline = [0, 1].map(|p| moved(shape.polygons[p], shape.centroids[p], q[p]));
    let polys = outline.clone().map(|o| Polygon { vertices: re(&o) });
    for (o, p) in outline.iter_mut().zip(&polys) {
        if counter_clockwise(p).vertices != p.vertices {
            o.reverse();
        }
    }
    let (pi, pj) = (counter_clockwise(&polys[0]), counter_clockwise(&polys[1]));
    let coord = pi.vertices.iter().chain(&pj.vertices).fold(0.0f64, |m, p| m.max(p[0].abs()).max(p[1].abs()));
    let size = pi.area().min(pj.area()).sqrt();
    let tol = 1e-11 * (coord + size);
    let v = overlap(&outline[0], &outline[1], tol);
    let area = signed_area(&v).abs();
    if v.len() < 3 || area.re.is_nan() || area.re <= 1e-15 * (coord + size).powi(2) {
        return None;
    }
    let x_c = centroid(&v);
    let refs = [0, 1].map(|p| [D::from(shape.centroids[p][0]) + q[p][0], D::from(shape.centroids[p][1]) + q[p][1]]);
    let arm = |p: usize| [x_c[0] - refs[p][0], x_c[1] - refs[p][1]];
    let edges =
        EdgeSums::of(&re(&v), (&pi, &pj), ([refs[0][0].re, refs[0][1].re], [refs[1][0].re, refs[1][1].re]), tol);
    let (normal, chord_length) = if edges.s[0].hypot(edges.s[1]) >= 1e-3 * edges.perimeter {
        let mut s = [D::constant(0.0); 2];
        for (k, side) in edges.sides.iter().enumerate() {
            let (a, b) = (v[k], v[(k + 1) % v.len()]);
            let nu = [b[1] - a[1], a[0] - b[0]];
            match side {
                Side::I => s = [s[0] + nu[0], s[1] + nu[1]],
                Side::J => s = [s[0] - nu[0], s[1] - nu[1]],
                Side::Both => {}
            }
        }
        let s_norm = s[0].hypot(s[1]);
        ([s[0] / s_norm, s[1] / s_norm], 0.5 * s_norm)
    } else {
        let d = [refs[1][0] - refs[0][0], refs[1][1] - refs[0][1]];
        let dn = d[0].hypot(d[1]);
        let n = if dn.re > 0.0 { [d[0] / dn, d[1] / dn] } else { [D::constant(1.0), D::constant(0.0)] };
        let t = [-n[1], n[0]];
        let proj: Vec<D> = v.iter().map(|p| (p[0] - x_c[0]) * t[0] + (p[1] - x_c[1]) * t[1]).collect();
        let lo = proj.iter().copied().reduce(|a, b| if b.re < a.re { b } else { a })?;
        let hi = proj.iter().copied().reduce(|a, b| if b.re > a.re { b } else { a })?;
        (n, hi - lo)
    };
    let l_c = 2.0 / (1.0 / shape.diameters[0] + 1.0 / shape.diameters[1]);
    let kappa = params.e_bar * params.t_z / l_c;
    let (arm_i, arm_j) = (arm(0), arm(1));
    Some(DualContact {
        normal,
        point: x_c,
        arm_i,
        arm_j,
        area,
        chord_length,
        k_n: kappa * chord_length,
        kappa,
        vertices: v,
        tol,
    })
}

fn centroid(v: &[DP]) -> DP {
    let n = v.len();
    let a = signed_area(v);
    let (mut cx, mut cy) = (D::constant(0.0), D::constant(0.0));
    for i in 0..n {
        let (p, q) = (v[i], v[(i + 1) % n]);
        let w = cross(p, q);
        cx += (p[0] + q[0]) * w;
        cy += (p[1] + q[1]) * w;
    }
    [cx / (6.0 * a), cy / (6.0 * a)]
}

/// `b = (n, r_i × n, −n, −r_j × n)` and `c = (−t, −r_i × t, t, r_j × t)` on duals.
fn directions(c: &DualContact) -> ([D; 6], [D; 6]) {
    let n = c.normal;
    let t = [-n[1], n[0]];
    let b = [n[0], n[1], cross(c.arm_i, n), -n[0], -n[1], -cross(c.arm_j, n)];
    let cc = [-t[0], -t[1], -cross(c.arm_i, t), t[0], t[1], cross(c.arm_j, t)];
    (b, cc)
}

/// The normal force with crushing (module docs, "Crushing"), the point moved to the pressure
/// centroid; without crushing `κ S_r`.
fn crushed(mut c: DualContact, params: &MechParams, trial: &PairTrial) -> (D, DualContact) {
    let (Some(cr), Some(u)) = (&params.crushing, &trial.crush) else { return (c.kappa * c.area, c) };
    let profile = DualProfile::of(&c.vertices, c.normal, c.tol);
    let old = trial.plastic;
    let (f_n, depth) = if !u.plastic {
        let s = profile.clipped(D::constant(old.depth)).area;
        (if s.re > 0.0 { c.kappa * s } else { D::constant(0.0) }, D::constant(old.depth))
    } else if u.f_n > 0.0 {
        // g(Δ) = κ S(δ_p + Δ) − σ_c L t_z (1 − (κ_p + Δ)/δ_u), one Newton update on duals.
        let x = u.state.depth - old.depth;
        let d_u = cr.ultimate_penetration();
        let at = profile.clipped(D::constant(u.state.depth));
        let f_y = cr.stress * params.t_z * (1.0 - (old.kappa + x) / d_u).max(0.0) * c.chord_length;
        let g = c.kappa * at.area - f_y;
        let dg = -c.kappa * at.width.re + cr.stress * c.chord_length.re * params.t_z / d_u;
        let mut x_d = D::constant(x) - g / dg;
        x_d.re = x;
        let depth = D::constant(old.depth) + x_d;
        (c.kappa * profile.clipped(depth).area, depth)
    } else {
        return (D::constant(0.0), c);
    };
    if u.plastic || u.state.depth > 0.0 {
        let cl = profile.clipped(depth);
        if cl.area.re > 0.0 {
            let t = [-c.normal[1], c.normal[0]];
            let shift = cl.first / cl.area - (c.point[0] * t[0] + c.point[1] * t[1]);
            for p in [&mut c.point, &mut c.arm_i, &mut c.arm_j] {
                *p = [p[0] + shift * t[0], p[1] + shift * t[1]];
            }
        }
    }
    (f_n, c)
}

/// The thickness profile on duals ([`super::thickness::ThicknessProfile`], built as
/// `thickness_profile` builds it).
struct DualProfile {
    s: Vec<D>,
    delta: Vec<D>,
}

/// [`super::thickness::Clipped`] on duals.
struct DualClipped {
    area: D,
    first: D,
    width: D,
}

impl DualProfile {
    fn of(v: &[DP], n: DP, tol: f64) -> DualProfile {
        let m = v.len();
        let t = [-n[1], n[0]];
        let s: Vec<D> = v.iter().map(|p| p[0] * t[0] + p[1] * t[1]).collect();
        let h: Vec<D> = v.iter().map(|p| p[0] * n[0] + p[1] * n[1]).collect();
        let mut order: Vec<usize> = (0..m).collect();
        order.sort_by(|&a, &b| s[a].re.total_cmp(&s[b].re));
        let mut cuts: Vec<D> = Vec::with_capacity(m);
        for k in order {
            if cuts.last().is_none_or(|c: &D| (s[k].re - c.re).abs() > tol) {
                cuts.push(s[k]);
            }
        }
        let section = |s0: D| -> D {
            let (mut lo, mut hi): (Option<D>, Option<D>) = (None, None);
            for k in 0..m {
                let l = (k + 1) % m;
                let mut add = |x: D| {
                    lo = Some(lo.map_or(x, |a| if x.re < a.re { x } else { a }));
                    hi = Some(hi.map_or(x, |a| if x.re > a.re { x } else { a }));
                };
                if (s[k].re - s0.re).abs() <= tol {
                    add(h[k]);
                }
                let (a, b) = (s[k].re.min(s[l].re), s[k].re.max(s[l].re));
                if b - a > tol && s0.re > a + tol && s0.re < b - tol {
                    add(h[k] + (s0 - s[k]) / (s[l] - s[k]) * (h[l] - h[k]));
                }
            }
            match (lo, hi) {
                (Some(lo), Some(hi)) if hi.re >= lo.re => hi - lo,
                _ => D::constant(0.0),
            }
        };
        let delta = cuts.iter().map(|&c| section(c)).collect();
        DualProfile { s: cuts, delta }
    }

    fn clipped(&self, c: D) -> DualClipped {
        let zero = D::constant(0.0);
        let mut out = DualClipped { area: zero, first: zero, width: zero };
        for k in 0..self.s.len().saturating_sub(1) {
            let (s0, s1) = (self.s[k], self.s[k + 1]);
            let (a, b) = (self.delta[k] - c, self.delta[k + 1] - c);
            if s1.re <= s0.re || (a.re <= 0.0 && b.re <= 0.0) {
                continue;
            }
            let (lo, hi, ya, yb) = if a.re >= 0.0 && b.re >= 0.0 {
                (s0, s1, a, b)
            } else if a.re > 0.0 {
                (s0, s0 + (s1 - s0) * a / (a - b), a, zero)
            } else {
                (s1 - (s1 - s0) * b / (b - a), s1, zero, b)
            };
            let h = hi - lo;
            out.width += h;
            out.area += 0.5 * h * (ya + yb);
            out.first += h * (ya * (2.0 * lo + hi) + yb * (lo + 2.0 * hi)) / 6.0;
        }
        out
    }
}
