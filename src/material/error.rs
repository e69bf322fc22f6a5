//! Errors of the damage law's parameters and of its per-element set-up.
//!
//! Every variant names the parameter (with its job-file spelling) and the offending value, so a
//! message read in a log points at the line of the input to fix. The law itself never fails at a
//! material point: a finite strain always gives a finite response.

/// What is wrong with a set of [`DamageParams`](super::DamageParams) or an element size.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum MaterialError {
    /// A parameter without a positive bound (`nu`, `a_c`) is NaN or infinite.
    #[error("damage law parameter `{quantity}` must be finite, got {value}")]
    NonFinite {
        /// The parameter, as spelled in the job file (`nu`, `a_c`).
        quantity: &'static str,
        /// The offending value.
        value: f64,
    },
    /// A parameter that must be finite and > 0 is not (NaN, infinite, or <= 0).
    #[error("damage law parameter `{quantity}`: expected > 0, got {value}")]
    NonPositive {
        /// The parameter, as spelled in the job file.
        quantity: &'static str,
        /// The offending value.
        value: f64,
    },
    /// A parameter lies outside its admissible interval.
    #[error("damage law parameter `{quantity}` = {value} lies outside {range}")]
    OutOfRange {
        /// The parameter, as spelled in the job file.
        quantity: &'static str,
        /// The offending value.
        value: f64,
        /// The admissible interval, written as in mathematics (`[0, 1]`, `(-1, 0.5)`).
        range: &'static str,
    },
    /// The element characteristic length is not a finite positive number.
    #[error("element characteristic length h [m]: expected > 0, got {h}")]
    InvalidElementSize {
        /// The element size given (m).
        h: f64,
    },
    /// The element is too large for the `hillerborg_no_elastic` regularization: the fracture
    /// energy G_f cannot pay for the elastic energy f_t² h / (2E) stored in the element at the peak.
    #[error(
        "element size h = {h} m exceeds the limit 2 E G_f / f_t² = {limit} m of the \
         hillerborg_no_elastic regularization; refine the mesh (h < {limit} m) or use \
         regularization = \"hillerborg\""
    )]
    ElementTooLarge {
        /// The element size given (m).
        h: f64,
        /// The largest admissible size 2 E G_f / f_t² (m), excluded.
        limit: f64,
    },
}
