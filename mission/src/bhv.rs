//! `.bhv` files: `initialize` lines, `set MODE = VALUE { ... } ELSE` mode blocks and
//! `Behavior = BHV_TYPE { ... }` blocks, with their logic conditions parsed.
//!
//! ```
//! use mission::source::SourceMap;
//! let text = "initialize DEPLOY = false\n\
//!             set MODE = ACTIVE {\n  DEPLOY = true\n} INACTIVE\n\
//!             Behavior = BHV_Loiter\n{\n  name = loiter\n  condition = MODE == ACTIVE\n  speed = 1.3\n}\n";
//! let f = mission::bhv::parse_bhv(&SourceMap::from_text("a.bhv", text)).value;
//! assert_eq!(f.initializes[0].var, "DEPLOY");
//! assert_eq!(f.modes[0].else_value.as_deref(), Some("INACTIVE"));
//! assert_eq!(f.behaviors[0].kind, "BHV_Loiter");
//! assert_eq!(f.behaviors[0].name(), Some("loiter"));
//! assert_eq!(f.behaviors[0].get("SPEED"), Some("1.3"));
//! assert_eq!(f.behaviors[0].conditions[0].condition.variables(), ["MODE"]);
//! ```
//!
//! As in pHelmIvP: lines are trimmed; `//` and `#` lines are comments; a trailing `// ...` is
//! cut; a line ending in `\` continues on the next; a leading `{` or `}` is split off, a
//! trailing `{` too, but a trailing `}` stays part of the value (pHelmIvP does the same).
//! Lines starting with `<tag>` (nsplug plug-file section markers) are skipped.
//! Behaviour macros (`$[SPEED]`, `$(NX)`) in values are kept as text.

use std::fmt;

use crate::condition::{Condition, RelOp, parse_condition};
use crate::diagnostic::{Diagnostic, DiagnosticKind, quote_found};
use crate::moos::split_param;
use crate::source::{SourceLine, SourceMap, Span, column_of};
use crate::{Param, Parsed, strip_comment};

/// A parsed `.bhv` file.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct BehaviorFile {
    /// `initialize` / `initialize_` assignments, in file order (one per variable).
    pub initializes: Vec<Initialize>,
    /// `set` mode blocks, in file order (the order the helm evaluates them).
    pub modes: Vec<ModeBlock>,
    /// `Behavior` blocks, in file order.
    pub behaviors: Vec<BehaviorSpec>,
}

/// `initialize VAR = VALUE` (posted at helm start-up) or `initialize_ VAR = VALUE` (deferred:
/// posted only if no other app has posted VAR by then).
#[derive(Debug, Clone, PartialEq)]
pub struct Initialize {
    /// The MOOS variable.
    pub var: String,
    /// The value as written (quotes kept; the helm auto-types it).
    pub value: String,
    /// `initialize_` (deferred) rather than `initialize`.
    pub deferred: bool,
    /// Where the variable name is.
    pub span: Span,
}

/// A parsed condition with its source text and location.
#[derive(Debug, Clone, PartialEq)]
pub struct ConditionEntry {
    /// The condition text as written (after the `=` of a `condition` line).
    pub text: String,
    /// The parsed tree.
    pub condition: Condition,
    /// Where the condition text starts.
    pub span: Span,
}

/// `set VAR = VALUE { conditions } ELSEVALUE`.
#[derive(Debug, Clone, PartialEq)]
pub struct ModeBlock {
    /// The mode variable (usually `MODE`).
    pub var: String,
    /// The value given when every condition holds.
    pub value: String,
    /// The conditions (all must hold), in order.
    pub conditions: Vec<ConditionEntry>,
    /// The value given when the conditions fail but the parent-mode condition holds.
    pub else_value: Option<String>,
    /// Where the `set` line is.
    pub span: Span,
}

impl ModeBlock {
    /// The parent mode: the value of the first `VAR = X` condition on this block's own
    /// variable (e.g. `ACTIVE` for `MODE = ACTIVE`), which makes this a sub-mode.
    pub fn parent(&self) -> Option<&str> {
        self.conditions.iter().find_map(|c| match &c.condition {
            Condition::Compare {
                lhs: crate::condition::Operand::Var(v),
                op: RelOp::Eq,
                rhs: crate::condition::Operand::Str(s),
            } if *v == self.var => Some(s.as_str()),
            _ => None,
        })
    }
}

