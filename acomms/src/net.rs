//! The polled acoustic network (issue #16, point 2): the pure core of the `pAcomms` app. No
//! I/O and no clock: payloads, fixes and `now` go in, [`Event`]s come out (frames to send,
//! contact reports, vehicle views, command acknowledgements, commands to apply).
//!
//! # Roles
//!
//! - **Poller** (the base station or the lead agent): it owns the channel. Each turn it
//!   sends the head of its transmit queue, in priority order [`Priority::Command`] before
//!   [`Priority::Poll`] before [`Priority::Routine`] (first in, first out within one
//!   priority). A poll is a [`StatusRequest`] to the next vehicle of `poll_order`; a command
//!   is one of the authenticated commands, queued from text ([`parse_command`]). After a poll
//!   or a command the poller waits for the answer (the vehicle's [`Status`], or its
//!   [`Confirm`] of that command's sequence number) for at most `timeout_s` (4 s) from the
//!   start of its transmission, then moves on; two of its transmissions start at least
//!   `slot_s` apart. A command not confirmed is sent again, with a new sequence number, up
//!   to `command_tries` times in all. Routine traffic is the poller's own [`Localisation`],
//!   broadcast every `localisation_every_s` (0: never), which every vehicle hears with a
//!   USBL fix.
//! - **Vehicle** (answerer): it never speaks first. A status request for it is answered with
//!   its [`Status`] (from [`Node::set_vehicle_state`]), a localisation request with its
//!   [`Localisation`] (neither while [`VehicleState::position_known`] is false: no made-up
//!   position), a command is handed to the app to apply ([`Event::Apply`]) and
//!   confirmed to its sender. Confirmations go before answers in its queue.
//!
//! # Contact reports
//!
//! Every accepted packet heard with a USBL fix becomes a [`Contact`] of the sender
//! ([`ContactSource::Usbl`]): its position relative to the listener (east, north, and its
//! depth when the fix or the packet gives one) and, when the listener knows its own position
//! ([`Node::set_own`]), the absolute one. The relative position comes from the fix's
//! east/north offsets when it has them (a SeaTrac POSITION fix), else from range, azimuth and
//! elevation (horizontal range `r cos(el)`, or `sqrt(r^2 - dd^2)` with the depth difference
//! when the elevation is missing and both depths are known); the azimuth is clockwise from
//! north, or from the listener's heading with `usbl_body_frame`. A fix with a range only
//! gives a contact with no position. The contact's depth is the one the packet reports when
//! it carries one (the sender's pressure sensor beats a depth from the elevation), else the
//! fix's. A [`Status`] or [`Localisation`] also gives a contact
//! from the position the vehicle reports itself ([`ContactSource::Reported`]).
//!
//! # Rejections
//!
//! Every payload goes through [`Receiver`]: bad tags, replays, payloads for another node,
//! unknown message ids, truncated or malformed ones are refused and counted there; the node
//! adds senders outside the fleet list (when one is given) and messages its role does not
//! take (a command heard by a poller, a status request heard by a vehicle that is not asked).

use std::collections::VecDeque;

use crate::auth::Sequencer;
use crate::{
    Abort, Auth, BROADCAST, CommandKind, Confirm, Counters, FleetKey, Frame, GoTo, Kill,
    Localisation, Loiter, MAX_NODE, Packet, Receiver, Reject, Return, SetDepth, Status,
    StatusRequest, Surface, VehicleMode,
};

/// A node's part in the network.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Role {
    /// The base or lead agent: polls the vehicles and sends commands.
    Poller,
    /// A vehicle: answers polls and applies commands.
    Vehicle,
}

/// A node's settings.
#[derive(Debug, Clone)]
pub struct NetConfig {
    /// This node's modem id, 1-15.
    pub me: u8,
    /// Its role.
    pub role: Role,
    /// The fleet: modem id and name of every node (this one may be listed). Empty: any
    /// sender is taken and named `node<id>`.
    pub fleet: Vec<(u8, String)>,
    /// The vehicles a poller polls, in turn (empty: every fleet node but itself, in order).
    pub poll_order: Vec<u8>,
    /// Least seconds between the starts of two poller transmissions (4).
    pub slot_s: f64,
    /// Seconds a poller waits for an answer from the start of its transmission (4).
    pub timeout_s: f64,
    /// Transmissions of a command in all, until it is confirmed (2).
    pub command_tries: u32,
    /// Seconds between a poller's broadcasts of its own position (0: never).
    pub localisation_every_s: f64,
    /// The USBL azimuth is from the listener's heading rather than from north.
    pub usbl_body_frame: bool,
    /// The longest transmit queue; beyond it the oldest entry of the lowest priority is
    /// dropped (32).
    pub max_queue: usize,
    /// The first sequence number of this node's authenticated messages (0).
    pub first_seq: u32,
    /// The oldest a command may be on this node's clock when it arrives, seconds (its
    /// header's time field, see [`crate::auth`]); older ones (or stamped that far ahead)
    /// are refused and counted as stale. `None`: any age (60 s by default).
    pub command_max_age_s: Option<f64>,
}

/// The default oldest age of a command on arrival ([`NetConfig::command_max_age_s`]): a
/// minute, many poll cycles of 4 s, far below the half hour the time field can tell.
pub const DEFAULT_COMMAND_MAX_AGE_S: f64 = 60.0;

impl NetConfig {
    /// A node with the defaults: 4 s slots and timeouts, two tries per command.
    pub fn new(me: u8, role: Role) -> Self {
        NetConfig {
            me,
            role,
            fleet: Vec::new(),
            poll_order: Vec::new(),
            slot_s: 4.0,
            timeout_s: 4.0,
            command_tries: 2,
            localisation_every_s: 0.0,
            usbl_body_frame: false,
            max_queue: 32,
            first_seq: 0,
            command_max_age_s: Some(DEFAULT_COMMAND_MAX_AGE_S),
        }
    }

    /// The name of node `id`: its fleet name, else `node<id>`.
    pub fn name_of(&self, id: u8) -> String {
        self.fleet
            .iter()
            .find(|(i, _)| *i == id)
            .map_or_else(|| format!("node{id}"), |(_, n)| n.clone())
    }

    /// The id of the node named `name` (ignoring case).
    pub fn id_of(&self, name: &str) -> Option<u8> {
        self.fleet
            .iter()
            .find(|(_, n)| n.eq_ignore_ascii_case(name))
            .map(|(i, _)| *i)
    }

    fn polled(&self) -> Vec<u8> {
        if self.poll_order.is_empty() {
            self.fleet
                .iter()
                .map(|(i, _)| *i)
                .filter(|i| *i != self.me)
                .collect()
        } else {
            self.poll_order.clone()
        }
    }
}

/// Transmit priorities, highest first.
#[derive(Debug, Clone, Copy, PartialEq, Eq, PartialOrd, Ord, Hash)]
pub enum Priority {
    /// Commands and their confirmations.
    Command,
    /// Polls and their answers.
    Poll,
    /// Everything else (position broadcasts).
    Routine,
}

/// A priority queue, first in first out within one priority.
#[derive(Debug, Clone, Default)]
pub struct TxQueue<T> {
    lanes: [VecDeque<T>; 3],
}

impl<T> TxQueue<T> {
    /// An empty queue.
    pub fn new() -> Self {
        TxQueue {
            lanes: [VecDeque::new(), VecDeque::new(), VecDeque::new()],
        }
    }

    fn lane(p: Priority) -> usize {
        match p {
            Priority::Command => 0,
            Priority::Poll => 1,
            Priority::Routine => 2,
        }
    }

    /// Adds `item` at the back of its priority; past `max` entries, drops and returns the
    /// oldest entry of the lowest priority present.
    pub fn push(&mut self, p: Priority, item: T, max: usize) -> Option<T> {
        self.lanes[Self::lane(p)].push_back(item);
        if self.len() > max.max(1) {
            return self.lanes.iter_mut().rev().find_map(VecDeque::pop_front);
        }
        None
    }

