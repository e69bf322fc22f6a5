//! The cohesive beam: a 2D Euler–Bernoulli frame element joining two points (the seeds) attached
//! rigidly to particles i and j (paper §2.1, "Beam law").
//!
//! # Geometry
//! End points `p_i = c_i + r_i`, `p_j = c_j + r_j` (`c` the particle reference points), length
//! `ℓ = |p_j − p_i|`, axis `n = (p_j − p_i)/ℓ` (i → j), `t = e_z × n`. Section `A`, inertia `I`
//! (computed by the sample generator: `A = L_f t_z`, `I = α t_z L_f³/12`), lattice modulus `Ē`.
//!
//! # Law in local axes (the standard element, e.g. Przemieniecki §5.6, for the x–y plane)
//! Local end DOFs `d = (a_i, v_i, θ_i, a_j, v_j, θ_j)` with `a = u_end·n`, `v = u_end·t`, and `θ`
//! the particle rotation (about e_z). The forces the ends exert on the element, `f_l = K_l d`:
//!
//! ```text
//!          [  EA/ℓ     0        0      −EA/ℓ     0        0     ]
//!          [   0    12EI/ℓ³   6EI/ℓ²     0   −12EI/ℓ³   6EI/ℓ²  ]
//!   K_l =  [   0     6EI/ℓ²   4EI/ℓ      0    −6EI/ℓ²   2EI/ℓ   ]
//!          [ −EA/ℓ     0        0       EA/ℓ     0        0     ]
//!          [   0   −12EI/ℓ³  −6EI/ℓ²     0    12EI/ℓ³  −6EI/ℓ²  ]
//!          [   0     6EI/ℓ²   2EI/ℓ      0    −6EI/ℓ²   4EI/ℓ   ]
//! ```
//!
//! Written with `δn = (u_j − u_i)·n = a_j − a_i`, `δt = (u_i − u_j)·t = v_i − v_j` this is exactly
//! the paper's law (§2.1, corrected), signs included:
//!
//! ```text
//!   F_N = Ē A/ℓ δn                                   f_l = (−F_N, F_T, M_i, F_N, −F_T, M_j)
//!   F_T = 12ĒI/ℓ³ δt + 6ĒI/ℓ² (θ_i + θ_j)
//!   M_i =  6ĒI/ℓ² δt + ĒI/ℓ (4θ_i + 2θ_j)
//!   M_j =  6ĒI/ℓ² δt + ĒI/ℓ (2θ_i + 4θ_j)
//! ```
//!
//! `F_N` is the axial force (tension +), `F_T` the shear force acting on end i along `t`, `M_i`,
//! `M_j` the end moments. Rigid motion: a translation gives δn = δt = θ = 0; a rotation θ about any
//! point gives δn = 0, δt = −θℓ, so `F_T = −12ĒIθ/ℓ² + 12ĒIθ/ℓ² = 0`, `M = −6ĒIθ/ℓ + 6ĒIθ/ℓ = 0`.
//!
//! # Particle DOFs
//! The end point moves by `u_c + θ e_z × r` ([`super::kinematics`]), so
//! `a = n·u_c + θ (r × n)`, `v = t·u_c + θ (r·n)` and `d = T q` with, per end,
//! `T_e = [[n_x, n_y, r×n], [t_x, t_y, r·n], [0, 0, 1]]`. Particle stiffness `K = Tᵀ K_l T` (6×6,
//! order `(u_x,i, u_y,i, θ_i, u_x,j, u_y,j, θ_j)`), particle forces `f = Tᵀ f_l`:
//!
//! ```text
//!   f_i = ( −F_N n + F_T t ,  M_i + r_i × (−F_N n + F_T t) )
//!   f_j = (  F_N n − F_T t ,  M_j + r_j × ( F_N n − F_T t) )
//! ```
//!
//! **Sign convention of the returned forces**: like the frame elements of the structural model,
//! they are the *internal* (resisting) forces, i.e. what the particle exerts on the beam; the
//! beam pushes on the particle with `−f`. Equilibrium reads `Σ f_internal = f_external` and the
//! stiffness is `K = ∂f/∂q` (symmetric, positive semidefinite, null space = the rigid motions).

use nalgebra::{SMatrix, SVector};

use super::error::{finite, positive, MechanicsError};
use super::kinematics::{cross, dot, generalized_force, perp, point_displacement};
use super::MechParams;

