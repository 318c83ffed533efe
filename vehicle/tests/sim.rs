//! Marine simulator against the uSimMarineV22 formulas.

mod common;

use vehicle::moos::last_posting;
use vehicle::sim::{SimConfig, SimInputs, SimState, Simulator, StartPose, ThrustMap, step};
use vehicle::{ConfigError, ValueRef};

fn close(a: f64, b: f64, tol: f64) -> bool {
    (a - b).abs() <= tol
}

#[test]
fn thrust_map_interpolates_and_reflects() {
    let mut m = ThrustMap::default();
    assert_eq!(m.speed(40.0), 2.0, "default thrust_factor 20");
    m.add_spec("0:0, 20:1, 40:2, 80:3").unwrap();
    assert!(!m.using_thrust_factor());
    assert!(close(m.speed(30.0), 1.5, 1e-12));
    assert!(close(m.speed(60.0), 2.5, 1e-12));
    assert!(
        close(m.speed(90.0), 3.0, 1e-12),
        "flat from the last pair to 100"
    );
    assert_eq!(m.speed(100.0), 3.0);
    assert_eq!(m.speed(-50.0), 0.0, "no negative map, no reflection");
    m.reflect = true;
    assert!(close(m.speed(-30.0), -1.5, 1e-12));
    m.add_spec("-100:-2").unwrap();
    assert!(
        close(m.speed(-50.0), -1.0, 1e-12),
        "negative map from -100 up to 0:0"
    );
    assert!(m.add_pair(50.0, 0.5).is_err(), "non-ascending rejected");
    assert!(m.add_pair(120.0, 5.0).is_err());
    assert!(m.add_pair(10.0, -1.0).is_err());
}

#[test]
fn speed_from_thrust_map_with_mean_speed_update() {
    let cfg = SimConfig::from_params([
        ("thrust_map", "0:0, 20:1, 40:2, 100:4"),
        ("max_deceleration", "0"),
    ])
    .unwrap();
    let mut s = SimState::at(&cfg.start);
    let inputs = SimInputs {
        thrust: 30.0,
        ..SimInputs::from_config(&cfg)
    };
    // Target speed is the map value 1.5; the stored speed is the mean of prior and target,
    // so the gap halves every step.
    let mut expected = 0.0;
    for _ in 0..12 {
        s = step(&cfg, &s, &inputs, 0.1, None).0;
        expected = (expected + 1.5) / 2.0;
        assert!(
            close(s.speed_mps, expected, 1e-12),
            "{} vs {}",
            s.speed_mps,
            expected
        );
    }
    assert!(close(s.speed_mps, 1.5, 1e-3));
}

#[test]
fn turn_rate_follows_rudder_speed_and_thrust() {
    let cfg = SimConfig::from_params([("turn_spd_loss", "0"), ("max_deceleration", "0")]).unwrap();
    // Half of full speed (5 m/s): rate = 70 * 0.5 = 35; thrust 50 -> factor 1.
    let s0 = SimState {
        speed_mps: 2.5,
        heading_deg: 10.0,
        ..SimState::default()
    };
    let inp = SimInputs {
        thrust: 50.0,
        rudder_deg: 20.0,
        ..SimInputs::default()
    };
    let s1 = step(&cfg, &s0, &inp, 0.1, None).0;
    assert!(
        close(s1.heading_deg, 10.0 + 20.0 * 0.35 * 0.1, 1e-9),
        "{}",
        s1.heading_deg
    );
    // Full speed and thrust 100 (factor 2): 20 * 0.70 * 0.1 * 2.
    let s0 = SimState {
        speed_mps: 5.0,
        heading_deg: 10.0,
        ..SimState::default()
    };
    let inp = SimInputs {
        thrust: 100.0,
        rudder_deg: -20.0,
        ..SimInputs::default()
    };
    let s1 = step(&cfg, &s0, &inp, 0.1, None).0;
    assert!(
        close(s1.heading_deg, 10.0 - 2.8, 1e-9),
        "{}",
        s1.heading_deg
    );
    // Legacy model: no speed scaling of the rate.
    let legacy = SimConfig {
        turn_spd_loss: 0.0,
        max_deceleration_mps2: 0.0,
        ..SimConfig::legacy()
    };
    let s0 = SimState {
        speed_mps: 2.5,
        heading_deg: 10.0,
        ..SimState::default()
    };
    let inp = SimInputs {
        thrust: 50.0,
        rudder_deg: 20.0,
        ..SimInputs::default()
    };
    let s1 = step(&legacy, &s0, &inp, 0.1, None).0;
    assert!(close(s1.heading_deg, 10.0 + 20.0 * 0.70 * 0.1, 1e-9));
    // No turning at zero speed.
    let s0 = SimState {
        heading_deg: 10.0,
        ..SimState::default()
    };
    let s1 = step(
        &cfg,
        &s0,
        &SimInputs {
            rudder_deg: 100.0,
            ..SimInputs::default()
        },
        1.0,
        None,
    )
    .0;
    assert_eq!(s1.heading_deg, 10.0);
}

#[test]
fn turn_speed_loss_slows_the_vehicle() {
    let cfg = SimConfig::from_params([("max_deceleration", "0")]).unwrap();
    let s0 = SimState {
        speed_mps: 2.0,
        ..SimState::default()
    };
    let inp = SimInputs {
        thrust: 40.0,
        rudder_deg: 50.0,
        ..SimInputs::default()
    };
    let s1 = step(&cfg, &s0, &inp, 0.1, None).0;
    let target = 2.0 * (1.0 - 0.5 * 0.85);
    assert!(close(s1.speed_mps, (2.0 + target) / 2.0, 1e-9));
}

#[test]
fn deceleration_is_limited() {
    let cfg = SimConfig::default(); // max_deceleration 0.5
    let mut s = SimState {
        speed_mps: 3.0,
        ..SimState::default()
    };
    let inp = SimInputs::default(); // thrust 0 -> target 0
    for i in 1..=8 {
        let prev = s.speed_mps;
        s = step(&cfg, &s, &inp, 0.25, None).0;
        // Target limited to prev - 0.5*dt, stored speed is the mean with prev.
        let target = prev - 0.5 * 0.25;
        assert!(close(s.speed_mps, (prev + target) / 2.0, 1e-12), "step {i}");
    }
    assert!(close(s.speed_mps, 3.0 - 8.0 * 0.0625, 1e-9));
    // Acceleration limit likewise.
    let cfg = SimConfig::from_params([("max_acceleration", "0.2")]).unwrap();
    let s = step(
        &cfg,
        &SimState::default(),
        &SimInputs {
            thrust: 100.0,
            ..SimInputs::default()
        },
        1.0,
        None,
    )
    .0;
    assert!(close(s.speed_mps, 0.1, 1e-12));
}

