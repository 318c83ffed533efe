//! CoUGARs (BYU FRoSt Lab, Gen-1) controllers: heading PID to the top fin, the nested
//! depth -> pitch -> elevator-fin cascade, fin mixing ("kinematics"), the Teensy actuator
//! mapping to PWM microseconds, and a simple CougUV pitch/depth model to close the loop.
//!
//! Conventions (as on the vehicle): depth metres positive down; heading degrees ENU
//! (0 = east, counter-clockwise positive, -180..180); pitch degrees, positive nose down;
//! fins in degrees, `fin[0]` top (rudder), `fin[1]` starboard, `fin[2]` port; thruster percent.
//!
//! # Units fixed relative to the original code
//!
//! * The original PID class received the loop period as the integer `timer_period` in
//!   **milliseconds** (80) and used it as `Ts` in seconds. That made the dirty-derivative
//!   coefficient `beta = (2σ - Ts)/(2σ + Ts)` ≈ -0.9975 (an oscillating filter instead of a
//!   low-pass), the integrals 1000× too large and finite-difference rates 1000× too small.
//!   Here `Ts` is in **seconds** (0.08 s gives beta ≈ 0.111). Gains are taken as written, in
//!   per-second units; [`Gains::from_ms_tuned`] converts gains tuned against the old
//!   behaviour (ki × 1000, kd / 1000) for whoever wants the field integral strength back.
//! * The pitch-rate input of the pitch loop was the gyro rate in **rad/s** while pitch was in
//!   degrees; here it is degrees/s.
//! * The depth-reference filter already used seconds in the original; unchanged.
//! * The gain-scheduled pitch loop divided by `ki` in its back-calculation anti-windup (a
//!   division by zero for `ki = 0`, the coug2 setting): here the integrator is simply reset
//!   when `ki = 0`. The schedule `1/(u² k)` is also guarded against `u = 0` by
//!   `min_schedule_speed`.
//! * The surge speed used for gain scheduling was overridden with a constant 0.6 m/s on the
//!   vehicle; that stays the default (`fixed_surge = 0.6`) because the field gains were tuned
//!   with it, and `fixed_surge = none` uses the measured speed instead.

use moos_types::ByteString;

use crate::angle::angle180;
use crate::config::{ConfigError, Param, apply_params, parse_number, strict};
use crate::moos::{Posting, ValueRef};

const APP: &str = "coug_controls";

/// Time constant of the dirty derivative, seconds (σ of the original "ECEn 483" PID).
pub const SIGMA: f64 = 0.05;

/// Gain-scheduling constant `0.5 · 997 · 0.00665 · 0.5 · (-0.43) · cos 30°` (negative: a
/// negative elevator fin pitches the nose down).
pub fn pitch_schedule_constant() -> f64 {
    0.5 * 997.0 * 0.00665 * 0.5 * (-0.43) * 30f64.to_radians().cos()
}

/// One loop's gains and output limits.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Gains {
    /// Proportional gain.
    pub kp: f64,
    /// Integral gain (per second).
    pub ki: f64,
    /// Derivative gain (seconds).
    pub kd: f64,
    /// Lower output limit.
    pub min: f64,
    /// Upper output limit.
    pub max: f64,
}

impl Gains {
    /// Gains with symmetric limits `±limit`.
    pub fn new(kp: f64, ki: f64, kd: f64, limit: f64) -> Self {
        Gains {
            kp,
            ki,
            kd,
            min: -limit.abs(),
            max: limit.abs(),
        }
    }

    /// Converts gains tuned against the original millisecond-interval PID into the
    /// per-second gains that reproduce the same integral and derivative action here.
    pub fn from_ms_tuned(self) -> Self {
        Gains {
            ki: self.ki * 1000.0,
            kd: self.kd / 1000.0,
            ..self
        }
    }
}

/// The CoUGARs PID ("BYU ECEn 483 approach"): trapezoidal integrator, dirty derivative.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct CougPid {
    /// Gains and limits.
    pub gains: Gains,
    ts: f64,
    beta: f64,
    integrator: f64,
    error_prev: f64,
    x_prev: f64,
    x_dot: f64,
}

impl CougPid {
    /// A loop sampled every `ts` seconds.
    pub fn new(gains: Gains, ts: f64) -> Self {
        CougPid {
            gains,
            ts,
            beta: (2.0 * SIGMA - ts) / (2.0 * SIGMA + ts),
            integrator: 0.0,
            error_prev: 0.0,
            x_prev: 0.0,
            x_dot: 0.0,
        }
    }

    /// The dirty-derivative coefficient.
    pub fn beta(&self) -> f64 {
        self.beta
    }

