//! Simulator + marine PID + node reporter (configured from the real s1_alpha blocks) in
//! lockstep, driven by a scripted helm, logged by pLogger with alpha's own logger block.

use chrono::NaiveDate;
use mission::moos::{MissionFile, ProcessConfig};
use mission::source::SourceMap;
use runtime::antler::BuiltInApp;
use runtime::logger::{Logger, LoggerConfig, SharedBuffer};
use runtime::vehicle::VehicleApp;
use runtime::{App, Bus, Outcome, Poke, Post, Scheduler, VirtualClock};
use vehicle::geodesy::LocalGrid;

const START: f64 = 1_786_000_000.0;

fn alpha() -> MissionFile {
    let text = test_support::mission_text("s1_alpha/alpha.moos");
    let parsed = mission::moos::parse_moos(&SourceMap::from_text("alpha.moos", &text));
    assert!(!parsed.has_errors());
    parsed.value
}

fn block(m: &MissionFile, name: &str) -> ProcessConfig {
    m.process(name)
        .unwrap_or_else(|| panic!("no {name} block"))
        .clone()
}

/// Heading 90 at 2 m/s for 60 s, then heading 180.
struct ScriptedHelm;

impl App for ScriptedHelm {
    fn name(&self) -> &str {
        "pHelmIvP"
    }
    fn app_tick(&self) -> f64 {
        4.0
    }
    fn iterate(&mut self, now: f64, out: &mut Vec<Post>) -> runtime::AppResult {
        let heading = if now - START < 60.0 { 90.0 } else { 180.0 };
        out.push(Post::text("IVPHELM_STATE", "DRIVE"));
        out.push(Post::double("DESIRED_HEADING", heading));
        out.push(Post::double("DESIRED_SPEED", 2.0));
        out.push(Post::double("DESIRED_DEPTH", 0.0));
        Ok(())
    }
}

fn run() -> (Vec<u8>, Outcome) {
    let m = alpha();
    let grid = LocalGrid::new(43.8253, -70.3304).unwrap();
    let mut s = Scheduler::new(Bus::new("alpha", START), VirtualClock, START);
    let sim = VehicleApp::simulator(
        "uSimMarineV22",
        block(&m, "uSimMarineV22"),
        Some(grid),
        START,
        false,
    )
    .unwrap();
    assert!(sim.warnings().is_empty(), "{:?}", sim.warnings());
    assert_eq!(sim.app_tick(), 4.0);
    let pid = VehicleApp::marine_pid("pMarinePIDV22", block(&m, "pMarinePIDV22"), false).unwrap();
    assert_eq!(pid.app_tick(), 20.0);
    let rep = VehicleApp::node_reporter(
        "pNodeReporter",
        block(&m, "pNodeReporter"),
        "alpha",
        START,
        None,
        0,
    )
    .unwrap();
    let buf = SharedBuffer::default();
    let opened = NaiveDate::from_ymd_opt(2026, 8, 5)
        .unwrap()
        .and_hms_opt(18, 22, 55)
        .unwrap();
    let lb = block(&m, "pLogger");
    let logger = Logger::new(
        "pLogger",
        Some(lb.clone()),
        LoggerConfig::from_config(Some(&lb), None),
        buf.clone(),
        &opened,
        "Thu Jan  1 00:00:00 1970",
    );
    // ANTLER order of alpha: pLogger, uSimMarineV22, pMarinePIDV22, pHelmIvP, pNodeReporter.
    s.add_app(Box::new(logger)).unwrap();
    s.add_app(Box::new(sim)).unwrap();
    s.add_app(Box::new(pid)).unwrap();
    s.add_app(Box::new(ScriptedHelm)).unwrap();
    s.add_app(Box::new(rep)).unwrap();
    s.add_poke(Poke::parse("MOOS_MANUAL_OVERRIDE=false", "pHelmIvP").unwrap())
        .unwrap();
    let outcome = s.run(120.0).unwrap();
    (buf.contents(), outcome)
}

