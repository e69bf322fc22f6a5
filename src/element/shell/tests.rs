//! Tests of the flat shell elements: rigid-body modes, MacNeal–Harder patch tests, the
//! Scordelis–Lo roof, the first frequency of a simply supported plate, layered integration and the
//! damage law inside the element. Each test states its reference and tolerance.
//!
//! The small systems are assembled here with a dense assembler ([`Model`]) and solved by dense LU
//! (patches) or a skyline Cholesky written below (the roof: ~1700 DOF, profile ≈ 110).

use nalgebra::{DMatrix, DVector, Matrix2, SymmetricEigen, Vector3};

use super::layers::{plane_stress_matrix, ThicknessRule};
use super::{ShellMaterial, ShellQuad4, ShellSection, ShellTri3};
use crate::element::{AppliedLoads, Element, ElementOutput, EvalRequest, MassKind};
use crate::material::DamageParams;

mod layer_tests;

// ---------------------------------------------------------------------------------------------
// A tiny dense model: nodes, elements with their node lists, prescribed DOFs.
// ---------------------------------------------------------------------------------------------

enum Shell {
    Q(Box<ShellQuad4>),
    T(Box<ShellTri3>),
}

impl Shell {
    fn el(&mut self) -> &mut dyn Element {
        match self {
            Shell::Q(e) => e.as_mut(),
            Shell::T(e) => e.as_mut(),
        }
    }
    fn el_ref(&self) -> &dyn Element {
        match self {
            Shell::Q(e) => e.as_ref(),
            Shell::T(e) => e.as_ref(),
        }
    }
    fn axes(&self) -> nalgebra::Matrix3<f64> {
        match self {
            Shell::Q(e) => *e.local_axes(),
            Shell::T(e) => *e.local_axes(),
        }
    }
    fn resultants(&self, u: &[f64]) -> Vec<super::element::PointResultants> {
        match self {
            Shell::Q(e) => e.point_resultants(u).unwrap(),
            Shell::T(e) => e.point_resultants(u).unwrap(),
        }
    }
}

struct Model {
    nodes: Vec<[f64; 3]>,
    elements: Vec<(Shell, Vec<usize>)>,
}

impl Model {
    fn new(nodes: Vec<[f64; 3]>) -> Self {
        Model { nodes, elements: Vec::new() }
    }
    fn n_dofs(&self) -> usize {
        6 * self.nodes.len()
    }
    fn add_quad(&mut self, c: [usize; 4], s: &ShellSection) {
        let x = c.map(|i| self.nodes[i]);
        let e = ShellQuad4::new(x, s).expect("valid quad");
        self.elements.push((Shell::Q(Box::new(e)), c.to_vec()));
    }
    fn add_tri(&mut self, c: [usize; 3], s: &ShellSection) {
        let x = c.map(|i| self.nodes[i]);
        let e = ShellTri3::new(x, s).expect("valid triangle");
        self.elements.push((Shell::T(Box::new(e)), c.to_vec()));
    }
    fn dofs(conn: &[usize]) -> Vec<usize> {
        conn.iter().flat_map(|&n| (0..6).map(move |k| 6 * n + k)).collect()
    }
    /// Global tangent at u = 0 (elastic: the stiffness).
    fn stiffness(&mut self) -> DMatrix<f64> {
        let n = self.n_dofs();
        let mut k = DMatrix::zeros(n, n);
        let mut out = ElementOutput::new(24);
        for (e, conn) in &mut self.elements {
            let d = Self::dofs(conn);
            e.el().evaluate(&vec![0.0; d.len()], EvalRequest::ForceAndTangent, &mut out).unwrap();
            for (a, &ga) in d.iter().enumerate() {
                for (b, &gb) in d.iter().enumerate() {
                    k[(ga, gb)] += out.k_t[(a, b)];
                }
            }
        }
        k
    }
    fn mass(&self, kind: MassKind) -> DMatrix<f64> {
        let n = self.n_dofs();
        let mut m = DMatrix::zeros(n, n);
        let mut me = DMatrix::zeros(0, 0);
        for (e, conn) in &self.elements {
            let d = Self::dofs(conn);
            e.el_ref().mass(kind, &mut me);
            for (a, &ga) in d.iter().enumerate() {
                for (b, &gb) in d.iter().enumerate() {
                    m[(ga, gb)] += me[(a, b)];
                }
            }
        }
        m
    }
    fn gravity(&self, g: [f64; 3]) -> DVector<f64> {
        let mut f = DVector::zeros(self.n_dofs());
        let mut fe = DVector::zeros(0);
        for (e, conn) in &self.elements {
            e.el_ref().gravity_load(g, &mut fe);
            for (a, ga) in Self::dofs(conn).into_iter().enumerate() {
                f[ga] += fe[a];
            }
        }
        f
    }
    fn element_u(&self, i: usize, u: &DVector<f64>) -> Vec<f64> {
        Self::dofs(&self.elements[i].1).iter().map(|&d| u[d]).collect()
    }
}

