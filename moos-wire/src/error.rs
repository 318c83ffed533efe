//! Typed errors of the wire format and of reading packets from a byte stream.

use thiserror::Error;

/// Why bytes could not be decoded as a MOOS packet or message. Decoding never panics: every
/// malformed input maps to one of these.
#[derive(Debug, Clone, PartialEq, Eq, Error)]
pub enum DecodeError {
    /// The input ended before a field or string it announced.
    #[error("truncated: needed {needed} bytes, only {available} available")]
    Truncated {
        /// Bytes required.
        needed: usize,
        /// Bytes present.
        available: usize,
    },
    /// A packet's length field is smaller than its own 9-byte header.
    #[error("packet length {0} is smaller than the 9-byte header")]
    PacketTooShort(i32),
    /// A packet's length field exceeds the configured cap.
    #[error("packet length {len} exceeds the limit of {max} bytes")]
    PacketTooLarge {
        /// Announced length.
        len: usize,
        /// Configured limit.
        max: usize,
    },
    /// A packet announces a negative number of messages.
    #[error("negative message count {0}")]
    NegativeCount(i32),
    /// A packet announces more messages than its bytes could hold (each takes >= 54 bytes).
    #[error("message count {count} cannot fit in a {len}-byte packet")]
    CountTooLarge {
        /// Announced count.
        count: i32,
        /// Packet length.
        len: usize,
    },
    /// A message's length field is below the 54-byte minimum.
    #[error("message length {declared} is below the 54-byte minimum")]
    BadMessageLength {
        /// Announced length.
        declared: i32,
    },
    /// A message's length field disagrees with the bytes its fields use.
    #[error("message declares {declared} bytes but its fields use {actual}")]
    MessageLengthMismatch {
        /// Announced length.
        declared: i32,
        /// Bytes the fields used.
        actual: usize,
    },
    /// A string length field is negative.
    #[error("negative string length {0}")]
    NegativeStringLength(i32),
    /// Unknown message type byte.
    #[error("unknown message type code 0x{0:02x}")]
    UnknownMessageType(u8),
    /// Unknown data type byte.
    #[error("unknown data type code 0x{0:02x}")]
    UnknownDataType(u8),
    /// The packet's messages do not use exactly the packet's announced length.
    #[error("packet has {0} bytes left over after its messages")]
    TrailingBytes(usize),
}

/// Errors reading packets from a byte stream (a socket).
#[derive(Debug, Error)]
pub enum ReadError {
    /// Socket error.
    #[error("i/o: {0}")]
    Io(#[from] std::io::Error),
    /// Malformed bytes.
    #[error("decode: {0}")]
    Decode(#[from] DecodeError),
    /// The peer closed the connection in the middle of a packet.
    #[error("connection closed inside a packet ({0} bytes pending)")]
    ClosedMidPacket(usize),
}
