//! Byte-level helpers shared by the text formats: numbered lines, comment
//! stripping, whitespace tokens, number parsing, and telling text from what
//! is not text (a UTF-8 byte-order mark, UTF-16, binary data).
//!
//! Text is handled as bytes, not `str`: a file with a stray Latin-1 byte in a
//! comment or a group name must still read, and only the tokens we parse as
//! numbers need to be ASCII.

use std::borrow::Cow;

use crate::error::{Ctx, IoError};
use crate::Format;

/// The UTF-8 encoding of U+FEFF, which some editors put at the start of a file.
const UTF8_BOM: &[u8] = b"\xEF\xBB\xBF";

/// How much of a file [`check_text`] looks at: enough to see that a file is
/// binary or UTF-16, little enough to cost nothing on a large file.
const SAMPLE: usize = 4096;

/// The buffer without a leading UTF-8 byte-order mark.
pub(crate) fn strip_bom(bytes: &[u8]) -> &[u8] {
    bytes.strip_prefix(UTF8_BOM).unwrap_or(bytes)
}

/// Why bytes are not UTF-8 text.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) enum NotText {
    /// A UTF-16 byte-order mark, or NUL bytes interleaved with other bytes.
    Utf16,
    /// NUL bytes, or more control characters than text ever has.
    Binary,
}

/// Looks at the first [`SAMPLE`] bytes for UTF-16 or binary data.
///
/// Binary means a NUL byte, or more than one byte in 16 that is a control
/// character other than whitespace (random bytes have one in 9). Bytes that
/// are not valid UTF-8 do not count: a comment in Latin-1 or another 8-bit
/// encoding must not make a mesh unreadable.
pub(crate) fn sniff(bytes: &[u8]) -> Option<NotText> {
    let sample = &bytes[..bytes.len().min(SAMPLE)];
    if sample.starts_with(b"\xFF\xFE") || sample.starts_with(b"\xFE\xFF") || interleaved_nuls(sample) {
        return Some(NotText::Utf16);
    }
    if sample.contains(&0) || 16 * sample.iter().filter(|&&b| is_control(b)).count() > sample.len() {
        return Some(NotText::Binary);
    }
    None
}

/// A control character that is not whitespace: never part of a text mesh file.
pub(crate) fn is_control(b: u8) -> bool {
    matches!(b, 0..=8 | 0x0E..=0x1F | 0x7F)
}

/// UTF-16 text without a byte-order mark: ASCII characters are a NUL byte
/// and the character, so one byte position of each pair is almost always
/// NUL and the other almost never is.
fn interleaved_nuls(sample: &[u8]) -> bool {
    let pairs = sample.len() / 2;
    if pairs == 0 {
        return false;
    }
    let nuls_at = |parity: usize| sample.iter().skip(parity).step_by(2).take(pairs).filter(|&&b| b == 0).count();
    let (even, odd) = (nuls_at(0), nuls_at(1));
    let mostly = |n: usize| 4 * n >= 3 * pairs;
    let rarely = |n: usize| 8 * n < pairs;
    (mostly(even) && rarely(odd)) || (mostly(odd) && rarely(even))
}

/// [`sniff`] as an error of a text format (`format` names it in the message).
pub(crate) fn check_text(bytes: &[u8], format: Format, ctx: Ctx<'_>) -> Result<(), IoError> {
    match sniff(bytes) {
        None => Ok(()),
        Some(NotText::Utf16) => Err(ctx.utf16()),
        Some(NotText::Binary) => Err(ctx.binary(None, format)),
    }
}

/// Lines of a buffer with their 1-based numbers; `\n`, `\r\n` or a lone `\r`
/// (classic Mac OS) ends a line.
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
        let (line, advance) = match memchr::memchr2(b'\n', b'\r', rest) {
            Some(end) if rest[end..].starts_with(b"\r\n") => (&rest[..end], end + 2),
            Some(end) => (&rest[..end], end + 1),
            None => (rest, rest.len()),
        };
        self.pos += advance;
        self.line += 1;
        Some((self.line, line))
    }
}

/// The part of a line before a `#` comment.
pub(crate) fn strip_comment(line: &[u8]) -> &[u8] {
    match memchr::memchr(b'#', line) {
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
    fast_float2::parse(token).ok()
}

/// Why a token is not a usable integer.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) enum IntError {
    /// Not a decimal integer at all (`x`, `1.5`, empty).
    NotInteger,
    /// A decimal integer too large for any count or index (beyond `i128`).
    OutOfRange,
}