    /// The integrator state.
    pub fn integrator(&self) -> f64 {
        self.integrator
    }

    /// Zeroes the integrator.
    pub fn reset_integrator(&mut self) {
        self.integrator = 0.0;
    }

    fn sat(&self, u: f64) -> f64 {
        u.clamp(self.gains.min, self.gains.max)
    }

    /// Setpoint `r`, measurement `x`; derivative estimated from `x`; integrates only while
    /// `|x_dot| < 0.08` (on/off anti-windup). Used for heading.
    pub fn compute(&mut self, r: f64, x: f64) -> f64 {
        let e = r - x;
        if self.x_dot.abs() < 0.08 {
            self.integrator += self.ts / 2.0 * (e + self.error_prev);
        }
        self.x_dot = self.beta * self.x_dot + (1.0 - self.beta) * (x - self.x_prev) / self.ts;
        let u = self.gains.kp * e + self.gains.ki * self.integrator - self.gains.kd * self.x_dot;
        self.error_prev = e;
        self.x_prev = x;
        self.sat(u)
    }

    /// As [`CougPid::compute`] with the measured rate `x_dot`, no anti-windup. Used for depth.
    pub fn compute_with_rate(&mut self, r: f64, x: f64, x_dot: f64) -> f64 {
        let e = r - x;
        self.integrator += self.ts / 2.0 * (e + self.error_prev);
        let u = self.gains.kp * e + self.gains.ki * self.integrator - self.gains.kd * x_dot;
        self.error_prev = e;
        self.x_prev = x;
        self.sat(u)
    }

    /// Gain-scheduled by dynamic pressure: every term divided by `s = u² · k`, with
    /// back-calculation anti-windup. Used for pitch.
    pub fn compute_scheduled(&mut self, r: f64, x: f64, x_dot: f64, s: f64) -> f64 {
        let e = r - x;
        self.integrator += self.ts / 2.0 * (e + self.error_prev);
        let p = self.gains.kp * e / s;
        let d = self.gains.kd * x_dot / s;
        let i = self.gains.ki * self.integrator / s;
        let pd = p - d;
        let raw = pd + i;
        let u = self.sat(raw);
        if u != raw {
            if pd.abs() > u.abs() || self.gains.ki == 0.0 {
                self.integrator = 0.0;
            } else {
                self.integrator = (u - pd) * s / self.gains.ki;
            }
        }
        self.error_prev = e;
        self.x_prev = x;
        u
    }
}

/// Fin mixing and arming ("coug_kinematics").
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Kinematics {
    /// `fin_0/1/2_direction` (±1).
    pub direction: [f64; 3],
    /// `top_fin_offset`, `right_fin_offset`, `left_fin_offset`, degrees.
    pub offset: [f64; 3],
    /// `trim_ratio`: degrees of fin per percent of thrust.
    pub trim_ratio: f64,
    /// `demo_mode`: thruster 0 and fins doubled.
    pub demo_mode: bool,
}

impl Default for Kinematics {
    fn default() -> Self {
        Kinematics {
            direction: [1.0; 3],
            offset: [0.0; 3],
            trim_ratio: 0.0,
            demo_mode: false,
        }
    }
}

/// Elevator angle of the "fins up" surface command, degrees.
pub const SURFACE_FIN: f64 = 30.0;

impl Kinematics {
    /// coug1's field values: top offset -10°, directions (1, -1, -1).
    pub fn coug1() -> Self {
        Kinematics {
            direction: [1.0, -1.0, -1.0],
            offset: [-10.0, 0.0, 0.0],
            ..Kinematics::default()
        }
    }

    /// Mixes a controller command into servo angles: `dir·fin + offset + trim_ratio·thrust`.
    /// Thrust is 0 unless `armed`; `surface` replaces the fins with the fins-up command.
    pub fn mix(&self, cmd: &UCommand, armed: bool, surface: bool) -> UCommand {
        let thrust = if armed && !self.demo_mode {
            cmd.thruster
        } else {
            0.0
        };
        let fins_in = if surface {
            [0.0, -SURFACE_FIN, SURFACE_FIN]
        } else {
            cmd.fin
        };
        let mut fin = [0.0; 3];
        for i in 0..3 {
            let mut v = self.direction[i] * fins_in[i] + self.offset[i];
            if !surface {
                v += self.trim_ratio * thrust;
            }
            if self.demo_mode {
                v *= 2.0;
            }
            fin[i] = v;
        }
        UCommand {
            fin,
            thruster: thrust,
        }
    }
}

