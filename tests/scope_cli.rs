//! `coug scope` as uXMS: times since the DB started (never negative), wildcards, `--all`
//! without the status and summary variables, source and community columns, and no colour
//! codes when its output is piped. Against a `coug db` on 127.0.0.1, port 0.

mod common;

use std::time::Duration;

use common::*;
use moosdb::{Client, ClientConfig, Value};

fn scope(dir: &std::path::Path, port: u16, args: &[&str]) -> (String, String) {
    let p = port.to_string();
    let mut all = vec!["scope", "--port", p.as_str(), "--once"];
    all.extend_from_slice(args);
    let out = coug(dir, &all);
    assert_eq!(
        out.status.code(),
        Some(0),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    (
        String::from_utf8_lossy(&out.stdout).into_owned(),
        String::from_utf8_lossy(&out.stderr).into_owned(),
    )
}

#[test]
fn scope_shows_db_times_wildcards_all_and_plain_text() {
    let dir = fresh_dir("scope-cli");
    std::fs::write(dir.join("m.moos"), "ServerPort = 9000\nCommunity = abe\n").unwrap();
    let (_db, port) = spawn_db(&dir, "m.moos");
    // Post three variables, then wait (bounded) until they are in the DB.
    let rt = tokio::runtime::Builder::new_current_thread()
        .enable_all()
        .build()
        .unwrap();
    rt.block_on(async {
        let (client, mut inbox) =
            Client::start(ClientConfig::new("test_poster", "127.0.0.1", port));
        tokio::time::timeout(Duration::from_secs(30), client.wait_connected())
            .await
            .expect("connects")
            .expect("accepted");
        client.notify("NAV_X", Value::Double(12.5)).unwrap();
        client.notify("NAV_Y", Value::Double(-3.0)).unwrap();
        client.notify("FOO", Value::from("bar")).unwrap();
        client.register("FOO", 0.0);
        let deadline = tokio::time::Instant::now() + Duration::from_secs(30);
        loop {
            match tokio::time::timeout_at(deadline, inbox.recv()).await {
                Ok(Some(m)) if m.key_str() == "FOO" => break,
                Ok(Some(_)) => {}
                _ => panic!("FOO never came back"),
            }
        }
        client.close().await;
    });

    // A wildcard: both NAV_ variables, not FOO; times since the DB started, never negative;
    // the source and community columns.
    let (stdout, stderr) = scope(&dir, port, &["NAV_*"]);
    let lines: Vec<&str> = stdout.lines().collect();
    assert!(
        lines[0].starts_with("VarName")
            && lines[0].contains("(S)ource")
            && lines[0].contains("(C)ommunity"),
        "{stdout}"
    );
    let nav: Vec<&&str> = lines.iter().filter(|l| l.starts_with("NAV_")).collect();
    assert_eq!(nav.len(), 2, "{stdout}");
    for l in &nav {
        let cells: Vec<&str> = l.split_whitespace().collect();
        // NAME SOURCE TIME COMMUNITY VALUE
        assert_eq!(cells[1], "test_poster", "{l}");
        let t: f64 = cells[2].parse().unwrap_or_else(|_| panic!("a time in {l}"));
        assert!(t >= 0.0, "{l}");
        assert_eq!(cells[3], "abe", "{l}");
    }
    assert!(!stdout.contains("FOO"));
    for text in [&stdout, &stderr] {
        assert!(
            !text.contains('\u{1b}'),
            "colour codes in piped output: {text:?}"
        );
    }

    // --all: the posted variables and the DB's own, but not *_STATUS or the summaries.
    let (stdout, _) = scope(&dir, port, &["--all"]);
    assert!(
        stdout.contains("FOO") && stdout.contains("NAV_X") && stdout.contains("DB_UPTIME"),
        "{stdout}"
    );
    assert!(
        !stdout.contains("_STATUS") && !stdout.contains("DB_VARSUMMARY"),
        "{stdout}"
    );
    // --show picks the columns.
    let (stdout, _) = scope(&dir, port, &["--show=time", "FOO"]);
    let foo = stdout.lines().find(|l| l.starts_with("FOO")).unwrap();
    assert!(
        !foo.contains("test_poster") && foo.ends_with("\"bar\""),
        "{foo}"
    );
}