/// Parses a decimal integer (optional sign, at least one digit). An integer
/// too long for `i128` is [`IntError::OutOfRange`], not "not an integer":
/// callers convert the value to the type they need and report anything
/// outside it as out of range too, quoting the token.
pub(crate) fn parse_integer(token: &[u8]) -> Result<i128, IntError> {
    let digits = token.strip_prefix(b"-").or_else(|| token.strip_prefix(b"+")).unwrap_or(token);
    if digits.is_empty() || !digits.iter().all(u8::is_ascii_digit) {
        return Err(IntError::NotInteger);
    }
    // Up to 18 digits fit an i64 whatever they are: summed directly (the
    // common case, an index), longer ones through `i128`'s parser.
    if digits.len() <= 18 {
        let value = digits.iter().fold(0i64, |v, &d| 10 * v + i64::from(d - b'0'));
        return Ok(i128::from(if token[0] == b'-' { -value } else { value }));
    }
    // ASCII digits with an optional sign: valid UTF-8, and `parse` fails only on overflow.
    std::str::from_utf8(token).ok().and_then(|t| t.parse().ok()).ok_or(IntError::OutOfRange)
}

/// Parses a token as an integer that must fit `T` (a count or an index),
/// with the message a reader reports otherwise: `{what} 'x' is not an
/// integer`, `{what} -1 is negative`, `{what} 99999999999999999999 out of range`.
pub(crate) fn parse_bounded<T: TryFrom<i128>>(token: &[u8], what: &str) -> Result<T, String> {
    match parse_integer(token) {
        Err(IntError::NotInteger) => Err(format!("{what} '{}' is not an integer", show(token))),
        Ok(v) if v < 0 => Err(format!("{what} {v} is negative")),
        Ok(v) => T::try_from(v).map_err(|_| format!("{what} {v} out of range")),
        Err(IntError::OutOfRange) => Err(format!("{what} {} out of range", show(token))),
    }
}

/// A token for an error message: lossy UTF-8, cut to a readable length.
pub(crate) fn show(token: &[u8]) -> Cow<'_, str> {
    const MAX: usize = 40;
    let shown = if token.len() <= MAX {
        String::from_utf8_lossy(token)
    } else {
        Cow::Owned(format!("{}…", String::from_utf8_lossy(&token[..MAX])))
    };
    escape_controls(shown)
}

/// Control characters written as escapes (`\n`, `\u{1b}`), so that a quoted
/// token or name keeps a message on one line and cannot drive a terminal.
pub(crate) fn escape_controls(text: Cow<'_, str>) -> Cow<'_, str> {
    if text.chars().any(char::is_control) {
        Cow::Owned(
            text.chars().map(|c| if c.is_control() { c.escape_default().to_string() } else { c.into() }).collect(),
        )
    } else {
        text
    }
}

/// Formats `x` so that parsing it gives back the same bits: the shortest
/// round-trip form, with an exponent for very large or small magnitudes
/// (`0.1`, `1e-7`, `-0.0`, `NaN`, `inf`).
#[cfg(test)]
pub(crate) fn write_f64(out: &mut impl std::io::Write, x: f64) -> std::io::Result<()> {
    let mut buffer = F64Buffer::new();
    out.write_all(buffer.format(x))
}

/// Bytes a text writer assembles before handing them on.
const BLOCK: usize = 1 << 16;

/// Text assembled in blocks of [`BLOCK`] bytes before it goes to the
/// writer (a `write_all` or a `write!` per token costs more than the
/// token); numbers as [`F64Buffer::format`] and `itoa` write them.
pub(crate) struct TextOut<'a, W: std::io::Write> {
    out: &'a mut W,
    buf: Vec<u8>,
    floats: F64Buffer,
    ints: itoa::Buffer,
}

impl<'a, W: std::io::Write> TextOut<'a, W> {
    pub(crate) fn new(out: &'a mut W) -> Self {
        Self { out, buf: Vec::with_capacity(BLOCK + 1024), floats: F64Buffer::new(), ints: itoa::Buffer::new() }
    }

    pub(crate) fn bytes(&mut self, bytes: &[u8]) {
        self.buf.extend_from_slice(bytes);
    }

    /// The shortest form that reads back to the same bits ([`write_f64`]).
    pub(crate) fn f64(&mut self, x: f64) {
        self.buf.extend_from_slice(self.floats.format(x));
    }

