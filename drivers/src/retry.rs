//! The retry rule the drivers' commands share (iDVL's commands, iSeaTrac's send queue): a
//! command is sent, waits for its answer for a time, and is sent again while tries remain; a
//! "busy" answer holds it back for a while and sends it again without spending a try's
//! timeout. Time is the caller's `now`, in seconds; nothing here reads a clock.
//!
//! ```
//! use drivers::retry::{Next, Tries};
//! let mut t = Tries::new("calibrate_gyro");
//! assert_eq!(t.next(0.0, 3.0, 2), Next::Send);
//! t.sent(0.0);
//! assert_eq!(t.next(2.9, 3.0, 2), Next::Wait);
//! assert_eq!(t.next(3.0, 3.0, 2), Next::Send); // late: the second try
//! t.sent(3.0);
//! assert_eq!(t.next(6.0, 3.0, 2), Next::GiveUp);
//! assert_eq!(t.tries(), 2);
//! ```

/// Times within this of a deadline count as at it (sums of 0.05 s steps drift).
const EPS: f64 = 1e-9;

/// What to do with a command at a given time.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Next {
    /// Nothing yet: its answer may still come, or a busy device holds it back.
    Wait,
    /// Send it: never sent, held back long enough after a busy answer, or its answer is late
    /// and tries remain.
    Send,
    /// Its answer is late and every try is spent.
    GiveUp,
}

/// A command and its tries.
#[derive(Debug, Clone, PartialEq)]
pub struct Tries<C> {
    /// The command.
    pub cmd: C,
    /// When it was last sent, while its answer is awaited.
    sent_at: Option<f64>,
    /// Times sent.
    tries: u32,
    /// After a busy answer: not before this time.
    hold_until: Option<f64>,
}

impl<C> Tries<C> {
    /// `cmd`, not sent yet.
    pub fn new(cmd: C) -> Self {
        Tries {
            cmd,
            sent_at: None,
            tries: 0,
            hold_until: None,
        }
    }

    /// Times it was sent.
    pub fn tries(&self) -> u32 {
        self.tries
    }

    /// True while an answer to its last sending is awaited.
    pub fn awaiting(&self) -> bool {
        self.sent_at.is_some()
    }

    /// What to do at `now` when an answer may take `wait_s` seconds and the command may be
    /// sent `max_tries` times in all.
    pub fn next(&self, now: f64, wait_s: f64, max_tries: u32) -> Next {
        match (self.sent_at, self.hold_until) {
            (Some(t), _) if now - t < wait_s - EPS => Next::Wait,
            (Some(_), _) if self.tries >= max_tries => Next::GiveUp,
            (Some(_), _) => Next::Send,
            (None, Some(h)) if now < h - EPS => Next::Wait,
            (None, _) => Next::Send,
        }
    }

    /// It was sent at `now`: one more try, its answer awaited.
    pub fn sent(&mut self, now: f64) {
        self.tries += 1;
        self.sent_at = Some(now);
        self.hold_until = None;
    }

    /// The device answered busy at `now`: send it again from `now + hold_s`.
    pub fn busy(&mut self, now: f64, hold_s: f64) {
        self.sent_at = None;
        self.hold_until = Some(now + hold_s);
    }

    /// The connection it went to is gone: no answer will come; send it again (at once, or
    /// when a busy device's hold ends).
    pub fn unsent(&mut self) {
        self.sent_at = None;
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn busy_holds_back_without_giving_up_and_a_lost_connection_sends_again() {
        let mut t = Tries::new(7u8);
        t.sent(1.0);
        t.busy(1.1, 0.5);
        assert!(!t.awaiting());
        assert_eq!(t.next(1.5, 0.5, 1), Next::Wait);
        // A busy answer is an answer: even with the one try spent it goes again.
        assert_eq!(t.next(1.6, 0.5, 1), Next::Send);
        t.sent(1.6);
        assert_eq!(t.next(2.0, 0.5, 1), Next::Wait);
        assert_eq!(t.next(2.1, 0.5, 1), Next::GiveUp);
        t.unsent();
        assert_eq!(t.next(2.1, 0.5, 1), Next::Send);
        assert_eq!((t.tries(), t.cmd), (2, 7));
    }

    #[test]
    fn deadlines_reached_by_summed_steps_count() {
        let mut t = Tries::new(());
        t.sent(0.0);
        let now = (0..10).fold(0.0, |a, _| a + 0.05);
        assert!(now < 0.5);
        assert_eq!(t.next(now, 0.5, 3), Next::Send);
    }
}
