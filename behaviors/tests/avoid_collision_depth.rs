//! BHV_AvoidCollision's `collision_depth` (MOOS-IvP a2a9b716: `AOF_AvoidCollisionDepth`,
//! `getAvoidDepthIPF`, the `collision_depth` rules of `setParam`) against values worked out
//! from the C++ formulas.

use behaviors::aof_avoid_collision_depth::AofAvoidCollisionDepth;
use behaviors::contact::ContactInfo;
use behaviors::cpa::CpaEngine;
use behaviors::testing::Probe;
use behaviors::{AvoidCollision, Behavior, Common, Ctx, Emit, MapInfo, Out, ParamError, Value};
use ivp::Domain;

fn domain() -> Domain {
    Domain::parse_specs(["course:0:359:360", "speed:0:4:41", "depth:0:100:101"]).unwrap()
}

/// Ownship at the origin heading north at 2 m/s; the contact 100 m north heading south at
/// 2 m/s (head-on): rate of closure 4 m/s.
fn head_on() -> AofAvoidCollisionDepth {
    let e = CpaEngine::new(0.0, 100.0, 180.0, 2.0, 0.0, 0.0);
    AofAvoidCollisionDepth::new(&domain(), e, 0.0, 2.0, 120.0, 10.0, 75.0, 30.0).unwrap()
}

#[test]
fn the_objective_hand_worked() {
    let a = head_on();
    assert_eq!(a.rate_of_closure, 4.0);
    assert_eq!(a.max_decision_depth, 100.0);
    // At or below the collision depth: 90 + 10 (100 - z) / 100.
    assert_eq!(a.eval(0.0, 2.0, 50.0), 95.0);
    assert_eq!(a.eval(0.0, 2.0, 30.0), 97.0);
    assert_eq!(a.eval(0.0, 2.0, 100.0), 90.0);
    // Above it: the CPA metric plus the dive term. Straight at the contact: CPA 0, metric
    // 0; at the surface 0 + 10.
    assert!((a.eval(0.0, 2.0, 0.0) - 10.0).abs() < 1e-9);
    // East at 2 m/s: relative track (0, 100) + t (-2, -2), CPA at t = 25: (-50, 50),
    // 70.71 m; metric 100 (70.71 - 10) / 65 = 93.40; at 10 m the dive term is 9: 102.40.
    let want = 100.0 * (50.0 * 2f64.sqrt() - 10.0) / 65.0 + 9.0;
    assert!((a.eval(90.0, 2.0, 10.0) - want).abs() < 1e-9);
}

#[test]
fn the_metric_skews_when_opening_and_keeps_ten_metres() {
    // The contact 50 m south heading south at 1 m/s, ownship north at 2 m/s: opening at
    // cos(180) 2 + (-1) = -3 m/s: the all-clear distance 75 becomes 72.
    let e = CpaEngine::new(0.0, -50.0, 180.0, 1.0, 0.0, 0.0);
    let a = AofAvoidCollisionDepth::new(&domain(), e, 0.0, 2.0, 120.0, 10.0, 75.0, 30.0).unwrap();
    assert!((a.rate_of_closure + 3.0).abs() < 1e-12);
    assert!((a.metric(41.0) - 50.0).abs() < 1e-9); // 100 (41 - 10) / 62
    assert_eq!(a.metric(9.9), 0.0);
    assert_eq!(a.metric(72.5), 100.0);
    // Collision and all-clear 5 m apart: the all-clear distance is raised to min + 10.
    let mut b = head_on();
    b.all_clear_distance = 15.0;
    assert!((b.metric(15.0) - 50.0).abs() < 1e-9);
    // The dive term clips depths into [0, D].
    assert_eq!(b.dive(-5.0), 10.0);
    assert_eq!(b.dive(150.0), 0.0);
}

