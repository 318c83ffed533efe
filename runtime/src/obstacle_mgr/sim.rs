//! `uFldObstacleSim`: the obstacles of an obstacle file, posted as ground truth
//! (`KNOWN_OBSTACLE`), as obstacles given to the vehicles (`GIVEN_OBSTACLE`) or, with
//! `post_points`, as the points a range sensor on each vehicle would see
//! (`TRACKED_FEATURE_<VNAME>`); drawn for pMarineViewer (`VIEW_POLYGON`, `VIEW_POINT`); given
//! random lifetimes (`min_duration`/`max_duration`); and regenerated at random in the file's
//! region once the vehicles have left it (`reset_interval`, `reset_range`) or on `UFOS_RESET`
//! (issue #18).
//!
//! [`ObstacleFile`] reads the obstacle file ([`ObstacleFile::parse`]: every problem located
//! as `file:line`); [`ObstacleSim`] is the pure core (mail and time in, posts out, one
//! seeded generator for every random draw); [`ObstacleSimApp`] hosts it
//! ([`crate::hosted::Hosted`]). Facts from MOOS-IvP's `uFldObstacleSim`, `lib_obstacles`'
//! `ObstacleFieldGenerator` and `GeomUtils`' `randPointOnPoly` at a2a9b716.
//!
//! # The obstacle file
//!
//! One `key = value` a line; blank lines and `//` comments skipped: `region = <convex
//! polygon>`, `min_range = <number >= 0>`, `min_size`, `max_size`, and `poly = <convex
//! polygon>` (any number, each with its `label`). A region or obstacle that is not a convex
//! polygon stops the reading there (the obstacles before it kept), as the C++ does; a bad
//! number is warned and the reading goes on; after the file, an unset `min_size`,
//! `max_size` or `min_range`, or `min_size` above `max_size`, is warned (these are what a
//! reset needs). Lines with another key are ignored by the C++ silently; coug warns about
//! them (lines opening with `#` are taken as comments, as MOOS-IvP's `gen_obstacles` writes
//! them in some files).
//!
//! # Conformance with uFldObstacleSim (MOOS-IvP a2a9b716)
//!
//! | parameter | default | validation (C++ rule) | coug |
//! |---|---|---|---|
//! | obstacle_file | none | read after every other line; a file that cannot be read, a bad region or obstacle, and the sanity checks above also warn `Unhandled config line` | done |
//! | poly_vert_color, poly_edge_color | gray50 | a colour | done |
//! | poly_fill_color | white | a colour | done |
//! | poly_label_color | invisible | a colour | done |
//! | poly_vert_size, poly_edge_size | 1 | number >= 0 | done |
//! | poly_transparency | 0.15 | number >= 0 | done |
//! | draw_region | true | boolean | done |
//! | region_edge_color, region_vert_color | gray50, white | a colour | done |
//! | post_points | false | boolean | done |
//! | rate_points | 5 | number >= 0 (points per obstacle in range, per iteration) | done |
//! | point_size | 2 | number >= 0 | done |
//! | sensor_range | 50 | number >= 0 | done |
//! | min_duration, max_duration | -1 (none) | a number; each raises or lowers the other to keep min <= max; a negative min with a max >= 0 becomes 0 | done |
//! | refresh_interval | -1 (off) | number >= 0 | done |
//! | reset_interval | -1 (off) | number >= 0 | done |
//! | reset_range | 10 | number >= 0 | done |
//! | reuse_ids | true | boolean | done |
//! | post_visuals | true | boolean | done |
//!
//! | variable | when | format | coug |
//! |---|---|---|---|
//! | PLOGGER_CMD | start-up, a readable obstacle file | `COPY_FILE_REQUEST = <file>` | done |
//! | UFOS_MIN_RNG | start-up (each `min_range` line), each regeneration | double | done |
//! | VIEW_POLYGON | refresh (`post_visuals`): each obstacle, then the region (`draw_region`, convex) | `pts={..2 dp..},label=..,label_color=..,edge_color=..,vertex_color=..,fill_color=..,vertex_size=..,edge_size=..,fill_transparency=..`; region with 1 dp, `label=obs_region` | done |
//! | KNOWN_OBSTACLE | refresh, each obstacle | `pts={..2 dp..},label=<key>[,vsource=..][,duration=..]` | done |
//! | GIVEN_OBSTACLE | refresh, each obstacle, unless `post_points` | as KNOWN_OBSTACLE | done |
//! | KNOWN_OBSTACLE_CLEAR | a pending regeneration | `all` | done |
//! | VIEW_POLYGON, KNOWN_OBSTACLE, GIVEN_OBSTACLE | a regeneration with `reuse_ids = false`: the old obstacles erased | `pts={0,0:9,0:0,9},active=false,label=<key>,duration=0` | done |
//! | TRACKED_FEATURE_<VNAME> | `post_points`: each iteration, `rate_points` points on each obstacle within `sensor_range` of the vehicle | `x=..,y=..,key=<key>[,vsource=..]` (2 dp) | done |
//! | VIEW_POINT | with each point (`post_visuals`) | `x=..,y=..,label=<vname>:<key>:<n % 100>,label_color=invisible[,vertex_color=<node colour>],duration=10,vertex_size=<point_size>` | done |
//!
//! Refreshes: on `PMV_CONNECT`, a vehicle's first `NODE_REPORT`, every `refresh_interval`
//! and after a regeneration. Mail: `UFOS_RESET` asks for a regeneration (done when the
//! vehicles are beyond `reset_range` of the region), `UFOS_POINT_SIZE` (a size >= 1,
//! `smaller`, `bigger`), `NODE_REPORT` (name, time and a position needed; an underwater
//! type needs a depth), anything else is a `Bad Mail` run warning. C++ quirks kept: the app
//! registers `VEHICLE_CONNECT` but handles `OBM_CONNECT`, so `VEHICLE_CONNECT` mail is a
//! `Bad Mail` warning; a regeneration that cannot place every obstacle is retried next
//! iteration (`KNOWN_OBSTACLE_CLEAR` again); a point count that is not whole rounds up.
//! Differences: the C++ reseeds its generator from the clock at each regeneration and draws
//! from the process's `rand()`; coug draws from the app's seeded generator, so a lockstep run
//! repeats. The C++ has no drift of obstacles at a2a9b716 (the issue's "drift" is not there).

