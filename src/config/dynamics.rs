//! `[dynamics]`: the settings of a seismic time-history analysis (`[analysis] type =
//! "time_history"`): gravity first (a static step), then the base acceleration integrated implicitly.
//!
//! ```toml
//! [analysis]
//! type = "time_history"
//! [dynamics]
//! duration = 22.0                 # [s] analysed time after gravity
//! dt = 0.01                       # [s] time step (the records are interpolated linearly)
//! scheme = "newmark"              # or "hht"
//! beta = 0.25                     # Newmark β (default 1/4: average acceleration)
//! gamma = 0.5                     # Newmark γ (default 1/2)
//! # alpha = -0.05                 # HHT α in [-1/3, 0] (scheme = "hht"; then β, γ follow from α)
//! mass = "consistent"             # or "lumped"
//! newton = "modified"             # tangent | modified | initial | krylov
//! integration = "implicit"        # or "implex": the damage extrapolated (see IntegrationKind)
//! # implex_split = "current"      # implex: the split at the step's strain, or "frozen"
//! # implex_corrections = 2        # implex: equilibria re-solved at the implicitly updated damage
//! # implex_correction_tolerance = 1e-2  # implex: a pass changing no damage by more ends them
//! # implex_pass_tolerance = 1e-3        # implex: force tolerance of the passes before the last
//! krylov_dimension = 3            # newton = "krylov": subspace size before a tangent refresh
//! refresh_cost = 8                # newton = "krylov": extra iterations that pay for a fresh
//!                                 # tangent at a step's start (0: at every step)
//! max_iterations = 20
//! force_tolerance = 1e-6          # ‖r‖ ≤ tol · max(‖M ι a_g‖, ‖f_grav‖, ‖f_int‖)
//! max_substeps = 4                # halvings of a failing step
//! max_damage_increment = 0.1      # [-] largest d_t or d_c increment of a point in one substep
//!                                 # (1.0, the default: no control; DEFAULT_MAX_DAMAGE_INCREMENT)
//! damage_relaxation_time = 0.01   # [s] viscous (Duvaut-Lions) damage in the time history
//!                                 # (default none: rate independent)
//! output_every = 5                # steps between results (XDMF), CSV rows every step
//! gravity_steps = 1               # load steps of the static gravity phase
//! convergence = "church-convergence.json"  # a convergence study's band (scripts/convergence.py):
//!                                 # the damage shares are reported with it (config::convergence)
//! [dynamics.damping]              # Rayleigh C = α M + β K₀
//! frequencies = [1.0, 10.0]       # [Hz] two frequencies with the same ratio ...
//! ratio = 0.05
//! # alpha = 0.3  beta = 1e-3      # ... or the coefficients themselves
//! [[dynamics.ground_motion]]      # up to three, one per direction
//! direction = "x"
//! file = "records/vallorcine-like-synthetic.txt"
//! format = "two_column"
//! units = "m/s2"
//! scale = 1.0
//! [dynamics.checkpoint]
//! every_steps = 200
//! every_minutes = 10.0
//! [[dynamics.monitor]]
//! name = "top"
//! node = 123                      # a Gmsh node tag, or:
//! # group = "top"  near = [0, 0, 90]   # the group's node nearest to a point
//! [[dynamics.drift]]              # a storey drift (drift.rs)
//! name = "ground-floor"
//! levels = [0.0, 3.5]             # [m], or groups = ["base", "floor-1"]
//! [[dynamics.stop_when]]          # end the run once every such share is reached
//! group = "nave_vault"            # a substructure (a part's group of shells)
//! share = 0.5                     # of its area with d_t > 0.5, in (0, 1]
//! ```
use super::source::{Seg, Source};
use super::{ConfigError, RecordConfig, RecordFormat};
use crate::seismic::Record;
use serde::Deserialize;
use std::path::{Path, PathBuf};

/// `[[dynamics.stop_when]]`: a substructure's damage share that, with the others, ends the run.
#[derive(Clone, Debug, Deserialize, PartialEq, schemars::JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct StopWhenConfig {
    /// The substructure: a part's physical group of shells.
    pub group: String,
    /// The share of its area with d_t > 0.5 (the damage shares' measure), in (0, 1].
    pub share: f64,
}

