//! Engine behaviour driven by `.bhv` text and scripted mail (time, variable, value).

mod common;

use common::{all, get, is_str};
use helm::config::Globals;
use helm::{Helm, HelmState, Mail, Posting, Value};
use mission::source::SourceMap;

fn globals() -> Globals {
    Globals {
        lat_origin: Some("43.8253".into()),
        long_origin: Some("-70.3304".into()),
        community: Some("abe".into()),
    }
}

fn helm_with(params: &[(&str, &str)], bhv: &str) -> Helm {
    let parsed = mission::bhv::parse_bhv(&SourceMap::from_text("t.bhv", bhv));
    let mut p = vec![("domain", "course:0:359:360"), ("domain", "speed:0:4:41")];
    p.extend_from_slice(params);
    Helm::from_parsed(&p, &globals(), &parsed)
}

/// A scripted session: every step feeds nav at a fixed pose plus the given mail.
struct Script {
    helm: Helm,
    t: f64,
}

impl Script {
    fn new(helm: Helm) -> Self {
        Script { helm, t: 0.0 }
    }
    fn nav(&mut self, x: f64, y: f64, h: f64) {
        let t = self.t;
        self.helm.on_mail(&[
            Mail::new("NAV_X", x, t),
            Mail::new("NAV_Y", y, t),
            Mail::new("NAV_HEADING", h, t),
            Mail::new("NAV_SPEED", 1.0, t),
        ]);
    }
    /// Advances to time `t`, delivers `mail` (var, string value) and iterates.
    fn at(&mut self, t: f64, mail: &[(&str, &str)]) -> Vec<Posting> {
        self.t = t;
        let m: Vec<Mail> = mail
            .iter()
            .map(|(k, v)| Mail::new(k, *v, t).from("uPokeDB"))
            .collect();
        self.helm.on_mail(&m);
        self.helm.iterate(t).to_vec()
    }
    /// Nav at (x, y, h), then `at`.
    fn step(&mut self, t: f64, x: f64, y: f64, h: f64, mail: &[(&str, &str)]) -> Vec<Posting> {
        self.t = t;
        self.nav(x, y, h);
        self.at(t, mail)
    }
}

fn has_desired(posts: &[Posting]) -> bool {
    posts.iter().any(|p| p.key.starts_with("DESIRED_"))
}

const HEADING_BHV: &str = "\
initialize DEPLOY = false
Behavior = BHV_ConstantHeading
{
  name      = hdg
  condition = DEPLOY = true
  heading   = 45
  duration  = no-time-limit
  updates   = HDG_UPDATE
}
Behavior = BHV_ConstantSpeed
{
  name      = spd
  condition = DEPLOY = true
  speed     = 2
  duration  = no-time-limit
}
";

#[test]
fn unknown_helm_parameter_is_malconfig_and_never_decides() {
    let helm = helm_with(
        &[("start_engaged", "true"), ("bogus_param", "1")],
        HEADING_BHV,
    );
    assert_eq!(helm.state(), HelmState::Malconfig);
    assert!(helm.config_errors()[0].to_string().contains("bogus_param"));
    let mut s = Script::new(helm);
    let first = s.step(
        0.0,
        0.0,
        0.0,
        0.0,
        &[("MOOS_MANUAL_OVERRIDE", "false"), ("DEPLOY", "true")],
    );
    let why: Vec<&str> = all(&first, "IVPHELM_CONFIG_WARNING")
        .iter()
        .map(|v| v.as_str().unwrap())
        .collect();
    assert_eq!(why, ["Unhandled config line: bogus_param = 1"]);
    // pHelmIvP posts behaviour-set warnings (IVPHELM_BHVSET_WARNING) only from an enabled
    // helm: a MALCONFIG one returns before, so they are never posted here.
    assert!(all(&first, "IVPHELM_BHVSET_WARNING").is_empty());
    for k in 1..20 {
        let posts = s.step(
            f64::from(k),
            0.0,
            0.0,
            0.0,
            &[("MOOS_MANUAL_OVERRIDE", "false")],
        );
        assert!(!has_desired(&posts), "{posts:?}");
        assert_eq!(posts.len(), 1);
        assert!(is_str(get(&posts, "IVPHELM_STATE"), "MALCONFIG"));
    }
}

#[test]
fn unknown_behavior_parameter_is_malconfig_with_the_line() {
    let bhv = HEADING_BHV.replace("heading   = 45", "heading   = 45\n  headingg  = 50");
    let helm = helm_with(&[("start_engaged", "true")], &bhv);
    assert_eq!(helm.state(), HelmState::Malconfig);
    let msg = helm.config_errors()[0].to_string();
    assert!(msg.contains("t.bhv: Line 7: headingg = 50"), "{msg}");
    let mut s = Script::new(helm);
    for k in 0..10 {
        let posts = s.step(f64::from(k), 0.0, 0.0, 0.0, &[("DEPLOY", "true")]);
        assert!(!has_desired(&posts));
    }
    // A bad value is as fatal as an unknown name.
    let bhv = HEADING_BHV.replace("speed     = 2", "speed     = fast");
    let helm = helm_with(&[], &bhv);
    assert_eq!(helm.state(), HelmState::Malconfig);
    assert!(helm.config_errors()[0].to_string().contains("speed = fast"));
}

#[test]
fn missing_globals_and_unknown_behavior_types_are_malconfig() {
    let parsed = mission::bhv::parse_bhv(&SourceMap::from_text("t.bhv", HEADING_BHV));
    let g = Globals {
        community: None,
        ..globals()
    };
    let h = Helm::from_parsed(&[("domain", "course:0:359:360")], &g, &parsed);
    assert_eq!(h.state(), HelmState::Malconfig);
    assert_eq!(h.config_errors()[0].to_string(), "Missing global Community");
    let h = helm_with(&[], "Behavior = BHV_Teleport\n{\n name = x\n}\n");
    assert!(
        h.config_errors()[0]
            .to_string()
            .contains("unknown behavior type BHV_Teleport")
    );
}

