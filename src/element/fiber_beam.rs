//! 2-node 3D beam with a fiber section (displacement-based, Euler–Bernoulli), 12 DOF: masonry
//! pilasters and arches with the uniaxial damage law in every fiber (paper §4.2).
//!
//! # Kinematics (local axes and DOF of [`ElasticFrame3d`](super::ElasticFrame3d))
//! Linear axial displacement, cubic (Hermite) transverse displacements, ξ = x/L ∈ [0, 1]:
//! ```text
//!   ε₀ = u'           = (u2 − u1)/L                                   (constant)
//!   κz = v''          = [(12ξ−6)/L², (6ξ−4)/L, (6−12ξ)/L², (6ξ−2)/L] · (v1, θz1, v2, θz2)
//!   κy = w''          = same row · (w1, −θy1, w2, −θy2)               (θy = −w')
//!   fiber strain      ε_f = ε₀ − y_f κz − z_f κy = a_fᵀ e,  a_f = (1, −y_f, −z_f),  e = B u_l
//! ```
//! Section forces and tangent from the fibers (area A_f, stress σ_f, tangent E_f):
//! `s = Σ_f A_f σ_f a_f = (N, Mz, My)`, `k_s = Σ_f A_f E_f a_f a_fᵀ`. Element (Gauss–Legendre
//! points ξ_g, weights w_g on [0, 1]) plus elastic torsion GJ:
//! ```text
//!   f_l = Σ_g w_g L Bᵀ s(ξ_g) + GJ/L (θx2 − θx1) (−e_θx1 + e_θx2)
//!   K_l = Σ_g w_g L Bᵀ k_s B  + GJ/L [1 −1; −1 1] on (θx1, θx2)
//! ```
//! and in global axes f = Tᵀ f_l, K = Tᵀ K_l T. K_l is the consistent tangent of f_l (the fibers
//! return their consistent tangent dσ/dε), or, for [`EvalRequest::ForceAndSecant`], the secant
//! matrix with E_f = (1 − d) E.
//!
//! # Choice: displacement-based, and its known error
//! The displacement-based formulation is the simple, robust one (no element-level iterations) and
//! matches the shells' trial/commit state handling. Its known limits: along one element the axial
//! strain is constant and the curvature linear, so (i) when the section's neutral axis moves
//! (cracking on one side) axial equilibrium holds only on average over the element and the element
//! is too stiff, and (ii) a curvature concentrated near a member end (a hinge) is spread over the
//! element; the error falls as O(h) with mesh refinement (Neuenhofer & Filippou, J. Struct. Eng.
//! 123(7), 1997). Use several elements per member where damage is expected (4 to 8 per member
//! is common practice). Elastically the element is exact for end loads: two Gauss points
//! integrate Bᵀ k_s B (quadratic in ξ) exactly, so K_l equals the elastic frame's with the grid's
//! EA, EIy, EIz ([`fiber_section`](super::fiber_section) docs).
//!
//! # Regularization
//! The damage law's B_t uses the element length h = L (Hillerborg crack band). In axial tension
//! the strain is uniform over the element, every Gauss point softens together, and the element
//! dissipates exactly G_f A (plus the elastic energy f_t² A L/(2E) with `hillerborg`) per crack.
//! In bending the band is narrower than L, so the dissipated energy per crack is overestimated by
//! the same O(h) mesh dependence as above.
//!
//! # Mass and self weight
//! As the elastic frame ([`beam_inertia`](super::beam_inertia)), with the line mass ρ b h + m_ns
//! and the rotary inertia ρ Ip, Ip = b h (b² + h²)/12.
//!
//! # State and checkpoint layout
//! Damage material only (elastic fibers are stateless, `n_state() = 0`): one [`DamageState`] per
//! (Gauss point g, fiber f), g-major, then the dissipated energy, kept by a [`PointStates`]
//! (with IMPL-EX, the histories one step back after them: its docs):
//! ```text
//!   state[4 (g n_f + f) + 0..4] = [κ_t, κ_c, d_t, d_c],   state[4 n_g n_f] = dissipated energy (J)
//! ```
//!
//! # Cell outputs ([`CELL_OUTPUT_NAMES`])
//! `d_t_max`, `d_t_mean`, `d_c_max`, `d_c_mean` over all fibers of all Gauss points (the mean
//! weighted by fiber area and Gauss weight: a volume mean), `axial_force` (tension positive) and
//! the twelve end forces in local axes as for the elastic frame (f_l − f_q, OpenSees
//! `localForce`), and the dissipated energy (J); all at the given displacement from the
//! committed state.

