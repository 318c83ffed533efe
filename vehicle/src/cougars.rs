//! CoUGARs (BYU FRoSt Lab, Gen-1) controllers: heading PID to the top fin, the nested
//! depth -> pitch -> elevator-fin cascade, fin mixing ("kinematics"), the Teensy actuator
//! mapping to PWM microseconds, and a simple CougUV pitch/depth/heading model to close the loop
//! ([`crate::couguv`] flies it as a simulator). [`CougarsControl`] is the MOOS adapter of the
//! `pCougControls` app; [`vars`] lists the variables it posts for the Teensy driver and the
//! simulator.
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

impl Kinematics {
    /// The inverse of [`Kinematics::mix`] outside the surface command: the physical fin
    /// deflections (top, starboard, port) that give the servo-frame angles `servo_deg` at
    /// `thrust_pct` (`(servo / 2 in demo mode − offset − trim_ratio · thrust) / direction`; a
    /// zero direction reads as 1). What a simulator behind the servos flies.
    pub fn deflections(&self, servo_deg: [f64; 3], thrust_pct: f64) -> [f64; 3] {
        let mut fins = [0.0; 3];
        for (i, f) in fins.iter_mut().enumerate() {
            let v = if self.demo_mode {
                servo_deg[i] / 2.0
            } else {
                servo_deg[i]
            };
            let dir = if self.direction[i] == 0.0 {
                1.0
            } else {
                self.direction[i]
            };
            *f = (v - self.offset[i] - self.trim_ratio * thrust_pct) / dir;
        }
        fins
    }
}

/// The keys of a `pCougControls` block that set the fin kinematics ([`Kinematics`]): the
/// `vehicle` preset and the keys overriding it. Whoever else must know how the fins are
/// mounted (uSimDevices, undoing the servo angles) reads these same keys with
/// [`ControlsConfig::from_params_lenient`], so one configuration rules both.
pub const KINEMATICS_KEYS: [&str; 9] = [
    "vehicle",
    "fin_0_direction",
    "fin_1_direction",
    "fin_2_direction",
    "top_fin_offset",
    "right_fin_offset",
    "left_fin_offset",
    "trim_ratio",
    "demo_mode",
];

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

