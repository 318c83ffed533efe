//! BHV_LegRun: back and forth along one leg `p1`–`p2`, with a Williamson-style turn at each
//! end.
//!
//! # Conformance with BHV_LegRun (MOOS-IvP a2a9b716)
//!
//! The behaviour runs four modes in a cycle: `leg1` (towards `p1`), `turn1` (the turn at
//! `p1`, ending on the leg heading `p1 → p2`), `leg2` (towards `p2`), `turn2`. Legs are
//! followed by one waypoint engine over `[p1, p2]` (MOOS `WaypointEngineX`), turns by a
//! second one over the turn's points (MOOS `LegRun::initTurnPoints1/2`, built by
//! `TurnGenWilliamson`).
//!
//! | parameter | aliases | default | validation (C++ rule) | runtime update | coug |
//! |---|---|---|---|---|---|
//! | p1, p2 | vx1, vx2 | unset | a point (`string2Point`) | yes | done |
//! | leg | | | `x:y:ang:len` or `x=,y=,ang=,len=` (len > 0) | yes | done |
//! | leg_len, leg_len_mod, leg_ang, leg_ang_mod | | | number (len > 0) | yes | done |
//! | shift_pt | | | `x,y`, `x:y` or `x=..,y=..`; needs p1 and p2 | yes | done |
//! | turn_rad, turn1_rad, turn2_rad (and `_mod`) | | −1 (unset: the behaviour is invalid) | number > 0, raised to `turn_rad_min` | yes | done |
//! | turn_rad_min | | 2 | number > 0 | yes | done |
//! | turn_ext, turn1_ext, turn2_ext (and `_mod`) | | 0 | number ≥ 0 | yes | done |
//! | turn_bias, turn1_bias, turn2_bias (and `_mod`) | | 0 | number, clipped to [−100, 100] | yes | done |
//! | turn_dir, turn1_dir, turn2_dir | | port | `port`, `star`, `starboard`, `toggle` | yes | done |
//! | turn_pt_gap | | 20 (degrees between turn points) | number, at least 0.5 | yes | done |
//! | id | | | any text | yes | done |
//! | speed | | 0 | number in [0, domain max] (outside: clipped and refused, `setDoubleRngOnString`) | yes | done |
//! | patience | | 50 | number, clipped to [1, 99] | yes | done |
//! | init_leg_mode | | fixed | `fixed`, `close_turn`, `far_turn`, `resume` (exact case; `resume` is accepted, then a BHV_ERROR when the legs start, as in the C++) | yes | done |
//! | leg_spds | | | `clear`, `reset`, `replace,<list>` or a list of speeds `s` or `n:s` (n > 0, 0 ≤ s ≤ domain max), appended | yes | done |
//! | leg_spds_repeat, leg_spds_onturn | | false | MOOS boolean | yes | done |
//! | capture_radius | radius | 3 | number ≥ 0 (`atof`: text reads 0) | yes | done |
//! | slip_radius | | 15 | number ≥ 0 (`atof`) | yes | done |
//! | capture_line | | false | `true`, `false`, `absolute` (radii 0) | yes | done |
//! | lead, lead_damper | | 0 | number ≥ 0 | yes | done |
//! | repeat | | 0 | `forever` or a number ≥ 0 (other text accepted, ignored); > 0 makes the behaviour perpetual | yes | done |
//! | leg_endflag, leg1_endflag, leg2_endflag, turn_endflag, turn1_endflag, turn2_endflag | `..._end_flag` | none | `VAR = value` | yes | done |
//! | mid_leg_flag, mid_turn_flag | midlegflag, midturnflag | none | `VAR = value` | yes | done |
//! | mid_leg_pct, mid_turn_pct | | 25 | number in [0, 100] (outside: refused) | yes | done |
//! | visual_hints | | | `key=value` list (`HintHolder`: a key with `color` takes a colour, any other a number) | yes | done |
//!
//! The behaviour is perpetual by default (its constructor sets it). Anything else is handed to
//! the leg (MOOS `LegRun::setParam`) and refused there: the corpus mission `x1_legs` writes
//! `legflag` and `mid_pct`, which pHelmIvP at a2a9b716 refuses too (the helm is MALCONFIG).
//!
//! | variable | when | format | coug |
//! |---|---|---|---|
//! | LR_MODE | each mode change | `leg1`, `turn1`, `leg2`, `turn2`, `init` | done |
//! | LR_MODE_REPORT | each mode change | `vname=<ownship>,mode=<mode>,utc=<time>` | done |
//! | LR_NOW_SPD | each function built | the speed asked for | done |
//! | BHV_SETTINGS | configuration and updates | `type=BHV_LegRun,name=..,speed=..,currix=..,capture_radius=..,slip_radius=..[,capture_line=..],patience=..` | done |
//! | BHV_WARNING | configuration and updates | `Invalid or unset legrun` (retracted once valid) | done |
//! | VIEW_SEGLIST | turn preview (start, after a change), each turn | `<ownship>_pview1/2/3` (the two turns, the leg), `<ownship>_turn` | done |
//! | VIEW_POINT | each running iteration | `<ownship>'s next waypoint`, `<ownship>'s track-point` (when more than 5 m apart), `<ownship>_p1`, `<ownship>_p2`, `<ownship>_fpt1/2` (turn previews) | done |
//! | leg/turn end flags, mid flags | a leg or turn ends; passing `mid_leg_pct` / `mid_turn_pct` % of it | flags (repeatable) | done |
//! | endflag | the legs engine completes its repeats | the common endflags (not repeatable; the behaviour does not complete) | done |
//!
//! Macros: `SPEED`, `NI`, `NX`, `CYCLES`, `CYCREM`, `WPTS_HIT`, `MODE`, `DIST_NP`, `DIST_PP`,
//! `PCT_NP`, `LEG_ODO`, `LEG_ID`, `WRAPS`. `NY` is not expanded: the C++ expands `" NY"`.
//!
//! Objective function: ZAIC_PEAK on course (summit the bearing to the track point, base width
//! 180, wrapping) coupled with ZAIC_SPD on speed (summit the leg speed, 0.1 and `speed + 0.4`
//! at utilities 70 and 20), weights `patience` and `100 − patience`, normalised to [0, 100].

use geometry::{Point, Segment};
use ivp::{IvpFunction, ZaicPeak, ZaicSpd, couple_weighted};
use moos_types::fmt::compact;

use crate::behavior::{Behavior, Ctx, Out, ParamError, PostKey, add_flag_vars, add_vars};
use crate::color::Hints;
use crate::common::{Common, Flag};
use crate::param::{atof, is_number, moos_boolean, number};

// ---------------------------------------------------------------------------------------------
// Geometry helpers (MOOS GeomUtils).

fn project(x: f64, y: f64, hdg: f64, dist: f64) -> Point {
    geometry::project_point(x, y, hdg, dist)
}

/// The distance from `(px, py)` to the infinite line through `(x1, y1)` and `(x2, y2)`.
fn dist_to_line(px: f64, py: f64, x1: f64, y1: f64, x2: f64, y2: f64) -> f64 {
    let foot = Segment::from_xy(x1, y1, x2, y2).line_foot(px, py);
    (px - foot.x).hypot(py - foot.y)
}

fn seg_length(pts: &[Point]) -> f64 {
    pts.windows(2)
        .map(|w| (w[1].x - w[0].x).hypot(w[1].y - w[0].y))
        .sum()
}

/// The point `dist` metres along `pts` from its first vertex (MOOS `get_dist_point`).
fn dist_point(pts: &[Point], dist: f64) -> Point {
    match pts {
        [] => Point::new(0.0, 0.0),
        [p] => *p,
        _ if dist <= 0.0 => pts[0],
        _ if dist >= seg_length(pts) => pts[pts.len() - 1],
        _ => {
            let mut sofar = 0.0;
            for w in pts.windows(2) {
                let d = (w[1].x - w[0].x).hypot(w[1].y - w[0].y);
                if sofar + d < dist {
                    sofar += d;
                } else {
                    let t = if d > 0.0 { (dist - sofar) / d } else { 0.0 };
                    return Point::new(
                        w[0].x + t * (w[1].x - w[0].x),
                        w[0].y + t * (w[1].y - w[0].y),
                    );
                }
            }
            pts[pts.len() - 1]
        }
    }
}

// ---------------------------------------------------------------------------------------------
// The turn (MOOS TurnGenWilliamson, as LegRun drives it).

