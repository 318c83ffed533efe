//! `pObstacleMgr`: clusters of sensed points (`TRACKED_FEATURE`) and given polygons
//! (`GIVEN_OBSTACLE`, or `given_obstacle` lines) become obstacle polygons; an alert (asked
//! for by the helm's obstacle behaviours through `OBM_ALERT_REQUEST`) posts each obstacle
//! within range to the alert variable in the `name=<prefix><key>#poly=...` form, so the helm
//! spawns one behaviour per obstacle; obstacles expire (old points, given durations) with
//! `OBM_RESOLVED` (issue #18, point 4).
//!
//! [`ObstacleMgr`] is the pure core (mail and time in, posts out); [`ObstacleMgrApp`] is the
//! app with its appcast: the core hosted by [`crate::hosted::Hosted`]. Facts from MOOS-IvP's
//! `pObstacleMgr` and `lib_obstacles`' `Obstacle` at a2a9b716.
//!
//! Each iteration, in the C++ order: expiry (points older than `max_age_per_point`, given
//! obstacles older than their duration, polygons posted inactive), hulls of the point
//! obstacles that changed (convex hull, [`hull::convex_hull`], or with `lasso` a regular
//! polygon of `lasso_points` vertices and `lasso_radius` around the points' mean; an octagon
//! around the points when the hull is not convex), ranges (`OBM_MIN_DIST_EVER`; an obstacle
//! coming within `alert_range` is marked changed), then the alerts of changed obstacles.
//!
//! # Conformance with pObstacleMgr (MOOS-IvP a2a9b716)
//!
//! | parameter | default | validation (C++ rule) | coug |
//! |---|---|---|---|
//! | point_var | TRACKED_FEATURE | no white space; `GIVEN_OBSTABLE` refused | done |
//! | given_obstacle, given_obstable | none | a convex polygon spec (label = key, optional `duration`) | done |
//! | alert_range | 20 | number > 0 | done |
//! | ignore_range | -1 (off) | number > 0 | done |
//! | max_pts_per_cluster | 20 | number >= 0 (truncated) | done |
//! | max_age_per_point | 20 | number > 0 | done |
//! | post_dist_to_polys | close | true, false, close | done |
//! | post_view_polys | true | boolean | done |
//! | obstacles_color | blue | a colour | done |
//! | poly_label_thresh, poly_shade_thresh, poly_vertex_thresh | 25, 100, 150 | number >= 0 | done |
//! | given_max_duration | 60 | `off` or number > 0 | done |
//! | general_alert | none | `name=`, `update_var=`, `alert_range=` (> 0), nothing else | done |
//! | new_obs_flag | none | `VAR=value`, macros `$[OBS_NOW]`, `$[OBS_EVER]`, `$[TOTAL_DISABLED]`, ... | done |
//! | mailflag | none | `@KEY # VAR=value` (`@ANY`), macros `$[CNT]`, `$[MCNT]`, `$[UTC]` | done |
//! | disable_var, enable_var, expunge_var | none | no white space | done |
//! | lasso | false | boolean | done |
//! | lasso_points | 6 | number >= 0; below 3: warned, 3 | done |
//! | lasso_radius | 5 | number; <= 0: warned, 1 | done |
//!
//! | variable | when | format | coug |
//! |---|---|---|---|
//! | OBM_CONNECT | start-up | `true` | done |
//! | the alert's `update_var` | a changed obstacle within `alert_range` | `name=<name><key>#poly=pts={..5 dp..},label=<key>[,vsource=..]#id=<key>` | done |
//! | the general alert's `update_var` | as above, within its range, once a helm alert exists | same, its name ending in `_` | done |
//! | OBM_DIST_TO_OBJ | `post_dist_to_polys`: always, or within `alert_range` (`close`) | `<KEY>,<dist 1 dp>` | done |
//! | OBM_MIN_DIST_EVER | the closest range to any obstacle shrinks | double | done |
//! | OBM_RESOLVED | an obstacle expires | its key | done |
//! | VIEW_POLYGON | a point obstacle's hull changes (`post_view_polys`); erased on expiry | `pts={..5 dp..},label=obmgr_<key>,...` | done |
//! | BHV_ABLE_FILTER | mail on `disable_var`/`enable_var`/`expunge_var` | `obstacle_id=..` or `vsource=..`, `,action=..` | done |
//! | new_obs_flag, mailflag flags | a given obstacle arrives; a flagged mail | `VAR = value`, numbers as doubles | done |
//!
//! C++ quirks kept: `OBM_ALERT_REQUEST` replaces the one alert (the last request wins); the
//! obstacle count behind `$[OBS_EVER]` grows with every accepted point, not every obstacle; a
//! point's key comes from `key=` or `label=` (its `msg=` is not read); the general alert posts
//! only once a helm alert exists.

pub mod hull;
pub mod sim;

use std::collections::{BTreeMap, VecDeque};

use geometry::pattern::Radial;
use geometry::{Point, Polygon};
use mission::diagnostic::{Diagnostic, DiagnosticKind};
use mission::moos::ProcessConfig;
use moos_types::fmt::{compact_string, fixed, g_string};
use moos_types::text::{is_number, parse_string, set_boolean_on_string, tok_string_parse};

use crate::app::{Mail, Post, Subscription, Value};
use crate::appcasting::Note;
use crate::contact_mgr::{Flag, expand_able_macros, flag};
use crate::hosted::{AppCore, Hosted};

/// The program name.
pub const PROGRAM: &str = "pObstacleMgr";

/// `$[KEY]` replaced by `val` everywhere in `s`.
fn macro_expand(s: &str, key: &str, val: &str) -> String {
    s.replace(&format!("$[{key}]"), val)
}

/// An obstacle's polygon with what pObstacleMgr reads of its spec.
#[derive(Debug, Clone, Default, PartialEq)]
struct ObPoly {
    poly: Polygon,
    label: String,
    vsource: String,
    active: bool,
    /// The spec's display `duration`, if it has one.
    duration: Option<f64>,
}

impl ObPoly {
    fn null() -> ObPoly {
        ObPoly {
            active: true,
            ..ObPoly::default()
        }
    }

