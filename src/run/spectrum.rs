//! Response-spectrum analysis of a ground motion (rank 0; cheap), with Eurocode 8 elastic spectra
//! for comparison, like the paper's Fig. 7.
//!
//! Outputs: `spectrum.csv` (T, Sd, Sv, Sa at the job's damping), `spectrum.png` (Sa of the record
//! against the EC8 spectra), `record.png` (the acceleration history), and in `summary.json` the
//! record's intensity measures (PGA, PGV, PGD, Arias intensity, D5–95) and peak Sa.
use crate::config::SpectrumJob;
use crate::error::Error;
use crate::parallel::{agree, Context};
use crate::seismic::{intensity, log_periods, record_png, response_spectrum, spectrum_png, Ec8Spectrum, Ec8Type};
use std::fmt::Write as _;

/// What a spectrum run reports.
#[derive(Debug, Clone, serde::Serialize)]
pub struct SpectrumSummary {
    /// Record name.
    pub record: String,
    /// Duration [s].
    pub duration: f64,
    /// Time step [s].
    pub dt: f64,
    /// Peak ground acceleration [m/s²].
    pub pga: f64,
    /// Peak ground velocity [m/s].
    pub pgv: f64,
    /// Peak ground displacement [m].
    pub pgd: f64,
    /// Arias intensity [m/s].
    pub arias: f64,
    /// Significant duration D5–95 [s].
    pub d5_95: f64,
    /// Damping ratio.
    pub damping: f64,
    /// Largest Sa [m/s²] (`sa`) and its `period` [s].
    #[serde(serialize_with = "peak_names")]
    pub peak_sa: (f64, f64),
}

/// `(Sa, T)` as `{"sa": …, "period": …}`.
fn peak_names<S: serde::Serializer>(p: &(f64, f64), s: S) -> Result<S::Ok, S::Error> {
    crate::io::summary::write_named(&["sa", "period"], &[p.0, p.1], s)
}

/// Collective. Runs the job; rank 0 writes.
pub fn run(ctx: &Context, job: &SpectrumJob) -> Result<Option<SpectrumSummary>, Error> {
    let out = if ctx.rank == 0 { compute(ctx, job).map(Some) } else { Ok(None) };
    agree(&ctx.comm, out, Error::exit_code).map_err(Error::from)
}

fn compute(ctx: &Context, job: &SpectrumJob) -> Result<SpectrumSummary, Error> {
    let r = &job.record;
    let a = &job.spec.analysis;
    let dir = &job.output_dir;
    let periods = log_periods(a.periods.min, a.periods.max, a.periods.count);
    let sp = response_spectrum(r, &periods, a.damping)?;
    let mut csv = String::from("period,sd,sv,sa\n");
    for i in 0..sp.periods.len() {
        let _ = writeln!(csv, "{:e},{:e},{:e},{:e}", sp.periods[i], sp.sd[i], sp.sv[i], sp.sa[i]);
    }
    let f = dir.join("spectrum.csv");
    std::fs::write(&f, csv).map_err(|source| Error::OutputDir { path: f.clone(), source })?;
    let mut code = Vec::new();
    if let Some(e) = &job.spec.ec8 {
        let fine: Vec<f64> = (0..=400).map(|i| i as f64 * a.periods.max / 400.0).collect();
        for &t in &e.types {
            let s = Ec8Spectrum::new(t, e.ground, e.ag, 100.0 * a.damping)?;
            let kind = match t {
                Ec8Type::Type1 => "type 1 (Ms > 5.5)",
                Ec8Type::Type2 => "type 2 (Ms ≤ 5.5)",
            };
            code.push((format!("EC8 {kind}, ground {:?}, a_g = {} m/s²", e.ground, e.ag), s.curve(&fine)));
        }
    }
    let title = job.spec.title.clone().unwrap_or_else(|| format!("{}: elastic response spectrum", r.name));
    spectrum_png(&dir.join("spectrum.png"), &title, &[(r.name.as_str(), &sp)], &code)?;
    record_png(&dir.join("record.png"), r)?;
    let im = intensity(r);
    let peak = sp.sa.iter().zip(&sp.periods).fold((0.0, 0.0), |m, (s, t)| if *s > m.0 { (*s, *t) } else { m });
    ctx.log.info(format!(
        "{}: {} s at dt = {} s; PGA {:.4} m/s², PGV {:.4} m/s, PGD {:.4} m, Arias {:.4} m/s, D5-95 {:.2} s",
        r.name,
        r.duration(),
        r.dt,
        im.pga,
        im.pgv,
        im.pgd,
        im.arias,
        im.d5_95()
    ));
    ctx.log.info(format!("peak Sa ({:.0}% damping) = {:.4} m/s² at T = {:.3} s", 100.0 * a.damping, peak.0, peak.1));
    Ok(SpectrumSummary {
        record: r.name.clone(),
        duration: r.duration(),
        dt: r.dt,
        pga: im.pga,
        pgv: im.pgv,
        pgd: im.pgd,
        arias: im.arias,
        d5_95: im.d5_95(),
        damping: a.damping,
        peak_sa: peak,
    })
}
