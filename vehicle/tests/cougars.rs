//! CoUGARs cascade, mixing and actuators.

mod common;

use vehicle::ValueRef;
use vehicle::cougars::{
    Actuators, ControllerInputs, ControlsConfig, ControlsMode, CougPid, CougUvModel, CougUvState,
    CougarsConfig, CougarsControl, CougarsState, Gains, Kinematics, UCommand, compass_to_enu,
    pitch_schedule_constant, step, vars,
};
use vehicle::moos::last_posting;
use vehicle::{ConfigError, Posting};

struct Dive {
    cfg: CougarsConfig,
    ctl: CougarsState,
    model: CougUvModel,
    veh: CougUvState,
    t: f64,
}

impl Dive {
    fn new(cfg: CougarsConfig) -> Self {
        Dive {
            ctl: CougarsState::new(&cfg),
            cfg,
            model: CougUvModel::default(),
            veh: CougUvState {
                surge: 0.6,
                heading: 0.0,
                ..CougUvState::default()
            },
            t: 0.0,
        }
    }

    fn tick(&mut self, desired_depth: f64, desired_heading_enu: f64) -> UCommand {
        let inp = ControllerInputs {
            desired_depth,
            desired_heading: desired_heading_enu,
            desired_speed: 30.0, // 0.6 m/s at the model's 2 m/s full thrust
            depth: self.veh.depth,
            depth_rate: self.veh.depth_rate,
            pitch: self.veh.pitch.to_degrees(),
            pitch_rate: self.veh.pitch_rate.to_degrees(),
            heading: compass_to_enu(self.veh.heading),
            surge: self.veh.surge,
            ..ControllerInputs::default()
        };
        let (s, cmd) = step(&self.cfg, &self.ctl, &inp);
        self.ctl = s;
        self.veh = self.model.step(&self.veh, &cmd, self.cfg.ts());
        self.t += self.cfg.ts();
        cmd
    }
}

#[test]
fn dive_to_3m_with_coug1_gains_reaches_and_holds() {
    let cfg = CougarsConfig::coug1();
    assert_eq!(cfg.ts(), 0.08);
    let mut d = Dive::new(cfg);
    let mut reached = None;
    let mut max_depth: f64 = 0.0;
    while d.t < 400.0 {
        let cmd = d.tick(3.0, 90.0);
        // Saturation: pitch fin within the pitch loop's ±30, rudder within ±45.
        assert!(
            cmd.fin[1].abs() <= 30.0 && cmd.fin[2].abs() <= 30.0,
            "{cmd:?}"
        );
        assert!(cmd.fin[0].abs() <= 45.0);
        assert_eq!(cmd.fin[1], -cmd.fin[2], "elevators mirror each other");
        assert!(
            d.ctl.theta_ref.abs() <= 15.0 + 1e-9,
            "pitch reference within the depth loop limits"
        );
        max_depth = max_depth.max(d.veh.depth);
        if reached.is_none() && (d.veh.depth - 3.0).abs() < 0.2 {
            reached = Some(d.t);
        }
        if reached.is_some_and(|t0| d.t > t0 + 5.0) {
            assert!(
                (d.veh.depth - 3.0).abs() < 0.2,
                "left the band at t={} depth={}",
                d.t,
                d.veh.depth
            );
        }
    }
    let t0 = reached.expect("never reached 3 m");
    eprintln!(
        "reached 3 +- 0.2 m after {t0:.1} s; max depth {max_depth:.3} m; final {:.3} m",
        d.veh.depth
    );
    assert!(max_depth < 3.2, "overshoot to {max_depth}");
    assert!((d.veh.depth - 3.0).abs() < 0.1);
}

#[test]
fn dive_with_coug2_gains_too() {
    // coug2: pitch kd 0.7 and no integral terms; the dirty derivative works on the model's
    // pitch rate in degrees/s.
    let mut d = Dive::new(CougarsConfig::coug2());
    let mut max_depth: f64 = 0.0;
    while d.t < 400.0 {
        let cmd = d.tick(3.0, 90.0);
        assert!(cmd.fin[2].abs() <= 40.0 && cmd.fin[0].abs() <= 35.0);
        max_depth = max_depth.max(d.veh.depth);
    }
    assert!(
        (d.veh.depth - 3.0).abs() < 0.2,
        "final depth {}",
        d.veh.depth
    );
    assert!(max_depth < 3.2, "overshoot to {max_depth}");
}

#[test]
fn large_depth_error_uses_saturated_mode() {
    let mut d = Dive::new(CougarsConfig::coug1());
    d.tick(10.0, 90.0);
    assert!(d.ctl.saturated_mode, "10 m error > 2.5 m threshold");
    assert_eq!(d.ctl.depth_pid.integrator(), 0.0);
    // The depth reference leads the vehicle by the saturation offset.
    assert!(
        (d.ctl.z_ref - (d.veh.depth.min(0.01) + 1.7)).abs() < 0.05,
        "z_ref {}",
        d.ctl.z_ref
    );
    // The pitch reference low-passes towards +15 (nose down).
    let first = d.ctl.theta_ref;
    let a = (-0.08f64 * 0.15).exp();
    assert!((first - (1.0 - a) * 15.0).abs() < 1e-9, "{first}");
    for _ in 0..200 {
        d.tick(10.0, 90.0);
    }
    assert!(d.ctl.theta_ref > 10.0 && d.ctl.theta_ref <= 15.0);
}