    /// Takes the next entry: the oldest of the highest priority.
    pub fn pop(&mut self) -> Option<(Priority, T)> {
        const ORDER: [Priority; 3] = [Priority::Command, Priority::Poll, Priority::Routine];
        ORDER
            .iter()
            .find_map(|p| self.lanes[Self::lane(*p)].pop_front().map(|t| (*p, t)))
    }

    /// Entries queued.
    pub fn len(&self) -> usize {
        self.lanes.iter().map(VecDeque::len).sum()
    }

    /// True when nothing is queued.
    pub fn is_empty(&self) -> bool {
        self.len() == 0
    }
}

/// A command as the operator gives it ([`parse_command`]).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct CommandRequest {
    /// The vehicle's modem id (0: every vehicle).
    pub to: u8,
    /// Which command.
    pub kind: CommandKind,
    /// Point x (east), metres: go to and loiter.
    pub x_m: Option<f64>,
    /// Point y (north), metres: go to and loiter.
    pub y_m: Option<f64>,
    /// Depth, metres: required by `depth`, optional for go to and loiter.
    pub depth_m: Option<f64>,
    /// Loiter radius, metres (default 20).
    pub radius_m: Option<f64>,
    /// Speed, m/s, for go to and loiter (default 1).
    pub speed_mps: Option<f64>,
    /// Loiter clockwise (default false).
    pub clockwise: bool,
}

/// The word of a command in `ACOMMS_COMMAND` and the acknowledgements.
pub fn command_word(kind: CommandKind) -> &'static str {
    match kind {
        CommandKind::Kill => "kill",
        CommandKind::Surface => "surface",
        CommandKind::Abort => "abort",
        CommandKind::Return => "return",
        CommandKind::GoTo => "goto",
        CommandKind::Loiter => "loiter",
        CommandKind::SetDepth => "depth",
    }
}

/// Why a command text was refused.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum CommandError {
    /// A part is not `key=value`, or the key is not known.
    #[error("unknown field `{0}`")]
    UnknownField(String),
    /// No `to=`.
    #[error("to: missing (the vehicle's modem id or name)")]
    NoDestination,
    /// `to=` names no vehicle of the fleet, or this node.
    #[error("to={0}: not a vehicle of the fleet")]
    BadDestination(String),
    /// No `cmd=`.
    #[error("cmd: missing (kill, surface, abort, return, goto, loiter or depth)")]
    NoCommand,
    /// `cmd=` is not a command word.
    #[error("cmd={0}: not kill, surface, abort, return, goto, loiter or depth")]
    UnknownCommand(String),
    /// A number could not be read.
    #[error("{key}={value}: not a number")]
    BadNumber {
        /// The key.
        key: String,
        /// Its value.
        value: String,
    },
    /// A field the command needs is missing.
    #[error("cmd={cmd} needs {field}")]
    Missing {
        /// The command word.
        cmd: &'static str,
        /// The missing keys.
        field: &'static str,
    },
    /// A value is outside what the message can carry.
    #[error("{0}")]
    OutOfRange(String),
    /// Only a poller sends commands.
    #[error("this node is a vehicle: it sends no commands")]
    NotAPoller,
    /// The 24-bit sequence numbers are spent (change the fleet key).
    #[error("sequence numbers exhausted: change the fleet key")]
    SequenceExhausted,
}

/// Reads a command text: `to=<id or name>,cmd=<kill|surface|abort|return|goto|loiter|depth>`
/// then, as the command needs, `x=<m>,y=<m>` (goto, loiter), `depth=<m>` (required by
/// `depth`, optional for goto and loiter), `radius=<m>` (loiter, default 20), `speed=<m/s>`
/// (goto, loiter, default 1), `clockwise=<true|false>` (loiter). Keys ignore case; spaces
/// around parts are ignored. The value bounds are checked when the command is queued
/// ([`Node::command`]).
///
/// ```
/// use acomms::CommandKind;
/// use acomms::net::parse_command;
/// let c = parse_command("to=2,cmd=goto,x=10,y=-20.5", &[]).unwrap();
/// assert_eq!((c.to, c.kind, c.x_m, c.y_m), (2, CommandKind::GoTo, Some(10.0), Some(-20.5)));
/// assert!(parse_command("to=2,cmd=loiter,x=1", &[]).is_err());
/// ```
pub fn parse_command(text: &str, fleet: &[(u8, String)]) -> Result<CommandRequest, CommandError> {
    let mut to = None;
    let mut kind = None;
    let mut c = CommandRequest {
        to: 0,
        kind: CommandKind::Kill,
        x_m: None,
        y_m: None,
        depth_m: None,
        radius_m: None,
        speed_mps: None,
        clockwise: false,
    };
    for part in text.split(',').map(str::trim).filter(|p| !p.is_empty()) {
        let Some((k, v)) = part.split_once('=') else {
            return Err(CommandError::UnknownField(part.to_string()));
        };
        let (k, v) = (k.trim().to_ascii_lowercase(), v.trim());
        let num = |v: &str| {
            v.parse::<f64>()
                .ok()
                .filter(|x| x.is_finite())
                .ok_or_else(|| CommandError::BadNumber {
                    key: k.clone(),
                    value: v.to_string(),
                })
        };
        match k.as_str() {
            "to" => {
                let id = match v.parse::<u8>() {
                    Ok(i) => Some(i),
                    Err(_) => fleet
                        .iter()
                        .find(|(_, n)| n.eq_ignore_ascii_case(v))
                        .map(|(i, _)| *i),
                };
                match id {
                    Some(i) if i <= MAX_NODE => to = Some(i),
                    _ => return Err(CommandError::BadDestination(v.to_string())),
                }
            }
            "cmd" => {
                kind = Some(match v.to_ascii_lowercase().as_str() {
                    "kill" => CommandKind::Kill,
                    "surface" => CommandKind::Surface,
                    "abort" => CommandKind::Abort,
                    "return" => CommandKind::Return,
                    "goto" => CommandKind::GoTo,
                    "loiter" => CommandKind::Loiter,
                    "depth" => CommandKind::SetDepth,
                    _ => return Err(CommandError::UnknownCommand(v.to_string())),
                })
            }
            "x" => c.x_m = Some(num(v)?),
            "y" => c.y_m = Some(num(v)?),
            "depth" => c.depth_m = Some(num(v)?),
            "radius" => c.radius_m = Some(num(v)?),
            "speed" => c.speed_mps = Some(num(v)?),
            "clockwise" => {
                c.clockwise = match v.to_ascii_lowercase().as_str() {
                    "true" | "1" | "yes" => true,
                    "false" | "0" | "no" => false,
                    _ => return Err(CommandError::UnknownField(part.to_string())),
                }
            }
            _ => return Err(CommandError::UnknownField(part.to_string())),
        }
    }
    c.to = to.ok_or(CommandError::NoDestination)?;
    c.kind = kind.ok_or(CommandError::NoCommand)?;
    let word = command_word(c.kind);
    match c.kind {
        CommandKind::GoTo | CommandKind::Loiter if c.x_m.is_none() || c.y_m.is_none() => {
            return Err(CommandError::Missing {
                cmd: word,
                field: "x= and y=",
            });
        }
        CommandKind::SetDepth if c.depth_m.is_none() => {
            return Err(CommandError::Missing {
                cmd: word,
                field: "depth=",
            });
        }
        _ => {}
    }
    Ok(c)
}

impl CommandRequest {
    /// The message, with its authenticated header.
    pub fn packet(&self, auth: Auth) -> Packet {
        let speed = self.speed_mps.unwrap_or(1.0);
        match self.kind {
            CommandKind::Kill => Packet::Kill(Kill { auth }),
            CommandKind::Surface => Packet::Surface(Surface { auth }),
            CommandKind::Abort => Packet::Abort(Abort { auth }),
            CommandKind::Return => Packet::Return(Return { auth }),
            CommandKind::GoTo => Packet::GoTo(GoTo {
                auth,
                x_m: self.x_m.unwrap_or(0.0),
                y_m: self.y_m.unwrap_or(0.0),
                depth_m: self.depth_m,
                speed_mps: speed,
            }),
            CommandKind::Loiter => Packet::Loiter(Loiter {
                auth,
                x_m: self.x_m.unwrap_or(0.0),
                y_m: self.y_m.unwrap_or(0.0),
                radius_m: self.radius_m.unwrap_or(20.0),
                depth_m: self.depth_m,
                speed_mps: speed,
                clockwise: self.clockwise,
            }),
            CommandKind::SetDepth => Packet::SetDepth(SetDepth {
                auth,
                depth_m: self.depth_m.unwrap_or(0.0),
            }),
        }
    }
}

