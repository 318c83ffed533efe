//! `uFldNodeComms`: the shoreside's relay of node reports and node messages between vehicles
//! (issue #18, with the fleet brokers of `runtime::brokers`). Every vehicle's `NODE_REPORT`
//! (or `NODE_REPORT_LOCAL`) is kept in a ledger; at each iteration each new report is posted
//! as `NODE_REPORT_<VNAME>` for every other vehicle it reaches, which uFldShoreBroker's
//! `qbridge = NODE_REPORT` carries to that vehicle as its `NODE_REPORT`. `NODE_MESSAGE`s are
//! routed the same way to their `dest_node`/`dest_group` as `NODE_MESSAGE_<VNAME>`, and
//! `ACK_MESSAGE`s (`src=ben, dest=abe, id=abe_21`) to `ACK_MESSAGE_<dest>`.
//!
//! [`NodeComms`] is the pure core (mail and time in, posts out); [`NodeCommsApp`] is it
//! [`Hosted`]. Facts from MOOS-IvP's `uFldNodeComms` at a2a9b716 (`FldNodeComms`, over
//! `ContactLedger`, `NodeRecord`, `NodeMessage` and `XYCommsPulse`).
//!
//! A report reaches vehicle B from vehicle A when the two are within `critical_range`
//! (always), otherwise when B has reported within `stale_time`, the range is within
//! `comms_range` × A's stealth × B's earange (`comms_range = nolimit` or negative: always; 0:
//! never), the groups match (with `groups = true`), the drop draw keeps it, and at least
//! `min_rpt_interval` has passed since the last A-to-B report. The relayed text is the
//! ledger's record written back (MOOS `NodeRecord::getSpec`): x/y derived from lat/lon on the
//! mission's grid (and lat/lon from x/y), the type fixed (`uuv` is `auv`, unknown `ship`), a
//! default `LENGTH` by type, `COG` from the last two positions. The drop percentage draws
//! from a generator seeded by the run (MOOS seeds `rand()` with the wall clock), so lockstep
//! runs repeat.
//!
//! # Conformance with uFldNodeComms (MOOS-IvP a2a9b716)
//!
//! | parameter | default | validation (C++ rule) | coug |
//! |---|---|---|---|
//! | comms_range | 100 | number, or `nolimit` (-1) | done |
//! | critical_range | 30 | >= 0 | done |
//! | stale_time | 5 | number (forget after 20 times it) | done |
//! | min_msg_interval | 30 | >= 0 | done |
//! | min_rpt_interval | -1 (off) | >= 0 | done |
//! | max_msg_length | 1000 | unsigned (0: unlimited) | done |
//! | stealth | none | `vname=..,stealth=..` clipped to 0.1..1 | done |
//! | earange | none | `vname=..,earange=..` clipped to 1..10 | done |
//! | groups | false | boolean | done |
//! | msg_groups | false | boolean | done |
//! | view_node_rpt_pulses | true | boolean | done |
//! | drop_percentage | 0 | > 0 | done |
//! | pulse_duration | 10 | number (<= 0: no pulses) | done |
//! | shared_node_reports | off | `true` (0.1 s), `false`, or seconds >= 0 | done |
//! | msg_color, msg_repeat_color | white, light_green | colour | done |
//!
//! | variable | when | format | coug |
//! |---|---|---|---|
//! | NODE_REPORT_<VNAME> | a new report reaches VNAME | the record's spec | done |
//! | NODE_MESSAGE_<VNAME> (MEDIATED_MESSAGE_<VNAME> with `ack=true`) | a message reaches VNAME, at most one per source per `min_msg_interval` | the message's spec | done |
//! | VIEW_COMMS_PULSE | each relayed report (`view_node_rpt_pulses`) and message | `sx,sy,tx,ty,beam_width,fill,ptype`, label `<a>2<b>`, fill colour, time, duration | done |
//! | NODE_REPORT_UNC, RTE | `shared_node_reports` | the spec; real seconds since the last | done |
//! | mail UNC_COMMS_RANGE, UNC_STEALTH, UNC_EARANGE, UNC_DROP_PCT, UNC_SHARED_NODE_REPORTS, UNC_VIEW_NODE_RPT_PULSES | any time | as the parameters | done |
//! | ACK_MESSAGE_<VNAME> (the name as the acknowledgement gives it) | mail `ACK_MESSAGE = src=..,dest=..,id=..` whose two vehicles have valid reports not older than `stale_time` and are within comms range (not the critical range), the drop draw keeping it, at most one per source per `min_msg_interval` | `id=.., src=.., dest=..` | done |
//! | appcast | each report | configuration, node report and message summaries, blocked messages (invalid, missing info, stale receiver, too recent, too long, too far: acknowledgements count there too; the C++ keeps received/sent acknowledgement counts without showing them, [`NodeComms::ack_counts`]) | done |

use std::collections::{BTreeMap, BTreeSet, VecDeque};
use std::fmt::Write as _;

use mission::diagnostic::{Diagnostic, DiagnosticKind};
use mission::moos::ProcessConfig;
use moos_types::fmt::{compact_string, fixed};
use moos_types::text::{is_number, parse_string, parse_string_q, set_boolean_on_string};
use vehicle::geodesy::LocalGrid;

use crate::app::{Mail, Post, Subscription, Value};
use crate::appcasting::Note;
use crate::hosted::{AppCore, Hosted};

/// The program name.
pub const PROGRAM: &str = "uFldNodeComms";

pub use moos_types::node_record::NodeRecord;

/// A node message (MOOS `NodeMessage`, read as `string2NodeMessage`).
#[derive(Debug, Clone, Default, PartialEq)]
pub struct NodeMessage {
    src_node: String,
    dest_node: String,
    dest_group: String,
    src_app: String,
    src_bhv: String,
    var_name: String,
    string_val: String,
    double_val: Option<f64>,
    color: String,
    msg_id: String,
    ack: bool,
}

impl NodeMessage {
    /// Reads a message; an invalid one is the empty message.
    pub fn parse(text: &str) -> NodeMessage {
        let mut m = NodeMessage::default();
        let (mut sval, mut quoted) = (String::new(), false);
        for part in parse_string_q(text, ',') {
            let (l, v) = part.split_once('=').unwrap_or((part, ""));
            let (l, v) = (l.trim().to_ascii_lowercase(), v.trim());
            match l.as_str() {
                "src_node" => m.src_node = v.into(),
                "src_app" => m.src_app = v.into(),
                "src_bhv" => m.src_bhv = v.into(),
                "dest_node" => m.dest_node = v.into(),
                "dest_group" => m.dest_group = v.into(),
                "var_name" => m.var_name = v.into(),
                "string_val" => sval = v.into(),
                "color" if geometry::color::is_color(v) => m.color = v.into(),
                "ack_id" => m.msg_id = v.into(),
                "string_val_quoted" if v.eq_ignore_ascii_case("true") => quoted = true,
                "ack" if v.eq_ignore_ascii_case("true") => m.ack = true,
                "double_val" => m.double_val = Some(geometry::atof(v)),
                _ => {}
            }
        }
        let is_quoted = |s: &str| s.len() >= 2 && s.starts_with('"') && s.ends_with('"');
        if quoted && is_quoted(&sval) {
            sval = sval[1..sval.len() - 1].to_string();
        }
        m.string_val = if !is_quoted(&sval) && sval.contains(',') {
            format!("\"{sval}\"")
        } else {
            sval
        };
        if m.valid() { m } else { NodeMessage::default() }
    }

    /// A source, a destination, a variable, and not both a string and a double.
    pub fn valid(&self) -> bool {
        let has_dest = !self.dest_node.is_empty() || !self.dest_group.is_empty();
        let one_value = self.string_val.is_empty() || self.double_val.is_none();
        !self.src_node.is_empty() && has_dest && !self.var_name.is_empty() && one_value
    }

    /// MOOS `NodeMessage::length`: the string value's length, at least 2.
    pub fn length(&self) -> usize {
        self.string_val.len().max(2)
    }

