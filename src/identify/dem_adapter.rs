//! The one place the identification calls the DEM virtual lab (`crate::dem`): build a sample,
//! run a virtual test, return the curve and the derived numbers in the identification's terms.
//! Everything else in `identify/` sees only [`DemRun`], so a change of the DEM's interface is
//! absorbed here.
use super::curves::Curve;
use super::error::EvalError;
use crate::dem::error::TestFailure;
use crate::dem::mechanics::MechParams;
use crate::dem::sample::{Sample, SampleConfig};
use crate::dem::solver::{run_test, TestEnd, VirtualTest};
use serde::{Deserialize, Serialize};

/// The lattice parameters the identification varies or fixes (paper §2.1): α enters the sample
/// (beam inertias), the others the mechanics.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
pub struct DemParameters {
    /// Beam inertia coefficient α.
    pub alpha: f64,
    /// Lattice Young modulus Ē [Pa].
    pub e_bar: f64,
    /// Critical beam strain ε_cr.
    pub eps_cr: f64,
    /// Critical relative rotation θ_cr [rad].
    pub theta_cr: f64,
    /// Friction coefficient μ (fixed in the calibration).
    pub mu: f64,
    /// Tangential over normal contact stiffness.
    pub kt_over_kn: f64,
    /// Crushing stress σ_c [Pa] (`dem::mechanics::crushing`; `None`: paper §2.1's model).
    #[serde(default)]
    pub crushing_stress: Option<f64>,
    /// Crushing fracture energy G_c [J/m²], with `crushing_stress`.
    #[serde(default)]
    pub crushing_energy: Option<f64>,
}

impl DemParameters {
    /// The crushing parameters, when both are set.
    pub fn crushing(&self) -> Option<crate::dem::mechanics::Crushing> {
        match (self.crushing_stress, self.crushing_energy) {
            (Some(stress), Some(energy)) => Some(crate::dem::mechanics::Crushing { stress, energy }),
            _ => None,
        }
    }
}

/// What one virtual test gives the identification.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct DemRun {
    /// The loading curve in the test direction (compression: shortening and compressive
    /// stress positive), at most [`MAX_CURVE_POINTS`] points.
    pub curve: Curve,
    /// Initial Young modulus [Pa].
    pub young_modulus: f64,
    /// Poisson ratio.
    pub poisson: f64,
    /// Stress at the first beam break [Pa], if any broke.
    pub first_crack_stress: Option<f64>,
    /// Peak stress [Pa].
    pub peak_stress: f64,
    /// Strain at the peak (magnitude).
    pub strain_at_peak: f64,
    /// Beam-break events.
    pub events: usize,
    /// Wall time [s].
    pub seconds: f64,
    /// Whether the test's numbers are valid: false when the solver stopped before the peak
    /// (the DEM's `TestEnd::Failed`: no equilibrium before the force had fallen 10 % below its
    /// peak); the DEM job leaves such samples out of its statistics.
    #[serde(default = "yes")]
    pub valid: bool,
    /// How the test ended (`target`, `loss_of_load`, `collapse`, `failed`).
    #[serde(default)]
    pub end: String,
}

fn yes() -> bool {
    true
}

/// Curves sent back from a batch task are thinned to about this many points (the peak kept).
pub const MAX_CURVE_POINTS: usize = 400;

/// The sample configuration of sample `k` (seed `base.seed + k`) with inertia coefficient α.
pub fn sample_config(base: &SampleConfig, alpha: f64, k: usize) -> SampleConfig {
    let mut c = base.clone();
    c.seed = base.seed.wrapping_add(k as u64);
    c.alpha = alpha;
    c
}

/// Height of the sample [m] (the virtual test's gauge length).
pub fn sample_height(base: &SampleConfig) -> f64 {
    base.layout.domain().1
}

/// Runs `test` on sample `k` of `base` with `p`. The error names the sample and says what
/// stopped it.
pub fn run_virtual_test(
    base: &SampleConfig,
    p: &DemParameters,
    test: &VirtualTest,
    k: usize,
) -> Result<DemRun, EvalError> {
    let cfg = sample_config(base, p.alpha, k);
    let sample = Sample::build(&cfg).map_err(|e| TestFailure::Sample {
        sample: k,
        seed: Some(cfg.seed),
        message: e.to_string(),
    })?;
    let params = MechParams {
        e_bar: p.e_bar,
        t_z: cfg.thickness,
        eps_cr: p.eps_cr,
        theta_cr: p.theta_cr,
        mu: p.mu,
        kt_over_kn: p.kt_over_kn,
        crushing: p.crushing(),
    };
    params.validate().map_err(|e| TestFailure::Params { sample: k, message: e.to_string() })?;
    let r = run_test(&sample, &params, test).map_err(|e| TestFailure::solver(k, Some(cfg.seed), &e))?;
    let sign = if matches!(test, VirtualTest::Compression { .. }) { -1.0 } else { 1.0 };
    let stride = r.curve.len().div_ceil(MAX_CURVE_POINTS).max(1);
    let peak = r
        .curve
        .iter()
        .enumerate()
        .max_by(|a, b| (sign * a.1.stress).total_cmp(&(sign * b.1.stress)))
        .map_or(0, |p| p.0);
    let mut x = Vec::new();
    let mut y = Vec::new();
    for (i, c) in r.curve.iter().enumerate() {
        if i % stride == 0 || i + 1 == r.curve.len() || i == peak {
            x.push(sign * c.strain);
            y.push(sign * c.stress);
        }
    }
    // A post-peak collapse (no equilibrium once the force had fallen 10 % below its peak: a
    // brittle failure the quasi-static model cannot follow) carries nothing more, like a loss
    // of load: the curve is zero beyond its end.
    let collapsed = matches!(r.end, TestEnd::Collapse { .. });
    let curve = Curve { x, y, loss_of_load: r.stats.loss_of_load || collapsed }.monotonic();
    let end = match &r.end {
        TestEnd::Target => "target",
        TestEnd::LossOfLoad => "loss_of_load",
        TestEnd::Collapse { .. } => "collapse",
        TestEnd::Failed { .. } => "failed",
    };
    let d = &r.derived;
    Ok(DemRun {
        curve,
        young_modulus: d.young_modulus,
        poisson: d.poisson,
        first_crack_stress: d.first_crack_stress,
        peak_stress: d.peak_stress,
        strain_at_peak: d.strain_at_peak.abs(),
        events: r.stats.events,
        seconds: r.stats.seconds,
        valid: r.end.is_valid(),
        end: end.to_string(),
    })
}
