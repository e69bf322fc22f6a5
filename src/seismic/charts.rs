//! PNG charts of ground motion: a record's response spectra against code spectra (like the
//! paper's Fig. 7), and an acceleration time history. Linear axes; spectra on 0–4 s as in
//! Eurocode figures.
use super::record::Record;
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

/// The acceleration time history of a record.
pub fn record_png(path: &Path, r: &Record) -> Result<(), PlotError> {
    let pts = r.accel.iter().enumerate().map(|(i, a)| (i as f64 * r.dt, *a)).collect();
    LineChart::new(&format!("{}: ground acceleration", r.name), "time t [s]", "acceleration a [m/s²]")
        .size(1200, 500)
        .series(&r.name, pts, SeriesStyle::Line)
        .save_png(path)
}
