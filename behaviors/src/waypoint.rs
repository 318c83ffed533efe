//! BHV_Waypoint (reference §6.1): follows a list of points with capture/slip radii, capture
//! line, lead point, repeats, flags and viewer postings.
//!
//! # Conformance with BHV_Waypoint (MOOS-IvP a2a9b716)
//!
//! | parameter | aliases | type | default | validation (C++ rule) | runtime update | coug |
//! |---|---|---|---|---|---|---|
//! | points | polygon | seglist / polygon / pattern | none | any `string2SegList` form | yes | done |
//! | xpoints | | points | | replaces a route of the same length | yes | done |
//! | point | | point | | a single point | yes | done |
//! | newpt | | point | | appends a point | yes | open: untested |
//! | speed | | m/s | 0 | number >= 0, clipped to the domain | yes | done |
//! | speed_alt | | m/s | | number | yes | done |
//! | use_alt_speed | | bool | false | MOOS boolean | yes | done |
//! | capture_radius | radius | m | 3 | number >= 0 | yes | done |
//! | slip_radius | nm_radius | m | 15 | number >= 0 | yes | done |
//! | capture_line | | bool / absolute | false | | yes | done |
//! | lead | | m | −1 (off) | number | yes | done |
//! | lead_damper | | m | −1 (off) | number | yes | done |
//! | lead_to_start | | bool | false | MOOS boolean | yes | done |
//! | lead_condition | | condition | none | | yes | done |
//! | order | | normal, reverse, toggle | normal | | yes | done |
//! | repeat | | integer or forever | 0 | | yes | done |
//! | currix | | index | 0 | index within the route | yes | done |
//! | greedy_tour | | bool | false | | yes | done |
//! | shortest_tour | | bool | false | | yes | open: untested |
//! | wpt_status | wpt_status_var | var | WPT_STAT | | yes | done (alias untested) |
//! | wpt_index | wpt_index_var | var | WPT_INDEX | | yes | open: untested |
//! | cycle_index_var | | var | CYCLE_INDEX | | yes | open: untested |
//! | wpt_dist_to_prev, wpt_dist_to_next | | var | none | | yes | done |
//! | post_suffix | | text | none | | yes | done |
//! | cycleflag, wptflag | | flag | none | `VAR=value` | yes | done |
//! | wptflag_on_start | | bool | false | MOOS boolean | yes | done |
//! | reset_on_idle | | bool | false | MOOS boolean | yes | done |
//! | ipf_type | ipf-type | zaic, zaic_spd, roc | zaic | | yes | refused: `roc` (MALCONFIG); zaic/zaic_spd open: untested |
//! | crs_spd_zaic_ratio | | 1..99 | 50 | | yes | open: untested |
//! | patience | | 1..99 | 50 | | yes | done |
//! | efficiency_measure | | all, off | off | | yes | done |
//! | end_spd | | `slow_dist=..,stop_dist=..` | none | slow > stop >= 0 | yes | done |
//! | visual_hints | | hints | | sizes, colours | yes | open: untested |
//! | draw_path_loop | | bool | | | yes | refused: not supported yet (MALCONFIG) |
//! | eager_prev_index_flag | | bool | false | | yes | refused: not supported yet (MALCONFIG) |
//!
//! | variable | when | format | coug |
//! |---|---|---|---|
//! | WPT_STAT`<sfx>` | each running iteration | `vname=..,behavior-name=..,index=..,hits=..,cycles=..,dist=..,eta=..` | done |
//! | WPT_INDEX`<sfx>`, CYCLE_INDEX`<sfx>` | on change | numbers | done |
//! | `wpt_dist_to_prev`, `wpt_dist_to_next` | each running iteration | metres | done |
//! | WPT_EFF_DIST_*, WPT_EFF_TIME_*, WPT_EFF_SUMM_*, WPT_ODO | with efficiency_measure | numbers / summary | done |
//! | VIEW_SEGLIST, VIEW_POINT (`wpt`, `trk`) | running (drawn), idle (erased) | specs | done |
//! | BHV_SETTINGS | each start | settings string | open: not posted |
//! | WAYPT_UPIECE | | | open: not posted |
//!
//! | macro | meaning | coug |
//! |---|---|---|
//! | POINTS, SPEED, SPEED_ALT, USE_SPEED_ALT, IPF_TYPE, WPT_FLAG_ON_START, LEAD_TO_START, LEAD_DAMPER, ORDER | configuration (numbers 3 decimals, booleans 1/0) | done |
//! | NI, NX, NY, PI, PX, PY, X, Y, IX | next/previous point and index | done |
//! | CYCLES, CYCREM, WPTS_HIT, WPTS_REM, WPTS | progress counts | done |
//! | CYC_DIST_TOGO, ALL_DIST_TOGO | distance to the end of the cycle / of all cycles (−1 if endless) | done |

use geometry::spec::{parse_point, parse_waypoints};
use geometry::{Point, SegList, Segment, ViewPoint, ViewSegList};
use ivp::{IvpFunction, PeakComponent, ZaicPeak, ZaicSpd, couple_weighted};

use crate::behavior::{Behavior, Ctx, Out, ParamError, PostKey, add_flag_vars, add_vars, nav};
use crate::common::{Common, Flag};
use crate::fmt::compact;
use crate::param::{boolean, number, number_min};

/// Result of one waypoint-engine step (MOOS `WaypointEngine::setNextWaypoint`).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Step {
    /// No points.
    Empty,
    /// Heading for the current point.
    InTransit,
    /// The current point was reached; the next one is now current.
    Advanced,
    /// The last point was reached and a new cycle starts.
    Cycled,
    /// The last point was reached and no repeats remain.
    Completed,
}

/// How the objective function is built (`ipf_type`).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum IpfType {
    /// ZAIC_PEAK on speed coupled with a two-component ZAIC_PEAK on course (default).
    Zaic,
    /// ZAIC_SPD on speed coupled with the same course function.
    ZaicSpd,
}

/// The waypoint behaviour. See the module docs and reference §6.1.
#[derive(Debug, Clone)]
pub struct Waypoint {
    raw: SegList,
    points: SegList,
    reverse: bool,
    curr_ix: usize,
    cpa: Option<f64>,
    /// Capture radius, m (default 3).
    pub capture_radius: f64,
    /// Slip (non-monotonic) radius, m (default 15).
    pub slip_radius: f64,
    /// Capture line: arrival once past the line through the point perpendicular to the leg.
    pub capture_line: bool,
    repeats: u32,
    endless: bool,
    repeats_sofar: u32,
    cycles: u32,
    capture_hits: u32,
    nonmono_hits: u32,
    complete: bool,
    prevpt: Option<Point>,
    markpt: Option<Point>,
    /// Cruise speed, m/s.
    pub speed: f64,
    /// Alternative speed (−1 = unused).
    pub speed_alt: f64,
    /// Use `speed_alt` instead of `speed`.
    pub use_alt_speed: bool,
    /// Lead distance, m (−1 = off).
    pub lead: f64,
    /// Lead damper distance, m (−1 = off).
    pub lead_damper: f64,
    /// Use the position where the behaviour first ran as the anchor of the first leg.
    pub lead_to_start: bool,
    /// Course share of the coupled function (1..99, default 50).
    pub patience: f64,
    /// Objective function type.
    pub ipf_type: IpfType,
    var_report: String,
    var_index: String,
    var_cyindex: String,
    suffix: String,
    var_dist_prev: String,
    var_dist_next: String,
    cycle_flags: Vec<Flag>,
    wpt_flags: Vec<Flag>,
    wptflag_on_start: bool,
    started: bool,
    efficiency: bool,
    hint_vertex_size: f64,
    hint_edge_size: f64,
    hint_vertex_color: String,
    hint_edge_color: String,
    hint_nextpt_color: String,
    hint_nextpt_lcolor: String,
    hint_nextpt_vertex_size: f64,
    nextpt: Point,
    trackpt: Point,
    hitpt: Point,
    os: (f64, f64, f64, f64),
    odo_prev: Option<Point>,
    odo_leg: f64,
    odo_mark: Option<(Point, f64)>,
    odo_totals: [f64; 4],
    start_pending: bool,
    greedy_pending: bool,
    reset_on_idle: bool,
    lead_condition: Option<mission::condition::Condition>,
    end_spd: Option<(f64, f64)>,
    engine_prev: Option<Point>,
    prev_ix: Option<usize>,
    views: Views,
    spd_cache: Option<SpeedFunction>,
}

/// A built speed function and what it was built from.
#[derive(Debug, Clone)]
struct SpeedFunction {
    ipf_type: IpfType,
    speed: f64,
    domain: ivp::Domain,
    f: IvpFunction,
}

/// The configured status variables, for [`Views::names`].
struct WaypointNames<'a> {
    report: &'a str,
    index: &'a str,
    cyindex: &'a str,
    suffix: &'a str,
}

