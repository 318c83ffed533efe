//! Fuzz the MOOS packet decoder: arbitrary bytes must never panic, and whatever decodes must
//! re-encode to the same bytes (apart from the ignored compression flag)
//! (the body is `moos_wire::fuzz::moos_packet`, also run on stable by
//! `moos-wire/tests/fuzz.rs`).
#![no_main]

use libfuzzer_sys::fuzz_target;

fuzz_target!(|data: &[u8]| moos_wire::fuzz::moos_packet(data));
