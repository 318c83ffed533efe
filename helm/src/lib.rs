//! The coug helm: a native interval-programming (IvP) helm compatible with MOOS-IvP's pHelmIvP.
//!
//! - [`ivp`]: decision domains, piecewise-linear objective functions, the ZAIC builders,
//!   the reflector and coupler, and the exact branch-and-bound solver.
//!
//! Everything here is pure: no clock, no sockets, no files. Time enters as an argument.

#![warn(missing_docs)]
// Numeric kernels index several parallel arrays with one loop variable; iterator zips
// would hide which dimension is which.
#![allow(clippy::needless_range_loop)]

pub mod ivp;
