//! `coug run` in real time starts the ANTLER apps it does not build in from PATH, the way
//! pAntler does (`APP MISSION.moos MOOSNAME`), giving them a mission whose ServerPort is
//! the DB's real port and whose MOOSTimeWarp is the run's; a missing one is a warning, not a failure. Unix only (the stand-in
//! app is a shell script).

#![cfg(unix)]

mod common;

use std::os::unix::fs::PermissionsExt;
use std::process::Command;

use common::*;

#[test]
fn external_apps_start_from_path_and_missing_ones_warn() {
    let dir = fresh_dir("run-external");
    let bin = dir.join("bin");
    std::fs::create_dir_all(&bin).unwrap();
    let script = bin.join("uFakeApp");
    // Records its arguments and the mission's ServerPort, then waits to be stopped.
    std::fs::write(
        &script,
        "#!/bin/sh\nprintf '%s\\n' \"$@\" > \"$PWD/args.txt\"\n\
         grep -i '^ServerPort' \"$1\" > \"$PWD/port.txt\"\n\
         grep -i '^MOOSTimeWarp' \"$1\" > \"$PWD/warp.txt\"\nexec sleep 60\n",
    )
    .unwrap();
    std::fs::set_permissions(&script, std::fs::Permissions::from_mode(0o755)).unwrap();
    std::fs::write(
        dir.join("m.moos"),
        "ServerHost = localhost\nServerPort = 9000\nCommunity = ext\nMOOSTimeWarp = 1\n\
         ProcessConfig = ANTLER\n{\n  Run = MOOSDB @ NewConsole = false\n\
         Run = uFakeApp @ NewConsole = false ~ fake_2\n\
         Run = uNotInstalledAnywhere @ NewConsole = false\n}\n",
    )
    .unwrap();
    let path = format!(
        "{}:{}",
        bin.display(),
        std::env::var("PATH").unwrap_or_default()
    );
    let out = Command::new(env!("CARGO_BIN_EXE_coug"))
        .current_dir(&dir)
        .env("PATH", path)
        .args([
            "run",
            "m.moos",
            "--warp",
            "10",
            "--port",
            "0",
            "--max-time",
            "20",
            "--log-dir",
            "logs",
        ])
        .output()
        .expect("coug runs");
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert_eq!(out.status.code(), Some(0), "{stderr}");
    assert!(
        stderr.contains("cannot start uNotInstalledAnywhere"),
        "{stderr}"
    );
    let port: u16 = stderr
        .split("listening on 127.0.0.1:")
        .nth(1)
        .and_then(|r| r.split_whitespace().next())
        .and_then(|p| p.parse().ok())
        .expect("the DB's port on stderr");
    let args = std::fs::read_to_string(dir.join("args.txt")).expect("uFakeApp was started");
    let args: Vec<&str> = args.lines().collect();
    assert_eq!(args.len(), 2, "{args:?}");
    assert!(args[0].ends_with(".moos"), "{args:?}");
    assert_eq!(args[1], "fake_2");
    let port_line = std::fs::read_to_string(dir.join("port.txt")).unwrap();
    assert_eq!(port_line.trim(), format!("ServerPort = {port}"));
    // The run's warp, not the file's 1 (pAntler's `--MOOSTimeWarp=10` overload).
    let warp_line = std::fs::read_to_string(dir.join("warp.txt")).unwrap();
    assert_eq!(warp_line.trim(), "MOOSTimeWarp = 10");
}
