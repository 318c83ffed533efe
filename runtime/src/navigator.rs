//! `pNavGraph`: the sliding-window factor-graph navigator ([`nav`]) as a MOOS app.
//!
//! It reads the navigation sensors' variables (the table of [`crate::sensors`]: `DVL_*`,
//! `AHRS_*`, `PRESSURE`, `GPS_*`, whether uSimSensors or the real drivers post them) through
//! [`nav::feed::Feed`], the adapter the log replay (`coug nav`) uses too, and posts the
//! estimate. Nothing of the navigation (`NAV_X`...) is posted before the navigator is
//! initialised (an attitude and a first GPS fix); `NAV_STATUS` says why until then.
//!
//! # Posted
//!
//! After each iteration in which the navigator made a keyframe (the DVL rate, or its
//! dead-reckoning timer), at the newest keyframe:
//!
//! | variable | type | unit | meaning |
//! |---|---|---|---|
//! | `NAV_X`, `NAV_Y` | double | m | local grid east, north |
//! | `NAV_DEPTH` | double | m | depth, positive down |
//! | `NAV_HEADING` | double | deg | true heading, compass, `[0, 360)` |
//! | `NAV_SPEED` | double | m/s | horizontal speed over ground |
//! | `NAV_LAT`, `NAV_LONG` | double | deg | WGS 84, when the mission has LatOrigin/LongOrigin |
//! | `NAV_PITCH`, `NAV_ROLL` | double | rad | from the AHRS (radians, as uSimMarine posts them) |
//! | `NAV_POS_STD` | double | m | horizontal 1-sigma (semi-major axis of the error ellipse) |
//! | `NAV_HEADING_BIAS` | double | deg | estimated compass bias (AHRS heading minus true) |
//! | `NAV_CURRENT_X`, `NAV_CURRENT_Y` | double | m/s | estimated water current, east, north |
//! | `DR_X`, `DR_Y`, `DR_DEPTH` | double | m | the DVL + AHRS dead-reckoning baseline (prefix `dr_prefix`) |
//! | `NAV_DIVE_REPORT` | string | | at the first good fix after a resurfacing: `dive=N,dist=D,correction=C,ratio_pct=R,start=T0,surface=T1,fix=T2` (m, m, %, s) |
//! | `NAV_STATUS` | string | | when it changes (also before initialisation): `initialising: ...`, `ok`, `dead_reckoning: ...`, `degraded: ...` |
//!
//! # Configuration
//!
//! | parameter | default | meaning |
//! |---|---|---|
//! | `window_size` | 20 | keyframes in the window |
//! | `max_iterations` | 3 | Gauss-Newton iterations per update |
//! | `dvl_noise` | 0.02 | m/s, DVL velocity sigma |
//! | `heading_noise` | 1 | deg, AHRS yaw white-noise sigma |
//! | `depth_noise` | 0.05 | m |
//! | `gps_noise` | 1.5 | m per axis at HDOP 1 |
//! | `gps_max_depth` | 0.5 | m, fixes refused deeper (estimated depth) |
//! | `heading_bias_prior` | 5 | deg, initial sigma of the compass bias |
//! | `current_prior` | 0.3 | m/s, initial sigma of the current |
//! | `salinity` | 0 | ppt, water density `997 + 0.8 salinity` kg/m³ (the sensor's law) |
//! | `water_density` | from salinity | kg/m³, overrides the salinity |
//! | `atmospheric_pressure` | 101325 | Pa |
//! | `dr_prefix` | `DR` | prefix of the dead-reckoning variables |
//!
//! Unknown keys and bad values are warnings (`mission::Diagnostic`, kind `AppSetting`); the
//! app runs on with the defaults, as the other apps do.

use mission::diagnostic::{Diagnostic, DiagnosticKind};
use mission::moos::ProcessConfig;
use moos_types::ByteString;
use nav::Status;
use nav::feed::{Feed, FeedConfig, Snapshot};
use vehicle::geodesy::LocalGrid;

use crate::app::{Mail, Post, Subscription, Value};
use crate::appcasting::Note;
use crate::hosted::{AppCore, Hosted};

/// The MOOS name of the app.
pub const PROGRAM: &str = "pNavGraph";

/// The names the app posts, the dead-reckoning ones made from `dr_prefix`, made once: a
/// posting then shares its name's buffer instead of copying the name.
#[derive(Debug, Clone)]
struct Names {
    dr_x: ByteString,
    dr_y: ByteString,
    dr_depth: ByteString,
}