#[test]
fn buoyancy_rises_at_zero_speed() {
    let cfg =
        SimConfig::from_params([("start_pos", "x=0,y=0,heading=0,speed=0,depth=10")]).unwrap();
    let mut s = SimState::at(&cfg.start);
    let inp = SimInputs {
        elevator_deg: 100.0,
        ..SimInputs::from_config(&cfg)
    };
    for _ in 0..100 {
        s = step(&cfg, &s, &inp, 0.1, None).0;
    }
    assert!(close(s.depth, 10.0 - 0.025 * 10.0, 1e-9), "{}", s.depth);
    assert_eq!(s.pitch_rad, 0.0);
    // Floored at the surface.
    let top = SimState {
        depth: 0.01,
        ..SimState::default()
    };
    assert_eq!(step(&cfg, &top, &inp, 1.0, None).0.depth, 0.0);
}

#[test]
fn dive_rate_follows_elevator_and_speed() {
    let cfg = SimConfig::from_params([("buoyancy_rate", "0"), ("max_deceleration", "0")]).unwrap();
    for (speed, elevator) in [(1.0, 50.0), (2.0, 50.0), (3.0, -40.0), (0.5, 100.0)] {
        // Thrust that holds the speed (thrust_factor 20).
        let inp = SimInputs {
            thrust: speed * 20.0,
            elevator_deg: elevator,
            ..SimInputs::default()
        };
        let s0 = SimState {
            speed_mps: speed,
            depth: 5.0,
            ..SimState::default()
        };
        let pct = (speed / 2.0f64).min(1.0).sqrt();
        let act = elevator / 100.0 * pct * 0.5;
        let s1 = step(&cfg, &s0, &inp, 0.1, None).0;
        assert!(
            close(s1.depth, 5.0 + act * 0.1, 1e-12),
            "v={speed} e={elevator}"
        );
        assert!(close(s1.pitch_rad, -(act / speed).asin(), 1e-12));
        // Next step adds the pitch-induced rate -sin(pitch)*v.
        let s2 = step(&cfg, &s1, &inp, 0.1, None).0;
        let rate2 = -s1.pitch_rad.sin() * speed + act;
        assert!(close(s2.depth, s1.depth + rate2 * 0.1, 1e-12));
    }
}

#[test]
fn pitch_integrates_the_elevator_per_iteration_not_per_second() {
    // As in the C++ SimEngine: the new pitch is -asin((-sin(pitch)*v + actuator)/v) with no dt,
    // so one iteration's elevator moves the pitch by the same amount whatever dt is.
    let cfg = SimConfig::from_params([("max_depth_rate", "5"), ("max_deceleration", "0")]).unwrap();
    let inp = SimInputs {
        thrust: 40.0,
        elevator_deg: 13.0,
        ..SimInputs::default()
    };
    let s0 = SimState {
        speed_mps: 2.0,
        ..SimState::default()
    };
    let act = 0.13 * 5.0;
    for dt in [0.01, 0.1, 1.0] {
        let s1 = step(&cfg, &s0, &inp, dt, None).0;
        assert!(
            close(s1.pitch_rad, -(act / 2.0f64).asin(), 1e-12),
            "dt {dt}"
        );
        let s2 = step(&cfg, &s1, &inp, dt, None).0;
        assert!(
            close(s2.pitch_rad.sin(), -2.0 * act / 2.0, 1e-12),
            "dt {dt}"
        );
        // Past |rate| > speed the pitch falls back to 0 (the C++ guard on asin).
        let s3 = step(&cfg, &s2, &inp, dt, None).0;
        let s4 = step(&cfg, &s3, &inp, dt, None).0;
        assert!(
            s3.pitch_rad < s2.pitch_rad && s4.pitch_rad == 0.0,
            "dt {dt}"
        );
    }
}

#[test]
fn heading_wraps_at_0_and_360() {
    let cfg = SimConfig::from_params([("turn_spd_loss", "0"), ("max_deceleration", "0")]).unwrap();
    let s0 = SimState {
        speed_mps: 5.0,
        heading_deg: 359.0,
        ..SimState::default()
    };
    let s1 = step(
        &cfg,
        &s0,
        &SimInputs {
            thrust: 100.0,
            rudder_deg: 50.0,
            ..SimInputs::default()
        },
        0.1,
        None,
    )
    .0;
    assert!(
        close(s1.heading_deg, 359.0 + 7.0 - 360.0, 1e-9),
        "{}",
        s1.heading_deg
    );
    assert!(close(s1.yaw_rad, -(6.0f64).to_radians(), 1e-12));
    let s0 = SimState {
        speed_mps: 5.0,
        heading_deg: 1.0,
        ..SimState::default()
    };
    let s1 = step(
        &cfg,
        &s0,
        &SimInputs {
            thrust: 100.0,
            rudder_deg: -50.0,
            ..SimInputs::default()
        },
        0.1,
        None,
    )
    .0;
    assert!(close(s1.heading_deg, 354.0, 1e-9));
    assert!(close(s1.yaw_rad, (6.0f64).to_radians(), 1e-12));
    // Moving north across the wrap: position uses the circular mean heading (~0), not 180.
    assert!(s1.y > 0.0 && s1.x < 0.0);
}

#[test]
fn drift_moves_a_stopped_vehicle() {
    let cfg = SimConfig::from_params([("drift_x", "0.5"), ("drift_y", "-0.2")]).unwrap();
    let mut s = SimState::default();
    let inp = SimInputs::from_config(&cfg);
    for _ in 0..20 {
        s = step(&cfg, &s, &inp, 0.5, None).0;
    }
    assert!(close(s.x, 5.0, 1e-9) && close(s.y, -2.0, 1e-9));
    assert!(close(s.speed_og_mps, 0.5f64.hypot(0.2), 1e-12));
    assert!(close(
        s.heading_og_deg,
        0.5f64.atan2(-0.2).to_degrees(),
        1e-9
    ));
    assert_eq!(s.speed_mps, 0.0);
    // drift_vector = angle,magnitude (compass).
    let cfg = SimConfig::from_params([("drift_vector", "90,2")]).unwrap();
    assert!(close(cfg.drift_x_mps, 2.0, 1e-12) && close(cfg.drift_y_mps, 0.0, 1e-12));
}

#[test]
fn straight_line_position() {
    let cfg = SimConfig::from_params([("start_pos", "x=0,y=-20,heading=90,speed=2")]).unwrap();
    let mut s = SimState::at(&cfg.start);
    let inp = SimInputs {
        thrust: 40.0,
        ..SimInputs::from_config(&cfg)
    };
    for _ in 0..10 {
        s = step(&cfg, &s, &inp, 1.0, None).0;
    }
    assert!(close(s.x, 20.0, 1e-9) && close(s.y, -20.0, 1e-9));
}

