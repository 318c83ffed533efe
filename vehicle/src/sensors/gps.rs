//! A GPS receiver read through gpsd (NMEA GGA/RMC semantics, `cougars-vehicle.md` §3.3),
//! on a mast that is out of the water only while the vehicle is at the surface.
//!
//! Model:
//! - the receiver reports at `gps_rate` (5 Hz) whether or not it has a fix, as an NMEA
//!   receiver writes a GGA every epoch (quality 0 without a fix);
//! - the antenna is dry while the depth is under `gps_max_depth` (0.2 m); the receiver then
//!   needs `gps_acquire_time` (2 s, a hot start: the almanac and time are kept through a dive)
//!   before its first fix; any submersion loses the fix at once;
//! - with a fix, each epoch is lost with probability `gps_loss_prob` (0.01: waves over the
//!   antenna, multipath);
//! - at each acquisition the receiver draws its satellites in view (6 to 11) and
//!   `HDOP = 7.2 / satellites` (1.2 to 0.65), held until the fix is lost; the position error
//!   is white, σ = `gps_noise` × HDOP per horizontal axis (`gps_noise` 1.5 m, a consumer
//!   receiver's UERE); the Gen-1 `gps_odom` rejects fixes under 5 satellites, which these
//!   never are;
//! - without a fix the report has no position, 0 satellites underwater (3 at most in a
//!   dropout) and HDOP 99.99 (the "unknown" value receivers print).
//!
//! Latitude and longitude come from the local position through the mission's
//! [`LocalGrid`] (given with [`Gps::with_grid`]).

use super::{Noise, Schedule, Truth};
use crate::geodesy::LocalGrid;

/// The HDOP of a report without a fix.
pub const NO_FIX_HDOP: f64 = 99.99;

/// GPS settings.
#[derive(Debug, Clone, PartialEq)]
pub struct GpsConfig {
    /// `enable_gps` (true).
    pub enabled: bool,
    /// `gps_rate`, Hz (5).
    pub rate_hz: f64,
    /// `gps_noise`, m per axis at HDOP 1 (1.5).
    pub noise_m: f64,
    /// `gps_max_depth`, m: the antenna is dry above it (0.2).
    pub max_depth_m: f64,
    /// `gps_acquire_time`, s from surfacing to the first fix (2).
    pub acquire_time_s: f64,
    /// `gps_loss_prob`: chance that an epoch with a fix loses it (0.01).
    pub loss_prob: f64,
}

impl Default for GpsConfig {
    fn default() -> Self {
        GpsConfig {
            enabled: true,
            rate_hz: 5.0,
            noise_m: 1.5,
            max_depth_m: 0.2,
            acquire_time_s: 2.0,
            loss_prob: 0.01,
        }
    }
}

/// One GPS epoch.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct GpsReport {
    /// MOOS time, s.
    pub time: f64,
    /// A fix (GGA quality 1).
    pub fix: bool,
    /// Satellites used.
    pub satellites: u32,
    /// Horizontal dilution of precision ([`NO_FIX_HDOP`] without a fix).
    pub hdop: f64,
    /// Local position (east, north), m, with a fix.
    pub xy: Option<(f64, f64)>,
    /// Latitude and longitude, degrees, with a fix and a grid.
    pub lat_lon: Option<(f64, f64)>,
}

/// The GPS model.
#[derive(Debug, Clone)]
pub struct Gps {
    cfg: GpsConfig,
    noise: Noise,
    schedule: Schedule,
    grid: Option<LocalGrid>,
    /// When the antenna last came out of the water.
    dry_since: Option<f64>,
    /// The satellites of the current fix.
    satellites: Option<u32>,
}

impl Gps {
    /// A GPS drawing from `seed`, reporting local x/y only.
    pub fn new(cfg: GpsConfig, seed: u64) -> Self {
        Gps {
            cfg,
            noise: Noise::new(seed, 4),
            schedule: Schedule::default(),
            grid: None,
            dry_since: None,
            satellites: None,
        }
    }

    /// The same GPS also reporting latitude and longitude on `grid`.
    pub fn with_grid(mut self, grid: Option<LocalGrid>) -> Self {
        self.grid = grid;
        self
    }

    /// The settings.
    pub fn config(&self) -> &GpsConfig {
        &self.cfg
    }