/// The geometry of one beam, in the reference configuration.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct BeamGeom {
    /// Length `ℓ` (m), distance between the end points.
    pub ell: f64,
    /// Unit axis `n`, end i → end j.
    pub n: [f64; 2],
    /// Offset of end i from particle i's reference point (m).
    pub r_i: [f64; 2],
    /// Offset of end j from particle j's reference point (m).
    pub r_j: [f64; 2],
    /// Cross-section `A = L_f t_z` (m²).
    pub area: f64,
    /// Inertia `I = α t_z L_f³ / 12` (m⁴).
    pub inertia: f64,
}

/// The end actions of a beam (paper §2.1 notation) and the deformations they come from.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct BeamActions {
    /// `δn = (u_j − u_i)·n` at the end points (m), elongation.
    pub delta_n: f64,
    /// `δt = (u_i − u_j)·t` at the end points (m).
    pub delta_t: f64,
    /// Axial force `F_N` (N), tension positive.
    pub f_n: f64,
    /// Shear force `F_T` (N), acting on end i along `t`.
    pub f_t: f64,
    /// End moment at i (N·m).
    pub m_i: f64,
    /// End moment at j (N·m).
    pub m_j: f64,
}

impl BeamGeom {
    /// The geometry from the end points (seeds) and the particle reference points.
    /// Errors: non-finite points, coincident ends, non-positive `area` or `inertia`.
    pub fn from_points(
        seed_i: [f64; 2],
        seed_j: [f64; 2],
        ref_i: [f64; 2],
        ref_j: [f64; 2],
        area: f64,
        inertia: f64,
    ) -> Result<BeamGeom, MechanicsError> {
        finite("seed_i", seed_i)?;
        finite("seed_j", seed_j)?;
        finite("ref_i", ref_i)?;
        finite("ref_j", ref_j)?;
        let d = [seed_j[0] - seed_i[0], seed_j[1] - seed_i[1]];
        let ell = d[0].hypot(d[1]);
        let scale = seed_i[0].abs().max(seed_i[1].abs()).max(seed_j[0].abs()).max(seed_j[1].abs());
        if ell.is_nan() || ell <= 1e-12 * scale.max(f64::MIN_POSITIVE) {
            return Err(MechanicsError::ZeroLength { seed_i, seed_j });
        }
        let g = BeamGeom {
            ell,
            n: [d[0] / ell, d[1] / ell],
            r_i: [seed_i[0] - ref_i[0], seed_i[1] - ref_i[1]],
            r_j: [seed_j[0] - ref_j[0], seed_j[1] - ref_j[1]],
            area,
            inertia,
        };
        g.validate()?;
        Ok(g)
    }

    /// Checks a geometry given field by field: `ell`, `area`, `inertia` finite and > 0, `n` a unit
    /// vector (to 1e-9), offsets finite.
    pub fn validate(&self) -> Result<(), MechanicsError> {
        positive("ell", self.ell)?;
        positive("area", self.area)?;
        positive("inertia", self.inertia)?;
        finite("n", self.n)?;
        finite("r_i", self.r_i)?;
        finite("r_j", self.r_j)?;
        let norm = self.n[0].hypot(self.n[1]);
        if (norm - 1.0).abs() > 1e-9 {
            return Err(MechanicsError::NotUnit { n: self.n, norm });
        }
        Ok(())
    }

    /// The tangent `t = e_z × n`.
    pub fn t(&self) -> [f64; 2] {
        perp(self.n)
    }

    /// `δn = (u_j − u_i)·n` at the end points, for particle DOFs `q_i`, `q_j`.
    pub fn delta_n(&self, q_i: [f64; 3], q_j: [f64; 3]) -> f64 {
        let (ui, uj) = (point_displacement(q_i, self.r_i), point_displacement(q_j, self.r_j));
        dot([uj[0] - ui[0], uj[1] - ui[1]], self.n)
    }

    /// `δt = (u_i − u_j)·t` at the end points, for particle DOFs `q_i`, `q_j`.
    pub fn delta_t(&self, q_i: [f64; 3], q_j: [f64; 3]) -> f64 {
        let (ui, uj) = (point_displacement(q_i, self.r_i), point_displacement(q_j, self.r_j));
        dot([ui[0] - uj[0], ui[1] - uj[1]], self.t())
    }
}

