//! Fuzz the Teensy's `$DEPTH`/`$BATTE`/`$LEAK` telemetry and `$CONTR` command lines: any
//! bytes, split into lines in uneven pieces, never panic, the line counters add up, and what
//! parses re-encodes to a stable wire form (the body is `devices::fuzz::teensy`, also run on
//! stable by `devices/tests/fuzz.rs`).
#![no_main]

use libfuzzer_sys::fuzz_target;

fuzz_target!(|data: &[u8]| devices::fuzz::teensy(data));
