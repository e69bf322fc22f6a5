//! The identification job (SPEC §3): (a) DEM calibration against the experiment, (b) damage-law
//! identification from the (calibrated) DEM's virtual tests, (c) both as one chain ending in a
//! material file. Phases, each collective and followed by an agreement on errors:
//!
//! ```text
//!  calibrate      staged: elastic α, Ē (1-D root) → calibration_elastic.csv
//!                 then strengths: LHS × samples → EGO (q-EI); or joint: all unknowns by EGO
//!                                                 → calibration.json/.csv, calibration.png
//!  virtual tests  tension + compression × samples → dem_tension.csv, dem_compression.csv
//!  identify law   2⁵ factorial → EGO (q-EI)       → law.csv, law_error.png, law_tension.png,
//!                                                   law_compression.png, material.toml
//! ```
//! Rank 0 writes every file; `summary.json` gathers the numbers and the phase timings.
use crate::config::IdentifyJob;
use crate::error::Error;
use crate::identify::calibration::Stat;
use crate::identify::calibration::{CalibrationResult, QUANTITIES};
use crate::identify::collective::broadcast_json;
use crate::identify::curves::{mean_of, sample_curves_csv, Curve};
use crate::identify::material_file::{write_material_file, Provenance};
use crate::identify::virtual_tests::run_virtual_tests;
use crate::identify::{calibrate, identify, Calibration, EgoSettings, IdentifyError, LawFit, LawResult, Space};
use crate::parallel::{agree, Context};
use crate::plot::{LineChart, SeriesStyle};
use serde::Serialize;
use std::fmt::Write as _;
use std::path::Path;
use std::time::Instant;

/// What an identification reports (`summary.json`).
#[derive(Clone, Debug, Default, Serialize)]
pub struct IdentifySummary {
    /// Ranks.
    pub ranks: usize,
    /// Stage (a), if it ran.
    pub calibration: Option<CalibrationResult>,
    /// Whether each sample mean is within 5% of its target (E, ν, first crack, peak).
    pub calibration_within_5_percent: Option<[bool; 4]>,
    /// Stage (b), if it ran.
    pub law: Option<LawResult>,
    /// The material file written.
    pub material_file: Option<String>,
    /// Failed DEM samples of the virtual tests.
    pub virtual_test_failures: Vec<String>,
    /// Wall time per phase [s]: calibration, virtual tests, law identification.
    pub seconds: PhaseSeconds,
}

/// Wall time per phase [s].
#[derive(Clone, Debug, Default, Serialize)]
pub struct PhaseSeconds {
    /// DEM calibration.
    pub calibration: f64,
    /// Virtual tests of the calibrated DEM.
    pub virtual_tests: f64,
    /// Damage-law identification.
    pub law: f64,
    /// The whole job.
    pub total: f64,
}

fn analysis_err(e: IdentifyError) -> Error {
    Error::Analysis(e.to_string())
}

fn io_err(path: &Path) -> impl Fn(std::io::Error) -> Error + '_ {
    move |source| Error::OutputDir { path: path.to_path_buf(), source }
}

