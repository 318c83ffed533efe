//! The serial drivers end to end over pseudo-terminals, against tiny scripted fake devices
//! built from the `devices` encoders: values posted with their names and units, garbage for a
//! while, a device that disappears and returns (a udev-style symlink pointed at a new pty).
//! Every wait is bounded; nothing about timing is asserted.

mod common;

use std::time::Duration;

use common::{Pty, Stepper, point, scratch, serial};
use devices::seatrac::{self, Command, Cst, Response};
use devices::teensy::Telemetry;
use drivers::gps::{Gps, Source};
use drivers::seatrac::{SeaTrac, SeaTracConfig, blank_settings};
use drivers::teensy::{Teensy, TeensyConfig};
use drivers::{Driver, Protocol};
use moos_types::Value;

/// Deterministic junk: a linear congruential generator's bytes.
fn junk(n: usize, seed: u32) -> Vec<u8> {
    let mut x = seed;
    (0..n)
        .map(|_| {
            x = x.wrapping_mul(1_664_525).wrapping_add(1_013_904_223);
            (x >> 24) as u8
        })
        .collect()
}

/// `out` is the command `$CONTR,5,0,0,20`, once or repeated (the driver repeats it).
fn assert_contr(out: &[u8]) {
    let text = String::from_utf8_lossy(out);
    assert!(
        !text.is_empty() && text.lines().all(|l| l == "$CONTR,5,0,0,20"),
        "{text:?}"
    );
}

#[test]
fn iteensy_over_a_pty_garbage_then_values_then_a_replug() {
    let dir = scratch("teensy");
    let link = dir.join("teensy");
    let mut dev = Pty::new();
    point(&link, &dev.slave);
    let cfg = TeensyConfig {
        calibration_samples: 3,
        ..TeensyConfig::default()
    };
    let mut d = Driver::new(Teensy::new(cfg), serial(&link), 1.0);
    d.start().unwrap();
    let mut s = Stepper::new(100.0);
    s.until(&mut d, "connect", |_, d| d.status().starts_with("link=up"));
    assert!(d.protocol.calibrating());

    // A device babbling for a while, then a clean end of line.
    dev.write(&junk(3000, 7));
    dev.write(b"\r\n");
    for p in [84_000.0, 84_010.0, 84_020.0] {
        dev.write(
            Telemetry::Depth {
                pressure_pa: p,
                temp_degc: 18.5,
            }
            .encode()
            .as_bytes(),
        );
    }
    dev.write(
        Telemetry::Battery {
            voltage_v: 15.9,
            current_a: 1.2,
        }
        .encode()
        .as_bytes(),
    );
    dev.write(Telemetry::Leak { leak: false }.encode().as_bytes());
    // 2 m of fresh water under the calibrated atmosphere.
    let p2: f64 = 84_010.0 + 2.0 * 997.0 * 9.81;
    dev.write(format!("$DEPTH,{p2:.1},18.4\r\n").as_bytes());
    // The sample that completes the calibration is the first with a depth.
    s.until(&mut d, "telemetry", |s, _| s.count("DEPTH") == 2);
    let pressures = s.doubles("PRESSURE");
    assert_eq!(
        &pressures[pressures.len() - 4..],
        [84_000.0, 84_010.0, 84_020.0, (p2 * 10.0).round() / 10.0]
    );
    assert_eq!(s.doubles("TEENSY_ATM_PRESSURE"), [84_010.0]);
    let depth = s.doubles("DEPTH");
    assert!((depth[0] - 10.0 / (997.0 * 9.81)).abs() < 1e-9, "{depth:?}");
    assert!((depth[1] - 2.0).abs() < 1e-4, "{depth:?}");
    assert_eq!(s.doubles("BATTERY_VOLTAGE"), [15.9]);
    assert_eq!(s.doubles("BATTERY_CURRENT"), [1.2]);
    assert_eq!(s.doubles("LEAK"), [0.0]);
    let st = d.protocol.stats();
    assert!(st.garbage_bytes > 1000, "{st:?}");
    assert!(st.garbage_bytes + st.parse_errors + st.oversize > 0);

    // Commands out.
    s.mail(&mut d, "FIN_TOP_DEG", Value::Double(5.0));
    s.mail(&mut d, "THRUST_PCT", Value::Double(20.0));
    s.step(&mut d);
    let out = dev.read_until(|b| b.ends_with(b"\n"));
    assert_contr(&out);

    // Unplugged: the driver notices, keeps trying; plugged in again on a new pty.
    drop(dev);
    s.until(&mut d, "disconnect", |_, d| {
        d.status().starts_with("link=down")
    });
    let mut dev = Pty::new();
    point(&link, &dev.slave);
    s.until(&mut d, "reconnect", |_, d| d.counters().connects == 2);
    s.until(&mut d, "reconnect seen", |_, d| {
        d.status().starts_with("link=up")
    });
    // The last command is said again to the returned device.
    s.step(&mut d);
    let out = dev.read_until(|b| b.ends_with(b"\n"));
    assert_contr(&out);
    dev.write(Telemetry::Leak { leak: true }.encode().as_bytes());
    s.until(&mut d, "leak", |s, _| s.doubles("LEAK").len() == 2);
    assert_eq!(s.doubles("LEAK"), [0.0, 1.0]);
    let c = d.counters();
    assert!(c.disconnects >= 1 && c.connects == 2, "{c:?}");
    s.until(&mut d, "status", |s, _| {
        s.texts("TEENSY_DRIVER_STATUS")
            .last()
            .is_some_and(|t| t.contains(",leak=2,"))
    });
    let status = s.texts("TEENSY_DRIVER_STATUS");
    assert!(status.iter().any(|t| t.starts_with("link=down")));
    assert!(
        status
            .last()
            .unwrap()
            .starts_with("link=up,state=running,connects=2,")
    );
    let _ = std::fs::remove_dir_all(dir);
}

