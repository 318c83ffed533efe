//! Authentication of the messages that stop or move a vehicle (and of their confirmations).
//!
//! Every authenticated frame is `id | body | tag`, where the body starts with an
//! [`Auth`](crate::messages::Auth) header (sender 4 bits, destination 4 bits, sequence number
//! 24 bits) and the tag is the first [`TAG_BYTES`] bytes of HMAC-SHA256 over `id | body`
//! under the fleet's shared key. The cost is 7 bytes per command: 3 of sequence number and 4
//! of tag (the sender and destination ids are addressing every command needs anyway).
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
//!
//! What this does not cover:
//! - A delayed command: a recording of a command the vehicle never heard (jammed, or out of
//!   range) is accepted if played to it later, as long as it has accepted nothing newer from
//!   that sender. A time field (DCCL-style, seconds modulo an hour: 12 bits) in the header
//!   would bound that delay.
//! - One key for the whole fleet: any node holding it can command the others. Per-node keys
//!   would cost nothing on the wire (the sender id picks the key) but a key table on board.
//!
//! Status, status and localisation requests and localisation answers are not authenticated:
//! they command nothing, and a forged one can only mislead the picture the base draws.

use hmac::{Hmac, Mac};
use sha2::Sha256;

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