#[test]
fn adapter_posts_prefixed_nav_every_second_iteration() {
    let cfg = SimConfig::from_params([("PREFIX", "NAV"), ("default_water_depth", "50")]).unwrap();
    let grid = vehicle::geodesy::LocalGrid::new(43.8253, -70.3304).unwrap();
    let mut sim = Simulator::new(cfg, Some(grid), 100.0);
    sim.on_mail("DESIRED_THRUST", ValueRef::Double(40.0), 100.0);
    sim.on_mail("DESIRED_ELEVATOR", ValueRef::Double(10.0), 100.0);
    let mut out = Vec::new();
    sim.iterate(100.1, &mut out);
    assert!(
        last_posting(&out, "NAV_X").is_none(),
        "first iteration does not publish nav"
    );
    assert!(last_posting(&out, "USM_DRIFT_SUMMARY").is_some());
    out.clear();
    sim.iterate(100.2, &mut out);
    for var in [
        "NAV_X",
        "NAV_Y",
        "NAV_LAT",
        "NAV_LONG",
        "NAV_HEADING",
        "NAV_SPEED",
        "NAV_DEPTH",
        "NAV_Z",
        "NAV_PITCH",
        "NAV_YAW",
        "NAV_HEADING_OVER_GROUND",
        "NAV_SPEED_OVER_GROUND",
        "NAV_ALTITUDE",
        "TRUE_X",
        "TRUE_Y",
        "SIMULATION_MODE",
    ] {
        assert!(last_posting(&out, var).is_some(), "missing {var}");
    }
    let lat = last_posting(&out, "NAV_LAT").unwrap().as_f64().unwrap();
    assert!(close(lat, 43.8253, 1e-4));
    let spd = last_posting(&out, "NAV_SPEED").unwrap().as_f64().unwrap();
    assert!(
        close(spd, (spd * 100.0).round() / 100.0, 1e-12),
        "snapped to 0.01"
    );
    // An obstacle hit stops the vehicle where it is.
    out.clear();
    sim.on_mail("OBSTACLE_HIT", ValueRef::String("true"), 100.25);
    let (x, y) = (sim.state().x, sim.state().y);
    sim.iterate(100.3, &mut out);
    sim.iterate(100.4, &mut out);
    assert_eq!(last_posting(&out, "NAV_SPEED").unwrap().as_f64(), Some(0.0));
    assert_eq!((sim.state().x, sim.state().y), (x, y));
    sim.on_mail("OBSTACLE_HIT", ValueRef::String("false"), 100.45);
    // Reset through USM_RESET.
    let p = sim
        .on_mail("USM_RESET", ValueRef::String("x=5,y=6,heading=45"), 100.3)
        .unwrap();
    assert_eq!(p.value.as_f64(), Some(1.0));
    assert_eq!(
        (sim.state().x, sim.state().y, sim.state().heading_deg),
        (5.0, 6.0, 45.0)
    );
}

#[test]
fn legacy_adapter_posts_nav_every_iteration() {
    // uSimMarine (legacy) posts on every Iterate; uSimMarineV22 on every second one.
    for (legacy, expected) in [
        (true, [true, true, true, true]),
        (false, [false, true, false, true]),
    ] {
        let cfg = SimConfig {
            legacy,
            ..SimConfig::from_params([("prefix", "NAV")]).unwrap()
        };
        assert_eq!(cfg.nav_every(), if legacy { 1 } else { 2 });
        let mut sim = Simulator::new(cfg, None, 0.0);
        sim.on_mail("DESIRED_THRUST", ValueRef::Double(40.0), 0.0);
        for (i, want) in expected.into_iter().enumerate() {
            let mut out = Vec::new();
            sim.iterate(0.1 * (i + 1) as f64, &mut out);
            assert_eq!(
                last_posting(&out, "NAV_PITCH").is_some(),
                want,
                "legacy {legacy}, iteration {}",
                i + 1
            );
        }
    }
}

#[test]
fn config_errors_are_typed() {
    assert!(matches!(
        SimConfig::from_params([("turn_rate", "fast")]),
        Err(ConfigError::BadValue { key, .. }) if key == "turn_rate"
    ));
    assert!(matches!(
        SimConfig::from_params([("no_such_key", "1")]),
        Err(ConfigError::UnknownKey { .. })
    ));
    assert!(SimConfig::from_params([("thrust_map", "0:0, 50:3, 60:2")]).is_err());
    assert!(SimConfig::from_params([("turn_spd_loss", "1.5")]).is_err());
    let mut p = StartPose::default();
    p.apply_spec("5,10,180,2.0,3").unwrap();
    assert_eq!(
        (p.x, p.y, p.heading_deg, p.speed_mps, p.depth),
        (5.0, 10.0, 180.0, 2.0, 3.0)
    );
}

#[test]
fn reads_a_real_mission_block() {
    let text = test_support::mission_text("s7_golf/golf.moos");
    let block = common::process_config(&text, "uSimMarine");
    let (cfg, unknown) = SimConfig::from_params_lenient(common::pairs(&block)).unwrap();
    assert_eq!(cfg.prefix, "NAV");
    assert_eq!(cfg.start.heading_deg, 180.0);
    // FLOAT_RATE is not a uSimMarineV22 parameter: reported, not fatal.
    assert_eq!(unknown.len(), 1);
    assert!(matches!(&unknown[0], ConfigError::UnknownKey { key, .. } if key == "FLOAT_RATE"));
}

#[test]
fn turn_radius_limits_heading_change() {
    let base = SimConfig::from_params([("turn_spd_loss", "0"), ("max_deceleration", "0")]).unwrap();
    let limited = SimConfig {
        turn_radius: 10.0,
        ..base.clone()
    };
    let s0 = SimState {
        speed_mps: 5.0,
        heading_deg: 0.0,
        ..SimState::default()
    };
    let inp = SimInputs {
        thrust: 100.0,
        rudder_deg: 100.0,
        ..SimInputs::default()
    };
    let free = step(&base, &s0, &inp, 0.5, None).0;
    let lim = step(&limited, &s0, &inp, 0.5, None).0;
    assert!(
        free.heading_deg > 60.0,
        "unlimited turn {}",
        free.heading_deg
    );
    // Chord of 2.5 m on a 10 m circle at full speed: heading change 2*asin(2.5/20).
    let dist = (lim.x - s0.x).hypot(lim.y - s0.y);
    let phi = (dist / 20.0).asin().to_degrees();
    assert!(
        close(lim.heading_deg, 2.0 * phi, 1e-9),
        "{} vs {}",
        lim.heading_deg,
        2.0 * phi
    );
    assert!(lim.heading_deg < free.heading_deg);
}

#[test]
fn reverse_and_differential_thrust() {
    // uSimMarineV22 applies thrust_mode_reverse but never marks the line handled: a warning.
    let (rev, warnings) = SimConfig::from_params_lenient([
        ("thrust_mode_reverse", "true"),
        ("max_deceleration", "0"),
        ("thrust_reflect", "true"),
    ])
    .unwrap();
    assert!(rev.thrust_mode_reverse);
    assert_eq!(warnings.len(), 1, "{warnings:?}");
    assert!(warnings[0].to_string().contains("thrust_mode_reverse"));
    let s0 = SimState {
        heading_deg: 0.0,
        ..SimState::default()
    };
    let s1 = step(
        &rev,
        &s0,
        &SimInputs {
            thrust: -40.0,
            ..SimInputs::default()
        },
        1.0,
        None,
    )
    .0;
    // Negative thrust reversed is forward thrust of the reversed hull, which faces 180.
    assert_eq!(s1.heading_deg, 180.0);
    assert!(s1.speed_mps > 0.0);
    let diff = SimConfig::from_params([
        ("thrust_mode_diff", "differential"),
        ("max_deceleration", "0"),
    ])
    .unwrap();
    let s0 = SimState {
        heading_deg: 90.0,
        speed_mps: 2.0,
        ..SimState::default()
    };
    let inp = SimInputs {
        thrust_left: 60.0,
        thrust_right: 20.0,
        ..SimInputs::default()
    };
    let s1 = step(&diff, &s0, &inp, 0.5, None).0;
    // Turn: 36 deg/s at full differential, here (60-20)/200 of it.
    assert!(close(s1.heading_deg, 90.0 + 36.0 * 0.2 * 0.5, 1e-9));
    // Speed from the mean thrust 40 with the pseudo-rudder (60-20)/2 = 20 speed loss.
    let target = 2.0 * (1.0 - 0.2 * 0.85);
    assert!(close(s1.speed_mps, (2.0 + target) / 2.0, 1e-9));
}

