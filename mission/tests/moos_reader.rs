//! `.moos` lines that MOOS's own reader skips: each is at most a warning that says MOOS ignores
//! it, braces nested in a block are balanced, and the block of a program that reads its block
//! in its own syntax (Goby's protobuf text) is not checked line by line.

use mission::check::check_files;
use mission::diagnostic::{Diagnostic, DiagnosticKind, Severity};
use mission::moos::{MissionFile, parse_moos};
use mission::nsplug::{Options, preprocess};
use mission::source::{MemorySource, SourceMap};

fn parse(text: &str) -> (MissionFile, Vec<Diagnostic>) {
    let p = parse_moos(&SourceMap::from_text("m.moos", text));
    (p.value, p.diagnostics)
}

/// (line, kind) of each finding, all of them warnings.
fn warnings(d: &[Diagnostic]) -> Vec<(u32, DiagnosticKind)> {
    for x in d {
        assert_eq!(x.severity, Severity::Warning, "{x}");
        assert!(x.message.contains("MOOS"), "{x}");
    }
    d.iter().map(|x| (x.span.line, x.kind)).collect()
}

#[test]
fn free_text_in_the_global_section_is_a_warning() {
    let (m, d) = parse(
        "ServerHost = localhost\nMIT Sailing Pavilion (use this one)\nLatOrigin = 42.358\n\
         ProcessConfig = pShare\n{\n  input = route=localhost:9300\n}\n",
    );
    assert_eq!(warnings(&d), [(2, DiagnosticKind::MissingEquals)]);
    assert_eq!(
        d[0].to_string(),
        "m.moos:2:1: warning: line without `=`: MOOS ignores this line: expected `key = value`, \
         found `MIT Sailing Pavilion (use this one)`"
    );
    assert_eq!(m.global("LatOrigin"), Some("42.358"));
    assert_eq!(
        m.process("pShare").unwrap().get("input"),
        Some("route=localhost:9300")
    );
}

#[test]
fn hash_lines_inside_a_block_are_warnings_and_the_block_goes_on() {
    let (m, d) = parse(
        "ProcessConfig = uProcessWatch\n{\n  # Linux:\n  watch_all = true\n  # Mac:\n  \
         nowatch = uXMS*\n}\n",
    );
    assert_eq!(
        warnings(&d),
        [
            (3, DiagnosticKind::MissingEquals),
            (5, DiagnosticKind::MissingEquals)
        ]
    );
    let b = m.process("uProcessWatch").unwrap();
    assert_eq!(b.get("watch_all"), Some("true"));
    assert_eq!(b.get("nowatch"), Some("uXMS*"));
}

#[test]
fn banner_lines_are_warnings_in_and_out_of_blocks() {
    let (m, d) = parse(
        "//\n=======================\nServerPort = 9000\n=======================\n\
         ProcessConfig = pLogger\n{\n  ==========\n  AsyncLog = true\n}\n",
    );
    assert_eq!(
        warnings(&d),
        [
            (2, DiagnosticKind::EmptyKey),
            (4, DiagnosticKind::EmptyKey),
            (7, DiagnosticKind::EmptyKey)
        ]
    );
    assert!(d[0].message.contains("nothing before `=`"), "{}", d[0]);
    assert_eq!(m.global("ServerPort"), Some("9000"));
    assert_eq!(m.process("pLogger").unwrap().get("asynclog"), Some("true"));
}

#[test]
fn a_macro_that_expands_to_whole_lines_is_reported_once_by_nsplug() {
    let text = "ProcessConfig = pMarineViewer\n{\n  $(NODE_OFFSETS_LIST)\n  tiff_file = a.tif\n}\n";
    let fs = MemorySource::new().with("m.moos", text);
    // Undefined: nsplug's warning only (the parser does not add its own for the same line).
    let d = check_files(&fs, &["m.moos".into()], &Options::new());
    assert_eq!(d.len(), 1, "{d:#?}");
    assert_eq!(d[0].kind, DiagnosticKind::UndefinedMacro);
    assert_eq!((d[0].span.line, d[0].span.col), (3, 3));
    // Defined as the launch script does: the lines it stands for are read.
    let opts = Options::new().define("NODE_OFFSETS_LIST", "node_offset = abe,10,0");
    let pre = preprocess(&fs, "m.moos".as_ref(), &opts).unwrap();
    let p = parse_moos(&pre.source);
    assert!(p.diagnostics.is_empty(), "{:#?}", p.diagnostics);
    assert_eq!(
        p.value.process("pMarineViewer").unwrap().get("node_offset"),
        Some("abe,10,0")
    );
}