#[test]
fn new_desired_depth_restarts_the_reference() {
    let cfg = CougarsConfig::coug1();
    let mut s = CougarsState::new(&cfg);
    let inp = ControllerInputs {
        desired_depth: 2.0,
        depth: 0.5,
        surge: 0.6,
        ..ControllerInputs::default()
    };
    s = step(&cfg, &s, &inp).0;
    let az = (-0.08f64 * 0.30).exp();
    assert!((s.z_ref - (az * 0.5 + (1.0 - az) * 2.0)).abs() < 1e-12);
    let z1 = s.z_ref;
    // Same desired depth (within 1e-6): the filter continues.
    let inp2 = ControllerInputs {
        desired_depth: 2.0 + 1e-9,
        depth: 0.7,
        ..inp
    };
    s = step(&cfg, &s, &inp2).0;
    assert!((s.z_ref - (az * z1 + (1.0 - az) * 2.0)).abs() < 1e-9);
    // A new one restarts from the current depth.
    let inp3 = ControllerInputs {
        desired_depth: 1.0,
        depth: 0.7,
        ..inp
    };
    s = step(&cfg, &s, &inp3).0;
    assert!((s.z_ref - (az * 0.7 + (1.0 - az) * 1.0)).abs() < 1e-12);
}

#[test]
fn heading_loop_turns_the_right_way_and_saturates() {
    let cfg = CougarsConfig::coug1();
    let s = CougarsState::new(&cfg);
    // Desired compass 100, actual compass 90: turn right (clockwise) = positive rudder.
    let inp = ControllerInputs {
        desired_heading: compass_to_enu(100.0),
        heading: compass_to_enu(90.0),
        surge: 0.6,
        ..ControllerInputs::default()
    };
    let (_, cmd) = step(&cfg, &s, &inp);
    assert_eq!(cmd.fin[0], 30.0, "-kp * wrap(desired - actual) = -3 * -10");
    // Error across the ±180 wrap: desired compass 350, actual 10 -> turn left 20 degrees.
    let inp = ControllerInputs {
        desired_heading: compass_to_enu(350.0),
        heading: compass_to_enu(10.0),
        ..inp
    };
    assert_eq!(step(&cfg, &s, &inp).1.fin[0], -45.0, "-60 saturates at -45");
    // Truncated to whole degrees.
    let inp = ControllerInputs {
        desired_heading: compass_to_enu(91.7),
        heading: compass_to_enu(90.0),
        ..inp
    };
    assert_eq!(step(&cfg, &s, &inp).1.fin[0], 5.0);
    // Closed loop with the model: a 90 degree turn settles.
    let mut d = Dive::new(cfg);
    for _ in 0..2000 {
        d.tick(0.0, compass_to_enu(90.0));
    }
    assert!(
        (d.veh.heading - 90.0).abs() < 2.0,
        "heading {}",
        d.veh.heading
    );
}

#[test]
fn pitch_loop_gain_schedule_and_anti_windup() {
    let k = pitch_schedule_constant();
    assert!((k - 0.5 * 997.0 * 0.00665 * 0.5 * -0.43 * 0.8660254037844386).abs() < 1e-12);
    assert!(k < 0.0);
    // Pure P: fin = kp*e/(u^2 k).
    let mut p = CougPid::new(Gains::new(0.4, 0.0, 0.0, 30.0), 0.08);
    let s = 0.36 * k;
    let out = p.compute_scheduled(5.0, 0.0, 0.0, s);
    assert!(
        (out - 0.4 * 5.0 / s).abs() < 1e-12 && out < 0.0,
        "nose-down request gives a negative fin"
    );
    // Saturation with ki = 0 (coug2) resets the integrator instead of dividing by zero.
    let mut p = CougPid::new(Gains::new(0.45, 0.0, 0.7, 40.0), 0.08);
    let out = p.compute_scheduled(90.0, 0.0, 0.0, s);
    assert_eq!(out, -40.0);
    assert_eq!(p.integrator(), 0.0);
    // Back-calculation: integrator set so that p + i hits the limit exactly.
    let mut p = CougPid::new(Gains::new(0.01, 0.5, 0.0, 30.0), 0.08);
    for _ in 0..400 {
        p.compute_scheduled(20.0, 0.0, 0.0, s);
    }
    let pd = 0.01 * 20.0 / s;
    assert!(
        (0.5 * p.integrator() / s + pd + 30.0).abs() < 1e-9,
        "integrator {}",
        p.integrator()
    );
    // Seconds, not milliseconds: beta of the dirty derivative for Ts = 0.08 s.
    assert!((p.beta() - (0.1 - 0.08) / (0.1 + 0.08)).abs() < 1e-12);
    assert!(p.beta() > 0.0, "a low-pass filter");
    // What the original's Ts = 80 ("ms" used as seconds) gave: an oscillating filter.
    let bug = CougPid::new(Gains::new(1.0, 0.0, 0.0, 1.0), 80.0);
    assert!((bug.beta() + 0.9975).abs() < 1e-4);
    let g = Gains::new(1.0, 0.0002, 0.5, 10.0).from_ms_tuned();
    assert!((g.ki - 0.2).abs() < 1e-12 && (g.kd - 0.0005).abs() < 1e-12);
}

