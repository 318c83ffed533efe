//! Marine PID: loop semantics, closed loop with the simulator, staleness and override.

mod common;

use vehicle::ValueRef;
use vehicle::angle::angle180;
use vehicle::moos::last_posting;
use vehicle::pid::{MarinePid, PidConfig, PidInputs, PidState, ScalarPid, step};
use vehicle::sim::{self, SimConfig, SimInputs, SimState};

/// The pMarinePID block of the golf mission (a UUV with depth control, speed_factor 20).
fn golf_pid() -> PidConfig {
    let text = test_support::mission_text("s7_golf/golf.moos");
    let block = common::process_config(&text, "pMarinePID");
    PidConfig::from_params(common::pairs(&block)).expect("golf pMarinePID block is valid")
}

#[test]
fn scalar_pid_semantics() {
    // Pure P with output clamp.
    let mut p = ScalarPid::new(2.0, 0.0, 0.0, 0.0, 10.0);
    assert_eq!(p.run(3.0, 0.0), 6.0);
    assert_eq!(p.run(8.0, 1.0), 10.0);
    assert!(p.saturated());
    // Integral: ki*e*dt accumulated, clamped to the integral limit; none on the first call.
    let mut i = ScalarPid::new(0.0, 0.0, 0.5, 1.2, 100.0);
    assert_eq!(i.run(1.0, 0.0), 0.0);
    assert_eq!(i.run(1.0, 1.0), 0.5);
    assert_eq!(i.run(1.0, 2.0), 1.0);
    assert_eq!(i.run(1.0, 3.0), 1.2);
    // ki <= 0 holds the integral at zero.
    let mut z = ScalarPid::new(0.0, 0.0, 0.0, 5.0, 100.0);
    z.run(1.0, 0.0);
    z.run(1.0, 1.0);
    assert_eq!(z.integral(), 0.0);
    // Derivative: mean of the last (at most 9) difference quotients.
    let mut d = ScalarPid::new(0.0, 1.0, 0.0, 0.0, 1e9);
    d.run(0.0, 0.0);
    assert_eq!(d.run(2.0, 1.0), 2.0); // [2]
    assert_eq!(d.run(2.0, 2.0), 1.0); // [2, 0]
    for t in 3..20 {
        d.run(2.0, f64::from(t));
    }
    assert_eq!(d.run(2.0, 20.0), 0.0, "old samples leave the window");
    // Repeated time repeats the output.
    let mut r = ScalarPid::new(1.0, 0.0, 0.0, 0.0, 100.0);
    r.run(1.0, 0.0);
    r.run(2.0, 1.0);
    assert_eq!(r.run(50.0, 1.0), 2.0);
}

struct Loop {
    pid_cfg: PidConfig,
    pid: PidState,
    inputs: PidInputs,
    sim_cfg: SimConfig,
    sim: SimState,
    t: f64,
}

impl Loop {
    fn new(pid_cfg: PidConfig, start: SimState) -> Self {
        let sim_cfg = SimConfig::default();
        Loop {
            pid: PidState::new(&pid_cfg),
            pid_cfg,
            inputs: PidInputs {
                manual_override: false,
                ..PidInputs::default()
            },
            sim_cfg,
            sim: start,
            t: 0.0,
        }
    }

    /// One 0.1 s tick: nav and desired values in, PID, then the simulator.
    fn tick(&mut self, des_hdg: f64, des_spd: f64, des_dep: f64) -> vehicle::pid::PidOutputs {
        let t = self.t;
        let i = &mut self.inputs;
        i.desired_heading = Some((des_hdg, t));
        i.desired_speed = Some((des_spd, t));
        i.desired_depth = Some((des_dep, t));
        i.heading = Some((self.sim.heading_deg, t));
        i.speed = Some((self.sim.speed_mps, t));
        i.depth = Some((self.sim.depth, t));
        i.pitch = Some((self.sim.pitch_rad, t));
        let (p, out) = step(&self.pid_cfg, &self.pid, &self.inputs, t);
        self.pid = p;
        let sin = SimInputs {
            thrust: out.thrust,
            rudder_deg: out.rudder,
            elevator_deg: out.elevator,
            ..SimInputs::from_config(&self.sim_cfg)
        };
        self.sim = sim::step(&self.sim_cfg, &self.sim, &sin, 0.1, None).0;
        self.t += 0.1;
        out
    }
}

