//! The coug helm: a native interval-programming (IvP) helm with pHelmIvP's semantics.
//!
//! - [`ivp`]: the IvP core (re-export of the `ivp` crate).
//! - [`engine`]: [`Helm`], the iteration loop (reference `ivp-helm.md` §4): info buffer, modes,
//!   behaviour run states, flags, postings, all-stop, summary.
//! - [`config`]: the pHelmIvP ProcessConfig block (§4.1).
//! - [`ledger`]: the contact ledger fed by node reports.
//! - [`info_buffer`], [`mode`], [`runstate`], [`macro_expand`], [`allstop`], [`report`]: the
//!   parts of the loop, each after its pHelmIvP counterpart.
//!
//! Everything here is pure: no clock, no sockets, no files. Time enters as an argument.

#![warn(missing_docs)]

pub use ivp;

pub mod allstop;
pub mod config;
pub mod engine;
pub mod info_buffer;
pub mod ledger;
pub mod macro_expand;
pub mod mode;
pub mod plat_model;
pub mod report;
pub mod runstate;
pub mod testing;

/// What BHV_TestFailure does to the helm's process ([`Helm::take_fault`]).
pub use behaviors::Fault;
pub use engine::{Helm, HelmState, Mail, Posting, Value};

/// The conformance tables: every pHelmIvP parameter and posting, and coug's status for each.
#[doc = include_str!("conformance.md")]
pub mod conformance {}
