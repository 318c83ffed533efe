//! Where an emulator's truth comes from: the [`TruthSource`] trait, the simulator's feed
//! ([`SharedTruth`], for an emulator run in process beside the simulator) and a built-in
//! scenario ([`BoxScenario`], for `coug emulate` on its own).
//!
//! Times are emulator seconds: 0 when the emulator started, growing with its clock (tokio's
//! clock at the edge, so paused in tests). Queries come in non-decreasing time order.

use std::sync::{Arc, Mutex};

use vehicle::angle::angle360;
pub use vehicle::sensors::Truth;

/// Gives the vehicle's true state at an emulator time.
pub trait TruthSource: Send {
    /// The truth at `t` (emulator seconds; `Truth::time` is set to `t`).
    fn truth(&mut self, t: f64) -> Truth;
}

/// A vehicle standing still at the origin, at the surface, heading north.
#[derive(Debug, Clone, Copy, Default)]
pub struct Still;

impl TruthSource for Still {
    fn truth(&mut self, t: f64) -> Truth {
        Truth {
            time: t,
            ..Truth::default()
        }
    }
}

#[derive(Debug, Default)]
struct Fed {
    truth: Option<Truth>,
    /// The emulator time at which the latest truth was first read.
    stamped: Option<f64>,
}

/// Truth fed from outside (the simulator, in process): the latest [`Truth`] handed to
/// [`SharedTruth::feed`], moved on at constant velocity to the time it is read (with
/// [`Truth::advanced_to`]); before any feed, [`Still`]. Clones share the same state.
#[derive(Debug, Clone, Default)]
pub struct SharedTruth {
    inner: Arc<Mutex<Fed>>,
}

impl SharedTruth {
    /// An empty feed.
    pub fn new() -> Self {
        Self::default()
    }

    /// Hands the emulator a new truth (its `time` is the feeder's; only differences matter).
    pub fn feed(&self, truth: Truth) {
        let mut g = self.inner.lock().unwrap_or_else(|e| e.into_inner());
        g.truth = Some(truth);
        g.stamped = None;
    }
}

impl TruthSource for SharedTruth {
    fn truth(&mut self, t: f64) -> Truth {
        let mut g = self.inner.lock().unwrap_or_else(|e| e.into_inner());
        let Some(tr) = g.truth else {
            return Still.truth(t);
        };
        let at = *g.stamped.get_or_insert(t);
        let mut out = tr.advanced_to(tr.time + (t - at).max(0.0));
        out.time = t;
        out
    }
}

/// The built-in scenario of `coug emulate`: a vehicle driving a square, one side north, one
/// east, one south and one west, at constant speed, turning at a bounded rate at the
/// corners; the first side of every lap at the surface (a GPS fix), the other three at
/// `depth` (reached and left at a bounded vertical speed, nose down while diving).
#[derive(Debug, Clone)]
pub struct BoxScenario {
    /// Side of the square, m (100).
    pub side_m: f64,
    /// Speed through the water, m/s (1.5).
    pub speed_mps: f64,
    /// Depth of the submerged sides, m (5).
    pub depth_m: f64,
    /// Largest vertical speed, m/s (0.3).
    pub vertical_mps: f64,
    /// Turn rate at the corners, deg/s (15).
    pub turn_rate_deg_s: f64,
    state: Truth,
    leg: u32,
    along_m: f64,
}

impl Default for BoxScenario {
    fn default() -> Self {
        BoxScenario::new(100.0, 1.5, 5.0)
    }
}

/// The integration step of the scenario, s.
const STEP_S: f64 = 0.01;

impl BoxScenario {
    /// A square of `side_m` at `speed_mps`, submerged sides at `depth_m`.
    pub fn new(side_m: f64, speed_mps: f64, depth_m: f64) -> Self {
        BoxScenario {
            side_m,
            speed_mps,
            depth_m,
            vertical_mps: 0.3,
            turn_rate_deg_s: 15.0,
            state: Truth::default(),
            leg: 0,
            along_m: 0.0,
        }
    }

