//! MOOS-facing value types shared by the app adapters, and MOOS-IvP number formatting.

use std::fmt::Write as _;
use std::sync::Arc;

/// A value arriving as MOOS mail.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum MailValue<'a> {
    /// A double-valued message.
    Double(f64),
    /// A string-valued message.
    Str(&'a str),
}

impl MailValue<'_> {
    /// The value as a double: the number itself, or a string parsed as a number.
    pub fn as_f64(&self) -> Option<f64> {
        match *self {
            MailValue::Double(d) => Some(d),
            MailValue::Str(s) => s.trim().parse().ok(),
        }
    }

    /// The value as a string slice (`None` for doubles).
    pub fn as_str(&self) -> Option<&str> {
        match *self {
            MailValue::Double(_) => None,
            MailValue::Str(s) => Some(s),
        }
    }
}

/// A value an app publishes.
#[derive(Debug, Clone, PartialEq)]
pub enum Value {
    /// A double-valued posting.
    Double(f64),
    /// A string-valued posting.
    Str(String),
}

impl Value {
    /// The double, if this is one.
    pub fn as_f64(&self) -> Option<f64> {
        match self {
            Value::Double(d) => Some(*d),
            Value::Str(_) => None,
        }
    }

    /// The string, if this is one.
    pub fn as_str(&self) -> Option<&str> {
        match self {
            Value::Double(_) => None,
            Value::Str(s) => Some(s),
        }
    }
}

/// One `(variable, value)` pair an app wants published. Variable names are shared
/// (`Arc<str>`), so building a posting does not allocate a new name.
#[derive(Debug, Clone, PartialEq)]
pub struct Posting {
    /// The MOOS variable name.
    pub var: Arc<str>,
    /// The value.
    pub value: Value,
}

impl Posting {
    /// A double posting.
    pub fn double(var: &Arc<str>, value: f64) -> Self {
        Posting {
            var: Arc::clone(var),
            value: Value::Double(value),
        }
    }

    /// A string posting.
    pub fn string(var: &Arc<str>, value: impl Into<String>) -> Self {
        Posting {
            var: Arc::clone(var),
            value: Value::Str(value.into()),
        }
    }
}

/// Finds the last posting of `var` in `postings`.
pub fn last_posting<'a>(postings: &'a [Posting], var: &str) -> Option<&'a Value> {
    postings
        .iter()
        .rev()
        .find(|p| &*p.var == var)
        .map(|p| &p.value)
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
    // Writing to a String cannot fail.
    let _ = write!(out, "{val:.digits$}");
    if out[start..].contains('.') {
        let trimmed = out[start..]
            .trim_end_matches('0')
            .trim_end_matches('.')
            .len();
        out.truncate(start + trimmed);
    }
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
}
