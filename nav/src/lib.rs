//! `nav`: a pure sliding-window factor-graph navigator for a small AUV (issue #14, the core).
//!
//! It fuses a DVL (Water Linked A50: body velocity, bottom lock or water track), an AHRS
//! (SeaTrac X150: yaw, pitch, roll and gyro rates), a depth sensor and GPS (at the surface) into
//! per-keyframe position and heading, plus two slow states: the heading bias of the compass and
//! the 2-D water current. Pure: no I/O, no clock (every time is an argument), no allocation
//! growth with mission length.
//!
//! - [`measurements`]: inputs, validation, counted [`Rejection`]s;
//! - [`state`]: the state layout and frames (x east, y north, depth down; heading NED yaw);
//! - [`factors`]: residuals with analytic Jacobians;
//! - [`solver`]: block-tridiagonal Gauss-Newton and the dense batch reference;
//! - [`marginal`]: Schur-complement marginalisation into a prior;
//! - [`window`]: the [`Navigator`] (keyframes, time association, status, outputs);
//! - [`dive`]: dive reports; [`dead_reckoning`]: the DVL + AHRS baseline;
//! - [`config`]: settings and where their defaults come from;
//! - [`feed`]: the sensor variables (DVL_*, AHRS_*, PRESSURE, GPS_*) into the navigator and the
//!   baseline, shared by the pNavGraph app and the log replay.
#![warn(missing_docs)]

mod chol;
pub mod config;
pub mod dead_reckoning;
pub mod dive;
pub mod factors;
pub mod feed;
pub mod marginal;
pub mod measurements;
pub mod solver;
pub mod state;
pub mod window;

pub use config::NavConfig;
pub use dead_reckoning::DeadReckoner;
pub use dive::{DiveReport, DiveTracker};
pub use feed::{Feed, FeedConfig, Snapshot};
pub use measurements::{
    Attitude, Depth, DvlVelocity, GpsFix, GyroRates, Rejection, RejectionCounters, Sensor,
    VelocityReference,
};
pub use solver::{Prior, solve_batch};
pub use window::{Estimate, Navigator, Status};
