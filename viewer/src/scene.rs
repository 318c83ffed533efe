//! The scene a viewer page draws, built from MOOS mail; pure (time is an argument).
//!
//! - Vehicles from `NODE_REPORT` / `NODE_REPORT_LOCAL` (read by [`helm::ledger::NodeReport`]),
//!   each with a trail of at most [`SceneConfig::trail_max`] points. As pMarineViewer does, a
//!   vehicle whose last report arrived (viewer time, not the report's `TIME`) more than
//!   [`SceneConfig::stale_after_s`] ago is stale (greyed), and one silent for that plus
//!   [`SceneConfig::remove_after_s`] is removed. Each vehicle also keeps its depth and
//!   speed over the last [`SceneConfig::history_s`] seconds (points a second apart, and the newest) for
//!   the page's strip chart, so a page opened mid-run charts what came before it.
//! - Every `VIEW_*` object, keyed by kind and label: a new one with the same label replaces the
//!   old, `active=false` removes it, a positive `duration` expires it. Points, polygons and
//!   seglists are read by `geometry::spec`; circles, markers, vectors, arrows and pulses are
//!   kept as their `key=value` fields (numbers as JSON numbers) for the page to draw.
//!   Unlabelled objects each get their own key; at most [`SceneConfig::max_unlabeled`] of
//!   each kind are kept (oldest dropped). Range and comms pulses carry `t0`, their start
//!   (their `time=`, else when they came), and always a `duration` (pMarineViewer's 15 s
//!   and 3 s when not given): the page grows and fades them from `t0` as pMarineViewer
//!   does, and the scene drops them after `duration` (plus a range pulse's `linger`).
//! - Colours (`edge_color`, `vertex_color`, `fill_color`, `label_color`, a marker's `color`,
//!   `primary_color`, `secondary_color`, a report's `COLOR`) are read as MOOS reads them
//!   (`geometry::color`: names with or without `_`, `greyNN`, `hex:`, fractions) and handed
//!   to the page as CSS `#rrggbb`; `off`, `empty` and `invisible` as `transparent` (not
//!   drawn); what MOOS cannot read is passed on as written.
//! - The latest `APPCAST` per node and app.
//! - The mission's pMarineViewer buttons (`mission::buttons`).
//!
//! Every change bumps a version; [`Scene::snapshot`] is the whole scene as one JSON message
//! and [`Scene::delta_since`] the changes after a version, with the newest state of each
//! changed item only, so a slow client that asks rarely gets fewer, larger frames and never
//! the intermediate ones. Removals are remembered as tombstones (a bounded number); a client
//! older than the oldest tombstone kept gets a snapshot instead.
//!
//! Messages (`type` first):
//! - `{"type":"snapshot","version":v,"now":t,"trail_max":n,"stale_after":s,"vehicles":[..],"shapes":[..],"appcasts":[..],"buttons":[..]}`
//! - `{"type":"delta","version":v,"now":t,"vehicles":[..],"shapes":[..],"appcasts":[..],"removed_vehicles":[name..],"removed_shapes":[[kind,key]..]}`
//!
//! A vehicle is `{"name","type","color","x","y","heading","speed","depth","mode","allstop","helm","received","stale"}`
//! plus `"trail":[[x,y]..]` and `"history":[[t,depth,speed]..]` in a snapshot, or
//! `"trail_add":[[x,y]..]` (points after the client's version; the page appends and keeps
//! the last `trail_max`) in a delta. A shape is
//! `{"kind","key","label",...fields}`; an appcast `{"node","app","iteration","cfg_warnings","run_warnings","report"}`;
//! a button `{"label","key","postings":[[var,value]..]}`.

use std::collections::{BTreeMap, VecDeque};

use appcast::AppCast;
use geometry::spec::{Attributes, parse_point, parse_polygon, parse_seglist};
use helm::ledger::NodeReport;
use mission::buttons::{Button, ButtonValue};
use serde_json::{Map, Value as Json, json};

