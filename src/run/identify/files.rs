//! The identification's files, written by rank 0: the calibration's (`calibration.json`, `.csv`,
//! `.png`, `calibration_elastic.csv`), the virtual tests' curves, the law's (`law.csv`, its
//! pictures, `material.toml` with its provenance) and its variants' material files.
use super::provenance::{provenance, variant_provenance};
use super::IdentifySummary;
use crate::config::IdentifyJob;
use crate::error::Error;
use crate::identify::calibration::{CalibrationResult, QUANTITIES};
use crate::identify::curves::{Curve, MeanKind};
use crate::identify::elastic_fit::ElasticFit;
use crate::identify::material_file::{write_material_file, Provenance, VariantFigure};
use crate::identify::{CurveError, LawFit, LawResult};
use crate::io::IoError;
use crate::material::DamageParams;
use crate::parallel::Context;
use crate::plot::{LineChart, SeriesStyle};
use std::fmt::Write as _;
use std::path::{Path, PathBuf};

fn io_err(path: &Path) -> impl Fn(std::io::Error) -> Error + '_ {
    move |source| Error::OutputDir { path: path.to_path_buf(), source }
}

/// Rank 0: the calibration's files and log lines: the calibrated parameters and Table 1,
/// stage 1 (`calibration_elastic.csv`), the search's history (`calibration.csv`), the result
/// (`calibration.json`) and its curves (`calibration.png`).
pub(super) fn write_calibration(ctx: &Context, job: &IdentifyJob, r: &CalibrationResult) -> Result<(), Error> {
    let dir = &job.output_dir;
    log_calibration(ctx, r);
    if let Some(el) = &r.elastic {
        log_elastic_stage(ctx, el);
        write_text(&dir.join("calibration_elastic.csv"), &elastic_stage_csv(el))?;
    }
    write_text(&dir.join("calibration.csv"), &calibration_history_csv(r))?;
    let f = dir.join("calibration.json");
    let text = serde_json::to_string_pretty(r).map_err(|source| IoError::Json {
        file: f.clone(),
        what: "the calibration",
        source,
    })?;
    write_text(&f, &(text + "\n"))?;
    let f = dir.join("calibration.png");
    Ok(calibration_chart(r).save_png(&f)?)
}

/// The calibrated DEM in the log: its parameters and objective, then Table 1 (each quantity's
/// sample mean ± std against its target).
fn log_calibration(ctx: &Context, r: &CalibrationResult) {
    let p = &r.parameters;
    ctx.log.info(format!(
        "calibrated DEM ({:?}): alpha = {:.4}, e_bar = {:.4e} Pa, eps_cr = {:.4e}, theta_cr = {:.4e}{} (mu = {} fixed); J = {:.4e} after {} evaluations",
        r.strategy,
        p.alpha,
        p.e_bar,
        p.eps_cr,
        p.theta_cr,
        p.crushing_stress.map_or(String::new(), |s| format!(", crushing_stress = {s:.4e} Pa")),
        p.mu,
        r.objective,
        r.evaluations
    ));
    let t = r.targets.as_array();
    let scale = [1e9, 1.0, 1e6, 1e6];
    let unit = ["GPa", "", "MPa", "MPa"];
    for k in 0..4 {
        ctx.log.info(format!(
            "  {:20} {:10.4} ± {:.4} {} (n = {})   target {:.4}   error {:+.1}%",
            QUANTITIES[k],
            r.stats[k].mean / scale[k],
            r.stats[k].std / scale[k],
            unit[k],
            r.stats[k].n,
            t[k] / scale[k],
            100.0 * r.relative_errors[k]
        ));
    }
}

/// Stage 1 (the elastic fit of alpha) in the log: points evaluated, whether ν met its tolerance.
fn log_elastic_stage(ctx: &Context, el: &ElasticFit) {
    ctx.log.info(format!(
        "  stage 1 (elastic): {} alpha value(s) evaluated, nu {} its tolerance{}",
        el.points.len(),
        if el.converged { "within" } else { "NOT within" },
        el.note.as_ref().map_or(String::new(), |n| format!(": {n}"))
    ));
}

