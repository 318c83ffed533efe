//! Local x/y metres <-> latitude/longitude, consistent with MOOS-IvP's UTM-based local grid.
//!
//! MOOS-IvP (`CMOOSGeodesy`, built with `USE_UTM`) defines the local grid of a mission as UTM
//! easting/northing relative to the UTM coordinates of `LatOrigin`/`LongOrigin`: `x` is the
//! easting difference (metres, east), `y` the northing difference (metres, north). Both are
//! *grid* metres (they include the UTM scale factor, 0.9996 on the central meridian).
//!
//! **Bug not copied.** MOOS-IvP projects every point in *its own* UTM zone but subtracts the
//! origin's coordinates in the *origin's* zone, so a point across a zone boundary from the
//! origin lands hundreds of kilometres away. Here every point is projected with one Transverse
//! Mercator projection pinned to the origin's zone (central meridian, k0 = 0.9996, WGS 84),
//! which gives the same numbers as MOOS-IvP inside the origin's zone and correct ones outside
//! it. The projection itself is the Poder/Engsager TM of the `geodesy` crate (Rust Geodesy).

use geodesy::authoring::{FourierCoefficients, angular, fourier, gudermannian};
use geodesy::prelude::*;

/// Why a local grid could not be built or a point not converted.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum GeodesyError {
    /// The origin is not a valid latitude/longitude.
    #[error("invalid origin lat={lat}, lon={lon}: expected |lat| < 84 and |lon| <= 180")]
    InvalidOrigin {
        /// Origin latitude, degrees.
        lat: f64,
        /// Origin longitude, degrees.
        lon: f64,
    },
    /// The projection library rejected the operation or a coordinate.
    #[error("projection failed: {0}")]
    Projection(String),
}

/// UTM zone number (1..=60) of a point, with the Norway and Svalbard exceptions.
pub fn utm_zone(lat: f64, lon: f64) -> u8 {
    let lon = (lon + 180.0).rem_euclid(360.0) - 180.0;
    let mut zone = (((lon + 180.0) / 6.0).floor() as i32 + 1).clamp(1, 60);
    if (56.0..64.0).contains(&lat) && (3.0..12.0).contains(&lon) {
        zone = 32;
    }
    if (72.0..84.0).contains(&lat) {
        zone = match lon {
            l if (0.0..9.0).contains(&l) => 31,
            l if (9.0..21.0).contains(&l) => 33,
            l if (21.0..33.0).contains(&l) => 35,
            l if (33.0..42.0).contains(&l) => 37,
            _ => zone,
        };
    }
    zone as u8
}

/// Central meridian (degrees) of a UTM zone.
pub fn zone_central_meridian(zone: u8) -> f64 {
    f64::from(zone) * 6.0 - 183.0
}

/// The `geodesy` crate's definition of the projection of a zone's central meridian.
fn tm_definition(central_meridian: f64) -> String {
    format!("tmerc ellps=WGS84 lon_0={central_meridian} k_0=0.9996 x_0=500000")
}

/// Beyond this normalised easting (radians on the conformal sphere) the `geodesy` crate's
/// transverse Mercator gives no result.
const TM_MAX_EASTING: f64 = 2.623395162778;

/// One transverse Mercator projection (the Poder/Engsager series of the `geodesy` crate),
/// its constants read once from the operator the crate builds, evaluated per point by the
/// same steps and the same crate functions as its `tmerc` operator, so every result is the
/// crate's to the bit (tested against it), without its per-call look-ups of the operator,
/// its parameters by name and its ellipsoid.
#[derive(Debug, Clone)]
struct Tm {
    ellps: Ellipsoid,
    /// Central meridian, radians.
    lon_0: f64,
    /// False easting, metres.
    x_0: f64,
    /// The scaled radius (Qn in Engsager's notation).
    qs: f64,
    /// The northing offset of the latitude of origin.
    zb: f64,
    /// Series between geographic and conformal latitude.
    conformal: FourierCoefficients,
    /// Series between the conformal sphere and the projection.
    tm: FourierCoefficients,
}

