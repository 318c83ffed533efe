//! The helm's contact ledger (MOOS-IvP `ContactLedger` as pHelmIvP uses it): every node
//! report the helm receives (`NODE_REPORT`, `AIS_REPORT`, `AIS_REPORT_LOCAL`), kept by vehicle
//! name until it goes stale, summarised each iteration as `IVPHELM_LEDGER_SUMMARY`.
//!
//! Contact behaviours read their contacts from here (each iteration the helm copies the
//! ledger into the info buffer's contact snapshot, `behaviors::Info::contact`); the ledger's
//! other visible effects are the summary, the `<VNAME>_NAV_GROUP` / `<VNAME>_NAV_TYPE`
//! info-buffer entries the helm sets from each report, and the warnings for reports it
//! rejects.
//!
//! Rules, from `ContactLedger::processNodeReport` / `processNodeRecord` at a2a9b716:
//! - a report needs a name (`Missing vname.`), a `TIME`/`UTC_TIME` (`Missing timestamp.`),
//!   and x/y or a longitude (`Missing both x/y and lat/lon.`: the C++ tests the longitude
//!   twice for "lat/lon set");
//! - an accepted report counts in `reps` even when rejected afterwards: a type `auv` or
//!   `glider` (exact lower case) without a depth is dropped with `underwater vehicle type
//!   with no depth reported`;
//! - the type is fixed: `uuv` becomes `auv`, a type MOOS does not know becomes `ship`;
//! - a contact is stale when its report's own timestamp is older than `contact_max_age`
//!   (a report stamped 0 never goes stale, as `getUTCAge` treats 0 as unknown).

use moos_types::node_record::NodeRecord;
use std::collections::BTreeMap;

/// One vehicle as last reported.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct Contact {
    /// `GROUP`.
    pub group: String,
    /// `TYPE`, after the ledger's type fixing.
    pub vtype: String,
    /// `TIME` / `UTC_TIME` of the report, seconds.
    pub time: f64,
    /// When the helm received it, seconds.
    pub received: f64,
    /// Local x, metres, if reported.
    pub x_m: Option<f64>,
    /// Local y, metres, if reported.
    pub y_m: Option<f64>,
    /// Speed, m/s.
    pub speed_mps: f64,
    /// Heading, degrees.
    pub heading_deg: f64,
    /// Depth, metres, if reported.
    pub depth_m: Option<f64>,
}

/// The fields of a node report the helm reads (MOOS `NodeRecord`, parsed as
/// `string2NodeRecord`: comma-separated `KEY=value` pairs, or JSON in braces).
#[derive(Debug, Clone, Default, PartialEq)]
pub struct NodeReport {
    /// `NAME`.
    pub name: String,
    /// `TYPE` as reported.
    pub vtype: String,
    /// `GROUP`.
    pub group: String,
    /// `COLOR`.
    pub color: String,
    /// `TIME` or `UTC_TIME`.
    pub time: Option<f64>,
    /// `X`.
    pub x_m: Option<f64>,
    /// `Y`.
    pub y_m: Option<f64>,
    /// `LAT`.
    pub lat_deg: Option<f64>,
    /// `LON`.
    pub lon_deg: Option<f64>,
    /// `SPD` / `SPEED`.
    pub speed_mps: Option<f64>,
    /// `HDG` / `HEADING`.
    pub heading_deg: Option<f64>,
    /// `DEP` / `DEPTH`.
    pub depth_m: Option<f64>,
    /// `LENGTH` / `LEN`.
    pub length_m: Option<f64>,
    /// `MODE` (the helm's mode, `NOHELM-EVER`, ...), empty when absent.
    pub mode: String,
    /// `ALLSTOP` (the helm's all-stop reason, `clear` when driving), empty when absent.
    pub allstop: String,
}

impl NodeReport {
    /// Reads a report through the one node-report parse
    /// ([`moos_types::node_record::NodeRecord::parse`], MOOS `string2NodeRecord`): numeric
    /// fields take only values MOOS calls numbers (a numeric `COLOR` or `GROUP` is a property
    /// there, so neither is set); unknown keys are ignored. Never fails: missing fields stay
    /// unset.
    pub fn parse(report: &str) -> NodeReport {
        NodeReport::from(NodeRecord::parse(report))
    }
}

