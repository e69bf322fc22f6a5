//! A cursor over the bytes of an MSH file that reads the format's three number kinds.
//!
//! MSH 4.1 has three number kinds: `size_t` (tags and counts, 8 bytes in binary), `int`
//! (dimensions, entity tags, element types, 4 bytes) and `double` (coordinates, 8 bytes). In an
//! ASCII file they are whitespace-separated tokens; in a binary file the section headers and
//! end markers are still text lines but the section bodies are raw numbers in the byte order
//! announced by `$MeshFormat`. [`Cursor::size`], [`Cursor::int`] and [`Cursor::double`] read
//! the next number in whichever encoding the file uses, so each section is parsed by one code
//! path. Text positions are tracked as line numbers, binary positions as byte offsets.
//!
//! The hot loop (one node or element after another) allocates nothing: tokens are sub-slices
//! of the file, integers are parsed by hand, floats by `str::parse` on the borrowed token.

use super::error::{show, Location, MshError};

/// A reading position in an MSH file.
pub(super) struct Cursor<'a> {
    data: &'a [u8],
    pos: usize,
    /// 1-based line number of `pos`, maintained while reading text.
    line: usize,
    /// Whether section bodies are binary.
    binary: bool,
    /// Byte order of binary numbers.
    big_endian: bool,
    /// The file path, for messages.
    pub path: &'a str,
    /// The section being read, for messages.
    pub section: &'a str,
}

fn is_ws(b: u8) -> bool {
    matches!(b, b' ' | b'\t' | b'\r' | b'\n' | b'\x0b' | b'\x0c')
}

/// Parses an unsigned decimal integer (an optional leading `+` allowed); `None` on anything else
/// or on overflow.
pub(super) fn parse_u64(tok: &[u8]) -> Option<u64> {
    let digits = tok.strip_prefix(b"+").unwrap_or(tok);
    if digits.is_empty() {
        return None;
    }
    let mut v: u64 = 0;
    for &b in digits {
        if !b.is_ascii_digit() {
            return None;
        }
        v = v.checked_mul(10)?.checked_add(u64::from(b - b'0'))?;
    }
    Some(v)
}

/// Parses a signed decimal integer that fits an `i32`.
pub(super) fn parse_i32(tok: &[u8]) -> Option<i32> {
    match tok.strip_prefix(b"-") {
        Some(rest) => {
            let v = i64::try_from(parse_u64(rest)?).ok()?;
            i32::try_from(-v).ok()
        }
        None => i32::try_from(parse_u64(tok)?).ok(),
    }
}

/// Parses a finite float.
pub(super) fn parse_f64(tok: &[u8]) -> Option<f64> {
    let v: f64 = std::str::from_utf8(tok).ok()?.parse().ok()?;
    v.is_finite().then_some(v)
}

/// Trims ASCII whitespace at both ends.
pub(super) fn trim(mut s: &[u8]) -> &[u8] {
    while let [first, rest @ ..] = s {
        if !is_ws(*first) {
            break;
        }
        s = rest;
    }
    while let [rest @ .., last] = s {
        if !is_ws(*last) {
            break;
        }
        s = rest;
    }
    s
}

impl<'a> Cursor<'a> {
    /// A text cursor at the start of `data`.
    pub fn new(data: &'a [u8], path: &'a str) -> Self {
        Cursor { data, pos: 0, line: 1, binary: false, big_endian: false, path, section: "MeshFormat" }
    }

    /// Switches section bodies to binary numbers of the given byte order.
    pub fn set_binary(&mut self, big_endian: bool) {
        self.binary = true;
        self.big_endian = big_endian;
    }

    /// The current position, as reported in messages.
    pub fn loc(&self) -> Location {
        if self.binary {
            Location::Byte(self.pos)
        } else {
            Location::Line(self.line)
        }
    }

    /// Where the next number starts (in text, after skipping whitespace).
    #[inline]
    pub fn next_loc(&mut self) -> Location {
        if !self.binary {
            self.skip_ws();
        }
        self.loc()
    }

    /// The current byte offset.
    pub fn offset(&self) -> usize {
        self.pos
    }

    /// Bytes not yet read.
    pub fn remaining(&self) -> usize {
        self.data.len() - self.pos
    }

