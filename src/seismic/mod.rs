//! Ground motion: records (readers, checks, processing), intensity measures, response spectra,
//! Eurocode 8 elastic spectra, synthetic records, and charts.
//!
//! | file              | concept                                                            |
//! |-------------------|--------------------------------------------------------------------|
//! | `record`          | [`Record`]: uniform samples in m/s² with provenance                 |
//! | `units`           | [`AccelUnit`]: g, m/s², cm/s²                                      |
//! | `format_at2`      | PEER NGA `.AT2` reader                                             |
//! | `format_esm`      | ESM ASCII reader                                                   |
//! | `format_columns`  | two-column / one-column readers, two-column writer                 |
//! | `baseline`        | polynomial baseline correction (acceleration or displacement fit)  |
//! | `filter`          | zero-phase Butterworth band-pass by biquads                        |
//! | `intensity`       | PGA, PGV, PGD, Arias intensity, D5–95                              |
//! | `sdof`            | exact piecewise-linear SDOF recurrence (Nigam & Jennings)          |
//! | `spectrum`        | response spectra Sd, Sv, Sa over periods                           |
//! | `ec8`             | EN 1998-1 §3.2.2.2 horizontal elastic spectra                      |
//! | `fft`             | radix-2 complex FFT for spectral matching                          |
//! | `synthetic`       | filtered white noise (Kanai–Tajimi, Clough–Penzien) with envelope  |
//! | `matching`        | frequency-domain spectral matching                                 |
//! | `vallorcine`      | the synthetic Vallorcine-like stand-in record                      |
//! | `artificial`      | artificial records matched to EC8, one seed each                   |
//! | `set_scaling`     | one factor per recorded record: log least squares over a range     |
//! | `compatibility`   | EN 1998-1 §3.2.3.1.2(4) check of a set's mean spectrum             |
//! | `record_set`      | a set: artificial + scaled recorded records, spectra, check        |
//! | `fragility`       | lognormal fragility functions fitted to IDA passages (Baker 2015)   |
//! | `charts`          | PNG charts: record vs EC8 spectra, a set vs its target, history    |
mod artificial;
mod baseline;
mod charts;
mod compatibility;
mod ec8;
mod error;
mod fft;
mod filter;
mod format_at2;
mod format_columns;
mod format_esm;
mod fragility;
mod intensity;
mod matching;
mod record;
mod record_set;
mod sdof;
mod set_scaling;
mod spectrum;
mod synthetic;
mod text;
mod units;
mod vallorcine;

pub use artificial::{artificial_record, ArtificialSpec};
pub use baseline::{correct as baseline_correct, Baseline};
pub use charts::{record_png, record_set_png, spectrum_png};
pub use compatibility::{
    check_compatibility, check_periods, mean_sa, Compatibility, CompatibilityRules, RatioPoint, RuleOutcome,
    RULE_COUNT, RULE_SPECTRUM, RULE_STATIONARY, RULE_ZERO_PERIOD,
};
pub use ec8::{Ec8Spectrum, Ec8Type, GroundType};
pub use error::SeismicError;
pub use fft::{fft_in_place, Complex};
pub use filter::{band_pass, BandPass};
pub use format_at2::{parse_at2, read_at2};
pub use format_columns::{
    parse_one_column, parse_two_column, read_one_column, read_two_column, write_two_column, DEFAULT_DT_TOLERANCE,
};
pub use format_esm::{parse_esm, read_esm};
pub use fragility::{fit_fragility, normal_cdf, Estimator, FragilityFit, Passage};
pub use intensity::{husid, integrate, intensity, pga, Intensity};
pub use matching::{match_spectrum, MatchReport, MatchSettings};
pub use record::Record;
pub use record_set::{build_set, scale_recorded, Member, Origin, RecordSet, SetRecipe, SET_DAMPING};
pub use sdof::{peak_displacement, response_history, SdofStep};
pub use set_scaling::log_least_squares_factor;
pub use spectrum::{log_periods, response_spectrum, ResponseSpectrum};
pub use synthetic::{generate, Envelope, GroundFilter, SyntheticSpec};
pub use units::{AccelUnit, STANDARD_GRAVITY};
pub use vallorcine::{
    vallorcine_like_header, vallorcine_like_spec, vallorcine_like_synthetic, write_vallorcine_like,
    VALLORCINE_LIKE_FILE,
};
