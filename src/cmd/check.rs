//! `coug check FILE... [NAME=VALUE]...`: preprocess, parse and validate mission files.

use std::collections::HashMap;
use std::path::PathBuf;

use clap::Args;
use mission::check::{check_files, is_bhv};
use mission::diagnostic::Diagnostic;
use mission::nsplug::Options;
use mission::source::FsSource;

/// Arguments of `coug check`.
#[derive(Debug, Args)]
pub struct CheckArgs {
    /// Mission files (`.moos`, `.bhv`) and nsplug macro definitions (`NAME=VALUE`).
    #[arg(required = true, value_name = "FILE|NAME=VALUE")]
    pub items: Vec<String>,
    /// Extra directory searched for `#include` files (repeatable).
    #[arg(short = 'p', long = "path", value_name = "DIR")]
    pub include_paths: Vec<PathBuf>,
    /// Also print each finding's source line with a caret under the column.
    #[arg(long)]
    pub context: bool,
    /// Most findings printed per file (with the files it includes); a summary line counts
    /// the rest. 0 prints them all.
    #[arg(long, value_name = "N", default_value_t = DEFAULT_MAX_FINDINGS)]
    pub max_findings: usize,
}

/// Default of `--max-findings`.
pub const DEFAULT_MAX_FINDINGS: usize = 50;

/// The file named on the command line (or found through `behaviors =`) that a finding's
/// file was included from, if it was.
fn top_file(d: &Diagnostic) -> String {
    let mut file = d.span.file.clone();
    while let Some(site) = file.included_from.clone() {
        file = site.file;
    }
    file.name.clone()
}

/// What was left out for one file: errors, warnings.
#[derive(Default)]
struct LeftOut {
    errors: usize,
    warnings: usize,
}

/// Runs the check, prints one line per finding on stdout (at most `--max-findings` per file,
/// then one line counting the rest); returns the exit code: 1 if any finding is an error, left
/// out or not, 0 otherwise.
pub fn run(args: &CheckArgs) -> i32 {
    let mut opts = Options::new();
    opts.include_paths = args.include_paths.clone();
    let mut files = Vec::new();
    let mut macros = Vec::new();
    for item in &args.items {
        if item.contains('=') {
            opts.define_arg(item);
            macros.push(item.clone());
        } else {
            files.push(PathBuf::from(item));
        }
    }
    if files.is_empty() {
        errln!("coug check: error: no file given (arguments with `=` are macro definitions)");
        return 2;
    }
    // A fleet file is checked as `coug run` would start it: every community's mission read
    // with its macros and validated.
    let (fleets, files): (Vec<PathBuf>, Vec<PathBuf>) = files
        .into_iter()
        .partition(|p| p.extension().is_some_and(|e| e == "fleet"));
    let mut fleet_errors = false;
    for path in &fleets {
        match runtime::fleet::LoadedFleet::from_file(path, &macros, &args.include_paths) {
            Ok(fleet) => {
                let v = runtime::session::validate_fleet(&fleet);
                fleet_errors |= report_validation(&path.display().to_string(), &v, 0);
            }
            Err(e) => {
                for m in e.messages() {
                    outln!("{}", finding("error", &m));
                }
                fleet_errors = true;
            }
        }
    }
    if files.is_empty() {
        return i32::from(fleet_errors);
    }
    let mut findings = check_files(&FsSource, &files, &opts);
    // A binary built with behaviours of its own (`coug::main_with`) knows more types than
    // the stock catalog.
    findings.retain(|f| !registered_elsewhere(f));
    let mut shown: HashMap<String, usize> = HashMap::new();
    let mut left: Vec<(String, LeftOut)> = Vec::new();
    for f in &findings {
        let file = top_file(f);
        let n = shown.entry(file.clone()).or_default();
        if args.max_findings == 0 || *n < args.max_findings {
            *n += 1;
            if args.context {
                outln!("{}", f.render());
            } else {
                outln!("{f}");
            }
            continue;
        }
        let i = match left.iter().position(|(name, _)| *name == file) {
            Some(i) => i,
            None => {
                left.push((file, LeftOut::default()));
                left.len() - 1
            }
        };
        if f.is_error() {
            left[i].1.errors += 1;
        } else {
            left[i].1.warnings += 1;
        }
    }
    // Then what `coug run` would find starting each mission (one validation path): helms
    // that would be in MALCONFIG, the apps' configuration warnings, missing blocks.
    let mut run_errors = false;
    for path in files.iter().filter(|p| !is_bhv(p)) {
        let name = path.display().to_string();
        if findings.iter().any(|f| f.is_error() && top_file(f) == name) {
            continue;
        }
        let loaded = match runtime::session::load(path, &macros, &args.include_paths) {
            Ok(l) => l,
            Err(errors) => {
                for e in errors.messages() {
                    outln!("{}", finding("error", &e));
                    run_errors = true;
                }
                continue;
            }
        };
        let v = runtime::session::validate(&loaded);
        // The reader's own warnings were listed above.
        run_errors |= report_validation(&name, &v, loaded.warnings.len());
    }
    for (file, l) in &left {
        let n = l.errors + l.warnings;
        outln!(
            "{file}: note: {n} more finding{} not shown ({} error{}, {} warning{}); \
             --max-findings 0 shows them all",
            plural(n),
            l.errors,
            plural(l.errors),
            l.warnings,
            plural(l.warnings)
        );
    }
    i32::from(fleet_errors || run_errors || findings.iter().any(|f| f.is_error()))
}

/// Prints what a run would find starting mission (or fleet) `name`, past its first
/// `listed` warnings (the reader's, already shown); true when any of it is an error.
fn report_validation(name: &str, v: &runtime::session::Validation, listed: usize) -> bool {
    let mut errors = false;
    for w in v.warnings.iter().skip(listed) {
        outln!("{w}");
    }
    for (helm, reasons) in &v.malconfig {
        for r in reasons {
            // A template checked without its macros cannot say how it will run.
            let (severity, note) = if r.contains("$(") {
                (
                    "warning",
                    " (an nsplug macro is not expanded: give NAME=VALUE to check it as it will run)",
                )
            } else {
                errors = true;
                ("error", "")
            };
            let text = format!("{helm} would run in MALCONFIG (never driving): {r}{note}");
            outln!("{}", finding(severity, &text));
        }
    }
    for f in &v.failed {
        outln!("{}", finding("error", f));
        errors = true;
    }
    for e in &v.errors {
        outln!("{}", finding("error", &format!("{name}: {e}")));
        errors = true;
    }
    errors
}

/// `file:line: SEVERITY: rest` for a finding that starts with `file:line: `, else
/// `SEVERITY: finding`.
fn finding(severity: &str, text: &str) -> String {
    let mut parts = text.splitn(3, ':');
    if let (Some(file), Some(line), Some(rest)) = (parts.next(), parts.next(), parts.next())
        && !file.is_empty()
        && line.trim().parse::<u32>().is_ok()
    {
        return format!("{file}:{}: {severity}:{rest}", line.trim());
    }
    format!("{severity}: {text}")
}

fn plural(n: usize) -> &'static str {
    if n == 1 { "" } else { "s" }
}

/// Whether `f` is an unknown-behaviour finding for a type the process's registry has (one a
/// user's binary registered).
fn registered_elsewhere(f: &Diagnostic) -> bool {
    if f.kind != mission::diagnostic::DiagnosticKind::UnknownBehavior {
        return false;
    }
    let kind = f.message.split('`').nth(1).unwrap_or("");
    !kind.is_empty() && behaviors::Registry::global().contains(kind)
}
