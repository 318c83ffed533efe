//! NMEA 0183 GGA, RMC and VTG sentences (checksums verified; encoders for the emulator) and
//! gpsd's JSON reports TPV and SKY ([`gpsd`]).
//!
//! Layouts follow the NMEA 0183 sentence descriptions as documented publicly (gpsd's "NMEA
//! Revealed", `https://gpsd.gitlab.io/gpsd/NMEA.html`) and `cougars-vehicle.md` §3.3: fields
//! are comma-separated between `$` and `*`, the checksum is the XOR of every byte between
//! them written as two hex digits, lines end with `\r\n`. Empty fields decode to `None`.

use std::fmt::Write as _;

use crate::line::ProtocolError;

/// Why a sentence was refused.
#[derive(Debug, Clone, PartialEq, Eq, thiserror::Error)]
pub enum NmeaError {
    /// The line does not start with `$`.
    #[error("no leading '$'")]
    NoStart,
    /// No `*HH` checksum at the end.
    #[error("no '*HH' checksum")]
    NoChecksum,
    /// The checksum does not match the bytes.
    #[error("checksum {found:02X} where the bytes give {computed:02X}")]
    BadChecksum {
        /// The checksum written in the sentence.
        found: u8,
        /// The checksum of the bytes.
        computed: u8,
    },
    /// Not ASCII text.
    #[error("non-ASCII byte")]
    NotAscii,
    /// The address field is not a two-letter talker and a three-letter type.
    #[error("bad address field")]
    BadAddress,
    /// A sentence type this module does not decode.
    #[error("unsupported sentence {0}")]
    Unsupported(String),
    /// Too few fields for the sentence type.
    #[error("{kind}: {found} fields, at least {needed} needed")]
    TooFewFields {
        /// The sentence type.
        kind: &'static str,
        /// Fields present.
        found: usize,
        /// Fields needed.
        needed: usize,
    },
    /// A field does not parse or is out of range.
    #[error("{kind}: bad field {index} ({what})")]
    BadField {
        /// The sentence type.
        kind: &'static str,
        /// The field's index after the address (1-based).
        index: usize,
        /// What was expected.
        what: &'static str,
    },
}

impl ProtocolError for NmeaError {
    fn is_checksum(&self) -> bool {
        matches!(self, NmeaError::BadChecksum { .. })
    }
}

/// UTC time of day as NMEA writes it (`hhmmss.ss`).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct UtcTime {
    /// Hour, 0–23.
    pub hour: u8,
    /// Minute, 0–59.
    pub minute: u8,
    /// Seconds with their fraction, 0 ≤ s < 61 (a leap second).
    pub second: f64,
}

impl UtcTime {
    /// Seconds since midnight.
    pub fn seconds_of_day(&self) -> f64 {
        f64::from(self.hour) * 3600.0 + f64::from(self.minute) * 60.0 + self.second
    }
}

/// A date as RMC writes it (`ddmmyy`: a two-digit year).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Date {
    /// Day of the month, 1–31.
    pub day: u8,
    /// Month, 1–12.
    pub month: u8,
    /// Two-digit year, 0–99.
    pub year_2d: u8,
}

/// GGA: the fix (time, position, quality, satellites, HDOP, altitude).
#[derive(Debug, Clone, PartialEq)]
pub struct Gga {
    /// Talker id (`GP`, `GN`, ...).
    pub talker: [u8; 2],
    /// UTC time of the fix.
    pub time: Option<UtcTime>,
    /// Latitude, degrees north positive.
    pub lat_deg: Option<f64>,
    /// Longitude, degrees east positive.
    pub lon_deg: Option<f64>,
    /// Fix quality: 0 none, 1 GPS, 2 DGPS/SBAS, 4 RTK fixed, 5 RTK float, ...
    pub quality: u8,
    /// Satellites used.
    pub satellites: Option<u8>,
    /// Horizontal dilution of precision.
    pub hdop: Option<f64>,
    /// Antenna altitude above mean sea level, metres.
    pub altitude_msl_m: Option<f64>,
    /// Geoid separation (geoid above the ellipsoid), metres.
    pub geoid_separation_m: Option<f64>,
    /// Age of the differential corrections, seconds.
    pub dgps_age_s: Option<f64>,
    /// Differential reference station id.
    pub dgps_station: Option<u16>,
}

/// RMC: recommended minimum (time, validity, position, speed, course, date).
#[derive(Debug, Clone, PartialEq)]
pub struct Rmc {
    /// Talker id.
    pub talker: [u8; 2],
    /// UTC time of the fix.
    pub time: Option<UtcTime>,
    /// Status `A` (valid) is true, `V` (warning) false.
    pub valid: bool,
    /// Latitude, degrees north positive.
    pub lat_deg: Option<f64>,
    /// Longitude, degrees east positive.
    pub lon_deg: Option<f64>,
    /// Speed over ground, knots.
    pub speed_kn: Option<f64>,
    /// Course over ground, degrees true.
    pub course_deg: Option<f64>,
    /// Date of the fix.
    pub date: Option<Date>,
    /// Magnetic variation, degrees, east positive.
    pub mag_var_deg: Option<f64>,
    /// FAA mode indicator (NMEA 2.3: `A` autonomous, `D` differential, `N` not valid, ...).
    pub mode: Option<char>,
}

