//! MOOS `NodeRecord` as text: the one node-report parse (`string2NodeRecord`: the
//! comma-separated `KEY=value` form, or JSON in braces) and the record written back
//! (`NodeRecord::getSpec`). The helm's contact ledger, the contact managers, uFldNodeComms,
//! the viewer and the shoreside read reports through it.
//!
//! As `string2NodeRecordCSP`: keys are case-insensitive; `NAME`, `TYPE`, `MODE`, `ALLSTOP`
//! and `INDEX` are taken whatever their value; the numeric fields (`TIME`/`UTC_TIME`, `X`, `Y`,
//! `LAT`, `LON`, `SPD`/`SPEED`, `HDG`/`HEADING`, `DEP`/`DEPTH`, `LENGTH`/`LEN`, `YAW`,
//! `ALT`/`ALTITUDE`, `HDG_OG`, `COG`, `SPD_OG`, `TRANSPARENCY`) only with a value
//! [`crate::text::is_number`] accepts, and any other key with a numeric value is a property;
//! then `COLOR`, `GROUP`, `VSOURCE`, `LOAD_WARNING`, `THRUST_MODE_REVERSE=true` and
//! `TRAJECTORY` (braces stripped); anything else is a property. So a numeric `COLOR` or
//! `GROUP` is a property, not the colour or group, as in the C++. A later field wins.
//!
//! ```
//! use moos_types::node_record::NodeRecord;
//! let r = NodeRecord::parse("NAME=abe,X=10,Y=-5,SPD=1.5,HDG=90,GROUP=red,TIME=12.5");
//! assert_eq!((r.name.as_str(), r.x, r.speed), ("abe", Some(10.0), Some(1.5)));
//! assert!(r.valid());
//! assert_eq!(r.spec(), "NAME=abe,X=10,Y=-5,SPD=1.5,HDG=90,GROUP=red,TIME=12.5");
//! let j = NodeRecord::parse(r#"{"NAME":"abe","X":"10","Y":"-5","SPD":"1.5","HDG":"90"}"#);
//! assert_eq!((j.name.as_str(), j.heading), ("abe", Some(90.0)));
//! ```

use std::borrow::Cow;
use std::collections::BTreeMap;
use std::fmt::Write as _;

use crate::fmt::compact_string;
use crate::text::{atof, is_number};

/// A node report as MOOS `NodeRecord` holds it (what `string2NodeRecord` reads and
/// `getSpec` writes back).
#[derive(Debug, Clone, Default, PartialEq)]
pub struct NodeRecord {
    /// `NAME`.
    pub name: String,
    /// `X`.
    pub x: Option<f64>,
    /// `Y`.
    pub y: Option<f64>,
    /// `SPD` / `SPEED`.
    pub speed: Option<f64>,
    /// `HDG` / `HEADING`.
    pub heading: Option<f64>,
    /// `COG`.
    pub cog: Option<f64>,
    /// `DEP` / `DEPTH`.
    pub depth: Option<f64>,
    /// `LAT`.
    pub lat: Option<f64>,
    /// `LON`.
    pub lon: Option<f64>,
    /// `TYPE`.
    pub vtype: String,
    /// `COLOR`.
    pub color: String,
    /// `GROUP`.
    pub group: String,
    /// `VSOURCE`.
    pub vsource: String,
    /// `MODE`.
    pub mode: String,
    /// `ALLSTOP`.
    pub allstop: String,
    /// `LOAD_WARNING`.
    pub load_warning: String,
    /// `ALT` / `ALTITUDE`.
    pub altitude: Option<f64>,
    /// `SPD_OG`.
    pub speed_og: Option<f64>,
    /// `HDG_OG`.
    pub heading_og: Option<f64>,
    /// `INDEX`.
    pub index: i64,
    /// `THRUST_MODE_REVERSE=true`.
    pub thrust_mode_reverse: bool,
    /// Whether a `YAW` was reported (written back from the heading).
    pub yaw: bool,
    /// `TIME` / `UTC_TIME`.
    pub time: Option<f64>,
    /// `TRANSPARENCY`.
    pub transparency: Option<f64>,
    /// `LENGTH` / `LEN`.
    pub length: Option<f64>,
    /// `TRAJECTORY` (braces stripped).
    pub trajectory: Option<String>,
    /// Other numeric fields, by key.
    pub properties: BTreeMap<String, String>,
}