impl Tm {
    fn new(central_meridian: f64) -> Result<Self, GeodesyError> {
        let err = |e: geodesy::Error| GeodesyError::Projection(e.to_string());
        let mut ctx = Minimal::new();
        let op = ctx.op(&tm_definition(central_meridian)).map_err(err)?;
        let p = ctx.params(op, 0).map_err(err)?;
        let missing = |what: &str| GeodesyError::Projection(format!("tmerc without {what}"));
        Ok(Tm {
            ellps: p.ellps(0),
            lon_0: p.lon(0).to_radians(),
            x_0: p.x(0),
            qs: *p
                .real
                .get("scaled_radius")
                .ok_or_else(|| missing("a radius"))?,
            zb: *p.real.get("zb").ok_or_else(|| missing("zb"))?,
            conformal: p
                .fourier_coefficients
                .get("conformal")
                .copied()
                .ok_or_else(|| missing("its conformal series"))?,
            tm: p
                .fourier_coefficients
                .get("tm")
                .copied()
                .ok_or_else(|| missing("its TM series"))?,
        })
    }

    /// Longitude, latitude (radians) to easting, northing; `None` too far from the
    /// central meridian.
    fn fwd(&self, lon: f64, lat: f64) -> Option<(f64, f64)> {
        // Geographic to conformal latitude; longitude from the central meridian.
        let lat = self
            .ellps
            .latitude_geographic_to_conformal(lat, &self.conformal);
        let lon = lon - self.lon_0;
        // Conformal latitude and longitude to complex spherical latitude.
        let (sin_lat, cos_lat) = lat.sin_cos();
        let (sin_lon, cos_lon) = lon.sin_cos();
        let cos_lat_lon = cos_lat * cos_lon;
        let mut lat = sin_lat.atan2(cos_lat_lon);
        // To ellipsoidal normalised northing and easting (the crate's Clenshaw terms).
        let inv_denom_tan_lon = sin_lat.hypot(cos_lat_lon).recip();
        let tan_lon = sin_lon * cos_lat * inv_denom_tan_lon;
        let mut lon = tan_lon.asinh();
        let two_inv_denom_tan_lon = 2.0 * inv_denom_tan_lon;
        let two_inv_denom_tan_lon_square = two_inv_denom_tan_lon * inv_denom_tan_lon;
        let tmp_r = cos_lat_lon * two_inv_denom_tan_lon_square;
        let trig = [sin_lat * tmp_r, cos_lat_lon * tmp_r - 1.0];
        let hyp = [
            tan_lon * two_inv_denom_tan_lon,
            two_inv_denom_tan_lon_square - 1.0,
        ];
        let dc = fourier::complex_sin_optimized_for_tmerc(trig, hyp, &self.tm.fwd);
        lat += dc[0];
        lon += dc[1];
        if lon.abs() > TM_MAX_EASTING {
            return None;
        }
        Some((self.qs * lon + self.x_0, self.qs * lat + self.zb))
    }

    /// Easting, northing to longitude, latitude (radians); `None` too far from the
    /// central meridian.
    fn inv(&self, x: f64, y: f64) -> Option<(f64, f64)> {
        let mut lon = (x - self.x_0) / self.qs;
        let mut lat = (y - self.zb) / self.qs;
        if lon.abs() > TM_MAX_EASTING {
            return None;
        }
        // Normalised northing and easting to complex spherical latitude and longitude.
        let dc = fourier::complex_sin([2. * lat, 2. * lon], &self.tm.inv);
        lat += dc[0];
        lon += dc[1];
        lon = gudermannian::fwd(lon);
        // To Gaussian latitude and longitude.
        let (sin_lat, cos_lat) = lat.sin_cos();
        let (sin_lon, cos_lon) = lon.sin_cos();
        let cos_lat_lon = cos_lat * cos_lon;
        lon = sin_lon.atan2(cos_lat_lon);
        lat = (sin_lat * cos_lon).atan2(sin_lon.hypot(cos_lat_lon));
        // To geographic latitude and longitude.
        let lon = angular::normalize_symmetric(lon + self.lon_0);
        let lat = self
            .ellps
            .latitude_conformal_to_geographic(lat, &self.conformal);
        Some((lon, lat))
    }
}

