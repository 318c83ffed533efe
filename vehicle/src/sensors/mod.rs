//! Simulated navigation sensors of a CoUGARs-like AUV, driven by the simulator's truth: the
//! Water Linked A50 DVL ([`dvl`]), the SeaTrac X150's internal AHRS ([`ahrs`]), the MS5837
//! pressure sensor read through the Teensy ([`pressure`]) and a gpsd GPS ([`gps`]).
//!
//! Pure: no I/O, no clock. Each sensor is a struct built from [`SensorConfig`] and a seed;
//! `sample(&Truth)` returns its measurement when one is due at `truth.time` (each sensor keeps
//! its own schedule) and `None` otherwise. Every random draw comes from the sensor's own
//! seeded generator ([`Noise`]), so the same seed and the same truths give the same values,
//! and switching one sensor off does not change the others' draws.
//!
//! Frames and units (the ones the real drivers give, see `cougars-vehicle.md` §2.1, §3):
//!
//! | quantity | convention |
//! |---|---|
//! | x, y | local grid metres, x east, y north (MOOS) |
//! | depth | metres, positive down |
//! | heading | compass degrees, clockwise from true north, `[0, 360)` |
//! | pitch, roll | nose up positive, starboard down positive (uSimMarine's pitch sign) |
//! | body frame | FRD: forward, starboard, down (the A50's own frame) |
//! | world velocity | east, north, down, m/s |
//!
//! The MOOS app around these models is `runtime::sensors` (`uSimSensors`); its module docs
//! list every posted variable.

pub mod ahrs;
pub mod dvl;
pub mod gps;
pub mod pressure;

pub use ahrs::{Ahrs, AhrsReport};
pub use dvl::{Dvl, DvlReport};
pub use gps::{Gps, GpsReport};
pub use pressure::{PressureReport, PressureSensor};

use crate::angle::angle180;
use crate::config::{ConfigError, Param, apply_params, strict};

const APP: &str = "uSimSensors";

/// Slack on due times, seconds: tick times `k / AppTick` and sums of periods differ in the
/// last bits, and a report must not slip a whole tick for that.
const DUE_EPS: f64 = 1e-6;

/// The vehicle's true state at one instant, as the simulator knows it.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct Truth {
    /// MOOS time, seconds.
    pub time: f64,
    /// Metres east of the origin.
    pub x: f64,
    /// Metres north of the origin.
    pub y: f64,
    /// Depth, metres, positive down (0 at the surface).
    pub depth: f64,
    /// Compass heading, degrees clockwise from true north.
    pub heading_deg: f64,
    /// Pitch, radians, nose up positive.
    pub pitch_rad: f64,
    /// Roll, radians, starboard down positive.
    pub roll_rad: f64,
    /// Speed through the water, m/s.
    pub speed_mps: f64,
    /// Velocity over ground, east, m/s (world frame).
    pub vel_east_mps: f64,
    /// Velocity over ground, north, m/s (world frame).
    pub vel_north_mps: f64,
    /// Velocity over ground, down, m/s (world frame; positive while diving).
    pub vel_down_mps: f64,
    /// Rate of change of the heading, degrees/s (clockwise positive).
    pub yaw_rate_deg_s: f64,
    /// Rate of change of the pitch, radians/s.
    pub pitch_rate_rad_s: f64,
    /// Rate of change of the roll, radians/s.
    pub roll_rate_rad_s: f64,
}

impl Truth {
    /// The velocity over ground in the body frame (forward, starboard, down), m/s: the world
    /// velocity rotated by the inverse of the ZYX (heading, pitch, roll) attitude.
    pub fn body_velocity(&self) -> [f64; 3] {
        let (sp, cp) = self.heading_deg.to_radians().sin_cos();
        let (st, ct) = self.pitch_rad.sin_cos();
        let (sr, cr) = self.roll_rad.sin_cos();
        // NED components.
        let (n, e, d) = (self.vel_north_mps, self.vel_east_mps, self.vel_down_mps);
        let fwd = ct * cp * n + ct * sp * e - st * d;
        let stb = (sr * st * cp - cr * sp) * n + (sr * st * sp + cr * cp) * e + sr * ct * d;
        let down = (cr * st * cp + sr * sp) * n + (cr * st * sp - sr * cp) * e + cr * ct * d;
        [fwd, stb, down]
    }