    /// The message written back (MOOS `NodeMessage::getSpec`).
    pub fn spec(&self) -> String {
        let mut parts: Vec<String> = Vec::new();
        if !self.msg_id.is_empty() {
            parts.push(format!("ack_id={}", self.msg_id));
        }
        if self.ack {
            parts.push("ack=true".into());
        }
        for (k, v) in [
            ("src_node", &self.src_node),
            ("dest_node", &self.dest_node),
            ("dest_group", &self.dest_group),
            ("src_app", &self.src_app),
            ("src_bhv", &self.src_bhv),
            ("var_name", &self.var_name),
            ("color", &self.color),
        ] {
            if !v.is_empty() {
                parts.push(format!("{k}={v}"));
            }
        }
        if let Some(d) = self.double_val {
            parts.push(format!("double_val={}", compact_string(d, 6)));
        }
        if !self.string_val.is_empty() {
            let q = self.string_val.starts_with('"') && self.string_val.ends_with('"');
            if !q && self.string_val.contains(',') {
                parts.push(format!(
                    "string_val=\"{}\",string_val_quoted=true",
                    self.string_val
                ));
            } else {
                parts.push(format!("string_val={}", self.string_val));
            }
        }
        parts.join(",")
    }
}

/// An acknowledgement as MOOS `AckMessage` holds it: `src=henry, dest=ike, id=ike_21`.
///
/// ```
/// use runtime::node_comms::AckMessage;
/// let a = AckMessage::parse("src=henry, dest=ike, id=ike_21");
/// assert_eq!(a.spec(), "id=ike_21, src=henry, dest=ike");
/// assert!(!AckMessage::parse("src=henry, dest=henry, id=3").valid());
/// ```
#[derive(Debug, Clone, Default, PartialEq, Eq)]
pub struct AckMessage {
    /// `src`: the vehicle that acknowledges.
    pub src: String,
    /// `dest`: the vehicle the acknowledgement goes to.
    pub dest: String,
    /// `id`: the acknowledged message's id.
    pub id: String,
}

impl AckMessage {
    /// MOOS `string2AckMessage`: `src`, `dest` and `id` (keys in any case, other keys
    /// ignored); a name with white space, or the same as the other end, is not taken; an
    /// acknowledgement without all three is empty.
    pub fn parse(text: &str) -> AckMessage {
        let mut m = AckMessage::default();
        for part in parse_string_q(text, ',') {
            let (k, v) = part.split_once('=').unwrap_or((part, ""));
            let (k, v) = (k.trim().to_ascii_lowercase(), v.trim());
            let white = v.contains(char::is_whitespace);
            match k.as_str() {
                "src" if !white && v != m.dest => m.src = v.to_string(),
                "dest" if !white && v != m.src => m.dest = v.to_string(),
                "id" => m.id = v.to_string(),
                _ => {}
            }
        }
        if m.valid() { m } else { AckMessage::default() }
    }

    /// A source, a destination and an id.
    pub fn valid(&self) -> bool {
        !self.id.is_empty() && !self.src.is_empty() && !self.dest.is_empty()
    }

    /// MOOS `AckMessage::getSpec`: `id=.., src=.., dest=..`.
    pub fn spec(&self) -> String {
        format!("id={}, src={}, dest={}", self.id, self.src, self.dest)
    }
}

/// One vehicle in the ledger.
#[derive(Debug, Clone)]
struct Entry {
    record: NodeRecord,
    /// When its last report arrived.
    received: f64,
    reports: u32,
}

/// What goes out at most once per `min_msg_interval` from each source.
#[derive(Debug, Clone, Copy)]
enum Kind {
    /// A node (or mediated) message.
    Message,
    /// An acknowledgement.
    Ack,
}

/// A small seeded generator (splitmix64) for the drop draws.
#[derive(Debug, Clone)]
struct Draws(u64);

impl Draws {
    /// A number in `0..100` (MOOS `rand() % 100`).
    fn percent(&mut self) -> u64 {
        self.0 = self.0.wrapping_add(0x9E37_79B9_7F4A_7C15);
        let mut z = self.0;
        z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
        z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
        (z ^ (z >> 31)) % 100
    }
}

/// The settings of the block.
#[derive(Debug, Clone)]
struct Settings {
    comms_range: f64,
    critical_range: f64,
    stale_time: f64,
    stale_forget: f64,
    min_msg_interval: f64,
    min_rpt_interval: f64,
    min_share_interval: f64,
    max_msg_length: usize,
    apply_groups: bool,
    apply_groups_msgs: bool,
    view_node_rpt_pulses: bool,
    drop_pct: f64,
    pulse_duration: f64,
    msg_color: String,
    msg_repeat_color: String,
}

impl Default for Settings {
    fn default() -> Self {
        Settings {
            comms_range: 100.0,
            critical_range: 30.0,
            stale_time: 5.0,
            stale_forget: 100.0,
            min_msg_interval: 30.0,
            min_rpt_interval: -1.0,
            min_share_interval: -1.0,
            max_msg_length: 1000,
            apply_groups: false,
            apply_groups_msgs: false,
            view_node_rpt_pulses: true,
            drop_pct: 0.0,
            pulse_duration: 10.0,
            msg_color: "white".into(),
            msg_repeat_color: "light_green".into(),
        }
    }
}

/// The pure uFldNodeComms.
///
/// ```
/// use runtime::node_comms::NodeComms;
/// use runtime::app::Value;
/// let (mut nc, w) = NodeComms::new(None, 1, &["comms_range = 100", "view_node_rpt_pulses = false"]);
/// assert_eq!(w, ["Lat or Lon Origin not set in *.moos file."]);
/// let mut out = Vec::new();
/// nc.on_mail("NODE_REPORT", &Value::text("NAME=abe,X=0,Y=0,SPD=1,HDG=0,TIME=1,TYPE=kayak"), 1.0, &mut out);
/// nc.on_mail("NODE_REPORT", &Value::text("NAME=ben,X=50,Y=0,SPD=1,HDG=0,TIME=1,TYPE=kayak"), 1.0, &mut out);
/// nc.iterate(1.0, &mut out);
/// assert!(out.iter().any(|p| p.key == "NODE_REPORT_BEN" && p.value.as_str().unwrap().starts_with("NAME=abe,X=0,Y=0")));
/// ```
#[derive(Debug, Clone)]
pub struct NodeComms {
    s: Settings,
    grid: Option<LocalGrid>,
    draws: Draws,
    ledger: BTreeMap<String, Entry>,
    total_reports: u64,
    stealth: BTreeMap<String, f64>,
    earange: BTreeMap<String, f64>,
    new_record: BTreeSet<String>,
    messages: BTreeMap<String, Vec<NodeMessage>>,
    time_nmessage: BTreeMap<String, f64>,
    /// The acknowledgements received since the last iteration, by source.
    acks: BTreeMap<String, Vec<AckMessage>>,
    /// When each source's last acknowledgement went out.
    time_amessage: BTreeMap<String, f64>,
    acks_rcvd: BTreeMap<String, u32>,
    acks_sent: BTreeMap<String, u32>,
    total_acks_rcvd: u64,
    total_acks_sent: u64,
    last_rpt: BTreeMap<String, f64>,
    lshare: BTreeMap<String, f64>,
    last_messages: VecDeque<String>,
    recent_ackids: VecDeque<String>,
    reports_sent: BTreeMap<String, u32>,
    messages_rcvd: BTreeMap<String, u32>,
    messages_sent: BTreeMap<String, u32>,
    total_reports_sent: u64,
    total_messages_rcvd: u64,
    total_messages_sent: u64,
    dropped: u64,
    stale_dropped: u64,
    blk_invalid: u32,
    blk_tooquick: u32,
    blk_toolong: u32,
    blk_toofar: u32,
    blk_noinfo: u32,
    blk_toostale: u32,
    start: Option<f64>,
    warp: f64,
    notes: Vec<Note>,
}

