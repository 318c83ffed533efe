//! Fuzz the SeaTrac X150's ASCII-hex frames in both directions (CRC16, STATUS, PING, DAT,
//! ACOFIX): any bytes, split into lines in uneven pieces, never panic, the line counters add
//! up, and what decodes re-encodes to a stable wire form (the body is
//! `devices::fuzz::seatrac`, also run on stable by `devices/tests/fuzz.rs`).
#![no_main]

use libfuzzer_sys::fuzz_target;

fuzz_target!(|data: &[u8]| devices::fuzz::seatrac(data));
