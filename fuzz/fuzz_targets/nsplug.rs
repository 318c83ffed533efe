//! Fuzz the nsplug preprocessor: the input is split into a top file and an included file
//! (at the first NUL byte), preprocessed leniently and strictly; it must never panic or hang
//! (the body is `mission::fuzz::nsplug`, also run on stable by `mission/tests/fuzz.rs`).
#![no_main]

use libfuzzer_sys::fuzz_target;

fuzz_target!(|data: &[u8]| mission::fuzz::nsplug(data));