/// A view string with the key it was rendered for.
#[derive(Debug, Clone)]
struct Cached<K> {
    key: Option<K>,
    text: String,
}

impl<K> Default for Cached<K> {
    fn default() -> Self {
        Self {
            key: None,
            text: String::new(),
        }
    }
}

impl<K: PartialEq> Cached<K> {
    /// The text for `key`, rendered by `render` only when the key differs from the last one.
    fn get(&mut self, key: K, render: impl FnOnce(&mut String)) -> String {
        if self.key.as_ref() != Some(&key) {
            self.text.clear();
            render(&mut self.text);
            self.key = Some(key);
        }
        self.text.clone()
    }
}

/// The last rendered view strings with the inputs they were rendered from: the views are
/// posted every iteration but change rarely, so they are re-rendered only when an input
/// changes (parameters, which include the drawing hints, reset the cache).
#[derive(Debug, Clone, Default)]
struct Views {
    /// The vehicle and behaviour names the texts were rendered for.
    ownship: String,
    name: String,
    nextpt: Cached<(bool, Point)>,
    trackpt: Cached<(bool, Point)>,
    seglist: Option<(bool, SegList)>,
    seglist_text: String,
    /// `<var_report><suffix>`, `<var_index><suffix>`, `<var_cyindex><suffix>`.
    names: Option<[String; 3]>,
}

impl Views {
    /// The status variable names with the suffix (built once per configuration).
    fn names(&mut self, wpt: &WaypointNames<'_>) -> &[String; 3] {
        self.names.get_or_insert_with(|| {
            [wpt.report, wpt.index, wpt.cyindex].map(|v| format!("{v}{}", wpt.suffix))
        })
    }

    /// Forgets every text rendered for another vehicle or behaviour name.
    fn check_ctx(&mut self, ctx: &Ctx<'_>) {
        if self.ownship != ctx.ownship || self.name != ctx.name {
            *self = Views {
                ownship: ctx.ownship.to_string(),
                name: ctx.name.to_string(),
                ..Views::default()
            };
        }
    }
}

impl Default for Waypoint {
    fn default() -> Self {
        Self::new()
    }
}

impl Waypoint {
    /// The MOOS defaults (no points, speed 0, capture radius 3, slip radius 15).
    pub fn new() -> Self {
        Waypoint {
            raw: SegList::new(),
            points: SegList::new(),
            reverse: false,
            curr_ix: 0,
            cpa: None,
            capture_radius: 3.0,
            slip_radius: 15.0,
            capture_line: false,
            repeats: 0,
            endless: false,
            repeats_sofar: 0,
            cycles: 0,
            capture_hits: 0,
            nonmono_hits: 0,
            complete: false,
            prevpt: None,
            markpt: None,
            speed: 0.0,
            speed_alt: -1.0,
            use_alt_speed: false,
            lead: -1.0,
            lead_damper: -1.0,
            lead_to_start: false,
            patience: 50.0,
            ipf_type: IpfType::Zaic,
            var_report: "WPT_STAT".into(),
            var_index: "WPT_INDEX".into(),
            var_cyindex: "CYCLE_INDEX".into(),
            suffix: String::new(),
            var_dist_prev: String::new(),
            var_dist_next: String::new(),
            cycle_flags: Vec::new(),
            wpt_flags: Vec::new(),
            wptflag_on_start: false,
            started: false,
            efficiency: false,
            hint_vertex_size: 3.0,
            hint_edge_size: 1.0,
            hint_vertex_color: "dodger_blue".into(),
            hint_edge_color: "white".into(),
            hint_nextpt_color: "yellow".into(),
            hint_nextpt_lcolor: "aqua".into(),
            hint_nextpt_vertex_size: 5.0,
            nextpt: Point::new(0.0, 0.0),
            trackpt: Point::new(0.0, 0.0),
            hitpt: Point::new(0.0, 0.0),
            os: (0.0, 0.0, 0.0, 0.0),
            odo_prev: None,
            odo_leg: 0.0,
            odo_mark: None,
            odo_totals: [0.0; 4],
            start_pending: false,
            greedy_pending: false,
            reset_on_idle: false,
            lead_condition: None,
            end_spd: None,
            engine_prev: None,
            prev_ix: None,
            views: Views::default(),
            spd_cache: None,
        }
    }

    /// The points in traversal order.
    pub fn points(&self) -> &SegList {
        &self.points
    }
    /// Index of the point being sought.
    pub fn current_index(&self) -> usize {
        self.curr_ix
    }
    /// Completed cycles.
    pub fn cycles(&self) -> u32 {
        self.cycles
    }
    /// The point steered for on the last run (next point, or the lead point).
    pub fn track_point(&self) -> Point {
        self.trackpt
    }
    /// The effective speed: `speed_alt` when `use_alt_speed` and it is set, else `speed`.
    pub fn effective_speed(&self) -> f64 {
        if self.use_alt_speed && self.speed_alt >= 0.0 {
            self.speed_alt
        } else {
            self.speed
        }
    }

    fn set_points(&mut self, seglist: SegList) {
        self.raw = seglist;
        self.apply_order();
        self.prev_ix = None;
    }

    /// Distance from ownship to the end of the current cycle: to the next point, then along
    /// the remaining legs (MOOS `WaypointEngine::distToEndCycle`); −1 without a next point.
    fn dist_to_end_cycle(&self) -> f64 {
        let pts = self.points.points();
        let Some(next) = pts.get(self.curr_ix) else {
            return -1.0;
        };
        let (x, y) = (self.os.0, self.os.1);
        let mut d = (next.x - x).hypot(next.y - y);
        for w in pts[self.curr_ix..].windows(2) {
            d += (w[1].x - w[0].x).hypot(w[1].y - w[0].y);
        }
        d
    }

    /// [`Waypoint::dist_to_end_cycle`] plus the remaining full cycles, each the route length
    /// plus the gap from its last point back to its first (MOOS `distToEndFinal`); −1 when
    /// repeating endlessly.
    fn dist_to_end_final(&self) -> f64 {
        if self.endless {
            return -1.0;
        }
        let to_end = self.dist_to_end_cycle();
        let remaining = self.repeats.saturating_sub(self.repeats_sofar);
        let pts = self.points.points();
        if to_end < 0.0 || remaining == 0 || pts.is_empty() {
            return to_end;
        }
        let legs: f64 = pts
            .windows(2)
            .map(|w| (w[1].x - w[0].x).hypot(w[1].y - w[0].y))
            .sum();
        let (a, b) = (pts[0], pts[pts.len() - 1]);
        to_end + f64::from(remaining) * (legs + (a.x - b.x).hypot(a.y - b.y))
    }

    /// The speed to request at ownship `(x, y)`: the effective speed, tapered by `end_spd`
    /// (linear from full speed at `slow_dist` to 0 at `stop_dist` from the final point).
    pub fn desired_speed(&self, x: f64, y: f64) -> f64 {
        let speed = self.effective_speed();
        match (self.end_spd, self.points.points().last()) {
            (Some((slow, stop)), Some(last)) => {
                let d = (x - last.x).hypot(y - last.y);
                speed * ((d - stop) / (slow - stop)).clamp(0.0, 1.0)
            }
            _ => speed,
        }
    }

    /// Reorders the points as a greedy nearest-neighbour tour from `(x, y)`.
    fn greedy(&mut self, x: f64, y: f64) {
        let mut left: Vec<Point> = self.points.points().to_vec();
        let mut tour = Vec::with_capacity(left.len());
        let mut here = Point::new(x, y);
        while !left.is_empty() {
            let (i, _) = left
                .iter()
                .enumerate()
                .min_by(|a, b| a.1.dist(&here).total_cmp(&b.1.dist(&here)))
                .unwrap_or((0, &here));
            here = left.remove(i);
            tour.push(here);
        }
        self.raw = SegList::from_points(tour);
        self.points = self.raw.clone();
        self.curr_ix = 0;
        self.cpa = None;
    }

    /// Distance to the previous waypoint as MOOS `distToPrevWpt` gives it (−1 if none).
    fn dist_to_prev(&self, here: Point) -> f64 {
        if let Some(p) = self.engine_prev {
            return here.dist(&p);
        }
        match self.prev_ix.and_then(|i| self.points.get(i)) {
            Some(p) => here.dist(&p),
            None => -1.0,
        }
    }

    fn apply_order(&mut self) {
        self.points = self.raw.clone();
        if self.reverse {
            self.points.reverse();
        }
        self.curr_ix = 0;
        self.cpa = None;
        self.complete = false;
        self.repeats_sofar = 0;
        self.markpt = None;
    }

    fn reset_for_new_traversal(&mut self) {
        self.repeats_sofar = 0;
        self.cpa = None;
        self.curr_ix = 0;
        self.complete = false;
    }

