//! Plain-text records: two columns `t a`, or one column of `a` with a given dt; and the
//! two-column writer.
//!
//! Blank lines and lines starting with `#`, `%` or `!` are comments. Two-column files must have
//! strictly increasing time and a uniform step: every step within `dt_tolerance` (relative) of
//! the mean step `(t_last − t_first)/(n − 1)`; the record's clock restarts at 0 at the first sample.
//! A one-column file may hold several values per line (read in order).
use super::error::SeismicError;
use super::record::Record;
use super::text;
use super::units::AccelUnit;
use std::io::Write;
use std::path::Path;

/// Default relative tolerance on the uniformity of the time step (time columns printed with
/// 4–6 significant digits round steps by up to ~1e-4 relative at dt = 0.005 s).
pub const DEFAULT_DT_TOLERANCE: f64 = 1e-3;

fn stem(path: &Path) -> String {
    path.file_stem().map(|s| s.to_string_lossy().into_owned()).unwrap_or_default()
}

/// Reads a two-column `t a` file, acceleration in `unit`.
pub fn read_two_column(path: &Path, unit: AccelUnit, dt_tolerance: f64) -> Result<Record, SeismicError> {
    parse_two_column(&text::read(path)?, &path.display().to_string(), &stem(path), unit, dt_tolerance)
}

/// Parses two-column text; `file` names it in errors, `name` becomes the record's name.
pub fn parse_two_column(
    s: &str,
    file: &str,
    name: &str,
    unit: AccelUnit,
    dt_tolerance: f64,
) -> Result<Record, SeismicError> {
    let mut t = Vec::new();
    let mut a = Vec::new();
    let mut lines = Vec::new();
    for (k, line) in s.lines().enumerate() {
        if text::is_comment(line) {
            continue;
        }
        let toks: Vec<&str> = line.split_whitespace().collect();
        if toks.len() != 2 {
            return Err(SeismicError::Parse {
                file: file.into(),
                line: k + 1,
                reason: format!("expected 2 columns 't a', found {}", toks.len()),
            });
        }
        let (ti, ai) = (text::number(toks[0], file, k + 1)?, text::number(toks[1], file, k + 1)?);
        if let Some(&tp) = t.last() {
            if ti <= tp {
                return Err(SeismicError::NonMonotonicTime { file: file.into(), line: k + 1, t_prev: tp, t: ti });
            }
        }
        t.push(ti);
        a.push(ai * unit.to_si());
        lines.push(k + 1);
    }
    if t.len() < 2 {
        return Err(SeismicError::Parse {
            file: file.into(),
            line: s.lines().count(),
            reason: format!("{} data line(s), at least 2 needed", t.len()),
        });
    }
    let dt = (t[t.len() - 1] - t[0]) / (t.len() - 1) as f64;
    for i in 1..t.len() {
        let step = t[i] - t[i - 1];
        if (step - dt).abs() > dt_tolerance * dt {
            return Err(SeismicError::NonUniformDt {
                file: file.into(),
                line: lines[i],
                dt_mean: dt,
                dt_found: step,
                tolerance: dt_tolerance,
            });
        }
    }
    Record::new(name, dt, a, format!("read in {}, × {}", unit.name(), unit.to_si()), format!("two-column {file}"))
}

/// Reads a one-column file of accelerations in `unit` sampled every `dt`.
pub fn read_one_column(path: &Path, dt: f64, unit: AccelUnit) -> Result<Record, SeismicError> {
    parse_one_column(&text::read(path)?, &path.display().to_string(), &stem(path), dt, unit)
}

/// Parses one-column text (several values per line allowed).
pub fn parse_one_column(s: &str, file: &str, name: &str, dt: f64, unit: AccelUnit) -> Result<Record, SeismicError> {
    let mut a = Vec::new();
    for (k, line) in s.lines().enumerate() {
        if text::is_comment(line) {
            continue;
        }
        for tok in line.split_whitespace() {
            a.push(text::number(tok, file, k + 1)? * unit.to_si());
        }
    }
    Record::new(
        name,
        dt,
        a,
        format!("read in {}, × {}", unit.name(), unit.to_si()),
        format!("one-column {file}, dt = {dt} s"),
    )
}

/// Writes a record as two columns `t [s]  a [m/s²]` (time with 4 decimals, acceleration with
/// 7 significant digits), each header line prefixed by `# `.
pub fn write_two_column(r: &Record, path: &Path, header: &[String]) -> Result<(), SeismicError> {
    let io = |source| SeismicError::Io { path: path.to_path_buf(), source };
    if let Some(dir) = path.parent() {
        if !dir.as_os_str().is_empty() {
            std::fs::create_dir_all(dir).map_err(io)?;
        }
    }
    let mut out = String::with_capacity(24 * r.len() + 80 * header.len());
    for h in header {
        out.push_str("# ");
        out.push_str(h);
        out.push('\n');
    }
    for (i, a) in r.accel.iter().enumerate() {
        out.push_str(&format!("{:.4} {:.6e}\n", i as f64 * r.dt, a));
    }
    std::fs::File::create(path).and_then(|mut f| f.write_all(out.as_bytes())).map_err(io)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn two_column_checks_time() {
        let r = parse_two_column(
            "# t a\n0.0 1\n0.01 2\n\n0.02 3\n",
            "ok.txt",
            "ok",
            AccelUnit::CentimetersPerSecond2,
            1e-3,
        )
        .unwrap();
        assert!((r.dt - 0.01).abs() < 1e-15);
        assert!((r.accel[2] - 0.03).abs() < 1e-16);
        let e = parse_two_column("0 1\n0.01 2\n0.01 3\n", "m.txt", "m", AccelUnit::G, 1e-3).unwrap_err();
        assert!(matches!(e, SeismicError::NonMonotonicTime { line: 3, .. }), "{e}");
        let e = parse_two_column("0 1\n0.01 2\n0.025 3\n0.03 4\n", "u.txt", "u", AccelUnit::G, 1e-3).unwrap_err();
        assert!(matches!(e, SeismicError::NonUniformDt { line: 3, .. }), "{e}");
        assert!(e.to_string().starts_with("u.txt:3:"), "{e}");
        let e = parse_two_column("0 1 2\n", "c.txt", "c", AccelUnit::G, 1e-3).unwrap_err();
        assert!(e.to_string().starts_with("c.txt:1:"), "{e}");
    }

    #[test]
    fn one_column_and_round_trip() {
        let r = parse_one_column("% comment\n1 2\n3\n", "one.txt", "one", 0.02, AccelUnit::MetersPerSecond2).unwrap();
        assert_eq!(r.accel, vec![1.0, 2.0, 3.0]);
        let e = parse_one_column("1\nnan\n", "n.txt", "n", 0.02, AccelUnit::G).unwrap_err();
        assert!(e.to_string().starts_with("n.txt:2:"), "{e}");
        let dir = std::env::temp_dir().join(format!("mhpc-seismic-{}", std::process::id()));
        let f = dir.join("rt.txt");
        write_two_column(&r, &f, &["test".into()]).unwrap();
        let back = read_two_column(&f, AccelUnit::MetersPerSecond2, DEFAULT_DT_TOLERANCE).unwrap();
        assert_eq!(back.accel, r.accel);
        assert!((back.dt - 0.02).abs() < 1e-12);
    }
}
