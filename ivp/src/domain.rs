//! The decision domain: ordered, discretised decision variables (pHelmIvP's `IvPDomain`).

use std::fmt;
use std::sync::Arc;

use super::error::DomainError;

/// How a continuous value is snapped onto the grid of a [`DomainVar`].
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Snap {
    /// Round down to the grid point at or below the value.
    Floor,
    /// Round up to the grid point at or above the value.
    Ceil,
    /// Round to the nearest grid point (halfway rounds down, as MOOS-IvP does).
    Nearest,
}

/// One decision variable: `points` evenly spaced values from `low` to `high`.
#[derive(Debug, Clone, PartialEq)]
pub struct DomainVar {
    name: Arc<str>,
    low: f64,
    high: f64,
    points: u32,
    optional: bool,
}

impl DomainVar {
    /// A variable with the same validation rules as MOOS-IvP's `IvPDomain::addDomain`.
    ///
    /// ```
    /// # use ivp::DomainVar;
    /// let speed = DomainVar::new("speed", 0.0, 4.0, 41).unwrap();
    /// assert!((speed.delta() - 0.1).abs() < 1e-12);
    /// ```
    pub fn new(name: &str, low: f64, high: f64, points: u32) -> Result<Self, DomainError> {
        if name.is_empty() {
            return Err(DomainError::EmptyName);
        }
        if !low.is_finite() || !high.is_finite() {
            return Err(DomainError::NotFinite(name.to_string()));
        }
        if low > high {
            return Err(DomainError::LowAboveHigh {
                name: name.to_string(),
                low,
                high,
            });
        }
        if points < 1 {
            return Err(DomainError::ZeroPoints(name.to_string()));
        }
        if points == 1 && low != high {
            return Err(DomainError::SinglePointRange(name.to_string()));
        }
        if points > 1 && low == high {
            return Err(DomainError::ZeroRangeManyPoints(name.to_string()));
        }
        Ok(Self {
            name: Arc::from(name),
            low,
            high,
            points,
            optional: false,
        })
    }

    /// Marks the variable optional: no `MissingDecVars` all-stop when nobody decides it.
    pub fn with_optional(mut self, optional: bool) -> Self {
        self.optional = optional;
        self
    }

    /// The variable's name, e.g. `course`.
    pub fn name(&self) -> &str {
        &self.name
    }
    /// Lowest value.
    pub fn low(&self) -> f64 {
        self.low
    }
    /// Highest value.
    pub fn high(&self) -> f64 {
        self.high
    }
    /// Number of grid points.
    pub fn points(&self) -> u32 {
        self.points
    }
    /// Whether the variable was declared `optional`.
    pub fn is_optional(&self) -> bool {
        self.optional
    }
    /// Grid spacing, `(high-low)/(points-1)`, or 0 for a one-point variable.
    pub fn delta(&self) -> f64 {
        if self.points <= 1 {
            0.0
        } else {
            (self.high - self.low) / f64::from(self.points - 1)
        }
    }
    /// The value of grid index `ix` (`low + delta*ix`).
    pub fn value(&self, ix: u32) -> f64 {
        self.low + self.delta() * f64::from(ix)
    }
    /// The grid index of `val`, snapped as requested and clamped into the domain.
    ///
    /// ```
    /// # use ivp::{DomainVar, Snap};
    /// let c = DomainVar::new("course", 0.0, 359.0, 360).unwrap();
    /// assert_eq!(c.index(10.5, Snap::Floor), 10);
    /// assert_eq!(c.index(10.5, Snap::Ceil), 11);
    /// assert_eq!(c.index(10.5, Snap::Nearest), 10);
    /// assert_eq!(c.index(10.6, Snap::Nearest), 11);
    /// assert_eq!(c.index(400.0, Snap::Nearest), 359);
    /// ```
    pub fn index(&self, val: f64, snap: Snap) -> u32 {
        if val.is_nan() || val <= self.low {
            return 0;
        }
        let top = self.points - 1;
        if val >= self.high {
            return top;
        }
        let delta = self.delta();
        let steps = (val - self.low) / delta;
        let raw = match snap {
            Snap::Floor => steps.floor(),
            Snap::Ceil => steps.ceil(),
            Snap::Nearest => (steps - 0.5).ceil(),
        };
        if raw <= 0.0 { 0 } else { (raw as u32).min(top) }
    }