/// A mission's local grid: `LatOrigin`/`LongOrigin` and the projection of the origin's zone.
///
/// ```
/// let grid = vehicle::geodesy::LocalGrid::new(43.825300, -70.330400).unwrap();
/// let (lat, lon) = grid.to_latlon(100.0, -50.0).unwrap();
/// let (x, y) = grid.to_local(lat, lon).unwrap();
/// assert!((x - 100.0).abs() < 1e-6 && (y + 50.0).abs() < 1e-6);
/// ```
#[derive(Clone)]
pub struct LocalGrid {
    lat0: f64,
    lon0: f64,
    zone: u8,
    tm: Tm,
    east0: f64,
    north0: f64,
}

impl std::fmt::Debug for LocalGrid {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("LocalGrid")
            .field("lat0", &self.lat0)
            .field("lon0", &self.lon0)
            .field("zone", &self.zone)
            .finish()
    }
}

impl LocalGrid {
    /// Builds the grid for a mission origin (degrees).
    pub fn new(lat_origin: f64, lon_origin: f64) -> Result<Self, GeodesyError> {
        if !(lat_origin.is_finite() && lon_origin.is_finite())
            || lat_origin.abs() >= 84.0
            || lon_origin.abs() > 180.0
        {
            return Err(GeodesyError::InvalidOrigin {
                lat: lat_origin,
                lon: lon_origin,
            });
        }
        let zone = utm_zone(lat_origin, lon_origin);
        let mut grid = LocalGrid {
            lat0: lat_origin,
            lon0: lon_origin,
            zone,
            tm: Tm::new(zone_central_meridian(zone))?,
            east0: 0.0,
            north0: 0.0,
        };
        let (e, n) = grid.project(lat_origin, lon_origin)?;
        grid.east0 = e;
        grid.north0 = n;
        Ok(grid)
    }

    /// Origin latitude, degrees.
    pub fn lat_origin(&self) -> f64 {
        self.lat0
    }

    /// Origin longitude, degrees.
    pub fn lon_origin(&self) -> f64 {
        self.lon0
    }

    /// The origin's UTM zone, used for every point.
    pub fn zone(&self) -> u8 {
        self.zone
    }

    /// Easting/northing (with 500 km false easting, no false northing) in the origin's zone.
    fn project(&self, lat: f64, lon: f64) -> Result<(f64, f64), GeodesyError> {
        match self.tm.fwd(lon.to_radians(), lat.to_radians()) {
            Some((e, n)) if e.is_finite() && n.is_finite() => Ok((e, n)),
            _ => Err(GeodesyError::Projection(format!(
                "cannot project lat={lat}, lon={lon}"
            ))),
        }
    }

    /// Latitude/longitude (degrees) to local x (east) / y (north) metres.
    pub fn to_local(&self, lat: f64, lon: f64) -> Result<(f64, f64), GeodesyError> {
        let (e, n) = self.project(lat, lon)?;
        Ok((e - self.east0, n - self.north0))
    }