/// Solve K u = f with u = `prescribed` on the given DOFs; `skyline` selects the Cholesky solver
/// (K_ff must then be positive definite), otherwise dense LU.
fn solve(k: &DMatrix<f64>, f: &DVector<f64>, prescribed: &[(usize, f64)], skyline: bool) -> DVector<f64> {
    let n = k.nrows();
    let mut u = DVector::zeros(n);
    let mut fixed = vec![false; n];
    for &(d, v) in prescribed {
        fixed[d] = true;
        u[d] = v;
    }
    let free: Vec<usize> = (0..n).filter(|&d| !fixed[d]).collect();
    let kff = DMatrix::from_fn(free.len(), free.len(), |i, j| k[(free[i], free[j])]);
    let rhs = DVector::from_fn(free.len(), |i, _| {
        f[free[i]] - (0..n).filter(|&d| fixed[d]).map(|d| k[(free[i], d)] * u[d]).sum::<f64>()
    });
    let x = if skyline { skyline_cholesky_solve(kff, &rhs) } else { kff.lu().solve(&rhs).expect("regular") };
    for (i, &d) in free.iter().enumerate() {
        u[d] = x[i];
    }
    u
}

/// Cholesky L Lᵀ restricted to the profile (first nonzero of each row), in place on dense storage;
/// cost ~ n b² for profile b.
fn skyline_cholesky_solve(mut a: DMatrix<f64>, b: &DVector<f64>) -> DVector<f64> {
    let n = a.nrows();
    let first: Vec<usize> = (0..n).map(|i| (0..=i).find(|&j| a[(i, j)] != 0.0).unwrap_or(i)).collect();
    for i in 0..n {
        for j in first[i]..=i {
            let mut s = a[(i, j)];
            for k in first[i].max(first[j])..j {
                s -= a[(i, k)] * a[(j, k)];
            }
            if i == j {
                assert!(s > 0.0, "not positive definite at {i}: {s}");
                a[(i, i)] = s.sqrt();
            } else {
                a[(i, j)] = s / a[(j, j)];
            }
        }
    }
    let mut y = b.clone();
    for i in 0..n {
        let mut s = y[i];
        for k in first[i]..i {
            s -= a[(i, k)] * y[k];
        }
        y[i] = s / a[(i, i)];
    }
    for i in (0..n).rev() {
        y[i] /= a[(i, i)];
        let yi = y[i];
        for k in first[i]..i {
            y[k] -= a[(i, k)] * yi;
        }
    }
    y
}

fn elastic(t: f64, e: f64, nu: f64, rho: f64) -> ShellSection {
    ShellSection::elastic(t, e, nu, rho)
}

fn damage_params() -> DamageParams {
    // The material module's reference set.
    crate::material::test_support::params()
}

/// Components (11, 22, 12) of the symmetric 2×2 tensor `s` (global xy) in the element's local
/// axes e₁, e₂ (rows of `r`; the element lies in the global xy plane).
fn to_local(r: &nalgebra::Matrix3<f64>, s: &Matrix2<f64>) -> Vector3<f64> {
    let e1 = nalgebra::Vector2::new(r[(0, 0)], r[(0, 1)]);
    let e2 = nalgebra::Vector2::new(r[(1, 0)], r[(1, 1)]);
    Vector3::new(e1.dot(&(s * e1)), e2.dot(&(s * e2)), e1.dot(&(s * e2)))
}

// ---------------------------------------------------------------------------------------------
// Rigid-body modes
// ---------------------------------------------------------------------------------------------

