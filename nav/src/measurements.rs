//! The measurements the navigator takes, their validation, and the counted rejections.
//!
//! Every time is `t_s`, seconds on one clock (MOOS time in the app). Frames:
//! - body: forward, starboard, down (FRD), as the Water Linked A50 reports it;
//! - attitude: NED Euler angles (yaw about down, then pitch, then roll); `yaw_rad` is the compass
//!   heading in radians (0 = north, clockwise positive), so a MOOS `NAV_HEADING` h in degrees is
//!   `h.to_radians()`;
//! - local grid: x east, y north (metres, MOOS's local grid), depth positive down.

/// Where a DVL velocity is measured against.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum VelocityReference {
    /// Bottom lock: velocity over ground (the A50 within its 0.05-50 m altitude).
    Ground,
    /// Water track: velocity through the water; the water current must be added to get the
    /// velocity over ground (the estimator's current state enters the odometry).
    Water,
}

/// One DVL velocity report (A50 `velocity report`).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct DvlVelocity {
    /// Time of validity, seconds.
    pub t_s: f64,
    /// Velocity in the body frame, m/s: `[forward, starboard, down]`.
    pub vel_body_mps: [f64; 3],
    /// The DVL's `velocity_valid` flag.
    pub valid: bool,
    /// Figure of merit, m/s (the A50's own estimate of the velocity's standard deviation).
    pub fom_mps: f64,
    /// What the velocity is measured against.
    pub reference: VelocityReference,
}

/// One AHRS attitude (SeaTrac X150 `ATTITUDE`, converted to radians, declination applied).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Attitude {
    /// Time, seconds.
    pub t_s: f64,
    /// Compass heading in radians: 0 north, clockwise positive (the NED yaw). The estimator
    /// models it as true heading plus a slowly varying bias.
    pub yaw_rad: f64,
    /// Pitch, radians, nose up positive (NED).
    pub pitch_rad: f64,
    /// Roll, radians, starboard down positive (NED).
    pub roll_rad: f64,
}

/// Body angular rates (SeaTrac X150 `AHRS_COMP` gyro, FRD body axes).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct GyroRates {
    /// Time, seconds.
    pub t_s: f64,
    /// Rates about the body axes, rad/s: `[roll rate p, pitch rate q, yaw rate r]`.
    pub rates_body_radps: [f64; 3],
}

/// One depth (pressure already converted to metres of water).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Depth {
    /// Time, seconds.
    pub t_s: f64,
    /// Depth below the surface, metres, positive down.
    pub depth_m: f64,
}

/// One GPS fix, already projected on the local grid.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct GpsFix {
    /// Time, seconds.
    pub t_s: f64,
    /// East of the grid origin, metres.
    pub x_m: f64,
    /// North of the grid origin, metres.
    pub y_m: f64,
    /// Horizontal dilution of precision.
    pub hdop: f64,
    /// Satellites used.
    pub sats: u32,
}

/// Which sensor a rejection counts against.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Sensor {
    /// DVL velocity.
    Dvl,
    /// AHRS attitude.
    Attitude,
    /// Gyro rates.
    Gyro,
    /// Depth.
    Depth,
    /// GPS.
    Gps,
}

impl Sensor {
    /// All sensors, in counter order.
    pub const ALL: [Sensor; 5] = [
        Sensor::Dvl,
        Sensor::Attitude,
        Sensor::Gyro,
        Sensor::Depth,
        Sensor::Gps,
    ];

    fn index(self) -> usize {
        self as usize
    }
}

/// Why a measurement was not used.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Rejection {
    /// A NaN or infinite value.
    NonFinite,
    /// Older than the sensor's last accepted measurement.
    OutOfOrder,
    /// Same time as the sensor's last accepted measurement.
    Duplicate,
    /// Older than the oldest keyframe in the window (too late to use).
    TooOld,
    /// A value outside the sensor's physical range.
    OutOfRange,
    /// A jump no motion can explain (a GPS fix far outside its innovation gate, a depth step).
    Jump,
    /// The DVL flagged its velocity invalid, or its figure of merit is too poor.
    Invalid,
    /// Too few satellites or too large an HDOP.
    PoorFix,
    /// A GPS fix while the vehicle is submerged.
    Submerged,
    /// A time far from the navigator's clock (a clock jump, held until confirmed).
    ClockJump,
    /// More measurements of one sensor in one keyframe interval than the window keeps.
    Crowded,
}

