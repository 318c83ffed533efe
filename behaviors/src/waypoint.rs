//! BHV_Waypoint (reference §6.1): follows a list of points with capture/slip radii, capture
//! line, lead point, repeats, flags and viewer postings.
//!
//! # Conformance with BHV_Waypoint (MOOS-IvP a2a9b716)
//!
//! Numbers the C++ reads with `atof` (`radius`, `slip_radius`, `lead_damper`, `currix`,
//! `crs_spd_zaic_ratio`) take the numeric prefix of the value (`"abc"` is 0); `repeat` reads
//! the integer prefix of a number (`2.5` is 2). Booleans marked "MOOS boolean" take
//! `true/false/yes/no/on/off/toggle` in any case.
//!
//! | parameter | aliases | type | default | validation (C++ rule) | runtime update | coug |
//! |---|---|---|---|---|---|---|
//! | points | polygon, xpoints | seglist / polygon / pattern; `empty`, `start` | none | any `string2SegList` / `string2Poly` form, at least one point; `empty` and `start` only record the intent (the route is kept) | yes | done |
//! | xpoints | | points | | same length as the route; keeps the index and the reported indices | yes | done |
//! | point | | point; `empty`, `start` | | `string2Point`; `start`: the first known position (3 decimals) once the route is empty | yes | done |
//! | newpt | | point | | `string2Point`; appended to the route, ignored (accepted) while the order is reversed | yes | done |
//! | speed | | m/s | 0 | number >= 0, clipped to the domain | yes | done |
//! | speed_alt | | m/s | −1 (unused) | number >= 0 | yes | done |
//! | use_alt_speed | | MOOS boolean | false | any value accepted, a bad one ignored | yes | done |
//! | capture_radius | radius | m | 3 | > 0 | yes | done |
//! | slip_radius | nm_radius | m | 15 | >= 0 | yes | done |
//! | capture_line | | true, false, absolute | false | `absolute` also zeroes both radii | yes | done |
//! | lead | | m | −1 (off) | number; <= 0 turns it off | yes | done |
//! | lead_damper | | m | −1 (off) | > 0 | yes | done |
//! | lead_to_start | | MOOS boolean | false | | yes | done |
//! | lead_condition | | condition | none | logic condition (`,` read as `=`); several must all hold | yes | done |
//! | order | | normal, reverse(d), toggle | normal | exact lower case | yes | done |
//! | repeat | | integer or `forever` | 0 | number >= 0; > 0 or `forever` makes the behaviour perpetual | yes | done |
//! | currix | | index | 0 | >= 0; an index past the route is accepted and ignored | yes | done |
//! | greedy_tour | shortest_tour | MOOS boolean | false | any value accepted, a bad one ignored; the route is reordered nearest-first from the next known position (then reversed again if the order is reversed) | yes | done |
//! | wpt_status | wpt_status_var | var or `silent` | WPT_STAT | non-empty, no white space | yes | done |
//! | wpt_index | wpt_index_var | var or `silent` | WPT_INDEX | non-empty, no white space | yes | done |
//! | cycle_index_var | | var or `silent` | CYCLE_INDEX | non-empty, no white space | yes | done |
//! | wpt_dist_to_prev, wpt_dist_to_next | | var, empty or `silent` (off) | off | no white space | yes | done |
//! | post_suffix | | text | none | no white space; `_` prepended | yes | done |
//! | cycleflag, wptflag | | flag | none | `VAR=value` | yes | done |
//! | wptflag_on_start | | MOOS boolean | false | | yes | done |
//! | reset_on_idle | | MOOS boolean | false | | yes | done |
//! | ipf_type | ipf-type | zaic, zaic_spd, roc, rate_of_closure | zaic | any case (kept in lower case for `IPF_TYPE` and BHV_SETTINGS); any other value accepted and ignored | yes | done |
//! | ipf_type = roc | rate_of_closure | | | | | done: `AOF_Waypoint` reflected with 600 uniform pieces and 500 by smart refinement ([`roc`]); the desired speed as for the ZAICs (speed_alt, end_spd); crs_spd_zaic_ratio unused |
//! | crs_spd_zaic_ratio | patience | % course | 50 | in [1, 99]; the zaic types only (roc does not read it) | yes | done |
//! | efficiency_measure | | all, off | off | any case | yes | done |
//! | end_spd | | `slow_dist=..,stop_dist=..` | none | both given, slow > 0, stop >= 0, stop <= slow | yes | done |
//! | visual_hints | | hints | see [`Waypoint::new`] | each hint a colour (`isColor`) or a number; stops at the first bad one | yes | done |
//! | draw_path_loop | | MOOS boolean | false | | yes | done |
//! | eager_prev_index_flag | | MOOS boolean | false | | yes | done |
//!
//! | variable | when | format | coug |
//! |---|---|---|---|
//! | WPT_STAT`<sfx>` | each running iteration with a point to go; `completed`/`cycled` on those events | `vname=..,behavior-name=..,index=..,hits=..,cycles=..,dist=..,eta=..` | done |
//! | WPT_INDEX`<sfx>` | running, when the index differs from the last reported one | number | done |
//! | CYCLE_INDEX`<sfx>` | running, when the cycle count changes (not at 0) | number | done |
//! | `wpt_dist_to_prev`, `wpt_dist_to_next` | each running iteration with a point to go; −1 on running→idle | metres | done |
//! | WPT_ODO`<sfx>`, WPT_EFF_DIST_*, WPT_EFF_TIME_*, WPT_EFF_SUMM_* | WPT_ODO each running iteration; the rest on arrivals with efficiency_measure | numbers / summary | done |
//! | VIEW_SEGLIST, VIEW_POINT (`wpt`, `trk`) | running (drawn), running→idle and completed (erased) | specs | done |
//! | VIEW_POLYGON | with draw_path_loop, when the route is a convex polygon, before VIEW_SEGLIST | spec | done |
//! | BHV_SETTINGS | after configuration (once) and after each successful update (twice: the C++ posts it from `checkUpdates` and from `onSetParamComplete`), repeatable | `type=BHV_Waypoint,name=..,points=..,speed=..,...,crs_spd_zaic_ratio=..` | done |
//! | BHV_WARNING | after configuration/updates | `cycles/repeats not supported with single waypt`; `No waypts given. Set val to empty if intentional` (or its retraction, a filtered posting) | done |
//! | WAYPT_UPIECE | never: the C++ posting is commented out | | done (not posted) |
//!
//! | macro | meaning | coug |
//! |---|---|---|
//! | POINTS, SPEED, SPEED_ALT, USE_SPEED_ALT, IPF_TYPE, WPT_FLAG_ON_START, LEAD_TO_START, LEAD_DAMPER, ORDER | configuration (numbers 3 decimals, booleans 1/0) | done |
//! | NI, NX, NY, PI, PX, PY, X, Y, IX | next/previous point and index (X, Y = PX, PY) | done |
//! | CYCLES, CYCREM, WPTS_HIT, WPTS_REM, WPTS | progress counts | done |
//! | CYC_DIST_TOGO, ALL_DIST_TOGO | distance to the end of the cycle / of all cycles (−1 if endless) | done |

