//! Two `coug run` processes, each its own MOOS community with its own MOOSDB, bridged by
//! their pShare apps over loopback UDP (127.0.0.1 only): what one community's uTimerScript
//! posts reaches the other renamed, with its source, community and time kept, as between two
//! machines of a fleet. Waits are bounded (`--max-time` and receive timeouts).

mod common;

use test_support::missions::{counting_events, pshare_community, spawn_reading_stderr};

use std::net::UdpSocket;
use std::path::Path;
use std::process::{Child, Command};
use std::sync::mpsc;
use std::time::Duration;

use common::*;

/// A UDP port on 127.0.0.1 the system picked (the socket is closed again at once, so the
/// receiving pShare can bind it).
fn free_udp_port() -> u16 {
    UdpSocket::bind("127.0.0.1:0")
        .and_then(|s| s.local_addr())
        .expect("a loopback UDP socket")
        .port()
}

/// A one-community mission: the DB, pShare with `share` lines, pLogger (marking messages from
/// other communities `src@community`), and a uTimerScript
/// posting `COUNT = 1..=30` once a second when `sender`.
fn write_mission(dir: &Path, community: &str, share: &str, sender: bool) {
    let mut text = format!(
        "ServerHost = localhost\nServerPort = 0\nCommunity = {community}\nMOOSTimeWarp = 1\n\
         LatOrigin = 43.825300\nLongOrigin = -70.330400\n\n\
         ProcessConfig = ANTLER\n{{\n  Run = MOOSDB @ NewConsole = false\n  \
         Run = pShare @ NewConsole = false\n  Run = pLogger @ NewConsole = false\n"
    );
    if sender {
        text.push_str("  Run = uTimerScript @ NewConsole = false\n");
    }
    text.push_str("}\n\n");
    text.push_str(&format!(
        "ProcessConfig = pShare\n{{\n  AppTick = 10\n  listen_address = 127.0.0.1\n{share}}}\n\n"
    ));
    text.push_str(
        "ProcessConfig = pLogger\n{\n  AppTick = 10\n  AsyncLog = true\n  WildCardLogging = true\n  \
         MarkExternalCommunityMessages = true\n}\n\n",
    );
    if sender {
        text.push_str("ProcessConfig = uTimerScript\n{\n  AppTick = 10\n");
        for k in 1..=30 {
            text.push_str(&format!("  event = var=COUNT, val={k}, time={k}\n"));
        }
        text.push_str("}\n");
    }
    std::fs::write(dir.join(format!("{community}.moos")), text).unwrap();
}

/// Starts `coug run MISSION --warp W ...` in `dir` with stderr lines sent to the returned
/// channel.
fn start(dir: &Path, mission: &str, extra: &[&str]) -> (Child, mpsc::Receiver<String>) {
    let (child, rx) = spawn_reading_stderr(
        Command::new(env!("CARGO_BIN_EXE_coug"))
            .current_dir(dir)
            .args([
                "run",
                mission,
                "--warp",
                "4",
                "--port",
                "0",
                "--log-dir",
                "logs",
            ])
            .args(extra),
    );
    (child, rx)
}

/// Waits (bounded) for the run's DB to announce itself, returning the lines seen.
fn wait_listening(rx: &mpsc::Receiver<String>, who: &str) -> Vec<String> {
    let mut seen = Vec::new();
    loop {
        let line = rx
            .recv_timeout(Duration::from_secs(60))
            .unwrap_or_else(|_| panic!("{who} announces its MOOSDB within 60 s; saw {seen:?}"));
        let done = line.contains("listening on 127.0.0.1:");
        seen.push(line);
        if done {
            return seen;
        }
    }
}

#[test]
fn two_coug_processes_share_a_variable_over_loopback_udp() {
    let dir = fresh_dir("run-pshare-two-process");
    let port = free_udp_port();
    std::fs::create_dir_all(dir.join("shore")).unwrap();
    std::fs::create_dir_all(dir.join("henry")).unwrap();
    write_mission(
        &dir.join("shore"),
        "shore",
        &format!("  input = route = 127.0.0.1:{port}\n"),
        false,
    );
    write_mission(
        &dir.join("henry"),
        "henry",
        &format!("  output = src_name=COUNT, dest_name=HENRY_COUNT, route=127.0.0.1:{port}\n"),
        true,
    );

    // The receiver first, so its pShare listens before anything is sent; it ends once the
    // twentieth count has arrived (exit 0), or at its time limit (exit 2).
    let (mut shore, shore_rx) = start(
        &dir.join("shore"),
        "shore.moos",
        &["--until", "HENRY_COUNT >= 20", "--max-time", "120"],
    );
    wait_listening(&shore_rx, "the shore run");
    let (mut henry, henry_rx) = start(&dir.join("henry"), "henry.moos", &["--max-time", "40"]);
    wait_listening(&henry_rx, "the henry run");

    let shore_status = shore.wait().expect("the shore run ends");
    let henry_status = henry.wait().expect("the henry run ends");
    let shore_err: Vec<String> = shore_rx.try_iter().collect();
    assert_eq!(
        shore_status.code(),
        Some(0),
        "the shore saw HENRY_COUNT reach 20; stderr: {shore_err:?}"
    );
    assert!(henry_status.success(), "henry's run: {henry_status:?}");

    // The shore's log: HENRY_COUNT posted by henry's uTimerScript, in henry's community,
    // counting up without gaps from where the shore started hearing.
    let log = parse(&std::fs::read(find_alog(&dir.join("shore/logs"))).unwrap());
    let counts: Vec<(f64, String)> = log
        .entries
        .iter()
        .filter(|e| e.var == "HENRY_COUNT")
        .map(|e| (e.value.as_f64().expect("a number"), e.source.clone()))
        .collect();
    assert!(counts.len() >= 15, "{counts:?}");
    for w in counts.windows(2) {
        assert_eq!(
            w[1].0,
            w[0].0 + 1.0,
            "no count lost or repeated: {counts:?}"
        );
    }
    assert_eq!(counts.last().unwrap().0, 20.0, "{counts:?}");
    for (_, source) in &counts {
        assert_eq!(
            source, "uTimerScript@henry",
            "the writer and its community are kept"
        );
    }
    // The shore never had a COUNT of its own: only the renamed share crossed.
    assert!(log.entries.iter().all(|e| e.var != "COUNT"));
}

