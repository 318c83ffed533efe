//! `pAcomms`, the polled acoustic network app, and `uSimModem`, the simulated acoustic modem
//! (issue #16, points 2 and 3).
//!
//! # The modem interface
//!
//! pAcomms talks to its modem only through the variables of `iSeaTrac`
//! ([`drivers::seatrac`]), so on a vehicle it runs over the real SeaTrac driver unchanged and
//! in simulation over uSimModem:
//!
//! | variable | direction | format |
//! |---|---|---|
//! | `ACOMMS_TX` | pAcomms → modem | `dest=<id>,hex=<payload>,type=OWAYU` |
//! | `USBL_FIX` | modem → pAcomms | `src=<id>,dest=<id>,type=..` then `range=`, `azimuth=`, `elevation=`, `x=`, `y=`, `z=` as measured (posted with `USBL_SRC`, `USBL_RANGE`, `USBL_AZIMUTH`, `USBL_ELEVATION`, `USBL_X`, `USBL_Y`, `USBL_Z`) |
//! | `ACOMMS_RX` | modem → pAcomms | `src=<id>,dest=<id>,ack=0,hex=<payload>`, right after its `USBL_FIX` |
//! | `ACOMMS_TX_ACK`, `ACOMMS_ERROR` | modem → | a send went out, or failed |
//!
//! pAcomms pairs an `ACOMMS_RX` with the `USBL_FIX` of the same source received in the same
//! mail batch or within the second before it. The names are iSeaTrac's as they were; nothing
//! in `driver_apps` changed.
//!
//! # pAcomms
//!
//! The core is [`acomms::net`] (roles, queue, polls, timeouts, contacts); this app feeds it
//! the mail and posts what it says.
//!
//! | parameter | default | meaning |
//! |---|---|---|
//! | `modem_id` | required | this node's modem id, 1-15 |
//! | `role` | `vehicle` | `base` or `lead` (the poller) or `vehicle` |
//! | `key` | (a default, with a warning) | the fleet's shared secret (text) for the HMAC tags |
//! | `node` | | `<id>:<name>`, once per fleet node (this one may be listed); senders outside the list are refused when there is one |
//! | `poll_order` | the fleet list | `3,2,...`: the vehicles a poller polls, in turn |
//! | `slot`, `timeout` | 4, 4 | seconds between a poller's transmissions, and waiting for an answer |
//! | `command_tries` | 2 | transmissions of a command until confirmed |
//! | `command_max_age` | 60 | seconds: a command whose time field (the sender's clock when it sent it, see `acomms::auth`) is older than this on this node's clock when it arrives, or that far ahead, is refused and counted (`stale=` in `ACOMMS_STATUS`); 0: any age |
//! | `localisation_every` | 0 | seconds between a poller's position broadcasts (0: never) |
//! | `usbl_azimuth` | `world` | `world` (from north, as uSimModem and a SeaTrac with its AHRS) or `body` (from the listener's heading) |
//! | `x`, `y`, `depth` | | the listener's position when it has no `NAV_*` (a moored base) |
//! | `platform_type` | `UUV` | TYPE of the contacts' NODE_REPORTs |
//! | `usbl_suffix` | `_usbl` | appended to a contact's name in the NODE_REPORTs made from a USBL fix (empty: the vehicle's name) |
//! | `node_report_var` | `NODE_REPORT` | where the contacts' reports go |
//! | `waypoint_var`, `battery_var`, `nav_sigma_var` | `WPT_INDEX`, `BATTERY_VOLTAGE`, `NAV_POS_STD` | what a vehicle reports in its status besides `NAV_*`, `SAFETY_HEALTH`, `SAFETY_MODE` and `DEPLOY` |
//! | `kill_flag`, `surface_flag`, `abort_flag`, `return_flag`, `goto_flag`, `loiter_flag`, `depth_flag` | the table below | `VAR=VALUE` posted when the command is applied (repeatable; any given replace that command's defaults); macros `$(X)`, `$(Y)`, `$(DEPTH)`, `$(RADIUS)`, `$(SPEED)`, `$(CLOCKWISE)`, `$(FROM)`, `$(SEQ)` |
//!
//! Commands applied on a vehicle, by default (the vehicle then confirms to the sender):
//!
//! | command | posts | reaches |
//! |---|---|---|
//! | kill | `ACOMMS_KILL=true`, `MOOS_MANUAL_OVERRIDE=true` | pSafety (`rule = acomms_kill: ACOMMS_KILL == true -> allstop`: all-stop and its `allstop_flag`s, e.g. `COUG_ARM=false`) and the helm, which parks on the override |
//! | surface | `ACOMMS_SURFACE=true` | pSafety (`rule = acomms_surface: ACOMMS_SURFACE == true -> surface_disarm`: surfaces through the helm or the actuators, then disarms) |
//! | abort | `ACOMMS_ABORT=true` | pSafety (`rule = acomms_abort: ACOMMS_ABORT == true -> surface_disarm`): the mission stops and the vehicle comes up |
//! | return | `ACOMMS_RETURN=true`, `RETURN=true` | the `.bhv`'s return mode (pSafety's return flag's variable) |
//! | goto | `ACOMMS_GOTO_UPDATE=points=$(X),$(Y) # speed=$(SPEED)`, `ACOMMS_MODE=GOTO` | a waypoint behaviour with `updates = ACOMMS_GOTO_UPDATE` and a condition on `ACOMMS_MODE` |
//! | loiter | `ACOMMS_LOITER_UPDATE=center_assign=$(X),$(Y) # radius=$(RADIUS) # speed=$(SPEED) # clockwise=$(CLOCKWISE)`, `ACOMMS_MODE=LOITER` | a loiter behaviour with `updates = ACOMMS_LOITER_UPDATE` |
//! | depth | `ACOMMS_DEPTH_UPDATE=depth=$(DEPTH)` | a constant-depth behaviour with `updates = ACOMMS_DEPTH_UPDATE` (goto and loiter post it too when they carry a depth) |
//!
//! A vehicle answers polls only once it knows where it is (`NAV_X` and `NAV_Y`, or its `x`
//! and `y`): before its navigation's first position it leaves them unanswered (the poller
//! counts a timeout) rather than report 0,0.
//!
//! Every applied command is also posted as `ACOMMS_CMD_RECEIVED = from=<id>,cmd=<word>,seq=<n>`,
//! and every packet accepted from a poller as `ACOMMS_LAST_BASE_CONTACT = <time>` (pSafety's
//! `stale(ACOMMS_LAST_BASE_CONTACT)` comms rule).
//!
//! Postings of every node:
//!
//! | variable | when | value |
//! |---|---|---|
//! | `NODE_REPORT` | each contact with an absolute position | pNodeReporter's format ([`vehicle::node_report::write_report`]); `VSOURCE=acomms_reported` for the position a vehicle reports in its status (named after the vehicle), `VSOURCE=acomms_usbl` for the listener's USBL fix plus its own position (named with `usbl_suffix`) |
//! | `ACOMMS_CONTACT` | each contact | `name=..,id=..,source=usbl\|reported,time=..` and `rel_x`, `rel_y` (east, north of the listener), `range`, `x`, `y`, `depth` when known |
//! | `ACOMMS_STATUS` | when the counters change | `role=..,id=..,polls=..,answers=..,timeouts=..,losses=..,commands=..,confirmed=..,command_timeouts=..,applied=..,tx=..,rx=..,accepted=..,rejected=..,bad_tag=..,replayed=..,stale=..,foreign=..,unknown_id=..,unknown_sender=..,malformed=..,contacts=..` |
//! | `ACOMMS_WARNING` | a refused command, a full queue | the reason |
//!
//! A poller (`role = base` or `lead`) also reads `ACOMMS_COMMAND = to=<id>,cmd=<kill|surface|
//! abort|return|goto|loiter|depth>[,x=<m>,y=<m>][,depth=<m>][,radius=<m>][,speed=<m/s>]
//! [,clockwise=<bool>]` ([`acomms::net::parse_command`]; a bad one goes to `ACOMMS_WARNING` and
//! the appcast, and is never sent) and posts:
//!
//! - `ACOMMS_VEHICLE = id=<id>,name=<name>,time=<time of its last answer>,x=..,y=..,depth=..,
//!   heading=..,speed=..,battery_v=..,health=0x<4 hex digits>,mode=<idle|mission|loiter|
//!   returning|surfacing|surfaced|killed|fault>,polls=..,answers=..,timeouts=..` after each
//!   answer or timeout (time and the status keys, `mode` included, only once it has answered);
//! - `ACOMMS_COMMAND_ACK = to=<id>,cmd=<word>,seq=<n>,state=<queued|sent|confirmed|timeout>`
//!   (`,success=false` when the vehicle could not carry it out; `seq=0` while queued).
//!
//! # uSimModem
//!
//! The modem in simulation: the app takes the run's shared [`AcousticNet`] named by its
//! `channel` key (one per run, reached through [`crate::shared::Shared`], so every
//! community's uSimModem of a fleet run is on the same water), registers its `modem_id`, moves
//! its node to `<position_prefix>X`, `Y`, `DEPTH` (`NAV_` by default; `SIM_` for the
//! simulator's truth), sends each `ACOMMS_TX` when its previous transmission has ended, and
//! posts what it receives as iSeaTrac does (the fix first, then `ACOMMS_RX`).
//!
//! | parameter | default | meaning |
//! |---|---|---|
//! | `modem_id` | required | 1-15, unique on the channel |
//! | `channel` | `acoustic` | the shared channel's name |
//! | `position_prefix` | `NAV_` | where the node's position is read |
//! | `x`, `y`, `depth` | 0, 0, 0 | the position until one is read (a moored beacon) |
//! | `overhear` | true | post packets addressed to other modems too (SeaTrac beacons hear every packet) |
//! | `seed`, `bit_rate`, `sound_speed`, `max_range`, `overhead`, `loss` (`dune`, `none` or `R:P,R:P,..`), `usbl_azimuth_sigma`, `usbl_elevation_sigma`, `usbl_range_sigma` | the run's seed, [`achannel::Config`]'s defaults | the channel's settings: the first uSimModem to reach the channel makes it; a later one with other settings gets a warning (one without `seed` takes the channel's: a fleet's communities each have their own run seed) |
//!
//! It also posts `ACOMMS_CHANNEL = modem=<id>,sent=..,failed=..,received=..,transmitted=..,
//! arrivals=..,delivered=..,lost=..,collisions=..,half_duplex=..,out_of_range=..` when a
//! count changes: its own transmissions and receptions, then the channel's statistics (the
//! whole run's water, as the channel has been stepped to that instant), so a log shows the
//! channel's losses and collisions.
//!
//! The fix posted is the channel's: range, azimuth from north, elevation (positive: the sender
//! is shallower), the offsets east and north and the sender's depth computed from them. A
//! real SeaTrac measures a range only in a two-way exchange; the channel gives one always.
//!
//! ## Determinism across communities
//!
//! Several communities' uSimModems reach one [`AcousticNet`] in an order the scheduler picks.
//! The net is built so that order never matters: what an app asks at time `t` (its
//! registration, its position, its transmission) is stamped `t` and held; when the first app
//! arrives at a later time, everything held at earlier times is applied to the channel sorted
//! by (time, kind, modem id, then that modem's order of asking), and the channel is stepped to
//! the new time; what was held at the new time itself (a registration at start-up, made
//! before anyone synced) waits for the next instant. Within an instant the net so only
//! collects: the channel, its counts and every inbox are what the first sync of the instant
//! made them, whichever app came first, and every modem syncs before it reads them. This is
//! the tick barrier of a threaded fleet run (`session::FleetOptions::threads`): the
//! communities of an instant, stepped on several threads, hand their requests over in any
//! interleaving; they are merged in that fixed order when the run moves on, and receptions
//! are computed after the merge. Receptions complete by then go to each modem's inbox, which
//! only that modem's app drains. A transmission at `t` cannot change a reception complete by
//! `t` (the channel's intervals are half-open), so the order in which the apps of one instant
//! run changes nothing (tested by running the communities in both orders, and
//! missions/fleet_acomms on 1 and 4 threads). Apps must reach the net in non-decreasing time
//! across communities (the lockstep scheduler does: one instant at a time); a call earlier
//! than the latest seen is stamped at the latest and counted as late.