    /// The body angular rates (p roll, q pitch, r yaw about forward, starboard, down), rad/s,
    /// from the Euler angle rates, as a strapdown gyro measures them.
    pub fn body_rates(&self) -> [f64; 3] {
        let (st, ct) = self.pitch_rad.sin_cos();
        let (sr, cr) = self.roll_rad.sin_cos();
        let psi_dot = self.yaw_rate_deg_s.to_radians();
        let (theta_dot, phi_dot) = (self.pitch_rate_rad_s, self.roll_rate_rad_s);
        let p = phi_dot - psi_dot * st;
        let q = theta_dot * cr + psi_dot * ct * sr;
        let r = -theta_dot * sr + psi_dot * ct * cr;
        [p, q, r]
    }

    /// The truth moved on to `time`: position and depth at constant velocity, heading at
    /// the yaw rate (a record `dt` old is extrapolated so a sensor sampling between the
    /// simulator's postings sees a smooth track). Pitch and roll are held: uSimMarine's
    /// pitch jumps between iterations, and its differences are no rate to extrapolate with.
    pub fn advanced_to(&self, time: f64) -> Truth {
        let dt = time - self.time;
        Truth {
            time,
            x: self.x + self.vel_east_mps * dt,
            y: self.y + self.vel_north_mps * dt,
            depth: (self.depth + self.vel_down_mps * dt).max(0.0),
            heading_deg: crate::angle::angle360(self.heading_deg + self.yaw_rate_deg_s * dt),
            ..*self
        }
    }
}

/// Builds a [`Truth`] from the simulator's separate postings (`SIM_X`, `SIM_HEADING`, ...),
/// deriving the rates the simulator does not post (heading, pitch and depth rates) from
/// successive records.
#[derive(Debug, Clone, Default)]
pub struct TruthTracker {
    cur: Truth,
    have_pos: [bool; 4],
    have_vel: bool,
    // The previous distinct record of each differentiated quantity: (time, value).
    prev_heading: Option<(f64, f64)>,
    prev_pitch: Option<(f64, f64)>,
    prev_depth: Option<(f64, f64)>,
    sog: f64,
    hog_deg: f64,
}

/// One field of the simulator's truth, as the simulator posts it under its prefix.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum TruthField {
    /// `<P>_X`, m.
    X,
    /// `<P>_Y`, m.
    Y,
    /// `<P>_DEPTH`, m.
    Depth,
    /// `<P>_HEADING`, degrees.
    Heading,
    /// `<P>_SPEED`, m/s through the water.
    Speed,
    /// `<P>_PITCH`, radians, nose up positive.
    Pitch,
    /// `<P>_HEADING_OVER_GROUND`, degrees.
    HeadingOverGround,
    /// `<P>_SPEED_OVER_GROUND`, m/s.
    SpeedOverGround,
}

impl TruthField {
    /// Every field, with the suffix the simulator posts it under (`<P>_<suffix>`).
    pub const ALL: [(TruthField, &'static str); 8] = [
        (TruthField::X, "X"),
        (TruthField::Y, "Y"),
        (TruthField::Depth, "DEPTH"),
        (TruthField::Heading, "HEADING"),
        (TruthField::Speed, "SPEED"),
        (TruthField::Pitch, "PITCH"),
        (TruthField::HeadingOverGround, "HEADING_OVER_GROUND"),
        (TruthField::SpeedOverGround, "SPEED_OVER_GROUND"),
    ];
}

/// The rate of a quantity between two records, 0 when they share a time.
fn rate(prev: Option<(f64, f64)>, time: f64, delta: impl Fn(f64) -> f64) -> Option<f64> {
    let (t0, v0) = prev?;
    (time > t0).then(|| delta(v0) / (time - t0))
}

impl TruthTracker {
    /// An empty tracker: no truth until x, y, depth and heading have arrived.
    pub fn new() -> Self {
        Self::default()
    }