impl From<NodeRecord> for NodeReport {
    fn from(r: NodeRecord) -> NodeReport {
        NodeReport {
            name: r.name,
            vtype: r.vtype,
            group: r.group,
            color: r.color,
            time: r.time,
            x_m: r.x,
            y_m: r.y,
            lat_deg: r.lat,
            lon_deg: r.lon,
            speed_mps: r.speed,
            heading_deg: r.heading,
            depth_m: r.depth,
            length_m: r.length,
            mode: r.mode,
            allstop: r.allstop,
        }
    }
}

/// Vehicle types MOOS knows (`isKnownVehicleType`, case-insensitive).
const KNOWN_TYPES: [&str; 23] = [
    "auv",
    "kayak",
    "uuv",
    "usv",
    "glider",
    "asv",
    "ship",
    "mokai",
    "longship",
    "buoy",
    "heron",
    "swimmer",
    "cray",
    "bcray",
    "crayx",
    "wamv",
    "bcrayx",
    "smr",
    "smrx",
    "skyw",
    "skywalker",
    "quad",
    "quadcopter",
];

fn is_known_type(t: &str) -> bool {
    KNOWN_TYPES.iter().any(|k| k.eq_ignore_ascii_case(t))
}

/// A reported vehicle type as `ContactLedger::processNodeRecord` fixes it: `uuv` becomes
/// `auv`, a type MOOS does not know becomes `ship`.
pub fn fixed_type(vtype: &str) -> String {
    if vtype == "uuv" {
        "auv".into()
    } else if !is_known_type(vtype) {
        "ship".into()
    } else {
        vtype.to_string()
    }
}

/// Contacts by vehicle name (in name order, as the C++ map).
#[derive(Debug, Clone)]
pub struct ContactLedger {
    contacts: BTreeMap<String, Contact>,
    total_reports: u64,
    stale_thresh_s: f64,
}

impl ContactLedger {
    /// An empty ledger dropping contacts older than `stale_thresh_s` (pHelmIvP's
    /// `contact_max_age`, 45 s by default).
    pub fn new(stale_thresh_s: f64) -> Self {
        Self {
            contacts: BTreeMap::new(),
            total_reports: 0,
            stale_thresh_s,
        }
    }

    /// Takes one report received at `now`; returns the vehicle's name, or why the report
    /// was rejected (the text pHelmIvP shows after `The issue: `).
    pub fn process(&mut self, report: &NodeReport, now: f64) -> Result<String, String> {
        let mut why = String::new();
        if report.name.is_empty() {
            why.push_str("Missing vname.");
        }
        if report.time.is_none() {
            why.push_str("Missing timestamp.");
        }
        let has_xy = report.x_m.is_some() && report.y_m.is_some();
        if report.lon_deg.is_none() && !has_xy {
            why.push_str("Missing both x/y and lat/lon.");
        }
        if !why.is_empty() {
            return Err(why);
        }
        self.total_reports += 1;
        let vtype = fixed_type(&report.vtype);
        if (vtype == "auv" || vtype == "glider") && report.depth_m.is_none() {
            return Err("underwater vehicle type with no depth reported".into());
        }
        let contact = Contact {
            group: report.group.clone(),
            vtype,
            time: report.time.unwrap_or(0.0),
            received: now,
            x_m: report.x_m,
            y_m: report.y_m,
            speed_mps: report.speed_mps.unwrap_or(0.0),
            heading_deg: report.heading_deg.unwrap_or(0.0),
            depth_m: report.depth_m,
        };
        self.contacts.insert(report.name.clone(), contact);
        Ok(report.name.clone())
    }

    /// The contact called `name`.
    pub fn get(&self, name: &str) -> Option<&Contact> {
        self.contacts.get(name)
    }

