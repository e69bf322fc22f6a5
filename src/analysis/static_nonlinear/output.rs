//! What the increments write: `results.xdmf` (one step per converged increment), `curve.csv`
//! (one line each) and `curve.png` under displacement control.
use super::{control_start, Stage, StepReport};
use crate::analysis::assembly;
use crate::analysis::newton::{global_sum, Increment, NonlinearSystem};
use crate::analysis::output::{global_max_with_tag, node_triplets, MeshPiece};
use crate::analysis::Discretization;
use crate::config::{Job, StaticNonlinearConfig};
use crate::element::AppliedLoads;
use crate::error::Error;
use crate::io::IoError;
use crate::io::ResultsWriter;
use crate::mesh::Mesh;
use crate::model::StructuralModel;
use crate::parallel::{agree, Context};
use std::io::Write;

/// Where the converged increments go: `results.xdmf`, `curve.csv` (its header written), and the
/// overlay curve for `curve.png`, if any.
pub(super) struct Outputs {
    pub writer: ResultsWriter,
    pub curve_path: std::path::PathBuf,
    pub overlay: Option<(String, Vec<(f64, f64)>)>,
}

impl Outputs {
    /// Collective. Creates the results file and `curve.csv`, reads the overlay.
    pub fn open(
        ctx: &Context,
        job: &Job,
        cfg: &StaticNonlinearConfig,
        mesh: &Mesh,
        model: &StructuralModel,
        disc: &Discretization,
    ) -> Result<Outputs, Error> {
        let piece = MeshPiece::new(ctx, job, mesh, model, disc);
        let writer = agree(
            &ctx.comm,
            ResultsWriter::create(&ctx.comm, &job.output_dir, "results", &piece.view()).map_err(Error::from),
            Error::exit_code,
        )?;
        let curve_path = job.output_dir.join("curve.csv");
        if ctx.rank == 0 {
            let header = "stage,lambda,control_displacement,control_force,dissipated_energy,iterations,residual\n";
            std::fs::write(&curve_path, header)
                .map_err(|source| IoError::Write { file: curve_path.clone(), source })?;
        }
        let overlay = match cfg.control.as_ref().and_then(|c| c.overlay.as_ref()) {
            Some(o) => Some((
                o.label.clone(),
                agree(&ctx.comm, crate::analysis::curve_plot::read_overlay(o), Error::exit_code)?,
            )),
            None => None,
        };
        Ok(Outputs { writer, curve_path, overlay })
    }
}

/// Collective. `curve.png` of the control stage (rank 0 draws; all agree on the outcome).
pub(super) fn draw_curve(
    ctx: &Context,
    job: &Job,
    model: &StructuralModel,
    reports: &[StepReport],
    overlay: Option<&(String, Vec<(f64, f64)>)>,
) -> Result<(), Error> {
    let Some(ctl) = &model.control else { return Ok(()) };
    let drawn = if ctx.rank == 0 {
        let mut points = vec![(0.0, 0.0)];
        points
            .extend(reports.iter().filter(|r| r.stage == "control").map(|r| (r.control_displacement, r.control_force)));
        let dof = ["ux", "uy", "uz", "rx", "ry", "rz"][ctl.dof];
        crate::analysis::curve_plot::plot_curve(
            &job.output_dir.join("curve.png"),
            dof,
            &points,
            overlay.map(|(l, p)| (l.as_str(), p.as_slice())),
        )
    } else {
        Ok(())
    };
    agree(&ctx.comm, drawn, Error::exit_code)?;
    Ok(())
}

/// Collective. Writes one converged increment (fields, curve line) and returns its report.
#[allow(clippy::too_many_arguments)]
pub(super) fn write_step(
    ctx: &Context,
    disc: &Discretization,
    mesh: &Mesh,
    model: &StructuralModel,
    sys: &mut NonlinearSystem,
    writer: &mut ResultsWriter,
    curve: &std::path::Path,
    stage: &Stage,
    inc: &Increment,
    time: f64,
    pattern_resultant: f64,
    iterations: usize,
    residual: f64,
) -> Result<StepReport, Error> {
    let u = sys.u_committed.clone();
    let u_local = sys.local_form(&u)?;
    let mut umax = 0.0f64;
    for v in u.chunks_exact(6) {
        umax = umax.max((v[0] * v[0] + v[1] * v[1] + v[2] * v[2]).sqrt());
    }
    let (umax, _) = global_max_with_tag(&ctx.comm, umax, 0);
    let lambda = inc.lambda;
    let loads = AppliedLoads {
        gravity: model.gravity.map(|g| [g[0] * lambda, g[1] * lambda, g[2] * lambda]).unwrap_or([0.0; 3]),
    };
    let (names, values) = assembly::cell_outputs(ctx, disc, mesh, model, &u_local, &loads)?;
    let dissipated = names
        .iter()
        .position(|n| n == "dissipated_energy")
        .map(|k| global_sum(ctx, values[k].iter().filter(|x| x.is_finite()).sum()))
        .unwrap_or(0.0);
    let control_displacement = match &model.control {
        Some(c) => control_start(ctx, sys, disc, c),
        None => 0.0,
    };
    let control_force = sys.control_force(ctx, pattern_resultant);
    let wrote: Result<(), Error> = (|| {
        writer.begin_step(time)?;
        let n = disc.dofs.owned.len();
        writer.write_node_field("displacement", 3, &node_triplets(&u_local, n, 0))?;
        writer.write_node_field("rotation", 3, &node_triplets(&u_local, n, 3))?;
        for (name, v) in names.iter().zip(&values) {
            writer.write_cell_field(name, 1, v)?;
        }
        writer.end_step()?;
        if ctx.rank == 0 {
            let mut f = std::fs::OpenOptions::new()
                .append(true)
                .open(curve)
                .map_err(|source| IoError::Write { file: curve.to_path_buf(), source })?;
            writeln!(
                f,
                "{},{:.12e},{:.12e},{:.12e},{:.12e},{},{:.3e}",
                stage.name, lambda, control_displacement, control_force, dissipated, iterations, residual
            )
            .map_err(|source| IoError::Write { file: curve.to_path_buf(), source })?;
        }
        Ok(())
    })();
    agree(&ctx.comm, wrote, Error::exit_code)?;
    Ok(StepReport {
        stage: stage.name,
        lambda,
        control_displacement,
        control_force,
        dissipated_energy: dissipated,
        iterations,
        residual,
        max_displacement: umax,
    })
}
