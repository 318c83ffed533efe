//! The vehicle around the helm: marine simulator, controllers, node reports and geodesy.
//!
//! Filled by issue #7.
