//! Logic conditions of `.bhv` files (behaviour `condition =` lines and `set` mode blocks),
//! parsed with nom into a [`Condition`] tree that the helm evaluates.
//!
//! Grammar (keywords case-insensitive; `and` binds tighter than `or`):
//! ```text
//! expr     := and_expr ( "or" and_expr )*
//! and_expr := unary ( "and" unary )*
//! unary    := ( "!" | "not" ) unary | "(" expr ")" | relation
//! relation := VARIABLE op operand          op := = == != < <= > >=
//! operand  := "quoted text" | $(VARIABLE) | NUMBER | bare-literal
//! ```
//! MOOS-IvP requires the operands of `and`/`or` to be parenthesized; coug also accepts bare
//! relations there. `==` is the colon-field match used by hierarchical modes:
//! `MODE == LOITERING` holds when MODE is `ACTIVE:LOITERING` ([`field_match`]).
//! [`Condition::evaluate`] evaluates a tree against current variable values.
//!
//! ```
//! use mission::condition::{parse_condition, Condition, Operand, RelOp};
//! let c = parse_condition("(MODE == ACTIVE:LOITERING) and !(RETURN = true)").unwrap();
//! let Condition::And(parts) = &c else { panic!() };
//! assert_eq!(parts[0], Condition::Compare {
//!     lhs: Operand::Var("MODE".into()), op: RelOp::FieldEq, rhs: Operand::Str("ACTIVE:LOITERING".into()) });
//! assert_eq!(c.to_string(), "(MODE == ACTIVE:LOITERING) and !(RETURN = true)");
//! ```

use std::fmt;

use nom::branch::alt;
use nom::bytes::complete::{tag, tag_no_case, take_while, take_while1};
use nom::character::complete::{char, space0};
use nom::error::{ErrorKind, ParseError};
use nom::{IResult, Parser};

/// A relation operator.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum RelOp {
    /// `=`: exact equality.
    Eq,
    /// `==`: colon-field match (`ACTIVE:SURVEYING` matches `SURVEYING`).
    FieldEq,
    /// `!=`: not equal.
    Ne,
    /// `<`.
    Lt,
    /// `<=`.
    Le,
    /// `>`.
    Gt,
    /// `>=`.
    Ge,
}

impl RelOp {
    /// The operator as written in files.
    pub fn as_str(self) -> &'static str {
        match self {
            RelOp::Eq => "=",
            RelOp::FieldEq => "==",
            RelOp::Ne => "!=",
            RelOp::Lt => "<",
            RelOp::Le => "<=",
            RelOp::Gt => ">",
            RelOp::Ge => ">=",
        }
    }
}

/// One side of a relation.
#[derive(Debug, Clone, PartialEq)]
pub enum Operand {
    /// A MOOS variable: the left side, or `$(NAME)` on the right side.
    Var(String),
    /// A string literal (quoted or bare).
    Str(String),
    /// A numeric literal.
    Num(f64),
}

/// A parsed logic condition.
#[derive(Debug, Clone, PartialEq)]
pub enum Condition {
    /// All of these hold (two or more).
    And(Vec<Condition>),
    /// Any of these holds (two or more).
    Or(Vec<Condition>),
    /// The negation.
    Not(Box<Condition>),
    /// A relation `lhs op rhs`; `lhs` is always an [`Operand::Var`] when parsed.
    Compare {
        /// The variable tested.
        lhs: Operand,
        /// The relation.
        op: RelOp,
        /// What it is compared with.
        rhs: Operand,
    },
}

impl Condition {
    /// Every variable the condition reads (left sides and `$(VAR)` right sides), in order.
    pub fn variables(&self) -> Vec<&str> {
        let mut out = Vec::new();
        self.collect_vars(&mut out);
        out
    }

