//! The GPS: an NMEA 0183 receiver on a serial line ([`NmeaGps`]: GGA, RMC and VTG every
//! epoch, `cougars-vehicle.md` §3.3) and the gpsd daemon in front of it ([`Gpsd`]: JSON on
//! TCP, a VERSION banner on connection, TPV every epoch and SKY once a second while a
//! client watches).
//!
//! Both take their epochs from the GPS model of `vehicle::sensors::gps` (5 Hz; no fix while
//! the antenna is under water, a hot-start delay after surfacing, rare losses), latitude and
//! longitude from the local position through the mission origin's [`LocalGrid`]. Speed and
//! course come from the truth's velocity over ground plus white noise (σ 0.05 m/s per
//! axis, a receiver's Doppler velocity); the course is written only above 0.1 knot, as the
//! CoUGARs NMEA writer does.

use devices::nmea::{self, Date, Gga, Rmc, UtcTime, Vtg, gpsd};
use serde_json::json;
use vehicle::geodesy::LocalGrid;
use vehicle::sensors::Noise;
use vehicle::sensors::gps::{Gps, GpsConfig, GpsReport};

use crate::device::{Device, Situation};

/// Knots per metre a second (the CoUGARs NMEA writer's factor).
pub const KNOTS_PER_MPS: f64 = 1.94384;

/// σ of the Doppler velocity per horizontal axis, m/s.
const VEL_NOISE_MPS: f64 = 0.05;

/// The settings shared by both forms.
#[derive(Debug, Clone)]
pub struct GpsSettings {
    /// The GPS model's settings (rate, noise, antenna depth, acquisition time, losses).
    pub model: GpsConfig,
    /// The local grid's origin, degrees (Utah Lake, the CoUGARs' test site).
    pub origin_lat_lon: (f64, f64),
    /// Altitude above mean sea level written in GGA and TPV, m.
    pub altitude_msl_m: f64,
    /// The device path gpsd reports.
    pub device_path: String,
}

impl Default for GpsSettings {
    fn default() -> Self {
        GpsSettings {
            model: GpsConfig::default(),
            origin_lat_lon: (40.3394, -111.90721),
            altitude_msl_m: 1368.0,
            device_path: "/dev/ttyUSB0".to_string(),
        }
    }
}

/// A civil date and time of day, UTC.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Utc {
    /// Year.
    pub year: i64,
    /// Month, 1–12.
    pub month: u8,
    /// Day, 1–31.
    pub day: u8,
    /// Hundredths of a second since midnight.
    pub centis_of_day: u32,
}

impl Utc {
    /// The UTC date and time (to the hundredth) of a Unix time, s.
    pub fn from_unix(unix_s: f64) -> Utc {
        let cs = (unix_s * 100.0).round() as i64;
        let days = cs.div_euclid(8_640_000);
        let centis_of_day = cs.rem_euclid(8_640_000) as u32;
        // Days since 1970-01-01 to a proleptic Gregorian date, by 400-year eras.
        let z = days + 719_468;
        let era = z.div_euclid(146_097);
        let doe = z.rem_euclid(146_097);
        let yoe = (doe - doe / 1460 + doe / 36_524 - doe / 146_096) / 365;
        let doy = doe - (365 * yoe + yoe / 4 - yoe / 100);
        let mp = (5 * doy + 2) / 153;
        let day = (doy - (153 * mp + 2) / 5 + 1) as u8;
        let month = if mp < 10 { mp + 3 } else { mp - 9 } as u8;
        let year = yoe + era * 400 + i64::from(month <= 2);
        Utc {
            year,
            month,
            day,
            centis_of_day,
        }
    }

    /// The NMEA time of day.
    pub fn time(&self) -> UtcTime {
        let c = self.centis_of_day;
        UtcTime {
            hour: (c / 360_000) as u8,
            minute: (c / 6000 % 60) as u8,
            second: f64::from(c % 6000) / 100.0,
        }
    }