    /// `pts={...}` with `prec` decimals (MOOS `get_spec_pts`).
    fn spec_pts(&self, prec: usize) -> String {
        let mut s = String::new();
        geometry::spec::write_points(&mut s, self.poly.vertices(), prec);
        s
    }

    /// The erasing spec (MOOS `get_spec_inactive`).
    fn spec_inactive(&self) -> String {
        let mut s = String::from("pts={0,0:9,0:0,9},active=false");
        if !self.label.is_empty() {
            s.push_str(",label=");
            s.push_str(&self.label);
        }
        if self.duration == Some(0.0) {
            s.push_str(",duration=0");
        }
        s
    }
}

/// The distance from `(x, y)` to a polygon's boundary (MOOS `XYPolygon::dist_to_poly`): to
/// its one point or segment for one or two vertices, -1 for none.
fn dist_to_poly(p: &Polygon, x: f64, y: f64) -> f64 {
    let v = p.vertices();
    match v.len() {
        0 => -1.0,
        1 => (x - v[0].x).hypot(y - v[0].y),
        n => {
            let mut best = f64::INFINITY;
            let edges = if n == 2 { 1 } else { n };
            for i in 0..edges {
                let (a, b) = (v[i], v[(i + 1) % n]);
                let d = geometry::segment::dist_point_to_segment(a.x, a.y, b.x, b.y, x, y);
                if d < best {
                    best = d;
                }
            }
            best
        }
    }
}

/// One sensed point of an obstacle.
#[derive(Debug, Clone, Copy)]
struct SensedPoint {
    x: f64,
    y: f64,
    time: f64,
}

/// One obstacle (MOOS `Obstacle`).
#[derive(Debug, Clone)]
struct Obstacle {
    /// Newest first.
    points: VecDeque<SensedPoint>,
    poly: ObPoly,
    range: f64,
    duration: f64,
    tstamp: f64,
    max_points: usize,
    vsource: String,
    changed: bool,
    updates_total: u32,
    min_range: f64,
    poly_spec: String,
}

impl Default for Obstacle {
    fn default() -> Self {
        Obstacle {
            points: VecDeque::new(),
            poly: ObPoly::null(),
            range: 0.0,
            duration: -1.0,
            tstamp: 0.0,
            max_points: 20,
            vsource: String::new(),
            changed: false,
            updates_total: 0,
            min_range: -1.0,
            poly_spec: String::new(),
        }
    }
}

impl Obstacle {
    fn add_point(&mut self, p: SensedPoint) {
        self.points.push_front(p);
        if self.points.len() > self.max_points {
            self.points.pop_back();
        }
        self.duration = 0.0;
        self.changed = true;
    }

    /// Takes a new polygon unless it is not convex or is the same at 0.1 m.
    fn set_poly(&mut self, p: ObPoly) {
        if !p.poly.is_convex() {
            return;
        }
        let mut spec = p.spec_pts(1);
        if !p.label.is_empty() {
            spec.push_str(",label=");
            spec.push_str(&p.label);
        }
        if spec == self.poly_spec {
            return;
        }
        self.poly = p;
        self.poly_spec = spec;
        self.changed = true;
        self.updates_total += 1;
    }

    fn set_range(&mut self, r: f64) {
        self.range = r;
        if self.min_range < 0.0 || r < self.min_range {
            self.min_range = r;
        }
    }

    fn is_given(&self) -> bool {
        self.points.is_empty() && !self.poly.poly.is_empty()
    }

    fn time_to_live(&self, now: f64) -> f64 {
        if self.duration <= 0.0 || self.tstamp <= 0.0 {
            return -1.0;
        }
        (self.duration - (now - self.tstamp)).max(0.0)
    }

    /// Drops old points; true when the obstacle is to be removed.
    fn prune_by_age(&mut self, max_age: f64, now: f64) -> bool {
        if self.points.is_empty() {
            return self.duration >= 0.0 && now - self.tstamp > self.duration;
        }
        let before = self.points.len();
        self.points.retain(|p| now - p.time <= max_age);
        if self.points.len() != before {
            self.changed = true;
        }
        self.points.is_empty()
    }
}

/// The settings of a block.
#[derive(Debug, Clone)]
struct Settings {
    point_var: String,
    alert_var: String,
    alert_name: String,
    alert_range: f64,
    gen_alert_var: String,
    gen_alert_name: String,
    gen_alert_range: f64,
    poly_label_thresh: usize,
    poly_shade_thresh: usize,
    poly_vertex_thresh: usize,
    ignore_range: f64,
    max_pts_per_cluster: usize,
    max_age_per_point: f64,
    lasso: bool,
    lasso_points: u32,
    lasso_radius: f64,
    post_dist_to_polys: String,
    post_view_polys: bool,
    obstacles_color: String,
    given_max_duration: f64,
    new_obs_flags: Vec<Flag>,
    disable_var: String,
    enable_var: String,
    expunge_var: String,
}

impl Default for Settings {
    fn default() -> Self {
        Settings {
            point_var: String::new(),
            alert_var: String::new(),
            alert_name: String::new(),
            alert_range: 20.0,
            gen_alert_var: String::new(),
            gen_alert_name: String::new(),
            gen_alert_range: -1.0,
            poly_label_thresh: 25,
            poly_shade_thresh: 100,
            poly_vertex_thresh: 150,
            ignore_range: -1.0,
            max_pts_per_cluster: 20,
            max_age_per_point: 20.0,
            lasso: false,
            lasso_points: 6,
            lasso_radius: 5.0,
            post_dist_to_polys: "close".into(),
            post_view_polys: true,
            obstacles_color: "blue".into(),
            given_max_duration: 60.0,
            new_obs_flags: Vec::new(),
            disable_var: String::new(),
            enable_var: String::new(),
            expunge_var: String::new(),
        }
    }
}

/// A block line as the MOOS reader hands it to pObstacleMgr and uFldObstacleSim: every
/// blank removed, the parameter in lower case (`(param, value)`).
pub(crate) fn config_line(key: &str, value: &str) -> (String, String) {
    let strip = |t: &str| -> String {
        t.chars()
            .filter(|c| !matches!(c, ' ' | '\t' | '\r'))
            .collect()
    };
    (strip(key).to_ascii_lowercase(), strip(value))
}

