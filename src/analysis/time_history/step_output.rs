//! What a time history writes as it goes: `results.xdmf` every `output_every` steps (relative
//! and absolute motion, cell outputs), a row of `energy.csv` and `monitors.csv` every step (the
//! monitors, the base reactions, the storey drifts), the envelopes updated from both, and at the
//! end `envelopes.xdmf` and the monitors' pictures.
use super::base_shear;
use super::drift::{self, Drift};
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
    /// The storey drifts.
    pub drifts: Vec<Drift>,
    energy_csv: CsvLog,
    /// `monitors.csv`.
    pub monitor_csv: CsvLog,
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
        let drifts = drift::resolve(&it.cfg.drift, it.mesh, &sys.disc.dofs)?;
        for d in &drifts {
            let ([lo, hi], [nl, nu]) = (d.levels(), d.counts());
            ctx.log.info(format!("drift '{}': {nl} node(s) at mean z {lo:.4} m, {nu} at {hi:.4} m", d.name));
        }
        let restart_step = it.restart.then_some(state.step);
        let energy_csv = CsvLog::open(ctx, &dir.join("energy.csv"), EnergyBalance::CSV_HEADER, restart_step)?;
        let header = monitor::header(&monitors) + base_shear::HEADER + &drift::header(&drifts);
        let monitor_csv = CsvLog::open(ctx, &dir.join("monitors.csv"), &header, restart_step)?;
        if ctx.rank == 0 {
            write_groups(&dir.join(GROUPS_FILE), it.mesh, &ctx.log);
        }
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
        Ok(StepOutputs { env, monitors, drifts, energy_csv, monitor_csv, piece, writer })
    }

    /// Collective. Every step: the node envelopes, and the rows of `monitors.csv` (relative
    /// displacement, absolute acceleration, base reactions, drifts) and `energy.csv`.
    pub fn record(&mut self, ctx: &Context, it: &Integration, state: &State) {
        self.env.update_nodes(&state.u);
        let a_abs = absolute(&state.a, it.ground.acceleration(state.t));
        let mut local = monitor::local_values(&self.monitors, &state.u, &a_abs);
        let n_monitor = local.len();
        local.extend(base_shear::local_reaction(&state.f_int, &state.cv));
        local.extend(drift::local_sums(&self.drifts, &state.u));
        let mut vals = monitor::sum_over_ranks(ctx, &local);
        let sums = vals.split_off(n_monitor + 3);
        vals.extend(drift::ratios(&self.drifts, &sums));
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

    /// Collective. The peak base shear along x and y, then each drift's along x and y, each with
    /// its time, from the whole `monitors.csv` (a restarted run's rows before the restart
    /// included): rank 0 reads it, every rank gets the numbers (NaN where it cannot be read).
    pub fn peaks(&self, ctx: &Context) -> Vec<(f64, f64)> {
        use mpi::traits::{Communicator, Root};
        let mut names: Vec<String> = base_shear::SHEAR_COLUMNS.iter().map(|s| s.to_string()).collect();
        for d in &self.drifts {
            names.extend([format!("drift:{}:x", d.name), format!("drift:{}:y", d.name)]);
        }
        let mut buf = vec![f64::NAN; 2 * names.len()];
        if ctx.rank == 0 {
            match monitor::column_peaks(&self.monitor_csv.path, &names) {
                Ok(p) => buf = p.iter().flat_map(|&(v, t)| [v, t]).collect(),
                Err(e) => ctx.log.warn(format!("peak base shear and drifts not found: {e}")),
            }
        }
        ctx.comm.process_at_rank(0).broadcast_into(&mut buf[..]);
        buf.chunks(2).map(|c| (c[0], c[1])).collect()
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
            w.write_cell_field("d_t_max", 1, &env.cell_column(0))?;
            w.write_cell_field("d_c_max", 1, &env.cell_column(1))?;
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

/// The file that names the mesh's physical groups for the results (their cell field `group`
/// holds the physical tag): `dimension,tag,name`, one row per group.
pub const GROUPS_FILE: &str = "groups.csv";

/// Rank 0: [`GROUPS_FILE`] (a failure to write it is a warning: post-processing then shows tags).
fn write_groups(path: &std::path::Path, mesh: &Mesh, log: &crate::parallel::Log) {
    let mut text = String::from("dimension,tag,name\n");
    for g in &mesh.groups {
        text += &format!("{},{},{}\n", g.dim, g.tag, g.name.replace([',', '\n'], " "));
    }
    if let Err(e) = std::fs::write(path, text) {
        log.warn(format!("cannot write {}: {e}", path.display()));
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