/// Time after which `err` stays within `tol` until the end of `series`.
fn settle_time(series: &[(f64, f64)], tol: f64) -> Option<f64> {
    let last_out = series.iter().rposition(|(_, e)| e.abs() > tol)?;
    series.get(last_out + 1).map(|(t, _)| *t)
}

fn cfg_kp() -> f64 {
    golf_pid().yaw.kp
}

#[test]
fn heading_step_90_to_270_settles() {
    let cfg = golf_pid();
    assert_eq!((cfg.yaw.kp, cfg.speed_factor), (0.5, 20.0));
    let mut l = Loop::new(
        cfg,
        SimState {
            heading_deg: 90.0,
            speed_mps: 2.0,
            ..SimState::default()
        },
    );
    let mut series = Vec::new();
    for _ in 0..1200 {
        l.tick(270.0, 2.0, 0.0);
        series.push((l.t, angle180(l.sim.heading_deg - 270.0)));
    }
    let t = settle_time(&series, 2.0).expect("heading never settled");
    eprintln!("heading settles within 2 deg after {t:.1} s");
    // What the gains give: rudder = -kp*e (kp 0.5, never saturating for |e| <= 180), and the
    // heading rate is rudder * rate(v)/100 * thrust/50 with rate(v) = 70*v/5. Thrust is
    // 40 (speed_factor 20 * 2 m/s) and turning only slows the vehicle (v <= 2), so
    // |de/dt| <= k|e| with k = 0.5 * 0.28 * 0.8 = 0.112/s: reaching 2 degrees from 180 takes
    // at least ln(180/2)/k = 40.2 s. The speed lost in the turn (turn_spd_loss 0.85) may
    // stretch that, but by less than half.
    let k = cfg_kp() * (70.0 * 2.0 / 5.0 / 100.0) * (40.0 / 50.0);
    let t_min = (180.0f64 / 2.0).ln() / k;
    assert!(
        t >= t_min - 0.1,
        "settled in {t} s, faster than the gains allow ({t_min} s)"
    );
    assert!(
        t <= 1.5 * t_min,
        "settle time {t} s, expected under {} s",
        1.5 * t_min
    );
    // Proportional-only yaw loop: no overshoot beyond the tolerance band once settled,
    // and the speed recovers to 2 m/s (speed_factor 20 -> thrust 40).
    assert!(angle180(l.sim.heading_deg - 270.0).abs() < 0.5);
    assert!((l.sim.speed_mps - 2.0).abs() < 0.02);
}

#[test]
fn speed_pid_settles_without_speed_factor() {
    let mut cfg = golf_pid();
    cfg.speed_factor = 0.0;
    let mut l = Loop::new(
        cfg,
        SimState {
            heading_deg: 90.0,
            ..SimState::default()
        },
    );
    let mut series = Vec::new();
    for _ in 0..600 {
        l.tick(90.0, 2.0, 0.0);
        series.push((l.t, l.sim.speed_mps - 2.0));
    }
    let t = settle_time(&series, 0.05).expect("speed never settled");
    eprintln!("speed settles within 0.05 m/s after {t:.1} s");
    assert!(t < 30.0);
    assert!((l.pid.thrust - 40.0).abs() < 1.0, "thrust {}", l.pid.thrust);
}

#[test]
fn depth_step_settles() {
    let cfg = golf_pid();
    let mut l = Loop::new(
        cfg,
        SimState {
            heading_deg: 90.0,
            speed_mps: 2.0,
            ..SimState::default()
        },
    );
    let mut series = Vec::new();
    for _ in 0..3000 {
        let o = l.tick(90.0, 2.0, 10.0);
        assert!(o.elevator.abs() <= 13.0 + 1e-9);
        assert!(o.desired_pitch.abs() <= 15f64.to_radians() + 1e-12);
        series.push((l.t, l.sim.depth - 10.0));
    }
    let t = settle_time(&series, 0.2).expect("depth never settled");
    eprintln!("depth settles within 0.2 m after {t:.1} s");
    assert!(t < 250.0);
    // Diving pitches the nose down (negative pitch in the simulator's convention).
    let mut l = Loop::new(
        golf_pid(),
        SimState {
            heading_deg: 90.0,
            speed_mps: 2.0,
            ..SimState::default()
        },
    );
    for _ in 0..50 {
        l.tick(90.0, 2.0, 10.0);
    }
    assert!(l.sim.pitch_rad < 0.0 && l.sim.depth > 0.0);
}

