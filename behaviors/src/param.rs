//! Typed parsing of behaviour parameter values, as MOOS-IvP reads them.

use crate::behavior::ParamError;

/// Whether `s` is a number as MOOS `isNumber` reads it (optional sign, digits, one `.`, no
/// exponent: `1e3` is not a number to MOOS).
///
/// ```
/// assert!(behaviors::param::is_number("-3.5"));
/// assert!(!behaviors::param::is_number("3m"));
/// assert!(!behaviors::param::is_number("1e3"));
/// ```
pub fn is_number(s: &str) -> bool {
    geometry::is_number(s)
}

/// The number at the start of `s`, as C's `atof` reads it (what MOOS-IvP uses where it does
/// not validate): leading blanks skipped, the longest numeric prefix taken, 0 when there is
/// none.
///
/// ```
/// use behaviors::param::atof;
/// assert_eq!(atof(" 12.5m"), 12.5);
/// assert_eq!(atof("-3e2x"), -300.0);
/// assert_eq!(atof("abc"), 0.0);
/// ```
pub fn atof(s: &str) -> f64 {
    let t = s.trim_start();
    let b = t.as_bytes();
    let mut end = 0;
    let mut best = 0.0;
    // Grow the prefix one byte at a time and keep the last one that parses.
    while end < b.len() {
        end += 1;
        if let Ok(v) = t[..end].parse::<f64>()
            && !t[..end].ends_with(['+', '-'])
        {
            best = v;
        } else if !matches!(b[end - 1], b'0'..=b'9' | b'.' | b'e' | b'E' | b'+' | b'-') {
            break;
        }
    }
    if best.is_finite() { best } else { 0.0 }
}

/// Parses a number or returns [`ParamError::BadValue`].
pub fn number(param: &str, value: &str) -> Result<f64, ParamError> {
    let v = value.trim();
    if is_number(v) {
        v.parse::<f64>()
            .map_err(|_| ParamError::bad(param, value, "a number"))
    } else {
        Err(ParamError::bad(param, value, "a number"))
    }
}

/// Parses a number `>= min`.
pub fn number_min(param: &str, value: &str, min: f64) -> Result<f64, ParamError> {
    let v = number(param, value)?;
    if v < min {
        return Err(ParamError::bad(param, value, "a larger number"));
    }
    Ok(v)
}

/// Parses a MOOS boolean as `setBooleanOnString` does (any case): `true`/`yes`/`on`,
/// `false`/`no`/`off`, or `toggle`, which flips `current`.
///
/// ```
/// use behaviors::param::moos_boolean;
/// assert_eq!(moos_boolean("p", "Yes", false), Ok(true));
/// assert_eq!(moos_boolean("p", "toggle", true), Ok(false));
/// assert!(moos_boolean("p", "1", false).is_err());
/// ```
pub fn moos_boolean(param: &str, value: &str, current: bool) -> Result<bool, ParamError> {
    match value.trim().to_ascii_lowercase().as_str() {
        "true" | "yes" | "on" => Ok(true),
        "false" | "no" | "off" => Ok(false),
        "toggle" => Ok(!current),
        _ => Err(ParamError::bad(
            param,
            value,
            "true, false, yes, no, on, off or toggle",
        )),
    }
}

/// Parses a boolean (`true`/`false`, any case).
pub fn boolean(param: &str, value: &str) -> Result<bool, ParamError> {
    match value.trim().to_ascii_lowercase().as_str() {
        "true" => Ok(true),
        "false" => Ok(false),
        _ => Err(ParamError::bad(param, value, "true or false")),
    }
}