/// A received command, to be applied on the vehicle.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Applied {
    /// Disarm the thrusters.
    Kill,
    /// Drive to the surface.
    Surface,
    /// Stop the mission.
    Abort,
    /// Go home.
    Return,
    /// Go to a point.
    GoTo {
        /// East, m.
        x_m: f64,
        /// North, m.
        y_m: f64,
        /// Depth to hold, m.
        depth_m: Option<f64>,
        /// Speed, m/s.
        speed_mps: f64,
    },
    /// Loiter at a point.
    Loiter {
        /// Centre east, m.
        x_m: f64,
        /// Centre north, m.
        y_m: f64,
        /// Radius, m.
        radius_m: f64,
        /// Depth to hold, m.
        depth_m: Option<f64>,
        /// Speed, m/s.
        speed_mps: f64,
        /// Clockwise.
        clockwise: bool,
    },
    /// Hold a depth.
    SetDepth {
        /// Depth, m.
        depth_m: f64,
    },
}

impl Applied {
    /// The command's kind.
    pub fn kind(&self) -> CommandKind {
        match self {
            Applied::Kill => CommandKind::Kill,
            Applied::Surface => CommandKind::Surface,
            Applied::Abort => CommandKind::Abort,
            Applied::Return => CommandKind::Return,
            Applied::GoTo { .. } => CommandKind::GoTo,
            Applied::Loiter { .. } => CommandKind::Loiter,
            Applied::SetDepth { .. } => CommandKind::SetDepth,
        }
    }

    fn of(p: &Packet) -> Option<Applied> {
        Some(match *p {
            Packet::Kill(_) => Applied::Kill,
            Packet::Surface(_) => Applied::Surface,
            Packet::Abort(_) => Applied::Abort,
            Packet::Return(_) => Applied::Return,
            Packet::GoTo(g) => Applied::GoTo {
                x_m: g.x_m,
                y_m: g.y_m,
                depth_m: g.depth_m,
                speed_mps: g.speed_mps,
            },
            Packet::Loiter(l) => Applied::Loiter {
                x_m: l.x_m,
                y_m: l.y_m,
                radius_m: l.radius_m,
                depth_m: l.depth_m,
                speed_mps: l.speed_mps,
                clockwise: l.clockwise,
            },
            Packet::SetDepth(d) => Applied::SetDepth { depth_m: d.depth_m },
            _ => return None,
        })
    }
}

/// A command's state, as `ACOMMS_COMMAND_ACK` reports it.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum AckState {
    /// In the transmit queue.
    Queued,
    /// Handed to the modem.
    Sent,
    /// The vehicle confirmed it.
    Confirmed,
    /// No confirmation after every try.
    Timeout,
}

impl AckState {
    /// Its word.
    pub fn as_str(self) -> &'static str {
        match self {
            AckState::Queued => "queued",
            AckState::Sent => "sent",
            AckState::Confirmed => "confirmed",
            AckState::Timeout => "timeout",
        }
    }
}

/// A USBL fix of the sender, as the modem gives it (each part when measured).
#[derive(Debug, Clone, Copy, Default, PartialEq)]
pub struct Fix {
    /// Slant range, m.
    pub range_m: Option<f64>,
    /// Bearing of the sender, degrees clockwise from north (or from the listener's heading
    /// with `usbl_body_frame`).
    pub azimuth_deg: Option<f64>,
    /// Angle of the sender above the listener's horizontal plane, degrees.
    pub elevation_deg: Option<f64>,
    /// The sender's offset east of the listener, m (a SeaTrac POSITION fix).
    pub east_m: Option<f64>,
    /// The sender's offset north of the listener, m.
    pub north_m: Option<f64>,
    /// The sender's depth, m.
    pub depth_m: Option<f64>,
}

/// The listener's own navigation.
#[derive(Debug, Clone, Copy, Default, PartialEq)]
pub struct OwnNav {
    /// East, m.
    pub x_m: Option<f64>,
    /// North, m.
    pub y_m: Option<f64>,
    /// Depth, m.
    pub depth_m: Option<f64>,
    /// Heading, degrees.
    pub heading_deg: Option<f64>,
}

/// Where a contact's position comes from.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum ContactSource {
    /// The listener's USBL fix of the packet.
    Usbl,
    /// The position the vehicle reports in its status or localisation.
    Reported,
}

impl ContactSource {
    /// Its word.
    pub fn as_str(self) -> &'static str {
        match self {
            ContactSource::Usbl => "usbl",
            ContactSource::Reported => "reported",
        }
    }
}

/// Another node seen from this one.
#[derive(Debug, Clone, PartialEq)]
pub struct Contact {
    /// Its modem id.
    pub id: u8,
    /// Its name.
    pub name: String,
    /// When it was heard.
    pub time: f64,
    /// Where the position comes from.
    pub source: ContactSource,
    /// Offset east of the listener, m (USBL contacts with a bearing).
    pub rel_east_m: Option<f64>,
    /// Offset north of the listener, m.
    pub rel_north_m: Option<f64>,
    /// Slant range, m (USBL contacts).
    pub range_m: Option<f64>,
    /// Absolute east, m: the listener's own plus the offset, or the reported one.
    pub x_m: Option<f64>,
    /// Absolute north, m.
    pub y_m: Option<f64>,
    /// Depth, m.
    pub depth_m: Option<f64>,
    /// Heading, degrees (reported contacts).
    pub heading_deg: Option<f64>,
    /// Speed, m/s (reported contacts).
    pub speed_mps: Option<f64>,
}

/// What a poller knows of one vehicle (`ACOMMS_VEHICLE`).
#[derive(Debug, Clone, PartialEq)]
pub struct VehicleView {
    /// Its modem id.
    pub id: u8,
    /// Its name.
    pub name: String,
    /// When its last status arrived.
    pub last_answer: Option<f64>,
    /// Its last status.
    pub status: Option<Status>,
    /// Polls sent to it.
    pub polls: u64,
    /// Statuses received from it.
    pub answers: u64,
    /// Polls it did not answer in time.
    pub timeouts: u64,
}

/// What the vehicle reports in its status, kept up to date by the app.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct VehicleState {
    /// State.
    pub mode: VehicleMode,
    /// East, m.
    pub x_m: f64,
    /// North, m.
    pub y_m: f64,
    /// Depth, m.
    pub depth_m: f64,
    /// Heading, degrees.
    pub heading_deg: f64,
    /// Speed, m/s.
    pub speed_mps: f64,
    /// Battery, V.
    pub battery_v: f64,
    /// Waypoint index.
    pub waypoint: u8,
    /// The safety health word.
    pub health: u16,
    /// Navigation 1-sigma, m.
    pub nav_sigma_m: Option<f64>,
    /// Roll, degrees.
    pub roll_deg: f64,
    /// Pitch, degrees.
    pub pitch_deg: f64,
    /// False while the vehicle does not know where it is (no navigation yet): it then
    /// leaves status and localisation requests unanswered rather than report a position it
    /// does not have (the poller counts a timeout). True by default.
    pub position_known: bool,
}

impl Default for VehicleState {
    fn default() -> Self {
        VehicleState {
            mode: VehicleMode::Idle,
            x_m: 0.0,
            y_m: 0.0,
            depth_m: 0.0,
            heading_deg: 0.0,
            speed_mps: 0.0,
            battery_v: 0.0,
            waypoint: 0,
            health: 0,
            nav_sigma_m: None,
            roll_deg: 0.0,
            pitch_deg: 0.0,
            position_known: true,
        }
    }
}

