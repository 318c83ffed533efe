//! `nav`: a pure sliding-window factor-graph navigator for a small AUV.
#![warn(missing_docs)]

pub mod factors;
pub mod measurements;
pub mod state;
