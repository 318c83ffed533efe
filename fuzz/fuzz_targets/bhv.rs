//! Fuzz the .bhv parser and the condition parser; re-parse the canonical print.
#![no_main]

use libfuzzer_sys::fuzz_target;
use mission::bhv::parse_bhv;
use mission::condition::{moos_compat, parse_condition};
use mission::source::SourceMap;

fuzz_target!(|data: &[u8]| {
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
});