/// `calibration_elastic.csv`: each alpha of stage 1 with its ν and E/Ē statistics (or why it
/// failed).
fn elastic_stage_csv(el: &ElasticFit) -> String {
    let mut csv = String::from("round,alpha,poisson_mean,poisson_std,e_over_e_bar_mean,e_over_e_bar_std,n,error\n");
    for p in &el.points {
        let _ = match &p.value {
            Ok(m) => writeln!(
                csv,
                "{},{:e},{:e},{:e},{:e},{:e},{},",
                p.round, p.alpha, m.poisson.mean, m.poisson.std, m.e_ratio.mean, m.e_ratio.std, m.poisson.n
            ),
            Err(e) => writeln!(csv, "{},{:e},,,,,,{}", p.round, p.alpha, e.to_string().replace([',', '\n'], ";")),
        };
    }
    csv
}

/// `calibration.csv`: every evaluation of the search with its point (crushing stress included
/// when searched), its objective (or why it failed).
fn calibration_history_csv(r: &CalibrationResult) -> String {
    let crushing = r.history.first().is_some_and(|h| h.1.len() > 4);
    let mut csv = String::from(if crushing {
        "evaluation,iteration,alpha,e_bar,eps_cr,theta_cr,crushing_stress,objective,error\n"
    } else {
        "evaluation,iteration,alpha,e_bar,eps_cr,theta_cr,objective,error\n"
    });
    for (i, (it, x, v)) in r.history.iter().enumerate() {
        let (val, err) = match v {
            Ok(v) => (format!("{v:e}"), String::new()),
            Err(e) => (String::new(), e.to_string().replace([',', '\n'], ";")),
        };
        let extra = x.get(4).map_or(String::new(), |v| format!("{v:e},"));
        let _ = writeln!(csv, "{i},{it},{:e},{:e},{:e},{:e},{extra}{val},{err}", x[0], x[1], x[2], x[3]);
    }
    csv
}

/// `calibration.png`: the calibrated DEM's curves against the experimental points (E, first
/// crack, peak).
fn calibration_chart(r: &CalibrationResult) -> LineChart {
    let mut chart =
        LineChart::new("Calibrated DEM against the experiment", "strain ε [-] (test direction)", "stress σ [MPa]");
    for (i, run) in r.best_runs.iter().enumerate() {
        let pts = run.curve.x.iter().zip(&run.curve.y).map(|(&x, &y)| (x, y / 1e6)).collect();
        chart = chart.series(if i == 0 { "DEM samples at the optimum" } else { "" }, pts, SeriesStyle::Line);
    }
    let tg = &r.targets;
    let top = tg.peak_stress.max(r.stats[3].mean);
    chart = chart.series("experiment: E", vec![(0.0, 0.0), (top / tg.young_modulus, top / 1e6)], SeriesStyle::Dashed);
    chart.series(
        "experiment: first crack, peak",
        vec![
            (tg.first_crack_stress / tg.young_modulus, tg.first_crack_stress / 1e6),
            (tg.peak_stress / tg.young_modulus, tg.peak_stress / 1e6),
        ],
        SeriesStyle::Markers,
    )
}

/// Rank 0: writes `text` to `file`.
pub(super) fn write_text(file: &Path, text: &str) -> Result<(), Error> {
    std::fs::write(file, text).map_err(io_err(file))
}

/// Rank 0: the virtual tests' curves (mean, then each sample) as CSV.
pub(super) fn write_dem_curves(job: &IdentifyJob, samples: &[Curve], mean: &Curve, name: &str) -> Result<(), Error> {
    let mut s = String::from("strain,stress");
    for k in 0..samples.len() {
        let _ = write!(s, ",stress_sample_{k}");
    }
    s.push('\n');
    for (i, (&x, &y)) in mean.x.iter().zip(&mean.y).enumerate() {
        let _ = write!(s, "{x:e},{y:e}");
        for c in samples {
            let _ = write!(s, ",{:e}", c.at(mean.x[i]));
        }
        s.push('\n');
    }
    let f = job.output_dir.join(name);
    std::fs::write(&f, s).map_err(io_err(&f))
}