use std::collections::{BTreeMap, BTreeSet, VecDeque};
use std::fmt::Write as _;
use std::sync::{Arc, Mutex, PoisonError};

use achannel::{Channel, LossCurve, NodeId, Position, Usbl};
use acomms::net::{
    AckState, Applied, Contact, ContactSource, Event, Fix, NetConfig, NetCounters, Node, OwnNav,
    Role, VehicleState, VehicleView, command_word,
};
use acomms::{CommandKind, FleetKey, VehicleMode};
use mission::diagnostic::{Diagnostic, DiagnosticKind};
use mission::moos::ProcessConfig;
use moos_types::fmt::g as fmt_g;
use moos_types::text::parse_poke;
use vehicle::config::is_generic_app_key;
use vehicle::node_report::{NavRecord, NodeReportConfig, ReportInputs, write_report};

use crate::app::{Mail, Post, Subscription, Value};
use crate::appcasting::Note;
use crate::hosted::{AppCore, Hosted};
use crate::shared::Shared;

/// pAcomms's program name.
pub const PACOMMS: &str = "pAcomms";
/// uSimModem's program name.
pub const USIMMODEM: &str = "uSimModem";

/// The key used when a block gives none (every coug fleet without a key shares it: a warning
/// says so).
pub const DEFAULT_KEY: &str = "coug default fleet key: set `key` in pAcomms";

fn g(v: f64) -> String {
    let mut s = String::new();
    fmt_g(&mut s, v, 8);
    s
}

fn warn(block: &ProcessConfig, key: Option<&str>, message: String) -> Diagnostic {
    let span = key
        .and_then(|k| {
            block
                .entries
                .iter()
                .find(|p| p.key.trim().eq_ignore_ascii_case(k))
        })
        .map_or(&block.span, |p| &p.span);
    Diagnostic::line_warning(DiagnosticKind::AppSetting, span, message)
}

/// `key=value` fields of a comma-separated string, keys lower-cased.
fn fields(s: &str) -> impl Iterator<Item = (String, &str)> {
    s.split(',').filter_map(|p| {
        let (k, v) = p.split_once('=')?;
        Some((k.trim().to_ascii_lowercase(), v.trim()))
    })
}

fn hex(data: &[u8]) -> String {
    let mut s = String::with_capacity(data.len() * 2);
    for b in data {
        let _ = write!(s, "{b:02X}");
    }
    s
}

fn unhex(s: &str) -> Option<Vec<u8>> {
    let s = s.trim().as_bytes();
    if !s.len().is_multiple_of(2) {
        return None;
    }
    s.chunks(2)
        .map(|p| {
            let d = |c: u8| (c as char).to_digit(16);
            Some((d(p[0])? * 16 + d(p[1])?) as u8)
        })
        .collect()
}

// ---------------------------------------------------------------------------------------
// The shared channel.

/// A reception waiting in a modem's inbox.
#[derive(Debug, Clone, PartialEq)]
pub struct Delivered {
    /// The sender's modem id.
    pub src: u8,
    /// The destination the sender gave.
    pub dest: u8,
    /// The payload.
    pub payload: Arc<[u8]>,
    /// When it was received whole.
    pub arrival_s: f64,
    /// The receiver's fix of the sender.
    pub usbl: Usbl,
    /// The sender's true depth when it sent (not posted: a one-way fix has no remote depth
    /// sensor reading; kept for tests and a REQX-style fix).
    pub sender_depth_m: f64,
}

/// What a modem's transmission became.
#[derive(Debug, Clone, PartialEq)]
pub enum TxNotice {
    /// On the water, for `dest`.
    Sent {
        /// The destination.
        dest: u8,
    },
    /// Refused by the channel.
    Failed(String),
}

#[derive(Debug, Clone, PartialEq)]
enum OpKind {
    Register(Position),
    Move(Position),
    Transmit { dest: u8, payload: Vec<u8> },
}

impl OpKind {
    fn rank(&self) -> u8 {
        match self {
            OpKind::Register(_) => 0,
            OpKind::Move(_) => 1,
            OpKind::Transmit { .. } => 2,
        }
    }
}

#[derive(Debug, Clone, PartialEq)]
struct Op {
    t: f64,
    modem: u8,
    n: u64,
    kind: OpKind,
}

/// Counters of one modem on the net.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq)]
pub struct ModemCounts {
    /// Transmissions put on the water.
    pub sent: u64,
    /// Transmissions the channel refused.
    pub failed: u64,
    /// Receptions delivered to its inbox.
    pub received: u64,
}

/// The acoustic medium of a run: one [`achannel::Channel`] and, per modem id, its node, its
/// inbox and its notices (see the module docs for how the order of the apps is made not to
/// matter).
#[derive(Debug)]
pub struct AcousticNet {
    channel: Channel,
    nodes: BTreeMap<u8, NodeId>,
    modems: BTreeMap<NodeId, u8>,
    claimed: BTreeSet<u8>,
    now: f64,
    ops: Vec<Op>,
    next_op: u64,
    dests: VecDeque<(NodeId, f64, u8, f64)>,
    inboxes: BTreeMap<u8, Vec<Delivered>>,
    notices: BTreeMap<u8, Vec<TxNotice>>,
    counts: BTreeMap<u8, ModemCounts>,
    late: u64,
}

