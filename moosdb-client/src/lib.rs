//! The MOOS wire protocol (MOOS V10): a pure packet codec, an async client and an embeddable
//! MOOSDB that real C++ MOOS clients can use unchanged.
//!
//! - [`message`] and [`packet`]: byte-exact `CMOOSMsg` / `CMOOSCommPkt` encoding and
//!   zero-panic decoding with typed [`DecodeError`]s.
//! - [`codec`]: the 32-byte preamble and async packet I/O.
//! - [`time`]: MOOS time, warp and skew.
//! - [`db`]: the MOOSDB as a pure core ([`db::Database`]): time is an argument, no I/O.
//! - [`server`]: the tokio TCP edge around the core.
//! - [`client`]: the asynchronous client (connect, retry, register, notify, mail, reconnect).
//! - [`fuzz`]: the body of the packet fuzz target (cargo-fuzz and the stable bounded run).
//!
//! ```
//! use moosdb_client::{packet, Message, Value};
//! let mut bytes = Vec::new();
//! packet::encode_packet(&[Message::notify("DEPLOY", Value::from("true"), 1.0)], &mut bytes);
//! let back = packet::decode_packet(bytes.into()).unwrap();
//! assert_eq!(back[0].sval_str(), "true");
//! ```
#![warn(missing_docs)]

pub mod client;
pub mod codec;
pub mod db;
pub mod error;
pub mod fuzz;
pub mod message;
pub mod packet;
pub mod server;
pub mod time;

pub use client::{Client, ClientConfig, ClientError, ConnectionState, MailStream};
pub use db::{ClientId, Database, DbConfig, DbTime, Handshake};
pub use error::{DecodeError, ReadError};
pub use message::{DataType, Message, MsgType, Value};
pub use server::{Server, ServerConfig};
