//! Authentication of the messages that stop or move a vehicle (and of their confirmations).
//!
//! Every authenticated frame is `id | body | tag`, where the body starts with an
//! [`Auth`](crate::messages::Auth) header (sender 4 bits, destination 4 bits, sequence number
//! 24 bits, time sent 12 bits) and the tag is the first [`TAG_BYTES`] bytes of HMAC-SHA256
//! over `id | body` under the fleet's shared key. The cost is 68 bits per command: 24 of
//! sequence number, 12 of time and 32 of tag (the sender and destination ids are addressing
//! every command needs anyway), 9 to 10 bytes once the body is padded to whole bytes.
//!
//! - A stray or hostile modem without the key must guess a 32-bit tag: one chance in 2^32
//!   per packet. At one acoustic packet every 4 s, an attacker expects to need over 270
//!   years of air time for one forgery; the receiver counts every failure
//!   ([`crate::Counters::bad_tag`]), which the fleet can alarm on long before.
//! - A replayed packet (recorded and sent again, or heard twice through a multipath echo) is
//!   refused by the receiver's [`ReplayWindow`] per sender: a sequence number already seen,
//!   or more than [`WINDOW`] behind the highest seen, is refused. Out-of-order arrivals
//!   within the window are accepted once.
//! - The window starts empty: a vehicle that reboots would accept a replay of a packet sent
//!   before its reboot. Change the fleet key per mission (or keep the windows across
//!   reboots) so that old recordings are worthless.
//! - A delayed command (a recording of a command the vehicle never heard, jammed or out of
//!   range, played to it later; or a command held up in a queue): the header carries the
//!   time it was sent, DCCL-style, as whole seconds of the sender's clock modulo an hour (12
//!   bits, [`time_stamp`]). A receiver given a maximum age ([`crate::Receiver::with_max_age`])
//!   refuses a command whose age on its own clock ([`age`]) is beyond it, either way (a
//!   stamp from the future beyond the same bound means a clock off by that much), and counts
//!   it ([`crate::Counters::stale`]). The ages are read within half an hour: a recording
//!   replayed a whole number of hours later passes this check, and the sequence numbers
//!   must stop it (they do unless the vehicle rebooted). Confirmations carry the field too
//!   and are not checked (they move nothing). The field costs 12 bits: 2 more bytes on a
//!   kill, surface, abort or return (11 instead of 9), 1 on the others.
//!
//! What this does not cover:
//! - One key for the whole fleet: any node holding it can command the others. Per-node keys
//!   would cost nothing on the wire (the sender id picks the key) but a key table on board.
//!
//! Status, status and localisation requests and localisation answers are not authenticated:
//! they command nothing, and a forged one can only mislead the picture the base draws.

use hmac::{Hmac, Mac};
use sha2::Sha256;

/// The time field's modulo: an hour of seconds.
pub const TIME_MODULO: u32 = 3600;

/// The time field of a header sent at `now` (seconds of the sender's clock): whole seconds
/// modulo [`TIME_MODULO`]; a time that is not finite gives 0.
///
/// ```
/// assert_eq!(acomms::auth::time_stamp(7199.9), 3599);
/// assert_eq!(acomms::auth::time_stamp(-1.5), 3598);
/// ```
pub fn time_stamp(now: f64) -> u16 {
    if !now.is_finite() {
        return 0;
    }
    now.floor().rem_euclid(f64::from(TIME_MODULO)) as u16
}

/// The age at `now` (the receiver's clock) of a header stamped `stamp`, in seconds, read
/// within half an hour: in `[-1800, 1800)`, negative for a stamp ahead of the clock. A
/// header stamped at `t` and read at `t + d` is `d` to `d + 1` old (the stamp drops the
/// fraction).
///
/// ```
/// use acomms::auth::{age, time_stamp};
/// assert_eq!(age(time_stamp(3595.0), 3605.5), 10.5);
/// assert_eq!(age(time_stamp(100.0), 90.0), -10.0);
/// ```
pub fn age(stamp: u16, now: f64) -> f64 {
    let m = f64::from(TIME_MODULO);
    let a = (now.rem_euclid(m) - f64::from(stamp)).rem_euclid(m);
    if a >= m / 2.0 { a - m } else { a }
}