impl AcousticNet {
    /// A net over a channel with `config`.
    pub fn new(config: achannel::Config) -> Self {
        AcousticNet {
            channel: Channel::new(config),
            nodes: BTreeMap::new(),
            modems: BTreeMap::new(),
            claimed: BTreeSet::new(),
            now: f64::NEG_INFINITY,
            ops: Vec::new(),
            next_op: 0,
            dests: VecDeque::new(),
            inboxes: BTreeMap::new(),
            notices: BTreeMap::new(),
            counts: BTreeMap::new(),
            late: 0,
        }
    }

    /// The channel (its settings and statistics).
    pub fn channel(&self) -> &Channel {
        &self.channel
    }

    /// A modem's counters.
    pub fn counts(&self, modem: u8) -> ModemCounts {
        self.counts.get(&modem).copied().unwrap_or_default()
    }

    /// Calls stamped later than they came (out of time order).
    pub fn late(&self) -> u64 {
        self.late
    }

    /// Claims `modem` for one app; false when another app holds it.
    pub fn claim(&mut self, modem: u8) -> bool {
        self.claimed.insert(modem)
    }

    fn stamp(&mut self, t: f64) -> f64 {
        if t < self.now {
            self.late += 1;
            self.now
        } else {
            t
        }
    }

    fn hold(&mut self, t: f64, modem: u8, kind: OpKind) {
        let t = self.stamp(t);
        self.next_op += 1;
        self.ops.push(Op {
            t,
            modem,
            n: self.next_op,
            kind,
        });
    }

    /// Brings the channel to time `t`: when `t` is past the latest time seen, applies what
    /// was held at earlier times (by time, kind, modem, then each modem's order of asking)
    /// and steps the channel, filling the inboxes. What was held at `t` itself waits for
    /// the next instant, whoever asked first: within an instant the net only collects.
    pub fn sync(&mut self, t: f64) {
        if t <= self.now {
            return;
        }
        // Held at `t` already: an app that reached the net at this instant before anyone
        // synced (a registration at start-up). Kept for the next instant, so that what
        // the channel holds during the instant `t` does not depend on who came first.
        let (mut ops, now_ops): (Vec<Op>, Vec<Op>) = std::mem::take(&mut self.ops)
            .into_iter()
            .partition(|op| op.t < t);
        self.ops = now_ops;
        ops.sort_by(|a, b| {
            a.t.total_cmp(&b.t)
                .then(a.kind.rank().cmp(&b.kind.rank()))
                .then(a.modem.cmp(&b.modem))
                .then(a.n.cmp(&b.n))
        });
        for op in ops {
            self.apply(op);
        }
        self.now = t;
        for r in self.channel.step(t) {
            let (Some(&src), Some(&to)) = (self.modems.get(&r.from), self.modems.get(&r.to)) else {
                continue;
            };
            let found = self
                .dests
                .iter()
                .find(|(n, s, _, _)| *n == r.from && *s == r.sent_s)
                .map(|(_, _, d, depth)| (*d, *depth));
            let (dest, depth) = found.unwrap_or((0, 0.0));
            self.counts.entry(to).or_default().received += 1;
            self.inboxes.entry(to).or_default().push(Delivered {
                src,
                dest,
                payload: r.payload,
                arrival_s: r.arrival_s,
                usbl: r.usbl,
                sender_depth_m: depth,
            });
        }
        // Packets take at most a few seconds in the water: older senders are forgotten.
        while self.dests.front().is_some_and(|d| d.1 < t - 120.0) {
            self.dests.pop_front();
        }
    }

    fn apply(&mut self, op: Op) {
        match op.kind {
            OpKind::Register(p) => {
                if !self.nodes.contains_key(&op.modem) {
                    let id = self.channel.add_node(p);
                    self.nodes.insert(op.modem, id);
                    self.modems.insert(id, op.modem);
                }
            }
            OpKind::Move(p) => {
                if let Some(&id) = self.nodes.get(&op.modem) {
                    let _ = self.channel.set_position(id, p);
                }
            }
            OpKind::Transmit { dest, payload } => {
                let notice = match self.nodes.get(&op.modem) {
                    None => TxNotice::Failed("not registered".into()),
                    Some(&id) => match self.channel.transmit(id, &payload, op.t) {
                        Ok(_) => {
                            let depth = self.channel.position(id).map_or(0.0, |p| p.depth_m);
                            self.dests.push_back((id, op.t, dest, depth));
                            TxNotice::Sent { dest }
                        }
                        Err(e) => TxNotice::Failed(e.to_string()),
                    },
                };
                let c = self.counts.entry(op.modem).or_default();
                match notice {
                    TxNotice::Sent { .. } => c.sent += 1,
                    TxNotice::Failed(_) => c.failed += 1,
                }
                self.notices.entry(op.modem).or_default().push(notice);
            }
        }
    }

    /// Registers `modem` at `position`, at time `t` (held until the time moves on).
    pub fn register(&mut self, t: f64, modem: u8, position: Position) {
        self.hold(t, modem, OpKind::Register(position));
    }

    /// Moves `modem` to `position` at time `t`.
    pub fn set_position(&mut self, t: f64, modem: u8, position: Position) {
        self.hold(t, modem, OpKind::Move(position));
    }

    /// Sends `payload` from `modem` to `dest` at time `t`.
    pub fn transmit(&mut self, t: f64, modem: u8, dest: u8, payload: &[u8]) {
        self.hold(
            t,
            modem,
            OpKind::Transmit {
                dest,
                payload: payload.to_vec(),
            },
        );
    }

    /// Takes what `modem` received so far.
    pub fn take_inbox(&mut self, modem: u8) -> Vec<Delivered> {
        self.inboxes.remove(&modem).unwrap_or_default()
    }

    /// Takes what became of `modem`'s transmissions.
    pub fn take_notices(&mut self, modem: u8) -> Vec<TxNotice> {
        self.notices.remove(&modem).unwrap_or_default()
    }
}

/// The shared net of a run, as the apps hold it.
pub type SharedNet = Mutex<AcousticNet>;

/// The net named `name` in `shared`, made with `config` by the first app that asks.
pub fn shared_net(shared: &Shared, name: &str, config: achannel::Config) -> Arc<SharedNet> {
    shared.get_or_insert_with::<SharedNet, _>(name, || Mutex::new(AcousticNet::new(config)))
}

// ---------------------------------------------------------------------------------------
// uSimModem.

/// The core of `uSimModem`: the modem's node on a shared [`AcousticNet`].
pub struct SimModemCore {
    net: Arc<SharedNet>,
    /// A valid `modem_id` that another modem already holds on the channel: not running.
    claimed_twice: bool,
    channel_name: String,
    modem: Option<u8>,
    prefix: String,
    position: Position,
    overhear: bool,
    queue: VecDeque<(u8, Vec<u8>)>,
    tx_until: f64,
    registered: bool,
    posted_rx: u64,
    last_error: String,
    /// The counts `ACOMMS_CHANNEL` last showed (its text is built only when they change).
    last_counts: Option<(ModemCounts, achannel::Stats)>,
}

/// `uSimModem`: the acoustic modem in simulation, over a shared [`AcousticNet`].
pub type SimModemApp = Hosted<SimModemCore>;

fn channel_config(
    block: &ProcessConfig,
    seed: u64,
    warnings: &mut Vec<Diagnostic>,
) -> achannel::Config {
    let mut c = achannel::Config {
        seed,
        ..achannel::Config::default()
    };
    for p in &block.entries {
        let k = p.key.trim().to_ascii_lowercase();
        let v = p.value.trim();
        let num = |w: &mut Vec<Diagnostic>, ok: fn(f64) -> bool| -> Option<f64> {
            match v.parse::<f64>() {
                Ok(x) if x.is_finite() && ok(x) => Some(x),
                _ => {
                    w.push(warn(
                        block,
                        Some(&k),
                        format!("{USIMMODEM}: {k} = {v}: not a valid number, default kept"),
                    ));
                    None
                }
            }
        };
        let pos = |x: f64| x > 0.0;
        let nonneg = |x: f64| x >= 0.0;
        match k.as_str() {
            "seed" => match v.parse::<u64>() {
                Ok(s) => c.seed = s,
                Err(_) => warnings.push(warn(
                    block,
                    Some(&k),
                    format!("{USIMMODEM}: seed = {v}: not an unsigned integer"),
                )),
            },
            "bit_rate" => c.bit_rate_bps = num(warnings, pos).unwrap_or(c.bit_rate_bps),
            "sound_speed" => c.sound_speed_mps = num(warnings, pos).unwrap_or(c.sound_speed_mps),
            "max_range" => c.max_range_m = num(warnings, pos).unwrap_or(c.max_range_m),
            "overhead" => c.overhead_s = num(warnings, nonneg).unwrap_or(c.overhead_s),
            "usbl_azimuth_sigma" => {
                c.usbl.azimuth_sigma_deg = num(warnings, nonneg).unwrap_or(c.usbl.azimuth_sigma_deg)
            }
            "usbl_elevation_sigma" => {
                c.usbl.elevation_sigma_deg =
                    num(warnings, nonneg).unwrap_or(c.usbl.elevation_sigma_deg)
            }
            "usbl_range_sigma" => {
                c.usbl.range_sigma_m = num(warnings, nonneg).unwrap_or(c.usbl.range_sigma_m)
            }
            "loss" => match parse_loss(v) {
                Some(l) => c.loss = l,
                None => warnings.push(warn(
                    block,
                    Some(&k),
                    format!(
                        "{USIMMODEM}: loss = {v}: expected dune, none or RANGE:P,RANGE:P,.. \
                         (P in [0, 1])"
                    ),
                )),
            },
            _ => {}
        }
    }
    c
}

