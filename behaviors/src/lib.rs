//! Helm behaviours (BHV_Waypoint, BHV_Loiter, depth behaviours, ...) for the coug helm.
//!
//! Filled by the helm-engine and behaviour issues (#4, #5). Each behaviour will be a plain
//! struct that builds an IvP objective function from its parameters and the vehicle state.
