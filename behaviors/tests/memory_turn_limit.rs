//! BHV_MemoryTurnLimit as MOOS-IvP a2a9b716: the heading memory, the average, its ZAIC_PEAK
//! and its value rules.

mod support;

use behaviors::{ParamError, Value};
use support::{Bhv, posted, uuv_domain};

fn mtl() -> Bhv {
    Bhv::new("BHV_MemoryTurnLimit", "mtl", uuv_domain())
        .config(&[("memory_time", "10"), ("turn_range", "30")])
}

#[test]
fn defaults_and_constraint() {
    let b = behaviors::create("BHV_MemoryTurnLimit").unwrap();
    assert_eq!(b.default_name(), "mem_turn_limit");
    assert_eq!(b.domain_vars(), ["course"]);
    assert!(b.is_constraint());
}

#[test]
fn the_peak_follows_the_remembered_average_and_the_speed() {
    let mut b = mtl();
    b.num("NAV_HEADING", 80.0).num("NAV_SPEED", 0.75);
    b.run(0.0);
    b.num("NAV_HEADING", 100.0);
    let (f, out) = b.run(2.0);
    let f = f.unwrap();
    // Average of 80 and 100: atan2(sin 80 + sin 100, cos 80 + cos 100) = 90, posted rounded.
    assert_eq!(
        posted(&out, "MEM_HDG_AVG").and_then(Value::as_f64),
        Some(90.0)
    );
    // Peak width 30 * 0.75 / 1.5 = 15, summit delta 0.2, base width 0: 100 at 90,
    // 100 - 0.2 * 10 / 15 = 99.8667 at 100, 99.8 at 105 and 75, 0 beyond.
    let at = |c: u32| f.eval(&[c]).unwrap();
    assert!((at(90) - 100.0).abs() < 1e-6);
    assert!((at(100) - (100.0 - 0.2 * 10.0 / 15.0)).abs() < 1e-6);
    assert!((at(105) - 99.8).abs() < 1e-6);
    assert!((at(75) - 99.8).abs() < 1e-6);
    assert!(at(107).abs() < 1e-6 && at(73).abs() < 1e-6);

    // At 12 s the heading of 0 s is older than 10 s and forgotten (the one of 2 s, exactly
    // 10 s old, is kept): average of 100 and 120 = 110. At 2 m/s the peak width is the whole
    // turn range, 30: 99.8 at 140, 0 at 142.
    b.num("NAV_HEADING", 120.0).num("NAV_SPEED", 2.0);
    let (f, out) = b.run(12.0);
    let f = f.unwrap();
    assert_eq!(
        posted(&out, "MEM_HDG_AVG").and_then(Value::as_f64),
        Some(110.0)
    );
    assert!((f.eval(&[140]).unwrap() - 99.8).abs() < 1e-6);
    assert!(f.eval(&[142]).unwrap().abs() < 1e-6);

    // Below 0.3 m/s the width is 30 * 0.3 / 1.5 = 6 (a hair under in floating point, as in
    // the C++) (a new memory: heading 200 alone): 100 - 0.2 * 5 / 6 at 205, 0 at 207.
    let mut b = mtl();
    b.num("NAV_HEADING", 200.0).num("NAV_SPEED", 0.1);
    let f = b.run(0.0).0.unwrap();
    assert!((f.eval(&[205]).unwrap() - (100.0 - 0.2 * 5.0 / 6.0)).abs() < 1e-6);
    assert!(f.eval(&[207]).unwrap().abs() < 1e-6);
}

#[test]
fn wraps_around_north() {
    let mut b = mtl();
    b.num("NAV_HEADING", 350.0).num("NAV_SPEED", 1.5);
    b.run(0.0);
    b.num("NAV_HEADING", 20.0);
    let f = b.run(1.0).0.unwrap();
    // Average of 350 and 20: 5; peak width 30: 99.8 at 35 and at 335.
    assert!((f.eval(&[5]).unwrap() - 100.0).abs() < 1e-6);
    assert!((f.eval(&[35]).unwrap() - 99.8).abs() < 1e-6);
    assert!((f.eval(&[335]).unwrap() - 99.8).abs() < 1e-6);
}

#[test]
fn unset_parameters_warn_and_missing_nav_is_an_error() {
    let mut b = Bhv::new("BHV_MemoryTurnLimit", "mtl", uuv_domain()).config(&[]);
    b.num("NAV_HEADING", 0.0).num("NAV_SPEED", 1.0);
    let (f, out) = b.run(0.0);
    assert!(f.is_none());
    assert_eq!(
        posted(&out, "BHV_WARNING").and_then(Value::as_str),
        Some("mtl: Variable memory_time not specified")
    );
    b.set("memory_time", "5").unwrap();
    let (_, out) = b.run(0.0);
    assert_eq!(
        posted(&out, "BHV_WARNING").and_then(Value::as_str),
        Some("mtl: Variable turn_range not specified")
    );
    let mut b = Bhv::new("BHV_MemoryTurnLimit", "mtl", uuv_domain())
        .config(&[("memory_time", "5"), ("turn_range", "10")]);
    b.num("NAV_SPEED", 1.0);
    let (f, out) = b.run(0.0);
    assert!(f.is_none());
    assert_eq!(
        out.error.as_deref(),
        Some("No Ownship NAV_HEADING in info_buffer")
    );
    let mut b = Bhv::new("BHV_MemoryTurnLimit", "mtl", uuv_domain())
        .config(&[("memory_time", "5"), ("turn_range", "10")]);
    b.num("NAV_HEADING", 1.0);
    assert_eq!(
        b.run(0.0).1.error.as_deref(),
        Some("No Ownship NAV_SPEED in info_buffer")
    );
}

#[test]
fn values_are_refused_as_the_cpp() {
    let mut b = Bhv::new("BHV_MemoryTurnLimit", "mtl", uuv_domain());
    for (p, v) in [
        ("memory_time", "0"),
        ("turn_range", "0"),
        ("turn_range", "180"),
    ] {
        b.set(p, v).unwrap();
    }
    for (p, v) in [
        ("memory_time", "-1"),
        ("memory_time", "long"),
        ("turn_range", "-0.5"),
        ("turn_range", "180.5"),
        ("turn_range", "1e2"),
    ] {
        assert!(
            matches!(b.set(p, v), Err(ParamError::BadValue { .. })),
            "{p} = {v}"
        );
    }
}
