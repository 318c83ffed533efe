//! The Water Linked DVL A50 on TCP (`cougars-vehicle.md` §3.2, Water Linked's "DVL
//! protocol", `json_v3.1`): newline-delimited JSON, velocity reports (`"type":"velocity"`)
//! at the rate of the DVL model of `vehicle::sensors::dvl` (2 to 15 Hz with the altitude)
//! and dead-reckoning reports (`"type":"position_local"`) at 5 Hz, while the acoustics are
//! enabled; nothing while they are off. Out of bottom-lock range a velocity report says
//! so (`velocity_valid` false, altitude −1, every beam invalid).
//!
//! Commands and their answers (one `"type":"response"` line each, `format` `json_v3.1`):
//!
//! | command | effect | answer |
//! |---|---|---|
//! | `set_config` | the given parameters change (a speed of sound outside 1000–2000 m/s is refused, nothing changes) | `success` true, `result` null; false with `error_message` when refused |
//! | `get_config` | — | `result` with every parameter |
//! | `calibrate_gyro` | — | after [`A50Settings::gyro_calibration_s`] |
//! | `reset_dead_reckoning` | the dead reckoning restarts at 0 in the frame of the current heading | at once |
//! | anything else, or a line that is not JSON | — | `success` false, `error_message` saying why, `response_to` the command's name when there is one |
//!
//! The report members are filled as the A50 fills them: `time` is the milliseconds since
//! the previous velocity report; `time_of_validity` and `time_of_transmission` are Unix
//! microseconds; the covariance is diagonal, the figure of merit squared; the four beams
//! point 22.5° off vertical at 45°, 135°, 225° and 315° from forward, each with its velocity
//! (the body velocity along the beam), distance (altitude / cos 22.5°), signal strength and
//! noise density. Dead reckoning integrates the reported velocities (rotated by the
//! attitude) from the last reset, in a frame whose x is the heading at the reset; `yaw` is
//! the heading relative to it; `std` grows by 1.01 % of the distance travelled.

use devices::a50::{
    self, Command, Config, DeadReckoningReport, Response, Transducer, VelocityReport,
};
use devices::line::LineSplitter;
use vehicle::angle::angle180;
use vehicle::sensors::dvl::{Dvl, DvlConfig};

use crate::device::{Device, Situation};
use crate::truth::Truth;

/// The protocol format the emulated firmware writes.
pub const FORMAT: &str = "json_v3.1";

/// The dead-reckoning report period, s (5 Hz).
pub const DR_PERIOD_S: f64 = 0.2;

/// Beam angle from vertical, degrees.
pub const BEAM_ANGLE_DEG: f64 = 22.5;

/// The A50's settings.
#[derive(Debug, Clone)]
pub struct A50Settings {
    /// The DVL model (range, rates, noise).
    pub model: DvlConfig,
    /// The flat bottom's depth, m.
    pub water_depth_m: f64,
    /// The acoustics at power-up (the saved configuration): on.
    pub acoustic_enabled: bool,
    /// How long a gyro calibration takes before its answer, s (1).
    pub gyro_calibration_s: f64,
}

impl Default for A50Settings {
    fn default() -> Self {
        A50Settings {
            model: DvlConfig::default(),
            water_depth_m: 30.0,
            acoustic_enabled: true,
            gyro_calibration_s: 1.0,
        }
    }
}

#[derive(Debug, Clone, Copy, Default)]
struct DeadReckoning {
    /// Heading at the reset, degrees.
    heading0_deg: f64,
    /// Position in the reset frame (x along heading0, y to its right, z down), m.
    pos: [f64; 3],
    /// Distance travelled since the reset, m.
    travelled_m: f64,
    /// Time of the last velocity integrated.
    last_t: Option<f64>,
}

/// The A50.
pub struct A50 {
    settings: A50Settings,
    model: Dvl,
    config: Config,
    lines: LineSplitter,
    last_velocity_t: Option<f64>,
    next_dr_t: f64,
    dr: DeadReckoning,
    gyro_done_at: Option<f64>,
    commands: u64,
}