#[test]
fn stale_inputs_give_pid_stale_and_zero_outputs() {
    let mut app = MarinePid::new(golf_pid());
    let mut out = Vec::new();
    let feed_nav = |app: &mut MarinePid, t: f64| {
        for (v, x) in [
            ("NAV_HEADING", 90.0),
            ("NAV_SPEED", 2.0),
            ("NAV_DEPTH", 0.0),
            ("NAV_PITCH", 0.0),
        ] {
            app.on_mail(v, ValueRef::Double(x), t);
        }
    };
    // Under manual override (the initial state) the outputs are zero, posted once.
    feed_nav(&mut app, 0.0);
    app.iterate(0.0, &mut out);
    assert_eq!(
        last_posting(&out, "DESIRED_THRUST").unwrap().as_f64(),
        Some(0.0)
    );
    out.clear();
    app.iterate(0.1, &mut out);
    assert!(out.is_empty(), "zeros are posted only once: {out:?}");

    app.on_mail("MOOS_MANUAL_OVERRIDE", ValueRef::String("false"), 0.2);
    for (v, x) in [
        ("DESIRED_HEADING", 100.0),
        ("DESIRED_SPEED", 2.0),
        ("DESIRED_DEPTH", 0.0),
    ] {
        app.on_mail(v, ValueRef::Double(x), 0.2);
    }
    feed_nav(&mut app, 0.2);
    app.iterate(0.3, &mut out);
    assert_eq!(
        last_posting(&out, "PID_HAS_CONTROL").unwrap().as_str(),
        Some("true")
    );
    assert_eq!(
        last_posting(&out, "DESIRED_THRUST").unwrap().as_f64(),
        Some(40.0)
    );
    assert!(
        last_posting(&out, "DESIRED_RUDDER")
            .unwrap()
            .as_f64()
            .unwrap()
            > 0.0
    );

    // The helm goes quiet; nav keeps coming. After 2 s: stale.
    out.clear();
    let mut t = 0.3;
    while t < 2.6 {
        t += 0.1;
        feed_nav(&mut app, t);
        app.iterate(t, &mut out);
    }
    let stale: Vec<_> = out.iter().filter(|p| &*p.key == "PID_STALE").collect();
    assert!(!stale.is_empty(), "no PID_STALE");
    let s = stale[0].value.as_str().unwrap();
    assert!(s.starts_with("Stale DesHdg:"), "{s}");
    assert!(
        stale
            .iter()
            .any(|p| p.value.as_str().unwrap().starts_with("Stale DesSpd:"))
    );
    assert!(
        !stale
            .iter()
            .any(|p| p.value.as_str().unwrap().starts_with("Stale NavHdg"))
    );
    assert!(!app.last_outputs().has_control);
    assert_eq!(
        last_posting(&out, "DESIRED_THRUST").unwrap().as_f64(),
        Some(0.0)
    );
    assert_eq!(
        last_posting(&out, "DESIRED_RUDDER").unwrap().as_f64(),
        Some(0.0)
    );
    assert_eq!(
        last_posting(&out, "DESIRED_ELEVATOR").unwrap().as_f64(),
        Some(0.0)
    );

    // Override back on: PID_HAS_CONTROL=false.
    out.clear();
    app.on_mail("MOOS_MANUAL_OVERIDE", ValueRef::String("true"), t);
    app.iterate(t + 0.1, &mut out);
    assert_eq!(
        last_posting(&out, "PID_HAS_CONTROL").unwrap().as_str(),
        Some("false")
    );
}

