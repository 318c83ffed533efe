//! Fuzz the DVL A50's JSON lines (reports, responses and commands): any bytes, split into
//! lines in uneven pieces, never panic, the line counters add up, and what parses re-encodes
//! to a stable wire form (the body is `devices::fuzz::a50`, also run on stable by
//! `devices/tests/fuzz.rs`).
#![no_main]

use libfuzzer_sys::fuzz_target;

fuzz_target!(|data: &[u8]| devices::fuzz::a50(data));
