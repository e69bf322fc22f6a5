//! Eurocode 8 horizontal elastic response spectra (EN 1998-1:2004 §3.2.2.2).
//!
//! ```text
//! 0   ≤ T ≤ T_B : Se = a_g S [1 + T/T_B (2.5 η − 1)]
//! T_B ≤ T ≤ T_C : Se = a_g S η 2.5
//! T_C ≤ T ≤ T_D : Se = a_g S η 2.5 T_C/T
//! T_D ≤ T ≤ 4 s : Se = a_g S η 2.5 T_C T_D/T²
//! ```
//!
//! with `η = sqrt(10/(5 + ξ)) ≥ 0.55` (eq. 3.6, ξ the viscous damping in percent) and S, T_B, T_C,
//! T_D from Table 3.2 (type 1, surface-wave magnitude Ms > 5.5) or Table 3.3 (type 2, Ms ≤ 5.5).
//! `a_g = γ_I a_gR` is the design ground acceleration on type A ground. National annexes change
//! the table (the French annex, for instance, uses its own type-2 values in zones 1–4): every
//! field of [`Ec8Spectrum`] is public and can be overridden after construction.
use super::error::SeismicError;

/// Spectrum type.
#[derive(Clone, Copy, Debug, PartialEq, Eq, serde::Deserialize, serde::Serialize, schemars::JsonSchema)]
#[serde(rename_all = "snake_case")]
pub enum Ec8Type {
    /// Type 1 (Table 3.2): events with Ms > 5.5.
    Type1,
    /// Type 2 (Table 3.3): events with Ms ≤ 5.5.
    Type2,
}

/// Ground types of EN 1998-1 Table 3.1.
#[derive(Clone, Copy, Debug, PartialEq, Eq, serde::Deserialize, serde::Serialize, schemars::JsonSchema)]
pub enum GroundType {
    /// Rock, v_s,30 > 800 m/s.
    A,
    /// Very dense sand/gravel or very stiff clay, 360–800 m/s.
    B,
    /// Dense or medium-dense sand/gravel or stiff clay, 180–360 m/s.
    C,
    /// Loose-to-medium cohesionless soil or soft-to-firm cohesive soil, < 180 m/s.
    D,
    /// A surface alluvium layer of C or D values, 5–20 m thick, over stiffer material.
    E,
}

/// One horizontal elastic spectrum; all parameters public and overridable.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Ec8Spectrum {
    /// Design ground acceleration on type A ground a_g [m/s²].
    pub ag: f64,
    /// Soil factor S.
    pub s: f64,
    /// Lower limit of the constant-acceleration branch T_B [s].
    pub tb: f64,
    /// Upper limit of the constant-acceleration branch T_C [s].
    pub tc: f64,
    /// Start of the constant-displacement branch T_D [s].
    pub td: f64,
    /// Damping correction factor η.
    pub eta: f64,
}

impl Ec8Spectrum {
    /// The standard's table values (S, T_B, T_C, T_D) for a type and ground type.
    pub fn table(kind: Ec8Type, ground: GroundType) -> (f64, f64, f64, f64) {
        use GroundType::*;
        match (kind, ground) {
            // EN 1998-1 Table 3.2 (type 1).
            (Ec8Type::Type1, A) => (1.0, 0.15, 0.4, 2.0),
            (Ec8Type::Type1, B) => (1.2, 0.15, 0.5, 2.0),
            (Ec8Type::Type1, C) => (1.15, 0.20, 0.6, 2.0),
            (Ec8Type::Type1, D) => (1.35, 0.20, 0.8, 2.0),
            (Ec8Type::Type1, E) => (1.4, 0.15, 0.5, 2.0),
            // EN 1998-1 Table 3.3 (type 2).
            (Ec8Type::Type2, A) => (1.0, 0.05, 0.25, 1.2),
            (Ec8Type::Type2, B) => (1.35, 0.05, 0.25, 1.2),
            (Ec8Type::Type2, C) => (1.5, 0.10, 0.25, 1.2),
            (Ec8Type::Type2, D) => (1.8, 0.10, 0.30, 1.2),
            (Ec8Type::Type2, E) => (1.6, 0.05, 0.25, 1.2),
        }
    }

    /// η = sqrt(10/(5 + ξ)) ≥ 0.55, ξ in percent (eq. 3.6).
    pub fn eta_for(xi_percent: f64) -> f64 {
        (10.0 / (5.0 + xi_percent)).sqrt().max(0.55)
    }

