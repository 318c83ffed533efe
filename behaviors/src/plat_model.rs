//! The helm's platform model: where ownship goes when it turns to a new heading (MOOS-IvP
//! `lib_geometry/PlatModel`, `DubinsTurn` and `lib_helmivp/PMGen_Holonomic`,
//! `PMGen_Dubins` at a2a9b716; facts only, coug's own code).
//!
//! pHelmIvP builds one [`PlatModel`] each decision iteration from ownship's `NAV_X`,
//! `NAV_Y`, `NAV_HEADING` and `NAV_SPEED` and its `pmgen` settings (the helm crate's
//! `plat_model` module), and hands it to every behaviour ([`crate::Info::plat_model`]).
//!
//! - **Holonomic** (the default, `alg=holo`): ownship turns on the spot; the path to any
//!   heading is a ray from its position.
//! - **Dubins** (`alg=dubins`, `radius` 30 m, `spoke_degs` 10° by default): ownship turns on a
//!   circle of the turn radius whose centre is abeam on the turn's side. The model keeps the
//!   points ("spokes") on each circle every `spoke_degs` of turn, from ownship's position
//!   (spoke 0) to less than half a circle: starboard spoke `k` lies on the starboard circle at
//!   bearing `(h − 90) + k·spoke_degs` from its centre, port spoke `k` on the port circle at
//!   `(h + 90) − k·spoke_degs`. The path to heading `hdg` ([`PlatModel::turn`], MOOS
//!   `getTurnSeglr`) is the spokes `0..=n` on the turn's side, `n` the turn angle in spokes
//!   rounded to the nearest (at most the last spoke), followed by a ray along `hdg`.
//!
//! [`DubinsTurn`] is the exact arc of one turn (MOOS `DubinsTurn`): centre, the arc's
//! angles, where the ray starts, the arc's length and so the time a turn takes at a speed.
//! MOOS's `DubinsCache` (these turns for 360 headings) serves only BHV_AvoidWalls, which coug
//! does not have.

use geometry::{Point, angle_360, relative_angle};

/// The value of pi MOOS's `DubinsTurn` uses for its circumference (`MPI`, 12 digits).
#[allow(clippy::approx_constant)]
const MOOS_PI: f64 = 3.14159265359;

/// MOOS `degToRadians`.
fn rad(deg: f64) -> f64 {
    (deg / 180.0) * std::f64::consts::PI
}

/// MOOS `projectPoint`: `dist` metres from `(x, y)` along `heading`, exact at the four
/// cardinal headings.
pub fn project(heading: f64, dist: f64, x: f64, y: f64) -> Point {
    let h = angle_360(heading);
    if h == 0.0 {
        Point::new(x, y + dist)
    } else if h == 90.0 {
        Point::new(x + dist, y)
    } else if h == 180.0 {
        Point::new(x, y - dist)
    } else if h == 270.0 {
        Point::new(x - dist, y)
    } else {
        let (s, c) = rad(h).sin_cos();
        Point::new(x + s * dist, y + c * dist)
    }
}

/// MOOS `angleDiff`: the smaller angle between two headings, in `[0, 180]`.
pub fn angle_diff(a: f64, b: f64) -> f64 {
    let (a, b) = (angle_360(a), angle_360(b));
    let d = if b > a { b - a } else { a - b };
    if d >= 180.0 { 360.0 - d } else { d }
}

/// MOOS `portTurn`: turning from `osh` to `hdg` is a turn to port (a clockwise change of
/// more than 180°).
pub fn port_turn(osh: f64, hdg: f64) -> bool {
    angle_360(hdg - osh) > 180.0
}

/// Which generator made a model.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum PlatKind {
    /// `holo`: turns on the spot.
    Holonomic,
    /// `dubins`: turns on a circle.
    Dubins,
}

impl PlatKind {
    /// The model's type name (`holo`, `dubins`).
    pub fn as_str(self) -> &'static str {
        match self {
            PlatKind::Holonomic => "holo",
            PlatKind::Dubins => "dubins",
        }
    }
}

