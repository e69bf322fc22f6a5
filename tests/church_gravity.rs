//! The church of `jobs/church.toml` (the committed coarse mesh, the identified masonry law of
//! `materials/rubble-identified-spectral.toml`) under its own weight, on 1 and 2 ranks: it carries the
//! whole self-weight, and the nave vault's thrust matches a hand calculation.
//!
//! ```text
//!   job       jobs/church.toml as committed, as a time history of one 0.02 s step of the record
//!             (the gravity phase, 10 load steps, is the state of output step 0)
//!   checks    the gravity phase reaches λ = 1 (the run ends normally; a load it cannot carry
//!             stops it with "gravity: no static equilibrium");
//!             the thrust of each interior bay (x = 2.5-7.5, 7.5-12.5, 12.5-17.5 m: one tie and
//!             one transverse arch each) against the hand value below, within 10 %;
//!             the ties in tension; 1 vs 2 ranks: tie forces and thrusts within 1e-6 relative
//!             (Newton's force tolerance 1e-5 on the self-weight)
//! ```
//!
//! # The hand calculation: a hingeless segmental arch
//! The vault (a cylinder along x) is, per metre of nave, a circular arch of span 2c = 10.8 m and
//! rise f = 3.0 m (scripts/make_church_mesh.py: NAVE_WIDTH, NAVE_RISE; radius
//! R = (c² + f²)/(2f) = 6.36 m), monolithic with the walls at its springings: fixed ends. Its load
//! per unit arc length is the shell's weight w_v = t ρ g (nave_vault's thickness, vault_masonry's
//! density) plus, on the bands below z = 9.0 m (HAUNCH_FILL_TOP), the fill's
//! weight (nave_haunches' nonstructural mass × g). With the simply supported beam's moment M₀
//! and constant EI (axial shortening neglected: it changes H by 0.1 % here), the elastic-centre
//! method gives the horizontal thrust
//!
//! ```text
//!   H = ∫ M₀ (z − z̄) ds / ∫ (z − z̄)² ds,    z̄ = ∫ z ds / ∫ ds            (fixed ends)
//! ```
//!
//! (a two-hinged arch, z̄ → 0, gives 4 % less). H = 24.4 kN/m for the vault with the fill. Each
//! transverse arch (a frame along the vault's arc at x = 5, 10, 15; section `arch`, material
//! `elastic_masonry`) is the same arch under its own weight A ρ g per arc length: 44.6 kN. So
//! each interior bay thrusts 5 m × H plus one arch's thrust, 166.5 kN.
//!
//! The model's thrust is the horizontal force through the crown: the vault's hoop membrane force
//! in the crown cells (either side of y = 0) integrated along x over the bay, plus the axial
//! force of the transverse arch's crown elements, both times the cosine of their slope. (At the
//! crown of a symmetric arch under vertical loads the whole horizontal force crosses the crown
//! section, whatever then carries it: the ties, the walls' bending, the end walls.)
//! Computed on this mesh, with the identified law (10 nave-vault cells with d_t > 0.5 at the
//! end of gravity): +3.5 %, −4.0 %, −0.6 % in the three bays; the ties carry 39 %, 55 % and
//! 33 % of it (the tower stiffens the north wall of the third bay), the walls' bending and the
//! end walls the rest.
mod common;
use common::*;
use std::collections::BTreeMap;
use std::path::{Path, PathBuf};

fn root() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR"))
}

/// The nave vault's geometry (scripts/make_church_mesh.py): half span c = NAVE_WIDTH / 2,
/// rise, springing height, top of the haunch fill.
const HALF_SPAN: f64 = 5.4;
const RISE: f64 = 3.0;
const SPRINGING: f64 = 7.5;
const FILL_TOP: f64 = 9.0;
const G: f64 = 9.81;

/// Thrust H of a hingeless arch (module docs) from points along its axis, each
/// (y, z, ds, P): position across, height, arc length it stands for, vertical load there [N].
/// Midpoint rule; M₀(y) of the simply supported beam = R_A (y + c) − Σ_{loads left of y} P (y − y_P).
fn hingeless_arch_thrust(pts: &[(f64, f64, f64, f64)]) -> f64 {
    let total: f64 = pts.iter().map(|p| p.3).sum();
    let (mut left, mut left_moment) = (0.0, 0.0); // Σ P and Σ P y_P of the loads left of y
    let m0: Vec<f64> = pts
        .iter()
        .map(|&(y, _, _, p)| {
            let m = total / 2.0 * (y + HALF_SPAN) - (left * y - left_moment);
            left += p;
            left_moment += p * y;
            m
        })
        .collect();
    let length: f64 = pts.iter().map(|p| p.2).sum();
    let zbar = pts.iter().map(|p| p.1 * p.2).sum::<f64>() / length;
    let num: f64 = pts.iter().zip(&m0).map(|(p, m)| m * (p.1 - zbar) * p.2).sum();
    let den: f64 = pts.iter().map(|p| (p.1 - zbar).powi(2) * p.2).sum();
    num / den
}