fn count_zero_eigenvalues(k: &DMatrix<f64>) -> (usize, f64) {
    let sym = (k + k.transpose()) * 0.5;
    let ev = SymmetricEigen::new(sym).eigenvalues;
    let max = ev.amax();
    let zeros = ev.iter().filter(|l| l.abs() < 1e-10 * max).count();
    let min_nonzero = ev.iter().filter(|l| l.abs() >= 1e-10 * max).fold(f64::INFINITY, |m, l| m.min(l.abs()));
    (zeros, min_nonzero / max)
}

fn rigid_motion(coords: &[[f64; 3]], c: Vector3<f64>, th: Vector3<f64>) -> Vec<f64> {
    let mut u = Vec::new();
    for x in coords {
        let t = c + th.cross(&Vector3::from(*x));
        u.extend_from_slice(t.as_slice());
        u.extend_from_slice(th.as_slice());
    }
    u
}

/// K of one element (flat irregular quad, slightly warped quad, triangle, all arbitrarily placed
/// in space) has exactly 6 zero eigenvalues (|λ| < 1e-10 λ_max; the smallest non-zero one is
/// ≫ that), and a rigid motion gives |f| ≤ 1e-9 ‖K‖ ‖u‖.
#[test]
fn rigid_body_modes() {
    let s = elastic(0.05, 2e9, 0.25, 2000.0);
    // Orthonormal map of the plane xy to a tilted plane, plus a shift.
    let a = Vector3::new(0.6, 0.64, 0.48);
    let b = Vector3::new(-0.8, 0.48, 0.36);
    let n = a.cross(&b);
    let place = |x: f64, y: f64, z: f64| -> [f64; 3] { (Vector3::new(1.0, -2.0, 3.0) + a * x + b * y + n * z).into() };
    let flat = [place(0.0, 0.0, 0.0), place(1.1, 0.1, 0.0), place(1.0, 0.9, 0.0), place(-0.1, 0.8, 0.0)];
    // Warping ±0.02 on a ~1 m element: ratio 0.02 < WARPING_LIMIT.
    let warped = [place(0.0, 0.0, 0.02), place(1.1, 0.1, -0.02), place(1.0, 0.9, 0.02), place(-0.1, 0.8, -0.02)];
    let tri = [place(0.0, 0.0, 0.0), place(1.2, 0.2, 0.0), place(0.3, 0.9, 0.0)];
    type Placed = (Box<dyn Element>, Vec<[f64; 3]>);
    let mut elems: Vec<Placed> = vec![
        (Box::new(ShellQuad4::new(flat, &s).unwrap()), flat.to_vec()),
        (Box::new(ShellQuad4::new(warped, &s).unwrap()), warped.to_vec()),
        (Box::new(ShellTri3::new(tri, &s).unwrap()), tri.to_vec()),
    ];
    let mut out = ElementOutput::new(24);
    for (e, x) in &mut elems {
        let nd = e.n_dofs();
        e.evaluate(&vec![0.0; nd], EvalRequest::ForceAndTangent, &mut out).unwrap();
        let k = out.k_t.clone();
        let (zeros, gap) = count_zero_eigenvalues(&k);
        println!("{}: {zeros} zero eigenvalues, smallest non-zero / largest = {gap:e}", e.kind_name());
        assert_eq!(zeros, 6, "{}", e.kind_name());
        for (c, th) in [
            (Vector3::new(1.0, 2.0, -1.0), Vector3::zeros()),
            (Vector3::zeros(), Vector3::new(0.3, -0.2, 0.5)),
            (Vector3::new(-0.5, 0.1, 0.2), Vector3::new(-0.1, 0.4, 0.05)),
        ] {
            let u = rigid_motion(x, c, th);
            e.evaluate(&u, EvalRequest::Force, &mut out).unwrap();
            let un = DVector::from_column_slice(&u).norm();
            assert!(out.f_int.amax() <= 1e-9 * k.amax() * un, "{}: {}", e.kind_name(), out.f_int.amax());
        }
    }
}