/// VTG: course and speed over ground.
#[derive(Debug, Clone, PartialEq)]
pub struct Vtg {
    /// Talker id.
    pub talker: [u8; 2],
    /// Course over ground, degrees true.
    pub course_true_deg: Option<f64>,
    /// Course over ground, degrees magnetic.
    pub course_mag_deg: Option<f64>,
    /// Speed over ground, knots.
    pub speed_kn: Option<f64>,
    /// Speed over ground, km/h.
    pub speed_kmh: Option<f64>,
    /// FAA mode indicator (NMEA 2.3).
    pub mode: Option<char>,
}

/// One decoded sentence.
#[derive(Debug, Clone, PartialEq)]
pub enum Sentence {
    /// A GGA sentence.
    Gga(Gga),
    /// An RMC sentence.
    Rmc(Rmc),
    /// A VTG sentence.
    Vtg(Vtg),
}

impl Sentence {
    /// The sentence type: `GGA`, `RMC` or `VTG`.
    pub fn kind(&self) -> &'static str {
        match self {
            Sentence::Gga(_) => "GGA",
            Sentence::Rmc(_) => "RMC",
            Sentence::Vtg(_) => "VTG",
        }
    }

    /// The sentence with its checksum and `\r\n`.
    pub fn encode(&self) -> String {
        match self {
            Sentence::Gga(s) => s.encode(),
            Sentence::Rmc(s) => s.encode(),
            Sentence::Vtg(s) => s.encode(),
        }
    }
}

/// The longest sentence accepted (NMEA allows 82 characters; some receivers write more).
pub const MAX_LINE: usize = 120;

/// Knots to metres per second.
pub const MPS_PER_KNOT: f64 = 1852.0 / 3600.0;

/// The XOR of `body`'s bytes (the NMEA checksum of what lies between `$` and `*`).
pub fn checksum(body: &[u8]) -> u8 {
    body.iter().fold(0, |a, b| a ^ b)
}

/// `$` + `body` + `*HH\r\n`: a sentence with its checksum.
pub fn with_checksum(body: &str) -> String {
    format!("${body}*{:02X}\r\n", checksum(body.as_bytes()))
}

/// Checks the framing and checksum of `line` (a trailing `\r\n` is allowed) and returns the fields
/// between `$` and `*`, the address first.
pub fn split_checked(line: &[u8]) -> Result<Vec<&str>, NmeaError> {
    let line = line.strip_suffix(b"\n").unwrap_or(line);
    let line = line.strip_suffix(b"\r").unwrap_or(line);
    let rest = line.strip_prefix(b"$").ok_or(NmeaError::NoStart)?;
    if !rest.is_ascii() {
        return Err(NmeaError::NotAscii);
    }
    let star = rest
        .iter()
        .rposition(|&b| b == b'*')
        .ok_or(NmeaError::NoChecksum)?;
    let (body, sum) = (&rest[..star], &rest[star + 1..]);
    let found = match sum {
        [h, l] => match (hex_val(*h), hex_val(*l)) {
            (Some(h), Some(l)) => h << 4 | l,
            _ => return Err(NmeaError::NoChecksum),
        },
        _ => return Err(NmeaError::NoChecksum),
    };
    let computed = checksum(body);
    if found != computed {
        return Err(NmeaError::BadChecksum { found, computed });
    }
    // ASCII was checked above, so this cannot fail; map anyway rather than unwrap.
    let body = std::str::from_utf8(body).map_err(|_| NmeaError::NotAscii)?;
    Ok(body.split(',').collect())
}

fn hex_val(b: u8) -> Option<u8> {
    (b as char).to_digit(16).map(|d| d as u8)
}

/// Parses one GGA, RMC or VTG sentence (any talker), checksum required.
pub fn parse(line: &[u8]) -> Result<Sentence, NmeaError> {
    let f = split_checked(line)?;
    let addr = f[0].as_bytes();
    if addr.len() != 5
        || !addr
            .iter()
            .all(|b| b.is_ascii_uppercase() || b.is_ascii_digit())
    {
        return Err(NmeaError::BadAddress);
    }
    let talker = [addr[0], addr[1]];
    match &f[0][2..] {
        "GGA" => parse_gga(talker, &f).map(Sentence::Gga),
        "RMC" => parse_rmc(talker, &f).map(Sentence::Rmc),
        "VTG" => parse_vtg(talker, &f).map(Sentence::Vtg),
        other => Err(NmeaError::Unsupported(other.to_string())),
    }
}

struct Fields<'a> {
    kind: &'static str,
    f: &'a [&'a str],
}