    /// Takes one field posted at MOOS time `time`. Non-finite values are ignored.
    pub fn update(&mut self, field: TruthField, value: f64, time: f64) {
        if !value.is_finite() || !time.is_finite() {
            return;
        }
        self.cur.time = self.cur.time.max(time);
        match field {
            TruthField::X => {
                self.cur.x = value;
                self.have_pos[0] = true;
            }
            TruthField::Y => {
                self.cur.y = value;
                self.have_pos[1] = true;
            }
            TruthField::Depth => {
                if let Some(r) = rate(self.prev_depth, time, |d0| value - d0) {
                    self.cur.vel_down_mps = r;
                }
                if self.prev_depth.is_none_or(|(t0, _)| time > t0) {
                    self.prev_depth = Some((time, value));
                }
                self.cur.depth = value;
                self.have_pos[2] = true;
            }
            TruthField::Heading => {
                if let Some(r) = rate(self.prev_heading, time, |h0| angle180(value - h0)) {
                    self.cur.yaw_rate_deg_s = r;
                }
                if self.prev_heading.is_none_or(|(t0, _)| time > t0) {
                    self.prev_heading = Some((time, value));
                }
                self.cur.heading_deg = value;
                self.have_pos[3] = true;
            }
            TruthField::Speed => self.cur.speed_mps = value,
            TruthField::Pitch => {
                if let Some(r) = rate(self.prev_pitch, time, |p0| value - p0) {
                    self.cur.pitch_rate_rad_s = r;
                }
                if self.prev_pitch.is_none_or(|(t0, _)| time > t0) {
                    self.prev_pitch = Some((time, value));
                }
                self.cur.pitch_rad = value;
            }
            TruthField::HeadingOverGround => {
                self.hog_deg = value;
                self.set_ground_velocity();
            }
            TruthField::SpeedOverGround => {
                self.sog = value;
                self.have_vel = true;
                self.set_ground_velocity();
            }
        }
    }

    fn set_ground_velocity(&mut self) {
        let (s, c) = self.hog_deg.to_radians().sin_cos();
        self.cur.vel_east_mps = self.sog * s;
        self.cur.vel_north_mps = self.sog * c;
    }

    /// The truth at `now` (the latest record moved on at its velocity), once x, y, depth and
    /// heading are known. Without the speed over ground the horizontal velocity is the speed
    /// through the water along the heading.
    pub fn truth(&self, now: f64) -> Option<Truth> {
        if !self.have_pos.iter().all(|b| *b) {
            return None;
        }
        let mut t = self.cur;
        if !self.have_vel {
            let (s, c) = t.heading_deg.to_radians().sin_cos();
            t.vel_east_mps = t.speed_mps * s;
            t.vel_north_mps = t.speed_mps * c;
        }
        Some(t.advanced_to(now.max(t.time)))
    }
}

/// A seeded source of white noise: the only randomness of the sensor models.
#[derive(Debug, Clone)]
pub struct Noise {
    rng: fastrand::Rng,
}

impl Noise {
    /// A generator from `seed`, salted with `salt` (one per sensor).
    pub fn new(seed: u64, salt: u64) -> Self {
        let mixed = seed ^ salt.wrapping_mul(0x9e37_79b9_7f4a_7c15);
        Noise {
            rng: fastrand::Rng::with_seed(mixed),
        }
    }

    /// A uniform draw in `[0, 1)`.
    pub fn uniform(&mut self) -> f64 {
        self.rng.f64()
    }

    /// A uniform integer in `lo..=hi`.
    pub fn int(&mut self, lo: u32, hi: u32) -> u32 {
        self.rng.u32(lo..=hi)
    }

