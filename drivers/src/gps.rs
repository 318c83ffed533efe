//! `iGPS`: a GPS receiver's NMEA 0183 from a serial port (GGA, RMC, VTG, checksums verified),
//! or gpsd's JSON (TPV, SKY) over TCP (`cougars-vehicle.md` §3.3: the vehicle runs gpsd).
//!
//! # Variables
//!
//! Posted, as uSimSensors posts them (one report per epoch, closed by `GPS_FIX` ✱): an
//! epoch is a GGA sentence (NMEA) or a TPV report (gpsd).
//!
//! | variable | type | unit | meaning |
//! |---|---|---|---|
//! | `GPS_X`, `GPS_Y` | double | m | local grid east/north (`vehicle::geodesy::LocalGrid` from the mission's `LatOrigin`/`LongOrigin`, as the sensor models and the navigator); with a fix and an origin |
//! | `GPS_LAT`, `GPS_LONG` | double | deg | WGS 84; with a fix |
//! | `GPS_SATELLITES` | double | count | satellites used (GGA; gpsd: the last SKY's `used`); posted once known |
//! | `GPS_HDOP` | double | — | GGA's HDOP (99.99 without a fix, as the sensor model); gpsd: the last SKY's `hdop` |
//! | `GPS_FIX` ✱ | double | 1/0 | GGA quality > 0; gpsd TPV mode ≥ 2 |
//! | `GPS_SPEED` | double | m/s | speed over ground (RMC, VTG, TPV `speed`), when given |
//! | `GPS_COURSE` | double | deg | course over ground, true (RMC, VTG, TPV `track`), when given |
//!
//! # Parameters
//!
//! | parameter | default | meaning |
//! |---|---|---|
//! | `device`, `baud` | —, 9600 | NMEA from this serial port; without `device`, gpsd |
//! | `host`, `port` | `127.0.0.1`, 2947 | gpsd; on each connection the driver sends `?WATCH={"enable":true,"json":true}` |

use std::fmt::Write as _;

use devices::line::{LineSplitter, LinkStats};
use devices::nmea::{self, Sentence, gpsd};
use moos_types::Value;
use vehicle::ConfigError;
use vehicle::geodesy::LocalGrid;

use crate::link::LinkConfig;
use crate::params::{self, Common};
use crate::{Io, Protocol, g};

/// The program name.
pub const PROGRAM: &str = "iGPS";

/// The command that makes gpsd stream JSON reports.
pub const WATCH: &str = "?WATCH={\"enable\":true,\"json\":true}\n";

/// HDOP posted without a fix (the sensor model's value).
pub const NO_FIX_HDOP: f64 = 99.99;

/// Where the fixes come from.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Source {
    /// NMEA 0183 sentences (a serial port).
    Nmea,
    /// gpsd's JSON (a TCP client).
    Gpsd,
}

/// Reads a block's parameters: the source, the link and the problems found (`device` and
/// `host` together: the serial port wins, and that is a problem).
pub fn config_from_params<'a>(
    params: impl IntoIterator<Item = (&'a str, &'a str)>,
) -> (Source, Common, LinkConfig, Vec<ConfigError>) {
    let (common, mut problems) = params::read(PROGRAM, params, |_, _| None);
    if common.device.is_some() {
        if common.host.is_some() || common.port.is_some() {
            problems.push(ConfigError::BadValue {
                app: PROGRAM,
                key: "host".into(),
                value: common.host.clone().unwrap_or_default(),
                expected: "either `device` (NMEA) or `host`/`port` (gpsd), not both: using `device`",
            });
        }
        let link = common.serial_link("", 9600);
        (Source::Nmea, common, link, problems)
    } else {
        let link = common.tcp_link("127.0.0.1", 2947);
        (Source::Gpsd, common, link, problems)
    }
}

/// Counts of what came in.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq)]
pub struct GpsCounts {
    /// Epochs posted (GGA or TPV).
    pub epochs: u64,
    /// Of which with a fix.
    pub fixes: u64,
    /// RMC and VTG sentences.
    pub velocity: u64,
    /// SKY reports.
    pub sky: u64,
    /// Fixes that could not be put on the local grid.
    pub grid_errors: u64,
}