use std::collections::BTreeMap;
use std::path::{Path, PathBuf};

use geometry::{Point, Polygon, ViewPolygon};
use mission::diagnostic::{Diagnostic, DiagnosticKind};
use mission::moos::ProcessConfig;
use moos_types::fmt::{compact_string, fixed};
use moos_types::text::{is_number, set_boolean_on_string};

use crate::app::{Mail, Post, Subscription};
use crate::appcasting::Note;
use crate::hosted::{AppCore, Hosted};

/// The program name.
pub const PROGRAM: &str = "uFldObstacleSim";

/// A problem at one line of an obstacle file.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct FileProblem {
    /// The file as named in the block.
    pub file: String,
    /// Its line (1-based; 0 for the checks made after the whole file).
    pub line: u32,
    /// What is wrong, in the C++'s words where it has any.
    pub message: String,
}

impl std::fmt::Display for FileProblem {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        if self.line == 0 {
            write!(f, "{}: {}", self.file, self.message)
        } else {
            write!(f, "{}:{}: {}", self.file, self.line, self.message)
        }
    }
}

/// An obstacle file as `handleConfigObstacleFile` reads it.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct ObstacleFile {
    /// `region`: where regenerated obstacles go (a convex polygon), if given.
    pub region: Option<ViewPolygon>,
    /// `min_range`: the least distance between regenerated obstacles (0: unset).
    pub min_range: f64,
    /// `min_size`: the least diameter of a regenerated obstacle (0: unset).
    pub min_size: f64,
    /// `max_size`: the greatest diameter (0: unset).
    pub max_size: f64,
    /// Each `min_range` line's value, in order (each is posted as `UFOS_MIN_RNG`).
    pub min_range_posts: Vec<f64>,
    /// The obstacles (`poly` lines), with their labels.
    pub obstacles: Vec<ViewPolygon>,
    /// Every problem, in file order.
    pub problems: Vec<FileProblem>,
    /// False when the C++ would report the `obstacle_file` line unhandled (a line that
    /// stopped the reading, or a failed check after it).
    pub ok: bool,
}

/// A convex polygon in any MOOS form (MOOS `string2Poly` then `is_convex`).
fn convex_poly(s: &str) -> Option<ViewPolygon> {
    geometry::spec::parse_polygon(s)
        .ok()
        .filter(|v| v.polygon.is_convex())
}

/// `setNonNegDoubleOnString`: a number >= 0.
fn non_neg(v: &str) -> Option<f64> {
    let d = geometry::atof(v);
    (is_number(v) && d >= 0.0).then_some(d)
}

impl ObstacleFile {
    /// Reads the text of obstacle file `file` (named in the problems).
    ///
    /// ```
    /// use runtime::obstacle_mgr::sim::ObstacleFile;
    /// let f = ObstacleFile::parse("ob.txt", "region = pts={0,0:0,-50:50,-50:50,0}\n\
    ///     min_range = 2\nmin_size = 4\nmax_size = 6\n\
    ///     poly = pts={10,-10:14,-10:14,-14:10,-14},label=ob_0\nmax_size = big\n");
    /// assert!(f.ok);
    /// assert_eq!(f.obstacles[0].attrs.label, "ob_0");
    /// assert_eq!(f.problems[0].to_string(), "ob.txt:6: Poorly specified max_size: big");
    /// ```
    pub fn parse(file: &str, text: &str) -> ObstacleFile {
        let mut f = ObstacleFile {
            ok: true,
            ..ObstacleFile::default()
        };
        let problem = |line: usize, message: String| FileProblem {
            file: file.to_string(),
            line: line as u32,
            message,
        };
        for (i, raw) in text.lines().enumerate() {
            let n = i + 1;
            let line = raw.trim();
            if line.is_empty() || line.starts_with("//") {
                continue;
            }
            let (left, right) = line.split_once('=').unwrap_or((line, ""));
            let (left, right) = (left.trim(), right.trim());
            match left {
                "region" => match convex_poly(right) {
                    Some(mut r) => {
                        r.attrs.label = "obs_region".into();
                        f.region = Some(r);
                    }
                    None => {
                        f.problems
                            .push(problem(n, format!("Poorly specified region: {right}")));
                        f.ok = false;
                        return f;
                    }
                },
                "min_range" | "min_size" | "max_size" => {
                    let slot = match left {
                        "min_range" => &mut f.min_range,
                        "min_size" => &mut f.min_size,
                        _ => &mut f.max_size,
                    };
                    match non_neg(right) {
                        Some(d) => *slot = d,
                        None => f
                            .problems
                            .push(problem(n, format!("Poorly specified {left}: {right}"))),
                    }
                    if left == "min_range" {
                        f.min_range_posts.push(f.min_range);
                    }
                }
                "poly" => match convex_poly(right) {
                    Some(p) => f.obstacles.push(p),
                    None => {
                        f.problems
                            .push(problem(n, format!("Poorly specified obstacle: {right}")));
                        f.ok = false;
                        return f;
                    }
                },
                _ if line.starts_with('#') => {}
                _ => f.problems.push(problem(
                    n,
                    format!(
                        "not an obstacle file line (ignored, as uFldObstacleSim ignores it): {line}"
                    ),
                )),
            }
        }
        let after = |m: &str| problem(0, m.to_string());
        if f.min_size == 0.0 {
            f.problems
                .push(after("Unset or non-positive min_poly_size"));
            f.ok = false;
        } else if f.max_size == 0.0 {
            f.problems.push(after("Unset max_poly_size"));
            f.ok = false;
        } else if f.min_range == 0.0 {
            f.problems.push(after("Unset or non-positive min_range"));
            f.ok = false;
        } else if f.min_size > f.max_size {
            f.min_size = f.max_size;
            f.problems
                .push(after("min_poly_size greater than max_poly_size"));
            f.ok = false;
        }
        f
    }
}

