//! pShare datagrams: one serialised `CMOOSMsg` per UDP datagram (no packet header), the
//! layout of [`moos_wire::message`], the key renamed to the route's destination name.
//!
//! Sending keeps every other field of the mail as the DB delivered it (id, source, source
//! aux, community, time); a message whose serialised size is above [`MAX_UDP_SIZE`] is not
//! sent (`Share.cpp`). Receiving accepts a datagram only when it is exactly one notify
//! message of a double, string or binary value; anything else is an error to count, never a
//! panic. (The C++ listener decodes into a 128 KiB buffer without looking at the datagram's
//! length or the decode's result; coug refuses what does not decode.)

use bytes::Bytes;
use moos_wire::{DataType, DecodeError, Message, MsgType};
use thiserror::Error;

/// Largest serialised message pShare sends (`MAX_UDP_SIZE`, 48 KiB).
pub const MAX_UDP_SIZE: usize = 48 * 1024;

/// Bytes a listener reads per datagram (pShare's receive buffer, 128 KiB): anything longer
/// is cut by the socket and then refused.
pub const RECEIVE_BUFFER: usize = 2 * 64 * 1024;

/// Why a message was not sent.
#[derive(Debug, Clone, PartialEq, Eq, Error)]
pub enum EncodeError {
    /// Serialised, the message is larger than [`MAX_UDP_SIZE`].
    #[error("message of {0} bytes exceeds pShare's {MAX_UDP_SIZE}-byte limit: not forwarded")]
    TooLarge(usize),
}

/// Why a datagram was refused.
#[derive(Debug, Clone, PartialEq, Eq, Error)]
pub enum DatagramError {
    /// The bytes are not a MOOS message.
    #[error("not a MOOS message: {0}")]
    Decode(#[from] DecodeError),
    /// Bytes follow the message.
    #[error("{0} bytes after the message")]
    Trailing(usize),
    /// The message is not a notify (`'N'`).
    #[error("message type {0:?} is not a notify")]
    NotNotify(MsgType),
    /// The message carries no value (data type `'~'`).
    #[error("the message carries no value")]
    NoValue,
}

/// Serialises `msg` under the name `dest_name` into `out` (cleared first).
///
/// ```
/// use moos_wire::{Message, Value};
/// let m = Message::notify("NAV_X", Value::Double(2.5), 10.0);
/// let mut out = Vec::new();
/// pshare::datagram::encode(&m, "REMOTE_NAV_X", &mut out).unwrap();
/// let back = pshare::datagram::decode(out.into()).unwrap();
/// assert_eq!((&back.key[..], back.dval), (&b"REMOTE_NAV_X"[..], 2.5));
/// ```
pub fn encode(msg: &Message, dest_name: &str, out: &mut Vec<u8>) -> Result<(), EncodeError> {
    out.clear();
    let size = msg.encoded_len() - msg.key.len() + dest_name.len();
    if size > MAX_UDP_SIZE {
        return Err(EncodeError::TooLarge(size));
    }
    let mut renamed = msg.clone();
    renamed.key = Bytes::copy_from_slice(dest_name.as_bytes());
    renamed.encode(out);
    Ok(())
}

/// Reads one datagram (its strings share the datagram's buffer).
pub fn decode(datagram: Bytes) -> Result<Message, DatagramError> {
    let (msg, used) = Message::decode(&datagram)?;
    if used != datagram.len() {
        return Err(DatagramError::Trailing(datagram.len() - used));
    }
    if msg.msg_type != MsgType::Notify {
        return Err(DatagramError::NotNotify(msg.msg_type));
    }
    if msg.data_type == DataType::NotSet {
        return Err(DatagramError::NoValue);
    }
    Ok(msg)
}

/// Counts of what a listener received.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq)]
pub struct RxCounts {
    /// Datagrams accepted and posted.
    pub posted: u64,
    /// Datagrams whose name the white list does not let in.
    pub filtered: u64,
    /// Datagrams not posted because pShare registers for their name (loop guard).
    pub looped: u64,
    /// Datagrams that are not one notify message.
    pub garbage: u64,
    /// Datagrams dropped unread because the radio was down (a submerged vehicle, see
    /// [`crate::config::RadioGate`]).
    pub submerged: u64,
}

/// White-list check (`Listener.cpp` `IsWanted`): an empty list lets every name in.
pub fn wanted(white_list: &[String], key: &[u8]) -> bool {
    white_list.is_empty()
        || white_list
            .iter()
            .any(|p| moos_types::text::wildcard_match(p.as_bytes(), key))
}
