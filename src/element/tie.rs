//! 2-node tie (an iron tie rod): axial force only, small displacements, 12 DOF of which only the
//! translations take stiffness.
//!
//! # Kinematics and member force
//! ```text
//!   e = (x₂ − x₁) / L          unit axis, node 1 → node 2
//!   δ = e · (u₂ − u₁)          elongation (translations only; rotations do not enter)
//!   ε = δ / L                  strain (cell output `strain`)
//!   N = N₀ + k δ,  k = E A / L member force, tension positive; N₀ ≥ 0 the pretension
//! ```
//! Tension only (the default: a slender rod buckles at a few kN): N = max(0, N₀ + k δ). The tie
//! is *slack* when N₀ + k δ < 0; at exactly 0 it takes the taut branch, so a tie without
//! pretension is taut at u = 0 and the initial stiffness (modal analysis, Rayleigh damping,
//! linear statics) includes it.
//!
//! # Pretension: a static load, not an internal force
//! Every static driver solves r = λ f_static − f_int(u) = 0 with λ going from 0 to 1 (the
//! gravity phase of a time history, the load stage of `static_nonlinear`; λ = 1 in linear
//! statics). N splits into the pretension and the elastic part, N = N₀ + N_e:
//! ```text
//!   f_int = N_e [−e, e]        N_e = k δ (taut), −N₀ (slack)        (translations of nodes 1, 2)
//!   f_pre = N₀ [e, −e]         in f_static: it pulls the two ends together
//! ```
//! `f_pre` is [`pretension_load`]; the model adds it to the nodal loads
//! (`model::StructuralModel::nodal_loads`), so every driver scales it with the other static
//! loads. At λ = 1 the tie's share of the residual is f_pre − f_int = −(N₀ + N_e)[−e, e] =
//! −N [−e, e]: exactly the equilibrium with the true member force N, taut or slack (slack:
//! f_int = N₀ [e, −e] cancels f_pre, the tie exerts nothing). At λ = 0 and u = 0 the residual is
//! zero (N_e(0) = 0), a state at rest, so the gravity phase ramps the pretension up with the
//! self weight, and a job whose only static load is a pretension still has a gravity phase.
//!
//! Rejected alternative: f_int = N [−e, e] and no load. Exact at equilibrium too, but
//! f_int(0) = N₀ [−e, e] ≠ 0: linear statics (K u = f) would miss the pretension and a time
//! history would start out of balance.
//!
//! The element does not know λ: for λ < 1 its slack test uses the full N₀ (the state on the way
//! is not the one of a tie pretensioned by λ N₀). The element is path independent, so the state
//! at λ = 1 is exact whatever the path.
//!
//! # Tangent (consistent)
//! ```text
//!   K = k [  e eᵀ  −e eᵀ ]     on (u₁, u₂); zero rows and columns for the rotations;
//!         [ −e eᵀ   e eᵀ ]     K = 0 when slack
//! ```
//! The secant matrix ([`EvalRequest::ForceAndSecant`]) is the same: a tie has no softening.
//!
//! # Anchored ends
//! An end node that only ties touch must be held by supports in ux uy uz, and the model fixes its
//! rotations ([`crate::model::StructuralModel`]): all six of its equations are fixed, and
//! assembly keeps only the element's diagonal term K_ii on a fixed row. The tie's K_ii is zero for
//! the rotations and the transverse translations, and for everything when slack, which would
//! leave a zero row. On an anchored end ([`Tie::with_anchored_ends`]) the element therefore adds
//! k on each of the node's six diagonal terms, and k u_a to f_int to stay consistent. u_a = 0
//! there, so neither the forces nor the member force change; the value only scales the fixed
//! equation u_a = 0.
//!
//! # Mass and self weight
//! m = ρ A per length. Consistent: m L/6 [2 1; 1 2] for each translation direction (linear shape
//! functions); lumped: m L/2 on each translation. No rotary inertia: the rotations of a tie's
//! nodes are always those of a shell or beam, which carry rotary inertia, or fixed (anchored
//! ends), so the assembled M stays positive definite on the free DOFs. Self weight: m L g / 2 on
//! the translations of each node (no end moments: the tie carries no bending).
//!
//! # State and checkpoint layout
//! Tension only: one value, `state[0]` = 1 when the committed state is slack, 0 when taut. The
//! response does not depend on it (the element is path independent, `evaluate` never reads it);
//! it is there because the tie is nonlinear: a model with state is not treated as linear (the
//! time history's K₀ u shortcut would keep a slack tie taut), and a failed step's diagnosis lists
//! the ties that changed branch. Tension and compression (`tension_only = false`): linear,
//! `n_state() = 0`.
//!
//! # Cell outputs ([`CELL_OUTPUT_NAMES`])
//! `axial_force` = N with the full pretension (tension positive; 0 when slack), `strain` = δ/L.
//! Exact whenever the static load is fully applied (linear statics, the time history's steps, a
//! control stage); during a load stage (λ < 1) the force the tie would carry at full pretension.

