//! BHV_PeriodicSurface: the dive → ascend → at surface → mark → dive cycle, its speeds,
//! depths and status postings.

mod support;

use behaviors::{Info, ParamError, PeriodicSurface, Phase, Value};
use ivp::IvpFunction;
use support::{Bhv, decide, posted, uuv_domain};

/// The delta mission's block.
fn delta_surface() -> Bhv {
    Bhv::new("BHV_PeriodicSurface", "bhv_periodic_surface", uuv_domain()).config(&[
        ("period", "120"),
        ("zero_speed_depth", "0.5"),
        ("max_time_at_surface", "60"),
        ("ascent_speed", "1.0"),
        ("ascent_grade", "fullspeed"),
    ])
}

/// Speed and depth decided by the function alone.
fn speed_depth(b: &Bhv, f: IvpFunction) -> (f64, f64) {
    let d = decide(&b.domain, &[("psf", f, 1000.0)]);
    (d.get("speed").unwrap(), d.get("depth").unwrap())
}

#[test]
fn full_cycle_dive_ascend_surface_mark_dive() {
    let mut b = delta_surface();
    // Diving at 7 m: the first running iteration is a mark, the period starts.
    b.nav(0.0, 0.0, 90.0, 1.3, 7.0);
    let (f, out) = b.run(10.0);
    assert!(f.is_none());
    assert_eq!(posted(&out, "PENDING_SURFACE"), Some(&Value::Double(120.0)));
    // Waiting: no opinion, the countdown and TIME_AT_SURFACE = 0.
    let (f, out) = b.run(70.0);
    assert!(f.is_none());
    assert_eq!(posted(&out, "PENDING_SURFACE"), Some(&Value::Double(60.0)));
    assert_eq!(posted(&out, "TIME_AT_SURFACE"), Some(&Value::Double(0.0)));
    assert!(posted(&out, "PERIODIC_ASCEND").is_none());
    let (f, _) = b.run(129.75);
    assert!(f.is_none(), "0.25 s of the period left");

    // The period is up: ascend to the surface at the ascent speed.
    let (f, out) = b.run(130.0);
    assert_eq!(
        posted(&out, "PERIODIC_ASCEND"),
        Some(&Value::String("true".into()))
    );
    assert_eq!(speed_depth(&b, f.unwrap()), (1.0, 0.0));
    // fullspeed: the same speed all the way up.
    b.nav(10.0, 0.0, 90.0, 1.0, 3.0);
    let (f, out) = b.run(132.0);
    assert!(posted(&out, "PERIODIC_ASCEND").is_none(), "posted once");
    assert_eq!(speed_depth(&b, f.unwrap()), (1.0, 0.0));

    // At zero_speed_depth: at the surface, speed 0 at depth 0.
    b.nav(12.0, 0.0, 90.0, 1.0, 0.5);
    let (f, out) = b.run(134.0);
    assert_eq!(
        posted(&out, "PERIODIC_ASCEND"),
        Some(&Value::String("false".into()))
    );
    assert_eq!(posted(&out, "TIME_AT_SURFACE"), Some(&Value::Double(0.0)));
    assert_eq!(speed_depth(&b, f.unwrap()), (0.0, 0.0));
    b.nav(12.0, 0.0, 90.0, 0.0, 0.0);
    let (f, out) = b.run(137.6);
    assert_eq!(posted(&out, "TIME_AT_SURFACE"), Some(&Value::Double(4.0)));
    assert_eq!(speed_depth(&b, f.unwrap()), (0.0, 0.0));

    // A GPS fix (new value of the mark variable): the cycle ends, the vehicle may dive.
    b.text("GPS_UPDATE_RECEIVED", "RCVD_1");
    let (f, _) = b.run(138.0);
    assert!(f.is_none());
    let (f, out) = b.run(139.0);
    assert!(f.is_none(), "waiting again");
    assert_eq!(posted(&out, "TIME_AT_SURFACE"), Some(&Value::Double(0.0)));
    assert_eq!(posted(&out, "PENDING_SURFACE"), Some(&Value::Double(119.0)));
    // The same value again is no mark: the next ascent comes 120 s after the fix.
    b.nav(50.0, 0.0, 90.0, 1.3, 7.0);
    assert!(b.run(257.0).0.is_none());
    let (f, out) = b.run(258.0);
    assert!(f.is_some());
    assert_eq!(
        posted(&out, "PERIODIC_ASCEND"),
        Some(&Value::String("true".into()))
    );
}

