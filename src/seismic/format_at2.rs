//! PEER NGA `.AT2` acceleration files.
//!
//! Layout (NGA-West2 flatfile records):
//!
//! ```text
//! PEER NGA STRONG MOTION DATABASE RECORD
//! IMPERIAL VALLEY 10/15/79 2316, EL CENTRO ARRAY #6, 230
//! ACCELERATION TIME SERIES IN UNITS OF G
//! NPTS=  3930, DT=   .0100 SEC
//!   .1234E-02  .2345E-02 ...        (values in g, usually 5 per line)
//! ```
//!
//! Line 4 varies between releases: `NPTS= 3930, DT= .0100 SEC`, `NPTS=3930 DT=0.01`, or the old
//! NGA-West1 form `3930    0.0100    NPTS, DT`. The reader looks for `NPTS` and `DT` keys (any
//! separators); without keys it takes the first integer and the first real of the line.
//! The unit is read from line 3 (`UNITS OF G`, or `CM/S^2`, `M/S^2`); g when it names none.
//! Fixed-width values glued together without a blank (`-.1E-02-.2E-02`) are not supported.
use super::error::SeismicError;
use super::record::Record;
use super::text;
use super::units::AccelUnit;
use std::path::Path;

/// Reads an `.AT2` file into a record in m/s².
pub fn read_at2(path: &Path) -> Result<Record, SeismicError> {
    let s = text::read(path)?;
    let name = path.file_stem().map(|s| s.to_string_lossy().into_owned()).unwrap_or_default();
    parse_at2(&s, &path.display().to_string(), &name)
}

/// The `NPTS` and `DT` of the header's fourth line.
fn npts_dt(line: &str, file: &str) -> Result<(usize, f64), SeismicError> {
    let up = line.to_ascii_uppercase();
    let err = |reason: String| SeismicError::Parse { file: file.into(), line: 4, reason };
    // Tokens split on anything that cannot be part of a number or a key.
    let toks: Vec<&str> =
        up.split(|c: char| c == ',' || c == '=' || c.is_whitespace()).filter(|t| !t.is_empty()).collect();
    let after = |key: &str| toks.iter().position(|t| *t == key).and_then(|i| toks.get(i + 1).copied());
    if let (Some(n), Some(d)) = (after("NPTS"), after("DT")) {
        let n = n.parse::<usize>().map_err(|_| err(format!("NPTS '{n}' is not a count")))?;
        let d = text::number(d, file, 4)?;
        return Ok((n, d));
    }
    // Old form: "3930    0.0100    NPTS, DT".
    let nums: Vec<&str> = toks.iter().copied().filter(|t| text::is_numeric_line(t)).collect();
    if nums.len() >= 2 {
        if let Ok(n) = nums[0].parse::<usize>() {
            return Ok((n, text::number(nums[1], file, 4)?));
        }
    }
    Err(err(format!("cannot find NPTS and DT in '{}'", line.trim())))
}

/// Parses the text of an `.AT2` file; `file` names it in errors, `name` becomes the record's name.
pub fn parse_at2(s: &str, file: &str, name: &str) -> Result<Record, SeismicError> {
    let lines: Vec<&str> = s.lines().collect();
    if lines.len() < 4 {
        return Err(SeismicError::Parse {
            file: file.into(),
            line: lines.len(),
            reason: "header needs 4 lines".into(),
        });
    }
    let unit_line = lines[2].to_ascii_uppercase();
    let unit = if unit_line.contains("CM/S") || unit_line.contains("GAL") {
        AccelUnit::CentimetersPerSecond2
    } else if unit_line.contains("M/S") {
        AccelUnit::MetersPerSecond2
    } else {
        AccelUnit::G
    };
    let (npts, dt) = npts_dt(lines[3], file)?;
    let mut accel = Vec::with_capacity(npts);
    for (k, line) in lines.iter().enumerate().skip(4) {
        for tok in line.split_whitespace() {
            accel.push(text::number(tok, file, k + 1)? * unit.to_si());
        }
    }
    if accel.len() != npts {
        return Err(SeismicError::CountMismatch { file: file.into(), line: 4, declared: npts, found: accel.len() });
    }
    Record::new(
        name,
        dt,
        accel,
        format!("read in {}, × {}", unit.name(), unit.to_si()),
        format!("PEER AT2 {file}: {}", lines[1].trim()),
    )
    .map_err(|e| match e {
        SeismicError::InvalidParameter { reason, .. } => SeismicError::Parse { file: file.into(), line: 4, reason },
        e => e,
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    const HEAD: &str =
        "PEER NGA STRONG MOTION DATABASE RECORD\nTEST 01/01/00, STATION, 000\nACCELERATION TIME SERIES IN UNITS OF G\n";

    #[test]
    fn reads_both_header_forms() {
        let s = format!("{HEAD}NPTS=    7, DT=   .0050 SEC\n  .1000E+00 -.2000E+00  .0 1.0D-01 0.5\n .25 0.0\n");
        let r = parse_at2(&s, "t.AT2", "t").unwrap();
        assert_eq!(r.len(), 7);
        assert_eq!(r.dt, 0.005);
        // 0.1 g = 0.980665 m/s² exactly by definition; 1 ulp tolerance for the product.
        assert!((r.accel[0] - 0.980665).abs() < 1e-15);
        assert!((r.accel[3] - 0.980665).abs() < 1e-15, "Fortran D exponent");
        let old = format!("{HEAD}    7    0.0050    NPTS, DT\n.1 .2 .3 .4 .5\n.6 .7\n");
        let r = parse_at2(&old, "old.AT2", "old").unwrap();
        assert_eq!((r.len(), r.dt), (7, 0.005));
        let nospace = format!("{HEAD}NPTS=7 DT=0.005\n.1 .2 .3 .4 .5\n.6 .7\n");
        assert_eq!(parse_at2(&nospace, "n.AT2", "n").unwrap().len(), 7);
    }

    #[test]
    fn errors_name_file_and_line() {
        let s = format!("{HEAD}NPTS= 3, DT= .01 SEC\n.1 .2\n.3 .4\n");
        let e = parse_at2(&s, "count.AT2", "c").unwrap_err();
        assert!(matches!(e, SeismicError::CountMismatch { declared: 3, found: 4, .. }), "{e}");
        assert!(e.to_string().contains("count.AT2"), "{e}");
        let s = format!("{HEAD}NPTS= 3, DT= .01 SEC\n.1 NaN .3\n");
        let e = parse_at2(&s, "nan.AT2", "n").unwrap_err();
        assert!(e.to_string().starts_with("nan.AT2:5:"), "{e}");
        let s = format!("{HEAD}NPTS= 3, DT= .01 SEC\n.1 x .3\n");
        assert!(parse_at2(&s, "x.AT2", "x").unwrap_err().to_string().starts_with("x.AT2:5:"));
        let s = format!("{HEAD}points and steps\n.1 .2 .3\n");
        assert!(parse_at2(&s, "h.AT2", "h").unwrap_err().to_string().starts_with("h.AT2:4:"));
        let s = format!("{HEAD}NPTS= 3, DT= 0.0 SEC\n.1 .2 .3\n");
        assert!(parse_at2(&s, "dt.AT2", "dt").unwrap_err().to_string().starts_with("dt.AT2:4:"));
    }
}
