//! [`ShellElement`]: the part of the flat shell elements that does not depend on the shape —
//! layered section, integration-point state, force and tangent, mass, gravity, outputs,
//! checkpoints. [`mitc4`](super::mitc4) and [`tri3`](super::tri3) only supply the strain–
//! displacement matrices at the in-plane integration points.
//!
//! # Local DOF and strains (flat frame, [`geometry`](super::geometry))
//! Per node `u v w θx θy θz` along/about the local axes e₁ e₂ e₃ (right-hand rule). Through the
//! thickness (Reissner–Mindlin) a point at height z moves by (u + z θy, v − z θx, w), so with
//! βx = θy, βy = −θx:
//!
//! ```text
//!   ε₀ = [u,x,  v,y,  u,y + v,x]                  membrane strain
//!   κ  = [βx,x, βy,y, βx,y + βy,x]                curvature (layer strain ε = ε₀ + z κ)
//!   γ  = [w,x + βx, w,y + βy]                     transverse shear (MITC4; zero in the DKT)
//!   δ  = θz − ω,  ω = ½ (v,x − u,y)               drilling: rotation minus in-plane rotation
//! ```
//! Kirchhoff limit: θx = ∂w/∂y, θy = −∂w/∂x.
//!
//! # Virtual work at the integration points p (weights w_p = area weight)
//! ```text
//!   f = Σ_p w_p [ B_pᵀ (N, M) + B_sᵀ Q + B_δᵀ k_δ δ ],   Q = k G t γ (elastic, k = 5/6)
//!   K = Σ_p w_p [ B_pᵀ S B_p + k G t B_sᵀ B_s + k_δ B_δᵀ B_δ ]
//! ```
//! with B_p = [B_m; B_b] (6 × D), (N, M) and S = [[A, B], [B, D]] from the layers (their
//! consistent tangent, or their secant (1 − d) C₀ for [`EvalRequest::ForceAndSecant`])
//! ([`layers`](super::layers)). Global: f_g = Gᵀ f, K_g = Gᵀ K G ([`geometry`](super::geometry)).
//!
//! # Drilling stiffness (Hughes–Brezzi penalty)
//! Energy ½ ∫ k_δ (θz − ω)² dA with k_δ = α G t, α = [`DRILLING_FACTOR`] = 1e-2, integrated with
//! the same rule as the membrane (2×2 Gauss on quads, 3 points on triangles). It vanishes for
//! every linear displacement field with θz = ω (so the membrane patch test passes exactly) and for
//! rigid rotations about the normal (so the element keeps exactly 6 zero-energy modes); it gives
//! the θz DOF a stiffness where shells meet at an angle or a flat region has no other stiffness
//! for it. Small α leaves the membrane response practically unchanged.
//!
//! # Mass
//! Consistent: M_ab = ∫ N_a N_b dA × (m₀ on u v w, I_r on θx θy, I_r on θz) with the linear /
//! bilinear shape functions, m₀ = ρ t + non-structural mass per area, I_r = ρ t³ / 12.
//! Lumped: the row sums, i.e. the nodal areas A_a = ∫ N_a dA times the same densities, on the
//! diagonal. The drilling rotation gets I_r, the same as the bending rotations: a small positive
//! value that keeps M positive definite; with k_δ = α G t the drilling modes sit at
//! sqrt(12 α G / (ρ t²)), far above the structural ones. Both are transformed with G.
//! Gravity: f_a = ∫ N_a dA m₀ g (translations; consistent), transformed with G.
//!
//! # State and checkpoint layout
//! Damage material only (elastic elements are stateless, `n_state() = 0`): one [`DamageState`]
//! per (in-plane point p, thickness point j), p-major, and the dissipated energy, kept by a
//! [`PointStates`] (with IMPL-EX, the histories one step back after them: its docs):
//!
//! ```text
//!   state[4 (p n_z + j) + 0..4] = [κ_t, κ_c, d_t, d_c]     p < n_points, j < n_z = 2 layers + 1
//!   state[4 n_points n_z]       = energy dissipated by the element up to the committed state (J)
//! ```
//!
//! # Cell outputs ([`CELL_OUTPUT_NAMES`])
//! d_t and d_c max and mean (mean weighted by the integration weights, i.e. a volume mean over the
//! element), N and M (local axes e₁ e₂, mean over the in-plane points, N/m and N m/m), and the
//! dissipated energy (J), all at the given displacement from the committed state.