/// Time-integration scheme.
#[derive(Clone, Copy, Debug, Default, Deserialize, PartialEq, Eq, schemars::JsonSchema)]
#[serde(rename_all = "snake_case")]
pub enum SchemeName {
    /// Newmark's family (β, γ).
    #[default]
    Newmark,
    /// Hilber–Hughes–Taylor α.
    Hht,
}

/// Newton-type iteration within a step.
#[derive(Clone, Copy, Debug, Default, Deserialize, PartialEq, Eq, schemars::JsonSchema)]
#[serde(rename_all = "snake_case")]
pub enum NewtonKind {
    /// Full Newton: the tangent is reassembled and factored at every iteration.
    Tangent,
    /// Modified Newton: the tangent of the step's start, factored once per step.
    #[default]
    Modified,
    /// Initial stiffness: the initial tangent, factored once for the whole run (refactored only
    /// when the step size changes).
    Initial,
    /// Modified Newton with Krylov subspace acceleration (Carlson & Miller; OpenSees
    /// `KrylovNewton`): the tangent of the step's start, the corrections accelerated over the
    /// last `krylov_dimension` iterations, the tangent refreshed when that subspace is full.
    Krylov,
}

/// How a step integrates the damage law ([`DynamicsConfig::integration`]).
///
/// * `implicit`: each step's damage is the law's at the step's end strain; Newton follows the
///   softening inside the step, and a step it cannot follow is halved.
/// * `implex` (Oliver, Huespe and Cante, CMAME 197 (2008) 1865–1889; OpenSees' ASDConcrete3D
///   `-implex`): each integration point's damage history is extrapolated from its last two
///   committed steps, κ̃_{n+1} = κ_n + (Δt_{n+1}/Δt_n)(κ_n − κ_{n−1}), and the step is solved
///   with the damage d(κ̃) held fixed: its equilibrium has no softening branch. The unilateral
///   split is taken where `implex_split` says: at the step's strain (`current`, the default;
///   piecewise linear, a few Newton iterations where cracks open or close) or frozen at the
///   committed strain (`frozen`; the stress is the secant S(ε_n; d̃) times the strain, one
///   linear system, but a crack seen closing one step late creates energy). The converged
///   strain then updates the histories implicitly, κ_{n+1} = max(κ_n, ε_eq), for the committed
///   state, the output and the next extrapolation. The error is of first order in the step
///   size (`material::implex`). With `implex_corrections = K`, the step's equilibrium is then
///   solved K more times with the damage held at the implicit update of the last one: a
///   staggered iteration whose fixed point is the implicit step, with no decision that
///   round-off could flip (`analysis::time_history::stepper`, "IMPL-EX corrections").
///   Measured on the church against the implicit reference, with the choice made from it:
///   docs/convergence-implex.md.
///
/// With `implex`, `newton` chooses how the step's system is solved: `modified` and `tangent`
/// form and factor its matrix at the step's start (with the split frozen, one iteration then
/// ends the step), `krylov` keeps a factored matrix across steps while the refresh policy finds
/// it cheaper and accelerates the corrections on it. `initial` is refused: the undamaged
/// stiffness never sees the extrapolated damage, so the step converges at a linear rate that
/// degrades as the structure cracks. `max_substeps` keeps its meaning; `max_damage_increment`
/// measures the damage increment of a substep's implicit update, but a point crossing its
/// threshold jumps in damage whatever the step, so under strong shaking the control cuts steps
/// into many substeps (docs/convergence-implex.md). `damage_relaxation_time` is refused.
#[derive(Clone, Copy, Debug, Default, Deserialize, PartialEq, Eq, schemars::JsonSchema)]
#[serde(rename_all = "snake_case")]
pub enum IntegrationKind {
    /// The damage law at the step's end strain, Newton through the softening.
    #[default]
    Implicit,
    /// IMPL-EX: the step solved with the extrapolated damage, the histories updated after.
    Implex,
}

impl IntegrationKind {
    /// The job-file name of the variant.
    pub fn name(&self) -> &'static str {
        match self {
            IntegrationKind::Implicit => "implicit",
            IntegrationKind::Implex => "implex",
        }
    }
}

/// Ground-motion direction.
#[derive(Clone, Copy, Debug, Deserialize, PartialEq, Eq, schemars::JsonSchema)]
#[serde(rename_all = "snake_case")]
pub enum Direction {
    /// Global X.
    X,
    /// Global Y.
    Y,
    /// Global Z.
    Z,
}

