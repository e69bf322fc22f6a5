//! The paper's wall as a layered shell in its plane, under a constant 1 MPa compression and an
//! in-plane shear pushover.
//!
//! ```text
//!        ux imposed →  ========== stiff platen (elastic frame), kept horizontal (ry = 0)
//!        σ = 1 MPa ↓  |          |
//!                     |   wall   |  1.0 m wide (x) × 1.2 m high (z), 0.5 m thick (shell, normal y)
//!                     |          |  damage law in every layer point; out-of-plane DOFs fixed
//!                     ############  base clamped
//! ```
//! Damage parameters: the illustrative rubble-masonry set of `jobs/material-tension.toml` with the
//! compressive threshold of the paper's strength (ε₀^c = 2e-4: damage in uniaxial compression
//! starts at E ε₀^c/(√2 ν) = 2.1 MPa, Table 1's σ_max), so the 1 MPa preload stays elastic.
mod common;
use common::*;

const W: f64 = 1.0;
const H: f64 = 1.2;
const T: f64 = 0.5;
const SIGMA: f64 = 1.0e6;
const TARGET: f64 = 2.0e-3;

/// Writes the wall with nx × nz quads and its job; returns the job path.
fn wall(dir: &std::path::Path, nx: usize, nz: usize, steps: usize) -> std::path::PathBuf {
    let idx = |i: usize, k: usize| k * (nx + 1) + i;
    let mut nodes = Vec::new();
    for k in 0..=nz {
        for i in 0..=nx {
            nodes.push([W * i as f64 / nx as f64, 0.0, H * k as f64 / nz as f64]);
        }
    }
    let mut quads = Vec::new();
    for k in 0..nz {
        for i in 0..nx {
            quads.push([idx(i, k), idx(i + 1, k), idx(i + 1, k + 1), idx(i, k + 1)]);
        }
    }
    let platen: Vec<[usize; 2]> = (0..nx).map(|i| [idx(i, nz), idx(i + 1, nz)]).collect();
    write_mixed_mesh(
        &dir.join("wall.msh"),
        &nodes,
        &[("wall", quads)],
        &[("platen", platen)],
        &[
            ("base", (0..=nx).map(|i| idx(i, 0)).collect()),
            ("top", (0..=nx).map(|i| idx(i, nz)).collect()),
            ("all", (0..nodes.len()).collect()),
        ],
    );
    let per_node = SIGMA * W * T / (nx + 1) as f64;
    let job = format!(
        "[analysis]\ntype = \"static_nonlinear\"\nsteps = 2\n\
         [analysis.control]\ngroup = \"top\"\ndof = \"ux\"\ntarget = {TARGET:e}\nsteps = {steps}\n\
         [mesh]\nfile = \"wall.msh\"\n\
         [materials.masonry]\ntype = \"damage\"\n[materials.masonry.law]\n\
         E = 2.885e9\nnu = 0.19\neps0_t = 5.0e-5\neps0_c = 2.0e-4\ngf_t = 20.0\na_c = 0.8\nb_c = 1500.0\n\
         regularization = \"hillerborg\"\n\
         [materials.steel]\ntype = \"elastic\"\nE = 2.0e11\nnu = 0.3\n\
         [sections.wall]\ntype = \"shell\"\nthickness = {T}\nlayers = 1\n\
         [sections.platen]\ntype = \"frame\"\narea = 0.5\niy = 0.05\niz = 0.05\nj = 0.05\n\
         [[parts]]\ngroup = \"wall\"\nsection = \"wall\"\nmaterial = \"masonry\"\n\
         [[parts]]\ngroup = \"platen\"\nsection = \"platen\"\nmaterial = \"steel\"\n\
         [[supports]]\ngroup = \"base\"\ndofs = [\"all\"]\n\
         [[supports]]\ngroup = \"all\"\ndofs = [\"uy\", \"rx\", \"rz\"]\n\
         [[supports]]\ngroup = \"top\"\ndofs = [\"ry\"]\n\
         [[loads]]\ntype = \"nodal\"\ngroup = \"top\"\nforce = [0.0, 0.0, {}]\n\
         [output]\ndir = \"out\"\nexisting = \"overwrite\"\n",
        -per_node
    );
    std::fs::write(dir.join("job.toml"), job).unwrap();
    dir.join("job.toml")
}