proptest::proptest! {
    #[test]
    fn state_stays_well_formed(
        thrust in -100.0f64..100.0, rudder in -150.0f64..150.0, elevator in -150.0f64..150.0,
        heading in -720.0f64..720.0, speed in 0.0f64..5.0, depth in 0.0f64..50.0, dt in 0.01f64..2.0,
    ) {
        let cfg = SimConfig::default();
        let mut s = SimState::at(&StartPose { heading_deg: heading, speed_mps: speed, depth, ..StartPose::default() });
        let inp = SimInputs { thrust, rudder_deg: rudder, elevator_deg: elevator, ..SimInputs::from_config(&cfg) };
        for _ in 0..20 {
            let (n, out) = step(&cfg, &s, &inp, dt, None);
            s = n;
            proptest::prop_assert!((0.0..360.0).contains(&s.heading_deg));
            proptest::prop_assert!(s.depth >= 0.0 && s.depth.is_finite());
            proptest::prop_assert!(s.x.is_finite() && s.y.is_finite() && s.pitch_rad.is_finite());
            proptest::prop_assert!(out.speed_mps <= cfg.max_speed_mps);
        }
    }
}

#[test]
fn embedded_pid_drives_the_model_from_the_helm_outputs() {
    // uSimMarineV22 with PID gains in its block runs the PID itself (no pMarinePIDV22).
    let params = [
        ("start_pos", "x=0,y=0,heading=0,speed=0"),
        ("turn_rate", "70"),
        ("yaw_pid_kp", "1.2"),
        ("yaw_pid_kd", "0"),
        ("yaw_pid_ki", "0"),
        ("yaw_pid_integral_limit", "0.07"),
        ("maxrudder", "100"),
        ("speed_pid_kp", "1"),
        ("speed_pid_kd", "0"),
        ("speed_pid_ki", "0"),
        ("speed_pid_integral_limit", "0.07"),
        ("maxthrust", "100"),
        ("speed_factor", "20"),
        ("depth_control", "false"),
        ("post_des_thrust", "SIM_THRUST"),
    ];
    let (cfg, warnings) = SimConfig::from_params_lenient(params).unwrap();
    assert!(warnings.is_empty(), "{warnings:?}");
    let pid = cfg.pid.as_ref().expect("embedded PID");
    assert_eq!(pid.speed_factor, 20.0);
    let mut sim = Simulator::new(cfg, None, 0.0);
    let subs = sim.subscriptions();
    assert!(subs.contains(&"DESIRED_HEADING") && subs.contains(&"MOOS_MANUAL_OVERRIDE"));
    assert!(!subs.contains(&"DESIRED_RUDDER") && !subs.contains(&"DESIRED_THRUST"));
    sim.on_mail("MOOS_MANUAL_OVERRIDE", ValueRef::String("false"), 0.0);
    let mut out = Vec::new();
    let mut t = 0.0;
    while t < 60.0 {
        t += 0.1;
        sim.on_mail("DESIRED_HEADING", ValueRef::Double(90.0), t);
        sim.on_mail("DESIRED_SPEED", ValueRef::Double(2.0), t);
        out.clear();
        sim.iterate(t, &mut out);
    }
    // Thrust 2 m/s x 20 = 40 (posted as asked), heading brought round to 90.
    assert_eq!(
        last_posting(&out, "SIM_THRUST").unwrap().as_f64(),
        Some(40.0)
    );
    assert!(
        close(sim.state().heading_deg, 90.0, 2.0),
        "{}",
        sim.state().heading_deg
    );
    assert!(
        close(sim.state().speed_mps, 2.0, 0.1),
        "{}",
        sim.state().speed_mps
    );
    // Without yaw gains the PID keys are taken but no PID is embedded.
    let (cfg, w) = SimConfig::from_params_lenient([("speed_factor", "20")]).unwrap();
    assert!(cfg.pid.is_none() && w.is_empty(), "{w:?}");
    // Without the embedded PID, post_des_thrust is not posted (the C++ posts it only from
    // the embedded PID).
    let mut plain = Simulator::new(
        SimConfig::from_params([("post_des_thrust", "SIM_THRUST")]).unwrap(),
        None,
        0.0,
    );
    let mut out = Vec::new();
    plain.on_mail("DESIRED_THRUST", ValueRef::Double(30.0), 0.0);
    plain.iterate(0.1, &mut out);
    assert!(last_posting(&out, "SIM_THRUST").is_none(), "{out:?}");
}

#[test]
fn rudder_slew_limit_caps_the_rudder_change_per_second() {
    let cfg = SimConfig::from_params([("max_rudder_degs_per_sec", "10")]).unwrap();
    let mut sim = Simulator::new(cfg, None, 0.0);
    sim.on_mail("DESIRED_RUDDER", ValueRef::Double(40.0), 0.5);
    assert_eq!(sim.inputs().rudder_deg, 5.0, "10 deg/s for 0.5 s");
    sim.on_mail("DESIRED_RUDDER", ValueRef::Double(40.0), 1.5);
    assert_eq!(sim.inputs().rudder_deg, 15.0);
    sim.on_mail("DESIRED_RUDDER", ValueRef::Double(-40.0), 2.0);
    assert_eq!(sim.inputs().rudder_deg, 10.0);
    // No limit set: one change is still capped at 100 degrees (uSimMarineV22).
    let mut sim = Simulator::new(SimConfig::default(), None, 0.0);
    sim.on_mail("DESIRED_RUDDER", ValueRef::Double(-100.0), 1.0);
    sim.on_mail("DESIRED_RUDDER", ValueRef::Double(100.0), 1.1);
    assert_eq!(sim.inputs().rudder_deg, 0.0);
}

#[test]
fn dual_state_posts_the_drifting_ground_truth_beside_the_drift_free_nav() {
    let cfg = SimConfig::from_params([("prefix", "NAV"), ("dual_state", "true"), ("drift_x", "1")])
        .unwrap();
    assert!(cfg.dual_state);
    let mut sim = Simulator::new(cfg, None, 0.0);
    let mut out = Vec::new();
    let mut t = 0.0;
    for _ in 0..100 {
        t += 0.1;
        out.clear();
        sim.iterate(t, &mut out);
        if !out.iter().any(|p| &*p.key == "NAV_X") {
            out.clear();
            t += 0.1;
            sim.iterate(t, &mut out);
        }
    }
    // No thrust: the navigation stays put, the ground truth drifts 1 m/s east.
    let x = last_posting(&out, "NAV_X").unwrap().as_f64().unwrap();
    let gx = last_posting(&out, "NAV_GT_X").unwrap().as_f64().unwrap();
    assert_eq!(x, 0.0);
    assert!(close(gx, t, 0.05), "ground truth {gx} after {t} s");
    assert!(last_posting(&out, "NAV_GT_HEADING").is_some());
    // USM_RESET moves both.
    sim.on_mail("USM_RESET", ValueRef::String("x=5,y=6"), t);
    out.clear();
    sim.iterate(t + 0.1, &mut out);
    sim.iterate(t + 0.2, &mut out);
    assert!(close(
        last_posting(&out, "NAV_GT_X").unwrap().as_f64().unwrap(),
        5.2,
        0.05
    ));
    assert_eq!(last_posting(&out, "NAV_X").unwrap().as_f64(), Some(5.0));
}

