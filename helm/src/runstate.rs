//! Behaviour run states and the duration clock (reference §4.4, §5.5; MOOS
//! `IvPBehavior::isRunnable`, `durationExceeded`, `updateStateDurations`).

use std::fmt;

/// A behaviour's run state.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum RunState {
    /// Before its first iteration (MOOS "").
    New,
    /// Conditions do not hold.
    Idle,
    /// Conditions hold; no objective function this iteration.
    Running,
    /// Running and produced an objective function.
    Active,
    /// Completed (endflags posted); removed after the iteration.
    Completed,
    /// Disabled by a `BHV_ABLE_FILTER` (MOOS "disabled"): no function, no idle or running
    /// hooks.
    Disabled,
}

impl RunState {
    /// The name pHelmIvP reports.
    pub fn as_str(self) -> &'static str {
        match self {
            RunState::New => "",
            RunState::Idle => "idle",
            RunState::Running => "running",
            RunState::Active => "active",
            RunState::Completed => "completed",
            RunState::Disabled => "disabled",
        }
    }
    /// Running or active.
    pub fn is_running(self) -> bool {
        matches!(self, RunState::Running | RunState::Active)
    }
}

impl fmt::Display for RunState {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(self.as_str())
    }
}

/// The duration clock of one behaviour.
#[derive(Debug, Clone, Default)]
pub struct DurationClock {
    started: bool,
    start_time: f64,
    /// Seconds spent idle since the clock (re)started.
    pub idle_time: f64,
    /// Seconds spent running since the clock (re)started.
    pub running_time: f64,
    prev_state: Option<bool>,
    prev_time: f64,
    /// A reset is due on the next runnable check (perpetual behaviours after completing).
    pub reset_pending: bool,
    /// Time stamp of the last `duration_reset` post acted upon.
    pub reset_stamp: Option<f64>,
}

impl DurationClock {
    /// Restarts the clock (MOOS `durationReset`).
    pub fn reset(&mut self) {
        self.reset_pending = false;
        self.started = false;
        self.start_time = -1.0;
        self.idle_time = 0.0;
        self.running_time = 0.0;
    }

    /// Checks the duration at `now` (starting the clock on the first call). Returns
    /// `(exceeded, remaining)`; `duration < 0` never expires.
    pub fn check(&mut self, now: f64, duration: f64, idle_decay: bool) -> (bool, f64) {
        if duration < 0.0 {
            return (false, -1.0);
        }
        let mut elapsed = 0.0;
        if !self.started {
            self.started = true;
            self.start_time = now;
            self.idle_time = 0.0;
        } else {
            elapsed = now - self.start_time;
        }
        if !idle_decay {
            elapsed -= self.idle_time;
        }
        let remaining = (duration - elapsed).max(0.0);
        (elapsed >= duration, remaining)
    }

    /// Remaining seconds for the `duration_status` post of a running iteration.
    pub fn remaining(&self, now: f64, duration: f64, idle_decay: bool) -> f64 {
        let elapsed = if self.started {
            now - self.start_time
        } else {
            0.0
        };
        let mut remaining = duration - elapsed;
        if !idle_decay {
            remaining += self.idle_time;
        }
        remaining.max(0.0)
    }

    /// Accounts the time since the previous call to the previous state (MOOS
    /// `updateStateDurations`); `running` = the state now.
    pub fn account(&mut self, now: f64, running: bool) {
        if self.prev_state.is_some() {
            let dt = now - self.prev_time;
            if running {
                self.running_time += dt;
            } else {
                self.idle_time += dt;
            }
        }
        self.prev_state = Some(running);
        self.prev_time = now;
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn duration_expires_and_idle_decay_matters() {
        let mut d = DurationClock::default();
        assert_eq!(d.check(100.0, 10.0, true), (false, 10.0));
        assert_eq!(d.check(105.0, 10.0, true), (false, 5.0));
        assert!(d.check(110.0, 10.0, true).0);

        let mut d = DurationClock::default();
        d.check(0.0, 10.0, false);
        d.account(0.0, true);
        d.account(4.0, false); // 4 s idle
        assert_eq!(d.check(12.0, 10.0, false), (false, 2.0));
        assert!(d.check(14.0, 10.0, false).0);
        d.reset();
        assert_eq!(d.check(20.0, 10.0, false), (false, 10.0));
        assert_eq!(
            DurationClock::default().check(0.0, -1.0, true),
            (false, -1.0)
        );
    }
}