    fn collect_vars<'a>(&'a self, out: &mut Vec<&'a str>) {
        match self {
            Condition::And(v) | Condition::Or(v) => v.iter().for_each(|c| c.collect_vars(out)),
            Condition::Not(c) => c.collect_vars(out),
            Condition::Compare { lhs, rhs, .. } => {
                for o in [lhs, rhs] {
                    if let Operand::Var(v) = o {
                        out.push(v);
                    }
                }
            }
        }
    }

    /// Whether any relation uses `op`.
    pub fn uses_op(&self, op: RelOp) -> bool {
        match self {
            Condition::And(v) | Condition::Or(v) => v.iter().any(|c| c.uses_op(op)),
            Condition::Not(c) => c.uses_op(op),
            Condition::Compare { op: o, .. } => *o == op,
        }
    }
}

/// A variable's current value as the helm's info buffer holds it (a borrowed MOOS value;
/// surrounding double quotes of a string are ignored when comparing, and binary data
/// satisfies no relation).
pub use moos_types::ValueRef as Value;

impl Condition {
    /// Evaluates the condition with current variable values, as pHelmIvP does: a relation on
    /// an unknown variable is false (even `!=`); string with string compares strings
    /// (`<`, `>` lexicographic, `==` colon-field match); number with number compares numbers
    /// (`==` is plain equality); a string compared with a number is converted when it is
    /// numeric, else the relation is false.
    ///
    /// ```
    /// use mission::condition::{parse_condition, Value};
    /// let c = parse_condition("(MODE == SURVEYING) and (DEPTH < 10)").unwrap();
    /// let vars = |n: &str| match n {
    ///     "MODE" => Some(Value::String("ACTIVE:SURVEYING")),
    ///     "DEPTH" => Some(Value::Double(4.0)),
    ///     _ => None,
    /// };
    /// assert!(c.evaluate(&vars));
    /// ```
    pub fn evaluate<'a, F>(&self, lookup: &F) -> bool
    where
        F: Fn(&str) -> Option<Value<'a>>,
    {
        match self {
            Condition::And(v) => v.iter().all(|c| c.evaluate(lookup)),
            Condition::Or(v) => v.iter().any(|c| c.evaluate(lookup)),
            Condition::Not(c) => !c.evaluate(lookup),
            Condition::Compare { lhs, op, rhs } => {
                let (Some(l), Some(r)) = (side(lhs, lookup), side(rhs, lookup)) else {
                    return false;
                };
                relate(*op, l.value(), r.value())
            }
        }
    }
}