#[test]
fn decisions_need_control_nav_and_the_first_second() {
    let helm = helm_with(&[], HEADING_BHV);
    let mut s = Script::new(helm);
    // PARK, no nav yet: only the state.
    let posts = s.at(0.0, &[("DEPLOY", "true")]);
    assert!(is_str(get(&posts, "IVPHELM_STATE"), "PARK"));
    assert!(
        get(&posts, "IVPHELM_ALLSTOP").is_none(),
        "holding for nav: no all-stop"
    );
    // Nav without NAV_SPEED still holds.
    s.helm.on_mail(&[
        Mail::new("NAV_X", 0.0, 0.5),
        Mail::new("NAV_Y", 0.0, 0.5),
        Mail::new("NAV_HEADING", 0.0, 0.5),
    ]);
    let posts = s.at(0.5, &[("MOOS_MANUAL_OVERRIDE", "false")]);
    assert!(is_str(get(&posts, "IVPHELM_STATE"), "DRIVE"));
    assert!(get(&posts, "IVPHELM_ALLSTOP").is_none() && !has_desired(&posts));
    // With NAV_SPEED the helm is ready, but it is still the first second.
    s.helm.on_mail(&[Mail::new("NAV_SPEED", 0.0, 0.75)]);
    let posts = s.at(0.75, &[]);
    assert!(!has_desired(&posts) && get(&posts, "IVPHELM_ITER").is_none());
    let posts = s.at(1.0, &[]);
    assert_eq!(get(&posts, "IVPHELM_ITER"), Some(&Value::Double(1.0)));
    let pcs = get(&posts, "IVPHELM_TOTAL_PCS_FORMED")
        .unwrap()
        .as_f64()
        .unwrap();
    assert!(pcs >= 2.0, "two functions, at least a piece each: {pcs}");
    let summary = get(&posts, "IVPHELM_SUMMARY").unwrap().as_str().unwrap();
    assert!(
        summary.starts_with(&format!(
            "iter=1,utc_time=1.00,ofnum=2,total_pcs_formed={pcs}"
        )),
        "{summary}"
    );
    assert_eq!(get(&posts, "DESIRED_HEADING"), Some(&Value::Double(45.0)));
    assert_eq!(get(&posts, "DESIRED_SPEED"), Some(&Value::Double(2.0)));
    // Decisions are posted every iteration, not only on change.
    let posts = s.at(1.25, &[]);
    assert_eq!(get(&posts, "DESIRED_HEADING"), Some(&Value::Double(45.0)));
    assert!(get(&posts, "IVPHELM_ALLSTOP").is_none());
}

#[test]
fn manual_override_mid_mission_stops_and_resumes() {
    let mut s = Script::new(helm_with(&[("start_engaged", "true")], HEADING_BHV));
    s.step(0.0, 0.0, 0.0, 0.0, &[("DEPLOY", "true")]);
    let posts = s.step(1.0, 0.0, 0.0, 0.0, &[]);
    assert!(is_str(get(&posts, "IVPHELM_ALLSTOP"), "clear"));
    assert_eq!(get(&posts, "DESIRED_HEADING"), Some(&Value::Double(45.0)));

    let posts = s.step(2.0, 0.0, 0.0, 0.0, &[("MOOS_MANUAL_OVERRIDE", "true")]);
    assert!(is_str(get(&posts, "IVPHELM_STATE"), "PARK"));
    assert!(is_str(get(&posts, "IVPHELM_ALLSTOP"), "ManualOverride"));
    assert_eq!(get(&posts, "DESIRED_HEADING"), Some(&Value::Double(0.0)));
    assert_eq!(get(&posts, "DESIRED_SPEED"), Some(&Value::Double(0.0)));
    let posts = s.step(3.0, 0.0, 0.0, 0.0, &[]);
    assert!(
        !has_desired(&posts),
        "zeros once, then silence while parked"
    );

    // The legacy misspelling releases it too.
    let posts = s.step(4.0, 0.0, 0.0, 0.0, &[("MOOS_MANUAL_OVERIDE", "FALSE")]);
    assert!(is_str(get(&posts, "IVPHELM_STATE"), "DRIVE"));
    assert!(is_str(get(&posts, "IVPHELM_ALLSTOP"), "clear"));
    assert_eq!(get(&posts, "DESIRED_HEADING"), Some(&Value::Double(45.0)));

    // allow_park = false: override requests are ignored.
    let mut s = Script::new(helm_with(
        &[("start_engaged", "true"), ("allow_park", "false")],
        HEADING_BHV,
    ));
    s.step(0.0, 0.0, 0.0, 0.0, &[("DEPLOY", "true")]);
    let posts = s.step(1.0, 0.0, 0.0, 0.0, &[("MOOS_MANUAL_OVERRIDE", "true")]);
    assert!(is_str(get(&posts, "IVPHELM_STATE"), "DRIVE"));
    assert_eq!(get(&posts, "DESIRED_HEADING"), Some(&Value::Double(45.0)));
}

#[test]
fn runtime_updates_good_bad_and_duplicate() {
    let mut s = Script::new(helm_with(&[("start_engaged", "true")], HEADING_BHV));
    s.step(0.0, 0.0, 0.0, 0.0, &[("DEPLOY", "true")]);
    let posts = s.step(1.0, 0.0, 0.0, 0.0, &[("HDG_UPDATE", "heading=90")]);
    let r = get(&posts, "IVPHELM_UPDATE_RESULT")
        .unwrap()
        .as_str()
        .unwrap();
    assert_eq!(
        r,
        "bhv=hdg,var=HDG_UPDATE,time=1.00,result=success,val=heading=90"
    );
    assert_eq!(get(&posts, "DESIRED_HEADING"), Some(&Value::Double(90.0)));

    // A bad value: a warning, the result, and the old value kept.
    let posts = s.step(
        2.0,
        0.0,
        0.0,
        0.0,
        &[("HDG_UPDATE", "heading=east # peakwidth=5")],
    );
    let r = get(&posts, "IVPHELM_UPDATE_RESULT")
        .unwrap()
        .as_str()
        .unwrap();
    // MOOS-IvP IvPBehavior::checkUpdates: the value as received, after `val=`.
    assert_eq!(
        r,
        "bhv=hdg,var=HDG_UPDATE,time=2.00,result=param_error,val=heading=east # peakwidth=5"
    );
    let w = get(&posts, "BHV_WARNING").unwrap().as_str().unwrap();
    assert_eq!(
        w,
        "Faulty update for behavior: hdg. Bad parameter(s): heading"
    );
    assert_eq!(get(&posts, "DESIRED_HEADING"), Some(&Value::Double(90.0)));
    let summary = get(&posts, "IVPHELM_SUMMARY").unwrap().as_str().unwrap();
    assert!(summary.contains("hdg$1.00$100.00000$"), "{summary}");
    assert!(summary.contains("$1/2$1"), "updates good/total: {summary}");

    // The same string again is a duplicate; a name mismatch is neither good nor bad.
    let posts = s.step(3.0, 0.0, 0.0, 0.0, &[("HDG_UPDATE", "heading=90")]);
    assert_eq!(
        get(&posts, "IVPHELM_UPDATE_RESULT").and_then(Value::as_str),
        Some("bhv=hdg,var=HDG_UPDATE,time=3.00,result=duplicate,val=heading=90")
    );
    let posts = s.step(
        4.0,
        0.0,
        0.0,
        0.0,
        &[("HDG_UPDATE", "name=other # heading=10")],
    );
    assert_eq!(
        get(&posts, "IVPHELM_UPDATE_RESULT").and_then(Value::as_str),
        Some("bhv=hdg,var=HDG_UPDATE,time=4.00,result=name_mismatch,val=name=other # heading=10")
    );
    assert_eq!(get(&posts, "DESIRED_HEADING"), Some(&Value::Double(90.0)));
}