#[test]
fn wind_and_polar_plot_cap_the_speed_and_wind_conditions_change_at_run_time() {
    let cfg = SimConfig::from_params([
        ("prefix", "NAV"),
        ("start_pos", "x=0,y=0,heading=90,speed=0"),
        ("wind_conditions", "spd=2, dir=0"),
        ("polar_plot", "0,0:90,100:180,50"),
    ])
    .unwrap();
    assert!(SimConfig::from_params([("polar_plot", "0,0:200,10")]).is_err());
    assert!(SimConfig::from_params([("wind_conditions", "gust=4")]).is_err());
    let mut sim = Simulator::new(cfg, None, 0.0);
    sim.on_mail("DESIRED_THRUST", ValueRef::Double(100.0), 0.0);
    let run = |sim: &mut Simulator, t: &mut f64, secs: f64| {
        let mut out = Vec::new();
        for _ in 0..(secs * 10.0) as usize {
            *t += 0.1;
            sim.iterate(*t, &mut out);
        }
    };
    let mut t = 0.0;
    // Beam reach (90 deg off a wind from the north): 100 % of 2 m/s, though the thrust map
    // alone would give 5 m/s.
    run(&mut sim, &mut t, 5.0);
    assert!(
        close(sim.state().speed_mps, 2.0, 1e-9),
        "{}",
        sim.state().speed_mps
    );
    // The wind drops to 1 m/s from the east: on heading 90 we head straight into it, where
    // the polar gives 0 and (as the C++, which caps only above 0) the speed is not capped.
    sim.on_mail("WIND_CONDITIONS", ValueRef::String("spd=1,dir=90"), t);
    run(&mut sim, &mut t, 5.0);
    assert!(
        close(sim.state().speed_mps, 5.0, 1e-9),
        "{}",
        sim.state().speed_mps
    );
}

/// Iterates `sim` at `t0 + 1`, `t0 + 2`, ... `t0 + n` seconds, collecting every posting.
fn run_secs(sim: &mut Simulator, t0: f64, n: u32) -> Vec<vehicle::moos::Posting> {
    let mut out = Vec::new();
    for i in 1..=n {
        sim.iterate(t0 + f64::from(i), &mut out);
    }
    out
}

fn all_of(out: &[vehicle::moos::Posting], var: &str) -> Vec<vehicle::Value> {
    out.iter()
        .filter(|p| &*p.key == var)
        .map(|p| p.value.clone())
        .collect()
}

#[test]
fn usm_reset_counts_start_pos_lines_and_sets_only_the_given_fields() {
    // `initPosition` counts every call, the start_pos line included: the first USM_RESET
    // posts 2. Fields not given keep their values.
    let cfg = SimConfig::from_params([
        ("prefix", "NAV"),
        ("start_pos", "x=1,y=2,heading=30,speed=0"),
    ])
    .unwrap();
    assert_eq!(cfg.start_pos_count, 1);
    let mut sim = Simulator::new(cfg, None, 0.0);
    let p = sim
        .on_mail("USM_RESET", ValueRef::String("x=5, y=6"), 0.0)
        .unwrap();
    assert_eq!((&*p.key, p.value.as_f64()), ("USM_RESET_COUNT", Some(2.0)));
    let st = sim.state();
    assert_eq!((st.x, st.y, st.heading_deg), (5.0, 6.0, 30.0));
    // The older positional form x,y,heading,speed,depth.
    sim.on_mail("USM_RESET", ValueRef::String("7,8,90"), 0.0);
    assert_eq!(
        (sim.state().x, sim.state().y, sim.state().heading_deg),
        (7.0, 8.0, 90.0)
    );
    // `hdg` and `dep` aliases; an unknown field stops there (the fields before it stay
    // applied) and the reset is still counted.
    let p = sim
        .on_mail(
            "USM_RESET",
            ValueRef::String("hdg=180,x=-3,foo=1,y=99"),
            0.0,
        )
        .unwrap();
    assert_eq!(p.value.as_f64(), Some(4.0));
    assert_eq!(
        (sim.state().x, sim.state().y, sim.state().heading_deg),
        (-3.0, 8.0, 180.0)
    );
    // Values are read with atof: a non-number is 0.
    sim.on_mail("USM_RESET", ValueRef::String("x=abc"), 0.0);
    assert_eq!(sim.state().x, 0.0);
    assert_eq!(sim.reset_count(), 5);
    // Without start_pos the first reset is 1.
    let mut plain = Simulator::new(SimConfig::default(), None, 0.0);
    let p = plain
        .on_mail("USM_RESET", ValueRef::String("x=1"), 0.0)
        .unwrap();
    assert_eq!(p.value.as_f64(), Some(1.0));
    // A start_pos with a bad field is a warning; its count still grows.
    let (cfg, w) = SimConfig::from_params_lenient([("start_pos", "x=4,z=1")]).unwrap();
    assert_eq!((cfg.start.x, cfg.start_pos_count, w.len()), (4.0, 1, 1));
}

#[test]
fn paused_sim_posts_its_record_and_excludes_the_paused_time() {
    let cfg = SimConfig::from_params([("prefix", "NAV"), ("sim_pause", "true")]).unwrap();
    let mut sim = Simulator::new(cfg, None, 0.0);
    sim.on_mail("DESIRED_THRUST", ValueRef::Double(40.0), 0.0);
    // Paused: the navigation is still posted every second iteration, and it does not move.
    let out = run_secs(&mut sim, 0.0, 4);
    assert_eq!(all_of(&out, "NAV_SPEED").len(), 2);
    assert_eq!(last_posting(&out, "NAV_SPEED").unwrap().as_f64(), Some(0.0));
    sim.on_mail("USM_SIM_PAUSED", ValueRef::String("false"), 4.0);
    // One second after the pause ends: thrust 40 / factor 20 = 2 m/s, mean speed 1 m/s over
    // 1 s, not over the 5 s since start.
    let mut out = Vec::new();
    sim.iterate(5.0, &mut out);
    assert_eq!(sim.state().speed_mps, 1.0);
    assert_eq!(sim.state().y, 1.0);
}

