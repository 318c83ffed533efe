//! BHV_AvoidObstacleV24 on the helm's Dubins platform model against values worked out from
//! MOOS-IvP's formulas (`ObShipModelV24::seglrCPA`/`evalHdgSpd`, `distSeglrToPoly`,
//! `PlatModel::getTurnSeglr`, a2a9b716).
//!
//! The obstacle is the square x in [30, 40], y in [30, 40]; `min_util_cpa_dist = 8`,
//! `max_util_cpa_dist = 16`. Ownship at the origin heading north at 2 m/s; the Dubins model
//! has radius 20 and a spoke every 90°: turning to starboard by 45° to 135° the path is
//! (0, 0) → (20, 20), then the ray along the course.

use behaviors::obstacle::turn;
use behaviors::plat_model::PlatModel;
use behaviors::testing::Probe;
use behaviors::{AvoidObstacleV24, Behavior, Common, Ctx, Emit, MapInfo, Out};
use ivp::Domain;

fn domain() -> Domain {
    Domain::parse_specs(["course:0:359:360", "speed:0:4:41"]).unwrap()
}

fn info(model: PlatModel) -> MapInfo {
    MapInfo::new(100.0)
        .num("NAV_X", 0.0)
        .num("NAV_Y", 0.0)
        .num("NAV_HEADING", 0.0)
        .num("NAV_SPEED", 2.0)
        .with_plat_model(model)
}

fn ctx<'a>(info: &'a MapInfo, d: &'a Domain) -> Ctx<'a> {
    Ctx {
        info,
        domain: d,
        ownship: "abe",
        name: "avd_ob_1",
        perpetual: false,
    }
}

fn configured() -> AvoidObstacleV24 {
    let mut b = AvoidObstacleV24::new();
    let d = domain();
    let i = MapInfo::new(0.0);
    for (k, v) in [
        ("poly", "pts={30,30:30,40:40,40:40,30},label=ob_1"),
        ("id", "ob_1"),
        ("min_util_cpa_dist", "8"),
        ("max_util_cpa_dist", "16"),
        ("allowable_ttc", "5"),
        ("pwt_inner_dist", "10"),
        ("pwt_outer_dist", "60"),
        ("completed_dist", "80"),
    ] {
        b.set_param(k, v, &mut Common::new(b.kind()), &ctx(&i, &d))
            .unwrap();
    }
    b
}

fn run(b: &mut AvoidObstacleV24, model: PlatModel) -> (ivp::IvpFunction, Out) {
    let d = domain();
    let i = info(model);
    let mut out = Out::default();
    let f = b.on_run(&ctx(&i, &d), &mut out);
    (f.expect("a function"), out)
}

fn warned(out: &Out) -> bool {
    out.emits.iter().any(|e| match e {
        Emit::Post { var, value, .. } if var == "BHV_WARNING" => value
            .as_str()
            .is_some_and(|w| w.contains("holo plat_model not best")),
        _ => false,
    })
}

#[test]
fn a_heading_is_worth_its_turns_closest_approach() {
    let dubins = PlatModel::dubins(0.0, 0.0, 0.0, 2.0, 20.0, 90.0);
    let holo = PlatModel::holonomic(0.0, 0.0, 0.0, 2.0);
    let mut b = configured();
    let (f_holo, out) = run(&mut b, holo);
    assert!(warned(&out), "the holonomic model is warned about");
    let m = b.model.clone();
    // The turn's path to 90: the spoke (20, 20), then east.
    let path = dubins.turn(90.0);
    assert_eq!(
        (path.len(), path.vertex(1).x, path.vertex(1).y),
        (2, 20.0, 20.0)
    );
    // East: the ray from the origin passes the corner (30, 30) 30 m off: 100. The turn's
    // segment ends 14.14 m from that corner and its ray runs 10 m under the bottom edge:
    // (10 − 8) / (16 − 8) · 100 = 25.
    let near = |a: f64, b: f64| (a - b).abs() < 1e-9;
    assert!(near(turn::seglr_cpa(&holo_path(), &m.gut), 30.0));
    assert!(near(turn::seglr_cpa(&path, &m.gut), 10.0));
    assert_eq!(m.eval_heading(90.0), 100.0);
    assert!(near(turn::eval_heading(&m, &dubins, 90.0), 25.0));
    // 100 (still one spoke): the ray leaves (20, 20) heading 100 and passes the corner
    // (30, 30) at 10·(sin 100° − cos 100°) = 11.585 m, under the spoke's 14.14 m:
    // (11.585 − 8) / 8 · 100 = 44.81. From the origin the ray to 100 stays 42.43 m off: 100.
    let r = 100f64.to_radians();
    let e100 = (10.0 * (r.sin() - r.cos()) - 8.0) / 8.0 * 100.0;
    assert!((e100 - 44.81).abs() < 0.01);
    assert!((turn::eval_heading(&m, &dubins, 100.0) - e100).abs() < 1e-9);
    assert_eq!(m.eval_heading(100.0), 100.0);
    // Dead ahead, or 44° (rounded to no spoke), the path is the ray: both models agree.
    for h in [0.0, 44.0, 300.0] {
        assert_eq!(turn::eval_heading(&m, &dubins, h), m.eval_heading(h), "{h}");
    }
    // 45° points at the corner with either model: 0.
    assert_eq!(turn::eval_heading(&m, &dubins, 45.0), 0.0);
    assert_eq!(m.eval_heading(45.0), 0.0);

    // The behaviour on the Dubins model: no warning, and east is worth less than on the
    // holonomic model.
    let mut b = configured();
    let (f_turn, out) = run(&mut b, dubins);
    assert!(!warned(&out));
    let at = |f: &ivp::IvpFunction, c: f64| f.value_at(&[("course", c), ("speed", 2.0)]).unwrap();
    assert!(at(&f_turn, 90.0) < 40.0, "{}", at(&f_turn, 90.0));
    assert!(at(&f_holo, 90.0) > 99.0, "{}", at(&f_holo, 90.0));
    // North is open on both (the fitted pieces differ a little after normalising).
    assert!(at(&f_turn, 0.0) > 95.0 && at(&f_holo, 0.0) > 95.0);
}

fn holo_path() -> behaviors::plat_model::TurnPath<'static> {
    behaviors::plat_model::TurnPath {
        start: geometry::Point::new(0.0, 0.0),
        arc: &[],
        segs: &[],
        ray: 90.0,
        port: false,
    }
}