/// The `iGPS` protocol.
pub struct Gps {
    source: Source,
    grid: Option<LocalGrid>,
    lines: LineSplitter,
    counts: GpsCounts,
    sky: Option<(Option<f64>, u32)>,
    last: Option<(f64, f64)>,
    last_fix: bool,
}

impl Gps {
    /// A protocol reading `source`, putting fixes on `grid` (the mission's origin) when given.
    pub fn new(source: Source, grid: Option<LocalGrid>) -> Self {
        let lines = match source {
            Source::Nmea => LineSplitter::new(nmea::MAX_LINE).with_starts(b"$!"),
            // JSON nests objects: a `{` does not start a line.
            Source::Gpsd => LineSplitter::new(gpsd::MAX_LINE),
        };
        Gps {
            source,
            grid,
            lines,
            counts: GpsCounts::default(),
            sky: None,
            last: None,
            last_fix: false,
        }
    }

    /// The counts so far.
    pub fn counts(&self) -> GpsCounts {
        self.counts
    }

    fn position(&mut self, lat: f64, lon: f64, io: &mut Io) {
        if let Some(grid) = &self.grid {
            match grid.to_local(lat, lon) {
                Ok((x, y)) => {
                    io.double("GPS_X", x);
                    io.double("GPS_Y", y);
                }
                Err(_) => self.counts.grid_errors += 1,
            }
        }
        io.double("GPS_LAT", lat);
        io.double("GPS_LONG", lon);
        self.last = Some((lat, lon));
    }

    fn velocity(&mut self, speed_mps: Option<f64>, course: Option<f64>, io: &mut Io) {
        if let Some(s) = speed_mps {
            io.double("GPS_SPEED", s);
        }
        if let Some(c) = course {
            io.double("GPS_COURSE", c);
        }
    }

    fn nmea_line(&mut self, line: &[u8], io: &mut Io) {
        let r = nmea::parse(line);
        self.lines.stats_mut().record(&r);
        match r {
            Ok(Sentence::Gga(s)) => {
                self.counts.epochs += 1;
                let fix = s.quality > 0;
                let pos = s.lat_deg.zip(s.lon_deg).filter(|_| fix);
                if let Some((lat, lon)) = pos {
                    self.counts.fixes += 1;
                    self.position(lat, lon, io);
                }
                if let Some(n) = s.satellites {
                    io.double("GPS_SATELLITES", f64::from(n));
                }
                let hdop = if fix {
                    s.hdop.unwrap_or(NO_FIX_HDOP)
                } else {
                    NO_FIX_HDOP
                };
                io.double("GPS_HDOP", hdop);
                self.last_fix = pos.is_some();
                io.double("GPS_FIX", if pos.is_some() { 1.0 } else { 0.0 });
            }
            Ok(Sentence::Rmc(s)) => {
                self.counts.velocity += 1;
                if s.valid {
                    self.velocity(s.speed_mps(), s.course_deg, io);
                }
            }
            Ok(Sentence::Vtg(s)) => {
                self.counts.velocity += 1;
                let speed = s
                    .speed_kn
                    .map(|k| k * nmea::MPS_PER_KNOT)
                    .or(s.speed_kmh.map(|k| k / 3.6));
                if s.mode != Some('N') {
                    self.velocity(speed, s.course_true_deg, io);
                }
            }
            Err(_) => {}
        }
    }

    fn gpsd_line(&mut self, line: &[u8], io: &mut Io) {
        let r = gpsd::parse(line);
        self.lines.stats_mut().record(&r);
        match r {
            Ok(gpsd::Report::Tpv(t)) => {
                self.counts.epochs += 1;
                let pos = t.lat_deg.zip(t.lon_deg).filter(|_| t.mode >= 2);
                if let Some((lat, lon)) = pos {
                    self.counts.fixes += 1;
                    self.position(lat, lon, io);
                }
                if let Some((hdop, used)) = self.sky {
                    io.double("GPS_SATELLITES", f64::from(used));
                    let h = hdop.filter(|_| pos.is_some()).unwrap_or(NO_FIX_HDOP);
                    io.double("GPS_HDOP", h);
                } else if pos.is_none() {
                    io.double("GPS_HDOP", NO_FIX_HDOP);
                }
                self.last_fix = pos.is_some();
                io.double("GPS_FIX", if pos.is_some() { 1.0 } else { 0.0 });
                if pos.is_some() {
                    self.velocity(t.speed_mps, t.track_deg, io);
                }
            }
            Ok(gpsd::Report::Sky(s)) => {
                self.counts.sky += 1;
                let used = s.satellites.iter().filter(|v| v.used).count() as u32;
                self.sky = Some((s.hdop, used));
            }
            Ok(gpsd::Report::Other(_)) | Err(_) => {}
        }
    }
}

