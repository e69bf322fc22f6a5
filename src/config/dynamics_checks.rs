//! `[dynamics]`: the checks of the table's numbers after defaults (the time step and scheme, the
//! iterations, IMPL-EX's keys and the output, the damping), each error naming its key.
use super::{scheme_parameters, DampingConfig, DynamicsConfig, IntegrationKind, NewtonKind, SchemeName};
use crate::config::source::{Seg, Source};
use crate::config::ConfigError;

/// The time step and duration, and the scheme's parameters after defaults: HHT α in
/// [−1/3, 0], and Newmark's β, γ within its unconditional stability.
pub(super) fn check_time_and_scheme(src: &Source, d: &DynamicsConfig) -> Result<(), ConfigError> {
    let at = |k: &str| Seg::path(&["dynamics", k]);
    src.positive_finite(&at("dt"), d.dt, "time step", "s")?;
    src.positive_finite(&at("duration"), d.duration, "duration", "s")?;
    if d.duration / d.dt > 1e8 {
        return Err(src.error_at(&at("dt"), format!("{} steps of {} s: expected at most 1e8", d.duration / d.dt, d.dt)));
    }
    let (beta, gamma, alpha) = scheme_parameters(d);
    if d.scheme == SchemeName::Newmark && d.alpha.is_some() {
        return Err(src.error_at(&at("alpha"), "alpha is the HHT parameter: set scheme = \"hht\" to use it"));
    }
    if !(alpha.is_finite() && (-1.0 / 3.0 - 1e-12..=0.0).contains(&alpha)) {
        return Err(src.error_at(&at("alpha"), format!("expected HHT alpha in [-1/3, 0], got {alpha}")));
    }
    // Unconditional stability of Newmark (linear): γ ≥ 1/2 and β ≥ (γ + 1/2)²/4 (Hughes, *The
    // Finite Element Method*, §9.1); β > 0 so that a_{n+1} follows from u_{n+1}.
    if !(gamma.is_finite() && gamma >= 0.5) {
        return Err(src.error_at(&at("gamma"), format!("expected gamma >= 1/2 (unconditional stability), got {gamma}")));
    }
    let beta_min = (gamma + 0.5) * (gamma + 0.5) / 4.0;
    if !(beta.is_finite() && beta >= beta_min - 1e-12 && beta <= 0.5) {
        return Err(src.error_at(
            &at("beta"),
            format!(
                "expected beta in [(gamma + 1/2)^2/4, 1/2] = [{beta_min}, 0.5] (unconditional stability), got {beta}"
            ),
        ));
    }
    Ok(())
}

/// The Newton iteration's settings (iterations, subspace, tolerance, halvings, and the variants
/// that IMPL-EX accepts: [`IntegrationKind`]), the damage increment limit of a substep, and the
/// output and gravity step counts.
pub(super) fn check_iterations_and_output(src: &Source, d: &DynamicsConfig) -> Result<(), ConfigError> {
    let at = |k: &str| Seg::path(&["dynamics", k]);
    if d.max_iterations == 0 {
        return Err(src.error_at(&at("max_iterations"), "expected at least 1 iteration"));
    }
    if d.integration == IntegrationKind::Implicit && d.implex_split.is_some() {
        return Err(src.error_at(&at("implex_split"), "implex_split applies to integration = \"implex\" only"));
    }
    if d.integration == IntegrationKind::Implicit && d.implex_corrections > 0 {
        return Err(
            src.error_at(&at("implex_corrections"), "implex_corrections applies to integration = \"implex\" only")
        );
    }
    if !(d.implex_correction_tolerance.is_finite() && (0.0..1.0).contains(&d.implex_correction_tolerance)) {
        return Err(src.error_at(
            &at("implex_correction_tolerance"),
            format!("expected a damage change in [0, 1), got {}", d.implex_correction_tolerance),
        ));
    }
    if let Some(t) = d.implex_pass_tolerance {
        if d.implex_corrections == 0 {
            return Err(src.error_at(
                &at("implex_pass_tolerance"),
                "implex_pass_tolerance applies to integration = \"implex\" with implex_corrections > 0 only",
            ));
        }
        if !(t.is_finite() && t > 0.0 && t < 1.0) {
            return Err(src.error_at(&at("implex_pass_tolerance"), format!("expected a tolerance in (0, 1), got {t}")));
        }
    }
    if d.implex_corrections > 10 {
        return Err(src.error_at(
            &at("implex_corrections"),
            format!("expected 0 to 10 corrections, got {}", d.implex_corrections),
        ));
    }
    if d.integration == IntegrationKind::Implex && d.newton == NewtonKind::Initial {
        return Err(src.error_at(
            &at("newton"),
            "newton = \"initial\" never sees the extrapolated damage of integration = \"implex\": use \"modified\", \"krylov\" or \"tangent\"",
        ));
    }
    if !(1..=50).contains(&d.krylov_dimension) {
        return Err(src.error_at(
            &at("krylov_dimension"),
            format!("expected 1 to 50 subspace vectors, got {}", d.krylov_dimension),
        ));
    }
    if !(d.force_tolerance.is_finite() && d.force_tolerance > 0.0 && d.force_tolerance < 1.0) {
        return Err(
            src.error_at(&at("force_tolerance"), format!("expected a tolerance in (0, 1), got {}", d.force_tolerance))
        );
    }
    if d.max_substeps > 20 {
        return Err(src.error_at(&at("max_substeps"), format!("expected at most 20 halvings, got {}", d.max_substeps)));
    }
    let m = d.max_damage_increment;
    if !(m.is_finite() && m > 0.0 && m <= 1.0) {
        return Err(src.error_at(
            &at("max_damage_increment"),
            format!("expected a damage increment in (0, 1] (1.0: no control), got {m}"),
        ));
    }
    if d.output_every == 0 {
        return Err(src.error_at(&at("output_every"), "expected at least 1"));
    }
    if d.gravity_steps == 0 {
        return Err(src.error_at(&at("gravity_steps"), "expected at least 1"));
    }
    Ok(())
}

/// `[dynamics.damping]`: two frequencies with a ratio, or the Rayleigh coefficients (≥ 0).
pub(super) fn check_damping(src: &Source, dam: &DampingConfig) -> Result<(), ConfigError> {
    let dat = |k: &str| Seg::path(&["dynamics", "damping", k]);
    match (dam.frequencies, dam.ratio, dam.alpha, dam.beta) {
        (None, None, _, _) => {
            for (k, v) in [("alpha", dam.alpha), ("beta", dam.beta)] {
                if let Some(v) = v {
                    src.non_negative(&dat(k), v, &format!("Rayleigh coefficient {k}"), "")?;
                }
            }
        }
        (Some(f), Some(z), None, None) => {
            if !(f[0].is_finite() && f[0] > 0.0 && f[1].is_finite() && f[1] > f[0]) {
                return Err(
                    src.error_at(&dat("frequencies"), format!("expected two frequencies 0 < f1 < f2 [Hz], got {f:?}"))
                );
            }
            if !(z.is_finite() && (0.0..1.0).contains(&z)) {
                return Err(src.error_at(&dat("ratio"), format!("expected a damping ratio in [0, 1), got {z}")));
            }
        }
        _ => {
            return Err(src.error_at(
                &Seg::path(&["dynamics", "damping"]),
                "give either frequencies = [f1, f2] with ratio, or alpha and/or beta",
            ))
        }
    }
    Ok(())
}
