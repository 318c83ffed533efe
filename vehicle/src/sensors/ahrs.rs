//! The SeaTrac X150's internal AHRS, as the Gen-1 CoUGARs read it (`cougars-vehicle.md`
//! §2.1, §3.4, §3.5): a `CID_STATUS` at 10 Hz with the attitude (yaw, pitch, roll in
//! decidegrees) and the compensated gyro rates.
//!
//! Model:
//! - heading = true heading + `heading_bias` (a constant: a wrong declination or a bad
//!   compass calibration) + white noise σ `heading_noise` (1°, the HoloOcean bridge's
//!   modem AHRS), wrapped to `[0, 360)`; it is the heading the Gen-1 driver gives after
//!   adding its declination, so it is referred to true north;
//! - pitch, roll = truth + white noise σ `attitude_noise` (0.2°);
//! - gyro = the body rates (roll, pitch, yaw about forward, starboard, down) + white noise σ
//!   `gyro_noise` (0.05 deg/s, the SBG-class figure of the bridge, 7.4e-4 rad/s);
//! - the attitude angles are quantised to the X150's 0.1° (its decidegree fields); the gyro
//!   rates are its `AHRS_COMP` floats, not quantised.

use super::{Noise, Schedule, Truth};
use crate::angle::angle360;

/// AHRS settings.
#[derive(Debug, Clone, PartialEq)]
pub struct AhrsConfig {
    /// `enable_ahrs` (true).
    pub enabled: bool,
    /// `ahrs_rate`, Hz (10, the X150's status rate as the CoUGARs configure it).
    pub rate_hz: f64,
    /// `heading_bias`, degrees (0).
    pub heading_bias_deg: f64,
    /// `heading_noise`, degrees (1).
    pub heading_noise_deg: f64,
    /// `attitude_noise`, degrees, pitch and roll (0.2).
    pub attitude_noise_deg: f64,
    /// `gyro_noise`, degrees/s (0.05).
    pub gyro_noise_deg_s: f64,
}

impl Default for AhrsConfig {
    fn default() -> Self {
        AhrsConfig {
            enabled: true,
            rate_hz: 10.0,
            heading_bias_deg: 0.0,
            heading_noise_deg: 1.0,
            attitude_noise_deg: 0.2,
            gyro_noise_deg_s: 0.05,
        }
    }
}

/// One AHRS report.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct AhrsReport {
    /// MOOS time, s.
    pub time: f64,
    /// Heading, compass degrees `[0, 360)`.
    pub heading_deg: f64,
    /// Pitch, degrees, nose up positive.
    pub pitch_deg: f64,
    /// Roll, degrees, starboard down positive.
    pub roll_deg: f64,
    /// Gyro rates about forward, starboard, down (roll, pitch, yaw rates), degrees/s.
    pub gyro_deg_s: [f64; 3],
}

/// The X150 AHRS model.
#[derive(Debug, Clone)]
pub struct Ahrs {
    cfg: AhrsConfig,
    noise: Noise,
    schedule: Schedule,
}

/// Rounds to the X150's decidegree.
fn deci(deg: f64) -> f64 {
    (deg * 10.0).round() / 10.0
}

impl Ahrs {
    /// An AHRS drawing from `seed`.
    pub fn new(cfg: AhrsConfig, seed: u64) -> Self {
        Ahrs {
            cfg,
            noise: Noise::new(seed, 2),
            schedule: Schedule::default(),
        }
    }

    /// The settings.
    pub fn config(&self) -> &AhrsConfig {
        &self.cfg
    }

    /// The report due at `truth.time`, if any.
    pub fn sample(&mut self, truth: &Truth) -> Option<AhrsReport> {
        if !self.cfg.enabled || !self.schedule.due(truth.time) {
            return None;
        }
        self.schedule.done(truth.time, 1.0 / self.cfg.rate_hz);
        let c = &self.cfg;
        let heading =
            truth.heading_deg + c.heading_bias_deg + self.noise.gauss(c.heading_noise_deg);
        let pitch = truth.pitch_rad.to_degrees() + self.noise.gauss(c.attitude_noise_deg);
        let roll = truth.roll_rad.to_degrees() + self.noise.gauss(c.attitude_noise_deg);
        let rates = truth.body_rates();
        let mut gyro = [0.0; 3];
        for (g, r) in gyro.iter_mut().zip(rates) {
            *g = r.to_degrees() + self.noise.gauss(c.gyro_noise_deg_s);
        }
        Some(AhrsReport {
            time: truth.time,
            heading_deg: angle360(deci(heading)),
            pitch_deg: deci(pitch),
            roll_deg: deci(roll),
            gyro_deg_s: gyro,
        })
    }
}

