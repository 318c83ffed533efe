//! uFldNodeComms relays acknowledgements in a lockstep fleet (missions/fleet_acks): two
//! vehicles post `ACK_MESSAGE`s to the shoreside at 20, 25 and 55 s; the shoreside's
//! uFldNodeComms posts each as `ACK_MESSAGE_<dest>` (the one at 25 s held back by
//! `min_msg_interval`) and uFldShoreBroker carries it to its vehicle. Two runs write the same
//! bytes in every alog.

mod common;

use std::collections::BTreeMap;

use common::*;

/// `coug run fleet_acks.fleet --lockstep` for 70 s with its logs in `name`'s folder: every
/// community's alog, by community.
fn run(name: &str) -> BTreeMap<String, Vec<u8>> {
    let dir = fresh_dir(name);
    let fleet = project_mission("fleet_acks/fleet_acks.fleet");
    let logs = dir.join("logs");
    let args = [
        "run",
        fleet.to_str().unwrap(),
        "--lockstep",
        "--max-time",
        "70",
    ];
    let out = coug(
        &dir,
        &[&args[..], &["--log-dir", logs.to_str().unwrap()]].concat(),
    );
    let said = String::from_utf8_lossy(&out.stderr);
    // Exit 0: the run reached --max-time, with no --until condition to meet; no warning.
    assert_eq!(out.status.code(), Some(0), "{said}");
    assert!(!said.to_lowercase().contains("warning"), "{said}");
    ["abe", "ben", "shoreside"]
        .into_iter()
        .map(|m| {
            let alog = find_alog(&logs.join(m));
            (m.to_string(), std::fs::read(alog).expect("alog readable"))
        })
        .collect()
}

/// `var`'s string values in `log` written by `source` (any source: `None`).
fn texts(log: &alog::Alog, var: &str, source: Option<&str>) -> Vec<String> {
    log.entries
        .iter()
        .filter(|e| e.var == var && source.is_none_or(|s| e.source == s))
        .filter_map(|e| e.value.as_str().map(str::to_string))
        .collect()
}

#[test]
fn acknowledgements_reach_their_vehicle_through_the_shoreside() {
    // The same folder twice: the alogs name their own path.
    let a = run("run-fleet-acks-1");
    let b = run("run-fleet-acks-1");
    for (name, bytes) in &a {
        assert!(
            *bytes == b[name],
            "two lockstep runs differ in {name}'s alog"
        );
    }
    let shore = parse(&a["shoreside"]);
    for (v, peer) in [("abe", "ben"), ("ben", "abe")] {
        // What the shoreside heard from `peer` (the script's text, its blanks gone as the
        // mission reader drops them), and relayed to `v`: ids 1 and 3, not 2.
        let heard = texts(&shore, "ACK_MESSAGE", None);
        for n in 1..=3 {
            let sent = format!("src={peer},dest={v},id={v}_{n}");
            assert!(heard.contains(&sent), "{sent} not heard: {heard:?}");
        }
        let relayed = texts(&shore, &format!("ACK_MESSAGE_{v}"), Some("uFldNodeComms"));
        let want: Vec<String> = [1, 3]
            .iter()
            .map(|n| format!("id={v}_{n}, src={peer}, dest={v}"))
            .collect();
        assert_eq!(relayed, want, "relayed to {v}");
        // The vehicle got them, as ACK_MESSAGE.
        let mut got = texts(&parse(&a[v]), "ACK_MESSAGE", None);
        got.retain(|s| s.ends_with(&format!("dest={v}")));
        assert_eq!(got, want, "{v}'s ACK_MESSAGE");
    }
}
