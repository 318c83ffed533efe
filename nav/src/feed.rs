//! From sensor variables to the navigator and back: the one adapter that the live app
//! (`pNavGraph`) and the log replay (`coug nav`) share, so the navigator cannot tell simulation
//! from hardware from a log.
//!
//! It takes `(name, value, time)` triples with the names and units of the table in
//! `runtime::sensors` (the variables the real drivers post) and assembles them into reports,
//! each closed by its last variable (✱):
//!
//! | variables | closed by | becomes |
//! |---|---|---|
//! | `DVL_VEL_X/Y/Z` (m/s, body FRD), `DVL_FOM` (m/s), `DVL_ALTITUDE`, `DVL_WATER_TRACK` (1: through the water) | `DVL_VALID` ✱ (1/0) | [`DvlVelocity`] ([`VelocityReference::Water`] when `DVL_WATER_TRACK` = 1 came with it, else bottom lock: [`VelocityReference::Ground`]) |
//! | `AHRS_PITCH`, `AHRS_ROLL` (deg), `AHRS_ROLL/PITCH/YAW_RATE` (deg/s) | `AHRS_HEADING` ✱ (compass deg) | [`Attitude`] (radians, the compass heading is the NED yaw) and [`GyroRates`] |
//! | — | `PRESSURE` ✱ (Pa, absolute) | [`Depth`]: `(P - P_atm) / (rho g)`, `rho = 997 + 0.8 salinity` |
//! | `GPS_X`, `GPS_Y` (local grid m), `GPS_SATELLITES`, `GPS_HDOP` | `GPS_FIX` ✱ (1/0) | [`GpsFix`] when the fix is 1 and x, y came with it |
//!
//! A report's variables are taken when they arrive before its closing one (a value left from an
//! earlier report is not reused for x/y: a GPS fix needs `GPS_X`/`GPS_Y` since the last
//! `GPS_FIX`). Every report also goes to a [`DeadReckoner`] (the baseline). After each
//! keyframe, [`Feed::poll`] yields a [`Snapshot`]: the estimate, the status, the
//! dead-reckoning position and a dive report at a resurfacing.

use crate::NavConfig;
use crate::dead_reckoning::DeadReckoner;
use crate::dive::DiveReport;
use crate::measurements::{Attitude, Depth, DvlVelocity, GpsFix, GyroRates, VelocityReference};
use crate::window::{Estimate, Navigator, Status};

/// Gravity of the pressure-to-depth law, m/s² (as `vehicle::sensors::pressure`).
pub const G: f64 = 9.81;

/// Water density from salinity (ppt), kg/m³: the law of `vehicle::sensors::pressure` (the
/// Gen-1 depth converter's).
pub fn water_density(salinity_ppt: f64) -> f64 {
    997.0 + 0.8 * salinity_ppt
}

/// The variables a [`Feed`] reads, in the table's order.
pub const INPUTS: [&str; 19] = [
    "DVL_VEL_X",
    "DVL_VEL_Y",
    "DVL_VEL_Z",
    "DVL_ALTITUDE",
    "DVL_FOM",
    "DVL_WATER_TRACK",
    "DVL_VALID",
    "AHRS_PITCH",
    "AHRS_ROLL",
    "AHRS_ROLL_RATE",
    "AHRS_PITCH_RATE",
    "AHRS_YAW_RATE",
    "AHRS_HEADING",
    "PRESSURE",
    "GPS_X",
    "GPS_Y",
    "GPS_SATELLITES",
    "GPS_HDOP",
    "GPS_FIX",
];

/// Settings of a [`Feed`].
#[derive(Debug, Clone, PartialEq)]
pub struct FeedConfig {
    /// The navigator's settings.
    pub nav: NavConfig,
    /// Atmospheric pressure, Pa (101325; what the depth sensor reads at the surface).
    pub atmospheric_pa: f64,
    /// Salinity, ppt (0: fresh water), for the water density.
    pub salinity_ppt: f64,
    /// Water density, kg/m³, when set overrides the one from the salinity.
    pub density_kg_m3: Option<f64>,
}

