//! [`Polygon`]: a closed vertex ring with MOOS-IvP's convexity test (`XYPolygon`).

use crate::point::{Point, snap_to_step};
use crate::seglist::{SegList, bbox_center, closest_vertex};
use crate::segment::Segment;

/// A polygon: vertices in order, the last joined back to the first.
///
/// Convexity is computed when the polygon is built, with MOOS-IvP's rule
/// (`XYPolygon::determine_convexity`): at least three vertices, and for every edge all other
/// vertices that are not on the edge's line lie strictly on one side of it, with at least one
/// off the line. Either winding (clockwise or counter-clockwise) is accepted. A zero-length edge
/// (repeated vertex) makes the polygon non-convex. The rule costs O(n²); above 256 vertices an
/// equivalent O(n) turn test is used instead.
#[derive(Debug, Clone, PartialEq, Default)]
pub struct Polygon {
    pts: Vec<Point>,
    convex: bool,
}

fn orient(a: &Point, b: &Point, c: &Point) -> f64 {
    (b.x - a.x) * (c.y - a.y) - (b.y - a.y) * (c.x - a.x)
}

/// Above this many vertices the O(n²) MOOS rule is replaced by an O(n) turn test.
const EXACT_RULE_MAX: usize = 256;

fn is_convex_ring(pts: &[Point]) -> bool {
    let n = pts.len();
    if n < 3 {
        return false;
    }
    if n > EXACT_RULE_MAX {
        return is_convex_by_turns(pts);
    }
    for i in 0..n {
        let j = (i + 1) % n;
        let (a, b) = (&pts[i], &pts[j]);
        if a.x == b.x && a.y == b.y {
            return false;
        }
        let mut side: Option<bool> = None;
        for (k, p) in pts.iter().enumerate() {
            if k == i || k == j {
                continue;
            }
            let o = orient(a, b, p);
            if o == 0.0 {
                continue;
            }
            match side {
                None => side = Some(o > 0.0),
                Some(s) if s != (o > 0.0) => return false,
                Some(_) => {}
            }
        }
        if side.is_none() {
            return false;
        }
    }
    true
}

/// O(n) convexity for large vertex lists: no repeated consecutive vertex, every turn the same
/// way (straight continuations allowed, reversals not), and the turns add up to one full
/// revolution (so the ring does not wind twice). Agrees with the MOOS rule on simple rings.
fn is_convex_by_turns(pts: &[Point]) -> bool {
    let n = pts.len();
    let mut sign = 0.0f64;
    let mut total = 0.0f64;
    for i in 0..n {
        let a = &pts[i];
        let b = &pts[(i + 1) % n];
        let c = &pts[(i + 2) % n];
        let (ux, uy) = (b.x - a.x, b.y - a.y);
        let (vx, vy) = (c.x - b.x, c.y - b.y);
        if (ux == 0.0 && uy == 0.0) || (vx == 0.0 && vy == 0.0) {
            return false;
        }
        let cross = ux * vy - uy * vx;
        let dot = ux * vx + uy * vy;
        if cross == 0.0 {
            if dot < 0.0 {
                return false;
            }
            continue;
        }
        if sign == 0.0 {
            sign = cross.signum();
        } else if cross.signum() != sign {
            return false;
        }
        total += cross.atan2(dot);
    }
    sign != 0.0 && (total.abs() - 2.0 * std::f64::consts::PI).abs() < 1e-6
}

impl Polygon {
    /// A polygon with the given vertices (any shape; see [`is_convex`](Self::is_convex)).
    pub fn new(pts: Vec<Point>) -> Self {
        let convex = is_convex_ring(&pts);
        Polygon { pts, convex }
    }

    /// A polygon that must be convex.
    ///
    /// ```
    /// use geometry::{Point, Polygon};
    /// let sq = vec![Point::new(0.0, 0.0), Point::new(0.0, 10.0), Point::new(10.0, 10.0), Point::new(10.0, 0.0)];
    /// assert!(Polygon::convex(sq).is_ok());
    /// ```
    pub fn convex(pts: Vec<Point>) -> Result<Self, crate::ParseError> {
        let p = Polygon::new(pts);
        if p.convex {
            Ok(p)
        } else {
            Err(crate::ParseError::NotConvex)
        }
    }

    /// The vertices in order.
    pub fn vertices(&self) -> &[Point] {
        &self.pts
    }

