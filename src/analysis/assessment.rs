//! The `seismic_assessment` job (the church job): the stages of a seismic assessment chained in
//! one run on one [`FeProblem`]: its discretization (partition, numbering, elements) is set up
//! once, by the caller, and every stage works on it (deal.II's `setup_system` once, then phases).
//!
//! ```text
//!  setup            FeProblem::setup (the caller)
//!  1 modal          modal::run, the model as given               → modes.xdmf, the frequencies,
//!                                                                  the shapes kept in memory
//!  2 updating       modal_updating::run: factors s_g on E per group (LM, exact
//!                   sensitivities), targets paired by MAC with stage 1's shapes unless
//!                   target_shapes are given
//!                   the moduli moved on the problem: the owned elements built again with
//!                   E ← s_g E per part (G with it; a damage law's f_t = E ε₀ᵗ follows, ε₀ᵗ fixed)
//!                   → stages.json (stages 1–3 and the factors: what --restart reads back)
//!  3 modal (updated) modal::run                                  → modes-updated.xdmf
//!  4 time history   time_history::run: gravity, then [dynamics]
//!                   → results.xdmf, envelopes.xdmf, monitors.csv + PNGs, energy.csv, checkpoint/
//! ```
//!
//! `--restart` skips stages 1–3: it reads the factors from `stages.json`, moves the moduli and
//! continues the time history from its last checkpoint. `summary.json` holds every stage.
use super::modal;
use super::modal_updating::{self, UpdatingSummary};
use super::time_history::Start;
use super::time_history::{self, TimeHistorySummary};
use super::FeProblem;
use crate::config::{AssessmentConfig, Job, MaterialConfig};
use crate::error::{AnalysisError, Error};
use crate::io::IoError;
use crate::parallel::{agree, Phases};
use serde::{Deserialize, Serialize};
use std::path::Path;

/// The file holding the stages before the time history (read back by `--restart`).
pub const STAGES_FILE: &str = "stages.json";

crate::io::summary::named!(
    /// The seconds of stages 1–3.
    stage_seconds: ["modal", "updating", "modal_updated"]
);
crate::io::summary::named!(
    /// The seconds of an assessment run.
    run_seconds: ["stages", "time_history", "total"]
);

/// The modulus of one group's parts, before and after updating.
#[derive(Debug, Clone, Serialize, Deserialize, PartialEq)]
pub struct ModulusChange {
    /// Physical group.
    pub group: String,
    /// The material the job gives its parts.
    pub material: String,
    /// Factor on E (1 when the group is not updated).
    pub factor: f64,
    /// Young's modulus before [Pa].
    pub e_before: f64,
    /// After [Pa].
    pub e_after: f64,
    /// Tensile strength `f_t = E ε₀ᵗ` `before` and `after` [Pa] (damage materials).
    #[serde(with = "crate::io::summary::before_after::option")]
    pub f_t: Option<[f64; 2]>,
}

/// Stages 1–3, as written to [`STAGES_FILE`].
#[derive(Debug, Clone, Serialize, Deserialize)]
pub struct PreStages {
    /// Stage 1: modes of the model as given.
    pub modal: serde_json::Value,
    /// Stage 2 (null without `[analysis.updating]`).
    pub updating: serde_json::Value,
    /// The moduli of every part's group, before and after.
    pub moduli: Vec<ModulusChange>,
    /// Stage 3: modes of the updated model.
    pub modal_updated: serde_json::Value,
    /// Seconds of stages 1, 2, 3: `modal`, `updating`, `modal_updated`.
    #[serde(with = "stage_seconds")]
    pub seconds: [f64; 3],
}

/// What the assessment reports (`summary.json`).
#[derive(Debug, Clone, Serialize)]
pub struct AssessmentSummary {
    /// Ranks.
    pub ranks: usize,
    /// True when this run continued a time history from its checkpoint.
    pub restart: bool,
    /// Stages 1–3 (read back from `stages.json` on a restart).
    pub stages: PreStages,
    /// Stage 4.
    pub time_history: TimeHistorySummary,
    /// Seconds of this run: `stages` 1–3 (0 on a restart), `time_history`, `total`.
    #[serde(with = "run_seconds")]
    pub seconds: [f64; 3],
}

