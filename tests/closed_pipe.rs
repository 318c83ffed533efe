//! A reader that closes the pipe early (`coug ... | head -1`) ends coug quietly: no panic
//! (exit 101), no "Broken pipe" message, status 0.

mod common;

use std::io::{BufRead, BufReader};
use std::process::{Command, Stdio};

/// Starts `coug args` with stdout piped, reads one line, closes the pipe, and returns the exit
/// status and the stderr text.
fn read_one_line_then_close(args: &[&str], cwd: &std::path::Path) -> (Option<i32>, String) {
    let mut child = Command::new(env!("CARGO_BIN_EXE_coug"))
        .current_dir(cwd)
        .args(args)
        .stdout(Stdio::piped())
        .stderr(Stdio::piped())
        .spawn()
        .expect("coug starts");
    let mut first = String::new();
    BufReader::new(child.stdout.take().unwrap())
        .read_line(&mut first)
        .expect("one line");
    assert!(!first.is_empty());
    // The reader is dropped here: the pipe is closed while coug still has much to write.
    let out = child.wait_with_output().expect("coug ends");
    (
        out.status.code(),
        String::from_utf8_lossy(&out.stderr).into_owned(),
    )
}

#[test]
fn nsplug_to_a_closed_stdout_ends_quietly() {
    let dir = common::fresh_dir("closed_pipe_nsplug");
    // 4 MB of text: far more than a pipe buffer holds.
    let line = "// a line of a template long enough to fill the pipe buffer quickly\n";
    std::fs::write(dir.join("big.moos"), line.repeat(60_000)).unwrap();
    let (code, stderr) = read_one_line_then_close(&["nsplug", "big.moos", "-"], &dir);
    assert_eq!(code, Some(0), "stderr: {stderr}");
    assert!(!stderr.contains("panicked"), "{stderr}");
    assert!(!stderr.contains("Broken pipe"), "{stderr}");
}

#[test]
fn check_with_many_findings_to_a_closed_stdout_ends_quietly() {
    let dir = common::fresh_dir("closed_pipe_check");
    // Many files, each with a finding: the output outgrows a pipe buffer.
    let mut args = vec!["check".to_string()];
    for i in 0..3000 {
        let f = format!("m{i}.moos");
        std::fs::write(
            dir.join(&f),
            "ServerPort = 9000\nCommunity = abe\nProcessConfig = uSimMarineV22\n{\n  AppTick = 4\n",
        )
        .unwrap();
        args.push(f);
    }
    let args: Vec<&str> = args.iter().map(String::as_str).collect();
    let (code, stderr) = read_one_line_then_close(&args, &dir);
    assert!(code == Some(0), "status {code:?}, stderr: {stderr}");
    assert!(!stderr.contains("panicked"), "{stderr}");
}
