//! A driver against its device's emulator (crate `emulate`), over a pseudo-terminal or a
//! loopback TCP port (the A50): the real driver path with no hardware. The emulator measures
//! the truth it is fed; the driver must post what the sensor models would, and its commands
//! must reach the device. Faults (a disconnection, garbage) come from the emulator's plan, at
//! its times. Every wait is bounded; nothing about timing is asserted.

mod common;

use std::path::PathBuf;

use common::{Stepper, scratch, serial, tcp};
use drivers::dvl::{Dvl, DvlConfig};
use drivers::gps::{Gps, Source};
use drivers::seatrac::{SeaTrac, SeaTracConfig, Startup};
use drivers::teensy::{Teensy, TeensyConfig};
use drivers::{Driver, Protocol};
use emulate::build::{Kind, Options, Settings, spawn};
use emulate::fault::FaultPlan;
use emulate::seatrac::EchoBeacon;
use emulate::transport::Transport;
use emulate::truth::Truth;
use moos_types::Value;

/// One test's emulator: its tokio runtime, the running emulator, and the link a serial
/// driver opens (a pseudo-terminal's symlink in a scratch folder; empty over TCP).
struct Rig {
    rt: tokio::runtime::Runtime,
    emu: emulate::build::Running,
    link: PathBuf,
}

impl Rig {
    /// The `kind` emulator with `settings`, its draws seeded with `seed`, its faults `faults`:
    /// on a pseudo-terminal behind a link in the scratch folder `test`, or with `None` on a
    /// loopback TCP port.
    fn start(
        test: Option<&str>,
        kind: Kind,
        settings: Settings,
        seed: u64,
        faults: FaultPlan,
    ) -> Rig {
        let rt = tokio::runtime::Runtime::new().unwrap();
        let (link, transport) = match test {
            Some(t) => {
                let link = scratch(t).join("device");
                let transport = Transport::Pty {
                    link: Some(link.clone()),
                };
                (link, transport)
            }
            None => (PathBuf::new(), Transport::loopback(0)),
        };
        let options = Options {
            seed,
            faults,
            ..Options::default()
        };
        let emu = rt
            .block_on(spawn(kind, settings, transport, options))
            .unwrap();
        Rig { rt, emu, link }
    }

    /// The emulator's TCP address.
    fn addr(&self) -> std::net::SocketAddr {
        self.emu.handle.endpoint().tcp().expect("a TCP endpoint")
    }

    /// Stops the emulator.
    fn stop(self) {
        self.rt.block_on(self.emu.handle.stop()).unwrap();
    }
}

/// iTeensy on `link`. The test's MOOS time runs faster than the emulator's 20 Hz (0.05 s a
/// step, a couple of milliseconds apart): a long calibration timeout, so the samples decide,
/// not the clock.
fn iteensy(link: &std::path::Path) -> Driver<Teensy> {
    let cfg = TeensyConfig {
        calibration_samples: 5,
        calibration_timeout_s: 1e6,
        ..TeensyConfig::default()
    };
    Driver::new(Teensy::new(cfg), serial(link), 1.0)
}

/// iGPS reading NMEA on `link`, projecting on the emulator's default origin.
fn igps(link: &std::path::Path) -> Driver<Gps> {
    let (lat0, lon0) = Settings::default().gps.origin_lat_lon;
    let grid = vehicle::geodesy::LocalGrid::new(lat0, lon0).unwrap();
    Driver::new(Gps::new(Source::Nmea, Some(grid)), serial(link), 1.0)
}

/// The NMEA GPS emulator on a pseudo-terminal in the scratch folder `test` with the vehicle
/// at the surface 30 m east and 40 m north of its origin, and iGPS reading it, started.
fn gps_at_30_40(test: &str, seed: u64, faults: FaultPlan) -> (Rig, Driver<Gps>, Stepper) {
    let rig = Rig::start(Some(test), Kind::Gps, Settings::default(), seed, faults);
    let mut d = igps(&rig.link);
    rig.emu.truth.feed(Truth {
        x: 30.0,
        y: 40.0,
        ..Truth::default()
    });
    d.start().unwrap();
    (rig, d, Stepper::new(0.0))
}

