//! The fleet as the base sees it, kept from pAcomms's mail; pure (the MOOS time is an
//! argument).
//!
//! A vehicle is known by its modem id once an `ACOMMS_VEHICLE` names it; a vehicle heard
//! only through `NODE_REPORT(_LOCAL)` (a radio link at the surface, say) is listed by name
//! without an id and cannot be commanded acoustically. The position shown is the newer of
//! the acoustic answer (`time=`) and the node report (`TIME`).

use std::collections::BTreeMap;

use helm::ledger::NodeReport;

/// pAcomms's per-vehicle status variable.
pub const VEHICLE_VAR: &str = "ACOMMS_VEHICLE";
/// pAcomms's command acknowledgement variable.
pub const ACK_VAR: &str = "ACOMMS_COMMAND_ACK";

/// A mail the fleet could not read.
#[derive(Debug, Clone, PartialEq, Eq)]
pub enum Rejected {
    /// Not a variable the base reads.
    NotRead(String),
    /// A field the interface requires is missing or not a number (`id`, `name`, ...).
    BadField(&'static str),
}

impl std::fmt::Display for Rejected {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            Rejected::NotRead(v) => write!(f, "{v} is not read by the base"),
            Rejected::BadField(k) => write!(f, "missing or bad field {k}"),
        }
    }
}

impl std::error::Error for Rejected {}

/// What pAcomms last posted of one vehicle (`ACOMMS_VEHICLE`).
#[derive(Debug, Clone, Default, PartialEq)]
pub struct AcousticStatus {
    /// `time=`: MOOS time of the vehicle's last answer (`None` while `answers=0`).
    pub time: Option<f64>,
    /// `x=`, local metres.
    pub x: Option<f64>,
    /// `y=`, local metres.
    pub y: Option<f64>,
    /// `depth=`, metres.
    pub depth: Option<f64>,
    /// `heading=`, degrees.
    pub heading: Option<f64>,
    /// `speed=`, m/s.
    pub speed: Option<f64>,
    /// `battery_v=`, volts.
    pub battery_v: Option<f64>,
    /// `health=`, the safety supervisor's health word in hex, as posted.
    pub health: String,
    /// `polls=`.
    pub polls: u64,
    /// `answers=`.
    pub answers: u64,
    /// `timeouts=`.
    pub timeouts: u64,
}

/// The last acknowledgement of a command to a vehicle (`ACOMMS_COMMAND_ACK`).
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Ack {
    /// `cmd=`.
    pub cmd: String,
    /// `seq=`.
    pub seq: u64,
    /// `state=`: `queued`, `sent`, `confirmed` or `timeout`.
    pub state: String,
}

/// One vehicle's row.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct Vehicle {
    /// The vehicle's name.
    pub name: String,
    /// Its modem id, once pAcomms named it.
    pub id: Option<u32>,
    /// pAcomms's status of it.
    pub acoustic: Option<AcousticStatus>,
    /// Its last node report.
    pub report: Option<NodeReport>,
    /// The last acknowledgement of a command to it.
    pub ack: Option<Ack>,
}

/// Where a position came from.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Source {
    /// pAcomms's `ACOMMS_VEHICLE` (the vehicle's acoustic answer).
    Acoustic,
    /// A `NODE_REPORT`.
    NodeReport,
}

/// A vehicle's newest known position.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Fix {
    /// MOOS time of the fix.
    pub time: f64,
    /// Local x, metres.
    pub x: f64,
    /// Local y, metres.
    pub y: f64,
    /// Depth, metres, if known.
    pub depth: Option<f64>,
    /// Heading, degrees, if known.
    pub heading: Option<f64>,
    /// Speed, m/s, if known.
    pub speed: Option<f64>,
    /// Where it came from.
    pub source: Source,
}