#[test]
fn heading_pid_integrates_only_when_slow() {
    let mut p = CougPid::new(Gains::new(0.0, 1.0, 0.0, 100.0), 0.1);
    p.compute(0.0, 0.0);
    p.compute(0.0, 0.0);
    assert_eq!(p.integrator(), 0.0);
    // A jump makes x_dot large: the next call does not integrate.
    p.compute(0.0, 5.0);
    let i = p.integrator();
    assert!((i - 0.1 / 2.0 * -5.0).abs() < 1e-12);
    p.compute(0.0, 5.0);
    assert_eq!(p.integrator(), i, "|x_dot| >= 0.08 freezes the integrator");
}

#[test]
fn mixing_gives_documented_fin_signs() {
    // Before kinematics: fin = [rudder, -p, +p].
    let cfg = CougarsConfig::coug1();
    let mut s = CougarsState::new(&cfg);
    // Vehicle 1 m above the (filtered) reference and level: nose-down request, p < 0.
    let inp = ControllerInputs {
        desired_depth: 2.0,
        depth: 1.0,
        surge: 0.6,
        ..ControllerInputs::default()
    };
    for _ in 0..50 {
        s = step(&cfg, &s, &inp).0;
    }
    let (s2, cmd) = step(&cfg, &s, &inp);
    assert!(s2.pitch_fin < 0.0);
    assert_eq!(cmd.fin, [0.0, -s2.pitch_fin, s2.pitch_fin]);
    assert!(
        cmd.fin[1] > 0.0 && cmd.fin[2] < 0.0,
        "starboard = -p, port = +p"
    );
    // coug1 kinematics: dir (1,-1,-1), top offset -10.
    let k = Kinematics::coug1();
    let raw = UCommand {
        fin: [12.0, -8.0, 8.0],
        thruster: 30.0,
    };
    let m = k.mix(&raw, true, false);
    assert_eq!(m.fin, [2.0, 8.0, -8.0]);
    assert_eq!(m.thruster, 30.0);
    assert_eq!(
        k.mix(&raw, false, false).thruster,
        0.0,
        "disarmed: no thrust"
    );
    // Surface: fins up [0, -30, +30] through directions and offsets; thrust kept if armed.
    let up = k.mix(&raw, true, true);
    assert_eq!(up.fin, [-10.0, 30.0, -30.0]);
    assert_eq!(up.thruster, 30.0);
    // coug2: right offset -20, left +45, trim ratio.
    let k2 = Kinematics {
        trim_ratio: 0.1,
        ..CougarsConfig::coug2().kinematics
    };
    assert_eq!(k2.mix(&raw, true, false).fin, [15.0, -25.0, 56.0]);
    // Demo mode: fins doubled, no thrust.
    let kd = Kinematics {
        demo_mode: true,
        ..Kinematics::default()
    };
    let m = kd.mix(&raw, true, false);
    assert_eq!((m.fin, m.thruster), ([24.0, -16.0, 16.0], 0.0));
}

#[test]
fn actuator_pwm_mapping_and_failsafe() {
    let a = Actuators::default(); // coug1: 500..2500 us servos, 1100..1900 thruster
    assert_eq!(a.servo_us(0.0), 1500);
    assert_eq!(a.servo_us(-90.0), 500);
    assert_eq!(a.servo_us(90.0), 2500);
    assert_eq!(
        a.servo_us(45.9),
        a.servo_us(45.0),
        "fin truncated to whole degrees"
    );
    assert_eq!(a.servo_us(200.0), 2500, "clamped to 180 degrees");
    assert_eq!(a.thruster_us(0.0), 1500);
    assert_eq!(a.thruster_us(100.0), 1900);
    assert_eq!(a.thruster_us(-100.0), 1100);
    assert_eq!(a.thruster_us(50.0), 1700);
    assert_eq!(a.thruster_us(33.0), 1632, "integer map");
    let coug2 = CougarsConfig::coug2().actuators;
    assert_eq!(coug2.servo_us(0.0), 1500);
    assert_eq!(coug2.servo_us(90.0), 2000);
    let cmd = UCommand {
        fin: [10.0, -10.0, 10.0],
        thruster: 50.0,
    };
    let pwm = a.outputs(Some((&cmd, 20.0)), 21.0);
    assert_eq!(pwm.thruster_us, 1700);
    assert_eq!(
        pwm.servo_us,
        [a.servo_us(10.0), a.servo_us(-10.0), a.servo_us(10.0)]
    );
    // ESC held neutral during the 7 s arming delay.
    assert_eq!(a.outputs(Some((&cmd, 3.0)), 3.5).thruster_us, 1500);
    // More than 5 s without a command: centred servos, neutral thruster.
    let fs = a.outputs(Some((&cmd, 20.0)), 25.5);
    assert_eq!(fs.servo_us, [1500; 3]);
    assert_eq!(fs.thruster_us, 1500);
}

// ---------------------------------------------------------------------------------------
// pCougControls: the controllers as a MOOS app.

