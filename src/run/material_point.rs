//! Material-point analysis: one point of the damage law along a strain path.
//!
//! Outputs in the results folder:
//! * `curve.csv`: per step, the strain and stress components, d_t, d_c, κ_t, κ_c and the
//!   dissipated energy density;
//! * `stress_strain.png`: the driven stress against the driven strain (σ_xx–ε_xx, or τ_xy–γ_xy
//!   for pure shear); `damage.png`: d_t and d_c against the same strain;
//! * `summary.json`: the peak of the driven stress and the strain where it occurs, the final
//!   damage, the dissipated energy density and, for reference, E ε₀^t and the law's B_t.
//!
//! The computation is serial and cheap: rank 0 runs it, every rank agrees on the outcome.
use crate::config::{Kinematics, MaterialPointJob, PathConfig};
use crate::error::Error;
use crate::material::{
    run_path_into, LoadPath, NewtonSettings, PathError, PathRecord, PlaneStress, StressState, ThreeD, Uniaxial,
};
use crate::parallel::Context;
use crate::plot::{LineChart, SeriesStyle};
use std::fmt::Write as _;
use std::path::Path;

/// What a material-point run reports.
#[derive(Debug, Clone, serde::Serialize)]
pub struct MaterialPointSummary {
    /// Stress state.
    pub kinematics: String,
    /// Element size h [m].
    pub element_size: f64,
    /// The driven strain component (`xx`, or `xy` for pure shear).
    pub driven_component: String,
    /// Steps computed.
    pub steps: usize,
    /// Largest |driven stress| [Pa], with its sign.
    pub peak_stress: f64,
    /// Driven strain at that peak.
    pub strain_at_peak: f64,
    /// Final tensile damage.
    pub final_d_t: f64,
    /// Final compressive damage.
    pub final_d_c: f64,
    /// Energy dissipated per unit volume [J/m³].
    pub dissipated_energy_density: f64,
    /// E ε₀^t [Pa], the closed-form tensile strength.
    pub tensile_strength: f64,
    /// The regularized softening parameter B_t of the law at this h.
    pub b_t: f64,
}

/// Collective. Runs the job; rank 0 writes the outputs.
pub fn run(ctx: &Context, job: &MaterialPointJob) -> Result<MaterialPointSummary, Error> {
    let result = if ctx.rank == 0 { compute_and_write(ctx, job) } else { Ok(None) };
    let summary = crate::parallel::agree(&ctx.comm, result, Error::exit_code)?;
    // Only rank 0 holds the summary; the others return a copy of what they can know.
    Ok(summary.unwrap_or_else(|| MaterialPointSummary {
        kinematics: String::new(),
        element_size: job.spec.analysis.element_size,
        driven_component: String::new(),
        steps: 0,
        peak_stress: f64::NAN,
        strain_at_peak: f64::NAN,
        final_d_t: f64::NAN,
        final_d_c: f64::NAN,
        dissipated_energy_density: f64::NAN,
        tensile_strength: job.law.tensile_strength(),
        b_t: job.law.b_t(),
    }))
}

fn compute_and_write(ctx: &Context, job: &MaterialPointJob) -> Result<Option<MaterialPointSummary>, Error> {
    match job.spec.analysis.kinematics {
        Kinematics::PlaneStress => drive::<3, PlaneStress>(ctx, job, PlaneStress, "plane_stress"),
        Kinematics::Uniaxial => drive::<1, Uniaxial>(ctx, job, Uniaxial, "uniaxial"),
        Kinematics::ThreeD => drive::<6, ThreeD>(ctx, job, ThreeD, "three_d"),
    }
    .map(Some)
}

fn path_error(job: &MaterialPointJob, e: PathError) -> Error {
    match e {
        PathError::InvalidPath { .. } => job.source.error_at(&[crate::config::Seg::key("path")], e.to_string()).into(),
        other => Error::MaterialPoint { source: other, reached: None },
    }
}

fn build_path<const N: usize, M: StressState<N>>(p: &PathConfig) -> Result<LoadPath<N>, PathError> {
    match p {
        PathConfig::UniaxialTension(c) => LoadPath::uniaxial_tension(c.max_strain, c.steps),
        PathConfig::UniaxialCompression(c) => LoadPath::uniaxial_compression(c.max_shortening, c.steps),
        PathConfig::Uniaxial(c) => LoadPath::uniaxial(&c.targets, c.steps_per_segment),
        PathConfig::Cyclic(c) => LoadPath::cyclic_tension_compression(
            c.tension_amplitude,
            c.compression_amplitude,
            c.cycles,
            c.steps_per_segment,
        ),
        PathConfig::Biaxial(c) => LoadPath::biaxial(c.max_strain_xx, c.ratio, c.steps),
        PathConfig::PureShear(c) => LoadPath::pure_shear::<M>(c.max_gamma, c.steps),
        PathConfig::ShearUnderCompression(c) => {
            LoadPath::shear_under_compression::<M>(c.vertical_stress, &c.targets, c.steps_per_segment, c.preload_steps)
        }
    }
}