#[test]
fn hierarchical_modes_drive_behaviour_conditions() {
    let bhv = "\
initialize DEPLOY = false
initialize RETURN = false
set MODE = ACTIVE {
  DEPLOY = true
} INACTIVE
set MODE = RETURNING {
  MODE = ACTIVE
  RETURN = true
} SURVEYING
Behavior = BHV_ConstantHeading
{
  name = survey_hdg
  condition = MODE == SURVEYING
  heading = 100
  duration = no-time-limit
}
Behavior = BHV_ConstantHeading
{
  name = return_hdg
  condition = MODE == RETURNING
  heading = 280
  duration = no-time-limit
}
";
    let mut s = Script::new(helm_with(
        &[
            ("start_engaged", "true"),
            ("domain", "speed:0:4:41:optional"),
        ],
        bhv,
    ));
    // An optional var may stay undecided... but speed is declared twice here: MALCONFIG.
    assert_eq!(s.helm.state(), HelmState::Malconfig);

    let parsed = mission::bhv::parse_bhv(&SourceMap::from_text("m.bhv", bhv));
    let helm = Helm::from_parsed(
        &[
            ("domain", "course:0:359:360"),
            ("domain", "speed:0:4:41:optional"),
            ("start_engaged", "true"),
        ],
        &globals(),
        &parsed,
    );
    s = Script::new(helm);
    let posts = s.step(0.0, 0.0, 0.0, 0.0, &[]);
    assert!(is_str(
        get(&posts, "IVPHELM_MODESET"),
        "MODE#---,ACTIVE#---,INACTIVE#ACTIVE,RETURNING#ACTIVE,SURVEYING"
    ));
    let posts = s.step(1.0, 0.0, 0.0, 0.0, &[]);
    let mode = posts.iter().find(|p| p.key == "MODE").unwrap();
    assert_eq!(
        (mode.value.as_str(), &*mode.aux),
        (Some("INACTIVE"), "HELM_MODE")
    );
    let posts = s.step(2.0, 0.0, 0.0, 0.0, &[("DEPLOY", "true")]);
    assert!(is_str(get(&posts, "MODE"), "ACTIVE:SURVEYING"));
    // speed is optional: a course-only decision is complete.
    assert!(is_str(get(&posts, "IVPHELM_ALLSTOP"), "clear"));
    assert_eq!(get(&posts, "DESIRED_HEADING"), Some(&Value::Double(100.0)));
    let summary = get(&posts, "IVPHELM_SUMMARY").unwrap().as_str().unwrap();
    assert!(summary.contains("modes=MODE@ACTIVE:SURVEYING"), "{summary}");
    assert!(summary.contains("var=speed:varbalk"), "{summary}");
    let posts = s.step(3.0, 0.0, 0.0, 0.0, &[]);
    assert!(get(&posts, "MODE").is_none(), "mode posted on change only");
    let posts = s.step(4.0, 0.0, 0.0, 0.0, &[("RETURN", "true")]);
    assert!(is_str(get(&posts, "MODE"), "ACTIVE:RETURNING"));
    assert_eq!(get(&posts, "DESIRED_HEADING"), Some(&Value::Double(280.0)));
}

#[test]
fn missing_decision_variable_is_an_allstop() {
    let bhv = "Behavior = BHV_ConstantHeading\n{\n name = h\n heading = 10\n duration = no-time-limit\n}\n";
    let mut s = Script::new(helm_with(&[("start_engaged", "true")], bhv));
    s.step(0.0, 0.0, 0.0, 0.0, &[]);
    let posts = s.step(1.0, 0.0, 0.0, 0.0, &[]);
    assert!(is_str(get(&posts, "BHV_ERROR"), "MissingDecVars:speed"));
    assert!(is_str(
        get(&posts, "IVPHELM_ALLSTOP"),
        "MissingDecVars:speed"
    ));
    assert!(!has_desired(&posts), "grace iteration");
    let posts = s.step(2.0, 0.0, 0.0, 0.0, &[]);
    assert_eq!(get(&posts, "DESIRED_HEADING"), Some(&Value::Double(0.0)));
}

#[test]
fn constant_heading_default_duration_zero_completes_at_once() {
    let bhv =
        "Behavior = BHV_ConstantHeading\n{\n name = h\n heading = 10\n endflag = DONE = yes\n}\n";
    let mut s = Script::new(helm_with(&[("start_engaged", "true")], bhv));
    s.step(0.0, 0.0, 0.0, 0.0, &[]);
    let posts = s.step(1.0, 0.0, 0.0, 0.0, &[]);
    assert!(is_str(get(&posts, "DONE"), "yes"));
    assert!(is_str(get(&posts, "IVPHELM_ALLSTOP"), "NothingToDo"));
    // pHelmIvP's text: the file's behaviour is born with the first decision and dies in it.
    let events: Vec<&str> = posts
        .iter()
        .filter(|p| p.key == "IVPHELM_LIFE_EVENT")
        .map(|p| p.value.as_str().unwrap())
        .collect();
    assert_eq!(
        events,
        [
            "iter=0,time=1.00, bname=h, btype=BHV_ConstantHeading, event=spawn, seed=helm_startup,iter=1",
            "iter=0,time=1.00, bname=h, btype=BHV_ConstantHeading, event=death,iter=1",
        ]
    );
    let summary = get(&posts, "IVPHELM_SUMMARY").unwrap().as_str().unwrap();
    assert!(summary.contains("completed_bhvs=h$1.00$n/a"), "{summary}");
    assert!(s.helm.behavior_names().is_empty());
    assert!(is_str(get(&posts, "IVPHELM_COMPLETED_PENDING"), "true"));
    assert_eq!(
        get(&posts, "IVPHELM_COMPLETED_COUNT"),
        Some(&Value::Double(1.0))
    );
    assert!(is_str(get(&posts, "IVPHELM_STATEVARS"), "DONE"));
    assert_eq!(
        get(&posts, "IVPHELM_BHV_CNT_EVER"),
        Some(&Value::Double(1.0))
    );
}