/// Teensy actuator mapping (serial firmware).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Actuators {
    /// Servo pulse at 0°, µs (coug1 500, coug2 1000).
    pub servo_min_us: f64,
    /// Servo pulse at 180°, µs (coug1 2500, coug2 2000).
    pub servo_max_us: f64,
    /// Thruster pulse at -100 %, µs (1100).
    pub thruster_min_us: i64,
    /// Thruster pulse at +100 %, µs (1900).
    pub thruster_max_us: i64,
    /// Command-loss failsafe, seconds (5).
    pub failsafe_s: f64,
    /// ESC arming delay after boot, seconds (7).
    pub arm_delay_s: f64,
}

impl Default for Actuators {
    fn default() -> Self {
        Actuators {
            servo_min_us: 500.0,
            servo_max_us: 2500.0,
            thruster_min_us: 1100,
            thruster_max_us: 1900,
            failsafe_s: 5.0,
            arm_delay_s: 7.0,
        }
    }
}

/// PWM outputs to the three servos and the ESC.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Pwm {
    /// Servo pulses, µs.
    pub servo_us: [u16; 3],
    /// Thruster pulse, µs.
    pub thruster_us: u16,
}

/// Neutral thruster pulse, µs.
pub const THRUSTER_NEUTRAL_US: u16 = 1500;

impl Actuators {
    /// Servo pulse for a fin angle: the angle is truncated to whole degrees, offset by 90 and
    /// clamped to 0..180, then mapped linearly onto the pulse range.
    pub fn servo_us(&self, fin_deg: f64) -> u16 {
        let angle = (fin_deg.trunc() + 90.0).clamp(0.0, 180.0);
        (self.servo_min_us + angle * (self.servo_max_us - self.servo_min_us) / 180.0).round() as u16
    }

    /// Thruster pulse for a percent (integer `map(-100..100 -> min..max)`, as Arduino's `map`).
    pub fn thruster_us(&self, percent: f64) -> u16 {
        let x = (percent.trunc() as i64).clamp(-100, 100);
        let us =
            (x + 100) * (self.thruster_max_us - self.thruster_min_us) / 200 + self.thruster_min_us;
        us.clamp(0, i64::from(u16::MAX)) as u16
    }

    /// Outputs at `now` (seconds since boot), given the last command and when it arrived.
    /// Before the arming delay the ESC is held neutral; after `failsafe_s` without a command
    /// servos centre (90°) and the ESC goes neutral.
    pub fn outputs(&self, cmd: Option<(&UCommand, f64)>, now: f64) -> Pwm {
        let centre = self.servo_us(0.0);
        match cmd {
            Some((c, t)) if now - t <= self.failsafe_s => Pwm {
                servo_us: [
                    self.servo_us(c.fin[0]),
                    self.servo_us(c.fin[1]),
                    self.servo_us(c.fin[2]),
                ],
                thruster_us: if now < self.arm_delay_s {
                    THRUSTER_NEUTRAL_US
                } else {
                    self.thruster_us(c.thruster)
                },
            },
            _ => Pwm {
                servo_us: [centre; 3],
                thruster_us: THRUSTER_NEUTRAL_US,
            },
        }
    }
}

/// Controller configuration (the ROS parameters of `coug_controls`).
#[derive(Debug, Clone, PartialEq)]
pub struct CougarsConfig {
    /// Loop period, milliseconds (`timer_period`, 80).
    pub timer_period_ms: f64,
    /// Depth loop: output is the pitch reference, degrees.
    pub depth: Gains,
    /// Pitch loop: output is the elevator fin, degrees.
    pub pitch: Gains,
    /// Heading loop: output is the rudder (top fin), degrees.
    pub heading: Gains,
    /// Depth-reference filter natural frequency, rad/s (`wn_d_z`, 0.09).
    pub wn_d_z: f64,
    /// Saturated-mode pitch-reference filter natural frequency, rad/s (`wn_d_theta`, 0.25).
    pub wn_d_theta: f64,
    /// Depth error beyond which the outer loop saturates, m (`outer_loop_threshold`, 2.5).
    pub outer_loop_threshold: f64,
    /// Depth-reference lead in saturated mode, m (`saturation_offset`, 1.7).
    pub saturation_offset: f64,
    /// Below this surge speed the elevator is zeroed (`surge_threshold`, -1).
    pub surge_threshold: f64,
    /// Surge speed used for gain scheduling, m/s (`fixed_surge`, 0.6 as on the vehicle;
    /// `None` = measured).
    pub fixed_surge: Option<f64>,
    /// Lowest |surge| used in the schedule, m/s (`min_schedule_speed`, 0.1).
    pub min_schedule_speed: f64,
    /// Fin mixing.
    pub kinematics: Kinematics,
    /// PWM mapping.
    pub actuators: Actuators,
}