    /// The RMC date.
    pub fn date(&self) -> Date {
        Date {
            day: self.day,
            month: self.month,
            year_2d: self.year.rem_euclid(100) as u8,
        }
    }

    /// ISO 8601 as gpsd writes it: `2026-11-26T12:34:56.780Z`.
    pub fn iso(&self) -> String {
        let c = self.centis_of_day;
        format!(
            "{:04}-{:02}-{:02}T{:02}:{:02}:{:02}.{:02}0Z",
            self.year,
            self.month,
            self.day,
            c / 360_000,
            c / 6000 % 60,
            c / 100 % 60,
            c % 100
        )
    }
}

/// One epoch: the model's report and the velocity over ground.
#[derive(Debug, Clone, Copy)]
struct Epoch {
    report: GpsReport,
    vel_en_mps: (f64, f64),
    climb_mps: f64,
    utc: Utc,
}

/// The GPS model, grid and Doppler noise both forms share.
struct Receiver {
    settings: GpsSettings,
    model: Gps,
    vel_noise: Noise,
}

impl Receiver {
    fn new(settings: GpsSettings, seed: u64) -> Self {
        let (lat, lon) = settings.origin_lat_lon;
        let model = Gps::new(settings.model.clone(), seed).with_grid(LocalGrid::new(lat, lon).ok());
        Receiver {
            settings,
            model,
            vel_noise: Noise::new(seed, 0x6770),
        }
    }

    fn epoch(&mut self, s: &Situation) -> Option<Epoch> {
        let report = self.model.sample(&s.truth)?;
        let vel_en_mps = if report.fix {
            (
                s.truth.vel_east_mps + self.vel_noise.gauss(VEL_NOISE_MPS),
                s.truth.vel_north_mps + self.vel_noise.gauss(VEL_NOISE_MPS),
            )
        } else {
            (0.0, 0.0)
        };
        Some(Epoch {
            report,
            vel_en_mps,
            climb_mps: -s.truth.vel_down_mps,
            utc: Utc::from_unix(s.unix_s),
        })
    }

    fn period(&self) -> f64 {
        1.0 / self.settings.model.rate_hz.max(0.1)
    }
}

fn speed_course(vel_en_mps: (f64, f64)) -> (f64, f64) {
    let (e, n) = vel_en_mps;
    let speed = e.hypot(n);
    (speed, vehicle::angle::angle360(e.atan2(n).to_degrees()))
}

/// The three sentences of an epoch (GGA, RMC, VTG; talker GP).
pub fn nmea_epoch(
    utc: Utc,
    report: &GpsReport,
    vel_en_mps: (f64, f64),
    altitude_msl_m: f64,
) -> [nmea::Sentence; 3] {
    let fix = report.fix && report.lat_lon.is_some();
    let (lat, lon) = match report.lat_lon {
        Some((a, o)) if fix => (Some(a), Some(o)),
        _ => (None, None),
    };
    let (speed, course) = speed_course(vel_en_mps);
    let speed_kn = speed * KNOTS_PER_MPS;
    let course = (fix && speed_kn > 0.1).then_some(course);
    let mode = Some(if fix { 'A' } else { 'N' });
    let gga = Gga {
        talker: *b"GP",
        time: Some(utc.time()),
        lat_deg: lat,
        lon_deg: lon,
        quality: u8::from(fix),
        satellites: Some(report.satellites.min(99) as u8),
        hdop: fix.then_some(report.hdop),
        altitude_msl_m: fix.then_some(altitude_msl_m),
        geoid_separation_m: fix.then_some(0.0),
        dgps_age_s: None,
        dgps_station: None,
    };
    let rmc = Rmc {
        talker: *b"GP",
        time: Some(utc.time()),
        valid: fix,
        lat_deg: lat,
        lon_deg: lon,
        speed_kn: fix.then_some(speed_kn),
        course_deg: course,
        date: Some(utc.date()),
        mag_var_deg: None,
        mode,
    };
    let vtg = Vtg {
        talker: *b"GP",
        course_true_deg: course,
        course_mag_deg: None,
        speed_kn: fix.then_some(speed_kn),
        speed_kmh: fix.then_some(speed * 3.6),
        mode,
    };
    [
        nmea::Sentence::Gga(gga),
        nmea::Sentence::Rmc(rmc),
        nmea::Sentence::Vtg(vtg),
    ]
}