impl Default for FeedConfig {
    fn default() -> Self {
        FeedConfig {
            nav: NavConfig::default(),
            atmospheric_pa: 101_325.0,
            salinity_ppt: 0.0,
            density_kg_m3: None,
        }
    }
}

impl FeedConfig {
    /// The water density in force, kg/m³.
    pub fn density(&self) -> f64 {
        self.density_kg_m3
            .unwrap_or_else(|| water_density(self.salinity_ppt))
    }

    /// The depth (m, positive down) of an absolute pressure (Pa).
    pub fn depth_of(&self, pressure_pa: f64) -> f64 {
        (pressure_pa - self.atmospheric_pa) / (self.density() * G)
    }
}

/// What the feed says after a keyframe.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Snapshot {
    /// The estimate at the newest keyframe.
    pub estimate: Estimate,
    /// The navigator's status.
    pub status: Status,
    /// The dead-reckoning position (east, north, depth; m) at the estimate's time, once the
    /// baseline has its first fix.
    pub dead_reckoning: Option<[f64; 3]>,
    /// The dive report, at the first good fix after a resurfacing.
    pub dive: Option<DiveReport>,
}

impl Snapshot {
    /// The dive report as one MOOS string:
    /// `dive=N,dist=D,correction=C,ratio_pct=R,start=T0,surface=T1,fix=T2` (metres, percent,
    /// seconds; two decimals).
    pub fn dive_report_text(r: &DiveReport) -> String {
        format!(
            "dive={},dist={:.2},correction={:.2},ratio_pct={:.2},start={:.2},surface={:.2},fix={:.2}",
            r.dive,
            r.distance_m,
            r.correction_m,
            r.ratio_pct,
            r.start_t_s,
            r.surface_t_s,
            r.fix_t_s
        )
    }
}

#[derive(Debug, Clone, Copy, Default)]
struct Dvl {
    vel: [Option<f64>; 3],
    fom: Option<f64>,
    water: bool,
}

#[derive(Debug, Clone, Copy, Default)]
struct Ahrs {
    pitch_deg: Option<f64>,
    roll_deg: Option<f64>,
    rates_deg_s: [Option<f64>; 3],
}

#[derive(Debug, Clone, Copy, Default)]
struct Gps {
    x: Option<f64>,
    y: Option<f64>,
    sats: Option<f64>,
    hdop: Option<f64>,
}

/// Counts of the reports assembled.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq)]
pub struct FeedCounts {
    /// DVL reports (valid or not).
    pub dvl: u64,
    /// AHRS reports.
    pub ahrs: u64,
    /// Pressures.
    pub pressure: u64,
    /// GPS epochs with a fix.
    pub gps_fixes: u64,
}

/// The sensor-variable adapter around a [`Navigator`] and a [`DeadReckoner`].
#[derive(Debug, Clone)]
pub struct Feed {
    cfg: FeedConfig,
    nav: Navigator,
    dr: DeadReckoner,
    dvl: Dvl,
    ahrs: Ahrs,
    gps: Gps,
    counts: FeedCounts,
    polled_keyframes: u64,
}

impl Feed {
    /// A feed with its settings.
    pub fn new(cfg: FeedConfig) -> Feed {
        Feed {
            nav: Navigator::new(cfg.nav.clone()),
            dr: DeadReckoner::new(),
            cfg,
            dvl: Dvl::default(),
            ahrs: Ahrs::default(),
            gps: Gps::default(),
            counts: FeedCounts::default(),
            polled_keyframes: 0,
        }
    }

    /// The settings.
    pub fn config(&self) -> &FeedConfig {
        &self.cfg
    }

    /// The navigator.
    pub fn navigator(&self) -> &Navigator {
        &self.nav
    }

    /// The dead-reckoning baseline.
    pub fn dead_reckoner(&self) -> &DeadReckoner {
        &self.dr
    }

