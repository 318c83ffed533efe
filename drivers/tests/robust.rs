//! No protocol state machine panics on any byte stream, any mail or any time: arbitrary bytes
//! in arbitrary pieces, with valid frames mixed in, are counted and the valid ones still read.

use devices::seatrac::Response;
use devices::teensy::Telemetry;
use drivers::dvl::{Dvl, DvlConfig};
use drivers::gps::{Gps, Source};
use drivers::seatrac::{SeaTrac, SeaTracConfig};
use drivers::teensy::{Teensy, TeensyConfig};
use drivers::{Io, Protocol};
use moos_types::Value;
use proptest::prelude::*;

fn protocols() -> Vec<Box<dyn Protocol>> {
    let grid = vehicle::geodesy::LocalGrid::new(40.0, -111.0).ok();
    vec![
        Box::new(Gps::new(Source::Nmea, grid.clone())),
        Box::new(Gps::new(Source::Gpsd, grid)),
        Box::new(Dvl::new(DvlConfig::default())),
        Box::new(SeaTrac::new(SeaTracConfig::default())),
        Box::new(Teensy::new(TeensyConfig::default())),
    ]
}

/// A valid line of each protocol, to splice among the junk.
fn valid_lines() -> Vec<Vec<u8>> {
    vec![
        b"$GPGGA,123519,4807.038,N,01131.000,E,1,08,0.9,545.4,M,46.9,M,,*47\r\n".to_vec(),
        b"{\"class\":\"TPV\",\"mode\":3,\"lat\":40.0,\"lon\":-111.0}\n".to_vec(),
        b"{\"time\":1,\"vx\":0,\"vy\":0,\"vz\":0,\"fom\":0,\"altitude\":1,\"velocity_valid\":true}\n"
            .to_vec(),
        Response::SysAlive { seconds: 3 }.encode().into_bytes(),
        Telemetry::Leak { leak: true }.encode().into_bytes(),
    ]
}

proptest! {
    #![proptest_config(ProptestConfig { cases: 64, .. ProptestConfig::default() })]

    #[test]
    fn any_bytes_any_mail_any_time(
        pieces in prop::collection::vec(
            prop_oneof![
                prop::collection::vec(any::<u8>(), 0..300),
                (0usize..5).prop_map(|k| valid_lines()[k].clone()),
            ],
            0..40,
        ),
        times in prop::collection::vec(-1e9f64..1e9, 1..10),
        mail in prop::collection::vec(("[A-Z_]{3,20}", any::<f64>(), ".{0,40}"), 0..10),
    ) {
        for mut p in protocols() {
            let mut io = Io::default();
            p.on_connect(times[0], &mut io);
            for (k, piece) in pieces.iter().enumerate() {
                let now = times[k % times.len()];
                p.on_bytes(piece, now, &mut io);
                if let Some((key, d, s)) = mail.get(k % mail.len().max(1)) {
                    p.on_mail(key, &Value::Double(*d), now, &mut io);
                    p.on_mail(key, &Value::String(s.clone().into()), now, &mut io);
                    for real in p.subscriptions() {
                        p.on_mail(&real, &Value::String(s.clone().into()), now, &mut io);
                        p.on_mail(&real, &Value::Double(*d), now, &mut io);
                    }
                }
                p.tick(now, &mut io);
            }
            p.on_disconnect(times[0], &mut io);
            let st = p.stats();
            let total: usize = pieces.iter().map(Vec::len).sum();
            prop_assert_eq!(st.bytes, total as u64);
            // Every failed line is a line; garbage is a part of the bytes.
            prop_assert!(st.bad_checksum + st.parse_errors <= st.lines, "{:?}", st);
            prop_assert!(st.garbage_bytes <= st.bytes, "{:?}", st);
            let mut r = String::new();
            p.report(&mut r);
            p.status_extra(&mut r);
        }
    }
}