impl NodeComms {
    /// A relay on the mission's `grid` (`None`: a warning, no coordinate derivation), its
    /// drop draws seeded by `seed`, from the block's `param = value` lines; with the warnings
    /// the C++ app reports.
    pub fn new(grid: Option<LocalGrid>, seed: u64, lines: &[&str]) -> (NodeComms, Vec<String>) {
        let mut nc = NodeComms::blank(grid, seed);
        let mut w = nc.startup_warnings();
        for line in lines {
            let (k, v) = line.split_once('=').unwrap_or((line, ""));
            if let Err(e) = nc.configure(&k.trim().to_ascii_lowercase(), v.trim()) {
                w.push(e);
            }
        }
        (nc, w)
    }

    fn blank(grid: Option<LocalGrid>, seed: u64) -> NodeComms {
        NodeComms {
            s: Settings::default(),
            grid,
            draws: Draws(seed),
            ledger: BTreeMap::new(),
            total_reports: 0,
            stealth: BTreeMap::new(),
            earange: BTreeMap::new(),
            new_record: BTreeSet::new(),
            messages: BTreeMap::new(),
            time_nmessage: BTreeMap::new(),
            acks: BTreeMap::new(),
            time_amessage: BTreeMap::new(),
            acks_rcvd: BTreeMap::new(),
            acks_sent: BTreeMap::new(),
            total_acks_rcvd: 0,
            total_acks_sent: 0,
            last_rpt: BTreeMap::new(),
            lshare: BTreeMap::new(),
            last_messages: VecDeque::new(),
            recent_ackids: VecDeque::new(),
            reports_sent: BTreeMap::new(),
            messages_rcvd: BTreeMap::new(),
            messages_sent: BTreeMap::new(),
            total_reports_sent: 0,
            total_messages_rcvd: 0,
            total_messages_sent: 0,
            dropped: 0,
            stale_dropped: 0,
            blk_invalid: 0,
            blk_tooquick: 0,
            blk_toolong: 0,
            blk_toofar: 0,
            blk_noinfo: 0,
            blk_toostale: 0,
            start: None,
            warp: 1.0,
            notes: Vec::new(),
        }
    }

    fn startup_warnings(&self) -> Vec<String> {
        if self.grid.is_none() {
            vec!["Lat or Lon Origin not set in *.moos file.".to_string()]
        } else {
            Vec::new()
        }
    }

    /// One line of the block; `Err` with the C++'s warning.
    fn configure(&mut self, param: &str, value: &str) -> Result<(), String> {
        let s = &mut self.s;
        let d = geometry::atof(value);
        let num = is_number(value);
        let handled = match param {
            "comms_range" if value == "nolimit" => {
                s.comms_range = -1.0;
                true
            }
            "comms_range" => num.then(|| s.comms_range = d).is_some(),
            "critical_range" => (num && d >= 0.0).then(|| s.critical_range = d).is_some(),
            "stale_time" => {
                let ok = num.then(|| s.stale_time = d).is_some();
                s.stale_forget = s.stale_time * 20.0;
                ok
            }
            "min_msg_interval" => (num && d >= 0.0).then(|| s.min_msg_interval = d).is_some(),
            "min_rpt_interval" => (num && d >= 0.0).then(|| s.min_rpt_interval = d).is_some(),
            "max_msg_length" => (num && d >= 0.0)
                .then(|| s.max_msg_length = d as usize)
                .is_some(),
            "stealth" => self.set_stealth(value),
            "earange" => self.set_earange(value),
            "groups" => set_bool(&mut self.s.apply_groups, value),
            "msg_groups" => set_bool(&mut self.s.apply_groups_msgs, value),
            "view_node_rpt_pulses" => set_bool(&mut self.s.view_node_rpt_pulses, value),
            "drop_percentage" => (num && d > 0.0).then(|| s.drop_pct = d).is_some(),
            "pulse_duration" => num.then(|| s.pulse_duration = d).is_some(),
            "shared_node_reports" => self.set_shared(value),
            "msg_color" | "msg_repeat_color" => {
                let ok = geometry::color::is_color(value);
                if ok && param == "msg_color" {
                    s.msg_color = value.to_string();
                } else if ok {
                    s.msg_repeat_color = value.to_string();
                }
                ok
            }
            _ if appcast::casting::UNHANDLED_EXEMPT
                .contains(&param.to_ascii_uppercase().as_str())
                || matches!(param, "comms_policy" | "max_appcast_run_warnings") =>
            {
                true
            }
            _ => false,
        };
        if handled {
            Ok(())
        } else {
            Err(format!("Unhandled config line: {param}={value}"))
        }
    }

    fn vname_and(text: &str, keys: &[&str]) -> (String, String) {
        let (mut vname, mut val) = (String::new(), String::new());
        for part in parse_string(text, ',') {
            let (l, v) = part.split_once('=').unwrap_or((part, ""));
            let l = l.trim().to_ascii_lowercase();
            if l == "vname" {
                vname = v.trim().to_string();
            } else if keys.contains(&l.as_str()) {
                val = v.trim().to_string();
            }
        }
        (vname, val)
    }

    /// `vname=..,stealth=..` (MOOS `handleStealth`).
    fn set_stealth(&mut self, text: &str) -> bool {
        let (vname, v) = Self::vname_and(text, &["stealth"]);
        if !is_number(&v) {
            return false;
        }
        self.stealth
            .insert(vname, geometry::atof(&v).clamp(0.1, 1.0));
        true
    }

    /// `vname=..,earange=..` (MOOS `handleEarange`).
    fn set_earange(&mut self, text: &str) -> bool {
        let (vname, v) = Self::vname_and(text, &["earange", "earrange"]);
        if !is_number(&v) {
            return false;
        }
        self.earange
            .insert(vname, geometry::atof(&v).clamp(1.0, 10.0));
        true
    }

    fn set_shared(&mut self, v: &str) -> bool {
        if v.eq_ignore_ascii_case("true") {
            self.s.min_share_interval = 0.1;
        } else if v.eq_ignore_ascii_case("false") {
            self.s.min_share_interval = -1.0;
        } else if is_number(v) && geometry::atof(v) >= 0.0 {
            self.s.min_share_interval = geometry::atof(v);
        } else {
            return false;
        }
        true
    }

    /// The variables the app registers for.
    pub const SUBSCRIPTIONS: [&'static str; 11] = [
        "NODE_REPORT",
        "NODE_REPORT_LOCAL",
        "NODE_MESSAGE",
        "MEDIATED_MESSAGE",
        "ACK_MESSAGE",
        "UNC_COMMS_RANGE",
        "UNC_STEALTH",
        "UNC_EARANGE",
        "UNC_DROP_PCT",
        "UNC_SHARED_NODE_REPORTS",
        "UNC_VIEW_NODE_RPT_PULSES",
    ];

    /// One mail from `source` (MOOS `OnNewMail`).
    pub fn on_mail_from(&mut self, key: &str, value: &Value, source: &str, now: f64) {
        let sval = value.as_str().unwrap_or("");
        let dval = value.as_ref().as_f64().unwrap_or(0.0);
        let mut whynot = String::new();
        let handled = match key {
            "NODE_REPORT" | "NODE_REPORT_LOCAL" => match self.node_report(sval, now) {
                Ok(()) => true,
                Err(w) => {
                    whynot = w;
                    false
                }
            },
            "NODE_MESSAGE" | "MEDIATED_MESSAGE" => self.node_message(sval, source),
            "ACK_MESSAGE" => self.ack_message(sval),
            "UNC_SHARED_NODE_REPORTS" => self.set_shared(sval),
            "UNC_STEALTH" => self.set_stealth(sval),
            "UNC_COMMS_RANGE" => {
                self.s.comms_range = dval;
                true
            }
            "UNC_VIEW_NODE_RPT_PULSES" => set_bool(&mut self.s.view_node_rpt_pulses, sval),
            "UNC_EARANGE" => self.set_earange(sval),
            "UNC_DROP_PCT" => {
                let ok = (0.0..=100.0).contains(&dval);
                if ok {
                    self.s.drop_pct = dval;
                }
                ok
            }
            _ => false,
        };
        if !handled {
            let mut w = format!("Bad Mail: {key}");
            if !whynot.is_empty() {
                w.push(' ');
                w.push_str(&whynot);
            }
            self.notes.push(Note::Warning(w));
        }
    }

