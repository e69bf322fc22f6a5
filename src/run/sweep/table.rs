//! The sweep's results for an engineer: `sweep.csv` (one row per member), the intensity at which
//! each `[[sweep.limit]]` is passed per record and material with its spread and its fragility
//! function (`fragility.rs`), in `summary.json` and `summary.txt`, and the curves (`ida.rs`).
//!
//! The intensity of a limit, for one record and one material, is where the substructure's share
//! of area with d_t > 0.5 first reaches the limit's share along the increasing intensities,
//! linear between the two members around it (`hunt::crossing`). Not reached at the highest
//! intensity: reported as above it (`null`, "> x", censored there for the fits); reached at the
//! lowest: at or below it ("<= x"). A member that stopped converging (or, in a hunt, is on the
//! flat end of the IDA curve) passes every limit at its intensity: a member that cannot go on
//! has failed. Per material, the records' lognormal fit gives a median and the dispersion β over
//! the records (Vamvatsikos and Cornell 2002; Baker 2015 for the fit); the materials' medians
//! give the dispersion from the materials, kept apart from the records'.
use super::feed::{end_name, response};
use super::fragility::{self, Fragility};
use super::hunt::{crossing, Chain, Crossing, HuntEnd, Reading};
use super::ida;
use super::member::member_dir;
use super::outcome::{Outcome, Status};
use crate::config::{Intensities, Member, SweepJob};
use crate::error::{Error, JobError};
use crate::io::IoError;
use crate::parallel::Log;
use crate::seismic::{fit_fragility, FragilityFit};
use serde::Serialize;
use std::fmt::Write as _;
use std::path::Path;

/// One limit under one material: its crossings and their median and spread.
#[derive(Clone, Debug, Serialize)]
pub struct VariantLimit {
    /// The material variant.
    pub variant: String,
    /// Per record.
    pub crossings: Vec<Crossing>,
    /// The records' lognormal fit (moments, or maximum likelihood with censored records).
    pub fit: Option<FragilityFit>,
    /// Its median [m/s²].
    pub median: Option<f64>,
    /// Its dispersion over the records.
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
    /// The fragility over records and materials.
    pub fragility: Fragility,
}

