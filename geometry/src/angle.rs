//! Angle helpers in MOOS-IvP conventions (the `AngleUtils` / `GeomUtils` sense).
//!
//! Compass degrees: 0 = north (+y), 90 = east (+x), clockwise positive.

use crate::point::Point;

/// Normalises an angle in degrees to `[0, 360)`.
///
/// Unlike MOOS's loop-based `angle360`, tiny negative inputs that would round to exactly 360
/// come back as 0, so the result is always strictly below 360. NaN stays NaN.
///
/// ```
/// assert_eq!(geometry::angle_360(-90.0), 270.0);
/// assert_eq!(geometry::angle_360(720.0), 0.0);
/// ```
pub fn angle_360(deg: f64) -> f64 {
    if (0.0..360.0).contains(&deg) {
        return deg;
    }
    let r = deg.rem_euclid(360.0);
    if r >= 360.0 { 0.0 } else { r }
}

/// Normalises an angle in degrees to `(-180, 180]` (MOOS `angle180`).
///
/// ```
/// assert_eq!(geometry::angle_180(270.0), -90.0);
/// assert_eq!(geometry::angle_180(-180.0), 180.0);
/// ```
pub fn angle_180(deg: f64) -> f64 {
    let a = angle_360(deg);
    if a > 180.0 { a - 360.0 } else { a }
}

/// Absolute difference between two headings, in `[0, 180]`.
///
/// ```
/// assert_eq!(geometry::angle::angle_diff(350.0, 10.0), 20.0);
/// ```
pub fn angle_diff(a: f64, b: f64) -> f64 {
    // |a - b| is exactly symmetric and `%` is exact, so the result is symmetric in a and b.
    let r = (a - b).abs() % 360.0;
    if r > 180.0 { 360.0 - r } else { r }
}

/// Compass bearing from `(x0, y0)` to `(x1, y1)` in `[0, 360)` (MOOS `relAng`).
///
/// Returns 0 when the points coincide; axis-aligned directions are exact (0, 90, 180, 270).
///
/// ```
/// assert_eq!(geometry::relative_angle(0.0, 0.0, 10.0, 10.0), 45.0);
/// assert_eq!(geometry::relative_angle(0.0, 0.0, -1.0, 0.0), 270.0);
/// ```
pub fn relative_angle(x0: f64, y0: f64, x1: f64, y1: f64) -> f64 {
    let dx = x1 - x0;
    let dy = y1 - y0;
    if dx == 0.0 && dy == 0.0 {
        return 0.0;
    }
    if dx == 0.0 {
        return if dy > 0.0 { 0.0 } else { 180.0 };
    }
    if dy == 0.0 {
        return if dx > 0.0 { 90.0 } else { 270.0 };
    }
    if dx.abs() == dy.abs() {
        // Exact diagonals (atan2 would give 44.99999999999999 in some quadrants).
        return match (dx > 0.0, dy > 0.0) {
            (true, true) => 45.0,
            (true, false) => 135.0,
            (false, false) => 225.0,
            (false, true) => 315.0,
        };
    }
    angle_360(dx.atan2(dy).to_degrees())
}

/// Projects `(x, y)` by `dist` along compass heading `heading_deg` (MOOS `projectPoint`).
///
/// `x' = x + sin(h)·d`, `y' = y + cos(h)·d`, with exact results at 0, 90, 180 and 270 degrees.
///
/// ```
/// let p = geometry::project_point(0.0, 0.0, 90.0, 10.0);
/// assert_eq!((p.x, p.y), (10.0, 0.0));
/// ```
pub fn project_point(x: f64, y: f64, heading_deg: f64, dist: f64) -> Point {
    let h = angle_360(heading_deg);
    let (dx, dy) = if h == 0.0 {
        (0.0, dist)
    } else if h == 90.0 {
        (dist, 0.0)
    } else if h == 180.0 {
        (0.0, -dist)
    } else if h == 270.0 {
        (-dist, 0.0)
    } else {
        let r = h.to_radians();
        (r.sin() * dist, r.cos() * dist)
    };
    Point::new(x + dx, y + dy)
}

