//! Reading MOOS ProcessConfig parameters: typed errors and value parsers shared by all apps.
//!
//! Every app config is built from an iterator of `(key, value)` string pairs. Keys are
//! case-insensitive and surrounding blanks are ignored, as MOOS does. Each config type offers
//!
//! * `from_params`, strict: the first unknown key or bad value is an error, and
//! * `from_params_lenient`: unknown keys, bad values and missing required keys are returned
//!   as a list of [`ConfigError`]s next to the config (bad values leave the default in
//!   place), so the caller can warn (as the MOOS apps do with `reportConfigWarning`) and
//!   carry on: a swap-in app never exits on its configuration.
//!
//! The generic `CMOOSApp` keys (`AppTick`, `CommsTick`, `MaxAppTick`, `IterateMode`, ...) are
//! accepted by every app and ignored here.

/// A ProcessConfig parameter that could not be used.
#[derive(Debug, Clone, PartialEq, Eq, thiserror::Error)]
pub enum ConfigError {
    /// The key is not a parameter of this app.
    #[error("{app}: unknown parameter `{key}`")]
    UnknownKey {
        /// The app whose block held the key.
        app: &'static str,
        /// The key as given.
        key: String,
    },
    /// The value of a known key is not of the expected form.
    #[error("{app}: parameter `{key} = {value}`: expected {expected}")]
    BadValue {
        /// The app whose block held the key.
        app: &'static str,
        /// The key as given.
        key: String,
        /// The value as given.
        value: String,
        /// What the parameter accepts.
        expected: &'static str,
    },
    /// A parameter the app requires was not given.
    #[error("{app}: required parameter `{key}` is missing")]
    Missing {
        /// The app.
        app: &'static str,
        /// The required key.
        key: &'static str,
    },
}

/// Keys handled by the generic MOOS application base class, accepted in every block.
const GENERIC_APP_KEYS: &[&str] = &[
    "apptick",
    "commstick",
    "maxapptick",
    "iteratemode",
    "term_reporting",
    "app_logging",
    "max_appcast_events",
    "max_appcast_run_warnings",
    "uselogging",
    "debug",
    "deprecated_ok",
];

/// True for keys that belong to the generic MOOS app layer rather than to the app.
pub fn is_generic_app_key(key_lower: &str) -> bool {
    GENERIC_APP_KEYS.contains(&key_lower)
}

/// Context for parsing one parameter: the app name, the key and the value as given.
#[derive(Debug, Clone, Copy)]
pub(crate) struct Param<'a> {
    pub app: &'static str,
    pub key: &'a str,
    pub value: &'a str,
}

impl Param<'_> {
    pub(crate) fn bad(&self, expected: &'static str) -> ConfigError {
        ConfigError::BadValue {
            app: self.app,
            key: self.key.to_string(),
            value: self.value.to_string(),
            expected,
        }
    }

    pub(crate) fn f64(&self) -> Result<f64, ConfigError> {
        parse_number(self.value).ok_or_else(|| self.bad("a number"))
    }

    pub(crate) fn non_neg(&self) -> Result<f64, ConfigError> {
        match parse_number(self.value) {
            Some(v) if v >= 0.0 => Ok(v),
            _ => Err(self.bad("a non-negative number")),
        }
    }

    pub(crate) fn pos(&self) -> Result<f64, ConfigError> {
        match parse_number(self.value) {
            Some(v) if v > 0.0 => Ok(v),
            _ => Err(self.bad("a positive number")),
        }
    }

    pub(crate) fn range(
        &self,
        lo: f64,
        hi: f64,
        expected: &'static str,
    ) -> Result<f64, ConfigError> {
        match parse_number(self.value) {
            Some(v) if (lo..=hi).contains(&v) => Ok(v),
            _ => Err(self.bad(expected)),
        }
    }

    pub(crate) fn bool(&self) -> Result<bool, ConfigError> {
        parse_bool(self.value).ok_or_else(|| self.bad("true or false"))
    }

    /// A MOOS boolean as `setBooleanOnString` reads it: `toggle` flips `current`.
    pub(crate) fn bool_or_toggle(&self, current: bool) -> Result<bool, ConfigError> {
        set_bool_on_string(current, self.value).ok_or_else(|| self.bad("true, false or toggle"))
    }

    pub(crate) fn word(&self) -> Result<String, ConfigError> {
        let v = self.value.trim();
        if v.is_empty() || v.chars().any(char::is_whitespace) {
            Err(self.bad("a non-empty word without blanks"))
        } else {
            Ok(v.to_string())
        }
    }
}

/// Parses a number the way MOOS's `isNumber` + `atof` accept it (blanks around are allowed).
pub fn parse_number(s: &str) -> Option<f64> {
    moos_types::text::is_number(s).then(|| moos_types::text::atof(s.trim()))
}

/// Parses a MOOS boolean (`true`/`false`, case-insensitive; also `yes`/`no`, `on`/`off`).
pub fn parse_bool(s: &str) -> Option<bool> {
    let s = s.trim();
    if s.eq_ignore_ascii_case("toggle") {
        return None;
    }
    moos_types::text::set_boolean_on_string(false, s)
}

/// MOOS `setBooleanOnString`: `true`/`yes`/`on` and `false`/`no`/`off` (any case), or
/// `toggle`, which flips `current`; `None` for anything else. Blanks are not trimmed.
///
/// ```
/// use vehicle::config::set_bool_on_string;
/// assert_eq!(set_bool_on_string(false, "Toggle"), Some(true));
/// assert_eq!(set_bool_on_string(true, "OFF"), Some(false));
/// assert_eq!(set_bool_on_string(true, " true"), None);
/// ```
pub fn set_bool_on_string(current: bool, s: &str) -> Option<bool> {
    moos_types::text::set_boolean_on_string(current, s)
}

/// Runs `apply` over every pair; `apply` returns `Ok(false)` for keys it does not know.
/// Returns every problem (unknown keys and bad values, in file order): none is fatal, as
/// the C++ apps report them as config warnings and run on with the defaults.
pub(crate) fn apply_params<'a, T>(
    app: &'static str,
    target: &mut T,
    params: impl IntoIterator<Item = (&'a str, &'a str)>,
    mut apply: impl FnMut(&mut T, &str, Param<'a>) -> Result<bool, ConfigError>,
) -> Result<Vec<ConfigError>, ConfigError> {
    let mut unknown = Vec::new();
    for (key, value) in params {
        let key_t = key.trim();
        let lower = key_t.to_ascii_lowercase();
        if is_generic_app_key(&lower) {
            continue;
        }
        let p = Param {
            app,
            key: key_t,
            value: value.trim(),
        };
        match apply(target, &lower, p) {
            Ok(true) => {}
            Ok(false) => unknown.push(ConfigError::UnknownKey {
                app,
                key: key_t.to_string(),
            }),
            // As an AppCasting MOOS app: a config warning, the setting keeps its default and
            // the app runs on.
            Err(e) => unknown.push(e),
        }
    }
    Ok(unknown)
}

/// Turns a lenient result into a strict one: the first unknown key becomes the error.
pub(crate) fn strict<T>(r: Result<(T, Vec<ConfigError>), ConfigError>) -> Result<T, ConfigError> {
    let (t, unknown) = r?;
    match unknown.into_iter().next() {
        Some(e) => Err(e),
        None => Ok(t),
    }
}
