//! `coug emulate`: the DVL emulator announces its TCP endpoint, serves A50 reports to a
//! client, and ends cleanly on SIGINT with its summary; bad arguments are refused.

mod common;

use std::io::{BufRead, BufReader};
use std::process::{Command, Stdio};
use std::time::Duration;

use common::*;

#[test]
fn dvl_serves_reports_and_stops_on_sigint() {
    let dir = fresh_dir("emulate-dvl");
    let mut child = Command::new(env!("CARGO_BIN_EXE_coug"))
        .current_dir(&dir)
        .args(["emulate", "dvl", "--tcp", "0", "--seed", "3"])
        .stdout(Stdio::piped())
        .stderr(Stdio::null())
        .spawn()
        .expect("coug emulate starts");
    let out = child.stdout.take().expect("piped stdout");
    let (tx, rx) = std::sync::mpsc::channel();
    std::thread::spawn(move || {
        for line in BufReader::new(out).lines().map_while(Result::ok) {
            let _ = tx.send(line);
        }
    });
    let first = rx
        .recv_timeout(Duration::from_secs(60))
        .expect("the endpoint within 60 s");
    let addr = first
        .strip_prefix("coug emulate dvl: tcp ")
        .unwrap_or_else(|| panic!("{first}"))
        .to_string();
    let stream = std::net::TcpStream::connect(&addr).unwrap();
    stream
        .set_read_timeout(Some(Duration::from_secs(60)))
        .unwrap();
    let mut lines = BufReader::new(stream).lines();
    let report = lines.next().expect("a report").unwrap();
    assert!(
        report.starts_with('{')
            && (report.contains("\"type\":\"velocity\"")
                || report.contains("\"type\":\"position_local\"")),
        "{report}"
    );
    let pid = child.id().to_string();
    assert!(
        Command::new("kill")
            .args(["-INT", &pid])
            .status()
            .unwrap()
            .success()
    );
    let status = child.wait().unwrap();
    assert_eq!(status.code(), Some(0));
    let summary = rx
        .recv_timeout(Duration::from_secs(60))
        .expect("a summary line");
    assert!(summary.contains("1 connection(s)"), "{summary}");
}

#[test]
fn unknown_devices_and_faults_are_refused() {
    let dir = fresh_dir("emulate-bad");
    let out = coug(&dir, &["emulate", "sonar"]);
    assert_eq!(out.status.code(), Some(1));
    assert!(String::from_utf8_lossy(&out.stderr).contains("unknown device"));
    let out = coug(&dir, &["emulate", "gps", "--fault", "dropout@5"]);
    assert_eq!(out.status.code(), Some(1));
    assert!(String::from_utf8_lossy(&out.stderr).contains("needs '+DURATION'"));
}
