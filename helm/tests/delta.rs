//! The s4_delta mission end to end (the real delta.bhv and delta.moos: hierarchical modes, max
//! depth, loiter with periodic surfacing, survey, return) with a kinematic stand-in vehicle
//! that also moves in depth; and the operating-region guard stopping the vehicle.

mod common;

use behaviors::Info as _;
use common::{all, get, is_str};
use helm::config::Globals;
use helm::{Helm, HelmState, Mail, Posting, Value};
use mission::source::SourceMap;
use test_support::mission_text;

// ---------------------------------------------------------------------------------------------
// A vehicle that also dives.

/// A point-mass vehicle like the one in `common`, plus depth: it changes depth toward the
/// desired depth at a rate proportional to its speed (uSimMarine's `max_depth_rate` 5 m/s at
/// `max_depth_rate_speed` 2 m/s in delta.moos) and floats up at `buoyancy_rate` 0.025 m/s.
#[derive(Debug, Clone)]
struct Sub {
    x: f64,
    y: f64,
    heading: f64,
    speed: f64,
    depth: f64,
}

impl Sub {
    const TURN_RATE: f64 = 40.0;
    const ACCEL: f64 = 0.5;
    const MAX_DEPTH_RATE: f64 = 5.0;
    const MAX_DEPTH_RATE_SPEED: f64 = 2.0;
    const BUOYANCY_RATE: f64 = 0.025;

    fn new(x: f64, y: f64, heading: f64) -> Self {
        Sub {
            x,
            y,
            heading,
            speed: 0.0,
            depth: 0.0,
        }
    }

    fn step(&mut self, dt: f64, des_heading: f64, des_speed: f64, des_depth: f64) {
        let err = (des_heading - self.heading + 540.0).rem_euclid(360.0) - 180.0;
        let max = Self::TURN_RATE * dt;
        self.heading = (self.heading + err.clamp(-max, max)).rem_euclid(360.0);
        self.speed += (des_speed - self.speed).clamp(-Self::ACCEL * dt, Self::ACCEL * dt);
        let r = self.heading.to_radians();
        self.x += r.sin() * self.speed * dt;
        self.y += r.cos() * self.speed * dt;
        let rate = Self::MAX_DEPTH_RATE * (self.speed / Self::MAX_DEPTH_RATE_SPEED).min(1.0);
        self.depth += (des_depth - self.depth).clamp(-rate * dt, rate * dt);
        self.depth = (self.depth - Self::BUOYANCY_RATE * dt).max(0.0);
    }

    fn nav_mail(&self, t: f64) -> Vec<Mail> {
        vec![
            Mail::new("NAV_X", self.x, t).from("uSimMarine"),
            Mail::new("NAV_Y", self.y, t).from("uSimMarine"),
            Mail::new("NAV_HEADING", self.heading, t).from("uSimMarine"),
            Mail::new("NAV_SPEED", self.speed, t).from("uSimMarine"),
            Mail::new("NAV_DEPTH", self.depth, t).from("uSimMarine"),
        ]
    }
}

/// Lockstep loop as in `common::Rig`, with depth, and the delta mission's uTimerScript: once
/// `TIME_AT_SURFACE > 3` it posts `GPS_UPDATE_RECEIVED = RCVD_<n>` 0.75 s later (its event
/// time is 0.5..1.0 s), once per surfacing.
struct DeltaRig {
    helm: Helm,
    sub: Sub,
    t: f64,
    dt: f64,
    des: (f64, f64, f64),
    subs: Vec<String>,
    feedback: Vec<Mail>,
    log: Vec<(f64, Posting)>,
    gps_due: Option<f64>,
    gps_count: u32,
    armed: bool,
    max_depth_seen: f64,
}

impl DeltaRig {
    fn new(helm: Helm, sub: Sub) -> Self {
        let subs = helm.subscriptions().to_vec();
        DeltaRig {
            helm,
            sub,
            t: 0.0,
            dt: 0.25,
            des: (0.0, 0.0, 0.0),
            subs,
            feedback: Vec::new(),
            log: Vec::new(),
            gps_due: None,
            gps_count: 0,
            armed: true,
            max_depth_seen: 0.0,
        }
    }

