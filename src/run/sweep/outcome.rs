//! What one member of a sweep ended with, as its group's leader writes it to
//! `members/<name>/outcome.json`: the sweep's table is assembled from these files, so a restarted
//! sweep skips the members that have one.
use crate::analysis::time_history::{GroupDamage, TimeHistorySummary};
use crate::config::{Member, SweepJob};
use crate::error::Error;
use serde::{Deserialize, Serialize};
use std::path::Path;

/// The file name in a member's folder.
pub const OUTCOME_FILE: &str = "outcome.json";

/// How a member ended.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum Status {
    /// The whole duration ran.
    Completed,
    /// A step did not converge even with substeps (or another error stopped it): the diagnosis
    /// says where, the last converged state is checkpointed in the member's folder.
    Stopped,
    /// The material's gravity state could not be found (the model cannot carry its weight).
    GravityFailed,
}

impl Status {
    /// As written in the table.
    pub fn name(self) -> &'static str {
        match self {
            Status::Completed => "completed",
            Status::Stopped => "stopped",
            Status::GravityFailed => "gravity_failed",
        }
    }
}

/// Peak relative displacement of one monitor [m].
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct MonitorPeak {
    /// The monitor's name.
    pub name: String,
    /// Peak |u_x|, |u_y|, |u_z| [m] (`x`, `y`, `z`).
    #[serde(with = "crate::io::summary::xyz")]
    pub peak: [f64; 3],
}

/// One member's outcome.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct Outcome {
    /// The member's folder name.
    pub member: String,
    /// Its material variant.
    pub variant: String,
    /// Its record.
    pub record: String,
    /// The intensity [m/s²].
    pub intensity: f64,
    /// The factor on the record as written.
    pub factor: f64,
    /// How it ended.
    pub status: Status,
    /// Why it stopped.
    pub diagnosis: Option<String>,
    /// Time reached [s].
    pub time_reached: f64,
    /// The time [s] at which it had passed every limit and ended there (`[sweep.hunt]
    /// stop_at_passage`); its shares and peaks are then lower bounds of the whole record's.
    #[serde(default)]
    pub ended_at_limits: Option<f64>,
    /// Peak drift ratio (completed members).
    pub peak_drift_ratio: Option<f64>,
    /// Peak relative displacement over the nodes, `x` `y` `z` [m] (completed members).
    #[serde(with = "crate::io::summary::xyz::option")]
    pub peak_displacement: Option<[f64; 3]>,
    /// Peaks at the monitors (up to the time reached).
    pub monitors: Vec<MonitorPeak>,
    /// Damage per substructure at the end (completed members).
    pub damage: Vec<GroupDamage>,
    /// Newton iterations.
    pub iterations: usize,
    /// Wall seconds of this member's runs.
    pub seconds: f64,
}

impl Outcome {
    /// The outcome of `m` as it ran: completed with `summary`, or stopped with its diagnosis.
    pub fn new(
        job: &SweepJob,
        m: &Member,
        run: &Result<TimeHistorySummary, Error>,
        dir: &Path,
        seconds: f64,
    ) -> Outcome {
        let mut o = Outcome::of(job, m, Status::Completed);
        o.monitors = monitor_peaks(&dir.join("monitors.csv"));
        o.seconds = seconds;
        match run {
            Ok(s) => {
                o.time_reached = s.time;
                o.ended_at_limits = s.stopped_by_shares;
                o.peak_drift_ratio = Some(s.peak_drift_ratio);
                o.peak_displacement = Some(s.peak_displacement);
                o.damage = s.damage_by_group.clone();
                o.iterations = s.iterations;
            }
            Err(e) => {
                o.status = Status::Stopped;
                o.diagnosis = Some(e.to_string());
                o.time_reached = last_time(&dir.join("monitors.csv")).unwrap_or(0.0);
            }
        }
        o
    }

    /// A member of a material whose gravity failed.
    pub fn gravity_failed(job: &SweepJob, m: &Member, diagnosis: &str) -> Outcome {
        Outcome { diagnosis: Some(diagnosis.to_string()), ..Outcome::of(job, m, Status::GravityFailed) }
    }

