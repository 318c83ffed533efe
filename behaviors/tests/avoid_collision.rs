//! BHV_AvoidCollision against values worked out from MOOS-IvP's formulas (BHV_AvoidCollision
//! `getRelevance`, AOF_AvoidCollision `metric`, CPXEngineOG `evalCPA`, a2a9b716), its parameter
//! rules, and its postings.

use behaviors::contact::ContactInfo;
use behaviors::testing::Probe;
use behaviors::{AvoidCollision, Behavior, Common, Ctx, Emit, MapInfo, Out, ParamError, Value};
use ivp::Domain;

fn domain() -> Domain {
    Domain::parse_specs(["course:0:359:360", "speed:0:4:41"]).unwrap()
}

/// Ownship at the origin heading north at 2 m/s; contact `cn` at `(x, y)` heading `h` at `v`.
fn info(x: f64, y: f64, h: f64, v: f64) -> MapInfo {
    MapInfo::new(100.0)
        .num("NAV_X", 0.0)
        .num("NAV_Y", 0.0)
        .num("NAV_HEADING", 0.0)
        .num("NAV_SPEED", 2.0)
        .with_contact(
            "cn",
            ContactInfo {
                x_m: x,
                y_m: y,
                heading_deg: h,
                speed_mps: v,
                utc: 100.0,
                vtype: "kayak".into(),
                ..ContactInfo::default()
            },
        )
}

fn configured(params: &[(&str, &str)], d: &Domain, info: &MapInfo) -> AvoidCollision {
    let ctx = Ctx {
        info,
        domain: d,
        ownship: "abe",
        name: "avd_cn",
        perpetual: false,
    };
    let mut b = AvoidCollision::new();
    let mut common = Common::new("BHV_AvoidCollision");
    b.set_param("contact", "cn", &mut common, &ctx).unwrap();
    for (k, v) in params {
        b.set_param(k, v, &mut common, &ctx).unwrap();
    }
    b
}

fn set(b: &mut AvoidCollision, k: &str, v: &str) -> Result<(), ParamError> {
    let d = domain();
    let info = MapInfo::new(0.0);
    let ctx = Ctx {
        info: &info,
        domain: &d,
        ownship: "abe",
        name: "avd",
        perpetual: false,
    };
    b.set_param(k, v, &mut Common::new("BHV_AvoidCollision"), &ctx)
}

#[test]
fn relevance_follows_the_grade_between_the_pwt_distances() {
    // outer 200, inner 50: at 125 m the ratio is 75/150 = 0.5.
    let mut b = AvoidCollision::new();
    assert_eq!(b.relevance_at(125.0), 0.5f64.powf(1.5)); // quasi: 0.353553...
    b.pwt_grade = behaviors::PwtGrade::Linear;
    assert_eq!(b.relevance_at(125.0), 0.5);
    b.pwt_grade = behaviors::PwtGrade::Quadratic;
    assert_eq!(b.relevance_at(125.0), 0.25);
    assert_eq!(b.relevance_at(200.0), 0.0, "none at the outer distance");
    // Inside the inner distance the C++ ratio keeps growing: (200-25)/150 = 7/6.
    b.pwt_grade = behaviors::PwtGrade::Linear;
    assert!((b.relevance_at(25.0) - 7.0 / 6.0).abs() < 1e-12);
}

#[test]
fn the_metric_is_zero_below_min_then_25_to_100() {
    let m = |d| AvoidCollision::metric(d, 10.0, 75.0);
    assert_eq!(m(5.0), 0.0);
    assert_eq!(m(10.0), 25.0);
    assert_eq!(m(42.5), 62.5); // 25 + 75 * 32.5/65
    assert_eq!(m(75.0), 100.0);
    assert_eq!(m(80.0), 100.0);
}

