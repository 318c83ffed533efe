//! MOOS time: warp, skew and the skew estimator (reference section 5).
//!
//! `MOOSLocalTime = unix_time × warp` (the warp multiplies the absolute Unix time) and
//! `MOOSTime = MOOSLocalTime + skew`. Pauses such as the reconnect delay shrink with the warp;
//! liveness timers (the 1 s heartbeat, the DB's 5 s silence limit) are never warped.

use std::time::{Duration, SystemTime, UNIX_EPOCH};

use thiserror::Error;

/// Largest accepted warp (`MAX_TIME_WARP`).
pub const MAX_TIME_WARP: f64 = 400.0;

/// A rejected warp factor.
#[derive(Debug, Clone, Copy, PartialEq, Error)]
#[error("time warp {0} is outside (0, 400]")]
pub struct BadWarp(pub f64);

/// A validated time-warp factor.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Warp(f64);

impl Default for Warp {
    fn default() -> Self {
        Warp(1.0)
    }
}

impl Warp {
    /// A warp factor; MOOS accepts `0 < w <= 400`.
    ///
    /// ```
    /// assert!(moos_wire::time::Warp::new(10.0).is_ok());
    /// assert!(moos_wire::time::Warp::new(0.0).is_err());
    /// ```
    pub fn new(w: f64) -> Result<Warp, BadWarp> {
        if w > 0.0 && w <= MAX_TIME_WARP {
            Ok(Warp(w))
        } else {
            Err(BadWarp(w))
        }
    }

    /// The factor.
    pub fn factor(self) -> f64 {
        self.0
    }

    /// MOOS local time for a Unix time: `unix × warp`.
    pub fn local(self, unix: f64) -> f64 {
        unix * self.0
    }

    /// A warped pause (`MOOSPause`): `d / warp` of real time.
    pub fn pause(self, d: Duration) -> Duration {
        d.div_f64(self.0)
    }
}

/// Seconds since the Unix epoch from the system clock.
pub fn unix_now() -> f64 {
    SystemTime::now()
        .duration_since(UNIX_EPOCH)
        .map(|d| d.as_secs_f64())
        .unwrap_or(0.0)
}

/// One step of the client's skew estimator (`UpdateMOOSSkew`, drift detection off).
///
/// `rq` = local time the timing message left, `tx` = DB time it was echoed, `rx` = local time
/// the echo arrived. The measured skew is `0.5·((tx−rx)+(tx−rq))`; it replaces an old skew of
/// 0 and is otherwise blended `0.9·old + 0.1·measured`.
///
/// ```
/// use moos_wire::time::update_skew;
/// assert_eq!(update_skew(0.0, 10.0, 15.0, 10.0), 5.0);
/// ```
pub fn update_skew(old: f64, rq: f64, tx: f64, rx: f64) -> f64 {
    let measured = 0.5 * ((tx - rx) + (tx - rq));
    if old == 0.0 {
        measured
    } else {
        0.9 * old + 0.1 * measured
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn warp_multiplies_absolute_time_and_divides_pauses() {
        let w = Warp::new(4.0).unwrap();
        assert_eq!(w.local(100.0), 400.0);
        assert_eq!(w.pause(Duration::from_secs(1)), Duration::from_millis(250));
        assert_eq!(Warp::new(401.0), Err(BadWarp(401.0)));
        assert!(Warp::new(f64::NAN).is_err());
    }

    #[test]
    fn skew_blends_after_the_first_estimate() {
        let s1 = update_skew(0.0, 100.0, 102.0, 100.0);
        assert_eq!(s1, 2.0);
        let s2 = update_skew(s1, 100.0, 104.0, 100.0);
        assert!((s2 - (0.9 * 2.0 + 0.1 * 4.0)).abs() < 1e-12);
    }
}