impl Direction {
    /// 0, 1 or 2.
    pub fn index(self) -> usize {
        self as usize
    }
}

/// `[dynamics.damping]`: Rayleigh damping `C = α M + β K₀` (K₀ the initial stiffness).
#[derive(Clone, Debug, Default, Deserialize, PartialEq, schemars::JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct DampingConfig {
    /// Two frequencies [Hz] at which the damping ratio is `ratio`.
    pub frequencies: Option<[f64; 2]>,
    /// Damping ratio at those frequencies.
    pub ratio: Option<f64>,
    /// Mass-proportional coefficient α [1/s].
    pub alpha: Option<f64>,
    /// Stiffness-proportional coefficient β [s].
    pub beta: Option<f64>,
}

/// `[[dynamics.ground_motion]]`: one component of the base acceleration.
#[derive(Clone, Debug, Deserialize, PartialEq, schemars::JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct GroundMotionConfig {
    /// Direction of the component.
    pub direction: Direction,
    /// A record file (relative to the job file's folder).
    pub file: Option<PathBuf>,
    /// Its format.
    pub format: Option<RecordFormat>,
    /// Units of a column file: `g`, `m/s2`, `cm/s2`.
    pub units: Option<String>,
    /// Time step of a one-column file [s].
    pub dt: Option<f64>,
    /// A built-in synthetic record instead of a file: `"vallorcine_like"`.
    pub synthetic: Option<String>,
    /// Scale factor (default 1).
    #[serde(default = "one")]
    pub scale: f64,
    /// The record, read and scaled at load (m/s²).
    #[serde(skip)]
    pub record: Option<Record>,
}

/// `[dynamics.checkpoint]`: when to write the restart state.
#[derive(Clone, Debug, Default, Deserialize, PartialEq, schemars::JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct CheckpointConfig {
    /// Every this many steps (0 = never by count).
    #[serde(default)]
    pub every_steps: usize,
    /// Every this many minutes of wall time (0 = never by time).
    #[serde(default)]
    pub every_minutes: f64,
}

/// `[[dynamics.monitor]]`: a node whose history goes to `monitors.csv` and a PNG.
#[derive(Clone, Debug, Deserialize, PartialEq, schemars::JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct MonitorConfig {
    /// Name in the CSV header and the picture's file name.
    pub name: String,
    /// A Gmsh node tag.
    pub node: Option<u64>,
    /// A physical group, with `near`: its node nearest to that point.
    pub group: Option<String>,
    /// Point [m] (with `group`).
    pub near: Option<[f64; 3]>,
}

