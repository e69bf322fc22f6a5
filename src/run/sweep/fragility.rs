//! Fragility functions of a sweep's limits: per limit, the lognormal P(passed | IM = x) fitted
//! to the passages of every record under every material (`seismic::fit_fragility`: the method of
//! moments on ln IM when every record passed at a known intensity, maximum likelihood with the
//! censored records otherwise; Baker 2015), P(passed) at the site's code level, and
//! `fragility-<group>-<share>.png`: the passages as their empirical distribution, the fitted
//! curve, the code level.
use super::hunt::Crossing;
use crate::config::SweepJob;
use crate::plot::{LineChart, PlotError, SeriesStyle};
use crate::seismic::{fit_fragility, FragilityFit, Passage};
use serde::Serialize;
use std::path::Path;

/// One limit's fragility over records and materials.
#[derive(Clone, Debug, Serialize)]
pub struct Fragility {
    /// The lognormal fit (`None`: too few passages, see `passed`).
    pub fit: Option<FragilityFit>,
    /// Record-material pairs.
    pub records: usize,
    /// Passed at a known intensity.
    pub passed: usize,
    /// Not passed up to the highest intensity run (censored there).
    pub not_passed: usize,
    /// Passed at or below the lowest intensity run.
    pub at_or_below_lowest: usize,
    /// P(passed | IM = code level) from the fit.
    pub p_code_level: Option<f64>,
    /// Records that passed at or below the code level (a count, beside the fit's probability).
    pub passed_by_code_level: Option<usize>,
}

/// A crossing as a passage for the fit (`None` for a record without a member).
pub fn passage(c: &Crossing) -> Option<Passage> {
    match (c.how, c.intensity, c.censored_at) {
        ("at_or_below_lowest", Some(x), _) => Some(Passage::AtOrBelow(x)),
        (_, Some(x), _) => Some(Passage::At(x)),
        (_, None, Some(x)) => Some(Passage::Above(x)),
        _ => None,
    }
}

/// The fragility of the `crossings` of one limit under every material, at `code_level`.
pub fn fragility<'a>(crossings: impl Iterator<Item = &'a Crossing>, code_level: Option<f64>) -> Fragility {
    let p: Vec<Passage> = crossings.filter_map(passage).collect();
    let count = |f: fn(&Passage) -> bool| p.iter().filter(|x| f(x)).count();
    let fit = fit_fragility(&p);
    Fragility {
        fit,
        records: p.len(),
        passed: count(|x| matches!(x, Passage::At(_))),
        not_passed: count(|x| matches!(x, Passage::Above(_))),
        at_or_below_lowest: count(|x| matches!(x, Passage::AtOrBelow(_))),
        p_code_level: code_level.and_then(|c| fit.and_then(|f| f.probability(c))),
        passed_by_code_level: code_level
            .map(|c| p.iter().filter(|x| matches!(x, Passage::At(v) | Passage::AtOrBelow(v) if *v <= c)).count()),
    }
}

/// The fragility's lines for `summary.txt`.
pub fn text(f: &Fragility, im: &str, code_level: Option<f64>) -> String {
    let fit = match &f.fit {
        Some(x) => format!(
            "median {im} {:.3} m/s², beta {} ({})",
            x.median,
            x.beta.map_or("-".into(), |b| format!("{b:.3}")),
            match x.estimator {
                crate::seismic::Estimator::Moments => "method of moments on ln IM",
                crate::seismic::Estimator::CensoredMaximumLikelihood => "maximum likelihood with the censored records",
            }
        ),
        None => "not fitted (fewer than two passages at a known intensity)".into(),
    };
    let mut t = format!(
        "  fragility over {} record-material pair(s): {fit}; {} passed, {} not passed up to the highest intensity run, {} at or below the lowest\n",
        f.records, f.passed, f.not_passed, f.at_or_below_lowest
    );
    if let Some(c) = code_level {
        let p = f.p_code_level.map_or("not fitted".into(), |p| format!("{p:.3}"));
        let n = f.passed_by_code_level.unwrap_or(0);
        t += &format!("  P(passed | {im} = {c}) = {p} ({n} of {} record-material pair(s) passed by then)\n", f.records);
    }
    t
}

/// Draws `fragility-<group>-<share %>.png` of the limit of `group` at `share` from its
/// `crossings` under every material and its fragility `f`; whether there was a passage to draw.
pub fn draw(
    job: &SweepJob,
    group: &str,
    share: f64,
    crossings: &[&Crossing],
    f: &Fragility,
    out: &Path,
) -> Result<bool, PlotError> {
    let im = job.spec.sweep.scale_by.label();
    let mut known: Vec<f64> = crossings.iter().filter_map(|c| c.intensity).collect();
    if known.is_empty() {
        return Ok(false);
    }
    known.sort_by(f64::total_cmp);
    let total = crossings.iter().filter(|c| passage(c).is_some()).count();
    let points: Vec<(f64, f64)> = known.iter().enumerate().map(|(i, &x)| (x, (i + 1) as f64 / total as f64)).collect();
    let top = crossings.iter().filter_map(|c| c.intensity.or(c.censored_at)).fold(0.0f64, f64::max);
    let mut chart = LineChart::new(
        &format!("{group}: {:.0} % of its area with d_t > 0.5", 100.0 * share),
        &format!("{im} [m/s²]"),
        "P(limit passed)",
    )
    .series(&format!("passages ({} of {total} record-material pairs)", known.len()), points, SeriesStyle::Markers);
    if let Some((fit, beta)) = f.fit.and_then(|x| x.beta.map(|b| (x, b))) {
        let x_max = top.max(fit.median * (2.0 * beta).exp()).max(job.spec.sweep.code_level.unwrap_or(0.0));
        let curve: Vec<(f64, f64)> = (1..=200)
            .map(|i| {
                let x = x_max * i as f64 / 200.0;
                (x, fit.probability(x).unwrap_or(0.0))
            })
            .collect();
        chart = chart.series(&format!("lognormal: median {:.3}, beta {beta:.3}", fit.median), curve, SeriesStyle::Line);
    }
    if let Some(c) = job.spec.sweep.code_level {
        chart = chart.reference(&format!("site code level {im} = {c}"), vec![(c, 0.0), (c, 1.0)], SeriesStyle::Dashed);
    }
    let file = out.join(format!("fragility-{group}-{:.0}.png", 100.0 * share));
    chart.legend_upper_left().save_png(&file)?;
    Ok(true)
}
