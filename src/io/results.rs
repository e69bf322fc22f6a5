//! The results writer: one HDF5 file written collectively by all ranks, plus its XDMF index.
//!
//! HDF5 layout (`N` nodes, `C` cells, `L` = length of the Mixed topology array):
//!
//! | path                       | shape      | type | content                                      |
//! |----------------------------|------------|------|----------------------------------------------|
//! | `/mesh/coordinates`        | `N × 3`    | f64  | node coordinates                             |
//! | `/mesh/node_ids`           | `N`        | u64  | Gmsh node tags                               |
//! | `/mesh/topology`           | `L`        | i64  | XDMF Mixed topology (see [`super::output_mesh`]) |
//! | `/mesh/cell_ids`           | `C`        | u64  | Gmsh element tags                            |
//! | `/mesh/cell_group`         | `C`        | i32  | physical tag of each cell                    |
//! | `/mesh/cell_types`         | `C`        | i32  | Gmsh element type (15 point, 1 line, 2 tri, 3 quad) |
//! | `/steps/times`             | `steps`    | f64  | time of each started step (extendible)       |
//! | `/steps/<k>` (attr `time`) | group      |      | step `k` (0-based)                           |
//! | `/steps/<k>/<field>`       | `N` or `N × n_comp` (node), `C` or `C × n_comp` (cell) | f64 | |
//!
//! In ParaView / meshio the mesh datasets appear as the attributes `node_id`, `cell_id`, `group`
//! and `gmsh_type` in every step, next to the step's fields.
//!
//! Every call is collective over the communicator given to [`ResultsWriter::create`]: all ranks
//! call the same methods in the same order with the same names, `n_comp` and times. Arguments are
//! checked on every rank and compared across ranks before any collective HDF5 call, so a bad call
//! returns the same kind of error on every rank instead of leaving some waiting.
//!
//! The writer owns an MPI communicator and an MPI-IO file: drop it (collective) before the MPI
//! `Universe`.

use std::collections::HashMap;
use std::path::{Path, PathBuf};

use hdf5::Dataset;
use mpi::raw::AsRaw;
use mpi::topology::SimpleCommunicator;
use mpi::traits::{Communicator, CommunicatorCollectives, Root};

use super::collective::{agree, fnv1a, Verdict};
use super::hyperslab::{write_rows, CollectiveXfer};
use super::output_mesh::{mixed_len, OutputMesh};
use super::xdmf::{read_steps, write_atomic, Center, FieldRef, Number, StepRef, XdmfIndex};
use super::IoError;

/// Attribute names the writer itself puts in every grid: fields may not use them.
const RESERVED: [&str; 4] = ["node_id", "cell_id", "group", "gmsh_type"];

/// Writes a time series of node and cell fields on one mesh to `<dir>/<stem>.h5` and indexes it
/// in `<dir>/<stem>.xdmf`.
pub struct ResultsWriter {
    /// A duplicate of the caller's communicator (its own message space).
    comm: SimpleCommunicator,
    /// The HDF5 file, opened with the MPI-IO driver.
    file: hdf5::File,
    /// Collective transfer property list shared by all writes.
    xfer: CollectiveXfer,
    /// Path of the HDF5 file.
    h5_path: PathBuf,
    /// Path of the XDMF index.
    xdmf_path: PathBuf,
    /// This rank's first owned node and number of owned nodes.
    nodes: (usize, usize),
    /// This rank's first owned cell and number of owned cells.
    cells: (usize, usize),
    /// What the XDMF index lists (completed steps only).
    index: XdmfIndex,
    /// The leading steps of the index that live in earlier files (a restarted run's).
    kept_steps: usize,
    /// The step between `begin_step` and `end_step`, if any.
    current: Option<StepRef>,
    /// Components of every field written so far, to keep them constant across steps.
    n_comp_of: HashMap<(String, bool), usize>,
}

