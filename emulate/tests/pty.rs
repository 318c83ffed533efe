//! The serial emulators over real pseudo-terminals, opened by path as a driver opens a
//! device. Terminals deliver asynchronously in the kernel, so these run on the real clock;
//! every wait is bounded (a generous limit that fails the test, never a timing assertion).

use std::path::{Path, PathBuf};
use std::time::Duration;

use devices::line::LineSplitter;
use devices::nmea;
use devices::seatrac::{self, Command, Cst, Response, status_bits};
use devices::teensy::{Contr, Telemetry};
use emulate::build::{self, Kind, Options, Settings};
use emulate::fault::FaultPlan;
use emulate::pty::SerialClient;
use emulate::transport::{Endpoint, Transport};
use emulate::truth::Still;
use tokio::time::timeout;

const LIMIT: Duration = Duration::from_secs(20);

fn scratch(name: &str) -> PathBuf {
    let dir = std::env::temp_dir().join(format!("coug-emulate-{}-{name}", std::process::id()));
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).unwrap();
    dir
}

/// Reads lines until `want` of them are collected (bounded by [`LIMIT`]).
async fn read_lines(port: &SerialClient, splitter: &mut LineSplitter, want: usize) -> Vec<Vec<u8>> {
    let mut out = Vec::new();
    let mut buf = [0u8; 1024];
    timeout(LIMIT, async {
        while out.len() < want {
            let n = port.read(&mut buf).await.expect("the terminal is open");
            assert!(n > 0);
            splitter.push(&buf[..n], |l| out.push(l.to_vec()));
        }
    })
    .await
    .expect("lines within the limit");
    out
}

async fn spawn(kind: Kind, link: &Path, faults: &[&str]) -> build::Running {
    build::spawn_with(
        kind,
        Settings::default(),
        Transport::Pty {
            link: Some(link.to_path_buf()),
        },
        Options {
            seed: 2,
            faults: FaultPlan::parse(faults).unwrap(),
            epoch_unix_s: 1_795_000_000.0,
        },
        Box::new(Still),
    )
    .await
    .unwrap()
}

#[tokio::test]
async fn teensy_telemetry_and_commands_over_a_pty_and_a_reopened_one() {
    let dir = scratch("teensy");
    let link = dir.join("teensy");
    let run = spawn(Kind::Teensy, &link, &["disconnect@3+0.5", "leak@0"]).await;
    let Endpoint::Pty { path, .. } = run.handle.endpoint() else {
        panic!()
    };
    assert_eq!(std::fs::read_link(&link).unwrap(), path);
    let port = SerialClient::open(&link).unwrap();
    let mut split = LineSplitter::new(64).with_starts(b"$");
    let lines = read_lines(&port, &mut split, 9).await;
    let kinds: Vec<Telemetry> = lines.iter().map(|l| Telemetry::parse(l).unwrap()).collect();
    assert!(
        kinds
            .iter()
            .any(|m| matches!(m, Telemetry::Leak { leak: true }))
    );
    assert!(kinds.iter().any(|m| matches!(m, Telemetry::Depth { pressure_pa, .. } if (pressure_pa - 101325.0).abs() < 200.0)));
    port.write_all(b"$CONTR,5,-5,5,40\n").await.unwrap();
    let teensy = run.teensy.clone().unwrap();
    timeout(LIMIT, async {
        while teensy.get().accepted == 0 {
            tokio::time::sleep(Duration::from_millis(10)).await;
        }
    })
    .await
    .expect("the command arrives");
    assert_eq!(
        teensy.get().last.unwrap().1,
        Contr {
            fins_deg: [5.0, -5.0, 5.0],
            thrust_pct: 40
        }
    );
    // The disconnection: the terminal goes away (reads fail), a new one appears behind
    // the same link.
    let mut endpoints = run.handle.endpoints();
    timeout(LIMIT, async {
        let mut buf = [0u8; 256];
        while matches!(port.read(&mut buf).await, Ok(n) if n > 0) {}
    })
    .await
    .expect("the terminal closes");
    let new_path = timeout(LIMIT, async {
        loop {
            endpoints.changed().await.unwrap();
            if let Endpoint::Pty { path, .. } = endpoints.borrow().clone() {
                return path;
            }
        }
    })
    .await
    .expect("a new terminal");
    assert_eq!(std::fs::read_link(&link).unwrap(), new_path);
    let port = SerialClient::open(&link).unwrap();
    let mut split = LineSplitter::new(64).with_starts(b"$");
    let lines = read_lines(&port, &mut split, 6).await;
    assert!(lines.iter().all(|l| Telemetry::parse(l).is_ok()));
    let stats = run.handle.stop().await.unwrap();
    assert_eq!((stats.connections, stats.disconnects), (2, 1));
    assert!(!link.exists(), "the link goes with the terminal");
}

