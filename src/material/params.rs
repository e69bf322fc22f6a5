//! Input parameters of the masonry damage law, their validation, and the regularization of the
//! tensile softening slope by the element size (Hillerborg).
//!
//! # Job-file form (TOML)
//! ```toml
//! E = 2.885e9            # Young modulus [Pa]
//! nu = 0.19              # Poisson ratio [-]
//! eps0_t = 1.4e-4        # tensile damage threshold on ε_eq^t [-]
//! eps0_c = 2.0e-4        # compressive damage threshold on ε_eq^c (lateral extension) [-]
//! gf_t = 60.0            # tensile fracture energy G_f [J/m²]
//! a_c = 0.8              # compressive shape parameter A_c ∈ [0, 1] [-]
//! b_c = 1500.0           # compressive shape parameter B_c [1/strain], NOT regularized
//! regularization = "hillerborg"            # or "hillerborg_no_elastic"
//! # regularization = { none = { b_t = 4000.0 } }   # explicit B_t [1/strain], G_f then unused
//! ```
//!
//! # Regularization of B_t (tension)
//! With `f_t = E ε₀^t` and `h` the element characteristic length:
//!
//! | variant                  | B_t                                  | dissipated per volume, uniaxial tension to failure |
//! |--------------------------|--------------------------------------|-----------------------------------------------------|
//! | `hillerborg`             | f_t h / G_f                          | G_f / h + f_t² / (2E)                               |
//! | `hillerborg_no_elastic`  | f_t h / (G_f − f_t² h / (2E))        | G_f / h   (exact), needs h < 2 E G_f / f_t²        |
//! | `none`                   | b_t as given                         | f_t² / (2E) + f_t / b_t                             |
//!
//! Derivation: under uniaxial tension the stress–strain curve is σ = E ε up to ε₀^t, then
//! σ = f_t exp[−B_t (ε − ε₀^t)]. The stress goes to zero, so all the work is dissipated:
//! g = ∫₀^∞ σ dε = f_t ε₀^t / 2 + f_t / B_t = f_t² / (2E) + f_t / B_t. The `hillerborg` variant
//! sets the softening part f_t / B_t to G_f / h and so dissipates G_f per crack area plus the elastic
//! energy at the peak, h f_t²/(2E) per area (negligible for small elements); `hillerborg_no_elastic`
//! subtracts that elastic part so that the total is exactly G_f per crack area, which is possible
//! only while G_f > f_t² h / (2E).
//!
//! # B_c (compression) is not regularized
//! As in the paper (eq. 14) and SPEC §2, `B_c` is given directly in 1/strain and does not depend on
//! the element size: compressive softening is therefore mesh-dependent when it localizes. This
//! keeps the identified (ε₀^c, A_c, B_c) usable as they are in every element.

use serde::{Deserialize, Serialize};

use super::error::MaterialError;
use super::law::PointLaw;

/// How `B_t` follows from the element characteristic length (see the module docs).
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case", deny_unknown_fields)]
pub enum Regularization {
    /// `B_t = f_t h / G_f`: the softening branch dissipates G_f / h per volume.
    Hillerborg,
    /// `B_t = f_t h / (G_f − f_t² h / 2E)`: the whole curve dissipates G_f / h per volume;
    /// valid only for `h < 2 E G_f / f_t²`.
    HillerborgNoElastic,
    /// No regularization: `B_t` is given (1/strain) and the same in every element.
    #[serde(rename = "none")]
    Unregularized {
        /// The tensile softening parameter B_t (1/strain).
        b_t: f64,
    },
}

impl Regularization {
    /// The job-file name of the variant.
    pub fn name(&self) -> &'static str {
        match self {
            Regularization::Hillerborg => "hillerborg",
            Regularization::HillerborgNoElastic => "hillerborg_no_elastic",
            Regularization::Unregularized { .. } => "none",
        }
    }
}