/// What a node does or reports.
#[derive(Debug, Clone, PartialEq)]
pub enum Event {
    /// Hand this frame to the modem, for `dest` (0: every node).
    Transmit {
        /// The destination modem id.
        dest: u8,
        /// The frame.
        frame: Frame,
    },
    /// A contact report.
    Contact(Contact),
    /// A poller's view of a vehicle, after each answer or timeout.
    Vehicle(VehicleView),
    /// A command's state changed (poller).
    Ack {
        /// The vehicle.
        to: u8,
        /// The command.
        kind: CommandKind,
        /// The sequence number of its latest transmission.
        seq: u32,
        /// Its state.
        state: AckState,
        /// With `Confirmed`: whether the vehicle carried it out.
        success: Option<bool>,
    },
    /// A command to apply on this vehicle.
    Apply {
        /// Its sender.
        from: u8,
        /// Its sequence number.
        seq: u32,
        /// The command.
        command: Applied,
    },
    /// A packet from a poller was accepted (vehicle: the base is in contact).
    PollerHeard {
        /// The poller.
        from: u8,
    },
    /// A payload was refused.
    Rejected(Reject),
    /// Something the operator should know.
    Warning(String),
}

/// The node's own counters (the [`Receiver`]'s are beside them, [`Node::receiver_counters`]).
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq)]
pub struct NetCounters {
    /// Polls sent.
    pub polls: u64,
    /// Polls answered in time.
    pub answers: u64,
    /// Polls not answered in time.
    pub timeouts: u64,
    /// Statuses that came after their poll's timeout.
    pub late: u64,
    /// Command transmissions.
    pub commands_sent: u64,
    /// Commands confirmed.
    pub confirmed: u64,
    /// Commands given up after every try.
    pub command_timeouts: u64,
    /// Commands refused when given ([`parse_command`] or out of range).
    pub command_errors: u64,
    /// Commands applied (vehicle).
    pub applied: u64,
    /// Frames handed to the modem.
    pub transmitted: u64,
    /// Contact reports made.
    pub contacts: u64,
    /// Packets from a sender outside the fleet list.
    pub unknown_sender: u64,
    /// Valid packets this role does not take.
    pub ignored: u64,
    /// Queue entries dropped on overflow.
    pub dropped: u64,
}

impl NetCounters {
    /// Requests (polls and command transmissions) that got no answer in time.
    pub fn losses(&self) -> u64 {
        self.timeouts + self.command_timeouts
    }
}

#[derive(Debug, Clone, Copy, PartialEq)]
enum Item {
    Poll { to: u8 },
    Command { req: CommandRequest, tries: u32 },
    Localise,
    Answer { dest: u8, packet: Packet },
}

#[derive(Debug, Clone, Copy, PartialEq)]
enum Waiting {
    Poll {
        to: u8,
        since: f64,
    },
    Command {
        req: CommandRequest,
        seq: u32,
        tries: u32,
        since: f64,
    },
}

/// One node of the network: a poller or a vehicle.
#[derive(Debug, Clone)]
pub struct Node {
    cfg: NetConfig,
    key: FleetKey,
    receiver: Receiver,
    seq: Sequencer,
    queue: TxQueue<Item>,
    waiting: Option<Waiting>,
    last_tx: Option<f64>,
    next_localise: f64,
    next_poll: usize,
    views: Vec<VehicleView>,
    own: OwnNav,
    state: VehicleState,
    counters: NetCounters,
}

impl Node {
    /// A node with its settings and the fleet's key.
    pub fn new(cfg: NetConfig, key: FleetKey) -> Self {
        let views = if cfg.role == Role::Poller {
            cfg.polled()
                .into_iter()
                .map(|id| VehicleView {
                    id,
                    name: cfg.name_of(id),
                    last_answer: None,
                    status: None,
                    polls: 0,
                    answers: 0,
                    timeouts: 0,
                })
                .collect()
        } else {
            Vec::new()
        };
        Node {
            receiver: Receiver::new(cfg.me, key.clone()).with_max_age(cfg.command_max_age_s),
            seq: Sequencer::starting_at(cfg.first_seq),
            key,
            queue: TxQueue::new(),
            waiting: None,
            last_tx: None,
            next_localise: f64::NEG_INFINITY,
            next_poll: 0,
            views,
            own: OwnNav::default(),
            state: VehicleState::default(),
            counters: NetCounters::default(),
            cfg,
        }
    }

    /// The settings.
    pub fn config(&self) -> &NetConfig {
        &self.cfg
    }

    /// The node's counters.
    pub fn counters(&self) -> &NetCounters {
        &self.counters
    }

    /// The decoder's counters (every payload, accepted or refused by reason).
    pub fn receiver_counters(&self) -> &Counters {
        self.receiver.counters()
    }

    /// A poller's view of each polled vehicle, in poll order.
    pub fn views(&self) -> &[VehicleView] {
        &self.views
    }

    /// Entries in the transmit queue.
    pub fn queued(&self) -> usize {
        self.queue.len()
    }

    /// Sets the listener's own navigation.
    pub fn set_own(&mut self, own: OwnNav) {
        self.own = own;
    }

    /// The listener's own navigation.
    pub fn own(&self) -> &OwnNav {
        &self.own
    }

    /// Sets what a vehicle reports in its status.
    pub fn set_vehicle_state(&mut self, state: VehicleState) {
        self.state = state;
    }

    /// Queues a command from its text ([`parse_command`]); the command is checked against
    /// the message's bounds now, so a queued command can always be sent. Returns it.
    pub fn command(
        &mut self,
        now: f64,
        text: &str,
        out: &mut Vec<Event>,
    ) -> Result<CommandRequest, CommandError> {
        let r = self.check_command(text);
        match r {
            Ok(req) => {
                self.push(Priority::Command, Item::Command { req, tries: 0 }, out);
                out.push(Event::Ack {
                    to: req.to,
                    kind: req.kind,
                    seq: 0,
                    state: AckState::Queued,
                    success: None,
                });
                let _ = now;
                Ok(req)
            }
            Err(e) => {
                self.counters.command_errors += 1;
                Err(e)
            }
        }
    }

    fn check_command(&self, text: &str) -> Result<CommandRequest, CommandError> {
        if self.cfg.role != Role::Poller {
            return Err(CommandError::NotAPoller);
        }
        let req = parse_command(text, &self.cfg.fleet)?;
        let known = self.cfg.fleet.is_empty() || self.cfg.fleet.iter().any(|(i, _)| *i == req.to);
        if req.to == self.cfg.me || !(known || req.to == BROADCAST) {
            return Err(CommandError::BadDestination(req.to.to_string()));
        }
        req.packet(Auth::new(self.cfg.me, req.to, 0))
            .encode(&self.key)
            .map_err(|e| CommandError::OutOfRange(e.to_string()))?;
        Ok(req)
    }

    fn push(&mut self, p: Priority, item: Item, out: &mut Vec<Event>) {
        if let Some(dropped) = self.queue.push(p, item, self.cfg.max_queue) {
            self.counters.dropped += 1;
            out.push(Event::Warning(format!(
                "transmit queue full: dropped {}",
                describe(&dropped)
            )));
            if let Item::Command { req, .. } = dropped {
                out.push(Event::Ack {
                    to: req.to,
                    kind: req.kind,
                    seq: 0,
                    state: AckState::Timeout,
                    success: None,
                });
            }
        }
    }

    fn transmit(&mut self, now: f64, dest: u8, p: &Packet, out: &mut Vec<Event>) -> bool {
        match p.encode(&self.key) {
            Ok(frame) => {
                self.counters.transmitted += 1;
                self.last_tx = Some(now);
                out.push(Event::Transmit { dest, frame });
                true
            }
            Err(e) => {
                out.push(Event::Warning(format!("cannot encode {p:?}: {e}")));
                false
            }
        }
    }

    fn next_seq(&mut self, out: &mut Vec<Event>) -> Option<u32> {
        let s = self.seq.take();
        if s.is_none() {
            out.push(Event::Warning(CommandError::SequenceExhausted.to_string()));
        }
        s
    }

