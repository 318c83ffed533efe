//! The lockstep three-agent acoustic fleet (issue #16, "What must be shown", 4th point):
//! missions/fleet_acomms, a base beacon polling two CougUVs over uSimModem while they survey
//! their lanes at 3 m. The base knows where they are only from their acoustic answers; an
//! abort sent from the base mid-dive surfaces coug1 and stops its thruster; coug2 completes.
//! The positions the base logs are checked against each vehicle's truth (SIM_X/SIM_Y in its
//! own log), and the poll and channel statistics are read from the logs.

mod common;

use std::collections::BTreeMap;
use std::path::Path;

use common::*;
use runtime::fleet::LoadedFleet;
use runtime::session::{self, Ended, FleetOptions, FleetReport, Mode};

/// When the base's operator sends the abort to coug1 (simulated seconds from the start).
const ABORT_AT: f64 = 90.0;
/// The vehicles, their modem ids and their lanes (X1, X2).
const VEHICLES: [(&str, u8, f64, f64); 2] = [("coug1", 1, 0.0, 20.0), ("coug2", 2, 60.0, 80.0)];

fn options() -> FleetOptions {
    FleetOptions {
        deploy: true,
        pokes: vec![format!("base:ACOMMS_COMMAND=to=1,cmd=abort@{ABORT_AT}")],
        until: vec![
            "coug2: MISSION = complete".into(),
            "coug1: SAFETY_MODE = DISARMED".into(),
        ],
        max_time: 600.0,
        ..FleetOptions::default()
    }
}

/// Runs the fleet in lockstep in process on `threads` threads, logging under a fresh folder
/// `name`; returns the report and every community's alog bytes by name.
fn run_fleet(name: &str, threads: usize) -> (FleetReport, BTreeMap<String, Vec<u8>>) {
    let fleet = project_mission("fleet_acomms/fleet_acomms.fleet");
    let dir = fresh_dir(name);
    let loaded = LoadedFleet::from_file(&fleet, &[], &[])
        .unwrap_or_else(|e| panic!("{} does not load: {e}", fleet.display()));
    let checked = session::validate_fleet(&loaded);
    assert!(checked.errors.is_empty(), "{:?}", checked.errors);
    assert!(checked.malconfig.is_empty(), "{:?}", checked.malconfig);
    assert!(checked.failed.is_empty(), "{:?}", checked.failed);
    let warnings: Vec<String> = checked.warnings.iter().map(|w| w.located()).collect();
    assert!(warnings.is_empty(), "{warnings:?}");
    let opts = FleetOptions {
        mode: Mode::Lockstep,
        log_dir: Some(dir.join("logs")),
        threads,
        ..options()
    };
    let report = session::run_fleet(&loaded, &opts, &mut session::Quiet)
        .unwrap_or_else(|e| panic!("fleet run failed: {e}"));
    let mut logs = BTreeMap::new();
    for (member, r) in &report.members {
        let alog = find_alog(&dir.join("logs").join(member));
        assert_eq!(Path::new(&r.alog), alog, "the report names {member}'s log");
        let bytes = std::fs::read(&alog).expect("alog readable");
        // The report's totals, counted while the log was written, are those of the file
        // read back.
        let text = std::str::from_utf8(&bytes).expect("UTF-8");
        let back = session::LogTotals::from_alog(&alog::parse(text).expect("an alog"));
        assert_eq!(r.totals.as_ref(), Some(&back), "{member}'s totals");
        logs.insert(member.clone(), bytes);
    }
    (report, logs)
}

/// `(time, value)` of every numeric record of `var`.
fn series(log: &alog::Alog, var: &str) -> Vec<(f64, f64)> {
    log.entries
        .iter()
        .filter(|e| e.var == var)
        .filter_map(|e| Some((e.time, e.value.as_f64()?)))
        .collect()
}

/// `(time, value)` of every string record of `var`.
fn strings(log: &alog::Alog, var: &str) -> Vec<(f64, String)> {
    log.entries
        .iter()
        .filter(|e| e.var == var)
        .filter_map(|e| Some((e.time, e.value.as_str()?.to_string())))
        .collect()
}

/// The last value of a series at or before `t`.
fn at(s: &[(f64, f64)], t: f64) -> f64 {
    let i = s.partition_point(|p| p.0 <= t);
    assert!(i > 0, "no value at or before {t}");
    s[i - 1].1
}