/// Parameters of the tension/compression damage law (SPEC §2, paper eqs. 6–14). SI units.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct DamageParams {
    /// Young modulus E (Pa).
    #[serde(rename = "E")]
    pub e: f64,
    /// Poisson ratio ν, in (−1, 0.5).
    pub nu: f64,
    /// Tensile threshold ε₀^t on the equivalent strain ε_eq^t; the tensile strength is f_t = E ε₀^t.
    pub eps0_t: f64,
    /// Compressive threshold ε₀^c on ε_eq^c. Because ε_eq^c measures the positive principal strains
    /// (the lateral extension), under uniaxial compression damage starts at an axial strain of
    /// ε₀^c / (√2 ν), not at ε₀^c.
    pub eps0_c: f64,
    /// Tensile fracture energy G_f (J/m²), used by the Hillerborg regularizations.
    pub gf_t: f64,
    /// Compressive shape parameter A_c in [0, 1] (A_c = 1: no residual plateau).
    pub a_c: f64,
    /// Compressive shape parameter B_c (1/strain), > 0; not regularized (module docs).
    pub b_c: f64,
    /// How B_t is computed from the element size.
    pub regularization: Regularization,
}

/// A parameter must be finite and strictly positive.
fn positive(quantity: &'static str, value: f64) -> Result<(), MaterialError> {
    if !value.is_finite() {
        return Err(MaterialError::NonFinite { quantity, value });
    }
    if value <= 0.0 {
        return Err(MaterialError::NonPositive { quantity, value });
    }
    Ok(())
}

impl DamageParams {
    /// Check every parameter; the error names the first offending one with its value.
    ///
    /// Rules: E, ε₀^t, ε₀^c, G_f, B_c (and b_t for `none`) finite and > 0; ν in (−1, 0.5) (C₀
    /// positive definite); A_c in [0, 1] (d_c then increases from 0 to 1).
    pub fn validate(&self) -> Result<(), MaterialError> {
        positive("E", self.e)?;
        if !self.nu.is_finite() {
            return Err(MaterialError::NonFinite { quantity: "nu", value: self.nu });
        }
        if !(self.nu > -1.0 && self.nu < 0.5) {
            return Err(MaterialError::OutOfRange { quantity: "nu", value: self.nu, range: "(-1, 0.5)" });
        }
        positive("eps0_t", self.eps0_t)?;
        positive("eps0_c", self.eps0_c)?;
        positive("gf_t", self.gf_t)?;
        if !self.a_c.is_finite() {
            return Err(MaterialError::NonFinite { quantity: "a_c", value: self.a_c });
        }
        if !(0.0..=1.0).contains(&self.a_c) {
            return Err(MaterialError::OutOfRange { quantity: "a_c", value: self.a_c, range: "[0, 1]" });
        }
        positive("b_c", self.b_c)?;
        if let Regularization::Unregularized { b_t } = self.regularization {
            positive("b_t", b_t)?;
        }
        Ok(())
    }

    /// Tensile strength f_t = E ε₀^t (Pa).
    pub fn tensile_strength(&self) -> f64 {
        self.e * self.eps0_t
    }

    /// Largest element size 2 E G_f / f_t² (m) admitted by `hillerborg_no_elastic` (excluded);
    /// infinite for the other variants.
    pub fn element_size_limit(&self) -> f64 {
        match self.regularization {
            Regularization::HillerborgNoElastic => {
                let ft = self.tensile_strength();
                2.0 * self.e * self.gf_t / (ft * ft)
            }
            Regularization::Hillerborg | Regularization::Unregularized { .. } => f64::INFINITY,
        }
    }

