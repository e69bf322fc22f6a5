//! Errors of the element-level DEM mechanics.
//!
//! Each variant names the quantity and the offending value; the caller (sample setup, solver)
//! wraps it with the beam or particle id it was working on.

/// What went wrong while building or evaluating a beam, a contact or a threshold.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum MechanicsError {
    /// A quantity that must be finite and > 0 is not.
    #[error("`{quantity}`: expected > 0, got {value}")]
    NotPositive {
        /// The field name (`ell`, `area`, `inertia`, `e_bar`, `d_i`, ...).
        quantity: &'static str,
        /// The offending value.
        value: f64,
    },
    /// A quantity that must be finite and >= 0 is not.
    #[error("`{quantity}`: expected >= 0, got {value}")]
    Negative {
        /// The field name (`mu`, `f_n`, ...).
        quantity: &'static str,
        /// The offending value.
        value: f64,
    },
    /// A vector that must be finite is not.
    #[error("`{quantity}` must be finite, got {value:?}")]
    NotFinite {
        /// The field name (`n`, `r_i`, `seed_i`, ...).
        quantity: &'static str,
        /// The offending vector.
        value: [f64; 2],
    },
    /// The beam axis `n` is not a unit vector (|n| differs from 1 by more than 1e-9).
    #[error("beam axis n = {n:?} is not a unit vector (|n| = {norm})")]
    NotUnit {
        /// The axis as given.
        n: [f64; 2],
        /// Its norm.
        norm: f64,
    },
    /// The two beam end points coincide (to round-off).
    #[error("zero-length beam: ends at {seed_i:?} and {seed_j:?}")]
    ZeroLength {
        /// End point on particle i.
        seed_i: [f64; 2],
        /// End point on particle j.
        seed_j: [f64; 2],
    },
    /// The crushing softening is steeper than a contact's elastic stiffness (snap-back).
    #[error("`crushing_energy` = {energy} J/m² is too small for a contact of ℓ_c = {l_c} m: crushing needs G_c > σ_c² ℓ_c/(2 Ē) = {minimum} J/m² (softening without snap-back)")]
    CrushingSnapBack {
        /// The crushing energy given.
        energy: f64,
        /// The contact's length ℓ_c (m).
        l_c: f64,
        /// The smallest admissible energy for it.
        minimum: f64,
    },
}

/// `Ok(x)` if `x` is finite and > 0 ([`crate::bounds::positive`]).
pub(crate) fn positive(quantity: &'static str, value: f64) -> Result<f64, MechanicsError> {
    crate::bounds::positive(value).map_err(|b| MechanicsError::NotPositive { quantity, value: b.value })
}

/// `Ok(v)` if both components are finite.
pub(crate) fn finite(quantity: &'static str, value: [f64; 2]) -> Result<[f64; 2], MechanicsError> {
    if value.iter().all(|x| x.is_finite()) {
        Ok(value)
    } else {
        Err(MechanicsError::NotFinite { quantity, value })
    }
}

/// `Ok(x)` if `x` is finite and >= 0 ([`crate::bounds::non_negative`]).
pub(crate) fn non_negative(quantity: &'static str, value: f64) -> Result<f64, MechanicsError> {
    crate::bounds::non_negative(value).map_err(|b| MechanicsError::Negative { quantity, value: b.value })
}

impl MechanicsError {
    /// The parameter the error is about (`e_bar`, `mu`, `crushing_energy`, …), when it names one:
    /// the key a job file's error points at.
    pub fn quantity(&self) -> Option<&'static str> {
        match self {
            MechanicsError::NotPositive { quantity, .. }
            | MechanicsError::Negative { quantity, .. }
            | MechanicsError::NotFinite { quantity, .. } => Some(quantity),
            MechanicsError::CrushingSnapBack { .. } => Some("crushing_energy"),
            MechanicsError::NotUnit { .. } | MechanicsError::ZeroLength { .. } => None,
        }
    }
}