/// Collective. Runs the job's stages and writes the outputs.
pub fn run(ctx: &Context, path: &Path, job: &IdentifyJob) -> Result<IdentifySummary, Error> {
    let t_all = Instant::now();
    let spec = &job.spec;
    let seed = spec.analysis.seed;
    let mut summary = IdentifySummary { ranks: ctx.size, ..Default::default() };
    let mut dem = job.dem;

    // (a) DEM calibration.
    if let (Some(c), Some(targets)) = (&spec.calibration, job.targets) {
        let t0 = Instant::now();
        let b = &c.bounds;
        let mut unknowns = vec![("alpha", b.alpha), ("e_bar", b.e_bar), ("eps_cr", b.eps_cr), ("theta_cr", b.theta_cr)];
        if let Some(sc) = b.crushing_stress {
            unknowns.push(("crushing_stress", sc));
        }
        let space = Space::new(&unknowns).map_err(analysis_err)?;
        let cal = Calibration {
            sample: spec.sample.clone(),
            fixed: dem,
            test: c.test.clone(),
            samples: c.samples,
            space,
            targets,
            weights: c.weights,
            design_points: c.design_points,
            seed,
            ego: EgoSettings { iterations: c.iterations, batch: c.batch, seed, log_transform: true, target: None },
            strategy: c.strategy,
        };
        let result = agree(&ctx.comm, calibrate(ctx, &cal).map_err(analysis_err), Error::exit_code)?;
        let written = match &result {
            Some(r) => write_calibration(ctx, job, r).map(|_| r.parameters),
            None => Ok(dem),
        };
        let calibrated = agree(&ctx.comm, written, Error::exit_code)?;
        dem = broadcast_json(ctx, Some(&calibrated)).map_err(analysis_err)?;
        summary.calibration_within_5_percent = result.as_ref().map(|r| r.relative_errors.map(|e| e.abs() < 0.05));
        summary.calibration = result;
        summary.seconds.calibration = t0.elapsed().as_secs_f64();
    }

    // (b) damage-law identification.
    if let Some(l) = &spec.law {
        let t0 = Instant::now();
        let experiment = spec.experiment.clone().unwrap_or_default();
        // Reference curves (and whether they are already on a uniform grid from 0), the DEM's
        // elastic constants and the samples' peaks, on rank 0.
        type Reference = (Curve, Curve, bool, f64, f64, Option<[Stat; 2]>);
        let test_max = |t: &Option<crate::dem::solver::VirtualTest>, samples: &[Curve]| match t {
            Some(
                crate::dem::solver::VirtualTest::Tension { max_strain, .. }
                | crate::dem::solver::VirtualTest::Compression { max_strain, .. },
            ) => *max_strain,
            _ => samples.iter().map(|c| c.x[c.x.len() - 1]).fold(0.0, f64::max),
        };
        // The samples' curves, for the pictures (rank 0).
        let mut sample_curves: Option<(Vec<Curve>, Vec<Curve>)> = job.dem_samples.clone();
        let reference: Result<Option<Reference>, Error> = match (&job.dem_curves, &job.dem_samples) {
            (Some((t, c)), _) => Ok(Some((t.clone(), c.clone(), false, f64::NAN, f64::NAN, None))),
            (None, Some((ts, cs))) if ctx.rank == 0 => {
                let peaks = |s: &[Curve]| Stat::of(&s.iter().map(|c| c.peak().0).collect::<Vec<_>>());
                mean_of(l.mean, ts, test_max(&l.tension, ts), l.points, "DEM tension curve")
                    .and_then(|t| {
                        Ok((t, mean_of(l.mean, cs, test_max(&l.compression, cs), l.points, "DEM compression curve")?))
                    })
                    .map(|(t, c)| Some((t, c, true, f64::NAN, f64::NAN, Some([peaks(ts), peaks(cs)]))))
                    .map_err(analysis_err)
            }
            (None, Some(_)) => Ok(None),
            (None, None) => {
                let (Some(tt), Some(ct)) = (&l.tension, &l.compression) else {
                    return Err(Error::Analysis("[law] needs tension and compression tests".into()));
                };
                let v = run_virtual_tests(ctx, &spec.sample, &dem, tt, ct, l.samples, l.points, l.mean)
                    .map_err(analysis_err);
                let v = agree(&ctx.comm, v, Error::exit_code)?;
                let out = match v {
                    Some(v) => {
                        for f in &v.failures {
                            ctx.log.warn(f);
                        }
                        summary.virtual_test_failures = v.failures.clone();
                        ctx.log.info(format!(
                            "virtual tests: E = {:.4e} Pa, nu = {:.4} (compression means); sample peaks: tension {:.4e} ± {:.2e} Pa (n = {}), compression {:.4e} ± {:.2e} Pa (n = {})",
                            v.young_modulus, v.poisson, v.peaks[0].mean, v.peaks[0].std, v.peaks[0].n, v.peaks[1].mean, v.peaks[1].std, v.peaks[1].n
                        ));
                        write_dem_curves(job, &v.tension_samples, &v.tension, "dem_tension.csv")
                            .and_then(|_| {
                                write_dem_curves(job, &v.compression_samples, &v.compression, "dem_compression.csv")
                            })
                            .and_then(|_| {
                                write_text(
                                    &job.output_dir.join("dem_tension_samples.csv"),
                                    &sample_curves_csv(&v.tension_samples),
                                )
                            })
                            .and_then(|_| {
                                write_text(
                                    &job.output_dir.join("dem_compression_samples.csv"),
                                    &sample_curves_csv(&v.compression_samples),
                                )
                            })
                            .map(|_| {
                                sample_curves = Some((v.tension_samples, v.compression_samples));
                                Some((v.tension, v.compression, true, v.young_modulus, v.poisson, Some(v.peaks)))
                            })
                    }
                    None => Ok(None),
                };
                out
            }
        };
        let reference = agree(&ctx.comm, reference, Error::exit_code)?;
        summary.seconds.virtual_tests = t0.elapsed().as_secs_f64();
        let t1 = Instant::now();
        let sample_peaks = reference.as_ref().and_then(|r| r.5);
        let sample_peaks: Option<[Stat; 2]> = broadcast_json(ctx, Some(&sample_peaks)).map_err(analysis_err)?;
        let prepared = reference
            .map(|(t, c, gridded, e_dem, nu_dem, _)| -> Result<(Curve, Curve, f64, f64), Error> {
                let (e_x, nu_x) = match l.elastic {
                    crate::config::ElasticSource::Experiment => (experiment.young_modulus, experiment.poisson),
                    crate::config::ElasticSource::Dem => (None, None),
                };
                let e = l.young_modulus.or(e_x).unwrap_or(e_dem);
                let nu = l.poisson.or(nu_x).unwrap_or(nu_dem);
                if e_dem.is_finite() && (e - e_dem).abs() > 0.05 * e_dem {
                    ctx.log.warn(format!(
                        "the law's E = {e:.4e} Pa differs from the virtual tests' mean E = {e_dem:.4e} Pa by more than 5%: the law cannot follow the DEM's elastic branch (set [law] elastic = \"dem\" to use the DEM's)"
                    ));
                }
                if !(e.is_finite() && e > 0.0 && nu.is_finite() && nu > -1.0 && nu < 0.5) {
                    return Err(Error::Analysis(format!(
                        "{}: [law] needs young_modulus and poisson (or [experiment] ones) when the DEM curves come from files",
                        path.display()
                    )));
                }
                // Mean curves of samples are on their own uniform grids (through the mean peak
                // when peak-aligned); curves from dem_curves files are put on one.
                let (t, c) = if gridded {
                    t.check("DEM tension curve").and_then(|_| c.check("DEM compression curve")).map_err(analysis_err)?;
                    (t, c)
                } else {
                    (
                        LawFit::on_grid(&t, l.points, "DEM tension curve").map_err(analysis_err)?,
                        LawFit::on_grid(&c, l.points, "DEM compression curve").map_err(analysis_err)?,
                    )
                };
                Ok((t, c, e, nu))
            })
            .transpose();
        let prepared = agree(&ctx.comm, prepared, Error::exit_code)?;
        let (tension, compression, e, nu) = broadcast_json(ctx, prepared.as_ref()).map_err(analysis_err)?;
        let b = &l.bounds;
        let mut unknowns =
            vec![("eps0_t", b.eps0_t), ("eps0_c", b.eps0_c), ("gf_t", b.gf_t), ("a_c", b.a_c), ("b_c", b.b_c)];
        if let Some(g) = b.gf_c {
            unknowns.push((crate::identify::law_fit::GF_C, g));
        }
        let space = Space::new(&unknowns).map_err(analysis_err)?;
        let h = l.element_size.unwrap_or(spec.sample.layout.domain().1);
        let fit = LawFit {
            young_modulus: e,
            poisson: nu,
            regularization: l.regularization,
            element_size: h,
            tension,
            compression,
            measure: l.error,
            space,
            sample_peaks,
            levels: l.levels,
            ego: EgoSettings {
                iterations: l.iterations,
                batch: l.batch,
                seed: seed.wrapping_add(1000),
                log_transform: true,
                target: None,
            },
            polish_iterations: l.polish_iterations,
        };
        let result = agree(&ctx.comm, identify(ctx, &fit).map_err(analysis_err), Error::exit_code)?;
        let written = match &result {
            Some(r) => write_law(ctx, path, job, &fit, r, &summary, sample_curves.as_ref()).map(Some),
            None => Ok(None),
        };
        summary.material_file = agree(&ctx.comm, written, Error::exit_code)?;
        summary.law = result;
        summary.seconds.law = t1.elapsed().as_secs_f64();
    }
    summary.seconds.total = t_all.elapsed().as_secs_f64();
    ctx.log.info(format!(
        "identification wall time {:.2} s (calibration {:.2} s, virtual tests {:.2} s, law {:.2} s) on {} rank(s)",
        summary.seconds.total,
        summary.seconds.calibration,
        summary.seconds.virtual_tests,
        summary.seconds.law,
        ctx.size
    ));
    Ok(summary)
}

