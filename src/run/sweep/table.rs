//! The sweep's results for an engineer: `sweep.csv` (one row per member), the intensity at which
//! each `[[sweep.limit]]` is passed per record and material with its spread, in `summary.json`
//! and `summary.txt`, and the curves (`ida.rs`).
//!
//! The intensity of a limit, for one record and one material, is where the substructure's share
//! of area with d_t > 0.5 first reaches the limit's share along the increasing intensities,
//! linear between the two members around it. Not reached at the highest intensity: reported as
//! above it (`null`, "> x"); reached at the lowest: at or below it ("<= x"). Their spread is the
//! lognormal dispersion β = std(ln I) (sample standard deviation), the usual measure of record to
//! record variability in IDA (Vamvatsikos and Cornell 2002); the members that stopped are left
//! out of the crossings, and the limit is reported as passed at a stopped member's intensity (a
//! member that cannot go on has failed).
use super::ida;
use super::member::member_dir;
use super::outcome::{Outcome, Status};
use crate::config::{Member, SweepJob};
use crate::error::Error;
use crate::parallel::Log;
use serde::Serialize;
use std::fmt::Write as _;
use std::path::Path;

/// The crossing of one limit under one record and material.
#[derive(Clone, Debug, Serialize, PartialEq)]
pub struct Crossing {
    /// The record.
    pub record: String,
    /// The intensity [m/s²], or `None` when not reached.
    pub intensity: Option<f64>,
    /// "reached", "at_or_below_lowest", "above_highest", "stopped" (passed at a stopped member).
    pub how: &'static str,
}

/// One limit under one material: its crossings and their median and spread.
#[derive(Clone, Debug, Serialize)]
pub struct VariantLimit {
    /// The material variant.
    pub variant: String,
    /// Per record.
    pub crossings: Vec<Crossing>,
    /// Median over the records that reached it [m/s²] (geometric mean).
    pub median: Option<f64>,
    /// Lognormal dispersion over those records.
    pub beta_records: Option<f64>,
    /// Records that did not reach it.
    pub not_reached: usize,
}

/// One limit over the whole sweep.
#[derive(Clone, Debug, Serialize)]
pub struct LimitSummary {
    /// The substructure.
    pub group: String,
    /// The share of its area with d_t > 0.5.
    pub share: f64,
    /// Per material.
    pub variants: Vec<VariantLimit>,
    /// The dispersion from the records: the mean over the materials of each one's β.
    pub beta_records: Option<f64>,
    /// The dispersion from the materials: β of the materials' medians.
    pub beta_materials: Option<f64>,
}

/// Where a sweep's wall time went, in this run (a restarted sweep: its own part).
#[derive(Clone, Debug, Serialize)]
pub struct Timing {
    /// Groups and ranks per group.
    pub groups: usize,
    /// See `groups`.
    pub group_size: usize,
    /// Seconds of the gravity states (modal updating included).
    pub seconds_gravity: f64,
    /// Seconds of the members.
    pub seconds_members: f64,
    /// Members run by this run.
    pub members_run: usize,
    /// Members run per hour of the members' phase.
    pub members_per_hour: f64,
}

/// `summary.json` of a sweep.
#[derive(Clone, Debug, Serialize)]
pub struct SweepSummary {
    /// This run's timing.
    pub timing: Timing,
    /// Members in all.
    pub members: usize,
    /// Completed, stopped, gravity failed.
    pub completed: usize,
    /// See `completed`.
    pub stopped: usize,
    /// See `completed`.
    pub gravity_failed: usize,
    /// The intensity measure.
    pub intensity_measure: &'static str,
    /// The site's code level [m/s²].
    pub code_level: Option<f64>,
    /// The limits.
    pub limits: Vec<LimitSummary>,
    /// Per substructure and intensity: the mean share with d_t > 0.5 over the completed members.
    pub mean_share_dt: Vec<ShareCurve>,
}

/// One substructure's mean share with d_t > 0.5 against intensity.
#[derive(Clone, Debug, Serialize)]
pub struct ShareCurve {
    /// The substructure.
    pub group: String,
    /// Per intensity with completed members, lowest first.
    pub points: Vec<SharePoint>,
}

/// The mean share at one intensity.
#[derive(Clone, Copy, Debug, Serialize)]
pub struct SharePoint {
    /// The intensity [m/s²].
    pub intensity: f64,
    /// The mean share of the area with d_t > 0.5 over the completed members.
    pub share: f64,
}