    fn step(&mut self, extra: &[Mail]) -> Vec<Posting> {
        self.sub.step(self.dt, self.des.0, self.des.1, self.des.2);
        self.max_depth_seen = self.max_depth_seen.max(self.sub.depth);
        self.t += self.dt;
        let t = self.t;
        let mut mail = std::mem::take(&mut self.feedback);
        mail.extend(self.sub.nav_mail(t));
        mail.extend_from_slice(extra);
        if self.gps_due.is_some_and(|due| t >= due) {
            self.gps_due = None;
            self.gps_count += 1;
            let v = format!("RCVD_{}", self.gps_count);
            mail.push(Mail::new("GPS_UPDATE_RECEIVED", v.as_str(), t).from("uTimerScript"));
        }
        self.helm.on_mail(&mail);
        let posts = self.helm.iterate(t).to_vec();
        for p in &posts {
            match (&*p.key, &p.value) {
                ("DESIRED_HEADING", Value::Double(v)) => self.des.0 = *v,
                ("DESIRED_SPEED", Value::Double(v)) => self.des.1 = *v,
                ("DESIRED_DEPTH", Value::Double(v)) => self.des.2 = *v,
                ("TIME_AT_SURFACE", Value::Double(v)) => {
                    if *v > 3.0 && self.armed {
                        self.armed = false;
                        self.gps_due = Some(t + 0.75);
                    } else if *v == 0.0 {
                        self.armed = true;
                    }
                }
                _ => {}
            }
            if self.subs.iter().any(|s| *s == *p.key) {
                let mut m = Mail::new(&p.key, p.value.clone(), t).from("pHelmIvP");
                m.source_aux = p.aux.clone();
                self.feedback.push(m);
            }
            self.log.push((t, p.clone()));
        }
        posts
    }

    fn run_until(
        &mut self,
        max_secs: f64,
        what: &str,
        pred: impl Fn(&Self, &[Posting]) -> bool,
    ) -> Vec<Posting> {
        let end = self.t + max_secs;
        while self.t < end {
            let posts = self.step(&[]);
            if pred(self, &posts) {
                return posts;
            }
        }
        panic!(
            "{what}: not seen within {max_secs} s (t = {}, vehicle at {:.1},{:.1} depth {:.1})",
            self.t, self.sub.x, self.sub.y, self.sub.depth
        );
    }

    /// The values posted to `var` since time `since`, with their times.
    fn history(&self, var: &str, since: f64) -> Vec<(f64, Value)> {
        self.log
            .iter()
            .filter(|(t, p)| *t >= since && p.key == var)
            .map(|(t, p)| (*t, p.value.clone()))
            .collect()
    }
}

fn posted_str(posts: &[Posting], var: &str, val: &str) -> bool {
    posts
        .iter()
        .any(|p| p.key == var && p.value.as_str() == Some(val))
}

fn delta_helm() -> Helm {
    let moos = mission::moos::parse_moos(&SourceMap::from_text(
        "delta.moos",
        &mission_text("s4_delta/delta.moos"),
    ));
    assert!(!moos.has_errors(), "delta.moos: {:?}", moos.diagnostics);
    let bhv = mission::bhv::parse_bhv(&SourceMap::from_text(
        "delta.bhv",
        &mission_text("s4_delta/delta.bhv"),
    ));
    let helm = Helm::from_mission(&moos.value, &bhv);
    assert!(
        helm.config_errors().is_empty(),
        "{:?}",
        helm.config_errors()
    );
    helm
}