    /// Parses pHelmIvP's `domain =` value: `name:low:high:points[:optional]`, commas accepted
    /// as separators, or `name:low:high:delta=D`.
    ///
    /// ```
    /// # use ivp::DomainVar;
    /// let v = DomainVar::parse("speed:0:4:delta=0.1").unwrap();
    /// assert_eq!(v.points(), 41);
    /// assert!(DomainVar::parse("depth,0,100,101,optional").unwrap().is_optional());
    /// ```
    pub fn parse(spec: &str) -> Result<Self, DomainError> {
        let spec = spec.trim();
        let fields: Vec<&str> = spec.split([':', ',']).map(str::trim).collect();
        if fields.len() != 4 && fields.len() != 5 {
            return Err(DomainError::FieldCount {
                spec: spec.to_string(),
                found: fields.len(),
            });
        }
        let name = fields[0];
        let low = parse_number(spec, "low", fields[1])?;
        let high = parse_number(spec, "high", fields[2])?;
        // pHelmIvP: a 5th field of `optional` (any case) makes the variable optional; any
        // other 5th field leaves it mandatory (it is not an error).
        let optional = fields
            .get(4)
            .is_some_and(|f| f.eq_ignore_ascii_case("optional"));
        let points_field = fields[3];
        let points = if let Some(d) = strip_prefix_ci(points_field, "delta=") {
            let delta = parse_number(spec, "delta", d)?;
            if delta <= 0.0 || high < low {
                return Err(DomainError::BadField {
                    spec: spec.to_string(),
                    field: "delta",
                    found: d.to_string(),
                    expected: "a positive step no larger than the range",
                });
            }
            let count = (high - low) / delta + 1.0;
            if count >= f64::from(u32::MAX) {
                return Err(DomainError::TooManyPoints(spec.to_string()));
            }
            // pHelmIvP truncates: points = (int)(range/delta + 1); a zero range keeps 1 point.
            let pts = count as u32;
            if low == high { 1 } else { pts }
        } else {
            points_field
                .parse::<u32>()
                .map_err(|_| DomainError::BadField {
                    spec: spec.to_string(),
                    field: "points",
                    found: points_field.to_string(),
                    expected: "a whole number of points or `delta=D`",
                })?
        };
        // With `delta=`, high is re-derived from the truncated point count so the grid keeps
        // the requested spacing; MOOS-IvP keeps the given high and so the spacing changes.
        // We follow MOOS-IvP: same low, high and points.
        Ok(Self::new(name, low, high, points)?.with_optional(optional))
    }
}

fn strip_prefix_ci<'a>(s: &'a str, prefix: &str) -> Option<&'a str> {
    if s.len() >= prefix.len() && s[..prefix.len()].eq_ignore_ascii_case(prefix) {
        Some(&s[prefix.len()..])
    } else {
        None
    }
}

fn parse_number(spec: &str, field: &'static str, text: &str) -> Result<f64, DomainError> {
    match text.parse::<f64>() {
        Ok(v) if v.is_finite() => Ok(v),
        _ => Err(DomainError::BadField {
            spec: spec.to_string(),
            field,
            found: text.to_string(),
            expected: "a finite number",
        }),
    }
}

/// An ordered list of decision variables with unique names.
///
/// The variables are shared: cloning a domain (every built function carries one) copies a
/// pointer, not the variables.
#[derive(Debug, Clone, PartialEq, Default)]
pub struct Domain {
    vars: Arc<Vec<DomainVar>>,
}

impl Domain {
    /// An empty domain.
    pub fn new() -> Self {
        Self::default()
    }

    /// Builds a domain from `(name, low, high, points)` tuples.
    ///
    /// ```
    /// # use ivp::Domain;
    /// let d = Domain::from_vars(&[("course", 0.0, 359.0, 360), ("speed", 0.0, 4.0, 41)]).unwrap();
    /// assert_eq!(d.len(), 2);
    /// assert_eq!(d.index_of("speed"), Some(1));
    /// ```
    pub fn from_vars(vars: &[(&str, f64, f64, u32)]) -> Result<Self, DomainError> {
        let mut d = Self::new();
        for &(name, low, high, points) in vars {
            d.add(DomainVar::new(name, low, high, points)?)?;
        }
        Ok(d)
    }

    /// Parses several pHelmIvP `domain =` values in order (see [`DomainVar::parse`]).
    pub fn parse_specs<'a>(specs: impl IntoIterator<Item = &'a str>) -> Result<Self, DomainError> {
        let mut d = Self::new();
        for spec in specs {
            d.add(DomainVar::parse(spec)?)?;
        }
        Ok(d)
    }

    /// Appends a variable; names must be unique.
    pub fn add(&mut self, var: DomainVar) -> Result<(), DomainError> {
        if self.index_of(var.name()).is_some() {
            return Err(DomainError::Duplicate(var.name().to_string()));
        }
        Arc::make_mut(&mut self.vars).push(var);
        Ok(())
    }

    /// Number of variables.
    pub fn len(&self) -> usize {
        self.vars.len()
    }
    /// True when there are no variables.
    pub fn is_empty(&self) -> bool {
        self.vars.is_empty()
    }
    /// The variables, in order.
    pub fn vars(&self) -> &[DomainVar] {
        &self.vars
    }
    /// Variable `i`.
    pub fn var(&self, i: usize) -> Option<&DomainVar> {
        self.vars.get(i)
    }
    /// Position of the variable called `name`.
    pub fn index_of(&self, name: &str) -> Option<usize> {
        self.vars.iter().position(|v| &*v.name == name)
    }
    /// The variable called `name`.
    pub fn get(&self, name: &str) -> Option<&DomainVar> {
        self.vars.iter().find(|v| &*v.name == name)
    }
    /// The one-variable domain holding only `name` (MOOS-IvP's `subDomain`).
    pub fn sub_domain(&self, name: &str) -> Result<Domain, DomainError> {
        let var = self
            .get(name)
            .ok_or_else(|| DomainError::UnknownVar(name.to_string()))?;
        Ok(Domain {
            vars: Arc::new(vec![var.clone()]),
        })
    }
    /// Number of grid points in the whole domain (product over variables), saturating.
    pub fn size(&self) -> u64 {
        self.vars
            .iter()
            .fold(1u64, |acc, v| acc.saturating_mul(u64::from(v.points)))
    }
}

