//! Contact encounters in lockstep (issue #18, points 3 and 4): one simulated vehicle, a
//! contact whose NODE_REPORTs come from a generated uTimerScript (heading straight at it),
//! pBasicContactMgr alerting the helm, and the helm spawning BHV_AvoidCollision for the
//! contact. With the behaviour the closest approach stays above `min_util_cpa_dist`; without
//! it the same encounter is a collision.

mod common;

use std::path::{Path, PathBuf};

use common::*;

/// The contact's start (north of the vehicle), heading (south) and speed.
const CN_Y0: f64 = 240.0;
const CN_SPD: f64 = 2.0;
/// The behaviour's minimum CPA distance.
const MIN_UTIL_CPA: f64 = 10.0;

fn mission_text(contact_script: &str, cm_extra: &str) -> String {
    format!(
        r#"ServerHost   = localhost
ServerPort   = 9000
Community    = abe
MOOSTimeWarp = 1
LatOrigin  = 43.825300
LongOrigin = -70.330400

ProcessConfig = ANTLER
{{
  MSBetweenLaunches = 200
  Run = MOOSDB           @ NewConsole = false
  Run = pLogger          @ NewConsole = false
  Run = uSimMarineV22    @ NewConsole = false
  Run = pMarinePIDV22    @ NewConsole = false
  Run = pHelmIvP         @ NewConsole = false
  Run = pNodeReporter    @ NewConsole = false
  Run = pBasicContactMgr @ NewConsole = false
  Run = uTimerScript     @ NewConsole = false
}}

ProcessConfig = pLogger
{{
  AppTick   = 4
  CommsTick = 4
  File          = ENCOUNTER
  PATH          = ./logs/
  LogAuxSrc     = true
  WildCardLogging     = true
  WildCardOmitPattern = *_STATUS
}}

ProcessConfig = uSimMarineV22
{{
  AppTick   = 4
  CommsTick = 4
  start_pos     = x=0, y=0, heading=0, speed=0
  prefix        = NAV
  turn_rate     = 70
  thrust_map    = 0:0, 20:1, 40:2, 60:3, 80:4, 100:5
}}

ProcessConfig = pHelmIvP
{{
  AppTick   = 4
  CommsTick = 4
  behaviors = encounter.bhv
  domain    = course:0:359:360
  domain    = speed:0:4:41
}}

ProcessConfig = pMarinePIDV22
{{
  AppTick   = 10
  CommsTick = 10
  depth_control = false
  yaw_pid_kp             = 0.9
  yaw_pid_kd             = 0.3
  yaw_pid_ki             = 0.3
  yaw_pid_integral_limit = 0.07
  speed_pid_kp             = 1.0
  speed_pid_kd             = 0.0
  speed_pid_ki             = 0.0
  speed_pid_integral_limit = 0.07
  maxrudder = 100
  maxthrust = 100
  speed_factor = 20
}}

ProcessConfig = pNodeReporter
{{
  AppTick   = 2
  CommsTick = 2
  platform_type   = kayak
}}

ProcessConfig = pBasicContactMgr
{{
  AppTick   = 2
  CommsTick = 2
  alert_verbose = true
  decay = 30,60
{cm_extra}}}

ProcessConfig = uTimerScript
{{
  AppTick   = 4
  CommsTick = 4
{contact_script}}}
"#
    )
}

fn bhv_text(avoid: bool) -> String {
    let mut s = String::from(
        "initialize DEPLOY  = false
initialize MISSION = pending

set MODE = ACTIVE {
  DEPLOY = true
} INACTIVE

Behavior = BHV_Waypoint
{
  name      = transit
  pwt       = 100
  condition = MODE == ACTIVE
  endflag   = MISSION = complete
  speed          = 2
  capture_radius = 5
  points         = 0,300
}
",
    );
    if avoid {
        s.push_str(&format!(
            "
Behavior = BHV_AvoidCollision
{{
  name       = avd_
  pwt        = 300
  condition  = MODE == ACTIVE
  updates    = CONTACT_INFO
  endflag    = CONTACT_RESOLVED = $[CONTACT]
  templating = spawn

             contact = to-be-set
    on_no_contact_ok = true
         extrapolate = true
               decay = 30,60
      pwt_outer_dist = 100
      pwt_inner_dist = 40
      completed_dist = 150
   min_util_cpa_dist = {MIN_UTIL_CPA}
   max_util_cpa_dist = 30
           pwt_grade = linear
}}
"
        ));
    }
    s
}

