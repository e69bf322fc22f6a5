//! masonry-hpc: an MPI-parallel solver for the seismic assessment of historical masonry buildings.
//!
//! Read `ARCHITECTURE.md` first. The crate follows the physics and the numerics:
//!
//! | module      | concept                                                                  |
//! |-------------|--------------------------------------------------------------------------|
//! | [`config`]  | typed job files (TOML), validated once at load                          |
//! | [`dem`]     | the 2D discrete-element virtual testing lab                              |
//! | [`parallel`]| MPI context, rank-aware logging, METIS partition, DOF numbering, ghosts |
//! | [`petsc`]   | the project's own PETSc/SLEPc binding and its safe RAII layer           |
//! | [`mesh`]    | Gmsh MSH 4.1 input and the in-memory mesh                                |
//! | [`element`] | finite elements (3D frame beam, later shells and fiber beams)           |
//! | [`model`]   | the structural model: mesh + sections + supports + loads                |
//! | [`analysis`]| drivers: setup, assemble, solve, output                                  |
//! | [`io`]      | parallel HDF5 + XDMF results                                             |
//! | [`run`]     | a whole job: input checks agreed across ranks, PETSc start, dispatch     |
#![warn(missing_docs)]

pub mod analysis;
pub mod config;
pub mod dem;
pub mod element;
pub mod identify;
pub mod io;
pub mod material;
pub mod mesh;
pub mod model;
pub mod parallel;
pub mod petsc;
pub mod plot;
pub mod run;
pub mod seismic;