/// Reads `loss`: `dune` (DUNE's Gaussian), `none` (every packet in range decoded) or a table
/// `R:P,R:P,...` of success probabilities over range (DUNE's size factor kept).
pub fn parse_loss(v: &str) -> Option<LossCurve> {
    match v.trim().to_ascii_lowercase().as_str() {
        "dune" => return Some(LossCurve::dune()),
        "none" => {
            return Some(LossCurve::Table {
                points: vec![(0.0, 1.0)],
                size_sigma_bytes: f64::INFINITY,
            });
        }
        _ => {}
    }
    let mut points = Vec::new();
    for part in v.split(',') {
        let (r, p) = part.split_once(':')?;
        let (r, p) = (r.trim().parse::<f64>().ok()?, p.trim().parse::<f64>().ok()?);
        if !(r.is_finite() && r >= 0.0 && (0.0..=1.0).contains(&p)) {
            return None;
        }
        points.push((r, p));
    }
    if points.is_empty() || points.windows(2).any(|w| w[1].0 < w[0].0) {
        return None;
    }
    Some(LossCurve::Table {
        points,
        size_sigma_bytes: 800.0,
    })
}

fn modem_id(
    app: &str,
    block: &ProcessConfig,
    warnings: &mut Vec<Diagnostic>,
    required: bool,
) -> Option<u8> {
    match block.get("modem_id") {
        Some(v) => match v.trim().parse::<u8>() {
            Ok(i) if (1..=acomms::MAX_NODE).contains(&i) => Some(i),
            _ => {
                warnings.push(warn(
                    block,
                    Some("modem_id"),
                    format!("{app}: modem_id = {}: expected 1-15", v.trim()),
                ));
                None
            }
        },
        None => {
            if required {
                warnings.push(warn(
                    block,
                    None,
                    format!("{app}: required parameter `modem_id` is missing: not running"),
                ));
            }
            None
        }
    }
}

impl Hosted<SimModemCore> {
    /// The app `name` from its block; `shared` holds the run's channels; `seed` is the run's
    /// seed (a channel made by this app without `seed` uses it, mixed with the channel's
    /// name).
    pub fn new(name: &str, block: ProcessConfig, shared: &Shared, seed: u64) -> Self {
        let mut warnings = Vec::new();
        let modem = modem_id(USIMMODEM, &block, &mut warnings, true);
        let mut channel_name = "acoustic".to_string();
        let mut prefix = "NAV_".to_string();
        let mut position = Position::new(0.0, 0.0, 0.0);
        let mut overhear = true;
        for p in &block.entries {
            let k = p.key.trim().to_ascii_lowercase();
            let v = p.value.trim();
            let mut number = |dst: &mut f64| match v.parse::<f64>() {
                Ok(x) if x.is_finite() => *dst = x,
                _ => warnings.push(warn(
                    &block,
                    Some(&k),
                    format!("{USIMMODEM}: {k} = {v}: not a number"),
                )),
            };
            match k.as_str() {
                "modem_id"
                | "seed"
                | "bit_rate"
                | "sound_speed"
                | "max_range"
                | "overhead"
                | "loss"
                | "usbl_azimuth_sigma"
                | "usbl_elevation_sigma"
                | "usbl_range_sigma" => {}
                "channel" if !v.is_empty() => channel_name = v.to_string(),
                "position_prefix" if !v.is_empty() => prefix = v.to_string(),
                "x" => number(&mut position.x_m),
                "y" => number(&mut position.y_m),
                "depth" => number(&mut position.depth_m),
                "overhear" => match moos_types::text::strict_bool(v) {
                    Some(b) => overhear = b,
                    None => warnings.push(warn(
                        &block,
                        Some(&k),
                        format!("{USIMMODEM}: overhear = {v}: expected true or false"),
                    )),
                },
                k if is_generic_app_key(k) => {}
                _ => warnings.push(warn(
                    &block,
                    Some(&k),
                    format!("{USIMMODEM}: unknown parameter `{}`", p.key.trim()),
                )),
            }
        }
        let mixed = seed ^ fnv1a(&channel_name);
        let config = channel_config(&block, mixed, &mut warnings);
        let net = shared_net(shared, &channel_name, config.clone());
        {
            let mut n = net.lock().unwrap_or_else(PoisonError::into_inner);
            // Without its own `seed` a modem takes the channel's: in a fleet run every
            // community's seed differs (the run's mixed with its name), which is no
            // disagreement about the water.
            let mut wanted = config.clone();
            if block.get("seed").is_none() {
                wanted.seed = n.channel().config().seed;
            }
            if *n.channel().config() != wanted {
                warnings.push(warn(
                    &block,
                    None,
                    format!(
                        "{USIMMODEM}: channel `{channel_name}` was made by another modem with \
                         other settings: its settings are used"
                    ),
                ));
            }
            if let Some(m) = modem
                && !n.claim(m)
            {
                warnings.push(warn(
                    &block,
                    Some("modem_id"),
                    format!(
                        "{USIMMODEM}: modem_id {m} is already on channel `{channel_name}`: not running"
                    ),
                ));
            }
        }
        let claimed_twice = warnings
            .iter()
            .any(|w| w.message.contains("already on channel"));
        let core = SimModemCore {
            net,
            claimed_twice,
            channel_name,
            modem,
            prefix,
            position,
            overhear,
            queue: VecDeque::new(),
            tx_until: f64::NEG_INFINITY,
            registered: false,
            posted_rx: 0,
            last_error: String::new(),
            last_counts: None,
        };
        Hosted::host(name, block, warnings, core)
    }

    /// The shared net it is on.
    pub fn net(&self) -> &Arc<SharedNet> {
        &self.core().net
    }
}

impl SimModemCore {
    fn running(&self) -> Option<u8> {
        if self.claimed_twice { None } else { self.modem }
    }

    fn post_reception(&mut self, me: u8, d: &Delivered, own_depth: f64, out: &mut Vec<Post>) {
        if !self.overhear && d.dest != me && d.dest != acomms::BROADCAST {
            return;
        }
        self.posted_rx += 1;
        let u = d.usbl;
        let el = u.elevation_deg.to_radians();
        let h = u.range_m * el.cos();
        let az = u.azimuth_deg.to_radians();
        let (x, y, z) = (h * az.sin(), h * az.cos(), own_depth - u.range_m * el.sin());
        out.push(Post::double("USBL_SRC", f64::from(d.src)));
        out.push(Post::double("USBL_RANGE", u.range_m));
        out.push(Post::double("USBL_AZIMUTH", u.azimuth_deg));
        out.push(Post::double("USBL_ELEVATION", u.elevation_deg));
        out.push(Post::double("USBL_X", x));
        out.push(Post::double("USBL_Y", y));
        out.push(Post::double("USBL_Z", z));
        out.push(Post::text(
            "USBL_FIX",
            format!(
                "src={},dest={},type=OWAYU,range={},azimuth={},elevation={},x={},y={},z={}",
                d.src,
                d.dest,
                g(u.range_m),
                g(u.azimuth_deg),
                g(u.elevation_deg),
                g(x),
                g(y),
                g(z)
            ),
        ));
        out.push(Post::text(
            "ACOMMS_RX",
            format!(
                "src={},dest={},ack=0,hex={}",
                d.src,
                d.dest,
                hex(&d.payload)
            ),
        ));
    }

    fn write_report(&self, b: &mut String) {
        let _ = writeln!(
            b,
            "Channel: {}   modem id: {}   position from: {}X/Y/DEPTH",
            self.channel_name,
            self.modem.map_or("none".into(), |m| m.to_string()),
            self.prefix
        );
        let _ = writeln!(
            b,
            "Position: x={} y={} depth={}",
            g(self.position.x_m),
            g(self.position.y_m),
            g(self.position.depth_m)
        );
        let net = self.net.lock().unwrap_or_else(PoisonError::into_inner);
        let c = self.modem.map(|m| net.counts(m)).unwrap_or_default();
        let s = net.channel().stats();
        let _ = writeln!(b);
        let _ = writeln!(b, "Sent  Failed  Received  Posted  Queued");
        let _ = writeln!(
            b,
            "{}  {}  {}  {}  {}",
            c.sent,
            c.failed,
            c.received,
            self.posted_rx,
            self.queue.len()
        );
        let _ = writeln!(b);
        let _ = writeln!(
            b,
            "Channel: transmitted={} delivered={} lost={} collisions={} half_duplex={} out_of_range={}",
            s.transmitted, s.delivered, s.lost, s.collisions, s.half_duplex, s.out_of_range
        );
        if !self.last_error.is_empty() {
            let _ = writeln!(b, "Last error: {}", self.last_error);
        }
    }
}