/// `[dynamics]`.
#[derive(Clone, Debug, Deserialize, PartialEq, schemars::JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct DynamicsConfig {
    /// Analysed time [s] (after gravity).
    pub duration: f64,
    /// Time step [s].
    pub dt: f64,
    /// Scheme.
    #[serde(default)]
    pub scheme: SchemeName,
    /// Newmark β (default 1/4; with `hht`, (1 − α)²/4).
    pub beta: Option<f64>,
    /// Newmark γ (default 1/2; with `hht`, 1/2 − α).
    pub gamma: Option<f64>,
    /// HHT α ∈ [−1/3, 0] (default −0.05 with `hht`).
    pub alpha: Option<f64>,
    /// Mass matrix.
    #[serde(default = "consistent")]
    pub mass: crate::element::MassKind,
    /// Newton variant.
    #[serde(default)]
    pub newton: NewtonKind,
    /// How a step integrates the damage law (default `implicit`; [`IntegrationKind`]).
    #[serde(default)]
    pub integration: IntegrationKind,
    /// With `integration = "implex"`: where the unilateral split of a step's stress is taken,
    /// `current` (the default) or `frozen` (`material::implex::SplitAt`; [`IntegrationKind`]).
    pub implex_split: Option<crate::material::implex::SplitAt>,
    /// With `integration = "implex"`: how many times a step's equilibrium is solved again with
    /// the damage held at the implicit update of the last one, a staggered correction of the
    /// extrapolation (`analysis::time_history::stepper`, "IMPL-EX corrections"). 0 to 10;
    /// default 0 (IMPL-EX as published).
    #[serde(default)]
    pub implex_corrections: usize,
    /// With `implex_corrections`: a pass whose held damage changes by at most this at every
    /// point (max |Δd_t|, |Δd_c|) ends the corrections, 0 to 1 (default 0.01,
    /// [`DEFAULT_IMPLEX_CORRECTION_TOLERANCE`]; 0 keeps every pass that changes any damage).
    #[serde(default = "implex_correction_tolerance")]
    pub implex_correction_tolerance: f64,
    /// With `implex_corrections`: the relative force tolerance of the passes before the last,
    /// whose equilibria only decide the damage held for the next; the step's last equilibrium
    /// is solved to `force_tolerance` (`analysis::time_history::stepper`, "IMPL-EX
    /// corrections"). In (0, 1); default: `force_tolerance` (every pass to it).
    pub implex_pass_tolerance: Option<f64>,
    /// With `newton = "krylov"`: corrections kept in the acceleration subspace before the
    /// tangent is refreshed (default 3, as OpenSees).
    #[serde(default = "three")]
    pub krylov_dimension: usize,
    /// With `newton = "krylov"`: the extra iterations a kept tangent may cost before a step
    /// starts on a fresh one (default 8: an assembly and a factorization cost about 8 iterations
    /// on the church; 0 forms it at every step's start, as OpenSees).
    #[serde(default = "eight")]
    pub refresh_cost: usize,
    /// Newton iterations per (sub)step (default 20).
    #[serde(default = "twenty")]
    pub max_iterations: usize,
    /// A secant line search along each Newton correction of the time history
    /// (`analysis::line_search`: η with Δu · r(u + η Δu) ≈ 0; `analysis::time_history::stepper`).
    /// It costs nothing where the full correction already reduces that projection, and one or
    /// more residuals where the residual is kinked (a point crossing its damage threshold).
    /// Default false: on the church under strong shaking it did not reduce the failed steps
    /// (docs/convergence-implicit.md).
    #[serde(default)]
    pub line_search: bool,
    /// Relative force tolerance (default 1e-6).
    #[serde(default = "tol")]
    pub force_tolerance: f64,
    /// Halvings of a failing step (default 4).
    #[serde(default = "four")]
    pub max_substeps: usize,
    /// The largest increment of tensile or compressive damage [-] that any integration point may
    /// take in one substep: a converged substep over it is taken again as two halves, down to
    /// `dt / 2^max_substeps` (`analysis::time_history::stepper`). In (0, 1]; 1.0 switches the
    /// control off (every step starts at `dt` and is halved only when Newton fails). Default
    /// [`DEFAULT_MAX_DAMAGE_INCREMENT`].
    #[serde(default = "default_max_damage_increment")]
    pub max_damage_increment: f64,
    /// Relaxation time τ [s] of viscous (Duvaut–Lions) damage during the time history
    /// (`material::state`): the damage histories relax towards the rate-independent value over
    /// τ, which keeps the softening response unique (Needleman 1988) at the price of a
    /// rate effect of order E τ ε̇ on the stress. None (the default): rate independent. The
    /// gravity phase stays rate independent.
    pub damage_relaxation_time: Option<f64>,
    /// Results every this many steps (default 1).
    #[serde(default = "one_usize")]
    pub output_every: usize,
    /// Load steps of the gravity phase (default 1; ignored without `[gravity]`).
    #[serde(default = "one_usize")]
    pub gravity_steps: usize,
    /// Rayleigh damping (default none).
    #[serde(default)]
    pub damping: DampingConfig,
    /// Base acceleration components.
    #[serde(default)]
    pub ground_motion: Vec<GroundMotionConfig>,
    /// Checkpoints.
    #[serde(default)]
    pub checkpoint: CheckpointConfig,
    /// Monitored nodes.
    #[serde(default)]
    pub monitor: Vec<MonitorConfig>,
    /// Storey drifts between two levels (`drift.rs`).
    #[serde(default)]
    pub drift: Vec<super::drift::DriftConfig>,
    /// Damage shares that end the run once every one is reached (checked at the output steps,
    /// where the cell damage is read; `analysis::time_history::damage_shares`). Empty (the
    /// default): the run ends at `duration`.
    #[serde(default)]
    pub stop_when: Vec<StopWhenConfig>,
    /// A convergence study's band file (`scripts/convergence.py`'s `band.json`), relative to the
    /// job file: the damage shares are reported with its band where its settings are this job's
    /// (`config::convergence`).
    pub convergence: Option<PathBuf>,
    /// That file, read at load.
    #[serde(skip)]
    pub convergence_band: Option<super::convergence::ConvergenceBand>,
}

