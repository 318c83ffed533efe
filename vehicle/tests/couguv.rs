//! uSimCougUV: the CougUV model as a simulator (dynamics sanity, the MOOS adapter).

use vehicle::ValueRef;
use vehicle::angle::angle180;
use vehicle::cougars::{CougUvModel, UCommand, vars};
use vehicle::couguv::{CougUvSim, CougUvSimConfig, CougUvTruth, advance};
use vehicle::moos::last_posting;

fn run(model: &CougUvModel, start: CougUvTruth, cmd: UCommand, secs: f64) -> CougUvTruth {
    let mut t = start;
    let dt = 0.05;
    for _ in 0..(secs / dt).round() as usize {
        t = advance(model, &t, &cmd, (0.0, 0.0), dt);
    }
    t
}

fn thrust(pct: f64) -> UCommand {
    UCommand {
        fin: [0.0; 3],
        thruster: pct,
    }
}

#[test]
fn thrust_gives_a_steady_speed_after_the_surge_lag() {
    let m = CougUvModel::default();
    // 50 % of 2 m/s; the 20 s surge time constant: 63 % after 20 s, all of it after 200 s.
    let t20 = run(&m, CougUvTruth::default(), thrust(50.0), 20.0);
    assert!((t20.body.surge - 0.632).abs() < 0.01, "{}", t20.body.surge);
    let t = run(&m, CougUvTruth::default(), thrust(50.0), 200.0);
    assert!((t.body.surge - 1.0).abs() < 1e-3, "{}", t.body.surge);
    // Straight along the heading (north), level, at the surface.
    let t2 = run(&m, t, thrust(50.0), 10.0);
    assert!((t2.y - t.y - 10.0).abs() < 0.01 && (t2.x - t.x).abs() < 1e-9);
    assert_eq!((t2.body.depth, t2.body.heading), (0.0, 0.0));
    // Reverse thrust backs up; no thrust coasts down.
    let back = run(&m, CougUvTruth::default(), thrust(-50.0), 200.0);
    assert!((back.body.surge + 1.0).abs() < 1e-3);
    let coast = run(&m, t, thrust(0.0), 20.0);
    assert!((coast.body.surge - 0.368).abs() < 0.01);
}

#[test]
fn a_top_fin_turns_at_the_nomoto_rate() {
    let m = CougUvModel::default();
    let cruise = run(&m, CougUvTruth::default(), thrust(50.0), 200.0);
    let cmd = UCommand {
        fin: [10.0, 0.0, 0.0],
        thruster: 50.0,
    };
    let settled = run(&m, cruise, cmd, 10.0);
    let later = run(&m, settled, cmd, 10.0);
    // K δ u = 0.25 x 10° x 1 m/s = 2.5 °/s, clockwise (starboard) for a positive fin.
    let turned = angle180(later.body.heading - settled.body.heading);
    assert!((turned - 25.0).abs() < 0.1, "{turned}");
    // A negative fin turns to port; the fins are limited at delta_max (25°).
    let port = run(
        &m,
        cruise,
        UCommand {
            fin: [-40.0, 0.0, 0.0],
            ..cmd
        },
        10.0,
    );
    let more = run(
        &m,
        port,
        UCommand {
            fin: [-40.0, 0.0, 0.0],
            ..cmd
        },
        10.0,
    );
    let turned = angle180(more.body.heading - port.body.heading);
    assert!((turned + 62.5).abs() < 0.3, "{turned}");
    // A full circle (turning radius u/r = 22.9 m) comes back to where it started.
    let circle = run(&m, settled, cmd, 144.0);
    assert!(
        (circle.x - settled.x).hypot(circle.y - settled.y) < 0.5,
        "{:?} vs {:?}",
        (circle.x, circle.y),
        (settled.x, settled.y)
    );
}

#[test]
fn the_elevator_pitches_the_nose_against_the_restoring_moment() {
    let m = CougUvModel::default();
    let deep = CougUvTruth {
        body: vehicle::cougars::CougUvState {
            depth: 10.0,
            ..Default::default()
        },
        ..CougUvTruth::default()
    };
    let cruise = run(&m, deep, thrust(50.0), 200.0);
    // Port +10, starboard -10: nose up (the model's pitch is nose down positive).
    let cmd = UCommand {
        fin: [0.0, -10.0, 10.0],
        thruster: 50.0,
    };
    let t = run(&m, cruise, cmd, 30.0);
    let u: f64 = t.body.surge;
    let lift = 0.5 * m.rho * m.fin_area * m.cl_delta * m.fin_cant_deg.to_radians().cos() * u * u;
    let moment = 2.0 * (m.length / 2.0) * lift * 10f64.to_radians();
    let expected = -(moment / (m.mass * 9.81 * m.r_bg)).asin();
    assert!(
        (t.body.pitch - expected).abs() < 0.002,
        "pitch {} expected {expected}",
        t.body.pitch
    );
    // Nose up at speed: rising (plus the buoyancy), slower over the ground.
    assert!(t.body.depth < 10.0 - 3.0, "depth {}", t.body.depth);
    assert!((t.body.depth_rate - (u * t.body.pitch.sin() - m.buoyancy_rate)).abs() < 1e-9);
    // The opposite elevator dives.
    let down = UCommand {
        fin: [0.0, 10.0, -10.0],
        thruster: 50.0,
    };
    let d = run(&m, cruise, down, 30.0);
    assert!(d.body.pitch > 0.1 && d.body.depth > 13.0, "{:?}", d.body);
    // Released, the pitch returns to level (damped).
    let level = run(&m, d, thrust(50.0), 30.0);
    assert!(level.body.pitch.abs() < 0.005, "{}", level.body.pitch);
}

