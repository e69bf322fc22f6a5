//! masonry-hpc: an MPI-parallel solver for the seismic assessment of historical masonry buildings.
//!
//! Read `ARCHITECTURE.md` first. The modules form layers; each imports only from the layers
//! below it (no import cycle between modules):
//!
//! | layer              | modules                                                                  |
//! |--------------------|--------------------------------------------------------------------------|
//! | jobs               | [`run`]: input agreed across ranks, dispatch, the non-FE job drivers     |
//! | FE analyses        | [`analysis`]: static, modal, updating, time history, seismic assessment, and their machinery (discretization, assembly, Newton) |
//! | model and input    | [`model`] (mesh + parts + supports + loads), [`config`] (typed job files) |
//! | domain             | [`element`], [`material`], [`dem`], [`identify`], [`seismic`]            |
//! | platform           | [`petsc`], [`mesh`], [`io`], [`parallel`], [`plot`]                      |
//! | leaves             | [`error`] (the run's error and its exit codes), [`fault`] (fault injection for tests) |
//! | input bounds       | [`bounds`]: the one finite-and-positive check of input, below every layer |
#![warn(missing_docs)]

pub mod analysis;
pub mod bounds;
pub mod config;
pub mod dem;
pub mod element;
pub mod error;
pub mod fault;
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
