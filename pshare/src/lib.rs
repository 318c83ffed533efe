//! pShare, MOOS's UDP bridge between communities, as pure code (no sockets, no clock):
//!
//! - [`config`]: the `ProcessConfig = pShare` block and `PSHARE_CMD` directives, long and short
//!   forms, into typed shares ([`OutputSpec`], [`InputSpec`]); bad lines are [`LineError`]s;
//!   coug's surface-only radio ([`RadioGate`], `radio_max_depth`).
//! - [`route`]: the routing table ([`RouteTable`]): named and wildcard routes, renaming (prefix
//!   and caret), frequency, duration and share-count limits, with time as an argument.
//! - [`datagram`]: one serialised MOOS message per datagram (the `moos-wire` layout, key
//!   renamed), the 48 KiB limit, the white list, and decoding that refuses garbage with a typed
//!   error instead of panicking.
//!
//! The sockets are the app's (`runtime::pshare`). Facts come from MOOS's `pShare` sources
//! (`Share.cpp`, `Listener.cpp`, `Route.cpp`, `readme.md`); the code is coug's own.
//!
//! ```
//! use pshare::{Config, RouteTable};
//! let (cfg, bad) = Config::from_params([(1, "output", "NAV_X->REMOTE_NAV_X:127.0.0.1:9201")]);
//! assert!(bad.is_empty());
//! let mut table = RouteTable::default();
//! for s in &cfg.outputs { table.add(s, 0.0); }
//! let sends = table.route("NAV_X", "uSimMarine", 1.0);
//! assert_eq!(sends[0].dest_name, "REMOTE_NAV_X");
//! assert_eq!(sends[0].endpoint.to_string(), "127.0.0.1:9201");
//! ```
#![warn(missing_docs)]

pub mod config;
pub mod datagram;
pub mod route;

pub use config::{
    Command, Config, ConfigError, Endpoint, InputSpec, LineError, OutputSpec, RadioGate,
};
pub use datagram::{DatagramError, EncodeError, MAX_UDP_SIZE, RxCounts};
pub use route::{Added, Route, RouteTable, Send};
