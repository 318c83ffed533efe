//! Fault injection: what goes wrong, and when (emulator seconds).
//!
//! A [`FaultPlan`] is a list of [`Fault`]s read from `--fault` specifications, one each:
//!
//! | spec | effect |
//! |---|---|
//! | `noise@T+D[:K]` | from T for D s, extra white noise on the truth the device measures: σ 2 m on position, 0.1 m on depth, 0.2 m/s on velocities, 5° on heading, 2° on pitch and roll, each times K (1) |
//! | `dropout@T+D` | from T for D s the device is silent: no reports, no answers |
//! | `disconnect@T[+D]` | at T the connection (TCP socket or pseudo-terminal) is closed; the device is off for D s (1), then accepts again (a new pseudo-terminal, the link moved to it) |
//! | `garbage@T+D[:N]` | from T for D s, N random bytes a second (200) are mixed into the output, at random places |
//! | `leak@T` | the Teensy's leak sensor reads 1 from T on |
//! | `battery@T:R` | the battery voltage falls by R volts a second from T on (Teensy `$BATTE`, SeaTrac supply) |
//!
//! Every random draw comes from the emulator's seeded generator, and only while a fault is
//! active, so the same seed and plan give the same bytes.
//!
//! A plan's times count from its [`FaultClock`]'s origin on the emulator's clock: the
//! emulator's start by default (`coug emulate --fault`), or a moment set later, once it is
//! known: beside a community (`coug run --emulate`) uSimDevices sets it to the mission's
//! start, so `leak@120` means 120 s of the community's MOOS time after the mission started,
//! as the user reads it in the mission and its log, however long the emulators ran before.

use std::fmt;
use std::sync::Arc;
use std::sync::atomic::{AtomicU64, Ordering};

/// One kind of fault.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum FaultKind {
    /// Extra noise on the truth, the given multiple of the base σ.
    Noise {
        /// Multiple of the base σ of the module docs.
        scale: f64,
    },
    /// The device says nothing.
    Dropout,
    /// The connection is closed and the device is off for the fault's duration.
    Disconnect,
    /// Random bytes in the output.
    Garbage {
        /// Bytes a second.
        bytes_per_s: f64,
    },
    /// The leak sensor reads wet (duration unbounded).
    Leak,
    /// The battery falls at a rate (duration unbounded).
    Battery {
        /// Volts a second.
        volts_per_s: f64,
    },
}

/// A fault and its time window.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Fault {
    /// What happens.
    pub kind: FaultKind,
    /// When it starts, emulator seconds.
    pub start: f64,
    /// How long it lasts, s (infinite for the leak and the battery).
    pub duration: f64,
}

impl Fault {
    /// True while the fault is in effect at `t`.
    pub fn active(&self, t: f64) -> bool {
        t >= self.start && t < self.start + self.duration
    }
}

/// Why a `--fault` specification was refused.
#[derive(Debug, Clone, PartialEq, Eq, thiserror::Error)]
#[error(
    "bad fault {spec:?}: {why} (e.g. noise@30+10:3, dropout@20+5, disconnect@40+2, garbage@10+5:100, leak@60, battery@0:0.01)"
)]
pub struct FaultParseError {
    /// The specification.
    pub spec: String,
    /// What is wrong with it.
    pub why: &'static str,
}

impl std::str::FromStr for Fault {
    type Err = FaultParseError;

    fn from_str(spec: &str) -> Result<Self, Self::Err> {
        let bad = |why| FaultParseError {
            spec: spec.to_string(),
            why,
        };
        let (name, rest) = spec.split_once('@').ok_or(bad("no '@TIME'"))?;
        let (window, value) = match rest.split_once(':') {
            Some((w, v)) => (w, Some(v)),
            None => (rest, None),
        };
        let (start, duration) = match window.split_once('+') {
            Some((s, d)) => (s, Some(d)),
            None => (window, None),
        };
        let num = |s: &str, why| {
            s.trim()
                .parse::<f64>()
                .ok()
                .filter(|v| v.is_finite() && *v >= 0.0)
                .ok_or(bad(why))
        };
        let start = num(start, "the time is not a non-negative number")?;
        let duration = duration
            .map(|d| num(d, "the duration is not a non-negative number"))
            .transpose()?;
        let value = value
            .map(|v| num(v, "the value is not a non-negative number"))
            .transpose()?;
        let need_duration = duration.ok_or(bad("this fault needs '+DURATION'"));
        let (kind, duration) = match name.trim() {
            "noise" => (
                FaultKind::Noise {
                    scale: value.unwrap_or(1.0),
                },
                need_duration?,
            ),
            "dropout" => (FaultKind::Dropout, need_duration?),
            "disconnect" => (FaultKind::Disconnect, duration.unwrap_or(1.0)),
            "garbage" => (
                FaultKind::Garbage {
                    bytes_per_s: value.unwrap_or(200.0),
                },
                need_duration?,
            ),
            "leak" => (FaultKind::Leak, f64::INFINITY),
            "battery" => (
                FaultKind::Battery {
                    volts_per_s: value.ok_or(bad("the battery needs ':VOLTS_PER_SECOND'"))?,
                },
                f64::INFINITY,
            ),
            _ => return Err(bad("unknown fault")),
        };
        Ok(Fault {
            kind,
            start,
            duration,
        })
    }
}

