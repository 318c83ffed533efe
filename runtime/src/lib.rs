//! The in-process MOOS app framework behind `coug run`.
//!
//! - [`antler`]: a mission's ANTLER block resolved into built-in apps;
//! - [`app`]: the [`App`] trait (CMOOSApp's life cycle), [`Mail`], [`Post`], [`Value`];
//! - [`bus`]: the in-process MOOSDB ([`moosdb_client::Database`] core) the apps talk over;
//! - [`clock`]: lockstep ([`VirtualClock`]) or real time times a warp;
//! - [`realtime`]: real-time runs, each app a client of a TCP MOOSDB, with pokes and `until`;
//! - [`remote`]: one app as a MOOS process on a real MOOSDB (single-app swap-in mode);
//! - [`scheduler`]: runs every app at its own AppTick, with pokes and an `until` condition;
//! - [`summary`]: behaviour lists of IVPHELM_SUMMARY and run totals read from an alog;
//! - [`timer_script`]: the built-in uTimerScript;
//! - [`helm`]: the helm engine (pHelmIvP) as an app;
//! - [`logger`]: the built-in pLogger, writing alog files through the `alog` crate;
//! - [`plot`]: track and depth plots of an alog as SVG or PNG (`coug plot`);
//! - [`vehicle`]: the simulator, marine PID and node reporter of the `vehicle` crate as apps.
//!
//! Everything takes the MOOS time as an argument; only [`clock::WarpedWallClock`] reads
//! the wall clock.
#![warn(missing_docs)]

pub mod antler;
pub mod app;
pub mod bus;
pub mod clock;
pub mod helm;
pub mod logger;
pub mod plot;
pub mod realtime;
pub mod remote;
pub mod scheduler;
pub mod summary;
pub mod timer_script;
pub mod vehicle;

pub use app::{App, Mail, Post, Subscription, Value};
pub use bus::{Bus, BusError, DbHost, LocalDb};
pub use clock::{Clock, VirtualClock, WarpedWallClock};
pub use scheduler::{Outcome, Poke, PokeAt, Scheduler};