impl NodeRecord {
    /// Reads a report (MOOS `string2NodeRecordCSP`; a braced JSON report is read as its
    /// `"KEY":"value"` pairs). Never fails: missing fields stay unset.
    pub fn parse(text: &str) -> NodeRecord {
        let t = text.trim();
        let mut r = NodeRecord::default();
        if t.starts_with('{') && t.ends_with('}') && t.len() >= 2 {
            for f in t[1..t.len() - 1].split(',') {
                let f: Cow<'_, str> = if f.contains('"') {
                    Cow::Owned(f.replace('"', ""))
                } else {
                    Cow::Borrowed(f)
                };
                let (k, v) = f.split_once(':').unwrap_or((f.as_ref(), ""));
                r.set(k.trim(), v.trim());
            }
        } else {
            for f in split_outside_braces(text) {
                let (k, v) = f.split_once('=').unwrap_or((f, ""));
                r.set(k.trim(), v.trim());
            }
        }
        r
    }

    fn set(&mut self, left: &str, value: &str) {
        let d = || atof(value);
        let r = self;
        // The key upper-cased on the stack (this runs for every field of every report).
        let mut buf = [0u8; 24];
        let upper: Cow<'_, str> = match buf.get_mut(..left.len()) {
            Some(b) => {
                b.copy_from_slice(left.as_bytes());
                b.make_ascii_uppercase();
                Cow::Borrowed(std::str::from_utf8(b).unwrap_or_default())
            }
            None => Cow::Owned(left.to_ascii_uppercase()),
        };
        match upper.as_ref() {
            "NAME" => r.name = value.to_string(),
            "TYPE" => r.vtype = value.to_string(),
            "MODE" => r.mode = value.to_string(),
            "ALLSTOP" => r.allstop = value.to_string(),
            "INDEX" => r.index = d() as i64,
            p if is_number(value) => match p {
                "TIME" | "UTC_TIME" => r.time = Some(d()),
                "X" => r.x = Some(d()),
                "Y" => r.y = Some(d()),
                "LAT" => r.lat = Some(d()),
                "LON" => r.lon = Some(d()),
                "SPD" | "SPEED" => r.speed = Some(d()),
                "HDG" | "HEADING" => r.heading = Some(d()),
                "DEP" | "DEPTH" => r.depth = Some(d()),
                "LENGTH" | "LEN" => r.length = Some(d()),
                "YAW" => r.yaw = true,
                "ALT" | "ALTITUDE" => r.altitude = Some(d()),
                "HDG_OG" => r.heading_og = Some(d()),
                "COG" => r.cog = Some(d()),
                "SPD_OG" => r.speed_og = Some(d()),
                "TRANSPARENCY" => r.transparency = Some(d()),
                _ => {
                    r.properties.insert(left.to_string(), value.to_string());
                }
            },
            "COLOR" => r.color = value.to_string(),
            "GROUP" => r.group = value.to_string(),
            "VSOURCE" => r.vsource = value.to_string(),
            "LOAD_WARNING" => r.load_warning = value.to_string(),
            "THRUST_MODE_REVERSE" => {
                if value.eq_ignore_ascii_case("true") {
                    r.thrust_mode_reverse = true;
                }
            }
            "TRAJECTORY" => {
                let v = value.trim();
                let v = v
                    .strip_prefix('{')
                    .and_then(|s| s.strip_suffix('}'))
                    .unwrap_or(v);
                r.trajectory = Some(v.to_string());
            }
            _ => {
                r.properties.insert(left.to_string(), value.to_string());
            }
        }
    }

    /// The report written back (MOOS `NodeRecord::getSpec`, not terse).
    pub fn spec(&self) -> String {
        let mut s = format!("NAME={}", self.name);
        let num = |s: &mut String, k: &str, v: Option<f64>, p: usize| {
            if let Some(v) = v {
                let _ = write!(s, ",{k}={}", compact_string(v, p));
            }
        };
        num(&mut s, "X", self.x, 2);
        num(&mut s, "Y", self.y, 2);
        num(&mut s, "SPD", self.speed, 2);
        num(&mut s, "HDG", self.heading, 2);
        num(&mut s, "COG", self.cog, 2);
        num(&mut s, "DEP", self.depth, 2);
        num(&mut s, "LAT", self.lat, 8);
        num(&mut s, "LON", self.lon, 8);
        for (k, v) in [
            ("TYPE", &self.vtype),
            ("COLOR", &self.color),
            ("GROUP", &self.group),
            ("VSOURCE", &self.vsource),
            ("MODE", &self.mode),
            ("ALLSTOP", &self.allstop),
            ("LOAD_WARNING", &self.load_warning),
        ] {
            if !v.is_empty() {
                let _ = write!(s, ",{k}={v}");
            }
        }
        num(&mut s, "ALTITUDE", self.altitude, 2);
        num(&mut s, "SPD_OG", self.speed_og, 2);
        num(&mut s, "HDG_OG", self.heading_og, 2);
        if self.index != 0 {
            let _ = write!(s, ",INDEX={}", self.index);
        }
        if self.thrust_mode_reverse {
            s.push_str(",THRUST_MODE_REVERSE=true");
        }
        if self.yaw {
            // MOOS `headingToRadians`: counter-clockwise from east, in (-pi, pi].
            let h = self.heading.unwrap_or(0.0);
            let mut rad = (90.0 - h).to_radians();
            while rad > std::f64::consts::PI {
                rad -= 2.0 * std::f64::consts::PI;
            }
            while rad <= -std::f64::consts::PI {
                rad += 2.0 * std::f64::consts::PI;
            }
            num(&mut s, "YAW", Some(rad), 7);
        }
        num(&mut s, "TIME", self.time, 2);
        num(&mut s, "TRANSPARENCY", self.transparency, 2);
        num(&mut s, "LENGTH", self.length, 2);
        if let Some(t) = &self.trajectory {
            let _ = write!(s, ",TRAJECTORY={{{t}}}");
        }
        for (k, v) in &self.properties {
            let _ = write!(s, ",{k}={v}");
        }
        s
    }

    /// Both `X` and `Y` were reported.
    pub fn has_xy(&self) -> bool {
        self.x.is_some() && self.y.is_some()
    }

    /// Both `LAT` and `LON` were reported.
    pub fn has_latlon(&self) -> bool {
        self.lat.is_some() && self.lon.is_some()
    }

    /// MOOS `NodeRecord::valid()`: a name, a position (x/y or lat/lon), speed and heading.
    pub fn valid(&self) -> bool {
        !self.name.is_empty()
            && (self.has_xy() || self.has_latlon())
            && self.speed.is_some()
            && self.heading.is_some()
    }
}

