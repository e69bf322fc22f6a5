//! Outputs of the DEM lab beyond the curves and crack pictures: particle states as HDF5/XDMF.
pub mod particle_xdmf;

pub use particle_xdmf::{write_particle_states, ParticleOutputError};
