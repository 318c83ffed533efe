//! [`Segment`]: a directed line segment, with the distance / crossing helpers of MOOS-IvP's
//! `GeomUtils` and the track helpers a waypoint follower needs (perpendicular foot, `lead`
//! point, passing the end of a leg).
//!
//! Crossing tests use exact orientation signs instead of MOOS's slope/intercept cases, so
//! nearly-vertical segments are handled without rounding surprises; the answers agree with
//! MOOS wherever MOOS's arithmetic is exact. `closest_point` clamps the perpendicular foot to the
//! segment; MOOS's `perpSegIntPt` instead accepts a foot up to 1 m outside the segment's box
//! and otherwise snaps to the nearer end point, so distances can differ by a fraction of a metre
//! for points just beyond an end.

use crate::angle::{project_point, relative_angle};
use crate::point::{Point, dist};

/// A directed segment from `a` to `b`.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct Segment {
    /// Start point.
    pub a: Point,
    /// End point.
    pub b: Point,
}

fn cross(ux: f64, uy: f64, vx: f64, vy: f64) -> f64 {
    ux * vy - uy * vx
}

/// Orientation of `c` relative to the line `a→b`: > 0 left (counter-clockwise), < 0 right.
fn orient(ax: f64, ay: f64, bx: f64, by: f64, cx: f64, cy: f64) -> f64 {
    cross(bx - ax, by - ay, cx - ax, cy - ay)
}

/// For a `c` collinear with `a`,`b`: is `c` inside their bounding box?
fn within_box(ax: f64, ay: f64, bx: f64, by: f64, cx: f64, cy: f64) -> bool {
    cx >= ax.min(bx) && cx <= ax.max(bx) && cy >= ay.min(by) && cy <= ay.max(by)
}

/// True if the closed segments `(x1,y1)-(x2,y2)` and `(x3,y3)-(x4,y4)` share at least one point
/// (touching end points and collinear overlap count), MOOS `segmentsCross`.
#[allow(clippy::too_many_arguments)]
pub fn segments_cross(
    x1: f64,
    y1: f64,
    x2: f64,
    y2: f64,
    x3: f64,
    y3: f64,
    x4: f64,
    y4: f64,
) -> bool {
    let d1 = orient(x3, y3, x4, y4, x1, y1);
    let d2 = orient(x3, y3, x4, y4, x2, y2);
    let d3 = orient(x1, y1, x2, y2, x3, y3);
    let d4 = orient(x1, y1, x2, y2, x4, y4);
    let straddle = |p: f64, q: f64| (p > 0.0 && q < 0.0) || (p < 0.0 && q > 0.0);
    if straddle(d1, d2) && straddle(d3, d4) {
        return true;
    }
    (d1 == 0.0 && within_box(x3, y3, x4, y4, x1, y1))
        || (d2 == 0.0 && within_box(x3, y3, x4, y4, x2, y2))
        || (d3 == 0.0 && within_box(x1, y1, x2, y2, x3, y3))
        || (d4 == 0.0 && within_box(x1, y1, x2, y2, x4, y4))
}

/// Distance from `(px, py)` to the closed segment `(x1,y1)-(x2,y2)` (MOOS `distPointToSeg`).
///
/// ```
/// use geometry::segment::dist_point_to_segment;
/// assert_eq!(dist_point_to_segment(0.0, 0.0, 10.0, 0.0, 5.0, 3.0), 3.0);
/// assert_eq!(dist_point_to_segment(0.0, 0.0, 10.0, 0.0, 13.0, 4.0), 5.0);
/// ```
pub fn dist_point_to_segment(x1: f64, y1: f64, x2: f64, y2: f64, px: f64, py: f64) -> f64 {
    let f = Segment::from_xy(x1, y1, x2, y2).closest_point(px, py);
    dist(px, py, f.x, f.y)
}

impl Segment {
    /// A segment from `a` to `b`.
    pub const fn new(a: Point, b: Point) -> Self {
        Segment { a, b }
    }

    /// A segment from `(x1, y1)` to `(x2, y2)`.
    pub const fn from_xy(x1: f64, y1: f64, x2: f64, y2: f64) -> Self {
        Segment {
            a: Point::new(x1, y1),
            b: Point::new(x2, y2),
        }
    }

