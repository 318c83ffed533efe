//! `coug emulate`: the DVL emulator announces its TCP endpoint, serves A50 reports to a
//! client, and ends cleanly on SIGINT with its summary; the GPS, the X150 and the Teensy do
//! the same on pseudo-terminals; bad arguments are refused.

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

/// `coug emulate gps|seatrac|teensy --link PATH`: each serial device announces its
/// pseudo-terminal, serves its wire protocol on it to whoever opens the link (NMEA sentences
/// with their checksums, the Teensy's telemetry lines, the X150's answer to an alive
/// command), and ends cleanly on SIGINT with its summary. Every wait is bounded.
#[test]
fn serial_devices_serve_their_protocols_on_a_pty() {
    use std::io::{Read, Write};
    for device in ["gps", "seatrac", "teensy"] {
        let dir = fresh_dir(&format!("emulate-{device}-pty"));
        let link = dir.join(device);
        let mut child = Command::new(env!("CARGO_BIN_EXE_coug"))
            .current_dir(&dir)
            .args([
                "emulate",
                device,
                "--link",
                link.to_str().unwrap(),
                "--seed",
                "5",
            ])
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
        assert!(
            first.starts_with(&format!("coug emulate {device}: pty /dev/")),
            "{first}"
        );
        let mut port = std::fs::OpenOptions::new()
            .read(true)
            .write(true)
            .open(&link)
            .unwrap_or_else(|e| panic!("{device}: the link {}: {e}", link.display()));
        if device == "seatrac" {
            // CID_SYS_ALIVE: '#', the CID in hex, CRC-16/ARC of [0x01] low byte first.
            port.write_all(b"#01C1C0\r\n").unwrap();
        }
        let (ltx, lrx) = std::sync::mpsc::channel();
        std::thread::spawn(move || {
            let mut buf = [0u8; 512];
            let mut text = String::new();
            while let Ok(n) = port.read(&mut buf) {
                if n == 0 {
                    break;
                }
                text.push_str(&String::from_utf8_lossy(&buf[..n]));
                while let Some(i) = text.find('\n') {
                    let line: String = text.drain(..=i).collect();
                    if ltx.send(line.trim_end().to_string()).is_err() {
                        return;
                    }
                }
            }
        });
        let mut seen = Vec::new();
        let ok = |l: &str| match device {
            // A whole sentence: `$..*HH` with the XOR of what lies between.
            "gps" => {
                l.starts_with('$') && {
                    let (body, sum) = l[1..].rsplit_once('*').unwrap_or(("", ""));
                    let x = body.bytes().fold(0u8, |a, b| a ^ b);
                    sum == format!("{x:02X}")
                }
            }
            "teensy" => l.starts_with("$DEPTH,") || l.starts_with("$BATTE,"),
            _ => l.starts_with("$01"),
        };
        loop {
            let line = lrx
                .recv_timeout(Duration::from_secs(60))
                .unwrap_or_else(|_| panic!("{device}: no expected line within 60 s: {seen:?}"));
            if ok(&line) {
                break;
            }
            seen.push(line);
            assert!(seen.len() < 200, "{device}: {seen:?}");
        }
        let pid = child.id().to_string();
        assert!(
            Command::new("kill")
                .args(["-INT", &pid])
                .status()
                .unwrap()
                .success()
        );
        assert_eq!(child.wait().unwrap().code(), Some(0), "{device}");
        let summary = rx
            .recv_timeout(Duration::from_secs(60))
            .expect("a summary line");
        assert!(summary.contains("bytes out"), "{device}: {summary}");
    }
}