/// A colour as MOOS's `ColorPack` writes it back: `off`, `empty` and `invisible` are
/// `invisible`.
fn pack(c: &str) -> String {
    match c {
        "off" | "empty" | "invisible" => "invisible".into(),
        _ => c.to_string(),
    }
}

/// The distance from `(x, y)` to a polygon's edges (MOOS `XYPolygon::dist_to_poly`: 0 on an
/// edge, the distance to the nearest edge inside or out).
fn dist_to_poly(p: &Polygon, x: f64, y: f64) -> f64 {
    p.dist_to_boundary(x, y).unwrap_or(-1.0)
}

/// Whether two convex polygons touch: an edge of one crosses an edge of the other, or one
/// holds a vertex of the other (MOOS `XYPolygon::intersects`).
fn polys_intersect(a: &Polygon, b: &Polygon) -> bool {
    a.vertices().iter().any(|v| b.contains(v.x, v.y))
        || b.vertices().iter().any(|v| a.contains(v.x, v.y))
        || a.edges().any(|e| b.segment_intersects(&e))
}

/// The distance between two polygons (0 when they touch).
fn poly_poly_dist(a: &Polygon, b: &Polygon) -> f64 {
    if polys_intersect(a, b) {
        return 0.0;
    }
    let ab = a
        .vertices()
        .iter()
        .map(|v| dist_to_poly(b, v.x, v.y))
        .fold(f64::INFINITY, f64::min);
    b.vertices()
        .iter()
        .map(|v| dist_to_poly(a, v.x, v.y))
        .fold(ab, f64::min)
}

/// MOOS `randPointOnPoly`: a random point on the side of `poly` seen from `(vx, vy)`: a
/// whole-degree bearing drawn between the two bearings that bound the polygon, and the first
/// edge that bearing's ray meets. `None` from inside the polygon, for a polygon that is not
/// convex, or when the ray misses (a bearing grazing a vertex).
pub fn rand_point_on_poly(
    vx: f64,
    vy: f64,
    poly: &Polygon,
    rng: &mut fastrand::Rng,
) -> Option<Point> {
    if !poly.is_convex() || poly.contains(vx, vy) {
        return None;
    }
    let (bmin, bmax) = behaviors::obstacle::geom::bearing_min_max(vx, vy, poly)?;
    let choices = (geometry::angle::angle_diff(bmin, bmax) + 1.0) as u32;
    let bng = geometry::angle::angle_360(bmin + f64::from(rng.u32(0..choices.max(1))));
    let d = poly.ray_distance(vx, vy, bng)?;
    Some(geometry::angle::project_point(vx, vy, bng, d))
}

/// MOOS `ObstacleFieldGenerator`: `amount` obstacles of 8 vertices (on a 0.1 m grid) at
/// random in `region`, each a circle's diameter between `min_size` and `max_size`, wholly
/// inside the region, at least `min_range` from the others; labels `ob_<begin + i>`. Each
/// obstacle gets `tries + 1` attempts; `None` when one finds no place.
pub fn generate_field(
    region: &Polygon,
    amount: usize,
    (min_range, min_size, max_size): (f64, f64, f64),
    begin: u32,
    tries: u32,
    rng: &mut fastrand::Rng,
) -> Option<Vec<ViewPolygon>> {
    if !region.is_convex() {
        return None;
    }
    let v = region.vertices();
    let (minx, maxx) = v
        .iter()
        .fold((f64::INFINITY, f64::NEG_INFINITY), |(a, b), p| {
            (a.min(p.x), b.max(p.x))
        });
    let (miny, maxy) = v
        .iter()
        .fold((f64::INFINITY, f64::NEG_INFINITY), |(a, b), p| {
            (a.min(p.y), b.max(p.y))
        });
    let mut made: Vec<ViewPolygon> = Vec::new();
    'each: for _ in 0..amount {
        let mut diameter = min_size;
        if max_size > min_size {
            diameter += (max_size - min_size) * f64::from(rng.u32(0..1000)) / 1000.0;
        }
        for _ in 0..=tries {
            let x = minx + f64::from(rng.u32(0..10000)) / 10000.0 * (maxx - minx);
            let y = miny + f64::from(rng.u32(0..10000)) / 10000.0 * (maxy - miny);
            if !region.contains(x, y) || made.iter().any(|o| o.polygon.contains(x, y)) {
                continue;
            }
            // The C++ writes the centre with 1 decimal and reads it back.
            let round1 = |t: f64| {
                geometry::atof(&{
                    let mut s = String::new();
                    fixed(&mut s, t, 1);
                    s
                })
            };
            let poly = geometry::pattern::Radial {
                x: round1(x),
                y: round1(y),
                z: 0.0,
                radius: diameter / 2.0,
                pts: 8,
                snap: 0.1,
            }
            .polygon()
            .ok()
            .filter(Polygon::is_convex)?;
            if !poly.vertices().iter().all(|p| region.contains(p.x, p.y))
                || made.iter().any(|o| polys_intersect(&o.polygon, &poly))
                || made
                    .iter()
                    .any(|o| poly_poly_dist(&o.polygon, &poly) < min_range)
            {
                continue;
            }
            let mut v = ViewPolygon::new(poly);
            v.attrs.label = format!("ob_{}", begin as usize + made.len());
            made.push(v);
            continue 'each;
        }
        return None;
    }
    Some(made)
}