fn values(log: &alog::Alog, var: &str) -> Vec<(f64, f64)> {
    log.entries
        .iter()
        .filter(|e| e.var == var)
        .filter_map(|e| Some((e.time, e.value.as_f64()?)))
        .collect()
}

fn at(v: &[(f64, f64)], t: f64) -> f64 {
    v.iter().take_while(|(vt, _)| *vt <= t).last().unwrap().1
}

#[test]
fn sim_pid_and_reporter_follow_a_scripted_helm() {
    let (bytes, outcome) = run();
    assert_eq!(
        outcome,
        Outcome::MaxTime {
            time: START + 120.0
        }
    );
    let log = alog::parse(std::str::from_utf8(&bytes).unwrap()).unwrap();
    let x = values(&log, "NAV_X");
    let y = values(&log, "NAV_Y");
    let hdg = values(&log, "NAV_HEADING");
    let spd = values(&log, "NAV_SPEED");
    // The simulator iterates at its AppTick (4 Hz) and, as uSimMarineV22 does, posts
    // navigation every second iteration.
    assert!(
        x.len() >= 235 && x.len() <= 245,
        "{} NAV_X records",
        x.len()
    );
    assert!(x.windows(2).all(|w| w[1].0 - w[0].0 == 0.5));
    // Start pose from alpha's block: x=0, y=-20, heading 180.
    assert!(x[0].1.abs() < 0.01 && (y[0].1 + 20.0).abs() < 0.01);
    // Leg 1: east at about 2 m/s.
    assert!(
        (at(&hdg, 55.0) - 90.0).abs() < 5.0,
        "heading {}",
        at(&hdg, 55.0)
    );
    assert!(
        (at(&spd, 55.0) - 2.0).abs() < 0.3,
        "speed {}",
        at(&spd, 55.0)
    );
    assert!(at(&x, 60.0) > 60.0, "x {}", at(&x, 60.0));
    // Leg 2: south.
    assert!(
        (at(&hdg, 115.0) - 180.0).abs() < 5.0,
        "heading {}",
        at(&hdg, 115.0)
    );
    assert!(at(&y, 120.0) < at(&y, 60.0) - 60.0);
    assert!(values(&log, "NAV_LAT").len() > 200, "grid gives NAV_LAT");
    // The PID commands the simulator.
    assert!(
        !values(&log, "DESIRED_RUDDER").is_empty() && !values(&log, "DESIRED_THRUST").is_empty()
    );
    // Node reports carry the vehicle's position and the helm's mode.
    let reports: Vec<(f64, &str)> = log
        .entries
        .iter()
        .filter(|e| e.var == "NODE_REPORT_LOCAL")
        .map(|e| (e.time, e.value.as_str().unwrap()))
        .collect();
    // alpha runs pNodeReporter at AppTick 2.
    assert!(
        reports.len() >= 235 && reports.len() <= 242,
        "{} reports",
        reports.len()
    );
    let (t, r) = reports.iter().find(|(t, _)| *t >= 90.0).unwrap();
    assert!(r.contains("NAME=alpha") && r.contains("MODE=DRIVE"), "{r}");
    let field = |k: &str| -> f64 {
        r.split(',')
            .find_map(|kv| kv.strip_prefix(k))
            .unwrap_or_else(|| panic!("no {k} in {r}"))
            .parse()
            .unwrap()
    };
    assert!(
        (field("X=") - at(&x, *t)).abs() < 1.0,
        "{r} vs NAV_X {}",
        at(&x, *t)
    );
    assert!(
        (field("Y=") - at(&y, *t)).abs() < 1.0,
        "{r} vs NAV_Y {}",
        at(&y, *t)
    );
    // alpha's logger omits *_STATUS and logs with LogAuxSrc.
    assert!(log.entries.iter().all(|e| !e.var.ends_with("_STATUS")));
}

#[test]
fn the_vehicle_run_is_deterministic() {
    let (a, _) = run();
    let (b, _) = run();
    assert!(a.len() > 100_000);
    assert_eq!(a, b);
}