/// Signed turn from segment `1→2` to segment `2→3` in `(-180, 180]`; positive = turn right
/// (clockwise). Zero if either segment is degenerate (MOOS `segmentAngle`).
pub fn turn_angle(x1: f64, y1: f64, x2: f64, y2: f64, x3: f64, y3: f64) -> f64 {
    if (x1 == x2 && y1 == y2) || (x2 == x3 && y2 == y3) {
        return 0.0;
    }
    angle_180(relative_angle(x2, y2, x3, y3) - relative_angle(x1, y1, x2, y2))
}

/// Angle at vertex `b` between the rays `b→a` and `b→c`, in `[0, 180]`.
///
/// This is the waypoint `capture_line` test: the vehicle at `c` has passed waypoint `b` (coming
/// from `a`) once this angle is at least 90 degrees. Zero if `a` or `c` coincides with `b`.
///
/// ```
/// use geometry::angle::angle_at_vertex;
/// assert_eq!(angle_at_vertex(0.0, 0.0, 0.0, 10.0, 0.0, 20.0), 180.0);
/// assert_eq!(angle_at_vertex(0.0, 0.0, 0.0, 10.0, 5.0, 10.0), 90.0);
/// ```
pub fn angle_at_vertex(ax: f64, ay: f64, bx: f64, by: f64, cx: f64, cy: f64) -> f64 {
    if (ax == bx && ay == by) || (cx == bx && cy == by) {
        return 0.0;
    }
    angle_diff(
        relative_angle(bx, by, ax, ay),
        relative_angle(bx, by, cx, cy),
    )
}

/// Converts a compass heading (degrees) to a math angle (radians, counter-clockwise from +x),
/// wrapped to `(-π, π]`.
pub fn heading_to_math_rad(heading_deg: f64) -> f64 {
    angle_180(90.0 - heading_deg).to_radians()
}

/// Converts a math angle (radians, counter-clockwise from +x) to a compass heading in `[0, 360)`.
pub fn math_rad_to_heading(rad: f64) -> f64 {
    angle_360(90.0 - rad.to_degrees())
}