/// A turn from `start` on heading `hdg` back to `end` on the reverse heading, swinging
/// first away from the turn side, around a loop of `radius`, then back in (MOOS
/// `TurnGenWilliamson` as `LegRun` sets it up).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct WilliamsonTurn {
    /// Where the turn starts.
    pub start: Point,
    /// The heading at the start, degrees.
    pub hdg: f64,
    /// Where the turn ends.
    pub end: Point,
    /// The loop's radius, m.
    pub radius: f64,
    /// Degrees between points.
    pub gap: f64,
    /// The lane gap the bias maximum is taken from (LegRun sets 0.1 before generating).
    pub lane_gap0: f64,
    /// Sideways shift of the loop, −100..100 % of its maximum.
    pub bias_pct: f64,
    /// A port turn (else starboard).
    pub port: bool,
}

impl WilliamsonTurn {
    /// The turn's points (MOOS `TurnGenWilliamson::generate`).
    pub fn points(&self) -> Vec<Point> {
        williamson_points(self)
    }
}

fn williamson_points(t: &WilliamsonTurn) -> Vec<Point> {
    let WilliamsonTurn {
        start,
        hdg,
        end,
        radius,
        gap,
        lane_gap0,
        bias_pct,
        port,
    } = *t;
    let osh = geometry::angle_360(hdg);
    let (sx, sy) = (start.x, start.y);
    let r = radius;
    // Bias: the maximum is taken with the lane gap the caller sets (before generation).
    let max_bias = r - lane_gap0 / 2.0;
    let pct = bias_pct.clamp(-100.0, 100.0);
    let bias = ((pct / 100.0) * max_bias).clamp(-max_bias, max_bias);
    // Part 1-3: side of the end point, the lane gap and the natural extent.
    let osang = geometry::relative_angle(sx, sy, end.x, end.y);
    let angle_diff = geometry::angle_180(osang - osh);
    let ahead = project(sx, sy, osh, 20.0);
    let d = dist_to_line(end.x, end.y, sx, sy, ahead.x, ahead.y);
    let side = project(sx, sy, geometry::angle_360(osh + 90.0), 20.0);
    let nat = dist_to_line(end.x, end.y, sx, sy, side.x, side.y);
    let natural = if angle_diff < 90.0 && angle_diff > -90.0 {
        nat
    } else {
        -nat
    };
    let port_angle = geometry::angle_360(osh - 90.0);
    let star_angle = geometry::angle_360(osh + 90.0);
    let mut pts = Vec::new();
    let arc = |pts: &mut Vec<Point>, c: Point, from: f64, lim: f64, sign: f64| {
        let mut delta = 0.0;
        while delta <= lim {
            let a = geometry::angle_360(from + sign * delta);
            pts.push(project(c.x, c.y, a, r));
            delta += gap;
        }
    };
    let shift = |p: Point| {
        if natural > 0.0 {
            project(p.x, p.y, osh, natural)
        } else {
            p
        }
    };
    if 2.0 * r > d {
        // Lane switch 1: the loop is wider than the lanes.
        let v = (r + d / 2.0) / (2.0 * r);
        let theta = v.acos();
        let theta_deg = theta.to_degrees();
        let mut ang_w = (90.0 - theta_deg) * 2.0;
        let dist_b = theta.sin() * (2.0 * r);
        let mut be = dist_b;
        let k1 = r + d / 2.0 - bias;
        let k2 = r + d / 2.0 + bias;
        if bias != 0.0 {
            let m1 = (4.0 * r * r - k1 * k1).sqrt();
            let m2 = (4.0 * r * r - k2 * k2).sqrt();
            if be < m1 {
                be = m1 + 1.0;
            }
            if be < m2 {
                be = m2 + 1.0;
            }
        }
        let (c0, c1, c2) = if port {
            (
                project(sx, sy, port_angle, d / 2.0 - bias),
                project(sx, sy, star_angle, r),
                project(sx, sy, port_angle, r + d),
            )
        } else {
            (
                project(sx, sy, star_angle, d / 2.0 - bias),
                project(sx, sy, star_angle, r + d),
                project(sx, sy, port_angle, r),
            )
        };
        let c3 = project(c0.x, c0.y, osh, be);
        let (c1, c2, c3) = (shift(c1), shift(c2), shift(c3));
        if natural > 0.0 {
            pts.push(start);
        }
        let mut theta1 = theta_deg;
        let mut theta2 = (180.0 - ang_w) / 2.0;
        if be > dist_b {
            let m1 = (be / k1).atan().to_degrees();
            let m2 = (be / k2).atan().to_degrees();
            let h1 = (be * be + k1 * k1).sqrt() / 2.0;
            let h2 = (be * be + k2 * k2).sqrt() / 2.0;
            theta1 = m1 - (r / h1).acos().to_degrees();
            theta2 = m2 - (r / h2).acos().to_degrees();
            ang_w = 180.0 - (theta1 + theta2);
        }
        if port {
            arc(&mut pts, c1, port_angle, theta1, 1.0);
            arc(
                &mut pts,
                c3,
                geometry::angle_360(osh + 90.0 + theta1),
                360.0 - ang_w,
                -1.0,
            );
            arc(
                &mut pts,
                c2,
                geometry::angle_360(star_angle - theta2),
                theta2,
                1.0,
            );
        } else {
            arc(&mut pts, c2, star_angle, theta1, -1.0);
            arc(
                &mut pts,
                c3,
                geometry::angle_360(osh - 90.0 - theta1),
                360.0 - ang_w,
                1.0,
            );
            arc(
                &mut pts,
                c1,
                geometry::angle_360(port_angle + theta2),
                theta2,
                -1.0,
            );
        }
    } else {
        // Lane switch 2: lanes farther apart than the loop.
        let k = d / 2.0 - r;
        let c0 = project(sx, sy, if port { port_angle } else { star_angle }, d / 2.0);
        let c3 = c0;
        let c1 = shift(project(c3.x, c3.y, star_angle, k));
        let c2 = shift(project(c3.x, c3.y, port_angle, k));
        if natural > 0.0 {
            pts.push(start);
        }
        if port {
            arc(&mut pts, c1, geometry::angle_360(osh + 90.0), 90.0, -1.0);
            arc(&mut pts, c2, osh, 90.0, -1.0);
        } else {
            arc(&mut pts, c2, geometry::angle_360(osh - 90.0), 90.0, 1.0);
            arc(&mut pts, c1, osh, 90.0, 1.0);
        }
    }
    if natural < 0.0 {
        pts.push(end);
    }
    pts
}

// ---------------------------------------------------------------------------------------------
// The leg (MOOS LegRun).

/// The leg's end points and the turns at each end (MOOS `LegRun`).
#[derive(Debug, Clone)]
pub struct LegGeometry {
    /// First end point.
    pub p1: Option<Point>,
    /// Second end point.
    pub p2: Option<Point>,
    /// Turn radius at `p1` (−1 = unset).
    pub turn1_rad: f64,
    /// Turn radius at `p2` (−1 = unset).
    pub turn2_rad: f64,
    /// Smallest turn radius.
    pub turn_rad_min: f64,
    /// Extension of the leg before the turn at `p1`.
    pub turn1_ext: f64,
    /// Extension of the leg before the turn at `p2`.
    pub turn2_ext: f64,
    /// Bias of the turn at `p1`, %.
    pub turn1_bias: f64,
    /// Bias of the turn at `p2`, %.
    pub turn2_bias: f64,
    /// The turn at `p1` is to port.
    pub turn1_port: bool,
    /// The turn at `p2` is to port.
    pub turn2_port: bool,
    /// Degrees between turn points.
    pub turn_pt_gap: f64,
    /// The leg's id.
    pub id: String,
    modified: bool,
}

impl Default for LegGeometry {
    fn default() -> Self {
        LegGeometry {
            p1: None,
            p2: None,
            turn1_rad: -1.0,
            turn2_rad: -1.0,
            turn_rad_min: 2.0,
            turn1_ext: 0.0,
            turn2_ext: 0.0,
            turn1_bias: 0.0,
            turn2_bias: 0.0,
            turn1_port: true,
            turn2_port: true,
            turn_pt_gap: 20.0,
            id: String::new(),
            modified: true,
        }
    }
}

fn parse_pt(s: &str) -> Option<Point> {
    let t = s.trim();
    let t = if !t.contains(',') && t.contains(':') {
        t.replacen(':', ",", 1)
    } else {
        t.to_string()
    };
    geometry::spec::parse_point(&t).ok().map(|p| p.point)
}

fn num(v: &str) -> Option<f64> {
    is_number(v.trim()).then(|| atof(v.trim()))
}

