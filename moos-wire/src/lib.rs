//! The MOOS wire format (MOOS V10), as pure code: what real C++ MOOS clients and MOOSDBs put
//! on a socket, with no I/O and no async runtime.
//!
//! - [`message`] and [`packet`]: byte-exact `CMOOSMsg` / `CMOOSCommPkt` encoding and
//!   zero-panic decoding with typed [`DecodeError`]s; [`packet::StreamDecoder`] cuts a byte
//!   stream into packets.
//! - [`codec`]: the 32-byte connection preamble, and with the `codec` feature
//!   `codec::MoosCodec`, the packet framing as a `tokio_util::codec::{Decoder, Encoder}`.
//! - [`time`]: MOOS time, warp and skew.
//! - [`fuzz`]: the body of the packet fuzz target (cargo-fuzz and the stable bounded run in
//!   `moosdb/tests/fuzz.rs`, beside the recorded captures it seeds from).
//!
//! The MOOSDB and the async client built on it are in the `moosdb` crate.
//!
//! ```
//! use moos_wire::{packet, Message, Value};
//! let mut bytes = Vec::new();
//! packet::encode_packet(&[Message::notify("DEPLOY", Value::from("true"), 1.0)], &mut bytes);
//! let back = packet::decode_packet(bytes.into()).unwrap();
//! assert_eq!(back[0].sval_str(), "true");
//! ```
#![warn(missing_docs)]

pub mod codec;
pub mod error;
pub mod fuzz;
pub mod message;
pub mod packet;
pub mod time;

#[cfg(feature = "codec")]
pub use codec::MoosCodec;
pub use error::{DecodeError, ReadError};
pub use message::{DataType, Message, MsgType, Value};
