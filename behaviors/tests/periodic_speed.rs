//! BHV_PeriodicSpeed as MOOS-IvP a2a9b716: lazy and busy periods, the countdowns, the busy
//! count, the ZAIC_PEAK and the value rules.

mod support;

use behaviors::{ParamError, Value};
use support::{Bhv, posted, uuv_domain};

fn num(out: &behaviors::Out, var: &str) -> Option<f64> {
    posted(out, var).and_then(Value::as_f64)
}

#[test]
fn defaults_and_constructor_flags() {
    let b = behaviors::create("BHV_PeriodicSpeed").unwrap();
    assert_eq!(b.default_name(), "periodic_speed");
    assert_eq!(b.domain_vars(), ["speed"]);
    assert_eq!(
        b.default_common_params(),
        [
            ("activeflag", "PERIODIC_SPEED=1"),
            ("inactiveflag", "PERIODIC_SPEED=0")
        ]
    );
    // onSetParamComplete posts the busy count, not the settings.
    let b = Bhv::new("BHV_PeriodicSpeed", "ps", uuv_domain()).config(&[]);
    assert_eq!(num(&b.configured, "PS_BUSY_COUNT"), Some(0.0));
    assert!(posted(&b.configured, "BHV_SETTINGS").is_none());
}

#[test]
fn lazy_then_busy_then_lazy_with_countdowns() {
    let mut b = Bhv::new("BHV_PeriodicSpeed", "ps", uuv_domain()).config(&[
        ("period_lazy", "10"),
        ("period_busy", "5"),
        ("period_speed", "1"),
        ("peakwidth", "0.5"),
        ("basewidth", "0.5"),
    ]);
    // Running from 100: lazy, 10 s to the busy period (posted rounded above 1 s).
    let (f, out) = b.start(100.0);
    assert!(f.is_none());
    assert_eq!(num(&out, "PS_PENDING_ACTIVE"), Some(10.0));
    assert_eq!(num(&out, "PS_PENDING_INACTIVE"), Some(0.0));
    // 4.6 s to go: rounded to 5.
    let (_, out) = b.run(105.4);
    assert_eq!(num(&out, "PS_PENDING_ACTIVE"), Some(5.0));
    // 0.5 s to go: posted as is.
    let (_, out) = b.run(109.5);
    assert_eq!(num(&out, "PS_PENDING_ACTIVE"), Some(0.5));
    // 110: busy, count 1.
    let (f, out) = b.run(110.0);
    assert_eq!(num(&out, "PS_BUSY_COUNT"), Some(1.0));
    assert_eq!(num(&out, "PS_PENDING_ACTIVE"), Some(0.0));
    let f = f.unwrap();
    // ZAIC_PEAK summit 1, peak width 0.5, base width 0.5, summit delta 25: 100 at 1 m/s,
    // 100 - 25 * 0.25 / 0.5 = 87.5 at 1.25, 75 at the peak's edge 1.5, 75 - 75 * 0.25 /
    // 0.5 = 37.5 at 1.75, 0 from 2 (normalising to [0, 100] changes nothing).
    let at = |i: u32| f.eval(&[i]).unwrap();
    assert!((at(10) - 100.0).abs() < 1e-6);
    assert!((at(15) - 75.0).abs() < 1e-6);
    assert!((at(5) - 75.0).abs() < 1e-6);
    assert!(at(20).abs() < 1e-6 && at(0).abs() < 1e-6);
    let (_, out) = b.run(112.0);
    assert_eq!(num(&out, "PS_PENDING_INACTIVE"), Some(3.0));
    // 115: the busy period is over.
    let (f, out) = b.run(115.0);
    assert!(f.is_none());
    assert_eq!(num(&out, "PS_PENDING_INACTIVE"), Some(0.0));
    assert_eq!(num(&out, "PS_PENDING_ACTIVE"), Some(0.0));
    let (_, out) = b.run(118.0);
    assert_eq!(num(&out, "PS_PENDING_ACTIVE"), Some(7.0));
    // Idle with reset_upon_running: the countdown shows a whole lazy period.
    let out = b.idle(119.0);
    assert_eq!(num(&out, "PS_PENDING_ACTIVE"), Some(10.0));
    // Running again: lazy from the start.
    let (f, out) = b.start(130.0);
    assert!(f.is_none());
    assert_eq!(num(&out, "PS_PENDING_ACTIVE"), Some(10.0));
}

#[test]
fn without_reset_the_periods_go_on_while_idle_and_initially_busy_starts_busy() {
    let mut b = Bhv::new("BHV_PeriodicSpeed", "ps", uuv_domain()).config(&[
        ("period_lazy", "10"),
        ("period_busy", "5"),
        ("period_speed", "2"),
        ("reset_upon_running", "false"),
        ("initially_busy", "TRUE"),
    ]);
    // Idle from 0: the clock is marked at the first call, busy for 5 s (no count: the
    // count grows only when a lazy period ends).
    let out = b.idle(0.0);
    assert_eq!(num(&out, "PS_PENDING_INACTIVE"), Some(5.0));
    let out = b.idle(5.0);
    assert_eq!(num(&out, "PS_PENDING_INACTIVE"), Some(0.0));
    assert_eq!(num(&out, "PS_PENDING_ACTIVE"), Some(0.0));
    // Idle until 15: busy again, count 1; running at 16 gives the function.
    let out = b.idle(15.0);
    assert_eq!(num(&out, "PS_BUSY_COUNT"), Some(1.0));
    let (f, _) = b.start(16.0);
    // Peak width 0 ignores the summit delta: 100 at 2 m/s only.
    let f = f.unwrap();
    assert!((f.eval(&[20]).unwrap() - 100.0).abs() < 1e-6);
}

#[test]
fn values_are_refused_as_the_cpp() {
    let mut b = Bhv::new("BHV_PeriodicSpeed", "ps", uuv_domain());
    for (p, v) in [
        ("period_speed", "0"),
        ("zaic_basewidth", "0"),
        ("period_peakwidth", "1"),
        ("zaic_summit_delta", "0"),
        ("initially_busy", "False"),
        ("reset_upon_running", "no"),
    ] {
        b.set(p, v).unwrap_or_else(|e| panic!("{p} = {v}: {e}"));
    }
    for (p, v) in [
        ("period_busy", "0"),
        ("period_lazy", "-1"),
        ("period_lazy", "ten"),
        ("period_speed", "-0.1"),
        ("basewidth", "-1"),
        ("peakwidth", "x"),
        ("summit_delta", "-5"),
        ("initially_busy", "yes"),
        ("reset_upon_running", "sometimes"),
    ] {
        assert!(
            matches!(b.set(p, v), Err(ParamError::BadValue { .. })),
            "{p} = {v}"
        );
    }
}
