//! 2-node elastic 3D frame element (Euler–Bernoulli: no shear deformation), 12 DOF.
//!
//! # Local axes and DOF
//! Local axes from the orientation vector `vecxz` ([`LocalFrame`], OpenSees convention: `vecxz`
//! lies in the local x–z plane). Local DOF per node, node-major:
//!
//! ```text
//!   index:  0   1   2   3   4   5  |  6   7   8   9   10  11
//!   dof:    u1  v1  w1  θx1 θy1 θz1 |  u2  v2  w2  θx2 θy2 θz2
//! ```
//! u, v, w: displacements along local x, y, z; θ: rotations about local x, y, z (right-hand rule).
//! Euler–Bernoulli kinematics: θz = dv/dx, θy = −dw/dx.
//!
//! # Local stiffness K_l (standard, e.g. Przemieniecki, *Theory of Matrix Structural Analysis*, §5.6)
//! ```text
//!   axial   (u1, u2):           EA/L  [ 1 −1; −1 1 ]
//!   torsion (θx1, θx2):         GJ/L  [ 1 −1; −1 1 ]
//!   bending x–y (v1 θz1 v2 θz2), EIz/L³ ·
//!        [  12    6L   −12    6L  ]
//!        [  6L   4L²   −6L   2L²  ]
//!        [ −12   −6L    12   −6L  ]
//!        [  6L   2L²   −6L   4L²  ]
//!   bending x–z (w1 θy1 w2 θy2), EIy/L³ · S B S with S = diag(1, −1, 1, −1)
//!        (the same matrix B with the translation–rotation couplings negated, since θy = −dw/dx)
//! ```
//! Global: K = Tᵀ K_l T with T = diag(R, R, R, R).
//!
//! # Self weight and mass
//! From the line mass m = ρA + m_ns (non-structural mass per length) and the rotary inertia ρ Ip
//! per length: consistent nodal loads f_q and consistent or lumped mass, in
//! [`beam_inertia`](super::beam_inertia) (shared with the fiber beam). Global: f = Tᵀ f_q,
//! M = Tᵀ M_l T; the lumped matrix stays block diagonal per node in global axes.
//!
//! # Member end forces
//! f_l = K_l T u_e − f_q: the forces and moments the nodes exert on the element, in local axes, at
//! each end (OpenSees `localForce` convention: components along the local axes, **not** a section
//! sign convention). So a member in tension has N_1 < 0 and N_2 > 0; a cantilever carrying a tip
//! load P along +y at node 2 has Vy_2 = P, Vy_1 = −P, Mz_1 = −P L.

use nalgebra::{DMatrix, DVector, Matrix4};

use super::beam_inertia::{self, add_bar, add_plane, PLANE_XY, PLANE_XZ, S_XZ};
use super::error::{check_finite_displacement, check_len, ElementError};
use super::frame_section::FrameSection;
use super::local_frame::{LocalFrame, Mat12, Vec12};
use super::output::{prepare_matrix, prepare_vector, ElementOutput, EvalRequest};
use super::{AppliedLoads, Element, MassKind};

/// Number of DOF of the element.
const N_DOFS: usize = 12;

/// Names of the cell quantities: member end forces in local axes at node 1 then node 2.
/// Cell outputs: `axial_force` (engineering sign: tension positive; the mean of the two ends,
/// `(N_2 − N_1)/2`, which differs from either end only by the axial part of a distributed
/// load), then the twelve end forces in local axes as the element applies them to its nodes
/// (OpenSees `localForce`: `N_1 < 0` in tension).
const CELL_OUTPUT_NAMES: [&str; 13] =
    ["axial_force", "N_1", "Vy_1", "Vz_1", "T_1", "My_1", "Mz_1", "N_2", "Vy_2", "Vz_2", "T_2", "My_2", "Mz_2"];

/// A 2-node, 12-DOF linear elastic 3D frame element (Euler–Bernoulli). See the module docs for the
/// matrices and sign conventions. Stateless: `commit`/`revert` do nothing and `n_state() == 0`.
#[derive(Clone, Debug, PartialEq)]
pub struct ElasticFrame3d {
    coords: [[f64; 3]; 2],
    frame: LocalFrame,
    section: FrameSection,
}

