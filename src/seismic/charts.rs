//! PNG charts of ground motion: a record's response spectra against code spectra (like the
//! paper's Fig. 7), a record set's spectra against its target, and an acceleration time history.
//! Linear axes; spectra on 0–4 s as in Eurocode figures.
use super::ec8::Ec8Spectrum;
use super::record::Record;
use super::record_set::RecordSet;
use super::spectrum::ResponseSpectrum;
use crate::plot::{LineChart, PlotError, SeriesStyle};
use std::path::Path;

/// Sa(T) of records (solid lines) against code spectra `(label, (T, Se) points)` (dashed), T ≤ 4 s.
pub fn spectrum_png(
    path: &Path,
    title: &str,
    records: &[(&str, &ResponseSpectrum)],
    code_spectra: &[(String, Vec<(f64, f64)>)],
) -> Result<(), PlotError> {
    let mut chart = LineChart::new(title, "period T [s]", "spectral acceleration Sa, Se [m/s²]");
    for (label, s) in records {
        let pts = s.sa_curve().into_iter().filter(|p| p.0 <= 4.0).collect();
        chart = chart.series(&format!("{label} (ζ = {}%)", s.damping * 100.0), pts, SeriesStyle::Line);
    }
    for (label, pts) in code_spectra {
        chart = chart.series(label, pts.iter().copied().filter(|p| p.0 <= 4.0).collect(), SeriesStyle::Dashed);
    }
    chart.save_png(path)
}

/// A record set's 5 %-damped spectra (one colour), their mean, the target Se, `fraction`·Se, and
/// the check's period range shaded, for T ≤ `t_max` [s].
pub fn record_set_png(
    path: &Path,
    title: &str,
    set: &RecordSet,
    target: &Ec8Spectrum,
    fraction: f64,
    t_max: f64,
) -> Result<(), PlotError> {
    let keep = |pts: Vec<(f64, f64)>| pts.into_iter().filter(|p| p.0 <= t_max).collect::<Vec<_>>();
    let (a, b) = set.check.range;
    let mut chart = LineChart::new(title, "period T [s]", "spectral acceleration Sa, Se [m/s²] (5 % damping)").x_band(
        &format!("check range [{a:.3}, {b:.3}] s"),
        a,
        b,
    );
    for (i, m) in set.members.iter().enumerate() {
        let name = if i == 0 { format!("records ({})", set.members.len()) } else { String::new() };
        chart = chart.series(&name, keep(m.spectrum.sa_curve()), SeriesStyle::Line);
    }
    let mean = super::compatibility::mean_sa(&set.members.iter().map(|m| m.spectrum.clone()).collect::<Vec<_>>());
    chart = chart.series("mean of the set", keep(set.periods.iter().copied().zip(mean).collect()), SeriesStyle::Line);
    let fine: Vec<f64> = (0..=400).map(|i| i as f64 * t_max / 400.0).collect();
    let se = target.curve(&fine);
    let lower = se.iter().map(|&(t, s)| (t, fraction * s)).collect();
    chart
        .series(&format!("EC8 target Se (a_g = {} m/s², S = {})", target.ag, target.s), se, SeriesStyle::Dashed)
        .series(&format!("{} Se", fraction), lower, SeriesStyle::Dashed)
        .save_png(path)
}

/// The acceleration time history of a record.
pub fn record_png(path: &Path, r: &Record) -> Result<(), PlotError> {
    let pts = r.accel.iter().enumerate().map(|(i, a)| (i as f64 * r.dt, *a)).collect();
    LineChart::new(&format!("{}: ground acceleration", r.name), "time t [s]", "acceleration a [m/s²]")
        .size(1200, 500)
        .series(&r.name, pts, SeriesStyle::Line)
        .save_png(path)
}
