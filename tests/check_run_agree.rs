//! `coug check` and `coug run` share one validation path: what would keep a helm from driving
//! or end an app at start-up is an error for `check`, every warning `run` prints `check`
//! prints too.

mod common;

use std::path::Path;

use common::*;

const BASE: &str = "ServerHost = localhost
ServerPort = 9000
Community  = abe
LatOrigin  = 43.825300
LongOrigin = -70.330400

ProcessConfig = ANTLER
{
  Run = MOOSDB        @ NewConsole = false
  Run = uSimMarineV22 @ NewConsole = false
  Run = PID_RUN_LINE
  Run = pHelmIvP      @ NewConsole = false
  Run = pNodeReporter @ NewConsole = false
}

ProcessConfig = uSimMarineV22
{
  AppTick   = four
  start_pos = x=0, y=0
}

PID_BLOCK

HELM_BLOCK
";

const GOOD_PID: &str = "ProcessConfig = pMarinePIDV22
{
  AppTick = 10
  speed_factor = 20
  yaw_pid_kp = 0.5
  yaw_pid_kd = 0
  yaw_pid_ki = 0
  yaw_pid_integral_limit = 0.07
  maxrudder = 100
  speed_pid_kp = 1
  speed_pid_kd = 0
  speed_pid_ki = 0
  speed_pid_integral_limit = 0.07
  maxthrust = 100
  depth_control = false
}";

const HELM: &str = "ProcessConfig = pHelmIvP
{
  behaviors = m.bhv
  domain = course:0:359:360
  domain = speed:0:4:21
}";

const BHV: &str =
    "Behavior = BHV_ConstantSpeed\n{\n  name = cs\n  speed = 1\n  duration = no-time-limit\n}\n";

fn write(dir: &Path, pid_run: &str, pid: &str, helm: &str, bhv: Option<&str>) {
    let text = BASE
        .replace("PID_RUN_LINE", pid_run)
        .replace("PID_BLOCK", pid)
        .replace("HELM_BLOCK", helm);
    std::fs::write(dir.join("m.moos"), text).unwrap();
    let _ = std::fs::remove_file(dir.join("m.bhv"));
    if let Some(b) = bhv {
        std::fs::write(dir.join("m.bhv"), b).unwrap();
    }
}

/// `coug check m.moos`: (exit code, stdout); `coug run m.moos --lockstep`: stderr.
fn both(dir: &Path) -> (i32, String, String) {
    let c = coug(dir, &["check", "m.moos"]);
    let r = coug(
        dir,
        &[
            "run",
            "m.moos",
            "--lockstep",
            "--max-time",
            "2",
            "--log-dir",
            "logs",
        ],
    );
    (
        c.status.code().unwrap(),
        String::from_utf8_lossy(&c.stdout).into_owned(),
        String::from_utf8_lossy(&r.stderr).into_owned(),
    )
}

#[test]
fn what_run_cannot_use_check_reports_as_errors_and_their_warnings_agree() {
    let dir = fresh_dir("check-run-agree");
    let v22 = "pMarinePIDV22 @ NewConsole = false";

    // A sound mission: warnings only (AppTick = four; pNodeReporter without a block), the
    // same ones from both commands.
    write(&dir, v22, GOOD_PID, HELM, Some(BHV));
    let (code, check, run) = both(&dir);
    assert_eq!(code, 0, "{check}");
    for w in [
        "m.moos:18: warning: uSimMarineV22: AppTick = four: not a number",
        "m.moos:13: warning: pNodeReporter runs with no `ProcessConfig = pNodeReporter` block",
    ] {
        assert!(check.contains(w), "check lacks {w}:\n{check}");
        let text = w.replacen(": warning:", ":", 1);
        let tail = text.split_once(": ").unwrap().1;
        assert!(run.contains(tail), "run lacks {tail}:\n{run}");
    }

    // An unknown behaviour type, a missing behaviour file, a missing pHelmIvP block: the
    // helm would be in MALCONFIG, an error for check.
    for (helm, bhv, why) in [
        (
            HELM,
            Some("Behavior = BHV_Nonesuch\n{\n  name = x\n}\n"),
            "unknown behavior type BHV_Nonesuch",
        ),
        (HELM, None, "no such file: m.bhv"),
        ("", None, "pHelmIvP"),
    ] {
        write(&dir, v22, GOOD_PID, helm, bhv);
        let (code, check, run) = both(&dir);
        assert_eq!(code, 1, "{check}");
        assert!(
            check.contains("error: pHelmIvP would run in MALCONFIG (never driving)")
                && check.contains(why),
            "{why}:\n{check}"
        );
        assert!(run.contains("MALCONFIG"), "{run}");
    }

    // The older pMarinePID ends at start-up without its gains: an error for check, and run
    // goes on without it, saying so. pMarinePIDV22 only warns, in both.
    let legacy_pid = GOOD_PID
        .replace("pMarinePIDV22", "pMarinePID")
        .replace("  yaw_pid_kp = 0.5\n", "");
    write(
        &dir,
        "pMarinePID @ NewConsole = false",
        &legacy_pid,
        HELM,
        Some(BHV),
    );
    let (code, check, run) = both(&dir);
    assert_eq!(code, 1, "{check}");
    assert!(
        check.contains("error: pMarinePID: Improper PID Settings (yaw_pid_kp missing)"),
        "{check}"
    );
    assert!(run.contains("pMarinePID: Improper PID Settings (yaw_pid_kp missing): pMarinePID ends at start-up; the run goes on without it"), "{run}");
    let v22_pid = GOOD_PID.replace("  yaw_pid_kp = 0.5\n", "");
    write(&dir, v22, &v22_pid, HELM, Some(BHV));
    let (code, check, run) = both(&dir);
    assert_eq!(code, 0, "{check}");
    assert!(
        check.contains("warning: pMarinePIDV22: required parameter `yaw_pid_kp` is missing"),
        "{check}"
    );
    assert!(
        run.contains("pMarinePIDV22: required parameter `yaw_pid_kp` is missing"),
        "{run}"
    );
}
