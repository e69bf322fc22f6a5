//! A record set for a Eurocode 8 time-history assessment (EN 1998-1 §3.2.3.1): artificial
//! records matched to the elastic spectrum ([`super::artificial`]), recorded ones each scaled by
//! one factor ([`super::set_scaling`]), their 5 %-damped spectra on one list of periods, and the
//! set's compatibility check ([`super::compatibility`]).
//!
//! The spectra are computed on the union of the check's periods (T = 0, the range in log
//! steps, the corners inside it) and the caller's periods for tables and charts; the check
//! runs on the records as they will be written.
use super::artificial::{artificial_record, ArtificialSpec};
use super::compatibility::{check_compatibility, check_periods, Compatibility, CompatibilityRules};
use super::ec8::Ec8Spectrum;
use super::error::SeismicError;
use super::matching::MatchReport;
use super::record::Record;
use super::set_scaling::log_least_squares_factor;
use super::spectrum::{response_spectrum, ResponseSpectrum};

/// The damping ratio of EC8's compatibility rules.
pub const SET_DAMPING: f64 = 0.05;

/// Where a member of the set comes from.
#[derive(Clone, Debug, PartialEq)]
pub enum Origin {
    /// Generated and matched: its seed and matching history.
    Artificial {
        /// The seed it was generated from.
        seed: u64,
        /// The matching's misfit history.
        report: MatchReport,
    },
    /// Read from a file and scaled by one factor.
    Recorded {
        /// The factor applied.
        factor: f64,
    },
}

/// One record of the set.
#[derive(Clone, Debug, PartialEq)]
pub struct Member {
    /// The record as it joins the set (matched or scaled), m/s².
    pub record: Record,
    /// Its origin.
    pub origin: Origin,
    /// Its 5 %-damped spectrum on the set's periods.
    pub spectrum: ResponseSpectrum,
}

/// What a set is made of.
#[derive(Clone, Debug, PartialEq)]
pub struct SetRecipe<'a> {
    /// The target spectrum (5 % damping: η = 1).
    pub target: Ec8Spectrum,
    /// The rules, with the period range.
    pub rules: CompatibilityRules,
    /// Artificial records and how many, if any.
    pub artificial: Option<(&'a ArtificialSpec, usize)>,
    /// Recorded records, unscaled, in m/s².
    pub recorded: Vec<Record>,
    /// Number of log-spaced periods over the range (for the check and for the scale factors).
    pub range_points: usize,
    /// Further periods for tables and charts [s].
    pub chart_periods: Vec<f64>,
}

/// A built set and its check.
#[derive(Clone, Debug, PartialEq)]
pub struct RecordSet {
    /// The records, artificial first, in order.
    pub members: Vec<Member>,
    /// The periods of every spectrum [s], increasing, from 0.
    pub periods: Vec<f64>,
    /// The check.
    pub check: Compatibility,
}

/// The periods `n` log-spaced over `range`, both ends exact (the scale factors' periods).
fn range_periods(range: (f64, f64), n: usize) -> Vec<f64> {
    let n = n.max(2);
    (0..n)
        .map(|k| if k + 1 == n { range.1 } else { range.0 * (range.1 / range.0).powf(k as f64 / (n - 1) as f64) })
        .collect()
}

/// The recorded record `r` scaled by the log least-squares factor over the range of `recipe`.
pub fn scale_recorded(r: &Record, recipe: &SetRecipe) -> Result<(Record, f64), SeismicError> {
    let p = range_periods(recipe.rules.range, recipe.range_points);
    let sa = response_spectrum(r, &p, SET_DAMPING)?.sa;
    let se: Vec<f64> = p.iter().map(|&t| recipe.target.se(t)).collect();
    let f = log_least_squares_factor(&sa, &se)
        .map_err(|e| SeismicError::invalid(format!("record '{}'", r.name), e.to_string()))?;
    Ok((r.scaled(f)?, f))
}

/// Builds the set of `recipe` and checks it.
pub fn build_set(recipe: &SetRecipe) -> Result<RecordSet, SeismicError> {
    let mut periods = check_periods(recipe.rules.range, recipe.range_points, &recipe.target);
    periods.extend(recipe.chart_periods.iter().copied().filter(|t| t.is_finite() && *t > 0.0));
    periods.sort_by(f64::total_cmp);
    periods.dedup();
    let mut members = Vec::new();
    if let Some((spec, count)) = recipe.artificial {
        for k in 0..count {
            let (record, report) = artificial_record(spec, &recipe.target, k)?;
            let spectrum = response_spectrum(&record, &periods, SET_DAMPING)?;
            members.push(Member { record, origin: Origin::Artificial { seed: spec.seed_of(k), report }, spectrum });
        }
    }
    for r in &recipe.recorded {
        let (record, factor) = scale_recorded(r, recipe)?;
        let spectrum = response_spectrum(&record, &periods, SET_DAMPING)?;
        members.push(Member { record, origin: Origin::Recorded { factor }, spectrum });
    }
    let spectra: Vec<ResponseSpectrum> = members.iter().map(|m| m.spectrum.clone()).collect();
    let stationary = recipe.artificial.filter(|(_, n)| *n > 0).map(|(s, _)| s.stationary);
    let check = check_compatibility(&spectra, &recipe.target, &recipe.rules, stationary)?;
    Ok(RecordSet { members, periods, check })
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::seismic::ec8::{Ec8Type, GroundType};
    use crate::seismic::vallorcine::vallorcine_like_synthetic;

    #[test]
    fn a_recorded_record_is_scaled_to_the_target_in_log_mean() {
        // The Vallorcine-like record (PGA 0.45 m/s², far below EC8 zone 4) scaled over
        // [0.066, 0.66] s: after scaling, the mean of ln(Sa/Se) over the factor's periods is 0
        // (the definition of the factor; 1e-9 for the spectra's round-off), and the factor is the
        // same computed twice (a pure function of the record).
        let target = Ec8Spectrum::new(Ec8Type::Type1, GroundType::A, 1.6, 5.0).unwrap();
        let recipe = SetRecipe {
            target,
            rules: CompatibilityRules::ec8(0.33),
            artificial: None,
            recorded: vec![vallorcine_like_synthetic()],
            range_points: 40,
            chart_periods: vec![],
        };
        let (scaled, f) = scale_recorded(&recipe.recorded[0], &recipe).unwrap();
        assert!(f > 1.0, "a weak record is scaled up: {f}");
        let p = range_periods(recipe.rules.range, 40);
        let sa = response_spectrum(&scaled, &p, 0.05).unwrap().sa;
        let mean_log = p.iter().zip(&sa).map(|(t, s)| (s / target.se(*t)).ln()).sum::<f64>() / p.len() as f64;
        assert!(mean_log.abs() < 1e-9, "{mean_log}");
        let set = build_set(&recipe).unwrap();
        assert_eq!(set.members.len(), 1);
        assert!(matches!(set.members[0].origin, Origin::Recorded { factor } if factor == f));
        // One record: rule (4)a fails.
        assert!(!set.check.passed && set.check.failures()[0].contains("1 record(s)"), "{:?}", set.check.failures());
    }
}
