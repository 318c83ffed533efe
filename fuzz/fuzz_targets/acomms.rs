//! Fuzz the fleet's acoustic message receiver: arbitrary payloads must be refused and counted,
//! never panic, and whatever is accepted must re-encode to the same bytes (the body is
//! `acomms::fuzz::receive`, also run on stable by `acomms/tests/fuzz.rs`).
#![no_main]

use libfuzzer_sys::fuzz_target;

fuzz_target!(|data: &[u8]| acomms::fuzz::receive(data));