/// `(x, y)` moved `d` metres along compass heading `h`.
fn project(x: f64, y: f64, h: f64, d: f64) -> (f64, f64) {
    let r = h.to_radians();
    (x + r.sin() * d, y + r.cos() * d)
}

/// One NODE_REPORT a second for `secs` s: the contact from `(x0, y0)` heading `hdg` at
/// `spd`.
fn contact_script(x0: f64, y0: f64, hdg: f64, spd: f64, secs: u32) -> String {
    let mut s = String::new();
    for k in 0..secs {
        let (x, y) = project(x0, y0, hdg, spd * f64::from(k));
        let (x, y) = ((x * 100.0).round() / 100.0, (y * 100.0).round() / 100.0);
        s.push_str(&format!(
            "  event = var=NODE_REPORT, val=\"NAME=bob,TYPE=kayak,X={x},Y={y},SPD={spd},HDG={hdg},DEP=0,TIME=$(UTCTIME)\", time={k}\n"
        ));
    }
    s
}

fn write_files(dir: &Path, bhv: &str, moos: &str) -> PathBuf {
    std::fs::create_dir_all(dir).unwrap();
    std::fs::write(dir.join("encounter.bhv"), bhv).unwrap();
    let m = dir.join("encounter.moos");
    std::fs::write(&m, moos).unwrap();
    m
}

fn write_mission(dir: &Path, avoid: bool) -> PathBuf {
    let script = contact_script(0.0, CN_Y0, 180.0, CN_SPD, 150);
    write_files(dir, &bhv_text(avoid), &mission_text(&script, ""))
}

/// The log time of the contact's first report.
fn first_report(log: &alog::Alog) -> f64 {
    log.entries
        .iter()
        .find(|e| e.var == "NODE_REPORT")
        .map(|e| e.time)
        .expect("the contact's reports are logged")
}

/// The closest approach over the run: the vehicle's track against the contact's reported
/// straight line (its first report's log time is its time 0).
fn closest_approach(log: &alog::Alog) -> (f64, f64) {
    let t0 = first_report(log);
    track(log)
        .iter()
        .filter(|(t, _, _)| *t >= t0 && *t <= t0 + 149.0)
        .map(|&(t, x, y)| {
            let cy = CN_Y0 - CN_SPD * (t - t0);
            ((x * x + (y - cy) * (y - cy)).sqrt(), t)
        })
        .fold((f64::INFINITY, 0.0), |a, b| if b.0 < a.0 { b } else { a })
}

fn run(name: &str, avoid: bool) -> alog::Alog {
    let dir = fresh_dir(&format!("{name}-mission"));
    let mission = write_mission(&dir, avoid);
    let (bytes, _) = run_lockstep(
        name,
        &mission,
        &[],
        deploy_until("MISSION = complete", 400.0),
    );
    parse(&bytes)
}

#[test]
fn avoid_collision_keeps_the_closest_approach_above_its_minimum() {
    let log = run("contacts-avoid", true);
    let (cpa, at) = closest_approach(&log);
    eprintln!("with BHV_AvoidCollision: closest approach {cpa:.2} m at t={at:.1}");
    assert!(
        cpa > MIN_UTIL_CPA,
        "closest approach {cpa:.2} m at t={at:.1} is within min_util_cpa_dist"
    );
    // The contact manager alerted the helm, which spawned a behaviour for the contact.
    let has = |var: &str, needle: &str| {
        log.entries
            .iter()
            .any(|e| e.var == var && e.value.as_str().is_some_and(|s| s.contains(needle)))
    };
    assert!(has(
        "BCM_ALERT_REQUEST",
        "id=avd_, on_flag=CONTACT_INFO=name=$[VNAME] # contact=$[VNAME]"
    ));
    assert!(has("CONTACT_INFO", "name=bob # contact=bob"));
    assert!(has(
        "IVPHELM_LIFE_EVENT",
        "bname=avd_bob, btype=BHV_AvoidCollision, event=spawn"
    ));
    assert!(has("CONTACTS_ALERTED", "(bob,avd_)"));
    assert!(has("IVPHELM_CONTACT_SUMMARY", "bob"));
    assert!(has("BHV_IPF", "avd_bob"));
    // Once past, the behaviour completes and resolves the alert.
    assert!(has("CONTACT_RESOLVED", "bob"));
}