#[test]
fn delta_mission_dives_surfaces_periodically_surveys_and_returns() {
    let helm = delta_helm();
    // uSimMarine in delta.moos: start at 0,0 heading 180, at the surface.
    let mut rig = DeltaRig::new(helm, Sub::new(0.0, 0.0, 180.0));
    let posts = rig.step(&[]);
    assert!(is_str(
        get(&posts, "IVPHELM_DOMAIN"),
        "depth,0,199,200:speed,0,4,41:course,0,359,360"
    ));
    assert!(is_str(get(&posts, "PSURFACE"), "true"));
    for _ in 0..8 {
        rig.step(&[]);
    }

    // --- Deploy: ACTIVE:LOITERING. Max depth 7 m (pwt 200) beats the 50 m constant depth.
    let t = rig.t;
    let mut posts = rig.step(&[
        Mail::new("MOOS_MANUAL_OVERRIDE", "false", t).from("uPokeDB"),
        Mail::new("DEPLOY", "true", t).from("uPokeDB"),
    ]);
    posts.extend(rig.step(&[]));
    assert!(is_str(get(&posts, "MODE"), "ACTIVE:LOITERING"), "{posts:?}");
    assert!(is_str(get(&posts, "IVPHELM_ALLSTOP"), "clear"), "{posts:?}");
    assert_eq!(rig.helm.info().text("MODE"), Some("ACTIVE:LOITERING"));
    assert_eq!(rig.des.2, 7.0, "desired depth");
    assert_eq!(rig.des.1, 1.3, "loiter speed");
    let deployed = rig.t;

    // --- It dives to the max depth, never past it by more than the 1 m tolerance.
    rig.run_until(60.0, "at 7 m", |r, _| (r.sub.depth - 7.0).abs() < 0.2);
    assert!(rig.t - deployed < 30.0);

    // --- Periodic surfacing (period 120 s from deploy): ascend at 1 m/s, wait at the
    // surface at speed 0 until the GPS fix, then dive again. Twice.
    for cycle in 0..2 {
        let start = rig.t;
        let posts = rig.run_until(200.0, "PERIODIC_ASCEND=true", |_, p| {
            posted_str(p, "PERIODIC_ASCEND", "true")
        });
        let ascend_t = rig.t;
        assert!(
            rig.sub.depth > 6.0,
            "cycle {cycle}: ascent starts submerged, at {:.1} m",
            rig.sub.depth
        );
        assert_eq!(get(&posts, "DESIRED_DEPTH"), Some(&Value::Double(0.0)));
        assert_eq!(get(&posts, "DESIRED_SPEED"), Some(&Value::Double(1.0)));
        if cycle == 0 {
            let period = ascend_t - deployed;
            assert!(
                (119.0..=122.0).contains(&period),
                "first ascent after {period} s"
            );
        }
        let posts = rig.run_until(30.0, "PERIODIC_ASCEND=false", |_, p| {
            posted_str(p, "PERIODIC_ASCEND", "false")
        });
        assert!(
            rig.sub.depth <= 0.5,
            "at the surface: {:.2} m",
            rig.sub.depth
        );
        assert_eq!(get(&posts, "DESIRED_SPEED"), Some(&Value::Double(0.0)));
        assert_eq!(get(&posts, "DESIRED_DEPTH"), Some(&Value::Double(0.0)));
        // Waits at the surface, stopped, until the fix arrives.
        let fixes = rig.gps_count;
        rig.run_until(15.0, "GPS fix", |r, _| r.gps_count > fixes);
        let at_surface: Vec<f64> = rig
            .history("DESIRED_SPEED", ascend_t)
            .into_iter()
            .skip_while(|(_, v)| *v != Value::Double(0.0))
            .take_while(|(t, _)| *t < rig.t)
            .map(|(_, v)| v.as_f64().unwrap())
            .collect();
        assert!(at_surface.len() > 10 && at_surface.iter().all(|s| *s == 0.0));
        assert!(
            rig.history("TIME_AT_SURFACE", ascend_t)
                .iter()
                .any(|(_, v)| v.as_f64().unwrap() > 3.0)
        );
        // The fix ends the surfacing: back to the loiter speed and down to 7 m.
        let posts = rig.step(&[]);
        assert!(get(&posts, "PERIODIC_ASCEND").is_none());
        rig.run_until(30.0, "diving again", |r, _| r.sub.depth > 6.5);
        assert_eq!(rig.des.1, 1.3, "loiter speed again");
        assert_eq!(rig.des.2, 7.0);
        assert!(rig.t > start);
    }
    // The loiter was circling the radial polygon around (20,-80), radius 20.
    assert!(
        (rig.sub.x - 20.0).hypot(rig.sub.y + 80.0) < 35.0,
        "loitering near its polygon: {:.1},{:.1}",
        rig.sub.x,
        rig.sub.y
    );
    let loiter_vertices: Vec<f64> = rig
        .history("LOITER_INDEX", deployed)
        .iter()
        .map(|(_, v)| v.as_f64().unwrap())
        .collect();
    assert!(
        loiter_vertices.len() >= 4,
        "went round several loiter vertices: {loiter_vertices:?}"
    );

    // --- Survey: ACTIVE:SURVEYING, no periodic surfacing, still at 7 m, 2 m/s.
    let t = rig.t;
    let survey_t = t;
    rig.step(&[Mail::new("SURVEY", "true", t).from("pMarineViewer")]);
    let posts = rig.step(&[]);
    assert_eq!(rig.helm.info().text("MODE"), Some("ACTIVE:SURVEYING"));
    let survey_start = rig.t;
    assert!(
        is_str(get(&posts, "IVPHELM_ALLSTOP"), "clear") || get(&posts, "IVPHELM_ALLSTOP").is_none()
    );
    rig.run_until(60.0, "survey speed", |r, _| r.des.1 == 2.0);
    assert_eq!(rig.des.2, 7.0);
    // It reaches the bowtie around (80,-80) and goes through its points.
    rig.run_until(200.0, "at the bowtie", |r, _| {
        (r.sub.x - 80.0).hypot(r.sub.y + 80.0) < 30.0
    });
    rig.run_until(300.0, "survey index 3", |r, _| {
        r.history("WPT_INDEX", survey_start)
            .iter()
            .any(|(_, v)| v.as_f64() == Some(3.0))
    });
    let indices: Vec<f64> = rig
        .history("WPT_INDEX", survey_t)
        .iter()
        .map(|(_, v)| v.as_f64().unwrap())
        .collect();
    assert_eq!(indices, [0.0, 1.0, 2.0, 3.0], "bowtie points in order");
    assert!(
        rig.history("PERIODIC_ASCEND", survey_start).is_empty(),
        "no surfacing while surveying"
    );

    // --- Return: ACTIVE:RETURNING to 0,0 at 2 m/s; the endflags end the mission.
    let t = rig.t;
    rig.step(&[Mail::new("RETURN", "true", t).from("pMarineViewer")]);
    rig.step(&[]);
    assert_eq!(rig.helm.info().text("MODE"), Some("ACTIVE:RETURNING"));
    let posts = rig.run_until(400.0, "DEPLOY=false", |_, p| {
        posted_str(p, "DEPLOY", "false")
    });
    assert!(posted_str(&posts, "RETURNING", "false"));
    assert!(
        rig.sub.x.hypot(rig.sub.y) < 9.0,
        "home: {:.1},{:.1}",
        rig.sub.x,
        rig.sub.y
    );
    let posts = rig.step(&[]);
    assert_eq!(rig.helm.info().text("MODE"), Some("INACTIVE"), "{posts:?}");

    // --- Never deeper than max depth + tolerance, the whole mission.
    assert!(
        rig.max_depth_seen <= 8.0,
        "deepest {:.2} m",
        rig.max_depth_seen
    );
    assert!(rig.max_depth_seen > 6.5, "it did dive");
    let desired_depths: Vec<f64> = rig
        .history("DESIRED_DEPTH", 0.0)
        .iter()
        .map(|(_, v)| v.as_f64().unwrap())
        .collect();
    assert!(desired_depths.iter().all(|d| *d <= 7.0));
    assert!(rig.helm.state() == HelmState::Drive);
}

