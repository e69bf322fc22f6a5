//! The typed description of a virtual sample, as read from a job file, and its validation.
//!
//! ```toml
//! [sample]
//! seed = 7                # RNG seed: the same seed gives the same sample, bit for bit
//! thickness = 1.0         # out-of-plane thickness t_z (m), default 1
//! alpha = 0.8             # beam inertia coefficient α (paper §2.1, Table 1), default 0.8
//! facet_tolerance = 0.02  # tiny facet: shorter than this × mean particle diameter, default 0.02
//! tiny_facets = "merge"   # or "reject"
//! [sample.layout]
//! type = "coursed"        # or "random"
//! width = 1.0             # m
//! height = 1.2            # m
//! n_courses = 10
//! n_per_course = 6
//! jitter = 0.2            # seed jitter, fraction of the stone's half size, in [0, 1)
//! stagger = 1.0           # joint offset of alternate courses, fraction of half a stone, in [0, 1]
//! size_variability = 0.2  # stone width variation, fraction of the mean width, in [0, 1)
//! ```
use super::error::SampleError;
use serde::{Deserialize, Serialize};

/// Default out-of-plane thickness `t_z` (m): the 2D model is a 1 m slice (paper §2.1).
pub const DEFAULT_THICKNESS: f64 = 1.0;
/// Default beam inertia coefficient α: the paper's calibrated value (paper §2.1, Table 1).
pub const DEFAULT_ALPHA: f64 = 0.8;
/// Default tiny-facet tolerance, as a fraction of the mean particle diameter.
pub const DEFAULT_FACET_TOLERANCE: f64 = 0.02;
/// Largest admissible Poisson-disk `min_distance_factor`: random sequential adsorption of disks
/// jams at a covered fraction ≈ 0.547 (Feder 1980), i.e. `π f²/4 < 0.547`, `f < 0.83`; 0.8 keeps
/// dart throwing finishing in reasonable time.
pub const MAX_MIN_DISTANCE_FACTOR: f64 = 0.8;

/// What to do with a facet shorter than `facet_tolerance × mean diameter`.
#[derive(Clone, Copy, Debug, Default, Deserialize, Serialize, PartialEq, Eq, schemars::JsonSchema)]
#[serde(rename_all = "snake_case")]
pub enum TinyFacetPolicy {
    /// Snap its two end vertices together (the two particles then touch at a point, no beam).
    #[default]
    Merge,
    /// Fail with [`SampleError::TinyFacet`] naming the particles and the length.
    Reject,
}

/// Coursed (regular) masonry: courses of stones with jittered seeds and staggered joints.
#[derive(Clone, Debug, Deserialize, Serialize, PartialEq, schemars::JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct CoursedLayout {
    /// Domain width [m].
    pub width: f64,
    /// Domain height [m].
    pub height: f64,
    /// Number of courses (rows), ≥ 1.
    pub n_courses: usize,
    /// Stones per course, ≥ 1.
    pub n_per_course: usize,
    /// Seed jitter in [0, 1): each seed moves by up to this fraction of its stone's half width
    /// (horizontally) and half course height (vertically).
    #[serde(default)]
    pub jitter: f64,
    /// Joint offset of alternate courses in [0, 1], as a fraction of half a stone (1 = the usual
    /// half-stone bond).
    #[serde(default = "one")]
    pub stagger: f64,
    /// Stone width variability in [0, 1): every interior joint moves by up to this fraction of
    /// half the mean stone width.
    #[serde(default)]
    pub size_variability: f64,
}

/// Random (Poisson-disk) stones.
#[derive(Clone, Debug, Deserialize, Serialize, PartialEq, schemars::JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct RandomLayout {
    /// Domain width [m].
    pub width: f64,
    /// Domain height [m].
    pub height: f64,
    /// Number of particles, ≥ 1.
    pub n_particles: usize,
    /// Minimum seed distance `r = f · sqrt(width · height / n_particles)`, `f` in
    /// (0, [`MAX_MIN_DISTANCE_FACTOR`]]; default 0.7.
    #[serde(default = "default_min_distance_factor")]
    pub min_distance_factor: f64,
}