use nalgebra::{DMatrix, DVector, Matrix3, SMatrix, Vector3};

use super::beam_inertia;
use super::error::{check_finite_displacement, check_len, ElementError};
use super::fiber_section::{gauss_points, Fiber, FiberMaterial, FiberSection};
use super::local_frame::{LocalFrame, Mat12, Vec12};
use super::output::{prepare_matrix, prepare_vector, ElementOutput, EvalRequest};
use super::{AppliedLoads, Element, MassKind, PointStates, PointUpdate};
use crate::material::{DamageState, PointLaw, StressState, Uniaxial};

/// Number of DOF of the element.
const N_DOFS: usize = 12;

/// Names of the cell outputs (module docs).
pub const CELL_OUTPUT_NAMES: [&str; 18] = [
    "d_t_max",
    "d_t_mean",
    "d_c_max",
    "d_c_mean",
    "axial_force",
    "N_1",
    "Vy_1",
    "Vz_1",
    "T_1",
    "My_1",
    "Mz_1",
    "N_2",
    "Vy_2",
    "Vz_2",
    "T_2",
    "My_2",
    "Mz_2",
    "dissipated_energy",
];

/// Generalized strain–displacement matrix: e = (ε₀, κz, κy) = B u_l.
type Mat3x12 = SMatrix<f64, 3, 12>;

/// The fibers' law, ready to evaluate.
#[derive(Clone, Debug, PartialEq)]
enum FiberLaw {
    /// σ = E ε.
    Elastic(f64),
    /// The uniaxial damage law with B_t of this element's length.
    Damage(PointLaw),
}

/// A 2-node fiber beam (module docs).
#[derive(Clone, Debug, PartialEq)]
pub struct FiberBeam3d {
    coords: [[f64; 3]; 2],
    frame: LocalFrame,
    section: FiberSection,
    fibers: Vec<Fiber>,
    /// (ξ_g, w_g) on [0, 1] and B at each.
    points: Vec<(f64, Mat3x12)>,
    law: FiberLaw,
    /// GJ/L.
    torsion_stiffness: f64,
    /// The fibers' damage histories, g-major (module docs); empty for elastic fibers.
    states: PointStates,
}

/// The result of one evaluation in local axes.
struct LocalResponse {
    f: Vec12,
    k: Mat12,
    dissipation: f64,
}

/// B at ξ for an element of length `l` (module docs).
fn strain_matrix(xi: f64, l: f64) -> Mat3x12 {
    let mut b = Mat3x12::zeros();
    b[(0, 0)] = -1.0 / l;
    b[(0, 6)] = 1.0 / l;
    let row = [(12.0 * xi - 6.0) / (l * l), (6.0 * xi - 4.0) / l, (6.0 - 12.0 * xi) / (l * l), (6.0 * xi - 2.0) / l];
    // κz on (v1, θz1, v2, θz2) = DOF (1, 5, 7, 11).
    for (k, d) in [1, 5, 7, 11].into_iter().enumerate() {
        b[(1, d)] = row[k];
    }
    // κy on (w1, θy1, w2, θy2) = DOF (2, 4, 8, 10), rotations negated.
    for (k, (d, s)) in [(2, 1.0), (4, -1.0), (8, 1.0), (10, -1.0)].into_iter().enumerate() {
        b[(2, d)] = s * row[k];
    }
    b
}