/// [`config_line`] of a `param = value` line given whole.
pub(crate) fn config_text(line: &str) -> (String, String) {
    let (p, v) = line.split_once('=').unwrap_or((line, ""));
    config_line(p, v)
}

/// `setPosDoubleOnString`: a number > 0.
fn pos_double(v: &str) -> Option<f64> {
    let d = geometry::atof(v);
    (is_number(v) && d > 0.0).then_some(d)
}

/// `setUIntOnString`: a number >= 0, truncated.
fn uint(v: &str) -> Option<usize> {
    let d = geometry::atof(v);
    (is_number(v) && d >= 0.0).then_some(d as usize)
}

/// `setNonWhiteVarOnString`.
fn non_white(v: &str) -> Option<String> {
    (!v.is_empty() && !v.contains(char::is_whitespace)).then(|| v.to_string())
}

/// The `name=..,update_var=..,alert_range=..` of an alert request or a general alert.
fn parse_alert(s: &str, default_name: &str) -> Option<(String, String, f64)> {
    let (mut name, mut var, mut range) = (default_name.to_string(), String::new(), "");
    for piece in parse_string(s, ',') {
        let (p, v) = piece.split_once('=').unwrap_or((piece, ""));
        match p.trim().to_ascii_lowercase().as_str() {
            "name" => name = v.trim().to_string(),
            "update_var" => var = v.trim().to_string(),
            "alert_range" => range = v.trim(),
            _ => return None,
        }
    }
    if name.is_empty() || var.is_empty() || range.is_empty() || !is_number(range) {
        return None;
    }
    let r = geometry::atof(range);
    (r > 0.0).then_some((name, var, r))
}

/// The pure core of pObstacleMgr.
///
/// ```
/// use runtime::obstacle_mgr::ObstacleMgr;
/// use runtime::app::Value;
/// let (mut om, warnings) = ObstacleMgr::new(&["alert_range = 30"]);
/// assert!(warnings.is_empty());
/// let mut out = Vec::new();
/// om.on_mail("OBM_ALERT_REQUEST", &Value::text("name=avd_,update_var=OBSTACLE_ALERT,alert_range=30"), 1.0, &mut out);
/// for (x, y) in [(10.0, 10.0), (14.0, 10.0), (12.0, 14.0)] {
///     om.on_mail("TRACKED_FEATURE", &Value::text(format!("x={x},y={y},label=a")), 1.0, &mut out);
/// }
/// om.iterate(1.5, &mut out);
/// let alert = out.iter().find(|p| p.key == "OBSTACLE_ALERT").unwrap();
/// assert!(alert.value.as_str().unwrap().starts_with("name=avd_a#poly=pts={"));
/// ```
#[derive(Debug, Clone)]
pub struct ObstacleMgr {
    s: Settings,
    /// `given_obstacle` lines, taken at start-up, each with the number of `new_obs_flag`s
    /// configured before it (the C++ handles the line where it reads it).
    given_config: Vec<(String, usize)>,
    /// Mail flags raised by the current batch of mail, posted at its end.
    pending_flags: Vec<Flag>,
    mail_flags: BTreeMap<String, Vec<Flag>>,
    mail_total: u32,
    mail_total_by_key: BTreeMap<String, u32>,
    nav: (f64, f64),
    min_dist_ever: f64,
    points_total: u32,
    points_invalid: u32,
    points_ignored: u32,
    obstacles_released: u32,
    alerts_posted: u32,
    alerts_resolved: u32,
    given_mail_ever: u32,
    given_mail_good: u32,
    given_config_ever: u32,
    obstacles_ever: u32,
    label_over: bool,
    shade_over: bool,
    vertex_over: bool,
    obstacles: BTreeMap<String, Obstacle>,
    disabled: VecDeque<String>,
    enabled: VecDeque<String>,
    expunged: VecDeque<String>,
    notes: Vec<Note>,
}

impl ObstacleMgr {
    /// A manager from the block's `param = value` lines (in file order), with the warnings
    /// the C++ app reports for them.
    pub fn new(lines: &[&str]) -> (ObstacleMgr, Vec<String>) {
        let mut om = ObstacleMgr {
            s: Settings::default(),
            given_config: Vec::new(),
            pending_flags: Vec::new(),
            mail_flags: BTreeMap::new(),
            mail_total: 0,
            mail_total_by_key: BTreeMap::new(),
            nav: (0.0, 0.0),
            min_dist_ever: -1.0,
            points_total: 0,
            points_invalid: 0,
            points_ignored: 0,
            obstacles_released: 0,
            alerts_posted: 0,
            alerts_resolved: 0,
            given_mail_ever: 0,
            given_mail_good: 0,
            given_config_ever: 0,
            obstacles_ever: 0,
            label_over: false,
            shade_over: false,
            vertex_over: false,
            obstacles: BTreeMap::new(),
            disabled: VecDeque::new(),
            enabled: VecDeque::new(),
            expunged: VecDeque::new(),
            notes: Vec::new(),
        };
        let mut warnings = Vec::new();
        for line in lines {
            let (p, v) = config_text(line);
            if let Err(w) = om.configure(&p, &v) {
                warnings.push(w);
            }
        }
        om.finish_config();
        (om, warnings)
    }

    fn finish_config(&mut self) {
        if self.s.point_var.is_empty() {
            self.s.point_var = "TRACKED_FEATURE".into();
        }
    }

