//! The CoUGARs fleet's acoustic messages in the `compact` codec (issue #16, point 1): the
//! Gen-1 set (status, status request, emergency kill and surface with their confirmations,
//! localisation request and answer) and the commands the seed paper asks for (go to a point,
//! loiter at a point, return, set depth, abort), every one small enough for one SeaTrac DAT
//! packet ([`devices::seatrac::MAX_DAT_PAYLOAD`], checked at compile time).
//!
//! A frame is `id (1 byte) | body (bit-packed, zero-padded) | tag (4 bytes, authenticated
//! messages only)`. The ids (0x71-0x7E) differ from every Gen-1 (0x00-0x61) and Gen-2
//! (0x10-0x15, 0x30, 0x31) id, so a packet of the older protocols is refused as an unknown id
//! rather than misread.
//!
//! [`net`] is the polled network over these messages (issue #16, point 2): the pure core of
//! the `pAcomms` app (`runtime::acomms_apps`).
//!
//! # Sizes
//!
//! On the wire, id and tag included (pinned by `tests/sizes.rs`, listed by [`SIZE_TABLE`]):
//!
//! | message | id | body bits | bytes | authenticated | Gen-1 / Gen-2 |
//! |---|---|---|---|---|---|
//! | [`Status`] | 0x71 | 109 | 15 | no | 27 / 29 |
//! | [`StatusRequest`] | 0x72 | 8 | 2 | no | 2 / 1 |
//! | [`LocalisationRequest`] | 0x73 | 8 | 2 | no | 2 / - |
//! | [`Localisation`] | 0x74 | 77 | 11 | no | 29 / - |
//! | [`Confirm`] | 0x75 | 72 | 14 | yes | 3 / - |
//! | [`Kill`] | 0x78 | 44 | 11 | yes | 2 / 1 |
//! | [`Surface`] | 0x79 | 44 | 11 | yes | 2 / 1 |
//! | [`Abort`] | 0x7A | 44 | 11 | yes | - / 1 |
//! | [`Return`] | 0x7B | 44 | 11 | yes | - / 1 |
//! | [`GoTo`] | 0x7C | 95 | 17 | yes | - |
//! | [`Loiter`] | 0x7D | 104 | 18 | yes | - |
//! | [`SetDepth`] | 0x7E | 55 | 12 | yes | - |
//!
//! The full status (position to 0.1 m over +-5 km, depth to 0.1 m, heading to 0.5 degree,
//! speed, battery voltage, waypoint index, the 16-bit health word, navigation sigma and the
//! vehicle's mode) takes 15 bytes where the paper's structs take 26-29. Authentication costs
//! 68 bits per command (a 24-bit sequence number, a 12-bit time sent and a 32-bit tag; see
//! [`auth`]): the time field added 2 bytes to a kill, surface, abort or return (9 to 11) and
//! 1 byte to the others.
//!
//! # Receiving
//!
//! [`Receiver::receive`] refuses, and counts in [`Counters`], every payload that is not a
//! valid message for this node: empty or truncated, too long, unknown id, a field out of its
//! range or non-zero padding, a bad tag (wrong key, any byte changed), a sender id of 0 or of
//! the receiver itself, a request or command for another node, a replayed or too old sequence
//! number, and (given the receiver's clock, [`Receiver::receive_at`], and a maximum age,
//! [`Receiver::with_max_age`]) a command sent longer ago than that. No input makes it panic (`tests/fuzz.rs` runs [`fuzz::receive`]).
//!
//! ```
//! use acomms::{Auth, FleetKey, Kill, Packet, Receiver, Reject};
//! let key = FleetKey::new(b"fleet secret, 32 random bytes...");
//! let kill = Packet::Kill(Kill { auth: Auth::new(15, 2, 7) });
//! let frame = kill.encode(&key).unwrap();
//! assert_eq!(frame.len(), 11);
//!
//! let mut coug2 = Receiver::new(2, key.clone());
//! assert_eq!(coug2.receive(&frame), Ok(kill));
//! assert_eq!(coug2.receive(&frame), Err(Reject::Replayed { from: 15, seq: 7 }));
//! let mut coug3 = Receiver::new(3, key);
//! assert_eq!(coug3.receive(&frame), Err(Reject::NotForMe { to: 2 }));
//! let mut stranger = Receiver::new(2, FleetKey::new(b"another fleet"));
//! assert_eq!(stranger.receive(&frame), Err(Reject::BadTag));
//! assert_eq!(stranger.counters().bad_tag, 1);
//! ```