/// Every fix `(xs, ys)` within a few sigma of the emulated receiver's noise (1.5 m x HDOP
/// per axis) of (30, 40).
fn near_30_40(xs: &[f64], ys: &[f64]) {
    for (x, y) in xs.iter().zip(ys) {
        assert!(
            (x - 30.0).abs() < 10.0 && (y - 40.0).abs() < 10.0,
            "({x}, {y})"
        );
    }
}

#[test]
fn iteensy_against_the_teensy_emulator_depth_battery_and_fin_commands() {
    let rig = Rig::start(
        Some("against-teensy"),
        Kind::Teensy,
        Settings::default(),
        7,
        FaultPlan::default(),
    );
    // At the surface first: the driver calibrates the atmosphere there.
    rig.emu.truth.feed(Truth::default());
    let port = rig.emu.teensy.clone().expect("the Teensy's port");
    let mut d = iteensy(&rig.link);
    d.start().unwrap();
    let mut s = Stepper::new(100.0);
    s.until(&mut d, "calibrated at the surface", |s, _| {
        s.count("TEENSY_ATM_PRESSURE") == 1
    });
    let atm = s.doubles("TEENSY_ATM_PRESSURE")[0];
    // The emulated sensor's air (101325 Pa, as uSimSensors), not the driver's fallback
    // (87250 Pa, Utah Lake's altitude).
    assert!((atm - 101_325.0).abs() < 200.0, "atmosphere {atm} Pa");

    // Then 3 m down: the emulated MS5837 reads it, the driver posts the depth.
    rig.emu.truth.feed(Truth {
        depth: 3.0,
        ..Truth::default()
    });
    s.until(&mut d, "a depth near 3 m", |s, _| {
        s.doubles("DEPTH")
            .iter()
            .rev()
            .take(5)
            .filter(|z| (**z - 3.0).abs() < 0.1)
            .count()
            == 5
    });
    let v = s.doubles("BATTERY_VOLTAGE");
    assert!(v.last().is_some_and(|v| *v > 10.0 && *v < 20.0), "{v:?}");
    assert_eq!(s.doubles("LEAK").last(), Some(&0.0));

    // pCougControls' outputs become a $CONTR the device accepts.
    s.mail(&mut d, "FIN_TOP_DEG", Value::Double(5.0));
    s.mail(&mut d, "FIN_STBD_DEG", Value::Double(-3.0));
    s.mail(&mut d, "FIN_PORT_DEG", Value::Double(2.0));
    s.mail(&mut d, "THRUST_PCT", Value::Double(20.0));
    s.until(&mut d, "the command reaches the Teensy", |_, _| {
        port.get()
            .last
            .is_some_and(|(_, c)| c.fins_deg == [5.0, -3.0, 2.0] && c.thrust_pct == 20)
    });
    assert_eq!(port.get().refused, 0);
    let st = d.protocol.stats();
    assert_eq!(st.bad_checksum + st.oversize + st.parse_errors, 0, "{st:?}");
    rig.stop();
}

#[test]
fn igps_against_the_nmea_gps_emulator_fixes_at_the_surface_none_under_water() {
    let (rig, mut d, mut s) = gps_at_30_40("against-gps", 3, FaultPlan::default());
    s.until(&mut d, "five fixes", |s, _| {
        s.doubles("GPS_FIX").iter().filter(|f| **f == 1.0).count() >= 5
    });
    let (xs, ys) = (s.doubles("GPS_X"), s.doubles("GPS_Y"));
    assert!(xs.len() >= 5 && xs.len() == ys.len());
    near_30_40(&xs, &ys);
    // Satellites in view once fixed (zero while the receiver was acquiring).
    let sats = s.doubles("GPS_SATELLITES");
    assert!(sats.last().is_some_and(|n| *n >= 4.0), "{sats:?}");

    // Under water the antenna hears nothing: no more fixes, the driver says so.
    rig.emu.truth.feed(Truth {
        x: 30.0,
        y: 40.0,
        depth: 3.0,
        ..Truth::default()
    });
    s.until(&mut d, "the fix lost", |s, _| {
        s.doubles("GPS_FIX").last() == Some(&0.0)
    });
    assert_eq!(d.protocol.stats().bad_checksum, 0);
    rig.stop();
}

