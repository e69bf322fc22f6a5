//! The church pictures: `scripts/post_church.sh` on a small results folder written by the
//! program (tests/data/post_church/, made by the jobs there: the church meshed at 3 m, its three
//! lowest modes, then 0.16 s of a strong pulse so that tensile damage appears; README.md there).
//!
//! ```text
//!   missing file        results.h5 removed: exit code 1, the message names results.h5
//!   no ParaView         PVPYTHON pointing nowhere: exit code 0, the skip and its reason printed
//!   ParaView present    mesh.png, mode-1..3.png, damage-tension.png, damage-tension-gravity.png,
//!                       damage-compression.png, envelope-drift.png exist with the asked size and
//!                       are not blank (share of drawn pixels, luminance spread, number of
//!                       colours); damage-tension.png has pixels coloured by damage (and yellow
//!                       to red: d_t > ~0.5) where damage-compression.png (same views; the
//!                       fixture has no d_c) has none; damage-by-substructure.csv's largest d_t
//!                       at the first and the last step equal the ones read from results.h5
//!                       with the hdf5 crate
//!   matplotlib present  monitors.png exists and is not blank
//! ```
//! Skipped parts print why (pvpython, Xvfb or matplotlib missing: scripts/setup.sh --paraview).
mod common;
use common::*;
use std::path::{Path, PathBuf};
use std::process::Command;

fn root() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR"))
}

/// A scratch copy of the fixture folder (the pictures go into it).
fn fixture_copy(name: &str) -> PathBuf {
    let src = root().join("tests/data/post_church");
    let dir = scratch(name).join("church");
    std::fs::create_dir_all(&dir).unwrap();
    for f in [
        "modes.xdmf",
        "modes.h5",
        "results.xdmf",
        "results.h5",
        "envelopes.xdmf",
        "envelopes.h5",
        "monitors.csv",
        "summary.json",
    ] {
        std::fs::copy(src.join(f), dir.join(f)).unwrap_or_else(|e| panic!("fixture {f}: {e}"));
    }
    dir
}

fn post(dir: &Path, pvpython: Option<&str>) -> std::process::Output {
    let mut c = Command::new("bash");
    c.current_dir(root()).arg("scripts/post_church.sh").arg(dir).args(["--size", "800x600"]);
    if let Some(p) = pvpython {
        c.env("PVPYTHON", p);
    }
    run_with_timeout(c, std::time::Duration::from_secs(300))
}

fn on_path(exe: &str) -> bool {
    std::env::var_os("PATH").map(|p| std::env::split_paths(&p).any(|d| d.join(exe).is_file())).unwrap_or(false)
}

fn has_matplotlib() -> bool {
    ["python3", "/usr/bin/python3"].iter().any(|p| {
        Command::new(p).args(["-c", "import matplotlib"]).output().map(|o| o.status.success()).unwrap_or(false)
    })
}

/// Share of drawn (non-white) pixels, luminance standard deviation, number of distinct colours.
fn not_blank(png: &Path, size: Option<(u32, u32)>) -> image::RgbImage {
    let img = image::open(png).unwrap_or_else(|e| panic!("{}: {e}", png.display())).to_rgb8();
    if let Some(s) = size {
        assert_eq!(img.dimensions(), s, "{}", png.display());
    }
    let n = (img.width() * img.height()) as f64;
    let drawn = img.pixels().filter(|p| p.0.iter().any(|&c| c < 235)).count() as f64 / n;
    let lum: Vec<f64> =
        img.pixels().map(|p| 0.299 * p.0[0] as f64 + 0.587 * p.0[1] as f64 + 0.114 * p.0[2] as f64).collect();
    let mean = lum.iter().sum::<f64>() / n;
    let sd = (lum.iter().map(|l| (l - mean).powi(2)).sum::<f64>() / n).sqrt();
    let colours: std::collections::HashSet<[u8; 3]> = img.pixels().map(|p| p.0).collect();
    println!("{}: {:.1} % drawn, luminance sd {sd:.1}, {} colours", png.display(), 100.0 * drawn, colours.len());
    // A white picture has sd 0 and one colour; a four-view render of the church covers well over
    // 5 % of the picture and shades it with hundreds of colours.
    assert!(drawn > 0.05, "{}: almost blank ({:.2} % drawn)", png.display(), 100.0 * drawn);
    assert!(sd > 15.0, "{}: flat picture (luminance sd {sd:.1})", png.display());
    assert!(colours.len() > 100, "{}: only {} colours", png.display(), colours.len());
    img
}

/// Pixels of `img` coloured by damage where `reference` (the same views without damage) is not:
/// (coloured, of which yellow to red). The colour map (pv_church.py's LIGHT_RAINBOW) is light
/// grey-blue at 0 (RGB 209, 219, 235; shaded darker, never saturated), then blue, green, yellow,
/// orange, dark red: "coloured" = max − min of the channels above 60 (beams are grey, the
/// background white, the text black); "yellow to red" (d ≳ 0.5) = red above 150 and red − blue
/// above 110. The colour bar and the axes triads are the same in both pictures.
fn damage_pixels(img: &image::RgbImage, reference: &image::RgbImage) -> (usize, usize) {
    let sat = |p: &image::Rgb<u8>| p.0.iter().max().unwrap() - p.0.iter().min().unwrap();
    let warm = |p: &image::Rgb<u8>| p.0[0] > 150 && p.0[0] as i32 - p.0[2] as i32 > 110;
    let (mut coloured, mut strong) = (0, 0);
    for (p, r) in img.pixels().zip(reference.pixels()) {
        if sat(p) > 60 && sat(r) < 40 {
            coloured += 1;
            if warm(p) {
                strong += 1;
            }
        }
    }
    (coloured, strong)
}

