//! The wire protocols of the CougUV's devices as pure codecs (issue #15, part 1): parsers and
//! encoders with no I/O, no async runtime and no clock (times are arguments or fields), shared
//! by the drivers (`iGPS`, `iDVL`, `iSeaTrac`, `iTeensy`) and by the device emulators.
//!
//! - [`line`]: the bounded line accumulator every protocol reads through, with its counters
//!   ([`line::LinkStats`]: garbage bytes, oversize lines, bad checksums, parse errors).
//! - [`nmea`]: NMEA 0183 GGA, RMC and VTG with checksums, and gpsd's JSON TPV and SKY.
//! - [`a50`]: the Water Linked DVL A50's newline-delimited JSON (velocity and dead-reckoning
//!   reports, commands and their responses).
//! - [`seatrac`]: the SeaTrac X150's ASCII-hex frames with their CRC16 and the messages the
//!   CoUGARs driver uses (alive, settings, status, PING, DAT, the acoustic fix).
//! - [`teensy`]: the Teensy's ASCII serial link (`$CONTR` out, `$DEPTH`, `$BATTE`, `$LEAK` in)
//!   and pressure to depth.
//! - [`fuzz`]: one fuzz body per protocol, run on stable by `tests/fuzz.rs`.
//! - [`samples`]: a typical message of each device on the wire, for benches and examples.
//!
//! No function here panics on any input: every parser returns a typed error.
//!
//! ```
//! use devices::line::LineSplitter;
//! let mut lines = LineSplitter::new(82).with_starts(b"$");
//! let mut got = Vec::new();
//! lines.push(b"noise$GPVTG,054.7,T,034.4,M,005.5,N,010.2,K*48\r\n", |l| {
//!     got.push(devices::nmea::parse(l).map(|s| s.kind()))
//! });
//! assert_eq!(got, vec![Ok("VTG")]);
//! assert_eq!(lines.stats().garbage_bytes, 5);
//! ```

#![warn(missing_docs)]

pub mod a50;
pub mod fuzz;
pub mod line;
pub mod nmea;
pub mod samples;
pub mod seatrac;
pub mod teensy;
