//! Monitored nodes: their relative displacement and absolute acceleration at every step, to
//! `monitors.csv` (rank 0 appends a row per step and flushes it, so a killed run keeps its rows)
//! and, at the end, one PNG per node.
//!
//! A monitor names a node by its Gmsh tag, or by a physical group and a point: the group's node
//! nearest to it. The rank that owns the node supplies its values; a sum over ranks brings them to
//! every rank (the others add zeros), with the base reactions and the drifts of the same row
//! (`step_output.rs`).
use crate::config::MonitorConfig;
use crate::error::{AnalysisError, Error};
use crate::io::IoError;
use crate::mesh::Mesh;
use crate::parallel::{Context, DofMap};
use mpi::traits::CommunicatorCollectives;
use std::io::Write;
use std::path::{Path, PathBuf};

/// Values per monitor per row: u_x, u_y, u_z (relative), a_x, a_y, a_z (absolute).
pub const VALUES: usize = 6;

/// One resolved monitor.
#[derive(Clone, Debug)]
pub struct Monitor {
    /// Its name.
    pub name: String,
    /// Mesh node index.
    pub node: usize,
    /// Gmsh tag.
    pub tag: u64,
    /// Its coordinates [m].
    pub at: [f64; 3],
    /// Index among this rank's owned nodes, if it owns it.
    pub owned_index: Option<usize>,
}

/// A monitor or a drift (`key`, with its name) that cannot be placed on the model.
pub(super) fn placement(key: &str, reason: String) -> Error {
    AnalysisError::Placement { key: key.to_string(), reason }.into()
}

/// Resolves the job's monitors against the mesh (errors name the monitor).
pub fn resolve(cfg: &[MonitorConfig], mesh: &Mesh, dofs: &DofMap) -> Result<Vec<Monitor>, Error> {
    let mut out = Vec::new();
    for (i, m) in cfg.iter().enumerate() {
        let what = format!("dynamics.monitor[{i}] ('{}')", m.name);
        let node = match (m.node, &m.group, m.near) {
            (Some(tag), _, _) => mesh
                .node_tags
                .iter()
                .position(|&t| t == tag)
                .ok_or_else(|| placement(&what, format!("the mesh has no node with tag {tag}")))?,
            (None, Some(g), Some(p)) => {
                let group = mesh.group(g).map_err(|e| placement(&what, e.to_string()))?;
                let nodes = mesh.nodes_in_group(group);
                let d2 = |n: usize| (0..3).map(|k| (mesh.coords[n][k] - p[k]).powi(2)).sum::<f64>();
                nodes
                    .into_iter()
                    .filter(|&n| dofs.global[n] != usize::MAX)
                    .min_by(|&a, &b| d2(a).total_cmp(&d2(b)))
                    .ok_or_else(|| placement(&what, format!("group '{g}' has no node of the model")))?
            }
            _ => return Err(placement(&what, "give node, or group with near".into())),
        };
        if dofs.global[node] == usize::MAX {
            return Err(placement(&what, format!("node {} belongs to no element of the model", mesh.node_tags[node])));
        }
        let owned_index = dofs.owned.iter().position(|&n| n == node);
        out.push(Monitor { name: m.name.clone(), node, tag: mesh.node_tags[node], at: mesh.coords[node], owned_index });
    }
    Ok(out)
}

/// This rank's share of the monitors' values this step: the owner's relative displacement `u`
/// and absolute acceleration `a_abs` (owned DOFs, 6 per node), zeros for the nodes it does not
/// own; summed over ranks, the values.
pub fn local_values(monitors: &[Monitor], u: &[f64], a_abs: &[f64]) -> Vec<f64> {
    let mut local = vec![0.0; VALUES * monitors.len()];
    for (k, m) in monitors.iter().enumerate() {
        if let Some(i) = m.owned_index {
            local[VALUES * k..VALUES * k + 3].copy_from_slice(&u[6 * i..6 * i + 3]);
            local[VALUES * k + 3..VALUES * k + 6].copy_from_slice(&a_abs[6 * i..6 * i + 3]);
        }
    }
    local
}

/// Collective. `local` summed over the ranks, on every rank.
pub fn sum_over_ranks(ctx: &Context, local: &[f64]) -> Vec<f64> {
    let mut global = vec![0.0; local.len()];
    if !local.is_empty() {
        ctx.comm.all_reduce_into(local, &mut global[..], mpi::collective::SystemOperation::sum());
    }
    global
}

/// The largest |value| of each named column of a CSV file written by [`CsvLog`] and the `time`
/// of its row (the first such row), in the order of `names`; NaN for a missing column.
pub fn column_peaks(csv: &Path, names: &[String]) -> Result<Vec<(f64, f64)>, IoError> {
    let text = std::fs::read_to_string(csv).map_err(|source| IoError::Read { file: csv.to_path_buf(), source })?;
    let mut lines = text.lines();
    let header: Vec<&str> = lines.next().unwrap_or_default().split(',').collect();
    let cols: Vec<Option<usize>> = names.iter().map(|n| header.iter().position(|h| h == n)).collect();
    let mut peaks: Vec<(f64, f64)> =
        cols.iter().map(|c| if c.is_some() { (0.0, 0.0) } else { (f64::NAN, f64::NAN) }).collect();
    for line in lines {
        let v: Vec<f64> = line.split(',').map(|x| x.trim().parse().unwrap_or(f64::NAN)).collect();
        let t = v.get(1).copied().unwrap_or(f64::NAN);
        for (p, c) in peaks.iter_mut().zip(&cols) {
            if let Some(x) = c.and_then(|c| v.get(c)) {
                if x.abs() > p.0 {
                    *p = (x.abs(), t);
                }
            }
        }
    }
    Ok(peaks)
}

