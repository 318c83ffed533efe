//! BHV_Trail against values worked out from MOOS-IvP's BHV_Trail (a2a9b716): the trail point,
//! the three regions and their objectives, and the parameter rules.

use behaviors::contact::ContactInfo;
use behaviors::testing::Probe;
use behaviors::{Behavior, Common, Ctx, Emit, MapInfo, Out, PostKey, Trail, Value};
use ivp::Domain;

fn domain() -> Domain {
    Domain::parse_specs(["course:0:359:360", "speed:0:4:41"]).unwrap()
}

/// Ownship at `(x, y)`; contact `bob` at the origin heading east at 1.5 m/s.
fn info(x: f64, y: f64) -> MapInfo {
    MapInfo::new(5.0)
        .num("NAV_X", x)
        .num("NAV_Y", y)
        .num("NAV_HEADING", 90.0)
        .num("NAV_SPEED", 1.5)
        .with_contact(
            "bob",
            ContactInfo {
                heading_deg: 90.0,
                speed_mps: 1.5,
                ..ContactInfo::default()
            },
        )
}

fn run(x: f64, y: f64) -> (Option<ivp::IvpFunction>, Out) {
    let d = domain();
    let inf = info(x, y);
    let ctx = Ctx {
        info: &inf,
        domain: &d,
        ownship: "abe",
        name: "trail",
        perpetual: false,
    };
    let mut b = Trail::new();
    b.set_param("contact", "bob", &mut Common::new("BHV_Trail"), &ctx)
        .unwrap();
    let mut out = Out::default();
    let f = b.on_run(&ctx, &mut out);
    (f, out)
}

fn posted(out: &Out, var: &str) -> Vec<Value> {
    out.emits
        .iter()
        .filter_map(|e| match e {
            Emit::Post { var: v, value, .. } if v == var => Some(value.clone()),
            _ => None,
        })
        .collect()
}

#[test]
fn the_trail_point_is_behind_the_contact_or_at_an_absolute_angle() {
    let mut t = Trail::new();
    let (x, y) = t.trail_point(0.0, 0.0, 90.0);
    assert!((x + 50.0).abs() < 1e-9 && y.abs() < 1e-9, "({x}, {y})");
    t.angle_relative = false;
    let (x, y) = t.trail_point(0.0, 0.0, 90.0);
    assert!(x.abs() < 1e-9 && (y + 50.0).abs() < 1e-9, "({x}, {y})");
}

#[test]
fn inside_the_radius_it_matches_the_contact() {
    let (f, out) = run(-50.0, 2.0);
    let f = f.unwrap();
    assert_eq!(posted(&out, "REGION"), [Value::text("Inside radius")]);
    assert_eq!(posted(&out, "TRAIL_SPEED"), [Value::Double(1.5)]);
    assert_eq!(posted(&out, "TRAIL_DISTANCE"), [Value::Double(2.0)]);
    assert_eq!(posted(&out, "PURSUIT"), [Value::Double(1.0)]);
    assert!(out.emits.contains(&Emit::Post {
        var: "TRAIL_CTR".into(),
        value: Value::Double(1.0),
        key: PostKey::Repeatable
    }));
    assert_eq!(
        posted(&out, "VIEW_POINT"),
        [Value::text(
            "x=-50,y=0,label=abe_trailpoint,vertex_color=gray50,time=5,vertex_size=8"
        )]
    );
    assert_eq!(f.argmax2("course", "speed"), (90.0, 1.5));
}

#[test]
fn inside_nm_radius_it_aims_ahead_of_the_trail_point_and_adjusts_speed() {
    // 10 m behind the trail point: ahead = -10; aim at the point 20 m ahead of it,
    // (-30, 0): course 90; speed 1.5 (1 + 0.5 · 10/20) = 1.875.
    let (f, out) = run(-60.0, 0.0);
    let f = f.unwrap();
    assert_eq!(posted(&out, "REGION"), [Value::text("Inside nm_radius")]);
    assert_eq!(posted(&out, "TRAIL_HEADING"), [Value::Double(90.0)]);
    let spd = posted(&out, "TRAIL_SPEED")[0].as_ref().as_f64().unwrap();
    assert!((spd - 1.9).abs() < 1e-9, "{spd}");
    let (c, v) = f.argmax2("course", "speed");
    assert_eq!(c, 90.0);
    assert!((v - 1.875).abs() <= 0.1, "{v}");
}

#[test]
fn outside_nm_radius_it_cuts_the_range_to_the_moving_trail_point() {
    // 100 m south of the trail point, which moves east at 1.5 m/s: a course to the north,
    // leading it.
    let (f, out) = run(-50.0, -100.0);
    let f = f.unwrap();
    assert_eq!(posted(&out, "REGION"), [Value::text("Outside nm_radius")]);
    let (c, _) = f.argmax2("course", "speed");
    assert!((0.0..90.0).contains(&c), "course {c}");
}

#[test]
fn parameters_are_refused_as_the_cpp_refuses_them() {
    let d = domain();
    let inf = MapInfo::new(0.0);
    let ctx = Ctx {
        info: &inf,
        domain: &d,
        ownship: "abe",
        name: "trail",
        perpetual: false,
    };
    let mut b = Trail::new();
    let mut c = Common::new("BHV_Trail");
    for (k, v) in [
        ("trail_range", "-1"),
        ("nm_radius", "x"),
        ("trail_angle", "behind"),
        ("trail_angle_type", "sideways"),
        ("mod_trail_range_pct", "0"),
        ("no_alert_request", "maybe"),
    ] {
        assert!(
            b.set_param(k, v, &mut c, &ctx).is_err(),
            "{k} = {v} accepted"
        );
    }
    b.set_param("trail_angle", "270", &mut c, &ctx).unwrap();
    assert_eq!(b.trail_angle, -90.0);
    b.set_param("mod_trail_range", "-45", &mut c, &ctx).unwrap();
    assert_eq!(b.trail_range, 10.0, "at least 10");
    b.set_param("mod_trail_range_pct", "300", &mut c, &ctx)
        .unwrap();
    assert_eq!(b.trail_range, 30.0);
}
