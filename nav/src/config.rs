//! The navigator's settings and their defaults, with where each default comes from.
//!
//! Noise defaults follow the CoUGARs graphs (`../shared/reference/cougars-vehicle.md` §2) where
//! they make sense for this model, and depart where they do not:
//! - DVL velocity 0.02 m/s (Gen-2 `DVL body velocity`); the A50's figure of merit replaces it
//!   when larger.
//! - AHRS yaw 1 degree (Gen-2 AHRS yaw sigma). Gen-1 used 3 degrees on all three axes, but it
//!   had no bias state: here the slow part of the error is the bias, so the white part is small.
//! - Depth 0.05 m: between Gen-2 (0.02 m) and Gen-1 (0.1 m), for the MS5837 through the Teensy.
//! - GPS 1.5 m per axis times HDOP (at least 1), Huber 1.345 as in Gen-2. Gen-1's default of
//!   10/12/30 m came with a GPS that was also used underwater-adjacent (z > -0.25 m) and no gate.
//! - Heading bias prior 5 degrees ("within several degrees" for calibrated MEMS compasses),
//!   current prior 0.3 m/s.
//! - Unmeasured yaw rate 20 deg/s, for an interval with no gyro sample (the AHRS silent, or its
//!   lines held up by a stalled driver): Gen-2 refuses a keyframe without IMU data before it;
//!   here the dead-reckoning timer's keyframe is kept and its heading change bounded by a
//!   generous turn rate for a 1.5 m/s torpedo-shaped vehicle, so its heading is never free.

/// Settings of [`crate::Navigator`].
#[derive(Debug, Clone, PartialEq)]
pub struct NavConfig {
    /// Keyframes kept in the window (older ones are marginalised).
    pub window_size: usize,
    /// Gauss-Newton iterations at most per update.
    pub max_iterations: usize,
    /// Stop iterating when no state component moves more than this (m, rad, m/s). Position,
    /// depth, bias and current enter the factors linearly and the heading only through the
    /// rotation of a velocity, so after a step of 0.01 the next iteration would move the
    /// estimate by about `0.01^2 * speed * dt / 2` (micrometres): one iteration per keyframe is
    /// the common case, a GPS correction or a heading change takes a second.
    pub step_tolerance: f64,
    /// Minimum time between keyframes, seconds (DVL reports closer than this only update the
    /// held velocity).
    pub min_keyframe_interval_s: f64,
    /// DVL silence (or invalidity) after which keyframes come from the timer, seconds.
    pub dvl_timeout_s: f64,
    /// Timer keyframe period while dead reckoning, seconds.
    pub timer_period_s: f64,
    /// DVL velocity standard deviation, m/s (per axis).
    pub dvl_sigma_mps: f64,
    /// Worst DVL figure of merit accepted, m/s.
    pub max_fom_mps: f64,
    /// Velocity standard deviation while dead reckoning without a DVL, m/s.
    pub dr_sigma_mps: f64,
    /// AHRS yaw white-noise standard deviation, rad.
    pub yaw_sigma_rad: f64,
    /// Gyro heading-increment noise, rad per square-root second.
    pub gyro_sigma_rad_per_sqrt_s: f64,
    /// Yaw rate standard deviation, rad/s, for an interval no gyro sample covers (the AHRS and
    /// the gyro silent, as while the drivers' lines are held up): the heading increment is then
    /// `0 +- this * dt`, so the heading of a dead-reckoning keyframe is never left free (a free
    /// heading made the window singular and its covariance meaningless).
    pub unmeasured_yaw_rate_sigma_radps: f64,
    /// Depth standard deviation, m.
    pub depth_sigma_m: f64,
    /// Largest depth rate accepted between two depths, m/s (a larger step is a jump).
    pub depth_max_rate_mps: f64,
    /// GPS standard deviation per axis at HDOP 1, m.
    pub gps_sigma_m: f64,
    /// Huber threshold on the GPS whitened residual.
    pub gps_huber_k: f64,
    /// Chi-square gate (2 degrees of freedom) on the GPS innovation.
    pub gps_gate_chi2: f64,
    /// After this many consecutive gated fixes, the next one is used anyway (the estimate,
    /// not the GPS, is then assumed wrong; the Huber kernel still bounds each fix).
    pub gps_gate_reset: u32,
    /// Fewest satellites accepted.
    pub gps_min_sats: u32,
    /// Largest HDOP accepted.
    pub gps_max_hdop: f64,
    /// GPS fixes are refused when the estimated depth is larger, m.
    pub gps_max_depth_m: f64,
    /// Heading-bias random walk, rad per square-root second.
    pub bias_rw_rad_per_sqrt_s: f64,
    /// Current random walk, m/s per square-root second.
    pub current_rw_mps_per_sqrt_s: f64,
    /// Initial standard deviations: horizontal position (m), depth (m), heading (rad),
    /// heading bias (rad), current (m/s).
    pub prior_sigma: PriorSigma,
    /// A time this far from the navigator's clock is a clock jump, s.
    pub max_time_jump_s: f64,
    /// Consecutive measurements that confirm a clock jump (the navigator then re-anchors).
    pub clock_jump_confirm: u32,
    /// Attitude silence after which the status is degraded, s.
    pub attitude_timeout_s: f64,
    /// Horizontal sigma above which the status is degraded, m.
    pub degraded_sigma_m: f64,
    /// Measurements of one sensor kept per keyframe interval.
    pub max_per_interval: usize,
}

/// Initial standard deviations of the first keyframe.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct PriorSigma {
    /// Horizontal position around the first fix, m.
    pub position_m: f64,
    /// Depth, m.
    pub depth_m: f64,
    /// Heading, rad.
    pub heading_rad: f64,
    /// Heading bias around zero, rad.
    pub bias_rad: f64,
    /// Current around zero, m/s.
    pub current_mps: f64,
}

impl Default for NavConfig {
    fn default() -> Self {
        NavConfig {
            window_size: 20,
            max_iterations: 3,
            step_tolerance: 1e-2,
            min_keyframe_interval_s: 0.05,
            dvl_timeout_s: 1.0,
            timer_period_s: 0.5,
            dvl_sigma_mps: 0.02,
            max_fom_mps: 0.2,
            dr_sigma_mps: 0.3,
            yaw_sigma_rad: 1.0f64.to_radians(),
            gyro_sigma_rad_per_sqrt_s: 0.005,
            unmeasured_yaw_rate_sigma_radps: 20f64.to_radians(),
            depth_sigma_m: 0.05,
            depth_max_rate_mps: 3.0,
            gps_sigma_m: 1.5,
            gps_huber_k: 1.345,
            gps_gate_chi2: 25.0,
            gps_gate_reset: 25,
            gps_min_sats: 5,
            gps_max_hdop: 5.0,
            gps_max_depth_m: 0.5,
            bias_rw_rad_per_sqrt_s: 2e-5,
            current_rw_mps_per_sqrt_s: 5e-4,
            prior_sigma: PriorSigma {
                position_m: 10.0,
                depth_m: 1.0,
                heading_rad: 0.5,
                bias_rad: 5.0f64.to_radians(),
                current_mps: 0.3,
            },
            max_time_jump_s: 30.0,
            clock_jump_confirm: 10,
            attitude_timeout_s: 2.0,
            degraded_sigma_m: 50.0,
            max_per_interval: 16,
        }
    }
}
