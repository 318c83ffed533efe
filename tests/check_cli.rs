//! End-to-end tests of `coug check` and `coug nsplug` (the real binary, real files).

use std::process::Command;

use test_support::{mission_file, scratch_dir};

fn coug(args: &[&str]) -> (i32, String, String) {
    let out = Command::new(env!("CARGO_BIN_EXE_coug"))
        .args(args)
        .output()
        .expect("run coug");
    (
        out.status.code().expect("exit code"),
        String::from_utf8_lossy(&out.stdout).into_owned(),
        String::from_utf8_lossy(&out.stderr).into_owned(),
    )
}

#[test]
fn check_accepts_the_alpha_mission_and_its_behaviour_file() {
    let moos = mission_file("s1_alpha/alpha.moos");
    let (code, stdout, _) = coug(&["check", moos.to_str().unwrap()]);
    assert_eq!(code, 0, "{stdout}");
    assert!(!stdout.contains("error"), "{stdout}");
}

#[test]
fn check_reports_errors_one_per_line_and_exits_1() {
    let dir = scratch_dir("check-cli-errors");
    std::fs::write(
        dir.join("m.moos"),
        "ServerPort = 9000\nProcessConfig = pHelmIvP\n{\n  behaviors = m.bhv\n  bogus_param = 1\n}\n",
    )
    .unwrap();
    std::fs::write(
        dir.join("m.bhv"),
        "initialize DEPLOY = $(START)\nBehavior = BHV_Loiter\n{\n  condition = (DEPLOY = true\n  sped = 2\n}\n",
    )
    .unwrap();
    let m = dir.join("m.moos");
    let m_str = m.to_str().unwrap();
    let (code, stdout, _) = coug(&["check", m_str, "START=false"]);
    assert_eq!(code, 1);
    let b = dir.join("m.bhv").display().to_string();
    let lines: Vec<&str> = stdout.lines().collect();
    assert_eq!(
        lines,
        [
            format!(
                "{b}:4:29: error: malformed condition: expected `)`, `and` or `or`, found end of condition"
            ),
            format!("{m_str}:5:3: error: unknown pHelmIvP parameter `bogus_param`"),
            format!(
                "{b}:5:3: error: unknown parameter `sped` for BHV_Loiter (did you mean `speed`?)"
            ),
        ]
    );
    // Without START the macro stays and nsplug's warning is reported too.
    let (_, stdout, _) = coug(&["check", m_str]);
    assert!(
        stdout.contains(&format!("{b}:1:21: warning: undefined macro")),
        "{stdout}"
    );
    // --context adds the caret line.
    let (_, stdout, _) = coug(&["check", m_str, "START=false", "--context"]);
    assert!(
        stdout.contains("  4 |   condition = (DEPLOY = true\n    |                             ^"),
        "{stdout}"
    );
}

#[test]
fn check_warnings_alone_exit_0() {
    let dir = scratch_dir("check-cli-warnings");
    std::fs::write(
        dir.join("w.bhv"),
        "Behavior = BHV_ConstantSpeed\n{\n  speed = 1\n  condition = GHOST = 1\n}\n",
    )
    .unwrap();
    let (code, stdout, _) = coug(&["check", dir.join("w.bhv").to_str().unwrap()]);
    assert_eq!(code, 0, "{stdout}");
    assert_eq!(stdout.lines().count(), 1, "{stdout}");
    assert!(
        stdout.contains(":4:15: warning: condition tests `GHOST`"),
        "{stdout}"
    );
    // An unknown behaviour type is an error: the helm would be in MALCONFIG.
    std::fs::write(dir.join("u.bhv"), "Behavior = BHV_Unheard\n{\n  x = 1\n}\n").unwrap();
    let (code, stdout, _) = coug(&["check", dir.join("u.bhv").to_str().unwrap()]);
    assert_eq!(code, 1, "{stdout}");
    assert!(
        stdout.contains(":1:1: error: unknown behaviour type `BHV_Unheard`"),
        "{stdout}"
    );
}

