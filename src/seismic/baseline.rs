//! Baseline correction: removes the low-order polynomial drift that offsets in the acceleration
//! (instrument tilt, digitisation) turn into large spurious velocity and displacement.
//!
//! Two methods, both by linear least squares on the normalised time `τ = t/T` (`T` = duration):
//!
//! * [`Baseline::Acceleration`]`{ order }` fits `p(τ) = Σ_{k=0}^{order} c_k τ^k` to `a(t_i)` and
//!   subtracts it (order 0: mean removal; 1: linear; 2: quadratic).
//! * [`Baseline::Displacement`]`{ order }` integrates the record twice from rest (exactly for
//!   piecewise-linear `a`, [`super::intensity::integrate`]), fits
//!   `u(τ) ≈ Σ_{k=2}^{order+2} c_k τ^k` — no constant nor linear term, since the record starts at rest —
//!   and subtracts the fit's second derivative `Σ c_k k(k−1) t^{k−2}/T^k` from the acceleration
//!   (the correction to `a` is a polynomial of degree `order`). This is the usual "fit the
//!   displacement" correction (e.g. Boore & Bommer 2005, §4): it keeps displacement and velocity
//!   bounded without prescribing where the drift starts.
//!
//! Neither method can restore frequencies below the noise floor: combine with a high-pass
//! ([`super::filter`]) for records with long-period noise.
use super::error::SeismicError;
use super::intensity::integrate;
use super::record::Record;
use nalgebra::{DMatrix, DVector};

/// A baseline correction method.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Default)]
pub enum Baseline {
    /// No correction.
    #[default]
    None,
    /// Least-squares polynomial of the acceleration removed (order 0, 1 or 2).
    Acceleration {
        /// Polynomial order.
        order: usize,
    },
    /// Least-squares polynomial `Σ_{k=2}^{order+2} c_k τ^k` of the displacement removed (order 0, 1 or 2).
    Displacement {
        /// Order of the resulting correction to the acceleration.
        order: usize,
    },
}

/// Least-squares coefficients of `y ≈ Σ_j c_j τ^{powers[j]}` (normal equations; the powers are
/// ≤ 4 on τ ∈ [0, 1], so they are well conditioned).
fn fit(tau: &[f64], y: &[f64], powers: &[i32]) -> Option<Vec<f64>> {
    let m = powers.len();
    let a = DMatrix::from_fn(tau.len(), m, |i, j| tau[i].powi(powers[j]));
    let ata = a.transpose() * &a;
    let aty = a.transpose() * DVector::from_column_slice(y);
    ata.cholesky().map(|c| c.solve(&aty).iter().copied().collect())
}

/// The record with its baseline corrected by `method`.
pub fn correct(r: &Record, method: Baseline) -> Result<Record, SeismicError> {
    let what = || format!("baseline correction of record '{}'", r.name);
    let order = match method {
        Baseline::None => return Ok(r.clone()),
        Baseline::Acceleration { order } | Baseline::Displacement { order } => order,
    };
    if order > 2 {
        return Err(SeismicError::invalid(what(), format!("order {order}, only 0, 1, 2 are offered")));
    }
    let t_total = r.duration();
    let tau: Vec<f64> = (0..r.len()).map(|i| i as f64 * r.dt / t_total).collect();
    let mut out = r.clone();
    match method {
        Baseline::Acceleration { .. } => {
            let powers: Vec<i32> = (0..=order as i32).collect();
            let c = fit(&tau, &r.accel, &powers)
                .ok_or_else(|| SeismicError::invalid(what(), "singular fit (too few samples)"))?;
            for (a, &x) in out.accel.iter_mut().zip(&tau) {
                *a -= c.iter().zip(&powers).map(|(c, &p)| c * x.powi(p)).sum::<f64>();
            }
        }
        _ => {
            let (_, u) = integrate(&r.accel, r.dt);
            let powers: Vec<i32> = (2..=order as i32 + 2).collect();
            let c = fit(&tau, &u, &powers)
                .ok_or_else(|| SeismicError::invalid(what(), "singular fit (too few samples)"))?;
            for (a, &x) in out.accel.iter_mut().zip(&tau) {
                // d²/dt² of c (t/T)^k = c k (k−1) τ^{k−2} / T².
                *a -= c.iter().zip(&powers).map(|(c, &k)| c * (k * (k - 1)) as f64 * x.powi(k - 2)).sum::<f64>()
                    / (t_total * t_total);
            }
        }
    }
    out.units_note = format!("{}; baseline {:?}", r.units_note, method);
    Ok(out)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::seismic::intensity::intensity;
    use std::f64::consts::PI;

    fn pulse_with_drift(offset: f64, slope: f64) -> Record {
        // One full sine cycle (zero mean, ends at rest) in the middle of 20 s, plus a drift.
        let dt = 0.01;
        let n = 2001;
        let clean: Vec<f64> = (0..n)
            .map(|i| {
                let t = i as f64 * dt;
                if (8.0..=10.0).contains(&t) {
                    (PI * (t - 8.0)).sin()
                } else {
                    0.0
                }
            })
            .collect();
        let drift: Vec<f64> = clean.iter().enumerate().map(|(i, a)| a + offset + slope * i as f64 * dt).collect();
        Record::new("p", dt, drift, "", "").unwrap()
    }

    #[test]
    fn acceleration_fit_removes_a_linear_drift() {
        // Clean signal cos(2π·3t/T) over the whole record: orthogonal to 1 and t (whole cycles),
        // so the fit returns the drift up to the discrete sums' projection: both ends sample
        // cos = 1, a mean of 0.5/n = 2.5e-4 m/s² (measured 2.5e-4); tolerance 5e-4 against a 0.05 offset.
        let (dt, n) = (0.01, 2001);
        let big_t = (n - 1) as f64 * dt;
        let clean: Vec<f64> = (0..n).map(|i| 0.5 * (2.0 * PI * 3.0 * i as f64 * dt / big_t).cos()).collect();
        let drift: Vec<f64> = clean.iter().enumerate().map(|(i, a)| a + 0.05 - 0.004 * i as f64 * dt).collect();
        let r = Record::new("d", dt, drift, "", "").unwrap();
        let c = correct(&r, Baseline::Acceleration { order: 1 }).unwrap();
        let err = c.accel.iter().zip(&clean).map(|(a, b)| (a - b).abs()).fold(0.0, f64::max);
        assert!(err < 5e-4, "{err}");
    }

    #[test]
    fn displacement_fit_bounds_the_drift() {
        // An offset of 0.01 m/s² over 20 s gives 0.01·20²/2 = 2 m of spurious displacement.
        let r = pulse_with_drift(0.01, 0.0);
        let before = intensity(&r).pgd;
        let after = intensity(&correct(&r, Baseline::Displacement { order: 1 }).unwrap()).pgd;
        assert!(before > 1.5, "{before}");
        // The pulse itself (one cycle of sin πt) has velocity ≤ 2/π m/s and displacement ≤ 2/π m:
        // the corrected PGD is of the pulse's order, far below the 2 m of drift.
        assert!(after < 0.5, "{after}");
        assert!(correct(&r, Baseline::Acceleration { order: 3 }).is_err());
    }
}