    /// Member `m` with `status`, before anything of its run is known.
    fn of(job: &SweepJob, m: &Member, status: Status) -> Outcome {
        Outcome {
            member: m.name.clone(),
            variant: job.variants[m.variant].name.clone(),
            record: job.records[m.record].name.clone(),
            intensity: m.level,
            factor: m.factor,
            status,
            diagnosis: None,
            time_reached: 0.0,
            ended_at_limits: None,
            peak_drift_ratio: None,
            peak_displacement: None,
            monitors: Vec::new(),
            damage: Vec::new(),
            iterations: 0,
            seconds: 0.0,
        }
    }

    /// The share of `group`'s area with d_t > 0.5 (0 when it has none).
    pub fn share_dt(&self, group: &str) -> f64 {
        self.damage.iter().find(|d| d.group == group).map_or(0.0, |d| d.share_dt)
    }

    /// Writes it into `dir` (atomically: a killed sweep leaves a whole file or none).
    pub fn write(&self, dir: &Path) -> std::io::Result<()> {
        let text = serde_json::to_string_pretty(self).map_err(std::io::Error::other)?;
        let tmp = dir.join(format!("{OUTCOME_FILE}.tmp"));
        std::fs::write(&tmp, text + "\n")?;
        std::fs::rename(tmp, dir.join(OUTCOME_FILE))
    }

    /// Reads the one in `dir`, if any.
    pub fn read(dir: &Path) -> Option<Outcome> {
        let text = std::fs::read_to_string(dir.join(OUTCOME_FILE)).ok()?;
        serde_json::from_str(&text).ok()
    }
}

/// Peak |u_x|, |u_y|, |u_z| of every monitor in a time history's `monitors.csv` (columns
/// `<name>:ux`, `<name>:uy`, `<name>:uz`); none when the file is missing.
pub fn monitor_peaks(csv: &Path) -> Vec<MonitorPeak> {
    let Ok(text) = std::fs::read_to_string(csv) else { return Vec::new() };
    let mut lines = text.lines();
    let Some(header) = lines.next() else { return Vec::new() };
    let cols: Vec<&str> = header.split(',').collect();
    let mut out: Vec<MonitorPeak> = Vec::new();
    let mut slots: Vec<(usize, usize, usize)> = Vec::new(); // (column, monitor, component)
    for (c, name) in cols.iter().enumerate() {
        let Some((monitor, q)) = name.rsplit_once(':') else { continue };
        let Some(d) = ["ux", "uy", "uz"].iter().position(|x| *x == q) else { continue };
        let k = match out.iter().position(|m| m.name == monitor) {
            Some(k) => k,
            None => {
                out.push(MonitorPeak { name: monitor.to_string(), peak: [0.0; 3] });
                out.len() - 1
            }
        };
        slots.push((c, k, d));
    }
    for line in lines {
        let v: Vec<f64> = line.split(',').map(|x| x.trim().parse().unwrap_or(0.0)).collect();
        for &(c, k, d) in &slots {
            if let Some(x) = v.get(c) {
                out[k].peak[d] = out[k].peak[d].max(x.abs());
            }
        }
    }
    out
}

/// The time of the last row of a `monitors.csv`.
fn last_time(csv: &Path) -> Option<f64> {
    let text = std::fs::read_to_string(csv).ok()?;
    text.lines().skip(1).last()?.split(',').nth(1)?.trim().parse().ok()
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Peaks by hand from a three-row file with one monitor.
    #[test]
    fn monitor_peaks_are_the_largest_magnitudes() {
        let dir = std::env::temp_dir().join(format!("mhpc-outcome-{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        let f = dir.join("monitors.csv");
        std::fs::write(&f, "step,time,top:ux,top:uy,top:uz,top:ax_abs,top:ay_abs,top:az_abs\n0,0,0,0,0,9,9,9\n1,0.01,-2e-3,1e-3,0,0,0,0\n2,0.02,1e-3,-3e-3,5e-4,0,0,0\n").unwrap();
        let p = monitor_peaks(&f);
        assert_eq!(p, vec![MonitorPeak { name: "top".into(), peak: [2e-3, 3e-3, 5e-4] }]);
        assert_eq!(last_time(&f), Some(0.02));
        std::fs::remove_dir_all(dir).unwrap();
    }
}