impl Default for CougarsConfig {
    /// Declared defaults of the node: all gains 0.
    fn default() -> Self {
        CougarsConfig {
            timer_period_ms: 80.0,
            depth: Gains::new(0.0, 0.0, 0.0, 0.0),
            pitch: Gains::new(0.0, 0.0, 0.0, 0.0),
            heading: Gains::new(0.0, 0.0, 0.0, 0.0),
            wn_d_z: 0.09,
            wn_d_theta: 0.25,
            outer_loop_threshold: 2.5,
            saturation_offset: 1.7,
            surge_threshold: -1.0,
            fixed_surge: Some(0.6),
            min_schedule_speed: 0.1,
            kinematics: Kinematics::default(),
            actuators: Actuators::default(),
        }
    }
}

impl CougarsConfig {
    /// coug1's field configuration (base:mission_control/params/coug1_params.yaml).
    pub fn coug1() -> Self {
        CougarsConfig {
            depth: Gains::new(25.0, 0.005, 0.001, 15.0),
            pitch: Gains::new(0.40, 0.0002, 0.0, 30.0),
            heading: Gains::new(3.0, 0.0, 0.0, 45.0),
            wn_d_z: 0.30,
            wn_d_theta: 0.15,
            kinematics: Kinematics::coug1(),
            ..CougarsConfig::default()
        }
    }

    /// coug2's field configuration.
    pub fn coug2() -> Self {
        CougarsConfig {
            depth: Gains::new(20.0, 0.0, 0.0, 15.0),
            pitch: Gains::new(0.45, 0.0, 0.7, 40.0),
            heading: Gains::new(3.0, 0.0, 0.0, 35.0),
            wn_d_z: 0.30,
            wn_d_theta: 0.15,
            kinematics: Kinematics {
                direction: [1.0, 1.0, 1.0],
                offset: [0.0, -20.0, 45.0],
                ..Kinematics::default()
            },
            actuators: Actuators {
                servo_min_us: 1000.0,
                servo_max_us: 2000.0,
                ..Actuators::default()
            },
            ..CougarsConfig::default()
        }
    }

    /// Loop period in seconds.
    pub fn ts(&self) -> f64 {
        self.timer_period_ms / 1000.0
    }

    /// Strict construction from `(key, value)` pairs. Keys: `timer_period` (ms; also the
    /// YAML's `pid_timer_period`, which the original node ignored), `depth_kp|ki|kd`,
    /// `depth_min_output|max_output` (likewise `pitch_*`, `heading_*`), `wn_d_z`,
    /// `wn_d_theta`, `outer_loop_threshold`, `saturation_offset`, `surge_threshold`,
    /// `fixed_surge` (number or `none`), `min_schedule_speed`, `fin_0|1|2_direction`,
    /// `top_fin_offset`, `right_fin_offset`, `left_fin_offset`, `trim_ratio`, `demo_mode`,
    /// `servo_min_us`, `servo_max_us`, `thruster_min_us`, `thruster_max_us`.
    pub fn from_params<'a>(
        params: impl IntoIterator<Item = (&'a str, &'a str)>,
    ) -> Result<Self, ConfigError> {
        strict(Self::from_params_lenient(params))
    }

    /// As [`CougarsConfig::from_params`], with unknown keys returned as non-fatal errors.
    pub fn from_params_lenient<'a>(
        params: impl IntoIterator<Item = (&'a str, &'a str)>,
    ) -> Result<(Self, Vec<ConfigError>), ConfigError> {
        let mut cfg = CougarsConfig::default();
        let unknown = apply_params(APP, &mut cfg, params, Self::apply_one)?;
        Ok((cfg, unknown))
    }

    fn apply_one(&mut self, key: &str, p: Param<'_>) -> Result<bool, ConfigError> {
        let dir = |p: &Param<'_>| match parse_number(p.value) {
            Some(v) if v == 1.0 || v == -1.0 => Ok(v),
            _ => Err(p.bad("1 or -1")),
        };
        if let Some((loop_name, field)) = key.split_once('_') {
            let g = match loop_name {
                "depth" => Some(&mut self.depth),
                "pitch" => Some(&mut self.pitch),
                "heading" => Some(&mut self.heading),
                _ => None,
            };
            if let Some(g) = g {
                match field {
                    "kp" => g.kp = p.f64()?,
                    "ki" => g.ki = p.f64()?,
                    "kd" => g.kd = p.f64()?,
                    "min_output" => g.min = p.f64()?,
                    "max_output" => g.max = p.f64()?,
                    _ => return Ok(false),
                }
                return Ok(true);
            }
        }
        match key {
            "timer_period" | "pid_timer_period" => self.timer_period_ms = p.pos()?,
            "wn_d_z" => self.wn_d_z = p.non_neg()?,
            "wn_d_theta" => self.wn_d_theta = p.non_neg()?,
            "outer_loop_threshold" => self.outer_loop_threshold = p.non_neg()?,
            "saturation_offset" => self.saturation_offset = p.non_neg()?,
            "surge_threshold" => self.surge_threshold = p.f64()?,
            "fixed_surge" => {
                self.fixed_surge = if p.value.eq_ignore_ascii_case("none") {
                    None
                } else {
                    Some(p.f64()?)
                }
            }
            "min_schedule_speed" => self.min_schedule_speed = p.pos()?,
            "fin_0_direction" => self.kinematics.direction[0] = dir(&p)?,
            "fin_1_direction" => self.kinematics.direction[1] = dir(&p)?,
            "fin_2_direction" => self.kinematics.direction[2] = dir(&p)?,
            "top_fin_offset" => self.kinematics.offset[0] = p.f64()?,
            "right_fin_offset" => self.kinematics.offset[1] = p.f64()?,
            "left_fin_offset" => self.kinematics.offset[2] = p.f64()?,
            "trim_ratio" => self.kinematics.trim_ratio = p.f64()?,
            "demo_mode" => self.kinematics.demo_mode = p.bool()?,
            "servo_min_us" => self.actuators.servo_min_us = p.non_neg()?,
            "servo_max_us" => self.actuators.servo_max_us = p.non_neg()?,
            "thruster_min_us" => self.actuators.thruster_min_us = p.non_neg()? as i64,
            "thruster_max_us" => self.actuators.thruster_max_us = p.non_neg()? as i64,
            _ => return Ok(false),
        }
        Ok(true)
    }
}