/// A scripted SeaTrac beacon on the pty's master: answers the start-up sequence, streams
/// STATUS, answers the first DAT_SEND busy and the second OK, then sends a DAT_RECEIVE.
fn fake_beacon(mut dev: Pty) -> std::thread::JoinHandle<Vec<Command>> {
    std::thread::spawn(move || {
        let mut seen = Vec::new();
        let mut pending = Vec::new();
        let mut dat_sends = 0;
        // Noise on the line before anything else, and a frame with a broken CRC.
        dev.write(b"\x00\x13garbage");
        let mut bad = Response::SysAlive { seconds: 9 }.encode();
        bad.replace_range(1..3, "02");
        dev.write(bad.as_bytes());
        while dat_sends < 2 {
            let got = dev.read_until(|b| b.windows(2).any(|w| w == b"\r\n"));
            pending.extend_from_slice(&got);
            while let Some(end) = pending.windows(2).position(|w| w == b"\r\n") {
                let line: Vec<u8> = pending.drain(..end + 2).collect();
                let cmd = Command::decode(&line).expect("a valid command frame");
                let answer = match &cmd {
                    Command::SysAlive => vec![Response::SysAlive { seconds: 12 }],
                    Command::SettingsGet => vec![Response::SettingsGet(blank_settings())],
                    Command::SettingsSet(_) => vec![Response::SettingsSet(Cst::Ok)],
                    Command::SettingsSave => {
                        let mut v = vec![Response::SettingsSave(Cst::Ok)];
                        for k in 0..5 {
                            v.push(Response::Status(seatrac::Status {
                                timestamp_ms: 1000 + 100 * k,
                                environment: Some(seatrac::Environment {
                                    supply_mv: 15_000,
                                    temp_ddegc: 200,
                                    pressure_mbar: 1013,
                                    depth_dm: 3,
                                    vos_dmps: 14_800,
                                }),
                                attitude: Some(seatrac::Attitude {
                                    yaw_ddeg: 900,
                                    pitch_ddeg: 20,
                                    roll_ddeg: -5,
                                }),
                                mag_cal: None,
                                acc_cal: None,
                                ahrs_raw: None,
                                ahrs_comp: Some(seatrac::AhrsComp {
                                    acc: [0.0, 0.0, 1.0],
                                    mag: [0.0; 3],
                                    gyro: [0.0, 0.0, 1.5],
                                }),
                            }));
                        }
                        v
                    }
                    Command::DatSend { dest_id, data, .. } => {
                        dat_sends += 1;
                        if dat_sends == 1 {
                            vec![Response::DatSend {
                                status: Cst::XcvrBusy,
                                beacon_id: *dest_id,
                            }]
                        } else {
                            vec![
                                Response::DatSend {
                                    status: Cst::Ok,
                                    beacon_id: *dest_id,
                                },
                                Response::DatReceive {
                                    fix: seatrac::AcoFix {
                                        dest_id: 1,
                                        src_id: *dest_id,
                                        msg_type: seatrac::msg_type::OWAYU,
                                        attitude: seatrac::Attitude::default(),
                                        depth_local_dm: 3,
                                        vos_dmps: 14_800,
                                        rssi_cb: -700,
                                        range: None,
                                        usbl: Some(seatrac::Usbl {
                                            rssi_cb: vec![-700; 4],
                                            azimuth_ddeg: 1800,
                                            elevation_ddeg: 50,
                                            fit_error_centi: 5,
                                        }),
                                        position: None,
                                        position_enhanced: false,
                                        position_flt_error: false,
                                    },
                                    ack: false,
                                    data: data.iter().rev().copied().collect(),
                                },
                            ]
                        }
                    }
                    _ => Vec::new(),
                };
                seen.push(cmd);
                for a in answer {
                    dev.write(a.encode().as_bytes());
                }
            }
        }
        // Hold the line open a moment so the last frames are read before the hang-up.
        std::thread::sleep(Duration::from_millis(200));
        seen
    })
}

