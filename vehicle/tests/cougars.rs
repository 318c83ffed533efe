//! CoUGARs cascade, mixing and actuators.

use vehicle::ValueRef;
use vehicle::cougars::{
    Actuators, ControllerInputs, CougPid, CougUvModel, CougUvState, CougarsConfig, CougarsControl,
    CougarsState, Gains, Kinematics, UCommand, compass_to_enu, pitch_schedule_constant, step,
};
use vehicle::moos::last_posting;

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

#[test]
fn moos_adapter_starts_on_override_false_and_maps_units() {
    let mut c = CougarsControl::new(CougarsConfig::coug1(), 0.0);
    let mut out = Vec::new();
    c.on_mail("DESIRED_HEADING", ValueRef::Double(100.0), 0.0);
    c.on_mail("NAV_HEADING", ValueRef::Double(90.0), 0.0);
    c.on_mail("DESIRED_SPEED", ValueRef::Double(30.0), 0.0);
    c.on_mail("NAV_PITCH", ValueRef::Double(-0.1), 0.0);
    assert!(
        (c.inputs().pitch - 0.1f64.to_degrees()).abs() < 1e-12,
        "MOOS nose-down pitch is negative"
    );
    c.iterate(0.08, &mut out);
    assert!(out.is_empty(), "nothing before the start signal");
    c.on_mail("MOOS_MANUAL_OVERRIDE", ValueRef::String("false"), 0.1);
    c.iterate(10.0, &mut out);
    assert_eq!(
        last_posting(&out, "DESIRED_RUDDER").unwrap().as_f64(),
        Some(30.0)
    );
    assert_eq!(
        last_posting(&out, "DESIRED_THRUST").unwrap().as_f64(),
        Some(30.0)
    );
    assert_eq!(
        last_posting(&out, "COUG_FIN_0").unwrap().as_f64(),
        Some(20.0),
        "offset -10"
    );
    // 30 % -> 1100 + (30 + 100) * 800 / 200 us, the arming delay (7 s) being over at t = 10.
    assert_eq!(
        last_posting(&out, "COUG_THRUSTER_US").unwrap().as_f64(),
        Some(1620.0)
    );
    out.clear();
    c.on_mail("MOOS_MANUAL_OVERRIDE", ValueRef::String("true"), 10.1);
    c.iterate(10.2, &mut out);
    assert_eq!(
        last_posting(&out, "DESIRED_THRUST").unwrap().as_f64(),
        Some(0.0),
        "one stop command"
    );
    out.clear();
    c.iterate(10.3, &mut out);
    assert!(out.is_empty());
}

#[test]
fn config_from_params() {
    let cfg = CougarsConfig::from_params([
        ("depth_kp", "25"),
        ("depth_ki", "0.005"),
        ("depth_kd", "0.001"),
        ("depth_min_output", "-15"),
        ("depth_max_output", "15"),
        ("fin_1_direction", "-1"),
        ("top_fin_offset", "-10"),
        ("fixed_surge", "none"),
        ("timer_period", "100"),
    ])
    .unwrap();
    assert_eq!(cfg.depth, Gains::new(25.0, 0.005, 0.001, 15.0));
    assert_eq!(cfg.kinematics.direction, [1.0, -1.0, 1.0]);
    assert_eq!(cfg.fixed_surge, None);
    assert_eq!(cfg.ts(), 0.1);
    assert!(CougarsConfig::from_params([("fin_0_direction", "2")]).is_err());
    assert!(CougarsConfig::from_params([("depth_gain", "2")]).is_err());
}
