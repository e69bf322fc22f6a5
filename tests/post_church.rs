//! The church pictures: `scripts/post_church.sh` on a small results folder written by the
//! program (tests/data/post_church/, made by the jobs there: the church meshed at 3 m, its three
//! lowest modes, then 0.16 s of a strong pulse so that tensile damage appears; README.md there).
//!
//! ```text
//!   missing file        results.h5 removed: exit code 1, the message names results.h5
//!   no ParaView         PVPYTHON pointing nowhere: exit code 0, the skip and its reason printed
//!   ParaView present    mesh.png, mode-1..3.png, damage-tension.png, damage-compression.png,
//!                       envelope-drift.png exist with the asked size and are not blank (share
//!                       of drawn pixels, luminance spread, number of colours); damage-tension.png
//!                       shows damage colours (d_t > ~0.55 is yellow to red in Turbo) where the
//!                       fixture has d_t up to its maximum; damage-by-substructure.csv's largest
//!                       d_t equals the one read from results.h5 with the hdf5 crate
//!   matplotlib present  monitors.png exists and is not blank
//! ```
//! Skipped parts print why (pvpython, xvfb-run or matplotlib missing: scripts/setup.sh --paraview).
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
    for f in ["modes.xdmf", "modes.h5", "results.xdmf", "results.h5", "envelopes.xdmf", "envelopes.h5", "monitors.csv", "summary.json"] {
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
    ["python3", "/usr/bin/python3"]
        .iter()
        .any(|p| Command::new(p).args(["-c", "import matplotlib"]).output().map(|o| o.status.success()).unwrap_or(false))
}

/// Share of drawn (non-white) pixels, luminance standard deviation, number of distinct colours.
fn not_blank(png: &Path, size: Option<(u32, u32)>) -> image::RgbImage {
    let img = image::open(png).unwrap_or_else(|e| panic!("{}: {e}", png.display())).to_rgb8();
    if let Some(s) = size {
        assert_eq!(img.dimensions(), s, "{}", png.display());
    }
    let n = (img.width() * img.height()) as f64;
    let drawn = img.pixels().filter(|p| p.0.iter().any(|&c| c < 235)).count() as f64 / n;
    let lum: Vec<f64> = img.pixels().map(|p| 0.299 * p.0[0] as f64 + 0.587 * p.0[1] as f64 + 0.114 * p.0[2] as f64).collect();
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

/// Pixels in the damaged part of the Turbo map (d ≳ 0.55: yellow, orange, red): strong red, little
/// blue. Undamaged cells are dark blue (d = 0: RGB 48, 18, 59), beams grey, the background white.
fn damage_pixels(img: &image::RgbImage) -> usize {
    img.pixels().filter(|p| p.0[0] > 150 && p.0[2] < 90 && p.0[0] as i32 - p.0[2] as i32 > 110).count()
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
    assert!(stdout(&o).contains("skipped the ParaView pictures (/nonexistent/pvpython is not installed"), "{}", stdout(&o));
    assert!(!dir.join("pictures/damage-tension.png").exists());
}

#[test]
fn the_church_pictures() {
    if !(on_path("pvpython") && on_path("xvfb-run")) {
        println!("skipped: pvpython or xvfb-run is not installed (scripts/setup.sh --paraview)");
        return;
    }
    let dir = fixture_copy("post-church");
    let t0 = std::time::Instant::now();
    let o = post(&dir, None);
    println!("{}\n{}", stdout(&o), stderr(&o));
    assert!(o.status.success(), "post_church.sh failed");
    println!("post_church.sh: {:.1} s", t0.elapsed().as_secs_f64());
    let pics = dir.join("pictures");
    for f in ["mesh.png", "mode-1.png", "mode-2.png", "mode-3.png", "damage-compression.png", "envelope-drift.png"] {
        not_blank(&pics.join(f), Some((800, 600)));
    }
    // The fixture's tensile damage, read independently.
    let h5 = hdf5::File::open(dir.join("results.h5")).unwrap();
    let times: Vec<f64> = h5.dataset("steps/times").unwrap().read_raw().unwrap();
    let d: Vec<f64> = h5.dataset(&format!("steps/{}/d_t_max", times.len() - 1)).unwrap().read_raw().unwrap();
    let d_max = d.iter().copied().filter(|x| x.is_finite()).fold(0.0, f64::max);
    assert!(d_max > 0.6, "the fixture should hold damage above 0.6 (max d_t {d_max})");
    let img = not_blank(&pics.join("damage-tension.png"), Some((800, 600)));
    let warm = damage_pixels(&img);
    println!("damage-tension.png: {warm} pixels in damage colours; max d_t {d_max:.3}");
    // Some tens of damaged cells in four views of an 800 x 600 picture: at least 0.1 %.
    assert!(warm as f64 > 1e-3 * 800.0 * 600.0, "no damage colours in damage-tension.png ({warm} pixels)");
    // The modes are coloured with Viridis, whose colours never pass the damage test: the test
    // tells the two apart (it could fail).
    let mode = image::open(pics.join("mode-1.png")).unwrap().to_rgb8();
    assert!(damage_pixels(&mode) < warm / 10, "mode-1.png has {} 'damage' pixels", damage_pixels(&mode));

    // The table's largest d_t (4 decimals in the CSV) is the file's.
    let table = std::fs::read_to_string(pics.join("damage-by-substructure.csv")).unwrap();
    let all = table.lines().find(|l| l.starts_with("all shells,")).expect("an 'all shells' row");
    let max: f64 = all.split(',').nth(4).unwrap().parse().unwrap();
    assert!((max - d_max).abs() < 1e-4, "table max {max} vs results.h5 {d_max}");
    for name in ["nave_vault", "nave_walls", "facade"] {
        assert!(table.lines().any(|l| l.starts_with(&format!("{name},"))), "no row for {name}:\n{table}");
    }

    if has_matplotlib() {
        not_blank(&pics.join("monitors.png"), None);
    } else {
        println!("skipped monitors.png: no Python with matplotlib");
    }
}