/// The nave vault's circular arch (span 2 HALF_SPAN, RISE) in `n` equal pieces, under a load per
/// unit arc length `w(z)` [N/m per metre of arc], z the height above the springing.
fn circular_arch(n: usize, w: impl Fn(f64) -> f64) -> Vec<(f64, f64, f64, f64)> {
    let r = (HALF_SPAN * HALF_SPAN + RISE * RISE) / (2.0 * RISE);
    let zc = RISE - r; // centre height above the springing
    let half_angle = (HALF_SPAN / r).asin();
    let dth = 2.0 * half_angle / n as f64;
    (0..n)
        .map(|i| {
            let th = -half_angle + (i as f64 + 0.5) * dth;
            let z = zc + r * th.cos();
            (r * th.sin(), z, r * dth, w(z) * r * dth)
        })
        .collect()
}

/// The integration against a closed form: a parabolic arch z = f (1 − y²/c²) under a load
/// uniform along the span is funicular, M ≡ 0, so H = w (2c)² / (8 f) whatever the end fixity
/// (and whatever the weights ds). The midpoint M₀ is off by w dy²/8: 1e-9 relative here.
#[test]
fn hingeless_arch_thrust_of_a_funicular_parabola_is_w_l2_over_8f() {
    let (w, n) = (1000.0, 20_000);
    let dy = 2.0 * HALF_SPAN / n as f64;
    let pts: Vec<_> = (0..n)
        .map(|i| {
            let y = -HALF_SPAN + (i as f64 + 0.5) * dy;
            let slope = -2.0 * RISE * y / (HALF_SPAN * HALF_SPAN);
            (y, RISE * (1.0 - y * y / (HALF_SPAN * HALF_SPAN)), dy * (1.0 + slope * slope).sqrt(), w * dy)
        })
        .collect();
    let h = hingeless_arch_thrust(&pts);
    let exact = w * (2.0 * HALF_SPAN).powi(2) / (8.0 * RISE);
    assert!((h / exact - 1.0).abs() < 1e-6, "H = {h}, w L^2 / 8f = {exact}");
}

/// The $PhysicalNames of a Gmsh file: tag → name.
fn physical_names(msh: &Path) -> BTreeMap<i64, String> {
    let text = std::fs::read_to_string(msh).unwrap();
    let mut lines = text.lines().skip_while(|l| *l != "$PhysicalNames").skip(1);
    let n: usize = lines.next().unwrap().trim().parse().unwrap();
    lines
        .take(n)
        .map(|l| {
            let mut it = l.splitn(3, ' ');
            let _dim = it.next();
            let tag = it.next().unwrap().parse().unwrap();
            (tag, it.next().unwrap().trim_matches('"').to_string())
        })
        .collect()
}

/// The cells of `results.h5` (XDMF mixed topology: quads 5, triangles 4, polylines 2 n): their
/// node indices.
fn cells(f: &hdf5::File) -> Vec<Vec<usize>> {
    let topo: Vec<i64> = f.dataset("mesh/topology").unwrap().read_raw().unwrap();
    let types: Vec<i64> = f.dataset("mesh/cell_types").unwrap().read_raw().unwrap();
    let mut pos = 0;
    types
        .iter()
        .map(|_| {
            let (n, skip) = match topo[pos] {
                5 => (4, 1),
                4 => (3, 1),
                2 => (topo[pos + 1] as usize, 2),
                c => panic!("cell type {c}"),
            };
            pos += skip;
            let c = topo[pos..pos + n].iter().map(|&v| v as usize).collect();
            pos += n;
            c
        })
        .collect()
}

/// The gravity state of one run: the tie forces (by x) and each interior bay's thrust.
struct Gravity {
    ties: Vec<(f64, f64)>,
    bays: Vec<f64>,
}