#[test]
fn duration_status_reset_and_perpetual_endflags() {
    let bhv = "\
Behavior = BHV_ConstantSpeed
{
  name            = cs
  speed           = 1
  duration        = 3
  duration_status = CS_LEFT
  duration_reset  = CS_RESET = true
  perpetual       = true
  endflag         = CS_END = $[DUR_RUN_TIME]
  runflag         = CS_RUN = 1
  activeflag      = CS_ACTIVE = $[BHVNAME]/$[OWNSHIP]
}
Behavior = BHV_ConstantHeading
{
  name = h
  heading = 0
  duration = no-time-limit
}
";
    let mut s = Script::new(helm_with(&[("start_engaged", "true")], bhv));
    s.step(0.0, 0.0, 0.0, 0.0, &[]);
    let posts = s.step(1.0, 0.0, 0.0, 0.0, &[]);
    assert_eq!(get(&posts, "CS_RUN"), Some(&Value::Double(1.0)));
    assert!(is_str(get(&posts, "CS_ACTIVE"), "cs/abe"));
    assert_eq!(get(&posts, "CS_LEFT"), Some(&Value::Double(3.0)));
    let posts = s.step(2.0, 0.0, 0.0, 0.0, &[]);
    assert_eq!(get(&posts, "CS_LEFT"), Some(&Value::Double(2.0)));
    // A reset post restarts the clock.
    let posts = s.step(3.0, 0.0, 0.0, 0.0, &[("CS_RESET", "true")]);
    assert_eq!(all(&posts, "CS_LEFT"), [&Value::Double(3.0)]);
    s.step(4.0, 0.0, 0.0, 0.0, &[]);
    s.step(5.0, 0.0, 0.0, 0.0, &[]);
    let posts = s.step(6.0, 0.0, 0.0, 0.0, &[]);
    // Expired 3 s after the reset: endflag with the running time since the reset (a solo
    // numeric macro posts a double), but perpetual keeps it alive.
    assert_eq!(get(&posts, "CS_LEFT"), Some(&Value::Double(0.0)));
    assert_eq!(
        get(&posts, "CS_END"),
        Some(&Value::Double(3.0)),
        "{posts:?}"
    );
    assert_eq!(s.helm.behavior_names(), ["cs", "h"]);
    let posts = s.step(7.0, 0.0, 0.0, 0.0, &[]);
    assert_eq!(get(&posts, "DESIRED_SPEED"), Some(&Value::Double(1.0)));
}

#[test]
fn idle_and_inactive_flags_on_transitions() {
    let bhv = "\
initialize GO = false
Behavior = BHV_ConstantHeading
{
  name = h
  condition = GO = true
  heading = 0
  duration = no-time-limit
  idleflag = STATE_H = idle
  runflag = STATE_H = run
  inactiveflag = H_INACTIVE = $[BHVTYPE]
}
Behavior = BHV_ConstantSpeed
{
  name = s
  speed = 1
  duration = no-time-limit
}
";
    let mut s = Script::new(helm_with(&[("start_engaged", "true")], bhv));
    s.step(0.0, 0.0, 0.0, 0.0, &[]);
    let posts = s.step(1.0, 0.0, 0.0, 0.0, &[]);
    assert!(is_str(get(&posts, "STATE_H"), "idle"));
    assert!(is_str(get(&posts, "H_INACTIVE"), "BHV_ConstantHeading"));
    let posts = s.step(2.0, 0.0, 0.0, 0.0, &[]);
    assert!(
        get(&posts, "STATE_H").is_none(),
        "idle flags on the transition only"
    );
    let posts = s.step(3.0, 0.0, 0.0, 0.0, &[("GO", "true")]);
    assert!(is_str(get(&posts, "STATE_H"), "run"));
    let posts = s.step(4.0, 0.0, 0.0, 0.0, &[("GO", "false")]);
    assert!(is_str(get(&posts, "STATE_H"), "idle"));
    assert!(is_str(get(&posts, "IVPHELM_BHV_IDLE"), "h"));
}

#[test]
fn timer_posts_status_and_ends_by_duration() {
    let bhv = "\
initialize GO = false
Behavior = BHV_Timer
{
  name = t
  condition = GO = true
  duration = 3
  endflag = TIMER_DONE = true
}
Behavior = BHV_ConstantHeading
{
  name = h
  heading = 0
  duration = no-time-limit
}
Behavior = BHV_ConstantSpeed
{
  name = s
  speed = 1
  duration = no-time-limit
}
";
    let mut s = Script::new(helm_with(&[("start_engaged", "true")], bhv));
    s.step(0.0, 0.0, 0.0, 0.0, &[]);
    // Idle for two seconds: the timer posts both times every iteration (the helm filters
    // repeats); the times are accounted up to the previous iteration, as in pHelmIvP.
    let posts = s.step(1.0, 0.0, 0.0, 0.0, &[]);
    assert_eq!(get(&posts, "TIMER_IDLE"), Some(&Value::Double(0.0)));
    assert_eq!(get(&posts, "TIMER_RUNNING"), Some(&Value::Double(0.0)));
    s.step(2.0, 0.0, 0.0, 0.0, &[]);
    let posts = s.step(3.0, 0.0, 0.0, 0.0, &[]);
    assert_eq!(get(&posts, "TIMER_IDLE"), Some(&Value::Double(1.0)));
    let posts = s.step(4.0, 0.0, 0.0, 0.0, &[("GO", "true")]);
    assert!(is_str(get(&posts, "IVPHELM_BHV_RUNNING"), "t"));
    // The duration clock starts now and drops the idle time; the time since the previous
    // iteration is then booked as running (pHelmIvP's updateStateDurations).
    assert_eq!(get(&posts, "TIMER_IDLE"), Some(&Value::Double(0.0)));
    let posts = s.step(5.0, 0.0, 0.0, 0.0, &[]);
    assert_eq!(get(&posts, "TIMER_RUNNING"), Some(&Value::Double(1.0)));
    s.step(6.0, 0.0, 0.0, 0.0, &[]);
    let posts = s.step(7.0, 0.0, 0.0, 0.0, &[]);
    assert!(is_str(get(&posts, "TIMER_DONE"), "true"));
    assert_eq!(s.helm.behavior_names(), ["h", "s"]);
}