    /// Length in metres.
    pub fn length(&self) -> f64 {
        self.a.dist(&self.b)
    }

    /// Compass bearing from `a` to `b` (0 for a zero-length segment).
    pub fn bearing(&self) -> f64 {
        relative_angle(self.a.x, self.a.y, self.b.x, self.b.y)
    }

    fn dir(&self) -> (f64, f64) {
        (self.b.x - self.a.x, self.b.y - self.a.y)
    }

    /// Parameter `t` of the perpendicular foot of `(x, y)` on the infinite line (0 at `a`,
    /// 1 at `b`); `None` for a zero-length segment.
    fn foot_param(&self, x: f64, y: f64) -> Option<f64> {
        let (dx, dy) = self.dir();
        let len2 = dx * dx + dy * dy;
        if len2 == 0.0 {
            return None;
        }
        Some(((x - self.a.x) * dx + (y - self.a.y) * dy) / len2)
    }

    fn at(&self, t: f64) -> Point {
        let (dx, dy) = self.dir();
        Point::new(self.a.x + t * dx, self.a.y + t * dy)
    }

    /// The point of the segment nearest to `(x, y)`: the perpendicular foot, clamped to the
    /// end points (`a` for a zero-length segment).
    pub fn closest_point(&self, x: f64, y: f64) -> Point {
        match self.foot_param(x, y) {
            None => Point::new(self.a.x, self.a.y),
            Some(t) if t <= 0.0 => Point::new(self.a.x, self.a.y),
            Some(t) if t >= 1.0 => Point::new(self.b.x, self.b.y),
            Some(t) => self.at(t),
        }
    }

    /// The perpendicular foot of `(x, y)` on the infinite line through `a` and `b`, not clamped
    /// (MOOS `perpLineIntPt`); `a` for a zero-length segment.
    pub fn line_foot(&self, x: f64, y: f64) -> Point {
        match self.foot_param(x, y) {
            None => Point::new(self.a.x, self.a.y),
            Some(t) => self.at(t),
        }
    }

    /// Distance from `(x, y)` to the segment.
    pub fn dist_to_point(&self, x: f64, y: f64) -> f64 {
        let f = self.closest_point(x, y);
        dist(x, y, f.x, f.y)
    }

    /// Signed distance of the perpendicular foot of `(x, y)` from `a`, measured along `a→b`
    /// (negative before `a`, greater than [`length`](Self::length) beyond `b`). 0 for a
    /// zero-length segment.
    pub fn along_track(&self, x: f64, y: f64) -> f64 {
        let (dx, dy) = self.dir();
        let len = dx.hypot(dy);
        if len == 0.0 {
            return 0.0;
        }
        ((x - self.a.x) * dx + (y - self.a.y) * dy) / len
    }

    /// Signed cross-track distance of `(x, y)` from the line `a→b`: positive to the right
    /// (starboard when travelling from `a` to `b`), negative to the left. For a zero-length
    /// segment, the distance to `a`.
    pub fn cross_track(&self, x: f64, y: f64) -> f64 {
        let (dx, dy) = self.dir();
        let len = dx.hypot(dy);
        if len == 0.0 {
            return dist(x, y, self.a.x, self.a.y);
        }
        -cross(dx, dy, x - self.a.x, y - self.a.y) / len
    }

    /// True if this segment and `other` share at least one point.
    pub fn crosses(&self, other: &Segment) -> bool {
        segments_cross(
            self.a.x, self.a.y, self.b.x, self.b.y, other.a.x, other.a.y, other.b.x, other.b.y,
        )
    }

