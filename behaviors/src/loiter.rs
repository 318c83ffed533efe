//! BHV_Loiter (reference §6.2): circles a convex polygon clockwise or counter-clockwise.

use geometry::spec::parse_polygon;
use geometry::{Point, Polygon, ViewPoint, ViewPolygon};
use ivp::{IvpFunction, ZaicPeak, ZaicSpd, couple_weighted};

use crate::behavior::{Behavior, Ctx, Out, ParamError, PostKey, nav};
use crate::common::Common;
use crate::param::{boolean, number, number_min};

/// Direction setting (`clockwise = true | false | best`).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Direction {
    /// Clockwise (default).
    Clockwise,
    /// Counter-clockwise.
    CounterClockwise,
    /// Chosen on each idle→running transition: the direction whose entry vertex needs the
    /// smaller turn from the present heading.
    Best,
}

/// The loiter behaviour: a perpetual tour of the polygon's vertices in the chosen direction.
/// When farther than `acquire_dist` from the polygon it (re)acquires: it heads for the vertex
/// at the tangent on the side that joins the circulation (for clockwise, the vertex farthest
/// counter-clockwise in bearing as seen from ownship).
#[derive(Debug, Clone)]
pub struct Loiter {
    poly: Polygon,
    center_given: Option<Point>,
    /// Desired speed, m/s.
    pub speed: f64,
    /// Alternative speed (−1 = unused).
    pub speed_alt: f64,
    /// Use `speed_alt`.
    pub use_alt_speed: bool,
    /// Direction setting.
    pub direction: Direction,
    clockwise_now: bool,
    /// Capture radius, m (default 3).
    pub capture_radius: f64,
    /// Slip radius, m (default 15).
    pub slip_radius: f64,
    /// Distance from the polygon beyond which the loiter re-acquires, m (default 10).
    pub acquire_dist: f64,
    /// Course share of the coupled function (1..99, default 50).
    pub patience: f64,
    zaic_spd: bool,
    center_activate: bool,
    center_pending: bool,
    suffix: String,
    hint_vertex_size: f64,
    hint_edge_size: f64,
    hint_vertex_color: String,
    hint_edge_color: String,
    hint_nextpt_color: String,
    hint_nextpt_lcolor: String,
    order: Vec<Point>,
    curr_ix: usize,
    cpa: Option<f64>,
    acquire: bool,
    capture_hits: u32,
    nonmono_hits: u32,
}

impl Default for Loiter {
    fn default() -> Self {
        Self::new()
    }
}

impl Loiter {
    /// The MOOS defaults (no polygon, speed 0, clockwise).
    pub fn new() -> Self {
        Loiter {
            poly: Polygon::default(),
            center_given: None,
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
            center_pending: false,
            suffix: String::new(),
            hint_vertex_size: 1.0,
            hint_edge_size: 1.0,
            hint_vertex_color: "dodger_blue".into(),
            hint_edge_color: "white".into(),
            hint_nextpt_color: "yellow".into(),
            hint_nextpt_lcolor: "aqua".into(),
            order: Vec::new(),
            curr_ix: 0,
            cpa: None,
            acquire: true,
            capture_hits: 0,
            nonmono_hits: 0,
        }
    }

    /// The vertex being sought.
    pub fn next_vertex(&self) -> Option<Point> {
        self.order.get(self.curr_ix).copied()
    }

    /// Whether the loiter is circling clockwise now.
    pub fn is_clockwise(&self) -> bool {
        self.clockwise_now
    }

    fn reorder(&mut self) {
        let mut v: Vec<Point> = self.poly.vertices().to_vec();
        if self.poly.is_clockwise() != self.clockwise_now {
            v.reverse();
        }
        self.order = v;
        self.curr_ix = 0;
        self.cpa = None;
        self.acquire = true;
    }

    fn move_center(&mut self, c: Point) {
        let old = self.poly.center();
        let (dx, dy) = (c.x - old.x, c.y - old.y);
        let pts = self
            .poly
            .vertices()
            .iter()
            .map(|p| Point::new(p.x + dx, p.y + dy))
            .collect();
        self.poly = Polygon::new(pts);
        self.reorder();
    }

