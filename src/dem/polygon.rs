//! Convex polygons in the plane: the shape of a stone, of a Voronoi cell, of a contact overlap.
//!
//! Vertices are stored counter-clockwise without repeating the first one. The formulas:
//!
//! * area (shoelace) `A = ½ Σ (x_i y_{i+1} − x_{i+1} y_i)`;
//! * centroid `c = 1/(6A) Σ (p_i + p_{i+1}) (x_i y_{i+1} − x_{i+1} y_i)`;
//! * clipping by the half-plane `n·x ≤ d` (Sutherland–Hodgman, one edge): keep inside vertices,
//!   add the crossing point `p + t (q − p)`, `t = (d − n·p)/(n·(q − p))`, where an edge crosses;
//! * the intersection of two convex polygons is one polygon clipped by every edge half-plane of
//!   the other.

/// A point or vector of the plane.
pub type P2 = [f64; 2];

/// A convex polygon, vertices counter-clockwise.
#[derive(Clone, Debug, PartialEq)]
pub struct Polygon {
    /// Vertices, counter-clockwise, first not repeated.
    pub vertices: Vec<P2>,
}

fn cross(a: P2, b: P2) -> f64 {
    a[0] * b[1] - a[1] * b[0]
}

fn sub(a: P2, b: P2) -> P2 {
    [a[0] - b[0], a[1] - b[1]]
}

impl Polygon {
    /// A polygon from vertices in either orientation (made counter-clockwise).
    pub fn new(mut vertices: Vec<P2>) -> Polygon {
        let mut p = Polygon { vertices: Vec::new() };
        if signed_area(&vertices) < 0.0 {
            vertices.reverse();
        }
        p.vertices = vertices;
        p
    }

    /// The axis-aligned rectangle `[x0, x1] × [y0, y1]`.
    pub fn rectangle(x0: f64, y0: f64, x1: f64, y1: f64) -> Polygon {
        Polygon { vertices: vec![[x0, y0], [x1, y0], [x1, y1], [x0, y1]] }
    }

    /// Number of vertices.
    pub fn len(&self) -> usize {
        self.vertices.len()
    }

    /// Whether it has fewer than three vertices (no area).
    pub fn is_empty(&self) -> bool {
        self.vertices.len() < 3
    }

    /// Area (≥ 0).
    pub fn area(&self) -> f64 {
        signed_area(&self.vertices).abs()
    }

    /// Centroid (the vertex mean for a degenerate polygon).
    pub fn centroid(&self) -> P2 {
        let v = &self.vertices;
        let n = v.len();
        let a = signed_area(v);
        if n < 3 || a.abs() < f64::MIN_POSITIVE {
            let k = n.max(1) as f64;
            return [v.iter().map(|p| p[0]).sum::<f64>() / k, v.iter().map(|p| p[1]).sum::<f64>() / k];
        }
        let (mut cx, mut cy) = (0.0, 0.0);
        for i in 0..n {
            let (p, q) = (v[i], v[(i + 1) % n]);
            let w = cross(p, q);
            cx += (p[0] + q[0]) * w;
            cy += (p[1] + q[1]) * w;
        }
        [cx / (6.0 * a), cy / (6.0 * a)]
    }

    /// Second moment of area about the centroid, polar (`∫ |x − c|² dA`), for rotational inertia.
    pub fn polar_moment(&self) -> f64 {
        let c = self.centroid();
        let v: Vec<P2> = self.vertices.iter().map(|&p| sub(p, c)).collect();
        let n = v.len();
        let mut j = 0.0;
        for i in 0..n {
            let (p, q) = (v[i], v[(i + 1) % n]);
            let w = cross(p, q);
            j += w * (p[0] * p[0] + p[0] * q[0] + q[0] * q[0] + p[1] * p[1] + p[1] * q[1] + q[1] * q[1]);
        }
        (j / 12.0).abs()
    }

    /// The part with `n·x ≤ d`.
    pub fn clip_half_plane(&self, n: P2, d: f64) -> Polygon {
        let v = &self.vertices;
        let mut out = Vec::with_capacity(v.len() + 1);
        let side = |p: P2| n[0] * p[0] + n[1] * p[1] - d;
        for i in 0..v.len() {
            let (p, q) = (v[i], v[(i + 1) % v.len()]);
            let (sp, sq) = (side(p), side(q));
            if sp <= 0.0 {
                out.push(p);
            }
            if (sp < 0.0 && sq > 0.0) || (sp > 0.0 && sq < 0.0) {
                let t = sp / (sp - sq);
                out.push([p[0] + t * (q[0] - p[0]), p[1] + t * (q[1] - p[1])]);
            }
        }
        Polygon { vertices: out }
    }

