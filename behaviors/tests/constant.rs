//! BHV_ConstantSpeed, BHV_ConstantHeading, BHV_ConstantDepth: defaults, value rules, mismatch
//! variables and missing-nav warnings, as MOOS-IvP a2a9b716.

mod support;

use behaviors::{Emit, ParamError, Value};
use support::{Bhv, posted, uuv_domain};

fn warnings(out: &behaviors::Out) -> Vec<String> {
    out.emits
        .iter()
        .filter_map(|e| match e {
            Emit::Post { var, value, .. } if var == "BHV_WARNING" => {
                value.as_str().map(str::to_string)
            }
            _ => None,
        })
        .collect()
}

#[test]
fn defaults_names_and_durations() {
    for (kind, name) in [
        ("BHV_ConstantSpeed", "bhv_constant_speed"),
        ("BHV_ConstantHeading", "bhv_constantHeading"),
        ("BHV_ConstantDepth", "bhv_constantdepth"),
    ] {
        let b = behaviors::create(kind).unwrap();
        assert_eq!(b.default_name(), name, "{kind}");
        assert_eq!(
            b.default_duration(),
            0.0,
            "{kind}: the C++ constructor sets 0"
        );
    }
}

#[test]
fn values_are_clipped_or_rejected_as_the_cpp() {
    let mut b = Bhv::new("BHV_ConstantSpeed", "cs", uuv_domain());
    // Negative speed and widths are clipped to 0; summitdelta to [0, 100].
    for (p, v) in [
        ("speed", "-1"),
        ("peakwidth", "-2"),
        ("basewidth", "-3"),
        ("summitdelta", "150"),
    ] {
        b.set(p, v).unwrap_or_else(|e| panic!("{p} = {v}: {e}"));
    }
    for (p, v) in [
        ("speed", "fast"),
        // MOOS isNumber has no exponent: `2e1` fails setParam (MALCONFIG) as in the C++.
        ("speed", "2e1"),
        ("speed_mismatch_var", "A B"),
        ("peakwidth", "x"),
    ] {
        assert!(
            matches!(b.set(p, v), Err(ParamError::BadValue { .. })),
            "{p} = {v}"
        );
    }
    b.nav(0.0, 0.0, 0.0, 1.0, 0.0);
    let (f, _) = b.run(0.0);
    let f = f.unwrap();
    // Speed 0 with base width 0 and summit delta clipped to 100: peak at index 0 only.
    assert_eq!(f.eval(&[0]), Some(100.0));
    let mut h = Bhv::new("BHV_ConstantHeading", "ch", uuv_domain());
    assert!(matches!(
        h.set("heading", "north"),
        Err(ParamError::BadValue { .. })
    ));
    h.set("heading", "-90").unwrap();
    h.set("complete_thresh", "-1").unwrap();
    let mut d = Bhv::new("BHV_ConstantDepth", "cd", uuv_domain());
    d.set("depth", "-5").unwrap();
    assert!(matches!(
        d.set("depth_mismatch_var", "A B"),
        Err(ParamError::BadValue { .. })
    ));
    d.set("depth_mismatch_var", "").unwrap(); // no white space: accepted (turns it off)
}

#[test]
fn mismatch_variables_and_missing_nav_warnings() {
    let mut s = Bhv::new("BHV_ConstantSpeed", "cs", uuv_domain())
        .config(&[("speed", "2"), ("speed_mismatch_var", "SPD_MISS")]);
    let (_, out) = s.run(0.0);
    assert_eq!(
        warnings(&out),
        ["cs: No ownship SPEED info in info_buffer."]
    );
    s.nav(0.0, 0.0, 0.0, 1.5, 0.0);
    let (_, out) = s.run(1.0);
    assert_eq!(posted(&out, "SPD_MISS"), Some(&Value::Double(0.5)));
    let mut h = Bhv::new("BHV_ConstantHeading", "ch", uuv_domain())
        .config(&[("heading", "350"), ("heading_mismatch_var", "HDG_MISS")]);
    let (_, out) = h.run(0.0);
    assert_eq!(
        warnings(&out),
        ["ch: No ownship HEADING info in info_buffer."]
    );
    h.nav(0.0, 0.0, 10.0, 1.0, 0.0);
    let (_, out) = h.run(1.0);
    assert_eq!(posted(&out, "HDG_MISS"), Some(&Value::Double(20.0)));
    let mut d = Bhv::new("BHV_ConstantDepth", "cd", uuv_domain())
        .config(&[("depth", "10"), ("depth_mismatch_var", "DEP_MISS")]);
    d.nav(0.0, 0.0, 0.0, 1.0, 12.5);
    let (_, out) = d.run(1.0);
    assert_eq!(posted(&out, "DEP_MISS"), Some(&Value::Double(2.5)));
}

#[test]
fn clipped_values_leave_the_zaic_without_warnings() {
    // The C++ posts the ZAIC's warnings as BHV_WARNING; every ZAIC_PEAK warning needs a width
    // below 0 or a summit delta above the utility range (100), which the clips above rule out.
    for (kind, summit) in [
        ("BHV_ConstantSpeed", ("speed", "-3")),
        ("BHV_ConstantHeading", ("heading", "-725")),
        ("BHV_ConstantDepth", ("depth", "-8")),
    ] {
        let mut b = Bhv::new(kind, "c", uuv_domain());
        for (p, v) in [
            summit,
            ("peakwidth", "-2"),
            ("basewidth", "-3"),
            ("summitdelta", "1000000"),
        ] {
            b.set(p, v)
                .unwrap_or_else(|e| panic!("{kind}: {p} = {v}: {e}"));
        }
        b.nav(0.0, 0.0, 0.0, 1.0, 0.0);
        let (f, out) = b.run(0.0);
        assert!(f.is_some(), "{kind}: a function");
        assert_eq!(warnings(&out), Vec::<String>::new(), "{kind}");
    }
}