/// One vehicle as its node reports give it.
#[derive(Debug, Clone, Default)]
struct Vehicle {
    x: f64,
    y: f64,
    color: String,
    reports: u32,
}

/// The settings of a block.
#[derive(Debug, Clone)]
struct Settings {
    poly_fill_color: String,
    poly_edge_color: String,
    poly_vert_color: String,
    poly_label_color: String,
    poly_edge_size: f64,
    poly_vert_size: f64,
    poly_transparency: f64,
    draw_region: bool,
    region_edge_color: String,
    region_vert_color: String,
    post_points: bool,
    rate_points: f64,
    point_size: f64,
    min_duration: f64,
    max_duration: f64,
    refresh_interval: f64,
    reset_interval: f64,
    reset_range: f64,
    reuse_ids: bool,
    sensor_range: f64,
    post_visuals: bool,
}

impl Default for Settings {
    fn default() -> Self {
        Settings {
            poly_fill_color: "white".into(),
            poly_edge_color: "gray50".into(),
            poly_vert_color: "gray50".into(),
            poly_label_color: "invisible".into(),
            poly_edge_size: 1.0,
            poly_vert_size: 1.0,
            poly_transparency: 0.15,
            draw_region: true,
            region_edge_color: "gray50".into(),
            region_vert_color: "white".into(),
            post_points: false,
            rate_points: 5.0,
            point_size: 2.0,
            min_duration: -1.0,
            max_duration: -1.0,
            refresh_interval: -1.0,
            reset_interval: -1.0,
            reset_range: 10.0,
            reuse_ids: true,
            sensor_range: 50.0,
            post_visuals: true,
        }
    }
}

/// The pure core of uFldObstacleSim.
///
/// ```
/// use runtime::obstacle_mgr::sim::ObstacleSim;
/// use runtime::app::Value;
/// let file = "min_range = 2\nmin_size = 4\nmax_size = 6\n\
///             poly = pts={10,-10:14,-10:14,-14:10,-14},label=ob_0\n";
/// let (mut sim, problems) = ObstacleSim::new(&[], Some(("ob.txt", file)), 1);
/// assert!(problems.is_empty(), "{problems:?}");
/// let mut out = Vec::new();
/// sim.on_startup(0.0, &mut out);
/// sim.on_mail("PMV_CONNECT", &Value::text("true"), 1.0, &mut out);
/// sim.iterate(1.0, &mut out);
/// let given = out.iter().find(|p| p.key == "GIVEN_OBSTACLE").unwrap();
/// assert_eq!(given.value.as_str(), Some("pts={10,-10:14,-10:14,-14:10,-14},label=ob_0"));
/// ```
#[derive(Debug, Clone)]
pub struct ObstacleSim {
    s: Settings,
    file_name: String,
    region: Option<ViewPolygon>,
    min_range: f64,
    min_size: f64,
    max_size: f64,
    obstacles: Vec<ViewPolygon>,
    durations: Vec<f64>,
    rng: fastrand::Rng,
    startup_posts: Vec<Post>,
    vehicles: BTreeMap<String, Vehicle>,
    grid: Option<vehicle::geodesy::LocalGrid>,
    pts_published: BTreeMap<String, u32>,
    giv_published: BTreeMap<String, u32>,
    reset_tstamp: f64,
    reset_request: bool,
    reset_pending: bool,
    newly_exited: bool,
    region_entered: bool,
    reset_total: u32,
    min_vrange_to_region: f64,
    refresh_needed: bool,
    refresh_tstamp: f64,
    obstacles_made: u32,
    obstacles_posted: u32,
    notes: Vec<Note>,
}

impl ObstacleSim {
    /// A simulator from the block's `param = value` lines (in file order) and its obstacle
    /// file (name and text, when the block names one that could be read), seeded with
    /// `seed`; with the warnings the C++ app reports for them.
    pub fn new(
        lines: &[&str],
        file: Option<(&str, &str)>,
        seed: u64,
    ) -> (ObstacleSim, Vec<String>) {
        let mut sim = ObstacleSim::empty(seed);
        let mut warnings = Vec::new();
        for line in lines {
            let (p, v) = super::config_text(line);
            if let Err(w) = sim.configure(&p, &v) {
                warnings.push(w);
            }
        }
        if let Some((name, text)) = file {
            warnings.extend(sim.load_file(name, Some(text)));
        }
        sim.finish_config();
        (sim, warnings)
    }

    fn empty(seed: u64) -> ObstacleSim {
        ObstacleSim {
            s: Settings::default(),
            file_name: String::new(),
            region: None,
            min_range: 0.0,
            min_size: 0.0,
            max_size: 0.0,
            obstacles: Vec::new(),
            durations: Vec::new(),
            rng: fastrand::Rng::with_seed(seed),
            startup_posts: Vec::new(),
            vehicles: BTreeMap::new(),
            grid: None,
            pts_published: BTreeMap::new(),
            giv_published: BTreeMap::new(),
            reset_tstamp: 0.0,
            reset_request: false,
            reset_pending: false,
            newly_exited: false,
            region_entered: false,
            reset_total: 0,
            min_vrange_to_region: -1.0,
            refresh_needed: false,
            refresh_tstamp: -1.0,
            obstacles_made: 0,
            obstacles_posted: 0,
            notes: Vec::new(),
        }
    }