// ---------------------------------------------------------------------------------------------
// The operating-region guard in the engine.

fn globals() -> Globals {
    Globals {
        lat_origin: Some("43.8253".into()),
        long_origin: Some("-70.3304".into()),
        community: Some("abe".into()),
    }
}

fn uuv_helm(bhv: &str) -> Helm {
    let parsed = mission::bhv::parse_bhv(&SourceMap::from_text("op.bhv", bhv));
    Helm::from_parsed(
        &[
            ("domain", "course:0:359:360"),
            ("domain", "speed:0:4:41"),
            ("domain", "depth:0:100:101"),
            ("start_engaged", "true"),
        ],
        &globals(),
        &parsed,
    )
}

const GUARDED: &str = "\
Behavior = BHV_ConstantHeading
{
  name = hdg
  heading = 90
  duration = no-time-limit
}
Behavior = BHV_ConstantSpeed
{
  name = spd
  speed = 2
  duration = no-time-limit
}
Behavior = BHV_ConstantDepth
{
  name = dep
  depth = 5
  duration = no-time-limit
}
Behavior = BHV_OpRegion
{
  name = opreg
  polygon = pts={-50,-50:50,-50:50,50:-50,50}
  trigger_exit_time = 0
  max_depth = 10
  max_time = 0
  updates = OPREG_UPDATES
  breached_poly_flag = OPREG_BREACH = poly
  breached_depth_flag = OPREG_BREACH = depth
  breached_time_flag = OPREG_BREACH = time
}
";

/// Feeds nav at a pose and iterates at `t`.
fn at(helm: &mut Helm, t: f64, x: f64, depth: f64, mail: &[(&str, &str)]) -> Vec<Posting> {
    let mut m = vec![
        Mail::new("NAV_X", x, t),
        Mail::new("NAV_Y", 0.0, t),
        Mail::new("NAV_HEADING", 90.0, t),
        Mail::new("NAV_SPEED", 2.0, t),
        Mail::new("NAV_DEPTH", depth, t),
    ];
    for (k, v) in mail {
        m.push(Mail::new(k, *v, t).from("uPokeDB"));
    }
    helm.on_mail(&m);
    helm.iterate(t).to_vec()
}

fn assert_stopped_now(posts: &[Posting], why: &str) {
    let err = get(posts, "BHV_ERROR")
        .and_then(Value::as_str)
        .unwrap_or_else(|| panic!("no BHV_ERROR: {posts:?}"));
    assert!(err.starts_with("opreg: ") && err.contains(why), "{err}");
    assert!(is_str(get(posts, "IVPHELM_ALLSTOP"), "BehaviorError"));
    for var in ["DESIRED_SPEED", "DESIRED_HEADING", "DESIRED_DEPTH"] {
        assert_eq!(
            get(posts, var),
            Some(&Value::Double(0.0)),
            "{var} zeroed at once"
        );
    }
    let summary = get(posts, "IVPHELM_SUMMARY").unwrap().as_str().unwrap();
    assert!(summary.contains("halted=true"), "{summary}");
}

fn running_guard(bhv: &str) -> (Helm, f64) {
    let mut helm = uuv_helm(bhv);
    assert!(
        helm.config_errors().is_empty(),
        "{:?}",
        helm.config_errors()
    );
    let mut t = 0.0;
    while t < 3.0 {
        at(&mut helm, t, 0.0, 5.0, &[]);
        t += 0.5;
    }
    let posts = at(&mut helm, t, 10.0, 5.0, &[]);
    assert_eq!(
        get(&posts, "DESIRED_SPEED"),
        Some(&Value::Double(2.0)),
        "{posts:?}"
    );
    (helm, t)
}