use nalgebra::{DMatrix, DVector, Matrix6, SMatrix, SVector, Vector2, Vector3, Vector6};

use super::layers::{damage_section, plane_stress_matrix, NonlocalInput, SectionResponse, ThicknessRule};
use super::section::{ShellMaterial, ShellSection};
use super::{geometry::FlatGeometry, products, ShellError};
use crate::element::error::{check_finite_displacement, check_len};
use crate::element::output::{prepare_matrix, prepare_vector};
use crate::element::{
    AppliedLoads, Element, ElementError, ElementOutput, EvalRequest, MassKind, NonlocalPoint, PointStates, PointUpdate,
};
use crate::material::{nonlocal, plane_stress, DamageState, MaterialError, PointLaw, Split};

/// α of the drilling stiffness k_δ = α G t (module docs).
pub const DRILLING_FACTOR: f64 = 1e-2;

/// Names of the cell outputs of shell elements (module docs).
pub const CELL_OUTPUT_NAMES: [&str; 11] =
    ["d_t_max", "d_t_mean", "d_c_max", "d_c_mean", "Nxx", "Nyy", "Nxy", "Mxx", "Myy", "Mxy", "dissipated_energy"];

/// Stress resultants at one in-plane integration point, element local axes.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct PointResultants {
    /// Membrane forces [N_xx, N_yy, N_xy] (N/m).
    pub n: Vector3<f64>,
    /// Moments [M_xx, M_yy, M_xy] = ∫ σ z dz (N m/m).
    pub m: Vector3<f64>,
}

/// Strain–displacement matrices of one in-plane integration point, in the flat local frame.
#[derive(Clone, Debug, PartialEq)]
pub(crate) struct PlanePoint<const N: usize, const D: usize> {
    /// Area weight (Gauss weight × Jacobian).
    pub weight: f64,
    /// Shape function values (for mass and gravity).
    pub shape: SVector<f64, N>,
    /// [B_m; B_b]: (ε₀, κ) = b u.
    pub b: SMatrix<f64, 6, D>,
    /// B_s: γ = b_s u (zero for the DKT).
    pub b_s: SMatrix<f64, 2, D>,
    /// B_δ: θz − ω = b_d u.
    pub b_d: SMatrix<f64, 1, D>,
}

/// The material of the layers, ready to evaluate.
#[derive(Clone, Debug, PartialEq)]
enum SectionLaw {
    /// Elastic: the section tangent [[A, B], [B, D]] integrated once by the layer rule.
    Elastic(Matrix6<f64>),
    /// Damage law with B_t of this element's size.
    Damage(PointLaw),
}

/// A flat shell element with `N` nodes and `D` = 6 N DOF. Built by `ShellQuad4::new` (MITC4) and
/// `ShellTri3::new` (DKT + Allman); see the module docs for the formulation.
#[derive(Clone, Debug, PartialEq)]
pub struct ShellElement<const N: usize, const D: usize> {
    kind: &'static str,
    coords: [[f64; 3]; N],
    pub(super) geometry: FlatGeometry<N>,
    g: SMatrix<f64, D, D>,
    pub(super) points: Vec<PlanePoint<N, D>>,
    /// The columns where B, B_s and B_δ of some point are nonzero ([`products`](super::products)).
    active: [Vec<usize>; 3],
    section: ShellSection,
    pub(super) rule: ThicknessRule,
    law: SectionLaw,
    shear_stiffness: f64,
    drilling_stiffness: f64,
    /// The layer points' damage histories, p-major (module docs); empty for elastic sections.
    states: PointStates,
    /// Nonlocal averaging ([`Element::enable_nonlocal`]): `[ε̄_t, ε̄_c]` per state point, set by
    /// the driver before each evaluation; empty for the local law.
    averaged: Vec<[f64; 2]>,
    /// The points' own shares of their averages (same layout as `averaged`).
    self_share: Vec<f64>,
    /// The element tangent (global axes) while every point is in its virgin elastic state
    /// (module docs of [`Self::evaluate`]'s cache), once computed.
    elastic_k: Option<Box<SMatrix<f64, D, D>>>,
}

