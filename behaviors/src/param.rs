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
    moos_types::text::is_number(s)
}

/// C's `atof` as MOOS reads unvalidated numbers (see [`geometry::atof`]).
pub use geometry::atof;

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
    moos_types::text::set_boolean_on_string(current, value.trim())
        .ok_or_else(|| ParamError::bad(param, value, "true, false, yes, no, on, off or toggle"))
}

/// Parses a boolean (`true`/`false`, any case).
pub fn boolean(param: &str, value: &str) -> Result<bool, ParamError> {
    moos_types::text::strict_bool(value.trim())
        .ok_or_else(|| ParamError::bad(param, value, "true or false"))
}
