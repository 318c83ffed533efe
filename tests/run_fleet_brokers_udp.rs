//! missions/fleet_brokers in real time across processes (issue #16, point 5): the shoreside
//! and two vehicles each run as their own `coug run` (three communities, three MOOSDBs),
//! every MOOSDB and every pShare input on a port the system picks on 127.0.0.1. Only the
//! shoreside's pShare port is handed on (read from its `PSHARE_INPUT_SUMMARY` and given to
//! the vehicles as `SHORE_LISTEN`, as a fleet's well-known shore port would be); the
//! vehicles' ports reach the shoreside only in their brokers' pings. Over real UDP on
//! loopback the shoreside finds both vehicles, asks its pShare for the routes to the ports
//! the vehicles' pShares picked, hears their NODE_REPORTs, and its `DEPLOY_ALL` reaches both.
//!
//! Every wait is a bounded poll (a deadline, then a failure saying what was awaited and
//! what was seen); no duration is asserted. The runs end on `--until TEST_DONE = true`,
//! posted by the test, and at worst on their `--max-time`.

mod common;

use test_support::missions::spawn_reading_stderr;

use std::collections::{BTreeMap, BTreeSet};
use std::path::Path;
use std::process::Command;
use std::sync::mpsc;
use std::time::{Duration, Instant};

use common::*;
use moosdb::{Client, ClientConfig, Message, Value};

/// The time warp of every run.
const WARP: f64 = 4.0;
/// The vehicles: name, start x, survey points.
const VEHICLES: [(&str, &str, &str); 2] = [
    ("henry", "0", "20,-20:20,-100:40,-100:40,-20"),
    ("ike", "60", "80,-20:80,-100:100,-100:100,-20"),
];
/// The longest wall-clock wait for any one step.
const STEP: Duration = Duration::from_secs(120);

/// One `coug run` process with the port its MOOSDB announced.
struct Run {
    name: String,
    child: KillOnDrop,
    db_port: u16,
    stderr: mpsc::Receiver<String>,
}

/// Starts `coug run MISSION MACROS... --warp 4` in `dir/name` and waits (bounded) for its
/// MOOSDB to announce its port.
fn start(dir: &Path, name: &str, mission: &str, macros: &[String]) -> Run {
    let cwd = dir.join(name);
    std::fs::create_dir_all(&cwd).unwrap();
    let (child, rx) = spawn_reading_stderr(
        Command::new(env!("CARGO_BIN_EXE_coug"))
            .current_dir(&cwd)
            .arg("run")
            .arg(project_mission(mission))
            .args(macros)
            .args([
                "--warp",
                &WARP.to_string(),
                "--port",
                "0",
                "--log-dir",
                "logs",
            ])
            .args(["--until", "TEST_DONE = true", "--max-time", "900"]),
    );
    let mut seen = Vec::new();
    let deadline = Instant::now() + STEP;
    let db_port = loop {
        let left = deadline.saturating_duration_since(Instant::now());
        let line = rx
            .recv_timeout(left)
            .unwrap_or_else(|_| panic!("{name}: no MOOSDB announced; stderr: {seen:?}"));
        if let Some(p) = line
            .split("listening on 127.0.0.1:")
            .nth(1)
            .and_then(|r| r.split_whitespace().next())
            .and_then(|p| p.parse::<u16>().ok())
        {
            break p;
        }
        seen.push(line);
    };
    assert_ne!(db_port, 0, "{name}: a real port");
    Run {
        name: name.to_string(),
        child: KillOnDrop(child),
        db_port,
        stderr: rx,
    }
}

/// What the test's clients have heard, per community.
#[derive(Default)]
struct Heard {
    /// Every message, in arrival order, by community.
    mail: BTreeMap<String, Vec<Message>>,
}

impl Heard {
    fn texts(&self, who: &str, var: &str) -> Vec<String> {
        self.mail
            .get(who)
            .into_iter()
            .flatten()
            .filter(|m| m.key_str() == var)
            .map(|m| m.sval_str().into_owned())
            .collect()
    }

    fn summary(&self) -> String {
        let mut s = String::new();
        for (who, mail) in &self.mail {
            let vars: BTreeSet<String> = mail.iter().map(|m| m.key_str().into_owned()).collect();
            s.push_str(&format!("{who}: {} messages of {vars:?}; ", mail.len()));
        }
        s
    }
}