    /// The tensile softening parameter B_t (1/strain) for an element of characteristic length `h`
    /// (m), per the regularization (module docs). Validates the parameters and `h`.
    pub fn b_t(&self, h: f64) -> Result<f64, MaterialError> {
        self.validate()?;
        if !(h.is_finite() && h > 0.0) {
            return Err(MaterialError::InvalidElementSize { h });
        }
        let ft = self.tensile_strength();
        let b_t = match self.regularization {
            Regularization::Hillerborg => ft * h / self.gf_t,
            Regularization::HillerborgNoElastic => {
                let limit = self.element_size_limit();
                if h >= limit {
                    return Err(MaterialError::ElementTooLarge { h, limit });
                }
                ft * h / (self.gf_t - ft * ft * h / (2.0 * self.e))
            }
            Regularization::Unregularized { b_t } => b_t,
        };
        // Finite and > 0 for valid input; guard against overflow of extreme but valid numbers.
        positive("b_t", b_t)?;
        Ok(b_t)
    }

    /// The law at the material points of an element of characteristic length `h` (m): B_t computed
    /// by the regularization, elastic constants precomputed. Rejects invalid parameters, a
    /// non-positive `h`, and an element above the `hillerborg_no_elastic` size limit (the message
    /// gives the limit).
    pub fn for_element(&self, h: f64) -> Result<PointLaw, MaterialError> {
        let b_t = self.b_t(h)?;
        Ok(PointLaw::new(self, h, b_t))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Order-of-magnitude values for rubble masonry (SPEC §1 Table 1: E = 2.885 GPa, ν = 0.19).
    fn good() -> DamageParams {
        DamageParams {
            e: 2.885e9,
            nu: 0.19,
            eps0_t: 1.4e-4,
            eps0_c: 2.0e-4,
            gf_t: 60.0,
            a_c: 0.8,
            b_c: 1500.0,
            regularization: Regularization::Hillerborg,
        }
    }

    #[test]
    fn good_parameters_validate() {
        assert_eq!(good().validate(), Ok(()));
    }

    #[test]
    fn bad_thresholds_are_rejected() {
        for (eps0_t, eps0_c, q) in [(0.0, 1e-4, "eps0_t"), (-1e-4, 1e-4, "eps0_t"), (1e-4, 0.0, "eps0_c")] {
            let p = DamageParams { eps0_t, eps0_c, ..good() };
            match p.validate() {
                Err(MaterialError::NonPositive { quantity, .. }) => assert_eq!(quantity, q),
                other => panic!("expected NonPositive {q}, got {other:?}"),
            }
        }
        let p = DamageParams { eps0_t: f64::NAN, ..good() };
        assert!(matches!(p.validate(), Err(MaterialError::NonFinite { quantity: "eps0_t", .. })));
    }

    #[test]
    fn a_c_outside_unit_interval_is_rejected() {
        for a_c in [-0.1, 1.01] {
            let err = DamageParams { a_c, ..good() }.validate().unwrap_err();
            assert_eq!(err, MaterialError::OutOfRange { quantity: "a_c", value: a_c, range: "[0, 1]" });
            assert!(err.to_string().contains("[0, 1]"), "{err}");
        }
        // The ends are admissible.
        for a_c in [0.0, 1.0] {
            assert_eq!(DamageParams { a_c, ..good() }.validate(), Ok(()));
        }
    }

    #[test]
    fn other_bad_parameters_are_rejected() {
        let cases: [(DamageParams, &str); 7] = [
            (DamageParams { e: 0.0, ..good() }, "E"),
            (DamageParams { nu: 0.5, ..good() }, "nu"),
            (DamageParams { nu: -1.0, ..good() }, "nu"),
            (DamageParams { gf_t: -1.0, ..good() }, "gf_t"),
            (DamageParams { b_c: 0.0, ..good() }, "b_c"),
            (DamageParams { e: f64::INFINITY, ..good() }, "E"),
            (DamageParams { regularization: Regularization::Unregularized { b_t: 0.0 }, ..good() }, "b_t"),
        ];
        for (p, q) in cases {
            let err = p.validate().unwrap_err();
            assert!(err.to_string().contains(&format!("`{q}`")), "{q}: {err}");
        }
    }

    #[test]
    fn b_t_per_regularization() {
        let p = good();
        let ft = p.e * p.eps0_t;
        let h = 0.1;
        // B_t = f_t h / G_f (SPEC §2), to round-off.
        let b = p.b_t(h).unwrap();
        assert!((b - ft * h / p.gf_t).abs() <= 1e-12 * b);
        // B_t = f_t h / (G_f − f_t² h / 2E) (SPEC §2).
        let q = DamageParams { regularization: Regularization::HillerborgNoElastic, ..p };
        let b = q.b_t(h).unwrap();
        assert!((b - ft * h / (p.gf_t - ft * ft * h / (2.0 * p.e))).abs() <= 1e-12 * b);
        let r = DamageParams { regularization: Regularization::Unregularized { b_t: 321.0 }, ..p };
        assert_eq!(r.b_t(h), Ok(321.0));
        assert!(matches!(p.b_t(0.0), Err(MaterialError::InvalidElementSize { .. })));
        assert!(matches!(p.b_t(f64::NAN), Err(MaterialError::InvalidElementSize { .. })));
    }

    #[test]
    fn element_above_the_no_elastic_limit_is_rejected_with_the_limit() {
        let p = DamageParams {
            e: 3.0e9,
            eps0_t: 1.0e-4, // f_t = 0.3 MPa
            gf_t: 10.5,     // limit 2 E G_f / f_t² = 2·3e9·10.5 / 9e10 = 0.7 m
            regularization: Regularization::HillerborgNoElastic,
            ..good()
        };
        let limit = 2.0 * 3.0e9 * 10.5 / (0.3e6 * 0.3e6);
        assert!((p.element_size_limit() - 0.7).abs() < 1e-12);
        let err = p.for_element(0.75).unwrap_err();
        assert_eq!(err, MaterialError::ElementTooLarge { h: 0.75, limit });
        let msg = err.to_string();
        assert!(msg.contains("h = 0.75 m") && msg.contains("0.7"), "{msg}");
        assert!(msg.contains("2 E G_f / f_t²") && msg.contains("hillerborg_no_elastic"), "{msg}");
        // At the limit itself B_t would be infinite: rejected too.
        assert!(p.for_element(limit).is_err());
        assert!(p.for_element(0.69).is_ok());
        // The plain Hillerborg variant has no limit.
        let q = DamageParams { regularization: Regularization::Hillerborg, ..p };
        assert!(q.for_element(0.75).is_ok());
    }

    #[test]
    fn deserializes_from_toml_with_each_regularization() {
        let base =
            "E = 2.885e9\nnu = 0.19\neps0_t = 1.4e-4\neps0_c = 2e-4\ngf_t = 60.0\na_c = 0.8\nb_c = 1500.0\n";
        let p: DamageParams = toml::from_str(&format!("{base}regularization = \"hillerborg\"\n")).unwrap();
        assert_eq!(p, good());
        let p: DamageParams =
            toml::from_str(&format!("{base}regularization = \"hillerborg_no_elastic\"\n")).unwrap();
        assert_eq!(p.regularization, Regularization::HillerborgNoElastic);
        let p: DamageParams =
            toml::from_str(&format!("{base}regularization = {{ none = {{ b_t = 400.0 }} }}\n")).unwrap();
        assert_eq!(p.regularization, Regularization::Unregularized { b_t: 400.0 });
        // Unknown keys are errors, at the top level and inside the variant.
        let e = toml::from_str::<DamageParams>(&format!("{base}regularization = \"hillerborg\"\nGf = 1.0\n"));
        assert!(e.is_err());
        let e = toml::from_str::<DamageParams>(&format!(
            "{base}regularization = {{ none = {{ b_t = 400.0, bt = 1.0 }} }}\n"
        ));
        assert!(e.is_err());
        let e = toml::from_str::<DamageParams>(&format!("{base}regularization = \"mazars\"\n"));
        assert!(e.is_err());
    }
}