impl LegGeometry {
    /// Whether both points and both turn radii are set (MOOS `LegRun::valid`).
    pub fn valid(&self) -> bool {
        self.turn1_rad >= 0.0 && self.turn2_rad >= 0.0 && self.p1.is_some() && self.p2.is_some()
    }

    fn pts(&self) -> (Point, Point) {
        let z = Point::new(0.0, 0.0);
        (self.p1.unwrap_or(z), self.p2.unwrap_or(z))
    }

    /// The leg's length, −1 without both points.
    pub fn leg_len(&self) -> f64 {
        match (self.p1, self.p2) {
            (Some(a), Some(b)) => (a.x - b.x).hypot(a.y - b.y),
            _ => -1.0,
        }
    }

    /// The bearing `p1 → p2`, −1 without both points.
    pub fn leg_ang(&self) -> f64 {
        match (self.p1, self.p2) {
            (Some(a), Some(b)) => geometry::relative_angle(a.x, a.y, b.x, b.y),
            _ => -1.0,
        }
    }

    /// The leg's middle.
    pub fn center(&self) -> Point {
        let (a, b) = self.pts();
        Point::new((a.x + b.x) / 2.0, (a.y + b.y) / 2.0)
    }

    fn set_aux(&mut self, cx: f64, cy: f64, ang: f64, len: f64) -> bool {
        if len <= 0.0 {
            return false;
        }
        self.p1 = Some(project(cx, cy, ang - 180.0, len / 2.0));
        self.p2 = Some(project(cx, cy, ang, len / 2.0));
        true
    }

    fn set_rad(&mut self, which: u8, v: f64) -> bool {
        if v <= 0.0 {
            return false;
        }
        let v = v.max(self.turn_rad_min);
        if which != 2 {
            self.turn1_rad = v;
        }
        if which != 1 {
            self.turn2_rad = v;
        }
        true
    }

    fn set_ext(&mut self, which: u8, v: f64) -> bool {
        if v < 0.0 {
            return false;
        }
        if which != 2 {
            self.turn1_ext = v;
        }
        if which != 1 {
            self.turn2_ext = v;
        }
        true
    }

    fn set_bias(&mut self, which: u8, v: f64) {
        let v = v.clamp(-100.0, 100.0);
        if which != 2 {
            self.turn1_bias = v;
        }
        if which != 1 {
            self.turn2_bias = v;
        }
    }

    fn set_dir(port: &mut bool, v: &str) -> bool {
        match v.to_ascii_lowercase().as_str() {
            // The C++ toggles port to "start", which is not port.
            "toggle" => *port = !*port,
            "port" => *port = true,
            "star" | "starboard" => *port = false,
            _ => return false,
        }
        true
    }

    fn set_leg(&mut self, v: &str) -> bool {
        let (mut xs, mut ys, mut angs, mut lens) = ("", "", "", "");
        let lower = v.to_ascii_lowercase();
        if lower.contains("x=") {
            for part in lower.split(',') {
                let (k, val) = part.split_once('=').unwrap_or((part, ""));
                match k.trim() {
                    "x" => xs = val,
                    "y" => ys = val,
                    "ang" => angs = val,
                    "len" => lens = val,
                    _ => return false,
                }
            }
            match (num(xs), num(ys), num(angs), num(lens)) {
                (Some(x), Some(y), Some(a), Some(l)) => self.set_aux(x, y, a, l),
                _ => false,
            }
        } else {
            let f: Vec<&str> = v.split(':').collect();
            if f.len() != 4 {
                return false;
            }
            match (num(f[0]), num(f[1]), num(f[2]), num(f[3])) {
                (Some(x), Some(y), Some(a), Some(l)) => self.set_aux(x, y, a, l),
                _ => false,
            }
        }
    }

    fn shift_to(&mut self, v: &str) -> bool {
        if self.p1.is_none() || self.p2.is_none() {
            return false;
        }
        let (len, ang) = (self.leg_len(), self.leg_ang());
        let xs = moos_types::text::tok_string_parse(v, "x");
        let ys = moos_types::text::tok_string_parse(v, "y");
        let (cx, cy) = match (num(xs), num(ys)) {
            (Some(x), Some(y)) => (x, y),
            _ => {
                let s = v.replace(',', ":");
                let f: Vec<&str> = s.split(':').collect();
                if f.len() != 2 {
                    return false;
                }
                match (num(f[0]), num(f[1])) {
                    (Some(x), Some(y)) => (x, y),
                    _ => return false,
                }
            }
        };
        self.set_aux(cx, cy, ang, len)
    }

    /// Sets one leg parameter (MOOS `LegRun::setParam`); false when refused or unknown.
    pub fn set_param(&mut self, param: &str, val: &str) -> bool {
        self.modified = true;
        let n = num(val);
        match (param, n) {
            ("p1" | "vx1", _) => parse_pt(val).map(|p| self.p1 = Some(p)).is_some(),
            ("p2" | "vx2", _) => parse_pt(val).map(|p| self.p2 = Some(p)).is_some(),
            ("leg", _) => self.set_leg(val),
            ("leg_len", Some(v)) => {
                let c = self.center();
                v > 0.0 && self.set_aux(c.x, c.y, self.leg_ang(), v)
            }
            ("leg_len_mod", Some(v)) => {
                let (c, l) = (self.center(), self.leg_len() + v);
                l > 0.0 && self.set_aux(c.x, c.y, self.leg_ang(), l)
            }
            ("leg_ang", Some(v)) => {
                let c = self.center();
                self.set_aux(c.x, c.y, v, self.leg_len())
            }
            ("leg_ang_mod", Some(v)) => {
                let c = self.center();
                self.set_aux(c.x, c.y, self.leg_ang() + v, self.leg_len())
            }
            ("shift_pt", _) => self.shift_to(val),
            ("turn1_bias", Some(v)) => {
                self.set_bias(1, v);
                true
            }
            ("turn2_bias", Some(v)) => {
                self.set_bias(2, v);
                true
            }
            ("turn_bias", Some(v)) => {
                self.set_bias(0, v);
                true
            }
            ("turn1_bias_mod", Some(v)) => {
                self.set_bias(1, self.turn1_bias + v);
                true
            }
            ("turn2_bias_mod", Some(v)) => {
                self.set_bias(2, self.turn2_bias + v);
                true
            }
            ("turn_bias_mod", Some(v)) => {
                let (b1, b2) = (self.turn1_bias + v, self.turn2_bias + v);
                self.set_bias(1, b1);
                self.set_bias(2, b2);
                true
            }
            ("turn1_ext", Some(v)) => self.set_ext(1, v),
            ("turn2_ext", Some(v)) => self.set_ext(2, v),
            ("turn_ext", Some(v)) => self.set_ext(0, v),
            ("turn1_ext_mod", Some(v)) => self.set_ext(1, self.turn1_ext + v),
            ("turn2_ext_mod", Some(v)) => self.set_ext(2, self.turn2_ext + v),
            ("turn_ext_mod", Some(v)) => {
                let (e1, e2) = (self.turn1_ext + v, self.turn2_ext + v);
                self.set_ext(1, e1) && self.set_ext(2, e2)
            }
            ("turn1_rad", Some(v)) => self.set_rad(1, v),
            ("turn2_rad", Some(v)) => self.set_rad(2, v),
            ("turn_rad", Some(v)) => self.set_rad(0, v),
            ("turn_rad_min", Some(v)) => {
                if v <= 0.0 {
                    return false;
                }
                self.turn_rad_min = v;
                true
            }
            ("turn1_rad_mod", Some(v)) => self.set_rad(1, self.turn1_rad + v),
            ("turn2_rad_mod", Some(v)) => self.set_rad(2, self.turn2_rad + v),
            ("turn_rad_mod", Some(v)) => {
                let (r1, r2) = (self.turn1_rad + v, self.turn2_rad + v);
                self.set_rad(1, r1) && self.set_rad(2, r2)
            }
            ("turn_pt_gap", Some(v)) => {
                self.turn_pt_gap = v.max(0.5);
                true
            }
            ("turn1_dir", _) => Self::set_dir(&mut self.turn1_port, val),
            ("turn2_dir", _) => Self::set_dir(&mut self.turn2_port, val),
            ("turn_dir", _) => {
                Self::set_dir(&mut self.turn1_port, val);
                Self::set_dir(&mut self.turn2_port, val)
            }
            ("id", _) => {
                self.id = val.to_string();
                true
            }
            _ => false,
        }
    }