/// The standard 6×6 local stiffness `K_l` of the 2D frame element (see the module docs) for
/// `EA`, `EI` and length `ℓ`, DOFs `(a_i, v_i, θ_i, a_j, v_j, θ_j)`.
pub fn local_stiffness(ell: f64, ea: f64, ei: f64) -> SMatrix<f64, 6, 6> {
    let (a, b, c, d, e) = (ea / ell, 12.0 * ei / ell.powi(3), 6.0 * ei / ell.powi(2), 4.0 * ei / ell, 2.0 * ei / ell);
    SMatrix::<f64, 6, 6>::from_row_slice(&[
        a, 0.0, 0.0, -a, 0.0, 0.0, //
        0.0, b, c, 0.0, -b, c, //
        0.0, c, d, 0.0, -c, e, //
        -a, 0.0, 0.0, a, 0.0, 0.0, //
        0.0, -b, -c, 0.0, b, -c, //
        0.0, c, e, 0.0, -c, d,
    ])
}

/// The map `T` from particle DOFs `(u_x,i, u_y,i, θ_i, u_x,j, u_y,j, θ_j)` to local end DOFs
/// `(a_i, v_i, θ_i, a_j, v_j, θ_j)`.
pub fn transformation(geom: &BeamGeom) -> SMatrix<f64, 6, 6> {
    let (n, t) = (geom.n, geom.t());
    let mut m = SMatrix::<f64, 6, 6>::zeros();
    for (k, r) in [(0, geom.r_i), (3, geom.r_j)] {
        m[(k, k)] = n[0];
        m[(k, k + 1)] = n[1];
        m[(k, k + 2)] = cross(r, n);
        m[(k + 1, k)] = t[0];
        m[(k + 1, k + 1)] = t[1];
        m[(k + 1, k + 2)] = dot(r, n);
        m[(k + 2, k + 2)] = 1.0;
    }
    m
}

/// The end actions `F_N, F_T, M_i, M_j` (paper §2.1) for particle DOFs `q_i`, `q_j`.
pub fn beam_actions(geom: &BeamGeom, params: &MechParams, q_i: [f64; 3], q_j: [f64; 3]) -> BeamActions {
    let (ea, ei, l) = (params.e_bar * geom.area, params.e_bar * geom.inertia, geom.ell);
    let delta_n = geom.delta_n(q_i, q_j);
    let delta_t = geom.delta_t(q_i, q_j);
    let (th_i, th_j) = (q_i[2], q_j[2]);
    BeamActions {
        delta_n,
        delta_t,
        f_n: ea / l * delta_n,
        f_t: 12.0 * ei / l.powi(3) * delta_t + 6.0 * ei / l.powi(2) * (th_i + th_j),
        m_i: 6.0 * ei / l.powi(2) * delta_t + ei / l * (4.0 * th_i + 2.0 * th_j),
        m_j: 6.0 * ei / l.powi(2) * delta_t + ei / l * (2.0 * th_i + 4.0 * th_j),
    }
}

/// The internal generalized forces `(f_i, f_j)` = `(F_x, F_y, M_z)` about each particle's reference
/// point (what the particles exert on the beam; the beam acts on the particles with minus these).
pub fn beam_forces(geom: &BeamGeom, params: &MechParams, q_i: [f64; 3], q_j: [f64; 3]) -> ([f64; 3], [f64; 3]) {
    let a = beam_actions(geom, params, q_i, q_j);
    let (n, t) = (geom.n, geom.t());
    let fi = [-a.f_n * n[0] + a.f_t * t[0], -a.f_n * n[1] + a.f_t * t[1]];
    let mut gi = generalized_force(fi, geom.r_i);
    let mut gj = generalized_force([-fi[0], -fi[1]], geom.r_j);
    gi[2] += a.m_i;
    gj[2] += a.m_j;
    (gi, gj)
}

/// The particle stiffness `K = Tᵀ K_l T` (6×6, symmetric), `= ∂(beam_forces)/∂(q_i, q_j)`.
pub fn beam_stiffness(geom: &BeamGeom, params: &MechParams) -> SMatrix<f64, 6, 6> {
    let kl = local_stiffness(geom.ell, params.e_bar * geom.area, params.e_bar * geom.inertia);
    let t = transformation(geom);
    let k = t.transpose() * kl * t;
    // Symmetric by construction; remove the round-off asymmetry.
    (k + k.transpose()) * 0.5
}

/// `(q_i, q_j)` stacked as the 6-vector the stiffness acts on.
pub fn stack(q_i: [f64; 3], q_j: [f64; 3]) -> SVector<f64, 6> {
    SVector::<f64, 6>::from_column_slice(&[q_i[0], q_i[1], q_i[2], q_j[0], q_j[1], q_j[2]])
}

#[cfg(test)]
mod tests {
    use super::super::kinematics::rigid_motion_dofs;
    use super::*;

    fn params() -> MechParams {
        MechParams { e_bar: 2.5e9, ..MechParams::default() }
    }

