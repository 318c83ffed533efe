//! The vehicle around the helm: marine simulator, controllers, node reports and geodesy.
//!
//! Every app of this crate is split in two layers:
//!
//! * a **pure step function** (`step(config, state, inputs, dt) -> (state, outputs)`) that does no
//!   I/O, reads no clock and owns no sockets, and
//! * a small **MOOS adapter** (`on_mail(var, value, time)` plus `iterate(time, &mut postings)`)
//!   that speaks MOOS variable names, so that `coug run` can wire the apps to an in-process
//!   MOOSDB.
//!
//! Configuration mirrors the MOOS ProcessConfig blocks of the C++ apps these replace
//! (`uSimMarineV22`, `pMarinePIDV22`, `pNodeReporter`), read from `(key, value)` string pairs
//! with case-insensitive keys; `Default` gives the MOOS defaults.
//!
//! | module | replaces / reproduces |
//! |---|---|
//! | [`sim`] | `uSimMarineV22` (and the older `uSimMarine`) |
//! | [`pid`] | `pMarinePIDV22` |
//! | [`cougars`] | the CoUGARs Gen-1 depth/pitch/heading controllers, fin mixing and actuators, and their app `pCougControls` ([`cougars::CougarsControl`]) |
//! | [`couguv`] | `uSimCougUV`: the CougUV torpedo model (three fins, a thruster) as a simulator posting uSimMarine's truth |
//! | [`node_report`] | `pNodeReporter` (`NODE_REPORT_LOCAL`) |
//! | [`wormhole`] | uSimMarineV22's wormholes |
//! | [`geodesy`] | MOOS-IvP's UTM-based local grid, without its cross-zone bug |
//! | [`sensors`] | simulated DVL (Water Linked A50), AHRS (SeaTrac X150), pressure (MS5837) and GPS, driven by the simulator's truth |
#![warn(missing_docs)]

pub mod angle;
pub mod config;
pub mod cougars;
pub mod couguv;
pub mod geodesy;
pub mod moos;
pub mod node_report;
pub mod pid;
pub mod polar;
pub mod sensors;
pub mod sim;
pub mod wormhole;

pub use config::ConfigError;
pub use moos::{Posting, Value, ValueRef};

/// What an app reports for its appcast: the workspace's one appcast note type.
pub use appcast::Note as AppcastNote;

/// The most notes an app keeps between two `take_appcast_notes` (the oldest go first).
pub use appcast::MAX_NOTES as MAX_APPCAST_NOTES;

/// Appends `note` to `notes`, dropping the oldest beyond [`MAX_APPCAST_NOTES`].
pub(crate) fn push_note(notes: &mut std::collections::VecDeque<AppcastNote>, note: AppcastNote) {
    if notes.len() >= MAX_APPCAST_NOTES {
        notes.pop_front();
    }
    notes.push_back(note);
}