#[test]
fn nav_yaw_and_output_suffix() {
    let mut cfg = golf_pid();
    cfg.output_suffix = "_L".into();
    let mut app = MarinePid::new(cfg);
    let mut out = Vec::new();
    app.iterate(0.05, &mut out);
    app.on_mail(
        "NAV_YAW",
        ValueRef::Double(-std::f64::consts::FRAC_PI_2),
        0.0,
    );
    assert_eq!(app.inputs().heading.unwrap().0, 90.0);
    assert!(last_posting(&out, "DESIRED_RUDDER_L").is_some());
}

#[test]
fn required_keys_are_enforced() {
    let err = PidConfig::from_params([("yaw_pid_kp", "1")]).unwrap_err();
    assert!(
        matches!(
            err,
            vehicle::ConfigError::Missing {
                key: "yaw_pid_kd",
                ..
            }
        ),
        "{err}"
    );
    let surface = [
        ("YAW_PID_KP", "1.2"),
        ("YAW_PID_KD", "0"),
        ("YAW_PID_KI", "0"),
        ("YAW_PID_INTEGRAL_LIMIT", "0.07"),
        ("SPEED_PID_KP", "1"),
        ("SPEED_PID_KD", "0"),
        ("SPEED_PID_KI", "0"),
        ("SPEED_PID_INTEGRAL_LIMIT", "0.07"),
        ("MAXRUDDER", "100"),
        ("MAXTHRUST", "100"),
        ("depth_control", "false"),
        ("speed_factor", "20"),
    ];
    let cfg = PidConfig::from_params(surface).unwrap();
    assert!(!cfg.depth_control);
    assert!(PidConfig::from_params(surface.iter().copied().chain([("maxrudder", "x")])).is_err());
}

/// A pMarinePIDV22 with the golf gains, fed every input at `t` (override lifted first).
fn v22_running(
    mut cfg: PidConfig,
    des_hdg: f64,
    des_spd: f64,
) -> (MarinePid, Vec<vehicle::moos::Posting>) {
    cfg.legacy = false;
    let mut app = MarinePid::new(cfg);
    // PIDEngine stamps mail with its clock, the time of the last iteration (0, "never
    // received", before the first): the app has iterated once before the inputs come.
    let mut out = Vec::new();
    app.iterate(0.05, &mut out);
    app.on_mail("MOOS_MANUAL_OVERRIDE", ValueRef::String("false"), 0.0);
    for (v, x) in [
        ("DESIRED_HEADING", des_hdg),
        ("DESIRED_SPEED", des_spd),
        ("DESIRED_DEPTH", 5.0),
        ("NAV_HEADING", 90.0),
        ("NAV_SPEED", 1.0),
        ("NAV_DEPTH", 0.0),
        ("NAV_PITCH", 0.0),
    ] {
        app.on_mail(v, ValueRef::Double(x), 0.0);
    }
    app.iterate(0.1, &mut out);
    (app, out)
}

fn num(out: &[vehicle::moos::Posting], var: &str) -> Option<f64> {
    last_posting(out, var).and_then(|p| p.as_f64())
}

#[test]
fn v22_zero_or_negative_desired_speed_is_an_all_stop_of_every_actuator() {
    // speed_factor 20 (golf): desired 0 or -1 gives thrust below 0.01, so 0, and then the
    // rudder and elevator are not computed (0) although the heading is 90 deg off.
    for des in [0.0, -1.0] {
        let (app, out) = v22_running(golf_pid(), 180.0, des);
        assert!(app.last_outputs().has_control);
        assert_eq!(num(&out, "DESIRED_THRUST"), Some(0.0), "speed {des}");
        assert_eq!(num(&out, "DESIRED_RUDDER"), Some(0.0), "speed {des}");
        assert_eq!(num(&out, "DESIRED_ELEVATOR"), Some(0.0), "speed {des}");
    }
    // A small positive speed still steers.
    let (_, out) = v22_running(golf_pid(), 180.0, 0.5);
    assert_eq!(num(&out, "DESIRED_THRUST"), Some(10.0));
    assert!(num(&out, "DESIRED_RUDDER").unwrap() != 0.0);
}

