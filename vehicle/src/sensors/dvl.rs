//! The Water Linked DVL A50: bottom-track velocity over ground in its FRD body frame.
//!
//! What the A50 does and how it is modelled (`cougars-vehicle.md` §3.2; the A50 datasheet):
//!
//! - **Range.** Bottom lock from 0.05 m to 50 m altitude (the datasheet's range; the
//!   HoloOcean bridge also uses 50 m). Altitude is the water depth (a flat bottom,
//!   `water_depth`) minus the vehicle depth. Outside the range the report is invalid
//!   (`velocity_valid = false`): no velocity, altitude -1 and figure of merit
//!   [`INVALID_FOM`], as the A50's JSON reports carry.
//! - **Rate.** The A50 pings faster as the bottom gets closer, between 2 and 15 Hz (its
//!   datasheet gives the span, not the law). The law here is linear in altitude:
//!   `rate = max_rate - (max_rate - min_rate) * (h - min_alt) / (max_alt - min_alt)`,
//!   15 Hz at 0.05 m down to 2 Hz at 50 m; without lock it searches at the lowest rate.
//! - **Errors.** Velocity = `(1 + scale_error) * v_body + white noise` (per axis, σ
//!   `dvl_noise`, 0.02 m/s by default as the HoloOcean bridge and the Gen-2 FGO use; scale
//!   0.5 % by default, inside the A50's ±1.01 % long-term accuracy). The figure of merit is
//!   the A50's estimate of its velocity error, m/s: here the noise σ. The altitude gets
//!   white noise `dvl_altitude_noise` (0.05 m).
//! - **Water track** (`dvl_water_track`, off by default). The A50 itself only bottom-tracks;
//!   larger DVLs measure the velocity through the water when the bottom is out of range. With
//!   the option on, a report out of bottom-lock range is valid and carries the velocity
//!   through the water (the truth's speed through the water along its heading, plus its
//!   vertical velocity, in the body frame) with the same scale error and noise, altitude -1,
//!   and `water_track` set; it pings at the rate of mid-range altitude. A navigator must then
//!   add the water current to get the velocity over ground.

use super::{Noise, Schedule, Truth};

/// The figure of merit of an invalid report, m/s.
pub const INVALID_FOM: f64 = 10.0;

/// DVL settings.
#[derive(Debug, Clone, PartialEq)]
pub struct DvlConfig {
    /// `enable_dvl` (true).
    pub enabled: bool,
    /// `dvl_noise`, m/s per axis (0.02).
    pub noise_mps: f64,
    /// `dvl_scale_error`, a fraction (0.005 = +0.5 %).
    pub scale_error: f64,
    /// `dvl_min_altitude`, m (0.05).
    pub min_altitude_m: f64,
    /// `dvl_max_altitude`, m (50).
    pub max_altitude_m: f64,
    /// `dvl_min_rate`, Hz, at the maximum altitude and while searching (2).
    pub min_rate_hz: f64,
    /// `dvl_max_rate`, Hz, at the minimum altitude (15).
    pub max_rate_hz: f64,
    /// `dvl_altitude_noise`, m (0.05).
    pub altitude_noise_m: f64,
    /// `dvl_water_track`: velocity through the water when the bottom is out of range (false).
    pub water_track: bool,
}

impl Default for DvlConfig {
    fn default() -> Self {
        DvlConfig {
            enabled: true,
            noise_mps: 0.02,
            scale_error: 0.005,
            min_altitude_m: 0.05,
            max_altitude_m: 50.0,
            min_rate_hz: 2.0,
            max_rate_hz: 15.0,
            altitude_noise_m: 0.05,
            water_track: false,
        }
    }
}

impl DvlConfig {
    /// The ping rate at altitude `h` (m), Hz: the linear law of the module docs; the lowest
    /// rate outside the range.
    pub fn rate_at(&self, h: f64) -> f64 {
        if !self.in_range(h) {
            return self.min_rate_hz;
        }
        let span = self.max_altitude_m - self.min_altitude_m;
        let f = if span > 0.0 {
            ((h - self.min_altitude_m) / span).clamp(0.0, 1.0)
        } else {
            0.0
        };
        self.max_rate_hz - (self.max_rate_hz - self.min_rate_hz) * f
    }

    /// True when the A50 holds bottom lock at altitude `h` (m).
    pub fn in_range(&self, h: f64) -> bool {
        h >= self.min_altitude_m && h <= self.max_altitude_m
    }
}