    /// Every contact, by name (in name order).
    pub fn iter(&self) -> impl Iterator<Item = (&str, &Contact)> + '_ {
        self.contacts.iter().map(|(k, v)| (k.as_str(), v))
    }

    /// Drops every contact whose report is older than the stale threshold at `now`; those
    /// named in `keep` (contacts a behaviour still reasons about) get `keep_factor` times
    /// the threshold (at least once; a negative factor keeps them for good).
    pub fn clear_stale(&mut self, now: f64, keep: &[&str], keep_factor: f64) {
        let factor = if keep_factor > 0.0 && keep_factor < 1.0 {
            1.0
        } else {
            keep_factor
        };
        let thresh = self.stale_thresh_s;
        self.contacts.retain(|name, c| {
            let kept = keep.contains(&name.as_str());
            if kept && factor < 0.0 {
                return true;
            }
            let age = if c.time == 0.0 { -1.0 } else { now - c.time };
            let limit = if kept { thresh * factor } else { thresh };
            age <= limit
        });
    }

    /// `IVPHELM_LEDGER_SUMMARY`: `now:<contacts>, reps:<reports>, who:<first amt names>`.
    pub fn summary(&self, amt: usize, out: &mut String) {
        use std::fmt::Write;
        let _ = write!(
            out,
            "now:{}, reps:{}, who:",
            self.contacts.len(),
            self.total_reports
        );
        for (i, name) in self.contacts.keys().take(amt).enumerate() {
            if i > 0 {
                out.push(',');
            }
            out.push_str(name);
        }
    }

    /// Number of contacts.
    pub fn len(&self) -> usize {
        self.contacts.len()
    }

    /// Whether the ledger is empty.
    pub fn is_empty(&self) -> bool {
        self.contacts.is_empty()
    }
}

/// Contacts a behaviour may not spawn for (BehaviorSet's `BHV_ABLE_FILTER` blacklist):
/// `action=disable,contact=<name>` adds a name, `action=able,contact=<name>` removes it,
/// and only the 200 most recent additions are kept.
#[derive(Debug, Clone, Default)]
pub struct DisabledContacts {
    /// Additions, newest first (a name may appear more than once, as in the C++ list).
    order: std::collections::VecDeque<String>,
    names: std::collections::HashSet<String>,
}

impl DisabledContacts {
    /// How many additions are remembered (BehaviorSet `m_max_blacklist`).
    pub const MAX: usize = 200;

    /// Applies the helm-level part of a `BHV_ABLE_FILTER` message (the `contact` and
    /// `action` fields, read as MOOS `tokStringParse`: case-sensitive keys, first match).
    pub fn apply(&mut self, msg: &str) {
        use moos_types::text::tok_string_parse;
        let contact = tok_string_parse(msg, "contact").to_string();
        if contact.is_empty() {
            return;
        }
        match tok_string_parse(msg, "action") {
            "able" => {
                self.names.remove(&contact);
            }
            "disable" => {
                self.names.insert(contact.clone());
                self.order.push_front(contact);
                if self.order.len() > Self::MAX
                    && let Some(old) = self.order.pop_back()
                {
                    self.names.remove(&old);
                }
            }
            _ => {}
        }
    }