    /// One configuration line; `Err(warning)` as the C++ reports it.
    fn configure(&mut self, param: &str, value: &str) -> Result<(), String> {
        let unhandled = || format!("Unhandled config line: {param}={value}");
        let s = &mut self.s;
        let ok = match param {
            "point_var" if !value.eq_ignore_ascii_case("GIVEN_OBSTABLE") => {
                non_white(value).map(|v| s.point_var = v).is_some()
            }
            "given_obstable" | "given_obstacle" => {
                // Counted now; the obstacle itself is made at start-up, with the time.
                self.given_config_ever += 1;
                let ok = Self::read_given(value).is_some();
                if ok {
                    let n = s.new_obs_flags.len();
                    self.given_config.push((value.to_string(), n));
                }
                ok
            }
            "alert_range" => pos_double(value).map(|d| s.alert_range = d).is_some(),
            "ignore_range" => pos_double(value).map(|d| s.ignore_range = d).is_some(),
            "max_pts_per_cluster" => uint(value).map(|n| s.max_pts_per_cluster = n).is_some(),
            "max_age_per_point" => pos_double(value).map(|d| s.max_age_per_point = d).is_some(),
            "post_dist_to_polys" => {
                let v = value.trim().to_ascii_lowercase();
                let ok = matches!(v.as_str(), "true" | "false" | "close");
                if ok {
                    s.post_dist_to_polys = v;
                }
                ok
            }
            "post_view_polys" => set_boolean_on_string(s.post_view_polys, value)
                .map(|b| s.post_view_polys = b)
                .is_some(),
            "obstacles_color" => {
                let ok = geometry::color::is_color(value);
                if ok {
                    s.obstacles_color = value.to_string();
                }
                ok
            }
            "poly_label_thresh" => uint(value).map(|n| s.poly_label_thresh = n).is_some(),
            "poly_shade_thresh" => uint(value).map(|n| s.poly_shade_thresh = n).is_some(),
            "poly_vertex_thresh" => uint(value).map(|n| s.poly_vertex_thresh = n).is_some(),
            "given_max_duration" => {
                if value.eq_ignore_ascii_case("off") {
                    s.given_max_duration = -1.0;
                    true
                } else {
                    pos_double(value)
                        .map(|d| s.given_max_duration = d)
                        .is_some()
                }
            }
            "general_alert" => match parse_alert(value, "gen_alert") {
                Some((mut name, var, range)) => {
                    if !name.ends_with('_') {
                        name.push('_');
                    }
                    s.gen_alert_name = name;
                    s.gen_alert_var = var;
                    s.gen_alert_range = range;
                    true
                }
                None => false,
            },
            "new_obs_flag" => flag(value).map(|f| s.new_obs_flags.push(f)).is_some(),
            "mailflag" => self.add_mail_flag(value),
            "disable_var" => non_white(value).map(|v| s.disable_var = v).is_some(),
            "enable_var" => non_white(value).map(|v| s.enable_var = v).is_some(),
            "expunge_var" => non_white(value).map(|v| s.expunge_var = v).is_some(),
            "lasso" => set_boolean_on_string(s.lasso, value)
                .map(|b| s.lasso = b)
                .is_some(),
            "lasso_points" => {
                let ok = uint(value).map(|n| s.lasso_points = n as u32).is_some();
                if s.lasso_points < 3 {
                    s.lasso_points = 3;
                    // The C++ warns and goes on; the line itself counts as handled.
                    return if ok {
                        Err("lasso_points must be at least 3 points".into())
                    } else {
                        Err(format!(
                            "lasso_points must be at least 3 points\n{}",
                            unhandled()
                        ))
                    };
                }
                ok
            }
            _ if appcast::casting::UNHANDLED_EXEMPT
                .contains(&param.to_ascii_uppercase().as_str())
                || matches!(param, "comms_policy" | "max_appcast_run_warnings") =>
            {
                true
            }
            "lasso_radius" => {
                let ok = is_number(value);
                if ok {
                    s.lasso_radius = geometry::atof(value);
                }
                if s.lasso_radius <= 0.0 {
                    s.lasso_radius = 1.0;
                    return Err("lasso_radius must be at positive number".into());
                }
                ok
            }
            _ => false,
        };
        if ok { Ok(()) } else { Err(unhandled()) }
    }

    /// `@KEY # VAR=value` (MOOS `MailFlagSet::addFlag`).
    fn add_mail_flag(&mut self, s: &str) -> bool {
        let (key, rest) = s.split_once('#').unwrap_or((s, ""));
        let key = key.trim();
        let Some(key) = key.strip_prefix('@') else {
            return false;
        };
        let key = key.trim();
        if key.is_empty() {
            return false;
        }
        match flag(rest) {
            Some(f) => {
                self.mail_flags.entry(key.to_string()).or_default().push(f);
                true
            }
            None => false,
        }
    }

    /// A given polygon as `string2Poly` reads it, when it is convex.
    fn read_given(s: &str) -> Option<ObPoly> {
        let v = geometry::spec::parse_polygon(s).ok()?;
        if !v.polygon.is_convex() {
            return None;
        }
        Some(ObPoly {
            poly: v.polygon,
            label: v.attrs.label,
            vsource: v.attrs.vsource,
            active: v.attrs.active,
            duration: v.attrs.duration,
        })
    }

    /// The variables the app registers for (besides the appcast's).
    pub fn subscriptions(&self) -> Vec<String> {
        let mut v = vec![
            self.s.point_var.clone(),
            "NAV_X".into(),
            "NAV_Y".into(),
            "GIVEN_OBSTACLE".into(),
            "OBM_ALERT_REQUEST".into(),
        ];
        v.extend(self.mail_flags.keys().cloned());
        for var in [&self.s.disable_var, &self.s.enable_var, &self.s.expunge_var] {
            if !var.is_empty() {
                v.push(var.clone());
            }
        }
        v
    }

    /// At start-up: `OBM_CONNECT` and the configured given obstacles.
    pub fn on_startup(&mut self, now: f64, out: &mut Vec<Post>) {
        let all_flags = self.s.new_obs_flags.clone();
        for (g, n) in std::mem::take(&mut self.given_config) {
            self.s.new_obs_flags.truncate(n);
            self.given(&g, false, now, out);
            self.s.new_obs_flags.clone_from(&all_flags);
        }
        out.push(Post::text("OBM_CONNECT", "true"));
        self.notes.push(Note::Event("OBM_CONNECT=true".into()));
    }