fn sim(params: &[(&str, &str)]) -> CougUvSim {
    CougUvSim::new(
        CougUvSimConfig::from_params(params.iter().copied()).unwrap(),
        None,
    )
}

#[test]
fn the_app_flies_the_posted_fins_and_posts_the_truth_under_its_prefix() {
    let mut s = sim(&[
        ("prefix", "TRU"),
        ("start_pos", "x=5, y=-3, heading=90, speed=1, depth=2"),
        ("default_water_depth", "30"),
        ("drift_x", "0.1"),
        ("buoyancy_rate", "0"),
    ]);
    let mut out = Vec::new();
    s.iterate(10.0, &mut out);
    let get = |out: &[vehicle::Posting], v: &str| {
        last_posting(out, v)
            .and_then(|x| x.as_f64())
            .unwrap_or_else(|| panic!("{v}"))
    };
    assert_eq!(
        get(&out, "TRU_X"),
        5.0,
        "the first iteration posts the start"
    );
    assert_eq!((get(&out, "TRU_DEPTH"), get(&out, "TRU_Z")), (2.0, -2.0));
    assert_eq!(get(&out, "TRU_ALTITUDE"), 28.0);
    assert_eq!(get(&out, "TRU_HEADING"), 90.0);
    assert!((get(&out, "TRU_YAW") + 90f64.to_radians()).abs() < 1e-12);
    // A nose-up elevator: TRU_PITCH (MOOS: nose up positive) grows.
    for (v, x) in [
        (vars::FIN_DEFLECT_TOP_DEG, 0.0),
        (vars::FIN_DEFLECT_STBD_DEG, -10.0),
        (vars::FIN_DEFLECT_PORT_DEG, 10.0),
        (vars::THRUST_PCT, 50.0),
    ] {
        s.on_mail(v, ValueRef::Double(x), 10.0);
    }
    for k in 1..=40 {
        out.clear();
        s.iterate(10.0 + f64::from(k) * 0.05, &mut out);
    }
    assert!(get(&out, "TRU_PITCH") > 0.02, "{}", get(&out, "TRU_PITCH"));
    assert!(get(&out, "TRU_DEPTH") < 2.0);
    // East at about 1 m/s plus the current: over the ground a little faster, heading east.
    assert!(get(&out, "TRU_X") > 5.0 + 2.0 * 1.0);
    let sog = get(&out, "TRU_SPEED_OVER_GROUND");
    assert!(sog > get(&out, "TRU_SPEED") * 0.99 + 0.05, "{sog}");
    assert!((get(&out, "TRU_HEADING_OVER_GROUND") - 90.0).abs() < 0.5);
}

#[test]
fn the_actuators_stop_without_commands_and_bad_settings_are_reported() {
    let mut s = sim(&[("command_timeout", "5")]);
    s.on_mail(vars::THRUST_PCT, ValueRef::Double(80.0), 0.0);
    let mut out = Vec::new();
    s.iterate(0.0, &mut out);
    s.iterate(4.0, &mut out);
    let v4 = s.truth().body.surge;
    assert!(v4 > 0.2, "{v4}");
    s.iterate(10.0, &mut out);
    s.iterate(30.0, &mut out);
    assert!(
        s.truth().body.surge < v4,
        "the failsafe stopped the thruster: {}",
        s.truth().body.surge
    );
    assert_eq!(s.command().thruster, 80.0, "the last command is kept");
    let (cfg, problems) = CougUvSimConfig::from_params_lenient([
        ("mass", "-3"),
        ("start_pos", "x=1, colour=2"),
        ("fin_cant", "30"),
        ("wings", "2"),
    ])
    .unwrap();
    assert_eq!(problems.len(), 3, "{problems:?}");
    assert_eq!(cfg.model.mass, 31.03, "a bad value keeps the default");
    assert_eq!(cfg.start.x, 0.0, "a bad start_pos is not applied");
    assert_eq!(cfg.prefix, "SIM");
}

/// Two simulators from `params` given [`full_command`] at 0 s: one iterated at 0 and 40 s
/// (a stalled run's one step), one at 20 Hz from 0 to 40 s.
fn once_and_fine(params: &[(&str, &str)]) -> (CougUvSim, CougUvSim) {
    let mut once = sim(params);
    let mut out = Vec::new();
    full_command(&mut once, 0.0);
    once.iterate(0.0, &mut out);
    once.iterate(40.0, &mut out);
    let mut fine = sim(params);
    full_command(&mut fine, 0.0);
    for k in 0..=800 {
        out.clear();
        fine.iterate(f64::from(k) * 0.05, &mut out);
    }
    (once, fine)
}

