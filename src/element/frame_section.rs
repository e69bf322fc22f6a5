//! Properties of an elastic frame section (homogeneous material, prismatic member).

use serde::{Deserialize, Serialize};

use super::error::ElementError;

/// Elastic section of a 3D frame member. SI units throughout (N, m, kg).
///
/// `iy` and `iz` are second moments of area about the **local** y and z axes (see
/// [`LocalFrame`](super::LocalFrame) for how those axes follow from the orientation vector):
/// - `iz` resists bending in the local x–y plane (deflection v along y, rotation θz);
/// - `iy` resists bending in the local x–z plane (deflection w along z, rotation θy).
///
/// For a rectangle b (along local y) × h (along local z): Iy = b h³/12, Iz = h b³/12.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct FrameSection {
    /// Young's modulus E (Pa).
    pub e: f64,
    /// Shear modulus G (Pa).
    pub g: f64,
    /// Cross-section area A (m²).
    pub area: f64,
    /// Second moment of area about local y, Iy (m⁴).
    pub iy: f64,
    /// Second moment of area about local z, Iz (m⁴).
    pub iz: f64,
    /// Saint-Venant torsion constant J (m⁴).
    pub j: f64,
    /// Mass density ρ (kg/m³).
    pub density: f64,
    /// Non-structural mass per length (kg/m), ≥ 0: adds to the translational mass and the self
    /// weight, carries no stiffness (default 0).
    #[serde(default)]
    pub nonstructural_mass: f64,
}

impl FrameSection {
    /// Check that every quantity is finite and strictly positive; the error names the first that is not.
    pub fn validate(&self) -> Result<(), ElementError> {
        let fields =
            [("e", self.e), ("g", self.g), ("area", self.area), ("iy", self.iy), ("iz", self.iz), ("j", self.j)];
        for (quantity, value) in fields {
            ElementError::positive(quantity, value)?;
        }
        // A massless member (density 0) is allowed: a static model without self-weight.
        ElementError::non_negative("density", self.density)?;
        ElementError::non_negative("nonstructural_mass", self.nonstructural_mass)?;
        Ok(())
    }

    /// Polar moment of area Ip = Iy + Iz, which sets the mass moment of inertia per unit length
    /// about the member axis, ρ Ip (it equals J only for circular sections).
    pub fn polar_moment(&self) -> f64 {
        self.iy + self.iz
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn good() -> FrameSection {
        FrameSection {
            e: 30e9,
            g: 12.5e9,
            area: 0.06,
            iy: 4.5e-4,
            iz: 2.0e-4,
            j: 4.7e-4,
            density: 2500.0,
            nonstructural_mass: 0.0,
        }
    }

    #[test]
    fn valid_section_passes() {
        assert_eq!(good().validate(), Ok(()));
    }

    #[test]
    fn each_bad_quantity_is_named() {
        type Spoil = fn(&mut FrameSection);
        let cases: [(&str, Spoil); 7] = [
            ("e", |s| s.e = 0.0),
            ("g", |s| s.g = -1.0),
            ("area", |s| s.area = f64::NAN),
            ("iy", |s| s.iy = f64::INFINITY),
            ("iz", |s| s.iz = -2e-4),
            ("j", |s| s.j = 0.0),
            ("density", |s| s.density = -2500.0),
        ];
        for (name, spoil) in cases {
            let mut s = good();
            spoil(&mut s);
            match s.validate() {
                Err(ElementError::InvalidSection { quantity, .. }) => assert_eq!(quantity, name),
                other => panic!("{name}: expected InvalidSection, got {other:?}"),
            }
        }
        let msg = FrameSection { iz: -2e-4, ..good() }.validate().unwrap_err().to_string();
        assert!(msg.contains("iz") && msg.contains("-0.0002"), "{msg}");
    }

    #[test]
    fn unknown_fields_are_refused_by_serde() {
        let ok: Result<FrameSection, _> =
            serde_json::from_str(r#"{"e":1,"g":1,"area":1,"iy":1,"iz":1,"j":1,"density":1}"#);
        assert!(ok.is_ok());
        let bad: Result<FrameSection, _> =
            serde_json::from_str(r#"{"e":1,"g":1,"area":1,"iy":1,"iz":1,"j":1,"density":1,"rho":1}"#);
        assert!(bad.is_err());
    }
}