/// The MOOS variables of `pCougControls` (the controllers as an app, [`CougarsControl`]) and
/// of the CougUV simulator (`uSimCougUV`, [`crate::couguv`]), shared with the Teensy driver.
///
/// | variable | unit | meaning | read by |
/// |---|---|---|---|
/// | `FIN_TOP_DEG` | deg | `$CONTR` field 1: top fin servo angle from the servo centre, after the vehicle's fin direction, offset and trim (kinematics) | `iTeensy` |
/// | `FIN_STBD_DEG` | deg | `$CONTR` field 2: starboard fin, as `FIN_TOP_DEG` | `iTeensy` |
/// | `FIN_PORT_DEG` | deg | `$CONTR` field 3: port fin, as `FIN_TOP_DEG` | `iTeensy` |
/// | `THRUST_PCT` | % | `$CONTR` field 4: thruster, a whole number in −100..100; 0 when not armed | `iTeensy`, `uSimCougUV` |
/// | `FIN_DEFLECT_TOP_DEG` | deg | the physical top fin (rudder) deflection commanded, before the kinematics: positive turns the vehicle to starboard (clockwise seen from above) | `uSimCougUV` |
/// | `FIN_DEFLECT_STBD_DEG` | deg | the physical starboard fin deflection: positive pitches the nose down | `uSimCougUV` |
/// | `FIN_DEFLECT_PORT_DEG` | deg | the physical port fin deflection: positive pitches the nose up (the elevator mix is `stbd = −p`, `port = +p`) | `uSimCougUV` |
/// | `COUG_PITCH_REF_DEG` | deg | the depth loop's pitch reference, positive nose **up** (MOOS's sign) | logs |
/// | `COUG_DEPTH_REF` | m | the filtered depth reference, positive down | logs |
/// | `COUG_CONTROLS_STATE` | | on change: `disarmed`, `active`, `stale: <vars>`, `allstop: zero speed` | logs, `pSafety` |
///
/// The fins and the thrust are posted together, every iteration while armed, in the order
/// of the table: a reader can take a command when `THRUST_PCT` arrives.
pub mod vars {
    /// `$CONTR` top fin, servo frame, degrees.
    pub const FIN_TOP_DEG: &str = "FIN_TOP_DEG";
    /// `$CONTR` starboard fin, servo frame, degrees.
    pub const FIN_STBD_DEG: &str = "FIN_STBD_DEG";
    /// `$CONTR` port fin, servo frame, degrees.
    pub const FIN_PORT_DEG: &str = "FIN_PORT_DEG";
    /// `$CONTR` thruster, percent (whole number).
    pub const THRUST_PCT: &str = "THRUST_PCT";
    /// Physical top fin deflection, degrees (positive turns to starboard).
    pub const FIN_DEFLECT_TOP_DEG: &str = "FIN_DEFLECT_TOP_DEG";
    /// Physical starboard fin deflection, degrees (positive pitches nose down).
    pub const FIN_DEFLECT_STBD_DEG: &str = "FIN_DEFLECT_STBD_DEG";
    /// Physical port fin deflection, degrees (positive pitches nose up).
    pub const FIN_DEFLECT_PORT_DEG: &str = "FIN_DEFLECT_PORT_DEG";
    /// The pitch reference of the depth loop, degrees, nose up positive.
    pub const COUG_PITCH_REF_DEG: &str = "COUG_PITCH_REF_DEG";
    /// The filtered depth reference, metres, positive down.
    pub const COUG_DEPTH_REF: &str = "COUG_DEPTH_REF";
    /// The controller's state, posted on change.
    pub const COUG_CONTROLS_STATE: &str = "COUG_CONTROLS_STATE";
    /// `true` forces the fins-up surface command (the `surface` service of the kinematics).
    pub const COUG_SURFACE: &str = "COUG_SURFACE";
}

impl Kinematics {
    /// The physical deflections and thrust of a command: what [`Kinematics::mix`] gives with
    /// directions 1, no offsets and no trim (the fins-up command when `surface`, the thrust
    /// only when `armed`, demo mode kept). This is what the fins do once the servos are
    /// mounted as the kinematics describe, and what the simulator integrates.
    pub fn physical(&self, cmd: &UCommand, armed: bool, surface: bool) -> UCommand {
        Kinematics {
            direction: [1.0; 3],
            offset: [0.0; 3],
            trim_ratio: 0.0,
            demo_mode: self.demo_mode,
        }
        .mix(cmd, armed, surface)
    }
}

/// The `pCougControls` configuration: the controllers' ([`CougarsConfig`]) and the app's
/// own settings.
#[derive(Debug, Clone, PartialEq)]
pub struct ControlsConfig {
    /// Gains, limits, filters, kinematics and PWM mapping.
    pub cougars: CougarsConfig,
    /// Thrust percent per m/s of `DESIRED_SPEED` (`speed_factor`, as pMarinePID's); 0 (the
    /// default) takes `DESIRED_SPEED` as thrust percent, as the Gen-1 MOOS bridge did.
    pub speed_factor: f64,
    /// Largest |thrust|, percent (`max_thrust`, 100).
    pub max_thrust: f64,
    /// `DESIRED_*` older than this, seconds, stops the vehicle (`tardy_helm_threshold`, 2;
    /// 0 = never stale once received).
    pub tardy_helm_s: f64,
    /// `NAV_*` older than this, seconds, stops the vehicle (`tardy_nav_threshold`, 2;
    /// 0 = never stale once received).
    pub tardy_nav_s: f64,
    /// The gains were tuned against the original millisecond-interval PID
    /// (`ms_tuned_gains`, false): every loop's gains go through [`Gains::from_ms_tuned`]
    /// once the block is read, which gives the field gains the integral (×1000) and
    /// derivative (÷1000) action they had on the vehicle.
    pub ms_tuned_gains: bool,
}