    /// A zero-mean normal draw with standard deviation `std` (Box-Muller; 0 when `std` is
    /// 0, without consuming a draw, so a noiseless sensor keeps the others' sequences).
    pub fn gauss(&mut self, std: f64) -> f64 {
        if std == 0.0 {
            return 0.0;
        }
        // 1 - u is in (0, 1]: the logarithm stays finite.
        let u1 = 1.0 - self.rng.f64();
        let u2 = self.rng.f64();
        std * (-2.0 * u1.ln()).sqrt() * (std::f64::consts::TAU * u2).cos()
    }
}

/// When a periodic report is next due.
#[derive(Debug, Clone, Copy, Default, PartialEq)]
pub struct Schedule {
    next: Option<f64>,
}

impl Schedule {
    /// True when a report is due at `time` (the first call always is).
    pub fn due(&self, time: f64) -> bool {
        self.next.is_none_or(|n| time + DUE_EPS >= n)
    }

    /// A report was made at `time`; the next is `period` after the one that was due (keeping
    /// the phase, so the mean rate is exact when ticks do not divide the period), or after
    /// `time` when the reports fell more than a period behind.
    pub fn done(&mut self, time: f64, period: f64) {
        let base = self.next.unwrap_or(time);
        let mut n = base + period;
        if n <= time + DUE_EPS {
            n = time + period;
        }
        self.next = Some(n);
    }
}

/// The settings of all four sensors (the `uSimSensors` ProcessConfig block). `Default` gives
/// the documented defaults.
#[derive(Debug, Clone, PartialEq)]
pub struct SensorConfig {
    /// `prefix`: the simulator's truth prefix (`SIM` reads `SIM_X`, ...).
    pub prefix: String,
    /// `seed`: seeds every draw; `None` takes the run's seed.
    pub seed: Option<u64>,
    /// `water_depth`, m: the flat bottom the DVL sees (altitude = water depth - depth).
    pub water_depth: f64,
    /// DVL settings.
    pub dvl: dvl::DvlConfig,
    /// AHRS settings.
    pub ahrs: ahrs::AhrsConfig,
    /// Pressure settings.
    pub pressure: pressure::PressureConfig,
    /// GPS settings.
    pub gps: gps::GpsConfig,
}

impl Default for SensorConfig {
    fn default() -> Self {
        SensorConfig {
            prefix: "SIM".to_string(),
            seed: None,
            water_depth: 30.0,
            dvl: dvl::DvlConfig::default(),
            ahrs: ahrs::AhrsConfig::default(),
            pressure: pressure::PressureConfig::default(),
            gps: gps::GpsConfig::default(),
        }
    }
}

impl SensorConfig {
    /// Strict: the first unknown key or bad value is an error.
    ///
    /// ```
    /// use vehicle::sensors::SensorConfig;
    /// let c = SensorConfig::from_params([("heading_bias", "3"), ("seed", "7")]).unwrap();
    /// assert_eq!(c.ahrs.heading_bias_deg, 3.0);
    /// assert_eq!(c.seed, Some(7));
    /// ```
    pub fn from_params<'a>(
        params: impl IntoIterator<Item = (&'a str, &'a str)>,
    ) -> Result<Self, ConfigError> {
        strict(Self::from_params_lenient(params))
    }

