//! The validations behind `coug check`: preprocess and parse every file, then report
//!
//! - an unknown behaviour type (warning),
//! - a parameter unknown to a known behaviour type or to pHelmIvP's ProcessConfig (error: the
//!   real helm treats it as a configuration warning and refuses to drive, MALCONFIG),
//! - a condition or mode that tests a variable nothing initializes or posts (warning),
//! - a condition pHelmIvP rejects although coug reads it: an operand of `and`/`or` without
//!   parentheses, or `not` instead of `!` (error),
//! - a behaviour condition testing a mode variable for a value no `set` block gives
//!   (`MODE == SURVEYNG`; warning).
//!
//! nsplug's undefined-macro warnings are kept only for macros nsplug should have expanded: a
//! `$(NAME)` that the line's program expands itself at run time (uTimerScript's `$(COUNT)` and
//! random variables, pMarineViewer's click macros `$(XPOS)`, the helm's flag macros; see
//! [`catalog::is_runtime_macro`]) is not reported. The helm's `$[NAME]` is never an nsplug
//! macro.
//!
//! A `.moos` file's pHelmIvP `behaviors = FILE` entries are checked too (resolved beside the
//! `.moos` file) unless they were named on the command line already. Variables posted by the
//! `.moos` processes (`VAR=value` pairs in their parameters, e.g. pMarineViewer buttons or
//! uTimerScript events) count as posted for every file of the same check.
//!
//! ```
//! use mission::check::check_files;
//! use mission::source::MemorySource;
//! let fs = MemorySource::new().with("a.bhv", "Behavior = BHV_Loiter\n{\n  sped = 2\n}\n");
//! let findings = check_files(&fs, &["a.bhv".into()], &Default::default());
//! assert_eq!(findings[0].to_string(),
//!     "a.bhv:3:3: error: unknown parameter `sped` for BHV_Loiter (did you mean `speed`?)");
//! ```

use std::collections::{HashMap, HashSet};
use std::path::{Path, PathBuf};
use std::rc::Rc;
use std::sync::Arc;

use crate::bhv::{BehaviorFile, param_name, parse_bhv};
use crate::catalog::{self, WELL_KNOWN_VARS};
use crate::condition::{Condition, Operand, RelOp, moos_compat};
use crate::diagnostic::{Diagnostic, DiagnosticKind, quote_found};
use crate::moos::{MissionFile, ProcessConfig, parse_moos};
use crate::nsplug::{Options, expand_macros, preprocess, unexpanded_macros};
use crate::source::{FileSource, SourceMap, Span, column_of};

/// A parsed file of a check run.
enum Parsed {
    Moos(MissionFile),
    Bhv(BehaviorFile),
}

/// Whether `path` names a `.bhv` file (else it is read as `.moos`).
pub fn is_bhv(path: &Path) -> bool {
    path.extension()
        .is_some_and(|e| e.eq_ignore_ascii_case("bhv"))
}

