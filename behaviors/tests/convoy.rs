//! BHV_Convoy against values worked out from MOOS-IvP's BHV_Convoy (a2a9b716): marks, the set
//! speed by range band, the objective, the safety adjustments and the parameter rules.

use behaviors::contact::ContactInfo;
use behaviors::testing::Probe;
use behaviors::{Behavior, Common, Convoy, Ctx, Emit, MapInfo, Out, Value};
use ivp::Domain;

fn domain() -> Domain {
    Domain::parse_specs(["course:0:359:360", "speed:0:4:41"]).unwrap()
}

fn info(now: f64, cx: f64, cy: f64) -> MapInfo {
    MapInfo::new(now)
        .num("NAV_X", 0.0)
        .num("NAV_Y", 0.0)
        .num("NAV_HEADING", 0.0)
        .num("NAV_SPEED", 1.0)
        .with_contact(
            "bob",
            ContactInfo {
                x_m: cx,
                y_m: cy,
                heading_deg: 90.0,
                speed_mps: 1.2,
                ..ContactInfo::default()
            },
        )
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
fn the_set_speed_follows_the_range_bands() {
    let b = Convoy::new(); // estop 15, tailgating 30, lagging 70, faster 1.5, slower 0.5
    assert_eq!(b.set_speed_at(10.0, 2.0), 0.0);
    assert_eq!(b.set_speed_at(20.0, 2.0), 1.0);
    assert_eq!(b.set_speed_at(50.0, 2.0), 2.0);
    assert_eq!(b.set_speed_at(80.0, 2.0), 3.0);
}

#[test]
fn it_follows_the_contact_s_marks() {
    let d = domain();
    let mut b = Convoy::new();
    let inf = info(0.0, 0.0, 40.0);
    let ctx = Ctx {
        info: &inf,
        domain: &d,
        ownship: "abe",
        name: "convoy",
        perpetual: false,
    };
    let mut c = Common::new("BHV_Convoy");
    b.set_param("contact", "bob", &mut c, &ctx).unwrap();
    b.set_common(&c);
    b.on_set_param_complete(&ctx, &mut Out::default());
    // First mark at the contact (0, 40): head north at the 2 s average (1.2: range 40 is
    // between tailgating and lagging).
    let mut out = Out::default();
    let f = b.on_run(&ctx, &mut out).expect("a mark to go to");
    assert_eq!(
        posted(&out, "VIEW_POINT"),
        [Value::text(
            "x=0,y=40,label=abe_bob_0,label_color=invisible,vertex_color=white"
        )]
    );
    assert_eq!(posted(&out, "WPTY"), [Value::Double(40.0)]);
    assert_eq!(posted(&out, "AVG2"), [Value::Double(1.2)]);
    let (crs, spd) = f.argmax2("course", "speed");
    assert_eq!(crs, 0.0);
    assert!((spd - 1.2).abs() < 1e-9, "{spd}");
    // The C++ weight is IvPFunction's default 10 whatever pwt says (pwt 100 here).
    assert_eq!(b.pwt_factor(), 0.1);
    // The contact moves 12 m east: a second mark (more than inter_mark_range 10 away), the
    // path 12 m long; ownship still heads for the oldest one.
    let inf = info(1.0, 12.0, 40.0);
    let ctx = Ctx { info: &inf, ..ctx };
    let mut out = Out::default();
    b.on_run(&ctx, &mut out).unwrap();
    assert_eq!(
        posted(&out, "VIEW_POINT"),
        [Value::text(
            "x=12,y=40,label=abe_bob_1,label_color=invisible,vertex_color=white"
        )]
    );
    let mut out = Out::default();
    b.on_run(&ctx, &mut out).unwrap();
    assert_eq!(posted(&out, "TLEN"), [Value::Double(12.0)]);
    assert_eq!(posted(&out, "QLEN"), [Value::Double(2.0)]);
    // Leaving the running state erases the marks.
    let mut out = Out::default();
    b.on_run_to_idle(&ctx, &mut out);
    assert_eq!(
        posted(&out, "VIEW_POINT"),
        [
            Value::text("x=0,y=0,active=false,label=abe_bob_1"),
            Value::text("x=0,y=0,active=false,label=abe_bob_0"),
        ]
    );
}

#[test]
fn safety_ranges_are_widened_and_parameters_refused_as_the_cpp_does() {
    let d = domain();
    let inf = MapInfo::new(0.0);
    let ctx = Ctx {
        info: &inf,
        domain: &d,
        ownship: "abe",
        name: "convoy",
        perpetual: false,
    };
    let mut b = Convoy::new();
    let mut c = Common::new("BHV_Convoy");
    for (k, v) in [
        ("spd_slower", "1.5"),
        ("spd_faster", "0.5"),
        ("max_mark_range", "0"),
        ("rng_estop", "-1"),
        ("rng_safety", "maybe"),
        ("radius", "x"),
        ("speed", "1"),
    ] {
        assert!(
            b.set_param(k, v, &mut c, &ctx).is_err(),
            "{k} = {v} accepted"
        );
    }
    b.set_param("range_estop", "2", &mut c, &ctx).unwrap();
    b.set_param("cruise_speed", "3", &mut c, &ctx).unwrap();
    let mut out = Out::default();
    b.on_set_param_complete(&ctx, &mut out);
    assert_eq!(
        (b.rng_estop, b.rng_tgating, b.rng_lagging),
        (5.0, 30.0, 70.0)
    );
    assert_eq!(b.cruise_speed, 2.0, "capped at spd_max");
    assert_eq!(posted(&out, "BHV_WARNING").len(), 2);
}
