//! The geometry of the obstacle behaviours, after the definitions of MOOS-IvP's `GeomUtils`
//! and `AngleUtils` (`polyRayCPA`, `segRayCPA`, `distPointToRay`, `bearingMinMaxToPoly`,
//! `polyAft`, `relBearing`, `XYPolygon::dist_to_poly`).

use geometry::{Point, Polygon, angle_360, relative_angle};

/// The bearing of `(x, y)` from ownship relative to its heading, in `[0, 360)`.
///
/// ```
/// use behaviors::obstacle::geom::rel_bearing;
/// assert_eq!(rel_bearing(0.0, 0.0, 90.0, 0.0, 10.0), 270.0);
/// ```
pub fn rel_bearing(osx: f64, osy: f64, osh: f64, x: f64, y: f64) -> f64 {
    angle_360(relative_angle(osx, osy, x, y) - osh)
}

fn dist_point_seg(a: Point, b: Point, x: f64, y: f64) -> f64 {
    geometry::segment::dist_point_to_segment(a.x, a.y, b.x, b.y, x, y)
}

/// The distance from `(x, y)` to the polygon's boundary (inside too); -1 when empty.
pub fn dist_to_poly(p: &Polygon, x: f64, y: f64) -> f64 {
    let v = p.vertices();
    match v.len() {
        0 => -1.0,
        1 => (x - v[0].x).hypot(y - v[0].y),
        2 => dist_point_seg(v[0], v[1], x, y),
        n => (0..n)
            .map(|i| dist_point_seg(v[i], v[(i + 1) % n], x, y))
            .fold(f64::INFINITY, f64::min),
    }
}

/// The unit vector of a compass heading.
fn dir(hdg: f64) -> (f64, f64) {
    let r = hdg.to_radians();
    (r.sin(), r.cos())
}

/// The distance from point `p` to the ray from `(rx, ry)` along `hdg`: to its foot when
/// the point is ahead of the ray's base, else to the base.
pub fn dist_point_to_ray(px: f64, py: f64, rx: f64, ry: f64, hdg: f64) -> f64 {
    let (dx, dy) = dir(hdg);
    let t = (px - rx) * dx + (py - ry) * dy;
    if t <= 0.0 {
        return (px - rx).hypot(py - ry);
    }
    let (fx, fy) = (rx + t * dx, ry + t * dy);
    (px - fx).hypot(py - fy)
}

/// Whether the ray from `(rx, ry)` along `hdg` meets the segment `a`-`b`.
pub fn ray_crosses_seg(rx: f64, ry: f64, hdg: f64, a: Point, b: Point) -> bool {
    let (dx, dy) = dir(hdg);
    let (ex, ey) = (b.x - a.x, b.y - a.y);
    let cross = |ux: f64, uy: f64, vx: f64, vy: f64| ux * vy - uy * vx;
    let denom = cross(dx, dy, ex, ey);
    let (wx, wy) = (a.x - rx, a.y - ry);
    if denom.abs() < 1e-12 {
        // Parallel: crossing only when collinear and some of the segment is ahead.
        if cross(wx, wy, dx, dy).abs() > 1e-9 {
            return false;
        }
        let ta = wx * dx + wy * dy;
        let tb = (b.x - rx) * dx + (b.y - ry) * dy;
        return ta >= 0.0 || tb >= 0.0;
    }
    let t = cross(wx, wy, ex, ey) / denom;
    let u = cross(wx, wy, dx, dy) / denom;
    t >= 0.0 && (0.0..=1.0).contains(&u)
}

