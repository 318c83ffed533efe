//! BHV_Loiter (reference §6.2): circles a convex polygon clockwise or counter-clockwise.
//!
//! # Conformance with BHV_Loiter (MOOS-IvP a2a9b716)
//!
//! | parameter | aliases | type | default | validation (C++ rule) | runtime update | coug |
//! |---|---|---|---|---|---|---|
//! | polygon | | polygon | none | convex (any `string2Poly` form) | yes | done |
//! | speed | | m/s | 0 | number >= 0, clipped to the domain's top | yes | done |
//! | speed_alt | | m/s | −1 (unused) | number (negative ok, not clipped) | yes | done |
//! | use_alt_speed | | bool | false | MOOS boolean | yes | done |
//! | clockwise | | bool or `best` | true | MOOS boolean, toggle, `best` | yes | done |
//! | capture_radius | radius | m | 3 | number >= 0 | yes | done |
//! | slip_radius | nm_radius | m | 15 | number >= 0 (0 = off) | yes | done |
//! | acquire_dist | acquire_distance | m | 10 | number >= 0 | yes | done |
//! | patience | | 1..99 | 50 | number in [1, 99] | yes | done |
//! | center_assign | | `present_position`, `x,y`, `x=..,y=..` | none | any text; applied at once with the last iteration's position, what cannot be read ignored silently | yes | done |
//! | xcenter_assign, ycenter_assign | | number | none | any text, appended as `,x=<v>` / `,y=<v>` to the pending assignment (applied at the next run; a non-number ignored) | yes | done |
//! | center_activate | | bool | false | `true`/`false` | yes | done |
//! | mod_poly_rad | | m | | number; grows the polygon about its vertex centroid, largest radius >= 5 m | yes | done |
//! | spiral_factor | | 0..100 | (bonus −2°) | any text (`atof`); bonus −75 + 0.74 × value | yes | done |
//! | slingshot | | degrees | −1 (off) | number >= 0; completes after that much bearing sweep | yes | done |
//! | ipf_type | ipf-type | enum | zaic | `zaic`, `zaic_spd`; other values keep the type | yes | done |
//! | post_suffix | | text | none | non-empty, no white space; `_` + upper case | yes | done |
//! | visual_hints | | hints | | vertex/edge/nextpt sizes and colours, label, lcolor | yes | done |
//!
//! | variable | when | format | coug |
//! |---|---|---|---|
//! | LOITER_REPORT`<sfx>` | running and idle iterations | `index=..,capture_hits=..,nonmono_hits=..,acquire_mode=true\|false` | done |
//! | LOITER_INDEX`<sfx>`, LOITER_MODE`<sfx>`, LOITER_ACQUIRE`<sfx>` | same | number; `idle`, `acquiring_*`, `recovering_*`, `stable`; 1/0 | done |
//! | LOITER_DIST_TO_POLY`<sfx>`, LOITER_ETA_TO_POLY`<sfx>` | same | integer above 10 (ETA also at 0), else decimal | done |
//! | LOITER_DIST_TO_VERT | running iterations (never suffixed) | metres | done |
//! | LOITER_BNG_TOTAL, LOITER_BNG_DELTA | with `slingshot`, while loitering | degrees | done |
//! | LOITER_COMPLETE | on completion | `true` | done |
//! | BHV_SETTINGS | each idle→running transition (repeatable) | `type=BHV_Loiter,name=..,x=..,y=..,clockwise=..,dynamic_clockwise=..,center_activate=..,desired_speed=..,polygon="pts={..}"` | done |
//! | VIEW_POLYGON, VIEW_POINT | running (drawn), idle/complete (erased) | `<us>_<name>` polygon, `<us>_waypoint` point | done |
//!
//! | macro | meaning | coug |
//! |---|---|---|
//! | PTS | vertex count | done |
//! | CX, CY | bounding-box centre (3 decimals, compact) | done |
//! | CENTER | `x=CX,y=CY` (2 decimals) | done |
//! | CWISE | `1` clockwise, `0` counter-clockwise (the C++ int overload) | done |
//! | RAD | largest centre-to-vertex distance | done |

use geometry::spec::parse_polygon;
use geometry::{Point, Polygon, ViewPoint, ViewPolygon};
use ivp::{IvpFunction, ZaicPeak, ZaicSpd, couple_weighted};

use crate::behavior::{Behavior, Ctx, Out, ParamError, add_vars, nav};
use crate::common::Common;
use crate::param::{boolean, number, number_min};

/// Direction setting (`clockwise = true | false | best`).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Direction {
    /// Clockwise (default).
    Clockwise,
    /// Counter-clockwise.
    CounterClockwise,
    /// Chosen on each idle→running transition from outside the polygon: the direction whose
    /// entry vertex needs the smaller turn from the present heading (MOOS
    /// `LoiterEngine::resetClockwiseBest`).
    Best,
}

/// The loiter behaviour (reference §6.2, MOOS `BHV_Loiter` + `LoiterEngine`): a perpetual tour
/// of the polygon's vertices in the chosen direction, with a waypoint engine (capture and slip
/// radii). When farther than `acquire_dist` outside the polygon it acquires an entry vertex:
/// among the vertices visible from ownship, the one whose turn onto the next edge is the most
/// clockwise (clockwise loiter) or counter-clockwise; from inside, the vertex needing the
/// smallest turn, favouring the one ahead (spiral factor −2).
#[derive(Debug, Clone)]
pub struct Loiter {
    poly: Polygon,
    center_assign: String,
    center_pending: bool,
    /// Desired speed, m/s.
    pub speed: f64,
    /// Alternative speed (−1 = unused).
    pub speed_alt: f64,
    /// Use `speed_alt`.
    pub use_alt_speed: bool,
    /// Direction setting.
    pub direction: Direction,
    clockwise_now: bool,
    /// Ownship position at the last run iteration (MOOS `m_osx`, `m_osy`; 0 before any).
    os: Point,
    /// Capture radius, m (default 3).
    pub capture_radius: f64,
    /// Slip radius, m (default 15).
    pub slip_radius: f64,
    /// Distance outside the polygon beyond which the loiter acquires, m (default 10).
    pub acquire_dist: f64,
    /// Course share of the coupled function (1..99, default 50).
    pub patience: f64,
    zaic_spd: bool,
    center_activate: bool,
    suffix: String,
    hint_vertex_size: f64,
    hint_edge_size: f64,
    hint_vertex_color: String,
    hint_edge_color: String,
    hint_nextpt_color: String,
    hint_nextpt_lcolor: String,
    hint_nextpt_vertex_size: f64,
    hint_poly_label: String,
    hint_poly_lcolor: String,
    curr_ix: usize,
    cpa: Option<f64>,
    acquire: bool,
    mode: &'static str,
    capture_hits: u32,
    nonmono_hits: u32,
    next: Point,
    /// Bonus (degrees, negative favours) for the vertex ahead when acquiring from inside.
    spiral_factor: f64,
    /// `slingshot`: complete once the bearing to the centre has swept more than this many
    /// degrees while loitering (−1 = off).
    slingshot_deg: f64,
    bearing_last_deg: Option<f64>,
    bearing_total_deg: f64,
    /// Signed distance to the polygon (negative inside) and its ETA, as last measured.
    dist_to_poly: f64,
    eta_to_poly: f64,
}

