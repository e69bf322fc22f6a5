//! IDA curves: per substructure, its share of area with d_t > 0.5 against the intensity, one
//! curve per record (and material), their mean on a grid, the site's code level (dashed vertical)
//! and the limits set on it (dashed horizontal): `ida-<group>.png`. A member that ended once it
//! had passed every limit (`[sweep.hunt] stop_at_passage`) is also marked: its share is a lower
//! bound of the whole record's.
use super::outcome::{Outcome, Status};
use crate::config::{Member, SweepJob};
use crate::plot::{LineChart, PlotError, SeriesStyle};
use std::path::Path;

/// Draws one chart per substructure in `groups` into `out`; the number drawn.
pub fn draw(
    job: &SweepJob,
    members: &[Member],
    outcomes: &[Outcome],
    groups: &[String],
    out: &Path,
) -> Result<usize, PlotError> {
    let im = job.spec.sweep.scale_by.label();
    let top = members.iter().map(|m| m.level).fold(0.0f64, f64::max).max(1e-3);
    let grid = match job.intensities() {
        crate::config::Intensities::Grid(x) => x,
        crate::config::Intensities::Hunt(_) => &[],
    };
    let mut n = 0;
    for g in groups {
        let mut chart = LineChart::new(
            &format!("{g}: area with d_t > 0.5 against {im}"),
            &format!("{im} [m/s²]"),
            "area with d_t > 0.5 [%]",
        );
        let mut all: Vec<(f64, f64)> = Vec::new();
        let ended: Vec<(f64, f64)> = members
            .iter()
            .zip(outcomes)
            .filter(|(_, o)| o.status == Status::Completed && o.ended_at_limits.is_some())
            .map(|(m, o)| (m.level, 100.0 * o.share_dt(g)))
            .collect();
        for (v, variant) in job.variants.iter().enumerate() {
            for (r, record) in job.records.iter().enumerate() {
                let pts: Vec<(f64, f64)> = members
                    .iter()
                    .zip(outcomes)
                    .filter(|(m, o)| m.variant == v && m.record == r && o.status == Status::Completed)
                    .map(|(m, o)| (m.level, 100.0 * o.share_dt(g)))
                    .collect();
                if pts.is_empty() {
                    continue;
                }
                all.extend(&pts);
                let name = if job.variants.len() > 1 {
                    format!("{} / {}", record.name, variant.name)
                } else {
                    record.name.clone()
                };
                chart = chart.series(&name, pts, SeriesStyle::Line);
            }
        }
        if all.is_empty() {
            continue;
        }
        // The mean over the records at each intensity of a grid (a hunt's levels differ by record).
        let mean: Vec<(f64, f64)> = grid
            .iter()
            .filter_map(|&x| {
                let ys: Vec<f64> = all.iter().filter(|p| p.0 == x).map(|p| p.1).collect();
                (!ys.is_empty()).then(|| (x, ys.iter().sum::<f64>() / ys.len() as f64))
            })
            .collect();
        if !mean.is_empty() {
            chart = chart.reference("mean", mean, SeriesStyle::Markers);
        }
        if !ended.is_empty() {
            chart = chart.reference("ended at every limit passed (at least)", ended, SeriesStyle::Markers);
        }
        // The code level spans the data and the limits, so that the axis keeps their scale.
        let limits = job.spec.sweep.limit.iter().filter(|l| &l.group == g).map(|l| 100.0 * l.share);
        let y_top = all.iter().map(|p| p.1).chain(limits).fold(1.0f64, f64::max) * 1.1;
        if let Some(c) = job.spec.sweep.code_level {
            let name = format!("site code level {im} = {c}");
            chart = chart.reference(&name, vec![(c, 0.0), (c, y_top)], SeriesStyle::Dashed);
        }
        for l in job.spec.sweep.limit.iter().filter(|l| &l.group == g) {
            chart = chart.reference(
                &format!("limit {:.0} %", 100.0 * l.share),
                vec![(0.0, 100.0 * l.share), (top, 100.0 * l.share)],
                SeriesStyle::Dashed,
            );
        }
        let file = out.join(format!("ida-{g}.png"));
        chart.legend_upper_left().save_png(&file)?;
        n += 1;
    }
    Ok(n)
}