impl Vehicle {
    /// The newer of the acoustic answer's and the node report's positions.
    pub fn fix(&self) -> Option<Fix> {
        let acoustic = self.acoustic.as_ref().and_then(|a| {
            Some(Fix {
                time: a.time?,
                x: a.x?,
                y: a.y?,
                depth: a.depth,
                heading: a.heading,
                speed: a.speed,
                source: Source::Acoustic,
            })
        });
        let report = self.report.as_ref().and_then(|r| {
            Some(Fix {
                time: r.time?,
                x: r.x_m?,
                y: r.y_m?,
                depth: r.depth_m,
                heading: r.heading_deg,
                speed: r.speed_mps,
                source: Source::NodeReport,
            })
        });
        match (acoustic, report) {
            (Some(a), Some(r)) => Some(if r.time > a.time { r } else { a }),
            (a, r) => a.or(r),
        }
    }

    /// Seconds since the vehicle was last heard (its last acoustic answer or node report) at
    /// MOOS time `now`; `None` if it never answered.
    pub fn age(&self, now: f64) -> Option<f64> {
        let a = self.acoustic.as_ref().and_then(|a| a.time);
        let r = self.report.as_ref().and_then(|r| r.time);
        let last = match (a, r) {
            (Some(a), Some(r)) => a.max(r),
            (a, r) => a.or(r)?,
        };
        Some((now - last).max(0.0))
    }

    /// The link's quality: answers over polls, `None` before the first poll.
    pub fn link_ratio(&self) -> Option<f64> {
        let a = self.acoustic.as_ref()?;
        (a.polls > 0).then(|| a.answers as f64 / a.polls as f64)
    }
}

/// `key=value` pairs of a comma-separated posting, keys lower-cased, blanks trimmed.
pub fn pairs(s: &str) -> impl Iterator<Item = (String, &str)> {
    s.split(',').filter_map(|p| {
        let (k, v) = p.split_once('=')?;
        Some((k.trim().to_ascii_lowercase(), v.trim()))
    })
}

fn number(v: &str) -> Option<f64> {
    v.parse::<f64>().ok().filter(|x| x.is_finite())
}

/// Every vehicle by name.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct Fleet {
    vehicles: BTreeMap<String, Vehicle>,
}

impl Fleet {
    /// An empty fleet.
    pub fn new() -> Fleet {
        Fleet::default()
    }

    /// The vehicles, by name.
    pub fn vehicles(&self) -> &BTreeMap<String, Vehicle> {
        &self.vehicles
    }

    /// The vehicle with modem id `id`.
    pub fn by_id(&self, id: u32) -> Option<&Vehicle> {
        self.vehicles.values().find(|v| v.id == Some(id))
    }

    /// The vehicle named `name` (case-insensitive).
    pub fn by_name(&self, name: &str) -> Option<&Vehicle> {
        self.vehicles
            .values()
            .find(|v| v.name.eq_ignore_ascii_case(name))
    }

    /// Takes one mail: `ACOMMS_VEHICLE`, `ACOMMS_COMMAND_ACK`, `NODE_REPORT` or
    /// `NODE_REPORT_LOCAL`.
    pub fn apply(&mut self, var: &str, value: &str) -> Result<(), Rejected> {
        match var {
            VEHICLE_VAR => self.apply_vehicle(value),
            ACK_VAR => self.apply_ack(value),
            "NODE_REPORT" | "NODE_REPORT_LOCAL" => {
                let r = NodeReport::parse(value);
                if r.name.is_empty() {
                    return Err(Rejected::BadField("NAME"));
                }
                let v = self.vehicles.entry(r.name.clone()).or_default();
                v.name = r.name.clone();
                v.report = Some(r);
                Ok(())
            }
            other => Err(Rejected::NotRead(other.to_string())),
        }
    }

