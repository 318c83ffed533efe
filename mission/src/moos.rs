//! `.moos` files: global parameters, `ProcessConfig = NAME { ... }` blocks and the ANTLER
//! block's `Run =` lines.
//!
//! ```
//! use mission::source::SourceMap;
//! let text = "ServerPort = 9000\nProcessConfig = ANTLER\n{\n  Run = pHelmIvP @ NewConsole = false ~ helm2\n}\n";
//! let m = mission::moos::parse_moos(&SourceMap::from_text("a.moos", text)).value;
//! let runs = m.antler_runs();
//! assert_eq!(runs[0].app, "pHelmIvP");
//! assert_eq!(runs[0].alias.as_deref(), Some("helm2"));
//! assert_eq!(runs[0].option("newconsole"), Some("false"));
//! ```
//!
//! Lines starting with `<tag>` (section markers of nsplug plug files, see
//! [`crate::nsplug`]) are skipped.
//!
//! Differences from MOOS's own reader, on purpose: [`MissionFile::global`] only looks at lines
//! outside `ProcessConfig` blocks (MOOS scans the whole file), values keep their inner spaces,
//! and `ProcessConfig = NAME {` with the brace on the same line is accepted (MOOS wants the
//! `{` on the next line and would not find the block; coug warns).

use std::fmt;

use crate::diagnostic::{Diagnostic, DiagnosticKind, quote_found};
use crate::source::{SourceLine, SourceMap, Span, column_of};
use crate::{Param, Parsed, strip_comment};

/// A parsed `.moos` file.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct MissionFile {
    /// Top-level `key = value` lines (outside any block), in file order.
    pub globals: Vec<Param>,
    /// The `ProcessConfig` blocks, in file order.
    pub processes: Vec<ProcessConfig>,
    /// `define: NAME = value` lines (MOOS's file-local `${NAME}` variables).
    pub defines: Vec<Param>,
}

/// One `ProcessConfig = NAME { ... }` block.
#[derive(Debug, Clone, PartialEq)]
pub struct ProcessConfig {
    /// The process name as written (`pHelmIvP`, `ANTLER`, ...).
    pub name: String,
    /// Where the `ProcessConfig` line is.
    pub span: Span,
    /// The `key = value` lines in file order (repeated keys kept).
    pub entries: Vec<Param>,
}

impl ProcessConfig {
    /// The first value of `key` (case-insensitive), as MOOS's `GetConfigurationParam`
    /// (which also skips empty values).
    pub fn get(&self, key: &str) -> Option<&str> {
        self.get_all(key).find(|v| !v.is_empty())
    }

    /// Every value of `key` (case-insensitive), in file order.
    pub fn get_all<'a>(&'a self, key: &str) -> impl Iterator<Item = &'a str> + use<'a> {
        let key = key.to_string();
        self.entries
            .iter()
            .filter(move |p| p.is(&key))
            .map(|p| p.value.as_str())
    }

    /// The entries of `key` with their lines, in file order.
    pub fn params<'a>(&'a self, key: &str) -> impl Iterator<Item = &'a Param> + use<'a> {
        let key = key.to_string();
        self.entries.iter().filter(move |p| p.is(&key))
    }
}

/// One ANTLER `Run = APP @ OPTIONS ~ ALIAS` line.
#[derive(Debug, Clone, PartialEq)]
pub struct AntlerRun {
    /// The program to launch (text before `@`).
    pub app: String,
    /// `key = value` options between `@` and `~` (e.g. `NewConsole = false`), in order.
    pub options: Vec<(String, String)>,
    /// The MOOS name after `~`, if given (default: the program's base name).
    pub alias: Option<String>,
    /// Where the `Run` line is.
    pub span: Span,
}

impl AntlerRun {
    /// An option's value, by case-insensitive name.
    pub fn option(&self, name: &str) -> Option<&str> {
        self.options
            .iter()
            .find(|(k, _)| k.eq_ignore_ascii_case(name))
            .map(|(_, v)| v.as_str())
    }

    /// The MOOS name the process runs under: the alias, else the base name of the program.
    pub fn moos_name(&self) -> &str {
        match &self.alias {
            Some(a) => a,
            None => self.app.rsplit('/').next().unwrap_or(&self.app),
        }
    }

    /// Parses the value of a `Run` line (`MOOSDB @ NewConsole = false ~ DB`).
    pub fn parse(value: &str, span: Span) -> AntlerRun {
        let (head, alias) = match value.split_once('~') {
            Some((h, a)) => (h, Some(a.trim().to_string()).filter(|a| !a.is_empty())),
            None => (value, None),
        };
        let (app, opts) = head.split_once('@').unwrap_or((head, ""));
        let options = opts
            .split(',')
            .filter(|o| !o.trim().is_empty())
            .map(|o| match o.split_once('=') {
                Some((k, v)) => (k.trim().to_string(), v.trim().to_string()),
                None => (o.trim().to_string(), String::new()),
            })
            .collect();
        AntlerRun {
            app: app.trim().to_string(),
            options,
            alias,
            span,
        }
    }
}