/// True if compass angle `q` lies within the smaller arc between `a` and `b` (inclusive).
/// If the two bounds are exactly opposite every angle is contained (MOOS `containsAngle`).
pub fn contains_angle(a: f64, b: f64, q: f64) -> bool {
    let (mut lo, mut hi) = (angle_360(a), angle_360(b));
    let q = angle_360(q);
    if lo == hi {
        return q == lo;
    }
    if (hi - lo).abs() == 180.0 {
        return true;
    }
    if lo > hi {
        std::mem::swap(&mut lo, &mut hi);
    }
    if hi - lo > 180.0 {
        q >= hi || q <= lo
    } else {
        q >= lo && q <= hi
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn angle_360_seam() {
        assert_eq!(angle_360(0.0), 0.0);
        assert_eq!(angle_360(360.0), 0.0);
        assert_eq!(angle_360(-360.0), 0.0);
        assert_eq!(angle_360(359.5), 359.5);
        assert_eq!(angle_360(-0.5), 359.5);
        assert_eq!(angle_360(725.0), 5.0);
        // -1e-20 + 360 rounds to 360.0 in f64; we must still stay below 360.
        assert_eq!(angle_360(-1e-20), 0.0);
        assert!(angle_360(f64::NAN).is_nan());
    }

    #[test]
    fn angle_180_range() {
        assert_eq!(angle_180(180.0), 180.0);
        assert_eq!(angle_180(-180.0), 180.0);
        assert_eq!(angle_180(181.0), -179.0);
        assert_eq!(angle_180(-179.0), -179.0);
        assert_eq!(angle_180(359.0), -1.0);
        assert_eq!(angle_180(0.0), 0.0);
    }

    #[test]
    fn relative_angle_quadrants() {
        assert_eq!(relative_angle(0.0, 0.0, 0.0, 5.0), 0.0);
        assert_eq!(relative_angle(0.0, 0.0, 5.0, 0.0), 90.0);
        assert_eq!(relative_angle(0.0, 0.0, 0.0, -5.0), 180.0);
        assert_eq!(relative_angle(0.0, 0.0, -5.0, 0.0), 270.0);
        assert_eq!(relative_angle(1.0, 1.0, 1.0, 1.0), 0.0);
        assert_eq!(relative_angle(0.0, 0.0, 3.0, 3.0), 45.0);
        assert_eq!(relative_angle(0.0, 0.0, 3.0, -3.0), 135.0);
        assert_eq!(relative_angle(0.0, 0.0, -3.0, -3.0), 225.0);
        assert_eq!(relative_angle(0.0, 0.0, -3.0, 3.0), 315.0);
        // atan(1/sqrt(3)) = 30 degrees east of north.
        let a = relative_angle(0.0, 0.0, 1.0, 3f64.sqrt());
        assert!((a - 30.0).abs() < 1e-12, "{a}");
        // Just west of north sits just below the seam.
        let a = relative_angle(0.0, 0.0, -1e-3, 1.0);
        assert!(a > 359.9 && a < 360.0, "{a}");
        let a = relative_angle(0.0, 0.0, 1e-3, 1.0);
        assert!(a > 0.0 && a < 0.1, "{a}");
    }

    #[test]
    fn project_point_exact_on_axes() {
        let p = project_point(1.0, 2.0, 0.0, 10.0);
        assert_eq!((p.x, p.y), (1.0, 12.0));
        let p = project_point(1.0, 2.0, 360.0, 10.0);
        assert_eq!((p.x, p.y), (1.0, 12.0));
        let p = project_point(1.0, 2.0, -90.0, 10.0);
        assert_eq!((p.x, p.y), (-9.0, 2.0));
        let p = project_point(1.0, 2.0, 180.0, 10.0);
        assert_eq!((p.x, p.y), (1.0, -8.0));
        // 30 degrees: x = sin 30 * 10 = 5, y = cos 30 * 10 = 8.660254...
        let p = project_point(0.0, 0.0, 30.0, 10.0);
        assert!((p.x - 5.0).abs() < 1e-12 && (p.y - 8.660_254_037_844_386).abs() < 1e-12);
    }

    #[test]
    fn turn_and_vertex_angles() {
        // North then east: a right turn of 90.
        assert_eq!(turn_angle(0.0, 0.0, 0.0, 10.0, 10.0, 10.0), 90.0);
        assert_eq!(turn_angle(0.0, 0.0, 0.0, 10.0, -10.0, 10.0), -90.0);
        assert_eq!(turn_angle(0.0, 0.0, 0.0, 10.0, 0.0, 0.0), 180.0);
        assert_eq!(angle_at_vertex(0.0, 0.0, 0.0, 10.0, 0.0, 0.0), 0.0);
        assert_eq!(angle_at_vertex(0.0, 0.0, 0.0, 10.0, 3.0, 13.0), 135.0);
        assert_eq!(angle_diff(1.0, 359.0), 2.0);
        assert_eq!(angle_diff(90.0, 270.0), 180.0);
        // Found by proptest: must be exactly symmetric.
        assert_eq!(
            angle_diff(0.0, 53.07843368622421),
            angle_diff(53.07843368622421, 0.0)
        );
        assert_eq!(angle_diff(-710.0, 10.0), 0.0);
    }

    #[test]
    fn heading_math_conversions() {
        assert!((heading_to_math_rad(0.0) - std::f64::consts::FRAC_PI_2).abs() < 1e-15);
        assert!((heading_to_math_rad(90.0)).abs() < 1e-15);
        assert!((math_rad_to_heading(std::f64::consts::PI) - 270.0).abs() < 1e-12);
    }

    #[test]
    fn contains_angle_wraps() {
        assert!(contains_angle(350.0, 10.0, 0.0));
        assert!(contains_angle(350.0, 10.0, 355.0));
        assert!(!contains_angle(350.0, 10.0, 20.0));
        assert!(contains_angle(10.0, 50.0, 30.0));
        assert!(contains_angle(0.0, 180.0, 271.0));
        assert!(contains_angle(5.0, 5.0, 5.0));
        assert!(!contains_angle(5.0, 5.0, 6.0));
    }
}
