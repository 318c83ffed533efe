//! pSafety end to end, in lockstep: each rule kind's fault injected mid-dive into
//! `tests/missions/safety` (uSimMarineV22 + pMarinePIDV22 + pHelmIvP + pSafety; the watched
//! sensors are uTimerScript heartbeats paused by `<SENSOR>_FAULT` pokes), and the action
//! checked in the alog; a helm in MALCONFIG and a helm killed mid-dive still get the vehicle
//! surfaced, on the actuators.
//!
//! Bounds: the vehicle dives to about 3.7 m; a `surface_disarm` with the helm alive reaches
//! 0.3 m within 15 s of the trigger (the actuators: thrust 20, elevator -100; it takes
//! about 3 s) and is disarmed 5 s (`surface_hold`) later; buoyancy alone (0.025 m/s) would
//! take about 150 s.

mod common;

use std::path::PathBuf;

use alog::Alog;
use common::*;

fn mission() -> PathBuf {
    let p = PathBuf::from(concat!(
        env!("CARGO_MANIFEST_DIR"),
        "/tests/missions/safety/safety.moos"
    ));
    assert!(p.is_file(), "{} is missing", p.display());
    p
}

/// Runs the test mission with `macros` and `pokes` until `CHECK_END = true` (poked at `end`).
fn run(name: &str, macros: &[&str], pokes: &[&str], end: f64) -> Alog {
    let mut opts = deploy_until("CHECK_END = true", end + 60.0);
    opts.pokes = pokes.iter().map(|p| p.to_string()).collect();
    opts.pokes.push(format!("CHECK_END=true@{end}"));
    let (bytes, _) = run_lockstep(name, &mission(), macros, opts);
    parse(&bytes)
}

/// `(time, value)` of every string post of `var`.
fn texts(log: &Alog, var: &str) -> Vec<(f64, String)> {
    log.entries
        .iter()
        .filter(|e| e.var == var)
        .filter_map(|e| Some((e.time, e.value.as_str()?.to_string())))
        .collect()
}

/// The time of the first post of `var` whose text starts with `prefix`, after `after`.
fn first_text(log: &Alog, var: &str, prefix: &str, after: f64) -> Option<f64> {
    texts(log, var)
        .into_iter()
        .find(|(t, v)| *t >= after && v.starts_with(prefix))
        .map(|(t, _)| t)
}

/// The last NAV_DEPTH at or before `t`.
fn depth_at(log: &Alog, t: f64) -> f64 {
    depths(log)
        .iter()
        .rev()
        .find(|p| p.0 <= t)
        .map_or(0.0, |p| p.1)
}

/// The trigger event of `rule`: its time, checked to be within `within` s after `fault`.
fn trigger(log: &Alog, rule: &str, fault: f64, within: f64) -> (f64, String) {
    let (t, text) = texts(log, "SAFETY_EVENT")
        .into_iter()
        .find(|(_, v)| v.starts_with(&format!("trigger={rule},")))
        .unwrap_or_else(|| panic!("{rule} never triggered: {:?}", texts(log, "SAFETY_EVENT")));
    assert!(
        t >= fault && t <= fault + within,
        "{rule} triggered at {t}, fault at {fault}"
    );
    // Nothing else triggered before it (the nominal dive is clean).
    let first = texts(log, "SAFETY_EVENT")
        .into_iter()
        .find(|(_, v)| v.starts_with("trigger="))
        .unwrap();
    assert_eq!(first.1, text, "another rule triggered first");
    (t, text)
}

