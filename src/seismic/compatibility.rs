//! Compatibility of a record set with a Eurocode 8 elastic spectrum (EN 1998-1:2004 §3.2.3.1).
//!
//! The rules for a suite of artificial accelerograms (§3.2.3.1.2(4)), which a suite of recorded
//! or simulated accelerograms must satisfy too (§3.2.3.1.3(3)):
//!
//! ```text
//! (4)a  n ≥ 3                                         at least 3 accelerograms
//! (4)b  (1/n) Σ_i Sa_i(0) ≥ a_g S                     mean zero-period spectral acceleration (= PGA)
//! (4)c  S̄a(T) = (1/n) Σ_i Sa_i(T, 5 %) ≥ 0.9 Se(T)    for every T in [0.2 T₁, 2 T₁]
//! ```
//!
//! T₁ is the structure's fundamental period in the direction the records will be applied; a job
//! may give the range itself instead. Rule (c) is checked on the periods the spectra were
//! computed at that fall in the range: [`check_periods`] gives `n` periods spaced evenly in
//! log T over the range, both ends included, plus the spectrum's corner periods T_B, T_C, T_D
//! that fall inside (where Se has kinks), so the lowest ratio between two checked periods of a
//! smooth mean spectrum is missed by little. The report gives the ratio `S̄a/Se` at every checked
//! period, its minimum and where it is.
//!
//! For artificial records §3.2.3.1.2(3) also asks for a stationary part of at least 10 s when
//! no site-specific data are available; the generator's envelope has it as a parameter
//! ([`super::artificial`]), and the check reports it as a fourth rule when given.
use super::ec8::Ec8Spectrum;
use super::error::SeismicError;
use super::spectrum::ResponseSpectrum;

/// The EN 1998-1 clause of each rule.
pub const RULE_COUNT: &str = "EN 1998-1 §3.2.3.1.2(4)a";
/// Clause of the zero-period rule.
pub const RULE_ZERO_PERIOD: &str = "EN 1998-1 §3.2.3.1.2(4)b";
/// Clause of the 90 % rule.
pub const RULE_SPECTRUM: &str = "EN 1998-1 §3.2.3.1.2(4)c";
/// Clause of the stationary-duration rule.
pub const RULE_STATIONARY: &str = "EN 1998-1 §3.2.3.1.2(3)";

/// What the check demands; [`CompatibilityRules::ec8`] gives the standard's values.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct CompatibilityRules {
    /// Least number of records (3).
    pub min_records: usize,
    /// Fraction of the target the mean may not fall below (0.9).
    pub fraction: f64,
    /// The period range `[t_min, t_max]` of rule (c) [s].
    pub range: (f64, f64),
    /// Least stationary part of artificial records [s] (10), checked when the set says how long
    /// its artificial records' stationary part is.
    pub min_stationary: f64,
}

impl CompatibilityRules {
    /// The standard's rules for a structure of fundamental period `t1` [s]: range [0.2 T₁, 2 T₁].
    pub fn ec8(t1: f64) -> CompatibilityRules {
        CompatibilityRules::ec8_range(0.2 * t1, 2.0 * t1)
    }

    /// The standard's rules over a given period range [s].
    pub fn ec8_range(t_min: f64, t_max: f64) -> CompatibilityRules {
        CompatibilityRules { min_records: 3, fraction: 0.9, range: (t_min, t_max), min_stationary: 10.0 }
    }
}

/// One rule's outcome.
#[derive(Clone, Debug, PartialEq, serde::Serialize)]
pub struct RuleOutcome {
    /// The clause, e.g. `EN 1998-1 §3.2.3.1.2(4)c`.
    pub rule: String,
    /// What it demands, in words.
    pub demand: String,
    /// The set's value and the limit, in words.
    pub found: String,
    /// Whether the set meets it.
    pub passed: bool,
}

/// The ratio of the mean spectrum to the target at one checked period.
#[derive(Clone, Copy, Debug, PartialEq, serde::Serialize)]
pub struct RatioPoint {
    /// Period [s].
    pub period: f64,
    /// Mean Sa of the set [m/s²].
    pub mean_sa: f64,
    /// Target Se [m/s²].
    pub target: f64,
    /// `mean_sa / target`.
    pub ratio: f64,
}

/// The result of [`check_compatibility`].
#[derive(Clone, Debug, PartialEq, serde::Serialize)]
pub struct Compatibility {
    /// Whether every rule is met.
    pub passed: bool,
    /// Every rule checked, in the standard's order.
    pub rules: Vec<RuleOutcome>,
    /// Number of records.
    pub records: usize,
    /// The period range of rule (c) [s], `low` and `high`.
    #[serde(serialize_with = "crate::io::summary::low_high")]
    pub range: (f64, f64),
    /// Lowest `S̄a/Se` over the range.
    pub min_ratio: f64,
    /// The period where it is lowest [s].
    pub period_of_min: f64,
    /// Mean PGA of the set [m/s²] (rule (b)).
    pub mean_pga: f64,
    /// a_g S of the target [m/s²].
    pub ag_s: f64,
    /// The ratio at every checked period of the range (in tables, not in summaries).
    #[serde(skip_serializing)]
    pub ratios: Vec<RatioPoint>,
}