/// The closest approach of the ray from `(rx, ry)` along `hdg` to a convex polygon
/// (MOOS `polyRayCPA`): 0 when the ray meets an edge, else the least, over the edges, of
/// the edge ends' distances to the ray and the ray base's distance to the edge; -1 for a
/// polygon that is not convex.
///
/// ```
/// use behaviors::obstacle::geom::ray_cpa;
/// use geometry::{Point, Polygon};
/// let sq = Polygon::new(vec![Point::new(-5.0, 20.0), Point::new(-5.0, 30.0), Point::new(5.0, 30.0), Point::new(5.0, 20.0)]);
/// assert_eq!(ray_cpa(0.0, 0.0, 0.0, &sq), 0.0);
/// // East: the bottom edge passes 20 m from the ray's base.
/// assert_eq!(ray_cpa(0.0, 0.0, 90.0, &sq), 20.0);
/// assert!((ray_cpa(15.0, 0.0, 0.0, &sq) - 10.0).abs() < 1e-12);
/// ```
pub fn ray_cpa(rx: f64, ry: f64, hdg: f64, poly: &Polygon) -> f64 {
    if !poly.is_convex() {
        return -1.0;
    }
    let v = poly.vertices();
    let n = v.len();
    let edges = || (0..n).map(|i| (v[i], v[(i + 1) % n]));
    if edges().any(|(a, b)| ray_crosses_seg(rx, ry, hdg, a, b)) {
        return 0.0;
    }
    edges()
        .map(|(a, b)| {
            let d1 = dist_point_to_ray(a.x, a.y, rx, ry, hdg);
            let d2 = dist_point_to_ray(b.x, b.y, rx, ry, hdg);
            let d3 = dist_point_seg(a, b, rx, ry);
            d1.min(d2).min(d3)
        })
        .fold(f64::INFINITY, f64::min)
}

/// The two bearings from `(osx, osy)` bounding a polygon (MOOS `bearingMinMaxToPoly`):
/// `(min, max)` of the vertices' bearings, or when they wrap through north, the least above
/// 180 and the greatest at or below 180 (so `min > max`); `None` for an empty polygon or a
/// point inside a convex one.
pub fn bearing_min_max(osx: f64, osy: f64, poly: &Polygon) -> Option<(f64, f64)> {
    bearing_min_max_x(osx, osy, poly).map(|b| (b.0, b.1))
}

/// [`bearing_min_max`] with the distances from `(osx, osy)` to the vertices at the two
/// bearings: `(min, max, min_dist, max_dist)` (MOOS `bearingMinMaxToPolyX`).
pub fn bearing_min_max_x(osx: f64, osy: f64, poly: &Polygon) -> Option<(f64, f64, f64, f64)> {
    let v = poly.vertices();
    if v.is_empty() || (poly.is_convex() && poly.contains(osx, osy)) {
        return None;
    }
    let angles: Vec<f64> = v
        .iter()
        .map(|p| relative_angle(osx, osy, p.x, p.y))
        .collect();
    let mut q = [false; 4];
    for a in &angles {
        let k = if (0.0..90.0).contains(a) {
            0
        } else if (90.0..180.0).contains(a) {
            1
        } else if (180.0..270.0).contains(a) {
            2
        } else {
            3
        };
        q[k] = true;
    }
    let closest_angle = || {
        let c = poly.closest_boundary_point(osx, osy).unwrap_or_default();
        relative_angle(osx, osy, c.x, c.y)
    };
    let wrap = match q {
        [true, false, false, true] | [true, false, true, true] | [true, true, false, true] => true,
        [true, false, true, false] => {
            let a = closest_angle();
            !(a > 45.0 && a <= 225.0)
        }
        [false, true, false, true] => {
            let a = closest_angle();
            !(a > 135.0 && a <= 315.0)
        }
        _ => false,
    };
    let (mut bmin, mut bmax) = (360.0, 0.0);
    let (mut imin, mut imax) = (0, 0);
    for (i, &a) in angles.iter().enumerate() {
        if !wrap {
            if a < bmin {
                (bmin, imin) = (a, i);
            }
            if a > bmax {
                (bmax, imax) = (a, i);
            }
        } else if a > 180.0 && a < bmin {
            (bmin, imin) = (a, i);
        } else if a <= 180.0 && a > bmax {
            (bmax, imax) = (a, i);
        }
    }
    let d = |i: usize| (osx - v[i].x).hypot(osy - v[i].y);
    Some((bmin, bmax, d(imin), d(imax)))
}

