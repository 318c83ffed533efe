//! Fuzz the nsplug preprocessor: the input is split into a top file and an included file
//! (at the first NUL byte), preprocessed leniently and strictly; it must never panic or hang.
#![no_main]

use libfuzzer_sys::fuzz_target;
use mission::nsplug::{Options, preprocess};
use mission::source::MemorySource;

fuzz_target!(|data: &[u8]| {
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
});