/// World (north, east, down) velocity of a body (forward, starboard, down) velocity.
fn body_to_ned(t: &Truth, v: [f64; 3]) -> [f64; 3] {
    let (sp, cp) = t.heading_deg.to_radians().sin_cos();
    let (st, ct) = t.pitch_rad.sin_cos();
    let (sr, cr) = t.roll_rad.sin_cos();
    // The transpose of the rotation in `Truth::body_velocity`.
    let n = ct * cp * v[0] + (sr * st * cp - cr * sp) * v[1] + (cr * st * cp + sr * sp) * v[2];
    let e = ct * sp * v[0] + (sr * st * sp + cr * cp) * v[1] + (cr * st * sp - sr * cp) * v[2];
    let d = -st * v[0] + sr * ct * v[1] + cr * ct * v[2];
    [n, e, d]
}

impl A50 {
    /// An A50 with these settings, drawing from `seed`.
    pub fn new(settings: A50Settings, seed: u64) -> Self {
        A50 {
            model: Dvl::new(settings.model.clone(), settings.water_depth_m, seed),
            config: Config {
                speed_of_sound_mps: Some(1475.0),
                acoustic_enabled: Some(settings.acoustic_enabled),
                dark_mode_enabled: Some(false),
                mounting_rotation_offset_deg: Some(0.0),
                range_mode: Some("auto".to_string()),
            },
            settings,
            lines: LineSplitter::new(a50::MAX_LINE),
            last_velocity_t: None,
            next_dr_t: 0.0,
            dr: DeadReckoning::default(),
            gyro_done_at: None,
            commands: 0,
        }
    }

    /// The current configuration (what `get_config` answers).
    pub fn config(&self) -> &Config {
        &self.config
    }

    /// True while the acoustics are on.
    pub fn acoustic_enabled(&self) -> bool {
        self.config.acoustic_enabled.unwrap_or(true)
    }

    /// Commands received (well formed or not).
    pub fn commands(&self) -> u64 {
        self.commands
    }

    fn respond(to: &str, error: Option<String>, result: Option<Config>) -> String {
        Response {
            response_to: to.to_string(),
            success: error.is_none(),
            error_message: error.unwrap_or_default(),
            result,
            format: Some(FORMAT.to_string()),
        }
        .encode()
    }

    fn command(&mut self, s: &Situation, line: &[u8]) -> String {
        self.commands += 1;
        match a50::parse_command(line) {
            Ok(Command::SetConfig(c)) => {
                if let Some(v) = c.speed_of_sound_mps
                    && !(1000.0..=2000.0).contains(&v)
                {
                    return Self::respond(
                        "set_config",
                        Some(format!("speed_of_sound {v} out of range 1000-2000")),
                        None,
                    );
                }
                let cur = &mut self.config;
                cur.speed_of_sound_mps = c.speed_of_sound_mps.or(cur.speed_of_sound_mps);
                cur.acoustic_enabled = c.acoustic_enabled.or(cur.acoustic_enabled);
                cur.dark_mode_enabled = c.dark_mode_enabled.or(cur.dark_mode_enabled);
                cur.mounting_rotation_offset_deg = c
                    .mounting_rotation_offset_deg
                    .or(cur.mounting_rotation_offset_deg);
                cur.range_mode = c.range_mode.or(cur.range_mode.take());
                Self::respond("set_config", None, None)
            }
            Ok(Command::GetConfig) => Self::respond("get_config", None, Some(self.config.clone())),
            Ok(Command::CalibrateGyro) => {
                self.gyro_done_at = Some(s.t + self.settings.gyro_calibration_s);
                String::new()
            }
            Ok(Command::ResetDeadReckoning) => {
                self.dr = DeadReckoning {
                    heading0_deg: s.truth.heading_deg,
                    ..DeadReckoning::default()
                };
                Self::respond("reset_dead_reckoning", None, None)
            }
            Err(e) => {
                // The command's name, when the line is JSON with one.
                let name = serde_json::from_slice::<serde_json::Value>(line)
                    .ok()
                    .and_then(|v| {
                        v.get("command")
                            .and_then(|c| c.as_str())
                            .map(str::to_string)
                    })
                    .unwrap_or_default();
                let why = match e {
                    a50::A50Error::Unknown => format!("unknown command {name:?}"),
                    other => other.to_string(),
                };
                Self::respond(&name, Some(why), None)
            }
        }
    }

