//! Typed parsing of behaviour parameter values, as MOOS-IvP reads them.

use crate::behavior::ParamError;

/// Whether `s` is a number as MOOS `isNumber` reads it (optional sign, digits, one `.`,
/// optional exponent).
///
/// ```
/// assert!(behaviors::param::is_number("-3.5"));
/// assert!(!behaviors::param::is_number("3m"));
/// ```
pub fn is_number(s: &str) -> bool {
    mission::condition::is_numeric(s.trim())
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

/// Parses a boolean (`true`/`false`, any case).
pub fn boolean(param: &str, value: &str) -> Result<bool, ParamError> {
    match value.trim().to_ascii_lowercase().as_str() {
        "true" => Ok(true),
        "false" => Ok(false),
        _ => Err(ParamError::bad(param, value, "true or false")),
    }
}
