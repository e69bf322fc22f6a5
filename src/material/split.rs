//! [`Split`]: how the free energy is shared between the tensile and the compressive damage, the
//! unilateral effect of the law.
//!
//! # The two splits
//! ```text
//!   trace     ψ = [(1 − d_t) H(tr σ̃) + (1 − d_c) H(−tr σ̃)] ½ ε:C₀:ε          (the paper's, eq. 6)
//!   spectral  ψ = (1 − d_t) ψ₀⁺(ε) + (1 − d_c) ψ₀⁻(ε),
//!             ψ₀±(ε) = λ/2 ⟨tr ε⟩±² + μ Σ_i ⟨ε_i⟩±²                            (Miehe et al. 2010)
//! ```
//! (⟨x⟩₊ = max(x, 0), ⟨x⟩₋ = min(x, 0), ε_i the principal strains). Both keep the damage criteria
//! of the paper: the equivalent strains, the histories κ_t, κ_c, the softening laws and the
//! Hillerborg regularization are the same; only the stress and the energy released by damage
//! (Y_t, Y_c) differ.
//!
//! # Why a second split
//! The paper's split switches the whole stiffness when tr σ̃ changes sign. Where d_t ≠ d_c the free
//! energy jumps there by ±(d_t − d_c) ½ ε:C₀:ε with no work done: a crack that closes under shear
//! gains energy from nothing. Plane-stress layers smooth the switch over a band of stress
//! directions, which makes the stress continuous but not the derivative of any potential, so a
//! closed strain cycle still does net work. In the church's time history this is the "unilateral"
//! column of the energy balance, a quarter of the ground's input.
//!
//! The spectral split derives the stress from a potential that is C¹ in the strain
//! (⟨x⟩±² and Σ⟨ε_i⟩±² are C¹): σ = ∂ψ/∂ε is continuous, a closed strain cycle without damage
//! growth does no work, and since ψ is homogeneous of degree 2 in ε, ψ = ½ σ:ε still holds, so the
//! strain energy ½ uᵀ f_int of the energy balance keeps its meaning.
//!
//! # Why this one among the continuous splits
//! * **Volumetric–deviatoric** (Amor, Marigo and Maurini, JMPS 57, 2009): ψ₀⁺ = K/2 ⟨tr ε⟩₊² +
//!   μ dev ε : dev ε. The shear stiffness is degraded by d_t even under compression, so a closed
//!   crack keeps no shear and, as d_t → 1, no uniaxial compressive stiffness either (E → 9Kμ'/(3K +
//!   μ') with μ' → 0). Masonry whose joints have closed carries compression: rejected.
//! * **Effective-stress spectral split** (Faria, Oliver and Cervera, IJSS 35, 1998; Wu, Li and Faria,
//!   IJSS 43, 2006): σ = (1 − d⁺) σ̃⁺ + (1 − d⁻) σ̃⁻. Its secant (1 − d⁺) P⁺C₀ + (1 − d⁻) P⁻C₀ is
//!   not symmetric for ν ≠ 0 (P± the projections on the positive and negative principal
//!   stresses), so the stress is not the gradient of a potential and closed cycles do work: it
//!   cannot pass the energy test this split exists for.
//! * **Spectral strain split** (Miehe, Welschinger and Hofacker, IJNME 83, 2010): a potential; after
//!   a tensile crack, a uniaxial compression closes it with E/(1 + ν) of the stiffness at least
//!   (all of it while d_t < 1 keeps the lateral extension resisted), and a closed diagonal crack
//!   keeps the shear of its compressive strut. Chosen.
//!
//! # Crack-band regularization under the spectral split
//! B_t follows from G_f by the same Hillerborg formulas, which integrate the paper's uniaxial
//! curve σ = (1 − d_t) E ε. Under the spectral split the lateral contraction of a bar in tension
//! keeps its energy undamaged, so at the same d_t its stress lies between (1 − d_t) E ε and
//! (1 − d_t)(λ + 2μ) ε, and the energy to failure per crack area exceeds G_f by a factor that
//! depends on B_t ε₀^t, hence on h. For the law of materials/rubble-identified-spectral.toml
//! (`hillerborg_no_elastic`, G_f 17.5 J/m², ν 0.188), integrated numerically along uniaxial
//! tension: +6.8 % at h = 0.2 m, +5.2 % at 0.5 m, +4.0 % at 0.85 m, +3.0 % at the
//! identification's 1.2 m, +1.4 % at 2.0 m. The identification fits the curve at its own h, so
//! the wall's energy is the DEM's; an element between 0.2 and 2.0 m dissipates −1.6 % to +3.7 %
//! of it per crack area. (`spectral_tests.rs` checks the bound λ + 2μ on the reference law.)
//!
//! # In the kinematics of the law
//! * 3D: the principal strains of ε; the tangent needs the derivative of ε₊ (spectral.rs).
//! * Plane stress (shell layers): ε_zz is a principal strain, found from σ_zz = ∂ψ/∂ε_zz = 0, which
//!   is piecewise linear and increasing in ε_zz (one root, in closed form). With damage this ε_zz
//!   differs from the elastic −ν/(1 − ν)(ε_xx + ε_yy); the damage criteria keep the elastic one
//!   (the choice of [`EZZ_ENTERS_EQUIVALENT_STRAIN`](super::plane_stress::EZZ_ENTERS_EQUIVALENT_STRAIN)
//!   is made on it), so the criteria remain a function of the in-plane strain alone and the
//!   identification's paths keep their meaning. The reduced potential min over ε_zz of ψ is again
//!   C¹ and homogeneous of degree 2.
//! * Uniaxial stress (fibers): the two lateral principal strains, equal, found from σ₂₂ = 0 in the
//!   same way.

use serde::{Deserialize, Serialize};

/// The unilateral split of the free energy (module docs).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash, Serialize, Deserialize, schemars::JsonSchema)]
#[serde(rename_all = "snake_case")]
pub enum Split {
    /// The paper's split on the sign of tr σ̃ (smoothed over a band of stress directions in plane
    /// stress): not derived from a potential, so crack closure exchanges energy with no work.
    #[default]
    Trace,
    /// The spectral strain split of Miehe et al. (2010): the stress derives from a C¹ potential.
    Spectral,
}

impl Split {
    /// The job-file name of the variant.
    pub fn name(&self) -> &'static str {
        match self {
            Split::Trace => "trace",
            Split::Spectral => "spectral",
        }
    }

    /// Whether this is the paper's split (the default, left out when a material file is written).
    pub fn is_trace(&self) -> bool {
        *self == Split::Trace
    }
}