    /// The turn at `p1` (`which = 1`: from the end of leg 1 back onto the heading `p1 → p2`)
    /// or at `p2` (`which = 2`), empty without both points (MOOS `initTurnPoints1/2`).
    pub fn turn_points(&self, which: u8) -> Vec<Point> {
        let (Some(p1), Some(p2)) = (self.p1, self.p2) else {
            return Vec::new();
        };
        let (at, to, ext, rad, bias, port) = if which == 1 {
            (
                p1,
                p2,
                self.turn1_ext,
                self.turn1_rad,
                self.turn1_bias,
                self.turn1_port,
            )
        } else {
            (
                p2,
                p1,
                self.turn2_ext,
                self.turn2_rad,
                self.turn2_bias,
                self.turn2_port,
            )
        };
        // The heading the turn ends on (away from this end); it starts on the reverse.
        let th = geometry::relative_angle(at.x, at.y, to.x, to.y);
        let mut pts = Vec::new();
        let mut start = at;
        if ext > 0.0 {
            pts.push(at);
            start = project(at.x, at.y, th - 180.0, ext);
        }
        // The generator's radius is only taken when positive (TurnGenerator: 10 otherwise).
        let r = if rad > 0.0 { rad } else { 10.0 };
        let turn = WilliamsonTurn {
            start,
            hdg: th + 180.0,
            end: at,
            radius: r,
            gap: self.turn_pt_gap,
            lane_gap0: 0.1,
            bias_pct: bias,
            port,
        };
        pts.extend(turn.points());
        pts
    }
}

// ---------------------------------------------------------------------------------------------
// The waypoint engine (MOOS WaypointEngineX).

#[derive(Debug, Clone, Copy, PartialEq, Eq)]
enum WptState {
    Empty,
    Transit,
    Advanced,
    Cycled,
    Completed,
}

/// A waypoint engine over a list of points (MOOS `WaypointEngineX`).
#[derive(Debug, Clone)]
struct WptEngine {
    pts: Vec<Point>,
    capture_line: bool,
    capture_radius: f64,
    slip_radius: f64,
    max_repeats: i64,
    lead: f64,
    lead_damper: f64,
    curr_ix: usize,
    state: WptState,
    current_cpa: f64,
    hits: u32,
    repeats_sofar: u32,
    prevpt: Option<Point>,
    trackpt: Point,
}

impl Default for WptEngine {
    fn default() -> Self {
        WptEngine {
            pts: Vec::new(),
            capture_line: false,
            capture_radius: 3.0,
            slip_radius: 15.0,
            max_repeats: 0,
            lead: 0.0,
            lead_damper: 0.0,
            curr_ix: 0,
            state: WptState::Transit,
            current_cpa: -1.0,
            hits: 0,
            repeats_sofar: 0,
            prevpt: None,
            trackpt: Point::new(0.0, 0.0),
        }
    }
}

impl WptEngine {
    /// MOOS `WaypointEngineX::setParam` for the parameters LegRun hands it.
    fn set_param(&mut self, param: &str, value: &str) -> bool {
        let lv = value.to_ascii_lowercase();
        match param {
            "repeat" => {
                if lv == "forever" {
                    self.max_repeats = -1;
                } else if is_number(value) {
                    let n = atof(value) as i64;
                    if n < 0 {
                        return false;
                    }
                    self.max_repeats = n;
                }
                true
            }
            "radius" | "capture_radius" => {
                let d = atof(value);
                if d < 0.0 {
                    return false;
                }
                self.capture_radius = d;
                true
            }
            "slip_radius" => {
                let d = atof(value);
                if d < 0.0 {
                    return false;
                }
                self.slip_radius = d;
                true
            }
            "capture_line" => {
                match lv.as_str() {
                    "true" => self.capture_line = true,
                    "false" => self.capture_line = false,
                    "absolute" => {
                        self.capture_line = true;
                        self.capture_radius = 0.0;
                        self.slip_radius = 0.0;
                    }
                    _ => return false,
                }
                true
            }
            "lead" | "lead_damper" => match num(value) {
                Some(d) if d >= 0.0 => {
                    if param == "lead" {
                        self.lead = d;
                    } else {
                        self.lead_damper = d;
                    }
                    true
                }
                _ => false,
            },
            _ => false,
        }
    }

    fn reset_state(&mut self) {
        self.pts.clear();
        self.prevpt = None;
        self.curr_ix = 0;
        self.state = WptState::Transit;
        self.current_cpa = -1.0;
        self.hits = 0;
        self.repeats_sofar = 0;
    }

    fn set_points(&mut self, pts: Vec<Point>, retain: bool) {
        self.state = WptState::Transit;
        self.current_cpa = -1.0;
        self.repeats_sofar = 0;
        self.pts = pts;
        if retain {
            let n = self.pts.len();
            let ix = if self.curr_ix == 0 {
                n.checked_sub(1)
            } else {
                Some(self.curr_ix - 1)
            };
            if let Some(p) = ix.and_then(|i| self.pts.get(i)) {
                self.prevpt = Some(*p);
            }
        } else {
            self.curr_ix = 0;
        }
    }

    fn set_curr_index(&mut self, ix: usize) {
        if ix < self.pts.len() {
            self.curr_ix = ix;
            self.current_cpa = -1.0;
        }
    }

    fn point(&self) -> Point {
        self.pts
            .get(self.curr_ix)
            .copied()
            .unwrap_or(Point::new(0.0, 0.0))
    }

    fn reset_for_new_traversal(&mut self) {
        self.curr_ix = 0;
        self.state = WptState::Transit;
        self.current_cpa = -1.0;
        self.prevpt = None;
        self.repeats_sofar = 0;
    }

    fn repeats_remaining(&self) -> u32 {
        let max = self.max_repeats as u32;
        if self.repeats_sofar > max {
            0
        } else {
            max.wrapping_sub(self.repeats_sofar)
        }
    }

    fn completed(&self) -> bool {
        self.state == WptState::Completed
    }

    fn advanced(&self) -> bool {
        matches!(
            self.state,
            WptState::Completed | WptState::Cycled | WptState::Advanced
        )
    }

    fn set_next_waypoint(&mut self, osx: f64, osy: f64) {
        if self.prevpt.is_none() {
            self.prevpt = Some(Point::new(osx, osy));
        }
        self.state = self.step(osx, osy);
        self.trackpt = self.point();
        if !matches!(self.state, WptState::Completed | WptState::Empty) {
            self.calc_track_point(osx, osy);
        }
    }

    fn step(&mut self, osx: f64, osy: f64) -> WptState {
        let n = self.pts.len();
        if n == 0 {
            return WptState::Empty;
        }
        if self.completed() {
            return WptState::Completed;
        }
        let c = self.point();
        let dist = (osx - c.x).hypot(osy - c.y);
        if self.current_cpa == -1.0 || dist < self.current_cpa {
            self.current_cpa = dist;
        }
        // Captured, or slipped past within the slip radius.
        let mut advance = dist < self.capture_radius
            || (self.slip_radius > self.capture_radius
                && dist > self.current_cpa
                && self.current_cpa <= self.slip_radius);
        if advance {
            self.hits += 1;
        }
        if !advance
            && self.capture_line
            && let Some(p) = self.prevpt
            && geometry::angle::angle_at_vertex(p.x, p.y, c.x, c.y, osx, osy) >= 90.0
        {
            advance = true;
            self.hits += 1;
        }
        if !advance {
            return WptState::Transit;
        }
        self.curr_ix += 1;
        self.prevpt = Some(self.pts[self.curr_ix - 1]);
        if self.curr_ix >= n {
            self.curr_ix = 0;
            self.current_cpa = -1.0;
            self.repeats_sofar += 1;
            if self.max_repeats >= 0 && i64::from(self.repeats_sofar) > self.max_repeats {
                self.prevpt = None;
                return WptState::Completed;
            }
            return WptState::Cycled;
        }
        let c = self.point();
        self.current_cpa = (osx - c.x).hypot(osy - c.y);
        WptState::Advanced
    }

    fn calc_track_point(&mut self, osx: f64, osy: f64) {
        if self.lead <= 0.0 || self.lead_damper <= 0.0 {
            return;
        }
        let Some(p) = self.prevpt else {
            return;
        };
        let c = self.point();
        let seg = Segment::from_xy(p.x, p.y, c.x, c.y);
        self.trackpt = seg.lead_point_damped(osx, osy, self.lead, self.lead_damper);
    }

    fn dist_to_next(&self, osx: f64, osy: f64) -> f64 {
        match self.pts.get(self.curr_ix) {
            Some(c) => (osx - c.x).hypot(osy - c.y),
            None => -1.0,
        }
    }

    fn dist_to_prev(&self, osx: f64, osy: f64) -> f64 {
        self.prevpt.map_or(-1.0, |p| (osx - p.x).hypot(osy - p.y))
    }