#[test]
fn opregion_polygon_breach_stops_the_vehicle_within_one_iteration() {
    let (mut helm, mut t) = running_guard(GUARDED);
    t += 0.5;
    let posts = at(&mut helm, t, 49.5, 5.0, &[]);
    assert_eq!(get(&posts, "DESIRED_SPEED"), Some(&Value::Double(2.0)));
    assert!(get(&posts, "BHV_ERROR").is_none());
    t += 0.5;
    let posts = at(&mut helm, t, 50.5, 5.0, &[]);
    assert_stopped_now(&posts, "Polygon containment failure");
    assert!(is_str(get(&posts, "OPREG_BREACH"), "poly"));
    // While outside it stays stopped: the guard errs every iteration, the all-stop holds.
    for k in 1..6 {
        let posts = at(&mut helm, t + f64::from(k), 50.5 + f64::from(k), 5.0, &[]);
        assert!(get(&posts, "BHV_ERROR").is_some());
        assert!(
            all(&posts, "DESIRED_SPEED")
                .iter()
                .all(|v| v.as_f64() == Some(0.0)),
            "{posts:?}"
        );
    }
    // As in pHelmIvP (behaviour states are reset every iteration), back inside the helm
    // resumes.
    let posts = at(&mut helm, t + 7.0, 40.0, 5.0, &[]);
    assert!(is_str(get(&posts, "IVPHELM_ALLSTOP"), "clear"), "{posts:?}");
}

#[test]
fn opregion_depth_breach_stops_the_vehicle_within_one_iteration() {
    let (mut helm, t) = running_guard(GUARDED);
    let posts = at(&mut helm, t + 0.5, 0.0, 9.9, &[]);
    assert!(get(&posts, "BHV_ERROR").is_none());
    let posts = at(&mut helm, t + 1.0, 0.0, 10.2, &[]);
    assert_stopped_now(&posts, "Depth failure");
    assert!(is_str(get(&posts, "OPREG_BREACH"), "depth"));
}

#[test]
fn opregion_time_breach_stops_the_vehicle_within_one_iteration() {
    let bhv = GUARDED.replace("max_time = 0", "max_time = 20");
    let (mut helm, t0) = running_guard(&bhv);
    // The clock started on the guard's first running iteration, at 1 s (the helm makes no
    // decisions during its first second).
    let mut t = t0;
    let mut stopped_at = None;
    while t < 40.0 {
        t += 0.5;
        let posts = at(&mut helm, t, 0.0, 5.0, &[]);
        if get(&posts, "BHV_ERROR").is_some() {
            assert_stopped_now(&posts, "timeout failure");
            assert!(is_str(get(&posts, "OPREG_BREACH"), "time"));
            stopped_at = Some(t);
            break;
        }
        assert_eq!(
            get(&posts, "DESIRED_SPEED"),
            Some(&Value::Double(2.0)),
            "t={t}"
        );
    }
    let stopped_at = stopped_at.expect("a time breach");
    assert!(
        (20.0..=22.0).contains(&stopped_at),
        "stopped at {stopped_at}"
    );
}

#[test]
fn bad_values_are_malconfig_at_start_and_rejected_updates_at_run_time() {
    for (from, to) in [
        ("max_depth = 10", "max_depth = -10"),
        ("max_depth = 10", "max_depth = ten"),
        ("trigger_exit_time = 0", "trigger_exit_time = soon"),
        (
            "polygon = pts={-50,-50:50,-50:50,50:-50,50}",
            "polygon = pts={0,0:10,10:0,20:5,10}",
        ),
    ] {
        let helm = uuv_helm(&GUARDED.replace(from, to));
        assert_eq!(helm.state(), HelmState::Malconfig, "{to}");
        let msg = helm.config_errors()[0].to_string();
        assert!(msg.contains(to), "{msg}");
    }
    for (bhv, bad) in [
        (
            "Behavior = BHV_PeriodicSurface\n{\n ascent_grade = steep\n}\n",
            "ascent_grade = steep",
        ),
        (
            "Behavior = BHV_MaxDepth\n{\n max_depth = deep\n}\n",
            "max_depth = deep",
        ),
        (
            "Behavior = BHV_ConstantDepth\n{\n depth = 5m\n}\n",
            "depth = 5m",
        ),
    ] {
        let helm = uuv_helm(bhv);
        assert_eq!(helm.state(), HelmState::Malconfig, "{bad}");
        assert!(helm.config_errors()[0].to_string().contains(bad));
    }

    // At run time: a good update moves the limit, a bad one is refused and the limit kept.
    let (mut helm, t) = running_guard(GUARDED);
    let posts = at(
        &mut helm,
        t + 0.5,
        0.0,
        5.0,
        &[("OPREG_UPDATES", "max_depth=20")],
    );
    let r = get(&posts, "IVPHELM_UPDATE_RESULT")
        .unwrap()
        .as_str()
        .unwrap();
    assert!(r.contains("result=success"), "{r}");
    let posts = at(
        &mut helm,
        t + 1.0,
        0.0,
        15.0,
        &[("OPREG_UPDATES", "max_depth=-1")],
    );
    let r = get(&posts, "IVPHELM_UPDATE_RESULT")
        .unwrap()
        .as_str()
        .unwrap();
    assert!(r.contains("result=param_error"), "{r}");
    assert!(
        get(&posts, "BHV_ERROR").is_none(),
        "15 m is within the updated 20 m"
    );
    assert_eq!(get(&posts, "DESIRED_SPEED"), Some(&Value::Double(2.0)));
    let posts = at(&mut helm, t + 1.5, 0.0, 21.0, &[]);
    assert_stopped_now(&posts, "max:20.00000");
}