impl Rejection {
    /// All reasons, in counter order.
    pub const ALL: [Rejection; 11] = [
        Rejection::NonFinite,
        Rejection::OutOfOrder,
        Rejection::Duplicate,
        Rejection::TooOld,
        Rejection::OutOfRange,
        Rejection::Jump,
        Rejection::Invalid,
        Rejection::PoorFix,
        Rejection::Submerged,
        Rejection::ClockJump,
        Rejection::Crowded,
    ];

    /// A short lower-case name for reports.
    pub fn name(self) -> &'static str {
        match self {
            Rejection::NonFinite => "non_finite",
            Rejection::OutOfOrder => "out_of_order",
            Rejection::Duplicate => "duplicate",
            Rejection::TooOld => "too_old",
            Rejection::OutOfRange => "out_of_range",
            Rejection::Jump => "jump",
            Rejection::Invalid => "invalid",
            Rejection::PoorFix => "poor_fix",
            Rejection::Submerged => "submerged",
            Rejection::ClockJump => "clock_jump",
            Rejection::Crowded => "crowded",
        }
    }

    fn index(self) -> usize {
        self as usize
    }
}

/// Counts of rejected measurements per sensor and reason (fixed size, never grows).
#[derive(Debug, Clone, Default, PartialEq, Eq)]
pub struct RejectionCounters {
    counts: [[u64; 11]; 5],
}

impl RejectionCounters {
    /// Counts one rejection.
    pub fn count(&mut self, sensor: Sensor, why: Rejection) {
        self.counts[sensor.index()][why.index()] += 1;
    }

    /// Rejections of one sensor for one reason.
    pub fn get(&self, sensor: Sensor, why: Rejection) -> u64 {
        self.counts[sensor.index()][why.index()]
    }

    /// All rejections of one sensor.
    pub fn of_sensor(&self, sensor: Sensor) -> u64 {
        self.counts[sensor.index()].iter().sum()
    }

    /// All rejections for one reason.
    pub fn of_reason(&self, why: Rejection) -> u64 {
        self.counts.iter().map(|c| c[why.index()]).sum()
    }

    /// All rejections.
    pub fn total(&self) -> u64 {
        self.counts.iter().flatten().sum()
    }
}

fn finite(values: &[f64]) -> Result<(), Rejection> {
    if values.iter().all(|v| v.is_finite()) {
        Ok(())
    } else {
        Err(Rejection::NonFinite)
    }
}

/// Largest speed a DVL report may claim, m/s (a small AUV does about 2).
pub const MAX_SPEED_MPS: f64 = 10.0;
/// Largest plausible angular rate, rad/s.
pub const MAX_RATE_RADPS: f64 = 10.0;
/// Depth range accepted, metres (a little above the surface to the A50's depth rating).
pub const DEPTH_RANGE_M: (f64, f64) = (-5.0, 300.0);
/// Largest grid coordinate accepted, metres (a local grid, not the globe).
pub const MAX_GRID_M: f64 = 1.0e7;

impl DvlVelocity {
    /// Checks the values (not the time order, which the navigator checks). `max_fom_mps` is the
    /// worst figure of merit accepted.
    pub fn check(&self, max_fom_mps: f64) -> Result<(), Rejection> {
        finite(&[self.t_s])?;
        finite(&self.vel_body_mps)?;
        if !self.valid {
            return Err(Rejection::Invalid);
        }
        if !self.fom_mps.is_finite() {
            return Err(Rejection::NonFinite);
        }
        if self.fom_mps > max_fom_mps {
            return Err(Rejection::Invalid);
        }
        if self.vel_body_mps.iter().any(|v| v.abs() > MAX_SPEED_MPS) || self.fom_mps < 0.0 {
            return Err(Rejection::OutOfRange);
        }
        Ok(())
    }
}

