//! nsplug preprocessor: includes (nested, tagged, cycles, missing, search path), macros,
//! conditionals, strict mode.

use mission::diagnostic::{DiagnosticKind, Severity};
use mission::nsplug::{Options, Preprocessed, preprocess};
use mission::source::MemorySource;

fn run(
    fs: &MemorySource,
    top: &str,
    opts: &Options,
) -> Result<Preprocessed, mission::diagnostic::Diagnostic> {
    preprocess(fs, top.as_ref(), opts)
}

fn text(fs: &MemorySource, top: &str, opts: &Options) -> String {
    run(fs, top, opts).expect("preprocess").source.text()
}

#[test]
fn nested_includes_map_lines_back_to_their_files() {
    let fs = MemorySource::new()
        .with("m/top.moos", "a = 1\n#include \"sub/mid.moos\"\nz = 26\n")
        .with("m/sub/mid.moos", "b = 2\n#include leaf.moos\nc = 3\n")
        .with("m/sub/leaf.moos", "// leaf\nleaf = $(V)\n");
    let out = run(&fs, "m/top.moos", &Options::new().define("V", "x")).unwrap();
    assert_eq!(
        out.source.text(),
        "a = 1\nb = 2\n// leaf\nleaf = x\nc = 3\nz = 26\n"
    );
    let origin: Vec<(String, u32)> = out
        .source
        .lines()
        .iter()
        .map(|l| (l.file.name.clone(), l.line))
        .collect();
    assert_eq!(
        origin,
        [
            ("m/top.moos".to_string(), 1),
            ("m/sub/mid.moos".to_string(), 1),
            ("m/sub/leaf.moos".to_string(), 1),
            ("m/sub/leaf.moos".to_string(), 2),
            ("m/sub/mid.moos".to_string(), 3),
            ("m/top.moos".to_string(), 3),
        ]
    );
    // The include chain is kept: leaf was included from mid.moos line 2, itself from top line 2.
    let leaf = &out.source.lines()[3].file;
    let from = leaf.included_from.as_ref().unwrap();
    assert_eq!(
        (from.file.name.as_str(), from.line, from.col),
        ("m/sub/mid.moos", 2, 10)
    );
    assert_eq!(from.file.included_from.as_ref().unwrap().line, 2);
}

#[test]
fn include_path_and_angle_form() {
    let fs = MemorySource::new()
        .with(
            "m/top.moos",
            "#include <common.moos>\n#include plugs.moos <b>\n",
        )
        .with("lib/common.moos", "common = yes\n")
        .with(
            "lib/plugs.moos",
            "<tag><a>\na = 1\n<tag><b>\nb = 2\n#define X 1\nb2 = 3\n<tag><c>\nc = 3\n",
        );
    let mut opts = Options::new();
    opts.include_paths.push("lib".into());
    assert_eq!(
        text(&fs, "m/top.moos", &opts),
        "common = yes\nb = 2\nb2 = 3\n"
    );
    // Without the path the include is missing.
    let err = run(&fs, "m/top.moos", &Options::new()).unwrap_err();
    assert_eq!(err.kind, DiagnosticKind::IncludeNotFound);
    assert_eq!(
        (err.span.file.name.as_str(), err.span.line, err.span.col),
        ("m/top.moos", 1, 10)
    );
}

#[test]
fn include_cycle_is_a_clear_error() {
    let fs = MemorySource::new()
        .with("a.moos", "x = 1\n#include b.moos\n")
        .with("b.moos", "y = 2\n#include ./a.moos\n");
    let err = run(&fs, "a.moos", &Options::new()).unwrap_err();
    assert_eq!(err.kind, DiagnosticKind::IncludeCycle);
    assert_eq!((err.span.file.name.as_str(), err.span.line), ("b.moos", 2));
    assert_eq!(
        err.to_string(),
        "b.moos:2:10: error: #include cycle: a.moos -> b.moos -> a.moos: expected a file that is not already being included, found `./a.moos`"
    );
    assert!(
        err.render().contains("= included from a.moos:2:10"),
        "{}",
        err.render()
    );
    // A file including itself.
    let fs = MemorySource::new().with("self.bhv", "#include self.bhv\n");
    assert_eq!(
        run(&fs, "self.bhv", &Options::new()).unwrap_err().kind,
        DiagnosticKind::IncludeCycle
    );
}

