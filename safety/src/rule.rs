//! One safety rule and its parser.
//!
//! ```text
//! rule = NAME : CONDITION -> ACTION [, OPTION]...
//! ```
//!
//! See the crate documentation for the grammar, the terms and the options.

use std::fmt;

use thiserror::Error;

/// What a rule does while it is triggered, least drastic first.
#[derive(Debug, Clone, Copy, PartialEq, Eq, PartialOrd, Ord, Hash)]
pub enum Action {
    /// Report only (SAFETY_EVENT, an appcast run warning); never commands the vehicle.
    Warn,
    /// Post the configured return flags (the `.bhv` takes the vehicle home).
    Return,
    /// Take the helm off (manual override: the helm parks and posts its all-stop) and hold
    /// the actuators at zero.
    AllStop,
    /// Come up (through the helm or on the actuators), then disarm the thruster.
    SurfaceDisarm,
}

impl Action {
    /// The word used in rules, `SAFETY_MODE` and `SAFETY_EVENT`.
    pub fn as_str(self) -> &'static str {
        match self {
            Action::Warn => "warn",
            Action::Return => "return",
            Action::AllStop => "allstop",
            Action::SurfaceDisarm => "surface_disarm",
        }
    }

    /// The action named `word` (`all-stop`, `all_stop` and `surface` also read).
    pub fn parse(word: &str) -> Option<Action> {
        Some(match word.to_ascii_lowercase().as_str() {
            "warn" => Action::Warn,
            "return" => Action::Return,
            "allstop" | "all_stop" | "all-stop" => Action::AllStop,
            "surface_disarm" | "surface" => Action::SurfaceDisarm,
            _ => return None,
        })
    }

    /// The default priority of a rule with this action (1 is the highest).
    pub fn default_priority(self) -> u8 {
        match self {
            Action::SurfaceDisarm => 1,
            Action::AllStop => 2,
            Action::Return => 3,
            Action::Warn => 4,
        }
    }
}

/// What a rule watches, for the health word's bits (see [`crate::HEALTH_BITS`]).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum Kind {
    /// A leak sensor.
    Leak,
    /// The battery.
    Battery,
    /// Depth limits.
    Depth,
    /// A sensor stopped reporting (DVL, depth, AHRS, GPS).
    Sensor,
    /// Navigation quality (position sigma).
    Nav,
    /// Acoustic contact with the base.
    Comms,
    /// A vital app (helm, controller, driver) silent or misconfigured.
    App,
    /// Anything else.
    Other,
}

impl Kind {
    /// Every kind, in bit order.
    pub const ALL: [Kind; 8] = [
        Kind::Leak,
        Kind::Battery,
        Kind::Depth,
        Kind::Sensor,
        Kind::Nav,
        Kind::Comms,
        Kind::App,
        Kind::Other,
    ];

    /// The kind's word (`kind=` option, and a rule named so takes that kind).
    pub fn as_str(self) -> &'static str {
        match self {
            Kind::Leak => "leak",
            Kind::Battery => "battery",
            Kind::Depth => "depth",
            Kind::Sensor => "sensor",
            Kind::Nav => "nav",
            Kind::Comms => "comms",
            Kind::App => "app",
            Kind::Other => "other",
        }
    }

    /// The kind named `word`.
    pub fn parse(word: &str) -> Option<Kind> {
        Kind::ALL
            .into_iter()
            .find(|k| k.as_str().eq_ignore_ascii_case(word))
    }

    /// The kind's bit in the health word.
    pub fn bit(self) -> u32 {
        let i = Kind::ALL.iter().position(|k| *k == self).unwrap_or(7);
        1 << (8 + i)
    }
}

/// A comparison operator.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Op {
    /// `==`
    Eq,
    /// `!=`
    Ne,
    /// `<`
    Lt,
    /// `<=`
    Le,
    /// `>`
    Gt,
    /// `>=`
    Ge,
}

impl Op {
    /// The operator as written.
    pub fn as_str(self) -> &'static str {
        match self {
            Op::Eq => "==",
            Op::Ne => "!=",
            Op::Lt => "<",
            Op::Le => "<=",
            Op::Gt => ">",
            Op::Ge => ">=",
        }
    }

    /// Whether `a OP b` holds for numbers (false when either is NaN).
    pub fn holds(self, a: f64, b: f64) -> bool {
        match self {
            Op::Eq => a == b,
            Op::Ne => a != b && !a.is_nan() && !b.is_nan(),
            Op::Lt => a < b,
            Op::Le => a <= b,
            Op::Gt => a > b,
            Op::Ge => a >= b,
        }
    }
}

