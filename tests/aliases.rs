//! The binary under MOOS names (`coug install-aliases`): every app coug does the job of has a
//! link, `--help` is honoured by each, pLogger/uTimerScript/uPokeDB work as their C++
//! namesakes against a `coug db`; one error style; no file that is not a mission is taken
//! for one.

mod common;

use std::path::{Path, PathBuf};
use std::process::{Child, Command, Stdio};
use std::time::{Duration, Instant};

use common::*;
use moosdb::{Client, ClientConfig};

const NAMES: [&str; 11] = [
    "MOOSDB",
    "pHelmIvP",
    "uSimMarine",
    "uSimMarineV22",
    "pMarinePID",
    "pMarinePIDV22",
    "pNodeReporter",
    "pLogger",
    "uTimerScript",
    "uPokeDB",
    "uXMS",
];

fn install(dir: &Path) -> PathBuf {
    let bin = dir.join("bin");
    let out = coug(dir, &["install-aliases", bin.to_str().unwrap()]);
    assert_eq!(
        out.status.code(),
        Some(0),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    bin
}

/// Waits for `child` at most `secs` (a bound, not a measurement); kills it on timeout.
fn wait_bounded(mut child: Child, secs: u64) -> std::process::Output {
    let deadline = Instant::now() + Duration::from_secs(secs);
    while child.try_wait().unwrap().is_none() {
        if Instant::now() > deadline {
            let _ = child.kill();
            panic!("still running after {secs} s");
        }
        std::thread::sleep(Duration::from_millis(20));
    }
    child.wait_with_output().unwrap()
}

#[test]
fn every_alias_is_linked_and_answers_help_without_starting() {
    let dir = fresh_dir("aliases-help");
    let bin = install(&dir);
    for name in NAMES {
        assert!(bin.join(name).exists(), "{name} linked");
        let child = Command::new(bin.join(name))
            .arg("--help")
            .current_dir(&dir)
            .stdout(Stdio::piped())
            .stderr(Stdio::piped())
            .spawn()
            .unwrap();
        // MOOSDB --help used to start a DB on port 9000 and never end.
        let out = wait_bounded(child, 30);
        assert_eq!(out.status.code(), Some(0), "{name}");
        let text = String::from_utf8_lossy(&out.stdout);
        assert!(text.contains("Usage"), "{name}: {text}");
    }
}

#[test]
fn files_that_are_not_missions_are_refused_with_one_error_style() {
    let dir = fresh_dir("aliases-not-a-mission");
    let bin = install(&dir);
    std::fs::write(
        dir.join("words.moos"),
        "some random words\nand more of them\n",
    )
    .unwrap();
    let expect = "words.moos: not a MOOS mission file";
    for args in [
        vec!["run", "words.moos", "--lockstep"],
        vec!["db", "words.moos", "--port", "0"],
        vec!["poke", "words.moos", "X=1"],
        vec!["helm", "words.moos"],
    ] {
        let child = Command::new(env!("CARGO_BIN_EXE_coug"))
            .args(&args)
            .current_dir(&dir)
            .stdout(Stdio::piped())
            .stderr(Stdio::piped())
            .spawn()
            .unwrap();
        let out = wait_bounded(child, 30);
        let stderr = String::from_utf8_lossy(&out.stderr);
        assert_eq!(out.status.code(), Some(1), "{args:?}: {stderr}");
        assert!(stderr.contains(expect), "{args:?}: {stderr}");
        assert!(stderr.contains(": error: "), "{args:?}: {stderr}");
    }
    let out = Command::new(bin.join("MOOSDB"))
        .arg("words.moos")
        .current_dir(&dir)
        .output()
        .unwrap();
    assert_eq!(out.status.code(), Some(1));
    // User errors: one line style, no anyhow `Caused by:` block, no backtrace.
    let out = Command::new(env!("CARGO_BIN_EXE_coug"))
        .args(["plot", "missing.alog", "-o", "x.svg"])
        .env("RUST_BACKTRACE", "1")
        .current_dir(&dir)
        .output()
        .unwrap();
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert_eq!(out.status.code(), Some(1));
    assert!(stderr.starts_with("coug plot: error: "), "{stderr}");
    assert!(
        !stderr.contains("Caused by") && !stderr.contains("backtrace"),
        "{stderr}"
    );
    assert_eq!(stderr.lines().count(), 1, "{stderr}");
}

#[test]
fn info_says_what_each_command_does() {
    let dir = fresh_dir("aliases-info");
    let out = coug(&dir, &["info"]);
    let text = String::from_utf8_lossy(&out.stdout);
    for cmd in [
        "run",
        "check",
        "plot",
        "db",
        "poke",
        "scope",
        "install-aliases",
        "uXMS",
    ] {
        assert!(text.contains(cmd), "{cmd}: {text}");
    }
}

/// A mission for the logger and timer-script aliases, with its DB on `port`.
fn mission(port: u16) -> String {
    format!(
        "ServerHost = localhost\nServerPort = {port}\nCommunity = abe\n\n\
         ProcessConfig = pLogger\n{{\n  AppTick = 10\n  File = ALIAS\n  PATH = ./logs/\n  WildcardLogging = true\n}}\n\n\
         ProcessConfig = uTimerScript\n{{\n  AppTick = 10\n  event = var=TICKED, val=yes, time=0\n}}\n"
    )
}

#[test]
fn plogger_utimerscript_and_upokedb_aliases_do_their_jobs() {
    let dir = fresh_dir("aliases-apps");
    let bin = install(&dir);
    std::fs::write(dir.join("m.moos"), mission(9000)).unwrap();
    let (db, port) = spawn_db(&dir, "m.moos");
    let mut procs = vec![db];
    std::fs::write(dir.join("m.moos"), mission(port)).unwrap();
    let logger = Command::new(bin.join("pLogger"))
        .arg("m.moos")
        .current_dir(&dir)
        .stdout(Stdio::null())
        .stderr(Stdio::piped())
        .spawn()
        .unwrap();
    // Once the logger is in (its LOGGER_DIRECTORY), start the timer script; once its posting
    // is in the DB, poke through the uPokeDB link; watch for both (bounded waits).
    let rt = tokio::runtime::Builder::new_current_thread()
        .enable_all()
        .build()
        .unwrap();
    let seen = rt.block_on(async {
        let (client, mut inbox) = Client::start(ClientConfig::new("test_watch", "127.0.0.1", port));
        tokio::time::timeout(Duration::from_secs(30), client.wait_connected())
            .await
            .expect("connects")
            .expect("accepted");
        client.register("LOGGER_DIRECTORY", 0.0);
        client.register("PLOGGER_STATUS", 0.0);
        client.register("TICKED", 0.0);
        client.register("POKED", 0.0);
        let mut seen = Vec::new();
        let deadline = tokio::time::Instant::now() + Duration::from_secs(60);
        let mut poked = false;
        // After POKED, two more of the logger's own status posts: its packets since then
        // have brought it the held mail, and it has iterated over it.
        let mut statuses_after = 0;
        while seen.len() < 2 || statuses_after < 2 {
            match tokio::time::timeout_at(deadline, inbox.recv()).await {
                Ok(Some(m)) => {
                    let k = m.key_str().into_owned();
                    if k == "PLOGGER_STATUS" {
                        if seen.len() == 2 {
                            statuses_after += 1;
                        }
                        continue;
                    }
                    if k == "LOGGER_DIRECTORY" {
                        if procs.len() == 1 {
                            let timer = Command::new(bin.join("uTimerScript"))
                                .arg("m.moos")
                                .current_dir(&dir)
                                .stdout(Stdio::null())
                                .stderr(Stdio::null())
                                .spawn()
                                .unwrap();
                            procs.push(KillOnDrop(timer));
                        }
                        continue;
                    }
                    if k == "TICKED" && !poked {
                        poked = true;
                        let st = Command::new(bin.join("uPokeDB"))
                            .args(["m.moos", "POKED=3.5"])
                            .current_dir(&dir)
                            .output()
                            .unwrap();
                        assert_eq!(
                            st.status.code(),
                            Some(0),
                            "{}",
                            String::from_utf8_lossy(&st.stderr)
                        );
                    }
                    if !seen.contains(&k) {
                        seen.push(k);
                    }
                }
                _ => break,
            }
        }
        client.close().await;
        seen
    });
    assert_eq!(seen, ["TICKED", "POKED"]);
    // pLogger ends on SIGTERM with its log flushed: the alog has both, the mission copy is
    // beside it.
    let pid = logger.id().to_string();
    assert!(
        Command::new("kill")
            .args(["-TERM", &pid])
            .status()
            .unwrap()
            .success()
    );
    let out = wait_bounded(logger, 30);
    assert_eq!(
        out.status.code(),
        Some(0),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let session = std::fs::read_dir(dir.join("logs"))
        .unwrap()
        .next()
        .unwrap()
        .unwrap()
        .path();
    let root = session.file_name().unwrap().to_string_lossy().into_owned();
    assert!(root.starts_with("ALIAS_"), "{root}");
    let alog = std::fs::read_to_string(session.join(format!("{root}.alog"))).unwrap();
    assert!(
        alog.lines()
            .any(|l| l.contains(" TICKED ") && l.ends_with("yes ")),
        "{alog}"
    );
    assert!(alog.lines().any(|l| l.contains(" POKED ")), "{alog}");
    assert!(session.join(format!("{root}._moos")).is_file());
}
