//! BHV_ConstantDepth and BHV_MaxDepth: their objective functions in user terms.

mod support;

use behaviors::{Emit, ParamError, Value};
use support::{Bhv, at_depth, decide, posted, uuv_domain};

/// The delta mission's constant-depth block.
fn delta_constant_depth() -> Bhv {
    Bhv::new("BHV_ConstantDepth", "bhv_const_depth", uuv_domain()).config(&[
        ("depth", "50"),
        ("peakwidth", "8"),
        ("basewidth", "12"),
        ("summitdelta", "10"),
    ])
}

/// The delta mission's max-depth block.
fn delta_max_depth() -> Bhv {
    Bhv::new("BHV_MaxDepth", "maxdepth", uuv_domain())
        .config(&[("max_depth", "7"), ("tolerance", "1")])
}

#[test]
fn constant_depth_peaks_at_the_configured_depth_with_its_widths() {
    let mut b = delta_constant_depth();
    b.nav(0.0, 0.0, 0.0, 1.0, 3.0);
    let (f, out) = b.run(1.0);
    let f = f.expect("a depth function");
    assert!(out.error.is_none());
    // Summit: 50 m at full utility.
    assert_eq!(at_depth(&f, 50), 100.0);
    // The plateau is 8 m either side, dropping by summitdelta (10) to its edges.
    assert!((at_depth(&f, 42) - 90.0).abs() < 1e-6);
    assert!((at_depth(&f, 58) - 90.0).abs() < 1e-6);
    assert!(at_depth(&f, 46) > at_depth(&f, 44));
    // Then a 12 m ramp down to nothing: 36 m is halfway, 30 m and shallower worth nothing.
    assert!((at_depth(&f, 36) - 45.0).abs() < 1e-6);
    assert_eq!(at_depth(&f, 30), 0.0);
    assert_eq!(at_depth(&f, 5), 0.0);
    // Alone, it decides 50 m.
    let d = decide(&b.domain, &[("cd", f, 100.0)]);
    assert_eq!(d.get("depth"), Some(50.0));
}

#[test]
fn constant_depth_defaults_mismatch_and_missing_depth() {
    let mut b = Bhv::new("BHV_ConstantDepth", "cd", uuv_domain())
        .config(&[("depth", "20"), ("depth_mismatch_var", "DEPTH_MISS")]);
    assert_eq!(
        b.bhv.default_duration(),
        0.0,
        "completes at once without a duration"
    );
    b.nav(0.0, 0.0, 0.0, 1.0, 23.5);
    let (f, out) = b.run(1.0);
    let f = f.unwrap();
    assert_eq!(posted(&out, "DEPTH_MISS"), Some(&Value::Double(3.5)));
    // Defaults: plateau 3 m with a 50 drop, base 100 m.
    assert!((at_depth(&f, 20) - 100.0).abs() < 1e-6);
    assert!(
        (at_depth(&f, 23) - 50.0).abs() < 1e-6,
        "{}",
        at_depth(&f, 23)
    );
    assert!(at_depth(&f, 123) < 1e-6);
    assert!((at_depth(&f, 73) - 25.0).abs() < 1e-6);
    assert!(at_depth(&f, 60) > 0.0);

    // No NAV_DEPTH: a warning, and the function all the same.
    let mut b = Bhv::new("BHV_ConstantDepth", "cd", uuv_domain()).config(&[("depth", "20")]);
    b.num("NAV_X", 0.0);
    let (f, out) = b.run(1.0);
    assert!(f.is_some());
    assert!(matches!(posted(&out, "BHV_WARNING"), Some(Value::String(s)) if s.contains("DEPTH")));
}

#[test]
fn constant_depth_parameter_values() {
    let mut b = Bhv::new("BHV_ConstantDepth", "cd", uuv_domain());
    for (p, v) in [
        ("depth", "deep"),
        ("peakwidth", "3m"),
        ("summitdelta", ""),
        ("depth_mismatch_var", "A B"),
    ] {
        assert!(
            matches!(b.set(p, v), Err(ParamError::BadValue { .. })),
            "{p} = {v} must be rejected"
        );
    }
    assert!(matches!(
        b.set("depthh", "3"),
        Err(ParamError::Unknown { .. })
    ));
    // As in MOOS-IvP, a negative depth is clipped to the surface, summitdelta into 0..100.
    b.set("depth", "-5").unwrap();
    b.set("summitdelta", "400").unwrap();
    b.nav(0.0, 0.0, 0.0, 1.0, 0.0);
    let f = b.run(0.0).0.unwrap();
    let d = decide(&b.domain, &[("cd", f, 100.0)]);
    assert_eq!(d.get("depth"), Some(0.0));
}