    /// One mail (no source).
    pub fn on_mail(&mut self, key: &str, value: &Value, now: f64, _out: &mut Vec<Post>) {
        self.on_mail_from(key, value, "", now);
    }

    /// MOOS `ContactLedger::processNodeReport` then `processNodeRecord`.
    fn node_report(&mut self, text: &str, now: f64) -> Result<(), String> {
        let mut r = NodeRecord::parse(text);
        let mut why = String::new();
        if r.name.is_empty() {
            why.push_str("Missing vname.");
        }
        if r.time.is_none() {
            why.push_str("Missing timestamp.");
        }
        if !r.has_latlon() && !r.has_xy() {
            why.push_str("Missing both x/y and lat/lon.");
        }
        if !why.is_empty() {
            return Err(why);
        }
        if let Some(g) = &self.grid {
            if r.has_latlon() && !r.has_xy() {
                if let Ok((x, y)) = g.to_local(r.lat.unwrap_or(0.0), r.lon.unwrap_or(0.0)) {
                    r.x = Some(x);
                    r.y = Some(y);
                }
            } else if !r.has_latlon()
                && r.has_xy()
                && let Ok((lat, lon)) = g.to_latlon(r.x.unwrap_or(0.0), r.y.unwrap_or(0.0))
            {
                r.lat = Some(lat);
                r.lon = Some(lon);
            }
        }
        self.total_reports += 1;
        r.vtype = helm::ledger::fixed_type(&r.vtype);
        if (r.vtype == "auv" || r.vtype == "glider") && r.depth.is_none() {
            return Err("underwater vehicle type with no depth reported".into());
        }
        if r.length.is_none_or(|l| l <= 0.0) {
            r.length = Some(match r.vtype.as_str() {
                "auv" | "kayak" | "heron" => 3.0,
                "glider" => 2.0,
                "cray" | "bcray" | "crayx" | "bcrayx" => 1.5,
                "ship" => 12.0,
                "longship" => 15.0,
                "wamv" | "smr" => 6.0,
                _ => r.length.unwrap_or(0.0),
            });
        }
        if r.cog.is_none() {
            match self.ledger.get(&r.name) {
                Some(prev) => {
                    let p = &prev.record;
                    if let (Some(px), Some(py), Some(x), Some(y)) = (p.x, p.y, r.x, r.y) {
                        r.cog = Some(vehicle::angle::rel_ang(px, py, x, y));
                    }
                }
                None => r.cog = r.heading.or(Some(0.0)),
            }
        }
        let name = r.name.clone();
        let e = self.ledger.entry(name.clone()).or_insert(Entry {
            record: NodeRecord::default(),
            received: now,
            reports: 0,
        });
        e.record = r;
        e.received = now;
        e.reports += 1;
        self.new_record.insert(name);
        Ok(())
    }

    /// MOOS `handleMailNodeMessage`.
    fn node_message(&mut self, text: &str, source: &str) -> bool {
        self.last_messages.push_back(text.to_string());
        if self.last_messages.len() > 5 {
            self.last_messages.pop_front();
        }
        let mut m = NodeMessage::parse(text);
        if !m.valid() {
            return false;
        }
        if m.src_app.is_empty() {
            m.src_app = source.to_string();
        }
        let src = m.src_node.clone();
        self.messages.entry(src.clone()).or_default().push(m);
        *self.messages_rcvd.entry(src).or_default() += 1;
        self.total_messages_rcvd += 1;
        self.notes.push(Note::Event(format!("Msg rec'd: {text}")));
        true
    }

    /// MOOS `handleMailAckMessage`: kept (with the last messages shown) and counted by its
    /// source; false when it is not a valid acknowledgement.
    fn ack_message(&mut self, text: &str) -> bool {
        self.last_messages.push_back(text.to_string());
        if self.last_messages.len() > 5 {
            self.last_messages.pop_front();
        }
        let m = AckMessage::parse(text);
        if !m.valid() {
            return false;
        }
        let src = m.src.clone();
        self.acks.entry(src.clone()).or_default().push(m);
        *self.acks_rcvd.entry(src).or_default() += 1;
        self.total_acks_rcvd += 1;
        self.notes.push(Note::Event(format!("Msg rec'd: {text}")));
        true
    }

    fn position(&self, v: &str) -> (f64, f64) {
        self.ledger.get(v).map_or((0.0, 0.0), |e| {
            (e.record.x.unwrap_or(0.0), e.record.y.unwrap_or(0.0))
        })
    }

    fn range(&self, a: &str, b: &str) -> f64 {
        let (x1, y1) = self.position(a);
        let (x2, y2) = self.position(b);
        (x1 - x2).hypot(y1 - y2)
    }

    /// MOOS `ContactLedger::isValid`: a name, x/y, lat/lon and a time. Without a grid the
    /// latitude and longitude are not required (MOOS makes them up from its uninitialised
    /// geodesy; coug cannot).
    fn is_valid(&self, r: &NodeRecord) -> bool {
        !r.name.is_empty()
            && r.has_xy()
            && (r.has_latlon() || self.grid.is_none())
            && r.time.is_some()
    }

    /// MOOS `hasVNameValidNotStale(v, thresh)` (the ledger itself has no stale threshold).
    fn valid_not_stale(&self, v: &str, thresh: f64, now: f64) -> bool {
        let Some(e) = self.ledger.get(v) else {
            return false;
        };
        if !e.record.valid() {
            return false;
        }
        !(thresh > 0.0 && now - e.record.time.unwrap_or(0.0) > thresh)
    }

    /// MOOS `isStale`: no report received within `thresh` (negative: never stale).
    fn is_stale(&self, v: &str, thresh: f64, now: f64) -> bool {
        if thresh < 0.0 {
            return false;
        }
        self.ledger
            .get(v)
            .is_some_and(|e| now - e.received >= thresh)
    }

    /// Whether `b` hears `a` (MOOS `meetsRangeThresh`).
    fn in_range(&self, a: &str, b: &str, now: f64) -> bool {
        if self.s.comms_range < 0.0 {
            return true;
        }
        if self.s.comms_range == 0.0 {
            return false;
        }
        if !self.valid_not_stale(a, 0.0, now) || !self.valid_not_stale(b, 0.0, now) {
            return false;
        }
        let stealth = self.stealth.get(a).copied().unwrap_or(1.0);
        let earange = self.earange.get(b).copied().unwrap_or(1.0);
        self.range(a, b) <= self.s.comms_range * stealth * earange
    }

    fn in_critical_range(&self, a: &str, b: &str, now: f64) -> bool {
        self.valid_not_stale(a, 0.0, now)
            && self.valid_not_stale(b, 0.0, now)
            && self.range(a, b) <= self.s.critical_range
    }

    /// True when the draw drops the message (MOOS `meetsDropPercentage`).
    fn drop_draw(&mut self) -> bool {
        if self.s.drop_pct > 0.0 && (self.draws.percent() as f64) < self.s.drop_pct {
            self.dropped += 1;
            return true;
        }
        false
    }

    fn rate_ok(&mut self, a: &str, b: &str, now: f64) -> bool {
        if self.s.min_rpt_interval < 0.0 {
            return true;
        }
        let key = format!("{}:{}", a.to_ascii_lowercase(), b.to_ascii_lowercase());
        match self.last_rpt.get(&key) {
            None => {
                self.last_rpt.insert(key, now);
                true
            }
            Some(t) => now - t >= self.s.min_rpt_interval,
        }
    }

    /// One iteration (MOOS `Iterate`).
    pub fn iterate(&mut self, now: f64, out: &mut Vec<Post>) {
        self.start.get_or_insert(now);
        for name in std::mem::take(&mut self.new_record) {
            self.distribute_report(&name, now, out);
            self.local_share(&name, now, out);
        }
        let sources: Vec<String> = self.messages.keys().cloned().collect();
        for src in sources {
            let msgs = self.messages.remove(&src).unwrap_or_default();
            for m in msgs {
                if self.interval_ok(Kind::Message, &src, now) {
                    self.distribute_message(&src, &m, now, out);
                }
            }
        }
        for (src, acks) in std::mem::take(&mut self.acks) {
            for m in acks {
                if self.interval_ok(Kind::Ack, &src, now) {
                    self.distribute_ack(&src, &m, now, out);
                }
            }
        }
        self.clear_stale(now);
    }