/// The number after `key=` in a status line (`DVL_DRIVER_STATUS` and the like).
fn field(status: &str, key: &str) -> Option<u64> {
    status
        .split(',')
        .find_map(|kv| kv.strip_prefix(key)?.strip_prefix('='))
        .and_then(|v| v.parse().ok())
}

/// 10 m down, heading east at 1 m/s, level, over the A50 emulator's flat bottom at 30 m.
fn cruising_east() -> Truth {
    Truth {
        depth: 10.0,
        heading_deg: 90.0,
        vel_east_mps: 1.0,
        speed_mps: 1.0,
        ..Truth::default()
    }
}

#[test]
fn idvl_against_the_a50_emulator_reports_acoustics_and_commands() {
    let mut settings = Settings::default();
    settings.dvl.gyro_calibration_s = 0.3;
    let rig = Rig::start(None, Kind::Dvl, settings, 11, FaultPlan::default());
    rig.emu.truth.feed(cruising_east());
    // The test's MOOS time runs faster than the emulator's clock: the commands wait for
    // their answers as long as it takes (their retries are the unit tests').
    let cfg = DvlConfig {
        command_timeout_s: 1e6,
        gyro_timeout_s: 1e6,
        ..DvlConfig::default()
    };
    let mut d = Driver::new(
        Dvl::new(cfg),
        tcp(&rig.addr().ip().to_string(), rig.addr().port()),
        1.0,
    );
    d.start().unwrap();
    let mut s = Stepper::new(0.0);

    // On connection the driver turns the acoustics off (the A50 powers up with them on and
    // must not overheat in air); the emulator confirms.
    s.until(&mut d, "acoustics off at the connection", |s, _| {
        s.doubles("DVL_ACOUSTIC_ENABLED") == [0.0]
    });
    assert_eq!(s.texts("DVL_COMMAND_ACK"), ["set_config"]);

    // Deployed and 10 m down: the automatic mode turns them on and the reports flow.
    s.mail(&mut d, "DEPLOY", Value::String("true".into()));
    s.mail(&mut d, "NAV_DEPTH", Value::Double(10.0));
    s.until(&mut d, "acoustics on", |s, _| {
        s.doubles("DVL_ACOUSTIC_ENABLED").last() == Some(&1.0)
    });
    let on = s.mark();
    s.until(&mut d, "ten velocity reports", |s, _| {
        s.doubles_since(on, "DVL_VALID").len() >= 10
    });
    // The body velocity (forward, starboard, down) of 1 m/s east heading east, and the
    // altitude over the bottom (30 m - 10 m), within the model's noise (0.02 m/s, 0.5 %
    // scale, 0.05 m).
    assert!(s.doubles_since(on, "DVL_VALID").iter().all(|v| *v == 1.0));
    for (key, want, tol) in [
        ("DVL_VEL_X", 1.0, 0.1),
        ("DVL_VEL_Y", 0.0, 0.1),
        ("DVL_VEL_Z", 0.0, 0.1),
        ("DVL_ALTITUDE", 20.0, 0.3),
    ] {
        let got = s.doubles_since(on, key);
        assert!(got.len() >= 10, "{key}: {got:?}");
        assert!(
            got.iter().all(|v| (v - want).abs() < tol),
            "{key} not {want}: {got:?}"
        );
    }
    let fom = s.doubles_since(on, "DVL_FOM");
    assert!(fom.iter().all(|f| *f > 0.0 && *f < 0.1), "{fom:?}");
    // Each report is posted at the step its line arrived in, closed by DVL_VALID: the
    // velocity, altitude and validity of one report share one time, and times only grow.
    let times: Vec<f64> = s.posts[on..].iter().map(|(t, _)| *t).collect();
    assert!(times.windows(2).all(|w| w[0] <= w[1]));
    let report: Vec<(f64, &str)> = s.posts[on..]
        .iter()
        .filter(|(_, p)| p.key.starts_with("DVL_VEL_") || &*p.key == "DVL_VALID")
        .map(|(t, p)| (*t, &*p.key))
        .collect();
    for w in report.windows(4) {
        if w[0].1 == "DVL_VEL_X" {
            assert_eq!(w[3].1, "DVL_VALID", "{w:?}");
            assert!(w.iter().all(|(t, _)| *t == w[0].0), "{w:?}");
        }
    }

    // Dead reckoning (5 Hz): from the A50's power-up frame (x north), the vehicle has gone
    // east (y) heading 90 deg relative to it.
    s.until(&mut d, "a metre of dead reckoning", |s, _| {
        s.doubles("DVL_DR_Y").last().is_some_and(|y| *y > 1.0)
    });
    assert!(s.doubles("DVL_DR_X").last().unwrap().abs() < 0.5);
    assert!((s.doubles("DVL_DR_YAW").last().unwrap() - 90.0).abs() < 1e-6);

    // Hold still, calibrate the gyro, reset the dead reckoning: both reach the DVL and are
    // answered, one after the other.
    s.mail(&mut d, "DVL_CALIBRATE_GYRO", Value::Double(1.0));
    s.mail(&mut d, "DVL_RESET_DR", Value::Double(1.0));
    s.until(&mut d, "both commands answered", |s, _| {
        s.find_text("DVL_COMMAND_ACK", "reset_dead_reckoning")
            .is_some()
    });
    let acks = s.texts("DVL_COMMAND_ACK");
    assert_eq!(
        acks[acks.len() - 2..],
        ["calibrate_gyro", "reset_dead_reckoning"]
    );
    let reset = s
        .find_text("DVL_COMMAND_ACK", "reset_dead_reckoning")
        .unwrap();
    s.until(&mut d, "dead reckoning after the reset", |s, _| {
        s.doubles_since(reset, "DVL_DR_X").len() >= 3
    });
    // The new frame's x is the heading at the reset (east): the track restarts at 0 along x.
    let xs = s.doubles_since(reset, "DVL_DR_X");
    assert!(xs[0] < 0.5 && xs.windows(2).all(|w| w[1] >= w[0]), "{xs:?}");
    let ys = s.doubles_since(reset, "DVL_DR_Y");
    assert!(ys.iter().all(|y| y.abs() < 0.2), "{ys:?}");
    assert!(
        s.doubles_since(reset, "DVL_DR_YAW")
            .iter()
            .all(|y| y.abs() < 1e-6)
    );

    // The configuration read back says the acoustics are on.
    let before = s.doubles("DVL_ACOUSTIC_ENABLED").len();
    s.mail(&mut d, "DVL_GET_CONFIG", Value::Double(1.0));
    s.until(&mut d, "get_config answered", |s, _| {
        s.texts("DVL_COMMAND_ACK").last().map(String::as_str) == Some("get_config")
    });
    assert_eq!(s.doubles("DVL_ACOUSTIC_ENABLED")[before..], [1.0]);

    // At the surface the acoustics go off; once the DVL has answered, no report follows
    // (the answer and the reports share one ordered stream).
    s.mail(&mut d, "NAV_DEPTH", Value::Double(0.1));
    s.until(&mut d, "acoustics off at the surface", |s, _| {
        s.doubles("DVL_ACOUSTIC_ENABLED").last() == Some(&0.0)
    });
    let off = s.mark();
    s.steps(&mut d, 100);
    assert_eq!(s.doubles_since(off, "DVL_VALID"), Vec::<f64>::new());
    let status = s.status("DVL_DRIVER_STATUS");
    assert_eq!(field(&status, "commands"), Some(6), "{status}");
    assert_eq!(field(&status, "acks"), Some(6), "{status}");
    assert_eq!(field(&status, "command_errors"), Some(0), "{status}");
    assert_eq!(field(&status, "parse_errors"), Some(0), "{status}");
    assert!(status.contains(",acoustics=off,"), "{status}");
    assert!(s.warnings.is_empty(), "{:?}", s.warnings);
    d.stop();
    rig.stop();
}

