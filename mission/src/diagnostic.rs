//! Findings about mission files: errors and warnings that name the file, line and column, what
//! was found and what was expected, and can be rendered with the source line and a caret.

use std::fmt::{self, Write as _};

use crate::source::{SourceLine, Span};

/// How serious a finding is.
#[derive(Debug, Clone, Copy, PartialEq, Eq, PartialOrd, Ord, Hash)]
pub enum Severity {
    /// Worth telling the user; the mission still runs.
    Warning,
    /// The real programs would reject (or misread) the mission.
    Error,
}

impl fmt::Display for Severity {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(match self {
            Severity::Warning => "warning",
            Severity::Error => "error",
        })
    }
}

/// What kind of problem a [`Diagnostic`] reports (stable, for tests and tools).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum DiagnosticKind {
    /// A file could not be read.
    Unreadable,
    /// `#include` names a file found neither beside the including file nor on the include path.
    IncludeNotFound,
    /// `#include` would include a file that is already being included.
    IncludeCycle,
    /// `#else`, `#elseifdef` or `#endif` without an open `#ifdef`/`#ifndef`.
    DanglingDirective,
    /// An `#ifdef`/`#ifndef` still open at the end of the file.
    UnterminatedConditional,
    /// A directive without its required argument (`#define` alone, `#include` alone).
    MissingDirectiveArgument,
    /// A `$(NAME)` or `%(NAME)` left unexpanded.
    UndefinedMacro,
    /// An `#ifdef` mixing `||` and `&&` (nsplug evaluates it as false).
    MixedLogic,
    /// `#define` of a macro that already has a value.
    RedefinedMacro,
    /// A line that should be `key = value` has no `=`.
    MissingEquals,
    /// A `key = value` line with nothing before the `=`.
    EmptyKey,
    /// A block opened with `{` is not closed before the end of the file.
    UnterminatedBlock,
    /// A `}` with no open block.
    UnexpectedCloseBrace,
    /// A block header not followed by `{`.
    MissingOpenBrace,
    /// A line that fits no statement of the grammar.
    UnexpectedLine,
    /// A logic condition that does not parse.
    BadCondition,
    /// A behaviour type that coug does not know.
    UnknownBehavior,
    /// A parameter unknown to its behaviour type or to pHelmIvP.
    UnknownParameter,
    /// A condition or mode uses a variable that nothing initializes or posts.
    UnknownVariable,
    /// A condition tests a mode variable for a value that no `set` block gives.
    UnknownMode,
    /// A top-level setting (`ServerPort`, `LatOrigin`, ...) the apps cannot read; they keep
    /// their default.
    BadGlobal,
    /// A setting an app cannot use, does not support or ignores; the app goes on without it.
    AppSetting,
    /// An app runs without a `ProcessConfig` block of its MOOS name (every setting at its
    /// default).
    NoConfigBlock,
    /// An app of the ANTLER block that will not run (pLogger without a log target).
    AppNotRun,
}

/// One finding: severity, kind, where, what was found, what was expected.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Diagnostic {
    /// Error or warning.
    pub severity: Severity,
    /// What kind of problem.
    pub kind: DiagnosticKind,
    /// Where (file of the included text when the problem is inside an `#include`).
    pub span: Span,
    /// What is wrong, in words.
    pub message: String,
    /// What the parser found there, if it is one token or line.
    pub found: Option<String>,
    /// What would have been accepted there.
    pub expected: Option<String>,
    /// The text of the line the column refers to (for the caret rendering).
    pub source_line: Option<String>,
}

impl Diagnostic {
    /// An error.
    pub fn error(kind: DiagnosticKind, span: Span, message: impl Into<String>) -> Self {
        Diagnostic {
            severity: Severity::Error,
            kind,
            span,
            message: message.into(),
            found: None,
            expected: None,
            source_line: None,
        }
    }

    /// A warning about the line of `span`, shown as `file:line` (no column: the whole
    /// setting is meant), as the apps' configuration warnings are.
    pub fn line_warning(kind: DiagnosticKind, span: &Span, message: impl Into<String>) -> Self {
        Self::warning(kind, span.at_col(0), message)
    }

    /// A warning.
    pub fn warning(kind: DiagnosticKind, span: Span, message: impl Into<String>) -> Self {
        Diagnostic {
            severity: Severity::Warning,
            ..Self::error(kind, span, message)
        }
    }

    /// Sets what was found.
    pub fn found(mut self, found: impl Into<String>) -> Self {
        self.found = Some(found.into());
        self
    }

    /// Sets what was expected.
    pub fn expected(mut self, expected: impl Into<String>) -> Self {
        self.expected = Some(expected.into());
        self
    }

    /// Attaches the source line for the caret rendering.
    pub fn with_line(mut self, line: &SourceLine) -> Self {
        self.source_line = Some(line.text.clone());
        self
    }

    /// `file:line: message` without the severity (the text an app's config warning shows
    /// in its appcast).
    pub fn located(&self) -> String {
        format!("{}: {}", self.span, self.message)
    }

    /// Whether this is an error (not a warning).
    pub fn is_error(&self) -> bool {
        self.severity == Severity::Error
    }

    /// The full rendering: the one-line summary, the source line with a caret under the
    /// column, and the chain of `#include`s that led there.
    ///
    /// ```
    /// use mission::diagnostic::{Diagnostic, DiagnosticKind};
    /// use mission::source::Span;
    /// let mut d = Diagnostic::error(DiagnosticKind::MissingEquals, Span::new("a.moos", 3, 3), "bad line");
    /// d.source_line = Some("  oops".into());
    /// assert!(d.render().ends_with("\n  3 |   oops\n    |   ^"));
    /// ```
    pub fn render(&self) -> String {
        let mut out = self.to_string();
        if let Some(text) = &self.source_line {
            let shown = text.replace('\t', " ");
            let num = self.span.line.to_string();
            let pad = " ".repeat(num.len().max(3));
            let _ = write!(out, "\n{pad} |\n{num:>w$} | {shown}", w = pad.len());
            let col = usize::try_from(self.span.col.max(1) - 1).unwrap_or(0);
            let _ = write!(out, "\n{pad} | {}^", " ".repeat(col));
        }
        let mut from = self.span.file.included_from.clone();
        while let Some(site) = from {
            let _ = write!(out, "\n  = included from {site}");
            from = site.file.included_from.clone();
        }
        out
    }
}

impl fmt::Display for Diagnostic {
    /// `file:line:col: error: message (expected X, found Y)` on one line.
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "{}: {}: {}", self.span, self.severity, self.message)?;
        match (&self.expected, &self.found) {
            (Some(e), Some(fd)) => write!(f, ": expected {e}, found {fd}"),
            (Some(e), None) => write!(f, ": expected {e}"),
            (None, Some(fd)) => write!(f, ": found {fd}"),
            (None, None) => Ok(()),
        }
    }
}

impl std::error::Error for Diagnostic {}

/// Quotes a found token for a message: `` `tok` ``, or `end of line` when empty.
pub fn quote_found(tok: &str) -> String {
    if tok.is_empty() {
        "end of line".to_string()
    } else {
        let short: String = tok.chars().take(40).collect();
        if short.len() < tok.len() {
            format!("`{short}...`")
        } else {
            format!("`{short}`")
        }
    }
}