    /// MOOS `distributeNodeReportInfo`.
    fn distribute_report(&mut self, us: &str, now: f64, out: &mut Vec<Post>) {
        let Some(e) = self.ledger.get(us) else {
            return;
        };
        if !self.is_valid(&e.record) {
            return;
        }
        let report = e.record.spec();
        let names: Vec<String> = self.ledger.keys().cloned().collect();
        for v in names {
            if v == us {
                continue;
            }
            if self.in_critical_range(us, &v, now) {
                self.post_report(us, &v, &report, now, out);
                continue;
            }
            if self.is_stale(&v, self.s.stale_time, now) || !self.in_range(us, &v, now) {
                continue;
            }
            if self.s.apply_groups && self.ledger[us].record.group != self.ledger[&v].record.group {
                continue;
            }
            if self.drop_draw() || !self.rate_ok(us, &v, now) {
                continue;
            }
            self.post_report(us, &v, &report, now, out);
        }
    }

    fn post_report(&mut self, us: &str, v: &str, report: &str, now: f64, out: &mut Vec<Post>) {
        out.push(Post::text(
            format!("NODE_REPORT_{}", v.to_ascii_uppercase()),
            report.to_string(),
        ));
        if self.s.view_node_rpt_pulses {
            self.pulse(us, v, "nrep", "auto", 0.35, now, out);
        }
        self.total_reports_sent += 1;
        *self.reports_sent.entry(v.to_string()).or_default() += 1;
        let key = format!("{}:{}", us.to_ascii_lowercase(), v.to_ascii_lowercase());
        self.last_rpt.insert(key, now);
    }

    /// MOOS `localShareNodeReportInfo`.
    fn local_share(&mut self, us: &str, now: f64, out: &mut Vec<Post>) {
        let Some(e) = self.ledger.get(us) else {
            return;
        };
        let r = &e.record;
        if !self.is_valid(r) || self.s.min_share_interval < 0.0 {
            return;
        }
        if let Some(t) = self.lshare.get(us) {
            let real = (now - t) / self.warp;
            out.push(Post::double("RTE", real));
            if real < self.s.min_share_interval {
                return;
            }
        }
        self.lshare.insert(us.to_string(), now);
        out.push(Post::text("NODE_REPORT_UNC", r.spec()));
    }

    /// Whether a message (an acknowledgement) of `src` may go out now, at most one per
    /// `min_msg_interval` for each kind (the time is then taken); else counted as too
    /// recent. The C++ starts from time 0, so the first one always goes.
    fn interval_ok(&mut self, kind: Kind, src: &str, now: f64) -> bool {
        let times = match kind {
            Kind::Message => &mut self.time_nmessage,
            Kind::Ack => &mut self.time_amessage,
        };
        if times
            .get(src)
            .is_none_or(|t| now - t >= self.s.min_msg_interval)
        {
            times.insert(src.to_string(), now);
            true
        } else {
            self.blk_tooquick += 1;
            false
        }
    }

    /// MOOS `distributeAckMessageInfo(src, msg)`: posted as `ACK_MESSAGE_<dest>` (the name
    /// as the acknowledgement gives it) when both vehicles have valid reports not older than
    /// `stale_time`, are within comms range, and the drop draw keeps it.
    fn distribute_ack(&mut self, src: &str, m: &AckMessage, now: f64, out: &mut Vec<Post>) {
        if !m.valid() {
            self.blk_invalid += 1;
            return;
        }
        let dest = m.dest.as_str();
        let has_valid = |v: &str| self.ledger.get(v).is_some_and(|e| e.record.valid());
        if !has_valid(src) || !has_valid(dest) {
            self.blk_noinfo += 1;
            return;
        }
        let stale = self.s.stale_time;
        if !self.valid_not_stale(src, stale, now) || !self.valid_not_stale(dest, stale, now) {
            self.blk_toostale += 1;
            return;
        }
        if !self.in_range(src, dest, now) {
            self.blk_toofar += 1;
            return;
        }
        if self.drop_draw() {
            return;
        }
        out.push(Post::text(format!("ACK_MESSAGE_{dest}"), m.spec()));
        self.total_acks_sent += 1;
        *self.acks_sent.entry(dest.to_string()).or_default() += 1;
    }

    /// MOOS `distributeNodeMessageInfo(src, msg)`.
    fn distribute_message(&mut self, src: &str, m: &NodeMessage, now: f64, out: &mut Vec<Post>) {
        if !m.valid() {
            self.blk_invalid += 1;
            return;
        }
        if self.s.max_msg_length > 0 && m.length() > self.s.max_msg_length {
            self.blk_toolong += 1;
            return;
        }
        if !self.valid_not_stale(src, 0.0, now) {
            return;
        }
        let color = if m.color.is_empty() {
            self.s.msg_color.clone()
        } else {
            m.color.clone()
        };
        let by_group = |g: &str| -> BTreeSet<String> {
            let g = g.trim();
            if g.is_empty() {
                return BTreeSet::new();
            }
            self.ledger
                .iter()
                .filter(|(_, e)| g == "all" || e.record.group == g)
                .map(|(n, _)| n.clone())
                .collect()
        };
        let all = ["ALL", "all"].contains(&m.dest_node.as_str())
            || ["ALL", "all"].contains(&m.dest_group.as_str());
        let mut dests = if all {
            by_group("all")
        } else {
            let mut d: BTreeSet<String> = m
                .dest_node
                .split(':')
                .map(str::trim)
                .filter(|n| self.ledger.contains_key(*n))
                .map(str::to_string)
                .collect();
            d.extend(by_group(&m.dest_group));
            d
        };
        dests.remove(src);
        for d in dests {
            if self.s.apply_groups_msgs
                && self.ledger.get(src).map(|e| &e.record.group)
                    != self.ledger.get(&d).map(|e| &e.record.group)
            {
                continue;
            }
            if !self.valid_not_stale(&d, self.s.stale_time, now) {
                self.blk_noinfo += 1;
                continue;
            }
            if !self.in_range(src, &d, now) {
                self.blk_toofar += 1;
                continue;
            }
            if self.drop_draw() {
                continue;
            }
            let prefix = if m.ack {
                "MEDIATED_MESSAGE_"
            } else {
                "NODE_MESSAGE_"
            };
            out.push(Post::text(
                format!("{prefix}{}", d.to_ascii_uppercase()),
                m.spec(),
            ));
            let repeat = !m.msg_id.is_empty() && self.recent_ackids.contains(&m.msg_id);
            let c = if repeat {
                self.s.msg_repeat_color.clone()
            } else {
                color.clone()
            };
            self.pulse(src, &d, "msg", &c, 0.6, now, out);
            if !m.msg_id.is_empty() {
                self.recent_ackids.push_front(m.msg_id.clone());
                self.recent_ackids.truncate(100);
            }
            self.total_messages_sent += 1;
            *self.messages_sent.entry(d).or_default() += 1;
        }
    }

    /// MOOS `clearStaleNodes`: vehicles silent for 20 × `stale_time` are forgotten.
    fn clear_stale(&mut self, now: f64) {
        if self.s.stale_forget < 0.0 {
            return;
        }
        let stale: Vec<String> = self
            .ledger
            .keys()
            .filter(|v| self.is_stale(v, self.s.stale_forget, now))
            .cloned()
            .collect();
        self.stale_dropped += stale.len() as u64;
        for v in stale {
            self.ledger.remove(&v);
            self.messages.remove(&v);
            self.new_record.remove(&v);
            self.time_nmessage.remove(&v);
            self.lshare.remove(&v);
            self.reports_sent.remove(&v);
            self.messages_rcvd.remove(&v);
            self.messages_sent.remove(&v);
        }
    }

