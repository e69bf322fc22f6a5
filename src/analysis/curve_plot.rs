//! The force–displacement chart of a displacement-controlled nonlinear static run (`curve.png`),
//! with an optional second curve read from a CSV file (e.g. the DEM virtual test of the same
//! wall, `[analysis.control.overlay]`).
use std::path::Path;

use crate::config::CurveOverlayConfig;
use crate::error::{AnalysisError, Error};
use crate::plot::{LineChart, SeriesStyle};

/// Reads the overlay curve: columns `x` and `y` of a CSV file with a header line, scaled.
/// Lines whose two fields do not parse as numbers are skipped; no point at all is an error.
pub fn read_overlay(o: &CurveOverlayConfig) -> Result<Vec<(f64, f64)>, Error> {
    let err = |reason: String| Error::from(AnalysisError::OverlayCurve { file: o.file.clone(), reason });
    let text = std::fs::read_to_string(&o.file).map_err(|e| err(e.to_string()))?;
    let mut lines = text.lines();
    let header: Vec<&str> = lines.next().unwrap_or_default().split(',').map(str::trim).collect();
    let col = |name: &str| {
        header
            .iter()
            .position(|h| *h == name)
            .ok_or_else(|| err(format!("no column '{name}' (columns: {})", header.join(", "))))
    };
    let (ix, iy) = (col(&o.x)?, col(&o.y)?);
    let points: Vec<(f64, f64)> = lines
        .filter_map(|l| {
            let f: Vec<&str> = l.split(',').map(str::trim).collect();
            let x = f.get(ix)?.parse::<f64>().ok()?;
            let y = f.get(iy)?.parse::<f64>().ok()?;
            (x.is_finite() && y.is_finite()).then_some((x * o.x_scale, y * o.y_scale))
        })
        .collect();
    if points.is_empty() {
        return Err(err(format!("no numeric rows in columns '{}' and '{}'", o.x, o.y)));
    }
    Ok(points)
}

/// Draws `curve.png`: the computed control force against the control displacement, and the
/// overlay if given.
pub fn plot_curve(
    path: &Path,
    dof: &str,
    points: &[(f64, f64)],
    overlay: Option<(&str, &[(f64, f64)])>,
) -> Result<(), Error> {
    let mut chart = LineChart::new(
        "Force at the control against its displacement",
        &format!("control displacement {dof} [m]"),
        "control force [N]",
    )
    .series("finite elements", points.to_vec(), SeriesStyle::Line);
    if let Some((label, o)) = overlay {
        chart = chart.series(label, o.to_vec(), SeriesStyle::Dashed);
    }
    Ok(chart.save_png(path)?)
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Columns picked by name and scaled; a missing column names the available ones.
    #[test]
    fn overlay_columns_by_name() {
        let dir = std::env::temp_dir().join(format!("curve-plot-{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        let file = dir.join("c.csv");
        std::fs::write(&file, "state,displacement,stress\n0,0,0\n1,1e-3,2e5\nbad,row\n2,2e-3,1e5\n").unwrap();
        let mut o = CurveOverlayConfig {
            file: file.clone(),
            x: "displacement".into(),
            y: "stress".into(),
            x_scale: 1.0,
            y_scale: 0.5,
            label: "DEM".into(),
        };
        let p = read_overlay(&o).unwrap();
        assert_eq!(p, vec![(0.0, 0.0), (1e-3, 1e5), (2e-3, 5e4)]);
        plot_curve(&dir.join("c.png"), "ux", &[(0.0, 0.0), (1e-3, 9e4)], Some(("DEM", &p))).unwrap();
        assert!(std::fs::metadata(dir.join("c.png")).unwrap().len() > 1000);
        o.y = "force".into();
        let e = read_overlay(&o).unwrap_err().to_string();
        assert!(e.contains("no column 'force'") && e.contains("displacement"), "{e}");
        let _ = std::fs::remove_dir_all(dir);
    }
}