#[test]
fn without_avoid_collision_the_same_encounter_collides() {
    let log = run("contacts-none", false);
    let (cpa, at) = closest_approach(&log);
    eprintln!("without: closest approach {cpa:.2} m at t={at:.1}");
    assert!(
        cpa < 3.0,
        "without the behaviour the vehicles should meet, closest {cpa:.2} m at t={at:.1}"
    );
}

/// A behaviour file with one spawning contact-behaviour template and nothing else, the run
/// ending when the timer script posts `MISSION = complete`.
fn template_bhv(body: &str) -> String {
    format!(
        "initialize DEPLOY  = false
initialize MISSION = pending

set MODE = ACTIVE {{
  DEPLOY = true
}} INACTIVE

{body}"
    )
}

/// `(time, range)` from the vehicle's track to the contact's reported straight line.
fn ranges(log: &alog::Alog, x0: f64, y0: f64, hdg: f64, spd: f64) -> Vec<(f64, f64)> {
    let t0 = first_report(log);
    track(log)
        .iter()
        .filter(|(t, _, _)| *t >= t0)
        .map(|&(t, x, y)| {
            let (px, py) = project(x0, y0, hdg, spd * (t - t0));
            (t, (x - px).hypot(y - py))
        })
        .collect()
}

/// One spawning contact-behaviour template of type `kind` named `prefix`, with `own` (its
/// own parameters, one a line) after the spawning lines every template here shares.
fn template(kind: &str, prefix: &str, own: &str) -> String {
    format!(
        "Behavior = {kind}
{{
  name       = {prefix}
  pwt        = 100
  condition  = MODE == ACTIVE
  updates    = CONTACT_INFO
  templating = spawn
  contact    = to-be-set
{own}}}
"
    )
}

/// A contact reporting once a second along a straight line: from `from` (x, y), heading
/// `hdg` at `spd`, for `secs` s; the timer script ends the mission at `end` s.
#[derive(Clone, Copy)]
struct Crossing {
    from: (f64, f64),
    hdg: f64,
    spd: f64,
    secs: u32,
    end: u32,
}

impl Crossing {
    /// The contact from `from`, heading `hdg` at `spd`, reporting for `secs` s, the mission
    /// ending at `end` s.
    fn new(from: (f64, f64), hdg: f64, spd: f64, secs: u32, end: u32) -> Crossing {
        Crossing {
            from,
            hdg,
            spd,
            secs,
            end,
        }
    }

    /// `(time, range)` from the vehicle's track to this contact.
    fn ranges(&self, log: &alog::Alog) -> Vec<(f64, f64)> {
        ranges(log, self.from.0, self.from.1, self.hdg, self.spd)
    }
}

/// pBasicContactMgr's extra line: an alert `id` posting `CONTACT_INFO` for a contact within 100 m.
fn alert(id: &str) -> String {
    format!(
        "  alert = id={id}, var=CONTACT_INFO, val=\"name=$[VNAME] # contact=$[VNAME]\", alert_range=100\n"
    )
}

/// Runs `name` in lockstep: the vehicle with the one template `bhv` against the contact `c`,
/// the contact manager's block with `cm_extra`, until the mission completes (or 110 s after
/// it should have).
fn run_template(name: &str, bhv: &str, c: &Crossing, cm_extra: &str) -> alog::Alog {
    let script = contact_script(c.from.0, c.from.1, c.hdg, c.spd, c.secs)
        + &format!("  event = var=MISSION, val=complete, time={}\n", c.end);
    let dir = fresh_dir(&format!("{name}-mission"));
    let mission = write_files(&dir, &template_bhv(bhv), &mission_text(&script, cm_extra));
    let (bytes, _) = run_lockstep(
        name,
        &mission,
        &[],
        deploy_until("MISSION = complete", f64::from(c.end) + 110.0),
    );
    parse(&bytes)
}

