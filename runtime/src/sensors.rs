//! `uSimSensors`: the simulated navigation sensors of a CoUGARs-like AUV as a MOOS app.
//!
//! It reads the simulator's truth, which uSimMarine(V22) posts under its `prefix` (`SIM` in
//! the project's missions, so that `NAV_*` is the navigator's alone), runs the seeded sensor
//! models of [`vehicle::sensors`] on it, and posts what the real drivers will post: the same
//! variables with the same units and frames, so a navigator cannot tell simulation from
//! hardware.
//!
//! # Variables
//!
//! Read (`<P>` is the `prefix` parameter): `<P>_X`, `<P>_Y`, `<P>_DEPTH`, `<P>_HEADING`,
//! `<P>_SPEED`, `<P>_PITCH` (posted by the simulator with depth control),
//! `<P>_HEADING_OVER_GROUND`, `<P>_SPEED_OVER_GROUND`. Nothing is posted before x, y, depth and
//! heading have arrived. The heading, pitch and depth rates are differentiated from
//! successive records; between records the truth is extrapolated at its velocity. The
//! simulator has no roll: roll is 0.
//!
//! Posted (every report's variables in one iteration, at its time; the last variable of a
//! report, marked ✱, closes it, so a reader can take a report when that variable arrives):
//!
//! | variable | type | unit | frame / meaning | rate |
//! |---|---|---|---|---|
//! | `DVL_VEL_X` | double | m/s | velocity over ground, body forward (A50 FRD) | each valid DVL report, 2–15 Hz (rises as the altitude falls) |
//! | `DVL_VEL_Y` | double | m/s | body starboard | as `DVL_VEL_X` |
//! | `DVL_VEL_Z` | double | m/s | body down | as `DVL_VEL_X` |
//! | `DVL_ALTITUDE` | double | m | above the bottom; -1 without bottom lock | each DVL report |
//! | `DVL_FOM` | double | m/s | A50 figure of merit (velocity error estimate); 10 without lock | each DVL report |
//! | `DVL_WATER_TRACK` | double | 1 | the velocity is through the water, not over ground (only with `dvl_water_track`, only in such reports) | each water-track report, the mid-range rate (8.5 Hz) |
//! | `DVL_VALID` ✱ | double | 1/0 | A50 `velocity_valid` (bottom lock, or water track) | each DVL report, 2 Hz while searching |
//! | `AHRS_PITCH` | double | deg | nose up positive | 10 Hz |
//! | `AHRS_ROLL` | double | deg | starboard down positive | 10 Hz |
//! | `AHRS_ROLL_RATE` | double | deg/s | gyro about body forward | 10 Hz |
//! | `AHRS_PITCH_RATE` | double | deg/s | gyro about body starboard | 10 Hz |
//! | `AHRS_YAW_RATE` | double | deg/s | gyro about body down (clockwise seen from above) | 10 Hz |
//! | `AHRS_HEADING` ✱ | double | deg | compass, clockwise from true north (declination applied, as the Gen-1 driver does), `[0, 360)` | 10 Hz |
//! | `PRESSURE` ✱ | double | Pa | absolute (atmosphere included), MS5837 | 20 Hz |
//! | `GPS_X` | double | m | local grid east | each epoch with a fix |
//! | `GPS_Y` | double | m | local grid north | each epoch with a fix |
//! | `GPS_LAT` | double | deg | WGS 84 latitude | each epoch with a fix, when the mission has LatOrigin/LongOrigin |
//! | `GPS_LONG` | double | deg | WGS 84 longitude | as `GPS_LAT` |
//! | `GPS_SATELLITES` | double | count | satellites used (0 underwater) | 5 Hz |
//! | `GPS_HDOP` | double | — | horizontal dilution of precision (99.99 without a fix) | 5 Hz |
//! | `GPS_FIX` ✱ | double | 1/0 | GGA quality: 1 fix, 0 none (antenna underwater, acquiring, dropout) | 5 Hz |
//!
//! The rates are the defaults; each sensor reports at most once per iteration, so the app's
//! `AppTick` must be at least the highest rate (20 with the defaults; a lower one is warned
//! about).
//!
//! # Configuration
//!
//! | parameter | default | meaning |
//! |---|---|---|
//! | `prefix` | `SIM` | the simulator's truth prefix |
//! | `seed` | the run's seed mixed with the MOOS name | seeds every draw (same seed, same values) |
//! | `water_depth` | 30 | m, the flat bottom the DVL sees |
//! | `enable_dvl`, `enable_ahrs`, `enable_pressure`, `enable_gps` | true | each sensor on or off |
//! | `dvl_noise`, `dvl_scale_error` | 0.02, 0.005 | m/s per axis; fraction |
//! | `dvl_min_altitude`, `dvl_max_altitude` | 0.05, 50 | m, the bottom-lock range |
//! | `dvl_min_rate`, `dvl_max_rate` | 2, 15 | Hz, at the far and near ends of the range |
//! | `dvl_altitude_noise` | 0.05 | m |
//! | `dvl_water_track` | false | velocity through the water out of bottom-lock range (a water-track DVL; the A50 has none) |
//! | `ahrs_rate`, `heading_bias`, `heading_noise`, `attitude_noise`, `gyro_noise` | 10, 0, 1, 0.2, 0.05 | Hz, deg, deg, deg, deg/s |
//! | `pressure_rate`, `salinity`, `atmospheric_pressure`, `pressure_noise`, `pressure_quantum` | 20, 0, 101325, 20, 10 | Hz, ppt, Pa, Pa, Pa |
//! | `gps_rate`, `gps_noise`, `gps_max_depth`, `gps_acquire_time`, `gps_loss_prob` | 5, 1.5, 0.2, 2, 0.01 | Hz, m at HDOP 1, m, s, per epoch |
//!
//! Unknown keys and bad values are warnings (`mission::Diagnostic`, kind `AppSetting`); the
//! app runs on with the defaults, as the vehicle apps do. The models, their laws and the
//! sources of the defaults are documented in [`vehicle::sensors`].