impl Protocol for Gps {
    fn program(&self) -> &'static str {
        PROGRAM
    }

    fn status_var(&self) -> &'static str {
        "GPS_DRIVER_STATUS"
    }

    fn on_connect(&mut self, _now: f64, io: &mut Io) {
        self.lines.reset();
        if self.source == Source::Gpsd {
            io.send(WATCH);
            io.events.push("gpsd: WATCH sent".into());
        }
    }

    fn on_bytes(&mut self, data: &[u8], _now: f64, io: &mut Io) {
        let mut got = Vec::new();
        self.lines.push(data, |l| got.push(l.to_vec()));
        for l in got {
            match self.source {
                Source::Nmea => self.nmea_line(&l, io),
                Source::Gpsd => self.gpsd_line(&l, io),
            }
        }
    }

    fn on_mail(&mut self, _key: &str, _value: &Value, _now: f64, _io: &mut Io) {}

    fn stats(&self) -> LinkStats {
        *self.lines.stats()
    }

    fn state(&self) -> &'static str {
        "running"
    }

    fn status_extra(&self, out: &mut String) {
        let c = &self.counts;
        let _ = write!(
            out,
            ",source={},epochs={},fixes={},fix={}",
            match self.source {
                Source::Nmea => "nmea",
                Source::Gpsd => "gpsd",
            },
            c.epochs,
            c.fixes,
            u8::from(self.last_fix)
        );
    }

    fn report(&self, out: &mut String) {
        let c = &self.counts;
        let _ = writeln!(
            out,
            "Epochs: {}   fixes: {}   speed/course: {}   sky: {}   grid: {}",
            c.epochs,
            c.fixes,
            c.velocity,
            c.sky,
            if self.grid.is_some() {
                "LatOrigin/LongOrigin"
            } else {
                "none (no GPS_X/GPS_Y)"
            }
        );
        if let Some((lat, lon)) = self.last {
            let _ = writeln!(
                out,
                "Last fix: {} {} ({})",
                g(lat),
                g(lon),
                if self.last_fix { "current" } else { "lost" }
            );
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn doubles(io: &Io, key: &str) -> Vec<f64> {
        io.doubles(key)
    }

    fn keys(io: &Io) -> Vec<&str> {
        io.posts.iter().map(|p| &*p.key).collect()
    }

    #[test]
    fn nmea_gga_is_an_epoch_on_the_mission_grid_and_bad_checksums_are_counted() {
        let grid = LocalGrid::new(48.0, 11.0).unwrap();
        let mut p = Gps::new(Source::Nmea, Some(grid.clone()));
        let mut io = Io::default();
        p.on_connect(0.0, &mut io);
        assert!(io.tx.is_empty(), "nothing is sent to an NMEA receiver");
        // The classic example sentence (48°07.038' N, 11°31.000' E), with its checksum.
        let gga = b"$GPGGA,123519,4807.038,N,01131.000,E,1,08,0.9,545.4,M,46.9,M,,*47\r\n";
        p.on_bytes(&gga[..20], 1.0, &mut io);
        p.on_bytes(&gga[20..], 1.0, &mut io);
        assert_eq!(
            keys(&io),
            [
                "GPS_X",
                "GPS_Y",
                "GPS_LAT",
                "GPS_LONG",
                "GPS_SATELLITES",
                "GPS_HDOP",
                "GPS_FIX"
            ]
        );
        let lat = 48.0 + 7.038 / 60.0;
        let lon = 11.0 + 31.0 / 60.0;
        assert!((doubles(&io, "GPS_LAT")[0] - lat).abs() < 1e-12);
        assert!((doubles(&io, "GPS_LONG")[0] - lon).abs() < 1e-12);
        let (x, y) = grid
            .to_local(doubles(&io, "GPS_LAT")[0], doubles(&io, "GPS_LONG")[0])
            .unwrap();
        assert_eq!(doubles(&io, "GPS_X"), [x]);
        assert_eq!(doubles(&io, "GPS_Y"), [y]);
        let (blat, blon) = grid.to_latlon(x, y).unwrap();
        assert!((blat - lat).abs() < 1e-9 && (blon - lon).abs() < 1e-9);
        assert!(
            x > 38_000.0 && y > 13_000.0,
            "east and north of the origin: {x} {y}"
        );
        assert_eq!(doubles(&io, "GPS_SATELLITES"), [8.0]);
        assert_eq!(doubles(&io, "GPS_HDOP"), [0.9]);
        assert_eq!(doubles(&io, "GPS_FIX"), [1.0]);
        let mut io = Io::default();
        p.on_bytes(
            b"$GPGGA,123519,4807.038,N,01131.000,E,1,08,0.9,545.4,M,46.9,M,,*48\r\n",
            2.0,
            &mut io,
        );
        assert!(io.posts.is_empty());
        assert_eq!(p.stats().bad_checksum, 1);
        p.on_bytes(
            b"$GPVTG,054.7,T,034.4,M,005.5,N,010.2,K*48\r\n",
            2.0,
            &mut io,
        );
        assert!((doubles(&io, "GPS_SPEED")[0] - 5.5 * nmea::MPS_PER_KNOT).abs() < 1e-12);
        assert_eq!(doubles(&io, "GPS_COURSE"), [54.7]);
    }

    #[test]
    fn a_gga_without_a_fix_posts_no_position() {
        let mut p = Gps::new(Source::Nmea, None);
        let mut io = Io::default();
        let line = nmea::with_checksum("GPGGA,123519,,,,,0,00,,,M,,M,,");
        p.on_bytes(format!("{line}\r\n").as_bytes(), 1.0, &mut io);
        assert_eq!(keys(&io), ["GPS_SATELLITES", "GPS_HDOP", "GPS_FIX"]);
        assert_eq!(doubles(&io, "GPS_HDOP"), [NO_FIX_HDOP]);
        assert_eq!(doubles(&io, "GPS_FIX"), [0.0]);
    }

    #[test]
    fn gpsd_watch_then_sky_and_tpv() {
        let mut p = Gps::new(Source::Gpsd, None);
        let mut io = Io::default();
        p.on_connect(0.0, &mut io);
        assert_eq!(io.tx, vec![WATCH.as_bytes().to_vec()]);
        p.on_bytes(
            b"{\"class\":\"VERSION\",\"release\":\"3.25\"}\n\
              {\"class\":\"SKY\",\"hdop\":1.2,\"satellites\":[{\"PRN\":1,\"used\":true},{\"PRN\":2,\"used\":false},{\"PRN\":3,\"used\":true}]}\n\
              {\"class\":\"TPV\",\"mode\":3,\"lat\":40.07,\"lon\":-111.6,\"speed\":0.5,\"track\":90.0}\n",
            1.0,
            &mut io,
        );
        assert_eq!(
            keys(&io),
            [
                "GPS_LAT",
                "GPS_LONG",
                "GPS_SATELLITES",
                "GPS_HDOP",
                "GPS_FIX",
                "GPS_SPEED",
                "GPS_COURSE"
            ]
        );
        assert_eq!(doubles(&io, "GPS_SATELLITES"), [2.0]);
        assert_eq!(doubles(&io, "GPS_HDOP"), [1.2]);
        let mut io = Io::default();
        p.on_bytes(b"{\"class\":\"TPV\",\"mode\":1}\nnot json}\n", 2.0, &mut io);
        assert_eq!(doubles(&io, "GPS_FIX"), [0.0]);
        assert_eq!(doubles(&io, "GPS_HDOP"), [NO_FIX_HDOP]);
        assert_eq!(p.stats().parse_errors, 1);
    }

    #[test]
    fn config_picks_the_source() {
        let (s, _, l, pr) = config_from_params([("device", "/dev/tnt1")]);
        assert_eq!(
            (s, l.endpoint.to_string(), pr.len()),
            (Source::Nmea, "/dev/tnt1@9600".into(), 0)
        );
        let (s, _, l, _) = config_from_params([("port", "3000")]);
        assert_eq!(
            (s, l.endpoint.to_string()),
            (Source::Gpsd, "tcp://127.0.0.1:3000".into())
        );
        let (_, _, _, pr) = config_from_params([("device", "/dev/x"), ("host", "h")]);
        assert_eq!(pr.len(), 1);
    }
}