/// The error of an HDF5 call on `dataset` of `file`.
fn h5_error(file: &Path, dataset: &str) -> impl FnOnce(hdf5::Error) -> IoError {
    let (file, dataset) = (file.to_path_buf(), dataset.to_string());
    move |source| IoError::Hdf5 { file, dataset, source }
}

/// Collective. Creates `dir` (on every rank; an error names the ranks that failed).
fn make_dir(comm: &SimpleCommunicator, dir: &Path, xdmf_path: &Path) -> Result<(), IoError> {
    let made = std::fs::create_dir_all(dir);
    let v = agree(comm, made.is_ok(), 0);
    if v.ok() {
        return Ok(());
    }
    Err(IoError::Xdmf {
        file: xdmf_path.to_path_buf(),
        reason: match made {
            Err(e) => format!("cannot create directory {}: {e}", dir.display()),
            Ok(()) => format!("directory {} failed on rank(s) {:?}", dir.display(), v.failed),
        },
    })
}

/// Collective. The `/mesh` group (coordinates, node ids, mixed topology, cell ids, groups and
/// Gmsh types: each rank its own rows; `topology` = this rank's piece, its offset and the global
/// length) and the empty `/steps/times`.
fn write_mesh(
    file: &hdf5::File,
    xfer: &CollectiveXfer,
    mesh: &OutputMesh,
    (topo, topo_at, topo_len): (&[i64], usize, usize),
    h5_path: &Path,
) -> Result<(), IoError> {
    let h5err = |dataset: &str| h5_error(h5_path, dataset);
    let (n, c) = (mesh.n_nodes_global, mesh.n_cells_global);
    let g = file.create_group("mesh").map_err(h5err("/mesh"))?;
    let flat: Vec<f64> = mesh.coords.iter().flatten().copied().collect();
    let put = |path: &str, ds: hdf5::Result<Dataset>, write: &dyn Fn(&Dataset) -> hdf5::Result<()>| {
        ds.and_then(|d| write(&d)).map_err(h5err(path))
    };
    let (no, co) = (mesh.node_offset, mesh.cell_offset);
    put("/mesh/coordinates", g.new_dataset::<f64>().shape([n, 3]).create("coordinates"), &|d| {
        write_rows(d, xfer, no, 3, &flat)
    })?;
    put("/mesh/node_ids", g.new_dataset::<u64>().shape([n]).create("node_ids"), &|d| {
        write_rows(d, xfer, no, 1, mesh.node_ids)
    })?;
    put("/mesh/topology", g.new_dataset::<i64>().shape([topo_len]).create("topology"), &|d| {
        write_rows(d, xfer, topo_at, 1, topo)
    })?;
    put("/mesh/cell_ids", g.new_dataset::<u64>().shape([c]).create("cell_ids"), &|d| {
        write_rows(d, xfer, co, 1, mesh.cell_ids)
    })?;
    put("/mesh/cell_group", g.new_dataset::<i32>().shape([c]).create("cell_group"), &|d| {
        write_rows(d, xfer, co, 1, mesh.cell_groups)
    })?;
    put("/mesh/cell_types", g.new_dataset::<i32>().shape([c]).create("cell_types"), &|d| {
        write_rows(d, xfer, co, 1, &mesh.gmsh_types())
    })?;
    let steps = file.create_group("steps").map_err(h5err("/steps"))?;
    steps.new_dataset::<f64>().chunk(64).shape(0..).create("times").map_err(h5err("/steps/times"))?;
    Ok(())
}

