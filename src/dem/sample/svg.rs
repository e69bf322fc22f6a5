//! A sample drawn as SVG: stones as polygons, optionally the intact beams, broken beams as thick
//! coloured segments along their facet (the crack is the shared edge), a legend and a scale bar.
//!
//! Deformed shapes: particle `k` with `(u_x, u_y, θ)` is drawn moved rigidly about its centroid by
//! `(e u_x, e u_y, e θ)`, `e` the exaggeration factor. A crack (the facet of a broken beam) is drawn
//! at the mean of its images under the motions of its two particles. SVG's y axis points down: a
//! point `(x, y)` goes to `(x₀ + s x, y₀ − s y)`.
use super::builder::Sample;
use super::error::SampleError;
use crate::dem::polygon::P2;
use std::fmt::Write;

/// How one category of broken beams is drawn.
#[derive(Clone, Debug, PartialEq)]
pub struct CrackCategory {
    /// Legend text, e.g. "tension".
    pub label: String,
    /// SVG colour, e.g. "#d62728".
    pub colour: String,
}

/// Drawing options.
#[derive(Clone, Debug, PartialEq)]
pub struct SvgStyle {
    /// Picture width (px).
    pub width_px: f64,
    /// Displacement (and rotation) exaggeration factor `e`.
    pub exaggeration: f64,
    /// Draw the intact beams (seed to seed).
    pub draw_beams: bool,
    /// Category `k` of a broken beam is drawn with `categories[k]`; a missing one in grey.
    pub categories: Vec<CrackCategory>,
    /// A title line.
    pub title: Option<String>,
}

impl Default for SvgStyle {
    /// 800 px wide, no exaggeration, no beams, categories 0 = tension (red), 1 = shear (blue),
    /// 2 = crushing (orange; only with the optional crushing of `dem::mechanics::crushing`).
    fn default() -> Self {
        SvgStyle {
            width_px: 800.0,
            exaggeration: 1.0,
            draw_beams: false,
            categories: vec![
                CrackCategory { label: "tension".into(), colour: "#d62728".into() },
                CrackCategory { label: "shear".into(), colour: "#1f77b4".into() },
                CrackCategory { label: "crushing".into(), colour: "#ff7f0e".into() },
            ],
            title: None,
        }
    }
}

/// The sample as an SVG document.
///
/// `displacements[k] = (u_x, u_y, θ)` of particle `k` (m, m, rad), or `None` for the undeformed
/// sample; `broken` lists `(beam index, category)`. Errors: a displacement count other than the
/// particle count, a beam index past the lattice.
pub fn draw_svg(
    sample: &Sample,
    displacements: Option<&[[f64; 3]]>,
    broken: &[(usize, u8)],
    style: &SvgStyle,
) -> Result<String, SampleError> {
    let is_broken = check_inputs(sample, displacements, broken)?;
    let scene = Scene { sample, displacements, exaggeration: style.exaggeration };
    let shapes: Vec<Vec<P2>> = (0..sample.particles.len())
        .map(|k| {
            let p = &sample.particles[k];
            p.polygon.vertices.iter().map(|&v| p.moved_point(v, scene.motion(k))).collect()
        })
        .collect();
    let frame = Frame::fit(sample, &shapes, style);
    // Writing to a String cannot fail.
    let mut out = String::new();
    let (w, h) = (style.width_px, frame.height_px);
    let _ = writeln!(
        out,
        r#"<svg xmlns="http://www.w3.org/2000/svg" width="{w:.0}" height="{h:.0}" viewBox="0 0 {w:.1} {h:.1}" font-family="sans-serif" font-size="13">"#
    );
    let _ = writeln!(out, r#"<rect width="100%" height="100%" fill="white"/>"#);
    if let Some(t) = &style.title {
        let _ = writeln!(out, r#"<text x="{}" y="24" font-size="15">{}</text>"#, frame.margin, escape(t));
    }
    if displacements.is_some() {
        // The undeformed outline, dashed.
        let (a, b) = (frame.map([0.0, sample.height]), frame.map([sample.width, 0.0]));
        let _ = writeln!(
            out,
            r##"<rect x="{:.2}" y="{:.2}" width="{:.2}" height="{:.2}" fill="none" stroke="#999" stroke-dasharray="4 3"/>"##,
            a.0,
            a.1,
            b.0 - a.0,
            b.1 - a.1
        );
    }
    write_stones(&mut out, &frame, &shapes);
    if style.draw_beams {
        write_intact_beams(&mut out, &frame, &scene, &is_broken);
    }
    write_cracks(&mut out, &frame, &scene, broken, style);
    write_scale_and_legend(&mut out, &frame, &scene, broken, style);
    let _ = writeln!(out, "</svg>");
    Ok(out)
}

/// The beam flags `broken` marks, after checking the displacement count and the beam indices.
fn check_inputs(
    sample: &Sample,
    displacements: Option<&[[f64; 3]]>,
    broken: &[(usize, u8)],
) -> Result<Vec<bool>, SampleError> {
    let np = sample.particles.len();
    if let Some(d) = displacements {
        if d.len() != np {
            return Err(SampleError::DisplacementCount { got: d.len(), expected: np });
        }
    }
    let mut is_broken = vec![false; sample.beams.len()];
    for &(b, _) in broken {
        if b >= sample.beams.len() {
            return Err(SampleError::BeamIndex { index: b, count: sample.beams.len() });
        }
        is_broken[b] = true;
    }
    Ok(is_broken)
}

/// The sample with its (exaggerated) particle motions.
struct Scene<'s> {
    sample: &'s Sample,
    displacements: Option<&'s [[f64; 3]]>,
    exaggeration: f64,
}

impl Scene<'_> {
    /// `e (u_x, u_y, θ)` of particle `k` (zero undeformed).
    fn motion(&self, k: usize) -> [f64; 3] {
        let e = self.exaggeration;
        self.displacements.map_or([0.0; 3], |d| [e * d[k][0], e * d[k][1], e * d[k][2]])
    }

    /// Point `v` of particle `k`, moved with it.
    fn moved(&self, k: usize, v: P2) -> P2 {
        self.sample.particles[k].moved_point(v, self.motion(k))
    }
}