/// Rank 0: the calibration's files and log lines.
fn write_calibration(ctx: &Context, job: &IdentifyJob, r: &CalibrationResult) -> Result<(), Error> {
    let dir = &job.output_dir;
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
    if let Some(el) = &r.elastic {
        ctx.log.info(format!(
            "  stage 1 (elastic): {} alpha value(s) evaluated, nu {} its tolerance{}",
            el.points.len(),
            if el.converged { "within" } else { "NOT within" },
            el.note.as_ref().map_or(String::new(), |n| format!(": {n}"))
        ));
        let mut csv = String::from("round,alpha,poisson_mean,poisson_std,e_over_e_bar_mean,e_over_e_bar_std,n,error\n");
        for p in &el.points {
            let _ = match &p.value {
                Ok(m) => writeln!(
                    csv,
                    "{},{:e},{:e},{:e},{:e},{:e},{},",
                    p.round, p.alpha, m.poisson.mean, m.poisson.std, m.e_ratio.mean, m.e_ratio.std, m.poisson.n
                ),
                Err(e) => writeln!(csv, "{},{:e},,,,,,{}", p.round, p.alpha, e.replace([',', '\n'], ";")),
            };
        }
        let f = dir.join("calibration_elastic.csv");
        std::fs::write(&f, csv).map_err(io_err(&f))?;
    }
    let crushing = r.history.first().is_some_and(|h| h.1.len() > 4);
    let mut csv = String::from(if crushing {
        "evaluation,iteration,alpha,e_bar,eps_cr,theta_cr,crushing_stress,objective,error\n"
    } else {
        "evaluation,iteration,alpha,e_bar,eps_cr,theta_cr,objective,error\n"
    });
    for (i, (it, x, v)) in r.history.iter().enumerate() {
        let (val, err) = match v {
            Ok(v) => (format!("{v:e}"), String::new()),
            Err(e) => (String::new(), e.replace([',', '\n'], ";")),
        };
        let extra = x.get(4).map_or(String::new(), |v| format!("{v:e},"));
        let _ = writeln!(csv, "{i},{it},{:e},{:e},{:e},{:e},{extra}{val},{err}", x[0], x[1], x[2], x[3]);
    }
    let f = dir.join("calibration.csv");
    std::fs::write(&f, csv).map_err(io_err(&f))?;
    let f = dir.join("calibration.json");
    let text = serde_json::to_string_pretty(r)
        .map_err(|e| Error::Analysis(format!("{}: the calibration cannot be written as JSON: {e}", f.display())))?;
    std::fs::write(&f, text + "\n").map_err(io_err(&f))?;
    // The calibrated DEM's curves against the experimental points.
    let mut chart =
        LineChart::new("Calibrated DEM against the experiment", "strain ε [-] (test direction)", "stress σ [MPa]");
    for (i, run) in r.best_runs.iter().enumerate() {
        let pts = run.curve.x.iter().zip(&run.curve.y).map(|(&x, &y)| (x, y / 1e6)).collect();
        chart = chart.series(if i == 0 { "DEM samples at the optimum" } else { "" }, pts, SeriesStyle::Line);
    }
    let tg = &r.targets;
    let top = tg.peak_stress.max(r.stats[3].mean);
    chart = chart.series("experiment: E", vec![(0.0, 0.0), (top / tg.young_modulus, top / 1e6)], SeriesStyle::Dashed);
    chart = chart.series(
        "experiment: first crack, peak",
        vec![
            (tg.first_crack_stress / tg.young_modulus, tg.first_crack_stress / 1e6),
            (tg.peak_stress / tg.young_modulus, tg.peak_stress / 1e6),
        ],
        SeriesStyle::Markers,
    );
    let f = dir.join("calibration.png");
    chart.save_png(&f).map_err(|e| Error::Analysis(e.to_string()))
}

