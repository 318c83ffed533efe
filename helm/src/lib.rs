//! The coug helm: a native interval-programming (IvP) helm compatible with MOOS-IvP's pHelmIvP.
//!
//! - [`ivp`]: the IvP core (re-export of the `ivp` crate): decision domains, piecewise-linear
//!   objective functions, the ZAIC builders, the reflector and coupler, and the exact solver.
//!
//! Everything here is pure: no clock, no sockets, no files. Time enters as an argument.

#![warn(missing_docs)]

pub use ivp;
