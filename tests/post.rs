//! The pictures of any model: `scripts/post.sh` on a time history of the template building
//! (docs/own-building.md) cut to 0.05 s: a results folder without modes, as a sweep member's is,
//! with the model's own groups.
//!
//! ```text
//!   pictures     mesh.png, damage-tension.png, damage-tension-gravity.png,
//!                damage-compression.png, envelope-drift.png, monitors.png
//!   views.json   titles and view names without a church term; every view frames the whole
//!                model: its bounding box's largest normalized device coordinate below 1
//!   the CSV      damage-by-group.csv lists the model's groups (south, north, west, east,
//!                floor) and "all shells", after gravity and at the end
//! ```
//! The ParaView part is skipped, with the reason printed, without pvpython or Xvfb
//! (scripts/setup.sh --paraview).
mod common;
use common::*;
use std::path::PathBuf;
use std::process::Command;

fn root() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR"))
}

fn on_path(exe: &str) -> bool {
    std::env::var_os("PATH").map(|p| std::env::split_paths(&p).any(|d| d.join(exe).is_file())).unwrap_or(false)
}

/// Words of the church's pictures that have no place in another model's.
const CHURCH_TERMS: [&str; 8] = ["church", "nave", "choir", "tower", "vault", "entrance", "substructure", "sacristy"];

#[test]
fn post_draws_any_model_with_its_own_groups_and_frames_every_view() {
    let dir = scratch("post-template");
    let text = std::fs::read_to_string(root().join("jobs/template-building.toml")).unwrap();
    let text = text
        .replace("\"../meshes/house.msh\"", &format!("{:?}", root().join("meshes/house.msh").to_str().unwrap()))
        .replace(
            "\"records/template-building-01.txt\"",
            &format!("{:?}", root().join("jobs/records/template-building-01.txt").to_str().unwrap()),
        )
        .replace("duration = 12.0", "duration = 0.05")
        .replace("output_every = 10", "output_every = 1")
        .replace("dir = \"../results/template-building\"", "dir = \"out\"\nexisting = \"overwrite\"")
        .replace("law_file = \"../materials/", &format!("law_file = \"{}/materials/", root().to_str().unwrap()));
    std::fs::write(dir.join("house.toml"), text).unwrap();
    let o = run(2, &[dir.join("house.toml").to_str().unwrap()]);
    assert!(o.status.success(), "{}\n{}", stdout(&o), stderr(&o));
    let out = dir.join("out");
    assert!(out.join("groups.csv").is_file(), "the time history names its groups");

    let mut c = Command::new("bash");
    c.current_dir(root()).arg("scripts/post.sh").arg(&out).args(["--size", "800x600"]);
    let o = run_with_timeout(c, std::time::Duration::from_secs(600));
    let (so, se) = (stdout(&o), stderr(&o));
    assert_eq!(o.status.code(), Some(0), "{so}\n{se}");
    if !(on_path("pvpython") && on_path("Xvfb")) {
        assert!(so.contains("skipped the ParaView pictures"), "{so}");
        println!("pvpython or Xvfb missing: the ParaView pictures are skipped (scripts/setup.sh --paraview)");
        return;
    }
    let pictures = out.join("pictures");
    for png in
        ["mesh.png", "damage-tension.png", "damage-tension-gravity.png", "damage-compression.png", "envelope-drift.png"]
    {
        let img = image::open(pictures.join(png)).unwrap_or_else(|e| panic!("{png}: {e}")).to_rgb8();
        assert_eq!(img.dimensions(), (800, 600), "{png}");
    }
    let views: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(pictures.join("views.json")).unwrap()).unwrap();
    let views = views.as_array().unwrap();
    assert_eq!(views.len(), 5, "{views:?}");
    for p in views {
        let title = p["title"].as_str().unwrap().to_lowercase();
        for v in p["views"].as_array().unwrap() {
            let name = v["title"].as_str().unwrap().to_lowercase();
            for t in CHURCH_TERMS {
                assert!(!title.contains(t) && !name.contains(t), "'{t}' in {p}");
            }
            let extent = v["extent"].as_f64().unwrap();
            assert!(extent > 0.5 && extent < 1.0, "{}: view {} extent {extent}: not framed", p["file"], v["name"]);
        }
    }
    let mesh = views.iter().find(|p| p["file"] == "mesh.png").unwrap();
    let groups: Vec<&str> = mesh["groups"].as_array().unwrap().iter().map(|g| g.as_str().unwrap()).collect();
    assert_eq!(groups, ["south", "north", "west", "east", "floor"], "the legend names the model's groups");
    let csv = std::fs::read_to_string(pictures.join("damage-by-group.csv")).unwrap();
    let mut lines = csv.lines();
    assert!(lines.next().unwrap().starts_with("state,group,area_m2,share_dt_above_0.05,share_dt_above_0.5"), "{csv}");
    let rows: Vec<(String, String)> = lines
        .map(|l| {
            let f: Vec<&str> = l.split(',').collect();
            (f[0].to_string(), f[1].to_string())
        })
        .collect();
    for state in ["gravity", "end"] {
        let g: Vec<&str> = rows.iter().filter(|r| r.0 == state).map(|r| r.1.as_str()).collect();
        assert_eq!(g, ["south", "north", "west", "east", "floor", "all shells"], "{state}: {csv}");
    }
    let monitors = image::open(pictures.join("monitors.png"));
    assert!(monitors.is_ok(), "monitors.png: {so}");
}