impl Default for Loiter {
    fn default() -> Self {
        Self::new()
    }
}

/// Whether vertex `i` of a convex polygon is visible from the outside point `(x, y)`: the
/// point lies outside the line of one of the two edges meeting at `i`.
fn vertex_viewable(v: &[Point], i: usize, x: f64, y: f64) -> bool {
    let n = v.len();
    let cw = signed_area(v) < 0.0;
    let outside = |a: Point, b: Point| {
        let cross = (b.x - a.x) * (y - a.y) - (b.y - a.y) * (x - a.x);
        if cw { cross > 0.0 } else { cross < 0.0 }
    };
    let prev = v[(i + n - 1) % n];
    let next = v[(i + 1) % n];
    outside(prev, v[i]) || outside(v[i], next)
}

fn signed_area(v: &[Point]) -> f64 {
    let n = v.len();
    (0..n)
        .map(|i| {
            let (a, b) = (v[i], v[(i + 1) % n]);
            a.x * b.y - b.x * a.y
        })
        .sum::<f64>()
        / 2.0
}

impl Loiter {
    /// The MOOS defaults (no polygon, speed 0, clockwise).
    pub fn new() -> Self {
        Loiter {
            poly: Polygon::default(),
            center_assign: String::new(),
            center_pending: false,
            os: Point::new(0.0, 0.0),
            speed: 0.0,
            speed_alt: -1.0,
            use_alt_speed: false,
            direction: Direction::Clockwise,
            clockwise_now: true,
            capture_radius: 3.0,
            slip_radius: 15.0,
            acquire_dist: 10.0,
            patience: 50.0,
            zaic_spd: false,
            center_activate: false,
            suffix: String::new(),
            hint_vertex_size: 1.0,
            hint_edge_size: 1.0,
            hint_vertex_color: "dodger_blue".into(),
            hint_edge_color: "white".into(),
            hint_nextpt_color: "yellow".into(),
            hint_nextpt_lcolor: "aqua".into(),
            hint_nextpt_vertex_size: 5.0,
            hint_poly_label: String::new(),
            hint_poly_lcolor: String::new(),
            curr_ix: 0,
            cpa: None,
            acquire: false,
            mode: "idle",
            capture_hits: 0,
            nonmono_hits: 0,
            next: Point::new(0.0, 0.0),
            spiral_factor: SPIRAL_FACTOR,
            slingshot_deg: -1.0,
            bearing_last_deg: None,
            bearing_total_deg: 0.0,
            dist_to_poly: 0.0,
            eta_to_poly: 0.0,
        }
    }

    /// MOOS `postStatusReports`: LOITER_REPORT, _INDEX, _MODE, _ACQUIRE, _DIST_TO_POLY and
    /// _ETA_TO_POLY (with the `post_suffix`; distance and ETA as integers above 10).
    fn post_status_reports(&self, out: &mut Out) {
        let sfx = &self.suffix;
        out.post(
            format!("LOITER_REPORT{sfx}"),
            format!(
                "index={},capture_hits={},nonmono_hits={},acquire_mode={}",
                self.curr_ix, self.capture_hits, self.nonmono_hits, self.acquire
            ),
        );
        out.post(format!("LOITER_INDEX{sfx}"), self.curr_ix as f64);
        out.post(format!("LOITER_MODE{sfx}"), self.mode);
        out.post(
            format!("LOITER_ACQUIRE{sfx}"),
            if self.acquire { 1.0 } else { 0.0 },
        );
        let (dist, eta) = (self.dist_to_poly, self.eta_to_poly);
        if dist > 10.0 {
            out.post_int(format!("LOITER_DIST_TO_POLY{sfx}"), dist);
        } else {
            out.post(format!("LOITER_DIST_TO_POLY{sfx}"), dist);
        }
        if eta > 10.0 || eta == 0.0 {
            out.post_int(format!("LOITER_ETA_TO_POLY{sfx}"), eta);
        } else {
            out.post(format!("LOITER_ETA_TO_POLY{sfx}"), eta);
        }
    }

    /// The vertex being sought.
    pub fn next_vertex(&self) -> Option<Point> {
        self.poly.vertices().get(self.curr_ix).copied()
    }

    /// Whether the loiter is circling clockwise now.
    pub fn is_clockwise(&self) -> bool {
        self.clockwise_now
    }