/// Store and forward on the surface-only radio, in a lockstep fleet of a diver and a
/// shoreside: the diver posts `PING = k` and `STATE = k` every second from 1 s to 30 s and is
/// under from 9.5 s to 19.5 s. The shoreside receives exactly what `radio_store` says, and
/// the diver's pShare appcast gives the counts.
#[test]
fn a_surfacing_vehicle_forwards_what_its_store_kept() {
    // (radio_store lines, the PINGs and STATEs the shoreside must log, the store's appcast
    // line)
    let surface: Vec<u32> = (1..=9).chain(20..=30).collect();
    let with = |kept: &[u32]| -> Vec<u32> {
        let mut v: Vec<u32> = (1..=9).collect();
        v.extend_from_slice(kept);
        v.extend(20..=30);
        v
    };
    let cases = [
        ("", surface, None),
        (
            "  radio_store = latest\n",
            with(&[19]),
            Some(
                "Store: latest (at most 100)  queued=0 stored=20 forwarded=2 superseded=18 overflow=0",
            ),
        ),
        (
            "  radio_store = all\n  radio_store_max = 4\n",
            with(&[18, 19]),
            Some("Store: all (at most 4)  queued=0 stored=20 forwarded=4 superseded=0 overflow=16"),
        ),
    ];
    for (store, want, cast) in cases {
        let dir = fresh_dir("run-pshare-radio-store");
        let events = |var: &str| counting_events(var, 30);
        let mission = pshare_community;
        let diver = mission(
            "diver",
            &format!(
                "  radio_max_depth = 1\n{store}  input = route = localhost:39521\n  \
                 output = PING->localhost:39520\n  output = STATE->localhost:39520\n"
            ),
            &format!(
                "  event = var=NAV_DEPTH, val=0, time=0.5\n  event = var=NAV_DEPTH, val=3, time=9.5\n  \
                 event = var=NAV_DEPTH, val=0.4, time=19.5\n  event = var=DONE, val=1, time=31\n{}{}",
                events("PING"),
                events("STATE")
            ),
        );
        let shore = mission("shore", "  input = route = localhost:39520\n", "");
        std::fs::write(dir.join("diver.moos"), diver).unwrap();
        std::fs::write(dir.join("shore.moos"), shore).unwrap();
        let loaded = runtime::fleet::LoadedFleet::from_missions(
            &[dir.join("shore.moos"), dir.join("diver.moos")],
            &[],
            &[],
        )
        .expect("loads");
        let checked = runtime::session::validate_fleet(&loaded);
        assert!(checked.warnings.is_empty(), "{:?}", checked.warnings);
        let opts = runtime::session::FleetOptions {
            mode: runtime::session::Mode::Lockstep,
            pokes: vec![
                "diver:APPCAST_REQ:=node=diver,app=pShare,duration=20,key=t,thresh=any@25".into(),
            ],
            until: vec!["diver: DONE = 1".into()],
            max_time: 60.0,
            log_dir: Some(dir.join("logs")),
            ..Default::default()
        };
        let report = runtime::session::run_fleet(&loaded, &opts, &mut runtime::session::Quiet)
            .expect("runs");
        assert!(!report.until_pending(), "{report}");
        let log = |community: &str| {
            parse(&std::fs::read(find_alog(&dir.join("logs").join(community))).unwrap())
        };
        let shore_log = log("shore");
        let heard = |var: &str| -> Vec<u32> {
            shore_log
                .entries
                .iter()
                .filter(|e| e.var == var)
                .map(|e| e.value.as_f64().expect("a number") as u32)
                .collect()
        };
        assert_eq!(heard("PING"), want, "PING with {store:?}");
        assert_eq!(heard("STATE"), want, "STATE with {store:?}");
        // Forwarded messages keep their writer's time: 19 s for PING 19, not the surfacing.
        if cast.is_some() {
            let start = shore_log.entries[0].time;
            let ping19 = shore_log
                .entries
                .iter()
                .find(|e| e.var == "PING" && e.value.as_f64() == Some(19.0))
                .expect("PING 19");
            assert!(
                (ping19.time - start - 19.0).abs() < 1e-6,
                "{} vs start {start}",
                ping19.time
            );
        }
        let diver_log = log("diver");
        let casts: Vec<&str> = diver_log
            .entries
            .iter()
            .filter(|e| e.var == "APPCAST" && e.source == "pShare")
            .filter_map(|e| e.value.as_str())
            .collect();
        let last = casts.last().expect("pShare appcasts");
        match cast {
            Some(line) => assert!(last.contains(line), "{line} in {last}"),
            None => assert!(!last.contains("Store:"), "{last}"),
        }
    }
}