    /// The point where this segment meets `other`, if they do. For collinear overlapping
    /// segments, the shared point nearest to `self.a`.
    ///
    /// ```
    /// use geometry::Segment;
    /// let track = Segment::from_xy(0.0, 0.0, 0.0, 100.0);
    /// let path = Segment::from_xy(-5.0, 40.0, 5.0, 50.0);
    /// let p = track.intersection(&path).unwrap();
    /// assert_eq!((p.x, p.y), (0.0, 45.0));
    /// ```
    pub fn intersection(&self, other: &Segment) -> Option<Point> {
        if !self.crosses(other) {
            return None;
        }
        let (dx, dy) = self.dir();
        let (ex, ey) = other.dir();
        let denom = cross(dx, dy, ex, ey);
        if denom != 0.0 {
            let t = cross(other.a.x - self.a.x, other.a.y - self.a.y, ex, ey) / denom;
            return Some(self.at(t.clamp(0.0, 1.0)));
        }
        // Parallel (collinear, since they cross) or degenerate: pick the nearest shared end point.
        let candidates = [
            (self.a, other.dist_to_point(self.a.x, self.a.y) == 0.0),
            (self.b, other.dist_to_point(self.b.x, self.b.y) == 0.0),
            (other.a, self.dist_to_point(other.a.x, other.a.y) == 0.0),
            (other.b, self.dist_to_point(other.b.x, other.b.y) == 0.0),
        ];
        candidates
            .iter()
            .filter(|(_, on)| *on)
            .map(|(p, _)| Point::new(p.x, p.y))
            .min_by(|p, q| self.a.dist(p).total_cmp(&self.a.dist(q)))
    }

    /// Shortest distance between this segment and `other` (0 if they cross).
    pub fn dist_to_segment(&self, other: &Segment) -> f64 {
        if self.crosses(other) {
            return 0.0;
        }
        self.dist_to_point(other.a.x, other.a.y)
            .min(self.dist_to_point(other.b.x, other.b.y))
            .min(other.dist_to_point(self.a.x, self.a.y))
            .min(other.dist_to_point(self.b.x, self.b.y))
    }

    /// Distance from `(x, y)` along compass heading `heading_deg` to the first point of this
    /// segment, or `None` if the ray misses it.
    pub fn ray_distance(&self, x: f64, y: f64, heading_deg: f64) -> Option<f64> {
        let u = project_point(0.0, 0.0, heading_deg, 1.0);
        let (ux, uy) = (u.x, u.y);
        let (dx, dy) = self.dir();
        let (wx, wy) = (self.a.x - x, self.a.y - y);
        let denom = cross(ux, uy, dx, dy);
        if denom != 0.0 {
            let s = cross(wx, wy, dx, dy) / denom;
            let t = cross(wx, wy, ux, uy) / denom;
            return (s >= 0.0 && (0.0..=1.0).contains(&t)).then_some(s);
        }
        if cross(wx, wy, ux, uy) != 0.0 {
            return None;
        }
        let sa = wx * ux + wy * uy;
        let sb = (self.b.x - x) * ux + (self.b.y - y) * uy;
        if sa < 0.0 && sb < 0.0 {
            None
        } else if sa * sb <= 0.0 {
            Some(0.0)
        } else {
            Some(sa.min(sb))
        }
    }

    /// True once `(x, y)` is on or beyond the line through `b` perpendicular to the segment,
    /// i.e. the angle at `b` between `a` and `(x, y)` is at least 90 degrees. This is the
    /// waypoint `capture_line` test. A zero-length segment counts as passed.
    pub fn passed_end(&self, x: f64, y: f64) -> bool {
        let (dx, dy) = self.dir();
        (x - self.b.x) * dx + (y - self.b.y) * dy >= 0.0
    }

    /// Where a vehicle moving from `from` to `to` crosses the line through `b` perpendicular to
    /// the segment (the "end of leg" line), if it crosses it in the forward direction during
    /// that move. `None` for a zero-length segment.
    pub fn end_line_crossing(&self, from: Point, to: Point) -> Option<Point> {
        let (dx, dy) = self.dir();
        if dx == 0.0 && dy == 0.0 {
            return None;
        }
        let s0 = (from.x - self.b.x) * dx + (from.y - self.b.y) * dy;
        let s1 = (to.x - self.b.x) * dx + (to.y - self.b.y) * dy;
        if !(s0 < 0.0 && s1 >= 0.0) {
            return None;
        }
        let t = s0 / (s0 - s1);
        Some(Point::new(
            from.x + t * (to.x - from.x),
            from.y + t * (to.y - from.y),
        ))
    }

