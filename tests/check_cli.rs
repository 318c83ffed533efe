//! End-to-end tests of `coug check` and `coug nsplug` (the real binary, real files).

use std::path::{Path, PathBuf};
use std::process::Command;

const SHARED: &str = concat!(env!("CARGO_MANIFEST_DIR"), "/../shared");

fn corpus(rel: &str) -> PathBuf {
    let p = Path::new(SHARED).join("corpus/moos-ivp-missions").join(rel);
    assert!(
        p.is_file(),
        "corpus file {} is missing: these tests need ../shared/corpus",
        p.display()
    );
    p
}

/// A fresh scratch directory for one test.
fn scratch(name: &str) -> PathBuf {
    let dir = std::env::temp_dir().join(format!("coug-check-cli-{}-{name}", std::process::id()));
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).expect("create scratch dir");
    dir
}

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
    let moos = corpus("s1_alpha/alpha.moos");
    let (code, stdout, _) = coug(&["check", moos.to_str().unwrap()]);
    assert_eq!(code, 0, "{stdout}");
    assert!(!stdout.contains("error"), "{stdout}");
}

#[test]
fn check_reports_errors_one_per_line_and_exits_1() {
    let dir = scratch("errors");
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
    let dir = scratch("warnings");
    std::fs::write(
        dir.join("w.bhv"),
        "Behavior = BHV_Unheard\n{\n  x = 1\n  condition = GHOST = 1\n}\n",
    )
    .unwrap();
    let (code, stdout, _) = coug(&["check", dir.join("w.bhv").to_str().unwrap()]);
    assert_eq!(code, 0, "{stdout}");
    assert_eq!(stdout.lines().count(), 2, "{stdout}");
    assert!(
        stdout.contains(":1:1: warning: unknown behaviour type `BHV_Unheard`"),
        "{stdout}"
    );
    assert!(
        stdout.contains(":4:15: warning: condition tests `GHOST`"),
        "{stdout}"
    );
}

#[test]
fn nsplug_expands_templates_like_the_launch_scripts_do() {
    let dir = scratch("nsplug");
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
