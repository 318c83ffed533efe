//! The obstacle behaviours (issue #18, point 4): BHV_AvoidObstacleV24 ([`v24`]) and the
//! older BHV_AvoidObstacle, BHV_AvoidObstacleX and BHV_AvoidObstacleV21 ([`legacy`]), over
//! the code they share here:
//!
//! - [`geom`]: the MOOS-IvP geometry they use (a ray's closest approach to a polygon, bearings
//!   to a polygon, "aft" tests), written from `GeomUtils`/`AngleUtils`' definitions;
//! - [`ObstacleBase`]: the obstacle polygon (`poly`/`polygon`, from the obstacle manager's
//!   alert), its id (`id`/`obid`, set once), the alert request to pObstacleMgr
//!   (`OBM_ALERT_REQUEST`) a spawning template posts at helm start, the resolution through
//!   `OBM_RESOLVED`;
//! - [`ShipModel`]: MOOS-IvP's `ObShipModel`: ownship and the obstacle, the range, the buffer
//!   polygons (`mid` at `min_util_cpa`, `rim` at `max_util_cpa`), the range relevance and the
//!   utility of a heading (its ray's closest approach to the obstacle);
//! - [`Hints`]: `visual_hints` as MOOS's `HintHolder` keeps them and `applyHints` applies them.

mod able;
pub mod geom;
pub mod legacy;
pub mod refinery;

pub mod turn;
pub mod v24;

use std::collections::{BTreeMap, BTreeSet};

/// The `Behavior` methods every obstacle type answers alike: its course and speed, its
/// default name (the C++ constructor's), a constraint; with two arguments its type name too.
macro_rules! obstacle_identity {
    ($name:literal) => {
        fn domain_vars(&self) -> &'static [&'static str] {
            &["course", "speed"]
        }

        fn default_name(&self) -> &'static str {
            $name
        }

        fn is_constraint(&self) -> bool {
            true
        }
    };
    ($kind:literal, $name:literal) => {
        fn kind(&self) -> &'static str {
            $kind
        }

        $crate::obstacle::obstacle_identity!($name);
    };
}
pub(crate) use obstacle_identity;

use geometry::{Attributes, Polygon, ViewPolygon};

use crate::behavior::{Ctx, Out, ParamError};
use crate::common::{Common, Flag};

/// `visual_hints` (MOOS `HintHolder`): colours (keys containing `color`, `lcolor` read as
/// `label_color`) and measures (numbers >= 0).
#[derive(Debug, Clone, Default, PartialEq)]
pub struct Hints {
    colors: BTreeMap<String, String>,
    measures: BTreeMap<String, f64>,
}

impl Hints {
    /// Sets a colour (no check).
    pub fn color(&mut self, key: &str, value: &str) {
        self.colors.insert(key.to_string(), value.to_string());
    }

    /// Sets a measure (no check).
    pub fn measure(&mut self, key: &str, value: f64) {
        self.measures.insert(key.to_string(), value);
    }

    /// Reads `key=value, ...`; false (and the hints before the bad one kept) at the first
    /// hint that is not a colour or a number >= 0, as `HintHolder::setHints`.
    ///
    /// ```
    /// let mut h = behaviors::obstacle::Hints::default();
    /// assert!(h.set("edge_color = red, vertex_size = 3"));
    /// assert!(!h.set("edge_color = bluish"));
    /// assert!(!h.set("vertex_size = -1"));
    /// ```
    pub fn set(&mut self, spec: &str) -> bool {
        for piece in moos_types::text::parse_string(spec, ',') {
            let (k, v) = piece.split_once('=').unwrap_or((piece, ""));
            let (k, v) = (k.trim().to_ascii_lowercase(), v.trim());
            if k.contains("color") {
                if !geometry::color::is_color(v) {
                    return false;
                }
                self.color(&k.replace("lcolor", "label_color"), v);
            } else {
                let d = crate::param::atof(v);
                if !crate::param::is_number(v) || d < 0.0 {
                    return false;
                }
                self.measure(&k, d);
            }
        }
        true
    }

    /// The colour of `<prefix>_<key>`, else of `<key>` (MOOS `applyHints`).
    fn pick_color(&self, prefix: &str, key: &str) -> Option<String> {
        self.colors
            .get(&format!("{prefix}_{key}"))
            .or_else(|| self.colors.get(key))
            .map(|c| visible(c))
    }

