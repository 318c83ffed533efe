//! The fuzz body of the drivers' protocol state machines, shared by `tests/fuzz.rs` (stable,
//! a fixed count of seeded mutants through `test_support::fuzz::Campaign`) and the cargo-fuzz
//! target `fuzz/fuzz_targets/drivers.rs`: any bytes, in uneven pieces, at any times, through
//! every protocol (iGPS over NMEA and over gpsd, iDVL, iSeaTrac, iTeensy) after a connection,
//! with their ticks; nothing panics and the counters add up.
//!
//! ```
//! drivers::fuzz::protocols(b"$GPVTG,054.7,T,034.4,M,005.5,N,010.2,K*48\r\n\xff{\"a\":}\n$40300F55D0\r\n");
//! ```

use crate::dvl::{Dvl, DvlConfig};
use crate::gps::{Gps, Source};
use crate::seatrac::{SeaTrac, SeaTracConfig};
use crate::teensy::{Teensy, TeensyConfig};
use crate::{Io, Protocol};

/// Feeds `data` to each protocol in pieces of 1 to 23 bytes (a fixed pattern), ticking after
/// each piece at a time that the data's own bytes move on (so timeouts and retries run too),
/// and checks what every link reports: each byte counted once, each failed line a line, the
/// status and report written.
pub fn protocols(data: &[u8]) {
    let grid = vehicle::geodesy::LocalGrid::new(40.0717976, -111.6002054).ok();
    let all: Vec<Box<dyn Protocol>> = vec![
        Box::new(Gps::new(Source::Nmea, grid.clone())),
        Box::new(Gps::new(Source::Gpsd, grid)),
        Box::new(Dvl::new(DvlConfig::default())),
        Box::new(SeaTrac::new(SeaTracConfig::default())),
        Box::new(Teensy::new(TeensyConfig::default())),
    ];
    for mut p in all {
        let mut io = Io::default();
        let mut now = 0.0;
        p.on_connect(now, &mut io);
        let (mut at, mut step) = (0, 1);
        while at < data.len() {
            let end = (at + step).min(data.len());
            let piece = &data[at..end];
            p.on_bytes(piece, now, &mut io);
            now += f64::from(piece[0] % 8) * 0.25;
            p.tick(now, &mut io);
            at = end;
            step = step % 23 + 1;
        }
        p.on_disconnect(now, &mut io);
        let st = p.stats();
        assert_eq!(st.bytes, data.len() as u64, "{}", p.program());
        assert!(
            st.bad_checksum + st.parse_errors <= st.lines,
            "{}: {st:?}",
            p.program()
        );
        assert!(st.garbage_bytes <= st.bytes, "{}: {st:?}", p.program());
        assert!(
            io.posts.iter().all(|post| !post.key.is_empty()),
            "{}",
            p.program()
        );
        let mut text = String::new();
        p.status_extra(&mut text);
        p.report(&mut text);
    }
}