/// A `surface_disarm` on the actuators from mid-dive: the helm overridden (all-stop), up
/// within 15 s, disarmed after 5 s there, and nothing but zero thrust afterwards.
fn assert_surfaced_and_disarmed(log: &Alog, t_trig: f64) -> f64 {
    assert!(
        depth_at(log, t_trig) > 2.5,
        "not mid-dive: {} m",
        depth_at(log, t_trig)
    );
    let ov = log
        .entries
        .iter()
        .find(|e| e.var == "MOOS_MANUAL_OVERRIDE" && e.time >= t_trig)
        .expect("the helm is overridden");
    assert_eq!(
        (ov.source.as_str(), ov.value.as_str()),
        ("pSafety", Some("true"))
    );
    assert!(ov.time - t_trig < 0.01, "override at {}", ov.time);
    let stop = first_text(log, "IVPHELM_ALLSTOP", "ManualOverride", t_trig).expect("all-stop");
    assert!(stop - t_trig <= 0.5, "helm all-stop at {stop}");
    let up = depths(log)
        .into_iter()
        .find(|p| p.0 > t_trig && p.1 < 0.3)
        .expect("surfaces")
        .0;
    assert!(
        up - t_trig <= 15.0,
        "surfaced {} s after the trigger",
        up - t_trig
    );
    let disarmed = first_text(log, "SAFETY_MODE", "DISARMED", t_trig).expect("disarmed");
    assert!(
        disarmed - up >= 5.0 && disarmed - up <= 6.0,
        "disarmed at {disarmed}, up at {up}"
    );
    assert!(depth_at(log, disarmed) < 0.3);
    assert_eq!(
        first_text(log, "THRUST_ARMED", "false", t_trig),
        Some(disarmed),
        "the disarm flag"
    );
    let after: Vec<f64> = log
        .entries
        .iter()
        .filter(|e| e.var == "DESIRED_THRUST" && e.time >= disarmed)
        .filter_map(|e| e.value.as_f64())
        .collect();
    assert!(
        after.len() > 10 && after.iter().all(|x| *x == 0.0),
        "{after:?}"
    );
    assert!(
        depths(log)
            .iter()
            .filter(|p| p.0 >= disarmed)
            .all(|p| p.1 < 0.3),
        "stays at the surface"
    );
    let speed = log
        .entries
        .iter()
        .rev()
        .find(|e| e.var == "NAV_SPEED")
        .and_then(|e| e.value.as_f64())
        .unwrap();
    assert!(speed < 0.05, "still moving at {speed} m/s");
    disarmed
}

#[test]
fn leak_mid_dive_all_stop_surface_and_disarm() {
    let log = run("safety-leak", &[], &["LEAK=false", "LEAK=true@60"], 100.0);
    let (t, text) = trigger(&log, "leak", 60.0, 0.3);
    assert_eq!(
        text,
        "trigger=leak,action=surface_disarm,priority=1,reason=LEAK == true (LEAK=true)"
    );
    assert_surfaced_and_disarmed(&log, t);
    assert_eq!(
        first_text(&log, "SAFETY_EVENT", "mode=SURFACE,via=actuators", t),
        Some(t)
    );
    // The health word: triggered, surfacing, on the actuators, a leak; then disarmed.
    let health: Vec<f64> = log
        .entries
        .iter()
        .filter(|e| e.var == "SAFETY_HEALTH")
        .filter_map(|e| e.value.as_f64())
        .collect();
    assert_eq!(
        health,
        [0.0, (1 + 16 + 64 + 256) as f64, (1 + 32 + 64 + 256) as f64]
    );
    // Latched: the leak reading false again does not release it.
    assert_eq!(last_str(&log, "SAFETY_MODE").as_deref(), Some("DISARMED"));
}

#[test]
fn low_battery_mid_dive_surfaces_and_disarms() {
    let log = run(
        "safety-battery",
        &[],
        &["BATTERY_VOLTAGE=16.2", "BATTERY_VOLTAGE=13.6@60"],
        100.0,
    );
    let (t, text) = trigger(&log, "battery", 60.0, 0.3);
    assert!(
        text.ends_with("reason=BATTERY_VOLTAGE < 14 (BATTERY_VOLTAGE=13.6)"),
        "{text}"
    );
    assert_surfaced_and_disarmed(&log, t);
}

#[test]
fn too_deep_surfaces_and_disarms() {
    // A mission error: the helm is told to go to 12 m; the 8 m limit stops it.
    let log = run("safety-depth", &[], &["DEPTH_UPDATE=depth=12@60"], 120.0);
    let (t, text) = trigger(&log, "depth", 60.0, 30.0);
    assert!(
        text.contains("reason=NAV_DEPTH > 8 (NAV_DEPTH=8."),
        "{text}"
    );
    assert_surfaced_and_disarmed(&log, t);
    let max = depths(&log).iter().map(|p| p.1).fold(0.0, f64::max);
    assert!(max < 9.0, "went down to {max} m");
}