/// A Goby app's block: protobuf text with nested braces, read by the app itself.
const GOBY: &str = "ProcessConfig = pAcommsHandler\n\
{\n\
  common {\n\
    log: false\n\
    verbosity: VERBOSE\n\
  }\n\
  modem_id: 2\n\
  driver_type: DRIVER_WHOI_MICROMODEM\n\
  driver_cfg { serial_port: \"/dev/ttyUSB0\" }\n\
  queue_cfg\n\
  {\n\
    message_entry {\n\
      protobuf_name: \"NavReport\"\n\
      role { type: SOURCE_ID field: \"src\" }\n\
    }\n\
  }\n\
  translator_entry {\n\
    trigger { type: TRIGGER_PUBLISH moos_var: \"NAV_REPORT_OUT\" }\n\
  }\n\
}\n\
\n\
ProcessConfig = pNodeReporter\n\
{\n\
  platform_type = kayak\n\
}\n";

#[test]
fn goby_blocks_are_balanced_and_not_checked_line_by_line() {
    let (m, d) = parse(GOBY);
    assert!(d.is_empty(), "{d:#?}");
    let names: Vec<&str> = m.processes.iter().map(|p| p.name.as_str()).collect();
    assert_eq!(names, ["pAcommsHandler", "pNodeReporter"]);
    assert!(m.processes[0].entries.is_empty());
    assert_eq!(
        m.process("pNodeReporter").unwrap().get("platform_type"),
        Some("kayak")
    );
    // Also under an alias given by the ANTLER block.
    let aliased = format!(
        "ProcessConfig = ANTLER\n{{\n  Run = pAcommsHandler @ NewConsole = false ~ acomms\n}}\n{}",
        GOBY.replace("= pAcommsHandler", "= acomms")
    );
    let (m, d) = parse(&aliased);
    assert!(d.is_empty(), "{d:#?}");
    assert_eq!(m.processes.len(), 3);
}

#[test]
fn nested_braces_in_a_known_program_are_balanced_with_one_warning() {
    let (m, d) = parse(
        "ProcessConfig = pHelmIvP\n{\n  behaviors = a.bhv\n  extra {\n    x = 1\n  }\n  \
         domain = course:0:359:360\n}\nProcessConfig = pLogger\n{\n  AsyncLog = true\n}\n",
    );
    assert_eq!(warnings(&d), [(4, DiagnosticKind::UnexpectedLine)]);
    let helm = m.process("pHelmIvP").unwrap();
    assert_eq!(helm.get("domain"), Some("course:0:359:360"));
    assert_eq!(helm.get("x"), None);
    assert_eq!(m.process("pLogger").unwrap().get("asynclog"), Some("true"));
}

#[test]
fn unknown_programs_keep_their_entries_and_known_aliases_are_checked() {
    // An app coug does not know: its `key = value` lines are entries, nothing is reported.
    let (m, d) = parse("ProcessConfig = iGPS_Custom\n{\n  PORT = /dev/ttyS0\n  raw line\n}\n");
    assert!(d.is_empty(), "{d:#?}");
    assert_eq!(
        m.process("iGPS_Custom").unwrap().get("port"),
        Some("/dev/ttyS0")
    );
    // A known program under an ANTLER alias is checked.
    let (_, d) = parse(
        "ProcessConfig = ANTLER\n{\n  Run = uTimerScript @ NewConsole = false ~ uTS_2\n}\n\
         ProcessConfig = uTS_2\n{\n  paused false\n}\n",
    );
    assert_eq!(warnings(&d), [(7, DiagnosticKind::MissingEquals)]);
}

#[test]
fn blocks_moos_cannot_find_stay_errors() {
    // No `{` after ProcessConfig: MOOS does not find the block, the app gets no configuration.
    let (_, d) = parse("ProcessConfig = pShare\n  input = x\n}\n");
    assert_eq!(d.len(), 1, "{d:#?}");
    assert_eq!(
        (d[0].severity, d[0].kind),
        (Severity::Error, DiagnosticKind::MissingOpenBrace)
    );
    // Never closed, also when nested braces swallow the end.
    let (_, d) = parse("ProcessConfig = pShare\n{\n  a {\n  input = x\n}\n");
    assert!(
        d.iter()
            .any(|x| x.is_error() && x.kind == DiagnosticKind::UnterminatedBlock),
        "{d:#?}"
    );
    // A stray `{` or `}` outside any block is skipped by MOOS: a warning.
    let (_, d) = parse("{\nServerPort = 9000\n}\n");
    assert_eq!(
        warnings(&d),
        [
            (1, DiagnosticKind::UnexpectedLine),
            (3, DiagnosticKind::UnexpectedCloseBrace)
        ]
    );
}