    /// The standard spectrum for `kind`, `ground`, design ground acceleration `ag` [m/s²] and
    /// viscous damping `xi_percent` [%] (5 for the usual η = 1).
    pub fn new(kind: Ec8Type, ground: GroundType, ag: f64, xi_percent: f64) -> Result<Ec8Spectrum, SeismicError> {
        let (s, tb, tc, td) = Ec8Spectrum::table(kind, ground);
        crate::bounds::non_negative(xi_percent)
            .map_err(|b| SeismicError::out_of_bounds("EC8 spectrum damping ξ [%]", b))?;
        let sp = Ec8Spectrum { ag, s, tb, tc, td, eta: Ec8Spectrum::eta_for(xi_percent) };
        sp.validate()?;
        Ok(sp)
    }

    /// Checks overridden parameters: a_g ≥ 0, S > 0, 0 < T_B < T_C < T_D, η > 0.
    pub fn validate(&self) -> Result<(), SeismicError> {
        crate::bounds::non_negative(self.ag).map_err(|b| SeismicError::out_of_bounds("EC8 spectrum a_g [m/s²]", b))?;
        let ok = self.s > 0.0
            && self.tb > 0.0
            && self.tb < self.tc
            && self.tc < self.td
            && self.td.is_finite()
            && self.eta > 0.0;
        if ok {
            Ok(())
        } else {
            Err(SeismicError::invalid(
                "EC8 spectrum",
                format!("needs a_g ≥ 0, S > 0, 0 < T_B < T_C < T_D, η > 0: {self:?}"),
            ))
        }
    }

    /// Se(T) [m/s²] (eqs. 3.2–3.5), T ≥ 0 (the fourth branch is used beyond 4 s too).
    pub fn se(&self, t: f64) -> f64 {
        let plateau = self.ag * self.s * self.eta * 2.5;
        if t <= self.tb {
            self.ag * self.s * (1.0 + t / self.tb * (2.5 * self.eta - 1.0))
        } else if t <= self.tc {
            plateau
        } else if t <= self.td {
            plateau * self.tc / t
        } else {
            plateau * self.tc * self.td / (t * t)
        }
    }

    /// (T, Se) at the given periods, for charts.
    pub fn curve(&self, periods: &[f64]) -> Vec<(f64, f64)> {
        periods.iter().map(|&t| (t, self.se(t))).collect()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn corner_values_are_exact() {
        // Closed forms at the corners (EN 1998-1 eqs. 3.2–3.5), to round-off (1e-12 relative).
        let close = |a: f64, b: f64| (a - b).abs() <= 1e-12 * b.abs();
        for kind in [Ec8Type::Type1, Ec8Type::Type2] {
            for g in [GroundType::A, GroundType::B, GroundType::C, GroundType::D, GroundType::E] {
                let sp = Ec8Spectrum::new(kind, g, 1.6, 5.0).unwrap();
                let (s, tb, tc, td) = Ec8Spectrum::table(kind, g);
                assert_eq!(sp.eta, 1.0);
                assert!(close(sp.se(0.0), 1.6 * s));
                assert!(close(sp.se(tb), 1.6 * s * 2.5));
                assert!(close(sp.se(tc), 1.6 * s * 2.5));
                assert!(close(sp.se(td), 1.6 * s * 2.5 * tc / td));
                assert!(close(sp.se(4.0), 1.6 * s * 2.5 * tc * td / 16.0));
                // Midway up the first branch: a_g S (1 + 0.5·1.5).
                assert!(close(sp.se(tb / 2.0), 1.6 * s * 1.75));
            }
        }
        // Type 1 ground B: the plateau 1.6·1.2·2.5 = 4.8 m/s².
        assert!(close(Ec8Spectrum::new(Ec8Type::Type1, GroundType::B, 1.6, 5.0).unwrap().se(0.3), 4.8));
    }

    #[test]
    fn damping_correction_and_overrides() {
        // η(10%) = sqrt(10/15) = 0.81650; η(30%) = sqrt(10/35) = 0.5345 → floor 0.55.
        assert!((Ec8Spectrum::eta_for(10.0) - (10.0f64 / 15.0).sqrt()).abs() < 1e-15);
        assert_eq!(Ec8Spectrum::eta_for(30.0), 0.55);
        let mut sp = Ec8Spectrum::new(Ec8Type::Type2, GroundType::A, 1.6, 5.0).unwrap();
        sp.td = 2.5;
        assert!(sp.validate().is_ok());
        sp.tc = 3.0;
        assert!(sp.validate().is_err());
        assert!(Ec8Spectrum::new(Ec8Type::Type2, GroundType::A, -1.0, 5.0).is_err());
    }
}