/// A MOOS client on one community's DB with the inbox it reads.
struct Tap {
    who: String,
    client: Client,
    inbox: moosdb::MailStream,
}

async fn tap(who: &str, port: u16, vars: &[&str]) -> Tap {
    let mut cc = ClientConfig::new(&format!("test_{who}"), "127.0.0.1", port);
    cc.warp = moosdb::time::Warp::new(WARP).unwrap();
    let (client, inbox) = Client::start(cc);
    tokio::time::timeout(STEP, client.wait_connected())
        .await
        .unwrap_or_else(|_| panic!("{who}: the test's client connects"))
        .unwrap_or_else(|e| panic!("{who}: the DB accepts the test's client: {e}"));
    for v in vars {
        client.register(v, 0.0);
    }
    Tap {
        who: who.to_string(),
        client,
        inbox,
    }
}

/// Reads every tap until `done` holds, or fails after [`STEP`] naming `what`.
async fn until(taps: &mut [Tap], heard: &mut Heard, what: &str, done: impl Fn(&Heard) -> bool) {
    let deadline = tokio::time::Instant::now() + STEP;
    loop {
        for t in taps.iter_mut() {
            while let Some(m) = t.inbox.try_recv() {
                heard.mail.entry(t.who.clone()).or_default().push(m);
            }
        }
        if done(heard) {
            return;
        }
        assert!(
            tokio::time::Instant::now() < deadline,
            "not seen within {STEP:?}: {what}; heard {}",
            heard.summary()
        );
        tokio::time::sleep(Duration::from_millis(50)).await;
    }
}

/// The port of the first `host:port` route of a `PSHARE_INPUT_SUMMARY`, if not 0.
fn summary_port(summary: &str) -> Option<u16> {
    let first = summary.split(',').next()?;
    let port = first.rsplit(':').next()?.parse::<u16>().ok()?;
    (port != 0).then_some(port)
}

