//! The nsplug preprocessor, compatible with MOOS-IvP's `nsplug`: `#include` (with include
//! path and `<tag>` sections), `#define`, `$(NAME)` / `%(NAME)` expansion (with `$(NAME=default)`),
//! `#ifdef` / `#ifndef` / `#elseifdef` / `#else` / `#endif`, and a strict mode.
//!
//! ```
//! use mission::nsplug::{preprocess, Options};
//! use mission::source::MemorySource;
//! let fs = MemorySource::new()
//!     .with("m.moos", "#include plug.moos\nCommunity = %(VNAME)\n")
//!     .with("plug.moos", "ServerPort = $(PORT)\n");
//! let opts = Options::new().define("VNAME", "henry").define("PORT", "9001");
//! let out = preprocess(&fs, "m.moos".as_ref(), &opts).unwrap();
//! assert_eq!(out.source.text(), "ServerPort = 9001\nCommunity = HENRY\n");
//! assert_eq!(out.source.lines()[0].file.name, "plug.moos");
//! ```

use std::collections::HashMap;
use std::path::{Path, PathBuf};
use std::sync::Arc;

use crate::diagnostic::{Diagnostic, DiagnosticKind, quote_found};
use crate::source::{
    FileSource, SourceError, SourceFile, SourceLine, SourceMap, Span, column_of, line_number,
    normalize, split_lines,
};

/// The value nsplug gives a macro defined without a value (`nsplug in out NAME`, `#define NAME`).
/// It makes `#ifdef NAME` true and substitutes as the empty string.
pub const DEFINED: &str = "<defined>";

/// Most substitutions made in one line (nsplug's limit; stops `#define A $(A)` loops).
const MAX_SUBS_PER_LINE: usize = 100;

/// How to preprocess.
#[derive(Debug, Clone, Default)]
pub struct Options {
    /// Macros defined before the first line (the `NAME=VALUE` command-line arguments).
    pub defines: HashMap<String, String>,
    /// Extra directories searched for `#include` files after the including file's directory
    /// (`-p DIR`, `--path=DIR:DIR`).
    pub include_paths: Vec<PathBuf>,
    /// An unexpanded macro, or an `#ifdef` mixing `||` and `&&`, is an error (`--strict`).
    pub strict: bool,
    /// Keep partially expanded lines (`--lenient`). By default, as in nsplug, a line in which a
    /// macro is left undefined is emitted exactly as written.
    pub lenient: bool,
}

impl Options {
    /// No macros, no include path, not strict.
    pub fn new() -> Self {
        Self::default()
    }

    /// Defines a macro (builder form).
    pub fn define(mut self, name: &str, value: &str) -> Self {
        self.defines.insert(name.to_string(), value.to_string());
        self
    }

    /// Adds one command-line argument: `NAME=VALUE` defines NAME, a bare `NAME` defines it as
    /// [`DEFINED`].
    pub fn define_arg(&mut self, arg: &str) {
        match arg.split_once('=') {
            Some((k, v)) => self.defines.insert(k.to_string(), v.to_string()),
            None => self.defines.insert(arg.to_string(), DEFINED.to_string()),
        };
    }
}

/// The result of preprocessing: the text with its source map, and the warnings.
#[derive(Debug, Clone)]
pub struct Preprocessed {
    /// The output lines, each mapped to its file and line.
    pub source: SourceMap,
    /// Warnings (undefined macros, redefinitions, mixed logic). Errors abort instead.
    pub diagnostics: Vec<Diagnostic>,
    /// The macros defined at the end (command line plus `#define`s).
    pub macros: HashMap<String, String>,
}

/// Preprocesses `path` read through `fs`. Fatal problems (missing include, include cycle,
/// dangling `#endif`, undefined macro in strict mode...) return the error; everything else is
/// collected in [`Preprocessed::diagnostics`].
pub fn preprocess(
    fs: &dyn FileSource,
    path: &Path,
    opts: &Options,
) -> Result<Preprocessed, Diagnostic> {
    let mut ex = Expander {
        fs,
        opts,
        macros: opts.defines.clone(),
        out: SourceMap::default(),
        diagnostics: Vec::new(),
        stack: Vec::new(),
    };
    let text = fs.read(path).map_err(|e| unreadable(path, None, &e))?;
    let file = Arc::new(SourceFile {
        name: path.display().to_string(),
        included_from: None,
    });
    ex.expand_file(path, file, &text, None)?;
    Ok(Preprocessed {
        source: ex.out,
        diagnostics: ex.diagnostics,
        macros: ex.macros,
    })
}