fn full_command(s: &mut CougUvSim, t: f64) {
    // Full thrust, a hard starboard turn and a full nose-down elevator.
    for (v, x) in [
        (vars::FIN_DEFLECT_TOP_DEG, 25.0),
        (vars::FIN_DEFLECT_STBD_DEG, 25.0),
        (vars::FIN_DEFLECT_PORT_DEG, -25.0),
        (vars::THRUST_PCT, 100.0),
    ] {
        s.on_mail(v, ValueRef::Double(x), t);
    }
}

/// A real-time run starved for 5 s of wall time at a warp of 8 iterates once over 40
/// simulated seconds: the command given before the stall flies until the failsafe's 5 s, the
/// rest of the gap with the actuators stopped, as 800 iterations at 20 Hz would have it; the
/// vehicle stays finite and physically plausible.
#[test]
fn a_forty_second_step_flies_the_command_until_the_failsafe_as_short_steps_do() {
    let params = [
        ("start_pos", "x=0, y=0, heading=0, speed=1, depth=2"),
        ("command_timeout", "5"),
    ];
    let (once, fine) = once_and_fine(&params);
    let (a, b) = (once.truth(), fine.truth());
    assert!(a.is_finite(), "{a:?}");
    for (what, x, y) in [
        ("x", a.x, b.x),
        ("y", a.y, b.y),
        ("depth", a.body.depth, b.body.depth),
        ("heading", a.body.heading, b.body.heading),
        ("pitch", a.body.pitch, b.body.pitch),
        ("surge", a.body.surge, b.body.surge),
    ] {
        assert!(
            (x - y).abs() < 1e-3 * (1.0 + y.abs()),
            "{what}: one 40 s step {x}, 20 Hz {y}"
        );
    }
    // It flew the command for 5 s (nose down, a turn, faster), then coasted and rose.
    assert!(a.body.surge > 0.1 && a.body.surge < 1.0, "{a:?}");
    assert!(a.x.hypot(a.y) > 10.0, "{a:?}");
    assert!((0.0..30.0).contains(&a.body.depth), "{a:?}");
    assert!(a.body.pitch.abs() < 0.5, "{a:?}");
    assert!(a.body.fins.iter().all(|f| f.abs() < 1e-6), "{a:?}");
}

/// Without a failsafe (`command_timeout = 0`) the command flies the whole 40 s step, and the
/// substeps keep the pendulum and the actuator lags as stable as at 20 Hz: fins within their
/// limits, surge below the top speed, depth not negative, and the same vehicle as short steps.
#[test]
fn a_forty_second_step_without_failsafe_stays_finite_and_plausible() {
    let params = [
        ("start_pos", "x=0, y=0, heading=0, speed=1, depth=5"),
        ("command_timeout", "0"),
    ];
    let (once, fine) = once_and_fine(&params);
    let (a, b) = (once.truth(), fine.truth());
    assert!(a.is_finite(), "{a:?}");
    assert!(a.body.fins.iter().all(|f| f.abs() <= 25.0 + 1e-9), "{a:?}");
    assert!(a.body.surge > 1.0 && a.body.surge <= 2.0, "{a:?}");
    assert!(a.body.depth >= 0.0 && a.x.hypot(a.y) < 2.0 * 40.0, "{a:?}");
    assert!(
        (a.x - b.x).abs() < 1e-2
            && (a.y - b.y).abs() < 1e-2
            && (a.body.depth - b.body.depth).abs() < 1e-2,
        "one step {a:?}\n20 Hz {b:?}"
    );
    assert_eq!(once.refused_steps(), 0);
}

/// A model whose state is not finite (a zero mass, which the configuration refuses, set
/// directly) is refused with a warning: the truth stays where it was, never NaN.
#[test]
fn a_non_finite_state_is_refused_with_a_warning() {
    let mut cfg = CougUvSimConfig::from_params([("start_pos", "x=3, y=4, speed=1")]).unwrap();
    cfg.model.mass = 0.0;
    let mut s = CougUvSim::new(cfg, None);
    let mut out = Vec::new();
    s.on_mail(vars::THRUST_PCT, ValueRef::Double(50.0), 0.0);
    s.iterate(0.0, &mut out);
    let before = *s.truth();
    out.clear();
    s.iterate(8.0, &mut out);
    assert_eq!(*s.truth(), before);
    assert_eq!(s.refused_steps(), 1);
    let w = s.take_warnings();
    assert!(w.len() == 1 && w[0].contains("not finite"), "{w:?}");
    assert_eq!(
        last_posting(&out, "SIM_X").and_then(|v| v.as_f64()),
        Some(3.0)
    );
    assert!(s.take_warnings().is_empty());
}