impl ResultsWriter {
    /// Collective. Creates `<dir>/<stem>.h5` and `<dir>/<stem>.xdmf` (replacing older ones) and
    /// writes the mesh once. Creates `dir` if needed.
    pub fn create(comm: &SimpleCommunicator, dir: &Path, stem: &str, mesh: &OutputMesh) -> Result<Self, IoError> {
        let h5_name = format!("{stem}.h5");
        let h5_path = dir.join(&h5_name);
        let xdmf_path = dir.join(format!("{stem}.xdmf"));
        let comm = comm.duplicate();

        // 1. Every rank checks its piece, then all check the offsets of all pieces.
        let (topo, topo_at, topo_len) = agree_on_layout(&comm, mesh, stem, &h5_path)?;

        // 2. The directory, then the file (collective create with the MPI-IO driver).
        make_dir(&comm, dir, &xdmf_path)?;
        let h5err = |dataset: &str| h5_error(&h5_path, dataset);
        let file = hdf5::File::with_options()
            .with_fapl(|p| p.mpio(comm.as_raw(), None))
            .create(&h5_path)
            .map_err(h5err("/"))?;
        let xfer = CollectiveXfer::new().map_err(h5err("/"))?;

        // 3. The mesh, each rank its own rows; the index of the XDMF file.
        let topology = (topo.as_slice(), topo_at, topo_len);
        write_mesh(&file, &xfer, mesh, topology, &h5_path)?;
        debug_assert_eq!(topo.len(), mesh.cell_kinds.iter().map(|&k| mixed_len(k)).sum::<usize>());
        let (n, c) = (mesh.n_nodes_global, mesh.n_cells_global);
        let (no, co) = (mesh.node_offset, mesh.cell_offset);
        let index = XdmfIndex::for_mesh(h5_name, n, c, topo_len);
        let mut w = ResultsWriter {
            comm,
            file,
            xfer,
            h5_path,
            xdmf_path,
            nodes: (no, mesh.n_owned_nodes()),
            cells: (co, mesh.n_owned_cells()),
            index,
            current: None,
            n_comp_of: HashMap::new(),
            kept_steps: 0,
        };
        w.publish()?;
        Ok(w)
    }

    /// Collective. As [`Self::create`], for a restarted time history: its steps go to
    /// `<dir>/<stem>.h5`, and the run's index `prior` (its XDMF file) goes on with them. The index
    /// keeps its steps up to the time `until` (the checkpoint's; those after it were written before
    /// the run stopped and are computed again), each pointing at its own HDF5 file, so the whole
    /// run stays one series. Errors: `prior` unreadable, not in the layout this writer writes, or
    /// written for another mesh.
    pub fn create_continuing(
        comm: &SimpleCommunicator,
        dir: &Path,
        stem: &str,
        mesh: &OutputMesh,
        prior: &Path,
        until: f64,
    ) -> Result<Self, IoError> {
        let read = std::fs::read_to_string(prior)
            .map_err(|e| e.to_string())
            .and_then(|text| read_steps(&text).map_err(|e| e.to_string()))
            .and_then(|r| {
                let sizes = (mesh.n_nodes_global, mesh.n_cells_global);
                if (r.n_nodes, r.n_cells) == sizes || r.steps.is_empty() {
                    Ok(r.steps)
                } else {
                    Err(format!("written for {} nodes and {} cells, not this mesh's {sizes:?}", r.n_nodes, r.n_cells))
                }
            });
        let v = agree(comm, read.is_ok(), 0);
        let steps = match read {
            Ok(steps) if v.ok() => steps,
            Ok(_) => {
                let reason = format!("unreadable on rank(s) {:?}", v.failed);
                return Err(IoError::Xdmf { file: prior.to_path_buf(), reason });
            }
            Err(reason) => return Err(IoError::Xdmf { file: prior.to_path_buf(), reason }),
        };
        let mut w = Self::create(comm, dir, stem, mesh)?;
        let own_index = std::mem::replace(&mut w.xdmf_path, prior.to_path_buf());
        let until = until + 1e-9 * (1.0 + until.abs()); // the checkpoint's own step, to round-off
        w.index.steps = steps.into_iter().filter(|s| s.time <= until).collect();
        w.kept_steps = w.index.steps.len();
        w.publish()?;
        if w.comm.rank() == 0 {
            // The restarted part's own index, written by `create`, is not needed: `prior` lists it.
            let _ = std::fs::remove_file(own_index);
        }
        Ok(w)
    }