/// Where an `#ifdef` chain stands (one entry per open conditional).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
enum Mode {
    /// In an `#ifdef`/`#elseifdef` branch that holds.
    IfdefYes,
    /// In an `#ifdef`/`#elseifdef` branch that does not hold (a later branch may).
    IfdefNo,
    /// An earlier branch held: skip the rest of the chain.
    IfdefNoMore,
    /// In an `#ifndef` that holds.
    IfndefYes,
    /// In an `#ifndef` that does not hold.
    IfndefNo,
    /// In an `#else` that is taken.
    ElseYes,
    /// In an `#else` that is skipped.
    ElseNo,
}

impl Mode {
    fn skips(self) -> bool {
        matches!(
            self,
            Mode::IfdefNo | Mode::IfdefNoMore | Mode::IfndefNo | Mode::ElseNo
        )
    }
}

struct Expander<'a> {
    fs: &'a dyn FileSource,
    opts: &'a Options,
    macros: HashMap<String, String>,
    out: SourceMap,
    diagnostics: Vec<Diagnostic>,
    /// Normalized paths of the files being expanded (include-cycle detection).
    stack: Vec<PathBuf>,
}

fn unreadable(path: &Path, at: Option<Span>, e: &SourceError) -> Diagnostic {
    let span = at.unwrap_or_else(|| Span::new(&path.display().to_string(), 1, 1));
    Diagnostic::error(DiagnosticKind::Unreadable, span, e.to_string())
}

/// The first whitespace-separated token of a trimmed line and the (trimmed) rest.
fn split_directive(line: &str) -> (&str, &str) {
    let t = line.trim();
    match t.find([' ', '\t']) {
        Some(i) => (&t[..i], t[i..].trim()),
        None => (t, ""),
    }
}