/// One A50 velocity report.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct DvlReport {
    /// MOOS time of validity, s.
    pub time: f64,
    /// `velocity_valid`: bottom lock, or water track.
    pub valid: bool,
    /// True when the velocity is through the water (water track), not over ground.
    pub water_track: bool,
    /// Velocity over ground (through the water in water track), forward, starboard, down
    /// (FRD), m/s; zeros when invalid.
    pub velocity_mps: [f64; 3],
    /// Figure of merit, m/s ([`INVALID_FOM`] when invalid).
    pub fom: f64,
    /// Altitude above the bottom, m; -1 when invalid.
    pub altitude_m: f64,
}

/// The A50 model.
#[derive(Debug, Clone)]
pub struct Dvl {
    cfg: DvlConfig,
    water_depth: f64,
    noise: Noise,
    schedule: Schedule,
}

impl Dvl {
    /// An A50 over a flat bottom at `water_depth` metres, drawing from `seed`.
    pub fn new(cfg: DvlConfig, water_depth: f64, seed: u64) -> Self {
        Dvl {
            cfg,
            water_depth,
            noise: Noise::new(seed, 1),
            schedule: Schedule::default(),
        }
    }

    /// The settings.
    pub fn config(&self) -> &DvlConfig {
        &self.cfg
    }

    /// The report due at `truth.time`, if any.
    pub fn sample(&mut self, truth: &Truth) -> Option<DvlReport> {
        if !self.cfg.enabled || !self.schedule.due(truth.time) {
            return None;
        }
        let h = self.water_depth - truth.depth;
        let water = !self.cfg.in_range(h) && self.cfg.water_track;
        let rate = if water {
            self.cfg
                .rate_at(0.5 * (self.cfg.min_altitude_m + self.cfg.max_altitude_m))
        } else {
            self.cfg.rate_at(h)
        };
        self.schedule.done(truth.time, 1.0 / rate);
        if !self.cfg.in_range(h) && !water {
            return Some(DvlReport {
                time: truth.time,
                valid: false,
                water_track: false,
                velocity_mps: [0.0; 3],
                fom: INVALID_FOM,
                altitude_m: -1.0,
            });
        }
        let k = 1.0 + self.cfg.scale_error;
        let v = if water {
            let (s, c) = truth.heading_deg.to_radians().sin_cos();
            Truth {
                vel_east_mps: truth.speed_mps * s,
                vel_north_mps: truth.speed_mps * c,
                ..*truth
            }
            .body_velocity()
        } else {
            truth.body_velocity()
        };
        let sigma = self.cfg.noise_mps;
        let velocity_mps = [
            k * v[0] + self.noise.gauss(sigma),
            k * v[1] + self.noise.gauss(sigma),
            k * v[2] + self.noise.gauss(sigma),
        ];
        let altitude_m = if water {
            -1.0
        } else {
            (h + self.noise.gauss(self.cfg.altitude_noise_m)).max(0.0)
        };
        Some(DvlReport {
            time: truth.time,
            valid: true,
            water_track: water,
            velocity_mps,
            fom: sigma,
            altitude_m,
        })
    }
}

#[cfg(test)]
mod tests {
    use super::super::mean_std;
    use super::*;

    fn cruising(depth: f64, time: f64) -> Truth {
        Truth {
            time,
            depth,
            heading_deg: 30.0,
            speed_mps: 1.5,
            vel_east_mps: 1.5 * 30f64.to_radians().sin(),
            vel_north_mps: 1.5 * 30f64.to_radians().cos(),
            ..Truth::default()
        }
    }

    /// Reports of a run at 100 Hz sampling for `secs`.
    fn run(dvl: &mut Dvl, depth: f64, secs: u32) -> Vec<DvlReport> {
        (0..secs * 100)
            .filter_map(|k| dvl.sample(&cruising(depth, f64::from(k) / 100.0)))
            .collect()
    }

    #[test]
    fn noise_and_scale_error_have_the_configured_statistics() {
        let cfg = DvlConfig {
            scale_error: 0.02,
            noise_mps: 0.03,
            ..DvlConfig::default()
        };
        let mut dvl = Dvl::new(cfg, 20.0, 11);
        let reps = run(&mut dvl, 5.0, 2000);
        assert!(reps.len() > 10_000, "{}", reps.len());
        assert!(reps.iter().all(|r| r.valid && r.fom == 0.03));
        let fwd: Vec<f64> = reps.iter().map(|r| r.velocity_mps[0]).collect();
        let stb: Vec<f64> = reps.iter().map(|r| r.velocity_mps[1]).collect();
        let down: Vec<f64> = reps.iter().map(|r| r.velocity_mps[2]).collect();
        let (m, s) = mean_std(&fwd);
        // 1.5 m/s forward, 2 % too fast.
        assert!((m - 1.53).abs() < 0.002, "{m}");
        assert!((s - 0.03).abs() < 0.002, "{s}");
        for v in [stb, down] {
            let (m, s) = mean_std(&v);
            assert!(m.abs() < 0.002, "{m}");
            assert!((s - 0.03).abs() < 0.002, "{s}");
        }
        let alt: Vec<f64> = reps.iter().map(|r| r.altitude_m).collect();
        let (m, s) = mean_std(&alt);
        assert!(
            (m - 15.0).abs() < 0.005 && (s - 0.05).abs() < 0.005,
            "{m} {s}"
        );
    }