/// Euler–Bernoulli bending stiffness of the x–y plane (v1 θz1 v2 θz2) for EI = 1.
fn bending_stiffness_unit(l: f64) -> Matrix4<f64> {
    let (l2, l3) = (l * l, l * l * l);
    #[rustfmt::skip]
    let b = Matrix4::new(
        12.0,      6.0 * l,  -12.0,      6.0 * l,
        6.0 * l,   4.0 * l2, -6.0 * l,   2.0 * l2,
        -12.0,    -6.0 * l,   12.0,     -6.0 * l,
        6.0 * l,   2.0 * l2, -6.0 * l,   4.0 * l2,
    );
    b / l3
}

/// Copy a 12×12 static matrix into a dynamic one of the same size.
fn copy_into(dst: &mut DMatrix<f64>, src: &Mat12) {
    prepare_matrix(dst, N_DOFS);
    dst.copy_from(src);
}

impl ElasticFrame3d {
    /// An element from node 1 at `x1` to node 2 at `x2`, local axes from `vecxz`
    /// (see [`LocalFrame`]), with the elastic `section` (validated here).
    ///
    /// Errors: [`ElementError::InvalidSection`], [`ElementError::NonFiniteCoordinates`],
    /// [`ElementError::ZeroLength`], [`ElementError::BadOrientation`].
    pub fn new(x1: [f64; 3], x2: [f64; 3], vecxz: [f64; 3], section: FrameSection) -> Result<Self, ElementError> {
        section.validate()?;
        let frame = LocalFrame::from_vecxz(x1, x2, vecxz)?;
        Ok(Self { coords: [x1, x2], frame, section })
    }

    /// Node coordinates the element was built from.
    pub fn coords(&self) -> &[[f64; 3]; 2] {
        &self.coords
    }

    /// Length and local axes.
    pub fn local_frame(&self) -> &LocalFrame {
        &self.frame
    }

    /// The section.
    pub fn section(&self) -> &FrameSection {
        &self.section
    }

    /// Local stiffness K_l (module docs).
    pub fn local_stiffness(&self) -> Mat12 {
        let s = &self.section;
        let l = self.frame.length();
        let mut k = Mat12::zeros();
        add_bar(&mut k, 0, 6, s.e * s.area / l, -s.e * s.area / l);
        add_bar(&mut k, 3, 9, s.g * s.j / l, -s.g * s.j / l);
        let b = bending_stiffness_unit(l);
        add_plane(&mut k, PLANE_XY, [1.0; 4], &(b * (s.e * s.iz)));
        add_plane(&mut k, PLANE_XZ, S_XZ, &(b * (s.e * s.iy)));
        k
    }

    /// Global stiffness K = Tᵀ K_l T.
    pub fn global_stiffness(&self) -> Mat12 {
        self.frame.mat12_to_global(&self.local_stiffness())
    }

    /// Line mass ρA + non-structural mass per length (kg/m).
    pub fn line_mass(&self) -> f64 {
        self.section.density * self.section.area + self.section.nonstructural_mass
    }

    /// Local mass matrix of the chosen kind ([`beam_inertia`](super::beam_inertia) docs).
    pub fn local_mass(&self, kind: MassKind) -> Mat12 {
        let s = &self.section;
        beam_inertia::local_mass(self.frame.length(), self.line_mass(), s.density * s.polar_moment(), kind)
    }

    /// Consistent nodal loads f_q of the self weight (structural and non-structural mass) under
    /// acceleration `g`, in local axes. These are also the fixed-end forces subtracted in
    /// [`Self::end_forces`].
    pub fn local_gravity_load(&self, g: [f64; 3]) -> Vec12 {
        beam_inertia::local_gravity_load(&self.frame, self.line_mass(), g)
    }

    /// Member end forces f_l = K_l T u_e − f_q(loads.gravity), local axes, ordered as
    /// [`Element::cell_output_names`] (N, Vy, Vz, T, My, Mz at node 1, then at node 2).
    pub fn end_forces(&self, u_e: &[f64], loads: &AppliedLoads) -> Result<Vec12, ElementError> {
        check_len("u_e", N_DOFS, u_e.len())?;
        check_finite_displacement(u_e)?;
        let u_l = self.frame.vec12_to_local(&Vec12::from_column_slice(u_e));
        Ok(self.local_stiffness() * u_l - self.local_gravity_load(loads.gravity))
    }
}