    /// An oblique beam with off-axis offsets on both sides (nothing aligned with the axes).
    fn oblique() -> (BeamGeom, [f64; 2], [f64; 2]) {
        let (ci, cj) = ([0.10, 0.20], [0.31, 0.27]);
        let (si, sj) = ([0.17, 0.19], [0.26, 0.31]);
        let g = BeamGeom::from_points(si, sj, ci, cj, 0.12, 0.8 * 0.12f64.powi(3) / 12.0).unwrap();
        (g, ci, cj)
    }

    fn norm3(a: [f64; 3]) -> f64 {
        a.iter().map(|x| x * x).sum::<f64>().sqrt()
    }

    #[test]
    fn stiffness_along_x_is_the_textbook_frame_element() {
        // Przemieniecki §5.6 entries for a beam along x with no offsets: EA/ℓ, 12EI/ℓ³, 6EI/ℓ²,
        // 4EI/ℓ, 2EI/ℓ. Values: Ē = 2e9, A = 0.1, I = 2e-4, ℓ = 0.5. Tolerance 1e-12 relative.
        let p = MechParams { e_bar: 2e9, ..MechParams::default() };
        let g = BeamGeom { ell: 0.5, n: [1.0, 0.0], r_i: [0.0; 2], r_j: [0.0; 2], area: 0.1, inertia: 2e-4 };
        let k = beam_stiffness(&g, &p);
        let (ea, ei, l) = (2e9 * 0.1, 2e9 * 2e-4, 0.5);
        let want = local_stiffness(l, ea, ei);
        let (a, b, c, d, e) = (ea / l, 12.0 * ei / l.powi(3), 6.0 * ei / l.powi(2), 4.0 * ei / l, 2.0 * ei / l);
        let checks = [
            ((0, 0), a),
            ((0, 3), -a),
            ((1, 1), b),
            ((1, 4), -b),
            ((1, 2), c),
            ((1, 5), c),
            ((2, 4), -c),
            ((4, 5), -c),
            ((2, 2), d),
            ((5, 5), d),
            ((2, 5), e),
            ((0, 1), 0.0),
            ((0, 2), 0.0),
        ];
        for ((r, cc), v) in checks {
            assert!((k[(r, cc)] - v).abs() <= 1e-12 * a, "K[{r},{cc}] = {} vs {v}", k[(r, cc)]);
            assert!((k[(cc, r)] - v).abs() <= 1e-12 * a);
        }
        assert!((k - want).abs().max() <= 1e-12 * a);
    }

    #[test]
    fn rigid_translation_and_rotation_give_zero_forces() {
        // paper §2.1 unit test. Scale: forces of a unit-size deformation of the same amplitude,
        // ‖K‖ ‖q‖; zero means below 1e-12 of it.
        let p = params();
        let (g, ci, cj) = oblique();
        let k = beam_stiffness(&g, &p);
        for (about, u, th) in [
            ([0.0, 0.0], [1e-3, -2e-3], 0.0),  // translation
            ([0.0, 0.0], [0.0, 0.0], 1e-3),    // rotation about the origin
            ([3.0, -1.0], [0.0, 0.0], -2e-3),  // rotation about a far point
            ([0.2, 0.25], [4e-4, 1e-4], 5e-4), // both
        ] {
            let qi = rigid_motion_dofs(about, u, th, ci);
            let qj = rigid_motion_dofs(about, u, th, cj);
            let scale = k.abs().max() * norm3(qi).max(norm3(qj));
            let (fi, fj) = beam_forces(&g, &p, qi, qj);
            assert!(norm3(fi) <= 1e-12 * scale && norm3(fj) <= 1e-12 * scale, "{fi:?} {fj:?} vs {scale}");
            let a = beam_actions(&g, &p, qi, qj);
            assert!(a.f_n.abs().max(a.f_t.abs()).max(a.m_i.abs()).max(a.m_j.abs()) <= 1e-12 * scale);
            let kq = k * stack(qi, qj);
            assert!(kq.abs().max() <= 1e-12 * scale);
        }
    }

    #[test]
    fn stiffness_has_rank_three() {
        // Null space = the 3 rigid motions, so K has exactly 3 eigenvalues above round-off
        // (1e-10 of the largest): breaking a beam is a rank-3 update of the global matrix.
        let (g, _, _) = oblique();
        let k = beam_stiffness(&g, &params());
        let ev = k.symmetric_eigen().eigenvalues;
        let top = ev.abs().max();
        assert_eq!(ev.iter().filter(|&&e| e > 1e-10 * top).count(), 3, "{ev}");
        assert!(ev.iter().all(|&e| e > -1e-10 * top));
    }

