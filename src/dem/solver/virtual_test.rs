//! The virtual tests (paper §2.1, "Virtual tests"): uniaxial compression and tension, shear under
//! constant vertical compression, their cyclic versions, and the derived numbers.
//!
//! ```toml
//! [test]
//! type = "compression"      # or "tension"
//! max_strain = 2e-3         # |ε_yy| at the end (platen displacement / height)
//! steps = 50
//! # type = "shear", vertical_stress = 1e6, max_displacement = 6e-3, steps = 60, rotation = "fixed"
//! # type = "cyclic_tension_compression", amplitudes = [5e-5, 1e-4, 2e-4], compression_ratio = 1.0,
//! #        steps_per_half_cycle = 20
//! # type = "cyclic_shear", vertical_stress = 1e6, amplitudes = [1e-3, 2e-3, 4e-3],
//! #        steps_per_half_cycle = 20, rotation = "fixed"
//! ```
//!
//! **Cyclic protocol** ([`cyclic_protocol`]). Cycle `k` drives the platen from where it is to
//! `+a_k` and then to `−c a_k` (`c` = `compression_ratio` for tension–compression, 1 for shear);
//! after the last cycle it returns to 0. Each branch is one load stage, with
//! `⌈n |Δ| / ((1 + c) a_k)⌉` steps, `n` = `steps_per_half_cycle` (a full half cycle `+a_k → −c a_k`
//! gets `n` steps). Loading and unloading go through the same event-driven solver: broken beams
//! stay broken, cracks close through contacts, closed cracks slide with Coulomb friction, so the
//! loops show stiffness degradation, crack closure and frictional hysteresis. Amplitudes are
//! strains `U_y/H` (tension–compression) or top-platen displacements in m (shear).
//!
//! **Stopping.** Monotonic tests: the target, or loss of load (the driven force below
//! `loss_fraction` × its peak after a break). Cyclic tests: the end of the protocol, or loss of
//! load in every direction visited: the largest |force| of the latest branch towards `+` (and
//! towards `−`) below `loss_fraction` × that direction's peak.
//!
//! Platens are bonded to the bottom and top rows ([`super::dofs`]). Sign convention: tension
//! positive; `strain = U_y/H` (compression, tension) or `U_x/H` (shear), `stress = F/(W t_z)` with
//! `F` the top platen's force along the driven DOF. Lateral strain `(ū_x,right − ū_x,left)/W`.
//! The tests run in [`super::test_run`].

use serde::{Deserialize, Serialize};

use super::dofs::DofControl;
use super::error::{non_negative, positive, DemError};
use super::records::LoadPoint;

/// Rotation of the top platen in the shear test.
#[derive(Clone, Copy, Debug, Default, Deserialize, Serialize, PartialEq, Eq, schemars::JsonSchema)]
#[serde(rename_all = "snake_case")]
pub enum PlatenRotation {
    /// Θ = 0.
    #[default]
    Fixed,
    /// Zero moment.
    Free,
}

fn default_vertical_stress() -> f64 {
    1e6
}
fn default_preload_steps() -> usize {
    5
}

/// A virtual test.
#[derive(Clone, Debug, Deserialize, Serialize, PartialEq, schemars::JsonSchema)]
#[serde(tag = "type", rename_all = "snake_case", deny_unknown_fields)]
pub enum VirtualTest {
    /// Uniaxial compression along y.
    Compression {
        /// Final |ε_yy| [-].
        max_strain: f64,
        /// Load steps.
        steps: usize,
    },
    /// Uniaxial tension along y.
    Tension {
        /// Final ε_yy [-].
        max_strain: f64,
        /// Load steps.
        steps: usize,
    },
    /// Shear under a constant vertical compression.
    Shear {
        /// Vertical compressive stress held on the top platen [Pa].
        #[serde(default = "default_vertical_stress")]
        vertical_stress: f64,
        /// Final horizontal displacement of the top platen [m].
        max_displacement: f64,
        /// Load steps of the horizontal displacement.
        steps: usize,
        /// Steps of the vertical preload.
        #[serde(default = "default_preload_steps")]
        preload_steps: usize,
        /// Platen rotation.
        #[serde(default)]
        rotation: PlatenRotation,
    },
    /// Cycles of tension and compression along y, amplitudes increasing per cycle.
    CyclicTensionCompression {
        /// Tensile strain amplitude `ε_yy` [-] of each cycle, > 0, non-decreasing.
        amplitudes: Vec<f64>,
        /// Compressive amplitude over tensile amplitude (≥ 0; 0 = unload to zero strain only).
        #[serde(default = "one")]
        compression_ratio: f64,
        /// Load steps per half cycle (`+a → −c a`).
        steps_per_half_cycle: usize,
    },
    /// Cycles of horizontal top-platen displacement `±a_k` under a constant vertical compression.
    CyclicShear {
        /// Vertical compressive stress held on the top platen [Pa].
        #[serde(default = "default_vertical_stress")]
        vertical_stress: f64,
        /// Displacement amplitude of each cycle [m], > 0, non-decreasing.
        amplitudes: Vec<f64>,
        /// Load steps per half cycle (`+a → −a`).
        steps_per_half_cycle: usize,
        /// Steps of the vertical preload.
        #[serde(default = "default_preload_steps")]
        preload_steps: usize,
        /// Platen rotation.
        #[serde(default)]
        rotation: PlatenRotation,
    },
}