/// Reads output step 0 (the end of the gravity phase) of `out/results.h5`.
fn read_gravity(out: &Path, names: &BTreeMap<i64, String>) -> Gravity {
    let f = hdf5::File::open(out.join("results.h5")).unwrap();
    let xyz: Vec<f64> = f.dataset("mesh/coordinates").unwrap().read_raw().unwrap();
    let group: Vec<i64> = f.dataset("mesh/cell_group").unwrap().read_raw().unwrap();
    let field = |name: &str| -> Vec<f64> { f.dataset(&format!("steps/0/{name}")).unwrap().read_raw().unwrap() };
    let (nxx, nyy, nxy, axial) = (field("Nxx"), field("Nyy"), field("Nxy"), field("axial_force"));
    let tag = |name: &str| *names.iter().find(|(_, n)| *n == name).unwrap_or_else(|| panic!("no group {name}")).0;
    let (vault, ties, arches) = (tag("nave_vault"), tag("nave_ties"), tag("arches"));
    let p = |i: usize| nalgebra::Vector3::new(xyz[3 * i], xyz[3 * i + 1], xyz[3 * i + 2]);
    let mut tie_forces = Vec::new();
    let mut crown = Vec::new(); // (x min, x max, horizontal force per length or force, is_rib)
    for (e, c) in cells(&f).iter().enumerate() {
        let x: Vec<_> = c.iter().map(|&i| p(i)).collect();
        let centre = x.iter().sum::<nalgebra::Vector3<f64>>() / x.len() as f64;
        let (x0, x1) = x.iter().fold((f64::MAX, f64::MIN), |(a, b), v| (a.min(v.x), b.max(v.x)));
        if group[e] == ties {
            tie_forces.push((centre.x, axial[e]));
        } else if group[e] == arches && centre.y.abs() < 0.6 && centre.x < 19.0 {
            // A crown element of a transverse arch: compression negative; its slope's cosine.
            let d = (x[1] - x[0]).normalize();
            crown.push((centre.x, centre.x, -axial[e] * d.y.abs(), true));
        } else if group[e] == vault && c.len() == 4 && centre.y.abs() < 0.6 {
            // Local axes of the flat quad (src/element/shell/geometry.rs): e₃ the mean normal,
            // e₁ the mean direction of the sides 1→2 and 4→3.
            let e3 = (x[2] - x[0]).cross(&(x[3] - x[1])).normalize();
            let v = 0.5 * (x[1] + x[2] - x[0] - x[3]);
            let e1 = (v - e3 * v.dot(&e3)).normalize();
            let e2 = e3.cross(&e1);
            // The hoop direction: the cell's tangent normal to the generators (x).
            let t = nalgebra::Vector3::new(0.0, -e3.z, e3.y).normalize();
            let (a, b) = (e1.dot(&t), e2.dot(&t));
            let hoop = nxx[e] * a * a + nyy[e] * b * b + 2.0 * nxy[e] * a * b;
            crown.push((x0, x1, -hoop * t.y.abs(), false));
        }
    }
    tie_forces.sort_by(|a, b| a.0.total_cmp(&b.0));
    let bays = (1..=3)
        .map(|k| {
            let (lo, hi) = (5.0 * k as f64 - 2.5, 5.0 * k as f64 + 2.5);
            // Two vault cells per x station (either side of the crown): their mean times the
            // station's width; the rib's two crown elements: their mean.
            let shell: f64 = crown
                .iter()
                .filter(|c| !c.3 && c.0 >= lo - 1e-9 && c.1 <= hi + 1e-9)
                .map(|c| c.2 * (c.1 - c.0) / 2.0)
                .sum();
            let ribs: Vec<f64> =
                crown.iter().filter(|c| c.3 && (c.0 - 5.0 * k as f64).abs() < 0.5).map(|c| c.2).collect();
            assert_eq!(ribs.len(), 2, "bay {k}: the transverse arch's two crown elements");
            shell + ribs.iter().sum::<f64>() / 2.0
        })
        .collect();
    Gravity { ties: tie_forces, bays }
}