fn drive<const N: usize, M: StressState<N>>(
    ctx: &Context,
    job: &MaterialPointJob,
    kinematics: M,
    name: &str,
) -> Result<MaterialPointSummary, Error> {
    let path = build_path::<N, M>(&job.spec.path).map_err(|e| path_error(job, e))?;
    ctx.log.info(format!("material point: {name}, {} steps, h = {} m", path.len(), job.spec.analysis.element_size));
    // A path the law cannot follow to its end keeps the steps it reached (curve and pictures).
    let mut records = Vec::with_capacity(path.len() + 1);
    let stopped = run_path_into(kinematics, &job.law, &path, &NewtonSettings::default(), &mut records).err();
    let driven = match (&job.spec.path, M::SHEAR_XY) {
        (PathConfig::PureShear(_) | PathConfig::ShearUnderCompression(_), Some(i)) => i,
        _ => 0,
    };
    let comp = M::COMPONENTS[driven];
    let dir = &job.output_dir;
    write_csv(&dir.join("curve.csv"), &records, &M::COMPONENTS)?;
    let (strain_label, stress_label) = if driven == 0 {
        ("strain ε_xx [-]".to_string(), "stress σ_xx [MPa]".to_string())
    } else {
        (format!("shear strain γ_{comp} [-]"), format!("shear stress τ_{comp} [MPa]"))
    };
    let title = job.spec.title.clone().unwrap_or_else(|| "material point".into());
    let curve: Vec<(f64, f64)> = records.iter().map(|r| (r.strain[driven], r.stress[driven] / 1e6)).collect();
    let plot = Error::MaterialPointChart;
    LineChart::new(&title, &strain_label, &stress_label)
        .series("damage law", curve, SeriesStyle::Line)
        .save_png(&dir.join("stress_strain.png"))
        .map_err(plot)?;
    LineChart::new(&format!("{title}: damage"), &strain_label, "damage [-]")
        .series("d_t (tension)", records.iter().map(|r| (r.strain[driven], r.d_t)).collect(), SeriesStyle::Line)
        .series("d_c (compression)", records.iter().map(|r| (r.strain[driven], r.d_c)).collect(), SeriesStyle::Line)
        .save_png(&dir.join("damage.png"))
        .map_err(plot)?;
    if let Some(e) = stopped {
        return Err(match path_error(job, e) {
            Error::MaterialPoint { source, .. } => {
                Error::MaterialPoint { source, reached: Some((records.len() - 1, dir.join("curve.csv"))) }
            }
            other => other,
        });
    }
    let peak = records
        .iter()
        .max_by(|a, b| a.stress[driven].abs().total_cmp(&b.stress[driven].abs()))
        .copied()
        .unwrap_or(records[0]);
    let last = records[records.len() - 1];
    let summary = MaterialPointSummary {
        kinematics: name.into(),
        element_size: job.spec.analysis.element_size,
        driven_component: comp.into(),
        steps: records.len() - 1,
        peak_stress: peak.stress[driven],
        strain_at_peak: peak.strain[driven],
        final_d_t: last.d_t,
        final_d_c: last.d_c,
        dissipated_energy_density: last.dissipated,
        tensile_strength: job.law.tensile_strength(),
        b_t: job.law.b_t(),
    };
    ctx.log.info(format!(
        "peak {} = {:.6e} Pa at {} = {:.6e}; final d_t = {:.4}, d_c = {:.4}; dissipated {:.6e} J/m³",
        if driven == 0 { "σ_xx" } else { "τ" },
        summary.peak_stress,
        if driven == 0 { "ε_xx" } else { "γ" },
        summary.strain_at_peak,
        summary.final_d_t,
        summary.final_d_c,
        summary.dissipated_energy_density
    ));
    Ok(summary)
}

fn write_csv<const N: usize>(file: &Path, records: &[PathRecord<N>], comps: &[&str; N]) -> Result<(), Error> {
    let mut s = String::from("step");
    for c in comps {
        let _ = write!(s, ",strain_{c}");
    }
    for c in comps {
        let _ = write!(s, ",stress_{c}");
    }
    s.push_str(",d_t,d_c,kappa_t,kappa_c,dissipated\n");
    for r in records {
        let _ = write!(s, "{}", r.step);
        for v in r.strain.iter().chain(r.stress.iter()) {
            let _ = write!(s, ",{v:e}");
        }
        let _ = writeln!(s, ",{:e},{:e},{:e},{:e},{:e}", r.d_t, r.d_c, r.kappa_t, r.kappa_c, r.dissipated);
    }
    std::fs::write(file, s).map_err(|source| Error::OutputDir { path: file.to_path_buf(), source })
}