    fn pick_measure(&self, prefix: &str, key: &str) -> Option<f64> {
        self.measures
            .get(&format!("{prefix}_{key}"))
            .or_else(|| self.measures.get(key))
            .copied()
    }

    /// The label, vertex, edge and fill colours and the edge and vertex sizes for `prefix`
    /// (MOOS `applyHints(poly, hints, prefix)`).
    pub fn apply(&self, prefix: &str, a: &mut Attributes) {
        if let Some(c) = self.pick_color(prefix, "label_color") {
            a.label_color = Some(c);
        }
        if let Some(c) = self.pick_color(prefix, "vertex_color") {
            a.vertex_color = Some(c);
        }
        if let Some(c) = self.pick_color(prefix, "edge_color") {
            a.edge_color = Some(c);
        }
        if let Some(c) = self.pick_color(prefix, "fill_color") {
            a.fill_color = Some(c);
        }
        if let Some(m) = self.pick_measure(prefix, "edge_size") {
            a.edge_size = Some(m);
        }
        if let Some(m) = self.pick_measure(prefix, "vertex_size") {
            a.vertex_size = Some(m);
        }
    }

    /// A measure by its key.
    pub fn get_measure(&self, key: &str) -> Option<f64> {
        self.measures.get(key).copied()
    }

    /// A colour by its key (as written in a spec).
    pub fn get_color(&self, key: &str) -> Option<String> {
        self.colors.get(key).map(|c| visible(c))
    }
}

/// A colour as MOOS's `ColorPack::str` writes it: `off`, `empty` and `invisible` are
/// `invisible`.
fn visible(c: &str) -> String {
    match c.to_ascii_lowercase().as_str() {
        "off" | "empty" | "invisible" => "invisible".into(),
        _ => c.to_string(),
    }
}

/// The erasing spec of a polygon (MOOS `get_spec_inactive`).
pub fn spec_inactive(label: &str) -> String {
    let mut s = String::from("pts={0,0:9,0:0,9},active=false");
    if !label.is_empty() {
        s.push_str(",label=");
        s.push_str(label);
    }
    s
}

/// What every obstacle behaviour shares: the obstacle, its id, the alert request and the
/// resolution.
#[derive(Debug, Clone, Default)]
pub struct ObstacleBase {
    /// The obstacle ("gut") polygon with its label and vsource, once given.
    pub poly: Option<ViewPolygon>,
    /// The obstacle id (`id`/`obid`).
    pub obstacle_id: String,
    /// The resolution is pending: the behaviour completes at its next idle or running
    /// iteration.
    pub resolved_pending: bool,
    /// The variable the obstacle manager announces resolutions on.
    pub resolved_var: String,
    /// `can_disable` (IvPBehavior's `m_can_disable`, false): `BHV_ABLE_FILTER` acts on the
    /// behaviour (`able.rs`).
    pub can_disable: bool,
    /// Disabled by a `BHV_ABLE_FILTER`.
    pub disabled: bool,
    /// The template's `updates` variable.
    pub update_var: String,
    /// A spawning template.
    pub spawnable: bool,
}

impl ObstacleBase {
    /// A base with `OBM_RESOLVED` as the resolution variable.
    pub fn new() -> Self {
        ObstacleBase {
            resolved_var: "OBM_RESOLVED".into(),
            ..ObstacleBase::default()
        }
    }

    /// The polygon's label (the obstacle key), or empty.
    pub fn label(&self) -> &str {
        self.poly.as_ref().map_or("", |p| p.attrs.label.as_str())
    }

    /// The gut polygon's vertices (empty when none).
    pub fn gut(&self) -> &Polygon {
        static EMPTY: std::sync::OnceLock<Polygon> = std::sync::OnceLock::new();
        self.poly
            .as_ref()
            .map_or_else(|| EMPTY.get_or_init(Polygon::default), |p| &p.polygon)
    }