// ---------------------------------------------------------------------------------------------
// MacNeal–Harder patch (MacNeal & Harder 1985, Fig. 2): rectangle 0.24 × 0.12, 5 elements.
// ---------------------------------------------------------------------------------------------
//
//   3 (0,.12) ______________________ 2 (.24,.12)
//       |  \                    /  |
//       |   7 (.08,.08)__6 (.16,.08)|
//       |   |              \       |
//       |   4 (.04,.02)_____5 (.18,.03)
//       |  /                   \   |
//   0 (0,0) ______________________ 1 (.24,0)

fn patch_nodes() -> Vec<[f64; 3]> {
    vec![
        [0.0, 0.0, 0.0],
        [0.24, 0.0, 0.0],
        [0.24, 0.12, 0.0],
        [0.0, 0.12, 0.0],
        [0.04, 0.02, 0.0],
        [0.18, 0.03, 0.0],
        [0.16, 0.08, 0.0],
        [0.08, 0.08, 0.0],
    ]
}
const PATCH_QUADS: [[usize; 4]; 5] = [[0, 1, 5, 4], [1, 2, 6, 5], [2, 3, 7, 6], [3, 0, 4, 7], [4, 5, 6, 7]];

fn patch_model(s: &ShellSection, triangles: bool) -> Model {
    let mut m = Model::new(patch_nodes());
    for q in PATCH_QUADS {
        if triangles {
            m.add_tri([q[0], q[1], q[2]], s);
            m.add_tri([q[0], q[2], q[3]], s);
        } else {
            m.add_quad(q, s);
        }
    }
    m
}

/// Membrane patch: u = 1e-3 (x + y/2), v = 1e-3 (y + x/2) on the boundary nodes (all other boundary
/// DOF 0). Exact: ε = 1e-3 (1, 1, 1) (γ_xy), N = t C ε everywhere. Checked at every in-plane point
/// of every element in its local axes, relative to |N|: 1e-8. Quads and triangles (CST).
#[test]
fn membrane_patch_test() {
    let (e, nu, t) = (1e6, 0.25, 0.001);
    let s = elastic(t, e, nu, 1.0);
    let eps = Vector3::new(1e-3, 1e-3, 1e-3);
    let n = plane_stress_matrix(e, nu) * eps * t;
    let n_tensor = Matrix2::new(n.x, n.z, n.z, n.y);
    for triangles in [false, true] {
        let mut m = patch_model(&s, triangles);
        let k = m.stiffness();
        let mut bc = Vec::new();
        for (i, x) in m.nodes.iter().enumerate().take(4) {
            let (u, v) = (1e-3 * (x[0] + x[1] / 2.0), 1e-3 * (x[1] + x[0] / 2.0));
            bc.extend([(6 * i, u), (6 * i + 1, v)]);
            bc.extend((2..6).map(|c| (6 * i + c, 0.0)));
        }
        let u = solve(&k, &DVector::zeros(m.n_dofs()), &bc, false);
        for (i, x) in m.nodes.iter().enumerate().skip(4) {
            assert!((u[6 * i] - 1e-3 * (x[0] + x[1] / 2.0)).abs() < 1e-12, "interior u");
            assert!((u[6 * i + 1] - 1e-3 * (x[1] + x[0] / 2.0)).abs() < 1e-12, "interior v");
        }
        let mut worst = 0.0f64;
        for i in 0..m.elements.len() {
            let ue = m.element_u(i, &u);
            let el = &m.elements[i].0;
            let expect = to_local(&el.axes(), &n_tensor);
            for super::element::PointResultants { n: nn, m: mm } in el.resultants(&ue) {
                worst = worst.max((nn - expect).amax() / n.amax());
                assert!(mm.amax() < 1e-8 * n.amax() * t);
            }
        }
        println!("membrane patch ({}): worst relative error {worst:e}", if triangles { "tri" } else { "quad" });
        assert!(worst < 1e-8);
    }
}