/// Checks `paths` (preprocessed with `opts`) and returns every finding, file by file.
pub fn check_files(fs: &dyn FileSource, paths: &[PathBuf], opts: &Options) -> Vec<Diagnostic> {
    let mut out = Vec::new();
    let mut parsed = Vec::new();
    let mut sources: Vec<SourceMap> = Vec::new();
    let mut queue: Vec<(PathBuf, Option<Span>)> = paths.iter().map(|p| (p.clone(), None)).collect();
    let mut seen: HashSet<PathBuf> = paths.iter().map(|p| crate::source::normalize(p)).collect();
    let mut i = 0;
    while i < queue.len() {
        let (path, from) = queue[i].clone();
        i += 1;
        if from.is_some() && !fs.exists(&path) {
            if let Some(at) = from {
                out.push(
                    Diagnostic::warning(
                        DiagnosticKind::Unreadable,
                        at,
                        format!("behaviour file `{}` not found, not checked", path.display()),
                    )
                    .expected("the file named by `behaviors`, beside the .moos file"),
                );
            }
            continue;
        }
        let pre = match preprocess(fs, &path, opts) {
            Ok(p) => p,
            Err(d) => {
                out.push(d);
                continue;
            }
        };
        let bhv = is_bhv(&path);
        if bhv {
            for d in pre.diagnostics {
                // `$(X)` in behaviour flags is a helm macro, expanded at run time, not by nsplug.
                let helm_macro = d.kind == DiagnosticKind::UndefinedMacro
                    && d.source_line.as_deref().is_some_and(|l| {
                        let key = l.split('=').next().unwrap_or("");
                        param_name(key.trim()).ends_with("flag")
                    });
                if !helm_macro {
                    out.push(d);
                }
            }
            let p = parse_bhv(&pre.source);
            out.extend(p.diagnostics);
            parsed.push(Parsed::Bhv(p.value));
            sources.push(pre.source);
        } else {
            let p = parse_moos(&pre.source);
            let lines = entry_lines(&p.value);
            for mut d in pre.diagnostics {
                if d.kind != DiagnosticKind::UndefinedMacro
                    || nsplug_macro_left(&mut d, &lines, &pre.macros)
                {
                    out.push(d);
                }
            }
            out.extend(p.diagnostics);
            let dir = path.parent().unwrap_or(Path::new("")).to_path_buf();
            for helm in helm_blocks(&p.value) {
                for b in helm.params("behaviors") {
                    let file = dir.join(&b.value);
                    if !b.value.is_empty() && seen.insert(crate::source::normalize(&file)) {
                        queue.push((file, Some(b.span.clone())));
                    }
                }
            }
            parsed.push(Parsed::Moos(p.value));
            sources.push(pre.source);
        }
    }

    let mut known: HashSet<String> = WELL_KNOWN_VARS.iter().map(|s| s.to_string()).collect();
    for p in &parsed {
        match p {
            Parsed::Moos(m) => moos_posts(m, &mut known),
            Parsed::Bhv(b) => bhv_posts(b, &mut known),
        }
    }
    for p in &parsed {
        match p {
            Parsed::Moos(m) => check_helm_config(m, &mut out),
            Parsed::Bhv(b) => {
                check_behaviors(b, &mut out);
                check_variables(b, &known, &mut out);
                check_mode_values(b, &mut out);
                check_moos_compat(b, &mut out);
            }
        }
    }
    attach_source_lines(&mut out, &sources);
    out
}

/// Where each entry of a `.moos` file's blocks is: (file, line) -> the block's program, the
/// key, and the random-variable names the block declares (uTimerScript's `rand_var`).
type EntryLines = HashMap<(usize, u32), (String, String, Rc<Vec<String>>)>;

fn entry_lines(m: &MissionFile) -> EntryLines {
    let mut out = HashMap::new();
    for block in &m.processes {
        let program = m.program_of(block);
        let vars = Rc::new(random_vars(block));
        for e in &block.entries {
            let at = (Arc::as_ptr(&e.span.file) as usize, e.span.line);
            out.insert(at, (program.clone(), e.key.clone(), vars.clone()));
        }
    }
    out
}

/// The names of uTimerScript's random variables (`rand_var = varname=ANG, min=0, max=359`
/// and `rand_pair = varname1=X, varname2=Y, ...`), which its events use as `$(ANG)`.
fn random_vars(block: &ProcessConfig) -> Vec<String> {
    let specs = ["rand_var", "randvar", "rand_pair", "randpair"]
        .into_iter()
        .flat_map(|k| block.get_all(k));
    let mut out = Vec::new();
    for spec in specs {
        for part in spec.split(',') {
            if let Some((k, v)) = part.split_once('=')
                && matches!(k.trim(), "varname" | "varname1" | "varname2")
            {
                out.push(v.trim().to_string());
            }
        }
    }
    out
}

