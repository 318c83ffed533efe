//! Small string helpers shared by the parsers (MOOS `parseStringQ`, `biteStringX`, `isNumber`).

use std::borrow::Cow;

use crate::error::ParseError;

/// Splits on `sep` except inside `{...}` or `"..."` (MOOS `parseStringQ`). Pieces are trimmed.
pub(crate) fn split_top(s: &str, sep: char) -> impl Iterator<Item = &str> {
    let mut depth = 0i32;
    let mut quoted = false;
    let mut start = 0usize;
    let mut done = false;
    let mut chars = s.char_indices();
    std::iter::from_fn(move || {
        if done {
            return None;
        }
        for (i, c) in chars.by_ref() {
            match c {
                '"' => quoted = !quoted,
                '{' if !quoted => depth += 1,
                '}' if !quoted => depth -= 1,
                c if c == sep && !quoted && depth <= 0 => {
                    let piece = &s[start..i];
                    start = i + c.len_utf8();
                    return Some(piece.trim());
                }
                _ => {}
            }
        }
        done = true;
        Some(s[start..].trim())
    })
}

/// Splits `key=value` at the first `=`; both sides trimmed. Without `=` the value is empty.
pub(crate) fn split_kv(piece: &str) -> (&str, &str) {
    match piece.split_once('=') {
        Some((k, v)) => (k.trim(), v.trim()),
        None => (piece.trim(), ""),
    }
}

/// Splits at the first `sep` (MOOS `biteStringX`): (before, after), both trimmed.
pub(crate) fn bite(s: &str, sep: char) -> (&str, &str) {
    match s.split_once(sep) {
        Some((a, b)) => (a.trim(), b.trim()),
        None => (s.trim(), ""),
    }
}

/// Lower-cases ASCII only when needed.
pub(crate) fn lower(s: &str) -> Cow<'_, str> {
    if s.bytes().any(|b| b.is_ascii_uppercase()) {
        Cow::Owned(s.to_ascii_lowercase())
    } else {
        Cow::Borrowed(s)
    }
}

/// MOOS `isNumber` and C `atof`: the workspace's one definition of each.
pub use moos_types::text::{atof, is_number};

/// Splits on `sep` outside double quotes, pieces untrimmed (MOOS `parseStringQ`).
///
/// ```
/// assert_eq!(geometry::split_unquoted("a=\"x#y\"#b", '#'), ["a=\"x#y\"", "b"]);
/// ```
pub fn split_unquoted(s: &str, sep: char) -> Vec<&str> {
    let mut out = Vec::new();
    let (mut start, mut quoted) = (0, false);
    for (i, c) in s.char_indices() {
        if c == '"' {
            quoted = !quoted;
        } else if c == sep && !quoted {
            out.push(&s[start..i]);
            start = i + c.len_utf8();
        }
    }
    out.push(&s[start..]);
    out
}

/// Parses a MOOS number (see [`is_number`]).
pub(crate) fn number(s: &str) -> Option<f64> {
    if !is_number(s) {
        return None;
    }
    let s = s.trim();
    let s = s.strip_prefix('+').unwrap_or(s);
    s.parse::<f64>().ok()
}

/// Parses a number or reports which key it was for.
pub(crate) fn need_number(key: &str, s: &str) -> Result<f64, ParseError> {
    number(s).ok_or_else(|| ParseError::BadNumber {
        key: key.to_string(),
        found: s.to_string(),
    })
}

/// Parses a MOOS boolean (`true`/`false`, any case).
pub(crate) fn boolean(s: &str) -> Option<bool> {
    moos_types::text::strict_bool(s)
}

/// Removes every whitespace character (MOOS `removeWhite`).
pub(crate) fn remove_white(s: &str) -> Cow<'_, str> {
    if s.chars().any(char::is_whitespace) {
        Cow::Owned(s.chars().filter(|c| !c.is_whitespace()).collect())
    } else {
        Cow::Borrowed(s)
    }
}

/// Writes `v` as MOOS `doubleToStringX(v, prec)` (the workspace's one implementation,
/// [`moos_types::fmt::compact`]).
pub(crate) fn write_num(out: &mut String, v: f64, prec: usize) {
    moos_types::fmt::compact(out, v, prec);
}

#[cfg(test)]
mod tests {
    use super::*;

    fn fmt(v: f64, p: usize) -> String {
        let mut s = String::new();
        write_num(&mut s, v, p);
        s
    }

    #[test]
    fn number_formatting_compacts_like_double_to_string_x() {
        assert_eq!(fmt(10.0, 2), "10");
        assert_eq!(fmt(-20.5, 2), "-20.5");
        assert_eq!(fmt(-0.001, 2), "0");
        assert_eq!(fmt(0.0, 0), "0");
        assert_eq!(fmt(100.0, 0), "100");
        assert_eq!(fmt(1.23456, 3), "1.235");
        assert_eq!(fmt(5.0, 1), "5");
        // printf rounds the exact binary value: 0.125 is exact, ties go to even.
        assert_eq!(fmt(0.125, 2), "0.12");
        assert_eq!(fmt(2.675, 2), "2.67");
    }

    #[test]
    fn is_number_follows_moos() {
        for ok in ["1", "-1", "+2", "1.", ".5", "-0.25", " 7 "] {
            assert!(is_number(ok), "{ok}");
        }
        for bad in [
            "", "-", ".", "1e3", "1.2.3", "abc", "1-2", "$(X)", "+", "1 2",
        ] {
            assert!(!is_number(bad), "{bad}");
        }
    }

    #[test]
    fn split_top_respects_braces_and_quotes() {
        let v: Vec<_> = split_top("pts={1,2:3,4}, label=a, msg=\"x,y\"", ',').collect();
        assert_eq!(v, vec!["pts={1,2:3,4}", "label=a", "msg=\"x,y\""]);
        let v: Vec<_> = split_top("", ',').collect();
        assert_eq!(v, vec![""]);
    }
}