    /// The intersection with another convex polygon (empty when they do not overlap).
    pub fn intersection(&self, other: &Polygon) -> Polygon {
        let mut r = self.clone();
        let w = &other.vertices;
        for i in 0..w.len() {
            if r.is_empty() {
                break;
            }
            let (p, q) = (w[i], w[(i + 1) % w.len()]);
            let e = sub(q, p);
            // Inside of a CCW edge is to its left: outward normal (e_y, −e_x).
            let n = [e[1], -e[0]];
            r = r.clip_half_plane(n, n[0] * p[0] + n[1] * p[1]);
        }
        r
    }

    /// Whether the polygon is convex and counter-clockwise (every turn left, within `tol`
    /// relative to the edge lengths).
    pub fn is_convex(&self, tol: f64) -> bool {
        let v = &self.vertices;
        let n = v.len();
        n >= 3
            && (0..n).all(|i| {
                let (a, b, c) = (v[i], v[(i + 1) % n], v[(i + 2) % n]);
                let (e1, e2) = (sub(b, a), sub(c, b));
                let scale = (e1[0].hypot(e1[1]) * e2[0].hypot(e2[1])).max(f64::MIN_POSITIVE);
                cross(e1, e2) >= -tol * scale
            })
    }

    /// Length of the shortest edge.
    pub fn shortest_edge(&self) -> f64 {
        let v = &self.vertices;
        (0..v.len())
            .map(|i| {
                let e = sub(v[(i + 1) % v.len()], v[i]);
                e[0].hypot(e[1])
            })
            .fold(f64::INFINITY, f64::min)
    }

    /// The polygon moved rigidly: rotated by `theta` about `about`, then translated by `u`.
    pub fn moved(&self, about: P2, u: P2, theta: f64) -> Polygon {
        let (s, c) = theta.sin_cos();
        Polygon {
            vertices: self
                .vertices
                .iter()
                .map(|&p| {
                    let r = sub(p, about);
                    [about[0] + c * r[0] - s * r[1] + u[0], about[1] + s * r[0] + c * r[1] + u[1]]
                })
                .collect(),
        }
    }
}

fn signed_area(v: &[P2]) -> f64 {
    let n = v.len();
    if n < 3 {
        return 0.0;
    }
    0.5 * (0..n).map(|i| cross(v[i], v[(i + 1) % n])).sum::<f64>()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn rectangle_properties_match_closed_forms() {
        // 2 × 1 rectangle: A = 2, centroid (1, 0.5), J = A (a² + b²)/12 = 2·5/12.
        let r = Polygon::rectangle(0.0, 0.0, 2.0, 1.0);
        assert!((r.area() - 2.0).abs() < 1e-15);
        assert_eq!(r.centroid(), [1.0, 0.5]);
        assert!((r.polar_moment() - 10.0 / 12.0).abs() < 1e-14);
        assert!(r.is_convex(0.0));
        assert!((r.shortest_edge() - 1.0).abs() < 1e-15);
    }

    #[test]
    fn clockwise_input_is_reoriented() {
        let p = Polygon::new(vec![[0.0, 0.0], [0.0, 1.0], [1.0, 1.0], [1.0, 0.0]]);
        assert!(signed_area(&p.vertices) > 0.0);
    }

    #[test]
    fn overlap_of_two_squares() {
        // Unit squares, the second shifted by (0.75, 0.5): overlap 0.25 × 0.5 at (0.875, 0.75).
        let a = Polygon::rectangle(0.0, 0.0, 1.0, 1.0);
        let b = Polygon::rectangle(0.75, 0.5, 1.75, 1.5);
        let o = a.intersection(&b);
        assert!((o.area() - 0.125).abs() < 1e-15, "{o:?}");
        let c = o.centroid();
        assert!((c[0] - 0.875).abs() < 1e-15 && (c[1] - 0.75).abs() < 1e-15);
        // Disjoint squares do not overlap.
        let far = Polygon::rectangle(2.0, 0.0, 3.0, 1.0);
        assert!(a.intersection(&far).area() < 1e-300);
    }

    #[test]
    fn clipping_a_triangle() {
        // Right triangle (0,0),(2,0),(0,2) cut by x ≤ 1: area 2 − ½ = 1.5.
        let t = Polygon::new(vec![[0.0, 0.0], [2.0, 0.0], [0.0, 2.0]]);
        let c = t.clip_half_plane([1.0, 0.0], 1.0);
        assert!((c.area() - 1.5).abs() < 1e-15);
        assert!(c.is_convex(1e-12));
    }

    #[test]
    fn rigid_motion_keeps_area_and_moves_centroid() {
        let r = Polygon::rectangle(0.0, 0.0, 2.0, 1.0);
        let m = r.moved([1.0, 0.5], [3.0, -1.0], 0.7);
        assert!((m.area() - 2.0).abs() < 1e-14);
        let c = m.centroid();
        assert!((c[0] - 4.0).abs() < 1e-14 && (c[1] + 0.5).abs() < 1e-14);
    }
}