/// How the seeds are laid out.
#[derive(Clone, Debug, Deserialize, Serialize, PartialEq, schemars::JsonSchema)]
#[serde(tag = "type", rename_all = "snake_case")]
pub enum SampleLayout {
    /// Coursed masonry.
    Coursed(CoursedLayout),
    /// Random stones.
    Random(RandomLayout),
}

/// `[sample]`: a virtual masonry sample.
#[derive(Clone, Debug, Deserialize, Serialize, PartialEq, schemars::JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct SampleConfig {
    /// The seed layout.
    pub layout: SampleLayout,
    /// Out-of-plane thickness `t_z` [m].
    #[serde(default = "default_thickness")]
    pub thickness: f64,
    /// RNG seed.
    #[serde(default)]
    pub seed: u64,
    /// Beam inertia coefficient α (see [`super::lattice::beam_inertia`]).
    #[serde(default = "default_alpha")]
    pub alpha: f64,
    /// Tiny-facet tolerance, fraction of the mean particle diameter, in [0, 0.5); 0 disables.
    #[serde(default = "default_facet_tolerance")]
    pub facet_tolerance: f64,
    /// What to do with tiny facets.
    #[serde(default)]
    pub tiny_facets: TinyFacetPolicy,
}

fn one() -> f64 {
    1.0
}
fn default_min_distance_factor() -> f64 {
    0.7
}
fn default_thickness() -> f64 {
    DEFAULT_THICKNESS
}
fn default_alpha() -> f64 {
    DEFAULT_ALPHA
}
fn default_facet_tolerance() -> f64 {
    DEFAULT_FACET_TOLERANCE
}

/// The options of the tessellation and the lattice that do not depend on the layout.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct GeometryOptions {
    /// Out-of-plane thickness `t_z` [m].
    pub thickness: f64,
    /// Beam inertia coefficient α.
    pub alpha: f64,
    /// Tiny-facet tolerance (fraction of the mean diameter); 0 disables the check.
    pub facet_tolerance: f64,
    /// What to do with tiny facets.
    pub tiny_facets: TinyFacetPolicy,
}

impl Default for GeometryOptions {
    fn default() -> Self {
        GeometryOptions {
            thickness: DEFAULT_THICKNESS,
            alpha: DEFAULT_ALPHA,
            facet_tolerance: DEFAULT_FACET_TOLERANCE,
            tiny_facets: TinyFacetPolicy::Merge,
        }
    }
}

impl GeometryOptions {
    /// Checks every value's range.
    pub fn validate(&self) -> Result<(), SampleError> {
        SampleError::positive("thickness", self.thickness)?;
        SampleError::positive("alpha", self.alpha)?;
        in_range("facet_tolerance", self.facet_tolerance, 0.0, 0.5, false, "a number in [0, 0.5)")
    }
}

impl SampleLayout {
    /// Domain `(width, height)` (m).
    pub fn domain(&self) -> (f64, f64) {
        match self {
            SampleLayout::Coursed(c) => (c.width, c.height),
            SampleLayout::Random(r) => (r.width, r.height),
        }
    }
}

impl SampleConfig {
    /// The paper's wall (paper §2.1, Table 1): 1.00 m wide × 1.20 m high, 10 staggered courses of 6
    /// stones (jitter 0.2, size variability 0.2), 1 m thick, α = 0.8, tiny facets merged.
    pub fn paper_wall(seed: u64) -> SampleConfig {
        SampleConfig {
            layout: SampleLayout::Coursed(CoursedLayout {
                width: 1.0,
                height: 1.2,
                n_courses: 10,
                n_per_course: 6,
                jitter: 0.2,
                stagger: 1.0,
                size_variability: 0.2,
            }),
            thickness: 1.0,
            seed,
            alpha: 0.8,
            facet_tolerance: 0.02,
            tiny_facets: TinyFacetPolicy::Merge,
        }
    }

    /// The layout-independent options.
    pub fn geometry_options(&self) -> GeometryOptions {
        GeometryOptions {
            thickness: self.thickness,
            alpha: self.alpha,
            facet_tolerance: self.facet_tolerance,
            tiny_facets: self.tiny_facets,
        }
    }