fn fnv1a(s: &str) -> u64 {
    let mut h: u64 = 0xcbf2_9ce4_8422_2325;
    for b in s.bytes() {
        h ^= u64::from(b);
        h = h.wrapping_mul(0x0000_0100_0000_01B3);
    }
    h
}

impl AppCore for SimModemCore {
    fn subscriptions(&self) -> Vec<Subscription> {
        let p = &self.prefix;
        [
            "ACOMMS_TX".to_string(),
            format!("{p}X"),
            format!("{p}Y"),
            format!("{p}DEPTH"),
        ]
        .into_iter()
        .map(Subscription::var)
        .collect()
    }

    fn on_startup(&mut self, now: f64, _out: &mut Vec<Post>, _notes: &mut Vec<Note>) {
        if let Some(m) = self.running() {
            let mut net = self.net.lock().unwrap_or_else(PoisonError::into_inner);
            net.register(now, m, self.position);
            self.registered = true;
        }
    }

    fn on_mail(&mut self, m: &Mail, _now: f64, out: &mut Vec<Post>, notes: &mut Vec<Note>) {
        let key: &str = &m.key;
        if key == "ACOMMS_TX" {
            let parsed = m
                .value
                .as_str()
                .ok_or_else(|| "expected a string".to_string())
                .and_then(parse_tx);
            match parsed {
                Ok(tx) => self.queue.push_back(tx),
                Err(why) => {
                    let why = format!("ACOMMS_TX: {why}");
                    out.push(Post::text("ACOMMS_ERROR", why.clone()));
                    notes.push(Note::Warning(why));
                }
            }
            return;
        }
        let Some(v) = m.value.as_f64() else { return };
        if !v.is_finite() {
            return;
        }
        match key.strip_prefix(self.prefix.as_str()) {
            Some("X") => self.position.x_m = v,
            Some("Y") => self.position.y_m = v,
            Some("DEPTH") => self.position.depth_m = v,
            _ => {}
        }
    }

    fn iterate(&mut self, now: f64, out: &mut Vec<Post>, notes: &mut Vec<Note>) {
        // Every modem, running or not, brings the net to this instant before reading it
        // (its appcast shows the channel's counts): they then read the same counts,
        // whichever community's modem came first.
        self.net
            .lock()
            .unwrap_or_else(PoisonError::into_inner)
            .sync(now);
        let Some(me) = self.running() else { return };
        let net = self.net.clone();
        let mut n = net.lock().unwrap_or_else(PoisonError::into_inner);
        if !self.registered {
            n.register(now, me, self.position);
            self.registered = true;
        }
        n.sync(now);
        let inbox = n.take_inbox(me);
        let notices = n.take_notices(me);
        let counts = (n.counts(me), *n.channel().stats());
        n.set_position(now, me, self.position);
        if now >= self.tx_until
            && let Some((dest, data)) = self.queue.pop_front()
        {
            self.tx_until = now + n.channel().config().airtime_s(data.len());
            n.transmit(now, me, dest, &data);
        }
        drop(n);
        let depth = self.position.depth_m;
        for d in &inbox {
            self.post_reception(me, d, depth, out);
        }
        for t in notices {
            match t {
                TxNotice::Sent { dest } => out.push(Post::text(
                    "ACOMMS_TX_ACK",
                    format!("dest={dest},cid=DAT_SEND"),
                )),
                TxNotice::Failed(why) => {
                    let why = format!("DAT_SEND: {why}");
                    out.push(Post::text("ACOMMS_ERROR", why.clone()));
                    notes.push(Note::Warning(why.clone()));
                    self.last_error = why;
                }
            }
        }
        if self.last_counts != Some(counts) {
            out.push(Post::text(
                "ACOMMS_CHANNEL",
                counts_text(me, counts.0, &counts.1),
            ));
            self.last_counts = Some(counts);
        }
    }

    fn report(&self, _now: f64, body: &mut String) {
        self.write_report(body);
    }
}

/// `ACOMMS_CHANNEL`'s value: the modem's counters and the channel's (run-wide) statistics.
fn counts_text(me: u8, c: ModemCounts, s: &achannel::Stats) -> String {
    format!(
        "modem={me},sent={},failed={},received={},transmitted={},arrivals={},delivered={},\
         lost={},collisions={},half_duplex={},out_of_range={}",
        c.sent,
        c.failed,
        c.received,
        s.transmitted,
        s.arrivals,
        s.delivered,
        s.lost,
        s.collisions,
        s.half_duplex,
        s.out_of_range
    )
}

/// Reads `ACOMMS_TX` as iSeaTrac does: `dest=..,hex=..[,type=..]`.
fn parse_tx(s: &str) -> Result<(u8, Vec<u8>), String> {
    let mut dest = None;
    let mut data = None;
    for (k, v) in fields(s) {
        match k.as_str() {
            "dest" => dest = v.parse::<u8>().ok().filter(|d| *d <= acomms::MAX_NODE),
            "hex" => data = unhex(v),
            "type" => {}
            _ => return Err(format!("unknown field `{k}`")),
        }
    }
    let dest = dest.ok_or("dest: expected a beacon id 0-15")?;
    let data = data.ok_or("hex: expected the payload as hex")?;
    if data.len() > acomms::MAX_FRAME {
        return Err(format!(
            "payload of {} bytes: at most {}",
            data.len(),
            acomms::MAX_FRAME
        ));
    }
    Ok((dest, data))
}

// ---------------------------------------------------------------------------------------
// pAcomms.

/// The commands' flag keys, in [`CommandKind`] order of the table.
const FLAG_KEYS: [(&str, CommandKind); 7] = [
    ("kill_flag", CommandKind::Kill),
    ("surface_flag", CommandKind::Surface),
    ("abort_flag", CommandKind::Abort),
    ("return_flag", CommandKind::Return),
    ("goto_flag", CommandKind::GoTo),
    ("loiter_flag", CommandKind::Loiter),
    ("depth_flag", CommandKind::SetDepth),
];

/// The default flags of a command (the module's table).
pub fn default_flags(kind: CommandKind) -> Vec<String> {
    let v: &[&str] = match kind {
        CommandKind::Kill => &["ACOMMS_KILL=true", "MOOS_MANUAL_OVERRIDE=true"],
        CommandKind::Surface => &["ACOMMS_SURFACE=true"],
        CommandKind::Abort => &["ACOMMS_ABORT=true"],
        CommandKind::Return => &["ACOMMS_RETURN=true", "RETURN=true"],
        CommandKind::GoTo => &[
            "ACOMMS_GOTO_UPDATE=points=$(X),$(Y) # speed=$(SPEED)",
            "ACOMMS_MODE=GOTO",
        ],
        CommandKind::Loiter => &[
            "ACOMMS_LOITER_UPDATE=center_assign=$(X),$(Y) # radius=$(RADIUS) # speed=$(SPEED) # clockwise=$(CLOCKWISE)",
            "ACOMMS_MODE=LOITER",
        ],
        CommandKind::SetDepth => &["ACOMMS_DEPTH_UPDATE=depth=$(DEPTH)"],
    };
    v.iter().map(|s| s.to_string()).collect()
}

/// The core of `pAcomms`: the network node and what it knows of its own vehicle.
pub struct AcommsCore {
    node: Option<Node>,
    role: Role,
    flags: BTreeMap<CommandKindKey, Vec<String>>,
    own: OwnNav,
    fixed: OwnNav,
    state: VehicleState,
    deploy: bool,
    safety_mode: String,
    killed: bool,
    last_command: Option<CommandKind>,
    report_cfg: NodeReportConfig,
    usbl_suffix: String,
    report_var: String,
    waypoint_var: String,
    battery_var: String,
    sigma_var: String,
    last_fix: Option<(f64, u8, Fix)>,
    events: Vec<Event>,
    last_status: String,
    /// The counters `last_status` was built from (it is rebuilt only when they change).
    status_counts: Option<(NetCounters, acomms::Counters)>,
    commands_given: u64,
    /// The `USBL_FIX`es of the mail being delivered, with their times.
    batch_fixes: Vec<(f64, u8, Fix)>,
    /// The `ACOMMS_RX`es of the mail being delivered, with their times.
    batch_rx: Vec<(f64, u8, Vec<u8>)>,
}

/// `pAcomms`: the polled acoustic network over a modem's MOOS variables.
pub type AcommsApp = Hosted<AcommsCore>;

/// A [`CommandKind`] as a map key.
type CommandKindKey = u8;