    /// MOOS `pctToNextWpt`: the share of the way from the previous point (the last one for
    /// index 0) to the next.
    fn pct_to_next(&self, osx: f64, osy: f64) -> f64 {
        let z = Point::new(0.0, 0.0);
        let curr = self.pts.get(self.curr_ix).copied().unwrap_or(z);
        let prev = if self.curr_ix > 0 {
            self.pts.get(self.curr_ix - 1).copied().unwrap_or(z)
        } else {
            self.pts.last().copied().unwrap_or(z)
        };
        let dn = (osx - curr.x).hypot(osy - curr.y);
        let dp = (osx - prev.x).hypot(osy - prev.y);
        let total = dn + dp;
        if total <= 0.0 { -1.0 } else { dp / total }
    }

    /// MOOS `pctToEnd`: distance done over the list's length.
    fn pct_to_end(&self, osx: f64, osy: f64) -> f64 {
        let len = seg_length(&self.pts);
        if len <= 0.0 {
            return 0.0;
        }
        let rest = self.pts.get(self.curr_ix..).map_or(0.0, seg_length);
        let to_end = self.dist_to_next(osx, osy) + rest;
        (len - to_end).max(0.0) / len
    }
}

// ---------------------------------------------------------------------------------------------
// Wrap detection (MOOS WrapDetector) and the odometer.

#[derive(Debug, Clone, Default)]
struct WrapDetector {
    last: Option<Point>,
    legs: std::collections::VecDeque<Segment>,
    wraps: u32,
}

impl WrapDetector {
    fn update(&mut self, x: f64, y: f64) {
        let Some(last) = self.last else {
            self.last = Some(Point::new(x, y));
            return;
        };
        let seg = Segment::from_xy(last.x, last.y, x, y);
        if seg.length() < 1.0 {
            return;
        }
        let n = self.legs.len();
        let wrapped = n > 1 && self.legs.iter().take(n - 1).any(|s| s.crosses(&seg));
        if !wrapped {
            self.legs.push_back(seg);
            if self.legs.len() > 5000 {
                self.legs.pop_front();
            }
            self.last = Some(Point::new(x, y));
            return;
        }
        self.wraps += 1;
        self.last = None;
        self.legs.clear();
    }
    fn reset(&mut self) {
        *self = WrapDetector::default();
    }
}

#[derive(Debug, Clone, Default)]
struct Odometer {
    prev: Option<(f64, f64)>,
    total: f64,
    paused: bool,
}

impl Odometer {
    fn update(&mut self, x: f64, y: f64) {
        if let Some((px, py)) = self.prev
            && !self.paused
        {
            self.total += (x - px).hypot(y - py);
        }
        self.prev = Some((x, y));
    }
    fn reset(&mut self) {
        self.prev = None;
        self.total = 0.0;
    }
}

// ---------------------------------------------------------------------------------------------
// The behaviour.

/// The mode the behaviour is in.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum LegMode {
    /// Before the first run, and after the leg changes.
    Init,
    /// Towards `p1`.
    Leg1,
    /// Turning at `p1`.
    Turn1,
    /// Towards `p2`.
    Leg2,
    /// Turning at `p2`.
    Turn2,
}

impl LegMode {
    /// The name the behaviour posts (`LR_MODE`).
    pub fn name(self) -> &'static str {
        match self {
            LegMode::Init => "init",
            LegMode::Leg1 => "leg1",
            LegMode::Turn1 => "turn1",
            LegMode::Leg2 => "leg2",
            LegMode::Turn2 => "turn2",
        }
    }
    fn next(self) -> Option<LegMode> {
        match self {
            LegMode::Leg1 => Some(LegMode::Turn1),
            LegMode::Turn1 => Some(LegMode::Leg2),
            LegMode::Leg2 => Some(LegMode::Turn2),
            LegMode::Turn2 => Some(LegMode::Leg1),
            LegMode::Init => None,
        }
    }
    fn is_leg(self) -> bool {
        matches!(self, LegMode::Leg1 | LegMode::Leg2)
    }
    fn is_turn(self) -> bool {
        matches!(self, LegMode::Turn1 | LegMode::Turn2)
    }
}

#[derive(Debug, Clone, Default)]
struct Flags {
    mid_leg: Vec<Flag>,
    mid_turn: Vec<Flag>,
    leg_end: Vec<Flag>,
    leg1_end: Vec<Flag>,
    leg2_end: Vec<Flag>,
    turn_end: Vec<Flag>,
    turn1_end: Vec<Flag>,
    turn2_end: Vec<Flag>,
}

/// Runs a leg back and forth with turns at its ends (see the module docs).
#[derive(Debug, Clone)]
pub struct LegRun {
    /// The leg and its turns.
    pub leg: LegGeometry,
    /// Cruise speed, m/s.
    pub cruise_spd: f64,
    /// Course weight in the coupling, [1, 99].
    pub patience: f64,
    /// `fixed`, `close_turn`, `far_turn` or `resume`.
    pub init_leg_mode: String,
    /// Percent of a leg after which the mid-leg flags go out.
    pub mid_leg_pct: f64,
    /// Percent of a turn after which the mid-turn flags go out.
    pub mid_turn_pct: f64,
    /// Leg speed schedule.
    pub leg_spds: Vec<f64>,
    /// Start the schedule again once done.
    pub leg_spds_repeat: bool,
    /// Keep a leg's speed through the next turn.
    pub leg_spds_onturn: bool,
    max_spd: f64,
    hints: Hints,
    flags: Flags,
    legs: WptEngine,
    turn: WptEngine,
    odometer: Odometer,
    wraps: WrapDetector,
    // State.
    mode: LegMode,
    pending: Option<LegMode>,
    nextpt: Point,
    trackpt: Point,
    turn_pt1: Option<Point>,
    turn_pt2: Option<Point>,
    mid_leg_done: bool,
    mid_turn_done: bool,
    preview_pending: bool,
    leg_count1: u32,
    leg_count2: u32,
    spds_ix: usize,
    spds_curr: f64,
    os: (f64, f64),
}

impl Default for LegRun {
    fn default() -> Self {
        Self::new()
    }
}

impl LegRun {
    /// The MOOS defaults.
    pub fn new() -> Self {
        let mut hints = Hints::default();
        for (k, v) in [
            ("vertex_size", "3"),
            ("edge_size", "1"),
            ("nextpt_vertex_size", "3"),
            ("legpt_vertex_size", "7"),
            ("turn_vertex_size", "2"),
            ("turn_edge_size", "1"),
        ] {
            hints.set_measure(k, v);
        }
        for (k, v) in [
            ("vertex_color", "dodger_blue"),
            ("edge_color", "gray60"),
            ("label_color", "off"),
            ("nextpt_vertex_color", "yellow"),
            ("nextpt_label_color", "aqua"),
            ("legpt_vertex_color", "orange"),
            ("legpt_label_color", "off"),
            ("turn_vertex_color", "gray70"),
            ("turn_edge_color", "gray30"),
            ("turn_label_color", "off"),
        ] {
            hints.set_color(k, v);
        }
        LegRun {
            leg: LegGeometry::default(),
            cruise_spd: 0.0,
            patience: 50.0,
            init_leg_mode: "fixed".into(),
            mid_leg_pct: 25.0,
            mid_turn_pct: 25.0,
            leg_spds: Vec::new(),
            leg_spds_repeat: false,
            leg_spds_onturn: false,
            max_spd: 0.0,
            hints,
            flags: Flags::default(),
            legs: WptEngine::default(),
            turn: WptEngine::default(),
            odometer: Odometer::default(),
            wraps: WrapDetector::default(),
            mode: LegMode::Init,
            pending: None,
            nextpt: Point::new(0.0, 0.0),
            trackpt: Point::new(0.0, 0.0),
            turn_pt1: None,
            turn_pt2: None,
            mid_leg_done: false,
            mid_turn_done: false,
            preview_pending: true,
            leg_count1: 0,
            leg_count2: 0,
            spds_ix: 0,
            spds_curr: -1.0,
            os: (0.0, 0.0),
        }
    }

    /// The mode the behaviour is in.
    pub fn mode(&self) -> LegMode {
        self.mode
    }

    /// The point the course function aims at (the track point of the leg or turn).
    pub fn track_point(&self) -> Point {
        self.trackpt
    }

    /// The legs and turns finished since the start.
    pub fn legs_done(&self) -> u32 {
        self.leg_count1 + self.leg_count2
    }