/// (displacement, force, dissipated energy) of the control stage.
fn curve(dir: &std::path::Path) -> Vec<(f64, f64, f64)> {
    let text = std::fs::read_to_string(dir.join("out/curve.csv")).unwrap();
    text.lines()
        .skip(1)
        .filter(|l| l.starts_with("control"))
        .map(|l| {
            let c: Vec<&str> = l.split(',').collect();
            (c[2].parse().unwrap(), c[3].parse().unwrap(), c[4].parse().unwrap())
        })
        .collect()
}

/// The wall passes its peak: on the 5 × 6 mesh with 14 increments to 2.8 mm the shear force
/// rises, peaks inside the run (measured: 0.3207 MN at 2.4 mm) and then falls (measured: 0.3171 MN
/// at 2.8 mm, 1.1% below the peak; 0.271 MN, 15% below, at 4 mm with 20 increments). Before the
/// unilateral switch of the plane-stress law was smoothed (material::plane_stress, "The switch")
/// every run stopped before the peak with the force still rising (1.16 mm on this mesh).
/// Asserted: the peak is not the last point, and the last force is at least 0.5% below it.
#[test]
fn wall_shear_passes_its_peak_and_softens() {
    let dir = scratch("wall-shear-peak");
    let job = wall(&dir, 5, 6, 14);
    let text = std::fs::read_to_string(&job).unwrap().replace("target = 2e-3", "target = 2.8e-3");
    std::fs::write(&job, text).unwrap();
    let out = run(0, &[job.to_str().unwrap()]);
    assert!(out.status.success(), "{}\n{}", stdout(&out), stderr(&out));
    let c = curve(&dir);
    let (k, peak) =
        c.iter().enumerate().map(|(k, x)| (k, x.1)).fold((0, f64::MIN), |a, b| if b.1 > a.1 { b } else { a });
    let last = c.last().unwrap();
    println!(
        "peak {peak:.4e} N at {:.3e} m; final {:.4e} N at {:.3e} m; dissipated {:.4e} J",
        c[k].0, last.1, last.0, last.2
    );
    assert!((last.0 - 2.8e-3).abs() < 1e-9, "the run reached the target");
    assert!(k + 1 < c.len(), "the force still rises at the end");
    assert!(last.1 < 0.995 * peak, "no softening after the peak: {} vs {peak}", last.1);
    // Diagonal localization of the compression damage: in each interior row of cells (rows 1–4 of
    // 0–5, away from the crushed base and top rows) the d_c-weighted centroid x̄ moves towards the
    // pushed side going down, along the compressed diagonal from the top-left to the bottom-right
    // corner (measured x̄ ≈ 0.67, 0.54, 0.47, 0.33 m from row 1 to 4). Asserted: x̄ decreases with
    // the height row by row and by more than 0.25 m over the four rows (a vertical band would not
    // move; the diagonal's own run over the four rows is 4 × 0.2 × W/H = 0.67 m).
    let f = hdf5::File::open(dir.join("out/results.h5")).unwrap();
    let steps: Vec<usize> =
        f.group("steps").unwrap().member_names().unwrap().iter().filter_map(|s| s.parse().ok()).collect();
    let dc: Vec<f64> =
        f.dataset(&format!("steps/{}/d_c_max", steps.iter().max().unwrap())).unwrap().read_raw().unwrap();
    let dc: Vec<f64> = dc.into_iter().filter(|x| x.is_finite()).collect(); // the quads (the platen has none)
    assert_eq!(dc.len(), 30);
    let centroid = |k: usize| {
        let row = &dc[5 * k..5 * k + 5];
        let w: f64 = row.iter().sum();
        assert!(w > 0.0, "no compression damage in row {k}");
        row.iter().enumerate().map(|(i, d)| d * (i as f64 + 0.5) * W / 5.0).sum::<f64>() / w
    };
    let xs: Vec<f64> = (1..=4).map(centroid).collect();
    println!("d_c-weighted centroid x per row 1..4: {xs:?}");
    assert!(xs.windows(2).all(|p| p[1] < p[0]) && xs[0] - xs[3] > 0.25, "no diagonal band: {xs:?}");
}