    /// The entry vertex for ownship at `(x, y)` circling in direction `cw`, and its bearing.
    fn entry_vertex(&self, x: f64, y: f64, cw: bool) -> Option<(usize, f64)> {
        let c = self.poly.center();
        let to_center = geometry::relative_angle(x, y, c.x, c.y);
        let mut v: Vec<Point> = self.poly.vertices().to_vec();
        if self.poly.is_clockwise() != cw {
            v.reverse();
        }
        if self.poly.contains(x, y) {
            // Inside: the vertex after the nearest one, so the tour continues forward.
            let (near, _) = v.iter().enumerate().min_by(|a, b| {
                a.1.dist(&Point::new(x, y))
                    .total_cmp(&b.1.dist(&Point::new(x, y)))
            })?;
            let ix = (near + 1) % v.len();
            return Some((ix, geometry::relative_angle(x, y, v[ix].x, v[ix].y)));
        }
        let rel =
            |p: &Point| geometry::angle_180(geometry::relative_angle(x, y, p.x, p.y) - to_center);
        let pick = v.iter().enumerate().min_by(|a, b| {
            let (ra, rb) = (rel(a.1), rel(b.1));
            if cw {
                ra.total_cmp(&rb)
            } else {
                rb.total_cmp(&ra)
            }
        })?;
        Some((pick.0, geometry::relative_angle(x, y, pick.1.x, pick.1.y)))
    }

    fn effective_speed(&self) -> f64 {
        if self.use_alt_speed && self.speed_alt >= 0.0 {
            self.speed_alt
        } else {
            self.speed
        }
    }
}

