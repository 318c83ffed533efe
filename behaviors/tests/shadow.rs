//! BHV_Shadow against values worked out from MOOS-IvP's construction (two ZAIC_PEAKs coupled
//! 50/50 and normalised, BHV_Shadow `getRelevance`, a2a9b716) and its parameter rules.

use behaviors::contact::ContactInfo;
use behaviors::testing::Probe;
use behaviors::{Behavior, Common, Ctx, Emit, MapInfo, Out, Shadow, Value};
use ivp::Domain;

fn domain() -> Domain {
    Domain::parse_specs(["course:0:359:360", "speed:0:4:41"]).unwrap()
}

fn info() -> MapInfo {
    MapInfo::new(5.0)
        .num("NAV_X", 0.0)
        .num("NAV_Y", 0.0)
        .num("NAV_HEADING", 0.0)
        .num("NAV_SPEED", 1.0)
        .with_contact(
            "bob",
            ContactInfo {
                x_m: 30.0,
                y_m: 40.0,
                heading_deg: 45.0,
                speed_mps: 1.5,
                ..ContactInfo::default()
            },
        )
}

fn configured(params: &[(&str, &str)], ctx: &Ctx<'_>) -> Shadow {
    let mut b = Shadow::new();
    let mut common = Common::new("BHV_Shadow");
    b.set_param("contact", "bob", &mut common, ctx).unwrap();
    for (k, v) in params {
        b.set_param(k, v, &mut common, ctx).unwrap();
    }
    b
}

#[test]
fn it_peaks_at_the_contact_s_heading_and_speed() {
    let d = domain();
    let inf = info();
    let ctx = Ctx {
        info: &inf,
        domain: &d,
        ownship: "abe",
        name: "shadow",
        perpetual: false,
    };
    let mut b = configured(&[], &ctx);
    let mut out = Out::default();
    let f = b
        .on_run(&ctx, &mut out)
        .expect("always relevant with pwt_outer_dist 0");
    assert_eq!(b.pwt_factor(), 1.0);
    assert_eq!(f.argmax2("course", "speed"), (45.0, 1.5));
    assert_eq!(f.value_at(&[("course", 45.0), ("speed", 1.5)]), Some(100.0));
    // Opposite heading: 180 degrees off is peak (20) + base (160) away: the course half is
    // 0, the speed half full: 50. The contact's speed at 2.5 m/s off is beyond 0.1 + 2: 50.
    let opp = f.value_at(&[("course", 225.0), ("speed", 1.5)]).unwrap();
    assert!((opp - 50.0).abs() < 1e-6, "{opp}");
    let fast = f.value_at(&[("course", 45.0), ("speed", 4.0)]).unwrap();
    assert!((fast - 50.0).abs() < 1e-6, "{fast}");
    // Postings: the contact and the relevance, rounded.
    for (var, v) in [
        ("SHADOW_CONTACT_X", 30.0),
        ("SHADOW_CONTACT_Y", 40.0),
        ("SHADOW_CONTACT_SPEED", 2.0),
        ("SHADOW_CONTACT_HEADING", 45.0),
        ("SHADOW_RELEVANCE", 1.0),
    ] {
        assert!(
            out.emits.contains(&Emit::Post {
                var: var.into(),
                value: Value::Double(v),
                key: behaviors::PostKey::Var
            }),
            "{var} = {v}: {:?}",
            out.emits
        );
    }
    // Beyond pwt_outer_dist (the contact is 50 m away): no function.
    let mut far = configured(&[("pwt_outer_dist", "50")], &ctx);
    assert!(far.on_run(&ctx, &mut Out::default()).is_none());
    let mut near = configured(&[("pwt_outer_dist", "50.1")], &ctx);
    assert!(near.on_run(&ctx, &mut Out::default()).is_some());
}

#[test]
fn parameters_are_refused_as_the_cpp_refuses_them() {
    let d = domain();
    let inf = MapInfo::new(0.0);
    let ctx = Ctx {
        info: &inf,
        domain: &d,
        ownship: "abe",
        name: "shadow",
        perpetual: false,
    };
    let mut b = Shadow::new();
    let mut c = Common::new("BHV_Shadow");
    for (k, v) in [
        ("pwt_outer_dist", "-1"),
        ("hdg_peakwidth", "wide"),
        ("speed_basewidth", "-0.5"),
        ("heading", "90"),
    ] {
        assert!(
            b.set_param(k, v, &mut c, &ctx).is_err(),
            "{k} = {v} accepted"
        );
    }
    b.set_param("hdg_basewidth", "90", &mut c, &ctx).unwrap();
    assert_eq!(b.hdg_basewidth, 90.0);
}
