//! Fuzz the .moos parser (after preprocessing) and its ANTLER `Run` reader.
#![no_main]

use libfuzzer_sys::fuzz_target;
use mission::moos::parse_moos;
use mission::nsplug::{Options, preprocess};
use mission::source::{MemorySource, SourceMap};

fuzz_target!(|data: &[u8]| {
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
});