    /// `VIEW_COMMS_PULSE` from `a` to `b` (MOOS `postViewCommsPulse`, `XYCommsPulse`).
    #[allow(clippy::too_many_arguments)]
    fn pulse(
        &self,
        a: &str,
        b: &str,
        ptype: &str,
        color: &str,
        fill: f64,
        now: f64,
        out: &mut Vec<Post>,
    ) {
        if self.s.pulse_duration <= 0.0 {
            return;
        }
        let lc = color.to_ascii_lowercase();
        if lc == "invisible" || lc == "off" || a == b {
            return;
        }
        let (x1, y1) = self.position(a);
        let (x2, y2) = self.position(b);
        let width = (0.1 * (x1 - x2).hypot(y1 - y2)).max(5.0);
        let mut label = format!("{a}2{b}");
        if color != "auto" {
            label.push_str(color);
        }
        let mut s = String::new();
        for (k, v) in [
            ("sx=", x1),
            (",sy=", y1),
            (",tx=", x2),
            (",ty=", y2),
            (",beam_width=", width),
            (",fill=", fill),
        ] {
            s.push_str(k);
            s.push_str(&compact_string(v, 5));
        }
        s.push_str(",ptype=");
        s.push_str(ptype);
        let mut attrs = geometry::Attributes::labeled(label);
        attrs.fill_color = Some(if color == "auto" { "orange" } else { color }.to_string());
        attrs.time = Some(now);
        attrs.duration = Some(self.s.pulse_duration);
        attrs.write_spec(&mut s, 0);
        out.push(Post::text("VIEW_COMMS_PULSE", s));
    }

    /// Takes the appcast events and warnings gathered since the last call.
    pub fn take_notes(&mut self) -> Vec<Note> {
        std::mem::take(&mut self.notes)
    }

    /// Reports relayed so far, and reports the drop draws kept back.
    pub fn counts(&self) -> (u64, u64) {
        (self.total_reports_sent, self.dropped)
    }

    /// The acknowledgements received and relayed so far (MOOS keeps these counts; its
    /// appcast does not show them).
    pub fn ack_counts(&self) -> (u64, u64) {
        (self.total_acks_rcvd, self.total_acks_sent)
    }

    /// The appcast body (MOOS `buildReport`).
    pub fn report(&self, now: f64, b: &mut String) {
        let s = &self.s;
        let shared = s.min_rpt_interval > 0.0;
        let mut share = shared.to_string();
        if shared {
            let _ = write!(share, " ({})", compact_string(s.min_share_interval, 2));
        }
        let _ = writeln!(b, "Configuration:  ");
        let _ = writeln!(
            b,
            "       Comms Range: {}",
            compact_string(s.comms_range, 5)
        );
        let _ = writeln!(
            b,
            "    Critical Range: {}",
            compact_string(s.critical_range, 5)
        );
        let _ = writeln!(b, "        Stale Drop: {}", compact_string(s.stale_time, 5));
        let _ = writeln!(
            b,
            "       Stale Foget: {}",
            compact_string(s.stale_forget, 5)
        );
        let _ = writeln!(b, "   Max Message Len: {}", s.max_msg_length);
        let _ = writeln!(
            b,
            "   Min Message Int: {}",
            compact_string(s.min_msg_interval, 5)
        );
        let _ = writeln!(
            b,
            "   Min Report  Int: {}",
            compact_string(s.min_rpt_interval, 2)
        );
        let _ = writeln!(b, "          Drop Pct: {}", compact_string(s.drop_pct, 2));
        let _ = writeln!(b, "Apply Group (reps): {}", s.apply_groups);
        let _ = writeln!(b, "Apply Group (msgs): {}", s.apply_groups_msgs);
        let _ = writeln!(b, "     Share Reports: {share}");
        let _ = writeln!(b);
        let elapsed = now - self.start.unwrap_or(now);
        let _ = writeln!(b, "Node Report Summary");
        let _ = writeln!(b, "======================================");
        let _ = writeln!(
            b,
            "     Total Received: {:<10}Elapsed      Rate",
            self.total_reports
        );
        for (v, e) in &self.ledger {
            let mut age = String::from("(");
            fixed(&mut age, now - e.received, 1);
            age.push(')');
            let rate = if elapsed > 0.0 {
                let mut r = String::new();
                fixed(&mut r, f64::from(e.reports) / elapsed, 2);
                r
            } else {
                "n/a".into()
            };
            let _ = writeln!(
                b,
                "  {v:<17}: {:<7}{age:<8}{:<12}",
                e.reports,
                format!("[{rate}]")
            );
        }
        let _ = writeln!(b, "     --------------- ");
        let _ = writeln!(b, "         Total Sent: {}", self.total_reports_sent);
        for (v, n) in &self.reports_sent {
            let _ = writeln!(b, "  {v:<17}: {n}");
        }
        let _ = writeln!(b, "     --------------- ");
        let _ = writeln!(b, "     Stale Vehicles: {}", self.stale_dropped);
        let _ = writeln!(b);
        let _ = writeln!(b, "Node Message Summary");
        let _ = writeln!(b, "======================================");
        let _ = writeln!(b, "    Total Msgs Received: {}", self.total_messages_rcvd);
        for (v, n) in &self.messages_rcvd {
            let mut t = String::from("(");
            fixed(
                &mut t,
                now - self.time_nmessage.get(v).copied().unwrap_or(0.0),
                1,
            );
            t.push(')');
            let _ = writeln!(b, "  {v:<20}: {n}{t:<12}");
        }
        let _ = writeln!(b, "     ------------------ ");
        let _ = writeln!(b, "            Total Sent: {}", self.total_messages_sent);
        for (v, n) in &self.messages_sent {
            let _ = writeln!(b, "  {v:<20}: {n}");
        }
        let total = self.blk_invalid
            + self.blk_toostale
            + self.blk_tooquick
            + self.blk_toolong
            + self.blk_toofar
            + self.blk_noinfo;
        let _ = writeln!(b, "     ------------------ ");
        let _ = writeln!(b, "    Total Blocked Msgs: {total}");
        let _ = writeln!(b, "               Invalid: {}", self.blk_invalid);
        let _ = writeln!(b, "          Missing Info: {}", self.blk_noinfo);
        let _ = writeln!(b, "        Stale Receiver: {}", self.blk_toostale);
        let _ = writeln!(b, "            Too Recent: {}", self.blk_tooquick);
        let _ = writeln!(b, "          Msg Too Long: {}", self.blk_toolong);
        let _ = writeln!(b, "         Range Too Far: {}\n", self.blk_toofar);
    }
}

/// MOOS `setBooleanOnString` into `b`.
fn set_bool(b: &mut bool, v: &str) -> bool {
    match set_boolean_on_string(*b, v) {
        Some(x) => {
            *b = x;
            true
        }
        None => false,
    }
}

/// The `uFldNodeComms` app: the core [`Hosted`].
pub type NodeCommsApp = Hosted<NodeComms>;

impl Hosted<NodeComms> {
    /// The app `name` from its block, on the mission's `grid`, its drop draws seeded by
    /// `seed`.
    pub fn new(name: &str, block: ProcessConfig, grid: Option<LocalGrid>, seed: u64) -> Self {
        let mut core = NodeComms::blank(grid, seed);
        let mut warnings = Vec::new();
        for w in core.startup_warnings() {
            warnings.push(Diagnostic::line_warning(
                DiagnosticKind::AppSetting,
                &block.span,
                format!("{PROGRAM}: {w}"),
            ));
        }
        for p in &block.entries {
            if let Err(w) = core.configure(&p.key.trim().to_ascii_lowercase(), p.value.trim()) {
                warnings.push(Diagnostic::line_warning(
                    DiagnosticKind::AppSetting,
                    &p.span,
                    format!("{PROGRAM}: {w}"),
                ));
            }
        }
        Hosted::host(name, block, warnings, core)
    }

    /// Sets the mission's `Community` and `MOOSTimeWarp` (the warp also scales
    /// `shared_node_reports`' real-time interval).
    pub fn with_globals(mut self, community: Option<&str>, warp: f64) -> Self {
        self.core_mut().warp = warp;
        crate::antler::BuiltInApp::with_appcast_globals(self, community, warp)
    }
}

impl AppCore for NodeComms {
    fn subscriptions(&self) -> Vec<Subscription> {
        Self::SUBSCRIPTIONS
            .iter()
            .map(|v| Subscription::var(*v))
            .collect()
    }