impl<'a> Fields<'a> {
    fn need(kind: &'static str, f: &'a [&'a str], needed: usize) -> Result<Self, NmeaError> {
        if f.len() - 1 < needed {
            return Err(NmeaError::TooFewFields {
                kind,
                found: f.len() - 1,
                needed,
            });
        }
        Ok(Fields { kind, f })
    }
    fn bad(&self, index: usize, what: &'static str) -> NmeaError {
        NmeaError::BadField {
            kind: self.kind,
            index,
            what,
        }
    }
    fn raw(&self, i: usize) -> &'a str {
        self.f.get(i).copied().unwrap_or("")
    }
    fn num(&self, i: usize) -> Result<Option<f64>, NmeaError> {
        let s = self.raw(i);
        if s.is_empty() {
            return Ok(None);
        }
        let plain = s
            .bytes()
            .all(|b| b.is_ascii_digit() || b == b'.' || b == b'-' || b == b'+');
        match s.parse::<f64>() {
            Ok(v) if plain && v.is_finite() => Ok(Some(v)),
            _ => Err(self.bad(i, "a number")),
        }
    }
    fn int<T: std::str::FromStr>(&self, i: usize) -> Result<Option<T>, NmeaError> {
        let s = self.raw(i);
        if s.is_empty() {
            return Ok(None);
        }
        if !s.bytes().all(|b| b.is_ascii_digit()) {
            return Err(self.bad(i, "an integer"));
        }
        s.parse().map(Some).map_err(|_| self.bad(i, "an integer"))
    }
    fn time(&self, i: usize) -> Result<Option<UtcTime>, NmeaError> {
        let s = self.raw(i);
        if s.is_empty() {
            return Ok(None);
        }
        let b = s.as_bytes();
        if b.len() < 6 || !b[..6].iter().all(u8::is_ascii_digit) {
            return Err(self.bad(i, "hhmmss.ss"));
        }
        let two = |k: usize| (b[k] - b'0') * 10 + (b[k + 1] - b'0');
        let (hour, minute) = (two(0), two(2));
        let frac_ok = b[6..].is_empty() || (b[6] == b'.' && b[7..].iter().all(u8::is_ascii_digit));
        let second: f64 = match s[4..].parse() {
            Ok(v) if frac_ok => v,
            _ => return Err(self.bad(i, "hhmmss.ss")),
        };
        if hour > 23 || minute > 59 || !(0.0..61.0).contains(&second) {
            return Err(self.bad(i, "a time of day"));
        }
        Ok(Some(UtcTime {
            hour,
            minute,
            second,
        }))
    }
    /// `ddmm.mmmm` (or `dddmm.mmmm`) and its hemisphere at `i + 1`.
    fn coord(&self, i: usize, pos: u8, neg: u8, max_deg: f64) -> Result<Option<f64>, NmeaError> {
        let (s, h) = (self.raw(i), self.raw(i + 1));
        if s.is_empty() && h.is_empty() {
            return Ok(None);
        }
        let v = self.num(i)?.ok_or(self.bad(i, "a coordinate"))?;
        if v < 0.0 {
            return Err(self.bad(i, "a coordinate"));
        }
        let deg = (v / 100.0).floor();
        let min = v - deg * 100.0;
        if min >= 60.0 {
            return Err(self.bad(i, "minutes under 60"));
        }
        let d = deg + min / 60.0;
        if d > max_deg {
            return Err(self.bad(i, "a coordinate in range"));
        }
        match h.as_bytes() {
            [c] if *c == pos => Ok(Some(d)),
            [c] if *c == neg => Ok(Some(-d)),
            _ => Err(self.bad(i + 1, "a hemisphere")),
        }
    }
    fn char(&self, i: usize) -> Result<Option<char>, NmeaError> {
        match self.raw(i).as_bytes() {
            [] => Ok(None),
            [c] if c.is_ascii_alphabetic() => Ok(Some(*c as char)),
            _ => Err(self.bad(i, "one letter")),
        }
    }
    fn unit(&self, i: usize, unit: &str) -> Result<(), NmeaError> {
        let s = self.raw(i);
        if s.is_empty() || s == unit {
            Ok(())
        } else {
            Err(self.bad(i, "a unit letter"))
        }
    }
}

fn parse_gga(talker: [u8; 2], f: &[&str]) -> Result<Gga, NmeaError> {
    let x = Fields::need("GGA", f, 14)?;
    x.unit(10, "M")?;
    x.unit(12, "M")?;
    Ok(Gga {
        talker,
        time: x.time(1)?,
        lat_deg: x.coord(2, b'N', b'S', 90.0)?,
        lon_deg: x.coord(4, b'E', b'W', 180.0)?,
        quality: x.int(6)?.unwrap_or(0),
        satellites: x.int(7)?,
        hdop: x.num(8)?,
        altitude_msl_m: x.num(9)?,
        geoid_separation_m: x.num(11)?,
        dgps_age_s: x.num(13)?,
        dgps_station: x.int(14)?,
    })
}

fn parse_rmc(talker: [u8; 2], f: &[&str]) -> Result<Rmc, NmeaError> {
    let x = Fields::need("RMC", f, 11)?;
    let valid = match x.raw(2) {
        "A" => true,
        "V" => false,
        _ => return Err(x.bad(2, "A or V")),
    };
    let date = match x.raw(9).as_bytes() {
        [] => None,
        b if b.len() == 6 && b.iter().all(u8::is_ascii_digit) => {
            let two = |k: usize| (b[k] - b'0') * 10 + (b[k + 1] - b'0');
            let (day, month, year_2d) = (two(0), two(2), two(4));
            if !(1..=31).contains(&day) || !(1..=12).contains(&month) {
                return Err(x.bad(9, "a date"));
            }
            Some(Date {
                day,
                month,
                year_2d,
            })
        }
        _ => return Err(x.bad(9, "ddmmyy")),
    };
    let mag_var_deg = match (x.num(10)?, x.raw(11)) {
        (None, _) => None,
        (Some(v), "E") => Some(v),
        (Some(v), "W") => Some(-v),
        _ => return Err(x.bad(11, "E or W")),
    };
    Ok(Rmc {
        talker,
        time: x.time(1)?,
        valid,
        lat_deg: x.coord(3, b'N', b'S', 90.0)?,
        lon_deg: x.coord(5, b'E', b'W', 180.0)?,
        speed_kn: x.num(7)?,
        course_deg: x.num(8)?,
        date,
        mag_var_deg,
        mode: x.char(12)?,
    })
}