#[test]
fn missing_include_names_file_and_line() {
    let fs = MemorySource::new().with(
        "dir/meta.moos",
        "// header\n\n  #include plug_nothere.moos\n",
    );
    let err = run(&fs, "dir/meta.moos", &Options::new()).unwrap_err();
    assert_eq!(err.kind, DiagnosticKind::IncludeNotFound);
    assert_eq!(
        err.to_string(),
        "dir/meta.moos:3:12: error: cannot find include file `plug_nothere.moos`: expected a file `plug_nothere.moos` beside dir/meta.moos or on the include path (-p), found no such file"
    );
    assert!(
        err.render()
            .ends_with("  3 |   #include plug_nothere.moos\n    |            ^"),
        "{}",
        err.render()
    );
}

#[test]
fn macros_plain_uppercase_defaults_and_define() {
    let fs = MemorySource::new().with(
        "t.moos",
        "#define $(PORT) 9001\n#define EMPTY\nCommunity = %(VNAME)\nname = $(VNAME)\nport = $(PORT)\n\
         warp = $(WARP=10) $(SPD:=2) %(C=red)\ne = [$(EMPTY)]\n",
    );
    let out = run(&fs, "t.moos", &Options::new().define("VNAME", "henry")).unwrap();
    assert_eq!(
        out.source.text(),
        "Community = HENRY\nname = henry\nport = 9001\nwarp = 10 2 RED\ne = []\n"
    );
    assert!(out.diagnostics.is_empty(), "{:?}", out.diagnostics);
    // Command-line style arguments.
    let mut opts = Options::new();
    opts.define_arg("WARP=5");
    opts.define_arg("FLAG");
    let fs = MemorySource::new().with("u.moos", "w = $(WARP=10)\n#ifdef FLAG\nflag = on\n#endif\n");
    assert_eq!(text(&fs, "u.moos", &opts), "w = 5\nflag = on\n");
}

#[test]
fn redefinition_warns_and_overrides() {
    let fs = MemorySource::new().with("t.moos", "#define A 1\n#define A 2\na = $(A)\n");
    let out = run(&fs, "t.moos", &Options::new()).unwrap();
    assert_eq!(out.source.text(), "a = 2\n");
    assert_eq!(out.diagnostics[0].kind, DiagnosticKind::RedefinedMacro);
    assert_eq!(out.diagnostics[0].span.line, 2);
}

#[test]
fn undefined_macro_warns_by_default_and_fails_in_strict_mode() {
    let fs = MemorySource::new().with(
        "t.moos",
        "ok = 1\n  port = $(PORT) and $(KNOWN)\n// $(COMMENTED)\n",
    );
    let opts = Options::new().define("KNOWN", "k");
    let out = run(&fs, "t.moos", &opts).unwrap();
    // As nsplug: the line is kept exactly as written, with a warning.
    assert_eq!(
        out.source.text(),
        "ok = 1\n  port = $(PORT) and $(KNOWN)\n// $(COMMENTED)\n"
    );
    assert_eq!(out.diagnostics.len(), 1, "no warning for a commented line");
    let w = &out.diagnostics[0];
    assert_eq!(
        (w.severity, w.kind, w.span.line, w.span.col),
        (Severity::Warning, DiagnosticKind::UndefinedMacro, 2, 10)
    );
    assert_eq!(w.found.as_deref(), Some("`$(PORT)`"));
    // Lenient: partial expansion.
    let mut lenient = opts.clone();
    lenient.lenient = true;
    assert_eq!(
        run(&fs, "t.moos", &lenient).unwrap().source.lines()[1].text,
        "  port = $(PORT) and k"
    );
    // Strict: an error at the same place.
    let mut strict = opts;
    strict.strict = true;
    let e = run(&fs, "t.moos", &strict).unwrap_err();
    assert_eq!(
        (e.severity, e.kind, e.span.line, e.span.col),
        (Severity::Error, DiagnosticKind::UndefinedMacro, 2, 10)
    );
}

fn branch(src: &str, opts: &Options) -> String {
    let fs = MemorySource::new().with("c.moos", src);
    text(&fs, "c.moos", opts)
}