#[test]
fn drift_summary_is_posted_at_start_and_on_each_new_drift_source() {
    let mut sim = Simulator::new(SimConfig::default(), None, 0.0);
    let out = run_secs(&mut sim, 0.0, 1);
    assert_eq!(
        all_of(&out, "USM_DRIFT_SUMMARY"),
        vec![vehicle::Value::String(
            "ang=0, mag=0, xmag=0, ymag=0".into()
        )]
    );
    sim.on_mail_from("DRIFT_X", ValueRef::Double(3.0), 1.0, "uTimerScript");
    sim.on_mail_from("DRIFT_Y", ValueRef::Double(4.0), 1.0, "uTimerScript");
    let out = run_secs(&mut sim, 1.0, 1);
    // relAng(0,0,3,4) = 36.87 deg, magnitude 5.
    assert_eq!(
        all_of(&out, "USM_DRIFT_SUMMARY"),
        vec![vehicle::Value::String(
            "ang=36.87, mag=5, xmag=3, ymag=4".into()
        )]
    );
    // The same source again: the drift changes, no new summary.
    sim.on_mail_from(
        "DRIFT_VECTOR",
        ValueRef::String("90,2"),
        2.0,
        "uTimerScript",
    );
    let out = run_secs(&mut sim, 2.0, 1);
    assert!(all_of(&out, "USM_DRIFT_SUMMARY").is_empty());
    assert!(close(sim.inputs().drift_x_mps, 2.0, 1e-12));
    // A new source: a summary; DRIFT_VECTOR_MULT scales the vector.
    sim.on_mail_from("DRIFT_VECTOR_MULT", ValueRef::Double(1.5), 3.0, "pOther");
    let out = run_secs(&mut sim, 3.0, 1);
    assert_eq!(
        all_of(&out, "USM_DRIFT_SUMMARY"),
        vec![vehicle::Value::String(
            "ang=90, mag=3, xmag=3, ymag=0".into()
        )]
    );
    // Mail without a source (start-up rule) never re-posts it.
    sim.on_mail("DRIFT_X", ValueRef::Double(1.0), 4.0);
    assert!(all_of(&run_secs(&mut sim, 4.0, 1), "USM_DRIFT_SUMMARY").is_empty());
}

#[test]
fn usm_reset_nav_moves_the_nav_record_to_the_ground_truth() {
    let cfg = SimConfig::from_params([("prefix", "NAV"), ("dual_state", "true"), ("drift_x", "1")])
        .unwrap();
    let mut sim = Simulator::new(cfg, None, 0.0);
    assert!(sim.subscriptions().contains(&"USM_RESET_NAV"));
    let out = run_secs(&mut sim, 0.0, 4);
    // Nav without drift stays at 0; ground truth drifts 1 m/s east for 4 s.
    assert_eq!(last_posting(&out, "NAV_X").unwrap().as_f64(), Some(0.0));
    assert_eq!(last_posting(&out, "NAV_GT_X").unwrap().as_f64(), Some(4.0));
    sim.on_mail("USM_RESET_NAV", ValueRef::String("true"), 4.0);
    assert_eq!(sim.state().x, 4.0);
    let out = run_secs(&mut sim, 4.0, 2);
    assert_eq!(last_posting(&out, "NAV_X").unwrap().as_f64(), Some(4.0));
    assert_eq!(last_posting(&out, "NAV_GT_X").unwrap().as_f64(), Some(6.0));
    // Without dual_state the ground truth is not propagated: USM_RESET_NAV goes back to it.
    let mut single = Simulator::new(
        SimConfig::from_params([("drift_x", "1"), ("start_pos", "x=2,y=3")]).unwrap(),
        None,
        0.0,
    );
    run_secs(&mut single, 0.0, 3);
    assert_eq!(single.state().x, 5.0);
    single.on_mail("USM_RESET_NAV", ValueRef::String("true"), 3.0);
    assert_eq!((single.state().x, single.state().y), (2.0, 3.0));
}

const WORM: &str =
    "tag=One, madrid_poly={0,0:10,0:10,10:0,10}, weber_poly=pts={100,0:110,0:110,10:100,10}";

#[test]
fn wormholes_fade_carry_and_emerge() {
    let cfg = SimConfig::from_params([
        ("prefix", "NAV"),
        ("start_pos", "x=5,y=5"),
        ("wormhole", WORM),
    ])
    .unwrap();
    let holes = cfg.wormholes.holes();
    assert_eq!(holes.len(), 1);
    assert_eq!(holes[0].tag, "one");
    let mut sim = Simulator::new(cfg, None, 0.0);
    let out = run_secs(&mut sim, 0.0, 12);
    // Entered at t=1 (half the 10 s tunnel to fade), carried at t=6, emerged after t=11.
    let transp: Vec<f64> = all_of(&out, "NAV_TRANSP")
        .iter()
        .map(|v| v.as_f64().unwrap())
        .collect();
    let want = [1.0, 0.8, 0.6, 0.4, 0.2, 0.0, 0.2, 0.4, 0.6, 0.8, 1.0, 1.0];
    assert_eq!(transp.len(), want.len());
    for (got, want) in transp.iter().zip(want) {
        assert!(close(*got, want, 1e-12), "{transp:?}");
    }
    // Same offset from the weber centroid (105,5) as from the madrid one (5,5); posted from
    // the next navigation report (the C++ moves the vehicle after posting).
    let xs: Vec<f64> = all_of(&out, "NAV_X")
        .iter()
        .map(|v| v.as_f64().unwrap())
        .collect();
    assert_eq!(xs, vec![5.0, 5.0, 5.0, 105.0, 105.0, 105.0]);
    // The polygons every 10th iteration: weber first.
    assert_eq!(
        all_of(&out, "VIEW_POLYGON"),
        vec![
            vehicle::Value::String("pts={100,0:110,0:110,10:100,10},label=one_weber,label_color=invisible,edge_color=invisible,vertex_color=invisible,fill_color=white,fill_transparency=0.1".into()),
            vehicle::Value::String("pts={0,0:10,0:10,10:0,10},label=one_madrid,label_color=invisible,edge_color=invisible,vertex_color=invisible,fill_color=white,fill_transparency=0.1".into()),
        ]
    );
}

#[test]
fn wormhole_config_is_checked_as_the_cpp_does() {
    let bad = |spec: &str| {
        let (cfg, w) = SimConfig::from_params_lenient([("wormhole", spec)]).unwrap();
        assert_eq!(w.len(), 1, "{spec}: {w:?}");
        assert!(matches!(w[0], ConfigError::BadValue { .. }), "{spec}");
        cfg
    };
    bad("madrid_poly={0,0:10,0:10,10}");
    bad("tag=a, connection=sideways");
    bad("tag=a, delay=-1");
    bad("tag=a, id_change=maybe");
    bad("tag=a, colour=red");
    // A non-convex polygon; the tag is still registered (as the C++), without polygons.
    let cfg = bad("tag=z, madrid_poly={0,0:10,0:5,2:10,10:0,10}");
    assert_eq!(cfg.wormholes.holes().len(), 1);
    assert!(cfg.wormholes.holes()[0].madrid.is_none());
    // `connection = both` is accepted and never carries a vehicle.
    let cfg = SimConfig::from_params([
        ("start_pos", "x=5,y=5"),
        (
            "wormhole",
            &format!("{WORM}, connection=both, delay=2, id_change=false"),
        ),
    ])
    .unwrap();
    let mut sim = Simulator::new(cfg, None, 0.0);
    run_secs(&mut sim, 0.0, 12);
    assert_eq!(sim.state().x, 5.0);
}

