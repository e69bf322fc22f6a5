//! Particle states of one virtual test as HDF5 + XDMF 3 for ParaView: `<stem>.h5` and
//! `<stem>.xdmf` in a sample's folder. Each sample is computed on one rank, so the file is written
//! serially by that rank (hdf5-metno, default file driver).
//!
//! The mesh (written once) has `C = P + B` cells, in one XDMF `Mixed` topology:
//! * the `P` stones as polygons (XDMF type 3, then the vertex count, then the vertices); every
//!   stone has its own copies of its vertices, so stones can separate;
//! * the `B` beams broken by the end of the test as 2-node lines (type 2, count 2) along the facet
//!   they bonded (the crack), with their own two nodes.
//!
//! A time step is a recorded state (`Time` = the state index, the `state` column of
//! `curve.csv`; strain and stress are attributes of `/steps/<k>`). Fields:
//!
//! | name                    | centre | content                                                     |
//! |-------------------------|--------|-------------------------------------------------------------|
//! | `displacement`          | node   | exact rigid motion of the node: `u + (R(θ) − 1)(x − c)` of its stone (crack nodes: the mean of the two stones) |
//! | `particle_displacement` | cell   | `(u_x, u_y, 0)` of the stone's centroid (lines: mean of the two stones) |
//! | `rotation`              | cell   | `θ` (rad, counter-clockwise)                                 |
//! | `crack`                 | cell   | −1 for stones and for beams still intact at the state; 0 broken in tension, 1 in shear/rotation, 2 crushed |
//! | `particle`, `beam`      | cell   | stone index (−1 on lines), beam index (−1 on stones)         |
//!
//! A beam counts as broken from the state after its pre-break state (`BrokenBeam::state`) on.
//! In ParaView: open the `.xdmf` (XDMF reader), `Warp By Vector` with `displacement` (scale ~100),
//! `Threshold` on `crack` ≥ 0 to show the cracks coloured by mode.
//!
//! HDF5 layout: `/mesh/coordinates` (N × 3, f64), `/mesh/topology` (L, i64), `/mesh/particle`,
//! `/mesh/beam` (C, i32); `/steps/<k>/{displacement, particle_displacement, rotation, crack}`,
//! attributes `state`, `strain`, `stress` on `/steps/<k>`.
use std::fmt::Write as _;
use std::path::{Path, PathBuf};

use crate::dem::sample::Sample;
use crate::dem::solver::{FailureModeTag, ParticleState, TestResult};

/// Writing the particle states failed.
#[derive(Debug, thiserror::Error)]
pub enum ParticleOutputError {
    /// The HDF5 library reported an error.
    #[error("{}: {what}: HDF5 error: {source}", file.display())]
    Hdf5 {
        /// The file.
        file: PathBuf,
        /// The dataset or group.
        what: String,
        /// The HDF5 error.
        #[source]
        source: hdf5::Error,
    },
    /// Writing the XDMF index failed.
    #[error("{}: {source}", file.display())]
    Io {
        /// The file.
        file: PathBuf,
        /// The OS error.
        #[source]
        source: std::io::Error,
    },
    /// The states do not fit the sample (internal inconsistency).
    #[error("{}: {reason}", file.display())]
    Inconsistent {
        /// The file.
        file: PathBuf,
        /// What does not fit.
        reason: String,
    },
}

/// The output mesh: node coordinates, which stone(s) each node follows, the Mixed topology.
struct Mesh {
    coordinates: Vec<[f64; 3]>,
    /// Per node: the stones whose rigid motion it follows (one, or two for crack nodes).
    follows: Vec<(usize, Option<usize>)>,
    topology: Vec<i64>,
    particle: Vec<i32>,
    beam: Vec<i32>,
    /// Per cell: the stones `(i, j)` it shows (i = j for a stone).
    stones: Vec<(usize, usize)>,
    /// Per line cell: the state index of its pre-break state and its mode.
    cracks: Vec<(usize, i32)>,
}