#[test]
fn head_on_it_refuses_holding_course_and_prefers_turning_away() {
    // Contact 100 m ahead heading south at 2 m/s.
    let d = domain();
    let inf = info(0.0, 100.0, 180.0, 2.0);
    let mut b = configured(&[], &d, &inf);
    let ctx = Ctx {
        info: &inf,
        domain: &d,
        ownship: "abe",
        name: "avd_cn",
        perpetual: false,
    };
    let mut out = Out::default();
    let f = b
        .on_run(&ctx, &mut out)
        .expect("a function within pwt_outer_dist");
    // Relevance at 100 m: ((200-100)/150)^1.5 = (2/3)^1.5 = 0.544331...
    assert!((b.pwt_factor() - (2.0f64 / 3.0).powf(1.5)).abs() < 1e-12);
    assert!(out.emits.contains(&Emit::Post {
        var: "AVD_DEBUG".into(),
        value: Value::String("In getRelevance: 100.00000".into()),
        key: behaviors::PostKey::Var,
    }));
    // Straight at it at any speed: CPA 0 (they meet within the 120 s leg) -> utility 0.
    // Normalised 0..100, and sampled in 3x3 pieces: near zero.
    for spd in [1.0, 2.0, 3.0] {
        let v = f.value_at(&[("course", 1.0), ("speed", spd)]).unwrap();
        assert!(v < 10.0, "course 1 at {spd}: {v}");
    }
    // Due east at 2 m/s: relative track (0,100) + t(-2,-2): CPA at t=25, 70.71 m:
    // 25 + 75 * (70.71 - 10) / 65 = 95.05; due west the same by symmetry.
    let east = f.value_at(&[("course", 90.0), ("speed", 2.0)]).unwrap();
    let west = f.value_at(&[("course", 270.0), ("speed", 2.0)]).unwrap();
    assert!((east - 95.05).abs() < 5.0, "east {east}");
    assert!((east - west).abs() < 1.0, "east {east} west {west}");
    // Stopped: the contact runs over ownship.
    assert!(f.value_at(&[("course", 90.0), ("speed", 0.0)]).unwrap() < 10.0);
    // Every maximum is a course well off the contact's bearing.
    let (c, _) = f.argmax2("course", "speed");
    assert!((40.0..=320.0).contains(&c), "argmax course {c}");
}

#[test]
fn beyond_the_outer_distance_no_function_and_it_completes_past_completed_dist() {
    let d = domain();
    let far = info(0.0, 300.0, 180.0, 2.0);
    let mut b = configured(&[], &d, &far);
    let ctx = Ctx {
        info: &far,
        domain: &d,
        ownship: "abe",
        name: "avd_cn",
        perpetual: false,
    };
    let mut out = Out::default();
    assert!(b.on_run(&ctx, &mut out).is_none());
    assert!(!out.completed);
    // 1.1 x completed_dist (100) = 110 < 300: complete.
    let mut b = configured(&[("completed_dist", "100")], &d, &far);
    let mut out = Out::default();
    assert!(b.on_run(&ctx, &mut out).is_none());
    assert!(out.completed);
    // A missing contact is a warning (on_no_contact_ok), not an error.
    let none = MapInfo::new(0.0)
        .num("NAV_X", 0.0)
        .num("NAV_Y", 0.0)
        .num("NAV_HEADING", 0.0);
    let ctx = Ctx { info: &none, ..ctx };
    let mut out = Out::default();
    assert!(b.on_run(&ctx, &mut out).is_none());
    assert!(out.error.is_none());
    assert!(out.emits.contains(&Emit::Post {
        var: "BHV_WARNING".into(),
        value: Value::String("avd_cn: cn x/y/heading/speed info not found".into()),
        key: behaviors::PostKey::Repeatable,
    }));
}

#[test]
fn parameters_are_refused_as_the_cpp_refuses_them() {
    let mut b = AvoidCollision::new();
    for (k, v) in [
        ("pwt_outer_dist", "-1"),
        ("pwt_inner_dist", "x"),
        ("min_util_cpa_dist", "-3"),
        ("completed_dist", "-1"),
        ("pwt_grade", "cubic"),
        ("roc_max_heighten", "-1"),
        ("no_alert_request", "perhaps"),
        ("collision_depth", "5"), // no depth in the domain
        ("decay", "30,15"),
        ("time_on_leg", "-1"),
        ("no_such_param", "1"),
    ] {
        assert!(set(&mut b, k, v).is_err(), "{k} = {v} accepted");
    }
    // Pairs keep their order: a low end above the high end raises it, and back.
    set(&mut b, "pwt_inner_dist", "300").unwrap();
    assert_eq!((b.pwt_inner_dist, b.pwt_outer_dist), (300.0, 300.0));
    set(&mut b, "pwt_outer_dist", "20").unwrap();
    assert_eq!((b.pwt_inner_dist, b.pwt_outer_dist), (20.0, 20.0));
    set(&mut b, "max_util_cpa_dist", "5").unwrap();
    assert_eq!((b.min_util_cpa_dist, b.max_util_cpa_dist), (5.0, 5.0));
    set(&mut b, "pwt_grade", "LINEAR").unwrap();
    assert_eq!(b.pwt_grade, behaviors::PwtGrade::Linear);
    set(&mut b, "contact_type_required", "kayak").unwrap();
    assert_eq!(b.base.filter.summary(), "match_type=kayak");
}