impl<const N: usize, const D: usize> ShellElement<N, D> {
    /// Assemble an element from its geometry and integration points (validated section).
    pub(super) fn from_parts(
        kind: &'static str,
        coords: [[f64; 3]; N],
        geometry: FlatGeometry<N>,
        points: Vec<PlanePoint<N, D>>,
        section: &ShellSection,
    ) -> Result<Self, ShellError> {
        section.validate()?;
        let rule = ThicknessRule::simpson(section.thickness, section.layers);
        let h = geometry.characteristic_length();
        let law = match section.material {
            ShellMaterial::Elastic { e, nu } => SectionLaw::Elastic(rule.elastic_section(&plane_stress_matrix(e, nu))),
            ShellMaterial::Damage(p) => {
                SectionLaw::Damage(p.for_element(h).map_err(|source| ShellError::Material { h, source })?)
            }
        };
        let n_states = match law {
            SectionLaw::Elastic(_) => 0,
            SectionLaw::Damage(_) => points.len() * rule.len(),
        };
        let g = geometry.transformation::<D>();
        let active = [
            products::active_columns(points.iter().map(|p| &p.b)),
            products::active_columns(points.iter().map(|p| &p.b_s)),
            products::active_columns(points.iter().map(|p| &p.b_d)),
        ];
        Ok(ShellElement {
            kind,
            coords,
            geometry,
            g,
            points,
            active,
            section: *section,
            rule,
            law,
            shear_stiffness: section.shear_stiffness(),
            drilling_stiffness: DRILLING_FACTOR * section.material.shear_modulus() * section.thickness,
            states: PointStates::new(n_states, 3),
            averaged: Vec::new(),
            self_share: Vec::new(),
            elastic_k: None,
        })
    }

    /// Whether every layer point's trial state is elastic and undamaged (or the section is
    /// elastic): d_t = d_c = 0 and κ at the law's thresholds.
    fn trial_is_elastic(&self) -> bool {
        match &self.law {
            SectionLaw::Elastic(_) => true,
            SectionLaw::Damage(law) => {
                let v = DamageState::virgin(law);
                self.states.trial().iter().all(|s| *s == v)
            }
        }
    }

    /// `Gᵀ k G`, node block by node block ([`products`](super::products) docs).
    #[cfg(test)]
    pub(super) fn to_global(&self, k: &SMatrix<f64, D, D>) -> SMatrix<f64, D, D> {
        products::rotate::<N, D>(&self.g, k, false)
    }

    /// Node coordinates the element was built from (global).
    pub fn coords(&self) -> &[[f64; 3]; N] {
        &self.coords
    }

    /// The section.
    pub fn section(&self) -> &ShellSection {
        &self.section
    }

    /// Local axes: rows e₁, e₂, e₃ in global components ([`geometry`](super::geometry) docs).
    pub fn local_axes(&self) -> &nalgebra::Matrix3<f64> {
        &self.geometry.rotation
    }

    /// Area of the (projected) element (m²).
    pub fn area(&self) -> f64 {
        self.geometry.area
    }

    /// Heights of the nodes above the mean plane (m); zero for flat elements.
    pub fn warping_offsets(&self) -> &[f64; N] {
        &self.geometry.offsets
    }

    /// Number of in-plane integration points.
    pub fn n_plane_points(&self) -> usize {
        self.points.len()
    }

    /// Number of material points through the thickness (2 layers + 1).
    pub fn n_thickness_points(&self) -> usize {
        self.rule.len()
    }

    /// Energy dissipated up to the committed state (J).
    pub fn dissipated_energy(&self) -> f64 {
        self.states.dissipated()
    }

    /// The committed states, p-major (module docs); empty for elastic sections.
    pub fn committed_states(&self) -> &[DamageState] {
        self.states.committed()
    }

    fn flat_displacement(&self, u_e: &[f64]) -> Result<SVector<f64, D>, ElementError> {
        check_len("u_e", D, u_e.len())?;
        check_finite_displacement(u_e)?;
        Ok(self.g * SVector::<f64, D>::from_column_slice(u_e))
    }