    fn velocity(&mut self, s: &Situation) -> Option<String> {
        let r = self.model.sample(&s.truth)?;
        let time_ms = self
            .last_velocity_t
            .map_or(0.0, |p| ((s.t - p) * 1000.0 * 1000.0).round() / 1000.0);
        self.last_velocity_t = Some(s.t);
        let us = (s.unix_s * 1e6).round() as u64;
        let (sb, cb) = BEAM_ANGLE_DEG.to_radians().sin_cos();
        let transducers = (0..4)
            .map(|k| {
                let az = (45.0 + 90.0 * f64::from(k)).to_radians();
                let dir = [sb * az.cos(), sb * az.sin(), cb];
                let v: f64 = (0..3).map(|i| dir[i] * r.velocity_mps[i]).sum();
                Transducer {
                    id: i64::from(k),
                    velocity_mps: if r.valid { v } else { 0.0 },
                    distance_m: if r.valid {
                        r.altitude_m.max(0.0) / cb
                    } else {
                        0.0
                    },
                    rssi_dbm: if r.valid {
                        -30.0 - 0.8 * r.altitude_m.max(0.0)
                    } else {
                        -95.0
                    },
                    nsd_dbm: -90.0,
                    beam_valid: r.valid,
                }
            })
            .collect();
        if r.valid {
            // Dead reckoning integrates what the DVL measured.
            let dt = self.dr.last_t.map_or(0.0, |p| s.t - p);
            let ned = body_to_ned(&s.truth, r.velocity_mps);
            let (sh, ch) = self.dr.heading0_deg.to_radians().sin_cos();
            let step = [
                (ch * ned[0] + sh * ned[1]) * dt,
                (-sh * ned[0] + ch * ned[1]) * dt,
                ned[2] * dt,
            ];
            for (p, d) in self.dr.pos.iter_mut().zip(step) {
                *p += d;
            }
            self.dr.travelled_m += step.iter().map(|d| d * d).sum::<f64>().sqrt();
            self.dr.last_t = Some(s.t);
        } else {
            self.dr.last_t = None;
        }
        let var = r.fom * r.fom;
        Some(
            VelocityReport {
                time_ms,
                time_of_validity_us: Some(us),
                time_of_transmission_us: Some(us),
                vel_body_mps: r.velocity_mps,
                fom_mps: r.fom,
                covariance: Some([[var, 0.0, 0.0], [0.0, var, 0.0], [0.0, 0.0, var]]),
                altitude_m: r.altitude_m,
                transducers,
                velocity_valid: r.valid,
                status: 0,
                format: Some(FORMAT.to_string()),
            }
            .encode(),
        )
    }

    fn dead_reckoning(&self, s: &Situation) -> String {
        DeadReckoningReport {
            ts_s: (s.t * 1000.0).round() / 1000.0,
            x_m: self.dr.pos[0],
            y_m: self.dr.pos[1],
            z_m: self.dr.pos[2],
            std_m: 0.0101 * self.dr.travelled_m,
            roll_deg: s.truth.roll_rad.to_degrees(),
            pitch_deg: s.truth.pitch_rad.to_degrees(),
            yaw_deg: angle180(s.truth.heading_deg - self.dr.heading0_deg),
            status: 0,
            format: Some(FORMAT.to_string()),
        }
        .encode()
    }
}

