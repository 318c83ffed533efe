//! The bodies of the fuzz targets of this crate, shared by the cargo-fuzz binaries
//! (`fuzz/fuzz_targets/{nsplug,moos,bhv}.rs`, nightly) and the bounded stable runs of
//! `tests/fuzz.rs`. Each takes arbitrary bytes and must return without panicking (or
//! hanging): the parsers report diagnostics, never panic.
//!
//! ```
//! mission::fuzz::moos(b"ProcessConfig = a\n{\n  x = $(X\n");
//! mission::fuzz::bhv(b"Behavior = BHV_Waypoint\n{\n  condition = (A = 1\n");
//! mission::fuzz::nsplug(b"#include inc.moos\0#ifdef A 1\n$(V)\n");
//! ```

use crate::bhv::parse_bhv;
use crate::condition::{moos_compat, parse_condition};
use crate::moos::parse_moos;
use crate::nsplug::{Options, preprocess};
use crate::source::{MemorySource, SourceMap};

/// nsplug: the input is split at its first NUL byte into a top file and an included file
/// (also found as `plugs.moos`), preprocessed leniently and strictly with two macros defined.
pub fn nsplug(data: &[u8]) {
    let text = String::from_utf8_lossy(data);
    let (top, inc) = text.split_once('\0').unwrap_or((&text, ""));
    let fs = MemorySource::new()
        .with("top.moos", top)
        .with("inc.moos", inc)
        .with("plugs.moos", inc);
    for strict in [false, true] {
        let mut opts = Options::new().define("A", "1").define("V", "x$(A)");
        opts.strict = strict;
        let _ = preprocess(&fs, "top.moos".as_ref(), &opts);
    }
}

/// The `.moos` parser (its ANTLER `Run` reader, its canonical print and its diagnostics),
/// then nsplug and the parser on the preprocessed text.
pub fn moos(data: &[u8]) {
    let text = String::from_utf8_lossy(data);
    let parsed = parse_moos(&SourceMap::from_text("f.moos", &text));
    let _ = parsed.value.antler_runs();
    let _ = parsed.value.to_string();
    for d in &parsed.diagnostics {
        let _ = d.render();
    }
    let fs = MemorySource::new().with("f.moos", text.as_ref());
    if let Ok(pre) = preprocess(&fs, "f.moos".as_ref(), &Options::new()) {
        let _ = parse_moos(&pre.source);
    }
}

/// The condition parser (and its MOOS-compatible reading), then the `.bhv` parser, its
/// diagnostics, and the parser again on its canonical print.
pub fn bhv(data: &[u8]) {
    let text = String::from_utf8_lossy(data);
    if parse_condition(&text).is_ok() {
        let _ = moos_compat(&text);
    }
    let parsed = parse_bhv(&SourceMap::from_text("f.bhv", &text));
    for d in &parsed.diagnostics {
        let _ = d.render();
    }
    let printed = parsed.value.to_string();
    let _ = parse_bhv(&SourceMap::from_text("f.bhv", &printed));
}