#[test]
fn stale_dvl_and_depth_sensor_surface_and_disarm() {
    for (sensor, rule, var) in [
        ("DVL", "dvl", "DVL_VALID"),
        ("PRESSURE", "pressure", "PRESSURE"),
    ] {
        let log = run(
            &format!("safety-{rule}"),
            &[],
            &[&format!("{sensor}_FAULT=true@60")],
            100.0,
        );
        // The last heartbeat is at most 0.5 s before the fault; stale after 3 s more.
        let (t, text) = trigger(&log, rule, 62.5, 1.5);
        assert!(
            text.contains(&format!("reason=stale({var}) > 3 (no {var} for ")),
            "{text}"
        );
        assert_surfaced_and_disarmed(&log, t);
    }
}

#[test]
fn stale_ahrs_is_an_all_stop() {
    let log = run("safety-ahrs", &[], &["AHRS_FAULT=true@60"], 100.0);
    let (t, _) = trigger(&log, "ahrs", 62.5, 1.5);
    assert_eq!(first_text(&log, "SAFETY_MODE", "ALLSTOP", t), Some(t));
    assert!(first_text(&log, "IVPHELM_ALLSTOP", "ManualOverride", t).is_some());
    assert!(first_text(&log, "SAFETY_MODE", "SURFACE", t).is_none());
    let thrust: Vec<f64> = log
        .entries
        .iter()
        .filter(|e| e.var == "DESIRED_THRUST" && e.time > t)
        .filter_map(|e| e.value.as_f64())
        .collect();
    assert!(!thrust.is_empty() && thrust.iter().all(|x| *x == 0.0));
    // Stopped, rising only with its buoyancy (0.025 m/s): still deep 35 s later.
    let speed = log
        .entries
        .iter()
        .rev()
        .find(|e| e.var == "NAV_SPEED")
        .and_then(|e| e.value.as_f64())
        .unwrap();
    assert!(speed < 0.05, "{speed}");
    assert!(depth_at(&log, 100.0) > 2.0, "{}", depth_at(&log, 100.0));
}

#[test]
fn gps_silent_at_the_surface_is_a_warning_that_clears() {
    // The GPS stops mid-dive (expected there), the helm brings the vehicle up at 80 s; the
    // warning comes once it is up (10 s stale and shallower than 0.5 m) and clears 5 s
    // after the GPS is back. The helm keeps driving throughout.
    let log = run(
        "safety-gps",
        &[],
        &[
            "GPS_FAULT=true@60",
            "DEPTH_UPDATE=depth=0@80",
            "GPS_FAULT=false@150",
        ],
        170.0,
    );
    let up = depths(&log)
        .into_iter()
        .find(|p| p.0 > 80.0 && p.1 < 0.5)
        .expect("the helm brings it up")
        .0;
    let (t, text) = trigger(&log, "gps", up, 1.0);
    assert!(
        text.starts_with("trigger=gps,action=warn,priority=4,"),
        "{text}"
    );
    assert_eq!(first_text(&log, "SAFETY_MODE", "WARN", t), Some(t));
    let cleared = first_text(&log, "SAFETY_EVENT", "clear=gps,by=cleared", t).expect("clears");
    assert!((155.0..=157.0).contains(&cleared), "{cleared}");
    assert_eq!(first_text(&log, "SAFETY_MODE", "OK", t), Some(cleared));
    assert!(
        !log.entries
            .iter()
            .any(|e| e.var == "MOOS_MANUAL_OVERRIDE" && e.source == "pSafety"),
        "a warning never overrides the helm"
    );
}

