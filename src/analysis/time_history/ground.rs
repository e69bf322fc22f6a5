//! The base acceleration `a_g(t)` of up to three components, each its own record.
//!
//! A record is taken as piecewise linear between its samples (as the response-spectrum
//! integrator does), so an analysis step need not match the record's: `a_g(t)` is interpolated
//! linearly (a documented resampling, no filtering). The ground velocity and displacement, needed
//! for absolute motions, are the exact integrals of that piecewise-linear acceleration from rest
//! (no baseline correction is applied here: correct the record in `[dynamics.ground_motion]`'s
//! file if its displacement drifts).
use crate::seismic::Record;

/// Ground motion: a record per direction (x, y, z), or none.
#[derive(Clone, Debug, Default)]
pub struct GroundMotion {
    /// Record of each direction.
    pub components: [Option<Record>; 3],
    /// Per direction, cumulative ground velocity and displacement at the record's samples.
    integrals: [Vec<(f64, f64)>; 3],
}

impl GroundMotion {
    /// From records by direction.
    pub fn new(components: [Option<Record>; 3]) -> GroundMotion {
        let integrals = std::array::from_fn(|d| match &components[d] {
            None => Vec::new(),
            Some(r) => {
                let (mut v, mut u) = (0.0, 0.0);
                let mut out = vec![(0.0, 0.0)];
                for w in r.accel.windows(2) {
                    let h = r.dt;
                    // Exact over a linear segment a(s) = a0 + (a1 − a0) s/h.
                    u += v * h + h * h * (w[0] / 3.0 + w[1] / 6.0);
                    v += h * (w[0] + w[1]) / 2.0;
                    out.push((v, u));
                }
                out
            }
        });
        GroundMotion { components, integrals }
    }

    /// `a_g(t)` per direction [m/s²] (0 where there is no record; the last sample beyond the end).
    pub fn acceleration(&self, t: f64) -> [f64; 3] {
        std::array::from_fn(|d| match &self.components[d] {
            None => 0.0,
            Some(r) => {
                let (i, s) = locate(r, t);
                let a = &r.accel;
                if i + 1 >= a.len() {
                    a[a.len() - 1]
                } else {
                    a[i] + (a[i + 1] - a[i]) * s
                }
            }
        })
    }

    /// Ground velocity and displacement per direction at `t` (exact integrals, from rest).
    pub fn velocity_displacement(&self, t: f64) -> ([f64; 3], [f64; 3]) {
        let mut v = [0.0; 3];
        let mut u = [0.0; 3];
        for d in 0..3 {
            let Some(r) = &self.components[d] else { continue };
            let (i, s) = locate(r, t);
            let (v0, u0) = self.integrals[d][i.min(self.integrals[d].len() - 1)];
            if i + 1 >= r.accel.len() {
                v[d] = v0;
                u[d] = u0;
                continue;
            }
            let (a0, a1) = (r.accel[i], r.accel[i + 1]);
            let tau = s * r.dt;
            let slope = (a1 - a0) / r.dt;
            v[d] = v0 + a0 * tau + slope * tau * tau / 2.0;
            u[d] = u0 + v0 * tau + a0 * tau * tau / 2.0 + slope * tau * tau * tau / 6.0;
        }
        (v, u)
    }
}

/// Segment index and fraction in it for time `t` (clamped to the record).
fn locate(r: &Record, t: f64) -> (usize, f64) {
    let x = (t / r.dt).max(0.0);
    let i = x.floor() as usize;
    if i + 1 >= r.accel.len() {
        (r.accel.len() - 1, 0.0)
    } else {
        (i, x - i as f64)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn interpolation_and_exact_integrals() {
        // a(t) = t on [0, 1] sampled at dt = 0.5: a linear record, so v = t²/2 and u = t³/6
        // exactly at every t (the piecewise-linear integrals are exact for it).
        let r = Record::new("ramp", 0.5, vec![0.0, 0.5, 1.0], "m/s2", "test").unwrap();
        let g = GroundMotion::new([Some(r), None, None]);
        for t in [0.0, 0.2, 0.5, 0.77, 1.0] {
            let a = g.acceleration(t);
            assert!((a[0] - t).abs() < 1e-15 && a[1] == 0.0);
            let (v, u) = g.velocity_displacement(t);
            assert!((v[0] - t * t / 2.0).abs() < 1e-15, "{t}");
            assert!((u[0] - t * t * t / 6.0).abs() < 1e-15, "{t}");
        }
    }
}
