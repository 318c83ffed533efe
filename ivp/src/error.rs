//! Typed errors of the IvP core.

use thiserror::Error;

/// A bad decision domain or domain specification.
#[derive(Debug, Clone, PartialEq, Error)]
pub enum DomainError {
    /// The variable has no name.
    #[error("domain variable has an empty name")]
    EmptyName,
    /// Low or high is infinite or NaN.
    #[error("domain variable {0:?}: low and high must be finite numbers")]
    NotFinite(String),
    /// `low > high`.
    #[error("domain variable {name:?}: low {low} is above high {high}")]
    LowAboveHigh {
        /// Variable name.
        name: String,
        /// Given low.
        low: f64,
        /// Given high.
        high: f64,
    },
    /// Zero grid points.
    #[error("domain variable {0:?}: needs at least one point")]
    ZeroPoints(String),
    /// One point but `low != high`.
    #[error("domain variable {0:?}: one point requires low == high")]
    SinglePointRange(String),
    /// `low == high` but more than one point.
    #[error("domain variable {0:?}: a zero range requires exactly one point")]
    ZeroRangeManyPoints(String),
    /// The `delta=` form gives more points than can be represented.
    #[error("domain {0:?}: too many points")]
    TooManyPoints(String),
    /// Wrong number of `:`-separated fields.
    #[error(
        "domain {spec:?}: expected 4 or 5 fields (name:low:high:points[:optional]), found {found}"
    )]
    FieldCount {
        /// The spec as given.
        spec: String,
        /// Number of fields found.
        found: usize,
    },
    /// A field could not be read.
    #[error("domain {spec:?}: {field} field {found:?} is not {expected}")]
    BadField {
        /// The spec as given.
        spec: String,
        /// Which field.
        field: &'static str,
        /// The text found.
        found: String,
        /// What was expected.
        expected: &'static str,
    },
    /// Two variables share a name.
    #[error("domain variable {0:?} declared twice")]
    Duplicate(String),
    /// A variable name not in the domain.
    #[error("domain variable {0:?} not recognized")]
    UnknownVar(String),
    /// Two domains that must be disjoint share a variable.
    #[error("domains overlap in variable {0:?}")]
    Overlap(String),
}

/// A bad objective function, builder parameter, or solver input.
#[derive(Debug, Clone, PartialEq, Error)]
pub enum IvpError {
    /// A domain problem.
    #[error(transparent)]
    Domain(#[from] DomainError),
    /// The builder's domain is unusable for it (e.g. ZAIC needs exactly one variable with delta > 0).
    #[error("{builder}: {reason}")]
    BadDomain {
        /// Builder name, e.g. `ZAIC_LEQ`.
        builder: &'static str,
        /// What is wrong.
        reason: String,
    },
    /// A builder parameter is out of range.
    #[error("{builder}: parameter {param} = {value} is out of range: {expected}")]
    BadParam {
        /// Builder name.
        builder: &'static str,
        /// Parameter name.
        param: &'static str,
        /// Value given.
        value: f64,
        /// What was expected.
        expected: &'static str,
    },
    /// A piece does not fit the function's domain.
    #[error("piece {piece}: {reason}")]
    BadPiece {
        /// Index of the piece.
        piece: usize,
        /// What is wrong.
        reason: String,
    },
    /// A reflector setting could not be read.
    #[error("reflector: {0}")]
    Reflector(String),
    /// An encoded function (`BHV_IPF` text) could not be read.
    #[error("encoded IvP function: {0}")]
    Decode(String),
}
