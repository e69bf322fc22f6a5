//! The benchmark sample shared by the DEM examples: N random Voronoi stones in a 1 m × 1 m square
//! (seed 7, α 0.8, minimum seed distance 0.7 of the mean spacing, tiny facets merged).
use masonry_hpc::dem::sample::{RandomLayout, Sample, SampleConfig, SampleLayout, TinyFacetPolicy};

#[allow(dead_code)]
pub fn random_square(n: usize) -> Result<Sample, Box<dyn std::error::Error>> {
    random_square_seeded(n, 7)
}

/// The same square with another seed of the stones' positions.
pub fn random_square_seeded(n: usize, seed: u64) -> Result<Sample, Box<dyn std::error::Error>> {
    Ok(Sample::build(&SampleConfig {
        layout: SampleLayout::Random(RandomLayout {
            width: 1.0,
            height: 1.0,
            n_particles: n,
            min_distance_factor: 0.7,
        }),
        thickness: 1.0,
        seed,
        alpha: 0.8,
        facet_tolerance: 0.02,
        tiny_facets: TinyFacetPolicy::Merge,
    })?)
}