impl Compatibility {
    /// The rules that failed, as "clause: found" lines.
    pub fn failures(&self) -> Vec<String> {
        self.rules.iter().filter(|r| !r.passed).map(|r| format!("{}: {}", r.rule, r.found)).collect()
    }
}

/// Periods for the check: 0 (for rule (b)), `n` (≥ 2) periods spaced evenly in log T over
/// `[t_min, t_max]` (both ends exact), and the target's corners T_B, T_C, T_D inside; increasing.
pub fn check_periods(range: (f64, f64), n: usize, target: &Ec8Spectrum) -> Vec<f64> {
    let (a, b) = range;
    let n = n.max(2);
    let mut p: Vec<f64> = (0..n).map(|k| a * (b / a).powf(k as f64 / (n - 1) as f64)).collect();
    p[n - 1] = b;
    p.extend([target.tb, target.tc, target.td].into_iter().filter(|&t| t > a && t < b));
    p.push(0.0);
    p.sort_by(f64::total_cmp);
    p.dedup();
    p
}

/// The mean spectrum of a set computed on one list of periods: `(1/n) Σ_i Sa_i(T_k)`.
pub fn mean_sa(spectra: &[ResponseSpectrum]) -> Vec<f64> {
    let n = spectra.len().max(1) as f64;
    let m = spectra.first().map_or(0, |s| s.sa.len());
    (0..m).map(|k| spectra.iter().map(|s| s.sa[k]).sum::<f64>() / n).collect()
}

fn in_range(t: f64, (a, b): (f64, f64)) -> bool {
    t >= a * (1.0 - 1e-12) && t <= b * (1.0 + 1e-12)
}

