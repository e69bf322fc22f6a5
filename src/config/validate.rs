//! Checks of a job file that need no mesh: positive moduli and sections, names that resolve.
//!
//! [`validate_structural`] runs the checks table by table, in the file's order of concern
//! (materials, sections, the analysis, parts, supports, loads, masses, gravity, solver options),
//! and returns the first problem found.
use super::analysis::*;
use super::job::*;
use super::source::{Seg, Source};
use super::ConfigError;
use std::collections::BTreeMap;

fn finite3(src: &Source, path: &[Seg], v: &[f64; 3]) -> Result<(), ConfigError> {
    if v.iter().all(|x| x.is_finite()) {
        Ok(())
    } else {
        Err(src.error_at(path, format!("expected three finite numbers, got {v:?}")))
    }
}

fn names<T>(m: &BTreeMap<String, T>) -> String {
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
        validate_material(src, name, m)?;
    }
    for (name, s) in &job.sections {
        validate_section(src, name, s)?;
    }
    validate_analysis(src, job)?;
    validate_parts(src, job)?;
    validate_supports_and_loads(src, job)?;
    for (i, m) in job.masses.iter().enumerate() {
        validate_point_mass(src, i, m)?;
    }
    if let Some(g) = &job.gravity {
        finite3(src, &Seg::path(&["gravity", "acceleration"]), &g.acceleration)?;
    }
    validate_petsc_options(src, &job.solver.petsc)
}

/// `[materials.NAME]`: an elastic material's moduli and density, or a damage material's
/// density and its law (inline, checked here, or in a file, checked when the job is loaded).
fn validate_material(src: &Source, name: &str, m: &MaterialConfig) -> Result<(), ConfigError> {
    let table = Seg::path(&["materials", name]);
    let at = |k: &str| Seg::path(&["materials", name, k]);
    match m {
        MaterialConfig::Elastic(ElasticMaterial { e, nu, g, density }) => {
            src.positive_finite(&at("E"), *e, "Young's modulus E", "Pa")?;
            match (nu, g) {
                (Some(_), Some(_)) => return Err(src.error_at(&at("G"), "give either nu or G, not both")),
                (None, None) => {
                    return Err(
                        src.error_at(&table, "an elastic material needs nu (Poisson ratio) or G (shear modulus [Pa])")
                    )
                }
                (Some(nu), None) => {
                    if !(nu.is_finite() && *nu > -1.0 && *nu < 0.5) {
                        return Err(
                            src.error_at(&at("nu"), format!("Poisson ratio nu must lie in (-1, 0.5), got {nu}"))
                        );
                    }
                }
                (None, Some(g)) => {
                    src.positive_finite(&at("G"), *g, "shear modulus G", "Pa")?;
                }
            }
            src.non_negative(&at("density"), *density, "density", "kg/m^3").map(drop)
        }
        MaterialConfig::Damage(d) => {
            src.non_negative(&at("density"), d.density, "density", "kg/m^3")?;
            match (&d.law, &d.law_file) {
                (Some(_), Some(_)) => Err(src.error_at(&at("law_file"), "give either [law] or law_file, not both")),
                (None, None) => Err(src.error_at(&table, "a damage material needs its [law] table or a law_file")),
                (Some(law), None) => law.validate().map_err(|e| src.error_at(&at("law"), e.to_string())),
                (None, Some(_)) => Ok(()), // read and validated when the job is loaded
            }
        }
    }
}