    /// The same digits in `{:e}`'s layout ([`F64Buffer::format_exp`]).
    pub(crate) fn f64_exp(&mut self, x: f64) {
        self.buf.extend_from_slice(self.floats.format_exp(x));
    }

    pub(crate) fn int(&mut self, v: impl itoa::Integer) {
        self.buf.extend_from_slice(self.ints.format(v).as_bytes());
    }

    /// Ends a line, handing the block on when it is full.
    pub(crate) fn end_line(&mut self) -> std::io::Result<()> {
        self.buf.push(b'\n');
        if self.buf.len() >= BLOCK {
            self.out.write_all(&self.buf)?;
            self.buf.clear();
        }
        Ok(())
    }

    /// Hands on what is left.
    pub(crate) fn finish(mut self) -> std::io::Result<()> {
        self.out.write_all(&self.buf)?;
        self.buf.clear();
        Ok(())
    }
}

/// Room for one number of [`F64Buffer::format`].
pub(crate) struct F64Buffer {
    digits: zmij::Buffer,
    text: [u8; 32],
}

impl F64Buffer {
    pub(crate) fn new() -> Self {
        Self { digits: zmij::Buffer::new(), text: [0; 32] }
    }

    /// `x` as Rust's `{:?}` lays it out — decimal for 10⁻⁴ ≤ |x| < 10¹⁶
    /// (`0.1`, `1.0`, `-0.0`), otherwise `1e20`, `1.5e-7` — with the shortest
    /// digits that read back to the same bits (Schubfach, the `zmij` crate;
    /// where two shortest forms are equally close, the last digit may differ
    /// from `{:?}`'s: both read back to `x`). `NaN`, `inf`, `-inf` otherwise.
    pub(crate) fn format(&mut self, x: f64) -> &[u8] {
        if !x.is_finite() {
            return non_finite(x);
        }
        if x == 0.0 || (1e-4..1e16).contains(&x.abs()) {
            // zmij's decimal range covers this one, in the same layout.
            return self.digits.format_finite(x).as_bytes();
        }
        self.scientific(x)
    }

    /// `x` as Rust's `{:e}` lays it out — `1.5e-7`, `1e0`, `1.25e20`,
    /// `-0e0` — with the digits of [`F64Buffer::format`].
    pub(crate) fn format_exp(&mut self, x: f64) -> &[u8] {
        if !x.is_finite() {
            return non_finite(x);
        }
        if x == 0.0 {
            return if x.is_sign_negative() { b"-0e0" } else { b"0e0" };
        }
        self.scientific(x)
    }

    /// A finite, non-zero `x` as `d[.ddd]e[-]n`.
    fn scientific(&mut self, x: f64) -> &[u8] {
        let plain = self.digits.format_finite(x).as_bytes();
        // zmij writes `1.5e-7` or `1e+20`, `123.25`, and small numbers down
        // to 1e-5 (or so) as `0.00001`; re-laid as `1.2325e2`, `1e-5`.
        let (negative, body) = match plain.split_first() {
            Some((b'-', rest)) => (true, rest),
            _ => (false, plain),
        };
        let (mantissa, exponent) = match memchr::memchr(b'e', body) {
            Some(e) => (&body[..e], parse_exponent(&body[e + 1..])),
            None => (body, 0),
        };
        // All mantissa digits, the point after `point` of them; the first
        // non-zero one, at `first`, has the exponent point − 1 − first (+ e).
        let mut digits = [0u8; 24];
        let (mut n, mut point) = (0, None);
        for &c in mantissa.iter().take(digits.len()) {
            if c == b'.' {
                point = Some(n);
            } else {
                digits[n] = c;
                n += 1;
            }
        }
        let point = point.unwrap_or(n) as i32;
        let first = digits[..n].iter().position(|&d| d != b'0').unwrap_or(0);
        let e10 = point - 1 - first as i32 + exponent;
        let digits = &digits[first..n];
        let n = digits.iter().rposition(|&d| d != b'0').map_or(1, |last| last + 1);
        let mut len = 0;
        let mut put = |text: &mut [u8; 32], b: u8| {
            text[len] = b;
            len += 1;
        };
        if negative {
            put(&mut self.text, b'-');
        }
        put(&mut self.text, digits[0]);
        if n > 1 {
            put(&mut self.text, b'.');
            for &d in &digits[1..n] {
                put(&mut self.text, d);
            }
        }
        put(&mut self.text, b'e');
        if e10 < 0 {
            put(&mut self.text, b'-');
        }
        let mut exp_digits = itoa::Buffer::new();
        for &d in exp_digits.format(e10.unsigned_abs()).as_bytes() {
            put(&mut self.text, d);
        }
        &self.text[..len]
    }
}

