//! Material variants (`[law] variants`, identify::variants): after the main law, the law fitted
//! again to subsets of the DEM samples, one variant after the other, each collective:
//!
//! ```text
//!  rank 0     the variants' samples (halves or bootstrap) → every rank
//!  per variant
//!   rank 0    its samples' mean curves (`[law] mean`, as the main law's) → every rank
//!   all       identify(): the main fit's design, optimizer settings, E, ν and h on them
//!   rank 0    material-variant-<k>.toml (results), <stem>-variant-<k>.toml (copy), log lines
//! ```
//! A variant's mean curves are those a law-only job would average from its samples alone (the
//! same `mean_of_samples`), so its law is the main law of such a job (`tests/identify.rs`).
use super::files::write_variant;
use super::{analysis_err, mean_of_samples, IdentifySummary};
use crate::config::{IdentifyJob, LawIdentConfig, LawVariants};
use crate::error::{Error, JobError};
use crate::identify::collective::broadcast_json;
use crate::identify::curves::Curve;
use crate::identify::law_fit::LawEvaluation;
use crate::identify::material_file::VariantFigure;
use crate::identify::variants::{variant_samples, VariantSamples, VariantScheme};
use crate::identify::{identify, LawFit, LawResult, Stat};
use crate::material::DamageParams;
use crate::parallel::{agree, Context};
use serde::Serialize;
use std::path::Path;

/// One variant in `summary.json`.
#[derive(Clone, Debug, Serialize)]
pub struct VariantSummary {
    /// Its number, 1..=count.
    pub variant: usize,
    /// How the samples were chosen.
    pub scheme: VariantScheme,
    /// Its samples in each test (numbered from 1 in the order of the curves).
    pub samples: VariantSamples,
    /// The material file written (the copy's path when there is one).
    pub material_file: String,
    /// Tensile strength f_t = E ε₀ᵗ [Pa].
    pub f_t: f64,
    /// Tensile fracture energy G_f [J/m²] (per the law's regularization).
    pub gf_t: f64,
    /// Compressive strength parameter f_c = E ε₀ᶜ / r [Pa] (material::params: the stress at the
    /// compressive threshold; the law's compressive peak is `law_peaks[1]`).
    pub f_c: f64,
    /// The whole law.
    pub params: DamageParams,
    /// The fitted measure's errors on the variant's mean curves.
    pub fit: LawEvaluation,
    /// The law's peaks against its mean curves' (`tension`, `compression`), relative.
    #[serde(with = "crate::io::summary::tension_compression")]
    pub peak_errors: [f64; 2],
    /// The law's peaks (`tension`, `compression`) [Pa].
    #[serde(with = "crate::io::summary::tension_compression")]
    pub law_peaks: [f64; 2],
    /// The variant's mean curves' peaks (`tension`, `compression`) [Pa].
    #[serde(with = "crate::io::summary::tension_compression")]
    pub dem_peaks: [f64; 2],
}

/// Collective. The variants of `[law] variants` (`v`), each fitted like `main` on the mean
/// curves of its samples (`samples`, significant on rank 0), their files written; rank 0 gets
/// their summaries (the others an empty list).
#[allow(clippy::too_many_arguments)] // the job and its settings, the main fit, the samples, the summary
pub(super) fn fit_variants(
    ctx: &Context,
    path: &Path,
    job: &IdentifyJob,
    l: &LawIdentConfig,
    v: &LawVariants,
    main: &LawFit,
    samples: Option<&(Vec<Curve>, Vec<Curve>)>,
    summary: &IdentifySummary,
) -> Result<Vec<VariantSummary>, Error> {
    let chosen = if ctx.rank == 0 { choose(v, samples).map(Some) } else { Ok(None) };
    let chosen = agree(&ctx.comm, chosen, Error::exit_code)?;
    let chosen: Vec<VariantSamples> = broadcast_json(ctx, chosen.as_ref()).map_err(analysis_err)?;
    let of = samples.map_or([0, 0], |(t, c)| [t.len(), c.len()]);
    let mut fitted = Vec::with_capacity(chosen.len());
    for (k, s) in chosen.into_iter().enumerate() {
        let figure = VariantFigure {
            number: k + 1,
            count: v.count,
            scheme: v.scheme.name(),
            seed: (v.scheme == VariantScheme::Bootstrap).then_some(v.seed),
            tension: s.tension.clone(),
            compression: s.compression.clone(),
            of,
        };
        ctx.log.info(format!(
            "material variant {}/{} ({}): tension samples {:?} of {}, compression samples {:?} of {}",
            figure.number, figure.count, figure.scheme, s.tension, of[0], s.compression, of[1]
        ));
        let curves = match samples {
            Some((t, c)) if ctx.rank == 0 => subset_curves(l, t, c, &s).map(Some),
            _ => Ok(None),
        };
        let curves = agree(&ctx.comm, curves, Error::exit_code)?;
        let (tension, compression, sample_peaks): (Curve, Curve, Option<[Stat; 2]>) =
            broadcast_json(ctx, curves.as_ref()).map_err(analysis_err)?;
        let fit = LawFit { tension, compression, sample_peaks, ..main.clone() };
        let result = agree(&ctx.comm, identify(ctx, &fit).map_err(analysis_err), Error::exit_code)?;
        let written = match &result {
            Some(r) => write_variant(ctx, path, job, &fit, r, summary, figure.clone()).map(Some),
            None => Ok(None),
        };
        if let (Some(r), Some(file)) = (result, agree(&ctx.comm, written, Error::exit_code)?) {
            let entry = variant_summary(v.scheme, &figure, s, file, r);
            log_variant(ctx, &entry);
            fitted.push(entry);
        }
    }
    Ok(fitted)
}