    #[test]
    fn stiffness_is_symmetric_and_the_derivative_of_the_forces() {
        // The law is linear: central differences are exact up to round-off; tolerance 1e-7 of ‖K‖.
        let p = params();
        let (g, _, _) = oblique();
        let k = beam_stiffness(&g, &p);
        assert!((k - k.transpose()).abs().max() == 0.0);
        let q0 = [1e-4, -3e-5, 2e-4, -5e-5, 7e-5, -1e-4];
        let h = 1e-6;
        for c in 0..6 {
            let (mut qp, mut qm) = (q0, q0);
            qp[c] += h;
            qm[c] -= h;
            let f = |q: [f64; 6]| {
                let (a, b) = beam_forces(&g, &p, [q[0], q[1], q[2]], [q[3], q[4], q[5]]);
                [a[0], a[1], a[2], b[0], b[1], b[2]]
            };
            let (fp, fm) = (f(qp), f(qm));
            for r in 0..6 {
                let fd = (fp[r] - fm[r]) / (2.0 * h);
                assert!((fd - k[(r, c)]).abs() <= 1e-7 * k.abs().max(), "({r},{c}) {fd} vs {}", k[(r, c)]);
            }
        }
        // And f = K q exactly (linear law), 1e-12 relative.
        let (fi, fj) = beam_forces(&g, &p, [q0[0], q0[1], q0[2]], [q0[3], q0[4], q0[5]]);
        let kq = k * SVector::<f64, 6>::from_column_slice(&q0);
        let f = [fi[0], fi[1], fi[2], fj[0], fj[1], fj[2]];
        for r in 0..6 {
            assert!((kq[r] - f[r]).abs() <= 1e-12 * kq.abs().max());
        }
    }

    #[test]
    fn hand_computed_actions_and_offset_moments() {
        // Beam along x, ℓ = 1, ĒA = 1, ĒI = 1 (Ē = 1, A = 1, I = 1) — the formulas by hand.
        let p = MechParams { e_bar: 1.0, ..MechParams::default() };
        let mut g = BeamGeom { ell: 1.0, n: [1.0, 0.0], r_i: [0.0; 2], r_j: [0.0; 2], area: 1.0, inertia: 1.0 };
        // Cantilever tip: particle j lifted by v = 0.01: δt = −0.01, F_T = −0.12, M_i = M_j = −0.06;
        // force needed on j is +0.12 along y (internal force at j = −F_T t = +0.12 e_y).
        let a = beam_actions(&g, &p, [0.0; 3], [0.0, 0.01, 0.0]);
        assert!((a.f_t + 0.12).abs() < 1e-15 && (a.m_i + 0.06).abs() < 1e-15 && (a.m_j + 0.06).abs() < 1e-15);
        let (fi, fj) = beam_forces(&g, &p, [0.0; 3], [0.0, 0.01, 0.0]);
        assert!((fj[1] - 0.12).abs() < 1e-15 && (fi[1] + 0.12).abs() < 1e-15);
        // Moment equilibrium about end i: M_i + M_j + ℓ·f_jy = −0.06 − 0.06 + 0.12 = 0.
        assert!((fi[2] + fj[2] + 1.0 * fj[1]).abs() < 1e-15);
        // Axial stretch 0.002 with end i offset r_i = (0, 0.3): F_N = 0.002; internal force at i is
        // −F_N n = (−0.002, 0) and its moment about c_i is r_i × f = −0.3·(−0.002) = +6e-4.
        g.r_i = [0.0, 0.3];
        let (fi, fj) = beam_forces(&g, &p, [0.0; 3], [0.002, 0.0, 0.0]);
        assert!((fi[0] + 0.002).abs() < 1e-15 && (fj[0] - 0.002).abs() < 1e-15);
        assert!((fi[2] - 6e-4).abs() < 1e-16 && fj[2].abs() < 1e-16);
    }

    #[test]
    fn bad_geometry_is_an_error() {
        assert!(matches!(
            BeamGeom::from_points([0.0, 0.0], [0.0, 0.0], [0.0; 2], [0.0; 2], 1.0, 1.0),
            Err(MechanicsError::ZeroLength { .. })
        ));
        assert!(BeamGeom::from_points([0.0, 0.0], [1.0, 0.0], [0.0; 2], [0.0; 2], -1.0, 1.0).is_err());
        let g = BeamGeom { ell: 1.0, n: [1.0, 1.0], r_i: [0.0; 2], r_j: [0.0; 2], area: 1.0, inertia: 1.0 };
        assert!(matches!(g.validate(), Err(MechanicsError::NotUnit { .. })));
    }
}