fn build_mesh(sample: &Sample, result: &TestResult) -> Mesh {
    let mut m = Mesh {
        coordinates: Vec::new(),
        follows: Vec::new(),
        topology: Vec::new(),
        particle: Vec::new(),
        beam: Vec::new(),
        stones: Vec::new(),
        cracks: Vec::new(),
    };
    for (p, particle) in sample.particles.iter().enumerate() {
        m.topology.push(3);
        m.topology.push(particle.polygon.vertices.len() as i64);
        for v in &particle.polygon.vertices {
            m.topology.push(m.coordinates.len() as i64);
            m.coordinates.push([v[0], v[1], 0.0]);
            m.follows.push((p, None));
        }
        m.particle.push(p as i32);
        m.beam.push(-1);
        m.stones.push((p, p));
    }
    for b in &result.broken {
        let beam = &sample.beams[b.beam];
        m.topology.extend([2, 2, m.coordinates.len() as i64, m.coordinates.len() as i64 + 1]);
        for v in beam.facet {
            m.coordinates.push([v[0], v[1], 0.0]);
            m.follows.push((beam.i, Some(beam.j)));
        }
        m.particle.push(-1);
        m.beam.push(b.beam as i32);
        m.stones.push((beam.i, beam.j));
        m.cracks.push((
            b.state,
            match b.mode {
                FailureModeTag::Tension => 0,
                FailureModeTag::Shear => 1,
                FailureModeTag::Crushing => 2,
            },
        ));
    }
    m
}

/// Node displacement of point `x` of stone `p` under `(u_x, u_y, θ)`: `u + (R(θ) − 1)(x − c)`.
fn rigid(sample: &Sample, p: usize, dofs: [f64; 3], x: [f64; 3]) -> [f64; 2] {
    let moved = sample.particles[p].moved_point([x[0], x[1]], dofs);
    [moved[0] - x[0], moved[1] - x[1]]
}

/// Writes `<dir>/<stem>.h5` and `<dir>/<stem>.xdmf` (replacing older ones) from the particle
/// states kept in `result`. Nothing is written when no state was kept.
pub fn write_particle_states(
    dir: &Path,
    stem: &str,
    sample: &Sample,
    result: &TestResult,
) -> Result<(), ParticleOutputError> {
    if result.particle_states.is_empty() {
        return Ok(());
    }
    let h5_name = format!("{stem}.h5");
    let h5_path = dir.join(&h5_name);
    let h5 = |what: &str| h5_error(&h5_path, what);
    let mesh = build_mesh(sample, result);
    let file = hdf5::File::create(&h5_path).map_err(h5("/"))?;
    write_mesh(&file, &mesh, &h5_path)?;
    let steps = file.create_group("steps").map_err(h5("/steps"))?;
    let mut xml_steps = String::new();
    for (k, ps) in result.particle_states.iter().enumerate() {
        if ps.dofs.len() != sample.particles.len() {
            return Err(ParticleOutputError::Inconsistent {
                file: h5_path.clone(),
                reason: format!(
                    "state {}: {} particle states for {} stones",
                    ps.state,
                    ps.dofs.len(),
                    sample.particles.len()
                ),
            });
        }
        let name = format!("/steps/{k}");
        let sg = steps.create_group(&k.to_string()).map_err(h5(&name))?;
        let curve = result.curve.get(ps.state);
        for (attr, value) in
            [("strain", curve.map_or(f64::NAN, |c| c.strain)), ("stress", curve.map_or(f64::NAN, |c| c.stress))]
        {
            sg.new_attr::<f64>().create(attr).and_then(|a| a.write_scalar(&value)).map_err(h5(&name))?;
        }
        sg.new_attr::<u64>().create("state").and_then(|a| a.write_scalar(&(ps.state as u64))).map_err(h5(&name))?;
        StateFields::of(sample, &mesh, ps).write(&sg, &name, &h5_path)?;
        push_state_grid(&mut xml_steps, &h5_name, &name, ps.state, &mesh);
    }
    file.close().map_err(h5("/"))?;
    let xml = format!(
        "<?xml version=\"1.0\" encoding=\"utf-8\"?>\n<Xdmf Version=\"3.0\">\n  <Domain>\n    \
         <Grid Name=\"particles\" GridType=\"Collection\" CollectionType=\"Temporal\">\n{xml_steps}    </Grid>\n  </Domain>\n</Xdmf>\n"
    );
    let xdmf = dir.join(format!("{stem}.xdmf"));
    std::fs::write(&xdmf, xml).map_err(|source| ParticleOutputError::Io { file: xdmf, source })
}