#![warn(missing_docs)]

pub mod auth;
pub mod fuzz;
pub mod messages;
pub mod net;

pub use auth::{FleetKey, ReplayWindow, Sequencer};
pub use compact::{Compact, DecodeError, EncodeError};
pub use messages::*;

use auth::{ReplayError, TAG_BYTES};
use devices::seatrac::MAX_DAT_PAYLOAD;

/// The largest frame: one SeaTrac DAT payload.
pub const MAX_FRAME: usize = MAX_DAT_PAYLOAD;

/// The highest node id (SeaTrac beacon ids are 1-15).
pub const MAX_NODE: u8 = 15;

/// The destination that means every vehicle (SeaTrac's BEACON_ALL).
pub const BROADCAST: u8 = 0;

/// One encoded frame, at most [`MAX_FRAME`] bytes, on the stack.
#[derive(Clone, Copy, PartialEq, Eq)]
pub struct Frame {
    buf: [u8; MAX_FRAME],
    len: u8,
}

impl Frame {
    /// The frame's bytes.
    pub fn as_bytes(&self) -> &[u8] {
        &self.buf[..usize::from(self.len)]
    }
}

impl std::ops::Deref for Frame {
    type Target = [u8];
    fn deref(&self) -> &[u8] {
        self.as_bytes()
    }
}

impl std::fmt::Debug for Frame {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(f, "Frame(")?;
        for b in self.as_bytes() {
            write!(f, "{b:02X}")?;
        }
        write!(f, ")")
    }
}

/// One row of [`SIZE_TABLE`].
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct SizeRow {
    /// The message's name.
    pub name: &'static str,
    /// Its id byte.
    pub id: u8,
    /// Bits of its body (without id and tag).
    pub body_bits: usize,
    /// Bytes on the wire: id, padded body and tag.
    pub wire_bytes: usize,
    /// Whether it carries a sequence number and tag.
    pub authenticated: bool,
}

/// A message type's place in the protocol.
pub trait Message: Compact {
    /// Its id byte.
    const ID: u8;
    /// Whether it is authenticated (its body starts with an [`Auth`]).
    const AUTHENTICATED: bool;
    /// Bytes on the wire.
    const WIRE_BYTES: usize =
        1 + Self::SIZE_BYTES + if Self::AUTHENTICATED { TAG_BYTES } else { 0 };
}

