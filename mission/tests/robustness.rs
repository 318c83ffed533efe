//! No input makes the preprocessor or the parsers panic (random bytes, and random lines built
//! from the grammar's own tokens, which reach much deeper than bytes).

use mission::bhv::parse_bhv;
use mission::condition::{moos_compat, parse_condition};
use mission::moos::parse_moos;
use mission::nsplug::{Options, preprocess};
use mission::source::{MemorySource, SourceMap};
use proptest::prelude::*;

fn everything(text: &str, other: &str) {
    let map = SourceMap::from_text("f", text);
    let _ = parse_moos(&map);
    let _ = parse_bhv(&map);
    let _ = parse_condition(text);
    let _ = moos_compat(text);
    let fs = MemorySource::new().with("f", text).with("inc.moos", other);
    for strict in [false, true] {
        let mut opts = Options::new().define("A", "1").define("B", "$(A)$(A)");
        opts.strict = strict;
        if let Ok(pre) = preprocess(&fs, "f".as_ref(), &opts) {
            let _ = parse_moos(&pre.source);
            let _ = parse_bhv(&pre.source);
        }
    }
}

const TOKENS: &[&str] = &[
    "{",
    "}",
    "=",
    "==",
    "!=",
    "<",
    ">=",
    "(",
    ")",
    "!",
    "\"",
    "and",
    "or",
    "not",
    "//",
    "\\",
    "#ifdef A",
    "#ifndef B",
    "#else",
    "#elseifdef A 1",
    "#endif",
    "#define",
    "#define C $(C)",
    "#include inc.moos",
    "#include f",
    "#include <inc.moos>",
    "#include inc.moos <t>",
    "<tag><t>",
    "$(A)",
    "%(B)",
    "$(",
    "%(X=",
    "Behavior",
    "BHV_Waypoint",
    "set",
    "MODE",
    "initialize",
    "initialize_",
    "ProcessConfig",
    "ANTLER",
    "Run",
    "@",
    "~",
    ",",
    "condition",
    "x",
    "1.5",
    "-2e3",
    " ",
    "\t",
    "é",
    "\u{0}",
];

fn token_lines() -> impl Strategy<Value = String> {
    prop::collection::vec(
        prop::collection::vec(prop::sample::select(TOKENS), 0..8),
        0..30,
    )
    .prop_map(|lines| {
        lines
            .iter()
            .map(|l| l.join(" "))
            .collect::<Vec<_>>()
            .join("\n")
    })
}

proptest! {
    #![proptest_config(ProptestConfig { cases: 512, failure_persistence: None, ..ProptestConfig::default() })]

    #[test]
    fn random_bytes_never_panic(a in prop::collection::vec(any::<u8>(), 0..600),
                                b in prop::collection::vec(any::<u8>(), 0..200)) {
        everything(&String::from_utf8_lossy(&a), &String::from_utf8_lossy(&b));
    }

    #[test]
    fn random_token_lines_never_panic(a in token_lines(), b in token_lines()) {
        everything(&a, &b);
    }
}

#[test]
fn deep_nesting_is_an_error_not_a_stack_overflow() {
    let deep = format!("{}A = 1{}", "(".repeat(100_000), ")".repeat(100_000));
    let e = parse_condition(&deep).unwrap_err();
    assert!(e.expected.contains("nested"), "{e}");
    let nots = format!("{}(A = 1)", "!".repeat(100_000));
    assert!(parse_condition(&nots).is_err());
    // Within the limit it parses.
    let ok = format!("{}A = 1{}", "(".repeat(40), ")".repeat(40));
    assert!(parse_condition(&ok).is_ok());
}

#[test]
fn self_referencing_macros_terminate() {
    let fs = MemorySource::new().with("f", "v = $(LOOP) %(LOOP)\n");
    let out = preprocess(
        &fs,
        "f".as_ref(),
        &Options::new().define("LOOP", "x$(LOOP)"),
    )
    .unwrap();
    assert_eq!(out.source.lines().len(), 1);
}