    /// One configuration line (pass 1: everything but `obstacle_file`); `Err(warning)` as
    /// the C++ reports it.
    fn configure(&mut self, param: &str, value: &str) -> Result<(), String> {
        let s = &mut self.s;
        let color = |slot: &mut String| {
            let ok = geometry::color::is_color(value);
            if ok {
                *slot = value.to_string();
            }
            ok
        };
        let nn = |slot: &mut f64| non_neg(value).map(|d| *slot = d).is_some();
        let boolean = |slot: &mut bool| {
            set_boolean_on_string(*slot, value)
                .map(|b| *slot = b)
                .is_some()
        };
        let ok = match param {
            "obstacle_file" => true,
            "poly_vert_color" => color(&mut s.poly_vert_color),
            "poly_fill_color" => color(&mut s.poly_fill_color),
            "poly_edge_color" => color(&mut s.poly_edge_color),
            "poly_label_color" => color(&mut s.poly_label_color),
            "poly_vert_size" => nn(&mut s.poly_vert_size),
            "poly_edge_size" => nn(&mut s.poly_edge_size),
            "poly_transparency" => nn(&mut s.poly_transparency),
            "draw_region" => boolean(&mut s.draw_region),
            "region_edge_color" => color(&mut s.region_edge_color),
            "region_vert_color" => color(&mut s.region_vert_color),
            "post_points" => boolean(&mut s.post_points),
            "rate_points" => nn(&mut s.rate_points),
            "point_size" => nn(&mut s.point_size),
            "sensor_range" => nn(&mut s.sensor_range),
            "min_duration" => {
                let ok = is_number(value);
                if ok {
                    s.min_duration = geometry::atof(value);
                    if s.min_duration > s.max_duration {
                        s.max_duration = s.min_duration;
                    }
                }
                ok
            }
            "max_duration" => {
                let ok = is_number(value);
                if ok {
                    s.max_duration = geometry::atof(value);
                    if s.max_duration < s.min_duration {
                        s.min_duration = s.max_duration;
                    }
                    if s.min_duration < 0.0 && s.max_duration >= 0.0 {
                        s.min_duration = 0.0;
                    }
                }
                ok
            }
            "refresh_interval" => nn(&mut s.refresh_interval),
            "reset_interval" => nn(&mut s.reset_interval),
            "reset_range" => nn(&mut s.reset_range),
            "reuse_ids" => boolean(&mut s.reuse_ids),
            "post_visuals" => boolean(&mut s.post_visuals),
            _ if appcast::casting::UNHANDLED_EXEMPT
                .contains(&param.to_ascii_uppercase().as_str())
                || matches!(param, "comms_policy" | "max_appcast_run_warnings") =>
            {
                true
            }
            _ => false,
        };
        if ok {
            Ok(())
        } else {
            Err(format!("Unhandled config line: {param}={value}"))
        }
    }

    /// Pass 2: the obstacle file named `name` with its text (`None`: it could not be read),
    /// read with the colours and sizes of pass 1; the warnings it gives.
    fn load_file(&mut self, name: &str, text: Option<&str>) -> Vec<String> {
        let unhandled = format!("Unhandled config line: obstacle_file={name}");
        let Some(text) = text.filter(|t| !t.is_empty()) else {
            return vec![format!("Error reading: {name}"), unhandled];
        };
        self.file_name = name.to_string();
        self.startup_posts.push(Post::text(
            "PLOGGER_CMD",
            format!("COPY_FILE_REQUEST = {name}"),
        ));
        let f = ObstacleFile::parse(name, text);
        for r in &f.min_range_posts {
            self.startup_posts.push(Post::double("UFOS_MIN_RNG", *r));
        }
        if let Some(mut r) = f.region {
            r.attrs.edge_color = Some(pack(&self.s.region_edge_color));
            r.attrs.vertex_color = Some(pack(&self.s.region_vert_color));
            self.region = Some(r);
        }
        (self.min_range, self.min_size, self.max_size) = (f.min_range, f.min_size, f.max_size);
        for mut p in f.obstacles {
            self.dress(&mut p);
            self.obstacles.push(p);
            self.durations.push(-1.0);
            self.obstacles_made += 1;
        }
        let mut w: Vec<String> = f.problems.iter().map(ToString::to_string).collect();
        if !f.ok {
            w.push(unhandled);
        }
        w
    }

    /// The simulator's colours and sizes on an obstacle.
    fn dress(&self, p: &mut ViewPolygon) {
        let s = &self.s;
        let a = &mut p.attrs;
        a.edge_color = Some(pack(&s.poly_edge_color));
        a.vertex_color = Some(pack(&s.poly_vert_color));
        a.fill_color = Some(pack(&s.poly_fill_color));
        a.label_color = Some(pack(&s.poly_label_color));
        a.vertex_size = Some(s.poly_vert_size);
        a.edge_size = Some(s.poly_edge_size);
        a.fill_transparency = Some(s.poly_transparency.clamp(0.0, 1.0));
    }

    /// The obstacles' random lifetimes (MOOS `handleConfigObstacleDurations`).
    fn finish_config(&mut self) {
        if self.s.max_duration <= 0.0 {
            return;
        }
        let lo = self.s.min_duration.max(0.0);
        let hi = self.s.max_duration;
        for d in &mut self.durations {
            *d = if lo >= hi {
                lo
            } else {
                lo + f64::from(self.rng.u32(0..10001)) / 10000.0 * (hi - lo)
            };
        }
    }

    /// Sets the local grid node reports with only `LAT`/`LON` are placed on.
    pub fn set_grid(&mut self, grid: Option<vehicle::geodesy::LocalGrid>) {
        self.grid = grid;
    }

