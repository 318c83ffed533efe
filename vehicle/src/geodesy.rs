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

use std::sync::Arc;

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
    ctx: Arc<Minimal>,
    op: OpHandle,
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
        let cm = zone_central_meridian(zone);
        let mut ctx = Minimal::new();
        let def = format!("tmerc ellps=WGS84 lon_0={cm} k_0=0.9996 x_0=500000");
        let op = ctx
            .op(&def)
            .map_err(|e| GeodesyError::Projection(e.to_string()))?;
        let mut grid = LocalGrid {
            lat0: lat_origin,
            lon0: lon_origin,
            zone,
            ctx: Arc::new(ctx),
            op,
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
        let mut data = [Coor2D::geo(lat, lon)];
        let n = self
            .ctx
            .apply(self.op, Fwd, &mut data)
            .map_err(|e| GeodesyError::Projection(e.to_string()))?;
        let (e, nn) = (data[0][0], data[0][1]);
        if n != 1 || !e.is_finite() || !nn.is_finite() {
            return Err(GeodesyError::Projection(format!(
                "cannot project lat={lat}, lon={lon}"
            )));
        }
        Ok((e, nn))
    }

    /// Latitude/longitude (degrees) to local x (east) / y (north) metres.
    pub fn to_local(&self, lat: f64, lon: f64) -> Result<(f64, f64), GeodesyError> {
        let (e, n) = self.project(lat, lon)?;
        Ok((e - self.east0, n - self.north0))
    }

    /// Local x (east) / y (north) metres to latitude/longitude (degrees).
    pub fn to_latlon(&self, x: f64, y: f64) -> Result<(f64, f64), GeodesyError> {
        let mut data = [Coor2D::raw(x + self.east0, y + self.north0)];
        let n = self
            .ctx
            .apply(self.op, Inv, &mut data)
            .map_err(|e| GeodesyError::Projection(e.to_string()))?;
        let (lon, lat) = (data[0][0].to_degrees(), data[0][1].to_degrees());
        if n != 1 || !lat.is_finite() || !lon.is_finite() {
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
}