#[test]
fn a_spawning_template_asks_the_contact_manager_for_alerts() {
    let d = domain();
    let inf = MapInfo::new(0.0);
    let ctx = Ctx {
        info: &inf,
        domain: &d,
        ownship: "abe",
        name: "avd_",
        perpetual: false,
    };
    let mut b = AvoidCollision::new();
    let mut common = Common::new("BHV_AvoidCollision");
    common.set_param("updates", "CONTACT_INFO").unwrap();
    common.set_param("templating", "spawn").unwrap();
    b.set_param("pwt_outer_dist", "80.26", &mut common, &ctx)
        .unwrap();
    b.set_param("match_group", "blue", &mut common, &ctx)
        .unwrap();
    b.set_common(&common);
    let mut out = Out::default();
    b.on_helm_start(&ctx, &mut out);
    assert_eq!(
        out.emits,
        [Emit::Post {
            var: "BCM_ALERT_REQUEST".into(),
            value: Value::String(
                "id=avd_, on_flag=CONTACT_INFO=name=$[VNAME] # contact=$[VNAME],\
                 alert_range=80.3, cpa_range=500,match_group=blue"
                    .into()
            ),
            key: behaviors::PostKey::Var,
        }]
    );
    // Not a template, or no_alert_request: nothing.
    let mut b = AvoidCollision::new();
    b.set_common(&Common::new("BHV_AvoidCollision"));
    let mut out = Out::default();
    b.on_helm_start(&ctx, &mut out);
    assert!(out.emits.is_empty());
}

/// The objective function is the one the reflector built before its uniform grid had a
/// path of its own: the same pieces and weights, to the bit, as the general path of boxes
/// (forced here by a refine region that covers the domain with the same 3 x 3 pieces),
/// on a few geometries.
#[test]
fn the_objective_is_the_box_list_reflection_to_the_bit() {
    let d = domain();
    let geometries = [
        (0.0, 100.0, 180.0, 2.0),
        (80.0, 30.0, 270.0, 1.5),
        (-60.0, -90.0, 45.0, 3.0),
        (5.0, 8.0, 10.0, 0.0),
        (140.0, -20.0, 300.0, 2.5),
    ];
    for (x, y, h, v) in geometries {
        let inf = info(x, y, h, v);
        let mut b = configured(&[("max_util_cpa_dist", "30")], &d, &inf);
        let ctx = Ctx {
            info: &inf,
            domain: &d,
            ownship: "abe",
            name: "avd_cn",
            perpetual: false,
        };
        let mut out = Out::default();
        b.on_run(&ctx, &mut out).expect("a function");
        let fast = b.objective(&ctx).expect("an objective");
        let min = if b.base.range <= b.min_util_cpa_dist {
            b.base.range / 2.0
        } else {
            b.min_util_cpa_dist
        };
        let engine = b.base.cpa_engine();
        let tol = b.base.time_on_leg;
        let reference = ivp::Reflector::new(&d, |p: &[f64]| {
            AvoidCollision::metric(engine.eval_cpa(p[0], p[1], tol), min, b.max_util_cpa_dist)
        })
        .set_params(
            "uniform_piece = course:3,speed:3 # refine_region = course:0:359,speed:0:4 \
             # refine_piece = course:3,speed:3",
        )
        .unwrap()
        .build()
        .unwrap();
        assert_eq!(fast.piece_count(), 1680);
        assert_eq!(fast.piece_count(), reference.piece_count());
        let bits = |w: &[f64]| w.iter().map(|x| x.to_bits()).collect::<Vec<_>>();
        for (p, q) in fast.pieces().zip(reference.pieces()) {
            assert_eq!((p.lo, p.hi), (q.lo, q.hi), "contact at {x},{y}");
            assert_eq!(bits(p.wts), bits(q.wts), "contact at {x},{y}");
        }
    }
}
