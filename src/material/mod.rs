//! The continuum masonry damage law: isotropic damage with separate tension and compression
//! variables and the unilateral effect (paper §3.1; paper eqs. 6–14 in consistent form).
//!
//! **Cycles.** The law's files are one concept, the damage law at a point, split by what a
//! reader looks for: [`PointLaw`] (`law.rs`) is built from the parameters of `params.rs` and
//! reads the damage sides of `state.rs`, whose evolution in `state.rs`, `response.rs` and
//! `plane_stress.rs` is computed with the point's law; `plane_stress.rs` and `uniaxial.rs` hand
//! the spectral split to `spectral.rs`, which returns their response types.
//!
//! | file              | concept                                                                  |
//! |-------------------|--------------------------------------------------------------------------|
//! | `params.rs`       | [`DamageParams`], [`Regularization`]: input, validation, B_t(h)          |
//! | `law.rs`          | [`PointLaw`]: the law of one element (B_t fixed), damage and dissipation |
//! | `error.rs`        | [`MaterialError`]                                                        |
//! | `damage.rs`       | scalar laws d_t(κ), d_c(κ), slopes, dissipation primitives              |
//! | `state.rs`        | [`DamageState`], [`Side`], the history update                            |
//! | `principal.rs`    | principal strains, ε_eq = sqrt(Σ⟨ε_i⟩₊²) and its gradient               |
//! | `response.rs`     | [`Response`], stress / secant / consistent tangent, [`StressState`]      |
//! | `split.rs`        | [`Split`]: the paper's split on tr σ̃ or the spectral split, and why      |
//! | `spectral.rs`     | the spectral split's stress, tangents and energies in every kinematics   |
//! | `plane_stress.rs` | shell layers: (ε_xx, ε_yy, γ_xy), ε_zz from σ_zz = 0                    |
//! | `nonlocal.rs`     | shell layers with averaged damage-driving strains (nonlocal integral)    |
//! | `uniaxial.rs`     | beam fibers: ε_11, lateral strains −ν ε in ε_eq                          |
//! | `three_d.rs`      | general 3D, Voigt `[xx, yy, zz, yz, xz, xy]`                             |
//! | `implex.rs`       | IMPL-EX: the step's stress from the extrapolated history (any kinematics)|
//! | `path.rs`         | material-point driver under mixed strain/stress control                  |
//!
//! # The law
//! ```text
//!   σ̃ = C₀ : ε                                            (isotropic E, ν)
//!   σ  = [ (1 − d_t) H(tr σ̃) + (1 − d_c) H(−tr σ̃) ] C₀ : ε   (H(0) = 1 on the tension side)
//!   ε_eq = sqrt( Σ_i ⟨ε_i⟩₊² )  over the principal strains of ε; it drives κ_t if tr σ̃ ≥ 0,
//!                                κ_c if tr σ̃ < 0 (ε^t = H(tr σ̃) ε, ε^c = H(−tr σ̃) ε)
//!   κ_k = max(ε₀^k, max over time ε_eq^k)
//!   d_t = 1 − (ε₀^t/κ_t) exp[−B_t (κ_t − ε₀^t)]
//!   d_c = 1 − (1 − A_c) ε₀^c/κ_c − A_c exp[−B_c (κ_c − ε₀^c)]
//! ```
//! B_t is regularized by the element size (Hillerborg, [`params`] docs); B_c is not.
//!
//! # Dissipation
//! Each update returns the energy per volume dissipated since the committed state,
//! Δφ = c [F(κ_new) − F(κ_old)] with c = Y/ε_eq², Y = ½ ε:C₀:ε of the active side and
//! F(κ) = ∫ κ² d'(κ) dκ in closed form ([`damage`] docs). It is the exact integral of
//! Y ḋ along a radial strain increment (Clausius–Duhem: Y ≥ 0, ḋ ≥ 0, so Δφ ≥ 0), hence exact for
//! any step size under monotonic uniaxial loading: a monotonic tension to failure dissipates
//! exactly [`PointLaw::tensile_failure_energy_density`] = f_t²/(2E) + f_t/B_t, i.e. G_f/h +
//! f_t²/(2E) with `hillerborg` and G_f/h with `hillerborg_no_elastic`. Callers sum Δφ over
//! converged steps.
//!
//! # Use
//! ```
//! use masonry_hpc::material::{plane_stress, DamageParams, DamageState, Regularization, Split};
//! use nalgebra::Vector3;
//! let params = DamageParams { e: 3.0e9, nu: 0.2, eps0_t: 1e-4, eps0_c: 2e-4, gf_t: 50.0,
//!     a_c: 0.8, b_c: 1000.0, gf_c: None, regularization: Regularization::Hillerborg, split: Split::Trace };
//! let law = params.for_element(0.1).unwrap();          // once per element
//! let committed = DamageState::default();                // per integration point
//! let r = plane_stress::update(&law, &Vector3::new(2e-4, 0.0, 0.0), &committed);
//! assert!(r.state.d_t > 0.0 && r.state.d_c == 0.0 && r.dissipation > 0.0);
//! // converged: committed = r.state; dissipated += r.dissipation
//! ```

pub mod damage;
pub mod error;
pub mod implex;
pub mod law;
pub mod nonlocal;
pub mod params;
pub mod path;
pub mod plane_stress;
pub mod principal;
pub mod response;
pub mod spectral;
pub mod split;
pub mod state;
pub mod three_d;
pub mod uniaxial;

#[cfg(test)]
mod bar_tests;
#[cfg(test)]
pub(crate) mod test_support;

pub use error::MaterialError;
pub use law::PointLaw;
pub use params::{DamageParams, Regularization};
pub use path::{run_path, run_path_into, Control, LoadPath, NewtonSettings, PathError, PathRecord};
pub use plane_stress::PlaneStress;
pub use response::{Response, StressState};
pub use split::Split;
pub use state::{DamageState, Side};
pub use three_d::ThreeD;
pub use uniaxial::{Uniaxial, UniaxialResponse};