#[test]
fn ifdef_forms() {
    let src = "#ifdef XMODE SIM\nsim\n#elseifdef XMODE M300\nm300\n#else\nother\n#endif\nafter\n";
    assert_eq!(
        branch(src, &Options::new().define("XMODE", "SIM")),
        "sim\nafter\n"
    );
    assert_eq!(
        branch(src, &Options::new().define("XMODE", "M300")),
        "m300\nafter\n"
    );
    assert_eq!(
        branch(src, &Options::new().define("XMODE", "X")),
        "other\nafter\n"
    );
    assert_eq!(branch(src, &Options::new()), "other\nafter\n");
    // Bare name: defined with a non-empty value.
    let bare = "#ifdef GUI\ngui\n#endif\n";
    assert_eq!(branch(bare, &Options::new().define("GUI", "yes")), "gui\n");
    assert_eq!(branch(bare, &Options::new().define("GUI", "")), "");
    assert_eq!(branch(bare, &Options::new()), "");
    // Value given as another macro's name.
    let indirect = "#ifdef VNAME LEADER\nlead\n#endif\n";
    assert_eq!(
        branch(
            indirect,
            &Options::new()
                .define("VNAME", "abe")
                .define("LEADER", "abe")
        ),
        "lead\n"
    );
    // Disjunction and conjunction.
    let or = "#ifdef A 1 || B 2\nyes\n#endif\n";
    assert_eq!(branch(or, &Options::new().define("B", "2")), "yes\n");
    assert_eq!(branch(or, &Options::new().define("B", "3")), "");
    let and = "#ifdef A 1 && B\nyes\n#endif\n";
    assert_eq!(
        branch(and, &Options::new().define("A", "1").define("B", "")),
        "yes\n"
    );
    assert_eq!(branch(and, &Options::new().define("A", "1")), "");
    // #ifndef: none of the names has a value.
    let ndef = "#ifndef A B\nnone\n#else\nsome\n#endif\n";
    assert_eq!(branch(ndef, &Options::new()), "none\n");
    assert_eq!(branch(ndef, &Options::new().define("B", "1")), "some\n");
    // Nesting, and directives in skipped regions have no effect.
    let nested =
        "#ifdef A\n#define X inner\n#ifdef B\nab\n#else\na\n#endif\n#endif\nx = $(X=none)\n";
    assert_eq!(
        branch(nested, &Options::new().define("A", "1")),
        "a\nx = inner\n"
    );
    assert_eq!(
        branch(nested, &Options::new().define("B", "1")),
        "x = none\n"
    );
    // An earlier true branch stops the chain.
    let chain = "#ifdef A\na\n#elseifdef B\nb\n#elseifdef C\nc\n#endif\n";
    assert_eq!(
        branch(chain, &Options::new().define("A", "1").define("B", "1")),
        "a\n"
    );
    assert_eq!(branch(chain, &Options::new().define("C", "1")), "c\n");
}

#[test]
fn mixed_logic_is_false_with_a_warning_and_an_error_when_strict() {
    let fs = MemorySource::new().with("c.moos", "#ifdef A || B && C\nyes\n#endif\n");
    let opts = Options::new()
        .define("A", "1")
        .define("B", "1")
        .define("C", "1");
    let out = run(&fs, "c.moos", &opts).unwrap();
    assert_eq!(out.source.text(), "");
    assert_eq!(out.diagnostics[0].kind, DiagnosticKind::MixedLogic);
    let mut strict = opts;
    strict.strict = true;
    assert_eq!(
        run(&fs, "c.moos", &strict).unwrap_err().kind,
        DiagnosticKind::MixedLogic
    );
}

#[test]
fn dangling_and_unclosed_conditionals_are_errors() {
    for (src, line, what) in [
        ("a\n#endif\n", 2, "`#endif`"),
        ("#else\n", 1, "`#else`"),
        ("x\n\n   #elseifdef A\n", 3, "`#elseifdef`"),
    ] {
        let fs = MemorySource::new().with("d.moos", src);
        let e = run(&fs, "d.moos", &Options::new()).unwrap_err();
        assert_eq!(
            (e.kind, e.span.line, e.found.as_deref()),
            (DiagnosticKind::DanglingDirective, line, Some(what))
        );
    }
    let fs = MemorySource::new().with("d.moos", "a\n#ifdef A\nb\n");
    let e = run(&fs, "d.moos", &Options::new()).unwrap_err();
    assert_eq!(
        (e.kind, e.span.line),
        (DiagnosticKind::UnterminatedConditional, 2)
    );
    assert_eq!(
        e.expected.as_deref(),
        Some("`#endif` before the end of the file")
    );
}

#[test]
fn missing_top_file_is_an_error_not_a_panic() {
    let e = run(&MemorySource::new(), "nothere.moos", &Options::new()).unwrap_err();
    assert_eq!(e.kind, DiagnosticKind::Unreadable);
}

#[test]
fn quoted_include_names_may_hold_spaces_and_macros() {
    let fs = MemorySource::new()
        .with("top.moos", "#include \"my plugs/$(V)_plug.moos\"\n")
        .with("my plugs/abe_plug.moos", "ok = 1\n");
    let out = run(&fs, "top.moos", &Options::new().define("V", "abe")).unwrap();
    assert_eq!(out.source.text(), "ok = 1\n");
    assert_eq!(out.source.lines()[0].file.name, "my plugs/abe_plug.moos");
}