fn side<'c, 'a, F>(o: &'c Operand, lookup: &F) -> Option<Side<'c, 'a>>
where
    F: Fn(&str) -> Option<Value<'a>>,
{
    match o {
        Operand::Var(v) => lookup(v).map(Side::Val),
        Operand::Str(s) => Some(Side::Lit(s)),
        Operand::Num(n) => Some(Side::Val(Value::Double(*n))),
    }
}

/// An operand resolved for evaluation: a literal of the condition or a variable's value.
enum Side<'c, 'a> {
    Lit(&'c str),
    Val(Value<'a>),
}

impl Side<'_, '_> {
    fn value(&self) -> Value<'_> {
        match self {
            Side::Lit(s) => Value::String(s),
            Side::Val(v) => *v,
        }
    }
}

fn unquote(s: &str) -> &str {
    s.strip_prefix('"')
        .and_then(|t| t.strip_suffix('"'))
        .unwrap_or(s)
}

fn numeric(s: &str) -> Option<f64> {
    let s = unquote(s).trim();
    if is_numeric(s) { s.parse().ok() } else { None }
}

fn relate(op: RelOp, l: Value<'_>, r: Value<'_>) -> bool {
    match (l, r) {
        (Value::String(a), Value::String(b)) => {
            let (a, b) = (unquote(a), unquote(b));
            match op {
                RelOp::Eq => a == b,
                RelOp::FieldEq => field_match(a, b),
                RelOp::Ne => a != b,
                RelOp::Lt => a < b,
                RelOp::Le => a <= b,
                RelOp::Gt => a > b,
                RelOp::Ge => a >= b,
            }
        }
        (Value::Double(a), Value::Double(b)) => compare_num(op, a, b),
        (Value::String(a), Value::Double(b)) => numeric(a).is_some_and(|a| compare_num(op, a, b)),
        (Value::Double(a), Value::String(b)) => numeric(b).is_some_and(|b| compare_num(op, a, b)),
        (Value::Binary(_), _) | (_, Value::Binary(_)) => false,
    }
}

fn compare_num(op: RelOp, a: f64, b: f64) -> bool {
    match op {
        RelOp::Eq | RelOp::FieldEq => a == b,
        RelOp::Ne => a != b,
        RelOp::Lt => a < b,
        RelOp::Le => a <= b,
        RelOp::Gt => a > b,
        RelOp::Ge => a >= b,
    }
}

/// The colon-field match of `==`: the side with fewer `:`-separated components matches when
/// its components appear, in order and adjacent, among the other side's components
/// (components trimmed). `ACTIVE:SURVEYING` matches `SURVEYING`, `ACTIVE` and
/// `ACTIVE:SURVEYING`, not `SURV`.
///
/// ```
/// use mission::condition::field_match;
/// assert!(field_match("ACTIVE:SURVEYING", "SURVEYING"));
/// assert!(field_match("ACTIVE", "ACTIVE:SURVEYING"));
/// assert!(!field_match("ACTIVE:SURVEYING", "TIVE:SURV"));
/// ```
pub fn field_match(a: &str, b: &str) -> bool {
    // Allocation-free: the helm evaluates conditions every iteration.
    let ca = a.split(':').count();
    let cb = b.split(':').count();
    let (short, long, ns, nl) = if ca < cb {
        (a, b, ca, cb)
    } else {
        (b, a, cb, ca)
    };
    (0..=nl - ns).any(|start| {
        long.split(':')
            .skip(start)
            .take(ns)
            .zip(short.split(':'))
            .all(|(x, y)| x.trim() == y.trim())
    })
}

/// Whether `s` is a number as conditions read it: MOOS `isNumber` (no exponent), as the
/// helm's `ParseNode` does.
pub fn is_numeric(s: &str) -> bool {
    moos_types::text::is_number(s)
}

fn is_word_char(c: char) -> bool {
    !c.is_whitespace() && !matches!(c, '"' | '<' | '>' | '=' | '!' | '(' | ')')
}

fn is_keyword(s: &str) -> bool {
    ["and", "or", "not"]
        .iter()
        .any(|k| s.eq_ignore_ascii_case(k))
}

impl fmt::Display for Operand {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            Operand::Var(v) => write!(f, "$({v})"),
            Operand::Num(n) => write!(f, "{n}"),
            Operand::Str(s) => {
                let bare = !s.is_empty()
                    && s.chars().all(is_word_char)
                    && !is_numeric(s)
                    && !is_keyword(s)
                    && !s.starts_with("$(");
                if bare {
                    f.write_str(s)
                } else {
                    write!(f, "\"{s}\"")
                }
            }
        }
    }
}

impl fmt::Display for Condition {
    /// The canonical form: relations as `VAR op value`, every operand of `and`/`or` and `!`
    /// parenthesized (as MOOS-IvP requires).
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            Condition::And(v) | Condition::Or(v) => {
                let sep = if matches!(self, Condition::And(_)) {
                    " and "
                } else {
                    " or "
                };
                for (i, c) in v.iter().enumerate() {
                    if i > 0 {
                        f.write_str(sep)?;
                    }
                    match c {
                        Condition::Not(_) => write!(f, "{c}")?,
                        _ => write!(f, "({c})")?,
                    }
                }
                Ok(())
            }
            Condition::Not(c) => write!(f, "!({c})"),
            Condition::Compare { lhs, op, rhs } => {
                match lhs {
                    Operand::Var(v) => f.write_str(v)?,
                    other => write!(f, "{other}")?,
                }
                write!(f, " {} {rhs}", op.as_str())
            }
        }
    }
}

