//! BHV_ZigZag as MOOS-IvP a2a9b716: its coupled objective function, its legs and flags, its
//! drawings and its value rules.

mod support;

use behaviors::{Emit, ParamError, Value};
use support::{Bhv, posted, posted_all, uuv_domain};

/// `VAR=value` of every flag emitted, in order.
fn flags(out: &behaviors::Out) -> Vec<String> {
    out.emits
        .iter()
        .filter_map(|e| match e {
            Emit::Flag { flag, .. } => Some(format!("{}={}", flag.var, flag.value)),
            _ => None,
        })
        .collect()
}

fn zig(params: &[(&str, &str)]) -> Bhv {
    Bhv::new("BHV_ZigZag", "zz", uuv_domain()).config(params)
}

#[test]
fn defaults() {
    let b = behaviors::create("BHV_ZigZag").unwrap();
    assert_eq!(b.default_name(), "zig");
    assert_eq!(b.domain_vars(), ["course", "speed"]);
    assert!(!b.is_constraint());
    // onSetParamComplete is empty in the C++: no BHV_SETTINGS.
    let z = zig(&[("speed", "1")]);
    assert!(z.configured.emits.is_empty());
}

#[test]
fn the_objective_function_couples_the_cpp_zaics() {
    // stem 90, zig angle 30, port first: the first leg asks for 60.
    let mut b = zig(&[("speed", "2"), ("stem_hdg", "90"), ("zig_angle", "30")]);
    b.nav(0.0, 0.0, 90.0, 2.0, 0.0);
    let f = b.start(0.0).0.unwrap();
    // Course: ZAIC_PEAK summit 60, base width 180, peak width 0: 100 at 60, 100 - 100 * 90
    // / 180 = 50 at 150, 0 at 240. Speed: ZAIC_SPD summit 2 (100), 0.1 m/s at 85, 2.4 m/s at
    // 20, linear between (2.2 m/s: 100 - 80 * 0.2 / 0.4 = 60). Coupled 50/50 then
    // normalised to [0, 100] (the minimum, 0 + 0, stays 0):
    let at = |crs: u32, spd: u32| f.eval(&[crs, spd]).unwrap();
    assert!((at(60, 20) - 100.0).abs() < 1e-6);
    // (60, 2.2): 50 + 0.5 * 60 = 80.
    assert!((at(60, 22) - 80.0).abs() < 1e-6);
    // (150, 2.0): 0.5 * 50 + 50 = 75.
    assert!((at(150, 20) - 75.0).abs() < 1e-6);
    // (240, 2.4): 0 + 0.5 * 20 = 10.
    assert!((at(240, 24) - 10.0).abs() < 1e-6);
    // Starboard first: the first leg asks for 120.
    let mut b = zig(&[
        ("speed", "2"),
        ("stem_hdg", "90"),
        ("zig_angle", "30"),
        ("zig_first", "Starboard"),
    ]);
    b.nav(0.0, 0.0, 90.0, 2.0, 0.0);
    let f = b.start(0.0).0.unwrap();
    assert!((f.eval(&[120, 20]).unwrap() - 100.0).abs() < 1e-6);
    let mut side = String::new();
    assert!(b.bhv.macro_value("ZIG_SIDE", &mut side));
    assert_eq!(side, "star");
}

