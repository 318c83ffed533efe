//! `coug view`'s command line: a non-loopback bind without a token is refused before anything
//! is bound or joined; the help names every option.

mod common;

use common::*;

#[test]
fn non_loopback_bind_without_token_is_refused() {
    let dir = fresh_dir("view-cli");
    let out = coug(&dir, &["view", "--bind", "0.0.0.0", "--http-port", "0"]);
    assert_eq!(out.status.code(), Some(1));
    let err = String::from_utf8_lossy(&out.stderr);
    assert!(
        err.contains("coug view: error:") && err.contains("needs a token"),
        "{err}"
    );
}

#[test]
fn help_names_the_options() {
    let dir = fresh_dir("view-help");
    let out = coug(&dir, &["view", "--help"]);
    let text = String::from_utf8_lossy(&out.stdout);
    for opt in [
        "MISSION.moos",
        "--host",
        "--port",
        "--http-port",
        "--bind",
        "--token",
    ] {
        assert!(text.contains(opt), "{opt}: {text}");
    }
}

#[test]
fn base_help_names_the_options_and_a_missing_db_is_an_error() {
    let dir = fresh_dir("base-help");
    let out = coug(&dir, &["base", "--help"]);
    let text = String::from_utf8_lossy(&out.stdout);
    for opt in ["MISSION.moos", "--host", "--port", "--timeout"] {
        assert!(text.contains(opt), "{opt}: {text}");
    }
    // Nothing listens on port 1: the base says so and exits 1 before touching the terminal.
    let out = coug(
        &dir,
        &[
            "base",
            "--host",
            "127.0.0.1",
            "--port",
            "1",
            "--timeout",
            "0",
        ],
    );
    assert_eq!(out.status.code(), Some(1));
    let err = String::from_utf8_lossy(&out.stderr);
    assert!(err.contains("coug base: error:"), "{err}");
}

/// `coug run --view` keeps serving the page after the run ends, until SIGINT. No clock in
/// the test: it reads the run's stderr until the line saying the run ended, then fetches the
/// page (the server must still answer), then sends SIGINT and waits for the exit (code 0,
/// the run's report on stdout). The receive timeouts only bound a hung binary.
#[test]
fn run_view_serves_after_the_run_until_sigint() {
    use std::io::{BufRead, BufReader, Read, Write};
    use std::process::{Command, Stdio};
    use std::time::Duration;

    let dir = fresh_dir("run-view-after");
    let alpha = test_support::mission_file("s1_alpha/alpha.moos");
    let logs = dir.join("logs");
    let mut child = Command::new(env!("CARGO_BIN_EXE_coug"))
        .current_dir(&dir)
        .arg("run")
        .arg(&alpha)
        .args(["--lockstep", "--deploy", "--max-time", "20", "--view"])
        .args(["--http-port", "0", "--log-dir"])
        .arg(&logs)
        .stdout(Stdio::piped())
        .stderr(Stdio::piped())
        .spawn()
        .expect("coug run starts");
    let err = child.stderr.take().expect("piped stderr");
    let (tx, rx) = std::sync::mpsc::channel();
    std::thread::spawn(move || {
        for line in BufReader::new(err).lines().map_while(Result::ok) {
            let _ = tx.send(line);
        }
    });
    let mut addr = None;
    loop {
        let line = rx
            .recv_timeout(Duration::from_secs(300))
            .expect("the run's stderr");
        if let Some(rest) = line.strip_prefix("coug run: viewer at http://") {
            addr = Some(rest.trim_end_matches('/').to_string());
        }
        if line.contains("the run ended; the viewer stays up until Ctrl-C") {
            break;
        }
    }
    let addr = addr.expect("the viewer's address before the run ended");
    let mut stream = std::net::TcpStream::connect(&addr).expect("the viewer still listens");
    stream
        .set_read_timeout(Some(Duration::from_secs(60)))
        .unwrap();
    write!(
        stream,
        "GET / HTTP/1.1\r\nHost: {addr}\r\nConnection: close\r\n\r\n"
    )
    .unwrap();
    let mut page = String::new();
    stream.read_to_string(&mut page).unwrap();
    assert!(page.starts_with("HTTP/1.1 200"), "{page}");
    assert!(page.contains("viewer.js"), "{page}");
    assert!(child.try_wait().unwrap().is_none(), "still running");
    let pid = child.id().to_string();
    assert!(
        Command::new("kill")
            .args(["-INT", &pid])
            .status()
            .unwrap()
            .success()
    );
    let mut out = String::new();
    child
        .stdout
        .take()
        .unwrap()
        .read_to_string(&mut out)
        .unwrap();
    let status = child.wait().unwrap();
    assert_eq!(status.code(), Some(0), "stdout: {out}");
    assert!(out.contains(".alog"), "the run's report: {out}");
}

#[test]
fn view_warns_of_a_background_it_cannot_find() {
    let dir = fresh_dir("view-background");
    std::fs::write(
        dir.join("m.moos"),
        "ServerHost = 127.0.0.1\nServerPort = 1\nLatOrigin = 43.8253\nLongOrigin = -70.3304\n\
         ProcessConfig = pMarineViewer\n{\n  tiff_file = nowhere.tif\n}\n",
    )
    .unwrap();
    // No DB on port 1: the view ends with an error, after the warning.
    let out = coug(
        &dir,
        &["view", "m.moos", "--http-port", "0", "--timeout", "0"],
    );
    let err = String::from_utf8_lossy(&out.stderr);
    assert!(
        err.contains("coug view: warning: m.moos: background image not found: nowhere.tif"),
        "{err}"
    );
    assert_eq!(out.status.code(), Some(1), "{err}");
}
