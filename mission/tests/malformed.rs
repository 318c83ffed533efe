//! Malformed input: each mistake gives the exact file:line:col and names what was expected,
//! also through `#include`.

use mission::bhv::parse_bhv;
use mission::check::check_files;
use mission::diagnostic::{Diagnostic, DiagnosticKind, Severity};
use mission::moos::parse_moos;
use mission::nsplug::{Options, preprocess};
use mission::source::{MemorySource, SourceMap};

fn moos_errors(text: &str) -> Vec<Diagnostic> {
    parse_moos(&SourceMap::from_text("m.moos", text)).diagnostics
}

fn bhv_errors(text: &str) -> Vec<Diagnostic> {
    parse_bhv(&SourceMap::from_text("b.bhv", text)).diagnostics
}

fn only(d: Vec<Diagnostic>) -> Diagnostic {
    assert_eq!(d.len(), 1, "expected one diagnostic, got {d:#?}");
    d.into_iter().next().unwrap()
}

#[test]
fn moos_unterminated_block() {
    let d = only(moos_errors(
        "ServerPort = 9000\nProcessConfig = pHelmIvP\n{\n  AppTick = 4\n",
    ));
    assert_eq!(d.kind, DiagnosticKind::UnterminatedBlock);
    assert_eq!(
        d.to_string(),
        "m.moos:2:1: error: block `ProcessConfig = pHelmIvP` is never closed: expected `}` before the end of the file, found end of file"
    );
    // A block left open before the next one.
    let d = only(moos_errors(
        "ProcessConfig = A\n{\n  x = 1\nProcessConfig = B\n{\n}\n",
    ));
    assert_eq!(
        (d.kind, d.span.line),
        (DiagnosticKind::UnterminatedBlock, 1)
    );
    assert!(
        d.message
            .contains("before the next `ProcessConfig` (m.moos:4)"),
        "{}",
        d.message
    );
}

#[test]
fn moos_extra_close_brace() {
    // MOOS's reader skips a `}` that closes nothing: a warning, not an error.
    let d = only(moos_errors("ProcessConfig = A\n{\n  x = 1\n}\n  }\n"));
    assert_eq!(d.severity, Severity::Warning);
    assert_eq!(
        d.to_string(),
        "m.moos:5:3: warning: `}` without an open block: MOOS ignores this line: expected a `ProcessConfig = NAME` line and `{` before it, found `}`"
    );
    assert!(
        d.render().ends_with("  5 |   }\n    |   ^"),
        "{}",
        d.render()
    );
}

#[test]
fn moos_line_without_equals() {
    // MOOS skips the line: a warning in the block of a program that reads `key = value`.
    let d = only(moos_errors(
        "ProcessConfig = pNodeReporter\n{\n  AppTick 4\n}\n",
    ));
    assert_eq!(
        d.to_string(),
        "m.moos:3:3: warning: line without `=`: MOOS ignores this line: expected `key = value`, found `AppTick 4`"
    );
    // A forgotten `{`: one error, and the lines are still read as the block's.
    let p = parse_moos(&SourceMap::from_text(
        "m.moos",
        "ProcessConfig = A\n  AppTick = 4\n}\n",
    ));
    assert_eq!(p.value.process("A").unwrap().get("apptick"), Some("4"));
    let d = only(p.diagnostics);
    assert_eq!((d.kind, d.span.line), (DiagnosticKind::MissingOpenBrace, 2));
    assert_eq!(d.expected.as_deref(), Some("`{` on the next line"));
}

#[test]
fn bhv_unterminated_blocks() {
    let d = only(bhv_errors("Behavior = BHV_Loiter\n{\n  speed = 1\n"));
    assert_eq!(
        d.to_string(),
        "b.bhv:1:1: error: block `Behavior = BHV_Loiter` is never closed: expected `}` before the end of the file, found end of file"
    );
    let d = only(bhv_errors("set MODE = A {\n  DEPLOY = true\n"));
    assert_eq!(
        (d.kind, d.span.line),
        (DiagnosticKind::UnterminatedBlock, 1)
    );
    // Next behaviour starts while the first is open: both are kept, the first is reported.
    let p = parse_bhv(&SourceMap::from_text(
        "b.bhv",
        "Behavior = BHV_A\n{\n a = 1\nBehavior = BHV_B\n{\n}\n",
    ));
    let d = only(p.diagnostics);
    assert_eq!(
        (d.kind, d.span.line),
        (DiagnosticKind::UnterminatedBlock, 1)
    );
    assert_eq!(d.found.as_deref(), Some("`Behavior = BHV_B`"));
    assert_eq!(p.value.behaviors.len(), 2);
}

