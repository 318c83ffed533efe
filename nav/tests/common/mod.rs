//! Shared test helpers.
pub mod truth;