/// The swap-in contract of the vehicle apps: a bad or unsupported setting is a config
/// warning naming the file and line; the app is built and runs with the rest.
#[test]
fn vehicle_apps_run_on_with_config_warnings() {
    let text = "Community = abe\nProcessConfig = pNodeReporter\n{\n  platform_type = kayak\n  \
                nohelm_threshold = -1\n  extrap_enabled = maybe\n}\n\
                ProcessConfig = pMarinePIDV22\n{\n  yaw_pid_kp = fast\n  speed_factor = 20\n}\n";
    let m = mission::moos::parse_moos(&SourceMap::from_text("w.moos", text)).value;
    let rep = VehicleApp::node_reporter(
        "pNodeReporter",
        block(&m, "pNodeReporter"),
        "abe",
        START,
        None,
        0,
    )
    .expect("the reporter runs");
    let w: Vec<String> = rep.warnings().iter().map(|d| d.located()).collect();
    assert_eq!(w.len(), 2, "{w:?}");
    assert!(
        w[0].starts_with("w.moos:5: ") && w[0].contains("nohelm_threshold"),
        "{w:?}"
    );
    assert!(
        w[1].starts_with("w.moos:6: ") && w[1].contains("extrap_enabled = maybe"),
        "{w:?}"
    );
    let pid = VehicleApp::marine_pid("pMarinePIDV22", block(&m, "pMarinePIDV22"), false)
        .expect("the PID runs");
    let w: Vec<String> = pid.warnings().iter().map(|d| d.located()).collect();
    assert!(
        w.iter()
            .any(|x| x.starts_with("w.moos:10: ") && x.contains("yaw_pid_kp")),
        "{w:?}"
    );
    assert!(
        w.iter().any(|x| x.contains("maxrudder")),
        "missing gains are named: {w:?}"
    );
    // The reporter still reports.
    let mut s = Scheduler::new(Bus::new("abe", START), VirtualClock, START);
    s.add_app(Box::new(rep)).unwrap();
    s.add_poke(Poke::parse("NAV_X=5", "uPokeDB").unwrap())
        .unwrap();
    s.add_poke(Poke::parse("NAV_Y=7", "uPokeDB").unwrap())
        .unwrap();
    s.run(5.0).unwrap();
    let report = s.current("NODE_REPORT_LOCAL").expect("a node report");
    assert!(report.as_str().unwrap().contains("X=5"), "{report:?}");
}

#[test]
fn simulator_runs_on_with_config_warnings_and_takes_drift_from_a_source() {
    let text = "Community = abe\nProcessConfig = uSimMarineV22\n{\n  prefix = NAV\n  \
                current_x = 1\n  wormhole = tag=w1, connection=sideways\n  \
                start_pos = x=10, y=20\n}\n";
    let m = mission::moos::parse_moos(&SourceMap::from_text("s.moos", text)).value;
    let sim = VehicleApp::simulator(
        "uSimMarineV22",
        block(&m, "uSimMarineV22"),
        None,
        START,
        false,
    )
    .expect("the simulator runs");
    let w: Vec<String> = sim.warnings().iter().map(|d| d.located()).collect();
    assert_eq!(w.len(), 2, "{w:?}");
    assert!(
        w[0].starts_with("s.moos:5: ") && w[0].contains("current_x"),
        "{w:?}"
    );
    assert!(
        w[1].starts_with("s.moos:6: ") && w[1].contains("connection"),
        "{w:?}"
    );
    let mut s = Scheduler::new(Bus::new("abe", START), VirtualClock, START);
    s.add_app(Box::new(sim)).unwrap();
    s.add_poke(Poke::parse("DRIFT_X=2", "uPokeDB").unwrap())
        .unwrap();
    s.run(3.0).unwrap();
    // The other settings applied: the prefix and the start position.
    let y = s.current("NAV_Y").expect("navigation is posted");
    assert_eq!(y.as_f64(), Some(20.0));
    // The first drift from uPokeDB re-posted the summary.
    let summary = s.current("USM_DRIFT_SUMMARY").expect("a drift summary");
    assert_eq!(summary.as_str(), Some("ang=90, mag=2, xmag=2, ymag=0"));
    assert!(
        s.current("NAV_X").unwrap().as_f64().unwrap() > 10.0,
        "drifting east"
    );
    // The (rejected) wormhole still has its tag registered, so <prefix>_TRANSP is posted.
    assert_eq!(s.current("NAV_TRANSP").and_then(|v| v.as_f64()), Some(1.0));
}