#[test]
fn the_reflector_refines_above_the_collision_depth_and_keeps_one_piece_below() {
    let f = head_on().build(&domain()).unwrap();
    // Above 30 m (depths 0..29, 30 points): 36 courses x 9 speeds (5 points, the last of 1)
    // x 1 depth piece = 324; from 30 m down one piece: 325.
    assert_eq!(f.piece_count(), 325);
    // Below, 90 + 10 (100 - z) / 100 is linear: the piece is exact.
    let v = f
        .value_at(&[("course", 123.0), ("speed", 3.1), ("depth", 50.0)])
        .unwrap();
    assert!((v - 95.0).abs() < 1e-9, "{v}");
    // Above, straight at the contact near the surface: near 10.
    let v = f
        .value_at(&[("course", 0.0), ("speed", 2.0), ("depth", 0.0)])
        .unwrap();
    assert!(v < 20.0, "{v}");
}

fn info(with_depth: bool) -> MapInfo {
    let i = MapInfo::new(100.0)
        .num("NAV_X", 0.0)
        .num("NAV_Y", 0.0)
        .num("NAV_HEADING", 0.0)
        .num("NAV_SPEED", 2.0)
        .with_contact(
            "cn",
            ContactInfo {
                x_m: 0.0,
                y_m: 100.0,
                heading_deg: 180.0,
                speed_mps: 2.0,
                utc: 100.0,
                ..ContactInfo::default()
            },
        );
    if with_depth {
        i.num("NAV_DEPTH", 0.0)
    } else {
        i
    }
}

fn set(b: &mut AvoidCollision, d: &Domain, k: &str, v: &str) -> Result<(), ParamError> {
    let inf = info(true);
    let ctx = Ctx {
        info: &inf,
        domain: d,
        ownship: "abe",
        name: "avd",
        perpetual: false,
    };
    b.set_param(k, v, &mut Common::new("BHV_AvoidCollision"), &ctx)
}

#[test]
fn collision_depth_follows_the_cpp_rules() {
    let flat = Domain::parse_specs(["course:0:359:360", "speed:0:4:41"]).unwrap();
    let deep = domain();
    let mut b = AvoidCollision::new();
    // No depth domain: refused.
    assert!(set(&mut b, &flat, "collision_depth", "5").is_err());
    // Not above 0 (atof: text is 0): refused.
    for v in ["0", "-2", "abc"] {
        assert!(set(&mut b, &deep, "collision_depth", v).is_err(), "{v}");
    }
    // At or below the domain's deepest: accepted, nothing changes.
    set(&mut b, &deep, "collision_depth", "100").unwrap();
    assert_eq!(b.collision_depth, 0.0);
    assert_eq!(b.domain_vars(), ["course", "speed"]);
    set(&mut b, &deep, "collision_depth", "30").unwrap();
    assert_eq!(b.collision_depth, 30.0);
    assert_eq!(b.domain_vars(), ["course", "speed", "depth"]);
}

#[test]
fn a_running_iteration_builds_the_depth_function() {
    let d = domain();
    let inf = info(true);
    let ctx = Ctx {
        info: &inf,
        domain: &d,
        ownship: "abe",
        name: "avd_cn",
        perpetual: false,
    };
    let mut b = AvoidCollision::new();
    let mut common = Common::new("BHV_AvoidCollision");
    b.set_param("contact", "cn", &mut common, &ctx).unwrap();
    b.set_param("collision_depth", "30", &mut common, &ctx)
        .unwrap();
    let mut out = Out::default();
    let f = b.on_run(&ctx, &mut out).expect("a function");
    assert_eq!(f.piece_count(), 325);
    assert!(out.emits.contains(&Emit::Post {
        var: "AVD_STATUS".into(),
        value: Value::String("".into()),
        key: behaviors::PostKey::Var,
    }));
    // Normalised 0..100: the best is off the contact's track at the surface (raw 110), the
    // worst straight at it just above 30 m; at 30 m and below every course is near the best.
    let deep = f
        .value_at(&[("course", 0.0), ("speed", 2.0), ("depth", 30.0)])
        .unwrap();
    let shallow = f
        .value_at(&[("course", 0.0), ("speed", 2.0), ("depth", 5.0)])
        .unwrap();
    assert!(
        deep > 80.0 && shallow < 20.0,
        "deep {deep} shallow {shallow}"
    );
}