/// The error of an HDF5 call on `what` in `file`.
fn h5_error(file: &Path, what: &str) -> impl FnOnce(hdf5::Error) -> ParticleOutputError {
    let (file, what) = (file.to_path_buf(), what.to_string());
    move |source| ParticleOutputError::Hdf5 { file, what, source }
}

/// `rows × 3` values as an array (an error names `file` when the count does not fit).
fn rows_of_three(v: Vec<f64>, rows: usize, file: &Path) -> Result<ndarray::Array2<f64>, ParticleOutputError> {
    ndarray::Array2::from_shape_vec((rows, 3), v)
        .map_err(|e| ParticleOutputError::Inconsistent { file: file.to_path_buf(), reason: e.to_string() })
}

/// The `/mesh` group: node coordinates, mixed topology, and each cell's particle and beam.
fn write_mesh(file: &hdf5::File, mesh: &Mesh, h5_path: &Path) -> Result<(), ParticleOutputError> {
    let h5 = |what: &str| h5_error(h5_path, what);
    let g = file.create_group("mesh").map_err(h5("/mesh"))?;
    let coords: Vec<f64> = mesh.coordinates.iter().flatten().copied().collect();
    let coords = rows_of_three(coords, mesh.coordinates.len(), h5_path)?;
    g.new_dataset_builder().with_data(&coords).create("coordinates").map_err(h5("/mesh/coordinates"))?;
    g.new_dataset_builder().with_data(&mesh.topology[..]).create("topology").map_err(h5("/mesh/topology"))?;
    g.new_dataset_builder().with_data(&mesh.particle[..]).create("particle").map_err(h5("/mesh/particle"))?;
    g.new_dataset_builder().with_data(&mesh.beam[..]).create("beam").map_err(h5("/mesh/beam"))?;
    Ok(())
}

/// The fields of one kept state on the mesh: node displacements (a crack's nodes follow the
/// mean of their two stones), each cell's stone displacement and rotation (a crack cell: the
/// mean of its two stones), and the crack mode of the cells broken by then (−1: none or a stone).
struct StateFields {
    displacement: Vec<f64>,
    particle_displacement: Vec<f64>,
    rotation: Vec<f64>,
    crack: Vec<i32>,
}

impl StateFields {
    fn of(sample: &Sample, mesh: &Mesh, ps: &ParticleState) -> StateFields {
        let (n_nodes, n_cells) = (mesh.coordinates.len(), mesh.particle.len());
        let mut displacement = Vec::with_capacity(3 * n_nodes);
        for (x, &(i, j)) in mesh.coordinates.iter().zip(&mesh.follows) {
            let a = rigid(sample, i, ps.dofs[i], *x);
            let d = match j {
                Some(j) => {
                    let b = rigid(sample, j, ps.dofs[j], *x);
                    [0.5 * (a[0] + b[0]), 0.5 * (a[1] + b[1])]
                }
                None => a,
            };
            displacement.extend([d[0], d[1], 0.0]);
        }
        let (mut particle_displacement, mut rotation, mut crack) =
            (Vec::with_capacity(3 * n_cells), Vec::with_capacity(n_cells), Vec::with_capacity(n_cells));
        for &(i, j) in &mesh.stones {
            let (a, b) = (ps.dofs[i], ps.dofs[j]);
            particle_displacement.extend([0.5 * (a[0] + b[0]), 0.5 * (a[1] + b[1]), 0.0]);
            rotation.push(0.5 * (a[2] + b[2]));
        }
        crack.extend(std::iter::repeat_n(-1i32, sample.particles.len()));
        crack.extend(mesh.cracks.iter().map(|&(at, mode)| if ps.state > at { mode } else { -1 }));
        StateFields { displacement, particle_displacement, rotation, crack }
    }