/// A `key=value` field of a comma-separated string.
fn field<'a>(s: &'a str, key: &str) -> Option<&'a str> {
    s.split(',')
        .find_map(|p| p.strip_prefix(key)?.strip_prefix('='))
}

fn num(s: &str, key: &str) -> f64 {
    field(s, key)
        .and_then(|v| v.parse().ok())
        .unwrap_or_else(|| panic!("{key} in {s}"))
}

fn first_time(log: &alog::Alog, var: &str, value: &str) -> Option<f64> {
    log.entries
        .iter()
        .find(|e| e.var == var && e.value.as_str() == Some(value))
        .map(|e| e.time)
}

/// Mean and maximum.
fn mean_max(v: &[f64]) -> (f64, f64) {
    let mean = v.iter().sum::<f64>() / v.len() as f64;
    (mean, v.iter().copied().fold(0.0, f64::max))
}

#[test]
fn a_base_polls_two_couguvs_underwater_aborts_one_and_runs_repeat() {
    let (report, logs) = run_fleet("run-fleet-acomms-1", 1);
    let summary = report.to_string();
    assert!(
        matches!(
            report.ended,
            Ended::Outcome(runtime::Outcome::ConditionMet { .. })
        ),
        "{summary}"
    );
    assert_eq!(logs.len(), 3, "{summary}");
    let base = parse(&logs["base"]);
    let vlogs: Vec<alog::Alog> = VEHICLES.iter().map(|v| parse(&logs[v.0])).collect();
    // One clock: every log starts at the same MOOS time, so record times compare.
    for l in &vlogs {
        assert_eq!(l.log_start, base.log_start);
    }
    // The communities share nothing but the water: no pShare, and the base never sees a
    // vehicle's own node reports.
    assert!(
        !base
            .entries
            .iter()
            .any(|e| e.var.starts_with("NODE_REPORT_LOCAL"))
    );

    // ---- Positions at the base, from the acoustic answers, against the truth.
    let rx = strings(&base, "ACOMMS_RX");
    let mut figures = Vec::new();
    for ((name, id, _, _), log) in VEHICLES.iter().zip(&vlogs) {
        let (sx, sy) = (series(log, "SIM_X"), series(log, "SIM_Y"));
        let (nx, ny) = (series(log, "NAV_X"), series(log, "NAV_Y"));
        let tx = strings(log, "ACOMMS_TX");
        let mut at_rx = Vec::new();
        let mut at_tx = Vec::new();
        let mut latency = Vec::new();
        let mut usbl = Vec::new();
        for (t, r) in strings(&base, "NODE_REPORT") {
            let vsource = field(&r, "VSOURCE").expect("VSOURCE");
            let who = field(&r, "NAME").unwrap();
            let (x, y) = (num(&r, "X"), num(&r, "Y"));
            let truth = |t: f64| (x - at(&sx, t)).hypot(y - at(&sy, t));
            if who == format!("{name}_usbl") {
                assert_eq!(vsource, "acomms_usbl", "{r}");
                usbl.push(truth(t));
                continue;
            }
            if who != *name {
                continue;
            }
            assert_eq!(vsource, "acomms_reported", "{r}");
            at_rx.push(truth(t));
            // The packet it came in: the base's last reception from this vehicle, found by
            // its bytes among the vehicle's transmissions.
            let (_, got) = rx
                .iter()
                .rfind(|(tr, s)| *tr <= t && field(s, "src") == Some(&id.to_string()))
                .expect("the status's reception");
            let hex = field(got, "hex").unwrap();
            let (ts, _) = tx
                .iter()
                .rfind(|(tt, s)| *tt <= t && field(s, "hex") == Some(hex))
                .unwrap_or_else(|| panic!("{name} never sent {hex}"));
            // Never a made-up position before the navigator's first one.
            assert!(
                *ts >= nx[0].0,
                "{name}: status sent at {ts} before any NAV_X: {r}"
            );
            // The vehicle reported its navigation when it answered (the codec's 0.1 m): the
            // NAV_X/Y it had read, posted at the answer's instant or one navigator tick before.
            let nav = [*ts, ts - 0.099]
                .iter()
                .map(|&t| (x - at(&nx, t)).hypot(y - at(&ny, t)))
                .fold(f64::INFINITY, f64::min);
            assert!(nav <= 0.08, "{name} at {ts}: {nav} m from its NAV_X/Y");
            at_tx.push(truth(*ts));
            latency.push(t - ts);
        }
        assert!(
            at_rx.len() >= 10,
            "{name}: {} reported positions",
            at_rx.len()
        );
        assert!(
            usbl.len() >= at_rx.len(),
            "{name}: {} USBL fixes",
            usbl.len()
        );
        let (rx_mean, rx_max) = mean_max(&at_rx);
        let (tx_mean, tx_max) = mean_max(&at_tx);
        let (u_mean, u_max) = mean_max(&usbl);
        let (l_mean, l_max) = mean_max(&latency);
        figures.push(format!(
            "{name}: {} reported positions: error vs truth when heard mean {rx_mean:.2} m max \
             {rx_max:.2} m, vs truth when sent (navigation error) mean {tx_mean:.2} m max \
             {tx_max:.2} m, age mean {l_mean:.2} s max {l_max:.2} s; {} USBL fixes: error \
             mean {u_mean:.2} m max {u_max:.2} m",
            at_rx.len(),
            usbl.len()
        ));
        assert!(tx_max < 3.0, "{name}: navigation error up to {tx_max} m");
        assert!(
            rx_max < 5.0,
            "{name}: reported position off by up to {rx_max} m"
        );
        assert!(u_max < 6.0, "{name}: USBL fix off by up to {u_max} m");
        assert!(l_max < 4.0, "{name}: a status {l_max} s old");
    }

    // ---- The abort: sent from the base, confirmed, applied on coug1 only.
    let acks: Vec<String> = strings(&base, "ACOMMS_COMMAND_ACK")
        .into_iter()
        .map(|(_, s)| s)
        .collect();
    assert_eq!(
        acks.first().map(String::as_str),
        Some("to=1,cmd=abort,seq=0,state=queued"),
        "{acks:?}"
    );
    assert!(
        acks.iter()
            .any(|a| a.starts_with("to=1,cmd=abort,seq=") && a.ends_with(",state=confirmed")),
        "{acks:?}"
    );
    assert!(
        !acks.iter().any(|a| a.contains("success=false")),
        "{acks:?}"
    );
    let (c1, c2) = (&vlogs[0], &vlogs[1]);
    let applied = strings(c1, "ACOMMS_CMD_RECEIVED");
    assert!(
        !applied.is_empty() && applied[0].1.starts_with("from=15,cmd=abort,seq="),
        "{applied:?}"
    );
    let t_cmd = applied[0].0;
    assert!(
        t_cmd > ABORT_AT && t_cmd < ABORT_AT + 12.0,
        "applied at {t_cmd}"
    );
    assert!(strings(c2, "ACOMMS_CMD_RECEIVED").is_empty());
    assert!(!c2.entries.iter().any(|e| e.var == "ACOMMS_ABORT"));

    // coug1 was diving when it came, came up with its fins up, and was disarmed at the
    // surface: thrust 0 from then on.
    let depth1 = series(c1, "SIM_DEPTH");
    let dived = at(&depth1, t_cmd);
    assert!(dived > 2.0, "coug1 at {dived} m when the abort came");
    let t_surface_mode = first_time(c1, "SAFETY_MODE", "SURFACE").expect("SURFACE");
    assert!(t_surface_mode >= t_cmd && t_surface_mode < t_cmd + 0.5);
    let t_up = depth1
        .iter()
        .find(|p| p.0 > t_cmd && p.1 < 0.3)
        .expect("coug1 surfaced")
        .0;
    let t_disarm = first_time(c1, "SAFETY_MODE", "DISARMED").expect("DISARMED");
    let thrust = series(c1, "THRUST_PCT");
    assert!(thrust.iter().any(|p| p.0 < t_cmd && p.1 > 10.0));
    let after: Vec<f64> = thrust
        .iter()
        .filter(|p| p.0 >= t_disarm)
        .map(|p| p.1)
        .collect();
    assert!(
        !after.is_empty() && after.iter().all(|&t| t == 0.0),
        "{after:?}"
    );
    assert_eq!(last_str(c1, "MISSION").as_deref(), Some("pending"));
    let speed1 = series(c1, "SIM_SPEED");
    let end = report.sim_s();
    // Bounds: the command reaches coug1 within 12 s of the operator's poke (the base's
    // current slot, at most one 4 s timeout, the 1.4 s packet); it is at the surface
    // 25 s after the poke and disarmed 5 s (pSafety's surface_hold) later.
    assert!(
        t_up - ABORT_AT < 25.0,
        "surfaced {} s after the abort",
        t_up - ABORT_AT
    );
    assert!(
        t_disarm - t_up < 6.0,
        "disarmed {} s after surfacing",
        t_disarm - t_up
    );
    // Unpowered, it glides to a stop.
    assert!(
        at(&speed1, end) < 0.1,
        "coug1 still at {} m/s",
        at(&speed1, end)
    );
    figures.push(format!(
        "abort: poked at {ABORT_AT} s, applied on coug1 at {t_cmd:.1} s at {dived:.2} m, \
         at the surface at {t_up:.1} s ({:.1} s after the poke), disarmed (thrust 0) at \
         {t_disarm:.1} s; speed at the end ({end:.0} s) {:.2} m/s",
        t_up - ABORT_AT,
        at(&speed1, end)
    ));

    // The base sees coug1 surfacing, then surfaced, in its answers.
    let views1: Vec<String> = strings(&base, "ACOMMS_VEHICLE")
        .into_iter()
        .filter(|(t, s)| *t > t_cmd && s.starts_with("id=1,") && s.contains(",time="))
        .map(|(_, s)| s)
        .collect();
    assert!(
        views1.iter().any(|s| s.contains(",mode=surfacing,")),
        "{views1:?}"
    );
    assert!(
        views1.last().is_some_and(|s| s.contains(",mode=surfaced,")),
        "{views1:?}"
    );

    // ---- coug2 was left alone and completed its lane at depth.
    assert_eq!(last_str(c2, "MISSION").as_deref(), Some("complete"));
    assert!(
        !c2.entries
            .iter()
            .any(|e| e.var == "SAFETY_MODE" && e.value.as_str().is_some_and(|m| m != "OK"))
    );
    let (_, _, x1, x2) = VEHICLES[1];
    let t = track(c2);
    visits_in_order(
        &t,
        &[
            (x1, -15.0),
            (x1, -75.0),
            (x2, -75.0),
            (x2, -15.0),
            (x2, 0.0),
        ],
        5.0,
        0,
    );
    let depth2 = series(c2, "SIM_DEPTH");
    let dove = depth2.iter().filter(|p| p.1 > 2.5).count();
    assert!(dove > 1000, "coug2 spent {dove} records below 2.5 m");
    let views2: Vec<String> = strings(&base, "ACOMMS_VEHICLE")
        .into_iter()
        .filter(|(_, s)| s.starts_with("id=2,") && s.contains(",time="))
        .map(|(_, s)| s)
        .collect();
    assert!(
        views2.iter().all(|s| s.contains(",mode=mission,")),
        "{views2:?}"
    );

    // ---- Poll and channel statistics, from the logs.
    let status = strings(&base, "ACOMMS_STATUS").last().unwrap().1.clone();
    let (polls, answers, timeouts, losses) = (
        num(&status, "polls"),
        num(&status, "answers"),
        num(&status, "timeouts"),
        num(&status, "losses"),
    );
    assert!(
        (0.0..=1.0).contains(&(polls - answers - timeouts)),
        "at most the last poll outstanding: {status}"
    );
    assert_eq!(num(&status, "confirmed"), 1.0, "{status}");
    for k in [
        "bad_tag",
        "replayed",
        "foreign",
        "unknown_sender",
        "malformed",
    ] {
        assert_eq!(num(&status, k), 0.0, "{k}: {status}");
    }
    // One transmission every 4 s slot over the run: a poll, or the abort in its place.
    let slots = (end / 4.0).floor();
    assert!(
        polls + num(&status, "commands") >= slots - 2.0,
        "{polls} polls in {end} s: {status}"
    );
    assert!(answers >= 0.8 * polls, "{status}");
    let channel = strings(&base, "ACOMMS_CHANNEL").last().unwrap().1.clone();
    let collisions = num(&channel, "collisions");
    assert_eq!(collisions, 0.0, "a polled MAC: {channel}");
    let per_vehicle: Vec<String> = VEHICLES
        .iter()
        .map(|(name, id, _, _)| {
            let v = strings(&base, "ACOMMS_VEHICLE")
                .into_iter()
                .rfind(|(_, s)| s.starts_with(&format!("id={id},")))
                .unwrap()
                .1;
            format!(
                "{name} {}/{}/{}",
                num(&v, "polls"),
                num(&v, "answers"),
                num(&v, "timeouts")
            )
        })
        .collect();
    figures.push(format!(
        "{end:.0} s: base polls={polls} answers={answers} timeouts={timeouts} \
         losses={losses} (polls/answers/timeouts: {}); channel: {channel}",
        per_vehicle.join(", ")
    ));
    eprintln!("{}", figures.join("\n"));

    // ---- Determinism: a second run writes the same bytes in every community's log (the
    // same folder name: an alog names its own path), here with the communities stepped on
    // several threads (one each: three), which hand their modems' requests to the shared
    // channel in whatever order the threads interleave.
    let (_, again) = run_fleet("run-fleet-acomms-1", 4);
    assert_eq!(again.len(), logs.len());
    for (name, bytes) in &logs {
        assert!(
            *bytes == again[name],
            "lockstep runs of fleet_acomms on 1 and 4 threads wrote different alogs for {name}"
        );
    }
}