    /// The reports assembled so far.
    pub fn counts(&self) -> FeedCounts {
        self.counts
    }

    /// Takes one variable (`name`, a double `value`, its posting time `t_s`); returns false
    /// when the name is not one of [`INPUTS`]. A closing variable hands its report to the
    /// navigator and the baseline (a rejected measurement is counted by the navigator).
    pub fn take(&mut self, name: &str, value: f64, t_s: f64) -> bool {
        match name {
            "DVL_VEL_X" => self.dvl.vel[0] = Some(value),
            "DVL_VEL_Y" => self.dvl.vel[1] = Some(value),
            "DVL_VEL_Z" => self.dvl.vel[2] = Some(value),
            "DVL_FOM" => self.dvl.fom = Some(value),
            "DVL_ALTITUDE" => {}
            "DVL_WATER_TRACK" => self.dvl.water = value == 1.0,
            "DVL_VALID" => self.close_dvl(value, t_s),
            "AHRS_PITCH" => self.ahrs.pitch_deg = Some(value),
            "AHRS_ROLL" => self.ahrs.roll_deg = Some(value),
            "AHRS_ROLL_RATE" => self.ahrs.rates_deg_s[0] = Some(value),
            "AHRS_PITCH_RATE" => self.ahrs.rates_deg_s[1] = Some(value),
            "AHRS_YAW_RATE" => self.ahrs.rates_deg_s[2] = Some(value),
            "AHRS_HEADING" => self.close_ahrs(value, t_s),
            "PRESSURE" => {
                self.counts.pressure += 1;
                let m = Depth {
                    t_s,
                    depth_m: self.cfg.depth_of(value),
                };
                let _ = self.nav.depth(&m);
                self.dr.depth(&m);
            }
            "GPS_X" => self.gps.x = Some(value),
            "GPS_Y" => self.gps.y = Some(value),
            "GPS_SATELLITES" => self.gps.sats = Some(value),
            "GPS_HDOP" => self.gps.hdop = Some(value),
            "GPS_FIX" => self.close_gps(value, t_s),
            _ => return false,
        }
        true
    }

    fn close_dvl(&mut self, valid: f64, t_s: f64) {
        self.counts.dvl += 1;
        let d = std::mem::take(&mut self.dvl);
        let valid = valid == 1.0;
        let vel = match d.vel {
            [Some(x), Some(y), Some(z)] => [x, y, z],
            _ if valid => [f64::NAN; 3],
            _ => [0.0; 3],
        };
        let m = DvlVelocity {
            t_s,
            vel_body_mps: vel,
            valid,
            fom_mps: d.fom.unwrap_or(0.0),
            reference: if d.water {
                VelocityReference::Water
            } else {
                VelocityReference::Ground
            },
        };
        let _ = self.nav.dvl(&m);
        self.dr.dvl(&m);
    }

    fn close_ahrs(&mut self, heading_deg: f64, t_s: f64) {
        self.counts.ahrs += 1;
        let a = std::mem::take(&mut self.ahrs);
        let att = Attitude {
            t_s,
            yaw_rad: heading_deg.rem_euclid(360.0).to_radians(),
            pitch_rad: a.pitch_deg.unwrap_or(0.0).to_radians(),
            roll_rad: a.roll_deg.unwrap_or(0.0).to_radians(),
        };
        let _ = self.nav.attitude(&att);
        self.dr.attitude(&att);
        if let [Some(p), Some(q), Some(r)] = a.rates_deg_s {
            let _ = self.nav.gyro(&GyroRates {
                t_s,
                rates_body_radps: [p.to_radians(), q.to_radians(), r.to_radians()],
            });
        }
    }