/// Why a condition did not parse.
#[derive(Debug, Clone, PartialEq, Eq, thiserror::Error)]
#[error("at byte {offset}: expected {expected}, found {found}")]
pub struct ConditionError {
    /// Byte offset in the condition text where the problem is.
    pub offset: usize,
    /// What would have been accepted there.
    pub expected: String,
    /// What is there (`end of condition` at the end).
    pub found: String,
}

/// nom error that remembers the furthest point reached and what was expected there.
#[derive(Debug, Clone, PartialEq)]
struct PErr<'a> {
    at: &'a str,
    expected: &'static str,
}

impl<'a> ParseError<&'a str> for PErr<'a> {
    fn from_error_kind(input: &'a str, _kind: ErrorKind) -> Self {
        PErr {
            at: input,
            expected: "a condition",
        }
    }
    fn append(_input: &'a str, _kind: ErrorKind, other: Self) -> Self {
        other
    }
    fn or(self, other: Self) -> Self {
        // Keep the error that got furthest into the input.
        if other.at.len() < self.at.len() {
            other
        } else {
            self
        }
    }
}

type Res<'a, O> = IResult<&'a str, O, PErr<'a>>;

fn fail<'a, O>(at: &'a str, expected: &'static str) -> Res<'a, O> {
    Err(nom::Err::Error(PErr { at, expected }))
}

fn keyword<'a>(kw: &'static str) -> impl Fn(&'a str) -> Res<'a, &'a str> {
    move |i: &'a str| {
        let (rest, k) = tag_no_case(kw).parse(i)?;
        match rest.chars().next() {
            Some(c) if is_word_char(c) => fail(i, kw),
            _ => Ok((rest, k)),
        }
    }
}

fn expr(i: &str) -> Res<'_, Condition> {
    let (mut i, first) = and_expr(i)?;
    let mut items = vec![first];
    loop {
        let Ok((j, _)) = (space0, keyword("or"), space0).parse(i) else {
            break;
        };
        let (j, next) = and_expr(j)?;
        items.push(next);
        i = j;
    }
    Ok((
        i,
        if items.len() == 1 {
            items.remove(0)
        } else {
            Condition::Or(items)
        },
    ))
}

fn and_expr(i: &str) -> Res<'_, Condition> {
    let (mut i, first) = unary(i)?;
    let mut items = vec![first];
    loop {
        let Ok((j, _)) = (space0, keyword("and"), space0).parse(i) else {
            break;
        };
        let (j, next) = unary(j)?;
        items.push(next);
        i = j;
    }
    Ok((
        i,
        if items.len() == 1 {
            items.remove(0)
        } else {
            Condition::And(items)
        },
    ))
}

fn unary(i: &str) -> Res<'_, Condition> {
    let (i, _) = space0(i)?;
    if let Ok((j, _)) = alt((tag("!"), keyword("not"))).parse(i) {
        let (j, _) = space0(j)?;
        let (j, inner) = unary(j)?;
        return Ok((j, Condition::Not(Box::new(inner))));
    }
    if let Ok((j, _)) = char::<&str, PErr<'_>>('(').parse(i) {
        let (j, _) = space0(j)?;
        let (j, inner) = expr(j)?;
        let (j, _) = space0(j)?;
        return match char::<&str, PErr<'_>>(')').parse(j) {
            Ok((k, _)) => Ok((k, inner)),
            Err(_) => fail(j, "`)`, `and` or `or`"),
        };
    }
    relation(i)
}

fn variable(i: &str) -> Res<'_, &str> {
    let r: Res<'_, &str> = take_while1(is_word_char).parse(i);
    match r {
        Ok((rest, v)) if !is_keyword(v) => Ok((rest, v)),
        _ => fail(i, "a variable name or `(`"),
    }
}