/// What works today, on the coarse mesh with few increments: the preload by load control, then
/// the shear pushover elastic up to the first crack and into the damaged range; the stiffness of
/// the elastic part matches the wall's shear-flexure stiffness of a fixed–fixed member,
/// K = 1/(H/(κ G A) + H³/(12 E I)) with κ = 5/6, A = W T, I = T W³/12, within 15% (the 2D stress
/// field at the clamped ends is stiffer than beam theory's; 5 × 6 elements).
#[test]
fn wall_shear_elastic_branch_and_first_damage() {
    let dir = scratch("wall-shear-elastic");
    let job = wall(&dir, 5, 6, 40);
    let text = std::fs::read_to_string(&job)
        .unwrap()
        .replace("target = 2e-3", "target = 6e-4")
        .replace("steps = 40", "steps = 6");
    std::fs::write(&job, text).unwrap();
    let out = run(0, &[job.to_str().unwrap()]);
    assert!(out.status.success(), "{}\n{}", stdout(&out), stderr(&out));
    let c = curve(&dir);
    assert_eq!(c.len(), 6);
    let (e, nu) = (2.885e9, 0.19);
    let g = e / (2.0 * (1.0 + nu));
    let k = 1.0 / (H / (5.0 / 6.0 * g * W * T) + H.powi(3) / (12.0 * e * T * W.powi(3) / 12.0));
    let k_fe = c[0].1 / c[0].0;
    println!("elastic stiffness {k_fe:.4e} N/m vs beam theory {k:.4e} N/m");
    assert!((k_fe - k).abs() < 0.15 * k, "{k_fe} vs {k}");
    assert!(c[0].2 == 0.0, "no damage in the first increment");
    assert!(c.last().unwrap().2 > 0.0, "damage by 0.6 mm");
}

/// The viscous damage option (`[analysis] damage_relaxation_time`, Duvaut–Lions on the damage
/// histories, material::state) on the 5 × 6 wall with A_c = 0.3 (residual compressive strength
/// 1.5 MPa, above the preload) and gf_c = 264.6 J/m², 14 increments to 2.8 mm, rate independent
/// and with τ = 0.002 and 0.0005 (of the stage's pseudo-time; the nominal increment is 1/14).
/// Duvaut–Lions converges to the rate-independent law as τ → 0, and the viscous stress lags
/// above the rate-independent envelope. Asserted: every run reaches the target; the peak force
/// does not fall as τ grows (1e-9 relative); the dissipated energy's distance to the
/// rate-independent one shrinks as τ goes from 0.002 to 0.0005. Measured: 319.9 J, 330.9 J
/// (+3.5%), 321.1 J (+0.4%); peaks 0.27788, 0.27920, 0.27812 MN.
#[test]
fn viscous_damage_tends_to_the_rate_independent_wall() {
    let mut results = Vec::new();
    for tau in [None, Some(0.002), Some(0.0005)] {
        let dir = scratch(&format!("wall-shear-viscous-{}", tau.map_or("none".to_string(), |t| t.to_string())));
        let job = wall(&dir, 5, 6, 14);
        let mut text = std::fs::read_to_string(&job)
            .unwrap()
            .replace("target = 2e-3", "target = 2.8e-3")
            .replace("a_c = 0.8\n", "a_c = 0.3\ngf_c = 264.6\n");
        if let Some(t) = tau {
            text = text.replace(
                "steps = 2\n[analysis.control]",
                &format!("steps = 2\ndamage_relaxation_time = {t}\n[analysis.control]"),
            );
            assert!(text.contains("damage_relaxation_time"));
        }
        std::fs::write(&job, text).unwrap();
        let out = run(0, &[job.to_str().unwrap()]);
        assert!(out.status.success(), "{}\n{}", stdout(&out), stderr(&out));
        let c = curve(&dir);
        let last = *c.last().unwrap();
        assert!((last.0 - 2.8e-3).abs() < 1e-9, "τ = {tau:?}: the run stopped at {}", last.0);
        let peak = c.iter().map(|x| x.1).fold(f64::MIN, f64::max);
        println!("τ = {tau:?}: peak {peak:.4e} N, dissipated {:.4e} J at 2.8 mm", last.2);
        results.push((peak, last.2));
    }
    let [(p0, e0), (p1, e1), (p2, e2)] = [results[0], results[1], results[2]];
    assert!(
        p1 >= p2 * (1.0 - 1e-9) && p2 >= p0 * (1.0 - 1e-9),
        "peaks {p1} (τ = 0.002), {p2} (0.0005), {p0} (rate independent)"
    );
    assert!((e2 - e0).abs() < (e1 - e0).abs(), "energies {e1} (τ = 0.002), {e2} (0.0005), {e0} (rate independent)");
}