/// Limits and thresholds of a [`Scene`].
#[derive(Debug, Clone, PartialEq)]
pub struct SceneConfig {
    /// Most trail points kept per vehicle.
    pub trail_max: usize,
    /// Seconds without a report after which a vehicle is stale (pMarineViewer's
    /// `stale_report_thresh`, default 60).
    pub stale_after_s: f64,
    /// Seconds after going stale at which a vehicle is removed (`stale_remove_thresh`, 180).
    pub remove_after_s: f64,
    /// Most unlabelled objects kept per kind.
    pub max_unlabeled: usize,
    /// Removals remembered for deltas.
    pub max_tombstones: usize,
    /// Seconds of depth and speed kept per vehicle for the strip chart.
    pub history_s: f64,
}

impl Default for SceneConfig {
    fn default() -> Self {
        SceneConfig {
            trail_max: 300,
            stale_after_s: 60.0,
            remove_after_s: 180.0,
            max_unlabeled: 500,
            max_tombstones: 4096,
            history_s: 300.0,
        }
    }
}

/// The kinds of `VIEW_*` objects the scene keeps.
#[derive(Debug, Clone, Copy, PartialEq, Eq, PartialOrd, Ord, Hash)]
pub enum ShapeKind {
    /// `VIEW_POINT`.
    Point,
    /// `VIEW_POLYGON`.
    Polygon,
    /// `VIEW_SEGLIST`.
    SegList,
    /// `VIEW_CIRCLE`.
    Circle,
    /// `VIEW_MARKER` (or `MARKER`).
    Marker,
    /// `VIEW_VECTOR`.
    Vector,
    /// `VIEW_ARROW`.
    Arrow,
    /// `VIEW_RANGE_PULSE`.
    RangePulse,
    /// `VIEW_COMMS_PULSE`.
    CommsPulse,
}

impl ShapeKind {
    /// Every kind with its MOOS variable.
    pub const ALL: [(ShapeKind, &'static str); 9] = [
        (ShapeKind::Point, "VIEW_POINT"),
        (ShapeKind::Polygon, "VIEW_POLYGON"),
        (ShapeKind::SegList, "VIEW_SEGLIST"),
        (ShapeKind::Circle, "VIEW_CIRCLE"),
        (ShapeKind::Marker, "VIEW_MARKER"),
        (ShapeKind::Vector, "VIEW_VECTOR"),
        (ShapeKind::Arrow, "VIEW_ARROW"),
        (ShapeKind::RangePulse, "VIEW_RANGE_PULSE"),
        (ShapeKind::CommsPulse, "VIEW_COMMS_PULSE"),
    ];

    /// The kind a MOOS variable carries (`MARKER` is `VIEW_MARKER`, as in pMarineViewer).
    pub fn from_var(var: &str) -> Option<ShapeKind> {
        if var == "MARKER" {
            return Some(ShapeKind::Marker);
        }
        ShapeKind::ALL
            .iter()
            .find(|(_, v)| *v == var)
            .map(|(k, _)| *k)
    }

    /// The name used in the JSON messages (`polygon`, `range_pulse`, ...).
    pub fn name(self) -> &'static str {
        match self {
            ShapeKind::Point => "point",
            ShapeKind::Polygon => "polygon",
            ShapeKind::SegList => "seglist",
            ShapeKind::Circle => "circle",
            ShapeKind::Marker => "marker",
            ShapeKind::Vector => "vector",
            ShapeKind::Arrow => "arrow",
            ShapeKind::RangePulse => "range_pulse",
            ShapeKind::CommsPulse => "comms_pulse",
        }
    }
}

/// One vehicle as last reported.
#[derive(Debug, Clone, PartialEq)]
pub struct Vehicle {
    /// The report as read.
    pub report: NodeReport,
    /// Viewer time the last report arrived, seconds.
    pub received: f64,
    /// Greyed: no report for longer than the stale threshold.
    pub stale: bool,
    trail: VecDeque<(f64, f64, u64)>,
    history: VecDeque<[f64; 3]>,
    changed: u64,
}