#[test]
fn nsplug_expands_templates_like_the_launch_scripts_do() {
    let dir = scratch_dir("check-cli-nsplug");
    std::fs::create_dir_all(dir.join("plugs")).unwrap();
    std::fs::write(
        dir.join("meta.moos"),
        "Community = $(VNAME)\n#include plug.moos\n#ifdef GUI yes\nRun = pMarineViewer\n#endif\nname = %(VNAME)\n",
    )
    .unwrap();
    std::fs::write(dir.join("plugs/plug.moos"), "ServerPort = $(PORT=9000)\n").unwrap();
    let out = dir.join("targ.moos");
    let meta = dir.join("meta.moos");
    let plugs = dir.join("plugs");
    let args = [
        "nsplug",
        meta.to_str().unwrap(),
        out.to_str().unwrap(),
        "VNAME=henry",
        "GUI=yes",
        "-p",
        plugs.to_str().unwrap(),
    ];
    let (code, _, stderr) = coug(&args);
    assert_eq!(code, 0, "{stderr}");
    assert_eq!(
        std::fs::read_to_string(&out).unwrap(),
        "Community = henry\nServerPort = 9000\nRun = pMarineViewer\nname = HENRY\n"
    );
    // Strict mode: an undefined macro aborts and nothing is written.
    let out2 = dir.join("strict.moos");
    let (code, _, stderr) = coug(&[
        "nsplug",
        dir.join("meta.moos").to_str().unwrap(),
        out2.to_str().unwrap(),
        "--strict",
        "-p",
        dir.join("plugs").to_str().unwrap(),
    ]);
    assert_eq!(code, 1);
    assert!(
        stderr.contains("meta.moos:1:13: error: undefined macro"),
        "{stderr}"
    );
    assert!(!out2.exists());
    // A missing include is an error naming the file and line.
    let (code, _, stderr) = coug(&[
        "nsplug",
        dir.join("meta.moos").to_str().unwrap(),
        out2.to_str().unwrap(),
    ]);
    assert_eq!(code, 1);
    assert!(
        stderr.contains("meta.moos:2:10: error: cannot find include file `plug.moos`"),
        "{stderr}"
    );
}

#[test]
fn check_prints_at_most_max_findings_per_file_and_says_how_many_were_left_out() {
    let dir = scratch_dir("check-cli-cap");
    // Thousands of lines MOOS would skip (warnings), and one real error at the end.
    let mut text = String::from("ServerPort = 9000\n");
    for i in 0..5000 {
        text.push_str(&format!("garbage line {i}\n"));
    }
    text.push_str("ProcessConfig = pShare\n");
    std::fs::write(dir.join("big.moos"), &text).unwrap();
    std::fs::write(dir.join("small.moos"), "just text\n").unwrap();
    let big = dir.join("big.moos");
    let small = dir.join("small.moos");
    let (big_s, small_s) = (big.to_str().unwrap(), small.to_str().unwrap());

    let (code, stdout, _) = coug(&["check", big_s, small_s]);
    assert_eq!(code, 1, "the error left out still sets the exit code");
    let lines: Vec<&str> = stdout.lines().collect();
    // 50 of big's, small's own line and its refusal as a mission, big's note.
    assert_eq!(lines.len(), 50 + 2 + 1, "{}", lines[..5].join("\n"));
    assert!(
        stdout.contains("small.moos: not a MOOS mission file"),
        "{stdout}"
    );
    assert!(lines[..50].iter().all(|l| l.starts_with(big_s)), "{stdout}");
    assert!(lines[0].contains(":2:1: warning: line without `=`: MOOS ignores this line"));
    assert!(lines.contains(&format!("{small_s}:1:1: warning: line without `=`: MOOS ignores this line: expected `key = value`, found `just text`").as_str()));
    assert_eq!(
        *lines.last().unwrap(),
        format!(
            "{big_s}: note: 4951 more findings not shown (1 error, 4950 warnings); \
             --max-findings 0 shows them all"
        )
    );

    let (_, stdout, _) = coug(&["check", big_s, "--max-findings", "3"]);
    assert_eq!(stdout.lines().count(), 4, "{stdout}");
    let (code, stdout, _) = coug(&["check", big_s, "--max-findings", "0"]);
    assert_eq!(code, 1);
    assert_eq!(stdout.lines().count(), 5001, "every finding, no summary");
}

