//! The emulators without I/O: deterministic from a seed, faults at their configured times
//! through the whole [`Emulator`], and no panic on any bytes a host may send.

use devices::line::LineSplitter;
use devices::teensy::{self, Telemetry};
use emulate::build::{self, Kind, Settings};
use emulate::device::Emulator;
use emulate::fault::FaultPlan;
use emulate::transport::Transport;
use emulate::truth::BoxScenario;
use proptest::prelude::*;

const KINDS: [Kind; 4] = [Kind::Gps, Kind::Dvl, Kind::Seatrac, Kind::Teensy];

fn emulator(kind: Kind, transport: &Transport, faults: &[&str], seed: u64) -> Emulator {
    let mut settings = Settings::default();
    // Status on, so the SeaTrac talks without a driver.
    settings.seatrac.settings.set_status_mode(4);
    settings.seatrac.settings.set_status_output(0x23);
    let (dev, _) = build::device(kind, settings, transport, seed);
    Emulator::new(
        dev,
        Box::new(BoxScenario::new(40.0, 1.5, 3.0)),
        FaultPlan::parse(faults).unwrap(),
        seed,
        1_795_000_000.0,
    )
}

/// Every byte the emulator writes over `secs` seconds of ticks.
fn run(e: &mut Emulator, secs: f64) -> Vec<u8> {
    let p = e.period();
    let n = (secs / p).round() as u32;
    (0..n)
        .flat_map(|k| e.tick(f64::from(k) * p).bytes)
        .collect()
}

#[test]
fn the_same_seed_gives_the_same_bytes_and_another_seed_others() {
    for transport in [Transport::loopback(0), Transport::Pty { link: None }] {
        for kind in KINDS {
            let faults = ["noise@5+5:1", "garbage@12+2:50"];
            let a = run(&mut emulator(kind, &transport, &faults, 7), 60.0);
            let b = run(&mut emulator(kind, &transport, &faults, 7), 60.0);
            let c = run(&mut emulator(kind, &transport, &faults, 8), 60.0);
            assert!(!a.is_empty(), "{kind:?}");
            assert_eq!(a, b, "{kind:?} {transport:?}");
            // gpsd says nothing until a client watches.
            if !(kind == Kind::Gps && matches!(transport, Transport::Tcp(_))) {
                assert_ne!(a, c, "{kind:?} {transport:?}");
            }
        }
    }
}

#[test]
fn the_teensy_leaks_and_its_battery_falls_at_the_configured_times() {
    let pty = Transport::Pty { link: None };
    let mut e = emulator(
        Kind::Teensy,
        &pty,
        &["leak@10", "battery@20:0.1", "dropout@30+5"],
        1,
    );
    let p = e.period();
    let mut split = LineSplitter::new(teensy::MAX_LINE).with_starts(b"$");
    let mut seen = Vec::new();
    for k in 0..(50.0 / p) as u32 {
        let t = f64::from(k) * p;
        let out = e.tick(t).bytes;
        split.push(&out, |l| seen.push((t, Telemetry::parse(l).unwrap())));
    }
    let first_leak = seen
        .iter()
        .find(|(_, m)| matches!(m, Telemetry::Leak { leak: true }))
        .unwrap()
        .0;
    assert!((first_leak - 10.0).abs() < 1e-9, "{first_leak}");
    let volts = |t0: f64| {
        seen.iter()
            .find_map(|(t, m)| match m {
                Telemetry::Battery { voltage_v, .. } if *t >= t0 => Some(*voltage_v),
                _ => None,
            })
            .unwrap()
    };
    assert_eq!(volts(19.0), 16.4);
    assert_eq!(volts(25.0), 15.9);
    // Silent from 30 s to 35 s.
    assert!(seen.iter().all(|(t, _)| !(30.0..35.0).contains(t)));
    assert!(seen.iter().any(|(t, _)| *t >= 35.0));
    assert_eq!(split.stats().garbage_bytes, 0);
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(64))]

    #[test]
    fn no_bytes_from_a_host_make_an_emulator_panic(
        chunks in proptest::collection::vec(proptest::collection::vec(any::<u8>(), 0..120), 1..8),
        starts in proptest::collection::vec(prop_oneof![Just(b'$'), Just(b'#'), Just(b'?'), Just(b'{')], 1..8),
    ) {
        for transport in [Transport::loopback(0), Transport::Pty { link: None }] {
            for kind in KINDS {
                let mut e = emulator(kind, &transport, &[], 3);
                for (k, (c, s)) in chunks.iter().zip(starts.iter().cycle()).enumerate() {
                    let mut data = vec![*s];
                    data.extend(c);
                    data.push(b'\n');
                    let t = k as f64 * 0.1;
                    let _ = e.receive(t, &data);
                    let _ = e.tick(t);
                }
            }
        }
    }
}