/// An armed coug1 controller with fresh inputs at `t`: level at `depth`, heading `nav_hdg`
/// (compass), asked for `des_hdg` (compass), `des_depth`, 1 m/s at 50 %/(m/s).
fn armed(cfg: ControlsConfig) -> CougarsControl {
    let mut c = CougarsControl::new(cfg);
    c.on_mail("DEPLOY", ValueRef::String("true"), 0.0);
    c.on_mail("MOOS_MANUAL_OVERRIDE", ValueRef::String("false"), 0.0);
    c
}

fn coug1() -> ControlsConfig {
    ControlsConfig::from_params([("vehicle", "coug1"), ("speed_factor", "50")]).unwrap()
}

fn feed(c: &mut CougarsControl, t: f64, des: (f64, f64, f64), nav: (f64, f64, f64, f64)) {
    let (hdg, spd, dep) = des;
    c.on_mail("DESIRED_HEADING", ValueRef::Double(hdg), t);
    c.on_mail("DESIRED_SPEED", ValueRef::Double(spd), t);
    c.on_mail("DESIRED_DEPTH", ValueRef::Double(dep), t);
    let (nh, nd, np, ns) = nav;
    c.on_mail("NAV_HEADING", ValueRef::Double(nh), t);
    c.on_mail("NAV_DEPTH", ValueRef::Double(nd), t);
    c.on_mail("NAV_PITCH", ValueRef::Double(np), t);
    c.on_mail("NAV_SPEED", ValueRef::Double(ns), t);
}

fn num(out: &[Posting], var: &str) -> f64 {
    last_posting(out, var)
        .and_then(|v| v.as_f64())
        .unwrap_or_else(|| panic!("{var} not posted: {out:?}"))
}

/// One tick at `t` with the given desired and navigation values; the postings.
fn tick(
    c: &mut CougarsControl,
    t: f64,
    des: (f64, f64, f64),
    nav: (f64, f64, f64, f64),
) -> Vec<Posting> {
    feed(c, t, des, nav);
    let mut out = Vec::new();
    c.iterate(t, &mut out);
    out
}

#[test]
fn a_heading_error_to_starboard_gives_a_starboard_turning_top_fin() {
    // (desired compass, actual compass): each wants a clockwise (starboard) turn of 10°,
    // including across north (0/360) and across ENU ±180 (compass 270).
    for (des, nav) in [(100.0, 90.0), (5.0, 355.0), (275.0, 265.0), (185.0, 175.0)] {
        let mut c = armed(coug1());
        let out = tick(&mut c, 1.0, (des, 1.0, 0.0), (nav, 0.0, 0.0, 1.0));
        assert_eq!(c.mode(), &ControlsMode::Active);
        let top = num(&out, vars::FIN_DEFLECT_TOP_DEG);
        assert_eq!(
            top, 30.0,
            "{des} from {nav}: kp 3 x 10 degrees to starboard"
        );
        // coug1's top fin: direction +1, offset -10 in the servo frame.
        assert_eq!(num(&out, vars::FIN_TOP_DEG), 20.0);
        // To port: the other way.
        let mut c = armed(coug1());
        let out = tick(&mut c, 1.0, (nav, 1.0, 0.0), (des, 0.0, 0.0, 1.0));
        assert_eq!(num(&out, vars::FIN_DEFLECT_TOP_DEG), -30.0);
    }
}

#[test]
fn closed_loop_the_starboard_fin_turns_the_model_clockwise() {
    // The model's sign: a positive top fin deflection increases the compass heading.
    let m = CougUvModel::default();
    let mut s = CougUvState {
        surge: 1.0,
        heading: 90.0,
        ..CougUvState::default()
    };
    let cmd = UCommand {
        fin: [10.0, 0.0, 0.0],
        thruster: 50.0,
    };
    for _ in 0..20 {
        s = m.step(&s, &cmd, 0.1);
    }
    // 2.5 °/s at 1 m/s (k 0.25 x 10° x 1 m/s) behind the 1 s Nomoto lag: about 2.6° in 2 s.
    assert!(
        s.heading > 92.0 && s.heading < 93.0,
        "heading {}",
        s.heading
    );
}

#[test]
fn no_declination_is_added_to_the_true_heading() {
    // NAV_HEADING is true (the AHRS driver or uSimSensors applied the declination once):
    // on the desired heading the top fin is centred, whatever the heading.
    for h in [0.0, 10.7, 90.0, 200.0, 349.3] {
        let mut c = armed(coug1());
        let out = tick(&mut c, 1.0, (h, 1.0, 0.0), (h, 0.0, 0.0, 1.0));
        assert_eq!(num(&out, vars::FIN_DEFLECT_TOP_DEG), 0.0, "at {h}");
    }
}