    /// One step of the waypoint engine for ownship at `(x, y)` (MOOS `setNextWaypoint`):
    /// capture radius, slip radius (non-monotonic arrival) and capture line.
    pub fn step(&mut self, x: f64, y: f64) -> Step {
        let n = self.points.len();
        if n == 0 {
            return Step::Empty;
        }
        if self.complete {
            return Step::Completed;
        }
        self.engine_prev = self.prevpt;
        let pt = self.points.points()[self.curr_ix];
        let dist = (x - pt.x).hypot(y - pt.y);
        let cpa = match self.cpa {
            Some(c) if c <= dist => c,
            _ => dist,
        };
        self.cpa = Some(cpa);
        let mut advance = false;
        if dist < self.capture_radius {
            advance = true;
            self.capture_hits += 1;
        } else if self.slip_radius > self.capture_radius && dist > cpa && cpa <= self.slip_radius {
            advance = true;
            self.nonmono_hits += 1;
        }
        if self.capture_line
            && let Some(prev) = self.prevpt
            && Segment::from_xy(prev.x, prev.y, pt.x, pt.y).passed_end(x, y)
            && (prev.x != pt.x || prev.y != pt.y)
        {
            advance = true;
        }
        if !advance {
            return Step::InTransit;
        }
        self.curr_ix += 1;
        if self.curr_ix >= n {
            self.cycles += 1;
            self.curr_ix = 0;
            self.cpa = None;
            self.repeats_sofar += 1;
            if self.endless || self.repeats_sofar <= self.repeats {
                return Step::Cycled;
            }
            self.complete = true;
            return Step::Completed;
        }
        self.prev_ix = Some(self.curr_ix - 1);
        self.engine_prev = None;
        let next = self.points.points()[self.curr_ix];
        self.cpa = Some((x - next.x).hypot(y - next.y));
        Step::Advanced
    }

    fn post_wpt_flags(&mut self, out: &mut Out) {
        for f in &self.wpt_flags {
            out.flag(f, true);
        }
    }

    fn set_next_waypoint(&mut self, ctx: &Ctx<'_>, out: &mut Out) -> bool {
        let (osx, osy, _, _) = self.os;
        let step = self.step(osx, osy);
        if step == Step::Empty {
            return false;
        }
        if step != Step::InTransit {
            self.mark_odo_leg(ctx, out);
        }
        out.post(format!("WPT_ODO{}", self.suffix), self.odo_leg);
        if matches!(step, Step::Completed | Step::Cycled) {
            if self.var_report != "silent" {
                let word = if step == Step::Completed {
                    "completed"
                } else {
                    "cycled"
                };
                out.post(
                    format!("{}{}", self.var_report, self.suffix),
                    format!("behavior-name={},{word}", ctx.name),
                );
            }
            for f in &self.cycle_flags {
                out.flag(f, true);
            }
        }
        if step == Step::Completed {
            let n = self.points.len();
            self.hitpt = self.points.points()[n - 1];
            self.post_wpt_flags(out);
            out.complete();
            self.markpt = None;
            if ctx.perpetual {
                self.reset_for_new_traversal();
            }
            return false;
        }
        let next = self.points.points()[self.curr_ix];
        self.nextpt = next;
        self.trackpt = next;
        let lead_ok = self.lead_condition.as_ref().is_none_or(|c| {
            c.evaluate(&|n: &str| match ctx.info.text(n) {
                Some(s) => Some(mission::condition::Value::Str(s)),
                None => ctx.info.num(n).map(mission::condition::Value::Num),
            })
        });
        if self.lead > 0.0 && lead_ok {
            let anchor = if self.curr_ix > 0 {
                Some(self.points.points()[self.curr_ix - 1])
            } else if self.cycles > 0 {
                Some(self.points.points()[self.points.len() - 1])
            } else if self.lead_to_start {
                Some(*self.markpt.get_or_insert(Point::new(osx, osy)))
            } else {
                None
            };
            if let Some(a) = anchor {
                let leg = Segment::from_xy(a.x, a.y, next.x, next.y);
                self.trackpt = leg.lead_point_damped(osx, osy, self.lead, self.lead_damper);
            }
        }
        true
    }

    fn mark_odo_leg(&mut self, ctx: &Ctx<'_>, out: &mut Out) {
        if !self.efficiency {
            return;
        }
        let now = ctx.info.now();
        let here = Point::new(self.os.0, self.os.1);
        let Some((mark, t0)) = self.odo_mark else {
            self.odo_mark = Some((here, now));
            self.odo_leg = 0.0;
            return;
        };
        let lin = here.dist(&mark);
        let lin_time = if self.speed > 0.0 {
            lin / self.speed
        } else {
            0.0
        };
        let odo = self.odo_leg;
        let odo_time = now - t0;
        let t = &mut self.odo_totals;
        t[0] += lin;
        t[1] += lin_time;
        t[2] += odo;
        t[3] += odo_time;
        let ratio = |a: f64, b: f64| if b > 0.0 { a / b } else { 0.0 };
        let (dist_all, time_all) = (ratio(t[0], t[2]), ratio(t[1], t[3]));
        let (dist_leg, time_leg) = (ratio(lin, odo), ratio(lin_time, odo_time));
        let summary = |lin: f64, odo: f64, eff: f64, lt: f64, ot: f64, et: f64| {
            let mut s = format!("vname={}, bhv_name={}, linear_dist=", ctx.ownship, ctx.name);
            compact(&mut s, lin, 1);
            s.push_str(", odo_dist=");
            compact(&mut s, odo, 1);
            s.push_str(", efficiency_dist=");
            compact(&mut s, eff, 3);
            s.push_str(", linear_time=");
            compact(&mut s, lt, 1);
            s.push_str(", odo_time=");
            compact(&mut s, ot, 1);
            s.push_str(", efficiency_time=");
            compact(&mut s, et, 3);
            s
        };
        let sfx = &self.suffix;
        out.post(
            format!("WPT_EFF_SUMM_LEG{sfx}"),
            summary(lin, odo, dist_leg, lin_time, odo_time, time_leg),
        );
        out.post(
            format!("WPT_EFF_SUMM_ALL{sfx}"),
            summary(t[0], t[2], dist_all, t[1], t[3], time_all),
        );
        out.post(format!("WPT_EFF_DIST_ALL{sfx}"), dist_all);
        out.post(format!("WPT_EFF_TIME_ALL{sfx}"), time_all);
        out.post(format!("WPT_EFF_DIST_LEG{sfx}"), dist_leg);
        out.post(format!("WPT_EFF_TIME_LEG{sfx}"), time_leg);
        self.odo_mark = Some((here, now));
        self.odo_leg = 0.0;
    }

    /// The VIEW_POINT text of the next point (`trackpt == false`) or the track point, rendered
    /// only when the point or the active state changed.
    fn point_view(&mut self, ctx: &Ctx<'_>, active: bool, trackpt: bool) -> String {
        self.views.check_ctx(ctx);
        let pt = if trackpt { self.trackpt } else { self.nextpt };
        let slot = if trackpt {
            &mut self.views.trackpt
        } else {
            &mut self.views.nextpt
        };
        let mut view = std::mem::take(slot);
        let text = view.get((active, pt), |s| self.render_point(ctx, active, trackpt, s));
        if trackpt {
            self.views.trackpt = view;
        } else {
            self.views.nextpt = view;
        }
        text
    }

    fn render_point(&self, ctx: &Ctx<'_>, active: bool, trackpt: bool, s: &mut String) {
        let (pt, which) = if trackpt {
            (self.trackpt, "trackpt")
        } else {
            (self.nextpt, "nextpt")
        };
        let label = format!("{}'s {which}", ctx.ownship);
        if !active {
            ViewPoint::erase_spec(&label, s);
            return;
        }
        let mut vp = ViewPoint::new(pt);
        vp.attrs.label = label;
        vp.attrs.vertex_color = Some(self.hint_nextpt_color.clone());
        if trackpt {
            vp.attrs.label_color = Some(self.hint_nextpt_color.clone());
            vp.attrs.vertex_size = Some(4.0);
        } else {
            vp.attrs.label_color = Some(self.hint_nextpt_lcolor.clone());
            vp.attrs.vertex_size = Some(self.hint_nextpt_vertex_size);
        }
        vp.spec(s);
    }

    fn seglist_view(&mut self, ctx: &Ctx<'_>, active: bool) -> String {
        self.views.check_ctx(ctx);
        let fresh = match &self.views.seglist {
            Some((a, pts)) => *a == active && (!active || *pts == self.points),
            None => false,
        };
        if !fresh {
            let pts = if active {
                self.points.clone()
            } else {
                SegList::new()
            };
            self.views.seglist_text = self.render_seglist(ctx, active, pts.clone());
            self.views.seglist = Some((active, pts));
        }
        self.views.seglist_text.clone()
    }