#[test]
fn three_coug_processes_find_each_other_and_share_over_loopback_udp() {
    let dir = fresh_dir("run-fleet-brokers-udp");
    let rt = tokio::runtime::Builder::new_current_thread()
        .enable_all()
        .build()
        .unwrap();
    let mut heard = Heard::default();

    // The shoreside first: its MOOSDB and its pShare input on ports the system picks.
    let shore = start(
        &dir,
        "shoreside",
        "fleet_brokers/shoreside.moos",
        &[
            "VNAME=shoreside".into(),
            "VINDEX=0".into(),
            "SHORE_PORT=0".into(),
            "SHORE_LISTEN=0".into(),
        ],
    );
    let mut taps = vec![rt.block_on(tap(
        "shoreside",
        shore.db_port,
        &[
            "PSHARE_INPUT_SUMMARY",
            "PSHARE_CMD",
            "UFSB_NODE_COUNT",
            "NODE_REPORT",
            "NODE_BROKER_PING",
        ],
    ))];
    rt.block_on(until(
        &mut taps,
        &mut heard,
        "the shoreside's pShare reports the port it listens on",
        |h| {
            h.texts("shoreside", "PSHARE_INPUT_SUMMARY")
                .iter()
                .any(|s| summary_port(s).is_some())
        },
    ));
    let shore_summary = heard.texts("shoreside", "PSHARE_INPUT_SUMMARY")[0].clone();
    let shore_listen = summary_port(&shore_summary).unwrap();
    assert!(
        shore_summary.starts_with("localhost:"),
        "the route as written, with the picked port: {shore_summary}"
    );

    // The vehicles, told only where the shoreside listens.
    let mut runs = vec![shore];
    for (i, (name, x, points)) in VEHICLES.iter().enumerate() {
        let run = start(
            &dir,
            name,
            "fleet_brokers/vehicle.moos",
            &[
                format!("VNAME={name}"),
                format!("VINDEX={}", i + 1),
                "VPORT=0".into(),
                "LISTEN=0".into(),
                format!("SHORE_LISTEN={shore_listen}"),
                format!("MODEM_ID={}", i + 1),
                format!("START_X={x}"),
                "COLOR=yellow".into(),
                format!("POINTS={points}"),
            ],
        );
        taps.push(rt.block_on(tap(
            name,
            run.db_port,
            &["PSHARE_INPUT_SUMMARY", "NODE_BROKER_ACK", "DEPLOY"],
        )));
        runs.push(run);
    }

    // Found: the shoreside counts both vehicles and hears their node reports, which only
    // the routes their brokers asked for at run time carry.
    rt.block_on(until(
        &mut taps,
        &mut heard,
        "both vehicles' NODE_REPORTs at the shoreside",
        |h| {
            let reports = h.texts("shoreside", "NODE_REPORT");
            VEHICLES
                .iter()
                .all(|(v, _, _)| reports.iter().any(|r| r.contains(&format!("NAME={v},"))))
        },
    ));
    rt.block_on(until(
        &mut taps,
        &mut heard,
        "UFSB_NODE_COUNT = 2 at the shoreside",
        |h| {
            h.mail["shoreside"]
                .iter()
                .any(|m| m.key_str() == "UFSB_NODE_COUNT" && m.dval == 2.0)
        },
    ));
    // The shoreside's routes go to the ports the vehicles' pShares picked, learnt from
    // their pings only.
    let cmds = heard.texts("shoreside", "PSHARE_CMD");
    let pings = heard.texts("shoreside", "NODE_BROKER_PING");
    for (run, (v, _, _)) in runs[1..].iter().zip(VEHICLES) {
        let summaries = heard.texts(v, "PSHARE_INPUT_SUMMARY");
        let port = summaries
            .iter()
            .find_map(|s| summary_port(s))
            .unwrap_or_else(|| panic!("{v}'s pShare reported its port: {summaries:?}"));
        assert_ne!(port, shore_listen);
        // The ping names the vehicle's MOOSDB and pShare as bound, and the run's warp.
        let record = format!(
            "community={v},hostip=localhost,port_db={},port_udp={port},pshare_iroutes=localhost:{port},timewarp={WARP},",
            run.db_port
        );
        assert!(
            pings.iter().any(|p| p.starts_with(&record)),
            "{record} in {pings:?}"
        );
        let ack = format!(
            "cmd=output,src_name=NODE_BROKER_ACK_{},dest_name=NODE_BROKER_ACK,route=localhost:{port}",
            v.to_uppercase()
        );
        assert!(cmds.contains(&ack), "{ack} in {cmds:?}");
        let deploy =
            format!("cmd=output,src_name=DEPLOY_ALL,dest_name=DEPLOY,route=localhost:{port}");
        assert!(cmds.contains(&deploy), "{deploy} in {cmds:?}");
        let acks = heard.texts(v, "NODE_BROKER_ACK");
        assert!(
            acks.iter().any(|a| a.starts_with("community=shoreside,")
                && a.contains(&format!(",port_udp={shore_listen},"))),
            "{v} was acknowledged by the shoreside: {acks:?}"
        );
    }

    // The operator's deploy, posted once on the shoreside, reaches both vehicles over UDP.
    taps[0]
        .client
        .notify("DEPLOY_ALL", Value::text("true"))
        .expect("the shoreside takes DEPLOY_ALL");
    rt.block_on(until(
        &mut taps,
        &mut heard,
        "DEPLOY = true from the shoreside on both vehicles",
        |h| {
            VEHICLES.iter().all(|(v, _, _)| {
                h.mail.get(*v).is_some_and(|mail| {
                    mail.iter().any(|m| {
                        m.key_str() == "DEPLOY"
                            && m.sval_str() == "true"
                            && &m.community[..] == b"shoreside"
                    })
                })
            })
        },
    ));

    // Done: every run ends on its own condition (bounded wait, then killed on drop).
    for t in &taps {
        t.client
            .notify("TEST_DONE", Value::text("true"))
            .unwrap_or_else(|e| panic!("{}: TEST_DONE posted: {e}", t.who));
    }
    rt.block_on(async {
        for t in taps {
            t.client.close().await;
        }
    });
    let deadline = Instant::now() + STEP;
    for mut run in runs {
        let status = loop {
            if let Some(s) = run.child.0.try_wait().expect("waits") {
                break s;
            }
            assert!(
                Instant::now() < deadline,
                "{} did not end on TEST_DONE; stderr: {:?}",
                run.name,
                run.stderr.try_iter().collect::<Vec<_>>()
            );
            std::thread::sleep(Duration::from_millis(50));
        };
        assert!(
            status.success(),
            "{}: {status:?}; stderr: {:?}",
            run.name,
            run.stderr.try_iter().collect::<Vec<_>>()
        );
    }
}