    /// Number of vertices.
    pub fn len(&self) -> usize {
        self.pts.len()
    }

    /// True if there are no vertices.
    pub fn is_empty(&self) -> bool {
        self.pts.is_empty()
    }

    /// True if the polygon is convex by MOOS-IvP's rule (see the type docs).
    pub fn is_convex(&self) -> bool {
        self.convex
    }

    /// The edges, including the closing edge from the last vertex to the first
    /// (none for fewer than two vertices; a single edge for two).
    pub fn edges(&self) -> impl Iterator<Item = Segment> + '_ {
        let n = self.pts.len();
        let count = match n {
            0 | 1 => 0,
            2 => 1,
            _ => n,
        };
        (0..count).map(move |i| Segment::new(self.pts[i], self.pts[(i + 1) % n]))
    }

    /// True if `(x, y)` is inside or on the boundary.
    ///
    /// For convex polygons this equals MOOS's `contains`. For non-convex polygons MOOS always
    /// answers false; this method instead gives the geometric answer (even-odd rule). Fewer than
    /// three vertices: false.
    pub fn contains(&self, x: f64, y: f64) -> bool {
        let n = self.pts.len();
        if n < 3 {
            return false;
        }
        let q = Point::new(x, y);
        let mut inside = false;
        for i in 0..n {
            let a = &self.pts[i];
            let b = &self.pts[(i + 1) % n];
            if orient(a, b, &q) == 0.0
                && x >= a.x.min(b.x)
                && x <= a.x.max(b.x)
                && y >= a.y.min(b.y)
                && y <= a.y.max(b.y)
            {
                return true;
            }
            if (a.y > y) != (b.y > y) {
                let xc = a.x + (y - a.y) * (b.x - a.x) / (b.y - a.y);
                if x < xc {
                    inside = !inside;
                }
            }
        }
        inside
    }

    /// Distance from `(x, y)` to the nearest edge (whether inside or outside), MOOS
    /// `dist_to_poly`. One vertex: distance to it; two: distance to the segment; `None` if empty.
    pub fn dist_to_boundary(&self, x: f64, y: f64) -> Option<f64> {
        match self.pts.len() {
            0 => None,
            1 => Some(self.pts[0].dist(&Point::new(x, y))),
            _ => {
                // Minimum of squared distances, one square root at the end.
                let d2 = self
                    .edges()
                    .map(|e| {
                        let c = e.closest_point(x, y);
                        (c.x - x) * (c.x - x) + (c.y - y) * (c.y - y)
                    })
                    .fold(f64::INFINITY, f64::min);
                Some(d2.sqrt())
            }
        }
    }

    /// The boundary point nearest to `(x, y)` (a vertex for a one-vertex polygon); `None` if
    /// empty.
    ///
    /// ```
    /// use geometry::{Point, Polygon};
    /// let sq = Polygon::new(vec![Point::new(0.0, 0.0), Point::new(0.0, 10.0), Point::new(10.0, 10.0), Point::new(10.0, 0.0)]);
    /// assert_eq!(sq.closest_boundary_point(4.0, 3.0), Some(Point::new(4.0, 0.0)));
    /// ```
    pub fn closest_boundary_point(&self, x: f64, y: f64) -> Option<Point> {
        match self.pts.len() {
            0 => None,
            1 => Some(self.pts[0]),
            _ => self
                .edges()
                .map(|e| {
                    let c = e.closest_point(x, y);
                    ((c.x - x) * (c.x - x) + (c.y - y) * (c.y - y), c)
                })
                .min_by(|a, b| a.0.total_cmp(&b.0))
                .map(|(_, c)| c),
        }
    }

    /// Distance to the boundary, negative when `(x, y)` is strictly inside (the loiter's
    /// "distance to polygon"). `None` if empty.
    pub fn signed_distance(&self, x: f64, y: f64) -> Option<f64> {
        let d = self.dist_to_boundary(x, y)?;
        Some(if self.contains(x, y) { -d } else { d })
    }

    /// Distance from `(x, y)` along compass heading `heading_deg` to the first edge the ray
    /// meets, or `None` if it meets none (MOOS `dist_to_poly(px, py, angle)`, used for the
    /// OpRegion trajectory perimeter distance).
    pub fn ray_distance(&self, x: f64, y: f64, heading_deg: f64) -> Option<f64> {
        if self.pts.len() == 1 {
            let p = self.pts[0];
            return Segment::new(p, p).ray_distance(x, y, heading_deg);
        }
        self.edges()
            .filter_map(|e| e.ray_distance(x, y, heading_deg))
            .min_by(f64::total_cmp)
    }

    /// True if the segment touches the polygon: crosses an edge or has an end point inside
    /// (MOOS `seg_intercepts`).
    pub fn segment_intersects(&self, seg: &Segment) -> bool {
        match self.pts.len() {
            0 => false,
            1 => seg.dist_to_point(self.pts[0].x, self.pts[0].y) == 0.0,
            _ => {
                self.contains(seg.a.x, seg.a.y)
                    || self.contains(seg.b.x, seg.b.y)
                    || self.edges().any(|e| e.crosses(seg))
            }
        }
    }

    /// The points where `seg` crosses the polygon's edges, in edge order.
    pub fn segment_crossings(&self, seg: &Segment) -> Vec<Point> {
        self.edges().filter_map(|e| seg.intersection(&e)).collect()
    }

    /// Signed area (shoelace): positive for counter-clockwise, negative for clockwise vertex
    /// order (x east, y north).
    pub fn signed_area(&self) -> f64 {
        let n = self.pts.len();
        if n < 3 {
            return 0.0;
        }
        let mut s = 0.0;
        for i in 0..n {
            let a = &self.pts[i];
            let b = &self.pts[(i + 1) % n];
            s += a.x * b.y - b.x * a.y;
        }
        s / 2.0
    }

    /// Area in square metres.
    pub fn area(&self) -> f64 {
        self.signed_area().abs()
    }

    /// True if the vertices run clockwise (as MOOS's radial and oval generators produce them).
    pub fn is_clockwise(&self) -> bool {
        self.signed_area() < 0.0
    }

    /// Area centroid; for a degenerate (zero-area) vertex list, the mean of the vertices;
    /// origin if empty.
    ///
    /// ```
    /// use geometry::{Point, Polygon};
    /// let tri = Polygon::new(vec![Point::new(0.0, 0.0), Point::new(6.0, 0.0), Point::new(0.0, 3.0)]);
    /// assert_eq!(tri.centroid(), Point::new(2.0, 1.0));
    /// ```
    pub fn centroid(&self) -> Point {
        let n = self.pts.len();
        if n == 0 {
            return Point::default();
        }
        let a = self.signed_area();
        if a == 0.0 {
            let (sx, sy) = self
                .pts
                .iter()
                .fold((0.0, 0.0), |(sx, sy), p| (sx + p.x, sy + p.y));
            return Point::new(sx / n as f64, sy / n as f64);
        }
        let (mut cx, mut cy) = (0.0, 0.0);
        for i in 0..n {
            let p = &self.pts[i];
            let q = &self.pts[(i + 1) % n];
            let c = p.x * q.y - q.x * p.y;
            cx += (p.x + q.x) * c;
            cy += (p.y + q.y) * c;
        }
        Point::new(cx / (6.0 * a), cy / (6.0 * a))
    }

    /// Middle of the bounding box (MOOS `get_center_x/y`); origin if empty.
    pub fn center(&self) -> Point {
        bbox_center(&self.pts)
    }

    /// The largest distance from [`Polygon::center`] to a vertex (MOOS `max_radius`); 0 if
    /// empty.
    ///
    /// ```
    /// use geometry::{Point, Polygon};
    /// let sq = Polygon::new(vec![Point::new(0.0, 0.0), Point::new(0.0, 6.0), Point::new(8.0, 6.0), Point::new(8.0, 0.0)]);
    /// assert_eq!(sq.max_radius(), 5.0);
    /// ```
    pub fn max_radius(&self) -> f64 {
        let c = self.center();
        self.pts
            .iter()
            .map(|p| (p.x - c.x).hypot(p.y - c.y))
            .fold(0.0, f64::max)
    }

    /// The polygon grown outward by `dist` metres (MOOS-IvP `XYPolyExpander::getBufferPoly`):
    /// every edge is moved out by `dist` along its normal (the side away from the vertex
    /// centroid), and each corner is rounded by points every `deg_delta` degrees (clipped to
    /// `[0.2, 45]`) on a circle of radius `dist` about the original vertex; an edge end within
    /// 1 m of the point before it is dropped. Returns `None` for a non-convex polygon, or when
    /// the result is not convex (MOOS then tries to repair it; coug keeps the caller's
    /// fallback).
    ///
    /// ```
    /// use geometry::{Point, Polygon};
    /// let sq = Polygon::new(vec![Point::new(0.0, 0.0), Point::new(0.0, 10.0), Point::new(10.0, 10.0), Point::new(10.0, 0.0)]);
    /// let b = sq.buffered(5.0, 15.0).unwrap();
    /// assert!(b.contains(-4.0, 5.0) && b.contains(5.0, 14.0) && !b.contains(-6.0, 5.0));
    /// ```
    pub fn buffered(&self, dist: f64, deg_delta: f64) -> Option<Polygon> {
        use crate::angle::{angle_360, angle_diff, relative_angle};
        if !self.is_convex() {
            return None;
        }
        let deg_delta = deg_delta.clamp(0.2, 45.0);
        let v = &self.pts;
        let n = v.len();
        let (sx, sy) = v
            .iter()
            .fold((0.0, 0.0), |(sx, sy), p| (sx + p.x, sy + p.y));
        let c = Point::new(sx / n as f64, sy / n as f64);
        // Each edge moved out: (start, end).
        let moved: Vec<(Point, Point)> = (0..n)
            .map(|i| {
                let (a, b) = (v[i], v[(i + 1) % n]);
                let along = relative_angle(a.x, a.y, b.x, b.y);
                let to_c = relative_angle(a.x, a.y, c.x, c.y);
                let (b1, b2) = (angle_360(along - 90.0), angle_360(along + 90.0));
                let out = if angle_diff(b1, to_c) < angle_diff(b2, to_c) {
                    b2
                } else {
                    b1
                };
                (a.project(out, dist), b.project(out, dist))
            })
            .collect();
        let clockwise = self.is_clockwise();
        let mut pts: Vec<Point> = Vec::new();
        for k in 0..n {
            // At vertex k: the end of the previous edge, the corner arc, the start of edge k.
            let from = moved[(k + n - 1) % n].1;
            let to = moved[k].0;
            pts.push(from);
            let vk = v[k];
            let a1 = relative_angle(vk.x, vk.y, from.x, from.y);
            let a2 = relative_angle(vk.x, vk.y, to.x, to.y);
            let steps = (angle_diff(a1, a2) / deg_delta).max(0.0) as u32;
            for j in 1..steps {
                let step = f64::from(j) * deg_delta;
                let a = angle_360(if clockwise { a1 + step } else { a1 - step });
                pts.push(vk.project(a, dist));
            }
            let last = pts[pts.len() - 1];
            if pts.len() < 2 || (to.x - last.x).hypot(to.y - last.y) > 1.0 {
                pts.push(to);
            }
        }
        let p = Polygon::new(pts);
        p.is_convex().then_some(p)
    }

    /// Index of the vertex nearest `(x, y)` (first one on ties); `None` if empty.
    pub fn closest_vertex(&self, x: f64, y: f64) -> Option<usize> {
        closest_vertex(&self.pts, x, y)
    }

    /// The vertices as a seglist in the same cyclic order, starting at the vertex nearest
    /// `(x, y)` (MOOS `exportSegList`, used when a waypoint `points` value is a polygon).
    ///
    /// ```
    /// use geometry::{Point, Polygon};
    /// let sq = Polygon::new(vec![Point::new(0.0, 0.0), Point::new(0.0, 10.0), Point::new(10.0, 10.0), Point::new(10.0, 0.0)]);
    /// let s = sq.export_seglist(9.0, 9.0);
    /// assert_eq!(s.get(0), Some(Point::new(10.0, 10.0)));
    /// assert_eq!(s.get(3), Some(Point::new(0.0, 10.0)));
    /// ```
    pub fn export_seglist(&self, x: f64, y: f64) -> SegList {
        let Some(start) = self.closest_vertex(x, y) else {
            return SegList::new();
        };
        let n = self.pts.len();
        (0..n).map(|k| self.pts[(start + k) % n]).collect()
    }

    /// The vertices as a seglist in stored order.
    pub fn to_seglist(&self) -> SegList {
        SegList::from_points(self.pts.clone())
    }

    /// Reverses the vertex order (clockwise ↔ counter-clockwise); convexity is unchanged.
    pub fn reverse(&mut self) {
        self.pts.reverse();
    }

    /// Moves every vertex by `(dx, dy)`.
    pub fn shift(&mut self, dx: f64, dy: f64) {
        for p in &mut self.pts {
            p.x += dx;
            p.y += dy;
        }
    }

    /// Moves the polygon so the middle of its bounding box is at `(x, y)` (MOOS
    /// `new_center`, used by the loiter's `center_assign`).
    ///
    /// ```
    /// use geometry::{Point, Polygon};
    /// let mut sq = Polygon::new(vec![Point::new(0.0, 0.0), Point::new(0.0, 10.0), Point::new(10.0, 10.0), Point::new(10.0, 0.0)]);
    /// sq.new_center(100.0, -50.0);
    /// assert_eq!(sq.vertices()[0], Point::new(95.0, -55.0));
    /// ```
    pub fn new_center(&mut self, x: f64, y: f64) {
        let c = self.center();
        self.shift(x - c.x, y - c.y);
    }

    /// Snaps `x`/`y` of every vertex to multiples of `step`. As in MOOS, a snap that would turn
    /// a convex polygon non-convex is undone; returns false in that case.
    pub fn apply_snap(&mut self, step: f64) -> bool {
        let was_convex = self.convex;
        let before = self.pts.clone();
        for p in &mut self.pts {
            p.x = snap_to_step(p.x, step);
            p.y = snap_to_step(p.y, step);
        }
        self.convex = is_convex_ring(&self.pts);
        if was_convex && !self.convex {
            self.pts = before;
            self.convex = true;
            return false;
        }
        true
    }
}