/// `NaN`, `inf` or `-inf`, as `{:?}` and `{:e}` write them.
fn non_finite(x: f64) -> &'static [u8] {
    match (x.is_nan(), x > 0.0) {
        (true, _) => b"NaN",
        (false, true) => b"inf",
        (false, false) => b"-inf",
    }
}

/// The decimal exponent after an `e` (`+20`, `-7`, `5`).
fn parse_exponent(text: &[u8]) -> i32 {
    let (sign, digits) = match text.split_first() {
        Some((b'-', rest)) => (-1, rest),
        Some((b'+', rest)) => (1, rest),
        _ => (1, text),
    };
    sign * digits.iter().fold(0i32, |v, &d| 10 * v + i32::from(d - b'0'))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn lines_number_from_one_and_strip_cr() {
        let lines: Vec<_> = Lines::new(b"a\r\nb\n\nc").collect();
        assert_eq!(lines, vec![(1, &b"a"[..]), (2, b"b"), (3, b""), (4, b"c")]);
        // Classic Mac OS line ends: one line each, not one line for the whole file.
        let lines: Vec<_> = Lines::new(b"a\rb\r\rc\r\n").collect();
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
    fn formatted_numbers_read_back_and_match_debug_but_for_ties() {
        let mut buffer = F64Buffer::new();
        let mut x: u64 = 0x9e37_79b9_7f4a_7c15;
        let mut values = vec![0.0, -0.0, 1.0, 0.1, 1e-4, 9.9e-5, 1e-5, 1e16, 9.999999999999998e15, 1e20, 1e21, 5e-324];
        values.extend([f64::MAX, f64::MIN_POSITIVE, -1.5e-7, 123456789012345680.0, 1e300, 2.5e-300]);
        for _ in 0..200_000 {
            x ^= x << 13;
            x ^= x >> 7;
            x ^= x << 17;
            values.push(f64::from_bits(x));
            let e = (x % 45) as i32 - 22;
            values.push((x >> 11) as f64 / (1u64 << 53) as f64 * 10f64.powi(e));
        }
        for v in values.into_iter().filter(|v| v.is_finite()) {
            let ours = std::str::from_utf8(buffer.format(v)).unwrap().to_owned();
            let ours_exp = std::str::from_utf8(buffer.format_exp(v)).unwrap().to_owned();
            for (ours, std) in [(ours, format!("{v:?}")), (ours_exp, format!("{v:e}"))] {
                assert_eq!(parse_f64(ours.as_bytes()).map(f64::to_bits), Some(v.to_bits()), "{ours}");
                if ours != std {
                    // Two shortest forms equally close to v: the same but for the last digit.
                    let (a, b) = (ours.split('e').next().unwrap(), std.split('e').next().unwrap());
                    assert!(a.len() == b.len() && a[..a.len() - 1] == b[..b.len() - 1], "{ours} vs {std}");
                    assert_eq!(ours.split('e').nth(1), std.split('e').nth(1), "{ours} vs {std}");
                }
            }
        }
        assert_eq!(buffer.format_exp(-0.0), b"-0e0");
        assert_eq!(buffer.format_exp(100.0), b"1e2");
        assert_eq!(buffer.format_exp(0.00123), b"1.23e-3");
        assert_eq!(buffer.format_exp(f64::INFINITY), b"inf");
        assert_eq!(buffer.format(f64::NAN), b"NaN");
        assert_eq!(buffer.format(f64::NEG_INFINITY), b"-inf");
        assert_eq!(buffer.format(1e-5), b"1e-5");
        assert_eq!(buffer.format(-1.25e20), b"-1.25e20");
    }

    #[test]
    fn parse_f64_accepts_what_str_parse_accepts() {
        let odd = ["1", "1.", ".5", "+1", "-.5", "1e5", "1e", "1.e5", ".e5", "inf", "Infinity", "-nan", "NaN", "+inf"];
        let odd =
            odd.iter().chain(&["infin", "1_0", "0x10", " 1", "1 ", "", "-", ".", "e5", "1E+5", "1e400", "1e-400"]);
        let mut x: u64 = 0x2545_f491_4f6c_dd1d;
        let alphabet = b"0123456789.eE+-infatyINFATY_ ";
        let random = (0..100_000).map(|_| {
            x ^= x << 13;
            x ^= x >> 7;
            x ^= x << 17;
            (0..1 + (x % 8) as usize).map(|i| alphabet[((x >> (8 + 6 * i)) % alphabet.len() as u64) as usize]).collect()
        });
        for token in odd.map(|t| t.as_bytes().to_vec()).chain(random) {
            let std: Option<f64> = std::str::from_utf8(&token).ok().and_then(|t| t.parse().ok());
            let ours = parse_f64(&token);
            assert_eq!(ours.map(|v| v.is_nan()), std.map(|v| v.is_nan()), "{}", show(&token));
            assert_eq!(ours.filter(|v| !v.is_nan()).map(f64::to_bits), std.filter(|v| !v.is_nan()).map(f64::to_bits));
        }
    }

    #[test]
    fn tokens_and_comments() {
        let t: Vec<_> = tokens(strip_comment(b" 1\t2  3 # four")).collect();
        assert_eq!(t, vec![&b"1"[..], b"2", b"3"]);
    }

    #[test]
    fn integers_too_long_are_out_of_range_not_non_integers() {
        assert_eq!(parse_integer(b"-7"), Ok(-7));
        assert_eq!(parse_integer(b"+7"), Ok(7));
        assert_eq!(parse_integer(b"99999999999999999999"), Ok(99_999_999_999_999_999_999));
        assert_eq!(parse_integer(&[b'9'; 60]), Err(IntError::OutOfRange));
        for bad in [&b"x"[..], b"", b"-", b"1.5", b"1e3", b"--1", b" 1"] {
            assert_eq!(parse_integer(bad), Err(IntError::NotInteger), "{}", show(bad));
        }
        assert_eq!(parse_bounded::<u32>(b"4294967295", "index"), Ok(u32::MAX));
        assert_eq!(
            parse_bounded::<u32>(b"99999999999999999999", "index").unwrap_err(),
            "index 99999999999999999999 out of range"
        );
        assert_eq!(
            parse_bounded::<u32>(&[b'9'; 60], "index").unwrap_err(),
            format!("index {}… out of range", "9".repeat(40))
        );
        assert_eq!(parse_bounded::<u32>(b"-1", "index").unwrap_err(), "index -1 is negative");
        assert_eq!(parse_bounded::<u32>(b"q", "index").unwrap_err(), "index 'q' is not an integer");
    }

    #[test]
    fn sniffing_tells_text_from_utf16_and_binary() {
        assert_eq!(sniff(b""), None);
        assert_eq!(sniff(b"v 0 0 0\r\n\tf 1 2 3\x0c\n"), None);
        // Latin-1 and other 8-bit encodings are text with invalid UTF-8.
        assert_eq!(sniff(b"# caf\xe9 \xc0\xc1\xc2\xc3\xc4\xc5\xc6\xc7\nv 0 0 0\n"), None);
        assert_eq!(sniff(b"\xFF\xFEv\0 \0"), Some(NotText::Utf16));
        assert_eq!(sniff(b"\xFE\xFF\0v\0 "), Some(NotText::Utf16));
        let le: Vec<u8> = "v 0 0 0\n".bytes().flat_map(|b| [b, 0]).collect();
        let be: Vec<u8> = "OFF\n3 1 0\n".bytes().flat_map(|b| [0, b]).collect();
        assert_eq!(sniff(&le), Some(NotText::Utf16));
        assert_eq!(sniff(&be), Some(NotText::Utf16));
        assert_eq!(sniff(b"v 0 0 0\n\0"), Some(NotText::Binary));
        assert_eq!(sniff(b"\x01\x02\x03v 0 0 0\n"), Some(NotText::Binary));
        // One stray control character in a line of text is not binary.
        assert_eq!(sniff(b"v 0 0 0 \x1a\nf 1 2 3\n# some text to make it long\n"), None);
        // Only the sample is looked at.
        let mut late = b"v 0 0 0\n".repeat(SAMPLE);
        late.push(0);
        assert_eq!(sniff(&late), None);
        assert_eq!(strip_bom(b"\xEF\xBB\xBFv"), b"v");
        assert_eq!(strip_bom(b"v"), b"v");
    }

    #[test]
    fn shown_tokens_stay_on_one_line() {
        assert_eq!(show(b"a\x1b[2Jb"), "a\\u{1b}[2Jb");
        assert_eq!(show(b"x\ny"), "x\\ny");
        assert_eq!(show(b"caf\xe9"), "caf\u{fffd}");
        assert_eq!(show(&[b'7'; 50]), format!("{}…", "7".repeat(40)));
    }
}