#[test]
fn legs_alternate_with_flags_until_more_than_max_legs_are_done() {
    let mut b = zig(&[
        ("speed", "1"),
        ("stem_hdg", "0"),
        ("zig_angle", "30"),
        ("hdg_thresh", "5"),
        ("max_zig_legs", "2"),
        ("zigflag", "ZIG=$[ZIGS]"),
        ("zagflag", "ZAG=$[ZAGS]"),
        ("portflag", "SIDE=$[ZIG_SIDE]"),
        ("starflag", "SIDE=star"),
        ("portflagx", "PX=$[ZIG_PORT]"),
        ("starflagx", "SX=true"),
    ]);
    b.nav(0.0, 0.0, 0.0, 1.0, 0.0);
    let (f, out) = b.start(0.0);
    assert!(f.is_some());
    // Stem to port at once; the port flag is expanded before the state changes (stem).
    assert_eq!(flags(&out), ["SIDE=stem"]);
    // Heading 340, 10 from 330: the turn goes on.
    b.nav(0.0, 5.0, 340.0, 1.0, 0.0);
    let (_, out) = b.run(1.0);
    assert!(flags(&out).is_empty());
    // Heading 332, within 5 of 330: leg 1 done, starboard next.
    b.nav(-2.0, 10.0, 332.0, 1.0, 0.0);
    let (_, out) = b.run(2.0);
    assert_eq!(flags(&out), ["ZIG=1", "PX=true", "SIDE=star"]);
    // Overshoot: set heading 30, the vehicle at 45 (diff 15 > 5) has swung past it (30 is
    // not between 45 and 45 + 170 = 215): leg 2 done.
    b.nav(0.0, 15.0, 45.0, 1.0, 0.0);
    let (f, out) = b.run(3.0);
    assert_eq!(flags(&out), ["ZIG=2", "ZAG=1", "SX=true", "SIDE=star"]);
    assert!(f.is_some());
    // Leg 3 done: 3 > max_zig_legs = 2, so no new port/star flag, and complete.
    b.nav(0.0, 20.0, 331.0, 1.0, 0.0);
    let (f, out) = b.run(4.0);
    assert_eq!(flags(&out), ["ZIG=3", "PX=true"]);
    assert!(f.is_none() && out.completed);
}

#[test]
fn fierce_zigging_asks_past_the_current_heading() {
    let mut b = zig(&[
        ("speed", "1"),
        ("zig_angle", "20"),
        ("fierce_zigging", "true"),
        ("zig_angle_fierce", "45"),
    ]);
    b.nav(0.0, 0.0, 10.0, 1.0, 0.0);
    // Port leg: requested 10 - 45 = 325 (the set heading stays 340).
    let f = b.start(0.0).0.unwrap();
    assert!((f.eval(&[325, 10]).unwrap() - 100.0).abs() < 1e-6);
    let (_, out) = b.run(1.0);
    let lines: Vec<&str> = posted_all(&out, "VIEW_SEGLIST")
        .into_iter()
        .filter_map(Value::as_str)
        .collect();
    // 20 m lines from 0,0: set 340 (sin -0.342, cos 0.940 → -6.8, 18.8), requested 325
    // (-11.5, 16.4), one decimal.
    assert_eq!(
        lines,
        [
            "pts={0,0:-6.8,18.8},label=zig_set_abe,label_color=invisible,edge_color=white,\
             vertex_color=white,duration=5,vertex_size=2,edge_size=1",
            "pts={0,0:-11.5,16.4},label=zig_req_abe,label_color=invisible,edge_color=yellow,\
             vertex_color=yellow,duration=5,vertex_size=2,edge_size=1",
        ]
    );
    let out = b.stop(2.0);
    let erased: Vec<&str> = posted_all(&out, "VIEW_SEGLIST")
        .into_iter()
        .filter_map(Value::as_str)
        .collect();
    assert_eq!(
        erased,
        [
            "pts={0,0:9,0:0,9},active=false,label=zig_set_abe",
            "pts={0,0:9,0:0,9},active=false,label=zig_req_abe",
        ]
    );
}

#[test]
fn stale_or_missing_nav_is_an_error() {
    let mut b = zig(&[("speed", "1"), ("zig_angle", "20")]);
    b.num("NAV_X", 0.0).num("NAV_Y", 0.0).num("NAV_SPEED", 1.0);
    let (f, out) = b.run(0.0);
    assert!(f.is_none());
    assert_eq!(
        out.error.as_deref(),
        Some("ownship NAV_HEADING not found or stale.")
    );
    b.num("NAV_HEADING", 0.0);
    // Written at 0; at 5.5 s they are older than 5 s.
    let (f, out) = b.run(5.5);
    assert!(f.is_none());
    assert_eq!(
        out.error.as_deref(),
        Some("ownship NAV_X/Y not found or stale.")
    );
    assert!(posted(&out, "VIEW_SEGLIST").is_none());
}

