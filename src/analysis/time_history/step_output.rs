//! What a time history writes as it goes: `results.xdmf` every `output_every` steps (relative
//! and absolute motion, cell outputs), a row of `energy.csv` and `monitors.csv` every step, the
//! envelopes updated from both, and at the end `envelopes.xdmf` and the monitors' pictures.
use super::envelope::Envelopes;
use super::integration::{Integration, SavedEnvelopes, RESULTS_STEM};
use super::monitor::{self, CsvLog, Monitor};
use super::petsc_system::PetscSystem;
use super::stepper::State;
use super::EnergyBalance;
use crate::analysis::output::{node_triplets, MeshPiece};
use crate::element::AppliedLoads;
use crate::error::Error;
use crate::io::ResultsWriter;
use crate::mesh::Mesh;
use crate::parallel::{agree, Context};

/// The outputs of one run, open.
pub(super) struct StepOutputs {
    /// Peak values per node and cell.
    pub env: Envelopes,
    /// The monitored nodes.
    pub monitors: Vec<Monitor>,
    energy_csv: CsvLog,
    monitor_csv: CsvLog,
    piece: MeshPiece,
    /// The results file of this run.
    pub writer: ResultsWriter,
}

impl StepOutputs {
    /// Collective. Opens the CSV logs (continued after the state's step on a restart) and the
    /// results file `<stem>.xdmf`; the envelopes start from `saved` when their sizes fit.
    pub fn open(
        ctx: &Context,
        sys: &PetscSystem,
        it: &Integration,
        state: &State,
        saved: Option<SavedEnvelopes>,
    ) -> Result<StepOutputs, Error> {
        let dir = &it.job.output_dir;
        let mut env = Envelopes::new(heights(sys, it.mesh), sys.disc.elements.len());
        if let Some((node, cell)) = saved {
            if node.len() == env.node.len() && cell.len() == env.cell.len() {
                env.node = node;
                env.cell = cell;
            }
        }
        let monitors = monitor::resolve(&it.cfg.monitor, it.mesh, &sys.disc.dofs)?;
        for m in &monitors {
            ctx.log.info(format!("monitor '{}': node {} at {:?}", m.name, m.tag, it.mesh.coords[m.node]));
        }
        let restart_step = it.restart.then_some(state.step);
        let energy_csv = CsvLog::open(ctx, &dir.join("energy.csv"), EnergyBalance::CSV_HEADER, restart_step)?;
        let monitor_csv = CsvLog::open(ctx, &dir.join("monitors.csv"), &monitor::header(&monitors), restart_step)?;
        let piece = MeshPiece::new(ctx, it.job, it.mesh, it.model, &sys.disc);
        // A restart continues the run's index (one series in ParaView); its own steps go to a file
        // of their own. Without the index (removed by hand) the restart gets an index of its own.
        let index = dir.join(format!("{RESULTS_STEM}.xdmf"));
        let created = if it.restart && index.exists() {
            ResultsWriter::create_continuing(&ctx.comm, dir, &it.stem, &piece.view(), &index, state.t)
        } else {
            if it.restart {
                ctx.log.warn(format!("{} not found: the restarted part gets an index of its own", index.display()));
            }
            ResultsWriter::create(&ctx.comm, dir, &it.stem, &piece.view())
        };
        let writer = agree(&ctx.comm, created.map_err(Error::from), Error::exit_code)?;
        Ok(StepOutputs { env, monitors, energy_csv, monitor_csv, piece, writer })
    }

    /// Collective. Every step: the node envelopes, and the rows of `monitors.csv` (relative
    /// displacement, absolute acceleration) and `energy.csv`.
    pub fn record(&mut self, ctx: &Context, it: &Integration, state: &State) {
        self.env.update_nodes(&state.u);
        let a_abs = absolute(&state.a, it.ground.acceleration(state.t));
        let vals = monitor::values(ctx, &self.monitors, &state.u, &a_abs);
        let mut row = format!("{},{:.10e}", state.step, state.t);
        for v in vals {
            row += &format!(",{v:.17e}");
        }
        self.monitor_csv.row(&row, &ctx.log);
        self.energy_csv.row(&state.energy.csv_row(state.step, state.t), &ctx.log);
    }