/// Two threads (the base and coug1 on one, coug2 on the other) write the bytes of one
/// thread too, run after run.
#[test]
fn two_threads_write_the_bytes_of_one() {
    let (_, one) = run_fleet("run-fleet-acomms-2", 1);
    for _ in 0..2 {
        let (_, two) = run_fleet("run-fleet-acomms-2", 2);
        assert_eq!(two.len(), one.len());
        for (name, bytes) in &one {
            assert!(
                *bytes == two[name],
                "lockstep runs of fleet_acomms on 1 and 2 threads wrote different alogs for {name}"
            );
        }
    }
}

/// In real time too the communities' uSimModems share one channel: a vehicle hears the base's
/// poll (each community on its own thread and TCP MOOSDB, ServerPort = 0).
#[test]
fn a_real_time_fleet_shares_the_acoustic_channel() {
    let dir = fresh_dir("run-fleet-acomms-realtime");
    let mission = |community: &str, id: u8, role: &str, x: f64| {
        format!(
            "ServerHost = localhost\nServerPort = 0\nCommunity = {community}\n\
             ProcessConfig = ANTLER\n{{\n  Run = MOOSDB @ NewConsole = false\n  \
             Run = pLogger @ NewConsole = false\n  Run = uSimModem @ NewConsole = false\n  \
             Run = pAcomms @ NewConsole = false\n}}\n\
             ProcessConfig = pLogger\n{{\n  AppTick = 10\n  WildCardLogging = true\n}}\n\
             ProcessConfig = uSimModem\n{{\n  AppTick = 10\n  modem_id = {id}\n  seed = 3\n  \
             x = {x}\n  y = 0\n  depth = 2\n}}\n\
             ProcessConfig = pAcomms\n{{\n  AppTick = 10\n  modem_id = {id}\n  role = {role}\n  \
             key = a fleet secret\n  node = 15:base\n  node = 1:auv\n  x = {x}\n  y = 0\n}}\n"
        )
    };
    std::fs::write(dir.join("base.moos"), mission("base", 15, "base", 0.0)).unwrap();
    std::fs::write(dir.join("auv.moos"), mission("auv", 1, "vehicle", 100.0)).unwrap();
    let loaded =
        LoadedFleet::from_missions(&[dir.join("base.moos"), dir.join("auv.moos")], &[], &[])
            .expect("loads");
    let opts = FleetOptions {
        mode: Mode::RealTime {
            warp: Some(10.0),
            port: None,
        },
        until: vec!["auv: ACOMMS_LAST_BASE_CONTACT > 0".into()],
        max_time: 120.0,
        log_dir: Some(dir.join("logs")),
        ..FleetOptions::default()
    };
    let report = session::run_fleet(&loaded, &opts, &mut session::Quiet).expect("runs");
    assert!(!report.until_pending(), "the poll never crossed: {report}");
    let auv = parse(&std::fs::read(find_alog(&dir.join("logs/auv"))).unwrap());
    let rx = strings(&auv, "ACOMMS_RX");
    assert!(
        rx.iter().any(|(_, s)| s.starts_with("src=15,dest=1,")),
        "{rx:?}"
    );
}