    /// The report due at `truth.time`, if any.
    pub fn sample(&mut self, truth: &Truth) -> Option<GpsReport> {
        if !self.cfg.enabled {
            return None;
        }
        let t = truth.time;
        // The antenna's state is followed at every call, not only at epochs.
        if truth.depth < self.cfg.max_depth_m {
            self.dry_since.get_or_insert(t);
        } else {
            self.dry_since = None;
            self.satellites = None;
        }
        if !self.schedule.due(t) {
            return None;
        }
        self.schedule.done(t, 1.0 / self.cfg.rate_hz);
        let no_fix = |satellites| GpsReport {
            time: t,
            fix: false,
            satellites,
            hdop: NO_FIX_HDOP,
            xy: None,
            lat_lon: None,
        };
        let Some(since) = self.dry_since else {
            return Some(no_fix(0));
        };
        if t - since + 1e-9 < self.cfg.acquire_time_s {
            return Some(no_fix(0));
        }
        if self.satellites.is_some() && self.noise.uniform() < self.cfg.loss_prob {
            self.satellites = None;
            let seen = self.noise.int(0, 3);
            return Some(no_fix(seen));
        }
        let sats = match self.satellites {
            Some(s) => s,
            None => {
                let s = self.noise.int(6, 11);
                self.satellites = Some(s);
                s
            }
        };
        let hdop = (7.2 / f64::from(sats) * 100.0).round() / 100.0;
        let sigma = self.cfg.noise_m * hdop;
        let x = truth.x + self.noise.gauss(sigma);
        let y = truth.y + self.noise.gauss(sigma);
        let lat_lon = self.grid.as_ref().and_then(|g| g.to_latlon(x, y).ok());
        Some(GpsReport {
            time: t,
            fix: true,
            satellites: sats,
            hdop,
            xy: Some((x, y)),
            lat_lon,
        })
    }
}

#[cfg(test)]
mod tests {
    use super::super::mean_std;
    use super::*;

    fn at(time: f64, depth: f64) -> Truth {
        Truth {
            time,
            x: 100.0,
            y: -50.0,
            depth,
            ..Truth::default()
        }
    }

    #[test]
    fn fixes_only_with_the_antenna_out_of_the_water() {
        let mut gps = Gps::new(GpsConfig::default(), 3);
        // 30 s under, 30 s at the surface, 30 s under, sampled at 20 Hz.
        let mut reps = Vec::new();
        for k in 0..1800 {
            let t = f64::from(k) / 20.0;
            let depth = if (30.0..60.0).contains(&t) { 0.05 } else { 2.0 };
            if let Some(r) = gps.sample(&at(t, depth)) {
                reps.push((depth, r));
            }
        }
        assert_eq!(reps.len(), 450, "5 Hz whether or not there is a fix");
        assert!(
            reps.iter().filter(|(d, _)| *d > 1.0).all(|(_, r)| !r.fix
                && r.xy.is_none()
                && r.satellites == 0
                && r.hdop == NO_FIX_HDOP)
        );
        let fixes: Vec<&GpsReport> = reps.iter().filter(|(_, r)| r.fix).map(|(_, r)| r).collect();
        // No fix before the acquisition time: the first at 32 s.
        assert_eq!(fixes[0].time, 32.0);
        assert!(fixes.iter().all(|r| r.time < 60.0));
        // 28 s of fixes at 5 Hz, less about 1 % lost epochs and their reacquisitions.
        assert!((120..=141).contains(&fixes.len()), "{}", fixes.len());
        assert!(fixes.iter().all(|r| r.satellites >= 6 && r.hdop <= 1.2));
    }

    #[test]
    fn position_noise_scales_with_hdop() {
        let cfg = GpsConfig {
            noise_m: 2.0,
            loss_prob: 0.02,
            ..GpsConfig::default()
        };
        let mut gps = Gps::new(cfg, 17);
        let mut ex = Vec::new();
        let mut ey = Vec::new();
        let mut losses = 0;
        let mut prev_fix = false;
        for k in 0..100_000 {
            let r = gps.sample(&at(f64::from(k) / 5.0, 0.0)).unwrap();
            if let Some((x, y)) = r.xy {
                // Normalised by the HDOP of the fix.
                ex.push((x - 100.0) / r.hdop);
                ey.push((y + 50.0) / r.hdop);
            } else if prev_fix {
                losses += 1;
            }
            prev_fix = r.fix;
        }
        for e in [ex, ey] {
            let (m, s) = mean_std(&e);
            assert!(m.abs() < 0.03, "{m}");
            assert!((s - 2.0).abs() < 0.03, "{s}");
        }
        // 2 % of the epochs with a fix lose it.
        let rate = f64::from(losses) / 100_000.0;
        assert!((rate - 0.02).abs() < 0.003, "{rate}");
    }

    #[test]
    fn latitude_and_longitude_on_the_grid_and_seeded() {
        let grid = LocalGrid::new(40.0717976, -111.6002054).unwrap();
        let run = |seed| {
            let mut g = Gps::new(GpsConfig::default(), seed).with_grid(Some(grid.clone()));
            (0..200)
                .filter_map(|k| g.sample(&at(f64::from(k) / 5.0, 0.0)))
                .collect::<Vec<_>>()
        };
        let a = run(5);
        assert_eq!(a, run(5));
        assert_ne!(a, run(6));
        let r = a.iter().find(|r| r.fix).unwrap();
        let (x, y) = r.xy.unwrap();
        let (lat, lon) = r.lat_lon.unwrap();
        let (lat0, lon0) = grid.to_latlon(x, y).unwrap();
        assert_eq!((lat, lon), (lat0, lon0));
        // About 100 m east, 50 m south of the origin.
        assert!(lat < 40.0717976 && lon > -111.6002054);
    }
}
