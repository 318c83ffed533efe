//! Swap-in: the embedded DB alone (`coug db`) plus `pHelmIvP`, `uSimMarineV22`,
//! `pMarinePIDV22` and `pNodeReporter` started as separate processes through the links of
//! `coug install-aliases` (as pAntler starts them: `APP MISSION.moos`), complete the real
//! alpha mission in real time at a warp. The test's own MOOS client deploys the vehicle
//! and watches it. Loopback only, OS-picked DB port, bounded waits.

mod common;

use std::io::{BufRead, BufReader};
use std::path::Path;
use std::process::{Child, Command, Stdio};
use std::sync::mpsc;
use std::time::Duration;

use common::*;
use moosdb::{Client, ClientConfig, Value};

/// Kills the processes this test started when it ends, pass or fail.
struct Procs(Vec<Child>);

impl Drop for Procs {
    fn drop(&mut self) {
        for c in &mut self.0 {
            let _ = c.kill();
            let _ = c.wait();
        }
    }
}

const WARP: f64 = 20.0;

/// alpha.moos with a warp and a port of our choosing (other lines unchanged).
fn write_mission(dir: &Path, port: u16) {
    let text = std::fs::read_to_string(test_support::mission_file("s1_alpha/alpha.moos")).unwrap();
    let mut out = String::new();
    for line in text.lines() {
        let t = line.trim_start();
        if t.starts_with("ServerPort") {
            out.push_str(&format!("ServerPort   = {port}\n"));
        } else if t.starts_with("MOOSTimeWarp") {
            out.push_str(&format!("MOOSTimeWarp = {WARP}\n"));
        } else {
            out.push_str(line);
            out.push('\n');
        }
    }
    std::fs::write(dir.join("alpha.moos"), out).unwrap();
}

#[test]
fn alias_links_run_alpha_as_separate_processes() {
    let dir = fresh_dir("run-swapin");
    std::fs::copy(
        test_support::mission_file("s1_alpha/alpha.bhv"),
        dir.join("alpha.bhv"),
    )
    .unwrap();
    let bin = dir.join("bin");
    let out = coug(&dir, &["install-aliases", bin.to_str().unwrap()]);
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    for app in [
        "MOOSDB",
        "pHelmIvP",
        "uSimMarineV22",
        "pMarinePIDV22",
        "pNodeReporter",
    ] {
        assert!(bin.join(app).exists(), "no link {app}");
    }

    // The DB reads the warp from the mission and takes an OS-picked port.
    write_mission(&dir, 9000);
    let mut procs = Procs(Vec::new());
    let mut db = Command::new(env!("CARGO_BIN_EXE_coug"))
        .current_dir(&dir)
        .args(["db", "alpha.moos", "--port", "0"])
        .stdout(Stdio::piped())
        .stderr(Stdio::null())
        .spawn()
        .expect("coug db starts");
    let stdout = db.stdout.take().unwrap();
    procs.0.push(db);
    let (tx, rx) = mpsc::channel();
    std::thread::spawn(move || {
        for line in BufReader::new(stdout).lines().map_while(Result::ok) {
            let _ = tx.send(line);
        }
    });
    let port: u16 = loop {
        let line = rx
            .recv_timeout(Duration::from_secs(60))
            .expect("coug db announces its port within 60 s");
        if let Some(rest) = line.split("listening on 127.0.0.1:").nth(1) {
            break rest.split_whitespace().next().unwrap().parse().unwrap();
        }
    };
    // The apps read the port from the mission, as under pAntler.
    write_mission(&dir, port);
    for app in [
        "uSimMarineV22",
        "pMarinePIDV22",
        "pHelmIvP",
        "pNodeReporter",
    ] {
        let child = Command::new(bin.join(app))
            .current_dir(&dir)
            .arg("alpha.moos")
            .stdout(Stdio::null())
            .stderr(Stdio::null())
            .spawn()
            .unwrap_or_else(|e| panic!("{app} starts through its link: {e}"));
        procs.0.push(child);
    }

    let rt = tokio::runtime::Builder::new_current_thread()
        .enable_all()
        .build()
        .unwrap();
    let (track, complete, report) = rt.block_on(async {
        let mut cc = ClientConfig::new("test_observer", "127.0.0.1", port);
        cc.warp = moosdb::time::Warp::new(WARP).unwrap();
        let (client, mut inbox) = Client::start(cc);
        tokio::time::timeout(Duration::from_secs(30), client.wait_connected())
            .await
            .expect("connects within 30 s")
            .expect("accepted");
        for v in [
            "NAV_X",
            "NAV_Y",
            "MISSION",
            "IVPHELM_STATE",
            "NODE_REPORT_LOCAL",
        ] {
            client.register(v, 0.0);
        }
        let deadline = tokio::time::Instant::now() + Duration::from_secs(240);
        let mut deployed = false;
        let (mut x, mut y) = (None, None);
        let mut track = Vec::new();
        let mut complete = false;
        let mut report = false;
        while let Ok(Some(m)) = tokio::time::timeout_at(deadline, inbox.recv()).await {
            match m.key_str().as_ref() {
                // The helm is up: deploy, as uPokeDB would.
                "IVPHELM_STATE" if !deployed => {
                    client.notify("DEPLOY", Value::from("true")).expect("poke");
                    client
                        .notify("MOOS_MANUAL_OVERRIDE", Value::from("false"))
                        .expect("poke");
                    deployed = true;
                }
                "NAV_X" => x = Some(m.dval),
                "NAV_Y" => y = Some(m.dval),
                "NODE_REPORT_LOCAL" => report = true,
                "MISSION" if m.sval_str() == "complete" => {
                    complete = true;
                    break;
                }
                _ => {}
            }
            if let (Some(x), Some(y)) = (x, y) {
                track.push((0.0, x, y));
            }
        }
        client.close().await;
        (track, complete, report)
    });
    assert!(complete, "MISSION = complete not seen within 240 s");
    assert!(report, "pNodeReporter published no NODE_REPORT_LOCAL");
    let survey = [
        (60.0, -40.0),
        (60.0, -160.0),
        (150.0, -160.0),
        (180.0, -100.0),
        (150.0, -40.0),
    ];
    let after = visits_in_order(&track, &survey, 15.0, 0);
    visits_in_order(&track, &[(0.0, -20.0)], 8.0, after);
}
