//! What can go wrong while building a virtual sample, each case naming what and where.
use thiserror::Error;

/// An error building, checking or drawing a virtual masonry sample.
#[derive(Debug, Error, Clone, PartialEq)]
pub enum SampleError {
    /// A configuration value outside its admissible range.
    #[error("sample config: `{field}`: expected {expected}, got {value}")]
    InvalidConfig {
        /// The config key.
        field: &'static str,
        /// The value given, as text.
        value: String,
        /// What is admissible.
        expected: &'static str,
    },
    /// No seed at all.
    #[error("sample: no seed given (at least one particle is needed)")]
    NoSeeds,
    /// A seed on or outside the domain boundary, or not finite.
    #[error("sample: seed {index} at ({x}, {y}) is not strictly inside the domain [0, {width}] × [0, {height}] m")]
    SeedOutsideDomain {
        /// Seed (particle) index.
        index: usize,
        /// Seed x (m).
        x: f64,
        /// Seed y (m).
        y: f64,
        /// Domain width (m).
        width: f64,
        /// Domain height (m).
        height: f64,
    },
    /// Two seeds closer than the duplicate tolerance: their cells would be degenerate.
    #[error(
        "sample: seeds {i} and {j} are {distance:e} m apart (duplicate tolerance {tolerance:e} m): their cells would be degenerate"
    )]
    DuplicateSeeds {
        /// First seed.
        i: usize,
        /// Second seed.
        j: usize,
        /// Their distance (m).
        distance: f64,
        /// The tolerance (m).
        tolerance: f64,
    },
    /// Dart throwing could not place the requested number of Poisson-disk seeds.
    #[error(
        "sample: placed only {placed} of {target} Poisson-disk seeds at minimum distance {min_distance} m after {attempts} attempts: lower `min_distance_factor`"
    )]
    PoissonDiskFailed {
        /// Seeds placed.
        placed: usize,
        /// Seeds asked for.
        target: usize,
        /// Minimum distance (m).
        min_distance: f64,
        /// Attempts made.
        attempts: usize,
    },
    /// A cell with (numerically) no area.
    #[error("sample: the cell of particle {particle} has area {area:e} m² (degenerate)")]
    ZeroAreaCell {
        /// Particle index.
        particle: usize,
        /// Its area (m²).
        area: f64,
    },
    /// A cell that is not convex (after merging tiny facets).
    #[error("sample: the cell of particle {particle} is not convex")]
    NonConvexCell {
        /// Particle index.
        particle: usize,
    },
    /// A cell that does not contain its own seed.
    #[error("sample: the cell of particle {particle} does not contain its seed ({x}, {y})")]
    SeedOutsideCell {
        /// Particle index.
        particle: usize,
        /// Seed x (m).
        x: f64,
        /// Seed y (m).
        y: f64,
    },
    /// A facet shorter than the tolerance, with the policy `reject`.
    #[error(
        "sample: the facet shared by particles {i} and {j} is {length:e} m long, shorter than the tolerance {tolerance:e} m (policy `reject`)"
    )]
    TinyFacet {
        /// First particle.
        i: usize,
        /// Second particle.
        j: usize,
        /// Facet length (m).
        length: f64,
        /// Tolerance (m).
        tolerance: f64,
    },
    /// A tiny facet whose two end points are both on the domain boundary cannot be merged.
    #[error(
        "sample: the facet shared by particles {i} and {j} ({length:e} m) joins two boundary points and cannot be merged"
    )]
    CannotMergeFacet {
        /// First particle.
        i: usize,
        /// Second particle.
        j: usize,
        /// Facet length (m).
        length: f64,
    },
    /// The two sides of a shared edge do not match (a tessellation defect).
    #[error("sample: the edge of particle {i} facing particle {j} has no matching edge in particle {j}")]
    NonConforming {
        /// Particle whose edge has no twin.
        i: usize,
        /// The neighbour it names.
        j: usize,
    },
    /// The cells do not tile the domain.
    #[error("sample: the cell areas sum to {sum} m², the domain is {domain} m² (relative gap {relative:e})")]
    TilingMismatch {
        /// Sum of cell areas (m²).
        sum: f64,
        /// Domain area (m²).
        domain: f64,
        /// |sum − domain| / domain.
        relative: f64,
    },
    /// A displacement array whose length is not the particle count.
    #[error("svg: {got} displacement triples given for {expected} particles")]
    DisplacementCount {
        /// Triples given.
        got: usize,
        /// Particles.
        expected: usize,
    },
    /// A broken-beam index past the end of the lattice.
    #[error("svg: broken beam index {index} but the lattice has {count} beams")]
    BeamIndex {
        /// Index given.
        index: usize,
        /// Beam count.
        count: usize,
    },
}

impl SampleError {
    /// Nothing when `v` is finite and > 0 ([`crate::bounds::positive`]), else
    /// [`SampleError::InvalidConfig`] naming `field`.
    pub fn positive(field: &'static str, v: f64) -> Result<(), SampleError> {
        crate::bounds::positive(v).map(drop).map_err(|b| SampleError::InvalidConfig {
            field,
            value: b.value.to_string(),
            expected: b.expected,
        })
    }
}