    /// Lenient: unknown keys and bad values are returned beside the config (bad values keep
    /// the default), for the app to warn about.
    pub fn from_params_lenient<'a>(
        params: impl IntoIterator<Item = (&'a str, &'a str)>,
    ) -> Result<(Self, Vec<ConfigError>), ConfigError> {
        let mut cfg = SensorConfig::default();
        let unknown = apply_params(APP, &mut cfg, params, |c, key, p| c.apply_one(key, p))?;
        Ok((cfg, unknown))
    }

    /// The highest report rate of the enabled sensors, Hz (the AppTick the app needs).
    pub fn max_rate_hz(&self) -> f64 {
        let mut r: f64 = 0.0;
        if self.dvl.enabled {
            r = r.max(self.dvl.max_rate_hz);
        }
        if self.ahrs.enabled {
            r = r.max(self.ahrs.rate_hz);
        }
        if self.pressure.enabled {
            r = r.max(self.pressure.rate_hz);
        }
        if self.gps.enabled {
            r = r.max(self.gps.rate_hz);
        }
        r
    }

    fn apply_one(&mut self, key: &str, p: Param<'_>) -> Result<bool, ConfigError> {
        match key {
            "prefix" => self.prefix = p.word()?,
            "seed" => {
                self.seed = Some(
                    p.value
                        .parse::<u64>()
                        .map_err(|_| p.bad("a non-negative integer"))?,
                );
            }
            "water_depth" => self.water_depth = p.pos()?,
            "enable_dvl" => self.dvl.enabled = p.bool()?,
            "enable_ahrs" => self.ahrs.enabled = p.bool()?,
            "enable_pressure" => self.pressure.enabled = p.bool()?,
            "enable_gps" => self.gps.enabled = p.bool()?,
            // DVL
            "dvl_noise" => self.dvl.noise_mps = p.non_neg()?,
            "dvl_scale_error" => self.dvl.scale_error = p.range(-0.5, 0.5, "in [-0.5, 0.5]")?,
            "dvl_min_altitude" => self.dvl.min_altitude_m = p.non_neg()?,
            "dvl_max_altitude" => self.dvl.max_altitude_m = p.pos()?,
            "dvl_min_rate" => self.dvl.min_rate_hz = p.pos()?,
            "dvl_max_rate" => self.dvl.max_rate_hz = p.pos()?,
            "dvl_altitude_noise" => self.dvl.altitude_noise_m = p.non_neg()?,
            "dvl_water_track" => self.dvl.water_track = p.bool()?,
            // AHRS
            "ahrs_rate" => self.ahrs.rate_hz = p.pos()?,
            "heading_bias" => self.ahrs.heading_bias_deg = p.f64()?,
            "heading_noise" => self.ahrs.heading_noise_deg = p.non_neg()?,
            "attitude_noise" => self.ahrs.attitude_noise_deg = p.non_neg()?,
            "gyro_noise" => self.ahrs.gyro_noise_deg_s = p.non_neg()?,
            // Pressure
            "pressure_rate" => self.pressure.rate_hz = p.pos()?,
            "salinity" => self.pressure.salinity_ppt = p.range(0.0, 50.0, "0 to 50 ppt")?,
            "atmospheric_pressure" => self.pressure.atmospheric_pa = p.pos()?,
            "pressure_noise" => self.pressure.noise_pa = p.non_neg()?,
            "pressure_quantum" => self.pressure.quantum_pa = p.non_neg()?,
            // GPS
            "gps_rate" => self.gps.rate_hz = p.pos()?,
            "gps_noise" => self.gps.noise_m = p.non_neg()?,
            "gps_max_depth" => self.gps.max_depth_m = p.non_neg()?,
            "gps_acquire_time" => self.gps.acquire_time_s = p.non_neg()?,
            "gps_loss_prob" => self.gps.loss_prob = p.range(0.0, 1.0, "a probability in [0, 1]")?,
            _ => return Ok(false),
        }
        if self.dvl.min_rate_hz > self.dvl.max_rate_hz {
            self.dvl.min_rate_hz = self.dvl.max_rate_hz;
        }
        Ok(true)
    }
}

/// What one sampling instant produced.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct Reports {
    /// A DVL report, when one was due.
    pub dvl: Option<DvlReport>,
    /// An AHRS report, when one was due.
    pub ahrs: Option<AhrsReport>,
    /// A pressure report, when one was due.
    pub pressure: Option<PressureReport>,
    /// A GPS report, when one was due.
    pub gps: Option<GpsReport>,
}

/// The four sensors together, as the `uSimSensors` app runs them.
#[derive(Debug, Clone)]
pub struct SensorSuite {
    cfg: SensorConfig,
    /// The DVL.
    pub dvl: Dvl,
    /// The AHRS.
    pub ahrs: Ahrs,
    /// The pressure sensor.
    pub pressure: PressureSensor,
    /// The GPS.
    pub gps: Gps,
}