    fn close_gps(&mut self, fix: f64, t_s: f64) {
        let g = std::mem::take(&mut self.gps);
        let (true, Some(x), Some(y)) = (fix == 1.0, g.x, g.y) else {
            return;
        };
        self.counts.gps_fixes += 1;
        let sats = g.sats.unwrap_or(0.0);
        let m = GpsFix {
            t_s,
            x_m: x,
            y_m: y,
            hdop: g.hdop.unwrap_or(1.0),
            sats: if sats.is_finite() && sats > 0.0 {
                sats.min(f64::from(u32::MAX)) as u32
            } else {
                0
            },
        };
        let _ = self.nav.gps(&m);
        self.dr.gps(&m);
    }

    /// Advances the navigator's time (its dead-reckoning timer), as the app does each
    /// iteration and the replay at each record.
    pub fn advance(&mut self, t_s: f64) {
        self.nav.advance(t_s);
    }

    /// The snapshot after a new keyframe (`None` when none was made since the last call, or
    /// before the navigator is initialised).
    pub fn poll(&mut self) -> Option<Snapshot> {
        let k = self.nav.keyframes();
        if k == self.polled_keyframes {
            return None;
        }
        self.polled_keyframes = k;
        let estimate = self.nav.estimate()?;
        Some(Snapshot {
            estimate,
            status: self.nav.status(),
            dead_reckoning: self.dr.position_at(estimate.t_s),
            dive: self.nav.take_dive_report(),
        })
    }

