//! Linear scaling of a recorded accelerogram to a target spectrum over a period range: one
//! factor per record (its shape is kept), for joining a set checked by
//! [`super::compatibility`].
//!
//! The factor minimizes the squared misfit in log spectral acceleration over periods `T_k`
//! spaced evenly in log T over the range, as the PEER ground-motion database's scaling does
//! (Ancheta et al. 2014, *Earthquake Spectra* 30(3), "NGA-West2 database", scaling by the
//! mean-squared error of ln Sa with uniform weights):
//!
//! ```text
//! min_f Σ_k (ln Se(T_k) − ln(f Sa(T_k)))²   ⇒   ln f = (1/m) Σ_k ln(Se(T_k)/Sa(T_k))
//! ```
//!
//! i.e. `f` is the geometric mean of the ratios target/record; the scaled record's spectrum is
//! `f Sa(T)` (the oscillator is linear). EN 1998-1 §3.2.3.1.3(1)P scales recorded motions to
//! the zone's a_g S: that rule is the check's (4)b, verified on the whole set afterwards, not
//! imposed on each record; the geometric mean puts each record's spectrum around the target
//! in the range, so the set's mean there lies near or above it (an arithmetic mean of
//! log-symmetric scatter exceeds the geometric mean).
use super::error::SeismicError;

/// `exp(mean_k ln(target_k / sa_k))` over the given values (both > 0 at every period).
pub fn log_least_squares_factor(sa: &[f64], target: &[f64]) -> Result<f64, SeismicError> {
    let what = "scale factor of a recorded record";
    if sa.is_empty() || sa.len() != target.len() {
        return Err(SeismicError::invalid(what, "needs the record's and the target's spectra at the same periods"));
    }
    for (k, (&s, &t)) in sa.iter().zip(target).enumerate() {
        for (whose, v) in [("record's", s), ("target's", t)] {
            crate::bounds::positive(v).map_err(|b| {
                SeismicError::out_of_bounds(format!("{what}: the {whose} spectral acceleration at period index {k}"), b)
            })?;
        }
    }
    let mean_log = sa.iter().zip(target).map(|(s, t)| (t / s).ln()).sum::<f64>() / sa.len() as f64;
    Ok(mean_log.exp())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_factor_is_the_geometric_mean_of_the_ratios() {
        // Ratios 2 and 8: geometric mean 4 (exact to round-off).
        let f = log_least_squares_factor(&[1.0, 1.0], &[2.0, 8.0]).unwrap();
        assert!((f - 4.0).abs() < 1e-14, "{f}");
        // A spectrum proportional to the target, Sa = Se/2.5, is scaled back exactly by 2.5.
        let se = [3.1, 4.0, 4.0, 2.2, 1.0];
        let sa: Vec<f64> = se.iter().map(|x| x / 2.5).collect();
        assert!((log_least_squares_factor(&sa, &se).unwrap() - 2.5).abs() < 1e-14);
        assert!(log_least_squares_factor(&[0.0, 1.0], &[1.0, 1.0]).is_err());
        assert!(log_least_squares_factor(&[1.0], &[1.0, 1.0]).is_err());
    }
}