fn kind_key(k: CommandKind) -> CommandKindKey {
    FLAG_KEYS.iter().position(|(_, c)| *c == k).unwrap_or(0) as u8
}

impl Hosted<AcommsCore> {
    /// The app `name` from its block. Problems are warnings at their lines; without a valid
    /// `modem_id` the app runs idle (it posts its appcast only).
    pub fn new(name: &str, block: ProcessConfig) -> Self {
        let mut warnings = Vec::new();
        let modem = modem_id(PACOMMS, &block, &mut warnings, true);
        let mut role = Role::Vehicle;
        let mut cfg = NetConfig::new(modem.unwrap_or(1), Role::Vehicle);
        let mut key = None;
        let mut fixed = OwnNav::default();
        let mut flags: BTreeMap<CommandKindKey, Vec<String>> = BTreeMap::new();
        let mut report_cfg = NodeReportConfig {
            platform_type: "UUV".into(),
            ..NodeReportConfig::default()
        };
        let mut usbl_suffix = "_usbl".to_string();
        let mut report_var = "NODE_REPORT".to_string();
        let mut waypoint_var = "WPT_INDEX".to_string();
        let mut battery_var = "BATTERY_VOLTAGE".to_string();
        let mut sigma_var = "NAV_POS_STD".to_string();
        for p in &block.entries {
            let k = p.key.trim().to_ascii_lowercase();
            let v = p.value.trim();
            let mut bad = |expected: &str| {
                warnings.push(warn(
                    &block,
                    Some(&k),
                    format!("{PACOMMS}: {k} = {v}: expected {expected}"),
                ))
            };
            let number = |min: f64| v.parse::<f64>().ok().filter(|x| x.is_finite() && *x >= min);
            match k.as_str() {
                "modem_id" => {}
                "role" => match v.to_ascii_lowercase().as_str() {
                    "base" | "lead" | "poller" => role = Role::Poller,
                    "vehicle" => role = Role::Vehicle,
                    _ => bad("base, lead or vehicle"),
                },
                "key" if !v.is_empty() => key = Some(v.to_string()),
                "node" => {
                    let parsed = v.split_once(':').and_then(|(i, n)| {
                        let i = i.trim().parse::<u8>().ok()?;
                        let n = n.trim();
                        ((1..=acomms::MAX_NODE).contains(&i) && !n.is_empty())
                            .then(|| (i, n.to_string()))
                    });
                    match parsed {
                        Some((i, _)) if cfg.fleet.iter().any(|(j, _)| *j == i) => {
                            bad("a node id not listed before")
                        }
                        Some(n) => cfg.fleet.push(n),
                        None => bad("<id 1-15>:<name>"),
                    }
                }
                "poll_order" => {
                    let ids: Option<Vec<u8>> = v
                        .split(',')
                        .map(|s| {
                            s.trim()
                                .parse::<u8>()
                                .ok()
                                .filter(|i| (1..=acomms::MAX_NODE).contains(i))
                        })
                        .collect();
                    match ids {
                        Some(ids) if !ids.is_empty() => cfg.poll_order = ids,
                        _ => bad("modem ids 1-15 separated by commas"),
                    }
                }
                "slot" => match number(0.0) {
                    Some(x) => cfg.slot_s = x,
                    None => bad("seconds >= 0"),
                },
                "timeout" => match number(0.0).filter(|x| *x > 0.0) {
                    Some(x) => cfg.timeout_s = x,
                    None => bad("seconds > 0"),
                },
                "command_max_age" => match number(0.0) {
                    Some(x) if x > 0.0 => cfg.command_max_age_s = Some(x),
                    Some(_) => cfg.command_max_age_s = None,
                    None => bad("seconds >= 0"),
                },
                "command_tries" => match v.parse::<u32>() {
                    Ok(n) if n >= 1 => cfg.command_tries = n,
                    _ => bad("a count >= 1"),
                },
                "localisation_every" => match number(0.0) {
                    Some(x) => cfg.localisation_every_s = x,
                    None => bad("seconds >= 0"),
                },
                "usbl_azimuth" => match v.to_ascii_lowercase().as_str() {
                    "world" => cfg.usbl_body_frame = false,
                    "body" => cfg.usbl_body_frame = true,
                    _ => bad("world or body"),
                },
                "x" | "y" | "depth" => match number(f64::NEG_INFINITY) {
                    Some(x) if k == "x" => fixed.x_m = Some(x),
                    Some(x) if k == "y" => fixed.y_m = Some(x),
                    Some(x) => fixed.depth_m = Some(x),
                    None => bad("metres"),
                },
                "platform_type" if !v.is_empty() => report_cfg.platform_type = v.to_string(),
                "usbl_suffix" => usbl_suffix = v.to_string(),
                "node_report_var" if !v.is_empty() => report_var = v.to_string(),
                "waypoint_var" if !v.is_empty() => waypoint_var = v.to_string(),
                "battery_var" if !v.is_empty() => battery_var = v.to_string(),
                "nav_sigma_var" if !v.is_empty() => sigma_var = v.to_string(),
                k if is_generic_app_key(k) => {}
                _ => {
                    if let Some((_, kind)) = FLAG_KEYS.iter().find(|(f, _)| *f == k) {
                        if parse_poke(v).is_some() {
                            flags
                                .entry(kind_key(*kind))
                                .or_default()
                                .push(v.to_string());
                        } else {
                            bad("VAR=VALUE");
                        }
                    } else {
                        warnings.push(warn(
                            &block,
                            Some(&k),
                            format!("{PACOMMS}: unknown parameter `{}`", p.key.trim()),
                        ));
                    }
                }
            }
        }
        for (_, kind) in FLAG_KEYS {
            flags
                .entry(kind_key(kind))
                .or_insert_with(|| default_flags(kind));
        }
        if key.is_none() {
            warnings.push(warn(
                &block,
                None,
                format!(
                    "{PACOMMS}: no `key`: the default fleet key is used, which every coug \
                     fleet without a key shares"
                ),
            ));
        }
        if let Some(m) = modem {
            for i in &cfg.poll_order {
                if *i == m {
                    warnings.push(warn(
                        &block,
                        Some("poll_order"),
                        format!("{PACOMMS}: poll_order lists this node ({m}) itself"),
                    ));
                }
            }
        }
        if role == Role::Vehicle && block.get("poll_order").is_some() {
            warnings.push(warn(
                &block,
                Some("poll_order"),
                format!("{PACOMMS}: poll_order is for a base or lead; a vehicle never polls"),
            ));
        }
        if role == Role::Poller
            && cfg.poll_order.is_empty()
            && cfg.fleet.iter().all(|(i, _)| Some(*i) == modem)
        {
            warnings.push(warn(
                &block,
                None,
                format!(
                    "{PACOMMS}: a {} with no `node` list nor `poll_order` polls nobody",
                    "poller"
                ),
            ));
        }
        cfg.role = role;
        let key = FleetKey::new(key.as_deref().unwrap_or(DEFAULT_KEY).as_bytes());
        let node = modem.map(|_| Node::new(cfg, key));
        let core = AcommsCore {
            node,
            role,
            flags,
            own: OwnNav::default(),
            fixed,
            state: VehicleState::default(),
            deploy: false,
            safety_mode: String::new(),
            killed: false,
            last_command: None,
            report_cfg,
            usbl_suffix,
            report_var,
            waypoint_var,
            battery_var,
            sigma_var,
            last_fix: None,
            events: Vec::new(),
            last_status: String::new(),
            status_counts: None,
            commands_given: 0,
            batch_fixes: Vec::new(),
            batch_rx: Vec::new(),
        };
        Hosted::host(name, block, warnings, core)
    }

    /// The network core (none without a valid `modem_id`).
    pub fn node(&self) -> Option<&Node> {
        self.core().node.as_ref()
    }
}

impl AcommsCore {
    fn mode(&self) -> VehicleMode {
        if self.killed {
            return VehicleMode::Killed;
        }
        match self.safety_mode.as_str() {
            "DISARMED" => return VehicleMode::Surfaced,
            "SURFACE" => return VehicleMode::Surfacing,
            "RETURN" => return VehicleMode::Returning,
            "ALLSTOP" | "MALCONFIG" => return VehicleMode::Fault,
            _ => {}
        }
        match self.last_command {
            Some(CommandKind::Loiter) => VehicleMode::Loiter,
            Some(CommandKind::Return) => VehicleMode::Returning,
            Some(CommandKind::Surface | CommandKind::Abort) => VehicleMode::Surfacing,
            _ if self.deploy => VehicleMode::Mission,
            _ => VehicleMode::Idle,
        }
    }

    fn own_nav(&self) -> OwnNav {
        OwnNav {
            x_m: self.own.x_m.or(self.fixed.x_m),
            y_m: self.own.y_m.or(self.fixed.y_m),
            depth_m: self.own.depth_m.or(self.fixed.depth_m),
            heading_deg: self.own.heading_deg,
        }
    }

