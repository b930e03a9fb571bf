//! Byte-level helpers shared by the text formats: numbered lines, comment
//! stripping, whitespace tokens and number parsing.
//!
//! Text is handled as bytes, not `str`: a file with a stray Latin-1 byte in a
//! comment or a group name must still read, and only the tokens we parse as
//! numbers need to be ASCII.

use std::borrow::Cow;

/// Lines of a buffer with their 1-based numbers; `\n` or `\r\n` ends a line.
pub(crate) struct Lines<'a> {
    bytes: &'a [u8],
    pos: usize,
    line: usize,
}

impl<'a> Lines<'a> {
    pub(crate) fn new(bytes: &'a [u8]) -> Self {
        Self { bytes, pos: 0, line: 0 }
    }

    /// Bytes consumed so far (the start of the next line).
    pub(crate) fn offset(&self) -> usize {
        self.pos
    }

    /// Number of the last line returned (0 before the first).
    pub(crate) fn line(&self) -> usize {
        self.line
    }
}

impl<'a> Iterator for Lines<'a> {
    type Item = (usize, &'a [u8]);

    fn next(&mut self) -> Option<Self::Item> {
        if self.pos >= self.bytes.len() {
            return None;
        }
        let rest = &self.bytes[self.pos..];
        let (mut line, advance) = match rest.iter().position(|&b| b == b'\n') {
            Some(end) => (&rest[..end], end + 1),
            None => (rest, rest.len()),
        };
        if let [head @ .., b'\r'] = line {
            line = head;
        }
        self.pos += advance;
        self.line += 1;
        Some((self.line, line))
    }
}

/// The part of a line before a `#` comment.
pub(crate) fn strip_comment(line: &[u8]) -> &[u8] {
    match line.iter().position(|&b| b == b'#') {
        Some(hash) => &line[..hash],
        None => line,
    }
}

/// Whitespace-separated tokens of a line.
pub(crate) fn tokens(line: &[u8]) -> impl Iterator<Item = &[u8]> {
    line.split(|b| b.is_ascii_whitespace()).filter(|t| !t.is_empty())
}

/// True when the buffer holds only whitespace.
pub(crate) fn is_blank(bytes: &[u8]) -> bool {
    bytes.iter().all(u8::is_ascii_whitespace)
}

/// Parses a decimal number; accepts `nan`, `inf`, `-inf`, `infinity` in any case.
pub(crate) fn parse_f64(token: &[u8]) -> Option<f64> {
    std::str::from_utf8(token).ok()?.parse().ok()
}

/// Parses a decimal integer (optional sign).
pub(crate) fn parse_i64(token: &[u8]) -> Option<i64> {
    std::str::from_utf8(token).ok()?.parse().ok()
}

/// A token for an error message: lossy UTF-8, cut to a readable length.
pub(crate) fn show(token: &[u8]) -> Cow<'_, str> {
    const MAX: usize = 40;
    if token.len() <= MAX {
        String::from_utf8_lossy(token)
    } else {
        Cow::Owned(format!("{}…", String::from_utf8_lossy(&token[..MAX])))
    }
}

/// Formats `x` so that parsing it gives back the same bits: the shortest
/// round-trip form, with an exponent for very large or small magnitudes
/// (`0.1`, `1e-7`, `-0.0`, `NaN`, `inf`).
pub(crate) fn write_f64(out: &mut impl std::io::Write, x: f64) -> std::io::Result<()> {
    write!(out, "{x:?}")
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn lines_number_from_one_and_strip_cr() {
        let lines: Vec<_> = Lines::new(b"a\r\nb\n\nc").collect();
        assert_eq!(lines, vec![(1, &b"a"[..]), (2, b"b"), (3, b""), (4, b"c")]);
    }

    #[test]
    fn numbers_round_trip_through_write_f64() {
        for x in [0.1, -0.0, 1e-300, 1.7976931348623157e308, 5e-324, f64::INFINITY, -f64::INFINITY] {
            let mut s = Vec::new();
            write_f64(&mut s, x).unwrap();
            assert_eq!(parse_f64(&s).unwrap().to_bits(), x.to_bits(), "{}", show(&s));
        }
        let mut s = Vec::new();
        write_f64(&mut s, f64::NAN).unwrap();
        assert!(parse_f64(&s).unwrap().is_nan());
    }

    #[test]
    fn tokens_and_comments() {
        let t: Vec<_> = tokens(strip_comment(b" 1\t2  3 # four")).collect();
        assert_eq!(t, vec![&b"1"[..], b"2", b"3"]);
        assert_eq!(parse_i64(b"-7"), Some(-7));
        assert_eq!(parse_i64(b"x"), None);
    }
}