#[test]
fn check_accepts_a_goby_app_block_and_the_lines_moos_skips() {
    let dir = scratch_dir("check-cli-goby");
    std::fs::write(
        dir.join("goby.moos"),
        "ServerHost = localhost\nServerPort = 9000\nMIT Sailing Pavilion (use this one)\n\
         ==================\n\
         ProcessConfig = ANTLER\n{\n  Run = MOOSDB @ NewConsole = false\n  \
         Run = pAcommsHandler @ NewConsole = false\n}\n\
         ProcessConfig = pAcommsHandler\n{\n  common {\n    log: false\n  }\n  modem_id: 2\n  \
         driver_cfg {\n    [micromodem.Config.reset_nvram]: true\n  }\n}\n\
         ProcessConfig = uProcessWatch\n{\n  # Linux:\n  watch_all = true\n}\n",
    )
    .unwrap();
    let f = dir.join("goby.moos");
    let (code, stdout, _) = coug(&["check", f.to_str().unwrap()]);
    assert_eq!(code, 0, "{stdout}");
    let lines: Vec<&str> = stdout.lines().collect();
    assert_eq!(lines.len(), 3, "{stdout}");
    for (line, text) in [
        (3, "line without `="),
        (4, "nothing before `="),
        (22, "line without `="),
    ] {
        assert!(
            lines.iter().any(|l| l.contains(&format!(":{line}:"))
                && l.contains(&format!("warning: {text}"))
                && l.contains("MOOS ignores this line")),
            "line {line}: {stdout}"
        );
    }
}

#[test]
fn check_does_not_warn_about_the_apps_own_runtime_macros() {
    let dir = scratch_dir("check-cli-runtime-macros");
    std::fs::write(
        dir.join("m.moos"),
        "Community = $(VNAME)\n\
         ProcessConfig = uTimerScript\n{\n  \
         randvar = varname=ANG, min=0, max=359, key=at_reset\n  \
         event = var=GPS_UPDATE_RECEIVED, val=\"RCVD_$(COUNT)\", time=0.5\n  \
         event = var=DRIFT, val=\"$(ANG),{$(7)*0.2}\", time=1\n  \
         event = var=OWN, val=\"$(COUNT)_$(SHORE)\", time=2\n}\n\
         ProcessConfig = pMarineViewer\n{\n  \
         left_context[pt] = VIEW_POINT = x=$(XPOS),y=$(YPOS),label=$(VNAME)\n  \
         button_one = DEPLOY # DEPLOY_ALL=true # STAMP=$(UTC)\n  \
         button_two = GO # GO_$(XPOS)=true\n}\n\
         ProcessConfig = pHelmIvP\n{\n  behaviors = m.bhv\n}\n",
    )
    .unwrap();
    std::fs::write(
        dir.join("m.bhv"),
        "initialize DEPLOY = false\n\
         Behavior = BHV_Loiter\n{\n  condition = DEPLOY = true\n  \
         endflag = LOITER_DONE = $[OSX],$[OSY]\n  endflag = PT = $(X),$(Y)\n  \
         polygon = format=radial, x=$[OSX], y=$[OSY], radius=20, pts=8\n}\n",
    )
    .unwrap();
    let m = dir.join("m.moos");
    let m_s = m.to_str().unwrap();
    let (code, stdout, _) = coug(&["check", m_s]);
    assert_eq!(code, 0, "{stdout}");
    let macros: Vec<&str> = stdout
        .lines()
        .filter(|l| l.contains("undefined macro"))
        .collect();
    // The nsplug macros: `$(VNAME)` in a global line, `$(SHORE)` after a runtime `$(COUNT)`
    // (reported at its own column), and `$(XPOS)` in a button, which pMarineViewer does not
    // expand.
    assert_eq!(macros.len(), 3, "{stdout}");
    assert!(
        macros[0].starts_with(&format!("{m_s}:1:13: warning: undefined macro"))
            && macros[0].ends_with("found `$(VNAME)`"),
        "{stdout}"
    );
    assert!(
        macros[1].starts_with(&format!("{m_s}:7:34: warning:"))
            && macros[1].ends_with("found `$(SHORE)`"),
        "{stdout}"
    );
    assert!(
        macros[2].starts_with(&format!("{m_s}:13:24: warning:"))
            && macros[2].ends_with("found `$(XPOS)`"),
        "{stdout}"
    );
    assert!(!stdout.contains("OSX"), "{stdout}");
}