/// World to picture: `(x, y) → (margin + s (x − x₀), top + s (y₁ − y))`, the world box holding
/// the domain and every drawn vertex, with room for the title above and the legend below.
struct Frame {
    margin: f64,
    top: f64,
    /// Pixels per metre.
    s: f64,
    x0: f64,
    y0: f64,
    x1: f64,
    y1: f64,
    height_px: f64,
}

impl Frame {
    fn fit(sample: &Sample, shapes: &[Vec<P2>], style: &SvgStyle) -> Frame {
        let (mut x0, mut y0, mut x1, mut y1) = (0.0f64, 0.0f64, sample.width, sample.height);
        for v in shapes.iter().flatten() {
            x0 = x0.min(v[0]);
            y0 = y0.min(v[1]);
            x1 = x1.max(v[0]);
            y1 = y1.max(v[1]);
        }
        let margin = 30.0;
        let top = if style.title.is_some() { 40.0 } else { margin };
        let bottom = 40.0 + 22.0 * (style.categories.len() as f64 / 2.0).ceil().max(1.0) + 20.0;
        let s = (style.width_px - 2.0 * margin) / (x1 - x0).max(f64::MIN_POSITIVE);
        let height_px = top + s * (y1 - y0) + bottom;
        Frame { margin, top, s, x0, y0, x1, y1, height_px }
    }

    fn map(&self, p: P2) -> (f64, f64) {
        (self.margin + self.s * (p[0] - self.x0), self.top + self.s * (self.y1 - p[1]))
    }
}