const NAV_X: ByteString = ByteString::from_static("NAV_X");
const NAV_Y: ByteString = ByteString::from_static("NAV_Y");
const NAV_DEPTH: ByteString = ByteString::from_static("NAV_DEPTH");
const NAV_HEADING: ByteString = ByteString::from_static("NAV_HEADING");
const NAV_SPEED: ByteString = ByteString::from_static("NAV_SPEED");
const NAV_LAT: ByteString = ByteString::from_static("NAV_LAT");
const NAV_LONG: ByteString = ByteString::from_static("NAV_LONG");
const NAV_PITCH: ByteString = ByteString::from_static("NAV_PITCH");
const NAV_ROLL: ByteString = ByteString::from_static("NAV_ROLL");
const NAV_POS_STD: ByteString = ByteString::from_static("NAV_POS_STD");
const NAV_HEADING_BIAS: ByteString = ByteString::from_static("NAV_HEADING_BIAS");
const NAV_CURRENT_X: ByteString = ByteString::from_static("NAV_CURRENT_X");
const NAV_CURRENT_Y: ByteString = ByteString::from_static("NAV_CURRENT_Y");

/// The navigator: the core of the `pNavGraph` app.
pub struct NavCore {
    feed: Feed,
    grid: Option<LocalGrid>,
    names: Names,
    /// The status last posted (its text is `Status::describe`, a function of the value).
    posted_status: Option<Status>,
    last: Option<Snapshot>,
    dives: Vec<String>,
}

/// The `pNavGraph` app.
pub type NavApp = Hosted<NavCore>;

/// Reads the block into the feed's settings and the dead-reckoning prefix; problems are
/// warnings at their lines.
fn configure(block: &ProcessConfig) -> (FeedConfig, String, Vec<Diagnostic>) {
    let mut cfg = FeedConfig::default();
    let mut dr_prefix = "DR".to_string();
    let mut warnings = Vec::new();
    for p in &block.entries {
        let key = p.key.trim().to_ascii_lowercase();
        let value = p.value.trim();
        if vehicle::config::is_generic_app_key(&key) {
            continue;
        }
        let num = vehicle::config::parse_number(value).filter(|v| v.is_finite());
        let pos = num.filter(|v| *v > 0.0);
        let n = &mut cfg.nav;
        let ok = match key.as_str() {
            "window_size" => pos
                .filter(|v| v.fract() == 0.0 && *v >= 2.0 && *v <= 1000.0)
                .map(|v| n.window_size = v as usize),
            "max_iterations" => pos
                .filter(|v| v.fract() == 0.0 && *v <= 100.0)
                .map(|v| n.max_iterations = v as usize),
            "dvl_noise" => pos.map(|v| n.dvl_sigma_mps = v),
            "heading_noise" => pos.map(|v| n.yaw_sigma_rad = v.to_radians()),
            "depth_noise" => pos.map(|v| n.depth_sigma_m = v),
            "gps_noise" => pos.map(|v| n.gps_sigma_m = v),
            "gps_max_depth" => num.map(|v| n.gps_max_depth_m = v),
            "heading_bias_prior" => pos.map(|v| n.prior_sigma.bias_rad = v.to_radians()),
            "current_prior" => pos.map(|v| n.prior_sigma.current_mps = v),
            "salinity" => num.filter(|v| *v >= 0.0).map(|v| cfg.salinity_ppt = v),
            "water_density" => pos.map(|v| cfg.density_kg_m3 = Some(v)),
            "atmospheric_pressure" => pos.map(|v| cfg.atmospheric_pa = v),
            "dr_prefix" => (!value.is_empty() && !value.contains(char::is_whitespace))
                .then(|| dr_prefix = value.to_string()),
            _ => {
                warnings.push(Diagnostic::line_warning(
                    DiagnosticKind::AppSetting,
                    &p.span,
                    format!("{PROGRAM}: unknown parameter `{}`", p.key.trim()),
                ));
                continue;
            }
        };
        if ok.is_none() {
            warnings.push(Diagnostic::line_warning(
                DiagnosticKind::AppSetting,
                &p.span,
                format!(
                    "{PROGRAM}: parameter `{} = {value}`: not a usable value, default kept",
                    p.key.trim()
                ),
            ));
        }
    }
    (cfg, dr_prefix, warnings)
}

impl Hosted<NavCore> {
    /// The app `name` from its `block`; `grid` (the mission's origin) adds NAV_LAT/NAV_LONG.
    /// Configuration problems are [`Hosted::warnings`].
    pub fn new(name: &str, block: ProcessConfig, grid: Option<LocalGrid>) -> Self {
        let (cfg, dr, warnings) = configure(&block);
        let core = NavCore {
            feed: Feed::new(cfg),
            grid,
            names: Names {
                dr_x: ByteString::from(format!("{dr}_X")),
                dr_y: ByteString::from(format!("{dr}_Y")),
                dr_depth: ByteString::from(format!("{dr}_DEPTH")),
            },
            posted_status: None,
            last: None,
            dives: Vec::new(),
        };
        Hosted::host(name, block, warnings, core)
    }