/// Ownship's platform model for one helm iteration (MOOS `PlatModel`, see the module docs).
#[derive(Debug, Clone, PartialEq)]
pub struct PlatModel {
    kind: PlatKind,
    pose: (f64, f64, f64, f64),
    radius: f64,
    spoke_degs: f64,
    star: Vec<Point>,
    port: Vec<Point>,
    /// Each side's segments between successive spokes: `(heading, length)`.
    star_segs: Vec<(f64, f64)>,
    port_segs: Vec<(f64, f64)>,
    id: u64,
}

/// The heading and length of each segment of `pts`.
fn segments(pts: &[Point]) -> Vec<(f64, f64)> {
    pts.windows(2)
        .map(|w| {
            let (a, b) = (w[0], w[1]);
            (
                relative_angle(a.x, a.y, b.x, b.y),
                (a.x - b.x).hypot(a.y - b.y),
            )
        })
        .collect()
}

impl PlatModel {
    /// The holonomic model at ownship's pose (`x`, `y`, heading wrapped into `[0, 360)`,
    /// speed at least 0).
    pub fn holonomic(x: f64, y: f64, h: f64, v: f64) -> Self {
        PlatModel {
            kind: PlatKind::Holonomic,
            pose: (x, y, angle_360(h), v.max(0.0)),
            radius: 0.0,
            spoke_degs: 0.0,
            star: Vec::new(),
            port: Vec::new(),
            star_segs: Vec::new(),
            port_segs: Vec::new(),
            id: 0,
        }
    }

    /// The Dubins model at ownship's pose with turn radius `radius` and a spoke every
    /// `spoke_degs` degrees (MOOS `PMGen_Dubins::generate`). Spokes are laid while their
    /// angle, summed spoke by spoke, stays below 180°; a non-positive `spoke_degs` (which
    /// `mod_spoke_degs` can make and on which the C++ loops forever) lays none.
    pub fn dubins(x: f64, y: f64, h: f64, v: f64, radius: f64, spoke_degs: f64) -> Self {
        let h = angle_360(h);
        let star_c = project(h + 90.0, radius, x, y);
        let port_c = project(h - 90.0, radius, x, y);
        let mut star = vec![Point::new(x, y)];
        let mut port = vec![Point::new(x, y)];
        if spoke_degs > 0.0 {
            let mut degs = spoke_degs;
            while degs < 180.0 {
                star.push(project(
                    angle_360((h - 90.0) + degs),
                    radius,
                    star_c.x,
                    star_c.y,
                ));
                port.push(project(
                    angle_360((h + 90.0) - degs),
                    radius,
                    port_c.x,
                    port_c.y,
                ));
                degs += spoke_degs;
            }
        }
        PlatModel {
            kind: PlatKind::Dubins,
            pose: (x, y, h, v.max(0.0)),
            radius,
            spoke_degs,
            star_segs: segments(&star),
            port_segs: segments(&port),
            star,
            port,
            id: 0,
        }
    }

    /// The model numbered `id` (the generator counts the models it makes).
    pub fn with_id(mut self, id: u64) -> Self {
        self.id = id;
        self
    }

    /// The generator's count when it made this model.
    pub fn id(&self) -> u64 {
        self.id
    }

    /// Holonomic or Dubins.
    pub fn kind(&self) -> PlatKind {
        self.kind
    }

    /// Whether the model is the holonomic one (MOOS `isHolonomic`).
    pub fn is_holonomic(&self) -> bool {
        self.kind == PlatKind::Holonomic
    }

    /// Ownship `(x, y, heading, speed)`.
    pub fn pose(&self) -> (f64, f64, f64, f64) {
        self.pose
    }

    /// The turn radius, m (0 for the holonomic model).
    pub fn radius(&self) -> f64 {
        self.radius
    }

    /// Degrees between spokes (0 for the holonomic model).
    pub fn spoke_degs(&self) -> f64 {
        self.spoke_degs
    }

    /// The starboard spokes, ownship's position first (empty for the holonomic model).
    pub fn star_spokes(&self) -> &[Point] {
        &self.star
    }

    /// The port spokes, ownship's position first (empty for the holonomic model).
    pub fn port_spokes(&self) -> &[Point] {
        &self.port
    }