impl Default for ControlsConfig {
    fn default() -> Self {
        ControlsConfig {
            cougars: CougarsConfig::default(),
            speed_factor: 0.0,
            max_thrust: 100.0,
            tardy_helm_s: 2.0,
            tardy_nav_s: 2.0,
            ms_tuned_gains: false,
        }
    }
}

const CONTROLS_APP: &str = "pCougControls";

impl ControlsConfig {
    /// Strict construction from `(key, value)` pairs (see
    /// [`ControlsConfig::from_params_lenient`]).
    pub fn from_params<'a>(
        params: impl IntoIterator<Item = (&'a str, &'a str)>,
    ) -> Result<Self, ConfigError> {
        strict(Self::from_params_lenient(params))
    }

    /// Reads a `pCougControls` block: `vehicle = coug1 | coug2` first selects a field
    /// preset (wherever the line is; the declared defaults, all gains 0, without one), then
    /// every [`CougarsConfig::from_params`] key overrides it, and the app's own keys
    /// `speed_factor`, `max_thrust`, `tardy_helm_threshold`, `tardy_nav_threshold`,
    /// `ms_tuned_gains`. Unknown
    /// keys and bad values come back as non-fatal errors (the setting keeps its value).
    pub fn from_params_lenient<'a>(
        params: impl IntoIterator<Item = (&'a str, &'a str)>,
    ) -> Result<(Self, Vec<ConfigError>), ConfigError> {
        let params: Vec<(&str, &str)> = params.into_iter().collect();
        let mut cfg = ControlsConfig::default();
        let mut problems = Vec::new();
        for (k, v) in &params {
            if k.trim().eq_ignore_ascii_case("vehicle") {
                match v.trim().to_ascii_lowercase().as_str() {
                    "coug1" => cfg.cougars = CougarsConfig::coug1(),
                    "coug2" => cfg.cougars = CougarsConfig::coug2(),
                    "none" | "default" => cfg.cougars = CougarsConfig::default(),
                    _ => problems.push(ConfigError::BadValue {
                        app: CONTROLS_APP,
                        key: k.trim().to_string(),
                        value: v.trim().to_string(),
                        expected: "coug1, coug2 or none",
                    }),
                }
            }
        }
        let unknown = apply_params(CONTROLS_APP, &mut cfg, params, |c, key, p| {
            match key {
                "vehicle" => {}
                "speed_factor" => c.speed_factor = p.non_neg()?,
                "max_thrust" => c.max_thrust = p.range(0.0, 100.0, "a number in 0..100")?,
                "tardy_helm_threshold" => c.tardy_helm_s = p.non_neg()?,
                "tardy_nav_threshold" => c.tardy_nav_s = p.non_neg()?,
                "ms_tuned_gains" => c.ms_tuned_gains = p.bool()?,
                _ => return c.cougars.apply_one(key, p),
            }
            Ok(true)
        })?;
        problems.extend(unknown);
        if cfg.ms_tuned_gains {
            let c = &mut cfg.cougars;
            c.depth = c.depth.from_ms_tuned();
            c.pitch = c.pitch.from_ms_tuned();
            c.heading = c.heading.from_ms_tuned();
        }
        Ok((cfg, problems))
    }
}

/// A quantity's rate from its successive distinct samples (time, value), per second.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
struct Rate {
    prev: Option<(f64, f64)>,
    rate: f64,
}

impl Rate {
    fn update(&mut self, time: f64, value: f64) {
        match self.prev {
            Some((t0, v0)) if time > t0 => {
                self.rate = (value - v0) / (time - t0);
                self.prev = Some((time, value));
            }
            Some(_) => {}
            None => self.prev = Some((time, value)),
        }
    }
}