    /// The feed's settings in force.
    pub fn config(&self) -> &FeedConfig {
        self.core().feed.config()
    }
}

impl NavCore {
    fn post_snapshot(&mut self, s: &Snapshot, out: &mut Vec<Post>, notes: &mut Vec<Note>) {
        let e = &s.estimate;
        out.push(Post::double(NAV_X, e.x_m));
        out.push(Post::double(NAV_Y, e.y_m));
        out.push(Post::double(NAV_DEPTH, e.depth_m));
        out.push(Post::double(NAV_HEADING, e.heading_rad.to_degrees()));
        out.push(Post::double(NAV_SPEED, e.speed_mps));
        if let Some((lat, lon)) = self
            .grid
            .as_ref()
            .and_then(|g| g.to_latlon(e.x_m, e.y_m).ok())
        {
            out.push(Post::double(NAV_LAT, lat));
            out.push(Post::double(NAV_LONG, lon));
        }
        out.push(Post::double(NAV_PITCH, e.pitch_rad));
        out.push(Post::double(NAV_ROLL, e.roll_rad));
        out.push(Post::double(NAV_POS_STD, e.pos_sigma_m));
        out.push(Post::double(
            NAV_HEADING_BIAS,
            e.heading_bias_rad.to_degrees(),
        ));
        out.push(Post::double(NAV_CURRENT_X, e.current_east_mps));
        out.push(Post::double(NAV_CURRENT_Y, e.current_north_mps));
        if let Some([x, y, d]) = s.dead_reckoning {
            out.push(Post::double(&self.names.dr_x, x));
            out.push(Post::double(&self.names.dr_y, y));
            out.push(Post::double(&self.names.dr_depth, d));
        }
        if let Some(r) = &s.dive {
            let text = Snapshot::dive_report_text(r);
            out.push(Post::text("NAV_DIVE_REPORT", text.as_str()));
            notes.push(Note::Event(format!("dive report: {text}")));
            self.dives.push(text);
        }
    }
}

fn appcast_body(feed: &Feed, last: Option<&Snapshot>, dives: &[String], out: &mut String) {
    use std::fmt::Write as _;
    let nav = feed.navigator();
    let c = feed.counts();
    let _ = writeln!(out, "Status: {}", feed.status().describe());
    let _ = writeln!(
        out,
        "Keyframes: {} (window {})  Reports: DVL {}  AHRS {}  pressure {}  GPS fixes {}",
        nav.keyframes(),
        nav.window_len(),
        c.dvl,
        c.ahrs,
        c.pressure,
        c.gps_fixes
    );
    let _ = writeln!(out, "Rejected: {}", nav.rejections().total());
    if let Some(s) = last {
        let e = &s.estimate;
        let _ = writeln!(
            out,
            "Estimate: x={:.1} y={:.1} depth={:.1} hdg={:.1} spd={:.2} sigma={:.2}",
            e.x_m,
            e.y_m,
            e.depth_m,
            e.heading_rad.to_degrees(),
            e.speed_mps,
            e.pos_sigma_m
        );
        let _ = writeln!(
            out,
            "Slow states: heading bias {:.2} deg, current ({:.3}, {:.3}) m/s",
            e.heading_bias_rad.to_degrees(),
            e.current_east_mps,
            e.current_north_mps
        );
        if let Some([x, y, _]) = s.dead_reckoning {
            let _ = writeln!(out, "Dead reckoning: x={x:.1} y={y:.1}");
        }
    }
    let _ = writeln!(out);
    let _ = writeln!(out, "Dive reports: {}", dives.len());
    for d in dives.iter().rev().take(5) {
        let _ = writeln!(out, "  {d}");
    }
}

impl AppCore for NavCore {
    fn subscriptions(&self) -> Vec<Subscription> {
        nav::feed::INPUTS
            .iter()
            .map(|v| Subscription::var(*v))
            .collect()
    }

    fn on_mail(&mut self, m: &Mail, _now: f64, _out: &mut Vec<Post>, _notes: &mut Vec<Note>) {
        if let Value::Double(v) = m.value {
            // The driver's posting time is the measurement's time.
            self.feed.take(&m.key, v, m.time);
        }
    }

    fn iterate(&mut self, now: f64, out: &mut Vec<Post>, notes: &mut Vec<Note>) {
        self.feed.advance(now);
        if let Some(s) = self.feed.poll() {
            self.post_snapshot(&s, out, notes);
            self.last = Some(s);
        }
        // Equal statuses have equal texts: the text is made only when the status changes.
        let status = self.feed.status();
        if self.posted_status != Some(status) {
            out.push(Post::text("NAV_STATUS", status.describe()));
            self.posted_status = Some(status);
        }
    }

