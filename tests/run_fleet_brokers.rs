//! The fleet handshake of uFldNodeBroker and uFldShoreBroker in a lockstep `coug run`
//! (missions/fleet_brokers: fleet_survey with no route written out): the shoreside finds
//! the three vehicles from their pings, the routes are created at run time through
//! `PSHARE_CMD`, every vehicle's NODE_REPORT reaches the shoreside, and the shoreside's
//! DEPLOY button (`DEPLOY_ALL`, a qbridge) reaches every vehicle, which completes its
//! survey. Two runs write the same bytes in every alog.

mod common;

use std::collections::BTreeMap;

use common::*;
use runtime::fleet::LoadedFleet;
use runtime::session::{self, Ended, FleetOptions, Mode};

const VEHICLES: [&str; 3] = ["henry", "ike", "jing"];

/// What the fleet's observer was told: each community's helm summaries and progress values.
#[derive(Default)]
struct Seen {
    summaries: BTreeMap<String, usize>,
    nav_x: BTreeMap<String, f64>,
}

impl session::Observer for Seen {
    fn member_helm_summary(&mut self, member: &str, _summary: &str) {
        *self.summaries.entry(member.to_string()).or_default() += 1;
    }

    fn step(&mut self, _sim_s: f64, current: &dyn Fn(&str) -> Option<runtime::app::Value>) {
        for v in VEHICLES {
            if let Some(x) = current(&format!("{v}:NAV_X")).and_then(|x| x.as_f64()) {
                self.nav_x.insert(v.to_string(), x);
            }
        }
    }
}

fn run(name: &str) -> (BTreeMap<String, Vec<u8>>, Seen) {
    let dir = fresh_dir(name);
    let fleet = project_mission("fleet_brokers/fleet_brokers.fleet");
    let loaded = LoadedFleet::from_file(&fleet, &[], &[]).expect("the fleet loads");
    let checked = session::validate_fleet(&loaded);
    assert!(
        checked.warnings.is_empty() && checked.errors.is_empty() && checked.malconfig.is_empty(),
        "{checked:?}"
    );
    let opts = FleetOptions {
        mode: Mode::Lockstep,
        buttons: vec!["shoreside:DEPLOY".into()],
        until: vec!["MISSION = complete".into()],
        max_time: 600.0,
        log_dir: Some(dir.join("logs")),
        ..FleetOptions::default()
    };
    let mut seen = Seen::default();
    let report = session::run_fleet(&loaded, &opts, &mut seen).expect("runs");
    assert!(
        matches!(
            report.ended,
            Ended::Outcome(runtime::Outcome::ConditionMet { .. })
        ),
        "{report}"
    );
    let logs = report
        .members
        .iter()
        .map(|(m, _)| {
            let alog = find_alog(&dir.join("logs").join(m));
            (m.clone(), std::fs::read(alog).expect("alog readable"))
        })
        .collect();
    (logs, seen)
}

fn values<'a>(log: &'a alog::Alog, var: &str) -> Vec<&'a alog::Entry> {
    log.entries.iter().filter(|e| e.var == var).collect()
}