use mission::diagnostic::{Diagnostic, DiagnosticKind};
use mission::moos::ProcessConfig;
use vehicle::geodesy::LocalGrid;
use vehicle::sensors::{Reports, SensorConfig, SensorSuite, TruthField, TruthTracker};

use crate::app::{Mail, Post, Subscription, Value};
use crate::appcasting::Note;
use crate::hosted::{AppCore, Hosted};

/// The MOOS name of the app.
pub const PROGRAM: &str = "uSimSensors";

/// Counts of the reports posted, per sensor.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq)]
struct Counts {
    dvl: u64,
    dvl_valid: u64,
    ahrs: u64,
    pressure: u64,
    gps: u64,
    gps_fix: u64,
}

/// The sensor models: the core of the `uSimSensors` app.
pub struct SensorsCore {
    suite: SensorSuite,
    tracker: TruthTracker,
    truth_vars: Vec<(String, TruthField)>,
    counts: Counts,
    last: Reports,
}

/// The `uSimSensors` app.
pub type SensorsApp = Hosted<SensorsCore>;

impl Hosted<SensorsCore> {
    /// The app `name` from its `block`; `grid` (the mission's origin) adds GPS_LAT/GPS_LONG;
    /// `seed` is used when the block sets none. Configuration problems are
    /// [`Hosted::warnings`].
    pub fn new(name: &str, block: ProcessConfig, grid: Option<LocalGrid>, seed: u64) -> Self {
        let params = block
            .entries
            .iter()
            .map(|p| (p.key.as_str(), p.value.as_str()));
        let (cfg, problems) = match SensorConfig::from_params_lenient(params) {
            Ok(r) => r,
            Err(e) => (SensorConfig::default(), vec![e]),
        };
        let mut warnings = crate::vehicle::config_warnings(&block, &problems);
        let tick = crate::app::app_tick_of(Some(&block));
        let need = cfg.max_rate_hz();
        if tick + 1e-9 < need {
            let span = block
                .entries
                .iter()
                .find(|p| p.key.trim().eq_ignore_ascii_case("AppTick"))
                .map_or(&block.span, |p| &p.span);
            warnings.push(Diagnostic::line_warning(
                DiagnosticKind::AppSetting,
                span,
                format!(
                    "{PROGRAM}: AppTick {tick} is below the fastest sensor's rate ({need} Hz): \
                     sensors report at most once per iteration"
                ),
            ));
        }
        let truth_vars = TruthField::ALL
            .iter()
            .map(|(f, suffix)| (format!("{}_{suffix}", cfg.prefix), *f))
            .collect();
        let mut suite = SensorSuite::new(cfg, seed);
        suite.gps = suite.gps.clone().with_grid(grid);
        let core = SensorsCore {
            suite,
            tracker: TruthTracker::new(),
            truth_vars,
            counts: Counts::default(),
            last: Reports::default(),
        };
        Hosted::host(name, block, warnings, core)
    }

    /// The sensors' configuration in force.
    pub fn config(&self) -> &SensorConfig {
        self.core().suite.config()
    }
}

