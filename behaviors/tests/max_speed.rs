//! BHV_MaxSpeed as MOOS-IvP a2a9b716: its ZAIC_LEQ, its slack variable, its value rules.

mod support;

use behaviors::{ParamError, Value};
use support::{Bhv, posted, uuv_domain};

#[test]
fn defaults_name_and_constraint() {
    let b = behaviors::create("BHV_MaxSpeed").unwrap();
    assert_eq!(b.default_name(), "maxspd");
    assert_eq!(b.domain_vars(), ["speed"]);
    assert!(b.is_constraint(), "the C++ isConstraint() is true");
    assert_eq!(b.default_duration(), -1.0);
}

#[test]
fn the_objective_function_is_the_cpp_zaic_leq() {
    // Defaults: max_speed 1, basewidth 0.5, on speed:0:4:41 (delta 0.1).
    let mut b = Bhv::new("BHV_MaxSpeed", "maxspd", uuv_domain()).config(&[]);
    b.nav(0.0, 0.0, 0.0, 0.4, 0.0);
    let f = b.run(0.0).0.unwrap();
    // Summit index round(1 / 0.1) = 10; below it utility 100 plus the 1e-5 tie-breaking
    // slope per index: 100 + 10 * 1e-5 at the summit, 100 at 0 m/s.
    assert!((f.eval(&[10]).unwrap() - 100.0001).abs() < 1e-9);
    assert!((f.eval(&[0]).unwrap() - 100.0).abs() < 1e-9);
    // The ramp: base width floor((0.5 + 0.05) / 0.1) = 5 indices, slope -100 / 5 = -20 per
    // index: 1.2 m/s (index 12) is worth 100 - 2 * 20 = 60, 1.5 m/s (index 15) 0.
    assert!((f.eval(&[12]).unwrap() - 60.0).abs() < 1e-9);
    assert!((f.eval(&[15]).unwrap() - 0.0).abs() < 1e-9);
    // Beyond the ramp: 0 with slope -1e-5 per index (pieces are linear in the absolute
    // index, as the C++ writes them): index 20 is worth -20 * 1e-5.
    assert!((f.eval(&[20]).unwrap() + 0.0002).abs() < 1e-9);

    // max_speed 2, tolerance (the basewidth alias) 1: summit index 20, ramp 10 indices of
    // slope -10: 2.3 m/s is worth 70.
    let mut b = Bhv::new("BHV_MaxSpeed", "maxspd", uuv_domain())
        .config(&[("max_speed", "2"), ("tolerance", "1")]);
    b.nav(0.0, 0.0, 0.0, 0.4, 0.0);
    let f = b.run(0.0).0.unwrap();
    assert!((f.eval(&[23]).unwrap() - 70.0).abs() < 1e-9);
    assert!((f.eval(&[30]).unwrap() - 0.0).abs() < 1e-9);
}

#[test]
fn slack_is_posted_idle_and_running_and_missing_speed_warns() {
    let mut b = Bhv::new("BHV_MaxSpeed", "maxspd", uuv_domain())
        .config(&[("max_speed", "1.5"), ("speed_slack_var", "SPD_SLACK")]);
    b.num("NAV_SPEED", 1.2);
    // 1.5 - 1.2 = 0.3 (to within float rounding).
    let out = b.idle(1.0);
    let v = posted(&out, "SPD_SLACK").and_then(Value::as_f64).unwrap();
    assert!((v - 0.3).abs() < 1e-12);
    let (_, out) = b.run(2.0);
    assert!(posted(&out, "SPD_SLACK").is_some());

    let mut b = Bhv::new("BHV_MaxSpeed", "maxspd", uuv_domain()).config(&[]);
    let (f, out) = b.run(0.0);
    assert!(
        f.is_some(),
        "the C++ still builds its function without NAV_SPEED"
    );
    assert_eq!(
        posted(&out, "BHV_WARNING").and_then(Value::as_str),
        Some("maxspd: No ownship SPEED info in info_buffer.")
    );
    let out = b.idle(1.0);
    assert!(posted(&out, "BHV_WARNING").is_some());
}

#[test]
fn values_are_clipped_or_refused_as_the_cpp() {
    let mut b = Bhv::new("BHV_MaxSpeed", "maxspd", uuv_domain());
    // Negative numbers are clipped to 0 (vclip_min).
    for p in ["max_speed", "basewidth", "tolerance"] {
        b.set(p, "-3").unwrap();
    }
    // Not a MOOS number (no exponent, no units), or a variable name with white space:
    // setParam returns false, the helm goes MALCONFIG.
    for (p, v) in [
        ("max_speed", "fast"),
        ("max_speed", "1e1"),
        ("basewidth", "0.5m"),
        ("tolerance", ""),
        ("speed_slack_var", "A B"),
    ] {
        assert!(
            matches!(b.set(p, v), Err(ParamError::BadValue { .. })),
            "{p} = {v}"
        );
    }
    assert!(matches!(
        b.set("speed", "1"),
        Err(ParamError::Unknown { .. })
    ));
}