    /// Skips whitespace, counting line breaks.
    pub fn skip_ws(&mut self) {
        while let Some(&b) = self.data.get(self.pos) {
            if !is_ws(b) {
                break;
            }
            if b == b'\n' {
                self.line += 1;
            }
            self.pos += 1;
        }
    }

    /// After skipping whitespace: the next line (trimmed, without its line break), consuming the
    /// line break itself and nothing after it (binary data may follow). `None` at end of file.
    pub fn next_line(&mut self) -> Option<(&'a [u8], Location)> {
        self.skip_ws();
        if self.pos >= self.data.len() {
            return None;
        }
        let at = self.loc();
        let rest = &self.data[self.pos..];
        let (line, used) = match rest.iter().position(|&b| b == b'\n') {
            Some(i) => (&rest[..i], i + 1),
            None => (rest, rest.len()),
        };
        self.pos += used;
        if used > line.len() {
            self.line += 1;
        }
        Some((trim(line), at))
    }

    /// Skips lines up to and including the line that reads `marker` (a skipped section's end).
    /// Returns `false` if the file ends first.
    pub fn skip_to_line(&mut self, marker: &[u8]) -> bool {
        while self.pos < self.data.len() {
            let rest = &self.data[self.pos..];
            let (line, used) = match rest.iter().position(|&b| b == b'\n') {
                Some(i) => (&rest[..i], i + 1),
                None => (rest, rest.len()),
            };
            self.pos += used;
            if used > line.len() {
                self.line += 1;
            }
            if trim(line) == marker {
                return true;
            }
        }
        false
    }

    /// The next whitespace-separated token and where it starts.
    pub fn token(&mut self, what: &'static str) -> Result<(&'a [u8], Location), MshError> {
        self.skip_ws();
        if self.pos >= self.data.len() {
            return Err(self.truncated(what));
        }
        let at = self.loc();
        let start = self.pos;
        while let Some(&b) = self.data.get(self.pos) {
            if is_ws(b) {
                break;
            }
            self.pos += 1;
        }
        Ok((&self.data[start..self.pos], at))
    }

    /// The next `n` raw bytes.
    pub fn bytes<const N: usize>(&mut self, what: &'static str) -> Result<[u8; N], MshError> {
        let Some(s) = self.data.get(self.pos..self.pos + N) else {
            self.pos = self.data.len();
            return Err(self.truncated(what));
        };
        let mut a = [0u8; N];
        a.copy_from_slice(s);
        self.pos += N;
        Ok(a)
    }

    /// A `size_t` (tag or count) and where it starts.
    #[inline]
    pub fn size(&mut self, what: &'static str) -> Result<(u64, Location), MshError> {
        if self.binary {
            let at = self.loc();
            let b = self.bytes::<8>(what)?;
            Ok((if self.big_endian { u64::from_be_bytes(b) } else { u64::from_le_bytes(b) }, at))
        } else {
            let (tok, at) = self.token(what)?;
            match parse_u64(tok) {
                Some(v) => Ok((v, at)),
                None => Err(self.bad_token(tok, at, "a non-negative integer", what)),
            }
        }
    }

    /// A `size_t` used as a count, checked to fit `usize`.
    pub fn count(&mut self, what: &'static str) -> Result<(usize, Location), MshError> {
        let (v, at) = self.size(what)?;
        let n = usize::try_from(v).map_err(|_| self.format(at, format!("{what} {v} is too large")))?;
        Ok((n, at))
    }

    /// An `int` (dimension, entity tag, element type) and where it starts.
    #[inline]
    pub fn int(&mut self, what: &'static str) -> Result<(i32, Location), MshError> {
        if self.binary {
            let at = self.loc();
            let b = self.bytes::<4>(what)?;
            Ok((if self.big_endian { i32::from_be_bytes(b) } else { i32::from_le_bytes(b) }, at))
        } else {
            let (tok, at) = self.token(what)?;
            match parse_i32(tok) {
                Some(v) => Ok((v, at)),
                None => Err(self.bad_token(tok, at, "a 32-bit integer", what)),
            }
        }
    }

