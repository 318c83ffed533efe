//! A driver against its device's emulator (crate `emulate`), over a pseudo-terminal: the
//! real driver path with no hardware. The emulator measures the truth it is fed; the driver
//! must post what the sensor models would, and its commands must reach the device. Every wait
//! is bounded; nothing about timing is asserted.

mod common;

use std::time::Duration;

use common::{Stepper, scratch};
use drivers::gps::{Gps, Source};
use drivers::link::{Endpoint, LinkConfig};
use drivers::teensy::{Teensy, TeensyConfig};
use drivers::{Driver, Protocol};
use emulate::build::{Kind, Options, Settings, spawn};
use emulate::transport::Transport;
use emulate::truth::Truth;
use moos_types::Value;

fn serial(path: &std::path::Path) -> LinkConfig {
    let mut l = LinkConfig::new(Endpoint::Serial {
        path: path.to_path_buf(),
        baud: 115_200,
    });
    l.backoff_min = Duration::from_millis(20);
    l.backoff_max = Duration::from_millis(100);
    l
}

#[test]
fn iteensy_against_the_teensy_emulator_depth_battery_and_fin_commands() {
    let dir = scratch("against-teensy");
    let link = dir.join("teensy");
    let rt = tokio::runtime::Runtime::new().unwrap();
    let emu = rt
        .block_on(spawn(
            Kind::Teensy,
            Settings::default(),
            Transport::Pty {
                link: Some(link.clone()),
            },
            Options {
                seed: 7,
                ..Options::default()
            },
        ))
        .unwrap();
    // At the surface first: the driver calibrates the atmosphere there.
    emu.truth.feed(Truth::default());
    let port = emu.teensy.clone().expect("the Teensy's port");

    // The test's MOOS time runs faster than the emulator's 20 Hz (0.05 s a step, a couple of
    // milliseconds apart): a long calibration timeout, so the samples decide, not the clock.
    let cfg = TeensyConfig {
        calibration_samples: 5,
        calibration_timeout_s: 1e6,
        ..TeensyConfig::default()
    };
    let mut d = Driver::new(Teensy::new(cfg), serial(&link), 1.0);
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
    emu.truth.feed(Truth {
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
    rt.block_on(emu.handle.stop()).unwrap();
}

#[test]
fn igps_against_the_nmea_gps_emulator_fixes_at_the_surface_none_under_water() {
    let dir = scratch("against-gps");
    let link = dir.join("gps");
    let rt = tokio::runtime::Runtime::new().unwrap();
    let settings = Settings::default();
    let (lat0, lon0) = settings.gps.origin_lat_lon;
    let emu = rt
        .block_on(spawn(
            Kind::Gps,
            settings,
            Transport::Pty {
                link: Some(link.clone()),
            },
            Options {
                seed: 3,
                ..Options::default()
            },
        ))
        .unwrap();
    // 30 m east and 40 m north of the origin, at the surface.
    emu.truth.feed(Truth {
        x: 30.0,
        y: 40.0,
        ..Truth::default()
    });
    let grid = vehicle::geodesy::LocalGrid::new(lat0, lon0).unwrap();
    let mut d = Driver::new(Gps::new(Source::Nmea, Some(grid)), serial(&link), 1.0);
    d.start().unwrap();
    let mut s = Stepper::new(0.0);
    s.until(&mut d, "five fixes", |s, _| {
        s.doubles("GPS_FIX").iter().filter(|f| **f == 1.0).count() >= 5
    });
    // Within a few sigma of the emulated receiver's noise (1.5 m x HDOP per axis).
    let (xs, ys) = (s.doubles("GPS_X"), s.doubles("GPS_Y"));
    assert!(xs.len() >= 5 && xs.len() == ys.len());
    for (x, y) in xs.iter().zip(&ys) {
        assert!(
            (x - 30.0).abs() < 10.0 && (y - 40.0).abs() < 10.0,
            "({x}, {y})"
        );
    }
    // Satellites in view once fixed (zero while the receiver was acquiring).
    let sats = s.doubles("GPS_SATELLITES");
    assert!(sats.last().is_some_and(|n| *n >= 4.0), "{sats:?}");

    // Under water the antenna hears nothing: no more fixes, the driver says so.
    emu.truth.feed(Truth {
        x: 30.0,
        y: 40.0,
        depth: 3.0,
        ..Truth::default()
    });
    s.until(&mut d, "the fix lost", |s, _| {
        s.doubles("GPS_FIX").last() == Some(&0.0)
    });
    assert_eq!(d.protocol.stats().bad_checksum, 0);
    rt.block_on(emu.handle.stop()).unwrap();
}
