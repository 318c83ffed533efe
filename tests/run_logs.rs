//! Where `coug run` writes its logs: named from the wall-clock start, never over an existing
//! log, and nothing at all on disk when the mission fails before it starts.

mod common;

use std::path::{Path, PathBuf};

use common::*;

/// Every `.alog` under `dir`, sorted.
fn alogs(dir: &Path) -> Vec<PathBuf> {
    let mut found = Vec::new();
    let mut stack = vec![dir.to_path_buf()];
    while let Some(d) = stack.pop() {
        for e in std::fs::read_dir(&d).into_iter().flatten().flatten() {
            let p = e.path();
            if p.is_dir() {
                stack.push(p);
            } else if p.extension().is_some_and(|x| x == "alog") {
                found.push(p);
            }
        }
    }
    found.sort();
    found
}

fn survey_run(dir: &Path) {
    let m = project_mission("surface_survey/survey.moos");
    let out = coug(
        dir,
        &[
            "run",
            m.to_str().unwrap(),
            "--lockstep",
            "--deploy",
            "--max-time",
            "30",
            "--log-dir",
            "logs",
        ],
    );
    assert_eq!(
        out.status.code(),
        Some(0),
        "runs to --max-time: {}",
        String::from_utf8_lossy(&out.stderr)
    );
}

#[test]
fn two_lockstep_runs_into_one_folder_keep_both_logs_with_identical_contents() {
    let dir = fresh_dir("run-logs-twice");
    survey_run(&dir);
    survey_run(&dir);
    let logs = alogs(&dir.join("logs"));
    assert_eq!(logs.len(), 2, "both logs kept: {logs:?}");
    let (a, b) = (
        std::fs::read(&logs[0]).unwrap(),
        std::fs::read(&logs[1]).unwrap(),
    );
    assert!(a.len() > 10_000, "{} bytes", a.len());
    assert!(
        a == b,
        "lockstep contents are byte-identical, only the names differ"
    );
    // Named from the wall clock, not from the virtual start date (6 Aug 2026).
    for l in &logs {
        let name = l.file_name().unwrap().to_string_lossy();
        assert!(!name.contains("_6_8_2026_____"), "{name}");
        let year = chrono_year_of(&name);
        assert!(year >= 2026, "{name}");
    }
}

/// The year in a pLogger name `STEM_D_M_YYYY_____HH_MM_SS[.alog]`.
fn chrono_year_of(name: &str) -> i32 {
    let date = name.split("_____").next().unwrap();
    date.rsplit('_').next().unwrap().parse().unwrap()
}

#[test]
fn a_mission_that_fails_to_start_creates_and_touches_nothing() {
    let dir = fresh_dir("run-logs-failed");
    // An earlier log in the folder the failing run would use.
    let earlier = dir.join("logs/MOOSLog_1_1_2026_____00_00_00/MOOSLog_1_1_2026_____00_00_00.alog");
    std::fs::create_dir_all(earlier.parent().unwrap()).unwrap();
    std::fs::write(&earlier, "%% an earlier log\n").unwrap();
    std::fs::write(dir.join("bad.moos"), "ServerPort = 9000\nCommunity = abe\n").unwrap();
    let before: Vec<PathBuf> = std::fs::read_dir(&dir)
        .unwrap()
        .flatten()
        .map(|e| e.path())
        .collect();
    for extra in [&["--log-dir", "logs"][..], &[][..]] {
        let mut args = vec!["run", "bad.moos", "--lockstep"];
        args.extend_from_slice(extra);
        let out = coug(&dir, &args);
        assert_eq!(out.status.code(), Some(1));
        assert!(String::from_utf8_lossy(&out.stderr).contains("ANTLER"));
    }
    let after: Vec<PathBuf> = std::fs::read_dir(&dir)
        .unwrap()
        .flatten()
        .map(|e| e.path())
        .collect();
    assert_eq!(before.len(), after.len(), "no coug-run-* folder: {after:?}");
    assert_eq!(alogs(&dir.join("logs")), std::slice::from_ref(&earlier));
    assert_eq!(
        std::fs::read_to_string(&earlier).unwrap(),
        "%% an earlier log\n"
    );
}