impl Vehicle {
    /// Depth and speed over time for the strip chart, oldest first: `[time, depth, speed]`
    /// (a missing value as 0, as the page charts it).
    pub fn history(&self) -> impl Iterator<Item = [f64; 3]> + '_ {
        self.history.iter().copied()
    }

    /// The trail, oldest first.
    pub fn trail(&self) -> impl Iterator<Item = (f64, f64)> + '_ {
        self.trail.iter().map(|&(x, y, _)| (x, y))
    }

    /// The helm's state read from the report's MODE: `NOHELM` for `NOHELM-*`, the state
    /// itself for `DRIVE`, `PARK`, `MALCONFIG`, `STANDBY`, `DISABLED` (and `+` forms), `DRIVE`
    /// for a modes string (pNodeReporter posts modes only while driving), empty when absent.
    pub fn helm_state(&self) -> &str {
        let m = self.report.mode.as_str();
        if m.starts_with("NOHELM") {
            "NOHELM"
        } else if matches!(
            m,
            "DRIVE" | "DRIVE+" | "PARK" | "PARK+" | "MALCONFIG" | "STANDBY" | "DISABLED" | ""
        ) {
            m
        } else {
            "DRIVE"
        }
    }

    fn to_json(&self, trail_since: Option<u64>) -> Json {
        let r = &self.report;
        let mut o = json!({
            "name": r.name,
            "type": r.vtype,
            "color": if r.color.is_empty() { String::new() } else { css_color(&r.color) },
            "x": r.x_m,
            "y": r.y_m,
            "heading": r.heading_deg,
            "speed": r.speed_mps,
            "depth": r.depth_m,
            "mode": r.mode,
            "allstop": r.allstop,
            "helm": self.helm_state(),
            "received": self.received,
            "stale": self.stale,
        });
        let pts = |since: u64| -> Json {
            Json::Array(
                self.trail
                    .iter()
                    .filter(|p| p.2 > since)
                    .map(|&(x, y, _)| json!([x, y]))
                    .collect(),
            )
        };
        match trail_since {
            None => {
                o["trail"] = pts(0);
                o["history"] = json!(self.history);
            }
            Some(v) => o["trail_add"] = pts(v),
        }
        o
    }
}

/// One `VIEW_*` object.
#[derive(Debug, Clone, PartialEq)]
pub struct Shape {
    /// Its kind.
    pub kind: ShapeKind,
    /// Its label (empty for an unlabelled object).
    pub label: String,
    /// What the page draws: `pts` for points, polygons and seglists, the colours and sizes,
    /// or every field of the other kinds.
    pub fields: Map<String, Json>,
    /// Viewer time after which it is dropped (a positive `duration`).
    pub expires: Option<f64>,
    changed: u64,
}

/// The latest appcast of one app.
#[derive(Debug, Clone, PartialEq)]
pub struct AppcastEntry {
    /// The appcast as parsed.
    pub cast: AppCast,
    changed: u64,
}

/// Why a piece of mail was not taken into the scene.
#[derive(Debug, Clone, PartialEq)]
pub enum Rejected {
    /// The variable is not one the scene reads.
    NotViewed,
    /// A node report without a NAME.
    NoName,
    /// A `VIEW_*` string that does not parse.
    BadShape(String),
}

/// The scene: vehicles, `VIEW_*` objects, appcasts, buttons.
#[derive(Debug, Clone)]
pub struct Scene {
    config: SceneConfig,
    version: u64,
    now: f64,
    vehicles: BTreeMap<String, Vehicle>,
    shapes: BTreeMap<(ShapeKind, String), Shape>,
    unlabeled: BTreeMap<ShapeKind, VecDeque<String>>,
    unlabeled_count: u64,
    appcasts: BTreeMap<(String, String), AppcastEntry>,
    buttons: Vec<Button>,
    tombstones: VecDeque<(u64, Tomb)>,
    /// Oldest version a delta can start from (tombstones before it were dropped).
    horizon: u64,
}