/// What the controller did in its last iteration.
#[derive(Debug, Clone, PartialEq)]
pub enum ControlsMode {
    /// Not deployed, or under manual override: nothing is posted (one all-stop on entry).
    Disarmed,
    /// The cascade runs.
    Active,
    /// Armed, but inputs missing or older than their threshold: all-stop every iteration.
    Stale(Vec<&'static str>),
    /// Armed with a zero (or negative) desired speed, as the helm's all-stop posts:
    /// thruster off and fins centred every iteration.
    AllStop,
}

impl ControlsMode {
    /// The `COUG_CONTROLS_STATE` text.
    pub fn text(&self) -> String {
        match self {
            ControlsMode::Disarmed => "disarmed".to_string(),
            ControlsMode::Active => "active".to_string(),
            ControlsMode::Stale(v) => format!("stale: {}", v.join(",")),
            ControlsMode::AllStop => "allstop: zero speed".to_string(),
        }
    }
}

/// Input variables whose age is watched: helm set-points, then navigation.
const HELM_INPUTS: [&str; 3] = ["DESIRED_HEADING", "DESIRED_SPEED", "DESIRED_DEPTH"];
const NAV_INPUTS: [&str; 4] = ["NAV_HEADING", "NAV_DEPTH", "NAV_PITCH", "NAV_SPEED"];

/// A `NAV_DEPTH` below this, metres, is taken for an ENU z (negative underwater) posted as a
/// depth, and reported.
pub const NEGATIVE_DEPTH_WARNING_M: f64 = -0.5;

/// The CoUGARs controllers as a MOOS app (`pCougControls`; `runtime` wraps it): the heading
/// loop, the depth → pitch → elevator cascade ([`step`]) and the fin mixing
/// ([`Kinematics`]) from the helm's `DESIRED_HEADING` / `DESIRED_SPEED` / `DESIRED_DEPTH`
/// and the navigator's `NAV_HEADING` / `NAV_DEPTH` / `NAV_PITCH` / `NAV_SPEED`, to the fin
/// angles and thrust of [`vars`].
///
/// # Conventions at the boundary (the traps of the Gen-1 stack, fixed here)
///
/// * **Heading**: `DESIRED_HEADING` and `NAV_HEADING` are compass degrees (clockwise from
///   true north), as the helm and the navigator post them; both go through
///   [`compass_to_enu`] before the ENU heading loop, so a desired heading to starboard of
///   the current one gives a positive (starboard-turning) top fin, across 0/360 too.
/// * **Declination** is applied once, by whoever turns the magnetic AHRS yaw into a true
///   heading (the SeaTrac driver, or uSimSensors, posting `AHRS_HEADING`); the navigator's
///   `NAV_HEADING` is true and this app adds nothing (the Gen-1 controller added it a
///   second time to a yaw its MOOS bridge did not correct).
/// * **Depth**: `NAV_DEPTH` and `DESIRED_DEPTH` are metres, positive down. A `NAV_DEPTH`
///   below [`NEGATIVE_DEPTH_WARNING_M`] (an ENU z, as the Gen-1 bridge posted) is used as
///   given and reported as a run warning.
/// * **Pitch**: `NAV_PITCH` is MOOS's, radians, nose up positive; the cascade works in
///   degrees nose down positive. Its rate is differentiated from successive `NAV_PITCH`
///   mail (the depth rate likewise from `NAV_DEPTH`).
/// * **Speed**: `DESIRED_SPEED` times `speed_factor` is the thrust percent (with
///   `speed_factor = 0`, `DESIRED_SPEED` is the percent, as on the Gen-1 vehicle); clamped
///   to `±max_thrust` and truncated to a whole percent (the `$CONTR` field is an integer).
///   `NAV_SPEED` (m/s) feeds the pitch loop's gain schedule only with `fixed_surge = none`.
///
/// # Arming and all-stop (as pMarinePID)
///
/// The controller is armed only while `DEPLOY` is true and `MOOS_MANUAL_OVERRIDE` (or the
/// legacy `MOOS_MANUAL_OVERIDE`) is false (initially: not deployed, overridden). Unarmed it
/// posts nothing; on disarming it posts one all-stop, the disarmed output: thrust 0 and
/// every fin at zero deflection (the servo frame's offsets: centred and aligned with the
/// hull), even under `COUG_SURFACE` (iTeensy repeats it until the next command).
/// Armed, it posts the all-stop every iteration while a helm set-point or navigation
/// variable has never arrived or is older than its threshold (`stale: ...`), or the desired
/// speed is not positive (`allstop`); otherwise the cascade's command. Arming restarts the
/// loops from zero. `COUG_SURFACE = true` replaces the fins with the fins-up command (thrust
/// kept while armed; thrust 0 with the fins still up in a stale or all-stop iteration, so a
/// vehicle coasting up with a dead helm keeps its nose up).
///
/// Against CoUGARs (`cougars-vehicle.md` §1.5, §6; `coug_kinematics.cpp`): there the surface
/// override outlives the disarm, and a 1 s timer republishes the fins-up command with the
/// thrust zeroed, so a vehicle surfaced by `surface_then_disarm` sits at the surface with its
/// elevators at ±30° for as long as the node runs. Disarmed, coug centres them instead: with
/// no thrust the fins steer nothing, a disarmed vehicle then looks the same whether its
/// software is alive or not (the Teensy's own command-loss failsafe centres the servos too),
/// and nothing sticks out at ±30° while the vehicle is recovered by hand.
pub struct CougarsControl {
    cfg: ControlsConfig,
    state: CougarsState,
    inputs: ControllerInputs,
    deployed: bool,
    overridden: bool,
    surface: bool,
    was_armed: bool,
    helm_time: [Option<f64>; 3],
    nav_time: [Option<f64>; 4],
    pitch_rate: Rate,
    depth_rate: Rate,
    mode: ControlsMode,
    posted_mode: Option<String>,
    last_servo: UCommand,
    last_physical: UCommand,
    warnings: Vec<String>,
    warned_negative_depth: bool,
    names: [ByteString; 10],
}

impl CougarsControl {
    /// A controller, not armed.
    pub fn new(cfg: ControlsConfig) -> Self {
        let names = [
            vars::FIN_TOP_DEG,
            vars::FIN_STBD_DEG,
            vars::FIN_PORT_DEG,
            vars::THRUST_PCT,
            vars::FIN_DEFLECT_TOP_DEG,
            vars::FIN_DEFLECT_STBD_DEG,
            vars::FIN_DEFLECT_PORT_DEG,
            vars::COUG_PITCH_REF_DEG,
            vars::COUG_DEPTH_REF,
            vars::COUG_CONTROLS_STATE,
        ];
        CougarsControl {
            state: CougarsState::new(&cfg.cougars),
            inputs: ControllerInputs {
                surge: cfg.cougars.fixed_surge.unwrap_or(0.0),
                ..ControllerInputs::default()
            },
            cfg,
            deployed: false,
            overridden: true,
            surface: false,
            was_armed: false,
            helm_time: [None; 3],
            nav_time: [None; 4],
            pitch_rate: Rate::default(),
            depth_rate: Rate::default(),
            mode: ControlsMode::Disarmed,
            posted_mode: None,
            last_servo: UCommand::default(),
            last_physical: UCommand::default(),
            warnings: Vec::new(),
            warned_negative_depth: false,
            names: names.map(ByteString::from),
        }
    }

