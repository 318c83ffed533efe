//! MOOS-facing value types shared by the app adapters, and MOOS-IvP number formatting.

use std::fmt::Write as _;

/// A value arriving as MOOS mail, borrowed: the workspace's one view of a MOOS value.
pub use moos_types::ValueRef;

/// A value an app publishes: the workspace's one MOOS value type.
pub use moos_types::Value;

/// One posting an app wants published: the workspace's one posting type.
pub use moos_types::Post as Posting;

/// Finds the last posting of `var` in `postings`.
pub fn last_posting<'a>(postings: &'a [Posting], var: &str) -> Option<&'a Value> {
    postings
        .iter()
        .rev()
        .find(|p| p.key == var)
        .map(|p| &p.value)
}

/// Appends `val` formatted like MOOS-IvP's `doubleToString(val, digits)`: fixed-point with
/// `digits` decimals (C `%.Nf`).
///
/// ```
/// let mut s = String::new();
/// vehicle::moos::push_double(&mut s, 102.0, 5);
/// assert_eq!(s, "102.00000");
/// ```
pub fn push_double(out: &mut String, val: f64, digits: usize) {
    // Writing to a String cannot fail.
    let _ = write!(out, "{val:.digits$}");
}

/// Appends `val` formatted like MOOS-IvP's `dstringCompact(doubleToString(val, digits))`:
/// fixed-point, then trailing zeros and a trailing point removed. Unlike
/// [`push_double_x`] a negative value that rounds to zero stays `-0`.
///
/// ```
/// let mut s = String::new();
/// vehicle::moos::push_double_compact(&mut s, -1e-12, 8);
/// assert_eq!(s, "-0");
/// ```
pub fn push_double_compact(out: &mut String, val: f64, digits: usize) {
    let start = out.len();
    push_double(out, val, digits);
    if out[start..].contains('.') {
        let trimmed = out[start..]
            .trim_end_matches('0')
            .trim_end_matches('.')
            .len();
        out.truncate(start + trimmed);
    }
}

/// Appends `val` formatted like MOOS-IvP's `doubleToStringX(val, digits)`: fixed-point with
/// `digits` decimals, then trailing zeros and a trailing point removed, and `-0` written `0`.
///
/// ```
/// let mut s = String::new();
/// vehicle::moos::push_double_x(&mut s, 12.50, 2);
/// assert_eq!(s, "12.5");
/// ```
pub fn push_double_x(out: &mut String, val: f64, digits: usize) {
    let start = out.len();
    push_double_compact(out, val, digits);
    if &out[start..] == "-0" {
        out.truncate(start);
        out.push('0');
    }
}

/// `doubleToStringX` as a new string; see [`push_double_x`].
pub fn double_x(val: f64, digits: usize) -> String {
    let mut s = String::new();
    push_double_x(&mut s, val, digits);
    s
}

/// MOOS-IvP `parseString(s, sep)`: the pieces between separators; a separator at the very
/// end adds no empty piece, and an empty string has none.
pub fn parse_string(s: &str, sep: char) -> Vec<&str> {
    let mut pieces = Vec::new();
    let mut rest = s;
    while !rest.is_empty() {
        match rest.find(sep) {
            Some(i) => {
                pieces.push(&rest[..i]);
                rest = &rest[i + sep.len_utf8()..];
            }
            None => {
                pieces.push(rest);
                rest = "";
            }
        }
    }
    pieces
}

/// MOOS-IvP `parseStringQ(s, sep)`: as [`parse_string`], but a separator inside double
/// quotes or braces does not split.
pub fn parse_string_q(s: &str, sep: char) -> Vec<&str> {
    let (mut pieces, mut in_quotes, mut braces, mut start) = (Vec::new(), false, 0u32, 0);
    for (i, c) in s.char_indices() {
        match c {
            '"' => in_quotes = !in_quotes,
            '{' => braces += 1,
            '}' => braces = braces.saturating_sub(1),
            c if c == sep && !in_quotes && braces == 0 => {
                pieces.push(&s[start..i]);
                start = i + c.len_utf8();
            }
            _ => {}
        }
    }
    if start < s.len() {
        pieces.push(&s[start..]);
    }
    pieces
}

/// MOOS-IvP `tokStringParse(s, key, ',', '=')`: the value (blank ends stripped) of the first
/// `key=value` piece whose key (blank ends stripped) is `key`; empty when there is none, or
/// when a piece before it is not exactly one `left=right` pair.
///
/// ```
/// use vehicle::moos::tok_string_parse;
/// assert_eq!(tok_string_parse("app=pHelmIvP, maxgap=2.5", "maxgap"), "2.5");
/// assert_eq!(tok_string_parse("app=pHelmIvP,junk,maxgap=2.5", "maxgap"), "");
/// ```
pub fn tok_string_parse<'a>(s: &'a str, key: &str) -> &'a str {
    for piece in parse_string_q(s, ',') {
        let parts = parse_string(piece, '=');
        if parts.len() != 2 {
            return "";
        }
        if parts[0].trim() == key {
            return parts[1].trim();
        }
    }
    ""
}

/// A double as a C++ stream writes it by default (`%g`, 6 significant digits).
pub(crate) fn stream_double(v: f64) -> String {
    if v == 0.0 || !v.is_finite() {
        return if v == 0.0 { "0".into() } else { v.to_string() };
    }
    let sci = format!("{v:.5e}");
    let (mant, exp) = sci.split_once('e').unwrap_or((&sci, "0"));
    let exp: i32 = exp.parse().unwrap_or(0);
    let trim = |s: &str| -> String {
        if s.contains('.') {
            s.trim_end_matches('0').trim_end_matches('.').to_string()
        } else {
            s.to_string()
        }
    };
    if !(-4..6).contains(&exp) {
        format!(
            "{}e{}{:02}",
            trim(mant),
            if exp < 0 { '-' } else { '+' },
            exp.abs()
        )
    } else {
        let digits = usize::try_from(5 - exp).unwrap_or(0);
        trim(&format!("{v:.digits$}"))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn double_x_compacts() {
        assert_eq!(double_x(0.0, 2), "0");
        assert_eq!(double_x(-0.001, 2), "0");
        assert_eq!(double_x(100.0, 2), "100");
        assert_eq!(double_x(12.34567, 2), "12.35");
        assert_eq!(double_x(-20.5, 2), "-20.5");
        assert_eq!(double_x(43.825300001, 8), "43.8253");
        assert_eq!(double_x(7.0, 0), "7");
    }

    #[test]
    fn moos_string_parsing() {
        assert_eq!(parse_string("a,,b,", ','), ["a", "", "b"]);
        assert_eq!(parse_string(",a", ','), ["", "a"]);
        assert!(parse_string("", ',').is_empty());
        assert_eq!(
            parse_string_q(r#"a="x,y",b={1,2},c"#, ','),
            [r#"a="x,y""#, "b={1,2}", "c"]
        );
        assert_eq!(tok_string_parse("mhash=abc-1 , utc=5", "mhash"), "abc-1");
        assert_eq!(tok_string_parse("a=1=2,mhash=x", "mhash"), "");
        assert_eq!(tok_string_parse("a=,mhash=x", "mhash"), "");
        assert_eq!(tok_string_parse("", "mhash"), "");
    }
}