    /// The navigator's status now.
    pub fn status(&self) -> Status {
        self.nav.status()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn ahrs(f: &mut Feed, t: f64, heading: f64) {
        for (k, v) in [
            ("AHRS_PITCH", 0.0),
            ("AHRS_ROLL", 0.0),
            ("AHRS_ROLL_RATE", 0.0),
            ("AHRS_PITCH_RATE", 0.0),
            ("AHRS_YAW_RATE", 0.0),
            ("AHRS_HEADING", heading),
        ] {
            assert!(f.take(k, v, t));
        }
    }

    fn dvl(f: &mut Feed, t: f64, fwd: f64) {
        for (k, v) in [
            ("DVL_VEL_X", fwd),
            ("DVL_VEL_Y", 0.0),
            ("DVL_VEL_Z", 0.0),
            ("DVL_ALTITUDE", 20.0),
            ("DVL_FOM", 0.01),
            ("DVL_VALID", 1.0),
        ] {
            assert!(f.take(k, v, t));
        }
    }

    fn gps(f: &mut Feed, t: f64, x: f64, y: f64) {
        for (k, v) in [
            ("GPS_X", x),
            ("GPS_Y", y),
            ("GPS_SATELLITES", 9.0),
            ("GPS_HDOP", 1.0),
            ("GPS_FIX", 1.0),
        ] {
            assert!(f.take(k, v, t));
        }
    }

    #[test]
    fn pressure_is_depth_by_the_sensor_law() {
        let c = FeedConfig {
            salinity_ppt: 35.0,
            ..FeedConfig::default()
        };
        let p = 101_325.0 + (997.0 + 0.8 * 35.0) * 9.81 * 4.0;
        assert!((c.depth_of(p) - 4.0).abs() < 1e-12);
        let c = FeedConfig {
            density_kg_m3: Some(1000.0),
            atmospheric_pa: 84_000.0,
            ..FeedConfig::default()
        };
        assert!((c.depth_of(84_000.0 + 9810.0) - 1.0).abs() < 1e-12);
    }

    #[test]
    fn reports_close_on_their_last_variable_and_nothing_before_a_fix() {
        let mut f = Feed::new(FeedConfig::default());
        assert!(!f.take("NAV_X", 1.0, 0.0));
        ahrs(&mut f, 0.1, 90.0);
        dvl(&mut f, 0.1, 1.0);
        assert!(f.take("PRESSURE", 101_325.0, 0.1));
        assert!(f.poll().is_none(), "no fix: not initialised");
        assert!(matches!(f.status(), Status::Initialising(_)));
        // A fix without its x/y is no fix.
        assert!(f.take("GPS_FIX", 1.0, 0.15));
        assert_eq!(f.counts().gps_fixes, 0);
        gps(&mut f, 0.2, 10.0, 20.0);
        assert_eq!(f.counts().gps_fixes, 1);
        let s = f.poll().expect("initialised at the fix");
        assert!((s.estimate.x_m - 10.0).abs() < 1e-6 && (s.estimate.y_m - 20.0).abs() < 1e-6);
        assert!(f.poll().is_none(), "one snapshot per keyframe");
        assert_eq!(
            (f.counts().ahrs, f.counts().dvl, f.counts().pressure),
            (1, 1, 1)
        );
    }

    #[test]
    fn heading_east_moves_east_and_dead_reckoning_follows() {
        let mut f = Feed::new(FeedConfig::default());
        ahrs(&mut f, 0.0, 90.0);
        gps(&mut f, 0.0, 0.0, 0.0);
        let mut last = None;
        for i in 1..=100 {
            let t = f64::from(i) * 0.1;
            ahrs(&mut f, t, 90.0);
            dvl(&mut f, t, 1.0);
            f.take("PRESSURE", 101_325.0 + 997.0 * 9.81 * 3.0, t);
            f.advance(t);
            if let Some(s) = f.poll() {
                last = Some(s);
            }
        }
        let s = last.unwrap();
        assert!((s.estimate.x_m - 10.0).abs() < 0.3, "{:?}", s.estimate);
        assert!(s.estimate.y_m.abs() < 0.3);
        assert!((s.estimate.heading_rad.to_degrees() - 90.0).abs() < 1.0);
        assert!((s.estimate.depth_m - 3.0).abs() < 0.1);
        let dr = s.dead_reckoning.unwrap();
        assert!((dr[0] - 10.0).abs() < 0.2 && dr[1].abs() < 0.1, "{dr:?}");
        assert_eq!(s.status, Status::Ok);
    }

    #[test]
    fn dive_report_text_is_stable() {
        let r = DiveReport {
            dive: 2,
            start_t_s: 10.0,
            surface_t_s: 300.5,
            fix_t_s: 303.25,
            distance_m: 412.345,
            correction_m: 2.5,
            ratio_pct: 0.606,
        };
        assert_eq!(
            Snapshot::dive_report_text(&r),
            "dive=2,dist=412.35,correction=2.50,ratio_pct=0.61,start=10.00,surface=300.50,fix=303.25"
        );
    }

    /// Stopped at the surface, drifting east at 0.1 m/s: with water-track reports the
    /// fixes show the current; with bottom lock the DVL already sees the drift (no current).
    fn drift(water: bool) -> (f64, f64) {
        let mut f = Feed::new(FeedConfig::default());
        let mut current = (0.0, 0.0);
        for i in 0..=600 {
            let t = f64::from(i) * 0.1;
            ahrs(&mut f, t, 0.0);
            let over_ground_east = if water { 0.0 } else { 0.1 };
            for (k, v) in [
                ("DVL_VEL_X", 0.0),
                // Heading north: starboard is east.
                ("DVL_VEL_Y", over_ground_east),
                ("DVL_VEL_Z", 0.0),
                ("DVL_FOM", 0.01),
            ] {
                f.take(k, v, t);
            }
            if water {
                assert!(f.take("DVL_WATER_TRACK", 1.0, t));
            }
            f.take("DVL_VALID", 1.0, t);
            if i % 2 == 0 {
                gps(&mut f, t, 0.1 * t, 0.0);
            }
            f.advance(t);
            if let Some(s) = f.poll() {
                current = (s.estimate.current_east_mps, s.estimate.current_north_mps);
            }
        }
        current
    }

    #[test]
    fn water_track_reports_make_the_current_observable() {
        let (cx, cy) = drift(true);
        assert!((cx - 0.1).abs() < 0.01 && cy.abs() < 0.01, "{cx} {cy}");
        let (cx, cy) = drift(false);
        assert!(cx.abs() < 0.01 && cy.abs() < 0.01, "{cx} {cy}");
    }
}