/// Setpoints and measurements of one controller tick.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct ControllerInputs {
    /// Desired depth, m (positive down), or desired altitude when `dfb`.
    pub desired_depth: f64,
    /// Depth-from-bottom mode.
    pub dfb: bool,
    /// Desired heading, degrees ENU.
    pub desired_heading: f64,
    /// Desired speed = thruster percent (Gen-1).
    pub desired_speed: f64,
    /// Depth, m.
    pub depth: f64,
    /// Altitude above the bottom, m (DVL).
    pub altitude: f64,
    /// Depth rate, m/s (positive down).
    pub depth_rate: f64,
    /// Pitch, degrees (positive nose down).
    pub pitch: f64,
    /// Pitch rate, degrees/s.
    pub pitch_rate: f64,
    /// Heading, degrees ENU.
    pub heading: f64,
    /// Measured surge speed, m/s.
    pub surge: f64,
}

/// A fin/thruster command (`UCommand`): fins in degrees, thruster percent.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct UCommand {
    /// `[top, starboard, port]`, degrees.
    pub fin: [f64; 3],
    /// Thruster, percent.
    pub thruster: f64,
}

/// Controller memory.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct CougarsState {
    /// Depth loop.
    pub depth_pid: CougPid,
    /// Pitch loop.
    pub pitch_pid: CougPid,
    /// Heading loop.
    pub heading_pid: CougPid,
    /// Filtered depth reference, m.
    pub z_ref: f64,
    /// Pitch reference, degrees.
    pub theta_ref: f64,
    /// Last desired depth seen (a change re-initialises `z_ref`).
    pub last_desired_depth: Option<f64>,
    /// Pitch fin of the last tick (before mixing), degrees.
    pub pitch_fin: f64,
    /// True when the last tick ran in saturated outer-loop mode.
    pub saturated_mode: bool,
}

impl CougarsState {
    /// Fresh loops from a config.
    pub fn new(cfg: &CougarsConfig) -> Self {
        let ts = cfg.ts();
        CougarsState {
            depth_pid: CougPid::new(cfg.depth, ts),
            pitch_pid: CougPid::new(cfg.pitch, ts),
            heading_pid: CougPid::new(cfg.heading, ts),
            z_ref: 0.0,
            theta_ref: 0.0,
            last_desired_depth: None,
            pitch_fin: 0.0,
            saturated_mode: false,
        }
    }
}