impl SensorsCore {
    fn post(&mut self, r: &Reports, out: &mut Vec<Post>) {
        if let Some(d) = &r.dvl {
            self.counts.dvl += 1;
            if d.valid {
                self.counts.dvl_valid += 1;
                out.push(Post::double("DVL_VEL_X", d.velocity_mps[0]));
                out.push(Post::double("DVL_VEL_Y", d.velocity_mps[1]));
                out.push(Post::double("DVL_VEL_Z", d.velocity_mps[2]));
            }
            if d.water_track {
                out.push(Post::double("DVL_WATER_TRACK", 1.0));
            }
            out.push(Post::double("DVL_ALTITUDE", d.altitude_m));
            out.push(Post::double("DVL_FOM", d.fom));
            out.push(Post::double("DVL_VALID", if d.valid { 1.0 } else { 0.0 }));
            self.last.dvl = Some(*d);
        }
        if let Some(a) = &r.ahrs {
            self.counts.ahrs += 1;
            out.push(Post::double("AHRS_PITCH", a.pitch_deg));
            out.push(Post::double("AHRS_ROLL", a.roll_deg));
            out.push(Post::double("AHRS_ROLL_RATE", a.gyro_deg_s[0]));
            out.push(Post::double("AHRS_PITCH_RATE", a.gyro_deg_s[1]));
            out.push(Post::double("AHRS_YAW_RATE", a.gyro_deg_s[2]));
            out.push(Post::double("AHRS_HEADING", a.heading_deg));
            self.last.ahrs = Some(*a);
        }
        if let Some(p) = &r.pressure {
            self.counts.pressure += 1;
            out.push(Post::double("PRESSURE", p.pressure_pa));
            self.last.pressure = Some(*p);
        }
        if let Some(g) = &r.gps {
            self.counts.gps += 1;
            if let Some((x, y)) = g.xy {
                self.counts.gps_fix += 1;
                out.push(Post::double("GPS_X", x));
                out.push(Post::double("GPS_Y", y));
            }
            if let Some((lat, lon)) = g.lat_lon {
                out.push(Post::double("GPS_LAT", lat));
                out.push(Post::double("GPS_LONG", lon));
            }
            out.push(Post::double("GPS_SATELLITES", f64::from(g.satellites)));
            out.push(Post::double("GPS_HDOP", g.hdop));
            out.push(Post::double("GPS_FIX", if g.fix { 1.0 } else { 0.0 }));
            self.last.gps = Some(*g);
        }
    }
}

/// The appcast body: the truth source and, per sensor, its state, report count and latest
/// values.
fn appcast_body(app: &Body<'_>, out: &mut String) {
    use std::fmt::Write as _;
    let c = app.suite.config();
    let have = if app.tracker.truth(0.0).is_some() {
        "yes"
    } else {
        "waiting"
    };
    let _ = writeln!(
        out,
        "Truth: {}_* ({have})   water_depth: {} m",
        c.prefix, c.water_depth
    );
    let _ = writeln!(out);
    let on = |b: bool| if b { "on" } else { "off" };
    let _ = writeln!(out, "Sensor    State  Reports  Latest");
    let _ = writeln!(out, "--------  -----  -------  ------");
    let dvl = app.last.dvl.map_or(String::new(), |d| {
        if d.valid {
            format!(
                "v=({:.2},{:.2},{:.2}) alt={:.1} ({} valid)",
                d.velocity_mps[0],
                d.velocity_mps[1],
                d.velocity_mps[2],
                d.altitude_m,
                app.counts.dvl_valid
            )
        } else {
            "no bottom lock".to_string()
        }
    });
    let _ = writeln!(
        out,
        "DVL       {:<5}  {:<7}  {dvl}",
        on(c.dvl.enabled),
        app.counts.dvl
    );
    let ahrs = app.last.ahrs.map_or(String::new(), |a| {
        format!(
            "hdg={:.1} pitch={:.1} roll={:.1} bias={}",
            a.heading_deg, a.pitch_deg, a.roll_deg, c.ahrs.heading_bias_deg
        )
    });
    let _ = writeln!(
        out,
        "AHRS      {:<5}  {:<7}  {ahrs}",
        on(c.ahrs.enabled),
        app.counts.ahrs
    );
    let pr = app
        .last
        .pressure
        .map_or(String::new(), |p| format!("{:.1} Pa", p.pressure_pa));
    let _ = writeln!(
        out,
        "Pressure  {:<5}  {:<7}  {pr}",
        on(c.pressure.enabled),
        app.counts.pressure
    );
    let gps = app.last.gps.map_or(String::new(), |g| {
        if g.fix {
            format!(
                "fix sats={} hdop={} ({} fixes)",
                g.satellites, g.hdop, app.counts.gps_fix
            )
        } else {
            format!("no fix ({} fixes)", app.counts.gps_fix)
        }
    });
    let _ = writeln!(
        out,
        "GPS       {:<5}  {:<7}  {gps}",
        on(c.gps.enabled),
        app.counts.gps
    );
}