#[path = "waypoint_roc.rs"]
pub mod roc;

use geometry::spec::{parse_point, parse_waypoints};
use geometry::{Attributes, Point, Polygon, SegList, Segment, ViewPoint, ViewPolygon, ViewSegList};
use ivp::{IvpFunction, PeakComponent, ZaicPeak, ZaicSpd, couple_weighted};

use crate::behavior::{Behavior, Ctx, Out, ParamError, PostKey, add_flag_vars, add_vars, nav};
use crate::color::Hints;
use crate::common::{Common, Flag};
use crate::fmt::compact;
use crate::param::{atof, is_number, moos_boolean};

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
    /// `roc`: the rate-of-closure function [`roc::AofWaypoint`], reflected.
    Roc,
    /// `rate_of_closure`: the same as [`IpfType::Roc`] under its long name.
    RateOfClosure,
}

impl IpfType {
    fn name(self) -> &'static str {
        match self {
            IpfType::Zaic => "zaic",
            IpfType::ZaicSpd => "zaic_spd",
            IpfType::Roc => "roc",
            IpfType::RateOfClosure => "rate_of_closure",
        }
    }
}

/// The waypoint behaviour. See the module docs and reference §6.1.
#[derive(Debug, Clone)]
pub struct Waypoint {
    // --- the waypoint engine (MOOS `WaypointEngine`) ---
    raw: SegList,
    points: SegList,
    reverse: bool,
    curr_ix: usize,
    /// The engine's previous index (for the distance to the previous point).
    prev_ix: Option<usize>,
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
    perpetual: bool,
    /// The previous point handed to the engine for this iteration's capture line.
    engine_prev: Option<Point>,

    // --- configuration ---
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
    eager_prev_index: bool,
    reset_on_idle: bool,
    draw_path_loop: bool,
    efficiency: bool,
    hints: Hints,
    lead_conditions: Vec<mission::condition::Condition>,
    slow_dist: f64,
    stop_dist: f64,
    waypts_init: String,
    greedy_pending: bool,

    // --- state ---
    wpt_flag_published: bool,
    waypt_hit: bool,
    /// The previous point (MOOS `m_prevpt`): coordinates are kept when it is invalidated.
    prevpt: Point,
    prevpt_valid: bool,
    markpt: Option<Point>,
    prev_waypt_index: i64,
    prev_cycle_index: u32,
    nextpt: Point,
    trackpt: Point,
    nextpt_attrs: Attributes,
    trackpt_attrs: Attributes,
    os: (f64, f64, f64, f64),
    odo_prev: Option<Point>,
    odo_leg: f64,
    odo_mark: Option<(Point, f64)>,
    odo_disq: bool,
    odo_totals: [f64; 4],
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
    seglist: Cached<SegList>,
    /// `<var_report><suffix>`, `<var_index><suffix>`, `<var_cyindex><suffix>`.
    names: Option<[String; 3]>,
}