/// The stones as filled polygons.
fn write_stones(out: &mut String, frame: &Frame, shapes: &[Vec<P2>]) {
    let _ = writeln!(out, r##"<g fill="#ebe3d3" stroke="#4a4a4a" stroke-width="0.8" stroke-linejoin="round">"##);
    for shape in shapes {
        let pts: Vec<String> = shape
            .iter()
            .map(|&v| {
                let (x, y) = frame.map(v);
                format!("{x:.2},{y:.2}")
            })
            .collect();
        let _ = writeln!(out, r#"<polygon points="{}"/>"#, pts.join(" "));
    }
    let _ = writeln!(out, "</g>");
}

/// The intact beams, seed to seed.
fn write_intact_beams(out: &mut String, frame: &Frame, scene: &Scene<'_>, is_broken: &[bool]) {
    let sample = scene.sample;
    let _ = writeln!(out, r##"<g stroke="#7a8a99" stroke-width="0.6">"##);
    for b in sample.beams.iter().zip(is_broken).filter(|(_, &x)| !x).map(|(b, _)| b) {
        let (pi, pj) = (&sample.particles[b.i], &sample.particles[b.j]);
        let (a, c) = (frame.map(scene.moved(b.i, pi.seed)), frame.map(scene.moved(b.j, pj.seed)));
        let _ = writeln!(out, r#"<line x1="{:.2}" y1="{:.2}" x2="{:.2}" y2="{:.2}"/>"#, a.0, a.1, c.0, c.1);
    }
    let _ = writeln!(out, "</g>");
}

/// The broken beams as thick segments along their facet, coloured by category.
fn write_cracks(out: &mut String, frame: &Frame, scene: &Scene<'_>, broken: &[(usize, u8)], style: &SvgStyle) {
    let colour = |c: u8| style.categories.get(c as usize).map_or("#666666", |k| k.colour.as_str());
    let _ = writeln!(out, r#"<g stroke-width="3.5" stroke-linecap="round">"#);
    for &(k, cat) in broken {
        let b = &scene.sample.beams[k];
        let ends: Vec<(f64, f64)> = b
            .facet
            .iter()
            .map(|&f| {
                let (a, c) = (scene.moved(b.i, f), scene.moved(b.j, f));
                frame.map([0.5 * (a[0] + c[0]), 0.5 * (a[1] + c[1])])
            })
            .collect();
        let _ = writeln!(
            out,
            r#"<line x1="{:.2}" y1="{:.2}" x2="{:.2}" y2="{:.2}" stroke="{}"/>"#,
            ends[0].0,
            ends[0].1,
            ends[1].0,
            ends[1].1,
            colour(cat)
        );
    }
    let _ = writeln!(out, "</g>");
}

/// The scale bar (a round length near a fifth of the drawn width), the legend with the count of
/// each category, and the summary line.
fn write_scale_and_legend(
    out: &mut String,
    frame: &Frame,
    scene: &Scene<'_>,
    broken: &[(usize, u8)],
    style: &SvgStyle,
) {
    let (margin, s) = (frame.margin, frame.s);
    let ybar = frame.top + s * (frame.y1 - frame.y0) + 28.0;
    let len = nice_length((frame.x1 - frame.x0) / 5.0);
    let _ = writeln!(
        out,
        r#"<line x1="{margin}" y1="{ybar:.1}" x2="{:.1}" y2="{ybar:.1}" stroke="black" stroke-width="3"/>"#,
        margin + s * len
    );
    let _ =
        writeln!(out, r#"<text x="{:.1}" y="{:.1}">{}</text>"#, margin + s * len + 8.0, ybar + 5.0, length_label(len));
    let mut counts = vec![0usize; style.categories.len()];
    let mut other = 0;
    for &(_, c) in broken {
        match counts.get_mut(c as usize) {
            Some(n) => *n += 1,
            None => other += 1,
        }
    }
    let lx = margin + 0.4 * (style.width_px - 2.0 * margin);
    let mut entries: Vec<(String, String)> = style
        .categories
        .iter()
        .zip(&counts)
        .map(|(c, n)| (c.colour.clone(), format!("{} ({n})", escape(&c.label))))
        .collect();
    if other > 0 {
        entries.push(("#666666".into(), format!("other ({other})")));
    }
    for (r, (col, text)) in entries.iter().enumerate() {
        let (cx, cy) = (lx + 150.0 * (r % 2) as f64, ybar - 4.0 + 22.0 * (r / 2) as f64);
        let _ = writeln!(
            out,
            r#"<line x1="{cx:.1}" y1="{cy:.1}" x2="{:.1}" y2="{cy:.1}" stroke="{col}" stroke-width="3.5" stroke-linecap="round"/><text x="{:.1}" y="{:.1}">{text}</text>"#,
            cx + 24.0,
            cx + 32.0,
            cy + 5.0
        );
    }
    let sample = scene.sample;
    let summary = format!(
        "{} stones, {} beams, {} broken{}",
        sample.particles.len(),
        sample.beams.len(),
        broken.len(),
        if scene.displacements.is_some() {
            format!(", displacements × {}", scene.exaggeration)
        } else {
            String::new()
        }
    );
    let _ = writeln!(
        out,
        r##"<text x="{margin}" y="{:.1}" fill="#333">{}</text>"##,
        frame.height_px - 10.0,
        escape(&summary)
    );
}

/// The largest of `{1, 2, 5} × 10^k` not above `target`.
fn nice_length(target: f64) -> f64 {
    let p = 10f64.powf(target.log10().floor());
    [5.0, 2.0, 1.0].into_iter().map(|m| m * p).find(|&l| l <= target).unwrap_or(p)
}

fn length_label(l: f64) -> String {
    if l >= 1.0 {
        format!("{:.0} m", l)
    } else if l >= 0.01 {
        format!("{:.0} cm", l * 100.0)
    } else {
        format!("{} mm", l * 1000.0)
    }
}

fn escape(s: &str) -> String {
    s.replace('&', "&amp;").replace('<', "&lt;").replace('>', "&gt;").replace('"', "&quot;")
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn nice_scale_bar_lengths() {
        // 1.0/5 = 0.2 → 20 cm; 0.33 → 0.2 m... 0.33 ≥ 0.2: 20 cm; 7 → 5 m; 0.004 → 2 mm.
        assert_eq!(length_label(nice_length(0.2)), "20 cm");
        assert_eq!(length_label(nice_length(0.33)), "20 cm");
        assert_eq!(length_label(nice_length(7.0)), "5 m");
        assert_eq!(length_label(nice_length(0.004)), "2 mm");
        assert_eq!(escape("a<b & \"c\""), "a&lt;b &amp; &quot;c&quot;");
    }
}
