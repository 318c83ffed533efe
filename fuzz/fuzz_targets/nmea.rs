//! Fuzz the NMEA 0183 parser (GGA, RMC, VTG with checksums) and gpsd's JSON (TPV, SKY): any
//! bytes, split into lines in uneven pieces, never panic, the line counters add up, and what
//! parses re-encodes to a stable wire form (the body is `devices::fuzz::nmea`, also run on
//! stable by `devices/tests/fuzz.rs`).
#![no_main]

use libfuzzer_sys::fuzz_target;

fuzz_target!(|data: &[u8]| devices::fuzz::nmea(data));
