//! Local grid against independently computed values: geodesics from geographiclib-rs and the
//! classical Transverse Mercator point-scale and grid-convergence series.

use geographiclib_rs::{DirectGeodesic, Geodesic, InverseGeodesic};
use proptest::prelude::*;
use vehicle::geodesy::{LocalGrid, utm_zone, zone_central_meridian};

const A: f64 = 6_378_137.0;
const F: f64 = 1.0 / 298.257_223_563;
const K0: f64 = 0.9996;

fn e2() -> f64 {
    F * (2.0 - F)
}

/// Radii of curvature (meridian rho, prime vertical nu) at latitude `lat` (degrees).
fn radii(lat: f64) -> (f64, f64) {
    let s = lat.to_radians().sin();
    let w = 1.0 - e2() * s * s;
    (A * (1.0 - e2()) / w.powf(1.5), A / w.sqrt())
}

/// Grid easting from the central meridian, to third order in the longitude difference
/// (accurate to metres; the point scale below depends on it only weakly).
fn approx_easting(lat: f64, dlon_deg: f64) -> f64 {
    let (rho, nu) = radii(lat);
    let (c, t) = (lat.to_radians().cos(), lat.to_radians().tan());
    let eta2 = nu / rho - 1.0;
    let l = dlon_deg.to_radians();
    K0 * nu * c * l * (1.0 + (l * c).powi(2) / 6.0 * (1.0 - t * t + eta2))
}

/// TM point scale factor: k0 (1 + q²/2 + q⁴/24), q = E/(k0 sqrt(rho nu)).
fn point_scale(lat: f64, lon: f64, cm: f64) -> f64 {
    let (rho, nu) = radii(lat);
    let q = approx_easting(lat, lon - cm) / (K0 * (rho * nu).sqrt());
    K0 * (1.0 + q * q / 2.0 + q.powi(4) / 24.0)
}

/// Grid convergence (radians): angle from grid north to true north.
fn convergence(lat: f64, lon: f64, cm: f64) -> f64 {
    let (rho, nu) = radii(lat);
    let eta2 = nu / rho - 1.0;
    let (s, c, t) = (
        lat.to_radians().sin(),
        lat.to_radians().cos(),
        lat.to_radians().tan(),
    );
    let l = (lon - cm).to_radians();
    l * s
        * (1.0
            + (l * c).powi(2) / 3.0 * (1.0 + 3.0 * eta2 + 2.0 * eta2 * eta2)
            + (l * c).powi(4) / 15.0 * (2.0 - t * t))
}

/// Expected local (x, y) of the point at geodesic distance `s` and azimuth `azi` from the
/// origin: grid length = s × mean scale (Simpson over the line), grid bearing = azimuth at the
/// geodesic's midpoint minus the convergence there.
fn expected_local(
    g: &Geodesic,
    lat0: f64,
    lon0: f64,
    azi: f64,
    s: f64,
    cm: f64,
) -> (f64, f64, f64, f64) {
    let (lat1, lon1): (f64, f64) = g.direct(lat0, lon0, azi, s);
    let (latm, lonm, azim): (f64, f64, f64) = g.direct(lat0, lon0, azi, s / 2.0);
    let k = (point_scale(lat0, lon0, cm)
        + 4.0 * point_scale(latm, lonm, cm)
        + point_scale(lat1, lon1, cm))
        / 6.0;
    let bearing = azim.to_radians() - convergence(latm, lonm, cm);
    let d = s * k;
    (d * bearing.sin(), d * bearing.cos(), lat1, lon1)
}