/// jobs/church.toml as a time history of one step (module docs), paths made absolute.
fn write_job(dir: &Path) -> PathBuf {
    let text = std::fs::read_to_string(root().join("jobs/church.toml")).unwrap();
    let (a, b) = (text.find("[analysis]").unwrap(), text.find("[mesh]").unwrap());
    let text = format!("{}[analysis]\ntype = \"time_history\"\n\n{}", &text[..a], &text[b..]);
    let root = root().display().to_string();
    let text = text
        .replace("\"../", &format!("\"{root}/"))
        .replace("file = \"records/", &format!("file = \"{root}/jobs/records/"))
        .replace("convergence = \"church-", &format!("convergence = \"{root}/jobs/church-"))
        .replacen("duration = 22.0", "duration = 0.02", 1)
        .replacen("output_every = 25", "output_every = 1", 1)
        .replace(&format!("dir = \"{root}/results/church\""), "dir = \"out\"")
        .replace("existing = \"backup\"", "existing = \"overwrite\"");
    assert!(text.contains("duration = 0.02") && text.contains("dir = \"out\""), "jobs/church.toml changed its layout");
    let job = dir.join("church-gravity.toml");
    std::fs::write(&job, text).unwrap();
    job
}

#[test]
fn church_carries_its_weight_on_the_identified_law_with_the_thrust_of_a_hingeless_arch() {
    // The hand thrust from the job's own section and material values.
    let job: toml::Table = toml::from_str(&std::fs::read_to_string(root().join("jobs/church.toml")).unwrap()).unwrap();
    let get = |path: &[&str]| -> f64 {
        let mut v = &toml::Value::Table(job.clone());
        for k in path {
            v = v.get(*k).unwrap_or_else(|| panic!("jobs/church.toml: no {}", path.join(".")));
        }
        v.as_float().unwrap()
    };
    assert!(job["materials"]["vault_masonry"]["law_file"]
        .as_str()
        .unwrap()
        .ends_with("rubble-identified-spectral.toml"));
    let w_vault = get(&["sections", "nave_vault", "thickness"]) * get(&["materials", "vault_masonry", "density"]) * G;
    assert_eq!(get(&["sections", "nave_haunches", "thickness"]), get(&["sections", "nave_vault", "thickness"]));
    let w_fill = get(&["sections", "nave_haunches", "nonstructural_mass"]) * G;
    let w_rib = get(&["sections", "arch", "area"]) * get(&["materials", "elastic_masonry", "density"]) * G;
    let h_vault = hingeless_arch_thrust(&circular_arch(20_000, |z| {
        if z < FILL_TOP - SPRINGING {
            w_vault + w_fill
        } else {
            w_vault
        }
    }));
    let h_rib = hingeless_arch_thrust(&circular_arch(20_000, |_| w_rib));
    let hand = 5.0 * h_vault + h_rib;
    eprintln!(
        "hand: vault with fill H = {:.2} kN/m, transverse arch {:.2} kN; per bay {:.1} kN",
        h_vault / 1e3,
        h_rib / 1e3,
        hand / 1e3
    );

    let base = scratch("church-gravity");
    let names = physical_names(&root().join("meshes/church.msh"));
    let mut runs = Vec::new();
    for np in [1, 2] {
        let dir = base.join(format!("np{np}"));
        std::fs::create_dir_all(&dir).unwrap();
        let job = write_job(&dir);
        let o = run(np, &[job.to_str().unwrap()]);
        assert!(o.status.success(), "np = {np}: the church did not carry its weight\n{}\n{}", stdout(&o), stderr(&o));
        assert!(stdout(&o).contains("gravity: λ = 1.0000"), "np = {np}\n{}", stdout(&o));
        let g = read_gravity(&dir.join("out"), &names);
        assert_eq!(g.ties.len(), 3, "np = {np}: three tie rods");
        for ((x, n), bay) in g.ties.iter().zip(&g.bays) {
            eprintln!(
                "np = {np}: bay at x = {x:.1}: thrust {:.1} kN ({:+.1} % against the hand value), tie {:.1} kN ({:.0} % of it)",
                bay / 1e3,
                100.0 * (bay / hand - 1.0),
                n / 1e3,
                100.0 * n / bay
            );
            assert!(*n > 0.0, "np = {np}: the tie at x = {x} is not in tension: {n} N");
            assert!(
                (bay / hand - 1.0).abs() < 0.10,
                "np = {np}: bay at x = {x}: thrust {bay:.0} N against {hand:.0} N by hand"
            );
        }
        runs.push(g);
    }
    for (a, b) in runs[0].ties.iter().zip(&runs[1].ties) {
        assert!((a.1 - b.1).abs() <= 1e-6 * a.1.abs(), "tie at x = {}: {} vs {} N on 1 and 2 ranks", a.0, a.1, b.1);
    }
    for (a, b) in runs[0].bays.iter().zip(&runs[1].bays) {
        assert!((a - b).abs() <= 1e-6 * a.abs(), "bay thrust {a} vs {b} N on 1 and 2 ranks");
    }
}
