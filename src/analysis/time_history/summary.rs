//! What a time history reports in `summary.json` ([`TimeHistorySummary`]): sizes, settings,
//! iterations, timings, the run's energies, peaks and damage; arrays of distinct quantities are
//! written with their names (`crate::io::summary`).
use super::damage_shares::GroupDamage;
use super::stepper::StepReport;

crate::io::summary::named!(
    /// Newmark β, γ and HHT α.
    scheme_names: ["beta", "gamma", "alpha"]
);
crate::io::summary::named!(
    /// Rayleigh α [1/s] and β [s].
    rayleigh_names: ["alpha", "beta"]
);
crate::io::summary::named!(
    /// The final energies, as the columns of `energy.csv`.
    energy_names: ["input", "kinetic", "strain", "damping", "dissipated_damage", "unilateral"]
);
crate::io::summary::named!(
    /// The horizontal directions.
    horizontal: ["x", "y"]
);
crate::io::summary::named!(
    /// A drift's levels.
    lower_upper: ["lower", "upper"]
);

/// One storey drift's peaks.
#[derive(Debug, Clone, Default, serde::Serialize)]
pub struct DriftPeak {
    /// Its name.
    pub name: String,
    /// The mean z of the lower and the upper level's nodes (`lower`, `upper`) [m].
    #[serde(with = "lower_upper")]
    pub levels: [f64; 2],
    /// Their nodes.
    #[serde(with = "lower_upper")]
    pub nodes: [usize; 2],
    /// The largest |drift| along x and y over the steps (`x`, `y`).
    #[serde(with = "horizontal")]
    pub peak: [f64; 2],
    /// The time of each [s].
    #[serde(with = "horizontal")]
    pub peak_time: [f64; 2],
}

crate::io::summary::named!(
    /// The run's phases.
    seconds_names: ["setup", "gravity", "stepping", "output", "checkpoints"]
);

