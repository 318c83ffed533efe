//! Corpus test: every real MOOS-IvP mission file (../shared/corpus/moos-ivp-missions) is
//! preprocessed and parsed; files without nsplug macros must parse with zero errors.

use std::collections::HashSet;

use mission::bhv::parse_bhv;
use mission::check::{check_files, is_bhv};
use mission::diagnostic::{DiagnosticKind, Severity};
use mission::moos::parse_moos;
use mission::nsplug::{Options, preprocess};
use mission::source::FsSource;

/// Relative paths (as in MACROS.txt) of the files that use no nsplug macro.
fn macro_free() -> HashSet<String> {
    let path = test_support::corpus("MACROS.txt");
    let text = std::fs::read_to_string(&path)
        .unwrap_or_else(|e| panic!("cannot read {}: {e}", path.display()));
    text.lines()
        .filter(|l| !l.starts_with('#'))
        .filter_map(|l| {
            let mut f = l.split('\t');
            let name = f.next()?;
            let macros = f.nth(1)?;
            (macros == "macros=").then(|| name.to_string())
        })
        .collect()
}

#[test]
fn every_corpus_file_parses_and_macro_free_files_have_no_errors() {
    let dir = test_support::mission_file("");
    let files = test_support::files_with_ext(&dir, &["moos", "bhv"]);
    let free = macro_free();
    assert_eq!(
        files.len(),
        417,
        "the corpus README promises 417 .moos/.bhv files"
    );
    let mut failures = Vec::new();
    let (mut n_free, mut pre_fail, mut with_errors, mut warnings, mut errors) = (0, 0, 0, 0, 0);
    for f in &files {
        let rel = f.strip_prefix(&dir).unwrap().to_string_lossy().to_string();
        let is_free = free.contains(&rel);
        n_free += usize::from(is_free);
        let diags = match preprocess(&FsSource, f, &Options::new()) {
            Ok(pre) => {
                let mut d = pre.diagnostics;
                if is_bhv(f) {
                    d.extend(parse_bhv(&pre.source).diagnostics);
                } else {
                    d.extend(parse_moos(&pre.source).diagnostics);
                }
                d
            }
            Err(e) => {
                pre_fail += 1;
                vec![e]
            }
        };
        let errs: Vec<_> = diags.iter().filter(|d| d.is_error()).collect();
        warnings += diags.len() - errs.len();
        errors += errs.len();
        with_errors += usize::from(!errs.is_empty());
        if is_free && !errs.is_empty() {
            failures.push(format!(
                "{rel}:\n{}",
                errs.iter()
                    .map(|e| e.render())
                    .collect::<Vec<_>>()
                    .join("\n")
            ));
        }
        if !is_free {
            for e in &errs {
                eprintln!("template {rel}: {e}");
            }
        }
    }
    println!(
        "corpus: {} files, {} without macros, {} templates; {} failed preprocessing (templates \
         without their macros), {} files with errors, {} errors, {} warnings",
        files.len(),
        n_free,
        files.len() - n_free,
        pre_fail,
        with_errors,
        errors,
        warnings
    );
    assert_eq!(n_free, 181, "MACROS.txt lists 181 macro-free files");
    // Regression guards for the templates read without their macros: only
    // m9_indigo/meta_shoreside.moos (its plug file is not in the corpus) may fail.
    assert!(
        pre_fail <= 1,
        "{pre_fail} templates failed preprocessing (baseline 1)"
    );
    assert!(
        with_errors <= 1,
        "{with_errors} files with errors (baseline 1)"
    );
    assert!(
        failures.is_empty(),
        "macro-free files with errors:\n{}",
        failures.join("\n")
    );
}

