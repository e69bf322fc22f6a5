//! A ground-acceleration record: uniform sampling, SI units, with its provenance.
use super::error::SeismicError;

/// One horizontal (or vertical) component of ground acceleration, sampled every `dt`.
///
/// Sample `i` is at time `t_i = i·dt` (the record's own clock starts at 0). Between samples the
/// acceleration is taken as linear, which is what the response-spectrum integrator and the
/// integrals of [`super::intensity`] assume.
#[derive(Clone, Debug, PartialEq)]
pub struct Record {
    /// A name for legends and messages.
    pub name: String,
    /// Time step [s], > 0.
    pub dt: f64,
    /// Acceleration [m/s²].
    pub accel: Vec<f64>,
    /// What the original units were and how they were converted (e.g. "read in g, × 9.80665").
    pub units_note: String,
    /// Where the data came from (a file path, "synthetic: ...").
    pub source: String,
}

impl Record {
    /// A checked record: `dt > 0` and finite, at least two samples, every value finite.
    pub fn new(
        name: impl Into<String>,
        dt: f64,
        accel: Vec<f64>,
        units_note: impl Into<String>,
        source: impl Into<String>,
    ) -> Result<Record, SeismicError> {
        let name = name.into();
        crate::bounds::positive(dt)
            .map_err(|b| SeismicError::out_of_bounds(format!("time step dt [s] of record '{name}'"), b))?;
        if accel.len() < 2 {
            return Err(SeismicError::invalid(
                format!("record '{name}'"),
                format!("{} sample(s), at least 2 needed", accel.len()),
            ));
        }
        if let Some(i) = accel.iter().position(|a| !a.is_finite()) {
            return Err(SeismicError::NonFinite { file: name, line: i + 1, value: accel[i].to_string() });
        }
        Ok(Record { name, dt, accel, units_note: units_note.into(), source: source.into() })
    }

    /// Number of samples.
    pub fn len(&self) -> usize {
        self.accel.len()
    }

    /// True when there is no sample (never for a record built by [`Record::new`]).
    pub fn is_empty(&self) -> bool {
        self.accel.is_empty()
    }

    /// Duration `(n − 1)·dt` [s].
    pub fn duration(&self) -> f64 {
        (self.accel.len().max(1) - 1) as f64 * self.dt
    }

    /// Times of the samples [s].
    pub fn times(&self) -> Vec<f64> {
        (0..self.accel.len()).map(|i| i as f64 * self.dt).collect()
    }

    /// The record multiplied by `factor` (finite, any sign).
    pub fn scaled(&self, factor: f64) -> Result<Record, SeismicError> {
        if !factor.is_finite() {
            return Err(SeismicError::invalid(
                format!("scale factor of record '{}'", self.name),
                format!("{factor} is not finite"),
            ));
        }
        let mut r = self.clone();
        r.accel.iter_mut().for_each(|a| *a *= factor);
        r.units_note = format!("{}; scaled by {factor}", self.units_note);
        Ok(r)
    }

    /// Checks that the record lasts at least `requested` seconds (e.g. the analysis duration).
    pub fn require_duration(&self, requested: f64) -> Result<(), SeismicError> {
        if self.duration() + 1e-9 * self.dt < requested {
            return Err(SeismicError::TooShort { name: self.name.clone(), duration: self.duration(), requested });
        }
        Ok(())
    }

    /// Acceleration at time `t` by linear interpolation, 0 outside the record.
    pub fn at(&self, t: f64) -> f64 {
        if t.is_nan() || t < 0.0 || t > self.duration() {
            return 0.0;
        }
        let x = t / self.dt;
        let i = (x.floor() as usize).min(self.accel.len() - 1);
        if i + 1 >= self.accel.len() {
            return self.accel[i];
        }
        let f = x - i as f64;
        self.accel[i] * (1.0 - f) + self.accel[i + 1] * f
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn bad_records_are_refused_with_their_name() {
        let e = Record::new("r1", 0.0, vec![0.0, 1.0], "", "").unwrap_err();
        assert!(e.to_string().contains("r1"), "{e}");
        let e = Record::new("r2", 0.01, vec![0.0, f64::NAN, 1.0], "", "").unwrap_err();
        assert!(matches!(e, SeismicError::NonFinite { line: 2, .. }), "{e}");
        let r = Record::new("r3", 0.01, vec![0.0; 101], "", "").unwrap();
        assert!((r.duration() - 1.0).abs() < 1e-12);
        assert!(r.require_duration(1.0).is_ok());
        let e = r.require_duration(2.0).unwrap_err();
        assert!(e.to_string().contains("shorter than the requested 2 s"), "{e}");
        assert!(r.scaled(f64::INFINITY).is_err());
    }

    #[test]
    fn scaling_and_interpolation() {
        let r = Record::new("r", 0.5, vec![0.0, 1.0, -1.0], "m/s^2", "test").unwrap().scaled(2.0).unwrap();
        assert_eq!(r.accel, vec![0.0, 2.0, -2.0]);
        // Linear between samples: halfway between 2 and −2 is 0; a quarter is 1.
        assert!((r.at(0.75)).abs() < 1e-15);
        assert!((r.at(0.625) - 1.0).abs() < 1e-15);
        assert_eq!(r.at(5.0), 0.0);
    }
}