/// `Behavior = KIND { param = value ... }`.
#[derive(Debug, Clone, PartialEq)]
pub struct BehaviorSpec {
    /// The behaviour type, e.g. `BHV_Waypoint`.
    pub kind: String,
    /// Every `param = value` line of the block, in file order (including `condition` lines).
    pub params: Vec<Param>,
    /// The parsed `condition` lines (all must hold), in order.
    pub conditions: Vec<ConditionEntry>,
    /// Where the `Behavior` line is.
    pub span: Span,
}

/// The parameter name as pHelmIvP compares it: lower case, leading `_` removed.
pub fn param_name(key: &str) -> String {
    key.trim_start_matches('_').to_ascii_lowercase()
}

impl BehaviorSpec {
    /// The behaviour's name (`name` or `descriptor` parameter).
    pub fn name(&self) -> Option<&str> {
        self.get("name").or_else(|| self.get("descriptor"))
    }

    /// The first value of a parameter (case-insensitive, leading `_` ignored).
    pub fn get(&self, key: &str) -> Option<&str> {
        self.get_all(key).next()
    }

    /// Every value of a parameter, in file order.
    pub fn get_all<'a>(&'a self, key: &str) -> impl Iterator<Item = &'a str> + use<'a> {
        let want = param_name(key);
        self.params
            .iter()
            .filter(move |p| param_name(&p.key) == want)
            .map(|p| p.value.as_str())
    }
}

impl BehaviorFile {
    /// Same content as `other`, ignoring source locations and condition spelling (the parsed
    /// conditions are compared), for round-trip checks.
    pub fn same_content(&self, other: &BehaviorFile) -> bool {
        let inits = |f: &BehaviorFile| -> Vec<(String, String, bool)> {
            f.initializes
                .iter()
                .map(|i| (i.var.clone(), i.value.clone(), i.deferred))
                .collect()
        };
        let conds = |v: &[ConditionEntry]| -> Vec<Condition> {
            v.iter().map(|c| c.condition.clone()).collect()
        };
        let params = |v: &[Param]| -> Vec<(String, String)> {
            v.iter().map(|p| (p.key.clone(), p.value.clone())).collect()
        };
        inits(self) == inits(other)
            && self.modes.len() == other.modes.len()
            && self.modes.iter().zip(&other.modes).all(|(a, b)| {
                a.var == b.var
                    && a.value == b.value
                    && a.else_value == b.else_value
                    && conds(&a.conditions) == conds(&b.conditions)
            })
            && self.behaviors.len() == other.behaviors.len()
            && self.behaviors.iter().zip(&other.behaviors).all(|(a, b)| {
                a.kind == b.kind
                    && params(&a.params) == params(&b.params)
                    && conds(&a.conditions) == conds(&b.conditions)
            })
    }
}

impl fmt::Display for BehaviorFile {
    /// Canonical form: initializes, then mode blocks (conditions printed canonically), then
    /// behaviour blocks with the brace on its own line.
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        for i in &self.initializes {
            let kw = if i.deferred {
                "initialize_"
            } else {
                "initialize"
            };
            writeln!(f, "{kw} {} = {}", i.var, i.value)?;
        }
        for m in &self.modes {
            writeln!(f, "\nset {} = {} {{", m.var, m.value)?;
            for c in &m.conditions {
                writeln!(f, "  {}", c.condition)?;
            }
            match &m.else_value {
                Some(e) => writeln!(f, "}} {e}")?,
                None => writeln!(f, "}}")?,
            }
        }
        for b in &self.behaviors {
            writeln!(f, "\nBehavior = {}\n{{", b.kind)?;
            for p in &b.params {
                writeln!(f, "  {} = {}", p.key, p.value)?;
            }
            writeln!(f, "}}")?;
        }
        Ok(())
    }
}

/// A logical line: comment cut, `\` continuations joined, with its first physical line.
struct Logical<'a> {
    text: String,
    /// Byte offset of `text` in `line.text` (for columns; exact for the first physical line).
    offset: usize,
    line: &'a SourceLine,
}