    /// The obstacles (their polygons, labels and display attributes).
    pub fn obstacles(&self) -> &[ViewPolygon] {
        &self.obstacles
    }

    /// The obstacles' lifetimes (-1: none).
    pub fn durations(&self) -> &[f64] {
        &self.durations
    }

    /// The variables the app registers for (besides the appcast's).
    pub fn subscriptions(&self) -> Vec<String> {
        [
            "PMV_CONNECT",
            "VEHICLE_CONNECT",
            "UFOS_RESET",
            "UFOS_POINT_SIZE",
            "NODE_REPORT",
        ]
        .map(String::from)
        .to_vec()
    }

    /// At start-up: what reading the file posts, and the reset clock started.
    pub fn on_startup(&mut self, now: f64, out: &mut Vec<Post>) {
        out.append(&mut self.startup_posts);
        self.reset_tstamp = now;
    }

    /// One mail (MOOS `OnNewMail`).
    pub fn on_mail(
        &mut self,
        key: &str,
        value: &crate::app::Value,
        _now: f64,
        _out: &mut Vec<Post>,
    ) {
        let sval = value.as_str().unwrap_or("");
        let mut whynot = String::new();
        let handled = match key {
            "PMV_CONNECT" | "OBM_CONNECT" => {
                self.refresh_needed = true;
                true
            }
            "UFOS_RESET" => {
                self.reset_request = true;
                true
            }
            "UFOS_POINT_SIZE" => self.point_size(sval),
            "NODE_REPORT" => self.node_report(sval, &mut whynot),
            _ => false,
        };
        if !handled {
            let mut w = format!("Bad Mail: {key}");
            if !whynot.is_empty() {
                w.push(' ');
                w.push_str(&whynot);
            }
            self.notes.push(Note::Warning(w));
        }
    }

    fn point_size(&mut self, s: &str) -> bool {
        let s = s.to_ascii_lowercase();
        let d = geometry::atof(&s);
        if d >= 1.0 {
            self.s.point_size = d;
        } else if s == "smaller" && self.s.point_size >= 2.0 {
            self.s.point_size -= 1.0;
        } else if s == "bigger" {
            self.s.point_size += 1.0;
        } else {
            return false;
        }
        true
    }

    /// MOOS `ContactLedger::processNodeReport` as far as the simulator reads it.
    fn node_report(&mut self, s: &str, whynot: &mut String) -> bool {
        let r = helm::ledger::NodeReport::parse(s);
        if r.name.is_empty() {
            whynot.push_str("Missing vname.");
        }
        if r.time.is_none() {
            whynot.push_str("Missing timestamp.");
        }
        let latlon = r.lat_deg.zip(r.lon_deg);
        let xy = match (r.x_m.zip(r.y_m), latlon, &self.grid) {
            (Some(xy), _, _) => Some(xy),
            (None, Some((lat, lon)), Some(g)) => g.to_local(lat, lon).ok(),
            (None, Some(_), None) => Some((0.0, 0.0)),
            _ => None,
        };
        if xy.is_none() {
            whynot.push_str("Missing both x/y and lat/lon.");
        }
        if !whynot.is_empty() {
            return false;
        }
        let vtype = r.vtype.to_ascii_lowercase();
        if matches!(vtype.as_str(), "uuv" | "auv" | "glider") && r.depth_m.is_none() {
            whynot.push_str("underwater vehicle type with no depth reported");
            return false;
        }
        let (x, y) = xy.unwrap_or_default();
        let v = self.vehicles.entry(r.name.clone()).or_default();
        (v.x, v.y, v.color) = (x, y, r.color.clone());
        v.reports += 1;
        if v.reports == 1 {
            self.refresh_needed = true;
        }
        true
    }

    /// One iteration (MOOS `Iterate`).
    pub fn iterate(&mut self, now: f64, out: &mut Vec<Post>) {
        self.update_vranges(now);
        self.update_field(out);
        if self.s.refresh_interval > 0.0 && now - self.refresh_tstamp > self.s.refresh_interval {
            self.refresh_needed = true;
        }
        if self.s.post_points {
            self.post_points(out);
        }
        if self.refresh_needed {
            self.post_refresh(now, out);
        }
    }

    fn update_vranges(&mut self, now: f64) {
        let mut min_vrange = -1.0;
        if let Some(region) = self.region.as_ref().map(|r| &r.polygon) {
            for v in self.vehicles.values() {
                if region.contains(v.x, v.y) {
                    self.region_entered = true;
                    min_vrange = 0.0;
                } else {
                    let range = dist_to_poly(region, v.x, v.y);
                    if min_vrange < 0.0 || range < min_vrange {
                        min_vrange = range;
                    }
                }
            }
        }
        if self.min_vrange_to_region <= 0.0 && min_vrange > 0.0 {
            self.newly_exited = true;
        }
        if min_vrange <= 0.0 || !self.region_entered {
            self.newly_exited = false;
        }
        self.min_vrange_to_region = min_vrange;
        if (self.s.reset_interval > 0.0 || self.reset_request)
            && self.min_vrange_to_region > self.s.reset_range
            && (self.newly_exited || self.reset_request)
            && (now - self.reset_tstamp > self.s.reset_interval || self.reset_request)
        {
            self.reset_pending = true;
            self.reset_request = false;
            self.reset_tstamp = now;
            self.newly_exited = false;
        }
    }

