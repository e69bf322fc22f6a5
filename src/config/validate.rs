//! Checks of a job file that need no mesh: positive moduli and sections, names that resolve.
use super::job::*;
use super::source::{Seg, Source};
use super::ConfigError;

fn key(k: &str) -> Seg {
    Seg::Key(k.to_string())
}

fn positive(src: &Source, path: &[Seg], what: &str, v: f64) -> Result<(), ConfigError> {
    if v.is_finite() && v > 0.0 {
        Ok(())
    } else {
        Err(src.error_at(path, format!("{what} must be a finite number > 0, got {v}")))
    }
}

fn finite3(src: &Source, path: &[Seg], v: &[f64; 3]) -> Result<(), ConfigError> {
    if v.iter().all(|x| x.is_finite()) {
        Ok(())
    } else {
        Err(src.error_at(path, format!("expected three finite numbers, got {v:?}")))
    }
}

fn names<T>(m: &std::collections::BTreeMap<String, T>) -> String {
    if m.is_empty() {
        "none is defined".to_string()
    } else {
        format!("defined: {}", m.keys().cloned().collect::<Vec<_>>().join(", "))
    }
}

/// Validates a structural job file; the first problem found is returned.
pub fn validate_structural(src: &Source, job: &StructuralJobFile) -> Result<(), ConfigError> {
    for (name, m) in &job.materials {
        let at = |k: &str| vec![key("materials"), key(name), key(k)];
        match m {
            MaterialConfig::Elastic(ElasticMaterial { e, nu, g, density }) => {
                positive(src, &at("E"), "Young's modulus E [Pa]", *e)?;
                match (nu, g) {
                    (Some(_), Some(_)) => {
                        return Err(src.error_at(&at("G"), "give either nu or G, not both"))
                    }
                    (None, None) => {
                        return Err(src.error_at(
                            &[key("materials"), key(name)],
                            "an elastic material needs nu (Poisson ratio) or G (shear modulus [Pa])",
                        ))
                    }
                    (Some(nu), None) => {
                        if !(nu.is_finite() && *nu > -1.0 && *nu < 0.5) {
                            return Err(src.error_at(
                                &at("nu"),
                                format!("Poisson ratio nu must lie in (-1, 0.5), got {nu}"),
                            ));
                        }
                    }
                    (None, Some(g)) => positive(src, &at("G"), "shear modulus G [Pa]", *g)?,
                }
                if !(density.is_finite() && *density >= 0.0) {
                    return Err(src.error_at(
                        &at("density"),
                        format!("density [kg/m^3] must be a finite number >= 0, got {density}"),
                    ));
                }
            }
            MaterialConfig::Damage(d) => {
                if !(d.density.is_finite() && d.density >= 0.0) {
                    return Err(src.error_at(&at("density"), format!("density [kg/m^3] must be a finite number >= 0, got {}", d.density)));
                }
                match (&d.law, &d.law_file) {
                    (Some(_), Some(_)) => return Err(src.error_at(&at("law_file"), "give either [law] or law_file, not both")),
                    (None, None) => return Err(src.error_at(&[key("materials"), key(name)], "a damage material needs its [law] table or a law_file")),
                    (Some(law), None) => law.validate().map_err(|e| src.error_at(&at("law"), e.to_string()))?,
                    (None, Some(_)) => {} // read and validated when the job is loaded
                }
            }
        }
    }
    for (name, s) in &job.sections {
        let at = |k: &str| vec![key("sections"), key(name), key(k)];
        match s {
            SectionConfig::Frame(FrameSectionConfig { area, iy, iz, j }) => {
                positive(src, &at("area"), "section area [m^2]", *area)?;
                positive(src, &at("iy"), "second moment iy [m^4]", *iy)?;
                positive(src, &at("iz"), "second moment iz [m^4]", *iz)?;
                positive(src, &at("j"), "torsion constant j [m^4]", *j)?;
            }
            SectionConfig::Shell(ShellSectionConfig { thickness, layers, nonstructural_mass }) => {
                positive(src, &at("thickness"), "shell thickness [m]", *thickness)?;
                if *layers == 0 || *layers > 99 {
                    return Err(src.error_at(&at("layers"), format!("expected 1 to 99 layers, got {layers}")));
                }
                if !(nonstructural_mass.is_finite() && *nonstructural_mass >= 0.0) {
                    return Err(src.error_at(&at("nonstructural_mass"), format!("expected a finite mass per area >= 0 [kg/m^2], got {nonstructural_mass}")));
                }
            }
        }
    }
    if let AnalysisConfig::Modal(m) = &job.analysis {
        if m.modes == 0 {
            return Err(src.error_at(&[key("analysis"), key("modes")], "expected at least 1 mode"));
        }
        if !job.materials.values().any(|m| m.density() > 0.0) {
            return Err(src.error_at(
                &[key("materials")],
                "a modal analysis needs mass: give at least one material a density > 0",
            ));
        }
    }
    if let AnalysisConfig::ModalUpdating(u) = &job.analysis {
        let at = |k: &str, i: usize, f: &str| vec![key("analysis"), key(k), Seg::Index(i), key(f)];
        if u.targets.is_empty() || u.parameters.is_empty() {
            return Err(src.error_at(&[key("analysis")], "modal updating needs [[analysis.targets]] and [[analysis.parameters]]"));
        }
        for (i, t) in u.targets.iter().enumerate() {
            if t.mode == 0 || t.mode > u.modes {
                return Err(src.error_at(&at("targets", i, "mode"), format!("expected a mode number in 1..={} (modes)", u.modes)));
            }
            positive(src, &at("targets", i, "frequency"), "target frequency [Hz]", t.frequency)?;
        }
        for (i, p) in u.parameters.iter().enumerate() {
            positive(src, &at("parameters", i, "min"), "lower bound of the modulus factor", p.min)?;
            if !(p.max.is_finite() && p.max > p.min) {
                return Err(src.error_at(&at("parameters", i, "max"), format!("expected max > min = {}, got {}", p.min, p.max)));
            }
            if !job.parts.iter().any(|q| q.group == p.group) {
                return Err(src.error_at(
                    &at("parameters", i, "group"),
                    format!("group '{}' is not one of the job's parts ({})", p.group, job.parts.iter().map(|q| q.group.as_str()).collect::<Vec<_>>().join(", ")),
                ));
            }
        }
        if !job.materials.values().any(|m| m.density() > 0.0) {
            return Err(src.error_at(&[key("materials")], "modal updating needs mass: give at least one material a density > 0"));
        }
    }
    if job.parts.is_empty() {
        return Err(src.error_at(
            &[],
            "the job has no [[parts]]: map at least one physical group to a section and a material",
        ));
    }
    for (i, p) in job.parts.iter().enumerate() {
        let at = |k: &str| vec![key("parts"), Seg::Index(i), key(k)];
        if !job.sections.contains_key(&p.section) {
            return Err(src.error_at(
                &at("section"),
                format!("no section named '{}' ({})", p.section, names(&job.sections)),
            ));
        }
        if !job.materials.contains_key(&p.material) {
            return Err(src.error_at(
                &at("material"),
                format!("no material named '{}' ({})", p.material, names(&job.materials)),
            ));
        }
        if let (SectionConfig::Frame(_), MaterialConfig::Damage(_)) = (&job.sections[&p.section], &job.materials[&p.material]) {
            return Err(src.error_at(
                &at("material"),
                format!("frame section '{}' needs an elastic material; '{}' is a damage material (damage goes in shell layers)", p.section, p.material),
            ));
        }
        if let Some(v) = &p.orientation {
            finite3(src, &at("orientation"), v)?;
            if v.iter().map(|x| x * x).sum::<f64>() == 0.0 {
                return Err(src.error_at(&at("orientation"), "the orientation vector must not be zero"));
            }
        }
    }
    for (i, s) in job.supports.iter().enumerate() {
        if s.dofs.is_empty() {
            return Err(src.error_at(
                &[key("supports"), Seg::Index(i), key("dofs")],
                "expected at least one of all, ux, uy, uz, rx, ry, rz",
            ));
        }
    }
    for (i, l) in job.loads.iter().enumerate() {
        match l {
            LoadConfig::Nodal(NodalLoadConfig { force, moment, .. }) => {
                finite3(src, &[key("loads"), Seg::Index(i), key("force")], force)?;
                finite3(src, &[key("loads"), Seg::Index(i), key("moment")], moment)?;
            }
        }
    }
    if let Some(g) = &job.gravity {
        finite3(src, &[key("gravity"), key("acceleration")], &g.acceleration)?;
    }
    for (k, v) in &job.solver.petsc {
        if matches!(v, toml::Value::Array(_) | toml::Value::Table(_) | toml::Value::Datetime(_)) {
            return Err(src.error_at(
                &[key("solver"), key("petsc"), key(k)],
                "a PETSc option value must be a string, a number or a boolean",
            ));
        }
    }
    Ok(())
}