#[test]
fn idvl_against_the_a50_emulator_survives_a_disconnect_and_garbage() {
    let rig = Rig::start(
        None,
        Kind::Dvl,
        Settings::default(),
        12,
        away_then_garbage(),
    );
    rig.emu.truth.feed(cruising_east());
    let mut d = Driver::new(
        Dvl::new(DvlConfig::default()),
        tcp(&rig.addr().ip().to_string(), rig.addr().port()),
        1.0,
    );
    let mut s = Stepper::new(0.0);
    s.mail(&mut d, "DEPLOY", Value::String("true".into()));
    s.mail(&mut d, "NAV_DEPTH", Value::Double(10.0));
    d.start().unwrap();
    // Over TCP the emulator, while away, hangs up on every connection: each is counted.
    let (back, clean) = survives_away_and_garbage(&mut s, &mut d, "DVL_VALID", 10);
    // Back, the driver said the acoustics again.
    assert!(
        s.texts_since(back, "DVL_COMMAND_ACK")
            .contains(&"set_config".to_string())
    );
    // Past the garbage the reports carry the truth.
    let vx = s.doubles_since(clean, "DVL_VEL_X");
    assert!(vx.iter().all(|v| (v - 1.0).abs() < 0.1), "{vx:?}");
    let status = s.status("DVL_DRIVER_STATUS");
    assert!(
        field(&status, "parse_errors").is_some_and(|n| n > 0),
        "{status}"
    );
    assert!(status.starts_with("link=up,"), "{status}");
    d.stop();
    rig.stop();
}