/// `[sections.NAME]`: positive dimensions, fiber and layer counts in range, non-negative
/// non-structural masses and pretensions.
fn validate_section(src: &Source, name: &str, s: &SectionConfig) -> Result<(), ConfigError> {
    let at = |k: &str| Seg::path(&["sections", name, k]);
    let mass_per = |v: f64, per: &str, unit: &str| {
        src.non_negative(&at("nonstructural_mass"), v, &format!("non-structural mass per {per}"), unit).map(drop)
    };
    match s {
        SectionConfig::Frame(FrameSectionConfig { area, iy, iz, j, nonstructural_mass }) => {
            src.positive_finite(&at("area"), *area, "section area", "m^2")?;
            src.positive_finite(&at("iy"), *iy, "second moment iy", "m^4")?;
            src.positive_finite(&at("iz"), *iz, "second moment iz", "m^4")?;
            src.positive_finite(&at("j"), *j, "torsion constant j", "m^4")?;
            mass_per(*nonstructural_mass, "length", "kg/m")
        }
        SectionConfig::Fiber(f) => {
            src.positive_finite(&at("width"), f.width, "section width", "m")?;
            src.positive_finite(&at("height"), f.height, "section height", "m")?;
            let max = crate::element::MAX_FIBERS_PER_SIDE;
            for (k, n) in [("ny", f.ny), ("nz", f.nz)] {
                if n < 2 || n > max {
                    return Err(src.error_at(
                        &at(k),
                        format!(
                            "expected 2 to {max} fibers (one fiber across a side has no bending stiffness), got {n}"
                        ),
                    ));
                }
            }
            if !(2..=5).contains(&f.integration_points) {
                return Err(src.error_at(
                    &at("integration_points"),
                    format!("expected 2 to 5 Gauss points, got {}", f.integration_points),
                ));
            }
            if let Some(j) = f.torsion_constant {
                src.positive_finite(&at("torsion_constant"), j, "torsion constant", "m^4")?;
            }
            mass_per(f.nonstructural_mass, "length", "kg/m")
        }
        SectionConfig::Tie(TieSectionConfig { area, pretension, .. }) => {
            src.positive_finite(&at("area"), *area, &format!("area of tie section '{name}'"), "m^2")?;
            let what = format!("pretension of tie section '{name}' (tension positive)");
            src.non_negative(&at("pretension"), *pretension, &what, "N").map(drop)
        }
        SectionConfig::Shell(ShellSectionConfig { thickness, layers, nonstructural_mass }) => {
            src.positive_finite(&at("thickness"), *thickness, "shell thickness", "m")?;
            if *layers == 0 || *layers > 99 {
                return Err(src.error_at(&at("layers"), format!("expected 1 to 99 layers, got {layers}")));
            }
            mass_per(*nonstructural_mass, "area", "kg/m^2")
        }
    }
}

/// `[analysis]`: what each analysis type needs beyond its defaults (modes and mass, load
/// steps and tolerances, updating targets, the assessment's stages).
fn validate_analysis(src: &Source, job: &StructuralJobFile) -> Result<(), ConfigError> {
    match &job.analysis {
        AnalysisConfig::Modal(m) => {
            if m.modes == 0 {
                return Err(src.error_at(&Seg::path(&["analysis", "modes"]), "expected at least 1 mode"));
            }
            if !has_mass(job) {
                return Err(src.error_at(
                    &Seg::path(&["materials"]),
                    "a modal analysis needs mass: give at least one material a density > 0 (or a non-structural or point mass)",
                ));
            }
            Ok(())
        }
        AnalysisConfig::StaticNonlinear(c) => validate_static_nonlinear(src, c),
        AnalysisConfig::ModalUpdating(u) => validate_updating(src, job, u, &Seg::path(&["analysis"])),
        AnalysisConfig::SeismicAssessment(a) => super::assessment::validate_assessment(src, job, a),
        _ => Ok(()),
    }
}

/// `[analysis] type = "static_nonlinear"`: steps, iterations and tolerances, the optional
/// regularizations, and the displacement control.
fn validate_static_nonlinear(src: &Source, c: &StaticNonlinearConfig) -> Result<(), ConfigError> {
    let at = |k: &str| Seg::path(&["analysis", k]);
    if c.steps == 0 {
        return Err(src.error_at(&at("steps"), "expected at least 1 load step"));
    }
    if c.max_iterations == 0 {
        return Err(src.error_at(&at("max_iterations"), "expected at least 1 iteration"));
    }
    src.positive_finite(&at("force_tolerance"), c.force_tolerance, "force tolerance", "")?;
    src.positive_finite(&at("energy_tolerance"), c.energy_tolerance, "energy tolerance", "")?;
    if let Some(tau) = c.damage_relaxation_time {
        src.positive_finite(&at("damage_relaxation_time"), tau, "damage relaxation time", "")?;
    }
    if let Some(r) = c.nonlocal_radius {
        src.positive_finite(&at("nonlocal_radius"), r, "nonlocal radius", "m")?;
    }
    match &c.control {
        Some(ctl) => validate_control(src, ctl),
        None => Ok(()),
    }
}

