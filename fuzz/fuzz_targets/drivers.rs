//! Fuzz the drivers' protocol state machines (iGPS over NMEA and gpsd, iDVL, iSeaTrac,
//! iTeensy): any bytes at any times after a connection never panic and every link's counters
//! add up (the body is `drivers::fuzz::protocols`, also run on stable by
//! `drivers/tests/fuzz.rs`).
#![no_main]

use libfuzzer_sys::fuzz_target;

fuzz_target!(|data: &[u8]| drivers::fuzz::protocols(data));