#[test]
fn v22_negative_speed_factor_stops_and_a_negative_config_factor_is_ignored() {
    let (mut app, _) = v22_running(golf_pid(), 90.0, 2.0);
    app.on_mail("SPEED_FACTOR", ValueRef::Double(-20.0), 0.2);
    let mut out = Vec::new();
    app.iterate(0.3, &mut out);
    assert_eq!(num(&out, "DESIRED_THRUST"), Some(0.0));
    // In the block, a negative factor is not taken (setNonNegDoubleOnString): a warning,
    // and the speed loop is used (factor 0).
    let text = test_support::mission_text("s7_golf/golf.moos");
    let block = common::process_config(&text, "pMarinePID");
    let mut pairs: Vec<(&str, &str)> = common::pairs(&block).collect();
    pairs.retain(|(k, _)| !k.eq_ignore_ascii_case("speed_factor"));
    pairs.push(("speed_factor", "-3"));
    let (cfg, warnings) = PidConfig::from_params_lenient(pairs).unwrap();
    assert_eq!(cfg.speed_factor, 0.0);
    assert_eq!(warnings.len(), 1, "{warnings:?}");
}

#[test]
fn v22_simulation_mode_never_takes_control() {
    // MOOS-IvP a2a9b716: with `simulation = true` the staleness check, the only place that
    // clears the initial "stale" state, is skipped: the outputs stay at the all-stop.
    let mut cfg = golf_pid();
    cfg.simulation = true;
    let (mut app, out) = v22_running(cfg, 180.0, 2.0);
    assert!(!app.last_outputs().has_control);
    assert_eq!(num(&out, "DESIRED_THRUST"), Some(0.0));
    assert_eq!(num(&out, "DESIRED_RUDDER"), Some(0.0));
    let mut out = Vec::new();
    app.iterate(0.2, &mut out);
    assert!(
        !out.iter().any(|p| p.key.starts_with("DESIRED_")),
        "the all-stop is posted once: {out:?}"
    );
}

#[test]
fn v22_thrust_cap_is_read_and_clipped_but_not_applied() {
    let mut cfg = golf_pid();
    cfg.enable_thrust_cap = true;
    let (mut app, _) = v22_running(cfg, 90.0, 4.0);
    assert!(app.subscriptions().contains(&"PID_THRUST_CAP"));
    // `setDoubleClipRngOnString` reads the string value: a double mail is not taken.
    app.on_mail("PID_THRUST_CAP", ValueRef::Double(50.0), 0.2);
    assert_eq!(app.thrust_cap(), 100.0);
    app.on_mail("PID_THRUST_CAP", ValueRef::String("50"), 0.2);
    assert_eq!(app.thrust_cap(), 50.0);
    app.on_mail("PID_THRUST_CAP", ValueRef::String("5"), 0.2);
    assert_eq!(app.thrust_cap(), 20.0, "clipped to [20, 100]");
    app.on_mail("PID_THRUST_CAP", ValueRef::String("fast"), 0.2);
    assert_eq!(app.thrust_cap(), 20.0, "a non-number is not taken");
    let mut out = Vec::new();
    app.iterate(0.3, &mut out);
    // 4 m/s x speed factor 20: the C++ posts the uncapped 80.
    assert_eq!(num(&out, "DESIRED_THRUST"), Some(80.0));
}

#[test]
fn v22_debug_reports_follow_the_loops_in_the_cpp_format() {
    let mut cfg = golf_pid();
    cfg.speed_debug = true;
    cfg.heading_debug = true;
    let (_, out) = v22_running(cfg, 270.0, 2.0);
    let spd = last_posting(&out, "PID_SPD_DEBUG")
        .unwrap()
        .as_str()
        .unwrap()
        .to_string();
    assert_eq!(
        spd,
        "PID_SPEED:  (Want):2.00000 (Curr):1.00000 (Diff):1.00000 (Fctr):20.00000 THRUST:40.00000"
    );
    let hdg = last_posting(&out, "PID_HDG_DEBUG")
        .unwrap()
        .as_str()
        .unwrap()
        .to_string();
    // The desired heading in (-180, 180]: 270 -> -90; error angle180(90 - -90) = 180.
    assert!(
        hdg.starts_with("PID_COURSE:  (Want):-90.00000 (Curr):90.00000 (Diff):180.00000 RUDDER:"),
        "{hdg}"
    );
    // Debug reports come after the actuator postings.
    let ix = |v: &str| out.iter().position(|p| &*p.key == v).unwrap();
    assert!(ix("DESIRED_THRUST") < ix("PID_SPD_DEBUG"));
}