    /// One step at time `now`: timeouts, then at most one transmission (a poller, when its
    /// slot has come and nothing is awaited; a vehicle, every answer due).
    pub fn tick(&mut self, now: f64, out: &mut Vec<Event>) {
        match self.cfg.role {
            Role::Poller => self.tick_poller(now, out),
            Role::Vehicle => {
                while let Some((_, item)) = self.queue.pop() {
                    if let Item::Answer { dest, packet } = item {
                        self.transmit(now, dest, &packet, out);
                    }
                }
            }
        }
    }

    fn tick_poller(&mut self, now: f64, out: &mut Vec<Event>) {
        if let Some(w) = self.waiting {
            let since = match w {
                Waiting::Poll { since, .. } | Waiting::Command { since, .. } => since,
            };
            if now < since + self.cfg.timeout_s - 1e-9 {
                return;
            }
            self.waiting = None;
            match w {
                Waiting::Poll { to, .. } => {
                    self.counters.timeouts += 1;
                    if let Some(v) = self.views.iter_mut().find(|v| v.id == to) {
                        v.timeouts += 1;
                        out.push(Event::Vehicle(v.clone()));
                    }
                }
                Waiting::Command {
                    req, seq, tries, ..
                } => {
                    if tries < self.cfg.command_tries {
                        self.push(Priority::Command, Item::Command { req, tries }, out);
                    } else {
                        self.counters.command_timeouts += 1;
                        out.push(Event::Ack {
                            to: req.to,
                            kind: req.kind,
                            seq,
                            state: AckState::Timeout,
                            success: None,
                        });
                    }
                }
            }
        }
        if let Some(t) = self.last_tx
            && now < t + self.cfg.slot_s - 1e-9
        {
            return;
        }
        if self.cfg.localisation_every_s > 0.0 && now >= self.next_localise {
            self.next_localise = now + self.cfg.localisation_every_s;
            self.push(Priority::Routine, Item::Localise, out);
        }
        let polled = self.cfg.polled();
        let poll_queued = self.queue.lanes[1]
            .iter()
            .any(|i| matches!(i, Item::Poll { .. }));
        if !poll_queued && !polled.is_empty() {
            let to = polled[self.next_poll % polled.len()];
            self.next_poll = (self.next_poll + 1) % polled.len();
            self.push(Priority::Poll, Item::Poll { to }, out);
        }
        let Some((_, item)) = self.queue.pop() else {
            return;
        };
        let me = self.cfg.me;
        match item {
            Item::Poll { to } => {
                let p = Packet::StatusRequest(StatusRequest { from: me, to });
                if self.transmit(now, to, &p, out) {
                    self.counters.polls += 1;
                    if let Some(v) = self.views.iter_mut().find(|v| v.id == to) {
                        v.polls += 1;
                    }
                    self.waiting = Some(Waiting::Poll { to, since: now });
                }
            }
            Item::Command { req, tries } => {
                let Some(seq) = self.next_seq(out) else {
                    return;
                };
                let p = req.packet(Auth::new(me, req.to, seq).at(now));
                if self.transmit(now, req.to, &p, out) {
                    self.counters.commands_sent += 1;
                    out.push(Event::Ack {
                        to: req.to,
                        kind: req.kind,
                        seq,
                        state: AckState::Sent,
                        success: None,
                    });
                    self.waiting = Some(Waiting::Command {
                        req,
                        seq,
                        tries: tries + 1,
                        since: now,
                    });
                }
            }
            Item::Localise => {
                let o = self.own;
                let p = Packet::Localisation(Localisation {
                    from: me,
                    x_m: o.x_m.unwrap_or(0.0),
                    y_m: o.y_m.unwrap_or(0.0),
                    depth_m: o.depth_m.unwrap_or(0.0).max(0.0),
                    roll_deg: 0.0,
                    pitch_deg: 0.0,
                    heading_deg: heading_field(o.heading_deg.unwrap_or(0.0)),
                });
                self.transmit(now, BROADCAST, &p, out);
            }
            Item::Answer { .. } => {}
        }
    }

    /// A payload from the modem, from modem `src` when the modem says, with the fix it
    /// measured.
    pub fn receive(&mut self, now: f64, payload: &[u8], fix: Option<&Fix>, out: &mut Vec<Event>) {
        let p = match self.receiver.receive_at(payload, now) {
            Ok(p) => p,
            Err(r) => {
                out.push(Event::Rejected(r));
                return;
            }
        };
        let from = p.from();
        if !self.cfg.fleet.is_empty() && !self.cfg.fleet.iter().any(|(i, _)| *i == from) {
            self.counters.unknown_sender += 1;
            out.push(Event::Rejected(Reject::BadSender(from)));
            return;
        }
        if let Some(f) = fix {
            self.usbl_contact(now, from, f, reported_depth(&p), out);
        }
        match self.cfg.role {
            Role::Poller => self.poller_takes(now, p, out),
            Role::Vehicle => self.vehicle_takes(now, p, out),
        }
    }

    fn usbl_contact(
        &mut self,
        now: f64,
        from: u8,
        f: &Fix,
        remote_depth: Option<f64>,
        out: &mut Vec<Event>,
    ) {
        if f.range_m.is_none() && f.azimuth_deg.is_none() && f.east_m.is_none() {
            return;
        }
        let rel = relative(f, &self.own, remote_depth, self.cfg.usbl_body_frame);
        // The depth the sender reports (its pressure sensor) beats one from the elevation.
        let depth = remote_depth.or(f.depth_m).or(rel.and_then(|r| r.2));
        let (x, y) = match (rel, self.own.x_m, self.own.y_m) {
            (Some((e, n, _)), Some(ox), Some(oy)) => (Some(ox + e), Some(oy + n)),
            _ => (None, None),
        };
        self.counters.contacts += 1;
        out.push(Event::Contact(Contact {
            id: from,
            name: self.cfg.name_of(from),
            time: now,
            source: ContactSource::Usbl,
            rel_east_m: rel.map(|r| r.0),
            rel_north_m: rel.map(|r| r.1),
            range_m: f.range_m,
            x_m: x,
            y_m: y,
            depth_m: depth,
            heading_deg: None,
            speed_mps: None,
        }));
    }

    fn reported_contact(&mut self, now: f64, p: &Packet, out: &mut Vec<Event>) {
        let (from, x, y, d, h, s) = match *p {
            Packet::Status(s) => (
                s.from,
                s.x_m,
                s.y_m,
                s.depth_m,
                s.heading_deg,
                Some(s.speed_mps),
            ),
            Packet::Localisation(l) => (l.from, l.x_m, l.y_m, l.depth_m, l.heading_deg, None),
            _ => return,
        };
        self.counters.contacts += 1;
        out.push(Event::Contact(Contact {
            id: from,
            name: self.cfg.name_of(from),
            time: now,
            source: ContactSource::Reported,
            rel_east_m: None,
            rel_north_m: None,
            range_m: None,
            x_m: Some(x),
            y_m: Some(y),
            depth_m: Some(d),
            heading_deg: Some(h),
            speed_mps: s,
        }));
    }

    fn poller_takes(&mut self, now: f64, p: Packet, out: &mut Vec<Event>) {
        match p {
            Packet::Status(s) => {
                self.reported_contact(now, &p, out);
                let awaited =
                    matches!(self.waiting, Some(Waiting::Poll { to, .. }) if to == s.from);
                if awaited {
                    self.waiting = None;
                    self.counters.answers += 1;
                } else {
                    self.counters.late += 1;
                }
                if let Some(v) = self.views.iter_mut().find(|v| v.id == s.from) {
                    if awaited {
                        v.answers += 1;
                    }
                    v.last_answer = Some(now);
                    v.status = Some(s);
                    out.push(Event::Vehicle(v.clone()));
                }
            }
            Packet::Localisation(_) => self.reported_contact(now, &p, out),
            Packet::Confirm(c) => {
                if let Some(Waiting::Command { req, seq, .. }) = self.waiting
                    && c.auth.from == req.to
                    && c.command_seq == seq
                {
                    self.waiting = None;
                }
                self.counters.confirmed += 1;
                out.push(Event::Ack {
                    to: c.auth.from,
                    kind: c.command,
                    seq: c.command_seq,
                    state: AckState::Confirmed,
                    success: Some(c.success),
                });
            }
            _ => self.counters.ignored += 1,
        }
    }