impl Behavior for Loiter {
    fn kind(&self) -> &'static str {
        "BHV_Loiter"
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
                if let Some(c) = self.center_given {
                    self.move_center(c);
                } else {
                    self.reorder();
                }
            }
            "speed" => self.speed = clip(number_min(param, v, 0.0)?),
            "speed_alt" => self.speed_alt = clip(number(param, v)?),
            "use_alt_speed" => self.use_alt_speed = boolean(param, v)?,
            "clockwise" => {
                self.direction = match v.to_ascii_lowercase().as_str() {
                    "true" => Direction::Clockwise,
                    "false" => Direction::CounterClockwise,
                    "best" => Direction::Best,
                    _ => return Err(ParamError::bad(param, value, "true, false or best")),
                };
                if self.direction != Direction::Best {
                    self.clockwise_now = self.direction == Direction::Clockwise;
                    self.reorder();
                }
            }
            "capture_radius" | "radius" => self.capture_radius = number_min(param, v, 0.0)?,
            "slip_radius" | "nm_radius" => self.slip_radius = number_min(param, v, 0.0)?,
            "acquire_dist" => self.acquire_dist = number_min(param, v, 0.0)?,
            "patience" => {
                let d = number(param, v)?;
                if !(1.0..=99.0).contains(&d) {
                    return Err(ParamError::bad(param, value, "a number in [1, 99]"));
                }
                self.patience = d;
            }
            "center_assign" | "xcenter_assign" | "ycenter_assign" => {
                let here = nav(ctx.info).map(|n| Point::new(n.0, n.1));
                let cur = self.center_given.unwrap_or_else(|| self.poly.center());
                let c = if v.eq_ignore_ascii_case("present_position") {
                    here.ok_or_else(|| {
                        ParamError::bad(param, value, "a position (none known yet)")
                    })?
                } else if param == "xcenter_assign" {
                    Point::new(number(param, v)?, cur.y)
                } else if param == "ycenter_assign" {
                    Point::new(cur.x, number(param, v)?)
                } else {
                    let nums: Vec<&str> = v
                        .split(',')
                        .map(|s| s.split_once('=').map_or(s, |kv| kv.1).trim())
                        .collect();
                    if nums.len() != 2 {
                        return Err(ParamError::bad(param, value, "x,y or present_position"));
                    }
                    Point::new(number(param, nums[0])?, number(param, nums[1])?)
                };
                self.center_given = Some(c);
                if !self.poly.is_empty() {
                    self.move_center(c);
                }
            }
            "center_activate" => self.center_activate = boolean(param, v)?,
            "ipf_type" => {
                self.zaic_spd = match v.to_ascii_lowercase().as_str() {
                    "zaic" => false,
                    "zaic_spd" => true,
                    _ => return Err(ParamError::bad(param, value, "zaic or zaic_spd")),
                }
            }
            "post_suffix" => {
                if v.contains(char::is_whitespace) {
                    return Err(ParamError::bad(param, value, "a suffix without spaces"));
                }
                self.suffix = if v.is_empty() || v.starts_with('_') {
                    v.into()
                } else {
                    format!("_{}", v.to_ascii_uppercase())
                };
            }
            "visual_hints" => {
                for h in v.split(',') {
                    let (k, val) = h.split_once('=').unwrap_or((h, ""));
                    let (k, val) = (k.trim().to_ascii_lowercase(), val.trim());
                    let num = val.parse::<f64>().ok().filter(|d| *d >= 0.0);
                    match (k.as_str(), num) {
                        ("vertex_size", Some(d)) => self.hint_vertex_size = d,
                        ("edge_size", Some(d)) => self.hint_edge_size = d,
                        ("vertex_color", _) => self.hint_vertex_color = val.into(),
                        ("edge_color", _) => self.hint_edge_color = val.into(),
                        ("nextpt_color", _) => self.hint_nextpt_color = val.into(),
                        ("nextpt_lcolor", _) => self.hint_nextpt_lcolor = val.into(),
                        _ => {}
                    }
                }
            }
            "mod_poly_rad" | "spiral_factor" | "slingshot" => {
                return Err(ParamError::bad(
                    param,
                    value,
                    "a parameter coug does not support yet",
                ));
            }
            _ => return Err(ParamError::unknown(param)),
        }
        Ok(())
    }

    fn on_idle_to_run(&mut self, ctx: &Ctx<'_>, _out: &mut Out) {
        if self.center_activate {
            self.center_pending = true;
        }
        self.acquire = true;
        if self.direction == Direction::Best
            && let Some((x, y, h, _)) = nav(ctx.info)
        {
            let turn = |cw| {
                self.entry_vertex(x, y, cw)
                    .map_or(360.0, |(_, b)| geometry::angle_180(b - h).abs())
            };
            let cw = turn(true) <= turn(false);
            if cw != self.clockwise_now {
                self.clockwise_now = cw;
                self.reorder();
            }
        }
    }

    fn on_run_to_idle(&mut self, ctx: &Ctx<'_>, out: &mut Out) {
        out.post(
            "VIEW_POLYGON",
            ViewPolygon::erase(&format!("{}_{}", ctx.ownship, ctx.name)).to_spec(),
        );
        let mut s = String::new();
        ViewPoint::erase_spec(&format!("{}'s next waypoint", ctx.ownship), &mut s);
        out.post_key("VIEW_POINT", s, PostKey::Tag("wpt"));
    }

    fn on_run(&mut self, ctx: &Ctx<'_>, out: &mut Out) -> Option<IvpFunction> {
        let Some((x, y, _, _)) = nav(ctx.info) else {
            out.error("No ownship X/Y/heading info in info_buffer.");
            return None;
        };
        if self.order.is_empty() {
            return None;
        }
        if self.center_pending {
            self.center_pending = false;
            self.move_center(Point::new(x, y));
        }
        let dist_poly = self.poly.signed_distance(x, y).unwrap_or(0.0);
        let outside = dist_poly > self.acquire_dist;
        if outside && !self.acquire {
            self.acquire = true;
        }
        if self.acquire {
            if let Some((ix, _)) = self.entry_vertex(x, y, self.clockwise_now) {
                self.curr_ix = ix;
                self.cpa = None;
            }
            if !outside {
                self.acquire = false;
            }
        }
        // Capture / slip on the current vertex; the tour repeats forever.
        let pt = self.order[self.curr_ix];
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
            self.curr_ix = (self.curr_ix + 1) % self.order.len();
            let n = self.order[self.curr_ix];
            self.cpa = Some((x - n.x).hypot(y - n.y));
        }
        let next = self.order[self.curr_ix];
        let sfx = self.suffix.clone();
        let mode = if self.acquire {
            if dist_poly > 0.0 {
                "acquiring_external"
            } else {
                "acquiring_internal"
            }
        } else if dist_poly > self.acquire_dist {
            "recovering_external"
        } else {
            "stable"
        };
        out.post(
            format!("LOITER_REPORT{sfx}"),
            format!(
                "index={},capture_hits={},nonmono_hits={},acquire_mode={}",
                self.curr_ix,
                self.capture_hits,
                self.nonmono_hits,
                if self.acquire { "true" } else { "false" }
            ),
        );
        out.post(format!("LOITER_INDEX{sfx}"), self.curr_ix as f64);
        out.post(format!("LOITER_MODE{sfx}"), mode);
        out.post(
            format!("LOITER_ACQUIRE{sfx}"),
            if self.acquire { 1.0 } else { 0.0 },
        );
        out.post_int(
            format!("LOITER_DIST_TO_VERT{sfx}"),
            (x - next.x).hypot(y - next.y),
        );
        let mut vp = ViewPolygon::new(self.poly.clone());
        vp.attrs.label = format!("{}_{}", ctx.ownship, ctx.name);
        vp.attrs.vertex_color = Some(self.hint_vertex_color.clone());
        vp.attrs.edge_color = Some(self.hint_edge_color.clone());
        vp.attrs.vertex_size = Some(self.hint_vertex_size);
        vp.attrs.edge_size = Some(self.hint_edge_size);
        out.post("VIEW_POLYGON", vp.to_spec());
        let mut pt = ViewPoint::new(next);
        pt.attrs.label = format!("{}'s next waypoint", ctx.ownship);
        pt.attrs.vertex_color = Some(self.hint_nextpt_color.clone());
        pt.attrs.label_color = Some(self.hint_nextpt_lcolor.clone());
        pt.attrs.vertex_size = Some(4.0);
        out.post_key("VIEW_POINT", pt.to_spec(), PostKey::Tag("wpt"));

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
        couple_weighted(&crs, &spd, self.patience, 100.0 - self.patience, true).ok()
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::behavior::MapInfo;
    use ivp::{Domain, Problem};

    fn run(clockwise: &str, x: f64, y: f64) -> (Loiter, f64, f64) {
        let d = Domain::parse_specs(["course:0:359:360", "speed:0:4:41"]).unwrap();
        let info = MapInfo::new(0.0)
            .num("NAV_X", x)
            .num("NAV_Y", y)
            .num("NAV_HEADING", 0.0)
            .num("NAV_SPEED", 1.0);
        let ctx = Ctx {
            info: &info,
            domain: &d,
            ownship: "abe",
            name: "loiter",
            perpetual: false,
        };
        let mut l = Loiter::new();
        let mut c = Common::new("BHV_Loiter");
        // A square centred on (0, 100): corners (±20, 80) and (±20, 120).
        l.set_param("polygon", "-20,80:-20,120:20,120:20,80", &mut c, &ctx)
            .unwrap();
        l.set_param("clockwise", clockwise, &mut c, &ctx).unwrap();
        l.set_param("speed", "1.5", &mut c, &ctx).unwrap();
        let mut out = Out::default();
        l.on_idle_to_run(&ctx, &mut out);
        let f = l.on_run(&ctx, &mut out).unwrap();
        let mut p = Problem::new(d);
        p.add("loiter", f).unwrap();
        let dec = p.solve().unwrap();
        (l, dec.get("course").unwrap(), dec.get("speed").unwrap())
    }

    #[test]
    fn picks_the_tangent_vertex_for_the_direction() {
        // From due south, clockwise circulation enters on the west side, counter-clockwise on
        // the east side.
        let (l, course, speed) = run("true", 0.0, 0.0);
        assert_eq!(l.next_vertex(), Some(Point::new(-20.0, 80.0)));
        assert!(course > 300.0, "course {course}");
        assert_eq!(speed, 1.5);
        let (l, course, _) = run("false", 0.0, 0.0);
        assert_eq!(l.next_vertex(), Some(Point::new(20.0, 80.0)));
        assert!(course > 0.0 && course < 60.0, "course {course}");
    }

    #[test]
    fn best_direction_follows_the_heading() {
        // Heading north from due south: both entries need the same turn, so clockwise wins
        // ties; the choice is recorded.
        let (l, _, _) = run("best", 0.0, 0.0);
        assert!(l.is_clockwise());
    }

    #[test]
    fn rejects_non_convex_polygons() {
        let d = Domain::parse_specs(["course:0:359:360", "speed:0:4:41"]).unwrap();
        let info = MapInfo::new(0.0);
        let ctx = Ctx {
            info: &info,
            domain: &d,
            ownship: "abe",
            name: "l",
            perpetual: false,
        };
        let mut l = Loiter::new();
        let mut c = Common::new("BHV_Loiter");
        let e = l.set_param("polygon", "pts={0,0:10,10:0,20:5,10}", &mut c, &ctx);
        assert!(matches!(e, Err(ParamError::BadValue { .. })));
    }
}