#[test]
fn v22_mail_is_stamped_with_the_engine_clock() {
    // PIDEngine stamps inputs with its own time (the last iteration's), 0 before the first
    // iteration, and 0 means "never received": mail before the first iteration does not count.
    let mut app = MarinePid::new(golf_pid());
    app.on_mail("MOOS_MANUAL_OVERRIDE", ValueRef::String("false"), 1.0);
    app.on_mail("DESIRED_HEADING", ValueRef::Double(90.0), 1.0);
    assert!(app.inputs().desired_heading.is_none());
    let mut out = Vec::new();
    app.iterate(10.0, &mut out);
    app.on_mail("DESIRED_HEADING", ValueRef::Double(90.0), 11.5);
    assert_eq!(app.inputs().desired_heading, Some((90.0, 10.0)));
    for (v, x) in [
        ("DESIRED_SPEED", 2.0),
        ("DESIRED_DEPTH", 0.0),
        ("NAV_HEADING", 90.0),
        ("NAV_SPEED", 2.0),
        ("NAV_DEPTH", 0.0),
        ("NAV_PITCH", 0.0),
    ] {
        app.on_mail(v, ValueRef::Double(x), 11.5);
    }
    // Ages are counted from the stamp (10), not the mail time: 12.5 - 10 = 2.5 > 2.
    out.clear();
    app.iterate(12.5, &mut out);
    let stale: Vec<&str> = out
        .iter()
        .filter(|p| &*p.key == "PID_STALE")
        .filter_map(|p| p.value.as_str())
        .collect();
    assert_eq!(
        stale,
        vec![
            "Stale DesHdg:2.5",
            "Stale DesSpd:2.5",
            "Stale NavHdg:2.5",
            "Stale NavSpd:2.5",
            "Stale DesDepth:2.5",
            "Stale NavDep:2.5",
            "Stale NavPitch:2.5"
        ]
    );
}

#[test]
fn v22_max_saturation_debug_postings_precede_each_report() {
    // golf: yaw kp 0.5, maxrudder 100; z-to-pitch kp 0.12 (limit maxpitch 15 deg), pitch kp
    // 0.5 (limit maxelevator 13 deg). Heading error 180: 0.5 x 180 = 90 < 100, no saturation.
    let mut cfg = golf_pid();
    cfg.heading_debug = true;
    cfg.depth_debug = true;
    let (_, out) = v22_running(cfg.clone(), 270.0, 2.0);
    assert!(last_posting(&out, "PID_MAX_SAT_HDG_DEBUG").is_none());
    // Depth error 0 - 5: 0.12 x -5 = -0.6 rad beyond 15 deg (0.262 rad): the depth-to-pitch
    // loop saturates ("Z:"); the pitch loop's 0.5 x 0.262 = 0.131 rad is within 13 deg.
    let sats: Vec<&str> = out
        .iter()
        .filter(|p| &*p.key == "PID_MAX_SAT_DEP_DEBUG")
        .map(|p| p.value.as_str().unwrap())
        .collect();
    assert_eq!(sats, ["Z:"]);
    let ix = |v: &str| out.iter().position(|p| &*p.key == v).unwrap();
    assert!(ix("PID_MAX_SAT_DEP_DEBUG") < ix("PID_DEP_DEBUG"));
    // A rudder limit of 50 saturates the heading loop: an empty debug string (ScalarPID's
    // own debug text is never switched on at a2a9b716), posted before PID_HDG_DEBUG.
    cfg.max_rudder = 50.0;
    let (_, out) = v22_running(cfg, 270.0, 2.0);
    assert_eq!(
        last_posting(&out, "PID_MAX_SAT_HDG_DEBUG").and_then(|v| v.as_str()),
        Some("")
    );
    let ix = |v: &str| out.iter().position(|p| &*p.key == v).unwrap();
    assert!(ix("PID_MAX_SAT_HDG_DEBUG") < ix("PID_HDG_DEBUG"));
}
