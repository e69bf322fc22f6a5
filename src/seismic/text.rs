//! Small helpers shared by the record readers: reading a file, parsing Fortran-style numbers.
use super::error::SeismicError;
use std::path::Path;

/// The file's text, or [`SeismicError::Io`] naming it.
pub(crate) fn read(path: &Path) -> Result<String, SeismicError> {
    std::fs::read_to_string(path).map_err(|source| SeismicError::Io { path: path.to_path_buf(), source })
}

/// A number as written by Fortran or C (`.1234E-02`, `1.0D-03`, `-5`); NaN/inf are refused
/// as [`SeismicError::NonFinite`], anything else unreadable as [`SeismicError::Parse`].
pub(crate) fn number(token: &str, file: &str, line: usize) -> Result<f64, SeismicError> {
    let t = token.trim().replace(['D', 'd'], "E");
    match t.parse::<f64>() {
        Ok(x) if x.is_finite() => Ok(x),
        Ok(_) => Err(SeismicError::NonFinite { file: file.into(), line, value: token.into() }),
        Err(_) => Err(SeismicError::Parse { file: file.into(), line, reason: format!("'{token}' is not a number") }),
    }
}

/// True for a line that holds only whitespace-separated numbers (at least one).
pub(crate) fn is_numeric_line(line: &str) -> bool {
    let mut any = false;
    for tok in line.split_whitespace() {
        let t = tok.replace(['D', 'd'], "E");
        if t.parse::<f64>().is_err() {
            return false;
        }
        any = true;
    }
    any
}

/// True for blank lines and comments (`#`, `%`, `!`).
pub(crate) fn is_comment(line: &str) -> bool {
    let t = line.trim_start();
    t.is_empty() || t.starts_with('#') || t.starts_with('%') || t.starts_with('!')
}
