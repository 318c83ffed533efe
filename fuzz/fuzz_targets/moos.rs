//! Fuzz the .moos parser (after preprocessing) and its ANTLER `Run` reader
//! (the body is `mission::fuzz::moos`, also run on stable by `mission/tests/fuzz.rs`).
#![no_main]

use libfuzzer_sys::fuzz_target;

fuzz_target!(|data: &[u8]| mission::fuzz::moos(data));
