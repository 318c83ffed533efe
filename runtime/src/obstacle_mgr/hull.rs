//! The convex hull of an obstacle's points, as pObstacleMgr builds it with MOOS-IvP's
//! `ConvexHullGenerator` (a Graham scan from the lowest point, rays within 0.1° merged to the
//! farthest point, a left-turn tolerance of 0.01 on the cross product, and "settling": while
//! the result is not convex, drop the vertex with the smallest cross product), plus the
//! thin boxes it gives for one or two distinct points.
//!
//! The vertex order matters (the hull is posted vertex by vertex): it is the scan's stack
//! from its top, so the last point scanned comes first and the root (lowest point) last.

use geometry::{Point, Polygon, angle_180, angle_360, project_point, relative_angle};

/// The cross product MOOS's `threePointXProduct` computes for the turn `p0 -> p1 -> p2`.
fn xproduct(p0: Point, p1: Point, p2: Point) -> f64 {
    let (ax, ay) = (p2.x - p0.x, p2.y - p0.y);
    let (bx, by) = (p1.x - p0.x, p1.y - p0.y);
    ax * by - bx * ay
}

/// A triangle 0.1 m around one point (bearings 30, 150 and 270).
fn one_point(a: Point) -> Polygon {
    let pts = [30.0, 150.0, 270.0]
        .iter()
        .map(|h| project_point(a.x, a.y, *h, 0.1))
        .collect();
    Polygon::new(pts)
}

/// A box around the segment `a`-`b`, one tenth of its length wide on each side.
fn two_points(a: Point, b: Point) -> Polygon {
    let dist = (a.x - b.x).hypot(a.y - b.y);
    if dist < 0.001 {
        return one_point(a);
    }
    let w = dist / 10.0;
    let ang = relative_angle(a.x, a.y, b.x, b.y);
    let (l, r) = (angle_360(ang + 90.0), angle_360(ang + 270.0));
    Polygon::new(vec![
        project_point(a.x, a.y, l, w),
        project_point(a.x, a.y, r, w),
        project_point(b.x, b.y, r, w),
        project_point(b.x, b.y, l, w),
    ])
}

/// Drops, while the polygon is not convex and has three vertices or more, the vertex whose
/// turn has the smallest cross product (the first such vertex on ties).
fn settle(poly: Polygon) -> Polygon {
    let mut pts = poly.vertices().to_vec();
    let mut poly = poly;
    while !poly.is_convex() && pts.len() >= 3 {
        let n = pts.len();
        let mut best = (0usize, 0.0f64);
        for i in 0..n {
            let prev = pts[(i + n - 1) % n];
            let next = pts[(i + 1) % n];
            let x = xproduct(prev, pts[i], next).abs();
            if i == 0 || x < best.1 {
                best = (i, x);
            }
        }
        pts.remove(best.0);
        poly = Polygon::new(pts.clone());
    }
    poly
}