/// Collective. Runs the assessment of `p` (see the module docs).
pub fn run(mut p: FeProblem, cfg: &AssessmentConfig, restart: bool) -> Result<AssessmentSummary, Error> {
    let (ctx, job) = (p.ctx, p.job);
    let log = &ctx.log;
    let mut phases = Phases::default();
    phases.add("setup", p.take_setup_seconds());
    log.info(format!(
        "setup: {} equations, {} element(s) on {} rank(s): one discretization for every stage",
        6 * p.disc.dofs.n_global_nodes,
        p.model.cells.len(),
        ctx.size
    ));
    let stages = phases.time("stages 1-3", || -> Result<PreStages, Error> {
        if restart {
            let file = job.output_dir.join(STAGES_FILE);
            let read = read_stages(&file).and_then(|s| part_factors(job, &s.moduli).map(|f| (s, f)));
            let (stages, factors) = agree(&ctx.comm, read, Error::exit_code)?;
            log.info(format!("restart: stages 1-3 read back from {} (modal updating skipped)", file.display()));
            p.rebuild_elements(&factors)?;
            Ok(stages)
        } else {
            pre_stages(&mut p, cfg)
        }
    })?;

    log.info(format!(
        "stage 4/4: gravity, then the ground motion on the updated model{}",
        if restart { " (restart)" } else { "" }
    ));
    let start = if restart { Start::Restart } else { Start::Gravity };
    let th = phases.time("time history", || time_history::run(p, start, &mut ()))?;
    let [t_setup, t_pre, t_th] = phases.seconds_of(["setup", "stages 1-3", "time history"]);
    Ok(AssessmentSummary {
        ranks: ctx.size,
        restart,
        stages,
        time_history: th,
        seconds: [if restart { 0.0 } else { t_setup + t_pre }, t_th, t_setup + t_pre + t_th],
    })
}

/// The factor on E of every part (in the job's order), read from the `stages.json` of an earlier
/// run in `dir` (a sweep's stages of one material, shared by its members).
pub fn part_factors_in(job: &Job, dir: &Path) -> Result<Vec<f64>, Error> {
    let stages = read_stages(&dir.join(STAGES_FILE))?;
    part_factors(job, &stages.moduli)
}

/// The factor on E of every part (in the job's order), from the moduli of [`modulus_changes`];
/// an error when they are not this job's (a `stages.json` of another job).
fn part_factors(job: &Job, moduli: &[ModulusChange]) -> Result<Vec<f64>, Error> {
    let parts = &job.spec.parts;
    if moduli.len() != parts.len()
        || moduli.iter().zip(parts).any(|(m, p)| m.group != p.group || m.material != p.material)
    {
        return Err(AnalysisError::StagesOfOtherParts { name: STAGES_FILE, parts: parts.len() }.into());
    }
    Ok(moduli.iter().map(|m| m.factor).collect())
}

