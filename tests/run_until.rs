//! `--until` on a variable nothing in the mission posts is named up front, instead of a
//! silent run to `--max-time`.

mod common;

use common::*;

fn run(until: &str) -> String {
    let dir = fresh_dir(&format!("run-until-{}", until.len()));
    let m = project_mission("surface_survey/survey.moos");
    let out = coug(
        &dir,
        &[
            "run",
            m.to_str().unwrap(),
            "--lockstep",
            "--deploy",
            "--until",
            until,
            "--max-time",
            "5",
            "--log-dir",
            "logs",
        ],
    );
    assert_eq!(out.status.code(), Some(2));
    String::from_utf8_lossy(&out.stderr).into_owned()
}

#[test]
fn an_until_variable_nothing_posts_is_named_up_front() {
    let stderr = run("MISSON = complete");
    assert!(
        stderr.contains(
            "warning: --until: nothing in the mission posts, initialises or names MISSON; the run may go on to --max-time (5 s)"
        ),
        "{stderr}"
    );
    // The mission's own flag variable (survey.bhv posts MISSION) is not warned about.
    let stderr = run("MISSION = complete");
    assert!(!stderr.contains("--until:"), "{stderr}");
}
