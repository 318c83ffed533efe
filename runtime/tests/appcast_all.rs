//! Every built-in app a mission runs answers APPCAST_REQ with a well-formed APPCAST naming
//! itself and the community: the CougUV survey (simulator, sensors, navigator, PID, helm,
//! node reporter, uTimerScript) and delta (the legacy simulator and PID). pLogger has its
//! own test (it needs a log), in `logger.rs`.

use runtime::session;
use runtime::{Mail, Value};

fn answers_appcast_requests(mission: &std::path::Path, community: &str, expected: &[&str]) {
    let loaded = session::load(mission, &[], &[]).expect("loads");
    let plan = loaded.plan(1000.0, 1, None).expect("plans");
    let mut seen = Vec::new();
    for mut app in plan.apps {
        let name = app.name().to_string();
        assert!(
            app.subscriptions()
                .iter()
                .any(|s| s.pattern == "APPCAST_REQ"),
            "{name} registers APPCAST_REQ"
        );
        let mut out = Vec::new();
        app.on_startup(1000.0, &mut out).unwrap();
        let dt = 1.0 / app.app_tick().max(1.0);
        let mut t = 1000.0;
        for _ in 0..4 {
            t += dt;
            app.iterate(t, &mut out).unwrap();
        }
        out.clear();
        let req = format!("node={community},app={name},duration=3.0,key=uMAC_9,thresh=any");
        let mail = Mail {
            key: "APPCAST_REQ".into(),
            value: Value::text(req),
            time: t,
            source: "uMAC_9".into(),
            source_aux: Default::default(),
            community: community.into(),
        };
        app.on_mail(&[mail], t, &mut out).unwrap();
        // Within the rate limit (0.5 s real time at most): a few iterations.
        let mut cast = None;
        for _ in 0..40 {
            t += dt;
            app.iterate(t, &mut out).unwrap();
            if let Some(p) = out.iter().find(|p| &*p.key == "APPCAST") {
                cast = Some(appcast::AppCast::parse(p.value.as_str().unwrap()));
                break;
            }
        }
        let cast = cast.unwrap_or_else(|| panic!("{name} answered no APPCAST_REQ"));
        assert_eq!(cast.proc_name(), name);
        assert_eq!(cast.node_name(), community, "{name}");
        assert!(
            cast.iteration() >= 5,
            "{name}: iteration {}",
            cast.iteration()
        );
        assert!(!cast.messages().is_empty(), "{name} reports nothing");
        // The string round-trips: well-formed.
        assert_eq!(
            appcast::AppCast::parse(&cast.to_moos_string()).messages(),
            cast.messages()
        );
        seen.push(name);
    }
    for e in expected {
        assert!(seen.iter().any(|s| s == e), "{e} not in {seen:?}");
    }
}

#[test]
fn every_app_of_the_couguv_survey_answers_appcast_requests() {
    let m = test_support::workspace_root().join("missions/cougUV_survey/cougUV_survey.moos");
    answers_appcast_requests(
        &m,
        "cougUV",
        &[
            "uSimMarineV22",
            "uSimSensors",
            "pNavGraph",
            "pMarinePIDV22",
            "pHelmIvP",
            "pNodeReporter",
            "uTimerScript_GPS",
        ],
    );
}

#[test]
fn delta_legacy_apps_answer_appcast_requests() {
    let m = test_support::mission_file("s4_delta/delta.moos");
    answers_appcast_requests(
        &m,
        "henry",
        &[
            "uSimMarine",
            "pMarinePID",
            "pHelmIvP",
            "pNodeReporter",
            "uTimerScript",
        ],
    );
}