/// Rank 0: the law's files (history, charts, material file); returns the material file's path.
pub(super) fn write_law(
    ctx: &Context,
    path: &Path,
    job: &IdentifyJob,
    fit: &LawFit,
    r: &LawResult,
    summary: &IdentifySummary,
    samples: Option<&(Vec<Curve>, Vec<Curve>)>,
) -> Result<String, Error> {
    log_law(ctx, fit, r);
    let f = job.output_dir.join("law.csv");
    std::fs::write(&f, law_history_csv(fit, r)).map_err(io_err(&f))?;
    draw_law(job, fit, r, samples)?;
    let provenance = provenance(path, job, fit, r, summary);
    write_material_files(ctx, job, &r.params, &provenance, "material.toml", job.material_copy.as_deref())
}

/// Rank 0: a material variant's files, `material-variant-<k>.toml` in the results and its copy
/// `<stem>-variant-<k>.toml` beside the material file the variants are named after (if any);
/// returns the path of the copy, else of the results' file.
pub(super) fn write_variant(
    ctx: &Context,
    path: &Path,
    job: &IdentifyJob,
    fit: &LawFit,
    r: &LawResult,
    summary: &IdentifySummary,
    variant: VariantFigure,
) -> Result<String, Error> {
    let k = variant.number;
    let copy = job.variants_beside.as_deref().map(|f| variant_path(f, k));
    let provenance = variant_provenance(path, job, fit, r, summary, variant);
    write_material_files(ctx, job, &r.params, &provenance, &format!("material-variant-{k}.toml"), copy.as_deref())
}

/// `<stem>-variant-<k>.toml` beside `file`.
fn variant_path(file: &Path, k: usize) -> PathBuf {
    let stem = file.file_stem().map_or_else(|| "material".into(), |s| s.to_string_lossy().into_owned());
    file.with_file_name(format!("{stem}-variant-{k}.toml"))
}

/// The identified law in the log: its parameters, the peaks of the DEM and of the law, every
/// error measure, and the fitted one.
fn log_law(ctx: &Context, fit: &LawFit, r: &LawResult) {
    let p = &r.params;
    ctx.log.info(format!(
        "identified law: eps0_t = {:.4e}, eps0_c = {:.4e}, gf_t = {:.4} J/m² ({}; softening energy f_t h/B_t {:.4} J/m²), a_c = {:.4}, b_c = {:.4}{} (E = {:.4e} Pa, nu = {:.3}, h = {} m)",
        p.eps0_t,
        p.eps0_c,
        p.gf_t,
        p.regularization.name(),
        fit.softening_energy(p),
        p.a_c,
        p.b_c,
        p.gf_c.map_or(String::new(), |g| format!(", gf_c = {g:.4} J/m²")),
        p.e,
        p.nu,
        fit.element_size
    ));
    ctx.log.info(format!(
        "  peaks: DEM tension {:.4e} Pa, law {:.4e} Pa; DEM compression {:.4e} Pa, law {:.4e} Pa{}",
        r.dem_peaks[0],
        r.law_peaks[0],
        r.dem_peaks[1],
        r.law_peaks[1],
        r.dem_sample_peaks.map_or(String::new(), |s| format!(
            " (samples: tension {:.4e} ± {:.2e}, compression {:.4e} ± {:.2e})",
            s[0].mean, s[0].std, s[1].mean, s[1].std
        ))
    ));
    for m in &r.measures {
        let v = |e: &Option<CurveError>| e.map_or("-".to_string(), |e| format!("{:.4}", e.value));
        let parts = |e: &Option<CurveError>| {
            e.and_then(|e| e.parts).map_or(String::new(), |p| {
                format!(
                    " [envelope {:.4}, peak {:+.4}, peak strain {:+.4}, post-peak energy {}: DEM {:.4e}, law {:.4e} J/m³]",
                    p.envelope,
                    p.peak,
                    p.peak_strain,
                    p.energy.map_or("-".into(), |x| format!("{x:+.4}")),
                    p.reference_energy,
                    p.model_energy
                )
            })
        };
        ctx.log.info(format!(
            "  {:13} tension {}{}, compression {}{}",
            m.measure,
            v(&m.tension),
            parts(&m.tension),
            v(&m.compression),
            parts(&m.compression)
        ));
    }
    ctx.log.info(format!(
        "  error ({:?}): tension {:.4} over {} points, compression {:.4} over {} points; peak error tension {:+.2}%, compression {:+.2}%",
        fit.measure,
        r.fit.tension.value,
        r.fit.tension.points,
        r.fit.compression.value,
        r.fit.compression.points,
        100.0 * r.tension_peak_error,
        100.0 * r.compression_peak_error
    ));
}