impl Element for ElasticFrame3d {
    fn kind_name(&self) -> &'static str {
        "elastic_frame_3d"
    }

    fn n_nodes(&self) -> usize {
        2
    }

    /// f_int = K u_e (linear), K_t = K.
    fn evaluate(&mut self, u_e: &[f64], request: EvalRequest, out: &mut ElementOutput) -> Result<(), ElementError> {
        check_len("u_e", N_DOFS, u_e.len())?;
        check_finite_displacement(u_e)?;
        out.prepare(N_DOFS);
        let k = self.global_stiffness();
        let f = k * Vec12::from_column_slice(u_e);
        out.f_int.copy_from(&f);
        if request.wants_tangent() {
            out.k_t.copy_from(&k);
            out.has_tangent = true;
        }
        Ok(())
    }

    fn commit(&mut self) {}

    fn revert(&mut self) {}

    fn mass(&self, kind: MassKind, m: &mut DMatrix<f64>) {
        copy_into(m, &self.frame.mat12_to_global(&self.local_mass(kind)));
    }

    fn gravity_load(&self, g: [f64; 3], f: &mut DVector<f64>) {
        prepare_vector(f, N_DOFS);
        f.copy_from(&self.frame.vec12_to_global(&self.local_gravity_load(g)));
    }

    fn cell_output_names(&self) -> &'static [&'static str] {
        &CELL_OUTPUT_NAMES
    }

    fn cell_output(&self, u_e: &[f64], loads: &AppliedLoads, values: &mut [f64]) -> Result<(), ElementError> {
        check_len("cell output", CELL_OUTPUT_NAMES.len(), values.len())?;
        let f = self.end_forces(u_e, loads)?;
        values[0] = 0.5 * (f[6] - f[0]);
        values[1..].copy_from_slice(f.as_slice());
        Ok(())
    }

    fn n_state(&self) -> usize {
        0
    }

    fn save_state(&self, out: &mut [f64]) -> Result<(), ElementError> {
        check_len("state", 0, out.len())
    }

    fn load_state(&mut self, state: &[f64]) -> Result<(), ElementError> {
        check_len("state", 0, state.len())
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use nalgebra::{Cholesky, DMatrix, DVector, Matrix3, SymmetricEigen, Vector3};

    /// A 0.3 m (along local y) × 0.5 m (along local z) concrete-like section; Iy ≠ Iz on purpose so
    /// a swapped inertia shows. J from Roark's rectangle formula (its value does not matter here).
    fn section() -> FrameSection {
        let (b, h) = (0.3, 0.5);
        FrameSection {
            e: 30e9,
            g: 12.5e9,
            area: b * h,
            iy: b * h * h * h / 12.0,
            iz: h * b * b * b / 12.0,
            j: 2.65e-3,
            density: 2500.0,
            nonstructural_mass: 0.0,
        }
    }

    /// Deterministic pseudo-random numbers in [−1, 1) (64-bit LCG, Knuth's MMIX constants).
    struct Lcg(u64);
    impl Lcg {
        fn next(&mut self) -> f64 {
            self.0 = self.0.wrapping_mul(6364136223846793005).wrapping_add(1442695040888963407);
            ((self.0 >> 11) as f64 / (1u64 << 53) as f64) * 2.0 - 1.0
        }
        fn vec3(&mut self, scale: f64) -> [f64; 3] {
            [self.next() * scale, self.next() * scale, self.next() * scale]
        }
    }

    /// Arbitrarily oriented elements: axis-aligned ones plus seeded random ones.
    fn elements() -> Vec<ElasticFrame3d> {
        let mut out = vec![
            ElasticFrame3d::new([0.0; 3], [3.0, 0.0, 0.0], [0.0, 0.0, 1.0], section()).unwrap(),
            ElasticFrame3d::new([1.0, 2.0, 0.0], [1.0, 2.0, 4.0], [1.0, 0.0, 0.0], section()).unwrap(),
            ElasticFrame3d::new([0.0; 3], [0.0, -2.5, 0.0], [0.3, 0.0, 1.0], section()).unwrap(),
        ];
        let mut rng = Lcg(42);
        while out.len() < 10 {
            let x1 = rng.vec3(10.0);
            let x2 = rng.vec3(10.0);
            if let Ok(e) = ElasticFrame3d::new(x1, x2, rng.vec3(1.0), section()) {
                out.push(e);
            }
        }
        out
    }

    fn dmat(m: &Mat12) -> DMatrix<f64> {
        DMatrix::from_column_slice(12, 12, m.as_slice())
    }

    /// Rigid-body field u(x) = c + θ × x, rotation θ at both nodes: K u = 0 (exact in theory;
    /// tolerance 1e-9 relative to ‖K‖·‖u‖ for round-off).
    #[test]
    fn rigid_body_motion_gives_no_internal_force() {
        let mut rng = Lcg(7);
        let mut out = ElementOutput::new(12);
        for mut el in elements() {
            for _ in 0..5 {
                let c = Vector3::from(rng.vec3(1.0));
                let th = Vector3::from(rng.vec3(0.01));
                let mut u = [0.0; 12];
                for (n, x) in el.coords().iter().enumerate() {
                    let t = c + th.cross(&Vector3::from(*x));
                    u[6 * n..6 * n + 3].copy_from_slice(t.as_slice());
                    u[6 * n + 3..6 * n + 6].copy_from_slice(th.as_slice());
                }
                el.evaluate(&u, EvalRequest::Force, &mut out).unwrap();
                assert!(!out.has_tangent);
                let k_norm = el.global_stiffness().amax();
                let u_norm = u.iter().fold(0.0f64, |a, x| a.max(x.abs()));
                let rel = out.f_int.amax() / (k_norm * u_norm);
                assert!(rel < 1e-9, "rigid motion: |f|/(|K||u|) = {rel:e} for {:?}", el.coords());
            }
        }
    }

    /// K symmetric (to 1e-12 relative, round-off of Tᵀ K_l T), positive semidefinite with exactly 6
    /// zero eigenvalues (3 translations + 3 rotations): |λ| < 1e-10 λmax for 6 of them, and the
    /// other 6 > 1e-6 λmax (the smallest, 3EIz/L³-like, is ~1e-3 λmax for these elements).
    #[test]
    fn stiffness_is_symmetric_psd_with_six_rigid_modes() {
        for el in elements() {
            let k = dmat(&el.global_stiffness());
            let kmax = k.amax();
            assert!((&k - k.transpose()).amax() < 1e-12 * kmax);
            let mut ev: Vec<f64> = SymmetricEigen::new(k).eigenvalues.iter().copied().collect();
            ev.sort_by(|a, b| a.total_cmp(b));
            let lmax = ev[11];
            let zeros = ev.iter().filter(|l| l.abs() < 1e-10 * lmax).count();
            assert_eq!(zeros, 6, "eigenvalues {ev:?}");
            assert!(ev[6] > 1e-6 * lmax, "eigenvalues {ev:?}");
            assert!(ev[0] > -1e-10 * lmax, "negative eigenvalue {ev:?}");
        }
    }

    /// Solve the cantilever fixed at node 1 (free DOF 6..12) under the global tip load `f_tip`
    /// (6 components: force and moment at node 2); returns the tip (translation, rotation) in
    /// local axes.
    fn cantilever_tip(el: &ElasticFrame3d, f_tip_local: [f64; 6]) -> (Vector3<f64>, Vector3<f64>) {
        let fr = el.local_frame();
        let f = fr.to_global(&Vector3::new(f_tip_local[0], f_tip_local[1], f_tip_local[2]));
        let m = fr.to_global(&Vector3::new(f_tip_local[3], f_tip_local[4], f_tip_local[5]));
        let k = dmat(&el.global_stiffness());
        let kff = k.view((6, 6), (6, 6)).into_owned();
        let rhs = DVector::from_column_slice(&[f.x, f.y, f.z, m.x, m.y, m.z]);
        let u = Cholesky::new(kff).expect("K_ff of a cantilever is SPD").solve(&rhs);
        (fr.to_local(&Vector3::new(u[0], u[1], u[2])), fr.to_local(&Vector3::new(u[3], u[4], u[5])))
    }

    fn assert_rel(got: f64, want: f64, tol: f64, what: &str) {
        assert!(((got - want) / want).abs() < tol, "{what}: got {got:e}, want {want:e}");
    }

    /// One-element cantilever, exact for Euler–Bernoulli (cubic shape functions reproduce the exact
    /// solution for end loads): tip P along local y → v = PL³/(3EIz), θz = +PL²/(2EIz); along local
    /// z → w = PL³/(3EIy), θy = −PL²/(2EIy); axial P → PL/EA; torque T → TL/GJ. Source: Gere &
    /// Timoshenko, *Mechanics of Materials*, cantilever table. Tolerance 1e-10 relative; the other
    /// components must vanish to 1e-10 of the main one. Every orientation of `elements()`.
    #[test]
    fn cantilever_tip_displacements() {
        let s = section();
        let (p, t) = (1.0e4, 2.0e3);
        for el in elements() {
            let l = el.local_frame().length();
            let small = |v: &Vector3<f64>, keep: usize, scale: f64| {
                (0..3).filter(|&i| i != keep).all(|i| v[i].abs() < 1e-10 * scale.abs())
            };
            // P along local y: bending in x-y plane, Iz.
            let (u, r) = cantilever_tip(&el, [0.0, p, 0.0, 0.0, 0.0, 0.0]);
            let v = p * l.powi(3) / (3.0 * s.e * s.iz);
            let th = p * l * l / (2.0 * s.e * s.iz);
            assert_rel(u.y, v, 1e-10, "v tip");
            assert_rel(r.z, th, 1e-10, "θz tip");
            assert!(small(&u, 1, v) && small(&r, 2, th), "u {u:?} r {r:?}");
            // P along local z: bending in x-z plane, Iy, θy = −dw/dx.
            let (u, r) = cantilever_tip(&el, [0.0, 0.0, p, 0.0, 0.0, 0.0]);
            let w = p * l.powi(3) / (3.0 * s.e * s.iy);
            let th = -p * l * l / (2.0 * s.e * s.iy);
            assert_rel(u.z, w, 1e-10, "w tip");
            assert_rel(r.y, th, 1e-10, "θy tip");
            assert!(small(&u, 2, w) && small(&r, 1, th), "u {u:?} r {r:?}");
            // Axial.
            let (u, r) = cantilever_tip(&el, [p, 0.0, 0.0, 0.0, 0.0, 0.0]);
            let ua = p * l / (s.e * s.area);
            assert_rel(u.x, ua, 1e-10, "axial");
            assert!(small(&u, 0, ua) && r.amax() < 1e-10 * ua / l);
            // Torque.
            let (u, r) = cantilever_tip(&el, [0.0, 0.0, 0.0, t, 0.0, 0.0]);
            let tx = t * l / (s.g * s.j);
            assert_rel(r.x, tx, 1e-10, "twist");
            assert!(small(&r, 0, tx) && u.amax() < 1e-10 * tx * l);
        }
    }

    /// End forces of the cantilever with tip load P along local y: statics gives Vy_2 = P,
    /// Vy_1 = −P, Mz_1 = −P L, Mz_2 = 0 (module-doc convention), to 1e-9 relative to P·L.
    #[test]
    fn cantilever_end_forces_balance_the_load() {
        let p = 1.0e4;
        for el in elements() {
            let l = el.local_frame().length();
            let (u, r) = cantilever_tip(&el, [0.0, p, 0.0, 0.0, 0.0, 0.0]);
            let fr = el.local_frame();
            let (ug, rg) = (fr.to_global(&u), fr.to_global(&r));
            let mut ue = [0.0; 12];
            ue[6..9].copy_from_slice(ug.as_slice());
            ue[9..12].copy_from_slice(rg.as_slice());
            let mut vals = [0.0; 13];
            el.cell_output(&ue, &AppliedLoads::default(), &mut vals).unwrap();
            let want = [0.0, -p, 0.0, 0.0, 0.0, -p * l, 0.0, p, 0.0, 0.0, 0.0, 0.0];
            assert!(vals[0].abs() < 1e-9 * p, "no axial force under a transverse load");
            for i in 0..12 {
                assert!(
                    (vals[1 + i] - want[i]).abs() < 1e-9 * p * l,
                    "{}: {} vs {}",
                    CELL_OUTPUT_NAMES[1 + i],
                    vals[1 + i],
                    want[i]
                );
            }
        }
    }

    /// Self weight of a horizontal beam along X with vecxz = Z (local = global axes), g = −9.81 Z:
    /// q = −ρAg per length along z. Consistent nodal loads (Przemieniecki; fixed-end actions of a
    /// uniform load): Fz = qL/2 at each node, My = −qL²/12 at node 1 and +qL²/12 at node 2.
    /// Fixed-fixed, one element: u = 0, so the member end forces are the support reactions
    /// −f_q: Vz = ρAgL/2 upward at both ends and the end moments wL²/12 (w = ρAg). 1e-12 relative.
    #[test]
    fn self_weight_fixed_fixed_reactions() {
        let s = section();
        let l = 4.0;
        let el = ElasticFrame3d::new([0.0; 3], [l, 0.0, 0.0], [0.0, 0.0, 1.0], s).unwrap();
        let g = [0.0, 0.0, -9.81];
        let w = s.density * s.area * 9.81;
        let mut f = DVector::zeros(0);
        el.gravity_load(g, &mut f);
        let want =
            [0.0, 0.0, -w * l / 2.0, 0.0, w * l * l / 12.0, 0.0, 0.0, 0.0, -w * l / 2.0, 0.0, -w * l * l / 12.0, 0.0];
        for i in 0..12 {
            assert!((f[i] - want[i]).abs() < 1e-12 * w * l * l, "f[{i}] = {} vs {}", f[i], want[i]);
        }
        let mut vals = [0.0; 13];
        el.cell_output(&[0.0; 12], &AppliedLoads { gravity: g }, &mut vals).unwrap();
        for i in 0..12 {
            assert!((vals[1 + i] + want[i]).abs() < 1e-12 * w * l * l, "{}: {}", CELL_OUTPUT_NAMES[1 + i], vals[1 + i]);
        }
        assert!(vals[3] > 0.0 && vals[9] > 0.0, "supports push up");
    }

    /// Two elements, fixed-fixed, self weight: Euler–Bernoulli elements with consistent loads give
    /// exact nodal displacements, so the midspan deflection is w L⁴/(384 EI) (Gere & Timoshenko,
    /// fixed-fixed beam under uniform load) to 1e-10 relative, with zero midspan rotation; the
    /// end moment from the member forces is wL²/12 (same source).
    #[test]
    fn self_weight_fixed_fixed_midspan_deflection() {
        let s = section();
        let l: f64 = 6.0;
        let g = [0.0, 0.0, -9.81];
        let w = s.density * s.area * 9.81;
        let e1 = ElasticFrame3d::new([0.0; 3], [l / 2.0, 0.0, 0.0], [0.0, 0.0, 1.0], s).unwrap();
        let e2 = ElasticFrame3d::new([l / 2.0, 0.0, 0.0], [l, 0.0, 0.0], [0.0, 0.0, 1.0], s).unwrap();
        // Free DOF: the 6 of the middle node = DOF 6..12 of e1 and 0..6 of e2.
        let (k1, k2) = (dmat(&e1.global_stiffness()), dmat(&e2.global_stiffness()));
        let kff = k1.view((6, 6), (6, 6)) + k2.view((0, 0), (6, 6));
        let (mut f1, mut f2) = (DVector::zeros(0), DVector::zeros(0));
        e1.gravity_load(g, &mut f1);
        e2.gravity_load(g, &mut f2);
        let rhs = f1.rows(6, 6) + f2.rows(0, 6);
        let u = Cholesky::new(kff).unwrap().solve(&rhs);
        let want = -w * l.powi(4) / (384.0 * s.e * s.iy);
        assert_rel(u[2], want, 1e-10, "midspan deflection");
        assert!(u[4].abs() < 1e-10 * want.abs() / l, "midspan rotation {}", u[4]);
        let mut ue = [0.0; 12];
        ue[6..12].copy_from_slice(u.as_slice());
        let mut vals = [0.0; 13];
        e1.cell_output(&ue, &AppliedLoads { gravity: g }, &mut vals).unwrap();
        assert_rel(vals[5].abs(), w * l * l / 12.0, 1e-10, "end moment");
        assert_rel(vals[3], w * l / 2.0, 1e-10, "end shear");
    }

    /// Oblique element: the nodal loads add up to the weight ρ A L g, and their moment about node 1
    /// equals that of the distributed load, (L/2) e_x × (ρ A L g) (statics), to 1e-12 relative.
    #[test]
    fn self_weight_resultant_oblique() {
        let s = section();
        let g = Vector3::new(0.3, -1.2, -9.81);
        for el in elements() {
            let l = el.local_frame().length();
            let mut f = DVector::zeros(12);
            el.gravity_load(g.into(), &mut f);
            let weight = g * (s.density * s.area * l);
            let sum = f.fixed_rows::<3>(0) + f.fixed_rows::<3>(6);
            assert!((sum - weight).amax() < 1e-12 * weight.norm());
            let arm = el.local_frame().axis(0) * l;
            let moment = arm.cross(&f.fixed_rows::<3>(6).into_owned()) + f.fixed_rows::<3>(3) + f.fixed_rows::<3>(9);
            let want = (el.local_frame().axis(0) * (l / 2.0)).cross(&weight);
            assert!((moment - want).amax() < 1e-12 * weight.norm() * l);
        }
    }

    /// Rigid translation r along each global axis: rᵀ M r = ρ A L (total mass); rigid rotation
    /// about the element axis: rᵀ M r = ρ Ip L (polar mass moment); both for consistent and lumped
    /// mass (exact by construction; 1e-12 relative). M symmetric and positive definite (Cholesky).
    #[test]
    fn mass_totals_and_definiteness() {
        let s = section();
        for el in elements() {
            let l = el.local_frame().length();
            for kind in [MassKind::Consistent, MassKind::Lumped] {
                let mut m = DMatrix::zeros(0, 0);
                el.mass(kind, &mut m);
                assert_eq!(m.shape(), (12, 12));
                assert!((&m - m.transpose()).amax() < 1e-12 * m.amax());
                for d in 0..3 {
                    let mut r = DVector::zeros(12);
                    r[d] = 1.0;
                    r[6 + d] = 1.0;
                    let mass = (r.transpose() * &m * &r)[0];
                    assert_rel(mass, s.density * s.area * l, 1e-12, "translational mass");
                }
                let ex = el.local_frame().axis(0);
                let mut r = DVector::zeros(12);
                for n in 0..2 {
                    r.fixed_rows_mut::<3>(6 * n + 3).copy_from(&ex);
                }
                let rot = (r.transpose() * &m * &r)[0];
                assert_rel(rot, s.density * s.polar_moment() * l, 1e-12, "torsional inertia");
                assert!(Cholesky::new(m).is_some(), "{kind:?} mass not positive definite");
            }
        }
    }

    /// Lumped mass in global axes: no coupling between the nodes or between translations and
    /// rotations (exact zeros up to round-off of R).
    #[test]
    fn lumped_mass_is_nodal() {
        for el in elements() {
            let mut m = DMatrix::zeros(12, 12);
            el.mass(MassKind::Lumped, &mut m);
            for i in 0..12 {
                for j in 0..12 {
                    let same_block = i / 3 == j / 3;
                    if !same_block {
                        assert!(m[(i, j)].abs() < 1e-12 * m.amax(), "M[{i},{j}] = {}", m[(i, j)]);
                    }
                }
            }
            let t = m.view((0, 0), (3, 3)).into_owned();
            assert!((t - Matrix3::identity() * m[(0, 0)]).amax() < 1e-12 * m[(0, 0)]);
        }
    }

    /// Cantilever of n elements along an oblique axis; returns the square roots of the smallest
    /// generalized eigenvalues of K φ = ω² M φ (rad/s), ascending.
    fn cantilever_frequencies(n: usize, len: f64, kind: MassKind) -> Vec<f64> {
        let axis = Vector3::new(1.0, 2.0, 2.0) / 3.0; // unit
        let vecxz = [0.0, 0.0, 1.0];
        let nd = 6 * (n + 1);
        let (mut k, mut m) = (DMatrix::zeros(nd, nd), DMatrix::zeros(nd, nd));
        let mut me = DMatrix::zeros(12, 12);
        for e in 0..n {
            let x1 = axis * (len * e as f64 / n as f64);
            let x2 = axis * (len * (e + 1) as f64 / n as f64);
            let el = ElasticFrame3d::new(x1.into(), x2.into(), vecxz, section()).unwrap();
            el.mass(kind, &mut me);
            let ke = dmat(&el.global_stiffness());
            let mut kv = k.view_mut((6 * e, 6 * e), (12, 12));
            kv += &ke;
            let mut mv = m.view_mut((6 * e, 6 * e), (12, 12));
            mv += &me;
        }
        // Node 0 clamped.
        let kf = k.view((6, 6), (nd - 6, nd - 6)).into_owned();
        let mf = m.view((6, 6), (nd - 6, nd - 6)).into_owned();
        // M = C Cᵀ, A = C⁻¹ K C⁻ᵀ (symmetric), eig(A) = ω².
        let c = Cholesky::new(mf).unwrap().unpack();
        let x = c.solve_lower_triangular(&kf).unwrap(); // C⁻¹ K
        let a = c.solve_lower_triangular(&x.transpose()).unwrap(); // C⁻¹ (C⁻¹ K)ᵀ = C⁻¹ K C⁻ᵀ
        let a = (&a + a.transpose()) * 0.5;
        let mut w2: Vec<f64> = SymmetricEigen::new(a).eigenvalues.iter().copied().collect();
        w2.sort_by(|a, b| a.total_cmp(b));
        w2.iter().map(|x| x.max(0.0).sqrt()).collect()
    }

    /// First bending frequency of a cantilever: ω₁ = (β₁L)² √(EI/(ρ A L⁴)), β₁L = 1.875104
    /// (Euler–Bernoulli cantilever; Clough & Penzien, *Dynamics of Structures*, §18). With Iz < Iy
    /// the two lowest modes are the first bending modes about z then about y (torsion and axial
    /// modes are far higher for this section). 16 elements: lumped mass within 0.5% (observed
    /// −0.25%, O(h²) convergence); consistent mass within 1e-5 (observed 2e-7, O(h⁴)).
    #[test]
    fn cantilever_first_bending_frequencies() {
        let s = section();
        let len: f64 = 8.0;
        let beta2 = 1.875104f64 * 1.875104;
        let w_z = beta2 * (s.e * s.iz / (s.density * s.area * len.powi(4))).sqrt();
        let w_y = beta2 * (s.e * s.iy / (s.density * s.area * len.powi(4))).sqrt();
        for (kind, tol) in [(MassKind::Consistent, 1e-5), (MassKind::Lumped, 5e-3)] {
            let w = cantilever_frequencies(16, len, kind);
            let (f1, f2) = (w[0] / (2.0 * std::f64::consts::PI), w[1] / (2.0 * std::f64::consts::PI));
            assert_rel(f1, w_z / (2.0 * std::f64::consts::PI), tol, &format!("{kind:?} f1"));
            assert_rel(f2, w_y / (2.0 * std::f64::consts::PI), tol, &format!("{kind:?} f2"));
        }
    }

    #[test]
    fn bad_input_is_an_error_not_a_panic() {
        let mut el = elements().remove(3);
        let mut out = ElementOutput::new(0);
        let e = el.evaluate(&[0.0; 11], EvalRequest::Force, &mut out).unwrap_err();
        assert_eq!(e, ElementError::WrongLength { what: "u_e", expected: 12, got: 11 });
        let mut u = [0.0; 12];
        u[7] = f64::NAN;
        let e = el.evaluate(&u, EvalRequest::Force, &mut out).unwrap_err();
        assert!(matches!(e, ElementError::NonFiniteDisplacement { index: 7, .. }));
        let e = el.cell_output(&[0.0; 12], &AppliedLoads::default(), &mut [0.0; 6]).unwrap_err();
        assert!(matches!(e, ElementError::WrongLength { what: "cell output", .. }));
        assert!(el.load_state(&[1.0]).is_err());
        let bad = FrameSection { j: 0.0, ..section() };
        let e = ElasticFrame3d::new([0.0; 3], [1.0, 0.0, 0.0], [0.0, 0.0, 1.0], bad).unwrap_err();
        assert_eq!(e, ElementError::InvalidSection { quantity: "j", value: 0.0, expected: "> 0" });
    }

    /// evaluate with a tangent: f_int = K u (linear element), K_t = K, buffers resized once.
    #[test]
    fn evaluate_fills_force_and_tangent() {
        let mut el = elements().remove(5);
        let mut out = ElementOutput::new(24);
        let u: Vec<f64> = (0..12).map(|i| 1e-3 * (i as f64).cos()).collect();
        el.evaluate(&u, EvalRequest::ForceAndTangent, &mut out).unwrap();
        assert!(out.has_tangent);
        assert_eq!(out.n_dofs(), 12);
        let k = dmat(&el.global_stiffness());
        assert!((&out.k_t - &k).amax() == 0.0);
        assert!((&out.f_int - &k * DVector::from_vec(u)).amax() < 1e-12 * out.f_int.amax());
        assert_eq!(el.n_dofs(), 12);
        assert_eq!(el.cell_output_names().len(), 13);
    }

    /// A bar stretched by δ along its axis carries N = EA δ / L in tension: `axial_force` is
    /// +EAδ/L (engineering sign), N_1 = −EAδ/L and N_2 = +EAδ/L (OpenSees localForce), 1e-12.
    #[test]
    fn axial_force_is_positive_in_tension() {
        let s = section();
        let el = ElasticFrame3d::new([0.0; 3], [2.0, 0.0, 0.0], [0.0, 0.0, 1.0], s).unwrap();
        let delta = 1e-3;
        let mut ue = [0.0; 12];
        ue[6] = delta;
        let mut vals = [0.0; 13];
        el.cell_output(&ue, &AppliedLoads::default(), &mut vals).unwrap();
        let n = s.e * s.area * delta / 2.0;
        assert!((vals[0] - n).abs() < 1e-12 * n, "axial_force {}", vals[0]);
        assert!((vals[1] + n).abs() < 1e-12 * n && (vals[7] - n).abs() < 1e-12 * n, "{vals:?}");
    }
}