    /// The speed the next function asks for: the schedule's, else the cruise speed.
    pub fn now_speed(&self) -> f64 {
        if self.spds_curr > 0.0 {
            self.spds_curr
        } else {
            self.cruise_spd
        }
    }

    fn set_leg_spds(&mut self, value: &str) -> bool {
        let mut s: String = value
            .chars()
            .filter(|c| !c.is_whitespace())
            .collect::<String>()
            .to_ascii_lowercase();
        if s == "clear" {
            self.leg_spds.clear();
            self.spds_ix = 0;
            return true;
        }
        if s == "reset" {
            self.spds_ix = 0;
            return true;
        }
        if let Some(rest) = s.strip_prefix("replace,") {
            self.leg_spds.clear();
            self.spds_ix = 0;
            s = rest.to_string();
        }
        let mut new = Vec::new();
        for piece in s.split(',') {
            let (amt, spd) = match piece.split_once(':') {
                Some((a, sp)) => {
                    let (Some(a), Some(sp)) = (num(a), num(sp)) else {
                        return false;
                    };
                    let n = a as i64;
                    if n <= 0 {
                        return false;
                    }
                    (n, sp)
                }
                None => match num(piece) {
                    Some(sp) => (1, sp),
                    None => return false,
                },
            };
            if spd < 0.0 || spd > self.max_spd {
                return false;
            }
            for _ in 0..amt {
                new.push(spd);
            }
        }
        self.leg_spds.extend(new);
        true
    }

    /// Posts `flags` with this behaviour's macros expanded now, as the C++ expands them when
    /// it posts a flag (the helm expands the common macros).
    fn post_flags(&self, out: &mut Out, flags: &[Flag], repeatable: bool) {
        for f in flags {
            let mut f = f.clone();
            if let crate::common::FlagValue::String(s) = &mut f.value
                && s.contains('$')
            {
                for m in MACROS {
                    for pat in [format!("$[{m}]"), format!("$({m})")] {
                        if s.contains(&pat) {
                            let mut v = String::new();
                            self.macro_value(m, &mut v);
                            *s = s.replace(&pat, &v).into();
                        }
                    }
                }
            }
            out.flag(&f, repeatable);
        }
    }

    fn set_mode(&mut self, mode: LegMode, ctx: &Ctx<'_>, out: &mut Out) {
        self.mode = mode;
        out.post("LR_MODE", mode.name());
        let mut r = format!("vname={},mode={},utc=", ctx.ownship, mode.name());
        compact(&mut r, ctx.info.now(), 5);
        out.post("LR_MODE_REPORT", r);
    }

    fn init_leg_mode(&mut self, ctx: &Ctx<'_>, out: &mut Out) {
        if self.mode != LegMode::Init {
            return;
        }
        let first = match self.init_leg_mode.as_str() {
            "fixed" => true,
            m @ ("far_turn" | "close_turn") => {
                let (p1, p2) = self.leg.pts();
                let d1 = (self.os.0 - p1.x).hypot(self.os.1 - p1.y);
                let d2 = (self.os.0 - p2.x).hypot(self.os.1 - p2.y);
                if m == "far_turn" { d1 > d2 } else { d1 < d2 }
            }
            _ => {
                out.error("Bad init leg direction, check init_leg_mode param.");
                return;
            }
        };
        if first {
            self.set_mode(LegMode::Leg1, ctx, out);
            self.legs.set_curr_index(0);
        } else {
            self.set_mode(LegMode::Leg2, ctx, out);
            self.legs.set_curr_index(1);
        }
    }

    fn handle_mode_switch(&mut self, ctx: &Ctx<'_>, out: &mut Out) {
        let Some(next) = self.pending.take() else {
            return;
        };
        if next == self.mode {
            return;
        }
        self.set_mode(next, ctx, out);
        self.mid_leg_done = false;
        self.mid_turn_done = false;
        match next {
            LegMode::Turn1 => {
                self.leg_count1 += 1;
                self.init_turn(ctx, out);
            }
            LegMode::Turn2 => {
                self.leg_count2 += 1;
                self.init_turn(ctx, out);
            }
            _ => {}
        }
        self.update_leg_spd();
    }

    fn update_leg_spd(&mut self) {
        if self.mode.is_leg() {
            self.spds_curr = -1.0;
            if !self.leg_spds.is_empty() {
                if self.spds_ix >= self.leg_spds.len() {
                    if self.leg_spds_repeat {
                        self.spds_ix = 0;
                        self.spds_curr = self.leg_spds[0];
                    } else {
                        self.leg_spds.clear();
                    }
                } else {
                    self.spds_curr = self.leg_spds[self.spds_ix];
                    self.spds_ix += 1;
                }
            }
        }
        if self.mode.is_turn() && !self.leg_spds_onturn {
            self.spds_curr = -1.0;
        }
    }

    fn init_turn(&mut self, ctx: &Ctx<'_>, out: &mut Out) {
        let pts = match self.mode {
            LegMode::Turn1 => self.leg.turn_points(1),
            LegMode::Turn2 => self.leg.turn_points(2),
            _ => return,
        };
        self.turn.reset_state();
        self.turn.set_points(pts, false);
        self.post_turn_seglist(ctx, out, true);
    }

    fn run_leg_mode(&mut self, ctx: &Ctx<'_>, out: &mut Out) -> bool {
        if self.legs.pts.is_empty() {
            return false;
        }
        let (x, y) = self.os;
        self.legs.set_next_waypoint(x, y);
        if self.legs.advanced() {
            self.post_flags(out, &self.flags.leg_end, true);
            match self.mode {
                LegMode::Leg1 => self.post_flags(out, &self.flags.leg1_end, true),
                LegMode::Leg2 => self.post_flags(out, &self.flags.leg2_end, true),
                _ => {}
            }
            self.pending = self.mode.next();
            self.odometer.paused = true;
        }
        if self.legs.completed() {
            out.end_flags(false);
            if ctx.perpetual {
                self.legs.reset_for_new_traversal();
            }
            self.post_steer_points(ctx, out, false);
            return false;
        }
        self.trackpt = self.legs.trackpt;
        self.nextpt = self.legs.point();
        self.post_steer_points(ctx, out, true);
        self.post_leg_points(ctx, out, true);
        let pct = 100.0 * self.legs.pct_to_next(x, y);
        if pct > self.mid_leg_pct && !self.mid_leg_done {
            self.post_flags(out, &self.flags.mid_leg, true);
            self.mid_leg_done = true;
        }
        true
    }

    fn run_turn_mode(&mut self, ctx: &Ctx<'_>, out: &mut Out) -> bool {
        let (x, y) = self.os;
        self.turn.set_next_waypoint(x, y);
        self.trackpt = self.turn.trackpt;
        self.nextpt = self.turn.point();
        if self.turn.completed() {
            self.post_flags(out, &self.flags.turn_end, true);
            match self.mode {
                LegMode::Turn1 => self.post_flags(out, &self.flags.turn1_end, true),
                LegMode::Turn2 => self.post_flags(out, &self.flags.turn2_end, true),
                _ => {}
            }
            self.pending = self.mode.next();
            self.post_turn_seglist(ctx, out, false);
            self.post_steer_points(ctx, out, false);
            self.wraps.reset();
            self.odometer.reset();
            self.odometer.paused = false;
            return false;
        }
        if self.turn.advanced() {
            self.post_turn_seglist(ctx, out, true);
        }
        self.post_steer_points(ctx, out, true);
        self.post_leg_points(ctx, out, true);
        let pct = 100.0 * self.turn.pct_to_end(x, y);
        if pct > self.mid_turn_pct && !self.mid_turn_done {
            self.post_flags(out, &self.flags.mid_turn, true);
            self.mid_turn_done = true;
        }
        true
    }

    fn run_mode(&mut self, ctx: &Ctx<'_>, out: &mut Out) -> bool {
        if self.mode.is_leg() {
            self.run_leg_mode(ctx, out)
        } else if self.mode.is_turn() {
            self.run_turn_mode(ctx, out)
        } else {
            false
        }
    }