/// Rank 0. Reads every member's outcome and writes the table, the summary and the curves.
pub fn write_results(job: &SweepJob, members: &[Member], timing: Timing, log: &Log) -> Result<(), Error> {
    let out = &job.output_dir;
    let outcomes: Vec<Outcome> = members
        .iter()
        .map(|m| {
            Outcome::read(&member_dir(out, m)).ok_or_else(|| {
                Error::Analysis(format!("member {} has no outcome in {}", m.name, member_dir(out, m).display()))
            })
        })
        .collect::<Result<_, _>>()?;
    let groups = groups_of(job, &outcomes);
    let io = |p: &Path, source| Error::OutputDir { path: p.to_path_buf(), source };
    let csv = out.join("sweep.csv");
    std::fs::write(&csv, table_csv(job, &outcomes, &groups)).map_err(|e| io(&csv, e))?;

    let summary = summarize(job, members, &outcomes, &groups, timing);
    let file = out.join("summary.json");
    let text = crate::io::summary::summary_json(&summary).map_err(|e| Error::Analysis(e.to_string()))?;
    std::fs::write(&file, text + "\n").map_err(|e| io(&file, e))?;
    let txt = out.join("summary.txt");
    let text = summary_text(job, &summary);
    std::fs::write(&txt, &text).map_err(|e| io(&txt, e))?;
    for line in text.lines() {
        log.info(line);
    }
    let pictures = ida::draw(job, members, &outcomes, &groups, out).map_err(Error::Analysis)?;
    log.info(format!(
        "results: {}, {}, {} picture(s) ida-*.png in {}",
        csv.display(),
        txt.display(),
        pictures,
        out.display()
    ));
    Ok(())
}

/// The substructures in the table: every group some outcome has damage for, in order.
fn groups_of(job: &SweepJob, outcomes: &[Outcome]) -> Vec<String> {
    let mut g: Vec<String> = Vec::new();
    for p in &job.base.spec.parts {
        if !g.contains(&p.group) && outcomes.iter().any(|o| o.damage.iter().any(|d| d.group == p.group)) {
            g.push(p.group.clone());
        }
    }
    g
}

fn num(x: Option<f64>) -> String {
    x.map_or(String::new(), |v| format!("{v:.6e}"))
}

/// `sweep.csv`: member, variant, record, intensity measure, intensity, factor, status, time
/// reached, peak drift ratio, peak |u| (x y z), per monitor its peaks, per substructure the
/// shares with d_t > 0.5 (with its convergence band where `[dynamics] convergence`
/// gives one: empty otherwise) and d_c > 0.5, the diagnosis of a stopped member (quoted).
fn table_csv(job: &SweepJob, outcomes: &[Outcome], groups: &[String]) -> String {
    let monitors: Vec<String> =
        job.base.spec.dynamics.as_ref().map(|d| d.monitor.iter().map(|m| m.name.clone()).collect()).unwrap_or_default();
    let mut s = String::from(
        "member,variant,record,intensity_measure,intensity,factor,status,time_reached,peak_drift_ratio,peak_ux,peak_uy,peak_uz",
    );
    for m in &monitors {
        for q in ["ux", "uy", "uz"] {
            let _ = write!(s, ",{m}:peak_{q}");
        }
    }
    for g in groups {
        let _ = write!(s, ",{g}:share_dt_above_0.5,{g}:share_dt_above_0.5_band,{g}:share_dc_above_0.5");
    }
    s.push_str(",diagnosis\n");
    for o in outcomes {
        let p = o.peak_displacement;
        let _ = write!(
            s,
            "{},{},{},{},{:.6e},{:.6e},{},{:.6e},{},{},{},{}",
            o.member,
            o.variant,
            o.record,
            job.spec.sweep.scale_by.label(),
            o.intensity,
            o.factor,
            o.status.name(),
            o.time_reached,
            num(o.peak_drift_ratio),
            num(p.map(|p| p[0])),
            num(p.map(|p| p[1])),
            num(p.map(|p| p[2]))
        );
        for m in &monitors {
            let peak = o.monitors.iter().find(|x| &x.name == m).map(|x| x.peak);
            for d in 0..3 {
                let _ = write!(s, ",{}", num(peak.map(|p| p[d])));
            }
        }
        for g in groups {
            let d = o.damage.iter().find(|d| &d.group == g);
            let _ = write!(
                s,
                ",{},{},{}",
                num(d.map(|d| d.share_dt)),
                num(d.and_then(|d| d.share_dt_band)),
                num(d.map(|d| d.share_dc))
            );
        }
        let diag = o.diagnosis.as_deref().map(|d| format!("\"{}\"", d.replace('"', "'"))).unwrap_or_default();
        let _ = writeln!(s, ",{diag}");
    }
    s
}