    /// `poly`/`polygon`: a convex polygon in any MOOS form; `Err` with the C++ message.
    pub fn set_poly(&mut self, value: &str) -> Result<(), &'static str> {
        match geometry::spec::parse_polygon(value) {
            Ok(v) if v.polygon.is_convex() => {
                self.poly = Some(v);
                Ok(())
            }
            _ => Err("obstacle is not convex"),
        }
    }

    /// `id`/`obid`: white-space free; once set it cannot change.
    pub fn set_id(&mut self, param: &str, value: &str) -> Result<(), ParamError> {
        if !self.obstacle_id.is_empty() && self.obstacle_id != value {
            return Err(ParamError::bad(param, value, "the id already set"));
        }
        if value.is_empty() || value.contains(char::is_whitespace) {
            return Err(ParamError::bad(param, value, "a name without white space"));
        }
        self.obstacle_id = value.to_string();
        Ok(())
    }

    /// Takes the template's `updates` variable and templating.
    pub fn set_common(&mut self, common: &Common) {
        self.update_var.clone_from(&common.update_var);
        self.spawnable = common.templating.spawns();
    }

    /// At helm start, for a spawning template with an `updates` variable:
    /// `OBM_ALERT_REQUEST = name=<name>,update_var=<var>,alert_range=<range, 1 decimal>`.
    pub fn alert_request(&self, ctx: &Ctx<'_>, alert_range: f64, out: &mut Out) {
        if !self.spawnable || self.update_var.is_empty() {
            return;
        }
        out.post(
            "OBM_ALERT_REQUEST",
            format!(
                "name={},update_var={},alert_range={}",
                ctx.name,
                self.update_var,
                moos_types::fmt::compact_string(alert_range, 1)
            ),
        );
    }

    /// The obstacle manager's resolution posted this iteration (`OBM_RESOLVED`):
    /// `NOTED_RESOLVED` echoes it, and it is ours when it names our id. The info buffer
    /// keeps the latest posting of a variable: of several resolutions in one helm
    /// iteration, the last is seen.
    pub fn check_resolved(&mut self, ctx: &Ctx<'_>, out: &mut Out) {
        if !ctx.info.is_fresh(&self.resolved_var) {
            return;
        }
        let Some(id) = ctx.info.text(&self.resolved_var) else {
            return;
        };
        out.post("NOTED_RESOLVED", id.to_string());
        if self.obstacle_id == id {
            self.resolved_pending = true;
        }
    }
}

/// A number >= 0 (the C++ `non_neg_number` gate of the obstacle behaviours' distances).
pub fn non_neg(param: &str, value: &str) -> Result<f64, ParamError> {
    let d = crate::param::atof(value);
    if crate::param::is_number(value) && d >= 0.0 {
        Ok(d)
    } else {
        Err(ParamError::bad(param, value, "a number >= 0"))
    }
}

/// The parameters of a [`ShipModel`] the behaviours over it read alike (`poly`/`polygon`,
/// `allowable_ttc`, `min_util_cpa_dist`, `max_util_cpa_dist`, `pwt_inner_dist`,
/// `pwt_outer_dist`, `completed_dist`): `None` for any other parameter.
pub fn ship_param(
    base: &mut ObstacleBase,
    model: &mut ShipModel,
    param: &str,
    value: &str,
) -> Option<Result<(), ParamError>> {
    let bad = |r: Result<(), &'static str>| r.map_err(|e| ParamError::bad(param, value, e));
    let dist = |set: fn(&mut ShipModel, f64) -> Result<(), &'static str>, model: &mut ShipModel| {
        non_neg(param, value).and_then(|d| bad(set(model, d)))
    };
    Some(match param {
        "polygon" | "poly" => bad(base.set_poly(value)).map(|()| {
            let v = base.poly.as_ref().expect("just set");
            model.set_gut(&v.polygon, &v.attrs.label);
        }),
        "allowable_ttc" => bad(model.set_allowable_ttc(crate::param::atof(value))),
        "min_util_cpa_dist" => dist(ShipModel::set_min_util_cpa, model),
        "max_util_cpa_dist" => dist(ShipModel::set_max_util_cpa, model),
        "pwt_inner_dist" => dist(ShipModel::set_pwt_inner, model),
        "pwt_outer_dist" => dist(ShipModel::set_pwt_outer, model),
        "completed_dist" => dist(ShipModel::set_completed, model),
        _ => return None,
    })
}

/// The `BHV_SETTINGS` line of a behaviour over a [`ShipModel`]:
/// `type=<kind>,name=<name>` and its six distances with 2 decimals.
pub fn ship_config_status(kind: &str, name: &str, m: &ShipModel) -> String {
    let mut s = format!("type={kind},name={name}");
    for (k, v) in [
        ("allowable_ttc", m.allowable_ttc),
        ("min_util_cpa", m.min_util_cpa),
        ("max_util_cpa", m.max_util_cpa),
        ("pwt_outer_dist", m.pwt_outer_dist),
        ("pwt_inner_dist", m.pwt_inner_dist),
        ("completed_dist", m.completed_dist),
    ] {
        s.push(',');
        s.push_str(k);
        s.push('=');
        moos_types::fmt::fixed(&mut s, v, 2);
    }
    s
}