/// The law of issue 5's acceptance case (jobs/wall-shear-fe.toml): the job law of [`wall`] with
/// A_c = 0.3 and G_c = 264.6 J/m² (see the test below for why).
fn acceptance_law(text: &str) -> String {
    text.replace("target = 2e-3", "target = 2.8e-3").replace("a_c = 0.8\n", "a_c = 0.3\ngf_c = 264.6\n")
}

/// d_c (largest over the layers) of the nx × nz quads at the last converged step, row by row
/// from the base (x fastest), and the cells' centroids.
fn compression_damage(dir: &std::path::Path, nx: usize, nz: usize) -> (Vec<f64>, Vec<[f64; 2]>) {
    let f = hdf5::File::open(dir.join("out/results.h5")).unwrap();
    let steps: Vec<usize> =
        f.group("steps").unwrap().member_names().unwrap().iter().filter_map(|s| s.parse().ok()).collect();
    let dc: Vec<f64> =
        f.dataset(&format!("steps/{}/d_c_max", steps.iter().max().unwrap())).unwrap().read_raw().unwrap();
    let dc: Vec<f64> = dc.into_iter().filter(|x| x.is_finite()).collect(); // the quads (points and the platen have none)
    assert_eq!(dc.len(), nx * nz);
    let centroids = (0..nx * nz)
        .map(|c| {
            [
                (c % nx) as f64 * W / nx as f64 + 0.5 * W / nx as f64,
                (c / nx) as f64 * H / nz as f64 + 0.5 * H / nz as f64,
            ]
        })
        .collect();
    (dc, centroids)
}

/// The d_c-weighted Pearson correlation of the cells' x and z: −1 when the compression damage lies
/// on the line from the top-left to the bottom-right corner (the strut of a wall pushed towards +x
/// at its top), 0 for a horizontal band or a uniform field, +1 on the other diagonal.
fn weighted_xz_correlation(d: &[f64], c: &[[f64; 2]]) -> f64 {
    let w: f64 = d.iter().sum();
    let mean = |k: usize| d.iter().zip(c).map(|(d, c)| d * c[k]).sum::<f64>() / w;
    let (mx, mz) = (mean(0), mean(1));
    let cov = |a: usize, ma: f64, b: usize, mb: f64| {
        d.iter().zip(c).map(|(d, c)| d * (c[a] - ma) * (c[b] - mb)).sum::<f64>() / w
    };
    cov(0, mx, 1, mz) / (cov(0, mx, 0, mx) * cov(1, mz, 1, mz)).sqrt()
}

/// Radius of the nonlocal averaging of issue 5's acceptance case (jobs/wall-shear-fe.toml):
/// about one stone of the paper's wall (ten courses of six stones in 1.2 × 1.0 m: 0.17 × 0.12 m),
/// and 2.25 elements of the coarsest of the three meshes.
const NONLOCAL_RADIUS: f64 = 0.15;

/// What one run of the acceptance case gives (see [`acceptance_run`]).
#[derive(Debug, Clone, Copy)]
#[allow(dead_code)] // the fields are read through Debug, in the printed line
struct Acceptance {
    peak: f64,
    peak_at: f64,
    last: f64,
    energy: f64,
    corr_c: f64,
    longest_column: f64,
}