#[derive(Debug, Clone, PartialEq)]
enum Tomb {
    Vehicle(String),
    Shape(ShapeKind, String),
}

/// The MOOS variables a viewer registers for.
pub fn viewed_variables() -> Vec<&'static str> {
    let mut v = vec!["NODE_REPORT", "NODE_REPORT_LOCAL", "APPCAST", "MARKER"];
    v.extend(ShapeKind::ALL.iter().map(|(_, var)| *var));
    v
}

impl Scene {
    /// An empty scene with the mission's buttons.
    pub fn new(config: SceneConfig, buttons: Vec<Button>) -> Scene {
        Scene {
            config,
            version: 0,
            now: 0.0,
            vehicles: BTreeMap::new(),
            shapes: BTreeMap::new(),
            unlabeled: BTreeMap::new(),
            unlabeled_count: 0,
            appcasts: BTreeMap::new(),
            buttons,
            tombstones: VecDeque::new(),
            horizon: 0,
        }
    }

    /// The version of the newest change.
    pub fn version(&self) -> u64 {
        self.version
    }

    /// The vehicles by name.
    pub fn vehicles(&self) -> &BTreeMap<String, Vehicle> {
        &self.vehicles
    }

    /// The object of `kind` labelled `label`.
    pub fn shape(&self, kind: ShapeKind, label: &str) -> Option<&Shape> {
        self.shapes.get(&(kind, label.to_string()))
    }

    /// How many objects the scene holds.
    pub fn shape_count(&self) -> usize {
        self.shapes.len()
    }

    /// The latest appcast of `app` on `node`.
    pub fn appcast(&self, node: &str, app: &str) -> Option<&AppCast> {
        self.appcasts
            .get(&(node.to_string(), app.to_string()))
            .map(|e| &e.cast)
    }

    /// The nodes that have sent a report or an appcast.
    pub fn nodes(&self) -> Vec<String> {
        let mut n: Vec<String> = self.vehicles.keys().cloned().collect();
        n.extend(self.appcasts.keys().map(|(node, _)| node.clone()));
        n.sort();
        n.dedup();
        n
    }

    /// The mission's buttons.
    pub fn buttons(&self) -> &[Button] {
        &self.buttons
    }

    fn bump(&mut self) -> u64 {
        self.version += 1;
        self.version
    }

    fn bury(&mut self, tomb: Tomb) {
        let v = self.bump();
        self.tombstones.push_back((v, tomb));
        while self.tombstones.len() > self.config.max_tombstones {
            if let Some((v, _)) = self.tombstones.pop_front() {
                self.horizon = v;
            }
        }
    }

    /// Takes one piece of mail (a string value `value` of `var`) at viewer time `now`.
    pub fn apply(&mut self, var: &str, value: &str, now: f64) -> Result<(), Rejected> {
        self.now = self.now.max(now);
        match var {
            "NODE_REPORT" | "NODE_REPORT_LOCAL" => self.node_report(value, now),
            "APPCAST" => {
                let cast = AppCast::parse(value);
                let key = (cast.node_name().to_string(), cast.proc_name().to_string());
                let changed = self.bump();
                self.appcasts.insert(key, AppcastEntry { cast, changed });
                Ok(())
            }
            _ => match ShapeKind::from_var(var) {
                Some(kind) => self.view(kind, value, now),
                None => Err(Rejected::NotViewed),
            },
        }
    }

