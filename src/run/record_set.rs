//! A record set compatible with a Eurocode 8 elastic spectrum (EN 1998-1 §3.2.3.1), built and
//! checked on rank 0 (seconds of work; the other ranks wait for the agreed outcome).
//!
//! Phases: build (artificial records generated and matched, recorded ones scaled, spectra,
//! check: [`crate::seismic::build_set`]), then output:
//!
//! * `record-NN.txt`: every record of the set, two columns `t [s]  a [m/s²]` with a `#` header
//!   saying what it is (a time-history job reads it with `format = "two_column"`,
//!   `units = "m/s2"`), and `record-NN.png`, its acceleration history;
//! * `spectra.csv`: T, the target Se, 0.9 Se, the set's mean, mean/Se, whether T is in the
//!   check's range, then Sa of every record (5 % damping, T = 0 gives the PGA);
//! * `spectra.png`: the records' spectra, their mean, Se and 0.9 Se, the range shaded;
//! * `check.txt` and `summary.json`: each rule with its clause, what the set has and whether it
//!   passes; the lowest mean/Se over the range and its period; each record's origin (seed, or
//!   file and scale factor), PGA, PGV, PGD, D5–95.
//!
//! A set that fails the check ends the job with an error (exit code 1) after writing all of
//! this, unless `[record_set] require_compatible = false`.
use crate::config::RecordSetJob;
use crate::error::{Error, JobError};
use crate::parallel::{agree, Context};
use crate::seismic::{
    build_set, intensity, log_periods, record_png, record_set_png, write_two_column, Compatibility, Ec8Type, Member,
    Origin, RecordSet, SetRecipe,
};
use std::fmt::Write as _;
use std::path::Path;

/// Periods of the tables and the chart besides the check's: 150 log-spaced over 0.02–4 s.
const CHART_PERIODS: (f64, f64, usize) = (0.02, 4.0, 150);

crate::io::summary::named!(
    /// The corner periods of an EN 1998-1 spectrum.
    corner_names: ["t_b", "t_c", "t_d"]
);

/// The target spectrum, as summarized.
#[derive(Debug, Clone, serde::Serialize)]
pub struct TargetSummary {
    /// `type1` or `type2`.
    pub spectrum_type: Ec8Type,
    /// Ground type.
    pub ground: crate::seismic::GroundType,
    /// a_g [m/s²].
    pub ag: f64,
    /// Soil factor S.
    pub s: f64,
    /// Corner periods `t_b`, `t_c`, `t_d` [s].
    #[serde(with = "corner_names")]
    pub corners: [f64; 3],
}

/// One record of the set, as summarized.
#[derive(Debug, Clone, serde::Serialize)]
pub struct RecordSummary {
    /// The file written, in the results folder.
    pub file: String,
    /// Record name.
    pub name: String,
    /// `artificial` or `recorded`.
    pub origin: &'static str,
    /// Seed of an artificial record.
    pub seed: Option<u64>,
    /// Largest |Sa/Se − 1| over the matching periods `before` and `after` matching (artificial).
    #[serde(with = "crate::io::summary::before_after::option")]
    pub matching_max_misfit: Option<[f64; 2]>,
    /// Scale factor of a recorded record.
    pub scale_factor: Option<f64>,
    /// Where it came from.
    pub source: String,
    /// Duration [s] and time step [s].
    pub duration: f64,
    /// Time step [s].
    pub dt: f64,
    /// PGA [m/s²].
    pub pga: f64,
    /// PGV [m/s].
    pub pgv: f64,
    /// PGD [m].
    pub pgd: f64,
    /// D5–95 [s].
    pub d5_95: f64,
}

/// What a record-set run reports.
#[derive(Debug, Clone, serde::Serialize)]
pub struct RecordSetSummary {
    /// The target.
    pub target: TargetSummary,
    /// T₁ [s], when the range comes from it.
    pub t1: Option<f64>,
    /// The records.
    pub records: Vec<RecordSummary>,
    /// The check.
    pub check: Compatibility,
}