#[test]
fn stem_distance_and_odometry_macros() {
    let mut b = zig(&[("speed", "1"), ("zig_angle", "20"), ("max_stem_odo", "50")]);
    b.nav(10.0, 10.0, 0.0, 1.0, 0.0);
    b.start(0.0);
    // 3 m east and 40 m north of the stem's start: 3 m off the stem, 40 m along it; the
    // odometer has 40.11 m (hypot(3, 40)).
    b.nav(13.0, 50.0, 0.0, 1.0, 0.0);
    let (f, out) = b.run(1.0);
    assert!(f.is_some() && !out.completed);
    let m = |name: &str| {
        let mut s = String::new();
        assert!(b.bhv.macro_value(name, &mut s), "{name}");
        s
    };
    assert_eq!(m("STEM_DIST"), "3");
    assert_eq!(m("STEM_ODO"), "40");
    assert_eq!(m("ODO"), "40.112");
    assert_eq!(m("ZIGS_TOGO"), "2");
    // 50 m along the stem: complete.
    b.nav(13.0, 60.0, 0.0, 1.0, 0.0);
    let (f, out) = b.run(2.0);
    assert!(f.is_none() && out.completed);
}

#[test]
fn speed_on_activation_and_mod_speed() {
    let mut b = zig(&[
        ("speed", "1.5"),
        ("speed_on_active", "true"),
        ("zig_angle", "20"),
    ]);
    b.nav(0.0, 0.0, 0.0, 0.8, 0.0);
    b.start(0.0);
    let speed = |b: &Bhv| {
        let mut s = String::new();
        b.bhv.macro_value("STEM_SPD", &mut s);
        s
    };
    assert_eq!(speed(&b), "0.8");
    // mod_speed adds and clips to the domain (0..4): 0.8 + 5 -> 4, the summit at index 40
    // with the port leg's 340.
    b.set("mod_speed", "5").unwrap();
    let f = b.run(1.0).0.unwrap();
    assert!((f.eval(&[340, 40]).unwrap() - 100.0).abs() < 1e-6);
    // reset: back to the speed taken on activation, 0.8.
    b.set("mod_speed", "reset").unwrap();
    let f = b.run(2.0).0.unwrap();
    assert!((f.eval(&[340, 8]).unwrap() - 100.0).abs() < 1e-6);
    // -9: clipped to 0.
    b.set("mod_speed", "-9").unwrap();
    let f = b.run(3.0).0.unwrap();
    assert!((f.eval(&[340, 0]).unwrap() - 100.0).abs() < 1e-6);
}

#[test]
fn values_are_refused_as_the_cpp() {
    let mut b = Bhv::new("BHV_ZigZag", "zz", uuv_domain());
    for (p, v) in [
        ("speed", "0"),
        ("stem_hdg", "-90"),
        ("hdg_thresh", "0"),
        ("zig_angle", "1"),
        ("zig_angle", "75"),
        ("delta_heading", "40"),
        ("zig_first", "LEFT"),
        ("zig_first", "right"),
        ("max_zig_legs", "0"),
        ("max_zig_legs", "3.7"),
        ("max_zig_zags", "1"),
        ("max_stem_odo", "0.1"),
        ("zigflag", "A=1"),
        ("visual_hints", "draw_set_hdg=false, req_hdg_color=red"),
    ] {
        b.set(p, v).unwrap_or_else(|e| panic!("{p} = {v}: {e}"));
    }
    for (p, v) in [
        ("speed", "-1"),
        ("speed", "fast"),
        ("mod_speed", "more"),
        ("stem_hdg", "north"),
        ("hdg_thresh", "-1"),
        ("zig_angle", "0.5"),
        ("zig_angle", "76"),
        ("zig_angle_fierce", "80"),
        ("zig_first", "up"),
        ("max_zig_legs", "-1"),
        ("max_zig_zags", "0.5"),
        ("max_stem_odo", "0"),
        ("fierce_zigging", "maybe"),
        ("zigflag", "novalue"),
        ("visual_hints", "draw_set_hdg=maybe"),
        ("visual_hints", "req_hdg_color=nocolor"),
        ("visual_hints", "edge_size=3"),
    ] {
        assert!(
            matches!(b.set(p, v), Err(ParamError::BadValue { .. })),
            "{p} = {v}"
        );
    }
}