/// The default of `[dynamics] max_damage_increment`: 1.0, the control off. On the church's main
/// job (jobs/church.toml, the paper's split) a limit of 0.1 doubled the stepping time (8,927
/// iterations and 503 factorizations against 4,813 and 221; 158 cuts down to dt/256) and moved
/// the shares of d_t > 0.5 by at most 1.3 points (the nave vault's crown part, 15.4 → 16.7 %;
/// the other parts within 0.1). The implicit law's convergence study of the main job
/// (`scripts/convergence.py`, docs/convergence-implicit.md) keeps it off: without it the shares
/// at dt/2 and dt/4 agree within 0.11 point at the code level and 1.4 points at 1.5 times it
/// (the 2-point band), while the error of the job's own dt (up to 5.6 points at 1.5 times the
/// code level) travels with the numbers as their band. 0.1 follows a point's softening branch
/// in about ten substeps.
pub const DEFAULT_MAX_DAMAGE_INCREMENT: f64 = 1.0;

/// The change of held damage that ends a step's IMPL-EX corrections
/// (`analysis::time_history::stepper`, "IMPL-EX corrections"). Each pass divides the step's
/// difference from the implicit step by 10 to 40 on the damage bar (`implex_tests.rs`: at 0.01
/// it ends 7.7e-1 → 2.1e-2 of the peak displacement, 5.1e-2 → 3.7e-4 in d_t, from the implicit
/// run, with 3 passes in the place of 48). On the church at the code level it changes no share
/// at its printed digits and takes 3,757 iterations (0: 4,044). Measured with the whole study:
/// docs/convergence-implex.md, "Corrections".
pub const DEFAULT_IMPLEX_CORRECTION_TOLERANCE: f64 = 1e-2;

fn default_max_damage_increment() -> f64 {
    DEFAULT_MAX_DAMAGE_INCREMENT
}
fn one() -> f64 {
    1.0
}
fn one_usize() -> usize {
    1
}
fn three() -> usize {
    3
}
fn eight() -> usize {
    8
}
fn twenty() -> usize {
    20
}
fn four() -> usize {
    4
}
fn tol() -> f64 {
    1e-6
}
fn implex_correction_tolerance() -> f64 {
    DEFAULT_IMPLEX_CORRECTION_TOLERANCE
}
fn consistent() -> crate::element::MassKind {
    crate::element::MassKind::Consistent
}

/// `[[dynamics.stop_when]]`: each names a part's group, its share in (0, 1].
pub fn check_stop_when(src: &Source, rules: &[StopWhenConfig], parts: &[super::PartConfig]) -> Result<(), ConfigError> {
    for (i, r) in rules.iter().enumerate() {
        let at = |k: &str| [Seg::key("dynamics"), Seg::key("stop_when"), Seg::Index(i), Seg::key(k)];
        if !parts.iter().any(|p| p.group == r.group) {
            let names: Vec<&str> = parts.iter().map(|p| p.group.as_str()).collect();
            return Err(src.error_at(
                &at("group"),
                format!("group '{}' is not one of the job's parts ({})", r.group, names.join(", ")),
            ));
        }
        if !(r.share.is_finite() && r.share > 0.0 && r.share <= 1.0) {
            return Err(src.error_at(&at("share"), format!("expected a share of the area in (0, 1], got {}", r.share)));
        }
    }
    Ok(())
}

/// Newmark parameters after defaults: (β, γ, α_HHT).
pub fn scheme_parameters(d: &DynamicsConfig) -> (f64, f64, f64) {
    match d.scheme {
        SchemeName::Newmark => (d.beta.unwrap_or(0.25), d.gamma.unwrap_or(0.5), 0.0),
        SchemeName::Hht => {
            let a = d.alpha.unwrap_or(-0.05);
            (d.beta.unwrap_or((1.0 - a) * (1.0 - a) / 4.0), d.gamma.unwrap_or(0.5 - a), a)
        }
    }
}

