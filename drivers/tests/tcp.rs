//! The TCP drivers end to end over loopback (127.0.0.1, port 0), against tiny scripted fake
//! servers built from the `devices` encoders: gpsd (WATCH, then reports; a hang-up and a
//! reconnection), the DVL A50 (garbage, an oversize line, reports, a command and its
//! response), and a peer that stalls (never reads, never writes). Every wait is bounded;
//! nothing about timing is asserted.

mod common;

use std::io::{BufRead, BufReader, Write};
use std::net::{TcpListener, TcpStream};
use std::sync::mpsc;
use std::time::{Duration, Instant};

use common::{BOUND, Stepper, tcp};
use devices::a50::{self, Command, Config, Response, VelocityReport};
use devices::nmea::gpsd::{Satellite, Sky, Tpv};
use drivers::dvl::{Dvl, DvlConfig};
use drivers::gps::{Gps, Source, WATCH};
use drivers::link::Link;
use drivers::{Driver, Protocol};
use moos_types::Value;

fn read_line(s: &TcpStream) -> String {
    s.set_read_timeout(Some(BOUND)).unwrap();
    let mut r = BufReader::new(s.try_clone().unwrap());
    let mut line = String::new();
    r.read_line(&mut line).unwrap();
    line
}

fn tpv(lat: f64) -> String {
    Tpv {
        mode: 3,
        lat_deg: Some(lat),
        lon_deg: Some(-111.6),
        speed_mps: Some(0.4),
        track_deg: Some(45.0),
        ..Tpv::default()
    }
    .encode()
}

#[test]
fn igps_through_gpsd_with_a_hang_up_and_a_reconnection() {
    let l = TcpListener::bind("127.0.0.1:0").unwrap();
    let port = l.local_addr().unwrap().port();
    let (done_tx, done_rx) = mpsc::channel::<()>();
    let server = std::thread::spawn(move || {
        let mut watches = Vec::new();
        // First connection: WATCH, a SKY and a fix, then the server goes away.
        let (mut s, _) = l.accept().unwrap();
        watches.push(read_line(&s));
        let sky = Sky {
            hdop: Some(0.8),
            satellites: (1..=6)
                .map(|prn| Satellite {
                    prn,
                    used: prn <= 5,
                    ..Satellite::default()
                })
                .collect(),
            ..Sky::default()
        };
        s.write_all(b"{\"class\":\"VERSION\",\"release\":\"3.25\",\"proto_major\":3}\n")
            .unwrap();
        s.write_all(sky.encode().as_bytes()).unwrap();
        s.write_all(tpv(40.07).as_bytes()).unwrap();
        drop(s);
        // It comes back: the driver watches again.
        let (mut s, _) = l.accept().unwrap();
        watches.push(read_line(&s));
        s.write_all(tpv(40.08).as_bytes()).unwrap();
        let _ = done_rx.recv_timeout(BOUND);
        watches
    });
    let grid = vehicle::geodesy::LocalGrid::new(40.07, -111.6).unwrap();
    let mut d = Driver::new(
        Gps::new(Source::Gpsd, Some(grid)),
        tcp("127.0.0.1", port),
        1.0,
    );
    d.start().unwrap();
    let mut s = Stepper::new(0.0);
    s.until(&mut d, "two fixes", |s, _| s.count("GPS_FIX") == 2);
    done_tx.send(()).unwrap();
    let watches = server.join().unwrap();
    assert_eq!(watches, [WATCH, WATCH]);
    assert_eq!(s.doubles("GPS_LAT"), [40.07, 40.08]);
    assert_eq!(s.doubles("GPS_FIX"), [1.0, 1.0]);
    assert_eq!(
        s.doubles("GPS_SATELLITES"),
        [5.0, 5.0],
        "the last SKY's used satellites"
    );
    assert_eq!(s.doubles("GPS_HDOP"), [0.8, 0.8]);
    let x = s.doubles("GPS_X");
    let y = s.doubles("GPS_Y");
    assert!(
        x[0].abs() < 1e-6 && y[0].abs() < 1e-6,
        "at the origin: {x:?} {y:?}"
    );
    assert!((y[1] - 1110.0).abs() < 10.0, "0.01° north: {y:?}");
    assert_eq!(s.doubles("GPS_SPEED"), [0.4, 0.4]);
    let c = d.counters();
    assert_eq!(c.connects, 2, "{c:?}");
    assert!(c.disconnects >= 1, "{c:?}");
}

fn report(vx: f64) -> String {
    VelocityReport {
        time_ms: 100.0,
        time_of_validity_us: Some(1_700_000_000_000_000),
        time_of_transmission_us: Some(1_700_000_000_050_000),
        vel_body_mps: [vx, 0.01, -0.02],
        fom_mps: 0.003,
        covariance: None,
        altitude_m: 6.5,
        transducers: (0..4)
            .map(|id| a50::Transducer {
                id,
                velocity_mps: vx,
                distance_m: 7.5,
                rssi_dbm: -40.0,
                nsd_dbm: -90.0,
                beam_valid: true,
            })
            .collect(),
        velocity_valid: true,
        status: 0,
        format: Some("json_v3.1".into()),
    }
    .encode()
}