#[test]
fn constant_depth_without_a_depth_domain_stays_silent() {
    let surface = ivp::Domain::parse_specs(["course:0:359:360", "speed:0:4:41"]).unwrap();
    let mut b = Bhv::new("BHV_ConstantDepth", "cd", surface).config(&[("depth", "5")]);
    b.nav(0.0, 0.0, 0.0, 1.0, 0.0);
    let (f, out) = b.run(0.0);
    assert!(f.is_none());
    assert!(out.error.is_none(), "pHelmIvP keeps it idle: no error");
}

#[test]
fn max_depth_leaves_shallower_depths_free_and_penalizes_deeper() {
    let mut b = delta_max_depth();
    b.nav(0.0, 0.0, 0.0, 1.0, 3.0);
    let (f, out) = b.run(1.0);
    let f = f.unwrap();
    assert!(out.error.is_none() && out.emits.is_empty());
    // Every depth from the surface to 7 m is (almost) fully preferred, ties going deeper.
    for d in 0..=7 {
        assert!((at_depth(&f, d) - 100.0).abs() < 0.01, "depth {d}");
    }
    assert!(at_depth(&f, 7) > at_depth(&f, 6));
    assert!(at_depth(&f, 1) > at_depth(&f, 0));
    // Past the 1 m tolerance: nothing.
    assert!(at_depth(&f, 8) < 0.01);
    for d in [9, 20, 199] {
        assert!(at_depth(&f, d) < 0.01, "depth {d}");
        assert!(at_depth(&f, d) <= at_depth(&f, 8));
    }

    // Default tolerance 100 m: a gentle ramp; basewidth is the same setting.
    let mut b = Bhv::new("BHV_MaxDepth", "md", uuv_domain()).config(&[("max_depth", "10")]);
    b.nav(0.0, 0.0, 0.0, 1.0, 3.0);
    let f = b.run(0.0).0.unwrap();
    assert!((at_depth(&f, 60) - 50.0).abs() < 1e-6);
    b.set("basewidth", "20").unwrap();
    let f = b.run(0.0).0.unwrap();
    assert!((at_depth(&f, 20) - 50.0).abs() < 1e-6);
}

#[test]
fn max_depth_shapes_the_depth_decision_when_violated() {
    // The delta mission: constant depth asks for 50 m (pwt 100), max depth 7 m (pwt 200).
    let mut cd = delta_constant_depth();
    let mut md = delta_max_depth();
    md.set("depth_slack_var", "DEPTH_SLACK").unwrap();
    // The vehicle is already too deep, at 12 m.
    cd.nav(0.0, 0.0, 0.0, 1.0, 12.0);
    md.nav(0.0, 0.0, 0.0, 1.0, 12.0);
    let (fcd, _) = cd.run(5.0);
    let (fmd, out) = md.run(5.0);
    assert_eq!(posted(&out, "DEPTH_SLACK"), Some(&Value::Double(-5.0)));
    let alone = decide(&cd.domain, &[("cd", fcd.clone().unwrap(), 100.0)]);
    assert_eq!(alone.get("depth"), Some(50.0));
    let both = decide(
        &cd.domain,
        &[("cd", fcd.unwrap(), 100.0), ("md", fmd.unwrap(), 200.0)],
    );
    assert_eq!(both.get("depth"), Some(7.0), "back up to the max depth");
}

#[test]
fn max_depth_parameter_values() {
    let mut b = Bhv::new("BHV_MaxDepth", "md", uuv_domain());
    assert_eq!(
        b.bhv.default_duration(),
        -1.0,
        "no time limit, as in MOOS-IvP"
    );
    assert!(matches!(
        b.set("max_depth", "seven"),
        Err(ParamError::BadValue { .. })
    ));
    assert!(matches!(
        b.set("tolerance", "1 m"),
        Err(ParamError::BadValue { .. })
    ));
    assert!(matches!(
        b.set("depth_slack_var", "A B"),
        Err(ParamError::BadValue { .. })
    ));
    assert!(matches!(
        b.set("maxdepth", "7"),
        Err(ParamError::Unknown { .. })
    ));
    b.set("max_depth", "-3").unwrap();
    b.nav(0.0, 0.0, 0.0, 1.0, 0.0);
    let (f, out) = b.run(0.0);
    assert!(f.is_some());
    assert!(!out.emits.iter().any(|e| matches!(e, Emit::Post { .. })));
}
