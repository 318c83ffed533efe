//! `coug run --warp 10` on the project's surface mission with the MOOSDB on TCP (loopback,
//! OS-picked port): an independent client of the test (the project's own MOOS client)
//! subscribes to NODE_REPORT_LOCAL and sees the vehicle move. Waits are bounded.

mod common;

use std::io::{BufRead, BufReader};
use std::process::{Command, Stdio};
use std::sync::mpsc;
use std::time::Duration;

use common::*;
use moosdb::{Client, ClientConfig};

/// `X=..` and `Y=..` of a node report.
fn xy(report: &str) -> Option<(f64, f64)> {
    let field = |k: &str| {
        report.split(',').find_map(|kv| {
            let (a, b) = kv.split_once('=')?;
            (a.trim() == k).then(|| b.trim().parse::<f64>().ok())?
        })
    };
    Some((field("X")?, field("Y")?))
}

#[test]
fn warp_10_run_serves_node_reports_to_an_outside_client() {
    let mission = project_mission("surface_survey/survey.moos");
    let dir = fresh_dir("run-realtime");
    let mut child = Command::new(env!("CARGO_BIN_EXE_coug"))
        .current_dir(&dir)
        .args([
            "run",
            mission.to_str().unwrap(),
            "--warp",
            "10",
            "--port",
            "0",
            "--deploy",
            "--max-time",
            "80",
            "--log-dir",
            "logs",
        ])
        .stdout(Stdio::piped())
        .stderr(Stdio::piped())
        .spawn()
        .expect("coug starts");
    let (tx, rx) = mpsc::channel();
    let stderr = child.stderr.take().unwrap();
    let reader = std::thread::spawn(move || {
        let mut all = String::new();
        for line in BufReader::new(stderr).lines().map_while(Result::ok) {
            let _ = tx.send(line.clone());
            all.push_str(&line);
            all.push('\n');
        }
        all
    });
    // The DB announces its OS-picked port.
    let port: u16 = loop {
        let line = rx
            .recv_timeout(Duration::from_secs(60))
            .expect("coug run announces its MOOSDB within 60 s");
        if let Some(rest) = line.split("listening on 127.0.0.1:").nth(1) {
            break rest
                .split_whitespace()
                .next()
                .and_then(|p| p.parse().ok())
                .expect("a port number");
        }
    };
    assert_ne!(port, 0);

    let rt = tokio::runtime::Builder::new_current_thread()
        .enable_all()
        .build()
        .unwrap();
    let positions = rt.block_on(async {
        let mut cc = ClientConfig::new("test_observer", "127.0.0.1", port);
        cc.warp = moosdb::time::Warp::new(10.0).unwrap();
        let (client, mut inbox) = Client::start(cc);
        tokio::time::timeout(Duration::from_secs(30), client.wait_connected())
            .await
            .expect("connects within 30 s")
            .expect("the DB accepts the observer");
        client.register("NODE_REPORT_LOCAL", 0.0);
        let mut positions = Vec::new();
        let deadline = tokio::time::Instant::now() + Duration::from_secs(60);
        while positions.len() < 40 {
            let m = match tokio::time::timeout_at(deadline, inbox.recv()).await {
                Ok(Some(m)) => m,
                _ => break,
            };
            if m.key_str() == "NODE_REPORT_LOCAL"
                && let Some(p) = xy(&m.sval_str())
            {
                positions.push(p);
            }
        }
        client.close().await;
        positions
    });
    let status = child.wait().expect("coug run ends");
    let stderr = reader.join().unwrap();
    let stdout = {
        let mut s = String::new();
        use std::io::Read;
        child.stdout.take().unwrap().read_to_string(&mut s).unwrap();
        s
    };
    assert!(
        positions.len() >= 10,
        "only {} node reports seen\nstderr:\n{}",
        positions.len(),
        tail(&stderr, 20)
    );
    let (x0, y0) = positions[0];
    let moved = positions
        .iter()
        .map(|&(x, y)| (x - x0).hypot(y - y0))
        .fold(0.0, f64::max);
    assert!(
        moved > 10.0,
        "the vehicle moved only {moved} m: {positions:?}"
    );
    assert_eq!(status.code(), Some(0), "stderr:\n{}", tail(&stderr, 20));
    assert!(stdout.contains("max time 80 s reached"), "{stdout}");
    // The run also logged to its alog.
    let log = parse(&std::fs::read(find_alog(&dir.join("logs"))).unwrap());
    assert!(track(&log).len() > 50);
}

#[test]
fn real_time_progress_names_the_active_behaviours_at_any_warp() {
    // The helm writes `active_bhvs` into IVPHELM_SUMMARY only when it changes; at warp 50 the
    // helm posts far faster than the progress line is drawn, so the latest summary alone
    // almost never has the field. The progress follows every posting, as in lockstep.
    let mission = project_mission("surface_survey/survey.moos");
    let dir = fresh_dir("run-realtime-progress");
    let out = coug(
        &dir,
        &[
            "run",
            mission.to_str().unwrap(),
            "--warp",
            "50",
            "--port",
            "0",
            "--deploy",
            "--max-time",
            "60",
            "--log-dir",
            "logs",
        ],
    );
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert_eq!(out.status.code(), Some(0), "{stderr}");
    let late: Vec<&str> = stderr
        .lines()
        .filter(|l| {
            l.strip_prefix("t=")
                .and_then(|r| r.trim_start().split('s').next())
                .and_then(|t| t.trim().parse::<f64>().ok())
                .is_some_and(|t| t >= 10.0)
        })
        .collect();
    assert!(late.len() >= 3, "{stderr}");
    for l in late {
        assert!(l.contains("active=survey,cruise"), "{l}\n{stderr}");
    }
}