#[test]
fn delta_helm_subscribes_to_every_variable_its_behaviours_read() {
    let mut helm = delta_helm();
    let subs = helm.subscriptions().to_vec();
    for var in [
        // BHV_PeriodicSurface's mark variable and nav needs.
        "GPS_UPDATE_RECEIVED",
        "NAV_DEPTH",
        "NAV_SPEED",
        // Condition variables and `updates` variables.
        "MODE",
        "PSURFACE",
        "UP_LOITER",
        "UPDATES_RETURN",
        "DEPTH_VALUE",
        "SURVEY_UPDATES",
        "IVPHELM_STATE",
        // Mode-declaration conditions (`set MODE = ACTIVE { DEPLOY = true }`, ...).
        "DEPLOY",
        "RETURN",
        "SURVEY",
    ] {
        assert!(subs.iter().any(|s| s == var), "{var} missing from {subs:?}");
    }
    let mut seen = subs.clone();
    seen.sort();
    seen.dedup();
    assert_eq!(seen.len(), subs.len(), "no duplicates: {subs:?}");
    // The start-up registrations announce the same list.
    let posts = helm.iterate(0.0).to_vec();
    let announced: Vec<&str> = all(&posts, "IVPHELM_REGISTER")
        .into_iter()
        .filter_map(Value::as_str)
        .collect();
    assert!(announced.contains(&"GPS_UPDATE_RECEIVED"), "{announced:?}");
    assert_eq!(announced.len(), subs.len());
}

const MARKED: &str = "\
Behavior = BHV_PeriodicSurface
{
  name      = psurf
  updates   = PSURF_UPDATES
  period    = 100
  mark_variable = FIX_ONE
}
Behavior = BHV_OpRegion
{
  name      = opreg
  min_altitude = 2
  reset_var = OPREG_RESET
  updates   = OPREG_UPDATES
}
";

#[test]
fn a_mark_variable_set_at_run_time_is_subscribed_to_and_announced() {
    let mut helm = uuv_helm(MARKED);
    assert!(
        helm.config_errors().is_empty(),
        "{:?}",
        helm.config_errors()
    );
    let subs = helm.subscriptions();
    for var in [
        "FIX_ONE",
        "GPS_UPDATE_RECEIVED",
        "NAV_ALTITUDE",
        "OPREG_RESET",
    ] {
        assert!(subs.iter().any(|s| s == var), "{var} missing from {subs:?}");
    }
    assert!(!subs.iter().any(|s| s == "FIX_TWO"));
    let mut t = 0.0;
    while t < 2.0 {
        at(&mut helm, t, 0.0, 5.0, &[("NAV_ALTITUDE", "10")]);
        t += 0.5;
    }
    let posts = at(
        &mut helm,
        t,
        0.0,
        5.0,
        &[("PSURF_UPDATES", "mark_variable=FIX_TWO")],
    );
    let r = get(&posts, "IVPHELM_UPDATE_RESULT")
        .and_then(Value::as_str)
        .unwrap_or_else(|| panic!("no update result: {posts:?}"));
    assert!(r.contains("result=success"), "{r}");
    let subs = helm.subscriptions();
    assert!(subs.iter().any(|s| s == "FIX_TWO"), "{subs:?}");
    assert!(
        subs.iter().any(|s| s == "FIX_ONE"),
        "registrations only grow"
    );
    let announced: Vec<&str> = all(&posts, "IVPHELM_REGISTER")
        .into_iter()
        .filter_map(Value::as_str)
        .collect();
    assert_eq!(announced, ["FIX_TWO"]);
    // Registered once: a second identical update announces nothing.
    let posts = at(
        &mut helm,
        t + 0.5,
        0.0,
        5.0,
        &[("PSURF_UPDATES", "mark_variable=FIX_TWO # period=90")],
    );
    assert!(all(&posts, "IVPHELM_REGISTER").is_empty());
}

const TIMED: &str = "\
Behavior = BHV_ConstantHeading
{
  name = hdg
  heading = 90
  duration = no-time-limit
}
Behavior = BHV_ConstantDepth
{
  name = dep
  depth = 5
  duration = no-time-limit
}
Behavior = BHV_ConstantSpeed
{
  name = spd
  speed = 2
  duration = no-time-limit
}
Behavior = BHV_OpRegion
{
  name = opreg
  max_time = 3
  reset_var = OPREG_RESET
  breached_time_flag = OPREG_BREACH = time
}
";