/// Collective. Runs the job; rank 0 builds, checks and writes everything, `summary.json` included.
pub fn run(ctx: &Context, job: &RecordSetJob) -> Result<(), Error> {
    let out = if ctx.rank == 0 { compute(ctx, job) } else { Ok(()) };
    agree(&ctx.comm, out, Error::exit_code).map_err(Error::from)
}

fn compute(ctx: &Context, job: &RecordSetJob) -> Result<(), Error> {
    let recipe = SetRecipe {
        target: job.target,
        rules: job.rules,
        artificial: job.artificial.as_ref().map(|(s, n)| (s, *n)),
        recorded: job.recorded.clone(),
        range_points: job.spec.record_set.range_points,
        chart_periods: log_periods(CHART_PERIODS.0, CHART_PERIODS.1, CHART_PERIODS.2),
    };
    let set = build_set(&recipe)?;
    let dir = &job.output_dir;
    let mut records = Vec::new();
    for (i, m) in set.members.iter().enumerate() {
        let file = format!("record-{:02}.txt", i + 1);
        write_two_column(&m.record, &dir.join(&file), &header(job, m))?;
        let png = dir.join(format!("record-{:02}.png", i + 1));
        record_png(&png, &m.record)?;
        records.push(record_summary(file, m));
        let r = records.last().map_or(String::new(), |r: &RecordSummary| {
            format!("{}: {} ({}), PGA {:.4} m/s², D5-95 {:.2} s", r.file, r.name, r.origin, r.pga, r.d5_95)
        });
        ctx.log.info(r);
    }
    write_text(&dir.join("spectra.csv"), &spectra_csv(&set, job))?;
    let title = format!(
        "{} record(s) against EC8 {}, ground {:?}, a_g = {} m/s²",
        set.members.len(),
        type_name(job.spec.record_set.spectrum_type),
        job.spec.record_set.ground,
        job.target.ag
    );
    record_set_png(&dir.join("spectra.png"), &title, &set, &job.target, job.rules.fraction, CHART_PERIODS.1)?;
    let c = &set.check;
    write_text(&dir.join("check.txt"), &check_text(c))?;
    ctx.log.info(format!(
        "check over [{:.4}, {:.4}] s: lowest mean/Se {:.4} at T = {:.4} s; mean PGA {:.4} m/s² (a_g S = {:.4}): {}",
        c.range.0,
        c.range.1,
        c.min_ratio,
        c.period_of_min,
        c.mean_pga,
        c.ag_s,
        if c.passed { "compatible" } else { "NOT compatible" }
    ));
    let summary = RecordSetSummary {
        target: TargetSummary {
            spectrum_type: job.spec.record_set.spectrum_type,
            ground: job.spec.record_set.ground,
            ag: job.target.ag,
            s: job.target.s,
            corners: [job.target.tb, job.target.tc, job.target.td],
        },
        t1: job.spec.record_set.t1,
        records,
        check: set.check.clone(),
    };
    super::write_summary(ctx, dir, &summary)?;
    ctx.log.info(format!("results: {}", dir.display()));
    if !c.passed {
        let e = JobError::RecordSetNotCompatible {
            file: job.source.file.clone(),
            check: dir.join("check.txt"),
            failures: c.failures(),
        };
        if job.spec.record_set.require_compatible {
            return Err(e.into());
        }
        ctx.log.warn(e.to_string());
    }
    Ok(())
}

fn type_name(t: Ec8Type) -> &'static str {
    match t {
        Ec8Type::Type1 => "type 1",
        Ec8Type::Type2 => "type 2",
    }
}

fn write_text(path: &Path, text: &str) -> Result<(), Error> {
    std::fs::write(path, text).map_err(|source| Error::OutputDir { path: path.to_path_buf(), source })
}