#[test]
fn skewed_mail_is_ignored_and_deferred_initialize_waits() {
    let bhv = "initialize_ LATE = 7\ninitialize_ KNOWN = 1\n".to_string() + HEADING_BHV;
    let mut s = Script::new(helm_with(&[("start_engaged", "true")], &bhv));
    let posts = s.step(0.0, 0.0, 0.0, 0.0, &[]);
    assert!(get(&posts, "LATE").is_none(), "deferred");
    s.helm
        .on_mail(&[Mail::new("KNOWN", "2", 100.0).from("other")]);
    let posts = s.step(100.0, 0.0, 0.0, 0.0, &[]);
    assert!(
        get(&posts, "LATE").is_none(),
        "not before IVPHELM_STATE mail"
    );
    // Mail 70 s old is skewed (ok_skew 60).
    s.helm
        .on_mail(&[Mail::new("DEPLOY", "true", 30.0).from("uPokeDB")]);
    s.helm
        .on_mail(&[Mail::new("IVPHELM_STATE", "DRIVE", 101.0).from("pHelmIvP")]);
    let posts = s.step(101.0, 0.0, 0.0, 0.0, &[]);
    let skew = get(&posts, "IVPHELM_SKEW").unwrap().as_str().unwrap();
    assert!(
        skew.starts_with("Helm ignores MOOS msg due to skew: DEPLOY Source=uPokeDB Skew=71.00"),
        "{skew}"
    );
    assert!(is_str(get(&posts, "IVPHELM_ALLSTOP"), "NothingToDo"));
    let late = posts.iter().find(|p| p.key == "LATE").unwrap();
    assert_eq!(
        (&late.value, &*late.aux),
        (&Value::Double(7.0), "HELM_VAR_INIT")
    );
    assert!(
        get(&posts, "KNOWN").is_none(),
        "already known: not initialized"
    );
}

#[test]
fn helm_prefix_and_park_on_allstop() {
    let mut s = Script::new(helm_with(
        &[
            ("start_engaged", "true"),
            ("helm_prefix", "H1_"),
            ("park_on_allstop", "true"),
        ],
        HEADING_BHV,
    ));
    s.step(0.0, 0.0, 0.0, 0.0, &[("DEPLOY", "true")]);
    let posts = s.step(1.0, 0.0, 0.0, 0.0, &[]);
    assert_eq!(
        get(&posts, "H1_DESIRED_HEADING"),
        Some(&Value::Double(45.0))
    );
    assert!(get(&posts, "DESIRED_HEADING").is_none());
    let posts = s.step(2.0, 0.0, 0.0, 0.0, &[("DEPLOY", "false")]);
    assert!(is_str(get(&posts, "IVPHELM_ALLSTOP"), "NothingToDo"));
    let posts = s.step(3.0, 0.0, 0.0, 0.0, &[]);
    assert!(
        is_str(get(&posts, "IVPHELM_STATE"), "PARK"),
        "parked after the all-stop"
    );
}

#[test]
fn behavior_error_halts_the_helm() {
    // A speed behaviour in a course-only domain has a null domain (MOOS `isRunnable`): it
    // reports an error, BHV_ERROR, and the helm halts.
    let bhv =
        "Behavior = BHV_ConstantSpeed\n{\n name = s\n speed = 1\n duration = no-time-limit\n}\n";
    let parsed = mission::bhv::parse_bhv(&SourceMap::from_text("e.bhv", bhv));
    let helm = Helm::from_parsed(
        &[("domain", "course:0:359:360"), ("start_engaged", "true")],
        &globals(),
        &parsed,
    );
    let mut s = Script::new(helm);
    s.step(0.0, 0.0, 0.0, 0.0, &[]);
    let posts = s.step(1.0, 0.0, 0.0, 0.0, &[]);
    assert!(is_str(
        get(&posts, "BHV_ERROR"),
        "s: Null IvPDomain given to Behavior"
    ));
    assert!(is_str(get(&posts, "IVPHELM_ALLSTOP"), "BehaviorError"));
    assert_eq!(
        get(&posts, "DESIRED_HEADING"),
        Some(&Value::Double(0.0)),
        "zeros at once"
    );
    let summary = get(&posts, "IVPHELM_SUMMARY").unwrap().as_str().unwrap();
    assert!(summary.contains("halted=true"), "{summary}");
}

#[test]
fn depth_domain_holds_for_nav_depth() {
    let bhv = "Behavior = BHV_ConstantHeading\n{\n name = h\n heading = 10\n duration = no-time-limit\n}\n";
    let parsed = mission::bhv::parse_bhv(&SourceMap::from_text("d.bhv", bhv));
    let helm = Helm::from_parsed(
        &[
            ("domain", "course:0:359:360"),
            ("domain", "speed:0:4:41:optional"),
            ("domain", "depth:0:100:101:optional"),
            ("start_engaged", "true"),
        ],
        &globals(),
        &parsed,
    );
    let mut s = Script::new(helm);
    s.step(0.0, 0.0, 0.0, 0.0, &[]);
    let posts = s.step(2.0, 0.0, 0.0, 0.0, &[]);
    assert!(
        get(&posts, "IVPHELM_ITER").is_none(),
        "no NAV_DEPTH yet: {posts:?}"
    );
    let posts = s.step(3.0, 0.0, 0.0, 0.0, &[("NAV_DEPTH", "4")]);
    assert_eq!(get(&posts, "DESIRED_HEADING"), Some(&Value::Double(10.0)));
    // Undecided optional variables are posted as 0 (pHelmIvP's getDecision default).
    assert_eq!(get(&posts, "DESIRED_DEPTH"), Some(&Value::Double(0.0)));
}