fn check_origin(lat0: f64, lon0: f64, expect_cross_zone: bool) {
    let g = Geodesic::wgs84();
    let grid = LocalGrid::new(lat0, lon0).unwrap();
    let cm = zone_central_meridian(grid.zone());
    let mut crossed = false;
    let mut worst: f64 = 0.0;
    for s in [10.0, 250.0, 1_000.0, 4_000.0, 10_000.0] {
        for i in 0..24 {
            let azi = f64::from(i) * 15.0 + 7.5;
            let (ex, ey, lat, lon) = expected_local(&g, lat0, lon0, azi, s, cm);
            crossed |= utm_zone(lat, lon) != grid.zone();
            let (x, y) = grid.to_local(lat, lon).unwrap();
            let err = (x - ex).hypot(y - ey);
            worst = worst.max(err);
            assert!(
                err < 0.01,
                "origin ({lat0},{lon0}) azi {azi} s {s}: got ({x},{y}) expected ({ex},{ey})"
            );
            // Lengths alone, straight from the geodesic inverse.
            let (s12, _, _, _): (f64, f64, f64, f64) = g.inverse(lat0, lon0, lat, lon);
            let k_mid = point_scale((lat0 + lat) / 2.0, (lon0 + lon) / 2.0, cm);
            assert!(((x.hypot(y) / k_mid) - s12).abs() < 0.01 + 1e-6 * s12);
            // And back.
            let (blat, blon) = grid.to_latlon(x, y).unwrap();
            let (back, _, _, _): (f64, f64, f64, f64) = g.inverse(lat, lon, blat, blon);
            assert!(back < 0.001, "round trip off by {back} m");
        }
    }
    assert_eq!(
        crossed, expect_cross_zone,
        "zone crossing expectation for ({lat0},{lon0})"
    );
    eprintln!(
        "origin ({lat0}, {lon0}) zone {}: worst error {:.2} mm",
        grid.zone(),
        worst * 1000.0
    );
}

#[test]
fn equator_within_1cm_up_to_10km() {
    check_origin(0.0, -2.0, false);
    check_origin(0.03, 100.9, false);
}

#[test]
fn sixty_north_within_1cm_up_to_10km() {
    check_origin(60.0, 25.0, false);
    check_origin(60.17, 24.94, false);
}

#[test]
fn across_a_utm_zone_boundary_within_1cm() {
    // Origin 0.01 degree west of 6 E (zone 31); points up to 10 km away fall in zone 32.
    check_origin(45.0, 5.99, true);
    // And at 60 N across 24 E (zone 34 | 35).
    check_origin(60.0, 23.95, true);
    // Just south of the equator across 0 E.
    check_origin(-0.02, -0.03, true);
}

#[test]
fn crossing_the_boundary_is_continuous() {
    // Stepping east across the zone boundary, x grows smoothly (MOOS-IvP jumps by ~hundreds of km).
    let grid = LocalGrid::new(43.0, 5.995).unwrap();
    let mut prev = grid.to_local(43.0, 5.995).unwrap().0;
    for i in 1..=20 {
        let lon = 5.995 + f64::from(i) * 0.0005;
        let x = grid.to_local(43.0, lon).unwrap().0;
        let step = x - prev;
        assert!(step > 40.0 && step < 41.0, "step {step} m at lon {lon}");
        prev = x;
    }
}

#[test]
fn matches_moos_inside_the_origin_zone() {
    // Inside the origin's zone the grid is plain UTM differences: x from the central
    // meridian is the UTM easting minus 500 km, and the origin at the central meridian on the
    // equator has UTM (500000, 0).
    let grid = LocalGrid::new(0.0, -3.0).unwrap();
    let (x, y) = grid.to_local(0.0, -3.0).unwrap();
    assert!(x.abs() < 1e-9 && y.abs() < 1e-9);
    // One degree of latitude along the central meridian: k0 × meridian arc (geodesic).
    let g = Geodesic::wgs84();
    let s: f64 = g.inverse(0.0, -3.0, 1.0, -3.0);
    let (x, y) = grid.to_local(1.0, -3.0).unwrap();
    assert!(x.abs() < 1e-6);
    assert!((y - K0 * s).abs() < 1e-4, "{y} vs {}", K0 * s);
}

proptest! {
    #[test]
    fn round_trip(lat0 in -70.0f64..70.0, lon0 in -179.0f64..179.0, dx in -20_000.0f64..20_000.0, dy in -20_000.0f64..20_000.0) {
        let grid = LocalGrid::new(lat0, lon0).unwrap();
        let (lat, lon) = grid.to_latlon(dx, dy).unwrap();
        let (x, y) = grid.to_local(lat, lon).unwrap();
        prop_assert!((x - dx).abs() < 1e-5 && (y - dy).abs() < 1e-5);
    }
}
