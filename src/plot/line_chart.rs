//! A line chart: several named series of (x, y) points on linear axes, saved as PNG.
use super::font;
use plotters::prelude::*;
use std::path::{Path, PathBuf};

/// A closed interval of a coordinate, `(low, high)`.
type Span = (f64, f64);

/// Errors drawing a chart.
#[derive(Debug, thiserror::Error)]
pub enum PlotError {
    /// The chart cannot be drawn from these data.
    #[error("chart '{title}': {reason}")]
    Data {
        /// The chart's title.
        title: String,
        /// What is wrong.
        reason: String,
    },
    /// Rendering or writing the file failed.
    #[error("cannot write chart {}: {message}", path.display())]
    Render {
        /// The file.
        path: PathBuf,
        /// What the backend said.
        message: String,
    },
}

/// How a series is drawn.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum SeriesStyle {
    /// A polyline.
    Line,
    /// Markers only (e.g. experimental points).
    Markers,
    /// A dashed polyline (e.g. a reference or code spectrum).
    Dashed,
}

/// One named series.
#[derive(Clone, Debug)]
pub struct Series {
    /// Legend entry.
    pub name: String,
    /// Points.
    pub points: Vec<(f64, f64)>,
    /// Style.
    pub style: SeriesStyle,
    /// A reference (a mean, a code level, a limit): drawn in black, outside the palette.
    pub reference: bool,
}

/// A chart under construction.
#[derive(Clone, Debug)]
pub struct LineChart {
    title: String,
    x_label: String,
    y_label: String,
    series: Vec<Series>,
    bands: Vec<Band>,
    size: (u32, u32),
    /// The legend in the upper left corner (for data that rise to the right).
    legend_left: bool,
}

/// A shaded vertical band `x0 ≤ x ≤ x1` behind the series (e.g. a period range), with a legend entry.
#[derive(Clone, Debug)]
struct Band {
    name: String,
    span: Span,
}

const BAND_COLOUR: RGBColor = RGBColor(255, 220, 120);

const PALETTE: [RGBColor; 6] = [
    RGBColor(31, 119, 180),
    RGBColor(214, 39, 40),
    RGBColor(44, 160, 44),
    RGBColor(255, 127, 14),
    RGBColor(148, 103, 189),
    RGBColor(90, 90, 90),
];

impl LineChart {
    /// A chart with a title and axis labels (include units: "strain [-]", "stress [MPa]").
    pub fn new(title: &str, x_label: &str, y_label: &str) -> LineChart {
        LineChart {
            title: title.into(),
            x_label: x_label.into(),
            y_label: y_label.into(),
            series: Vec::new(),
            bands: Vec::new(),
            size: (1000, 700),
            legend_left: false,
        }
    }

    /// Adds a series.
    pub fn series(mut self, name: &str, points: Vec<(f64, f64)>, style: SeriesStyle) -> LineChart {
        self.series.push(Series { name: name.into(), points, style, reference: false });
        self
    }

    /// Puts the legend in the upper left corner (curves that rise to the right).
    pub fn legend_upper_left(mut self) -> LineChart {
        self.legend_left = true;
        self
    }

    /// Adds a reference series (a mean, a code level, a limit): black, so that it cannot be taken
    /// for one of the data series, which keep the palette.
    pub fn reference(mut self, name: &str, points: Vec<(f64, f64)>, style: SeriesStyle) -> LineChart {
        self.series.push(Series { name: name.into(), points, style, reference: true });
        self
    }

    /// Adds a shaded vertical band over `x0 ≤ x ≤ x1`, drawn behind the series.
    pub fn x_band(mut self, name: &str, x0: f64, x1: f64) -> LineChart {
        self.bands.push(Band { name: name.into(), span: (x0.min(x1), x0.max(x1)) });
        self
    }

    /// Image size in pixels (default 1000 × 700).
    pub fn size(mut self, width: u32, height: u32) -> LineChart {
        self.size = (width, height);
        self
    }

    /// The data range `((x0, x1), (y0, y1))`, padded by 5%; an error when there is no finite point.
    fn range(&self) -> Result<(Span, Span), PlotError> {
        let pts = self.series.iter().flat_map(|s| s.points.iter()).filter(|p| p.0.is_finite() && p.1.is_finite());
        let (mut x0, mut x1, mut y0, mut y1) = (f64::INFINITY, f64::NEG_INFINITY, f64::INFINITY, f64::NEG_INFINITY);
        for &(x, y) in pts {
            x0 = x0.min(x);
            x1 = x1.max(x);
            y0 = y0.min(y);
            y1 = y1.max(y);
        }
        if !x0.is_finite() {
            return Err(PlotError::Data { title: self.title.clone(), reason: "no finite data point".into() });
        }
        let pad = |a: f64, b: f64| {
            let d = if b > a { 0.05 * (b - a) } else { 0.5 * a.abs().max(1.0) };
            (a - d, b + d)
        };
        Ok((pad(x0, x1), pad(y0, y1)))
    }

