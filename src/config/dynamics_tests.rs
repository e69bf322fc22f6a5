//! `[dynamics] integration`: read, defaulted, refused with the key named.
use crate::config::{IntegrationKind, Job, NewtonKind};

/// A time-history job (frame elements; the mesh is not read at load) with `extra` in
/// `[dynamics]`, loaded from a file of its own.
fn load(extra: &str) -> Result<Job, String> {
    let text = format!(
        "[analysis]\ntype = \"time_history\"\n[mesh]\nfile = \"m.msh\"\n\
         [materials.steel]\ntype = \"elastic\"\nE = 210e9\nnu = 0.3\n\
         [sections.s]\ntype = \"frame\"\narea = 1e-3\niy = 1e-6\niz = 1e-6\nj = 2e-6\n\
         [[parts]]\ngroup = \"beams\"\nsection = \"s\"\nmaterial = \"steel\"\n\
         [dynamics]\nduration = 1.0\ndt = 0.01\n{extra}\n\
         [[dynamics.ground_motion]]\ndirection = \"x\"\nsynthetic = \"vallorcine_like\"\n"
    );
    let dir = std::env::temp_dir().join(format!("mhpc-dynamics-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    static NEXT: std::sync::atomic::AtomicUsize = std::sync::atomic::AtomicUsize::new(0);
    let k = NEXT.fetch_add(1, std::sync::atomic::Ordering::SeqCst);
    let f = dir.join(format!("job-{k}.toml"));
    std::fs::write(&f, text).unwrap();
    Job::load(&f).map_err(|e| e.to_string())
}

fn integration(job: &Job) -> (IntegrationKind, NewtonKind) {
    let d = job.spec.dynamics.as_ref().unwrap();
    (d.integration, d.newton)
}

#[test]
fn implicit_is_the_default_and_implex_is_read() {
    assert_eq!(integration(&load("").unwrap()), (IntegrationKind::Implicit, NewtonKind::Modified));
    assert_eq!(integration(&load("integration = \"implicit\"").unwrap()).0, IntegrationKind::Implicit);
    for newton in ["modified", "tangent", "krylov"] {
        let job = load(&format!("integration = \"implex\"\nnewton = \"{newton}\"")).unwrap();
        assert_eq!(integration(&job).0, IntegrationKind::Implex, "{newton}");
    }
}

#[test]
fn an_unknown_integration_is_refused_at_its_key() {
    let e = load("integration = \"explicit\"").err().expect("refused");
    assert!(e.contains("dynamics.integration") && e.contains("implicit") && e.contains("implex"), "{e}");
}

#[test]
fn implex_with_the_initial_stiffness_is_refused_at_the_newton_key() {
    let e = load("integration = \"implex\"\nnewton = \"initial\"").err().expect("refused");
    assert!(e.contains("dynamics.newton") && e.contains("implex"), "{e}");
    assert!(load("integration = \"implicit\"\nnewton = \"initial\"").is_ok());
}

#[test]
fn the_implex_split_is_read_and_refused_without_implex() {
    use crate::material::implex::SplitAt;
    let split = |extra: &str| load(extra).map(|j| j.spec.dynamics.unwrap().implex_split);
    assert_eq!(split("integration = \"implex\"").unwrap(), None);
    assert_eq!(split("integration = \"implex\"\nimplex_split = \"frozen\"").unwrap(), Some(SplitAt::Frozen));
    assert_eq!(split("integration = \"implex\"\nimplex_split = \"current\"").unwrap(), Some(SplitAt::Current));
    let e = split("implex_split = \"frozen\"").expect_err("refused");
    assert!(e.contains("dynamics.implex_split") && e.contains("implex"), "{e}");
    let e = split("integration = \"implex\"\nimplex_split = \"late\"").expect_err("refused");
    assert!(e.contains("dynamics.implex_split") && e.contains("frozen"), "{e}");
}

#[test]
fn implex_corrections_are_read_and_refused_without_implex_or_out_of_range() {
    let k = |extra: &str| load(extra).map(|j| j.spec.dynamics.unwrap().implex_corrections);
    assert_eq!(k("").unwrap(), 0, "IMPL-EX as published by default");
    assert_eq!(k("integration = \"implex\"\nimplex_corrections = 2").unwrap(), 2);
    let e = k("implex_corrections = 2").expect_err("refused");
    assert!(e.contains("dynamics.implex_corrections") && e.contains("implex"), "{e}");
    let e = k("integration = \"implex\"\nimplex_corrections = 11").expect_err("refused");
    assert!(e.contains("dynamics.implex_corrections") && e.contains("0 to 10"), "{e}");
    let e = k("integration = \"implex\"\nimplex_corrections = -1").expect_err("refused");
    assert!(e.contains("implex_corrections"), "{e}");
}

#[test]
fn implex_correction_tolerance_is_read_and_refused_out_of_range() {
    let tol = |extra: &str| load(extra).map(|j| j.spec.dynamics.unwrap().implex_correction_tolerance);
    let implex = "integration = \"implex\"\nimplex_corrections = 4\n";
    assert_eq!(tol(implex).unwrap(), super::DEFAULT_IMPLEX_CORRECTION_TOLERANCE);
    assert_eq!(tol(&format!("{implex}implex_correction_tolerance = 0.0")).unwrap(), 0.0);
    for bad in ["-1e-3", "1.0", "nan"] {
        let e = tol(&format!("{implex}implex_correction_tolerance = {bad}")).expect_err("refused");
        assert!(e.contains("dynamics.implex_correction_tolerance") && e.contains("[0, 1)"), "{bad}: {e}");
    }
}

#[test]
fn implex_pass_tolerance_is_read_and_refused_without_corrections_or_out_of_range() {
    let tol = |extra: &str| load(extra).map(|j| j.spec.dynamics.unwrap().implex_pass_tolerance);
    let implex = "integration = \"implex\"\nimplex_corrections = 4\n";
    assert_eq!(tol(implex).unwrap(), None);
    assert_eq!(tol(&format!("{implex}implex_pass_tolerance = 1e-3")).unwrap(), Some(1e-3));
    let e = tol("integration = \"implex\"\nimplex_pass_tolerance = 1e-3").expect_err("no corrections");
    assert!(e.contains("dynamics.implex_pass_tolerance") && e.contains("implex_corrections > 0"), "{e}");
    for bad in ["0.0", "1.0", "nan"] {
        let e = tol(&format!("{implex}implex_pass_tolerance = {bad}")).expect_err("refused");
        assert!(e.contains("dynamics.implex_pass_tolerance") && e.contains("(0, 1)"), "{bad}: {e}");
    }
}

#[test]
fn implex_with_viscous_damage_is_refused_at_the_relaxation_key() {
    let e = load("integration = \"implex\"\ndamage_relaxation_time = 0.01").err().expect("refused");
    assert!(e.contains("dynamics.damage_relaxation_time") && e.contains("implicit"), "{e}");
}