fn rel_op(i: &str) -> Res<'_, RelOp> {
    let r: Res<'_, &str> = alt((
        tag("=="),
        tag("!="),
        tag("<="),
        tag(">="),
        tag("="),
        tag("<"),
        tag(">"),
    ))
    .parse(i);
    match r {
        Ok((rest, s)) => Ok((
            rest,
            match s {
                "==" => RelOp::FieldEq,
                "!=" => RelOp::Ne,
                "<=" => RelOp::Le,
                ">=" => RelOp::Ge,
                "=" => RelOp::Eq,
                "<" => RelOp::Lt,
                _ => RelOp::Gt,
            },
        )),
        Err(_) => fail(i, "a relation operator (=, ==, !=, <, <=, >, >=)"),
    }
}

fn operand(i: &str) -> Res<'_, Operand> {
    if let Some(q) = i.strip_prefix('"') {
        return match q.find('"') {
            Some(end) => Ok((&q[end + 1..], Operand::Str(q[..end].to_string()))),
            None => fail(&i[i.len()..], "a closing `\"`"),
        };
    }
    if let Some(body) = i.strip_prefix("$(") {
        let (rest, name) = take_while(|c: char| c != ')' && c != '(' && !c.is_whitespace())
            .parse(body)
            .map_err(|_: nom::Err<PErr<'_>>| {
                nom::Err::Error(PErr {
                    at: body,
                    expected: "a variable name",
                })
            })?;
        if name.is_empty() {
            return fail(body, "a variable name");
        }
        return match rest.strip_prefix(')') {
            Some(r) => Ok((r, Operand::Var(name.to_string()))),
            None => fail(rest, "`)` closing `$(`"),
        };
    }
    let r: Res<'_, &str> = take_while1(is_word_char).parse(i);
    match r {
        Ok((rest, w)) => {
            let n = if is_numeric(w) {
                w.parse::<f64>().ok().filter(|n| n.is_finite())
            } else {
                None
            };
            Ok((
                rest,
                n.map_or_else(|| Operand::Str(w.to_string()), Operand::Num),
            ))
        }
        Err(_) => fail(i, "a value (number, text, \"quoted text\" or $(VAR))"),
    }
}

fn relation(i: &str) -> Res<'_, Condition> {
    let (i, var) = variable(i)?;
    let (i, _) = space0(i)?;
    let (i, op) = rel_op(i)?;
    let (i, _) = space0(i)?;
    let (i, rhs) = operand(i)?;
    Ok((
        i,
        Condition::Compare {
            lhs: Operand::Var(var.to_string()),
            op,
            rhs,
        },
    ))
}

fn found_at(rest: &str) -> String {
    let tok: String = rest
        .trim_start()
        .chars()
        .take_while(|c| !c.is_whitespace())
        .take(30)
        .collect();
    if tok.is_empty() {
        "end of condition".to_string()
    } else {
        format!("`{tok}`")
    }
}

/// Parses a whole condition; trailing text is an error.
///
/// ```
/// let e = mission::condition::parse_condition("(DEPLOY = true").unwrap_err();
/// assert_eq!(e.expected, "`)`, `and` or `or`");
/// assert_eq!(e.offset, 14);
/// ```
pub fn parse_condition(text: &str) -> Result<Condition, ConditionError> {
    let err = |at: &str, expected: &str| ConditionError {
        offset: text.len() - at.len(),
        expected: expected.to_string(),
        found: found_at(at),
    };
    if let Some(at) = too_deep(text) {
        return Err(err(
            &text[at..],
            "at most 64 nested parentheses or negations",
        ));
    }
    match expr(text) {
        Ok((rest, c)) => {
            let rest_trim = rest.trim_start();
            if rest_trim.is_empty() {
                Ok(c)
            } else {
                Err(err(rest_trim, "`and`, `or` or the end of the condition"))
            }
        }
        Err(nom::Err::Error(e) | nom::Err::Failure(e)) => {
            let at = if e.at.trim_start().is_empty() {
                e.at
            } else {
                e.at.trim_start()
            };
            Err(err(at, e.expected))
        }
        Err(nom::Err::Incomplete(_)) => Err(err("", "more input")),
    }
}