impl Expander<'_> {
    fn expand_file(
        &mut self,
        path: &Path,
        file: Arc<SourceFile>,
        text: &str,
        tag: Option<&str>,
    ) -> Result<(), Diagnostic> {
        self.stack.push(normalize(path));
        let mut modes: Vec<(Mode, usize)> = Vec::new();
        // With a tag, only the lines of the matching `<tag><NAME>` section are taken.
        let mut in_section = tag.is_none();
        let mut tag_seen = false;
        let lines: Vec<&str> = split_lines(text).collect();
        for (i, raw) in lines.iter().enumerate() {
            let here = SourceLine {
                text: (*raw).to_string(),
                file: file.clone(),
                line: line_number(i),
            };
            let indent = raw.len() - raw.trim_start().len();
            if let Some(t) = tag {
                if let Some(rest) = raw.trim_start().strip_prefix("<tag>") {
                    in_section = rest.trim() == t;
                    tag_seen |= in_section;
                    continue;
                }
                if !in_section || raw.trim_start().starts_with('#') {
                    continue;
                }
            }
            let (left, rest) = split_directive(raw);
            let skipping = modes.iter().any(|(m, _)| m.skips());
            match left {
                "#ifdef" => {
                    let yes = self.check_ifdef(rest, &here, indent)?;
                    modes.push((if yes { Mode::IfdefYes } else { Mode::IfdefNo }, i));
                }
                "#ifndef" => {
                    let yes = self.check_ifndef(rest);
                    modes.push((if yes { Mode::IfndefYes } else { Mode::IfndefNo }, i));
                }
                "#elseifdef" => {
                    let Some(top) = modes.last_mut() else {
                        return Err(dangling(&here, indent, "#elseifdef"));
                    };
                    match top.0 {
                        Mode::IfdefYes => top.0 = Mode::IfdefNoMore,
                        Mode::IfdefNo => {
                            let yes = self.check_ifdef(rest, &here, indent)?;
                            if let Some(top) = modes.last_mut()
                                && yes
                            {
                                top.0 = Mode::IfdefYes;
                            }
                        }
                        Mode::IfdefNoMore => {}
                        _ => {
                            return Err(dangling(&here, indent, "#elseifdef")
                                .expected("`#elseifdef` only inside an `#ifdef` chain"));
                        }
                    }
                }
                "#else" => {
                    let Some(top) = modes.last_mut() else {
                        return Err(dangling(&here, indent, "#else"));
                    };
                    match top.0 {
                        Mode::IfdefYes | Mode::IfndefYes => top.0 = Mode::ElseNo,
                        Mode::IfdefNo | Mode::IfndefNo => top.0 = Mode::ElseYes,
                        _ => {}
                    }
                }
                "#endif" => {
                    if modes.pop().is_none() {
                        return Err(dangling(&here, indent, "#endif"));
                    }
                }
                _ if skipping => {}
                "#include" => self.include(rest, &here, indent, path, &file)?,
                "#define" => self.define(rest, &here, indent)?,
                _ => {
                    let text = self.substitute(raw, &here)?;
                    self.out.push(SourceLine { text, ..here });
                }
            }
        }
        if let Some(&(_, open)) = modes.last() {
            let raw = lines.get(open).copied().unwrap_or("");
            let line = SourceLine {
                text: raw.to_string(),
                file: file.clone(),
                line: line_number(open),
            };
            let indent = raw.len() - raw.trim_start().len();
            return Err(Diagnostic::error(
                DiagnosticKind::UnterminatedConditional,
                line.span(column_of(raw, indent)),
                "conditional block is never closed",
            )
            .expected("`#endif` before the end of the file")
            .found("end of file")
            .with_line(&line));
        }
        if let (Some(t), false) = (tag, tag_seen) {
            let span = file
                .included_from
                .clone()
                .unwrap_or_else(|| Span::new(&file.name, 1, 1));
            self.diagnostics.push(
                Diagnostic::warning(
                    DiagnosticKind::IncludeNotFound,
                    span,
                    format!("no `<tag>{t}` section in {}", file.name),
                )
                .expected(format!("a line `<tag>{t}` in the included file")),
            );
        }
        self.stack.pop();
        Ok(())
    }

    fn include(
        &mut self,
        rest: &str,
        here: &SourceLine,
        indent: usize,
        path: &Path,
        file: &Arc<SourceFile>,
    ) -> Result<(), Diagnostic> {
        let arg_col = here.text.find("#include").map_or(indent, |p| p + 8);
        let arg_col =
            arg_col + (here.text.len() - arg_col - here.text[arg_col..].trim_start().len());
        let span = here.span(column_of(&here.text, arg_col));
        let expanded = self.substitute(rest, here)?;
        let arg = expanded.trim();
        let (name, tag) = parse_include_arg(arg);
        if name.is_empty() {
            return Err(Diagnostic::error(
                DiagnosticKind::MissingDirectiveArgument,
                span,
                "`#include` without a file name",
            )
            .expected("a file name, e.g. `#include plug_pHelmIvP.moos`")
            .found("end of line")
            .with_line(here));
        }
        let dir = path.parent().unwrap_or(Path::new(""));
        let mut candidates = vec![dir.join(name)];
        candidates.extend(self.opts.include_paths.iter().map(|p| p.join(name)));
        let Some(found) = candidates.into_iter().find(|c| self.fs.exists(c)) else {
            return Err(Diagnostic::error(
                DiagnosticKind::IncludeNotFound,
                span,
                format!("cannot find include file `{name}`"),
            )
            .expected(format!(
                "a file `{name}` beside {} or on the include path (-p)",
                file.name
            ))
            .found("no such file")
            .with_line(here));
        };
        let norm = normalize(&found);
        if self.stack.contains(&norm) {
            let chain: Vec<String> = self
                .stack
                .iter()
                .chain(std::iter::once(&norm))
                .map(|p| p.display().to_string())
                .collect();
            return Err(Diagnostic::error(
                DiagnosticKind::IncludeCycle,
                span,
                format!("#include cycle: {}", chain.join(" -> ")),
            )
            .expected("a file that is not already being included")
            .found(quote_found(name))
            .with_line(here));
        }
        let text = self
            .fs
            .read(&found)
            .map_err(|e| unreadable(&found, Some(span.clone()), &e).with_line(here))?;
        let child = Arc::new(SourceFile {
            name: found.display().to_string(),
            included_from: Some(span),
        });
        self.expand_file(&found, child, &text, tag)
    }

    fn define(&mut self, rest: &str, here: &SourceLine, indent: usize) -> Result<(), Diagnostic> {
        let mut parts = rest.split_whitespace();
        let mut name = parts.next().unwrap_or("");
        let value: Vec<&str> = parts.collect();
        let value = value.join(" ");
        if let Some(inner) = name.strip_prefix("$(").and_then(|n| n.strip_suffix(')'))
            && !inner.is_empty()
        {
            name = inner;
        }
        if name.is_empty() {
            return Err(Diagnostic::error(
                DiagnosticKind::MissingDirectiveArgument,
                here.span(column_of(&here.text, indent)),
                "`#define` without a macro name",
            )
            .expected("`#define NAME VALUE`")
            .found("end of line")
            .with_line(here));
        }
        let value = if value.is_empty() {
            DEFINED.to_string()
        } else {
            value
        };
        if let Some(old) = self.macros.get(name)
            && *old != value
        {
            self.diagnostics.push(
                Diagnostic::warning(
                    DiagnosticKind::RedefinedMacro,
                    here.span(column_of(&here.text, indent)),
                    format!("macro `{name}` redefined from `{old}` to `{value}`"),
                )
                .with_line(here),
            );
        }
        self.macros.insert(name.to_string(), value);
        Ok(())
    }

    /// Expands the macros of `line`; warns (or, strict, fails) on what stays unexpanded.
    fn substitute(&mut self, line: &str, here: &SourceLine) -> Result<String, Diagnostic> {
        let (expanded, undefined) = expand_macros(line, &self.macros);
        let Some((at, name)) = undefined else {
            return Ok(expanded);
        };
        if line.trim_start().starts_with("//") {
            return Ok(if self.opts.lenient {
                expanded
            } else {
                line.to_string()
            });
        }
        let col = here.text.find(&name).unwrap_or(at);
        let d = Diagnostic::warning(
            DiagnosticKind::UndefinedMacro,
            here.span(column_of(&here.text, col)),
            "undefined macro",
        )
        .expected("a macro defined by `#define` or on the command line (NAME=VALUE)")
        .found(quote_found(&name))
        .with_line(here);
        if self.opts.strict {
            return Err(Diagnostic {
                severity: crate::diagnostic::Severity::Error,
                ..d
            });
        }
        self.diagnostics.push(d);
        Ok(if self.opts.lenient {
            expanded
        } else {
            line.to_string()
        })
    }

    fn check_ifdef(
        &mut self,
        entry: &str,
        here: &SourceLine,
        indent: usize,
    ) -> Result<bool, Diagnostic> {
        let disj = entry.contains("||");
        let conj = entry.contains("&&");
        if disj && conj {
            let d = Diagnostic::warning(
                DiagnosticKind::MixedLogic,
                here.span(column_of(&here.text, indent)),
                "`#ifdef` mixes `||` and `&&`; nsplug evaluates it as false",
            )
            .expected("only `||` or only `&&`")
            .with_line(here);
            if self.opts.strict {
                return Err(Diagnostic {
                    severity: crate::diagnostic::Severity::Error,
                    ..d
                });
            }
            self.diagnostics.push(d);
            return Ok(false);
        }
        let value = |name: &str| self.macros.get(name).map(String::as_str);
        let holds = |part: &str, bare_needs_value: bool| {
            let (name, want) = split_directive(part);
            if want.is_empty() {
                match value(name) {
                    Some(v) => !bare_needs_value || !v.is_empty(),
                    None => false,
                }
            } else {
                let have = value(name);
                have == Some(want) || (have.is_some() && have == value(want))
            }
        };
        Ok(if conj {
            entry.split("&&").all(|p| holds(p, false))
        } else {
            entry.split("||").any(|p| holds(p, true))
        })
    }

    fn check_ifndef(&self, entry: &str) -> bool {
        entry
            .split_whitespace()
            .all(|n| self.macros.get(n).is_none_or(|v| v.is_empty()))
    }
}

