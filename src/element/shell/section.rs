//! [`ShellSection`]: thickness, layers, material and masses of a shell.
//!
//! # Job-file form (TOML)
//! ```toml
//! thickness = 0.6                     # m
//! layers = 7                          # optional, default 7 (Simpson rule per layer, layers.rs)
//! density = 2000.0                    # kg/m³
//! nonstructural_mass_per_area = 50.0  # optional, kg/m², default 0 (plaster, fill, ...)
//! material = { elastic = { E = 2.9e9, nu = 0.19 } }
//! # material = { damage = { E = 2.9e9, nu = 0.19, eps0_t = 1.4e-4, eps0_c = 2e-4, gf_t = 60.0,
//! #                         a_c = 0.8, b_c = 1500.0, regularization = "hillerborg" } }
//! ```
//!
//! # Transverse shear
//! Elastic in both cases (paper §4.2): Q = k G t γ with k = 5/6 ([`SHEAR_CORRECTION`]) and the
//! undamaged G = E / (2(1 + ν)).

use serde::{Deserialize, Serialize};

use super::error::ShellError;
use crate::element::ElementError;
use crate::material::DamageParams;

/// Default number of layers through the thickness.
pub const DEFAULT_LAYERS: usize = 7;

/// Shear correction factor k of the transverse shear stiffness k G t (Reissner–Mindlin, 5/6).
pub const SHEAR_CORRECTION: f64 = 5.0 / 6.0;

fn default_layers() -> usize {
    DEFAULT_LAYERS
}

/// The material of every layer of a shell.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case", deny_unknown_fields)]
pub enum ShellMaterial {
    /// Isotropic linear elasticity.
    Elastic {
        /// Young modulus E (Pa).
        #[serde(rename = "E")]
        e: f64,
        /// Poisson ratio ν in (−1, 0.5).
        nu: f64,
    },
    /// The tension/compression damage law in plane stress at every layer point (paper §3.1), with B_t
    /// regularized by the element size h = sqrt(area).
    Damage(DamageParams),
}

impl ShellMaterial {
    /// Young modulus E (Pa).
    pub fn e(&self) -> f64 {
        match self {
            ShellMaterial::Elastic { e, .. } => *e,
            ShellMaterial::Damage(p) => p.e,
        }
    }

    /// Poisson ratio ν.
    pub fn nu(&self) -> f64 {
        match self {
            ShellMaterial::Elastic { nu, .. } => *nu,
            ShellMaterial::Damage(p) => p.nu,
        }
    }

    /// Undamaged shear modulus G = E / (2(1 + ν)) (Pa).
    pub fn shear_modulus(&self) -> f64 {
        self.e() / (2.0 * (1.0 + self.nu()))
    }
}

/// A homogeneous shell section: thickness, layers, material and masses. SI units.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct ShellSection {
    /// Thickness t (m).
    pub thickness: f64,
    /// Number of layers through the thickness (default [`DEFAULT_LAYERS`]).
    #[serde(default = "default_layers")]
    pub layers: usize,
    /// Material of the layers.
    pub material: ShellMaterial,
    /// Mass density ρ (kg/m³); ≥ 0.
    pub density: f64,
    /// Additional mass per area (kg/m²) carried without stiffness; ≥ 0. Adds to the translational
    /// mass and to the self weight.
    #[serde(default)]
    pub nonstructural_mass_per_area: f64,
}

impl ShellSection {
    /// An elastic section with the default number of layers and no non-structural mass.
    pub fn elastic(thickness: f64, e: f64, nu: f64, density: f64) -> Self {
        ShellSection {
            thickness,
            layers: DEFAULT_LAYERS,
            material: ShellMaterial::Elastic { e, nu },
            density,
            nonstructural_mass_per_area: 0.0,
        }
    }

    /// Check the values; the error names the first offending quantity. The damage parameters are
    /// checked when the law is set up for an element (they need the element size).
    pub fn validate(&self) -> Result<(), ShellError> {
        let positive = ElementError::positive;
        let non_negative = ElementError::non_negative;
        positive("thickness", self.thickness)?;
        if self.layers == 0 {
            return Err(ShellError::NoLayers { layers: 0 });
        }
        non_negative("density", self.density)?;
        non_negative("nonstructural_mass_per_area", self.nonstructural_mass_per_area)?;
        positive("E", self.material.e())?;
        let nu = self.material.nu();
        if !(nu.is_finite() && nu > -1.0 && nu < 0.5) {
            return Err(ElementError::InvalidSection { quantity: "nu", value: nu, expected: "in (-1, 0.5)" }.into());
        }
        Ok(())
    }

    /// Mass per area of the translations, ρ t + non-structural mass (kg/m²).
    pub fn mass_per_area(&self) -> f64 {
        self.density * self.thickness + self.nonstructural_mass_per_area
    }

    /// Rotary inertia per area of the bending rotations, ρ t³ / 12 (kg).
    pub fn rotary_inertia_per_area(&self) -> f64 {
        self.density * self.thickness.powi(3) / 12.0
    }

    /// Elastic transverse shear stiffness k G t (N/m), [`SHEAR_CORRECTION`].
    pub fn shear_stiffness(&self) -> f64 {
        SHEAR_CORRECTION * self.material.shear_modulus() * self.thickness
    }
}