    /// A pending regeneration (MOOS `updateObstaclesField`).
    fn update_field(&mut self, out: &mut Vec<Post>) {
        if !self.reset_pending {
            return;
        }
        out.push(Post::text("KNOWN_OBSTACLE_CLEAR", "all"));
        let region = self
            .region
            .as_ref()
            .map(|r| r.polygon.clone())
            .unwrap_or_default();
        let begin = if self.s.reuse_ids {
            0
        } else {
            self.obstacles_made
        };
        let made = generate_field(
            &region,
            self.obstacles.len(),
            (self.min_range, self.min_size, self.max_size),
            begin,
            25000,
            &mut self.rng,
        );
        out.push(Post::double("UFOS_MIN_RNG", self.min_range));
        let Some(mut made) = made.filter(|m| m.len() == self.obstacles.len()) else {
            return;
        };
        if !self.s.reuse_ids {
            self.post_erase(out);
        }
        for p in &mut made {
            self.dress(p);
        }
        self.obstacles_made += made.len() as u32;
        self.obstacles = made;
        self.reset_total += 1;
        self.refresh_needed = true;
        self.reset_pending = false;
    }

    /// Every obstacle posted (MOOS `postObstaclesRefresh`).
    fn post_refresh(&mut self, now: f64, out: &mut Vec<Post>) {
        if self.s.post_visuals {
            for o in &self.obstacles {
                let mut v = o.clone();
                v.precision = 2;
                out.push(Post::text("VIEW_POLYGON", v.to_spec()));
            }
            if let Some(r) = self.region.as_ref().filter(|r| r.polygon.is_convex())
                && self.s.draw_region
            {
                let mut v = r.clone();
                v.precision = 1;
                out.push(Post::text("VIEW_POLYGON", v.to_spec()));
            }
        }
        for (o, d) in self.obstacles.iter().zip(&self.durations) {
            let mut spec = String::new();
            geometry::spec::write_points(&mut spec, o.polygon.vertices(), 2);
            let key = &o.attrs.label;
            if !key.is_empty() {
                spec.push_str(",label=");
                spec.push_str(key);
            }
            if !o.attrs.vsource.is_empty() {
                spec.push_str(",vsource=");
                spec.push_str(&o.attrs.vsource);
            }
            if *d >= 0.0 {
                spec.push_str(",duration=");
                spec.push_str(&compact_string(*d, 5));
            }
            out.push(Post::text("KNOWN_OBSTACLE", spec.as_str()));
            if !self.s.post_points {
                out.push(Post::text("GIVEN_OBSTACLE", spec));
                *self.giv_published.entry(key.clone()).or_default() += 1;
            }
        }
        self.refresh_needed = false;
        self.refresh_tstamp = now;
        self.obstacles_posted += 1;
    }

    /// The obstacles erased (MOOS `postObstaclesErase`).
    fn post_erase(&self, out: &mut Vec<Post>) {
        for o in &self.obstacles {
            let mut spec = behaviors::obstacle::spec_inactive(&o.attrs.label);
            spec.push_str(",duration=0");
            if self.s.post_visuals {
                out.push(Post::text("VIEW_POLYGON", spec.as_str()));
            }
            out.push(Post::text("KNOWN_OBSTACLE", spec.as_str()));
            if !self.s.post_points {
                out.push(Post::text("GIVEN_OBSTACLE", spec));
            }
        }
    }

    /// The sensed points (MOOS `postPoints`).
    fn post_points(&mut self, out: &mut Vec<Post>) {
        // `j < rate_points` with `j` counting from 0: a fraction rounds up.
        let per = self.s.rate_points.ceil().max(0.0) as u32;
        for (vname, v) in &self.vehicles {
            let var = format!("TRACKED_FEATURE_{}", vname.to_ascii_uppercase());
            for o in &self.obstacles {
                if dist_to_poly(&o.polygon, v.x, v.y) > self.s.sensor_range {
                    continue;
                }
                for _ in 0..per {
                    let Some(p) = rand_point_on_poly(v.x, v.y, &o.polygon, &mut self.rng) else {
                        continue;
                    };
                    let key = &o.attrs.label;
                    let mut msg = format!(
                        "x={},y={},key={key}",
                        compact_string(p.x, 2),
                        compact_string(p.y, 2)
                    );
                    if !o.attrs.vsource.is_empty() {
                        msg.push_str(",vsource=");
                        msg.push_str(&o.attrs.vsource);
                    }
                    out.push(Post::text(&var, msg));
                    let n = self.pts_published.entry(key.clone()).or_default();
                    *n += 1;
                    if self.s.post_visuals {
                        let mut vp = geometry::ViewPoint::new(p);
                        vp.attrs.label = format!("{vname}:{key}:{}", *n % 100);
                        if !v.color.is_empty() && geometry::color::is_color(&v.color) {
                            vp.attrs.vertex_color = Some(pack(&v.color));
                        }
                        vp.attrs.vertex_size = Some(self.s.point_size);
                        vp.attrs.label_color = Some("invisible".into());
                        vp.attrs.duration = Some(10.0);
                        out.push(Post::text("VIEW_POINT", vp.to_spec()));
                    }
                }
            }
        }
    }

    /// Takes the appcast events and warnings gathered since the last call.
    pub fn take_notes(&mut self) -> Vec<Note> {
        std::mem::take(&mut self.notes)
    }