    /// The loiter mode posted in `LOITER_MODE` (stable, acquiring_external, ...).
    pub fn mode(&self) -> &'static str {
        self.mode
    }

    /// Orders the vertices for the current direction (MOOS `setClockwise`).
    fn set_clockwise(&mut self, cw: bool) {
        self.clockwise_now = cw;
        if !self.poly.is_empty() && self.poly.is_clockwise() != cw {
            let mut v = self.poly.vertices().to_vec();
            v.reverse();
            self.poly = Polygon::new(v);
        }
        self.curr_ix = 0;
        self.cpa = None;
    }

    fn set_center(&mut self, c: Point) {
        let old = self.poly.center();
        let (dx, dy) = (c.x - old.x, c.y - old.y);
        let pts = self
            .poly
            .vertices()
            .iter()
            .map(|p| Point::new(p.x + dx, p.y + dy))
            .collect();
        self.poly = Polygon::new(pts);
    }

    /// The entry vertex from outside for direction `cw` (MOOS `acquireVertexOut`).
    fn vertex_out(&self, x: f64, y: f64, cw: bool) -> usize {
        let v = self.poly.vertices();
        // The vertex order used for `cw`.
        let ordered: Vec<Point> = if self.poly.is_clockwise() == cw {
            v.to_vec()
        } else {
            v.iter().rev().copied().collect()
        };
        let n = ordered.len();
        let mut best: Option<(usize, f64)> = None;
        for i in 0..n {
            if !vertex_viewable(&ordered, i, x, y) {
                continue;
            }
            let (a, b) = (ordered[i], ordered[(i + 1) % n]);
            let ang = geometry::angle::turn_angle(x, y, a.x, a.y, b.x, b.y);
            let better = match best {
                None => true,
                Some((_, b)) => (cw && ang > b) || (!cw && ang < b),
            };
            if better {
                best = Some((i, ang));
            }
        }
        let ix = best.map_or(0, |b| b.0);
        // Back to the index in the current vertex order.
        if self.poly.is_clockwise() == cw {
            ix
        } else {
            n - 1 - ix
        }
    }

    /// The entry vertex from inside (MOOS `acquireVertexIn`).
    fn vertex_in(&self, h: f64, x: f64, y: f64) -> usize {
        let v = self.poly.vertices();
        let n = v.len();
        let mut ahead = 0;
        let mut smallest = 360.0;
        for (i, p) in v.iter().enumerate() {
            let d = (h - geometry::relative_angle(x, y, p.x, p.y)).abs();
            if d < smallest {
                smallest = d;
                ahead = i;
            }
        }
        let mut low = f64::INFINITY;
        let mut low_ix = 0;
        for i in 0..n {
            let (a, b) = (v[i], v[(i + 1) % n]);
            let mut ang = geometry::angle::turn_angle(x, y, a.x, a.y, b.x, b.y).abs();
            if i == ahead {
                ang += self.spiral_factor;
            }
            if ang < low {
                low = ang;
                low_ix = i;
            }
        }
        low_ix
    }

    fn effective_speed(&self) -> f64 {
        if self.use_alt_speed && self.speed_alt >= 0.0 {
            self.speed_alt
        } else {
            self.speed
        }
    }

    fn label(&self, ctx: &Ctx<'_>) -> String {
        if self.hint_poly_label.is_empty() {
            format!("{}_{}", ctx.ownship, ctx.name.to_ascii_lowercase())
        } else {
            self.hint_poly_label.clone()
        }
    }

    fn post_erasables(&self, ctx: &Ctx<'_>, out: &mut Out) {
        out.post(
            "VIEW_POLYGON",
            ViewPolygon::erase(&self.label(ctx)).to_spec(),
        );
        let mut s = String::new();
        ViewPoint::erase_spec(&format!("{}_waypoint", ctx.ownship), &mut s);
        out.post("VIEW_POINT", s);
    }

    /// MOOS `updateCenter`: `present_position`, `x,y`, `x=..,y=..`, `x=..` or `y=..`.
    /// Applies a pending centre assignment (MOOS `updateCenter`): `present_position` moves
    /// the polygon to ownship's last position; `x=..,y=..` pieces set what they name with a
    /// number; `x,y` sets both when both are numbers; anything else is ignored silently.
    /// The assignment is consumed either way.
    fn update_center(&mut self) {
        if !self.center_pending {
            return;
        }
        let a = std::mem::take(&mut self.center_assign).to_ascii_lowercase();
        self.center_pending = false;
        let num = |t: &str| crate::param::is_number(t).then(|| crate::param::atof(t.trim()));
        if a == "present_position" {
            self.set_center(self.os);
        } else if a.contains('=') {
            let mut p = self.poly.center();
            let mut any = false;
            for part in a.split(',') {
                let kv: Vec<&str> = part.split('=').collect();
                if let [k, v] = kv[..] {
                    match (k.trim(), num(v)) {
                        ("x", Some(x)) => (p.x, any) = (x, true),
                        ("y", Some(y)) => (p.y, any) = (y, true),
                        _ => {}
                    }
                }
            }
            if any {
                self.set_center(p);
            }
        } else if let [sx, sy] = a.split(',').collect::<Vec<_>>()[..]
            && let (Some(x), Some(y)) = (num(sx), num(sy))
        {
            self.set_center(Point::new(x, y));
        }
    }
}

/// MOOS `LoiterEngine` default spiral factor: a small bonus for the vertex ahead.
const SPIRAL_FACTOR: f64 = -2.0;

/// The smallest largest-radius `mod_poly_rad` shrinks a polygon to, m (MOOS LoiterEngine).
const MIN_MOD_RADIUS: f64 = 5.0;

