//! Angle helpers with the MOOS-IvP conventions (compass headings in degrees, clockwise from
//! north; x east, y north).

use std::f64::consts::PI;

/// `[0, 360)` and `(-180, 180]` wrapping: the workspace's one definition of each
/// (`geometry::angle_360`, `geometry::angle_180`; MOOS `angle360`, `angle180`).
pub use geometry::{angle_180 as angle180, angle_360 as angle360};

/// Wraps an angle in radians into `[-pi, pi]`, as MOOS-IvP's `radAngleWrap`.
pub fn rad_angle_wrap(rad: f64) -> f64 {
    if (-PI..=PI).contains(&rad) {
        rad
    } else {
        let mut r = (rad + PI).rem_euclid(2.0 * PI) - PI;
        if r < -PI {
            r += 2.0 * PI;
        }
        r
    }
}

/// Compass heading (degrees) to the mathematical angle in radians (counter-clockwise from
/// east), wrapped into `[-pi, pi]`, as MOOS-IvP's `headingToRadians`.
pub fn heading_to_radians(heading_deg: f64) -> f64 {
    rad_angle_wrap((90.0 - heading_deg).to_radians())
}

/// Compass bearing in degrees `[0, 360)` from `(x0, y0)` to `(x1, y1)`; 0 when the points are
/// equal (MOOS-IvP's `relAng`).
pub fn rel_ang(x0: f64, y0: f64, x1: f64, y1: f64) -> f64 {
    if x0 == x1 && y0 == y1 {
        return 0.0;
    }
    angle360((x1 - x0).atan2(y1 - y0).to_degrees())
}

/// Signed smallest difference `a - b` in degrees, in `(-180, 180]`.
pub fn heading_diff(a: f64, b: f64) -> f64 {
    angle180(a - b)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn wraps() {
        assert_eq!(angle360(360.0), 0.0);
        assert_eq!(angle360(-1e-15), 0.0);
        assert_eq!(angle180(180.0), 180.0);
        assert_eq!(angle180(181.0), -179.0);
        assert!((heading_to_radians(0.0) - PI / 2.0).abs() < 1e-12);
        assert!((heading_to_radians(270.0) + PI).abs() < 1e-12);
        assert!((heading_to_radians(180.0) + PI / 2.0).abs() < 1e-12);
        assert_eq!(rel_ang(0.0, 0.0, 1.0, 0.0), 90.0);
        assert_eq!(rel_ang(0.0, 0.0, 0.0, -1.0), 180.0);
        assert_eq!(rel_ang(1.0, 1.0, 1.0, 1.0), 0.0);
    }
}