#[test]
fn wind_conditions_apply_piece_by_piece_and_the_arrow_is_posted_every_50th_iteration() {
    let cfg = SimConfig::from_params([
        ("wind_conditions", "spd=2,dir=0"),
        ("polar_plot", "0,0:90,100:180,50"),
    ])
    .unwrap();
    let mut sim = Simulator::new(cfg, None, 0.0);
    // A bad piece: the speed before it is taken, the polar keeps its old wind angle.
    sim.on_mail(
        "WIND_CONDITIONS",
        ValueRef::String("spd=3,gust=1,dir=90"),
        0.0,
    );
    let w = sim.inputs().wind.unwrap();
    assert_eq!(
        (w.speed_mps, w.dir_deg, sim.inputs().polar_wind_deg),
        (3.0, 0.0, 0.0)
    );
    // A negative speed is skipped, the rest read: the polar follows.
    sim.on_mail("WIND_CONDITIONS", ValueRef::String("spd=-1,dir=450"), 0.0);
    let w = sim.inputs().wind.unwrap();
    assert_eq!(
        (w.speed_mps, w.dir_deg, sim.inputs().polar_wind_deg),
        (3.0, 90.0, 90.0)
    );
    let mut out = Vec::new();
    for i in 1..=100 {
        sim.iterate(f64::from(i) * 0.1, &mut out);
    }
    let arrows = all_of(&out, "VIEW_ARROW");
    assert_eq!(arrows.len(), 2, "iterations 50 and 100");
    assert_eq!(
        arrows[0].as_str().unwrap(),
        "ctrx=0,ctry=0,ang=270,bwid=5,blen=20,hwid=10,hlen=10,label=windmod,edge_color=off,vertex_color=off,fill_color=green,fill_transparency=0.2"
    );
    // Without a polar plot there is no sailing and no arrow.
    let mut plain = Simulator::new(
        SimConfig::from_params([("wind_conditions", "spd=2,dir=0")]).unwrap(),
        None,
        0.0,
    );
    assert!(all_of(&run_secs(&mut plain, 0.0, 50), "VIEW_ARROW").is_empty());
}

#[test]
fn trim_and_buoyancy_handshakes_report_as_the_cpp() {
    let cfg = SimConfig::from_params([("trim_tolerance", "5"), ("max_trim_delay", "8")]).unwrap();
    let mut sim = Simulator::new(cfg, None, 0.0);
    let p = sim
        .on_mail("BUOYANCY_CONTROL", ValueRef::String("true"), 0.0)
        .unwrap();
    assert_eq!(
        (&*p.key, p.value.as_str()),
        (
            "BUOYANCY_REPORT",
            Some("status=1,error=0,progressing,buoyancy=0.0")
        )
    );
    assert_eq!(sim.inputs().buoyancy_rate_mps, 0.0);
    let p = sim
        .on_mail("TRIM_CONTROL", ValueRef::String("TRUE"), 0.0)
        .unwrap();
    assert_eq!(
        p.value.as_str(),
        Some("status=1,error=0,progressing,trim_pitch=0.0,trim_roll=0.0")
    );
    let out = run_secs(&mut sim, 0.0, 6);
    // Both complete once 5 s have passed (the pitch, 0 at rest, is within the tolerance).
    assert_eq!(
        all_of(&out, "BUOYANCY_REPORT"),
        vec![vehicle::Value::String(
            "status=2,error=0,completed,buoyancy=0.0".into()
        )]
    );
    assert_eq!(
        all_of(&out, "TRIM_REPORT"),
        vec![vehicle::Value::String(
            "status=2,error=0,completed,trim_pitch=0.00000,trim_roll=0.0".into()
        )]
    );
    let ix = |v: &str| out.iter().position(|p| &*p.key == v).unwrap();
    assert!(ix("BUOYANCY_REPORT") < ix("USM_X").max(ix("TRIM_REPORT") + 1));
}

#[test]
fn sim_config_rules_follow_on_startup() {
    let warn = |k: &str, v: &str| {
        let (cfg, w) = SimConfig::from_params_lenient([(k, v)]).unwrap();
        (cfg, w.len())
    };
    // Keys the C++ block does not take (mail names only, or coug inventions).
    for k in ["current_x", "current_y", "water_depth", "legacy"] {
        assert!(matches!(
            SimConfig::from_params([(k, "1")]),
            Err(ConfigError::UnknownKey { .. })
        ));
    }
    // thrust_factor: applied when >= 0, but always reported unhandled.
    let (cfg, n) = warn("thrust_factor", "10");
    assert_eq!((cfg.thrust_map.thrust_factor, n), (10.0, 1));
    let (cfg, n) = warn("thrust_factor", "-1");
    assert_eq!((cfg.thrust_map.thrust_factor, n), (20.0, 1));
    // turn_spd_loss is read with atof: a non-number is 0, accepted.
    let (cfg, n) = warn("turn_spd_loss", "abc");
    assert_eq!((cfg.turn_spd_loss, n), (0.0, 0));
    let (cfg, n) = warn("turn_spd_loss", "1.5");
    assert_eq!((cfg.turn_spd_loss, n), (0.85, 1));
    // post_des_* naming the PID's own variable is unhandled.
    let (cfg, n) = warn("post_des_thrust", "DESIRED_THRUST");
    assert_eq!((cfg.post_des_thrust, n), (None, 1));
    let (cfg, n) = warn("post_des_rudder", "SIM_RUDDER");
    assert_eq!((cfg.post_des_rudder.as_deref(), n), (Some("SIM_RUDDER"), 0));
    // thrust_reflect takes true/false only.
    assert_eq!(warn("thrust_reflect", "yes").1, 1);
    // Turn-speed map: null speed > 0, full rate in (0, 100].
    assert_eq!(warn("turn_spd_map_null_speed", "0").1, 1);
    assert_eq!(warn("turn_spd_map_full_rate", "0").1, 1);
    assert_eq!(warn("turn_spd_map_full_rate", "100").1, 0);
    // Negative limits are refused.
    for k in [
        "max_acceleration",
        "max_deceleration",
        "max_rudder_degs_per_sec",
        "turn_radius",
        "default_water_depth",
    ] {
        assert_eq!(warn(k, "-1").1, 1, "{k}");
    }
    assert_eq!(warn("max_speed", "0").1, 1);
    // Without the embedded PID, PID keys (depth_control included) are taken silently and
    // have no effect: depth outputs stay on.
    let (cfg, n) = warn("depth_control", "false");
    assert_eq!((cfg.depth_control, n), (true, 0));
    assert_eq!(warn("maxrudder", "40").1, 0);
}

#[test]
fn a_bad_depth_control_with_the_embedded_pid_leaves_the_sim_uncoupled_with_defaults() {
    let (cfg, w) = SimConfig::from_params_lenient([
        ("prefix", "NAV"),
        ("yaw_pid_kp", "1"),
        ("depth_control", "maybe"),
    ])
    .unwrap();
    assert_eq!(w.len(), 1);
    assert!(
        w[0].to_string().contains("Improper DEP PID Setting"),
        "{}",
        w[0]
    );
    assert!(cfg.pid.is_none());
    assert_eq!(
        cfg.prefix, "USM",
        "the simulator's own settings were never read"
    );
}