fn dangling(here: &SourceLine, indent: usize, what: &str) -> Diagnostic {
    Diagnostic::error(
        DiagnosticKind::DanglingDirective,
        here.span(column_of(&here.text, indent)),
        format!("dangling `{what}`"),
    )
    .expected("an open `#ifdef` or `#ifndef` before it")
    .found(format!("`{what}`"))
    .with_line(here)
}

/// Splits an `#include` argument into the file name and the optional `<tag>`:
/// `plugs.moos <origin_warp>`, `"plug a.moos"`, `<plug.moos>`.
fn parse_include_arg(arg: &str) -> (&str, Option<&str>) {
    if let Some(q) = arg.strip_prefix('"')
        && let Some(end) = q.find('"')
    {
        let tag = q[end + 1..].trim();
        return (&q[..end], (!tag.is_empty()).then_some(tag));
    }
    if arg.starts_with('<') && arg.ends_with('>') && !arg[1..].contains('<') {
        return (arg[1..arg.len() - 1].trim(), None);
    }
    match arg.find([' ', '\t']) {
        Some(i) => {
            let tag = arg[i..].trim();
            (&arg[..i], (!tag.is_empty()).then_some(tag))
        }
        None => (arg, None),
    }
}

/// Expands `$(NAME)`, `%(NAME)` (upper-cased), `$(NAME=default)` and `$(NAME:=default)` in
/// `line`, repeatedly until nothing changes (at most 100 substitutions). Returns the expanded
/// text and, if a macro stays unexpanded, its byte offset in the result and its text.
///
/// ```
/// use std::collections::HashMap;
/// let m = HashMap::from([("V".to_string(), "abe".to_string())]);
/// let (s, undef) = mission::nsplug::expand_macros("$(V) %(V) $(W=7) $(X)", &m);
/// assert_eq!(s, "abe ABE 7 $(X)");
/// assert_eq!(undef, Some((10, "$(X)".to_string())));
/// ```
pub fn expand_macros(
    line: &str,
    macros: &HashMap<String, String>,
) -> (String, Option<(usize, String)>) {
    let mut cur = line.to_string();
    let mut subs = 0;
    loop {
        let mut changed = false;
        let mut out = String::with_capacity(cur.len());
        let mut rest = cur.as_str();
        while let Some(p) = rest.find(['$', '%']) {
            let (before, from) = rest.split_at(p);
            out.push_str(before);
            let upper = from.starts_with('%');
            let body = &from[1..];
            let close = body
                .strip_prefix('(')
                .and_then(|b| b.find(')').map(|e| (b, e)));
            let Some((b, end)) = close.filter(|_| subs < MAX_SUBS_PER_LINE) else {
                out.push_str(&from[..1]);
                rest = body;
                continue;
            };
            let inner = &b[..end];
            let (name, default) = match inner.find(":=").or_else(|| inner.find('=')) {
                Some(i) => {
                    let skip = if inner[i..].starts_with(":=") { 2 } else { 1 };
                    (&inner[..i], Some(&inner[i + skip..]))
                }
                None => (inner, None),
            };
            let value = macros
                .get(name)
                .map(|v| if v == DEFINED { "" } else { v.as_str() })
                .or(default);
            match value {
                Some(v) => {
                    if upper {
                        out.push_str(&v.to_uppercase());
                    } else {
                        out.push_str(v);
                    }
                    subs += 1;
                    changed = true;
                }
                None => out.push_str(&from[..end + 3]),
            }
            rest = &b[end + 1..];
        }
        out.push_str(rest);
        cur = out;
        if !changed || subs >= MAX_SUBS_PER_LINE {
            break;
        }
    }
    let undefined = find_macro(&cur).map(|(at, len)| (at, cur[at..at + len].to_string()));
    (cur, undefined)
}

/// Byte offset and length of the first `$(...)` or `%(...)` in `s` (to the first `)`, or to
/// the end of the line when unclosed).
fn find_macro(s: &str) -> Option<(usize, usize)> {
    let a = s.find("$(");
    let b = s.find("%(");
    let at = match (a, b) {
        (Some(x), Some(y)) => x.min(y),
        (x, y) => x.or(y)?,
    };
    let len = s[at..].find(')').map_or(s.len() - at, |e| e + 1);
    Some((at, len))
}

/// Every `$(...)` and `%(...)` left in `s`, in order: byte offset and text (to the first `)`,
/// or to the end of the line when unclosed).
///
/// ```
/// let left = mission::nsplug::unexpanded_macros("x=$(XPOS),y=%(Y) $(Z");
/// assert_eq!(left, vec![(2, "$(XPOS)"), (12, "%(Y)"), (17, "$(Z")]);
/// ```
pub fn unexpanded_macros(s: &str) -> Vec<(usize, &str)> {
    let mut out = Vec::new();
    let mut from = 0;
    while let Some((at, len)) = find_macro(&s[from..]) {
        out.push((from + at, &s[from + at..from + at + len]));
        from += at + len;
    }
    out
}