impl Attitude {
    /// Checks the values.
    pub fn check(&self) -> Result<(), Rejection> {
        finite(&[self.t_s, self.yaw_rad, self.pitch_rad, self.roll_rad])?;
        let tau = std::f64::consts::TAU;
        if self.yaw_rad.abs() > tau
            || self.pitch_rad.abs() > 1.4
            || self.roll_rad.abs() > std::f64::consts::PI
        {
            return Err(Rejection::OutOfRange);
        }
        Ok(())
    }
}

impl GyroRates {
    /// Checks the values.
    pub fn check(&self) -> Result<(), Rejection> {
        finite(&[self.t_s])?;
        finite(&self.rates_body_radps)?;
        if self
            .rates_body_radps
            .iter()
            .any(|r| r.abs() > MAX_RATE_RADPS)
        {
            return Err(Rejection::OutOfRange);
        }
        Ok(())
    }
}

impl Depth {
    /// Checks the values.
    pub fn check(&self) -> Result<(), Rejection> {
        finite(&[self.t_s, self.depth_m])?;
        if self.depth_m < DEPTH_RANGE_M.0 || self.depth_m > DEPTH_RANGE_M.1 {
            return Err(Rejection::OutOfRange);
        }
        Ok(())
    }
}

impl GpsFix {
    /// Checks the values; `min_sats` and `max_hdop` bound the fix quality (the Gen-1 graph
    /// refused fixes with fewer than 5 satellites).
    pub fn check(&self, min_sats: u32, max_hdop: f64) -> Result<(), Rejection> {
        finite(&[self.t_s, self.x_m, self.y_m, self.hdop])?;
        if self.x_m.abs() > MAX_GRID_M || self.y_m.abs() > MAX_GRID_M || self.hdop <= 0.0 {
            return Err(Rejection::OutOfRange);
        }
        if self.sats < min_sats || self.hdop > max_hdop {
            return Err(Rejection::PoorFix);
        }
        Ok(())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn checks_reject_bad_values() {
        let d = DvlVelocity {
            t_s: 1.0,
            vel_body_mps: [1.0, 0.0, 0.0],
            valid: true,
            fom_mps: 0.01,
            reference: VelocityReference::Ground,
        };
        assert_eq!(d.check(0.1), Ok(()));
        let mut bad = d;
        bad.vel_body_mps[1] = f64::NAN;
        assert_eq!(bad.check(0.1), Err(Rejection::NonFinite));
        bad = d;
        bad.valid = false;
        assert_eq!(bad.check(0.1), Err(Rejection::Invalid));
        bad = d;
        bad.fom_mps = 0.5;
        assert_eq!(bad.check(0.1), Err(Rejection::Invalid));
        bad = d;
        bad.vel_body_mps[0] = 40.0;
        assert_eq!(bad.check(0.1), Err(Rejection::OutOfRange));
        let g = GpsFix {
            t_s: 0.0,
            x_m: 1.0,
            y_m: 2.0,
            hdop: 1.0,
            sats: 8,
        };
        assert_eq!(g.check(5, 5.0), Ok(()));
        assert_eq!(
            GpsFix { sats: 3, ..g }.check(5, 5.0),
            Err(Rejection::PoorFix)
        );
        assert_eq!(
            GpsFix {
                x_m: f64::INFINITY,
                ..g
            }
            .check(5, 5.0),
            Err(Rejection::NonFinite)
        );
        assert_eq!(
            Depth {
                t_s: 0.0,
                depth_m: 900.0
            }
            .check(),
            Err(Rejection::OutOfRange)
        );
        let mut c = RejectionCounters::default();
        c.count(Sensor::Gps, Rejection::Jump);
        c.count(Sensor::Gps, Rejection::Jump);
        c.count(Sensor::Dvl, Rejection::Invalid);
        assert_eq!(c.get(Sensor::Gps, Rejection::Jump), 2);
        assert_eq!(c.of_sensor(Sensor::Gps), 2);
        assert_eq!(c.of_reason(Rejection::Invalid), 1);
        assert_eq!(c.total(), 3);
    }
}
