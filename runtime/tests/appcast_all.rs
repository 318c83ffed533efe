//! Every built-in app a mission runs answers APPCAST_REQ with a well-formed APPCAST naming
//! itself and the community: the CougUV survey (simulator, sensors, navigator, PID, helm,
//! node reporter, uTimerScript) and delta (the legacy simulator and PID), and every app of
//! `runtime::antler::BUILT_INS` (one mission runs them all, pLogger writing into memory), so
//! an app added to the list is held to it too. pLogger's report has its own test, in
//! `logger.rs`.

use runtime::session;
use runtime::{Mail, Value};

fn answers_appcast_requests(mission: &std::path::Path, community: &str, expected: &[&str]) {
    let loaded = session::load(mission, &[], &[]).expect("loads");
    let plan = loaded.plan(1000.0, 1, None).expect("plans");
    let seen = each_answers(plan.apps, community);
    for e in expected {
        assert!(seen.iter().any(|s| s == e), "{e} not in {seen:?}");
    }
}

/// What each built-in app's report shows of its state, as its C++ original does (the helm's
/// MALCONFIG notice, the simulator's poses, the PID's settings, the logger's counts) or, for
/// coug's own apps, their health (links and counters of the drivers, the navigator's status,
/// the supervisor's mode and health word, the network's and the channel's counts).
fn reported(app: &str) -> Option<&'static [&'static str]> {
    Some(match app {
        // Its report, or why it cannot drive (a mission without its behaviour file).
        "pHelmIvP" => &["Helm Iteration", "The helm is in the MALCONFIG state"],
        "uSimMarine" | "uSimMarineV22" => &["Current Pose"],
        "pMarinePID" | "pMarinePIDV22" => &["PID Settings"],
        "pNodeReporter" => &["Vehicle Configuration"],
        "pLogger" => &["Logged Records"],
        "uTimerScript" => &["Elements"],
        "uSimSensors" => &["Reports"],
        "pNavGraph" => &["Status:"],
        "pSafety" => &["Health:"],
        "pCougControls" => &["Armed:"],
        "uSimCougUV" => &["Fins now"],
        "pShare" => &["Input routes"],
        "iGPS" | "iDVL" | "iSeaTrac" | "iTeensy" => &["Disconnects"],
        "uSimDevices" => &["Bench:"],
        "pAcomms" => &["Polls  Answers  Timeouts"],
        "uSimModem" => &["collisions"],
        "pBasicContactMgr" => &["Alert Status Summary"],
        _ => return None,
    })
}

/// Starts each app, iterates it, sends it an APPCAST_REQ and checks its APPCAST; returns
/// the apps' names.
fn each_answers(apps: Vec<Box<dyn runtime::App>>, community: &str) -> Vec<String> {
    let mut seen = Vec::new();
    for mut app in apps {
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
        if let Some(what) = reported(&name) {
            assert!(
                what.iter().any(|w| cast.messages().contains(w)),
                "{name}'s report has none of {what:?}:\n{}",
                cast.messages()
            );
        }
        // The string round-trips: well-formed.
        assert_eq!(
            appcast::AppCast::parse(&cast.to_moos_string()).messages(),
            cast.messages()
        );
        seen.push(name);
    }
    seen
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

/// A mission whose ANTLER block runs every built-in app once (MOOSDB aside), each with the
/// least configuration it needs to build: pShare listening on loopback, the drivers on
/// devices that are not there (their links retry in the background; they still appcast).
fn every_built_in_mission() -> String {
    let mut antler =
        String::from("ProcessConfig = ANTLER\n{\n  Run = MOOSDB @ NewConsole = false\n");
    let mut blocks = String::new();
    for b in runtime::antler::BUILT_INS {
        if b.program == "MOOSDB" {
            continue;
        }
        antler.push_str(&format!("  Run = {} @ NewConsole = false\n", b.program));
        let body = match b.program {
            "pShare" => "  input = route = 127.0.0.1:0\n".to_string(),
            "iGPS" | "iDVL" => "  host = 127.0.0.1\n  port = 1\n".to_string(),
            "iSeaTrac" | "iTeensy" => "  device = /nonexistent/coug-test-tty\n".to_string(),
            "pAcomms" | "uSimModem" => "  modem_id = 1\n".to_string(),
            // The legacy PID ends at start-up without every gain.
            "pMarinePID" => vehicle::pid::REQUIRED_ALWAYS
                .iter()
                .chain(vehicle::pid::REQUIRED_DEPTH)
                .map(|g| format!("  {g} = 1\n"))
                .collect(),
            _ => String::new(),
        };
        blocks.push_str(&format!(
            "ProcessConfig = {}\n{{\n  AppTick = 4\n{body}}}\n",
            b.program
        ));
    }
    antler.push_str("}\n");
    format!(
        "ServerHost = localhost\nServerPort = 9000\nCommunity = every\nLatOrigin = 42.358456\nLongOrigin = -71.087589\n{antler}{blocks}"
    )
}

#[test]
fn every_built_in_app_answers_appcast_requests() {
    use runtime::antler::{Launch, LogTarget, logger_config, plan};
    let text = every_built_in_mission();
    let m = mission::moos::parse_moos(&mission::source::SourceMap::from_text("every.moos", &text));
    assert!(!m.has_errors(), "{text}");
    let m = m.value;
    let target = LogTarget {
        config: logger_config(&m),
        writer: Box::new(runtime::logger::SharedBuffer::default()),
        opened: chrono::NaiveDate::from_ymd_opt(2026, 8, 5)
            .unwrap()
            .and_hms_opt(18, 22, 55)
            .unwrap(),
        opened_on: "Thu Jan  1 00:00:00 1970".into(),
        side: None,
    };
    let p = plan(&m, Launch::new(1000.0, 1).with_log(target), &mut |_, _| {
        None
    })
    .expect("plans");
    assert!(p.failed.is_empty(), "apps left out: {:?}", p.failed);
    assert!(p.external.is_empty(), "not built in: {:?}", p.external);
    let seen = each_answers(p.apps, "every");
    let expected: Vec<&str> = runtime::antler::BUILT_INS
        .iter()
        .map(|b| b.program)
        .filter(|p| *p != "MOOSDB")
        .collect();
    let mut got: Vec<&str> = seen.iter().map(String::as_str).collect();
    got.sort_unstable();
    let mut want = expected.clone();
    want.sort_unstable();
    assert_eq!(got, want, "every built-in app, once");
}