#[test]
fn deeper_than_desired_gives_nose_up_fins() {
    // NAV_DEPTH positive down: at 4 m asked for 3 m, level, the elevator pitches nose up
    // (port positive, starboard negative), and the pitch reference is nose up.
    let mut c = armed(coug1());
    let mut out = Vec::new();
    for k in 1..=25 {
        out = tick(
            &mut c,
            f64::from(k) * 0.08,
            (90.0, 1.0, 3.0),
            (90.0, 4.0, 0.0, 1.0),
        );
    }
    assert!(num(&out, vars::COUG_PITCH_REF_DEG) > 0.0, "{out:?}");
    let (stbd, port) = (
        num(&out, vars::FIN_DEFLECT_STBD_DEG),
        num(&out, vars::FIN_DEFLECT_PORT_DEG),
    );
    assert!(port > 0.0 && stbd == -port, "stbd {stbd} port {port}");
    // Shallower than desired: nose down.
    let mut c = armed(coug1());
    for k in 1..=25 {
        out = tick(
            &mut c,
            f64::from(k) * 0.08,
            (90.0, 1.0, 3.0),
            (90.0, 2.0, 0.0, 1.0),
        );
    }
    assert!(num(&out, vars::FIN_DEFLECT_PORT_DEG) < 0.0);
    // And the model pitches nose up (MOOS pitch positive) under the first command.
    let m = CougUvModel::default();
    let mut s = CougUvState {
        surge: 1.0,
        ..CougUvState::default()
    };
    let cmd = UCommand {
        fin: [0.0, -10.0, 10.0],
        thruster: 50.0,
    };
    for _ in 0..30 {
        s = m.step(&s, &cmd, 0.1);
    }
    assert!(
        s.pitch < -0.02,
        "model pitch {} (nose down positive)",
        s.pitch
    );
}

#[test]
fn moos_pitch_is_nose_up_in_radians() {
    // NAV_PITCH +0.1 rad (nose up) is -5.73° in the cascade's nose-down convention.
    let mut c = armed(coug1());
    tick(&mut c, 1.0, (90.0, 1.0, 0.0), (90.0, 0.0, 0.1, 1.0));
    assert!((c.inputs().pitch + 0.1f64.to_degrees()).abs() < 1e-12);
    // Its rate from successive mail: +0.1 rad/s nose up is -5.73 °/s.
    c.on_mail("NAV_PITCH", ValueRef::Double(0.2), 2.0);
    assert!((c.inputs().pitch_rate + 0.1f64.to_degrees()).abs() < 1e-9);
    assert!(
        (c.inputs().heading - 0.0).abs() < 1e-12,
        "compass 90 is ENU 0"
    );
}

#[test]
fn outputs_stay_within_the_loop_limits() {
    // Full errors every way: rudder within ±45 (coug1), elevator within ±30, thrust ≤ 100.
    let mut c = armed(coug1());
    for k in 1..200 {
        let t = f64::from(k) * 0.08;
        let out = tick(&mut c, t, (270.0, 5.0, 10.0), (0.0, 0.0, 0.3, 0.2));
        let top = num(&out, vars::FIN_DEFLECT_TOP_DEG);
        let port = num(&out, vars::FIN_DEFLECT_PORT_DEG);
        assert!(top.abs() <= 45.0 && port.abs() <= 30.0, "{top} {port}");
        assert_eq!(
            num(&out, vars::THRUST_PCT),
            100.0,
            "5 m/s x 50 capped at 100"
        );
    }
    let mut c = armed(coug1());
    let out = tick(&mut c, 1.0, (200.0, 1.0, 0.0), (0.0, 0.0, 0.0, 1.0));
    assert_eq!(
        num(&out, vars::FIN_DEFLECT_TOP_DEG),
        -45.0,
        "160° to port saturates"
    );
    // max_thrust and the whole-percent truncation.
    let cfg = ControlsConfig::from_params([
        ("vehicle", "coug1"),
        ("speed_factor", "33.3"),
        ("max_thrust", "60"),
    ])
    .unwrap();
    let mut c = armed(cfg);
    let out = tick(&mut c, 1.0, (90.0, 1.0, 0.0), (90.0, 0.0, 0.0, 1.0));
    assert_eq!(num(&out, vars::THRUST_PCT), 33.0);
    let out = tick(&mut c, 1.08, (90.0, 3.0, 0.0), (90.0, 0.0, 0.0, 1.0));
    assert_eq!(num(&out, vars::THRUST_PCT), 60.0);
}

#[test]
fn not_armed_before_deploy_nor_under_manual_override() {
    let mut c = CougarsControl::new(coug1());
    let out = tick(&mut c, 1.0, (90.0, 1.0, 2.0), (80.0, 0.0, 0.0, 1.0));
    assert!(!out.iter().any(|p| p.key == vars::THRUST_PCT), "{out:?}");
    assert_eq!(
        last_posting(&out, vars::COUG_CONTROLS_STATE).and_then(|v| v.as_str()),
        Some("disarmed")
    );
    // Override false without DEPLOY: still disarmed (and the state is not posted again).
    c.on_mail("MOOS_MANUAL_OVERRIDE", ValueRef::String("false"), 1.0);
    let out = tick(&mut c, 1.5, (90.0, 1.0, 2.0), (80.0, 0.0, 0.0, 1.0));
    assert!(out.is_empty(), "{out:?}");
    // DEPLOY: armed, the cascade runs.
    c.on_mail("DEPLOY", ValueRef::String("true"), 2.0);
    let out = tick(&mut c, 2.0, (90.0, 1.0, 2.0), (80.0, 0.0, 0.0, 1.0));
    assert_eq!(num(&out, vars::THRUST_PCT), 50.0);
    assert_eq!(
        last_posting(&out, vars::COUG_CONTROLS_STATE).and_then(|v| v.as_str()),
        Some("active")
    );
    // The legacy single-R override disarms: one all-stop (zero deflections, the servo
    // frame at the offsets), then silence.
    c.on_mail("MOOS_MANUAL_OVERIDE", ValueRef::String("true"), 2.1);
    let out = tick(&mut c, 2.16, (90.0, 1.0, 2.0), (80.0, 0.0, 0.0, 1.0));
    assert_eq!(num(&out, vars::THRUST_PCT), 0.0);
    assert_eq!(num(&out, vars::FIN_DEFLECT_TOP_DEG), 0.0);
    assert_eq!(num(&out, vars::FIN_DEFLECT_PORT_DEG), 0.0);
    assert_eq!(num(&out, vars::FIN_TOP_DEG), -10.0, "coug1's top offset");
    let out = tick(&mut c, 2.24, (90.0, 1.0, 2.0), (80.0, 0.0, 0.0, 1.0));
    assert!(out.is_empty(), "{out:?}");
}