/// Checks the set whose 5 %-damped spectra are `spectra` (one per record, all on the same
/// periods, which include T = 0, where Sa = PGA) against `target` under `rules`.
/// `stationary` is the stationary part of the set's artificial records [s], if it has any.
pub fn check_compatibility(
    spectra: &[ResponseSpectrum],
    target: &Ec8Spectrum,
    rules: &CompatibilityRules,
    stationary: Option<f64>,
) -> Result<Compatibility, SeismicError> {
    let what = "compatibility check of a record set";
    let (a, b) = rules.range;
    if !(a > 0.0 && b > a && b.is_finite()) {
        return Err(SeismicError::invalid(what, format!("period range [{a}, {b}] s: expected 0 < min < max")));
    }
    let Some(first) = spectra.first() else {
        return Err(SeismicError::invalid(what, "the set has no record"));
    };
    let periods = &first.periods;
    if spectra.iter().any(|s| s.periods != *periods || s.sa.len() != periods.len()) {
        return Err(SeismicError::invalid(what, "the records' spectra are not on the same periods"));
    }
    if spectra.iter().any(|s| (s.damping - 0.05).abs() > 1e-12) {
        return Err(SeismicError::invalid(what, "EC8's rules concern 5 %-damped spectra"));
    }
    let Some(k0) = periods.iter().position(|&t| t == 0.0) else {
        return Err(SeismicError::invalid(what, "the periods must include T = 0 (the PGA)"));
    };
    let mean = mean_sa(spectra);
    let ratios: Vec<RatioPoint> = periods
        .iter()
        .zip(&mean)
        .filter(|(t, _)| in_range(**t, rules.range))
        .map(|(&period, &mean_sa)| {
            let target = target.se(period);
            RatioPoint { period, mean_sa, target, ratio: mean_sa / target }
        })
        .collect();
    let Some(lowest) = ratios.iter().min_by(|x, y| x.ratio.total_cmp(&y.ratio)) else {
        return Err(SeismicError::invalid(what, format!("no period of the spectra falls in [{a}, {b}] s")));
    };
    let (min_ratio, period_of_min) = (lowest.ratio, lowest.period);
    let ag_s = target.ag * target.s;
    let n = spectra.len();
    let mut out = vec![
        RuleOutcome {
            rule: RULE_COUNT.into(),
            demand: format!("at least {} records", rules.min_records),
            found: format!("{n} record(s), at least {} needed", rules.min_records),
            passed: n >= rules.min_records,
        },
        RuleOutcome {
            rule: RULE_ZERO_PERIOD.into(),
            demand: "mean zero-period spectral acceleration (PGA) ≥ a_g S".into(),
            found: format!("mean PGA {:.4} m/s² against a_g S = {ag_s:.4} m/s²", mean[k0]),
            passed: mean[k0] >= ag_s,
        },
        RuleOutcome {
            rule: RULE_SPECTRUM.into(),
            demand: format!("mean 5 %-damped spectrum ≥ {} of the target over [{a:.4}, {b:.4}] s", rules.fraction),
            found: format!("lowest mean/target {min_ratio:.4} at T = {period_of_min:.4} s, limit {}", rules.fraction),
            passed: min_ratio >= rules.fraction,
        },
    ];
    if let Some(s) = stationary {
        out.push(RuleOutcome {
            rule: RULE_STATIONARY.into(),
            demand: format!("stationary part of artificial records ≥ {} s", rules.min_stationary),
            found: format!("{s} s, at least {} s needed", rules.min_stationary),
            passed: s >= rules.min_stationary,
        });
    }
    Ok(Compatibility {
        passed: out.iter().all(|r| r.passed),
        rules: out,
        records: n,
        range: rules.range,
        min_ratio,
        period_of_min,
        mean_pga: mean[k0],
        ag_s,
        ratios,
    })
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::seismic::ec8::{Ec8Type, GroundType};

    fn target() -> Ec8Spectrum {
        Ec8Spectrum::new(Ec8Type::Type1, GroundType::A, 1.6, 5.0).unwrap()
    }

    /// A "spectrum" that is `f(T) · Se(T)` at the given periods (Sa(0) = f(0) · a_g S).
    fn shaped(periods: &[f64], f: impl Fn(f64) -> f64) -> ResponseSpectrum {
        let sa: Vec<f64> = periods.iter().map(|&t| f(t) * target().se(t)).collect();
        ResponseSpectrum { damping: 0.05, periods: periods.to_vec(), sd: sa.clone(), sv: sa.clone(), sa }
    }

    #[test]
    fn periods_cover_the_range_and_the_corners() {
        // T₁ = 0.33 s: [0.066, 0.66] s holds T_B = 0.15 and T_C = 0.4 of type 1, ground A (Table 3.2).
        let r = CompatibilityRules::ec8(0.33);
        let p = check_periods(r.range, 5, &target());
        assert_eq!(p.len(), 1 + 5 + 2);
        assert_eq!(p[0], 0.0);
        assert!((p[1] - 0.066).abs() < 1e-15 && p[7] == 0.66);
        assert!(p.contains(&0.15) && p.contains(&0.4));
        assert!(p.windows(2).all(|w| w[1] > w[0]));
    }

    #[test]
    fn the_mean_is_checked_and_the_lowest_period_found() {
        let r = CompatibilityRules::ec8(0.33);
        let p = check_periods(r.range, 50, &target());
        // Three records at 1.0, 1.1 and 1.2 Se: the mean is 1.1 Se everywhere (exact to round-off).
        let set: Vec<_> = [1.0, 1.1, 1.2].iter().map(|&f| shaped(&p, move |_| f)).collect();
        let c = check_compatibility(&set, &target(), &r, Some(10.0)).unwrap();
        assert!(c.passed, "{:?}", c.failures());
        assert!((c.min_ratio - 1.1).abs() < 1e-12 && (c.mean_pga - 1.1 * 1.6).abs() < 1e-12);
        assert_eq!(c.ratios.len(), 52);
        // Records at 0.8 (dip(T) + d), d = 0, 0.1, 0.2, with a dip of Se to 0.85 at T = 0.4 s only
        // (a triangle on ±0.05 s): the mean is 0.8 · 1.1 = 0.88 away from the dip (rule (b)
        // fails: 0.88 a_g S < a_g S) and 0.8 · (0.85 + 0.1) = 0.76 at 0.4 s (rule (c) fails there).
        let dip = |t: f64| 1.0 - 0.15 * (1.0 - ((t - 0.4) / 0.05).abs()).max(0.0);
        let weak: Vec<_> = [0.0, 0.1, 0.2].iter().map(|&d| shaped(&p, move |t| 0.8 * (dip(t) + d))).collect();
        let c = check_compatibility(&weak, &target(), &r, None).unwrap();
        assert!(!c.passed);
        assert!((c.min_ratio - 0.76).abs() < 1e-12 && c.period_of_min == 0.4, "{c:?}");
        let f = c.failures();
        assert_eq!(f.len(), 2, "{f:?}");
        assert!(f[0].starts_with(RULE_ZERO_PERIOD) && f[1].starts_with(RULE_SPECTRUM), "{f:?}");
        assert!(f[1].contains("0.7600 at T = 0.4000 s"), "{f:?}");
    }

    #[test]
    fn too_few_records_and_a_short_stationary_part_fail() {
        let r = CompatibilityRules::ec8(0.33);
        let p = check_periods(r.range, 10, &target());
        let set = vec![shaped(&p, |_| 1.2), shaped(&p, |_| 1.2)];
        let c = check_compatibility(&set, &target(), &r, Some(8.0)).unwrap();
        let f = c.failures();
        assert_eq!(f.len(), 2, "{f:?}");
        assert!(f[0].starts_with(RULE_COUNT) && f[1].starts_with(RULE_STATIONARY), "{f:?}");
        // Spectra without T = 0, or on other periods, or no record: refused with a reason.
        let no_zero = shaped(&p[1..], |_| 1.0);
        assert!(check_compatibility(&[no_zero], &target(), &r, None).is_err());
        assert!(check_compatibility(&[set[0].clone(), shaped(&p[..5], |_| 1.0)], &target(), &r, None).is_err());
        assert!(check_compatibility(&[], &target(), &r, None).is_err());
        let bad = CompatibilityRules::ec8_range(0.5, 0.1);
        assert!(check_compatibility(&set, &target(), &bad, None).is_err());
    }
}
