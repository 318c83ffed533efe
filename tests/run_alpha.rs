//! `coug run` end to end on the real s1_alpha mission, in lockstep:
//! `--deploy --until "MISSION = complete"` completes, the vehicle passes every survey
//! vertex in order (within the slip radius) and then reaches the return point, two runs
//! write byte-identical alogs, and `coug plot` draws the log.

mod common;

use common::*;

#[test]
fn alpha_completes_in_order_and_logs_are_byte_identical() {
    let mission = corpus("s1_alpha/alpha.moos");
    let args = [
        "--deploy",
        "--until",
        "MISSION = complete",
        "--max-time",
        "1500",
    ];
    let (a, stdout) = run_lockstep("run-alpha-1", &mission, &args);
    let (b, _) = run_lockstep("run-alpha-2", &mission, &args);
    assert!(a.len() > 1_000_000, "alog of {} bytes", a.len());
    assert!(a == b, "two lockstep runs of alpha wrote different alogs");
    assert!(stdout.contains("until condition met"), "{stdout}");
    assert!(stdout.contains("MISSION = \"complete\""), "{stdout}");

    let log = parse(&a);
    let t = track(&log);
    // alpha.bhv: the survey polygon in order (slip radius 15), then 0,-20 (slip radius 8).
    let survey = [
        (60.0, -40.0),
        (60.0, -160.0),
        (150.0, -160.0),
        (180.0, -100.0),
        (150.0, -40.0),
    ];
    let after_survey = visits_in_order(&t, &survey, 15.0, 0);
    visits_in_order(&t, &[(0.0, -20.0)], 8.0, after_survey);
    assert_eq!(last_str(&log, "MISSION").as_deref(), Some("complete"));
    assert_eq!(last_str(&log, "DEPLOY").as_deref(), Some("false"));
    // The external apps of alpha's ANTLER block are skipped with a warning in lockstep.
    check_plots(&a, "run-alpha", false);
}

#[test]
fn max_time_first_exits_2_with_what_is_pending() {
    let mission = corpus("s1_alpha/alpha.moos");
    let dir = fresh_dir("run-alpha-maxtime");
    let m = mission.to_str().unwrap();
    let out = coug(
        &dir,
        &[
            "run",
            m,
            "--lockstep",
            "--deploy",
            "--until",
            "MISSION = complete",
            "--max-time",
            "30",
            "--log-dir",
            "logs",
        ],
    );
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert_eq!(out.status.code(), Some(2), "{stderr}");
    assert!(
        stderr.contains("still pending") && stderr.contains("MISSION = (never posted)"),
        "{stderr}"
    );
    assert!(
        stderr.contains("pMarineViewer is not built into coug; skipped in lockstep"),
        "{stderr}"
    );
    let log = parse(&std::fs::read(find_alog(&dir.join("logs"))).unwrap());
    let end = log.entries.last().unwrap().time;
    assert!((29.0..=31.0).contains(&end), "log ends at {end}");
}

#[test]
fn errors_in_files_exit_1_with_file_and_line() {
    let dir = fresh_dir("run-bad-files");
    std::fs::write(
        dir.join("bad.moos"),
        "ServerPort = 9000\nProcessConfig = ANTLER\n{\n  Run = MOOSDB\n  Run = pHelmIvP\n}\n\
         ProcessConfig = pHelmIvP\n{\n  behaviors = bad.bhv\n}\n",
    )
    .unwrap();
    std::fs::write(
        dir.join("bad.bhv"),
        "initialize DEPLOY = false\nBehavior = BHV_Waypoint\n{\n  name = w\n  condition = DEPLOY ==\n}\n",
    )
    .unwrap();
    let out = coug(
        &dir,
        &["run", "bad.moos", "--lockstep", "--log-dir", "logs"],
    );
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert_eq!(out.status.code(), Some(1), "{stderr}");
    assert!(stderr.contains("bad.bhv:5"), "{stderr}");
    let out = coug(
        &dir,
        &["run", "missing.moos", "--lockstep", "--log-dir", "logs"],
    );
    assert_eq!(out.status.code(), Some(1));
    let alpha = corpus("s1_alpha/alpha.moos");
    let out = coug(
        &dir,
        &[
            "run",
            alpha.to_str().unwrap(),
            "--lockstep",
            "--until",
            "X = = =",
        ],
    );
    assert_eq!(out.status.code(), Some(1));
    assert!(String::from_utf8_lossy(&out.stderr).contains("--until"));
}
