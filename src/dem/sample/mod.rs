//! Virtual masonry samples (paper §2.1, geometry and lattice): seeds (coursed or Poisson-disk),
//! Voronoi cells clipped to the wall, one rigid particle per cell, one beam per shared edge.
//!
//! ```text
//! SampleConfig ──seeds──▶ [P2] ──voronoi──▶ RawCell ──topology──▶ Tessellation
//!        (coursed | random, seeded RNG)   (clipped)    (welded, tiny facets merged)
//!                                                              │
//!                        Sample { particles, beams, neighbours, boundary } ◀──┘ ──svg──▶ String
//! ```
//!
//! Conventions for mechanics: particle `k`'s DOF `(u_x, u_y, θ)` are those of its centroid
//! [`Particle::centroid`]; beam `b` joins the seeds of `b.i < b.j`, whose offsets from the centroids
//! are `b.arm_i`, `b.arm_j`; `b.normal` points from `i` to `j`, `b.tangent = e_z × normal`.
pub mod builder;
pub mod checks;
pub mod config;
pub mod error;
pub mod lattice;
pub mod particle;
pub mod seeds;
pub mod svg;
#[cfg(test)]
mod tests;
pub mod topology;
pub mod voronoi;

pub use builder::{BoundaryParticles, Sample};
pub use config::{CoursedLayout, GeometryOptions, RandomLayout, SampleConfig, SampleLayout, TinyFacetPolicy};
pub use error::SampleError;
pub use lattice::{beam_inertia, Beam};
pub use particle::Particle;
pub use svg::{draw_svg, CrackCategory, SvgStyle};
pub use topology::MergedFacet;