    /// A `double`, required to be finite.
    #[inline]
    pub fn double(&mut self, what: &'static str) -> Result<f64, MshError> {
        if self.binary {
            let at = self.loc();
            let b = self.bytes::<8>(what)?;
            let v = if self.big_endian { f64::from_be_bytes(b) } else { f64::from_le_bytes(b) };
            if v.is_finite() {
                Ok(v)
            } else {
                Err(self.format(at, format!("{what} is not a finite number ({v})")))
            }
        } else {
            let (tok, at) = self.token(what)?;
            parse_f64(tok).ok_or_else(|| self.bad_token(tok, at, "a finite float", what))
        }
    }

    /// Reads the end marker `$End<section>` of the current section.
    pub fn expect_end(&mut self) -> Result<(), MshError> {
        let marker = format!("$End{}", self.section);
        match self.next_line() {
            None => Err(self.truncated("its end marker")),
            Some((line, _)) if line == marker.as_bytes() => Ok(()),
            Some((line, at)) => Err(MshError::TrailingData {
                path: self.path.to_string(),
                at,
                section: self.section.to_string(),
                found: show(line),
            }),
        }
    }

    /// The error for a token that does not parse: an early section end or garbled text.
    fn bad_token(&self, tok: &[u8], at: Location, expected: &'static str, what: &'static str) -> MshError {
        if tok.first() == Some(&b'$') {
            MshError::EarlyEnd {
                path: self.path.to_string(),
                at,
                section: self.section.to_string(),
                what,
                found: show(tok),
            }
        } else {
            MshError::Garbled { path: self.path.to_string(), at, expected, what, found: show(tok) }
        }
    }

    /// The error for an unexpected end of file.
    pub fn truncated(&self, what: &'static str) -> MshError {
        MshError::Truncated { path: self.path.to_string(), at: self.loc(), section: self.section.to_string(), what }
    }

    /// A [`MshError::Format`] at `at`.
    pub fn format(&self, at: Location, message: String) -> MshError {
        MshError::Format { path: self.path.to_string(), at, message }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn integers_parse_exactly_and_reject_overflow() {
        assert_eq!(parse_u64(b"0"), Some(0));
        assert_eq!(parse_u64(b"+17"), Some(17));
        assert_eq!(parse_u64(b"18446744073709551615"), Some(u64::MAX));
        assert_eq!(parse_u64(b"18446744073709551616"), None);
        assert_eq!(parse_u64(b""), None);
        assert_eq!(parse_u64(b"-1"), None);
        assert_eq!(parse_u64(b"1.0"), None);
        assert_eq!(parse_i32(b"-2147483648"), Some(i32::MIN));
        assert_eq!(parse_i32(b"2147483648"), None);
        assert_eq!(parse_i32(b"-"), None);
        assert_eq!(parse_f64(b"1.5e3"), Some(1500.0));
        assert_eq!(parse_f64(b"inf"), None);
        assert_eq!(parse_f64(b"nan"), None);
        assert_eq!(parse_f64(b"1,5"), None);
    }

    #[test]
    fn lines_are_counted_across_tokens_and_lines() {
        let mut c = Cursor::new(b"a b\n\n c\r\nd", "f");
        assert_eq!(c.token("x").unwrap().1, Location::Line(1));
        assert_eq!(c.token("x").unwrap().1, Location::Line(1));
        assert_eq!(c.token("x").unwrap(), (&b"c"[..], Location::Line(3)));
        assert_eq!(c.next_line().unwrap(), (&b"d"[..], Location::Line(4)));
        assert!(c.next_line().is_none());
    }

    #[test]
    fn binary_numbers_follow_the_byte_order() {
        let mut le = Cursor::new(&[1, 0, 0, 0, 2, 0, 0, 0, 0, 0, 0, 0], "f");
        le.set_binary(false);
        assert_eq!(le.int("i").unwrap(), (1, Location::Byte(0)));
        assert_eq!(le.size("s").unwrap(), (2, Location::Byte(4)));
        let mut be = Cursor::new(&[0, 0, 0, 1], "f");
        be.set_binary(true);
        assert_eq!(be.int("i").unwrap().0, 1);
        assert!(matches!(be.int("i"), Err(MshError::Truncated { at: Location::Byte(4), .. })));
    }
}