/// Rank 0. The variants' samples over the curves at hand.
fn choose(v: &LawVariants, samples: Option<&(Vec<Curve>, Vec<Curve>)>) -> Result<Vec<VariantSamples>, Error> {
    let Some((t, c)) = samples else {
        return Err(JobError::VariantsWithoutSamples.into());
    };
    variant_samples(v.scheme, v.count, v.seed, t.len(), c.len()).map_err(analysis_err)
}

/// Rank 0. The mean curves of a variant's samples, as a law-only job of those samples alone
/// would average them, checked, and the samples' peaks.
fn subset_curves(
    l: &LawIdentConfig,
    tension: &[Curve],
    compression: &[Curve],
    s: &VariantSamples,
) -> Result<(Curve, Curve, Option<[Stat; 2]>), Error> {
    let ts = VariantSamples::pick(tension, &s.tension);
    let cs = VariantSamples::pick(compression, &s.compression);
    let r = mean_of_samples(l, &ts, &cs)?;
    r.tension.check("DEM tension curve of the variant").map_err(analysis_err)?;
    r.compression.check("DEM compression curve of the variant").map_err(analysis_err)?;
    Ok((r.tension, r.compression, r.sample_peaks))
}

/// The variant's entry of `summary.json`.
fn variant_summary(
    scheme: VariantScheme,
    figure: &VariantFigure,
    samples: VariantSamples,
    file: String,
    r: LawResult,
) -> VariantSummary {
    let p = r.params;
    VariantSummary {
        variant: figure.number,
        scheme,
        samples,
        material_file: file,
        f_t: p.tensile_strength(),
        gf_t: p.gf_t,
        f_c: p.compressive_strength(),
        params: p,
        fit: r.fit,
        peak_errors: [r.tension_peak_error, r.compression_peak_error],
        law_peaks: r.law_peaks,
        dem_peaks: r.dem_peaks,
    }
}

/// The variant's law and errors in the log.
fn log_variant(ctx: &Context, v: &VariantSummary) {
    let p = &v.params;
    ctx.log.info(format!(
        "material variant {}: eps0_t = {:.4e} (f_t = {:.4e} Pa), gf_t = {:.4} J/m², eps0_c = {:.4e} (f_c = {:.4e} Pa), a_c = {:.4}, b_c = {:.4}{}",
        v.variant,
        p.eps0_t,
        v.f_t,
        p.gf_t,
        p.eps0_c,
        v.f_c,
        p.a_c,
        p.b_c,
        p.gf_c.map_or(String::new(), |g| format!(", gf_c = {g:.4} J/m²"))
    ));
    ctx.log.info(format!(
        "  error: tension {:.4}, compression {:.4}; peaks: tension {:.4e} Pa ({:+.2}%), compression {:.4e} Pa ({:+.2}%) against its samples' mean curves",
        v.fit.tension.value,
        v.fit.compression.value,
        v.law_peaks[0],
        100.0 * v.peak_errors[0],
        v.law_peaks[1],
        100.0 * v.peak_errors[1]
    ));
}
