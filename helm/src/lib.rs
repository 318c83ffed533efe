//! The coug helm: a native interval-programming (IvP) helm compatible with MOOS-IvP's pHelmIvP.
//!
//! - [`ivp`]: decision domains, piecewise-linear objective functions, the ZAIC builders,
//!   the reflector and coupler, and the exact branch-and-bound solver.
//!
//! Everything here is pure: no clock, no sockets, no files. Time enters as an argument.

pub mod ivp;