fn record_summary(file: String, m: &Member) -> RecordSummary {
    let im = intensity(&m.record);
    let (origin, seed, misfit, factor) = match &m.origin {
        Origin::Artificial { seed, report } => {
            let after = report.max_misfit.get(report.best).copied().unwrap_or(f64::NAN);
            ("artificial", Some(*seed), Some([report.max_misfit[0], after]), None)
        }
        Origin::Recorded { factor } => ("recorded", None, None, Some(*factor)),
    };
    RecordSummary {
        file,
        name: m.record.name.clone(),
        origin,
        seed,
        matching_max_misfit: misfit,
        scale_factor: factor,
        source: m.record.source.clone(),
        duration: m.record.duration(),
        dt: m.record.dt,
        pga: im.pga,
        pgv: im.pgv,
        pgd: im.pgd,
        d5_95: im.d5_95(),
    }
}

/// The `#` header of a written record.
fn header(job: &RecordSetJob, m: &Member) -> Vec<String> {
    let t = &job.target;
    let (a, b) = job.rules.range;
    let what = match &m.origin {
        Origin::Artificial { seed, .. } => format!(
            "ARTIFICIAL ground acceleration (not a recording), seed {seed}: filtered white noise matched to the target"
        ),
        Origin::Recorded { factor } => {
            format!("RECORDED ground acceleration scaled by {factor:.6} (log least squares over [{a:.4}, {b:.4}] s)")
        }
    };
    let im = intensity(&m.record);
    vec![
        format!("{}: {what}", m.record.name),
        format!(
            "target: EN 1998-1 elastic spectrum {}, ground {:?}, a_g = {} m/s^2, S = {}, 5% damping",
            type_name(job.spec.record_set.spectrum_type),
            job.spec.record_set.ground,
            t.ag,
            t.s
        ),
        format!("source: {}", m.record.source),
        format!("processing: {}", m.record.units_note),
        format!("units: time s, acceleration m/s^2; dt = {} s; {} samples", m.record.dt, m.record.len()),
        format!(
            "PGA = {:.4} m/s^2, PGV = {:.4} m/s, PGD = {:.4} m, D5-95 = {:.2} s",
            im.pga,
            im.pgv,
            im.pgd,
            im.d5_95()
        ),
        "columns: t [s]  a [m/s^2]".into(),
    ]
}

/// `spectra.csv`: one row per period.
fn spectra_csv(set: &RecordSet, job: &RecordSetJob) -> String {
    let mean = crate::seismic::mean_sa(&set.members.iter().map(|m| m.spectrum.clone()).collect::<Vec<_>>());
    let mut s = String::from("period,target_se,target_fraction,mean_sa,mean_over_target,in_check_range");
    for i in 0..set.members.len() {
        let _ = write!(s, ",sa_record_{:02}", i + 1);
    }
    s.push('\n');
    let (a, b) = set.check.range;
    for (k, &t) in set.periods.iter().enumerate() {
        let se = job.target.se(t);
        let inside = t >= a * (1.0 - 1e-12) && t <= b * (1.0 + 1e-12);
        let _ =
            write!(s, "{t:e},{se:e},{:e},{:e},{:e},{}", job.rules.fraction * se, mean[k], mean[k] / se, inside as u8);
        for m in &set.members {
            let _ = write!(s, ",{:e}", m.spectrum.sa[k]);
        }
        s.push('\n');
    }
    s
}

/// `check.txt`: the rules and the lowest ratio, for people.
fn check_text(c: &Compatibility) -> String {
    let mut s = format!(
        "EN 1998-1 §3.2.3.1 compatibility of a set of {} record(s): {}\n\n",
        c.records,
        if c.passed { "PASSED" } else { "FAILED" }
    );
    for r in &c.rules {
        let _ = writeln!(s, "{} {}: {}\n    {}", if r.passed { "pass" } else { "FAIL" }, r.rule, r.demand, r.found);
    }
    let _ = writeln!(
        s,
        "\nperiod range [{:.4}, {:.4}] s, {} periods checked; lowest mean/target {:.4} at T = {:.4} s",
        c.range.0,
        c.range.1,
        c.ratios.len(),
        c.min_ratio,
        c.period_of_min
    );
    s
}
