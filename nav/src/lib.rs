//! `nav`: a pure sliding-window factor-graph navigator for a small AUV.
#![warn(missing_docs)]

pub mod factors;
pub mod marginal;
pub mod measurements;
pub mod solver;
pub mod state;