    /// The colour of each series: named series take the palette's colours in turn; a series
    /// without a name (one of many samples) continues the group of the named series before it,
    /// so a legend entry's colour is that of every curve it stands for.
    fn colours(&self) -> Vec<RGBColor> {
        let mut k = 0;
        self.series
            .iter()
            .enumerate()
            .map(|(i, s)| {
                if s.reference {
                    return BLACK;
                }
                if i > 0 && !s.name.is_empty() {
                    k += 1;
                }
                PALETTE[k % PALETTE.len()]
            })
            .collect()
    }

    /// Draws the chart to a PNG file.
    pub fn save_png(&self, path: &Path) -> Result<(), PlotError> {
        let ((x0, x1), (y0, y1)) = self.range()?;
        font::ensure_registered();
        let render = |e: &dyn std::fmt::Display| PlotError::Render { path: path.to_path_buf(), message: e.to_string() };
        let root = BitMapBackend::new(path, self.size).into_drawing_area();
        root.fill(&WHITE).map_err(|e| render(&e))?;
        let mut chart = ChartBuilder::on(&root)
            .caption(&self.title, (font::FAMILY, 26))
            .margin(20)
            .x_label_area_size(55)
            .y_label_area_size(85)
            .build_cartesian_2d(x0..x1, y0..y1)
            .map_err(|e| render(&e))?;
        chart
            .configure_mesh()
            .x_desc(&self.x_label)
            .y_desc(&self.y_label)
            .label_style((font::FAMILY, 16))
            .axis_desc_style((font::FAMILY, 18))
            .light_line_style(RGBColor(240, 240, 240))
            .max_light_lines(2)
            .draw()
            .map_err(|e| render(&e))?;
        for b in &self.bands {
            let (a, c) = (b.span.0.max(x0), b.span.1.min(x1));
            let fill = BAND_COLOUR.mix(0.45).filled();
            chart
                .draw_series(std::iter::once(Rectangle::new([(a, y0), (c, y1)], fill)))
                .map_err(|e| render(&e))?
                .label(b.name.clone())
                .legend(move |(x, y)| Rectangle::new([(x, y - 6), (x + 20, y + 6)], fill));
        }
        for (s, color) in self.series.iter().zip(self.colours()) {
            let pts: Vec<(f64, f64)> =
                s.points.iter().copied().filter(|p| p.0.is_finite() && p.1.is_finite()).collect();
            // A dense trace (an accelerogram: more points than half the pixels across) is drawn 1
            // pixel wide: plotters draws a wider stroke of a near-vertical segment with gaps.
            let width = if 2 * pts.len() > self.size.0 as usize { 1 } else { 2 };
            let anno = match s.style {
                SeriesStyle::Line => chart.draw_series(LineSeries::new(pts, color.stroke_width(width))),
                SeriesStyle::Dashed => chart.draw_series(DashedLineSeries::new(pts, 8, 5, color.stroke_width(width))),
                SeriesStyle::Markers => chart.draw_series(pts.into_iter().map(|p| Circle::new(p, 5, color.filled()))),
            }
            .map_err(|e| render(&e))?;
            // A series without a name (one of many samples) gets no legend entry.
            // Its legend entry is drawn as the series is: a line, a dashed line or a dot.
            if !s.name.is_empty() {
                let entry = anno.label(s.name.clone());
                match s.style {
                    SeriesStyle::Line => {
                        entry.legend(move |(x, y)| PathElement::new(vec![(x, y), (x + 20, y)], color.stroke_width(3)));
                    }
                    SeriesStyle::Dashed => {
                        entry.legend(move |(x, y)| {
                            EmptyElement::at((x, y))
                                + PathElement::new(vec![(0, 0), (8, 0)], color.stroke_width(3))
                                + PathElement::new(vec![(13, 0), (20, 0)], color.stroke_width(3))
                        });
                    }
                    SeriesStyle::Markers => {
                        entry.legend(move |(x, y)| Circle::new((x + 10, y), 5, color.filled()));
                    }
                }
            }
        }
        if self.series.iter().filter(|s| !s.name.is_empty()).count() + self.bands.len() > 1 {
            chart
                .configure_series_labels()
                .label_font((font::FAMILY, 16))
                .background_style(WHITE.mix(0.85))
                .border_style(BLACK)
                .position(if self.legend_left {
                    SeriesLabelPosition::UpperLeft
                } else {
                    SeriesLabelPosition::UpperRight
                })
                .draw()
                .map_err(|e| render(&e))?;
        }
        root.present().map_err(|e| render(&e))?;
        Ok(())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn unnamed_series_share_the_colour_of_their_group() {
        let c = LineChart::new("t", "x", "y")
            .series("samples", vec![(0.0, 0.0)], SeriesStyle::Line)
            .series("", vec![(0.0, 1.0)], SeriesStyle::Line)
            .series("", vec![(0.0, 2.0)], SeriesStyle::Line)
            .series("experiment", vec![(0.0, 3.0)], SeriesStyle::Markers)
            .series("law", vec![(0.0, 4.0)], SeriesStyle::Line);
        assert_eq!(c.colours(), vec![PALETTE[0], PALETTE[0], PALETTE[0], PALETTE[1], PALETTE[2]]);
    }

    #[test]
    fn references_are_black_and_leave_the_palette_to_the_data() {
        let c = LineChart::new("t", "x", "y")
            .series("a", vec![(0.0, 0.0)], SeriesStyle::Line)
            .reference("mean", vec![(0.0, 1.0)], SeriesStyle::Markers)
            .series("b", vec![(0.0, 2.0)], SeriesStyle::Line);
        assert_eq!(c.colours(), vec![PALETTE[0], BLACK, PALETTE[1]]);
    }

    #[test]
    fn a_chart_is_written_as_png() {
        let dir = std::env::temp_dir().join(format!("mhpc-plot-{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        let f = dir.join("sine.png");
        let pts: Vec<(f64, f64)> = (0..200).map(|i| (i as f64 * 0.05, (i as f64 * 0.05).sin())).collect();
        LineChart::new("sin(x)", "x [rad]", "sin x [-]")
            .series("sin", pts, SeriesStyle::Line)
            .series("points", vec![(1.0, 0.8), (2.0, 0.9)], SeriesStyle::Markers)
            .series("chord", vec![(0.0, 1.0), (3.0, -1.0)], SeriesStyle::Dashed)
            .x_band("a band", 2.0, 4.0)
            .save_png(&f)
            .unwrap();
        let bytes = std::fs::read(&f).unwrap();
        assert_eq!(&bytes[1..4], b"PNG", "a PNG signature");
        assert!(bytes.len() > 5_000, "a chart, not an empty image: {} bytes", bytes.len());
    }

    /// A dense zigzag (2000 points across 600 pixels, every segment near-vertical) is drawn
    /// without gaps: in the middle third of the trace, each pixel column is coloured over at
    /// least 95 % of the rows between the trace's extremes (less 10 % at each end).
    #[test]
    fn a_dense_trace_is_drawn_without_gaps() {
        let dir = std::env::temp_dir().join(format!("mhpc-plot-dense-{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        let f = dir.join("zigzag.png");
        let pts: Vec<(f64, f64)> = (0..2000).map(|i| (0.01 * i as f64, if i % 2 == 0 { 1.0 } else { -1.0 })).collect();
        LineChart::new("zigzag", "t", "a").size(600, 400).series("a", pts, SeriesStyle::Line).save_png(&f).unwrap();
        let img = image::open(&f).unwrap().to_rgb8();
        let c = PALETTE[0];
        let ours = |x: u32, y: u32| {
            let p = img.get_pixel(x, y).0;
            (p[0] as i32 - c.0 as i32).abs() + (p[1] as i32 - c.1 as i32).abs() + (p[2] as i32 - c.2 as i32).abs() < 90
        };
        let (w, h) = img.dimensions();
        let hits: Vec<(u32, u32)> =
            (0..w).flat_map(|x| (0..h).map(move |y| (x, y))).filter(|&(x, y)| ours(x, y)).collect();
        let (x0, x1) = (hits.iter().map(|p| p.0).min().unwrap(), hits.iter().map(|p| p.0).max().unwrap());
        let (y0, y1) = (hits.iter().map(|p| p.1).min().unwrap(), hits.iter().map(|p| p.1).max().unwrap());
        let (r0, r1) = (y0 + (y1 - y0) / 10, y1 - (y1 - y0) / 10);
        for x in x0 + (x1 - x0) / 3..x1 - (x1 - x0) / 3 {
            let covered = (r0..=r1).filter(|&y| ours(x, y)).count() as f64 / (r1 - r0 + 1) as f64;
            assert!(covered >= 0.95, "column {x}: {:.1} % of the trace's height drawn", 100.0 * covered);
        }
        std::fs::remove_dir_all(dir).unwrap();
    }

    #[test]
    fn no_data_is_an_error() {
        let e = LineChart::new("empty", "x", "y").save_png(Path::new("/nonexistent/x.png")).unwrap_err();
        assert!(e.to_string().contains("no finite data point"), "{e}");
    }
}
