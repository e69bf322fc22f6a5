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
//! # Distributed load (self weight)
//! q = ρ A g per unit length (global), q_l = R q. Consistent (= fixed-end) nodal loads f_q = ∫ Nᵀ q_l:
//! ```text
//!   node 1: ( qx L/2, qy L/2, qz L/2, 0, −qz L²/12, +qy L²/12 )
//!   node 2: ( qx L/2, qy L/2, qz L/2, 0, +qz L²/12, −qy L²/12 )
//! ```
//! Global: f = Tᵀ f_q.
//!
//! # Member end forces
//! f_l = K_l T u_e − f_q: the forces and moments the nodes exert on the element, in local axes, at
//! each end (OpenSees `localForce` convention: components along the local axes, **not** a section
//! sign convention). So a member in tension has N_1 < 0 and N_2 > 0; a cantilever carrying a tip
//! load P along +y at node 2 has Vy_2 = P, Vy_1 = −P, Mz_1 = −P L.
//!
//! # Mass
//! Consistent (Przemieniecki §11): axial ρAL/6 [2 1; 1 2]; torsion ρIpL/6 [2 1; 1 2] with the polar
//! moment Ip = Iy + Iz (the mass moment of inertia per length is ρ∫r²dA = ρ Ip; J is a stiffness
//! constant and equals Ip only for circles); bending ρAL/420 ·
//! ```text
//!        [ 156    22L    54   −13L ]
//!        [ 22L    4L²   13L   −3L² ]
//!        [  54    13L   156   −22L ]
//!        [ −13L  −3L²  −22L    4L² ]
//! ```
//! in the x–y plane and S·S-signed in the x–z plane. The rotary inertia of the cross-section in
//! bending (terms in ρI/L) is neglected, consistent with Euler–Bernoulli kinematics.
//!
//! Lumped: ρAL/2 on each translation; ρ Ip L/2 on each torsional rotation; on each bending rotation
//! ρ A (L/2)³ / 3 = ρAL³/24, the moment of inertia of the half-element (a rod of length L/2) about
//! its node. The bending values keep M positive definite and barely change the low frequencies.
//! Rotated to global axes the lumped matrix stays block diagonal per node (translations diagonal,
//! rotations a 3×3 block).

use nalgebra::{DMatrix, DVector, Matrix4, Vector3};

use super::error::{check_finite_displacement, check_len, ElementError};
use super::frame_section::FrameSection;
use super::local_frame::{LocalFrame, Mat12, Vec12};
use super::output::{prepare_matrix, prepare_vector, ElementOutput, EvalRequest};
use super::{AppliedLoads, Element, MassKind};

/// Number of DOF of the element.
const N_DOFS: usize = 12;

/// Local DOF indices of the x–y bending plane: v1, θz1, v2, θz2.
const PLANE_XY: [usize; 4] = [1, 5, 7, 11];
/// Local DOF indices of the x–z bending plane: w1, θy1, w2, θy2.
const PLANE_XZ: [usize; 4] = [2, 4, 8, 10];
/// Sign flip S = diag(1, −1, 1, −1) that maps the x–y bending matrices to the x–z plane.
const S_XZ: [f64; 4] = [1.0, -1.0, 1.0, -1.0];

/// Names of the cell quantities: member end forces in local axes at node 1 then node 2.
const CELL_OUTPUT_NAMES: [&str; 12] =
    ["N_1", "Vy_1", "Vz_1", "T_1", "My_1", "Mz_1", "N_2", "Vy_2", "Vz_2", "T_2", "My_2", "Mz_2"];

/// A 2-node, 12-DOF linear elastic 3D frame element (Euler–Bernoulli). See the module docs for the
/// matrices and sign conventions. Stateless: `commit`/`revert` do nothing and `n_state() == 0`.
#[derive(Clone, Debug, PartialEq)]
pub struct ElasticFrame3d {
    coords: [[f64; 3]; 2],
    frame: LocalFrame,
    section: FrameSection,
}

/// Add the 2×2 block `c [1 −1; −1 1]` on DOF `i`, `j`.
fn add_bar(m: &mut Mat12, i: usize, j: usize, diag: f64, off: f64) {
    m[(i, i)] += diag;
    m[(j, j)] += diag;
    m[(i, j)] += off;
    m[(j, i)] += off;
}

/// Scatter the 4×4 bending block `b` into `m` on `dofs`, signed by `s` (m[dᵢ,dⱼ] += sᵢ sⱼ bᵢⱼ).
fn add_plane(m: &mut Mat12, dofs: [usize; 4], s: [f64; 4], b: &Matrix4<f64>) {
    for (a, &da) in dofs.iter().enumerate() {
        for (c, &dc) in dofs.iter().enumerate() {
            m[(da, dc)] += s[a] * s[c] * b[(a, c)];
        }
    }
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

/// Consistent bending mass of the x–y plane (v1 θz1 v2 θz2) for ρA = 1.
fn bending_mass_unit(l: f64) -> Matrix4<f64> {
    let l2 = l * l;
    #[rustfmt::skip]
    let b = Matrix4::new(
        156.0,     22.0 * l,   54.0,     -13.0 * l,
        22.0 * l,  4.0 * l2,   13.0 * l, -3.0 * l2,
        54.0,      13.0 * l,   156.0,    -22.0 * l,
        -13.0 * l, -3.0 * l2, -22.0 * l,  4.0 * l2,
    );
    b * (l / 420.0)
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

    /// Local mass matrix of the chosen kind (module docs).
    pub fn local_mass(&self, kind: MassKind) -> Mat12 {
        let s = &self.section;
        let l = self.frame.length();
        let m_line = s.density * s.area; // ρA, mass per length
        let i_line = s.density * s.polar_moment(); // ρ Ip, rotary inertia per length
        let mut m = Mat12::zeros();
        match kind {
            MassKind::Consistent => {
                add_bar(&mut m, 0, 6, m_line * l / 3.0, m_line * l / 6.0);
                add_bar(&mut m, 3, 9, i_line * l / 3.0, i_line * l / 6.0);
                let b = bending_mass_unit(l) * m_line;
                add_plane(&mut m, PLANE_XY, [1.0; 4], &b);
                add_plane(&mut m, PLANE_XZ, S_XZ, &b);
            }
            MassKind::Lumped => {
                let half = m_line * l / 2.0;
                let rot_bending = m_line * l * l * l / 24.0;
                for n in 0..2 {
                    let o = 6 * n;
                    m[(o, o)] = half;
                    m[(o + 1, o + 1)] = half;
                    m[(o + 2, o + 2)] = half;
                    m[(o + 3, o + 3)] = i_line * l / 2.0;
                    m[(o + 4, o + 4)] = rot_bending;
                    m[(o + 5, o + 5)] = rot_bending;
                }
            }
        }
        m
    }

    /// Consistent nodal loads f_q of the self weight under acceleration `g`, in local axes
    /// (module docs). These are also the fixed-end forces subtracted in [`Self::end_forces`].
    pub fn local_gravity_load(&self, g: [f64; 3]) -> Vec12 {
        let s = &self.section;
        let l = self.frame.length();
        let q = self.frame.to_local(&(Vector3::from(g) * (s.density * s.area)));
        let (f, m) = (l / 2.0, l * l / 12.0);
        Vec12::from_column_slice(&[
            q.x * f, q.y * f, q.z * f, 0.0, -q.z * m, q.y * m, //
            q.x * f, q.y * f, q.z * f, 0.0, q.z * m, -q.y * m,
        ])
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
        values.copy_from_slice(f.as_slice());
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
