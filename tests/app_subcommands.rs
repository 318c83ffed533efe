//! `coug helm|sim|pid|nodereporter MISSION.moos [ALIAS]`: the single apps by subcommand,
//! each its own MOOS client of a `coug db`, under the MOOS name pAntler would give them
//! (the variant the mission's ANTLER block runs; the alias when one is given).

mod common;

use std::collections::BTreeSet;
use std::process::{Command, Stdio};
use std::time::Duration;

use common::*;
use moosdb::{Client, ClientConfig};

fn mission_with_port(port: u16) -> String {
    let text = std::fs::read_to_string(test_support::mission_file("s1_alpha/alpha.moos")).unwrap();
    text.lines()
        .map(|l| {
            if l.trim_start().starts_with("ServerPort") {
                format!("ServerPort = {port}")
            } else {
                l.to_string()
            }
        })
        .collect::<Vec<_>>()
        .join("\n")
}

#[test]
fn subcommands_join_the_db_under_their_moos_names() {
    let dir = fresh_dir("app-subcommands");
    std::fs::copy(
        test_support::mission_file("s1_alpha/alpha.bhv"),
        dir.join("alpha.bhv"),
    )
    .unwrap();
    std::fs::write(dir.join("alpha.moos"), mission_with_port(9000)).unwrap();
    let (db, port) = spawn_db(&dir, "alpha.moos");
    let mut procs = vec![db];
    std::fs::write(dir.join("alpha.moos"), mission_with_port(port)).unwrap();
    for args in [
        vec!["helm", "alpha.moos"],
        vec!["sim", "alpha.moos"],
        vec!["pid", "alpha.moos"],
        vec!["nodereporter", "alpha.moos", "pNodeReporter_2"],
    ] {
        let c = Command::new(env!("CARGO_BIN_EXE_coug"))
            .current_dir(&dir)
            .args(&args)
            .stdout(Stdio::null())
            .stderr(Stdio::null())
            .spawn()
            .unwrap();
        procs.push(KillOnDrop(c));
    }
    let expected: BTreeSet<&str> = [
        "PHELMIVP_STATUS",
        "USIMMARINEV22_STATUS",
        "PMARINEPIDV22_STATUS",
        "PNODEREPORTER_2_STATUS",
    ]
    .into_iter()
    .collect();
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
        for v in &expected {
            client.register(v, 0.0);
        }
        let mut seen = BTreeSet::new();
        let deadline = tokio::time::Instant::now() + Duration::from_secs(60);
        while seen.len() < expected.len() {
            match tokio::time::timeout_at(deadline, inbox.recv()).await {
                Ok(Some(m)) => {
                    seen.insert(m.key_str().into_owned());
                }
                _ => break,
            }
        }
        client.close().await;
        seen
    });
    let seen: BTreeSet<&str> = seen.iter().map(String::as_str).collect();
    assert_eq!(seen, expected);
}

#[test]
fn a_subcommand_without_a_mission_exits_1_with_usage() {
    let dir = fresh_dir("app-usage");
    let out = coug(&dir, &["helm"]);
    assert_eq!(out.status.code(), Some(1));
    assert!(String::from_utf8_lossy(&out.stderr).contains("usage: coug helm MISSION.moos"));
}