fn parse_vtg(talker: [u8; 2], f: &[&str]) -> Result<Vtg, NmeaError> {
    let x = Fields::need("VTG", f, 8)?;
    x.unit(2, "T")?;
    x.unit(4, "M")?;
    x.unit(6, "N")?;
    x.unit(8, "K")?;
    Ok(Vtg {
        talker,
        course_true_deg: x.num(1)?,
        course_mag_deg: x.num(3)?,
        speed_kn: x.num(5)?,
        speed_kmh: x.num(7)?,
        mode: x.char(9)?,
    })
}

fn talker_str(t: &[u8; 2]) -> String {
    t.iter()
        .map(|&b| {
            if b.is_ascii_uppercase() || b.is_ascii_digit() {
                b as char
            } else {
                'X'
            }
        })
        .collect()
}

fn put_time(out: &mut String, t: Option<UtcTime>) {
    if let Some(t) = t {
        // Hundredths, carried so that 59.999 s never prints as "60.00".
        let cs = (t.second.clamp(0.0, 60.99) * 100.0).round() as u32;
        let _ = write!(
            out,
            "{:02}{:02}{:02}.{:02}",
            t.hour.min(23),
            t.minute.min(59),
            cs / 100,
            cs % 100
        );
    }
}

fn put_num(out: &mut String, v: Option<f64>, decimals: usize) {
    if let Some(v) = v.filter(|v| v.is_finite()) {
        let _ = write!(out, "{v:.decimals$}");
    }
}

fn put_coord(out: &mut String, v: Option<f64>, deg_digits: usize, pos: char, neg: char) {
    let Some(v) = v.filter(|v| v.is_finite()) else {
        out.push(',');
        return;
    };
    // In units of 1e-5 minute, so the minutes never round up to 60.
    let units = (v.abs() * 60.0 * 1e5).round() as u64;
    let (deg, rest) = (units / 6_000_000, units % 6_000_000);
    let _ = write!(
        out,
        "{deg:0deg_digits$}{:02}.{:05},{}",
        rest / 100_000,
        rest % 100_000,
        if v < 0.0 && units > 0 { neg } else { pos }
    );
}

impl Gga {
    /// The sentence with its checksum and `\r\n` (time to hundredths, minutes to 1e-5).
    pub fn encode(&self) -> String {
        let mut b = format!("{}GGA,", talker_str(&self.talker));
        put_time(&mut b, self.time);
        b.push(',');
        put_coord(&mut b, self.lat_deg, 2, 'N', 'S');
        b.push(',');
        put_coord(&mut b, self.lon_deg, 3, 'E', 'W');
        let _ = write!(b, ",{},", self.quality);
        if let Some(n) = self.satellites {
            let _ = write!(b, "{n:02}");
        }
        b.push(',');
        put_num(&mut b, self.hdop, 1);
        b.push(',');
        put_num(&mut b, self.altitude_msl_m, 1);
        b.push_str(",M,");
        put_num(&mut b, self.geoid_separation_m, 1);
        b.push_str(",M,");
        put_num(&mut b, self.dgps_age_s, 1);
        b.push(',');
        if let Some(n) = self.dgps_station {
            let _ = write!(b, "{n:04}");
        }
        with_checksum(&b)
    }
}

impl Rmc {
    /// The sentence with its checksum and `\r\n`.
    pub fn encode(&self) -> String {
        let mut b = format!("{}RMC,", talker_str(&self.talker));
        put_time(&mut b, self.time);
        b.push_str(if self.valid { ",A," } else { ",V," });
        put_coord(&mut b, self.lat_deg, 2, 'N', 'S');
        b.push(',');
        put_coord(&mut b, self.lon_deg, 3, 'E', 'W');
        b.push(',');
        put_num(&mut b, self.speed_kn, 3);
        b.push(',');
        put_num(&mut b, self.course_deg, 2);
        b.push(',');
        if let Some(d) = self.date {
            let _ = write!(
                b,
                "{:02}{:02}{:02}",
                d.day.clamp(1, 31),
                d.month.clamp(1, 12),
                d.year_2d.min(99)
            );
        }
        b.push(',');
        match self.mag_var_deg.filter(|v| v.is_finite()) {
            Some(v) => {
                // The direction of what is written: a value that rounds to 0.0 is east, so
                // it reads back as it was written.
                let tenths = (v.abs() * 10.0).round();
                let dir = if v < 0.0 && tenths > 0.0 { 'W' } else { 'E' };
                let _ = write!(b, "{:.1},{dir}", tenths / 10.0);
            }
            None => b.push(','),
        }
        if let Some(m) = self.mode.filter(char::is_ascii_alphabetic) {
            let _ = write!(b, ",{m}");
        }
        with_checksum(&b)
    }