    fn node_report(&mut self, value: &str, now: f64) -> Result<(), Rejected> {
        let report = NodeReport::parse(value);
        if report.name.is_empty() {
            return Err(Rejected::NoName);
        }
        let v = self.bump();
        let trail_max = self.config.trail_max;
        let veh = self
            .vehicles
            .entry(report.name.clone())
            .or_insert_with(|| Vehicle {
                report: NodeReport::default(),
                received: now,
                stale: false,
                trail: VecDeque::new(),
                history: VecDeque::new(),
                changed: v,
            });
        if let (Some(x), Some(y)) = (report.x_m, report.y_m) {
            veh.trail.push_back((x, y, v));
            while veh.trail.len() > trail_max {
                veh.trail.pop_front();
            }
        }
        if report.depth_m.is_some() || report.speed_mps.is_some() {
            // Points a second apart at least, and the newest always: the last point goes
            // when it is less than a second after the one before it.
            let n = veh.history.len();
            if n >= 2 && veh.history[n - 1][0] - veh.history[n - 2][0] < 1.0 {
                veh.history.pop_back();
            }
            let point = [
                now,
                report.depth_m.unwrap_or(0.0),
                report.speed_mps.unwrap_or(0.0),
            ];
            veh.history.push_back(point);
            while veh
                .history
                .front()
                .is_some_and(|p| p[0] < now - self.config.history_s)
            {
                veh.history.pop_front();
            }
        }
        veh.report = report;
        veh.received = now;
        veh.stale = false;
        veh.changed = v;
        Ok(())
    }

    fn view(&mut self, kind: ShapeKind, value: &str, now: f64) -> Result<(), Rejected> {
        let (attrs, mut fields) = match kind {
            ShapeKind::Point => {
                let p = parse_point(value).map_err(|e| Rejected::BadShape(e.to_string()))?;
                let mut f = Map::new();
                f.insert("x".into(), json!(p.point.x));
                f.insert("y".into(), json!(p.point.y));
                (p.attrs, f)
            }
            ShapeKind::Polygon => {
                let p = parse_polygon(value).map_err(|e| Rejected::BadShape(e.to_string()))?;
                (p.attrs, pts_field(p.polygon.vertices()))
            }
            ShapeKind::SegList => {
                let s = parse_seglist(value).map_err(|e| Rejected::BadShape(e.to_string()))?;
                (s.attrs, pts_field(s.seglist.points()))
            }
            _ => generic(value)?,
        };
        attrs_fields(&attrs, &mut fields);
        let mut key = attrs.label.clone();
        if !attrs.active {
            // `active=false` erases the object with this label (an unlabelled erase is a no-op).
            if self.shapes.remove(&(kind, key.clone())).is_some() {
                self.bury(Tomb::Shape(kind, key));
            }
            return Ok(());
        }
        if key.is_empty() {
            self.unlabeled_count += 1;
            key = format!("#{}", self.unlabeled_count);
            let q = self.unlabeled.entry(kind).or_default();
            q.push_back(key.clone());
            if q.len() > self.config.max_unlabeled {
                let old = q.pop_front().unwrap_or_default();
                if self.shapes.remove(&(kind, old.clone())).is_some() {
                    self.bury(Tomb::Shape(kind, old));
                }
            }
        }
        let mut expires = attrs.duration.filter(|d| *d > 0.0).map(|d| now + d);
        if let Some(default) = match kind {
            ShapeKind::RangePulse => Some(15.0),
            ShapeKind::CommsPulse => Some(3.0),
            _ => None,
        } {
            let t0 = attrs.time.unwrap_or(now);
            let duration = attrs.duration.unwrap_or(default);
            let linger = fields.get("linger").and_then(Json::as_f64).unwrap_or(0.0);
            fields.insert("t0".into(), json!(t0));
            fields.insert("duration".into(), json!(duration));
            expires = (duration > 0.0).then_some(t0 + duration + linger.max(0.0));
        }
        fields.insert("kind".into(), json!(kind.name()));
        fields.insert("key".into(), json!(key));
        let changed = self.bump();
        self.shapes.insert(
            (kind, key),
            Shape {
                kind,
                label: attrs.label,
                fields,
                expires,
                changed,
            },
        );
        Ok(())
    }