impl Behavior for Loiter {
    fn kind(&self) -> &'static str {
        "BHV_Loiter"
    }

    /// The loiter's own macros (MOOS-IvP a2a9b716 `BHV_Loiter::expandMacros`), usable in all
    /// of its flags: `PTS` (vertex count), `CX`/`CY` (centre of the polygon's bounding box,
    /// up to 3 decimals, trailing zeros dropped), `CENTER` (`x=CX,y=CY` with up to 2
    /// decimals), `CWISE` (the current direction as MOOS prints a bool through its integer
    /// overload: `1` clockwise, `0` counter-clockwise) and `RAD` (largest centre-to-vertex
    /// distance, up to 3 decimals).
    fn macro_value(&self, name: &str, out: &mut String) -> bool {
        let c = self.poly.center();
        match name {
            "PTS" => crate::fmt::compact(out, self.poly.len() as f64, 0),
            "CX" => crate::fmt::compact(out, c.x, 3),
            "CY" => crate::fmt::compact(out, c.y, 3),
            "CENTER" => {
                out.push_str("x=");
                crate::fmt::compact(out, c.x, 2);
                out.push_str(",y=");
                crate::fmt::compact(out, c.y, 2);
            }
            "CWISE" => out.push(if self.clockwise_now { '1' } else { '0' }),
            "RAD" => crate::fmt::compact(out, self.poly.max_radius(), 3),
            _ => return false,
        }
        true
    }

    fn default_name(&self) -> &'static str {
        "bhv_loiter"
    }

    fn domain_vars(&self) -> &'static [&'static str] {
        &["course", "speed"]
    }

    fn info_vars(&self, out: &mut Vec<String>) {
        add_vars(out, ["NAV_X", "NAV_Y", "NAV_HEADING", "NAV_SPEED"]);
    }

    fn set_param(
        &mut self,
        param: &str,
        value: &str,
        _common: &mut Common,
        ctx: &Ctx<'_>,
    ) -> Result<(), ParamError> {
        let v = value.trim();
        let clip = |s: f64| ctx.domain.get("speed").map_or(s, |d| s.min(d.high()));
        match param {
            "polygon" => {
                let p = parse_polygon(v)
                    .map_err(|_| ParamError::bad(param, value, "a convex polygon"))?
                    .polygon;
                if p.len() < 3 || !p.is_convex() {
                    return Err(ParamError::bad(param, value, "a convex polygon"));
                }
                self.poly = p;
                let cw = self.clockwise_now;
                self.set_clockwise(cw);
            }
            "speed" => self.speed = clip(number_min(param, v, 0.0)?),
            // Negative values are taken; not clipped to the domain (MOOS).
            "speed_alt" => self.speed_alt = number(param, v)?,
            "use_alt_speed" => self.use_alt_speed = boolean(param, v)?,
            // `best`, or a MOOS boolean (`true`/`yes`/`on`, `false`/`no`/`off`, `toggle`).
            "clockwise" => {
                self.direction = match v.to_ascii_lowercase().as_str() {
                    "true" | "yes" | "on" => Direction::Clockwise,
                    "false" | "no" | "off" => Direction::CounterClockwise,
                    "toggle" if self.clockwise_now => Direction::CounterClockwise,
                    "toggle" => Direction::Clockwise,
                    "best" => Direction::Best,
                    _ => return Err(ParamError::bad(param, value, "a boolean or best")),
                };
                if self.direction != Direction::Best {
                    self.set_clockwise(self.direction == Direction::Clockwise);
                }
            }
            "capture_radius" | "radius" => self.capture_radius = number_min(param, v, 0.0)?,
            "slip_radius" | "nm_radius" => self.slip_radius = number_min(param, v, 0.0)?,
            "acquire_dist" | "acquire_distance" => self.acquire_dist = number_min(param, v, 0.0)?,
            "patience" => {
                let d = number(param, v)?;
                if !(1.0..=99.0).contains(&d) {
                    return Err(ParamError::bad(param, value, "a number in [1, 99]"));
                }
                self.patience = d;
            }
            // Any text (MOOS): what cannot be read is ignored when applied, which is at
            // once, with the position of the last iteration.
            "center_assign" => {
                self.center_assign = v.to_string();
                self.center_pending = true;
                self.update_center();
            }
            // Appended to the pending assignment, applied at the next run iteration.
            "xcenter_assign" | "ycenter_assign" => {
                let axis = if param == "xcenter_assign" { "x" } else { "y" };
                self.center_assign.push_str(&format!(",{axis}={v}"));
                self.center_pending = true;
            }
            "center_activate" => self.center_activate = boolean(param, v)?,
            // MOOS takes any value and keeps the type unless it is `zaic` or `zaic_spd`.
            "ipf_type" | "ipf-type" => match v.to_ascii_lowercase().as_str() {
                "zaic" => self.zaic_spd = false,
                "zaic_spd" => self.zaic_spd = true,
                _ => {}
            },
            // `_` + the value in upper case; empty or with white space is rejected (MOOS).
            "post_suffix" => {
                if v.is_empty() || v.contains(char::is_whitespace) {
                    return Err(ParamError::bad(param, value, "a suffix without spaces"));
                }
                self.suffix = format!("_{}", v.to_ascii_uppercase());
            }
            "visual_hints" => {
                use crate::hints::{color, pairs, size};
                for (k, val) in pairs(v) {
                    match (k.as_str(), color(val), size(val)) {
                        ("vertex_size", _, Some(d)) => self.hint_vertex_size = d,
                        ("edge_size", _, Some(d)) => self.hint_edge_size = d,
                        ("nextpt_vertex_size", _, Some(d)) => self.hint_nextpt_vertex_size = d,
                        ("vertex_color", Some(c), _) => self.hint_vertex_color = c.into(),
                        ("edge_color", Some(c), _) => self.hint_edge_color = c.into(),
                        ("nextpt_color", Some(c), _) => self.hint_nextpt_color = c.into(),
                        ("nextpt_lcolor", Some(c), _) => self.hint_nextpt_lcolor = c.into(),
                        ("label", _, _) => self.hint_poly_label = val.into(),
                        // The C++ takes any label colour here, unchecked.
                        ("lcolor" | "label_color", _, _) => self.hint_poly_lcolor = val.into(),
                        // MOOS ignores unknown hints and bad values.
                        _ => {}
                    }
                }
            }
            // Grows (or shrinks) the polygon about its vertex centroid so that its largest
            // radius changes by the value, never below 5 m; the vertex being sought is kept
            // and the loiter re-acquires (MOOS LoiterEngine::modPolyRad).
            "mod_poly_rad" => {
                let delta = number(param, v)?;
                if !self.poly.is_empty() {
                    let cur = self.poly.max_radius();
                    let amt = (cur + delta).max(MIN_MOD_RADIUS) - cur;
                    let n = self.poly.len() as f64;
                    let (sx, sy) = self
                        .poly
                        .vertices()
                        .iter()
                        .fold((0.0, 0.0), |(sx, sy), p| (sx + p.x, sy + p.y));
                    let (cx, cy) = (sx / n, sy / n);
                    let pts = self
                        .poly
                        .vertices()
                        .iter()
                        .map(|p| p.project(geometry::relative_angle(cx, cy, p.x, p.y), amt))
                        .collect();
                    self.poly = Polygon::new(pts);
                }
                self.acquire = true;
                self.mode = "idle";
            }
            // MOOS LoiterEngine::setSpiralFactor: any text (atof), 0..100 mapped onto a bonus
            // of −75..−1 degrees for the vertex ahead.
            "spiral_factor" => {
                let pct = crate::param::atof(v) / 100.0;
                self.spiral_factor = -75.0 + pct * 74.0;
            }
            "slingshot" => self.slingshot_deg = number_min(param, v, 0.0)?,
            _ => return Err(ParamError::unknown(param)),
        }
        Ok(())
    }

    fn config_status(&self, name: &str) -> Option<String> {
        let c = self.poly.center();
        let mut st = format!("type=BHV_Loiter,name={name},x=");
        crate::fmt::fixed(&mut st, c.x, 2);
        st.push_str(",y=");
        crate::fmt::fixed(&mut st, c.y, 2);
        st.push_str(&format!(
            ",clockwise={},dynamic_clockwise={},center_activate={},desired_speed=",
            self.clockwise_now,
            self.direction == Direction::Best,
            self.center_activate
        ));
        crate::fmt::fixed(&mut st, self.speed, 1);
        st.push_str(",polygon=\"");
        st.push_str(&ViewPolygon::new(self.poly.clone()).to_spec());
        st.push('"');
        Some(st)
    }

    fn on_idle_to_run(&mut self, ctx: &Ctx<'_>, out: &mut Out) {
        crate::behavior::post_config_status(&*self, ctx, out);
        if self.center_activate {
            self.center_assign = "present_position".into();
            self.center_pending = true;
        }
        if self.direction == Direction::Best
            && !self.poly.is_empty()
            && let Some((x, y, h, _)) = nav(ctx.info)
            && !self.poly.contains(x, y)
        {
            let turn = |cw| {
                let i = self.vertex_out(x, y, cw);
                let p = self.poly.vertices()[i];
                geometry::angle_180(h - geometry::relative_angle(x, y, p.x, p.y)).abs()
            };
            let cw = turn(true) < turn(false);
            if cw != self.clockwise_now || self.cpa.is_none() {
                self.set_clockwise(cw);
            }
        }
    }

    fn on_idle(&mut self, ctx: &Ctx<'_>, out: &mut Out) {
        self.post_erasables(ctx, out);
        self.mode = "idle";
        self.post_status_reports(out);
        self.bearing_last_deg = None;
        self.bearing_total_deg = 0.0;
    }

    fn on_complete(&mut self, ctx: &Ctx<'_>, out: &mut Out) {
        self.post_erasables(ctx, out);
        out.post("LOITER_COMPLETE", "true");
        self.bearing_last_deg = None;
        self.bearing_total_deg = 0.0;
    }

    fn on_run(&mut self, ctx: &Ctx<'_>, out: &mut Out) -> Option<IvpFunction> {
        if self.poly.is_empty() {
            out.warning(ctx.name, "Empty/NULL Loiter Specification.");
            let mut s = String::new();
            ViewPoint::erase_spec(&format!("{}_waypoint", ctx.ownship), &mut s);
            out.post("VIEW_POINT", s);
            return None;
        }
        let Some((x, y, h, v)) = nav(ctx.info) else {
            out.error("No ownship X/Y/HEADING/SPEED info in info_buffer.");
            return None;
        };
        // A pending centre assignment applies before the distance is measured (as the MOOS
        // unit tests of the newer BHV_Loiter expect).
        self.os = Point::new(x, y);
        self.update_center();
        let dist_poly = self.poly.signed_distance(x, y).unwrap_or(0.0);
        let eta = if dist_poly > 0.0 && h > 0.001 && v > 0.0 {
            dist_poly / v
        } else {
            0.0
        };
        // Loiter mode (MOOS updateLoiterMode).
        let position = if dist_poly > self.acquire_dist {
            1
        } else if dist_poly < -self.acquire_dist {
            -1
        } else {
            0
        };
        self.mode = match (position, self.mode) {
            (0, _) => "stable",
            (1, "stable" | "recovering_external") => "recovering_external",
            (1, _) => "acquiring_external",
            (_, "stable" | "recovering_internal") => "recovering_internal",
            _ => "acquiring_internal",
        };
        self.acquire = dist_poly > self.acquire_dist;
        if self.acquire {
            self.curr_ix = if self.poly.contains(x, y) {
                self.vertex_in(h, x, y)
            } else {
                self.vertex_out(x, y, self.clockwise_now)
            };
            self.cpa = None;
        }
        // slingshot: sweep of the bearing from ownship to the centre while loitering.
        let mut slingshot_done = false;
        if !self.acquire && self.slingshot_deg > -1.0 {
            let c = self.poly.center();
            let bng = geometry::relative_angle(x, y, c.x, c.y);
            if let Some(last) = self.bearing_last_deg {
                let delta = geometry::angle::angle_diff(bng, last);
                self.bearing_total_deg += delta;
                out.post("LOITER_BNG_TOTAL", self.bearing_total_deg);
                out.post("LOITER_BNG_DELTA", delta);
            }
            self.bearing_last_deg = Some(bng);
            slingshot_done = self.bearing_total_deg > self.slingshot_deg;
        }
        // Waypoint engine on the vertices, repeating forever.
        let verts = self.poly.vertices();
        let pt = verts[self.curr_ix];
        let dist = (x - pt.x).hypot(y - pt.y);
        let cpa = self.cpa.map_or(dist, |c| c.min(dist));
        self.cpa = Some(cpa);
        let mut advance = false;
        if dist < self.capture_radius {
            advance = true;
            self.capture_hits += 1;
        } else if self.slip_radius > self.capture_radius && dist > cpa && cpa <= self.slip_radius {
            advance = true;
            self.nonmono_hits += 1;
        }
        if advance {
            self.curr_ix = (self.curr_ix + 1) % verts.len();
            let n = verts[self.curr_ix];
            self.cpa = Some((x - n.x).hypot(y - n.y));
            self.acquire = false;
        }
        self.next = verts[self.curr_ix];
        let next = self.next;
        out.post("LOITER_DIST_TO_VERT", (x - next.x).hypot(y - next.y));

        let speed = self.effective_speed();
        let spd = if self.zaic_spd {
            ZaicSpd::new(ctx.domain, "speed", speed, 0.1, speed + 0.4, 85.0, 20.0)
                .ok()?
                .extract()
                .ok()?
        } else {
            let mut z = ZaicPeak::new(ctx.domain, "speed").ok()?;
            z.set_params(speed, 0.0, 0.3, 0.0, 0.0, 100.0).ok()?;
            z.extract().ok()?
        };
        let bearing = geometry::relative_angle(x, y, next.x, next.y);
        let mut crs = ZaicPeak::new(ctx.domain, "course").ok()?;
        crs.set_value_wrap(true);
        crs.set_params(bearing, 0.0, 180.0, 0.0, 0.0, 100.0).ok()?;
        let crs = crs.extract().ok()?;
        let ipf = couple_weighted(&crs, &spd, self.patience, 100.0 - self.patience, true).ok();

        let mut vp = ViewPolygon::new(self.poly.clone());
        vp.attrs.label = self.label(ctx);
        if !self.hint_poly_lcolor.is_empty() {
            vp.attrs.label_color = Some(self.hint_poly_lcolor.clone());
        }
        vp.attrs.vertex_color = Some(self.hint_vertex_color.clone());
        vp.attrs.edge_color = Some(self.hint_edge_color.clone());
        vp.attrs.vertex_size = Some(self.hint_vertex_size);
        vp.attrs.edge_size = Some(self.hint_edge_size);
        out.post("VIEW_POLYGON", vp.to_spec());
        let mut pt = ViewPoint::new(next);
        pt.attrs.label = format!("{}_waypoint", ctx.ownship);
        pt.attrs.label_color = Some(self.hint_nextpt_lcolor.clone());
        pt.attrs.vertex_color = Some(self.hint_nextpt_color.clone());
        pt.attrs.vertex_size = Some(self.hint_nextpt_vertex_size);
        out.post("VIEW_POINT", pt.to_spec());

        self.dist_to_poly = dist_poly;
        self.eta_to_poly = eta;
        self.post_status_reports(out);
        if slingshot_done {
            out.complete();
        }
        ipf
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::behavior::{Emit, MapInfo};
    use ivp::{Domain, Problem};

    const SQUARE: &str = "-20,80:-20,120:20,120:20,80";

    fn domain() -> Domain {
        Domain::parse_specs(["course:0:359:360", "speed:0:4:41"]).unwrap()
    }

    fn info(x: f64, y: f64, h: f64) -> MapInfo {
        MapInfo::new(0.0)
            .num("NAV_X", x)
            .num("NAV_Y", y)
            .num("NAV_HEADING", h)
            .num("NAV_SPEED", 1.0)
    }

    fn loiter(params: &[(&str, &str)]) -> Loiter {
        let d = domain();
        let i = info(0.0, 0.0, 0.0);
        let ctx = Ctx {
            info: &i,
            domain: &d,
            ownship: "abe",
            name: "loiter",
            perpetual: false,
        };
        let mut l = Loiter::new();
        let mut c = Common::new("BHV_Loiter");
        for (k, v) in params {
            l.set_param(k, v, &mut c, &ctx).unwrap();
        }
        l
    }

    /// One running iteration at (x, y, h): (course, speed) and the output.
    fn run(l: &mut Loiter, x: f64, y: f64, h: f64, first: bool) -> (f64, f64, Out) {
        let d = domain();
        let i = info(x, y, h);
        let ctx = Ctx {
            info: &i,
            domain: &d,
            ownship: "abe",
            name: "loiter",
            perpetual: false,
        };
        let mut out = Out::default();
        if first {
            l.on_idle_to_run(&ctx, &mut out);
        }
        let f = l.on_run(&ctx, &mut out).unwrap();
        let mut p = Problem::new(d.clone());
        p.add("loiter", f).unwrap();
        let dec = p.solve().unwrap();
        (dec.get("course").unwrap(), dec.get("speed").unwrap(), out)
    }

    /// Runs `f` with the test context at ownship (0, 0), heading 0.
    fn with_ctx<R>(f: impl FnOnce(&Ctx<'_>) -> R) -> R {
        let d = domain();
        let i = info(0.0, 0.0, 0.0);
        f(&Ctx {
            info: &i,
            domain: &d,
            ownship: "abe",
            name: "loiter",
            perpetual: false,
        })
    }

    fn posted<'a>(out: &'a Out, var: &str) -> Option<&'a crate::Value> {
        out.emits.iter().find_map(|e| match e {
            Emit::Post { var: v, value, .. } if v == var => Some(value),
            _ => None,
        })
    }

    #[test]
    fn entry_vertex_follows_the_configured_direction() {
        // From due south of the square, clockwise circulation enters at the south-west corner
        // (then heads north along the west side), counter-clockwise at the south-east one.
        let mut l = loiter(&[("polygon", SQUARE), ("clockwise", "true"), ("speed", "1.5")]);
        let (course, speed, out) = run(&mut l, 0.0, 0.0, 0.0, true);
        assert_eq!(l.next_vertex(), Some(Point::new(-20.0, 80.0)));
        assert_eq!(course, 346.0);
        assert_eq!(speed, 1.5);
        assert_eq!(
            posted(&out, "LOITER_ACQUIRE"),
            Some(&crate::Value::Double(1.0))
        );
        assert_eq!(
            posted(&out, "LOITER_MODE").unwrap().as_str(),
            Some("acquiring_external")
        );

        let mut l = loiter(&[
            ("polygon", SQUARE),
            ("clockwise", "false"),
            ("speed", "1.5"),
        ]);
        let (course, _, _) = run(&mut l, 0.0, 0.0, 0.0, true);
        assert_eq!(l.next_vertex(), Some(Point::new(20.0, 80.0)));
        assert_eq!(course, 14.0);
    }

    #[test]
    fn best_direction_needs_the_smaller_turn() {
        let mut l = loiter(&[("polygon", SQUARE), ("clockwise", "best")]);
        run(&mut l, 0.0, 0.0, 350.0, true);
        assert!(l.is_clockwise(), "heading 350: the west entry is closer");
        let mut l = loiter(&[("polygon", SQUARE), ("clockwise", "best")]);
        run(&mut l, 0.0, 0.0, 10.0, true);
        assert!(!l.is_clockwise(), "heading 10: the east entry is closer");
    }

    #[test]
    fn circulates_clockwise_around_the_vertices() {
        let mut l = loiter(&[("polygon", SQUARE), ("clockwise", "true"), ("speed", "1")]);
        // On the polygon near the south-west corner: capture it, then head north.
        run(&mut l, -20.0, 79.0, 0.0, true);
        assert_eq!(l.next_vertex(), Some(Point::new(-20.0, 120.0)));
        let (course, _, out) = run(&mut l, -20.0, 100.0, 0.0, false);
        assert_eq!(course, 0.0);
        assert_eq!(
            posted(&out, "LOITER_MODE").unwrap().as_str(),
            Some("stable")
        );
        run(&mut l, -20.0, 119.0, 0.0, false);
        let (course, _, _) = run(&mut l, -10.0, 120.0, 90.0, false);
        assert_eq!(l.next_vertex(), Some(Point::new(20.0, 120.0)));
        assert_eq!(course, 90.0);
    }

    #[test]
    fn inside_the_polygon_is_acquiring_internal_with_alt_speed() {
        let mut l = loiter(&[
            ("polygon", "radial:: x=0, y=0, radius=40, pts=4, snap=1"),
            ("speed", "2"),
            ("speed_alt", "1"),
            ("use_alt_speed", "true"),
            ("post_suffix", "survey"),
            ("visual_hints", "edge_color=yellow,label=loiter_box"),
        ]);
        let (_, speed, out) = run(&mut l, 0.0, 0.0, 90.0, true);
        assert_eq!(speed, 1.0);
        assert_eq!(
            posted(&out, "LOITER_MODE_SURVEY").unwrap().as_str(),
            Some("acquiring_internal")
        );
        assert_eq!(
            posted(&out, "LOITER_ACQUIRE_SURVEY"),
            Some(&crate::Value::Double(0.0))
        );
        let poly = posted(&out, "VIEW_POLYGON").unwrap().as_str().unwrap();
        assert!(
            poly.contains("label=loiter_box") && poly.contains("edge_color=yellow"),
            "{poly}"
        );
    }

    #[test]
    fn idle_erases_and_completion_is_posted() {
        let mut l = loiter(&[("polygon", SQUARE)]);
        let mut out = Out::default();
        with_ctx(|ctx| l.on_idle(ctx, &mut out));
        assert!(
            posted(&out, "VIEW_POLYGON")
                .unwrap()
                .as_str()
                .unwrap()
                .contains("active=false")
        );
        assert!(
            posted(&out, "VIEW_POINT")
                .unwrap()
                .as_str()
                .unwrap()
                .contains("active=false")
        );
        with_ctx(|ctx| l.on_complete(ctx, &mut out));
        assert_eq!(
            posted(&out, "LOITER_COMPLETE").unwrap().as_str(),
            Some("true")
        );
        // No polygon: a warning and no function.
        let mut empty = Loiter::new();
        let mut out = Out::default();
        assert!(with_ctx(|ctx| empty.on_run(ctx, &mut out)).is_none());
        assert!(
            posted(&out, "BHV_WARNING")
                .unwrap()
                .as_str()
                .unwrap()
                .contains("Empty/NULL")
        );
    }

    #[test]
    fn rejects_non_convex_polygons_and_bad_values() {
        let d = domain();
        let i = info(0.0, 0.0, 0.0);
        let ctx = Ctx {
            info: &i,
            domain: &d,
            ownship: "abe",
            name: "l",
            perpetual: false,
        };
        let mut l = Loiter::new();
        let mut c = Common::new("BHV_Loiter");
        for (k, v) in [
            ("polygon", "pts={0,0:10,10:0,20:5,10}"),
            ("clockwise", "sideways"),
            ("speed", "-1"),
            ("patience", "100"),
        ] {
            assert!(
                matches!(
                    l.set_param(k, v, &mut c, &ctx),
                    Err(ParamError::BadValue { .. })
                ),
                "{k} = {v}"
            );
        }
    }

    #[test]
    fn center_assign_moves_the_polygon() {
        let mut l = loiter(&[
            ("polygon", "radial:: x=0, y=0, radius=30, pts=4, snap=1"),
            ("center_assign", "x=100,y=-20"),
            ("speed", "2"),
        ]);
        let (_, _, out) = run(&mut l, 100.0, -20.0, 0.0, true);
        let report = posted(&out, "LOITER_REPORT").unwrap().as_str().unwrap();
        assert!(report.ends_with("acquire_mode=false"), "{report}");
        let v = l.next_vertex().unwrap();
        assert!(
            (v.x - 100.0).abs() <= 30.0 && (v.y + 20.0).abs() <= 30.0,
            "{v:?}"
        );
    }

    #[test]
    fn center_assignments_read_what_they_can_and_ignore_the_rest() {
        // Square centred on (0,100).
        let mut l = loiter(&[("polygon", SQUARE)]);
        let c = |l: &Loiter| l.poly.center();
        // Unreadable text is accepted and changes nothing (MOOS ignores it silently).
        for junk in ["north", "x=abc", "1,2,3", "z=4", "1e3,5"] {
            set(&mut l, "center_assign", junk).unwrap();
            assert!(near(c(&l), 0.0, 100.0), "{junk}: {:?}", c(&l));
        }
        // Applied at once: only the readable piece counts.
        set(&mut l, "center_assign", "x=10, y=oops").unwrap();
        assert!(near(c(&l), 10.0, 100.0), "{:?}", c(&l));
        set(&mut l, "center_assign", " -5 , 7 ").unwrap();
        assert!(near(c(&l), -5.0, 7.0), "{:?}", c(&l));
        // present_position at configuration: ownship's position is still (0,0) (MOOS m_osx).
        set(&mut l, "center_assign", "Present_Position").unwrap();
        assert!(near(c(&l), 0.0, 0.0), "{:?}", c(&l));
        // x/ycenter_assign wait for the next run; a non-number piece is ignored there.
        set(&mut l, "xcenter_assign", "40").unwrap();
        set(&mut l, "ycenter_assign", "far").unwrap();
        assert!(near(c(&l), 0.0, 0.0));
        run(&mut l, 0.0, 0.0, 0.0, true);
        assert!(near(c(&l), 40.0, 0.0), "{:?}", c(&l));
        // present_position as an update uses the last run iteration's position.
        run(&mut l, 3.0, 4.0, 0.0, false);
        set(&mut l, "center_assign", "present_position").unwrap();
        assert!(near(c(&l), 3.0, 4.0), "{:?}", c(&l));
    }

    fn set(l: &mut Loiter, k: &str, v: &str) -> Result<(), ParamError> {
        with_ctx(|ctx| l.set_param(k, v, &mut Common::new("BHV_Loiter"), ctx))
    }

    fn near(a: Point, x: f64, y: f64) -> bool {
        (a.x - x).abs() < 1e-9 && (a.y - y).abs() < 1e-9
    }

    #[test]
    fn mod_poly_rad_grows_and_shrinks_about_the_centroid_with_a_5_m_floor() {
        let mut l = loiter(&[("polygon", SQUARE)]);
        // Centroid (0,100), largest radius hypot(20,20); +10 m moves every vertex 10 m out
        // along its diagonal: (-20,80) -> (-20 - 10/sqrt2, 80 - 10/sqrt2).
        set(&mut l, "mod_poly_rad", "10").unwrap();
        let h = 10.0 / 2f64.sqrt();
        let v = l.poly.vertices().to_vec();
        assert!(v.iter().any(|p| near(*p, -20.0 - h, 80.0 - h)), "{v:?}");
        assert!(v.iter().any(|p| near(*p, 20.0 + h, 120.0 + h)), "{v:?}");
        assert!((l.poly.max_radius() - (800f64.sqrt() + 10.0)).abs() < 1e-9);
        assert!(l.acquire && l.mode == "idle");
        // A shrink below 5 m stops at 5 m.
        set(&mut l, "mod_poly_rad", "-100").unwrap();
        assert!(
            (l.poly.max_radius() - 5.0).abs() < 1e-9,
            "{}",
            l.poly.max_radius()
        );
        assert!(matches!(
            set(&mut l, "mod_poly_rad", "big"),
            Err(ParamError::BadValue { .. })
        ));
    }

    #[test]
    fn slingshot_completes_after_the_bearing_sweep_and_posts_its_progress() {
        let mut l = loiter(&[("polygon", SQUARE), ("slingshot", "90")]);
        assert!(matches!(
            set(&mut l, "slingshot", "-1"),
            Err(ParamError::BadValue { .. })
        ));
        // Inside the square on a 10 m circle about its centre, 30 degrees a step.
        let mut totals = Vec::new();
        let mut done_at = None;
        for k in 0..6 {
            let a = (k as f64 * 30.0).to_radians();
            let (x, y) = (10.0 * a.sin(), 100.0 + 10.0 * a.cos());
            let (_, _, out) = run(&mut l, x, y, 90.0, k == 0);
            if let Some(crate::Value::Double(t)) = posted(&out, "LOITER_BNG_TOTAL") {
                totals.push((t * 1e6).round() / 1e6);
            }
            if out.completed && done_at.is_none() {
                done_at = Some(k);
            }
        }
        assert_eq!(totals[..4], [30.0, 60.0, 90.0, 120.0]);
        // 90 is not more than 90: completion comes with the fourth step (120).
        assert_eq!(done_at, Some(4));
        // Off by default: no sweep postings.
        let mut plain = loiter(&[("polygon", SQUARE)]);
        let (_, _, out) = run(&mut plain, 0.0, 110.0, 90.0, true);
        let (_, _, out2) = run(&mut plain, 10.0, 100.0, 90.0, false);
        assert!(
            posted(&out, "LOITER_BNG_TOTAL").is_none()
                && posted(&out2, "LOITER_BNG_TOTAL").is_none()
        );
    }

    #[test]
    fn spiral_factor_and_the_other_cpp_value_rules() {
        let mut l = loiter(&[]);
        assert_eq!(l.spiral_factor, -2.0);
        set(&mut l, "spiral_factor", "50").unwrap();
        assert_eq!(l.spiral_factor, -38.0);
        set(&mut l, "spiral_factor", "lots").unwrap();
        assert_eq!(l.spiral_factor, -75.0, "atof of text is 0");
        // clockwise takes MOOS booleans and toggle.
        set(&mut l, "clockwise", "no").unwrap();
        assert!(!l.clockwise_now);
        set(&mut l, "clockwise", "toggle").unwrap();
        assert!(l.clockwise_now);
        assert!(set(&mut l, "clockwise", "sideways").is_err());
        // acquire_distance is an alias; ipf_type keeps its value on an unknown type.
        set(&mut l, "acquire_distance", "25").unwrap();
        assert_eq!(l.acquire_dist, 25.0);
        set(&mut l, "ipf_type", "zaic_spd").unwrap();
        set(&mut l, "ipf_type", "roc").unwrap();
        assert!(l.zaic_spd);
        // post_suffix: `_` + upper case, never empty.
        set(&mut l, "post_suffix", "a1").unwrap();
        assert_eq!(l.suffix, "_A1");
        set(&mut l, "post_suffix", "_b").unwrap();
        assert_eq!(l.suffix, "__B");
        assert!(set(&mut l, "post_suffix", "").is_err());
        // speed_alt is taken as given (negative ok, not clipped to the domain).
        set(&mut l, "speed_alt", "9").unwrap();
        assert_eq!(l.speed_alt, 9.0);
    }

    #[test]
    fn settings_on_start_idle_reports_and_unsuffixed_vertex_distance() {
        let mut l = loiter(&[("polygon", SQUARE), ("speed", "1.25"), ("post_suffix", "a")]);
        let (_, _, out) = run(&mut l, 0.0, 0.0, 0.0, true);
        assert_eq!(
            posted(&out, "BHV_SETTINGS").and_then(|v| v.as_str()),
            Some(
                "type=BHV_Loiter,name=loiter,x=0.00,y=100.00,clockwise=true,\
                 dynamic_clockwise=false,center_activate=false,desired_speed=1.2,\
                 polygon=\"pts={-20,80:-20,120:20,120:20,80}\""
            )
        );
        // The suffix applies to the status reports, not to LOITER_DIST_TO_VERT.
        assert!(posted(&out, "LOITER_DIST_TO_VERT").is_some());
        assert!(posted(&out, "LOITER_MODE_A").is_some());
        // Idle: erased drawings and the status reports with mode idle.
        let mut out = Out::default();
        with_ctx(|ctx| l.on_idle(ctx, &mut out));
        assert_eq!(
            posted(&out, "LOITER_MODE_A"),
            Some(&crate::Value::String("idle".into()))
        );
        assert!(posted(&out, "LOITER_REPORT_A").is_some());
    }
}