    /// Speed over ground in metres per second.
    pub fn speed_mps(&self) -> Option<f64> {
        self.speed_kn.map(|k| k * MPS_PER_KNOT)
    }
}

impl Vtg {
    /// The sentence with its checksum and `\r\n`.
    pub fn encode(&self) -> String {
        let mut b = format!("{}VTG,", talker_str(&self.talker));
        put_num(&mut b, self.course_true_deg, 1);
        b.push_str(",T,");
        put_num(&mut b, self.course_mag_deg, 1);
        b.push_str(",M,");
        put_num(&mut b, self.speed_kn, 1);
        b.push_str(",N,");
        put_num(&mut b, self.speed_kmh, 1);
        b.push_str(",K");
        if let Some(m) = self.mode.filter(char::is_ascii_alphabetic) {
            let _ = write!(b, ",{m}");
        }
        with_checksum(&b)
    }
}

pub mod gpsd {
    //! gpsd's JSON reports (gpsd_json(5), `https://gpsd.io/gpsd_json.html`): TPV (time,
    //! position, velocity) and SKY (dilutions and satellites), one JSON object per line, each
    //! with a `class`.

    use serde_json::{Map, Value, json};

    use crate::line::ProtocolError;

    /// Why a gpsd line was refused.
    #[derive(Debug, Clone, PartialEq, Eq, thiserror::Error)]
    pub enum GpsdError {
        /// Not a JSON object.
        #[error("not JSON: {0}")]
        Json(String),
        /// No `class` member.
        #[error("no class")]
        NoClass,
        /// A member of the wrong JSON type.
        #[error("member {0} has the wrong type")]
        BadMember(&'static str),
    }

    impl ProtocolError for GpsdError {
        fn is_checksum(&self) -> bool {
            false
        }
    }

    /// A TPV report. gpsd omits what it does not know; so do these fields.
    #[derive(Debug, Clone, PartialEq, Default)]
    pub struct Tpv {
        /// The device path.
        pub device: Option<String>,
        /// ISO 8601 UTC time of the fix, as gpsd wrote it.
        pub time: Option<String>,
        /// Fix mode: 0 unknown, 1 no fix, 2 2D, 3 3D.
        pub mode: u8,
        /// Latitude, degrees.
        pub lat_deg: Option<f64>,
        /// Longitude, degrees.
        pub lon_deg: Option<f64>,
        /// Altitude (`altMSL`, else the older `alt`), metres.
        pub alt_m: Option<f64>,
        /// Course over ground, degrees true.
        pub track_deg: Option<f64>,
        /// Speed over ground, metres per second.
        pub speed_mps: Option<f64>,
        /// Climb rate, metres per second.
        pub climb_mps: Option<f64>,
        /// Horizontal position error estimate, metres.
        pub eph_m: Option<f64>,
        /// Vertical position error estimate, metres.
        pub epv_m: Option<f64>,
        /// Time error estimate, seconds.
        pub ept_s: Option<f64>,
    }

    /// One satellite of a SKY report.
    #[derive(Debug, Clone, PartialEq, Default)]
    pub struct Satellite {
        /// PRN (satellite id).
        pub prn: i64,
        /// Elevation, degrees.
        pub el_deg: Option<f64>,
        /// Azimuth, degrees true.
        pub az_deg: Option<f64>,
        /// Signal to noise, dB-Hz.
        pub ss_dbhz: Option<f64>,
        /// Used in the fix.
        pub used: bool,
    }

    /// A SKY report.
    #[derive(Debug, Clone, PartialEq, Default)]
    pub struct Sky {
        /// The device path.
        pub device: Option<String>,
        /// ISO 8601 UTC time.
        pub time: Option<String>,
        /// Horizontal dilution of precision.
        pub hdop: Option<f64>,
        /// Vertical dilution of precision.
        pub vdop: Option<f64>,
        /// Position dilution of precision.
        pub pdop: Option<f64>,
        /// Satellites in view.
        pub satellites: Vec<Satellite>,
    }

    /// The longest gpsd line accepted (a SKY report with many satellites runs to kilobytes).
    pub const MAX_LINE: usize = 16384;

    /// One gpsd report.
    #[derive(Debug, Clone, PartialEq)]
    pub enum Report {
        /// A TPV report.
        Tpv(Tpv),
        /// A SKY report.
        Sky(Sky),
        /// Another class (VERSION, DEVICES, WATCH, ...), by name.
        Other(String),
    }

    fn num(o: &Map<String, Value>, k: &'static str) -> Result<Option<f64>, GpsdError> {
        match o.get(k) {
            None | Some(Value::Null) => Ok(None),
            Some(v) => v.as_f64().map(Some).ok_or(GpsdError::BadMember(k)),
        }
    }

    fn text(o: &Map<String, Value>, k: &'static str) -> Result<Option<String>, GpsdError> {
        match o.get(k) {
            None | Some(Value::Null) => Ok(None),
            Some(Value::String(s)) => Ok(Some(s.clone())),
            Some(_) => Err(GpsdError::BadMember(k)),
        }
    }