/// The hull of `points` (empty polygon for no points).
///
/// ```
/// use geometry::Point;
/// let pts = [(0.0, 0.0), (10.0, 0.0), (10.0, 10.0), (0.0, 10.0), (5.0, 5.0)]
///     .map(|(x, y)| Point::new(x, y));
/// let h = runtime::obstacle_mgr::hull::convex_hull(&pts);
/// assert!(h.is_convex());
/// assert_eq!(h.len(), 4);
/// ```
pub fn convex_hull(points: &[Point]) -> Polygon {
    if points.is_empty() {
        return Polygon::default();
    }
    // The root: lowest y, then lowest x (the first such point).
    let mut ri = 0;
    for (i, p) in points.iter().enumerate().skip(1) {
        let r = points[ri];
        if p.y < r.y || (p.y == r.y && p.x < r.x) {
            ri = i;
        }
    }
    let root = points[ri];
    let mut rest: Vec<(Point, f64)> = points
        .iter()
        .enumerate()
        .filter(|(i, p)| *i != ri && (p.x != root.x || p.y != root.y))
        .map(|(_, p)| {
            let ang = angle_180(relative_angle(root.x, root.y, p.x, p.y));
            (Point::new(p.x, p.y), ang)
        })
        .collect();
    // Highest angle first; on equal angles the earlier point first.
    let mut sorted = Vec::with_capacity(rest.len());
    while !rest.is_empty() {
        let mut best = 0;
        for (i, (_, a)) in rest.iter().enumerate() {
            if *a > rest[best].1 {
                best = i;
            }
        }
        sorted.push(rest.remove(best));
    }
    // Rays within 0.1 degree of one another keep their point farthest from the root.
    let d = |p: &Point| (p.x - root.x).hypot(p.y - root.y);
    let mut merged: Vec<Point> = Vec::new();
    let mut queue: std::collections::VecDeque<(Point, f64)> = sorted.into();
    'outer: while let Some(mut a) = queue.pop_front() {
        loop {
            let Some(b) = queue.front().copied() else {
                merged.push(a.0);
                break 'outer;
            };
            if (a.1 - b.1).abs() > 0.1 {
                merged.push(a.0);
                break;
            }
            queue.pop_front();
            if d(&b.0) > d(&a.0) {
                a = b;
            }
            if queue.is_empty() {
                merged.push(a.0);
                break 'outer;
            }
        }
    }
    match merged.len() {
        0 => return one_point(root),
        1 => return two_points(root, merged[0]),
        _ => {}
    }
    // The scan; the stack's top is its last element here.
    let mut stack = vec![root, merged[0]];
    for &p in &merged[1..] {
        while stack.len() > 1 {
            let n = stack.len();
            let (top, below) = (stack[n - 1], stack[n - 2]);
            if xproduct(below, top, p) < -0.01 {
                break;
            }
            stack.pop();
        }
        stack.push(p);
    }
    match stack.len() {
        1 => one_point(stack[0]),
        2 => two_points(stack[1], stack[0]),
        _ => {
            let pts: Vec<Point> = stack.iter().rev().copied().collect();
            let poly = settle(Polygon::new(pts));
            if poly.len() == 2 {
                let v = poly.vertices();
                return two_points(v[0], v[1]);
            }
            poly
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn pts(v: &[(f64, f64)]) -> Vec<Point> {
        v.iter().map(|(x, y)| Point::new(*x, *y)).collect()
    }

    fn xy(p: &Polygon) -> Vec<(f64, f64)> {
        p.vertices().iter().map(|p| (p.x, p.y)).collect()
    }

    #[test]
    fn a_square_with_an_inner_point_is_its_corners_from_the_last_scanned() {
        // Root (0,0); rays from it: (0,10) at 0°, (10,10) at 45°, (5,5) at 45° (nearer:
        // merged away), (10,0) at 90°. Sorted highest first: (10,0), (10,10), (0,10). The
        // stack from its top: (0,10), (10,10), (10,0), root.
        let h = convex_hull(&pts(&[
            (0.0, 0.0),
            (5.0, 5.0),
            (10.0, 0.0),
            (10.0, 10.0),
            (0.0, 10.0),
        ]));
        assert_eq!(xy(&h), [(0.0, 10.0), (10.0, 10.0), (10.0, 0.0), (0.0, 0.0)]);
        assert!(h.is_convex());
    }

    #[test]
    fn one_point_is_a_small_triangle_and_two_a_thin_box() {
        let h = convex_hull(&pts(&[(3.0, 4.0), (3.0, 4.0)]));
        assert_eq!(h.len(), 3);
        let v = h.vertices();
        assert!((v[0].x - (3.0 + 0.1 * 30f64.to_radians().sin())).abs() < 1e-12);
        // Bearing 270 is due west.
        assert!((v[2].x - 2.9).abs() < 1e-12 && (v[2].y - 4.0).abs() < 1e-12);
        // Two points 10 m apart due north: a box 1 m either side.
        let h = convex_hull(&pts(&[(0.0, 0.0), (0.0, 10.0)]));
        assert_eq!(xy(&h), [(1.0, 0.0), (-1.0, 0.0), (-1.0, 10.0), (1.0, 10.0)]);
    }

    #[test]
    fn collinear_points_give_the_box_of_their_ends() {
        // (0,0), (5,5), (10,10) on one ray: merged to the farthest, a two-point hull.
        let h = convex_hull(&pts(&[(5.0, 5.0), (0.0, 0.0), (10.0, 10.0)]));
        assert_eq!(h.len(), 4);
        assert!(h.is_convex());
        assert!(h.contains(5.0, 5.0));
    }
}