/// Whether the undefined-macro warning `d` is about a macro nsplug should have expanded
/// (else every macro left in the line is one that the line's program expands itself at run
/// time: uTimerScript's `$(COUNT)`, pMarineViewer's `$(XPOS)`). When the line has both kinds,
/// the warning is moved to the first nsplug macro.
fn nsplug_macro_left(
    d: &mut Diagnostic,
    lines: &EntryLines,
    macros: &HashMap<String, String>,
) -> bool {
    let at = (Arc::as_ptr(&d.span.file) as usize, d.span.line);
    let (Some((program, key, vars)), Some(text)) = (lines.get(&at), d.source_line.as_deref())
    else {
        return true;
    };
    let (expanded, _) = expand_macros(text, macros);
    let runtime = |m: &str| {
        m.strip_prefix("$(")
            .and_then(|r| r.strip_suffix(')'))
            .is_some_and(|name| catalog::is_runtime_macro(program, key, name, vars))
    };
    let Some((_, first)) = unexpanded_macros(&expanded)
        .into_iter()
        .find(|(_, m)| !runtime(m))
    else {
        return false;
    };
    if d.found.as_deref() != Some(&quote_found(first))
        && let Some(col) = text.find(first)
    {
        d.span = d.span.at_col(column_of(text, col));
        d.found = Some(quote_found(first));
    }
    true
}

/// Conditions coug reads but pHelmIvP rejects (its behaviour or mode is then a fatal
/// configuration error): unparenthesized `and`/`or` operands, `not`.
fn check_moos_compat(b: &BehaviorFile, out: &mut Vec<Diagnostic>) {
    let entries = b
        .modes
        .iter()
        .flat_map(|m| m.conditions.iter())
        .chain(b.behaviors.iter().flat_map(|s| s.conditions.iter()));
    for c in entries {
        if let Some(e) = moos_compat(&c.text) {
            let col = c.span.col
                + u32::try_from(c.text.get(..e.offset).map_or(0, |p| p.chars().count()))
                    .unwrap_or(0);
            out.push(
                Diagnostic::error(
                    DiagnosticKind::BadCondition,
                    c.span.at_col(col),
                    "condition that pHelmIvP rejects",
                )
                .expected(e.expected)
                .found(e.found),
            );
        }
    }
}

/// Gives every finding that lacks it the text of its line, for the caret rendering.
fn attach_source_lines(out: &mut [Diagnostic], sources: &[SourceMap]) {
    for d in out.iter_mut().filter(|d| d.source_line.is_none()) {
        let line = sources
            .iter()
            .flat_map(|s| s.lines())
            .find(|l| std::sync::Arc::ptr_eq(&l.file, &d.span.file) && l.line == d.span.line);
        if let Some(l) = line {
            d.source_line = Some(l.text.clone());
        }
    }
}

/// Behaviour conditions such as `MODE == SURVEYING` on a mode variable declared by this
/// file's `set` blocks must name values those blocks can produce (a typo never matches).
fn check_mode_values(b: &BehaviorFile, out: &mut Vec<Diagnostic>) {
    for spec in &b.behaviors {
        for c in &spec.conditions {
            let mut bad = Vec::new();
            mode_refs(&c.condition, &mut |var, value| {
                let values: Vec<&str> = b
                    .modes
                    .iter()
                    .filter(|m| m.var == var)
                    .flat_map(|m| std::iter::once(m.value.as_str()).chain(m.else_value.as_deref()))
                    .collect();
                if values.is_empty() {
                    return;
                }
                if let Some(part) = value
                    .split(':')
                    .map(str::trim)
                    .find(|p| !values.contains(p))
                {
                    bad.push((var.to_string(), part.to_string(), values.join(", ")));
                }
            });
            for (var, part, values) in bad {
                out.push(Diagnostic::warning(
                    DiagnosticKind::UnknownMode,
                    c.span.clone(),
                    format!(
                        "condition tests {var} for `{part}`, a value no `set {var}` block gives \
                         (the blocks give: {values})"
                    ),
                ));
            }
        }
    }
}