    /// Parses one gpsd JSON line.
    pub fn parse(line: &[u8]) -> Result<Report, GpsdError> {
        let v: Value = serde_json::from_slice(line).map_err(|e| GpsdError::Json(e.to_string()))?;
        let o = v
            .as_object()
            .ok_or(GpsdError::Json("not an object".into()))?;
        let class = match o.get("class") {
            Some(Value::String(c)) => c.as_str(),
            _ => return Err(GpsdError::NoClass),
        };
        match class {
            "TPV" => Ok(Report::Tpv(Tpv {
                device: text(o, "device")?,
                time: text(o, "time")?,
                mode: match o.get("mode") {
                    None => 0,
                    Some(m) => m
                        .as_u64()
                        .filter(|m| *m <= 3)
                        .ok_or(GpsdError::BadMember("mode"))? as u8,
                },
                lat_deg: num(o, "lat")?,
                lon_deg: num(o, "lon")?,
                alt_m: match num(o, "altMSL")? {
                    Some(a) => Some(a),
                    None => num(o, "alt")?,
                },
                track_deg: num(o, "track")?,
                speed_mps: num(o, "speed")?,
                climb_mps: num(o, "climb")?,
                eph_m: num(o, "eph")?,
                epv_m: num(o, "epv")?,
                ept_s: num(o, "ept")?,
            })),
            "SKY" => {
                let mut satellites = Vec::new();
                match o.get("satellites") {
                    None | Some(Value::Null) => {}
                    Some(Value::Array(a)) => {
                        for s in a {
                            let s = s.as_object().ok_or(GpsdError::BadMember("satellites"))?;
                            satellites.push(Satellite {
                                prn: s
                                    .get("PRN")
                                    .and_then(Value::as_i64)
                                    .ok_or(GpsdError::BadMember("PRN"))?,
                                el_deg: num(s, "el")?,
                                az_deg: num(s, "az")?,
                                ss_dbhz: num(s, "ss")?,
                                used: match s.get("used") {
                                    None => false,
                                    Some(u) => u.as_bool().ok_or(GpsdError::BadMember("used"))?,
                                },
                            });
                        }
                    }
                    Some(_) => return Err(GpsdError::BadMember("satellites")),
                }
                Ok(Report::Sky(Sky {
                    device: text(o, "device")?,
                    time: text(o, "time")?,
                    hdop: num(o, "hdop")?,
                    vdop: num(o, "vdop")?,
                    pdop: num(o, "pdop")?,
                    satellites,
                }))
            }
            other => Ok(Report::Other(other.to_string())),
        }
    }

    fn put(o: &mut Map<String, Value>, k: &str, v: Option<f64>) {
        if let Some(v) = v.filter(|v| v.is_finite()) {
            o.insert(k.into(), json!(v));
        }
    }

    fn put_text(o: &mut Map<String, Value>, k: &str, v: &Option<String>) {
        if let Some(v) = v {
            o.insert(k.into(), json!(v));
        }
    }

    impl Tpv {
        /// The report as gpsd writes it: one JSON line with its `\n` (altitude as `altMSL`).
        pub fn encode(&self) -> String {
            let mut o = Map::new();
            o.insert("class".into(), json!("TPV"));
            put_text(&mut o, "device", &self.device);
            put_text(&mut o, "time", &self.time);
            o.insert("mode".into(), json!(self.mode.min(3)));
            put(&mut o, "lat", self.lat_deg);
            put(&mut o, "lon", self.lon_deg);
            put(&mut o, "altMSL", self.alt_m);
            put(&mut o, "track", self.track_deg);
            put(&mut o, "speed", self.speed_mps);
            put(&mut o, "climb", self.climb_mps);
            put(&mut o, "eph", self.eph_m);
            put(&mut o, "epv", self.epv_m);
            put(&mut o, "ept", self.ept_s);
            format!("{}\n", Value::Object(o))
        }
    }

