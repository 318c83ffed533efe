//! Emulators on a warped clock, for a community running at a MOOS time warp (hardware in the
//! loop without hardware, `coug run` with `MOOSTimeWarp` above 1).
//!
//! The edge ([`crate::transport`]) counts emulator time in wall seconds. Beside a community
//! whose MOOS time runs `k` times faster, every device must count in the same warped
//! seconds, or its report rates, timeouts and delays (the Teensy's ESC arming and command
//! failsafe, the A50's gyro calibration, the GPS's acquisition time) would be `k` times too
//! slow for the apps. [`Warped`] wraps a device so it sees `k·t` wherever the edge passes
//! `t`, and asks the edge to tick `k` times as often (never faster than
//! [`MIN_WALL_PERIOD_S`]: reports due in between go out together at the next tick, as the
//! devices' schedules already allow); [`WarpedTruth`] does the same for a truth source, so
//! the simulator's latest truth is moved on by warped seconds.
//!
//! Fault plans ([`crate::fault::FaultPlan`]) are read by the [`crate::device::Emulator`] on
//! the edge's clock, before the device sees the time: [`faults_to_wall`] turns a plan written
//! in warped seconds (times, durations, rates) into the edge's.

use crate::device::{Device, Situation};
use crate::fault::{FaultKind, FaultPlan};
use crate::truth::{Truth, TruthSource};

/// The shortest tick period a warped device asks of the edge, wall seconds.
pub const MIN_WALL_PERIOD_S: f64 = 0.004;

/// A usable warp: finite and positive, else 1 (what every warped emulator runs at).
pub fn usable_warp(warp: f64) -> f64 {
    usable(warp)
}

fn usable(warp: f64) -> f64 {
    if warp.is_finite() && warp > 0.0 {
        warp
    } else {
        1.0
    }
}

/// `plan`, written in seconds of a clock `warp` times faster than the wall's, in wall
/// seconds: start times and durations divided by the warp, the garbage's bytes and the
/// battery's volts per second multiplied by it (a warp that is not finite and positive is 1).
pub fn faults_to_wall(plan: &FaultPlan, warp: f64) -> FaultPlan {
    let k = usable(warp);
    FaultPlan::new(
        plan.faults
            .iter()
            .map(|f| {
                let mut w = *f;
                w.start /= k;
                w.duration /= k;
                w.kind = match f.kind {
                    FaultKind::Garbage { bytes_per_s } => FaultKind::Garbage {
                        bytes_per_s: bytes_per_s * k,
                    },
                    FaultKind::Battery { volts_per_s } => FaultKind::Battery {
                        volts_per_s: volts_per_s * k,
                    },
                    other => other,
                };
                w
            })
            .collect(),
    )
}

/// A device whose time runs `warp` times faster than the edge's.
pub struct Warped {
    inner: Box<dyn Device>,
    warp: f64,
    /// The Unix time of emulator time 0 (the warped Unix time is `epoch + warp·t`).
    epoch_unix_s: f64,
}

impl Warped {
    /// `inner` on a clock `warp` times faster (a warp that is not finite and positive is
    /// 1); the edge's `unix_s` is taken as `epoch_unix_s + t` and becomes
    /// `epoch_unix_s + warp·t`.
    pub fn new(inner: Box<dyn Device>, warp: f64, epoch_unix_s: f64) -> Self {
        Warped {
            inner,
            warp: usable(warp),
            epoch_unix_s,
        }
    }

    /// The warp in force.
    pub fn warp(&self) -> f64 {
        self.warp
    }

    fn warped(&self, s: &Situation) -> Situation {
        let t = s.t * self.warp;
        let mut truth = s.truth;
        truth.time = t;
        Situation {
            t,
            unix_s: self.epoch_unix_s + t,
            truth,
            ..*s
        }
    }
}

impl Device for Warped {
    fn name(&self) -> &'static str {
        self.inner.name()
    }

    fn period(&self) -> f64 {
        let p = self.inner.period();
        (p / self.warp).max(p.min(MIN_WALL_PERIOD_S))
    }

    fn connected(&mut self, s: &Situation) -> Vec<u8> {
        let w = self.warped(s);
        self.inner.connected(&w)
    }

    fn tick(&mut self, s: &Situation) -> Vec<u8> {
        let w = self.warped(s);
        self.inner.tick(&w)
    }

    fn receive(&mut self, s: &Situation, data: &[u8]) -> Vec<u8> {
        let w = self.warped(s);
        self.inner.receive(&w, data)
    }
}