    fn apply_vehicle(&mut self, value: &str) -> Result<(), Rejected> {
        let mut id = None;
        let mut name = None;
        let mut s = AcousticStatus::default();
        for (k, v) in pairs(value) {
            match k.as_str() {
                "id" => id = v.parse::<u32>().ok(),
                "name" if !v.is_empty() => name = Some(v.to_string()),
                "time" => s.time = number(v),
                "x" => s.x = number(v),
                "y" => s.y = number(v),
                "depth" => s.depth = number(v),
                "heading" => s.heading = number(v),
                "speed" => s.speed = number(v),
                "battery_v" => s.battery_v = number(v),
                "health" => s.health = v.to_string(),
                "polls" => s.polls = v.parse().unwrap_or(0),
                "answers" => s.answers = v.parse().unwrap_or(0),
                "timeouts" => s.timeouts = v.parse().unwrap_or(0),
                _ => {}
            }
        }
        if s.answers == 0 {
            // Never answered: whatever `time=` says, there is no answer to date.
            s.time = None;
        }
        let id = id.ok_or(Rejected::BadField("id"))?;
        let name = name.ok_or(Rejected::BadField("name"))?;
        // A modem id moves with its name: drop it from another row that had it.
        for v in self.vehicles.values_mut() {
            if v.id == Some(id) && v.name != name {
                v.id = None;
            }
        }
        let v = self.vehicles.entry(name.clone()).or_default();
        v.name = name;
        v.id = Some(id);
        v.acoustic = Some(s);
        Ok(())
    }

    fn apply_ack(&mut self, value: &str) -> Result<(), Rejected> {
        let (mut to, mut cmd, mut seq, mut state) = (None, None, 0, None);
        for (k, v) in pairs(value) {
            match k.as_str() {
                "to" => to = v.parse::<u32>().ok(),
                "cmd" => cmd = Some(v.to_string()),
                "seq" => seq = v.parse().unwrap_or(0),
                "state" => state = Some(v.to_string()),
                _ => {}
            }
        }
        let to = to.ok_or(Rejected::BadField("to"))?;
        let ack = Ack {
            cmd: cmd.ok_or(Rejected::BadField("cmd"))?,
            seq,
            state: state.ok_or(Rejected::BadField("state"))?,
        };
        let v = self
            .vehicles
            .values_mut()
            .find(|v| v.id == Some(to))
            .ok_or(Rejected::BadField("to"))?;
        v.ack = Some(ack);
        Ok(())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn status_report_and_ack_make_one_row() {
        let mut f = Fleet::new();
        f.apply(VEHICLE_VAR, "id=2,name=coug2,polls=1,answers=0,timeouts=1")
            .unwrap();
        let v = f.by_id(2).unwrap();
        assert_eq!(v.fix(), None, "no position before the first answer");
        assert_eq!(v.age(100.0), None);
        assert_eq!(v.link_ratio(), Some(0.0));
        f.apply(
            VEHICLE_VAR,
            "id=2,name=coug2,time=100,x=10,y=-20,depth=5,heading=90,speed=1.5,battery_v=15.9,\
             health=0x0,polls=4,answers=3,timeouts=1",
        )
        .unwrap();
        let v = f.by_name("COUG2").unwrap();
        assert_eq!(v.age(112.5), Some(12.5));
        assert_eq!(v.link_ratio(), Some(0.75));
        let fix = v.fix().unwrap();
        assert_eq!((fix.x, fix.y, fix.source), (10.0, -20.0, Source::Acoustic));
        // A newer node report wins the position.
        f.apply("NODE_REPORT", "NAME=coug2,X=11,Y=-21,TIME=105,DEP=0")
            .unwrap();
        let v = f.by_id(2).unwrap();
        assert_eq!(v.fix().unwrap().source, Source::NodeReport);
        assert_eq!(v.age(112.5), Some(7.5));
        f.apply(ACK_VAR, "to=2,cmd=abort,seq=7,state=sent").unwrap();
        assert_eq!(f.by_id(2).unwrap().ack.as_ref().unwrap().state, "sent");
        assert_eq!(
            f.apply(ACK_VAR, "to=9,cmd=abort,seq=7,state=sent"),
            Err(Rejected::BadField("to"))
        );
        assert_eq!(
            f.apply(VEHICLE_VAR, "name=x"),
            Err(Rejected::BadField("id"))
        );
        assert!(f.apply("DEPLOY", "true").is_err());
    }
}