#[test]
fn embedded_pid_with_speed_factor_and_no_depth_control() {
    let cfg = SimConfig::from_params([
        ("prefix", "NAV"),
        ("post_des_thrust", "SIM_THRUST"),
        ("yaw_pid_kp", "1"),
        ("yaw_pid_kd", "0"),
        ("yaw_pid_ki", "0"),
        ("yaw_pid_integral_limit", "0"),
        ("maxrudder", "100"),
        ("speed_pid_kp", "1"),
        ("speed_pid_kd", "0"),
        ("speed_pid_ki", "0"),
        ("speed_pid_integral_limit", "0"),
        ("maxthrust", "100"),
        ("speed_factor", "20"),
        ("depth_control", "false"),
    ])
    .unwrap();
    assert!(!cfg.depth_control);
    let mut sim = Simulator::new(cfg, None, 0.0);
    let subs = sim.subscriptions();
    assert!(subs.contains(&"DESIRED_SPEED") && !subs.contains(&"DESIRED_THRUST"));
    run_secs(&mut sim, 0.0, 1);
    sim.on_mail("MOOS_MANUAL_OVERRIDE", ValueRef::String("false"), 1.0);
    sim.on_mail("DESIRED_HEADING", ValueRef::Double(0.0), 1.0);
    sim.on_mail("DESIRED_SPEED", ValueRef::Double(1.5), 1.0);
    let out = run_secs(&mut sim, 1.0, 2);
    // Thrust = desired speed x speed factor = 30, handed to the model and echoed.
    assert_eq!(
        last_posting(&out, "SIM_THRUST").unwrap().as_f64(),
        Some(30.0)
    );
    assert_eq!(sim.inputs().thrust, 30.0);
    // No depth control: none of the depth outputs.
    assert!(
        last_posting(&out, "NAV_Z").is_none() && last_posting(&out, "SIMULATION_MODE").is_none()
    );
    // SPEED_FACTOR at run time.
    // (The helm keeps posting: inputs older than tardy_helm_threshold = 2 s are stale.)
    sim.on_mail("SPEED_FACTOR", ValueRef::Double(10.0), 3.0);
    sim.on_mail("DESIRED_HEADING", ValueRef::Double(0.0), 3.0);
    sim.on_mail("DESIRED_SPEED", ValueRef::Double(1.5), 3.0);
    let out = run_secs(&mut sim, 3.0, 1);
    assert_eq!(
        last_posting(&out, "SIM_THRUST").unwrap().as_f64(),
        Some(15.0)
    );
}

#[test]
fn start_keys_rotate_speed_depth_rate_speed_and_navpos_summary() {
    let (cfg, w) = SimConfig::from_params_lenient([
        ("start_x", "3"),
        ("start_y", "4"),
        ("start_heading", "90"),
        ("start_speed", "0"),
        ("start_depth", "2"),
        ("rotate_speed", "10"),
        ("post_navpos_summary", "true"),
        ("max_depth_rate_speed", "4"),
        ("start_speed", "fast"),
    ])
    .unwrap();
    assert_eq!(w.len(), 1, "start_speed=fast: {w:?}");
    assert_eq!(
        (
            cfg.start.x,
            cfg.start.y,
            cfg.start.heading_deg,
            cfg.start.depth
        ),
        (3.0, 4.0, 90.0, 2.0)
    );
    assert_eq!(
        SimConfig::from_params_lenient([("start_depth", "-1")])
            .unwrap()
            .1
            .len(),
        1
    );
    let mut sim = Simulator::new(cfg.clone(), None, 0.0);
    let out = run_secs(&mut sim, 0.0, 2);
    // Rudder 0, speed 0: only the external rotation turns it, 10 deg/s for 2 s.
    assert_eq!(
        last_posting(&out, "USM_HEADING").unwrap().as_f64(),
        Some(110.0)
    );
    assert_eq!(
        last_posting(&out, "USM_NAVPOS_SUMMARY").unwrap().as_str(),
        Some("x=3,y=4")
    );
    // Depth rate at 1 m/s with max_depth_rate_speed 4: sqrt(1/4) x 0.5 m/s at full elevator.
    let s0 = SimState {
        speed_mps: 1.0,
        ..SimState::default()
    };
    let inp = SimInputs {
        thrust: 20.0,
        elevator_deg: 100.0,
        ..SimInputs::default()
    };
    let s1 = step(
        &SimConfig {
            rotate_speed_deg_s: 0.0,
            ..cfg
        },
        &s0,
        &inp,
        1.0,
        None,
    )
    .0;
    assert!(close(s1.depth, 0.25, 1e-12), "{}", s1.depth);
}

/// uSimMarineV22 over a stalled real-time iteration (40 simulated seconds at once) does what
/// the C++ `USM_Model::propagate` does: one step of the whole gap, no substeps (its model is
/// kinematic: speed towards the thrust map's with the acceleration limits, heading at the
/// rudder's turn rate, depth at a rate, position along the heading). That stays finite and
/// bounded: full thrust and rudder for 40 s leave the speed at most the map's top speed and
/// the vehicle at most that speed times 40 s from where it was.
#[test]
fn a_forty_second_step_is_one_step_as_the_cpp_and_stays_bounded() {
    let (cfg, warnings) = SimConfig::from_params_lenient([
        ("start_pos", "x=0, y=0, heading=0, speed=1, depth=5"),
        ("max_acceleration", "0.5"),
        ("max_deceleration", "0.5"),
    ])
    .unwrap();
    assert!(warnings.is_empty(), "{warnings:?}");
    let mut sim = Simulator::new(cfg, None, 0.0);
    let mut out = Vec::new();
    for (v, x) in [
        ("DESIRED_THRUST", 100.0),
        ("DESIRED_RUDDER", 100.0),
        ("DESIRED_ELEVATOR", -100.0),
    ] {
        sim.on_mail(v, ValueRef::Double(x), 0.0);
    }
    sim.iterate(0.0, &mut out);
    sim.iterate(40.0, &mut out);
    let s = *sim.state();
    for v in [s.x, s.y, s.heading_deg, s.speed_mps, s.depth, s.pitch_rad] {
        assert!(v.is_finite(), "{s:?}");
    }
    assert!(s.speed_mps > 0.0 && s.speed_mps <= 5.0 + 1e-9, "{s:?}");
    assert!(
        s.x.hypot(s.y) <= 1.0f64.max(s.speed_mps) * 40.0 + 1e-9,
        "{s:?}"
    );
    assert!(
        (0.0..360.0).contains(&s.heading_deg) && s.depth >= 0.0,
        "{s:?}"
    );
    // One step: a straight line at the step's mean heading (over ground: half way from 0° to
    // the heading the step ends with) and the new speed, not a curve.
    assert!(
        (s.heading_og_deg - s.heading_deg / 2.0).abs() < 1e-9,
        "{s:?}"
    );
    let h = s.heading_og_deg.to_radians();
    assert!(
        (s.x - s.speed_mps * 40.0 * h.sin()).abs() < 1e-6
            && (s.y - s.speed_mps * 40.0 * h.cos()).abs() < 1e-6,
        "{s:?}"
    );
}