    /// Checks every value's range; the builder calls it first.
    pub fn validate(&self) -> Result<(), SampleError> {
        let (w, h) = self.layout.domain();
        SampleError::positive("width", w)?;
        SampleError::positive("height", h)?;
        match &self.layout {
            SampleLayout::Coursed(c) => {
                at_least_one("n_courses", c.n_courses)?;
                at_least_one("n_per_course", c.n_per_course)?;
                in_range("jitter", c.jitter, 0.0, 1.0, false, "a number in [0, 1)")?;
                in_range("stagger", c.stagger, 0.0, 1.0, true, "a number in [0, 1]")?;
                in_range("size_variability", c.size_variability, 0.0, 1.0, false, "a number in [0, 1)")?;
            }
            SampleLayout::Random(r) => {
                at_least_one("n_particles", r.n_particles)?;
                let f = r.min_distance_factor;
                if !(f > 0.0 && f <= MAX_MIN_DISTANCE_FACTOR) {
                    return Err(invalid("min_distance_factor", f, "a number in (0, 0.8]"));
                }
            }
        }
        self.geometry_options().validate()
    }
}

fn invalid(field: &'static str, value: impl ToString, expected: &'static str) -> SampleError {
    SampleError::InvalidConfig { field, value: value.to_string(), expected }
}

fn at_least_one(field: &'static str, v: usize) -> Result<(), SampleError> {
    if v >= 1 {
        Ok(())
    } else {
        Err(invalid(field, v, "an integer ≥ 1"))
    }
}

fn in_range(
    field: &'static str,
    v: f64,
    lo: f64,
    hi: f64,
    hi_closed: bool,
    expected: &'static str,
) -> Result<(), SampleError> {
    let ok = v >= lo && (v < hi || (hi_closed && v == hi));
    if ok {
        Ok(())
    } else {
        Err(invalid(field, v, expected))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    const PAPER_WALL: &str = r#"
        seed = 7
        [layout]
        type = "coursed"
        width = 1.0
        height = 1.2
        n_courses = 10
        n_per_course = 6
        jitter = 0.2
    "#;

    #[test]
    fn toml_with_defaults() {
        let c: SampleConfig = toml::from_str(PAPER_WALL).expect("valid config");
        assert_eq!(c.thickness, 1.0);
        assert_eq!(c.alpha, 0.8);
        assert_eq!(c.tiny_facets, TinyFacetPolicy::Merge);
        let SampleLayout::Coursed(l) = &c.layout else { panic!("coursed expected") };
        assert_eq!((l.stagger, l.size_variability), (1.0, 0.0));
        assert!(c.validate().is_ok());
    }

    #[test]
    fn unknown_key_is_rejected() {
        let bad = PAPER_WALL.replace("jitter", "jiter");
        assert!(toml::from_str::<SampleConfig>(&bad).is_err());
    }

    #[test]
    fn random_layout_parses() {
        let c: SampleConfig =
            toml::from_str("[layout]\ntype = \"random\"\nwidth = 1.0\nheight = 1.0\nn_particles = 100\n")
                .expect("valid config");
        assert!(matches!(c.layout, SampleLayout::Random(RandomLayout { min_distance_factor: 0.7, .. })));
    }

    #[test]
    fn out_of_range_values_are_named() {
        let mut c: SampleConfig = toml::from_str(PAPER_WALL).expect("valid config");
        c.thickness = -1.0;
        let e = c.validate().unwrap_err();
        assert!(matches!(e, SampleError::InvalidConfig { field: "thickness", .. }), "{e}");
        c.thickness = 1.0;
        if let SampleLayout::Coursed(l) = &mut c.layout {
            l.jitter = 1.0;
        }
        let e = c.validate().unwrap_err();
        assert!(e.to_string().contains("`jitter`: expected a number in [0, 1), got 1"), "{e}");
        if let SampleLayout::Coursed(l) = &mut c.layout {
            l.jitter = 0.1;
            l.n_courses = 0;
        }
        assert!(matches!(c.validate(), Err(SampleError::InvalidConfig { field: "n_courses", .. })));
        if let SampleLayout::Coursed(l) = &mut c.layout {
            l.n_courses = 3;
            l.width = f64::NAN;
        }
        assert!(matches!(c.validate(), Err(SampleError::InvalidConfig { field: "width", .. })));
    }
}