/// The range and closest-approach flags of V24 and V21 (`rng_flag`, `cpa_flag`) and the
/// ranges they follow: the closest range ever, and per pass the closest range while closing
/// and the farthest while opening (1 m of hysteresis).
#[derive(Debug, Clone)]
pub struct RangeFlags {
    /// `rng_flag`s: the range below which each is posted (<= 0: always) and the flag.
    pub rng_flags: Vec<(f64, Flag)>,
    /// `cpa_flag`s, posted at each closest approach within `pwt_outer_dist`.
    pub cpa_flags: Vec<Flag>,
    closing: bool,
    cpa_rng_sofar: f64,
    fpa_rng_sofar: f64,
    cpa_rng_ever: f64,
    /// What `$[CPA]` expands to outside the CPA flags: the closest range ever (-1 before).
    pub cpa_reported: f64,
}

impl Default for RangeFlags {
    fn default() -> Self {
        RangeFlags {
            rng_flags: Vec::new(),
            cpa_flags: Vec::new(),
            closing: false,
            cpa_rng_sofar: -1.0,
            fpa_rng_sofar: -1.0,
            cpa_rng_ever: -1.0,
            cpa_reported: -1.0,
        }
    }
}

impl RangeFlags {
    /// `rng_flag = [<RANGE ]VAR=value` (MOOS `handleParamRangeFlag`: a bad flag after a good
    /// threshold is ignored, not refused).
    pub fn set_rng_flag(&mut self, param: &str, value: &str) -> Result<(), ParamError> {
        if value.is_empty() {
            return Err(ParamError::bad(param, value, "[<range ]VAR=value"));
        }
        let (thresh, rest) = match value.strip_prefix('<') {
            Some(r) => {
                let (num, tail) = r.split_once(' ').unwrap_or((r, ""));
                if !crate::param::is_number(num.trim()) {
                    return Err(ParamError::bad(param, value, "<RANGE VAR=value"));
                }
                (crate::param::atof(num.trim()), tail.trim())
            }
            None => (-1.0, value),
        };
        if let Some(f) = Flag::parse(rest) {
            self.rng_flags.push((thresh, f));
        }
        Ok(())
    }

    /// `cpa_flag = VAR=value`.
    pub fn set_cpa_flag(&mut self, param: &str, value: &str) -> Result<(), ParamError> {
        match Flag::parse(value) {
            Some(f) => {
                self.cpa_flags.push(f);
                Ok(())
            }
            None => Err(ParamError::bad(param, value, "VAR=value")),
        }
    }

    /// One range to the obstacle: the range flags that apply, and at a closest approach
    /// within `outer` the CPA flags with `$[CPA]` at this pass's closest range (the helm
    /// expands the flags' other macros when it posts them, so `$[CPA]` is expanded here).
    pub fn update(&mut self, range: f64, outer: f64, out: &mut Out) {
        if self.cpa_rng_ever < 0.0 || range < self.cpa_rng_ever {
            self.cpa_rng_ever = range;
        }
        self.cpa_reported = self.cpa_rng_ever;
        for (thresh, f) in &self.rng_flags {
            if *thresh <= 0.0 || range < *thresh {
                out.flag(f, false);
            }
        }
        let mut cpa_event = false;
        if self.cpa_rng_sofar < 0.0 || self.fpa_rng_sofar < 0.0 {
            (self.cpa_rng_sofar, self.fpa_rng_sofar) = (range, range);
        }
        if self.closing {
            self.cpa_rng_sofar = self.cpa_rng_sofar.min(range);
            if range > self.cpa_rng_sofar + 1.0 {
                self.closing = false;
                cpa_event = true;
                self.fpa_rng_sofar = range;
            }
        } else {
            self.fpa_rng_sofar = self.fpa_rng_sofar.max(range);
            if range < self.fpa_rng_sofar - 1.0 {
                self.closing = true;
                self.cpa_rng_sofar = range;
            }
        }
        if cpa_event && range < outer {
            let mut c = String::new();
            moos_types::fmt::compact(&mut c, self.cpa_rng_sofar, 3);
            for f in &self.cpa_flags {
                let mut f = f.clone();
                if let moos_types::Value::String(s) = &f.value {
                    f.value = moos_types::Value::text(s.replace("$[CPA]", &c));
                }
                out.flag(&f, false);
            }
        }
    }
}