fn logical_lines(src: &SourceMap) -> Vec<Logical<'_>> {
    let mut out: Vec<Logical<'_>> = Vec::new();
    let mut cont: Option<Logical<'_>> = None;
    for line in src.lines() {
        let raw = line.text.as_str();
        let t = raw.trim();
        let (piece, offset) = (t, raw.len() - raw.trim_start().len());
        let joined = match cont.take() {
            Some(mut c) => {
                c.text.push_str(piece);
                c
            }
            None => Logical {
                text: piece.to_string(),
                offset,
                line,
            },
        };
        if let Some(stripped) = joined.text.strip_suffix('\\') {
            let keep = stripped.to_string();
            cont = Some(Logical {
                text: keep,
                ..joined
            });
            continue;
        }
        out.push(joined);
    }
    if let Some(c) = cont {
        out.push(c);
    }
    for l in &mut out {
        if l.text.starts_with("//") || l.text.starts_with('#') || l.text.starts_with("<tag>") {
            l.text.clear();
        } else {
            let cut = strip_comment(&l.text).trim_end().len();
            l.text.truncate(cut);
        }
    }
    out
}

/// What the parser is inside of.
enum State {
    Top,
    Behavior(BehaviorSpec, usize),
    Mode(ModeBlock, usize),
    /// Another `{ ... }` block at top level, ignored (depth of nested braces).
    Ignored(usize),
}

/// A header line waiting for its `{`.
enum Pending {
    Behavior(BehaviorSpec, usize),
    Mode(ModeBlock, usize),
}

struct Parser<'a> {
    lines: Vec<Logical<'a>>,
    file: BehaviorFile,
    diags: Vec<Diagnostic>,
    state: State,
    pending: Option<Pending>,
}

/// Parses preprocessed `.bhv` text. Never fails: what cannot be read is reported.
pub fn parse_bhv(src: &SourceMap) -> Parsed<BehaviorFile> {
    let mut p = Parser {
        lines: logical_lines(src),
        file: BehaviorFile::default(),
        diags: Vec::new(),
        state: State::Top,
        pending: None,
    };
    let mut i = 0;
    while i < p.lines.len() {
        i = p.line(i);
    }
    p.finish();
    Parsed {
        value: p.file,
        diagnostics: p.diags,
    }
}

impl<'a> Parser<'a> {
    fn span(&self, idx: usize, byte: usize) -> Span {
        let l = &self.lines[idx];
        l.line.span(column_of(&l.line.text, l.offset + byte))
    }

    fn err(
        &self,
        kind: DiagnosticKind,
        idx: usize,
        byte: usize,
        msg: impl Into<String>,
    ) -> Diagnostic {
        Diagnostic::error(kind, self.span(idx, byte), msg).with_line(self.lines[idx].line)
    }

    /// Handles logical line `idx`; returns the index of the next line to read.
    fn line(&mut self, idx: usize) -> usize {
        let text = self.lines[idx].text.clone();
        let mut body = text.as_str();
        let mut off = 0;
        if body.is_empty() {
            return idx + 1;
        }
        // A leading brace is handled first.
        if let Some(rest) = body.strip_prefix('{') {
            self.open_brace(idx, 0);
            off = 1 + (rest.len() - rest.trim_start().len());
            body = rest.trim_start();
        } else if let Some(rest) = body.strip_prefix('}') {
            let after = rest.trim();
            let next = self.close_brace(idx, after, 1 + (rest.len() - rest.trim_start().len()));
            return next.unwrap_or(idx + 1);
        }
        if body.is_empty() {
            return idx + 1;
        }
        // A trailing brace is handled after the statement.
        let trailing = body.ends_with('{');
        if trailing {
            body = body[..body.len() - 1].trim_end();
        }
        if !body.is_empty() {
            self.statement(idx, off, body);
        }
        if trailing {
            self.open_brace(idx, off + body.len());
        }
        idx + 1
    }

    fn open_brace(&mut self, idx: usize, byte: usize) {
        if let State::Ignored(d) = &mut self.state {
            *d += 1;
            return;
        }
        match self.pending.take() {
            Some(Pending::Behavior(b, at)) => self.state = State::Behavior(b, at),
            Some(Pending::Mode(m, at)) => self.state = State::Mode(m, at),
            None => match self.state {
                State::Top => self.state = State::Ignored(1),
                _ => {
                    let d = self
                        .err(
                            DiagnosticKind::UnexpectedLine,
                            idx,
                            byte,
                            "`{` inside a block",
                        )
                        .expected("a parameter line or `}`")
                        .found("`{`");
                    self.diags.push(d);
                }
            },
        }
    }