#[test]
fn cut_range_closes_on_a_crossing_contact() {
    let own = "  pwt_outer_dist = 200
  pwt_inner_dist = 0
    giveup_range = 500
      pursueflag = PURSUING = $[CONTACT]
";
    let c = Crossing::new((0.0, 100.0), 90.0, 1.0, 100, 90);
    let log = run_template(
        "contacts-cut",
        &template("BHV_CutRange", "cut_", own),
        &c,
        "",
    );
    let r = c.ranges(&log);
    let first = r.first().unwrap().1;
    let closest = r.iter().map(|x| x.1).fold(f64::INFINITY, f64::min);
    eprintln!("BHV_CutRange: range {first:.1} m at the first report, closest {closest:.2} m");
    assert!(first > 95.0, "{first}");
    assert!(
        closest < 10.0,
        "never closed on the contact: closest {closest:.2} m"
    );
    assert!(
        log.entries
            .iter()
            .any(|e| e.var == "PURSUING" && e.value.as_str() == Some("bob"))
    );
}

#[test]
fn shadow_takes_the_contact_s_heading_and_speed() {
    let c = Crossing::new((20.0, 20.0), 90.0, 1.5, 100, 90);
    let log = run_template(
        "contacts-shadow",
        &template("BHV_Shadow", "shd_", ""),
        &c,
        &alert("shd"),
    );
    let last = |var: &str| -> Vec<f64> {
        log.entries
            .iter()
            .filter(|e| e.var == var && e.time > 60.0)
            .filter_map(|e| e.value.as_f64())
            .collect()
    };
    let (hdgs, spds) = (last("NAV_HEADING"), last("NAV_SPEED"));
    assert!(!hdgs.is_empty() && !spds.is_empty());
    let mean = |v: &[f64]| v.iter().sum::<f64>() / v.len() as f64;
    eprintln!(
        "BHV_Shadow: heading {:.1}, speed {:.2} after 60 s",
        mean(&hdgs),
        mean(&spds)
    );
    assert!(hdgs.iter().all(|h| (h - 90.0).abs() < 5.0), "{hdgs:?}");
    assert!(spds.iter().all(|v| (v - 1.5).abs() < 0.2), "{spds:?}");
}

#[test]
fn trail_keeps_station_behind_the_contact() {
    let own = "  no_alert_request = false
    pwt_outer_dist = 300
       trail_range = 30
       trail_angle = 180
";
    let c = Crossing::new((0.0, 60.0), 90.0, 1.5, 150, 140);
    let log = run_template(
        "contacts-trail",
        &template("BHV_Trail", "trl_", own),
        &c,
        "",
    );
    // The trail point: 30 m behind the contact (west of it).
    let behind = Crossing {
        from: (-30.0, 60.0),
        ..c
    };
    let r = behind.ranges(&log);
    let late: Vec<f64> = r.iter().filter(|(t, _)| *t > 100.0).map(|x| x.1).collect();
    assert!(!late.is_empty());
    let worst = late.iter().cloned().fold(0.0, f64::max);
    eprintln!(
        "BHV_Trail: {:.1} m from the trail point at the first report, at most {worst:.2} m after 100 s",
        r[0].1
    );
    assert!(
        worst < 10.0,
        "not trailing: {worst:.2} m from the trail point"
    );
}

#[test]
fn convoy_follows_the_contact_along_its_track() {
    // Straight ahead of the vehicle, heading away from it.
    let c = Crossing::new((0.0, 40.0), 0.0, 1.2, 200, 190);
    let log = run_template(
        "contacts-convoy",
        &template("BHV_Convoy", "cnv_", ""),
        &c,
        &alert("cnv"),
    );
    let r = c.ranges(&log);
    let tr = track(&log);
    let late: Vec<(f64, f64, f64)> = tr.iter().filter(|(t, ..)| *t > 120.0).cloned().collect();
    assert!(!late.is_empty());
    let off_track = late.iter().map(|(_, x, _)| x.abs()).fold(0.0, f64::max);
    let late_r: Vec<f64> = r.iter().filter(|(t, _)| *t > 120.0).map(|x| x.1).collect();
    let (lo, hi) = late_r
        .iter()
        .fold((f64::INFINITY, 0.0f64), |(a, b), &x| (a.min(x), b.max(x)));
    eprintln!(
        "BHV_Convoy: after 120 s at most {off_track:.2} m off the contact's track, {lo:.1}..{hi:.1} m behind it"
    );
    assert!(off_track < 5.0, "{off_track}");
    assert!(lo > 10.0 && hi < 80.0, "{lo}..{hi}");
}