/// A truth source read at `warp` times the edge's time (the truth's `time` is the warped
/// one, as [`Warped`] gives its device).
pub struct WarpedTruth<T> {
    inner: T,
    warp: f64,
}

impl<T: TruthSource> WarpedTruth<T> {
    /// `inner` read at `warp·t` (a warp that is not finite and positive is 1).
    pub fn new(inner: T, warp: f64) -> Self {
        WarpedTruth {
            inner,
            warp: usable(warp),
        }
    }
}

impl<T: TruthSource> TruthSource for WarpedTruth<T> {
    fn truth(&mut self, t: f64) -> Truth {
        self.inner.truth(t * self.warp)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::truth::SharedTruth;

    /// Reports the time it sees at every tick, and answers with it.
    struct Clock(f64);
    impl Device for Clock {
        fn name(&self) -> &'static str {
            "clock"
        }
        fn period(&self) -> f64 {
            self.0
        }
        fn tick(&mut self, s: &Situation) -> Vec<u8> {
            assert_eq!(s.truth.time, s.t, "the truth is read at the device's time");
            format!("t={} unix={}", s.t, s.unix_s).into_bytes()
        }
        fn receive(&mut self, s: &Situation, _: &[u8]) -> Vec<u8> {
            format!("heard at {}", s.t).into_bytes()
        }
    }

    fn at(t: f64) -> Situation {
        Situation {
            t,
            unix_s: 1000.0 + t,
            truth: Truth {
                time: t,
                ..Truth::default()
            },
            leak: false,
            battery_drop_v: 0.0,
        }
    }

    #[test]
    fn the_device_sees_warped_time_and_ticks_faster_down_to_a_floor() {
        let mut d = Warped::new(Box::new(Clock(1.0)), 8.0, 1000.0);
        assert_eq!(d.period(), 0.125);
        assert_eq!(d.tick(&at(2.0)), b"t=16 unix=1016");
        assert_eq!(d.receive(&at(0.5), b"x"), b"heard at 4");
        // A device ticking every 20 ms at warp 10 asks for 4 ms, not 2.
        assert_eq!(
            Warped::new(Box::new(Clock(0.02)), 10.0, 0.0).period(),
            0.004
        );
        // A device already faster than the floor keeps its own period.
        assert_eq!(
            Warped::new(Box::new(Clock(0.001)), 4.0, 0.0).period(),
            0.001
        );
        // A bad warp is no warp.
        let mut same = Warped::new(Box::new(Clock(0.5)), f64::NAN, 1000.0);
        assert_eq!((same.warp(), same.period()), (1.0, 0.5));
        assert_eq!(same.tick(&at(3.0)), b"t=3 unix=1003");
    }

    #[test]
    fn fault_plans_in_warped_seconds_become_wall_seconds() {
        let plan = FaultPlan::parse(&[
            "leak@80",
            "dropout@40+8",
            "garbage@16+4:100",
            "battery@8:0.5",
        ])
        .unwrap();
        let wall = faults_to_wall(&plan, 8.0);
        assert!(!wall.leak(9.9) && wall.leak(10.0));
        assert!(!wall.silent(4.9) && wall.silent(5.0) && wall.silent(5.9) && !wall.silent(6.0));
        assert_eq!(
            (wall.garbage_rate(2.2), wall.garbage_rate(2.5)),
            (800.0, 0.0)
        );
        // 0.5 V per warped second for 1 wall second: 8 warped seconds, 4 V.
        assert!((wall.battery_drop_v(2.0) - 4.0).abs() < 1e-9);
        assert_eq!(faults_to_wall(&plan, 1.0), plan);
    }

    #[test]
    fn a_fed_truth_moves_on_by_warped_seconds() {
        let feed = SharedTruth::new();
        let mut t = WarpedTruth::new(feed.clone(), 5.0);
        feed.feed(Truth {
            time: 10.0,
            x: 1.0,
            vel_east_mps: 2.0,
            ..Truth::default()
        });
        assert_eq!(t.truth(1.0).x, 1.0);
        // 0.1 s of wall time is half a warped second: 1 m at 2 m/s.
        let later = t.truth(1.1);
        assert!((later.x - 2.0).abs() < 1e-9, "{}", later.x);
        assert!((later.time - 5.5).abs() < 1e-9, "{}", later.time);
    }
}