/// `[analysis.control]`: a group or a node, one DOF, a non-zero target, and a finite pattern.
fn validate_control(src: &Source, ctl: &DisplacementControlConfig) -> Result<(), ConfigError> {
    let at = |k: &str| Seg::path(&["analysis", "control", k]);
    match (&ctl.group, &ctl.node) {
        (Some(_), Some(_)) => return Err(src.error_at(&at("node"), "give either group or node, not both")),
        (None, None) => {
            return Err(src
                .error_at(&Seg::path(&["analysis", "control"]), "the control needs a group or a node (Gmsh node tag)"))
        }
        _ => {}
    }
    if matches!(ctl.dof, DofName::All) {
        return Err(src.error_at(&at("dof"), "expected one DOF: ux, uy, uz, rx, ry or rz"));
    }
    if !(ctl.target.is_finite() && ctl.target != 0.0) {
        return Err(src.error_at(&at("target"), format!("expected a finite, non-zero target, got {}", ctl.target)));
    }
    if ctl.steps == 0 {
        return Err(src.error_at(&at("steps"), "expected at least 1 step"));
    }
    for (i, p) in ctl.pattern.iter().enumerate() {
        let at =
            |k: &str| vec![Seg::key("analysis"), Seg::key("control"), Seg::key("pattern"), Seg::Index(i), Seg::key(k)];
        finite3(src, &at("force"), &p.force)?;
        finite3(src, &at("moment"), &p.moment)?;
    }
    Ok(())
}

/// `[[parts]]`: at least one; each names a section and a material that exist and suit each
/// other, and a finite, non-zero orientation where one is allowed.
fn validate_parts(src: &Source, job: &StructuralJobFile) -> Result<(), ConfigError> {
    if job.parts.is_empty() {
        return Err(
            src.error_at(&[], "the job has no [[parts]]: map at least one physical group to a section and a material")
        );
    }
    for (i, p) in job.parts.iter().enumerate() {
        let at = |k: &str| vec![Seg::key("parts"), Seg::Index(i), Seg::key(k)];
        let Some(section) = job.sections.get(&p.section) else {
            return Err(
                src.error_at(&at("section"), format!("no section named '{}' ({})", p.section, names(&job.sections)))
            );
        };
        let Some(material) = job.materials.get(&p.material) else {
            return Err(src
                .error_at(&at("material"), format!("no material named '{}' ({})", p.material, names(&job.materials))));
        };
        match (section, material) {
            (SectionConfig::Frame(_), MaterialConfig::Damage(_)) => {
                return Err(src.error_at(
                    &at("material"),
                    format!("frame section '{}' needs an elastic material; '{}' is a damage material (damage goes in shell layers and fiber sections)", p.section, p.material),
                ));
            }
            (SectionConfig::Tie(_), MaterialConfig::Damage(_)) => {
                return Err(src.error_at(
                    &at("material"),
                    format!("tie section '{}' needs an elastic material (type = \"elastic\": E, density); '{}' is a damage material", p.section, p.material),
                ));
            }
            _ => {}
        }
        if let (SectionConfig::Tie(_), Some(_)) = (section, &p.orientation) {
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
    Ok(())
}

/// `[[supports]]` fix at least one DOF; `[[loads]]` are finite.
fn validate_supports_and_loads(src: &Source, job: &StructuralJobFile) -> Result<(), ConfigError> {
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
    Ok(())
}

/// `[[masses]]` entry `i`: a group or a node, a mass and inertias that are finite and ≥ 0.
fn validate_point_mass(src: &Source, i: usize, m: &PointMassConfig) -> Result<(), ConfigError> {
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
    src.non_negative(&at("mass"), m.mass, "point mass", "kg")?;
    for (axis, x) in ["x", "y", "z"].iter().zip(m.rotary_inertia) {
        src.non_negative(&at("rotary_inertia"), x, &format!("rotary inertia about {axis}"), "kg m^2")?;
    }
    Ok(())
}

/// `[solver.petsc]`: every option value is a string, a number or a boolean.
fn validate_petsc_options(src: &Source, petsc: &BTreeMap<String, toml::Value>) -> Result<(), ConfigError> {
    for (k, v) in petsc {
        if matches!(v, toml::Value::Array(_) | toml::Value::Table(_) | toml::Value::Datetime(_)) {
            return Err(src.error_at(
                &Seg::path(&["solver", "petsc", k]),
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
        src.positive_finite(&at("targets", i, "frequency"), t.frequency, "target frequency", "Hz")?;
    }
    for (i, p) in u.parameters.iter().enumerate() {
        src.positive_finite(&at("parameters", i, "min"), p.min, "lower bound of the modulus factor", "")?;
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
