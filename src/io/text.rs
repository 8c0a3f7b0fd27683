//! Helpers shared by the text formats (OBJ, OFF, ASCII PLY): lines, tokens, numbers and
//! the float formatting that makes text round trips bit-exact.
//!
//! Files are handled as bytes, not `str`: a stray non-UTF-8 byte in a comment or a
//! material name must not stop a mesh from loading. Numbers are ASCII, so each number
//! token is checked as UTF-8 on its own and parsed with the standard library, whose
//! `f64` parsing is correctly rounded (the shortest decimal written by [`Float`] reads
//! back to the same bits).

use std::fmt;

/// The physical lines of a file, numbered from 1. `\n` ends a line; a `\r` before it
/// (CRLF files) is dropped. A leading UTF-8 byte-order mark is skipped.
pub(crate) struct Lines<'a> {
    rest: &'a [u8],
    number: usize,
    done: bool,
}

impl<'a> Lines<'a> {
    pub(crate) fn new(bytes: &'a [u8]) -> Self {
        let rest = bytes.strip_prefix(b"\xEF\xBB\xBF").unwrap_or(bytes);
        Lines {
            rest,
            number: 0,
            done: false,
        }
    }

    /// The number of the last line returned (0 before the first).
    pub(crate) fn number(&self) -> usize {
        self.number
    }
}

impl<'a> Iterator for Lines<'a> {
    type Item = (usize, &'a [u8]);

    fn next(&mut self) -> Option<Self::Item> {
        if self.done {
            return None;
        }
        let (line, rest) = match self.rest.iter().position(|&b| b == b'\n') {
            Some(i) => (&self.rest[..i], &self.rest[i + 1..]),
            None => {
                self.done = true;
                if self.rest.is_empty() {
                    return None;
                }
                (self.rest, &self.rest[self.rest.len()..])
            }
        };
        self.rest = rest;
        self.number += 1;
        let line = line.strip_suffix(b"\r").unwrap_or(line);
        Some((self.number, line))
    }
}

/// `line` up to the first `#` (a comment in OBJ and OFF).
pub(crate) fn strip_comment(line: &[u8]) -> &[u8] {
    match line.iter().position(|&b| b == b'#') {
        Some(i) => &line[..i],
        None => line,
    }
}

/// Whether a byte separates tokens (space, tab, CR, LF, vertical tab, form feed).
#[inline]
pub(crate) fn is_space(b: u8) -> bool {
    matches!(b, b' ' | b'\t' | b'\r' | b'\n' | 0x0b | 0x0c)
}

/// The whitespace-separated tokens of a line.
pub(crate) fn tokens(line: &[u8]) -> Tokens<'_> {
    Tokens { rest: line }
}

/// Iterator of [`tokens`].
#[derive(Clone)]
pub(crate) struct Tokens<'a> {
    rest: &'a [u8],
}

impl<'a> Iterator for Tokens<'a> {
    type Item = &'a [u8];

    #[inline]
    fn next(&mut self) -> Option<&'a [u8]> {
        let start = self.rest.iter().position(|&b| !is_space(b))?;
        let rest = &self.rest[start..];
        let end = rest.iter().position(|&b| is_space(b)).unwrap_or(rest.len());
        self.rest = &rest[end..];
        Some(&rest[..end])
    }
}

/// A decimal floating-point number (`1`, `-0.5`, `1e-7`, `inf`, `nan`…); `None` if the
/// token is not one. Non-finite values are returned; callers reject them with a message.
#[inline]
pub(crate) fn parse_f64(tok: &[u8]) -> Option<f64> {
    std::str::from_utf8(tok).ok()?.parse().ok()
}

/// A decimal integer with an optional sign.
#[inline]
pub(crate) fn parse_i64(tok: &[u8]) -> Option<i64> {
    std::str::from_utf8(tok).ok()?.parse().ok()
}

/// A decimal integer without a minus sign.
#[inline]
pub(crate) fn parse_u64(tok: &[u8]) -> Option<u64> {
    std::str::from_utf8(tok).ok()?.parse().ok()
}

/// A name from the file (a PLY element or property), as katachi keeps and shows it: lossy
/// UTF-8 with control characters escaped (`\u{1b}`), so that a message echoing it cannot
/// carry terminal escape codes or break its line. Printable names are unchanged.
pub(crate) fn name(tok: &[u8]) -> String {
    crate::error::escape_control_characters(&String::from_utf8_lossy(tok)).into_owned()
}

/// A token quoted for a message: lossy UTF-8, at most 40 characters.
pub(crate) fn show(tok: &[u8]) -> String {
    let s = String::from_utf8_lossy(tok);
    let mut out: String = s.chars().take(40).collect();
    if s.chars().count() > 40 {
        out.push('…');
    }
    format!("'{}'", out.escape_debug())
}

/// Formats an `f64` as the shortest decimal that reads back to the same bits: plain
/// notation (`0.25`, `-3`, `-0`) for ordinary magnitudes, exponent notation (`1e-7`,
/// `1.5e20`) for very small or large ones so no line grows to hundreds of digits.
#[derive(Clone, Copy)]
pub(crate) struct Float(pub f64);

impl fmt::Display for Float {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        let a = self.0.abs();
        if a != 0.0 && a.is_finite() && !(1e-5..1e16).contains(&a) {
            write!(f, "{:e}", self.0)
        } else {
            write!(f, "{}", self.0)
        }
    }
}

/// A message for a number that should be finite but is not.
pub(crate) fn not_finite(what: &str, value: f64) -> String {
    format!("{what} is {value}, not a finite number")
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn lines_handle_crlf_bom_and_missing_final_newline() {
        let l: Vec<_> = Lines::new(b"\xEF\xBB\xBFa\r\nb\n\nc").collect();
        assert_eq!(
            l,
            vec![
                (1, &b"a"[..]),
                (2, &b"b"[..]),
                (3, &b""[..]),
                (4, &b"c"[..])
            ]
        );
        assert_eq!(Lines::new(b"a\n").count(), 1);
        assert_eq!(Lines::new(b"").count(), 0);
    }

    #[test]
    fn tokens_split_on_any_ascii_space() {
        let t: Vec<_> = tokens(b"  f 1/2\t3 \x0c4  ").collect();
        assert_eq!(t, vec![&b"f"[..], b"1/2", b"3", b"4"]);
    }

    #[test]
    fn floats_round_trip_bit_exact() {
        for x in [
            0.1,
            -0.0,
            1e-300,
            5e-324,
            1.7976931348623157e308,
            123456789.123,
            1e16,
            9999999999999998.0,
            1e-5,
            9.99e-6,
            -2.5e-7,
        ] {
            let s = Float(x).to_string();
            let y: f64 = s.parse().unwrap();
            assert_eq!(x.to_bits(), y.to_bits(), "{x} printed as {s}");
            assert!(s.len() < 30, "{s}");
        }
        assert_eq!(Float(1.0).to_string(), "1");
        assert_eq!(Float(-0.0).to_string(), "-0");
    }
}