impl SensorSuite {
    /// The sensors of `cfg`, every draw from `seed` (the config's own seed wins).
    pub fn new(cfg: SensorConfig, seed: u64) -> Self {
        let seed = cfg.seed.unwrap_or(seed);
        SensorSuite {
            dvl: Dvl::new(cfg.dvl.clone(), cfg.water_depth, seed),
            ahrs: Ahrs::new(cfg.ahrs.clone(), seed),
            pressure: PressureSensor::new(cfg.pressure.clone(), seed),
            gps: Gps::new(cfg.gps.clone(), seed),
            cfg,
        }
    }

    /// The configuration.
    pub fn config(&self) -> &SensorConfig {
        &self.cfg
    }

    /// Samples every enabled sensor at `truth.time`.
    pub fn sample(&mut self, truth: &Truth) -> Reports {
        Reports {
            dvl: self.dvl.sample(truth),
            ahrs: self.ahrs.sample(truth),
            pressure: self.pressure.sample(truth),
            gps: self.gps.sample(truth),
        }
    }
}

/// Mean and (population) standard deviation of `v`, for the statistics tests.
#[cfg(test)]
pub(crate) fn mean_std(v: &[f64]) -> (f64, f64) {
    let n = v.len() as f64;
    let m = v.iter().sum::<f64>() / n;
    let var = v.iter().map(|x| (x - m).powi(2)).sum::<f64>() / n;
    (m, var.sqrt())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn body_velocity_rotates_world_into_frd() {
        // Heading east at 2 m/s, level: all forward.
        let t = Truth {
            heading_deg: 90.0,
            vel_east_mps: 2.0,
            ..Truth::default()
        };
        let v = t.body_velocity();
        assert!((v[0] - 2.0).abs() < 1e-12 && v[1].abs() < 1e-12 && v[2].abs() < 1e-12);
        // Heading north, a current to the east: to starboard.
        let t = Truth {
            heading_deg: 0.0,
            vel_east_mps: 0.5,
            ..Truth::default()
        };
        let v = t.body_velocity();
        assert!(v[0].abs() < 1e-12 && (v[1] - 0.5).abs() < 1e-12);
        // Nose down 30 degrees, moving along the body axis: all forward.
        let th: f64 = -30f64.to_radians();
        let t = Truth {
            heading_deg: 0.0,
            pitch_rad: th,
            vel_north_mps: th.cos(),
            vel_down_mps: -th.sin(),
            ..Truth::default()
        };
        let v = t.body_velocity();
        assert!((v[0] - 1.0).abs() < 1e-12 && v[1].abs() < 1e-12 && v[2].abs() < 1e-12);
        // Rolled 90 degrees starboard down, the starboard axis points down: sinking is
        // starboard velocity.
        let t = Truth {
            roll_rad: std::f64::consts::FRAC_PI_2,
            vel_down_mps: 1.0,
            ..Truth::default()
        };
        let v = t.body_velocity();
        assert!((v[1] - 1.0).abs() < 1e-12 && v[2].abs() < 1e-12, "{v:?}");
    }

    #[test]
    fn body_rates_of_a_level_turn_are_yaw_only() {
        let t = Truth {
            yaw_rate_deg_s: 10.0,
            ..Truth::default()
        };
        let [p, q, r] = t.body_rates();
        assert_eq!((p, q), (0.0, 0.0));
        assert!((r - 10f64.to_radians()).abs() < 1e-15);
    }

    #[test]
    fn tracker_derives_rates_and_waits_for_a_full_record() {
        let mut tr = TruthTracker::new();
        tr.update(TruthField::X, 1.0, 10.0);
        tr.update(TruthField::Y, 2.0, 10.0);
        tr.update(TruthField::Heading, 359.0, 10.0);
        assert!(tr.truth(10.0).is_none(), "no depth yet");
        tr.update(TruthField::Depth, 1.0, 10.0);
        tr.update(TruthField::SpeedOverGround, 1.0, 10.0);
        tr.update(TruthField::HeadingOverGround, 90.0, 10.0);
        tr.update(TruthField::Heading, 1.0, 10.5);
        tr.update(TruthField::Depth, 1.5, 10.5);
        tr.update(TruthField::X, 1.5, 10.5);
        let t = tr.truth(10.5).unwrap();
        assert!(
            (t.yaw_rate_deg_s - 4.0).abs() < 1e-12,
            "wraps through north"
        );
        assert!((t.vel_down_mps - 1.0).abs() < 1e-12);
        assert!((t.vel_east_mps - 1.0).abs() < 1e-12);
        // Extrapolated a quarter second on.
        let t = tr.truth(10.75).unwrap();
        assert!((t.x - 1.75).abs() < 1e-12 && (t.depth - 1.75).abs() < 1e-12);
        assert!((t.heading_deg - 2.0).abs() < 1e-9);
        // A non-finite value is ignored.
        tr.update(TruthField::X, f64::NAN, 11.0);
        assert!(tr.truth(11.0).unwrap().x.is_finite());
    }

    #[test]
    fn schedule_keeps_its_phase_and_mean_rate() {
        // 15 Hz reports on a 20 Hz tick: 15 reports a second on average.
        let mut s = Schedule::default();
        let mut n = 0;
        for k in 0..2000 {
            let t = 100.0 + f64::from(k) / 20.0;
            if s.due(t) {
                s.done(t, 1.0 / 15.0);
                n += 1;
            }
        }
        assert!((n - 1500_i32).abs() <= 1, "{n}");
        // 10 Hz on a 20 Hz tick: every other tick, despite rounding.
        let mut s = Schedule::default();
        let due: Vec<bool> = (0..40)
            .map(|k| {
                let t = 1_786_000_000.0 + f64::from(k) / 20.0;
                let d = s.due(t);
                if d {
                    s.done(t, 0.1);
                }
                d
            })
            .collect();
        assert!(due.iter().step_by(2).all(|d| *d));
        assert!(due.iter().skip(1).step_by(2).all(|d| !*d));
    }

    #[test]
    fn config_reads_every_key_and_reports_unknown_ones() {
        let (c, bad) = SensorConfig::from_params_lenient([
            ("prefix", "TRUTH"),
            ("water_depth", "12"),
            ("enable_gps", "false"),
            ("dvl_noise", "0.05"),
            ("salinity", "35"),
            ("AppTick", "20"),
            ("gps_loss_prob", "2"),
            ("colour", "red"),
        ])
        .unwrap();
        assert_eq!(c.prefix, "TRUTH");
        assert_eq!(c.water_depth, 12.0);
        assert!(!c.gps.enabled);
        assert_eq!(c.dvl.noise_mps, 0.05);
        assert_eq!(c.pressure.salinity_ppt, 35.0);
        assert_eq!(c.gps.loss_prob, gps::GpsConfig::default().loss_prob);
        assert_eq!(bad.len(), 2, "{bad:?}");
        assert!(matches!(&bad[1], ConfigError::UnknownKey { key, .. } if key == "colour"));
        assert_eq!(c.max_rate_hz(), 20.0);
    }

    #[test]
    fn noise_is_seeded_and_normal() {
        let mut a = Noise::new(5, 1);
        let mut b = Noise::new(5, 1);
        let va: Vec<f64> = (0..20_000).map(|_| a.gauss(2.0)).collect();
        let vb: Vec<f64> = (0..20_000).map(|_| b.gauss(2.0)).collect();
        assert_eq!(va, vb);
        let (m, s) = mean_std(&va);
        assert!(m.abs() < 0.05, "{m}");
        assert!((s - 2.0).abs() < 0.05, "{s}");
        let mut c = Noise::new(5, 2);
        assert_ne!(c.gauss(1.0), va[0] / 2.0);
    }
}