use nalgebra::{DMatrix, DVector, Vector3};

use super::error::{check_finite_displacement, check_len, ElementError};
use super::output::{prepare_matrix, prepare_vector, ElementOutput, EvalRequest};
use super::{AppliedLoads, Element, MassKind};

/// Number of DOF of the element.
const N_DOFS: usize = 12;

/// Relative tolerance below which a tie is taken to have zero length (as [`super::LocalFrame`]):
/// L ≤ 1e-10 (1 + max |coordinate|).
const ZERO_LENGTH_RTOL: f64 = 1e-10;

/// Names of the cell quantities: the member force N (tension positive) and the strain δ/L.
pub const CELL_OUTPUT_NAMES: [&str; 2] = ["axial_force", "strain"];

/// Section and material of a tie. SI units.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct TieSection {
    /// Young's modulus E (Pa).
    pub e: f64,
    /// Cross-section area A (m²).
    pub area: f64,
    /// Mass density ρ (kg/m³), ≥ 0.
    pub density: f64,
    /// Pretension N₀ (N), ≥ 0: the initial axial force (lack of fit), tension positive.
    pub pretension: f64,
    /// Whether the tie carries tension only (slack in compression).
    pub tension_only: bool,
}

impl TieSection {
    /// Check E and A (finite, > 0), the density and the pretension (finite, ≥ 0); the error names
    /// the first quantity that is not.
    pub fn validate(&self) -> Result<(), ElementError> {
        for (quantity, value) in [("e", self.e), ("area", self.area)] {
            ElementError::positive(quantity, value)?;
        }
        for (quantity, value) in [("density", self.density), ("pretension", self.pretension)] {
            ElementError::non_negative(quantity, value)?;
        }
        Ok(())
    }
}

/// The unit axis e and the length L of the segment x₁ → x₂.
///
/// Errors: [`ElementError::NonFiniteCoordinates`], [`ElementError::ZeroLength`] (L ≤ 1e-10 (1 +
/// max |coordinate|), as for frames).
pub fn tie_axis(x1: [f64; 3], x2: [f64; 3]) -> Result<(Vector3<f64>, f64), ElementError> {
    for (node, c) in [x1, x2].into_iter().enumerate() {
        if c.iter().any(|x| !x.is_finite()) {
            return Err(ElementError::NonFiniteCoordinates { node, coords: c });
        }
    }
    let (a, b) = (Vector3::from(x1), Vector3::from(x2));
    let length = (b - a).norm();
    if length <= ZERO_LENGTH_RTOL * (1.0 + a.amax().max(b.amax())) {
        return Err(ElementError::ZeroLength { node1: x1, node2: x2, length });
    }
    Ok(((b - a) / length, length))
}

/// The equivalent static load of the pretension `n0` of a tie x₁ → x₂ (module docs):
/// f_pre = N₀ [e, −e], the forces on the two end nodes (global axes), pulling them together.
pub fn pretension_load(x1: [f64; 3], x2: [f64; 3], n0: f64) -> Result<[[f64; 3]; 2], ElementError> {
    let (e, _) = tie_axis(x1, x2)?;
    let f = e * n0;
    Ok([[f.x, f.y, f.z], [-f.x, -f.y, -f.z]])
}

