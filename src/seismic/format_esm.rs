//! ESM (Engineering Strong-Motion database) ASCII files.
//!
//! A header of `KEY: value` lines (64 in ESM files; the reader takes any number) followed by one
//! value per line. Keys used: `NDATA` (count), `SAMPLING_INTERVAL_S` (dt [s]), `UNITS`
//! (`cm/s^2` for acceleration files); `EVENT_NAME`, `STATION_CODE`, `STREAM` name the record
//! when present. The data start at the first line that holds only numbers.
use super::error::SeismicError;
use super::record::Record;
use super::text;
use super::units::AccelUnit;
use std::collections::HashMap;
use std::path::Path;

/// Reads an ESM ASCII acceleration file into a record in m/s².
pub fn read_esm(path: &Path) -> Result<Record, SeismicError> {
    parse_esm(&text::read(path)?, &path.display().to_string())
}

/// Parses the text of an ESM ASCII file; `file` names it in errors.
pub fn parse_esm(s: &str, file: &str) -> Result<Record, SeismicError> {
    let mut header: HashMap<String, (String, usize)> = HashMap::new();
    let mut accel = Vec::new();
    let mut in_data = false;
    for (k, line) in s.lines().enumerate() {
        let ln = k + 1;
        if line.trim().is_empty() {
            continue;
        }
        if !in_data && !text::is_numeric_line(line) {
            match line.split_once(':') {
                Some((key, value)) => {
                    header.insert(key.trim().to_ascii_uppercase(), (value.trim().to_string(), ln));
                }
                None => {
                    return Err(SeismicError::Parse {
                        file: file.into(),
                        line: ln,
                        reason: format!("expected 'KEY: value' or a number, found '{}'", line.trim()),
                    })
                }
            }
            continue;
        }
        in_data = true;
        for tok in line.split_whitespace() {
            accel.push(text::number(tok, file, ln)?);
        }
    }
    let last = s.lines().count();
    let get = |key: &str| {
        header.get(key).ok_or_else(|| SeismicError::Parse {
            file: file.into(),
            line: last,
            reason: format!("header has no {key}"),
        })
    };
    let (n_txt, n_line) = get("NDATA")?;
    let ndata = n_txt.parse::<usize>().map_err(|_| SeismicError::Parse {
        file: file.into(),
        line: *n_line,
        reason: format!("NDATA '{n_txt}' is not a count"),
    })?;
    let (dt_txt, dt_line) = get("SAMPLING_INTERVAL_S")?;
    let dt = text::number(dt_txt, file, *dt_line)?;
    let (u_txt, u_line) = get("UNITS")?;
    let unit = AccelUnit::parse(u_txt).ok_or_else(|| SeismicError::Parse {
        file: file.into(),
        line: *u_line,
        reason: format!("units '{u_txt}' are not an acceleration unit (cm/s^2, m/s^2, g)"),
    })?;
    if accel.len() != ndata {
        return Err(SeismicError::CountMismatch {
            file: file.into(),
            line: *n_line,
            declared: ndata,
            found: accel.len(),
        });
    }
    accel.iter_mut().for_each(|a| *a *= unit.to_si());
    let field = |k: &str| header.get(k).map(|v| v.0.clone()).unwrap_or_default();
    let name = [field("EVENT_NAME"), field("STATION_CODE"), field("STREAM")]
        .iter()
        .filter(|s| !s.is_empty())
        .cloned()
        .collect::<Vec<_>>()
        .join(" ");
    let name = if name.is_empty() { file.to_string() } else { name };
    Record::new(name, dt, accel, format!("read in {}, × {}", unit.name(), unit.to_si()), format!("ESM ASCII {file}"))
        .map_err(|e| match e {
            SeismicError::InvalidParameter { reason, .. } => {
                SeismicError::Parse { file: file.into(), line: *dt_line, reason }
            }
            e => e,
        })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn reads_header_and_converts_cm() {
        let s = "EVENT_NAME: TEST\nSTATION_CODE: ABC\nSTREAM: HNE\nNDATA: 3\nSAMPLING_INTERVAL_S: 0.005000\nUNITS: cm/s^2\nUSER5:\n1.0\n-2.5E+01\n0.0\n";
        let r = parse_esm(s, "t.ASC").unwrap();
        assert_eq!(r.name, "TEST ABC HNE");
        assert_eq!(r.dt, 0.005);
        // 1 cm/s² = 0.01 m/s² exactly (1 ulp for the product).
        assert!((r.accel[1] + 0.25).abs() < 1e-16);
    }

    #[test]
    fn errors_name_file_and_line() {
        let s = "NDATA: 4\nSAMPLING_INTERVAL_S: 0.01\nUNITS: cm/s^2\n1\n2\n3\n";
        let e = parse_esm(s, "n.ASC").unwrap_err();
        assert!(matches!(e, SeismicError::CountMismatch { line: 1, declared: 4, found: 3, .. }), "{e}");
        let s = "NDATA: 2\nSAMPLING_INTERVAL_S: 0.01\nUNITS: cm\n1\n2\n";
        assert!(parse_esm(s, "u.ASC").unwrap_err().to_string().starts_with("u.ASC:3:"));
        let s = "NDATA: 2\nSAMPLING_INTERVAL_S: 0.01\nUNITS: cm/s^2\n1\ninf\n";
        assert!(parse_esm(s, "i.ASC").unwrap_err().to_string().starts_with("i.ASC:5:"));
        let s = "NDATA: 2\nUNITS: cm/s^2\n1\n2\n";
        assert!(parse_esm(s, "d.ASC").unwrap_err().to_string().contains("SAMPLING_INTERVAL_S"));
    }
}

#[cfg(test)]
mod fixture_tests {
    use super::*;
    use crate::seismic::format_at2::read_at2;
    use std::path::PathBuf;

    fn fixture(name: &str) -> PathBuf {
        PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("tests/data/records").join(name)
    }

    #[test]
    fn fixtures_read_from_disk() {
        // Hand-written fixtures: values chosen so the converted peaks are exact multiples.
        let r = read_at2(&fixture("tiny.AT2")).unwrap();
        assert_eq!((r.len(), r.dt), (12, 0.01));
        // 0.03 g = 0.2941995 m/s² (g = 9.80665 exactly); 1e-15 for the product's rounding.
        assert!((crate::seismic::pga(&r) - 0.03 * 9.80665).abs() < 1e-15);
        let r = read_esm(&fixture("tiny_esm.ASC")).unwrap();
        assert_eq!((r.len(), r.dt), (6, 0.005));
        assert!((crate::seismic::pga(&r) - 0.2).abs() < 1e-15, "20 cm/s² = 0.2 m/s²");
        let e = read_esm(&fixture("missing.ASC")).unwrap_err();
        assert!(e.to_string().contains("missing.ASC"), "{e}");
    }
}