    /// The variables the app registers for.
    pub fn subscriptions() -> Vec<&'static str> {
        let mut v: Vec<&'static str> = HELM_INPUTS.to_vec();
        v.extend(NAV_INPUTS);
        v.extend([
            "DEPLOY",
            "MOOS_MANUAL_OVERRIDE",
            "MOOS_MANUAL_OVERIDE",
            vars::COUG_SURFACE,
        ]);
        v
    }

    /// The configuration in force.
    pub fn config(&self) -> &ControlsConfig {
        &self.cfg
    }

    /// Controller memory.
    pub fn state(&self) -> &CougarsState {
        &self.state
    }

    /// Latest inputs, in the controller's conventions (ENU heading, pitch nose down).
    pub fn inputs(&self) -> &ControllerInputs {
        &self.inputs
    }

    /// What the last iteration did.
    pub fn mode(&self) -> &ControlsMode {
        &self.mode
    }

    /// True while deployed and not overridden.
    pub fn armed(&self) -> bool {
        self.deployed && !self.overridden
    }

    /// The last command posted: servo frame (the `$CONTR` fields) and physical deflections.
    pub fn last_command(&self) -> (UCommand, UCommand) {
        (self.last_servo, self.last_physical)
    }

    /// Run warnings raised since the last call (a negative `NAV_DEPTH`).
    pub fn take_warnings(&mut self) -> Vec<String> {
        std::mem::take(&mut self.warnings)
    }