impl Device for A50 {
    fn name(&self) -> &'static str {
        "dvl"
    }

    fn period(&self) -> f64 {
        0.02
    }

    fn connected(&mut self, _: &Situation) -> Vec<u8> {
        self.lines.reset();
        Vec::new()
    }

    fn tick(&mut self, s: &Situation) -> Vec<u8> {
        let mut out = String::new();
        if let Some(done) = self.gyro_done_at
            && s.t + 1e-9 >= done
        {
            self.gyro_done_at = None;
            out.push_str(&Self::respond("calibrate_gyro", None, None));
        }
        if self.acoustic_enabled() {
            if let Some(v) = self.velocity(s) {
                out.push_str(&v);
            }
            if s.t + 1e-9 >= self.next_dr_t {
                out.push_str(&self.dead_reckoning(s));
                self.next_dr_t = (self.next_dr_t + DR_PERIOD_S).max(s.t + DR_PERIOD_S * 0.5);
            }
        } else {
            // The pings stop; so does the integration.
            self.dr.last_t = None;
        }
        out.into_bytes()
    }

    fn receive(&mut self, s: &Situation, data: &[u8]) -> Vec<u8> {
        let mut lines = Vec::new();
        self.lines.push(data, |l| lines.push(l.to_vec()));
        lines
            .iter()
            .flat_map(|l| self.command(s, l).into_bytes())
            .collect()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn at(t: f64, depth: f64) -> Situation {
        Situation {
            t,
            unix_s: 1_795_000_000.0 + t,
            truth: Truth {
                time: t,
                depth,
                heading_deg: 90.0,
                vel_east_mps: 1.0,
                speed_mps: 1.0,
                ..Truth::default()
            },
            leak: false,
            battery_drop_v: 0.0,
        }
    }

    fn quiet() -> A50Settings {
        let mut s = A50Settings::default();
        s.model.noise_mps = 0.0;
        s.model.scale_error = 0.0;
        s.model.altitude_noise_m = 0.0;
        s
    }

    fn messages(bytes: &[u8]) -> Vec<a50::Message> {
        bytes
            .split(|&b| b == b'\n')
            .filter(|l| !l.is_empty())
            .map(|l| a50::parse(l).unwrap())
            .collect()
    }

    #[test]
    fn velocity_reports_carry_the_truth_in_the_body_frame() {
        let mut d = A50::new(quiet(), 1);
        let m = messages(&d.tick(&at(0.0, 10.0)));
        assert_eq!(m.len(), 2, "a velocity and a dead-reckoning report");
        let a50::Message::Velocity(v) = &m[0] else {
            panic!("{m:?}")
        };
        assert!(v.velocity_valid);
        assert!(
            (v.vel_body_mps[0] - 1.0).abs() < 1e-12,
            "{:?}",
            v.vel_body_mps
        );
        assert!(v.vel_body_mps[1].abs() < 1e-12 && v.vel_body_mps[2].abs() < 1e-12);
        assert_eq!(v.altitude_m, 20.0);
        assert_eq!(v.time_of_validity_us, Some(1_795_000_000_000_000));
        assert_eq!(v.format.as_deref(), Some(FORMAT));
        assert_eq!(v.transducers.len(), 4);
        let c = BEAM_ANGLE_DEG.to_radians().cos();
        assert!((v.transducers[0].distance_m - 20.0 / c).abs() < 1e-12);
        let s = BEAM_ANGLE_DEG.to_radians().sin();
        assert!((v.transducers[1].velocity_mps - s * 135f64.to_radians().cos()).abs() < 1e-12);
        // At 20 m altitude the model pings at 15 - 13 * 19.95 / 49.95 Hz.
        let rate = 15.0 - 13.0 * (20.0 - 0.05) / 49.95;
        let mut n = 0;
        let mut last_ms = 0.0;
        for k in 1..=500 {
            for m in messages(&d.tick(&at(f64::from(k) * 0.02, 10.0))) {
                if let a50::Message::Velocity(v) = m {
                    n += 1;
                    last_ms = v.time_ms;
                }
            }
        }
        assert!(
            (f64::from(n) - 10.0 * rate).abs() <= 1.0,
            "{n} in 10 s at {rate} Hz"
        );
        assert!((last_ms - 1000.0 / rate).abs() <= 20.0, "{last_ms}");
    }

    #[test]
    fn out_of_range_there_is_no_bottom_lock() {
        let mut s = quiet();
        s.water_depth_m = 100.0;
        let mut d = A50::new(s, 1);
        let m = messages(&d.tick(&at(0.0, 1.0)));
        let a50::Message::Velocity(v) = &m[0] else {
            panic!()
        };
        assert!(!v.velocity_valid && v.altitude_m == -1.0);
        assert!(v.transducers.iter().all(|t| !t.beam_valid));
    }

    #[test]
    fn commands_change_the_state_and_get_the_documented_answers() {
        let mut d = A50::new(quiet(), 1);
        let off = Command::SetConfig(Config {
            acoustic_enabled: Some(false),
            ..Config::default()
        })
        .encode();
        let m = messages(&d.receive(&at(0.0, 5.0), off.as_bytes()));
        let a50::Message::Response(r) = &m[0] else {
            panic!()
        };
        assert_eq!(
            (r.response_to.as_str(), r.success, &r.result),
            ("set_config", true, &None)
        );
        assert!(!d.acoustic_enabled());
        assert!(
            d.tick(&at(0.1, 5.0)).is_empty(),
            "acoustics off: no reports"
        );
        // get_config, split across two reads.
        let get = Command::GetConfig.encode();
        let (a, b) = get.as_bytes().split_at(7);
        assert!(d.receive(&at(0.2, 5.0), a).is_empty());
        let m = messages(&d.receive(&at(0.2, 5.0), b));
        let a50::Message::Response(r) = &m[0] else {
            panic!()
        };
        let c = r.result.clone().unwrap();
        assert_eq!(
            (c.acoustic_enabled, c.speed_of_sound_mps),
            (Some(false), Some(1475.0))
        );
        // A bad speed of sound is refused and changes nothing.
        let bad = br#"{"command":"set_config","parameters":{"speed_of_sound":99}}"#;
        let m = messages(&d.receive(&at(0.3, 5.0), &[&bad[..], b"\n"].concat()));
        let a50::Message::Response(r) = &m[0] else {
            panic!()
        };
        assert!(!r.success && r.error_message.contains("speed_of_sound"));
        // Unknown commands and non-JSON lines get an error answer.
        let m = messages(&d.receive(
            &at(0.3, 5.0),
            b"{\"command\":\"self_destruct\"}\nnot json\n",
        ));
        assert_eq!(m.len(), 2);
        let a50::Message::Response(r) = &m[0] else {
            panic!()
        };
        assert_eq!(
            (r.response_to.as_str(), r.success),
            ("self_destruct", false)
        );
        // calibrate_gyro answers after its calibration time.
        assert!(
            d.receive(&at(1.0, 5.0), Command::CalibrateGyro.encode().as_bytes())
                .is_empty()
        );
        assert!(d.tick(&at(1.5, 5.0)).is_empty());
        let m = messages(&d.tick(&at(2.0, 5.0)));
        let a50::Message::Response(r) = &m[0] else {
            panic!()
        };
        assert_eq!(
            (r.response_to.as_str(), r.success),
            ("calibrate_gyro", true)
        );
        assert_eq!(d.commands(), 6);
    }

    #[test]
    fn dead_reckoning_integrates_from_its_reset_in_the_reset_frame() {
        let mut d = A50::new(quiet(), 1);
        d.receive(
            &at(0.0, 5.0),
            Command::ResetDeadReckoning.encode().as_bytes(),
        );
        let mut last = None;
        for k in 0..=500 {
            for m in messages(&d.tick(&at(f64::from(k) * 0.02, 5.0))) {
                if let a50::Message::DeadReckoning(r) = m {
                    last = Some(r);
                }
            }
        }
        // 10 s east at 1 m/s with the reset heading east: 10 m along x (to the last ping).
        let r = last.unwrap();
        assert!((r.x_m - 10.0).abs() < 0.1 && r.y_m.abs() < 1e-9, "{r:?}");
        assert!((r.std_m - 0.0101 * r.x_m).abs() < 1e-9 && r.yaw_deg == 0.0);
        assert_eq!(r.ts_s, 10.0);
        let m = messages(&d.receive(
            &at(10.0, 5.0),
            Command::ResetDeadReckoning.encode().as_bytes(),
        ));
        let a50::Message::Response(r) = &m[0] else {
            panic!()
        };
        assert!(r.success);
        let m = messages(&d.tick(&at(10.2, 5.0)));
        let Some(a50::Message::DeadReckoning(r)) = m.last() else {
            panic!("{m:?}")
        };
        assert!(r.x_m.abs() < 1e-9);
    }
}