#[test]
fn check_reads_fleet_files_as_coug_run_starts_them() {
    let root = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("missions");
    for fleet in [
        "fleet_survey/fleet_survey.fleet",
        "fleet_acomms/fleet_acomms.fleet",
    ] {
        let path = root.join(fleet);
        let (code, stdout, stderr) = coug(&["check", path.to_str().unwrap()]);
        assert_eq!(code, 0, "{fleet}: {stdout}{stderr}");
        assert!(stdout.is_empty(), "{fleet}: {stdout}");
    }
    // Errors in the fleet file itself, each at its line.
    let dir = scratch_dir("check-cli-fleet");
    let bad = dir.join("bad.fleet");
    std::fs::write(&bad, "vehicle = x\nbogus line\n").unwrap();
    let (code, stdout, _) = coug(&["check", bad.to_str().unwrap()]);
    assert_eq!(code, 1, "{stdout}");
    let lines: Vec<&str> = stdout.lines().collect();
    assert_eq!(lines.len(), 2, "{stdout}");
    assert!(
        lines[0].starts_with(&format!("{}:1: error:", bad.display())),
        "{stdout}"
    );
    assert!(
        lines[1].starts_with(&format!("{}:2: error:", bad.display())),
        "{stdout}"
    );
    // A community whose helm would be in MALCONFIG is an error named after the community.
    std::fs::write(
        dir.join("v.moos"),
        "ServerPort = 0\nCommunity = v1\n\nProcessConfig = ANTLER\n{\n  Run = MOOSDB @ NewConsole = false\n  \
         Run = pHelmIvP @ NewConsole = false\n}\n\nProcessConfig = pHelmIvP\n{\n  behaviors = v.bhv\n  \
         Domain = course:0:359:360\n  Domain = speed:0:4:21\n  bogus_param = 1\n}\n",
    )
    .unwrap();
    std::fs::write(
        dir.join("v.bhv"),
        "Behavior = BHV_ConstantSpeed\n{\n  speed = 1\n}\n",
    )
    .unwrap();
    let fleet = dir.join("one.fleet");
    std::fs::write(&fleet, "vehicle = henry v.moos\n").unwrap();
    let (code, stdout, _) = coug(&["check", fleet.to_str().unwrap()]);
    assert_eq!(code, 1, "{stdout}");
    assert!(
        stdout.contains("henry: pHelmIvP would run in MALCONFIG (never driving)"),
        "{stdout}"
    );
}

#[test]
fn check_reports_a_psafety_block_s_unknown_key_once_at_its_line() {
    // pSafety refuses a block with an unknown key (MALCONFIG); pCougControls only warns.
    let dir = scratch_dir("check-cli-psafety");
    let m = dir.join("s.moos");
    std::fs::write(
        &m,
        "Community = abe\nProcessConfig = ANTLER\n{\n  Run = MOOSDB @ NewConsole = false\n  \
         Run = pSafety @ NewConsole = false\n  Run = pCougControls @ NewConsole = false\n}\n\
         ProcessConfig = pSafety\n{\n  bogus_key = 1\n}\n\
         ProcessConfig = pCougControls\n{\n  other_key = 2\n}\n",
    )
    .unwrap();
    let m = m.to_str().unwrap();
    let (code, stdout, _) = coug(&["check", m]);
    assert_eq!(code, 1, "{stdout}");
    let lines: Vec<&str> = stdout.lines().collect();
    assert_eq!(
        lines,
        [
            format!("{m}:14: warning: pCougControls: unknown parameter `other_key`"),
            format!(
                "error: pSafety would run in MALCONFIG (never driving): {m}:10: pSafety: unknown parameter `bogus_key`"
            ),
        ]
    );
}