/// One controller tick (period `cfg.timer_period_ms`). Returns the command before mixing:
/// `fin = [rudder, -pitch_fin, +pitch_fin]`, `thruster = desired_speed`.
pub fn step(
    cfg: &CougarsConfig,
    state: &CougarsState,
    inp: &ControllerInputs,
) -> (CougarsState, UCommand) {
    let mut s = *state;
    let ts = cfg.ts();
    let (tracked, hold) = if inp.dfb {
        (inp.altitude, -1.0)
    } else {
        (inp.depth, 1.0)
    };

    // A new desired depth restarts the reference from where the vehicle is.
    let changed = s
        .last_desired_depth
        .is_none_or(|d| (d - inp.desired_depth).abs() > 1e-6);
    if changed {
        s.z_ref = tracked;
        s.last_desired_depth = Some(inp.desired_depth);
    }

    if inp.surge < cfg.surge_threshold {
        s.theta_ref = inp.pitch;
        s.pitch_fin = 0.0;
    } else {
        let z_d = inp.desired_depth;
        let az = (-ts * cfg.wn_d_z).exp();
        s.z_ref = az * s.z_ref + (1.0 - az) * z_d;
        let err = z_d - tracked;
        if err.abs() > cfg.outer_loop_threshold {
            s.saturated_mode = true;
            let theta_d = cfg.depth.max * err.signum() * hold;
            let at = (-ts * cfg.wn_d_theta).exp();
            s.theta_ref = at * s.theta_ref + (1.0 - at) * theta_d;
            s.z_ref = tracked + cfg.saturation_offset * err.signum();
            s.depth_pid.reset_integrator();
        } else {
            s.saturated_mode = false;
            let rate = if inp.dfb {
                -inp.depth_rate
            } else {
                inp.depth_rate
            };
            s.theta_ref = s.depth_pid.compute_with_rate(s.z_ref, tracked, rate) * hold;
        }
        let u = cfg.fixed_surge.unwrap_or(inp.surge);
        let u = if u.abs() < cfg.min_schedule_speed {
            cfg.min_schedule_speed
        } else {
            u
        };
        let sched = u * u * pitch_schedule_constant();
        s.pitch_fin = s
            .pitch_pid
            .compute_scheduled(s.theta_ref, inp.pitch, inp.pitch_rate, sched)
            .trunc();
    }

    let yaw_err = angle180(inp.desired_heading - inp.heading);
    let rudder = s.heading_pid.compute(0.0, yaw_err).trunc();
    let cmd = UCommand {
        fin: [rudder, -s.pitch_fin, s.pitch_fin],
        thruster: inp.desired_speed,
    };
    (s, cmd)
}

/// Compass heading (MOOS, degrees clockwise from north) to ENU degrees in (-180, 180], as the
/// MOOS bridge converted `DESIRED_HEADING`.
pub fn compass_to_enu(compass: f64) -> f64 {
    angle180(90.0 - compass)
}

/// Parameters of the simple CougUV pitch/depth/heading model (Gen-1 simulation values:
/// `torpedo_3fin.json`).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct CougUvModel {
    /// Mass, kg (31.03).
    pub mass: f64,
    /// Length, m (1.6).
    pub length: f64,
    /// Diameter, m (0.19).
    pub diameter: f64,
    /// Water density, kg/m³ (1026).
    pub rho: f64,
    /// Centre of gravity below buoyancy, m (0.02).
    pub r_bg: f64,
    /// Pitch damping ratio (0.8).
    pub zeta_pitch: f64,
    /// Fin area, m² (0.00665).
    pub fin_area: f64,
    /// Fin lift slope per radian (0.9).
    pub cl_delta: f64,
    /// Fin cant angle, degrees (30).
    pub fin_cant_deg: f64,
    /// Largest physical fin deflection, degrees (25).
    pub delta_max_deg: f64,
    /// Fin actuator time constant, s (0.1).
    pub t_delta: f64,
    /// Surge time constant, s (20).
    pub t_surge: f64,
    /// Speed at 100 % thrust, m/s (2.0).
    pub max_speed: f64,
    /// Nomoto yaw gain (0.25) and time constant (1 s).
    pub k_nomoto: f64,
    /// See `k_nomoto`.
    pub t_yaw: f64,
    /// Rise rate from positive buoyancy, m/s (0).
    pub buoyancy_rate: f64,
}

impl Default for CougUvModel {
    fn default() -> Self {
        CougUvModel {
            mass: 31.03,
            length: 1.6,
            diameter: 0.19,
            rho: 1026.0,
            r_bg: 0.02,
            zeta_pitch: 0.8,
            fin_area: 0.00665,
            cl_delta: 0.9,
            fin_cant_deg: 30.0,
            delta_max_deg: 25.0,
            t_delta: 0.1,
            t_surge: 20.0,
            max_speed: 2.0,
            k_nomoto: 0.25,
            t_yaw: 1.0,
            buoyancy_rate: 0.0,
        }
    }
}