    impl Sky {
        /// The report as one JSON line with its `\n`.
        pub fn encode(&self) -> String {
            let mut o = Map::new();
            o.insert("class".into(), json!("SKY"));
            put_text(&mut o, "device", &self.device);
            put_text(&mut o, "time", &self.time);
            put(&mut o, "hdop", self.hdop);
            put(&mut o, "vdop", self.vdop);
            put(&mut o, "pdop", self.pdop);
            let sats: Vec<Value> = self
                .satellites
                .iter()
                .map(|s| {
                    let mut m = Map::new();
                    m.insert("PRN".into(), json!(s.prn));
                    put(&mut m, "el", s.el_deg);
                    put(&mut m, "az", s.az_deg);
                    put(&mut m, "ss", s.ss_dbhz);
                    m.insert("used".into(), json!(s.used));
                    Value::Object(m)
                })
                .collect();
            o.insert("satellites".into(), Value::Array(sats));
            format!("{}\n", Value::Object(o))
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use proptest::prelude::*;

    // The worked examples of the public NMEA descriptions (gpsd "NMEA Revealed" and the
    // widely reproduced Dale DePriester sentence list), checksums as published.
    const GGA: &[u8] = b"$GPGGA,123519,4807.038,N,01131.000,E,1,08,0.9,545.4,M,46.9,M,,*47";
    const RMC: &[u8] = b"$GPRMC,123519,A,4807.038,N,01131.000,E,022.4,084.4,230394,003.1,W*6A";
    const VTG: &[u8] = b"$GPVTG,054.7,T,034.4,M,005.5,N,010.2,K*48";

    fn close(a: Option<f64>, b: f64) -> bool {
        a.is_some_and(|a| (a - b).abs() < 1e-9)
    }

    #[test]
    fn documented_gga_decodes() {
        let Sentence::Gga(g) = parse(GGA).unwrap() else {
            panic!()
        };
        assert_eq!(g.talker, *b"GP");
        assert_eq!(
            g.time.unwrap().seconds_of_day(),
            12.0 * 3600.0 + 35.0 * 60.0 + 19.0
        );
        assert!(close(g.lat_deg, 48.0 + 7.038 / 60.0));
        assert!(close(g.lon_deg, 11.0 + 31.0 / 60.0));
        assert_eq!((g.quality, g.satellites), (1, Some(8)));
        assert!(close(g.hdop, 0.9) && close(g.altitude_msl_m, 545.4));
        assert!(close(g.geoid_separation_m, 46.9));
        assert_eq!((g.dgps_age_s, g.dgps_station), (None, None));
    }

    #[test]
    fn documented_rmc_and_vtg_decode() {
        let Sentence::Rmc(r) = parse(RMC).unwrap() else {
            panic!()
        };
        assert!(r.valid);
        assert!(close(r.speed_kn, 22.4) && close(r.course_deg, 84.4));
        assert!(close(r.speed_mps(), 22.4 * 1852.0 / 3600.0));
        assert_eq!(
            r.date,
            Some(Date {
                day: 23,
                month: 3,
                year_2d: 94
            })
        );
        assert!(close(r.mag_var_deg, -3.1));
        assert_eq!(r.mode, None);
        let Sentence::Vtg(v) = parse(VTG).unwrap() else {
            panic!()
        };
        assert!(close(v.course_true_deg, 54.7) && close(v.course_mag_deg, 34.4));
        assert!(close(v.speed_kn, 5.5) && close(v.speed_kmh, 10.2));
    }

    #[test]
    fn checksums_and_framing_are_enforced() {
        let mut bad = GGA.to_vec();
        let n = bad.len();
        bad[n - 1] = b'8';
        assert_eq!(
            parse(&bad),
            Err(NmeaError::BadChecksum {
                found: 0x48,
                computed: 0x47
            })
        );
        assert_eq!(parse(&GGA[1..]), Err(NmeaError::NoStart));
        assert_eq!(parse(&GGA[..n - 3]), Err(NmeaError::NoChecksum));
        assert!(matches!(
            parse(with_checksum("GPGSV,1,1,00").as_bytes()),
            Err(NmeaError::Unsupported(_))
        ));
        assert!(matches!(
            parse(with_checksum("GPGGA,123519,4867.0,N,,,1,,,,,,,,").as_bytes()),
            Err(NmeaError::BadField { index: 2, .. })
        ));
        assert!(matches!(
            parse(with_checksum("GPGGA,1,inf").as_bytes()),
            Err(NmeaError::TooFewFields { .. })
        ));
    }

    #[test]
    fn the_cougars_constructor_layout_round_trips() {
        // nmea_constructor.py (§3.3): GGA with 4 satellites and HDOP 1.5, RMC with mode A.
        let g = Gga {
            talker: *b"GP",
            time: Some(UtcTime {
                hour: 17,
                minute: 5,
                second: 9.25,
            }),
            lat_deg: Some(40.246_1),
            lon_deg: Some(-111.648_2),
            quality: 1,
            satellites: Some(4),
            hdop: Some(1.5),
            altitude_msl_m: Some(1372.0),
            geoid_separation_m: Some(-17.2),
            dgps_age_s: None,
            dgps_station: None,
        };
        let line = g.encode();
        assert!(line.starts_with("$GPGGA,170509.25,4014.76600,N,11138.89200,W,1,04,1.5,"));
        assert!(line.ends_with("\r\n"));
        let back = parse(line.trim_end().as_bytes()).unwrap();
        assert_eq!(back.encode(), line);
    }

    fn opt<T: std::fmt::Debug + Clone>(
        s: impl Strategy<Value = T>,
    ) -> impl Strategy<Value = Option<T>> {
        proptest::option::of(s)
    }

    fn time() -> impl Strategy<Value = UtcTime> {
        (0u8..24, 0u8..60, 0u32..6000).prop_map(|(hour, minute, cs)| UtcTime {
            hour,
            minute,
            second: f64::from(cs) / 100.0,
        })
    }

    proptest! {
        #[test]
        fn arbitrary_bytes_never_panic(data in proptest::collection::vec(any::<u8>(), 0..120)) {
            let _ = parse(&data);
            let _ = gpsd::parse(&data);
            let mut framed = b"$".to_vec();
            framed.extend_from_slice(&data);
            let _ = parse(&framed);
        }

        #[test]
        fn gga_encode_decode_is_identity_on_the_wire(
            t in opt(time()), lat in opt(-90.0f64..90.0), lon in opt(-180.0f64..180.0),
            q in 0u8..9, n in opt(0u8..40), hdop in opt(0.0f64..50.0),
            alt in opt(-100.0f64..9000.0), geo in opt(-100.0f64..100.0),
        ) {
            let g = Gga { talker: *b"GN", time: t, lat_deg: lat, lon_deg: lon, quality: q,
                satellites: n, hdop, altitude_msl_m: alt, geoid_separation_m: geo,
                dgps_age_s: None, dgps_station: None };
            let line = g.encode();
            let back = parse(line.trim_end().as_bytes()).unwrap();
            prop_assert_eq!(back.encode(), line);
            let Sentence::Gga(b) = back else { panic!() };
            if let (Some(a), Some(b)) = (lat, b.lat_deg) { prop_assert!((a - b).abs() < 1e-6); }
            if let (Some(a), Some(b)) = (lon, b.lon_deg) { prop_assert!((a - b).abs() < 1e-6); }
        }

        #[test]
        fn rmc_and_vtg_encode_decode_is_identity_on_the_wire(
            t in opt(time()), valid in any::<bool>(), lat in opt(-90.0f64..90.0),
            sog in opt(0.0f64..100.0), cog in opt(0.0f64..360.0),
            d in opt((1u8..32, 1u8..13, 0u8..100)), var in opt(-30.0f64..30.0),
            mode in opt(prop::sample::select(vec!['A', 'D', 'N', 'E'])),
        ) {
            let r = Rmc { talker: *b"GP", time: t, valid, lat_deg: lat, lon_deg: lat.map(|l| l * 2.0),
                speed_kn: sog, course_deg: cog,
                date: d.map(|(day, month, year_2d)| Date { day, month, year_2d }),
                mag_var_deg: var, mode };
            let line = r.encode();
            prop_assert_eq!(parse(line.trim_end().as_bytes()).unwrap().encode(), line);
            let v = Vtg { talker: *b"GP", course_true_deg: cog, course_mag_deg: cog,
                speed_kn: sog, speed_kmh: sog.map(|s| s * 1.852), mode };
            let line = v.encode();
            prop_assert_eq!(parse(line.trim_end().as_bytes()).unwrap().encode(), line);
        }
    }

    /// Found by the proptest above: a westerly variation under 0.05 degrees was written
    /// `0.0,W` and read back as east; it is written `0.0,E` now.
    #[test]
    fn a_variation_that_rounds_to_zero_is_written_east() {
        let r = Rmc {
            talker: *b"GP",
            time: None,
            valid: false,
            lat_deg: None,
            lon_deg: None,
            speed_kn: None,
            course_deg: None,
            date: None,
            mag_var_deg: Some(-0.0054),
            mode: None,
        };
        let line = r.encode();
        assert!(line.contains(",0.0,E"), "{line}");
        assert_eq!(parse(line.trim_end().as_bytes()).unwrap().encode(), line);
        let west = Rmc {
            mag_var_deg: Some(-3.26),
            ..r
        };
        assert!(west.encode().contains(",3.3,W"), "{}", west.encode());
    }

    #[test]
    fn documented_gpsd_tpv_and_sky_decode_and_round_trip() {
        // The examples of gpsd_json(5) (TPV and SKY sections).
        let tpv = br#"{"class":"TPV","device":"/dev/pts/1","time":"2005-06-08T10:34:48.283Z","ept":0.005,"lat":46.498293369,"lon":7.567411672,"alt":1343.127,"eph":36.000,"epv":32.321,"track":10.3788,"speed":0.091,"climb":-0.085,"mode":3}"#;
        let gpsd::Report::Tpv(t) = gpsd::parse(tpv).unwrap() else {
            panic!()
        };
        assert_eq!(t.mode, 3);
        assert_eq!(t.lat_deg, Some(46.498293369));
        assert_eq!(
            (t.alt_m, t.speed_mps, t.ept_s),
            (Some(1343.127), Some(0.091), Some(0.005))
        );
        assert_eq!(gpsd::parse(t.encode().as_bytes()), Ok(gpsd::Report::Tpv(t)));
        let sky = br#"{"class":"SKY","device":"/dev/pts/1","time":"2005-07-08T11:28:07.114Z","xdop":1.55,"hdop":1.24,"pdop":1.99,"satellites":[{"PRN":23,"el":6,"az":84,"ss":0,"used":false},{"PRN":28,"el":7,"az":160,"ss":0,"used":false},{"PRN":8,"el":66,"az":189,"ss":44,"used":true}]}"#;
        let gpsd::Report::Sky(s) = gpsd::parse(sky).unwrap() else {
            panic!()
        };
        assert_eq!((s.hdop, s.pdop, s.vdop), (Some(1.24), Some(1.99), None));
        assert_eq!(s.satellites.len(), 3);
        assert!(s.satellites[2].used && s.satellites[2].ss_dbhz == Some(44.0));
        assert_eq!(gpsd::parse(s.encode().as_bytes()), Ok(gpsd::Report::Sky(s)));
        assert_eq!(
            gpsd::parse(br#"{"class":"VERSION","release":"3.22"}"#),
            Ok(gpsd::Report::Other("VERSION".into()))
        );
        assert_eq!(gpsd::parse(br#"{"mode":3}"#), Err(gpsd::GpsdError::NoClass));
        assert_eq!(
            gpsd::parse(br#"{"class":"TPV","mode":"3"}"#),
            Err(gpsd::GpsdError::BadMember("mode"))
        );
    }
}