#[test]
fn all_stop_on_zero_speed_and_on_stale_inputs() {
    let mut c = armed(coug1());
    // The helm's all-stop: DESIRED_SPEED 0 (or below): thrust 0 and fins centred, every
    // iteration, whatever the heading and depth errors.
    for k in 0..3 {
        let out = tick(
            &mut c,
            1.0 + f64::from(k),
            (180.0, 0.0, 3.0),
            (90.0, 0.0, 0.0, 1.0),
        );
        assert_eq!(c.mode(), &ControlsMode::AllStop);
        assert_eq!(num(&out, vars::THRUST_PCT), 0.0);
        assert_eq!(num(&out, vars::FIN_DEFLECT_TOP_DEG), 0.0);
        assert_eq!(num(&out, vars::FIN_DEFLECT_STBD_DEG), 0.0);
    }
    // Navigation silent for more than 2 s: all-stop, naming what is stale.
    feed(&mut c, 10.0, (90.0, 1.0, 0.0), (90.0, 0.0, 0.0, 1.0));
    let mut out = Vec::new();
    c.iterate(10.5, &mut out);
    assert_eq!(c.mode(), &ControlsMode::Active);
    for v in ["DESIRED_HEADING", "DESIRED_SPEED", "DESIRED_DEPTH"] {
        c.on_mail(v, ValueRef::Double(1.0), 12.5);
    }
    out.clear();
    c.iterate(12.5, &mut out);
    assert_eq!(
        c.mode(),
        &ControlsMode::Stale(vec!["NAV_HEADING", "NAV_DEPTH", "NAV_PITCH"])
    );
    assert_eq!(num(&out, vars::THRUST_PCT), 0.0);
    assert_eq!(
        last_posting(&out, vars::COUG_CONTROLS_STATE).and_then(|v| v.as_str()),
        Some("stale: NAV_HEADING,NAV_DEPTH,NAV_PITCH")
    );
    // Never received at all: stale too (a fresh controller, armed, without any input).
    let mut c = armed(coug1());
    let mut out = Vec::new();
    c.iterate(0.1, &mut out);
    assert!(matches!(c.mode(), ControlsMode::Stale(v) if v.len() == 6));
    assert_eq!(num(&out, vars::THRUST_PCT), 0.0);
    // NAV_SPEED is watched only when the gain schedule uses it.
    let cfg = ControlsConfig::from_params([("vehicle", "coug1"), ("fixed_surge", "none")]);
    let mut c = armed(cfg.unwrap());
    c.iterate(0.1, &mut out);
    assert!(matches!(c.mode(), ControlsMode::Stale(v) if v.len() == 7));
}

#[test]
fn surface_command_puts_the_fins_up_and_keeps_the_thrust() {
    let mut c = armed(coug1());
    c.on_mail(vars::COUG_SURFACE, ValueRef::String("true"), 0.5);
    let out = tick(&mut c, 1.0, (90.0, 1.0, 3.0), (45.0, 1.0, 0.0, 1.0));
    assert_eq!(num(&out, vars::FIN_DEFLECT_TOP_DEG), 0.0);
    assert_eq!(num(&out, vars::FIN_DEFLECT_STBD_DEG), -30.0);
    assert_eq!(num(&out, vars::FIN_DEFLECT_PORT_DEG), 30.0, "nose up");
    assert_eq!(num(&out, vars::THRUST_PCT), 50.0);
    // coug1's servo frame: directions (1, -1, -1), top offset -10.
    assert_eq!(num(&out, vars::FIN_TOP_DEG), -10.0);
    assert_eq!(num(&out, vars::FIN_STBD_DEG), 30.0);
    assert_eq!(num(&out, vars::FIN_PORT_DEG), -30.0);
}