/// An NMEA 0183 receiver on a serial line: GGA, RMC and VTG each epoch. It ignores what it
/// is sent.
pub struct NmeaGps {
    rx: Receiver,
}

impl NmeaGps {
    /// A receiver with these settings, drawing from `seed`.
    pub fn new(settings: GpsSettings, seed: u64) -> Self {
        NmeaGps {
            rx: Receiver::new(settings, seed),
        }
    }
}

impl Device for NmeaGps {
    fn name(&self) -> &'static str {
        "gps"
    }

    fn period(&self) -> f64 {
        self.rx.period()
    }

    fn tick(&mut self, s: &Situation) -> Vec<u8> {
        let Some(e) = self.rx.epoch(s) else {
            return Vec::new();
        };
        nmea_epoch(
            e.utc,
            &e.report,
            e.vel_en_mps,
            self.rx.settings.altitude_msl_m,
        )
        .iter()
        .flat_map(|m| m.encode().into_bytes())
        .collect()
    }

    fn receive(&mut self, _: &Situation, _: &[u8]) -> Vec<u8> {
        Vec::new()
    }
}

/// The gpsd protocol release this emulates.
pub const GPSD_RELEASE: &str = "3.25";

/// gpsd on TCP: a VERSION banner on connection; `?WATCH={"enable":true,"json":true}` is
/// answered with DEVICES and WATCH and starts the stream (TPV every epoch, SKY every
/// second); `?WATCH={"enable":false}` stops it; `?VERSION;`, `?DEVICES;` and `?POLL;` are
/// answered; anything else gets an ERROR object, as gpsd does.
pub struct Gpsd {
    rx: Receiver,
    watching: bool,
    pending: Vec<u8>,
    epochs: u64,
    last: Option<(Tpv, gpsd::Sky)>,
}

type Tpv = gpsd::Tpv;

impl Gpsd {
    /// gpsd in front of a receiver with these settings, drawing from `seed`.
    pub fn new(settings: GpsSettings, seed: u64) -> Self {
        Gpsd {
            rx: Receiver::new(settings, seed),
            watching: false,
            pending: Vec::new(),
            epochs: 0,
            last: None,
        }
    }

    /// True while the connected client watches.
    pub fn watching(&self) -> bool {
        self.watching
    }

    fn version() -> String {
        format!(
            "{}\n",
            json!({"class": "VERSION", "release": GPSD_RELEASE, "rev": GPSD_RELEASE,
                   "proto_major": 3, "proto_minor": 15})
        )
    }

    fn devices(&self) -> String {
        format!(
            "{}\n",
            json!({"class": "DEVICES", "devices": [{"class": "DEVICE",
                   "path": self.rx.settings.device_path, "driver": "NMEA0183", "activated": "",
                   "flags": 1, "native": 0, "bps": 9600, "parity": "N", "stopbits": 1,
                   "cycle": self.rx.period()}]})
        )
    }

    fn watch(&self) -> String {
        format!(
            "{}\n",
            json!({"class": "WATCH", "enable": self.watching, "json": self.watching,
                   "nmea": false, "raw": 0, "scaled": false, "timing": false,
                   "split24": false, "pps": false})
        )
    }