    /// The objective function for the current track point and speed.
    pub fn build_of(&self, ctx: &Ctx<'_>, out: &mut Out) -> Option<IvpFunction> {
        let spd_now = self.now_speed();
        out.post("LR_NOW_SPD", spd_now);
        let spd = ZaicSpd::new(ctx.domain, "speed", spd_now, 0.1, spd_now + 0.4, 70.0, 20.0)
            .and_then(|z| z.extract());
        let spd = match spd {
            Ok(f) => Some(f),
            Err(_) => {
                out.warning(ctx.name, "Failure on the SPD ZAIC via ZAIC_SPD utility");
                None
            }
        };
        let ang = geometry::relative_angle(self.os.0, self.os.1, self.trackpt.x, self.trackpt.y);
        let crs = ZaicPeak::new(ctx.domain, "course").and_then(|mut z| {
            z.set_value_wrap(true);
            z.set_params(ang, 0.0, 180.0, 0.0, 0.0, 100.0)?;
            z.extract()
        });
        let crs = match crs {
            Ok(f) => Some(f),
            Err(_) => {
                out.warning(ctx.name, "Failure on the CRS ZAIC");
                None
            }
        };
        let f = match (crs, spd) {
            (Some(c), Some(s)) => {
                couple_weighted(&c, &s, self.patience, 100.0 - self.patience, true).ok()
            }
            _ => None,
        };
        if f.is_none() {
            out.warning(ctx.name, "Failure on the CRS_SPD COUPLER");
        }
        f
    }

    // ----- drawings -----

    fn view_seglist(&self, pts: &[Point], label: String, prefix: &str) -> String {
        let mut v = geometry::ViewSegList::new(geometry::SegList::from_points(pts.to_vec()));
        v.attrs.label = label;
        self.hints.apply(&mut v.attrs, prefix, true, false);
        v.to_spec()
    }

    fn erase_seglist(label: &str) -> String {
        format!("pts={{0,0:9,0:0,9}},active=false,label={label}")
    }

    fn erase_point(label: &str) -> String {
        let mut s = String::new();
        geometry::ViewPoint::erase_spec(label, &mut s);
        s
    }

    fn post_turn_seglist(&self, ctx: &Ctx<'_>, out: &mut Out, active: bool) {
        let label = format!("{}_turn", ctx.ownship);
        let spec = if active {
            self.view_seglist(&self.turn.pts, label, "turn")
        } else {
            Self::erase_seglist(&label)
        };
        out.post("VIEW_SEGLIST", spec);
    }

    fn post_steer_points(&self, ctx: &Ctx<'_>, out: &mut Out, active: bool) {
        let tlabel = format!("{}'s track-point", ctx.ownship);
        let nlabel = format!("{}'s next waypoint", ctx.ownship);
        let spec = |p: Point, label: &str| {
            let mut v = geometry::ViewPoint::new(p);
            v.attrs.label = label.to_string();
            self.hints.apply(&mut v.attrs, "nextpt", false, false);
            v.to_spec()
        };
        let (mut tp, mut np) = (Self::erase_point(&tlabel), Self::erase_point(&nlabel));
        if active {
            np = spec(self.nextpt, &nlabel);
            let d = (self.nextpt.x - self.trackpt.x).hypot(self.nextpt.y - self.trackpt.y);
            if d > 5.0 {
                tp = spec(self.trackpt, &tlabel);
            }
        }
        out.post_key("VIEW_POINT", tp, PostKey::Tag("trk"));
        out.post_key("VIEW_POINT", np, PostKey::Tag("wpt"));
    }

    fn post_leg_points(&self, ctx: &Ctx<'_>, out: &mut Out, active: bool) {
        let (p1, p2) = self.leg.pts();
        for (p, tag, big) in [(p1, "p1", true), (p2, "p2", false)] {
            let mut v = geometry::ViewPoint::new(p);
            v.attrs.label = format!("{}_{tag}", ctx.ownship);
            if active {
                self.hints.apply(&mut v.attrs, "legpt", false, false);
                if big {
                    // Drawn a bit bigger than p2 (the C++ stores the size as an integer).
                    let s = v.attrs.vertex_size.unwrap_or(0.0) as i64 as f64;
                    v.attrs.vertex_size = Some(s * 1.5);
                }
            }
            out.post_key("VIEW_POINT", v.to_spec(), PostKey::Tag(tag));
        }
    }

    fn post_turn_preview(&mut self, ctx: &Ctx<'_>, out: &mut Out, active: bool) {
        let labels = [1, 2, 3].map(|k| format!("{}_pview{k}", ctx.ownship));
        if !active {
            for l in &labels {
                out.post("VIEW_SEGLIST", Self::erase_seglist(l));
            }
            return;
        }
        let s1 = self.leg.turn_points(1);
        let s2 = self.leg.turn_points(2);
        let s3: Vec<Point> = match (self.leg.p1, self.leg.p2) {
            (Some(a), Some(b)) => vec![a, b],
            _ => Vec::new(),
        };
        for (pts, label, prefix) in [
            (&s1, &labels[0], "turn"),
            (&s2, &labels[1], "turn"),
            (&s3, &labels[2], "legpt"),
        ] {
            if !pts.is_empty() {
                let spec = self.view_seglist(pts, label.clone(), prefix);
                out.post("VIEW_SEGLIST", spec);
            }
        }
        let mut change = false;
        let far = |a: Point, b: Option<Point>| {
            let b = b.unwrap_or(Point::new(0.0, 0.0));
            (a.x - b.x).hypot(a.y - b.y) > 1.0
        };
        // Both preview points sit at 42 % of the first turn's length (as the C++).
        let dist = seg_length(&s1) * 0.42;
        if s1.len() > 1 {
            let p = dist_point(&s1, dist);
            if far(p, self.turn_pt1) {
                self.turn_pt1 = Some(p);
                change = true;
            }
        }
        if s2.len() > 1 {
            let p = dist_point(&s2, dist);
            if far(p, self.turn_pt2) {
                self.turn_pt2 = Some(p);
                change = true;
            }
        }
        if change {
            self.post_turn_points(ctx, out, true);
        }
        self.preview_pending = false;
    }

    fn post_turn_points(&self, ctx: &Ctx<'_>, out: &mut Out, active: bool) {
        for (p, k) in [(self.turn_pt1, 1), (self.turn_pt2, 2)] {
            let label = if p.is_some() {
                format!("{}_fpt{k}", ctx.ownship)
            } else {
                String::new()
            };
            let spec = match p {
                Some(p) if active => {
                    let mut v = geometry::ViewPoint::new(p);
                    v.attrs.label = label;
                    v.attrs.label_color = Some("invisible".into());
                    v.attrs.vertex_color = Some("limegreen".into());
                    v.attrs.duration = Some(600.0);
                    v.attrs.vertex_size = Some(8.0);
                    v.to_spec()
                }
                _ => Self::erase_point(&label),
            };
            out.post("VIEW_POINT", spec);
        }
    }

    fn erase_all(&mut self, ctx: &Ctx<'_>, out: &mut Out) {
        self.post_turn_seglist(ctx, out, false);
        self.post_steer_points(ctx, out, false);
        self.post_leg_points(ctx, out, false);
        self.post_turn_preview(ctx, out, false);
        self.post_turn_points(ctx, out, false);
    }

    /// MOOS `updatePlatformInfo` plus the odometer and wrap detector.
    fn update_info(&mut self, ctx: &Ctx<'_>, out: &mut Out) -> bool {
        let (Some(x), Some(y)) = (ctx.info.num("NAV_X"), ctx.info.num("NAV_Y")) else {
            out.error("No ownship X/Y info in info_buffer.");
            return false;
        };
        if ctx.info.num("NAV_HEADING").is_none() {
            out.error("No ownship heading info in info_buffer.");
            return false;
        }
        self.os = (x, y);
        self.odometer.update(x, y);
        self.wraps.update(x, y);
        true
    }
}

/// The behaviour's own macros (see the module docs).
const MACROS: [&str; 13] = [
    "SPEED", "NI", "NX", "CYCLES", "CYCREM", "WPTS_HIT", "MODE", "DIST_NP", "DIST_PP", "PCT_NP",
    "LEG_ODO", "LEG_ID", "WRAPS",
];

