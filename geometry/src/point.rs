//! [`Point`]: an x/y (and optional z) position on the local grid, and snapping.

use crate::angle::{project_point, relative_angle};

/// A position in local grid metres: `x` east, `y` north, `z` depth/height.
///
/// `z` is 0 when unused; specs only write it when it is non-zero (as MOOS-IvP does).
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct Point {
    /// East, metres.
    pub x: f64,
    /// North, metres.
    pub y: f64,
    /// Optional third coordinate (0 = unset).
    pub z: f64,
}

impl Point {
    /// A 2-D point (`z = 0`).
    pub const fn new(x: f64, y: f64) -> Self {
        Point { x, y, z: 0.0 }
    }

    /// A point with a `z` value.
    pub const fn new_3d(x: f64, y: f64, z: f64) -> Self {
        Point { x, y, z }
    }

    /// Horizontal distance to `other` (z ignored).
    ///
    /// ```
    /// use geometry::Point;
    /// assert_eq!(Point::new(0.0, 0.0).dist(&Point::new(3.0, 4.0)), 5.0);
    /// ```
    pub fn dist(&self, other: &Point) -> f64 {
        dist(self.x, self.y, other.x, other.y)
    }

    /// Compass bearing from `self` to `other` in `[0, 360)`.
    pub fn bearing_to(&self, other: &Point) -> f64 {
        relative_angle(self.x, self.y, other.x, other.y)
    }

    /// The point `dist` metres away along compass heading `heading_deg`; `z` is kept.
    pub fn project(&self, heading_deg: f64, dist: f64) -> Point {
        let p = project_point(self.x, self.y, heading_deg, dist);
        Point::new_3d(p.x, p.y, self.z)
    }

    /// `x` and `y` rounded to the nearest multiple of `step` (see [`snap_to_step`]); `z` kept.
    pub fn snapped(&self, step: f64) -> Point {
        Point::new_3d(
            snap_to_step(self.x, step),
            snap_to_step(self.y, step),
            self.z,
        )
    }
}

/// Horizontal distance between `(x0, y0)` and `(x1, y1)`.
pub fn dist(x0: f64, y0: f64, x1: f64, y1: f64) -> f64 {
    (x1 - x0).hypot(y1 - y0)
}

/// Rounds `v` to the nearest multiple of `step`, ties away from zero (MOOS `snapToStep`).
/// A `step <= 0` (or NaN) returns `v` unchanged.
///
/// ```
/// use geometry::point::snap_to_step;
/// assert_eq!(snap_to_step(27.654, 1.0), 28.0);
/// assert_eq!(snap_to_step(-2.5, 1.0), -3.0);
/// assert_eq!(snap_to_step(6.18, 0.5), 6.0);
/// ```
pub fn snap_to_step(v: f64, step: f64) -> f64 {
    if step.is_nan() || step <= 0.0 {
        return v;
    }
    let q = v / step;
    let n = if q < 0.0 {
        (q - 0.5).trunc()
    } else {
        (q + 0.5).trunc()
    };
    n * step
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn snapping_rounds_half_away_from_zero() {
        assert_eq!(snap_to_step(2.5, 1.0), 3.0);
        assert_eq!(snap_to_step(2.49, 1.0), 2.0);
        assert_eq!(snap_to_step(-61.522, 1.0), -62.0);
        assert_eq!(snap_to_step(5.0, 0.0), 5.0);
        assert_eq!(snap_to_step(5.0, -1.0), 5.0);
        assert_eq!(snap_to_step(12.0, 5.0), 10.0);
        assert_eq!(snap_to_step(12.5, 5.0), 15.0);
    }

    #[test]
    fn point_project_keeps_z_and_bearing() {
        let p = Point::new_3d(1.0, 1.0, 7.0).project(180.0, 2.0);
        assert_eq!(p, Point::new_3d(1.0, -1.0, 7.0));
        assert_eq!(
            Point::new(0.0, 0.0).bearing_to(&Point::new(0.0, -3.0)),
            180.0
        );
        assert_eq!(Point::new(0.4, -0.6).snapped(1.0), Point::new(0.0, -1.0));
    }
}