    /// Closes the current block; for a mode block, reads the else value (`after` or the next
    /// line). Returns the next line index when it consumed a following line.
    fn close_brace(&mut self, idx: usize, after: &str, after_off: usize) -> Option<usize> {
        self.flush_pending(idx);
        match std::mem::replace(&mut self.state, State::Top) {
            State::Top => {
                let d = self
                    .err(
                        DiagnosticKind::UnexpectedCloseBrace,
                        idx,
                        0,
                        "`}` without an open block",
                    )
                    .expected("a `Behavior = TYPE` or `set VAR = VALUE` line and `{` before it")
                    .found("`}`");
                self.diags.push(d);
            }
            State::Ignored(d) if d > 1 => self.state = State::Ignored(d - 1),
            State::Ignored(_) => {}
            State::Behavior(b, _) => {
                self.file.behaviors.push(b);
                if !after.is_empty() {
                    let d = self
                        .err(
                            DiagnosticKind::UnexpectedLine,
                            idx,
                            after_off,
                            "text after the `}` closing a behaviour",
                        )
                        .expected("nothing after `}`")
                        .found(quote_found(after));
                    self.diags.push(d);
                }
            }
            State::Mode(mut m, _) => {
                let mut next = None;
                let mut else_val = after;
                let mut else_at = (idx, after_off);
                if after.is_empty() {
                    // The else value may be alone on the next non-empty line.
                    let j = (idx + 1..self.lines.len()).find(|&j| !self.lines[j].text.is_empty());
                    if let Some(j) = j {
                        let t = self.lines[j].text.as_str();
                        if is_else_token(t) {
                            else_val = t;
                            else_at = (j, 0);
                            next = Some(j + 1);
                        }
                    }
                }
                let else_val = else_val.to_string();
                if !else_val.is_empty() {
                    if else_val.split_whitespace().count() > 1 || else_val.contains(['=', '{', '}'])
                    {
                        let d = self
                            .err(
                                DiagnosticKind::UnexpectedLine,
                                else_at.0,
                                else_at.1,
                                "the else value of a mode must be one word",
                            )
                            .expected("`} ELSEVALUE` or `}`")
                            .found(quote_found(&else_val));
                        self.diags.push(d);
                    } else {
                        m.else_value = Some(else_val);
                    }
                }
                self.file.modes.push(m);
                return next;
            }
        }
        None
    }

    /// A header that never got its `{`.
    fn flush_pending(&mut self, idx: usize) {
        if let Some(p) = self.pending.take() {
            let (what, at) = match &p {
                Pending::Behavior(b, at) => (format!("`Behavior = {}`", b.kind), *at),
                Pending::Mode(m, at) => (format!("`set {} = {}`", m.var, m.value), *at),
            };
            let found = if idx < self.lines.len() {
                quote_found(&self.lines[idx].text)
            } else {
                "end of file".to_string()
            };
            let d = self
                .err(
                    DiagnosticKind::MissingOpenBrace,
                    at,
                    0,
                    format!("{what} is not followed by its block"),
                )
                .expected("`{` on the same or the next line")
                .found(found);
            self.diags.push(d);
        }
    }

    fn statement(&mut self, idx: usize, off: usize, body: &str) {
        if self.pending.is_some() {
            self.flush_pending(idx);
        }
        let first = body.split_whitespace().next().unwrap_or("");
        let is_header = header_kind(body);
        match (&mut self.state, is_header) {
            (State::Ignored(_), _) => {}
            (State::Behavior(..) | State::Mode(..), Some(_)) => {
                // A new header inside a block: the block was never closed.
                let (what, at) = match &self.state {
                    State::Behavior(b, at) => (format!("`Behavior = {}`", b.kind), *at),
                    State::Mode(m, at) => (format!("`set {} = {}`", m.var, m.value), *at),
                    _ => (String::new(), idx),
                };
                let l = self.lines[idx].line;
                let d = self
                    .err(
                        DiagnosticKind::UnterminatedBlock,
                        at,
                        0,
                        format!(
                            "block {what} is not closed before line {} of {}",
                            l.line, l.file.name
                        ),
                    )
                    .expected("`}`")
                    .found(quote_found(body));
                self.diags.push(d);
                match std::mem::replace(&mut self.state, State::Top) {
                    State::Behavior(b, _) => self.file.behaviors.push(b),
                    State::Mode(m, _) => self.file.modes.push(m),
                    _ => {}
                }
                self.top_statement(idx, off, body, first);
            }
            (State::Behavior(..), None) => self.behavior_param(idx, off, body),
            (State::Mode(..), None) => self.mode_condition(idx, off, body),
            (State::Top, _) => self.top_statement(idx, off, body, first),
        }
    }