#[test]
fn iseatrac_over_a_pty_start_up_status_and_dat() {
    let dir = scratch("seatrac");
    let link = dir.join("seatrac");
    let dev = Pty::new();
    point(&link, &dev.slave);
    let cfg = SeaTracConfig {
        beacon_id: 1,
        declination_deg: 10.7,
        ..SeaTracConfig::default()
    };
    let mut d = Driver::new(SeaTrac::new(cfg), serial(&link), 1.0);
    d.start().unwrap();
    let beacon = fake_beacon(dev);
    let mut s = Stepper::new(0.0);
    s.until(&mut d, "start-up", |_, d| d.protocol.state() == "running");
    s.until(&mut d, "status", |s, _| s.count("AHRS_HEADING") == 5);
    let h = s.doubles("AHRS_HEADING");
    assert!(h.iter().all(|h| (h - 100.7).abs() < 1e-9), "{h:?}");
    assert_eq!(s.doubles("AHRS_PITCH")[0], 2.0);
    assert_eq!(s.doubles("AHRS_ROLL")[0], -0.5);
    // The chip's z axis points up in the 45° mount: its +1.5 deg/s is a turn to port.
    assert_eq!(s.doubles("AHRS_YAW_RATE")[0], -1.5);
    assert_eq!(s.doubles("SEATRAC_DEPTH")[0], 0.3);
    assert_eq!(s.doubles("SEATRAC_SUPPLY_VOLTAGE")[0], 15.0);
    assert_eq!(s.doubles("SEATRAC_BEACON_ID"), [1.0]);

    s.mail(
        &mut d,
        "ACOMMS_TX",
        Value::String("dest=2,hex=010203".into()),
    );
    s.until(&mut d, "dat", |s, _| !s.texts("ACOMMS_RX").is_empty());
    assert_eq!(s.texts("ACOMMS_TX_ACK"), ["dest=2,cid=DAT_SEND"]);
    assert_eq!(s.texts("ACOMMS_RX"), ["src=2,dest=1,ack=0,hex=030201"]);
    assert_eq!(s.doubles("USBL_AZIMUTH"), [180.0]);
    assert_eq!(s.doubles("USBL_ELEVATION"), [5.0]);
    let seen = beacon.join().unwrap();
    let dats = seen
        .iter()
        .filter(|c| matches!(c, Command::DatSend { .. }))
        .count();
    assert_eq!(dats, 2, "sent again after XCVR_BUSY");
    let st = d.protocol.stats();
    assert_eq!(st.garbage_bytes, 9, "{st:?}");
    assert_eq!(st.bad_checksum, 1, "{st:?}");
    assert_eq!(d.protocol.counts().busy, 1);
    let _ = std::fs::remove_dir_all(dir);
}