#[test]
fn opregion_reset_acts_on_mail_of_this_iteration_even_when_repeated() {
    let mut helm = uuv_helm(TIMED);
    assert!(helm.config_errors().is_empty());
    // Decisions start at 1 s; the region's clock with them.
    let mut t = 0.0;
    while t <= 4.0 {
        let posts = at(&mut helm, t, 0.0, 5.0, &[]);
        assert!(get(&posts, "BHV_ERROR").is_none(), "t={t}: {posts:?}");
        t += 0.5;
    }
    let posts = at(&mut helm, t, 0.0, 5.0, &[]);
    assert_stopped_now(&posts, "timeout failure");
    assert!(is_str(get(&posts, "OPREG_BREACH"), "time"));
    for round in 0..2 {
        // The same value each time: each fresh posting is a reset.
        let posts = at(&mut helm, t + 0.5, 0.0, 5.0, &[("OPREG_RESET", "time")]);
        assert!(
            get(&posts, "BHV_ERROR").is_none(),
            "round {round}: reset by fresh mail: {posts:?}"
        );
        assert_eq!(get(&posts, "DESIRED_SPEED"), Some(&Value::Double(2.0)));
        t += 0.5;
        // No new mail: the value stays in the buffer but resets nothing; the clock runs.
        let reset_at = t;
        while t < reset_at + 3.5 {
            t += 0.5;
            let posts = at(&mut helm, t, 0.0, 5.0, &[]);
            let err = get(&posts, "BHV_ERROR").is_some();
            assert_eq!(err, t - reset_at > 3.0, "round {round}, t={t}: {posts:?}");
        }
    }
}

const POLY_VAR: &str = "\
Behavior = BHV_ConstantHeading
{
  name = hdg
  heading = 90
  duration = no-time-limit
}
Behavior = BHV_ConstantDepth
{
  name = dep
  depth = 5
  duration = no-time-limit
}
Behavior = BHV_ConstantSpeed
{
  name = spd
  speed = 2
  duration = no-time-limit
}
Behavior = BHV_OpRegion
{
  name = opreg
  polygon = pts={-50,-50:50,-50:50,50:-50,50}
  opregion_poly_var = OPREG_POLY
  configflag = OPREG_CONFIGURED = true
  updates = OPREG_UPDATES
}
";

#[test]
fn opregion_posts_its_polygon_at_configuration_on_the_first_iteration() {
    let mut helm = uuv_helm(POLY_VAR);
    assert!(helm.config_errors().is_empty());
    let mut first = Vec::new();
    let mut t = 0.0;
    while t <= 2.0 {
        let posts = at(&mut helm, t, 0.0, 5.0, &[]);
        let n = all(&posts, "OPREG_POLY").len();
        if t < 1.0 {
            assert_eq!(n, 0, "no behaviour postings before the first decision");
        } else if first.is_empty() {
            first = posts;
        } else {
            assert_eq!(n, 0, "posted once (duplicate filter)");
        }
        t += 0.5;
    }
    let vars: Vec<&str> = first.iter().map(|p| &*p.key).collect();
    let poly = vars.iter().position(|v| *v == "OPREG_POLY");
    let conf = vars.iter().position(|v| *v == "OPREG_CONFIGURED");
    let status = first
        .iter()
        .position(|p| p.key == "BHV_STATUS" && p.aux.ends_with(":opreg"));
    let (Some(poly), Some(conf), Some(status)) = (poly, conf, status) else {
        panic!("missing postings: {vars:?}");
    };
    // MOOS posts onSetParamComplete's messages ahead of the first iteration's configflags.
    assert!(poly < conf && conf < status, "{vars:?}");
    assert!(is_str(
        get(&first, "OPREG_POLY"),
        "pts={-50,-50:50,-50:50,50:-50,50}"
    ));
    assert_eq!(first[poly].aux, "1:opreg");
    // An update with a new polygon posts it in the update's iteration.
    let posts = at(
        &mut helm,
        t,
        0.0,
        5.0,
        &[("OPREG_UPDATES", "polygon=pts={-60,-60:60,-60:60,60:-60,60}")],
    );
    assert!(
        is_str(
            get(&posts, "OPREG_POLY"),
            "pts={-60,-60:60,-60:60,60:-60,60}"
        ),
        "{posts:?}"
    );
}

// ---------------------------------------------------------------------------------------------
// Safety defaults: BHV_MaxDepth has no default duration (IvPBehavior's −1; only the constant-*
// behaviours set 0 in their constructors at MOOS-IvP a2a9b716).

const DEEP_VS_MAXDEPTH: &str = "\
Behavior = BHV_ConstantHeading
{
  name = hdg
  heading = 90
  duration = no-time-limit
}
Behavior = BHV_ConstantSpeed
{
  name = spd
  speed = 2
  duration = no-time-limit
}
Behavior = BHV_ConstantDepth
{
  name = deep
  pwt = 120
  depth = 30
  duration = no-time-limit
}
Behavior = BHV_MaxDepth
{
  name = maxd
  pwt = 300
  max_depth = 12
  tolerance = 4
  depth_slack_var = DEPTH_SLACK
}
";