#[test]
fn a_fresh_posting_of_the_same_fix_is_no_mark_as_in_moos() {
    // MOOS `checkForMarking` compares the mark variable's value with the last one seen; it
    // does not look at the posting time. A GPS driver that re-posts an identical value does
    // not end the cycle; a new value does.
    let mut b = delta_surface();
    b.nav(0.0, 0.0, 90.0, 1.3, 7.0);
    b.post(0.0, "GPS_UPDATE_RECEIVED", "RCVD_1");
    assert!(b.run(0.0).0.is_none(), "first iteration: a mark");
    assert!(b.run(1.0).0.is_none(), "first value seen: a mark at 1 s");
    b.nav(0.0, 0.0, 90.0, 0.0, 0.0);
    let (f, _) = b.run(121.0);
    assert!(f.is_some(), "the period is up");
    b.post(122.0, "GPS_UPDATE_RECEIVED", "RCVD_1");
    assert_eq!(b.info.age("GPS_UPDATE_RECEIVED"), Some(0.0), "fresh mail");
    let (f, out) = b.run(122.0);
    assert!(f.is_some(), "same value re-posted: still at the surface");
    assert_eq!(posted(&out, "TIME_AT_SURFACE"), Some(&Value::Double(1.0)));
    b.post(123.0, "GPS_UPDATE_RECEIVED", "RCVD_2");
    let (f, _) = b.run(123.0);
    assert!(f.is_none(), "a new value is a mark");
    assert!(b.run(124.0).0.is_none(), "waiting again");
}

#[test]
fn ascent_grades_taper_the_speed() {
    let run = |grade: &str, depth: f64| -> f64 {
        let mut b = Bhv::new("BHV_PeriodicSurface", "psf", uuv_domain()).config(&[
            ("period", "10"),
            ("ascent_grade", grade),
            ("ascent_speed", "current"),
        ]);
        b.nav(0.0, 0.0, 0.0, 2.0, 10.0);
        b.run(0.0);
        assert!(b.run(10.0).0.is_some(), "ascent starts at 10 m, 2 m/s");
        b.nav(0.0, 0.0, 0.0, 1.7, depth);
        let f = b.run(11.0).0.unwrap();
        speed_depth(&b, f).0
    };
    assert_eq!(run("linear", 5.0), 1.0);
    assert_eq!(run("linear", 2.5), 0.5);
    assert_eq!(run("quadratic", 5.0), 0.5);
    assert_eq!(run("quasi", 10.0), 2.0);
    assert_eq!(run("fullspeed", 2.5), 2.0);
    assert_eq!(
        run("linear", 12.0),
        2.0,
        "deeper than the start: full speed"
    );
}

#[test]
fn surface_timeout_restarts_the_period() {
    let mut b = delta_surface();
    b.nav(0.0, 0.0, 0.0, 1.0, 5.0);
    b.run(0.0);
    b.run(120.0);
    b.nav(0.0, 0.0, 0.0, 0.0, 0.2);
    assert!(b.run(125.0).0.is_some(), "at the surface");
    assert!(b.run(184.0).0.is_some(), "59 s at the surface");
    let (f, out) = b.run(185.0);
    assert!(f.is_none());
    assert_eq!(
        posted(&out, "PSF_AT_SURFACE_TIMEOUT"),
        Some(&Value::String("Timestamp=185.00".into()))
    );
    assert_eq!(posted(&out, "TIME_AT_SURFACE"), Some(&Value::Double(60.0)));
    let (f, out) = b.run(186.0);
    assert!(f.is_none());
    assert_eq!(posted(&out, "PENDING_SURFACE"), Some(&Value::Double(119.0)));
}

