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
//! As MOOS's own reader, lines it skips are read past: a line without `=` (free text, `#`
//! lines), one with nothing before `=` (`=====` banners), a `{` or `}` outside a block. They
//! are warnings outside blocks and in the blocks of the programs of
//! [`crate::catalog::MOOS_CONFIG_APPS`], and not reported in other programs' blocks, which may
//! hold their own syntax (Goby's protobuf text); braces nested in a block are balanced.
//!
//! Differences from MOOS's own reader, on purpose: [`MissionFile::global`] only looks at lines
//! outside `ProcessConfig` blocks (MOOS scans the whole file), values keep their inner spaces,
//! `ProcessConfig = NAME {` with the brace on the same line is accepted (MOOS wants the
//! `{` on the next line and would not find the block; coug warns), and a `}` nested in a block
//! closes its `{` (MOOS ends the block at the first `}`; coug warns when the program is one it
//! knows).

use std::fmt;

use crate::catalog;
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
    /// The MOOS name after `~`, if given (default: the program's base name); an
    /// `--alias=NAME` among the [`extra_args`](Self::extra_args) replaces it, as a MOOS app
    /// reads its command line.
    pub alias: Option<String>,
    /// pAntler's `ExtraProcessParams = NAME`: the ANTLER block's parameter `NAME`, split at
    /// commas, given to the program after its mission file and MOOS name (filled in by
    /// [`MissionFile::antler_runs`]; empty from [`AntlerRun::parse`] alone).
    pub extra_args: Vec<String>,
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
            extra_args: Vec::new(),
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

    /// The program that reads `block`: the base name of the program of the ANTLER `Run` line
    /// that gives it its MOOS name (`Run = uTimerScript @ NewConsole = false ~ uTS_2`), else
    /// the block's own name.
    ///
    /// ```
    /// use mission::source::SourceMap;
    /// let text = "ProcessConfig = ANTLER\n{\n  Run = /opt/uTimerScript @ X = 1 ~ uTS_2\n}\n\
    ///             ProcessConfig = uTS_2\n{\n}\nProcessConfig = pShare\n{\n}\n";
    /// let m = mission::moos::parse_moos(&SourceMap::from_text("a.moos", text)).value;
    /// assert_eq!(m.program_of(&m.processes[1]), "uTimerScript");
    /// assert_eq!(m.program_of(&m.processes[2]), "pShare");
    /// ```
    pub fn program_of(&self, block: &ProcessConfig) -> String {
        self.antler_runs()
            .into_iter()
            .find(|r| {
                r.alias
                    .as_deref()
                    .is_some_and(|a| a.eq_ignore_ascii_case(&block.name))
            })
            .map(|r| r.app.rsplit('/').next().unwrap_or(&r.app).to_string())
            .unwrap_or_else(|| block.name.clone())
    }

    /// The `Run` lines of the ANTLER block, in file order (empty without an ANTLER block),
    /// with their `ExtraProcessParams` resolved as pAntler does: the named parameter of the
    /// ANTLER block, split at commas, and an `--alias=NAME` among them naming the process.
    ///
    /// ```
    /// use mission::source::SourceMap;
    /// let text = "ProcessConfig = ANTLER\n{\n  Run = pHelmIvP @ NewConsole = true, \
    ///             ExtraProcessParams=HParams\n  HParams=--alias=pHelmIvP_Standby\n}\n";
    /// let m = mission::moos::parse_moos(&SourceMap::from_text("a.moos", text)).value;
    /// let runs = m.antler_runs();
    /// assert_eq!(runs[0].moos_name(), "pHelmIvP_Standby");
    /// assert_eq!(runs[0].extra_args, ["--alias=pHelmIvP_Standby"]);
    /// ```
    pub fn antler_runs(&self) -> Vec<AntlerRun> {
        let Some(antler) = self.process("ANTLER") else {
            return Vec::new();
        };
        antler
            .params("Run")
            .map(|r| {
                let mut run = AntlerRun::parse(&r.value, r.span.clone());
                let extra = run
                    .option("ExtraProcessParams")
                    .and_then(|name| antler.params(name).next())
                    .map(|p| p.value.clone());
                if let Some(extra) = extra {
                    run.extra_args = extra
                        .split(',')
                        .map(str::trim)
                        .filter(|a| !a.is_empty())
                        .map(String::from)
                        .collect();
                    if let Some(alias) = run
                        .extra_args
                        .iter()
                        .find_map(|a| a.strip_prefix("--alias="))
                        .filter(|a| !a.is_empty())
                    {
                        run.alias = Some(alias.to_string());
                    }
                }
                run
            })
            .collect()
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

/// The text of a mission with top-level settings replaced or added, as pAntler's
/// command-line overloads (`--ServerPort=N`) change what its apps read: every line the
/// parser reads as global `key` (case-insensitive) becomes `key = value`; a key the file
/// lacks is added at the top, in the order given. Every other line (comments, blocks,
/// free-format lines of third-party apps) is kept as written.
///
/// ```
/// let text = "ServerPort = 9000 // the DB\nProcessConfig = A\n{\n  ServerPort = 1\n}\n";
/// let out = mission::moos::override_globals(text, &[("serverport", "9011"), ("MOOSTimeWarp", "4")]);
/// assert_eq!(out, "MOOSTimeWarp = 4\nServerPort = 9011\nProcessConfig = A\n{\n  ServerPort = 1\n}\n");
/// ```
pub fn override_globals(text: &str, overrides: &[(&str, &str)]) -> String {
    // Parsed as one file, so each global's span line is its line in `text`.
    let parsed = parse_moos(&SourceMap::from_text("mission", text));
    let mut replace: Vec<Option<usize>> = Vec::new();
    let mut found = vec![false; overrides.len()];
    for g in &parsed.value.globals {
        let Some(i) = overrides.iter().position(|(k, _)| g.is(k)) else {
            continue;
        };
        let line = usize::try_from(g.span.line).unwrap_or(0).saturating_sub(1);
        if replace.len() <= line {
            replace.resize(line + 1, None);
        }
        replace[line] = Some(i);
        found[i] = true;
    }
    let mut out = String::with_capacity(text.len() + 64);
    for (i, (k, v)) in overrides.iter().enumerate() {
        if !found[i] {
            out.push_str(&format!("{k} = {v}\n"));
        }
    }
    for (n, line) in crate::source::split_lines(text).enumerate() {
        match replace.get(n).copied().flatten() {
            Some(i) => {
                let (k, v) = overrides[i];
                let key = line.split('=').next().map_or(k, str::trim);
                out.push_str(&format!("{key} = {v}\n"));
            }
            None => {
                out.push_str(line);
                out.push('\n');
            }
        }
    }
    out
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
    /// Depth of `{ ... }` nested inside the block (Goby's protobuf text: `common {`).
    depth: usize,
}

/// What MOOS's reader says about a line it skips, for a block's program or the global section.
const SKIPPED: &str = "MOOS ignores this line";

/// A finding and the index of its source line, to put findings back in file order.
type Found = (usize, Diagnostic);

/// `code` with the text between double quotes blanked out (braces and `=` in strings do not
/// count).
fn unquoted(code: &str) -> String {
    let mut quoted = false;
    code.chars()
        .map(|c| {
            if c == '"' {
                quoted = !quoted;
                c
            } else if quoted {
                ' '
            } else {
                c
            }
        })
        .collect()
}

/// `{` minus `}` outside double quotes.
fn brace_balance(code: &str) -> isize {
    let u = unquoted(code);
    let count = |ch| isize::try_from(u.matches(ch).count()).unwrap_or(isize::MAX);
    count('{') - count('}')
}

/// Whether the whole line is one macro reference such as `$(NODE_OFFSETS_LIST)` (left by
/// nsplug, which already reported it).
fn is_lone_macro(trimmed: &str) -> bool {
    (trimmed.starts_with("$(") || trimmed.starts_with("%("))
        && trimmed.ends_with(')')
        && trimmed[2..].find(')') == Some(trimmed.len() - 3)
}

/// Parses preprocessed `.moos` text. Never fails: what cannot be read is reported.
///
/// As MOOS's reader (`CMOOSFileReader`, `CProcessConfigReader`), a line without `=` or with
/// nothing before it is skipped: outside a block and in the block of a program of
/// [`catalog::MOOS_CONFIG_APPS`] it is a warning; in the block of another program it is not
/// reported, since such programs may read their block in their own syntax. Braces nested in a
/// block (`common {` ... `}`) are balanced and their lines are not entries. A `}` or `{` with
/// no block is a warning. A block MOOS cannot find (no `{` after `ProcessConfig`, never
/// closed) is an error: its program would run without its configuration.
pub fn parse_moos(src: &SourceMap) -> Parsed<MissionFile> {
    let mut file = MissionFile::default();
    let mut diags: Vec<Found> = Vec::new();
    // Findings about lines of a block, by block index: reported only for known programs.
    let mut block_notes: Vec<(usize, Found)> = Vec::new();
    let mut open: Option<Open> = None;
    // A `ProcessConfig = X` line waiting for its `{`.
    let mut pending: Option<(ProcessConfig, SourceLine)> = None;

    for (idx, line) in src.lines().iter().enumerate() {
        let raw = line.text.as_str();
        let code = strip_comment(raw);
        let trimmed = code.trim();
        // Empty lines, and `<tag><NAME>` section markers of nsplug plug files.
        if trimmed.is_empty() || trimmed.starts_with("<tag>") {
            continue;
        }
        let indent = code.len() - code.trim_start().len();
        let at = |byte: usize| line.span(column_of(raw, byte));
        // A skipped line: a note of the open block, else a finding of the global section.
        let skip = |open: &Option<Open>,
                    d: Diagnostic,
                    diags: &mut Vec<Found>,
                    notes: &mut Vec<(usize, Found)>| match open {
            Some(_) => notes.push((file.processes.len(), (idx, d))),
            None => diags.push((idx, d)),
        };

        if let Some((header, hline)) = pending.take() {
            if let Some(rest) = trimmed.strip_prefix('{') {
                open = Some(Open {
                    block: header,
                    line: hline,
                    depth: 0,
                });
                if rest.trim().is_empty() {
                    continue;
                }
                // Text after the `{` is read as the first line of the block.
                let off = code.find('{').map_or(indent, |p| p + 1);
                if let Some(o) = open.as_mut() {
                    match block_entry(&code[off..], off, line) {
                        Ok(p) => o.block.entries.push(p),
                        Err(d) => block_notes.push((file.processes.len(), (idx, d))),
                    }
                }
                continue;
            }
            diags.push((
                idx,
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
            ));
            // Recover as if the `{` had been there: the lines that follow are the block's.
            open = Some(Open {
                block: header,
                line: hline,
                depth: 0,
            });
        }

        let balance = brace_balance(code);
        let header =
            split_param(code).is_some_and(|(_, k, _)| k.eq_ignore_ascii_case("ProcessConfig"));

        // Inside braces nested in a block: only the braces count, until the block's own `}`.
        if let Some(o) = open.as_mut().filter(|o| o.depth > 0 && !header) {
            let depth = isize::try_from(o.depth).unwrap_or(isize::MAX) + balance;
            if depth >= 0 {
                o.depth = usize::try_from(depth).unwrap_or(0);
                continue;
            }
            // More `}` than the nesting: the last one closes the block.
            o.depth = 0;
            if let Some(o) = open.take() {
                file.processes.push(o.block);
            }
            continue;
        }

        if trimmed.starts_with('}') {
            match open.take() {
                Some(o) => file.processes.push(o.block),
                None => diags.push((
                    idx,
                    Diagnostic::warning(
                        DiagnosticKind::UnexpectedCloseBrace,
                        at(indent),
                        format!("`}}` without an open block: {SKIPPED}"),
                    )
                    .expected("a `ProcessConfig = NAME` line and `{` before it")
                    .found("`}`")
                    .with_line(line),
                )),
            }
            continue;
        }

        // A line that opens braces of its own in a block (`common {`, or `{` alone): nested.
        let has_eq = unquoted(code).contains('=');
        if let Some(o) = open.as_mut().filter(|_| balance > 0 && !has_eq) {
            o.depth = usize::try_from(balance).unwrap_or(0);
            block_notes.push((
                file.processes.len(),
                (
                    idx,
                    Diagnostic::warning(
                        DiagnosticKind::UnexpectedLine,
                        at(indent),
                        format!(
                            "`{{` nested in the block of {}: MOOS does not nest blocks, it \
                             ignores this line and ends the block at the next `}}` (coug \
                             skips to the matching `}}`)",
                            o.block.name
                        ),
                    )
                    .expected("`key = value`")
                    .found(quote_found(trimmed))
                    .with_line(line),
                ),
            ));
            continue;
        }

        if trimmed.starts_with('{') {
            diags.push((
                idx,
                Diagnostic::warning(
                    DiagnosticKind::UnexpectedLine,
                    at(indent),
                    format!("`{{` without a `ProcessConfig = NAME` line before it: {SKIPPED}"),
                )
                .expected("`ProcessConfig = NAME` on the line before")
                .found("`{`")
                .with_line(line),
            ));
            continue;
        }

        let Some((kstart, key, value)) = split_param(code) else {
            // A line that is only a macro nsplug left: nsplug reported it already.
            if !is_lone_macro(trimmed) {
                skip(
                    &open,
                    missing_equals(trimmed, at(indent), line),
                    &mut diags,
                    &mut block_notes,
                );
            }
            continue;
        };
        if key.is_empty() {
            skip(
                &open,
                Diagnostic::warning(
                    DiagnosticKind::EmptyKey,
                    at(kstart),
                    format!("nothing before `=`: {SKIPPED}"),
                )
                .expected("a parameter name before `=`")
                .found(quote_found(trimmed))
                .with_line(line),
                &mut diags,
                &mut block_notes,
            );
            continue;
        }

        if key.eq_ignore_ascii_case("ProcessConfig") {
            if let Some(o) = open.take() {
                diags.push((idx, unterminated(&o, line)));
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
                diags.push((
                    idx,
                    Diagnostic::error(
                        DiagnosticKind::UnexpectedLine,
                        at(code.find('=').map_or(kstart, |p| p + 1)),
                        "`ProcessConfig` without a process name",
                    )
                    .expected("a process name, e.g. `ProcessConfig = pHelmIvP`")
                    .found("end of line")
                    .with_line(line),
                ));
            }
            if brace {
                diags.push((
                    idx,
                    Diagnostic::warning(
                        DiagnosticKind::MissingOpenBrace,
                        at(code.rfind('{').unwrap_or(kstart)),
                        "MOOS only finds a block whose `{` is on the line after `ProcessConfig`",
                    )
                    .expected("`{` on its own line")
                    .with_line(line),
                ));
                open = Some(Open {
                    block,
                    line: line.clone(),
                    depth: 0,
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

    let end = src.lines().len();
    if let Some((header, hline)) = pending {
        diags.push((
            end,
            Diagnostic::error(
                DiagnosticKind::MissingOpenBrace,
                header.span.clone(),
                format!("`ProcessConfig = {}` has no block", header.name),
            )
            .expected("`{` on the next line")
            .found("end of file")
            .with_line(&hline),
        ));
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
        diags.push((end, d));
        file.processes.push(o.block);
    }

    // The skipped lines of a block count only for programs that read MOOS `key = value` lines.
    let known: Vec<bool> = file
        .processes
        .iter()
        .map(|p| catalog::reads_moos_config(&file.program_of(p)))
        .collect();
    diags.extend(
        block_notes
            .into_iter()
            .filter(|(b, _)| known.get(*b).copied().unwrap_or(false))
            .map(|(_, found)| found),
    );
    diags.sort_by_key(|(i, _)| *i);
    Parsed {
        value: file,
        diagnostics: diags.into_iter().map(|(_, d)| d).collect(),
    }
}

fn missing_equals(trimmed: &str, span: Span, line: &SourceLine) -> Diagnostic {
    Diagnostic::warning(
        DiagnosticKind::MissingEquals,
        span,
        format!("line without `=`: {SKIPPED}"),
    )
    .expected("`key = value`")
    .found(quote_found(trimmed))
    .with_line(line)
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
fn block_entry(text: &str, offset: usize, line: &SourceLine) -> Result<Param, Diagnostic> {
    let span = |k: usize| line.span(column_of(&line.text, offset + k));
    match split_param(text) {
        Some((k, key, value)) if !key.is_empty() => Ok(Param {
            key: key.to_string(),
            value: value.to_string(),
            span: span(k),
        }),
        _ => Err(missing_equals(text.trim(), span(0), line)),
    }
}