/// A 2-node tie rod (module docs). Path independent; tension-only ties record whether they are
/// slack as their state.
#[derive(Clone, Debug, PartialEq)]
pub struct Tie {
    coords: [[f64; 3]; 2],
    axis: Vector3<f64>,
    length: f64,
    section: TieSection,
    anchored: [bool; 2],
    /// Trial state: slack at the last evaluation.
    slack: bool,
    /// Committed state.
    slack_committed: bool,
}

impl Tie {
    /// A tie from node 1 at `x1` to node 2 at `x2` with `section` (validated here); no end
    /// anchored.
    ///
    /// Errors: [`ElementError::InvalidSection`], [`ElementError::NonFiniteCoordinates`],
    /// [`ElementError::ZeroLength`].
    pub fn new(x1: [f64; 3], x2: [f64; 3], section: TieSection) -> Result<Self, ElementError> {
        section.validate()?;
        let (axis, length) = tie_axis(x1, x2)?;
        Ok(Self { coords: [x1, x2], axis, length, section, anchored: [false; 2], slack: false, slack_committed: false })
    }

    /// The same tie with the ends marked `anchored` (nodes only ties touch; module docs).
    pub fn with_anchored_ends(mut self, anchored: [bool; 2]) -> Self {
        self.anchored = anchored;
        self
    }

    /// Node coordinates the element was built from.
    pub fn coords(&self) -> &[[f64; 3]; 2] {
        &self.coords
    }

    /// The unit axis e (node 1 → node 2).
    pub fn axis(&self) -> Vector3<f64> {
        self.axis
    }

    /// The length L.
    pub fn length(&self) -> f64 {
        self.length
    }

    /// The section.
    pub fn section(&self) -> &TieSection {
        &self.section
    }

    /// Axial stiffness k = E A / L (N/m).
    pub fn axial_stiffness(&self) -> f64 {
        self.section.e * self.section.area / self.length
    }

    /// Elongation δ = e · (u₂ − u₁) of the element displacement `u_e` (12 values, unchecked).
    fn elongation_of(&self, u_e: &[f64]) -> f64 {
        (0..3).map(|d| self.axis[d] * (u_e[6 + d] - u_e[d])).sum()
    }

    /// Elongation δ = e · (u₂ − u₁) (m).
    pub fn elongation(&self, u_e: &[f64]) -> Result<f64, ElementError> {
        check_len("u_e", N_DOFS, u_e.len())?;
        check_finite_displacement(u_e)?;
        Ok(self.elongation_of(u_e))
    }

    /// Whether the tie is slack at elongation `delta`: tension only and N₀ + k δ < 0.
    fn is_slack(&self, delta: f64) -> bool {
        self.section.tension_only && self.section.pretension + self.axial_stiffness() * delta < 0.0
    }

    /// The member force N (tension positive) at elongation `delta`, with the full pretension.
    pub fn axial_force(&self, delta: f64) -> f64 {
        if self.is_slack(delta) {
            0.0
        } else {
            self.section.pretension + self.axial_stiffness() * delta
        }
    }

    /// f_pre = N₀ [e, −e] on the element's 12 DOF (see [`pretension_load`]).
    pub fn pretension_load(&self) -> DVector<f64> {
        let mut f = DVector::zeros(N_DOFS);
        for d in 0..3 {
            f[d] = self.section.pretension * self.axis[d];
            f[6 + d] = -self.section.pretension * self.axis[d];
        }
        f
    }
}