    /// The path ownship follows to hold heading `hdg` (MOOS `getTurnSeglr`): the spokes of
    /// the turn's side up to the turn angle in spokes rounded to the nearest, then a ray
    /// along `hdg`. A model without spokes gives the ray from ownship's position.
    pub fn turn(&self, hdg: f64) -> TurnPath<'_> {
        let (x, y, osh, _) = self.pose;
        let start = Point::new(x, y);
        if self.star.is_empty() || self.port.is_empty() {
            return TurnPath {
                start,
                arc: &[],
                segs: &[],
                ray: hdg,
                port: false,
            };
        }
        let segs = (angle_diff(osh, hdg) / self.spoke_degs + 0.5).trunc();
        let n = if segs > 0.0 { segs as usize } else { 0 };
        let port = port_turn(osh, hdg);
        let (side, segs) = self.side(port);
        let n = n.min(side.len() - 1);
        TurnPath {
            start,
            arc: &side[1..=n],
            segs: &segs[..n],
            ray: hdg,
            port,
        }
    }

    /// The spokes of the port (`port`) or starboard side and the segments between them,
    /// `(heading, length)`.
    pub fn side(&self, port: bool) -> (&[Point], &[(f64, f64)]) {
        if port {
            (&self.port, &self.port_segs)
        } else {
            (&self.star, &self.star_segs)
        }
    }

    /// MOOS `PlatModel::getSpec`: `id=..,type=..,osx=..,osy=..,osh=..,osv=..,spokes:S:P`.
    pub fn spec(&self) -> String {
        let (x, y, h, v) = self.pose;
        let mut s = format!("id={},type={}", self.id, self.kind.as_str());
        for (k, val) in [("osx", x), ("osy", y), ("osh", h), ("osv", v)] {
            s.push(',');
            s.push_str(k);
            s.push('=');
            moos_types::fmt::compact(&mut s, val, 1);
        }
        s.push_str(&format!(",spokes:{}:{}", self.star.len(), self.port.len()));
        s
    }
}

/// A turn's path: vertices from ownship's position, then a ray (MOOS `XYSeglr`).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct TurnPath<'a> {
    /// Ownship's position, the first vertex.
    pub start: Point,
    /// The spokes after it.
    pub arc: &'a [Point],
    /// The segments between the vertices: `(heading, length)`.
    pub segs: &'a [(f64, f64)],
    /// The ray's heading from the last vertex.
    pub ray: f64,
    /// The spokes are the port side's (else the starboard side's, or none).
    pub port: bool,
}

impl TurnPath<'_> {
    /// The number of vertices (at least 1).
    pub fn len(&self) -> usize {
        1 + self.arc.len()
    }

    /// Always false: a path has its start.
    pub fn is_empty(&self) -> bool {
        false
    }

    /// Vertex `i` (0 is the start).
    pub fn vertex(&self, i: usize) -> Point {
        if i == 0 { self.start } else { self.arc[i - 1] }
    }

    /// The heading from vertex `i` to the next, or the ray's heading at the last (MOOS
    /// `getVertAngle`).
    pub fn vert_angle(&self, i: usize) -> f64 {
        match self.segs.get(i) {
            Some(s) => s.0,
            None => self.ray,
        }
    }

    /// The distance from vertex `i` to the next, or −1 at the last (MOOS `getVertDist`).
    pub fn vert_dist(&self, i: usize) -> f64 {
        match self.segs.get(i) {
            Some(s) => s.1,
            None => -1.0,
        }
    }

    /// The distance along the path from the start to vertex `i` (MOOS `getVertPDist`).
    pub fn vert_pdist(&self, i: usize) -> f64 {
        (0..i.min(self.len() - 1)).map(|k| self.vert_dist(k)).sum()
    }

    /// The last vertex, where the ray starts.
    pub fn ray_base(&self) -> Point {
        self.vertex(self.len() - 1)
    }

    /// The length of the vertices' polyline, m.
    pub fn length(&self) -> f64 {
        self.vert_pdist(self.len() - 1)
    }
}

/// One turn on a circle of radius `rad` from ownship's pose to a new heading (MOOS
/// `DubinsTurn`).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct DubinsTurn {
    /// The arc's centre.
    pub center: Point,
    /// The turn radius, m.
    pub radius: f64,
    /// The arc's start angle (clockwise from it to `rangle`), seen from the centre.
    pub langle: f64,
    /// The arc's end angle, seen from the centre.
    pub rangle: f64,
    /// Where ownship leaves the arc on the new heading.
    pub ray_start: Point,
    /// The arc's length, m.
    pub arc_len: f64,
    /// The new heading (0 when there is no turn, as the C++ leaves it).
    pub heading: f64,
    /// +1 a starboard turn, −1 port, 0 none.
    pub turn: i8,
}