#[test]
fn the_brokers_find_the_fleet_and_bridge_reports_and_commands_at_run_time() {
    let (a, seen) = run("run-fleet-brokers-1");
    let (b, _) = run("run-fleet-brokers-1");
    // The observer heard every vehicle's helm and read its position by name (what `coug
    // run` prints per community); each came home near its start x (0, 60, 120).
    for (v, home) in VEHICLES.iter().zip([0.0, 60.0, 120.0]) {
        assert!(
            seen.summaries.get(*v).is_some_and(|n| *n > 10),
            "{v}: {:?}",
            seen.summaries
        );
        assert!(
            (seen.nav_x[*v] - home).abs() < 10.0,
            "{v}: {:?}",
            seen.nav_x
        );
    }
    assert!(
        !seen.summaries.contains_key("shoreside"),
        "no helm on the shoreside"
    );
    assert_eq!(a.len(), 4);
    for (name, bytes) in &a {
        assert!(
            *bytes == b[name],
            "two lockstep runs differ in {name}'s alog"
        );
    }

    let shore = parse(&a["shoreside"]);
    // Found: every vehicle's ping arrived, and the node count reached three.
    let count = values(&shore, "UFSB_NODE_COUNT");
    assert_eq!(count.last().and_then(|e| e.value.as_f64()), Some(3.0));
    for v in VEHICLES {
        let pinged = values(&shore, "NODE_BROKER_PING").iter().any(|e| {
            e.value
                .as_str()
                .is_some_and(|s| s.starts_with(&format!("community={v},")))
        });
        assert!(pinged, "{v} pinged the shoreside");
        // Routes created at run time: the acknowledgement and the qbridged commands to the
        // vehicle's input route, learnt from its ping.
        let port = 9300 + VEHICLES.iter().position(|x| *x == v).unwrap() + 1;
        for (src, dest) in [
            (
                format!("NODE_BROKER_ACK_{}", v.to_uppercase()),
                "NODE_BROKER_ACK",
            ),
            ("DEPLOY_ALL".to_string(), "DEPLOY"),
            (format!("RETURN_{}", v.to_uppercase()), "RETURN"),
        ] {
            let cmd = format!("cmd=output,src_name={src},dest_name={dest},route=localhost:{port}");
            assert!(
                values(&shore, "PSHARE_CMD")
                    .iter()
                    .any(|e| e.value.as_str() == Some(&cmd)),
                "the shoreside asked for {cmd}"
            );
        }
        // The vehicle's node reports reached the shoreside through the bridge it made.
        let reports = values(&shore, "NODE_REPORT")
            .iter()
            .filter(|e| {
                e.value
                    .as_str()
                    .is_some_and(|s| s.contains(&format!("NAME={v},")))
            })
            .count();
        assert!(
            reports > 100,
            "{v}: {reports} node reports at the shoreside"
        );
    }

    for v in VEHICLES {
        let log = parse(&a[v]);
        let acks = values(&log, "NODE_BROKER_ACK");
        assert!(
            acks.iter().all(|e| e.value.as_str().is_some_and(|s| s
                .starts_with("community=shoreside,")
                && s.contains(",status=ok,key=0,"))),
            "{v}"
        );
        assert!(!acks.is_empty(), "{v} was acknowledged");
        let bridged =
            "cmd=output,src_name=NODE_REPORT_LOCAL,dest_name=NODE_REPORT,route=localhost:9300";
        let cmds = values(&log, "PSHARE_CMD");
        assert!(
            cmds.iter().any(|e| e.value.as_str() == Some(bridged)),
            "{v}"
        );
        // The bridge was asked for only after the acknowledgement.
        let first_ack = acks[0].time;
        let first_bridge = cmds
            .iter()
            .find(|e| e.value.as_str() == Some(bridged))
            .unwrap()
            .time;
        assert!(first_bridge >= first_ack, "{v}");
        // The shoreside's button press, bridged: DEPLOY from the shoreside's uPokeDB.
        let deploys = values(&log, "DEPLOY");
        assert!(
            deploys
                .iter()
                .any(|e| e.source == "uPokeDB" && e.value.as_str() == Some("true")),
            "{v}: DEPLOY relayed from the shoreside"
        );
        assert_eq!(
            last_str(&log, "MISSION").as_deref(),
            Some("complete"),
            "{v}"
        );
    }
}

/// The brokers' every parameter is known to `coug check`: a block using them all is
/// clean, and unknown or bad lines are warnings at their line.
#[test]
fn coug_check_knows_the_brokers_parameters() {
    let dir = fresh_dir("run-fleet-brokers-check");
    let m = "ServerHost = localhost\nServerPort = 9000\nCommunity = shore\n\
             ProcessConfig = ANTLER\n{\n  Run = MOOSDB @ NewConsole = false\n  \
             Run = uFldShoreBroker @ NewConsole = false\n  Run = uFldNodeBroker @ NewConsole = false\n}\n\
             ProcessConfig = uFldShoreBroker\n{\n  AppTick = 4\n  bridge = src=FOO_$V, alias=FOO\n  \
             qbridge = DEPLOY, RETURN\n  keyword = lemon\n  auto_bridge_realmcast = false\n  \
             auto_bridge_appcast = true\n  auto_bridge_mhash = false\n  warning_on_stale = true\n  \
             try_vnode = route=127.0.0.1:9201\n  host_ip = 127.0.0.1\n}\n\
             ProcessConfig = uFldNodeBroker\n{\n  AppTick = 4\n  \
             try_shore_host = pshare_route=127.0.0.1:9200\n  bridge = src=NODE_REPORT_LOCAL, alias=NODE_REPORT\n  \
             auto_bridge_realmcast = false\n  auto_bridge_appcast = false\n  auto_bridge_pshare_vars = true\n  \
             host_ip = localhost\n}\n";
    std::fs::write(dir.join("clean.moos"), m).unwrap();
    let o = coug(&dir, &["check", "clean.moos"]);
    let out = String::from_utf8_lossy(&o.stdout).to_string() + &String::from_utf8_lossy(&o.stderr);
    assert!(o.status.success() && !out.contains("warning"), "{out}");
    let bad = m
        .replace("keyword = lemon", "keywords = lemon")
        .replace("pshare_route=127.0.0.1:9200", "pshare_route=nowhere")
        .replace("warning_on_stale = true", "warning_on_stale = maybe");
    std::fs::write(dir.join("bad.moos"), bad).unwrap();
    let o = coug(&dir, &["check", "bad.moos"]);
    let out = String::from_utf8_lossy(&o.stdout).to_string() + &String::from_utf8_lossy(&o.stderr);
    for expected in [
        "bad.moos:15: warning: uFldShoreBroker: unhandled config line: keywords = lemon",
        "bad.moos:19: warning: uFldShoreBroker: unhandled config line: warning_on_stale = maybe",
        "bad.moos:26: warning: uFldNodeBroker: unhandled config line: try_shore_host = pshare_route=nowhere (invalid pshare_route \"nowhere\")",
    ] {
        assert!(out.contains(expected), "{expected}\n{out}");
    }
}