impl MissionFile {
    /// The value of the first top-level parameter `name` (case-insensitive), e.g. `LatOrigin`.
    pub fn global(&self, name: &str) -> Option<&str> {
        self.globals
            .iter()
            .find(|p| p.is(name))
            .map(|p| p.value.as_str())
    }

    /// The first `ProcessConfig` block for `name` (case-insensitive).
    pub fn process(&self, name: &str) -> Option<&ProcessConfig> {
        self.processes
            .iter()
            .find(|p| p.name.eq_ignore_ascii_case(name))
    }

    /// The `Run` lines of the ANTLER block, in file order (empty without an ANTLER block).
    pub fn antler_runs(&self) -> Vec<AntlerRun> {
        self.process("ANTLER")
            .map(|p| {
                p.params("Run")
                    .map(|r| AntlerRun::parse(&r.value, r.span.clone()))
                    .collect()
            })
            .unwrap_or_default()
    }

    /// Same content as `other`, ignoring source locations (for round-trip checks).
    pub fn same_content(&self, other: &MissionFile) -> bool {
        let kv = |v: &[Param]| -> Vec<(String, String)> {
            v.iter().map(|p| (p.key.clone(), p.value.clone())).collect()
        };
        kv(&self.globals) == kv(&other.globals)
            && kv(&self.defines) == kv(&other.defines)
            && self.processes.len() == other.processes.len()
            && self
                .processes
                .iter()
                .zip(&other.processes)
                .all(|(a, b)| a.name == b.name && kv(&a.entries) == kv(&b.entries))
    }
}

impl fmt::Display for MissionFile {
    /// Canonical form: defines, globals, then each block with the brace on its own line.
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        for d in &self.defines {
            writeln!(f, "{} = {}", d.key, d.value)?;
        }
        for g in &self.globals {
            writeln!(f, "{} = {}", g.key, g.value)?;
        }
        for p in &self.processes {
            writeln!(f, "\nProcessConfig = {}\n{{", p.name)?;
            for e in &p.entries {
                writeln!(f, "  {} = {}", e.key, e.value)?;
            }
            writeln!(f, "}}")?;
        }
        Ok(())
    }
}

/// Splits `key = value` at the first `=`: byte offset of the key start, key, value (trimmed).
pub(crate) fn split_param(text: &str) -> Option<(usize, &str, &str)> {
    let eq = text.find('=')?;
    let key_start = text.len() - text.trim_start().len();
    Some((key_start, text[..eq].trim(), text[eq + 1..].trim()))
}

/// The block being read.
struct Open {
    block: ProcessConfig,
    line: SourceLine,
}

