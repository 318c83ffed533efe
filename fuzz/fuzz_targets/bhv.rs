//! Fuzz the .bhv parser and the condition parser; re-parse the canonical print
//! (the body is `mission::fuzz::bhv`, also run on stable by `mission/tests/fuzz.rs`).
#![no_main]

use libfuzzer_sys::fuzz_target;

fuzz_target!(|data: &[u8]| mission::fuzz::bhv(data));