impl fmt::Display for Fault {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        let (s, d) = (self.start, self.duration);
        match self.kind {
            FaultKind::Noise { scale } => write!(f, "noise@{s}+{d}:{scale}"),
            FaultKind::Dropout => write!(f, "dropout@{s}+{d}"),
            FaultKind::Disconnect => write!(f, "disconnect@{s}+{d}"),
            FaultKind::Garbage { bytes_per_s } => write!(f, "garbage@{s}+{d}:{bytes_per_s}"),
            FaultKind::Leak => write!(f, "leak@{s}"),
            FaultKind::Battery { volts_per_s } => write!(f, "battery@{s}:{volts_per_s}"),
        }
    }
}

/// Where a fault plan's time 0 is on the emulator's clock (seconds of the edge's clock),
/// shared between the emulator that reads it and whoever sets it later. While it is pending
/// (no origin yet) no fault is in effect.
#[derive(Debug, Clone)]
pub struct FaultClock(Arc<AtomicU64>);

impl Default for FaultClock {
    /// Origin 0: the plan counts from the emulator's start.
    fn default() -> Self {
        FaultClock::at(0.0)
    }
}

impl FaultClock {
    /// A clock whose origin is `origin` emulator seconds.
    pub fn at(origin: f64) -> Self {
        FaultClock(Arc::new(AtomicU64::new(origin.to_bits())))
    }

    /// A clock without an origin yet: every fault waits for [`FaultClock::start_at`].
    pub fn pending() -> Self {
        FaultClock::at(f64::INFINITY)
    }

    /// Sets the origin: plan time 0 is emulator time `origin` (a value that is not finite
    /// leaves the clock pending).
    pub fn start_at(&self, origin: f64) {
        let o = if origin.is_finite() {
            origin
        } else {
            f64::INFINITY
        };
        self.0.store(o.to_bits(), Ordering::Relaxed);
    }

    /// The origin, emulator seconds (infinite while pending).
    pub fn origin(&self) -> f64 {
        f64::from_bits(self.0.load(Ordering::Relaxed))
    }

    /// The plan's time at emulator time `t` (−∞ while pending: before every fault).
    pub fn plan_time(&self, t: f64) -> f64 {
        let o = self.origin();
        if o.is_finite() {
            t - o
        } else {
            f64::NEG_INFINITY
        }
    }
}

/// The faults of one emulator.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct FaultPlan {
    /// The faults, in any order.
    pub faults: Vec<Fault>,
}

impl FaultPlan {
    /// A plan of these faults.
    pub fn new(faults: Vec<Fault>) -> Self {
        FaultPlan { faults }
    }

    /// Parses `--fault` specifications.
    pub fn parse<S: AsRef<str>>(specs: &[S]) -> Result<Self, FaultParseError> {
        let faults = specs
            .iter()
            .map(|s| s.as_ref().parse())
            .collect::<Result<_, _>>()?;
        Ok(FaultPlan { faults })
    }

    fn active(&self, t: f64) -> impl Iterator<Item = &Fault> {
        self.faults.iter().filter(move |f| f.active(t))
    }

    /// The noise multiple at `t` (0 outside every burst; overlapping bursts add).
    pub fn noise_scale(&self, t: f64) -> f64 {
        self.active(t)
            .map(|f| match f.kind {
                FaultKind::Noise { scale } => scale,
                _ => 0.0,
            })
            .sum()
    }

    /// True while a dropout silences the device.
    pub fn silent(&self, t: f64) -> bool {
        self.active(t).any(|f| f.kind == FaultKind::Dropout)
    }