fn one() -> f64 {
    1.0
}

/// The branches of a cyclic protocol: `(target, steps)` with targets `+a_1, −c a_1, +a_2, …,
/// −c a_N, 0` (see the module documentation); zero-length branches are left out.
pub fn cyclic_protocol(amplitudes: &[f64], ratio: f64, steps_per_half_cycle: usize) -> Vec<(f64, usize)> {
    let n = steps_per_half_cycle.max(1) as f64;
    let mut out = Vec::with_capacity(2 * amplitudes.len() + 1);
    let mut at = 0.0f64;
    let mut push = |target: f64, span: f64, at: &mut f64| {
        let d = (target - *at).abs();
        if d > 0.0 {
            out.push((target, ((n * d / span) - 1e-9).ceil().max(1.0) as usize));
            *at = target;
        }
    };
    for &a in amplitudes {
        let span = (1.0 + ratio) * a;
        push(a, span, &mut at);
        push(-ratio * a, span, &mut at);
    }
    if let Some(&a) = amplitudes.last() {
        push(0.0, (1.0 + ratio) * a, &mut at);
    }
    out
}

fn check_amplitudes(amplitudes: &[f64]) -> Result<(), DemError> {
    if amplitudes.is_empty() {
        return Err(DemError::InvalidParameter {
            field: "amplitudes",
            value: "[]".into(),
            expected: "at least one amplitude",
        });
    }
    for (k, &a) in amplitudes.iter().enumerate() {
        positive("amplitudes", a)?;
        if k > 0 && a < amplitudes[k - 1] {
            return Err(DemError::InvalidParameter {
                field: "amplitudes",
                value: format!("{a} after {}", amplitudes[k - 1]),
                expected: "amplitudes that do not decrease from one cycle to the next",
            });
        }
    }
    Ok(())
}

impl VirtualTest {
    /// Checks the parameters.
    pub fn validate(&self) -> Result<(), DemError> {
        let steps = |s: usize| {
            if s == 0 {
                Err(DemError::InvalidParameter { field: "steps", value: "0".into(), expected: "at least 1" })
            } else {
                Ok(())
            }
        };
        let half_cycle_steps = |s: usize| {
            if s == 0 {
                Err(DemError::InvalidParameter {
                    field: "steps_per_half_cycle",
                    value: "0".into(),
                    expected: "at least 1",
                })
            } else {
                Ok(())
            }
        };
        match *self {
            VirtualTest::Compression { max_strain, steps: s } | VirtualTest::Tension { max_strain, steps: s } => {
                positive("max_strain", max_strain)?;
                steps(s)
            }
            VirtualTest::Shear { vertical_stress, max_displacement, steps: s, preload_steps, .. } => {
                non_negative("vertical_stress", vertical_stress)?;
                positive("max_displacement", max_displacement)?;
                steps(s)?;
                steps(preload_steps)
            }
            VirtualTest::CyclicTensionCompression { ref amplitudes, compression_ratio, steps_per_half_cycle } => {
                check_amplitudes(amplitudes)?;
                non_negative("compression_ratio", compression_ratio)?;
                half_cycle_steps(steps_per_half_cycle)
            }
            VirtualTest::CyclicShear {
                vertical_stress, ref amplitudes, steps_per_half_cycle, preload_steps, ..
            } => {
                non_negative("vertical_stress", vertical_stress)?;
                check_amplitudes(amplitudes)?;
                half_cycle_steps(steps_per_half_cycle)?;
                steps(preload_steps)
            }
        }
    }