    /// One mail (MOOS `OnNewMail`); posts what the mail makes the C++ post at once. Call
    /// [`ObstacleMgr::end_mail`] after the last mail of a batch.
    pub fn on_mail(&mut self, key: &str, value: &Value, now: f64, out: &mut Vec<Post>) {
        let dval = value.as_ref().as_f64().unwrap_or(0.0);
        let sval = value.as_str().unwrap_or("");
        let mut handled = self.mail_flag(key, now);
        if key == self.s.point_var {
            handled = self.new_point(sval, now);
        }
        if key == "NAV_X" {
            self.nav.0 = dval;
            handled = true;
        } else if key == "NAV_Y" {
            self.nav.1 = dval;
            handled = true;
        } else if key == "GIVEN_OBSTACLE" {
            handled = self.given(sval, true, now, out);
        } else if key == "OBM_ALERT_REQUEST" {
            handled = self.alert_request(sval);
        } else if !self.s.disable_var.is_empty() && key == self.s.disable_var {
            handled = self.able(sval, "disable", out);
        } else if !self.s.expunge_var.is_empty() && key == self.s.expunge_var {
            handled = self.able(sval, "expunge", out);
        } else if !self.s.enable_var.is_empty() && key == self.s.enable_var {
            handled = self.able(sval, "enable", out);
        }
        if !handled {
            self.notes
                .push(Note::Warning(format!("Unhandled Mail: {key}")));
        }
    }

    /// After a batch of mail: the mail flags it raised (MOOS posts them at the end of
    /// `OnNewMail`, macros expanded then).
    pub fn end_mail(&mut self, out: &mut Vec<Post>) {
        let flags = std::mem::take(&mut self.pending_flags);
        self.post_flags(&flags, out);
    }

    /// The mail flags of `key` (or of `@ANY`), kept for [`ObstacleMgr::end_mail`].
    fn mail_flag(&mut self, key: &str, now: f64) -> bool {
        let flags = match self
            .mail_flags
            .get(key)
            .or_else(|| self.mail_flags.get("ANY"))
        {
            Some(f) => f.clone(),
            None => return false,
        };
        self.mail_total += 1;
        let cnt = {
            let c = self.mail_total_by_key.entry(key.to_string()).or_insert(0);
            *c += 1;
            *c
        };
        let expanded: Vec<Flag> = flags
            .into_iter()
            .map(|mut f| {
                if let Value::String(s) = &f.value {
                    let mut t = macro_expand(s, "CNT", &cnt.to_string());
                    t = macro_expand(&t, "MCNT", &self.mail_total.to_string());
                    t = macro_expand(&t, "UTC", &compact_string(now, 2));
                    f.value = Value::String(t.into());
                }
                f
            })
            .collect();
        let room = 1000usize.saturating_sub(self.pending_flags.len());
        self.pending_flags.extend(expanded.into_iter().take(room));
        true
    }

    /// A `TRACKED_FEATURE` point: `x=..,y=..,key=..` (or `label=`), optional `vsource`.
    fn new_point(&mut self, s: &str, now: f64) -> bool {
        let (mut xs, mut ys, mut key, mut vsource) = ("", "", "", "");
        for piece in parse_string(s, ',') {
            let (p, v) = piece.split_once('=').unwrap_or((piece, ""));
            match p.trim() {
                "x" => xs = v.trim(),
                "y" => ys = v.trim(),
                "vsource" => vsource = v.trim(),
                "key" | "label" => key = v.trim(),
                _ => {}
            }
        }
        if xs.is_empty() || ys.is_empty() || key.is_empty() || vsource.contains(char::is_whitespace)
        {
            self.points_invalid += 1;
            self.notes.push(Note::Warning(format!("Invalid point:{s}")));
            return false;
        }
        let (x, y) = (geometry::atof(xs), geometry::atof(ys));
        if self.s.ignore_range > 0.0 && (self.nav.0 - x).hypot(self.nav.1 - y) > self.s.ignore_range
        {
            self.points_ignored += 1;
            return true;
        }
        self.points_total += 1;
        let max = self.s.max_pts_per_cluster;
        let ob = self.obstacles.entry(key.to_string()).or_default();
        ob.max_points = max;
        ob.add_point(SensedPoint { x, y, time: now });
        ob.changed = true;
        ob.vsource = vsource.to_string();
        self.obstacles_ever += 1;
        true
    }

    /// A given obstacle from mail (`from_mail`) or from the block.
    fn given(&mut self, s: &str, from_mail: bool, now: f64, out: &mut Vec<Post>) -> bool {
        if from_mail {
            self.given_mail_ever += 1;
        }
        let Some(poly) = Self::read_given(s) else {
            return false;
        };
        let dur_str = tok_string_parse(s, "duration");
        let duration = if is_number(dur_str) {
            geometry::atof(dur_str)
        } else {
            -1.0
        };
        if from_mail {
            if self.s.given_max_duration > 0.0 {
                if dur_str.is_empty() {
                    self.notes.push(Note::Warning(
                        "Incoming GIVEN_OBSTACLE has missing duration".into(),
                    ));
                    self.notes.push(Note::Warning(s.to_string()));
                    return false;
                }
                if duration > self.s.given_max_duration {
                    self.notes.push(Note::Warning(
                        "Incoming GIVEN_OBSTACLE has duration exceeding max duration".into(),
                    ));
                    return false;
                }
            }
            self.given_mail_good += 1;
        }
        let key = poly.label.clone();
        if self.obstacles.get(&key).is_some_and(|o| !o.is_given()) {
            self.notes.push(Note::Warning(
                "Reject given obst: already known as data obstacle".into(),
            ));
            return false;
        }
        let vsource = poly.vsource.clone();
        let ob = self.obstacles.entry(key.clone()).or_default();
        ob.set_poly(poly);
        ob.duration = duration;
        ob.tstamp = now;
        ob.changed = true;
        ob.vsource = vsource;
        self.obstacles_ever += 1;
        let flags = self.s.new_obs_flags.clone();
        self.post_flags(&flags, out);
        let ob = &self.obstacles[&key];
        let mut info = format!(
            "given={}, duration={}",
            ob.is_given(),
            compact_string(ob.duration, 5)
        );
        if now > 0.0 {
            info.push_str(&format!(", age={}", compact_string(now - ob.tstamp, 1)));
        }
        self.notes
            .push(Note::Event(format!("new obstacle: {info}")));
        true
    }