#[test]
fn waypoint_points_and_currix_updates() {
    let bhv = "\
Behavior = BHV_Waypoint
{
  name    = wpt
  speed   = 2
  points  = 0,100:100,100:100,0
  updates = WPT_UPDATE
  wptflag = HIT = $(X),$(Y) next=$(NX),$(NY)
}
";
    let mut s = Script::new(helm_with(&[("start_engaged", "true")], bhv));
    s.step(0.0, 0.0, 0.0, 0.0, &[]);
    let posts = s.step(1.0, 0.0, 0.0, 0.0, &[]);
    assert_eq!(get(&posts, "DESIRED_HEADING"), Some(&Value::Double(0.0)));
    // Jump to the third point.
    let posts = s.step(2.0, 0.0, 0.0, 0.0, &[("WPT_UPDATE", "currix=2")]);
    assert_eq!(get(&posts, "WPT_INDEX"), Some(&Value::Double(2.0)));
    assert_eq!(get(&posts, "DESIRED_HEADING"), Some(&Value::Double(90.0)));
    // New points; a radial polygon form starts at the vertex nearest the vehicle.
    let posts = s.step(
        3.0,
        0.0,
        0.0,
        0.0,
        &[(
            "WPT_UPDATE",
            "points = radial:: x=0, y=-50, radius=10, pts=4",
        )],
    );
    assert!(
        get(&posts, "IVPHELM_UPDATE_RESULT")
            .unwrap()
            .as_str()
            .unwrap()
            .contains("success")
    );
    let seg = get(&posts, "VIEW_SEGLIST").unwrap().as_str().unwrap();
    assert!(seg.starts_with("pts={"), "{seg}");
    let hdg = get(&posts, "DESIRED_HEADING").unwrap().as_f64().unwrap();
    assert!((90.0..=270.0).contains(&hdg), "heading south-ish: {hdg}");
    // Arriving at the first radial vertex posts the wptflag with the point reached.
    let (nx, ny) = {
        let inner = seg.trim_start_matches("pts={");
        let first = inner.split(':').next().unwrap();
        let (a, b) = first.split_once(',').unwrap();
        (
            a.parse::<f64>().unwrap(),
            b.trim_end_matches('}').parse::<f64>().unwrap(),
        )
    };
    let posts = s.step(4.0, nx, ny + 1.0, 180.0, &[]);
    let hit = get(&posts, "HIT").unwrap().as_str().unwrap();
    let (xy, next) = hit.split_once(" next=").unwrap();
    let (hx, hy) = xy.split_once(',').unwrap();
    assert!(
        (hx.parse::<f64>().unwrap() - nx).abs() < 0.006,
        "{hit} vs {nx},{ny}"
    );
    assert!(
        (hy.parse::<f64>().unwrap() - ny).abs() < 0.006,
        "{hit} vs {nx},{ny}"
    );
    assert_ne!(next, xy, "the next point is the following vertex");
}

#[test]
fn offboard_flags_become_node_messages() {
    let bhv = "\
Behavior = BHV_ConstantHeading
{
  name = h
  heading = 0
  duration = no-time-limit
  runflag = #all LOITER_NOW = true
  runflag = #group+ TEAM = a,b
  runflag = LOCAL = 1 [if] (ARMED = yes)
}
Behavior = BHV_ConstantSpeed
{
  name = s
  speed = 1
  duration = no-time-limit
}
";
    let mut s = Script::new(helm_with(&[("start_engaged", "true")], bhv));
    s.step(0.0, 0.0, 0.0, 0.0, &[("ABE_NAV_GROUP", "red")]);
    let posts = s.step(1.0, 0.0, 0.0, 0.0, &[]);
    let msgs: Vec<&str> = all(&posts, "NODE_MESSAGE_LOCAL")
        .iter()
        .map(|v| v.as_str().unwrap())
        .collect();
    assert_eq!(
        msgs,
        [
            "src_node=abe,dest_node=all,src_app=pHelmIvP,src_bhv=h,var_name=LOITER_NOW,string_val=true",
            "src_node=abe,dest_node=all,dest_group=red,src_app=pHelmIvP,src_bhv=h,var_name=TEAM,string_val=\"a,b\"",
        ]
    );
    assert!(
        get(&posts, "LOITER_NOW").is_none(),
        "#all is off-board only"
    );
    assert!(is_str(get(&posts, "TEAM"), "a,b"), "#group+ is also local");
    assert!(get(&posts, "LOCAL").is_none(), "[if] condition false");
}

#[test]
fn the_helm_can_move_between_threads() {
    fn assert_send<T: Send>(_: &T) {}
    let helm = helm_with(&[], HEADING_BHV);
    assert_send(&helm);
    let h = std::thread::spawn(move || helm.state()).join().unwrap();
    assert_eq!(h, HelmState::Park);
}

#[test]
fn counter_and_position_macros() {
    let bhv = "\
initialize GO = false
Behavior = BHV_ConstantHeading
{
  name = h
  condition = GO = true
  heading = 0
  duration = no-time-limit
  runflag = RUN_NUM = $[CTR]
  runflag = OTHER = $[CTR2]/$[CTR2]
  runflag = WHERE = $[OSX],$(OSY) h=$[OSH] v=$[OSV] $[UNKNOWN]
}
Behavior = BHV_ConstantSpeed
{
  name = s
  speed = 1
  duration = no-time-limit
}
";
    let mut s = Script::new(helm_with(&[("start_engaged", "true")], bhv));
    s.step(0.0, 0.0, 0.0, 0.0, &[]);
    s.step(1.0, 0.0, 0.0, 0.0, &[]);
    let posts = s.step(2.0, 12.3456, -7.5, 370.0, &[("GO", "true")]);
    assert_eq!(get(&posts, "RUN_NUM"), Some(&Value::Double(1.0)));
    assert!(
        is_str(get(&posts, "OTHER"), "1/1"),
        "one increment per expansion"
    );
    assert!(
        is_str(get(&posts, "WHERE"), "12.346,-7.5 h=10 v=1 $[UNKNOWN]"),
        "{:?}",
        get(&posts, "WHERE")
    );
    s.step(3.0, 0.0, 0.0, 0.0, &[("GO", "false")]);
    let posts = s.step(4.0, 0.0, 0.0, 0.0, &[("GO", "true")]);
    assert_eq!(get(&posts, "RUN_NUM"), Some(&Value::Double(2.0)));
}

const NULL_DOMAIN_BHV: &str = "\
Behavior = BHV_ConstantHeading
{
  name      = hdg
  heading   = 45
  duration  = no-time-limit
}
Behavior = BHV_ConstantSpeed
{
  name      = spd
  speed     = 2
  duration  = no-time-limit
}
Behavior = BHV_ConstantDepth
{
  name      = dep
  condition = DIVE = true
  depth     = 10
  duration  = no-time-limit
}
";

fn status_of<'a>(posts: &'a [Posting], name: &str) -> Option<&'a str> {
    all(posts, "BHV_STATUS")
        .into_iter()
        .filter_map(Value::as_str)
        .find(|s| s.starts_with(&format!("name={name},")))
}