/// Every vertex of the polygon lies more than `xbng` degrees abaft the beam (relative
/// bearing in `(90 + xbng, 270 − xbng)`, `xbng` clipped to `[-90, 90]`); false when empty
/// (MOOS `polyAft`).
pub fn poly_aft(osx: f64, osy: f64, osh: f64, poly: &Polygon, xbng: f64) -> bool {
    let v = poly.vertices();
    if v.is_empty() {
        return false;
    }
    let x = xbng.clamp(-90.0, 90.0);
    v.iter().all(|p| {
        let r = rel_bearing(osx, osy, osh, p.x, p.y);
        r > 90.0 + x && r < 270.0 - x
    })
}

/// The polygon grown by `dist` (MOOS `XYPolyExpander::getBufferPoly` with corners every
/// `rdegs` degrees); the polygon itself for a distance of 0 or less.
pub fn buffer(p: &Polygon, dist: f64, rdegs: f64) -> Option<Polygon> {
    if !p.is_convex() {
        return None;
    }
    if dist <= 0.0 {
        return Some(p.clone());
    }
    p.buffered(dist, rdegs)
}

/// The distance from `(x, y)` to the polygon's vertices taken as an open path (MOOS
/// `XYSegList::dist_to_point`: the closing edge is not counted); 0 when empty.
pub fn dist_to_open_path(p: &Polygon, x: f64, y: f64) -> f64 {
    let v = p.vertices();
    match v.len() {
        0 => 0.0,
        1 => (x - v[0].x).hypot(y - v[0].y),
        n => (0..n - 1)
            .map(|i| dist_point_seg(v[i], v[i + 1], x, y))
            .fold(f64::INFINITY, f64::min),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn square(x0: f64, y0: f64, x1: f64, y1: f64) -> Polygon {
        Polygon::new(vec![
            Point::new(x0, y0),
            Point::new(x0, y1),
            Point::new(x1, y1),
            Point::new(x1, y0),
        ])
    }

    #[test]
    fn bearings_bound_the_polygon_and_wrap_through_north() {
        let sq = square(-5.0, 20.0, 5.0, 30.0);
        // Vertices at bearings 14.04 (5,20), 9.46 (5,30), 350.54 and 345.96: quadrants 1
        // and 4 wrap.
        let (bmin, bmax) = bearing_min_max(0.0, 0.0, &sq).unwrap();
        assert!((bmin - (360.0 - 5f64.atan2(20.0).to_degrees())).abs() < 1e-9);
        assert!((bmax - 5f64.atan2(20.0).to_degrees()).abs() < 1e-9);
        let sq = square(20.0, -5.0, 30.0, 5.0);
        let (bmin, bmax) = bearing_min_max(0.0, 0.0, &sq).unwrap();
        assert!(bmin < bmax && (bmin - (90.0 - 5f64.atan2(20.0).to_degrees())).abs() < 1e-9);
        assert!(bearing_min_max(25.0, 0.0, &sq).is_none());
    }

    #[test]
    fn aft_means_wholly_behind_the_beam_by_the_margin() {
        let sq = square(-5.0, -30.0, 5.0, -20.0);
        assert!(poly_aft(0.0, 0.0, 0.0, &sq, 20.0));
        // Heading 90: the square spans relative bearings 76..104, abeam.
        assert!(!poly_aft(0.0, 0.0, 90.0, &sq, 20.0));
        // Heading 60: 106..134, abaft the beam but not by 20 degrees everywhere.
        assert!(poly_aft(0.0, 0.0, 60.0, &sq, 0.0));
        assert!(!poly_aft(0.0, 0.0, 60.0, &sq, 20.0));
        assert!(!poly_aft(0.0, 0.0, 180.0, &sq, 20.0));
        assert!(!poly_aft(0.0, 0.0, 0.0, &Polygon::default(), 0.0));
    }
}