/// Bytes of truncated HMAC-SHA256 appended to an authenticated frame.
pub const TAG_BYTES: usize = 4;

/// The highest sequence number (24 bits).
pub const MAX_SEQ: u32 = (1 << 24) - 1;

/// How many sequence numbers behind the highest one a receiver still accepts (once each).
pub const WINDOW: u32 = 64;

/// The fleet's shared secret, keyed once (HMAC's inner and outer pads are computed here, so
/// each tag costs two compressions of SHA-256). Its `Debug` shows nothing of the key.
#[derive(Clone)]
pub struct FleetKey {
    mac: Hmac<Sha256>,
}

impl std::fmt::Debug for FleetKey {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str("FleetKey(..)")
    }
}

impl FleetKey {
    /// A key from its bytes (any length; 32 random bytes are right for HMAC-SHA256).
    pub fn new(key: &[u8]) -> Self {
        // HMAC takes a key of any length, so this cannot fail.
        let mac = <Hmac<Sha256> as Mac>::new_from_slice(key).unwrap_or_else(|_| unreachable!());
        Self { mac }
    }

    /// The tag of `data` (the frame's id and body).
    pub fn tag(&self, data: &[u8]) -> [u8; TAG_BYTES] {
        let mut m = self.mac.clone();
        m.update(data);
        let full = m.finalize().into_bytes();
        let mut t = [0; TAG_BYTES];
        t.copy_from_slice(&full[..TAG_BYTES]);
        t
    }

    /// Whether `tag` is the tag of `data` (compared in constant time).
    pub fn verify(&self, data: &[u8], tag: &[u8]) -> bool {
        if tag.len() != TAG_BYTES {
            return false;
        }
        let mut m = self.mac.clone();
        m.update(data);
        m.verify_truncated_left(tag).is_ok()
    }
}

/// Why a sequence number was refused.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum ReplayError {
    /// Already accepted once.
    Replayed,
    /// More than [`WINDOW`] behind the highest accepted.
    TooOld,
}

/// One sender's accepted sequence numbers: the highest, and a bitmap of the [`WINDOW`]
/// before it (as IPsec's and DTLS's anti-replay windows).
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq)]
pub struct ReplayWindow {
    highest: Option<u32>,
    /// Bit `i` set: `highest - i` was accepted (bit 0 is `highest` itself).
    seen: u64,
}

impl ReplayWindow {
    /// An empty window (accepts any first number).
    pub fn new() -> Self {
        Self::default()
    }

    /// The highest number accepted so far.
    pub fn highest(&self) -> Option<u32> {
        self.highest
    }

    /// Whether `seq` would be accepted, without recording it.
    pub fn check(&self, seq: u32) -> Result<(), ReplayError> {
        let Some(h) = self.highest else {
            return Ok(());
        };
        if seq > h {
            return Ok(());
        }
        let back = h - seq;
        if back >= WINDOW {
            return Err(ReplayError::TooOld);
        }
        if self.seen & (1u64 << back) != 0 {
            return Err(ReplayError::Replayed);
        }
        Ok(())
    }

    /// Accepts `seq` if [`check`](Self::check) allows it, and records it.
    pub fn accept(&mut self, seq: u32) -> Result<(), ReplayError> {
        self.check(seq)?;
        match self.highest {
            Some(h) if seq <= h => self.seen |= 1u64 << (h - seq),
            Some(h) => {
                let shift = seq - h;
                self.seen = if shift >= 64 { 0 } else { self.seen << shift };
                self.seen |= 1;
                self.highest = Some(seq);
            }
            None => {
                self.seen = 1;
                self.highest = Some(seq);
            }
        }
        Ok(())
    }
}

/// A sender's sequence numbers: 0, 1, 2, ... up to [`MAX_SEQ`], then none (change the key).
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq)]
pub struct Sequencer {
    next: u32,
}

impl Sequencer {
    /// Starts at `next` (restore it from storage across restarts).
    pub fn starting_at(next: u32) -> Self {
        Self { next }
    }

    /// The next number, or `None` once the 24 bits are spent.
    pub fn take(&mut self) -> Option<u32> {
        if self.next > MAX_SEQ {
            return None;
        }
        let s = self.next;
        self.next += 1;
        Some(s)
    }
}
