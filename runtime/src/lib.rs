//! The MOOS app framework behind `coug run`: coug's built-in apps and the two ways of
//! running them.
//!
//! Running:
//! - [`scheduler`]: lockstep — every app on one in-process [`bus`] (the `moosdb`
//!   DB core), each at its own AppTick on a virtual [`clock`], with pokes and an `until`
//!   condition; deterministic, as fast as the CPU allows;
//! - [`realtime`]: real time times a warp — each app a client of a TCP MOOSDB, so real
//!   MOOS apps can join;
//! - [`remote`]: one app as a MOOS process (the single-app swap-in mode);
//! - [`antler`]: a mission's ANTLER block resolved into apps (the registry of built-ins);
//! - [`session`]: a whole mission run as a library (load, validate, plan, run lockstep or
//!   real time, report), which `coug run` and the end-to-end tests call; also several
//!   communities in one run ([`session::run_fleet`], the [`fleet`] file).
//!
//! Apps ([`app`] defines the [`App`] trait, [`Mail`], [`Post`], [`Value`]):
//! [`helm`] (pHelmIvP), [`vehicle`] (uSimMarine(V22), pMarinePID(V22), pNodeReporter),
//! [`timer_script`] (uTimerScript), [`logger`] (pLogger, through the `alog` crate),
//! [`sensors`] (uSimSensors: simulated DVL, AHRS, pressure and GPS), [`safety`] (pSafety, the
//! safety supervisor), [`cougars`] (pCougControls, the CoUGARs controllers; uSimCougUV, the
//! CougUV simulator), [`pshare`] (pShare: the UDP bridge between
//! communities), [`hil`] (uSimDevices: the CougUV model behind the device emulators, and the
//! emulators' bench for hardware in the loop without hardware);
//! [`appcasting`] is libMOOS's AppCastingMOOSApp layer around the swap-in apps.
//!
//! [`shared`] holds the objects communities of one run share (a fleet's acoustic channel).
//!
//! After a run: [`summary`] (distance, depth, behaviour lists) and [`plot`] (SVG/PNG).
//!
//! Apps take the MOOS time as an argument; only [`clock::WarpedWallClock`] and the
//! real-time/remote runners read the wall clock.
#![warn(missing_docs)]

pub mod acomms_apps;
pub mod antler;
pub mod app;
pub mod appcasting;
pub mod brokers;
pub mod bus;
pub mod clock;
pub mod contact_mgr;
pub mod cougars;
pub mod driver_apps;
pub mod fleet;
pub mod helm;
pub mod hil;
pub mod hosted;
pub mod logger;
pub mod navigator;
pub mod navreplay;
pub mod node_comms;
pub mod obstacle_mgr;
pub mod plot;
pub mod procinfo;
pub mod pshare;
pub mod realtime;
pub mod remote;
pub mod safety;
pub mod scheduler;
pub mod scope;
pub mod sensors;
pub mod session;
pub mod shared;
pub mod summary;
#[cfg(test)]
mod testing;
pub mod timer_script;
pub mod vehicle;

/// The date-time crate of [`antler::LogTarget`] (so callers need not depend on it).
pub use chrono;

pub use app::{App, AppError, AppResult, Mail, Post, Subscription, Value};
pub use bus::{Bus, BusError, DbHost, LocalDb};
pub use clock::{Clock, VirtualClock, WarpedWallClock};
pub use scheduler::{Outcome, Poke, PokeAt, RunError, Scheduler};