/// What the appcast body reads.
struct Body<'a> {
    suite: &'a SensorSuite,
    tracker: &'a TruthTracker,
    counts: &'a Counts,
    last: &'a Reports,
}

impl AppCore for SensorsCore {
    fn subscriptions(&self) -> Vec<Subscription> {
        self.truth_vars
            .iter()
            .map(|(v, _)| Subscription::var(v))
            .collect()
    }

    fn on_mail(&mut self, m: &Mail, _now: f64, _out: &mut Vec<Post>, _notes: &mut Vec<Note>) {
        let Value::Double(v) = m.value else {
            return;
        };
        if let Some((_, f)) = self.truth_vars.iter().find(|(name, _)| **name == *m.key) {
            // The simulator's posting time is the truth's time.
            self.tracker.update(*f, v, m.time);
        }
    }

    fn iterate(&mut self, now: f64, out: &mut Vec<Post>, _notes: &mut Vec<Note>) {
        if let Some(truth) = self.tracker.truth(now) {
            let r = self.suite.sample(&truth);
            self.post(&r, out);
        }
    }

    fn report(&self, _now: f64, body: &mut String) {
        let view = Body {
            suite: &self.suite,
            tracker: &self.tracker,
            counts: &self.counts,
            last: &self.last,
        };
        appcast_body(&view, body);
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::antler::BuiltInApp;
    use crate::app::App;

    fn block(text: &str) -> ProcessConfig {
        crate::testing::block("s.moos", text)
    }

    fn mail(key: &str, v: f64, time: f64) -> Mail {
        crate::testing::mail(key, Value::Double(v), time, "uSimMarineV22")
    }

    #[test]
    fn unknown_keys_and_a_slow_tick_are_warnings_at_their_lines() {
        let b = block(
            "ProcessConfig = uSimSensors\n{\n  AppTick = 5\n  colour = red\n  \
             dvl_noise = fast\n  heading_bias = 3\n}\n",
        );
        let app = SensorsApp::new("uSimSensors", b, None, 1);
        let w: Vec<String> = app.warnings().iter().map(Diagnostic::located).collect();
        assert_eq!(w.len(), 3, "{w:?}");
        assert!(w[0].contains("s.moos:4") && w[0].contains("unknown parameter `colour`"));
        assert!(w[1].contains("s.moos:5") && w[1].contains("dvl_noise"));
        assert!(w[2].contains("s.moos:3") && w[2].contains("AppTick 5"));
        assert_eq!(app.config().ahrs.heading_bias_deg, 3.0);
        assert_eq!(
            app.config().dvl.noise_mps,
            0.02,
            "a bad value keeps the default"
        );
    }

    #[test]
    fn nothing_before_the_truth_then_reports_in_order() {
        let b = block("ProcessConfig = uSimSensors\n{\n  AppTick = 20\n  prefix = TRU\n}\n");
        let mut app = SensorsApp::new("uSimSensors", b, None, 1);
        assert!(app.warnings().is_empty());
        let subs: Vec<String> = app.subscriptions().into_iter().map(|s| s.pattern).collect();
        assert!(subs.contains(&"TRU_X".to_string()) && subs.contains(&"TRU_PITCH".to_string()));
        let mut out = Vec::new();
        app.on_startup(0.0, &mut out).unwrap();
        app.iterate(0.05, &mut out).unwrap();
        assert!(
            !out.iter()
                .any(|p| p.key.starts_with("DVL") || p.key == "PRESSURE")
        );
        let m: Vec<Mail> = [
            ("TRU_X", 3.0),
            ("TRU_Y", 4.0),
            ("TRU_DEPTH", 0.0),
            ("TRU_HEADING", 90.0),
        ]
        .iter()
        .map(|(k, v)| mail(k, *v, 0.05))
        .collect();
        app.on_mail(&m, 0.1, &mut out).unwrap();
        out.clear();
        app.iterate(0.1, &mut out).unwrap();
        let keys: Vec<&str> = out
            .iter()
            .map(|p| &*p.key)
            .filter(|k| !k.starts_with("APP"))
            .collect();
        // At the surface over 30 m of water: the DVL is in range, the GPS is acquiring.
        assert_eq!(
            keys,
            [
                "DVL_VEL_X",
                "DVL_VEL_Y",
                "DVL_VEL_Z",
                "DVL_ALTITUDE",
                "DVL_FOM",
                "DVL_VALID",
                "AHRS_PITCH",
                "AHRS_ROLL",
                "AHRS_ROLL_RATE",
                "AHRS_PITCH_RATE",
                "AHRS_YAW_RATE",
                "AHRS_HEADING",
                "PRESSURE",
                "GPS_SATELLITES",
                "GPS_HDOP",
                "GPS_FIX",
            ]
        );
    }
}