/// Rank 0: writes `text` to `file`.
fn write_text(file: &Path, text: &str) -> Result<(), Error> {
    std::fs::write(file, text).map_err(io_err(file))
}

/// Rank 0: the virtual tests' curves (mean, then each sample) as CSV.
fn write_dem_curves(job: &IdentifyJob, samples: &[Curve], mean: &Curve, name: &str) -> Result<(), Error> {
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
fn write_law(
    ctx: &Context,
    path: &Path,
    job: &IdentifyJob,
    fit: &LawFit,
    r: &LawResult,
    summary: &IdentifySummary,
    samples: Option<&(Vec<Curve>, Vec<Curve>)>,
) -> Result<String, Error> {
    let dir = &job.output_dir;
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
        let v = |e: &Option<crate::identify::CurveError>| e.map_or("-".to_string(), |e| format!("{:.4}", e.value));
        let parts = |e: &Option<crate::identify::CurveError>| {
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
    let names = fit.space.names();
    let mut csv = format!("evaluation,iteration,{},objective,best_so_far,error\n", names.join(","));
    for (i, ((it, x, v), best)) in r.history.iter().zip(&r.best_so_far).enumerate() {
        let (val, err) = match v {
            Ok(v) => (format!("{v:e}"), String::new()),
            Err(e) => (String::new(), e.replace([',', '\n'], ";")),
        };
        let xs: Vec<String> = x.iter().map(|v| format!("{v:e}")).collect();
        let _ = writeln!(csv, "{i},{it},{},{val},{best:e},{err}", xs.join(","));
    }
    let f = dir.join("law.csv");
    std::fs::write(&f, csv).map_err(io_err(&f))?;
    let plot = |c: LineChart, name: &str| -> Result<(), Error> {
        c.save_png(&dir.join(name)).map_err(|e| Error::Analysis(e.to_string()))
    };
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
        Some(crate::identify::curves::MeanKind::Pointwise) => "DEM: mean of the samples",
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
    let provenance = provenance(path, job, fit, r, summary);
    let f = dir.join("material.toml");
    write_material_file(&f, p, &provenance).map_err(Error::Analysis)?;
    if let Some(copy) = &job.material_copy {
        if let Some(parent) = copy.parent() {
            std::fs::create_dir_all(parent).map_err(io_err(parent))?;
        }
        write_material_file(copy, p, &provenance).map_err(Error::Analysis)?;
        ctx.log.info(format!("material file: {} (and {})", f.display(), copy.display()));
        return Ok(copy.display().to_string());
    }
    ctx.log.info(format!("material file: {}", f.display()));
    Ok(f.display().to_string())
}

/// The material file's provenance (identify::material_file) from the job and its results.
fn provenance(path: &Path, job: &IdentifyJob, fit: &LawFit, r: &LawResult, summary: &IdentifySummary) -> Provenance {
    use crate::identify::material_file::{MeasureFigure, PeakFigure, TargetFigure};
    let spec = &job.spec;
    let law = spec.law.as_ref();
    let from_files = job.dem_curves.is_some() || job.dem_samples.is_some();
    let seeds = |n: usize| (0..n as u64).map(|k| spec.sample.seed.wrapping_add(k)).collect::<Vec<_>>();
    let calibration_sample_seeds = match (&spec.calibration, &summary.calibration) {
        (Some(c), Some(_)) => seeds(c.samples),
        _ => Vec::new(),
    };
    let mean = match law.map(|l| l.mean) {
        Some(crate::identify::curves::MeanKind::Pointwise) => "pointwise",
        _ => "peak-aligned",
    };
    let test = |t: &Option<crate::dem::solver::VirtualTest>| match t {
        Some(crate::dem::solver::VirtualTest::Tension { max_strain, steps }) => {
            format!("tension to {max_strain:e} in {steps} steps")
        }
        Some(crate::dem::solver::VirtualTest::Compression { max_strain, steps }) => {
            format!("compression to {max_strain:e} in {steps} steps")
        }
        _ => "-".to_string(),
    };
    let curves = match (law, &job.dem_curves, &job.dem_samples) {
        (Some(l), Some(_), _) => l.dem_curves.as_ref().map_or(String::new(), |f| {
            format!("mean curves from the files {} and {} (paths from the job's folder)", f.tension.display(), f.compression.display())
        }),
        (Some(l), None, Some(_)) => l.dem_samples.as_ref().map_or(String::new(), |f| {
            format!(
                "every sample's curve from the files {} and {} (paths from the job's folder), {mean} mean on about {} points",
                f.tension.display(),
                f.compression.display(),
                l.points
            )
        }),
        (Some(l), None, None) => format!(
            "virtual tests of the {} DEM on the job's [sample] wall: {} and {}, {} samples each, {mean} mean on about {} points",
            if summary.calibration.is_some() { "calibrated" } else { "given" },
            test(&l.tension),
            test(&l.compression),
            l.samples,
            l.points
        ),
        _ => String::new(),
    };
    let elastic = match law {
        Some(l) if l.young_modulus.is_some() || l.poisson.is_some() => {
            "E and nu given in the job's [law] table".to_string()
        }
        Some(l) if l.elastic == crate::config::ElasticSource::Dem => {
            "E and nu: the virtual compression tests' means ([law] elastic = dem)".to_string()
        }
        _ => "E and nu: the job's [experiment] table".to_string(),
    };
    let calibration = summary.calibration.as_ref().map_or(Vec::new(), |c| {
        let t = c.targets.as_array();
        (0..4)
            .map(|k| TargetFigure {
                name: QUANTITIES[k],
                target: t[k],
                mean: c.stats[k].mean,
                std: c.stats[k].std,
                n: c.stats[k].n,
                relative_error: c.relative_errors[k],
            })
            .collect()
    });
    let peak = |k: usize, e: f64| PeakFigure {
        dem: r.dem_peaks[k],
        law: r.law_peaks[k],
        relative_error: e,
        samples: r.dem_sample_peaks.map(|s| (s[k].mean, s[k].std, s[k].n)),
    };
    Provenance {
        job: path.to_path_buf(),
        method: format!(
            "2^{} factorial + EGO (kriging, q-EI) + Nelder-Mead on the {} error between the law (plane-stress material point, uniaxial stress, element size h) and the DEM's mean tension and compression curves ({mean} mean of the samples)",
            fit.space.dim(),
            fit.measure.name(),
        ),
        seed: spec.analysis.seed,
        calibration_sample_seeds,
        law_sample_seeds: if from_files { Vec::new() } else { seeds(law.map_or(0, |l| l.samples)) },
        curves,
        elastic,
        element_size: fit.element_size,
        softening_energy: fit.softening_energy(&r.params),
        error_tension: r.fit.tension.value,
        error_compression: r.fit.compression.value,
        error_measure: fit.measure.name().to_string(),
        measures: r
            .measures
            .iter()
            .map(|m| MeasureFigure { measure: m.measure, tension: m.tension.map(|e| e.value), compression: m.compression.map(|e| e.value) })
            .collect(),
        peaks: Some([peak(0, r.tension_peak_error), peak(1, r.compression_peak_error)]),
        dem: if from_files { None } else { Some(summary.calibration.as_ref().map_or(job.dem, |c| c.parameters)) },
        calibration,
        virtual_test_failures: summary.virtual_test_failures.clone(),
        notes: law.and_then(|l| l.material_notes.clone()),
    }
}