    /// The appcast body (MOOS `buildReport`).
    pub fn report(&self, b: &mut String) {
        use std::fmt::Write as _;
        let s = &self.s;
        let x = |v: f64| compact_string(v, 5);
        let f = |v: f64, p: usize| {
            let mut t = String::new();
            fixed(&mut t, v, p);
            t
        };
        let dur = |v: f64| if v > 0.0 { f(v, 1) } else { "n/a".into() };
        let refresh = if s.refresh_interval > 0.0 {
            compact_string(s.refresh_interval, 1)
        } else {
            "n/a".into()
        };
        let _ = writeln!(b, "================================");
        let _ = writeln!(b, "Config (Obstacles) ");
        let _ = writeln!(b, "  Obstacles: {}", self.obstacles.len());
        let _ = writeln!(b, "  MinRange:  {}", x(self.min_range));
        let _ = writeln!(b, "  MinSize:   {}", x(self.min_size));
        let _ = writeln!(b, "  MaxSize:   {}", x(self.max_size));
        let _ = writeln!(b, "  ReuseIDs:  {}", s.reuse_ids);
        let _ = writeln!(b, "Config (Points)  ");
        let _ = writeln!(b, "  Post Points:   {}", s.post_points);
        let _ = writeln!(b, "  Rate Points:   {}", x(s.rate_points));
        let _ = writeln!(b, "Config (Duration)");
        let _ = writeln!(b, "  Min Duration:  {}", dur(s.min_duration));
        let _ = writeln!(b, "  Max Duration:  {}", dur(s.max_duration));
        let _ = writeln!(b, "  Refresh Intrv: {refresh}");
        let _ = writeln!(b, "Config (Reset)   ");
        let _ = writeln!(b, "  Reset Range:   {}", f(s.reset_range, 0));
        let _ = writeln!(b, "  Reset_Interv:  {}", f(s.reset_interval, 0));
        let _ = writeln!(b, "================================");
        let _ = writeln!(b, "State (Obstacles)               ");
        let _ = writeln!(b, "  Obstacles Posted: {}", self.obstacles_posted);
        let _ = writeln!(b, "State (resetting)   ");
        let _ = writeln!(b, "  Min Poly Range: {}", f(self.min_vrange_to_region, 0));
        let _ = writeln!(b, "  Reset Pending:  {}", self.reset_pending);
        let _ = writeln!(b, "  Newly Exited :  {}", self.newly_exited);
        let _ = writeln!(b, "  Reset Tstamp :  {}", f(self.reset_tstamp, 0));
        let _ = writeln!(b, "  Reset Total  :  {}", self.reset_total);
        let _ = writeln!(b, "\n");
        let mut t = appcast::Table::new(4);
        t.push("Obs | Obs      | Points     | Given ");
        t.push("Key | Duration | Published  | Published");
        t.add_header_lines();
        for (o, d) in self.obstacles.iter().zip(&self.durations) {
            let key = &o.attrs.label;
            t.push(key);
            t.push(&f(*d, 1));
            t.push(
                &self
                    .pts_published
                    .get(key)
                    .copied()
                    .unwrap_or(0)
                    .to_string(),
            );
            t.push(
                &self
                    .giv_published
                    .get(key)
                    .copied()
                    .unwrap_or(0)
                    .to_string(),
            );
        }
        t.write(b);
        let _ = writeln!(b, "\n");
    }
}

/// The `uFldObstacleSim` app: the core hosted with its name, block, warnings and appcast.
pub type ObstacleSimApp = Hosted<ObstacleSim>;

impl Hosted<ObstacleSim> {
    /// The app `name` from its block; `dir` is where a relative `obstacle_file` is found
    /// (the mission's folder), `seed` seeds its draws, `grid` places `LAT`/`LON` reports.
    /// Each problem is a configuration warning at its block line (the obstacle file's
    /// problems at the `obstacle_file` line, each naming its file and line; a mission
    /// without a usable `LatOrigin`/`LongOrigin` at the block, as the C++ warns).
    pub fn new(
        name: &str,
        block: ProcessConfig,
        dir: &Path,
        seed: u64,
        grid: Option<vehicle::geodesy::LocalGrid>,
    ) -> Self {
        let mut core = ObstacleSim::empty(seed);
        let mut warnings = Vec::new();
        let mut warn = |span: &mission::source::Span, m: &str| {
            warnings.push(Diagnostic::line_warning(
                DiagnosticKind::AppSetting,
                span,
                format!("{PROGRAM}: {m}"),
            ));
        };
        for p in &block.entries {
            let (k, v) = super::config_line(&p.key, &p.value);
            if let Err(m) = core.configure(&k, &v) {
                warn(&p.span, &m);
            }
        }
        // Pass 2: the obstacle files, with every colour and size already set.
        for p in &block.entries {
            let (k, file) = super::config_line(&p.key, &p.value);
            if k != "obstacle_file" {
                continue;
            }
            let path: PathBuf = if Path::new(&file).is_absolute() {
                PathBuf::from(&file)
            } else {
                dir.join(&file)
            };
            let text = std::fs::read_to_string(&path).ok();
            for m in core.load_file(&file, text.as_deref()) {
                warn(&p.span, &m);
            }
        }
        if grid.is_none() {
            warn(&block.span, "Lat or Lon Origin not set in *.moos file.");
        }
        core.finish_config();
        core.set_grid(grid);
        Hosted::host(name, block, warnings, core)
    }
}

impl AppCore for ObstacleSim {
    fn subscriptions(&self) -> Vec<Subscription> {
        ObstacleSim::subscriptions(self)
            .into_iter()
            .map(Subscription::var)
            .collect()
    }

    fn on_startup(&mut self, now: f64, out: &mut Vec<Post>, notes: &mut Vec<Note>) {
        ObstacleSim::on_startup(self, now, out);
        notes.append(&mut self.notes);
    }

    fn on_mail(&mut self, m: &Mail, now: f64, out: &mut Vec<Post>, notes: &mut Vec<Note>) {
        ObstacleSim::on_mail(self, &m.key, &m.value, now, out);
        notes.append(&mut self.notes);
    }

    fn iterate(&mut self, now: f64, out: &mut Vec<Post>, notes: &mut Vec<Note>) {
        ObstacleSim::iterate(self, now, out);
        notes.append(&mut self.notes);
    }

    fn report(&self, _now: f64, body: &mut String) {
        ObstacleSim::report(self, body);
    }
}

#[cfg(test)]
mod tests;