/// State of the CougUV model.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct CougUvState {
    /// Depth, m.
    pub depth: f64,
    /// Depth rate, m/s.
    pub depth_rate: f64,
    /// Pitch, radians (positive nose down).
    pub pitch: f64,
    /// Pitch rate, rad/s.
    pub pitch_rate: f64,
    /// Compass heading, degrees.
    pub heading: f64,
    /// Yaw rate, rad/s (clockwise positive).
    pub yaw_rate: f64,
    /// Surge, m/s.
    pub surge: f64,
    /// Physical fin deflections after the actuator lag, degrees `[top, stbd, port]`.
    pub fins: [f64; 3],
}

impl CougUvModel {
    /// Pitch moment of inertia including a rough added mass (twice the rigid body's).
    pub fn pitch_inertia(&self) -> f64 {
        let r = self.diameter / 2.0;
        2.0 * self.mass * (3.0 * r * r + self.length * self.length) / 12.0
    }

    /// Advances by `dt` seconds under command `cmd` (controller fins before mixing).
    /// A negative elevator fin (`port = -stbd = p < 0`) pitches the nose down.
    pub fn step(&self, st: &CougUvState, cmd: &UCommand, dt: f64) -> CougUvState {
        let mut s = *st;
        let n = (dt / 0.005).ceil().max(1.0) as usize;
        let h = dt / n as f64;
        let iyy = self.pitch_inertia();
        let restoring = self.mass * 9.81 * self.r_bg;
        let wn = (restoring / iyy).sqrt();
        let damping = 2.0 * self.zeta_pitch * wn * iyy;
        let lever = self.length / 2.0;
        let dmax = self.delta_max_deg;
        for _ in 0..n {
            for i in 0..3 {
                let target = cmd.fin[i].clamp(-dmax, dmax);
                s.fins[i] += (target - s.fins[i]) * (h / self.t_delta).min(1.0);
            }
            let u_ss = cmd.thruster.clamp(-100.0, 100.0) / 100.0 * self.max_speed;
            s.surge += (u_ss - s.surge) * (h / self.t_surge).min(1.0);
            let u2 = s.surge * s.surge;
            let lift = 0.5
                * self.rho
                * self.fin_area
                * self.cl_delta
                * self.fin_cant_deg.to_radians().cos()
                * u2;
            let elevator = ((s.fins[2] - s.fins[1]) / 2.0).to_radians();
            let moment =
                -2.0 * lever * lift * elevator - restoring * s.pitch.sin() - damping * s.pitch_rate;
            s.pitch_rate += moment / iyy * h;
            s.pitch += s.pitch_rate * h;
            let rudder = s.fins[0].to_radians();
            s.yaw_rate +=
                (self.k_nomoto * rudder * s.surge - s.yaw_rate) * (h / self.t_yaw).min(1.0);
            s.heading = crate::angle::angle360(s.heading + s.yaw_rate.to_degrees() * h);
            s.depth_rate = s.surge * s.pitch.sin() - self.buoyancy_rate;
            s.depth = (s.depth + s.depth_rate * h).max(0.0);
        }
        s
    }
}

/// The controllers as a MOOS app: `DESIRED_HEADING` (compass) / `DESIRED_SPEED` (thrust %) /
/// `DESIRED_DEPTH` and `NAV_*` in; `DESIRED_RUDDER`, `DESIRED_ELEVATOR` (positive dives, as
/// the marine simulator expects), `DESIRED_THRUST`, the mixed fins `COUG_FIN_0..2`, and the
/// PWM pulses `COUG_SERVO_US_0..2` / `COUG_THRUSTER_US` out.
///
/// The loop runs at `timer_period`; call [`CougarsControl::iterate`] at that rate. Nothing is
/// published until `MOOS_MANUAL_OVERRIDE=false` (the vehicle's start signal); going back to
/// `true` publishes one zero command. The thruster starts armed (`COUG_ARM=false` disarms,
/// as the `arm_thruster` service did); `COUG_SURFACE=true` forces the fins-up command;
/// `DESIRED_DEPTH_DFB=true` switches to depth-from-bottom (`NAV_ALTITUDE`).
pub struct CougarsControl {
    cfg: CougarsConfig,
    state: CougarsState,
    inputs: ControllerInputs,
    running: bool,
    stop_pending: bool,
    armed: bool,
    surface: bool,
    boot_time: f64,
    last: Option<(UCommand, f64)>,
    vars: [ByteString; 10],
}

