//! Input bounds: the one check that a number of the input is finite and > 0 ([`positive`]) or
//! finite and >= 0 ([`non_negative`]), with one message, `expected > 0, got -1`. Each layer maps
//! an [`OutOfBounds`] into its own typed error, which adds what was checked (the file and key, the
//! quantity, the field).

/// A value outside its bound: NaN, infinite, or on the wrong side of zero.
#[derive(Debug, Clone, Copy, PartialEq, thiserror::Error)]
#[error("expected {expected}, got {value}")]
pub struct OutOfBounds {
    /// The value given.
    pub value: f64,
    /// The bound it missed: `"> 0"` or `">= 0"`.
    pub expected: &'static str,
}

/// `value` when it is finite and > 0.
pub fn positive(value: f64) -> Result<f64, OutOfBounds> {
    if value.is_finite() && value > 0.0 {
        Ok(value)
    } else {
        Err(OutOfBounds { value, expected: "> 0" })
    }
}

/// `value` when it is finite and >= 0 (`-0.0` included).
pub fn non_negative(value: f64) -> Result<f64, OutOfBounds> {
    if value.is_finite() && value >= 0.0 {
        Ok(value)
    } else {
        Err(OutOfBounds { value, expected: ">= 0" })
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn positive_admits_finite_values_above_zero_only() {
        assert_eq!(positive(2.5), Ok(2.5));
        assert_eq!(positive(f64::MIN_POSITIVE), Ok(f64::MIN_POSITIVE));
        for v in [0.0, -0.0, -1.0, f64::INFINITY, f64::NEG_INFINITY] {
            assert_eq!(positive(v), Err(OutOfBounds { value: v, expected: "> 0" }), "{v}");
        }
        let nan = positive(f64::NAN).unwrap_err();
        assert!(nan.value.is_nan() && nan.expected == "> 0", "{nan:?}");
    }

    #[test]
    fn non_negative_admits_zero_and_finite_values_above() {
        assert_eq!(non_negative(2.5), Ok(2.5));
        assert_eq!(non_negative(0.0), Ok(0.0));
        assert_eq!(non_negative(-0.0), Ok(-0.0));
        for v in [-1.0, -f64::MIN_POSITIVE, f64::INFINITY, f64::NEG_INFINITY] {
            assert_eq!(non_negative(v), Err(OutOfBounds { value: v, expected: ">= 0" }), "{v}");
        }
        let nan = non_negative(f64::NAN).unwrap_err();
        assert!(nan.value.is_nan() && nan.expected == ">= 0", "{nan:?}");
    }

    #[test]
    fn the_message_names_the_bound_and_the_value() {
        assert_eq!(positive(-1.0).unwrap_err().to_string(), "expected > 0, got -1");
        assert_eq!(positive(0.0).unwrap_err().to_string(), "expected > 0, got 0");
        assert_eq!(positive(f64::NAN).unwrap_err().to_string(), "expected > 0, got NaN");
        assert_eq!(non_negative(-0.5).unwrap_err().to_string(), "expected >= 0, got -0.5");
        assert_eq!(non_negative(f64::INFINITY).unwrap_err().to_string(), "expected >= 0, got inf");
    }
}
