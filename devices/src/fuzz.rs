//! One fuzz body per protocol, shared by `tests/fuzz.rs` (stable, bounded by a count with
//! `test_support::fuzz::Campaign`) and any cargo-fuzz target. Each feeds the bytes through
//! the protocol's [`LineSplitter`] in uneven pieces, parses every line, and checks that what
//! parses re-encodes to a stable wire form (encode → decode → encode gives the same bytes)
//! and that the splitter's counters add up. Any input must end without a panic.
//!
//! ```
//! devices::fuzz::nmea(b"$GPVTG,054.7,T,034.4,M,005.5,N,010.2,K*48\r\n$GP\xff*00\r\n");
//! devices::fuzz::a50(b"{\"command\":\"get_config\"}\n{]\n");
//! devices::fuzz::seatrac(b"#01C1C0\r\n$40300F55D0\r\n$zz\r\n");
//! devices::fuzz::teensy(b"$DEPTH,101325.0,10.0\r\n$LEAK,1\r\n$CONTR,1,2,3,4\n");
//! ```

use crate::line::LineSplitter;
use crate::{a50 as dvl, nmea as gps, seatrac as modem, teensy as mcu};

/// Feeds `data` to `splitter` in pieces of 1 to 17 bytes (a fixed pattern), collecting the
/// lines, and checks the counters: every byte is in a line, dropped, or still pending.
fn lines(mut splitter: LineSplitter, data: &[u8]) -> Vec<Vec<u8>> {
    let mut out = Vec::new();
    let mut at = 0;
    let mut step = 1;
    while at < data.len() {
        let end = (at + step).min(data.len());
        splitter.push(&data[at..end], |l| out.push(l.to_vec()));
        at = end;
        step = step % 17 + 1;
    }
    let st = *splitter.stats();
    assert_eq!(st.bytes, data.len() as u64);
    assert_eq!(st.lines, out.len() as u64);
    assert!(st.garbage_bytes <= st.bytes);
    out
}

/// NMEA sentences and gpsd JSON lines.
pub fn nmea(data: &[u8]) {
    for l in lines(LineSplitter::new(gps::MAX_LINE).with_starts(b"$"), data) {
        assert!(l.len() <= gps::MAX_LINE + 1);
        if let Ok(s) = gps::parse(&l) {
            let wire = s.encode();
            let again = gps::parse(wire.as_bytes()).expect("an encoded sentence parses");
            assert_eq!(again.encode(), wire);
        }
    }
    for l in lines(LineSplitter::new(gps::gpsd::MAX_LINE), data) {
        match gps::gpsd::parse(&l) {
            Ok(gps::gpsd::Report::Tpv(t)) => {
                assert_eq!(
                    gps::gpsd::parse(t.encode().as_bytes()),
                    Ok(gps::gpsd::Report::Tpv(t))
                );
            }
            Ok(gps::gpsd::Report::Sky(s)) => {
                assert_eq!(
                    gps::gpsd::parse(s.encode().as_bytes()),
                    Ok(gps::gpsd::Report::Sky(s))
                );
            }
            _ => {}
        }
    }
}

/// DVL A50 JSON lines: reports, responses and commands.
pub fn a50(data: &[u8]) {
    for l in lines(LineSplitter::new(dvl::MAX_LINE), data) {
        if let Ok(m) = dvl::parse(&l) {
            assert_eq!(dvl::parse(m.encode().as_bytes()), Ok(m));
        }
        if let Ok(c) = dvl::parse_command(&l) {
            assert_eq!(dvl::parse_command(c.encode().as_bytes()), Ok(c));
        }
    }
}

/// SeaTrac frames in both directions.
pub fn seatrac(data: &[u8]) {
    for l in lines(LineSplitter::new(modem::MAX_FRAME).with_starts(b"#$"), data) {
        if let Ok(r) = modem::Response::decode(&l) {
            let wire = r.encode();
            let again = modem::Response::decode(wire.as_bytes()).expect("an encoded frame decodes");
            assert_eq!(again.encode(), wire);
        }
        if let Ok(c) = modem::Command::decode(&l) {
            let wire = c.encode().expect("a decoded command encodes");
            assert_eq!(modem::Command::decode(wire.as_bytes()), Ok(c));
        }
    }
}

/// Teensy telemetry and `$CONTR` lines.
pub fn teensy(data: &[u8]) {
    for l in lines(LineSplitter::new(mcu::MAX_LINE).with_starts(b"$"), data) {
        if let Ok(t) = mcu::Telemetry::parse(&l) {
            let wire = t.encode();
            let again = mcu::Telemetry::parse(wire.as_bytes()).expect("encoded telemetry parses");
            assert_eq!(again.encode(), wire);
        }
        if let Ok(c) = mcu::Contr::parse(&l) {
            let wire = c.encode();
            assert!(wire.len() <= mcu::TEENSY_LINE_BUFFER);
            let again = mcu::Contr::parse(wire.as_bytes()).expect("an encoded command parses");
            assert_eq!(again.encode(), wire);
        }
    }
}
