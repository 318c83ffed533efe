//! `coug run` end to end on the real s1_alpha mission, in lockstep:
//! `--deploy --until "MISSION = complete"` completes, the vehicle passes every survey
//! vertex in order (within the slip radius) and then reaches the return point, two runs
//! write byte-identical alogs, and `coug plot` draws the log.

mod common;

use common::*;

#[test]
fn alpha_completes_in_order_and_logs_are_byte_identical() {
    let mission = test_support::mission_file("s1_alpha/alpha.moos");
    let opts = deploy_until("MISSION = complete", 1500.0);
    let (a, stdout) = run_lockstep("run-alpha-1", &mission, &[], opts.clone());
    let (b, _) = run_lockstep("run-alpha-1", &mission, &[], opts);
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
    let mission = test_support::mission_file("s1_alpha/alpha.moos");
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
fn a_bad_behaviour_file_runs_the_helm_in_malconfig_and_bad_arguments_exit_1() {
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
    // A bad behaviour file is a helm configuration error: as pHelmIvP, the helm runs in
    // MALCONFIG (never drives) and says why; the run goes on to its end.
    let out = coug(
        &dir,
        &[
            "run",
            "bad.moos",
            "--lockstep",
            "--log-dir",
            "logs",
            "--until",
            "DEPLOY = true",
            "--max-time",
            "20",
        ],
    );
    let stderr = String::from_utf8_lossy(&out.stderr);
    let stdout = String::from_utf8_lossy(&out.stdout);
    assert_eq!(out.status.code(), Some(2), "{stderr}");
    assert!(
        stderr.contains("MALCONFIG") && stderr.contains("bad.bhv:5"),
        "{stderr}"
    );
    assert!(stdout.contains("helm state:  MALCONFIG"), "{stdout}");
    assert!(
        stdout.contains("malconfig:   ") && stdout.contains("bad.bhv:5"),
        "{stdout}"
    );
    let log = parse(&std::fs::read(find_alog(&dir.join("logs"))).unwrap());
    let states: Vec<&str> = log
        .entries
        .iter()
        .filter(|e| e.var == "IVPHELM_STATE")
        .filter_map(|e| e.value.as_str())
        .collect();
    assert!(
        states.len() > 10 && states.iter().all(|s| *s == "MALCONFIG"),
        "{states:?}"
    );
    assert!(
        !log.entries.iter().any(|e| e.var.starts_with("DESIRED_")),
        "a MALCONFIG helm posted a decision"
    );
    std::fs::remove_dir_all(dir.join("logs")).unwrap();
    let out = coug(
        &dir,
        &["run", "missing.moos", "--lockstep", "--log-dir", "logs"],
    );
    assert_eq!(out.status.code(), Some(1));
    let alpha = test_support::mission_file("s1_alpha/alpha.moos");
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