    /// Whether spawning for `contact` is disabled.
    pub fn contains(&self, contact: &str) -> bool {
        self.names.contains(contact)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn summary(l: &ContactLedger) -> String {
        let mut s = String::new();
        l.summary(20, &mut s);
        s
    }

    #[test]
    fn reports_are_read_as_node_records() {
        let r = NodeReport::parse(
            "NAME=abe,X=10.5,Y=-3,SPD=1.2,HDG=90,DEP=4,LAT=nan,TYPE=kayak,GROUP=red,\
             TIME=1000.25,TRAJECTORY={a=1,b=2},COLOR=red,LENGTH=4",
        );
        assert_eq!(r.name, "abe");
        assert_eq!((r.x_m, r.y_m), (Some(10.5), Some(-3.0)));
        assert_eq!(r.lat_deg, None, "not a MOOS number");
        assert_eq!((r.vtype.as_str(), r.group.as_str()), ("kayak", "red"));
        assert_eq!(
            (r.time, r.depth_m, r.length_m),
            (Some(1000.25), Some(4.0), Some(4.0))
        );
        // As the C++ reads it: a numeric group or colour is a property, not the group.
        let n = NodeReport::parse("NAME=abe,X=1,Y=2,GROUP=3,COLOR=4");
        assert_eq!((n.group.as_str(), n.color.as_str()), ("", ""));
        let j = NodeReport::parse(r#"{"NAME":"cal","X":1,"Y":2,"UTC_TIME":5,"TYPE":"UUV"}"#);
        assert_eq!(j.name, "cal");
        assert_eq!((j.x_m, j.time), (Some(1.0), Some(5.0)));
        assert_eq!(j.vtype, "UUV");
    }

    #[test]
    fn the_ledger_counts_keeps_and_summarises_as_pphelmivp() {
        let mut l = ContactLedger::new(45.0);
        assert_eq!(summary(&l), "now:0, reps:0, who:");
        let ok = |s: &str| NodeReport::parse(s);
        assert_eq!(
            l.process(&ok("NAME=ben,X=1,Y=2,TIME=100,TYPE=kayak,GROUP=g1"), 100.0),
            Ok("ben".into())
        );
        l.process(&ok("NAME=abe,X=1,Y=2,TIME=100"), 100.0).unwrap();
        l.process(&ok("NAME=abe,X=3,Y=2,TIME=101"), 101.0).unwrap();
        assert_eq!(summary(&l), "now:2, reps:3, who:abe,ben");
        assert_eq!(l.get("abe").unwrap().vtype, "ship", "no type: ship");
        assert_eq!(l.get("ben").unwrap().vtype, "kayak");
        // Rejections, with the C++ reasons; the first three are not counted.
        assert_eq!(
            l.process(&ok("X=1"), 102.0),
            Err("Missing vname.Missing timestamp.Missing both x/y and lat/lon.".into())
        );
        assert_eq!(
            l.process(&ok("NAME=cal,LAT=1,TIME=3"), 102.0),
            Err("Missing both x/y and lat/lon.".into()),
            "a latitude alone is not a position"
        );
        assert!(l.process(&ok("NAME=cal,LON=1,TIME=3,DEP=2"), 102.0).is_ok());
        assert_eq!(
            l.process(&ok("NAME=deb,X=1,Y=1,TIME=3,TYPE=uuv"), 102.0),
            Err("underwater vehicle type with no depth reported".into())
        );
        assert_eq!(summary(&l), "now:3, reps:5, who:abe,ben,cal");
        // uuv becomes auv; an upper-case AUV is known and kept as is (no depth check).
        l.process(&ok("NAME=eve,X=1,Y=1,TIME=3,TYPE=uuv,DEP=1"), 102.0)
            .unwrap();
        assert_eq!(l.get("eve").unwrap().vtype, "auv");
        l.process(&ok("NAME=fay,X=1,Y=1,TIME=3,TYPE=AUV"), 102.0)
            .unwrap();
        assert_eq!(l.get("fay").unwrap().vtype, "AUV");
    }

    #[test]
    fn stale_contacts_go_after_the_threshold_by_their_own_timestamp() {
        let mut l = ContactLedger::new(45.0);
        let r = |s: &str| NodeReport::parse(s);
        l.process(&r("NAME=abe,X=1,Y=2,TIME=100"), 100.0).unwrap();
        l.process(&r("NAME=ben,X=1,Y=2,TIME=120"), 100.0).unwrap();
        l.process(&r("NAME=zed,X=1,Y=2,TIME=0"), 100.0).unwrap();
        l.clear_stale(145.0, &[], 2.0);
        assert_eq!(l.len(), 3, "45 s old is not stale yet");
        l.clear_stale(145.5, &["abe"], 2.0);
        assert!(
            l.get("abe").is_some(),
            "kept contacts get twice the threshold"
        );
        l.clear_stale(145.5, &[], 2.0);
        assert!(l.get("abe").is_none());
        l.clear_stale(1e6, &[], 2.0);
        assert_eq!(l.len(), 1, "a report stamped 0 never goes stale");
        assert!(l.get("zed").is_some());
    }

    #[test]
    fn the_able_filter_blacklist_keeps_the_latest_200() {
        let mut d = DisabledContacts::default();
        d.apply("action=disable,contact=345");
        assert!(d.contains("345"));
        d.apply("action=able,contact=345");
        assert!(!d.contains("345"));
        d.apply("action=enable,contact=9");
        assert!(
            !d.contains("9"),
            "only `able` and `disable` touch the blacklist"
        );
        d.apply("action=disable,vsource=ais");
        for k in 0..=DisabledContacts::MAX {
            d.apply(&format!("action=disable,contact=c{k}"));
        }
        assert!(!d.contains("c0"), "the oldest of 201 is forgotten");
        assert!(d.contains("c1") && d.contains("c200"));
    }
}