    /// Takes one piece of mail posted at `time`.
    pub fn on_mail(&mut self, var: &str, value: ValueRef<'_>, time: f64) {
        let d = value.as_f64();
        let b = value.as_str().and_then(crate::config::parse_bool);
        if let (Some(i), Some(v)) = (HELM_INPUTS.iter().position(|n| *n == var), d) {
            self.helm_time[i] = Some(time);
            match i {
                0 => self.inputs.desired_heading = compass_to_enu(v),
                1 => self.inputs.desired_speed = v,
                _ => self.inputs.desired_depth = v,
            }
            return;
        }
        if let (Some(i), Some(v)) = (NAV_INPUTS.iter().position(|n| *n == var), d) {
            self.nav_time[i] = Some(time);
            match i {
                0 => self.inputs.heading = compass_to_enu(v),
                1 => {
                    if v < NEGATIVE_DEPTH_WARNING_M && !self.warned_negative_depth {
                        self.warned_negative_depth = true;
                        self.warnings.push(format!(
                            "NAV_DEPTH = {v:.2}: negative; NAV_DEPTH is positive down \
                             (an ENU z posted as a depth?)"
                        ));
                    }
                    self.inputs.depth = v;
                    self.depth_rate.update(time, v);
                    self.inputs.depth_rate = self.depth_rate.rate;
                }
                2 => {
                    // MOOS: radians, nose up positive; the cascade: degrees, nose down.
                    let deg = -v.to_degrees();
                    self.inputs.pitch = deg;
                    self.pitch_rate.update(time, deg);
                    self.inputs.pitch_rate = self.pitch_rate.rate;
                }
                _ => self.inputs.surge = v,
            }
            return;
        }
        match (var, b) {
            ("DEPLOY", Some(v)) => self.deployed = v,
            ("MOOS_MANUAL_OVERRIDE" | "MOOS_MANUAL_OVERIDE", Some(v)) => self.overridden = v,
            (vars::COUG_SURFACE, Some(v)) => self.surface = v,
            _ => {}
        }
    }