    fn on_mail(&mut self, m: &Mail, now: f64, _out: &mut Vec<Post>, notes: &mut Vec<Note>) {
        self.on_mail_from(&m.key, &m.value, &m.source, now);
        notes.extend(self.take_notes());
    }

    fn iterate(&mut self, now: f64, out: &mut Vec<Post>, notes: &mut Vec<Note>) {
        NodeComms::iterate(self, now, out);
        notes.extend(self.take_notes());
    }

    fn report(&self, now: f64, body: &mut String) {
        NodeComms::report(self, now, body);
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::antler::BuiltInApp;

    fn report(name: &str, x: f64, y: f64, t: f64) -> Value {
        Value::text(format!(
            "NAME={name},X={x},Y={y},SPD=1,HDG=90,TIME={t},TYPE=kayak,GROUP=blue"
        ))
    }

    fn sent<'a>(out: &'a [Post], to: &str) -> Vec<&'a str> {
        let key = format!("NODE_REPORT_{to}");
        out.iter()
            .filter(|p| p.key == key.as_str())
            .filter_map(|p| p.value.as_str())
            .collect()
    }

    #[test]
    fn reports_go_to_vehicles_within_comms_range_only() {
        // abe at the origin, ben 90 m east, cal 150 m east: with comms_range 100 and
        // critical_range 25, abe and ben hear each other, cal hears ben (60 m) but not abe.
        let (mut nc, w) = NodeComms::new(
            None,
            7,
            &[
                "comms_range = 100",
                "critical_range = 25",
                "pulse_duration = 5",
            ],
        );
        assert_eq!(w, ["Lat or Lon Origin not set in *.moos file."]);
        let mut out = Vec::new();
        for (n, x) in [("abe", 0.0), ("ben", 90.0), ("cal", 150.0)] {
            nc.on_mail("NODE_REPORT", &report(n, x, 0.0, 10.0), 10.0, &mut out);
        }
        nc.iterate(10.0, &mut out);
        let from = |v: &[&str], who: &str| v.iter().any(|r| r.starts_with(&format!("NAME={who},")));
        assert!(from(&sent(&out, "BEN"), "abe"));
        assert!(from(&sent(&out, "ABE"), "ben"));
        assert!(from(&sent(&out, "CAL"), "ben"));
        assert!(from(&sent(&out, "BEN"), "cal"));
        assert!(!from(&sent(&out, "CAL"), "abe"), "150 m > comms_range");
        assert!(!from(&sent(&out, "ABE"), "cal"));
        // The relayed text: the record written back, length and course over ground added.
        assert_eq!(
            sent(&out, "BEN")[0],
            "NAME=abe,X=0,Y=0,SPD=1,HDG=90,COG=90,TYPE=kayak,GROUP=blue,TIME=10,LENGTH=3"
        );
        // A pulse per relayed report, from sender to receiver.
        let pulse = out
            .iter()
            .find(|p| p.key == "VIEW_COMMS_PULSE")
            .and_then(|p| p.value.as_str())
            .unwrap();
        assert_eq!(
            pulse,
            "sx=0,sy=0,tx=90,ty=0,beam_width=9,fill=0.35,ptype=nrep,label=abe2ben,fill_color=orange,time=10,duration=5"
        );
        // Only new reports go out: nothing more at the next iteration.
        out.clear();
        nc.iterate(10.5, &mut out);
        assert!(out.iter().all(|p| !p.key.starts_with("NODE_REPORT_")));
    }

    #[test]
    fn critical_range_overrides_and_stealth_and_earange_scale_the_range() {
        let (mut nc, _) = NodeComms::new(
            None,
            1,
            &[
                "comms_range = 0",
                "critical_range = 20",
                "view_node_rpt_pulses = false",
            ],
        );
        let mut out = Vec::new();
        nc.on_mail("NODE_REPORT", &report("abe", 0.0, 0.0, 1.0), 1.0, &mut out);
        nc.on_mail("NODE_REPORT", &report("ben", 15.0, 0.0, 1.0), 1.0, &mut out);
        nc.iterate(1.0, &mut out);
        assert_eq!(
            sent(&out, "BEN").len(),
            1,
            "within critical_range, comms off"
        );
        assert!(out.iter().all(|p| p.key != "VIEW_COMMS_PULSE"));
        let (mut nc, _) = NodeComms::new(
            None,
            1,
            &[
                "comms_range = 100",
                "critical_range = 0",
                "stealth = vname=abe, stealth=0.5",
                "earange = vname=ben, earange=1.5",
            ],
        );
        // 100 * 0.5 * 1.5 = 75: ben at 70 m hears abe; abe at 70 m from ben hears ben
        // only within 100 * 1 * 1 (abe has no earange).
        out.clear();
        nc.on_mail("NODE_REPORT", &report("abe", 0.0, 0.0, 1.0), 1.0, &mut out);
        nc.on_mail("NODE_REPORT", &report("ben", 70.0, 0.0, 1.0), 1.0, &mut out);
        nc.iterate(1.0, &mut out);
        assert_eq!(sent(&out, "BEN").len(), 1);
        assert_eq!(sent(&out, "ABE").len(), 1);
        nc.on_mail("NODE_REPORT", &report("abe", 0.0, 0.0, 2.0), 2.0, &mut out);
        nc.on_mail("NODE_REPORT", &report("ben", 80.0, 0.0, 2.0), 2.0, &mut out);
        out.clear();
        nc.iterate(2.0, &mut out);
        assert!(sent(&out, "BEN").is_empty(), "80 m > 75 m");
        assert_eq!(sent(&out, "ABE").len(), 1, "80 m < 100 m");
    }

    #[test]
    fn a_seeded_drop_percentage_loses_its_share_of_reports() {
        // Two vehicles 10 m apart (critical_range 0 so the draw applies), 4000 reports each
        // way; 30 % configured.
        let run = |seed: u64| {
            let (mut nc, w) = NodeComms::new(
                None,
                seed,
                &[
                    "comms_range = 100",
                    "critical_range = 0",
                    "drop_percentage = 30",
                    "view_node_rpt_pulses = false",
                    "stale_time = -1",
                ],
            );
            assert_eq!(w.len(), 1);
            let mut out = Vec::new();
            for i in 0..4000 {
                let t = f64::from(i) * 0.5;
                nc.on_mail("NODE_REPORT", &report("abe", 0.0, 0.0, t), t, &mut out);
                nc.on_mail("NODE_REPORT", &report("ben", 10.0, 0.0, t), t, &mut out);
                nc.iterate(t, &mut out);
            }
            let got = out
                .iter()
                .filter(|p| p.key.starts_with("NODE_REPORT_"))
                .count();
            (got, nc.counts())
        };
        let (got, (sent_n, dropped)) = run(42);
        assert_eq!(got as u64, sent_n);
        assert_eq!(sent_n + dropped, 8000);
        let loss = dropped as f64 / 8000.0;
        // Binomial(8000, 0.3): sd 0.5 %; 4 sd either side.
        assert!((loss - 0.30).abs() < 0.02, "loss {loss}");
        // Same seed, same draws; another seed, other draws.
        assert_eq!(run(42).0, got);
        assert_ne!(run(43).0, got);
    }

    #[test]
    fn reports_in_lat_lon_get_x_y_on_the_grid() {
        let grid = LocalGrid::new(43.8253, -70.3304).unwrap();
        let (lat, lon) = grid.to_latlon(30.0, -40.0).unwrap();
        let (mut nc, w) = NodeComms::new(Some(grid), 1, &["view_node_rpt_pulses=false"]);
        assert!(w.is_empty());
        let mut out = Vec::new();
        let t = format!("NAME=abe,LAT={lat},LON={lon},SPD=1,HDG=0,TIME=3,TYPE=kayak");
        nc.on_mail("NODE_REPORT", &Value::text(t), 3.0, &mut out);
        nc.on_mail(
            "NODE_REPORT",
            &report("ben", 30.0, -20.0, 3.0),
            3.0,
            &mut out,
        );
        nc.iterate(3.0, &mut out);
        let r = NodeRecord::parse(sent(&out, "BEN")[0]);
        assert!((r.x.unwrap() - 30.0).abs() < 0.01 && (r.y.unwrap() + 40.0).abs() < 0.01);
        // ben's x/y gave it a latitude and longitude too.
        let r = NodeRecord::parse(sent(&out, "ABE")[0]);
        assert!(r.lat.is_some() && r.lon.is_some());
    }

    #[test]
    fn node_messages_are_routed_to_their_destinations_at_most_once_per_interval() {
        let (mut nc, _) =
            NodeComms::new(None, 1, &["comms_range = nolimit", "min_msg_interval = 10"]);
        let mut out = Vec::new();
        for (n, x) in [("abe", 0.0), ("ben", 50.0), ("cal", 900.0)] {
            nc.on_mail("NODE_REPORT", &report(n, x, 0.0, 1.0), 1.0, &mut out);
        }
        let msg = "src_node=abe,dest_node=all,var_name=FOO,string_val=\"a,b\"";
        nc.on_mail_from("NODE_MESSAGE", &Value::text(msg), "pHelmIvP", 1.0);
        nc.iterate(1.0, &mut out);
        let m: Vec<(&str, &str)> = out
            .iter()
            .filter(|p| p.key.starts_with("NODE_MESSAGE_"))
            .map(|p| (&*p.key, p.value.as_str().unwrap()))
            .collect();
        let spec = "src_node=abe,dest_node=all,src_app=pHelmIvP,var_name=FOO,string_val=\"a,b\"";
        assert_eq!(m, [("NODE_MESSAGE_BEN", spec), ("NODE_MESSAGE_CAL", spec)]);
        // A second within min_msg_interval is held back.
        out.clear();
        nc.on_mail(
            "NODE_MESSAGE",
            &Value::text("src_node=abe,dest_node=ben,var_name=X,double_val=2"),
            2.0,
            &mut out,
        );
        nc.iterate(2.0, &mut out);
        assert!(out.iter().all(|p| !p.key.starts_with("NODE_MESSAGE_")));
        // An invalid message is bad mail.
        nc.on_mail("NODE_MESSAGE", &Value::text("dest_node=ben"), 3.0, &mut out);
        assert!(
            nc.take_notes()
                .contains(&Note::Warning("Bad Mail: NODE_MESSAGE".into()))
        );
    }

    #[test]
    fn acknowledgements_go_to_their_destination_as_ack_message_vname() {
        // abe at the origin, ben 50 m east (comms_range 100, stale_time 5, min_msg_interval
        // 10): the C++'s checks in order, each blocked acknowledgement counted once.
        let (mut nc, _) = NodeComms::new(None, 1, &["min_msg_interval = 10"]);
        let mut out = Vec::new();
        let acks = |out: &[Post]| -> Vec<String> {
            out.iter()
                .filter(|p| p.key.starts_with("ACK_MESSAGE_"))
                .map(|p| format!("{}={}", p.key, p.value.as_str().unwrap()))
                .collect()
        };
        /// A step: the time, who reports from where, the acknowledgements mailed, what goes
        /// out, the counts received and relayed.
        type Step<'a> = (
            f64,
            &'a [(&'a str, f64)],
            &'a [&'a str],
            &'a [&'a str],
            (u64, u64),
        );
        let steps: [Step; 5] = [
            // Two from ben in one iteration: the first goes, to the name as written (not
            // upper case), the second is too recent.
            (
                1.0,
                &[("abe", 0.0), ("ben", 50.0)],
                &["src=ben, dest=abe, id=abe_1", "SRC=ben,DEST=abe,ID=abe_2"],
                &["ACK_MESSAGE_abe=id=abe_1, src=ben, dest=abe"],
                (2, 1),
            ),
            // 10 s later ben may send again; to a vehicle nobody knows: missing info.
            (
                11.0,
                &[("abe", 0.0), ("ben", 50.0)],
                &["src=ben, dest=cal, id=cal_1"],
                &[],
                (3, 1),
            ),
            // Beyond comms range: too far (the interval has passed again).
            (
                21.0,
                &[("abe", 0.0), ("ben", 500.0)],
                &["src=ben, dest=abe, id=abe_3"],
                &[],
                (4, 1),
            ),
            // abe's last report (21 s) older than stale_time: a stale receiver.
            (
                37.0,
                &[("ben", 50.0)],
                &["src=ben, dest=abe, id=abe_4"],
                &[],
                (5, 1),
            ),
            // abe acknowledges back, in range and fresh: ACK_MESSAGE_ben.
            (
                40.0,
                &[("abe", 0.0), ("ben", 50.0)],
                &["src=abe, dest=ben, id=ben_1"],
                &["ACK_MESSAGE_ben=id=ben_1, src=abe, dest=ben"],
                (6, 2),
            ),
        ];
        for (t, at, mail, want, counts) in steps {
            out.clear();
            for (v, x) in at {
                nc.on_mail("NODE_REPORT", &report(v, *x, 0.0, t), t, &mut out);
            }
            for m in mail {
                nc.on_mail("ACK_MESSAGE", &Value::text(*m), t, &mut out);
            }
            nc.iterate(t, &mut out);
            assert_eq!(acks(&out), want, "at {t}");
            assert_eq!(nc.ack_counts(), counts, "at {t}");
        }
        // Not an acknowledgement (no id; a source that is its destination): bad mail.
        for bad in ["src=ben, dest=abe", "src=abe, dest=abe, id=3"] {
            nc.on_mail("ACK_MESSAGE", &Value::text(bad), 41.0, &mut out);
        }
        let bad = Note::Warning("Bad Mail: ACK_MESSAGE".into());
        assert_eq!(nc.take_notes().iter().filter(|n| **n == bad).count(), 2);
        assert_eq!(nc.ack_counts(), (6, 2));
        let mut body = String::new();
        nc.report(41.0, &mut body);
        for line in [
            "    Total Blocked Msgs: 4",
            "          Missing Info: 1",
            "        Stale Receiver: 1",
            "            Too Recent: 1",
            "         Range Too Far: 1",
        ] {
            assert!(body.contains(line), "{line:?} in\n{body}");
        }
        assert!(NodeComms::SUBSCRIPTIONS.contains(&"ACK_MESSAGE"));
    }

    #[test]
    fn every_catalog_parameter_is_read() {
        for key in mission::catalog::NODE_COMMS_PARAMS {
            let value = match *key {
                "stealth" => "vname=abe, stealth=0.5",
                "earange" => "vname=abe, earange=2",
                "msg_color" | "msg_repeat_color" => "white",
                "groups"
                | "msg_groups"
                | "view_node_rpt_pulses"
                | "shared_node_reports"
                | "app_logging"
                | "deprecated_ok" => "true",
                _ => "5",
            };
            let line = format!("{key} = {value}");
            let (_, w) = NodeComms::new(None, 1, &[&line]);
            assert_eq!(w.len(), 1, "{line}: {w:?}");
        }
    }

    #[test]
    fn bad_lines_are_warned_and_the_app_registers_its_variables() {
        let (_, w) = NodeComms::new(
            None,
            1,
            &[
                "critical_range = -3",
                "drop_percentage = 0",
                "bogus = 2",
                "AppTick = 4",
            ],
        );
        assert_eq!(
            &w[1..],
            [
                "Unhandled config line: critical_range=-3",
                "Unhandled config line: drop_percentage=0",
                "Unhandled config line: bogus=2",
            ]
        );
        let block = crate::testing::block(
            "s.moos",
            "ProcessConfig = uFldNodeComms\n{\n  AppTick = 2\n  comms_range = far\n}\n",
        );
        let app = NodeCommsApp::new("uFldNodeComms", block, None, 1);
        let located: Vec<String> = app.warnings().iter().map(Diagnostic::located).collect();
        assert!(located[1].contains("s.moos:4") && located[1].contains("comms_range=far"));
        let subs: Vec<String> = crate::app::App::subscriptions(&app)
            .into_iter()
            .map(|s| s.pattern)
            .collect();
        assert!(subs.contains(&"NODE_REPORT_LOCAL".to_string()));
    }
}