    /// Collective. Starts output step `time` (the `k`-th call to `begin_step` writes `/steps/<k>`).
    pub fn begin_step(&mut self, time: f64) -> Result<(), IoError> {
        let k = self.own_steps();
        let group = format!("/steps/{k}");
        let problem = if self.current.is_some() {
            Some("begin_step called again before end_step".to_string())
        } else if !time.is_finite() {
            Some(format!("the step time {time} is not finite"))
        } else {
            None
        };
        let v = agree(&self.comm, problem.is_none(), time.to_bits());
        if let Some(reason) = problem {
            return Err(self.usage(&group, reason));
        }
        self.check_verdict(&v, &format!("begin_step({time:?}): time"))?;

        let h5err = self.h5err(&group);
        let g = self.file.create_group(&group).map_err(h5err)?;
        g.new_attr::<f64>()
            .create("time")
            .and_then(|a| a.write_scalar(&time))
            .map_err(self.h5err(&format!("{group}@time")))?;
        let times = self.file.dataset("steps/times").and_then(|d| {
            d.resize(k + 1)?;
            let mine: &[f64] = if self.comm.rank() == 0 { std::slice::from_ref(&time) } else { &[] };
            write_rows(&d, &self.xfer, k, 1, mine)
        });
        times.map_err(self.h5err("/steps/times"))?;
        self.current = Some(StepRef { time, fields: Vec::new(), h5_name: None });
        Ok(())
    }

    /// Collective. Node field on owned nodes, `n_comp` components per node (1 scalar, 3 vector,
    /// 6 = u+rotation...), node-major: `owned_values[i * n_comp + j]` is component `j` of owned
    /// node `i`.
    pub fn write_node_field(&mut self, name: &str, n_comp: usize, owned_values: &[f64]) -> Result<(), IoError> {
        self.write_field(Center::Node, name, n_comp, owned_values)
    }

    /// Collective. Cell field on owned cells, cell-major like [`Self::write_node_field`].
    pub fn write_cell_field(&mut self, name: &str, n_comp: usize, owned_values: &[f64]) -> Result<(), IoError> {
        self.write_field(Center::Cell, name, n_comp, owned_values)
    }

    /// Collective. Flushes the HDF5 file, then rank 0 rewrites the XDMF atomically (temp file +
    /// rename) so the pair stays readable up to the last completed step even if the run is killed
    /// later.
    pub fn end_step(&mut self) -> Result<(), IoError> {
        let k = self.own_steps();
        let Some(step) = self.current.take() else {
            return Err(self.usage(&format!("/steps/{k}"), "end_step called without begin_step".into()));
        };
        self.index.steps.push(step);
        self.publish()
    }

    /// Number of completed steps in the index (with those kept from before a restart).
    pub fn n_steps(&self) -> usize {
        self.index.steps.len()
    }

    /// Number of completed steps in this writer's own file.
    fn own_steps(&self) -> usize {
        self.index.steps.len() - self.kept_steps
    }

    /// Path of the HDF5 file.
    pub fn h5_path(&self) -> &Path {
        &self.h5_path
    }

    /// Path of the XDMF index.
    pub fn xdmf_path(&self) -> &Path {
        &self.xdmf_path
    }

    /// Collective. Closes the file, reporting errors that dropping the writer would ignore.
    /// A step begun but not ended is left out of the XDMF index.
    pub fn close(self) -> Result<(), IoError> {
        let ResultsWriter { file, h5_path, .. } = self;
        file.close().map_err(|source| IoError::Hdf5 { file: h5_path, dataset: "/".into(), source })
    }