/// The X150 emulator on a pseudo-terminal in the scratch folder `test`, its remote beacon
/// (15) at `remote` (x east, y north, depth), measuring `truth`, and iSeaTrac configured as
/// on Utah Lake (beacon 3, salt water, the declination 10.7 deg E) stepped until its
/// start-up sequence has run to its end. The test's MOOS time runs faster than the
/// emulator's clock (0.05 s a step, a few milliseconds apart): a send waits 5 s of it (100
/// steps) for its answer, so a loaded machine's slow answer is not taken for a lost one.
fn x150_running(
    test: &str,
    remote: (f64, f64, f64),
    busy_first: u32,
    faults: FaultPlan,
    truth: Truth,
) -> (Rig, Driver<SeaTrac>, Stepper) {
    let mut settings = Settings::default();
    settings.seatrac.declination_deg = 10.7;
    settings.seatrac.busy_first = busy_first;
    settings.seatrac.remote = Box::new(EchoBeacon {
        id: 15,
        position: remote,
        received: Vec::new(),
    });
    let rig = Rig::start(Some(test), Kind::Seatrac, settings, 21, faults);
    rig.emu.truth.feed(truth);
    let cfg = SeaTracConfig {
        beacon_id: 3,
        salinity_ppt: 35.0,
        declination_deg: 10.7,
        send_wait_s: 5.0,
        ..SeaTracConfig::default()
    };
    let mut d = Driver::new(SeaTrac::new(cfg), serial(&rig.link), 1.0);
    d.start().unwrap();
    let mut s = Stepper::new(0.0);
    s.until(&mut d, "running", |_, d| {
        d.protocol.startup() == Startup::Running
    });
    (rig, d, s)
}

/// The doubles posted to `key` since `mark`, each within `tol` of `want` (and at least one).
fn near_since(s: &Stepper, mark: usize, key: &str, want: f64, tol: f64) {
    near(&s.doubles_since(mark, key), want, tol, key);
}

fn near(got: &[f64], want: f64, tol: f64, what: &str) {
    assert!(!got.is_empty(), "{what}: nothing posted");
    assert!(
        got.iter().all(|v| (v - want).abs() < tol),
        "{what}: not within {tol} of {want}: {got:?}"
    );
}