/// Where the shares along increasing intensities `(x, share or None if stopped)` first reach `limit`.
pub fn crossing(record: &str, points: &[(f64, Option<f64>)], limit: f64) -> Crossing {
    let mut prev: Option<(f64, f64)> = None;
    for &(x, y) in points {
        match y {
            None => return Crossing { record: record.into(), intensity: Some(x), how: "stopped" },
            Some(y) if y >= limit => {
                return match prev {
                    None => Crossing { record: record.into(), intensity: Some(x), how: "at_or_below_lowest" },
                    Some((x0, y0)) => {
                        let t = if y > y0 { (limit - y0) / (y - y0) } else { 1.0 };
                        Crossing { record: record.into(), intensity: Some(x0 + t * (x - x0)), how: "reached" }
                    }
                }
            }
            Some(y) => prev = Some((x, y)),
        }
    }
    Crossing { record: record.into(), intensity: None, how: "above_highest" }
}

/// Geometric mean and lognormal dispersion (sample std of ln x; none below 2 values).
pub fn lognormal(xs: &[f64]) -> (Option<f64>, Option<f64>) {
    if xs.is_empty() {
        return (None, None);
    }
    let ln: Vec<f64> = xs.iter().map(|x| x.ln()).collect();
    let mean = ln.iter().sum::<f64>() / ln.len() as f64;
    let beta =
        (ln.len() > 1).then(|| (ln.iter().map(|l| (l - mean).powi(2)).sum::<f64>() / (ln.len() - 1) as f64).sqrt());
    (Some(mean.exp()), beta)
}

fn summarize(
    job: &SweepJob,
    members: &[Member],
    outcomes: &[Outcome],
    groups: &[String],
    timing: Timing,
) -> SweepSummary {
    let count = |s: Status| outcomes.iter().filter(|o| o.status == s).count();
    let points = |v: usize, r: usize, group: &str| -> Vec<(f64, Option<f64>)> {
        members
            .iter()
            .zip(outcomes)
            .filter(|(m, o)| m.variant == v && m.record == r && o.status != Status::GravityFailed)
            .map(|(m, o)| (m.level, (o.status == Status::Completed).then(|| o.share_dt(group))))
            .collect()
    };
    let limits = job
        .spec
        .sweep
        .limit
        .iter()
        .map(|l| {
            let variants: Vec<VariantLimit> = job
                .variants
                .iter()
                .enumerate()
                .map(|(v, variant)| {
                    let crossings: Vec<Crossing> = job
                        .records
                        .iter()
                        .enumerate()
                        .map(|(r, rec)| crossing(&rec.name, &points(v, r, &l.group), l.share))
                        .collect();
                    let reached: Vec<f64> = crossings.iter().filter_map(|c| c.intensity).collect();
                    let (median, beta_records) = lognormal(&reached);
                    VariantLimit {
                        variant: variant.name.clone(),
                        not_reached: crossings.len() - reached.len(),
                        crossings,
                        median,
                        beta_records,
                    }
                })
                .collect();
            let betas: Vec<f64> = variants.iter().filter_map(|v| v.beta_records).collect();
            let medians: Vec<f64> = variants.iter().filter_map(|v| v.median).collect();
            LimitSummary {
                group: l.group.clone(),
                share: l.share,
                beta_records: (!betas.is_empty()).then(|| betas.iter().sum::<f64>() / betas.len() as f64),
                beta_materials: lognormal(&medians).1,
                variants,
            }
        })
        .collect();
    let mean_share_dt = groups
        .iter()
        .map(|g| {
            let curve = job
                .spec
                .sweep
                .intensities
                .iter()
                .enumerate()
                .filter_map(|(i, &x)| {
                    let s: Vec<f64> = members
                        .iter()
                        .zip(outcomes)
                        .filter(|(m, o)| m.intensity == i && o.status == Status::Completed)
                        .map(|(_, o)| o.share_dt(g))
                        .collect();
                    (!s.is_empty()).then(|| SharePoint { intensity: x, share: s.iter().sum::<f64>() / s.len() as f64 })
                })
                .collect();
            ShareCurve { group: g.clone(), points: curve }
        })
        .collect();
    SweepSummary {
        timing,
        members: outcomes.len(),
        completed: count(Status::Completed),
        stopped: count(Status::Stopped),
        gravity_failed: count(Status::GravityFailed),
        intensity_measure: job.spec.sweep.scale_by.label(),
        code_level: job.spec.sweep.code_level,
        limits,
        mean_share_dt,
    }
}