    /// `OBM_ALERT_REQUEST = name=..,update_var=..,alert_range=..`: the one alert.
    fn alert_request(&mut self, s: &str) -> bool {
        let Some((name, var, range)) = parse_alert(s, "") else {
            return false;
        };
        self.s.alert_var = var;
        self.s.alert_name = name;
        self.s.alert_range = range;
        for ob in self.obstacles.values_mut() {
            ob.changed = true;
        }
        true
    }

    /// Mail on the disable/enable/expunge variable: `BHV_ABLE_FILTER`.
    fn able(&mut self, s: &str, action: &str, out: &mut Vec<Post>) -> bool {
        let mut id = String::new();
        let msg = if !s.contains('=') && !s.contains(',') {
            format!("obstacle_id={s}")
        } else {
            id = tok_string_parse(s, "obstacle_id").to_string();
            if !id.is_empty() {
                format!("obstacle_id={id}")
            } else {
                let vsource = tok_string_parse(s, "vsource");
                if vsource.is_empty() {
                    String::new()
                } else {
                    format!("vsource={vsource}")
                }
            }
        };
        if msg.is_empty() {
            return false;
        }
        out.push(Post::text(
            "BHV_ABLE_FILTER",
            format!("{msg},action={action}"),
        ));
        if !id.is_empty() {
            let move_front = |list: &mut VecDeque<String>, max: usize| {
                list.retain(|x| *x != id);
                list.push_front(id.clone());
                if list.len() > max {
                    list.pop_back();
                }
            };
            match action {
                "enable" => {
                    self.disabled.retain(|x| *x != id);
                    move_front(&mut self.enabled, 250);
                }
                "disable" => {
                    self.enabled.retain(|x| *x != id);
                    move_front(&mut self.disabled, 250);
                }
                _ => {
                    self.obstacles.remove(&id);
                    move_front(&mut self.expunged, 50);
                }
            }
        }
        true
    }

    /// `$[RECENT_DISABLED]`, `$[RECENT_ENABLED]`, `$[TOTAL_DISABLED]`, `$[ALL_DISABLED]`,
    /// `$[OBS_NOW]`, `$[OBS_EVER]`.
    fn expand_macros(&self, s: &str) -> String {
        let mut s = expand_able_macros(s, &self.disabled, &self.enabled, macro_expand);
        s = macro_expand(&s, "OBS_NOW", &self.obstacles.len().to_string());
        macro_expand(&s, "OBS_EVER", &self.obstacles_ever.to_string())
    }

    fn post_flags(&mut self, flags: &[Flag], out: &mut Vec<Post>) {
        for f in flags {
            match &f.value {
                Value::String(s) => {
                    let v = self.expand_macros(s.trim());
                    if !v.is_empty() {
                        out.push(Post::text(f.var.as_str(), v.as_str()));
                    }
                    self.notes.push(Note::Event(format!("{}={v}", f.var)));
                }
                v => {
                    let d = v.as_ref().as_f64().unwrap_or(0.0);
                    out.push(Post::double(f.var.as_str(), d));
                    self.notes
                        .push(Note::Event(format!("{}={}", f.var, compact_string(d, 4))));
                }
            }
        }
    }

    /// One iteration (MOOS `Iterate`).
    pub fn iterate(&mut self, now: f64, out: &mut Vec<Post>) {
        self.manage_memory(now, out);
        self.update_point_hulls(out);
        self.update_ranges(out);
        self.post_alerts(out);
    }

    fn manage_memory(&mut self, now: f64, out: &mut Vec<Post>) {
        let max_age = self.s.max_age_per_point;
        let forget: Vec<String> = self
            .obstacles
            .iter_mut()
            .filter_map(|(k, o)| {
                let remove = o.prune_by_age(max_age, now);
                (remove || !o.poly.active).then(|| k.clone())
            })
            .collect();
        for key in forget {
            let ob = self.obstacles.remove(&key).expect("listed");
            if self.s.post_view_polys {
                out.push(Post::text("VIEW_POLYGON", ob.poly.spec_inactive()));
            }
            out.push(Post::text("OBM_RESOLVED", key.as_str()));
            self.alerts_resolved += 1;
            self.notes.push(Note::Event(format!("OBM_RESOLVED={key}")));
            self.obstacles_released += 1;
        }
    }

    /// The hull (or lasso) of a point obstacle.
    fn point_poly(&mut self, key: &str) -> Polygon {
        let pts: Vec<Point> = self.obstacles[key]
            .points
            .iter()
            .map(|p| Point::new(p.x, p.y))
            .collect();
        let poly = if self.s.lasso {
            self.notes.push(Note::Event("gen_lasso".into()));
            let n = pts.len() as f64;
            let cx = pts.iter().map(|p| p.x).sum::<f64>() / n;
            let cy = pts.iter().map(|p| p.y).sum::<f64>() / n;
            // The C++ writes the centre and radius with two decimals and reads them back.
            let two = |v: f64| {
                let mut s = String::new();
                fixed(&mut s, v, 2);
                geometry::atof(&s)
            };
            Radial {
                x: two(cx),
                y: two(cy),
                z: 0.0,
                radius: two(self.s.lasso_radius),
                pts: self.s.lasso_points,
                snap: 0.01,
            }
            .polygon()
            .unwrap_or_default()
        } else {
            hull::convex_hull(&pts)
        };
        if poly.is_convex() {
            return poly;
        }
        self.notes.push(Note::Warning(format!(
            "hull failure - Placeholder needed {}",
            poly.len()
        )));
        // An octagon around the points' mean, as far out as the farthest point (0.5 m at
        // least), written with six significant digits and read back as the C++ does.
        let n = pts.len() as f64;
        let cx = pts.iter().map(|p| p.x).sum::<f64>() / n;
        let cy = pts.iter().map(|p| p.y).sum::<f64>() / n;
        let r = pts
            .iter()
            .map(|p| (p.x - cx).hypot(p.y - cy))
            .fold(0.0, f64::max)
            .max(0.5);
        let spec = format!(
            "format=radial, x={},y={},radius={},pts=8",
            g_string(cx, 6),
            g_string(cy, 6),
            g_string(r, 6)
        );
        geometry::spec::parse_polygon(&spec)
            .map(|v| v.polygon)
            .unwrap_or_default()
    }