    fn take_fix(&mut self, src: u8, t: f64, batch: &[(f64, u8, Fix)]) -> Option<Fix> {
        if let Some((_, _, f)) = batch.iter().rev().find(|(_, s, _)| *s == src) {
            return Some(*f);
        }
        match self.last_fix {
            Some((ft, s, f)) if s == src && t - ft <= 1.0 && t >= ft => Some(f),
            _ => None,
        }
    }

    fn apply(
        &mut self,
        from: u8,
        seq: u32,
        c: &Applied,
        out: &mut Vec<Post>,
        notes: &mut Vec<Note>,
    ) {
        let kind = c.kind();
        self.last_command = Some(kind);
        if kind == CommandKind::Kill {
            self.killed = true;
        }
        let (x, y, depth, radius, speed, cw) = match *c {
            Applied::GoTo {
                x_m,
                y_m,
                depth_m,
                speed_mps,
            } => (x_m, y_m, depth_m, None, speed_mps, false),
            Applied::Loiter {
                x_m,
                y_m,
                radius_m,
                depth_m,
                speed_mps,
                clockwise,
            } => (x_m, y_m, depth_m, Some(radius_m), speed_mps, clockwise),
            Applied::SetDepth { depth_m } => (0.0, 0.0, Some(depth_m), None, 0.0, false),
            _ => (0.0, 0.0, None, None, 0.0, false),
        };
        out.push(Post::text(
            "ACOMMS_CMD_RECEIVED",
            format!("from={from},cmd={},seq={seq}", command_word(kind)),
        ));
        let expand = |s: &str| {
            s.replace("$(X)", &g(x))
                .replace("$(Y)", &g(y))
                .replace("$(DEPTH)", &depth.map(g).unwrap_or_default())
                .replace("$(RADIUS)", &radius.map(g).unwrap_or_default())
                .replace("$(SPEED)", &g(speed))
                .replace("$(CLOCKWISE)", if cw { "true" } else { "false" })
                .replace("$(FROM)", &from.to_string())
                .replace("$(SEQ)", &seq.to_string())
        };
        if let Some(flags) = self.flags.get(&kind_key(kind)) {
            for f in flags {
                let text = expand(f);
                if let Some((var, value)) = parse_poke(&text) {
                    out.push(Post::new(var.to_string(), value));
                }
            }
        }
        if matches!(kind, CommandKind::GoTo | CommandKind::Loiter)
            && let Some(d) = depth
        {
            out.push(Post::text("ACOMMS_DEPTH_UPDATE", format!("depth={}", g(d))));
        }
        notes.push(Note::Event(format!(
            "applied {} from {from} (seq {seq})",
            command_word(kind)
        )));
    }

    fn node_report(&self, c: &Contact, out: &mut Vec<Post>) {
        let (Some(x), Some(y)) = (c.x_m, c.y_m) else {
            return;
        };
        let (name, vsource) = match c.source {
            ContactSource::Reported => (c.name.clone(), "acomms_reported"),
            ContactSource::Usbl => (format!("{}{}", c.name, self.usbl_suffix), "acomms_usbl"),
        };
        let cfg = NodeReportConfig {
            vsource: vsource.into(),
            ..self.report_cfg.clone()
        };
        let nav = NavRecord {
            x: Some(x),
            y: Some(y),
            speed: c.speed_mps,
            heading: c.heading_deg,
            depth: c.depth_m,
            ..NavRecord::default()
        };
        let mut s = String::new();
        write_report(
            &mut s,
            &cfg,
            &ReportInputs {
                name: &name,
                nav,
                time: c.time,
                ..ReportInputs::default()
            },
        );
        out.push(Post::text(self.report_var.clone(), s));
    }

    fn post_events(&mut self, now: f64, out: &mut Vec<Post>, notes: &mut Vec<Note>) {
        let events = std::mem::take(&mut self.events);
        for e in &events {
            match e {
                Event::Transmit { dest, frame } => out.push(Post::text(
                    "ACOMMS_TX",
                    format!("dest={dest},hex={},type=OWAYU", hex(frame)),
                )),
                Event::Contact(c) => {
                    self.node_report(c, out);
                    out.push(Post::text("ACOMMS_CONTACT", contact_text(c)));
                }
                Event::Vehicle(v) => out.push(Post::text("ACOMMS_VEHICLE", vehicle_text(v))),
                Event::Ack {
                    to,
                    kind,
                    seq,
                    state,
                    success,
                } => {
                    let mut s = format!(
                        "to={to},cmd={},seq={seq},state={}",
                        command_word(*kind),
                        state.as_str()
                    );
                    if *success == Some(false) {
                        s.push_str(",success=false");
                    }
                    if *state == AckState::Timeout {
                        notes.push(Note::Warning(format!(
                            "{} to {to}: no confirmation",
                            command_word(*kind)
                        )));
                    }
                    out.push(Post::text("ACOMMS_COMMAND_ACK", s));
                }
                Event::Apply { from, seq, command } => self.apply(*from, *seq, command, out, notes),
                Event::PollerHeard { .. } => {
                    out.push(Post::double("ACOMMS_LAST_BASE_CONTACT", now));
                }
                // Packets for another node are overheard all the time: counted, not noted.
                Event::Rejected(acomms::Reject::NotForMe { .. }) => {}
                Event::Rejected(r) => {
                    notes.push(Note::Event(format!("refused: {r}")));
                }
                Event::Warning(w) => {
                    out.push(Post::text("ACOMMS_WARNING", w.clone()));
                    notes.push(Note::Warning(w.clone()));
                }
            }
        }
        self.events = events;
        self.events.clear();
    }

    fn status_text(&self) -> String {
        let Some(n) = &self.node else {
            return String::new();
        };
        let c = n.counters();
        let r = n.receiver_counters();
        format!(
            "role={},id={},polls={},answers={},timeouts={},losses={},commands={},confirmed={},\
             command_timeouts={},applied={},tx={},rx={},accepted={},rejected={},bad_tag={},\
             replayed={},stale={},foreign={},unknown_id={},unknown_sender={},malformed={},contacts={}",
            if self.role == Role::Poller {
                "poller"
            } else {
                "vehicle"
            },
            n.config().me,
            c.polls,
            c.answers,
            c.timeouts,
            c.losses(),
            c.commands_sent,
            c.confirmed,
            c.command_timeouts,
            c.applied,
            c.transmitted,
            r.received,
            r.accepted,
            r.rejected() + c.unknown_sender,
            r.bad_tag,
            r.replayed + r.too_old,
            r.stale,
            r.not_for_me + r.bad_sender,
            r.unknown_id,
            c.unknown_sender,
            r.truncated + r.too_long + r.malformed,
            c.contacts
        )
    }

    fn write_report(&self, b: &mut String) {
        let Some(n) = &self.node else {
            let _ = writeln!(b, "Not running: no valid modem_id.");
            return;
        };
        let c = n.counters();
        let r = n.receiver_counters();
        let _ = writeln!(
            b,
            "Modem id: {}   role: {}   queued: {}",
            n.config().me,
            if self.role == Role::Poller {
                "poller"
            } else {
                "vehicle"
            },
            n.queued()
        );
        let _ = writeln!(b);
        let _ = writeln!(
            b,
            "Polls  Answers  Timeouts  Late  Commands  Confirmed  CmdTimeouts  Applied  Tx  Contacts"
        );
        let _ = writeln!(
            b,
            "{}  {}  {}  {}  {}  {}  {}  {}  {}  {}",
            c.polls,
            c.answers,
            c.timeouts,
            c.late,
            c.commands_sent,
            c.confirmed,
            c.command_timeouts,
            c.applied,
            c.transmitted,
            c.contacts
        );
        let _ = writeln!(b);
        let _ = writeln!(
            b,
            "Rx  Accepted  BadTag  Replayed  Stale  Foreign  UnknownId  UnknownSender  Malformed"
        );
        let _ = writeln!(
            b,
            "{}  {}  {}  {}  {}  {}  {}  {}  {}",
            r.received,
            r.accepted,
            r.bad_tag,
            r.replayed + r.too_old,
            r.stale,
            r.not_for_me + r.bad_sender,
            r.unknown_id,
            c.unknown_sender,
            r.truncated + r.too_long + r.malformed
        );
        if self.role == Role::Poller {
            let _ = writeln!(b);
            let mut t = appcast::Table::new(7);
            for h in [
                "Id",
                "Name",
                "Polls",
                "Answers",
                "Timeouts",
                "LastAnswer",
                "Position",
            ] {
                t.push(h);
            }
            t.add_header_lines();
            for v in n.views() {
                t.push(&v.id.to_string());
                t.push(&v.name);
                t.push(&v.polls.to_string());
                t.push(&v.answers.to_string());
                t.push(&v.timeouts.to_string());
                t.push(&v.last_answer.map_or("-".into(), g));
                t.push(&v.status.map_or("-".into(), |s| {
                    format!("{},{},{}", g(s.x_m), g(s.y_m), g(s.depth_m))
                }));
            }
            t.write(b);
        }
    }
}