    fn top_statement(&mut self, idx: usize, off: usize, body: &str, first: &str) {
        if first.eq_ignore_ascii_case("initialize") || first.eq_ignore_ascii_case("initialize_") {
            self.initialize(idx, off, body, first);
            return;
        }
        match header_kind(body) {
            Some(Header::Behavior) => {
                let (_, _, kind) = split_param(body).unwrap_or((0, "", ""));
                if kind.is_empty() {
                    let d = self
                        .err(
                            DiagnosticKind::UnexpectedLine,
                            idx,
                            off + body.len(),
                            "`Behavior =` without a type",
                        )
                        .expected("a behaviour type, e.g. `Behavior = BHV_Waypoint`")
                        .found("end of line");
                    self.diags.push(d);
                    return;
                }
                let spec = BehaviorSpec {
                    kind: kind.to_string(),
                    params: Vec::new(),
                    conditions: Vec::new(),
                    span: self.span(idx, off),
                };
                self.pending = Some(Pending::Behavior(spec, idx));
            }
            Some(Header::Mode) => {
                let rest = body[first.len()..].trim_start();
                let rest_off = off + (body.len() - rest.len());
                match split_param(rest) {
                    Some((_, var, value)) if !var.is_empty() && !value.is_empty() => {
                        let m = ModeBlock {
                            var: var.to_string(),
                            value: value.to_string(),
                            conditions: Vec::new(),
                            else_value: None,
                            span: self.span(idx, off),
                        };
                        self.pending = Some(Pending::Mode(m, idx));
                    }
                    _ => {
                        let d = self
                            .err(
                                DiagnosticKind::UnexpectedLine,
                                idx,
                                rest_off,
                                "malformed `set` line",
                            )
                            .expected("`set VAR = VALUE {`")
                            .found(quote_found(rest));
                        self.diags.push(d);
                    }
                }
            }
            None => {
                let d = self
                    .err(DiagnosticKind::UnexpectedLine, idx, off, "unexpected line at top level")
                    .expected("`initialize VAR = VALUE`, `set VAR = VALUE {`, `Behavior = TYPE` or a comment")
                    .found(quote_found(body));
                self.diags.push(d);
            }
        }
    }

    fn initialize(&mut self, idx: usize, off: usize, body: &str, first: &str) {
        let deferred = first.ends_with('_');
        let rest = &body[first.len()..];
        let mut start = off + first.len();
        for piece in split_commas(rest) {
            let p_off = start + (piece.len() - piece.trim_start().len());
            start += piece.len() + 1;
            match split_param(piece) {
                Some((_, var, value)) if !var.is_empty() => {
                    self.file.initializes.push(Initialize {
                        var: var.to_string(),
                        value: value.to_string(),
                        deferred,
                        span: self.span(idx, p_off),
                    });
                }
                Some(_) => {
                    let d = self
                        .err(
                            DiagnosticKind::EmptyKey,
                            idx,
                            p_off,
                            "`initialize` without a variable name",
                        )
                        .expected("`initialize VAR = VALUE`")
                        .found(quote_found(piece.trim()));
                    self.diags.push(d);
                }
                None => {
                    let d = self
                        .err(
                            DiagnosticKind::MissingEquals,
                            idx,
                            p_off,
                            "`initialize` without `=`",
                        )
                        .expected("`initialize VAR = VALUE`")
                        .found(quote_found(piece.trim()));
                    self.diags.push(d);
                }
            }
        }
    }