    /// Advances viewer time to `now`: vehicles go stale or are removed, objects expire.
    /// Call it periodically (the server does, about once a second).
    pub fn tick(&mut self, now: f64) {
        self.now = self.now.max(now);
        let (stale_after, remove_after) = (
            self.config.stale_after_s,
            self.config.stale_after_s + self.config.remove_after_s,
        );
        let gone: Vec<String> = self
            .vehicles
            .iter()
            .filter(|(_, v)| now - v.received > remove_after)
            .map(|(n, _)| n.clone())
            .collect();
        for name in gone {
            self.vehicles.remove(&name);
            self.bury(Tomb::Vehicle(name));
        }
        let turning: Vec<String> = self
            .vehicles
            .iter()
            .filter(|(_, v)| !v.stale && now - v.received > stale_after)
            .map(|(n, _)| n.clone())
            .collect();
        for name in turning {
            let v = self.bump();
            if let Some(veh) = self.vehicles.get_mut(&name) {
                veh.stale = true;
                veh.changed = v;
            }
        }
        let expired: Vec<(ShapeKind, String)> = self
            .shapes
            .iter()
            .filter(|(_, s)| s.expires.is_some_and(|t| now > t))
            .map(|(k, _)| k.clone())
            .collect();
        for (kind, key) in expired {
            self.shapes.remove(&(kind, key.clone()));
            self.bury(Tomb::Shape(kind, key));
        }
    }

    /// The whole scene as one message.
    pub fn snapshot(&self) -> Json {
        json!({
            "type": "snapshot",
            "version": self.version,
            "now": self.now,
            "trail_max": self.config.trail_max,
            "stale_after": self.config.stale_after_s,
            "vehicles": self.vehicles.values().map(|v| v.to_json(None)).collect::<Vec<_>>(),
            "shapes": self.shapes.values().map(|s| Json::Object(s.fields.clone())).collect::<Vec<_>>(),
            "appcasts": self.appcasts.values().map(appcast_json).collect::<Vec<_>>(),
            "buttons": self.buttons.iter().map(button_json).collect::<Vec<_>>(),
        })
    }

    /// What changed after version `since`: `None` when nothing did, a snapshot when `since`
    /// is older than the oldest removal remembered, else a delta.
    pub fn delta_since(&self, since: u64) -> Option<Json> {
        if since >= self.version {
            return None;
        }
        if since < self.horizon {
            return Some(self.snapshot());
        }
        let mut removed_vehicles = Vec::new();
        let mut removed_shapes = Vec::new();
        for (v, tomb) in self.tombstones.iter().rev() {
            if *v <= since {
                break;
            }
            match tomb {
                Tomb::Vehicle(n) if !self.vehicles.contains_key(n) => {
                    removed_vehicles.push(json!(n))
                }
                Tomb::Shape(k, key) if !self.shapes.contains_key(&(*k, key.clone())) => {
                    removed_shapes.push(json!([k.name(), key]))
                }
                _ => {}
            }
        }
        Some(json!({
            "type": "delta",
            "version": self.version,
            "now": self.now,
            "vehicles": self.vehicles.values().filter(|v| v.changed > since)
                .map(|v| v.to_json(Some(since))).collect::<Vec<_>>(),
            "shapes": self.shapes.values().filter(|s| s.changed > since)
                .map(|s| Json::Object(s.fields.clone())).collect::<Vec<_>>(),
            "appcasts": self.appcasts.values().filter(|a| a.changed > since)
                .map(appcast_json).collect::<Vec<_>>(),
            "removed_vehicles": removed_vehicles,
            "removed_shapes": removed_shapes,
        }))
    }
}

/// A MOOS colour as CSS (see the module docs).
pub fn css_color(moos: &str) -> String {
    let t = moos.trim();
    if matches!(
        t.to_ascii_lowercase().as_str(),
        "off" | "empty" | "invisible"
    ) {
        return "transparent".into();
    }
    match geometry::color::color_rgb(t) {
        Some(rgb) => {
            let b = rgb.map(|c| (c.clamp(0.0, 1.0) * 255.0).round() as u8);
            format!("#{:02x}{:02x}{:02x}", b[0], b[1], b[2])
        }
        None => t.to_string(),
    }
}

