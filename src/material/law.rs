//! [`PointLaw`]: the damage law of one element, ready to evaluate at its material points.

use super::damage::{self, CompressionSoftening, DamageValue};
use super::params::{DamageParams, Regularization};
use super::split::Split;
use super::state::Side;

/// The damage law with B_t (and B_c) fixed for one element size and the isotropic elastic constants
/// precomputed. Built only by [`DamageParams::for_element`], so its values are always valid.
/// `Copy` and small: an element keeps one per integration point group, or one per element.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct PointLaw {
    e: f64,
    nu: f64,
    lambda: f64,
    mu: f64,
    eps0_t: f64,
    eps0_c: f64,
    b_t: f64,
    a_c: f64,
    b_c: f64,
    softening_c: Option<CompressionSoftening>,
    h: f64,
    regularization: Regularization,
    relaxation: f64,
    split: Split,
}

impl PointLaw {
    /// Assemble from validated parameters (crate-internal: use [`DamageParams::for_element`]).
    pub(super) fn new(p: &DamageParams, h: f64, b_t: f64, b_s: Option<f64>) -> Self {
        let lambda = p.e * p.nu / ((1.0 + p.nu) * (1.0 - 2.0 * p.nu));
        let mu = p.e / (2.0 * (1.0 + p.nu));
        PointLaw {
            e: p.e,
            nu: p.nu,
            lambda,
            mu,
            eps0_t: p.eps0_t,
            eps0_c: p.eps0_c,
            b_t,
            a_c: p.a_c,
            b_c: p.b_c,
            softening_c: b_s.map(|b_s| CompressionSoftening::new(p.eps0_c, p.b_c, b_s)),
            h,
            regularization: p.regularization,
            relaxation: f64::INFINITY,
            split: p.split,
        }
    }

    /// The law with the viscous (Duvaut–Lions) regularization of the damage histories for one
    /// increment of (pseudo-)time `dt` and the relaxation time `tau` (same unit): the ratio
    /// r = Δt/τ used when the histories evolve (the `material::state` module docs). With
    /// `tau = None` (the default of every law) the law is rate independent (r = ∞).
    pub fn with_relaxation(mut self, dt: f64, tau: Option<f64>) -> Self {
        self.relaxation = match tau {
            Some(tau) if tau > 0.0 && dt.is_finite() && dt >= 0.0 => dt / tau,
            _ => f64::INFINITY,
        };
        self
    }

    /// The law with the damage histories frozen at the state it is evaluated from: r = 0, the
    /// τ → ∞ limit of the viscous update (`material::state` docs), so κ = κ_committed exactly,
    /// the damage terms of the tangent vanish (∂κ/∂ε_eq = 0) and nothing is dissipated. The
    /// stress is then the law's response at fixed damage, and the tangent its exact derivative.
    /// IMPL-EX ([`super::implex`]) evaluates the stress of a step this way, from the extrapolated
    /// history.
    pub fn with_frozen_history(mut self) -> Self {
        self.relaxation = 0.0;
        self
    }

    /// r = Δt/τ of the viscous regularization (∞: rate independent, the default; 0: frozen).
    pub fn relaxation(&self) -> f64 {
        self.relaxation
    }

    /// The unilateral split of the free energy.
    #[inline]
    pub fn split(&self) -> Split {
        self.split
    }

    /// Young modulus E (Pa).
    pub fn e(&self) -> f64 {
        self.e
    }
    /// Poisson ratio ν.
    pub fn nu(&self) -> f64 {
        self.nu
    }
    /// Lamé's first parameter λ = E ν / ((1 + ν)(1 − 2ν)) (Pa).
    pub fn lambda(&self) -> f64 {
        self.lambda
    }
    /// Shear modulus μ = E / (2(1 + ν)) (Pa).
    pub fn mu(&self) -> f64 {
        self.mu
    }
    /// Tensile threshold ε₀^t.
    pub fn eps0_t(&self) -> f64 {
        self.eps0_t
    }
    /// Compressive threshold ε₀^c.
    pub fn eps0_c(&self) -> f64 {
        self.eps0_c
    }
    /// Tensile softening parameter B_t for this element (1/strain).
    pub fn b_t(&self) -> f64 {
        self.b_t
    }
    /// Compressive shape parameter A_c.
    pub fn a_c(&self) -> f64 {
        self.a_c
    }
    /// Compressive shape parameter B_c (1/strain).
    pub fn b_c(&self) -> f64 {
        self.b_c
    }
    /// The regularized compressive softening of this element (`gf_c` given), else `None`.
    pub fn compression_softening(&self) -> Option<CompressionSoftening> {
        self.softening_c
    }
    /// The element characteristic length h this law was built for (m).
    pub fn element_size(&self) -> f64 {
        self.h
    }
    /// The regularization B_t came from.
    pub fn regularization(&self) -> Regularization {
        self.regularization
    }
    /// Tensile strength f_t = E ε₀^t (Pa).
    pub fn tensile_strength(&self) -> f64 {
        self.e * self.eps0_t
    }

    /// The threshold ε₀ of one side.
    #[inline]
    pub fn threshold(&self, side: Side) -> f64 {
        match side {
            Side::Tension => self.eps0_t,
            Side::Compression => self.eps0_c,
        }
    }

    /// d_t or d_c (with integrity and slope) at the history value `kappa`.
    #[inline]
    pub fn damage(&self, side: Side, kappa: f64) -> DamageValue {
        match side {
            Side::Tension => damage::tension(self.eps0_t, self.b_t, kappa),
            Side::Compression => match &self.softening_c {
                None => damage::compression(self.eps0_c, self.a_c, self.b_c, kappa),
                Some(s) => damage::compression_softened(self.eps0_c, self.a_c, self.b_c, s, kappa),
            },
        }
    }

    /// Energy per volume (J/m³) dissipated while κ of `side` grows from `kappa_old` to `kappa_new`
    /// along a radial strain path with Y = c κ², i.e. c [F(κ_new) − F(κ_old)]
    /// ([`damage`] module docs). Never negative for `c ≥ 0`, `kappa_new ≥ kappa_old`.
    #[inline]
    pub fn dissipation(&self, side: Side, c: f64, kappa_old: f64, kappa_new: f64) -> f64 {
        let df = match side {
            Side::Tension => {
                damage::tension_primitive(self.eps0_t, self.b_t, kappa_new)
                    - damage::tension_primitive(self.eps0_t, self.b_t, kappa_old)
            }
            Side::Compression => match &self.softening_c {
                None => {
                    damage::compression_primitive(self.eps0_c, self.a_c, self.b_c, kappa_new)
                        - damage::compression_primitive(self.eps0_c, self.a_c, self.b_c, kappa_old)
                }
                Some(s) => {
                    damage::compression_softened_primitive(self.eps0_c, self.a_c, self.b_c, s, kappa_new)
                        - damage::compression_softened_primitive(self.eps0_c, self.a_c, self.b_c, s, kappa_old)
                }
            },
        };
        (c * df).max(0.0)
    }

    /// Energy per volume (J/m³) dissipated by a monotonic uniaxial tension to complete failure:
    /// f_t²/(2E) + f_t/B_t — that is G_f/h + f_t²/(2E) for `hillerborg`, exactly G_f/h for
    /// `hillerborg_no_elastic` ([`params`](super::params) module docs).
    pub fn tensile_failure_energy_density(&self) -> f64 {
        let ft = self.tensile_strength();
        ft * ft / (2.0 * self.e) + ft / self.b_t
    }
}