    /// Section response at point `p` for the flat displacement `uf`, the states of its layer
    /// points read and written through `points`. (The point's own data, each argument distinct:
    /// no struct would name them better.)
    #[allow(clippy::too_many_arguments)]
    fn section_at(
        law: &SectionLaw,
        rule: &ThicknessRule,
        pt: &PlanePoint<N, D>,
        uf: &SVector<f64, D>,
        points: &mut PointUpdate,
        secant: bool,
        nonlocal: Option<NonlocalInput>,
    ) -> SectionResponse {
        let strain: Vector6<f64> = pt.b * uf;
        match law {
            SectionLaw::Elastic(s) => {
                let r = s * strain;
                SectionResponse {
                    n: r.fixed_rows::<3>(0).into_owned(),
                    m: r.fixed_rows::<3>(3).into_owned(),
                    tangent: *s,
                    dissipation: 0.0,
                }
            }
            SectionLaw::Damage(law) => {
                let e0: Vector3<f64> = strain.fixed_rows::<3>(0).into_owned();
                let ka: Vector3<f64> = strain.fixed_rows::<3>(3).into_owned();
                damage_section(law, rule, &e0, &ka, points, secant, nonlocal)
            }
        }
    }

    /// Membrane forces N and moments M (local axes) at every in-plane integration point, at the
    /// total displacement `u_e` from the committed state.
    pub fn point_resultants(&self, u_e: &[f64]) -> Result<Vec<PointResultants>, ElementError> {
        let uf = self.flat_displacement(u_e)?;
        let nz = self.rule.len();
        let mut scratch = vec![DamageState::default(); nz];
        let mut out = Vec::with_capacity(self.points.len());
        for (p, pt) in self.points.iter().enumerate() {
            let committed = self.states_of(p, self.states.committed());
            let r = Self::section_at(
                &self.law,
                &self.rule,
                pt,
                &uf,
                &mut PointUpdate::implicit(committed, &mut scratch[..committed.len()]),
                false,
                self.nonlocal_input(p),
            );
            out.push(PointResultants { n: r.n, m: r.m });
        }
        Ok(out)
    }

    /// The averaged driving strains of in-plane point `p`'s layer points (nonlocal law), else None.
    fn nonlocal_input(&self, p: usize) -> Option<NonlocalInput<'_>> {
        let nz = self.rule.len();
        (!self.averaged.is_empty()).then(|| NonlocalInput {
            averaged: &self.averaged[p * nz..(p + 1) * nz],
            self_share: &self.self_share[p * nz..(p + 1) * nz],
        })
    }

    fn states_of<'a>(&self, p: usize, all: &'a [DamageState]) -> &'a [DamageState] {
        let nz = self.rule.len();
        if all.is_empty() {
            &[]
        } else {
            &all[p * nz..(p + 1) * nz]
        }
    }
}