fn contact_text(c: &Contact) -> String {
    let mut s = format!(
        "name={},id={},source={},time={}",
        c.name,
        c.id,
        c.source.as_str(),
        g(c.time)
    );
    let mut add = |k: &str, v: Option<f64>| {
        if let Some(v) = v {
            let _ = write!(s, ",{k}={}", g(v));
        }
    };
    add("rel_x", c.rel_east_m);
    add("rel_y", c.rel_north_m);
    add("range", c.range_m);
    add("x", c.x_m);
    add("y", c.y_m);
    add("depth", c.depth_m);
    s
}

/// The `ACOMMS_VEHICLE` text of a view.
pub fn vehicle_text(v: &VehicleView) -> String {
    let mut s = format!("id={},name={}", v.id, v.name);
    if let (Some(t), Some(st)) = (v.last_answer, v.status) {
        let _ = write!(
            s,
            ",time={},x={},y={},depth={},heading={},speed={},battery_v={},health=0x{:04X},mode={}",
            g(t),
            g(st.x_m),
            g(st.y_m),
            g(st.depth_m),
            g(st.heading_deg),
            g(st.speed_mps),
            g(st.battery_v),
            st.health,
            mode_word(st.mode)
        );
    }
    let _ = write!(
        s,
        ",polls={},answers={},timeouts={}",
        v.polls, v.answers, v.timeouts
    );
    s
}

/// A vehicle mode's word in `ACOMMS_VEHICLE`.
pub fn mode_word(m: VehicleMode) -> &'static str {
    match m {
        VehicleMode::Idle => "idle",
        VehicleMode::Mission => "mission",
        VehicleMode::Loiter => "loiter",
        VehicleMode::Returning => "returning",
        VehicleMode::Surfacing => "surfacing",
        VehicleMode::Surfaced => "surfaced",
        VehicleMode::Killed => "killed",
        VehicleMode::Fault => "fault",
    }
}

/// Reads `USBL_FIX`: the source and the fix's parts.
fn parse_fix(s: &str) -> Option<(u8, Fix)> {
    let mut src = None;
    let mut f = Fix::default();
    for (k, v) in fields(s) {
        let num = || v.parse::<f64>().ok().filter(|x| x.is_finite());
        match k.as_str() {
            "src" => src = v.parse::<u8>().ok(),
            "range" => f.range_m = num(),
            "azimuth" => f.azimuth_deg = num(),
            "elevation" => f.elevation_deg = num(),
            "x" => f.east_m = num(),
            "y" => f.north_m = num(),
            "z" => f.depth_m = num(),
            _ => {}
        }
    }
    Some((src?, f))
}

/// Reads `ACOMMS_RX`: the source and the payload.
fn parse_rx(s: &str) -> Option<(u8, Vec<u8>)> {
    let mut src = None;
    let mut data = None;
    for (k, v) in fields(s) {
        match k.as_str() {
            "src" => src = v.parse::<u8>().ok(),
            "hex" => data = unhex(v),
            _ => {}
        }
    }
    Some((src?, data?))
}

impl AppCore for AcommsCore {
    fn subscriptions(&self) -> Vec<Subscription> {
        let mut v: Vec<String> = [
            "ACOMMS_RX",
            "USBL_FIX",
            "NAV_X",
            "NAV_Y",
            "NAV_DEPTH",
            "NAV_HEADING",
            "NAV_SPEED",
            "NAV_PITCH",
            "NAV_ROLL",
            "SAFETY_HEALTH",
            "SAFETY_MODE",
            "DEPLOY",
        ]
        .iter()
        .map(|s| s.to_string())
        .collect();
        v.push(self.waypoint_var.clone());
        v.push(self.battery_var.clone());
        v.push(self.sigma_var.clone());
        if self.role == Role::Poller {
            v.push("ACOMMS_COMMAND".into());
        }
        v.into_iter().map(Subscription::var).collect()
    }

    fn on_mail(&mut self, m: &Mail, now: f64, out: &mut Vec<Post>, notes: &mut Vec<Note>) {
        let key: &str = &m.key;
        match key {
            "USBL_FIX" => {
                if let Some((src, f)) = m.value.as_str().and_then(parse_fix) {
                    self.batch_fixes.push((m.time, src, f));
                }
                return;
            }
            "ACOMMS_RX" => {
                match m.value.as_str().and_then(parse_rx) {
                    Some((src, data)) => self.batch_rx.push((m.time, src, data)),
                    None => notes.push(Note::Warning(format!(
                        "ACOMMS_RX: cannot read {:?}",
                        m.value
                    ))),
                }
                return;
            }
            "ACOMMS_COMMAND" => {
                let text = match &m.value {
                    Value::String(s) => s.to_string(),
                    other => format!("{other:?}"),
                };
                self.commands_given += 1;
                if let Some(n) = &mut self.node
                    && let Err(e) = n.command(now, &text, &mut self.events)
                {
                    let w = format!("ACOMMS_COMMAND = {text}: {e}");
                    out.push(Post::text("ACOMMS_WARNING", w.clone()));
                    notes.push(Note::Warning(w));
                }
                return;
            }
            "SAFETY_MODE" => {
                self.safety_mode = m.value.as_str().unwrap_or("").trim().to_ascii_uppercase();
                return;
            }
            "DEPLOY" => {
                let s = match &m.value {
                    Value::String(s) => s.to_string(),
                    Value::Double(d) => (*d != 0.0).to_string(),
                    Value::Binary(_) => String::new(),
                };
                self.deploy = moos_types::text::strict_bool(&s).unwrap_or(false);
                return;
            }
            _ => {}
        }
        let Some(v) = m.value.as_f64().filter(|v| v.is_finite()) else {
            return;
        };
        match key {
            "NAV_X" => self.own.x_m = Some(v),
            "NAV_Y" => self.own.y_m = Some(v),
            "NAV_DEPTH" => self.own.depth_m = Some(v),
            "NAV_HEADING" => self.own.heading_deg = Some(v),
            "NAV_SPEED" => self.state.speed_mps = v,
            "NAV_PITCH" => self.state.pitch_deg = v.to_degrees(),
            "NAV_ROLL" => self.state.roll_deg = v.to_degrees(),
            "SAFETY_HEALTH" => self.state.health = v.clamp(0.0, 65535.0) as u16,
            k if k == self.waypoint_var => self.state.waypoint = v.clamp(0.0, 255.0) as u8,
            k if k == self.battery_var => self.state.battery_v = v,
            k if k == self.sigma_var => self.state.nav_sigma_m = Some(v),
            _ => {}
        }
    }

    /// A packet is paired with a fix of the same delivery, so the batch is read here.
    fn mail_done(&mut self, now: f64, out: &mut Vec<Post>, notes: &mut Vec<Note>) {
        let fixes = std::mem::take(&mut self.batch_fixes);
        let rx = std::mem::take(&mut self.batch_rx);
        let own = self.own_nav();
        if let Some(n) = &mut self.node {
            n.set_own(own);
        }
        for (t, src, data) in rx {
            let fix = self.take_fix(src, t, &fixes);
            if let Some(n) = &mut self.node {
                n.receive(now, &data, fix.as_ref(), &mut self.events);
            }
        }
        if let Some(&(t, s, f)) = fixes.last() {
            self.last_fix = Some((t, s, f));
        }
        self.post_events(now, out, notes);
    }

    fn iterate(&mut self, now: f64, out: &mut Vec<Post>, notes: &mut Vec<Note>) {
        let own = self.own_nav();
        let mut st = self.state;
        st.mode = self.mode();
        st.x_m = own.x_m.unwrap_or(0.0);
        st.y_m = own.y_m.unwrap_or(0.0);
        st.depth_m = own.depth_m.unwrap_or(0.0);
        st.heading_deg = own.heading_deg.unwrap_or(0.0);
        // No NAV_X/NAV_Y (nor a fixed x, y) yet: no answer rather than a made-up 0,0.
        st.position_known = own.x_m.is_some() && own.y_m.is_some();
        if let Some(n) = &mut self.node {
            n.set_own(own);
            n.set_vehicle_state(st);
            n.tick(now, &mut self.events);
        }
        self.post_events(now, out, notes);
        // The text is a function of the counters alone (the role and id are fixed).
        let counts = self
            .node
            .as_ref()
            .map(|n| (*n.counters(), *n.receiver_counters()));
        if counts != self.status_counts {
            self.status_counts = counts;
            let status = self.status_text();
            if !status.is_empty() && status != self.last_status {
                out.push(Post::text("ACOMMS_STATUS", status.clone()));
                self.last_status = status;
            }
        }
    }

    fn report(&self, _now: f64, body: &mut String) {
        self.write_report(body);
    }
}