#[test]
fn iseatrac_against_the_x150_emulator_startup_status_ping_dat_and_busy() {
    // The base beacon (15) 20 m east and 20 m deeper: from a vehicle heading 030 deg, it is
    // 60 deg to starboard and 45 deg down, 28.28 m away. The start-up sequence runs to its
    // end: the beacon takes id 3 and sends its STATUS at 10 Hz with attitude, AHRS and
    // environment (the settings it was given).
    let truth = Truth {
        depth: 10.0,
        heading_deg: 30.0,
        ..Truth::default()
    };
    let (rig, mut d, mut s) = x150_running(
        "against-seatrac",
        (20.0, 0.0, 30.0),
        2,
        FaultPlan::default(),
        truth,
    );
    assert_eq!(s.doubles("SEATRAC_BEACON_ID"), [3.0]);
    let up = s.mark();
    s.until(&mut d, "ten STATUS", |s, _| {
        s.doubles_since(up, "AHRS_HEADING").len() >= 10
    });
    // The AHRS (σ 1 deg heading, 0.2 deg attitude) writes the magnetic yaw; the driver adds
    // the declination once.
    near_since(&s, up, "AHRS_HEADING", 30.0, 4.0);
    near_since(&s, up, "AHRS_PITCH", 0.0, 1.0);
    near_since(&s, up, "AHRS_ROLL", 0.0, 1.0);
    near_since(&s, up, "AHRS_YAW_RATE", 0.0, 0.3);
    // The environment block: the modem's depth sensor (σ 0.1 m), the supply, the absolute
    // pressure (101325 Pa + 997 kg/m³ · 9.81 · 10 m, in whole mbar), the speed of sound.
    near_since(&s, up, "SEATRAC_DEPTH", 10.0, 0.5);
    near_since(&s, up, "SEATRAC_SUPPLY_VOLTAGE", 16.4, 1e-9);
    near_since(&s, up, "SEATRAC_TEMP", 15.0, 1e-9);
    near_since(&s, up, "SEATRAC_PRESSURE", 199_100.0, 1e-6);
    near_since(&s, up, "SEATRAC_VOS", 1475.0, 1e-9);

    // A ping to the base: the transceiver says busy twice (the emulator's first two sends),
    // the driver sends it again each time, then the fix comes back with range and angles.
    s.mail(&mut d, "SEATRAC_PING", Value::String("15".into()));
    s.until(&mut d, "the ping's fix", |s, _| s.count("USBL_FIX") >= 1);
    assert_eq!(s.texts("ACOMMS_TX_ACK"), ["dest=15,cid=PING_SEND"]);
    assert_eq!(d.protocol.counts().busy, 2);
    let range = (20f64).hypot(20.0);
    near(&s.doubles("USBL_RANGE"), range, 0.5, "USBL_RANGE");
    near(&s.doubles("USBL_AZIMUTH"), 60.0, 4.0, "USBL_AZIMUTH");
    near(&s.doubles("USBL_ELEVATION"), -45.0, 4.0, "USBL_ELEVATION");
    // The position: east and north of the vehicle, and the base's depth below the surface.
    // The beacon writes the offsets on magnetic north (10.7° off, to its decimetre); the
    // driver's declination turns them back onto true north.
    near(&s.doubles("USBL_X"), 20.0, 0.1, "USBL_X");
    near(&s.doubles("USBL_Y"), 0.0, 0.1, "USBL_Y");
    near(&s.doubles("USBL_Z"), 30.0, 1e-9, "USBL_Z");
    assert_eq!(s.doubles("USBL_SRC"), [15.0]);
    let fix = s.texts("USBL_FIX").pop().unwrap();
    assert!(fix.starts_with("src=15,dest=3,type=RESPU,"), "{fix}");

    // A data request: the base echoes the payload back with a fix.
    let sent = s.mark();
    s.mail(
        &mut d,
        "ACOMMS_TX",
        Value::String("dest=15,hex=C0FFEE01,type=REQU".into()),
    );
    s.until(&mut d, "the echo", |s, _| {
        !s.texts_since(sent, "ACOMMS_RX").is_empty()
    });
    assert_eq!(
        s.texts_since(sent, "ACOMMS_RX"),
        ["src=15,dest=3,ack=1,hex=C0FFEE01"]
    );
    assert_eq!(
        s.texts_since(sent, "ACOMMS_TX_ACK"),
        ["dest=15,cid=DAT_SEND"]
    );
    near_since(&s, sent, "USBL_RANGE", range, 0.5);
    near_since(&s, sent, "USBL_AZIMUTH", 60.0, 4.0);
    let c = d.protocol.counts();
    assert_eq!((c.sent_ok, c.dat_rx, c.send_errors), (2, 1, 0), "{c:?}");
    assert_eq!(d.protocol.queued(), 0);

    // Turning right at 10 deg/s, pitching up at 0.1 rad/s and rolling at 0.05 rad/s (level
    // for now): the gyro, written in the modem's 45 deg frame, comes back as the body's
    // rates, as uSimSensors posts them (about forward, starboard and down).
    rig.emu.truth.feed(Truth {
        depth: 10.0,
        heading_deg: 30.0,
        yaw_rate_deg_s: 10.0,
        pitch_rate_rad_s: 0.1,
        roll_rate_rad_s: 0.05,
        ..Truth::default()
    });
    // The first STATUS after the feed may still be the old truth's.
    s.steps(&mut d, 5);
    let turning = s.mark();
    s.until(&mut d, "five STATUS while turning", |s, _| {
        s.doubles_since(turning, "AHRS_YAW_RATE").len() >= 6
    });
    let skip = |k: &str| s.doubles_since(turning, k)[1..].to_vec();
    near(&skip("AHRS_YAW_RATE"), 10.0, 0.3, "AHRS_YAW_RATE");
    near(
        &skip("AHRS_PITCH_RATE"),
        0.1f64.to_degrees(),
        0.3,
        "AHRS_PITCH_RATE",
    );
    near(
        &skip("AHRS_ROLL_RATE"),
        0.05f64.to_degrees(),
        0.3,
        "AHRS_ROLL_RATE",
    );
    let st = d.protocol.stats();
    assert_eq!(st.bad_checksum + st.parse_errors + st.oversize, 0, "{st:?}");
    assert!(s.warnings.is_empty(), "{:?}", s.warnings);
    d.stop();
    rig.stop();
}

