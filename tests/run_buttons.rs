//! Mission buttons: stock missions say what "start" means in pMarineViewer's buttons.
//! s7_golf's DEPLOY button also sets SURVEY=true; `--deploy` presses it (or `--button DEPLOY`),
//! so the vehicle surveys and returns home, in lockstep.

mod common;

use common::*;

/// Runs golf in lockstep with `press` until it is home again; returns the log.
fn golf(name: &str, press: RunOptions) -> alog::Alog {
    let mission = test_support::mission_file("s7_golf/golf.moos");
    let opts = RunOptions {
        until: Some("RETURNING = false".into()),
        max_time: 1500.0,
        ..press
    };
    let (bytes, stdout) = run_lockstep(name, &mission, &[], opts);
    assert!(stdout.contains("until condition met"), "{stdout}");
    parse(&bytes)
}

fn assert_surveyed_and_home(log: &alog::Alog) {
    assert!(
        log.entries
            .iter()
            .any(|e| e.var == "MODE" && e.value.as_str() == Some("ACTIVE:SURVEYING")),
        "the DEPLOY button's SURVEY=true starts the survey"
    );
    let t = track(log);
    // The lawnmower is centred on (80,-80), 70 x 30 m: the track reaches it...
    let reached = t.iter().any(|&(_, x, y)| (x - 80.0).hypot(y + 80.0) < 30.0);
    assert!(reached, "never reached the survey area");
    // ...and ends home at (0,0), within the return waypoint's slip radius (8 m).
    let &(_, x, y) = t.last().unwrap();
    assert!(x.hypot(y) < 8.0, "ended at {x},{y}");
}

#[test]
fn deploy_presses_the_missions_deploy_button() {
    let log = golf(
        "golf-deploy",
        RunOptions {
            deploy: true,
            ..RunOptions::default()
        },
    );
    assert_surveyed_and_home(&log);
}

#[test]
fn button_by_label_and_unknown_buttons_are_named() {
    let log = golf(
        "golf-button",
        RunOptions {
            buttons: vec!["deploy".into()],
            ..RunOptions::default()
        },
    );
    assert_surveyed_and_home(&log);
    let dir = fresh_dir("golf-no-button");
    let m = test_support::mission_file("s7_golf/golf.moos");
    let out = coug(
        &dir,
        &[
            "run",
            m.to_str().unwrap(),
            "--lockstep",
            "--button",
            "LAUNCH",
        ],
    );
    assert_eq!(out.status.code(), Some(1));
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert!(
        stderr.contains(
            "--button LAUNCH: no such button; the mission's buttons: DEPLOY, RETURN, THREAT-DETECT"
        ),
        "{stderr}"
    );
    assert!(!dir.join("logs").exists());
}
