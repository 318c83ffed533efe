//! The emulators over loopback TCP, on tokio's paused clock: a client connects, reads
//! parseable reports at the device's rate in virtual time, talks to the device, and
//! survives a disconnection fault.

use std::time::Duration;

use devices::a50;
use devices::nmea::gpsd;
use emulate::build::{self, Kind, Options, Settings};
use emulate::fault::FaultPlan;
use emulate::transport::Transport;
use emulate::truth::{Still, Truth};
use tokio::io::{AsyncBufReadExt, AsyncWriteExt, BufReader};
use tokio::net::TcpStream;
use tokio::time::{Instant, timeout};

type Lines = tokio::io::Lines<BufReader<TcpStream>>;

async fn connect(addr: std::net::SocketAddr) -> Lines {
    BufReader::new(TcpStream::connect(addr).await.unwrap()).lines()
}

/// The next line within `secs` virtual seconds (None on timeout or end of stream).
async fn next(lines: &mut Lines, secs: f64) -> Option<String> {
    timeout(Duration::from_secs_f64(secs), lines.next_line())
        .await
        .ok()
        .and_then(|r| r.ok().flatten())
}

#[tokio::test(start_paused = true)]
async fn gpsd_streams_tpv_at_five_hertz_to_a_watcher() {
    let mut settings = Settings::default();
    settings.gps.model.loss_prob = 0.0;
    let run = build::spawn_with(
        Kind::Gps,
        settings,
        Transport::loopback(0),
        Options {
            seed: 4,
            epoch_unix_s: 1_795_000_000.0,
            ..Options::default()
        },
        Box::new(Still),
    )
    .await
    .unwrap();
    let addr = run.handle.endpoint().tcp().unwrap();
    let mut lines = connect(addr).await;
    let banner = next(&mut lines, 1.0).await.unwrap();
    assert!(matches!(gpsd::parse(banner.as_bytes()), Ok(gpsd::Report::Other(c)) if c == "VERSION"));
    lines
        .get_mut()
        .get_mut()
        .write_all(b"?WATCH={\"enable\":true,\"json\":true};")
        .await
        .unwrap();
    let start = Instant::now();
    let (mut tpv, mut sky, mut fixes) = (Vec::new(), 0, 0);
    while start.elapsed() < Duration::from_secs(10) {
        let line = next(&mut lines, 1.0).await.expect("a report every epoch");
        match gpsd::parse(line.as_bytes()).unwrap() {
            gpsd::Report::Tpv(t) => {
                fixes += usize::from(t.mode == 3);
                tpv.push(t);
            }
            gpsd::Report::Sky(_) => sky += 1,
            gpsd::Report::Other(c) => assert!(c == "DEVICES" || c == "WATCH", "{c}"),
        }
    }
    assert!((49..=51).contains(&tpv.len()), "{} TPV in 10 s", tpv.len());
    assert!((9..=11).contains(&sky), "{sky} SKY in 10 s");
    // The 2 s acquisition, then a fix every epoch; times 0.2 s apart.
    assert!((39..=41).contains(&fixes), "{fixes}");
    assert_eq!(tpv[1].time.as_deref(), Some("2026-11-18T11:06:40.400Z"));
    let fix = tpv.last().unwrap();
    assert!((fix.lat_deg.unwrap() - 40.3394).abs() < 1e-4);
    run.handle.stop().await.unwrap();
}

#[tokio::test(start_paused = true)]
async fn dvl_answers_commands_and_comes_back_after_a_disconnection() {
    let run = build::spawn(
        Kind::Dvl,
        Settings::default(),
        Transport::loopback(0),
        Options {
            seed: 1,
            faults: FaultPlan::parse(&["disconnect@3+1"]).unwrap(),
            epoch_unix_s: 1_795_000_000.0,
        },
    )
    .await
    .unwrap();
    // The simulator's truth: 10 m deep (20 m over the bottom), 1 m/s north.
    run.truth.feed(Truth {
        depth: 10.0,
        vel_north_mps: 1.0,
        speed_mps: 1.0,
        ..Truth::default()
    });
    let addr = run.handle.endpoint().tcp().unwrap();
    let mut lines = connect(addr).await;
    let mut velocities = 0;
    let mut last_dr = None;
    let start = Instant::now();
    while let Some(line) = next(&mut lines, 1.0).await {
        match a50::parse(line.as_bytes()).unwrap() {
            a50::Message::Velocity(v) => {
                assert!(v.velocity_valid && (v.vel_body_mps[0] - 1.0).abs() < 0.2);
                velocities += 1;
            }
            a50::Message::DeadReckoning(d) => last_dr = Some(d),
            a50::Message::Response(r) => panic!("{r:?}"),
        }
    }
    // Closed by the fault at 3 s: 3 s of reports at the model's rate for 20 m.
    let closed_at = start.elapsed().as_secs_f64();
    assert!((2.9..3.1).contains(&closed_at), "{closed_at}");
    let rate = 15.0 - 13.0 * (20.0 - 0.05) / 49.95;
    assert!(
        (f64::from(velocities) - 3.0 * rate).abs() <= 2.0,
        "{velocities}"
    );
    assert!(last_dr.unwrap().x_m > 2.0, "dead reckoning moved north");
    // While the device is off a connection is closed at once.
    let mut refused = connect(addr).await;
    assert_eq!(next(&mut refused, 0.5).await, None);
    tokio::time::sleep(Duration::from_secs(1)).await;
    // Back on: a new connection gets reports, and commands are answered.
    let mut lines = connect(addr).await;
    let off = a50::Command::SetConfig(a50::Config {
        acoustic_enabled: Some(false),
        ..a50::Config::default()
    });
    lines
        .get_mut()
        .get_mut()
        .write_all(off.encode().as_bytes())
        .await
        .unwrap();
    let mut answered = false;
    while let Some(line) = next(&mut lines, 1.0).await {
        if let a50::Message::Response(r) = a50::parse(line.as_bytes()).unwrap() {
            assert_eq!((r.response_to.as_str(), r.success), ("set_config", true));
            answered = true;
            break;
        }
    }
    assert!(answered);
    // Acoustics off: silence.
    assert_eq!(next(&mut lines, 2.0).await, None);
    let stats = run.handle.stop().await.unwrap();
    assert_eq!((stats.connections, stats.disconnects), (2, 1));
}

#[tokio::test(start_paused = true)]
async fn a_newer_connection_replaces_an_older_one() {
    let run = build::spawn_with(
        Kind::Dvl,
        Settings::default(),
        Transport::loopback(0),
        Options::default(),
        Box::new(Still),
    )
    .await
    .unwrap();
    let addr = run.handle.endpoint().tcp().unwrap();
    let mut first = connect(addr).await;
    assert!(next(&mut first, 1.0).await.is_some());
    let mut second = connect(addr).await;
    assert!(next(&mut second, 1.0).await.is_some());
    // The first one was dropped: what it had buffered, then its end.
    let mut n = 0;
    while next(&mut first, 1.0).await.is_some() {
        n += 1;
        assert!(n < 100, "the old connection still gets reports");
    }
    run.handle.stop().await.unwrap();
}
