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
    let e = style.exaggeration;
    let motion = |k: usize| displacements.map_or([0.0; 3], |d| [e * d[k][0], e * d[k][1], e * d[k][2]]);
    let shapes: Vec<Vec<P2>> = (0..np)
        .map(|k| {
            let p = &sample.particles[k];
            p.polygon.vertices.iter().map(|&v| p.moved_point(v, motion(k))).collect()
        })
        .collect();

    // World bounding box: the domain and every drawn vertex.
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
    let map = |p: P2| (margin + s * (p[0] - x0), top + s * (y1 - p[1]));

    let mut out = String::new();
    let w = style.width_px;
    // Writing to a String cannot fail.
    let _ = writeln!(
        out,
        r#"<svg xmlns="http://www.w3.org/2000/svg" width="{w:.0}" height="{height_px:.0}" viewBox="0 0 {w:.1} {height_px:.1}" font-family="sans-serif" font-size="13">"#
    );
    let _ = writeln!(out, r#"<rect width="100%" height="100%" fill="white"/>"#);
    if let Some(t) = &style.title {
        let _ = writeln!(out, r#"<text x="{margin}" y="24" font-size="15">{}</text>"#, escape(t));
    }
    if displacements.is_some() {
        let (a, b) = (map([0.0, sample.height]), map([sample.width, 0.0]));
        let _ = writeln!(
            out,
            r##"<rect x="{:.2}" y="{:.2}" width="{:.2}" height="{:.2}" fill="none" stroke="#999" stroke-dasharray="4 3"/>"##,
            a.0,
            a.1,
            b.0 - a.0,
            b.1 - a.1
        );
    }
    let _ = writeln!(out, r##"<g fill="#ebe3d3" stroke="#4a4a4a" stroke-width="0.8" stroke-linejoin="round">"##);
    for shape in &shapes {
        let pts: Vec<String> = shape
            .iter()
            .map(|&v| {
                let (x, y) = map(v);
                format!("{x:.2},{y:.2}")
            })
            .collect();
        let _ = writeln!(out, r#"<polygon points="{}"/>"#, pts.join(" "));
    }
    let _ = writeln!(out, "</g>");
    if style.draw_beams {
        let _ = writeln!(out, r##"<g stroke="#7a8a99" stroke-width="0.6">"##);
        for b in sample.beams.iter().zip(&is_broken).filter(|(_, &x)| !x).map(|(b, _)| b) {
            let pi = &sample.particles[b.i];
            let pj = &sample.particles[b.j];
            let (a, c) = (map(pi.moved_point(pi.seed, motion(b.i))), map(pj.moved_point(pj.seed, motion(b.j))));
            let _ = writeln!(out, r#"<line x1="{:.2}" y1="{:.2}" x2="{:.2}" y2="{:.2}"/>"#, a.0, a.1, c.0, c.1);
        }
        let _ = writeln!(out, "</g>");
    }
    let colour = |c: u8| style.categories.get(c as usize).map_or("#666666", |k| k.colour.as_str());
    let _ = writeln!(out, r#"<g stroke-width="3.5" stroke-linecap="round">"#);
    for &(k, cat) in broken {
        let b = &sample.beams[k];
        let (pi, pj) = (&sample.particles[b.i], &sample.particles[b.j]);
        let ends: Vec<(f64, f64)> = b
            .facet
            .iter()
            .map(|&f| {
                let (a, c) = (pi.moved_point(f, motion(b.i)), pj.moved_point(f, motion(b.j)));
                map([0.5 * (a[0] + c[0]), 0.5 * (a[1] + c[1])])
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

    // Scale bar: a round length near a fifth of the drawn width.
    let ybar = top + s * (y1 - y0) + 28.0;
    let len = nice_length((x1 - x0) / 5.0);
    let _ = writeln!(
        out,
        r#"<line x1="{margin}" y1="{ybar:.1}" x2="{:.1}" y2="{ybar:.1}" stroke="black" stroke-width="3"/>"#,
        margin + s * len
    );
    let _ =
        writeln!(out, r#"<text x="{:.1}" y="{:.1}">{}</text>"#, margin + s * len + 8.0, ybar + 5.0, length_label(len));
    // Legend: counts per category, then the totals.
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
    let summary = format!(
        "{} stones, {} beams, {} broken{}",
        np,
        sample.beams.len(),
        broken.len(),
        if displacements.is_some() { format!(", displacements × {e}") } else { String::new() }
    );
    let _ =
        writeln!(out, r##"<text x="{margin}" y="{:.1}" fill="#333">{}</text>"##, height_px - 10.0, escape(&summary));
    let _ = writeln!(out, "</svg>");
    Ok(out)
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