    /// True while a disconnection keeps the device off.
    pub fn offline(&self, t: f64) -> bool {
        self.active(t).any(|f| f.kind == FaultKind::Disconnect)
    }

    /// The disconnections that start in `(after, upto]`, by start time: the edge closes its
    /// connection once for each.
    pub fn disconnects_between(&self, after: f64, upto: f64) -> usize {
        self.faults
            .iter()
            .filter(|f| f.kind == FaultKind::Disconnect && f.start > after && f.start <= upto)
            .count()
    }

    /// Garbage bytes a second at `t`.
    pub fn garbage_rate(&self, t: f64) -> f64 {
        self.active(t)
            .map(|f| match f.kind {
                FaultKind::Garbage { bytes_per_s } => bytes_per_s,
                _ => 0.0,
            })
            .sum()
    }

    /// True once a leak has started.
    pub fn leak(&self, t: f64) -> bool {
        self.active(t).any(|f| f.kind == FaultKind::Leak)
    }

    /// How far the battery has fallen by `t`, volts.
    pub fn battery_drop_v(&self, t: f64) -> f64 {
        self.faults
            .iter()
            .map(|f| match f.kind {
                FaultKind::Battery { volts_per_s } if t > f.start => volts_per_s * (t - f.start),
                _ => 0.0,
            })
            .sum()
    }
}

#[cfg(test)]
mod clock_tests {
    use super::*;

    #[test]
    fn a_pending_clock_holds_every_fault_until_its_origin_is_set() {
        let plan = FaultPlan::parse(&["leak@10", "dropout@5+1"]).unwrap();
        let c = FaultClock::pending();
        let shared = c.clone();
        assert!(!plan.leak(c.plan_time(1e9)) && !plan.silent(c.plan_time(5.5)));
        assert_eq!(
            plan.disconnects_between(c.plan_time(0.0), c.plan_time(1e9)),
            0
        );
        // The mission starts 3.5 s into the emulator's run: its 10 s is the emulator's 13.5.
        shared.start_at(3.5);
        assert_eq!(c.origin(), 3.5);
        assert!(!plan.leak(c.plan_time(13.4)) && plan.leak(c.plan_time(13.5)));
        assert!(plan.silent(c.plan_time(9.0)) && !plan.silent(c.plan_time(8.4)));
        assert_eq!(FaultClock::default().plan_time(2.0), 2.0);
        c.start_at(f64::NAN);
        assert_eq!(c.plan_time(100.0), f64::NEG_INFINITY);
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn specifications_parse_and_print_back() {
        for s in [
            "noise@30+10:3",
            "dropout@20+5",
            "disconnect@40+2",
            "garbage@10+5:100",
            "leak@60",
            "battery@0:0.01",
        ] {
            let f: Fault = s.parse().unwrap();
            assert_eq!(f.to_string(), s);
        }
        let d: Fault = "disconnect@4".parse().unwrap();
        assert_eq!(d.duration, 1.0);
        let n: Fault = "noise@1+2".parse().unwrap();
        assert_eq!(n.kind, FaultKind::Noise { scale: 1.0 });
        for bad in [
            "noise@1",
            "storm@1+2",
            "leak",
            "dropout@-1+2",
            "battery@3",
            "garbage@1+x",
        ] {
            assert!(bad.parse::<Fault>().is_err(), "{bad}");
        }
    }

    #[test]
    fn the_plan_answers_by_time() {
        let p = FaultPlan::parse(&[
            "dropout@10+5",
            "disconnect@20+2",
            "leak@30",
            "battery@40:0.5",
            "noise@0+1:2",
            "noise@0.5+1",
            "garbage@50+1:300",
        ])
        .unwrap();
        assert!(!p.silent(9.99) && p.silent(10.0) && p.silent(14.9) && !p.silent(15.0));
        assert!(p.offline(21.0) && !p.offline(22.0));
        assert_eq!(p.disconnects_between(19.0, 20.0), 1);
        assert_eq!(p.disconnects_between(20.0, 25.0), 0);
        assert!(!p.leak(29.0) && p.leak(30.0) && p.leak(1e6));
        assert_eq!(p.battery_drop_v(40.0), 0.0);
        assert_eq!(p.battery_drop_v(44.0), 2.0);
        assert_eq!(p.noise_scale(0.7), 3.0);
        assert_eq!(p.noise_scale(1.2), 1.0);
        assert_eq!(p.garbage_rate(50.5), 300.0);
        assert_eq!(p.garbage_rate(51.5), 0.0);
    }
}