impl CougarsControl {
    /// A controller; `boot_time` starts the ESC arming delay.
    pub fn new(cfg: CougarsConfig, boot_time: f64) -> Self {
        let names = [
            "DESIRED_RUDDER",
            "DESIRED_ELEVATOR",
            "DESIRED_THRUST",
            "COUG_FIN_0",
            "COUG_FIN_1",
            "COUG_FIN_2",
            "COUG_SERVO_US_0",
            "COUG_SERVO_US_1",
            "COUG_SERVO_US_2",
            "COUG_THRUSTER_US",
        ];
        CougarsControl {
            state: CougarsState::new(&cfg),
            cfg,
            inputs: ControllerInputs {
                surge: 0.6,
                ..ControllerInputs::default()
            },
            running: false,
            stop_pending: false,
            armed: true,
            surface: false,
            boot_time,
            last: None,
            vars: names.map(ByteString::from),
        }
    }

    /// Controller memory.
    pub fn state(&self) -> &CougarsState {
        &self.state
    }

    /// Latest inputs.
    pub fn inputs(&self) -> &ControllerInputs {
        &self.inputs
    }

    /// Takes one piece of mail. `NAV_PITCH` is MOOS's (radians, negative nose down);
    /// `COUG_ARM` / `COUG_SURFACE` are the arm and surface services.
    pub fn on_mail(&mut self, var: &str, value: ValueRef<'_>, _time: f64) {
        let d = value.as_f64();
        let b = value.as_str().and_then(crate::config::parse_bool);
        match (var, d, b) {
            ("DESIRED_HEADING", Some(v), _) => self.inputs.desired_heading = compass_to_enu(v),
            ("DESIRED_SPEED", Some(v), _) => self.inputs.desired_speed = v,
            ("DESIRED_DEPTH", Some(v), _) => self.inputs.desired_depth = v,
            ("NAV_HEADING", Some(v), _) => self.inputs.heading = compass_to_enu(v),
            ("NAV_DEPTH", Some(v), _) => self.inputs.depth = v,
            ("NAV_ALTITUDE", Some(v), _) => self.inputs.altitude = v,
            ("NAV_PITCH", Some(v), _) => self.inputs.pitch = -v.to_degrees(),
            ("NAV_SPEED", Some(v), _) => self.inputs.surge = v,
            ("MOOS_MANUAL_OVERRIDE" | "MOOS_MANUAL_OVERIDE", _, Some(o)) => {
                if o && self.running {
                    self.stop_pending = true;
                }
                self.running = !o;
            }
            ("COUG_ARM", _, Some(a)) => self.armed = a,
            ("COUG_SURFACE", _, Some(s)) => self.surface = s,
            ("DESIRED_DEPTH_DFB", _, Some(f)) => self.inputs.dfb = f,
            _ => {}
        }
    }

    /// One controller tick at `time`; appends postings to `out`.
    pub fn iterate(&mut self, time: f64, out: &mut Vec<Posting>) {
        let cmd = if self.running {
            let (s, cmd) = step(&self.cfg, &self.state, &self.inputs);
            self.state = s;
            cmd
        } else if self.stop_pending {
            self.stop_pending = false;
            UCommand::default()
        } else {
            return;
        };
        let mixed = self.cfg.kinematics.mix(&cmd, self.armed, self.surface);
        self.last = Some((mixed, time));
        let since_boot = time - self.boot_time;
        let pwm = self
            .cfg
            .actuators
            .outputs(Some((&mixed, since_boot)), since_boot);
        let v = &self.vars;
        out.push(Posting::double(&v[0], cmd.fin[0]));
        // The simulator's elevator dives when positive; a negative pitch fin (port fin,
        // `fin[2]`) pitches the nose down, hence the sign.
        out.push(Posting::double(&v[1], -cmd.fin[2]));
        out.push(Posting::double(&v[2], mixed.thruster));
        for i in 0..3 {
            out.push(Posting::double(&v[3 + i], mixed.fin[i]));
            out.push(Posting::double(&v[6 + i], f64::from(pwm.servo_us[i])));
        }
        out.push(Posting::double(&v[9], f64::from(pwm.thruster_us)));
    }

    /// PWM outputs at `time` with the failsafe applied to the last command.
    pub fn pwm(&self, time: f64) -> Pwm {
        let since_boot = time - self.boot_time;
        let last = self.last.map(|(c, t)| (c, t - self.boot_time));
        self.cfg
            .actuators
            .outputs(last.as_ref().map(|(c, t)| (c, *t)), since_boot)
    }
}