impl std::str::FromStr for Polygon {
    type Err = crate::ParseError;

    /// Parses any polygon form (see [`crate::spec::parse_polygon`]), keeping only the shape.
    fn from_str(s: &str) -> Result<Self, Self::Err> {
        crate::spec::parse_polygon(s).map(|v| v.polygon)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn poly(v: &[(f64, f64)]) -> Polygon {
        Polygon::new(v.iter().map(|&(x, y)| Point::new(x, y)).collect())
    }

    #[test]
    fn convexity_rule() {
        assert!(poly(&[(0.0, 0.0), (10.0, 0.0), (10.0, 10.0), (0.0, 10.0)]).is_convex());
        assert!(poly(&[(0.0, 0.0), (0.0, 10.0), (10.0, 10.0), (10.0, 0.0)]).is_convex());
        // A collinear middle vertex is tolerated (MOOS ignores points on the edge line).
        assert!(poly(&[(0.0, 0.0), (5.0, 0.0), (10.0, 0.0), (10.0, 10.0)]).is_convex());
        // Dent.
        assert!(
            !poly(&[
                (0.0, 0.0),
                (10.0, 0.0),
                (5.0, 2.0),
                (10.0, 10.0),
                (0.0, 10.0)
            ])
            .is_convex()
        );
        // Bow tie (self-crossing).
        assert!(!poly(&[(0.0, 0.0), (10.0, 10.0), (10.0, 0.0), (0.0, 10.0)]).is_convex());
        // Repeated vertex, too few, all collinear.
        assert!(!poly(&[(0.0, 0.0), (10.0, 0.0), (10.0, 0.0), (0.0, 10.0)]).is_convex());
        assert!(!poly(&[(0.0, 0.0), (10.0, 0.0)]).is_convex());
        assert!(!poly(&[(0.0, 0.0), (1.0, 1.0), (2.0, 2.0)]).is_convex());
        // The corpus loiter/waypoint pentagon.
        let p = poly(&[
            (60.0, -40.0),
            (60.0, -160.0),
            (150.0, -160.0),
            (180.0, -100.0),
            (150.0, -40.0),
        ]);
        assert!(p.is_convex());
    }

    #[test]
    fn large_rings_use_the_turn_test_consistently() {
        let ring = |n: u32, turns: f64| -> Vec<Point> {
            (0..n)
                .map(|i| {
                    crate::angle::project_point(
                        0.0,
                        0.0,
                        turns * 360.0 * f64::from(i) / f64::from(n),
                        100.0,
                    )
                })
                .collect()
        };
        let big = ring(1000, 1.0);
        assert!(is_convex_ring(&big));
        assert!(!is_convex_ring(&ring(1001, 2.0))); // winds twice
        let mut dented = big.clone();
        dented[500] = Point::new(dented[500].x * 0.5, dented[500].y * 0.5);
        assert!(!is_convex_ring(&dented));
        let mut repeated = big.clone();
        repeated[10] = repeated[9];
        assert!(!is_convex_ring(&repeated));
        // Both rules agree on mid-size rings.
        for n in [3u32, 7, 64, 256] {
            let r = ring(n, 1.0);
            assert_eq!(is_convex_ring(&r), is_convex_by_turns(&r), "n={n}");
        }
        let l = [
            (0.0, 0.0),
            (0.0, 10.0),
            (5.0, 10.0),
            (5.0, 5.0),
            (10.0, 5.0),
            (10.0, 0.0),
        ]
        .map(|(x, y)| Point::new(x, y));
        assert!(!is_convex_by_turns(&l));
        let spike =
            [(0.0, 0.0), (10.0, 0.0), (5.0, 0.0), (5.0, 5.0)].map(|(x, y)| Point::new(x, y));
        assert!(!is_convex_by_turns(&spike) && !is_convex_ring(&spike));
    }

    #[test]
    fn contains_and_distance() {
        let sq = poly(&[(0.0, 0.0), (0.0, 10.0), (10.0, 10.0), (10.0, 0.0)]);
        assert!(sq.contains(5.0, 5.0));
        assert!(sq.contains(0.0, 5.0)); // on edge
        assert!(sq.contains(10.0, 10.0)); // vertex
        assert!(!sq.contains(10.1, 5.0));
        assert!(!sq.contains(-1.0, -1.0));
        assert_eq!(sq.dist_to_boundary(5.0, 3.0), Some(3.0));
        assert_eq!(sq.signed_distance(5.0, 3.0), Some(-3.0));
        assert_eq!(sq.dist_to_boundary(13.0, 14.0), Some(5.0));
        assert_eq!(sq.ray_distance(5.0, 5.0, 90.0), Some(5.0));
        assert_eq!(sq.ray_distance(5.0, -4.0, 0.0), Some(4.0));
        assert_eq!(sq.ray_distance(5.0, -4.0, 180.0), None);
        // Non-convex L shape: the notch is outside.
        let l = poly(&[
            (0.0, 0.0),
            (0.0, 10.0),
            (5.0, 10.0),
            (5.0, 5.0),
            (10.0, 5.0),
            (10.0, 0.0),
        ]);
        assert!(!l.is_convex());
        assert!(l.contains(2.0, 8.0));
        assert!(!l.contains(8.0, 8.0));
        assert_eq!(Polygon::default().dist_to_boundary(0.0, 0.0), None);
    }

    #[test]
    fn segment_tests() {
        let sq = poly(&[(0.0, 0.0), (0.0, 10.0), (10.0, 10.0), (10.0, 0.0)]);
        assert!(sq.segment_intersects(&Segment::from_xy(2.0, 2.0, 3.0, 3.0))); // inside
        assert!(sq.segment_intersects(&Segment::from_xy(-5.0, 5.0, 15.0, 5.0))); // through
        assert!(!sq.segment_intersects(&Segment::from_xy(-5.0, 11.0, 15.0, 11.0)));
        let x = sq.segment_crossings(&Segment::from_xy(-5.0, 5.0, 15.0, 5.0));
        assert_eq!(x, vec![Point::new(0.0, 5.0), Point::new(10.0, 5.0)]);
    }

    #[test]
    fn area_centroid_winding() {
        let sq = poly(&[(0.0, 0.0), (0.0, 10.0), (10.0, 10.0), (10.0, 0.0)]);
        assert_eq!(sq.signed_area(), -100.0);
        assert!(sq.is_clockwise());
        assert_eq!(sq.centroid(), Point::new(5.0, 5.0));
        assert_eq!(sq.center(), Point::new(5.0, 5.0));
        let line = poly(&[(0.0, 0.0), (2.0, 0.0), (4.0, 0.0)]);
        assert_eq!(line.centroid(), Point::new(2.0, 0.0));
    }

    #[test]
    fn snap_reverts_when_it_breaks_convexity() {
        // A thin triangle whose snapped vertices become collinear.
        let mut t = poly(&[(0.0, 0.0), (5.0, 0.2), (10.0, 0.0)]);
        assert!(t.is_convex());
        assert!(!t.apply_snap(1.0));
        assert_eq!(t.vertices()[1], Point::new(5.0, 0.2));
        let mut sq = poly(&[(0.2, 0.1), (0.0, 9.8), (10.3, 10.0), (10.0, 0.4)]);
        assert!(sq.apply_snap(1.0));
        assert_eq!(sq.vertices()[2], Point::new(10.0, 10.0));
    }
}