impl DubinsTurn {
    /// The turn from `(osx, osy)` heading `osh` to `new_hdg` on radius `rad` (MOOS
    /// `DubinsTurn::setTurn`): starboard unless the new heading is nearer the port beam;
    /// the centre abeam on the turn's side; the arc from ownship to where the circle's
    /// tangent is the new heading; its length the arc's fraction of the circumference
    /// `2·3.14159265359·rad`. No turn: a zero arc on the port circle.
    pub fn new(osx: f64, osy: f64, osh: f64, rad: f64, new_hdg: f64) -> Self {
        let delta = angle_diff(osh, new_hdg);
        let beam_star = angle_360(osh + 90.0);
        let beam_port = angle_360(osh - 90.0);
        if delta == 0.0 {
            return DubinsTurn {
                center: project(beam_port, rad, osx, osy),
                radius: rad,
                langle: beam_star,
                rangle: beam_star,
                ray_start: Point::new(osx, osy),
                arc_len: 0.0,
                heading: 0.0,
                turn: 0,
            };
        }
        let new_hdg = angle_360(new_hdg);
        let star = angle_diff(osh - 90.0, new_hdg) >= angle_diff(osh + 90.0, new_hdg);
        let (center, langle, rangle, ray_start) = if star {
            let c = project(beam_star, rad, osx, osy);
            let r = angle_360(beam_port + delta);
            (c, beam_port, r, project(r, rad, c.x, c.y))
        } else {
            let c = project(beam_port, rad, osx, osy);
            let l = angle_360(beam_star - delta);
            (c, l, beam_star, project(l, rad, c.x, c.y))
        };
        let mut arc = rangle - langle;
        if rangle < langle {
            arc = (360.0 - langle) + rangle;
        }
        DubinsTurn {
            center,
            radius: rad,
            langle,
            rangle,
            ray_start,
            arc_len: arc / 360.0 * (MOOS_PI * rad * 2.0),
            heading: new_hdg,
            turn: if star { 1 } else { -1 },
        }
    }