/// Splits at commas outside `{...}` (MOOS `parseStringZ(s, ',', "{")`).
fn split_outside_braces(s: &str) -> Vec<&str> {
    let mut out = Vec::new();
    let (mut depth, mut start) = (0usize, 0);
    for (i, c) in s.char_indices() {
        match c {
            '{' => depth += 1,
            '}' => depth = depth.saturating_sub(1),
            ',' if depth == 0 => {
                out.push(&s[start..i]);
                start = i + 1;
            }
            _ => {}
        }
    }
    out.push(&s[start..]);
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    /// As `string2NodeRecordCSP`: a numeric `COLOR` or `GROUP` is a property (the numeric
    /// branch comes first), a non-numeric `X` is not a position, keys are case-insensitive,
    /// commas inside braces do not split, and a later field wins.
    #[test]
    fn fields_follow_string2noderecord() {
        let r = NodeRecord::parse(
            "name=abe,COLOR=7,GROUP=2,X=far,Y=3,Spd=1,HDG=10,TRAJECTORY={1,2:3,4},hdg=20,INDEX=4.9",
        );
        assert_eq!(r.name, "abe");
        assert_eq!((r.color.as_str(), r.group.as_str()), ("", ""));
        assert_eq!(r.properties.get("COLOR").map(String::as_str), Some("7"));
        assert_eq!(r.properties.get("GROUP").map(String::as_str), Some("2"));
        assert_eq!(
            (r.x, r.y, r.speed, r.heading),
            (None, Some(3.0), Some(1.0), Some(20.0))
        );
        assert_eq!(r.trajectory.as_deref(), Some("1,2:3,4"));
        assert_eq!(r.index, 4);
        assert!(!r.valid(), "no position");
        // JSON: quotes dropped, `:` separates.
        let j =
            NodeRecord::parse(r#" {"NAME":"ben","LAT":"43.8","LON":"-70.3","SPD":"0","HDG":"0"} "#);
        assert!(j.has_latlon() && !j.has_xy() && j.valid(), "{j:?}");
    }
}