/// Surfaced with the fins up, then disarmed (pSafety's surface-then-disarm): one all-stop
/// with the thrust 0 and the fins centred (zero deflection, the servo frame's offsets), not
/// the fins-up command CoUGARs' kinematics keeps republishing; then nothing, and re-arming
/// later still finds the surface flag.
#[test]
fn disarming_under_the_surface_flag_centres_the_fins_and_stops_the_thrust() {
    let mut c = armed(coug1());
    c.on_mail(vars::COUG_SURFACE, ValueRef::String("true"), 0.5);
    let out = tick(&mut c, 1.0, (90.0, 1.0, 3.0), (45.0, 1.0, 0.0, 1.0));
    assert_eq!(
        num(&out, vars::FIN_DEFLECT_PORT_DEG),
        30.0,
        "fins up while armed"
    );
    c.on_mail("DEPLOY", ValueRef::String("false"), 1.05);
    let out = tick(&mut c, 1.1, (90.0, 1.0, 3.0), (45.0, 1.0, 0.0, 1.0));
    for (var, want) in [
        (vars::FIN_TOP_DEG, -10.0),
        (vars::FIN_STBD_DEG, 0.0),
        (vars::FIN_PORT_DEG, 0.0),
        (vars::THRUST_PCT, 0.0),
        (vars::FIN_DEFLECT_TOP_DEG, 0.0),
        (vars::FIN_DEFLECT_STBD_DEG, 0.0),
        (vars::FIN_DEFLECT_PORT_DEG, 0.0),
    ] {
        assert_eq!(num(&out, var), want, "{var}");
    }
    assert_eq!(c.mode(), &ControlsMode::Disarmed);
    assert_eq!(c.last_command().1.fin, [0.0; 3]);
    let out = tick(&mut c, 1.2, (90.0, 1.0, 3.0), (45.0, 1.0, 0.0, 1.0));
    assert!(
        out.iter()
            .all(|p| !p.key.starts_with("FIN_") && p.key != vars::THRUST_PCT),
        "nothing more while disarmed"
    );
    // Armed again under the flag: the fins go up again (the flag is the operator's to lift).
    c.on_mail("DEPLOY", ValueRef::String("true"), 1.25);
    let out = tick(&mut c, 1.3, (90.0, 1.0, 3.0), (45.0, 1.0, 0.0, 1.0));
    assert_eq!(num(&out, vars::FIN_DEFLECT_PORT_DEG), 30.0);
}

#[test]
fn a_negative_nav_depth_is_reported_once() {
    let mut c = armed(coug1());
    tick(&mut c, 1.0, (90.0, 1.0, 3.0), (90.0, -0.2, 0.0, 1.0));
    assert!(
        c.take_warnings().is_empty(),
        "surface noise is not an ENU z"
    );
    tick(&mut c, 1.1, (90.0, 1.0, 3.0), (90.0, -2.5, 0.0, 1.0));
    let w = c.take_warnings();
    assert_eq!(w.len(), 1);
    assert!(w[0].contains("positive down"), "{w:?}");
    tick(&mut c, 1.2, (90.0, 1.0, 3.0), (90.0, -2.6, 0.0, 1.0));
    assert!(c.take_warnings().is_empty());
}

#[test]
fn controls_config_presets_overrides_and_problems() {
    // The preset applies first wherever its line is; later keys override it.
    let c = ControlsConfig::from_params([("heading_kp", "2"), ("vehicle", "coug2")]).unwrap();
    assert_eq!(c.cougars.heading.kp, 2.0);
    assert_eq!(c.cougars.pitch, CougarsConfig::coug2().pitch);
    assert_eq!(c.cougars.kinematics, CougarsConfig::coug2().kinematics);
    let d = ControlsConfig::from_params([("AppTick", "10")]).unwrap();
    assert_eq!(
        d.cougars,
        CougarsConfig::default(),
        "no preset: declared defaults"
    );
    assert_eq!((d.speed_factor, d.max_thrust), (0.0, 100.0));
    // The gains tuned against the millisecond PID.
    let m =
        ControlsConfig::from_params([("vehicle", "coug1"), ("ms_tuned_gains", "true")]).unwrap();
    assert!((m.cougars.pitch.ki - 0.2).abs() < 1e-12);
    assert!((m.cougars.depth.kd - 1e-6).abs() < 1e-15);
    let (c, problems) = ControlsConfig::from_params_lenient([
        ("vehicle", "coug9"),
        ("speed_factor", "-1"),
        ("colour", "red"),
        ("pitch_kp", "0.5"),
    ])
    .unwrap();
    assert_eq!(problems.len(), 3, "{problems:?}");
    assert!(matches!(&problems[0], ConfigError::BadValue { key, .. } if key == "vehicle"));
    assert!(matches!(&problems[1], ConfigError::BadValue { key, .. } if key == "speed_factor"));
    assert!(matches!(&problems[2], ConfigError::UnknownKey { key, .. } if key == "colour"));
    assert_eq!((c.speed_factor, c.cougars.pitch.kp), (0.0, 0.5));
}

// ---------------------------------------------------------------------------------------
// Large steps: a real-time run starved for 5 s of wall time at a warp of 8.

