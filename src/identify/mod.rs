//! Identification (paper §3.2): calibrate the DEM's lattice parameters against experimental
//! numbers, then identify the continuum damage law from the calibrated DEM's virtual tests, both
//! by kriging-based efficient global optimization over MPI batches.
//!
//! | file               | concept                                                                 |
//! |--------------------|-------------------------------------------------------------------------|
//! | `space.rs`         | [`Space`]: named unknowns in intervals, the map to the unit cube        |
//! | `doe.rs`           | designs of experiments: Latin hypercube, two-level factorial           |
//! | `ego.rs`           | [`Ego`]: kriging + expected improvement (egobox), ask-and-tell, q-EI    |
//! | `collective.rs`    | the EGO loop over MPI ranks (rank 0 asks, every rank evaluates)         |
//! | `curves.rs`        | [`Curve`]: resampling, mean curves over samples                         |
//! | `stat.rs`          | [`Stat`]: mean and sample standard deviation                            |
//! | `error_measure.rs` | paper eq. 15 and the relative RMS                                       |
//! | `dem_adapter.rs`   | the one adapter to the DEM virtual lab                                  |
//! | `calibration.rs`   | (a) DEM calibration against E, ν, first-crack and peak stresses         |
//! | `elastic_fit.rs`   | (a), staged: stage 1, (α, Ē) from (ν, E) on the elastic state          |
//! | `virtual_tests.rs` | the calibrated DEM's tension and compression tests, mean curves         |
//! | `law_fit.rs`       | (b) damage-law identification from the virtual tests                    |
//! | `polish.rs`        | Nelder–Mead polish of the EGO optimum (cheap objectives)                |
//! | `material_file.rs` | the material file (`[law]` table) structural jobs read by path          |
//! | `variants.rs`      | material variants: the samples each variant of the law is fitted to     |
//! | `error.rs`         | [`IdentifyError`]                                                       |
//!
//! Reproducibility: the designs are seeded, the surrogate's optimizers are seeded per
//! iteration, the DEM samples have fixed seeds, and the batch returns results in task order
//! whatever rank computed them: the same job gives the same result on any number of ranks.
pub mod calibration;
pub mod collective;
pub mod curves;
pub mod dem_adapter;
pub mod doe;
pub mod ego;
pub mod elastic_fit;
pub mod error;
pub mod error_measure;
pub mod law_fit;
pub mod material_file;
pub mod polish;
pub mod space;
pub mod stat;
pub mod variants;
pub mod virtual_tests;

pub use calibration::{calibrate, Calibration, CalibrationResult, Strategy, Targets};
pub use curves::Curve;
pub use dem_adapter::{DemParameters, DemRun};
pub use ego::{Ego, EgoSettings, Evaluation};
pub use error::{EvalError, IdentifyError};
pub use error_measure::{curve_error, CurveError, ErrorMeasure};
pub use law_fit::{identify, LawFit, LawResult};
pub use space::Space;
pub use stat::Stat;

/// A search's history for the summary: each point as `iteration`, `point` (its coordinates
/// named by `names`, in order) and `objective` (`{"Ok": value}` or `{"Err": why}`).
fn named_history<S: serde::Serializer>(
    names: &[&str],
    h: &[(usize, Vec<f64>, Result<f64, EvalError>)],
    s: S,
) -> Result<S::Ok, S::Error> {
    use serde::ser::{SerializeSeq, SerializeStruct};
    struct Point<'a>(&'a [&'a str], &'a [f64]);
    impl serde::Serialize for Point<'_> {
        fn serialize<S: serde::Serializer>(&self, s: S) -> Result<S::Ok, S::Error> {
            crate::io::summary::write_named(self.0, self.1, s)
        }
    }
    struct Entry<'a>(&'a [&'a str], &'a (usize, Vec<f64>, Result<f64, EvalError>));
    impl serde::Serialize for Entry<'_> {
        fn serialize<S: serde::Serializer>(&self, s: S) -> Result<S::Ok, S::Error> {
            let (iteration, x, objective) = self.1;
            let mut e = s.serialize_struct("Entry", 3)?;
            e.serialize_field("iteration", iteration)?;
            e.serialize_field("point", &Point(self.0, x))?;
            e.serialize_field("objective", &Objective(objective))?;
            e.end()
        }
    }
    struct Objective<'a>(&'a Result<f64, EvalError>);
    impl serde::Serialize for Objective<'_> {
        fn serialize<S: serde::Serializer>(&self, s: S) -> Result<S::Ok, S::Error> {
            crate::io::summary::with_message(self.0, s)
        }
    }
    let mut seq = s.serialize_seq(Some(h.len()))?;
    for entry in h {
        seq.serialize_element(&Entry(names, entry))?;
    }
    seq.end()
}