macro_rules! packets {
    ($( $(#[$doc:meta])* $variant:ident = $id:literal, $auth:literal; )*) => {
        /// Every message of the protocol.
        #[derive(Debug, Clone, Copy, PartialEq)]
        pub enum Packet {
            $( $(#[$doc])* $variant($variant), )*
        }

        $(
            impl Message for $variant {
                const ID: u8 = $id;
                const AUTHENTICATED: bool = $auth;
            }
            const _: () = assert!(<$variant as Message>::WIRE_BYTES <= MAX_FRAME);
            impl From<$variant> for Packet {
                fn from(m: $variant) -> Self {
                    Packet::$variant(m)
                }
            }
        )*

        /// Every message's size, in id order.
        pub const SIZE_TABLE: &[SizeRow] = &[
            $( SizeRow {
                name: stringify!($variant),
                id: $id,
                body_bits: <$variant as Compact>::SIZE_BITS,
                wire_bytes: <$variant as Message>::WIRE_BYTES,
                authenticated: $auth,
            }, )*
        ];

        impl Packet {
            /// The id byte.
            pub fn id(&self) -> u8 {
                match self { $( Packet::$variant(_) => $id, )* }
            }

            /// Bytes on the wire.
            pub fn wire_bytes(&self) -> usize {
                match self { $( Packet::$variant(_) => <$variant as Message>::WIRE_BYTES, )* }
            }

            fn write_body(&self, out: &mut [u8]) -> Result<usize, EncodeError> {
                match self { $( Packet::$variant(m) => m.encode_into(out), )* }
            }

            /// Whether the message with id `id` is authenticated, and its size on the
            /// wire; `None` for an unknown id.
            pub fn layout(id: u8) -> Option<(bool, usize)> {
                match id {
                    $( $id => Some(($auth, <$variant as Message>::WIRE_BYTES)), )*
                    _ => None,
                }
            }

            fn decode_body(id: u8, body: &[u8]) -> Option<Result<Packet, DecodeError>> {
                match id {
                    $( $id => Some($variant::decode(body).map(Packet::$variant)), )*
                    _ => None,
                }
            }
        }
    };
}

packets! {
    /// A vehicle's status.
    Status = 0x71, false;
    /// A request for a status.
    StatusRequest = 0x72, false;
    /// A request for a localisation answer.
    LocalisationRequest = 0x73, false;
    /// A pose for cooperative localisation.
    Localisation = 0x74, false;
    /// A vehicle's answer to a command.
    Confirm = 0x75, true;
    /// Emergency kill.
    Kill = 0x78, true;
    /// Emergency surface.
    Surface = 0x79, true;
    /// Abort the mission.
    Abort = 0x7A, true;
    /// Return home.
    Return = 0x7B, true;
    /// Go to a point.
    GoTo = 0x7C, true;
    /// Loiter at a point.
    Loiter = 0x7D, true;
    /// Hold a depth.
    SetDepth = 0x7E, true;
}

impl Packet {
    /// The sending node.
    pub fn from(&self) -> u8 {
        match self {
            Packet::Status(m) => m.from,
            Packet::StatusRequest(m) => m.from,
            Packet::LocalisationRequest(m) => m.from,
            Packet::Localisation(m) => m.from,
            _ => self.auth().map_or(0, |a| a.from),
        }
    }

    /// The destination node, for the messages that name one (0: every vehicle).
    pub fn to(&self) -> Option<u8> {
        match self {
            Packet::StatusRequest(m) => Some(m.to),
            Packet::LocalisationRequest(m) => Some(m.to),
            _ => self.auth().map(|a| a.to),
        }
    }

    /// The authenticated header, for the messages that carry one.
    pub fn auth(&self) -> Option<Auth> {
        match self {
            Packet::Confirm(m) => Some(m.auth),
            Packet::Kill(m) => Some(m.auth),
            Packet::Surface(m) => Some(m.auth),
            Packet::Abort(m) => Some(m.auth),
            Packet::Return(m) => Some(m.auth),
            Packet::GoTo(m) => Some(m.auth),
            Packet::Loiter(m) => Some(m.auth),
            Packet::SetDepth(m) => Some(m.auth),
            Packet::Status(_)
            | Packet::StatusRequest(_)
            | Packet::LocalisationRequest(_)
            | Packet::Localisation(_) => None,
        }
    }

    /// Encodes the frame, signing authenticated messages with `key`.
    pub fn encode(&self, key: &FleetKey) -> Result<Frame, EncodeError> {
        let mut f = Frame {
            buf: [0; MAX_FRAME],
            len: 0,
        };
        f.buf[0] = self.id();
        let n = 1 + self.write_body(&mut f.buf[1..])?;
        let n = if self.auth().is_some() {
            let tag = key.tag(&f.buf[..n]);
            f.buf[n..n + TAG_BYTES].copy_from_slice(&tag);
            n + TAG_BYTES
        } else {
            n
        };
        f.len = n as u8;
        Ok(f)
    }
}

/// Why a payload was refused.
#[derive(Debug, Clone, Copy, PartialEq, Eq, thiserror::Error)]
pub enum Reject {
    /// No byte at all.
    #[error("empty payload")]
    Empty,
    /// Not a message id of this protocol.
    #[error("unknown message id 0x{0:02X}")]
    UnknownId(u8),
    /// Shorter than its message.
    #[error("truncated: {got} of {expected} bytes")]
    Truncated {
        /// The message's size.
        expected: usize,
        /// The payload's size.
        got: usize,
    },
    /// Longer than its message.
    #[error("too long: {got} bytes for {expected}")]
    TooLong {
        /// The message's size.
        expected: usize,
        /// The payload's size.
        got: usize,
    },
    /// The tag does not match (another key, or a changed byte).
    #[error("bad authentication tag")]
    BadTag,
    /// A field is out of its range, or the padding is not zero.
    #[error("malformed: {0}")]
    Malformed(DecodeError),
    /// The sender id is 0 or the receiver's own.
    #[error("bad sender id {0}")]
    BadSender(u8),
    /// A request or command for another node.
    #[error("for node {to}")]
    NotForMe {
        /// Its destination.
        to: u8,
    },
    /// A sequence number already accepted from this sender.
    #[error("replay of {from}'s sequence {seq}")]
    Replayed {
        /// The sender.
        from: u8,
        /// The sequence number.
        seq: u32,
    },
    /// A sequence number older than the replay window.
    #[error("{from}'s sequence {seq} is older than the window")]
    TooOld {
        /// The sender.
        from: u8,
        /// The sequence number.
        seq: u32,
    },
    /// A command whose time field is older (or further ahead) than the receiver's maximum
    /// age on its clock.
    #[error("{from}'s command is {age_s} s old")]
    Stale {
        /// The sender.
        from: u8,
        /// Its age in whole seconds (negative: ahead of the receiver's clock).
        age_s: i32,
    },
}

/// What a [`Receiver`] has seen: every payload is counted once, as accepted or under the
/// reason it was refused.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq)]
pub struct Counters {
    /// Payloads given.
    pub received: u64,
    /// Messages accepted.
    pub accepted: u64,
    /// Empty or shorter than their message.
    pub truncated: u64,
    /// Longer than their message.
    pub too_long: u64,
    /// Unknown id.
    pub unknown_id: u64,
    /// Field out of range or non-zero padding.
    pub malformed: u64,
    /// Tag mismatch.
    pub bad_tag: u64,
    /// Sender 0 or the receiver itself.
    pub bad_sender: u64,
    /// Addressed to another node.
    pub not_for_me: u64,
    /// Sequence number already accepted.
    pub replayed: u64,
    /// Sequence number behind the window.
    pub too_old: u64,
    /// Commands older than the maximum age (or stamped that far ahead).
    pub stale: u64,
}

impl Counters {
    /// Payloads refused, all reasons.
    pub fn rejected(&self) -> u64 {
        self.truncated
            + self.too_long
            + self.unknown_id
            + self.malformed
            + self.bad_tag
            + self.bad_sender
            + self.not_for_me
            + self.replayed
            + self.too_old
            + self.stale
    }
}

/// A node's decoder: checks every payload against the protocol, the fleet key, its own id and
/// each sender's replay window, and counts what it refuses.
#[derive(Debug, Clone)]
pub struct Receiver {
    me: u8,
    key: FleetKey,
    windows: [ReplayWindow; MAX_NODE as usize + 1],
    counters: Counters,
    max_age_s: Option<f64>,
}

impl Receiver {
    /// The decoder of node `me` (1-15) with the fleet's key.
    pub fn new(me: u8, key: FleetKey) -> Self {
        Self {
            me,
            key,
            windows: [ReplayWindow::new(); MAX_NODE as usize + 1],
            counters: Counters::default(),
            max_age_s: None,
        }
    }

    /// Refuses, in [`Receiver::receive_at`], commands whose time field is more than
    /// `max_age_s` seconds old on the receiver's clock (or that far ahead); `None` (the
    /// default) takes any age.
    ///
    /// ```
    /// use acomms::{Auth, FleetKey, Kill, Packet, Receiver, Reject};
    /// let key = FleetKey::new(b"k");
    /// let sent_at = 1_786_000_010.0;
    /// let kill = Packet::Kill(Kill { auth: Auth::new(15, 2, 7).at(sent_at) });
    /// let frame = kill.encode(&key).unwrap();
    /// let mut v = Receiver::new(2, key).with_max_age(Some(30.0));
    /// assert_eq!(v.receive_at(&frame, sent_at + 45.0), Err(Reject::Stale { from: 15, age_s: 45 }));
    /// assert_eq!(v.receive_at(&frame, sent_at + 3.0), Ok(kill));
    /// assert_eq!(v.counters().stale, 1);
    /// ```
    pub fn with_max_age(mut self, max_age_s: Option<f64>) -> Self {
        self.max_age_s = max_age_s;
        self
    }

    /// The maximum age of a command, if any.
    pub fn max_age(&self) -> Option<f64> {
        self.max_age_s
    }

    /// This node's id.
    pub fn me(&self) -> u8 {
        self.me
    }

    /// What it has seen so far.
    pub fn counters(&self) -> &Counters {
        &self.counters
    }

    /// The replay window kept for sender `from`.
    pub fn window(&self, from: u8) -> Option<&ReplayWindow> {
        self.windows.get(usize::from(from))
    }

    /// Decodes and checks one payload; the message if it is valid and for this node. No
    /// clock: the time field is not checked (see [`Receiver::receive_at`]).
    pub fn receive(&mut self, payload: &[u8]) -> Result<Packet, Reject> {
        self.receive_checked(payload, None)
    }

    /// [`Receiver::receive`] at `now` (the receiver's clock, seconds): a command older than
    /// the maximum age ([`Receiver::with_max_age`]) is refused too, before its sequence number
    /// is taken.
    pub fn receive_at(&mut self, payload: &[u8], now: f64) -> Result<Packet, Reject> {
        self.receive_checked(payload, Some(now))
    }

    fn receive_checked(&mut self, payload: &[u8], now: Option<f64>) -> Result<Packet, Reject> {
        self.counters.received += 1;
        let r = self.check(payload, now);
        let c = &mut self.counters;
        match r {
            Ok(_) => c.accepted += 1,
            Err(Reject::Empty | Reject::Truncated { .. }) => c.truncated += 1,
            Err(Reject::TooLong { .. }) => c.too_long += 1,
            Err(Reject::UnknownId(_)) => c.unknown_id += 1,
            Err(Reject::Malformed(_)) => c.malformed += 1,
            Err(Reject::BadTag) => c.bad_tag += 1,
            Err(Reject::BadSender(_)) => c.bad_sender += 1,
            Err(Reject::NotForMe { .. }) => c.not_for_me += 1,
            Err(Reject::Replayed { .. }) => c.replayed += 1,
            Err(Reject::TooOld { .. }) => c.too_old += 1,
            Err(Reject::Stale { .. }) => c.stale += 1,
        }
        r
    }

    fn check(&mut self, payload: &[u8], now: Option<f64>) -> Result<Packet, Reject> {
        let Some(&id) = payload.first() else {
            return Err(Reject::Empty);
        };
        let (authenticated, expected) = Packet::layout(id).ok_or(Reject::UnknownId(id))?;
        let got = payload.len();
        if got < expected {
            return Err(Reject::Truncated { expected, got });
        }
        if got > expected {
            return Err(Reject::TooLong { expected, got });
        }
        let signed_end = if authenticated {
            let end = expected - TAG_BYTES;
            if !self.key.verify(&payload[..end], &payload[end..]) {
                return Err(Reject::BadTag);
            }
            end
        } else {
            expected
        };
        let packet = Packet::decode_body(id, &payload[1..signed_end])
            .ok_or(Reject::UnknownId(id))?
            .map_err(Reject::Malformed)?;
        let from = packet.from();
        if from == 0 || from == self.me {
            return Err(Reject::BadSender(from));
        }
        if let Some(to) = packet.to()
            && to != self.me
            && to != BROADCAST
        {
            return Err(Reject::NotForMe { to });
        }
        if let (Some(a), Some(now), Some(max)) = (packet.auth(), now, self.max_age_s)
            && !matches!(packet, Packet::Confirm(_))
        {
            let age = auth::age(a.time_s, now);
            if age.abs() > max {
                return Err(Reject::Stale {
                    from: a.from,
                    age_s: age.floor() as i32,
                });
            }
        }
        if let Some(a) = packet.auth() {
            let w = &mut self.windows[usize::from(a.from)];
            w.accept(a.seq).map_err(|e| match e {
                ReplayError::Replayed => Reject::Replayed {
                    from: a.from,
                    seq: a.seq,
                },
                ReplayError::TooOld => Reject::TooOld {
                    from: a.from,
                    seq: a.seq,
                },
            })?;
        }
        Ok(packet)
    }
}