#[test]
fn depth_behaviour_in_a_course_speed_helm_has_a_null_domain() {
    let mut s = Script::new(helm_with(&[("start_engaged", "true")], NULL_DOMAIN_BHV));
    assert!(s.helm.config_errors().is_empty());
    s.step(0.0, 0.0, 0.0, 0.0, &[]);
    // Idle by its condition: no error, the others drive.
    let posts = s.step(1.0, 0.0, 0.0, 0.0, &[]);
    assert!(get(&posts, "BHV_ERROR").is_none(), "{posts:?}");
    assert!(is_str(get(&posts, "IVPHELM_ALLSTOP"), "clear"));
    assert_eq!(get(&posts, "DESIRED_HEADING"), Some(&Value::Double(45.0)));
    assert_eq!(get(&posts, "IVPHELM_IPF_CNT"), Some(&Value::Double(2.0)));
    assert_eq!(
        status_of(&posts, "dep"),
        Some("name=dep,pc=DIVE = true,state=idle,updates=n/a")
    );
    // Conditions met: the missing `depth` variable keeps it idle with pc=null-domain, and it
    // posts pHelmIvP's error, which halts the helm.
    let posts = s.step(2.0, 0.0, 0.0, 0.0, &[("DIVE", "true")]);
    assert_eq!(
        status_of(&posts, "dep"),
        Some("name=dep,pc=null-domain,state=idle,updates=n/a")
    );
    assert!(is_str(
        get(&posts, "BHV_ERROR"),
        "dep: Null IvPDomain given to Behavior"
    ));
    assert!(is_str(get(&posts, "IVPHELM_ALLSTOP"), "BehaviorError"));
    assert_eq!(get(&posts, "IVPHELM_IPF_CNT"), Some(&Value::Double(0.0)));
    assert_eq!(get(&posts, "DESIRED_HEADING"), Some(&Value::Double(0.0)));
    // Idle again by its condition: the helm drives again.
    let posts = s.step(3.0, 0.0, 0.0, 0.0, &[("DIVE", "false")]);
    assert!(get(&posts, "BHV_ERROR").is_none(), "{posts:?}");
    assert!(is_str(get(&posts, "IVPHELM_ALLSTOP"), "clear"));
    assert_eq!(get(&posts, "DESIRED_SPEED"), Some(&Value::Double(2.0)));
}

#[test]
fn periodic_surface_without_a_depth_domain_is_a_null_domain_error() {
    // Before: it silently produced nothing and the helm drove on.
    let bhv = "Behavior = BHV_PeriodicSurface\n{\n name = ps\n period = 10\n}\n\
               Behavior = BHV_ConstantSpeed\n{\n name = spd\n speed = 1\n duration = no-time-limit\n}\n";
    let mut s = Script::new(helm_with(&[("start_engaged", "true")], bhv));
    s.step(0.0, 0.0, 0.0, 0.0, &[]);
    let posts = s.step(1.0, 0.0, 0.0, 0.0, &[]);
    assert!(is_str(
        get(&posts, "BHV_ERROR"),
        "ps: Null IvPDomain given to Behavior"
    ));
    assert!(
        status_of(&posts, "ps")
            .unwrap()
            .contains("pc=null-domain,state=idle")
    );
    assert!(is_str(get(&posts, "IVPHELM_ALLSTOP"), "BehaviorError"));
}

#[test]
fn unnamed_behaviours_get_moos_ivp_default_names() {
    let kinds = [
        ("BHV_Waypoint", "bhv_waypoint"),
        ("BHV_Loiter", "bhv_loiter"),
        ("BHV_ConstantSpeed", "bhv_constant_speed"),
        ("BHV_ConstantHeading", "bhv_constantHeading"),
        ("BHV_Timer", "bhv_timer"),
        ("BHV_ConstantDepth", "bhv_constantdepth"),
        ("BHV_MaxDepth", "maxdepth"),
        ("BHV_OpRegion", "bhv_opregion"),
        ("BHV_PeriodicSurface", "periodic_surface"),
        ("BHV_GoToDepth", "bhv_goto_depth"),
        ("BHV_StationKeep", "station_keep"),
    ];
    let mut bhv = String::from("initialize GO = false\n");
    for (kind, _) in kinds {
        bhv.push_str(&format!(
            "Behavior = {kind}\n{{\n  condition = GO = true\n}}\n"
        ));
    }
    let parsed = mission::bhv::parse_bhv(&SourceMap::from_text("n.bhv", &bhv));
    let helm = Helm::from_parsed(
        &[
            ("domain", "course:0:359:360"),
            ("domain", "speed:0:4:41"),
            ("domain", "depth:0:100:101"),
            ("start_engaged", "true"),
        ],
        &globals(),
        &parsed,
    );
    assert!(
        helm.config_errors().is_empty(),
        "{:?}",
        helm.config_errors()
    );
    let expected: Vec<&str> = kinds.iter().map(|k| k.1).collect();
    assert_eq!(helm.behavior_names(), expected);
    // The status line carries the default name.
    let mut s = Script::new(helm);
    s.step(0.0, 0.0, 0.0, 0.0, &[]);
    s.helm.on_mail(&[Mail::new("NAV_DEPTH", 0.0, 1.0)]);
    let posts = s.step(1.0, 0.0, 0.0, 0.0, &[]);
    assert_eq!(
        status_of(&posts, "maxdepth"),
        Some("name=maxdepth,pc=GO = true,state=idle,updates=n/a")
    );
}

const LOITER_MACROS_BHV: &str = "\
initialize DEPLOY = false
Behavior = BHV_Loiter
{
  name      = loiter
  condition = DEPLOY = true
  speed     = 1.5
  polygon   = 0,0 : 0,-40 : 60,-40 : 60,0
  runflag   = LOITER_AT = $[CENTER]
  runxflag  = LOITER_INFO = cx=$[CX],cy=$[CY],rad=$[RAD],pts=$[PTS],cw=$[CWISE]
}
";

#[test]
fn loiter_macros_expand_in_run_and_runx_flags_after_on_run() {
    let mut s = Script::new(helm_with(&[("start_engaged", "true")], LOITER_MACROS_BHV));
    s.step(0.0, 100.0, 100.0, 180.0, &[]);
    let posts = s.step(1.0, 100.0, 100.0, 180.0, &[("DEPLOY", "true")]);
    // Bounding-box centre (30,-20); largest centre-to-vertex distance hypot(30,20) =
    // 36.05551..., printed by MOOS doubleToStringX(v, 3).
    assert_eq!(
        get(&posts, "LOITER_AT").and_then(Value::as_str),
        Some("x=30,y=-20"),
        "{posts:?}"
    );
    let info = get(&posts, "LOITER_INFO").and_then(Value::as_str).unwrap();
    assert!(
        info.starts_with("cx=30,cy=-20,rad=36.056,pts=4,cw="),
        "{info}"
    );
    // runx flags: every running iteration (repeatable); run flags only on entry.
    let posts = s.step(2.0, 100.0, 100.0, 180.0, &[]);
    assert!(get(&posts, "LOITER_INFO").is_some(), "{posts:?}");
    assert!(get(&posts, "LOITER_AT").is_none(), "{posts:?}");
}