impl fmt::Display for Domain {
    /// The `IVPHELM_DOMAIN` format: `name,low,high,points:name,...` with compact numbers.
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        for (i, v) in self.vars.iter().enumerate() {
            if i > 0 {
                f.write_str(":")?;
            }
            let mut s = String::new();
            s.push_str(&v.name);
            s.push(',');
            crate::encode::push_compact5(&mut s, v.low);
            s.push(',');
            crate::encode::push_compact5(&mut s, v.high);
            write!(f, "{s},{}", v.points)?;
        }
        Ok(())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn typical_helm_domains_parse() {
        let d =
            Domain::parse_specs(["course:0:359:360", "speed:0:4:41", "depth:0:100:101"]).unwrap();
        assert_eq!(d.len(), 3);
        let c = d.var(0).unwrap();
        assert_eq!(c.delta(), 1.0);
        assert_eq!(c.value(359), 359.0);
        let s = d.get("speed").unwrap();
        assert!((s.value(15) - 1.5).abs() < 1e-12);
        assert_eq!(d.size(), 360 * 41 * 101);
        assert_eq!(
            d.to_string(),
            "course,0,359,360:speed,0,4,41:depth,0,100,101"
        );
    }

    #[test]
    fn delta_form_truncates_like_phelmivp() {
        // range 4, delta 0.3 -> (int)(13.33 + 1) = 14 points.
        let v = DomainVar::parse("speed:0:4:delta=0.3").unwrap();
        assert_eq!(v.points(), 14);
        let v = DomainVar::parse("depth:5:5:delta=1").unwrap();
        assert_eq!(v.points(), 1);
        assert_eq!(v.delta(), 0.0);
    }

    #[test]
    fn snapping_rules() {
        let s = DomainVar::new("speed", 0.0, 4.0, 41).unwrap();
        assert_eq!(s.index(-1.0, Snap::Ceil), 0);
        assert_eq!(s.index(5.0, Snap::Floor), 40);
        assert_eq!(s.index(1.04, Snap::Floor), 10);
        assert_eq!(s.index(1.04, Snap::Ceil), 11);
        assert_eq!(s.index(1.04, Snap::Nearest), 10);
        assert_eq!(s.index(1.06, Snap::Nearest), 11);
        // exactly halfway rounds down (subtract delta/2 then ceil)
        let c = DomainVar::new("course", 0.0, 359.0, 360).unwrap();
        assert_eq!(c.index(7.5, Snap::Nearest), 7);
        assert_eq!(c.index(f64::NAN, Snap::Nearest), 0);
    }

    #[test]
    fn bad_domains_are_typed_errors() {
        assert!(matches!(
            DomainVar::parse("course:0:359"),
            Err(DomainError::FieldCount { found: 3, .. })
        ));
        assert!(matches!(
            DomainVar::parse("course:10:0:11"),
            Err(DomainError::LowAboveHigh { .. })
        ));
        assert!(matches!(
            DomainVar::parse("course:0:359:0"),
            Err(DomainError::ZeroPoints(_))
        ));
        assert!(matches!(
            DomainVar::parse("course:0:359:x"),
            Err(DomainError::BadField {
                field: "points",
                ..
            })
        ));
        assert!(matches!(
            DomainVar::parse("course:zero:359:360"),
            Err(DomainError::BadField { field: "low", .. })
        ));
        // pHelmIvP reads any 5th field other than `optional` as "mandatory".
        let v = DomainVar::parse("course:0:359:360:maybe").unwrap();
        assert!(!v.is_optional());
        assert!(
            DomainVar::parse("course:0:359:360:OPTIONAL")
                .unwrap()
                .is_optional()
        );
        assert!(matches!(
            DomainVar::parse("course:0:359:1"),
            Err(DomainError::SinglePointRange(_))
        ));
        assert!(matches!(
            DomainVar::parse("speed:0:4:delta=0"),
            Err(DomainError::BadField { field: "delta", .. })
        ));
        assert!(matches!(
            DomainVar::parse(":0:4:5"),
            Err(DomainError::EmptyName)
        ));
        assert!(matches!(
            DomainVar::parse("x:0:inf:5"),
            Err(DomainError::BadField { field: "high", .. })
        ));
        let mut d = Domain::new();
        d.add(DomainVar::parse("course:0:359:360").unwrap())
            .unwrap();
        assert!(matches!(
            d.add(DomainVar::parse("course:0:10:11").unwrap()),
            Err(DomainError::Duplicate(_))
        ));
        assert!(matches!(
            d.sub_domain("speed"),
            Err(DomainError::UnknownVar(_))
        ));
    }
}