#[tokio::test]
async fn seatrac_start_up_over_a_pty() {
    let dir = scratch("seatrac");
    let link = dir.join("seatrac");
    let run = spawn(Kind::Seatrac, &link, &[]).await;
    let port = SerialClient::open(&link).unwrap();
    let mut split = LineSplitter::new(seatrac::MAX_FRAME).with_starts(b"$");
    port.write_all(Command::SysAlive.encode().unwrap().as_bytes())
        .await
        .unwrap();
    let r = read_lines(&port, &mut split, 1).await;
    assert!(matches!(
        Response::decode(&r[0]),
        Ok(Response::SysAlive { .. })
    ));
    port.write_all(Command::SettingsGet.encode().unwrap().as_bytes())
        .await
        .unwrap();
    let r = read_lines(&port, &mut split, 1).await;
    let Ok(Response::SettingsGet(mut s)) = Response::decode(&r[0]) else {
        panic!("{r:?}")
    };
    s.set_beacon_id(2);
    s.set_status_mode(4);
    s.set_status_output(
        status_bits::ATTITUDE | status_bits::ENVIRONMENT | status_bits::AHRS_COMP_DATA,
    );
    port.write_all(Command::SettingsSet(s).encode().unwrap().as_bytes())
        .await
        .unwrap();
    port.write_all(Command::SettingsSave.encode().unwrap().as_bytes())
        .await
        .unwrap();
    // The two answers, then 10 Hz status (in whatever order they interleave).
    let r = read_lines(&port, &mut split, 5).await;
    let decoded: Vec<Response> = r.iter().map(|l| Response::decode(l).unwrap()).collect();
    assert!(decoded.contains(&Response::SettingsSet(Cst::Ok)));
    assert!(decoded.contains(&Response::SettingsSave(Cst::Ok)));
    let statuses: Vec<_> = decoded
        .iter()
        .filter_map(|m| match m {
            Response::Status(s) => Some(s),
            _ => None,
        })
        .collect();
    assert!(!statuses.is_empty());
    assert!(
        statuses
            .iter()
            .all(|s| s.attitude.is_some() && s.environment.is_some() && s.ahrs_comp.is_some())
    );
    run.handle.stop().await.unwrap();
}

#[tokio::test]
async fn nmea_gps_over_a_pty_without_a_link() {
    let run = build::spawn_with(
        Kind::Gps,
        Settings::default(),
        Transport::Pty { link: None },
        Options::default(),
        Box::new(Still),
    )
    .await
    .unwrap();
    let path = run.handle.endpoint().serial_path().unwrap().to_path_buf();
    assert!(path.starts_with("/dev/pts"), "{path:?}");
    let port = SerialClient::open(&path).unwrap();
    let mut split = LineSplitter::new(nmea::MAX_LINE).with_starts(b"$");
    let lines = read_lines(&port, &mut split, 6).await;
    let kinds: Vec<&str> = lines
        .iter()
        .map(|l| nmea::parse(l).unwrap().kind())
        .collect();
    assert!(
        kinds.windows(3).any(|w| w == ["GGA", "RMC", "VTG"]),
        "{kinds:?}"
    );
    run.handle.stop().await.unwrap();
}