#[test]
fn idle_start_counts_the_period_from_the_first_dive_and_numeric_marks() {
    let mut b = delta_surface();
    b.nav(0.0, 0.0, 0.0, 1.0, 0.0);
    let out = b.idle(0.0);
    assert!(out.error.is_none());
    // Submerged while idle: the period starts then.
    b.nav(0.0, 0.0, 0.0, 1.0, 3.0);
    let out = b.idle(5.0);
    assert_eq!(posted(&out, "PENDING_SURFACE"), Some(&Value::Double(120.0)));
    let out = b.idle(65.0);
    assert_eq!(posted(&out, "PENDING_SURFACE"), Some(&Value::Double(60.0)));
    // Running from 100: no extra mark, ascent at 125.
    assert!(b.run(100.0).0.is_none());
    assert!(b.run(124.0).0.is_none());
    assert!(b.run(125.0).0.is_some());
    // A numeric mark variable works too.
    b.num("GPS_UPDATE_RECEIVED", 1.0);
    assert!(b.run(126.0).0.is_none());
    assert!(b.run(127.0).0.is_none(), "waiting after the mark");
    b.num("GPS_UPDATE_RECEIVED", 2.0);
    assert!(b.run(246.0).0.is_none(), "a new mark at 246");
    assert!(b.run(247.0).0.is_none());
    assert!(b.run(366.0).0.is_some());
}

#[test]
fn acomms_marks_extend_the_period_up_to_a_limit() {
    let mut b = delta_surface();
    b.set("acomms_mark_variable", "ACOMMS_RCVD,30,45").unwrap();
    b.nav(0.0, 0.0, 0.0, 1.0, 5.0);
    b.run(0.0);
    b.text("ACOMMS_RCVD", "a");
    assert!(b.run(1.0).0.is_none());
    b.text("ACOMMS_RCVD", "b");
    assert!(b.run(2.0).0.is_none());
    b.text("ACOMMS_RCVD", "c");
    assert!(b.run(3.0).0.is_none());
    // 120 + min(30 + 30 + 30, 45) = 165.
    assert!(b.run(164.0).0.is_none());
    assert!(b.run(165.0).0.is_some());
}

#[test]
fn missing_nav_is_an_error_and_bad_values_are_rejected() {
    let mut b = delta_surface();
    b.num("NAV_SPEED", 1.0);
    let (f, out) = b.run(0.0);
    assert!(f.is_none());
    assert!(out.error.as_deref().unwrap().contains("NAV_DEPTH"));
    assert_eq!(
        posted(&out, "PENDING_SURFACE"),
        Some(&Value::String("ERROR".into()))
    );

    let mut b = Bhv::new("BHV_PeriodicSurface", "p", uuv_domain());
    for (p, v) in [
        ("period", "0"),
        ("period", "soon"),
        ("mark_variable", ""),
        ("ascent_speed", "-1"),
        ("ascent_speed", "fast"),
        ("zero_speed_depth", "-0.5"),
        ("max_time_at_surface", "x"),
        ("ascent_grade", "steep"),
        ("acomms_mark_variable", "A,30"),
        ("acomms_mark_variable", "A,30,10"),
        ("acomms_mark_variable", "A B,30,40"),
    ] {
        assert!(
            matches!(b.set(p, v), Err(ParamError::BadValue { .. })),
            "{p} = {v}"
        );
    }
    assert!(matches!(
        b.set("periodd", "3"),
        Err(ParamError::Unknown { .. })
    ));
    // The defaults, as in MOOS-IvP.
    let d = PeriodicSurface::new();
    assert_eq!(
        (d.period, d.max_time_at_surface, d.ascent_speed),
        (300.0, 300.0, -1.0)
    );
    assert_eq!(d.mark_variable, "GPS_UPDATE_RECEIVED");
    assert_eq!(d.phase(), Phase::Waiting);
}