    fn reports(&self, e: &Epoch) -> (Tpv, gpsd::Sky) {
        let r = &e.report;
        let fix = r.fix && r.lat_lon.is_some();
        let (speed, course) = speed_course(e.vel_en_mps);
        let sigma = self.rx.settings.model.noise_m * r.hdop;
        let tpv = Tpv {
            device: Some(self.rx.settings.device_path.clone()),
            time: Some(e.utc.iso()),
            mode: if fix { 3 } else { 1 },
            lat_deg: r.lat_lon.filter(|_| fix).map(|p| p.0),
            lon_deg: r.lat_lon.filter(|_| fix).map(|p| p.1),
            alt_m: fix.then_some(self.rx.settings.altitude_msl_m),
            track_deg: fix.then_some(course),
            speed_mps: fix.then_some(speed),
            climb_mps: fix.then_some(e.climb_mps),
            eph_m: fix.then_some(2.0 * sigma),
            epv_m: fix.then_some(3.0 * sigma),
            ept_s: Some(0.005),
        };
        let n = r.satellites;
        let satellites = (0..n)
            .map(|k| gpsd::Satellite {
                prn: i64::from(k) * 3 + 2,
                el_deg: Some(f64::from(15 + (k * 23) % 70)),
                az_deg: Some(f64::from(k * 360 / n.max(1))),
                ss_dbhz: Some(f64::from(36 + (k * 7) % 12)),
                used: fix,
            })
            .collect();
        let sky = gpsd::Sky {
            device: Some(self.rx.settings.device_path.clone()),
            time: Some(e.utc.iso()),
            hdop: fix.then_some(r.hdop),
            vdop: fix.then_some((r.hdop * 1.5 * 100.0).round() / 100.0),
            pdop: fix.then_some((r.hdop * 1.8 * 100.0).round() / 100.0),
            satellites,
        };
        (tpv, sky)
    }

    fn command(&mut self, cmd: &str) -> String {
        let cmd = cmd.trim();
        if cmd.is_empty() {
            return String::new();
        }
        let (name, arg) = match cmd.find('=') {
            Some(i) => (&cmd[..i], Some(&cmd[i + 1..])),
            None => (cmd, None),
        };
        match name {
            "?VERSION" => Self::version(),
            "?DEVICES" => self.devices(),
            "?WATCH" => {
                if let Some(arg) = arg {
                    let Ok(serde_json::Value::Object(o)) = serde_json::from_str(arg) else {
                        return format!(
                            "{}\n",
                            json!({"class": "ERROR", "message": "Invalid WATCH: bad JSON"})
                        );
                    };
                    let enable = o.get("enable").and_then(|v| v.as_bool());
                    let json_on = o.get("json").and_then(|v| v.as_bool());
                    match enable {
                        Some(false) => self.watching = false,
                        _ => self.watching = json_on.unwrap_or(true),
                    }
                }
                if self.watching {
                    format!("{}{}", self.devices(), self.watch())
                } else {
                    self.watch()
                }
            }
            "?POLL" => {
                let (tpv, sky) = match &self.last {
                    Some((t, s)) => (
                        vec![report_value(&t.encode())],
                        vec![report_value(&s.encode())],
                    ),
                    None => (Vec::new(), Vec::new()),
                };
                let time = self.last.as_ref().and_then(|(t, _)| t.time.clone());
                format!(
                    "{}\n",
                    json!({"class": "POLL", "time": time, "active": 1, "tpv": tpv, "sky": sky})
                )
            }
            _ => format!(
                "{}\n",
                json!({"class": "ERROR", "message": format!("Unrecognized request '{}'", name.trim_start_matches('?'))})
            ),
        }
    }
}

fn report_value(line: &str) -> serde_json::Value {
    serde_json::from_str(line.trim_end()).unwrap_or(serde_json::Value::Null)
}