    /// The fields as datasets of the step group `sg` (named `name` in `h5_path`).
    fn write(self, sg: &hdf5::Group, name: &str, h5_path: &Path) -> Result<(), ParticleOutputError> {
        let rows = (self.displacement.len() / 3, self.rotation.len());
        let disp = rows_of_three(self.displacement, rows.0, h5_path)?;
        let pd = rows_of_three(self.particle_displacement, rows.1, h5_path)?;
        let at = |field: &str| h5_error(h5_path, &format!("{name}/{field}"));
        sg.new_dataset_builder().with_data(&disp).create("displacement").map_err(at("displacement"))?;
        sg.new_dataset_builder().with_data(&pd).create("particle_displacement").map_err(at("particle_displacement"))?;
        sg.new_dataset_builder().with_data(&self.rotation[..]).create("rotation").map_err(at("rotation"))?;
        sg.new_dataset_builder().with_data(&self.crack[..]).create("crack").map_err(at("crack"))?;
        Ok(())
    }
}

/// The XDMF grid of one kept state (`name` its HDF5 group).
fn push_state_grid(xml: &mut String, h5_name: &str, name: &str, state: usize, mesh: &Mesh) {
    let (n_nodes, n_cells) = (mesh.coordinates.len(), mesh.particle.len());
    let _ = writeln!(xml, "      <Grid Name=\"state_{state}\" GridType=\"Uniform\">");
    let _ = writeln!(xml, "        <Time Value=\"{state}\"/>");
    push_mesh(xml, h5_name, n_nodes, n_cells, mesh.topology.len());
    for (field, center, comps, number, prec) in [
        ("displacement", "Node", 3, "Float", 8),
        ("particle_displacement", "Cell", 3, "Float", 8),
        ("rotation", "Cell", 1, "Float", 8),
        ("crack", "Cell", 1, "Int", 4),
    ] {
        let rows = if center == "Node" { n_nodes } else { n_cells };
        push_attribute(xml, h5_name, field, center, rows, comps, number, prec, &format!("{name}/{field}"));
    }
    xml.push_str("      </Grid>\n");
}

fn push_mesh(s: &mut String, h5: &str, n_nodes: usize, n_cells: usize, topo_len: usize) {
    let _ = writeln!(s, "        <Topology TopologyType=\"Mixed\" NumberOfElements=\"{n_cells}\">");
    let _ = writeln!(
        s,
        "          <DataItem Dimensions=\"{topo_len}\" NumberType=\"Int\" Precision=\"8\" Format=\"HDF\">{h5}:/mesh/topology</DataItem>"
    );
    s.push_str("        </Topology>\n        <Geometry GeometryType=\"XYZ\">\n");
    let _ = writeln!(
        s,
        "          <DataItem Dimensions=\"{n_nodes} 3\" NumberType=\"Float\" Precision=\"8\" Format=\"HDF\">{h5}:/mesh/coordinates</DataItem>"
    );
    s.push_str("        </Geometry>\n");
    for field in ["particle", "beam"] {
        push_attribute(s, h5, field, "Cell", n_cells, 1, "Int", 4, &format!("/mesh/{field}"));
    }
}

#[allow(clippy::too_many_arguments)]
fn push_attribute(
    s: &mut String,
    h5: &str,
    name: &str,
    center: &str,
    rows: usize,
    comps: usize,
    number: &str,
    prec: u8,
    path: &str,
) {
    let (kind, dims) = if comps == 1 { ("Scalar", format!("{rows}")) } else { ("Vector", format!("{rows} {comps}")) };
    let _ = writeln!(s, "        <Attribute Name=\"{name}\" AttributeType=\"{kind}\" Center=\"{center}\">");
    let _ = writeln!(
        s,
        "          <DataItem Dimensions=\"{dims}\" NumberType=\"{number}\" Precision=\"{prec}\" Format=\"HDF\">{h5}:{path}</DataItem>"
    );
    s.push_str("        </Attribute>\n");
}