    /// Whether the test cycles (several loading and unloading branches).
    pub fn is_cyclic(&self) -> bool {
        matches!(self, VirtualTest::CyclicTensionCompression { .. } | VirtualTest::CyclicShear { .. })
    }

    /// Whether the driven DOF is the top platen's horizontal displacement (shear tests).
    pub fn is_shear(&self) -> bool {
        matches!(self, VirtualTest::Shear { .. } | VirtualTest::CyclicShear { .. })
    }
}

/// One load stage of a test's protocol.
pub(super) struct Stage {
    /// The load at the stage's end.
    pub(super) target: LoadPoint,
    /// Its load steps.
    pub(super) steps: usize,
    /// Monotonic tests: `run_stage` watches the driven force for loss of load.
    pub(super) monitor: bool,
    /// Cyclic branches: the direction (±1) of the amplitude the branch ends at; `None` for a
    /// preload, a monotonic stage or the final return to zero.
    pub(super) towards: Option<f64>,
}

/// The platen controls, the driven top DOF (0 = U_x, 1 = U_y), the stages and the first stage
/// whose force is the test's driven force.
pub(super) fn protocol(test: &VirtualTest, w: f64, h: f64, tz: f64) -> ([DofControl; 3], usize, Vec<Stage>, usize) {
    use DofControl::{Force, Prescribed};
    let fixed = [Prescribed; 3];
    let axial = |value: f64| LoadPoint { prescribed: vec![0.0, 0.0, 0.0, 0.0, value * h, 0.0], forces: vec![] };
    // Shear: the top platen holds the vertical force; U_x (and Θ when fixed) prescribed.
    let shear_setup = |vertical_stress: f64, rotation: PlatenRotation| {
        let fy = -vertical_stress * w * tz;
        let (ctl, forces) = match rotation {
            PlatenRotation::Fixed => ([Prescribed, Force, Prescribed], vec![fy]),
            PlatenRotation::Free => ([Prescribed, Force, Force], vec![fy, 0.0]),
        };
        let n_p = if rotation == PlatenRotation::Fixed { 5 } else { 4 };
        let at = move |ux: f64| {
            let mut p = vec![0.0; n_p];
            p[3] = ux;
            LoadPoint { prescribed: p, forces: forces.clone() }
        };
        (ctl, at)
    };
    let cyclic = |amplitudes: &[f64], ratio: f64, n: usize, point: &dyn Fn(f64) -> LoadPoint| -> Vec<Stage> {
        cyclic_protocol(amplitudes, ratio, n)
            .into_iter()
            .map(|(target, steps)| Stage {
                target: point(target),
                steps,
                monitor: false,
                towards: (target != 0.0).then(|| target.signum()),
            })
            .collect()
    };
    match *test {
        VirtualTest::Compression { max_strain, steps } | VirtualTest::Tension { max_strain, steps } => {
            let sign = if matches!(test, VirtualTest::Compression { .. }) { -1.0 } else { 1.0 };
            (fixed, 1, vec![Stage { target: axial(sign * max_strain), steps, monitor: true, towards: None }], 0)
        }
        VirtualTest::Shear { vertical_stress, max_displacement, steps, preload_steps, rotation } => {
            let (ctl, at) = shear_setup(vertical_stress, rotation);
            let stages = vec![
                Stage { target: at(0.0), steps: preload_steps, monitor: false, towards: None },
                Stage { target: at(max_displacement), steps, monitor: true, towards: None },
            ];
            (ctl, 0, stages, 1)
        }
        VirtualTest::CyclicTensionCompression { ref amplitudes, compression_ratio, steps_per_half_cycle } => {
            (fixed, 1, cyclic(amplitudes, compression_ratio, steps_per_half_cycle, &axial), 0)
        }
        VirtualTest::CyclicShear { vertical_stress, ref amplitudes, steps_per_half_cycle, preload_steps, rotation } => {
            let (ctl, at) = shear_setup(vertical_stress, rotation);
            let mut stages = vec![Stage { target: at(0.0), steps: preload_steps, monitor: false, towards: None }];
            stages.extend(cyclic(amplitudes, 1.0, steps_per_half_cycle, &at));
            (ctl, 0, stages, 1)
        }
    }
}