    /// Checks, agrees on and writes one field of the current step.
    fn write_field(&mut self, center: Center, name: &str, n_comp: usize, values: &[f64]) -> Result<(), IoError> {
        let k = self.own_steps();
        let dataset = format!("/steps/{k}/{name}");
        let owned = match center {
            Center::Node => self.nodes,
            Center::Cell => self.cells,
        };
        let problem = self.field_problem(center, name, n_comp, values.len(), owned.1);
        let key = fnv1a(format!("{center:?}\u{0}{name}\u{0}{n_comp}").as_bytes());
        let v = agree(&self.comm, problem.is_none(), key);
        if let Some(reason) = problem {
            return Err(self.usage(&dataset, reason));
        }
        self.check_verdict(&v, &format!("field '{name}' ({center:?}, {n_comp} components) of step {k}"))?;

        let rows = match center {
            Center::Node => self.index.n_nodes,
            Center::Cell => self.index.n_cells,
        };
        let builder = self.file.new_dataset::<f64>();
        let ds =
            if n_comp == 1 { builder.shape([rows]) } else { builder.shape([rows, n_comp]) }.create(dataset.as_str());
        ds.and_then(|d| write_rows(&d, &self.xfer, owned.0, n_comp, values)).map_err(self.h5err(&dataset))?;

        self.n_comp_of.insert((name.to_string(), center == Center::Node), n_comp);
        if let Some(step) = self.current.as_mut() {
            step.fields.push(FieldRef { name: name.into(), center, n_comp, number: Number::F64, h5_path: dataset });
        }
        Ok(())
    }

    /// What is wrong with a field call on this rank, if anything.
    fn field_problem(&self, center: Center, name: &str, n_comp: usize, len: usize, owned: usize) -> Option<String> {
        let Some(step) = &self.current else {
            return Some("field written outside begin_step/end_step".into());
        };
        if name.is_empty() || name == "." || name.contains('/') || name.chars().any(char::is_control) {
            return Some(format!("invalid field name '{name}' (empty, '.', '/' or control characters)"));
        }
        if RESERVED.contains(&name) {
            return Some(format!("the field name '{name}' is reserved for the mesh attributes {RESERVED:?}"));
        }
        if step.fields.iter().any(|f| f.name == name) {
            return Some(format!("field '{name}' written twice in this step"));
        }
        if n_comp == 0 {
            return Some("n_comp is 0".into());
        }
        if let Some(&before) = self.n_comp_of.get(&(name.to_string(), center == Center::Node)) {
            if before != n_comp {
                return Some(format!("{n_comp} components, but earlier steps wrote {before}"));
            }
        }
        if len != owned * n_comp {
            let what = if center == Center::Node { "nodes" } else { "cells" };
            return Some(format!("{len} values for {owned} owned {what} × {n_comp} components"));
        }
        None
    }

    /// Collective. Flushes the HDF5 file; rank 0 then rewrites the XDMF index and tells the others
    /// whether that worked.
    fn publish(&mut self) -> Result<(), IoError> {
        self.file.flush().map_err(self.h5err("/"))?;
        let mut failure = String::new();
        if self.comm.rank() == 0 {
            if let Err(e) = write_atomic(&self.xdmf_path, &self.index.render()) {
                failure = e.to_string();
            }
        }
        let mut failed = i32::from(!failure.is_empty());
        self.comm.process_at_rank(0).broadcast_into(&mut failed);
        if failed != 0 {
            let reason = if failure.is_empty() { "failed on rank 0".into() } else { failure };
            return Err(IoError::Xdmf { file: self.xdmf_path.clone(), reason });
        }
        Ok(())
    }

    /// The error for a wrong call on this rank.
    fn usage(&self, dataset: &str, reason: String) -> IoError {
        IoError::InvalidField { file: self.h5_path.clone(), dataset: dataset.into(), reason }
    }

    /// The error when another rank failed or disagreed (this rank's own checks passed).
    fn check_verdict(&self, v: &Verdict, what: &str) -> Result<(), IoError> {
        if v.ok() {
            return Ok(());
        }
        let (kind, ranks) =
            if v.failed.is_empty() { ("differs from rank 0", v.differ.clone()) } else { ("failed", v.failed.clone()) };
        Err(IoError::Collective { file: self.h5_path.clone(), what: format!("{what} {kind}"), ranks })
    }