fn summary_text(job: &SweepJob, s: &SweepSummary) -> String {
    let im = s.intensity_measure;
    let mut t = String::new();
    let _ = writeln!(
        t,
        "sweep {}: {} member(s): {} completed, {} stopped, {} without a gravity state",
        job.source.file.display(),
        s.members,
        s.completed,
        s.stopped,
        s.gravity_failed
    );
    let w = &s.timing;
    let _ = writeln!(
        t,
        "this run: {} group(s) of {} rank(s); gravity states {:.1} s, {} member(s) in {:.1} s ({:.1} per hour)",
        w.groups, w.group_size, w.seconds_gravity, w.members_run, w.seconds_members, w.members_per_hour
    );
    if let Some(c) = s.code_level {
        let _ = writeln!(t, "site code level: {im} = {c} m/s²");
    }
    let _ = writeln!(t, "mean share of area with d_t > 0.5 per substructure, by {im} [m/s²]:");
    for c in &s.mean_share_dt {
        let row: Vec<String> =
            c.points.iter().map(|p| format!("{:.3}: {:.1} %", p.intensity, 100.0 * p.share)).collect();
        let _ = writeln!(t, "  {:16} {}", c.group, row.join(", "));
    }
    for l in &s.limits {
        let _ = writeln!(t, "{} passes {:.0} % of its area with d_t > 0.5:", l.group, 100.0 * l.share);
        for v in &l.variants {
            let per: Vec<String> = v
                .crossings
                .iter()
                .map(|c| match (c.how, c.intensity) {
                    ("above_highest", _) => {
                        format!("{} > {:.3}", c.record, job.spec.sweep.intensities.last().copied().unwrap_or(0.0))
                    }
                    ("at_or_below_lowest", Some(x)) => format!("{} <= {x:.3}", c.record),
                    ("stopped", Some(x)) => format!("{} {x:.3} (stopped)", c.record),
                    (_, Some(x)) => format!("{} {x:.3}", c.record),
                    _ => c.record.clone(),
                })
                .collect();
            let _ = writeln!(
                t,
                "  material {}: median {im} {} m/s², beta over records {} ({} of {} record(s) not reached); {}",
                v.variant,
                v.median.map_or("-".into(), |m| format!("{m:.3}")),
                v.beta_records.map_or("-".into(), |b| format!("{b:.3}")),
                v.not_reached,
                v.crossings.len(),
                per.join(", ")
            );
        }
        let _ = writeln!(
            t,
            "  spread: from the records beta = {}, from the materials beta = {}",
            l.beta_records.map_or("-".into(), |b| format!("{b:.3}")),
            l.beta_materials.map_or("-".into(), |b| format!("{b:.3}"))
        );
    }
    t
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Crossings by hand: between 1 (0.2) and 2 (0.6) the share reaches 0.5 at 1.75; above the
    /// highest; at the lowest; at a stopped member.
    #[test]
    fn crossings_of_a_limit() {
        let c = crossing("r", &[(1.0, Some(0.2)), (2.0, Some(0.6)), (3.0, Some(0.9))], 0.5);
        assert_eq!(c.how, "reached");
        assert!((c.intensity.unwrap() - 1.75).abs() < 1e-12);
        assert_eq!(crossing("r", &[(1.0, Some(0.1)), (2.0, Some(0.2))], 0.5).intensity, None);
        assert_eq!(crossing("r", &[(1.0, Some(0.7))], 0.5).how, "at_or_below_lowest");
        let s = crossing("r", &[(1.0, Some(0.1)), (2.0, None)], 0.5);
        assert_eq!((s.how, s.intensity), ("stopped", Some(2.0)));
    }

    /// Geometric mean and sample dispersion by hand: e and e³ → e², β = √2.
    #[test]
    fn lognormal_median_and_dispersion() {
        let e = std::f64::consts::E;
        let (m, b) = lognormal(&[e, e.powi(3)]);
        assert!((m.unwrap() - e * e).abs() < 1e-12);
        assert!((b.unwrap() - 2f64.sqrt()).abs() < 1e-12);
        assert_eq!(lognormal(&[2.0]).1, None);
    }
}
