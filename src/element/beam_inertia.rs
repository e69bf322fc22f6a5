//! Mass matrices and self-weight loads of 2-node, 12-DOF beams in local axes, shared by the elastic
//! frame ([`ElasticFrame3d`](super::ElasticFrame3d)) and the fiber beam
//! ([`FiberBeam3d`](super::FiberBeam3d)). Both use the same cubic (Hermite) transverse and linear
//! axial/torsional shape functions, so they share these matrices.
//!
//! # Line densities
//! `m = ρ A + m_ns` (kg/m: structural plus non-structural mass per length, which adds to the
//! translational mass and the self weight but carries no stiffness) and `i = ρ Ip` (kg m: the
//! mass moment of inertia per length about the member axis, Ip = Iy + Iz the polar moment of
//! area; the non-structural mass is taken to sit on the axis).
//!
//! # Consistent mass (Przemieniecki, *Theory of Matrix Structural Analysis*, §11)
//! axial m L/6 [2 1; 1 2]; torsion i L/6 [2 1; 1 2]; bending m L/420 ·
//! ```text
//!        [ 156    22L    54   −13L ]
//!        [ 22L    4L²   13L   −3L² ]
//!        [  54    13L   156   −22L ]
//!        [ −13L  −3L²  −22L    4L² ]
//! ```
//! in the x–y plane (v1 θz1 v2 θz2) and S-signed in the x–z plane (w1 θy1 w2 θy2,
//! S = diag(1, −1, 1, −1), since θy = −dw/dx). The rotary inertia of the section in bending
//! (terms in ρI/L) is neglected, consistent with Euler–Bernoulli kinematics.
//!
//! # Lumped mass
//! m L/2 on each translation; i L/2 on each torsional rotation; on each bending rotation
//! m (L/2)³/3 = m L³/24, the moment of inertia of the half-element (a rod of length L/2) about its
//! node: it keeps M positive definite and barely changes the low frequencies.
//!
//! # Self weight
//! q = m g per length (global), q_l = R q; consistent (= fixed-end) nodal loads f_q = ∫ Nᵀ q_l:
//! ```text
//!   node 1: ( qx L/2, qy L/2, qz L/2, 0, −qz L²/12, +qy L²/12 )
//!   node 2: ( qx L/2, qy L/2, qz L/2, 0, +qz L²/12, −qy L²/12 )
//! ```

use nalgebra::{Matrix4, Vector3};

use super::local_frame::{LocalFrame, Mat12, Vec12};
use super::MassKind;

/// Local DOF indices of the x–y bending plane: v1, θz1, v2, θz2.
pub(crate) const PLANE_XY: [usize; 4] = [1, 5, 7, 11];
/// Local DOF indices of the x–z bending plane: w1, θy1, w2, θy2.
pub(crate) const PLANE_XZ: [usize; 4] = [2, 4, 8, 10];
/// Sign flip S = diag(1, −1, 1, −1) that maps the x–y bending matrices to the x–z plane.
pub(crate) const S_XZ: [f64; 4] = [1.0, -1.0, 1.0, -1.0];

/// Add the 2×2 block `[diag off; off diag]` on DOF `i`, `j`.
pub(crate) fn add_bar(m: &mut Mat12, i: usize, j: usize, diag: f64, off: f64) {
    m[(i, i)] += diag;
    m[(j, j)] += diag;
    m[(i, j)] += off;
    m[(j, i)] += off;
}

/// Scatter the 4×4 bending block `b` into `m` on `dofs`, signed by `s` (m[dᵢ,dⱼ] += sᵢ sⱼ bᵢⱼ).
pub(crate) fn add_plane(m: &mut Mat12, dofs: [usize; 4], s: [f64; 4], b: &Matrix4<f64>) {
    for (a, &da) in dofs.iter().enumerate() {
        for (c, &dc) in dofs.iter().enumerate() {
            m[(da, dc)] += s[a] * s[c] * b[(a, c)];
        }
    }
}

/// Consistent bending mass of the x–y plane (v1 θz1 v2 θz2) for a unit line mass.
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

/// Local mass matrix of a beam of length `l`, line mass `m_line` (kg/m) and rotary inertia per
/// length `i_line` (kg m), of the chosen kind (module docs).
pub(crate) fn local_mass(l: f64, m_line: f64, i_line: f64, kind: MassKind) -> Mat12 {
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

/// Consistent nodal loads (local axes) of the self weight of line mass `m_line` under the
/// acceleration `g` (global), module docs.
pub(crate) fn local_gravity_load(frame: &LocalFrame, m_line: f64, g: [f64; 3]) -> Vec12 {
    let l = frame.length();
    let q = frame.to_local(&(Vector3::from(g) * m_line));
    let (f, m) = (l / 2.0, l * l / 12.0);
    Vec12::from_column_slice(&[
        q.x * f,
        q.y * f,
        q.z * f,
        0.0,
        -q.z * m,
        q.y * m, //
        q.x * f,
        q.y * f,
        q.z * f,
        0.0,
        q.z * m,
        -q.y * m,
    ])
}