/// The CSV header.
pub fn header(monitors: &[Monitor]) -> String {
    let mut h = String::from("step,time");
    for m in monitors {
        for q in ["ux", "uy", "uz", "ax_abs", "ay_abs", "az_abs"] {
            h += &format!(",{}:{q}", m.name);
        }
    }
    h
}

/// A CSV file that rank 0 appends rows to, flushed per row; on a restart, rows after the
/// checkpoint's step are dropped first, so the file continues exactly where the state does.
pub struct CsvLog {
    file: Option<std::fs::File>,
    /// Its path.
    pub path: PathBuf,
}

impl CsvLog {
    /// Rank 0 creates (or, with `restart_step`, truncates after that step and reopens) `path`.
    pub fn open(ctx: &Context, path: &Path, header: &str, restart_step: Option<usize>) -> Result<CsvLog, Error> {
        let opened = if ctx.rank == 0 {
            (|| -> std::io::Result<std::fs::File> {
                let mut text = format!("{header}\n");
                if let Some(k) = restart_step {
                    if let Ok(old) = std::fs::read_to_string(path) {
                        for line in old.lines().skip(1) {
                            match line.split(',').next().and_then(|s| s.parse::<usize>().ok()) {
                                Some(s) if s <= k => text += &format!("{line}\n"),
                                _ => {}
                            }
                        }
                    }
                }
                let mut f = std::fs::File::create(path)?;
                f.write_all(text.as_bytes())?;
                f.flush()?;
                Ok(f)
            })()
            .map(Some)
            .map_err(|source| Error::from(IoError::Write { file: path.to_path_buf(), source }))
        } else {
            Ok(None)
        };
        let file = crate::parallel::agree(&ctx.comm, opened, Error::exit_code)?;
        Ok(CsvLog { file, path: path.to_path_buf() })
    }

    /// Rank 0 appends a row (write errors are reported once, then the file is dropped).
    pub fn row(&mut self, line: &str, log: &crate::parallel::Log) {
        if let Some(f) = &mut self.file {
            if let Err(e) = writeln!(f, "{line}").and_then(|_| f.flush()) {
                log.warn(format!("cannot append to {}: {e}; no more rows", self.path.display()));
                self.file = None;
            }
        }
    }
}

/// Rank 0 draws one PNG per monitor from the CSV file: the relative displacement against time,
/// in millimetres, one line per component with its peak |u| in the legend.
pub fn draw(csv: &Path, monitors: &[Monitor], dir: &Path) -> Result<Vec<PathBuf>, Error> {
    use crate::plot::{LineChart, SeriesStyle};
    let text = std::fs::read_to_string(csv).map_err(|source| IoError::Read { file: csv.to_path_buf(), source })?;
    let rows: Vec<Vec<f64>> =
        text.lines().skip(1).map(|l| l.split(',').filter_map(|x| x.parse().ok()).collect()).collect();
    let mut files = Vec::new();
    for (k, m) in monitors.iter().enumerate() {
        let [x, y, z] = m.at;
        let title = format!(
            "monitor '{}' (node {} at x {x:.2}, y {y:.2}, z {z:.2} m): displacement relative to the base",
            m.name, m.tag
        );
        let mut chart = LineChart::new(&title, "time t [s]", "displacement u [mm]").size(1200, 700);
        let mut drawn = 0;
        for (c, q) in ["u_x", "u_y", "u_z"].iter().enumerate() {
            let col = 2 + VALUES * k + c;
            let pts: Vec<(f64, f64)> = rows.iter().filter(|r| r.len() > col).map(|r| (r[1], 1e3 * r[col])).collect();
            // Components that stay exactly zero are left out, unless all do.
            if pts.iter().any(|p| p.1 != 0.0) || (c == 2 && drawn == 0) {
                let peak = pts.iter().fold(0.0_f64, |a, p| a.max(p.1.abs()));
                chart = chart.series(&format!("{q} (peak {} mm)", three_digits(peak)), pts, SeriesStyle::Line);
                drawn += 1;
            }
        }
        let file = dir.join(format!("monitor-{}.png", m.name));
        chart.save_png(&file)?;
        files.push(file);
    }
    Ok(files)
}

/// `v` with three significant digits in fixed notation (0.00405, 1.76, 1230).
fn three_digits(v: f64) -> String {
    if v == 0.0 || !v.is_finite() {
        return format!("{v}");
    }
    let decimals = (2 - v.abs().log10().floor() as i32).max(0) as usize;
    format!("{v:.decimals$}")
}

#[cfg(test)]
mod tests {
    use super::three_digits;

    /// Peaks by hand from a three-row file: the largest magnitude and its time; NaN for a column
    /// the header lacks.
    #[test]
    fn column_peaks_are_the_largest_magnitudes_with_their_time() {
        let f = std::env::temp_dir().join(format!("mhpc-column-peaks-{}.csv", std::process::id()));
        std::fs::write(&f, "step,time,reaction_x,drift:a:x\n0,0,1.5,0\n1,0.01,-4.0,2e-3\n2,0.02,3.0,-3e-3\n").unwrap();
        let names: Vec<String> = ["reaction_x", "drift:a:x", "missing"].iter().map(|s| s.to_string()).collect();
        let p = super::column_peaks(&f, &names).unwrap();
        assert_eq!((p[0], p[1]), ((4.0, 0.01), (3e-3, 0.02)));
        assert!(p[2].0.is_nan());
        std::fs::remove_file(f).unwrap();
    }

    #[test]
    fn peaks_keep_three_significant_digits() {
        assert_eq!(three_digits(0.0040512), "0.00405");
        assert_eq!(three_digits(1.7561), "1.76");
        assert_eq!(three_digits(1234.4), "1234");
        assert_eq!(three_digits(0.0), "0");
    }
}