/// The surface survey with its pLogger block's settings replaced, written into `dir` beside
/// a copy of its behaviour file.
fn survey_with_logger(dir: &Path, settings: &str) -> PathBuf {
    let src = project_mission("surface_survey/survey.moos");
    let text = std::fs::read_to_string(&src).unwrap();
    let text = text.replace(
        "  File          = SURVEY\n  AsyncLog      = true\n  FileTimeStamp = true\n",
        settings,
    );
    assert!(text.contains(settings));
    let m = dir.join("survey.moos");
    std::fs::write(&m, &text).unwrap();
    std::fs::copy(
        project_mission("surface_survey/survey.bhv"),
        dir.join("survey.bhv"),
    )
    .unwrap();
    m
}

#[test]
fn plogger_path_file_and_timestamp_settings_are_followed_with_its_copies() {
    let dir = fresh_dir("run-logs-plogger");
    let m = survey_with_logger(
        &dir,
        "  File          = MYLOG\n  PATH          = ./my_logs/\n  FileTimeStamp = false\n  SyncLog       = true @ 0.2\n  WildcardExclusionLog = true\n",
    );
    let run = |cwd: &Path| {
        coug(
            cwd,
            &[
                "run",
                m.to_str().unwrap(),
                "--lockstep",
                "--deploy",
                "--max-time",
                "20",
            ],
        )
    };
    // Run from another folder: PATH is relative to where the run starts, as pLogger's is.
    let cwd = dir.join("cwd");
    std::fs::create_dir_all(&cwd).unwrap();
    let out = run(&cwd);
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert_eq!(out.status.code(), Some(0), "{stderr}");
    let session = cwd.join("my_logs/MYLOG");
    assert!(session.join("MYLOG.alog").is_file(), "{stderr}");
    // The mission copy under a banner naming it, and the helm's behaviour file copied on its
    // PLOGGER_CMD = COPY_FILE_REQUEST (pLogger's `<name>._<ext>`).
    let copy = std::fs::read_to_string(session.join("MYLOG._moos")).unwrap();
    assert!(copy.starts_with("%%%%"), "{copy}");
    assert!(
        copy.contains("%% LOG FILE:       ./my_logs/MYLOG/MYLOG._moos\n"),
        "{copy}"
    );
    let body: Vec<&str> = copy.lines().skip(5).collect();
    let original = std::fs::read_to_string(&m).unwrap();
    assert_eq!(body, original.lines().collect::<Vec<_>>());
    assert_eq!(
        std::fs::read(session.join("survey._bhv")).unwrap(),
        std::fs::read(dir.join("survey.bhv")).unwrap()
    );
    // WildcardExclusionLog: what WildCardOmitPattern (`*_STATUS`) keeps out of the alog goes
    // to the `.xlog`, in the alog's line format without a banner.
    let alog = std::fs::read_to_string(session.join("MYLOG.alog")).unwrap();
    let xlog = std::fs::read_to_string(session.join("MYLOG.xlog")).unwrap();
    assert!(!alog.contains("PHELMIVP_STATUS"));
    let first = xlog.lines().next().unwrap();
    assert!(first.starts_with("0.00000         "), "{first}");
    assert!(
        xlog.lines().any(|l| l.contains(" PHELMIVP_STATUS ")),
        "{xlog}"
    );
    // Every record (DB_VARSUMMARY's value spans lines) is of an omitted variable.
    for l in xlog.lines() {
        let mut f = l.split_whitespace();
        if f.next().is_some_and(|t| t.parse::<f64>().is_ok()) {
            let var = f.next().unwrap();
            assert!(
                var.ends_with("_STATUS") || var == "DB_VARSUMMARY" || var == "DB_RWSUMMARY",
                "{l}"
            );
        }
    }
    // A key coug's pLogger does not support is named, with its line.
    assert!(
        stderr.contains("survey.moos:39: warning: pLogger: SyncLog = true @ 0.2: not supported"),
        "{stderr}"
    );
    // Without a time stamp the next run finds the name taken: refused, nothing overwritten.
    let before = std::fs::read(session.join("MYLOG.alog")).unwrap();
    let out = run(&cwd);
    assert_eq!(out.status.code(), Some(1));
    assert!(
        String::from_utf8_lossy(&out.stderr).contains("never writes over a log"),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    assert_eq!(std::fs::read(session.join("MYLOG.alog")).unwrap(), before);
}