    fn vehicle_takes(&mut self, now: f64, p: Packet, out: &mut Vec<Event>) {
        let me = self.cfg.me;
        let from = p.from();
        match p {
            Packet::StatusRequest(_) | Packet::LocalisationRequest(_)
                if p.to() == Some(me) && !self.state.position_known =>
            {
                out.push(Event::PollerHeard { from });
                self.counters.ignored += 1;
            }
            Packet::StatusRequest(r) if r.to == me => {
                out.push(Event::PollerHeard { from });
                let s = self.status();
                self.push(
                    Priority::Poll,
                    Item::Answer {
                        dest: from,
                        packet: Packet::Status(s),
                    },
                    out,
                );
            }
            Packet::LocalisationRequest(r) if r.to == me => {
                out.push(Event::PollerHeard { from });
                let st = self.state;
                let l = Localisation {
                    from: me,
                    x_m: st.x_m,
                    y_m: st.y_m,
                    depth_m: st.depth_m.max(0.0),
                    roll_deg: st.roll_deg,
                    pitch_deg: st.pitch_deg,
                    heading_deg: heading_field(st.heading_deg),
                };
                self.push(
                    Priority::Poll,
                    Item::Answer {
                        dest: from,
                        packet: Packet::Localisation(l),
                    },
                    out,
                );
            }
            Packet::Status(_) | Packet::Localisation(_) => self.reported_contact(now, &p, out),
            _ => {
                let (Some(command), Some(a)) = (Applied::of(&p), p.auth()) else {
                    self.counters.ignored += 1;
                    return;
                };
                out.push(Event::PollerHeard { from });
                self.counters.applied += 1;
                out.push(Event::Apply {
                    from,
                    seq: a.seq,
                    command,
                });
                let Some(seq) = self.next_seq(out) else {
                    return;
                };
                let c = Confirm {
                    auth: Auth::new(me, from, seq).at(now),
                    command: command.kind(),
                    command_seq: a.seq,
                    success: true,
                };
                self.push(
                    Priority::Command,
                    Item::Answer {
                        dest: from,
                        packet: Packet::Confirm(c),
                    },
                    out,
                );
            }
        }
    }

    fn status(&self) -> Status {
        let s = &self.state;
        let finite = |v: f64| if v.is_finite() { v } else { 0.0 };
        Status {
            from: self.cfg.me,
            mode: s.mode,
            x_m: finite(s.x_m),
            y_m: finite(s.y_m),
            depth_m: finite(s.depth_m),
            heading_deg: heading_field(finite(s.heading_deg)),
            speed_mps: finite(s.speed_mps),
            battery_v: finite(s.battery_v),
            waypoint: s.waypoint,
            health: s.health,
            nav_sigma_m: s.nav_sigma_m.filter(|v| v.is_finite()),
        }
    }
}

/// A heading for a 0.5-degree field in [0, 359.5]: wrapped, and 359.75 or more is 0.
fn heading_field(h: f64) -> f64 {
    let h = h.rem_euclid(360.0);
    if h >= 359.75 || !h.is_finite() {
        0.0
    } else {
        h
    }
}

fn reported_depth(p: &Packet) -> Option<f64> {
    match p {
        Packet::Status(s) => Some(s.depth_m),
        Packet::Localisation(l) => Some(l.depth_m),
        _ => None,
    }
}

fn describe(i: &Item) -> String {
    match i {
        Item::Poll { to } => format!("the poll of {to}"),
        Item::Command { req, .. } => format!("{} to {}", command_word(req.kind), req.to),
        Item::Localise => "a position broadcast".into(),
        Item::Answer { packet, .. } => format!("an answer of id 0x{:02X}", packet.id()),
    }
}

/// The sender's offset from the listener, `(east, north, sender depth)`, from a fix: its
/// east/north offsets when it has them, else range and azimuth with the elevation (or the
/// depth difference, when both depths are known). `None` without a bearing.
pub fn relative(
    f: &Fix,
    own: &OwnNav,
    remote_depth: Option<f64>,
    body_frame: bool,
) -> Option<(f64, f64, Option<f64>)> {
    if let (Some(e), Some(n)) = (f.east_m, f.north_m) {
        return Some((e, n, f.depth_m.or(remote_depth)));
    }
    let r = f.range_m?;
    let mut az = f.azimuth_deg?;
    if body_frame {
        az += own.heading_deg?;
    }
    let (h, depth) = match (f.elevation_deg, own.depth_m, f.depth_m.or(remote_depth)) {
        (Some(el), own_d, _) => {
            let el = el.to_radians();
            (r * el.cos(), own_d.map(|d| d - r * el.sin()))
        }
        (None, Some(od), Some(rd)) => {
            let dd = rd - od;
            ((r * r - dd * dd).max(0.0).sqrt(), Some(rd))
        }
        (None, _, rd) => (r, rd),
    };
    let a = az.to_radians();
    Some((h * a.sin(), h * a.cos(), depth))
}

#[cfg(test)]
mod tests {
    use super::*;

    fn key() -> FleetKey {
        FleetKey::new(b"test fleet key")
    }

    fn fleet() -> Vec<(u8, String)> {
        vec![
            (15, "base".into()),
            (2, "coug2".into()),
            (3, "coug3".into()),
        ]
    }

    fn poller() -> Node {
        let mut c = NetConfig::new(15, Role::Poller);
        c.fleet = fleet();
        c.poll_order = vec![3, 2];
        Node::new(c, key())
    }

    fn vehicle(id: u8) -> Node {
        let mut c = NetConfig::new(id, Role::Vehicle);
        c.fleet = fleet();
        Node::new(c, key())
    }

    fn frames(ev: &[Event]) -> Vec<(u8, Frame)> {
        ev.iter()
            .filter_map(|e| match e {
                Event::Transmit { dest, frame } => Some((*dest, *frame)),
                _ => None,
            })
            .collect()
    }

    /// The packet in a frame, read by whichever node may take it.
    fn decode(f: &Frame) -> Packet {
        (1..=MAX_NODE)
            .find_map(|me| Receiver::new(me, key()).receive(f).ok())
            .expect("a valid frame")
    }

    #[test]
    fn polls_follow_the_order_and_a_timeout_moves_on_after_4_s() {
        let mut b = poller();
        let mut ev = Vec::new();
        b.tick(0.0, &mut ev);
        let f = frames(&ev);
        assert_eq!(f.len(), 1);
        assert_eq!(f[0].0, 3);
        assert_eq!(
            decode(&f[0].1),
            Packet::StatusRequest(StatusRequest { from: 15, to: 3 })
        );
        // Nothing more while the answer is awaited.
        for t in [1.0, 2.0, 3.9] {
            ev.clear();
            b.tick(t, &mut ev);
            assert!(frames(&ev).is_empty(), "at {t}");
        }
        ev.clear();
        b.tick(4.0, &mut ev);
        let f = frames(&ev);
        assert_eq!(f.len(), 1);
        assert_eq!(f[0].0, 2, "the next vehicle after the timeout");
        assert_eq!(b.counters().timeouts, 1);
        let v3 = ev.iter().find_map(|e| match e {
            Event::Vehicle(v) if v.id == 3 => Some(v.clone()),
            _ => None,
        });
        let v3 = v3.expect("a view of 3 at its timeout");
        assert_eq!((v3.polls, v3.answers, v3.timeouts), (1, 0, 1));
        // Then back to 3.
        ev.clear();
        b.tick(8.0, &mut ev);
        assert_eq!(frames(&ev)[0].0, 3);
        assert_eq!(b.counters().polls, 3);
    }