#[test]
fn run_flags_see_the_values_on_run_just_set() {
    // The waypoint picks its next point inside on_run; since Feb 2026 pHelmIvP posts run
    // flags after on_run, so $[NX]/$[NY] name the first point already on entry.
    let bhv = "\
initialize DEPLOY = false
Behavior = BHV_Waypoint
{
  name      = wpt
  condition = DEPLOY = true
  speed     = 2
  points    = 60,-40 : 60,-160
  runflag   = FIRST_WPT = $[NX],$[NY]
}
";
    let mut s = Script::new(helm_with(&[("start_engaged", "true")], bhv));
    s.step(0.0, 0.0, 0.0, 0.0, &[]);
    let posts = s.step(1.0, 0.0, 0.0, 0.0, &[("DEPLOY", "true")]);
    assert_eq!(
        get(&posts, "FIRST_WPT").and_then(Value::as_str),
        Some("60,-40"),
        "{posts:?}"
    );
}

#[test]
fn waypoint_macros_expand_as_the_cpp() {
    let bhv = "\
initialize DEPLOY = false
Behavior = BHV_Waypoint
{
  name      = wpt
  condition = DEPLOY = true
  speed     = 2.125
  repeat    = 1
  points    = 60,-40 : 60,-160
  runflag   = M = pts:$[POINTS]|spd:$[SPEED]|alt:$[USE_SPEED_ALT]|ipf:$[IPF_TYPE]|ord:$[ORDER]|cyc:$[CYC_DIST_TOGO]|all:$[ALL_DIST_TOGO]|nx:$[NX]
}
";
    let mut s = Script::new(helm_with(&[("start_engaged", "true")], bhv));
    s.step(0.0, 0.0, 0.0, 0.0, &[]);
    let posts = s.step(1.0, 0.0, 0.0, 0.0, &[("DEPLOY", "true")]);
    // To the end of the cycle: hypot(60, 40) + 120 = 192.111; plus one more cycle of the
    // 120 m leg and the 120 m gap back: 432.111 (doubleToStringX(v, 3)).
    assert_eq!(
        get(&posts, "M").and_then(Value::as_str),
        Some(
            "pts:pts={60,-40:60,-160}|spd:2.125|alt:0|ipf:zaic|ord:normal|cyc:192.111|all:432.111|nx:60"
        ),
        "{posts:?}"
    );
}

#[test]
fn us_from_the_bhv_file_is_replaced_by_the_community_but_an_update_renames() {
    // The C++ helm sets `us` to its community for every behaviour once loaded; a later
    // update sets the behaviour's own name for $[OWNSHIP] (and node messages).
    let bhv = "\
Behavior = BHV_ConstantSpeed
{
  name       = cs
  speed      = 1
  us         = bob
  condition  = GO = true
  duration   = no-time-limit
  updates    = CS_UPDATE
  runflag    = WHO = $[OWNSHIP]
}
";
    let helm = helm_with(&[("start_engaged", "true")], bhv);
    assert_eq!(helm.config_errors(), &[]);
    let mut s = Script::new(helm);
    s.step(0.0, 0.0, 0.0, 0.0, &[]);
    let posts = s.step(1.0, 0.0, 0.0, 0.0, &[("GO", "true")]);
    assert!(is_str(get(&posts, "WHO"), "abe"), "{posts:?}");
    s.step(
        2.0,
        0.0,
        0.0,
        0.0,
        &[("GO", "false"), ("CS_UPDATE", "us=carol")],
    );
    let posts = s.step(3.0, 0.0, 0.0, 0.0, &[("GO", "true")]);
    assert!(is_str(get(&posts, "WHO"), "carol"), "{posts:?}");
}

#[test]
fn bhv_settings_once_after_configuration_twice_after_each_update_and_on_each_start() {
    // MOOS: onSetParamComplete posts postConfigStatus at configuration; after an update
    // checkUpdates posts it and onSetParamComplete again; Loiter and StationKeep also post
    // it on each idle-to-running transition.
    let bhv = "\
Behavior = BHV_Loiter
{
  name      = lt
  speed     = 1
  condition = GO = true
  duration  = no-time-limit
  updates   = LT_UPDATE
  polygon   = format=radial, x=0, y=0, radius=20, pts=4
}
";
    let mut s = Script::new(helm_with(&[("start_engaged", "true")], bhv));
    let count = |p: &[Posting]| all(p, "BHV_SETTINGS").len();
    let first = s.step(0.0, 0.0, 0.0, 0.0, &[]);
    let second = s.step(1.0, 0.0, 0.0, 0.0, &[]);
    assert_eq!(
        count(&first) + count(&second),
        1,
        "once after configuration"
    );
    let upd = s.step(2.0, 0.0, 0.0, 0.0, &[("LT_UPDATE", "speed=1.5")]);
    let settings = all(&upd, "BHV_SETTINGS");
    assert_eq!(settings.len(), 2, "{upd:?}");
    assert!(
        settings[1]
            .as_str()
            .unwrap()
            .contains(",desired_speed=1.5,")
    );
    let run = s.step(3.0, 0.0, 0.0, 0.0, &[("GO", "true")]);
    assert_eq!(count(&run), 1, "on the start of running");
}

#[test]
fn hold_on_apps_holds_the_configuration_postings_until_db_clients_names_them() {
    // pHelmIvP posts its behaviours' start messages (made at configuration) only once every
    // hold_on_apps app is in DB_CLIENTS; the helm decides meanwhile.
    let bhv = "\
Behavior = BHV_Loiter
{
  name      = lt
  speed     = 1
  duration  = no-time-limit
  polygon   = format=radial, x=0, y=0, radius=20, pts=4
}
";
    let helm = helm_with(
        &[
            ("start_engaged", "true"),
            ("hold_on_apps", "pContactMgrV20, uFldNodeComms"),
        ],
        bhv,
    );
    assert!(helm.holding());
    let mut s = Script::new(helm);
    let count = |p: &[Posting]| all(p, "BHV_SETTINGS").len();
    let mut seen = count(&s.step(0.0, 0.0, 0.0, 0.0, &[]));
    let p = s.step(
        1.0,
        0.0,
        0.0,
        0.0,
        &[("DB_CLIENTS", "pHelmIvP,pContactMgrV20,")],
    );
    seen += count(&p);
    assert_eq!(seen, 0, "held: one app still missing");
    assert!(
        get(&p, "DESIRED_SPEED").is_some(),
        "the helm decides meanwhile"
    );
    let p = s.step(
        2.0,
        0.0,
        0.0,
        0.0,
        &[("DB_CLIENTS", "uFldNodeComms,pHelmIvP,pContactMgrV20,")],
    );
    assert_eq!(count(&p), 1, "released once all are seen");
    assert!(!s.helm.holding());
}
