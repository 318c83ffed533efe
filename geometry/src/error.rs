//! Typed errors for the geometry string parsers.

use thiserror::Error;

/// Why a point, seglist, polygon or pattern string was rejected.
///
/// Every variant says what was expected; the offending text is included where there is one.
#[derive(Debug, Clone, PartialEq, Eq, Error)]
pub enum ParseError {
    /// The string was empty (or only whitespace).
    #[error("empty geometry specification")]
    Empty,
    /// A value that must be a number was not (MOOS `isNumber`: optional sign, digits, one `.`).
    #[error("expected a number for `{key}`, found `{found}`")]
    BadNumber {
        /// Parameter (or positional field) name.
        key: String,
        /// The text that was found.
        found: String,
    },
    /// A required parameter of a format was not given.
    #[error("missing required parameter `{key}` for {format}")]
    Missing {
        /// Parameter name.
        key: &'static str,
        /// Format name (e.g. `lawnmower`).
        format: &'static str,
    },
    /// A parameter value is out of its allowed range.
    #[error("invalid value `{found}` for `{key}`: expected {expected}")]
    InvalidValue {
        /// Parameter name.
        key: String,
        /// The text or number that was found.
        found: String,
        /// What the parameter must be.
        expected: &'static str,
    },
    /// A parameter this format does not know (MOOS returns a null shape for these).
    #[error("unknown parameter `{key}` for {format}")]
    UnknownKey {
        /// Parameter name as written.
        key: String,
        /// Format name.
        format: &'static str,
    },
    /// A vertex was not of the form `x,y[,z][,property]`.
    #[error("bad vertex `{0}`: expected x,y[,z][,property]")]
    BadVertex(String),
    /// `pts=` was not followed by a `{...}` group, or text after `}` did not start with a comma.
    #[error(
        "malformed pts group: expected pts={{x,y:x,y:...}} followed by `,key=value` pairs, found `{0}`"
    )]
    BadPointGroup(String),
    /// A positional form had the wrong number of comma-separated fields.
    #[error("{format} expects {expected} comma-separated fields, found {found}")]
    FieldCount {
        /// Format name.
        format: &'static str,
        /// Allowed field counts, e.g. `6 or 7`.
        expected: &'static str,
        /// Number of fields found.
        found: usize,
    },
    /// `format=` named a format this shape kind does not have.
    #[error("unknown {kind} format `{found}`; expected one of {expected}")]
    UnknownFormat {
        /// `seglist` or `polygon`.
        kind: &'static str,
        /// The format name found.
        found: String,
        /// The accepted names.
        expected: &'static str,
    },
    /// A form MOOS-IvP itself never accepts (kept as an explicit error so the cause is clear).
    #[error("unsupported form: {0}")]
    Unsupported(&'static str),
    /// A polygon form that must be convex produced (or listed) a non-convex vertex list.
    #[error("polygon is not convex (MOOS-IvP requires a convex polygon for this form)")]
    NotConvex,
    /// A string that carries no vertices and is not an erase (`active=false`) spec.
    #[error("no vertices given in `{0}`")]
    NoVertices(String),
    /// The requested pattern would have more vertices than the safety limit.
    #[error("pattern would generate {0} vertices, more than the limit of {limit}", limit = crate::pattern::MAX_VERTICES)]
    TooManyVertices(u64),
}