    #[test]
    fn a_vehicle_that_does_not_know_where_it_is_does_not_answer() {
        let mut b = poller();
        let mut v3 = vehicle(3);
        v3.set_vehicle_state(VehicleState {
            position_known: false,
            ..VehicleState::default()
        });
        let mut ev = Vec::new();
        b.tick(0.0, &mut ev);
        let poll = frames(&ev)[0].1;
        let mut vev = Vec::new();
        v3.receive(0.5, &poll, None, &mut vev);
        v3.tick(0.6, &mut vev);
        assert!(frames(&vev).is_empty(), "no made-up 0,0: {vev:?}");
        assert!(vev.contains(&Event::PollerHeard { from: 15 }));
        assert_eq!(v3.counters().ignored, 1);
        // Once its navigation has a position it answers.
        v3.set_vehicle_state(VehicleState {
            x_m: 5.0,
            ..VehicleState::default()
        });
        vev.clear();
        v3.receive(1.0, &poll, None, &mut vev);
        v3.tick(1.1, &mut vev);
        assert_eq!(frames(&vev).len(), 1);
    }

    #[test]
    fn an_answer_ends_the_wait_but_the_slot_still_holds() {
        let mut b = poller();
        let mut v3 = vehicle(3);
        v3.set_vehicle_state(VehicleState {
            x_m: 12.3,
            y_m: -45.6,
            depth_m: 3.2,
            heading_deg: 90.0,
            speed_mps: 1.0,
            battery_v: 16.0,
            mode: VehicleMode::Mission,
            ..VehicleState::default()
        });
        let mut ev = Vec::new();
        b.tick(0.0, &mut ev);
        let poll = frames(&ev)[0].1;
        let mut vev = Vec::new();
        v3.receive(0.5, &poll, None, &mut vev);
        v3.tick(0.6, &mut vev);
        let answer = frames(&vev);
        assert_eq!(answer.len(), 1);
        assert_eq!(answer[0].0, 15);
        ev.clear();
        b.receive(1.5, &answer[0].1, None, &mut ev);
        assert_eq!(b.counters().answers, 1);
        let view = b.views().iter().find(|v| v.id == 3).unwrap();
        assert_eq!(view.last_answer, Some(1.5));
        let s = view.status.unwrap();
        assert!((s.x_m - 12.3).abs() < 0.051 && (s.y_m + 45.6).abs() < 0.051);
        // The reported position is a contact.
        let c = ev
            .iter()
            .find_map(|e| match e {
                Event::Contact(c) => Some(c.clone()),
                _ => None,
            })
            .unwrap();
        assert_eq!(
            (c.source, c.name.as_str()),
            (ContactSource::Reported, "coug3")
        );
        // The slot (4 s from the poll's start) is not over at 2 s.
        ev.clear();
        b.tick(2.0, &mut ev);
        assert!(frames(&ev).is_empty());
        b.tick(4.0, &mut ev);
        assert_eq!(frames(&ev)[0].0, 2);
        assert_eq!(b.counters().timeouts, 0);
    }

    #[test]
    fn commands_go_before_polls_before_routine() {
        let mut q = TxQueue::new();
        q.push(Priority::Routine, "r1", 10);
        q.push(Priority::Poll, "p1", 10);
        q.push(Priority::Command, "c1", 10);
        q.push(Priority::Poll, "p2", 10);
        q.push(Priority::Command, "c2", 10);
        let order: Vec<&str> = std::iter::from_fn(|| q.pop().map(|(_, x)| x)).collect();
        assert_eq!(order, ["c1", "c2", "p1", "p2", "r1"]);
        // Overflow drops the oldest of the lowest priority present.
        let mut q = TxQueue::new();
        q.push(Priority::Command, "c", 2);
        q.push(Priority::Poll, "p", 2);
        assert_eq!(q.push(Priority::Routine, "r", 2), Some("r"));
        assert_eq!(q.push(Priority::Command, "c2", 2), Some("p"));

        // In the poller: a command queued while a poll waits goes at the next slot, before
        // the next poll.
        let mut b = poller();
        let mut ev = Vec::new();
        b.tick(0.0, &mut ev);
        b.command(1.0, "to=2,cmd=surface", &mut ev).unwrap();
        ev.clear();
        b.tick(4.0, &mut ev);
        let f = frames(&ev);
        assert_eq!(f.len(), 1);
        assert!(matches!(decode(&f[0].1), Packet::Surface(_)));
    }

    #[test]
    fn a_command_is_authenticated_end_to_end_and_a_replay_is_refused() {
        let mut b = poller();
        let mut v2 = vehicle(2);
        let mut v3 = vehicle(3);
        let mut ev = Vec::new();
        b.command(0.0, "to=2,cmd=kill", &mut ev).unwrap();
        assert!(ev.iter().any(|e| matches!(
            e,
            Event::Ack {
                state: AckState::Queued,
                ..
            }
        )));
        b.tick(0.0, &mut ev);
        let (dest, kill) = frames(&ev)[0];
        assert_eq!(dest, 2);
        // The vehicle applies it and confirms it.
        let mut vev = Vec::new();
        v2.receive(0.5, &kill, None, &mut vev);
        assert!(vev.iter().any(|e| matches!(
            e,
            Event::Apply {
                from: 15,
                command: Applied::Kill,
                ..
            }
        )));
        v2.tick(0.6, &mut vev);
        let confirm = frames(&vev)[0].1;
        // The other vehicle hears it and refuses it as not its own.
        let mut ev3 = Vec::new();
        v3.receive(0.5, &kill, None, &mut ev3);
        assert!(!ev3.iter().any(|e| matches!(e, Event::Apply { .. })));
        assert_eq!(v3.receiver_counters().not_for_me, 1);
        // The poller takes the confirmation.
        ev.clear();
        b.receive(1.0, &confirm, None, &mut ev);
        assert!(ev.iter().any(|e| matches!(
            e,
            Event::Ack {
                to: 2,
                kind: CommandKind::Kill,
                seq: 0,
                state: AckState::Confirmed,
                success: Some(true)
            }
        )));
        // The same frame again is a replay: refused, counted, not applied.
        vev.clear();
        v2.receive(5.0, &kill, None, &mut vev);
        assert!(!vev.iter().any(|e| matches!(e, Event::Apply { .. })));
        assert_eq!(v2.receiver_counters().replayed, 1);
        // A frame signed with another key is refused.
        let mut stranger = Node::new(NetConfig::new(15, Role::Poller), FleetKey::new(b"x"));
        let mut sev = Vec::new();
        stranger.command(0.0, "to=2,cmd=kill", &mut sev).unwrap();
        stranger.tick(0.0, &mut sev);
        let forged = frames(&sev)[0].1;
        v2.receive(6.0, &forged, None, &mut vev);
        assert_eq!(v2.receiver_counters().bad_tag, 1);
        // A sender outside the fleet is refused.
        let mut c = NetConfig::new(9, Role::Poller);
        c.fleet = vec![(9, "rogue".into()), (2, "coug2".into())];
        let mut rogue = Node::new(c, key());
        let mut rev = Vec::new();
        rogue.command(0.0, "to=2,cmd=kill", &mut rev).unwrap();
        rogue.tick(0.0, &mut rev);
        vev.clear();
        v2.receive(7.0, &frames(&rev)[0].1, None, &mut vev);
        assert!(!vev.iter().any(|e| matches!(e, Event::Apply { .. })));
        assert_eq!(v2.counters().unknown_sender, 1);
    }

