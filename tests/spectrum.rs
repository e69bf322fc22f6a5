//! The spectrum job through the program: the record read back independently, the outputs, and
//! bad input (alone and under mpirun -n 2).
mod common;
use common::*;
use std::path::Path;

fn job(dir: &Path, record_line: &str) -> std::path::PathBuf {
    let root = Path::new(env!("CARGO_MANIFEST_DIR"));
    let rec = root.join("jobs/records/vallorcine-like-synthetic.txt");
    let text = format!(
        "[analysis]\ntype = \"spectrum\"\ndamping = 0.05\n[record]\n{}\nformat = \"two_column\"\nunits = \"m/s2\"\n\
         [ec8]\nground = \"A\"\nag = 1.6\n[output]\ndir = \"out\"\nexisting = \"overwrite\"\n",
        record_line.replace("RECORD", rec.to_str().unwrap())
    );
    std::fs::write(dir.join("sp.toml"), text).unwrap();
    dir.join("sp.toml")
}

#[test]
fn spectrum_of_the_synthetic_record() {
    // Independent check: the PGA the job reports equals max |a| of the committed file, read
    // here by plain parsing (1e-12 relative); Sa at the shortest period (0.02 s, a nearly rigid
    // oscillator) is within 5% of the PGA.
    let root = Path::new(env!("CARGO_MANIFEST_DIR"));
    let text = std::fs::read_to_string(root.join("jobs/records/vallorcine-like-synthetic.txt")).unwrap();
    let pga = text
        .lines()
        .filter(|l| !l.trim_start().starts_with('#') && !l.trim().is_empty())
        .map(|l| l.split_whitespace().nth(1).unwrap().parse::<f64>().unwrap().abs())
        .fold(0.0, f64::max);
    for np in [0, 2] {
        let dir = scratch(&format!("spectrum-{np}"));
        let f = job(&dir, "file = \"RECORD\"");
        let out = run(np, &[f.to_str().unwrap()]);
        assert!(out.status.success(), "np={np}: {}", stderr(&out));
        let s: serde_json::Value = common::summary(&dir.join("out"));
        assert!((s["pga"].as_f64().unwrap() - pga).abs() <= 1e-12 * pga, "{s} vs {pga}");
        let csv = std::fs::read_to_string(dir.join("out/spectrum.csv")).unwrap();
        let row: Vec<f64> = csv.lines().nth(2).unwrap().split(',').map(|v| v.parse().unwrap()).collect();
        assert!((row[0] - 0.02).abs() < 1e-12 && (row[3] - pga).abs() < 0.05 * pga, "{row:?}");
        for png in ["spectrum.png", "record.png"] {
            assert_eq!(&std::fs::read(dir.join("out").join(png)).unwrap()[1..4], b"PNG");
        }
    }
}

#[test]
fn a_missing_record_file_is_located() {
    let dir = scratch("spectrum-missing");
    let f = job(&dir, "file = \"nope.txt\"");
    for np in [0, 2] {
        let out = run(np, &[f.to_str().unwrap()]);
        let err = stderr(&out);
        assert_eq!(out.status.code(), Some(2), "{err}");
        assert!(err.contains("sp.toml:5:1: key 'record.file'") && err.contains("nope.txt"), "np={np}: {err}");
        assert_eq!(err.matches("error:").count(), 1, "{err}");
    }
}