/// pNodeReporter's wiring: PNODEREPORTER_PID at start-up (single-app mode), the `NAV_*`
/// wildcard and the alt-nav and platform-report inputs subscribed, and mail stamped with
/// the reporter's own time (MOOS `m_curr_time` in OnNewMail), not the writer's.
#[test]
fn node_reporter_startup_subscriptions_and_mail_time() {
    use runtime::app::{Mail, Value};
    let text = "Community = abe\nProcessConfig = pNodeReporter\n{\n  alt_nav_prefix = NAV_GT\n  \
                plat_report_input = BATT_V, gap=1\n}\n";
    let m = mission::moos::parse_moos(&SourceMap::from_text("n.moos", text)).value;
    let make = || {
        VehicleApp::node_reporter(
            "pNodeReporter",
            block(&m, "pNodeReporter"),
            "abe",
            START,
            None,
            0,
        )
        .unwrap()
    };
    let mut rep = make();
    let subs: Vec<String> = rep.subscriptions().into_iter().map(|s| s.pattern).collect();
    for v in [
        "NAV_*",
        "NAV_TRAJECTORY",
        "NAV_GT_X",
        "NAV_GT_TRANSP",
        "BATT_V",
    ] {
        assert!(subs.iter().any(|s| s == v), "{v} in {subs:?}");
    }
    assert!(rep.subscriptions().iter().any(|s| s.is_wildcard()));
    let mut out = Vec::new();
    rep.set_process_id(4321);
    rep.on_startup(START, &mut out).unwrap();
    assert_eq!(out.len(), 1);
    assert_eq!(out[0].key, "PNODEREPORTER_PID");
    assert_eq!(out[0].value, Value::Double(4321.0));
    // Without a process id (`coug run`): nothing.
    let mut out = Vec::new();
    make().on_startup(START, &mut out).unwrap();
    assert!(out.is_empty());
    // Mail written 100 s before the reporter reads it: the alt-nav record counts as fresh
    // from the reading (within 5 s at START + 3), so its report follows the node report.
    let mail = |key: &str, x: f64| Mail {
        key: key.into(),
        value: Value::Double(x),
        time: START - 100.0,
        source: "uSimMarine".into(),
        source_aux: Default::default(),
        community: "abe".into(),
    };
    let batch: Vec<Mail> = [
        ("NAV_X", 1.0),
        ("NAV_Y", 2.0),
        ("NAV_SPEED", 0.0),
        ("NAV_HEADING", 0.0),
        ("NAV_GT_X", 3.0),
        ("NAV_GT_Y", 4.0),
        ("BATT_V", 12.0),
    ]
    .into_iter()
    .map(|(k, x)| mail(k, x))
    .collect();
    let mut out = Vec::new();
    rep.on_mail(&batch, START + 1.0, &mut out).unwrap();
    rep.iterate(START + 3.0, &mut out).unwrap();
    let reports: Vec<String> = out
        .iter()
        .filter(|p| p.key == "NODE_REPORT_LOCAL")
        .filter_map(|p| p.value.as_str().map(str::to_string))
        .collect();
    assert_eq!(reports.len(), 2, "{reports:?}");
    assert!(
        reports[1].starts_with("NAME=abe_GT,X=3,Y=4,"),
        "{reports:?}"
    );
    // The platform input changed after its (zero) last report time: reported at once.
    let plat: Vec<&Post> = out
        .iter()
        .filter(|p| p.key == "PLATFORM_REPORT_LOCAL")
        .collect();
    assert_eq!(
        plat[0].value,
        Value::text("platform=abe,utc_time=1786000003.00000,BATT_V=12")
    );
}