    fn render_seglist(&self, ctx: &Ctx<'_>, active: bool, points: SegList) -> String {
        let mut v = ViewSegList::new(points);
        v.precision = 3;
        v.attrs.label = format!("{}_{}", ctx.ownship, ctx.name);
        v.attrs.active = active;
        if active {
            v.attrs.vertex_color = Some(self.hint_vertex_color.clone());
            v.attrs.edge_color = Some(self.hint_edge_color.clone());
            v.attrs.edge_size = Some(self.hint_edge_size);
            v.attrs.vertex_size = Some(self.hint_vertex_size);
        }
        v.to_spec()
    }

    fn post_names(&mut self) -> &[String; 3] {
        let w = WaypointNames {
            report: &self.var_report,
            index: &self.var_index,
            cyindex: &self.var_cyindex,
            suffix: &self.suffix,
        };
        self.views.names(&w)
    }

    fn post_status(&mut self, ctx: &Ctx<'_>, out: &mut Out) {
        let (osx, osy, _, osv) = self.os;
        let dist = (osx - self.nextpt.x).hypot(osy - self.nextpt.y);
        let eta = dist / osv;
        if self.var_report != "silent" {
            let mut stat = String::with_capacity(96);
            stat.push_str("vname=");
            stat.push_str(ctx.ownship);
            stat.push_str(",behavior-name=");
            stat.push_str(ctx.name);
            stat.push_str(",index=");
            crate::fmt::uint(&mut stat, self.curr_ix as u64);
            stat.push_str(",hits=");
            crate::fmt::uint(&mut stat, u64::from(self.capture_hits));
            stat.push('/');
            crate::fmt::uint(&mut stat, u64::from(self.capture_hits + self.nonmono_hits));
            stat.push_str(",cycles=");
            crate::fmt::uint(&mut stat, u64::from(self.cycles));
            stat.push_str(",dist=");
            crate::fmt::std_fixed(&mut stat, dist, 0);
            stat.push_str(",eta=");
            crate::fmt::std_fixed(&mut stat, eta, 0);
            let var = self.post_names()[0].clone();
            out.post(var, stat);
        }
        if self.var_index != "silent" {
            let var = self.post_names()[1].clone();
            out.post(var, self.curr_ix as f64);
        }
    }

    fn hint(&mut self, hint: &str) {
        let (k, v) = hint.split_once('=').unwrap_or((hint, ""));
        let (k, v) = (k.trim().to_ascii_lowercase(), v.trim());
        let num = v.parse::<f64>().ok().filter(|d| *d >= 0.0);
        match (k.as_str(), num) {
            ("vertex_size", Some(d)) => self.hint_vertex_size = d,
            ("edge_size", Some(d)) => self.hint_edge_size = d,
            ("nextpt_vertex_size", Some(d)) => self.hint_nextpt_vertex_size = d,
            ("vertex_color", _) if !v.is_empty() => self.hint_vertex_color = v.into(),
            ("edge_color", _) if !v.is_empty() => self.hint_edge_color = v.into(),
            ("nextpt_color", _) if !v.is_empty() => self.hint_nextpt_color = v.into(),
            ("nextpt_lcolor", _) if !v.is_empty() => self.hint_nextpt_lcolor = v.into(),
            // MOOS ignores hints it does not know.
            _ => {}
        }
    }

    /// The speed objective function for `speed`, built once per (type, speed, domain): the
    /// cruise speed rarely changes while the course function is rebuilt every iteration.
    fn speed_of(&mut self, ctx: &Ctx<'_>, speed: f64) -> Option<&IvpFunction> {
        let fresh = self.spd_cache.as_ref().is_some_and(|c| {
            c.ipf_type == self.ipf_type
                && c.speed.to_bits() == speed.to_bits()
                && c.domain == *ctx.domain
        });
        if !fresh {
            self.spd_cache = None;
            let f = match self.ipf_type {
                IpfType::Zaic => {
                    let mut z = ZaicPeak::new(ctx.domain, "speed").ok()?;
                    z.set_params(speed, speed / 2.0, 1.6, 20.0, 0.0, 100.0)
                        .ok()?;
                    z.extract().ok()?
                }
                IpfType::ZaicSpd => {
                    let z = ZaicSpd::new(ctx.domain, "speed", speed, 0.1, speed + 0.4, 70.0, 20.0)
                        .ok()?;
                    z.extract().ok()?
                }
            };
            self.spd_cache = Some(SpeedFunction {
                ipf_type: self.ipf_type,
                speed,
                domain: ctx.domain.clone(),
                f,
            });
        }
        self.spd_cache.as_ref().map(|c| &c.f)
    }

    fn build_of(&mut self, ctx: &Ctx<'_>, out: &mut Out) -> Option<IvpFunction> {
        let (osx, osy, osh, _) = self.os;
        let speed = self.desired_speed(osx, osy);
        self.speed_of(ctx, speed)?;
        let bearing = geometry::relative_angle(osx, osy, self.trackpt.x, self.trackpt.y);
        let mut crs = ZaicPeak::new(ctx.domain, "course").ok()?;
        crs.set_value_wrap(true);
        crs.set_params(bearing, 0.0, 180.0, 50.0, 0.0, 100.0).ok()?;
        crs.add_component(PeakComponent {
            summit: osh,
            peakwidth: 30.0,
            basewidth: 180.0,
            summitdelta: 5.0,
            minutil: 0.0,
            maxutil: 20.0,
        })
        .ok()?;
        crs.set_combine(ivp::Combine::Sum);
        let crs = crs.extract().ok()?;
        let spd = &self.spd_cache.as_ref()?.f;
        match couple_weighted(&crs, spd, self.patience, 100.0 - self.patience, true) {
            Ok(f) => Some(f),
            Err(e) => {
                out.warning(ctx.name, &format!("Failure on the CRS_SPD COUPLER: {e}"));
                None
            }
        }
    }
}