/// Erases the three polygons a behaviour over a [`ShipModel`] draws (MOOS
/// `postErasablePolygons`): the obstacle's, then the two buffers' (each with an empty label
/// while `m` has derived no buffers yet), each under its posting key.
pub fn erase_ship_polygons(
    m: &ShipModel,
    buffers: [&str; 2],
    keys: [&'static str; 3],
    out: &mut Out,
) {
    let derived = !m.mid.is_empty();
    let labels = [
        m.label.clone(),
        if derived {
            buffers[0].to_string()
        } else {
            String::new()
        },
        if derived {
            buffers[1].to_string()
        } else {
            String::new()
        },
    ];
    for (key, label) in keys.into_iter().zip(labels) {
        out.post_key(
            "VIEW_POLYGON",
            spec_inactive(&label),
            crate::behavior::PostKey::Tag(key),
        );
    }
}

/// The idle tail every obstacle behaviour shares: its polygons erased (by `erase`), then
/// completion once the obstacle is resolved.
pub fn idle_tail(base: &ObstacleBase, erase: impl FnOnce(&mut Out), out: &mut Out) {
    erase(out);
    if base.resolved_pending {
        out.complete();
    }
}

/// Ownship as the helm's platform model has it: `(x, y, heading, speed)`, known once
/// `NAV_X`, `NAV_Y`, `NAV_HEADING` and `NAV_SPEED` all are (pHelmIvP's `updatePlatModel`).
/// The helm's default model is holonomic: a heading's path is a ray from ownship.
pub fn plat_pose(ctx: &Ctx<'_>) -> Option<(f64, f64, f64, f64)> {
    let i = ctx.info;
    Some((
        i.num("NAV_X")?,
        i.num("NAV_Y")?,
        i.num("NAV_HEADING")?,
        i.num("NAV_SPEED")?,
    ))
}

/// MOOS-IvP's `ObShipModel` (`ObShipModelV24` and its older form): the settings, ownship,
/// the obstacle and what is derived from them.
#[derive(Debug, Clone)]
pub struct ShipModel {
    /// Utility at or below `min_util_cpa` (0).
    pub min_util: f64,
    /// Utility at or above `max_util_cpa` (100).
    pub max_util: f64,
    /// `min_util_cpa_dist` (8).
    pub min_util_cpa: f64,
    /// `max_util_cpa_dist` (16).
    pub max_util_cpa: f64,
    /// `pwt_inner_dist` (10).
    pub pwt_inner_dist: f64,
    /// `pwt_outer_dist` (50).
    pub pwt_outer_dist: f64,
    /// `allowable_ttc` (20).
    pub allowable_ttc: f64,
    /// `completed_dist` (50).
    pub completed_dist: f64,
    /// Degrees between the points of a buffer polygon's rounded corners (30).
    pub obuff_rdegs: f64,
    /// Only headings that keep the obstacle on its present side are allowed.
    pub side_lock: bool,
    /// The parameters set explicitly (the C++ `m_set_params`).
    pub set: BTreeSet<&'static str>,
    /// Ownship `(x, y, heading, speed)`, once known.
    pub pose: Option<(f64, f64, f64, f64)>,
    /// The obstacle.
    pub gut: Polygon,
    /// The obstacle's label.
    pub label: String,
    /// Derived: range from ownship to the obstacle (0 inside), -1 before any update.
    pub range: f64,
    /// Derived: `min_util_cpa`, or less when ownship is already closer.
    pub min_util_cpa_flex: f64,
    /// Derived: `max_util_cpa`, or less when ownship is already closer.
    pub max_util_cpa_flex: f64,
    /// Derived: the obstacle grown by `min_util_cpa_flex`.
    pub mid: Polygon,
    /// Derived: the obstacle grown by `max_util_cpa_flex`.
    pub rim: Polygon,
    /// Derived: the centre of the obstacle's bounding box.
    pub center: (f64, f64),
    /// Derived: bearing from ownship to the obstacle's centre.
    pub obcent_bng: f64,
    /// Derived: that bearing relative to ownship's heading.
    pub obcent_relbng: f64,
    /// Derived: `star`, `port` or `n/a`: the side the obstacle's centre is on.
    pub passing_side: &'static str,
    /// Derived: the expansion failed (`<expand_failure> <obstacle spec>`).
    pub failed_expand: String,
    /// The words that open [`ShipModel::failed_expand`] (`Bad Expand:` in V24, `Failed
    /// Expand:` in the older model).
    pub expand_failure: &'static str,
    /// The derived values are up to date.
    pub fresh: bool,
}

impl Default for ShipModel {
    fn default() -> Self {
        ShipModel {
            min_util: 0.0,
            max_util: 100.0,
            min_util_cpa: 8.0,
            max_util_cpa: 16.0,
            pwt_inner_dist: 10.0,
            pwt_outer_dist: 50.0,
            allowable_ttc: 20.0,
            completed_dist: 50.0,
            obuff_rdegs: 30.0,
            side_lock: false,
            set: BTreeSet::new(),
            pose: None,
            gut: Polygon::default(),
            label: String::new(),
            range: -1.0,
            min_util_cpa_flex: 8.0,
            max_util_cpa_flex: 16.0,
            mid: Polygon::default(),
            rim: Polygon::default(),
            center: (0.0, 0.0),
            obcent_bng: -1.0,
            obcent_relbng: -1.0,
            passing_side: "n/a",
            failed_expand: String::new(),
            expand_failure: "Bad Expand:",
            fresh: false,
        }
    }
}

impl ShipModel {
    /// Why an avoidance objective cannot be built (the AOFs' `initialize` checks): a
    /// utility distance or `allowable_ttc` not set, the obstacle not convex or around
    /// ownship.
    pub fn aof_problem(&self) -> Option<&'static str> {
        let m = self;
        let (osx, osy) = m.pose.map(|p| (p.0, p.1)).unwrap_or_default();
        if !m.set.contains("min_util_cpa") {
            Some("min_util_cpa is not set")
        } else if !m.set.contains("max_util_cpa") {
            Some("max_util_cpa is not set")
        } else if !m.set.contains("allowable_ttc") {
            Some("allowable_ttc is not set")
        } else if !m.gut.is_convex() {
            Some("m_obstacle is not convex")
        } else if m.gut.contains(osx, osy) {
            Some("m_obstacle contains osx,osy")
        } else {
            None
        }
    }

    /// `pwt_inner_dist`: >= 0; `pwt_outer_dist` and `completed_dist` raised to it, an error
    /// when they were set explicitly.
    pub fn set_pwt_inner(&mut self, v: f64) -> Result<(), &'static str> {
        if v < 0.0 {
            return Err("pwt_inner_dist must be a positive number");
        }
        self.pwt_inner_dist = v;
        self.set.insert("pwt_inner_dist");
        self.fresh = false;
        if self.pwt_outer_dist < v {
            self.pwt_outer_dist = v;
            if self.set.contains("pwt_outer_dist") {
                return Err("pwt_inner_dist must be <= pwt_outer_dist");
            }
        }
        if self.completed_dist < v {
            self.completed_dist = v;
            if self.set.contains("completed_dist") {
                return Err("pwt_inner_dist must be <= completed_dist");
            }
        }
        Ok(())
    }

    /// `pwt_outer_dist`: >= 0; `pwt_inner_dist` lowered and `completed_dist` raised to it.
    pub fn set_pwt_outer(&mut self, v: f64) -> Result<(), &'static str> {
        if v < 0.0 {
            return Err("pwt_outer_dist must be a positive number");
        }
        self.fresh = false;
        self.pwt_outer_dist = v;
        self.set.insert("pwt_outer_dist");
        if self.pwt_inner_dist > v {
            self.pwt_inner_dist = v;
            if self.set.contains("pwt_inner_dist") {
                return Err("pwt_outer_dist must be >= pwt_inner_dist");
            }
        }
        if self.completed_dist < v {
            self.completed_dist = v;
            if self.set.contains("completed_dist") {
                return Err("pwt_outer_dist must be <= completed_dist");
            }
        }
        Ok(())
    }

    /// `completed_dist`: >= 0; both weight distances lowered to it.
    pub fn set_completed(&mut self, v: f64) -> Result<(), &'static str> {
        if v < 0.0 {
            return Err("completed_dist must be a positive number");
        }
        self.fresh = false;
        self.completed_dist = v;
        self.set.insert("completed_dist");
        if self.pwt_inner_dist > v {
            self.pwt_inner_dist = v;
            if self.set.contains("pwt_inner_dist") {
                return Err("completed_dist must be >= pwt_inner_dist");
            }
        }
        if self.pwt_outer_dist > v {
            self.pwt_outer_dist = v;
            if self.set.contains("pwt_outer_dist") {
                return Err("completed_dist must be >= pwt_outer_dist");
            }
        }
        Ok(())
    }

    /// `min_util_cpa_dist`: >= 0; `max_util_cpa_dist` raised to it.
    pub fn set_min_util_cpa(&mut self, v: f64) -> Result<(), &'static str> {
        if v < 0.0 {
            return Err("min_util_cpa cannot be a negative number");
        }
        self.fresh = false;
        self.min_util_cpa = v;
        self.set.insert("min_util_cpa");
        if self.max_util_cpa < v {
            self.max_util_cpa = v;
            if self.set.contains("max_util_cpa") {
                return Err("min_util_cpa must be <= max_util_cpa");
            }
        }
        Ok(())
    }

    /// `max_util_cpa_dist`: >= 0; `min_util_cpa_dist` lowered to it.
    pub fn set_max_util_cpa(&mut self, v: f64) -> Result<(), &'static str> {
        if v < 0.0 {
            return Err("max_util_cpa cannot be a negative number");
        }
        self.fresh = false;
        self.max_util_cpa = v;
        self.set.insert("max_util_cpa");
        if self.min_util_cpa > v {
            self.min_util_cpa = v;
            if self.set.contains("min_util_cpa") {
                return Err("max_util_cpa must be >= min_util_cpa");
            }
        }
        Ok(())
    }

    /// `allowable_ttc`: >= 0.
    pub fn set_allowable_ttc(&mut self, v: f64) -> Result<(), &'static str> {
        if v < 0.0 {
            return Err("allowable_ttc cannot be a negative number");
        }
        self.fresh = false;
        self.allowable_ttc = v;
        self.set.insert("allowable_ttc");
        Ok(())
    }

    /// Sets the obstacle.
    pub fn set_gut(&mut self, p: &Polygon, label: &str) {
        self.gut = p.clone();
        self.label = label.to_string();
        self.set.insert("gut_poly");
        self.fresh = false;
    }

    /// Sets ownship's pose.
    pub fn set_pose(&mut self, pose: Option<(f64, f64, f64, f64)>) {
        if pose != self.pose {
            self.pose = pose;
            self.fresh = false;
        }
    }

    /// Recomputes the derived values when stale (MOOS `setCachedVals` / `updateDynamic`).
    pub fn update(&mut self) {
        if self.fresh {
            return;
        }
        self.fresh = true;
        if !self.gut.is_convex() {
            return;
        }
        let (osx, osy, osh, _) = self.pose.unwrap_or_default();
        self.range = if self.gut.contains(osx, osy) {
            0.0
        } else {
            geom::dist_to_poly(&self.gut, osx, osy)
        };
        self.min_util_cpa_flex = self.min_util_cpa;
        self.max_util_cpa_flex = self.max_util_cpa;
        if self.range < self.min_util_cpa_flex + 1.0 {
            self.min_util_cpa_flex = (self.range - 1.0).max(0.0);
        }
        if self.range < self.max_util_cpa_flex + 1.0 {
            self.max_util_cpa_flex = (self.range - 1.0).max(0.0);
        }
        let mid = geom::buffer(&self.gut, self.min_util_cpa_flex, self.obuff_rdegs);
        let rim = geom::buffer(&self.gut, self.max_util_cpa_flex, self.obuff_rdegs);
        let (Some(mid), Some(rim)) = (mid, rim) else {
            let mut spec = format!("{} ", self.expand_failure);
            let mut v = ViewPolygon::new(self.gut.clone());
            v.attrs.label.clone_from(&self.label);
            v.spec(&mut spec);
            self.failed_expand = spec;
            self.mid = Polygon::default();
            self.rim = Polygon::default();
            return;
        };
        self.mid = mid;
        self.rim = rim;
        let c = self.gut.center();
        self.center = (c.x, c.y);
        self.obcent_bng = geometry::relative_angle(osx, osy, c.x, c.y);
        self.obcent_relbng = geom::rel_bearing(osx, osy, osh, c.x, c.y);
        self.passing_side = if self.obcent_relbng > 0.0 && self.obcent_relbng < 180.0 {
            "star"
        } else if self.obcent_relbng > 180.0 {
            "port"
        } else {
            "n/a"
        };
    }

    /// Why the model cannot be used (MOOS `isValid`), or `None`.
    pub fn invalid(&self) -> Option<String> {
        let mut issue = Vec::new();
        if self.pwt_outer_dist < self.pwt_inner_dist {
            issue.push("pwt_outer < pwt_inner");
        }
        if self.completed_dist < self.pwt_outer_dist {
            issue.push("completed_dist < pwt_outer");
        }
        if self.max_util_cpa < self.min_util_cpa {
            issue.push("max_util_cpa < min_util_cpa");
        }
        if !self.gut.is_convex() {
            issue.push("gut_poly is not convex");
        }
        if !self.mid.is_convex() {
            issue.push("mid_poly is not convex");
        }
        if !self.rim.is_convex() {
            issue.push("rim_poly is not convex");
        }
        if self.pose.is_none() {
            issue.push("plat_model not valid");
        }
        if !self.fresh {
            issue.push("stale cache");
        }
        (!issue.is_empty()).then(|| issue.join(","))
    }

    /// The range relevance in `[0, 1]` (MOOS `getRangeRelevance`): 1 within
    /// `pwt_inner_dist`, 0 at or beyond `pwt_outer_dist`, linear between; then scaled by
    /// the cosine of the angle from ownship's heading to the nearer of the two bearings
    /// bounding the obstacle (full when the heading is between them across north, at least
    /// 0.01 when scaled to 0).
    pub fn range_relevance(&self) -> f64 {
        if self.pwt_outer_dist < self.pwt_inner_dist || self.range >= self.pwt_outer_dist {
            return 0.0;
        }
        let pct = if self.range <= self.pwt_inner_dist {
            1.0
        } else {
            let d = self.pwt_outer_dist - self.pwt_inner_dist;
            if d <= 0.0 {
                return 0.0;
            }
            (self.pwt_outer_dist - self.range) / d
        };
        let (osx, osy, osh, _) = self.pose.unwrap_or_default();
        let Some((bmin, bmax)) = geom::bearing_min_max(osx, osy, &self.gut) else {
            return pct;
        };
        if bmin > bmax {
            return pct;
        }
        let theta =
            geometry::angle::angle_diff(osh, bmin).min(geometry::angle::angle_diff(osh, bmax));
        let cos = theta.to_radians().cos().max(0.0);
        let pct2 = cos * pct;
        if pct > 0.0 && pct2 == 0.0 { 0.01 } else { pct2 }
    }

    /// The obstacle lies wholly at least `xbng` degrees abaft the beam (MOOS `polyAft`).
    pub fn obstacle_aft(&self, xbng: f64) -> bool {
        let (osx, osy, osh, _) = self.pose.unwrap_or_default();
        geom::poly_aft(osx, osy, osh, &self.gut, xbng)
    }

    /// The utility of holding heading `hdg` (MOOS `evalHdgSpd` with the holonomic model):
    /// with the side lock, 0 for a heading that puts the obstacle's centre on the other
    /// side; else, for the closest approach `d` of the heading's ray to the obstacle,
    /// `max_util` at or beyond `max_util_cpa`, `min_util` at or within `min_util_cpa`,
    /// `100·(d − min)/(max − min)` between.
    pub fn eval_heading(&self, hdg: f64) -> f64 {
        let (osx, osy, _, _) = self.pose.unwrap_or_default();
        if self.side_lock {
            let rel = geom::rel_bearing(osx, osy, hdg, self.center.0, self.center.1);
            let side = if rel > 0.0 && rel < 180.0 {
                "star"
            } else {
                "port"
            };
            if side != self.passing_side {
                return 0.0;
            }
        }
        let cpa = geom::ray_cpa(osx, osy, hdg, &self.gut);
        if cpa >= self.max_util_cpa {
            return self.max_util;
        }
        if cpa <= self.min_util_cpa {
            return self.min_util;
        }
        let range = self.max_util_cpa - self.min_util_cpa;
        if range <= 0.0 {
            return self.min_util;
        }
        let pct = ((cpa - self.min_util_cpa) / range).clamp(0.0, 1.0);
        pct * (self.max_util - self.min_util)
    }
}