/// Issue 5's acceptance case on an nx × nz mesh written by [`wall`] with the relaxation time
/// `tau`: the law of jobs/wall-shear-fe.toml (A_c = 0.3, G_c = 264.6 J/m², nonlocal radius
/// [`NONLOCAL_RADIUS`], residual tolerance 1e-4), the platen pushed 4 mm in 20 increments.
/// Asserted per run: the run reaches 4 mm; the force peaks inside the run and falls by more than
/// 10% after it (softening); the compression damage lies on the loaded diagonal (in the rows
/// between the top and bottom rows the d_c-weighted correlation of the cells' x and z is below
/// −0.5: −1 on the line from the top-left to the bottom-right corner, 0 for horizontal bands or
/// a uniform field); no vertical splitting crack: in no column of cells is d_t > 0.9 in 90% or
/// more of those rows (the splitting crack of the local law had d_t ≈ 1 over the whole height of
/// one column; a diagonal band crosses a column over at most its width divided by its slope).
/// `test` names the calling test: each has its own scratch directory (tests run concurrently).
fn acceptance_run(test: &str, nx: usize, nz: usize, tau: f64) -> Acceptance {
    let dir = scratch(&format!("wall-shear-{test}-{nx}x{nz}-tau{tau}"));
    let job = wall(&dir, nx, nz, 20);
    let text = acceptance_law(&std::fs::read_to_string(&job).unwrap())
        .replace("target = 2.8e-3", "target = 4e-3")
        .replace(
            "steps = 2\n[analysis.control]",
            &format!("steps = 2\nforce_tolerance = 1e-4\nenergy_tolerance = 1e-10\ndamage_relaxation_time = {tau}\nnonlocal_radius = {NONLOCAL_RADIUS}\n[analysis.control]"),
        );
    assert!(
        text.contains("damage_relaxation_time")
            && text.contains("nonlocal_radius")
            && text.contains("gf_c = 264.6")
            && text.contains("target = 4e-3")
    );
    std::fs::write(&job, text).unwrap();
    // The 25 × 30 mesh alone takes 216–231 s in a debug build on a 2-core AMD EPYC, and the
    // three meshes run at once: 900 s tells a hang from that work.
    let out = run_for(0, &[job.to_str().unwrap()], std::time::Duration::from_secs(900));
    assert!(out.status.success(), "{nx} x {nz}: {}\n{}", stdout(&out), stderr(&out));
    let c = curve(&dir);
    let last = *c.last().unwrap();
    assert!((last.0 - 4e-3).abs() < 1e-9, "{nx} x {nz}: stopped at {}", last.0);
    let (k, peak) =
        c.iter().enumerate().map(|(k, x)| (k, x.1)).fold((0, f64::MIN), |a, b| if b.1 > a.1 { b } else { a });
    assert!(
        k + 1 < c.len() && last.1 < 0.9 * peak,
        "{nx} x {nz}: no softening: peak {peak} at {}, final {}",
        c[k].0,
        last.1
    );
    // The rows under the platen and above the base crush over most of the width (bonded
    // ends): the diagonal is judged on the rows between them.
    let (dc, centroids) = compression_damage(&dir, nx, nz);
    let inner = nx..nx * (nz - 1);
    let corr_c = weighted_xz_correlation(&dc[inner.clone()], &centroids[inner]);
    let dt = tension_damage(&dir, nx, nz);
    let longest_column = (0..nx)
        .map(|i| (1..nz - 1).filter(|&r| dt[r * nx + i] > 0.9).count() as f64 / (nz - 2) as f64)
        .fold(0.0, f64::max);
    let a = Acceptance { peak, peak_at: c[k].0, last: last.1, energy: last.2, corr_c, longest_column };
    println!("{nx} x {nz}, tau {tau}: {a:?}");
    assert!(corr_c < -0.5, "{nx} x {nz}: compression damage not on the loaded diagonal (correlation {corr_c})");
    assert!(
        longest_column < 0.9,
        "{nx} x {nz}: a vertical splitting crack (d_t > 0.9 over {longest_column} of a column)"
    );
    a
}

/// d_t (largest over the layers) of the nx × nz quads at the last converged step, row by row
/// from the base (x fastest).
fn tension_damage(dir: &std::path::Path, nx: usize, nz: usize) -> Vec<f64> {
    let f = hdf5::File::open(dir.join("out/results.h5")).unwrap();
    let steps: Vec<usize> =
        f.group("steps").unwrap().member_names().unwrap().iter().filter_map(|s| s.parse().ok()).collect();
    let dt: Vec<f64> =
        f.dataset(&format!("steps/{}/d_t_max", steps.iter().max().unwrap())).unwrap().read_raw().unwrap();
    let dt: Vec<f64> = dt.into_iter().filter(|x| x.is_finite()).collect();
    assert_eq!(dt.len(), nx * nz);
    dt
}