/// Checks `[dynamics]` and reads its records (paths relative to `folder`). Errors name the key.
pub fn load_dynamics(src: &Source, folder: &Path, d: &mut DynamicsConfig) -> Result<(), ConfigError> {
    checks::check_time_and_scheme(src, d)?;
    checks::check_iterations_and_output(src, d)?;
    checks::check_damping(src, &d.damping)?;
    read_ground_motions(src, folder, d)?;
    check_monitors(src, &d.monitor)?;
    super::drift::check_drifts(src, &d.drift)?;
    if let Some(tau) = d.damage_relaxation_time {
        src.positive_finite(&Seg::path(&["dynamics", "damage_relaxation_time"]), tau, "damage relaxation time", "s")?;
        if d.integration == IntegrationKind::Implex {
            return Err(src.error_at(
                &Seg::path(&["dynamics", "damage_relaxation_time"]),
                "viscous damage applies to integration = \"implicit\" only (IMPL-EX extrapolates the rate-independent law)",
            ));
        }
    }
    if let Some(p) = &d.convergence {
        let file = super::resolve(folder, p);
        let band = super::convergence::ConvergenceBand::read(&file)
            .map_err(|e| src.error_at(&Seg::path(&["dynamics", "convergence"]), e.to_string()))?;
        d.convergence = Some(file);
        d.convergence_band = Some(band);
    }
    let every = d.checkpoint.every_minutes;
    src.non_negative(&Seg::path(&["dynamics", "checkpoint", "every_minutes"]), every, "checkpoint interval", "min")?;
    Ok(())
}

/// `[[dynamics.ground_motion]]`: one to three components in distinct directions, each record
/// read, scaled and long enough for the duration, kept in its `record`.
fn read_ground_motions(src: &Source, folder: &Path, d: &mut DynamicsConfig) -> Result<(), ConfigError> {
    if d.ground_motion.is_empty() {
        return Err(
            src.error_at(&[Seg::key("dynamics")], "a time history needs at least one [[dynamics.ground_motion]]")
        );
    }
    if d.ground_motion.len() > 3 {
        return Err(src.error_at(
            &[Seg::key("dynamics"), Seg::key("ground_motion"), Seg::Index(3)],
            "at most three components (x, y, z)",
        ));
    }
    let duration = d.duration;
    for i in 0..d.ground_motion.len() {
        let at = |k: &str| vec![Seg::key("dynamics"), Seg::key("ground_motion"), Seg::Index(i), Seg::key(k)];
        let dir = d.ground_motion[i].direction;
        if d.ground_motion[..i].iter().any(|g| g.direction == dir) {
            return Err(src.error_at(&at("direction"), format!("direction {dir:?} is given twice")));
        }
        let record = read_component(src, folder, &d.ground_motion[i], &at)?;
        record
            .require_duration(duration)
            .map_err(|e| src.error_at(&at("file"), format!("{e} (dynamics.duration = {duration} s)")))?;
        d.ground_motion[i].record = Some(record);
    }
    Ok(())
}

/// `[[dynamics.monitor]]`: distinct names fit for a CSV header and a file name; a node, or a
/// group with a point.
fn check_monitors(src: &Source, monitors: &[MonitorConfig]) -> Result<(), ConfigError> {
    for (i, m) in monitors.iter().enumerate() {
        let at = |k: &str| vec![Seg::key("dynamics"), Seg::key("monitor"), Seg::Index(i), Seg::key(k)];
        if m.name.is_empty() || m.name.contains([',', '/', '\\', '"']) {
            return Err(src.error_at(&at("name"), "expected a non-empty name without , / \\ or quotes"));
        }
        if monitors[..i].iter().any(|o| o.name == m.name) {
            return Err(src.error_at(&at("name"), format!("monitor '{}' is given twice", m.name)));
        }
        match (m.node, &m.group, m.near) {
            (Some(_), None, None) | (None, Some(_), Some(_)) => {}
            _ => {
                return Err(src.error_at(
                    &[Seg::key("dynamics"), Seg::key("monitor"), Seg::Index(i)],
                    "give node = <Gmsh tag>, or group with near = [x, y, z]",
                ))
            }
        }
    }
    Ok(())
}

/// Reads one component's record (file or synthetic), scaled.
fn read_component(
    src: &Source,
    folder: &Path,
    g: &GroundMotionConfig,
    at: &dyn Fn(&str) -> Vec<Seg>,
) -> Result<Record, ConfigError> {
    let r = RecordConfig {
        file: g.file.clone(),
        format: g.format,
        units: g.units.clone(),
        dt: g.dt,
        synthetic: g.synthetic.clone(),
        scale: g.scale,
    };
    super::record::read_record(src, folder, &r, at)
}

#[path = "dynamics_checks.rs"]
mod checks;

#[cfg(test)]
#[path = "dynamics_tests.rs"]
mod tests;
