//! Results output: one HDF5 file written collectively by all ranks through MPI-IO, and an XDMF 3
//! index next to it that ParaView 5.11 and meshio read as a time series.
//!
//! | file               | concept                                                     |
//! |--------------------|-------------------------------------------------------------|
//! | `output_mesh.rs`   | the rank's piece of the mesh in output numbering; Mixed topology |
//! | `results.rs`       | [`ResultsWriter`]: the HDF5 layout and the collective calls  |
//! | `hyperslab.rs`     | collective MPI-IO hyperslab writes (`H5Pset_dxpl_mpio`)      |
//! | `collective.rs`    | agreeing on arguments across ranks before a collective call |
//! | `xdmf.rs`          | the XDMF index text and its atomic replacement              |
//! | `error.rs`         | [`IoError`]                                                 |
//! | `paths.rs`         | [`normalize`]: paths as the user reads them in messages      |
//! | `summary.rs`       | `summary.json`: its format version, arrays as named fields   |
//!
//! Use: `ResultsWriter::create` once (writes the mesh), then per output step `begin_step(t)`,
//! any number of `write_node_field` / `write_cell_field`, `end_step()`. After every `end_step`
//! the `.h5` + `.xdmf` pair is complete and readable. Runnable example: `examples/io_demo.rs`.

mod collective;
mod error;
mod hyperslab;
mod output_mesh;
mod paths;
mod results;
pub mod summary;
mod xdmf;

pub use error::IoError;
pub use output_mesh::OutputMesh;
pub use paths::normalize;
pub use results::ResultsWriter;