#[cfg(test)]
mod tests {
    use super::super::mean_std;
    use super::*;
    use crate::angle::angle180;

    fn run(ahrs: &mut Ahrs, truth: Truth, secs: u32) -> Vec<AhrsReport> {
        (0..secs * 20)
            .filter_map(|k| {
                ahrs.sample(&Truth {
                    time: f64::from(k) / 20.0,
                    ..truth
                })
            })
            .collect()
    }

    #[test]
    fn heading_bias_and_noise_have_the_configured_statistics() {
        let cfg = AhrsConfig {
            heading_bias_deg: 3.0,
            heading_noise_deg: 0.8,
            attitude_noise_deg: 0.3,
            gyro_noise_deg_s: 0.1,
            ..AhrsConfig::default()
        };
        let truth = Truth {
            heading_deg: 358.5,
            pitch_rad: -10f64.to_radians(),
            roll_rad: 2f64.to_radians(),
            yaw_rate_deg_s: 4.0,
            ..Truth::default()
        };
        let reps = run(&mut Ahrs::new(cfg, 9), truth, 2000);
        // 10 Hz.
        assert_eq!(reps.len(), 20_000);
        // Heading error, wrapped across north.
        let e: Vec<f64> = reps
            .iter()
            .map(|r| angle180(r.heading_deg - 358.5))
            .collect();
        let (m, s) = mean_std(&e);
        assert!((m - 3.0).abs() < 0.02, "{m}");
        assert!((s - 0.8).abs() < 0.02, "{s}");
        assert!(reps.iter().all(|r| (0.0..360.0).contains(&r.heading_deg)));
        let p: Vec<f64> = reps.iter().map(|r| r.pitch_deg).collect();
        let (m, s) = mean_std(&p);
        assert!((m + 10.0).abs() < 0.01 && (s - 0.3).abs() < 0.02, "{m} {s}");
        let r: Vec<f64> = reps.iter().map(|r| r.roll_deg).collect();
        let (m, s) = mean_std(&r);
        assert!((m - 2.0).abs() < 0.01 && (s - 0.3).abs() < 0.02, "{m} {s}");
        // Yaw rate about the body's down axis, level-ish: 4 cos(10) cos(2) deg/s, plus the
        // pitch-axis share 4 cos(10) sin(2).
        let ct = 10f64.to_radians().cos();
        let gz: Vec<f64> = reps.iter().map(|r| r.gyro_deg_s[2]).collect();
        let (m, s) = mean_std(&gz);
        assert!(
            (m - 4.0 * ct * 2f64.to_radians().cos()).abs() < 0.005,
            "{m}"
        );
        assert!((s - 0.1).abs() < 0.005, "{s}");
        let gy: Vec<f64> = reps.iter().map(|r| r.gyro_deg_s[1]).collect();
        let (m, _) = mean_std(&gy);
        assert!(
            (m - 4.0 * ct * 2f64.to_radians().sin()).abs() < 0.005,
            "{m}"
        );
    }

    #[test]
    fn angles_are_decidegrees_and_seeded() {
        let truth = Truth {
            heading_deg: 45.0,
            ..Truth::default()
        };
        let a = run(&mut Ahrs::new(AhrsConfig::default(), 1), truth, 10);
        let b = run(&mut Ahrs::new(AhrsConfig::default(), 1), truth, 10);
        assert_eq!(a, b);
        for r in &a {
            for v in [r.heading_deg, r.pitch_deg, r.roll_deg] {
                assert!(((v * 10.0).round() - v * 10.0).abs() < 1e-9, "{v}");
            }
        }
        let c = run(&mut Ahrs::new(AhrsConfig::default(), 2), truth, 10);
        assert_ne!(a, c);
    }
}