    /// Maps an HDF5 error on `dataset` to an [`IoError`].
    fn h5err(&self, dataset: &str) -> impl FnOnce(hdf5::Error) -> IoError {
        let file = self.h5_path.clone();
        let dataset = dataset.to_string();
        move |source| IoError::Hdf5 { file, dataset, source }
    }
}

/// Collective. Checks this rank's piece of the mesh, then, from one all-gather of the piece sizes,
/// that the pieces tile the global node and cell ranges in rank order; every rank reaches the same
/// verdict from the same data. Returns this rank's Mixed topology, its offset in the global
/// topology array (the exclusive prefix sum of the ranks' lengths) and the global length.
fn agree_on_layout(
    comm: &SimpleCommunicator,
    mesh: &OutputMesh,
    stem: &str,
    h5_path: &Path,
) -> Result<(Vec<i64>, usize, usize), IoError> {
    let rank = comm.rank();
    let h5_path = h5_path.to_path_buf();
    let mut problem = mesh.local_problem();
    if stem.is_empty() || stem.contains(['/', '\\']) {
        problem = Some(format!("the file stem '{stem}' is empty or contains a path separator"));
    }
    let topo = if problem.is_none() { mesh.mixed_topology() } else { Vec::new() };
    let mine = [
        u64::from(problem.is_none()),
        mesh.n_owned_nodes() as u64,
        mesh.n_owned_cells() as u64,
        topo.len() as u64,
        mesh.node_offset as u64,
        mesh.cell_offset as u64,
        mesh.n_nodes_global as u64,
        mesh.n_cells_global as u64,
    ];
    let size = comm.size() as usize;
    let mut all = vec![0u64; mine.len() * size];
    comm.all_gather_into(&mine[..], &mut all[..]);
    let rows: Vec<&[u64]> = all.chunks_exact(mine.len()).collect();
    if rows.iter().any(|row| row[0] == 0) {
        return Err(match problem {
            Some(reason) => IoError::InvalidMesh { file: h5_path, rank, reason },
            None => IoError::Collective {
                file: h5_path,
                what: "ResultsWriter::create: output mesh".into(),
                ranks: rows.iter().enumerate().filter(|(_, w)| w[0] == 0).map(|(q, _)| q as i32).collect(),
            },
        });
    }
    let (mut node_at, mut cell_at, mut topo_at, mut topo_len) = (0u64, 0u64, 0u64, 0u64);
    for (q, row) in rows.iter().enumerate() {
        let reason = if row[4] != node_at {
            Some(format!("node_offset {} but the lower ranks own {node_at} nodes", row[4]))
        } else if row[5] != cell_at {
            Some(format!("cell_offset {} but the lower ranks own {cell_at} cells", row[5]))
        } else if row[6] != rows[0][6] || row[7] != rows[0][7] {
            Some(format!(
                "global counts {} nodes / {} cells differ from rank 0's {} / {}",
                row[6], row[7], rows[0][6], rows[0][7]
            ))
        } else {
            None
        };
        if let Some(reason) = reason {
            return Err(IoError::InvalidMesh { file: h5_path, rank: q as i32, reason });
        }
        if q == rank as usize {
            topo_at = topo_len;
        }
        node_at += row[1];
        cell_at += row[2];
        topo_len += row[3];
    }
    if node_at != mesh.n_nodes_global as u64 || cell_at != mesh.n_cells_global as u64 {
        return Err(IoError::InvalidMesh {
            file: h5_path,
            rank,
            reason: format!(
                "the ranks own {node_at} nodes and {cell_at} cells in total, not the stated {} and {}",
                mesh.n_nodes_global, mesh.n_cells_global
            ),
        });
    }
    Ok((topo, topo_at as usize, topo_len as usize))
}