/// The right-hand side of a comparison.
#[derive(Debug, Clone, PartialEq)]
pub enum Operand {
    /// A number: the variable's double value (or a numeric string) is compared.
    Number(f64),
    /// `true` / `false`: a MOOS boolean string, or a double (non-zero is true).
    Bool(bool),
    /// A word: the string value, compared ignoring ASCII case (`==` and `!=` only).
    Word(String),
}

impl fmt::Display for Operand {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            Operand::Number(x) => write!(f, "{x}"),
            Operand::Bool(b) => write!(f, "{b}"),
            Operand::Word(w) => f.write_str(w),
        }
    }
}

/// One term of a condition; a condition holds when all its terms hold.
#[derive(Debug, Clone, PartialEq)]
pub enum Term {
    /// `VAR OP VALUE`: the latest value of `VAR`; false while `VAR` has never been received
    /// (pair it with a `stale(VAR)` rule to catch a sensor that never reports).
    Compare {
        /// The variable.
        var: String,
        /// The operator.
        op: Op,
        /// The value compared with.
        value: Operand,
    },
    /// `stale(VAR) > SECONDS`: no mail of `VAR` for more than that (counted from pSafety's
    /// start while it has never been received).
    Stale {
        /// The variable.
        var: String,
        /// Seconds.
        seconds: f64,
    },
    /// `silent(APP) > SECONDS`: no `<APP>_STATUS` and no other mail from `APP` for more than
    /// that (counted from pSafety's start while it has never been heard).
    Silent {
        /// The app's MOOS name (case as written; `<APP>_STATUS` is its upper case).
        app: String,
        /// Seconds.
        seconds: f64,
    },
}

impl fmt::Display for Term {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            Term::Compare { var, op, value } => write!(f, "{var} {} {value}", op.as_str()),
            Term::Stale { var, seconds } => write!(f, "stale({var}) > {seconds}"),
            Term::Silent { app, seconds } => write!(f, "silent({app}) > {seconds}"),
        }
    }
}

/// When a triggered rule lets go.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Release {
    /// Stays triggered until `SAFETY_RESET` names it (or `all`) while its condition is false.
    Latch,
    /// Clears by itself once its condition has been false for this many seconds.
    Clear(f64),
}

/// A parsed rule.
#[derive(Debug, Clone, PartialEq)]
pub struct Rule {
    /// The rule's name (unique in a block).
    pub name: String,
    /// All must hold.
    pub terms: Vec<Term>,
    /// What it does.
    pub action: Action,
    /// 1 is the highest; among triggered rules the highest priority commands the vehicle.
    pub priority: u8,
    /// Latched (the default) or clearing.
    pub release: Release,
    /// Its health-word bit.
    pub kind: Kind,
}

impl Rule {
    /// The condition as text (`LEAK == true and ...`).
    pub fn condition_text(&self) -> String {
        let parts: Vec<String> = self.terms.iter().map(Term::to_string).collect();
        parts.join(" and ")
    }
}

/// Why a rule's text cannot be read.
#[derive(Debug, Clone, PartialEq, Eq, Error)]
pub enum RuleError {
    /// No `NAME :` at the start.
    #[error("expected `NAME : CONDITION -> ACTION`, found no `:` after the rule's name")]
    MissingName,
    /// The name is empty or has characters other than letters, digits, `_` and `-`.
    #[error("bad rule name `{0}`: use letters, digits, `_` and `-`")]
    BadName(String),
    /// No `->` between the condition and the action.
    #[error("expected `->` between the condition and the action")]
    MissingArrow,
    /// Nothing before `->`.
    #[error("the condition is empty")]
    EmptyCondition,
    /// A term that is none of the forms.
    #[error(
        "cannot read the term `{0}`: expected `VAR OP VALUE`, `stale(VAR) > SECONDS` or `silent(APP) > SECONDS`"
    )]
    BadTerm(String),
    /// `=` where `==` is meant, or an operator that is not one of `== != < <= > >=`.
    #[error("bad operator in `{0}`: use one of == != < <= > >=")]
    BadOperator(String),
    /// A variable or app name with spaces or nothing in it.
    #[error("bad variable or app name `{0}`")]
    BadVariable(String),
    /// `stale(..)`/`silent(..)` without `> SECONDS` (a positive number).
    #[error("`{0}`: expected `> SECONDS` with a positive number of seconds")]
    BadTimeout(String),
    /// `<`, `<=`, `>`, `>=` with a word or a boolean.
    #[error("`{0}`: an order comparison needs a number")]
    OrderOnWord(String),
    /// An empty value after the operator.
    #[error("`{0}`: no value after the operator")]
    MissingValue(String),
    /// The action word is not known.
    #[error("unknown action `{0}`: expected surface_disarm, allstop, return or warn")]
    UnknownAction(String),
    /// No action after `->`.
    #[error("no action after `->`")]
    MissingAction,
    /// An option that is not known.
    #[error("unknown option `{0}`: expected priority=N, latch, clear[=SECONDS] or kind=K")]
    UnknownOption(String),
    /// `priority=` not an integer 1..=99.
    #[error("bad priority `{0}`: expected an integer from 1 (highest) to 99")]
    BadPriority(String),
    /// `clear=` not a number of seconds >= 0.
    #[error("bad clear delay `{0}`: expected seconds >= 0")]
    BadClear(String),
    /// `kind=` not a known kind.
    #[error("unknown kind `{0}`: expected leak, battery, depth, sensor, nav, comms, app or other")]
    UnknownKind(String),
    /// Both `latch` and `clear`, or an option given twice.
    #[error("option `{0}` given twice or contradicting another")]
    ConflictingOption(String),
}

