//! `coug base`: the fleet's base station in a terminal (issue #16, point 6).
//!
//! The base joins the base (shoreside) community's MOOSDB as a client and talks to the
//! vehicles through the acoustic network app pAcomms, whose interface it reads and writes:
//!
//! - pAcomms posts, per vehicle, `ACOMMS_VEHICLE = "id=<modem id>,name=<vname>,time=<MOOS
//!   time of the last answer>,x=..,y=..,depth=..,heading=..,speed=..,battery_v=..,health=<hex>,
//!   polls=<n>,answers=<n>,timeouts=<n>"` (no position keys before the first answer), the
//!   vehicle's `NODE_REPORT`, and `ACOMMS_COMMAND_ACK = "to=<id>,cmd=<..>,seq=<n>,state=<queued|
//!   sent|confirmed|timeout>"`;
//! - the base posts `ACOMMS_COMMAND = "to=<modem id>,cmd=<kill|surface|abort|return|goto|loiter|
//!   depth>[,x=<m>,y=<m>][,depth=<m>][,radius=<m>]"` (local metres).
//!
//! Modules: [`fleet`] (pure: the vehicles' state from that mail, ages from the MOOS time
//! given), [`command`] (pure: the typed command line read, checked and turned into the exact
//! `ACOMMS_COMMAND`), [`console`] (pure: keys in, postings out, the confirmation of anything
//! that moves a vehicle, and the ratatui rendering, testable on ratatui's `TestBackend`), and
//! [`terminal`], the one I/O edge (the MOOS client and the crossterm terminal).
#![warn(missing_docs)]

pub mod command;
pub mod console;
pub mod fleet;
pub mod terminal;

/// The variables the base station reads.
pub const READS: [&str; 4] = [
    fleet::VEHICLE_VAR,
    fleet::ACK_VAR,
    "NODE_REPORT",
    "NODE_REPORT_LOCAL",
];