#[test]
fn idvl_garbage_then_reports_and_a_checked_command() {
    let l = TcpListener::bind("127.0.0.1:0").unwrap();
    let port = l.local_addr().unwrap().port();
    let (done_tx, done_rx) = mpsc::channel::<()>();
    let server = std::thread::spawn(move || {
        let (mut s, _) = l.accept().unwrap();
        let first = read_line(&s);
        s.write_all(
            Response {
                response_to: "set_config".into(),
                success: true,
                error_message: String::new(),
                result: None,
                format: Some("json_v3.1".into()),
            }
            .encode()
            .as_bytes(),
        )
        .unwrap();
        // Garbage for a while: noise, broken JSON, an oversize line.
        s.write_all(b"\x00\x01\x02 not json at all\n{\"vx\": 1,\n")
            .unwrap();
        s.write_all(&vec![b'x'; a50::MAX_LINE + 10]).unwrap();
        s.write_all(b"\n").unwrap();
        for k in 0..3 {
            s.write_all(report(0.5 + 0.1 * f64::from(k)).as_bytes())
                .unwrap();
        }
        // A command from MOOS: answered with a failure.
        let second = read_line(&s);
        s.write_all(
            Response {
                response_to: "reset_dead_reckoning".into(),
                success: false,
                error_message: "not allowed now".into(),
                result: None,
                format: None,
            }
            .encode()
            .as_bytes(),
        )
        .unwrap();
        let _ = done_rx.recv_timeout(BOUND);
        (first, second)
    });
    let mut d = Driver::new(Dvl::new(DvlConfig::default()), tcp("127.0.0.1", port), 1.0);
    d.start().unwrap();
    let mut s = Stepper::new(0.0);
    s.until(&mut d, "reports", |s, _| s.count("DVL_VALID") == 3);
    s.mail(&mut d, "DVL_RESET_DR", Value::Double(1.0));
    s.until(&mut d, "refusal", |s, _| {
        !s.texts("DVL_COMMAND_ERROR").is_empty()
    });
    done_tx.send(()).unwrap();
    let (first, second) = server.join().unwrap();
    assert_eq!(
        a50::parse_command(first.trim_end().as_bytes()).unwrap(),
        Command::SetConfig(Config {
            acoustic_enabled: Some(false),
            ..Config::default()
        })
    );
    assert_eq!(
        a50::parse_command(second.trim_end().as_bytes()).unwrap(),
        Command::ResetDeadReckoning
    );
    assert_eq!(s.doubles("DVL_VEL_X"), [0.5, 0.6, 0.7]);
    assert_eq!(s.doubles("DVL_VEL_Z"), [-0.02; 3]);
    assert_eq!(s.doubles("DVL_ALTITUDE"), [6.5; 3]);
    assert_eq!(s.doubles("DVL_ACOUSTIC_ENABLED"), [0.0]);
    assert_eq!(
        s.texts("DVL_COMMAND_ERROR"),
        ["reset_dead_reckoning: not allowed now"]
    );
    let st = d.protocol.stats();
    assert_eq!(st.parse_errors, 2, "{st:?}");
    assert_eq!(st.oversize, 1, "{st:?}");
    assert!(s.warnings.iter().any(|w| w.contains("not allowed now")));
}

#[test]
fn a_stalled_peer_never_blocks_the_app_and_is_dropped_after_the_stall_timeout() {
    // A peer that accepts and then neither reads nor writes.
    let l = TcpListener::bind("127.0.0.1:0").unwrap();
    let port = l.local_addr().unwrap().port();
    let (done_tx, done_rx) = mpsc::channel::<()>();
    let server = std::thread::spawn(move || {
        let mut held = Vec::new();
        l.set_nonblocking(true).unwrap();
        let end = Instant::now() + BOUND;
        while done_rx.try_recv().is_err() && Instant::now() < end {
            if let Ok((s, _)) = l.accept() {
                held.push(s);
            }
            std::thread::sleep(Duration::from_millis(5));
        }
        held.len()
    });

    // The link alone: sends far beyond what the socket buffers hold all return at once;
    // what cannot go is dropped and counted.
    let mut cfg = tcp("127.0.0.1", port);
    cfg.write_timeout = Duration::from_millis(50);
    cfg.tx_capacity = 4;
    let link = Link::open(cfg).unwrap();
    let end = Instant::now() + BOUND;
    while !link.connected() {
        assert!(Instant::now() < end, "no connection");
        std::thread::sleep(Duration::from_millis(5));
    }
    let mut refused = 0;
    let end = Instant::now() + BOUND;
    while link.counters().write_timeouts == 0 {
        assert!(Instant::now() < end, "no write timed out");
        if !link.send(vec![b'z'; 64 * 1024]) {
            refused += 1;
            std::thread::sleep(Duration::from_millis(1));
        }
    }
    assert!(refused > 0, "a full send queue refuses at once");
    let c = link.counters();
    assert!(c.connected, "a stalled writer is not a lost link: {c:?}");
    assert!(c.tx_dropped >= c.write_timeouts + refused, "{c:?}");
    drop(link);

    // The driver: iterations go on while the peer says nothing; the stall timeout drops the
    // connection and the driver reconnects.
    let mut cfg = tcp("127.0.0.1", port);
    cfg.stall_timeout = Some(Duration::from_millis(200));
    let mut d = Driver::new(Dvl::new(DvlConfig::default()), cfg, 1.0);
    d.start().unwrap();
    let mut s = Stepper::new(0.0);
    for _ in 0..50 {
        s.mail(&mut d, "DVL_GET_CONFIG", Value::Double(1.0));
    }
    s.until(&mut d, "a stall and a reconnection", |_, d| {
        let c = d.counters();
        c.stalls >= 1 && c.connects >= 2
    });
    assert!(s.count("DVL_VALID") == 0);
    let status = s.texts("DVL_DRIVER_STATUS");
    assert!(status.iter().any(|t| t.contains("stalls=1")), "{status:?}");
    // The commands waited (one in flight at a time): no response, so they time out in the
    // DVL's virtual time, never blocking.
    assert!(d.protocol.counts().sent >= 1);
    done_tx.send(()).unwrap();
    // Connections complete in the kernel's backlog before the fake accepts them: its count
    // is not asserted.
    server.join().unwrap();
}