#[test]
fn igps_nmea_over_a_pty() {
    let dir = scratch("gps");
    let link = dir.join("gps");
    let mut dev = Pty::new();
    point(&link, &dev.slave);
    let grid = vehicle::geodesy::LocalGrid::new(40.0717976, -111.6002054).unwrap();
    let mut d = Driver::new(
        Gps::new(Source::Nmea, Some(grid.clone())),
        serial(&link),
        1.0,
    );
    d.start().unwrap();
    let mut s = Stepper::new(0.0);
    s.until(&mut d, "connect", |_, d| d.status().starts_with("link=up"));
    // GGA and RMC as the CoUGARs' NMEA constructor writes them for gpsd (§3.3).
    let gga = devices::nmea::with_checksum(
        "GPGGA,171530.00,4004.3079,N,11136.0123,W,1,04,1.5,1367.0,M,0.0,M,,",
    );
    let rmc = devices::nmea::with_checksum(
        "GPRMC,171530.00,A,4004.3079,N,11136.0123,W,1.0,90.0,261126,,,A",
    );
    dev.write(format!("{gga}\r\n{rmc}\r\n").as_bytes());
    s.until(&mut d, "fix", |s, _| s.count("GPS_COURSE") == 1);
    let lat = 40.0 + 4.3079 / 60.0;
    let lon = -(111.0 + 36.0123 / 60.0);
    let (x, y) = grid
        .to_local(s.doubles("GPS_LAT")[0], s.doubles("GPS_LONG")[0])
        .unwrap();
    assert!((s.doubles("GPS_LAT")[0] - lat).abs() < 1e-9);
    assert!((s.doubles("GPS_LONG")[0] - lon).abs() < 1e-9);
    assert_eq!(s.doubles("GPS_X"), [x]);
    assert_eq!(s.doubles("GPS_Y"), [y]);
    assert_eq!(s.doubles("GPS_SATELLITES"), [4.0]);
    assert_eq!(s.doubles("GPS_HDOP"), [1.5]);
    assert_eq!(s.doubles("GPS_FIX"), [1.0]);
    assert!((s.doubles("GPS_SPEED")[0] - 1852.0 / 3600.0).abs() < 1e-12);
    // GPS_FIX closes the epoch: it comes after the position, as uSimSensors posts it.
    let keys: Vec<&str> = s
        .posts
        .iter()
        .map(|(_, p)| &*p.key)
        .filter(|k| k.starts_with("GPS_") && *k != "GPS_DRIVER_STATUS")
        .collect();
    assert_eq!(
        keys[..7],
        [
            "GPS_X",
            "GPS_Y",
            "GPS_LAT",
            "GPS_LONG",
            "GPS_SATELLITES",
            "GPS_HDOP",
            "GPS_FIX"
        ]
    );
    let _ = std::fs::remove_dir_all(dir);
}