/// Checks a condition that [`parse_condition`] accepts against pHelmIvP's stricter rules:
/// every operand of `and`/`or` must be parenthesized (`(A = 1) and !(B = 2)`), and negation
/// is written `!(...)` (coug also reads `not`). Returns where the first violation is.
///
/// ```
/// use mission::condition::moos_compat;
/// assert!(moos_compat("(A = 1) and ((B = 2) or !(C = 3))").is_none());
/// let e = moos_compat("(A = 1) and B = 2").unwrap();
/// assert_eq!(e.offset, 12);
/// ```
pub fn moos_compat(text: &str) -> Option<ConditionError> {
    compat_at(text, 0)
}

fn compat_at(text: &str, base: usize) -> Option<ConditionError> {
    let lead = text.len() - text.trim_start().len();
    let t = text.trim();
    let base = base + lead;
    let issue = |off: usize, expected: &str, rest: &str| ConditionError {
        offset: base + off,
        expected: expected.to_string(),
        found: found_at(rest),
    };
    let parts = split_connectives(t);
    if parts.len() > 1 {
        for &(start, end) in &parts {
            let part = &t[start..end];
            let plead = part.len() - part.trim_start().len();
            let inner = wrapped(part.trim());
            match inner {
                Some(_) => {
                    if let Some(e) = compat_at(part, base + start) {
                        return Some(e);
                    }
                }
                None => {
                    return Some(issue(
                        start + plead,
                        "a parenthesized operand of `and`/`or` (pHelmIvP requires it)",
                        part.trim(),
                    ));
                }
            }
        }
        return None;
    }
    let starts_not = t.get(..3).is_some_and(|k| k.eq_ignore_ascii_case("not"));
    if starts_not && !t.get(3..).is_some_and(|r| r.starts_with(is_word_char)) {
        return Some(issue(0, "`!(...)` (pHelmIvP has no `not`)", t));
    }
    if let Some(rest) = t.strip_prefix('!') {
        return compat_at(rest, base + 1);
    }
    if let Some(inner) = t.strip_prefix('(').and_then(|r| r.strip_suffix(')'))
        && wrapped(t).is_some()
    {
        return compat_at(inner, base + 1);
    }
    None
}

/// `(x)` or `!(x)` (spaces allowed after `!`) whose first `(` closes at the very end.
fn wrapped(t: &str) -> Option<&str> {
    let body = match t.strip_prefix('!') {
        Some(r) => r.trim_start(),
        None => t,
    };
    let inner = body.strip_prefix('(')?;
    let mut depth = 1usize;
    let mut quoted = false;
    for (i, c) in inner.char_indices() {
        match c {
            '"' => quoted = !quoted,
            _ if quoted => {}
            '(' => depth += 1,
            ')' => {
                depth -= 1;
                if depth == 0 {
                    return (i + 1 == inner.len()).then(|| &inner[..i]);
                }
            }
            _ => {}
        }
    }
    None
}

/// Byte ranges of the operands of the top-level `and`/`or` connectives of `t`.
fn split_connectives(t: &str) -> Vec<(usize, usize)> {
    let b = t.as_bytes();
    let mut parts = Vec::new();
    let (mut depth, mut quoted, mut start) = (0usize, false, 0usize);
    let mut i = 0;
    while i < b.len() {
        match b[i] {
            b'"' => quoted = !quoted,
            _ if quoted => {}
            b'(' => depth += 1,
            b')' => depth = depth.saturating_sub(1),
            _ if depth == 0 => {
                for kw in [&b"and"[..], &b"or"[..]] {
                    let end = i + kw.len();
                    // A connective stands between two operands: never first or last.
                    if i == 0 || end >= b.len() || !b[i..end].eq_ignore_ascii_case(kw) {
                        continue;
                    }
                    let before_ok = b[i - 1].is_ascii_whitespace() || b[i - 1] == b')';
                    let after_ok = b[end].is_ascii_whitespace() || b[end] == b'(';
                    if before_ok && after_ok {
                        parts.push((start, i));
                        start = end;
                        i = end - 1;
                        break;
                    }
                }
            }
            _ => {}
        }
        i += 1;
    }
    parts.push((start, b.len()));
    parts
}