fn is_name(s: &str) -> bool {
    !s.is_empty()
        && s.chars()
            .all(|c| c.is_ascii_alphanumeric() || c == '_' || c == '-')
}

fn is_var(s: &str) -> bool {
    !s.is_empty()
        && s.chars()
            .all(|c| !c.is_whitespace() && !matches!(c, '(' | ')' | '=' | '<' | '>' | '!' | ','))
}

/// Splits `s` on the word `and` (any case, between white space).
fn split_and(s: &str) -> Vec<String> {
    let mut terms = vec![String::new()];
    for w in s.split_whitespace() {
        if w.eq_ignore_ascii_case("and") {
            terms.push(String::new());
        } else {
            let t = terms.last_mut().expect("one term at least");
            if !t.is_empty() {
                t.push(' ');
            }
            t.push_str(w);
        }
    }
    terms
}

/// The first operator in `s` (byte offset, operator, its length).
fn find_op(s: &str) -> Option<(usize, Op, usize)> {
    let b = s.as_bytes();
    for i in 0..b.len() {
        let two = b.get(i + 1).copied();
        let r = match (b[i], two) {
            (b'=', Some(b'=')) => (Op::Eq, 2),
            (b'!', Some(b'=')) => (Op::Ne, 2),
            (b'<', Some(b'=')) => (Op::Le, 2),
            (b'>', Some(b'=')) => (Op::Ge, 2),
            (b'<', _) => (Op::Lt, 1),
            (b'>', _) => (Op::Gt, 1),
            _ => continue,
        };
        return Some((i, r.0, r.1));
    }
    None
}

fn parse_seconds(text: &str, op: Op, rhs: &str) -> Result<f64, RuleError> {
    if !matches!(op, Op::Gt | Op::Ge) {
        return Err(RuleError::BadTimeout(text.to_string()));
    }
    match rhs.trim().parse::<f64>() {
        Ok(s) if s.is_finite() && s > 0.0 => Ok(s),
        _ => Err(RuleError::BadTimeout(text.to_string())),
    }
}

fn parse_term(text: &str) -> Result<Term, RuleError> {
    let t = text.trim();
    if t.is_empty() {
        return Err(RuleError::EmptyCondition);
    }
    let Some((at, op, len)) = find_op(t) else {
        if t.contains('=') {
            return Err(RuleError::BadOperator(t.to_string()));
        }
        return Err(RuleError::BadTerm(t.to_string()));
    };
    let lhs = t[..at].trim();
    let rhs = t[at + len..].trim();
    if rhs.starts_with(['=', '<', '>', '!']) {
        return Err(RuleError::BadOperator(t.to_string()));
    }
    let lower = lhs.to_ascii_lowercase();
    for (func, silent) in [("stale", false), ("silent", true)] {
        if let Some(rest) = lower.strip_prefix(func)
            && rest.trim_start().starts_with('(')
        {
            let open = lhs.find('(').unwrap_or(0);
            let Some(inner) = lhs[open + 1..].strip_suffix(')') else {
                return Err(RuleError::BadTerm(t.to_string()));
            };
            let name = inner.trim();
            if !is_var(name) {
                return Err(RuleError::BadVariable(name.to_string()));
            }
            let seconds = parse_seconds(t, op, rhs)?;
            return Ok(if silent {
                Term::Silent {
                    app: name.to_string(),
                    seconds,
                }
            } else {
                Term::Stale {
                    var: name.to_string(),
                    seconds,
                }
            });
        }
    }
    if !is_var(lhs) {
        return Err(if lhs.is_empty() || lhs.contains(['(', ')']) {
            RuleError::BadTerm(t.to_string())
        } else {
            RuleError::BadVariable(lhs.to_string())
        });
    }
    if rhs.is_empty() {
        return Err(RuleError::MissingValue(t.to_string()));
    }
    let value = if let Some(x) = rhs.parse::<f64>().ok().filter(|x| x.is_finite()) {
        Operand::Number(x)
    } else if rhs.eq_ignore_ascii_case("true") {
        Operand::Bool(true)
    } else if rhs.eq_ignore_ascii_case("false") {
        Operand::Bool(false)
    } else if is_var(rhs) {
        Operand::Word(rhs.to_string())
    } else {
        return Err(RuleError::BadTerm(t.to_string()));
    };
    if !matches!(value, Operand::Number(_)) && !matches!(op, Op::Eq | Op::Ne) {
        return Err(RuleError::OrderOnWord(t.to_string()));
    }
    Ok(Term::Compare {
        var: lhs.to_string(),
        op,
        value,
    })
}