/// Issue 5's acceptance case: "a shell wall with the paper's wall geometry under constant 1 MPa
/// compression and in-plane shear softens and localizes damage diagonally; the dissipated energy
/// varies less than 5% across three meshes" (the 5% is the issue's tolerance).
///
/// The case ([`acceptance_run`]): the wall of [`wall`] (1.0 × 1.2 × 0.5 m, 1 MPa by load
/// control, then the platen pushed 4 mm in 20 increments), the law of jobs/wall-shear-fe.toml:
/// A_c = 0.3 (residual compressive strength (1 − A_c) f_c = 1.5 MPa, above the 1 MPa preload),
/// G_c = 264.6 J/m², the viscous damage `damage_relaxation_time = 0.002`, and the nonlocal
/// averaging of the damage-driving strains within R = 0.15 m (material::nonlocal; the softening
/// regularized by R, not by the element size).
/// Without the averaging (the law before it) the post-peak mechanism was not unique: the 15 × 18
/// mesh written here took a vertical splitting crack along a mesh line (256 J against 428 J at
/// 2.8 mm), the meshes of scripts/make_quad_mesh.py (same geometry, other numbering) the diagonal
/// band, and on 20 × 24 τ/2 gave the splitting crack (234 J) where τ and τ/4 gave the band.
/// A second obstacle was the unilateral switch: with its band β = 0.1 (material::plane_stress,
/// "Why not narrower") the 25 × 30 mesh stopped at 3.62 mm, no increment converging even at
/// 2e-5 of the stage; with β = 0.3 every mesh reaches 4 mm.
///
/// Measured (this test's meshes, β = 0.3): the diagonal band of d_c, flexural cracks (d_t) at
/// the heel and the opposite top corner, no splitting crack on any mesh; peaks 278.1, 276.2 and
/// 275.2 kN at 2.2–2.3 mm, 232.9, 231.2 and 230.8 kN at 4 mm (−16 %); 606.2, 597.3 and 585.0 J
/// dissipated: (max − min)/mean = 3.55 %; d_c correlations −0.569, −0.599, −0.618; the longest
/// d_t > 0.9 run in a column 0.125, 0.136 and 0.143 of the inner rows. The meshes of
/// scripts/make_quad_mesh.py (the job's numbering) give 606.2, 597.3 and 584.5 J.
///
/// Asserted: per mesh, those of [`acceptance_run`]; across the 15 × 18, 20 × 24 and 25 × 30
/// meshes, (max − min) / mean of the dissipated energy at 4 mm below 0.05. The three meshes run
/// at the same time (the largest one sets the test's duration).
#[test]
fn wall_shear_dissipated_energy_agrees_across_three_meshes() {
    let runs: Vec<Acceptance> = std::thread::scope(|s| {
        let handles: Vec<_> = [(15, 18), (20, 24), (25, 30)]
            .map(|(nx, nz)| s.spawn(move || acceptance_run("meshes", nx, nz, 0.002)))
            .into_iter()
            .collect();
        handles.into_iter().map(|h| h.join().expect("the run panicked: its message is above")).collect()
    });
    let energies: Vec<f64> = runs.iter().map(|a| a.energy).collect();
    let mean = energies.iter().sum::<f64>() / 3.0;
    let spread =
        (energies.iter().cloned().fold(f64::MIN, f64::max) - energies.iter().cloned().fold(f64::MAX, f64::min)) / mean;
    println!("dissipated energies {energies:?} J, spread {spread:.4}");
    assert!(spread < 0.05, "the dissipated energy depends on the mesh: {energies:?} J, (max − min)/mean = {spread}");
}

/// The same mechanism whatever the viscosity: the acceptance case on the 20 × 24 mesh with
/// τ = 0.002 and τ/2 (where the local law jumped from the diagonal band to a splitting crack).
/// Asserted: both runs pass [`acceptance_run`]'s checks, and their dissipated energies at 4 mm
/// differ by less than 5% (the issue's tolerance for meshes, applied to τ).
/// Measured (this test's mesh, β = 0.3): τ 597.3 J, τ/2 595.0 J (0.4 %); peaks 276.2 and
/// 275.8 kN, 231.2 and 230.5 kN at 4 mm; d_c correlations −0.599 and −0.601; the longest
/// d_t > 0.9 run in a column 0.136 of the inner rows in both (the heel crack). Ignored for its
/// cost (minutes of CPU in the debug build).
#[test]
#[ignore = "minutes of CPU: cargo test --test wall_shear -- --ignored"]
fn wall_shear_mechanism_does_not_depend_on_the_viscosity() {
    let a = acceptance_run("viscosity", 20, 24, 0.002);
    let b = acceptance_run("viscosity", 20, 24, 0.001);
    let d = (a.energy - b.energy).abs() / a.energy;
    println!("tau: {:.1} J, tau/2: {:.1} J, relative difference {d:.4}", a.energy, b.energy);
    assert!(d < 0.05, "tau {} J vs tau/2 {} J", a.energy, b.energy);
}