/// `law.csv`: every evaluation of the search with its point, its error (or why it failed) and
/// the best error so far.
fn law_history_csv(fit: &LawFit, r: &LawResult) -> String {
    let names = fit.space.names();
    let mut csv = format!("evaluation,iteration,{},objective,best_so_far,error\n", names.join(","));
    for (i, ((it, x, v), best)) in r.history.iter().zip(&r.best_so_far).enumerate() {
        let (val, err) = match v {
            Ok(v) => (format!("{v:e}"), String::new()),
            Err(e) => (String::new(), e.to_string().replace([',', '\n'], ";")),
        };
        let xs: Vec<String> = x.iter().map(|v| format!("{v:e}")).collect();
        let _ = writeln!(csv, "{i},{it},{},{val},{best:e},{err}", xs.join(","));
    }
    csv
}

/// `law_error.png` (the error history) and `law_tension.png`, `law_compression.png` (the DEM's
/// samples and mean against the law).
fn draw_law(
    job: &IdentifyJob,
    fit: &LawFit,
    r: &LawResult,
    samples: Option<&(Vec<Curve>, Vec<Curve>)>,
) -> Result<(), Error> {
    let dir = &job.output_dir;
    let plot = |c: LineChart, name: &str| -> Result<(), Error> { Ok(c.save_png(&dir.join(name))?) };
    let evals: Vec<(f64, f64)> =
        r.history.iter().enumerate().filter_map(|(i, (_, _, v))| v.as_ref().ok().map(|v| (i as f64, *v))).collect();
    let best: Vec<(f64, f64)> =
        r.best_so_far.iter().enumerate().filter(|(_, v)| v.is_finite()).map(|(i, v)| (i as f64, *v)).collect();
    plot(
        LineChart::new(
            "Damage-law identification: error history",
            "evaluation",
            &format!("error F ({:?})", fit.measure),
        )
        .series("each evaluation", evals, SeriesStyle::Markers)
        .series("best so far", best, SeriesStyle::Line),
        "law_error.png",
    )?;
    let mean_name = match job.spec.law.as_ref().map(|l| l.mean) {
        Some(MeanKind::Pointwise) => "DEM: mean of the samples",
        _ => "DEM: peak-aligned mean of the samples",
    };
    for (k, (name, dem, law, file)) in [
        ("tension", &fit.tension, &r.law_curves.0, "law_tension.png"),
        ("compression", &fit.compression, &r.law_curves.1, "law_compression.png"),
    ]
    .into_iter()
    .enumerate()
    {
        let end = dem.x[dem.x.len() - 1];
        let pts =
            |c: &Curve| c.x.iter().zip(&c.y).filter(|p| *p.0 <= end).map(|(&x, &y)| (x, y / 1e6)).collect::<Vec<_>>();
        let mut chart = LineChart::new(
            &format!("Uniaxial {name}: DEM against the identified law"),
            "strain ε [-] (test direction)",
            "stress σ [MPa]",
        );
        let own = samples.map(|s| if k == 0 { &s.0 } else { &s.1 });
        for (i, c) in own.into_iter().flatten().enumerate() {
            chart = chart.series(if i == 0 { "DEM samples" } else { "" }, pts(c), SeriesStyle::Dashed);
        }
        chart =
            chart.series(mean_name, pts(dem), SeriesStyle::Markers).series("damage law", pts(law), SeriesStyle::Line);
        plot(chart, file)?;
    }
    Ok(())
}

/// The material file `name` in the results folder, and its copy at `copy` if given; returns the
/// path of the copy, else of the results' file.
fn write_material_files(
    ctx: &Context,
    job: &IdentifyJob,
    law: &DamageParams,
    provenance: &Provenance,
    name: &str,
    copy: Option<&Path>,
) -> Result<String, Error> {
    let f = job.output_dir.join(name);
    write_material_file(&f, law, provenance)?;
    if let Some(copy) = copy {
        if let Some(parent) = copy.parent() {
            std::fs::create_dir_all(parent).map_err(io_err(parent))?;
        }
        write_material_file(copy, law, provenance)?;
        ctx.log.info(format!("material file: {} (and {})", f.display(), copy.display()));
        return Ok(copy.display().to_string());
    }
    ctx.log.info(format!("material file: {}", f.display()));
    Ok(f.display().to_string())
}