/// Reads one rule (the value of a `rule =` line).
///
/// ```
/// use safety::rule::{parse_rule, Action, Kind, Release};
/// let r = parse_rule("leak: LEAK == true -> surface_disarm, priority=1, latch").unwrap();
/// assert_eq!((r.name.as_str(), r.action, r.priority), ("leak", Action::SurfaceDisarm, 1));
/// assert_eq!((r.release, r.kind), (Release::Latch, Kind::Leak));
/// assert!(parse_rule("leak: LEAK = true -> surface_disarm").is_err());
/// ```
pub fn parse_rule(text: &str) -> Result<Rule, RuleError> {
    let Some((name, rest)) = text.split_once(':') else {
        return Err(RuleError::MissingName);
    };
    let name = name.trim();
    if !is_name(name) {
        return Err(RuleError::BadName(name.to_string()));
    }
    let Some((cond, tail)) = rest.split_once("->") else {
        return Err(RuleError::MissingArrow);
    };
    if cond.trim().is_empty() {
        return Err(RuleError::EmptyCondition);
    }
    let terms = split_and(cond)
        .iter()
        .map(|t| parse_term(t))
        .collect::<Result<Vec<_>, _>>()?;
    let mut parts = tail.split(',').map(str::trim);
    let action_word = parts.next().unwrap_or("");
    if action_word.is_empty() {
        return Err(RuleError::MissingAction);
    }
    let action =
        Action::parse(action_word).ok_or_else(|| RuleError::UnknownAction(action_word.into()))?;
    let mut priority = None;
    let mut release = None;
    let mut kind = None;
    for opt in parts {
        let (key, value) = match opt.split_once('=') {
            Some((k, v)) => (k.trim().to_ascii_lowercase(), Some(v.trim())),
            None => (opt.to_ascii_lowercase(), None),
        };
        let dup = || RuleError::ConflictingOption(key.clone());
        match (key.as_str(), value) {
            ("priority", Some(v)) => {
                let p = v
                    .parse::<u8>()
                    .ok()
                    .filter(|p| (1..=99).contains(p))
                    .ok_or_else(|| RuleError::BadPriority(v.to_string()))?;
                if priority.replace(p).is_some() {
                    return Err(dup());
                }
            }
            ("latch", None) => {
                if release.replace(Release::Latch).is_some() {
                    return Err(dup());
                }
            }
            ("clear", v) => {
                let s = match v {
                    None => 0.0,
                    Some(v) => v
                        .parse::<f64>()
                        .ok()
                        .filter(|s| s.is_finite() && *s >= 0.0)
                        .ok_or_else(|| RuleError::BadClear(v.to_string()))?,
                };
                if release.replace(Release::Clear(s)).is_some() {
                    return Err(dup());
                }
            }
            ("kind", Some(v)) => {
                let k = Kind::parse(v).ok_or_else(|| RuleError::UnknownKind(v.to_string()))?;
                if kind.replace(k).is_some() {
                    return Err(dup());
                }
            }
            _ => return Err(RuleError::UnknownOption(opt.to_string())),
        }
    }
    Ok(Rule {
        name: name.to_string(),
        terms,
        action,
        priority: priority.unwrap_or_else(|| action.default_priority()),
        release: release.unwrap_or(Release::Latch),
        kind: kind.or_else(|| Kind::parse(name)).unwrap_or(Kind::Other),
    })
}