/// Collective. Stages 1–3 on `p` (its elements left with the updated moduli); rank 0 writes
/// them to `stages.json` in the job's results folder. A sweep runs them once per material.
pub fn pre_stages(p: &mut FeProblem, cfg: &AssessmentConfig) -> Result<PreStages, Error> {
    let (ctx, job) = (p.ctx, p.job);
    let log = &ctx.log;
    let mut phases = Phases::default();
    log.info(format!("stage 1/4: modal analysis of the model as given, {} mode(s)", cfg.modes));
    let (modal, shapes) = phases.time("modal", || modal::run(p, &cfg.modal(), "modes"))?;

    let updating = phases.time("updating", || -> Result<Option<UpdatingSummary>, Error> {
        Ok(match &cfg.updating {
            Some(u) => {
                log.info(format!(
                    "stage 2/4: modal updating of {} group modulus(es) to {} target frequency(ies)",
                    u.parameters.len(),
                    u.targets.len()
                ));
                // Without measured shapes, the targets are stage 1's modes: each target keeps the
                // computed mode most like its stage-1 shape (MAC), so a reordering of close modes as
                // the moduli move does not pair a target with another mode.
                if u.target_shapes.is_none() {
                    log.info("  targets paired by MAC with the mode shapes of stage 1");
                }
                Some(modal_updating::run(p, u, Some(&shapes))?)
            }
            None => {
                log.info("stage 2/4: no [analysis.updating]: the moduli are used as given");
                None
            }
        })
    })?;
    let moduli = modulus_changes(job, updating.as_ref());
    log.info("moduli of the time history: group, material, factor, E before -> after [Pa], f_t before -> after [Pa]");
    let (wg, wm) = moduli.iter().fold((12, 16), |(g, w), m| (g.max(m.group.len()), w.max(m.material.len())));
    for m in &moduli {
        log.info(format!(
            "  {:wg$} {:wm$} {:8.5}  {:11.4e} -> {:11.4e}{}",
            m.group,
            m.material,
            m.factor,
            m.e_before,
            m.e_after,
            m.f_t.map(|[a, b]| format!("   {a:.4e} -> {b:.4e}")).unwrap_or_default()
        ));
    }

    log.info("stage 3/4: modal analysis of the updated model");
    let factors: Vec<f64> = moduli.iter().map(|m| m.factor).collect();
    let (modal_updated, _) = phases.time("modal (updated)", || -> Result<_, Error> {
        p.rebuild_elements(&factors)?;
        modal::run(p, &cfg.modal(), "modes-updated")
    })?;

    let stages = PreStages {
        modal: to_value(&modal)?,
        updating: match updating.as_ref() {
            Some(u) => to_value(u)?,
            None => serde_json::Value::Null,
        },
        moduli,
        modal_updated: to_value(&modal_updated)?,
        seconds: phases.seconds_of(["modal", "updating", "modal (updated)"]),
    };
    let written = if ctx.rank == 0 { write_stages(&job.output_dir.join(STAGES_FILE), &stages) } else { Ok(()) };
    agree(&ctx.comm, written, Error::exit_code)?;
    Ok(stages)
}

fn to_value<T: Serialize>(v: &T) -> Result<serde_json::Value, Error> {
    serde_json::to_value(v)
        .map_err(|source| Error::from(IoError::Json { file: STAGES_FILE.into(), what: "a stage's summary", source }))
}

fn write_stages(file: &Path, stages: &PreStages) -> Result<(), Error> {
    let text = serde_json::to_string_pretty(stages).map_err(|source| IoError::Json {
        file: file.to_path_buf(),
        what: "the stages",
        source,
    })?;
    std::fs::write(file, text + "\n").map_err(|source| Error::OutputDir { path: file.to_path_buf(), source })
}

fn read_stages(file: &Path) -> Result<PreStages, Error> {
    let text = std::fs::read_to_string(file)
        .map_err(|source| AnalysisError::StagesMissing { file: file.to_path_buf(), source })?;
    serde_json::from_str(&text).map_err(|e| {
        Error::from(AnalysisError::StagesInvalid {
            file: file.to_path_buf(),
            reason: format!("not a stages file of a seismic assessment: {e}"),
        })
    })
}

/// The modulus of every part's group: the updating's factor (1 for groups it does not update).
pub fn modulus_changes(job: &Job, updating: Option<&UpdatingSummary>) -> Vec<ModulusChange> {
    let factor_of =
        |group: &str| updating.and_then(|u| u.parameters.iter().find(|p| p.group == group)).map(|p| p.factor);
    job.spec
        .parts
        .iter()
        .map(|part| {
            let material = job.spec.materials.get(&part.material);
            let e = material.and_then(MaterialConfig::young_modulus).unwrap_or(f64::NAN);
            let factor = factor_of(&part.group);
            let s = factor.unwrap_or(1.0);
            let eps0_t = match material {
                Some(MaterialConfig::Damage(d)) => d.law.as_ref().map(|l| l.eps0_t),
                _ => None,
            };
            ModulusChange {
                group: part.group.clone(),
                material: part.material.clone(),
                factor: s,
                e_before: e,
                e_after: s * e,
                f_t: eps0_t.map(|eps| [e * eps, s * e * eps]),
            }
        })
        .collect()
}