    /// The waypoint-follower track point for a vehicle at `(x, y)` on the leg `a→b` with a
    /// `lead` distance (MOOS `BHV_Waypoint`): take the perpendicular foot of the vehicle on the
    /// segment, then move `lead` metres from it along the leg direction `a→b`, but never past
    /// `b`. `lead = 0` gives the foot itself; a negative `lead` (MOOS: lead off) returns `b`.
    ///
    /// ```
    /// use geometry::Segment;
    /// let leg = Segment::from_xy(0.0, 0.0, 0.0, 100.0);
    /// let t = leg.lead_point(8.0, 30.0, 20.0);
    /// assert_eq!((t.x, t.y), (0.0, 50.0));
    /// let t = leg.lead_point(8.0, 90.0, 20.0);
    /// assert_eq!((t.x, t.y), (0.0, 100.0));
    /// ```
    pub fn lead_point(&self, x: f64, y: f64, lead: f64) -> Point {
        self.lead_point_damped(x, y, lead, -1.0)
    }

    /// [`lead_point`](Self::lead_point) with MOOS's `lead_damper`: when the vehicle is closer
    /// than `damper` metres to the track line, the lead grows by the factor
    /// `1 + 2·(1 − d/damper)` (up to 3× on the line itself). `damper <= 0` disables it.
    ///
    /// ```
    /// use geometry::Segment;
    /// let leg = Segment::from_xy(0.0, 0.0, 0.0, 100.0);
    /// // 5 m off the line with damper 20: factor 1 + 2*(1 - 5/20) = 2.5, lead 10 -> 25.
    /// let t = leg.lead_point_damped(5.0, 30.0, 10.0, 20.0);
    /// assert_eq!((t.x, t.y), (0.0, 55.0));
    /// ```
    pub fn lead_point_damped(&self, x: f64, y: f64, lead: f64, damper: f64) -> Point {
        let end = Point::new(self.b.x, self.b.y);
        if lead.is_nan() || lead < 0.0 {
            return end;
        }
        let foot = self.closest_point(x, y);
        let mut factor = 1.0;
        if damper > 0.0 {
            let off = dist(foot.x, foot.y, x, y);
            if off < damper {
                factor += 2.0 * (1.0 - off / damper);
            }
        }
        let reach = lead * factor;
        if foot.dist(&end) <= reach {
            return end;
        }
        let (dx, dy) = self.dir();
        let len = dx.hypot(dy);
        Point::new(foot.x + reach * dx / len, foot.y + reach * dy / len)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn point_to_segment_distances() {
        let s = Segment::from_xy(0.0, 0.0, 10.0, 10.0);
        // Foot of (10,0) is (5,5): distance sqrt(50).
        assert!((s.dist_to_point(10.0, 0.0) - 50f64.sqrt()).abs() < 1e-12);
        assert_eq!(s.closest_point(-3.0, -4.0), Point::new(0.0, 0.0));
        assert_eq!(s.closest_point(20.0, 20.0), Point::new(10.0, 10.0));
        assert_eq!(s.line_foot(20.0, 20.0), Point::new(20.0, 20.0));
        let z = Segment::from_xy(1.0, 1.0, 1.0, 1.0);
        assert_eq!(z.dist_to_point(4.0, 5.0), 5.0);
    }

    #[test]
    fn along_and_cross_track() {
        let s = Segment::from_xy(0.0, 0.0, 0.0, 10.0); // heading north
        assert_eq!(s.along_track(3.0, 4.0), 4.0);
        assert_eq!(s.cross_track(3.0, 4.0), 3.0); // east of a northbound leg = starboard
        assert_eq!(s.cross_track(-2.0, 4.0), -2.0);
        assert_eq!(s.along_track(0.0, -5.0), -5.0);
    }

    #[test]
    fn crossing_cases() {
        let s = Segment::from_xy(0.0, 0.0, 10.0, 0.0);
        assert!(s.crosses(&Segment::from_xy(5.0, -1.0, 5.0, 1.0)));
        assert!(s.crosses(&Segment::from_xy(10.0, 0.0, 12.0, 5.0))); // shared end point
        assert!(s.crosses(&Segment::from_xy(5.0, 0.0, 5.0, 3.0))); // T junction
        assert!(!s.crosses(&Segment::from_xy(11.0, -1.0, 11.0, 1.0)));
        assert!(s.crosses(&Segment::from_xy(8.0, 0.0, 15.0, 0.0))); // collinear overlap
        assert!(!s.crosses(&Segment::from_xy(11.0, 0.0, 15.0, 0.0))); // collinear gap
        assert!(!s.crosses(&Segment::from_xy(0.0, 1.0, 10.0, 1.0))); // parallel
        let p = s
            .intersection(&Segment::from_xy(3.0, -3.0, 7.0, 1.0))
            .unwrap();
        assert!((p.x - 6.0).abs() < 1e-12 && p.y.abs() < 1e-12);
        let p = s
            .intersection(&Segment::from_xy(8.0, 0.0, 15.0, 0.0))
            .unwrap();
        assert_eq!(p, Point::new(8.0, 0.0));
        assert_eq!(s.intersection(&Segment::from_xy(0.0, 1.0, 10.0, 1.0)), None);
        assert_eq!(
            s.dist_to_segment(&Segment::from_xy(13.0, 4.0, 20.0, 4.0)),
            5.0
        );
        assert_eq!(
            s.dist_to_segment(&Segment::from_xy(5.0, -1.0, 5.0, 1.0)),
            0.0
        );
    }

    #[test]
    fn ray_distances() {
        let s = Segment::from_xy(-5.0, 10.0, 5.0, 10.0);
        assert_eq!(s.ray_distance(0.0, 0.0, 0.0), Some(10.0));
        assert_eq!(s.ray_distance(0.0, 0.0, 180.0), None);
        // At 45 degrees the ray reaches y=10 at x=10, east of the segment's end x=5.
        assert_eq!(s.ray_distance(0.0, 0.0, 45.0), None);
        let wide = Segment::from_xy(-5.0, 10.0, 15.0, 10.0);
        let d = wide.ray_distance(0.0, 0.0, 45.0).unwrap();
        assert!((d - 200f64.sqrt()).abs() < 1e-9);
        // Collinear ray.
        let s = Segment::from_xy(0.0, 5.0, 0.0, 9.0);
        assert_eq!(s.ray_distance(0.0, 0.0, 0.0), Some(5.0));
        assert_eq!(s.ray_distance(0.0, 6.0, 0.0), Some(0.0));
        assert_eq!(s.ray_distance(0.0, 10.0, 0.0), None);
    }

    #[test]
    fn leg_end_and_lead() {
        let leg = Segment::from_xy(0.0, 0.0, 0.0, 100.0);
        assert!(!leg.passed_end(5.0, 99.0));
        assert!(leg.passed_end(5.0, 100.0));
        assert!(leg.passed_end(-50.0, 130.0));
        let c = leg
            .end_line_crossing(Point::new(2.0, 90.0), Point::new(6.0, 110.0))
            .unwrap();
        assert!((c.x - 4.0).abs() < 1e-12 && (c.y - 100.0).abs() < 1e-12);
        assert_eq!(
            leg.end_line_crossing(Point::new(2.0, 101.0), Point::new(6.0, 110.0)),
            None
        );
        // Foot at (0,30); 20 m on toward (0,100) is (0,50).
        assert_eq!(leg.lead_point(-7.0, 30.0, 20.0), Point::new(0.0, 50.0));
        // Behind the start: foot clamps to a.
        assert_eq!(leg.lead_point(0.0, -40.0, 10.0), Point::new(0.0, 10.0));
        assert_eq!(leg.lead_point(3.0, 30.0, 0.0), Point::new(0.0, 30.0));
        assert_eq!(leg.lead_point(3.0, 30.0, -1.0), Point::new(0.0, 100.0));
        // On the line with damper 20: factor 3, lead 10 -> 30.
        assert_eq!(
            leg.lead_point_damped(0.0, 30.0, 10.0, 20.0),
            Point::new(0.0, 60.0)
        );
        // Beyond the damper distance: no change.
        assert_eq!(
            leg.lead_point_damped(25.0, 30.0, 10.0, 20.0),
            Point::new(0.0, 40.0)
        );
        // Diagonal leg: foot of (10,0) on (0,0)->(20,20) is (5,5); lead sqrt(2)*5 gives (10,10).
        let d = Segment::from_xy(0.0, 0.0, 20.0, 20.0);
        let t = d.lead_point(10.0, 0.0, 50f64.sqrt());
        assert!((t.x - 10.0).abs() < 1e-12 && (t.y - 10.0).abs() < 1e-12);
    }
}
