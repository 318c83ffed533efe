//! Small MOOS missions written by the tests themselves (no corpus), and the one way the
//! end-to-end tests read a `coug` child's stderr line by line.
//!
//! ```
//! let m = test_support::missions::community(
//!     "alpha",
//!     9000,
//!     &[("pLogger", test_support::missions::WILDCARD_LOGGER), ("uTimerScript", "  AppTick = 4\n")],
//! );
//! assert!(m.starts_with("ServerHost = localhost\nServerPort = 9000\nCommunity = alpha\n"));
//! assert!(m.contains("  Run = uTimerScript @ NewConsole = false\n}\n"));
//! assert!(m.ends_with("ProcessConfig = uTimerScript\n{\n  AppTick = 4\n}\n"));
//! assert_eq!(test_support::missions::counting_events("P", 2), "  event = var=P, val=1, time=1\n  event = var=P, val=2, time=2\n");
//! ```

use std::io::{BufRead, BufReader};
use std::process::{Child, Command, Stdio};
use std::sync::mpsc;

/// pLogger's block body in the tests' small missions: AppTick 10, every variable logged.
pub const WILDCARD_LOGGER: &str = "  AppTick = 10\n  WildCardLogging = true\n";

/// A community's mission: `ServerHost = localhost`, `port`, `community`, an ANTLER block
/// running the MOOSDB and each app of `blocks` in order, then each app's `ProcessConfig`
/// block with its body (lines ending in a newline).
pub fn community(community: &str, port: u16, blocks: &[(&str, &str)]) -> String {
    let mut s = format!(
        "ServerHost = localhost\nServerPort = {port}\nCommunity = {community}\n\
         ProcessConfig = ANTLER\n{{\n  Run = MOOSDB @ NewConsole = false\n"
    );
    for (app, _) in blocks {
        s.push_str(&format!("  Run = {app} @ NewConsole = false\n"));
    }
    s.push_str("}\n");
    for (app, body) in blocks {
        s.push_str(&format!("ProcessConfig = {app}\n{{\n{body}}}\n"));
    }
    s
}

/// A pShare test community on port 9000: pLogger logging everything, uTimerScript at AppTick
/// 4 with `script` (its event lines) and pShare at AppTick 4 with `share` (its lines).
pub fn pshare_community(name: &str, share: &str, script: &str) -> String {
    community(
        name,
        9000,
        &[
            ("pLogger", WILDCARD_LOGGER),
            ("uTimerScript", &format!("  AppTick = 4\n{script}")),
            ("pShare", &format!("  AppTick = 4\n{share}")),
        ],
    )
}

/// uTimerScript event lines posting `var` = k at k seconds, for k from 1 to `n`.
pub fn counting_events(var: &str, n: u32) -> String {
    (1..=n)
        .map(|k| format!("  event = var={var}, val={k}, time={k}\n"))
        .collect()
}

/// Starts `cmd` (a `coug` run) with its stdout discarded and its stderr read line by line on
/// a thread of its own: the child and the lines as they come.
pub fn spawn_reading_stderr(cmd: &mut Command) -> (Child, mpsc::Receiver<String>) {
    let mut child = cmd
        .stdout(Stdio::null())
        .stderr(Stdio::piped())
        .spawn()
        .expect("coug starts");
    let (tx, rx) = mpsc::channel();
    let stderr = child.stderr.take().expect("a piped stderr");
    std::thread::spawn(move || {
        for line in BufReader::new(stderr).lines().map_while(Result::ok) {
            if tx.send(line).is_err() {
                break;
            }
        }
    });
    (child, rx)
}