/// Parses preprocessed `.moos` text. Never fails: what cannot be read is reported.
pub fn parse_moos(src: &SourceMap) -> Parsed<MissionFile> {
    let mut file = MissionFile::default();
    let mut diags = Vec::new();
    let mut open: Option<Open> = None;
    // A `ProcessConfig = X` line waiting for its `{`.
    let mut pending: Option<(ProcessConfig, SourceLine)> = None;

    for line in src.lines() {
        let raw = line.text.as_str();
        let code = strip_comment(raw);
        let trimmed = code.trim();
        // Empty lines, and `<tag><NAME>` section markers of nsplug plug files.
        if trimmed.is_empty() || trimmed.starts_with("<tag>") {
            continue;
        }
        let indent = code.len() - code.trim_start().len();
        let at = |byte: usize| line.span(column_of(raw, byte));

        if let Some((header, hline)) = pending.take() {
            if let Some(rest) = trimmed.strip_prefix('{') {
                open = Some(Open {
                    block: header,
                    line: hline,
                });
                if rest.trim().is_empty() {
                    continue;
                }
                // Text after the `{` is read as the first line of the block.
                let off = code.find('{').map_or(indent, |p| p + 1);
                read_block_line(
                    &code[off..],
                    off,
                    line,
                    open.as_mut().map(|o| &mut o.block),
                    &mut diags,
                );
                continue;
            }
            diags.push(
                Diagnostic::error(
                    DiagnosticKind::MissingOpenBrace,
                    at(indent),
                    format!(
                        "`ProcessConfig = {}` (line {}) is not followed by its block",
                        header.name, hline.line
                    ),
                )
                .expected("`{` on the next line")
                .found(quote_found(trimmed))
                .with_line(line),
            );
            // Recover as if the `{` had been there: the lines that follow are the block's.
            open = Some(Open {
                block: header,
                line: hline,
            });
        }

        if trimmed.starts_with('}') {
            match open.take() {
                Some(o) => file.processes.push(o.block),
                None => diags.push(
                    Diagnostic::error(
                        DiagnosticKind::UnexpectedCloseBrace,
                        at(indent),
                        "`}` without an open block",
                    )
                    .expected("a `ProcessConfig = NAME` line and `{` before it")
                    .found("`}`")
                    .with_line(line),
                ),
            }
            continue;
        }

        if trimmed.starts_with('{') {
            diags.push(
                Diagnostic::error(
                    DiagnosticKind::UnexpectedLine,
                    at(indent),
                    "`{` without a `ProcessConfig = NAME` line before it",
                )
                .expected("`ProcessConfig = NAME` on the line before")
                .found("`{`")
                .with_line(line),
            );
            continue;
        }

        let Some((kstart, key, value)) = split_param(code) else {
            diags.push(
                Diagnostic::error(
                    DiagnosticKind::MissingEquals,
                    at(indent),
                    "parameter line without `=`",
                )
                .expected("`key = value`")
                .found(quote_found(trimmed))
                .with_line(line),
            );
            continue;
        };
        if key.is_empty() {
            diags.push(
                Diagnostic::error(DiagnosticKind::EmptyKey, at(kstart), "nothing before `=`")
                    .expected("a parameter name before `=`")
                    .found(quote_found(trimmed))
                    .with_line(line),
            );
            continue;
        }

        if key.eq_ignore_ascii_case("ProcessConfig") {
            if let Some(o) = open.take() {
                diags.push(unterminated(&o, line));
                file.processes.push(o.block);
            }
            let (name, brace) = match value.strip_suffix('{') {
                Some(n) => (n.trim(), true),
                None => (value, false),
            };
            let block = ProcessConfig {
                name: name.to_string(),
                span: at(kstart),
                entries: Vec::new(),
            };
            if name.is_empty() {
                diags.push(
                    Diagnostic::error(
                        DiagnosticKind::UnexpectedLine,
                        at(code.find('=').map_or(kstart, |p| p + 1)),
                        "`ProcessConfig` without a process name",
                    )
                    .expected("a process name, e.g. `ProcessConfig = pHelmIvP`")
                    .found("end of line")
                    .with_line(line),
                );
            }
            if brace {
                diags.push(
                    Diagnostic::warning(
                        DiagnosticKind::MissingOpenBrace,
                        at(code.rfind('{').unwrap_or(kstart)),
                        "MOOS only finds a block whose `{` is on the line after `ProcessConfig`",
                    )
                    .expected("`{` on its own line")
                    .with_line(line),
                );
                open = Some(Open {
                    block,
                    line: line.clone(),
                });
            } else {
                pending = Some((block, line.clone()));
            }
            continue;
        }

        let param = Param {
            key: key.to_string(),
            value: value.to_string(),
            span: at(kstart),
        };
        match open.as_mut() {
            Some(o) => o.block.entries.push(param),
            None if key
                .get(..7)
                .is_some_and(|k| k.eq_ignore_ascii_case("define:")) =>
            {
                file.defines.push(Param {
                    key: format!("define: {}", key.get(7..).unwrap_or("").trim()),
                    ..param
                })
            }
            None => file.globals.push(param),
        }
    }

    if let Some((header, hline)) = pending {
        diags.push(
            Diagnostic::error(
                DiagnosticKind::MissingOpenBrace,
                header.span.clone(),
                format!("`ProcessConfig = {}` has no block", header.name),
            )
            .expected("`{` on the next line")
            .found("end of file")
            .with_line(&hline),
        );
    }
    if let Some(o) = open {
        let d = Diagnostic::error(
            DiagnosticKind::UnterminatedBlock,
            o.block.span.clone(),
            format!("block `ProcessConfig = {}` is never closed", o.block.name),
        )
        .expected("`}` before the end of the file")
        .found("end of file")
        .with_line(&o.line);
        diags.push(d);
        file.processes.push(o.block);
    }
    Parsed {
        value: file,
        diagnostics: diags,
    }
}

fn unterminated(o: &Open, next: &SourceLine) -> Diagnostic {
    Diagnostic::error(
        DiagnosticKind::UnterminatedBlock,
        o.block.span.clone(),
        format!(
            "block `ProcessConfig = {}` is not closed before the next `ProcessConfig` ({}:{})",
            o.block.name, next.file.name, next.line
        ),
    )
    .expected("`}`")
    .found("`ProcessConfig`")
    .with_line(&o.line)
}

/// Reads text that follows a `{` on the same line as a block entry.
fn read_block_line(
    text: &str,
    offset: usize,
    line: &SourceLine,
    block: Option<&mut ProcessConfig>,
    diags: &mut Vec<Diagnostic>,
) {
    let Some(block) = block else { return };
    match split_param(text) {
        Some((k, key, value)) if !key.is_empty() => block.entries.push(Param {
            key: key.to_string(),
            value: value.to_string(),
            span: line.span(column_of(&line.text, offset + k)),
        }),
        _ => diags.push(
            Diagnostic::error(
                DiagnosticKind::MissingEquals,
                line.span(column_of(&line.text, offset)),
                "parameter line without `=`",
            )
            .expected("`key = value`")
            .found(quote_found(text.trim()))
            .with_line(line),
        ),
    }
}
