//! The Blue Robotics MS5837 (Bar30, the 30BA on coug1) read by the Teensy, which prints
//! `$DEPTH,<pressure Pa>,<temp>` about 20 times a second (`cougars-vehicle.md` §3.1).
//!
//! Model: `P = P_atm + ρ·g·depth + noise`, quantised, with the Gen-1 conversion's constants
//! (§2.1): `ρ = 997 + 0.8·salinity` kg/m³ (salinity in ppt: 0 fresh, 35 sea), `g = 9.81`.
//! Defaults: `P_atm` 101 325 Pa (Utah Lake's vehicles calibrate about 84 000 at 1400 m),
//! noise σ 20 Pa (the 30BA's 0.2 mbar resolution at OSR 8192, about 2 mm of water),
//! quantum 10 Pa (the 30BA's 0.1 mbar output step). [`depth_from_pressure`] is the driver's
//! inverse.

use super::{Noise, Schedule, Truth};

/// Gravity of the Gen-1 conversion, m/s².
pub const G: f64 = 9.81;

/// Water density from salinity (ppt), kg/m³, as the Gen-1 depth converter computes it.
pub fn water_density(salinity_ppt: f64) -> f64 {
    997.0 + 0.8 * salinity_ppt
}

/// Depth (m, positive down) of an absolute pressure (Pa), the Gen-1 converter's formula.
pub fn depth_from_pressure(pressure_pa: f64, atmospheric_pa: f64, salinity_ppt: f64) -> f64 {
    (pressure_pa - atmospheric_pa) / (water_density(salinity_ppt) * G)
}

/// Pressure sensor settings.
#[derive(Debug, Clone, PartialEq)]
pub struct PressureConfig {
    /// `enable_pressure` (true).
    pub enabled: bool,
    /// `pressure_rate`, Hz (20).
    pub rate_hz: f64,
    /// `salinity`, ppt (0: fresh water).
    pub salinity_ppt: f64,
    /// `atmospheric_pressure`, Pa (101325).
    pub atmospheric_pa: f64,
    /// `pressure_noise`, Pa (20).
    pub noise_pa: f64,
    /// `pressure_quantum`, Pa (10; 0 = none).
    pub quantum_pa: f64,
}

impl Default for PressureConfig {
    fn default() -> Self {
        PressureConfig {
            enabled: true,
            rate_hz: 20.0,
            salinity_ppt: 0.0,
            atmospheric_pa: 101_325.0,
            noise_pa: 20.0,
            quantum_pa: 10.0,
        }
    }
}

/// One pressure report.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct PressureReport {
    /// MOOS time, s.
    pub time: f64,
    /// Absolute pressure, Pa.
    pub pressure_pa: f64,
}

/// The MS5837 model.
#[derive(Debug, Clone)]
pub struct PressureSensor {
    cfg: PressureConfig,
    noise: Noise,
    schedule: Schedule,
}

impl PressureSensor {
    /// A pressure sensor drawing from `seed`.
    pub fn new(cfg: PressureConfig, seed: u64) -> Self {
        PressureSensor {
            cfg,
            noise: Noise::new(seed, 3),
            schedule: Schedule::default(),
        }
    }

    /// The settings.
    pub fn config(&self) -> &PressureConfig {
        &self.cfg
    }

    /// The report due at `truth.time`, if any.
    pub fn sample(&mut self, truth: &Truth) -> Option<PressureReport> {
        if !self.cfg.enabled || !self.schedule.due(truth.time) {
            return None;
        }
        self.schedule.done(truth.time, 1.0 / self.cfg.rate_hz);
        let c = &self.cfg;
        let p = c.atmospheric_pa
            + water_density(c.salinity_ppt) * G * truth.depth.max(0.0)
            + self.noise.gauss(c.noise_pa);
        let q = c.quantum_pa;
        let pressure_pa = if q > 0.0 { (p / q).round() * q } else { p };
        Some(PressureReport {
            time: truth.time,
            pressure_pa,
        })
    }
}

#[cfg(test)]
mod tests {
    use super::super::mean_std;
    use super::*;

    fn run(s: &mut PressureSensor, depth: f64, secs: u32) -> Vec<PressureReport> {
        (0..secs * 20)
            .filter_map(|k| {
                s.sample(&Truth {
                    time: f64::from(k) / 20.0,
                    depth,
                    ..Truth::default()
                })
            })
            .collect()
    }

    #[test]
    fn density_follows_salinity() {
        assert_eq!(water_density(0.0), 997.0);
        assert_eq!(water_density(35.0), 1025.0);
    }

    #[test]
    fn pressure_to_depth_round_trip() {
        for (sal, depth) in [(0.0, 0.0), (0.0, 3.0), (35.0, 4.5), (35.0, 40.0)] {
            let cfg = PressureConfig {
                salinity_ppt: sal,
                atmospheric_pa: 84_246.0,
                ..PressureConfig::default()
            };
            let reps = run(&mut PressureSensor::new(cfg.clone(), 4), depth, 500);
            assert_eq!(reps.len(), 10_000, "20 Hz");
            let d: Vec<f64> = reps
                .iter()
                .map(|r| depth_from_pressure(r.pressure_pa, cfg.atmospheric_pa, sal))
                .collect();
            let (m, s) = mean_std(&d);
            // 20 Pa noise is 2 mm of fresh water; the mean is within a tenth of that.
            assert!((m - depth).abs() < 2e-4, "{sal} {depth}: {m}");
            let expect = (20f64.powi(2) + 10f64.powi(2) / 12.0).sqrt() / (water_density(sal) * G);
            assert!((s - expect).abs() < 0.05 * expect, "{s} vs {expect}");
        }
    }

    #[test]
    fn readings_are_quantised_and_seeded() {
        let cfg = PressureConfig::default();
        let a = run(&mut PressureSensor::new(cfg.clone(), 8), 2.0, 5);
        assert!(a.iter().all(|r| (r.pressure_pa / 10.0).fract() == 0.0));
        assert_eq!(a, run(&mut PressureSensor::new(cfg.clone(), 8), 2.0, 5));
        assert_ne!(a, run(&mut PressureSensor::new(cfg.clone(), 9), 2.0, 5));
        let exact = PressureConfig {
            noise_pa: 0.0,
            quantum_pa: 0.0,
            ..cfg
        };
        let r = run(&mut PressureSensor::new(exact, 8), 2.0, 1);
        assert_eq!(r[0].pressure_pa, 101_325.0 + 997.0 * 9.81 * 2.0);
    }
}