impl FiberBeam3d {
    /// An element from node 1 at `x1` to node 2 at `x2`, local axes from `vecxz` (see
    /// [`LocalFrame`]), with the fiber `section` (validated here; the damage law is set up for
    /// h = L).
    ///
    /// Errors: [`ElementError::InvalidSection`], [`ElementError::InvalidCount`],
    /// [`ElementError::NonFiniteCoordinates`], [`ElementError::ZeroLength`],
    /// [`ElementError::BadOrientation`], [`ElementError::Material`].
    pub fn new(x1: [f64; 3], x2: [f64; 3], vecxz: [f64; 3], section: FiberSection) -> Result<Self, ElementError> {
        section.validate()?;
        let frame = LocalFrame::from_vecxz(x1, x2, vecxz)?;
        let l = frame.length();
        let law = match section.material {
            FiberMaterial::Elastic { e, .. } => FiberLaw::Elastic(e),
            FiberMaterial::Damage(p) => {
                FiberLaw::Damage(p.for_element(l).map_err(|source| ElementError::Material { h: l, source })?)
            }
        };
        let fibers = section.fibers();
        let points: Vec<(f64, Mat3x12)> =
            gauss_points(section.integration_points).into_iter().map(|(xi, w)| (w, strain_matrix(xi, l))).collect();
        let n_states = match law {
            FiberLaw::Elastic(_) => 0,
            FiberLaw::Damage(_) => points.len() * fibers.len(),
        };
        let torsion_stiffness = section.material.shear_modulus() * section.torsion_constant() / l;
        Ok(Self {
            coords: [x1, x2],
            frame,
            section,
            fibers,
            points,
            law,
            torsion_stiffness,
            states: PointStates::new(n_states, 1),
        })
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
    pub fn section(&self) -> &FiberSection {
        &self.section
    }

    /// Energy dissipated up to the committed state (J).
    pub fn dissipated_energy(&self) -> f64 {
        self.states.dissipated()
    }

    /// The committed states, g-major (module docs); empty for elastic fibers.
    pub fn committed_states(&self) -> &[DamageState] {
        self.states.committed()
    }

    fn local_displacement(&self, u_e: &[f64]) -> Result<Vec12, ElementError> {
        check_len("u_e", N_DOFS, u_e.len())?;
        check_finite_displacement(u_e)?;
        Ok(self.frame.vec12_to_local(&Vec12::from_column_slice(u_e)))
    }

    /// Force, tangent (if `want_k`) and dissipation in local axes at `u_l`, the fibers' states
    /// read and written through `states` (none for elastic fibers). Pure in (the states it
    /// reads, u_l).
    fn respond(&self, u_l: &Vec12, want_k: bool, secant: bool, states: &mut PointUpdate) -> LocalResponse {
        let l = self.frame.length();
        let nf = self.fibers.len();
        let mut f = Vec12::zeros();
        let mut k = Mat12::zeros();
        let mut dissipation = 0.0;
        for (g, (w, b)) in self.points.iter().enumerate() {
            let e: Vector3<f64> = b * u_l;
            let mut s = Vector3::zeros();
            let mut ks = Matrix3::zeros();
            let mut diss = 0.0;
            for (i, fib) in self.fibers.iter().enumerate() {
                let a = Vector3::new(1.0, -fib.y, -fib.z);
                let eps = a.dot(&e);
                let (sigma, tangent) = match &self.law {
                    FiberLaw::Elastic(modulus) => (modulus * eps, *modulus),
                    FiberLaw::Damage(law) => {
                        let strain = nalgebra::Vector1::new(eps);
                        let r = states.respond(law, g * nf + i, &strain, Uniaxial::evaluate);
                        diss += fib.area * r.dissipation;
                        (r.stress[0], if secant { r.secant[0] } else { r.tangent[0] })
                    }
                };
                s += a * (fib.area * sigma);
                if want_k {
                    ks += a * a.transpose() * (fib.area * tangent);
                }
            }
            let wl = w * l;
            f += b.tr_mul(&s) * wl;
            if want_k {
                k += b.tr_mul(&(ks * b)) * wl;
            }
            dissipation += wl * diss;
        }
        let twist = self.torsion_stiffness * (u_l[9] - u_l[3]);
        f[3] -= twist;
        f[9] += twist;
        if want_k {
            beam_inertia::add_bar(&mut k, 3, 9, self.torsion_stiffness, -self.torsion_stiffness);
        }
        LocalResponse { f, k, dissipation }
    }

    /// Local tangent stiffness at `u_e` from the committed state (for tests and diagnostics).
    pub fn local_tangent(&self, u_e: &[f64]) -> Result<Mat12, ElementError> {
        let u_l = self.local_displacement(u_e)?;
        let mut scratch = self.states.committed().to_vec();
        let mut states = PointUpdate::implicit(self.states.committed(), &mut scratch);
        Ok(self.respond(&u_l, true, false, &mut states).k)
    }

    /// Local mass matrix of the chosen kind ([`beam_inertia`](super::beam_inertia)).
    pub fn local_mass(&self, kind: MassKind) -> Mat12 {
        let s = &self.section;
        beam_inertia::local_mass(self.frame.length(), s.line_mass(), s.density * s.polar_moment(), kind)
    }
}

impl Element for FiberBeam3d {
    fn kind_name(&self) -> &'static str {
        "fiber_beam_3d"
    }

    fn n_nodes(&self) -> usize {
        2
    }