    fn update_point_hulls(&mut self, out: &mut Vec<Post>) {
        let n = self.obstacles.len();
        let (label_over, shade_over, vertex_over) = (
            n > self.s.poly_label_thresh,
            n > self.s.poly_shade_thresh,
            n > self.s.poly_vertex_thresh,
        );
        let crossed = label_over != self.label_over
            || shade_over != self.shade_over
            || vertex_over != self.vertex_over;
        (self.label_over, self.shade_over, self.vertex_over) =
            (label_over, shade_over, vertex_over);
        let keys: Vec<String> = self.obstacles.keys().cloned().collect();
        for key in keys {
            let ob = &self.obstacles[&key];
            if (!ob.changed && !crossed) || ob.points.is_empty() {
                continue;
            }
            let poly = self.point_poly(&key);
            let label = format!("obmgr_{key}");
            self.obstacles
                .get_mut(&key)
                .expect("listed")
                .set_poly(ObPoly {
                    poly: poly.clone(),
                    label: label.clone(),
                    vsource: String::new(),
                    active: true,
                    duration: None,
                });
            if self.s.post_view_polys {
                let c = &self.s.obstacles_color;
                let mut v = geometry::ViewPolygon::new(poly);
                v.precision = 5;
                v.attrs.label = label;
                if label_over {
                    v.attrs.label_color = Some("invisible".into());
                }
                if shade_over {
                    v.attrs.fill_color = Some("invisible".into());
                } else {
                    v.attrs.fill_color = Some(c.clone());
                    v.attrs.fill_transparency = Some(0.15);
                }
                if vertex_over {
                    v.attrs.vertex_color = Some("invisible".into());
                    v.attrs.vertex_size = Some(0.0);
                } else {
                    v.attrs.vertex_color = Some(c.clone());
                    v.attrs.vertex_size = Some(3.0);
                }
                v.attrs.edge_color = Some(c.clone());
                v.attrs.edge_size = Some(1.0);
                out.push(Post::text("VIEW_POLYGON", v.to_spec()));
            }
        }
    }

    fn update_ranges(&mut self, out: &mut Vec<Post>) {
        let (x, y) = self.nav;
        let alert_range = self.s.alert_range;
        for ob in self.obstacles.values_mut() {
            let range = dist_to_poly(&ob.poly.poly, x, y);
            if self.min_dist_ever < 0.0 || range < self.min_dist_ever {
                self.min_dist_ever = range;
                out.push(Post::double("OBM_MIN_DIST_EVER", range));
            }
            if ob.range > alert_range && range <= alert_range {
                ob.changed = true;
            }
            ob.set_range(range);
        }
    }

    fn post_alerts(&mut self, out: &mut Vec<Post>) {
        if self.s.alert_var.is_empty() {
            return;
        }
        let (x, y) = self.nav;
        let keys: Vec<String> = self.obstacles.keys().cloned().collect();
        for key in keys {
            let ob = &self.obstacles[&key];
            if !ob.poly.poly.is_convex() {
                continue;
            }
            let dist = dist_to_poly(&ob.poly.poly, x, y);
            let close = dist <= self.s.alert_range;
            let post_dist = match self.s.post_dist_to_polys.as_str() {
                "true" => true,
                "close" => close,
                _ => false,
            };
            if post_dist {
                let mut d = String::new();
                fixed(&mut d, dist, 1);
                out.push(Post::text(
                    "OBM_DIST_TO_OBJ",
                    format!("{},{d}", key.to_ascii_uppercase()),
                ));
            }
            if !ob.changed {
                continue;
            }
            let ob = self.obstacles.get_mut(&key).expect("listed");
            ob.changed = false;
            ob.updates_total += 1;
            if close {
                let (var, name) = (self.s.alert_var.clone(), self.s.alert_name.clone());
                self.post_alert(&key, &var, &name, out);
            }
            if dist <= self.s.gen_alert_range {
                let (var, name) = (self.s.gen_alert_var.clone(), self.s.gen_alert_name.clone());
                self.post_alert(&key, &var, &name, out);
            }
        }
    }

    fn post_alert(&mut self, key: &str, var: &str, name: &str, out: &mut Vec<Post>) {
        let ob = &self.obstacles[key];
        let mut s = format!("name={name}{key}#poly={},label={key}", ob.poly.spec_pts(5));
        if !ob.vsource.is_empty() {
            s.push_str(",vsource=");
            s.push_str(&ob.vsource);
        }
        s.push_str("#id=");
        s.push_str(key);
        self.alerts_posted += 1;
        out.push(Post::text(var, s.as_str()));
        self.notes.push(Note::Event(format!("{var}={s}")));
    }

    /// Takes the appcast events and warnings gathered since the last call.
    pub fn take_notes(&mut self) -> Vec<Note> {
        std::mem::take(&mut self.notes)
    }