/// Calls `f(var, value)` for every `VAR = value` / `VAR == value` / `VAR != value` relation.
fn mode_refs<'a>(c: &'a Condition, f: &mut impl FnMut(&'a str, &'a str)) {
    match c {
        Condition::And(v) | Condition::Or(v) => v.iter().for_each(|c| mode_refs(c, f)),
        Condition::Not(c) => mode_refs(c, f),
        Condition::Compare {
            lhs: Operand::Var(var),
            op: RelOp::Eq | RelOp::FieldEq | RelOp::Ne,
            rhs: Operand::Str(value),
        } if !value.contains('$') => f(var, value),
        Condition::Compare { .. } => {}
    }
}

/// The ProcessConfig blocks pHelmIvP reads: `pHelmIvP`, and the MOOS names that the ANTLER
/// block gives it (`Run = pHelmIvP @ NewConsole = false ~ pHelmIvP_2`).
fn helm_blocks(m: &MissionFile) -> Vec<&crate::moos::ProcessConfig> {
    let runs = m.antler_runs();
    let is_helm = |app: &str| {
        app.rsplit('/')
            .next()
            .is_some_and(|b| b.eq_ignore_ascii_case("pHelmIvP"))
    };
    m.processes
        .iter()
        .filter(|p| {
            p.name.eq_ignore_ascii_case("pHelmIvP")
                || runs
                    .iter()
                    .any(|r| is_helm(&r.app) && r.moos_name().eq_ignore_ascii_case(&p.name))
        })
        .collect()
}

fn check_helm_config(m: &MissionFile, out: &mut Vec<Diagnostic>) {
    for block in helm_blocks(m) {
        for e in &block.entries {
            if !catalog::helm_accepts(&e.key) && !e.key.contains('$') {
                let hint = suggest(&e.key, catalog::HELM_PARAMS.iter().copied());
                out.push(Diagnostic::error(
                    DiagnosticKind::UnknownParameter,
                    e.span.clone(),
                    format!("unknown pHelmIvP parameter `{}`{hint}", e.key),
                ));
            }
        }
    }
}

fn check_behaviors(b: &BehaviorFile, out: &mut Vec<Diagnostic>) {
    for spec in &b.behaviors {
        let Some(kind) = catalog::behavior(&spec.kind) else {
            if !spec.kind.contains('$') {
                out.push(Diagnostic::error(
                    DiagnosticKind::UnknownBehavior,
                    spec.span.clone(),
                    format!(
                        "unknown behaviour type `{}`: the helm would run in MALCONFIG and never drive",
                        spec.kind
                    ),
                ));
            }
            continue;
        };
        for p in &spec.params {
            if !kind.accepts(&p.key) && !p.key.contains('$') {
                let all = kind.params.iter().chain(catalog::COMMON_PARAMS).copied();
                let hint = suggest(&param_name(&p.key), all);
                out.push(Diagnostic::error(
                    DiagnosticKind::UnknownParameter,
                    p.span.clone(),
                    format!("unknown parameter `{}` for {}{hint}", p.key, kind.name),
                ));
            }
        }
    }
}

fn check_variables(b: &BehaviorFile, known: &HashSet<String>, out: &mut Vec<Diagnostic>) {
    let entries = b
        .modes
        .iter()
        .flat_map(|m| m.conditions.iter())
        .chain(b.behaviors.iter().flat_map(|s| s.conditions.iter()));
    for c in entries {
        let mut reported: Vec<&str> = Vec::new();
        for v in c.condition.variables() {
            if v.contains('$') || known.contains(v) || reported.contains(&v) {
                continue;
            }
            reported.push(v);
            out.push(Diagnostic::warning(
                DiagnosticKind::UnknownVariable,
                c.span.clone(),
                format!("condition tests `{v}`, which nothing initializes or posts"),
            ));
        }
    }
}