    fn report(&self, _now: f64, body: &mut String) {
        appcast_body(&self.feed, self.last.as_ref(), &self.dives, body);
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::antler::BuiltInApp;
    use crate::app::App;

    fn block(text: &str) -> ProcessConfig {
        crate::testing::block("n.moos", text)
    }

    fn mail(key: &str, v: f64, time: f64) -> Mail {
        crate::testing::mail(key, Value::Double(v), time, "uSimSensors")
    }

    #[test]
    fn unknown_keys_and_bad_values_are_warnings_at_their_lines() {
        let b = block(
            "ProcessConfig = pNavGraph\n{\n  AppTick = 10\n  colour = red\n  \
             window_size = 1.5\n  gps_noise = 3\n  water_density = 1025\n  dr_prefix = DEAD\n}\n",
        );
        let app = NavApp::new("pNavGraph", b, None);
        let w: Vec<String> = app.warnings().iter().map(Diagnostic::located).collect();
        assert_eq!(w.len(), 2, "{w:?}");
        assert!(w[0].contains("n.moos:4") && w[0].contains("unknown parameter `colour`"));
        assert!(w[1].contains("n.moos:5") && w[1].contains("window_size"));
        assert_eq!(app.config().nav.gps_sigma_m, 3.0);
        assert_eq!(
            app.config().nav.window_size,
            20,
            "a bad value keeps the default"
        );
        assert_eq!(app.config().density(), 1025.0);
        assert_eq!(app.core().names.dr_x, "DEAD_X");
    }

    #[test]
    fn no_navigation_before_a_fix_then_the_estimate() {
        let b = block("ProcessConfig = pNavGraph\n{\n  AppTick = 10\n}\n");
        let grid = LocalGrid::new(40.237, -111.745).ok();
        let mut app = NavApp::new("pNavGraph", b, grid);
        assert!(app.warnings().is_empty());
        let subs: Vec<String> = app.subscriptions().into_iter().map(|s| s.pattern).collect();
        assert!(
            subs.contains(&"AHRS_HEADING".to_string()) && subs.contains(&"GPS_FIX".to_string())
        );
        let mut out = Vec::new();
        app.on_startup(0.0, &mut out).unwrap();
        let ahrs = |t: f64| {
            [
                ("AHRS_PITCH", 0.0),
                ("AHRS_ROLL", 0.0),
                ("AHRS_ROLL_RATE", 0.0),
                ("AHRS_PITCH_RATE", 0.0),
                ("AHRS_YAW_RATE", 0.0),
                ("AHRS_HEADING", 180.0),
            ]
            .iter()
            .map(|(k, v)| mail(k, *v, t))
            .collect::<Vec<_>>()
        };
        app.on_mail(&ahrs(0.1), 0.1, &mut out).unwrap();
        app.iterate(0.1, &mut out).unwrap();
        let nav: Vec<&str> = out
            .iter()
            .map(|p| &*p.key)
            .filter(|k| k.starts_with("NAV_") || k.starts_with("DR_"))
            .collect();
        assert_eq!(nav, ["NAV_STATUS"], "only the status before a fix");
        assert_eq!(
            out.iter().find(|p| p.key == "NAV_STATUS").unwrap().value,
            Value::text("initialising: waiting for a GPS fix")
        );
        out.clear();
        let mut m = ahrs(0.2);
        m.extend(
            [
                ("GPS_X", 5.0),
                ("GPS_Y", -3.0),
                ("GPS_SATELLITES", 9.0),
                ("GPS_HDOP", 1.0),
                ("GPS_FIX", 1.0),
            ]
            .iter()
            .map(|(k, v)| mail(k, *v, 0.2)),
        );
        app.on_mail(&m, 0.2, &mut out).unwrap();
        app.iterate(0.2, &mut out).unwrap();
        let get = |k: &str| match out.iter().find(|p| p.key == k).map(|p| &p.value) {
            Some(Value::Double(v)) => *v,
            other => panic!("{k}: {other:?}"),
        };
        assert!((get("NAV_X") - 5.0).abs() < 1e-6 && (get("NAV_Y") + 3.0).abs() < 1e-6);
        assert!((get("NAV_HEADING") - 180.0).abs() < 1e-6);
        assert!(get("NAV_LAT") < 40.237 && get("NAV_LONG") > -111.745);
        assert!((get("DR_X") - 5.0).abs() < 1e-9);
        assert!(get("NAV_POS_STD") > 0.0);
        assert!(out.iter().any(|p| p.key == "NAV_STATUS"));
    }
}
