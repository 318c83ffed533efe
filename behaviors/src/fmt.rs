//! Number formatting as MOOS-IvP writes numbers (`doubleToString`, `doubleToStringX`).

use std::fmt::Write as _;

/// Appends `v` with `prec` decimals (MOOS `doubleToString(v, prec)`).
///
/// ```
/// let mut s = String::new();
/// behaviors::fmt::fixed(&mut s, 100.0, 5);
/// assert_eq!(s, "100.00000");
/// ```
pub fn fixed(out: &mut String, v: f64, prec: usize) {
    let start = out.len();
    write!(out, "{v:.prec$}").ok();
    if out[start..].starts_with('-') && out[start + 1..].bytes().all(|b| b == b'0' || b == b'.') {
        out.remove(start);
    }
}

/// Appends `v` with at most `prec` decimals, trailing zeros and a trailing `.` removed
/// (MOOS `doubleToStringX(v, prec)`).
///
/// ```
/// let mut s = String::new();
/// behaviors::fmt::compact(&mut s, 2.50, 2);
/// s.push(',');
/// behaviors::fmt::compact(&mut s, -0.001, 2);
/// assert_eq!(s, "2.5,0");
/// ```
pub fn compact(out: &mut String, v: f64, prec: usize) {
    let start = out.len();
    fixed(out, v, prec);
    if out[start..].contains('.') {
        let keep = out[start..]
            .trim_end_matches('0')
            .trim_end_matches('.')
            .len();
        out.truncate(start + keep);
    }
    if &out[start..] == "-0" {
        out.truncate(start);
        out.push('0');
    }
}

/// [`compact`] into a new string.
pub fn compact_string(v: f64, prec: usize) -> String {
    let mut s = String::new();
    compact(&mut s, v, prec);
    s
}