/// x1_legs's BHV_LegRun writes `legflag` and `mid_pct`, which BHV_LegRun at MOOS-IvP
/// a2a9b716 does not know: pHelmIvP refuses them as well (its helm is MALCONFIG).
fn x1_legs_unknown(rel: &str, d: &mission::diagnostic::Diagnostic) -> bool {
    rel.starts_with("x1_legs/")
        && d.kind == DiagnosticKind::UnknownParameter
        && (d.message.contains("`legflag`") || d.message.contains("`mid_pct`"))
}

/// `coug check` over the corpus: every macro-free file checked alone gets no error, and the
/// counts of each kind of finding over the whole corpus are printed.
#[test]
fn check_flags_no_error_in_macro_free_corpus_files() {
    let dir = test_support::mission_file("");
    let free = macro_free();
    let mut counts: std::collections::BTreeMap<String, usize> = Default::default();
    let mut false_errors = Vec::new();
    for f in test_support::files_with_ext(&dir, &["moos", "bhv"]) {
        let rel = f.strip_prefix(&dir).unwrap().to_string_lossy().to_string();
        let findings = check_files(&FsSource, std::slice::from_ref(&f), &Options::new());
        for d in &findings {
            *counts
                .entry(format!("{:?} {:?}", d.severity, d.kind))
                .or_default() += 1;
            // A behaviour type coug does not have yet is a true error for coug (its helm
            // would be in MALCONFIG), not a misreading of the file: those are listed apart.
            if free.contains(&rel) && d.severity == Severity::Error {
                if d.kind == DiagnosticKind::UnknownBehavior {
                    assert!(d.message.contains("unknown behaviour type `BHV_"), "{d}");
                } else if x1_legs_unknown(&rel, d) {
                    // True errors too: pHelmIvP refuses them (see `x1_legs_unknown`).
                } else {
                    false_errors.push(d.to_string());
                }
            }
            if d.kind == DiagnosticKind::UnknownParameter {
                eprintln!("{rel}: {d}");
            }
        }
    }
    println!("coug check over the corpus (each file alone, no macros defined):");
    for (k, n) in &counts {
        println!("  {k}: {n}");
    }
    assert!(
        false_errors.is_empty(),
        "errors in macro-free files:\n{}",
        false_errors.join("\n")
    );
}

/// Every macro name MACROS.txt lists for the files of each mission folder.
fn folder_macros() -> std::collections::HashMap<String, Vec<String>> {
    let path = test_support::corpus("MACROS.txt");
    let text = std::fs::read_to_string(&path)
        .unwrap_or_else(|e| panic!("cannot read {}: {e}", path.display()));
    let mut out: std::collections::HashMap<String, Vec<String>> = Default::default();
    for l in text.lines().filter(|l| !l.starts_with('#')) {
        let mut f = l.split('\t');
        let (Some(name), Some(macros)) = (f.next(), f.nth(1)) else {
            continue;
        };
        let folder = name.rsplit_once('/').map_or("", |(d, _)| d).to_string();
        let list = macros.trim_start_matches("macros=");
        out.entry(folder).or_default().extend(
            list.split(',')
                .filter(|m| !m.is_empty())
                .map(str::to_string),
        );
    }
    out
}

