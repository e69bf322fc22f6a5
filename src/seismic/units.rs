//! Acceleration units of record files, converted to m/s² on reading.

/// Standard gravity [m/s²] (CGPM 1901, exact), the "g" of PEER and ESM files.
pub const STANDARD_GRAVITY: f64 = 9.80665;

/// The unit a file's acceleration values are written in.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum AccelUnit {
    /// Multiples of standard gravity g = 9.80665 m/s².
    G,
    /// m/s².
    MetersPerSecond2,
    /// cm/s² (gal).
    CentimetersPerSecond2,
}

impl AccelUnit {
    /// The factor that turns a value in this unit into m/s².
    pub fn to_si(self) -> f64 {
        match self {
            AccelUnit::G => STANDARD_GRAVITY,
            AccelUnit::MetersPerSecond2 => 1.0,
            AccelUnit::CentimetersPerSecond2 => 0.01,
        }
    }

    /// A short name ("g", "m/s^2", "cm/s^2").
    pub fn name(self) -> &'static str {
        match self {
            AccelUnit::G => "g",
            AccelUnit::MetersPerSecond2 => "m/s^2",
            AccelUnit::CentimetersPerSecond2 => "cm/s^2",
        }
    }

    /// Recognises a unit written in a file header ("g", "G", "cm/s^2", "cm/s2", "gal", "m/s^2", "m/s**2").
    pub fn parse(text: &str) -> Option<AccelUnit> {
        let t: String = text.trim().to_ascii_lowercase().chars().filter(|c| !c.is_whitespace()).collect();
        let t = t.replace("**", "^").replace("s2", "s^2").replace("sec", "s");
        match t.as_str() {
            "g" | "unitsofg" => Some(AccelUnit::G),
            "cm/s^2" | "gal" | "gals" => Some(AccelUnit::CentimetersPerSecond2),
            "m/s^2" => Some(AccelUnit::MetersPerSecond2),
            _ => None,
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn units_convert_to_si() {
        // Exact by definition.
        assert_eq!(AccelUnit::G.to_si(), 9.80665);
        assert_eq!(AccelUnit::CentimetersPerSecond2.to_si(), 0.01);
        assert_eq!(AccelUnit::parse(" cm/s^2 "), Some(AccelUnit::CentimetersPerSecond2));
        assert_eq!(AccelUnit::parse("CM/S**2"), Some(AccelUnit::CentimetersPerSecond2));
        assert_eq!(AccelUnit::parse("m/s2"), Some(AccelUnit::MetersPerSecond2));
        assert_eq!(AccelUnit::parse("G"), Some(AccelUnit::G));
        assert_eq!(AccelUnit::parse("furlong"), None);
    }
}