#[test]
fn a_missing_result_file_is_named() {
    let dir = fixture_copy("post-missing");
    std::fs::remove_file(dir.join("results.h5")).unwrap();
    let o = post(&dir, None);
    assert_eq!(o.status.code(), Some(1), "{}\n{}", stdout(&o), stderr(&o));
    assert!(stderr(&o).contains("missing results.h5"), "{}", stderr(&o));
}

#[test]
fn without_paraview_the_pictures_are_skipped_with_the_reason() {
    let dir = fixture_copy("post-noparaview");
    let o = post(&dir, Some("/nonexistent/pvpython"));
    assert!(o.status.success(), "{}\n{}", stdout(&o), stderr(&o));
    assert!(
        stdout(&o).contains("skipped the ParaView pictures (/nonexistent/pvpython is not installed"),
        "{}",
        stdout(&o)
    );
    assert!(!dir.join("pictures/damage-tension.png").exists());
}

#[test]
fn the_church_pictures() {
    if !(on_path("pvpython") && on_path("Xvfb")) {
        println!("skipped: pvpython or Xvfb is not installed (scripts/setup.sh --paraview)");
        return;
    }
    let dir = fixture_copy("post-church");
    let t0 = std::time::Instant::now();
    let o = post(&dir, None);
    println!("{}\n{}", stdout(&o), stderr(&o));
    assert!(o.status.success(), "post_church.sh failed");
    println!("post_church.sh: {:.1} s", t0.elapsed().as_secs_f64());
    let pics = dir.join("pictures");
    for f in [
        "mesh.png",
        "mode-1.png",
        "mode-2.png",
        "mode-3.png",
        "damage-compression.png",
        "damage-tension-gravity.png",
        "envelope-drift.png",
    ] {
        not_blank(&pics.join(f), Some((800, 600)));
    }
    // The fixture's tensile damage, read independently.
    let h5 = hdf5::File::open(dir.join("results.h5")).unwrap();
    let times: Vec<f64> = h5.dataset("steps/times").unwrap().read_raw().unwrap();
    let d: Vec<f64> = h5.dataset(&format!("steps/{}/d_t_max", times.len() - 1)).unwrap().read_raw().unwrap();
    let d_max = d.iter().copied().filter(|x| x.is_finite()).fold(0.0, f64::max);
    assert!(d_max > 0.6, "the fixture should hold damage above 0.6 (max d_t {d_max})");
    let tension = not_blank(&pics.join("damage-tension.png"), Some((800, 600)));
    // The fixture has no compressive damage: damage-compression.png, drawn with the same views,
    // colour map and bar, is the picture of the church without damage. Damage shows as pixels
    // that are coloured in damage-tension.png and not in it.
    let dc: Vec<f64> = h5.dataset(&format!("steps/{}/d_c_max", times.len() - 1)).unwrap().read_raw().unwrap();
    let dc_max = dc.iter().copied().filter(|x| x.is_finite()).fold(0.0, f64::max);
    assert!(dc_max < 0.05, "the fixture was expected without compressive damage (max d_c {dc_max})");
    let reference = not_blank(&pics.join("damage-compression.png"), Some((800, 600)));
    let (coloured, strong) = damage_pixels(&tension, &reference);
    println!(
        "damage-tension.png: {coloured} pixels coloured by damage, {strong} of them yellow to red; max d_t {d_max:.3}"
    );
    // 12 damaged cells of about 3 m x 3 m, a few of them seen in each of four 400 x 278 views.
    assert!(coloured > 400, "too few damage colours in damage-tension.png ({coloured} pixels)");
    assert!(strong > 50, "no damage above 0.5 drawn in damage-tension.png ({strong} pixels)");
    let (_, wrong) = damage_pixels(&reference, &tension);
    assert_eq!(wrong, 0, "damage-compression.png has damage colours where damage-tension.png has none");

    // The table's largest d_t (4 decimals in the CSV) is the file's.
    let table = std::fs::read_to_string(pics.join("damage-by-substructure.csv")).unwrap();
    let all = table.lines().find(|l| l.starts_with("end,all shells,")).expect("an 'all shells' row at the end");
    let max: f64 = all.split(',').nth(5).unwrap().parse().unwrap();
    assert!((max - d_max).abs() < 1e-4, "table max {max} vs results.h5 {d_max}");
    // The first step's rows: the fixture starts undamaged (no gravity, the pulse starts at 0).
    let first =
        table.lines().find(|l| l.starts_with("gravity,all shells,")).expect("an 'all shells' row after gravity");
    let max0: f64 = first.split(',').nth(5).unwrap().parse().unwrap();
    let d0: Vec<f64> = h5.dataset("steps/0/d_t_max").unwrap().read_raw().unwrap();
    let d0_max = d0.iter().copied().filter(|x| x.is_finite()).fold(0.0, f64::max);
    assert!((max0 - d0_max).abs() < 1e-4, "table max after gravity {max0} vs results.h5 step 0 {d0_max}");
    for state in ["gravity", "end"] {
        for name in ["nave_vault", "nave_walls", "facade"] {
            assert!(
                table.lines().any(|l| l.starts_with(&format!("{state},{name},"))),
                "no {state} row for {name}:\n{table}"
            );
        }
    }

    if has_matplotlib() {
        not_blank(&pics.join("monitors.png"), None);
    } else {
        println!("skipped monitors.png: no Python with matplotlib");
    }
}