    /// Collective. One output step: relative and absolute motion, cell outputs (which update the
    /// cell envelopes).
    pub fn write_step(
        &mut self,
        ctx: &Context,
        sys: &mut PetscSystem,
        it: &Integration,
        state: &State,
    ) -> Result<(), Error> {
        let n = sys.disc.dofs.owned.len();
        let ag = it.ground.acceleration(state.t);
        let (vg, ug) = it.ground.velocity_displacement(state.t);
        let u_local = sys.local_form(&state.u)?;
        let loads = AppliedLoads { gravity: it.model.gravity.unwrap_or([0.0; 3]) };
        let (names, values) =
            crate::analysis::assembly::cell_outputs(ctx, &sys.disc, it.mesh, it.model, &u_local, &loads)?;
        self.env.update_cells(&names, &values);
        let w = &mut self.writer;
        let written: Result<(), Error> = (|| {
            w.begin_step(state.t)?;
            w.write_node_field("displacement", 3, &node_triplets(&state.u, n, 0))?;
            w.write_node_field("rotation", 3, &node_triplets(&state.u, n, 3))?;
            w.write_node_field("velocity", 3, &node_triplets(&state.v, n, 0))?;
            w.write_node_field("acceleration", 3, &node_triplets(&state.a, n, 0))?;
            w.write_node_field("absolute_displacement", 3, &node_triplets(&absolute(&state.u, ug), n, 0))?;
            w.write_node_field("absolute_velocity", 3, &node_triplets(&absolute(&state.v, vg), n, 0))?;
            w.write_node_field("absolute_acceleration", 3, &node_triplets(&absolute(&state.a, ag), n, 0))?;
            for (name, v) in names.iter().zip(&values) {
                w.write_cell_field(name, 1, v)?;
            }
            w.end_step()?;
            Ok(())
        })();
        agree(&ctx.comm, written, Error::exit_code)?;
        Ok(())
    }

    /// Collective. `envelopes.xdmf` at time `t`, the results file closed, and on rank 0 the
    /// monitors' pictures (a failure to draw them is a warning).
    pub fn close(self, ctx: &Context, sys: &PetscSystem, dir: &std::path::Path, t: f64) -> Result<(), Error> {
        let env = &self.env;
        let written: Result<(), Error> = (|| {
            let mut w = ResultsWriter::create(&ctx.comm, dir, "envelopes", &self.piece.view())?;
            w.begin_step(t)?;
            let n = sys.disc.dofs.owned.len();
            let node3: Vec<f64> = (0..n).flat_map(|i| env.node[4 * i..4 * i + 3].to_vec()).collect();
            w.write_node_field("peak_displacement", 3, &node3)?;
            w.write_node_field("peak_drift_ratio", 1, &env.node_column(3))?;
            w.write_cell_field("max_d_t", 1, &env.cell_column(0))?;
            w.write_cell_field("max_d_c", 1, &env.cell_column(1))?;
            w.end_step()?;
            w.close()?;
            Ok(())
        })();
        agree(&ctx.comm, written, Error::exit_code)?;
        agree(&ctx.comm, self.writer.close().map_err(Error::from), Error::exit_code)?;
        if ctx.rank == 0 && !self.monitors.is_empty() {
            match monitor::draw(&self.monitor_csv.path, &self.monitors, dir) {
                Ok(files) => ctx.log.info(format!(
                    "monitors: {} and {} picture(s)",
                    self.monitor_csv.path.display(),
                    files.len()
                )),
                Err(e) => ctx.log.warn(format!("monitor pictures not drawn: {e}")),
            }
        }
        Ok(())
    }
}

/// Heights of the owned nodes above the model's lowest node.
fn heights(sys: &PetscSystem, mesh: &Mesh) -> Vec<f64> {
    let dofs = &sys.disc.dofs;
    let z0 = (0..mesh.coords.len())
        .filter(|&n| dofs.global[n] != usize::MAX)
        .map(|n| mesh.coords[n][2])
        .fold(f64::INFINITY, f64::min);
    dofs.owned.iter().map(|&n| mesh.coords[n][2] - z0).collect()
}

/// Translations plus the ground's (per direction) at every owned node.
fn absolute(rel: &[f64], g: [f64; 3]) -> Vec<f64> {
    let mut out = rel.to_vec();
    for node in out.chunks_mut(6) {
        for d in 0..3 {
            node[d] += g[d];
        }
    }
    out
}
