//! The project's own missions pass `coug check` (no errors) and each has a README that
//! names the command that runs it.

mod common;

use common::*;

#[test]
fn project_missions_check_clean_and_document_their_command() {
    for (dir, moos, bhv) in [
        ("surface_survey", "survey.moos", "survey.bhv"),
        ("dive", "dive.moos", "dive.bhv"),
        ("cougUV_survey", "cougUV_survey.moos", "cougUV_survey.bhv"),
        ("cougUV", "cougUV.moos", "cougUV.bhv"),
    ] {
        let m = project_mission(&format!("{dir}/{moos}"));
        let b = project_mission(&format!("{dir}/{bhv}"));
        let out = coug(
            m.parent().unwrap(),
            &["check", m.to_str().unwrap(), b.to_str().unwrap()],
        );
        let text = String::from_utf8_lossy(&out.stdout);
        assert_eq!(out.status.code(), Some(0), "{dir}: {text}");
        assert!(!text.contains("error"), "{dir}: {text}");
        let readme = std::fs::read_to_string(m.parent().unwrap().join("README.md"))
            .unwrap_or_else(|e| panic!("{dir}/README.md: {e}"));
        assert!(
            readme.contains(&format!("run missions/{dir}/{moos} --lockstep --deploy")),
            "{dir}/README.md lacks its run command"
        );
    }
}