/// The nonlocal option (`[analysis] nonlocal_radius`, analysis::nonlocal) on the 5 × 6 wall
/// (h = 0.2 m, R = 0.45 m) with A_c = 0.3, G_c = 264.6 J/m², 4 increments to 1.2 mm (damage
/// by then: the averages reach beyond a rank's cells), on 1 rank and on 2 ranks (METIS splits
/// the cells: the averaging gathers every rank's points). Asserted: both reach 1.2 mm, damage
/// has grown, and the force and the dissipated energy of every increment agree to 1e-6
/// relative (the same Newton iterates up to round-off; the residual tolerance is 1e-8).
#[test]
fn nonlocal_wall_agrees_on_one_and_two_ranks() {
    let mut curves = Vec::new();
    for np in [0, 2] {
        let dir = scratch(&format!("wall-shear-nonlocal-np{np}"));
        let job = wall(&dir, 5, 6, 4);
        let text = acceptance_law(&std::fs::read_to_string(&job).unwrap())
            .replace("target = 2.8e-3", "target = 1.2e-3")
            .replace("steps = 2\n[analysis.control]", "steps = 2\nnonlocal_radius = 0.45\n[analysis.control]");
        assert!(text.contains("nonlocal_radius = 0.45") && text.contains("target = 1.2e-3"));
        std::fs::write(&job, text).unwrap();
        let out = run(np, &[job.to_str().unwrap()]);
        assert!(out.status.success(), "np = {np}: {}\n{}", stdout(&out), stderr(&out));
        assert!(stdout(&out).contains("nonlocal averaging: radius 0.45 m"), "{}", stdout(&out));
        let c = curve(&dir);
        assert!((c.last().unwrap().0 - 1.2e-3).abs() < 1e-12, "np = {np}: stopped at {}", c.last().unwrap().0);
        assert!(c.last().unwrap().2 > 0.0, "np = {np}: no damage by 1.2 mm");
        curves.push(c);
    }
    assert_eq!(curves[0].len(), curves[1].len());
    for (a, b) in curves[0].iter().zip(&curves[1]) {
        println!("{:.3e} m: {:.6e} / {:.6e} N, {:.6e} / {:.6e} J", a.0, a.1, b.1, a.2, b.2);
        assert!((a.1 - b.1).abs() <= 1e-6 * a.1.abs(), "force {} vs {}", a.1, b.1);
        assert!((a.2 - b.2).abs() <= 1e-6 * a.2.abs().max(1e-3), "energy {} vs {}", a.2, b.2);
    }
}

/// Bad nonlocal input: a radius that is not positive is named with its key and line; a radius
/// on a model whose shells are elastic (nothing to average) stops with the reason. 1 and 2 ranks,
/// one message, exit code 2.
#[test]
fn nonlocal_radius_bad_input_is_named() {
    let dir = scratch("wall-shear-nonlocal-bad");
    let job = wall(&dir, 2, 2, 2);
    let text = std::fs::read_to_string(&job)
        .unwrap()
        .replace("steps = 2\n[analysis.control]", "steps = 2\nnonlocal_radius = -0.1\n[analysis.control]");
    std::fs::write(&job, &text).unwrap();
    expect_job_error(
        &job,
        2,
        &["key 'analysis.nonlocal_radius'", "job.toml:4:1", "nonlocal radius [m]: expected > 0, got -0.1"],
    );
    let elastic = text
        .replace("nonlocal_radius = -0.1", "nonlocal_radius = 0.1")
        .replace(
            "[materials.masonry]\ntype = \"damage\"\n[materials.masonry.law]\n",
            "[materials.masonry]\ntype = \"elastic\"\n",
        )
        .replace(
            "eps0_t = 5.0e-5\neps0_c = 2.0e-4\ngf_t = 20.0\na_c = 0.8\nb_c = 1500.0\nregularization = \"hillerborg\"\n",
            "",
        );
    assert!(elastic.contains("type = \"elastic\"\nE = 2.885e9\nnu = 0.19\n[materials.steel]"), "{elastic}");
    std::fs::write(&job, elastic).unwrap();
    expect_job_error(&job, 2, &["nonlocal_radius = 0.1", "no element of the model has a damage law"]);
}
