//! Checks of a job file that need no mesh: positive moduli and sections, names that resolve.
use super::analysis::*;
use super::job::*;
use super::source::{Seg, Source};
use super::ConfigError;

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

/// Whether anything in the job carries mass: a material density, a non-structural mass of a
/// section, or a point mass.
fn has_mass(job: &StructuralJobFile) -> bool {
    job.materials.values().any(|m| m.density() > 0.0)
        || job.masses.iter().any(|m| m.mass > 0.0)
        || job.sections.values().any(|s| match s {
            SectionConfig::Frame(f) => f.nonstructural_mass > 0.0,
            SectionConfig::Shell(sh) => sh.nonstructural_mass > 0.0,
            SectionConfig::Fiber(f) => f.nonstructural_mass > 0.0,
            SectionConfig::Tie(_) => false,
        })
}

/// Validates a structural job file; the first problem found is returned.
pub fn validate_structural(src: &Source, job: &StructuralJobFile) -> Result<(), ConfigError> {
    for (name, m) in &job.materials {
        let at = |k: &str| vec![Seg::key("materials"), Seg::key(name), Seg::key(k)];
        match m {
            MaterialConfig::Elastic(ElasticMaterial { e, nu, g, density }) => {
                positive(src, &at("E"), "Young's modulus E [Pa]", *e)?;
                match (nu, g) {
                    (Some(_), Some(_)) => return Err(src.error_at(&at("G"), "give either nu or G, not both")),
                    (None, None) => {
                        return Err(src.error_at(
                            &[Seg::key("materials"), Seg::key(name)],
                            "an elastic material needs nu (Poisson ratio) or G (shear modulus [Pa])",
                        ))
                    }
                    (Some(nu), None) => {
                        if !(nu.is_finite() && *nu > -1.0 && *nu < 0.5) {
                            return Err(
                                src.error_at(&at("nu"), format!("Poisson ratio nu must lie in (-1, 0.5), got {nu}"))
                            );
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
                    return Err(src.error_at(
                        &at("density"),
                        format!("density [kg/m^3] must be a finite number >= 0, got {}", d.density),
                    ));
                }
                match (&d.law, &d.law_file) {
                    (Some(_), Some(_)) => {
                        return Err(src.error_at(&at("law_file"), "give either [law] or law_file, not both"))
                    }
                    (None, None) => {
                        return Err(src.error_at(
                            &[Seg::key("materials"), Seg::key(name)],
                            "a damage material needs its [law] table or a law_file",
                        ))
                    }
                    (Some(law), None) => law.validate().map_err(|e| src.error_at(&at("law"), e.to_string()))?,
                    (None, Some(_)) => {} // read and validated when the job is loaded
                }
            }
        }
    }
    for (name, s) in &job.sections {
        let at = |k: &str| vec![Seg::key("sections"), Seg::key(name), Seg::key(k)];
        match s {
            SectionConfig::Frame(FrameSectionConfig { area, iy, iz, j, nonstructural_mass }) => {
                positive(src, &at("area"), "section area [m^2]", *area)?;
                positive(src, &at("iy"), "second moment iy [m^4]", *iy)?;
                positive(src, &at("iz"), "second moment iz [m^4]", *iz)?;
                positive(src, &at("j"), "torsion constant j [m^4]", *j)?;
                if !(nonstructural_mass.is_finite() && *nonstructural_mass >= 0.0) {
                    return Err(src.error_at(
                        &at("nonstructural_mass"),
                        format!("expected a finite mass per length >= 0 [kg/m], got {nonstructural_mass}"),
                    ));
                }
            }
            SectionConfig::Fiber(f) => {
                positive(src, &at("width"), "section width [m]", f.width)?;
                positive(src, &at("height"), "section height [m]", f.height)?;
                let max = crate::element::MAX_FIBERS_PER_SIDE;
                for (k, n) in [("ny", f.ny), ("nz", f.nz)] {
                    if n < 2 || n > max {
                        return Err(src.error_at(&at(k), format!("expected 2 to {max} fibers (one fiber across a side has no bending stiffness), got {n}")));
                    }
                }
                if !(2..=5).contains(&f.integration_points) {
                    return Err(src.error_at(
                        &at("integration_points"),
                        format!("expected 2 to 5 Gauss points, got {}", f.integration_points),
                    ));
                }
                if let Some(j) = f.torsion_constant {
                    positive(src, &at("torsion_constant"), "torsion constant [m^4]", j)?;
                }
                if !(f.nonstructural_mass.is_finite() && f.nonstructural_mass >= 0.0) {
                    return Err(src.error_at(
                        &at("nonstructural_mass"),
                        format!("expected a finite mass per length >= 0 [kg/m], got {}", f.nonstructural_mass),
                    ));
                }
            }
            SectionConfig::Tie(TieSectionConfig { area, pretension, .. }) => {
                positive(src, &at("area"), &format!("area [m^2] of tie section '{name}'"), *area)?;
                if !(pretension.is_finite() && *pretension >= 0.0) {
                    return Err(src.error_at(
                        &at("pretension"),
                        format!("pretension [N] of tie section '{name}' must be a finite number >= 0 (tension positive), got {pretension}"),
                    ));
                }
            }
            SectionConfig::Shell(ShellSectionConfig { thickness, layers, nonstructural_mass }) => {
                positive(src, &at("thickness"), "shell thickness [m]", *thickness)?;
                if *layers == 0 || *layers > 99 {
                    return Err(src.error_at(&at("layers"), format!("expected 1 to 99 layers, got {layers}")));
                }
                if !(nonstructural_mass.is_finite() && *nonstructural_mass >= 0.0) {
                    return Err(src.error_at(
                        &at("nonstructural_mass"),
                        format!("expected a finite mass per area >= 0 [kg/m^2], got {nonstructural_mass}"),
                    ));
                }
            }
        }
    }
    if let AnalysisConfig::Modal(m) = &job.analysis {
        if m.modes == 0 {
            return Err(src.error_at(&[Seg::key("analysis"), Seg::key("modes")], "expected at least 1 mode"));
        }
        if !has_mass(job) {
            return Err(src.error_at(
                &[Seg::key("materials")],
                "a modal analysis needs mass: give at least one material a density > 0 (or a non-structural or point mass)",
            ));
        }
    }
    if let AnalysisConfig::StaticNonlinear(c) = &job.analysis {
        let at = |k: &str| vec![Seg::key("analysis"), Seg::key(k)];
        if c.steps == 0 {
            return Err(src.error_at(&at("steps"), "expected at least 1 load step"));
        }
        if c.max_iterations == 0 {
            return Err(src.error_at(&at("max_iterations"), "expected at least 1 iteration"));
        }
        positive(src, &at("force_tolerance"), "force tolerance", c.force_tolerance)?;
        positive(src, &at("energy_tolerance"), "energy tolerance", c.energy_tolerance)?;
        if let Some(tau) = c.damage_relaxation_time {
            positive(src, &at("damage_relaxation_time"), "damage relaxation time", tau)?;
        }
        if let Some(r) = c.nonlocal_radius {
            positive(src, &at("nonlocal_radius"), "nonlocal radius (m)", r)?;
        }
        if let Some(ctl) = &c.control {
            let at = |k: &str| vec![Seg::key("analysis"), Seg::key("control"), Seg::key(k)];
            match (&ctl.group, &ctl.node) {
                (Some(_), Some(_)) => return Err(src.error_at(&at("node"), "give either group or node, not both")),
                (None, None) => {
                    return Err(src.error_at(
                        &[Seg::key("analysis"), Seg::key("control")],
                        "the control needs a group or a node (Gmsh node tag)",
                    ))
                }
                _ => {}
            }
            if matches!(ctl.dof, DofName::All) {
                return Err(src.error_at(&at("dof"), "expected one DOF: ux, uy, uz, rx, ry or rz"));
            }
            if !(ctl.target.is_finite() && ctl.target != 0.0) {
                return Err(
                    src.error_at(&at("target"), format!("expected a finite, non-zero target, got {}", ctl.target))
                );
            }
            if ctl.steps == 0 {
                return Err(src.error_at(&at("steps"), "expected at least 1 step"));
            }
            for (i, p) in ctl.pattern.iter().enumerate() {
                let at = |k: &str| {
                    vec![Seg::key("analysis"), Seg::key("control"), Seg::key("pattern"), Seg::Index(i), Seg::key(k)]
                };
                finite3(src, &at("force"), &p.force)?;
                finite3(src, &at("moment"), &p.moment)?;
            }
        }
    }
    if let AnalysisConfig::ModalUpdating(u) = &job.analysis {
        validate_updating(src, job, u, &[Seg::key("analysis")])?;
    }
    if let AnalysisConfig::SeismicAssessment(a) = &job.analysis {
        super::assessment::validate_assessment(src, job, a)?;
    }
    if job.parts.is_empty() {
        return Err(
            src.error_at(&[], "the job has no [[parts]]: map at least one physical group to a section and a material")
        );
    }
    for (i, p) in job.parts.iter().enumerate() {
        let at = |k: &str| vec![Seg::key("parts"), Seg::Index(i), Seg::key(k)];
        if !job.sections.contains_key(&p.section) {
            return Err(
                src.error_at(&at("section"), format!("no section named '{}' ({})", p.section, names(&job.sections)))
            );
        }
        if !job.materials.contains_key(&p.material) {
            return Err(src
                .error_at(&at("material"), format!("no material named '{}' ({})", p.material, names(&job.materials))));
        }
        if let (SectionConfig::Frame(_), MaterialConfig::Damage(_)) =
            (&job.sections[&p.section], &job.materials[&p.material])
        {
            return Err(src.error_at(
                &at("material"),
                format!("frame section '{}' needs an elastic material; '{}' is a damage material (damage goes in shell layers and fiber sections)", p.section, p.material),
            ));
        }
        if let (SectionConfig::Tie(_), MaterialConfig::Damage(_)) =
            (&job.sections[&p.section], &job.materials[&p.material])
        {
            return Err(src.error_at(
                &at("material"),
                format!("tie section '{}' needs an elastic material (type = \"elastic\": E, density); '{}' is a damage material", p.section, p.material),
            ));
        }
        if let (SectionConfig::Tie(_), Some(_)) = (&job.sections[&p.section], &p.orientation) {
            return Err(src.error_at(
                &at("orientation"),
                format!(
                    "tie section '{}' carries axial force only and has no local axes: remove orientation",
                    p.section
                ),
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
                &[Seg::key("supports"), Seg::Index(i), Seg::key("dofs")],
                "expected at least one of all, ux, uy, uz, rx, ry, rz",
            ));
        }
    }
    for (i, l) in job.loads.iter().enumerate() {
        match l {
            LoadConfig::Nodal(NodalLoadConfig { force, moment, .. }) => {
                finite3(src, &[Seg::key("loads"), Seg::Index(i), Seg::key("force")], force)?;
                finite3(src, &[Seg::key("loads"), Seg::Index(i), Seg::key("moment")], moment)?;
            }
        }
    }
    for (i, m) in job.masses.iter().enumerate() {
        let at = |k: &str| vec![Seg::key("masses"), Seg::Index(i), Seg::key(k)];
        match (&m.group, &m.node) {
            (Some(_), Some(_)) => return Err(src.error_at(&at("node"), "give either group or node, not both")),
            (None, None) => {
                return Err(src.error_at(
                    &[Seg::key("masses"), Seg::Index(i)],
                    "a point mass needs a group or a node (Gmsh node tag)",
                ))
            }
            _ => {}
        }
        if !(m.mass.is_finite() && m.mass >= 0.0) {
            return Err(src.error_at(&at("mass"), format!("expected a finite mass >= 0 [kg], got {}", m.mass)));
        }
        if m.rotary_inertia.iter().any(|x| !(x.is_finite() && *x >= 0.0)) {
            return Err(src.error_at(
                &at("rotary_inertia"),
                format!("expected three finite inertias >= 0 [kg m^2], got {:?}", m.rotary_inertia),
            ));
        }
    }
    if let Some(g) = &job.gravity {
        finite3(src, &[Seg::key("gravity"), Seg::key("acceleration")], &g.acceleration)?;
    }
    for (k, v) in &job.solver.petsc {
        if matches!(v, toml::Value::Array(_) | toml::Value::Table(_) | toml::Value::Datetime(_)) {
            return Err(src.error_at(
                &[Seg::key("solver"), Seg::key("petsc"), Seg::key(k)],
                "a PETSc option value must be a string, a number or a boolean",
            ));
        }
    }
    Ok(())
}

/// Checks of a modal updating's targets and parameters; `base` is where its keys are (`analysis`,
/// or `analysis.updating` in a seismic assessment).
pub(super) fn validate_updating(
    src: &Source,
    job: &StructuralJobFile,
    u: &ModalUpdatingConfig,
    base: &[Seg],
) -> Result<(), ConfigError> {
    let at = |k: &str, i: usize, f: &str| {
        let mut p = base.to_vec();
        p.extend([Seg::key(k), Seg::Index(i), Seg::key(f)]);
        p
    };
    let table = if base.len() > 1 { "analysis.updating" } else { "analysis" };
    if u.targets.is_empty() || u.parameters.is_empty() {
        return Err(src.error_at(base, format!("modal updating needs [[{table}.targets]] and [[{table}.parameters]]")));
    }
    for (i, t) in u.targets.iter().enumerate() {
        if t.mode == 0 || t.mode > u.modes {
            return Err(
                src.error_at(&at("targets", i, "mode"), format!("expected a mode number in 1..={} (modes)", u.modes))
            );
        }
        positive(src, &at("targets", i, "frequency"), "target frequency [Hz]", t.frequency)?;
    }
    for (i, p) in u.parameters.iter().enumerate() {
        positive(src, &at("parameters", i, "min"), "lower bound of the modulus factor", p.min)?;
        if !(p.max.is_finite() && p.max > p.min) {
            return Err(
                src.error_at(&at("parameters", i, "max"), format!("expected max > min = {}, got {}", p.min, p.max))
            );
        }
        if !job.parts.iter().any(|q| q.group == p.group) {
            return Err(src.error_at(
                &at("parameters", i, "group"),
                format!(
                    "group '{}' is not one of the job's parts ({})",
                    p.group,
                    job.parts.iter().map(|q| q.group.as_str()).collect::<Vec<_>>().join(", ")
                ),
            ));
        }
    }
    if !has_mass(job) {
        return Err(src.error_at(
            &[Seg::key("materials")],
            "modal updating needs mass: give at least one material a density > 0",
        ));
    }
    Ok(())
}