impl Behavior for LegRun {
    fn kind(&self) -> &'static str {
        "BHV_LegRun"
    }

    fn default_name(&self) -> &'static str {
        "legrun"
    }

    fn domain_vars(&self) -> &'static [&'static str] {
        &["course", "speed"]
    }

    fn default_common_params(&self) -> &'static [(&'static str, &'static str)] {
        &[("perpetual", "true")]
    }

    fn info_vars(&self, out: &mut Vec<String>) {
        add_vars(out, ["NAV_X", "NAV_Y", "NAV_SPEED", "NAV_HEADING"]);
        let f = &self.flags;
        for l in [
            &f.mid_leg,
            &f.mid_turn,
            &f.leg_end,
            &f.leg1_end,
            &f.leg2_end,
            &f.turn_end,
            &f.turn1_end,
            &f.turn2_end,
        ] {
            add_flag_vars(out, l);
        }
    }

    fn set_param(
        &mut self,
        param: &str,
        value: &str,
        common: &mut Common,
        ctx: &Ctx<'_>,
    ) -> Result<(), ParamError> {
        let v = value.trim();
        let bad = |what: &'static str| Err(ParamError::bad(param, value, what));
        self.max_spd = ctx.domain.get("speed").map_or(0.0, |d| d.high());
        let flag = |l: &mut Vec<Flag>| -> Result<(), ParamError> {
            l.push(Flag::parse(v).ok_or_else(|| ParamError::bad(param, value, "VAR = value"))?);
            Ok(())
        };
        match param {
            "capture_line" | "lead" | "lead_damper" | "radius" | "capture_radius"
            | "slip_radius" => {
                let a = self.turn.set_param(param, v);
                let b = self.legs.set_param(param, v);
                if !(a && b) {
                    return bad(match param {
                        "capture_line" => "true, false or absolute",
                        _ => "a number >= 0",
                    });
                }
            }
            "init_leg_mode" => match v {
                "fixed" | "close_turn" | "far_turn" | "resume" => self.init_leg_mode = v.into(),
                _ => return bad("fixed, close_turn, far_turn or resume"),
            },
            "leg_spds" => {
                if !self.set_leg_spds(v) {
                    return bad("clear, reset, or speeds `s` or `n:s` within the speed domain");
                }
            }
            "leg_spds_onturn" => {
                self.leg_spds_onturn = moos_boolean(param, v, self.leg_spds_onturn)?
            }
            "leg_spds_repeat" => {
                self.leg_spds_repeat = moos_boolean(param, v, self.leg_spds_repeat)?
            }
            "leg_endflag" | "leg_end_flag" => flag(&mut self.flags.leg_end)?,
            "leg1_endflag" | "leg1_end_flag" => flag(&mut self.flags.leg1_end)?,
            "leg2_endflag" | "leg2_end_flag" => flag(&mut self.flags.leg2_end)?,
            "turn_endflag" | "turn_end_flag" => flag(&mut self.flags.turn_end)?,
            "turn1_endflag" | "turn1_end_flag" => flag(&mut self.flags.turn1_end)?,
            "turn2_endflag" | "turn2_end_flag" => flag(&mut self.flags.turn2_end)?,
            "midlegflag" | "mid_leg_flag" => flag(&mut self.flags.mid_leg)?,
            "midturnflag" | "mid_turn_flag" => flag(&mut self.flags.mid_turn)?,
            "mid_leg_pct" | "mid_turn_pct" => {
                let p = number(param, v)?;
                if !(0.0..=100.0).contains(&p) {
                    return bad("a number in [0, 100]");
                }
                if param == "mid_leg_pct" {
                    self.mid_leg_pct = p;
                } else {
                    self.mid_turn_pct = p;
                }
            }
            "patience" => self.patience = number(param, v)?.clamp(1.0, 99.0),
            "repeat" => {
                if !self.legs.set_param(param, v) {
                    return bad("forever or a number >= 0");
                }
                if self.legs.max_repeats > 0 {
                    common.perpetual = true;
                }
            }
            "speed" => {
                let s = number(param, v)?;
                self.cruise_spd = s.clamp(0.0, self.max_spd.max(0.0));
                if s < 0.0 || s > self.max_spd {
                    return bad("a number in [0, the speed domain's maximum]");
                }
            }
            "visual_hints" => {
                if !self.hints.set_hints(v) {
                    return bad("key=value hints (colours for keys with `color`, else numbers)");
                }
            }
            _ => {
                self.preview_pending = true;
                if !self.leg.set_param(param, v) {
                    return if is_leg_param(param) {
                        bad("a value the leg accepts (see BHV_LegRun's table)")
                    } else {
                        Err(ParamError::unknown(param))
                    };
                }
            }
        }
        Ok(())
    }

    fn on_set_param_complete(&mut self, ctx: &Ctx<'_>, out: &mut Out) {
        let w = "Invalid or unset legrun";
        if !self.leg.valid() {
            out.warning(ctx.name, w);
        } else {
            out.post_key(
                "BHV_WARNING",
                format!("{}: {w}", ctx.name),
                PostKey::Tag("retract"),
            );
        }
        if self.leg.modified {
            let pts: Vec<Point> = [self.leg.p1, self.leg.p2].into_iter().flatten().collect();
            self.legs.set_points(pts, true);
            if self.mode.is_turn() {
                self.post_turn_seglist(ctx, out, false);
                self.post_steer_points(ctx, out, false);
            }
            self.set_mode(LegMode::Init, ctx, out);
            self.leg.modified = false;
        }
        crate::behavior::post_config_status(&*self, ctx, out);
    }

    fn config_status(&self, name: &str) -> Option<String> {
        let mut s = format!("type=BHV_LegRun,name={name},speed=");
        compact(&mut s, self.cruise_spd, 1);
        s.push_str(&format!(",currix={}", self.legs.curr_ix));
        s.push_str(",capture_radius=");
        compact(&mut s, self.legs.capture_radius, 1);
        s.push_str(",slip_radius=");
        compact(&mut s, self.legs.slip_radius, 1);
        if self.legs.capture_line {
            if self.legs.capture_radius == 0.0 && self.legs.slip_radius == 0.0 {
                s.push_str(",capture_line=absolute");
            } else {
                s.push_str(",capture_line=true");
            }
        }
        s.push_str(",patience=");
        compact(&mut s, self.patience, 2);
        Some(s)
    }

    fn on_idle(&mut self, ctx: &Ctx<'_>, out: &mut Out) {
        self.update_info(ctx, out);
    }

    fn on_idle_to_run(&mut self, _ctx: &Ctx<'_>, _out: &mut Out) {
        self.preview_pending = true;
        // A turn interrupted is skipped: the behaviour resumes on the next leg.
        self.mode = match self.mode {
            LegMode::Turn1 => LegMode::Leg2,
            LegMode::Turn2 => LegMode::Leg1,
            m => m,
        };
    }

    fn on_run_to_idle(&mut self, ctx: &Ctx<'_>, out: &mut Out) {
        self.erase_all(ctx, out);
        self.legs.current_cpa = -1.0;
        self.turn.current_cpa = -1.0;
    }

    fn on_complete(&mut self, ctx: &Ctx<'_>, out: &mut Out) {
        self.erase_all(ctx, out);
    }

    fn on_run(&mut self, ctx: &Ctx<'_>, out: &mut Out) -> Option<IvpFunction> {
        if !self.update_info(ctx, out) {
            self.erase_all(ctx, out);
            return None;
        }
        if !self.leg.valid() {
            return None;
        }
        if self.mode == LegMode::Init {
            self.init_leg_mode(ctx, out);
        }
        if self.preview_pending {
            self.post_turn_preview(ctx, out, true);
        }
        let mut ok = self.run_mode(ctx, out);
        self.handle_mode_switch(ctx, out);
        if !ok {
            ok = self.run_mode(ctx, out);
        }
        if !ok {
            return None;
        }
        self.build_of(ctx, out)
    }

    fn macro_value(&self, name: &str, out: &mut String) -> bool {
        let (x, y) = self.os;
        let d = |out: &mut String, v: f64| compact(out, v, 3);
        match name {
            "SPEED" => d(out, self.cruise_spd),
            "NI" => out.push_str(&self.legs.curr_ix.to_string()),
            "NX" => d(out, self.legs.point().x),
            "CYCLES" => out.push_str(&self.legs.repeats_sofar.to_string()),
            "CYCREM" => out.push_str(&self.legs.repeats_remaining().to_string()),
            "WPTS_HIT" => out.push_str(&self.legs.hits.to_string()),
            "MODE" => out.push_str(self.mode.name()),
            "DIST_NP" => d(out, self.legs.dist_to_next(x, y)),
            "DIST_PP" => d(out, self.legs.dist_to_prev(x, y)),
            "PCT_NP" => d(out, self.legs.pct_to_next(x, y)),
            "LEG_ODO" => d(out, self.odometer.total),
            "LEG_ID" => out.push_str(&(self.leg_count1 + self.leg_count2).to_string()),
            "WRAPS" => out.push_str(&self.wraps.wraps.to_string()),
            _ => return false,
        }
        true
    }
}

/// Whether `param` is a parameter of the leg (MOOS `LegRun::setParam`): a refused value for
/// one of these is a bad value, anything else an unknown parameter.
fn is_leg_param(param: &str) -> bool {
    LEG_PARAMS.contains(&param)
}

/// The parameters `LegRun::setParam` knows (listed once, in the catalog `coug check` reads).
pub use mission::catalog::LEG_PARAMS;
