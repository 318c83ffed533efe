//! A log that cannot be written fails the run: the disk "fills up" part-way through (the
//! process's file-size limit, RLIMIT_FSIZE, makes writes past 200 KiB fail with EFBIG, as a
//! full disk makes them fail with ENOSPC), and `coug run` ends with a non-zero exit and an
//! error naming the log; and a log folder that cannot be created fails the run before it
//! starts.

mod common;

use std::process::{Command, Output};

use common::{fresh_dir, project_mission};

/// Runs `coug` in `dir` with writes past `kib` KiB failing with EFBIG: the shell ignores
/// SIGXFSZ (an ignored signal stays ignored across exec), so the write fails with an error
/// instead of killing the process; the limit is in 1 KiB blocks.
fn coug_with_file_limit(dir: &std::path::Path, kib: u32, args: &[&str]) -> Output {
    Command::new("sh")
        .current_dir(dir)
        .arg("-c")
        .arg(format!("trap '' XFSZ; ulimit -f {kib}; exec \"$0\" \"$@\""))
        .arg(env!("CARGO_BIN_EXE_coug"))
        .args(args)
        .output()
        .expect("sh runs")
}

#[test]
fn a_log_that_fills_the_disk_mid_run_fails_the_run_with_a_clear_error() {
    let dir = fresh_dir("failing-disk");
    let mission = project_mission("surface_survey/survey.moos");
    let out = coug_with_file_limit(
        &dir,
        200,
        &[
            "run",
            mission.to_str().unwrap(),
            "--lockstep",
            "--deploy",
            "--until",
            "MISSION = complete",
            "--log-dir",
            "logs",
        ],
    );
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert_eq!(out.status.code(), Some(1), "stderr: {stderr}");
    assert!(
        stderr.contains("coug run: error: pLogger: the log logs/")
            && stderr.contains("could not be written"),
        "{stderr}"
    );
    assert!(stderr.contains("os error 27"), "EFBIG named: {stderr}");
    assert!(!stderr.contains("panicked"), "{stderr}");
    // The run stopped there: the survey did not go on to completion.
    let stdout = String::from_utf8_lossy(&out.stdout);
    assert!(!stdout.contains("until condition met"), "{stdout}");
    // The log was written up to the limit and no further.
    let alog = common::find_alog(&dir.join("logs"));
    let name = alog.file_name().unwrap().to_string_lossy();
    assert!(
        stderr.contains(&*name),
        "the error names the file on disk: {stderr}"
    );
    let len = std::fs::metadata(&alog).unwrap().len();
    assert!(len <= 200 * 1024, "{len} bytes");
}

/// The same in real time: the run (which would otherwise go on to its `--max-time` and exit
/// 0) ends with the error.
#[test]
fn a_real_time_run_ends_when_its_log_cannot_be_written() {
    let dir = fresh_dir("failing-disk-realtime");
    let mission = project_mission("surface_survey/survey.moos");
    let out = coug_with_file_limit(
        &dir,
        40,
        &[
            "run",
            mission.to_str().unwrap(),
            "--warp",
            "50",
            "--port",
            "0",
            "--deploy",
            "--max-time",
            "3000",
            "--log-dir",
            "logs",
        ],
    );
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert_eq!(out.status.code(), Some(1), "stderr: {stderr}");
    assert!(stderr.contains("could not be written"), "{stderr}");
    assert!(!stderr.contains("panicked"), "{stderr}");
}

#[test]
fn a_log_folder_that_cannot_be_created_fails_the_run_before_it_starts() {
    let dir = fresh_dir("unwritable-log-dir");
    let mission = project_mission("surface_survey/survey.moos");
    // procfs refuses new directories even to root.
    let out = common::coug(
        &dir,
        &[
            "run",
            mission.to_str().unwrap(),
            "--lockstep",
            "--deploy",
            "--log-dir",
            "/proc/coug-no-such-dir",
        ],
    );
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert_ne!(out.status.code(), Some(0), "stderr: {stderr}");
    assert!(stderr.contains("coug run: error:"), "{stderr}");
    assert!(stderr.contains("/proc/coug-no-such-dir"), "{stderr}");
    assert!(!stderr.contains("panicked"), "{stderr}");
    assert!(
        !String::from_utf8_lossy(&out.stdout).contains("t=  "),
        "the run did not start"
    );
}