    #[test]
    fn a_command_delivered_later_than_its_maximum_age_is_refused_and_counted() {
        // Two goto commands sent at 1000 s; one heard at once, the other held up (jammed,
        // recorded and played later, or stuck in a queue) and delivered 61 s later: past
        // the default 60 s it is refused as stale, counted, and applies nothing.
        let mut b = poller();
        let mut ev = Vec::new();
        b.command(1000.0, "to=2,cmd=goto,x=10,y=20", &mut ev)
            .unwrap();
        b.command(1000.0, "to=3,cmd=goto,x=30,y=40", &mut ev)
            .unwrap();
        b.tick(1000.0, &mut ev);
        b.tick(1004.0, &mut ev);
        let f = frames(&ev);
        let (to2, to3) = (f[0].1, f[1].1);
        assert_eq!((f[0].0, f[1].0), (2, 3));
        let mut v2 = vehicle(2);
        let mut vev = Vec::new();
        v2.receive(1000.5, &to2, None, &mut vev);
        assert!(vev.iter().any(|e| matches!(e, Event::Apply { .. })));
        let mut v3 = vehicle(3);
        let mut late = Vec::new();
        v3.receive(1004.0 + 61.0, &to3, None, &mut late);
        assert!(!late.iter().any(|e| matches!(e, Event::Apply { .. })));
        assert!(
            late.iter().any(|e| matches!(
                e,
                Event::Rejected(Reject::Stale {
                    from: 15,
                    age_s: 61
                })
            )),
            "{late:?}"
        );
        assert_eq!(v3.receiver_counters().stale, 1);
        // Without a maximum age the late copy would have been taken.
        let mut c = NetConfig::new(3, Role::Vehicle);
        c.command_max_age_s = None;
        let mut lax = Node::new(c, key());
        let mut lev = Vec::new();
        lax.receive(1004.0 + 61.0, &to3, None, &mut lev);
        assert!(lev.iter().any(|e| matches!(e, Event::Apply { .. })));
    }

    #[test]
    fn an_unconfirmed_command_is_sent_again_then_times_out() {
        let mut b = poller();
        let mut ev = Vec::new();
        b.command(0.0, "to=3,cmd=depth,depth=5", &mut ev).unwrap();
        b.tick(0.0, &mut ev);
        b.tick(4.0, &mut ev);
        b.tick(8.0, &mut ev);
        let sent: Vec<u32> = ev
            .iter()
            .filter_map(|e| match e {
                Event::Ack {
                    state: AckState::Sent,
                    seq,
                    ..
                } => Some(*seq),
                _ => None,
            })
            .collect();
        assert_eq!(sent, [0, 1], "two tries, each with its own sequence number");
        assert!(ev.iter().any(|e| matches!(
            e,
            Event::Ack {
                state: AckState::Timeout,
                seq: 1,
                ..
            }
        )));
        assert_eq!(b.counters().command_timeouts, 1);
    }

    #[test]
    fn bad_commands_are_refused_with_their_reason() {
        let mut b = poller();
        let mut ev = Vec::new();
        let cases = [
            ("cmd=kill", "to: missing"),
            ("to=2", "cmd: missing"),
            ("to=2,cmd=jump", "cmd=jump"),
            ("to=7,cmd=kill", "to=7"),
            ("to=15,cmd=kill", "to=15"),
            ("to=2,cmd=goto,x=1", "needs x= and y="),
            ("to=2,cmd=goto,x=1,y=9000", "outside"),
            ("to=2,cmd=depth", "needs depth="),
            ("to=2,cmd=depth,depth=deep", "not a number"),
            ("to=2,cmd=kill,colour=red", "unknown field"),
        ];
        for (text, why) in cases {
            let e = b.command(0.0, text, &mut ev).unwrap_err();
            assert!(e.to_string().contains(why), "{text}: {e}");
        }
        assert_eq!(b.queued(), 0);
        assert_eq!(b.counters().command_errors, cases.len() as u64);
        // Names are taken for ids.
        let c = b
            .command(0.0, "to=coug3,cmd=loiter,x=5,y=6,radius=30", &mut ev)
            .unwrap();
        assert_eq!((c.to, c.radius_m), (3, Some(30.0)));
    }

    #[test]
    fn a_usbl_fix_gives_relative_and_absolute_positions() {
        let mut v2 = vehicle(2);
        v2.set_own(OwnNav {
            x_m: Some(100.0),
            y_m: Some(200.0),
            depth_m: Some(5.0),
            heading_deg: Some(90.0),
        });
        // coug3 reports itself; the fix says 50 m slant, bearing 30 degrees, 3 m shallower:
        // elevation asin(3/50).
        let mut v3 = vehicle(3);
        v3.set_vehicle_state(VehicleState {
            depth_m: 2.0,
            ..VehicleState::default()
        });
        let mut e3 = Vec::new();
        let mut b = poller();
        let mut eb = Vec::new();
        b.tick(0.0, &mut eb);
        v3.receive(0.1, &frames(&eb)[0].1, None, &mut e3);
        v3.tick(0.2, &mut e3);
        let status = frames(&e3)[0].1;
        let el = (3.0f64 / 50.0).asin().to_degrees();
        let fix = Fix {
            range_m: Some(50.0),
            azimuth_deg: Some(30.0),
            elevation_deg: Some(el),
            ..Fix::default()
        };
        let mut ev = Vec::new();
        v2.receive(1.0, &status, Some(&fix), &mut ev);
        let usbl = ev
            .iter()
            .find_map(|e| match e {
                Event::Contact(c) if c.source == ContactSource::Usbl => Some(c.clone()),
                _ => None,
            })
            .expect("a USBL contact");
        let h = (50.0f64 * 50.0 - 9.0).sqrt();
        let (e, n) = (h * 0.5, h * 3f64.sqrt() / 2.0);
        assert!((usbl.rel_east_m.unwrap() - e).abs() < 1e-9);
        assert!((usbl.rel_north_m.unwrap() - n).abs() < 1e-9);
        assert!((usbl.x_m.unwrap() - (100.0 + e)).abs() < 1e-9);
        assert!((usbl.y_m.unwrap() - (200.0 + n)).abs() < 1e-9);
        assert!((usbl.depth_m.unwrap() - 2.0).abs() < 1e-9);
        assert_eq!(usbl.range_m, Some(50.0));
        assert_eq!(usbl.name, "coug3");
        // Overheard by a vehicle, the status is also a reported contact.
        assert!(
            ev.iter()
                .any(|e| matches!(e, Event::Contact(c) if c.source == ContactSource::Reported))
        );

        // In the body frame the listener's heading (90) is added: bearing 120.
        let mut c = NetConfig::new(2, Role::Vehicle);
        c.usbl_body_frame = true;
        let mut body = Node::new(c, key());
        body.set_own(*v2.own());
        let mut ev = Vec::new();
        body.receive(1.0, &status, Some(&fix), &mut ev);
        let c = ev
            .iter()
            .find_map(|e| match e {
                Event::Contact(c) if c.source == ContactSource::Usbl => Some(c.clone()),
                _ => None,
            })
            .unwrap();
        let a = 120f64.to_radians();
        assert!((c.rel_east_m.unwrap() - h * a.sin()).abs() < 1e-9);
        assert!((c.rel_north_m.unwrap() - h * a.cos()).abs() < 1e-9);

        // Without its own position the listener gets the relative position only.
        let mut lost = vehicle(2);
        let mut ev = Vec::new();
        lost.receive(1.0, &status, Some(&fix), &mut ev);
        let c = ev
            .iter()
            .find_map(|e| match e {
                Event::Contact(c) if c.source == ContactSource::Usbl => Some(c.clone()),
                _ => None,
            })
            .unwrap();
        assert!(c.rel_east_m.is_some() && c.x_m.is_none());

        // A SeaTrac POSITION fix's offsets win over the angles; no elevation: the depths.
        let f = Fix {
            range_m: Some(10.0),
            east_m: Some(-6.0),
            north_m: Some(8.0),
            depth_m: Some(4.0),
            ..Fix::default()
        };
        assert_eq!(
            relative(&f, &OwnNav::default(), None, false),
            Some((-6.0, 8.0, Some(4.0)))
        );
        let f = Fix {
            range_m: Some(5.0),
            azimuth_deg: Some(180.0),
            ..Fix::default()
        };
        let own = OwnNav {
            depth_m: Some(1.0),
            ..OwnNav::default()
        };
        let (e, n, d) = relative(&f, &own, Some(4.0), false).unwrap();
        assert!(e.abs() < 1e-9 && (n + 4.0).abs() < 1e-9 && d == Some(4.0));
    }
}
