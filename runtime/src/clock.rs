//! Clocks that pace the scheduler: a [`VirtualClock`] for lockstep (no waiting) and a
//! [`WarpedWallClock`] for real time times a warp factor (the only code here that reads
//! the wall clock; used by the binary, never by the lockstep tests).

use std::time::{Duration, Instant};

/// Decides when simulated time `t` is reached.
pub trait Clock {
    /// Waits until MOOS time `t` is due and returns the time to use for the events due
    /// then (`t` itself in lockstep; in real time also `t`, after sleeping).
    fn wait_until(&mut self, t: f64) -> f64;
}

/// Lockstep: every due time is reached at once, as fast as the CPU allows.
#[derive(Debug, Clone, Copy, Default)]
pub struct VirtualClock;

impl Clock for VirtualClock {
    fn wait_until(&mut self, t: f64) -> f64 {
        t
    }
}

/// Real time times a warp: MOOS time `start + warp × elapsed wall seconds`. MOOS apps
/// compute their time as Unix time × warp ([`WarpedWallClock::moos`] starts there), so a
/// run that shares its DB with real MOOS apps agrees with them.
#[derive(Debug, Clone, Copy)]
pub struct WarpedWallClock {
    origin: Instant,
    start: f64,
    warp: f64,
}

impl WarpedWallClock {
    /// A clock at MOOS time `start` now, running `warp` times faster than the wall clock
    /// (`warp` <= 0 or not finite is taken as 1).
    pub fn new(start: f64, warp: f64) -> Self {
        WarpedWallClock {
            origin: Instant::now(),
            start,
            warp: if warp.is_finite() && warp > 0.0 {
                warp
            } else {
                1.0
            },
        }
    }

    /// A clock on MOOS time: Unix time × `warp` (as `MOOSLocalTime` with a warp).
    pub fn moos(warp: f64) -> Self {
        let warp = if warp.is_finite() && warp > 0.0 {
            warp
        } else {
            1.0
        };
        let unix = std::time::SystemTime::now()
            .duration_since(std::time::UNIX_EPOCH)
            .map(|d| d.as_secs_f64())
            .unwrap_or(0.0);
        WarpedWallClock::new(unix * warp, warp)
    }

    /// The warp factor.
    pub fn warp(&self) -> f64 {
        self.warp
    }

    /// The current MOOS time by the wall clock.
    pub fn now(&self) -> f64 {
        self.start + self.origin.elapsed().as_secs_f64() * self.warp
    }
}

impl Clock for WarpedWallClock {
    fn wait_until(&mut self, t: f64) -> f64 {
        let ahead = (t - self.now()) / self.warp;
        if ahead > 0.0 {
            std::thread::sleep(Duration::from_secs_f64(ahead));
        }
        t
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn virtual_clock_never_waits() {
        let mut c = VirtualClock;
        assert_eq!(c.wait_until(1e9), 1e9);
    }

    #[test]
    fn warped_clock_does_not_return_early() {
        // Only a lower bound is checked: never a timing upper bound on a busy machine.
        let mut c = WarpedWallClock::new(1000.0, 400.0);
        assert_eq!(c.wait_until(1002.0), 1002.0);
        assert!(c.now() >= 1002.0 - 1e-9);
        assert_eq!(WarpedWallClock::new(0.0, -3.0).warp(), 1.0);
        let m = WarpedWallClock::moos(10.0);
        assert!(m.now() > 1.7e10, "Unix time times 10: {}", m.now());
    }
}