    /// The obstacles' keys, in key order.
    pub fn obstacles(&self) -> impl Iterator<Item = &str> + '_ {
        self.obstacles.keys().map(String::as_str)
    }

    /// The polygon of obstacle `key` (its vertices), if it has one.
    pub fn polygon(&self, key: &str) -> Option<&Polygon> {
        self.obstacles.get(key).map(|o| &o.poly.poly)
    }

    /// The appcast body (MOOS `buildReport`).
    pub fn report(&self, b: &mut String, now: f64) {
        use std::fmt::Write as _;
        let s = &self.s;
        let x1 = |v: f64| compact_string(v, 1);
        let _ = writeln!(b, "Configuration (point handling):             ");
        let _ = writeln!(b, "  point_var:    {}", s.point_var);
        let _ = writeln!(b, "  max_pts_per_cluster: {}", s.max_pts_per_cluster);
        let _ = writeln!(
            b,
            "  max_age_per_point:   {}",
            compact_string(s.max_age_per_point, 5)
        );
        let _ = writeln!(b, "  ignore_range:        {}", x1(s.ignore_range));
        let _ = writeln!(b, "Configuration (given_obstacles):            ");
        let _ = writeln!(
            b,
            "  given_max_duration: {}",
            g_string(s.given_max_duration, 6)
        );
        let _ = writeln!(b, "Configuration (viewing):                    ");
        let _ = writeln!(b, "  post_dist_to_polys: {}", s.post_dist_to_polys);
        let _ = writeln!(b, "  post_view_polys:    {}", s.post_view_polys);
        let _ = writeln!(b, "  obstacle color:     {}", s.obstacles_color);
        let _ = writeln!(b, "Configuration (alerts):                     ");
        let _ = writeln!(b, "  alert_var:   {}", s.alert_var);
        let _ = writeln!(b, "  alert_name:  {}", s.alert_name);
        let _ = writeln!(b, "  alert_range: {}", x1(s.alert_range));
        let _ = writeln!(b, "Configuration (general alert):              ");
        let _ = writeln!(b, "  gen_alert_var:   {}", s.gen_alert_var);
        let _ = writeln!(b, "  gen_alert_name:  {}", s.gen_alert_name);
        let _ = writeln!(b, "  gen_alert_range: {}", x1(s.gen_alert_range));
        let _ = writeln!(b, "Configuration (lasso option):               ");
        let _ = writeln!(b, "  lasso:        {}", s.lasso);
        let _ = writeln!(b, "  lasso_points: {}", s.lasso_points);
        let _ = writeln!(b, "  lasso_radius: {}", compact_string(s.lasso_radius, 5));
        let _ = writeln!(b, "============================================");
        let _ = writeln!(b, "State: (Nav)                                ");
        let _ = writeln!(
            b,
            "  Nav Position:      ({},{})",
            x1(self.nav.0),
            x1(self.nav.1)
        );
        let _ = writeln!(b, "State: (points):                            ");
        let _ = writeln!(b, "  Points Received:   {}", self.points_total);
        let _ = writeln!(b, "  Points Invalid:    {}", self.points_invalid);
        let _ = writeln!(b, "  Points Ignored:    {}", self.points_ignored);
        let _ = writeln!(b, "State: (given_obstacles):                   ");
        let _ = writeln!(b, "  Given Obstacles (mail) ever: {}", self.given_mail_ever);
        let _ = writeln!(b, "  Given Obstacles (mail) good: {}", self.given_mail_good);
        let _ = writeln!(
            b,
            "  Given Obstacles (config):    {}",
            self.given_config_ever
        );
        let _ = writeln!(b, "State: (obstacles):                         ");
        let _ = writeln!(b, "  Obstacles:          {}", self.obstacles.len());
        let _ = writeln!(b, "  Obstacles released: {}", self.obstacles_released);
        let _ = writeln!(b, "  Closest range ever: {}", x1(self.min_dist_ever));
        let _ = writeln!(b, "State: (alerts):                            ");
        let _ = writeln!(b, "  Alerts Posted:   {}", self.alerts_posted);
        let _ = writeln!(b, "  Alerts Resolved: {}", self.alerts_resolved);
        let _ = writeln!(b, "\n");
        let mut t = appcast::Table::new(9);
        t.push("    |     |       | Up    |      | Dur   | Time2 | Curr | Min ");
        t.push("Key | Pts | Verts | Dates | Type | ation | Live  | Dist | Dist");
        t.add_header_lines();
        for (key, o) in &self.obstacles {
            let (mut dur, mut ttl) = ("n/a".to_string(), "n/a".to_string());
            if o.is_given() && o.duration > 0.0 {
                dur = x1(o.duration);
                ttl = x1(o.time_to_live(now));
            }
            let (mut rng, mut min) = (String::new(), String::new());
            fixed(&mut rng, o.range, 1);
            fixed(&mut min, o.min_range, 1);
            t.push(key);
            t.push(&o.points.len().to_string());
            t.push(&o.poly.poly.len().to_string());
            t.push(&o.updates_total.to_string());
            t.push(if o.is_given() { "given" } else { "points" });
            t.push(&dur);
            t.push(&ttl);
            t.push(&rng);
            t.push(&min);
        }
        t.write(b);
        let _ = writeln!(b, "\n");
    }
}

/// The `pObstacleMgr` app: the core hosted with its name, block, warnings and appcast.
pub type ObstacleMgrApp = Hosted<ObstacleMgr>;

impl Hosted<ObstacleMgr> {
    /// The app `name` from its block; each bad line is a configuration warning at its line.
    pub fn new(name: &str, block: ProcessConfig) -> Self {
        let (mut core, _) = ObstacleMgr::new(&[]);
        let mut warnings = Vec::new();
        for p in &block.entries {
            let (k, v) = config_line(&p.key, &p.value);
            if let Err(msg) = core.configure(&k, &v) {
                for m in msg.split('\n') {
                    warnings.push(Diagnostic::line_warning(
                        DiagnosticKind::AppSetting,
                        &p.span,
                        format!("{PROGRAM}: {m}"),
                    ));
                }
            }
        }
        core.finish_config();
        Hosted::host(name, block, warnings, core)
    }
}

impl AppCore for ObstacleMgr {
    fn subscriptions(&self) -> Vec<Subscription> {
        ObstacleMgr::subscriptions(self)
            .into_iter()
            .map(Subscription::var)
            .collect()
    }

    fn on_startup(&mut self, now: f64, out: &mut Vec<Post>, notes: &mut Vec<Note>) {
        ObstacleMgr::on_startup(self, now, out);
        notes.append(&mut self.notes);
    }

    fn on_mail(&mut self, m: &Mail, now: f64, out: &mut Vec<Post>, notes: &mut Vec<Note>) {
        ObstacleMgr::on_mail(self, &m.key, &m.value, now, out);
        notes.append(&mut self.notes);
    }

    fn mail_done(&mut self, _now: f64, out: &mut Vec<Post>, notes: &mut Vec<Note>) {
        self.end_mail(out);
        notes.append(&mut self.notes);
    }

    fn iterate(&mut self, now: f64, out: &mut Vec<Post>, notes: &mut Vec<Note>) {
        ObstacleMgr::iterate(self, now, out);
        notes.append(&mut self.notes);
    }

    fn report(&self, now: f64, body: &mut String) {
        ObstacleMgr::report(self, body, now);
    }
}

#[cfg(test)]
mod tests;