#[test]
fn navigation_sigma_returns_home_then_resumes() {
    let log = run(
        "safety-nav",
        &[],
        &["NAV_POS_STD=1.5", "NAV_POS_STD=12@60", "NAV_POS_STD=2@90"],
        150.0,
    );
    let (t, _) = trigger(&log, "nav", 60.0, 0.3);
    assert_eq!(first_text(&log, "RETURN", "true", t), Some(t));
    let t_ = track(&log);
    let dist = |time: f64| {
        let p = t_.iter().rev().find(|p| p.0 <= time).unwrap();
        p.1.hypot(p.2)
    };
    assert!(
        dist(119.0) < dist(61.0) - 30.0,
        "heads home: {} -> {}",
        dist(61.0),
        dist(119.0)
    );
    assert!(depth_at(&log, 119.0) < 0.5, "returns at the surface");
    // 30 s after the sigma is good again: released, the clear flag, the survey resumes.
    let cleared = first_text(&log, "SAFETY_EVENT", "clear=nav,by=cleared", t).unwrap();
    assert!((120.0..=120.5).contains(&cleared), "{cleared}");
    assert_eq!(first_text(&log, "RETURN", "false", t), Some(cleared));
    assert!(dist(150.0) > dist(cleared) + 10.0, "surveys again");
}

#[test]
fn no_base_contact_returns() {
    // The base's messages stop after the one at 30 s: stale after 120 s more.
    let log = run("safety-comms", &[], &["BASE_FAULT=true@40"], 165.0);
    let (t, text) = trigger(&log, "comms", 150.0, 1.0);
    assert!(
        text.contains("stale(ACOMMS_LAST_BASE_CONTACT) > 120"),
        "{text}"
    );
    assert_eq!(first_text(&log, "SAFETY_MODE", "RETURN", t), Some(t));
    assert!(
        first_text(&log, "MODE", "ACTIVE:RETURNING", t).is_some(),
        "the helm returns"
    );
}

#[test]
fn surfacing_through_the_helm_then_disarm() {
    let log = run(
        "safety-viahelm",
        &["SURFACE_VIA=helm"],
        &["LEAK=true@60"],
        130.0,
    );
    let (t, _) = trigger(&log, "leak", 60.0, 0.3);
    assert_eq!(
        first_text(&log, "SAFETY_EVENT", "mode=SURFACE,via=helm", t),
        Some(t)
    );
    assert_eq!(first_text(&log, "SAFETY_SURFACE", "true", t), Some(t));
    // The helm brings it up (its safety behaviours); pSafety overrides only at the disarm.
    let disarmed = first_text(&log, "SAFETY_MODE", "DISARMED", t).expect("disarmed");
    let ov = log
        .entries
        .iter()
        .find(|e| e.var == "MOOS_MANUAL_OVERRIDE" && e.source == "pSafety")
        .unwrap();
    assert_eq!(ov.time, disarmed);
    assert!(first_text(&log, "SAFETY_EVENT", "helm_failed", t).is_none());
    assert!(disarmed - t <= 60.0, "{}", disarmed - t);
    assert!(depth_at(&log, disarmed) < 0.3);
}

#[test]
fn a_malconfig_helm_at_depth_is_surfaced_on_the_actuators() {
    // The helm cannot read its behaviours (MALCONFIG); the vehicle starts at 5 m.
    let log = run(
        "safety-helmcfg",
        &["BHV=no-such-file.bhv", "START_DEPTH=5"],
        &[],
        40.0,
    );
    let (t, text) = trigger(&log, "helmcfg", 0.0, 1.0);
    assert!(text.contains("IVPHELM_STATE=MALCONFIG"), "{text}");
    let up = depths(&log)
        .into_iter()
        .find(|p| p.1 < 0.3)
        .expect("surfaces")
        .0;
    assert!(up - t < 15.0, "{up}");
    let disarmed = first_text(&log, "SAFETY_MODE", "DISARMED", t).expect("disarmed");
    assert!(disarmed < 25.0 && depth_at(&log, disarmed) < 0.3);
}

#[test]
fn a_bad_rule_keeps_the_vehicle_from_deploying() {
    let log = run(
        "safety-malconfig",
        &["RULE=bad: LEAK = true -> surface_disarm"],
        &[],
        60.0,
    );
    assert_eq!(texts(&log, "SAFETY_MODE")[0].1, "MALCONFIG");
    assert_eq!(
        last_str(&log, "MOOS_MANUAL_OVERRIDE").as_deref(),
        Some("true")
    );
    assert!(
        texts(&log, "SAFETY_EVENT").is_empty(),
        "{:?}",
        texts(&log, "SAFETY_EVENT")
    );
    let max = depths(&log).iter().map(|p| p.1).fold(0.0, f64::max);
    let t = track(&log);
    let (x, y) = (t.last().unwrap().1, t.last().unwrap().2);
    assert!(
        max < 0.3 && x.hypot(y) < 2.0,
        "moved: depth {max}, at {x},{y}"
    );
    assert_eq!(
        last_str(&log, "IVPHELM_ALLSTOP").as_deref(),
        Some("ManualOverride")
    );
}