    /// Local x (east) / y (north) metres to latitude/longitude (degrees).
    pub fn to_latlon(&self, x: f64, y: f64) -> Result<(f64, f64), GeodesyError> {
        let inverted = self.tm.inv(x + self.east0, y + self.north0);
        let (lon, lat) = inverted.map_or((f64::NAN, f64::NAN), |(lon, lat)| {
            (lon.to_degrees(), lat.to_degrees())
        });
        if inverted.is_none() || !lat.is_finite() || !lon.is_finite() {
            return Err(GeodesyError::Projection(format!(
                "cannot invert x={x}, y={y}"
            )));
        }
        Ok((lat, crate::angle::angle180(lon)))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn zones() {
        assert_eq!(utm_zone(43.8, -70.3), 19);
        assert_eq!(utm_zone(0.0, 0.0), 31);
        assert_eq!(utm_zone(0.0, -0.1), 30);
        assert_eq!(utm_zone(60.0, 5.0), 32);
        assert_eq!(utm_zone(78.0, 15.0), 33);
        assert_eq!(zone_central_meridian(19), -69.0);
    }

    #[test]
    fn origin_is_zero_and_bad_origin_is_error() {
        let g = LocalGrid::new(40.3394, -111.90721).unwrap();
        let (x, y) = g.to_local(40.3394, -111.90721).unwrap();
        assert!(x.abs() < 1e-9 && y.abs() < 1e-9);
        assert!(matches!(
            LocalGrid::new(91.0, 0.0),
            Err(GeodesyError::InvalidOrigin { .. })
        ));
        assert!(LocalGrid::new(f64::NAN, 0.0).is_err());
    }
    /// The `geodesy` crate's operator applied per call, as `LocalGrid` did before it kept
    /// the operator's constants: the oracle of [`Tm`].
    struct Library {
        ctx: Minimal,
        op: OpHandle,
    }

    impl Library {
        fn new(central_meridian: f64) -> Self {
            let mut ctx = Minimal::new();
            let op = ctx.op(&tm_definition(central_meridian)).unwrap();
            Library { ctx, op }
        }

        fn apply(&self, c: Coor2D, dir: Direction) -> Option<(f64, f64)> {
            let mut data = [c];
            let n = self.ctx.apply(self.op, dir, &mut data).unwrap();
            (n == 1).then(|| (data[0][0], data[0][1]))
        }
    }

    fn bits(p: Option<(f64, f64)>) -> Option<(u64, u64)> {
        p.map(|(a, b)| (a.to_bits(), b.to_bits()))
    }

    #[test]
    fn the_projection_is_the_crate_s_to_the_bit() {
        for (lat0, lon0) in [
            (40.3394, -111.90721),
            (43.8253, -70.3304),
            (42.358456, -71.087589),
            (-33.86, 151.21),
            (0.0, 0.0),
            (60.0, 5.0),
            (78.0, 15.0),
            (-83.9, -179.9),
        ] {
            let grid = LocalGrid::new(lat0, lon0).unwrap();
            let lib = Library::new(zone_central_meridian(grid.zone()));
            let mut checked = 0;
            for i in -60..=60 {
                for j in -60..=60 {
                    // Local points up to ~25 km out, off any round number, then far ones
                    // (a whole zone and beyond, where the projection gives up).
                    let (x, y) = (f64::from(i) * 417.3 + 0.137, f64::from(j) * 409.9 - 0.071);
                    for (x, y) in [(x, y), (x * 1e3, y * 37.0)] {
                        let (e, n) = (x + grid.east0, y + grid.north0);
                        let want = lib.apply(Coor2D::raw(e, n), Inv);
                        assert_eq!(bits(grid.tm.inv(e, n)), bits(want), "inv {x},{y}");
                        let got = grid.to_latlon(x, y).ok();
                        let want = want
                            .map(|(lon, lat)| (lon.to_degrees(), lat.to_degrees()))
                            .filter(|(lon, lat)| lon.is_finite() && lat.is_finite())
                            .map(|(lon, lat)| (lat, crate::angle::angle180(lon)));
                        assert_eq!(bits(got), bits(want), "to_latlon {x},{y}");
                        let Some((lat, lon)) = got else { continue };
                        let want = lib.apply(Coor2D::geo(lat, lon), Fwd);
                        let fwd = grid.tm.fwd(lon.to_radians(), lat.to_radians());
                        assert_eq!(bits(fwd), bits(want), "fwd {lat},{lon}");
                        let want = want
                            .filter(|(e, n)| e.is_finite() && n.is_finite())
                            .map(|(e, n)| (e - grid.east0, n - grid.north0));
                        assert_eq!(bits(grid.to_local(lat, lon).ok()), bits(want));
                        checked += 1;
                    }
                }
            }
            assert!(checked >= 121 * 121, "{checked} points at {lat0},{lon0}");
        }
        // Points the projection refuses: the same errors.
        let grid = LocalGrid::new(43.8253, -70.3304).unwrap();
        assert!(grid.to_latlon(3e7, 0.0).is_err());
        assert!(grid.to_latlon(f64::NAN, 0.0).is_err());
        assert!(grid.to_local(f64::NAN, 0.0).is_err());
    }
}
