//! `[analysis] type = "seismic_assessment"`: the church job's chain in one run — modal analysis of
//! the elastic model, modal updating of substructure moduli to target frequencies, then gravity
//! and the earthquake of `[dynamics]` on the updated model (paper §4.2).
//!
//! ```toml
//! [analysis]
//! type = "seismic_assessment"
//! modes = 12                        # modes of the modal stage (default 12)
//! mass = "consistent"               # mass matrix of the modal stages (default consistent)
//! [analysis.updating]               # optional: without it the moduli are used as given
//! modes = 8                         # modes per eigensolve (>= the highest target mode)
//! max_iterations = 30
//! tolerance = 1e-4                  # RMS relative frequency error
//! [[analysis.updating.targets]]
//! mode = 1
//! frequency = 2.6                   # [Hz]
//! [[analysis.updating.parameters]]
//! group = "tower"                   # a physical group of the job's parts
//! min = 0.3                         # bounds on the factor on E
//! max = 3.0
//! [dynamics]                        # as for type = "time_history" (config::dynamics)
//! ```
//!
//! The updating keys are those of `type = "modal_updating"` ([`super::ModalUpdatingConfig`]),
//! one level down. Without `target_shapes`, target `mode = k` means stage 1's mode k, and each
//! target is paired by MAC with the computed mode most like stage 1's shape k. The factor of a group multiplies the Young modulus (and G with it) of the
//! material of that group's parts only: a material shared by several groups is copied per group
//! (`<material>@<group>`) before it is scaled. For a damage material the law's `E` is scaled,
//! so its tensile strength `f_t = E ε₀ᵗ` follows (ε₀ᵗ is the identified threshold strain).
use super::source::{Seg, Source};
use super::{ConfigError, ModalUpdatingConfig, StructuralJobFile};
use serde::Deserialize;

/// `[analysis] type = "seismic_assessment"`.
#[derive(Clone, Debug, Deserialize, PartialEq, schemars::JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct AssessmentConfig {
    /// Modes of the modal stage (default 12).
    #[serde(default = "default_assessment_modes")]
    pub modes: usize,
    /// Mass matrix of the modal stage (default consistent).
    #[serde(default = "default_assessment_mass")]
    pub mass: crate::element::MassKind,
    /// Modal updating of substructure moduli (optional).
    pub updating: Option<ModalUpdatingConfig>,
}

fn default_assessment_modes() -> usize {
    12
}

fn default_assessment_mass() -> crate::element::MassKind {
    crate::element::MassKind::Consistent
}

impl AssessmentConfig {
    /// The modal stage's settings.
    pub fn modal(&self) -> super::ModalConfig {
        super::ModalConfig { modes: self.modes, mass: self.mass }
    }
}

/// Checks of an assessment that need no mesh: at least one mode, and the updating's targets
/// and parameters (as for `modal_updating`, located under `analysis.updating`).
pub(super) fn validate_assessment(
    src: &Source,
    job: &StructuralJobFile,
    a: &AssessmentConfig,
) -> Result<(), ConfigError> {
    if a.modes == 0 {
        return Err(src.error_at(&[Seg::key("analysis"), Seg::key("modes")], "expected at least 1 mode"));
    }
    if job.dynamics.is_none() {
        return Err(src.error_at(
            &[Seg::key("analysis"), Seg::key("type")],
            "a seismic assessment needs a [dynamics] table (the earthquake stage)",
        ));
    }
    if let Some(u) = &a.updating {
        super::validate::validate_updating(src, job, u, &[Seg::key("analysis"), Seg::key("updating")])?;
    }
    Ok(())
}
