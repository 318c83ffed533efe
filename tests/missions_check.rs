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

/// missions/cougUV checks clean (no finding at all) in both its forms, simulation and the
/// vehicle's (`HW=true`), and pSafety guards both: in the plan, configured without error.
#[test]
fn couguv_checks_clean_in_both_forms_with_psafety_guarding() {
    let m = project_mission("cougUV/cougUV.moos");
    let b = project_mission("cougUV/cougUV.bhv");
    for macros in [&[][..], &["HW=true"][..]] {
        let mut args = vec!["check", m.to_str().unwrap(), b.to_str().unwrap()];
        args.extend(macros);
        let out = coug(m.parent().unwrap(), &args);
        let text = format!(
            "{}{}",
            String::from_utf8_lossy(&out.stdout),
            String::from_utf8_lossy(&out.stderr)
        );
        assert_eq!(out.status.code(), Some(0), "{macros:?}: {text}");
        assert!(text.trim().is_empty(), "{macros:?}: {text}");

        let macros: Vec<String> = macros.iter().map(|s| s.to_string()).collect();
        let loaded = runtime::session::load(&m, &macros, &[]).expect("loads");
        let plan = loaded.plan(0.0, 1, None).expect("plans");
        let safety = plan
            .apps
            .iter()
            .find(|a| a.name() == "pSafety")
            .unwrap_or_else(|| panic!("{macros:?}: no pSafety"));
        assert!(safety.malconfig().is_empty(), "{:?}", safety.malconfig());
        let rules = safety
            .process_config()
            .expect("its block")
            .params("rule")
            .count();
        assert_eq!(rules, 10, "{macros:?}");
        // The drivers run in the vehicle's form only, the simulators in simulation only.
        let names: Vec<&str> = plan.apps.iter().map(|a| a.name()).collect();
        let hw = !macros.is_empty();
        for d in ["iGPS", "iDVL", "iSeaTrac", "iTeensy"] {
            assert_eq!(names.contains(&d), hw, "{d}: {names:?}");
        }
        assert_eq!(names.contains(&"uSimCougUV"), !hw, "{names:?}");
        assert!(!names.contains(&"uSimDevices"), "{names:?}");
    }
}