#[test]
fn bhv_extra_close_brace() {
    let d = only(bhv_errors("Behavior = BHV_A\n{\n  a = 1\n}\n\n}\n"));
    assert_eq!(
        d.to_string(),
        "b.bhv:6:1: error: `}` without an open block: expected a `Behavior = TYPE` or `set VAR = VALUE` line and `{` before it, found `}`"
    );
}

#[test]
fn bhv_param_without_equals() {
    let d = only(bhv_errors(
        "Behavior = BHV_A\n{\n  name = a\n    speed 2.0\n}\n",
    ));
    assert_eq!(
        d.to_string(),
        "b.bhv:4:5: error: parameter line without `=`: expected `param = value` or `}`, found `speed 2.0`"
    );
    let d = only(bhv_errors("initialize DEPLOY\n"));
    assert_eq!(
        (d.kind, d.span.line, d.span.col),
        (DiagnosticKind::MissingEquals, 1, 12)
    );
}

#[test]
fn unbalanced_parenthesis_in_condition() {
    let d = only(bhv_errors(
        "Behavior = BHV_A\n{\n  condition = ((MODE == A) or (B = 1)\n}\n",
    ));
    assert_eq!(d.kind, DiagnosticKind::BadCondition);
    assert_eq!(
        d.to_string(),
        "b.bhv:3:38: error: malformed condition: expected `)`, `and` or `or`, found end of condition"
    );
    let d = only(bhv_errors(
        "Behavior = BHV_A\n{\n  condition = (MODE == A))\n}\n",
    ));
    assert_eq!(
        d.to_string(),
        "b.bhv:3:26: error: malformed condition: expected `and`, `or` or the end of the condition, found `)`"
    );
    let d = only(bhv_errors("set MODE = X {\n  (DEPLOY = true\n}\n"));
    assert_eq!(
        (d.kind, d.span.line, d.span.col),
        (DiagnosticKind::BadCondition, 2, 17)
    );
    let d = only(bhv_errors(
        "Behavior = BHV_A\n{\n  condition = DEPLOY true\n}\n",
    ));
    assert_eq!(
        d.expected.as_deref(),
        Some("a relation operator (=, ==, !=, <, <=, >, >=)")
    );
    assert_eq!(d.span.col, 22);
}

#[test]
fn field_match_is_refused_in_mode_blocks() {
    let d = only(bhv_errors("set MODE = X {\n  MODE == ACTIVE\n}\n"));
    assert_eq!(
        (d.kind, d.span.line, d.span.col),
        (DiagnosticKind::BadCondition, 2, 8)
    );
}

#[test]
fn errors_inside_includes_name_the_included_file() {
    let fs = MemorySource::new()
        .with(
            "meta.bhv",
            "initialize DEPLOY = false\n#include plug_bhv.bhv\n",
        )
        .with(
            "plug_bhv.bhv",
            "// plug\nBehavior = BHV_Loiter\n{\n  condition = (DEPLOY = true\n}\n",
        );
    let pre = preprocess(&fs, "meta.bhv".as_ref(), &Options::new()).unwrap();
    let d = only(parse_bhv(&pre.source).diagnostics);
    assert_eq!(d.span.file.name, "plug_bhv.bhv");
    assert_eq!((d.span.line, d.span.col), (4, 29));
    assert!(
        d.render().contains("= included from meta.bhv:2:10"),
        "{}",
        d.render()
    );

    let fs = MemorySource::new()
        .with("meta.moos", "#include plug.moos\nProcessConfig = B\n{\n}\n")
        .with("plug.moos", "ProcessConfig = A\n{\n  x = 1\n");
    let pre = preprocess(&fs, "meta.moos".as_ref(), &Options::new()).unwrap();
    let d = only(parse_moos(&pre.source).diagnostics);
    assert_eq!((d.span.file.name.as_str(), d.span.line), ("plug.moos", 1));
    assert!(d.message.contains("(meta.moos:2)"), "{}", d.message);
}

