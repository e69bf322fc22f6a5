//! Pictures for people: PNG charts of curves (stress–strain, time histories, spectra).
//!
//! Rendering uses `plotters` with its bitmap backend and a font compiled into the binary
//! (DejaVu Sans, `assets/fonts/`), so a chart looks the same on every machine and needs no
//! system font library.
mod font;
mod line_chart;

pub use line_chart::{LineChart, PlotError, Series, SeriesStyle};