impl Behavior for Waypoint {
    fn kind(&self) -> &'static str {
        "BHV_Waypoint"
    }

    fn default_name(&self) -> &'static str {
        "bhv_waypoint"
    }

    fn domain_vars(&self) -> &'static [&'static str] {
        &["course", "speed"]
    }

    fn info_vars(&self, out: &mut Vec<String>) {
        add_vars(out, ["NAV_X", "NAV_Y", "NAV_HEADING", "NAV_SPEED"]);
        if let Some(c) = &self.lead_condition {
            add_vars(out, c.variables());
        }
        add_flag_vars(out, &self.wpt_flags);
        add_flag_vars(out, &self.cycle_flags);
    }

    fn set_param(
        &mut self,
        param: &str,
        value: &str,
        common: &mut Common,
        ctx: &Ctx<'_>,
    ) -> Result<(), ParamError> {
        self.views = Views::default();
        let v = value.trim();
        let var_name = |v: &str| !v.is_empty() && !v.contains(char::is_whitespace);
        match param {
            "points" | "polygon" | "xpoints" if v.eq_ignore_ascii_case("empty") => {
                self.set_points(SegList::new());
            }
            "points" | "polygon" | "xpoints" => {
                let (x, y) = nav(ctx.info).map_or((0.0, 0.0), |n| (n.0, n.1));
                let parsed = parse_waypoints(v, x, y)
                    .map_err(|_| ParamError::bad(param, value, "a point list or polygon"))?;
                if parsed.seglist.is_empty() {
                    return Err(ParamError::bad(param, value, "at least one point"));
                }
                if param == "xpoints" {
                    // Same-length replacement keeping the progress along the route.
                    if parsed.seglist.len() != self.raw.len() {
                        return Err(ParamError::bad(
                            param,
                            value,
                            "as many points as the current route",
                        ));
                    }
                    let ix = self.curr_ix;
                    let (cycles, hits) = (self.repeats_sofar, self.complete);
                    self.raw = parsed.seglist;
                    self.points = self.raw.clone();
                    if self.reverse {
                        self.points.reverse();
                    }
                    self.curr_ix = ix;
                    self.repeats_sofar = cycles;
                    self.complete = hits;
                } else {
                    self.set_points(parsed.seglist);
                }
            }
            "point"
                if v.eq_ignore_ascii_case("start")
                    || v.eq_ignore_ascii_case("present_position") =>
            {
                // The position is taken when the behaviour first sees the vehicle's position.
                match nav(ctx.info) {
                    Some(n) => self.set_points(SegList::from_points(vec![Point::new(n.0, n.1)])),
                    None => {
                        self.set_points(SegList::new());
                        self.start_pending = true;
                    }
                }
            }
            "point" => {
                let p = {
                    parse_point(v)
                        .map_err(|_| ParamError::bad(param, value, "a point x,y"))?
                        .point
                };
                self.set_points(SegList::from_points(vec![p]));
            }
            "newpt" => {
                let p = parse_point(v).map_err(|_| ParamError::bad(param, value, "a point x,y"))?;
                self.raw.push(p.point);
                let ix = self.curr_ix;
                self.points = self.raw.clone();
                if self.reverse {
                    self.points.reverse();
                }
                self.curr_ix = ix.min(self.points.len() - 1);
                self.complete = false;
            }
            "speed" => {
                let s = number_min(param, v, 0.0)?;
                let max = ctx.domain.get("speed").map_or(s, |d| d.high());
                self.speed = s.min(max);
            }
            "speed_alt" => {
                let s = number(param, v)?;
                let max = ctx.domain.get("speed").map_or(s, |d| d.high());
                self.speed_alt = s.min(max);
            }
            "use_alt_speed" => self.use_alt_speed = boolean(param, v)?,
            "currix" => {
                // As in MOOS, an index past the last point is accepted and ignored.
                let i = number_min(param, v, 0.0)? as usize;
                if i < self.points.len() {
                    self.curr_ix = i;
                    self.cpa = None;
                }
            }
            "wpt_status" | "wpt_status_var" if var_name(v) => {
                self.var_report = if v.eq_ignore_ascii_case("silent") {
                    "silent".into()
                } else {
                    v.into()
                }
            }
            "wpt_index" | "wpt_index_var" if var_name(v) => {
                self.var_index = if v.eq_ignore_ascii_case("silent") {
                    "silent".into()
                } else {
                    v.into()
                }
            }
            "cycle_index_var" if var_name(v) => {
                self.var_cyindex = if v.eq_ignore_ascii_case("silent") {
                    "silent".into()
                } else {
                    v.into()
                }
            }
            "wpt_status" | "wpt_status_var" | "wpt_index" | "wpt_index_var" | "cycle_index_var" => {
                return Err(ParamError::bad(param, value, "a variable name"));
            }
            "wpt_dist_to_prev" | "wpt_dist_to_next" => {
                if v.contains(char::is_whitespace) {
                    return Err(ParamError::bad(param, value, "a variable name"));
                }
                let name = if v.eq_ignore_ascii_case("silent") {
                    String::new()
                } else {
                    v.to_string()
                };
                if param == "wpt_dist_to_prev" {
                    self.var_dist_prev = name;
                } else {
                    self.var_dist_next = name;
                }
            }
            "post_suffix" => {
                if v.contains(char::is_whitespace) {
                    return Err(ParamError::bad(param, value, "a suffix without spaces"));
                }
                self.suffix = if v.is_empty() || v.starts_with('_') {
                    v.into()
                } else {
                    format!("_{v}")
                };
            }
            "cycleflag" | "wptflag" => {
                let f =
                    Flag::parse(v).ok_or_else(|| ParamError::bad(param, value, "VAR = value"))?;
                if param == "cycleflag" {
                    self.cycle_flags.push(f);
                } else {
                    self.wpt_flags.push(f);
                }
            }
            "wptflag_on_start" => self.wptflag_on_start = boolean(param, v)?,
            "ipf_type" | "ipf-type" => {
                self.ipf_type = match v.to_ascii_lowercase().as_str() {
                    "zaic" => IpfType::Zaic,
                    "zaic_spd" => IpfType::ZaicSpd,
                    _ => return Err(ParamError::bad(param, value, "zaic or zaic_spd")),
                }
            }
            "lead" => {
                let d = number(param, v)?;
                self.lead = if d <= 0.0 { -1.0 } else { d };
            }
            "lead_damper" => {
                let d = number(param, v)?;
                if d <= 0.0 {
                    return Err(ParamError::bad(param, value, "a positive distance"));
                }
                self.lead_damper = d;
            }
            "lead_condition" => {
                let c = mission::condition::parse_condition(&v.replace(',', "="))
                    .map_err(|_| ParamError::bad(param, value, "a logic condition"))?;
                self.lead_condition = Some(c);
            }
            "end_spd" => {
                let mut slow = None;
                let mut stop = None;
                for part in v.split(',') {
                    let (k, x) = part.split_once('=').unwrap_or((part, ""));
                    let x = number(param, x)?;
                    match k.trim().to_ascii_lowercase().as_str() {
                        "slow_dist" => slow = Some(x),
                        "stop_dist" => stop = Some(x),
                        _ => {
                            return Err(ParamError::bad(param, value, "slow_dist=..,stop_dist=.."));
                        }
                    }
                }
                match (slow, stop.unwrap_or(0.0)) {
                    (Some(a), b) if a > b && b >= 0.0 => self.end_spd = Some((a, b)),
                    _ => {
                        return Err(ParamError::bad(param, value, "slow_dist > stop_dist >= 0"));
                    }
                }
            }
            "greedy_tour" | "shortest_tour" => self.greedy_pending = boolean(param, v)?,
            "reset_on_idle" => self.reset_on_idle = boolean(param, v)?,
            "lead_to_start" => self.lead_to_start = boolean(param, v)?,
            "order" => {
                let l = v.to_ascii_lowercase();
                self.reverse = match l.as_str() {
                    "normal" => false,
                    "reverse" | "reversed" => true,
                    "toggle" => !self.reverse,
                    _ => return Err(ParamError::bad(param, value, "normal, reverse or toggle")),
                };
                self.apply_order();
            }
            "repeat" => {
                if v.eq_ignore_ascii_case("forever") {
                    common.perpetual = true;
                    self.endless = true;
                } else {
                    let r = number_min(param, v, 0.0)?;
                    if r.fract() != 0.0 {
                        return Err(ParamError::bad(param, value, "a whole number or forever"));
                    }
                    if r > 0.0 {
                        common.perpetual = true;
                    }
                    self.repeats = r as u32;
                    self.endless = false;
                }
            }
            "radius" | "capture_radius" => {
                let d = number(param, v)?;
                if d <= 0.0 {
                    return Err(ParamError::bad(param, value, "a positive radius"));
                }
                self.capture_radius = d;
            }
            "nm_radius" | "slip_radius" => self.slip_radius = number_min(param, v, 0.0)?,
            "capture_line" => match v.to_ascii_lowercase().as_str() {
                "absolute" => {
                    self.capture_line = true;
                    self.capture_radius = 0.0;
                    self.slip_radius = 0.0;
                }
                _ => self.capture_line = boolean(param, v)?,
            },
            "crs_spd_zaic_ratio" | "patience" => {
                let d = number(param, v)?;
                if !(1.0..=99.0).contains(&d) {
                    return Err(ParamError::bad(param, value, "a number in [1, 99]"));
                }
                self.patience = d;
            }
            "efficiency_measure" => {
                self.efficiency = match v.to_ascii_lowercase().as_str() {
                    "all" => true,
                    "off" => false,
                    _ => return Err(ParamError::bad(param, value, "all or off")),
                }
            }
            "visual_hints" => {
                for h in v.split(',') {
                    self.hint(h);
                }
            }
            "draw_path_loop" | "eager_prev_index_flag" => {
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

    fn on_idle(&mut self, ctx: &Ctx<'_>, _out: &mut Out) {
        if self.start_pending
            && let Some((x, y, _, _)) = nav(ctx.info)
        {
            self.start_pending = false;
            self.set_points(SegList::from_points(vec![Point::new(x, y)]));
        }
    }

    fn on_idle_to_run(&mut self, _ctx: &Ctx<'_>, _out: &mut Out) {
        self.odo_prev = None;
        self.odo_mark = None;
    }

    fn on_run_to_idle(&mut self, ctx: &Ctx<'_>, out: &mut Out) {
        out.post_key(
            "VIEW_POINT",
            self.point_view(ctx, false, true),
            PostKey::Tag("trk"),
        );
        out.post_key(
            "VIEW_POINT",
            self.point_view(ctx, false, false),
            PostKey::Tag("wpt"),
        );
        out.post("VIEW_SEGLIST", self.seglist_view(ctx, false));
        self.cpa = None;
        if self.reset_on_idle {
            self.reset_for_new_traversal();
            self.prevpt = None;
            self.prev_ix = None;
        }
        if !self.var_dist_prev.is_empty() {
            out.post(self.var_dist_prev.clone(), -1.0);
        }
        if !self.var_dist_next.is_empty() {
            out.post(self.var_dist_next.clone(), -1.0);
        }
    }

    fn on_run(&mut self, ctx: &Ctx<'_>, out: &mut Out) -> Option<IvpFunction> {
        let Some(os) = nav(ctx.info) else {
            out.post_key(
                "VIEW_POINT",
                self.point_view(ctx, false, false),
                PostKey::Tag("wpt"),
            );
            out.error("No ownship X/Y/heading info in info_buffer.");
            return None;
        };
        self.os = os;
        let here = Point::new(os.0, os.1);
        if self.start_pending {
            self.start_pending = false;
            self.set_points(SegList::from_points(vec![here]));
        }
        if self.greedy_pending {
            self.greedy_pending = false;
            self.greedy(here.x, here.y);
        }
        if let Some(p) = self.odo_prev {
            self.odo_leg += here.dist(&p);
        }
        self.odo_prev = Some(here);

        let this = self.points.get(self.curr_ix);
        if self.prevpt.is_none() {
            self.prevpt = Some(here);
        }
        if !self.started {
            self.started = true;
            if self.wptflag_on_start {
                self.hitpt = here;
                if let Some(p) = this {
                    self.nextpt = p;
                }
                self.post_wpt_flags(out);
            }
        }
        let next_point = self.set_next_waypoint(ctx, out);
        let next = self.points.get(self.curr_ix);
        if let (Some(t), Some(n)) = (this, next)
            && (t.x != n.x || t.y != n.y)
        {
            self.prevpt = Some(t);
            self.hitpt = t;
            self.post_wpt_flags(out);
        }
        if self.var_cyindex != "silent" {
            let var = self.post_names()[2].clone();
            out.post(var, f64::from(self.cycles));
        }
        if !next_point {
            out.post_key(
                "VIEW_POINT",
                self.point_view(ctx, false, false),
                PostKey::Tag("wpt"),
            );
            return None;
        }
        self.post_status(ctx, out);
        out.post("VIEW_SEGLIST", self.seglist_view(ctx, true));
        out.post_key(
            "VIEW_POINT",
            self.point_view(ctx, true, false),
            PostKey::Tag("wpt"),
        );
        let far = self.nextpt.dist(&self.trackpt) > 5.0;
        out.post_key(
            "VIEW_POINT",
            self.point_view(ctx, far, true),
            PostKey::Tag("trk"),
        );
        if !self.var_dist_prev.is_empty() {
            out.post(self.var_dist_prev.clone(), self.dist_to_prev(here));
        }
        if !self.var_dist_next.is_empty() {
            out.post(self.var_dist_next.clone(), self.nextpt.dist(&here));
        }
        self.build_of(ctx, out)
    }

    fn macro_value(&self, name: &str, out: &mut String) -> bool {
        let n = self.points.len();
        // Numbers as MOOS `macroExpand(double)`: doubleToStringX(v, 3); booleans through the
        // integer overload (1/0).
        let flag = |out: &mut String, b: bool| out.push(if b { '1' } else { '0' });
        match name {
            "POINTS" => geometry::spec::write_points(out, self.points.points(), 1),
            "SPEED" => compact(out, self.speed, 3),
            "SPEED_ALT" => compact(out, self.speed_alt, 3),
            "USE_SPEED_ALT" => flag(out, self.use_alt_speed),
            "IPF_TYPE" => out.push_str(match self.ipf_type {
                IpfType::Zaic => "zaic",
                IpfType::ZaicSpd => "zaic_spd",
            }),
            "WPT_FLAG_ON_START" => flag(out, self.wptflag_on_start),
            "LEAD_TO_START" => flag(out, self.lead_to_start),
            "LEAD_DAMPER" => compact(out, self.lead_damper, 3),
            "ORDER" => out.push_str(if self.reverse { "reverse" } else { "normal" }),
            "PI" => match self.prev_ix {
                Some(i) => compact(out, i as f64, 0),
                None => out.push_str("-1"),
            },
            "CYC_DIST_TOGO" => compact(out, self.dist_to_end_cycle(), 3),
            "ALL_DIST_TOGO" => compact(out, self.dist_to_end_final(), 3),
            "X" => compact(out, self.hitpt.x, 3),
            "Y" => compact(out, self.hitpt.y, 3),
            "PX" => compact(out, self.prevpt.map_or(self.hitpt.x, |p| p.x), 3),
            "PY" => compact(out, self.prevpt.map_or(self.hitpt.y, |p| p.y), 3),
            "NX" => compact(out, self.nextpt.x, 3),
            "NY" => compact(out, self.nextpt.y, 3),
            "IX" | "NI" => compact(out, self.curr_ix as f64, 0),
            "CYCLES" => compact(out, f64::from(self.cycles), 0),
            "CYCREM" => compact(
                out,
                f64::from(self.repeats.saturating_sub(self.repeats_sofar)),
                0,
            ),
            "WPTS_HIT" => compact(out, f64::from(self.capture_hits + self.nonmono_hits), 0),
            "WPTS" => compact(out, n as f64, 0),
            "WPTS_REM" => compact(out, n.saturating_sub(self.curr_ix) as f64, 0),
            _ => return false,
        }
        true
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::behavior::{Emit, MapInfo};
    use ivp::{Domain, Problem};

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

    fn configure(w: &mut Waypoint, c: &mut Common, params: &[(&str, &str)]) {
        let d = domain();
        let i = info(0.0, 0.0, 0.0);
        let ctx = Ctx {
            info: &i,
            domain: &d,
            ownship: "abe",
            name: "wpt",
            perpetual: false,
        };
        for (k, v) in params {
            w.set_param(k, v, c, &ctx).unwrap();
        }
    }

    /// Runs one iteration at (x, y, heading); returns (course, speed) or None.
    fn run(
        w: &mut Waypoint,
        c: &Common,
        x: f64,
        y: f64,
        h: f64,
        out: &mut Out,
    ) -> Option<(f64, f64)> {
        let d = domain();
        let i = info(x, y, h);
        let ctx = Ctx {
            info: &i,
            domain: &d,
            ownship: "abe",
            name: "wpt",
            perpetual: c.perpetual,
        };
        let f = w.on_run(&ctx, out)?;
        let mut p = Problem::new(d.clone());
        p.add("wpt", f.with_pwt(100.0)).unwrap();
        let dec = p.solve().unwrap();
        Some((dec.get("course").unwrap(), dec.get("speed").unwrap()))
    }

    fn posted<'a>(out: &'a Out, var: &str) -> Vec<&'a crate::Value> {
        out.emits
            .iter()
            .filter_map(|e| match e {
                Emit::Post { var: v, value, .. } if v == var => Some(value),
                _ => None,
            })
            .collect()
    }

    #[test]
    fn point_due_east_gives_course_90_at_configured_speed() {
        let (mut w, mut c) = (Waypoint::new(), Common::new("BHV_Waypoint"));
        configure(&mut w, &mut c, &[("points", "100,0"), ("speed", "2.5")]);
        let mut out = Out::default();
        // Heading north: the heading-keeping component must not pull the course away.
        assert_eq!(run(&mut w, &c, 0.0, 0.0, 0.0, &mut out), Some((90.0, 2.5)));
        let stat = posted(&out, "WPT_STAT");
        assert_eq!(
            stat[0].as_str(),
            Some("vname=abe,behavior-name=wpt,index=0,hits=0/0,cycles=0,dist=100,eta=100")
        );
        assert_eq!(posted(&out, "WPT_INDEX")[0].as_num(), Some(0.0));
        let seglist = posted(&out, "VIEW_SEGLIST")[0].as_str().unwrap();
        assert!(
            seglist.starts_with("pts={100,0},label=abe_wpt"),
            "{seglist}"
        );
    }

    #[test]
    fn inside_capture_radius_the_next_point_is_taken() {
        let (mut w, mut c) = (Waypoint::new(), Common::new("BHV_Waypoint"));
        configure(
            &mut w,
            &mut c,
            &[
                ("points", "0,100:100,100"),
                ("speed", "2"),
                ("capture_radius", "5"),
            ],
        );
        let mut out = Out::default();
        let (course, _) = run(&mut w, &c, 0.0, 0.0, 0.0, &mut out).unwrap();
        assert_eq!(course, 0.0);
        // 6 m short: still seeking point 0.
        run(&mut w, &c, 0.0, 94.0, 0.0, &mut out).unwrap();
        assert_eq!(w.current_index(), 0);
        // 4 m short: captured; now heading east to (100, 100).
        let (course, _) = run(&mut w, &c, 0.0, 96.0, 0.0, &mut out).unwrap();
        assert_eq!(w.current_index(), 1);
        assert!((course - 88.0).abs() <= 1.0, "course {course}");
    }

    #[test]
    fn slip_radius_counts_as_arrival_when_moving_away() {
        let (mut w, mut c) = (Waypoint::new(), Common::new("BHV_Waypoint"));
        configure(
            &mut w,
            &mut c,
            &[
                ("points", "0,100:0,200"),
                ("capture_radius", "3"),
                ("slip_radius", "15"),
            ],
        );
        let mut out = Out::default();
        run(&mut w, &c, 10.0, 90.0, 0.0, &mut out);
        run(&mut w, &c, 10.0, 100.0, 0.0, &mut out); // closest: 10 m, inside slip radius
        assert_eq!(w.current_index(), 0);
        run(&mut w, &c, 10.0, 102.0, 0.0, &mut out); // moving away: non-monotonic arrival
        assert_eq!(w.current_index(), 1);

        // With a CPA outside the slip radius, moving away is not an arrival.
        let (mut w, mut c) = (Waypoint::new(), Common::new("BHV_Waypoint"));
        configure(&mut w, &mut c, &[("points", "0,100:0,200")]);
        run(&mut w, &c, 20.0, 100.0, 0.0, &mut out);
        run(&mut w, &c, 20.0, 104.0, 0.0, &mut out);
        assert_eq!(w.current_index(), 0);
    }

    #[test]
    fn capture_line_advances_once_past_the_perpendicular() {
        let (mut w, mut c) = (Waypoint::new(), Common::new("BHV_Waypoint"));
        configure(
            &mut w,
            &mut c,
            &[
                ("points", "0,100:0,200"),
                ("capture_line", "true"),
                ("slip_radius", "0"),
            ],
        );
        let mut out = Out::default();
        run(&mut w, &c, 0.0, 0.0, 0.0, &mut out);
        run(&mut w, &c, 40.0, 99.0, 0.0, &mut out);
        assert_eq!(w.current_index(), 0);
        run(&mut w, &c, 40.0, 100.5, 0.0, &mut out);
        assert_eq!(w.current_index(), 1);
    }

    #[test]
    fn lead_and_damper_move_the_aim_point() {
        // Leg (0,0) -> (0,100); vehicle 10 m east of the line at y = 30.
        let run_lead = |params: &[(&str, &str)]| {
            let (mut w, mut c) = (Waypoint::new(), Common::new("BHV_Waypoint"));
            let mut all = vec![("points", "0,0:0,100")];
            all.extend_from_slice(params);
            configure(&mut w, &mut c, &all);
            let mut out = Out::default();
            run(&mut w, &c, 0.0, -1.0, 0.0, &mut out); // captures (0,0)
            assert_eq!(w.current_index(), 1);
            run(&mut w, &c, 10.0, 30.0, 0.0, &mut out);
            w.track_point()
        };
        // No lead: aim at the point itself.
        assert_eq!(run_lead(&[]), Point::new(0.0, 100.0));
        // lead 20: 20 m ahead of the perpendicular foot (0, 30).
        assert_eq!(run_lead(&[("lead", "20")]), Point::new(0.0, 50.0));
        // damper 20 at 10 m off the line: factor 1 + 2*(1 - 10/20) = 2 -> 40 m ahead.
        assert_eq!(
            run_lead(&[("lead", "20"), ("lead_damper", "20")]),
            Point::new(0.0, 70.0)
        );
        // Beyond the damper distance the lead is unchanged.
        assert_eq!(
            run_lead(&[("lead", "20"), ("lead_damper", "5")]),
            Point::new(0.0, 50.0)
        );
    }

    #[test]
    fn last_point_completes_or_cycles_with_repeat() {
        let (mut w, mut c) = (Waypoint::new(), Common::new("BHV_Waypoint"));
        configure(
            &mut w,
            &mut c,
            &[("points", "0,10"), ("cycleflag", "LAP = $[CYCLES]")],
        );
        let mut out = Out::default();
        assert!(run(&mut w, &c, 0.0, 9.0, 0.0, &mut out).is_none());
        assert!(out.completed);
        assert_eq!(
            posted(&out, "WPT_STAT")[0].as_str(),
            Some("behavior-name=wpt,completed")
        );
        assert!(
            out.emits
                .iter()
                .any(|e| matches!(e, Emit::Flag { flag, .. } if flag.var == "LAP"))
        );

        let (mut w, mut c) = (Waypoint::new(), Common::new("BHV_Waypoint"));
        configure(&mut w, &mut c, &[("points", "0,10:0,20"), ("repeat", "1")]);
        assert!(c.perpetual, "repeat > 0 makes the behaviour perpetual");
        let mut out = Out::default();
        run(&mut w, &c, 0.0, 9.0, 0.0, &mut out);
        run(&mut w, &c, 0.0, 19.0, 0.0, &mut out);
        assert!(!out.completed);
        assert_eq!(w.cycles(), 1);
        assert_eq!(w.current_index(), 0);
        run(&mut w, &c, 0.0, 9.0, 0.0, &mut out);
        let mut out = Out::default();
        assert!(run(&mut w, &c, 0.0, 19.0, 0.0, &mut out).is_none());
        assert!(out.completed);
    }

    #[test]
    fn reverse_order_polygon_form_and_alt_speed() {
        let (mut w, mut c) = (Waypoint::new(), Common::new("BHV_Waypoint"));
        configure(
            &mut w,
            &mut c,
            &[
                ("polygon", "60,-40:60,-160:150,-160:180,-100:150,-40"),
                ("order", "reverse"),
                ("speed", "3"),
                ("speed_alt", "1.2"),
                ("use_alt_speed", "true"),
            ],
        );
        assert_eq!(w.points().get(0), Some(Point::new(150.0, -40.0)));
        let mut out = Out::default();
        let (_, speed) = run(&mut w, &c, 0.0, 0.0, 90.0, &mut out).unwrap();
        assert!((speed - 1.2).abs() < 1e-9, "speed {speed}");
        let mut s = String::new();
        assert!(w.macro_value("NX", &mut s));
        assert_eq!(s, "150");
    }

    #[test]
    fn bad_values_are_typed_errors() {
        let (mut w, mut c) = (Waypoint::new(), Common::new("BHV_Waypoint"));
        let d = domain();
        let i = info(0.0, 0.0, 0.0);
        let ctx = Ctx {
            info: &i,
            domain: &d,
            ownship: "abe",
            name: "wpt",
            perpetual: false,
        };
        for (k, v) in [
            ("capture_radius", "0"),
            ("speed", "fast"),
            ("order", "sideways"),
            ("repeat", "-1"),
            ("points", "not a point"),
            ("patience", "100"),
        ] {
            assert!(
                matches!(
                    w.set_param(k, v, &mut c, &ctx),
                    Err(ParamError::BadValue { .. })
                ),
                "{k} = {v}"
            );
        }
        assert_eq!(
            w.set_param("capture_radiuss", "3", &mut c, &ctx),
            Err(ParamError::unknown("capture_radiuss"))
        );
        // A rejected value leaves the old one.
        assert_eq!(w.capture_radius, 3.0);
    }

    fn run_at(
        w: &mut Waypoint,
        c: &Common,
        x: f64,
        y: f64,
        t: f64,
        out: &mut Out,
    ) -> Option<IvpFunction> {
        let d = domain();
        let i = info(x, y, 90.0).num("NAV_SPEED", 2.0);
        let mut i = i;
        i.set_now(t);
        let ctx = Ctx {
            info: &i,
            domain: &d,
            ownship: "abe",
            name: "wpt",
            perpetual: c.perpetual,
        };
        w.on_run(&ctx, out)
    }

    #[test]
    fn lead_to_start_anchors_the_first_leg_at_the_start_position() {
        let (mut w, mut c) = (Waypoint::new(), Common::new("BHV_Waypoint"));
        configure(
            &mut w,
            &mut c,
            &[
                ("point", "100,0"),
                ("speed", "2"),
                ("lead", "10"),
                ("lead_damper", "1"),
                ("lead_to_start", "true"),
            ],
        );
        let mut out = Out::default();
        run(&mut w, &c, 0.0, 10.0, 0.0, &mut out).unwrap();
        // On the start line (damper factor 3): 30 m along the leg from (0,10) to (100,0).
        let t = w.track_point();
        assert!(
            (t.x - 29.8511).abs() < 0.01 && (t.y - 7.01489).abs() < 0.01,
            "{t:?}"
        );
        // Without lead_to_start the first leg has no anchor: aim at the point.
        let (mut w, mut c) = (Waypoint::new(), Common::new("BHV_Waypoint"));
        configure(
            &mut w,
            &mut c,
            &[("point", "100,0"), ("lead", "10"), ("lead_damper", "1")],
        );
        run(&mut w, &c, 0.0, 10.0, 0.0, &mut out).unwrap();
        assert_eq!(w.track_point(), Point::new(100.0, 0.0));
    }

    #[test]
    fn lead_condition_switches_the_lead_point() {
        let (mut w, mut c) = (Waypoint::new(), Common::new("BHV_Waypoint"));
        configure(
            &mut w,
            &mut c,
            &[
                ("points", "0,0:100,0"),
                ("radius", "5"),
                ("lead", "10"),
                ("lead_damper", "1"),
                ("lead_condition", "ALLOW_LEAD=true"),
            ],
        );
        let d = domain();
        let mut out = Out::default();
        for (allow, x, y, want) in [("false", 0.0, 0.0, 100.0), ("true", 20.0, 10.0, 30.0)] {
            let i = info(x, y, 90.0).text("ALLOW_LEAD", allow);
            let ctx = Ctx {
                info: &i,
                domain: &d,
                ownship: "abe",
                name: "wpt",
                perpetual: false,
            };
            w.on_run(&ctx, &mut out).unwrap();
            assert!(
                (w.track_point().x - want).abs() < 0.01,
                "{allow}: {:?}",
                w.track_point()
            );
        }
        assert!(
            w.set_param(
                "lead_condition",
                "ALLOW_LEAD >",
                &mut c,
                &Ctx {
                    info: &info(0.0, 0.0, 0.0),
                    domain: &d,
                    ownship: "abe",
                    name: "wpt",
                    perpetual: false
                }
            )
            .is_err()
        );
    }

    #[test]
    fn end_speed_tapers_towards_the_final_point() {
        let (mut w, mut c) = (Waypoint::new(), Common::new("BHV_Waypoint"));
        configure(
            &mut w,
            &mut c,
            &[
                ("point", "100,0"),
                ("speed", "2"),
                ("capture_radius", "0.1"),
                ("slip_radius", "0"),
                ("end_spd", "slow_dist=25,stop_dist=1"),
            ],
        );
        // 20 m out: 2 * (20 - 1) / 24 = 1.58 m/s; 40 m out: full speed; 0.5 m out: stop.
        assert!((w.desired_speed(80.0, 0.0) - 2.0 * 19.0 / 24.0).abs() < 1e-12);
        assert_eq!(w.desired_speed(60.0, 0.0), 2.0);
        assert_eq!(w.desired_speed(99.5, 0.0), 0.0);
        let mut out = Out::default();
        let (_, speed) = run(&mut w, &c, 80.0, 0.0, 90.0, &mut out).unwrap();
        assert!((speed - 1.6).abs() < 1e-9, "{speed}");
        let d = domain();
        let i = info(0.0, 0.0, 0.0);
        let ctx = Ctx {
            info: &i,
            domain: &d,
            ownship: "abe",
            name: "wpt",
            perpetual: false,
        };
        assert!(
            w.set_param("end_spd", "slow_dist=10,stop_dist=20", &mut c, &ctx)
                .is_err()
        );
    }

    #[test]
    fn greedy_tour_starts_at_the_nearest_point() {
        let (mut w, mut c) = (Waypoint::new(), Common::new("BHV_Waypoint"));
        configure(
            &mut w,
            &mut c,
            &[("points", "30,0:10,0:20,0"), ("greedy_tour", "true")],
        );
        let mut out = Out::default();
        run(&mut w, &c, 0.0, 0.0, 90.0, &mut out).unwrap();
        let xs: Vec<f64> = w.points().points().iter().map(|p| p.x).collect();
        assert_eq!(xs, [10.0, 20.0, 30.0]);
    }

    #[test]
    fn reset_on_idle_rewinds_only_when_enabled() {
        for (reset, want) in [("true", 0), ("false", 1)] {
            let (mut w, mut c) = (Waypoint::new(), Common::new("BHV_Waypoint"));
            configure(
                &mut w,
                &mut c,
                &[
                    ("points", "0,0:50,0"),
                    ("radius", "5"),
                    ("reset_on_idle", reset),
                ],
            );
            let mut out = Out::default();
            run(&mut w, &c, 0.0, 0.0, 90.0, &mut out).unwrap();
            assert_eq!(w.current_index(), 1);
            let d = domain();
            let i = info(0.0, 0.0, 0.0);
            let ctx = Ctx {
                info: &i,
                domain: &d,
                ownship: "abe",
                name: "wpt",
                perpetual: false,
            };
            w.on_run_to_idle(&ctx, &mut out);
            assert_eq!(w.current_index(), want, "reset_on_idle = {reset}");
        }
    }

    #[test]
    fn xpoints_keeps_progress_and_needs_the_same_length() {
        let (mut w, mut c) = (Waypoint::new(), Common::new("BHV_Waypoint"));
        configure(
            &mut w,
            &mut c,
            &[("points", "0,100:100,100"), ("radius", "10")],
        );
        let mut out = Out::default();
        run(&mut w, &c, 0.0, 95.0, 0.0, &mut out).unwrap();
        assert_eq!(w.current_index(), 1);
        let d = domain();
        let i = info(0.0, 95.0, 0.0);
        let ctx = Ctx {
            info: &i,
            domain: &d,
            ownship: "abe",
            name: "wpt",
            perpetual: false,
        };
        w.set_param("xpoints", "pts={0,100:200,100}", &mut c, &ctx)
            .unwrap();
        assert!(
            w.set_param("xpoints", "pts={0,100:200,100:300,100}", &mut c, &ctx)
                .is_err()
        );
        let mut out = Out::default();
        run(&mut w, &c, 0.0, 95.0, 0.0, &mut out).unwrap();
        assert_eq!(w.current_index(), 1);
        let vp = posted(&out, "VIEW_POINT")[0].as_str().unwrap();
        assert!(vp.starts_with("x=200,y=100"), "{vp}");
    }

    #[test]
    fn point_start_waits_for_the_first_position_and_empty_has_no_function() {
        let (mut w, mut c) = (Waypoint::new(), Common::new("BHV_Waypoint"));
        let d = domain();
        let none = MapInfo::new(0.0);
        let ctx = Ctx {
            info: &none,
            domain: &d,
            ownship: "abe",
            name: "wpt",
            perpetual: false,
        };
        w.set_param("point", "start", &mut c, &ctx).unwrap();
        assert!(w.points().is_empty());
        let i = info(12.0, -8.0, 45.0);
        let ctx = Ctx {
            info: &i,
            domain: &d,
            ownship: "abe",
            name: "wpt",
            perpetual: false,
        };
        let mut out = Out::default();
        w.on_idle(&ctx, &mut out);
        assert_eq!(w.points().get(0), Some(Point::new(12.0, -8.0)));

        let (mut w, mut c) = (Waypoint::new(), Common::new("BHV_Waypoint"));
        configure(&mut w, &mut c, &[("points", "empty")]);
        let mut out = Out::default();
        assert!(run(&mut w, &c, 0.0, 0.0, 0.0, &mut out).is_none());
    }

    #[test]
    fn status_after_a_cycle_with_custom_variables() {
        let (mut w, mut c) = (Waypoint::new(), Common::new("BHV_Waypoint"));
        configure(
            &mut w,
            &mut c,
            &[
                ("points", "pts={0,0:10,0}"),
                ("speed", "2"),
                ("radius", "1"),
                ("repeat", "1"),
                ("post_suffix", "CUSTOM"),
                ("wpt_status", "WPT_STATUS"),
                ("wpt_dist_to_prev", "CUSTOM_DIST_TO_PREV"),
                ("wpt_dist_to_next", "CUSTOM_DIST_TO_NEXT"),
            ],
        );
        let mut out = Out::default();
        assert!(run_at(&mut w, &c, 0.0, 0.0, 0.0, &mut out).is_some());
        assert_eq!(posted(&out, "WPT_INDEX_CUSTOM")[0].as_num(), Some(1.0));
        assert_eq!(posted(&out, "CUSTOM_DIST_TO_NEXT")[0].as_num(), Some(10.0));
        let mut out = Out::default();
        assert!(run_at(&mut w, &c, 10.0, 0.0, 1.0, &mut out).is_some());
        assert_eq!(posted(&out, "CYCLE_INDEX_CUSTOM")[0].as_num(), Some(1.0));
        assert_eq!(posted(&out, "WPT_INDEX_CUSTOM")[0].as_num(), Some(0.0));
        assert_eq!(posted(&out, "CUSTOM_DIST_TO_PREV")[0].as_num(), Some(10.0));
        assert_eq!(posted(&out, "CUSTOM_DIST_TO_NEXT")[0].as_num(), Some(10.0));
        let stat = posted(&out, "WPT_STATUS_CUSTOM")
            .into_iter()
            .filter_map(|v| v.as_str())
            .find(|s| s.contains("index="))
            .unwrap();
        assert_eq!(
            stat,
            "vname=abe,behavior-name=wpt,index=0,hits=2/2,cycles=1,dist=10,eta=5"
        );
    }

    #[test]
    fn efficiency_of_one_leg() {
        let (mut w, mut c) = (Waypoint::new(), Common::new("BHV_Waypoint"));
        configure(
            &mut w,
            &mut c,
            &[
                ("points", "pts={0,0:10,0}"),
                ("speed", "2"),
                ("capture_radius", "1"),
                ("slip_radius", "0"),
                ("efficiency_measure", "all"),
            ],
        );
        let mut out = Out::default();
        run_at(&mut w, &c, 0.0, 0.0, 0.0, &mut out).unwrap();
        run_at(&mut w, &c, 6.0, 0.0, 3.0, &mut out).unwrap();
        let mut out = Out::default();
        assert!(run_at(&mut w, &c, 10.0, 0.0, 6.0, &mut out).is_none());
        assert!(out.completed);
        assert!((posted(&out, "WPT_EFF_DIST_ALL")[0].as_num().unwrap() - 1.0).abs() < 1e-6);
        assert!((posted(&out, "WPT_EFF_TIME_ALL")[0].as_num().unwrap() - 5.0 / 6.0).abs() < 1e-3);
        let sum = posted(&out, "WPT_EFF_SUMM_ALL")[0].as_str().unwrap();
        assert_eq!(
            sum,
            "vname=abe, bhv_name=wpt, linear_dist=10, odo_dist=10, efficiency_dist=1, \
             linear_time=5, odo_time=6, efficiency_time=0.833"
        );
    }
}
