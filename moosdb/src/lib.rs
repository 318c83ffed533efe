//! An embeddable MOOSDB that real C++ MOOS clients can use unchanged, and the async MOOS
//! client, on the MOOS V10 wire format of the `moos-wire` crate.
//!
//! - [`db`]: the MOOSDB as a pure core ([`db::Database`]): time is an argument, no I/O, no
//!   async runtime; always available.
//! - `server` (feature `net`, on by default): the tokio TCP edge around the core.
//! - `client` (feature `net`): the asynchronous client (connect, retry, register, notify,
//!   mail, reconnect).
//!
//! Both network halves frame their sockets with `tokio_util::codec` and
//! `moos_wire::MoosCodec`. The wire modules are re-exported here ([`message`], [`packet`],
//! [`codec`], [`error`], [`time`]) so `moosdb::Message` and `moos_wire::Message` are one type.
//!
//! ```
//! use moosdb::db::{Database, DbConfig, DbTime};
//! let _db = Database::new(DbConfig::default(), DbTime { moos: 0.0, mono: 0.0 });
//! let m: moos_wire::Message = moosdb::Message::notify("X", moosdb::Value::Double(1.0), 0.0);
//! assert_eq!(m.key_str(), "X");
//! ```
#![warn(missing_docs)]

#[cfg(feature = "net")]
pub mod client;
pub mod db;
#[cfg(feature = "net")]
pub mod server;

pub use moos_wire::{codec, error, message, packet, time};

#[cfg(feature = "net")]
pub use client::{Client, ClientConfig, ClientError, ConnectionState, MailStream};
pub use db::{ClientId, Database, DbConfig, DbTime, Handshake};
pub use moos_wire::{DataType, DecodeError, Message, MsgType, ReadError, Value};
#[cfg(feature = "net")]
pub use server::{Server, ServerConfig};