impl Element for Tie {
    fn kind_name(&self) -> &'static str {
        "tie"
    }

    fn n_nodes(&self) -> usize {
        2
    }

    /// f_int = N_e [−e, e] (plus k u_a on anchored ends), K_t as in the module docs.
    fn evaluate(&mut self, u_e: &[f64], request: EvalRequest, out: &mut ElementOutput) -> Result<(), ElementError> {
        let delta = self.elongation(u_e)?;
        out.prepare(N_DOFS);
        let k = self.axial_stiffness();
        let slack = self.is_slack(delta);
        let n_e = if slack { -self.section.pretension } else { k * delta };
        for d in 0..3 {
            out.f_int[d] = -n_e * self.axis[d];
            out.f_int[6 + d] = n_e * self.axis[d];
        }
        for (a, _) in self.anchored.iter().enumerate().filter(|(_, &held)| held) {
            for d in 0..6 {
                out.f_int[6 * a + d] += k * u_e[6 * a + d];
            }
        }
        if request.wants_tangent() {
            out.k_t.fill(0.0);
            if !slack {
                for i in 0..3 {
                    for j in 0..3 {
                        let kij = k * self.axis[i] * self.axis[j];
                        out.k_t[(i, j)] = kij;
                        out.k_t[(6 + i, 6 + j)] = kij;
                        out.k_t[(i, 6 + j)] = -kij;
                        out.k_t[(6 + i, j)] = -kij;
                    }
                }
            }
            for (a, _) in self.anchored.iter().enumerate().filter(|(_, &held)| held) {
                for d in 0..6 {
                    out.k_t[(6 * a + d, 6 * a + d)] += k;
                }
            }
            out.has_tangent = true;
        }
        self.slack = slack;
        Ok(())
    }

    fn commit(&mut self) {
        self.slack_committed = self.slack;
    }

    fn revert(&mut self) {
        self.slack = self.slack_committed;
    }

    fn mass(&self, kind: MassKind, m: &mut DMatrix<f64>) {
        prepare_matrix(m, N_DOFS);
        let total = self.section.density * self.section.area * self.length;
        let (diag, off) = match kind {
            MassKind::Consistent => (total / 3.0, total / 6.0),
            MassKind::Lumped => (total / 2.0, 0.0),
        };
        for d in 0..3 {
            m[(d, d)] = diag;
            m[(6 + d, 6 + d)] = diag;
            m[(d, 6 + d)] = off;
            m[(6 + d, d)] = off;
        }
    }

    fn gravity_load(&self, g: [f64; 3], f: &mut DVector<f64>) {
        prepare_vector(f, N_DOFS);
        let half = 0.5 * self.section.density * self.section.area * self.length;
        for d in 0..3 {
            f[d] = half * g[d];
            f[6 + d] = half * g[d];
        }
    }

    fn cell_output_names(&self) -> &'static [&'static str] {
        &CELL_OUTPUT_NAMES
    }

    fn cell_output(&self, u_e: &[f64], _loads: &AppliedLoads, values: &mut [f64]) -> Result<(), ElementError> {
        check_len("cell output", CELL_OUTPUT_NAMES.len(), values.len())?;
        let delta = self.elongation(u_e)?;
        values[0] = self.axial_force(delta);
        values[1] = delta / self.length;
        Ok(())
    }

    fn n_state(&self) -> usize {
        usize::from(self.section.tension_only)
    }

    fn save_state(&self, out: &mut [f64]) -> Result<(), ElementError> {
        check_len("state", self.n_state(), out.len())?;
        if let Some(s) = out.first_mut() {
            *s = if self.slack_committed { 1.0 } else { 0.0 };
        }
        Ok(())
    }

    fn load_state(&mut self, state: &[f64]) -> Result<(), ElementError> {
        check_len("state", self.n_state(), state.len())?;
        self.slack_committed = state.first().is_some_and(|&s| s > 0.5);
        self.slack = self.slack_committed;
        Ok(())
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use nalgebra::{Cholesky, Rotation3};

    /// A wrought-iron rod of 40 mm × 40 mm (A = 1.6e-3 m²), E = 190 GPa, ρ = 7700 kg/m³.
    fn section(pretension: f64, tension_only: bool) -> TieSection {
        TieSection { e: 190.0e9, area: 1.6e-3, density: 7700.0, pretension, tension_only }
    }

    /// Axis-aligned and oblique ties.
    fn ties(s: TieSection) -> Vec<Tie> {
        [
            ([0.0, 0.0, 0.0], [8.0, 0.0, 0.0]),
            ([1.0, 2.0, 7.5], [1.0, 12.4, 7.5]),
            ([0.3, -1.2, 2.0], [4.1, 3.3, 9.7]),
            ([5.0, 5.4, 7.5], [-2.0, 1.1, 6.0]),
        ]
        .into_iter()
        .map(|(a, b)| Tie::new(a, b, s).unwrap())
        .collect()
    }

    /// A displacement field with all 12 components non-zero, scaled by `scale`.
    fn some_u(scale: f64) -> Vec<f64> {
        (0..12).map(|i| scale * ((i as f64) * 0.7 + 0.3).sin()).collect()
    }

    fn rel_err(a: f64, b: f64) -> f64 {
        (a - b).abs() / b.abs()
    }

    /// K_t against central differences of f_int, column by column, on both branches (taut and
    /// slack, each away from the switch: ±1 cm along the axis, k δ ≥ 2.5e5 N beyond N₀ = 5e4 N)
    /// and with an anchored end: |K − K_fd| ≤ 1e-6 k (f_int is piecewise linear, so central
    /// differences within a branch are exact up to round-off ~1e-16 ‖f‖/h, h = 1e-7 m).
    #[test]
    fn tangent_matches_central_differences() {
        let h = 1e-7;
        for (s, anchored) in [
            (section(0.0, true), [false; 2]),
            (section(5.0e4, true), [false, true]),
            (section(5.0e4, false), [true, false]),
        ] {
            for tie in ties(s) {
                let mut tie = tie.with_anchored_ends(anchored);
                let k = tie.axial_stiffness();
                for sign in [1.0, -1.0] {
                    // Stretch (taut) or shorten far beyond the pretension (slack if tension only).
                    let mut u = some_u(1e-5);
                    for d in 0..3 {
                        u[6 + d] += sign * 1e-2 * tie.axis()[d];
                    }
                    let mut out = ElementOutput::new(12);
                    tie.evaluate(&u, EvalRequest::ForceAndTangent, &mut out).unwrap();
                    assert!(out.has_tangent);
                    let kt = out.k_t.clone();
                    let mut fd = DMatrix::zeros(12, 12);
                    for j in 0..12 {
                        let (mut up, mut um) = (u.clone(), u.clone());
                        up[j] += h;
                        um[j] -= h;
                        tie.evaluate(&up, EvalRequest::Force, &mut out).unwrap();
                        let fp = out.f_int.clone();
                        tie.evaluate(&um, EvalRequest::Force, &mut out).unwrap();
                        fd.set_column(j, &((fp - &out.f_int) / (2.0 * h)));
                    }
                    let err = (&kt - &fd).amax();
                    assert!(err <= 1e-6 * k, "sign {sign}, {:?}: |K − K_fd| = {err:e} vs k = {k:e}", tie.coords());
                    // The branch: K₁₂ = −k e eᵀ when taut, 0 when slack (no anchor terms there).
                    let slack = s.tension_only && sign < 0.0;
                    let want = if slack { 0.0 } else { k * tie.axis().amax().powi(2) };
                    let coupling = kt.view((0, 6), (3, 3)).amax();
                    assert!((coupling - want).abs() <= 1e-12 * k, "branch of K: {coupling:e} vs {want:e}");
                }
            }
        }
    }

    /// Rigid motions: a translation plus a linearized rotation u = c + θ × x gives δ = 0 to
    /// round-off (|δ| ≤ 1e-15 L θ-scale), so f_int = 0 and N = N₀; a finite rotation by angle t
    /// (Rodrigues) gives δ = O(t²): |δ| ≤ L t² (δ = L (cos t − 1) for a rotation about an axis
    /// normal to the tie), i.e. zero to first order.
    #[test]
    fn rigid_motions_do_not_stretch_the_tie() {
        let n0 = 2.0e4;
        for mut tie in ties(section(n0, true)) {
            let c = Vector3::new(1e-3, -2e-3, 5e-4);
            let theta = Vector3::new(3e-4, -1e-4, 2e-4);
            let mut u = vec![0.0; 12];
            for (a, x) in tie.coords().iter().enumerate() {
                let t = c + theta.cross(&Vector3::from(*x));
                u[6 * a..6 * a + 3].copy_from_slice(t.as_slice());
                u[6 * a + 3..6 * a + 6].copy_from_slice(theta.as_slice());
            }
            let l = tie.length();
            let delta = tie.elongation(&u).unwrap();
            assert!(delta.abs() <= 1e-15 * l.max(1.0) * 10.0, "linearized rotation: δ = {delta:e}");
            let mut out = ElementOutput::new(12);
            tie.evaluate(&u, EvalRequest::Force, &mut out).unwrap();
            assert!(out.f_int.amax() <= 1e-9 * tie.axial_stiffness() * 1e-3, "f_int = {}", out.f_int.amax());
            let mut vals = [0.0; 2];
            tie.cell_output(&u, &AppliedLoads::default(), &mut vals).unwrap();
            assert!((vals[0] - n0).abs() <= 1e-9 * n0, "N = {} vs N0 = {n0}", vals[0]);
            for t in [1e-2, 1e-3, 1e-4] {
                let rot = Rotation3::from_scaled_axis(Vector3::new(0.3, -0.8, 0.52).normalize() * t);
                let x0 = Vector3::from(tie.coords()[0]);
                let mut u = vec![0.0; 12];
                for (a, x) in tie.coords().iter().enumerate() {
                    let x = Vector3::from(*x);
                    let d = rot * (x - x0) - (x - x0);
                    u[6 * a..6 * a + 3].copy_from_slice(d.as_slice());
                }
                let delta = tie.elongation(&u).unwrap();
                assert!(delta.abs() <= l * t * t, "finite rotation {t}: δ = {delta:e}, L t² = {:e}", l * t * t);
            }
        }
    }

    /// Tension only: shortened beyond the pretension the tie is slack — N = 0 (cell output),
    /// K_t = 0, f_int = N₀ [e, −e] = f_pre so that f_pre − f_int = 0 (the tie exerts nothing),
    /// exact; the state records the branch through commit/revert. Without `tension_only` the same
    /// shortening gives N = N₀ + k δ < 0, exact to 1e-12 relative.
    #[test]
    fn tension_only_tie_goes_slack_in_compression() {
        let n0 = 1.0e4;
        for tie in ties(section(n0, true)) {
            let mut tie = tie;
            let k = tie.axial_stiffness();
            // δ = −2 N₀ / k: N₀ + k δ = −N₀ < 0.
            let mut u = vec![0.0; 12];
            for d in 0..3 {
                u[d] = n0 / k * tie.axis()[d];
                u[6 + d] = -n0 / k * tie.axis()[d];
            }
            assert!(rel_err(tie.elongation(&u).unwrap(), -2.0 * n0 / k) < 1e-12);
            let mut out = ElementOutput::new(12);
            tie.evaluate(&u, EvalRequest::ForceAndTangent, &mut out).unwrap();
            assert_eq!(out.k_t.amax(), 0.0, "slack: no stiffness");
            let residual = tie.pretension_load() - &out.f_int;
            assert!(residual.amax() <= 1e-12 * n0, "slack: f_pre − f_int = {}", residual.amax());
            let mut vals = [0.0; 2];
            tie.cell_output(&u, &AppliedLoads::default(), &mut vals).unwrap();
            assert_eq!(vals[0], 0.0);
            assert!(rel_err(vals[1], -2.0 * n0 / k / tie.length()) < 1e-12, "strain {}", vals[1]);
            // State: slack in the trial, committed on commit, forgotten on revert.
            assert_eq!(tie.n_state(), 1);
            let mut s = [9.0];
            tie.save_state(&mut s).unwrap();
            assert_eq!(s, [0.0], "committed: taut");
            tie.commit();
            tie.save_state(&mut s).unwrap();
            assert_eq!(s, [1.0], "committed: slack");
            tie.evaluate(&[0.0; 12], EvalRequest::Force, &mut out).unwrap();
            tie.revert();
            tie.commit();
            tie.save_state(&mut s).unwrap();
            assert_eq!(s, [1.0], "revert restores the committed branch");
            tie.load_state(&[0.0]).unwrap();
            tie.save_state(&mut s).unwrap();
            assert_eq!(s, [0.0]);
            // Exactly at N = 0 (no pretension, u = 0): the taut branch.
            let mut at_zero = Tie::new(tie.coords()[0], tie.coords()[1], section(0.0, true)).unwrap();
            at_zero.evaluate(&[0.0; 12], EvalRequest::ForceAndTangent, &mut out).unwrap();
            assert!(out.k_t.amax() > 0.0, "taut at N = 0");
        }
        let mut both = ties(section(n0, false)).remove(2);
        let k = both.axial_stiffness();
        let u: Vec<f64> =
            (0..12).map(|i| if (6..9).contains(&i) { -2.0 * n0 / k * both.axis()[i - 6] } else { 0.0 }).collect();
        let mut vals = [0.0; 2];
        both.cell_output(&u, &AppliedLoads::default(), &mut vals).unwrap();
        assert!(rel_err(vals[0], -n0) < 1e-12, "N = {}", vals[0]);
        let mut out = ElementOutput::new(12);
        both.evaluate(&u, EvalRequest::ForceAndTangent, &mut out).unwrap();
        assert!(out.k_t.amax() > 0.0);
        assert_eq!(both.n_state(), 0);
        assert!(both.load_state(&[1.0]).is_err());
    }

    /// Pretension: f_pre = N₀ [e, −e] (pulls the ends together: the force on node 1 points to
    /// node 2), sums to zero force and zero moment (collinear); at u = 0 f_int = 0 and N = N₀.
    /// A stretch δ gives N = N₀ + EA δ / L and f_int = EA δ / L [−e, e]. 1e-12 relative.
    #[test]
    fn pretension_load_and_member_force() {
        let n0 = 3.5e4;
        for mut tie in ties(section(n0, true)) {
            let e = tie.axis();
            let [x1, x2] = *tie.coords();
            let f = pretension_load(x1, x2, n0).unwrap();
            let (f1, f2) = (Vector3::from(f[0]), Vector3::from(f[1]));
            assert!((f1 - e * n0).amax() <= 1e-12 * n0, "towards node 2");
            assert!((f1 + f2).amax() <= 1e-12 * n0, "no net force");
            let moment = Vector3::from(x1).cross(&f1) + Vector3::from(x2).cross(&f2);
            assert!(moment.amax() <= 1e-11 * n0 * 10.0, "no net moment: {moment:?}");
            let fe = tie.pretension_load();
            assert!((fe.fixed_rows::<3>(0) - f1).amax() == 0.0 && (fe.fixed_rows::<3>(6) - f2).amax() == 0.0);
            let mut out = ElementOutput::new(12);
            tie.evaluate(&[0.0; 12], EvalRequest::Force, &mut out).unwrap();
            assert_eq!(out.f_int.amax(), 0.0, "at rest at u = 0");
            let mut vals = [0.0; 2];
            tie.cell_output(&[0.0; 12], &AppliedLoads::default(), &mut vals).unwrap();
            assert_eq!(vals, [n0, 0.0]);
            let delta = 2.0e-4;
            let mut u = vec![0.0; 12];
            for d in 0..3 {
                u[6 + d] = delta * e[d];
            }
            let k = tie.axial_stiffness();
            tie.cell_output(&u, &AppliedLoads::default(), &mut vals).unwrap();
            assert!(rel_err(vals[0], n0 + k * delta) < 1e-12, "N = {}", vals[0]);
            assert!(rel_err(vals[1], delta / tie.length()) < 1e-12);
            tie.evaluate(&u, EvalRequest::Force, &mut out).unwrap();
            assert!((out.f_int.fixed_rows::<3>(6) - e * (k * delta)).amax() <= 1e-12 * k * delta);
            assert!((out.f_int.fixed_rows::<3>(0) + e * (k * delta)).amax() <= 1e-12 * k * delta);
            assert_eq!(out.f_int.fixed_rows::<3>(3).amax() + out.f_int.fixed_rows::<3>(9).amax(), 0.0, "no moments");
        }
    }

    /// Mass: a rigid translation r along each axis gives rᵀ M r = ρ A L (consistent and lumped,
    /// 1e-12 relative); no rotary inertia (the rotation rows are zero); the translational 6×6 block
    /// is positive definite. Self weight ρ A L g / 2 per node, 1e-12 relative.
    #[test]
    fn mass_and_self_weight() {
        let s = section(0.0, true);
        for tie in ties(s) {
            let total = s.density * s.area * tie.length();
            for kind in [MassKind::Consistent, MassKind::Lumped] {
                let mut m = DMatrix::zeros(0, 0);
                tie.mass(kind, &mut m);
                assert_eq!(m.shape(), (12, 12));
                for d in 0..3 {
                    let mut r = DVector::zeros(12);
                    r[d] = 1.0;
                    r[6 + d] = 1.0;
                    assert!(rel_err((r.transpose() * &m * &r)[0], total) < 1e-12, "{kind:?}");
                }
                for i in [3, 4, 5, 9, 10, 11] {
                    assert_eq!(m.row(i).amax() + m.column(i).amax(), 0.0, "no rotary inertia");
                }
                let t = DMatrix::from_fn(6, 6, |i, j| m[(i + 3 * (i / 3), j + 3 * (j / 3))]);
                assert!(Cholesky::new(t).is_some(), "{kind:?}: translational mass not positive definite");
            }
            let g = [0.3, -1.2, -9.81];
            let mut f = DVector::zeros(0);
            tie.gravity_load(g, &mut f);
            for d in 0..3 {
                assert!((f[d] - total * g[d] / 2.0).abs() <= 1e-12 * total * 9.81);
                assert!((f[6 + d] - total * g[d] / 2.0).abs() <= 1e-12 * total * 9.81);
            }
            assert_eq!(f.fixed_rows::<3>(3).amax() + f.fixed_rows::<3>(9).amax(), 0.0);
        }
    }

    /// An anchored end: k on each of its six diagonal terms (fixed equations keep a non-zero
    /// diagonal even when the tie is slack); the other end and the member force unchanged.
    #[test]
    fn anchored_end_keeps_its_diagonal() {
        let mut tie = ties(section(1.0e4, true)).remove(0).with_anchored_ends([false, true]);
        let k = tie.axial_stiffness();
        let mut out = ElementOutput::new(12);
        let mut u = vec![0.0; 12];
        u[0] = 1e-2; // node 1 pushed towards node 2 along x: slack
        tie.evaluate(&u, EvalRequest::ForceAndTangent, &mut out).unwrap();
        for i in 0..12 {
            let want = if i >= 6 { k } else { 0.0 };
            assert_eq!(out.k_t[(i, i)], want, "K[{i},{i}]");
        }
        let mut vals = [0.0; 2];
        tie.cell_output(&u, &AppliedLoads::default(), &mut vals).unwrap();
        assert_eq!(vals[0], 0.0);
    }

    #[test]
    fn bad_input_is_an_error_not_a_panic() {
        let e = Tie::new([1.0; 3], [1.0; 3], section(0.0, true)).unwrap_err();
        assert!(matches!(e, ElementError::ZeroLength { .. }), "{e}");
        let e = Tie::new([0.0; 3], [1.0, 0.0, f64::NAN], section(0.0, true)).unwrap_err();
        assert!(matches!(e, ElementError::NonFiniteCoordinates { node: 1, .. }), "{e}");
        for (name, s) in [
            ("area", TieSection { area: 0.0, ..section(0.0, true) }),
            ("area", TieSection { area: -1.6e-3, ..section(0.0, true) }),
            ("e", TieSection { e: f64::NAN, ..section(0.0, true) }),
            ("pretension", section(-1.0, true)),
            ("density", TieSection { density: -1.0, ..section(0.0, true) }),
        ] {
            match Tie::new([0.0; 3], [1.0, 0.0, 0.0], s) {
                Err(ElementError::InvalidSection { quantity, .. }) => assert_eq!(quantity, name),
                other => panic!("{name}: {other:?}"),
            }
        }
        let mut tie = ties(section(0.0, true)).remove(1);
        let mut out = ElementOutput::new(12);
        assert!(matches!(
            tie.evaluate(&[0.0; 11], EvalRequest::Force, &mut out),
            Err(ElementError::WrongLength { what: "u_e", expected: 12, got: 11 })
        ));
        let mut u = [0.0; 12];
        u[8] = f64::INFINITY;
        assert!(matches!(
            tie.evaluate(&u, EvalRequest::Force, &mut out),
            Err(ElementError::NonFiniteDisplacement { index: 8, .. })
        ));
        assert!(tie.cell_output(&[0.0; 12], &AppliedLoads::default(), &mut [0.0; 3]).is_err());
        assert_eq!(tie.kind_name(), "tie");
        assert_eq!(tie.n_dofs(), 12);
    }
}