#[test]
fn iseatrac_against_the_x150_emulator_survives_a_disconnect_and_garbage() {
    // Away for 0.3 s only, and thinner garbage (300 bytes/s).
    let faults = FaultPlan::parse(&["disconnect@1+0.3", "garbage@2.5+1.5:300"]).unwrap();
    let truth = Truth {
        depth: 2.0,
        ..Truth::default()
    };
    let (rig, mut d, mut s) =
        x150_running("against-seatrac-faults", (0.0, 50.0, 5.0), 0, faults, truth);
    // Back on a new terminal, the driver runs the start-up again and the STATUS resumes.
    let (_, clean) = survives_away_and_garbage(&mut s, &mut d, "SEATRAC_DEPTH", 10);
    assert_eq!(d.protocol.startup(), Startup::Running);
    assert_eq!(s.doubles("SEATRAC_BEACON_ID"), [3.0, 3.0]);
    // Past the garbage the values are the truth's, and the status counts what was torn.
    near_since(&s, clean, "SEATRAC_DEPTH", 2.0, 0.5);
    let status = s.status("SEATRAC_DRIVER_STATUS");
    assert!(status.starts_with("link=up,state=running,"), "{status}");
    let counted: u64 = ["garbage_bytes", "bad_checksum", "parse_errors", "oversize"]
        .iter()
        .filter_map(|k| field(&status, k))
        .sum();
    assert_eq!(counted, errors(&d), "{status}");
    d.stop();
    rig.stop();
}

/// The errors a protocol has counted so far: broken lines of every kind.
fn errors<P: Protocol>(d: &Driver<P>) -> u64 {
    let s = d.protocol.stats();
    s.garbage_bytes + s.oversize + s.bad_checksum + s.parse_errors
}

/// Steps until `n` posts of `key` in a row arrived with no error counted among them; returns
/// the mark where that clean run starts (no clock: a run that long is what the garbage's
/// rate makes all but impossible while it lasts).
fn clean_run<P: Protocol>(s: &mut Stepper, d: &mut Driver<P>, key: &str, n: usize) -> usize {
    let mut seen = errors(d);
    let mut from = s.mark();
    s.until(d, "a clean run after the garbage", |s, d| {
        let e = errors(d);
        if e != seen {
            seen = e;
            from = s.mark();
        }
        s.doubles_since(from, key).len() >= n
    });
    from
}