    fn evaluate(&mut self, u_e: &[f64], request: EvalRequest, out: &mut ElementOutput) -> Result<(), ElementError> {
        let u_l = self.local_displacement(u_e)?;
        out.prepare(N_DOFS);
        let want_k = request.wants_tangent();
        let mut states = std::mem::replace(&mut self.states, PointStates::new(0, 1));
        let r = self.respond(&u_l, want_k, request.wants_secant(), &mut states.for_update());
        states.set_trial_dissipation(r.dissipation);
        self.states = states;
        out.f_int.copy_from(&self.frame.vec12_to_global(&r.f));
        if want_k {
            out.k_t.copy_from(&self.frame.mat12_to_global(&r.k));
            out.has_tangent = true;
        }
        Ok(())
    }

    fn commit(&mut self) {
        self.settle_implex();
        self.states.commit();
    }

    fn revert(&mut self) {
        self.states.revert();
    }

    /// Over the fibers of every Gauss point ([`crate::element::damage_increment`]).
    fn damage_increment(&self) -> f64 {
        self.states.damage_increment()
    }

    fn mass(&self, kind: MassKind, m: &mut DMatrix<f64>) {
        prepare_matrix(m, N_DOFS);
        m.copy_from(&self.frame.mat12_to_global(&self.local_mass(kind)));
    }

    fn gravity_load(&self, g: [f64; 3], f: &mut DVector<f64>) {
        prepare_vector(f, N_DOFS);
        let fl = beam_inertia::local_gravity_load(&self.frame, self.section.line_mass(), g);
        f.copy_from(&self.frame.vec12_to_global(&fl));
    }

    fn cell_output_names(&self) -> &'static [&'static str] {
        &CELL_OUTPUT_NAMES
    }

    fn cell_output(&self, u_e: &[f64], loads: &AppliedLoads, values: &mut [f64]) -> Result<(), ElementError> {
        check_len("cell output", CELL_OUTPUT_NAMES.len(), values.len())?;
        let u_l = self.local_displacement(u_e)?;
        let mut scratch = self.states.committed().to_vec();
        let r = self.respond(&u_l, false, false, &mut PointUpdate::implicit(self.states.committed(), &mut scratch));
        let (mut dt_max, mut dt_mean, mut dc_max, mut dc_mean) = (0.0f64, 0.0, 0.0f64, 0.0);
        if !scratch.is_empty() {
            let nf = self.fibers.len();
            let area = self.section.area();
            for (g, (w, _)) in self.points.iter().enumerate() {
                for (i, fib) in self.fibers.iter().enumerate() {
                    let s = &scratch[g * nf + i];
                    dt_max = dt_max.max(s.d_t);
                    dc_max = dc_max.max(s.d_c);
                    dt_mean += w * fib.area / area * s.d_t;
                    dc_mean += w * fib.area / area * s.d_c;
                }
            }
        }
        let fq = beam_inertia::local_gravity_load(&self.frame, self.section.line_mass(), loads.gravity);
        let end = r.f - fq;
        values[0] = dt_max;
        values[1] = dt_mean;
        values[2] = dc_max;
        values[3] = dc_mean;
        values[4] = 0.5 * (end[6] - end[0]);
        values[5..17].copy_from_slice(end.as_slice());
        values[17] = self.states.dissipated() + r.dissipation;
        Ok(())
    }

    fn dissipated_energy(&self) -> f64 {
        self.states.dissipated()
    }

    fn n_state(&self) -> usize {
        self.states.n_state()
    }

    fn save_state(&self, out: &mut [f64]) -> Result<(), ElementError> {
        self.states.save(out)
    }

    fn load_state(&mut self, state: &[f64]) -> Result<(), ElementError> {
        self.states.load(state)
    }

    fn set_implex(&mut self, split: Option<crate::material::implex::SplitAt>) {
        self.states.set_implex(split);
    }

    fn set_implex_step(&mut self, h: f64) {
        if let FiberLaw::Damage(law) = &self.law {
            self.states.set_implex_step(law, h);
        }
    }

    fn hold_implex_histories(&mut self) -> f64 {
        self.states.hold_trial()
    }

    /// Fiber i of Gauss point g (j = g n_f + i): the energy weighted by w_g L A_f as in
    /// [`Self::evaluate`].
    fn settle_implex(&mut self) {
        let FiberLaw::Damage(law) = &self.law else { return };
        let (nf, l, points, fibers) = (self.fibers.len(), self.frame.length(), &self.points, &self.fibers);
        self.states.settle(|j, e, c| {
            let r = Uniaxial::evaluate(law, &nalgebra::Vector1::new(e[0]), c);
            (r.state, points[j / nf].0 * l * fibers[j % nf].area * r.dissipation)
        });
    }
}

#[cfg(test)]
#[path = "fiber_beam_tests.rs"]
mod tests;