/// How one record's hunt under one material ended.
#[derive(Clone, Debug, Serialize)]
pub struct HuntSummary {
    /// The material.
    pub variant: String,
    /// The record.
    pub record: String,
    /// Members run.
    pub members: usize,
    /// Why the hunt stopped stepping up.
    pub end: Option<HuntEnd>,
    /// At which intensity [m/s²].
    pub at: Option<f64>,
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
    /// "hunt" (adaptive intensities) or "grid".
    pub intensities: &'static str,
    /// The intensity measure.
    pub intensity_measure: &'static str,
    /// The site's code level [m/s²].
    pub code_level: Option<f64>,
    /// The limits.
    pub limits: Vec<LimitSummary>,
    /// Per substructure and intensity of a grid: the mean share with d_t > 0.5 over the
    /// completed members.
    pub mean_share_dt: Vec<ShareCurve>,
    /// Per record and material, how its hunt ended.
    pub hunts: Vec<HuntSummary>,
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
            Outcome::read(&member_dir(out, m))
                .ok_or_else(|| Error::from(JobError::NoOutcome { member: m.name.clone(), dir: member_dir(out, m) }))
        })
        .collect::<Result<_, _>>()?;
    let groups = groups_of(job, &outcomes);
    let io = |p: &Path, source| Error::OutputDir { path: p.to_path_buf(), source };
    let csv = out.join("sweep.csv");
    std::fs::write(&csv, table_csv(job, &outcomes, &groups)).map_err(|e| io(&csv, e))?;

    let summary = summarize(job, members, &outcomes, &groups, timing);
    let file = out.join("summary.json");
    let text = crate::io::summary::summary_json(&summary).map_err(|source| IoError::Json {
        file: file.clone(),
        what: "the summary",
        source,
    })?;
    std::fs::write(&file, text + "\n").map_err(|e| io(&file, e))?;
    let txt = out.join("summary.txt");
    let text = summary_text(job, &summary);
    std::fs::write(&txt, &text).map_err(|e| io(&txt, e))?;
    for line in text.lines() {
        log.info(line);
    }
    let pictures = ida::draw(job, members, &outcomes, &groups, out)?;
    let mut curves = 0;
    for l in &summary.limits {
        let crossings: Vec<&Crossing> = l.variants.iter().flat_map(|v| &v.crossings).collect();
        curves += fragility::draw(job, &l.group, l.share, &crossings, &l.fragility, out)? as usize;
    }
    log.info(format!(
        "results: {}, {}, {} picture(s) ida-*.png and {} fragility-*.png in {}",
        csv.display(),
        txt.display(),
        pictures,
        curves,
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
/// reached, the time it ended at every limit passed (empty: it ran whole), peak drift ratio, peak |u| (x y z), per monitor its peaks, per substructure the
/// shares with d_t > 0.5 (with its convergence band where `[dynamics] convergence`
/// gives one: empty otherwise) and d_c > 0.5, the diagnosis of a stopped member (quoted).
fn table_csv(job: &SweepJob, outcomes: &[Outcome], groups: &[String]) -> String {
    let monitors: Vec<String> =
        job.base.spec.dynamics.as_ref().map(|d| d.monitor.iter().map(|m| m.name.clone()).collect()).unwrap_or_default();
    let mut s = String::from(
        "member,variant,record,intensity_measure,intensity,factor,status,time_reached,ended_at_limits,peak_drift_ratio,peak_ux,peak_uy,peak_uz",
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
            "{},{},{},{},{:.6e},{:.6e},{},{:.6e},{},{},{},{},{}",
            o.member,
            o.variant,
            o.record,
            job.spec.sweep.scale_by.label(),
            o.intensity,
            o.factor,
            o.status.name(),
            o.time_reached,
            num(o.ended_at_limits),
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

/// The readings of limit `k` along the levels of material `v` and record `r` (a hunt's through
/// its chain, which knows the flat end).
fn readings(
    job: &SweepJob,
    members: &[Member],
    outcomes: &[Outcome],
    v: usize,
    r: usize,
    k: usize,
) -> Vec<(f64, Reading)> {
    let mut pts: Vec<(&Member, &Outcome)> =
        members.iter().zip(outcomes).filter(|(m, _)| m.variant == v && m.record == r).collect();
    pts.sort_by(|a, b| a.0.level.total_cmp(&b.0.level));
    match job.intensities() {
        Intensities::Hunt(rules) => chain(job, rules, &pts).readings(k),
        Intensities::Grid(_) => {
            let group = &job.spec.sweep.limit[k].group;
            pts.iter()
                .filter_map(|(m, o)| match o.status {
                    Status::Completed => Some((m.level, Reading::Share(o.share_dt(group)))),
                    Status::Stopped => Some((m.level, Reading::Stopped)),
                    Status::GravityFailed => None,
                })
                .collect()
        }
    }
}

fn chain<'a>(job: &SweepJob, rules: &'a crate::config::HuntRules, pts: &[(&Member, &Outcome)]) -> Chain<'a> {
    let mut c = Chain::new(rules, job.spec.sweep.limit.iter().map(|l| l.share).collect());
    for (m, o) in pts {
        c.add(m.level, response(job, o));
    }
    c
}

/// One limit (`k`) under every material: the crossings, the fits, the spreads, the fragility.
fn limit_summary(job: &SweepJob, members: &[Member], outcomes: &[Outcome], k: usize) -> LimitSummary {
    let l = &job.spec.sweep.limit[k];
    let above = match job.intensities() {
        Intensities::Hunt(_) => "above_cap",
        Intensities::Grid(_) => "above_highest",
    };
    let variants: Vec<VariantLimit> = job
        .variants
        .iter()
        .enumerate()
        .map(|(v, variant)| {
            let crossings: Vec<Crossing> = (0..job.records.len())
                .map(|r| crossing(&job.records[r].name, &readings(job, members, outcomes, v, r, k), l.share, above))
                .collect();
            let passages: Vec<_> = crossings.iter().filter_map(fragility::passage).collect();
            let fit = fit_fragility(&passages);
            VariantLimit {
                variant: variant.name.clone(),
                not_reached: crossings.iter().filter(|c| c.intensity.is_none()).count(),
                crossings,
                median: fit.map(|f| f.median),
                beta_records: fit.and_then(|f| f.beta),
                fit,
            }
        })
        .collect();
    let betas: Vec<f64> = variants.iter().filter_map(|v| v.beta_records).collect();
    let medians: Vec<_> = variants.iter().filter_map(|v| v.median.map(crate::seismic::Passage::At)).collect();
    let fragility = fragility::fragility(variants.iter().flat_map(|v| &v.crossings), job.spec.sweep.code_level);
    LimitSummary {
        group: l.group.clone(),
        share: l.share,
        beta_records: (!betas.is_empty()).then(|| betas.iter().sum::<f64>() / betas.len() as f64),
        beta_materials: fit_fragility(&medians).and_then(|f| f.beta),
        variants,
        fragility,
    }
}

fn summarize(
    job: &SweepJob,
    members: &[Member],
    outcomes: &[Outcome],
    groups: &[String],
    timing: Timing,
) -> SweepSummary {
    let count = |s: Status| outcomes.iter().filter(|o| o.status == s).count();
    let limits = (0..job.spec.sweep.limit.len()).map(|k| limit_summary(job, members, outcomes, k)).collect();
    let (mut mean_share_dt, mut hunts) = (Vec::new(), Vec::new());
    match job.intensities() {
        Intensities::Grid(xs) => {
            for g in groups {
                let curve = xs
                    .iter()
                    .enumerate()
                    .filter_map(|(i, &x)| {
                        let s: Vec<f64> = members
                            .iter()
                            .zip(outcomes)
                            .filter(|(m, o)| m.intensity == Some(i) && o.status == Status::Completed)
                            .map(|(_, o)| o.share_dt(g))
                            .collect();
                        (!s.is_empty())
                            .then(|| SharePoint { intensity: x, share: s.iter().sum::<f64>() / s.len() as f64 })
                    })
                    .collect();
                mean_share_dt.push(ShareCurve { group: g.clone(), points: curve });
            }
        }
        Intensities::Hunt(rules) => {
            for (v, variant) in job.variants.iter().enumerate() {
                for (r, record) in job.records.iter().enumerate() {
                    let pts: Vec<(&Member, &Outcome)> =
                        members.iter().zip(outcomes).filter(|(m, _)| m.variant == v && m.record == r).collect();
                    let end = chain(job, rules, &pts).hunt_end();
                    hunts.push(HuntSummary {
                        variant: variant.name.clone(),
                        record: record.name.clone(),
                        members: pts.len(),
                        end: end.map(|e| e.0),
                        at: end.map(|e| e.1),
                    });
                }
            }
        }
    }
    SweepSummary {
        timing,
        members: outcomes.len(),
        completed: count(Status::Completed),
        stopped: count(Status::Stopped),
        gravity_failed: count(Status::GravityFailed),
        intensities: if matches!(job.intensities(), Intensities::Hunt(_)) { "hunt" } else { "grid" },
        intensity_measure: job.spec.sweep.scale_by.label(),
        code_level: job.spec.sweep.code_level,
        limits,
        mean_share_dt,
        hunts,
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
    if !s.mean_share_dt.is_empty() {
        let _ = writeln!(t, "mean share of area with d_t > 0.5 per substructure, by {im} [m/s²]:");
    }
    for c in &s.mean_share_dt {
        let row: Vec<String> =
            c.points.iter().map(|p| format!("{:.3}: {:.1} %", p.intensity, 100.0 * p.share)).collect();
        let _ = writeln!(t, "  {:16} {}", c.group, row.join(", "));
    }
    if !s.hunts.is_empty() {
        let _ = writeln!(t, "hunts (adaptive intensities), per record / material:");
    }
    for h in &s.hunts {
        let end = match (h.end, h.at) {
            (Some(e), Some(x)) => format!("stepped up to {im} {x:.4} m/s²: {}", end_name(e)),
            _ => "not run".into(),
        };
        let _ = writeln!(t, "  {} / {}: {} member(s), {end}", h.record, h.variant, h.members);
    }
    for l in &s.limits {
        limit_text(&mut t, s, l);
    }
    t
}

fn limit_text(t: &mut String, s: &SweepSummary, l: &LimitSummary) {
    let im = s.intensity_measure;
    let _ = writeln!(t, "{} passes {:.0} % of its area with d_t > 0.5:", l.group, 100.0 * l.share);
    for v in &l.variants {
        let per: Vec<String> = v
            .crossings
            .iter()
            .map(|c| match (c.how, c.intensity, c.censored_at) {
                ("above_cap", _, Some(x)) => format!("{} not passed up to the cap {x:.3}", c.record),
                (_, None, Some(x)) => format!("{} > {x:.3}", c.record),
                ("at_or_below_lowest", Some(x), _) => format!("{} <= {x:.3}", c.record),
                ("stopped", Some(x), _) => format!("{} {x:.3} (stopped)", c.record),
                ("flat", Some(x), _) => format!("{} {x:.3} (flat)", c.record),
                (_, Some(x), _) => format!("{} {x:.3}", c.record),
                _ => format!("{} (no member)", c.record),
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
    t.push_str(&fragility::text(&l.fragility, im, s.code_level));
}
