//! [`Response`]: what one strain update at a material point returns, and the assembly of the
//! stress, the secant and the consistent tangent shared by every kinematics.
//!
//! # Stress and tangents
//! With s = 1 − d of the active side (the [`Side`] of tr σ̃):
//!
//! ```text
//!   σ      = s C₀ ε
//!   secant = s C₀
//!   tangent = s C₀ − (C₀ ε) ⊗ d'(κ) ∂ε_eq/∂ε     while loading (ε_eq > committed κ)
//!           = s C₀                               otherwise (elastic unloading/reloading)
//! ```
//! The tangent is the exact derivative of the algorithmic stress (the update is explicit in the
//! strain, so it is also the consistent tangent). It is not symmetric while loading.
//!
//! # At tr σ̃ = 0
//! The factor s jumps from 1 − d_t to 1 − d_c when tr σ̃ changes sign, so if d_t ≠ d_c and σ̃ ≠ 0
//! there (any deviatoric strain) the stress itself is discontinuous: no tangent describes the jump.
//! The derivative of the Heaviside factor (a Dirac at tr σ̃ = 0) is left out, so secant and tangent
//! are the one-sided ones of the side selected by [`Side::of_trace`] (tension at tr σ̃ = 0 exactly).
//! A global Newton crossing the jump sees a residual the tangent did not predict; it converges
//! through it as a fixed-point on the new side (line search or a secant iteration help). In
//! uniaxial stress tr σ̃ = 0 only at ε = 0, where σ̃ = 0: no jump for fibers.

use nalgebra::{SMatrix, SVector};

use super::law::PointLaw;
use super::state::{DamageState, Evolution, Side};

/// The result of one update of a material point with `N` strain components.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Response<const N: usize> {
    /// Stress σ (Pa), same component order as the strain.
    pub stress: SVector<f64, N>,
    /// Secant stiffness (1 − d) C₀ of the active side (Pa).
    pub secant: SMatrix<f64, N, N>,
    /// Consistent tangent ∂σ/∂ε (Pa), module docs.
    pub tangent: SMatrix<f64, N, N>,
    /// The trial history (commit it when the global step converges).
    pub state: DamageState,
    /// Energy per volume dissipated from the committed to the trial state (J/m³), ≥ 0; the
    /// caller sums these over converged steps.
    pub dissipation: f64,
    /// The active side of the unilateral split.
    pub side: Side,
    /// Whether the active damage grew in this update.
    pub loading: bool,
}

/// Assemble the response from the elastic matrix `c0`, the strain, the history evolution and the
/// gradient ∂ε_eq/∂ε (used only while loading).
#[inline]
pub(super) fn assemble<const N: usize>(
    c0: &SMatrix<f64, N, N>,
    sigma_tilde: &SVector<f64, N>,
    side: Side,
    evo: Evolution,
    grad_eq: &SVector<f64, N>,
) -> Response<N> {
    let s = evo.integrity;
    let secant = c0 * s;
    let stress = sigma_tilde * s;
    let tangent = if evo.loading { secant - sigma_tilde * (grad_eq * evo.dd_deq).transpose() } else { secant };
    Response { stress, secant, tangent, state: evo.state, dissipation: evo.dissipation, side, loading: evo.loading }
}

/// A stress state (kinematics) of the law with `N` strain components, so that drivers such as
/// [`run_path`](super::run_path) are written once for fibers, shell layers and 3D points.
pub trait StressState<const N: usize> {
    /// Names of the strain components, in order (`"xx"`, `"yy"`, `"xy"`, ...).
    const COMPONENTS: [&'static str; N];
    /// Index of the in-plane shear γ_xy, if the kinematics has one.
    const SHEAR_XY: Option<usize>;
    /// The update at strain `strain` from the committed history.
    fn evaluate(law: &PointLaw, strain: &SVector<f64, N>, committed: &DamageState) -> Response<N>;
}