/// Byte offset where nesting of `(` (outside quotes) plus negations exceeds the parser's limit,
/// which keeps the recursive parser far from the stack's end on hostile input.
fn too_deep(text: &str) -> Option<usize> {
    const LIMIT: usize = 64;
    let mut depth = 0usize;
    let mut negations = 0usize;
    let mut quoted = false;
    let lower = text.as_bytes();
    for (i, &b) in lower.iter().enumerate() {
        match b {
            b'"' => quoted = !quoted,
            _ if quoted => {}
            b'(' => depth += 1,
            b')' => depth = depth.saturating_sub(1),
            b'!' => negations += 1,
            b'n' | b'N' if lower.len() >= i + 3 && lower[i..i + 3].eq_ignore_ascii_case(b"not") => {
                negations += 1
            }
            _ => {}
        }
        if depth + negations > LIMIT {
            return Some(i);
        }
    }
    None
}

#[cfg(test)]
mod tests {
    use super::*;

    fn eval(cond: &str, vars: &[(&str, Value<'static>)]) -> bool {
        let c = parse_condition(cond).unwrap();
        c.evaluate(&|n: &str| vars.iter().find(|(k, _)| *k == n).map(|(_, v)| *v))
    }

    #[test]
    fn colon_field_match_for_hierarchical_modes() {
        let mode = [("MODE", Value::String("ACTIVE:LOITERING"))];
        assert!(eval("MODE == LOITERING", &mode));
        assert!(eval("MODE == ACTIVE", &mode));
        assert!(eval("MODE == ACTIVE:LOITERING", &mode));
        assert!(!eval("MODE == LOITER", &mode));
        assert!(!eval("MODE == INACTIVE", &mode));
        assert!(!eval("MODE = LOITERING", &mode), "`=` is exact");
        assert!(eval("MODE = ACTIVE:LOITERING", &mode));
        let deep = [("MODE", Value::String("A:B:C"))];
        assert!(eval("MODE == A:B:C", &deep));
        assert!(eval("MODE == B:C", &deep));
        assert!(!eval("MODE == A:C", &deep));
    }

    #[test]
    fn types_and_unknown_variables() {
        let v = [
            ("N", Value::Double(5.0)),
            ("S", Value::String("abc")),
            ("T", Value::String("7")),
        ];
        assert!(eval("N > 4", &v));
        assert!(eval("N == 5", &v));
        assert!(
            !eval("N = abc", &v),
            "number vs non-numeric string is false"
        );
        assert!(!eval("N != abc", &v), "even for !=");
        assert!(eval("T > 6", &v), "numeric string vs number converts");
        assert!(eval("S < abd", &v), "lexicographic");
        assert!(eval("S = \"abc\"", &v));
        assert!(!eval("GHOST = 1", &v), "unknown variable: false");
        assert!(
            !eval("GHOST != 1", &v),
            "unknown variable: false even for !="
        );
        assert!(eval("!(GHOST = 1)", &v));
        assert!(eval(
            "N > $(T)",
            &[("N", Value::Double(8.0)), ("T", Value::String("7"))]
        ));
        assert!(!eval("N > $(U)", &v), "unknown right-hand variable: false");
        assert!(eval("(N = 1) or ((S = abc) and !(N < 0))", &v));
    }
}