/// pCougControls closing the loop on uSimCougUV (the mission's settings), both at 12.5 Hz,
/// with a stall of 40 simulated seconds mid-dive: neither iterates, then each takes the
/// whole gap in one step. The PID loops run on their fixed period (the C++ `Ts`), so the
/// gap enters only the rates taken from successive NAV samples; the controller first sees
/// its inputs stale (all-stop), then resumes, and the vehicle is back at the set depth with
/// every number finite and every fin within its limit (the controller's, the model's 25°).
#[test]
fn a_forty_second_stall_mid_dive_leaves_the_loop_finite_and_recovering() {
    use vehicle::couguv::{CougUvSim, CougUvSimConfig};
    let cfg = common::mission_controls();
    let mut c = armed(cfg);
    let mut sim = CougUvSim::new(
        CougUvSimConfig::from_params([
            ("prefix", "NAV"),
            ("start_pos", "heading=90"),
            ("buoyancy_rate", "0.05"),
        ])
        .unwrap(),
        None,
    );
    let mut nav: Vec<Posting> = Vec::new();
    let mut modes = Vec::new();
    let mut worst_fin: f64 = 0.0;
    // The mail of the previous tick (the helm's set-points, the simulator's NAV_*) is
    // stamped with that tick's time, as it was posted then: after the stall it is 40 s old.
    let mut posted = 0.0;
    let mut run = |c: &mut CougarsControl, sim: &mut CougUvSim, times: &[f64]| {
        for &t in times {
            for (k, v) in [
                ("DESIRED_HEADING", 180.0),
                ("DESIRED_SPEED", 1.0),
                ("DESIRED_DEPTH", 3.0),
            ] {
                c.on_mail(k, ValueRef::Double(v), posted);
            }
            for p in nav.drain(..) {
                if let Some(v) = p.value.as_f64() {
                    c.on_mail(&p.key, ValueRef::Double(v), posted);
                }
            }
            posted = t;
            let mut cmds = Vec::new();
            c.iterate(t, &mut cmds);
            modes.push(c.mode().clone());
            for p in &cmds {
                let Some(v) = p.value.as_f64() else { continue };
                assert!(v.is_finite(), "{} = {v} at {t}", p.key);
                if p.key.starts_with("FIN_DEFLECT") {
                    worst_fin = worst_fin.max(v.abs());
                }
                sim.on_mail(&p.key, ValueRef::Double(v), t);
            }
            sim.iterate(t, &mut nav);
            nav.retain(|p| p.key.starts_with("NAV_"));
            assert!(sim.truth().is_finite(), "{:?} at {t}", sim.truth());
        }
    };
    let ticks = |from: f64, to: f64| -> Vec<f64> {
        (0..=((to - from) / 0.08).round() as u32)
            .map(|k| from + f64::from(k) * 0.08)
            .collect()
    };
    run(&mut c, &mut sim, &ticks(0.0, 120.0));
    let before = *sim.truth();
    assert!((before.body.depth - 3.0).abs() < 0.3, "{before:?}");
    // The stall: the next iteration of both 40 s later.
    run(&mut c, &mut sim, &ticks(160.0, 280.0));
    assert!(
        matches!(modes[modes.len() - 1501], ControlsMode::Stale(_)),
        "all-stop on the stale inputs: {:?}",
        &modes[modes.len() - 1502..modes.len() - 1495]
    );
    assert_eq!(modes.last(), Some(&ControlsMode::Active));
    let s = c.state();
    for pid in [&s.depth_pid, &s.pitch_pid, &s.heading_pid] {
        assert!(pid.integrator().is_finite(), "{s:?}");
    }
    let after = *sim.truth();
    assert!((after.body.depth - 3.0).abs() < 0.3, "{after:?}");
    let lim = coug1().cougars;
    assert!(
        worst_fin <= lim.pitch.max.max(lim.heading.max) + 1e-9,
        "{worst_fin}"
    );
    assert!(
        after.body.fins.iter().all(|f| f.abs() <= 25.0 + 1e-9),
        "{after:?}"
    );
    assert!((after.body.surge - 1.0).abs() < 0.05, "{after:?}");
}

/// NAV samples a microsecond apart (a burst delivered at once after a stall) give rates of
/// thousands per second: the loops saturate for that tick, every output stays finite and
/// within its limits, and the next ordinary tick is back to normal.
#[test]
fn nav_samples_a_microsecond_apart_saturate_but_never_blow_up() {
    let mut c = armed(coug1());
    let des = (90.0, 1.0, 2.0);
    for k in 0..50 {
        let t = f64::from(k) * 0.08;
        let _ = tick(&mut c, t, des, (90.0, 2.0, 0.0, 1.0));
    }
    let t = 4.0;
    feed(&mut c, t, des, (90.0, 2.0, 0.0, 1.0));
    feed(&mut c, t + 1e-6, des, (90.0, 2.5, -0.2, 1.0));
    let mut out = Vec::new();
    c.iterate(t + 1e-6, &mut out);
    for p in &out {
        if let Some(v) = p.value.as_f64() {
            assert!(v.is_finite(), "{} = {v}", p.key);
        }
    }
    let lim = coug1().cougars.pitch.max;
    let port = num(&out, vars::FIN_DEFLECT_PORT_DEG);
    assert!(port.abs() <= lim + 1e-9, "{port}");
    let s = c.state();
    assert!(s.pitch_pid.integrator().is_finite() && s.depth_pid.integrator().is_finite());
    let out = tick(&mut c, t + 0.08, des, (90.0, 2.5, -0.2, 1.0));
    assert!(num(&out, vars::FIN_DEFLECT_PORT_DEG).is_finite());
}