/// An app that dies at `at`: from then on it neither reads nor posts (not even its
/// `<APP>_STATUS`: the scheduler drops a finished app from the community).
struct KilledAt {
    inner: Box<dyn runtime::App>,
    at: f64,
    dead: bool,
}

impl runtime::App for KilledAt {
    fn name(&self) -> &str {
        self.inner.name()
    }
    fn process_config(&self) -> Option<&mission::moos::ProcessConfig> {
        self.inner.process_config()
    }
    fn app_tick(&self) -> f64 {
        self.inner.app_tick()
    }
    fn subscriptions(&self) -> Vec<runtime::Subscription> {
        self.inner.subscriptions()
    }
    fn new_subscriptions(&mut self) -> Vec<runtime::Subscription> {
        self.inner.new_subscriptions()
    }
    fn on_startup(&mut self, now: f64, out: &mut Vec<runtime::Post>) -> runtime::AppResult {
        self.inner.on_startup(now, out)
    }
    fn on_mail(
        &mut self,
        mail: &[runtime::Mail],
        now: f64,
        out: &mut Vec<runtime::Post>,
    ) -> runtime::AppResult {
        if self.dead {
            return Ok(());
        }
        self.inner.on_mail(mail, now, out)
    }
    fn iterate(&mut self, now: f64, out: &mut Vec<runtime::Post>) -> runtime::AppResult {
        if now >= self.at {
            self.dead = true;
            return Ok(());
        }
        self.inner.iterate(now, out)
    }
    fn finished(&self) -> bool {
        self.dead
    }
}

/// One sample of the DB every 0.25 s.
struct Sample {
    t: f64,
    depth: f64,
    thrust: f64,
    mode: String,
}

/// Runs the test mission in lockstep with the helm killed at `helm_dies` s and pSafety
/// killed at `safety_dies` s (0: never runs); returns the samples and every SAFETY_EVENT.
fn run_with_kills(macros: &[&str], helm_dies: f64, safety_dies: f64) -> (Vec<Sample>, Vec<String>) {
    use runtime::antler::{Built, Launch, MissionGlobals};
    const START: f64 = 1_786_000_000.0;
    let macros: Vec<String> = macros.iter().map(|m| m.to_string()).collect();
    let loaded = runtime::session::load(&mission(), &macros, &[]).expect("loads");
    let m = loaded.mission.clone();
    let (globals, _) = MissionGlobals::from_mission(&m);
    let files = loaded.helm_files();
    let plan = runtime::antler::plan(
        &m,
        Launch::new(START, 1).with_helm_files(files.clone()),
        &mut |run, _| {
            let dies = match run.app.as_str() {
                "pHelmIvP" => helm_dies,
                "pSafety" => safety_dies,
                _ => return None,
            };
            let mut launch = Launch::new(START, 1).with_helm_files(files.clone());
            let built = runtime::antler::build(
                &run.app,
                run.moos_name(),
                &m,
                &globals,
                &mut launch,
                &mut Vec::new(),
            );
            Some(match built {
                Ok(Built::App(inner)) => Ok(Box::new(KilledAt {
                    inner,
                    at: START + dies,
                    dead: false,
                }) as Box<dyn runtime::App>),
                _ => Err("not built".to_string()),
            })
        },
    )
    .expect("plans");
    let mut s = runtime::Scheduler::new(
        runtime::Bus::new(&plan.globals.community, START),
        runtime::VirtualClock,
        START,
    );
    for app in plan.apps {
        s.add_app(app).unwrap();
    }
    for p in ["DEPLOY=true", "MOOS_MANUAL_OVERRIDE=false"] {
        s.add_poke(runtime::Poke::parse(p, "pHelmIvP").unwrap())
            .unwrap();
    }
    s.tap("SAFETY_EVENT");
    let num = |s: &runtime::Scheduler, k: &str| s.current(k).and_then(|v| v.as_f64());
    let mut samples = Vec::new();
    let mut events = Vec::new();
    for i in 1..=(140 * 4) {
        let t = f64::from(i) * 0.25;
        assert!(s.advance(START + t).unwrap().is_none());
        events.extend(
            s.take_taps()
                .into_iter()
                .filter_map(|p| p.value.as_str().map(String::from)),
        );
        samples.push(Sample {
            t,
            depth: num(&s, "NAV_DEPTH").unwrap_or(0.0),
            thrust: num(&s, "DESIRED_THRUST").unwrap_or(0.0),
            mode: s
                .current("SAFETY_MODE")
                .and_then(|v| v.as_str().map(String::from))
                .unwrap_or_default(),
        });
    }
    (samples, events)
}