    /// The inputs missing or too old at `now`.
    fn stale(&self, now: f64) -> Vec<&'static str> {
        let mut out = Vec::new();
        let old = |t: Option<f64>, limit: f64| match t {
            None => true,
            Some(t) => limit > 0.0 && now - t > limit,
        };
        for (i, name) in HELM_INPUTS.iter().enumerate() {
            if old(self.helm_time[i], self.cfg.tardy_helm_s) {
                out.push(*name);
            }
        }
        // NAV_SPEED matters only when the gain schedule uses it.
        let navs = if self.cfg.cougars.fixed_surge.is_some() {
            3
        } else {
            4
        };
        for (i, name) in NAV_INPUTS.iter().enumerate().take(navs) {
            if old(self.nav_time[i], self.cfg.tardy_nav_s) {
                out.push(*name);
            }
        }
        out
    }

    /// One controller tick at `now`; appends the postings to `out`. Call it every
    /// `timer_period` (the cascade's filters and integrators assume that period).
    pub fn iterate(&mut self, now: f64, out: &mut Vec<Posting>) {
        let armed = self.armed();
        if !armed {
            if self.was_armed {
                // The disarmed output: thrust 0 and the fins centred, whatever the surface
                // flag (see "Arming and all-stop").
                self.emit_with(&UCommand::default(), false, false, out);
            }
            self.was_armed = false;
            self.set_mode(ControlsMode::Disarmed, out);
            return;
        }
        if !self.was_armed {
            self.state = CougarsState::new(&self.cfg.cougars);
            self.was_armed = true;
        }
        let stale = self.stale(now);
        if !stale.is_empty() {
            self.set_mode(ControlsMode::Stale(stale), out);
            self.emit(&UCommand::default(), true, out);
            return;
        }
        let factor = if self.cfg.speed_factor > 0.0 {
            self.cfg.speed_factor
        } else {
            1.0
        };
        let thrust = (self.inputs.desired_speed * factor)
            .clamp(-self.cfg.max_thrust, self.cfg.max_thrust)
            .trunc();
        if thrust <= 0.0 {
            self.set_mode(ControlsMode::AllStop, out);
            self.emit(&UCommand::default(), true, out);
            return;
        }
        self.set_mode(ControlsMode::Active, out);
        let inputs = ControllerInputs {
            desired_speed: thrust,
            ..self.inputs
        };
        let (s, cmd) = step(&self.cfg.cougars, &self.state, &inputs);
        self.state = s;
        self.emit(&cmd, true, out);
        out.push(Posting::double(&self.names[7], -self.state.theta_ref));
        out.push(Posting::double(&self.names[8], self.state.z_ref));
    }

    fn set_mode(&mut self, mode: ControlsMode, out: &mut Vec<Posting>) {
        let text = mode.text();
        if self.posted_mode.as_deref() != Some(text.as_str()) {
            out.push(Posting::text(&self.names[9], text.clone()));
            self.posted_mode = Some(text);
        }
        self.mode = mode;
    }

    fn emit(&mut self, cmd: &UCommand, armed: bool, out: &mut Vec<Posting>) {
        self.emit_with(cmd, armed, self.surface, out);
    }

    fn emit_with(&mut self, cmd: &UCommand, armed: bool, surface: bool, out: &mut Vec<Posting>) {
        let k = &self.cfg.cougars.kinematics;
        let servo = k.mix(cmd, armed, surface);
        let physical = k.physical(cmd, armed, surface);
        for i in 0..3 {
            out.push(Posting::double(&self.names[i], servo.fin[i]));
        }
        out.push(Posting::double(&self.names[3], servo.thruster.trunc()));
        for i in 0..3 {
            out.push(Posting::double(&self.names[4 + i], physical.fin[i]));
        }
        self.last_servo = servo;
        self.last_physical = physical;
    }

    /// The appcast body: arming, mode, set-points and measurements in MOOS conventions, the
    /// references and the last command.
    pub fn appcast_body(&self, out: &mut String) {
        use std::fmt::Write as _;
        let i = &self.inputs;
        let _ = writeln!(
            out,
            "Armed: {}  (DEPLOY={}, MANUAL_OVERRIDE={})   Mode: {}",
            self.armed(),
            self.deployed,
            self.overridden,
            self.mode.text()
        );
        let _ = writeln!(out);
        let _ = writeln!(out, "Loop      Desired  Actual   Reference");
        let _ = writeln!(out, "--------  -------  -------  ---------");
        let compass = |enu: f64| crate::angle::angle360(90.0 - enu);
        let _ = writeln!(
            out,
            "heading   {:<7.1}  {:<7.1}  (deg, compass)",
            compass(i.desired_heading),
            compass(i.heading)
        );
        let _ = writeln!(
            out,
            "depth     {:<7.2}  {:<7.2}  {:.2} m",
            i.desired_depth, i.depth, self.state.z_ref
        );
        let _ = writeln!(
            out,
            "pitch     {:<7.1}  {:<7.1}  (deg, nose up){}",
            -self.state.theta_ref,
            -i.pitch,
            if self.state.saturated_mode {
                " saturated"
            } else {
                ""
            }
        );
        let _ = writeln!(out);
        let (s, p) = (self.last_servo, self.last_physical);
        let _ = writeln!(
            out,
            "Fins (servo, deg): top={} stbd={} port={}  thrust={} %",
            s.fin[0], s.fin[1], s.fin[2], s.thruster
        );
        let _ = writeln!(
            out,
            "Fins (deflection, deg): top={} stbd={} port={}",
            p.fin[0], p.fin[1], p.fin[2]
        );
    }
}