impl Views {
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

/// The behaviour's own macros (see [`Behavior::macro_value`]).
const MACROS: [&str; 25] = [
    "POINTS",
    "SPEED",
    "SPEED_ALT",
    "USE_SPEED_ALT",
    "IPF_TYPE",
    "WPT_FLAG_ON_START",
    "LEAD_TO_START",
    "LEAD_DAMPER",
    "ORDER",
    "NI",
    "NX",
    "NY",
    "PI",
    "PX",
    "PY",
    "X",
    "Y",
    "IX",
    "CYCLES",
    "CYCREM",
    "WPTS_HIT",
    "WPTS_REM",
    "WPTS",
    "CYC_DIST_TOGO",
    "ALL_DIST_TOGO",
];

/// The integer prefix of a number, as C's `atoi` reads it.
fn atoi(s: &str) -> i64 {
    let t = s.trim_start();
    let (sign, digits) = match t.as_bytes().first() {
        Some(b'-') => (-1, &t[1..]),
        Some(b'+') => (1, &t[1..]),
        _ => (1, t),
    };
    let end = digits
        .find(|c: char| !c.is_ascii_digit())
        .unwrap_or(digits.len());
    sign * digits[..end].parse::<i64>().unwrap_or(0)
}

impl Waypoint {
    /// The MOOS defaults: no points, speed 0, capture radius 3, slip radius 15, hints
    /// `vertex_size=3, edge_size=1, vertex_color=dodger_blue, edge_color=white,
    /// label_color=white, nextpt_color=yellow, nextpt_label_color=aqua, nextpt_vertex_size=5`.
    pub fn new() -> Self {
        let mut hints = Hints::default();
        hints.set_measure("vertex_size", "3");
        hints.set_measure("edge_size", "1");
        hints.set_color("vertex_color", "dodger_blue");
        hints.set_color("edge_color", "white");
        hints.set_color("label_color", "white");
        hints.set_color("nextpt_color", "yellow");
        hints.set_color("nextpt_label_color", "aqua");
        hints.set_measure("nextpt_vertex_size", "5");
        Waypoint {
            raw: SegList::new(),
            points: SegList::new(),
            reverse: false,
            curr_ix: 0,
            prev_ix: None,
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
            complete: true,
            perpetual: false,
            engine_prev: None,
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
            eager_prev_index: false,
            reset_on_idle: false,
            draw_path_loop: false,
            efficiency: false,
            hints,
            lead_conditions: Vec::new(),
            slow_dist: -1.0,
            stop_dist: -1.0,
            waypts_init: String::new(),
            greedy_pending: false,
            wpt_flag_published: false,
            waypt_hit: false,
            prevpt: Point::new(0.0, 0.0),
            prevpt_valid: false,
            markpt: None,
            prev_waypt_index: -1,
            prev_cycle_index: 0,
            nextpt: Point::new(0.0, 0.0),
            trackpt: Point::new(0.0, 0.0),
            nextpt_attrs: Attributes::default(),
            trackpt_attrs: Attributes::default(),
            os: (0.0, 0.0, 0.0, 0.0),
            odo_prev: None,
            odo_leg: 0.0,
            odo_mark: None,
            odo_disq: false,
            odo_totals: [0.0; 4],
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

    // ----- engine (MOOS WaypointEngine) -----

    /// A new route (MOOS `setSegList`): index 0, cycle count 0, not complete; reversed when
    /// the order is reversed. Hits and repeats so far are kept.
    fn set_seglist(&mut self, seglist: SegList) {
        self.curr_ix = 0;
        self.complete = false;
        self.cpa = None;
        self.cycles = 0;
        self.prev_ix = None;
        self.raw = seglist;
        self.points = self.raw.clone();
        if self.reverse {
            self.points.reverse();
        }
    }

    /// MOOS `setReverse`: a change of order restarts the route at index 0.
    fn set_reverse(&mut self, reverse: bool) {
        if self.reverse == reverse {
            return;
        }
        self.reverse = reverse;
        self.points = self.raw.clone();
        if reverse {
            self.points.reverse();
        }
        self.curr_ix = 0;
        self.prev_ix = None;
        self.complete = false;
    }

    /// MOOS `setCurrIndex`: ignored past the last point.
    fn set_curr_index(&mut self, i: usize) {
        if i < self.points.len() {
            self.curr_ix = i;
            self.cpa = None;
        }
    }

    /// MOOS `resetForNewTraversal`.
    fn reset_for_new_traversal(&mut self) {
        self.repeats_sofar = 0;
        self.cpa = None;
        self.curr_ix = 0;
        self.prev_ix = None;
        self.complete = false;
    }

    fn point_at(&self, i: usize) -> Point {
        self.points.get(i).unwrap_or(Point::new(0.0, 0.0))
    }

    /// Distance from `(x, y)` to the end of the current cycle: to the next point, then along
    /// the remaining legs (MOOS `WaypointEngine::distToEndCycle`); −1 without a next point.
    fn dist_to_end_cycle(&self, x: f64, y: f64) -> f64 {
        let pts = self.points.points();
        let Some(next) = pts.get(self.curr_ix) else {
            return -1.0;
        };
        let mut d = (next.x - x).hypot(next.y - y);
        for w in pts[self.curr_ix..].windows(2) {
            d += (w[1].x - w[0].x).hypot(w[1].y - w[0].y);
        }
        d
    }

    /// [`Waypoint::dist_to_end_cycle`] plus the remaining full cycles, each the route length
    /// plus the gap from its last point back to its first (MOOS `distToEndFinal`); −1 when
    /// repeating endlessly.
    fn dist_to_end_final(&self, x: f64, y: f64) -> f64 {
        if self.endless {
            return -1.0;
        }
        let to_end = self.dist_to_end_cycle(x, y);
        let remaining = self.repeats.saturating_sub(self.repeats_sofar);
        let pts = self.points.points();
        if to_end < 0.0 || remaining == 0 {
            return to_end;
        }
        let legs: f64 = pts
            .windows(2)
            .map(|w| (w[1].x - w[0].x).hypot(w[1].y - w[0].y))
            .sum();
        let (a, b) = (pts[0], pts[pts.len() - 1]);
        to_end + f64::from(remaining) * (legs + (a.x - b.x).hypot(a.y - b.y))
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

    /// The speed to request at ownship `(x, y)`: the effective speed, tapered by `end_spd`
    /// along the distance still to go (MOOS `distToEndFinal`: to the end of this cycle plus
    /// the remaining cycles): 0 within `stop_dist`, linear up to full speed at `slow_dist`.
    /// As in the C++, an endless route (distance −1) with `end_spd` asks for speed 0.
    pub fn desired_speed(&self, x: f64, y: f64) -> f64 {
        let mut speed = self.effective_speed();
        if self.slow_dist > 0.0 {
            let d = self.dist_to_end_final(x, y);
            if d <= self.stop_dist {
                speed = 0.0;
            } else if d < self.slow_dist {
                let range = self.slow_dist - self.stop_dist;
                let pct = if range > 0.0 {
                    (d - self.stop_dist) / range
                } else {
                    0.0
                };
                speed *= pct;
            }
        }
        speed
    }

    /// One step of the waypoint engine for ownship at `(x, y)` (MOOS `setNextWaypoint`):
    /// capture radius, slip radius (non-monotonic arrival) and capture line. At the end of
    /// the route a behaviour that is not perpetual completes; a perpetual one cycles until
    /// its repeats are used up.
    pub fn step(&mut self, x: f64, y: f64) -> Step {
        let n = self.points.len();
        if n == 0 {
            return Step::Empty;
        }
        if self.complete {
            return Step::Completed;
        }
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
            && let Some(prev) = self.engine_prev
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
            if self.perpetual {
                self.repeats_sofar += 1;
                if !self.endless && self.repeats_sofar > self.repeats {
                    self.complete = true;
                }
            } else {
                self.complete = true;
            }
            return if self.complete {
                Step::Completed
            } else {
                Step::Cycled
            };
        }
        self.prev_ix = Some(self.curr_ix - 1);
        self.engine_prev = None;
        let next = self.points.points()[self.curr_ix];
        self.cpa = Some((x - next.x).hypot(y - next.y));
        Step::Advanced
    }

    // ----- behaviour -----

    /// MOOS `updateInfoIn`: reads ownship (an error without it) and applies a pending
    /// greedy tour. `None` when ownship is unknown.
    fn update_info_in(&mut self, ctx: &Ctx<'_>, out: &mut Out) -> Option<(f64, f64, f64, f64)> {
        if ctx.info.num("NAV_X").is_none() || ctx.info.num("NAV_Y").is_none() {
            out.error("No ownship X/Y info in info_buffer.");
            return None;
        }
        let Some(os) = nav(ctx.info) else {
            out.error("No ownship heading info in info_buffer.");
            return None;
        };
        self.os = os;
        if self.greedy_pending {
            self.greedy_pending = false;
            self.greedy(os.0, os.1);
        }
        Some(os)
    }

    /// MOOS `onEveryState`: with `points = start` and an empty route, the route becomes the
    /// first known position (written with 3 decimals, as the C++ passes it to `point`).
    fn every_state(&mut self, ctx: &Ctx<'_>) {
        if self.points.is_empty()
            && self.waypts_init == "start"
            && let (Some(x), Some(y)) = (ctx.info.num("NAV_X"), ctx.info.num("NAV_Y"))
        {
            let round = |v: f64| crate::fmt::compact_string(v, 3).parse().unwrap_or(v);
            self.set_seglist(SegList::from_points(vec![Point::new(round(x), round(y))]));
            self.markpt = None;
        }
    }

    /// Reorders the route nearest-first from `(x, y)` (MOOS `greedyPath`: the first of equally
    /// near points wins), then sets it as a new route.
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
        self.set_seglist(SegList::from_points(tour));
    }

    /// `f` with this behaviour's macros expanded now (the C++ expands them when the flag is
    /// posted, mid-iteration); the helm expands the rest.
    fn flag_now(&self, f: &Flag) -> Flag {
        let mut f = f.clone();
        if let crate::common::FlagValue::String(s) = &mut f.value
            && s.contains(['[', '('])
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
        f
    }

    fn lead_allowed(&self, ctx: &Ctx<'_>) -> bool {
        self.lead_conditions.iter().all(|c| {
            c.evaluate(&|n: &str| match ctx.info.text(n) {
                Some(s) => Some(mission::condition::Value::String(s)),
                None => ctx.info.num(n).map(mission::condition::Value::Double),
            })
        })
    }

    fn set_next_waypoint(&mut self, ctx: &Ctx<'_>, out: &mut Out) -> bool {
        self.waypt_hit = false;
        if self.points.is_empty() {
            return false;
        }
        self.engine_prev = self.prevpt_valid.then_some(self.prevpt);
        let (osx, osy, _, _) = self.os;
        let step = self.step(osx, osy);
        if matches!(step, Step::Completed | Step::Cycled | Step::Advanced) {
            self.waypt_hit = true;
        }
        if step == Step::Empty {
            return false;
        }
        if step != Step::InTransit {
            self.mark_odo_leg(ctx, out);
        }
        out.post(format!("WPT_ODO{}", self.suffix), self.odo_leg);
        if matches!(step, Step::Completed | Step::Cycled) {
            if !self.var_report.eq_ignore_ascii_case("silent") {
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
                out.flag(&self.flag_now(f), true);
            }
        }
        if step == Step::Completed {
            out.complete();
            self.markpt = None;
            if self.perpetual {
                self.reset_for_new_traversal();
            }
            return false;
        }
        let next = self.points.points()[self.curr_ix];
        self.nextpt = next;
        self.trackpt = next;
        if self.lead >= 0.0 && self.lead_allowed(ctx) {
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
        let mark = match self.odo_mark {
            Some(m) if !self.odo_disq => m,
            _ => {
                self.odo_mark = Some((here, now));
                self.odo_leg = 0.0;
                self.odo_disq = false;
                return;
            }
        };
        let (mark, t0) = mark;
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

    /// The point drawings' attributes from the hints (MOOS `onSetParamComplete`): the
    /// general hints first, then the next-point colour and sizes over them.
    fn apply_point_hints(&mut self, ctx: &Ctx<'_>) {
        let h = &self.hints;
        let set = |slot: &mut Option<String>, c: Option<&str>| {
            if let Some(p) = c.and_then(crate::color::pack) {
                *slot = Some(p);
            }
        };
        let t = &mut self.trackpt_attrs;
        t.label = format!("{}'s trackpt", ctx.ownship);
        h.apply(t, "trackpt", false, false);
        t.vertex_size = Some(4.0);
        set(&mut t.label_color, h.color("nextpt_color"));
        set(&mut t.vertex_color, h.color("nextpt_color"));
        let n = &mut self.nextpt_attrs;
        n.label = format!("{}'s nextpt", ctx.ownship);
        h.apply(n, "nextpt", false, false);
        n.vertex_size = Some(h.measure("nextpt_vertex_size"));
        set(&mut n.vertex_color, h.color("nextpt_color"));
        set(&mut n.label_color, h.color("nextpt_label_color"));
    }

    /// The VIEW_POINT of the next point (`trackpt == false`, drawn with `active=true`) or the
    /// track point; the erase form when `!active`.
    fn point_view(&mut self, ctx: &Ctx<'_>, active: bool, trackpt: bool) -> String {
        self.views.check_ctx(ctx);
        let (pt, attrs) = if trackpt {
            (self.trackpt, &self.trackpt_attrs)
        } else {
            (self.nextpt, &self.nextpt_attrs)
        };
        let slot = if trackpt {
            &mut self.views.trackpt
        } else {
            &mut self.views.nextpt
        };
        slot.get((active, pt), |s| {
            if !active {
                ViewPoint::erase_spec(&attrs.label, s);
                return;
            }
            let mut vp = ViewPoint::new(pt);
            if trackpt {
                vp.attrs = attrs.clone();
                vp.spec(s);
            } else {
                // `get_spec("active=true")`: the active state is written out.
                vp.spec(s);
                s.push_str(",active=true");
                let base = s.len();
                attrs.write_spec(s, base - 1);
            }
        })
    }

    /// The route drawing (MOOS `postViewableSegList`): with draw_path_loop a convex route is
    /// also drawn as a polygon; an edge colour `off` draws the erase form instead.
    fn post_seglist(&mut self, ctx: &Ctx<'_>, out: &mut Out) {
        self.views.check_ctx(ctx);
        let label = format!("{}_{}", ctx.ownship, ctx.name);
        if self.hints.color("edge_color") == Some("off") {
            let mut s = String::from("pts={0,0:9,0:0,9},active=false,label=");
            s.push_str(&label);
            out.post("VIEW_SEGLIST", s);
            return;
        }
        if self.draw_path_loop {
            let poly = Polygon::new(self.points.points().to_vec());
            if poly.is_convex() {
                let mut vp = ViewPolygon::new(poly);
                self.hints.apply(&mut vp.attrs, "", true, true);
                out.post("VIEW_POLYGON", vp.to_spec());
            }
        }
        let hints = &self.hints;
        let text = self.views.seglist.get(self.points.clone(), |s| {
            let mut v = ViewSegList::new(self.points.clone());
            v.precision = 3;
            v.attrs.label = label.clone();
            hints.apply(&mut v.attrs, "", true, false);
            v.spec(s);
        });
        out.post("VIEW_SEGLIST", text);
    }

    /// MOOS `postErasables`: both points and the route (its points, `active=false`).
    fn post_erasables(&mut self, ctx: &Ctx<'_>, out: &mut Out) {
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
        let mut v = ViewSegList::new(self.points.clone());
        v.attrs.label = format!("{}_{}", ctx.ownship, ctx.name);
        v.attrs.active = false;
        out.post("VIEW_SEGLIST", v.to_spec());
    }

    fn post_names(&mut self) -> &[String; 3] {
        let (r, i, c, s) = (
            &self.var_report,
            &self.var_index,
            &self.var_cyindex,
            &self.suffix,
        );
        self.views
            .names
            .get_or_insert_with(|| [r, i, c].map(|v| format!("{v}{s}")))
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
            crate::fmt::fixed(&mut stat, dist, 0);
            stat.push_str(",eta=");
            crate::fmt::fixed(&mut stat, eta, 0);
            let var = self.post_names()[0].clone();
            out.post(var, stat);
        }
        if self.var_index != "silent" && self.curr_ix as i64 != self.prev_waypt_index {
            let var = self.post_names()[1].clone();
            out.post(var, self.curr_ix as f64);
        }
    }

    /// The BHV_SETTINGS text (MOOS `postConfigStatus`).
    fn settings(&self, name: &str) -> String {
        let x1 = |v: f64| crate::fmt::compact_string(v, 1);
        let mut pts = String::new();
        geometry::spec::write_points(&mut pts, self.points.points(), 1);
        let mut s = format!("type=BHV_Waypoint,name={name},points={pts}");
        s.push_str(&format!(
            ",speed={},speed_alt={},currix={},greedy_tour={},use_alt_speed={}",
            x1(self.speed),
            x1(self.speed_alt),
            self.curr_ix,
            self.greedy_pending,
            self.use_alt_speed
        ));
        s.push_str(&format!(
            ",wpt_status={},wpt_dist_to_prev={},wpt_dist_to_next={},wpt_index={}",
            self.var_report, self.var_dist_prev, self.var_dist_next, self.var_index
        ));
        // The C++ writes post_suffix twice.
        s.push_str(&format!(
            ",cycle_index_var={},post_suffix={},post_suffix={},ipf_type={}",
            self.var_cyindex,
            self.suffix,
            self.suffix,
            self.ipf_type.name()
        ));
        s.push_str(&format!(
            ",lead={},lead_damper={},lead_to_start={},order={}",
            x1(self.lead),
            x1(self.lead_damper),
            self.lead_to_start,
            if self.reverse { "reverse" } else { "normal" }
        ));
        if self.endless {
            s.push_str(",repeats=forever");
        } else {
            s.push_str(&format!(",repeats={}", self.repeats));
        }
        s.push_str(&format!(
            ",efficiency_measure={},capture_radius={},slip_radius={}",
            if self.efficiency { "all" } else { "off" },
            x1(self.capture_radius),
            x1(self.slip_radius)
        ));
        if self.capture_line {
            if self.capture_radius == 0.0 && self.slip_radius == 0.0 {
                s.push_str(",capture_line=absolute");
            } else {
                s.push_str(",capture_line=true");
            }
        }
        s.push_str(",crs_spd_zaic_ratio=");
        compact(&mut s, self.patience, 2);
        s
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
                IpfType::Roc | IpfType::RateOfClosure => return None,
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
        let util = match self.ipf_type {
            IpfType::Zaic => "ZAIC_PEAK",
            IpfType::ZaicSpd => "ZAIC_SPD",
            IpfType::Roc | IpfType::RateOfClosure => {
                let pt = (self.trackpt.x, self.trackpt.y);
                return roc::objective(ctx.domain, (osx, osy), pt, speed);
            }
        };
        if self.speed_of(ctx, speed).is_none() {
            out.warning(
                ctx.name,
                &format!("Failure on the SPD ZAIC via {util} utility"),
            );
            return None;
        }
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

    fn set_points_param(
        &mut self,
        param: &str,
        value: &str,
        ctx: &Ctx<'_>,
    ) -> Result<(), ParamError> {
        let lower = value.to_ascii_lowercase();
        if lower == "empty" || lower == "start" {
            self.waypts_init = lower;
            return Ok(());
        }
        let (x, y) = (self.os.0, self.os.1);
        let (x, y) = nav(ctx.info).map_or((x, y), |n| (n.0, n.1));
        let parsed = parse_waypoints(value, x, y)
            .map_err(|_| ParamError::bad(param, value, "a point list or polygon"))?;
        if parsed.seglist.is_empty() {
            return Err(ParamError::bad(param, value, "at least one point"));
        }
        if param == "xpoints" && parsed.seglist.len() != self.points.len() {
            return Err(ParamError::bad(
                param,
                value,
                "as many points as the current route",
            ));
        }
        let (ix, prev_wpt, prev_cyc) = (self.curr_ix, self.prev_waypt_index, self.prev_cycle_index);
        self.set_seglist(parsed.seglist);
        self.markpt = None;
        self.prev_cycle_index = 0;
        self.prev_waypt_index = -1;
        self.prevpt_valid = false;
        if param == "xpoints" {
            self.set_curr_index(ix);
            self.prev_waypt_index = prev_wpt;
            self.prev_cycle_index = prev_cyc;
        }
        Ok(())
    }

    fn set_var_name(param: &str, value: &str, slot: &mut String) -> Result<(), ParamError> {
        if value.is_empty() || value.contains(char::is_whitespace) {
            return Err(ParamError::bad(param, value, "a variable name"));
        }
        *slot = if value.eq_ignore_ascii_case("silent") {
            "silent".into()
        } else {
            value.into()
        };
        Ok(())
    }

    /// MOOS `setEndSpeed`: `slow_dist=<pos>,stop_dist=<non-neg>`, both given, stop <= slow.
    fn set_end_speed(&mut self, value: &str) -> bool {
        let (mut slow, mut stop) = (-1.0, -1.0);
        for part in value.split(',').filter(|p| !p.is_empty()) {
            let (k, v) = part.split_once('=').unwrap_or((part, ""));
            let (k, v) = (k.trim(), v.trim());
            let ok = match k {
                "slow_dist" if is_number(v) && atof(v) > 0.0 => {
                    slow = atof(v);
                    true
                }
                "stop_dist" if is_number(v) && atof(v) >= 0.0 => {
                    stop = atof(v);
                    true
                }
                _ => false,
            };
            if !ok {
                return false;
            }
        }
        if slow < 0.0 || stop < 0.0 || stop > slow {
            return false;
        }
        self.slow_dist = slow;
        self.stop_dist = stop;
        true
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
        for c in &self.lead_conditions {
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
        let bad = |expected| Err(ParamError::bad(param, value, expected));
        match param {
            "points" | "polygon" | "xpoints" => self.set_points_param(param, v, ctx)?,
            "point" if v.eq_ignore_ascii_case("start") || v.eq_ignore_ascii_case("empty") => {
                self.waypts_init = v.to_ascii_lowercase();
            }
            "point" => {
                let p = parse_point(v).map_err(|_| ParamError::bad(param, value, "a point x,y"))?;
                self.set_seglist(SegList::from_points(vec![p.point]));
                self.markpt = None;
            }
            "newpt" => {
                let p = parse_point(v).map_err(|_| ParamError::bad(param, value, "a point x,y"))?;
                // MOOS `addWaypoint`: only in the normal order.
                if !self.reverse {
                    self.raw.push(p.point);
                    self.points.push(p.point);
                }
            }
            "speed" if is_number(v) && atof(v) >= 0.0 => {
                let max = ctx.domain.get("speed").map_or(f64::MAX, |d| d.high());
                let s = atof(v).min(max);
                if s != self.speed {
                    self.odo_disq = true;
                }
                self.speed = s;
            }
            "speed_alt" if is_number(v) && atof(v) >= 0.0 => {
                let s = atof(v);
                if s != self.speed_alt {
                    self.odo_disq = true;
                }
                self.speed_alt = s;
            }
            "currix" if atof(v) >= 0.0 => self.set_curr_index(atof(v) as usize),
            "greedy_tour" | "shortest_tour" => {
                // The C++ ignores a value that is not a boolean.
                self.greedy_pending =
                    moos_boolean(param, v, self.greedy_pending).unwrap_or(self.greedy_pending);
            }
            "draw_path_loop" => self.draw_path_loop = moos_boolean(param, v, self.draw_path_loop)?,
            "use_alt_speed" => {
                let prev = self.use_alt_speed;
                self.use_alt_speed = moos_boolean(param, v, prev).unwrap_or(prev);
                if prev != self.use_alt_speed {
                    self.odo_disq = true;
                }
            }
            "wpt_status" | "wpt_status_var" => Self::set_var_name(param, v, &mut self.var_report)?,
            "wpt_index" | "wpt_index_var" => Self::set_var_name(param, v, &mut self.var_index)?,
            "cycle_index_var" => Self::set_var_name(param, v, &mut self.var_cyindex)?,
            "wpt_dist_to_prev" | "wpt_dist_to_next" => {
                if v.contains(char::is_whitespace) {
                    return bad("a variable name");
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
                    return bad("a suffix without spaces");
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
            "ipf_type" | "ipf-type" => match v.to_ascii_lowercase().as_str() {
                "zaic" => self.ipf_type = IpfType::Zaic,
                "zaic_spd" => self.ipf_type = IpfType::ZaicSpd,
                "roc" => self.ipf_type = IpfType::Roc,
                "rate_of_closure" => self.ipf_type = IpfType::RateOfClosure,
                // The C++ accepts and ignores any other value.
                _ => {}
            },
            "lead" if is_number(v) => {
                let d = atof(v);
                self.lead = if d <= 0.0 { -1.0 } else { d };
            }
            "wptflag_on_start" => {
                self.wptflag_on_start = moos_boolean(param, v, self.wptflag_on_start)?;
            }
            "reset_on_idle" => self.reset_on_idle = moos_boolean(param, v, self.reset_on_idle)?,
            "eager_prev_index_flag" => {
                self.eager_prev_index = moos_boolean(param, v, self.eager_prev_index)?;
            }
            "lead_to_start" => self.lead_to_start = moos_boolean(param, v, self.lead_to_start)?,
            "lead_damper" if atof(v) > 0.0 => self.lead_damper = atof(v),
            "lead_condition" => {
                let c = mission::condition::parse_condition(&v.replace(',', "="))
                    .map_err(|_| ParamError::bad(param, value, "a logic condition"))?;
                self.lead_conditions.push(c);
            }
            "order" => match v {
                "toggle" => self.set_reverse(!self.reverse),
                "reverse" | "reversed" => self.set_reverse(true),
                "normal" => self.set_reverse(false),
                _ => return bad("normal, reverse or toggle"),
            },
            "repeat" if v.eq_ignore_ascii_case("forever") => {
                common.perpetual = true;
                self.endless = true;
            }
            "efficiency_measure" => {
                self.efficiency = match v.to_ascii_lowercase().as_str() {
                    "all" => true,
                    "off" => false,
                    _ => return bad("all or off"),
                }
            }
            "repeat" => {
                let r = atoi(v);
                if r < 0 || !is_number(v) {
                    return bad("a whole number or forever");
                }
                if r > 0 {
                    common.perpetual = true;
                }
                self.repeats = r as u32;
                self.endless = false;
            }
            "radius" | "capture_radius" => {
                if atof(v) <= 0.0 {
                    return bad("a positive radius");
                }
                self.capture_radius = atof(v);
            }
            "nm_radius" | "slip_radius" => {
                if atof(v) < 0.0 {
                    return bad("a radius >= 0");
                }
                self.slip_radius = atof(v);
            }
            "capture_line" => match v.to_ascii_lowercase().as_str() {
                "absolute" => {
                    self.capture_line = true;
                    self.capture_radius = 0.0;
                    self.slip_radius = 0.0;
                }
                "true" => self.capture_line = true,
                "false" => self.capture_line = false,
                _ => return bad("true, false or absolute"),
            },
            "crs_spd_zaic_ratio" | "patience" => {
                let d = atof(v);
                if !(1.0..=99.0).contains(&d) {
                    return bad("a number in [1, 99]");
                }
                self.patience = d;
            }
            "visual_hints" => {
                if !self.hints.set_hints(v) {
                    return bad("hints key=colour or key=size");
                }
            }
            "end_spd" => {
                if !self.set_end_speed(v) {
                    return bad("slow_dist=..,stop_dist=.. with 0 <= stop_dist <= slow_dist");
                }
            }
            "speed" | "speed_alt" => return bad("a number >= 0"),
            "currix" => return bad("an index >= 0"),
            "lead" => return bad("a number"),
            "lead_damper" => return bad("a positive distance"),
            _ => return Err(ParamError::unknown(param)),
        }
        Ok(())
    }

    fn on_set_param_complete(&mut self, ctx: &Ctx<'_>, out: &mut Out) {
        self.views = Views::default();
        self.apply_point_hints(ctx);
        if self.points.len() == 1 && self.repeats > 0 {
            out.warning(ctx.name, "cycles/repeats not supported with single waypt");
        }
        let no_pts = "No waypts given. Set val to empty if intentional";
        if self.points.is_empty() {
            if self.waypts_init != "empty" && self.waypts_init != "start" {
                out.warning(ctx.name, no_pts);
            }
        } else {
            // MOOS `postRetractWMessage`: a filtered posting under its own key.
            out.post_key(
                "BHV_WARNING",
                format!("{}: {no_pts}", ctx.name),
                PostKey::Tag("retract"),
            );
        }
        // (After an update the helm has posted the settings once already, from `checkUpdates`.)
        crate::behavior::post_config_status(&*self, ctx, out);
    }

    fn config_status(&self, name: &str) -> Option<String> {
        Some(self.settings(name))
    }

    fn on_idle(&mut self, ctx: &Ctx<'_>, out: &mut Out) {
        self.every_state(ctx);
        self.update_info_in(ctx, out);
    }

    fn on_idle_to_run(&mut self, ctx: &Ctx<'_>, out: &mut Out) {
        self.every_state(ctx);
        if self.update_info_in(ctx, out).is_none() {
            return;
        }
        self.odo_disq = true;
        self.odo_prev = None;
    }

    fn on_run_to_idle(&mut self, ctx: &Ctx<'_>, out: &mut Out) {
        self.post_erasables(ctx, out);
        if self.reset_on_idle {
            self.reset_for_new_traversal();
        }
        self.cpa = None;
        self.odo_mark = None;
        self.odo_disq = true;
        if !self.var_dist_prev.is_empty() {
            out.post(self.var_dist_prev.clone(), -1.0);
        }
        if !self.var_dist_next.is_empty() {
            out.post(self.var_dist_next.clone(), -1.0);
        }
    }

    fn on_complete(&mut self, ctx: &Ctx<'_>, out: &mut Out) {
        self.post_erasables(ctx, out);
    }

    fn on_run(&mut self, ctx: &Ctx<'_>, out: &mut Out) -> Option<IvpFunction> {
        self.every_state(ctx);
        if self.points.is_empty() {
            return None;
        }
        self.perpetual = ctx.perpetual;
        let Some(os) = self.update_info_in(ctx, out) else {
            // `get_spec("active=false")`: the next point as it is, marked inactive.
            let mut s = String::new();
            ViewPoint::new(self.nextpt).spec(&mut s);
            s.push_str(",active=false");
            let base = s.len() - 1;
            self.nextpt_attrs.write_spec(&mut s, base);
            out.post_key("VIEW_POINT", s, PostKey::Tag("wpt"));
            return None;
        };
        let here = Point::new(os.0, os.1);
        if let Some(p) = self.odo_prev {
            self.odo_leg += here.dist(&p);
        }
        self.odo_prev = Some(here);

        let this = self.point_at(self.curr_ix);
        let this_i = self.curr_ix as i64;
        if !self.prevpt_valid {
            self.prevpt = here;
            self.prevpt_valid = true;
        }
        let next_point = self.set_next_waypoint(ctx, out);
        let next = self.point_at(self.curr_ix);
        let post_flags = next.x != this.x
            || next.y != this.y
            || (self.wptflag_on_start && !self.wpt_flag_published)
            || self.waypt_hit;
        if post_flags {
            self.prevpt = this;
            self.prevpt_valid = true;
            if self.eager_prev_index {
                self.prev_waypt_index = this_i;
            }
            // Not repeatable: the helm's duplicate filter applies, as in the C++.
            for f in &self.wpt_flags {
                out.flag(&self.flag_now(f), false);
            }
            self.wpt_flag_published = true;
        }
        if self.var_cyindex != "silent" && self.cycles != self.prev_cycle_index {
            let var = self.post_names()[2].clone();
            out.post(var, f64::from(self.cycles));
            self.prev_cycle_index = self.cycles;
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
        if !self.eager_prev_index {
            self.prev_waypt_index = self.curr_ix as i64;
        }
        self.post_seglist(ctx, out);
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
        let (osx, osy) = (self.os.0, self.os.1);
        match name {
            "POINTS" => geometry::spec::write_points(out, self.points.points(), 1),
            "SPEED" => compact(out, self.speed, 3),
            "SPEED_ALT" => compact(out, self.speed_alt, 3),
            "USE_SPEED_ALT" => flag(out, self.use_alt_speed),
            "IPF_TYPE" => out.push_str(self.ipf_type.name()),
            "WPT_FLAG_ON_START" => flag(out, self.wptflag_on_start),
            "LEAD_TO_START" => flag(out, self.lead_to_start),
            "LEAD_DAMPER" => compact(out, self.lead_damper, 3),
            "ORDER" => out.push_str(if self.reverse { "reverse" } else { "normal" }),
            "PI" => compact(out, self.prev_waypt_index as f64, 0),
            "CYC_DIST_TOGO" => compact(out, self.dist_to_end_cycle(osx, osy), 3),
            "ALL_DIST_TOGO" => compact(out, self.dist_to_end_final(osx, osy), 3),
            "X" | "PX" => compact(out, self.prevpt.x, 3),
            "Y" | "PY" => compact(out, self.prevpt.y, 3),
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
        assert_eq!(posted(&out, "WPT_INDEX")[0].as_f64(), Some(0.0));
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
        assert_eq!(posted(&out, "WPT_INDEX_CUSTOM")[0].as_f64(), Some(1.0));
        assert_eq!(posted(&out, "CUSTOM_DIST_TO_NEXT")[0].as_f64(), Some(10.0));
        let mut out = Out::default();
        assert!(run_at(&mut w, &c, 10.0, 0.0, 1.0, &mut out).is_some());
        assert_eq!(posted(&out, "CYCLE_INDEX_CUSTOM")[0].as_f64(), Some(1.0));
        assert_eq!(posted(&out, "WPT_INDEX_CUSTOM")[0].as_f64(), Some(0.0));
        assert_eq!(posted(&out, "CUSTOM_DIST_TO_PREV")[0].as_f64(), Some(10.0));
        assert_eq!(posted(&out, "CUSTOM_DIST_TO_NEXT")[0].as_f64(), Some(10.0));
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
        assert!((posted(&out, "WPT_EFF_DIST_ALL")[0].as_f64().unwrap() - 1.0).abs() < 1e-6);
        assert!((posted(&out, "WPT_EFF_TIME_ALL")[0].as_f64().unwrap() - 5.0 / 6.0).abs() < 1e-3);
        let sum = posted(&out, "WPT_EFF_SUMM_ALL")[0].as_str().unwrap();
        assert_eq!(
            sum,
            "vname=abe, bhv_name=wpt, linear_dist=10, odo_dist=10, efficiency_dist=1, \
             linear_time=5, odo_time=6, efficiency_time=0.833"
        );
    }
}