    /// Seconds the turn takes at `speed` m/s (the arc's length over the speed); infinite at
    /// speed 0 unless there is no arc.
    pub fn time_at(&self, speed: f64) -> f64 {
        if self.arc_len == 0.0 {
            0.0
        } else {
            self.arc_len / speed
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn near(a: f64, b: f64) -> bool {
        (a - b).abs() < 1e-9
    }

    #[test]
    fn holonomic_paths_are_rays_from_ownship() {
        let m = PlatModel::holonomic(5.0, 6.0, -90.0, -1.0);
        assert_eq!(m.pose(), (5.0, 6.0, 270.0, 0.0));
        let p = m.turn(45.0);
        assert_eq!((p.len(), p.start, p.ray), (1, Point::new(5.0, 6.0), 45.0));
        assert_eq!(p.vert_angle(0), 45.0);
        assert_eq!(p.vert_dist(0), -1.0);
        assert_eq!(
            m.spec(),
            "id=0,type=holo,osx=5,osy=6,osh=270,osv=0,spokes:0:0"
        );
    }

    #[test]
    fn dubins_spokes_lie_on_the_turning_circles() {
        // Heading north at the origin, radius 30, spokes every 10°: the starboard centre is
        // (30, 0); spoke k at bearing 270 + 10k from it: (30 − 30·cos(10k°), 30·sin(10k°)).
        let m = PlatModel::dubins(0.0, 0.0, 0.0, 2.0, 30.0, 10.0);
        assert_eq!(m.star_spokes().len(), 18, "0, 10, ..., 170 degrees");
        assert_eq!(m.port_spokes().len(), 18);
        for k in 1..18 {
            let a = (10.0 * k as f64).to_radians();
            let s = m.star_spokes()[k];
            assert!(
                near(s.x, 30.0 - 30.0 * a.cos()) && near(s.y, 30.0 * a.sin()),
                "{k}"
            );
            let p = m.port_spokes()[k];
            assert!(near(p.x, -(30.0 - 30.0 * a.cos())) && near(p.y, 30.0 * a.sin()));
            // Every spoke is the radius from its centre.
            assert!(near((s.x - 30.0).hypot(s.y), 30.0));
        }
        // Spoke 9 is abeam of the centre: (30, 30).
        assert!(near(m.star_spokes()[9].x, 30.0) && near(m.star_spokes()[9].y, 30.0));
        assert_eq!(
            m.spec(),
            "id=0,type=dubins,osx=0,osy=0,osh=0,osv=2,spokes:18:18"
        );
    }

    #[test]
    fn a_turn_takes_the_spokes_of_its_side_rounded_to_the_nearest() {
        let m = PlatModel::dubins(0.0, 0.0, 0.0, 2.0, 30.0, 10.0);
        // 44° to starboard: 4.4 + 0.5 → 4 spokes after the start, then the ray along 44.
        let p = m.turn(44.0);
        assert_eq!(p.len(), 5);
        assert_eq!(p.ray, 44.0);
        assert_eq!(p.vertex(4), m.star_spokes()[4]);
        // 45° rounds up to 5; 300° is a 60° port turn: 6 port spokes.
        assert_eq!(m.turn(45.0).len(), 6);
        let p = m.turn(300.0);
        assert_eq!((p.len(), p.vertex(6)), (7, m.port_spokes()[6]));
        // Dead ahead: the start alone. 180° (not a port turn): the last starboard spoke.
        assert_eq!(m.turn(0.0).len(), 1);
        assert_eq!(m.turn(180.0).len(), 18);
        // The chord between neighbouring spokes is 2·30·sin(5°); the first segment heads 5°.
        let p = m.turn(90.0);
        let chord = 60.0 * 5f64.to_radians().sin();
        assert!(near(p.vert_dist(0), chord) && near(p.vert_pdist(3), 3.0 * chord));
        assert!(near(p.vert_angle(0), 5.0) && near(p.vert_angle(1), 15.0));
        assert_eq!(p.vert_angle(9), 90.0, "the ray");
        assert!(near(p.length(), 9.0 * chord));
        assert_eq!(p.ray_base(), m.star_spokes()[9]);
    }

    #[test]
    fn dubins_turn_arc_radius_and_time() {
        // North at the origin, radius 20, to 90: a starboard quarter circle about (20, 0)
        // from bearing 270 to 0; the ray starts at (20, 20); the arc is 2·MOOS_PI·20/4 (the
        // C++'s 12-digit pi, 3.14159265359).
        let t = DubinsTurn::new(0.0, 0.0, 0.0, 20.0, 90.0);
        assert_eq!(t.turn, 1);
        assert_eq!(t.center, Point::new(20.0, 0.0));
        assert_eq!((t.langle, t.rangle), (270.0, 0.0));
        assert!(near(t.ray_start.x, 20.0) && near(t.ray_start.y, 20.0));
        let arc = MOOS_PI * 20.0 * 2.0 / 4.0;
        assert!(near(t.arc_len, arc));
        // At 2 m/s the turn takes arc / 2 s.
        assert!(near(t.time_at(2.0), arc / 2.0));
        // Port 135° from heading 90 at (10, 10), radius 10: centre (10, 20); the arc from
        // bearing 180 − 135 = 45 to 180; the ray starts 10 m from the centre at 45°.
        let t = DubinsTurn::new(10.0, 10.0, 90.0, 10.0, 315.0);
        assert_eq!(t.turn, -1);
        assert!(near(t.center.x, 10.0) && near(t.center.y, 20.0));
        assert_eq!((t.langle, t.rangle), (45.0, 180.0));
        let h = 10.0 * 45f64.to_radians().sin();
        assert!(near(t.ray_start.x, 10.0 + h) && near(t.ray_start.y, 20.0 + h));
        assert!(near(t.arc_len, 135.0 / 360.0 * MOOS_PI * 20.0));
        // No turn: a zero arc, no time.
        let t = DubinsTurn::new(0.0, 0.0, 30.0, 10.0, 30.0);
        assert_eq!((t.turn, t.arc_len, t.time_at(0.0)), (0, 0.0, 0.0));
        assert_eq!(t.ray_start, Point::new(0.0, 0.0));
    }
}