impl Device for Gpsd {
    fn name(&self) -> &'static str {
        "gpsd"
    }

    fn period(&self) -> f64 {
        self.rx.period()
    }

    fn connected(&mut self, _: &Situation) -> Vec<u8> {
        self.watching = false;
        self.pending.clear();
        Self::version().into_bytes()
    }

    fn tick(&mut self, s: &Situation) -> Vec<u8> {
        let Some(e) = self.rx.epoch(s) else {
            return Vec::new();
        };
        let (tpv, sky) = self.reports(&e);
        let per_second = (1.0 / self.rx.period()).round().max(1.0) as u64;
        let send_sky = self.epochs.is_multiple_of(per_second);
        self.epochs += 1;
        let mut out = String::new();
        if self.watching {
            out.push_str(&tpv.encode());
            if send_sky {
                out.push_str(&sky.encode());
            }
        }
        self.last = Some((tpv, sky));
        out.into_bytes()
    }

    fn receive(&mut self, _: &Situation, data: &[u8]) -> Vec<u8> {
        self.pending.extend_from_slice(data);
        let mut out = String::new();
        // Requests end with ';' (or a newline); a request longer than gpsd's buffer is dropped.
        while let Some(end) = self.pending.iter().position(|&b| b == b';' || b == b'\n') {
            let req: Vec<u8> = self.pending.drain(..=end).collect();
            let req = String::from_utf8_lossy(&req[..req.len() - 1]).into_owned();
            out.push_str(&self.command(&req));
        }
        if self.pending.len() > 1024 {
            self.pending.clear();
        }
        out.into_bytes()
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::truth::Truth;

    fn at(t: f64, depth: f64) -> Situation {
        Situation {
            t,
            unix_s: 1_795_000_000.0 + t,
            truth: Truth {
                time: t,
                x: 10.0,
                y: 20.0,
                depth,
                heading_deg: 90.0,
                vel_east_mps: 1.0,
                ..Truth::default()
            },
            leak: false,
            battery_drop_v: 0.0,
        }
    }

    #[test]
    fn utc_dates_follow_the_calendar() {
        let u = Utc::from_unix(0.0);
        assert_eq!((u.year, u.month, u.day, u.centis_of_day), (1970, 1, 1, 0));
        // 2000-02-29T23:59:59.99Z, a leap day.
        let u = Utc::from_unix(951_868_799.99);
        assert_eq!((u.year, u.month, u.day), (2000, 2, 29));
        assert_eq!(u.iso(), "2000-02-29T23:59:59.990Z");
        let t = u.time();
        assert_eq!((t.hour, t.minute, t.second), (23, 59, 59.99));
        assert_eq!(
            u.date(),
            Date {
                day: 29,
                month: 2,
                year_2d: 0
            }
        );
        assert_eq!(
            Utc::from_unix(1_795_000_000.0).iso(),
            "2026-11-18T11:06:40.000Z"
        );
    }

    #[test]
    fn nmea_epochs_parse_back_with_the_truth_in_them() {
        let mut settings = GpsSettings::default();
        settings.model.noise_m = 0.0;
        settings.model.loss_prob = 0.0;
        let mut gps = NmeaGps::new(settings, 1);
        // Under water: GGA quality 0, RMC void, no position.
        let out = gps.tick(&at(0.0, 3.0));
        let lines: Vec<_> = out
            .split(|&b| b == b'\n')
            .filter(|l| !l.is_empty())
            .collect();
        assert_eq!(lines.len(), 3);
        let nmea::Sentence::Gga(g) = nmea::parse(lines[0]).unwrap() else {
            panic!()
        };
        assert_eq!((g.quality, g.lat_deg), (0, None));
        let nmea::Sentence::Rmc(r) = nmea::parse(lines[1]).unwrap() else {
            panic!()
        };
        assert!(!r.valid && r.course_deg.is_none());
        // At the surface, after the 2 s acquisition: a fix at the truth's position.
        let mut fixes = Vec::new();
        for k in 1..=20 {
            let out = gps.tick(&at(f64::from(k) * 0.2, 0.0));
            for l in out.split(|&b| b == b'\n').filter(|l| !l.is_empty()) {
                fixes.push(nmea::parse(l).unwrap());
            }
        }
        let ggas: Vec<&Gga> = fixes
            .iter()
            .filter_map(|s| match s {
                nmea::Sentence::Gga(g) => Some(g),
                _ => None,
            })
            .collect();
        assert_eq!(ggas.len(), 20);
        assert_eq!(ggas[8].quality, 0, "1.8 s after surfacing");
        let g = ggas[19];
        assert_eq!(g.quality, 1);
        let grid = LocalGrid::new(40.3394, -111.90721).unwrap();
        let (x, y) = grid
            .to_local(g.lat_deg.unwrap(), g.lon_deg.unwrap())
            .unwrap();
        // Minutes to 1e-5 are about 2 cm.
        assert!(
            (x - 10.0).abs() < 0.03 && (y - 20.0).abs() < 0.03,
            "{x} {y}"
        );
        assert_eq!(g.time.unwrap().seconds_of_day(), 40000.0 + 4.0);
        let rmc = fixes
            .iter()
            .rev()
            .find_map(|s| match s {
                nmea::Sentence::Rmc(r) => Some(r),
                _ => None,
            })
            .unwrap();
        assert!(rmc.valid);
        assert!((rmc.speed_mps().unwrap() - 1.0).abs() < 0.2);
        assert!((rmc.course_deg.unwrap() - 90.0).abs() < 15.0);
        assert_eq!(
            rmc.date,
            Some(Date {
                day: 18,
                month: 11,
                year_2d: 26
            })
        );
    }

    #[test]
    fn gpsd_streams_only_to_a_watcher_and_answers_requests() {
        let mut settings = GpsSettings::default();
        settings.model.loss_prob = 0.0;
        settings.model.acquire_time_s = 0.0;
        let mut d = Gpsd::new(settings, 3);
        let banner = d.connected(&at(0.0, 0.0));
        assert!(
            matches!(gpsd::parse(&banner[..banner.len() - 1]), Ok(gpsd::Report::Other(c)) if c == "VERSION")
        );
        assert!(d.tick(&at(0.0, 0.0)).is_empty(), "nobody watches yet");
        let answer = d.receive(&at(0.1, 0.0), b"?WATCH={\"enable\":true,\"json\":true};");
        let classes: Vec<String> = answer
            .split(|&b| b == b'\n')
            .filter(|l| !l.is_empty())
            .map(|l| match gpsd::parse(l).unwrap() {
                gpsd::Report::Other(c) => c,
                other => panic!("{other:?}"),
            })
            .collect();
        assert_eq!(classes, vec!["DEVICES", "WATCH"]);
        let out = d.tick(&at(0.2, 0.0));
        let reports: Vec<gpsd::Report> = out
            .split(|&b| b == b'\n')
            .filter(|l| !l.is_empty())
            .map(|l| gpsd::parse(l).unwrap())
            .collect();
        let gpsd::Report::Tpv(tpv) = &reports[0] else {
            panic!()
        };
        assert_eq!(tpv.mode, 3);
        assert_eq!(tpv.time.as_deref(), Some("2026-11-18T11:06:40.200Z"));
        assert!((tpv.speed_mps.unwrap() - 1.0).abs() < 0.2);
        assert_eq!(
            reports.len(),
            1,
            "SKY once a second: not on the second epoch"
        );
        let poll = d.receive(&at(0.3, 0.0), b"?POLL;\n");
        assert!(String::from_utf8_lossy(&poll).contains("\"class\":\"POLL\""));
        let err = d.receive(&at(0.3, 0.0), b"?FOO;");
        assert!(String::from_utf8_lossy(&err).contains("\"class\":\"ERROR\""));
        d.receive(&at(0.3, 0.0), b"?WATCH={\"enable\":false};");
        assert!(d.tick(&at(0.4, 0.0)).is_empty());
        // Under water gpsd reports mode 1, no position.
        d.receive(&at(0.4, 0.0), b"?WATCH={\"enable\":true}");
        d.receive(&at(0.4, 0.0), b";");
        let out = d.tick(&at(0.6, 2.0));
        let gpsd::Report::Tpv(tpv) =
            gpsd::parse(out.split(|&b| b == b'\n').next().unwrap()).unwrap()
        else {
            panic!()
        };
        assert_eq!((tpv.mode, tpv.lat_deg), (1, None));
    }
}