impl<const N: usize, const D: usize> Element for ShellElement<N, D> {
    fn kind_name(&self) -> &'static str {
        self.kind
    }

    fn n_nodes(&self) -> usize {
        N
    }

    /// The tangent `Gᵀ (Σ_p w_p [Bᵀ S B + B_sᵀ k_s B_s + B_dᵀ k_d B_d]) G` is the same in every
    /// evaluation where each layer point of the element is elastic and undamaged (trial
    /// d_t = d_c = 0, κ at its thresholds: S is then the elastic section) or the section is
    /// elastic: it is computed once and kept, and evaluations in that state copy it. The forces
    /// and the states are computed at every evaluation. Not with nonlocal averaging (its inputs
    /// come from the neighbours).
    fn evaluate(&mut self, u_e: &[f64], request: EvalRequest, out: &mut ElementOutput) -> Result<(), ElementError> {
        let uf = self.flat_displacement(u_e)?;
        out.prepare(D);
        let want_k = request.wants_tangent();
        let nz = self.rule.len();
        let has_state = !self.states.is_empty();
        let mut f = SVector::<f64, D>::zeros();
        let mut dissipation = 0.0;
        // The section tangents of the points (at most 4), for the tangent after the loop.
        let mut tangents = [Matrix6::zeros(); 4];
        debug_assert!(self.points.len() <= tangents.len());
        let strain_len = self.states.strain_len();
        let mut states = self.states.for_update();
        for (p, pt) in self.points.iter().enumerate() {
            let range = if has_state { p * nz..(p + 1) * nz } else { 0..0 };
            let r = Self::section_at(
                &self.law,
                &self.rule,
                pt,
                &uf,
                &mut states.slice(range, strain_len),
                request.wants_secant(),
                if self.averaged.is_empty() {
                    None
                } else {
                    Some(NonlocalInput {
                        averaged: &self.averaged[p * nz..(p + 1) * nz],
                        self_share: &self.self_share[p * nz..(p + 1) * nz],
                    })
                },
            );
            let w = pt.weight;
            let q: Vector2<f64> = pt.b_s * uf * self.shear_stiffness;
            let drill = (pt.b_d * uf)[0] * self.drilling_stiffness;
            let mut nm = Vector6::zeros();
            nm.fixed_rows_mut::<3>(0).copy_from(&r.n);
            nm.fixed_rows_mut::<3>(3).copy_from(&r.m);
            f += (pt.b.tr_mul(&nm) + pt.b_s.tr_mul(&q) + pt.b_d.transpose() * drill) * w;
            tangents[p] = r.tangent;
            dissipation += w * r.dissipation;
        }
        self.states.set_trial_dissipation(dissipation);
        out.f_int.copy_from(&self.g.tr_mul(&f));
        if want_k {
            let elastic = !request.wants_secant() && self.averaged.is_empty() && self.trial_is_elastic();
            match (&self.elastic_k, elastic) {
                (Some(k), true) => out.k_t.copy_from(&**k),
                _ => {
                    let mut k = SMatrix::<f64, D, D>::zeros();
                    let [on_b, on_s, on_d] = &self.active;
                    let mut symmetric = true;
                    for (pt, t) in self.points.iter().zip(&tangents) {
                        let w = pt.weight;
                        products::add_btb(&mut k, &pt.b, t, w, on_b);
                        products::add_scaled_btb(&mut k, &pt.b_s, w * self.shear_stiffness, on_s);
                        products::add_scaled_btb(&mut k, &pt.b_d, w * self.drilling_stiffness, on_d);
                        symmetric &= *t == t.transpose();
                    }
                    let kg = products::rotate::<N, D>(&self.g, &k, symmetric);
                    out.k_t.copy_from(&kg);
                    if elastic {
                        self.elastic_k = Some(Box::new(kg));
                    }
                }
            }
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

    /// Over the layer points of every in-plane point ([`crate::element::damage_increment`]).
    fn damage_increment(&self) -> f64 {
        self.states.damage_increment()
    }

    fn mass(&self, kind: MassKind, m: &mut DMatrix<f64>) {
        prepare_matrix(m, D);
        let ml = self.local_mass(kind);
        m.copy_from(&products::rotate::<N, D>(&self.g, &ml, true));
    }

    fn gravity_load(&self, g: [f64; 3], f: &mut DVector<f64>) {
        prepare_vector(f, D);
        let gl = self.geometry.rotation * Vector3::from(g) * self.section.mass_per_area();
        let mut fl = SVector::<f64, D>::zeros();
        for pt in &self.points {
            for a in 0..N {
                for k in 0..3 {
                    fl[6 * a + k] += pt.weight * pt.shape[a] * gl[k];
                }
            }
        }
        f.copy_from(&self.g.tr_mul(&fl));
    }

    fn cell_output_names(&self) -> &'static [&'static str] {
        &CELL_OUTPUT_NAMES
    }

    fn cell_output(&self, u_e: &[f64], _loads: &AppliedLoads, values: &mut [f64]) -> Result<(), ElementError> {
        check_len("cell output", CELL_OUTPUT_NAMES.len(), values.len())?;
        let uf = self.flat_displacement(u_e)?;
        let nz = self.rule.len();
        let mut scratch = vec![DamageState::default(); if self.states.is_empty() { 0 } else { nz }];
        let (mut dt_max, mut dt_mean, mut dc_max, mut dc_mean) = (0.0f64, 0.0, 0.0f64, 0.0);
        let mut n = Vector3::zeros();
        let mut m = Vector3::zeros();
        let mut dissipation = 0.0;
        let mut volume = 0.0;
        for (p, pt) in self.points.iter().enumerate() {
            let committed = self.states_of(p, self.states.committed());
            let r = Self::section_at(
                &self.law,
                &self.rule,
                pt,
                &uf,
                &mut PointUpdate::implicit(committed, &mut scratch),
                false,
                self.nonlocal_input(p),
            );
            n += r.n;
            m += r.m;
            dissipation += pt.weight * r.dissipation;
            for (s, w) in scratch.iter().zip(self.rule.weights()) {
                dt_max = dt_max.max(s.d_t);
                dc_max = dc_max.max(s.d_c);
                dt_mean += pt.weight * w * s.d_t;
                dc_mean += pt.weight * w * s.d_c;
            }
            volume += pt.weight * self.section.thickness;
        }
        let np = self.points.len() as f64;
        values[0] = dt_max;
        values[1] = dt_mean / volume;
        values[2] = dc_max;
        values[3] = dc_mean / volume;
        values[4..7].copy_from_slice((n / np).as_slice());
        values[7..10].copy_from_slice((m / np).as_slice());
        values[10] = self.states.dissipated() + dissipation;
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

    /// Damage layers only: the law rebuilt with the regularization length `length` in place of
    /// the element size (the band width is then set by the averaging, not by the mesh), and one
    /// point per (in-plane point p, layer point j), p-major as the state, at the in-plane point's
    /// position (mid-surface), with volume w_p w_j, averaged within layer point j.
    fn enable_nonlocal(&mut self, length: f64) -> Result<Vec<NonlocalPoint>, MaterialError> {
        let (SectionLaw::Damage(_), ShellMaterial::Damage(p)) = (&self.law, &self.section.material) else {
            return Ok(Vec::new());
        };
        self.law = SectionLaw::Damage(p.for_element(length)?);
        let nz = self.rule.len();
        let n = self.points.len() * nz;
        self.averaged = vec![[0.0; 2]; n];
        self.self_share = vec![1.0; n];
        let mut out = Vec::with_capacity(n);
        for pt in &self.points {
            let mut x = [0.0; 3];
            for (a, c) in self.coords.iter().enumerate() {
                for k in 0..3 {
                    x[k] += pt.shape[a] * c[k];
                }
            }
            for (j, w) in self.rule.weights().iter().enumerate() {
                out.push(NonlocalPoint { x, volume: pt.weight * w, layer: j });
            }
        }
        Ok(out)
    }

    fn local_driving_strains(&self, u_e: &[f64], out: &mut Vec<f64>) -> Result<(), ElementError> {
        let SectionLaw::Damage(law) = &self.law else { return Ok(()) };
        if self.averaged.is_empty() {
            return Ok(());
        }
        let uf = self.flat_displacement(u_e)?;
        for pt in &self.points {
            let strain: Vector6<f64> = pt.b * uf;
            let e0: Vector3<f64> = strain.fixed_rows::<3>(0).into_owned();
            let ka: Vector3<f64> = strain.fixed_rows::<3>(3).into_owned();
            for z in self.rule.z() {
                out.extend_from_slice(&nonlocal::driving_strains(law, &(e0 + ka * *z)));
            }
        }
        Ok(())
    }

    fn set_nonlocal_strains(&mut self, averaged: &[f64], self_share: &[f64]) {
        for ((a, s), (v, share)) in
            self.averaged.iter_mut().zip(self.self_share.iter_mut()).zip(averaged.chunks_exact(2).zip(self_share))
        {
            *a = [v[0], v[1]];
            *s = *share;
        }
    }

    fn set_damage_relaxation(&mut self, dt: f64, tau: Option<f64>) {
        if let SectionLaw::Damage(law) = &mut self.law {
            *law = law.with_relaxation(dt, tau);
        }
    }

    fn set_implex(&mut self, split: Option<crate::material::implex::SplitAt>) {
        self.states.set_implex(split);
    }

    fn implex_tangent_symmetric(&self) -> bool {
        self.averaged.is_empty() && !matches!(&self.law, SectionLaw::Damage(l) if l.split() != Split::Spectral)
    }

    fn set_implex_step(&mut self, h: f64) {
        if let SectionLaw::Damage(law) = &self.law {
            self.states.set_implex_step(law, h);
        }
    }

    fn hold_implex_histories(&mut self) -> f64 {
        self.states.hold_trial()
    }

    /// Layer point j = p n_z + l: the law at its strain (nonlocal with its averages), the energy
    /// weighted by w_p w_l as in [`Self::evaluate`].
    fn settle_implex(&mut self) {
        let SectionLaw::Damage(law) = &self.law else { return };
        let (nz, points, weights) = (self.rule.len(), &self.points, self.rule.weights());
        let (averaged, share) = (&self.averaged, &self.self_share);
        self.states.settle(|j, e, c| {
            let strain = Vector3::from_column_slice(e);
            let (state, dissipation) = match averaged.is_empty() {
                true => plane_stress::update_state(law, &strain, c),
                false => {
                    let r = nonlocal::update(law, &strain, c, averaged[j], share[j]);
                    (r.state, r.dissipation)
                }
            };
            (state, points[j / nz].weight * weights[j % nz] * dissipation)
        });
    }
}
