//! The [`Sample`]: particles, lattice and boundary sets of one virtual wall, built from a typed
//! config or from explicit seeds.
//!
//! Phases: seeds → validate seeds → clipped Voronoi cells → weld into a conforming tessellation →
//! merge/reject tiny facets → particles → check cells (convex, seed inside, tiling) → beams →
//! neighbour lists and boundary sets.
use super::checks::{check_cells, check_seeds, mean_spacing};
use super::config::{GeometryOptions, SampleConfig, SampleLayout};
use super::error::SampleError;
use super::lattice::{beam_inertia, Beam};
use super::particle::Particle;
use super::seeds::{coursed_seeds, poisson_disk_seeds, rng};
use super::topology::{MergedFacet, Tessellation};
use super::voronoi::clipped_cells;
use crate::dem::polygon::{Polygon, P2};

/// The particles touching each side of the domain (an edge of positive length on it), ascending:
/// the rows bonded to the platens.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct BoundaryParticles {
    /// On `y = 0`.
    pub bottom: Vec<usize>,
    /// On `y = height`.
    pub top: Vec<usize>,
    /// On `x = 0`.
    pub left: Vec<usize>,
    /// On `x = width`.
    pub right: Vec<usize>,
}

/// A virtual masonry sample: stones (convex Voronoi cells) and the beams bonding them.
#[derive(Clone, Debug, PartialEq)]
pub struct Sample {
    /// Domain width (m); the domain is `[0, width] × [0, height]`.
    pub width: f64,
    /// Domain height (m).
    pub height: f64,
    /// Out-of-plane thickness `t_z` (m).
    pub thickness: f64,
    /// The inertia coefficient α the beams' `inertia` was computed with.
    pub alpha: f64,
    /// The stones, indexed like their seeds.
    pub particles: Vec<Particle>,
    /// The lattice, sorted by `(i, j)`, `i < j`.
    pub beams: Vec<Beam>,
    /// Per particle, `(neighbour, beam index)` sorted by neighbour.
    pub neighbours: Vec<Vec<(usize, usize)>>,
    /// Particles on each side of the domain.
    pub boundary: BoundaryParticles,
    /// Facets removed as too short (their particles touch at a point and have no beam).
    pub merged_facets: Vec<MergedFacet>,
}

impl Sample {
    /// Builds the sample a config describes (validated first). Deterministic: the same config
    /// gives the same sample, bit for bit.
    pub fn build(config: &SampleConfig) -> Result<Sample, SampleError> {
        config.validate()?;
        let mut rng = rng(config.seed);
        let seeds = match &config.layout {
            SampleLayout::Coursed(l) => coursed_seeds(l, &mut rng),
            SampleLayout::Random(l) => poisson_disk_seeds(l, &mut rng)?,
        };
        let (w, h) = config.layout.domain();
        Sample::from_seeds(w, h, &seeds, &config.geometry_options())
    }

    /// Builds the sample of explicit seeds in `[0, width] × [0, height]` (particle `k` = seed `k`).
    pub fn from_seeds(width: f64, height: f64, seeds: &[P2], options: &GeometryOptions) -> Result<Sample, SampleError> {
        for (field, v) in [("width", width), ("height", height)] {
            SampleError::positive(field, v)?;
        }
        options.validate()?;
        check_seeds(width, height, seeds)?;
        let raw = clipped_cells(width, height, seeds);
        let mut tess = Tessellation::weld(&raw, width, height, 1e-9 * mean_spacing(width, height, seeds.len()))?;
        let polygon = |t: &Tessellation, c: usize| Polygon::new(t.cells[c].iter().map(|&v| t.vertices[v]).collect());
        let mean_d =
            (0..seeds.len()).map(|c| 2.0 * (polygon(&tess, c).area() / std::f64::consts::PI).sqrt()).sum::<f64>()
                / seeds.len() as f64;
        let merged_facets = tess.merge_tiny_facets(options.facet_tolerance * mean_d, options.tiny_facets)?;
        let particles: Vec<Particle> =
            seeds.iter().enumerate().map(|(c, &s)| Particle::new(polygon(&tess, c), s)).collect();
        check_cells(width, height, &particles)?;
        let mut beams: Vec<Beam> = tess
            .facets()?
            .into_iter()
            .map(|f| {
                let (pi, pj) = (&particles[f.i], &particles[f.j]);
                let facet = [tess.vertices[f.a], tess.vertices[f.b]];
                Beam::new(f.i, f.j, pi.seed, pj.seed, pi.centroid, pj.centroid, facet, options.thickness, options.alpha)
            })
            .collect();
        beams.sort_by_key(|b| (b.i, b.j));
        let mut neighbours = vec![Vec::new(); particles.len()];
        for (k, b) in beams.iter().enumerate() {
            neighbours[b.i].push((b.j, k));
            neighbours[b.j].push((b.i, k));
        }
        for n in &mut neighbours {
            n.sort_unstable();
        }
        let [bottom, right, top, left] = tess.boundary_cells();
        Ok(Sample {
            width,
            height,
            thickness: options.thickness,
            alpha: options.alpha,
            particles,
            beams,
            neighbours,
            boundary: BoundaryParticles { bottom, top, left, right },
            merged_facets,
        })
    }

    /// Recomputes every beam's inertia for a new α (calibration loops vary it).
    pub fn set_alpha(&mut self, alpha: f64) -> Result<(), SampleError> {
        SampleError::positive("alpha", alpha)?;
        self.alpha = alpha;
        for b in &mut self.beams {
            b.inertia = beam_inertia(alpha, self.thickness, b.facet_length);
        }
        Ok(())
    }

    /// Domain area `W H` (m²).
    pub fn domain_area(&self) -> f64 {
        self.width * self.height
    }

    /// Mean equivalent diameter of the particles (m).
    pub fn mean_diameter(&self) -> f64 {
        self.particles.iter().map(|p| p.diameter).sum::<f64>() / self.particles.len().max(1) as f64
    }

    /// The index of the beam between particles `i` and `j` (either order), if any.
    pub fn beam_between(&self, i: usize, j: usize) -> Option<usize> {
        let list = self.neighbours.get(i)?;
        list.binary_search_by_key(&j, |&(n, _)| n).ok().map(|k| list[k].1)
    }
}
