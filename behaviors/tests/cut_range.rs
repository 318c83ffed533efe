//! BHV_CutRange against values worked out from MOOS-IvP's formulas (BHV_CutRange
//! `getRelevance`, AOF_CutRangeCPA `evalBox` and `metric`, CPAEngine `minMaxROC`, a2a9b716)
//! and its parameter rules.

use behaviors::contact::ContactInfo;
use behaviors::cpa::CpaEngine;
use behaviors::testing::Probe;
use behaviors::{Behavior, Common, Ctx, CutRange, MapInfo, Out};
use ivp::Domain;

fn domain() -> Domain {
    Domain::parse_specs(["course:0:359:360", "speed:0:4:41"]).unwrap()
}

fn set(b: &mut CutRange, k: &str, v: &str) -> Result<(), behaviors::ParamError> {
    let d = domain();
    let info = MapInfo::new(0.0);
    let ctx = Ctx {
        info: &info,
        domain: &d,
        ownship: "abe",
        name: "cut",
        perpetual: false,
    };
    b.set_param(k, v, &mut Common::new("BHV_CutRange"), &ctx)
}

#[test]
fn relevance_grows_with_range_while_in_pursuit() {
    let mut b = CutRange::new();
    set(&mut b, "pwt_outer_dist", "100").unwrap();
    set(&mut b, "pwt_inner_dist", "20").unwrap();
    assert_eq!(b.relevance_at(60.0), 0.0, "not in pursuit");
    b.set_in_pursuit(true);
    assert_eq!(b.relevance_at(60.0), 0.5); // (60-20)/80
    assert_eq!(b.relevance_at(150.0), 1.0);
    assert_eq!(b.relevance_at(10.0), 0.0);
}

#[test]
fn the_objective_trades_closure_rate_against_cpa_by_patience() {
    // Contact 100 m north heading east at 1 m/s; ownship at the origin; top speed 4.
    let e = CpaEngine::new(0.0, 100.0, 90.0, 1.0, 0.0, 0.0);
    // The contact moves across the line of sight: closure is ownship's alone, 4 cos(course).
    let bounds = CutRange::roc_bounds(&e, 4.0);
    assert!((bounds.0 + 4.0).abs() < 1e-12 && (bounds.1 - 4.0).abs() < 1e-12);
    let mut b = CutRange::new();
    // Patience 0: the normalised rate of closure: 100 heading at it, 50 across, 0 away.
    assert!((b.aof(&e, 100.0, bounds, 0.0, 4.0) - 100.0).abs() < 1e-9);
    assert!((b.aof(&e, 100.0, bounds, 90.0, 4.0) - 50.0).abs() < 1e-9);
    assert!(b.aof(&e, 100.0, bounds, 180.0, 4.0).abs() < 1e-9);
    // Patience 100: the CPA metric. North at 4 m/s for the 15 s leg: relative track
    // (0,100) + t(1,-4), its vertex at t = 400/17 > 15, so the CPA is at 15 s: (15, 40),
    // 42.72 m: 100 (1 - 42.72/100) = 57.28.
    set(&mut b, "max_patience", "100").unwrap();
    set(&mut b, "patience", "100").unwrap();
    let cpa = 15f64.hypot(40.0);
    assert!((b.aof(&e, 100.0, bounds, 0.0, 4.0) - (100.0 - cpa)).abs() < 1e-9);
    // Patience 50: the mean.
    set(&mut b, "patience", "50").unwrap();
    assert!((b.aof(&e, 100.0, bounds, 0.0, 4.0) - (50.0 + (100.0 - cpa) / 2.0)).abs() < 1e-9);
}

#[test]
fn in_pursuit_it_heads_for_the_contact_with_a_weighted_function() {
    let d = domain();
    let info = MapInfo::new(10.0)
        .num("NAV_X", 0.0)
        .num("NAV_Y", 0.0)
        .num("NAV_HEADING", 0.0)
        .num("NAV_SPEED", 1.0)
        .with_contact(
            "bob",
            ContactInfo {
                x_m: 0.0,
                y_m: 100.0,
                heading_deg: 90.0,
                speed_mps: 1.0,
                ..ContactInfo::default()
            },
        );
    let ctx = Ctx {
        info: &info,
        domain: &d,
        ownship: "abe",
        name: "cut_bob",
        perpetual: false,
    };
    let mut b = CutRange::new();
    for (k, v) in [
        ("contact", "bob"),
        ("pwt_outer_dist", "200"),
        ("pwt_inner_dist", "0"),
        ("giveup_range", "300"),
        ("pursueflag", "PURSUING=true"),
    ] {
        set(&mut b, k, v).unwrap();
    }
    let mut out = Out::default();
    b.on_set_param_complete(&ctx, &mut out);
    let mut out = Out::default();
    let f = b
        .on_run(&ctx, &mut out)
        .expect("in pursuit within giveup_range");
    assert_eq!(b.pwt_factor(), 0.5, "(100-0)/200");
    assert!(
        matches!(&out.emits[..], [behaviors::Emit::Flag { flag, .. }] if flag.var == "PURSUING")
    );
    // Patience 0: fastest straight at the contact's present position.
    assert_eq!(f.argmax2("course", "speed"), (0.0, 4.0));
    let across = f.value_at(&[("course", 90.0), ("speed", 4.0)]).unwrap();
    assert!((across - 50.0).abs() < 3.0, "{across}");
    // Without giveup_range the C++ never pursues: no function.
    let mut never = CutRange::new();
    set(&mut never, "contact", "bob").unwrap();
    set(&mut never, "pwt_outer_dist", "200").unwrap();
    assert!(never.on_run(&ctx, &mut Out::default()).is_none());
}

#[test]
fn parameters_are_refused_as_the_cpp_refuses_them() {
    let mut b = CutRange::new();
    for (k, v) in [
        ("patience", "101"),
        ("patience", "x"),
        ("max_patience", "-1"),
        ("giveup_range", "-5"),
        ("pursueflag", "novalue"),
        ("pwt_outer_dist", "-1"),
        ("speed", "2"),
    ] {
        assert!(set(&mut b, k, v).is_err(), "{k} = {v} accepted");
    }
    set(&mut b, "patience", "95").unwrap();
    let d = domain();
    let info = MapInfo::new(0.0);
    let ctx = Ctx {
        info: &info,
        domain: &d,
        ownship: "abe",
        name: "cut",
        perpetual: false,
    };
    b.on_set_param_complete(&ctx, &mut Out::default());
    assert_eq!(b.patience, 85.0, "lowered to max_patience");
}