/// Bending patch: w = 1e-3 (x² + xy + y²)/2, θx = ∂w/∂y, θy = −∂w/∂x on the boundary, u = v = θz
/// = 0 there, t = 0.001. Exact: κ = −1e-3 (1, 1, 1), M = D κ (Kirchhoff; the transverse shear is
/// zero), at every in-plane point, 1e-6 relative. Quads (MITC4) and triangles (DKT).
#[test]
fn bending_patch_test() {
    let (e, nu, t) = (1e6, 0.25, 0.001);
    let s = elastic(t, e, nu, 1.0);
    let kappa = Vector3::new(-1e-3, -1e-3, -1e-3);
    let mom = plane_stress_matrix(e, nu) * kappa * (t * t * t / 12.0);
    let m_tensor = Matrix2::new(mom.x, mom.z, mom.z, mom.y);
    let w = |x: &[f64; 3]| 1e-3 * (x[0] * x[0] + x[0] * x[1] + x[1] * x[1]) / 2.0;
    let thx = |x: &[f64; 3]| 1e-3 * (x[0] / 2.0 + x[1]);
    let thy = |x: &[f64; 3]| -1e-3 * (x[0] + x[1] / 2.0);
    for triangles in [false, true] {
        let mut m = patch_model(&s, triangles);
        let k = m.stiffness();
        let mut bc = Vec::new();
        for (i, x) in m.nodes.iter().enumerate().take(4) {
            bc.extend([
                (6 * i, 0.0),
                (6 * i + 1, 0.0),
                (6 * i + 2, w(x)),
                (6 * i + 3, thx(x)),
                (6 * i + 4, thy(x)),
                (6 * i + 5, 0.0),
            ]);
        }
        let u = solve(&k, &DVector::zeros(m.n_dofs()), &bc, false);
        for (i, x) in m.nodes.iter().enumerate().skip(4) {
            assert!((u[6 * i + 2] - w(x)).abs() < 1e-9 * w(x).abs(), "interior w");
        }
        let mut worst = 0.0f64;
        for i in 0..m.elements.len() {
            let ue = m.element_u(i, &u);
            let el = &m.elements[i].0;
            let expect = to_local(&el.axes(), &m_tensor);
            for super::element::PointResultants { m: mm, .. } in el.resultants(&ue) {
                worst = worst.max((mm - expect).amax() / mom.amax());
            }
        }
        println!("bending patch ({}): worst relative moment error {worst:e}", if triangles { "tri" } else { "quad" });
        assert!(worst < 1e-6);
    }
}

// ---------------------------------------------------------------------------------------------
// Scordelis–Lo roof (MacNeal & Harder 1985, test 3)
// ---------------------------------------------------------------------------------------------
//
//   Cylinder of radius R = 25 along global x, length L = 50, opening ±40° about the crown (+z),
//   t = 0.25, E = 4.32e8, ν = 0, self weight 90 per area (−z). Rigid diaphragms at the ends
//   (u_y = u_z = 0, θ_x = 0), long edges free. Quarter model x ∈ [0, 25], φ ∈ [0, 40°]:
//
//      φ=40° free edge  ·──────────────·  ← reference point (x = 25, φ = 40°): u_z = −0.3024
//                       │              │
//      x=0: diaphragm   │   n × n      │  x = 25: symmetry (u_x = θ_y = θ_z = 0)
//                       │              │
//      φ=0 crown        ·──────────────·  symmetry (u_y = θ_x = θ_z = 0)

fn scordelis_lo(n: usize, triangles: bool) -> f64 {
    let (r, half_l, phi_max) = (25.0, 25.0, 40f64.to_radians());
    let t = 0.25;
    let s = ShellSection { density: 90.0 / t, ..elastic(t, 4.32e8, 0.0, 0.0) };
    let id = |i: usize, j: usize| j * (n + 1) + i;
    let mut nodes = Vec::new();
    for j in 0..=n {
        for i in 0..=n {
            let phi = phi_max * j as f64 / n as f64;
            nodes.push([half_l * i as f64 / n as f64, r * phi.sin(), r * phi.cos()]);
        }
    }
    let mut m = Model::new(nodes);
    for j in 0..n {
        for i in 0..n {
            let q = [id(i, j), id(i + 1, j), id(i + 1, j + 1), id(i, j + 1)];
            if triangles {
                m.add_tri([q[0], q[1], q[2]], &s);
                m.add_tri([q[0], q[2], q[3]], &s);
            } else {
                m.add_quad(q, &s);
            }
        }
    }
    let mut bc = std::collections::BTreeMap::new();
    for k in 0..=n {
        for d in [1, 2, 3] {
            bc.insert(6 * id(0, k) + d, 0.0); // diaphragm
        }
        for d in [0, 4, 5] {
            bc.insert(6 * id(n, k) + d, 0.0); // symmetry x = L/2
        }
        for d in [1, 3, 5] {
            bc.insert(6 * id(k, 0) + d, 0.0); // symmetry at the crown
        }
    }
    let bc: Vec<(usize, f64)> = bc.into_iter().collect();
    let k = m.stiffness();
    let f = m.gravity([0.0, 0.0, -1.0]);
    let u = solve(&k, &f, &bc, true);
    -u[6 * id(n, n) + 2]
}