/// Templates expanded the way their launch scripts do (every macro of the folder defined, here
/// with the value `1`), then parsed and checked: no parse error, and `coug check` raises no
/// unknown-parameter error (pHelmIvP's or a behaviour's) on any real mission.
#[test]
fn templates_expanded_with_their_macros_parse_and_check_clean() {
    let dir = test_support::mission_file("");
    let macros = folder_macros();
    let (mut expanded, mut findings) = (0, std::collections::BTreeMap::<String, usize>::new());
    let mut problems = Vec::new();
    for f in test_support::files_with_ext(&dir, &["moos", "bhv"]) {
        let rel = f.strip_prefix(&dir).unwrap().to_string_lossy().to_string();
        let folder = rel.rsplit_once('/').map_or("", |(d, _)| d);
        let mut opts = Options::new();
        for m in macros.get(folder).into_iter().flatten() {
            opts.define_arg(&format!("{m}=1"));
        }
        match preprocess(&FsSource, &f, &opts) {
            Ok(pre) => {
                expanded += 1;
                let d = if is_bhv(&f) {
                    parse_bhv(&pre.source).diagnostics
                } else {
                    parse_moos(&pre.source).diagnostics
                };
                problems.extend(
                    d.iter()
                        .filter(|d| d.is_error())
                        .map(|d| format!("{rel}: {d}")),
                );
            }
            Err(e) => {
                // One corpus template includes a plug file that the corpus does not have.
                if !(e.kind == DiagnosticKind::IncludeNotFound
                    && rel == "m9_indigo/meta_shoreside.moos")
                {
                    problems.push(format!("{rel}: {e}"));
                }
            }
        }
        for d in check_files(&FsSource, std::slice::from_ref(&f), &opts) {
            *findings
                .entry(format!("{:?} {:?}", d.severity, d.kind))
                .or_default() += 1;
            // m3_casar's `active_grade` (in a BHV_AvoidCollision) is a parameter no behaviour
            // of MOOS-IvP a2a9b716 has: pHelmIvP refuses it as well.
            // m2_berta_obstacles gives BHV_AvoidObstacleV24 a `buffer_dist`, which only the
            // older BHV_AvoidObstacle takes: refused by pHelmIvP as well.
            let refused_by_moos = (rel == "m3_casar/meta_henry.bhv"
                && d.message.contains("`active_grade`"))
                || x1_legs_unknown(&rel, &d)
                || (rel == "m2_berta_obstacles/meta_vehicle.bhv"
                    && d.message.contains("`buffer_dist` for BHV_AvoidObstacleV24"));
            if d.kind == DiagnosticKind::UnknownParameter && !refused_by_moos {
                problems.push(format!("{rel}: {d}"));
            }
        }
    }
    println!("templates expanded with their folder's macros: {expanded} files preprocessed");
    println!("coug check over the corpus with macros defined:");
    for (k, n) in &findings {
        println!("  {k}: {n}");
    }
    assert_eq!(
        expanded, 416,
        "all but m9_indigo/meta_shoreside.moos expand"
    );
    assert!(
        problems.is_empty(),
        "errors in expanded corpus files:\n{}",
        problems.join("\n")
    );
}

/// The stock missions that are complete as written (no `#include`, not a `meta_`/`plug_`
/// template) use `$(X)` only as the apps' own run-time macros (uTimerScript's `$(COUNT)` and
/// random variables, pMarineViewer's `$(XPOS)`, the helm's flag macros): `coug check` warns
/// about none of them.
#[test]
fn complete_stock_missions_get_no_warning_about_runtime_macros() {
    let dir = test_support::mission_file("");
    let path = test_support::corpus("MACROS.txt");
    let text = std::fs::read_to_string(&path)
        .unwrap_or_else(|e| panic!("cannot read {}: {e}", path.display()));
    let mut checked = Vec::new();
    let mut warned = Vec::new();
    for l in text.lines().filter(|l| !l.starts_with('#')) {
        let f: Vec<&str> = l.split('\t').collect();
        let (Some(name), Some(&"includes=0"), Some(macros)) = (f.first(), f.get(1), f.get(2))
        else {
            continue;
        };
        let base = name.rsplit('/').next().unwrap_or(name);
        if *macros == "macros=" || base.starts_with("meta_") || base.starts_with("plug") {
            continue;
        }
        checked.push(name.to_string());
        for d in check_files(&FsSource, &[dir.join(name)], &Options::new()) {
            if d.kind == DiagnosticKind::UndefinedMacro {
                warned.push(d.to_string());
            }
        }
    }
    println!(
        "complete missions with run-time macros: {}",
        checked.join(" ")
    );
    assert!(checked.len() >= 14, "{checked:?}");
    assert!(warned.is_empty(), "{}", warned.join("\n"));
}