    #[test]
    fn bottom_lock_only_within_the_a50_range() {
        let cfg = DvlConfig::default();
        // Water 60 m deep: at 5 m depth the bottom is 55 m away, out of range.
        let mut dvl = Dvl::new(cfg.clone(), 60.0, 1);
        let far = run(&mut dvl, 5.0, 10);
        assert!(!far.is_empty() && far.iter().all(|r| !r.valid));
        assert!(
            far.iter()
                .all(|r| r.altitude_m == -1.0 && r.fom == INVALID_FOM)
        );
        assert!(far.iter().all(|r| r.velocity_mps == [0.0; 3]));
        // At 12 m depth: 48 m, in range.
        let mut dvl = Dvl::new(cfg.clone(), 60.0, 1);
        assert!(run(&mut dvl, 12.0, 10).iter().all(|r| r.valid));
        // On the bottom (3 cm): too close.
        let mut dvl = Dvl::new(cfg, 10.0, 1);
        assert!(run(&mut dvl, 9.97, 10).iter().all(|r| !r.valid));
    }

    #[test]
    fn rate_rises_as_altitude_falls() {
        let cfg = DvlConfig::default();
        assert_eq!(cfg.rate_at(0.05), 15.0);
        assert_eq!(cfg.rate_at(50.0), 2.0);
        assert_eq!(cfg.rate_at(80.0), 2.0);
        assert!((cfg.rate_at(25.025) - 8.5).abs() < 1e-9);
        // Counted over 100 s of sampling at 100 Hz.
        let count = |water: f64| {
            let mut dvl = Dvl::new(cfg.clone(), water, 3);
            run(&mut dvl, 5.0, 100).len() as f64 / 100.0
        };
        let near = count(5.5); // 0.5 m altitude
        let mid = count(30.0); // 25 m
        let far = count(54.0); // 49 m
        assert!((near - cfg.rate_at(0.5)).abs() < 0.5, "{near}");
        assert!((mid - cfg.rate_at(25.0)).abs() < 0.5, "{mid}");
        assert!((far - cfg.rate_at(49.0)).abs() < 0.5, "{far}");
        assert!(near > mid && mid > far);
    }

    #[test]
    fn same_seed_same_reports() {
        let mut a = Dvl::new(DvlConfig::default(), 20.0, 42);
        let mut b = Dvl::new(DvlConfig::default(), 20.0, 42);
        let mut c = Dvl::new(DvlConfig::default(), 20.0, 43);
        let (ra, rb, rc) = (
            run(&mut a, 4.0, 20),
            run(&mut b, 4.0, 20),
            run(&mut c, 4.0, 20),
        );
        assert_eq!(ra, rb);
        assert_ne!(ra, rc);
    }

    #[test]
    fn water_track_out_of_range_measures_the_velocity_through_the_water() {
        let cfg = DvlConfig {
            water_track: true,
            noise_mps: 0.0,
            scale_error: 0.0,
            ..DvlConfig::default()
        };
        // Heading north at 1.5 m/s through the water, pushed east at 0.1 m/s.
        let truth = Truth {
            time: 1.0,
            depth: 5.0,
            heading_deg: 0.0,
            speed_mps: 1.5,
            vel_east_mps: 0.1,
            vel_north_mps: 1.5,
            ..Truth::default()
        };
        let mut deep = Dvl::new(cfg.clone(), 100.0, 1);
        let r = deep.sample(&truth).unwrap();
        assert!(r.valid && r.water_track && r.altitude_m == -1.0);
        assert!((r.velocity_mps[0] - 1.5).abs() < 1e-12 && r.velocity_mps[1].abs() < 1e-12);
        // Within range it bottom-tracks: over ground, the current is seen.
        let mut shallow = Dvl::new(cfg, 20.0, 1);
        let r = shallow.sample(&truth).unwrap();
        assert!(r.valid && !r.water_track);
        assert!((r.velocity_mps[1] - 0.1).abs() < 1e-12);
        // Without the option, out of range is invalid.
        let mut a50 = Dvl::new(DvlConfig::default(), 100.0, 1);
        assert!(!a50.sample(&truth).unwrap().valid);
    }
}