#[test]
fn a_helm_killed_mid_dive_is_surfaced_on_the_actuators() {
    // Surfacing is configured through the helm; the helm is the failure, so pSafety takes
    // the actuators at once.
    let (samples, events) = run_with_kills(&["SURFACE_VIA=helm"], 60.0, 1e9);
    let at = |t: f64| samples.iter().find(|s| s.t >= t).unwrap();
    assert!(at(60.0).depth > 3.0, "mid-dive: {}", at(60.0).depth);
    // Silent for more than 5 s: the last status at 58-60 s, the trigger by 66 s.
    let trig = events
        .iter()
        .position(|e| e.starts_with("trigger=helm,action=surface_disarm"))
        .unwrap_or_else(|| panic!("{events:?}"));
    assert!(
        events[trig].contains("pHelmIvP silent for"),
        "{}",
        events[trig]
    );
    assert!(
        events[trig + 1].starts_with("mode=SURFACE,via=actuators,helm_failed=pHelmIvP silent for"),
        "{events:?}"
    );
    let surfacing = samples.iter().find(|s| s.mode == "SURFACE").unwrap().t;
    assert!((65.0..=66.5).contains(&surfacing), "{surfacing}");
    let up = samples
        .iter()
        .find(|s| s.t > 60.0 && s.depth < 0.3)
        .unwrap()
        .t;
    assert!(up - surfacing <= 15.0, "up at {up}");
    let disarmed = samples.iter().find(|s| s.mode == "DISARMED").unwrap().t;
    assert!(disarmed - up <= 6.0, "disarmed at {disarmed}");
    assert!(
        samples
            .iter()
            .filter(|s| s.t >= disarmed)
            .all(|s| s.thrust == 0.0 && s.depth < 0.3)
    );

    // The same failure without pSafety: the PID sees a tardy helm and stops; the vehicle
    // drifts up on its buoyancy alone and is still deep at the end.
    let (alone, events) = run_with_kills(&[], 60.0, 0.0);
    assert!(events.is_empty(), "{events:?}");
    let at = |t: f64| alone.iter().find(|s| s.t >= t).unwrap();
    assert!(at(60.0).depth > 3.0);
    assert!(at(100.0).depth > 2.0, "{}", at(100.0).depth);
    assert!(at(140.0).depth > 1.0, "{}", at(140.0).depth);
}

#[test]
fn check_and_run_report_a_bad_rule_at_its_line() {
    let loaded = runtime::session::load(
        &mission(),
        &["RULE=bad: LEAK = true -> surface_disarm".to_string()],
        &[],
    )
    .expect("loads");
    let v = runtime::session::validate(&loaded);
    assert!(v.errors.is_empty(), "{:?}", v.errors);
    let (app, why) = v
        .malconfig
        .iter()
        .find(|(a, _)| a == "pSafety")
        .expect("pSafety is MALCONFIG");
    assert_eq!(app, "pSafety");
    assert_eq!(why.len(), 1, "{why:?}");
    assert!(
        why[0].ends_with("safety.moos:148: pSafety: rule `bad: LEAK = true -> surface_disarm`: bad operator in `LEAK = true`: use one of == != < <= > >="),
        "{why:?}"
    );
    // The good mission has none.
    let loaded = runtime::session::load(&mission(), &[], &[]).unwrap();
    assert!(runtime::session::validate(&loaded).malconfig.is_empty());
}