    /// The side being driven (0 north, 1 east, 2 south, 3 west, then again).
    pub fn leg(&self) -> u32 {
        self.leg
    }

    fn step(&mut self, dt: f64) {
        let s = &mut self.state;
        let target_heading = f64::from(self.leg % 4) * 90.0;
        let target_depth = if self.leg.is_multiple_of(4) {
            0.0
        } else {
            self.depth_m
        };
        // Heading: toward the side's heading at the turn rate (the short way round).
        let err = vehicle::angle::angle180(target_heading - s.heading_deg);
        let max_turn = self.turn_rate_deg_s * dt;
        let turn = err.clamp(-max_turn, max_turn);
        s.yaw_rate_deg_s = turn / dt;
        s.heading_deg = angle360(s.heading_deg + turn);
        // Depth: toward the side's depth at the vertical speed.
        let dz = (target_depth - s.depth).clamp(-self.vertical_mps * dt, self.vertical_mps * dt);
        let vdown = dz / dt;
        let new_pitch = -(vdown.atan2(self.speed_mps));
        s.pitch_rate_rad_s = (new_pitch - s.pitch_rad) / dt;
        s.pitch_rad = new_pitch;
        s.depth = (s.depth + dz).max(0.0);
        s.vel_down_mps = vdown;
        let horiz = self.speed_mps * s.pitch_rad.cos();
        let (sh, ch) = s.heading_deg.to_radians().sin_cos();
        s.vel_east_mps = horiz * sh;
        s.vel_north_mps = horiz * ch;
        s.speed_mps = self.speed_mps;
        s.x += s.vel_east_mps * dt;
        s.y += s.vel_north_mps * dt;
        s.time += dt;
        self.along_m += horiz * dt;
        if self.along_m >= self.side_m {
            self.along_m = 0.0;
            self.leg += 1;
        }
    }
}

impl TruthSource for BoxScenario {
    fn truth(&mut self, t: f64) -> Truth {
        while self.state.time + STEP_S <= t {
            self.step(STEP_S);
        }
        self.state.advanced_to(t.max(self.state.time))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_box_is_driven_side_by_side_with_the_first_at_the_surface() {
        let mut b = BoxScenario::new(30.0, 1.5, 4.0);
        let t0 = b.truth(5.0);
        assert!(t0.depth == 0.0 && t0.heading_deg.abs() < 1e-9 && (t0.y - 7.5).abs() < 0.02);
        // After the first side (20 s) the vehicle turns east and dives.
        let t1 = b.truth(30.0);
        assert_eq!(b.leg(), 1);
        assert!((t1.heading_deg - 90.0).abs() < 1e-6, "{}", t1.heading_deg);
        assert!(t1.depth > 2.0 && t1.pitch_rad < 0.0, "{t1:?}");
        let t2 = b.truth(45.0);
        assert!((t2.depth - 4.0).abs() < 1e-9 && t2.pitch_rad == 0.0);
        // Four sides later it is back near the start, rising to the surface, nose up.
        let t4 = b.truth(86.0);
        assert_eq!(b.leg() % 4, 0);
        assert!(t4.x.abs() < 3.0 && t4.y.abs() < 10.0, "{t4:?}");
        assert!(t4.pitch_rad > 0.0 && t4.vel_down_mps < 0.0, "{t4:?}");
    }

    #[test]
    fn a_fed_truth_moves_on_at_constant_velocity() {
        let shared = SharedTruth::new();
        let mut reader = shared.clone();
        assert_eq!(reader.truth(1.0).x, 0.0);
        shared.feed(Truth {
            time: 500.0,
            x: 10.0,
            vel_east_mps: 2.0,
            ..Truth::default()
        });
        let a = reader.truth(3.0);
        assert_eq!((a.time, a.x), (3.0, 10.0));
        let b = reader.truth(4.5);
        assert_eq!((b.time, b.x), (4.5, 13.0));
    }
}