#[test]
fn check_reports_unknown_types_parameters_and_variables() {
    let fs = MemorySource::new()
        .with(
            "m/alpha.moos",
            "ProcessConfig = pHelmIvP\n{\n  behaviors = alpha.bhv\n  AppTick = 4\n  behaviour_dir = x\n}\n\
             ProcessConfig = pMarineViewer\n{\n  button_one = DEPLOY # DEPLOY=true\n}\n",
        )
        .with(
            "m/alpha.bhv",
            "initialize RETURN = false\nset MODE = ACTIVE {\n  DEPLOY = true\n} INACTIVE\n\
             Behavior = BHV_Waypoint\n{\n  condition = (MODE == ACTIVE) and (GHOST = 1)\n  capture_radiuss = 3\n  endflag = DONE = true\n  speed = 2\n}\n\
             Behavior = BHV_Mystery\n{\n  anything = 1\n  condition = DONE = true\n}\n",
        );
    let findings = check_files(&fs, &["m/alpha.moos".into()], &Options::new());
    let lines: Vec<String> = findings.iter().map(|d| d.to_string()).collect();
    assert_eq!(
        lines,
        [
            "m/alpha.moos:5:3: error: unknown pHelmIvP parameter `behaviour_dir`",
            "m/alpha.bhv:8:3: error: unknown parameter `capture_radiuss` for BHV_Waypoint (did you mean `capture_radius`?)",
            "m/alpha.bhv:12:1: error: unknown behaviour type `BHV_Mystery`: the helm would run in MALCONFIG and never drive",
            "m/alpha.bhv:7:15: warning: condition tests `GHOST`, which nothing initializes or posts",
        ]
    );
    assert_eq!(
        findings
            .iter()
            .filter(|d| d.severity == Severity::Error)
            .count(),
        3
    );
}

#[test]
fn check_warns_about_mode_values_no_set_block_gives() {
    let fs = MemorySource::new().with(
        "m.bhv",
        "initialize DEPLOY = false\nset MODE = ACTIVE {\n  DEPLOY = true\n} INACTIVE\n\
         set MODE = SURVEYING {\n  MODE = ACTIVE\n}\n\
         Behavior = BHV_Loiter\n{\n  condition = MODE == ACTIVE:SURVEYNG\n}\n\
         Behavior = BHV_Loiter\n{\n  condition = (MODE == ACTIVE:SURVEYING) or (MODE = INACTIVE)\n}\n",
    );
    let findings = check_files(&fs, &["m.bhv".into()], &Options::new());
    assert_eq!(findings.len(), 1, "{findings:#?}");
    let d = &findings[0];
    assert_eq!(
        (d.kind, d.severity),
        (DiagnosticKind::UnknownMode, Severity::Warning)
    );
    assert_eq!(
        d.to_string(),
        "m.bhv:10:15: warning: condition tests MODE for `SURVEYNG`, a value no `set MODE` block gives (the blocks give: ACTIVE, INACTIVE, SURVEYING)"
    );
    // Check findings carry their source line for the caret rendering.
    assert!(
        d.render()
            .ends_with("10 |   condition = MODE == ACTIVE:SURVEYNG\n    |               ^"),
        "{}",
        d.render()
    );
}

#[test]
fn check_flags_conditions_phelmivp_would_reject() {
    let fs = MemorySource::new().with(
        "c.bhv",
        "initialize A = 1, B = 2\nBehavior = BHV_Loiter\n{\n  condition = (A = 1) and B = 2\n  condition = not (A = 1)\n  condition = ((A = 1) or (B = 2)) and !(A = 3)\n}\n",
    );
    let lines: Vec<String> = check_files(&fs, &["c.bhv".into()], &Options::new())
        .iter()
        .map(|d| d.to_string())
        .collect();
    assert_eq!(
        lines,
        [
            "c.bhv:4:27: error: condition that pHelmIvP rejects: expected a parenthesized operand of `and`/`or` (pHelmIvP requires it), found `B`",
            "c.bhv:5:15: error: condition that pHelmIvP rejects: expected `!(...)` (pHelmIvP has no `not`), found `not`",
        ]
    );
}

#[test]
fn check_reads_the_helm_block_under_its_antler_alias() {
    let fs = MemorySource::new()
        .with(
            "h.moos",
            "ProcessConfig = ANTLER\n{\n  Run = pHelmIvP @ NewConsole = false ~ helm_b\n}\n\
             ProcessConfig = helm_b\n{\n  behaviors = h.bhv\n  bogus = 1\n}\n\
             ProcessConfig = other\n{\n  bogus = 1\n}\n",
        )
        .with("h.bhv", "Behavior = BHV_Timer\n{\n  nonsense = 2\n}\n");
    let lines: Vec<String> = check_files(&fs, &["h.moos".into()], &Options::new())
        .iter()
        .map(|d| d.to_string())
        .collect();
    assert_eq!(
        lines,
        [
            "h.moos:8:3: error: unknown pHelmIvP parameter `bogus`",
            "h.bhv:3:3: error: unknown parameter `nonsense` for BHV_Timer",
        ]
    );
}