/// Variables a `.bhv` file posts: initializes, mode variables, flags, `*_var` outputs and the
/// default outputs of its behaviour types.
fn bhv_posts(b: &BehaviorFile, known: &mut HashSet<String>) {
    known.extend(b.initializes.iter().map(|i| i.var.clone()));
    known.extend(b.modes.iter().map(|m| m.var.clone()));
    for spec in &b.behaviors {
        if let Some(t) = catalog::behavior(&spec.kind) {
            known.extend(t.posts.iter().map(|s| s.to_string()));
        }
        for p in &spec.params {
            let k = param_name(&p.key);
            if k.ends_with("flag") {
                if let Some((var, _)) = p.value.split_once('=') {
                    known.insert(var.trim().to_string());
                }
            } else if catalog::names_output_var(&k) {
                known.insert(p.value.trim().to_string());
            } else if k == "post_mapping"
                && let Some((_, new)) = p.value.split_once(',')
            {
                known.insert(new.trim().to_string());
            }
        }
    }
}

/// Variables a `.moos` file's processes post, as far as their configuration tells:
/// `NAME=value` pairs (upper-case names) and `var=NAME` / `alias=NAME` pairs; a pSafety
/// block adds the supervisor's words (`SAFETY_MODE`, `SAFETY_HEALTH`, `SAFETY_EVENT`).
fn moos_posts(m: &MissionFile, known: &mut HashSet<String>) {
    for block in &m.processes {
        if block.name.starts_with("pSafety") {
            known.extend(["SAFETY_MODE", "SAFETY_HEALTH", "SAFETY_EVENT"].map(String::from));
        }
    }
    for p in m.processes.iter().flat_map(|p| p.entries.iter()) {
        scan_assignments(&p.value, known);
    }
}

fn scan_assignments(text: &str, known: &mut HashSet<String>) {
    let b = text.as_bytes();
    let is_id = |c: u8| c.is_ascii_alphanumeric() || c == b'_';
    let mut i = 0;
    while i < b.len() {
        if !is_id(b[i]) || (i > 0 && is_id(b[i - 1])) {
            i += 1;
            continue;
        }
        let start = i;
        while i < b.len() && is_id(b[i]) {
            i += 1;
        }
        let word = &text[start..i];
        let mut j = i;
        while j < b.len() && b[j] == b' ' {
            j += 1;
        }
        if j < b.len() && b[j] == b'=' && b.get(j + 1) != Some(&b'=') {
            let upper = word.bytes().all(|c| !c.is_ascii_lowercase());
            if upper && word.bytes().next().is_some_and(|c| c.is_ascii_alphabetic()) {
                known.insert(word.to_string());
            } else if word.eq_ignore_ascii_case("var") || word.eq_ignore_ascii_case("alias") {
                let rest = text[j + 1..].trim_start();
                let name: String = rest
                    .bytes()
                    .take_while(|&c| is_id(c))
                    .map(char::from)
                    .collect();
                if !name.is_empty() {
                    known.insert(name);
                }
            }
        }
    }
}

/// ` (did you mean `x`?)` for the closest candidate within edit distance 2, else "".
fn suggest<'a>(word: &str, candidates: impl Iterator<Item = &'a str>) -> String {
    let w = word.to_ascii_lowercase();
    candidates
        .map(|c| (edit_distance(&w, c), c))
        .filter(|(d, _)| *d <= 2)
        .min_by_key(|(d, _)| *d)
        .map(|(_, c)| format!(" (did you mean `{c}`?)"))
        .unwrap_or_default()
}

fn edit_distance(a: &str, b: &str) -> usize {
    let b: Vec<char> = b.chars().collect();
    let mut prev: Vec<usize> = (0..=b.len()).collect();
    let mut cur = vec![0; b.len() + 1];
    for (i, ca) in a.chars().enumerate() {
        cur[0] = i + 1;
        for (j, cb) in b.iter().enumerate() {
            let sub = prev[j] + usize::from(ca != *cb);
            cur[j + 1] = sub.min(prev[j + 1] + 1).min(cur[j] + 1);
        }
        std::mem::swap(&mut prev, &mut cur);
    }
    prev[b.len()]
}