/// Vertical deflection at the middle of the free edge, reference 0.3024 (MacNeal & Harder 1985):
/// 16×16 quads within 2 %. The table (quads, and each quad split into two triangles) is printed.
#[test]
fn scordelis_lo_roof() {
    let reference = 0.3024;
    println!("Scordelis-Lo roof, u_z at the free-edge midpoint (reference {reference})");
    println!("  mesh     MITC4      ratio    DKT+CST    ratio");
    let mut quad16 = 0.0;
    for n in [4, 8, 16] {
        let q = scordelis_lo(n, false);
        let t = scordelis_lo(n, true);
        println!("  {n:2}x{n:<2}   {q:.5}   {:.4}   {t:.5}   {:.4}", q / reference, t / reference);
        if n == 16 {
            quad16 = q;
        }
    }
    assert!((quad16 / reference - 1.0).abs() < 0.02, "16x16 MITC4: {quad16}");
}

// ---------------------------------------------------------------------------------------------
// First frequency of a simply supported square plate (Leissa 1969, NASA SP-160, eq. 4.4)
// ---------------------------------------------------------------------------------------------

/// a = 1, t = 0.01, E = 2e11, ν = 0.3, ρ = 7850: ω₁ = 2π²/a² sqrt(D/(ρ t)), D = E t³/(12(1−ν²)).
/// 12×12 MITC4, consistent mass, w = 0 on the edges (rotations free); the in-plane DOF (u, v, θz)
/// are fixed everywhere: for a flat elastic plate they do not couple with bending. Within 1 %.
#[test]
fn plate_first_frequency() {
    let (a, t, e, nu, rho) = (1.0, 0.01, 2e11, 0.3, 7850.0);
    let n = 12;
    let s = elastic(t, e, nu, rho);
    let id = |i: usize, j: usize| j * (n + 1) + i;
    let mut nodes = Vec::new();
    for j in 0..=n {
        for i in 0..=n {
            nodes.push([a * i as f64 / n as f64, a * j as f64 / n as f64, 0.0]);
        }
    }
    let mut m = Model::new(nodes);
    for j in 0..n {
        for i in 0..n {
            m.add_quad([id(i, j), id(i + 1, j), id(i + 1, j + 1), id(i, j + 1)], &s);
        }
    }
    let k = m.stiffness();
    for kind in [MassKind::Consistent, MassKind::Lumped] {
        let mass = m.mass(kind);
        let mut free = Vec::new();
        for j in 0..=n {
            for i in 0..=n {
                let edge = i == 0 || j == 0 || i == n || j == n;
                let base = 6 * id(i, j);
                if !edge {
                    free.push(base + 2);
                }
                free.extend([base + 3, base + 4]);
            }
        }
        let kf = DMatrix::from_fn(free.len(), free.len(), |p, q| k[(free[p], free[q])]);
        let mf = DMatrix::from_fn(free.len(), free.len(), |p, q| mass[(free[p], free[q])]);
        let l = mf.cholesky().expect("M positive definite").l();
        let linv = l.clone().try_inverse().expect("regular L");
        let a_mat = &linv * kf * linv.transpose();
        let a_sym = (&a_mat + a_mat.transpose()) * 0.5;
        let lam = SymmetricEigen::new(a_sym).eigenvalues.min();
        let omega = lam.sqrt();
        let d = e * t * t * t / (12.0 * (1.0 - nu * nu));
        let exact = 2.0 * std::f64::consts::PI.powi(2) / (a * a) * (d / (rho * t)).sqrt();
        let err = omega / exact - 1.0;
        println!(
            "plate 12x12 {kind:?} mass: omega_1 = {omega:.4} rad/s, Leissa {exact:.4}, error {:.3} %",
            100.0 * err
        );
        if kind == MassKind::Consistent {
            assert!(err.abs() < 0.01);
        }
    }
}