#[test]
fn max_depth_without_a_duration_line_keeps_guarding_and_posts_its_slack() {
    let mut helm = uuv_helm(DEEP_VS_MAXDEPTH);
    assert!(
        helm.config_errors().is_empty(),
        "{:?}",
        helm.config_errors()
    );
    let mut slack = Vec::new();
    let mut seen_active = false;
    let mut t = 0.0;
    // 20 simulated minutes at 4 Hz, the vehicle held at 10 m.
    while t < 1200.0 {
        let posts = at(&mut helm, t, 0.0, 10.0, &[]);
        if let Some(v) = get(&posts, "DEPTH_SLACK").and_then(Value::as_f64) {
            slack.push(v);
        }
        if let Some(d) = get(&posts, "DESIRED_DEPTH").and_then(Value::as_f64) {
            // ConstantDepth alone would ask for 30 m; MaxDepth's LEQ (pwt 300, summit 12,
            // base width 4) outweighs it everywhere deeper than 12 m.
            assert!(d <= 12.0, "t={t}: DESIRED_DEPTH {d} deeper than max_depth");
        }
        let summary = get(&posts, "IVPHELM_SUMMARY").and_then(Value::as_str);
        if let Some(done) = summary.and_then(|s| s.split(",completed_bhvs=").nth(1)) {
            let done = done.split(',').next().unwrap_or_default();
            assert!(!done.contains("maxd"), "t={t}: maxd completed: {done}");
        }
        if let Some(active) = summary.and_then(|s| s.split(",active_bhvs=").nth(1)) {
            seen_active |= active
                .split(',')
                .next()
                .unwrap_or_default()
                .contains("maxd");
        }
        t += 0.25;
    }
    // max_depth − NAV_DEPTH = 12 − 10; posted once (duplicate filter), never with another value.
    assert!(!slack.is_empty(), "DEPTH_SLACK never posted");
    assert!(slack.iter().all(|s| *s == 2.0), "{slack:?}");
    assert!(seen_active, "maxd never listed as active");
}

// ---------------------------------------------------------------------------------------------
// BHV_OpRegionV24 in the engine.

const V24: &str = "\
Behavior = BHV_ConstantDepth
{
  name = dep
  depth = 0
  duration = no-time-limit
}
Behavior = BHV_ConstantHeading
{
  name = hdg
  heading = 90
  duration = no-time-limit
}
Behavior = BHV_ConstantSpeed
{
  name = spd
  speed = 2
  duration = no-time-limit
}
Behavior = BHV_OpRegionV24
{
  name = opr
  pwt = 300
  core_poly = -50,-50 : -50,50 : 50,50 : 50,-50
  save_dist = 10
  halt_dist = 40
  trigger_exit_time = 0
  breached_poly_flag = OPREG_BREACH = halt
  save_flag = OPREG_SAVE = $[SECS_OUT_SAVE_POLY]
}
";

#[test]
fn opregion_v24_halt_breach_all_stops_and_the_save_poly_turns_the_vehicle_back() {
    let mut helm = uuv_helm(V24);
    assert!(
        helm.config_errors().is_empty(),
        "{:?}",
        helm.config_errors()
    );
    let mut t = 0.0;
    while t < 3.0 {
        at(&mut helm, t, 0.0, 0.0, &[]);
        t += 0.5;
    }
    // Inside the core: the constant heading (east) wins.
    let posts = at(&mut helm, t, 20.0, 0.0, &[]);
    assert_eq!(
        get(&posts, "DESIRED_HEADING"),
        Some(&Value::Double(90.0)),
        "{posts:?}"
    );
    // 65 m east: outside the 60 m save polygon, still inside the 90 m halt polygon. The
    // recovery function (pwt 300) turns the vehicle back; the save flag expands its macro.
    let posts = at(&mut helm, t + 0.5, 65.0, 0.0, &[]);
    let hdg = get(&posts, "DESIRED_HEADING")
        .and_then(Value::as_f64)
        .unwrap();
    assert!(
        (180.0..=360.0).contains(&hdg),
        "heading {hdg} does not turn back"
    );
    assert_eq!(
        get(&posts, "OPREG_SAVE"),
        Some(&Value::Double(0.0)),
        "{posts:?}"
    );
    assert!(get(&posts, "BHV_ERROR").is_none());
    // 95 m east: outside the halt polygon after an entry: the helm all-stops at once.
    let posts = at(&mut helm, t + 1.0, 95.0, 0.0, &[]);
    let e = get(&posts, "BHV_ERROR").and_then(Value::as_str).unwrap();
    assert_eq!(e, "opr: OpRegion HaltPoly Failure");
    assert!(is_str(get(&posts, "OPREG_BREACH"), "halt"));
    assert!(is_str(get(&posts, "IVPHELM_ALLSTOP"), "BehaviorError"));
    assert_eq!(get(&posts, "DESIRED_SPEED"), Some(&Value::Double(0.0)));
}