fn pts_field(pts: &[geometry::Point]) -> Map<String, Json> {
    let mut f = Map::new();
    f.insert(
        "pts".into(),
        Json::Array(pts.iter().map(|p| json!([p.x, p.y])).collect()),
    );
    f
}

fn attrs_fields(a: &Attributes, f: &mut Map<String, Json>) {
    f.insert("label".into(), json!(a.label));
    for (k, v) in [
        ("msg", &a.msg),
        ("source", &a.source),
        ("vsource", &a.vsource),
    ] {
        if !v.is_empty() {
            f.insert(k.into(), json!(v));
        }
    }
    for (k, v) in [
        ("label_color", &a.label_color),
        ("edge_color", &a.edge_color),
        ("vertex_color", &a.vertex_color),
        ("fill_color", &a.fill_color),
    ] {
        if let Some(v) = v {
            f.insert(k.into(), json!(css_color(v)));
        }
    }
    for (k, v) in [
        ("vertex_size", a.vertex_size),
        ("edge_size", a.edge_size),
        ("fill_transparency", a.fill_transparency),
        ("duration", a.duration),
    ] {
        if let Some(v) = v {
            f.insert(k.into(), json!(v));
        }
    }
}

/// A circle, marker, vector, arrow or pulse: `key=value` pairs at the top level (commas
/// inside braces kept), the common fields read as `Attributes`, the rest kept with numbers as
/// numbers.
fn generic(value: &str) -> Result<(Attributes, Map<String, Json>), Rejected> {
    let mut attrs = Attributes::default();
    let mut f = Map::new();
    let mut depth = 0usize;
    let mut start = 0;
    let mut pieces = Vec::new();
    for (i, c) in value.char_indices() {
        match c {
            '{' => depth += 1,
            '}' => depth = depth.saturating_sub(1),
            ',' if depth == 0 => {
                pieces.push(&value[start..i]);
                start = i + 1;
            }
            _ => {}
        }
    }
    pieces.push(&value[start..]);
    for piece in pieces {
        let Some((k, v)) = piece.split_once('=') else {
            continue;
        };
        let (k, v) = (k.trim().to_ascii_lowercase(), v.trim());
        // `type` is ignored by the common fields but is a marker's shape.
        if k != "type"
            && attrs
                .set(&k, v)
                .map_err(|e| Rejected::BadShape(e.to_string()))?
        {
            continue;
        }
        let val = if k.ends_with("color") {
            json!(css_color(v))
        } else if geometry::is_number(v) {
            json!(geometry::atof(v))
        } else {
            json!(v)
        };
        f.insert(k, val);
    }
    if attrs.active && f.is_empty() {
        return Err(Rejected::BadShape(format!("no fields in {value:?}")));
    }
    Ok((attrs, f))
}

fn appcast_json(e: &AppcastEntry) -> Json {
    let c = &e.cast;
    json!({
        "node": c.node_name(),
        "app": c.proc_name(),
        "iteration": c.iteration(),
        "cfg_warnings": c.config_warnings().len(),
        "run_warnings": c.run_warning_total(),
        "report": c.to_formatted_string(false),
    })
}

/// A button's postings as text, as the page shows them.
pub fn button_value_text(v: &ButtonValue) -> String {
    match v {
        ButtonValue::Double(d) => moos_types::fmt::g_string(*d, 10),
        ButtonValue::Text(t) => t.clone(),
        ButtonValue::Utc => "$[UTC]".into(),
        ButtonValue::PressCount => "$[BIX]".into(),
    }
}

fn button_json(b: &Button) -> Json {
    json!({
        "label": b.label,
        "key": b.key,
        "postings": b.postings.iter().map(|(var, v)| json!([var, button_value_text(v)])).collect::<Vec<_>>(),
    })
}
