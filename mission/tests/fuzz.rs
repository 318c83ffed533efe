//! The fuzz targets of this crate (`mission::fuzz`, run by cargo-fuzz on nightly from
//! `fuzz/`) run on stable: each over its seeds (the real MOOS-IvP mission files of the shared
//! corpus, plus a few nsplug cases) and then over a fixed number of deterministic mutants of
//! them (`test_support::fuzz`), so every `cargo test` fuzzes for a short, bounded time and a
//! failure reproduces exactly.

use std::path::PathBuf;

use test_support::fuzz::Campaign;

/// Mutants of the `.moos` and `.bhv` targets: about three seconds each in a debug build.
const ITERATIONS: usize = 5000;
/// Mutants of the nsplug target (its inputs are smaller): about three seconds too.
const NSPLUG_ITERATIONS: usize = 10_000;

fn files(exts: &[&str]) -> Vec<PathBuf> {
    let files = test_support::files_with_ext(&test_support::mission_file(""), exts);
    assert!(
        files.len() > 60,
        "expected the corpus files, found {files:?}"
    );
    files
}

fn read(p: &PathBuf) -> Vec<u8> {
    std::fs::read(p).unwrap_or_else(|e| panic!("cannot read {}: {e}", p.display()))
}

/// The `.moos` and `.bhv` words and symbols the mutator may insert.
const MISSION_TOKENS: &[&str] = &[
    "ProcessConfig = ",
    "{\n",
    "}\n",
    " = ",
    "//",
    "Run = pHelmIvP @ NewConsole = false ~ pHelmIvP_2\n",
    "Behavior = BHV_Waypoint\n",
    "initialize ",
    "set MODE = ACTIVE {\n",
    "condition = ",
    " and ",
    " or ",
    "!(",
    "\"",
    "$(",
    ")",
    "%(",
    "#include ",
    "#ifdef ",
    "#endif\n",
];

#[test]
fn fuzz_moos_on_the_corpus_and_its_mutants() {
    let seeds: Vec<Vec<u8>> = files(&["moos"]).iter().map(read).collect();
    let r = Campaign::new("moos", seeds)
        .tokens(MISSION_TOKENS)
        .iterations(ITERATIONS)
        .run(mission::fuzz::moos);
    assert_eq!((r.seeds, r.mutants), (348, ITERATIONS), "{r:?}");
    assert!(r.changed > ITERATIONS * 9 / 10, "{r:?}");
}

#[test]
fn fuzz_bhv_on_the_corpus_and_its_mutants() {
    let mut seeds: Vec<Vec<u8>> = files(&["bhv"]).iter().map(read).collect();
    // Conditions alone reach the condition parser whole.
    for c in [
        "(DEPLOY = true) and (RETURN != true)",
        "!(NAV_SPEED > 1.5) or MODE == \"SURVEYING\"",
        "(A = 1) and ((B <= 2) or C:D)",
    ] {
        seeds.push(c.as_bytes().to_vec());
    }
    let r = Campaign::new("bhv", seeds)
        .tokens(MISSION_TOKENS)
        .iterations(ITERATIONS)
        .run(mission::fuzz::bhv);
    assert_eq!((r.seeds, r.mutants), (72, ITERATIONS), "{r:?}");
    assert!(r.changed > ITERATIONS * 9 / 10, "{r:?}");
}

#[test]
fn fuzz_nsplug_on_the_corpus_templates_and_their_mutants() {
    // The body splits its input at the first NUL into `top.moos` and `inc.moos` (also found
    // as `plugs.moos`): each corpus file using nsplug is a top file, and a few hand-made
    // pairs include, define and branch.
    let mut seeds: Vec<Vec<u8>> = files(&["moos", "bhv"])
        .iter()
        .map(read)
        .filter(|t| {
            let t = String::from_utf8_lossy(t);
            t.contains("#include") || t.contains("#ifdef") || t.contains("$(")
        })
        .collect();
    let templates = seeds.len();
    assert!(templates > 100, "only {templates} corpus templates");
    for s in [
        "#include inc.moos\nCommunity = $(V)\n\0ServerPort = $(PORT=9000)\n",
        "#ifdef A 1\nX = %(V)\n#elseifdef B\nY = 2\n#else\nZ = 3\n#endif\n\0",
        "#define W $(V)\n#include \"plugs.moos\" <tag>\n$(W)\n\0<tag>\nP = $(A)\n<tag2>\nQ\n",
        "#include inc.moos\n\0#include top.moos\n",
        "#ifndef NOPE\n#ifdef A || B && C\nT\n#endif\n#endif\n\0",
    ] {
        seeds.push(s.as_bytes().to_vec());
    }
    let r = Campaign::new("nsplug", seeds)
        .tokens(&[
            "#include inc.moos\n",
            "#include \"plugs.moos\"\n",
            "#include top.moos\n",
            "#define ",
            "#ifdef ",
            "#ifndef ",
            "#elseifdef ",
            "#else\n",
            "#endif\n",
            " || ",
            " && ",
            "$(A)",
            "$(V)",
            "%(V)",
            "$(",
            "=",
            ")",
            "<tag>",
            "\0",
            "\n",
        ])
        .iterations(NSPLUG_ITERATIONS)
        .run(mission::fuzz::nsplug);
    assert_eq!(
        (r.seeds, r.mutants),
        (templates + 5, NSPLUG_ITERATIONS),
        "{r:?}"
    );
    assert!(r.changed > NSPLUG_ITERATIONS * 9 / 10, "{r:?}");
}