/// What a time-history run reports (`summary.json`).
#[derive(Debug, Clone, Default, serde::Serialize)]
pub struct TimeHistorySummary {
    /// Ranks.
    pub ranks: usize,
    /// Equations (6 per node).
    pub equations: usize,
    /// Elements.
    pub elements: usize,
    /// Whether every element is linear.
    pub linear: bool,
    /// Scheme: Newmark β, γ and HHT α (`beta`, `gamma`, `alpha`).
    #[serde(with = "scheme_names")]
    pub scheme: [f64; 3],
    /// Rayleigh damping C = α M + β K₀: `alpha` [1/s], `beta` [s].
    #[serde(with = "rayleigh_names")]
    pub rayleigh: [f64; 2],
    /// Newton variant.
    pub newton: String,
    /// Whether each correction was followed by a line search (`[dynamics] line_search`).
    pub line_search: bool,
    /// How the steps integrate the damage law: `implicit` or `implex` (`stepper.rs`).
    pub integration: String,
    /// With IMPL-EX, where the split of a step's stress is taken: `current` or `frozen`.
    pub implex_split: Option<String>,
    /// With IMPL-EX, the step's equilibria solved again at the implicitly updated damage
    /// (`[dynamics] implex_corrections`).
    pub implex_corrections: usize,
    /// With IMPL-EX corrections, the change of held damage that ends them
    /// (`[dynamics] implex_correction_tolerance`).
    pub implex_correction_tolerance: f64,
    /// `[dynamics] implex_pass_tolerance` (None: every pass to the force tolerance).
    pub implex_pass_tolerance: Option<f64>,
    /// IMPL-EX correction passes made (each an equilibrium solved again; `stepper.rs`).
    pub implex_passes: usize,
    /// Linear solver.
    pub solver: String,
    /// Time step [s].
    pub dt: f64,
    /// Steps of the whole history.
    pub steps: usize,
    /// Step the run started from (0, or the checkpoint's on a restart).
    pub first_step: usize,
    /// Time reached [s].
    pub time: f64,
    /// Newton iterations (solves) in this run.
    pub iterations: usize,
    /// Steps that needed substeps.
    pub substepped_steps: usize,
    /// Newton iterations of the attempts that failed and were halved (not in `iterations`).
    pub failed_iterations: usize,
    /// The damage control's limit on a substep's damage increment (`[dynamics]
    /// max_damage_increment`; 1: off).
    pub max_damage_increment: f64,
    /// Steps with at least one substep cut by the damage control.
    pub damage_cut_steps: usize,
    /// Substeps cut by the damage control (taken again as two halves).
    pub damage_cuts: usize,
    /// Newton iterations of the cut substeps (not in `iterations`).
    pub damage_cut_iterations: usize,
    /// Substeps accepted at the smallest size with a damage increment over the limit.
    pub over_limit_substeps: usize,
    /// The smallest substep accepted [s].
    pub smallest_substep: f64,
    /// The largest damage increment of an accepted substep (0 with the control off).
    pub max_step_damage_increment: f64,
    /// Jacobian factorizations (operator changes).
    pub factorizations: usize,
    /// Krylov–Newton: steps that started on the tangent kept from an earlier step, and steps
    /// that started on a fresh one (`refresh.rs`).
    pub tangents_kept: usize,
    /// See `tangents_kept`.
    pub tangents_fresh: usize,
    /// Output steps written.
    pub output_steps: usize,
    /// Checkpoints written.
    pub checkpoints: usize,
    /// Final energies [J]: `input`, `kinetic`, `strain`, `damping`, `dissipated_damage` (the
    /// law's), `unilateral` (exchanged at unilateral switches), as the columns of `energy.csv`
    /// (`energy.rs`).
    #[serde(with = "energy_names")]
    pub energy: [f64; 6],
    /// Largest relative energy-balance error over the steps.
    pub max_balance_error: f64,
    /// Peak relative displacement over nodes and time, `x` `y` `z` [m].
    #[serde(with = "crate::io::summary::xyz")]
    pub peak_displacement: [f64; 3],
    /// Peak drift ratio: the largest √(u_x² + u_y²)/(z − z_base) over nodes and time, z_base the
    /// model's lowest z (`envelope.rs`).
    pub peak_drift_ratio: f64,
    /// The model's mass (`x`, `y`, `z`) [kg]: every element and point mass, support nodes included.
    #[serde(with = "crate::io::summary::xyz")]
    pub model_mass: [f64; 3],
    /// The resultant of its weight under `[gravity]` (`x`, `y`, `z`) [N].
    #[serde(with = "crate::io::summary::xyz")]
    pub weight: [f64; 3],
    /// The peak base shear, max |reaction_x| and max |reaction_y| over the steps (`x`, `y`) [N]
    /// (`base_shear.rs`; the history is in `monitors.csv`).
    #[serde(with = "horizontal")]
    pub peak_base_shear: [f64; 2],
    /// The time of each [s].
    #[serde(with = "horizontal")]
    pub peak_base_shear_time: [f64; 2],
    /// Per `[[dynamics.drift]]`: its levels and peak storey drift (`drift.rs`).
    pub drifts: Vec<DriftPeak>,
    /// Largest tensile and compressive damage (`d_t`, `d_c`).
    #[serde(with = "crate::io::summary::damage")]
    pub max_damage: [f64; 2],
    /// Seconds: `setup`, `gravity`, `stepping`, `output`, `checkpoints`.
    #[serde(with = "seconds_names")]
    pub seconds: [f64; 5],
    /// Stepping seconds per step.
    pub seconds_per_step: f64,
    /// Where the stepping's time goes in the system, per rank 0 [s]: Jacobian assembly
    /// (`assemble`), numeric factorization with its first solve (`factorize`), the other solves
    /// (`solve`), the elements' state updates and force assembly (`internal_force`).
    pub system_seconds: std::collections::BTreeMap<String, f64>,
    /// Results file of this run.
    pub results: String,
    /// Per group of shell parts: area shares with peak damage above 0.05 and 0.5 at the end
    /// (`damage_shares.rs`), with the convergence band where one applies.
    pub damage_by_group: Vec<GroupDamage>,
    /// The convergence band of `[dynamics] convergence`, and whether it applies.
    pub convergence: Option<crate::config::BandReport>,
    /// The time [s] at which every `[[dynamics.stop_when]]` share was reached and the run ended
    /// (None: it ran to `duration`).
    pub stopped_by_shares: Option<f64>,
}

impl TimeHistorySummary {
    /// A step's damage cuts and substep sizes (`stepper.rs`, "Damage control").
    pub(super) fn add_damage_control(&mut self, report: &StepReport) {
        self.damage_cut_steps += (report.damage_cuts > 0) as usize;
        self.damage_cuts += report.damage_cuts;
        self.damage_cut_iterations += report.damage_cut_iterations;
        self.over_limit_substeps += report.over_limit;
        self.smallest_substep = self.smallest_substep.min(report.smallest_substep);
        self.max_step_damage_increment = self.max_step_damage_increment.max(report.damage_increment);
    }
}