    fn behavior_param(&mut self, idx: usize, off: usize, body: &str) {
        let Some((k, key, value)) = split_param(body) else {
            let d = self
                .err(
                    DiagnosticKind::MissingEquals,
                    idx,
                    off,
                    "parameter line without `=`",
                )
                .expected("`param = value` or `}`")
                .found(quote_found(body));
            self.diags.push(d);
            return;
        };
        if key.is_empty() {
            let d = self
                .err(DiagnosticKind::EmptyKey, idx, off + k, "nothing before `=`")
                .expected("a parameter name before `=`")
                .found(quote_found(body));
            self.diags.push(d);
            return;
        }
        let value_off = off + body.find('=').map_or(0, |e| e + 1);
        let value_off = value_off
            + (body[value_off - off..].len() - body[value_off - off..].trim_start().len());
        let param = Param {
            key: key.to_string(),
            value: value.to_string(),
            span: self.span(idx, off + k),
        };
        let entry = if param_name(key) == "condition" {
            // Legacy `condition = VAR,value`: commas stand for `=` when no operator is given.
            let text = if value.contains(['=', '<', '>', '!']) {
                value.to_string()
            } else {
                value.replace(',', "=")
            };
            self.condition(idx, value_off, &text, false)
        } else {
            None
        };
        if let State::Behavior(b, _) = &mut self.state {
            b.params.push(param);
            if let Some(e) = entry {
                b.conditions.push(e);
            }
        }
    }

    fn mode_condition(&mut self, idx: usize, off: usize, body: &str) {
        if let Some(e) = self.condition(idx, off, body, true)
            && let State::Mode(m, _) = &mut self.state
        {
            m.conditions.push(e);
        }
    }

    fn condition(
        &mut self,
        idx: usize,
        off: usize,
        text: &str,
        in_mode: bool,
    ) -> Option<ConditionEntry> {
        match parse_condition(text) {
            Ok(c) => {
                if in_mode && c.uses_op(RelOp::FieldEq) {
                    let at = text.find("==").unwrap_or(0);
                    let d = self
                        .err(
                            DiagnosticKind::BadCondition,
                            idx,
                            off + at,
                            "`==` is not allowed in a `set` mode block",
                        )
                        .expected("`=` (exact match)")
                        .found("`==`");
                    self.diags.push(d);
                    return None;
                }
                Some(ConditionEntry {
                    text: text.to_string(),
                    condition: c,
                    span: self.span(idx, off),
                })
            }
            Err(e) => {
                let d = self
                    .err(
                        DiagnosticKind::BadCondition,
                        idx,
                        off + e.offset,
                        "malformed condition",
                    )
                    .expected(e.expected)
                    .found(e.found);
                self.diags.push(d);
                None
            }
        }
    }

    fn finish(&mut self) {
        let n = self.lines.len();
        self.flush_pending(n);
        match std::mem::replace(&mut self.state, State::Top) {
            State::Behavior(b, at) => {
                let d = self
                    .err(
                        DiagnosticKind::UnterminatedBlock,
                        at,
                        0,
                        format!("block `Behavior = {}` is never closed", b.kind),
                    )
                    .expected("`}` before the end of the file")
                    .found("end of file");
                self.diags.push(d);
                self.file.behaviors.push(b);
            }
            State::Mode(m, at) => {
                let d = self
                    .err(
                        DiagnosticKind::UnterminatedBlock,
                        at,
                        0,
                        format!("block `set {} = {}` is never closed", m.var, m.value),
                    )
                    .expected("`}` before the end of the file")
                    .found("end of file");
                self.diags.push(d);
                self.file.modes.push(m);
            }
            State::Ignored(_) | State::Top => {}
        }
    }
}

#[derive(Debug, Clone, Copy, PartialEq, Eq)]
enum Header {
    Behavior,
    Mode,
}

/// Whether a line starts a block: `Behavior = X` or `set VAR = VALUE`.
fn header_kind(body: &str) -> Option<Header> {
    let first = body.split_whitespace().next().unwrap_or("");
    if first.eq_ignore_ascii_case("set") && body.contains('=') {
        return Some(Header::Mode);
    }
    let key = body.split('=').next().unwrap_or("").trim();
    if body.contains('=') && key.eq_ignore_ascii_case("behavior") {
        return Some(Header::Behavior);
    }
    None
}

/// A lone else value after a mode block's `}`: one word, no `=` or braces, not a keyword.
fn is_else_token(t: &str) -> bool {
    !t.is_empty()
        && !t.contains(char::is_whitespace)
        && !t.contains(['=', '{', '}'])
        && !t.eq_ignore_ascii_case("set")
}

/// Splits on commas outside double quotes.
fn split_commas(s: &str) -> Vec<&str> {
    geometry::split_unquoted(s, ',')
}