/// The emulated device hangs up at 1 s and is away for half a second (a new pseudo-terminal
/// behind the same link, as a replugged USB device's udev link; over TCP a listener that
/// hangs up), then sends garbage for 1.5 s.
fn away_then_garbage() -> FaultPlan {
    FaultPlan::parse(&["disconnect@1+0.5", "garbage@2.5+1.5:400"]).unwrap()
}

/// What every driver does through [`away_then_garbage`] (or a plan like it): it posts `key`, reconnects through
/// its link (the status counts each disconnection, and the link is up once more than it was
/// down), posts `key` again, counts the broken lines, never panics, and then posts `clean`
/// values of `key` in a row with no error among them. Returns the marks where the posts
/// after the reconnection and the clean run start.
fn survives_away_and_garbage<P: Protocol>(
    s: &mut Stepper,
    d: &mut Driver<P>,
    key: &str,
    clean: usize,
) -> (usize, usize) {
    s.until(d, "posts before the fault", |s, _| s.count(key) >= 3);
    s.until(d, "a second connection", |_, d| d.counters().connects >= 2);
    let back = s.mark();
    s.until(d, "posts after the reconnection", |s, _| {
        s.doubles_since(back, key).len() >= 3
    });
    let status = s.status(d.protocol.status_var());
    let downs = field(&status, "disconnects").unwrap_or(0);
    assert!(downs >= 1, "{status}");
    assert_eq!(field(&status, "connects"), Some(downs + 1), "{status}");
    s.until(d, "garbage counted", |_, d| errors(d) > 0);
    (back, clean_run(s, d, key, clean))
}

#[test]
fn iteensy_against_the_teensy_emulator_survives_a_replug_and_garbage() {
    let rig = Rig::start(
        Some("against-teensy-faults"),
        Kind::Teensy,
        Settings::default(),
        31,
        away_then_garbage(),
    );
    rig.emu.truth.feed(Truth::default());
    let port = rig.emu.teensy.clone().expect("the Teensy's port");
    let mut d = iteensy(&rig.link);
    d.start().unwrap();
    let mut s = Stepper::new(100.0);
    let (_, clean) = survives_away_and_garbage(&mut s, &mut d, "PRESSURE", 40);
    // The surface's air (the emulated MS5837's 101325 Pa, its noise a few pascals) and the
    // depth from the calibration at the surface.
    near_since(&s, clean, "PRESSURE", 101_325.0, 200.0);
    near_since(&s, clean, "DEPTH", 0.0, 0.05);
    assert_eq!(s.doubles_since(clean, "LEAK").last(), Some(&0.0));
    let status = s.status("TEENSY_DRIVER_STATUS");
    assert!(status.starts_with("link=up,"), "{status}");
    assert!(
        field(&status, "parse_errors").unwrap_or(0) + field(&status, "garbage_bytes").unwrap_or(0)
            > 0,
        "{status}"
    );
    // Commands reach the new terminal.
    s.mail(&mut d, "FIN_TOP_DEG", Value::Double(4.0));
    s.mail(&mut d, "THRUST_PCT", Value::Double(10.0));
    s.until(&mut d, "a command after the replug", |_, _| {
        port.get()
            .last
            .is_some_and(|(_, c)| c.fins_deg[0] == 4.0 && c.thrust_pct == 10)
    });
    d.stop();
    rig.stop();
}

#[test]
fn igps_against_the_nmea_gps_emulator_survives_a_replug_and_garbage() {
    let (rig, mut d, mut s) = gps_at_30_40("against-gps-faults", 32, away_then_garbage());
    // Random bytes break sentences: their checksums fail or they do not frame; counted.
    let (_, clean) = survives_away_and_garbage(&mut s, &mut d, "GPS_X", 10);
    let (xs, ys) = (
        s.doubles_since(clean, "GPS_X"),
        s.doubles_since(clean, "GPS_Y"),
    );
    assert!(xs.len() >= 10 && ys.len() >= xs.len() - 1, "{xs:?} {ys:?}");
    near_30_40(&xs, &ys);
    let status = s.status("GPS_DRIVER_STATUS");
    assert!(status.starts_with("link=up,"), "{status}");
    d.stop();
    rig.stop();
}
